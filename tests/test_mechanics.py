"""Tests of lessons.core.mechanics: Lagrange wrapper, §2.2 solver, poses."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import ReferenceFrame, dynamicsymbols

from lessons.core.contract import Frame
from lessons.core.mechanics import (
    ConstrainedSystem,
    LagrangeModel,
    OdeStepper,
    ProgramStepper,
    bounds_of,
    box,
    formula_derivatives,
    integrate,
    numerical_second_derivative,
    quat_wxyz,
    quat_z,
    segment_pose,
)

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


def _cartesian_pendulum(rheonomic: bool = False) -> ConstrainedSystem:
    x, y, xd, yd = sp.symbols("x y x_d y_d", real=True)
    m, g = sp.symbols("m g", positive=True)
    t = T_
    L = 1 + sp.Rational(1, 5) * sp.sin(2 * t) if rheonomic else sp.Symbol("L", positive=True)
    params = [m, g] if rheonomic else [m, g, L]
    return ConstrainedSystem.build(
        [x, y],
        [xd, yd],
        t,
        sp.diag(m, m),
        sp.Matrix([0, -m * g]),
        params,
        f_hol=[x**2 + y**2 - L**2],
    )


def test_constrained_forms() -> None:
    cs = _cartesian_pendulum()
    x, y = cs.q
    xd, yd = cs.qd
    assert cs.H.shape == (1, 2)
    assert sp.simplify(cs.H - sp.Matrix([[2 * x, 2 * y]])) == sp.zeros(1, 2)
    assert sp.simplify(cs.Phi[0] - 2 * (xd**2 + yd**2)) == 0
    assert cs.psi[0] == 0


def test_rheonomic_psi_phi() -> None:
    """Digest S3b: psi = -2 L L', Phi = 2(x'^2 + y'^2) - 2(L'^2 + L L'')."""
    cs = _cartesian_pendulum(rheonomic=True)
    t = T_
    L = 1 + sp.Rational(1, 5) * sp.sin(2 * t)
    xd, yd = cs.qd
    assert sp.simplify(cs.psi[0] + 2 * L * L.diff(t)) == 0
    assert (
        sp.simplify(cs.Phi[0] - (2 * (xd**2 + yd**2) - 2 * (L.diff(t) ** 2 + L * L.diff(t, 2))))
        == 0
    )


def test_constrained_multiplier_and_projection() -> None:
    cs = _cartesian_pendulum()
    p = np.array([1.5, 9.81, 2.0])
    q = np.array([0.0, -2.0])
    qdd, lam = cs.solve(0.0, q, np.zeros(2), p, np.zeros(0))
    assert np.allclose(qdd, 0.0, atol=1e-14)
    assert lam[0] == pytest.approx(-1.5 * 9.81 / (2 * 2.0), rel=1e-12)  # H^T lambda = (0, m g)
    q0, qd0 = cs.consistent_initial(
        0.0, np.array([1.0, -1.0]), np.array([1.0, 1.0]), p, np.zeros(0)
    )
    f, c = cs.residuals(0.0, q0, qd0, p, np.zeros(0))
    assert abs(f[0]) < 1e-12 and abs(c[0]) < 1e-12


def test_baumgarte_reduces_drift() -> None:
    cs = _cartesian_pendulum()
    p = np.array([1.0, 9.81, 1.0])
    y0 = np.array([np.sin(1.0), -np.cos(1.0), 0.0, 0.0])
    drift = []
    for a in (0.0, 5.0):
        sol = solve_ivp(
            cs.rhs(p, lambda t, q, qd: np.zeros(0), a, a), (0, 10), y0, rtol=1e-5, atol=1e-5
        )
        drift.append(float(np.max(np.abs(sol.y[0] ** 2 + sol.y[1] ** 2 - 1.0))))
    assert drift[1] < drift[0] / 10


def test_formula_derivatives_and_differences() -> None:
    t = sp.Symbol("t", real=True)
    ev = formula_derivatives([sp.sin(2 * t), t**3], t)
    q, qd, qdd = ev(np.array([0.5, 1.0]))
    assert q.shape == (2, 2)
    assert qd[1, 1] == pytest.approx(3.0) and qdd[0, 0] == pytest.approx(-4 * np.sin(1.0))
    tt = np.linspace(0, 1, 1001)
    assert np.max(np.abs(numerical_second_derivative(tt, np.cos(tt)) + np.sin(tt))) < 1e-5


def test_integrate_reports_failure() -> None:
    y, msg = integrate(lambda t, y: np.array([np.nan]), np.array([1.0]), np.linspace(0, 1, 11))
    assert msg and np.isnan(y[0, -1])


def test_poses() -> None:
    assert np.allclose(quat_wxyz(np.eye(3)), [1, 0, 0, 0])
    a = 0.7
    R = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    assert np.allclose(quat_wxyz(R), quat_z(a))
    pos, qt = segment_pose(np.zeros(3), np.array([1.0, 0.0, 0.0]))
    assert np.allclose(pos, [0.5, 0, 0])
    w, x, y, z = qt
    Rm = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    assert np.allclose(Rm @ [0, 0, 1], [1, 0, 0])
    b = box("b", (1, 2, 3))
    assert np.allclose(b.vertices.max(axis=0) - b.vertices.min(axis=0), [1, 2, 3])
    lo, hi = bounds_of(np.array([[0, 0, 0], [1, np.nan, 1]]))
    assert all(np.isfinite(lo)) and all(np.isfinite(hi))


def test_steppers() -> None:
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
    ps = ProgramStepper(lambda params: lambda t: Frame(t=t, scalars={"s": t * 2}), {})  # type: ignore[arg-type]
    assert ps.advance(0.25).scalars["s"] == 0.5 and ps.reset().t == 0.0


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
    assert f.message and f.t == pytest.approx(0.4)
