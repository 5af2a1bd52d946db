"""The general surface analyzer (1.49)/(1.50) and its constant-speed variant (1.58)-(1.59).

One symbolic model serves every quadric: the field of (1.50) in convention B
(DESIGN.md §3.1) with the quadric's coefficients ``a11..a44`` and the controls
``u1, u2, u3`` as symbols.  It is lambdified once per process; a lesson substitutes
its surface's numbers to *display* the equations and passes the same numbers to the
lambdified functions to *integrate* them, so what is shown is what is run.

    dx/dphi =  u1 F_y/2 - u2 F_z/2
    dy/dphi = -u1 F_x/2 + u3 F_z/2          (1.50); F_x/2 = a11 x + a12 y + a31 z + a14 ...
    dz/dphi =  u2 F_x/2 - u3 F_y/2

With ``d phi = omega dt``, ``omega = +-V / |field|`` (1.58) the speed is ``V`` (1.59).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from lessons.core.formula import Formula, t_symbol
from lessons.core.integrators import gl_linear, solve_ivp_reference

COEFF_NAMES = ("a11", "a22", "a33", "a12", "a23", "a31", "a14", "a24", "a34", "a44")
x, y, z = sp.symbols("x y z", real=True)
u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
V, sigma = sp.symbols("V sigma", real=True)
A_SYM = {n: sp.Symbol(n, real=True) for n in COEFF_NAMES}
XYZ = (x, y, z)
U = (u1, u2, u3)

#: Fraction of the field's natural scale below which the constant-speed analyzer holds.
HOLD_TOL = 1e-9


def quadric_expr(a: Mapping[str, Any] = A_SYM) -> sp.Expr:
    """F of (1.42) with coefficients ``a`` (symbols by default)."""
    return (
        a["a11"] * x**2
        + a["a22"] * y**2
        + a["a33"] * z**2
        + 2 * a["a12"] * x * y
        + 2 * a["a23"] * y * z
        + 2 * a["a31"] * z * x
        + 2 * a["a14"] * x
        + 2 * a["a24"] * y
        + 2 * a["a34"] * z
        + a["a44"]
    )


def half_gradient_expr(F: sp.Expr) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(F_x/2, F_y/2, F_z/2): (1.45) with the common factor 2 dropped."""
    return tuple(sp.expand(sp.diff(F, v) / 2) for v in XYZ)  # type: ignore[return-value]


def field_expr(
    F: sp.Expr, controls: tuple[sp.Expr, sp.Expr, sp.Expr] = U
) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """The analyzer field (1.49) of surface ``F`` in convention B, gradient halved (1.50)."""
    gx, gy, gz = half_gradient_expr(F)
    c1, c2, c3 = controls
    return (c1 * gy - c2 * gz, -c1 * gx + c3 * gz, c2 * gx - c3 * gy)


@dataclass(frozen=True)
class _Numeric:
    linear: Any  # (u1,u2,u3, a...) -> (A 3x3 nested, c 3)
    field: Any  # (x,y,z,u1,u2,u3,a...) -> 3-tuple
    speed_field: Any  # (x,y,z,u1,u2,u3,a...,V,sigma) -> 3-tuple


@lru_cache(maxsize=1)
def _numeric() -> _Numeric:
    """Lambdify the symbolic field once per process."""
    f = field_expr(quadric_expr())
    coeffs = [A_SYM[n] for n in COEFF_NAMES]
    Amat = sp.Matrix(f).jacobian(sp.Matrix(XYZ))
    c0 = sp.Matrix(f).subs({x: 0, y: 0, z: 0})
    norm = sp.sqrt(sum(fi**2 for fi in f))
    omega = sigma * V / norm  # (1.58)
    fv = [omega * fi for fi in f]  # (1.59)
    return _Numeric(
        linear=sp.lambdify([*U, *coeffs], (Amat.tolist(), list(c0)), modules="numpy"),
        field=sp.lambdify([*XYZ, *U, *coeffs], f, modules="numpy", cse=True),
        speed_field=sp.lambdify([*XYZ, *U, *coeffs, V, sigma], fv, modules="numpy", cse=True),
    )


def _constant_value(u: Formula | float | None) -> float | None:
    """The number a control stands for when it does not depend on t, else None."""
    if u is None:
        return 0.0
    if not isinstance(u, Formula):
        return float(u)
    return u.constant_value


def _as_formula_values(u: Formula | float, t: np.ndarray) -> np.ndarray:
    c = _constant_value(u)
    if c is not None:
        return np.full(np.shape(t), c)
    return np.broadcast_to(np.asarray(u(t), dtype=float), np.shape(t))


@dataclass
class Controls:
    """u1, u2, u3 (formulas of t or numbers), the speed V and the direction sign (constant-speed mode)."""

    u1: Formula | float = 1.0
    u2: Formula | float = 0.0
    u3: Formula | float = 0.0
    V: Formula | float | None = None  # None: plain analyzer (1.50); else (1.59)
    sign: float = 1.0

    def at(self, t: np.ndarray) -> np.ndarray:
        """``(3, *t.shape)`` control values."""
        t = np.asarray(t, dtype=float)
        out = np.empty((3, *t.shape))
        for k, u in enumerate((self.u1, self.u2, self.u3)):
            c = _constant_value(u)
            out[k] = c if c is not None else u(t)  # type: ignore[operator]
        return out

    def constant(self) -> bool:
        """True when u1, u2, u3 (and V) do not depend on t."""
        return all(_constant_value(u) is not None for u in (self.u1, self.u2, self.u3, self.V))

    def speed(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return _as_formula_values(self.V if self.V is not None else 0.0, t)

    def check_finite(self, t_end: float) -> None:
        probe = np.linspace(0.0, max(t_end, 1e-9), 2001)
        for name in ("u1", "u2", "u3", "V"):
            f = getattr(self, name)
            if isinstance(f, Formula):
                f.check_finite(probe)


@dataclass
class AnalyzerModel:
    """The analyzer of one quadric (coefficients by textbook name), numeric and symbolic.

    ``coeffs`` has shape ``(N,)`` per name when a family runs on different surfaces.
    """

    coeffs: dict[str, np.ndarray]
    controls: Controls = field(default_factory=Controls)

    @classmethod
    def of(cls, coeffs: Mapping[str, float], controls: Controls) -> AnalyzerModel:
        return cls({n: np.asarray(float(coeffs.get(n, 0.0))) for n in COEFF_NAMES}, controls)

    # ---- symbolic (for display) -------------------------------------------------

    def surface_expr(self) -> sp.Expr:
        return quadric_expr(
            {n: sp.nsimplify(float(np.ravel(v)[0]), rational=True) for n, v in self.coeffs.items()}
        )

    def equations(self, controls: tuple[sp.Expr, sp.Expr, sp.Expr] = U) -> list[sp.Eq]:
        """The integrated system with this surface's numbers: dx/dt = ..., (phi = t)."""
        f = field_expr(self.surface_expr(), controls)
        return [
            sp.Eq(sp.Derivative(sp.Function(str(v))(t_symbol), t_symbol), sp.expand(fi))
            for v, fi in zip(XYZ, f)
        ]

    # ---- numeric ----------------------------------------------------------------

    def _c(self) -> list[np.ndarray]:
        return [self.coeffs[n] for n in COEFF_NAMES]

    def half_gradient(self, R: np.ndarray) -> np.ndarray:
        c = self.coeffs
        X, Y, Z = R[..., 0], R[..., 1], R[..., 2]
        return np.stack(
            [
                c["a11"] * X + c["a12"] * Y + c["a31"] * Z + c["a14"],
                c["a12"] * X + c["a22"] * Y + c["a23"] * Z + c["a24"],
                c["a31"] * X + c["a23"] * Y + c["a33"] * Z + c["a34"],
            ],
            axis=-1,
        )

    def F(self, R: np.ndarray) -> np.ndarray:
        c = self.coeffs
        X, Y, Z = R[..., 0], R[..., 1], R[..., 2]
        return (
            c["a11"] * X**2
            + c["a22"] * Y**2
            + c["a33"] * Z**2
            + 2 * (c["a12"] * X * Y + c["a23"] * Y * Z + c["a31"] * Z * X)
            + 2 * (c["a14"] * X + c["a24"] * Y + c["a34"] * Z)
            + c["a44"]
        )

    def F_scale(self, R: np.ndarray) -> np.ndarray:
        """Magnitude of F's terms at the points visited, per family member:
        max over samples of ‖Q‖|r|² + ‖b‖|r| + |a44| (round-off of F is ~1e-16 of it)."""
        c = self.coeffs
        qn = np.sqrt(
            sum(
                np.asarray(c[n], dtype=float) ** 2 * (1 if n in ("a11", "a22", "a33") else 2)
                for n in COEFF_NAMES[:6]
            )
        )
        bn = np.sqrt(sum(np.asarray(c[n], dtype=float) ** 2 for n in ("a14", "a24", "a34")))
        rn = np.linalg.norm(np.asarray(R, dtype=float), axis=-1)
        return (qn * rn**2 + bn * rn + np.abs(np.asarray(c["a44"], dtype=float))).max(axis=0)

    def linear_coeffs(self, t: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
        """``A (m, N, 3, 3)`` and ``c (m, N, 3)`` of the affine field at times ``t (m,)``."""
        uu = self.controls.at(t)  # (3, m)
        m = len(t)
        args = [u[:, None] for u in uu] + [
            np.broadcast_to(np.asarray(a, dtype=float), (n_points,))[None, :] for a in self._c()
        ]
        A_rows, c0 = _numeric().linear(*args)
        A = np.empty((m, n_points, 3, 3))
        for i in range(3):
            A[:, :, i, :] = np.stack(
                np.broadcast_arrays(*A_rows[i], np.empty((m, n_points)))[:3], axis=-1
            )
        cvec = np.stack(np.broadcast_arrays(*c0, np.empty((m, n_points)))[:3], axis=-1)
        return A, cvec

    def velocity(self, t: float, R: np.ndarray) -> np.ndarray:
        """The field at ``(t, R)``: (1.50), or (1.59) where ``controls.V`` is set (holding where it vanishes)."""
        R = np.atleast_2d(R)
        uu = self.controls.at(np.asarray(t))
        base = np.stack(
            _numeric().field(R[:, 0], R[:, 1], R[:, 2], *uu, *self._c()), axis=-1
        ) * np.ones_like(R)
        if self.controls.V is None:
            return base
        norm = np.linalg.norm(base, axis=-1)
        hold = norm <= self.hold_threshold(R, float(t))
        Vt = float(self.controls.speed(np.asarray(t)))
        with np.errstate(all="ignore"):
            out = np.stack(
                _numeric().speed_field(
                    R[:, 0], R[:, 1], R[:, 2], *uu, *self._c(), Vt, self.controls.sign
                ),
                axis=-1,
            ) * np.ones_like(R)
        out[hold] = 0.0
        return out

    def velocities(self, t: np.ndarray, R: np.ndarray) -> np.ndarray:
        """Batched field at samples ``t (m,)``, ``R (m, N, 3)`` (same model as :meth:`velocity`)."""
        t = np.asarray(t, dtype=float)
        A, c = self.linear_coeffs(t, R.shape[1])
        n = np.einsum("mnij,mnj->mni", A, R) + c
        if self.controls.V is None:
            return n
        norm = np.linalg.norm(n, axis=-1)
        thr = (
            np.stack([self.hold_threshold(R[k], float(t[k])) for k in range(len(t))])
            if len(t) < 50
            else self._thresholds(t, R)
        )
        scale = np.where(
            norm > thr,
            self.controls.sign * self.controls.speed(t)[:, None] / np.where(norm > 0, norm, 1.0),
            0.0,
        )
        return n * scale[..., None]

    def _thresholds(self, t: np.ndarray, R: np.ndarray) -> np.ndarray:
        uu = np.abs(self.controls.at(t)).max(axis=0) + 1e-300  # (m,)
        g = np.linalg.norm(self.half_gradient(R), axis=-1)
        qn = max(float(np.max(np.abs(self.coeffs[n]))) for n in COEFF_NAMES[:6])
        return HOLD_TOL * uu[:, None] * (g + qn * np.linalg.norm(R, axis=-1) + 1e-300)

    def hold_threshold(self, R: np.ndarray, t: float, umax: float | None = None) -> np.ndarray:
        """Below this |field| the constant-speed analyzer holds (the formula divides by ~0)."""
        uu = (
            float(np.abs(self.controls.at(np.asarray(t))).max()) if umax is None else umax
        ) + 1e-300
        g = np.linalg.norm(self.half_gradient(R), axis=-1)
        qn = max(float(np.max(np.abs(self.coeffs[n]))) for n in COEFF_NAMES[:6])
        scale = uu * (g + qn * np.linalg.norm(R, axis=-1) + 1e-300)
        return HOLD_TOL * scale

    def jacobian(self, t: float, R: np.ndarray) -> np.ndarray:
        """Jacobian of the field (exact for (1.50), projected for (1.59))."""
        R = np.atleast_2d(R)
        A, c = self.linear_coeffs(np.atleast_1d(float(t)), len(R))
        A = A[0]
        if self.controls.V is None:
            return A
        n = np.einsum("nij,nj->ni", A, R) + c[0]
        norm = np.linalg.norm(n, axis=-1)
        safe = np.where(norm > 0, norm, 1.0)
        nh = n / safe[:, None]
        Vt = float(self.controls.speed(np.asarray(t)))
        P = np.eye(3) - nh[:, :, None] * nh[:, None, :]
        J = (self.controls.sign * Vt / safe)[:, None, None] * np.einsum("nij,njk->nik", P, A)
        J[norm == 0] = 0.0
        return J


class SpeedStepper:
    """Gauss–Legendre steps of the constant-speed analyzer (1.59), vectorized over points.

    The field is ``omega (A(t) r + c(t))`` with ``A, c`` from the lambdified (1.50) and
    ``omega = sigma V / |A r + c|`` (1.58); stages are solved by simplified Newton to
    round-off (warm-started from the previous step), so F is kept to round-off.
    Where ``|A r + c|`` is below the hold threshold at the start of a step the point holds.
    """

    #: Largest turn of the velocity per substep (rad), see :meth:`step_substeps`.
    max_turn = 0.03

    def __init__(self, model: AnalyzerModel, stages: int = 3, max_iter: int = 30) -> None:
        from lessons.core.integrators import gauss_legendre

        self.model = model
        self.a, self.b, self.c = gauss_legendre(stages)
        self.s = stages
        self.max_iter = max_iter
        self.evaluations = 0
        self._K: np.ndarray | None = None

    def coefficients(self, t: float, h: float, n_steps: int, N: int) -> tuple[np.ndarray, ...]:
        """Batched A, c, sigma V and max|u| at the stage times of ``n_steps`` steps."""
        ts = (t + h * (np.arange(n_steps)[:, None] + self.c[None, :])).ravel()
        A, cc = self.model.linear_coeffs(ts, N)
        s = self.s
        Vs = self.model.controls.sign * self.model.controls.speed(ts)
        umax = np.abs(self.model.controls.at(ts)).max(axis=0)
        return (
            A.reshape(n_steps, s, N, 3, 3),
            cc.reshape(n_steps, s, N, 3),
            Vs.reshape(n_steps, s),
            umax.reshape(n_steps, s),
        )

    def step(
        self, t: float, R: np.ndarray, h: float, coeffs: tuple[np.ndarray, ...] | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """One step from ``(t, R (N, 3))``; returns the new state and the held mask."""
        s, a = self.s, self.a
        N = len(R)
        if coeffs is None:
            coeffs = tuple(x[0] for x in self.coefficients(t, h, 1, N))
        A, cc, Vs, umax = coeffs
        n0 = np.einsum("nij,nj->ni", A[0], R) + cc[0]
        norm0 = np.sqrt((n0 * n0).sum(-1))
        held = norm0 <= self.model.hold_threshold(R, float(t), umax=float(umax[0]))
        safe0 = np.where(held, 1.0, norm0)
        # simplified Newton matrix from the start point: J = omega (I - nn^T) A
        nh = n0 / safe0[:, None]
        P = np.eye(3) - nh[:, :, None] * nh[:, None, :]
        J = (Vs[s // 2] / safe0)[:, None, None] * (P @ A[s // 2])
        M = np.eye(3 * s) - h * (a[None, :, None, :, None] * J[:, None, :, None, :]).reshape(
            N, 3 * s, 3 * s
        )
        Minv = np.linalg.inv(M)
        if self._K is not None and self._K.shape == (N, s, 3):
            K = self._K.copy()
        else:
            K = np.repeat((n0 * (Vs[0] / safe0)[:, None])[:, None, :], s, axis=1)
        At = A.transpose(1, 0, 2, 3)  # (N, s, 3, 3)
        ct = cc.transpose(1, 0, 2)
        ha = h * a
        for _ in range(self.max_iter):
            Y = R[:, None, :] + ha @ K  # (N, s, 3)
            n = (At @ Y[..., None])[..., 0] + ct
            norm = np.sqrt((n * n).sum(-1))
            f = n * (Vs[None, :] / np.where(norm > 0, norm, 1.0))[..., None]
            self.evaluations += s
            dK = -(Minv @ (K - f).reshape(N, 3 * s, 1)).reshape(N, s, 3)
            K += dK
            if np.abs(dK).max() <= 2e-16 * (np.abs(K).max() + 1e-300):
                break
        K[held] = 0.0
        self._K = K
        return R + h * np.einsum("i,nid->nd", self.b, K), held

    def step_substeps(
        self, t: float, R: np.ndarray, h: float, coeffs: tuple[np.ndarray, ...]
    ) -> tuple[np.ndarray, np.ndarray]:
        """One output step of size ``h``, split into equal substeps where the curve turns fast.

        The turning rate of (1.59) is ``omega |A| = V |A| / |A r + c|``: near points where the
        analyzer's field is small the point turns quickly; the step is cut so that
        ``rate * substep <= max_turn`` (each substep is still a Gauss-Legendre step).
        """
        A, cc, Vs, _ = coeffs
        n0 = np.einsum("nij,nj->ni", A[0], R) + cc[0]
        norm0 = np.sqrt((n0 * n0).sum(-1))
        rate = (
            np.abs(Vs).max() * np.sqrt((A[0] ** 2).sum(axis=(-1, -2))) / np.maximum(norm0, 1e-300)
        )
        m = int(np.ceil(float(np.max(np.where(norm0 > 0, rate, 0.0))) * h / self.max_turn - 1e-12))
        if m <= 1:
            return self.step(t, R, h, coeffs)
        m = min(m, 10_000)
        hs = h / m
        held = np.zeros(len(R), dtype=bool)
        comp = np.zeros_like(R)
        batch = self.coefficients(t, hs, m, len(R))
        for j in range(m):
            new, hj = self.step(t + j * hs, R, hs, tuple(x[j] for x in batch))
            held |= hj
            inc = (new - R) - comp
            nxt = R + inc
            comp = (nxt - R) - inc
            R = nxt
        return R, held

    def integrate(
        self, R0: np.ndarray, t0: float, t_end: float, h: float, chunk: int = 2000
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        R = np.atleast_2d(np.asarray(R0, dtype=float))
        N = len(R)
        n_full = int(np.floor((t_end - t0) / h + 1e-9))
        rest = (t_end - t0) - n_full * h
        n_all = n_full + (1 if rest > 1e-12 * max(1.0, h) else 0)
        ts = np.empty(n_all + 1)
        out = np.empty((n_all + 1, *R.shape))
        held = np.zeros((n_all + 1, N), dtype=bool)
        ts[0], out[0] = t0, R
        comp = np.zeros_like(R)
        k = 0
        while k < n_all:
            if k >= n_full:
                hk, m = rest, 1
            else:
                hk, m = h, min(chunk, n_full - k)
            batch = self.coefficients(t0 + k * h, hk, m, N)
            for j in range(m):
                new, held[k] = self.step_substeps(t0 + k * h, R, hk, tuple(x[j] for x in batch))
                inc = (new - R) - comp  # compensated summation of the increments
                nxt = R + inc
                comp = (nxt - R) - inc
                R = nxt
                k += 1
                ts[k], out[k] = (t0 + k * h if k <= n_full else t_end), R
        if n_all:
            held[-1] = held[-2]
        return ts, out, held


@dataclass
class AnalyzerRun:
    """A finished analyzer run: samples ``t``, positions ``r (m, N, 3)``, velocities, invariant."""

    t: np.ndarray
    r: np.ndarray
    v: np.ndarray
    F: np.ndarray  # (m, N)
    F0: np.ndarray  # (N,)
    held: np.ndarray  # (m, N) bool: constant-speed analyzer held (field ~ 0)
    method: str
    nfev: int = 0

    @property
    def drift(self) -> np.ndarray:
        return np.abs(self.F - self.F0[None, :])


def integrate(
    model: AnalyzerModel,
    r0: np.ndarray,
    t_end: float,
    h: float = 1e-3,
    method: str = "gauss-legendre-3",
    t0: float = 0.0,
    samples: int | None = None,
    rtol: float = 1e-3,
    atol: float = 1e-6,
) -> AnalyzerRun:
    """Run the analyzer from ``r0 (N, 3)``.

    ``method``: ``gauss-legendre-2`` (order 4) / ``gauss-legendre-3`` (order 6, default):
    invariant-exact; or ``RK45``, ``DOP853``, ``Radau``... through ``solve_ivp`` with
    ``rtol``/``atol`` (the reference a generic solver gives).  ``samples`` thins the
    output to about that many evenly spaced samples.
    """
    R0 = np.atleast_2d(np.asarray(r0, dtype=float))
    N = len(R0)
    nfev = 0
    if method.startswith("gauss-legendre"):
        stages = int(method.rsplit("-", 1)[1])
        if model.controls.V is None:
            t, r = gl_linear(lambda ts: model.linear_coeffs(ts, N), R0, t0, t_end, h, stages)
        else:
            sp_stepper = SpeedStepper(model, stages)
            t, r, _ = sp_stepper.integrate(R0, t0, t_end, h)
            nfev = sp_stepper.evaluations
        if samples is not None and len(t) > samples:
            idx = np.unique(np.linspace(0, len(t) - 1, samples).round().astype(int))
            t, r = t[idx], r[idx]
    else:
        m = samples if samples is not None else int(round((t_end - t0) / h)) + 1
        t_eval = np.linspace(t0, t_end, max(m, 2))
        t, r, nfev = solve_ivp_reference(
            model.velocity, R0, t0, t_end, t_eval, method=method, rtol=rtol, atol=atol
        )
    v = model.velocities(t, r)
    F = model.F(r)
    held = np.zeros(F.shape, dtype=bool)
    if model.controls.V is not None:
        held = np.linalg.norm(v, axis=-1) == 0.0
    return AnalyzerRun(t=t, r=r, v=v, F=F, F0=model.F(R0), held=held, method=method, nfev=nfev)
