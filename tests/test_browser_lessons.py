"""Every lesson and every preset in a real browser, at a laptop's 1400x900 and a
projector's 1280x720: the camera frames the scene, no derivation step, figure or readout
overflows the panel (a formula too long even at its smallest size scrolls inside its
own line), no
TeX reaches the page, the readout shows the lesson's declared quantities, and an edited
value makes the panel say "custom".  Screenshots of every lesson go to tests/artifacts/.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from analyzer_lab.view.notation import name_text

from tests.support.browser import Page, quat_matrix
from tests.support.layout import run_box
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]

SIZES = {"laptop": (1400, 900), "projector": (1280, 720)}
#: The scene's projected box covers this share of the canvas's shorter side.
COVER = (0.15, 0.85)

OVERFLOW_JS = """() => {
  const bad = [];
  for (const el of document.querySelectorAll('.al-step, .al-figure, .al-readout')) {
    // a figure kept wide enough for its smallest text to read scrolls in its own box
    if (el.classList.contains('al-figure') && getComputedStyle(el).overflowX === 'auto') continue;
    if (el.offsetParent !== null && el.scrollWidth > el.clientWidth + 1) {
      bad.push(el.className + ': ' + el.scrollWidth + ' > ' + el.clientWidth);
    }
  }
  return bad;
}"""

#: The visible text of the page outside formulas, and the text inside formulas.
TEXT_JS = """() => {
  const prose = [], maths = [];
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  while (walker.nextNode()) {
    const el = walker.currentNode.parentElement;
    if (!el || el.offsetParent === null) continue;
    (el.closest('math') ? maths : prose).push(walker.currentNode.textContent);
  }
  return [prose.join(' '), maths.join(' ')];
}"""


def coverage(camera: Any, bounds: Any) -> float:
    """The scene box's projected extent over the canvas's shorter side, from the camera
    the page reports (viser's camera frame: x right, y down, z forward)."""
    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    corners = np.array(
        [[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])]
    )
    R = quat_matrix(np.asarray(camera.wxyz, dtype=float))
    p = (corners - np.asarray(camera.position, dtype=float)) @ R  # world -> camera
    assert np.all(p[:, 2] > 0), "the scene is behind the camera"
    W, H = float(camera.image_width), float(camera.image_height)
    f = (H / 2) / math.tan(float(camera.fov) / 2)
    u, v = f * p[:, 0] / p[:, 2], f * p[:, 1] / p[:, 2]
    return float(max(np.ptp(u), np.ptp(v)) / min(W, H))


def _cases() -> list[tuple[str, str]]:
    from analyzer_lab.lessons.catalog import all_lessons

    return [(lesson.id, p.name) for lesson in all_lessons() for p in lesson.presets]


@pytest.fixture(scope="module", params=list(SIZES))
def sized(request: Any, lab: Any, browser: Any) -> Iterator[tuple[str, Page]]:
    w, h = SIZES[request.param]
    context = browser.new_context(viewport={"width": w, "height": h}, accept_downloads=True)
    p = Page(lab, browser, context)
    yield request.param, p
    p.close()


def _choose(tab: Page, lesson_id: str, preset: str) -> None:
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.session.session import lesson_label

    if tab.session.lesson.id != lesson_id:
        tab.input_for("Lesson").click()
        label = lesson_label(get_lesson(lesson_id))
        tab.page.get_by_role("option", name=label, exact=True).click()
        wait_until(lambda: tab.session.lesson.id == lesson_id, 10, f"lesson {lesson_id}")
    if tab.session.preset != preset or tab.session.edits():
        tab.input_for("Preset").click()
        tab.page.get_by_role("option", name=preset, exact=True).click()
        wait_until(lambda: tab.session.preset == preset and not tab.session.edits(), 10, preset)


def _framed(tab: Page) -> float:
    """Wait until the page reports the camera the view framed; return its coverage."""
    want = tab.camera_revision()  # the preset's load has finished: its camera revision is set

    def ready() -> float | None:
        cam = tab.framed_camera(want)
        if cam is None:
            return None
        try:
            return coverage(cam, run_box(tab.session))
        except AssertionError:
            return None

    return wait_until(ready, 15, "the framed camera")


@pytest.mark.parametrize("lesson_id, preset", _cases())
def test_every_preset_is_framed_fits_and_reads(
    sized: tuple[str, Page], lesson_id: str, preset: str
) -> None:
    size, tab = sized
    tab.errors.clear()
    _choose(tab, lesson_id, preset)
    cover = _framed(tab)
    cam = tab.view.client.camera
    assert COVER[0] <= cover <= COVER[1], (
        f"the scene covers {cover:.0%} of the canvas; the scene and its run "
        f"{run_box(tab.session)}, "
        f"framed {tab.view.renderer.framed}, camera {cam.position} -> {cam.look_at}, "
        f"fov {cam.fov}, image {cam.image_width}x{cam.image_height}"
    )
    tab.tab("Lesson")
    wait_until(lambda: tab.page.locator(".al-step").count() > 0, 15, "the derivation")
    overflow = tab.page.evaluate(OVERFLOW_JS)
    assert overflow == [], overflow
    prose, maths = tab.page.evaluate(TEXT_JS)
    for tex in ("\\", "varphi", "{"):
        assert tex not in prose, f"raw TeX {tex!r} shown: ...{prose[prose.find(tex) - 40 :][:80]}"
    for tex in ("\\", "varphi"):  # inside a formula a brace is a set or a case split
        assert tex not in maths, f"raw TeX {tex!r} in a formula"
    readout = tab.page.locator(".al-readout").first.inner_text()
    for name in tab.session.lesson.readout:
        if name in tab.session.frame.scalars:
            assert name_text(name) in readout, f"readout lacks {name} ({name_text(name)})"
    assert " units" not in readout and "_" not in readout, readout  # textbook names
    if preset == tab.session.lesson.presets[0].name:
        tab.shot(f"{size}-{lesson_id}")
    assert tab.errors == [], tab.errors


def test_an_edit_makes_the_panel_say_custom(sized: tuple[str, Page]) -> None:
    _, tab = sized
    _choose(tab, "sphere", "example-1.1")
    tab.tab("Controls")
    tab.fill("u1(t) =", "4")
    wait_until(lambda: tab.session.edits(), 5, "the edit")
    note = tab.page.locator(".al-preset-note").first
    wait_until(lambda: "custom (from example-1.1)" in note.inner_text(), 5, "custom")
    assert "u1" in note.inner_text()
