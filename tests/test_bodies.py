"""Tests of analyzer_lab.lessons.kit.bodies: quaternions, segment poses, meshes and bounds."""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.kit.bodies import bounds_of, box, quat_z, quat_zyx, segment_pose
from analyzer_lab.lessons.mechanics.table.model import rotation
from scipy.spatial.transform import Rotation


def test_poses() -> None:
    assert np.allclose(quat_zyx(0.0, 0.0, 0.0), [1, 0, 0, 0])
    assert np.allclose(quat_zyx(0.7, 0.0, 0.0), quat_z(0.7))
    x, y, z, w = Rotation.from_matrix(rotation(0.3, -0.2, 0.9)).as_quat()
    assert np.allclose(quat_zyx(0.9, -0.2, 0.3), [w, x, y, z])
    pos, qt = segment_pose(np.zeros(3), np.array([1.0, 0.0, 0.0]))
    assert np.allclose(pos, [0.5, 0, 0])
    w, x, y, z = qt
    Rm = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    assert np.allclose(Rm @ [0, 0, 1], [1, 0, 0])
    b = box("b", (1, 2, 3))
    assert np.allclose(b.vertices.max(axis=0) - b.vertices.min(axis=0), [1, 2, 3])
    lo, hi = bounds_of(np.array([[0, 0, 0], [1, np.nan, 1]]))
    assert all(np.isfinite(lo)) and all(np.isfinite(hi))
