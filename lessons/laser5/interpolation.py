"""Interpolation along one task segment of the five-axis laser machine (LSP-2000 article).

A task segment runs from pose ``(p_a, n_a)`` to ``(p_b, n_b)``; the CNC executes it as
moves with a parameter ``tau in [0, 1]``.  The controllers of the article:

* linear interpolation (the LSP-2000 CNC, Fig. 3): all axes proportional in ``tau``;
  the rotary terms of (1b) sweep arcs, so the point bows off the chord;
* method 1: no rotation within a segment, the beam along the mean normal;
* method 2 (Fig. 4): recursive bisection, the mean normal at every split;
* nonlinear interpolation (4): the point linear on the chord, C and B linear in the
  same parameter ``t = tau`` (the leading axis sets ``t``), X, Y, Z from (3).

The measures used by the lesson's claims (deviation from the chord, speed ratio, axis
travel, backward motion, beam error, the sagitta estimate) are here too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from analyzer_lab.lessons.laser5.kinematics import Machine5, angle_between, unit
from analyzer_lab.lessons.laser5.task import Task


def interpolate_axes(
    machine: Machine5,
    q0: np.ndarray,
    q1: np.ndarray,
    p0: np.ndarray,
    p1: np.ndarray,
    nonlinear: np.ndarray | bool,
    tau: np.ndarray,
) -> np.ndarray:
    """Axis positions at ``tau`` of linear or nonlinear (4) moves (arrays broadcast).

    Both kinds move C and B linearly in ``tau``; a nonlinear move takes X, Y, Z from (3)
    for the point ``(1 - tau) p0 + tau p1`` on the chord.
    """
    tau = np.asarray(tau, dtype=float)[..., None]
    q = q0 + tau * (q1 - q0)
    if not np.any(nonlinear):
        return q
    on_chord = machine.axes_for(p0 + tau * (p1 - p0), q[..., 3], q[..., 4])
    return np.where(np.asarray(nonlinear)[..., None], on_chord, q)


def point_rate(
    machine: Machine5,
    q: np.ndarray,
    q0: np.ndarray,
    q1: np.ndarray,
    p0: np.ndarray,
    p1: np.ndarray,
    nonlinear: np.ndarray | bool,
) -> np.ndarray:
    """``dp/dtau`` of the working point at axis positions ``q`` of a move: the derivative of
    (1b) along a linear move, the chord ``p1 - p0`` along a nonlinear one."""
    along_axes = machine.point_velocity(q, q1 - q0)
    return np.where(np.asarray(nonlinear)[..., None], p1 - p0, along_axes)


@dataclass
class Move:
    """One CNC move ``tau in [0, 1]`` within task segment ``seg``.

    ``kind``: ``linear`` (all axes proportional) or ``nonlinear`` ((4)); ``lead`` names
    the leading rotary axis of a nonlinear move; ``depth`` the bisection level.
    """

    kind: str
    q0: np.ndarray
    q1: np.ndarray
    p0: np.ndarray
    p1: np.ndarray
    seg: int = 0
    depth: int = 0
    lead: str = ""

    def __post_init__(self) -> None:
        for name in ("q0", "q1", "p0", "p1"):
            setattr(self, name, np.asarray(getattr(self, name), dtype=float))

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.p1 - self.p0))

    def axes(self, machine: Machine5, tau: np.ndarray) -> np.ndarray:
        """Axis positions at ``tau`` (shape (..., 5))."""
        nonlinear = self.kind == "nonlinear"
        return interpolate_axes(machine, self.q0, self.q1, self.p0, self.p1, nonlinear, tau)


def nonlinear_move(
    q0: np.ndarray, q1: np.ndarray, p0: np.ndarray, p1: np.ndarray, seg: int = 0
) -> Move:
    """Nonlinear interpolation (4); the leading coordinate is the rotary axis that moves more
    (neither moving: proportional motion, a straight line)."""
    dC, dB = abs(q1[3] - q0[3]), abs(q1[4] - q0[4])
    lead = "" if max(dC, dB) == 0.0 else ("C" if dC >= dB else "B")
    return Move("nonlinear" if lead else "linear", q0, q1, p0, p1, seg, lead=lead)


def segment_distance(
    points: np.ndarray, a: np.ndarray, b: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Distance of points from the segment ``a -> b`` and the chord parameter (unclamped);
    ``a``, ``b`` broadcast against ``points``."""
    d = b - a
    L2 = np.sum(d * d, axis=-1)
    lam = np.sum((points - a) * d, axis=-1) / np.where(L2 > 0, L2, 1.0)
    foot = a + np.clip(lam, 0.0, 1.0)[..., None] * d
    return np.linalg.norm(points - foot, axis=-1), lam


def move_deviation(
    machine: Machine5,
    move: Move,
    a: np.ndarray | None = None,
    b: np.ndarray | None = None,
    samples: int = 33,
) -> float:
    """Largest distance [mm] of the working point from the segment ``a -> b`` (default: the
    move's chord): a grid, two zooms around its largest sample, then a parabola's top."""
    a = move.p0 if a is None else a
    b = move.p1 if b is None else b

    def dev(tau: np.ndarray) -> np.ndarray:
        p, _ = machine.forward(move.axes(machine, tau))
        return segment_distance(p, a, b)[0]

    tau = np.linspace(0.0, 1.0, samples)
    d = dev(tau)
    best = float(d.max())
    for _ in range(2):
        k = int(np.argmax(d))
        tau = np.linspace(tau[max(k - 1, 0)], tau[min(k + 1, len(tau) - 1)], samples)
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


Ends = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]  # (p_a, n_a, p_b, n_b)


def bisect_segment(
    machine: Machine5,
    ends: Ends,
    qa: np.ndarray,
    tol: float,
    max_depth: int = 30,
    seg: int = 0,
    max_pieces: int = 4096,
) -> Bisection:
    """Method 2: split the segment ``ends`` (start point and normal, end point and normal),
    starting from the axes ``qa``, until every linear piece deviates by at most ``tol`` [mm].

    The split point is the chord midpoint, its normal the normalized mean of the piece's
    end normals.  The refined task is translated in order, each pose by rule (2)/(3)
    with the previous pose's C as reference (what the CNC translator does), so the end
    pose of a split segment may lie on another branch than the unsplit one.
    """
    moves: list[Move] = []
    devs: list[float] = []

    def rec(
        pa: np.ndarray, na: np.ndarray, qa: np.ndarray, pb: np.ndarray, nb: np.ndarray, depth: int
    ) -> np.ndarray:
        qb = machine.inverse(pb, nb, C_ref=float(qa[3]))
        mv = Move("linear", qa, qb, pa, pb, seg, depth)
        dev = move_deviation(machine, mv)
        if dev <= tol or depth >= max_depth or len(moves) >= max_pieces:
            moves.append(mv)
            devs.append(dev)
            return qb
        pm, nm = 0.5 * (pa + pb), mean_normal(na, nb)
        qm = rec(pa, na, qa, pm, nm, depth + 1)
        return rec(pm, nm, qm, pb, nb, depth + 1)

    pa, na, pb, nb = ends
    rec(np.asarray(pa, float), unit(na), np.asarray(qa, float), np.asarray(pb, float), unit(nb), 0)
    worst = max(devs)
    return Bisection(moves, worst <= tol, max(m.depth for m in moves), worst)


def bisect_uniform(machine: Machine5, ends: Ends, qa: np.ndarray, depth: int) -> list[Move]:
    """Method 2 split ``depth`` times everywhere (2^depth pieces), translated in order."""
    pa, na, pb, nb = ends
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
        Move("linear", q0, q1, p0, p1, 0, depth)
        for (p0, _), (p1, _), q0, q1 in zip(nodes[:-1], nodes[1:], qs[:-1], qs[1:])
    ]


def nonlinear_submoves(machine: Machine5, move: Move, count: int) -> list[Move]:
    """The nonlinear move executed by a linear CNC as ``count`` linear sub-moves."""
    tau = np.linspace(0.0, 1.0, count + 1)
    qs = move.axes(machine, tau)
    ps = move.p0 + tau[:, None] * (move.p1 - move.p0)
    return [
        Move("linear", qs[k], qs[k + 1], ps[k], ps[k + 1], move.seg, lead=move.lead)
        for k in range(count)
    ]


def fixed_normal_move(machine: Machine5, ends: Ends, C_ref: float, seg: int = 0) -> Move:
    """Method 1: the whole segment with the beam along the mean normal, no rotation."""
    pa, na, pb, nb = ends
    nm = mean_normal(na, nb)
    q0 = machine.inverse(pa, nm, C_ref)
    q1 = machine.inverse(pb, nm, float(q0[3]))
    return Move("linear", q0, q1, pa, pb, seg)


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
