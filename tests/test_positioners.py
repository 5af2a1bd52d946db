"""Tests of lessons.positioners: Problems 2.1-2.5."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from lessons.catalog import all_lessons
from lessons.core.contract import Lesson, ParamError
from lessons.core.table6dof import inverse_dynamics, inverse_kinematics, program_state, table_joints
from lessons.positioners import LESSONS, Planar3Axis, Table6DOF, planar3_kinematics, planar3_phi

BY_ID = {l.id: l for l in LESSONS}
SMALL = ["linear-positioner", "rotary-positioner", "planar-2axis", "planar-3axis"]


def test_ids_in_catalog() -> None:
    ids = {l.id for l in all_lessons()}
    assert {
        "linear-positioner",
        "rotary-positioner",
        "planar-2axis",
        "planar-3axis",
        "table-6dof",
    } <= ids


@pytest.mark.parametrize("lesson", LESSONS, ids=lambda l: l.id)
def test_claims_pass(lesson: Lesson) -> None:
    for claim in lesson.claims():
        res = claim.check()
        assert res.passed, f"{lesson.id}/{claim.id}: expected {res.expected}, got {res.got}"


@pytest.mark.parametrize("lid", SMALL)
def test_presets_simulate(lid: str) -> None:
    lesson = BY_ID[lid]
    for preset in lesson.presets:
        params = lesson.resolve(preset=preset.name)
        r = lesson.simulate(params, 2.0)
        assert not r.messages
        for c in lesson.coords:  # type: ignore[attr-defined]
            for name in (c.name, f"{c.name}_dot", f"{c.name}_ddot"):
                assert r.series[name].shape == r.t.shape and np.all(np.isfinite(r.series[name]))
        for i in lesson.inputs:  # type: ignore[attr-defined]
            assert np.all(np.isfinite(r.series[i.name]))


@pytest.mark.parametrize("lid", SMALL)
def test_stepper_and_scene(lid: str) -> None:
    lesson = BY_ID[lid]
    for problem in ("forward", "inverse"):
        params = lesson.resolve({"problem": problem})
        st = lesson.stepper(params)
        f1 = st.advance(0.1)
        st.set_params(lesson.resolve({"problem": problem}))
        f2 = st.advance(0.1)
        assert f2.t == pytest.approx(0.2) and f1.poses and f1.scalars
        for name in lesson.scene(params).bodies:
            assert name.name in f2.poses
        f0 = st.reset()
        assert f0.t == 0.0
        sc = lesson.scene(params)
        assert np.all(np.isfinite(np.array(sc.bounds)))
        names = {s for p in lesson.plots for s in p.series}
        assert names <= set(f2.scalars)
        steps = lesson.derivation(params)
        assert steps and all(s.title for s in steps)


def test_linear_numbers() -> None:
    r = BY_ID["linear-positioner"].run("forward-constant-force")
    assert r.series["x"][-1] == pytest.approx(15.0, rel=1e-8)
    assert r.series["x_ddot"][0] == pytest.approx(0.3, rel=1e-12)
    inv = BY_ID["linear-positioner"].run("inverse-cosine-move")
    t = inv.t
    want = 5.0 * 0.1 * (np.pi / 2) ** 2 * np.cos(np.pi * t / 2) + 0.5
    assert np.max(np.abs(inv.series["F_dv"] - want)) < 1e-9


def test_rotary_inertia_and_validation() -> None:
    lesson = BY_ID["rotary-positioner"]
    inv = lesson.run("inverse-quarter-turn")
    J = 1.0 * 0.2**2 + 0.5 * 0.3**2 + 2.0 * 0.1**2
    t = inv.t
    phidd = 0.25 * np.sin(t)  # phi = (t - sin t)/4
    assert np.max(np.abs(inv.series["M_dv"] - J * phidd)) < 1e-9
    with pytest.raises(ParamError):
        lesson.resolve({"h1": 0, "h2": 0, "h3": 0})


def test_planar2_layouts_differ() -> None:
    lesson = BY_ID["planar-2axis"]
    h = lesson.run(values={"layout": "horizontal", "Q_y": "0"}, t_end=1.0)
    v = lesson.run(values={"layout": "vertical", "Q_y": "0"}, t_end=1.0)
    assert h.series["y"][-1] == pytest.approx(0.0, abs=1e-12)
    assert v.series["y"][-1] == pytest.approx(-9.81 / 2, rel=1e-8)
    assert np.allclose(v.series["v"], np.hypot(v.series["x_dot"], v.series["y_dot"]))


def test_planar3_kinematics_and_equations() -> None:
    xB, yB = planar3_kinematics(0.1, -0.2, 0.3, 0.5, np)
    a, b, c = planar3_phi(0.1, -0.2, float(xB), float(yB), 0.5)
    assert a == pytest.approx(0.3) and b == pytest.approx(0.3) and c == pytest.approx(0.3)
    # full range: atan2 recovers phi = 2.5 where arcsin cannot
    xB, yB = planar3_kinematics(0.0, 0.0, 2.5, 0.5, np)
    assert planar3_phi(0.0, 0.0, float(xB), float(yB), 0.5)[2] == pytest.approx(2.5)
    lesson = Planar3Axis()
    m = lesson.model(lesson.resolve())
    M = m.mass_matrix
    mA, mB, mAB, J, AB = m.params
    phi = m.q[2]
    assert sp.simplify(M[0, 0] - (mA + mB + mAB)) == 0
    assert sp.simplify(M[0, 2] - AB * mB * sp.sin(phi)) == 0
    assert sp.simplify(M[2, 2] - (J + AB**2 * mB)) == 0


def test_bad_formula_does_not_crash() -> None:
    lesson = BY_ID["linear-positioner"]
    r = lesson.simulate(lesson.resolve({"F_dv": "1/t"}), 1.0)
    assert r.messages and "F_dv" in r.messages[0]
    r = lesson.simulate(lesson.resolve({"problem": "inverse", "x_t": "log(t)"}), 1.0)
    assert r.messages


# ---------------------------------------------------------------- Problem 2.5


def test_table_inverse_kinematics_geometry() -> None:
    pose = np.array([0.0, 0.0, 0.2, 0.0, 0.0, 0.0])
    ind, ok = inverse_kinematics(pose, 0.3, 0.15)
    assert ok
    J = table_joints(pose, 0.15)
    for k in range(3):
        radial = J[k, :2] / np.linalg.norm(J[k, :2])
        d = ind[2 * k : 2 * k + 2] - J[k, :2]
        assert np.dot(d, radial) == pytest.approx(
            np.sqrt(0.05), abs=1e-12
        )  # outward along its axis
    _, ok = inverse_kinematics(np.array([0, 0, 0.35, 0, 0, 0.0]), 0.3, 0.15)
    assert not ok


def test_table_static_and_validation() -> None:
    lesson = Table6DOF()
    p = lesson.pvec(lesson.resolve({"m_l": 0.0, "M_c": 12.0}))
    q, qd, qdd, _ = program_state(np.array([0, 0, 0.25, 0, 0, 0.0]), np.zeros(6), np.zeros(6), p)
    F, lam = inverse_dynamics(q, qd, qdd, p)
    want = 12.0 * 9.81 * np.sqrt(0.3**2 - 0.25**2) / (3 * 0.25)
    assert np.allclose([np.hypot(F[2 * k], F[2 * k + 1]) for k in range(3)], want, rtol=1e-10)
    with pytest.raises(ParamError):
        lesson.resolve({"z_D_t": "0.5"})


def test_table_runs_short() -> None:
    lesson = Table6DOF()
    inv = lesson.run("inverse-program", t_end=1.0)
    assert not inv.messages and inv.metrics["max_constraint_residual"] < 1e-12
    fw = lesson.run("forward-disturbance", t_end=0.3)
    assert not fw.messages and fw.metrics["max_constraint_residual"] < 1e-9
    assert 0 < fw.metrics["max_tracking_error"] < 1e-3
    for problem in ("forward", "inverse"):
        params = lesson.resolve({"problem": problem})
        st = lesson.stepper(params)
        f = st.advance(0.02)
        assert set(f.poses) == {b.name for b in lesson.scene(params).bodies}
        st.set_params(params)
        assert st.advance(0.02).t == pytest.approx(0.04)
        assert st.reset().t == 0.0
    assert np.all(np.isfinite(np.array(lesson.scene(lesson.resolve()).bounds)))
    steps = lesson.derivation(lesson.resolve())
    assert any(s.reconstructed for s in steps)


def test_table_plots_have_frame_scalars() -> None:
    lesson = Table6DOF()
    for problem in ("forward", "inverse"):
        f = lesson.stepper(lesson.resolve({"problem": problem})).advance(0.01)
        assert {s for p in lesson.plots for s in p.series} <= set(f.scalars)


def test_leg_energy_equals_three_particles() -> None:
    """Slender rod: m/6 (|vA|^2 + vA.vJ + |vJ|^2) = m/6 at each end + 2m/3 at the middle."""
    rng = np.random.default_rng(3)
    vA, vJ = rng.normal(size=3), rng.normal(size=3)
    m = 0.7
    rod = m / 6 * (vA @ vA + vA @ vJ + vJ @ vJ)
    # the rod integral: v(s) = vA + s (vJ - vA), T = m/2 * int_0^1 |v(s)|^2 ds
    s = np.linspace(0, 1, 20001)
    v = vA[None, :] + s[:, None] * (vJ - vA)[None, :]
    integral = m / 2 * np.trapezoid(np.sum(v * v, axis=1), s)
    particles = 0.5 * (m / 6) * (vA @ vA + vJ @ vJ) + 0.5 * (2 * m / 3) * np.sum(
        ((vA + vJ) / 2) ** 2
    )
    assert rod == pytest.approx(integral, rel=1e-8) and rod == pytest.approx(particles, rel=1e-12)
