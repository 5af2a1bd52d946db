"""Lesson motion-program: textbook §1.1, eqs (1.1)-(1.15)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.curves.motion_law import motion_program
from analyzer_lab.lessons.analyzers.curves.space_curve import CurveFormulaParam
from analyzer_lab.lessons.analyzers.motion_program import LESSON, U_NAMES
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.lessons.kit.contract import Formula, ParamError

S_HELIX = math.pi * math.sqrt(2.0)
SERIES = ("x", "y", "z", "vx", "vy", "vz", "speed", "v_limit", "s", "x_analyzer")
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
        ({"profile": "trapezoid", "v0": 4, "Delta0": 2, "Delta1": 2}, "profile"),
        ({"profile": "triangle", "Delta0": 0, "Delta1": 0}, "profile"),
        ({"profile": "square"}, "profile"),
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
    end = motion_program(
        params["x"].text, params["y"].text, params["z"].text, params["phi0"], params["phi1"]
    ).curve.samples[-1]
    assert np.allclose([r.series["x"][-1], r.series["y"][-1], r.series["z"][-1]], end, atol=1e-9)
    json.dumps(r.to_json_dict())
    assert r.to_csv().count("\n") == len(r.t) + 1


# ---------------------------------------------------------------- the helix, (1.2)-(1.4)


def test_helix_forms_give_the_same_motion_and_1_4_reversed():
    r2 = LESSON.run("helix-1.2")
    r3 = LESSON.run("helix-1.3")
    r4 = LESSON.run("helix-1.4")
    for k in ("x", "y", "z"):
        assert np.max(np.abs(r2.series[k] - r3.series[k])) < 1e-9
    assert r4.series["x"][0] == pytest.approx(0.0, abs=1e-12)
    assert (r4.series["y"][0], r4.series["z"][0]) == pytest.approx((-1.0, math.pi), abs=1e-12)
    assert (r2.series["y"][0], r2.series["z"][0]) == pytest.approx((1.0, 0.0), abs=1e-12)


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
        ok = np.isfinite(r.series["speed"])
        assert np.max(r.series["speed"][ok] - r.series["v_limit"][ok]) <= 1e-9
        speed_prog = np.sqrt(sum(r.series[f"v{c}"] ** 2 for c in "xyz"))
        assert np.max(np.abs(speed_prog - r.series["v_limit"])) <= 1e-12
        assert np.max(r.series["v_limit"]) <= float(LESSON.resolve(preset=preset)["v0"]) + 1e-12
        assert r.series["s"][-1] == pytest.approx(r.metrics["S_l"], abs=1e-12)


# ---------------------------------------------------------------- singular cases of (1.14)/(1.15)


def test_pass_through_origin_is_reported_and_handled():
    r = LESSON.run("line-through-origin")
    t_star = 0.5 + (math.sqrt(3) - 0.25)  # s* = sqrt(3) on the plateau of v0 = 1
    assert r.metrics["singular_times"] == pytest.approx([t_star], abs=1e-7)
    assert any("(1.14) fails" in m for m in r.messages)
    gap = np.abs(r.t - t_star) < 1e-3 * r.metrics["T"] * (1 - 1e-9)  # open window
    assert gap.any() and np.all(np.isnan(r.series["x_analyzer"][gap]))
    assert np.all(np.isnan(r.series["u11"][gap]))
    assert np.all(np.isfinite(r.series["x_analyzer"][~gap]))
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
    assert math.isnan(r.series["x_analyzer"][1])
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
    assert "recomputed" in f.message
    f = st.reset()
    assert f.t == 0.0


def test_stepper_through_the_origin():
    """Points stay drawable; the values of (1.5) are undefined only inside the window,
    and the frame says why."""
    params = LESSON.resolve(preset="line-through-origin")
    st = LESSON.stepper(params)
    gaps = 0
    for _ in range(300):
        f = st.advance(1 / 60)
        assert all(np.all(np.isfinite(v)) for v in f.points.values())
        if not math.isfinite(f.scalars["x_analyzer"]):
            gaps += 1
            assert "origin" in f.message and not math.isfinite(f.scalars["u11"])
        else:
            assert all(math.isfinite(v) for v in f.scalars.values())
    assert gaps >= 1
    assert f.scalars["error"] < 1e-6


def test_forced_profiles():
    """The profile choice: a forced triangle with L > 0 peaks above v0 (and says so)."""
    params = LESSON.resolve(preset="helix-1.2", values={"profile": "triangle"})
    r = LESSON.simulate(params)
    v1 = math.sqrt(2 * S_HELIX * 1.0 / 2.0)  # sqrt(2 S_l v0 / (Delta0 + Delta1))
    assert v1 == pytest.approx(2.107815, abs=1e-6)
    assert r.metrics["profile"] == "triangle"
    assert r.metrics["v1"] == pytest.approx(v1, abs=1e-12)
    assert r.metrics["T"] == pytest.approx(2 * v1, abs=1e-12)
    assert any("exceeds" in m for m in r.messages)
    assert r.metrics["max_error"] < 1e-6
    same = LESSON.simulate(LESSON.resolve(preset="helix-1.2", values={"profile": "trapezoid"}))
    auto = LESSON.simulate(LESSON.resolve(preset="helix-1.2"))
    assert np.array_equal(same.series["x"], auto.series["x"])


def test_notes_say_what_was_done():
    kinds = {n.kind for n in LESSON.notes(LESSON.resolve(preset="helix-triangle"))}
    assert kinds == {"info", "reconstructed"}
    recon = [n for n in LESSON.notes(LESSON.resolve(preset="helix-triangle")) if n.source]
    assert recon[0].source == "(1.9)" and recon[0].evidence
    texts = [n.text for n in LESSON.notes(LESSON.resolve(preset="line-through-origin"))]
    assert any("(1.14) fails" in t for t in texts)


def test_declarations():
    assert LESSON.declaration_errors() == []
    assert LESSON.modes == ("profile",) and LESSON.param("profile").group == "mode"
    assert [g.name for g in LESSON.groups] == ["mode", "curve", "law"]
    units = {s.name: s.unit for s in LESSON.series}
    assert units["x_analyzer"] == "m" and units["speed"] == "m/s" and units["u23"] == "1/s"


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
