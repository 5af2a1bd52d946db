"""Tests of analyzer_lab.lessons.mechanics.constrained_dynamics and
analyzer_lab.lessons.mechanics.lagrange.examples (§2.2).
"""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.kit.dense_solution import DenseSolution
from analyzer_lab.lessons.mechanics.constrained_dynamics import (
    LESSON,
    pendulum_drift,
    rheonomic_drift_numbers,
)
from analyzer_lab.lessons.mechanics.lagrange.constraint_eval import CORRECTIONS
from analyzer_lab.lessons.mechanics.lagrange.examples import (
    ExampleRun,
    PendulumReference,
    evaluator,
    inputs_at,
    inputs_of,
    planar3_acceleration_difference,
    system,
)


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


@pytest.mark.parametrize(
    "example", ["pendulum", "rheonomic-pendulum", "knife-edge", "planar-3axis"]
)
def test_generated_accelerations_match_the_stacked_solve(example: str) -> None:
    """(2.34) generated on floats (the integrator's right-hand side) is the stacked solve."""
    ev, cs = evaluator(example), system(example)[1]
    rng = np.random.default_rng(3)
    acc = ev.accelerations()
    for _ in range(10):
        q, qd, t = rng.normal(size=cs.n), rng.normal(size=cs.n), float(rng.uniform(0, 5))
        p, u = rng.uniform(0.5, 2.0, len(cs.params)), inputs_of(example, np.array([t]))
        assert inputs_at(example, t) == pytest.approx(u[:, 0], abs=1e-15)
        for a, b in ((0.0, 0.0), (5.0, 7.0)):
            P = ev.parts(np.array([t]), q[:, None], qd[:, None], p, u)
            want = ev.solve(P, qd[:, None], a, b)[0][0]
            got = acc(list(q), list(qd), t, list(p), inputs_at(example, t), a, b)
            assert np.max(np.abs(np.array(got) - want)) <= 1e-12 * max(1.0, np.max(np.abs(want)))


@pytest.mark.parametrize(
    ("g", "L", "theta", "omega", "t0"),
    [
        (9.81, 1.0, 1.0, 0.0, 0.0),  # released from rest (the presets)
        (9.81, 1.0, 1.0, -2.0, 3.0),  # swinging back
        (9.81, 2.0, -2.5, 1.0, 1.0),
        (9.81, 1.0, 0.5, 8.0, 0.0),  # over the top
        (9.81, 1.0, 0.5, -8.0, 0.0),
        (5.0, 1.0, -3.1, -0.2, 0.0),  # near the top
        (0.0, 1.0, 1.0, 2.0, 0.0),  # no gravity
        (9.81, 1.0, 0.0, 0.0, 0.0),  # at rest at the bottom
    ],
)
def test_pendulum_closed_form_is_the_angle_ode(
    g: float, L: float, theta: float, omega: float, t0: float
) -> None:
    ref = PendulumReference(g, L, t0, theta, omega)
    ode = DenseSolution(
        lambda t, z: np.array([z[1], -g / L * np.sin(z[0])]),
        t0,
        np.array([theta, omega]),
        "DOP853",
        1e-12,
        1e-12,
    )
    t = np.linspace(t0, t0 + 10.0, 201)
    a, b = ref.state(t), ode.state(t)
    assert np.abs(np.sin(a[:, 0]) - np.sin(b[:, 0])).max() < 1e-8
    assert np.abs(np.cos(a[:, 0]) - np.cos(b[:, 0])).max() < 1e-8
    assert np.abs(a[:, 1] - b[:, 1]).max() < 1e-7


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_live_frames_read_the_table_as_the_run_is_sampled(preset: str) -> None:
    """Played frames on the session's grain read blocks of the observation evaluated at
    once; off the grain the frame is observed alone.  Both are the headless run's values."""
    params = LESSON.resolve(preset=preset)
    st = LESSON.stepper(params)
    run = ExampleRun(params)
    grain = 1.0 / 600.0
    for dt in [17 * grain, 16 * grain, 0.013, 17 * grain, 500 * grain, 3 * grain]:
        fr = st.advance(dt)
        want = LESSON.observation(params, np.array([fr.t]), run.state(np.array([fr.t])))
        assert set(fr.scalars) == set(want)
        for name, v in want.items():
            assert fr.scalars[name] == pytest.approx(float(v[0]), rel=1e-12, abs=1e-14), name
    assert st._table is not None and st._table.builds >= 1


def test_run_metrics_count_the_solver_work() -> None:
    r = LESSON.simulate(LESSON.resolve(preset="knife-edge"), 2.0)
    run = ExampleRun(LESSON.resolve(preset="knife-edge"))
    run.state(r.t)
    assert r.metrics["steps"] == run.main.steps > 0
    assert r.metrics["nfev"] == run.main.evaluations > r.metrics["steps"]
