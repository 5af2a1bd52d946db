"""Gauss-Legendre integrators: tableau order, quadratic invariants, accuracy."""

import numpy as np
import pytest
from analyzer_lab.lessons.kit.integrators import (
    MAX_STAGES,
    apply_propagators,
    gauss_legendre,
    gl_linear,
    gl_propagators,
)


@pytest.mark.parametrize("s", range(1, MAX_STAGES + 1))
def test_tableau_order_conditions(s):
    a, b, c = gauss_legendre(s)
    assert b.sum() == pytest.approx(1.0, abs=1e-15)
    assert np.allclose(a.sum(axis=1), c, rtol=0, atol=1e-15)
    for k in range(1, 2 * s + 1):  # quadrature exact to degree 2s - 1
        assert b @ c ** (k - 1) == pytest.approx(1.0 / k, abs=1e-15)
    for k in range(1, s + 1):  # stage order s: a integrates degree s - 1 exactly
        assert np.allclose(a @ c ** (k - 1), c**k / k, rtol=0, atol=1e-15)
    # b_i a_ij + b_j a_ji = b_i b_j: the condition for keeping quadratic invariants
    ba = b[:, None] * a
    assert np.abs(ba + ba.T - np.outer(b, b)).max() < 1e-15


def test_tableau_stage_counts():
    with pytest.raises(ValueError, match="1 to 6"):
        gauss_legendre(MAX_STAGES + 1)
    with pytest.raises(ValueError):
        gauss_legendre(0)


def rotation_coeffs(omega):
    def coeffs(t):
        A = np.zeros((len(t), 1, 2, 2))
        A[:, 0, 0, 1] = omega(t)
        A[:, 0, 1, 0] = -omega(t)
        return A, np.zeros((len(t), 1, 2))

    return coeffs


@pytest.mark.parametrize(
    "s, order, hs", [(2, 4, (0.1, 0.05)), (3, 6, (0.1, 0.05)), (4, 8, (0.4, 0.2))]
)
def test_linear_convergence_order(s, order, hs):
    omega = lambda t: 1.0 + t  # exact: angle = t + t^2/2
    errs = []
    for h in hs:
        t, r = gl_linear(rotation_coeffs(omega), np.array([[1.0, 0.0]]), 0.0, 2.0, h, s)
        ang = 2.0 + 2.0
        exact = np.array([np.cos(ang), -np.sin(ang)])
        errs.append(np.abs(r[-1, 0] - exact).max())
    rate = np.log2(errs[0] / errs[1])
    assert rate == pytest.approx(order, abs=0.3)


def test_linear_keeps_circle_over_1e5_steps():
    t, r = gl_linear(
        rotation_coeffs(lambda t: 3.0 + np.sin(t)),
        np.array([[1.0, 0.0], [0.0, 2.0]]),
        0.0,
        100.0,
        1e-3,
        3,
    )
    assert len(t) == 100_001
    drift = np.abs((r**2).sum(-1) - (r[0] ** 2).sum(-1)).max()
    assert drift < 1e-13


def test_last_step_shortened():
    t, _ = gl_linear(
        rotation_coeffs(lambda t: 1.0 + 0 * t), np.array([[1.0, 0.0]]), 0.0, 1.05, 0.1, 2
    )
    assert t[-1] == pytest.approx(1.05) and len(t) == 12


def test_propagators_applied_in_two_pieces_equal_one():
    coeffs = rotation_coeffs(lambda t: 3.0 + np.sin(t))
    D, phi = gl_propagators(coeffs, 0.0, 0.01, 100, 3)
    r0 = np.array([[1.0, 0.0]])
    whole, _ = apply_propagators(D, phi, r0)
    first, comp = apply_propagators(D[:40], phi[:40], r0)
    second, _ = apply_propagators(D[40:], phi[40:], first[-1], comp)
    assert np.array_equal(whole[40:], second)


def test_order_12_matches_the_exact_rotation_at_large_steps():
    omega = lambda t: 1.0 + t  # exact: angle = t + t^2/2
    exact = np.array([np.cos(4.0), -np.sin(4.0)])
    errs = {}
    for s, h in ((6, 0.5), (6, 0.25), (3, 0.25)):
        t, r = gl_linear(rotation_coeffs(omega), np.array([[1.0, 0.0]]), 0.0, 2.0, h, s)
        errs[s, h] = np.abs(r[-1, 0] - exact).max()
    assert errs[6, 0.25] < 1e-11 < errs[3, 0.25]
    assert errs[6, 0.5] / errs[6, 0.25] > 2**10  # order 12 (less the round-off)
