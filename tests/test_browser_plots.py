"""The live plots in a real browser: the whole run whatever tab was open, x = the run so
far, and no empty chart for a preset that does not define its series."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.session.session import lesson_label

from tests.support.browser import ARTIFACTS, Page
from tests.support.waiting import wait_until

pytestmark = pytest.mark.browser

#: The charts as the page drew them (viser's uPlot testpoint): title, series labels,
#: x data ends and x scale.
CHARTS_JS = """() => Object.values((window.__viserTestpoints || {}).uplots || {}).map(
  ({chart}) => ({
    title: (chart.root.querySelector('.u-title') || {}).innerText || '',
    labels: chart.series.map(s => s.label),
    n: chart.data[0].length,
    first: chart.data[0][0],
    last: chart.data[0][chart.data[0].length - 1],
    min: chart.scales.x.min,
    max: chart.scales.x.max,
    finite: chart.data.slice(1).some(col => Array.from(col).some(Number.isFinite)),
  }))"""
SHOTS = Path("/tmp/plots-shots")


@pytest.fixture()
def wide(lab: Any, browser: Any) -> Iterator[Page]:
    """A page of ``lab`` at 1400 x 900."""
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    p = Page(lab, browser, context)
    yield p
    p.close()


def _charts(tab: Page) -> list[dict[str, Any]]:
    return tab.page.evaluate(CHARTS_JS)


def _shot(tab: Page, name: str) -> None:
    tab.shot(name)
    SHOTS.mkdir(exist_ok=True)
    shutil.copy(ARTIFACTS / f"{name}.png", SHOTS / f"{name}.png")


def test_a_plot_keeps_the_whole_run_after_playing_on_another_tab(wide: Page) -> None:
    tab = wide
    tab.load(lesson_label(get_lesson("sphere")), "example-1.2")
    tab.tab("Controls")
    tab.page.get_by_text("pause at t_end").click()
    wait_until(lambda: not tab.session.pause_at_end, 10, "pause at t_end off")
    tab.select("Speed", "8x")
    wait_until(lambda: tab.session.speed == 8.0, 10, "8x")
    tab.tab("Lesson")
    tab.button("Play")
    wait_until(lambda: tab.session.frame.t > 40.0, 120, "40 s of the run on the Lesson tab")
    tab.tab("Plots")
    tab.button("Pause")
    wait_until(lambda: not tab.session.playing, 10, "paused")
    end = float(tab.session.log.t[-1])
    expected = len(tab.view.plots.charts)
    assert expected == len(get_lesson("sphere").plots)

    def whole_run() -> bool:
        charts = _charts(tab)
        return len(charts) == expected and all(
            c["first"] == 0.0
            and c["last"] == pytest.approx(end, abs=1e-9)
            and c["min"] == pytest.approx(0.0, abs=1e-9)
            and c["max"] == pytest.approx(end, rel=1e-9)
            for c in charts
        )

    wait_until(whole_run, 30, f"every chart spanning t = 0 to {end:.3f} s")
    for c in _charts(tab):
        assert 100 < c["n"] < 4 * 360 * len(c["labels"]), c  # decimated, not a 12 Hz sample
    _shot(tab, "plots-sphere-example-1.2-whole-run")
    assert tab.errors == []


@pytest.mark.parametrize(
    ("lesson_id", "preset", "hidden", "kept"),
    [
        ("constrained-dynamics", "pendulum-drift", {"Rod length"}, {"Constraint drift": ["f"]}),
        ("self-study-2", "c2-4a", {"Angle phi", "Moments"}, {"Translations": ["z"]}),
    ],
)
def test_a_preset_without_a_series_shows_no_empty_chart(
    wide: Page, lesson_id: str, preset: str, hidden: set[str], kept: dict[str, list[str]]
) -> None:
    tab = wide
    lesson = get_lesson(lesson_id)
    tab.load(lesson_label(lesson), preset)
    tab.tab("Plots")
    tab.button("Step")
    wait_until(lambda: tab.session.frame.t > 0.0, 20, "a step")
    shown = [spec.title for spec, names in zip(lesson.plots, tab.view.plots.layout) if names]
    assert not hidden & set(shown)

    def drawn() -> list[dict[str, Any]] | None:
        charts = _charts(tab)
        if sorted(c["title"] for c in charts) != sorted(shown):
            return None
        return charts if all(c["finite"] and c["n"] > 1 for c in charts) else None

    charts = wait_until(drawn, 60, "only the defined charts, each with numbers")
    for title, labels in kept.items():
        chart = next(c for c in charts if c["title"] == title)
        assert chart["labels"] == ["t", *labels]
    note = tab.page.locator(".al-plots-undefined").inner_text()
    assert note.startswith("Not defined for this preset:")
    for title in hidden:
        assert title in note
    _shot(tab, f"plots-{lesson_id}-{preset}")
    assert tab.errors == []
