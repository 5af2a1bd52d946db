"""Tests of the servo-errors lesson (Leppik 1960) and lessons/core/servo.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal

from lessons.core.contract import ParamError, Params
from lessons.core.servo import (
    Channel,
    TwoAxisServo,
    circle_axes_29_30,
    delta_parabola_13,
    ellipse_distance,
    parabola_table,
    power_distance,
    power_program,
    table_ratio_interval,
)
from lessons.servo_errors import LESSON, table_rows

SERIES = ("t", "x", "y", "z", "x1", "y1")


# ---------------------------------------------------------------- core


@pytest.mark.filterwarnings("ignore::scipy.signal.BadCoefficients")
def test_open_loop_channel_matches_closed_loop_of_W() -> None:
    k, T = 200.0, 0.5
    ch = Channel.from_open_loop(k, T)
    assert ch.T1 == pytest.approx(1 / k) and ch.T2sq == pytest.approx(T / k)
    # closed loop of W = k/((Ts+1)s) is k / (T s^2 + s + k) = 1 / ((T/k) s^2 + (1/k) s + 1)
    ss = ch.state_space()
    b, a = signal.ss2tf(ss.A, ss.B, ss.C, ss.D)
    assert np.allclose(b[0] / a[-1], [0.0, 0.0, 1.0]) and np.allclose(
        a / a[-1], [T / k, 1 / k, 1.0]
    )
    w = 3.0
    expected = k / ((1j * w) * (T * 1j * w + 1) + k)
    assert ch.response(w) == pytest.approx(expected, rel=1e-12)
    _, h = signal.freqresp(ch.state_space(), [w])
    assert h[0] == pytest.approx(expected, rel=1e-10)


def test_exact_step_agrees_with_lsim() -> None:
    """The matrix-exponential model and scipy.signal.lsim give the same channel output."""
    ch = Channel(0.01, 0.001)
    system = TwoAxisServo(power_program(2, -50.0, 0.0, 0.0, 20.0, 5.0), ch, ch)
    t = np.linspace(0.0, 2.0, 4001)
    out = system.outputs(system.run(t, system.initial_state()))
    _, y, _ = signal.lsim(ch.state_space(), out["y"], t, X0=[out["y"][0], 0.0])
    assert np.max(np.abs(y - out["y1"])) < 1e-3  # lsim interpolates the input linearly: O(dt^2)
    assert np.max(np.abs(y - out["y1"])) > 0.0


def test_distances() -> None:
    d, fx, fy = power_distance(
        np.array([0.0, 3.0]), np.array([-0.2, 0.45 - 0.1]), 2, 0.0, 0.0, 20.0
    )
    assert d[0] == pytest.approx(-0.2, abs=1e-12)
    assert d[1] < 0 and abs(d[1]) < 0.1
    assert fy[1] == pytest.approx(fx[1] ** 2 / 20.0)
    d, _, _ = ellipse_distance(np.array([15.5, 0.0]), np.array([0.0, 5.0]), 0.0, 0.0, 15.0, 6.0)
    assert d[0] == pytest.approx(-0.5, abs=1e-10) and d[1] == pytest.approx(1.0, abs=1e-10)


# ---------------------------------------------------------------- the table


def test_parabola_table_three_ways() -> None:
    rows = table_rows()
    assert len(rows) == 16
    cell = next(r for r in rows if r["k"] == 100 and r["T"] == 0.1)
    assert cell["formula_13"] == pytest.approx(-0.2375)
    assert cell["simulated"] == pytest.approx(-0.2375, rel=1e-4)
    assert cell["printed"] == pytest.approx(-0.19)
    assert cell["printed_over_formula"] == pytest.approx(0.8)
    for r in rows:
        assert r["simulated"] == pytest.approx(r["formula_13"], rel=0.01)
        assert r["within_print_rounding"], r
        assert abs(r["printed"] - r["formula_13"]) > 0.1 * abs(
            r["formula_13"]
        )  # the printed values are not (13)
    lo, hi = table_ratio_interval()
    assert lo == pytest.approx(0.79467, abs=1e-4) and hi == pytest.approx(0.80533, abs=1e-4)


def test_table_with_omega_squared_20_matches_the_print() -> None:
    rows = parabola_table(omega=math.sqrt(20.0))  # omega^2 = 20 reproduces the printed values
    assert all(
        abs(r.simulated - r.printed)
        <= 0.5 * 10 ** -(len(r.printed_text.split(".")[1]) if "." in r.printed_text else 0) + 1e-9
        for r in rows
    )


# ---------------------------------------------------------------- presets, runs


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_presets_resolve_and_simulate(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    assert isinstance(params, Params)
    result = LESSON.run(preset)
    data = result.to_json_dict()
    for name in SERIES[1:]:
        assert name in result.series and len(result.series[name]) == len(result.t)
        assert np.all(np.isfinite(result.series[name]))
    assert np.all(result.series["z"] == 0.0)
    assert "delta_after_transient" in data["metrics"]
    assert math.isfinite(result.metrics["delta_after_transient"])


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
    assert np.max(np.abs(r.series["ex"])) > 0.3  # the lag is along the line
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


def test_axes_printed_vs_corrected_differ_by_cos() -> None:
    _, a, b = circle_axes_29_30(9.14566, 10.36061, math.radians(31.622))
    _, ap, bp = circle_axes_29_30(9.14566, 10.36061, math.radians(31.622), printed=True)
    assert (a, b) == pytest.approx((12.10648, 6.66471), abs=2e-4)
    assert (ap, bp) == pytest.approx((13.11954, 7.22241), abs=2e-4)


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
    assert abs(on.series["ex"][-1]) < 1e-6 and abs(on.series["ey"][-1]) < 1e-6


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
    assert set(frame.scalars) >= {"x1 - x", "y1 - y", "delta", "delta steady", "delta article"}
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


@pytest.mark.parametrize("curve", ["line", "parabola", "circle", "ellipse", "cubic", "quartic"])
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


@pytest.mark.parametrize("claim", LESSON.claims(), ids=lambda c: c.id)
def test_claims_pass(claim) -> None:
    result = claim.check()
    assert result.passed, (claim.id, result.expected, result.got)


def test_formula_13_numbers() -> None:
    assert delta_parabola_13(5, 20, 0.01, 0.001) == pytest.approx(-0.2375)
    assert delta_parabola_13(5, 20, 0.01, 0.00005) == pytest.approx(0.0)  # T1^2 = 2 T2^2: no error
