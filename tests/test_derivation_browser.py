"""Derivations in a real browser at a laptop's 1400x900 and a phone's 390x844: no part of
a formula is drawn below 11 px, and nothing in a derivation is cut off (an element wider
or taller than its box is allowed only where it scrolls).  Screenshots of the Lesson tab
go to tests/artifacts/ (and to $DERIVATION_SHOTS when it is set)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.support.browser import Page
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]

SIZES = {"laptop": (1400, 900), "phone": (390, 844)}
#: Lessons with the longest sums, matrices, nested scripts and LaTeX statements.
CASES = [
    ("constrained-dynamics", "planar-3axis", "d'Alembert principle"),
    ("quadric", "ellipsoid", "The second-order surface"),
    ("carriage-free-vibration", "example", "Matrix form"),
    ("planar-3axis", "forward-drives", "Equations of motion"),
    ("self-study-2", "c2-4a", "Lagrange equations"),
]
MIN_PX = 11.0

#: Every formula element's font size below MIN_PX, and every box of the derivation whose
#: content does not fit it: wider than the box where the box does not scroll sideways, or
#: taller where it hides what sticks out.  (A MathML element's ink may pass its own box;
#: the HTML box around it must hold it or scroll.)
MEASURE_JS = """(minPx) => {
  const small = [], clipped = [];
  const root = document.querySelector('.al-derivation');
  if (!root) return [['no derivation'], [], 0];
  const scrolls = (v) => v === 'auto' || v === 'scroll';
  const hides = (v) => v === 'hidden' || v === 'clip';
  const say = (el, what) => what + ' ' + el.tagName + '.' + el.className + ' "'
    + (el.textContent || '').trim().slice(0, 40) + '"';
  for (const el of [root, ...root.querySelectorAll('*')]) {
    const tag = el.tagName.toLowerCase();
    if (tag === 'style') continue;
    const cs = getComputedStyle(el);
    if (el.closest('math')) {
      if ((el.textContent || '').trim() && parseFloat(cs.fontSize) < minPx)
        small.push(say(el, cs.fontSize));
      continue;
    }
    if (el.namespaceURI !== 'http://www.w3.org/1999/xhtml' || el.clientWidth === 0) continue;
    if (el.scrollWidth > el.clientWidth + 1 && !scrolls(cs.overflowX))
      clipped.push(say(el, 'width ' + el.scrollWidth + '>' + el.clientWidth));
    if (el.scrollHeight > el.clientHeight + 1 && hides(cs.overflowY))
      clipped.push(say(el, 'height ' + el.scrollHeight + '>' + el.clientHeight));
  }
  return [small, clipped, root.getBoundingClientRect().width];
}"""


def _shots() -> Path | None:
    where = os.environ.get("DERIVATION_SHOTS")
    if not where:
        return None
    path = Path(where)
    path.mkdir(parents=True, exist_ok=True)
    return path


@pytest.fixture(scope="module")
def lab(make_lab: Any) -> Any:
    """The module's server; a derivation may take its time on a busy machine (the
    limit is not what this module tests)."""
    server = make_lab(lesson="sphere")
    server.derivations.seconds = 120.0
    return server


@pytest.fixture(scope="module", params=list(SIZES))
def sized(request: Any, lab: Any, browser: Any) -> Iterator[tuple[str, Page]]:
    w, h = SIZES[request.param]
    context = browser.new_context(viewport={"width": w, "height": h})
    p = Page(lab, browser, context, ready_seconds=120.0)
    yield request.param, p
    p.close()


def _choose(tab: Page, lesson_id: str, preset: str) -> None:
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.session.session import lesson_label

    tab.tab("Controls")
    if tab.session.lesson.id != lesson_id:
        tab.input_for("Lesson").click()
        label = lesson_label(get_lesson(lesson_id))
        tab.page.get_by_role("option", name=label, exact=True).click()
        wait_until(lambda: tab.session.lesson.id == lesson_id, 60, f"lesson {lesson_id}")
    if tab.session.preset != preset or tab.session.edits():
        tab.input_for("Preset").click()
        tab.page.get_by_role("option", name=preset, exact=True).click()
        wait_until(lambda: tab.session.preset == preset and not tab.session.edits(), 60, preset)


@pytest.mark.parametrize("lesson_id, preset, step", CASES)
def test_formulas_are_readable_and_never_cut_off(
    sized: tuple[str, Page], lesson_id: str, preset: str, step: str
) -> None:
    size, tab = sized
    tab.errors.clear()
    _choose(tab, lesson_id, preset)
    tab.tab("Lesson")
    steps = tab.page.locator(".al-step")
    wait_until(
        lambda: steps.count() > 0 and tab.page.get_by_text(step).count() > 0,
        60,
        f"the derivation of {lesson_id}",
    )
    small, clipped, width = tab.page.evaluate(MEASURE_JS, MIN_PX)
    assert width > 0, "the derivation is not shown"
    assert small == [], f"{lesson_id} at {size}: text below {MIN_PX} px: {small[:8]}"
    assert clipped == [], f"{lesson_id} at {size}: cut off: {clipped[:8]}"
    target = steps.filter(has_text=step).first
    target.scroll_into_view_if_needed()
    name = f"derivation-{size}-{lesson_id}"
    tab.shot(name)
    shots = _shots()
    if shots is not None:
        tab.page.screenshot(path=str(shots / f"{name}.png"))
    assert tab.errors == [], tab.errors
