"""A page in its language: the chrome of a page built in Russian, and numbers typed with a
decimal comma (read in Russian, refused with a clear message in English); real websockets
to an in-process server."""

from __future__ import annotations

import asyncio
import json
import re
from collections.abc import Callable
from typing import Any

import pytest
from analyzer_lab.lessons.catalog import get_lesson

from tests.support.client import ProtoClient, handled, open_page
from tests.support.waiting import until

pytestmark = pytest.mark.timeout(300)

#: The chrome's English labels (what the existing tests select by) and their Russian.
CHROME = {
    "Lesson": "Урок",
    "Preset": "Пример",
    "Run": "Движение",
    "Speed": "Скорость",
    "go to t [s]": "перейти к t [с]",
    "pause at t_end": "пауза при t_end",
    "Playback": "Воспроизведение",
    "Vectors": "Векторы",
    "Snap to surface": "Привязать к поверхности",
    "grid step [s]": "шаг сетки [с]",
    "Download CSV (grid)": "Скачать CSV (сетка)",
    "HTML replay": "Повтор в HTML",
}


def test_a_page_built_in_russian_shows_russian_chrome(labs: dict[str, Any]) -> None:
    async def go() -> None:
        c, view = await open_page(labs["ru"], "Движение")
        try:
            await c.wait_for("шаг сетки [с]")
            assert view.language.code == "ru"
            for english, russian in CHROME.items():
                assert russian in c.gui, russian
                assert english not in c.gui, english
            buttons = c.last["GuiButtonGroupMessage"]["props"]
            assert buttons["label"] == "Движение"
            assert buttons["options"] == ["Пуск", "Пауза", "Шаг", "Сброс"]
            tabs = c.last["GuiTabGroupMessage"]["props"]["_tab_labels"]
            assert tabs == ["Урок", "Параметры", "Графики", "Экспорт"]
            readout = next(h for h in c.html.values() if "al-readout" in h)
            assert "t =    0,000 с" in readout and "пауза" in readout
            assert re.search(r"= \d+,\d+(&nbsp;|<)", readout.split("al-readout-values")[1])
            # the Russian Play button plays, Reset resets (the commands behind the labels)
            await c.set("Движение", "Пуск")
            await until(lambda: view.session.playing, 10, "play")
            await c.set("Движение", "Сброс")
            await until(lambda: not view.session.playing, 10, "reset")
            # a refusal in the page's language
            await c.set("Скорость", "9z")
            await until(
                lambda: any("отклонено: неизвестная скорость" in n for n in _notices(view)),
                10,
                "the refusal",
            )
        finally:
            await c.close()

    asyncio.run(go())


def test_an_english_page_stays_english(labs: dict[str, Any]) -> None:
    async def go() -> None:
        c, view = await open_page(labs["en"], "Run")
        try:
            await c.wait_for("grid step [s]")
            assert view.language.code == "en"
            for english, russian in CHROME.items():
                assert english in c.gui and russian not in c.gui, english
            tabs = c.last["GuiTabGroupMessage"]["props"]["_tab_labels"]
            assert tabs == ["Lesson", "Controls", "Plots", "Export"]
            readout = next(h for h in c.html.values() if "al-readout" in h)
            assert "t =    0.000 s" in readout and "paused" in readout
        finally:
            await c.close()

    asyncio.run(go())


def _kept(storage: dict[str, str]) -> str | None:
    """The language kept in a browser's saved state."""
    return json.loads(storage.get("analyzer-lab-state") or "{}").get("language")


def _notices(view: Any) -> list[str]:
    return [text for _, text in view.session.notices]


def _field_error(c: ProtoClient) -> str:
    return next((h for h in c.html.values() if "al-field-error" in h), "")


def test_a_decimal_comma_is_read_in_russian_and_refused_with_a_message_in_english(
    labs: dict[str, Any],
) -> None:
    async def go() -> None:
        ru, ru_view = await open_page(labs["ru"], "Движение")
        en, en_view = await open_page(labs["en"], "Run")
        try:
            await ru.set("радиус сферы R", "0,5")  # the lesson's label in Russian
            await ru.set("u1(t) =", "0,5*sin(2,5*t)")
            await handled(ru, ru_view)
            assert ru_view.session.params["R"] == 0.5
            assert ru_view.session.params["u1"].text == "0.5*sin(2.5*t)"
            assert not ru_view.controls.failing()
            # "go to t" reads it too
            await ru.set("перейти к t [с]", "0,25")
            await until(lambda: abs(ru_view.session.frame.t - 0.25) < 1e-9, 10, "go to t")

            before = en_view.session.params["R"]
            await en.set("sphere radius R", "0,5")
            await handled(en, en_view)
            await until(lambda: "R" in en_view.controls.failing(), 10, "the field's error")
            message = await until(lambda: _field_error(en), 10, "the message on the page")
            assert "0,5 has a decimal comma: write 0.5 with a dot" in message
            assert en_view.session.params["R"] == before  # nothing else changed
        finally:
            await ru.close()
            await en.close()

    asyncio.run(go())


def test_the_language_picker_switches_the_page_and_the_browser_keeps_it(
    make_lab: Callable[..., Any],
) -> None:
    lab = make_lab(lessons=[get_lesson("sphere")], lesson="sphere", warm_up=False)
    storage: dict[str, str] = {}  # one browser's local storage, shared by its pages

    async def go() -> None:
        before = set(lab.views)
        c = await ProtoClient(lab.url, storage=storage).start()
        await c.wait_for("Run")
        view = lab.views[max(await until(lambda: set(lab.views) - before, 10, "the view"))]
        try:
            assert "Language" in c.gui
            assert view.language_dd.options == ("English", "Русский")
            await c.set("Language", "Русский")
            await until(lambda: view.language.code == "ru", 10, "the page in Russian")
            # the lesson's controls are rebuilt in Russian; the chrome is relabelled
            await c.wait_for("Привязать к поверхности")
            await c.wait_for("Векторы")
            with view.session.lock:
                assert view.lesson_dd.label == "Урок" and view.preset_dd.label == "Пример"
                assert view.transport.options == ("Пуск", "Пауза", "Шаг", "Сброс")
                assert view.clock.goto.label == "перейти к t [с]"
                assert view.exports.grid_step.label == "шаг сетки [с]"
                assert view.tabs._tab_labels == ("Урок", "Параметры", "Графики", "Экспорт")
                assert view.preset_dd.value == "(по умолчанию)"
            await until(
                lambda: any("0,000 с" in h and "пауза" in h for h in c.html.values()),
                10,
                "the readout in Russian",
            )
            await until(lambda: _kept(storage) == "ru", 10, "the language kept")
            # the relabelled buttons (the same element) drive the transport in Russian
            await c.set("Run", "Пуск")
            await until(lambda: view.session.playing, 10, "play")
            await c.set("Run", "Пауза")
            await until(lambda: not view.session.playing, 10, "pause")
        finally:
            await c.close()
        # the browser's next page opens in the language it chose
        again = await ProtoClient(lab.url, storage=storage).start()
        try:
            await again.wait_for("Урок")
            assert "Lesson" not in again.gui
        finally:
            await again.close()
        # a kept code the lab does not know is ignored: the server's default
        storage["analyzer-lab-state"] = json.dumps(
            {**json.loads(storage["analyzer-lab-state"]), "language": "xx"}
        )
        other = await ProtoClient(lab.url, storage=storage).start()
        try:
            await other.wait_for("Lesson")
        finally:
            await other.close()

    asyncio.run(go())


def _derivation(c: ProtoClient) -> str:
    return next((h for h in c.html.values() if "al-derivation" in h), "")


def test_the_derivation_is_shown_in_the_pages_language(labs: dict[str, Any]) -> None:
    """Its step titles and prose in Russian on a Russian page (built in a derivation
    process, numbers as written), English on an English page, and in Russian again once
    the English page switches."""

    async def go() -> None:
        ru, _ = await open_page(labs["ru"], "Движение")
        en, en_view = await open_page(labs["en"], "Run")
        try:
            await until(lambda: "2. Касание<" in _derivation(ru), 60, "the Russian derivation")
            shown = _derivation(ru)
            assert "Tangency" not in shown and "5. Сфера<" in shown
            words = re.sub(r"<[^>]*>", " ", shown)  # the shown text, tags and classes left out
            assert "reconstructed" not in words and "corrected" not in words
            assert "восстановлено" in words and "Рис. 1.15" in words
            assert "Fig." not in words and "Problem" not in words and "derived" not in words
            assert "Задача 1.4: структурная схема анализатора" in words  # the figure's caption
            head = next(h for h in ru.html.values() if "Учебник, §1.3, задача 1.4" in h)
            assert "Textbook" not in head and "eqs" not in head
            assert re.search(r"сфера R=1(\.0)?: F = \S+ с числами этого урока", shown)
            await until(lambda: "2. Tangency<" in _derivation(en), 60, "the English one")
            assert "Касание" not in _derivation(en)
            await en.set("Language", "Русский")
            await until(lambda: en_view.language.code == "ru", 10, "the page in Russian")
            await until(lambda: "2. Касание<" in _derivation(en), 60, "the derivation switched")
        finally:
            await ru.close()
            await en.close()

    asyncio.run(go())


def test_a_lessons_note_is_shown_in_the_pages_language(labs: dict[str, Any]) -> None:
    """A note the lesson writes with the values of a run (its start point projected onto
    a sphere of radius 2), notified as the session does on a restart, is shown in Russian
    with its own numbers; the session keeps the lesson's English."""
    sphere = get_lesson("sphere")
    note = next(n for n in sphere.open({"R": 2.0}).notes if "projected to" in n.text)
    assert "(2, 0, 0)" in note.text

    async def go() -> None:
        c, view = await open_page(labs["ru"], "Движение")
        try:
            with view.session.lock:
                view.session.notify(note.text, "warning")
            await until(
                lambda: any("спроецирована в (2, 0, 0)" in h for h in c.html.values()),
                10,
                "the note in Russian",
            )
            status = next(h for h in c.html.values() if "спроецирована в (" in h)
            assert "начальная точка (" in status and "projected" not in status
            assert _notices(view)[-1] == note.text
        finally:
            await c.close()

    asyncio.run(go())


def test_the_lesson_head_writes_names_as_the_textbook_does() -> None:
    from analyzer_lab.i18n import ENGLISH
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.view.page import lesson_head_html

    head = lesson_head_html(get_lesson("planar-3axis"), ENGLISH)
    assert "turns by φ" in head and "x<sub>A</sub>, y<sub>A</sub>, φ" in head, head
    assert "phi" not in head and "x_A" not in head


def test_a_word_as_a_subscript_is_in_the_pages_language() -> None:
    from analyzer_lab.i18n import ENGLISH, language_of
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.view.page import lesson_head_html

    lesson = get_lesson("linear-positioner")
    assert "R<sub>sopr</sub>" in lesson_head_html(lesson, ENGLISH)
    ru = lesson_head_html(lesson, language_of("ru"))
    assert "R<sub>сопр</sub>" in ru and "F<sub>dv</sub>" in ru and "sopr" not in ru, ru
