"""A motion program along a space curve and the linear analyzer that reproduces it.

Textbook §1.1 (and the motion-program journal article).  The curve l (1.1)
(:mod:`analyzer_lab.lessons.analyzers.curves.space_curve`) is
run by arc length s(t) (1.7) of a speed law v(t) (:mod:`analyzer_lab.lessons.analyzers.curves.profiles`): the
time law X(t) = r(omega(s(t))) (1.10), (1.11), with the velocity Xdot = r'/|r'| v(t)
(no numerical differentiation).  The controls (1.15) u_ij = Xdot_i X_j / D,
D = X^2 + Y^2 + Z^2 (1.14), make the linear system (1.5) Xdot = U(t) X reproduce it.

:func:`motion_program` builds, once per parameter set, the time law and the solution of
(1.5) from r(phi0): classical RK4 on a fixed step grid on [0, T] (steps aligned with the
kinks of v(t), the cusps of l and the windows around passes through the origin, and
h max(|U|, turning rate of the tangent) <= STEP_ANGLE), kept as a dense solution (cubic
Hermite with the slopes U X at the steps).  A run and the live view
(:class:`ProgramStepper`) both read this one solution.  Where D vanishes (1.15) divides
by zero and (1.5), which has the zero solution, cannot reach or leave the origin: the
solution is undefined (NaN) in a short window around that time and restarts from the
curve after it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.curves.arclength import CubicHermite
from analyzer_lab.lessons.analyzers.curves.profiles import SpeedProfile, speed_profile
from analyzer_lab.lessons.analyzers.curves.space_curve import CurveModel, curve_model
from analyzer_lab.lessons.kit.contract import ClaimResult, Frame, ParamError, Params, Stepper

#: half-width of the undefined window around a pass through the origin, as a fraction of T
GAP_FRACTION = 1e-3
#: each RK4 step turns the field by at most STEP_ANGLE (rad)
STEP_ANGLE = 0.02
#: the base grid of the steps: about this many nodes on [0, T]
BASE_NODES = 2000
MAX_STEPS_PER_INTERVAL = 400


@dataclass
class Program:
    """The motion program: curve, speed law, singular windows and the solution of (1.5)."""

    curve: CurveModel
    profile: SpeedProfile
    singular_t: tuple[float, ...]  # times where X(t) = 0
    gaps: tuple[tuple[float, float], ...]  # windows where (1.5) is undefined
    cusp_t: tuple[float, ...]  # times where r'(phi) = 0
    steps: np.ndarray | None = None  # the RK4 step grid on [0, T]
    Y: np.ndarray | None = None  # (n, 3) solution of (1.5) at the steps
    F: np.ndarray | None = None  # (n, 3) its slope U Y at the steps
    dense: CubicHermite | None = None  # the solution between the steps

    @property
    def T(self) -> float:
        return self.profile.T

    @property
    def kinks(self) -> tuple[float, ...]:
        """Times where Xdot may jump in slope or direction: kinks of v(t), cusps of l."""
        return tuple(sorted(set(self.profile.breakpoints) | set(self.cusp_t)))

    def law(self, t: np.ndarray) -> dict[str, np.ndarray]:
        """s(t) (1.7), v(t), phi = omega(s), X(t) (1.11), Xdot = r'/|r'| v, D (1.14)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        arc = self.curve.arc
        s, v = self.profile.s(t), self.profile.v(t)
        phi = arc.omega(s)
        X = arc.r(phi)
        V = arc.unit_tangent(phi) * v[:, None]
        V[~np.isfinite(V)] = 0.0  # r' without a limiting direction there
        return {"s": s, "v": v, "phi": phi, "X": X, "V": V, "D": np.einsum("ij,ij->i", X, X)}

    def controls(self, law: dict[str, np.ndarray]) -> np.ndarray:
        """(1.15): U = Xdot X^T / D, shape (N, 3, 3); NaN where D = 0."""
        D = law["D"]
        with np.errstate(all="ignore"):
            U = law["V"][:, :, None] * law["X"][:, None, :] / D[:, None, None]
        U[D <= 0] = np.nan
        return U

    def in_gap(self, t: np.ndarray) -> np.ndarray:
        """True inside a window around a pass through the origin (open intervals)."""
        t = np.asarray(t, dtype=float)
        out = np.zeros(t.shape, dtype=bool)
        for a, b in self.gaps:
            out |= (t > a) & (t < b)
        return out

    def solution(self, t: np.ndarray) -> np.ndarray:
        """The solution of (1.5) at the times ``t`` (N, 3): dense output of the RK4 steps;
        at rest after T; NaN inside the windows around the origin."""
        assert self.dense is not None
        t = np.atleast_1d(np.asarray(t, dtype=float))
        Y = self.dense(t)
        Y[self.in_gap(t)] = np.nan
        return Y


def _base_nodes(prog: Program, samples: int = BASE_NODES) -> np.ndarray:
    """Times on [0, T]: half uniform in time, a quarter uniform in arc length, a quarter
    uniform in the arc-length table's parameter (so a curve whose shape changes fast in
    time is still resolved), an eighth log-spaced, plus the kinks of v(t), the cusps and
    the window edges."""
    T = prog.T
    marks = {0.0, T}
    marks.update(b for b in prog.kinks if 0 < b < T)
    for a, b in prog.gaps:
        marks.update(e for e in (a, b) if 0 < e < T)
    marks_l = sorted(marks)
    half = max(samples // 2, 2)
    parts = [
        np.linspace(a, b, max(2, math.ceil(half * (b - a) / T)) + 1)[:-1]
        for a, b in zip(marks_l[:-1], marks_l[1:])
    ]
    arc = prog.curve.arc
    q = max(samples // 4, 2)
    s_geo = np.concatenate(
        [np.linspace(0.0, arc.S_l, q + 1), arc.s_of_theta(np.linspace(0.0, np.pi, q + 1))]
    )
    t_geo = prog.profile.time_at(s_geo)
    parts.append(t_geo[(t_geo > 0) & (t_geo < T)])
    # log-spaced too: |U| ~ v/|X| may fall like 1/t over many decades of a huge curve
    first = min([b for b in prog.kinks if b > 0] + [T])
    parts.append(np.geomspace(1e-3 * first, T, max(samples // 8, 2)))
    t = np.unique(np.concatenate([*parts, np.array(marks_l)]))
    # drop points crowding a mark or each other (keep the marks)
    keep = np.ones(len(t), dtype=bool)
    is_mark = np.isin(t, np.array(marks_l))
    last = -math.inf
    for i, v in enumerate(t):
        tiny = 1e-12 * max(abs(v), 1e-15 * T)
        if not is_mark[i] and (
            v - last < tiny or (i + 1 < len(t) and is_mark[i + 1] and t[i + 1] - v < tiny)
        ):
            keep[i] = False
        else:
            last = v
    return t[keep]


def step_grid(prog: Program, samples: int = BASE_NODES, angle: float = STEP_ANGLE) -> np.ndarray:
    """The RK4 steps: each interval of the base nodes split so that h * rate <= ``angle``,
    rate = max(|U|, turning rate of the tangent), max-filtered over neighbouring intervals."""
    t = _base_nodes(prog, samples)
    law = prog.law(t)
    with np.errstate(all="ignore"):
        unorm = np.linalg.norm(law["V"], axis=1) / np.sqrt(law["D"])
    unorm = np.where(np.isfinite(unorm), unorm, 0.0)
    tan = prog.curve.arc.unit_tangent(law["phi"])
    dots = np.clip(np.einsum("ij,ij->i", tan[:-1], tan[1:]), -1.0, 1.0)
    width = np.diff(t)
    turn = np.nan_to_num(np.arccos(dots) / np.maximum(width, 1e-300))
    rate = np.maximum(np.maximum(unorm[:-1], unorm[1:]), turn)
    padded = np.concatenate([[rate[0]], rate, [rate[-1]]])
    rate = np.maximum.reduce([padded[:-2], padded[1:-1], padded[2:]])
    m = np.nan_to_num(np.ceil(width * rate / angle), nan=1.0, posinf=MAX_STEPS_PER_INTERVAL)
    m = np.clip(m, 1, MAX_STEPS_PER_INTERVAL).astype(int)
    idx = np.repeat(np.arange(len(width)), m)
    local = np.arange(len(idx)) - np.repeat(np.cumsum(m) - m, m)
    return np.append(t[idx] + width[idx] * local / m[idx], t[-1])


def solve_15(prog: Program, steps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(1.5) with the controls (1.15) by classical RK4, one step per interval of ``steps``,
    from r(phi0): the state Y (n, 3) and its slope U Y at every step.  A step inside a
    window around the origin leaves NaN; on leaving the window (1.5) restarts from X(t)."""
    n = len(steps)
    stages = np.empty(2 * n - 1)
    stages[0::2] = steps
    stages[1::2] = 0.5 * (steps[:-1] + steps[1:])
    law = prog.law(stages)
    D = law["D"]
    with np.errstate(all="ignore"):
        A = np.where(D[:, None] > 0, law["V"] / D[:, None], 0.0)
    Al, Xl = A.tolist(), law["X"].tolist()
    gap = prog.in_gap(stages).tolist()
    Y = np.full((n, 3), np.nan)
    y = [math.nan] * 3 if gap[0] else list(Xl[0])
    Y[0] = y
    for i in range(n - 1):
        j = 2 * i
        if gap[j + 1]:  # suspended; restarted from the curve at the window's end
            y = [math.nan] * 3 if gap[j + 2] else list(Xl[j + 2])
        else:
            if not math.isfinite(y[0]):
                y = list(Xl[j])
            y = _rk4_step(y, steps[i + 1] - steps[i], Al[j : j + 3], Xl[j : j + 3])
        Y[i + 1] = y
    Xs, As = law["X"][0::2], A[0::2]
    return Y, As * np.einsum("ij,ij->i", Xs, Y)[:, None]


def _rk4_step(y: list[float], h: float, a: list[list[float]], x: list[list[float]]) -> list:
    """One RK4 step of y' = a(t) (x(t) . y) (the rank-one field (1.5) + (1.15)); ``a``, ``x``
    at the start, the middle and the end of the step."""
    k = []
    z = y
    for a_j, x_j, w in ((a[0], x[0], 0.5), (a[1], x[1], 0.5), (a[1], x[1], 1.0), (a[2], x[2], 0)):
        c = x_j[0] * z[0] + x_j[1] * z[1] + x_j[2] * z[2]
        kj = [a_j[0] * c, a_j[1] * c, a_j[2] * c]
        k.append(kj)
        z = [y[0] + w * h * kj[0], y[1] + w * h * kj[1], y[2] + w * h * kj[2]]
    return [y[i] + h / 6 * (k[0][i] + 2 * k[1][i] + 2 * k[2][i] + k[3][i]) for i in range(3)]


def check_controls() -> ClaimResult:
    """(1.15) read as u_ij = Xdot_i X_j / D gives U X = Xdot and rank U = 1; the other
    reading X_i Xdot_j / D does not."""
    r1, r2, rank = controls_residuals()
    ok = r1 == sp.zeros(3, 1) and r2 != sp.zeros(3, 1) and rank == 1
    return ClaimResult(
        "U X - Xdot = 0, rank U = 1; alternative reading != 0",
        f"{list(r1)}; alternative zero: {r2 == sp.zeros(3, 1)}",
        bool(ok),
    )


def controls_residuals() -> tuple[sp.Matrix, sp.Matrix, int]:
    """U X - Xdot for (1.15) read as u_ij = Xdot_i X_j / D and for the other reading
    X_i Xdot_j / D (symbolic, simplified), and the rank of the first U."""
    t = sp.Symbol("t", real=True)
    X = sp.Matrix([sp.Function(n)(t) for n in ("X", "Y", "Z")])
    D = (X.T * X)[0]
    U = X.diff(t) * X.T / D
    other = X * X.diff(t).T / D
    return sp.simplify(U * X - X.diff(t)), sp.simplify(other * X - X.diff(t)), U.rank()


@lru_cache(maxsize=32)
def motion_program(
    x: str,
    y: str,
    z: str,
    phi0: float,
    phi1: float,
    v0: float = 1.0,
    Delta0: float = 1.0,
    Delta1: float = 1.0,
    profile: str = "auto",
) -> Program:
    """The program and its (1.5) solution for these values (cached); a bad value raises
    :class:`ParamError` naming it."""
    cm = curve_model(x, y, z, float(phi0), float(phi1))
    try:
        prof = speed_profile(cm.arc.S_l, float(v0), float(Delta0), float(Delta1), profile)
    except ValueError as exc:
        raise ParamError("profile", str(exc)) from None
    ts = tuple(float(v) for v in prof.time_at(np.array(cm.origin_s)))
    half = GAP_FRACTION * prof.T
    cusp_t = tuple(float(v) for v in prof.time_at(np.array(cm.cusp_s)))
    prog = Program(cm, prof, ts, tuple((t - half, t + half) for t in ts), cusp_t)
    prog.steps = step_grid(prog)
    prog.Y, prog.F = solve_15(prog, prog.steps)
    prog.dense = CubicHermite(prog.steps, prog.Y, prog.F)
    return prog


class ProgramStepper(Stepper):
    """The live run of a motion program: frames read the program point X(t) and the
    solution of (1.5) from the program computed once per parameter set, so a frame costs
    one evaluation of the time law and of the dense solution.  ``program`` gives the
    program of the parameters; ``scalars(params, t, Y)`` is the lesson's observation at
    one time (``Y`` the solution there, shape (1, 3)): it must hold the series x, y, z,
    vx, vy, vz and x_analyzer."""

    def __init__(
        self,
        params: Params,
        program: Callable[[Params], Program],
        scalars: Callable[[Params, float, np.ndarray], dict[str, float]],
    ) -> None:
        self._program, self._scalars = program, scalars
        self._t = 0.0
        self._note = ""
        self._use(params)

    def _use(self, params: Params) -> None:
        self._params = params
        self._prog = self._program(params)
        pts = self._prog.curve.samples
        size = max(float(np.max(pts.max(axis=0) - pts.min(axis=0))), 1e-9)
        self._vscale = 0.25 * size / max(self._prog.profile.v1, 1e-12)  # arrow length

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        prog, t = self._prog, self._t
        Y = prog.solution(np.array([t]))
        sc = self._scalars(self._params, t, Y)
        X = np.array([[sc["x"], sc["y"], sc["z"]]])
        V = np.array([[sc["vx"], sc["vy"], sc["vz"]]])
        msgs = [self._note] if self._note else []
        if not math.isfinite(sc["x_analyzer"]) and not self._note:
            msgs.append("(1.5) is suspended near the origin (1.14)")
        if t >= prog.T and not msgs:
            msgs.append(f"the motion is complete at T = {prog.T:.6g}")
        return Frame(
            t=t,
            points={"point": X, "analyzer": np.where(np.isfinite(Y), Y, X)},
            vectors={"velocity": (X, V * self._vscale)},
            scalars=sc,
            message=" ".join(msgs),
        )

    def advance(self, dt: float) -> Frame:
        dt = float(dt)
        if not math.isfinite(dt) or dt <= 0:
            return self.frame()
        a, b = self._t, self._t + dt
        self._t = b
        self._note = ""
        for ts, (g0, g1) in zip(self._prog.singular_t, self._prog.gaps):
            if a < g1 and b > g0:
                self._note = (
                    f"X(t) passes through the origin at t = {ts:.4g}: (1.14) fails, (1.15) divides"
                    " by zero; (1.5) cannot pass the origin, so it is restarted from the curve"
                    f" after t = {g1:.4g}."
                )
        return self.frame()

    def set_params(self, params: Params) -> None:
        old = self._prog
        self._use(params)
        if self._prog is not old:
            self._note = (
                f"parameters changed at t = {self._t:.4g}: the program and (1.5) from r(phi0)"
                " are recomputed for the new values"
            )

    def reset(self) -> Frame:
        self._t = 0.0
        self._note = ""
        return self.frame()


__all__ = [
    "Program",
    "check_controls",
    "controls_residuals",
    "motion_program",
    "solve_15",
    "step_grid",
]
