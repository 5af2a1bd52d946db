"""The drawn carriage: lessons/core/carriage_geometry.py."""

from __future__ import annotations

import numpy as np
import pytest

from lessons.core.carriage_geometry import CarriageGeometry, body_rotvec

GEOM = CarriageGeometry(a=0.4, b=0.5, H=0.06, h=0.02)


def test_at_rest_the_box_sits_h_above_the_stiffness_centre() -> None:
    pos, quat = GEOM.pose(np.zeros(6))
    assert pos == pytest.approx([0.0, 0.0, 0.02])
    assert quat == pytest.approx([1.0, 0.0, 0.0, 0.0])
    assert GEOM.corner(np.zeros(6)) == pytest.approx([0.25, 0.2, 0.05])
    origins, dirs = GEOM.spring_vectors(np.zeros(6))
    assert origins.shape == dirs.shape == (6, 3)
    assert np.all(dirs[:4, 2] > 0)  # the four feet stand on the stator


def test_phi_y_turns_clockwise_about_y() -> None:
    """(2.40): x + h phi_y is the motion of the stiffness centre, h below O."""
    q = np.array([0.0, 0.0, 0.0, 0.0, 0.01, 0.0])
    assert body_rotvec(q) == pytest.approx([0.0, -0.01, 0.0])
    origins, dirs = GEOM.spring_vectors(q)
    bottom = origins[4] + dirs[4]  # the X spring ends at the stiffness centre
    assert bottom[0] == pytest.approx(GEOM.h * 0.01, rel=1e-4)


def test_max_corner_displacement_of_a_translation_and_a_turn() -> None:
    assert GEOM.max_corner_displacement(np.array([0.003, 0, 0, 0, 0, 0])) == pytest.approx(0.003)
    # a turn phi_z moves the far corners by phi_z * half the diagonal
    turn = GEOM.max_corner_displacement(np.array([0, 0, 0, 0, 0, 0.01]))
    assert turn == pytest.approx(0.01 * np.hypot(0.25, 0.2))
