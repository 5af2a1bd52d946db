"""Tests of the servo-errors lesson (Leppik 1960) and lessons/servo/model.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.kit.contract import ParamError, Params
from analyzer_lab.lessons.servo import LESSON
from analyzer_lab.lessons.servo.paths import CURVES

SERIES = [s.name for s in LESSON.series]


# ---------------------------------------------------------------- presets, runs


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_presets_resolve_and_simulate(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    assert isinstance(params, Params)
    result = LESSON.run(preset)
    data = result.to_json_dict()
    assert list(result.series) == SERIES
    for name in SERIES:
        assert len(result.series[name]) == len(result.t)
        assert np.all(np.isfinite(result.series[name])), name
    assert result.units == {name: "mm" for name in SERIES}
    assert "delta_after_transient" in data["metrics"]
    assert math.isfinite(result.metrics["delta_after_transient"])


def test_table_cells_through_the_lesson() -> None:
    rows = LESSON.derivation(LESSON.resolve(preset="table-parabola"))
    table = next(s for s in rows if s.source == "table")
    assert table.text.count("\n| ") == 17  # header + 16 cells


def test_table_preset_metrics() -> None:
    m = LESSON.run("table-parabola").metrics
    assert m["delta_13"] == pytest.approx(-0.2375)
    assert m["delta_after_transient"] == pytest.approx(-0.2375, rel=1e-3)
    assert m["table_printed"] == pytest.approx(-0.19)
    assert m["table_printed_over_13"] == pytest.approx(0.8)
    assert "0.8" in m["table_note"]


def test_line_offset_5_6() -> None:
    m = LESSON.run("line-45").metrics
    assert m["delta_5"] == pytest.approx(0.05)
    assert m["delta_end"] == pytest.approx(0.05, abs=1e-6)
    m = LESSON.run("line-45", values={"angle": 30, "gamma": 0.7}, t_end=2.0).metrics
    assert m["delta_end"] == pytest.approx(-0.0649519, abs=1e-6)


def test_line_at_rest_has_no_error_and_transient_follows_4() -> None:
    r = LESSON.run("line-transient", values={"xdot0": 0})
    assert np.max(np.abs(r.series["delta"])) < 1e-9
    assert np.max(np.abs(r.series["error_x"])) > 0.3  # the lag is along the line
    r = LESSON.run("line-transient")
    peak = float(np.max(np.abs(r.series["delta"])))
    assert peak == pytest.approx(0.580629, abs=1e-5)  # (4) with xdot0 = 50 mm/s at 45 deg
    T1, T2sq = 0.01, 0.0005
    assert 50 * math.sqrt(0.5) * 1.05 * T2sq / (T1 + math.sqrt(T2sq)) == pytest.approx(
        peak, rel=0.05
    )


def test_circle_28() -> None:
    m = LESSON.run("circle", t_end=8.0).metrics
    assert m["R0_minus_R_28"] == pytest.approx(-0.24295, abs=1e-5)
    assert m["sim_R0_minus_R"] == pytest.approx(m["R0_minus_R_28"], rel=1e-6)


def test_circle_nonidentical_29_30() -> None:
    m = LESSON.run("circle-nonidentical").metrics
    assert m["tilt_29_deg"] == pytest.approx(63.127, abs=1e-3)
    assert m["sim_tilt_deg"] == pytest.approx(m["tilt_29_deg"], abs=1e-3)
    assert m["sim_semi_major"] == pytest.approx(12.00691, abs=1e-4)
    assert m["sim_semi_minor"] == pytest.approx(10.78178, abs=1e-4)
    assert m["semi_major_30"] == pytest.approx(m["sim_semi_major"], rel=1e-5)
    assert m["semi_major_30_printed"] == pytest.approx(
        12.02954, abs=1e-4
    )  # the printed (30) misses the square


def test_ellipse_presets() -> None:
    m = LESSON.run("ellipse").metrics
    assert (m["sim_semi_major"], m["sim_semi_minor"]) == pytest.approx(
        (15.96743, 6.38697), abs=1e-4
    )
    m = LESSON.run("ellipse-nonidentical").metrics
    assert (m["sim_semi_major"], m["sim_semi_minor"]) == pytest.approx(
        (15.97402, 6.62696), abs=1e-4
    )
    assert m["sim_tilt_deg"] == pytest.approx(1.809, abs=1e-3)


@pytest.mark.parametrize(
    "preset",
    [
        "table-parabola",
        "line-45",
        "circle-nonidentical",
        "ellipse-nonidentical",
        "cubic",
        "quartic",
    ],
)
def test_correction_removes_steady_error(preset: str) -> None:
    off = LESSON.run(preset).metrics
    on = LESSON.run(preset, values={"correction": "on"}, t_end=LESSON.preset_t_end(preset) + 3.0)
    assert abs(off["delta_steady_extreme"]) > 1e-3
    assert abs(on.metrics["delta_steady_extreme"]) < 1e-9
    assert abs(on.series["delta"][-1]) < 1e-6
    assert abs(on.series["error_x"][-1]) < 1e-6 and abs(on.series["error_y"][-1]) < 1e-6


def test_parabola_correction_starts_at_22() -> None:
    r = LESSON.run("parabola-corrected")
    omega, p, T1, T2sq = 5.0, 20.0, 0.01, 0.001
    assert r.metrics["input_x0"] == pytest.approx(-125 + omega * p * T1 / 2)
    assert r.metrics["input_y0"] == pytest.approx(
        781.25 + omega * (-125) * T1 + omega**2 * p * T2sq / 2
    )


def test_cubic_and_quartic_shifts() -> None:
    m = LESSON.run("cubic").metrics
    assert m["delta_article"] == pytest.approx(0.00875, rel=1e-6)
    m = LESSON.run("quartic").metrics
    assert m["delta_article"] == pytest.approx(
        3 * 781.25 * (3e-8 + 8 * 2.5e-7 - 12 * 1e-4 * 5e-4), rel=1e-6
    )


def test_bad_input() -> None:
    with pytest.raises(ParamError):
        LESSON.resolve({"curve": "circle", "x0": 0, "y0": 0, "xc": 0, "yc": 0})
    with pytest.raises(ParamError):
        LESSON.resolve({"k": -1})
    with pytest.raises(ParamError):
        LESSON.resolve({"curve": "spiral"})
    r = LESSON.simulate(LESSON.resolve(preset="circle"), t_end=0.0)
    assert len(r.t) == 1 and r.messages
    r = LESSON.simulate(LESSON.resolve(preset="table-parabola", values={"y0": 0}), t_end=1.0)
    assert any("y0" in m for m in r.messages)


# ---------------------------------------------------------------- live


def test_stepper_is_exact_and_keeps_state() -> None:
    params = LESSON.resolve(preset="circle-nonidentical")
    run = LESSON.simulate(params, t_end=1.0)
    st = LESSON.stepper(params)
    for _ in range(100):
        frame = st.advance(0.01)
    assert st.t == pytest.approx(1.0)
    assert frame.points["reproduced"][0, 0] == pytest.approx(run.series["x1"][-1], abs=1e-9)
    assert frame.points["reproduced"][0, 1] == pytest.approx(run.series["y1"][-1], abs=1e-9)
    assert list(frame.scalars) == SERIES
    before = frame.points["reproduced"].copy()
    st.set_params(
        LESSON.resolve(preset="circle-nonidentical", values={"k": 300, "correction": "on"})
    )
    assert st.t == pytest.approx(1.0)
    assert np.allclose(st.frame().points["reproduced"], before)
    assert "corrected program" in st.frame().points
    for _ in range(300):
        frame = st.advance(0.01)
    assert abs(frame.scalars["delta"]) < 1e-4  # the corrected program has removed the error
    st.set_params(LESSON.resolve(preset="circle-nonidentical", values={"curve": "ellipse"}))
    assert st.t == 0.0 and "restarted" in st.frame().message
    frame = st.reset()
    assert frame.t == 0.0
    assert np.allclose(frame.points["reproduced"], frame.points["programmed"])


def test_error_point_magnifies_contour_error() -> None:
    params = LESSON.resolve(preset="circle", values={"magnify": 50})
    st = LESSON.stepper(params)
    frame = st.advance(4.0)
    r_err = float(np.hypot(*frame.points["error x N"][0, :2]))
    assert 10.0 - r_err == pytest.approx(50 * frame.scalars["delta"], rel=1e-9)
    origin, vec = frame.vectors["error vector x N"]
    assert float(np.hypot(*vec[0, :2])) == pytest.approx(50 * abs(frame.scalars["delta"]), rel=1e-9)


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_scene(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    scene = LESSON.scene(params)
    assert scene.planar
    lo, hi = np.array(scene.bounds[0]), np.array(scene.bounds[1])
    assert np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(hi > lo)
    assert {"programmed", "reproduced", "error x N"} <= set(scene.moving_points)
    frame = LESSON.stepper(params).advance(0.05)
    assert set(scene.moving_points) == set(frame.points)
    for c in scene.curves:
        assert np.all(np.isfinite(c.points)) and np.all(c.points[:, 2] == 0.0)
    names = {n for p in LESSON.plots for n in p.series}
    assert names <= set(frame.scalars)


# ---------------------------------------------------------------- page and claims


@pytest.mark.parametrize("curve", CURVES)
def test_derivation_marks_misprints(curve: str) -> None:
    values = {"curve": curve}
    if curve in ("circle", "ellipse"):
        values.update({"x0": 0, "y0": 6})
    steps = LESSON.derivation(LESSON.resolve(values))
    assert all(s.source for s in steps)
    assert any(s.reconstructed for s in steps)
    if curve == "parabola":
        table = next(s for s in steps if s.source == "table")
        assert (
            "0.8" in table.text
            and "-0.19" in table.text
            and "-0.2375" in table.text
            and table.reconstructed
        )
        assert any(s.source == "(18)" and s.reconstructed for s in steps)
    if curve == "circle":
        assert any(s.source == "(30)" and "cos^2" in (s.reconstructed or "") for s in steps)
    if curve == "parabola-horizontal":
        assert [s.source for s in steps].count("(19)") == 2
    text = " ".join(s.source + " " + s.text + " " + (s.reconstructed or "") for s in steps)
    assert "digest" not in text and "I.6" not in text and "I.7" not in text


@pytest.mark.parametrize("claim", LESSON.claims(), ids=lambda c: c.id)
def test_claims_pass(claim) -> None:
    result = claim.check()
    assert result.passed, (claim.id, result.expected, result.got)


# ---------------------------------------------------------------- horizontal parabola (19)


@pytest.mark.parametrize(
    ("preset", "gamma", "vertex_y", "at_zero"),
    [("fig4b-gamma-0.5", 0.5, 0.25, -0.234375), ("fig4b-gamma-1", 1.0, 0.0, -0.2375),
     ("fig4b-gamma-2", 2.0, -0.5, -0.225)],
)  # fmt: skip
def test_fig4b_presets_follow_19(
    preset: str, gamma: float, vertex_y: float, at_zero: float
) -> None:
    r = LESSON.run(preset)
    m = r.metrics
    assert (m["vertex_19_x"], m["vertex_19_y"]) == pytest.approx((-0.2375, vertex_y))
    assert m["delta_article"] == pytest.approx(-0.2375)  # (19): x_c for every gamma
    assert m["article_formula"] == "(19) vertex"
    after = r.t > 3.0  # 15 time constants: the transient has gone
    x1, y1 = r.series["x1"][after], r.series["y1"][after]
    c = 5.0 * 0.01 * (gamma - 1.0)
    assert np.max(np.abs(x1 - (y1**2 / 20.0 + c * y1 + at_zero))) < 1e-5
    # the steady output lags by T1 omega p / 2 = 0.5 mm: it passes its vertex at y = 0.5 mm
    i = int(np.argmin(np.abs(r.series["y"] - 0.5)))
    if gamma == 1.0:
        assert r.series["delta_steady"][i] == pytest.approx(-0.2375, abs=1e-9)


def test_fig4b_error_grows_off_the_vertex_for_gamma_2() -> None:
    r = LESSON.run("fig4b-gamma-2")
    # the steady output lags by gamma T1 omega p / 2 = 1 mm: |y1| <= 20 mm is y in [-19, 21]
    d, y1 = r.series["delta_steady"], r.series["y"] - 1.0
    left = float(np.max(np.abs(d[(y1 < 0) & (y1 >= -20)])))
    right = float(np.max(np.abs(d[(y1 > 0) & (y1 <= 20)])))
    assert left == pytest.approx(0.5533, abs=2e-4) and right == pytest.approx(0.3445, abs=2e-4)


def test_derivative_feed_forward_preset() -> None:
    m = LESSON.run("parabola-derivative").metrics
    assert m["delta_article"] == pytest.approx(-0.25)
    assert m["delta_after_transient"] == pytest.approx(-0.25, rel=1e-3)  # sampled
    r = LESSON.run("parabola-derivative", values={"curve": "circle", "x0": 0, "y0": 10})
    assert np.all(np.isnan(r.series["delta_article"]))
    assert any("derivative feed-forward" in m for m in r.messages)


def test_notes() -> None:
    notes = LESSON.notes(LESSON.resolve(preset="fig4b-gamma-0.5", values={"x0": 0}))
    kinds = {n.kind for n in notes}
    assert {"info", "corrected", "warning"} <= kinds
    assert any(n.text.startswith("x0 is taken on the curve") for n in notes)
    assert all(n.source.startswith("Leppik (1960)") for n in notes if n.kind != "info" or n.source)
    table = LESSON.notes(LESSON.resolve(preset="table-parabola"))
    assert any("-0.19" in n.text and "0.8" in n.text for n in table)


def test_declarations() -> None:
    assert LESSON.declaration_errors() == []
    assert LESSON.modes == ("curve", "correction")
    assert [g.name for g in LESSON.groups][0] == "mode"
    assert {LESSON.param(m).group for m in LESSON.modes} == {"mode"}
    assert all(s.unit == "mm" for s in LESSON.series)


def test_played_frames_carry_the_state_by_kept_step_maps() -> None:
    params = LESSON.resolve(preset="table-parabola")
    st = LESSON.stepper(params)
    system = st._setup.system
    z0 = system.initial_state(float(params["xdot0"]), float(params["ydot0"]))
    for k in range(600):  # 17 s of frames of 16 or 17 quanta of 1/600 s
        st.advance((17 if k % 3 else 16) / 600.0)
    exact = system.states([st.t], z0, 0.0)[0]
    carried = st._state()[0]
    assert np.max(np.abs(carried - exact)) <= 1e-10 * np.max(np.abs(exact))
    assert 0 < len(system._step_maps) <= 4  # the two frame lengths, rounded
    # new channel values: a new servo (its own maps), carried from the current state
    st.set_params(LESSON.resolve(preset="table-parabola", values={"k": 300}))
    assert st._setup.system is not system and not st._setup.system.__dict__.get("_step_maps")
    st.advance(17 / 600.0)  # solved at once from the new anchor
    st.advance(17 / 600.0)  # carried
    assert len(st._setup.system._step_maps) == 1
