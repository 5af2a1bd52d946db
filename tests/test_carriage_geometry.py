"""The drawn carriage: lessons/vibration/carriage/geometry.py."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.vibration.carriage.geometry import CarriageGeometry, body_rotvec

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


def test_drawn_is_pose_corner_and_springs() -> None:
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = rng.normal(scale=1e-3, size=6)
        pos, quat, corner, (anchors, springs) = GEOM.drawn(q)
        want_pos, want_quat = GEOM.pose(q)
        assert pos == pytest.approx(want_pos, abs=1e-15)
        assert quat == pytest.approx(want_quat, abs=1e-15)
        assert corner == pytest.approx(GEOM.corner(q), abs=1e-15)
        want_anchors, want_springs = GEOM.spring_vectors(q)
        assert np.array_equal(anchors, want_anchors)
        assert springs == pytest.approx(want_springs, abs=1e-15)
