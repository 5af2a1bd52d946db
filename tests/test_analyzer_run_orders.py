"""Gauss-Legendre of higher order for the analyzers: order 12 agrees with order 6 at a
tight step, keeps F to round-off, and the constant-speed substep rules (a stage's turning
rate, stages not solved, a zero field at the start) each do what they say."""

from functools import cache

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.field.analyzer import AnalyzerModel, Controls
from analyzer_lab.lessons.analyzers.field.params import METHODS
from analyzer_lab.lessons.analyzers.field.run import MAX_TURNS, SpeedStepper, Trajectory, integrate
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.formula import parse_formula

from tests.support.integrator_problems import problems


def benchmark_problem(k: int) -> tuple[AnalyzerModel, np.ndarray, float]:
    """Problem ``k`` of the integrator benchmark: model, start point, scale of F."""
    _, q, controls, r0 = problems()[k]
    return AnalyzerModel.of(q.coeffs(), controls), r0, q.scale


@cache
def near_zero_passage(t0: float) -> tuple[AnalyzerModel, np.ndarray]:
    """The benchmark's V = 1 run at ``t0`` (its field comes within 1.2e-3 of zero at
    t = 80.08, where the point turns at about 70 rad/s)."""
    model, r0, _ = benchmark_problem(1)
    return model, Trajectory(model, r0, 0.0, "gauss-legendre-6", 0.1).at([t0])[0]


def fine(model: AnalyzerModel, R: np.ndarray, t0: float, t1: float) -> np.ndarray:
    """The order-6 reference from ``(t0, R)`` at ``t1`` (h = 5e-4)."""
    return Trajectory(model, R, t0, "gauss-legendre-3", 5e-4).at([t1])[0]


def test_order_12_is_a_method_the_lessons_offer() -> None:
    assert "gauss-legendre-6" in METHODS
    model, r0, _ = benchmark_problem(1)
    assert Trajectory(model, r0, 0.0, "gauss-legendre-6", 0.1).stages == 6


@pytest.mark.parametrize("h", [0.1, 0.05])
def test_constant_speed_order_12_agrees_with_order_6_at_a_tight_step(h: float) -> None:
    model, r0, scale = benchmark_problem(1)
    old = integrate(model, r0, 5.0, h=0.0025, method="gauss-legendre-3", samples=51)
    new = integrate(model, r0, 5.0, h=h, method="gauss-legendre-6", samples=51)
    assert np.abs(new.r - old.r).max() < 1e-12
    assert new.drift.max() / scale < 1e-15
    assert np.abs(np.linalg.norm(new.v, axis=-1) - 1.0).max() < 1e-12  # |v| = V
    assert new.nfev < old.nfev / 3  # larger steps, fewer field evaluations


@pytest.mark.parametrize("k", [0, 2], ids=["ellipsoid", "hyperboloid"])
def test_affine_order_12_agrees_with_order_6_on_and_between_nodes(k: int) -> None:
    model, r0, scale = benchmark_problem(k)
    t = np.arange(0, 81) * 0.0625  # between the nodes of h = 0.1: shortened steps
    old = Trajectory(model, r0, 0.0, "gauss-legendre-3", 0.0125).at(t)
    new = Trajectory(model, r0, 0.0, "gauss-legendre-6", 0.1).at(t)
    assert np.abs(new - old).max() < 1e-12
    assert np.abs(model.F(new) - model.F(r0[None])).max() / scale < 1e-15


def test_constant_field_order_12_maps_agree_with_order_6() -> None:
    """A time-independent field: one step map, and the kept maps of shortened steps."""
    model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(5.0, 5.0, 5.0))
    t = np.arange(1, 73) / 36.0
    old = Trajectory(model, [1.0, 0.0, 0.0], 0.0, "gauss-legendre-3", 0.001).at(t)
    traj = Trajectory(model, [1.0, 0.0, 0.0], 0.0, "gauss-legendre-6", 0.05)
    new = traj.at(t)
    assert traj._map is not None and traj._short_maps
    assert np.abs(new - old).max() < 1e-12
    assert np.abs((new**2).sum(-1) - 1.0).max() < 1e-15


def test_turn_limits_grow_with_the_order() -> None:
    model, _, _ = benchmark_problem(1)
    turns = [SpeedStepper(model, s).max_turn for s in range(3, 7)]
    assert turns == [MAX_TURNS[s] for s in range(3, 7)] and turns == sorted(set(turns))
    # short steps (order 6) check the stages against twice the limit, long ones against it
    assert [SpeedStepper(model, s).recheck for s in (2, 3, 4, 6)] == [2.0, 2.0, 1.0, 1.0]
    custom = SpeedStepper(model, 6, max_turn=0.5, recheck=3.0)
    assert (custom.max_turn, custom.recheck) == (0.5, 3.0)


def test_stage_jacobians_solve_a_large_step_in_few_iterations() -> None:
    """Newton's matrix from each stage's own Jacobian at the predicted stages: steps of
    0.1 s at order 12 take about 3 iterations on average (substeps included), a cold
    step at most 8, each solved to round-off."""
    model, r0, _ = benchmark_problem(1)
    sp = SpeedStepper(model, 6)
    R, before = r0[None], None
    for k in range(200):
        R = sp.step_substeps(k * 0.1, R, 0.1, None, before)
        before = sp.last
        assert sp.converged
    assert sp.evaluations / 6 / 200 < 3.5
    cold = SpeedStepper(model, 6)
    out = cold.step(R, 0.1, tuple(x[0] for x in cold.coefficients(20.0, 0.1, 1, 1)))
    assert cold.converged and cold.evaluations <= 8 * 6
    assert abs(float(model.F(out)[0] - model.F(R)[0])) < 1e-15 * 100  # scale 100


def test_a_stage_turning_fast_takes_the_step_again_in_substeps() -> None:
    """At t = 79.95 the step's start turns slowly enough for one step of 0.1 s at a limit
    of 0.5 rad, but its stages nearer the zero passage turn at up to 17 rad/s: the step is
    taken again in substeps and agrees with the fine reference; one whole step does not."""
    model, R = near_zero_passage(79.95)
    ref = fine(model, R, 79.95, 80.05)
    one = SpeedStepper(model, 6)
    whole = one.step(R, 0.1, tuple(x[0] for x in one.coefficients(79.95, 0.1, 1, 1)))
    assert float(one.rates[0]) * 0.1 > one.recheck * 0.5 and one.recheck == 1.0
    assert np.abs(whole - ref).max() > 1e-9
    sp = SpeedStepper(model, 6, max_turn=0.5)
    A, c, Vs, _ = (x[0] for x in sp.coefficients(79.95, 0.1, 1, 1))
    start = np.abs(Vs).max() * np.linalg.norm(A[0]) / np.linalg.norm(A[0] @ R[0] + c[0])
    assert start * 0.1 < 0.5  # the start alone asks for one step
    out = sp.step_substeps(79.95, R, 0.1)
    assert sp.last is not None and sp.last[1] < 0.1 / 2
    assert np.abs(out - ref).max() < 1e-12
    assert abs(float(model.F(out)[0] - model.F(R)[0])) < 1e-15 * 100


def test_stages_not_solved_take_the_step_again_in_substeps() -> None:
    """A step of 0.2 s across the zero passage: its stages are not solved in 30
    iterations.  With the turning limit out of the way, that alone splits the step until
    every substep's are, so F is kept to round-off."""
    model, R = near_zero_passage(80.0)
    one = SpeedStepper(model, 6)
    one.step(R, 0.2, tuple(x[0] for x in one.coefficients(80.0, 0.2, 1, 1)))
    assert not one.converged
    sp = SpeedStepper(model, 6, max_turn=1e9)
    out = sp.step_substeps(80.0, R, 0.2)
    assert sp.converged and sp.last is not None and sp.last[1] == 0.2 / 2
    assert abs(float(model.F(out)[0] - model.F(R)[0])) < 1e-15 * 100  # scale 100


def test_a_zero_field_at_the_start_does_not_count() -> None:
    """Example 1.3 from (1, 0, 0): the field is zero at t = 0 and grows like t, so the
    rate's bound at a stage (about 1 / its time) times the substep never drops below the
    limit; the start is not counted and the step is not split to the last substep."""
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(f("sin(10*t)"), f("t"), f("5"), V=1.0)
    )
    R = np.array([[1.0, 0.0, 0.0]])
    sp = SpeedStepper(model, 3)
    assert sp.zero_field(0.0, R)[0] and not sp.zero_field(0.01, R)[0]
    out = sp.step_substeps(0.0, R, 0.05)
    assert sp.last is not None and sp.last[1] > 0.05 / 1000
    assert sp.evaluations < 3 * 3000
    assert abs(float((out**2).sum()) - 1.0) < 1e-15
    assert np.abs(out - fine(model, R, 0.0, 0.05)).max() < 1e-9
