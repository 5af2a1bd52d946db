"""Arc length (1.12) and its inverse (1.13), including the end-point singularity of (1.4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.curves.arclength import ArcLengthCurve, CubicHermite


def vec(*fs):
    def f(p):
        p = np.atleast_1d(p)
        with np.errstate(all="ignore"):
            return np.stack([np.broadcast_to(g(p), p.shape) for g in fs], axis=1)

    return f


H12 = (
    vec(np.sin, np.cos, lambda p: p),
    vec(np.cos, lambda p: -np.sin(p), lambda p: np.ones_like(p)),
    0.0,
    math.pi,
)
H14 = (
    vec(lambda p: np.sqrt(1 - p**2), lambda p: p, np.arccos),
    vec(
        lambda p: -p / np.sqrt(1 - p**2),
        lambda p: np.ones_like(p),
        lambda p: -1 / np.sqrt(1 - p**2),
    ),
    -1.0,
    1.0,
)


@pytest.mark.parametrize("spec", [H12, H14])
def test_helix_length(spec):
    assert ArcLengthCurve(*spec).S_l == pytest.approx(math.pi * math.sqrt(2), abs=1e-11)


def test_s_of_phi_for_1_4_and_inverse():
    c = ArcLengthCurve(*H14)
    phi = np.linspace(-1, 1, 301)
    exact = math.sqrt(2) * (np.arcsin(phi) + math.pi / 2)
    assert np.max(np.abs(c.s_of_phi(phi) - exact)) < 1e-11
    s = np.linspace(0, c.S_l, 501)
    assert np.max(np.abs(c.s_of_theta(c.theta_of_s(s)) - s)) < 1e-12
    assert np.max(np.abs(c.phi_of_s(exact[1:-1]) - phi[1:-1])) < 1e-9


def test_tangent_at_singular_ends_is_finite():
    c = ArcLengthCurve(*H14)
    tan = c.unit_tangent_theta(np.array([0.0, np.pi]))
    assert np.all(np.isfinite(tan))
    assert tan[0] == pytest.approx([1 / math.sqrt(2), 0, -1 / math.sqrt(2)], abs=1e-6)


def test_non_finite_derivative_is_refused():
    r = vec(np.sqrt, lambda p: p, lambda p: 0 * p)
    dr = vec(lambda p: 0.5 / np.sqrt(p), lambda p: np.ones_like(p), lambda p: 0 * p)
    with pytest.raises(ValueError, match="not finite"):
        ArcLengthCurve(r, dr, -1.0, 1.0)


def test_bad_range_is_refused():
    with pytest.raises(ValueError):
        ArcLengthCurve(*H12[:2], 1.0, 1.0)


def test_cubic_hermite_is_exact_for_cubics_and_at_nodes():
    x = np.array([0.0, 0.5, 2.0, 3.0])
    y = np.stack([x**3 - x, 2 * x], axis=1)
    dy = np.stack([3 * x**2 - 1, 2 + 0 * x], axis=1)
    h = CubicHermite(x, y, dy)
    q = np.linspace(0, 3, 31)
    assert np.max(np.abs(h(q) - np.stack([q**3 - q, 2 * q], axis=1))) < 1e-12
    assert np.array_equal(h(x), y)
    assert h(np.array([5.0])).tolist() == [[24.0, 6.0]]  # clamped to the last node


@pytest.mark.parametrize("spec", [H12, H14])
def test_tabulated_omega_matches_the_newton_inverse(spec):
    c = ArcLengthCurve(*spec)
    s = np.linspace(0, c.S_l, 20001)
    assert np.max(np.abs(c.omega(s) - c.phi_of_s(s))) < 1e-12
    assert c.omega(np.array([0.0, c.S_l])).tolist() == [c.phi0, c.phi1]


def test_tabulated_omega_through_a_cusp():
    r = vec(lambda p: p**3, lambda p: p**2, lambda p: 0 * p)
    dr = vec(lambda p: 3 * p**2, lambda p: 2 * p, lambda p: 0 * p)
    c = ArcLengthCurve(r, dr, -1.0, 1.0)
    s = np.linspace(0, c.S_l, 20001)
    assert np.all(np.isfinite(c.omega.coef))
    assert np.max(np.linalg.norm(c.r(c.omega(s)) - c.point_of_s(s), axis=1)) < 1e-8
