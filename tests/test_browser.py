"""The lab in a real browser: Playwright driving Debian's Chromium against an in-process server.

Screenshots go to tests/artifacts/ (git-ignored).  Without Chromium these tests skip
(install it with ``apt-get install chromium``); with CI=true they fail instead.  The
server, the browser and the pages are the fixtures of tests/conftest.py.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pytest

from tests.support.browser import ARTIFACTS, Page
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(300)]


def _label_of(lesson: Any) -> str:
    from analyzer_lab.session.session import lesson_label

    return lesson_label(lesson)


@pytest.mark.quick
def test_page_loads_with_title_math_and_no_console_errors(tab: Page) -> None:
    assert tab.page.title() == "Analyzer Lab"
    assert tab.page.locator("math").count() >= 5
    assert tab.page.locator(".al-reconstructed").count() >= 1
    assert tab.page.locator(".al-source").first.inner_text().startswith("(")
    tab.shot("page-loaded")
    assert tab.errors == []


def test_picker_lists_every_lesson_and_preset(tab: Page) -> None:
    from analyzer_lab.lessons.catalog import all_lessons

    options = tab.options("Lesson")
    assert options == [_label_of(l) for l in all_lessons()]
    assert tab.options("Preset") == ["(defaults)", *(p.name for p in tab.session.lesson.presets)]


def test_sphere_example_plays_slider_changes_motion_and_plots_update(tab: Page) -> None:
    tab.load(_label_of(tab.session.lesson), "example-1.1")
    tab.tab("Controls")
    tab.page.get_by_text("pause at t_end").click()  # keep playing past 10 s
    before = tab.shot("sphere-before-play")
    p0 = tab.session.frame.points["point"].copy()
    tab.button("Play")
    wait_until(lambda: tab.session.frame.t > 0.5, 30, "playback")
    assert not np.allclose(tab.session.frame.points["point"], p0)
    assert tab.session.frame.scalars["v2"] == pytest.approx(50.0)
    after = tab.shot("sphere-playing")
    assert before != after
    # move the u1 slider while playing: the speed changes, time keeps running
    t_before = tab.session.frame.t
    slider = tab.page.get_by_role("slider").first
    slider.focus()
    slider.press("End")  # u1 -> 20
    wait_until(lambda: tab.session.raw_values()["u1"] == "20", 20, "u1 from the slider")
    wait_until(lambda: abs(tab.session.frame.scalars["v2"] - 50.0) > 1.0, 20, "a changed motion")
    assert tab.session.playing and tab.session.frame.t > t_before
    assert tab.session.frame.scalars["u1"] == pytest.approx(20.0)
    assert tab.input_for("u1(t) =").input_value() == "20"
    # the live plots: uPlot charts exist and their pictures change while playing
    tab.tab("Plots")
    charts = tab.page.locator(".uplot")
    wait_until(lambda: charts.count() == len(tab.session.lesson.plots), 20, "uPlot charts")
    # the chart's frame (its uPlot is drawn anew as the x range grows with the run)
    box = wait_until(
        lambda: tab.page.locator(".uplot-container").first.bounding_box(), 20, "the chart's box"
    )
    c0 = tab.page.screenshot(clip=box)
    time.sleep(1.0)  # a second of playing: the chart's picture moves on
    c1 = tab.page.screenshot(clip=box, path=str(ARTIFACTS / "plot-velocity.png"))
    assert c0 != c1
    tab.button("Pause")
    assert tab.errors == []


def test_switching_lessons_while_charts_update_logs_no_error(tab: Page) -> None:
    """Lessons switched again and again while playing with the Plots tab open: the page
    never reports an update of a chart that is gone, and the replaced charts are removed."""
    from analyzer_lab.lessons.catalog import get_lesson

    tab.tab("Plots")
    order = ["sphere", "ellipsoid", "sphere-constant-speed", "quadric"] * 3
    for lesson_id in order:
        label = _label_of(get_lesson(lesson_id))
        if tab.session.lesson.id != lesson_id:
            tab.select("Lesson", label)
            wait_until(lambda: tab.session.lesson.id == lesson_id, 10, f"lesson {lesson_id}")
        tab.button("Play")
        wait_until(lambda: tab.session.playing and tab.session.frame.t > 0.1, 10, "playback")
        time.sleep(0.35)  # chart updates are flowing when the next switch comes
    charts = tab.page.locator(".uplot")
    wait_until(
        lambda: charts.count() == len(tab.session.lesson.plots),
        10,
        "only the current lesson's charts",
    )
    assert tab.errors == []


def test_bad_input_shows_a_message_next_to_its_field_and_changes_nothing(tab: Page) -> None:
    tab.tab("Controls")
    before = tab.session.raw_values()
    tab.fill("u1(t) =", "__import__('os')")
    wait_until(lambda: "u1" in tab.field_errors(), 5, "a refusal next to u1")
    assert tab.session.raw_values() == before
    # the typed text stays visible beside its message (never blanked or reverted)
    assert tab.input_for("u1(t) =").input_value() == "__import__('os')"
    tab.fill("sphere radius R", "-5")
    wait_until(lambda: "minimum" in tab.field_errors(), 5, "a range message")
    assert tab.input_for("sphere radius R").input_value() == "-5"
    tab.fill("sphere radius R", "nan")
    wait_until(lambda: "unknown name 'nan'" in tab.field_errors(), 5, "a NaN message")
    assert tab.session.raw_values() == before
    tab.shot("bad-input-message")
    tab.fill("u1(t) =", "5")  # fixed: its message goes away
    wait_until(lambda: "u1" not in tab.field_errors(), 5, "the u1 message cleared")
    tab.button("Play")
    wait_until(lambda: tab.session.frame.t > 0.2, 10, "playback after refusals")
    tab.button("Pause")


def test_two_contexts_are_independent(lab: Any, browser: Any) -> None:
    a = Page(lab, browser)
    b = Page(lab, browser)
    try:
        assert a.view is not b.view
        a.load(_label_of(a.session.lesson), "example-1.2")
        a.button("Play")
        wait_until(lambda: a.session.frame.t > 0.3, 10, "playback in a")
        assert (
            b.session.preset != "example-1.2" and b.session.frame.t == 0.0 and not b.session.playing
        )
        b.tab("Controls")
        b.fill("u2(t) =", "1.5")
        wait_until(lambda: b.session.raw_values()["u2"] == "1.5", 5, "u2 in b")
        assert a.session.raw_values()["u2"] == "5"
        a.button("Pause")
    finally:
        a.close()
        b.close()


def test_csv_exports_on_the_textbook_grid_and_of_the_frames(tab: Page) -> None:
    """Example 1.2 played to t_end: the grid CSV has |v|² at t = 0, 1, ..., 10 as the
    textbook tabulates it; the frames CSV has every played frame; both carry the lesson's
    declared series."""
    from analyzer_lab.lessons.analyzers.sphere import V2_TABLE

    tab.load(_label_of(tab.session.lesson), "example-1.2")
    tab.select("Speed", "8x")
    tab.button("Play")
    wait_until(lambda: tab.session.frame.t >= 10.0 - 1e-9, 20, "the run to t_end")
    tab.tab("Export")
    with tab.page.expect_download(timeout=20000) as info:
        tab.page.get_by_role("button", name="Download CSV (grid)").click()
    path = ARTIFACTS / "export-grid.csv"
    info.value.save_as(path)
    assert info.value.suggested_filename == "analyzer-lab-sphere-example-1.2.csv"
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    assert header[:4] == ["t", "x", "y", "z"]
    rows = [list(map(float, ln.split(","))) for ln in lines[1:]]
    assert [r[0] for r in rows] == pytest.approx(list(range(11)))
    v2 = [r[header.index("v2")] for r in rows]
    assert np.max(np.abs(np.array(v2) - np.array(V2_TABLE["example-1.2"]))) <= 5e-4
    with tab.page.expect_download(timeout=20000) as info:
        tab.page.get_by_role("button", name="Download CSV (frames)").click()
    frames = ARTIFACTS / "export-frames.csv"
    info.value.save_as(frames)
    flines = frames.read_text().splitlines()
    assert flines[0].split(",") == header
    assert len(flines) - 1 == len(tab.session.log) >= 10


def test_reload_restores_lesson_and_parameters(tab: Page) -> None:
    tab.load(_label_of(tab.session.lesson), "example-1.3")
    tab.tab("Controls")
    tab.fill("u3(t) =", "4")
    wait_until(lambda: tab.session.raw_values()["u3"] == "4", 5, "u3")
    wait_until(
        lambda: (tab.saved_state() or {}).get("values", {}).get("u3") == "4",
        5,
        "u3 saved in the page",
    )
    before = set(tab.lab.views)
    tab.page.reload()
    new = wait_until(lambda: set(tab.lab.views) - before, 20, "the reloaded session")
    tab.view = tab.lab.views[max(new)]
    wait_until(lambda: tab.session.raw_values().get("u3") == "4", 10, "restored values")
    assert tab.session.preset == "example-1.3" and tab.session.raw_values()["u1"] == "sin(10*t)"


def _catalog_cases() -> list[tuple[str, str]]:
    from analyzer_lab.lessons.catalog import all_lessons

    return [(l.id, p) for l in all_lessons() for p in ["(defaults)", *(q.name for q in l.presets)]]


def _choose_preset(tab: Page, preset: str, want: str | None) -> None:
    """Choose ``preset`` in the picker, once: the page's choice is taken as it was sent,
    also right after a lesson's (whose handling resets the picker)."""
    tab.input_for("Preset").click()
    tab.page.get_by_role("option", name=preset, exact=True).click()
    wait_until(lambda: tab.session.preset == want, 10, f"preset {preset}")


@pytest.mark.parametrize("lesson_id, preset", _catalog_cases())
def test_every_lesson_and_preset_plays(shared_tab: Page, lesson_id: str, preset: str) -> None:
    from analyzer_lab.lessons.catalog import get_lesson

    tab = shared_tab
    tab.errors.clear()
    label = _label_of(get_lesson(lesson_id))
    if tab.session.lesson.id != lesson_id:
        tab.input_for("Lesson").click()
        tab.page.get_by_role("option", name=label, exact=True).click()
        wait_until(lambda: tab.session.lesson.id == lesson_id, 10, f"lesson {lesson_id}")
    want = None if preset == "(defaults)" else preset
    if tab.session.preset != want or preset == "(defaults)":
        _choose_preset(tab, preset, want)
    time.sleep(0.06)  # viser's 50 ms input throttle
    t0 = tab.session.frame.t
    tab.page.get_by_role("button", name="Play", exact=True).click()
    # lessons choose their own time scale (slow motion for vibrations): any progress counts
    wait_until(
        lambda: tab.session.frame.t > t0 or (not tab.session.playing and tab.session.notices),
        10,
        "playback",
    )
    assert tab.page.locator("math").count() > 0
    assert "internal error" not in tab.status()
    errors = list(tab.errors)
    assert errors == [], errors


def test_arrow_keys_on_a_focused_slider_move_the_slider_not_the_camera(tab: Page) -> None:
    tab.load(_label_of(tab.session.lesson), "example-1.1")
    tab.tab("Controls")
    revision = tab.camera_revision()
    wait_until(lambda: tab.framed_camera(revision), 15, "the framed camera")
    before = np.array(tab.view.client.camera.position, dtype=float)
    tab.page.get_by_role("slider").first.focus()
    for _ in range(5):
        tab.page.keyboard.press("ArrowRight")
        time.sleep(0.1)  # one key per input viser sends (it sends at most every 50 ms)
    wait_until(lambda: tab.session.raw_values()["u1"] != "5", 5, "the slider moved")
    time.sleep(0.5)  # a camera the keys moved would be reported by now: none may come
    after = np.array(tab.view.client.camera.position, dtype=float)
    assert np.allclose(before, after), (before, after)
