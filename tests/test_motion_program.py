"""Lesson motion-program: textbook §1.1, eqs (1.1)-(1.15)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lessons.catalog import get_lesson
from lessons.core.contract import Formula, ParamError
from lessons.motion_program import (
    HELIX_12,
    LESSON,
    U_NAMES,
    CurveFormulaParam,
    helix_hausdorff,
    helix_length,
    helix_reversal_gap,
    program_from,
    reproduce,
)

S_HELIX = math.pi * math.sqrt(2.0)
SERIES = ("x", "y", "z", "vx", "vy", "vz", "v", "v_limit", "s", "x5", "y5", "z5")
METRICS = ("S_l", "T", "profile", "L", "v1")


def test_catalog_finds_the_lesson():
    assert get_lesson("motion-program") is LESSON


# ---------------------------------------------------------------- parameters


def test_curve_formula_param_parses_phi_only():
    p = LESSON.param("x")
    assert isinstance(p, CurveFormulaParam) and p.kind == "formula"
    f = p.parse("sqrt(1 - phi^2)")
    assert isinstance(f, Formula) and f.variables == ("phi",)
    assert f(np.array([0.6]))[0] == pytest.approx(0.8)
    assert p.parse(2.5)(np.array([1.0, 2.0])).tolist() == [2.5, 2.5]
    with pytest.raises(ParamError, match="^x: unknown name 't'"):
        p.parse("sin(t)")
    with pytest.raises(ParamError):
        p.parse("phi +* 2")
    with pytest.raises(ParamError):
        p.parse("__import__('os')")


@pytest.mark.parametrize(
    "values,name",
    [
        ({"phi0": "2", "phi1": "1"}, "phi1"),
        ({"x": "1", "y": "2", "z": "3"}, "x"),
        ({"y": "sqrt(phi - 1)"}, "y"),
        ({"z": "1/(phi - 1)"}, "z"),
        ({"v0": 0}, "v0"),
        ({"Delta0": -1}, "Delta0"),
    ],
)
def test_bad_values_are_refused_with_the_parameter_named(values, name):
    with pytest.raises(ParamError) as err:
        LESSON.resolve(values)
    assert err.value.name == name


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_resolves_simulates_and_finishes(preset):
    params = LESSON.resolve(preset=preset)
    r = LESSON.run(preset)
    for name in SERIES:
        assert r.series[name].shape == r.t.shape, name
    for name in METRICS:
        assert name in r.metrics
    assert r.metrics["profile"] in ("trapezoid", "triangle")
    assert r.t[-1] >= r.metrics["T"], "preset t_end must cover the whole motion"
    assert LESSON.preset(preset).t_end <= r.metrics["T"] + 1.0
    assert r.metrics["max_error"] < 1e-6
    assert r.metrics["max_speed_excess"] < 1e-9
    # the last point is the end of the curve
    end = program_from(
        params["x"].text, params["y"].text, params["z"].text, params["phi0"], params["phi1"]
    ).curve.samples[-1]
    assert np.allclose([r.series["x"][-1], r.series["y"][-1], r.series["z"][-1]], end, atol=1e-9)
    json.dumps(r.to_json_dict())
    assert r.to_csv().count("\n") == len(r.t) + 1


# ---------------------------------------------------------------- the helix, (1.2)-(1.4)


def test_helix_lengths_and_one_point_set():
    from lessons.motion_program import HELIX_13, HELIX_14

    for c in (HELIX_12, HELIX_13, HELIX_14):
        assert helix_length(c) == pytest.approx(S_HELIX, abs=1e-9)
    assert helix_hausdorff() <= 1e-9
    assert helix_reversal_gap() <= 1e-9


def test_helix_forms_give_the_same_motion_and_1_4_reversed():
    r2 = LESSON.run("helix-1.2")
    r3 = LESSON.run("helix-1.3")
    r4 = LESSON.run("helix-1.4")
    for k in ("x", "y", "z"):
        assert np.max(np.abs(r2.series[k] - r3.series[k])) < 1e-9
    assert r4.series["x"][0] == pytest.approx(0.0, abs=1e-12)
    assert (r4.series["y"][0], r4.series["z"][0]) == pytest.approx((-1.0, math.pi), abs=1e-12)
    assert (r2.series["y"][0], r2.series["z"][0]) == pytest.approx((1.0, 0.0), abs=1e-12)


def test_hausdorff_check_can_fail():
    from lessons.motion_program import _nearest_distance, curve_model

    other = curve_model("sin(phi)", "cos(phi)", "1.001*phi", 0.0, math.pi).arc
    pts = np.array([[0.0, -1.0, math.pi]])
    assert _nearest_distance(other, pts)[0] > 1e-3


# ---------------------------------------------------------------- speed law


def test_trapezoid_and_triangle_metrics():
    m = LESSON.run("helix-1.2").metrics
    assert m["profile"] == "trapezoid"
    assert m["L"] == pytest.approx(3.442882938158366, abs=1e-9)
    assert m["T"] == pytest.approx(5.442882938158366, abs=1e-9)
    m = LESSON.run("helix-triangle").metrics
    assert m["profile"] == "triangle"
    assert m["L"] == pytest.approx(-3.557117061841634, abs=1e-9)
    assert m["t1"] == pytest.approx(1.4904500894290902, abs=1e-9)
    assert m["v1"] == pytest.approx(2.9809001788581804, abs=1e-9)
    assert m["T"] == pytest.approx(2.9809001788581804, abs=1e-9)


def test_speed_never_exceeds_the_law():
    for preset in ("helix-1.2", "helix-triangle", "spiral"):
        r = LESSON.run(preset)
        ok = np.isfinite(r.series["v"])
        assert np.max(r.series["v"][ok] - r.series["v_limit"][ok]) <= 1e-9
        speed_prog = np.sqrt(r.series["vx"] ** 2 + r.series["vy"] ** 2 + r.series["vz"] ** 2)
        assert np.max(np.abs(speed_prog - r.series["v_limit"])) <= 1e-12
        assert np.max(r.series["v_limit"]) <= float(LESSON.resolve(preset=preset)["v0"]) + 1e-12
        assert r.series["s"][-1] == pytest.approx(r.metrics["S_l"], abs=1e-12)


# ---------------------------------------------------------------- (1.5) with (1.15)


@pytest.mark.parametrize("v0,d0,d1", [(1.0, 1.0, 1.0), (4.0, 2.0, 2.0)])
def test_rk4_reproduction_and_independent_dop853(v0, d0, d1):
    prog = program_from(*HELIX_12[:3], 0.0, math.pi, v0, d0, d1)
    res = reproduce(prog)
    assert np.max(res["err"]) <= 1e-6
    assert np.linalg.norm(res["X5"][-1] - [0.0, -1.0, math.pi]) <= 1e-6

    # the same system (1.5) with u_ij of (1.15), integrated by DOP853 (rtol 1e-11, atol 1e-12)
    def rhs(t, y):
        st = prog.state(np.array([t]))
        U = prog.controls(st)[0]
        return U @ y

    sol = solve_ivp(
        rhs,
        (0.0, prog.T),
        res["X"][0],
        method="DOP853",
        rtol=1e-11,
        atol=1e-12,
        t_eval=res["t"][::50],
    )
    X = prog.state(sol.t)["X"]
    assert np.max(np.linalg.norm(sol.y.T - X, axis=1)) <= 1e-6


def test_error_measure_detects_a_coarse_integration():
    prog = program_from(*HELIX_12[:3], 0.0, math.pi, 1.0, 1.0, 1.0)
    coarse = reproduce(prog, samples=6, substeps=1)
    assert np.max(coarse["err"]) > 1e-4


def test_controls_are_rank_one_and_reproduce_xdot():
    prog = program_from(*HELIX_12[:3], 0.0, math.pi, 1.0, 1.0, 1.0)
    st = prog.state(np.linspace(0, prog.T, 301))
    U = prog.controls(st)
    assert np.max(np.abs(np.einsum("nij,nj->ni", U, st["X"]) - st["V"])) < 1e-14
    sv = np.linalg.svd(U, compute_uv=False)
    assert np.max(sv[:, 1:]) < 1e-14
    assert np.min(st["D"]) == pytest.approx(1.0, abs=1e-12)  # (1.14): D = 1 + Z^2


# ---------------------------------------------------------------- singular cases of (1.14)/(1.15)


def test_pass_through_origin_is_reported_and_handled():
    r = LESSON.run("line-through-origin")
    t_star = 0.5 + (math.sqrt(3) - 0.25)  # s* = sqrt(3) on the plateau of v0 = 1
    assert r.metrics["singular_times"] == pytest.approx([t_star], abs=1e-7)
    assert any("(1.14) fails" in m for m in r.messages)
    gap = np.abs(r.t - t_star) < 1e-3 * r.metrics["T"] * (1 - 1e-9)  # open window
    assert gap.any() and np.all(np.isnan(r.series["x5"][gap]))
    assert np.all(np.isnan(r.series["u11"][gap]))
    assert np.all(np.isfinite(r.series["x5"][~gap]))
    assert r.metrics["max_error"] < 1e-6
    assert np.isfinite(r.metrics["max_abs_u"])


def test_curve_starting_at_the_origin():
    r = LESSON.run(
        values={
            "x": "phi*cos(phi)",
            "y": "phi*sin(phi)",
            "z": "0",
            "phi0": "0",
            "phi1": "2*pi",
            "v0": 2,
        },
        t_end=None,
    )
    assert r.metrics["singular_times"] == [0.0]
    assert math.isnan(r.series["x5"][1])
    assert r.metrics["max_error"] < 1e-6


def test_cusp_is_reported():
    r = LESSON.run(values={"x": "phi^3", "y": "phi^2", "z": "0.5", "phi0": "-1", "phi1": "1"})
    assert any("cusp" in m for m in r.messages)
    assert r.metrics["max_error"] < 1e-3


def test_early_stop_is_reported():
    r = LESSON.run("helix-1.2", t_end=2.0)
    assert r.t[-1] == pytest.approx(2.0)
    assert any("before the end" in m for m in r.messages)


# ---------------------------------------------------------------- live, scene, derivation


def test_stepper_advance_set_params_reset():
    params = LESSON.resolve(preset="helix-1.2")
    st = LESSON.stepper(params)
    f = st.frame()
    assert f.t == 0.0 and set(U_NAMES) <= set(f.scalars)
    assert f.points["point"] == pytest.approx(np.array([[0.0, 1.0, 0.0]]))
    for _ in range(120):
        f = st.advance(0.05)
    assert st.t == pytest.approx(6.0)
    assert f.points["analyzer"][0] == pytest.approx([0.0, -1.0, math.pi], abs=1e-6)
    assert f.scalars["error"] < 1e-6 and "complete" in f.message
    st.reset()
    f = st.advance(2.0)
    u = np.array([[f.scalars[f"u{i}{j}"] for j in (1, 2, 3)] for i in (1, 2, 3)])
    X = f.points["point"][0]
    assert np.linalg.matrix_rank(u, tol=1e-12) == 1
    assert u @ X == pytest.approx(
        f.vectors["velocity"][1][0]
        / np.linalg.norm(f.vectors["velocity"][1][0])
        * f.scalars["v_limit"],
        abs=1e-9,
    )
    st.set_params(LESSON.resolve(preset="helix-triangle"))
    assert st.t == pytest.approx(2.0)
    f = st.frame()
    assert "restarted" in f.message
    f = st.reset()
    assert f.t == 0.0


def test_stepper_through_the_origin():
    st = LESSON.stepper(LESSON.resolve(preset="line-through-origin"))
    seen = False
    for _ in range(300):
        f = st.advance(1 / 60)
        assert all(np.all(np.isfinite(v)) for v in f.points.values())
        assert all(math.isfinite(v) for v in f.scalars.values())
        seen |= "origin" in f.message
    assert seen
    assert f.scalars["error"] < 1e-6


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_scene(preset):
    sc = LESSON.scene(LESSON.resolve(preset=preset))
    lo, hi = np.array(sc.bounds[0]), np.array(sc.bounds[1])
    assert np.all(np.isfinite(lo)) and np.all(hi > lo)
    assert sc.curves and np.all(np.isfinite(sc.curves[0].points))
    assert {"point", "analyzer"} <= set(sc.moving_points) and "velocity" in sc.moving_vectors
    assert any(m.name == "start" for m in sc.markers)


def test_derivation_lists_every_equation_and_the_reconstructions():
    steps = LESSON.derivation(LESSON.resolve(preset="helix-1.4"))
    sources = " ".join(s.source for s in steps)
    for k in range(1, 16):
        assert f"(1.{k})" in sources, k
    recon = {s.source for s in steps if s.reconstructed}
    for eq in ("(1.1)", "(1.4)", "(1.5)", "(1.9)", "(1.12)"):
        assert eq in recon


def test_plots_name_frame_scalars():
    f = LESSON.stepper(LESSON.resolve()).advance(0.1)
    for p in LESSON.plots:
        for name in p.series:
            assert name in f.scalars


@pytest.mark.parametrize("claim", LESSON.claims(), ids=lambda c: c.id)
def test_claims(claim):
    res = claim.check()
    assert res.passed, (res.expected, res.got)
