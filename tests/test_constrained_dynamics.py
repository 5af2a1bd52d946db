"""Tests of lessons.constrained_dynamics and lessons.constrained_examples (§2.2)."""

from __future__ import annotations

import numpy as np
import pytest

from lessons.constrained_dynamics import LESSON, pendulum_drift, rheonomic_drift_numbers
from lessons.constrained_examples import ExampleRun, planar3_acceleration_difference, system
from lessons.core.constraint_eval import CORRECTIONS


def test_drift_numbers() -> None:
    d = pendulum_drift()
    assert d["free_max"] > 5e-5  # the unstabilized constraint error is visible
    assert d["free_50"] > 3 * d["free_10"]  # and grows with time
    assert d["stab_max"] < 1e-5 < d["free_max"]


def test_rheonomic_pendulum_drift_and_stabilization() -> None:
    d = rheonomic_drift_numbers()  # RK45, rtol = atol = 1e-6, 20 s
    assert 5e-5 <= d["free_f"] <= 1e-3 and 1e-4 <= d["free_err"] <= 3e-3
    assert d["stab_f"] <= 1e-6 and d["stab_err"] <= d["free_err"] / 10


def test_rheonomic_run_shows_length_and_drift() -> None:
    params = LESSON.resolve(preset="rheonomic-pendulum")
    r = LESSON.simulate(params, 2.0)
    assert {"length", "f", "f_dot", "lambda", "position_error"} <= set(r.series)
    L = r.series["length"]
    assert L == pytest.approx(1 + 0.2 * np.sin(2 * r.t), abs=1e-15)
    assert r.units["length"] == "m" and r.units["f"] == "m^2"
    # the start velocity is projected onto (2.29): radial speed L'(0) = 0.4 m/s
    assert np.hypot(r.series["x_dot"][0], r.series["y_dot"][0]) == pytest.approx(0.4, rel=1e-12)
    assert any("projected" in n.text for n in LESSON.notes(params))


def test_planar3_matches_reduced_model() -> None:
    assert planar3_acceleration_difference(seed=7) < 1e-12


def test_shapes() -> None:
    assert system("pendulum")[1].H.shape == (1, 2)
    assert system("rheonomic-pendulum")[1].H.shape == (1, 2)
    assert system("knife-edge")[1].H.shape == (1, 3)
    assert system("planar-3axis")[1].H.shape == (2, 5)


def test_knife_edge_no_side_slip() -> None:
    values = {"example": "knife-edge", "F": 3.0, "m": 2.0, "omega0": 2.0}
    p = LESSON.resolve({**values, "integrator": "DOP853", "rtol": 1e-10})
    t = np.linspace(0, 3, 121)
    s = LESSON.observation(p, t, ExampleRun(p).state(t))
    assert np.max(np.abs(s["g"])) < 1e-8
    assert np.max(s["speed_error"]) < 1e-7  # u = u0 + F/(m omega0) sin(omega0 t)


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_presets(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    r = LESSON.simulate(params, 2.0)
    assert not [m for m in r.messages if "not defined" in m or "stopped" in m]
    for name, column in r.series.items():
        assert column.shape == r.t.shape and np.all(np.isfinite(column)), name


def test_corrections_are_shown_and_noted() -> None:
    params = LESSON.resolve()
    steps = LESSON.derivation(params)
    tagged = [s for s in steps if s.reconstructed and s.reconstructed.startswith("corrected")]
    sources = {s.source for s in tagged}
    assert {"(2.24)", "§2.2, solution step 3", "§2.2, solution step 4"} <= sources
    assert any("v_2" in str(s.math) for s in tagged if s.source == "(2.24)")
    notes = [n for n in LESSON.notes(params) if n.kind == "corrected"]
    assert len(notes) == len(CORRECTIONS) and all(n.source and n.evidence for n in notes)


@pytest.mark.parametrize(
    "example", ["pendulum", "rheonomic-pendulum", "knife-edge", "planar-3axis"]
)
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
