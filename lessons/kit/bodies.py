"""Bodies in the scene: trimesh solids as :class:`MeshItem`, wxyz quaternions, poses.

The chapter 2 lessons draw their mechanisms from these: boxes, cylinders and combined
meshes posed by a position and a unit quaternion ``(w, x, y, z)`` (a rotation matrix, a
turn about Z, or a segment between two points), and scene bounds around sampled points.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import trimesh
from analyzer_lab.lessons.kit.contract import MeshItem

Array = np.ndarray


def quat_zyx(phi: float, beta: float, alpha: float) -> Array:
    """``R = Rz(phi) Ry(beta) Rx(alpha)`` as a unit quaternion ``(w, x, y, z)``."""
    cz, sz = np.cos(phi / 2), np.sin(phi / 2)
    cy, sy = np.cos(beta / 2), np.sin(beta / 2)
    cx, sx = np.cos(alpha / 2), np.sin(alpha / 2)
    return np.array(
        [
            cz * cy * cx + sz * sy * sx,
            cz * cy * sx - sz * sy * cx,
            cz * sy * cx + sz * cy * sx,
            sz * cy * cx - cz * sy * sx,
        ]
    )


def quat_z(angle: float) -> Array:
    """Rotation by ``angle`` about Z as ``(w, x, y, z)``."""
    return np.array([np.cos(angle / 2), 0.0, 0.0, np.sin(angle / 2)])


IDENTITY_Q = np.array([1.0, 0.0, 0.0, 0.0])


def segment_pose(p0: Array, p1: Array) -> tuple[Array, Array]:
    """Pose of a mesh built along +Z and centred at the origin so that it spans p0 -> p1."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    d = p1 - p0
    n = math.sqrt(d @ d)  # np.linalg.norm's own formula, without its checks
    if n < 1e-15:
        return (p0 + p1) / 2, IDENTITY_Q.copy()
    b = d / n
    if b[2] < -1.0 + 1e-12:  # straight down: half a turn about X
        return (p0 + p1) / 2, np.array([0.0, 1.0, 0.0, 0.0])
    q = np.array([1.0 + b[2], -b[1], b[0], 0.0])  # the shortest turn from +Z to b
    return (p0 + p1) / 2, q / math.sqrt(q @ q)


def mesh_item(
    name: str,
    mesh: trimesh.Trimesh,
    color: tuple[int, int, int] = (120, 160, 220),
    opacity: float = 1.0,
) -> MeshItem:
    return MeshItem(
        name=name,
        vertices=np.asarray(mesh.vertices, dtype=float),
        faces=np.asarray(mesh.faces, dtype=np.int64),
        color=color,
        opacity=opacity,
    )


def box(
    name: str,
    extents: Sequence[float],
    color: tuple[int, int, int] = (120, 160, 220),
    center: Sequence[float] = (0, 0, 0),
    opacity: float = 1.0,
) -> MeshItem:
    m = trimesh.creation.box(extents=list(extents))
    m.apply_translation(list(center))
    return mesh_item(name, m, color, opacity)


def cylinder(
    name: str,
    radius: float,
    height: float,
    color: tuple[int, int, int] = (120, 160, 220),
    center: Sequence[float] = (0, 0, 0),
    sections: int = 32,
    opacity: float = 1.0,
) -> MeshItem:
    m = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    m.apply_translation(list(center))
    return mesh_item(name, m, color, opacity)


def combine(
    name: str,
    meshes: Sequence[trimesh.Trimesh],
    color: tuple[int, int, int] = (120, 160, 220),
    opacity: float = 1.0,
) -> MeshItem:
    return mesh_item(name, trimesh.util.concatenate(list(meshes)), color, opacity)


def bounds_of(
    points: Array, pad: float = 0.1
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Axis-aligned bounds of finite points with a margin ``pad`` (relative, at least 0.05)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        pts = np.zeros((1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    m = max(float(np.max(hi - lo)) * pad, 0.05)
    return (tuple(float(v) for v in lo - m), tuple(float(v) for v in hi + m))  # type: ignore[return-value]
