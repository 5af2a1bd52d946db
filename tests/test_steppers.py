"""Tests of analyzer_lab.lessons.kit.steppers: dense solutions in chunks, closed forms, live steppers."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.lessons.kit.steppers import (
    CHUNK,
    ClosedForm,
    DenseSolution,
    OdeStepper,
    SolutionStepper,
    integrate,
)


def test_dense_solution_in_chunks_reads_the_same_whatever_the_order() -> None:
    rhs = lambda t, y: np.array([y[1], -y[0]])  # noqa: E731
    t = np.linspace(0.0, 2.5 * CHUNK, 51)
    a = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]))
    whole = a(t)
    assert np.max(np.abs(whole[:, 0] - np.cos(t))) < 1e-8
    b = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]))
    pieces = np.array([b(np.array([tt]))[0] for tt in t[::-1]])[::-1]
    assert np.array_equal(whole, pieces)  # one solution, bit for bit


def test_integrate_reports_failure() -> None:
    y, msg = integrate(lambda t, y: np.array([np.nan]), np.array([1.0]), np.linspace(0, 1, 11))
    assert msg and np.isnan(y[0, -1])


def test_dense_solution_stops_where_the_equations_fail() -> None:
    sol = DenseSolution(lambda t, y: np.array([np.nan]) if t > 0.5 else -y, 0.0, np.array([1.0]))
    y = sol(np.array([0.25, 1.0]))
    assert y[0, 0] == pytest.approx(np.exp(-0.25), rel=1e-8) and np.isnan(y[1, 0])
    assert sol.message and 0.0 < sol.stopped_at <= 0.5 + 1e-12


def test_ode_stepper() -> None:
    def make(params):  # type: ignore[no-untyped-def]
        k = float(params["k"])
        return (
            np.array([1.0]),
            (lambda t, y: -k * y),
            (lambda t, y: Frame(t=t, scalars={"y": float(y[0])})),
        )

    st = OdeStepper(make, {"k": 1.0})  # type: ignore[arg-type]
    f = st.advance(1.0)
    assert f.scalars["y"] == pytest.approx(np.exp(-1.0), rel=1e-6)
    st.set_params({"k": 0.0})  # type: ignore[arg-type]
    f = st.advance(1.0)
    assert f.t == pytest.approx(2.0) and f.scalars["y"] == pytest.approx(np.exp(-1.0), rel=1e-6)
    assert st.reset().scalars["y"] == 1.0


def test_stepper_stops_on_non_finite() -> None:
    def make(params):  # type: ignore[no-untyped-def]
        return (
            np.array([1.0]),
            (lambda t, y: np.array([np.nan]) if t > 0.5 else -y),
            (lambda t, y: Frame(t=t, scalars={"y": float(y[0])})),
        )

    st = OdeStepper(make, {})  # type: ignore[arg-type]
    st.advance(0.4)
    f = st.advance(0.4)
    assert f.message and 0.0 < f.t <= 0.5 + 1e-12 and np.isfinite(f.scalars["y"])
    assert st.advance(0.4).t == f.t  # holds at the last good time


def test_solution_stepper_on_a_closed_form() -> None:
    def start(params, t0, y):  # type: ignore[no-untyped-def]
        sol = ClosedForm(lambda t: np.column_stack([params["v"] * t]))
        return sol, lambda t, s: Frame(t=t, scalars={"s": float(s[0])})

    st = SolutionStepper(start, {"v": 2.0})  # type: ignore[arg-type]
    assert st.advance(0.25).scalars["s"] == 0.5
    st.set_params({"v": 4.0})  # type: ignore[arg-type]
    assert st.frame().scalars["s"] == 1.0 and st.reset().t == 0.0


def test_one_time_read_by_bisection_equals_the_whole_grid_at_piece_ends() -> None:
    rhs = lambda t, y: np.array([y[1], -y[0]])  # noqa: E731
    ends = np.arange(0, 6) * CHUNK  # the pieces' shared ends, and times inside them
    t = np.sort(np.concatenate([ends, ends[:-1] + 0.37 * CHUNK]))
    whole = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]))(t)
    one = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]))
    one(np.array([t[-1]]))  # every piece built before the reads below
    assert len(one._pieces) >= 5
    for k, tt in enumerate(t):
        assert np.array_equal(one(np.array([tt]))[0], whole[k])


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_one_time_read_equals_the_grid_inside_the_open_chunk(method: str) -> None:
    """A frame's one-time read (the step found by bisection, DOP853 read at the time
    itself) is the grid's number bit for bit, in the chunk being stepped and in pieces."""
    rhs = lambda t, y: np.array([y[1], -y[0] - 0.1 * y[1] * abs(y[1])])  # noqa: E731
    t = np.concatenate([np.linspace(0.0, 0.3 * CHUNK, 17), [1.0 / 3.0, 1.3 * CHUNK]])
    one = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]), method=method)
    got = []
    for tt in t:
        got.append(one(np.array([tt]))[0])
        if 0.0 < tt < CHUNK:
            assert one._open is not None and not one._pieces  # read inside the open chunk
    steps = one._open.ts if one._open is not None else []
    whole = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]), method=method)(t)
    assert np.array_equal(np.array(got), whole)
    for tt in [*steps[1:4], 0.5 * CHUNK]:  # step ends: the lower step, as OdeSolution picks
        assert np.array_equal(one(np.array([tt])), one(np.array([tt, tt]))[:1])
    assert np.isnan(one(np.array([-1.0]))).all() and np.array_equal(
        one(np.array([0.0]))[0], [1.0, 0.0]
    )
