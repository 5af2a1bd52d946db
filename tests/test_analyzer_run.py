"""The analyzer's trajectory: one step sequence however it is read, F kept to round-off,
the constant-speed analyzer holding only while its field is zero."""

import analyzer_lab.lessons.analyzers.field.run as analyzer_run
import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.field.analyzer import COEFF_NAMES, AnalyzerModel, Controls
from analyzer_lab.lessons.analyzers.field.run import (
    SHORT_GRAIN,
    SpeedStepper,
    Trajectory,
    integrate,
)
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.formula import parse_formula
from analyzer_lab.lessons.kit.integrators import gl_propagators

from tests.support.surfaces import SURFACES


def family_model(V):
    qs = [SURFACES[n][0] for n in SURFACES]
    coeffs = {n: np.array([getattr(q, n) for q in qs]) for n in COEFF_NAMES}
    f = parse_formula
    controls = Controls(f("0.6 + 0.3*sin(t)"), f("0.2*cos(2*t)"), f("0.4"), V=V)
    r0 = np.array([SURFACES[n][1] for n in SURFACES])
    scales = np.array([q.scale for q in qs])
    return AnalyzerModel(coeffs, controls), r0, scales


@pytest.mark.parametrize(
    "V", [None, parse_formula("1 + 0.5*sin(t)")], ids=["analyzer", "constant-speed"]
)
def test_invariant_round_off_over_1e5_steps_every_type(V):
    model, r0, scales = family_model(V)
    assert np.all(np.abs(model.F(r0)) < 1e-12)
    h = 1e-4 if V is None else 2e-4
    run = integrate(model, r0, 1e5 * h, h=h, samples=501)
    assert run.r.shape[1] == len(SURFACES)
    # relative to the size of F's terms where the point went (a hyperbolic paraboloid's
    # trajectories run far out): round-off of F itself is ~1e-16 of that
    rel = run.drift.max(axis=0) / np.maximum(scales, model.F_scale(run.r))
    assert np.all(rel <= 1e-12), dict(zip(SURFACES, rel))
    moved = np.linalg.norm(run.r[-1] - run.r[0], axis=-1)
    assert np.all(moved > 1e-3)


def test_speed_parallel_controls_hold():
    """u parallel to the gradient in constant-speed mode: grad F x w = 0, hold."""
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(0.0, 0.0, 2.0, V=1.0)
    )  # w ~ (u3,u2,u1) = (2,0,0)
    run = integrate(model, [1.0, 0.0, 0.0], 0.5, h=1e-2)
    assert run.held.all() and np.allclose(run.r, [1.0, 0.0, 0.0])


def test_reference_solver_drifts_where_gl_does_not():
    model, r0, scales = family_model(None)
    gl = integrate(model, r0, 50.0, h=1e-2, samples=501)
    rk = integrate(model, r0, 50.0, method="RK45", samples=501)
    gl_rel = gl.drift.max(axis=0) / np.maximum(scales, model.F_scale(gl.r))
    rk_rel = rk.drift.max(axis=0) / np.maximum(scales, model.F_scale(rk.r))
    assert gl_rel.max() < 1e-13
    assert rk_rel.max() > 1e-7


def test_example_1_3_constant_speed_leaves_at_once():
    """The field of Ex. 1.3 vanishes at (1, 0, 0) only at t = 0: the Gauss nodes lie inside
    the first step, so the point leaves at once (arc length t at speed V = 1)."""
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(f("sin(10*t)"), f("t"), f("5"), V=1.0)
    )
    run = integrate(model, [1.0, 0.0, 0.0], 0.2, h=0.05)
    speed = np.linalg.norm(run.v[:, 0], axis=-1)
    assert run.held[0, 0] and not run.held[1:].any()
    assert np.abs(speed[1:] - 1.0).max() < 1e-9
    assert np.linalg.norm(run.r[1, 0] - run.r[0, 0]) == pytest.approx(0.05, rel=0.02)


@pytest.mark.parametrize(
    "controls",
    [
        Controls(5.0, 5.0, 5.0),
        Controls(parse_formula("t"), 5.0, 5.0),
        Controls(parse_formula("t"), 5.0, 5.0, V=1.0),
    ],
    ids=["constant", "varying", "constant-speed"],
)
def test_trajectory_read_frame_by_frame_equals_read_at_once(controls):
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), controls)
    grid = np.arange(0, 201) * 0.01
    at_once = Trajectory(model, [1.0, 0.0, 0.0], h=0.01).at(grid)
    live = Trajectory(model, [1.0, 0.0, 0.0], h=0.01)
    t, k = 0.0, 0
    while k < len(grid):
        t = min(t + 1 / 36, grid[k])
        state = live.at(t)[0]
        if t == grid[k]:
            assert np.abs(state - at_once[k]).max() <= 1e-13
            k += 1


def test_between_nodes_a_shortened_step_keeps_the_order():
    """Off the node grid the state is one shortened step: as accurate as the nodes."""
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(parse_formula("t"), 5.0, 5.0))
    fine = integrate(model, [1.0, 0.0, 0.0], 1.0, h=1e-3, samples=8)
    coarse = integrate(model, [1.0, 0.0, 0.0], 1.0, h=2e-2, samples=8)
    assert np.abs(coarse.r - fine.r).max() < 1e-8


def test_scipy_methods_read_dense_output_in_pieces():
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(5.0, 5.0, 5.0))
    run = integrate(model, [1.0, 0.0, 0.0], 12.0, h=0.05, method="DOP853", rtol=1e-8, atol=1e-10)
    assert run.t[-1] == 12.0 and run.nfev > 0
    assert np.abs((run.v**2).sum(-1) - 50.0).max() < 1e-5


def test_reading_backwards_is_refused():
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(5.0, 5.0, 5.0))
    traj = Trajectory(model, [1.0, 0.0, 0.0], h=0.01)
    traj.at(5.0)
    with pytest.raises(ValueError, match="backwards"):
        traj.at(0.5)


def test_shortened_steps_of_a_constant_field_reuse_their_maps() -> None:
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(5.0, 5.0, 5.0))
    traj = Trajectory(model, np.array([1.0, 0.0, 0.0]), h=0.01)
    frames = [k / 600.0 for k in range(1, 400)]  # the session's time quanta
    states = traj.at(frames)
    assert 0 < len(traj._short_maps) <= 6  # 6 offsets of 1/600 s within a step of 0.01 s
    # each value is the shortened step from its node with the map of the rounded length
    k = int(np.floor(frames[100] / 0.01 + 1e-9))
    rest = frames[100] - k * 0.01
    node = Trajectory(model, np.array([1.0, 0.0, 0.0]), h=0.01).at([k * 0.01])[0]
    key = round(rest / 0.01 * SHORT_GRAIN)
    D, phi = gl_propagators(traj._coeffs, 0.0, key * 0.01 / SHORT_GRAIN, 1, 3)
    expected = node + (D[0] @ node[:, :, None])[:, :, 0] + phi[0]
    assert np.array_equal(states[100], expected)
    # and agrees with the shortened step of the exact length (|v| h / 2**40 apart)
    D, phi = gl_propagators(traj._coeffs, k * 0.01, rest, 1, 3)
    exact = node + (D[0] @ node[:, :, None])[:, :, 0] + phi[0]
    assert np.allclose(states[100], exact, rtol=0, atol=1e-13)


def test_time_dependent_field_keeps_no_shortened_maps() -> None:
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(parse_formula("t"), 5.0, 5.0))
    traj = Trajectory(model, np.array([1.0, 0.0, 0.0]), h=0.01)
    traj.at([k / 600.0 for k in range(1, 60)])
    assert traj._short_maps == {}


def test_speed_stages_extrapolate_the_step_before_exactly_for_a_quadratic() -> None:
    sp = SpeedStepper(AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(1.0, V=1.0)))
    # slopes of a degree-2 polynomial at the stage times of a step of length h ...
    poly = lambda x: 1.0 - 2.0 * x + 0.5 * x**2  # noqa: E731
    h = 0.02
    K = np.array([poly(h * c) for c in sp.c])[None, :, None] * np.ones((1, 1, 3))
    for ratio in (1.0, 0.5, 0.25):
        E = sp.extrapolation(ratio)
        pred = np.einsum("ij,njd->nid", E, K)
        # ... predict those of the next step (length ratio * h) exactly
        want = np.array([poly(h + ratio * h * c) for c in sp.c])
        assert np.allclose(pred[0, :, 0], want, rtol=0, atol=1e-13)


def test_speed_stages_from_the_step_before_converge_to_the_same_step_in_fewer_iterations() -> None:
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(5.0, 5.0, 5.0, V=1.0))
    r = np.array([[1.0, 0.0, 0.0]])
    sp = SpeedStepper(model)
    r1 = sp.step_substeps(0.0, r, 0.01)
    before = sp.last
    cold, warm = SpeedStepper(model), SpeedStepper(model)
    a = cold.step_substeps(0.01, r1, 0.01)
    b = warm.step_substeps(0.01, r1, 0.01, None, before)
    assert np.allclose(a, b, rtol=0, atol=1e-15)
    assert warm.evaluations < cold.evaluations
    # on the sphere at constant speed: on the surface, |v| = V
    assert abs(float(np.sum(b**2)) - 1.0) < 1e-14
    v = model.velocity(0.02, b)
    assert abs(float(np.linalg.norm(v)) - 1.0) < 1e-14


def test_frames_in_a_step_cut_into_many_substeps_read_its_substep_ends(monkeypatch) -> None:
    """Example 1.3's start, where the field is zero: any step from there is cut into ~200
    substeps however short; a frame is one shortened substep from the kept substep ends,
    the same state as the shortened step from the node to 1e-12."""
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(f("sin(10*t)"), f("t"), 5.0, V=1.0)
    )
    rng = np.random.default_rng(0)
    times = np.sort(
        np.concatenate([np.arange(1, 30) / 600, rng.uniform(0, 3, 300), np.arange(61) * 0.05])
    )
    traj = Trajectory(model, [1.0, 0.0, 0.0], h=0.05)
    got = traj.at(times)
    with monkeypatch.context() as m:
        m.setattr(analyzer_run, "KEEP_SUBSTEPS", 10**9)  # every frame a shortened step
        ref = Trajectory(model, [1.0, 0.0, 0.0], h=0.05).at(times)
    assert np.abs(got - ref).max() <= 1e-12
    assert np.abs((got**2).sum(-1) - 1.0).max() <= 1e-14
    # after the first frame in the first step, a frame takes a few substeps, not ~200
    live = Trajectory(model, [1.0, 0.0, 0.0], h=0.05)
    live.at(0.01)
    speed = live._speed
    assert speed is not None and live._substep_ends is not None
    assert len(live._substep_ends[2]) > 100
    before = speed.evaluations
    state = live.at(0.04)[0]
    assert speed.evaluations - before <= 3 * 30  # <= 3 substeps of <= 30 iterations
    assert np.array_equal(state, Trajectory(model, [1.0, 0.0, 0.0], h=0.05).at([0.01, 0.04])[1])
