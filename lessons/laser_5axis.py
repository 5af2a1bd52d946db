"""LSP-2000 five-axis laser machine (article 003): linear against nonlinear interpolation.

The machine: portal X on granite guides, portal Y on it, portal Z carrying the rotary
mechanism C (a horizontal lever of length R_C), at its end the rotary mechanism B (a
lever of length R_B along the beam); the working point is at the end of the B lever.
Kinematics (1a), (1b), (2), (3) are the digest's reconstruction (the article's (1), (2)
are lost, (3) survives as tokens); the interpolation formulas (4) are the article's.

A task is a list of surface points with the beam along the surface normal; the working
point must follow the polyline through them within the tolerance delta_p (20 um).
Four controllers run along every segment: linear interpolation of all axes, method 1
(no rotation within a segment, beam along the mean normal), method 2 (recursive
bisection, the mean normal at every split), and the nonlinear interpolation (4).

Coordinates: series and metrics are in the machine's left-handed frame (Z towards the
workpiece, i.e. down).  The scene is drawn in the viewer's right-handed z-up frame
``(x, y, -z)``, the mirror image that turns the left-handed triple right-handed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from scipy.spatial.transform import Rotation

from lessons.core.contract import (
    Claim,
    ClaimResult,
    CurveItem,
    DerivationStep,
    Frame,
    Lesson,
    MarkerItem,
    MeshItem,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Stepper,
    at_most,
    close,
)
from lessons.core.kinematics5 import (
    LimitError,
    Machine5,
    Move,
    Paraboloid,
    SphereCap,
    Task,
    Workpiece,
    angle_between,
    axis_path_length,
    bisect_segment,
    bisect_uniform,
    fixed_normal_moves,
    linear_move,
    make_task,
    mean_normal,
    move_deviation,
    moves_backwards,
    nonlinear_move,
    nonlinear_submoves,
    off_normal_max,
    point_speed_ratio,
    sagitta_estimate,
    segment_distance,
    translate_poses,
)

METHODS = ("linear", "bisection", "nonlinear", "fixed-normal")
SOURCE = "Article 003 (LSP-2000 five-axis laser complex), eqs (1)-(4)"
TRAIL_SAMPLES = 4000  # samples of a headless run, spread over the moves
MAX_MOVES = 4096  # CNC moves per program (bisection stops splitting beyond this)

# The prototype's segments on the paraboloid F = 500 mm (digest II.10): (u, v) offsets [mm].
SEGMENTS: dict[str, tuple[tuple[float, float], tuple[float, float]]] = {
    "S1": ((300.0, 0.0), (300.0, 60.0)),  # azimuthal
    "S2": ((100.0, 0.0), (160.0, 0.0)),  # radial
    "S3": ((250.0, -40.0), (300.0, 40.0)),  # oblique
    "S4": ((-30.0, 5.0), (30.0, 5.0)),  # past the apex: near-vertical beam
}


# ---------------------------------------------------------------- building a run


def machine_of(params: Params) -> Machine5:
    return Machine5(
        R_C=float(params["R_C"]),
        R_B=float(params["R_B"]),
        k_C1=float(params["k_C1"]),
        k_C2=float(params["k_C2"]),
        k_X=float(params["k_X"]),
        k_Y=float(params["k_Y"]),
        k_Z=float(params["k_Z"]),
        limits=str(params["limits"]),  # type: ignore[arg-type]
    )


def workpiece_of(params: Params) -> Workpiece:
    if params["surface"] == "sphere":
        R = float(params["R_s"])
        return SphereCap(R=R, radius=0.7 * R)
    return Paraboloid(F=float(params["F"]))


def task_of(params: Params) -> Task:
    return make_task(
        workpiece_of(params),
        str(params["path"]),
        int(params["segments"]),
        (float(params["u0"]), float(params["v0"])),
        (float(params["u1"]), float(params["v1"])),
        float(params["radius"]),
    )


def translate(machine: Machine5, task: Task) -> list[np.ndarray]:
    """The task as CNC commands (see :func:`lessons.core.kinematics5.translate_poses`)."""
    return translate_poses(machine, task.points, task.normals)


@dataclass
class Program:
    """The executed CNC program: moves with their durations, and what it achieves."""

    machine: Machine5
    task: Task
    method: str
    moves: list[Move]
    durations: np.ndarray
    starts: np.ndarray
    feed: float
    tolerance_mm: float
    converged: bool
    reorientations: int
    messages: list[str]

    @property
    def duration(self) -> float:
        return float(self.starts[-1] + self.durations[-1]) if self.moves else 0.0

    def locate(self, t: float) -> tuple[int, float]:
        """Move index and its parameter ``tau`` at time ``t`` (clamped to the program)."""
        t = min(max(t, 0.0), self.duration)
        k = int(np.searchsorted(self.starts, t, side="right") - 1)
        k = min(max(k, 0), len(self.moves) - 1)
        T = self.durations[k]
        return k, (1.0 if T <= 0 else min(max((t - self.starts[k]) / T, 0.0), 1.0))

    def sample(self, k: int, tau: np.ndarray) -> dict[str, np.ndarray]:
        """Tool point, beam, axes, deviation, off-normal angle and speed on move ``k``."""
        mv = self.moves[k]
        m = self.machine
        q = mv.axes(m, tau)
        p, n = m.forward(q)
        a, b = self.task.points[mv.seg], self.task.points[mv.seg + 1]
        dev, lam = segment_distance(p, a, b)
        normal = self.task.normal_at(mv.seg, lam)
        h = 1e-6
        lo, hi = np.clip(tau - h, 0, 1), np.clip(tau + h, 0, 1)
        dp = m.forward(mv.axes(m, hi))[0] - m.forward(mv.axes(m, lo))[0]
        T = self.durations[k]
        speed = (
            np.linalg.norm(dp, axis=-1) / np.maximum((hi - lo) * T, 1e-300)
            if T > 0
            else np.zeros(len(tau))
        )
        return {
            "q": q,
            "p": p,
            "n": n,
            "dev": dev,
            "normal": normal,
            "off": np.degrees(angle_between(n, normal)),
            "speed": speed,
        }


def build_program(params: Params) -> Program:
    """Translate the task and run the chosen controller over every segment."""
    machine = machine_of(params)
    task = task_of(params)
    method = str(params["method"])
    tol = float(params["tolerance_um"]) * 1e-3
    feed = float(params["V"])
    qs = translate(machine, task)
    moves: list[Move] = []
    messages: list[str] = []
    converged = True
    reorient = 0
    q_prev = qs[0]
    for i in range(task.segments):
        pa, pb = task.points[i], task.points[i + 1]
        na, nb = task.normals[i], task.normals[i + 1]
        if method == "linear":
            moves.append(linear_move(qs[i], qs[i + 1], pa, pb, i))
        elif method == "nonlinear":
            qb = machine.inverse(pb, nb, float(q_prev[3]))
            mv = nonlinear_move(q_prev, qb, pa, pb, i)
            n_sub = int(params["sub_moves"])
            moves.extend(
                nonlinear_submoves(machine, mv, n_sub)
                if n_sub > 0 and mv.kind == "nonlinear"
                else [mv]
            )
            q_prev = qb
        elif method == "bisection":
            budget = max(MAX_MOVES - len(moves) - (task.segments - i - 1), 1)
            bis = bisect_segment(
                machine,
                pa,
                na,
                q_prev,
                pb,
                nb,
                tol,
                int(params["max_depth"]),
                seg=i,
                max_pieces=budget,
            )
            converged &= bis.converged
            if not bis.converged and len(bis.moves) >= budget:
                messages.append(
                    f"segment {i + 1}: bisection stopped at the limit of {MAX_MOVES} moves "
                    f"with {bis.worst_mm:.3g} mm > {tol * 1e3:g} um."
                )
            elif not bis.converged:
                messages.append(
                    f"segment {i + 1}: bisection stopped at depth {bis.max_depth} with "
                    f"{bis.worst_mm:.3g} mm > {tol * 1e3:g} um: near the vertical a piece keeps "
                    "swinging C by a large angle whatever its length (the rotary limits force it)."
                )
            moves.extend(bis.moves)
            q_prev = bis.moves[-1].q1
        else:  # fixed-normal: method 1
            mv = fixed_normal_moves(machine, pa, na, pb, nb, float(q_prev[3]), seg=i)
            if moves and not np.allclose(moves[-1].q1[3:], mv.q0[3:], atol=1e-12):
                reorient += 1
            moves.append(mv)
            q_prev = mv.q1
            if i == 0:
                messages.append(
                    "method 1: the laser is switched off and on at every segment to re-orient the beam."
                )
    durations = np.array([mv.length / feed for mv in moves])
    starts = np.concatenate([[0.0], np.cumsum(durations)[:-1]])
    return Program(
        machine, task, method, moves, durations, starts, feed, tol, converged, reorient, messages
    )


def eval_moves(machine: Machine5, moves: list[Move], tau: np.ndarray) -> np.ndarray:
    """Axis positions of every move at the parameters ``tau``: shape (moves, len(tau), 5)."""
    out = np.empty((len(moves), len(tau), 5))
    lin = [i for i, mv in enumerate(moves) if mv.kind == "linear"]
    if lin:
        q0 = np.array([moves[i].q0 for i in lin])
        q1 = np.array([moves[i].q1 for i in lin])
        out[lin] = q0[:, None, :] + tau[None, :, None] * (q1 - q0)[:, None, :]
    for i, mv in enumerate(moves):
        if mv.kind != "linear":
            out[i] = mv.axes(machine, tau)
    return out


def program_metrics(prog: Program, samples: int = 65) -> dict[str, Any]:
    """Whole-program metrics on a fixed grid per move (independent of the display sampling).

    The largest deviation is refined by a bounded search on the few worst moves.
    """
    m, task = prog.machine, prog.task
    tau = np.linspace(0.0, 1.0, samples)
    q = eval_moves(m, prog.moves, tau)
    p, n = m.forward(q)
    segs = np.array([mv.seg for mv in prog.moves])
    a, b = task.points[segs][:, None, :], task.points[segs + 1][:, None, :]
    d = b - a
    lam = np.sum((p - a) * d, axis=-1) / np.sum(d * d, axis=-1)
    dev = np.linalg.norm(p - (a + np.clip(lam, 0.0, 1.0)[..., None] * d), axis=-1)
    per_move = dev.max(axis=1)
    worst = np.argsort(per_move)[-3:]
    dev_max = max(
        [float(per_move.max())]
        + [
            move_deviation(m, prog.moves[k], task.points[segs[k]], task.points[segs[k] + 1])
            for k in worst
        ]
    )
    # progress along each task segment must never decrease
    backwards = False
    for i in range(task.segments):
        lam_i = lam[segs == i].ravel()
        backwards |= bool(len(lam_i) and np.any(np.diff(lam_i) < -1e-9))
    uv = (1 - np.clip(lam, 0, 1))[..., None] * task.uv[segs][:, None, :] + np.clip(lam, 0, 1)[
        ..., None
    ] * task.uv[segs + 1][:, None, :]
    normal = task.workpiece.point_normal(uv[..., 0], uv[..., 1])[1]
    off = float(angle_between(n, normal).max()) if len(prog.moves) else 0.0
    step = np.diff(q, axis=1)
    rot = sum(abs(mv.q1[3] - mv.q0[3]) + abs(mv.q1[4] - mv.q0[4]) for mv in prog.moves)
    return {
        "deviation_max_mm": float(dev_max),
        "within_tolerance": bool(dev_max <= prog.tolerance_mm + 1e-12),
        "pieces": len(prog.moves),
        "axis_travel_mm": float(np.linalg.norm(step[..., :3], axis=-1).sum()),
        "xy_travel_mm": float(np.linalg.norm(step[..., :2], axis=-1).sum()),
        "rotary_travel_deg": float(math.degrees(rot)),
        "tool_path_mm": float(sum(mv.length for mv in prog.moves)),
        "off_normal_max_deg": float(math.degrees(off)),
        "backward_motion": bool(backwards),
        "converged": bool(prog.converged),
        "reorientations": int(prog.reorientations),
        "duration_s": prog.duration,
    }


# ---------------------------------------------------------------- the view: machine bodies


def to_view(v: np.ndarray) -> np.ndarray:
    """Machine frame (left-handed, Z down) -> viewer frame (right-handed, z up)."""
    v = np.asarray(v, dtype=float)
    return v * np.array([1.0, 1.0, -1.0])


BRIDGE_Z = 250.0  # viewer height of portal X's bridge [mm]
BED_Z = -1000.0  # viewer height of the granite bed's top


def _mesh(
    name: str, mesh: trimesh.Trimesh, color: tuple[int, int, int], opacity: float = 1.0
) -> MeshItem:
    return MeshItem(
        name, np.asarray(mesh.vertices, float), np.asarray(mesh.faces, int), color, opacity
    )


def _box(
    extents: tuple[float, float, float], centre: tuple[float, float, float]
) -> trimesh.Trimesh:
    return trimesh.creation.box(
        extents=extents, transform=trimesh.transformations.translation_matrix(centre)
    )


def _cyl(radius: float, a: np.ndarray, b: np.ndarray) -> trimesh.Trimesh:
    return trimesh.creation.cylinder(
        radius=radius, segment=np.array([a, b], dtype=float), sections=24
    )


def machine_bodies(machine: Machine5) -> list[MeshItem]:
    """Moving bodies in their local frames (posed by :func:`body_poses`)."""
    span = (-250.0, 3250.0)
    legs_h = BRIDGE_Z - BED_Z
    portal_x = trimesh.util.concatenate(
        [
            _box((160.0, span[1] - span[0], 120.0), (0.0, 0.5 * (span[0] + span[1]), BRIDGE_Z)),
            _box((160.0, 120.0, legs_h), (0.0, span[0], BED_Z + legs_h / 2)),
            _box((160.0, 120.0, legs_h), (0.0, span[1], BED_Z + legs_h / 2)),
        ]
    )
    portal_y = _box((260.0, 240.0, 200.0), (0.0, 0.0, 0.0))
    portal_z = _box((110.0, 110.0, 900.0), (0.0, 0.0, 450.0))
    lever_c = trimesh.util.concatenate(
        [
            _cyl(45.0, np.array([0, 0, -30.0]), np.array([0, 0, 30.0])),
            _box((50.0, max(machine.R_C, 1.0), 40.0), (0.0, machine.R_C / 2, 0.0)),
        ]
    )
    lever_b = trimesh.util.concatenate(
        [
            _cyl(35.0, np.array([-40.0, 0, 0]), np.array([40.0, 0, 0])),
            _cyl(18.0, np.array([0, 0, 0.0]), np.array([0, 0, -0.85 * machine.R_B])),
            _cyl(9.0, np.array([0, 0, -0.85 * machine.R_B]), np.array([0, 0, -machine.R_B])),
        ]
    )
    return [
        _mesh("portal_X", portal_x, (150, 150, 160)),
        _mesh("portal_Y", portal_y, (90, 110, 150)),
        _mesh("portal_Z", portal_z, (110, 130, 170)),
        _mesh("lever_C", lever_c, (230, 160, 40)),
        _mesh("lever_B", lever_b, (200, 90, 40)),
    ]


def body_poses(machine: Machine5, q: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Viewer poses (position, wxyz) of the moving bodies for axis positions ``q``."""
    c_pivot, b_pivot, _, _ = machine.pivots(q)
    cv, bv = to_view(c_pivot), to_view(b_pivot)
    th = float(machine.theta(q[3]))
    ident = np.array([1.0, 0.0, 0.0, 0.0])
    rz = Rotation.from_rotvec([0.0, 0.0, -th])
    rb = rz * Rotation.from_rotvec([float(q[4]), 0.0, 0.0])
    return {
        "portal_X": (np.array([cv[0], 0.0, 0.0]), ident),
        "portal_Y": (np.array([cv[0], cv[1], BRIDGE_Z]), ident),
        "portal_Z": (cv, ident),
        "lever_C": (cv, rz.as_quat(scalar_first=True)),
        "lever_B": (bv, rb.as_quat(scalar_first=True)),
    }


# ---------------------------------------------------------------- live stepper


class LaserStepper(Stepper):
    """Plays the CNC program; parameters may change while it runs (time is kept)."""

    def __init__(self, params: Params) -> None:
        self._t = 0.0
        self._prev_t = 0.0
        self.set_params(params)

    @property
    def t(self) -> float:
        return self._t

    def set_params(self, params: Params) -> None:
        self.params = params
        self.prog = build_program(params)
        m = self.prog.machine
        tau = np.linspace(0.0, 1.0, 33)
        q = eval_moves(m, self.prog.moves, tau)
        p, _ = m.forward(q)
        lin = np.concatenate(
            [
                np.zeros((len(q), 1)),
                np.cumsum(np.linalg.norm(np.diff(q[..., :3], axis=1), axis=-1), axis=1),
            ],
            axis=1,
        )
        tool = np.concatenate(
            [np.zeros((len(q), 1)), np.cumsum(np.linalg.norm(np.diff(p, axis=1), axis=-1), axis=1)],
            axis=1,
        )
        lin += np.concatenate([[0.0], np.cumsum(lin[:, -1])[:-1]])[:, None]
        tool += np.concatenate([[0.0], np.cumsum(tool[:, -1])[:-1]])[:, None]
        self._cum = [(tau, lin[k], tool[k]) for k in range(len(q))]
        self._t = min(self._t, self.prog.duration)

    def frame(self) -> Frame:
        prog = self.prog
        k, tau = prog.locate(self._t)
        s = prog.sample(k, np.array([tau]))
        taus, lin, tool = self._cum[k]
        p, n, normal = s["p"][0], s["n"][0], s["normal"][0]
        pv = to_view(p)[None]
        q = s["q"][0]
        msg = ""
        if self._t >= prog.duration:
            msg = "task finished"
        elif prog.messages:
            msg = prog.messages[0]
        return Frame(
            t=self._t,
            points={"tool": pv},
            vectors={
                "beam": (pv, 150.0 * to_view(n)[None]),
                "normal": (pv, 150.0 * to_view(normal)[None]),
            },
            poses=body_poses(prog.machine, q),
            scalars={
                "deviation_um": float(s["dev"][0]) * 1e3,
                "tolerance_um": prog.tolerance_mm * 1e3,
                "speed_mm_s": float(s["speed"][0]),
                "feed_mm_s": prog.feed,
                "off_normal_deg": float(s["off"][0]),
                "travel_linear_mm": float(np.interp(tau, taus, lin)),
                "travel_tool_mm": float(np.interp(tau, taus, tool)),
                "C_deg": math.degrees(float(q[3])),
                "B_deg": math.degrees(float(q[4])),
            },
            message=msg,
        )

    def advance(self, dt: float) -> Frame:
        self._t = min(self._t + max(float(dt), 0.0), self.prog.duration)
        return self.frame()

    def reset(self) -> Frame:
        self._t = 0.0
        return self.frame()


# ---------------------------------------------------------------- the prototype's segments


@dataclass
class SegmentStudy:
    """One segment of the prototype: the four controllers measured."""

    machine: Machine5
    task: Task
    qa: np.ndarray
    qb: np.ndarray

    @property
    def ends(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.task.points[0], self.task.normals[0], self.task.points[1], self.task.normals[1]

    def linear(self) -> Move:
        pa, _, pb, _ = self.ends
        return linear_move(self.qa, self.qb, pa, pb)

    def nonlinear(self) -> Move:
        pa, _, pb, _ = self.ends
        return nonlinear_move(self.qa, self.qb, pa, pb)


@lru_cache(maxsize=16)
def study(
    name: str, limits: str = "original", R_C: float = 200.0, R_B: float = 300.0
) -> SegmentStudy:
    """Segment ``name`` (S1..S4) of the prototype on the paraboloid F = 500 mm."""
    machine = Machine5(R_C=R_C, R_B=R_B, limits=limits)  # type: ignore[arg-type]
    a, b = SEGMENTS[name]
    task = make_task(Paraboloid(), "line", 1, a, b)
    qa = machine.inverse(task.points[0], task.normals[0])
    qb = machine.inverse(task.points[1], task.normals[1], float(qa[3]))
    return SegmentStudy(machine, task, qa, qb)


@lru_cache(maxsize=16)
def uniform_levels(name: str, limits: str, depth: int = 6) -> tuple[float, ...]:
    """Largest piece deviation after 0..depth uniform bisection levels [mm]."""
    s = study(name, limits)
    pa, na, pb, nb = s.ends
    out = [move_deviation(s.machine, s.linear())]
    for d in range(1, depth + 1):
        out.append(
            max(
                move_deviation(s.machine, mv)
                for mv in bisect_uniform(s.machine, pa, na, s.qa, pb, nb, d)
            )
        )
    return tuple(out)


@lru_cache(maxsize=16)
def adaptive(name: str, limits: str, tol: float = 0.020):
    s = study(name, limits)
    pa, na, pb, nb = s.ends
    return bisect_segment(s.machine, pa, na, s.qa, pb, nb, tol, 30)


# ---------------------------------------------------------------- claims


def _all(results: list[ClaimResult]) -> ClaimResult:
    return ClaimResult(
        expected="; ".join(r.expected for r in results),
        got="; ".join(r.got for r in results),
        passed=all(r.passed for r in results),
    )


def check_round_trip() -> ClaimResult:
    worst = 0.0
    for limits in ("original", "improved"):
        m = Machine5(limits=limits)  # type: ignore[arg-type]
        q = m.random_poses(np.random.default_rng(3), 1000)
        p, n = m.forward(q)
        for i in range(len(q)):
            q2 = m.inverse(p[i], n[i], C_ref=float(q[i, 3]))
            p2, n2 = m.forward(q2)
            worst = max(
                worst,
                float(np.abs(p2 - p[i]).max()),
                float(np.abs(q2[:3] - q[i, :3]).max()),
                float(np.abs(n2 - n[i]).max()),
            )
    return at_most(1e-9, worst, "max |p, n, X, Y, Z round-trip error| ")


def check_vertical() -> ClaimResult:
    m = Machine5()
    q1 = np.array([1000.0, 1000.0, 100.0, 1.0, 0.0])
    p, n = m.forward(q1)
    q0 = m.inverse(p, n)  # first variant: C = 0
    q_ref = m.inverse(p, n, C_ref=1.0)
    same = max(
        float(np.abs(m.forward(q0)[0] - p).max()), float(np.abs(m.forward(q_ref)[0] - p).max())
    )
    differ = float(np.hypot(*(q0[:2] - q1[:2])))
    ok = same <= 1e-9 and q0[3] == 0.0 and abs(q_ref[3] - 1.0) < 1e-12 and differ > 100.0
    return ClaimResult(
        expected="two axis sets (C = 0 and C = 1) give the same pose to 1e-9 mm; X, Y differ by R_C |2 sin(1/2)| = 191.8 mm",
        got=f"pose error {same:.2e} mm, C = {q0[3]:g} / {q_ref[3]:g}, |dXY| = {differ:.1f} mm",
        passed=ok,
    )


def check_linear_deviates() -> ClaimResult:
    s = study("S1")
    dev = move_deviation(s.machine, s.linear())
    est = sagitta_estimate(s.machine, s.qa, s.qb)
    r = [close(1.398, dev, atol=0.001), close(dev, est, rtol=0.005)]
    res = _all(r)
    res.passed = res.passed and dev > 0.020
    res.expected = (
        "S1 linear interpolation 1.398 mm > 0.020 mm; sagitta (R_C + R_B sin B) dC^2/8 within 0.5 %: "
        + res.expected
    )
    return res


def check_speed_nonuniform() -> ClaimResult:
    return _all(
        [
            close(1.008, point_speed_ratio(study("S1").machine, study("S1").linear()), atol=0.001),
            close(1.061, point_speed_ratio(study("S3").machine, study("S3").linear()), atol=0.001),
        ]
    )


def check_quarter() -> ClaimResult:
    ratios = {}
    for name in ("S1", "S2", "S3"):
        lv = uniform_levels(name, "original")
        ratios[name] = [lv[d] / lv[d + 1] for d in range(len(lv) - 1)]
    flat = [r for rs in ratios.values() for r in rs]
    last = [rs[-1] for rs in ratios.values()]
    lv = uniform_levels("S1", "original")
    ok = (
        min(flat) >= 3.4
        and max(flat) <= 4.05
        and all(abs(r - 4.0) < 0.02 for r in last)
        and abs(lv[1] - 0.355) < 0.001
    )
    return ClaimResult(
        expected="error ratio per split between 3.4 (first split of the oblique S3) and 4.05, 4.00 +- 0.02 at level 6; "
        "S1 level 1 = 0.355 mm",
        got="; ".join(f"{n}: " + ", ".join(f"{r:.3f}" for r in rs) for n, rs in ratios.items())
        + "; S1 levels "
        + ", ".join(f"{x:.3g}" for x in lv),
        passed=ok,
    )


def check_bisection_tolerance() -> ClaimResult:
    got = {n: adaptive(n, "original") for n in ("S1", "S2", "S3")}
    want = {"S1": (16, 4), "S2": (4, 2), "S3": (16, 4)}
    ok = all(
        b.converged and b.worst_mm <= 0.020 and (len(b.moves), b.max_depth) == want[n]
        for n, b in got.items()
    )
    return ClaimResult(
        expected="within 20 um: S1 16 pieces / depth 4, S2 4 / 2, S3 16 / 4",
        got=", ".join(
            f"{n} {len(b.moves)} / {b.max_depth} ({b.worst_mm * 1e3:.2f} um)"
            for n, b in got.items()
        ),
        passed=ok,
    )


def check_nonlinear_on_segment() -> ClaimResult:
    worst, ratio = 0.0, 0.0
    for limits in ("original", "improved"):
        for name in SEGMENTS:
            s = study(name, limits)
            worst = max(worst, move_deviation(s.machine, s.nonlinear()))
            ratio = max(ratio, abs(point_speed_ratio(s.machine, s.nonlinear()) - 1.0))
    ok = worst <= 1e-9 and ratio <= 1e-6
    return ClaimResult(
        expected="deviation <= 1e-9 mm and speed max/min - 1 <= 1e-6 on S1-S4, both limits",
        got=f"deviation {worst:.2e} mm, speed ratio - 1 = {ratio:.2e}",
        passed=ok,
    )


def check_sub_moves() -> ClaimResult:
    s = study("S1")
    pa, _, pb, _ = s.ends
    devs = [
        max(
            move_deviation(s.machine, mv, pa, pb)
            for mv in nonlinear_submoves(s.machine, s.nonlinear(), N)
        )
        for N in (4, 16, 64)
    ]
    return _all(
        [
            close(0.0874, devs[0], rtol=0.01),
            close(0.00547, devs[1], rtol=0.01),
            close(0.000342, devs[2], rtol=0.01),
        ]
    )


def check_fixed_normal() -> ClaimResult:
    s = study("S1")
    pa, na, pb, nb = s.ends
    mv = fixed_normal_moves(s.machine, pa, na, pb, nb, float(s.qa[3]))
    dev = move_deviation(s.machine, mv)
    off = math.degrees(off_normal_max(s.machine, s.task, [mv], samples=1025))
    half = 0.5 * math.degrees(float(angle_between(na, nb)))
    r = _all(
        [
            close(half, off, atol=1e-6),
            close(1.645, off, atol=0.001),
            at_most(1e-9, dev, "deviation "),
        ]
    )
    r.expected = (
        "beam error = half the angle between end normals (1.645 deg), point on the chord: "
        + r.expected
    )
    return r


def check_near_vertical_original() -> ClaimResult:
    s = study("S4", "original")
    dC = math.degrees(s.qb[3] - s.qa[3])
    lin = move_deviation(s.machine, s.linear())
    bis = adaptive("S4", "original")
    nl = s.nonlinear()
    xy = axis_path_length(s.machine, [nl], slice(0, 2))
    beam = math.degrees(off_normal_max(s.machine, s.task, [nl]))
    mid = mean_normal(s.ends[1], s.ends[3])
    az = math.degrees(math.atan2(mid[0], mid[1]) % (2 * math.pi))
    ok = (
        abs(dC + 198.925) < 0.01
        and abs(lin - 243.5) < 0.1
        and not bis.converged
        and bis.worst_mm > 400
        and abs(xy - 693.3) < 0.5
        and abs(beam - 2.029) < 0.002
        and az == 0.0
    )
    return ClaimResult(
        expected="S4, C in [0, 2pi): dC = -198.9 deg, linear 243.5 mm, mid normal azimuth 0 = 2pi, bisection never "
        "converges (worst > 400 mm), nonlinear: XY travel 693 mm, beam error 2.03 deg",
        got=f"dC = {dC:.3f} deg, linear {lin:.1f} mm, azimuth {az:g}, bisection {len(bis.moves)} pieces depth "
        f"{bis.max_depth} worst {bis.worst_mm:.0f} mm, XY travel {xy:.1f} mm, beam {beam:.3f} deg",
        passed=ok,
    )


def check_near_vertical_improved() -> ClaimResult:
    s = study("S4", "improved")
    dC = math.degrees(s.qb[3] - s.qa[3])
    dB = math.degrees(s.qb[4] - s.qa[4])
    lin = move_deviation(s.machine, s.linear())
    lv = uniform_levels("S4", "improved")
    bis = adaptive("S4", "improved")
    nl = s.nonlinear()
    xy = axis_path_length(s.machine, [nl], slice(0, 2))
    beam = math.degrees(off_normal_max(s.machine, s.task, [nl]))
    ok = (
        abs(dC + 18.925) < 0.01
        and abs(dB + 3.484) < 0.01
        and abs(lin - 1.509) < 0.001
        and abs(lv[1] - 41.4) < 0.1
        and bis.converged
        and (len(bis.moves), bis.max_depth) == (122, 9)
        and abs(xy - 78.1) < 0.1
        and abs(beam - 0.286) < 0.002
    )
    return ClaimResult(
        expected="S4, B in (-pi/4, pi/4), C free: dC = -18.9, dB = -3.48 deg, linear 1.509 mm, first split 41.4 mm, "
        "bisection converges with 122 pieces / depth 9, nonlinear XY travel 78.1 mm, beam error 0.286 deg",
        got=f"dC = {dC:.3f}, dB = {dB:.3f} deg, linear {lin:.3f} mm, first split {lv[1]:.1f} mm, bisection "
        f"{len(bis.moves)} / {bis.max_depth}, XY travel {xy:.1f} mm, beam {beam:.3f} deg",
        passed=ok,
    )


def check_backwards() -> ClaimResult:
    s = study("S4", "improved")
    pa, na, pb, nb = s.ends
    back = [
        moves_backwards(s.machine, bisect_uniform(s.machine, pa, na, s.qa, pb, nb, d), pa, pb)
        for d in range(1, 7)
    ]
    ordinary = []
    for name in ("S1", "S2", "S3"):
        t = study(name)
        a, an, b, bn = t.ends
        ordinary.append(
            moves_backwards(t.machine, bisect_uniform(t.machine, a, an, t.qa, b, bn, 2), a, b)
        )
    return ClaimResult(
        expected="S4 (improved limits) moves backwards at bisection levels 1-6; S1-S3 never",
        got=f"S4 levels 1-6: {back}; S1-S3 level 2: {ordinary}",
        passed=all(back) and not any(ordinary),
    )


def check_limits_circle() -> ClaimResult:
    out = {}
    for limits in ("original", "improved"):
        m = Machine5(limits=limits)  # type: ignore[arg-type]
        task = make_task(Paraboloid(), "circle", 32, radius=300.0)
        qs = translate(m, task)
        devs = [
            move_deviation(m, linear_move(qs[i], qs[i + 1], task.points[i], task.points[i + 1]))
            for i in range(32)
        ]
        spin = max(abs(math.degrees(qs[i + 1][3] - qs[i][3])) for i in range(32))
        out[limits] = (max(devs), spin)
    ok = (
        out["original"][1] > 340
        and out["original"][0] > 100
        and out["improved"][1] < 12
        and out["improved"][0] < 1.5
    )
    return ClaimResult(
        expected="circle r = 300 mm, 32 segments, linear interpolation: original limits spin C by 348.75 deg on the "
        "segment crossing 2pi (deviation > 100 mm); improved limits: 11.25 deg per segment, < 1.5 mm",
        got=f"original: spin {out['original'][1]:.2f} deg, {out['original'][0]:.1f} mm; "
        f"improved: spin {out['improved'][1]:.2f} deg, {out['improved'][0]:.3f} mm",
        passed=ok,
    )


def check_method1_rule() -> ClaimResult:
    """Method 1 admissible iff angle(n0, n1) <= 2 eps: the mean normal is within eps of both ends."""
    worst = 0.0
    for name in SEGMENTS:
        s = study(name)
        _, na, _, nb = s.ends
        nm = mean_normal(na, nb)
        half = 0.5 * float(angle_between(na, nb))
        worst = max(
            worst,
            abs(float(angle_between(nm, na)) - half),
            abs(float(angle_between(nm, nb)) - half),
        )
    return at_most(1e-12, worst, "| angle(mean, ends) - angle(n0, n1)/2 | ")


# ---------------------------------------------------------------- the lesson


def _preset_duration(values: dict[str, Any]) -> float:
    p = {prm.name: prm.parse(values.get(prm.name, prm.default)) for prm in PARAMS}
    task = task_of(Params(p))
    return float(np.linalg.norm(np.diff(task.points, axis=0), axis=1).sum() / float(p["V"]))


PARAMS: tuple[Param, ...] = (
    Param(
        "method",
        "choice",
        "bisection",
        "controller",
        choices=METHODS,
        group="method",
        help="linear: all axes proportional; bisection: method 2; nonlinear: interpolation (4); fixed-normal: method 1",
    ),
    Param(
        "limits",
        "choice",
        "improved",
        "rotary limits",
        choices=("original", "improved"),
        group="method",
        help="original: C in [0, 2pi), B in [0, pi/2]; improved: B in (-pi/4, pi/4), C free",
    ),
    Param(
        "tolerance_um", "float", 20.0, "tolerance delta_p", "um", 1.0, 1000.0, 1.0, group="method"
    ),
    Param("max_depth", "int", 30, "bisection depth cap", "", 1, 30, 1, group="method"),
    Param(
        "sub_moves",
        "int",
        0,
        "nonlinear as N linear moves (0: exact)",
        "",
        0,
        256,
        1,
        group="method",
    ),
    Param("R_C", "float", 200.0, "C lever R_C", "mm", 0.0, 1000.0, 10.0),
    Param("R_B", "float", 300.0, "B lever R_B", "mm", 10.0, 1000.0, 10.0),
    Param("k_C1", "choice", "1", "sense of C, k_C1", choices=("1", "-1")),
    Param("k_C2", "float", 0.0, "C zero offset k_C2", "rad", -math.pi, math.pi, 0.01),
    Param("k_X", "float", 0.0, "X offset k_X", "mm", -500.0, 500.0, 1.0),
    Param("k_Y", "float", 0.0, "Y offset k_Y", "mm", -500.0, 500.0, 1.0),
    Param("k_Z", "float", 0.0, "Z offset k_Z", "mm", -500.0, 500.0, 1.0),
    Param("V", "float", 50.0, "contour feed V", "mm/s", 0.1, 1000.0, 1.0),
    Param(
        "surface",
        "choice",
        "paraboloid",
        "workpiece",
        choices=("paraboloid", "sphere"),
        group="surface",
    ),
    Param(
        "F", "float", 500.0, "paraboloid focal length F", "mm", 100.0, 5000.0, 10.0, group="surface"
    ),
    Param("R_s", "float", 1000.0, "sphere radius", "mm", 200.0, 5000.0, 10.0, group="surface"),
    Param("path", "choice", "circle", "task path", choices=("line", "circle"), group="initial"),
    Param("u0", "float", 300.0, "start offset u0", "mm", -1000.0, 1000.0, 1.0, group="initial"),
    Param("v0", "float", 0.0, "start offset v0", "mm", -1000.0, 1000.0, 1.0, group="initial"),
    Param("u1", "float", 300.0, "end offset u1", "mm", -1000.0, 1000.0, 1.0, group="initial"),
    Param("v1", "float", 60.0, "end offset v1", "mm", -1000.0, 1000.0, 1.0, group="initial"),
    Param("radius", "float", 300.0, "circle radius", "mm", 1.0, 1000.0, 1.0, group="initial"),
    Param("segments", "int", 32, "task segments", "", 1, 200, 1, group="initial"),
)


def _seg(name: str) -> dict[str, Any]:
    (u0, v0), (u1, v1) = SEGMENTS[name]
    return {
        "path": "line",
        "segments": 1,
        "u0": u0,
        "v0": v0,
        "u1": u1,
        "v1": v1,
        "V": 10.0,
        "limits": "original",
    }


_PRESET_VALUES: list[tuple[str, str, dict[str, Any], str]] = [
    (
        "final-test",
        "Final test: paraboloid dish, circle r = 300 mm, bisection",
        {
            "method": "bisection",
            "limits": "improved",
            "path": "circle",
            "segments": 32,
            "radius": 300.0,
            "V": 50.0,
        },
        "The article's acceptance test machined a parabolic surface; F = 500 mm and the path are assumed.",
    ),
    (
        "segment-linear",
        "Ordinary segment S1: linear interpolation (1.398 mm)",
        {**_seg("S1"), "method": "linear"},
        "All axes proportional: the point sweeps an arc, 70 x the 20 um tolerance.",
    ),
    (
        "segment-bisection",
        "Ordinary segment S1: bisection to 20 um (16 pieces)",
        {**_seg("S1"), "method": "bisection"},
        "",
    ),
    (
        "segment-nonlinear",
        "Ordinary segment S1: nonlinear interpolation",
        {**_seg("S1"), "method": "nonlinear"},
        "The point stays on the chord at constant speed.",
    ),
    (
        "segment-nonlinear-16",
        "S1 nonlinear as 16 linear moves",
        {**_seg("S1"), "method": "nonlinear", "sub_moves": 16},
        "",
    ),
    (
        "segment-fixed-normal",
        "S1 method 1: no rotation, mean normal",
        {**_seg("S1"), "method": "fixed-normal"},
        "",
    ),
    (
        "oblique-linear",
        "Oblique segment S3: linear interpolation (3.06 mm)",
        {**_seg("S3"), "method": "linear"},
        "",
    ),
    (
        "radial-bisection",
        "Radial segment S2: B leads, bisection",
        {**_seg("S2"), "method": "bisection"},
        "",
    ),
    (
        "near-vertical-original",
        "Near-vertical beam S4, original limits: bisection fails",
        {**_seg("S4"), "method": "bisection", "limits": "original"},
        "The mean normal at the split has azimuth 0 = 2 pi: the next piece spins C by almost 360 deg.",
    ),
    (
        "near-vertical-improved",
        "Near-vertical beam S4, improved limits: bisection converges",
        {**_seg("S4"), "method": "bisection", "limits": "improved"},
        "122 pieces; the point moves backwards on the way.",
    ),
    (
        "near-vertical-nonlinear",
        "Near-vertical beam S4, original limits: nonlinear",
        {**_seg("S4"), "method": "nonlinear"},
        "On the chord, but the linear axes travel 693 mm for a 60 mm cut.",
    ),
    (
        "circle-original",
        "Circle with the original limits (C wraps at 2 pi)",
        {
            "method": "linear",
            "limits": "original",
            "path": "circle",
            "segments": 32,
            "radius": 300.0,
        },
        "",
    ),
    (
        "circle-improved",
        "Circle with the improved limits (C free)",
        {
            "method": "linear",
            "limits": "improved",
            "path": "circle",
            "segments": 32,
            "radius": 300.0,
        },
        "",
    ),
    (
        "sphere-dome",
        "Spherical dome, nonlinear interpolation",
        {
            "surface": "sphere",
            "method": "nonlinear",
            "limits": "improved",
            "path": "circle",
            "segments": 24,
            "radius": 400.0,
        },
        "",
    ),
]

PRESETS: tuple[Preset, ...] = tuple(
    Preset(name, title, values, t_end=_preset_duration(values), note=note)
    for name, title, values, note in _PRESET_VALUES
)


class Laser5Axis(Lesson):
    id = "laser-5axis"
    title = "LSP-2000 five-axis laser: linear vs nonlinear interpolation"
    chapter = "Articles"
    problem = "Article 003"
    source = SOURCE
    summary = (
        "A 5-axis laser machine follows a polyline on a paraboloid with the beam along the normal. Linear "
        "interpolation of the axes bows the working point off the segment; bisection, fixed normals and "
        "nonlinear interpolation (4) repair it differently, and the rotary limits decide near the vertical."
    )
    order = 300.0
    params = PARAMS
    presets = PRESETS
    t_end = PRESETS[0].t_end or 40.0
    plots = (
        PlotSpec("Deviation from the programmed segment", ("deviation_um", "tolerance_um"), "um"),
        PlotSpec("Contour speed", ("speed_mm_s", "feed_mm_s"), "mm/s"),
        PlotSpec("Beam off-normal angle", ("off_normal_deg",), "deg"),
        PlotSpec("Axis travel", ("travel_linear_mm", "travel_tool_mm"), "mm"),
        PlotSpec("Rotary axes", ("C_deg", "B_deg"), "deg"),
    )

    # -- parameters ---------------------------------------------------------------

    def validate(self, params: Params) -> None:
        wp = workpiece_of(params)
        if params["path"] == "circle":
            r_max = float(params["radius"])
        else:
            r_max = max(
                math.hypot(float(params["u0"]), float(params["v0"])),
                math.hypot(float(params["u1"]), float(params["v1"])),
            )
            if (
                math.hypot(
                    float(params["u1"]) - float(params["u0"]),
                    float(params["v1"]) - float(params["v0"]),
                )
                < 1e-6
            ):
                raise ParamError("u1", "the path's start and end coincide: nothing to machine")
        if r_max > wp.radius:
            raise ParamError(
                "radius" if params["path"] == "circle" else "u1",
                f"the path reaches {r_max:.0f} mm from the axis; the {wp.name} covers {wp.radius:.0f} mm",
            )
        if (
            params["method"] == "nonlinear"
            and int(params["segments"]) * int(params["sub_moves"]) > MAX_MOVES
        ):
            raise ParamError(
                "sub_moves", f"segments x sub_moves must stay within {MAX_MOVES} CNC moves"
            )
        try:
            translate(machine_of(params), task_of(params))
        except LimitError as exc:
            raise ParamError("limits", f"the task is out of reach: {exc}") from None

    # -- derivation -----------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        X, Y, Z, C, B = sp.symbols("X Y Z C B", real=True)
        R_C, R_B, k1, k2, kX, kY, kZ = sp.symbols("R_C R_B k_C1 k_C2 k_X k_Y k_Z", real=True)
        x, y, z, t = sp.symbols("x y z t", real=True)
        th = sp.Symbol("theta", real=True)
        n = sp.Matrix([sp.sin(B) * sp.sin(th), sp.sin(B) * sp.cos(th), sp.cos(B)])
        nx, ny, nz = sp.symbols("n_x n_y n_z", real=True)
        recon13 = "equations (1) and (2) are lost in the source; rebuilt from the machine description and the tokens of (3)"
        C0, C1, B0, B1, Ct, Bt = sp.symbols("C_0 C_1 B_0 B_1 C_t B_t", real=True)
        return [
            DerivationStep(
                "Frame and tool pose",
                "World axes x, y, z point like the CNC axes X, Y, Z and form a left-handed triple (Z towards the part). "
                "The tool pose is the working point p = (x, y, z) and the unit beam vector n; the working point lies at "
                "the end of the B lever. Axes: X, Y, Z linear; C turns the horizontal lever R_C (C = 0: along Y); "
                "B tilts the lever R_B, which points along Z at B = 0.",
                r"\mathbf q=(X,Y,Z,C,B),\qquad \theta=k_{C1}C+k_{C2}",
                source="text before (1)",
            ),
            DerivationStep(
                "Beam direction",
                "Forward kinematics, orientation part.",
                sp.Eq(sp.Symbol("n"), n, evaluate=False),
                source="(1a)",
                reconstructed=recon13,
            ),
            DerivationStep(
                "Working point",
                "Forward kinematics, position part: C lever plus B lever along the beam.",
                sp.Eq(
                    sp.Matrix([x, y, z]),
                    sp.Matrix(
                        [
                            X + kX + R_C * sp.sin(th) + R_B * n[0],
                            Y + kY + R_C * sp.cos(th) + R_B * n[1],
                            Z + kZ + R_B * n[2],
                        ]
                    ),
                    evaluate=False,
                ),
                source="(1b)",
                reconstructed=recon13,
            ),
            DerivationStep(
                "Rotary axes from the beam (rule 2)",
                "Under the limits the map is one-to-one except for a vertical beam, where infinitely many X, Y, C give "
                "the same pose; the rule's first variant fixes C there (here: keeps the current C, 0 at the start). "
                "Improved limits: of (theta, B) and (theta + pi, -B), shifted by whole turns, the one nearest the previous C.",
                r"B=\arccos n_z,\qquad C=\begin{cases}C^{*} & n_x=n_y=0\\ "
                r"\dfrac{\operatorname{atan2}(n_x,n_y)\bmod 2\pi-k_{C2}}{k_{C1}} & \text{otherwise}\end{cases}",
                source="(2)",
                reconstructed=recon13,
            ),
            DerivationStep(
                "Linear axes from the pose",
                "The inverse for the linear axes; all operators of (3) are lost glyphs.",
                [
                    sp.Eq(X, x - R_B * nx - R_C * sp.sin(k1 * C + k2) - kX),
                    sp.Eq(Y, y - R_B * ny - R_C * sp.cos(k1 * C + k2) - kY),
                    sp.Eq(Z, z - R_B * nz - kZ),
                ],
                source="(3)",
                reconstructed="operator signs lost in the source; chosen to invert (1b)",
            ),
            DerivationStep(
                "Rotary limits",
                "As built: C in [0, 2 pi), B in [0, pi/2]. Best found by simulation (Fig. 5c): B in "
                "(-pi/4, pi/4), C unrestricted, which makes the pose-to-axes map ambiguous.",
                r"C\in[0,2\pi),\;B\in[0,\tfrac{\pi}{2}]\qquad\text{vs}\qquad B\in(-\tfrac{\pi}{4},\tfrac{\pi}{4}),\;C\in\mathbb R",
                source="machine description, Fig. 5",
                reconstructed="the range glyphs (pi, the dash) are lost; read from the surviving digits",
            ),
            DerivationStep(
                "Linear interpolation",
                "The LSP-2000 CNC changes all axes proportionally along a segment; the C and B terms of (1b) "
                "then sweep arcs, so the point bows off the chord by about the arc's sagitta.",
                sp.Eq(
                    sp.Symbol("q(s)"),
                    (1 - sp.Symbol("s")) * sp.Symbol("q_0") + sp.Symbol("s") * sp.Symbol("q_1"),
                ),
                source="§ linear interpolation (Fig. 3)",
            ),
            DerivationStep(
                "Sagitta estimate",
                "Deviation for small angle changes.",
                sp.Eq(
                    sp.Symbol("delta"),
                    (R_C + R_B * sp.sin(B)) * sp.Symbol("Delta_C") ** 2 / 8
                    + R_B * sp.Symbol("Delta_B") ** 2 / 8,
                ),
                source="derived",
                reconstructed="not in the article: the digest's estimate of Fig. 3's deviation",
            ),
            DerivationStep(
                "Method 1: no rotation within a segment",
                "The beam is set along the mean normal and kept; admissible if the end normals differ by at "
                "most twice the tolerance epsilon (then the mean is within epsilon of both). The laser is "
                "switched off and on for every re-orientation.",
                r"\bar{\mathbf n}=\frac{\mathbf n_0+\mathbf n_1}{|\mathbf n_0+\mathbf n_1|},\qquad \angle(\mathbf n_0,\mathbf n_1)\le 2\varepsilon",
                source="method 1",
                reconstructed="'difference of normals within double tolerance' read as an angle",
            ),
            DerivationStep(
                "Method 2: recursive bisection",
                "A segment deviating by more than delta_p is halved; the normal at the split is the mean of the "
                "end normals. The sagitta is quadratic in the angle change, so each split cuts the deviation "
                "to about a quarter. Near the vertical the point can move across and even backwards.",
                r"\mathbf p_m=\tfrac12(\mathbf p_a+\mathbf p_b),\quad \mathbf n_m=\frac{\mathbf n_a+\mathbf n_b}{|\mathbf n_a+\mathbf n_b|},\quad \delta_{k+1}\approx\tfrac14\delta_k",
                source="method 2 (Fig. 4)",
            ),
            DerivationStep(
                "Nonlinear interpolation: the chord",
                "The point moves on the chord with parameter t in [0, 1].",
                sp.Eq(
                    sp.Matrix([sp.Symbol("x_t"), sp.Symbol("y_t"), sp.Symbol("z_t")]),
                    (1 - t) * sp.Matrix(sp.symbols("x_0 y_0 z_0"))
                    + t * sp.Matrix(sp.symbols("x_1 y_1 z_1")),
                    evaluate=False,
                ),
                source="(4)",
            ),
            DerivationStep(
                "Nonlinear interpolation: the leading axis",
                "The rotary axis that changes more leads; t follows from it, the other rotary axis is linear "
                "in t, and (1a), (3) give n_t and X_t, Y_t, Z_t. At constant contour speed t runs uniformly.",
                [sp.Eq(t, (Ct - C0) / (C1 - C0)), sp.Eq(Bt, (1 - t) * B0 + t * B1)],
                source="nonlinear interpolation algorithm",
            ),
            DerivationStep(
                "B leading",
                "By symmetry when B changes more.",
                [sp.Eq(t, (Bt - B0) / (B1 - B0)), sp.Eq(Ct, (1 - t) * C0 + t * C1)],
                source="nonlinear interpolation algorithm",
                reconstructed="implied by the text, not printed",
            ),
        ]

    # -- runs ---------------------------------------------------------------------------

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        prog = build_program(params)
        duration = prog.duration
        t_end = duration if t_end is None else float(t_end)
        per = int(min(200, max(4, math.ceil(TRAIL_SAMPLES / max(len(prog.moves), 1)))))
        cols: dict[str, list[np.ndarray]] = {
            k: []
            for k in ("t", "x", "y", "z", "dev", "off", "speed", "X", "Y", "Z", "C", "B", "piece")
        }
        for k, mv in enumerate(prog.moves):
            if prog.starts[k] > t_end:
                break
            tau = np.linspace(0.0, 1.0, per + 1)[(1 if k else 0) :]
            tt = prog.starts[k] + tau * prog.durations[k]
            if tt[-1] > t_end + 1e-12:  # the run stops inside this move: end exactly at t_end
                cut = (t_end - prog.starts[k]) / prog.durations[k]
                tau = np.append(tau[tau < cut], cut)
                tt = prog.starts[k] + tau * prog.durations[k]
            if not len(tau):
                continue
            s = prog.sample(k, tau)
            cols["t"].append(tt)
            for i, c in enumerate("xyz"):
                cols[c].append(s["p"][:, i])
            for i, c in enumerate(("X", "Y", "Z")):
                cols[c].append(s["q"][:, i])
            cols["C"].append(np.degrees(s["q"][:, 3]))
            cols["B"].append(np.degrees(s["q"][:, 4]))
            cols["dev"].append(s["dev"])
            cols["off"].append(s["off"])
            cols["speed"].append(s["speed"])
            cols["piece"].append(np.full(len(tau), float(k)))
        arr = {k: np.concatenate(v) if v else np.zeros(0) for k, v in cols.items()}
        messages = list(prog.messages)
        if t_end > duration + 1e-9 and len(arr["t"]):
            arr = {k: np.append(v, v[-1]) for k, v in arr.items()}
            arr["t"][-1] = t_end
            arr["speed"][-1] = 0.0
            messages.append(f"the task ends at t = {duration:.3g} s; the tool holds after that")
        elif t_end < duration - 1e-9:
            messages.append(
                f"run stops at t = {t_end:.3g} s of {duration:.3g} s; metrics cover the whole task"
            )
        metrics = program_metrics(prog)
        if prog.method == "fixed-normal":
            metrics["laser_switches"] = prog.task.segments
        series = {
            "x": arr["x"],
            "y": arr["y"],
            "z": arr["z"],
            "deviation_mm": arr["dev"],
            "off_normal_deg": arr["off"],
            "speed_mm_s": arr["speed"],
            "X": arr["X"],
            "Y": arr["Y"],
            "Z": arr["Z"],
            "C_deg": arr["C"],
            "B_deg": arr["B"],
            "piece": arr["piece"],
        }
        return RunResult(self.id, None, params.raw(), arr["t"], series, metrics, messages)

    def stepper(self, params: Params) -> Stepper:
        return LaserStepper(params)

    def scene(self, params: Params) -> SceneSpec:
        wp = workpiece_of(params)
        task = task_of(params)
        surf = wp.mesh()
        meshes = [
            MeshItem(
                "workpiece", to_view(surf.vertices), np.asarray(surf.faces), (120, 160, 220), 0.55
            )
        ]
        bed = _box((3800.0, 3800.0, 80.0), (1500.0, 1500.0, BED_Z - 40.0))
        meshes.append(_mesh("bed", bed, (90, 90, 95), 1.0))
        for y in (-250.0, 3250.0):
            meshes.append(
                _mesh(
                    f"guide_{int(y)}",
                    _box((3800.0, 80.0, 60.0), (1500.0, y, BED_Z + 30.0)),
                    (60, 60, 65),
                    1.0,
                )
            )
        curves = [CurveItem("task path", to_view(task.points), (30, 30, 30), 2.0)]
        step = max(1, len(task.points) // 48)
        for i in range(0, len(task.points), step):
            a = to_view(task.points[i])
            curves.append(
                CurveItem(
                    f"normal {i}",
                    np.array([a, a - 80.0 * to_view(task.normals[i])]),
                    (40, 150, 60),
                    1.5,
                )
            )
        markers = [
            MarkerItem("task points", to_view(task.points), (220, 60, 60), 8.0, "task points")
        ]
        lo = np.array([-400.0, -400.0, BED_Z - 100.0])
        hi = np.array([3400.0, 3400.0, BRIDGE_Z + 1000.0])
        return SceneSpec(
            bounds=(tuple(float(v) for v in lo), tuple(float(v) for v in hi)),  # type: ignore[arg-type]
            meshes=meshes,
            curves=curves,
            markers=markers,
            moving_points={"tool": (230, 40, 40)},
            moving_vectors={"beam": (255, 60, 30), "normal": (40, 160, 60)},
            bodies=machine_bodies(machine_of(params)),
            # the tool-point trail: green within the tolerance, red at twice it and beyond
            trail_color_by={
                "tool": (
                    "deviation_um",
                    float(params["tolerance_um"]),
                    2.0 * float(params["tolerance_um"]),
                )
            },
        )

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "kinematics-round-trip",
                "Forward and inverse kinematics are one-to-one under the limits "
                "(round trip within 1e-9 mm over random poses, both limit variants).",
                "(1)-(3)",
                check_round_trip,
            ),
            Claim(
                "vertical-beam",
                "For a vertical tool there are infinitely many positions of X, Y and C; the first "
                "variant of rule (2) removes the ambiguity.",
                "(2)",
                check_vertical,
            ),
            Claim(
                "linear-deviates",
                "Linear interpolation moves the working point off the segment (Fig. 3), far beyond "
                "the 20 um tolerance on an ordinary segment.",
                "§ linear interpolation",
                check_linear_deviates,
            ),
            Claim(
                "linear-speed",
                "Under linear interpolation the working point's speed is non-uniform.",
                "§ linear interpolation",
                check_speed_nonuniform,
            ),
            Claim(
                "bisection-quarter",
                "Each bisection cuts the deviation to about a quarter.",
                "method 2",
                check_quarter,
            ),
            Claim(
                "bisection-tolerance",
                "Recursive bisection brings ordinary segments within 20 um.",
                "method 2",
                check_bisection_tolerance,
            ),
            Claim(
                "bisection-backwards",
                "Within tolerance-driven splitting the working point can move across the "
                "trajectory and even backwards.",
                "method 2",
                check_backwards,
            ),
            Claim(
                "method1-double-tolerance",
                "Method 1: normals differing by at most twice the tolerance keep the mean "
                "normal within the tolerance of both ends.",
                "method 1",
                check_method1_rule,
            ),
            Claim(
                "fixed-normal",
                "Method 1 keeps the point on the segment; its beam error is half the angle between "
                "the end normals.",
                "method 1",
                check_fixed_normal,
            ),
            Claim(
                "nonlinear-on-segment",
                "Nonlinear interpolation keeps the working point on the segment at constant "
                "contour speed.",
                "(4)",
                check_nonlinear_on_segment,
            ),
            Claim(
                "nonlinear-sub-moves",
                "Executed as N linear moves, the nonlinear path deviates about 1/N^2 "
                "(S1: 0.0874, 0.00547, 0.000342 mm for N = 4, 16, 64).",
                "(4), prototype",
                check_sub_moves,
            ),
            Claim(
                "near-vertical-original",
                "Near the vertical beam with C in [0, 2pi) the bisection does not converge; "
                "the rotary limits had to change.",
                "Fig. 5a",
                check_near_vertical_original,
            ),
            Claim(
                "near-vertical-improved",
                "With B in (-pi/4, pi/4) and C unrestricted the results are best.",
                "Fig. 5c",
                check_near_vertical_improved,
            ),
            Claim(
                "limits-circle",
                "Changing the rotary limits reduces the deviation (a closed path crossing C = 2pi).",
                "Fig. 5",
                check_limits_circle,
            ),
        ]


LESSON = Laser5Axis()
