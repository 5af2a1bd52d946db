"""The readout's notices in the page's language: a Russian page shows the session's
refusals and "t reached" in Russian, an English page in English (real websockets to an
in-process server)."""

from __future__ import annotations

import asyncio
import html
from typing import Any

import pytest
from analyzer_lab.i18n import language_of

from tests.support.client import ProtoClient, handled, open_page
from tests.support.waiting import until

pytestmark = pytest.mark.timeout(300)


def _shown(c: ProtoClient, css: str) -> str:
    """The text of the page's html element with ``css`` (its escapes read back)."""
    return html.unescape(next((h for h in c.html.values() if css in h), ""))


async def _reach_the_end(c: ProtoClient, view: Any) -> None:
    """Play the last moment of the textbook's run: the session says the end is reached."""
    with view.session.lock:
        view.session.go_to(view.session.t_end - 0.05)
        view.session.play()
    await until(lambda: not view.session.playing, 20, "the end of the run")


@pytest.mark.parametrize(
    ("code", "first", "refused", "reached"),
    [
        (
            "ru",
            "Движение",
            "h: 0,5 больше максимума 0,1 с",
            "достигнуто t = 10 с (прогон учебника)",
        ),
        ("en", "Run", "h: 0.5 is above the maximum 0.1 s", "t = 10 s reached (the textbook's run)"),
    ],
)
def test_a_refused_value_and_the_end_of_the_run_in_the_pages_language(
    labs: dict[str, Any], code: str, first: str, refused: str, reached: str
) -> None:
    async def go() -> None:
        c, view = await open_page(labs[code], first)
        try:
            label = language_of(code).lesson_text(view.session.lesson.param("h").label)
            field = next(k for k in c.gui if k.startswith(label))
            before = view.session.params["h"]
            await c.set(field, "0,5" if code == "ru" else "0.5")
            await handled(c, view)
            shown = await until(lambda: _shown(c, "al-field-error"), 10, "the field's error")
            assert refused in shown
            assert view.session.params["h"] == before  # nothing else changed
            await _reach_the_end(c, view)
            notice = await until(
                lambda: reached in _shown(c, "al-message al-info") and _shown(c, "al-message"),
                10,
                "the notice on the page",
            )
            assert reached in notice
            # the hidden marker the page's <html lang> follows (tests/test_browser_language.py)
            assert f'data-al-lang="{code}"' in next(h for h in c.html.values() if "al-message" in h)
            # the session keeps the English text (logs, exports, the API)
            assert "t = 10 s reached (the textbook's run)" in view.session.notice[1]
        finally:
            await c.close()

    asyncio.run(go())


def test_a_russian_speed_refusal_names_the_speeds_with_a_decimal_comma(
    labs: dict[str, Any],
) -> None:
    async def go() -> None:
        c, view = await open_page(labs["ru"], "Движение")
        try:
            with view.session.lock:
                try:
                    view.session.set_speed(3)
                except ValueError as exc:
                    view.session.notify(view._refused(exc), "error")
                view.session.revision += 1
            text = await until(lambda: _shown(c, "al-message al-error"), 10, "the refusal")
            assert "отклонено: скорость должна быть одной из 0,25x" in text
            assert "получено 3" in text
        finally:
            await c.close()

    asyncio.run(go())


def test_a_lessons_note_on_a_russian_page_writes_its_numbers_with_the_decimal_comma(
    make_lab: Any,
) -> None:
    """The lesson's own note (translated in the ``lessons`` catalog) on a Russian page: its
    numbers with the decimal comma, its equation numbers with their dot; English keeps
    the dot."""
    from analyzer_lab.lessons.analyzers.motion_program import LESSON

    note = LESSON.notes(LESSON.resolve({}, None))[0].text
    assert note == "L = 3.44288: trapezoid, T = 5.44288 s (1.8), (1.9)"
    lab = make_lab(language="ru", lessons=[LESSON], lesson=LESSON.id, warm_up=False, restore=False)

    async def go() -> None:
        c, view = await open_page(lab, "Движение")
        try:
            with view.session.lock:
                view.session.notify(note, "warning")
                view.session.revision += 1
            text = await until(lambda: _shown(c, "al-message al-warning"), 10, "the note")
            assert ">L = 3,44288: трапеция, T = 5,44288 с (1.8), (1.9)<" in text, text
        finally:
            await c.close()

    asyncio.run(go())
    assert language_of("en").notice(note) == note
