"""Principle of building a motion program: textbook §1.1, eqs (1.1)-(1.15) (= article 001, (1)-(15)).

A space curve l is typed as x = f1(phi), y = f2(phi), z = f3(phi), phi in [phi0, phi1]
(1.1).  It is reparametrized by arc length (1.12), (1.13), (1.6), then by time with the
speed-limit law v(t) (1.7): a trapezoid (1.8) or, when L <= 0, the minimum-time
triangle (1.9).  The result is the time law X(t), Y(t), Z(t) (1.10), (1.11).  The
controls of the linear system (1.5) are the rank-one matrix (1.15)

    u_ij(t) = Xdot_i(t) X_j(t) / D(t),    D = X^2 + Y^2 + Z^2 != 0   (1.14),

so that U(t) X(t) = Xdot(t): the curve is a phase curve of (1.5).  Here (1.5) is
integrated with these u_ij by the classical fixed-step Runge-Kutta method of order 4
(steps aligned with the kinks of v(t)) and compared with X(t).

Where D vanishes (the curve passes through the origin) (1.15) divides by zero and
(1.5), which has the zero solution, cannot reach or leave the origin: the
integration is suspended in a short window around that time, restarted from the
curve, and the run says so.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
from scipy import integrate

from lessons.core.arclength import ArcLengthCurve
from lessons.core.contract import (
    Claim,
    ClaimResult,
    CurveItem,
    DerivationStep,
    Formula,
    Frame,
    Lesson,
    MarkerItem,
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
from lessons.core.formula import FormulaError, parse_formula
from lessons.core.profiles import SpeedProfile, speed_profile, triangle_1_9, triangle_symbolic

PHI = sp.Symbol("phi", real=True)
SQRT2PI = math.pi * math.sqrt(2.0)

#: half-width of the suspended window around a pass through the origin, as a fraction of T
GAP_FRACTION = 1e-3
#: RK4 steps per output interval at least; each step turns the field by at most STEP_ANGLE
SUBSTEPS = 4
STEP_ANGLE = 0.02
MAX_STEPS_PER_INTERVAL = 400
OUTPUT_SAMPLES = 2000
LIVE_STEPS = 1000


# ------------------------------------------------------------------ parameters


@dataclass(frozen=True)
class CurveFormulaParam(Param):
    """A formula of ``phi`` (a curve coordinate of (1.1)); shown like a formula field."""

    variable: str = "phi"

    def _parse(self, raw: Any) -> Formula:
        if isinstance(raw, Formula):
            if raw.variables == (self.variable,):
                return raw
            raw = raw.text
        if isinstance(raw, bool):
            raise ParamError(self.name, f"expected a formula of {self.variable}, got a boolean")
        if isinstance(raw, (int, float, np.floating, np.integer)):
            if not math.isfinite(float(raw)):
                raise ParamError(self.name, f"must be finite, got {float(raw)}")
            raw = repr(float(raw))
        if not isinstance(raw, str):
            raise ParamError(
                self.name, f"expected a formula of {self.variable}, got {type(raw).__name__}"
            )
        return parse_formula(raw, variables=(self.variable,))


# ------------------------------------------------------------------ the curve and the program


def _vector_fn(exprs: list[sp.Expr]) -> Callable[[np.ndarray], np.ndarray]:
    # derivatives of abs() bring sign() and DiracDelta(); the latter is zero almost everywhere
    exprs = [e.replace(sp.DiracDelta, lambda *a: sp.S.Zero) for e in exprs]
    fns = [sp.lambdify([PHI], e, modules="numpy") for e in exprs]

    def f(phi: np.ndarray) -> np.ndarray:
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        with np.errstate(all="ignore"):
            cols = [np.broadcast_to(np.asarray(fn(phi), dtype=float), phi.shape) for fn in fns]
        return np.stack(cols, axis=1)

    return f


@dataclass
class CurveModel:
    """The typed curve (1.1): formulas, derivatives, arc-length table."""

    texts: tuple[str, str, str]
    exprs: tuple[sp.Expr, sp.Expr, sp.Expr]
    dexprs: tuple[sp.Expr, sp.Expr, sp.Expr]
    phi0: float
    phi1: float
    arc: ArcLengthCurve
    scale: float  # max |r| on the curve (at least 1)
    samples: np.ndarray  # (N, 3) points, uniform in s
    origin_s: tuple[float, ...]  # arc lengths where the curve meets the origin
    min_radius: float  # min |r| on the curve
    cusp_s: tuple[float, ...] = ()  # arc lengths where r'(phi) = 0 (the tangent may flip)
    nonsmooth: bool = False  # the derivative contains sign/abs: corners possible


@lru_cache(maxsize=32)
def curve_model(x: str, y: str, z: str, phi0: float, phi1: float) -> CurveModel:
    """Build (and cache) the curve model; raises ParamError naming the bad coordinate."""
    forms = {}
    for name, text in (("x", x), ("y", y), ("z", z)):
        try:
            forms[name] = parse_formula(text, variables=("phi",))
        except FormulaError as exc:
            raise ParamError(name, str(exc)) from None
    exprs = tuple(forms[n].expr for n in "xyz")
    dexprs = tuple(sp.diff(e, PHI) for e in exprs)
    r = _vector_fn(list(exprs))
    dr = _vector_fn(list(dexprs))
    # values must be finite and real on the closed range (derivatives may blow up at the ends)
    probe = np.concatenate([[phi0, phi1], np.linspace(phi0, phi1, 401)])
    vals = r(probe)
    for k, name in enumerate("xyz"):
        bad = ~np.isfinite(vals[:, k])
        if bad.any():
            raise ParamError(
                name,
                f"{forms[name].text!r} is not a finite real number at phi = {probe[np.argmax(bad)]:.6g}",
            )
    for name in "xyz":
        _check_continuous(name, forms[name], phi0, phi1)
    try:
        arc = ArcLengthCurve(r, dr, phi0, phi1)
    except ValueError as exc:
        raise ParamError("x", f"arc length (1.12) cannot be computed: {exc}") from None
    if arc.table.accuracy > 1e-6 * max(arc.S_l, 1.0):
        raise ParamError(
            "x",
            f"arc length (1.12) does not settle (S_l ~ {arc.S_l:.4g}): the curve may have a pole or a jump in [phi0, phi1]",
        )
    if not arc.S_l > 1e-12:
        raise ParamError("x", "the curve has zero length: x, y, z do not change over [phi0, phi1]")
    s = np.linspace(0.0, arc.S_l, 801)
    pts = arc.point_of_s(s)
    scale = max(1.0, float(np.max(np.linalg.norm(pts, axis=1))))
    origin_s, rmin = _zero_passes(arc, r, dr)
    cusp_s, _ = _zero_passes(arc, dr, _vector_fn([sp.diff(e, PHI) for e in dexprs]))
    nonsmooth = any(e.has(sp.sign, sp.Abs, sp.Heaviside) for e in dexprs)
    return CurveModel(
        (x, y, z),
        exprs,
        dexprs,
        float(phi0),
        float(phi1),
        arc,
        scale,
        pts,
        origin_s,
        rmin,
        cusp_s,
        nonsmooth,
    )


def _check_continuous(name: str, f: Formula, phi0: float, phi1: float) -> None:
    """Refuse a coordinate that is not continuous on [phi0, phi1] (a pole, a log of 0, ...)."""
    from sympy.calculus.util import continuous_domain

    whole = sp.Interval(sp.Float(phi0), sp.Float(phi1))
    try:
        dom = continuous_domain(f.expr, PHI, whole)
    except Exception:  # sympy cannot decide: the numeric checks remain
        return
    missing = sp.Complement(whole, dom)
    if missing.is_empty is not False:
        return
    where = missing.inf
    raise ParamError(
        name,
        f"{f.text!r} is not continuous on [phi0, phi1]: undefined or singular at phi = {float(where):.6g}",
    )


def _zero_passes(
    arc: ArcLengthCurve,
    fn: Callable[[np.ndarray], np.ndarray],
    dfn: Callable[[np.ndarray], np.ndarray],
) -> tuple[tuple[float, ...], float]:
    """Arc lengths where fn(phi) = 0 (fn = r: passes through the origin, the singular case
    of (1.14)/(1.15); fn = r': cusps) and min |fn|.

    Local minima of |fn| on 4097 samples are refined by Gauss-Newton steps
    dphi = -(fn . fn') / |fn'|^2 inside the neighbouring samples; a zero is accepted when
    |fn| drops below 1e-9 of its value at the neighbouring samples.
    """
    th = np.linspace(0.0, np.pi, 4097)
    phis = arc.phi_of_theta(th)
    with np.errstate(all="ignore"):
        rad = np.linalg.norm(fn(phis), axis=1)
    rad = np.where(np.isfinite(rad), rad, np.inf)
    rmin = float(rad.min())
    left = np.concatenate([[np.inf], rad[:-1]])
    right = np.concatenate([rad[1:], [np.inf]])
    cand = np.nonzero((rad <= left) & (rad <= right) & np.isfinite(rad))[0]
    if len(cand) == 0:
        return (), rmin
    lo = phis[np.maximum(cand - 1, 0)]
    hi = phis[np.minimum(cand + 1, len(th) - 1)]
    phi = phis[cand].copy()
    with np.errstate(all="ignore"):
        for _ in range(60):
            f, d = fn(phi), dfn(phi)
            step = -np.einsum("ij,ij->i", f, d) / np.einsum("ij,ij->i", d, d)
            step = np.where(np.isfinite(step), step, 0.0)
            new = np.clip(phi + step, lo, hi)
            if np.all(new == phi):
                break
            phi = new
        val = np.linalg.norm(fn(phi), axis=1)
    val = np.where(np.isfinite(val), val, np.inf)
    rmin = min(rmin, float(val.min()))
    near = np.where(np.isfinite(left[cand]), left[cand], 0.0)
    near = np.maximum(near, np.where(np.isfinite(right[cand]), right[cand], 0.0))
    hit = (val <= 1e-9 * near) | (val == 0.0)
    found: list[float] = []
    for ph in np.sort(phi[hit]):
        s_star = float(arc.s_of_phi(np.array([ph]))[0])
        if s_star < 1e-12 * arc.S_l:
            s_star = 0.0
        elif s_star > (1 - 1e-12) * arc.S_l:
            s_star = arc.S_l
        if not found or abs(s_star - found[-1]) > 1e-9 * arc.S_l:
            found.append(s_star)
    return tuple(found), rmin


@dataclass
class Program:
    """The motion program: curve model + speed law + singular windows."""

    curve: CurveModel
    profile: SpeedProfile
    singular_t: tuple[float, ...]
    gaps: tuple[tuple[float, float], ...]
    cusp_t: tuple[float, ...] = ()
    rate_t: np.ndarray | None = None  # times of the rate table
    rate: np.ndarray | None = None  # max(|U|, turning rate of the tangent) near each time

    @property
    def T(self) -> float:
        return self.profile.T

    @property
    def kinks(self) -> tuple[float, ...]:
        """Times where Xdot may jump in slope or direction: kinks of v(t), cusps of l."""
        return tuple(sorted(set(self.profile.breakpoints) | set(self.cusp_t)))

    def substeps(self, nodes: np.ndarray, minimum: int = 1) -> np.ndarray:
        """RK4 steps per interval of ``nodes`` so that h * rate <= STEP_ANGLE."""
        nodes = np.asarray(nodes, dtype=float)
        w = np.diff(nodes)
        if self.rate_t is None or self.rate is None:
            return np.full(w.shape, max(minimum, SUBSTEPS), dtype=int)
        r = np.maximum(
            np.interp(nodes[:-1], self.rate_t, self.rate),
            np.interp(nodes[1:], self.rate_t, self.rate),
        )
        r = np.maximum(r, np.interp(0.5 * (nodes[:-1] + nodes[1:]), self.rate_t, self.rate))
        m = np.ceil(w * r / STEP_ANGLE)
        return np.clip(
            np.nan_to_num(m, nan=1.0, posinf=MAX_STEPS_PER_INTERVAL),
            minimum,
            MAX_STEPS_PER_INTERVAL,
        ).astype(int)

    def state(self, t: np.ndarray) -> dict[str, np.ndarray]:
        """X(t) (1.11), Xdot(t) = r'/|r'| v(t), s(t), phi, D, v(t) at the times ``t``."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        arc = self.curve.arc
        s = self.profile.s(t)
        theta = arc.theta_of_s(s)
        phi = arc.phi_of_theta(theta)
        X = arc.r(phi)
        v = self.profile.v(t)
        tan = arc.unit_tangent_theta(theta)
        V = np.where(v[:, None] > 0, tan * v[:, None], 0.0)
        V = np.nan_to_num(V)
        D = np.einsum("ij,ij->i", X, X)
        return {"t": t, "s": s, "phi": phi, "X": X, "V": V, "v": v, "D": D, "tangent": tan}

    def controls(self, st: dict[str, np.ndarray]) -> np.ndarray:
        """(1.15): U = Xdot X^T / D, shape (N, 3, 3); NaN where D = 0."""
        D = st["D"]
        with np.errstate(all="ignore"):
            U = st["V"][:, :, None] * st["X"][:, None, :] / D[:, None, None]
        U[D <= 0] = np.nan
        return U

    def in_gap(self, t: float) -> bool:
        return any(a < t < b for a, b in self.gaps)


@lru_cache(maxsize=32)
def _program(
    x: str, y: str, z: str, phi0: float, phi1: float, v0: float, Delta0: float, Delta1: float
) -> Program:
    cm = curve_model(x, y, z, phi0, phi1)
    prof = speed_profile(cm.arc.S_l, v0, Delta0, Delta1)
    ts = tuple(float(v) for v in prof.time_at(np.array(cm.origin_s))) if cm.origin_s else ()
    half = GAP_FRACTION * prof.T
    gaps = tuple((t - half, t + half) for t in ts)
    cusp_t = tuple(float(v) for v in prof.time_at(np.array(cm.cusp_s))) if cm.cusp_s else ()
    prog = Program(cm, prof, ts, gaps, cusp_t)
    t = _output_nodes(prog, prof.T, OUTPUT_SAMPLES)
    st = prog.state(t)
    with np.errstate(all="ignore"):
        unorm = np.linalg.norm(st["V"], axis=1) / np.sqrt(st["D"])
    unorm = np.where(np.isfinite(unorm), unorm, 0.0)
    dots = np.clip(np.einsum("ij,ij->i", st["tangent"][:-1], st["tangent"][1:]), -1.0, 1.0)
    turn = np.nan_to_num(np.arccos(dots) / np.maximum(np.diff(t), 1e-300))
    per_int = np.maximum(np.maximum(unorm[:-1], unorm[1:]), turn)
    padded = np.concatenate([[per_int[0]], per_int, [per_int[-1]]])
    rate = np.maximum.reduce([padded[:-2], padded[1:-1], padded[2:]])  # max-filter
    node_rate = np.concatenate([[rate[0]], np.maximum(rate[:-1], rate[1:]), [rate[-1]]])
    prog.rate_t, prog.rate = t, node_rate
    return prog


def program_of(params: Params) -> Program:
    return _program(
        params["x"].text,
        params["y"].text,
        params["z"].text,
        float(params["phi0"]),
        float(params["phi1"]),
        float(params["v0"]),
        float(params["Delta0"]),
        float(params["Delta1"]),
    )


def program_from(
    x: str,
    y: str,
    z: str,
    phi0: float,
    phi1: float,
    v0: float = 1.0,
    Delta0: float = 1.0,
    Delta1: float = 1.0,
) -> Program:
    """Build a program from text (used by claims and tests)."""
    return _program(x, y, z, float(phi0), float(phi1), float(v0), float(Delta0), float(Delta1))


# ------------------------------------------------------------------ integrating (1.5)


def integrate_15(
    prog: Program, nodes: np.ndarray, y0: np.ndarray, substeps: int | np.ndarray | None = None
) -> np.ndarray:
    """Integrate (1.5) with the controls (1.15) by classical RK4 (fixed steps inside each
    interval of ``nodes``); returns the state at every node (N, 3).

    ``substeps``: RK4 steps per interval (an int, one per interval, or ``None`` for the
    program's own choice: at least :data:`SUBSTEPS`, and h * rate <= :data:`STEP_ANGLE`
    where rate = max(|U|, turning rate of the tangent)).
    Inside a singular window (a pass through the origin) the state is NaN; on leaving
    it (or when the state is NaN) the integration restarts from the curve point X(t).
    Gap edges should be nodes.
    """
    nodes = np.asarray(nodes, dtype=float)
    n = len(nodes)
    widths = np.diff(nodes)
    if substeps is None:
        m_arr = prog.substeps(nodes)
    else:
        m_arr = np.broadcast_to(np.asarray(substeps, dtype=int), widths.shape).astype(int)
    m_arr = np.maximum(m_arr, 1)
    # stage times: for each interval, 2 m + 1 points (shared ends)
    counts = 2 * m_arr
    starts = np.concatenate([[0], np.cumsum(counts)])
    idx = np.repeat(np.arange(n - 1), counts)
    local = np.arange(int(starts[-1])) - starts[idx]
    fine = np.concatenate([nodes[idx] + widths[idx] * local / counts[idx], nodes[-1:]])
    st = prog.state(fine)
    D = st["D"]
    with np.errstate(all="ignore"):
        A = np.where(D[:, None] > 0, st["V"] / D[:, None], 0.0)
    A = A.tolist()
    Xf = st["X"].tolist()
    out = np.full((n, 3), np.nan)
    y = [float(c) for c in y0]
    if not all(math.isfinite(c) for c in y) and not prog.in_gap(float(nodes[0])):
        y = list(Xf[0])
    out[0] = y
    for i in range(n - 1):
        a, b = float(nodes[i]), float(nodes[i + 1])
        if prog.in_gap(0.5 * (a + b)):
            # suspended; restarted from the curve at the window's end
            y = [math.nan] * 3 if prog.in_gap(b) else list(Xf[int(starts[i + 1])])
            out[i + 1] = y
            continue
        base = int(starts[i])
        if not math.isfinite(y[0]):
            y = list(Xf[base])
        m = int(m_arr[i])
        h = (b - a) / m
        for k in range(m):
            j = base + 2 * k
            y = _rk4_step(y, h, A[j], Xf[j], A[j + 1], Xf[j + 1], A[j + 2], Xf[j + 2])
        out[i + 1] = y
    return out


def _rk4_step(
    y: list[float],
    h: float,
    a0: list[float],
    x0: list[float],
    a1: list[float],
    x1: list[float],
    a2: list[float],
    x2: list[float],
) -> list[float]:
    """One RK4 step of y' = a(t) (x(t) . y) (the rank-one field (1.5) + (1.15))."""
    c1 = x0[0] * y[0] + x0[1] * y[1] + x0[2] * y[2]
    k1 = [a0[0] * c1, a0[1] * c1, a0[2] * c1]
    y2 = [y[0] + 0.5 * h * k1[0], y[1] + 0.5 * h * k1[1], y[2] + 0.5 * h * k1[2]]
    c2 = x1[0] * y2[0] + x1[1] * y2[1] + x1[2] * y2[2]
    k2 = [a1[0] * c2, a1[1] * c2, a1[2] * c2]
    y3 = [y[0] + 0.5 * h * k2[0], y[1] + 0.5 * h * k2[1], y[2] + 0.5 * h * k2[2]]
    c3 = x1[0] * y3[0] + x1[1] * y3[1] + x1[2] * y3[2]
    k3 = [a1[0] * c3, a1[1] * c3, a1[2] * c3]
    y4 = [y[0] + h * k3[0], y[1] + h * k3[1], y[2] + h * k3[2]]
    c4 = x2[0] * y4[0] + x2[1] * y4[1] + x2[2] * y4[2]
    k4 = [a2[0] * c4, a2[1] * c4, a2[2] * c4]
    return [y[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]) for i in range(3)]


def _output_nodes(prog: Program, t_end: float, samples: int = OUTPUT_SAMPLES) -> np.ndarray:
    """Sample times on [0, t_end]: half uniform in time, a quarter uniform in arc length, a
    quarter uniform in the arc-length table's parameter (so a curve whose shape changes
    fast in time is still resolved), an eighth log-spaced, plus the kinks of v(t), the cusps
    and the gap edges."""
    marks = {0.0, float(t_end)}
    marks.update(b for b in prog.kinks if 0 < b < t_end)
    for a, b in prog.gaps:
        marks.update(e for e in (a, b) if 0 < e < t_end)
    marks_l = sorted(marks)
    half = max(samples // 2, 2)
    parts = []
    for a, b in zip(marks_l[:-1], marks_l[1:]):
        k = max(2, int(math.ceil(half * (b - a) / t_end)))
        parts.append(np.linspace(a, b, k + 1)[:-1])
    arc = prog.curve.arc
    q = max(samples // 4, 2)
    s_geo = np.concatenate(
        [np.linspace(0.0, arc.S_l, q + 1), arc.s_of_theta(np.linspace(0.0, np.pi, q + 1))]
    )
    t_geo = prog.profile.time_at(s_geo)
    parts.append(t_geo[(t_geo > 0) & (t_geo < t_end)])
    # log-spaced too: |U| ~ v/|X| may fall like 1/t over many decades of a huge curve
    first = min([b for b in prog.kinks if b > 0] + [t_end])
    parts.append(np.geomspace(1e-3 * first, t_end, max(samples // 8, 2)))
    t = np.unique(np.concatenate([*parts, np.array(marks_l)]))
    # drop points crowding a mark or each other (keep the marks)
    keep = np.ones(len(t), dtype=bool)
    is_mark = np.isin(t, np.array(marks_l))
    last = -math.inf
    for i, v in enumerate(t):
        tiny = 1e-12 * max(abs(v), 1e-15 * t_end)
        if not is_mark[i] and (
            v - last < tiny or (i + 1 < len(t) and is_mark[i + 1] and t[i + 1] - v < tiny)
        ):
            keep[i] = False
        else:
            last = v
    return t[keep]


def reproduce(
    prog: Program,
    t_end: float | None = None,
    samples: int = OUTPUT_SAMPLES,
    substeps: int | None = None,
) -> dict[str, np.ndarray]:
    """Program state and (1.5) solution on an output grid (the core of simulate())."""
    t_end = prog.T if t_end is None else float(t_end)
    t = _output_nodes(prog, t_end, samples)
    st = prog.state(t)
    m = prog.substeps(t, SUBSTEPS) if substeps is None else np.full(len(t) - 1, int(substeps))
    Y = integrate_15(prog, t, st["X"][0], m)
    U = prog.controls(st)
    # velocity of the phase point of (1.5): U(t) X5(t)
    V5 = np.einsum("nij,nj->ni", np.nan_to_num(U), Y)
    err = np.linalg.norm(Y - st["X"], axis=1)
    return {**st, "X5": Y, "U": U, "V5": V5, "err": err, "steps": int(np.sum(m))}


# ------------------------------------------------------------------ presets

HELIX_12 = ("sin(phi)", "cos(phi)", "phi", "0", "pi")
HELIX_13 = ("2*sin(phi)*cos(phi)", "2*cos(phi)^2 - 1", "2*phi", "0", "pi/2")
HELIX_14 = ("sqrt(1 - phi^2)", "phi", "acos(phi)", "-1", "1")


def _curve_values(c: tuple[str, str, str, str, str]) -> dict[str, str]:
    return dict(zip(("x", "y", "z", "phi0", "phi1"), c))


PRESETS = (
    Preset(
        "helix-1.2",
        "Helix half-turn (1.2): x = sin phi, y = cos phi, z = phi",
        {**_curve_values(HELIX_12), "v0": 1.0, "Delta0": 1.0, "Delta1": 1.0},
        t_end=6.0,
        note="The source gives no speed-profile numbers; v0 = 1, Delta0 = Delta1 = 1 are illustrative (trapezoid, T = 5.443).",
    ),
    Preset(
        "helix-1.3",
        "Same helix, form (1.3): x = 2 sin phi cos phi, y = 2 cos^2 phi - 1, z = 2 phi",
        {**_curve_values(HELIX_13), "v0": 1.0, "Delta0": 1.0, "Delta1": 1.0},
        t_end=6.0,
        note="(1.3)(phi) = (1.2)(2 phi): the same point set and the same motion.",
    ),
    Preset(
        "helix-1.4",
        "Same helix, form (1.4): x = sqrt(1 - phi^2), y = phi, z = arccos phi",
        {**_curve_values(HELIX_14), "v0": 1.0, "Delta0": 1.0, "Delta1": 1.0},
        t_end=6.0,
        note="(1.4)(phi) = (1.2)(arccos phi): same point set, run in the opposite direction; "
        "|r'|^2 = 2/(1 - phi^2) is singular (integrably) at both ends.",
    ),
    Preset(
        "helix-triangle",
        "Helix (1.2) with a short-curve speed law: triangle (1.9)",
        {**_curve_values(HELIX_12), "v0": 4.0, "Delta0": 2.0, "Delta1": 2.0},
        t_end=3.5,
        note="L = -3.557 < 0: minimum-time triangle, t1 = 1.4905, tau = v1 = 2.9809 (illustrative numbers).",
    ),
    Preset(
        "circle",
        "Circle of radius 2 in the plane z = 1",
        {
            "x": "2*cos(phi)",
            "y": "2*sin(phi)",
            "z": "1",
            "phi0": "0",
            "phi1": "2*pi",
            "v0": 2.0,
            "Delta0": 1.0,
            "Delta1": 1.0,
        },
        t_end=8.0,
    ),
    Preset(
        "spiral",
        "Conical spiral, two turns",
        {
            "x": "(1 + phi/5)*cos(phi)",
            "y": "(1 + phi/5)*sin(phi)",
            "z": "phi/10",
            "phi0": "0",
            "phi1": "4*pi",
            "v0": 2.0,
            "Delta0": 1.0,
            "Delta1": 1.0,
        },
        t_end=16.0,
    ),
    Preset(
        "line",
        "Straight segment from (1, 2, 0) to (3, 0, 1)",
        {
            "x": "1 + phi",
            "y": "2 - phi",
            "z": "phi/2",
            "phi0": "0",
            "phi1": "2",
            "v0": 1.0,
            "Delta0": 0.5,
            "Delta1": 0.5,
        },
        t_end=4.0,
    ),
    Preset(
        "line-through-origin",
        "Segment through the origin: (1.14) fails, (1.15) divides by zero",
        {
            "x": "phi",
            "y": "phi",
            "z": "phi",
            "phi0": "-1",
            "phi1": "1",
            "v0": 1.0,
            "Delta0": 0.5,
            "Delta1": 0.5,
        },
        t_end=4.5,
        note="X(t) passes through 0 at t = 1.982: no phase curve of (1.5) can pass the origin.",
    ),
)


def _scene_size(prog: Program) -> float:
    pts = prog.curve.samples
    return max(float(np.max(pts.max(axis=0) - pts.min(axis=0))), 1e-9)


# ------------------------------------------------------------------ stepper


class MotionStepper(Stepper):
    """Live run: the program point X(t) and the state of (1.5) integrated with (1.15)."""

    def __init__(self, lesson: MotionProgramLesson, params: Params) -> None:
        self._lesson = lesson
        self._params = params
        self._prog = program_of(params)
        self._t = 0.0
        self._y = self._prog.state(np.array([0.0]))["X"][0].copy()
        self._note = ""
        self._restarts = 0
        if self._prog.in_gap(0.0):
            self._y[:] = np.nan

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        return self._lesson._frame(self._prog, self._t, self._y, self._note)

    def advance(self, dt: float) -> Frame:
        dt = float(dt)
        if not math.isfinite(dt) or dt <= 0:
            return self.frame()
        prog = self._prog
        a, b = self._t, self._t + dt
        marks = {a, b}
        marks.update(p for p in prog.kinks if a < p < b)
        for g0, g1 in prog.gaps:
            marks.update(e for e in (g0, g1) if a < e < b)
        h = max(prog.T, 1e-9) / LIVE_STEPS
        ml = sorted(marks)
        nodes = [
            np.linspace(p, q, max(1, int(math.ceil((q - p) / h))) + 1)[:-1]
            for p, q in zip(ml[:-1], ml[1:])
        ]
        nodes_arr = np.concatenate([*nodes, [b]])
        was_nan = not np.all(np.isfinite(self._y))
        if a >= prog.T and np.all(np.isfinite(self._y)):
            Y = self._y[None, :]  # at rest: U = 0 after T
        else:
            Y = integrate_15(prog, nodes_arr, self._y)
        self._y = Y[-1].copy()
        self._t = b
        self._note = ""
        for ts, (g0, g1) in zip(prog.singular_t, prog.gaps):
            if a < g1 and b > g0:
                self._note = (
                    f"X(t) passes through the origin at t = {ts:.4g}: (1.14) fails, (1.15) divides by zero; "
                    "(1.5) cannot pass the origin, so it is restarted from the curve after t = "
                    f"{g1:.4g}."
                )
        if was_nan and np.all(np.isfinite(self._y)):
            self._restarts += 1
        return self.frame()

    def set_params(self, params: Params) -> None:
        new = program_of(params)
        self._params = params
        if new is not self._prog:
            self._prog = new
            self._y = new.state(np.array([self._t]))["X"][0].copy()
            if new.in_gap(self._t):
                self._y[:] = np.nan
            self._note = (
                f"parameters changed: (1.5) restarted from the curve point at t = {self._t:.4g}"
            )

    def reset(self) -> Frame:
        self._t = 0.0
        self._y = self._prog.state(np.array([0.0]))["X"][0].copy()
        if self._prog.in_gap(0.0):
            self._y[:] = np.nan
        self._note = ""
        return self.frame()


# ------------------------------------------------------------------ the lesson

U_NAMES = tuple(f"u{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3))


class MotionProgramLesson(Lesson):
    id = "motion-program"
    title = "Building a motion program along a space curve"
    chapter = "1"
    problem = "§1.1"
    source = "Textbook §1.1, eqs (1.1)-(1.15); article 001, eqs (1)-(15)"
    summary = (
        "A curve given by any parameter phi is reparametrized by arc length, then by time with a "
        "trapezoid or triangle speed law; the rank-one controls u_ij = Xdot_i X_j / D make the "
        "linear system (1.5) reproduce it."
    )
    order = 1.1
    t_end = 6.0
    params = (
        CurveFormulaParam(
            "x",
            "formula",
            HELIX_12[0],
            label="x = f1(phi)",
            group="controls",
            help="formula of phi (1.1)",
        ),
        CurveFormulaParam(
            "y",
            "formula",
            HELIX_12[1],
            label="y = f2(phi)",
            group="controls",
            help="formula of phi (1.1)",
        ),
        CurveFormulaParam(
            "z",
            "formula",
            HELIX_12[2],
            label="z = f3(phi)",
            group="controls",
            help="formula of phi (1.1)",
        ),
        Param(
            "phi0",
            "float",
            "0",
            label="phi0",
            min=-1000.0,
            max=1000.0,
            step=0.01,
            group="initial",
            help="start of the range I",
        ),
        Param(
            "phi1",
            "float",
            "pi",
            label="phi1",
            min=-1000.0,
            max=1000.0,
            step=0.01,
            group="initial",
            help="end of the range I",
        ),
        Param(
            "v0",
            "float",
            1.0,
            label="v0",
            unit="m/s",
            min=1e-3,
            max=1000.0,
            step=0.01,
            group="method",
            help="speed of the constant segment",
        ),
        Param(
            "Delta0",
            "float",
            1.0,
            label="Delta0",
            unit="s",
            min=0.0,
            max=1000.0,
            step=0.01,
            group="method",
            help="acceleration time",
        ),
        Param(
            "Delta1",
            "float",
            1.0,
            label="Delta1",
            unit="s",
            min=0.0,
            max=1000.0,
            step=0.01,
            group="method",
            help="deceleration time",
        ),
    )
    presets = PRESETS
    plots = (
        PlotSpec("Speed |v| of (1.5) and the limit v(t)", ("v", "v_limit"), "m/s"),
        PlotSpec("Arc length s(t) (1.7)", ("s",), "m"),
        PlotSpec("Coordinates X(t), Y(t), Z(t) (1.11)", ("x", "y", "z"), "m"),
        PlotSpec("Controls u_ij(t) (1.15)", U_NAMES, "1/s"),
        PlotSpec("Reproduction error |X5 - X|", ("error",), "m"),
    )

    def validate(self, params: Params) -> None:
        if not float(params["phi1"]) > float(params["phi0"]):
            raise ParamError("phi1", f"must be greater than phi0 = {float(params['phi0']):g}")
        program_of(params)  # raises ParamError naming the coordinate

    # -- simulate -------------------------------------------------------------------

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        prog = program_of(params)
        prof = prog.profile
        t_end = prof.T if t_end is None else float(t_end)
        messages: list[str] = []
        if not t_end > 0:
            raise ParamError("t_end", f"must be positive, got {t_end:g}")
        if t_end < prof.T:
            messages.append(
                f"stopped at t = {t_end:g} before the end of the motion (T = {prof.T:.6g})"
            )
        res = reproduce(prog, t_end)
        t, X, V, Y, U, V5 = res["t"], res["X"], res["V"], res["X5"], res["U"], res["V5"]
        speed5 = np.linalg.norm(V5, axis=1)
        speed5[~np.all(np.isfinite(Y), axis=1)] = np.nan
        vlim = res["v"]
        ok = np.isfinite(res["err"])
        max_err = float(np.max(res["err"][ok])) if ok.any() else math.nan
        excess = float(np.nanmax(speed5 - vlim)) if ok.any() else math.nan
        excess_prog = float(np.max(np.linalg.norm(V, axis=1) - vlim))
        cm = prog.curve
        if cm.arc.table.accuracy > 1e-9 * max(1.0, cm.arc.S_l):
            messages.append(
                f"arc length (1.12) settled only to {cm.arc.table.accuracy:.2g}: the curve is hard to integrate"
            )
        for ts, (g0, g1) in zip(prog.singular_t, prog.gaps):
            messages.append(
                f"X(t) = 0 at t = {ts:.6g}: (1.14) fails and (1.15) divides by zero there; the zero solution "
                f"of (1.5) cannot be left or reached, so (1.5) is suspended on ({max(g0, 0):.4g}, {g1:.4g}) and restarted from the curve"
            )
        for tc in prog.cusp_t:
            messages.append(
                f"r'(phi) = 0 at t = {tc:.6g}: the curve is not regular there (a cusp); the RK4 steps are split there"
            )
        if cm.nonsmooth:
            messages.append(
                "the curve uses abs(): its tangent may jump; RK4 loses accuracy on a step across a corner (see the error)"
            )
        if not prog.singular_t and cm.min_radius < 1e-3 * cm.scale:
            messages.append(
                f"the curve passes at {cm.min_radius:.3g} from the origin (curve size {cm.scale:.3g}): "
                "|u_ij| ~ v/|X| is large there"
            )
        series = {
            "x": X[:, 0],
            "y": X[:, 1],
            "z": X[:, 2],
            "vx": V[:, 0],
            "vy": V[:, 1],
            "vz": V[:, 2],
            "v": speed5,
            "v_limit": vlim,
            "s": res["s"],
            "phi": res["phi"],
            "x5": Y[:, 0],
            "y5": Y[:, 1],
            "z5": Y[:, 2],
            "error": res["err"],
            "D": res["D"],
        }
        gap = np.array([prog.in_gap(float(v)) for v in t], dtype=bool)
        U = U.copy()
        U[gap] = np.nan  # unbounded near the origin: left out of the series
        for k, name in enumerate(U_NAMES):
            series[name] = U[:, k // 3, k % 3]
        umax = float(np.nanmax(np.abs(U))) if np.isfinite(U).any() else math.nan
        metrics: dict[str, Any] = {
            "S_l": cm.arc.S_l,
            "T": prof.T,
            "profile": prof.kind,
            "L": prof.L,
            "Delta": prof.Delta,
            "t1": prof.t1,
            "tau": prof.tau,
            "v1": prof.v1,
            "k1": prof.k1,
            "k2": prof.k2,
            "max_error": max_err,
            "max_error_relative": max_err / cm.scale,
            "max_speed_excess": excess,
            "max_speed_excess_program": excess_prog,
            "min_D": float(np.min(res["D"])),
            "max_abs_u": umax,
            "singular_times": list(prog.singular_t),
            "integrator": (
                f"classical RK4 (order 4), fixed steps: >= {SUBSTEPS} per sample and h max(|U|, tangent turning rate) <= "
                f"{STEP_ANGLE}; steps aligned with the kinks of v(t) and the cusps of l"
            ),
            "rk4_steps": int(res["steps"]),
        }
        return RunResult(self.id, None, params.raw(), t, series, metrics, messages)

    # -- live -----------------------------------------------------------------------

    def stepper(self, params: Params) -> Stepper:
        return MotionStepper(self, params)

    def _frame(self, prog: Program, t: float, y: np.ndarray, note: str) -> Frame:
        st = prog.state(np.array([t]))
        X, V = st["X"][0], st["V"][0]
        U = prog.controls(st)[0]
        msgs = [note] if note else []
        if not np.all(np.isfinite(U)):
            U = np.zeros((3, 3))
            msgs.append("D = 0: (1.15) is undefined at the origin")
        finite = bool(np.all(np.isfinite(y)))
        y_show = y if finite else X
        if not finite and not note:
            msgs.append("(1.5) is suspended near the origin (1.14)")
        v5 = float(np.linalg.norm(U @ y_show)) if finite else float(st["v"][0])
        if t >= prog.T and not msgs:
            msgs.append(f"the motion is complete at T = {prog.T:.6g}")
        size = _scene_size(prog)
        vscale = 0.25 * size / max(prog.profile.v1, 1e-12)
        scalars = {
            "x": float(X[0]),
            "y": float(X[1]),
            "z": float(X[2]),
            "v": v5,
            "v_limit": float(st["v"][0]),
            "s": float(st["s"][0]),
            "error": float(np.linalg.norm(y - X)) if finite else 0.0,
            "D": float(st["D"][0]),
        }
        for k, name in enumerate(U_NAMES):
            scalars[name] = float(U[k // 3, k % 3])
        return Frame(
            t=float(t),
            points={
                "point": X[None, :].copy(),
                "analyzer": np.asarray(y_show, dtype=float)[None, :].copy(),
            },
            vectors={"velocity": (X[None, :].copy(), (V * vscale)[None, :])},
            scalars=scalars,
            message=" ".join(msgs),
        )

    # -- scene ----------------------------------------------------------------------

    def scene(self, params: Params) -> SceneSpec:
        prog = program_of(params)
        pts = prog.curve.samples
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pad = 0.1 * max(float(np.max(hi - lo)), 1.0)
        start, end = pts[0], pts[-1]
        return SceneSpec(
            bounds=(tuple(float(v) for v in lo - pad), tuple(float(v) for v in hi + pad)),  # type: ignore[arg-type]
            curves=[CurveItem("curve l (1.1)", pts.copy(), color=(40, 40, 40), width=2.0)],
            markers=[
                MarkerItem(
                    "start",
                    start[None, :].copy(),
                    color=(30, 160, 60),
                    size=0.06,
                    label="start r(phi0)",
                ),
                MarkerItem(
                    "end", end[None, :].copy(), color=(200, 60, 60), size=0.05, label="end r(phi1)"
                ),
                MarkerItem("origin", np.zeros((1, 3)), color=(120, 120, 120), size=0.04, label="O"),
            ],
            moving_points={"point": (220, 60, 60), "analyzer": (40, 90, 220)},
            moving_vectors={"velocity": (240, 150, 20)},
        )

    # -- derivation -----------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        prog = program_of(params)
        cm, prof = prog.curve, prog.profile
        x, y, z, s, t = sp.symbols("x y z s t", real=True)
        phi0, phi1 = sp.symbols("phi_0 phi_1", real=True)
        S_l, v0, D0, D1, L = sp.symbols("S_l v_0 Delta_0 Delta_1 L", positive=True)
        k1, k2, t1, tau, v1 = sp.symbols("k_1 k_2 t_1 tau v_1", positive=True)
        X, Y, Z = (sp.Function(n)(t) for n in ("X", "Y", "Z"))
        Xv = sp.Matrix([X, Y, Z])
        Dsym = sp.Symbol("D", positive=True)
        speed2 = sum(sp.diff(e, PHI) ** 2 for e in cm.exprs)
        if sp.count_ops(speed2) <= 40:
            speed2 = sp.simplify(speed2)
        tri = triangle_symbolic()
        U = Xv.diff(t) * Xv.T / Dsym
        steps = [
            DerivationStep(
                "The curve l",
                "A space curve given with an arbitrary parameter phi on I = [phi0, phi1]; here the typed one.",
                [sp.Eq(x, cm.exprs[0]), sp.Eq(y, cm.exprs[1]), sp.Eq(z, cm.exprs[2])],
                source="(1.1)",
                reconstructed="(1.1) was lost in extraction; its form follows from the text and from (1.13)",
            ),
            DerivationStep(
                "Example: a helix half-turn",
                "phi in [0, pi].",
                [sp.Eq(x, sp.sin(PHI)), sp.Eq(y, sp.cos(PHI)), sp.Eq(z, PHI)],
                source="(1.2)",
            ),
            DerivationStep(
                "The same helix, second form",
                "phi in [0, pi/2]; (1.3)(phi) = (1.2)(2 phi).",
                [
                    sp.Eq(x, 2 * sp.sin(PHI) * sp.cos(PHI)),
                    sp.Eq(y, 2 * sp.cos(PHI) ** 2 - 1),
                    sp.Eq(z, 2 * PHI),
                ],
                source="(1.3)",
            ),
            DerivationStep(
                "The same helix, third form",
                "phi in [-1, 1]; (1.4)(phi) = (1.2)(arccos phi): the same point set, traversed in the opposite "
                "direction, with |r'|^2 = 2/(1 - phi^2) integrably singular at both ends.",
                [sp.Eq(x, sp.sqrt(1 - PHI**2)), sp.Eq(y, PHI), sp.Eq(z, sp.acos(PHI))],
                source="(1.4)",
                reconstructed="the square root over 1 - phi^2 was lost; without it x^2 + y^2 != 1",
            ),
            DerivationStep(
                "The differential analyzer",
                "A linear system of the 3rd order whose coefficients u_ij(t) are the controls; its phase curve must "
                "start at r(phi0), describe l and only l, and never exceed the speed v(t).",
                sp.Eq(
                    Xv.diff(t), sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"u_{i + 1}{j + 1}")) * Xv
                ),
                source="(1.5)",
                reconstructed="(1.5) was lost in extraction; rebuilt from the text, article 001 and (1.15)",
            ),
            DerivationStep(
                "Arc length",
                f"For this curve |r'(phi)|^2 is shown below; S_l = s(phi1) = {cm.arc.S_l:.12g}. "
                "Numerically: the substitution phi = phi0 + (phi1 - phi0) sin^2(theta/2) removes end-point "
                "singularities such as that of (1.4).",
                [
                    sp.Eq(
                        sp.Function("s")(PHI),
                        sp.Integral(
                            sp.sqrt(
                                sum(
                                    sp.Derivative(sp.Function(f"f_{i}")(PHI), PHI) ** 2
                                    for i in (1, 2, 3)
                                )
                            ),
                            (PHI, phi0, PHI),
                        ),
                    ),
                    sp.Eq(sp.Symbol("|r'|^2"), speed2),
                ],
                source="(1.12)",
                reconstructed="decoded from the scrambled extraction; the radical sign was restored",
            ),
            DerivationStep(
                "Arc-length form",
                "s(phi) increases, so phi = omega(s) exists and x = f1(omega(s)) = x(s), ...",
                [
                    sp.Eq(x, sp.Function("f_1")(sp.Function("omega")(s))),
                    sp.Eq(x, sp.Function("x")(s)),
                ],
                source="(1.13), (1.6)",
            ),
            DerivationStep(
                "Path covered in time",
                "",
                sp.Eq(
                    sp.Function("s")(t),
                    sp.Integral(sp.Function("v")(sp.Symbol("xi")), (sp.Symbol("xi"), 0, t)),
                ),
                source="(1.7)",
            ),
            DerivationStep(
                "Length left for the constant speed",
                f"Here L = {prof.L:.6g}: the profile is a {prof.kind}.",
                sp.Eq(L, S_l - v0 / 2 * (D0 + D1)),
                source="(1.8)",
            ),
            DerivationStep(
                "Trapezoid (L > 0)",
                f"Constant segment Delta = L/v0, total time T = Delta0 + Delta + Delta1 (here T = {prof.T:.6g}).",
                [sp.Eq(sp.Symbol("Delta"), L / v0), sp.Eq(sp.Symbol("T"), D0 + L / v0 + D1)],
                source="(1.8)",
            ),
            DerivationStep(
                "Triangle (L <= 0): minimum time",
                "v1 = k1 t1 = k2 (tau - t1) and v1 tau / 2 = S_l give (1.9).",
                [sp.Eq(t1, tri["t_1"]), sp.Eq(tau, tri["tau"]), sp.Eq(v1, tri["v_1"])],
                source="(1.9)",
                reconstructed="(1.9) is scrambled in the extraction; re-derived (its symbol multiset matches)",
            ),
            DerivationStep(
                "Slopes of the triangle",
                "The source says only k1 = tg alpha, k2 = tg beta; the lab takes the trapezoid's ramps, so "
                "v1^2 = 2 S_l v0 / (Delta0 + Delta1), L <= 0 iff v1 <= v0, and the two cases join at L = 0.",
                [sp.Eq(k1, v0 / D0), sp.Eq(k2, v0 / D1)],
                source="(1.9)",
                reconstructed="slopes not given in the source (ambiguity 14); chosen so the two laws join at L = 0",
            ),
            DerivationStep(
                "s(t) in closed form",
                "Trapezoid: s = v0 t^2/(2 Delta0) on the ramp, v0 Delta0/2 + v0 (t - Delta0) on the plateau, "
                "S_l - v0 (T - t)^2/(2 Delta1) at the end. Triangle: s = k1 t^2/2, then S_l - k2 (tau - t)^2/2.",
                sp.Eq(sp.Function("s")(t), v0 * t**2 / (2 * D0)),
                source="(1.7)",
                reconstructed="the source only says 'integrate (1.7)'; the closed form is derived",
            ),
            DerivationStep(
                "The time law",
                "x(s(t)) = X(t), y(s(t)) = Y(t), z(s(t)) = Z(t): the motion along l at the speed v(t).",
                [sp.Eq(x, X), sp.Eq(y, Y), sp.Eq(z, Z)],
                source="(1.10), (1.11)",
            ),
            DerivationStep(
                "Velocity without numerical differentiation",
                "The unit tangent times the speed law.",
                sp.Eq(Xv.diff(t), sp.Symbol("r'(phi)/|r'(phi)|") * sp.Function("v")(t)),
                source="(1.11)",
                reconstructed="implementation detail, not printed in the source",
            ),
            DerivationStep(
                "No phase curve through the origin",
                f"(1.5) has the zero solution and unique solutions. Here min D = {float(np.min(prog.state(np.linspace(0, prof.T, 401))['D'])):.6g}"
                + (
                    f"; the curve meets the origin at t = {', '.join(f'{v:.6g}' for v in prog.singular_t)}."
                    if prog.singular_t
                    else "."
                ),
                sp.Ne(X**2 + Y**2 + Z**2, 0),
                source="(1.14)",
            ),
            DerivationStep(
                "The controls",
                "u_ij = Xdot_i X_j / D with D = X^2 + Y^2 + Z^2: a rank-one matrix with U X = Xdot, so X(t) solves (1.5). "
                "The dot belongs to the row variable (the other reading fails U X = Xdot).",
                [sp.Eq(sp.Symbol("U"), U), sp.Eq(Dsym, X**2 + Y**2 + Z**2)],
                source="(1.15)",
            ),
        ]
        return steps

    # -- claims ---------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "helix-length-1.2",
                "(1.2) has arc length pi sqrt(2) = 4.442883",
                "(1.2), (1.12)",
                lambda: close(SQRT2PI, helix_length(HELIX_12), atol=1e-9),
            ),
            Claim(
                "helix-length-1.3",
                "(1.3) has arc length pi sqrt(2)",
                "(1.3), (1.12)",
                lambda: close(SQRT2PI, helix_length(HELIX_13), atol=1e-9),
            ),
            Claim(
                "helix-length-1.4",
                "(1.4) has arc length pi sqrt(2) despite |r'|^2 = 2/(1 - phi^2)",
                "(1.4), (1.12)",
                lambda: close(SQRT2PI, helix_length(HELIX_14), atol=1e-9),
            ),
            Claim(
                "helix-same-curve",
                "(1.2), (1.3), (1.4) are one point set (sampled Hausdorff distance <= 1e-9)",
                "(1.2)-(1.4)",
                lambda: at_most(1e-9, helix_hausdorff(), "Hausdorff "),
            ),
            Claim(
                "helix-speeds",
                "|r'|^2 = 2, 8 and 2/(1 - phi^2) for (1.2), (1.3), (1.4); (1.3)(phi) = (1.2)(2 phi), (1.4)(phi) = (1.2)(arccos phi)",
                "(1.2)-(1.4)",
                check_helix_symbolic,
            ),
            Claim(
                "helix-1.4-reversed",
                "(1.4) runs the other way: r_(1.4)(s) = r_(1.2)(S_l - s), start (0, -1, pi)",
                "(1.4)",
                lambda: at_most(1e-9, helix_reversal_gap(), "max distance "),
            ),
            Claim(
                "helix-1.4-radical",
                "with the root x^2 + y^2 = 1 on (1.4); without it (x = 1 - phi^2) x^2 + y^2 = 0.8125 at phi = 0.5",
                "(1.4)",
                check_radical,
            ),
            Claim(
                "trapezoid-numbers",
                "v0 = 1, Delta0 = Delta1 = 1 on the helix: L = 3.442883, T = 5.442883",
                "(1.8)",
                check_trapezoid_numbers,
            ),
            Claim(
                "trapezoid-covers",
                "the trapezoid law covers exactly S_l: integral of v = s(T) = S_l, v <= v0, slopes v0/Delta",
                "(1.7), (1.8)",
                lambda: check_covers(1.0, 1.0, 1.0),
            ),
            Claim(
                "triangle-numbers",
                "v0 = 4, Delta0 = Delta1 = 2 on the helix: L = -3.557117, t1 = 1.490450, tau = v1 = 2.980900",
                "(1.9)",
                check_triangle_numbers,
            ),
            Claim(
                "triangle-covers",
                "the triangle law covers exactly S_l with v1 <= v0 and the ramps' slopes",
                "(1.7), (1.9)",
                lambda: check_covers(4.0, 1.0, 3.0),
            ),
            Claim(
                "triangle-formulas",
                "(1.9) solves v1 = k1 t1 = k2 (tau - t1), v1 tau/2 = S_l",
                "(1.9)",
                check_triangle_symbolic,
            ),
            Claim(
                "profiles-join",
                "at L = 0 the triangle has v1 = v0 and equals the trapezoid (Delta = 0)",
                "(1.8), (1.9)",
                check_join,
            ),
            Claim(
                "controls-identity",
                "U X = Xdot for u_ij = Xdot_i X_j / D; the reading X_i Xdot_j / D fails",
                "(1.15)",
                check_controls_symbolic,
            ),
            Claim(
                "reproduce-trapezoid",
                "(1.5) with (1.15) reproduces the helix, trapezoid law, to 1e-6 (RK4)",
                "(1.5), (1.15)",
                lambda: at_most(1e-6, reproduction_error(1.0, 1.0, 1.0), "max |X5 - X| "),
            ),
            Claim(
                "reproduce-triangle",
                "(1.5) with (1.15) reproduces the helix, triangle law, to 1e-6 (RK4)",
                "(1.5), (1.15)",
                lambda: at_most(1e-6, reproduction_error(4.0, 2.0, 2.0), "max |X5 - X| "),
            ),
            Claim(
                "speed-limit",
                "the speed of (1.5) never exceeds v(t) (within 1e-6)",
                "(1.5), (1.15)",
                lambda: at_most(1e-6, speed_excess(), "max(|U X5| - v) "),
            ),
            Claim(
                "end-point",
                "the motion ends at (0, -1, pi), the end of the helix",
                "(1.2), (1.11)",
                check_end_point,
            ),
            Claim(
                "helix-D",
                "(1.14) holds on the helix: D = 1 + Z^2 >= 1",
                "(1.14)",
                lambda: close(1.0, helix_min_D(), atol=1e-12),
            ),
        ]


# ------------------------------------------------------------------ claim computations


def helix_length(c: tuple[str, str, str, str, str]) -> float:
    from lessons.core.formula import parse_number

    return curve_model(c[0], c[1], c[2], parse_number(c[3]), parse_number(c[4])).arc.S_l


def _helix_arcs() -> list[ArcLengthCurve]:
    from lessons.core.formula import parse_number

    return [
        curve_model(c[0], c[1], c[2], parse_number(c[3]), parse_number(c[4])).arc
        for c in (HELIX_12, HELIX_13, HELIX_14)
    ]


def _nearest_distance(arc: ArcLengthCurve, pts: np.ndarray) -> np.ndarray:
    """Distance from each point to the curve ``arc``: nearest of 4001 samples, then Newton
    on the foot-point condition (r(s) - p) . r_s(s) = 0 (derivative ~1 in arc length)."""
    grid = np.linspace(0.0, arc.S_l, 4001)
    dense = arc.point_of_s(grid)
    d2 = np.sum((pts[:, None, :] - dense[None, :, :]) ** 2, axis=2)
    s = grid[np.argmin(d2, axis=1)]
    for _ in range(30):
        tan = arc.unit_tangent_theta(arc.theta_of_s(s))
        step = np.einsum("ij,ij->i", arc.point_of_s(s) - pts, tan)
        s_new = np.clip(s - step, 0.0, arc.S_l)
        done = np.max(np.abs(s_new - s)) < 1e-15 * max(1.0, arc.S_l)
        s = s_new
        if done:
            break
    return np.linalg.norm(arc.point_of_s(s) - pts, axis=1)


def helix_hausdorff(n: int = 101) -> float:
    """Sampled two-sided Hausdorff distance between the three helix forms (max over pairs)."""
    arcs = _helix_arcs()
    worst = 0.0
    for a in arcs:
        pts = a.r(np.linspace(a.phi0, a.phi1, n))
        for b in arcs:
            if b is not a:
                worst = max(worst, float(np.max(_nearest_distance(b, pts))))
    return worst


def helix_reversal_gap() -> float:
    """max |r_(1.4)(s) - r_(1.2)(S_l - s)| on 2001 samples, and the start point of (1.4)."""
    a12, _, a14 = _helix_arcs()
    s = np.linspace(0.0, a12.S_l, 2001)
    gap = float(np.max(np.linalg.norm(a14.point_of_s(s) - a12.point_of_s(a12.S_l - s), axis=1)))
    start = a14.r(np.array([-1.0]))[0]
    return max(gap, float(np.linalg.norm(start - np.array([0.0, -1.0, math.pi]))))


def check_helix_symbolic() -> ClaimResult:
    f12 = sp.Matrix([sp.sin(PHI), sp.cos(PHI), PHI])
    f13 = sp.Matrix([2 * sp.sin(PHI) * sp.cos(PHI), 2 * sp.cos(PHI) ** 2 - 1, 2 * PHI])
    f14 = sp.Matrix([sp.sqrt(1 - PHI**2), PHI, sp.acos(PHI)])
    sq = [sp.simplify(sum(d**2 for d in f.diff(PHI))) for f in (f12, f13, f14)]
    ok_sq = (
        sp.simplify(sq[0] - 2) == 0
        and sp.simplify(sq[1] - 8) == 0
        and sp.simplify(sq[2] - 2 / (1 - PHI**2)) == 0
    )
    ok_13 = all(
        sp.simplify(sp.expand_trig(a - b)) == 0 for a, b in zip(f13, f12.subs(PHI, 2 * PHI))
    )
    ok_14 = all(sp.simplify(a - b) == 0 for a, b in zip(f14, f12.subs(PHI, sp.acos(PHI))))
    return ClaimResult(
        "|r'|^2 = 2, 8, 2/(1-phi^2); both substitutions exact",
        f"{sq}; (1.3)~(1.2): {ok_13}; (1.4)~(1.2): {ok_14}",
        bool(ok_sq and ok_13 and ok_14),
    )


def check_radical() -> ClaimResult:
    phi = np.linspace(-1.0, 1.0, 201)
    with_root = parse_formula(HELIX_14[0], variables=("phi",))(phi) ** 2 + phi**2
    without = parse_formula("1 - phi^2", variables=("phi",)).value(0.5) ** 2 + 0.5**2
    dev = float(np.max(np.abs(with_root - 1.0)))
    ok = dev < 1e-14 and abs(without - 0.8125) < 1e-15
    return ClaimResult(
        "max |x^2 + y^2 - 1| < 1e-14 with the root; 0.8125 without",
        f"{dev:.2g}; {without:.10g}",
        ok,
    )


def check_trapezoid_numbers() -> ClaimResult:
    p = speed_profile(SQRT2PI, 1.0, 1.0, 1.0)
    ok = (
        p.kind == "trapezoid"
        and abs(p.L - 3.442882938158366) < 1e-9
        and abs(p.T - 5.442882938158366) < 1e-9
    )
    return ClaimResult(
        "trapezoid, L = 3.442883, T = 5.442883", f"{p.kind}, L = {p.L:.9g}, T = {p.T:.9g}", ok
    )


def check_triangle_numbers() -> ClaimResult:
    p = speed_profile(SQRT2PI, 4.0, 2.0, 2.0)
    t1, tau, v1 = triangle_1_9(SQRT2PI, p.k1, p.k2)
    ok = (
        p.kind == "triangle"
        and abs(p.L + 3.557117061841634) < 1e-9
        and abs(p.t1 - 1.4904500894290902) < 1e-9
        and abs(p.tau - 2.9809001788581804) < 1e-9
        and abs(p.v1 - 2.9809001788581804) < 1e-9
        and max(abs(t1 - p.t1), abs(tau - p.tau), abs(v1 - p.v1)) < 1e-12
    )
    return ClaimResult(
        "triangle, L = -3.557117, t1 = 1.490450, tau = v1 = 2.980900, as (1.9) prints",
        f"{p.kind}, L = {p.L:.9g}, t1 = {p.t1:.9g}, tau = {p.tau:.9g}, v1 = {p.v1:.9g}",
        ok,
    )


def check_covers(v0: float, Delta0: float, Delta1: float) -> ClaimResult:
    p = speed_profile(SQRT2PI, v0, Delta0, Delta1)
    area = 0.0
    for a, b in zip(p.breakpoints[:-1], p.breakpoints[1:]):
        area += integrate.quad(lambda t: float(p.v(t)), a, b, epsabs=1e-13, epsrel=1e-13)[0]
    t = np.linspace(0.0, p.T, 20001)
    vmax = float(np.max(p.v(t)))
    acc = p.acceleration(t)
    slopes_ok = np.all(acc <= p.k1 * (1 + 1e-12)) and np.all(-acc <= p.k2 * (1 + 1e-12))
    err = max(abs(area - SQRT2PI), abs(float(p.s(p.T)) - SQRT2PI))
    ok = err < 1e-10 and vmax <= v0 * (1 + 1e-12) and bool(slopes_ok)
    return ClaimResult(
        f"integral of v = s(T) = {SQRT2PI:.10g}, max v <= v0 = {v0:g}, |dv/dt| <= v0/Delta",
        f"{p.kind}: integral {area:.12g}, s(T) {float(p.s(p.T)):.12g}, max v {vmax:.6g}",
        ok,
    )


def check_triangle_symbolic() -> ClaimResult:
    sol = triangle_symbolic()
    S, k1, k2 = sp.symbols("S_l k_1 k_2", positive=True)
    printed = {
        "t_1": sp.sqrt(2 * S * k2 / (k1 * (k1 + k2))),
        "tau": (k1 + k2) / k2 * sp.sqrt(2 * S * k2 / (k1 * (k1 + k2))),
        "v_1": sp.sqrt(2 * S * k1 * k2 / (k1 + k2)),
    }
    diffs = {k: sp.simplify(sp.radsimp(sol[k] - printed[k])) for k in printed}
    ok = all(d == 0 for d in diffs.values())
    v0, D0, D1 = sp.symbols("v_0 Delta_0 Delta_1", positive=True)
    v1sq = sp.simplify((printed["v_1"] ** 2).subs({k1: v0 / D0, k2: v0 / D1}))
    ok = ok and sp.simplify(v1sq - 2 * S * v0 / (D0 + D1)) == 0
    return ClaimResult(
        "(1.9) - sympy solution = 0 for t1, tau, v1; v1^2 = 2 S_l v0/(Delta0+Delta1)",
        f"{diffs}; v1^2 = {v1sq}",
        bool(ok),
    )


def check_join() -> ClaimResult:
    v0, D0, D1 = 1.5, 0.7, 1.3
    S0 = v0 * (D0 + D1) / 2  # L = 0
    tri = speed_profile(S0, v0, D0, D1)
    near = speed_profile(S0 * (1 + 1e-9), v0, D0, D1)  # L slightly > 0: trapezoid
    t = np.linspace(0.0, tri.T, 2001)
    dv = float(np.max(np.abs(tri.v(t) - near.v(t))))
    ok = (
        tri.kind == "triangle"
        and near.kind == "trapezoid"
        and abs(tri.v1 - v0) < 1e-12
        and abs(tri.T - (D0 + D1)) < 1e-12
        and dv < 1e-8
    )
    return ClaimResult(
        "at L = 0: v1 = v0 = 1.5, tau = Delta0 + Delta1 = 2, laws coincide",
        f"{tri.kind}/{near.kind}, v1 = {tri.v1:.12g}, tau = {tri.T:.12g}, max |dv| = {dv:.2g}",
        ok,
    )


def check_controls_symbolic() -> ClaimResult:
    t = sp.Symbol("t", real=True)
    Xv = sp.Matrix([sp.Function(n)(t) for n in ("X", "Y", "Z")])
    D = (Xv.T * Xv)[0]
    U = Xv.diff(t) * Xv.T / D
    U_alt = Xv * Xv.diff(t).T / D
    r1 = sp.simplify(U * Xv - Xv.diff(t))
    r2 = sp.simplify(U_alt * Xv - Xv.diff(t))
    ok = r1 == sp.zeros(3, 1) and r2 != sp.zeros(3, 1) and U.rank() == 1
    return ClaimResult(
        "U X - Xdot = 0, rank U = 1; alternative reading != 0",
        f"{list(r1)}; alternative zero: {r2 == sp.zeros(3, 1)}",
        bool(ok),
    )


def reproduction_error(v0: float, Delta0: float, Delta1: float) -> float:
    prog = program_from(*HELIX_12[:3], 0.0, math.pi, v0, Delta0, Delta1)
    return float(np.nanmax(reproduce(prog)["err"]))


def speed_excess() -> float:
    worst = -math.inf
    for v0, d0, d1 in ((1.0, 1.0, 1.0), (4.0, 2.0, 2.0), (4.0, 1.0, 3.0)):
        prog = program_from(*HELIX_12[:3], 0.0, math.pi, v0, d0, d1)
        r = reproduce(prog)
        worst = max(
            worst,
            float(np.max(np.linalg.norm(r["V5"], axis=1) - r["v"])),
            float(np.max(np.linalg.norm(r["V"], axis=1) - r["v"])),
        )
    return worst


def check_end_point() -> ClaimResult:
    errs = []
    for v0, d0, d1 in ((1.0, 1.0, 1.0), (4.0, 2.0, 2.0)):
        prog = program_from(*HELIX_12[:3], 0.0, math.pi, v0, d0, d1)
        r = reproduce(prog)
        errs.append(float(np.linalg.norm(r["X5"][-1] - np.array([0.0, -1.0, math.pi]))))
    return at_most(1e-6, max(errs), "|X5(T) - (0, -1, pi)| ")


def helix_min_D() -> float:
    prog = program_from(*HELIX_12[:3], 0.0, math.pi, 1.0, 1.0, 1.0)
    return float(np.min(prog.state(np.linspace(0.0, prog.T, 2001))["D"]))


LESSON = MotionProgramLesson()
