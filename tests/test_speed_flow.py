"""(1.59) with constant controls and a skew field as a time change of (1.50): the same
trajectory as the stage-by-stage Gauss-Legendre solve, F kept, one value per time."""

import analyzer_lab.lessons.analyzers.field.run as analyzer_run
import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.field.analyzer import COEFF_NAMES, AnalyzerModel, Controls
from analyzer_lab.lessons.analyzers.field.run import MAX_TURNS, Trajectory
from analyzer_lab.lessons.analyzers.field.speed_flow import UniformSpeed, compose_power
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.formula import parse_formula
from analyzer_lab.lessons.kit.integrators import apply_propagators, gl_propagators

SPHERE = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(5.0, 5.0, 5.0, V=1.0))


def stage_solve(model, r0, h, monkeypatch):
    """The trajectory of the simplified-Newton solve of every step (the time change off)."""
    with monkeypatch.context() as m:
        m.setattr(analyzer_run.UniformSpeed, "of", classmethod(lambda cls, *a: None))
        traj = Trajectory(model, r0, h=h)
    assert traj._speed is not None and traj._uniform is None
    return traj


def played_times(t_end: float, dt: float) -> np.ndarray:
    """Times summed frame by frame as a session does (round-off of the sum included)."""
    out, t = [], 0.0
    while t < t_end:
        t += dt
        out.append(t)
    return np.array(out)


CASES = {
    # Fig. 1.28: u = (5, 5, 5), V = 1 from (1, 0, 0), h = 0.05
    "fig-1.28": (SPHERE, [[1.0, 0.0, 0.0]], 0.05),
    # a sphere off the origin (c != 0), reversed, fast
    "shifted-reverse": (
        AnalyzerModel.of(
            Quadric.sphere(2.0, (0.5, -1.0, 0.25)).coeffs(), Controls(1.0, -2.0, 0.5, 3.0, -1.0)
        ),
        [[2.5, -1.0, 0.25]],
        0.02,
    ),
    # a spheroid turned about its axis of symmetry (u1 only: w = (0, 0, u1))
    "spheroid-axis": (
        AnalyzerModel.of(Quadric.ellipsoid(2.0, 2.0, 0.5).coeffs(), Controls(3.0, V=2.0)),
        [[np.sqrt(2.0), 0.0, np.sqrt(0.125)]],
        0.05,
    ),
}


def test_only_a_skew_field_with_constant_controls_and_speed_is_a_time_change() -> None:
    f = parse_formula
    r0 = np.array([[1.0, 0.0, 0.0]])
    sphere = Quadric.sphere(1.0).coeffs()
    assert UniformSpeed.of(SPHERE, r0, 0.03) is not None
    for model in (
        AnalyzerModel.of(sphere, Controls(5.0, 5.0, 5.0)),  # (1.50): no V
        AnalyzerModel.of(sphere, Controls(f("t"), 5.0, 5.0, V=1.0)),
        AnalyzerModel.of(sphere, Controls(5.0, 5.0, 5.0, V=f("0.5 + 0.4*sin(t)"))),
        # an ellipsoid turned about no axis of symmetry: |A r + c| changes along the path
        AnalyzerModel.of(Quadric.ellipsoid(2.0, 1.0, 0.5).coeffs(), Controls(5.0, 5.0, 5.0, V=1)),
    ):
        assert UniformSpeed.of(model, r0, 0.03) is None
    ell = AnalyzerModel.of(Quadric.ellipsoid(2.0, 1.0, 0.5).coeffs(), Controls(5.0, 5.0, 5.0, V=1))
    assert Trajectory(ell, [[2.0, 0.0, 0.0]], h=0.05)._speed is not None


@pytest.mark.parametrize("case", list(CASES))
def test_time_change_agrees_with_the_stage_solve_at_nodes_and_between(case, monkeypatch) -> None:
    model, r0, h = CASES[case]
    r0 = np.array(r0)
    assert abs(float(model.F(r0)[0])) < 1e-14
    rng = np.random.default_rng(7)
    times = np.sort(
        np.concatenate([np.arange(0, 201) * h, played_times(10.0, 1 / 36), rng.uniform(0, 10, 300)])
    )
    fast = Trajectory(model, r0, h=h)
    assert fast._uniform is not None and fast._speed is None
    got = fast.at(times)
    ref = stage_solve(model, r0, h, monkeypatch).at(times)
    scale = np.abs(ref).max()
    assert np.abs(got - ref).max() <= 2e-13 * scale
    # F to round-off at every read time, |v| = V
    assert np.abs(model.F(got[:, 0]) - model.F(r0)[0]).max() <= 2e-15 * scale**2
    v = model.velocities(times, got)
    V = abs(float(model.controls.speed(np.zeros(1))[0]))
    assert np.abs(np.linalg.norm(v, axis=-1) - V).max() <= 1e-13


def test_invariant_and_speed_kept_over_1e5_steps() -> None:
    traj = Trajectory(SPHERE, [[1.0, 0.0, 0.0]], h=0.05)
    times = np.linspace(0.0, 5000.0, 2001) + 0.0123
    r = traj.at(times)
    # round-off of the repeated map, about sqrt(1e5) x 1e-16 (the stage-by-stage solve
    # drifts 4.6e-14 here)
    assert np.abs((r**2).sum(-1) - 1.0).max() <= 6e-14
    v = SPHERE.velocities(times, r)
    assert np.abs(np.linalg.norm(v, axis=-1) - 1.0).max() <= 1e-14


def test_played_frame_by_frame_equals_read_at_once() -> None:
    times = played_times(30.0, 17 / 600)  # drifting off the quanta by round-off of the sum
    live = Trajectory(SPHERE, [[1.0, 0.0, 0.0]], h=0.05)
    frames = np.array([live.at(t)[0] for t in times])
    at_once = Trajectory(SPHERE, [[1.0, 0.0, 0.0]], h=0.05).at(times)
    assert np.array_equal(frames, at_once)
    # a few Gauss-Legendre maps serve the frames: one per offset from the nodes
    assert len(live._uniform._coarse) <= 30  # offsets of 1/600 s within a step of 0.05 s


def apply(step_map, r: np.ndarray) -> np.ndarray:
    D, phi = step_map
    return r + (D[0] @ r[..., None])[..., 0] + phi[0]


def test_shortened_maps_agree_with_the_map_of_the_exact_length() -> None:
    u = UniformSpeed.of(SPHERE, np.array([[1.0, 0.0, 0.0]]), MAX_TURNS[3])
    assert u is not None
    r = np.array([[0.6, 0.8, 0.0]])
    for length in (1e-9, 1 / 600, 0.0123456789, 7 / 600 + 3e-14, 0.0499999):
        short, exact = u.short_map(length, 0.05, 3), u.step_map(length, 3)
        assert np.abs(apply(short, r) - apply(exact, r)).max() <= 2e-16


def test_a_step_is_its_substeps_composed() -> None:
    u = UniformSpeed.of(SPHERE, np.array([[1.0, 0.0, 0.0]]), MAX_TURNS[3])
    assert u.substeps(0.05) == 3  # 1.73 rad/s x 0.05 s > 2 x 0.03 rad
    D, phi = gl_propagators(u.coeffs, 0.0, 0.05 / 3, 1, 3)
    r = np.array([[1.0, 0.0, 0.0]])
    for m, step_map in (
        (3, u.step_map(0.05, 3)),
        *((m, compose_power(D, phi, m)) for m in (1, 2, 13)),
    ):
        seq, _ = apply_propagators(np.repeat(D, m, 0), np.repeat(phi, m, 0), r)
        assert np.abs(seq[-1] - apply(step_map, r)).max() <= 1e-15
    with pytest.raises(ValueError):
        compose_power(D, phi, 0)


def test_a_family_with_a_held_point(monkeypatch) -> None:
    """Per point its own rate; a point where the field vanishes holds for the whole run."""
    R = np.array([1.0, 2.0, 1.0])
    coeffs = {n: np.zeros(3) for n in COEFF_NAMES}
    for n in ("a11", "a22", "a33"):
        coeffs[n] = np.ones(3)
    coeffs["a44"] = -(R**2)
    model = AnalyzerModel(coeffs, Controls(2.0, 0.0, 0.0, V=1.5))  # w ~ (0, 0, 2)
    r0 = np.array([[1.0, 0.0, 0.0], [0.0, 2.0 * np.sqrt(0.5), np.sqrt(2.0)], [0.0, 0.0, 1.0]])
    times = np.concatenate([np.arange(0, 101) * 0.05, played_times(5.0, 1 / 36)])
    times.sort()
    fast = Trajectory(model, r0, h=0.05)
    assert fast._uniform is not None and fast._uniform.omega[2] == 0.0
    got = fast.at(times)
    ref = stage_solve(model, r0, 0.05, monkeypatch).at(times)
    assert np.abs(got - ref).max() <= 1e-13
    assert np.array_equal(got[:, 2], np.broadcast_to(r0[2], got[:, 2].shape))
    v = model.velocities(times, got)
    assert np.abs(np.linalg.norm(v[:, :2], axis=-1) - 1.5).max() <= 1e-13
    assert np.all(v[:, 2] == 0.0)


def reference_velocities(model: AnalyzerModel, t: np.ndarray, R: np.ndarray) -> np.ndarray:
    """(1.59) with the hold test at every point (the velocities before the cheap bound)."""
    A, c = model.linear_coeffs(t, R.shape[1])
    n = np.einsum("mnij,mnj->mni", A, R) + c
    norm = np.linalg.norm(n, axis=-1)
    umax = np.abs(model.controls.at(t)).max(axis=0)[:, None]
    scale = np.where(
        model.holds(norm, model.hold_size(R), umax),
        0.0,
        model.controls.sign * model.controls.speed(t)[:, None] / np.where(norm > 0, norm, 1.0),
    )
    return n * scale[..., None]


@pytest.mark.parametrize("quadric", ["sphere", "ellipsoid", "hyperboloid"])
def test_velocities_skip_the_hold_test_only_where_no_point_holds(quadric) -> None:
    q = {
        "sphere": Quadric.sphere(3.0, (1.0, -2.0, 0.5)),
        "ellipsoid": Quadric.ellipsoid(2.0, 1.0, 0.5, (0.0, 1.0, -1.0)),
        "hyperboloid": Quadric.hyperboloid_one_sheet(2.0, 1.0, 0.5),
    }[quadric]
    f = parse_formula
    model = AnalyzerModel.of(q.coeffs(), Controls(f("sin(t)"), 2.0, f("t - 1"), V=f("1 + t")))
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 2.0, 9)
    R = rng.normal(size=(9, 7, 3)) * 3
    # points where the field is zero or nearly: the half-gradient Q r + b along (u3, u2, u1)
    u = model.controls.at(t)
    w = np.stack([u[2], u[1], u[0]], axis=-1)  # (9, 3)
    for k, eps in enumerate((0.0, 1e-13, 1e-10, 1e-8, 1e-6)):
        g = w * (1 + k) + eps * rng.normal(size=w.shape)
        R[:, k] = np.linalg.solve(q.Q, (g - q.b).T).T
    R[:, 5] = np.linalg.solve(q.Q, -q.b)  # the centre: gradient zero
    got = model.velocities(t, R)
    ref = reference_velocities(model, t, R)
    assert np.array_equal(got, ref)
    held = np.linalg.norm(ref, axis=-1) == 0
    assert held.sum() >= 9 and not held[:, 6].any()  # some points held, random ones move
    # one point that moves at every time: the cheap bound skips the hold test, same values
    assert np.array_equal(model.velocities(t, R[:, 6:]), reference_velocities(model, t, R[:, 6:]))
