"""The classroom's folders of a page follow a switch of the page's language: the code
entry, the presenter's folder and, once the page is the instructor, the instructor's panel
(pages driven by real websocket clients, :class:`tests.support.client.ProtoClient`)."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

import pytest
from analyzer_lab.i18n import resolve
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE

from tests.support.client import ProtoClient
from tests.support.waiting import until

CODE = "test-code-5183"
RU = resolve("ru")[0]
pytestmark = pytest.mark.timeout(120)


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(
        lessons=[SPHERE], lesson="sphere", instructor_code=CODE, warm_up=False, restore=False
    )


async def page(lab: Any) -> tuple[ProtoClient, Any]:
    """A connected page and its server-side view."""
    before = set(lab.views)
    c = await ProtoClient(lab.url).start()
    await c.wait_for("Run")
    new = await until(lambda: set(lab.views) - before, 10, "the view")
    view = lab.views[max(new)]
    cid = view.client.client_id
    await until(lambda: cid in lab.classroom.board.students, 10, "the classroom's folders")
    return c, view


def entry_labels(lab: Any, view: Any) -> tuple[str, ...]:
    folder, text, btn = lab.classroom.entries[view.client.client_id]
    return folder.label, text.label, text.hint, btn.label


def presenter_labels(lab: Any, view: Any) -> tuple[str, ...]:
    p = lab.classroom.presenters[view.client.client_id]
    return p.folder.label, p.toggle.label, p.class_table.label, p.top_prev.label


def panel_labels(lab: Any, view: Any) -> tuple[str, ...]:
    p = lab.classroom.instructors[view.client.client_id]
    return p.folder.label, p.follow_btn.label, p.release_btn.label, p.notify_btn.label


def teacher_labels(t: Any) -> tuple[str, ...]:
    return (
        t.folder.label,
        t.picker.label,
        t.push_btn.label,
        t.csv_btn.label,
        t.author.label,
        t.a_btn.label,
    )


def test_the_classroom_folders_follow_the_pages_language(lab: Any) -> None:
    english_entry = (
        "Instructor",
        "Instructor code",
        "the code printed when the lab started",
        "Become instructor",
    )
    russian_entry = tuple(RU.gettext(t) for t in english_entry)
    assert russian_entry == (
        "Преподаватель",
        "Код преподавателя",
        "код, выведенный при запуске лаборатории",
        "Стать преподавателем",
    )

    async def go() -> None:
        a, av = await page(lab)
        b, bv = await page(lab)
        try:
            assert entry_labels(lab, av) == english_entry
            await a.set("Language", "Русский")
            await until(lambda: av.language.code == "ru", 10, "the page in Russian")
            with av.session.lock:
                assert entry_labels(lab, av) == russian_entry
                assert presenter_labels(lab, av) == (
                    "Показ",
                    "Режим показа",
                    RU.gettext("Show the class table"),
                    "◀ Предыдущий",
                )
            assert entry_labels(lab, bv) == english_entry  # the other page keeps its own
            assert presenter_labels(lab, bv)[0] == "Presenter"
            # the relabelled entry (the same elements) still makes the page the instructor,
            # whose panel is built in Russian
            await a.set("Instructor code", CODE, 0.1)
            await a.click("Become instructor")
            await a.wait_for("Следовать за мной")
            await until(lambda: lab.classroom.is_instructor(av.client.client_id), 10, "granted")
            # and a switch back relabels the panel too
            await a.set("Language", "English")
            await until(lambda: av.language.code == "en", 10, "the page in English")
            with av.session.lock:
                assert panel_labels(lab, av) == (
                    "Instructor panel",
                    "Follow me",
                    "Release",
                    "Notify all",
                )
                assert presenter_labels(lab, av)[:2] == ("Presenter", "Presenter mode")
                counts = lab.classroom.instructors[av.client.client_id].counts.content
                # the Assignments folder, built in Russian when the role was granted
                teacher = lab.classroom.board.teachers[av.client.client_id]
                assert teacher_labels(teacher) == (
                    "Assignments (class)",
                    "Assignment for all",
                    "Push assignment to all",
                    "Download results (CSV)",
                    "Author from this state",
                    "Download assignment",
                )
                assert teacher.picker.options[0] == "(none)"
                assert teacher.picker.value == "(none)"
                assert "become the assignment" in teacher.a_intro.content
                assert "No assignment pushed" in teacher.table.content
            assert "connected" in counts and "подключено" not in counts
            await a.set("Language", "Русский")
            await until(lambda: av.language.code == "ru", 10, "the page in Russian again")
            with av.session.lock:
                assert teacher_labels(teacher)[:3] == (
                    "Задания (класс)",
                    "Задание для всех",
                    "Выдать задание всем",
                )
                assert teacher.picker.options[0] == teacher.picker.value == RU.gettext("(none)")
                assert "Задание не выдано" in teacher.table.content
        finally:
            lab.classroom.release()
            await a.close()
            await b.close()

    asyncio.run(go())
