"""The student's assignment folder in the page's language: the labels, the task and hint
the file gives in Russian (``task_ru``, ``hint_ru``; English when it gives none) and the
check's verdict; real pages (viser's protocol over a websocket) against in-process servers."""

from __future__ import annotations

import asyncio
import copy
import html
import json
from collections.abc import Callable
from typing import Any

import pytest
from analyzer_lab.classroom.assignments import task_html, verdict_html
from analyzer_lab.classroom.course import Course
from analyzer_lab.classroom.store.sql_store import SqlStore
from analyzer_lab.i18n import language_of
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
from analyzer_lab.lessons.assignments import (
    AssignmentError,
    grade,
    parse_assignment,
    ready_assignments,
)

from tests.support.client import ProtoClient, open_page
from tests.support.waiting import until

pytestmark = pytest.mark.timeout(300)
TASK = "sphere-equator"
RU_ID = "sphere-equator-ru"
READY = {a.id: a for a in ready_assignments()}


def _with_russian(board: Any) -> None:
    """The ready sphere assignment, its task and hint also given in Russian."""
    data = copy.deepcopy(board.assignments[TASK].data)
    data["id"] = RU_ID
    data["task_ru"] = "Проведите точку по экватору со скоростью {s:g} м/с."
    data["hint_ru"] = "Скорость вдоль экватора равна |u1|·R."
    for check in data["checks"]:
        check["feedback_ru"] = f"Отзыв по проверке {check['id']} при скорости {{s:g}} м/с."
    board.assignments[RU_ID] = parse_assignment(json.loads(json.dumps(data)), "ru.json")


def _html(c: ProtoClient, cls: str) -> str:
    return next((h for h in c.html.values() if cls in h), "")


async def _chosen(lab: Any, code: str, aid: str, name: str) -> tuple[ProtoClient, Any, str]:
    """A page of ``lab`` (in ``code``, its language) with the assignment ``aid`` chosen and
    the student's ``name`` typed: its client, its view and the task once it shows the
    student's numbers."""
    tr = language_of(code).gettext
    c, view = await open_page(lab, tr("Run"))
    await c.wait_for(tr("Check my answer"))
    await c.set(tr("Assignment"), aid, 0.2)
    await c.set(tr("Your name"), name, 0.1)
    numbers = tr("Your numbers: {numbers}").split("{")[0].rstrip(": ")
    task = await until(
        lambda: numbers in _html(c, "al-assignment-task") and _html(c, "al-assignment-task"),
        30,
        "the task",
    )
    return c, view, task


def test_a_russian_page_shows_the_assignment_and_its_verdict_in_russian(
    labs: dict[str, Any],
) -> None:
    lab = labs["ru"]
    board = lab.classroom.board
    _with_russian(board)
    s = board.variant(RU_ID, board.class_id, "Аня").values["s"]

    async def go() -> None:
        c, view, task = await _chosen(lab, "ru", RU_ID, "Аня")
        try:
            for english in ("Check my answer", "Your name", "Join code"):
                assert english not in c.gui, english
            assert f"со скоростью {s:g} м/с" in task  # the placeholder filled in
            shown = [view.language.notice(text) for _, text in view.session.notices]
            assert any(f"открыто задание {RU_ID}" in n for n in shown), shown
            assert "Подсказка:" in task and "Скорость вдоль экватора" in task
            assert "Можно менять:" in task and "Цель:" in task
            assert "You may change" not in task and "Hint:" not in task
            await c.click("Проверить мой ответ", 0.1)  # the start values: the speed misses
            verdict = await until(
                lambda: (
                    "al-check" in _html(c, "al-assignment-result")
                    and _html(c, "al-assignment-result")
                ),
                30,
                "the verdict",
            )
            assert "не пройдена" in verdict and "не пройдено" in verdict
            assert "checks fail" not in verdict and "✗ fail" not in verdict
            assert f"Отзыв по проверке speed при скорости {s:g} м/с." in verdict
            assert "the speed along the equator is" not in verdict  # the English feedback
        finally:
            await c.close()

    asyncio.run(go())


def test_an_english_page_shows_the_english_task(labs: dict[str, Any]) -> None:
    lab = labs["en"]
    board = lab.classroom.board
    _with_russian(board)

    async def go() -> None:
        c, view, task = await _chosen(lab, "en", RU_ID, "Ann")
        try:
            assert "You may change:" in task and "Goal:" in task and "Hint:" in task
            assert "Проведите" not in task and "Подсказка" not in task
        finally:
            await c.close()

    asyncio.run(go())


def test_a_file_without_russian_falls_back_and_a_bad_one_is_refused(
    labs: dict[str, Any],
) -> None:
    board = labs["en"].classroom.board
    plain = board.variant(TASK, board.class_id, "Ann").assignment
    assert not plain.task_ru
    ru = language_of("ru")
    shown = task_html(plain, ru)
    assert html.escape(plain.task) in shown  # the English task, on a Russian page
    assert "Цель:" in shown
    data = copy.deepcopy(board.assignments[TASK].data)
    data["task_ru"] = ["not", "text"]
    with pytest.raises(AssignmentError, match="field task_ru: .*must be text"):
        parse_assignment(json.loads(json.dumps(data)), "bad.json")
    data = copy.deepcopy(board.assignments[TASK].data)
    data["checks"][0]["feedback_ru"] = 5
    with pytest.raises(AssignmentError, match=r"checks\[0\]\.feedback_ru: .*must be text"):
        parse_assignment(json.loads(json.dumps(data)), "bad.json")


CODE = "ru-class-code-2026-lab"


def test_the_instructors_assignments_folder_in_russian(make_lab: Callable[..., Any]) -> None:
    lab = make_lab(
        language="ru",
        lessons=[SPHERE],
        lesson="sphere",
        instructor_code=CODE,
        warm_up=False,
        restore=False,
    )

    async def go() -> None:
        inst, iv = await open_page(lab, "Движение")
        try:
            await inst.set("Код преподавателя", CODE, 0.1)
            await inst.click("Стать преподавателем")
            await inst.wait_for("Выдать задание всем")
            for english in (
                "Push assignment to all",
                "Download results (CSV)",
                "Assignments (class)",
            ):
                assert english not in inst.gui, english
            assert "Задания (класс)" in inst.gui and "Скачать оценки (CSV для Moodle)" in inst.gui
            assert "Панель преподавателя" in inst.gui and "Следовать за мной" in inst.gui
            panel = lab.classroom.instructors[iv.client.client_id]
            await until(lambda: "подключено студентов" in panel.counts.content, 10, "the counts")
            assert "работают самостоятельно" in panel.counts.content
            head = await until(
                lambda: next((h for h in inst.html.values() if "Задание не выдано" in h), ""),
                10,
                "the table's head",
            )
            assert "No assignment pushed" not in head
            student, sv = await open_page(lab, "Движение")
            try:
                await inst.set("Задание для всех", TASK, 0.1)
                await inst.click("Выдать задание всем")
                await until(
                    lambda: (
                        getattr(
                            lab.classroom.board.students.get(sv.client.client_id), "active", None
                        )
                        is not None
                    ),
                    20,
                    "the student's assignment",
                )
                task = await until(lambda: _html(student, "al-assignment-task"), 20, "the task")
                assert "Цель:" in task
                await until(lambda: any("Выдано:" in h for h in inst.html.values()), 10, "pushed")
                await student.set("Ваше имя", "Аня", 0.1)
                await student.click("Проверить мой ответ", 0.1)
                row = await until(
                    lambda: next((h for h in inst.html.values() if "al-roster-row" in h), ""),
                    30,
                    "the student's row",
                )
                assert "Аня" in row and ">нет<" in row  # the start values fail
                head = next(h for h in inst.html.values() if "<thead>" in h)
                assert "студент" in head and "попытки" in head and "attempts" not in head
            finally:
                await student.close()
        finally:
            await inst.close()

    asyncio.run(go())


WORDS_ID = "sphere-equator-words"


def _without_labels(board: Any) -> None:
    """The ready sphere assignment with its checks described by the model (no labels),
    the speed held within 0.0025 from t = 0.5 on."""
    data = copy.deepcopy(board.assignments[TASK].data)
    data["id"] = WORDS_ID
    for check in data["checks"]:
        check.pop("label")
    data["checks"][1].update({"tolerance": 0.0025, "from": 0.5})
    board.assignments[WORDS_ID] = parse_assignment(json.loads(json.dumps(data)), "words.json")


def test_the_checks_described_by_the_model_and_their_verdict_in_russian(
    labs: dict[str, Any],
) -> None:
    """A Russian page: the checks in words and what the verdict measured in Russian, with
    decimal commas (the English texts the grade holds unchanged)."""
    lab = labs["ru"]
    board = lab.classroom.board
    _without_labels(board)

    async def go() -> None:
        c, view, task = await _chosen(lab, "ru", WORDS_ID, "Аня")
        try:
            assert "траектория (x, y, z) лежит в плоскости +0*x +0*y +1*z = 0" in task, task
            assert "(с допуском 1e-09)" in task
            assert "speed отличается от" in task
            assert "не более чем на 0,0025 при t от 0,5 до конца" in task, task
            for english in ("stays within", "the path", "for t in", "lies in the plane"):
                assert english not in task, english
            await c.click("Проверить мой ответ", 0.1)  # the start values: the speed misses
            verdict = await until(
                lambda: (
                    "al-check" in _html(c, "al-assignment-result")
                    and _html(c, "al-assignment-result")
                ),
                30,
                "the verdict",
            )
            assert "не более чем на 0,0025 при t от 0,5 до конца" in verdict, verdict
            assert "наибольшее отклонение от плоскости" in verdict
            assert ", наибольшее при t = " in verdict
            assert "не выполнено: превышает допуск 0,0025 на " in verdict, verdict
            for english in ("largest at", "misses the tolerance", "farthest from", "stays within"):
                assert english not in verdict, english
        finally:
            await c.close()

    asyncio.run(go())


def test_the_checks_in_words_are_english_on_an_english_page_and_in_the_grade(
    labs: dict[str, Any],
) -> None:
    """The English text is the one the grade, the exports and the API hold; a grade that
    came back as plain data (JSON) shows its English text even on a Russian page."""
    board = labs["en"].classroom.board
    _without_labels(board)
    a = board.variant(WORDS_ID, board.class_id, "Ann").assignment
    speed = a.checks[1]
    assert speed.target is not None
    s = speed.target.text
    assert speed.describe() == f"speed stays within 0.0025 of {s} for t in [0.5, end]"
    assert str(a.checks[0].describe()) == (
        "the path (x, y, z) lies in the plane +0*x +0*y +1*z = 0 (within 1e-09)"
    )
    english = task_html(a)
    assert html.escape(str(speed.describe())) in english and "Goal:" in english
    g = grade(a, a.answers["wrong"])
    out = g.checks[1]
    assert out.message.startswith(f"|speed - ({s})| = ")
    assert " largest at t = " in out.message and "; misses the tolerance 0.0025 by " in out.message
    assert json.loads(json.dumps(g.to_json_dict()))["checks"][1]["message"] == out.message
    ru = language_of("ru")
    shown = verdict_html(g, ru, a)
    assert "при t от 0,5 до конца" in shown and "превышает допуск 0,0025 на" in shown
    assert "stays within" not in shown and "misses the tolerance" not in shown
    plain = copy.deepcopy(g)
    for o in plain.checks:
        o.text, o.message = str(o.text), str(o.message)  # as the store or the bus give it
    shown = verdict_html(plain, ru)
    assert html.escape(out.message) in shown and html.escape(str(speed.describe())) in shown


def test_a_join_refusal_on_a_russian_page_is_in_russian(make_lab: Callable[..., Any]) -> None:
    store = SqlStore("sqlite://")
    course = Course(store, store.open_class("ru-class", join_code="JOIN42"), b"r" * 32)
    lab = make_lab(language="ru", lessons=[SPHERE], lesson="sphere", course=course, warm_up=False)

    async def go() -> None:
        c, _ = await open_page(lab, "Движение")
        try:
            await c.wait_for("Проверить мой ответ")
            await c.set("Задание", TASK, 0.2)
            await until(lambda: _html(c, "al-assignment-task"), 30, "the task")
            await c.set("Ваше имя", "Аня", 0.1)
            await c.click("Проверить мой ответ", 0.1)  # no join code typed
            box = await until(
                lambda: _html(c, "al-assignment-error"), 30, "the refusal of the join"
            )
            assert "введите код класса, который дал преподаватель" in box, box
            assert "type the join code" not in box
            await c.set("Код класса", "WRONG9", 0.1)
            await c.click("Проверить мой ответ", 0.1)
            box = await until(
                lambda: (
                    "неизвестный код класса" in _html(c, "al-assignment-error")
                    and _html(c, "al-assignment-error")
                ),
                30,
                "the refusal of the wrong code",
            )
            assert "unknown join code" not in box
        finally:
            await c.close()

    try:
        asyncio.run(go())
        assert course.attempts() == []  # nothing recorded for a page that did not join
    finally:
        store.close()


def test_the_assignment_folder_follows_a_switch_of_the_pages_language(
    labs: dict[str, Any],
) -> None:
    """An English page with an open assignment switched to Russian: the folder's labels,
    "(none)" and the open task in Russian; choosing "(нет)" closes the assignment."""
    lab = labs["en"]

    async def go() -> None:
        c, view = await open_page(lab, "Run")
        try:
            students = lab.classroom.board.students
            panel = await until(lambda: students.get(view.client.client_id), 10, "the folder")
            assert panel.picker.options[0] == "(none)"
            await c.set("Assignment", TASK, 0.2)
            await until(lambda: "Goal:" in panel.task.content, 30, "the assignment open")
            await c.set("Language", "Русский")
            await until(lambda: view.language.code == "ru", 10, "the page in Russian")
            with view.session.lock:
                assert panel.picker.options[0] == "(нет)" and panel.picker.value == TASK
                labels = (panel.folder.label, panel.name.label, panel.check_btn.label)
                assert labels == ("Задание", "Ваше имя", "Проверить мой ответ")
                assert "Цель:" in panel.task.content and "Goal:" not in panel.task.content
            await c.set("Assignment", "(нет)", 0.2)
            await until(lambda: panel.active is None, 10, "the assignment closed")
            assert panel.picker.value == "(нет)" and panel.task.content == ""
        finally:
            await c.close()

    asyncio.run(go())


REFUSALS = [
    (
        {"t_end": -1},
        "bad.json: field t_end: must be positive, got -1",
        "bad.json: поле t_end: должно быть положительным, получено -1",
    ),
    (
        {"t_end": 2.5e4},
        "bad.json: field t_end: 25000 is above the limit 10000",
        "bad.json: поле t_end: 25000 больше предела 10000",
    ),
    (
        {"unlocked": "u1"},
        "bad.json: field unlocked: must be a non-empty list of parameter names, got text 'u1'",
        "bad.json: поле unlocked: должно быть непустым списком имён параметров, получено: текст 'u1'",
    ),
    (
        {"lesson": "nope"},
        "bad.json: field lesson: no lesson 'nope' (see 'analyzer-lab lessons')",
        "bad.json: поле lesson: нет урока 'nope' (см. 'analyzer-lab lessons')",
    ),
    (
        {"extra": 1},
        "bad.json: field extra: is not a field of an assignment",
        "bad.json: поле extra: не является полем задания",
    ),
    (
        {
            "t_end": 1.25,
            "checks": [{"id": "a", "kind": "within", "quantity": "x", "tolerance": 0.5, "at": 1.5}],
        },
        "bad.json: field checks[0].at: 1.5 is outside the run [0, 1.25]",
        "bad.json: поле checks[0].at: 1,5 вне расчёта [0; 1,25]",
    ),
]


@pytest.mark.parametrize(("change", "english", "russian"), REFUSALS)
def test_a_refused_file_in_english_unchanged_and_in_russian(
    change: dict[str, Any], english: str, russian: str
) -> None:
    """The refusal's English text is what it always was (logs, exports, tests compare
    it); a Russian page or command shows it in Russian with its decimal commas."""
    data = copy.deepcopy(dict(READY["circle-radius-2"].data))
    data.update(change)
    with pytest.raises(AssignmentError) as caught:
        parse_assignment(json.loads(json.dumps(data)), "bad.json")
    assert str(caught.value) == english
    assert language_of("ru").message(caught.value) == russian
    assert language_of("en").message(caught.value) == english


def test_a_refused_answer_says_answer_in_russian(labs: dict[str, Any]) -> None:
    a = labs["en"].classroom.board.variant(TASK, "class", "Ann").assignment
    with pytest.raises(AssignmentError) as caught:
        grade(a, {"u1": [1]})
    assert str(caught.value) == "answer: field u1: must be a number, a formula text or true/false"
    assert language_of("ru").message(caught.value) == (
        "ответ: поле u1: должно быть числом, текстом формулы или true/false"
    )


def test_the_russian_title_on_a_russian_page(labs: dict[str, Any]) -> None:
    board = labs["ru"].classroom.board
    a = board.variant(TASK, board.class_id, "Аня").assignment
    assert a.title_ru.startswith("По экватору со скоростью ") and "{" not in a.title_ru
    assert html.escape(a.title) in task_html(a) and a.title_ru not in task_html(a)

    async def go() -> None:
        c, _, task = await _chosen(labs["ru"], "ru", TASK, "Аня")
        try:
            assert f"<b>{html.escape(a.title_ru)}</b>" in task, task
            assert "Round the equator" not in task
        finally:
            await c.close()

    asyncio.run(go())


def test_a_refused_draft_on_a_russian_page_is_in_russian(make_lab: Callable[..., Any]) -> None:
    lab = make_lab(
        language="ru",
        lessons=[SPHERE],
        lesson="sphere",
        instructor_code=CODE,
        warm_up=False,
        restore=False,
    )

    async def go() -> None:
        inst, iv = await open_page(lab, "Движение")
        try:
            await inst.set("Код преподавателя", CODE, 0.1)
            await inst.click("Стать преподавателем")
            await inst.wait_for("Выдать задание всем")
            ru = language_of("ru").gettext
            await inst.set(ru("Unlocked"), "nope", 0.1)
            await inst.click(ru("Download assignment"), 0.1)
            panel = lab.classroom.board.teachers[iv.client.client_id]
            shown = await until(lambda: panel.a_error.content, 30, "the refusal")
            assert html.escape("черновик: поле unlocked[0]: 'nope' не является параметром") in shown
            assert "is not a parameter" not in shown and "draft" not in shown
        finally:
            await inst.close()

    asyncio.run(go())


def test_a_refused_varied_file_names_its_field_in_russian() -> None:
    data = copy.deepcopy(dict(READY[TASK].data))
    data["variables"] = {"s": {"from": 2, "to": 1.5, "step": 0.5}}
    with pytest.raises(AssignmentError) as caught:
        parse_assignment(json.loads(json.dumps(data)), "bad.json")
    assert str(caught.value) == "bad.json: field variables.s.to: 1.5 is below 'from' (2)"
    assert language_of("ru").message(caught.value) == (
        "bad.json: поле variables.s.to: 1,5 меньше 'from' (2)"
    )
