"""Tests of analyzer_lab.lessons.mechanics.lagrange.constrained: the §2.2 algorithm, (2.17)-(2.34)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.mechanics.lagrange.constrained import ConstrainedSystem
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import dynamicsymbols

T_ = dynamicsymbols._t


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
