"""Tests of lessons.planar_3axis: Problem 2.4, eqs (2.12)-(2.16)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from lessons.planar_3axis import LESSON, Planar3Axis, planar3_kinematics, planar3_phi


def test_planar3_kinematics_and_equations() -> None:
    xB, yB = planar3_kinematics(0.1, -0.2, 0.3, 0.5, np)
    a, b, c = planar3_phi(0.1, -0.2, float(xB), float(yB), 0.5)
    assert a == pytest.approx(0.3) and b == pytest.approx(0.3) and c == pytest.approx(0.3)
    # full range: atan2 recovers phi = 2.5 where arcsin cannot
    xB, yB = planar3_kinematics(0.0, 0.0, 2.5, 0.5, np)
    assert planar3_phi(0.0, 0.0, float(xB), float(yB), 0.5)[2] == pytest.approx(2.5)
    lesson = Planar3Axis()
    m = lesson.model(lesson.resolve())
    M = m.mass_matrix
    mA, mB, mAB, J, AB = m.params
    phi = m.q[2]
    assert sp.simplify(M[0, 0] - (mA + mB + mAB)) == 0
    assert sp.simplify(M[0, 2] - AB * mB * sp.sin(phi)) == 0
    assert sp.simplify(M[2, 2] - (J + AB**2 * mB)) == 0


def test_module_b_series() -> None:
    r = LESSON.run("inverse-program", t_end=1.0)
    xB, yB = planar3_kinematics(r.series["x_A"], r.series["y_A"], r.series["phi"], 0.5, np)
    assert np.allclose(r.series["x_B"], xB) and np.allclose(r.series["y_B"], yB)
