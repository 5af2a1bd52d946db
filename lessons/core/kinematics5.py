"""Five-axis laser machine LSP-2000 (article 003): kinematics, workpieces, controllers.

Machine coordinates ``q = (X, Y, Z, C, B)`` (mm, mm, mm, rad, rad); tool pose: working
point ``p = (x, y, z)`` and unit beam vector ``n``.  The world frame is the article's
*left-handed* triple: X and Y horizontal, Z towards the workpiece (down).

Equations (1), (2) of the article are lost and (3) survives only as tokens; the forms
here are the digest's reconstruction (marked (1a), (1b), (2), (3) RECON):

* (1a) ``n = (sin B sin theta, sin B cos theta, cos B)``, ``theta = k_C1 C + k_C2``;
* (1b) ``p = (X + k_X + R_C sin theta + R_B n_x, Y + k_Y + R_C cos theta + R_B n_y,
  Z + k_Z + R_B n_z)``;
* (2) ``B = arccos n_z``, ``C`` from ``atan2(n_x, n_y)``; a vertical beam keeps ``C`` (the
  rule's "first variant": infinitely many X, Y, C give the same pose);
* (3) ``X = x - R_B n_x - R_C sin theta - k_X`` (and Y, Z alike).

Controllers along one task segment (chord ``p_a -> p_b`` with normals ``n_a, n_b``):
linear interpolation in axis space; method 1 (fixed mean normal, no rotation); method 2
(recursive bisection, mean normal at the split); nonlinear interpolation (4): the point
linear in Cartesian space, C and B linear in the same parameter ``t``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal, Protocol

import numpy as np
import trimesh

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

    def in_limits(self, q: np.ndarray, tol: float = 1e-12) -> bool:
        """Whether ``q`` respects the rotary limits of the variant."""
        C, B = float(q[3]), float(q[4])
        if self.limits == "original":
            return -tol <= C < TWO_PI + tol and -tol <= B <= math.pi / 2 + tol
        return -math.pi / 4 < B < math.pi / 4

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
            C = ((math.atan2(nx, ny) - self.k_C2) / self.k_C1) % period
            return (0.0 if C >= period else C), tilt
        if tilt >= math.pi / 4:
            raise LimitError(
                f"beam tilt {math.degrees(tilt):.2f} deg is outside the B limit (-pi/4, pi/4)"
            )
        if math.hypot(nx, ny) < VERTICAL_EPS:
            return float(C_ref or 0.0), 0.0
        if C_ref is None:
            C = ((math.atan2(nx, ny) - self.k_C2) / self.k_C1) % period
            return (0.0 if C >= period else C), tilt
        best: tuple[float, float, float] | None = None
        for th, B in ((math.atan2(nx, ny), tilt), (math.atan2(nx, ny) + math.pi, -tilt)):
            C = (th - self.k_C2) / self.k_C1
            C += period * round((C_ref - C) / period)
            d = abs(C - C_ref)
            if best is None or d < best[0] - 1e-12:
                best = (d, C, B)
        assert best is not None
        return best[1], best[2]

    def inverse(self, p: np.ndarray, n: np.ndarray, C_ref: float | None = None) -> np.ndarray:
        """Rule (2) then (3): axis positions ``(X, Y, Z, C, B)`` for the pose ``(p, n)``."""
        C, B = self.rotary(n, C_ref)
        th = float(self.theta(C))
        nb = self.beam(C, B)
        p = np.asarray(p, dtype=float)
        X = p[0] - self.R_B * nb[0] - self.R_C * math.sin(th) - self.k_X
        Y = p[1] - self.R_B * nb[1] - self.R_C * math.cos(th) - self.k_Y
        Z = p[2] - self.R_B * nb[2] - self.k_Z
        return np.array([X, Y, Z, C, B])

    def axes_for(self, p: np.ndarray, C: np.ndarray, B: np.ndarray) -> np.ndarray:
        """(3) vectorised: linear axes that put the working point at ``p`` for given C, B."""
        th = self.theta(C)
        nb = self.beam(C, B)
        X = p[..., 0] - self.R_B * nb[..., 0] - self.R_C * np.sin(th) - self.k_X
        Y = p[..., 1] - self.R_B * nb[..., 1] - self.R_C * np.cos(th) - self.k_Y
        Z = p[..., 2] - self.R_B * nb[..., 2] - self.k_Z
        return np.stack(
            [
                X,
                Y,
                Z,
                np.asarray(C, float) * np.ones_like(X),
                np.asarray(B, float) * np.ones_like(X),
            ],
            axis=-1,
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


# ---------------------------------------------------------------- workpieces


class Workpiece(Protocol):
    """A surface seen from the tool side, parametrised by horizontal offsets (u, v).

    ``point_normal(u, v)`` gives surface points and unit normals pointing *into the
    material* (the beam direction); ``mesh()`` a trimesh for display; ``radius`` the
    largest offset ``sqrt(u^2 + v^2)`` covered.  Any quadric fits through
    :class:`QuadricCap`.
    """

    name: str
    radius: float

    def point_normal(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...

    def mesh(self) -> trimesh.Trimesh: ...


def disc_mesh(
    point_normal: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]],
    radius: float,
    rings: int = 24,
    sectors: int = 64,
) -> trimesh.Trimesh:
    """A height-field mesh over the disc ``u^2 + v^2 <= radius^2`` (polar grid)."""
    r = np.linspace(0.0, radius, rings + 1)[1:]
    a = np.linspace(0.0, TWO_PI, sectors, endpoint=False)
    rr, aa = np.meshgrid(r, a, indexing="ij")
    u = np.concatenate([[0.0], (rr * np.cos(aa)).ravel()])
    v = np.concatenate([[0.0], (rr * np.sin(aa)).ravel()])
    pts, _ = point_normal(u, v)
    faces = []
    for j in range(sectors):
        faces.append([0, 1 + j, 1 + (j + 1) % sectors])
    for i in range(rings - 1):
        for j in range(sectors):
            a0 = 1 + i * sectors + j
            a1 = 1 + i * sectors + (j + 1) % sectors
            b0 = a0 + sectors
            b1 = a1 + sectors
            faces += [[a0, b0, b1], [a0, b1, a1]]
    return trimesh.Trimesh(vertices=pts, faces=np.asarray(faces), process=False)


@dataclass(frozen=True)
class Paraboloid:
    """The article's final test part: dish ``z = z0 - r^2/(4F)`` (+z into the material).

    Inward normal ``n ~ (u/2F, v/2F, 1)`` (digest II.10; the dimensions are assumed).
    """

    F: float = 500.0
    centre: tuple[float, float] = (1500.0, 1500.0)
    z0: float = 900.0
    radius: float = 1000.0
    name: str = "paraboloid"

    def point_normal(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = np.asarray(u, dtype=float)
        v = np.asarray(v, dtype=float)
        p = np.stack(
            [self.centre[0] + u, self.centre[1] + v, self.z0 - (u * u + v * v) / (4 * self.F)],
            axis=-1,
        )
        n = unit(np.stack([u / (2 * self.F), v / (2 * self.F), np.ones_like(u)], axis=-1))
        return p, n

    def mesh(self) -> trimesh.Trimesh:
        return disc_mesh(self.point_normal, self.radius)


@dataclass(frozen=True)
class SphereCap:
    """A spherical dome (the ball is the material): top at ``z_top``, radius ``R``."""

    R: float = 1000.0
    centre: tuple[float, float] = (1500.0, 1500.0)
    z_top: float = 400.0
    radius: float = 700.0
    name: str = "sphere"

    def point_normal(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = np.asarray(u, dtype=float)
        v = np.asarray(v, dtype=float)
        h = np.sqrt(np.maximum(self.R**2 - u * u - v * v, 0.0))
        p = np.stack([self.centre[0] + u, self.centre[1] + v, self.z_top + self.R - h], axis=-1)
        n = np.stack([-u, -v, h], axis=-1) / self.R
        return p, unit(n)

    def mesh(self) -> trimesh.Trimesh:
        return disc_mesh(self.point_normal, self.radius)


@dataclass(frozen=True)
class QuadricCap:
    """Any quadric ``F(x, y, z) = 0`` as a workpiece: the root nearest the tool (smallest z).

    ``F`` and ``half_gradient`` take (..., 3) points (as a quadric class would provide);
    along a vertical line ``F`` is quadratic in z, so three evaluations give its roots.
    """

    F: Callable[[np.ndarray], np.ndarray]
    half_gradient: Callable[[np.ndarray], np.ndarray]
    centre: tuple[float, float] = (1500.0, 1500.0)
    radius: float = 500.0
    name: str = "quadric"

    def point_normal(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = np.atleast_1d(np.asarray(u, dtype=float))
        v = np.atleast_1d(np.asarray(v, dtype=float))
        x = self.centre[0] + u
        y = self.centre[1] + v

        def f(z: float) -> np.ndarray:
            return np.asarray(self.F(np.stack([x, y, np.full_like(x, z)], axis=-1)), dtype=float)

        f0, fp, fm = f(0.0), f(1.0), f(-1.0)
        a = (fp + fm) / 2 - f0
        b = (fp - fm) / 2
        c = f0
        with np.errstate(invalid="ignore", divide="ignore"):
            disc = np.sqrt(np.maximum(b * b - 4 * a * c, 0.0))
            r1 = (-b - disc) / (2 * a)
            r2 = (-b + disc) / (2 * a)
            z = np.where(np.abs(a) < 1e-14, -c / b, np.minimum(r1, r2))
        p = np.stack([x, y, z], axis=-1)
        g = np.asarray(self.half_gradient(p), dtype=float)
        g = np.where(g[..., 2:3] < 0, -g, g)
        return p, unit(g)

    def mesh(self) -> trimesh.Trimesh:
        return disc_mesh(self.point_normal, self.radius)


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


# ---------------------------------------------------------------- moves


@dataclass
class Move:
    """One CNC move ``tau in [0, 1]`` within task segment ``seg``.

    ``kind``: ``linear`` (all axes proportional), ``nonlinear`` ((4): point on the
    chord ``p0 -> p1``, C and B linear in ``t = tau``).  ``laser`` is off for pure
    re-orientations.  ``lead`` names the leading rotary coordinate (nonlinear moves).
    """

    kind: str
    q0: np.ndarray
    q1: np.ndarray
    p0: np.ndarray
    p1: np.ndarray
    seg: int
    depth: int = 0
    lead: str = ""
    laser: bool = True

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.p1 - self.p0))

    def axes(self, machine: Machine5, tau: np.ndarray) -> np.ndarray:
        """Axis positions at ``tau`` (shape (..., 5))."""
        tau = np.asarray(tau, dtype=float)
        if self.kind == "linear":
            return self.q0 + tau[..., None] * (self.q1 - self.q0)
        point = self.p0 + tau[..., None] * (self.p1 - self.p0)
        C = self.q0[3] + tau * (self.q1[3] - self.q0[3])
        B = self.q0[4] + tau * (self.q1[4] - self.q0[4])
        return machine.axes_for(point, C, B)


def linear_move(
    q0: np.ndarray, q1: np.ndarray, p0: np.ndarray, p1: np.ndarray, seg: int = 0, depth: int = 0
) -> Move:
    return Move(
        "linear",
        np.asarray(q0, float),
        np.asarray(q1, float),
        np.asarray(p0, float),
        np.asarray(p1, float),
        seg,
        depth,
    )


def nonlinear_move(
    q0: np.ndarray, q1: np.ndarray, p0: np.ndarray, p1: np.ndarray, seg: int = 0
) -> Move:
    """Nonlinear interpolation (4); the leading coordinate is the rotary axis that moves more."""
    dC, dB = abs(q1[3] - q0[3]), abs(q1[4] - q0[4])
    lead = "" if max(dC, dB) == 0.0 else ("C" if dC >= dB else "B")
    kind = "nonlinear" if lead else "linear"
    return Move(
        kind,
        np.asarray(q0, float),
        np.asarray(q1, float),
        np.asarray(p0, float),
        np.asarray(p1, float),
        seg,
        0,
        lead,
    )


def segment_distance(
    points: np.ndarray, a: np.ndarray, b: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Distance of points from the segment ``a -> b`` and the chord parameter (unclamped)."""
    d = b - a
    L2 = float(d @ d)
    lam = ((points - a) @ d) / L2 if L2 > 0 else np.zeros(points.shape[:-1])
    foot = a + np.clip(lam, 0.0, 1.0)[..., None] * d
    return np.linalg.norm(points - foot, axis=-1), lam


def move_deviation(
    machine: Machine5,
    move: Move,
    a: np.ndarray | None = None,
    b: np.ndarray | None = None,
    samples: int = 33,
) -> float:
    """Largest distance of the working point from the segment ``a -> b`` (default: the move's chord)."""
    a = move.p0 if a is None else a
    b = move.p1 if b is None else b

    def dev(tau: np.ndarray) -> np.ndarray:
        p, _ = machine.forward(move.axes(machine, tau))
        return segment_distance(p, a, b)[0]

    tau = np.linspace(0.0, 1.0, samples)
    d = dev(tau)
    best = float(d.max())
    for _ in range(
        2
    ):  # zoom twice around the largest sample, then a parabola through the top three
        k = int(np.argmax(d))
        lo, hi = tau[max(k - 1, 0)], tau[min(k + 1, len(tau) - 1)]
        tau = np.linspace(lo, hi, samples)
        d = dev(tau)
        best = max(best, float(d.max()))
    k = int(np.argmax(d))
    if 0 < k < len(tau) - 1:
        y0, y1, y2 = d[k - 1], d[k], d[k + 1]
        den = y0 - 2 * y1 + y2
        if den < 0:
            s = 0.5 * (y0 - y2) / den
            best = max(best, float(dev(np.array([tau[k] + s * (tau[1] - tau[0])]))[0]))
    return best


# ---------------------------------------------------------------- controllers


def mean_normal(na: np.ndarray, nb: np.ndarray) -> np.ndarray:
    """The mean of two normals, normalized (method 2's normal at a split)."""
    return unit(np.asarray(na, float) + np.asarray(nb, float))


@dataclass
class Bisection:
    """Result of method 2 on one segment: pieces (linear moves) and how it ended."""

    moves: list[Move]
    converged: bool
    max_depth: int
    worst_mm: float
    deviations: list[float] = field(default_factory=list)


def bisect_segment(
    machine: Machine5,
    pa: np.ndarray,
    na: np.ndarray,
    qa: np.ndarray,
    pb: np.ndarray,
    nb: np.ndarray,
    tol: float,
    max_depth: int = 30,
    seg: int = 0,
    max_pieces: int = 4096,
) -> Bisection:
    """Method 2: split the segment until every linear piece deviates by at most ``tol`` [mm].

    The split point is the chord midpoint, its normal the normalized mean of the piece's
    end normals.  The refined task is translated in order, each pose by rule (2)/(3)
    with the previous pose's C as reference (what the CNC translator does), so the end
    pose of a split segment may lie on another branch than the unsplit one.
    """
    moves: list[Move] = []
    devs: list[float] = []
    state = {"converged": True}

    def rec(
        pa: np.ndarray, na: np.ndarray, qa: np.ndarray, pb: np.ndarray, nb: np.ndarray, depth: int
    ) -> np.ndarray:
        qb = machine.inverse(pb, nb, C_ref=float(qa[3]))
        mv = linear_move(qa, qb, pa, pb, seg, depth)
        dev = move_deviation(machine, mv)
        if dev <= tol or depth >= max_depth or len(moves) >= max_pieces:
            if dev > tol:
                state["converged"] = False
            moves.append(mv)
            devs.append(dev)
            return qb
        pm, nm = 0.5 * (pa + pb), mean_normal(na, nb)
        qm = rec(pa, na, qa, pm, nm, depth + 1)
        return rec(pm, nm, qm, pb, nb, depth + 1)

    rec(np.asarray(pa, float), unit(na), np.asarray(qa, float), np.asarray(pb, float), unit(nb), 0)
    return Bisection(moves, state["converged"], max(m.depth for m in moves), max(devs), devs)


def bisect_uniform(
    machine: Machine5,
    pa: np.ndarray,
    na: np.ndarray,
    qa: np.ndarray,
    pb: np.ndarray,
    nb: np.ndarray,
    depth: int,
) -> list[Move]:
    """Method 2 split ``depth`` times everywhere (2^depth pieces), translated in order."""
    nodes = [(np.asarray(pa, float), unit(na)), (np.asarray(pb, float), unit(nb))]
    for _ in range(depth):
        new = [nodes[0]]
        for (p0, n0), (p1, n1) in zip(nodes[:-1], nodes[1:]):
            new += [(0.5 * (p0 + p1), mean_normal(n0, n1)), (p1, n1)]
        nodes = new
    qs = [np.asarray(qa, float)]
    for p, n in nodes[1:]:
        qs.append(machine.inverse(p, n, C_ref=float(qs[-1][3])))
    return [
        linear_move(q0, q1, p0, p1, 0, depth)
        for (p0, _), (p1, _), q0, q1 in zip(nodes[:-1], nodes[1:], qs[:-1], qs[1:])
    ]


def nonlinear_submoves(machine: Machine5, move: Move, count: int) -> list[Move]:
    """The nonlinear move executed by a linear CNC as ``count`` linear sub-moves."""
    tau = np.linspace(0.0, 1.0, count + 1)
    qs = move.axes(machine, tau)
    ps = move.p0 + tau[:, None] * (move.p1 - move.p0)
    return [
        Move("linear", qs[k], qs[k + 1], ps[k], ps[k + 1], move.seg, 0, move.lead)
        for k in range(count)
    ]


def fixed_normal_moves(
    machine: Machine5,
    pa: np.ndarray,
    na: np.ndarray,
    pb: np.ndarray,
    nb: np.ndarray,
    C_ref: float,
    seg: int = 0,
) -> Move:
    """Method 1: the whole segment with the beam along the mean normal, no rotation."""
    nm = mean_normal(na, nb)
    q0 = machine.inverse(pa, nm, C_ref)
    q1 = machine.inverse(pb, nm, float(q0[3]))
    return linear_move(q0, q1, pa, pb, seg)


# ---------------------------------------------------------------- segment analysis


def point_speed_ratio(machine: Machine5, move: Move, samples: int = 2001) -> float:
    """Max/min working-point speed along a move at a constant parameter rate."""
    tau = np.linspace(0.0, 1.0, samples)
    p, _ = machine.forward(move.axes(machine, tau))
    sp = np.linalg.norm(np.diff(p, axis=0), axis=-1)
    return float(sp.max() / sp.min()) if sp.min() > 0 else math.inf


def axis_path_length(
    machine: Machine5, moves: Sequence[Move], components: slice = slice(0, 3), samples: int = 513
) -> float:
    """Path length travelled by the linear axes (default X, Y, Z) over the moves [mm]."""
    total = 0.0
    for mv in moves:
        q = mv.axes(machine, np.linspace(0.0, 1.0, samples))[:, components]
        total += float(np.linalg.norm(np.diff(q, axis=0), axis=-1).sum())
    return total


def moves_backwards(
    machine: Machine5, moves: Sequence[Move], a: np.ndarray, b: np.ndarray, samples: int = 257
) -> bool:
    """Whether the working point's progress along ``a -> b`` ever decreases."""
    lams = []
    for mv in moves:
        p, _ = machine.forward(mv.axes(machine, np.linspace(0.0, 1.0, samples)))
        lams.append(segment_distance(p, a, b)[1])
    lam = np.concatenate(lams)
    return bool(np.any(np.diff(lam) < -1e-9))


def off_normal_max(
    machine: Machine5, task: Task, moves: Sequence[Move], samples: int = 257
) -> float:
    """Largest angle [rad] between the beam and the surface normal below the point."""
    worst = 0.0
    for mv in moves:
        a, b = task.points[mv.seg], task.points[mv.seg + 1]
        p, n = machine.forward(mv.axes(machine, np.linspace(0.0, 1.0, samples)))
        _, lam = segment_distance(p, a, b)
        worst = max(worst, float(angle_between(n, task.normal_at(mv.seg, lam)).max()))
    return worst


def sagitta_estimate(machine: Machine5, qa: np.ndarray, qb: np.ndarray) -> float:
    """Sagitta of the arc swept by linear C, B motion: ``(R_C + R_B sin B) dC^2/8 + R_B dB^2/8``."""
    B = 0.5 * (qa[4] + qb[4])
    dC = abs(machine.k_C1) * (qb[3] - qa[3])
    dB = qb[4] - qa[4]
    return float(
        (machine.R_C + machine.R_B * abs(math.sin(B))) * dC**2 / 8 + machine.R_B * dB**2 / 8
    )
