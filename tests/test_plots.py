"""The live plots' data: the whole run from the session's log, decimated, x = the run so
far; only the series a preset defines (no chart left empty)."""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.session.runlog import RunLog
from analyzer_lab.session.session import Session
from analyzer_lab.view.plots import COLUMNS, PlotPanel, chart_data


def _log(n: int, t_end: float) -> RunLog:
    log = RunLog()
    for t in np.linspace(0.0, t_end, n):
        log.add(Frame(float(t), scalars={"v": float(np.sin(2 * np.pi * 3.1 * t)), "d": 1e-16 * t}))
    return log


def test_chart_data_spans_the_whole_run_with_its_extremes() -> None:
    log = _log(12000, 96.0)  # 8x for 12 s, every frame played
    data = chart_data(log, ("v",))
    assert data.t[0] == 0.0 and data.t[-1] == 96.0
    assert data.x_range == (0.0, 96.0)
    assert len(data.t) <= 4 * COLUMNS + 2
    assert data.values[0].max() > 0.999 and data.values[0].min() < -0.999
    # no stretch of the run is left out: the kept samples are at most a pixel column apart
    assert np.diff(data.t).max() <= 2 * 96.0 / COLUMNS


def test_chart_data_of_a_tiny_series_is_scaled_and_a_missing_one_is_a_gap() -> None:
    data = chart_data(_log(100, 1.0), ("d", "absent"))
    assert data.exponent == -16
    assert np.isclose(np.nanmax(data.values[0]), 1.0)
    assert np.isnan(data.values[1]).all()


def test_a_fresh_run_has_an_x_range_of_positive_width() -> None:
    log = RunLog()
    log.add(Frame(0.0, scalars={"v": 1.0}))
    assert chart_data(log, ("v",), min_span=0.5).x_range == (0.0, 0.5)


def test_charts_show_only_the_series_a_preset_defines() -> None:
    cd = get_lesson("constrained-dynamics")
    setup = cd.open(None, "pendulum-drift")
    layout = dict(
        zip(
            (p.title for p in cd.plots),
            PlotPanel.layout_for(cd, setup.params, setup.stepper.reset()),
        )
    )
    assert layout["Constraint drift"] == ("f",)
    assert layout["Rod length"] == ()
    ss2 = get_lesson("self-study-2")
    setup = ss2.open(None, "c2-4a")
    layout = dict(
        zip(
            (p.title for p in ss2.plots),
            PlotPanel.layout_for(ss2, setup.params, setup.stepper.reset()),
        )
    )
    assert layout["Angle phi"] == () and layout["Moments"] == ()
    assert layout["Translations"] == ("z",)


def test_every_shown_chart_of_every_preset_gets_numbers_when_played() -> None:
    """A chart that is drawn has a series with a finite value once the run has moved:
    no preset of any lesson leaves a drawn chart empty."""
    empty = []
    for lesson in all_lessons():
        session = Session([lesson])
        for preset in (None, *(p.name for p in lesson.presets)):
            session.apply_preset(preset)
            layout = PlotPanel.layout_for(lesson, session.params, session.frame)
            session.go_to(min(session.t_end, 0.2 * lesson.time_scale))
            for spec, names in zip(lesson.plots, layout):
                if names and not np.isfinite(chart_data(session.log, names).values).any():
                    empty.append(f"{lesson.id}/{preset}: {spec.title}")
    assert empty == []


def test_a_russian_page_shows_the_plot_titles_in_russian() -> None:
    import viser
    from analyzer_lab.i18n import resolve

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        cd = get_lesson("constrained-dynamics")
        setup = cd.open(None, "pendulum-drift")
        frame = setup.stepper.reset()
        panel = PlotPanel(server.gui)
        folder = panel.build(cd, setup.params, RunLog(), frame, "pendulum-drift", resolve("ru")[0])
        titles = [chart.handle.title for chart in panel.charts]
        assert "Дрейф связей" in titles and "Constraint drift" not in titles
        assert "Длина стержня" in panel.missing  # a chart not defined, named in Russian
        # the charts' own chrome: the folder, the note, the time axis
        assert panel.note.content.count("Не определены в этом примере: “Длина стержня”")
        assert all(chart.handle.axes[0]["label"] == "t [с]" for chart in panel.charts)
        english = PlotPanel(server.gui)
        english_folder = english.build(cd, setup.params, RunLog(), frame, "pendulum-drift")
        assert "Constraint drift" in [chart.handle.title for chart in english.charts]
        assert "Not defined for this preset:" in english.note.content
        assert all(chart.handle.axes[0]["label"] == "t [s]" for chart in english.charts)
        assert folder.label == "Графики (весь прогон)"
        assert english_folder.label == "Live plots (the whole run)"
    finally:
        server.stop()
