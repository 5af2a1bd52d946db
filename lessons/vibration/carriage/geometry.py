"""Where the carriage of Problem 2.6 is drawn: its box, its springs and its small rotations.

The carriage is a box b (X) x a (Y) x H (Z) whose centre of gravity O lies h above the
centre of stiffness of the air bearing (the origin of the drawing).  Four vertical springs
stand for C_z and the rotational stiffnesses, two horizontal ones for C_x, C_y; the air gap
is drawn exaggerated.  A state ``q = (x, y, z, phi_x, phi_y, phi_z)`` poses the box and
stretches the springs; the sign of phi_y follows (2.40) (see :func:`body_rotvec`).
"""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.vibration.carriage.model import (
    rotvec_to_quaternion,
    small_rotation_matrix,
)


def body_rotvec(q: np.ndarray) -> np.ndarray:
    """Drawn rotation of the carriage.  (2.40)'s "+C_x h x phi_y" means the stiffness
    centre (h below O) moves by x + h phi_y: phi_y is counted clockwise about +Y."""
    return np.array([q[3], -q[4], q[5]])


class CarriageGeometry:
    """The box and the spring attachments of one carriage (lengths in m)."""

    def __init__(self, a: float, b: float, H: float, h: float) -> None:
        self.a, self.b, self.H, self.h = float(a), float(b), float(H), float(h)
        self.cg0 = np.array([0.0, 0.0, self.h])  # stiffness centre at the origin, O h above it
        self.gap = max(0.25 * max(self.a, self.b), 0.02)  # drawn air gap (exaggerated)
        self.floor = self.h - self.H / 2 - self.gap
        sx, sy = 0.4 * self.b, 0.4 * self.a
        feet = np.array([[sx, sy], [-sx, sy], [-sx, -sy], [sx, -sy]])
        self.body_pts = np.vstack(
            [np.column_stack([feet, np.full(4, -self.H / 2)]), [[0, 0, -self.h]] * 2]
        )
        reach = 0.5 * max(self.a, self.b) + self.gap
        self.anchors = np.vstack(
            [np.column_stack([feet, np.full(4, self.floor)]), [[-reach, 0, 0], [0, -reach, 0]]]
        )
        self.corners = np.array(
            [
                [x, y, z]
                for x in (-self.b / 2, self.b / 2)
                for y in (-self.a / 2, self.a / 2)
                for z in (-self.H / 2, self.H / 2)
            ]
        )

    def pose(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Position of O and the wxyz quaternion of the box for the state ``q``."""
        return self.cg0 + q[:3], rotvec_to_quaternion(body_rotvec(q))

    def corner(self, q: np.ndarray) -> np.ndarray:
        """The top corner (+b/2, +a/2, +H/2) of the posed box."""
        return self.cg0 + q[:3] + small_rotation_matrix(body_rotvec(q)) @ self.corners[-1]

    def spring_vectors(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Origins (the anchors) and directions of the six springs for the state ``q``."""
        R = small_rotation_matrix(body_rotvec(q))
        ends = self.cg0 + q[:3] + self.body_pts @ R.T
        return self.anchors.copy(), ends - self.anchors

    def drawn(
        self, q: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
        """:meth:`pose`, :meth:`corner` and :meth:`spring_vectors` of one state at once
        (one rotation matrix)."""
        r = body_rotvec(q)
        R = small_rotation_matrix(r)
        o = self.cg0 + q[:3]
        ends = o + self.body_pts @ R.T
        return (
            o,
            rotvec_to_quaternion(r),
            o + R @ self.corners[-1],
            (
                self.anchors.copy(),
                ends - self.anchors,
            ),
        )

    def max_corner_displacement(self, q: np.ndarray) -> float:
        """Largest displacement of a box corner for the linearized motion q."""
        r = body_rotvec(q)
        return float(np.max(np.linalg.norm(q[:3] + np.cross(r, self.corners), axis=1)))
