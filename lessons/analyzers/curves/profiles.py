"""Speed-limit profiles v(t) of a motion program: trapezoid (1.8) and triangle (1.9).

Textbook §1.1 (Fig. 1.1, Fig. 1.2).  The maximum allowed speed modulus is a law
``v = v(t)``: a ramp up of duration ``Delta0``, a constant segment at ``v0`` of
duration ``Delta`` and a ramp down of duration ``Delta1``.  With

    L = S_l - v0 (Delta0 + Delta1) / 2                                  (1.8)

the constant segment lasts ``Delta = L / v0`` when ``L > 0``.  When ``L <= 0`` the
curve is covered in minimum time by the triangle of Fig. 1.2 with rising slope
``k1 = tg(alpha)`` and falling slope ``k2 = tg(beta)``:

    t1 = sqrt(2 S_l k2 / (k1 (k1 + k2))),  tau = (k1 + k2) t1 / k2,
    v1 = sqrt(2 S_l k1 k2 / (k1 + k2))                                  (1.9)

The source gives the slopes only as ``k1 = tg alpha``, ``k2 = tg beta`` (Fig. 1.2); the
lab takes the trapezoid's, ``k1 = v0/Delta0`` and ``k2 = v0/Delta1``, so the two cases
join at ``L = 0`` (there ``v1 = v0``).
The closed forms of ``s(t) = integral of v`` (1.7) are derived here; the source only
says "integrate (1.7)".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import ClaimResult
from analyzer_lab.lessons.kit.once import once
from scipy import integrate

ProfileKind = Literal["trapezoid", "triangle"]
#: the speed-law choices: the source's rule (1.8)/(1.9), or one law forced
PROFILE_CHOICES = ("auto", "trapezoid", "triangle")


@dataclass(frozen=True)
class SpeedProfile:
    """A trapezoid or triangle speed law covering exactly the length ``S_l``.

    Both are stored as a generic trapezoid: ramp up ``rise`` (s), plateau ``flat``
    (s) at the peak ``peak``, ramp down ``fall`` (s).  For the trapezoid
    ``rise, flat, fall, peak = Delta0, Delta, Delta1, v0``; for the triangle
    ``t1, 0, tau - t1, v1``.
    """

    kind: ProfileKind
    S_l: float
    v0: float
    Delta0: float
    Delta1: float
    L: float  # (1.8)
    Delta: float  # constant-speed duration (0 for the triangle)
    T: float  # total time (tau for the triangle)
    t1: float  # time of the peak (start of the plateau)
    tau: float  # end of the motion (== T)
    v1: float  # peak speed (v0 for the trapezoid)
    k1: float  # rising slope v0/Delta0 (inf for an instant ramp)
    k2: float  # falling slope v0/Delta1

    @property
    def rise(self) -> float:
        return self.t1

    @property
    def flat(self) -> float:
        return self.Delta

    @property
    def fall(self) -> float:
        return self.T - self.t1 - self.Delta

    @property
    def peak(self) -> float:
        return self.v1

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Times where the acceleration jumps: 0, end of rise, end of plateau, T."""
        pts = [0.0, self.t1, self.t1 + self.Delta, self.T]
        out: list[float] = []
        for p in pts:
            if not out or p > out[-1]:
                out.append(p)
        return tuple(out)

    # -- the law ------------------------------------------------------------------

    @once
    def _pieces(self) -> tuple[np.ndarray, ...]:
        """Edges 0, t1, t1 + Delta, T and, for the five pieces (before 0, rise, plateau,
        fall, after T): start time, s and v at the start, acceleration."""
        a, c, T, p = self.rise, self.flat, self.T, self.peak
        edges = np.array([0.0, a, a + c, T])
        start = np.array([0.0, 0.0, a, a + c, T])
        s0 = np.array([0.0, 0.0, p * a / 2, p * a / 2 + p * c, self.S_l])
        v0 = np.array([0.0, 0.0, p, p, 0.0])
        acc = np.array(
            [0.0, p / a if a > 0 else 0.0, 0.0, -p / self.fall if self.fall > 0 else 0.0, 0.0]
        )
        return edges, start, s0, v0, acc

    def _piece(self, t: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        edges, start, *_ = self._pieces
        t = np.asarray(t, dtype=float)
        j = np.searchsorted(edges, t, side="right")
        return j, t - start[j]

    def v(self, t: np.ndarray | float) -> np.ndarray:
        """The speed law v(t) (zero before 0 and from T on)."""
        j, tau = self._piece(t)
        _, _, _, v0, acc = self._pieces
        return v0[j] + acc[j] * tau

    def s(self, t: np.ndarray | float) -> np.ndarray:
        """Path covered, s(t) = integral of v over [0, t] (1.7), in closed form."""
        j, tau = self._piece(t)
        _, _, s0, v0, acc = self._pieces
        return s0[j] + tau * (v0[j] + 0.5 * acc[j] * tau)

    def acceleration(self, t: np.ndarray | float) -> np.ndarray:
        """dv/dt (piecewise constant; zero outside the ramps)."""
        j, _ = self._piece(t)
        return self._pieces[4][j]

    def time_at(self, s: np.ndarray | float) -> np.ndarray:
        """Inverse of s(t) on [0, T]: the time when the path ``s`` is reached."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.S_l)
        a, c, T, p = self.rise, self.flat, self.T, self.peak
        s_a = p * a / 2
        s_b = s_a + p * c
        out = np.empty_like(s)
        up = s <= s_a
        out[up] = np.sqrt(2 * a * s[up] / p) if a > 0 else 0.0
        mid = (s > s_a) & (s <= s_b)
        out[mid] = a + (s[mid] - s_a) / p
        down = s > s_b
        out[down] = T - np.sqrt(np.maximum(2 * self.fall * (self.S_l - s[down]) / p, 0.0))
        return out


def trapezoid_L(S_l: float, v0: float, Delta0: float, Delta1: float) -> float:
    """(1.8): the length left for the constant-speed segment."""
    return S_l - v0 / 2 * (Delta0 + Delta1)


def triangle_1_9(S_l: float, k1: float, k2: float) -> tuple[float, float, float]:
    """(1.9) as printed: (t1, tau, v1) for finite positive slopes k1, k2."""
    t1 = math.sqrt(2 * S_l * k2 / (k1 * (k1 + k2)))
    tau = (k1 + k2) / k2 * t1
    v1 = math.sqrt(2 * S_l * k1 * k2 / (k1 + k2))
    return t1, tau, v1


def speed_profile(
    S_l: float, v0: float, Delta0: float, Delta1: float, kind: str = "auto"
) -> SpeedProfile:
    """The speed law of §1.1: trapezoid if L > 0 (1.8), else the minimum-time triangle (1.9).

    The triangle uses the trapezoid's slopes k1 = v0/Delta0, k2 = v0/Delta1.  Written
    with durations, its peak is ``v1 = sqrt(2 S_l v0 / (Delta0 + Delta1))``, reached at
    ``t1 = v1 Delta0 / v0`` and ending at ``tau = v1 (Delta0 + Delta1) / v0``; this equals
    (1.9) for finite slopes and stays defined when one ramp is instantaneous.

    ``kind`` ``"trapezoid"`` or ``"triangle"`` forces one law: the trapezoid needs L > 0;
    the triangle with L > 0 peaks above v0 (it covers the curve faster than the limit allows).
    """
    for name, val in (("S_l", S_l), ("v0", v0), ("Delta0", Delta0), ("Delta1", Delta1)):
        if not math.isfinite(val):
            raise ValueError(f"{name} must be finite, got {float(val)!r}")
    if S_l <= 0:
        raise ValueError(f"the curve length S_l must be positive, got {S_l:g}")
    if v0 <= 0:
        raise ValueError(f"v0 must be positive, got {v0:g}")
    if Delta0 < 0 or Delta1 < 0:
        raise ValueError("ramp durations Delta0, Delta1 must be >= 0")
    if kind not in PROFILE_CHOICES:
        raise ValueError(f"the profile must be one of {', '.join(PROFILE_CHOICES)}; got {kind!r}")
    k1 = v0 / Delta0 if Delta0 > 0 else math.inf
    k2 = v0 / Delta1 if Delta1 > 0 else math.inf
    L = trapezoid_L(S_l, v0, Delta0, Delta1)
    if kind == "trapezoid" and L <= 0:
        raise ValueError(f"a trapezoid needs L > 0 (1.8); here L = {L:.6g}")
    if kind == "trapezoid" or (kind == "auto" and L > 0):
        Delta = L / v0
        T = Delta0 + Delta + Delta1
        return SpeedProfile(
            "trapezoid", S_l, v0, Delta0, Delta1, L, Delta, T, Delta0, T, v0, k1, k2
        )
    if Delta0 + Delta1 <= 0:
        raise ValueError(
            "a triangle needs Delta0 + Delta1 > 0 (its ramps have the slopes v0/Delta)"
        )
    v1 = math.sqrt(2 * S_l * v0 / (Delta0 + Delta1))
    t1 = v1 * Delta0 / v0
    tau = v1 * (Delta0 + Delta1) / v0
    return SpeedProfile("triangle", S_l, v0, Delta0, Delta1, L, 0.0, tau, t1, tau, v1, k1, k2)


def integral_of_v(p: SpeedProfile) -> float:
    """The area under v(t) by adaptive quadrature, piece by piece (independent of s(t))."""
    return sum(
        integrate.quad(lambda t: float(p.v(t)), a, b, epsabs=1e-13, epsrel=1e-13)[0]
        for a, b in zip(p.breakpoints[:-1], p.breakpoints[1:])
    )


def triangle_printed() -> dict[str, sp.Expr]:
    """(1.9) as printed, in symbols S_l, k_1, k_2 (the names :func:`triangle_symbolic` uses)."""
    S, k1, k2 = sp.symbols("S_l k_1 k_2", positive=True)
    t1 = sp.sqrt(2 * S * k2 / (k1 * (k1 + k2)))
    return {"t_1": t1, "tau": (k1 + k2) / k2 * t1, "v_1": sp.sqrt(2 * S * k1 * k2 / (k1 + k2))}


def triangle_symbolic() -> dict[str, sp.Expr]:
    """Solve v1 = k1 t1 = k2 (tau - t1), v1 tau / 2 = S_l for (t1, tau, v1) with sympy (A2)."""
    return dict(_triangle_symbolic())


@lru_cache(maxsize=1)
def _triangle_symbolic() -> tuple[tuple[str, sp.Expr], ...]:
    S, k1, k2 = sp.symbols("S_l k_1 k_2", positive=True)
    t1, tau, v1 = sp.symbols("t_1 tau v_1", positive=True)
    sol = sp.solve(
        [sp.Eq(v1, k1 * t1), sp.Eq(v1, k2 * (tau - t1)), sp.Eq(v1 * tau / 2, S)],
        [t1, tau, v1],
        dict=True,
    )
    if len(sol) != 1:
        raise RuntimeError(f"expected one positive solution, got {sol}")
    return tuple((str(k), v) for k, v in sol[0].items())


# ------------------------------------------------------------------ checks of the laws


def check_covers(S_l: float, v0: float, Delta0: float, Delta1: float) -> ClaimResult:
    """The law covers exactly S_l: integral of v = s(T) = S_l, v <= v0, |dv/dt| <= v0/Delta."""
    p = speed_profile(S_l, v0, Delta0, Delta1)
    area = integral_of_v(p)
    t = np.linspace(0.0, p.T, 20001)
    vmax = float(np.max(p.v(t)))
    acc = p.acceleration(t)
    slopes_ok = np.all(acc <= p.k1 * (1 + 1e-12)) and np.all(-acc <= p.k2 * (1 + 1e-12))
    err = max(abs(area - S_l), abs(float(p.s(p.T)) - S_l))
    return ClaimResult(
        f"integral of v = s(T) = {S_l:.10g}, max v <= v0 = {v0:g}, |dv/dt| <= v0/Delta",
        f"{p.kind}: integral {area:.12g}, s(T) {float(p.s(p.T)):.12g}, max v {vmax:.6g}",
        bool(err < 1e-10 and vmax <= v0 * (1 + 1e-12) and slopes_ok),
    )


def check_numbers(p: SpeedProfile, kind: str, **want: float) -> ClaimResult:
    """The law's kind and numbers (to 1e-9); a triangle also against (1.9) as printed."""
    got = {k: float(getattr(p, k)) for k in want}
    ok = p.kind == kind and all(abs(got[k] - v) < 1e-9 for k, v in want.items())
    if p.kind == "triangle":
        printed = triangle_1_9(p.S_l, p.k1, p.k2)
        ok = ok and max(abs(a - b) for a, b in zip(printed, (p.t1, p.tau, p.v1))) < 1e-12
    return ClaimResult(
        ", ".join([kind, *(f"{k} = {v:.7g}" for k, v in want.items())]),
        ", ".join([p.kind, *(f"{k} = {v:.9g}" for k, v in got.items())]),
        bool(ok),
    )


def check_triangle_formulas() -> ClaimResult:
    """(1.9) as printed = the sympy solution; with the ramps' slopes v1^2 = 2 S_l v0/(D0 + D1)."""
    sol, printed = triangle_symbolic(), triangle_printed()
    diffs = {k: sp.simplify(sp.radsimp(sol[k] - printed[k])) for k in printed}
    S, k1, k2 = sp.symbols("S_l k_1 k_2", positive=True)
    v0, D0, D1 = sp.symbols("v_0 Delta_0 Delta_1", positive=True)
    v1sq = sp.simplify((printed["v_1"] ** 2).subs({k1: v0 / D0, k2: v0 / D1}))
    ok = all(d == 0 for d in diffs.values()) and sp.simplify(v1sq - 2 * S * v0 / (D0 + D1)) == 0
    return ClaimResult(
        "(1.9) - sympy solution = 0 for t1, tau, v1; v1^2 = 2 S_l v0/(Delta0+Delta1)",
        f"{diffs}; v1^2 = {v1sq}",
        bool(ok),
    )


def check_join() -> ClaimResult:
    """At L = 0 (v0 = 1.5, Delta0 = 0.7, Delta1 = 1.3) the triangle is the trapezoid."""
    v0, D0, D1 = 1.5, 0.7, 1.3
    S0 = v0 * (D0 + D1) / 2  # L = 0
    tri = speed_profile(S0, v0, D0, D1)
    near = speed_profile(S0 * (1 + 1e-9), v0, D0, D1)  # L slightly > 0: trapezoid
    t = np.linspace(0.0, tri.T, 2001)
    dv = float(np.max(np.abs(tri.v(t) - near.v(t))))
    ok = (tri.kind, near.kind) == ("triangle", "trapezoid") and dv < 1e-8
    ok = ok and abs(tri.v1 - v0) < 1e-12 and abs(tri.T - (D0 + D1)) < 1e-12
    return ClaimResult(
        "at L = 0: v1 = v0 = 1.5, tau = Delta0 + Delta1 = 2, laws coincide",
        f"{tri.kind}/{near.kind}, v1 = {tri.v1:.12g}, tau = {tri.T:.12g}, max |dv| = {dv:.2g}",
        ok,
    )


__all__ = [
    "PROFILE_CHOICES",
    "ProfileKind",
    "check_covers",
    "check_join",
    "check_numbers",
    "check_triangle_formulas",
    "SpeedProfile",
    "integral_of_v",
    "speed_profile",
    "trapezoid_L",
    "triangle_1_9",
    "triangle_printed",
    "triangle_symbolic",
]
