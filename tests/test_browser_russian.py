"""Every lesson on a Russian page in a real browser, at 1400x900 and at a projector's
1280x720: the layout checks of the English run hold (the scene framed in the free canvas,
nothing of the panel running over, no small text, contrast), no English word is left in
the panel's visible prose but for a short list of symbols, units and names, and in the
pseudo-language (every text half as long again) nothing of the panel runs over at
1280x720.  Screenshots go to ``$LAYOUT_SHOTS`` as ``ru-<size>-<lesson>.png`` and
``pseudo-projector-<lesson>.png``.

One page serves the module: the server's pages open in Russian; the page is switched to
the pseudo-language and back for its check."""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from analyzer_lab.i18n import language_of
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.pseudo import CODE as PSEUDO
from analyzer_lab.pseudo import HTML_LANG

from tests.support.browser import Page
from tests.support.layout import (
    GEOMETRY_JS,
    MIN_TEXT_PX,
    SHOTS,
    SIZES,
    check_screen,
    choose,
    dismissed,
)
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

#: Latin words a Russian page may show: function and method names, formats, the lab's name,
#: unit symbols the book writes in Latin, and the lessons' own symbols.
ALLOWED = {
    "analyzer", "lab", "csv", "json", "html", "sin", "cos", "tan", "exp", "sqrt", "atan",
    "atan2", "log", "abs", "max", "min", "sign", "pi", "english", "lsp", "dop853", "rk45",
    "arcsin", "arccos", "arctan", "sinh", "cosh", "tanh", "nan", "scipy", "linalg", "eigh",
    # the lessons' own names: a triangle, a choice's value, variables of a derivation's prose
    "abc", "inertia", "vertical",
}  # fmt: skip
#: The panel's visible prose: its text nodes outside formulas, figures and inputs.
PROSE_JS = """() => {
  const canvas = document.querySelector('canvas');
  const c = canvas.getBoundingClientRect();
  const words = [];
  const walk = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let n = walk.nextNode(); n; n = walk.nextNode()) {
    const el = n.parentElement;
    if (!el || !el.offsetParent || el.closest('math, svg, script, style, input, textarea')) continue;
    if (!el.checkVisibility({checkOpacity: true, checkVisibilityCSS: true})) continue;
    if (el.closest('.mantine-Notification-root')) continue;
    const r = el.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) continue;
    if (r.left < c.right && r.right > c.left && r.top < c.bottom && r.bottom > c.top
        && getComputedStyle(el).position !== 'fixed') continue;  // the scene's own labels
    words.push(n.textContent);
  }
  return words.join(' ');
}"""
_WORD = re.compile(r"(?<![A-Za-z0-9_])[A-Za-z]{3,}(?![A-Za-z0-9_])")


def english_words(text: str) -> list[str]:
    """The Latin words of three letters or more not in :data:`ALLOWED`, each with the
    text around it."""
    return sorted(
        {
            f"{m.group()} ({text[max(0, m.start() - 40) : m.end() + 20]!r})"
            for m in _WORD.finditer(text)
            if m.group().lower() not in ALLOWED
        }
    )


@pytest.fixture(scope="module")
def ru_lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lesson="sphere", language="ru", restore=False)


@pytest.fixture(scope="module")
def ru_page(ru_lab: Any, browser: Any) -> Iterator[Page]:
    w, h = SIZES["laptop"]
    SHOTS.mkdir(parents=True, exist_ok=True)
    context = browser.new_context(viewport={"width": w, "height": h})
    p = Page(ru_lab, browser, context, ready_seconds=180.0, first_label="Урок")
    yield p
    p.close()


def _lessons() -> list[str]:
    return [lesson.id for lesson in all_lessons()]


@pytest.mark.parametrize("lesson_id", _lessons())
def test_every_lesson_in_russian_at_1400x900_and_1280x720(ru_page: Page, lesson_id: str) -> None:
    tab = ru_page
    tab.errors.clear()
    choose(tab, lesson_id, get_lesson(lesson_id).presets[0].name)
    for size in ("laptop", "projector"):
        check_screen(tab, size, "in Russian")
        dismissed(tab)
        tab.page.screenshot(path=str(SHOTS / f"ru-{size}-{lesson_id}.png"))
        left = english_words(tab.page.evaluate(PROSE_JS))
        assert left == [], f"{lesson_id} at {size}: English words on the Russian page: {left}"
    assert tab.errors == []
    # the pseudo-language: every text half as long again, the panel still holds it
    with tab.session.lock:
        tab.view.set_language(language_of(PSEUDO))
    try:
        wait_until(
            lambda: tab.page.evaluate("document.documentElement.lang") == HTML_LANG,
            20,
            "the pseudo-language's page",
        )
        geo = wait_until(
            lambda: (
                (g := tab.page.evaluate(GEOMETRY_JS, MIN_TEXT_PX))["size"]
                == list(SIZES["projector"])
                and g
            ),
            10,
            "the page at 1280x720",
        )
        assert geo["over"] == [], f"{lesson_id} in the pseudo-language: {geo['over']}"
        assert geo["small"] == [], f"{lesson_id} in the pseudo-language: {geo['small']}"
        dismissed(tab)
        tab.page.screenshot(path=str(SHOTS / f"pseudo-projector-{lesson_id}.png"))
    finally:
        with tab.session.lock:
            tab.view.set_language(language_of("ru"))
        wait_until(lambda: tab.page.evaluate("document.documentElement.lang") == "ru", 20, "ru")
    tab.page.set_viewport_size({"width": SIZES["laptop"][0], "height": SIZES["laptop"][1]})
