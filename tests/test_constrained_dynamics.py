"""Tests of lessons.constrained_dynamics: the §2.2 algorithm on three examples."""

from __future__ import annotations

import numpy as np
import pytest

from lessons.constrained_dynamics import (
    LESSON,
    pendulum_drift,
    planar3_acceleration_difference,
    run_constrained,
    system,
)


def test_claims_pass() -> None:
    for claim in LESSON.claims():
        res = claim.check()
        assert res.passed, f"{claim.id}: expected {res.expected}, got {res.got}"


def test_drift_numbers() -> None:
    d = pendulum_drift()
    assert d["free_max"] > 5e-5  # the unstabilized constraint error is visible
    assert d["free_50"] > 3 * d["free_10"]  # and grows with time
    assert d["stab_max"] < 1e-5 < d["free_max"]


def test_planar3_matches_reduced_model() -> None:
    assert planar3_acceleration_difference(seed=7) < 1e-12


def test_shapes() -> None:
    assert system("pendulum")[1].H.shape == (1, 2)
    assert system("knife-edge")[1].H.shape == (1, 3)
    assert system("planar-3axis")[1].H.shape == (2, 5)


def test_knife_edge_no_side_slip() -> None:
    p = LESSON.resolve(
        {
            "example": "knife-edge",
            "F": 3.0,
            "m": 2.0,
            "omega0": 2.0,
            "integrator": "DOP853",
            "rtol": 1e-10,
        }
    )
    t = np.linspace(0, 3, 121)
    r = run_constrained("knife-edge", p, t)
    assert np.max(np.abs(r["c"])) < 1e-8
    assert np.max(r["ref_err"]) < 1e-7  # u = u0 + F/(m omega0) sin(omega0 t)


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_presets(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    r = LESSON.simulate(params, 2.0)
    assert not r.messages
    for name in ("f", "f_dot", "energy_error", "reference_error", "lambda_1", "q1"):
        assert r.series[name].shape == r.t.shape and np.all(np.isfinite(r.series[name]))
    assert r.metrics["max_abs_velocity_constraint"] < 1e-4


@pytest.mark.parametrize("example", ["pendulum", "knife-edge", "planar-3axis"])
def test_stepper_scene_derivation(example: str) -> None:
    params = LESSON.resolve({"example": example, "stabilization": True})
    st = LESSON.stepper(params)
    f = st.advance(0.05)
    sc = LESSON.scene(params)
    assert {b.name for b in sc.bodies} <= set(f.poses)
    assert np.all(np.isfinite(np.array(sc.bounds)))
    st.set_params(LESSON.resolve({"example": example, "stabilization": False}))
    assert st.advance(0.05).t == pytest.approx(0.1)
    assert st.reset().t == 0.0
    steps = LESSON.derivation(params)
    assert any(s.source == "(2.34)" for s in steps)
    assert any(s.source == "(2.29)" and s.reconstructed for s in steps)
