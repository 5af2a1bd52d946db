"""A Russian page in a real browser at 1400x900: the chrome and the lesson's own texts
(its picker label, head, preset titles, control labels) are Russian, its buttons work,
a number typed with a decimal comma is read, and no panel element runs past the panel or
the screen (the layout checks of the English run)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import pytest
from analyzer_lab.lessons.catalog import get_lesson

from tests.support.browser import ARTIFACTS, Page
from tests.support.layout import GEOMETRY_JS, MIN_TEXT_PX
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]


@pytest.fixture(scope="module")
def ru_lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lessons=[get_lesson("sphere")], lesson="sphere", language="ru", restore=False)


@pytest.fixture()
def ru_tab(ru_lab: Any, browser: Any) -> Iterator[Page]:
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    p = Page(ru_lab, browser, context, first_label="Урок")
    yield p
    p.close()


def _fits(tab: Page, where: str) -> None:
    geometry = tab.page.evaluate(GEOMETRY_JS, MIN_TEXT_PX)
    assert geometry["over"] == [], f"{where}: {geometry['over']}"
    assert geometry["small"] == [], f"{where}: {geometry['small']}"


def test_a_russian_page_at_1400x900(ru_tab: Page) -> None:
    page = ru_tab.page
    tabs = [t.strip() for t in page.get_by_role("tab").all_inner_texts()]
    assert tabs == ["Урок", "Параметры", "Графики", "Экспорт"]
    wait_until(
        lambda: page.evaluate("document.documentElement.lang") == "ru", 10, '<html lang="ru">'
    )
    for name in ("Пуск", "Пауза", "Шаг", "Сброс"):
        assert page.get_by_role("button", name=name, exact=True).count() == 1, name
    for label in ("Пример", "Скорость", "перейти к t [с]"):
        assert ru_tab.label(label).count() == 1, label
    readout = page.locator(".al-readout").first.inner_text()
    assert "t = 0,000 с" in " ".join(readout.split()) and "пауза" in readout
    # the lesson's own texts: the lesson picker, the lesson's head, a preset's title
    assert ru_tab.options("Урок") == ["Гл. 1 · Задача 1.4 · Перемещение по кривой на сфере"]
    page.get_by_text("Учебник, §1.3, задача 1.4", exact=False).first.wait_for(timeout=10000)
    ru_tab.select("Пример", "example-1.2")
    wait_until(lambda: ru_tab.session.preset == "example-1.2", 10, "the preset")
    note = page.locator(".al-preset-note").first
    wait_until(lambda: "Пример 1.2: u1 = t" in note.inner_text(), 10, "the preset's title")
    assert "семейство окружностей" in note.inner_text()
    _fits(ru_tab, "Урок")
    ru_tab.button("Пуск")
    wait_until(lambda: ru_tab.session.playing, 10, "play")
    wait_until(lambda: "идёт" in page.locator(".al-readout").first.inner_text(), 10, "идёт")
    ru_tab.button("Пауза")
    wait_until(lambda: not ru_tab.session.playing, 10, "pause")
    for name in ("Параметры", "Графики", "Экспорт"):
        ru_tab.tab(name)
        _fits(ru_tab, name)
    ru_tab.tab("Параметры")
    ru_tab.fill("радиус сферы R", "1,5")
    wait_until(lambda: ru_tab.session.params["R"] == 1.5, 10, "R = 1,5 read as 1.5")
    assert ru_tab.field_errors() == ""
    ru_tab.shot("language-ru-sphere-1400x900")
    assert (ARTIFACTS / "language-ru-sphere-1400x900.png").stat().st_size > 10_000
    assert not [e for e in ru_tab.errors if "pageerror" in e]


@pytest.fixture(scope="module")
def en_lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lessons=[get_lesson("sphere")], lesson="sphere")


def test_the_language_picker_in_a_browser_and_after_a_reload(en_lab: Any, browser: Any) -> None:
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    tab = Page(en_lab, browser, context)
    try:
        assert tab.options("Language") == ["English", "Русский"]
        lang = "document.documentElement.lang"
        wait_until(lambda: tab.page.evaluate(lang) == "en", 10, '<html lang="en">')
        tab.select("Language", "Русский")
        tab.label("Урок").wait_for(timeout=20000)
        wait_until(
            lambda: (
                [t.strip() for t in tab.page.get_by_role("tab").all_inner_texts()]
                == ["Урок", "Параметры", "Графики", "Экспорт"]
            ),
            10,
            "the tabs in Russian",
        )
        tab.label("Язык").wait_for(timeout=10000)
        wait_until(lambda: tab.page.evaluate(lang) == "ru", 10, 'the page\'s lang follows: "ru"')
        tab.tab("Параметры")
        tab.page.get_by_text("Векторы", exact=True).first.wait_for(timeout=10000)
        _fits(tab, "after the switch")
        tab.button("Пуск")
        wait_until(lambda: tab.session.playing, 10, "play")
        tab.button("Пауза")
        tab.shot("language-switched-ru-1400x900")
        before = set(en_lab.views)
        tab.page.reload()
        tab.label("Урок").wait_for(timeout=60000)  # the browser kept the choice
        new = wait_until(lambda: set(en_lab.views) - before, 20, "the new session")
        assert en_lab.views[max(new)].language.code == "ru"
        tab.select("Язык", "English")
        tab.label("Lesson").wait_for(timeout=20000)
        wait_until(lambda: tab.page.evaluate(lang) == "en", 10, 'the page\'s lang back to "en"')
        assert not [e for e in tab.errors if "pageerror" in e]
    finally:
        tab.close()
