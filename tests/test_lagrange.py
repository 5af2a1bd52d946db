"""Tests of analyzer_lab.lessons.mechanics.lagrange.model: the Lagrange model, motion laws, the inverse problem."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.mechanics.lagrange.model import (
    LagrangeModel,
    formula_derivatives,
    numerical_second_derivative,
    solve_small,
)
from sympy.physics.mechanics import ReferenceFrame, dynamicsymbols

T_ = dynamicsymbols._t


@pytest.fixture(scope="module")
def pendulum_angle() -> LagrangeModel:
    th = dynamicsymbols("theta")
    m, L, g = sp.symbols("m L g", positive=True)
    Mz = sp.Symbol("M_z", real=True)
    N = ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [th, N.z])
    B.set_ang_vel(N, th.diff(T_) * N.z)
    T = m * L**2 * th.diff(T_) ** 2 / 2
    U = -m * g * L * sp.cos(th)
    return LagrangeModel.build([th], T, U, T_, [m, L, g], [Mz], forcelist=[(B, Mz * N.z)], frame=N)


def test_lagrange_model_symbolic(pendulum_angle: LagrangeModel) -> None:
    m, L, g = pendulum_angle.params
    th = pendulum_angle.q[0]
    expected = m * L**2 * th.diff(T_, 2) + m * g * L * sp.sin(th) - pendulum_angle.inputs[0]
    assert sp.simplify(pendulum_angle.eom()[0] - expected) == 0
    eq = pendulum_angle.equations()[0]
    assert sp.simplify(eq.rhs - pendulum_angle.inputs[0]) == 0


def test_lagrange_model_numeric(pendulum_angle: LagrangeModel) -> None:
    p = np.array([2.0, 0.5, 9.81])
    qdd = pendulum_angle.accelerations(np.array([0.3]), np.array([1.0]), 0.0, p, np.array([0.7]))
    assert qdd[0] == pytest.approx((0.7 - 2 * 9.81 * 0.5 * np.sin(0.3)) / (2 * 0.25), rel=1e-12)
    # inverse at one instant recovers the input exactly
    u = pendulum_angle.solve_inputs(
        np.array([0.3]), np.array([1.0]), qdd, 0.0, p, np.array([123.0]), [0]
    )
    assert u[0] == pytest.approx(0.7, abs=1e-12)
    assert pendulum_angle.G(np.array([0.3]), np.array([1.0]), 0.0, p, np.zeros(1))[
        0, 0
    ] == pytest.approx(1.0)


def test_formula_derivatives_and_differences() -> None:
    t = sp.Symbol("t", real=True)
    ev = formula_derivatives([sp.sin(2 * t), t**3], t)
    q, qd, qdd = ev(np.array([0.5, 1.0]))
    assert q.shape == (2, 2)
    assert qd[1, 1] == pytest.approx(3.0) and qdd[0, 0] == pytest.approx(-4 * np.sin(1.0))
    tt = np.linspace(0, 1, 1001)
    assert np.max(np.abs(numerical_second_derivative(tt, np.cos(tt)) + np.sin(tt))) < 1e-5


def test_one_time_equals_the_array_and_keeps_numpy_arithmetic() -> None:
    from analyzer_lab.lessons.kit.formula import parse_formula, t_symbol
    from analyzer_lab.lessons.mechanics.lagrange.model import formula_derivatives

    ev = formula_derivatives([parse_formula("log(t)").expr, parse_formula("t**3").expr], t_symbol)
    grid = ev(np.array([0.5, 2.0]))
    for k, tt in enumerate((0.5, 2.0)):
        one = ev(np.array([tt]))
        for a, b in zip(one, grid):
            assert a.shape == (2, 1) and np.array_equal(a[:, 0], b[:, k])
    q, qd, qdd = ev(np.array([0.0]))  # 1/t at 0: inf as in an array, not an exception
    assert np.isinf(qd[0, 0]) and qd[1, 0] == 0.0


def test_small_solve_on_plain_numbers_equals_lapack() -> None:
    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 4):
        for _ in range(200):
            M, b = rng.normal(size=(n, n)), rng.normal(size=n)
            want = np.linalg.solve(M, b)
            got = solve_small(M.tolist(), b.tolist())
            assert np.allclose(got, want, rtol=1e-10, atol=1e-10 * np.abs(want).max())
    # a pivot of zero in the first column is swapped away; a singular matrix raises
    assert solve_small([[0.0, 2.0], [4.0, 1.0]], [2.0, 9.0]) == [2.0, 1.0]
    with pytest.raises(np.linalg.LinAlgError):
        solve_small([[1.0, 2.0], [2.0, 4.0]], [1.0, 1.0])
    with pytest.raises(np.linalg.LinAlgError):
        solve_small([[0.0]], [1.0])


def test_acceleration_list_equals_accelerations(pendulum_angle: LagrangeModel) -> None:
    p = np.array([2.0, 0.5, 9.81])
    for th, om, mz in ((0.3, 1.0, 0.7), (-2.0, 0.2, -5.0), (1e3, -7.0, 0.0)):
        q, qd, u = np.array([th]), np.array([om]), np.array([mz])
        want = pendulum_angle.accelerations(q, qd, 0.0, p, u)
        got = pendulum_angle.acceleration_list(q, qd, 0.0, p, [mz])
        assert np.allclose(got, want, rtol=1e-14, atol=0.0)
