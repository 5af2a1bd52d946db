"""Workpieces and task paths for the five-axis laser machine (LSP-2000 article).

A task (the article's "задание", section on the simulation model) is a sequence of tool
poses: points on the machined surface with the beam along the surface normal; the
working point must follow the polyline through the points.  Here a workpiece is a
surface seen from the tool side, parametrised by horizontal offsets ``(u, v)`` from its
centre (the article's final test part is a paraboloid dish; a spherical dome is added
for comparison), and a path is a straight line or a closed circle in ``(u, v)``.
Coordinates are the machine's left-handed frame (Z towards the material, i.e. down).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from analyzer_lab.lessons.laser5.kinematics import TWO_PI, unit


@dataclass(frozen=True)
class Workpiece:
    """A surface seen from the tool side: the height ``z(u, v)`` over the disc of offsets
    ``u^2 + v^2 <= radius^2`` around ``centre`` (+z into the material).

    ``point_normal(u, v)`` gives surface points and unit normals pointing *into the
    material* (the beam direction), ``n ~ (-z_u, -z_v, 1)``; ``mesh()`` a trimesh for
    display.  A workpiece implements :meth:`height` (z and its two slopes) and has a
    ``radius``.
    """

    centre: tuple[float, float] = (1500.0, 1500.0)

    def height(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
        """``z``, ``dz/du``, ``dz/dv`` at the offsets ``(u, v)``."""
        raise NotImplementedError

    def point_normal(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = np.asarray(u, dtype=float)
        v = np.asarray(v, dtype=float)
        z, z_u, z_v = self.height(u, v)
        p = np.stack([self.centre[0] + u, self.centre[1] + v, z], axis=-1)
        return p, unit(np.stack([-z_u, -z_v, np.ones_like(z)], axis=-1))

    def mesh(self, rings: int = 24, sectors: int = 64) -> trimesh.Trimesh:
        """A mesh over the disc (polar grid)."""
        r = np.linspace(0.0, self.radius, rings + 1)[1:]
        a = np.linspace(0.0, TWO_PI, sectors, endpoint=False)
        rr, aa = np.meshgrid(r, a, indexing="ij")
        u = np.concatenate([[0.0], (rr * np.cos(aa)).ravel()])
        v = np.concatenate([[0.0], (rr * np.sin(aa)).ravel()])
        pts, _ = self.point_normal(u, v)
        faces = [[0, 1 + j, 1 + (j + 1) % sectors] for j in range(sectors)]
        for i in range(rings - 1):
            for j in range(sectors):
                a0 = 1 + i * sectors + j
                a1 = 1 + i * sectors + (j + 1) % sectors
                faces += [[a0, a0 + sectors, a1 + sectors], [a0, a1 + sectors, a1]]
        return trimesh.Trimesh(vertices=pts, faces=np.asarray(faces), process=False)


@dataclass(frozen=True)
class Paraboloid(Workpiece):
    """The article's final test part: dish ``z = z0 - r^2/(4F)`` (+z into the material).

    Inward normal ``n ~ (u/2F, v/2F, 1)``; F and the dimensions are assumed (the article
    gives only "a part with a parabolic surface", Conclusions).
    """

    F: float = 500.0
    z0: float = 900.0
    radius: float = 1000.0

    def height(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
        return self.z0 - (u * u + v * v) / (4 * self.F), -u / (2 * self.F), -v / (2 * self.F)


@dataclass(frozen=True)
class SphereCap(Workpiece):
    """A spherical dome (the ball is the material): top at ``z_top``, radius ``R``."""

    R: float = 1000.0
    z_top: float = 400.0
    radius: float = 700.0

    def height(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
        h = np.sqrt(self.R**2 - u * u - v * v)
        return self.z_top + self.R - h, u / h, v / h


# ---------------------------------------------------------------- a task


@dataclass
class Task:
    """Task points along a path on the surface, the beam along the normal at each."""

    uv: np.ndarray  # (N+1, 2)
    points: np.ndarray  # (N+1, 3)
    normals: np.ndarray  # (N+1, 3)
    workpiece: Workpiece

    @property
    def segments(self) -> int:
        return len(self.points) - 1

    @property
    def length(self) -> float:
        """The polyline's length [mm]."""
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())

    def normal_at(self, seg: int, lam: np.ndarray) -> np.ndarray:
        """Surface normal below the chord point at parameter ``lam`` of segment ``seg``."""
        lam = np.clip(np.asarray(lam, dtype=float), 0.0, 1.0)
        uv = (1 - lam)[..., None] * self.uv[seg] + lam[..., None] * self.uv[seg + 1]
        return self.workpiece.point_normal(uv[..., 0], uv[..., 1])[1]


def make_task(
    workpiece: Workpiece,
    path: str,
    segments: int,
    start: tuple[float, float] = (0.0, 0.0),
    end: tuple[float, float] = (0.0, 0.0),
    radius: float = 300.0,
) -> Task:
    """A straight line in (u, v) from ``start`` to ``end`` or a closed circle of ``radius``."""
    if path == "circle":
        phi = np.linspace(0.0, TWO_PI, segments + 1)
        uv = np.stack([radius * np.sin(phi), radius * np.cos(phi)], axis=-1)
        uv[-1] = uv[0]
    else:
        s = np.linspace(0.0, 1.0, segments + 1)[:, None]
        uv = (1 - s) * np.asarray(start, float) + s * np.asarray(end, float)
    p, n = workpiece.point_normal(uv[:, 0], uv[:, 1])
    return Task(uv=uv, points=p, normals=n, workpiece=workpiece)
