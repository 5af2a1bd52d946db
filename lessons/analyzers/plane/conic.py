"""The plane conic analyzer (1.29)-(1.33), (1.40), solved exactly, and its digital form (1.24)-(1.25).

Conic (1.21) in the textbook's 2-D indexing (a13, a23 linear, a33 constant):

    F(x, y) = a11 x² + 2 a12 xy + a22 y² + 2 a13 x + 2 a23 y + a33 = 0          (1.21)

The analyzer moves the point along the level curve of F through its start point:

    dx/dt =  k(t) (a12 x + a22 y + a23) =  k F_y/2
    dy/dt = -k(t) (a11 x + a12 y + a13) = -k F_x/2                                 (1.30)-(1.32)

with k = ω² for the parabola (1.32)-(1.33) (dφ = ω dt, (1.31)) and k = u(t) for the
circle (1.40).  The gain is one scalar, so the point depends on it only through the
argument Θ(t) = ∫0^t k: with r' = A r + c in Θ and A traceless (A² = -D I,
D = a11 a22 - a12²) the solution is closed-form,

    r(Θ) = r0 + Θ f1(DΘ²) w0 + Θ² f2(DΘ²) A w0,   w0 = A r0 + c,

f1 = sin√q/√q, f2 = (1 - cos√q)/q (sinh, cosh for q < 0; 1, 1/2 at q = 0): an ellipse,
a hyperbola or (D = 0, the parabola's nilpotent matrix) a quadratic in Θ.  Θ(t) is
exact for a constant gain and an 8-point Gauss-Legendre sum over 0.01 s panels
otherwise.  :class:`PlanarTrack` holds this solution for one parameter set, so the
headless run and the live view read the same numbers at any time.

The *digital* analyzer replaces each integrator by successive additions (1.25):
y = y0 + ΣΔy, Δz = c·y·Δx.  The argument advances by a quantum Δ per iteration; each
coordinate keeps a remainder register and emits a step pulse of length ``pulse`` (the
basic length unit of a CNC interpolator) whenever the register passes half a pulse, so
the path is a staircase.  Two updates:

* ``simple``  (Euler): both increments from the old coordinates;
* ``improved`` (symplectic Euler): the y increment uses the x already updated.

On the circle x' = y, y' = -x the simple update multiplies the radius by √(1 + Δ²) per
iteration, i.e. by exp(πΔ) ≈ 1 + πΔ per turn (a spiral); the improved update keeps
x² + y² + Δxy exactly, a closed curve within ΔR/4 of the circle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.formula import Formula

CONIC_NAMES: tuple[str, ...] = ("a11", "a12", "a22", "a13", "a23", "a33")
X, Y = sp.symbols("x y", real=True)
DIGITAL_MODES = ("off", "simple", "improved")
#: Most iterations a digital run may take (a smaller Δ or a shorter run is asked for beyond).
MAX_DIGITAL_ITERATIONS = 400_000


def conic_expr(a: Mapping[str, object], x: sp.Symbol = X, y: sp.Symbol = Y) -> sp.Expr:
    """F of (1.21) with coefficients ``a`` (numbers or symbols)."""
    return (
        a["a11"] * x**2
        + 2 * a["a12"] * x * y
        + a["a22"] * y**2
        + 2 * a["a13"] * x
        + 2 * a["a23"] * y
        + a["a33"]
    )


def _gain_values(gain: Formula | float, t: np.ndarray) -> np.ndarray:
    t = np.asarray(t, dtype=float)
    if isinstance(gain, Formula):
        return np.broadcast_to(np.asarray(gain(t), dtype=float), t.shape).astype(float)
    return np.full(t.shape, float(gain))


def gain_expr(gain: Formula | float) -> sp.Expr:
    return gain.expr if isinstance(gain, Formula) else sp.nsimplify(float(gain), rational=True)


def _f1_f2(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """f1 = sin√q/√q and f2 = (1 - cos√q)/q (hyperbolic for q < 0), by series near 0."""
    q = np.asarray(q, dtype=float)
    small = np.abs(q) < 1e-2
    f1 = 1 - q / 6 * (1 - q / 20 * (1 - q / 42 * (1 - q / 72 * (1 - q / 110))))
    f2 = 0.5 - q / 24 * (1 - q / 30 * (1 - q / 56 * (1 - q / 90 * (1 - q / 132))))
    with np.errstate(all="ignore"):
        s = np.sqrt(np.abs(q))
        pos = q > 0
        f1 = np.where(small, f1, np.where(pos, np.sin(s), np.sinh(s)) / np.where(small, 1.0, s))
        big_f2 = np.where(pos, 1 - np.cos(s), np.cosh(s) - 1) / np.abs(np.where(small, 1.0, q))
        f2 = np.where(small, f2, big_f2)
    return f1, f2


def _f1_f2_one(q: float) -> tuple[float, float]:
    """:func:`_f1_f2` at one number (equal to round-off)."""
    if abs(q) < 1e-2:
        f1 = 1 - q / 6 * (1 - q / 20 * (1 - q / 42 * (1 - q / 72 * (1 - q / 110))))
        f2 = 0.5 - q / 24 * (1 - q / 30 * (1 - q / 56 * (1 - q / 90 * (1 - q / 132))))
        return f1, f2
    s = math.sqrt(abs(q))
    if q > 0:
        return math.sin(s) / s, (1 - math.cos(s)) / abs(q)
    try:
        return math.sinh(s) / s, (math.cosh(s) - 1) / abs(q)
    except OverflowError:
        return math.inf, math.inf


@dataclass
class PlanarModel:
    """The conic analyzer for ``N`` family members (coefficients of shape ``(N,)``)."""

    coeffs: dict[str, np.ndarray]
    gain: Formula | float = 1.0

    @classmethod
    def of(
        cls,
        coeffs: Sequence[Mapping[str, float]] | Mapping[str, float],
        gain: Formula | float = 1.0,
    ) -> PlanarModel:
        items = [coeffs] if isinstance(coeffs, Mapping) else list(coeffs)
        return cls({n: np.array([float(c.get(n, 0.0)) for c in items]) for n in CONIC_NAMES}, gain)

    @property
    def size(self) -> int:
        return len(self.coeffs["a11"])

    def through(self, r0: np.ndarray) -> PlanarModel:
        """The same analyzer with a33 chosen so that F(r0) = 0 (the level curve it traces)."""
        r0 = np.atleast_2d(r0)
        c = dict(self.coeffs)
        c["a33"] = np.zeros(len(r0))
        c["a33"] = -PlanarModel(c, self.gain).F(r0)
        return PlanarModel(c, self.gain)

    def F(self, R: np.ndarray) -> np.ndarray:
        return conic_expr(self.coeffs, R[..., 0], R[..., 1])

    def half_gradient(self, R: np.ndarray) -> np.ndarray:
        """(F_x/2, F_y/2) at ``R (..., N, 2)``."""
        c = self.coeffs
        x, y = R[..., 0], R[..., 1]
        return np.stack(
            [c["a11"] * x + c["a12"] * y + c["a13"], c["a12"] * x + c["a22"] * y + c["a23"]],
            axis=-1,
        )

    def scale(self, R: np.ndarray) -> np.ndarray:
        """A natural size of F near the states ``R (m, N, 2)``, one per time (for relative drift)."""
        c = self.coeffs
        q = max(float(np.max(np.abs(c[n]))) for n in ("a11", "a12", "a22"))
        lin = max(float(np.max(np.abs(c[n]))) for n in ("a13", "a23"))
        r = np.max(np.abs(R), axis=(-2, -1))
        return np.maximum(q * r * r + 2 * lin * r + float(np.max(np.abs(c["a33"]))), 1e-300)

    def velocity(self, t: float | np.ndarray, R: np.ndarray) -> np.ndarray:
        """The field at time(s) ``t`` and states ``R (..., N, 2)``."""
        g = self.half_gradient(R)
        k = _gain_values(self.gain, np.asarray(t, dtype=float))
        k = np.reshape(k, np.shape(k) + (1,) * (g.ndim - np.ndim(k)))
        return np.stack([k[..., 0] * g[..., 1], -k[..., 0] * g[..., 0]], axis=-1)

    def flow(self, r0: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """The exact solution from ``r0 (N, 2)`` after the arguments ``theta (m,)``: ``(m, N, 2)``."""
        c = self.coeffs
        th = np.asarray(theta, dtype=float)[:, None, None]
        g = self.half_gradient(r0)
        w0 = np.stack([g[:, 1], -g[:, 0]], axis=-1)  # A r0 + c
        Aw0 = np.stack(
            [c["a12"] * w0[:, 0] + c["a22"] * w0[:, 1], -c["a11"] * w0[:, 0] - c["a12"] * w0[:, 1]],
            axis=-1,
        )
        D = c["a11"] * c["a22"] - c["a12"] ** 2
        f1, f2 = _f1_f2(D[None, :, None] * th**2)
        return r0[None] + th * f1 * w0[None] + th**2 * f2 * Aw0[None]

    def members(self) -> list[list[float]]:
        """a11, a12, a22, a13, a23, a33 of each member as plain numbers (kept)."""
        rows = self.__dict__.get("_members")
        if rows is None:
            cols = [
                np.broadcast_to(np.asarray(self.coeffs[n], float), (self.size,))
                for n in CONIC_NAMES
            ]
            rows = self.__dict__["_members"] = np.stack(cols, axis=1).tolist()
        return rows

    def gain_one(self, t: float) -> float:
        """The gain k at one time (:func:`_gain_values` at ``[t]``)."""
        if isinstance(self.gain, Formula):
            return float(_gain_values(self.gain, np.array([t]))[0])
        return float(self.gain)

    def field_one(self, k: float, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The field (:meth:`velocity`) at the gain ``k`` and the half gradient
        (:meth:`half_gradient`) at the points ``r (N, 2)`` of one time, in plain floats."""
        vel, grad = [], []
        for (x, y), (a11, a12, a22, a13, a23, _) in zip(r.tolist(), self.members()):
            gx, gy = a11 * x + a12 * y + a13, a12 * x + a22 * y + a23
            vel.append([k * gy, -k * gx])
            grad.append([gx, gy])
        return np.array(vel), np.array(grad)

    def drift_one(self, r: list[list[float]]) -> float:
        """max |F| / :meth:`scale` over the points ``r`` (N x [x, y]) of one time."""
        consts = self.__dict__.get("_scale_consts")
        if consts is None:
            c = self.coeffs
            consts = self.__dict__["_scale_consts"] = (
                max(float(np.max(np.abs(c[n]))) for n in ("a11", "a12", "a22")),
                max(float(np.max(np.abs(c[n]))) for n in ("a13", "a23")),
                float(np.max(np.abs(c["a33"]))),
            )
        q, lin, a33 = consts
        if not math.isfinite(sum(x + y for x, y in r)):  # NaN as the arrays have it
            R = np.array(r)[None]
            return float(np.max(np.abs(self.F(R)), axis=1)[0] / self.scale(R)[0])
        F = max(
            abs(conic_expr(dict(zip(CONIC_NAMES, m)), x, y)) for (x, y), m in zip(r, self.members())
        )
        rr = max(max(abs(x), abs(y)) for x, y in r)
        return F / max(q * rr * rr + 2 * lin * rr + a33, 1e-300)

    def flow_one(self, r0: np.ndarray, theta: float) -> np.ndarray:
        """:meth:`flow` after one argument ``theta``: ``(N, 2)``, equal to round-off; the
        per-member constants w0, A w0, D of ``r0`` are kept."""
        cache = self.__dict__.setdefault("_flow_one", {})
        key = r0.tobytes()
        rows = cache.get(key)
        if rows is None:
            rows = []
            for (x, y), (a11, a12, a22, a13, a23, _) in zip(r0.tolist(), self.members()):
                w = (a12 * x + a22 * y + a23, -(a11 * x + a12 * y + a13))  # A r0 + c
                Aw = (a12 * w[0] + a22 * w[1], -a11 * w[0] - a12 * w[1])
                rows.append((x, y, w, Aw, a11 * a22 - a12**2))
            if len(cache) > 8:
                cache.clear()
            cache[key] = rows
        out = []
        for x, y, w, Aw, D in rows:
            f1, f2 = _f1_f2_one(D * theta**2)
            a, b = theta * f1, theta**2 * f2
            out.append([x + a * w[0] + b * Aw[0], y + a * w[1] + b * Aw[1]])
        return np.array(out)

    def equations(
        self, gain: sp.Expr | None = None, names: tuple[str, str] = ("x", "y")
    ) -> list[sp.Eq]:
        """dx/dt, dy/dt of the first member with its numbers (for display)."""
        k = gain_expr(self.gain) if gain is None else gain
        a = {n: sp.nsimplify(float(self.coeffs[n][0]), rational=True) for n in CONIC_NAMES}
        s1, s2 = (sp.Symbol(n, real=True) for n in names)
        rows = (
            k * (a["a12"] * s1 + a["a22"] * s2 + a["a23"]),
            -k * (a["a11"] * s1 + a["a12"] * s2 + a["a13"]),
        )
        return [sp.Eq(sp.Symbol(f"d{n}/dt"), sp.expand(r)) for n, r in zip(names, rows)]


class ArgumentIntegral:
    """Θ(t) = ∫0^t k(s) ds of a gain (a number or a formula of t).

    A formula is summed by 8-point Gauss-Legendre over panels of 0.01 s, computed in
    blocks of 256 panels and kept, so every caller gets the same numbers at the same t.
    """

    PANEL = 0.01
    BLOCK = 256
    NODES, WEIGHTS = np.polynomial.legendre.leggauss(8)

    def __init__(self, gain: Formula | float) -> None:
        self.gain = gain
        self.constant = float(gain) if not isinstance(gain, Formula) else gain.constant_value
        self.cum = np.zeros(1)  # Θ at the panel ends 0, H, 2H, ...

    def _panels(self, t0: np.ndarray, length: np.ndarray) -> np.ndarray:
        s = t0[:, None] + length[:, None] * (self.NODES[None, :] + 1) / 2
        return length / 2 * (_gain_values(self.gain, s) @ self.WEIGHTS)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.constant is not None:
            return self.constant * t
        H = self.PANEL
        j = np.floor(t / H + 1e-12).astype(int)
        while len(self.cum) <= int(j.max()):
            k0 = len(self.cum) - 1
            starts = (k0 + np.arange(self.BLOCK)) * H
            vals = self._panels(starts, np.full(self.BLOCK, H))
            self.cum = np.concatenate([self.cum, self.cum[-1] + np.cumsum(vals)])
        rest = t - j * H
        return self.cum[j] + self._panels(j * H, rest)


@dataclass
class DigitalAnalyzer:
    """The digital differential analyzer (1.25) of a :class:`PlanarModel`.

    State: pulse counters ``n (N, 2)`` (coordinate = start + n·pulse) and remainder
    registers ``acc (N, 2)`` in units of a pulse.  ``pulse = 0`` turns the position
    quantization off (plain successive additions).
    """

    model: PlanarModel
    r0: np.ndarray
    delta: float
    pulse: float = 0.0
    mode: str = "simple"
    n: np.ndarray = field(init=False)
    acc: np.ndarray = field(init=False)
    cont: np.ndarray = field(init=False)
    k: int = field(init=False, default=0)

    def __post_init__(self) -> None:
        if self.mode not in ("simple", "improved"):
            raise ValueError(f"digital mode must be simple or improved, got {self.mode!r}")
        if not (self.delta > 0 and np.isfinite(self.delta)):
            raise ValueError("the quantum delta must be positive")
        self.r0 = np.atleast_2d(np.asarray(self.r0, dtype=float)).copy()
        self.reset()

    def reset(self) -> None:
        self.n = np.zeros_like(self.r0)
        self.acc = np.zeros_like(self.r0)
        self.cont = self.r0.copy()  # unquantized register contents (pulse = 0)
        self.k = 0

    @property
    def position(self) -> np.ndarray:
        """The quantized coordinates (the staircase) ``(N, 2)``."""
        return self.cont.copy() if self.pulse <= 0 else self.r0 + self.n * self.pulse

    def run(self, iterations: int) -> tuple[np.ndarray, np.ndarray]:
        """Advance ``iterations`` additions; returns positions ``(iterations, N, 2)`` and
        pulses emitted per iteration ``(iterations, N, 2)`` (signed integers)."""
        c = self.model.coeffs
        a11, a12, a22, a13, a23 = (
            np.asarray(c[n], dtype=float) for n in ("a11", "a12", "a22", "a13", "a23")
        )
        ts = (self.k + np.arange(iterations)) * self.delta
        kk = _gain_values(self.model.gain, ts) * self.delta
        q = float(self.pulse)
        N = len(self.r0)
        pos = np.empty((iterations, N, 2))
        pul = np.zeros((iterations, N, 2), dtype=np.int64)
        improved = self.mode == "improved"
        if q <= 0:
            x, y = self.cont[:, 0].copy(), self.cont[:, 1].copy()
            for i in range(iterations):
                dx = kk[i] * (a12 * x + a22 * y + a23)
                xn = x + dx
                dy = -kk[i] * (a11 * (xn if improved else x) + a12 * y + a13)
                x, y = xn, y + dy
                pos[i, :, 0], pos[i, :, 1] = x, y
            self.cont = np.stack([x, y], axis=-1)
        else:
            x0, y0 = self.r0[:, 0], self.r0[:, 1]
            nx, ny = self.n[:, 0].copy(), self.n[:, 1].copy()
            ax, ay = self.acc[:, 0].copy(), self.acc[:, 1].copy()
            for i in range(iterations):
                xq, yq = x0 + nx * q, y0 + ny * q
                ax = ax + kk[i] * (a12 * xq + a22 * yq + a23) / q
                px = np.rint(ax)
                ax -= px
                nx = nx + px
                if improved:
                    xq = x0 + nx * q
                ay = ay - kk[i] * (a11 * xq + a12 * yq + a13) / q
                py = np.rint(ay)
                ay -= py
                ny = ny + py
                pos[i, :, 0], pos[i, :, 1] = x0 + nx * q, y0 + ny * q
                pul[i, :, 0], pul[i, :, 1] = px, py
            self.n = np.stack([nx, ny], axis=-1)
            self.acc = np.stack([ax, ay], axis=-1)
            self.cont = self.position
        self.k += iterations
        return pos, pul


class DigitalTrack:
    """The digital analyzer's additions, computed in blocks and kept: the position and the
    cumulative pulses after n additions (n = 0 is the start)."""

    BLOCK = 256

    def __init__(self, dda: DigitalAnalyzer) -> None:
        self.dda = dda
        self.k0 = dda.k
        self.pos = [dda.position[None]]
        self.counts = [np.zeros((1, *dda.r0.shape))]
        self.done = 0

    def at(self, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and cumulative pulses ``(m, N, 2)`` after ``n (m,)`` additions."""
        while self.done < int(np.max(n)):
            pos, pul = self.dda.run(self.BLOCK)
            self.pos.append(pos)
            self.counts.append(self.counts[-1][-1] + np.cumsum(pul, axis=0))
            self.done += self.BLOCK
        if len(self.pos) > 1:
            self.pos = [np.concatenate(self.pos)]
            self.counts = [np.concatenate(self.counts)]
        return self.pos[0][n], self.counts[0][n]


@dataclass
class PlanarState:
    """The analyzer at ``m`` times: the continuous point ``r (m, N, 2)`` and, with the
    digital analyzer on, its staircase ``digital``, its cumulative pulses ``counts`` and
    the continuous point at the same additions ``reference``; ``v``: the field at ``r``,
    when already computed."""

    model: PlanarModel
    r: np.ndarray
    digital: np.ndarray | None = None
    counts: np.ndarray | None = None
    reference: np.ndarray | None = None
    #: the field at ``r`` when a frame has already computed it (then read, not recomputed)
    v: np.ndarray | None = None


@dataclass
class PlanarTrack:
    """The solution of one parameter set from the anchor time ``t0`` (0, or the time of a
    live change): the continuous point in closed form and the digital additions."""

    model: PlanarModel
    r0: np.ndarray  # (N, 2) at t0
    t0: float = 0.0
    digital: DigitalTrack | None = None
    theta: ArgumentIntegral = field(init=False)

    def __post_init__(self) -> None:
        self.theta = ArgumentIntegral(self.model.gain)
        self.theta0 = float(self.theta(np.array([self.t0]))[0])

    def continuous(self, t: np.ndarray) -> np.ndarray:
        if np.shape(t) == (1,):  # a played frame: plain floats (equal to round-off)
            c = self.theta.constant
            th = c * float(t[0]) if c is not None else float(self.theta(t)[0])
            return self.model.flow_one(self.r0, th - self.theta0)[None]
        return self.model.flow(self.r0, self.theta(t) - self.theta0)

    def additions(self, t: np.ndarray) -> np.ndarray:
        """Additions done by the times ``t`` since the anchor (at most the run's limit)."""
        dda = self.digital.dda
        n = np.floor(np.asarray(t) / dda.delta + 1e-9).astype(int) - self.digital.k0
        return np.clip(n, 0, MAX_DIGITAL_ITERATIONS)

    def at(self, t: np.ndarray) -> PlanarState:
        t = np.asarray(t, dtype=float)
        state = PlanarState(self.model, self.continuous(t))
        if self.digital is not None:
            n = self.additions(t)
            state.digital, state.counts = self.digital.at(n)
            state.reference = self.continuous((self.digital.k0 + n) * self.digital.dda.delta)
        return state


def radius_growth_per_turn(delta: float, mode: str) -> float:
    """Relative radius error of the digital circle (u = 1) after one turn [derived, not in source]:
    ``exp(πΔ) - 1 ≈ πΔ`` for the simple update; the improved one stays within ``Δ/4`` of R."""
    if mode == "simple":
        # sqrt(1 + Δ²) per addition, 2π/Δ additions
        return float(np.expm1(np.log1p(delta**2) * np.pi / delta))
    return delta / 4.0


def embed(R2: np.ndarray, plane: str = "xy") -> np.ndarray:
    """Planar states ``(..., 2)`` as 3-D points in the plane ``xy`` (z = 0) or ``xz`` (y = 0)."""
    out = np.zeros(R2.shape[:-1] + (3,))
    out[..., 0] = R2[..., 0]
    out[..., 1 if plane == "xy" else 2] = R2[..., 1]
    return out
