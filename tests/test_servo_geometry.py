"""Tests of lessons/servo/geometry.py: signed contour distances and the ellipse fit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.servo.geometry import (
    ellipse_distance,
    fit_centred_ellipse,
    line_distance,
    power_distance,
)


def test_parabola_distance_and_sign() -> None:
    d, fx, fy = power_distance(np.array([0.0, 3.0]), np.array([-0.2, 0.35]), 2, 0.0, 0.0, 20.0)
    assert d[0] == pytest.approx(-0.2, abs=1e-12)  # below the vertex: outside, negative
    assert d[1] < 0 and abs(d[1]) < 0.1
    assert fy[1] == pytest.approx(fx[1] ** 2 / 20.0)


def test_ellipse_and_circle_distances() -> None:
    d, _, _ = ellipse_distance(np.array([15.5, 0.0]), np.array([0.0, 5.0]), 0.0, 0.0, 15.0, 6.0)
    assert d[0] == pytest.approx(-0.5, abs=1e-10) and d[1] == pytest.approx(1.0, abs=1e-10)
    radius = np.array([10.0, 10.0])
    d, _, _ = ellipse_distance(
        np.array([0.0, 9.0]), np.array([10.5, 0.0]), 0.0, 0.0, radius, radius
    )
    assert d == pytest.approx([-0.5, 1.0])


def test_line_distance_sign_follows_5() -> None:
    d, fx, fy = line_distance(np.array([1.0]), np.array([0.0]), 0.0, 0.0, 45.0)
    assert d[0] == pytest.approx(math.sqrt(0.5))
    assert (fx[0], fy[0]) == pytest.approx((0.5, 0.5))


def test_fit_centred_ellipse() -> None:
    th = np.linspace(0, 2 * math.pi, 200)
    a = math.radians(30.0)
    x = 5 * np.cos(th) * math.cos(a) - 2 * np.sin(th) * math.sin(a)
    y = 5 * np.cos(th) * math.sin(a) + 2 * np.sin(th) * math.cos(a)
    major, minor, angle = fit_centred_ellipse(x, y)
    assert (major, minor, angle) == pytest.approx((5.0, 2.0, 30.0))
    s = np.linspace(-1.0, 1.0, 50)  # a hyperbola x^2 - y^2 = 1 is no ellipse
    assert math.isnan(fit_centred_ellipse(np.cosh(s), np.sinh(s))[0])


@pytest.mark.parametrize("n", [2, 3, 4])
def test_one_point_distance_equals_the_array_path(n: int) -> None:
    rng = np.random.default_rng(n)
    xq, yq = rng.normal(size=40), rng.normal(size=40)
    guess = xq + rng.normal(scale=0.1, size=40)
    d, fx, fy = power_distance(xq, yq, n, 0.2, -0.1, 1.5, guess=guess)
    for k in range(40):
        d1, fx1, fy1 = power_distance(xq[k : k + 1], yq[k : k + 1], n, 0.2, -0.1, 1.5, guess[k])
        assert d1.shape == fx1.shape == fy1.shape == (1,)
        assert d1[0] == pytest.approx(d[k], rel=1e-13, abs=1e-14)
        assert fx1[0] == pytest.approx(fx[k], rel=1e-13, abs=1e-14)
        assert fy1[0] == pytest.approx(fy[k], rel=1e-13, abs=1e-14)
