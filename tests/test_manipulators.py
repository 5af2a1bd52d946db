"""Lagrangian models of C2.1-C2.6: lessons/mechanics/manipulators/models.py."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.mechanics.manipulators.models import by_hand, model_for

CASES = [
    ("C2.1a", "xyz"),
    ("C2.2a", "xyz"),
    ("C2.3a", "xyz"),
    ("C2.3b", "xyz"),
    ("C2.3c", "xyz"),
    ("C2.4a", "z"),
    ("C2.4b", "yz"),
    ("C2.4c", "xyz"),
    ("C2.5", "xyz"),
]


@pytest.mark.parametrize(("task", "axes"), CASES)
def test_lagranges_method_equals_the_hand_derivation(task: str, axes: str) -> None:
    model = model_for(task, axes)
    hand = by_hand(model)
    assert len(hand) == model.n == len(model.equations)
    assert [sp.simplify(e - h) for e, h in zip(model.equations, hand)] == [0] * model.n


def test_points_for_one_state_and_for_many() -> None:
    model = model_for("C2.3c")
    consts = [1.0, 0.5, 0.01, 0.2, 0.0]  # m1, m2, J, l, g_e
    q = np.array([[0.0, 0.1], [0.0, np.pi / 2]])  # (S, phi) at two samples
    many = model.point("M", q, consts)
    assert many.shape == (2, 3)
    assert np.allclose(many, [[0.2, 0.0, 0.0], [0.1, 0.2, 0.0]])
    assert np.allclose(model.point("M", q[:, 1], consts), many[1])


def test_c26_constraints_and_multipliers() -> None:
    assert [len(model_for(f"C2.6{c}").constraints) for c in "abc"] == [2, 4, 3]
    model = model_for("C2.6c")
    consts = [0.4, 0.3, 0.2, 0.1, 0.1, -0.1, 0.1, 0.15, 1e-9]
    q = np.array([0.0, 0.15, -0.13, -0.075, 0.13, -0.075])
    qd = np.array([-1.0, 0.0, 0.0, 0.0, 0.0, 0.0])  # A moves along the tangent at 1 m/s
    qdd, lam = model.accelerations(0.0, q, qd, consts, [0.0, 0.0, 0.0])
    # 2 lambda R = m v^2 / R: the multiplier holds A on the circle
    assert 2 * abs(lam[0]) * 0.15 == pytest.approx(0.4 * 1.0 / 0.15, rel=1e-9)
    assert qdd[1] == pytest.approx(-1.0 / 0.15, rel=1e-9)
