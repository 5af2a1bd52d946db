"""A space curve typed as formulas of phi (1.1): checks, arc length, special points.

The curve l of textbook §1.1 is x = f1(phi), y = f2(phi), z = f3(phi), phi in
[phi0, phi1] (1.1).  :func:`curve_model` parses the three formulas (never user text
through eval: :mod:`analyzer_lab.lessons.kit.formula`), refuses a coordinate that is not finite or
not continuous on the range (naming it), builds the arc-length table (1.12) and its
inverse (1.13) (:mod:`analyzer_lab.lessons.analyzers.curves.arclength`), and finds the special points a motion
program must know: passes through the origin, where (1.14) fails and (1.15) divides by
zero, and cusps, where r'(phi) = 0 and the tangent may flip.  :func:`nearest_distance`
measures how far points lie from a curve (used to show that (1.2)-(1.4) are one set).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.curves.arclength import ArcLengthCurve
from analyzer_lab.lessons.kit.contract import Formula, Param, ParamError
from analyzer_lab.lessons.kit.formula import FormulaError, parse_formula

PHI = sp.Symbol("phi", real=True)

log = logging.getLogger(__name__)


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


# ------------------------------------------------------------------ the curve


def vector_fn(exprs: list[sp.Expr]) -> Callable[[np.ndarray], np.ndarray]:
    """phi (N,) -> (N, 3): the three expressions of phi, lambdified once."""
    # derivatives of abs() bring sign() and DiracDelta(); the latter is zero almost everywhere
    exprs = [e.replace(sp.DiracDelta, lambda *a: sp.S.Zero) for e in exprs]
    fns = [sp.lambdify([PHI], e, modules="numpy") for e in exprs]

    def f(phi: np.ndarray) -> np.ndarray:
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        out = np.empty(phi.shape + (3,))
        with np.errstate(all="ignore"):
            for k, fn in enumerate(fns):
                out[:, k] = fn(phi)  # a constant broadcasts
        return out

    return f


@dataclass
class CurveModel:
    """The typed curve (1.1): its formulas and arc-length table (with r, r' and the range)."""

    exprs: tuple[sp.Expr, sp.Expr, sp.Expr]
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
    r = vector_fn(list(exprs))
    dr = vector_fn(list(dexprs))
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
            f"arc length (1.12) does not settle (S_l ~ {arc.S_l:.4g}): "
            "the curve may have a pole or a jump in [phi0, phi1]",
        )
    if not arc.S_l > 1e-12:
        raise ParamError("x", "the curve has zero length: x, y, z do not change over [phi0, phi1]")
    s = np.linspace(0.0, arc.S_l, 801)
    pts = arc.point_of_s(s)
    scale = max(1.0, float(np.max(np.linalg.norm(pts, axis=1))))
    origin_s, rmin = _zero_passes(arc, r, dr)
    cusp_s, _ = _zero_passes(arc, dr, vector_fn([sp.diff(e, PHI) for e in dexprs]))
    nonsmooth = any(e.has(sp.sign, sp.Abs, sp.Heaviside) for e in dexprs)
    return CurveModel(exprs, arc, scale, pts, origin_s, rmin, cusp_s, nonsmooth)


def _check_continuous(name: str, f: Formula, phi0: float, phi1: float) -> None:
    """Refuse a coordinate that is not continuous on [phi0, phi1] (a pole, a log of 0, ...)."""
    from sympy.calculus.util import continuous_domain

    whole = sp.Interval(sp.Float(phi0), sp.Float(phi1))
    try:
        dom = continuous_domain(f.expr, PHI, whole)
    except Exception:  # sympy cannot decide: the numeric checks remain
        log.debug("continuity of %s not decided symbolically", name, exc_info=True)
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


def nearest_distance(arc: ArcLengthCurve, pts: np.ndarray) -> np.ndarray:
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


def hausdorff(arcs: list[ArcLengthCurve], n: int = 101) -> float:
    """Sampled two-sided Hausdorff distance between curves (the largest over all pairs):
    ``n`` points of each, uniform in its own parameter, against every other curve."""
    worst = 0.0
    for a in arcs:
        pts = a.r(np.linspace(a.phi0, a.phi1, n))
        for b in arcs:
            if b is not a:
                worst = max(worst, float(np.max(nearest_distance(b, pts))))
    return worst


__all__ = [
    "PHI",
    "CurveFormulaParam",
    "CurveModel",
    "curve_model",
    "hausdorff",
    "nearest_distance",
    "vector_fn",
]
