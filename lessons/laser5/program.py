"""The executed CNC program of the five-axis laser machine (LSP-2000 article).

A task translated into CNC commands (rule (2)/(3)) and run by one controller (linear
interpolation, method 1, method 2 or the nonlinear interpolation (4)) becomes a list of
moves, each taking ``length / V`` seconds at the contour feed ``V``.  The program is
built once per parameter set; :meth:`Program.playhead` says where it is at given times
(move and ``tau``) and :meth:`Program.sample` evaluates the machine there, vectorised
over any number of times: the headless run and the live view read the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Note
from analyzer_lab.lessons.kit.once import once
from analyzer_lab.lessons.laser5.interpolation import (
    Bisection,
    Move,
    bisect_segment,
    fixed_normal_move,
    interpolate_axes,
    move_deviation,
    nonlinear_move,
    nonlinear_submoves,
    point_rate,
    segment_distance,
)
from analyzer_lab.lessons.laser5.kinematics import Machine5, angle_between, translate_poses
from analyzer_lab.lessons.laser5.task import Task

METHODS = ("linear", "bisection", "nonlinear", "fixed-normal")
MAX_MOVES = 4096  # CNC moves per program (bisection stops splitting beyond this)
TRAVEL_GRID = 32  # intervals per move of the travelled-path tables
RUN_SAMPLES = 4000  # samples of a headless run, spread over the moves


@dataclass(frozen=True)
class Playhead:
    """Where the program is at a number of times (leading axis = time): the move being
    executed, its parameter ``tau`` and whether the program still runs."""

    program: Program
    move: np.ndarray
    tau: np.ndarray
    running: np.ndarray

    @once
    def values(self) -> dict[str, np.ndarray]:
        """The machine at these times (:meth:`Program.sample`), evaluated once."""
        return self.program.sample(self)


@dataclass
class Program:
    """The executed CNC program: moves at the contour feed, and what the controller did."""

    machine: Machine5
    task: Task
    method: str
    moves: list[Move]
    feed: float
    tolerance_mm: float
    converged: bool = True
    reorientations: int = 0
    notes: list[Note] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.durations = np.array([mv.length / self.feed for mv in self.moves])
        self.starts = np.concatenate([[0.0], np.cumsum(self.durations)[:-1]])
        self.q0, self.q1, self.p0, self.p1 = (
            np.array([getattr(mv, a) for mv in self.moves]) for a in ("q0", "q1", "p0", "p1")
        )
        self.nonlinear = np.array([mv.kind == "nonlinear" for mv in self.moves])
        self.seg = np.array([mv.seg for mv in self.moves])

    @property
    def duration(self) -> float:
        return float(self.starts[-1] + self.durations[-1])

    def playhead(self, t: Any) -> Playhead:
        """The move and ``tau`` at times ``t``, clamped to the program.  A time within
        1e-9 of the program's duration of a move's end belongs to that move (``tau = 1``),
        so that a clock summed from frames finds the same move as a grid of samples."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        eps = 1e-9 * max(self.duration, 1.0)
        ends = self.starts + self.durations
        k = np.minimum(np.searchsorted(ends, t - eps, side="left"), len(self.moves) - 1)
        T = self.durations[k]
        tau = np.clip((t - self.starts[k]) / np.where(T > 0, T, 1.0), 0.0, 1.0)
        tau = np.where((T > 0) & (ends[k] - t > eps), tau, 1.0)
        return Playhead(self, k, tau, t <= self.duration + eps)

    def sample_times(self, t_end: float) -> np.ndarray:
        """A headless run's grid: every move sampled uniformly in ``tau`` (about
        :data:`RUN_SAMPLES` in all), cut at ``t_end``, which ends the grid (after the
        program's end the tool holds)."""
        per = int(min(200, max(4, math.ceil(RUN_SAMPLES / len(self.moves)))))
        grid = self.starts[:, None] + np.linspace(0.0, 1.0, per + 1) * self.durations[:, None]
        t = np.concatenate([grid[0], grid[1:, 1:].ravel()])
        return np.append(t[t < t_end - 1e-9 * max(t_end, 1.0)], t_end)

    def axes(self, k: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Axis positions of moves ``k`` at ``tau`` (broadcast; shape (..., 5))."""
        return interpolate_axes(
            self.machine, self.q0[k], self.q1[k], self.p0[k], self.p1[k], self.nonlinear[k], tau
        )

    @once
    def _travel_tables(self) -> tuple[np.ndarray, np.ndarray]:
        """Path travelled by X, Y, Z and by the working point from the start to each of
        ``TRAVEL_GRID + 1`` points of every move [mm] (polylines through the points)."""
        k = np.arange(len(self.moves))[:, None]
        q = self.axes(k, np.linspace(0.0, 1.0, TRAVEL_GRID + 1)[None, :])
        p, _ = self.machine.forward(q)

        def cumulative(x: np.ndarray) -> np.ndarray:
            step = np.linalg.norm(np.diff(x, axis=1), axis=-1)
            within = np.concatenate([np.zeros((len(x), 1)), np.cumsum(step, axis=1)], axis=1)
            return within + np.concatenate([[0.0], np.cumsum(within[:, -1])[:-1]])[:, None]

        return cumulative(q[..., :3]), cumulative(p)

    def sample(self, head: Playhead) -> dict[str, np.ndarray]:
        """Axes ``q``, working point ``p``, beam ``n``, surface ``normal`` below the point,
        deviation from the programmed segment and off-normal angle (rad), contour speed,
        travelled paths, at the playhead's times."""
        k, tau = head.move, head.tau
        q = self.axes(k, tau)
        p, n = self.machine.forward(q)
        seg = self.seg[k]
        deviation, lam = segment_distance(p, self.task.points[seg], self.task.points[seg + 1])
        normal = self.task.normal_at(seg, lam)
        rate = point_rate(
            self.machine, q, self.q0[k], self.q1[k], self.p0[k], self.p1[k], self.nonlinear[k]
        )
        T = self.durations[k]
        moving = head.running & (T > 0)
        speed = np.where(moving, np.linalg.norm(rate, axis=-1) / np.where(T > 0, T, 1.0), 0.0)
        pos = tau * TRAVEL_GRID
        i = np.minimum(np.floor(pos).astype(int), TRAVEL_GRID - 1)
        f = pos - i
        linear, tool = (tab[k, i] + f * (tab[k, i + 1] - tab[k, i]) for tab in self._travel_tables)
        return {
            "q": q,
            "p": p,
            "n": n,
            "normal": normal,
            "deviation": deviation,
            "off_normal": angle_between(n, normal),
            "speed": speed,
            "travel_linear": linear,
            "travel_tool": tool,
        }


def build_program(
    machine: Machine5,
    task: Task,
    method: str,
    tolerance_mm: float,
    feed: float,
    *,
    max_depth: int = 30,
    sub_moves: int = 0,
) -> Program:
    """Translate the task (rule (2)/(3)) and run the controller ``method`` over every segment."""
    qs = translate_poses(machine, task.points, task.normals)
    moves: list[Move] = []
    notes: list[Note] = []
    reorientations = 0
    q_prev = qs[0]
    for i in range(task.segments):
        pa, pb = task.points[i], task.points[i + 1]
        na, nb = task.normals[i], task.normals[i + 1]
        if method == "linear":
            moves.append(Move("linear", qs[i], qs[i + 1], pa, pb, i))
        elif method == "nonlinear":
            qb = machine.inverse(pb, nb, float(q_prev[3]))
            mv = nonlinear_move(q_prev, qb, pa, pb, i)
            split = sub_moves > 0 and mv.kind == "nonlinear"
            moves.extend(nonlinear_submoves(machine, mv, sub_moves) if split else [mv])
            q_prev = qb
        elif method == "bisection":
            budget = max(MAX_MOVES - len(moves) - (task.segments - i - 1), 1)
            ends = (pa, na, pb, nb)
            bis = bisect_segment(machine, ends, q_prev, tolerance_mm, max_depth, i, budget)
            if not bis.converged:
                notes.append(_bisection_stopped(i, bis, tolerance_mm, len(bis.moves) >= budget))
            moves.extend(bis.moves)
            q_prev = bis.moves[-1].q1
        else:  # fixed-normal: method 1
            mv = fixed_normal_move(machine, (pa, na, pb, nb), float(q_prev[3]), seg=i)
            if moves and not np.allclose(moves[-1].q1[3:], mv.q0[3:], atol=1e-12):
                reorientations += 1
            moves.append(mv)
            q_prev = mv.q1
    if method == "fixed-normal":
        notes.append(
            Note(
                "info",
                "method 1: the laser is switched off and on at every segment to re-orient"
                " the beam.",
                source="LSP-2000 article, method 1",
            )
        )
    converged = not any(note.kind == "warning" for note in notes)
    return Program(
        machine, task, method, moves, feed, tolerance_mm, converged, reorientations, notes
    )


def _bisection_stopped(seg: int, bis: Bisection, tol_mm: float, at_budget: bool) -> Note:
    """Why method 2 stopped on segment ``seg`` above the tolerance."""
    head = f"segment {seg + 1}: bisection stopped"
    tail = f"with {bis.worst_mm * 1e3:.4g} um > {tol_mm * 1e3:g} um"
    if at_budget:
        text = f"{head} at the limit of {MAX_MOVES} moves {tail}."
    else:
        text = (
            f"{head} at depth {bis.max_depth} {tail}: near the vertical a piece keeps swinging"
            " C by a large angle whatever its length (the rotary limits force it)."
        )
    return Note("warning", text, source="LSP-2000 article, method 2 and Fig. 5")


def program_metrics(prog: Program, samples: int = 65) -> dict[str, Any]:
    """Whole-program metrics on a fixed grid per move (independent of a run's sampling);
    the largest deviation is refined by a bounded search on the three worst moves."""
    m, task = prog.machine, prog.task
    k = np.arange(len(prog.moves))[:, None]
    q = prog.axes(k, np.linspace(0.0, 1.0, samples)[None, :])
    p, n = m.forward(q)
    segs = prog.seg
    a, b = task.points[segs][:, None, :], task.points[segs + 1][:, None, :]
    dev, lam = segment_distance(p, a, b)
    per_move = dev.max(axis=1)
    worst = [
        move_deviation(m, prog.moves[j], task.points[segs[j]], task.points[segs[j] + 1])
        for j in np.argsort(per_move)[-3:]
    ]
    dev_max = max([float(per_move.max()), *worst])
    # progress along each task segment must never decrease
    backwards = any(
        bool(np.any(np.diff(lam[segs == i].ravel()) < -1e-9)) for i in range(task.segments)
    )
    off = float(angle_between(n, task.normal_at(segs[:, None], lam)).max())
    step = np.diff(q, axis=1)
    rot = np.abs(prog.q1[:, 3:] - prog.q0[:, 3:]).sum()
    metrics: dict[str, Any] = {
        "deviation_max_um": dev_max * 1e3,
        "within_tolerance": bool(dev_max <= prog.tolerance_mm + 1e-12),
        "moves": len(prog.moves),
        "axis_travel_mm": float(np.linalg.norm(step[..., :3], axis=-1).sum()),
        "xy_travel_mm": float(np.linalg.norm(step[..., :2], axis=-1).sum()),
        "rotary_travel_deg": float(math.degrees(rot)),
        "tool_path_mm": float(sum(mv.length for mv in prog.moves)),
        "off_normal_max_deg": math.degrees(off),
        "backward_motion": backwards,
        "converged": bool(prog.converged),
        "reorientations": int(prog.reorientations),
        "duration_s": prog.duration,
    }
    if prog.method == "fixed-normal":
        metrics["laser_switches"] = task.segments
    return metrics
