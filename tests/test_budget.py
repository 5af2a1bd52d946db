"""The work budget of live stepping: every lesson's stepper returns within it (plus one
piece of work), and a run cut by the budget reads the same solution as one that is not."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.budget import clock, spent, work_budget
from analyzer_lab.lessons.kit.steppers import DenseSolution
from scipy.integrate import solve_ivp

BUDGET = 0.01
#: one indivisible piece of work beyond the budget (a block of steps, one solver step)
SLACK = 0.1


def _burn(seconds: float) -> None:
    end = clock() + seconds
    x = 0.0
    while clock() < end:
        x += 1.0


def test_spent_only_within_a_budget_and_after_its_time() -> None:
    assert not spent()
    with work_budget(0.02):
        assert not spent()
        _burn(0.03)
        assert spent()
    assert not spent()


def test_a_wall_clock_limit_counts_waiting_too() -> None:
    import time

    with work_budget(10.0, wall_seconds=0.02):
        assert not spent()
        time.sleep(0.03)  # no CPU spent, the wall time is
        assert spent()
    with work_budget(10.0):
        time.sleep(0.03)  # waiting spends no CPU: no limit reached
        assert not spent()


def test_a_nested_budget_keeps_the_earlier_deadline() -> None:
    with work_budget(0.01):
        with work_budget(10.0):
            _burn(0.02)
            assert spent()


@pytest.mark.parametrize("lesson", all_lessons(), ids=lambda l: l.id)
def test_every_stepper_asked_for_a_huge_dt_returns_within_its_budget(lesson) -> None:
    stepper = lesson.stepper(lesson.resolve())
    stepper.advance(0.01)  # first-use caches (lambdified formulas) are not stepping work
    with np.errstate(all="ignore"):
        for _ in range(3):
            t0, c0 = stepper.t, clock()
            with work_budget(BUDGET):
                stepper.advance(1000.0 * lesson.t_end)
            used = clock() - c0
            assert used < BUDGET + SLACK, f"{lesson.id}: {used:.3f} s CPU for one advance"
            assert stepper.t >= t0


@pytest.mark.parametrize(
    "lesson_id,values",
    [
        ("sphere", {"u1": "5*sin(t)", "h": 1.1e-5}),
        ("sphere-constant-speed", {"u1": "5*sin(t)", "h": 1.1e-5}),
        ("sphere", {"u1": "5*sin(t)", "integrator": "RK45", "rtol": 1e-14, "atol": 1e-16}),
        ("sphere", {"u1": "5*sin(t)", "integrator": "DOP853", "rtol": 1e-14, "atol": 1e-16}),
    ],
)
def test_the_attack_settings_are_cut_by_the_budget(lesson_id: str, values: dict) -> None:
    """A tiny step or a tight tolerance: one call asked for 100 s of lesson time stops
    early, with a finite state, and goes on at the next call."""
    lesson = get_lesson(lesson_id)
    stepper = lesson.stepper(lesson.resolve(values))
    with np.errstate(all="ignore"):
        times = []
        for _ in range(3):
            c0 = clock()
            with work_budget(BUDGET):
                frame = stepper.advance(100.0)
            assert clock() - c0 < BUDGET + SLACK
            times.append(stepper.t)
    assert 0 < times[0] < times[1] < times[2] < 100.0
    assert np.all(np.isfinite(frame.points["point"]))


@pytest.mark.parametrize("values", [{"h": 1e-3}, {"integrator": "RK45", "rtol": 1e-10}])
def test_a_run_cut_by_the_budget_reads_the_same_trajectory(values: dict) -> None:
    lesson = get_lesson("sphere")
    params = lesson.resolve({"u1": "5*sin(t)", **values})
    cut = lesson.stepper(params)
    while cut.t < 3.0:
        with work_budget(0.0005):
            cut.advance(3.0 - cut.t)
    whole = lesson.stepper(params)
    whole.advance(3.0)
    assert cut.t == pytest.approx(3.0, abs=1e-12)
    assert np.allclose(cut.frame().points["point"], whole.frame().points["point"], atol=1e-12)


def test_a_dense_solution_stepped_in_budget_pieces_is_solve_ivps_solution() -> None:
    """The chunk is stepped as solve_ivp steps it: the same steps, the same numbers."""

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return np.array([y[1], -np.sin(y[0]) + 0.3 * np.cos(2 * t)])

    sol = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]), rtol=1e-12, atol=1e-14, chunk=2.0)
    reached = 0.0
    while reached < 1.5:
        with work_budget(0.0):
            reached = sol.reach(1.5)
    ref = solve_ivp(
        rhs, (0.0, 2.0), [1.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True
    )
    t = np.linspace(0.0, 1.5, 7)
    assert np.array_equal(sol(t), ref.sol(t).T)
    assert np.array_equal(sol(np.array([2.0])), ref.sol(np.array([2.0])).T)


def test_a_dense_solution_stops_where_the_equations_are_not_finite() -> None:
    sol = DenseSolution(lambda t, y: np.array([np.sqrt(1.0 - t)]), 0.0, np.array([0.0]))
    with np.errstate(invalid="ignore"), work_budget(0.05):
        reached = sol.reach(3.0)
        out = sol(np.array([0.5, 2.0]))
    assert "non-finite" in sol.message and 0.9 < sol.stopped_at <= 1.0
    assert out[0, 0] == pytest.approx(2 / 3 * (1 - 0.5**1.5), rel=1e-7) and np.isnan(out[1, 0])
    assert reached == 3.0  # a stopped solution reports its end; the stepper holds there


def test_a_dense_solution_whose_solver_fails_keeps_the_steps_before() -> None:
    sol = DenseSolution(lambda t, y: np.array([1.0 / (1.0 - t)]), 0.0, np.array([0.0]))
    for _ in range(1000):  # budget pieces until the solver gives up at t = 1
        if sol.message:
            break
        with work_budget(0.01):
            sol.reach(3.0)
    assert sol.message.startswith("integration stopped at t = 1")
    assert sol(np.array([0.5]))[0, 0] == pytest.approx(np.log(2.0), rel=1e-7)
