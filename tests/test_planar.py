"""The plane conic analyzer in closed form and the argument integral Θ(t)."""

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.plane.conic import ArgumentIntegral, PlanarModel, PlanarTrack
from analyzer_lab.lessons.kit.formula import parse_formula
from scipy.integrate import solve_ivp


@pytest.mark.parametrize(
    ("coeffs", "gain"),
    [
        ({"a11": 1.0, "a22": 1.0}, "sin(t)"),  # ellipse (D > 0)
        ({"a11": 0.025, "a12": 0.5, "a22": 10.0, "a13": -7.0, "a23": -5.0}, "1"),  # parabola
        ({"a11": 1.0, "a22": -2.0, "a12": 0.3, "a13": 1.0}, "t"),  # hyperbola (D < 0)
    ],
)
def test_closed_form_matches_a_tight_numerical_solution(coeffs, gain):
    r0 = np.array([[1.0, 0.5]])
    model = PlanarModel.of(coeffs, parse_formula(gain)).through(r0)
    t = np.linspace(0.0, 2.0, 9)
    got = PlanarTrack(model, r0).at(t).r[:, 0]
    ref = solve_ivp(
        lambda s, y: model.velocity(s, y.reshape(1, 2)).ravel(),
        (0.0, 2.0),
        r0.ravel(),
        t_eval=t,
        rtol=1e-12,
        atol=1e-12,
    ).y.T
    assert np.max(np.abs(got - ref)) < 1e-8 * max(1.0, np.max(np.abs(ref)))
    assert np.max(np.abs(model.F(got[:, None]))) < 1e-12 * max(1.0, np.max(ref**2))


def test_argument_integral_is_the_same_for_any_caller():
    theta = ArgumentIntegral(parse_formula("sin(t)"))
    t = np.linspace(0.0, 7.0, 50)
    assert theta(t) == pytest.approx(1 - np.cos(t), abs=1e-14)
    fresh = ArgumentIntegral(parse_formula("sin(t)"))
    assert [float(fresh(np.array([s]))[0]) for s in t] == list(theta(t))
    assert ArgumentIntegral(2.0)(np.array([3.0]))[0] == 6.0
