"""Tests for the LSP-2000 lesson (article 003) and lessons/core/kinematics5.py."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from lessons.core.contract import ParamError
from lessons.core.kinematics5 import (
    LimitError,
    Machine5,
    Paraboloid,
    QuadricCap,
    SphereCap,
    angle_between,
    axis_path_length,
    bisect_segment,
    bisect_uniform,
    fixed_normal_moves,
    make_task,
    mean_normal,
    move_deviation,
    moves_backwards,
    nonlinear_submoves,
    off_normal_max,
    point_speed_ratio,
    sagitta_estimate,
)
from lessons.laser_5axis import (
    LESSON,
    adaptive,
    body_poses,
    machine_of,
    study,
    to_view,
    translate,
    uniform_levels,
)

# ---------------------------------------------------------------- kinematics


@pytest.mark.parametrize("limits", ["original", "improved"])
def test_round_trip_random_poses(limits: str) -> None:
    m = Machine5(R_C=230.0, R_B=310.0, k_C2=0.3, k_X=5.0, k_Y=-7.0, k_Z=11.0, limits=limits)  # type: ignore[arg-type]
    q = m.random_poses(np.random.default_rng(7), 500)
    p, n = m.forward(q)
    for i in range(len(q)):
        q2 = m.inverse(p[i], n[i], C_ref=float(q[i, 3]))
        assert m.in_limits(q2)
        p2, n2 = m.forward(q2)
        assert np.abs(p2 - p[i]).max() <= 1e-9
        assert np.abs(n2 - n[i]).max() <= 1e-12
        assert np.abs(q2 - q[i]).max() <= 1e-9


def test_inverse_sense_minus_one() -> None:
    m = Machine5(k_C1=-1.0)
    q = np.array([500.0, 600.0, 100.0, 2.0, 0.4])
    p, n = m.forward(q)
    assert np.allclose(m.inverse(p, n), q, atol=1e-9)


def test_vertical_beam_is_ambiguous_and_rule_picks_c() -> None:
    m = Machine5()
    q1 = np.array([1000.0, 1000.0, 100.0, 1.0, 0.0])
    p, n = m.forward(q1)
    assert np.allclose(p, [1168.294197, 1108.060461, 400.0], atol=1e-6)  # digest, script part B
    q0 = m.inverse(p, n)
    assert q0[3] == 0.0 and np.allclose(q0[:3], [1168.294197, 908.060461, 100.0], atol=1e-6)
    assert np.allclose(m.inverse(p, n, C_ref=1.0), q1, atol=1e-9)
    assert np.allclose(m.forward(q0)[0], p, atol=1e-9)


def test_limits_enforced() -> None:
    tilt = np.array([math.sin(0.9), 0.0, math.cos(0.9)])  # 51.6 deg
    assert Machine5().inverse(np.zeros(3), tilt)[4] == pytest.approx(0.9)
    with pytest.raises(LimitError):
        Machine5(limits="improved").inverse(np.zeros(3), tilt)
    with pytest.raises(LimitError):
        Machine5().inverse(np.zeros(3), np.array([1.0, 0.0, -0.1]))


def test_improved_takes_nearest_branch() -> None:
    m = Machine5(limits="improved")
    n = m.beam(-0.2, 0.1)
    C, B = m.rotary(n, C_ref=2.5)  # the branch (theta + pi, -B) is nearer
    assert C == pytest.approx(math.pi - 0.2) and B == pytest.approx(-0.1)
    C, B = m.rotary(n, C_ref=-0.1 + 4 * math.pi)
    assert C == pytest.approx(-0.2 + 4 * math.pi) and B == pytest.approx(0.1)


# ---------------------------------------------------------------- workpieces


def test_workpieces_points_and_normals() -> None:
    par = Paraboloid()
    p, n = par.point_normal(np.array([300.0]), np.array([0.0]))
    assert p[0] == pytest.approx([1800.0, 1500.0, 900.0 - 300.0**2 / 2000.0])
    assert n[0] == pytest.approx(np.array([0.3, 0.0, 1.0]) / math.hypot(0.3, 1.0))
    sph = SphereCap(R=1000.0)
    p, n = sph.point_normal(np.array([0.0, 600.0]), np.array([0.0, 0.0]))
    assert p[0] == pytest.approx([1500.0, 1500.0, 400.0])
    assert np.linalg.norm(p[1] - np.array([1500.0, 1500.0, 1400.0])) == pytest.approx(1000.0)
    assert n[1] == pytest.approx([-0.6, 0.0, 0.8])
    for wp in (par, sph):
        mesh = wp.mesh()
        assert len(mesh.faces) > 100 and np.isfinite(mesh.vertices).all()


def test_quadric_cap_matches_paraboloid() -> None:
    """Any quadric F = 0 with F, half_gradient plugs in; the paraboloid as a quadric agrees."""
    Fp, cx, cy, z0 = 500.0, 1500.0, 1500.0, 900.0

    def F(x: np.ndarray) -> np.ndarray:
        return (x[..., 0] - cx) ** 2 + (x[..., 1] - cy) ** 2 + 4 * Fp * (x[..., 2] - z0)

    def half_gradient(x: np.ndarray) -> np.ndarray:
        return np.stack([x[..., 0] - cx, x[..., 1] - cy, np.full(x.shape[:-1], 2 * Fp)], axis=-1)

    q = QuadricCap(F, half_gradient)
    u, v = np.array([0.0, 120.0, -250.0]), np.array([0.0, 40.0, 310.0])
    p1, n1 = q.point_normal(u, v)
    p2, n2 = Paraboloid().point_normal(u, v)
    assert np.allclose(p1, p2, atol=1e-9) and np.allclose(n1, n2, atol=1e-12)


# ---------------------------------------------------------------- the prototype's numbers


def test_linear_interpolation_deviates() -> None:
    s = study("S1")
    dev = move_deviation(s.machine, s.linear())
    assert dev == pytest.approx(1.398, abs=0.001)
    assert dev > 0.020 * 50
    assert sagitta_estimate(s.machine, s.qa, s.qb) == pytest.approx(dev, rel=0.005)
    assert move_deviation(study("S2").machine, study("S2").linear()) == pytest.approx(
        0.1305, abs=1e-4
    )
    assert move_deviation(study("S3").machine, study("S3").linear()) == pytest.approx(
        3.058, abs=1e-3
    )


def test_linear_speed_nonuniform() -> None:
    assert point_speed_ratio(study("S1").machine, study("S1").linear()) == pytest.approx(
        1.008, abs=1e-3
    )
    assert point_speed_ratio(study("S3").machine, study("S3").linear()) == pytest.approx(
        1.061, abs=1e-3
    )
    assert point_speed_ratio(study("S4").machine, study("S4").linear()) == pytest.approx(
        2.295, abs=2e-3
    )


def test_bisection_levels_quarter_per_split() -> None:
    lv = uniform_levels("S1", "original")
    assert lv[1:] == pytest.approx([0.355, 0.0891, 0.0223, 0.00558, 0.00139, 0.000349], rel=0.01)
    ratios = [lv[d] / lv[d + 1] for d in range(6)]
    assert all(3.9 < r < 4.05 for r in ratios)
    lv3 = uniform_levels("S3", "original")
    assert lv3[1] == pytest.approx(0.874, abs=1e-3)
    assert lv3[5] / lv3[6] == pytest.approx(4.0, abs=0.02)


def test_bisection_reaches_tolerance() -> None:
    for name, pieces, depth in (("S1", 16, 4), ("S2", 4, 2), ("S3", 16, 4)):
        b = adaptive(name, "original")
        assert b.converged and b.worst_mm <= 0.020
        assert (len(b.moves), b.max_depth) == (pieces, depth)


def test_tolerance_changes_pieces() -> None:
    s = study("S1")
    pa, na, pb, nb = s.ends
    assert len(bisect_segment(s.machine, pa, na, s.qa, pb, nb, 0.1).moves) == 4
    assert len(bisect_segment(s.machine, pa, na, s.qa, pb, nb, 0.001).moves) == 64


def test_nonlinear_keeps_point_on_segment_at_constant_speed() -> None:
    for limits in ("original", "improved"):
        for name in ("S1", "S2", "S3", "S4"):
            s = study(name, limits)
            nl = s.nonlinear()
            assert nl.lead == ("B" if name == "S2" else "C")
            assert move_deviation(s.machine, nl) <= 1e-9
            assert point_speed_ratio(s.machine, nl) == pytest.approx(1.0, abs=1e-6)


def test_nonlinear_as_linear_submoves_falls_as_inverse_square() -> None:
    s = study("S1")
    pa, _, pb, _ = s.ends
    devs = [
        max(
            move_deviation(s.machine, mv, pa, pb)
            for mv in nonlinear_submoves(s.machine, s.nonlinear(), N)
        )
        for N in (4, 16, 64)
    ]
    assert devs == pytest.approx([0.0874, 0.00547, 0.000342], rel=0.01)
    assert devs[0] / devs[1] == pytest.approx(16.0, rel=0.03)


def test_fixed_normal_half_angle() -> None:
    for name, half in (("S1", 1.645), ("S2", 1.690), ("S3", 2.578), ("S4", 1.718)):
        s = study(name)
        pa, na, pb, nb = s.ends
        mv = fixed_normal_moves(s.machine, pa, na, pb, nb, float(s.qa[3]))
        assert mv.q0[3:] == pytest.approx(mv.q1[3:])
        assert move_deviation(s.machine, mv) <= 1e-9
        assert math.degrees(off_normal_max(s.machine, s.task, [mv], samples=1025)) == pytest.approx(
            half, abs=1e-3
        )
        assert math.degrees(float(angle_between(mean_normal(na, nb), na))) == pytest.approx(
            half, abs=1e-3
        )


def test_nonlinear_orientation_and_axis_travel() -> None:
    for name, beam, xy in (("S1", 0.079, 5.9), ("S2", 0.006, 42.5), ("S3", 0.248, 35.9)):
        s = study(name)
        assert math.degrees(off_normal_max(s.machine, s.task, [s.nonlinear()])) == pytest.approx(
            beam, abs=1e-3
        )
        assert axis_path_length(s.machine, [s.nonlinear()], slice(0, 2)) == pytest.approx(
            xy, abs=0.05
        )


def test_near_vertical_original_limits() -> None:
    s = study("S4", "original")
    assert math.degrees(s.qb[3] - s.qa[3]) == pytest.approx(-198.925, abs=0.01)
    assert move_deviation(s.machine, s.linear()) == pytest.approx(243.5, abs=0.1)
    assert uniform_levels("S4", "original")[1:3] == pytest.approx([352.0, 364.0], abs=1.0)
    b = adaptive("S4", "original")
    assert not b.converged and b.max_depth == 30 and b.worst_mm == pytest.approx(403.0, abs=1.0)
    assert len(b.moves) == 143
    nl = s.nonlinear()
    assert axis_path_length(s.machine, [nl], slice(0, 2)) == pytest.approx(693.3, abs=0.2)
    assert math.degrees(off_normal_max(s.machine, s.task, [nl])) == pytest.approx(2.029, abs=2e-3)


def test_near_vertical_improved_limits() -> None:
    s = study("S4", "improved")
    assert math.degrees(s.qb[3] - s.qa[3]) == pytest.approx(-18.925, abs=0.01)
    assert math.degrees(s.qb[4] - s.qa[4]) == pytest.approx(-3.484, abs=0.01)
    assert move_deviation(s.machine, s.linear()) == pytest.approx(1.509, abs=1e-3)
    assert uniform_levels("S4", "improved")[1:] == pytest.approx(
        [41.4, 34.7, 22.4, 9.92, 3.18, 0.861], rel=0.01
    )
    b = adaptive("S4", "improved")
    assert b.converged and (len(b.moves), b.max_depth) == (122, 9)
    pa, na, pb, nb = s.ends
    assert moves_backwards(s.machine, bisect_uniform(s.machine, pa, na, s.qa, pb, nb, 1), pa, pb)
    assert axis_path_length(s.machine, [s.nonlinear()], slice(0, 2)) == pytest.approx(78.1, abs=0.1)


def test_every_claim_passes() -> None:
    for claim in LESSON.claims():
        result = claim.check()
        assert result.passed, (claim.id, result.expected, result.got)


def test_a_claim_can_fail() -> None:
    """The bisection claim would fail if the split normal were not renormalised."""
    s = study("S1")
    pa, na, pb, nb = s.ends
    m = s.machine
    bad = [move_deviation(m, mv) for mv in bisect_uniform(m, pa, na, s.qa, pb, nb, 1)]
    assert max(bad) == pytest.approx(0.355, abs=1e-3)
    # a wrong split normal (the start normal kept) leaves the deviation far above a quarter
    qm = m.inverse(0.5 * (pa + pb), na, float(s.qa[3]))
    from lessons.core.kinematics5 import linear_move

    wrong = move_deviation(m, linear_move(qm, s.qb, 0.5 * (pa + pb), pb))
    assert wrong > 0.355


# ---------------------------------------------------------------- the lesson contract


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_presets_resolve_and_run(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    assert params["tolerance_um"] == 20.0
    run = LESSON.run(preset)
    for key in ("x", "y", "z", "deviation_mm"):
        assert run.series[key].shape == run.t.shape and np.isfinite(run.series[key]).all()
    for key in ("deviation_max_mm", "pieces", "axis_travel_mm"):
        assert key in run.metrics
    assert run.t[-1] == pytest.approx(LESSON.preset(preset).t_end)
    json.dumps(run.to_json_dict())


def test_run_metrics_by_method() -> None:
    base = {"path": "line", "segments": 1, "u0": 300, "v0": 0, "u1": 300, "v1": 60, "V": 10}
    lin, bis, nl, fn = (
        LESSON.simulate(LESSON.resolve({**base, "method": m}))
        for m in ("linear", "bisection", "nonlinear", "fixed-normal")
    )
    assert nl.t[-1] == pytest.approx(6.0027, abs=1e-4)
    assert lin.metrics["deviation_max_mm"] == pytest.approx(1.398, abs=1e-3)
    assert bis.metrics["pieces"] == 16 and bis.metrics["deviation_max_mm"] <= 0.020
    assert (
        nl.metrics["deviation_max_mm"] <= 1e-9
        and np.ptp(nl.series["speed_mm_s"]) < 1e-3
        and nl.series["speed_mm_s"][0] == pytest.approx(10.0)
    )
    assert fn.metrics["off_normal_max_deg"] == pytest.approx(1.645, abs=1e-3)
    assert max(lin.series["deviation_mm"]) == pytest.approx(1.398, abs=2e-3)


def test_improved_limits_remove_the_wrap() -> None:
    orig = LESSON.run("circle-original")
    impr = LESSON.run("circle-improved")
    assert orig.metrics["deviation_max_mm"] > 100.0
    assert impr.metrics["deviation_max_mm"] == pytest.approx(1.378, abs=2e-3)


def test_t_end_truncates_and_holds() -> None:
    params = LESSON.resolve(preset="segment-linear")
    short = LESSON.simulate(params, 2.0)
    assert short.t[-1] == pytest.approx(2.0) and short.messages
    long = LESSON.simulate(params, 10.0)
    assert long.t[-1] == pytest.approx(10.0) and long.series["x"][-1] == long.series["x"][-2]


def test_validation() -> None:
    with pytest.raises(ParamError):
        LESSON.resolve({"method": "spline"})
    with pytest.raises(ParamError):
        LESSON.resolve({"path": "line", "u0": 10, "v0": 0, "u1": 10, "v1": 0})
    with pytest.raises(ParamError):  # 45 deg tilt at r = 2F: outside (-pi/4, pi/4)
        LESSON.resolve({"limits": "improved", "radius": 1000})
    with pytest.raises(ParamError):
        LESSON.resolve({"surface": "sphere", "radius": 900})
    LESSON.resolve({"R_C": 0.0, "R_B": 10.0, "k_C1": "-1", "k_C2": 0.5})


def test_stepper_advance_set_params_reset() -> None:
    params = LESSON.resolve(preset="segment-linear")
    st = LESSON.stepper(params)
    f0 = st.frame()
    assert f0.t == 0.0 and f0.scalars["deviation_um"] == pytest.approx(0.0, abs=1e-6)
    f = st.advance(3.0)
    assert f.t == pytest.approx(3.0)
    assert f.scalars["deviation_um"] == pytest.approx(1397.8, abs=2.0)
    assert set(f.poses) == {"portal_X", "portal_Y", "portal_Z", "lever_C", "lever_B"}
    assert {"deviation_um", "speed_mm_s", "off_normal_deg", "travel_linear_mm"} <= set(f.scalars)
    st.set_params(LESSON.resolve({"method": "nonlinear"}, preset="segment-linear"))
    f = st.frame()
    assert f.t == pytest.approx(3.0) and f.scalars["deviation_um"] < 1e-6
    assert f.scalars["speed_mm_s"] == pytest.approx(10.0, rel=1e-6)
    f = st.advance(1e3)
    assert f.message == "task finished"
    assert st.reset().t == 0.0


def test_scene_and_bodies() -> None:
    params = LESSON.resolve()
    scene = LESSON.scene(params)
    lo, hi = np.array(scene.bounds[0]), np.array(scene.bounds[1])
    assert np.isfinite(lo).all() and np.isfinite(hi).all() and (hi > lo).all()
    assert "tool" in scene.moving_points and "beam" in scene.moving_vectors
    names = {b.name for b in scene.bodies}
    assert names == {"portal_X", "portal_Y", "portal_Z", "lever_C", "lever_B"}
    for item in scene.meshes + scene.bodies:
        assert np.isfinite(item.vertices).all()
    # the posed B lever ends at the working point (viewer frame)
    m = machine_of(params)
    q = np.array([900.0, 1300.0, 250.0, 0.8, 0.35])
    pos, quat = body_poses(m, q)["lever_B"]
    tip = pos + Rotation.from_quat(quat, scalar_first=True).apply([0.0, 0.0, -m.R_B])
    assert np.allclose(tip, to_view(m.forward(q)[0]), atol=1e-9)
    # every posed body vertex stays inside the bounds for the default program
    frame = LESSON.stepper(params).advance(5.0)
    for body in scene.bodies:
        p, qw = frame.poses[body.name]
        v = Rotation.from_quat(qw, scalar_first=True).apply(body.vertices) + p
        assert (v >= lo - 1e-6).all() and (v <= hi + 1e-6).all()


def test_derivation_marks_reconstructions() -> None:
    steps = LESSON.derivation(LESSON.resolve())
    by_source = {s.source: s for s in steps}
    for src in ("(1a)", "(1b)", "(2)", "(3)"):
        assert by_source[src].reconstructed
    assert not by_source["(4)"].reconstructed


def test_task_translation_sequential() -> None:
    m = Machine5(limits="improved")
    task = make_task(Paraboloid(), "circle", 32, radius=300.0)
    qs = translate(m, task)
    steps = np.degrees(np.diff([q[3] for q in qs]))
    assert np.allclose(np.abs(steps), 11.25, atol=1e-9)


def test_vertical_start_takes_next_c() -> None:
    """A task starting at the apex (vertical beam) takes C from the next pose: no lever swing."""
    run = LESSON.simulate(
        LESSON.resolve(
            {
                "path": "line",
                "u0": 0,
                "v0": 0,
                "u1": 100,
                "v1": 0,
                "segments": 4,
                "method": "bisection",
                "limits": "original",
            }
        )
    )
    assert run.series["C_deg"][0] == pytest.approx(90.0) and run.series["B_deg"][0] == 0.0
    assert run.metrics["converged"] and run.metrics["pieces"] == 8


def test_line_through_apex_needs_improved_limits() -> None:
    """Across the apex the azimuth jumps by pi: C in [0, 2pi) must swing the lever, B of both signs need not."""
    base = {
        "path": "line",
        "u0": -100,
        "v0": 0,
        "u1": 100,
        "v1": 0,
        "segments": 1,
        "method": "bisection",
    }
    orig = LESSON.simulate(LESSON.resolve({**base, "limits": "original"}))
    impr = LESSON.simulate(LESSON.resolve({**base, "limits": "improved"}))
    assert not orig.metrics["converged"] and orig.metrics["deviation_max_mm"] > 100.0
    assert orig.messages and "vertical" in orig.messages[0]
    assert impr.metrics["converged"] and impr.metrics["deviation_max_mm"] <= 0.020
    assert impr.series["B_deg"].min() < 0.0 < impr.series["B_deg"].max()


def test_program_size_limits() -> None:
    with pytest.raises(ParamError):
        LESSON.resolve({"method": "nonlinear", "segments": 200, "sub_moves": 256})
    run = LESSON.simulate(
        LESSON.resolve({"method": "bisection", "tolerance_um": 1, "segments": 3, "radius": 900})
    )
    assert run.metrics["converged"] and run.metrics["deviation_max_mm"] <= 0.001
    assert run.metrics["pieces"] <= 4096


def test_scene_colours_the_tool_trail_by_deviation():
    params = LESSON.resolve({"tolerance_um": 20})
    scene = LESSON.scene(params)
    name, lo, hi = scene.trail_color_by["tool"]
    assert name == "deviation_um" and (lo, hi) == (20.0, 40.0)
    frame = LESSON.stepper(params).advance(0.5)
    assert name in frame.scalars and "tool" in frame.points
