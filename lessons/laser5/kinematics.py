"""Five-axis laser machine LSP-2000 (LSP-2000 article): the kinematics.

Machine coordinates ``q = (X, Y, Z, C, B)`` (mm, mm, mm, rad, rad); tool pose: working
point ``p = (x, y, z)`` and unit beam vector ``n``.  The world frame is the article's
*left-handed* triple: X and Y horizontal, Z towards the workpiece (down).  Equations (1),
(2) of the article are lost and (3) survives only as tokens; the forms here are rebuilt
from the machine description and those tokens (marked reconstructed in the lesson):

* (1a) ``n = (sin B sin theta, sin B cos theta, cos B)``, ``theta = k_C1 C + k_C2``;
* (1b) ``p = (X + k_X + R_C sin theta + R_B n_x, Y + k_Y + R_C cos theta + R_B n_y,
  Z + k_Z + R_B n_z)``;
* (2) ``B = arccos n_z``, ``C`` from ``atan2(n_x, n_y)``; a vertical beam keeps ``C`` (the
  rule's "first variant": infinitely many X, Y, C give the same pose);
* (3) ``X = x - R_B n_x - R_C sin theta - k_X`` (and Y, Z alike).

A task's poses become CNC commands with :func:`translate_poses`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

Limits = Literal["original", "improved"]
TWO_PI = 2.0 * math.pi
VERTICAL_EPS = 1e-12  # |(n_x, n_y)| below this: vertical beam, rule (2) first variant


class LimitError(ValueError):
    """A tool pose outside the rotary limits of the chosen variant."""


def unit(v: np.ndarray) -> np.ndarray:
    """Vectors divided by their length along the last axis."""
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle [rad] between unit vectors (robust near 0 and pi)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    dot = np.sum(a * b, axis=-1)
    return np.arctan2(cross, dot)


# ---------------------------------------------------------------- the machine


@dataclass(frozen=True)
class Machine5:
    """LSP-2000 kinematics, reconstructed (1a), (1b), (2), (3) with the given limits.

    ``limits="original"``: C in [0, 2 pi), B in [0, pi/2] (the machine as described);
    ``limits="improved"``: B in (-pi/4, pi/4), C unrestricted; the branch nearest the
    previous C is taken (the variant the article found best, Fig. 5c).
    """

    R_C: float = 200.0
    R_B: float = 300.0
    k_C1: float = 1.0
    k_C2: float = 0.0
    k_X: float = 0.0
    k_Y: float = 0.0
    k_Z: float = 0.0
    limits: Limits = "original"

    def theta(self, C: np.ndarray | float) -> np.ndarray:
        """Lever azimuth ``theta = k_C1 C + k_C2`` (from the tokens of (3))."""
        return self.k_C1 * np.asarray(C, dtype=float) + self.k_C2

    def beam(self, C: np.ndarray | float, B: np.ndarray | float) -> np.ndarray:
        """(1a): unit beam vector for rotary positions C, B (shape (..., 3))."""
        th = self.theta(C)
        B = np.asarray(B, dtype=float)
        return np.stack([np.sin(B) * np.sin(th), np.sin(B) * np.cos(th), np.cos(B)], axis=-1)

    def pivots(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """C pivot, B pivot, working point and beam for axis positions ``q`` (..., 5)."""
        q = np.asarray(q, dtype=float)
        th = self.theta(q[..., 3])
        n = self.beam(q[..., 3], q[..., 4])
        c_pivot = np.stack(
            [q[..., 0] + self.k_X, q[..., 1] + self.k_Y, q[..., 2] + self.k_Z], axis=-1
        )
        lever = np.stack([np.sin(th), np.cos(th), np.zeros_like(th)], axis=-1)
        b_pivot = c_pivot + self.R_C * lever
        return c_pivot, b_pivot, b_pivot + self.R_B * n, n

    def forward(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(1a), (1b): working point ``p`` and beam ``n`` for ``q = (X, Y, Z, C, B)``."""
        _, _, p, n = self.pivots(q)
        return p, n

    def point_velocity(self, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """Derivative of (1b): the working point's velocity for axis rates ``dq`` at ``q``."""
        q = np.asarray(q, dtype=float)
        dq = np.asarray(dq, dtype=float)
        th, B = self.theta(q[..., 3]), q[..., 4]
        dth, dB = self.k_C1 * dq[..., 3], dq[..., 4]
        sB, cB, st, ct = np.sin(B), np.cos(B), np.sin(th), np.cos(th)
        lever = self.R_C + self.R_B * sB
        return np.stack(
            [
                dq[..., 0] + lever * ct * dth + self.R_B * cB * st * dB,
                dq[..., 1] - lever * st * dth + self.R_B * cB * ct * dB,
                dq[..., 2] - self.R_B * sB * dB,
            ],
            axis=-1,
        )

    def rotary(self, n: np.ndarray, C_ref: float | None = None) -> tuple[float, float]:
        """Rule (2): rotary positions (C, B) for beam ``n``; ``C_ref`` resolves ambiguity.

        Vertical beam: ``C = C_ref`` ("first variant", 0 without a reference; the original
        limits fold it into [0, 2 pi)).  Improved limits: of the two branches
        ``(theta, B)`` and ``(theta + pi, -B)``, shifted by whole turns, the one nearest
        ``C_ref``; without a reference the original solution (B >= 0, C in [0, 2 pi)).
        Raises :class:`LimitError` when the tilt exceeds the B limit.
        """
        nx, ny, nz = (float(c) for c in unit(n))
        tilt = math.atan2(math.hypot(nx, ny), nz)
        period = TWO_PI / abs(self.k_C1)
        if self.limits == "original":
            if tilt > math.pi / 2 + 1e-12:
                raise LimitError(f"beam tilt {math.degrees(tilt):.2f} deg exceeds the B limit pi/2")
            if math.hypot(nx, ny) < VERTICAL_EPS:
                return float(np.mod(C_ref or 0.0, period)), 0.0
            return self._folded_C(nx, ny, period), tilt
        if tilt >= math.pi / 4:
            raise LimitError(
                f"beam tilt {math.degrees(tilt):.2f} deg is outside the B limit (-pi/4, pi/4)"
            )
        if math.hypot(nx, ny) < VERTICAL_EPS:
            return float(C_ref or 0.0), 0.0
        if C_ref is None:
            return self._folded_C(nx, ny, period), tilt
        best: tuple[float, float, float] | None = None
        for th, B in ((math.atan2(nx, ny), tilt), (math.atan2(nx, ny) + math.pi, -tilt)):
            C = (th - self.k_C2) / self.k_C1
            C += period * round((C_ref - C) / period)
            d = abs(C - C_ref)
            if best is None or d < best[0] - 1e-12:
                best = (d, C, B)
        assert best is not None
        return best[1], best[2]

    def _folded_C(self, nx: float, ny: float, period: float) -> float:
        """Rule (2) for a tilted beam: C from the azimuth, folded into one period."""
        C = ((math.atan2(nx, ny) - self.k_C2) / self.k_C1) % period
        return 0.0 if C >= period else C

    def inverse(self, p: np.ndarray, n: np.ndarray, C_ref: float | None = None) -> np.ndarray:
        """Rule (2) then (3): axis positions ``(X, Y, Z, C, B)`` for the pose ``(p, n)``."""
        C, B = self.rotary(n, C_ref)
        return self.axes_for(np.asarray(p, dtype=float), np.float64(C), np.float64(B))

    def axes_for(self, p: np.ndarray, C: np.ndarray, B: np.ndarray) -> np.ndarray:
        """(3): the axes ``(X, Y, Z, C, B)`` that put the working point at ``p`` for C, B."""
        th = self.theta(C)
        nb = self.beam(C, B)
        X = p[..., 0] - self.R_B * nb[..., 0] - self.R_C * np.sin(th) - self.k_X
        Y = p[..., 1] - self.R_B * nb[..., 1] - self.R_C * np.cos(th) - self.k_Y
        Z = p[..., 2] - self.R_B * nb[..., 2] - self.k_Z
        ones = np.ones_like(X)
        return np.stack(
            [X, Y, Z, np.asarray(C, float) * ones, np.asarray(B, float) * ones], axis=-1
        )

    def random_poses(self, rng: np.random.Generator, count: int) -> np.ndarray:
        """Random axis positions strictly inside the limits (for round-trip checks)."""
        X = rng.uniform(0.0, 3000.0, count)
        Y = rng.uniform(0.0, 3000.0, count)
        Z = rng.uniform(0.0, 600.0, count)
        if self.limits == "original":
            C = rng.uniform(0.0, TWO_PI, count) / abs(self.k_C1)
            B = rng.uniform(1e-3, math.pi / 2, count)
        else:
            C = rng.uniform(-4 * math.pi, 4 * math.pi, count)
            B = rng.uniform(-math.pi / 4 + 1e-3, math.pi / 4 - 1e-3, count)
        return np.stack([X, Y, Z, C, B], axis=-1)


# ---------------------------------------------------------------- translating a task


def vertical(n: np.ndarray) -> bool:
    """Whether the beam is vertical (rule (2)'s first variant applies)."""
    n = unit(n)
    return bool(math.hypot(float(n[0]), float(n[1])) < VERTICAL_EPS)


def translate_poses(machine: Machine5, points: np.ndarray, normals: np.ndarray) -> list[np.ndarray]:
    """Poses -> CNC commands in order, rule (2)/(3), each with the previous C as reference.

    A vertical beam leaves C free (first variant of rule (2)); it takes the C of the
    next non-vertical pose, so the lever does not swing on the way out of the vertical.
    """
    qs: list[np.ndarray] = []
    for i, (p, n) in enumerate(zip(points, normals)):
        ref = None if not qs else float(qs[-1][3])
        if vertical(n):
            for n_next in normals[i + 1 :]:
                if not vertical(n_next):
                    ref = machine.rotary(n_next, ref)[0]
                    break
        qs.append(machine.inverse(p, n, ref))
    return qs
