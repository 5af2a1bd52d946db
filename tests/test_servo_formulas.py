"""Tests of lessons/servo/formulas.py: the article's closed forms with numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.servo.formulas import (
    circle_axes_29_30,
    curve_19,
    delta_parabola_13,
    locus_18,
    parabola_vertex_17,
    parabola_vertex_19,
)


def test_formula_13_numbers() -> None:
    assert delta_parabola_13(5, 20, 0.01, 0.001) == pytest.approx(-0.2375)
    assert delta_parabola_13(5, 20, 0.01, 0.00005) == pytest.approx(0.0)  # T1^2 = 2 T2^2


def test_19_is_the_output_of_the_horizontal_parabola() -> None:
    """Eliminating t from the steady outputs x1 = x - T1 x' + (T1^2 - T2^2) x'',
    y1 = y - gamma T1 y' of x = omega^2 p t^2/4, y = omega p t/2 gives (19)."""
    t, w, p, T1, T2sq, g, y1 = sp.symbols("t omega p T_1 T_2sq gamma y_1")
    x = w**2 * p * t**2 / 4
    x1 = x - T1 * sp.diff(x, t) + (T1**2 - T2sq) * sp.diff(x, t, 2)
    ty = sp.solve(sp.Eq(y1, w * p * t / 2 - g * T1 * w * p / 2), t)[0]
    assert sp.simplify(x1.subs(t, ty) - curve_19(y1, w, p, T1, T2sq, g)) == 0


def test_19_fig4b_numbers() -> None:
    omega, p, T1, T2sq = 5.0, 20.0, 0.01, 0.001
    assert parabola_vertex_19(omega, p, T1, T2sq, 0.5) == pytest.approx((-0.2375, 0.25))
    assert parabola_vertex_19(omega, p, T1, T2sq, 2.0) == pytest.approx((-0.2375, -0.5))
    assert curve_19(0.0, omega, p, T1, T2sq, 0.5) == pytest.approx(-0.234375)
    assert curve_19(0.0, omega, p, T1, T2sq, 2.0) == pytest.approx(-0.225)
    y = np.linspace(-20, 20, 9)
    assert np.allclose(curve_19(y, omega, p, T1, T2sq, 1.0), y**2 / p - 0.2375)


def test_18_corrected_holds_the_vertices_and_the_printed_does_not() -> None:
    xv, yv = parabola_vertex_17(5.0, 20.0, 0.01, 0.001, 0.5)
    assert (xv, yv) == pytest.approx((-0.25, -0.121875))
    assert locus_18(xv, 5.0, 20.0, 0.01, 0.001) == pytest.approx(yv)
    assert locus_18(xv, 5.0, 20.0, 0.01, 0.001, printed=True) == pytest.approx(-0.23325)


def test_axes_printed_vs_corrected_differ_by_cos() -> None:
    _, a, b = circle_axes_29_30(9.14566, 10.36061, math.radians(31.622))
    _, ap, bp = circle_axes_29_30(9.14566, 10.36061, math.radians(31.622), printed=True)
    assert (a, b) == pytest.approx((12.10648, 6.66471), abs=2e-4)
    assert (ap, bp) == pytest.approx((13.11954, 7.22241), abs=2e-4)
