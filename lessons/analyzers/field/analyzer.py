"""The general surface analyzer (1.49)/(1.50) and its constant-speed variant (1.58)-(1.59).

One symbolic model serves every quadric: the field of (1.50) in convention B (the signs
that reproduce the surviving (1.55), (1.57), (1.62), (1.63)) with the quadric's
coefficients ``a11..a44`` and the controls ``u1, u2, u3`` as symbols.  It is lambdified
once per process; a lesson substitutes its surface's numbers to *display* the equations
and passes the same numbers to the lambdified functions to *integrate* them, so what is
shown is what is run.

    dx/dphi =  u1 F_y/2 - u2 F_z/2
    dy/dphi = -u1 F_x/2 + u3 F_z/2          (1.50); F_x/2 = a11 x + a12 y + a31 z + a14 ...
    dz/dphi =  u2 F_x/2 - u3 F_y/2

With ``d phi = omega dt``, ``omega = +-V / |field|`` (1.58) the speed is ``V`` (1.59).
The runs themselves are in :mod:`analyzer_lab.lessons.analyzers.field.run`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.surfaces.quadric import COEFF_NAMES, quadric_polynomial
from analyzer_lab.lessons.kit.formula import Formula, t_symbol

x, y, z = sp.symbols("x y z", real=True)
u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
A_SYM = {n: sp.Symbol(n, real=True) for n in COEFF_NAMES}
XYZ = (x, y, z)
U = (u1, u2, u3)

#: Fraction of the field's natural scale below which the constant-speed analyzer holds.
HOLD_TOL = 1e-9


def quadric_expr(a: Mapping[str, Any] = A_SYM) -> sp.Expr:
    """F of (1.42) with coefficients ``a`` (symbols by default)."""
    return quadric_polynomial(a, x, y, z)


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


@lru_cache(maxsize=1)
def _linear() -> Any:
    """The affine form ``A(u, a) r + c(u, a)`` of the field (1.50), lambdified once per process."""
    f = field_expr(quadric_expr())
    coeffs = [A_SYM[n] for n in COEFF_NAMES]
    Amat = sp.Matrix(f).jacobian(sp.Matrix(XYZ))
    c0 = sp.Matrix(f).subs({x: 0, y: 0, z: 0})
    return sp.lambdify([*U, *coeffs], (Amat.tolist(), list(c0)), modules="numpy")


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
        plan = self.__dict__.get("_at")
        if plan is None:
            plan = self.__dict__["_at"] = self._plan((self.u1, self.u2, self.u3))
        values, where, fn = plan
        out[0], out[1], out[2] = values
        if fn is not None:
            with np.errstate(all="ignore"):
                for k, v in zip(where, fn(t)):
                    out[k] = v
        return out

    def one(self, t: float) -> tuple[float, float, float, float]:
        """u1, u2, u3 and V (0 without it) at one time, as plain numbers: :meth:`at` and
        :meth:`speed` at ``[t]`` (the formulas of t are evaluated by one function, kept)."""
        plan = self.__dict__.get("_one")
        if plan is None:
            plan = self.__dict__["_one"] = self._plan((self.u1, self.u2, self.u3, self.V))
        values, where, fn = plan
        if fn is None:
            return values  # type: ignore[return-value]
        out = list(values)
        with np.errstate(all="ignore"):
            for k, v in zip(where, fn(float(t))):
                out[k] = float(v)
        return out[0], out[1], out[2], out[3]

    @staticmethod
    def _plan(controls: tuple[Any, ...]) -> tuple[tuple[float, ...], list[int], Any]:
        """The values of the constant ``controls`` (0 for None), the places of the formulas
        of t and one function of t for them all (the same expressions each formula
        evaluates; formulas of other variables evaluate themselves)."""
        values = [0.0] * len(controls)
        where: list[int] = []
        formulas: list[Formula] = []
        for k, u in enumerate(controls):
            c = _constant_value(u)
            if c is not None:
                values[k] = c
            else:
                assert isinstance(u, Formula)
                where.append(k)
                formulas.append(u)
        fn: Any = None
        if formulas and all(tuple(u.variables) == ("t",) for u in formulas):
            fn = sp.lambdify([t_symbol], [u.expr for u in formulas], modules="numpy")
        elif formulas:  # not formulas of t alone: each evaluates itself

            def fn(t: float) -> list[Any]:
                return [u(t) for u in formulas]

        return tuple(values), where, fn

    def constant(self) -> bool:
        """True when u1, u2, u3 (and V) do not depend on t."""
        return all(_constant_value(u) is not None for u in (self.u1, self.u2, self.u3, self.V))

    def speed(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return _as_formula_values(self.V if self.V is not None else 0.0, t)


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
        """``A (m, N, 3, 3)`` and ``c (m, N, 3)`` of the affine field at times ``t (m,)``.

        (1.50) is linear in the controls: ``A = sum_k u_k(t) A_k`` and ``c = sum_k u_k(t)
        c_k`` with ``A_k``, ``c_k`` of the surface alone, built once per family size."""
        return self._affine(self.controls.at(np.asarray(t, dtype=float)), n_points)

    def _affine(self, uu: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`linear_coeffs` from the control values ``uu (3, m)``."""
        Ak, ck = self._unit_fields(n_points)
        return np.einsum("km,knij->mnij", uu, Ak), np.einsum("km,kni->mni", uu, ck)

    def _unit_fields(self, n_points: int) -> tuple[np.ndarray, np.ndarray]:
        """``A_k (3, N, 3, 3)`` and ``c_k (3, N, 3)``: the field of the unit control u_k."""
        cache = self.__dict__.setdefault("_unit_cache", {})
        if n_points not in cache:
            A = np.empty((3, n_points, 3, 3))
            c = np.empty((3, n_points, 3))
            coeffs = [np.broadcast_to(np.asarray(a, dtype=float), (n_points,)) for a in self._c()]
            for k in range(3):
                unit = [np.full(n_points, float(k == j)) for j in range(3)]
                A_rows, c0 = _linear()(*unit, *coeffs)
                for i in range(3):
                    A[k, :, i, :] = np.stack(np.broadcast_arrays(*A_rows[i], unit[0])[:3], -1)
                c[k] = np.stack(np.broadcast_arrays(*c0, unit[0])[:3], axis=-1)
            cache[n_points] = (A, c)
        return cache[n_points]

    def velocities(self, t: np.ndarray, R: np.ndarray) -> np.ndarray:
        """The field at samples ``t (m,)``, ``R (m, N, 3)``: (1.50), or (1.59) where
        ``controls.V`` is set, zero where the field of (1.50) vanishes (see :meth:`holds`)."""
        t = np.asarray(t, dtype=float)
        uu = self.controls.at(t)
        A, c = self._affine(uu, R.shape[1])
        n = np.einsum("mnij,mnj->mni", A, R) + c
        if self.controls.V is None:
            return n
        norm = np.sqrt((n * n).sum(-1))
        umax = np.abs(uu).max(axis=0)[:, None]
        Vs = self.controls.sign * self.controls.speed(t)[:, None]
        # where |field| exceeds the hold bound at an upper bound of hold_size, no point holds
        q, b = self._hold_bound()
        if (norm > (umax + 1e-300) * (q * np.sqrt((R * R).sum(-1)) + b)).all():
            return n * (Vs / norm)[..., None]
        scale = np.where(
            self.holds(norm, self.hold_size(R), umax), 0.0, Vs / np.where(norm > 0, norm, 1.0)
        )
        return n * scale[..., None]

    def velocity(self, t: float, R: np.ndarray) -> np.ndarray:
        """The field at one time for points ``R (N, 3)`` (:meth:`velocities` at one sample)."""
        return self.velocities(np.atleast_1d(float(t)), np.atleast_2d(R)[None])[0]

    def at_one(
        self, t: float, R: np.ndarray
    ) -> tuple[tuple[float, float, float, float], np.ndarray, np.ndarray]:
        """A played frame's numbers in plain floats: the controls (u1, u2, u3, V), the field
        (:meth:`velocities`, equal to round-off) and the half gradient (:meth:`half_gradient`)
        at one time ``t`` for the points ``R (N, 3)``."""
        u = u1, u2, u3, V = self.controls.one(t)
        constant_speed = self.controls.V is not None
        if constant_speed:
            umax = max(abs(u1), abs(u2), abs(u3))
            qn = self.__dict__.get("_qn")
            if qn is None:
                self.hold_size(R[:1])  # keeps _qn
                qn = self.__dict__["_qn"]
            speed = self.controls.sign * V
        vel, grad = [], []
        for (x, y, z), c in zip(R.tolist(), self._member_coeffs(len(R))):
            a11, a12, a22, a31, a23, a33, a14, a24, a34 = c
            gx = a11 * x + a12 * y + a31 * z + a14
            gy = a12 * x + a22 * y + a23 * z + a24
            gz = a31 * x + a23 * y + a33 * z + a34
            n = [u1 * gy - u2 * gz, -u1 * gx + u3 * gz, u2 * gx - u3 * gy]  # (1.50)
            if constant_speed:  # (1.58)-(1.59)
                norm = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
                size = math.sqrt(gx * gx + gy * gy + gz * gz) + qn * math.sqrt(
                    x * x + y * y + z * z
                )
                held = norm <= HOLD_TOL * (umax + 1e-300) * (size + 1e-300)
                k = 0.0 if held else speed / (norm if norm > 0 else 1.0)
                n = [n[0] * k, n[1] * k, n[2] * k]
            vel.append(n)
            grad.append([gx, gy, gz])
        return u, np.array(vel), np.array(grad)

    def _member_coeffs(self, n_points: int) -> list[list[float]]:
        """a11, a12, a22, a31, a23, a33, a14, a24, a34 of each of ``n_points`` members (kept)."""
        cache = self.__dict__.setdefault("_member_cache", {})
        rows = cache.get(n_points)
        if rows is None:
            names = ("a11", "a12", "a22", "a31", "a23", "a33", "a14", "a24", "a34")
            cols = [np.broadcast_to(np.asarray(self.coeffs[m], float), (n_points,)) for m in names]
            rows = cache[n_points] = np.stack(cols, axis=1).tolist()
        return rows

    def F_one(self, R: np.ndarray) -> list[float]:
        """:meth:`F` at the points ``R (N, 3)`` of one time, in plain floats."""
        c = self._member_coeffs(len(R))
        a44 = np.broadcast_to(np.asarray(self.coeffs["a44"], float), (len(R),)).tolist()
        out = []
        for (X, Y, Z), (a11, a12, a22, a31, a23, a33, a14, a24, a34), d in zip(R.tolist(), c, a44):
            out.append(
                a11 * X**2
                + a22 * Y**2
                + a33 * Z**2
                + 2 * (a12 * X * Y + a23 * Y * Z + a31 * Z * X)
                + 2 * (a14 * X + a24 * Y + a34 * Z)
                + d
            )
        return out

    def hold_size(self, R: np.ndarray) -> np.ndarray:
        """The natural size ``|F_r/2| + |Q| |r|`` of the field per unit control at ``R (..., 3)``."""
        g = self.half_gradient(R)
        return np.sqrt((g * g).sum(-1)) + self._q_max() * np.sqrt((R * R).sum(-1))

    def _q_max(self) -> float:
        """The surface's largest quadratic coefficient ``max |a_ij|``, once per model."""
        qn = self.__dict__.get("_qn")
        if qn is None:
            qn = self.__dict__["_qn"] = max(
                float(np.max(np.abs(self.coeffs[n]))) for n in COEFF_NAMES[:6]
            )
        return qn

    def _hold_bound(self) -> tuple[np.ndarray, np.ndarray]:
        """``q, b`` with ``HOLD_TOL (umax + 1e-300) (hold_size(r) + 1e-300)`` (the bound of
        :meth:`holds`) at most ``(umax + 1e-300) (q |r| + b)``: hold_size is at most
        ``(|Q|_F + max|a_ij|) |r| + |b|`` (Cauchy-Schwarz); a factor 2 covers round-off."""
        cached = self.__dict__.get("_hold_bound_q_b")
        if cached is None:
            c = {k: np.asarray(v, dtype=float) for k, v in self.coeffs.items()}
            square = (1.0 if k in ("a11", "a22", "a33") else 2.0 for k in COEFF_NAMES[:6])
            qf = np.sqrt(sum(c[k] ** 2 * w for k, w in zip(COEFF_NAMES[:6], square)))
            bn = np.sqrt(c["a14"] ** 2 + c["a24"] ** 2 + c["a34"] ** 2)
            cached = self.__dict__["_hold_bound_q_b"] = (
                2.0 * HOLD_TOL * (qf + self._q_max()),
                2.0 * HOLD_TOL * (bn + 1e-300),
            )
        return cached

    @staticmethod
    def holds(norm: np.ndarray, size: np.ndarray, umax: np.ndarray) -> np.ndarray:
        """True where the constant-speed analyzer cannot move: ``|field|`` (``norm``) is below
        ``HOLD_TOL`` of its natural size ``max|u| size`` (:meth:`hold_size`), so
        ``omega = V/|field|`` (1.58) divides by (almost) zero."""
        return norm <= HOLD_TOL * (umax + 1e-300) * (size + 1e-300)


def observation_one(
    u: tuple[float, ...],
    R: np.ndarray,
    v: np.ndarray,
    F: list[float],
    F0: list[float],
    scale: float,
) -> dict[str, float]:
    """An analyzer lesson's series at one time in plain floats: the controls ``u``, the points
    ``R (N, 3)``, their velocities ``v (N, 3)``, F there and at the start (the drift), the
    scale of the drift (the lesson's observation at ``[t]``, equal to round-off)."""
    out = {"u1": u[0], "u2": u[1], "u3": u[2]}
    for k, ((x, y, z), (vx, vy, vz)) in enumerate(zip(R.tolist(), v.tolist())):
        sfx = "" if k == 0 else f"_{k + 1}"
        v2 = vx * vx + vy * vy + vz * vz
        out["x" + sfx], out["y" + sfx], out["z" + sfx] = x, y, z
        out["vx" + sfx], out["vy" + sfx], out["vz" + sfx] = vx, vy, vz
        out["v2" + sfx], out["speed" + sfx] = v2, math.sqrt(v2)
        out["drift" + sfx] = (F[k] - F0[k]) / scale
    return out
