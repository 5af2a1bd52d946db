"""Shared mechanics of chapter 2: Lagrange models, the §2.2 constrained solver, body poses.

* :class:`LagrangeModel` wraps ``sympy.physics.mechanics.LagrangesMethod``: from a
  Lagrangian ``L = T - U`` and applied forces (virtual work, (2.10)/(2.16)) it keeps the
  symbolic equations ``M(q) q'' = F(q, q', t, u)`` and lambdifies them once for the
  forward problem (integrate) and the inverse problem (forces from a motion law).
* :class:`ConstrainedSystem` is the formalized algorithm of §2.2, eqs (2.17)-(2.34), in
  its corrected form: ``H`` is ``v2 x n``, the velocity level (2.29) ``H q' = -psi``
  gives the initial velocities, the acceleration level (2.30) ``H q'' = -Phi`` closes
  (2.25) and gives the multipliers (2.33) and the accelerations (2.34).  Optional
  Baumgarte stabilization (not in the source) replaces ``Phi`` by
  ``Phi + 2 alpha (H q' + psi) + beta^2 f``.
* Poses and meshes: trimesh solids as :class:`MeshItem`, wxyz quaternions, segment poses.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols, msubs

from lessons.core.contract import Frame, MeshItem, Params, Stepper

Array = np.ndarray


# ---------------------------------------------------------------- symbolic tools


def plain_symbols(q: Sequence[sp.Function]) -> tuple[list[sp.Symbol], list[sp.Symbol]]:
    """Plain symbols standing for ``q(t)`` and ``q'(t)`` (names ``x``, ``x_d``)."""
    qs = [sp.Symbol(str(qi.func), real=True) for qi in q]
    qds = [sp.Symbol(f"{qi.func}_d", real=True) for qi in q]
    return qs, qds


def to_plain(expr: Any, q: Sequence[sp.Function], t: sp.Symbol) -> Any:
    """Replace ``q''``, ``q'`` and ``q`` by plain symbols (second derivatives by ``*_dd``)."""
    qs, qds = plain_symbols(q)
    qdds = {qi.diff(t, 2): sp.Symbol(f"{qi.func}_dd", real=True) for qi in q}
    return msubs(
        expr, qdds, {qi.diff(t): s for qi, s in zip(q, qds)}, {qi: s for qi, s in zip(q, qs)}
    )


@dataclass
class LagrangeModel:
    """Lagrange equations of the 2nd kind, ``d/dt dL/dq' - dL/dq = Q``, via LagrangesMethod.

    ``inputs`` are the force symbols (drive and resistance forces, moments) that enter
    the generalized forces linearly; ``params`` are the constant parameters.  Numeric
    functions take ``(q, qd, t, p, u)`` as flat arrays in those orders.
    """

    q: list[sp.Function]
    t: sp.Symbol
    params: list[sp.Symbol]
    inputs: list[sp.Symbol]
    lagrangian: sp.Expr
    method: LagrangesMethod
    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    _num: dict[str, Callable[..., Any]] = field(default_factory=dict, repr=False)

    @classmethod
    def build(
        cls,
        q: Sequence[sp.Function],
        T: sp.Expr,
        U: sp.Expr,
        t: sp.Symbol,
        params: Sequence[sp.Symbol],
        inputs: Sequence[sp.Symbol] = (),
        forcelist: Sequence[tuple[Any, Any]] | None = None,
        frame: Any = None,
    ) -> LagrangeModel:
        L = T - U
        lm = LagrangesMethod(
            L, list(q), forcelist=list(forcelist) if forcelist else None, frame=frame
        )
        lm.form_lagranges_equations()
        model = cls(
            list(q),
            t,
            list(params),
            list(inputs),
            L,
            lm,
            sp.Matrix(lm.mass_matrix),
            sp.Matrix(lm.forcing),
        )
        model._lambdify()
        return model

    @property
    def n(self) -> int:
        return len(self.q)

    def eom(self) -> sp.Matrix:
        """``d/dt dL/dq' - dL/dq - Q`` (each row is zero on a motion)."""
        return sp.Matrix(self.method.eom)

    def equations(self) -> list[sp.Eq]:
        """Rows ``M q'' - (F - Q) = Q``: left the inertia, velocity and potential terms,
        right the generalized forces of the inputs (the textbook's arrangement)."""
        qdd = sp.Matrix([qi.diff(self.t, 2) for qi in self.q])
        zero = {u: 0 for u in self.inputs}
        free = self.forcing.subs(zero)
        lhs = self.mass_matrix * qdd - free
        rhs = self.forcing - free
        return [sp.Eq(sp.simplify(lhs[i]), sp.simplify(rhs[i])) for i in range(self.n)]

    def plain(self, expr: Any) -> Any:
        return to_plain(expr, self.q, self.t)

    def _lambdify(self) -> None:
        qs, qds = plain_symbols(self.q)
        args = (qs, qds, self.t, self.params, self.inputs)
        M = self.plain(self.mass_matrix)
        F = self.plain(self.forcing)
        G = F.jacobian(self.inputs) if self.inputs else sp.zeros(self.n, 0)
        self._num["M"] = sp.lambdify(args, M, modules="numpy", cse=True)
        self._num["F"] = sp.lambdify(args, F, modules="numpy", cse=True)
        self._num["G"] = sp.lambdify(args, G, modules="numpy", cse=True)

    # -- numeric model ---------------------------------------------------------

    def M(self, q: Array, qd: Array, t: float, p: Array, u: Array) -> Array:
        return np.asarray(self._num["M"](q, qd, t, p, u), dtype=float)

    def F(self, q: Array, qd: Array, t: float, p: Array, u: Array) -> Array:
        return np.asarray(self._num["F"](q, qd, t, p, u), dtype=float).reshape(-1)

    def G(self, q: Array, qd: Array, t: float, p: Array, u: Array) -> Array:
        """``dF/du``: how each input enters the generalized forces (virtual work)."""
        return np.asarray(self._num["G"](q, qd, t, p, u), dtype=float).reshape(
            self.n, len(self.inputs)
        )

    def accelerations(self, q: Array, qd: Array, t: float, p: Array, u: Array) -> Array:
        return np.linalg.solve(self.M(q, qd, t, p, u), self.F(q, qd, t, p, u))

    def rhs(
        self, p: Array, u_of_t: Callable[[float, Array, Array], Array]
    ) -> Callable[[float, Array], Array]:
        """``y = [q, q']`` -> ``y'`` for solve_ivp (forward problem)."""
        n = self.n

        def f(t: float, y: Array) -> Array:
            q, qd = y[:n], y[n:]
            qdd = self.accelerations(q, qd, t, p, u_of_t(t, q, qd))
            return np.concatenate([qd, qdd])

        return f

    def solve_inputs(
        self,
        q: Array,
        qd: Array,
        qdd: Array,
        t: float,
        p: Array,
        u_known: Array,
        unknown: Sequence[int],
    ) -> Array:
        """Inverse problem at one instant: the inputs ``unknown`` (indices into ``inputs``)
        that make ``M q'' = F`` hold; the other inputs keep ``u_known``.  Least squares
        (minimum norm) when the unknown inputs outnumber the equations."""
        u0 = np.array(u_known, dtype=float)
        u0[list(unknown)] = 0.0
        resid = self.M(q, qd, t, p, u0) @ qdd - self.F(q, qd, t, p, u0)
        G = self.G(q, qd, t, p, u0)[:, list(unknown)]
        sol, *_ = np.linalg.lstsq(G, resid, rcond=None)
        out = u0.copy()
        out[list(unknown)] = sol
        return out


# ---------------------------------------------------------------- §2.2 constrained solver


@dataclass
class ConstrainedSystem:
    """The algorithm of §2.2 for ``A(q,t) q'' = B(q,q',t) + H^T lambda``.

    Holonomic constraints ``f_i(q, t) = 0`` (2.17) and nonholonomic ones
    ``g_i = a_i q' + a_i* = 0`` (2.18)-(2.19).  ``H`` (v2 x n) stacks ``f_i'`` and ``a_i``;
    ``psi`` stacks ``df_i/dt`` and ``a_i*`` (2.29); ``Phi`` is the acceleration-level free
    term (2.27)/(2.28)/(2.30).  ``B`` includes ``B*`` and may depend on ``inputs``.
    """

    q: list[sp.Symbol]
    qd: list[sp.Symbol]
    t: sp.Symbol
    params: list[sp.Symbol]
    inputs: list[sp.Symbol]
    A: sp.Matrix
    B: sp.Matrix
    f_hol: sp.Matrix
    H: sp.Matrix
    psi: sp.Matrix
    Phi: sp.Matrix
    n_hol: int
    _num: dict[str, Callable[..., Any]] = field(default_factory=dict, repr=False)

    @classmethod
    def build(
        cls,
        q: Sequence[sp.Symbol],
        qd: Sequence[sp.Symbol],
        t: sp.Symbol,
        A: sp.Matrix,
        B: sp.Matrix,
        params: Sequence[sp.Symbol] = (),
        inputs: Sequence[sp.Symbol] = (),
        f_hol: Sequence[sp.Expr] = (),
        a_nh: Sequence[Sequence[sp.Expr]] = (),
        a0_nh: Sequence[sp.Expr] = (),
    ) -> ConstrainedSystem:
        qv, qdv = sp.Matrix(q), sp.Matrix(qd)
        f = sp.Matrix(list(f_hol))
        rows: list[sp.Matrix] = []
        if len(f_hol):
            rows.append(f.jacobian(qv))  # f_i' (2.20)
        if len(a_nh):
            rows.append(sp.Matrix([list(r) for r in a_nh]))  # a_i (2.21)
        H = sp.Matrix.vstack(*rows) if rows else sp.zeros(0, len(q))
        psi = sp.Matrix([sp.diff(fi, t) for fi in f_hol] + list(a0_nh))  # (2.29)
        # Phi (2.27)/(2.28) as directional derivatives along (q', 1) in (q, t):
        # f'' = H q'' + d^2/ds^2 f(q + s q', t + s)|0 and g' = a q'' + d/ds g(q + s q', t + s)|0
        s = sp.Dummy("s")
        shift = {**{qi: qi + s * qdi for qi, qdi in zip(q, qd)}, t: t + s}
        phi_rows = [
            sp.diff(sp.sympify(fi, strict=True).xreplace(shift), s, 2).subs(s, 0) for fi in f_hol
        ]
        for row, a0 in zip(a_nh, a0_nh):
            g = sum(
                (sp.sympify(aij, strict=True) * qdj for aij, qdj in zip(row, qd)), sp.S.Zero
            ) + sp.sympify(a0, strict=True)
            phi_rows.append(sp.diff(g.xreplace(shift), s).subs(s, 0))
        Phi = sp.Matrix(phi_rows) if phi_rows else sp.zeros(0, 1)
        sys_ = cls(
            list(q),
            list(qd),
            t,
            list(params),
            list(inputs),
            sp.Matrix(A),
            sp.Matrix(B),
            f,
            H,
            psi,
            sp.Matrix(Phi),
            len(f_hol),
        )
        sys_._lambdify()
        return sys_

    @classmethod
    def from_lagrange(
        cls,
        model: LagrangeModel,
        f_hol: Sequence[sp.Expr] = (),
        a_nh: Sequence[Sequence[sp.Expr]] = (),
        a0_nh: Sequence[sp.Expr] = (),
    ) -> ConstrainedSystem:
        """The opened system of a :class:`LagrangeModel`: ``A`` its mass matrix, ``B`` its
        forcing (generalized forces plus the velocity terms of ``T``); constraints are
        written in the model's ``q(t)`` functions or in plain symbols."""
        qs, qds = plain_symbols(model.q)
        conv = lambda e: model.plain(sp.sympify(e, strict=True))  # noqa: E731
        return cls.build(
            qs,
            qds,
            model.t,
            model.plain(model.mass_matrix),
            model.plain(model.forcing),
            model.params,
            model.inputs,
            [conv(e) for e in f_hol],
            [[conv(e) for e in r] for r in a_nh],
            [conv(e) for e in a0_nh],
        )

    @property
    def n(self) -> int:
        return len(self.q)

    @property
    def v2(self) -> int:
        return int(self.H.rows)

    def _lambdify(self) -> None:
        args = (self.q, self.qd, self.t, self.params, self.inputs)
        for name in ("A", "B", "f_hol", "H", "psi", "Phi"):
            self._num[name] = sp.lambdify(args, getattr(self, name), modules="numpy", cse=True)

    def _eval(self, name: str, shape: tuple[int, int], *args: Any) -> Array:
        return np.asarray(self._num[name](*args), dtype=float).reshape(shape)

    def parts(
        self,
        t: float,
        q: Array,
        qd: Array,
        p: Array,
        u: Array,
        names: Sequence[str] = ("A", "B", "f", "H", "psi", "Phi"),
    ) -> dict[str, Array]:
        """Numeric ``A, B, f, H, psi, Phi`` at one state (or the subset ``names``)."""
        n, v2 = self.n, self.v2
        a = (q, qd, t, p, u)
        shapes = {
            "A": (n, n),
            "B": (n,),
            "f": (self.n_hol,),
            "H": (v2, n),
            "psi": (v2,),
            "Phi": (v2,),
        }
        return {k: self._eval("f_hol" if k == "f" else k, shapes[k], *a) for k in names}

    def solve(
        self,
        t: float,
        q: Array,
        qd: Array,
        p: Array,
        u: Array,
        alpha: float = 0.0,
        beta: float = 0.0,
    ) -> tuple[Array, Array]:
        """Accelerations (2.34) and multipliers (2.33) at one state."""
        P = self.parts(t, q, qd, p, u)
        A, B, H = P["A"], P["B"], P["H"]
        if self.v2 == 0:
            return np.linalg.solve(A, B), np.zeros(0)
        Phi = P["Phi"].copy()
        if alpha or beta:
            c = H @ qd + P["psi"]
            Phi += 2.0 * alpha * c
            Phi[: self.n_hol] += beta**2 * P["f"]
        X = np.linalg.solve(A, np.column_stack([B, H.T]))  # A^-1 [B | H^T]
        AinvB, AinvHT = X[:, 0], X[:, 1:]
        S = H @ AinvHT  # H A^-1 H^T (2.32)
        lam = -np.linalg.solve(S, H @ AinvB + Phi)  # (2.33)
        return AinvB + AinvHT @ lam, lam  # (2.31)/(2.34)

    def rhs(
        self,
        p: Array,
        u_of_t: Callable[[float, Array, Array], Array],
        alpha: float = 0.0,
        beta: float = 0.0,
    ) -> Callable[[float, Array], Array]:
        n = self.n

        def f(t: float, y: Array) -> Array:
            q, qd = y[:n], y[n:]
            qdd, _ = self.solve(t, q, qd, p, u_of_t(t, q, qd), alpha, beta)
            return np.concatenate([qd, qdd])

        return f

    def residuals(self, t: float, q: Array, qd: Array, p: Array, u: Array) -> tuple[Array, Array]:
        """``f`` (2.17) and the velocity-level rows ``H q' + psi`` ((2.26) and (2.19))."""
        P = self.parts(t, q, qd, p, u, ("f", "H", "psi"))
        return P["f"], P["H"] @ qd + P["psi"]

    def consistent_initial(
        self, t: float, q0: Array, qd0: Array, p: Array, u: Array, iters: int = 30
    ) -> tuple[Array, Array]:
        """Positions projected onto (2.17) (Gauss-Newton), velocities onto (2.29)."""
        q = np.array(q0, dtype=float)
        qd = np.array(qd0, dtype=float)
        for _ in range(iters):
            P = self.parts(t, q, qd, p, u)
            if self.n_hol == 0 or np.max(np.abs(P["f"]), initial=0.0) < 1e-14:
                break
            J = P["H"][: self.n_hol]
            q = q - np.linalg.pinv(J) @ P["f"]
        P = self.parts(t, q, qd, p, u)
        if self.v2:
            qd = qd - np.linalg.pinv(P["H"]) @ (P["H"] @ qd + P["psi"])
        return q, qd


# ---------------------------------------------------------------- formulas and differentiation


@lru_cache(maxsize=256)
def _derivative_functions(
    exprs: tuple[sp.Expr, ...], t: sp.Symbol
) -> tuple[tuple[Callable[..., Any], ...], ...]:
    """Numeric functions of the 0th, 1st and 2nd derivatives (built once per set of laws)."""
    return tuple(
        tuple(sp.lambdify(t, sp.diff(e, t, k), modules="numpy") for e in exprs) for k in range(3)
    )


def formula_derivatives(
    exprs: Sequence[sp.Expr], t: sp.Symbol
) -> Callable[[Array | float], tuple[Array, Array, Array]]:
    """``t -> (q, q', q'')`` for motion laws typed as formulas (exact derivatives);
    each is an ``(n, *shape(t))`` array."""
    fns = _derivative_functions(tuple(exprs), t)

    def ev(tt: Array | float) -> tuple[Array, Array, Array]:
        shape = np.shape(tt)
        with np.errstate(all="ignore"):
            return tuple(
                np.array(
                    [np.broadcast_to(np.asarray(f(tt), dtype=float), shape) for f in row],
                    dtype=float,
                )
                for row in fns
            )  # type: ignore[return-value]

    return ev


def sample_formulas(formulas: Sequence[Any], t: Array) -> Array:
    """Evaluate formulas of t on samples: an ``(k, len(t))`` array."""
    return np.array(
        [np.broadcast_to(np.asarray(f(t), dtype=float), np.shape(t)) for f in formulas], dtype=float
    ).reshape(len(formulas), -1)


def integrate(
    rhs: Callable[[float, Array], Array],
    y0: Array,
    t: Array,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str = "DOP853",
) -> tuple[Array, str]:
    """solve_ivp on the sample times; returns ``(y (n, len(t)), message)``.  A failed run is
    padded with NaN after the last good sample and the message says where it stopped."""
    bad: list[float] = []

    def guarded(tt: float, yy: Array) -> Array:
        # a non-finite derivative would make the step control loop forever: freeze the
        # state and let the terminal event below end the run
        if bad:
            return np.zeros_like(yy)
        try:
            out = np.asarray(rhs(tt, yy), dtype=float)
        except (np.linalg.LinAlgError, ZeroDivisionError, FloatingPointError, ValueError):
            out = np.array([np.nan])
        if not np.all(np.isfinite(out)):
            bad.append(tt)
            return np.zeros_like(yy)
        return out

    def stop(tt: float, yy: Array) -> float:
        return -1.0 if bad else 1.0

    stop.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(
        guarded,
        (float(t[0]), float(t[-1])),
        np.asarray(y0, dtype=float),
        method=method,
        t_eval=t,
        rtol=rtol,
        atol=atol,
        events=stop,
    )
    y = np.full((len(y0), len(t)), np.nan)
    k = sol.y.shape[1]
    if bad:
        k = int(np.searchsorted(t, bad[0], side="right"))
        k = min(k, sol.y.shape[1])
    y[:, :k] = sol.y[:, :k]
    if bad:
        msg = f"integration stopped at t = {bad[0]:.4g}: the equations gave a non-finite value (singular position or force)"
    elif not sol.success or k < len(t):
        msg = f"integration stopped at t = {t[max(k - 1, 0)]:.4g}: {sol.message}"
    else:
        msg = ""
    return y, msg


class OdeStepper(Stepper):
    """Live run of ``y' = rhs(t, y)``; ``make(params)`` gives ``(y0, rhs, frame_of(t, y))``.

    ``set_params`` rebuilds ``rhs`` and keeps ``(t, y)``; ``reset`` restarts from ``y0``.
    """

    def __init__(
        self,
        make: Callable[
            [Params], tuple[Array, Callable[[float, Array], Array], Callable[[float, Array], Frame]]
        ],
        params: Params,
        rtol: float = 1e-8,
        method: str = "DOP853",
    ) -> None:
        self._make = make
        self._rtol = rtol
        self._method = method
        self._params = params
        self._y0, self._rhs, self._frame_of = make(params)
        self._t = 0.0
        self._y = np.array(self._y0, dtype=float)
        self._message = ""

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        fr = self._frame_of(self._t, self._y)
        if self._message and not fr.message:
            fr.message = self._message
        return fr

    def advance(self, dt: float) -> Frame:
        if dt > 0 and not self._message:

            def guarded(tt: float, yy: Array) -> Array:
                out = np.asarray(self._rhs(tt, yy), dtype=float)
                if not np.all(np.isfinite(out)):
                    raise FloatingPointError(
                        f"the equations gave a non-finite value at t = {tt:.4g}"
                    )
                return out

            try:
                sol = solve_ivp(
                    guarded,
                    (self._t, self._t + dt),
                    self._y,
                    method=self._method,
                    rtol=self._rtol,
                    atol=self._rtol * 1e-2,
                )
                if sol.success and np.all(np.isfinite(sol.y[:, -1])):
                    self._y = sol.y[:, -1]
                    self._t = float(sol.t[-1])
                else:
                    self._message = f"stopped at t = {self._t:.4g}: {sol.message}"
            except (
                np.linalg.LinAlgError,
                ValueError,
                ZeroDivisionError,
                FloatingPointError,
            ) as exc:
                self._message = f"stopped at t = {self._t:.4g}: {exc}"
        return self.frame()

    def set_params(self, params: Params) -> None:
        self._params = params
        self._y0, self._rhs, self._frame_of = self._make(params)

    def reset(self) -> Frame:
        self._t = 0.0
        self._y = np.array(self._y0, dtype=float)
        self._message = ""
        return self.frame()


class ProgramStepper(Stepper):
    """Live run of a prescribed motion (inverse problem): the state is a function of t."""

    def __init__(self, make: Callable[[Params], Callable[[float], Frame]], params: Params) -> None:
        self._make = make
        self._frame_at = make(params)
        self._t = 0.0

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        return self._frame_at(self._t)

    def advance(self, dt: float) -> Frame:
        self._t += max(float(dt), 0.0)
        return self.frame()

    def set_params(self, params: Params) -> None:
        self._frame_at = self._make(params)

    def reset(self) -> Frame:
        self._t = 0.0
        return self.frame()


def numerical_second_derivative(t: Array, qd: Array) -> Array:
    """``q''`` from sampled ``q'`` by central differences (one-sided at the ends)."""
    return np.gradient(qd, t, axis=-1, edge_order=2)


def recover_inputs(
    model: LagrangeModel,
    t: Array,
    q: Array,
    qd: Array,
    p: Array,
    u_known: Array,
    unknown: Sequence[int],
) -> Array:
    """Inverse problem on a sampled motion (e.g. a forward run): ``q''`` by differences of
    the sampled ``q'``, then the unknown inputs at every sample; ``(n_inputs, len(t))``."""
    qdd = numerical_second_derivative(t, qd)
    return np.array(
        [
            model.solve_inputs(q[:, k], qd[:, k], qdd[:, k], float(t[k]), p, u_known[:, k], unknown)
            for k in range(len(t))
        ]
    ).T


# ---------------------------------------------------------------- poses and meshes


def quat_wxyz(R: Array) -> Array:
    """Rotation matrix -> unit quaternion ``(w, x, y, z)``."""
    x, y, z, w = Rotation.from_matrix(np.asarray(R, dtype=float)).as_quat()
    return np.array([w, x, y, z])


def quat_z(angle: float) -> Array:
    """Rotation by ``angle`` about Z as ``(w, x, y, z)``."""
    return np.array([np.cos(angle / 2), 0.0, 0.0, np.sin(angle / 2)])


IDENTITY_Q = np.array([1.0, 0.0, 0.0, 0.0])


def segment_pose(p0: Array, p1: Array) -> tuple[Array, Array]:
    """Pose of a mesh built along +Z and centred at the origin so that it spans p0 -> p1."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    d = p1 - p0
    n = np.linalg.norm(d)
    if n < 1e-15:
        return (p0 + p1) / 2, IDENTITY_Q.copy()
    rot, _ = Rotation.align_vectors([d / n], [[0.0, 0.0, 1.0]])
    x, y, z, w = rot.as_quat()
    return (p0 + p1) / 2, np.array([w, x, y, z])


def mesh_item(
    name: str,
    mesh: trimesh.Trimesh,
    color: tuple[int, int, int] = (120, 160, 220),
    opacity: float = 1.0,
) -> MeshItem:
    return MeshItem(
        name=name,
        vertices=np.asarray(mesh.vertices, dtype=float),
        faces=np.asarray(mesh.faces, dtype=np.int64),
        color=color,
        opacity=opacity,
    )


def box(
    name: str,
    extents: Sequence[float],
    color: tuple[int, int, int] = (120, 160, 220),
    center: Sequence[float] = (0, 0, 0),
    opacity: float = 1.0,
) -> MeshItem:
    m = trimesh.creation.box(extents=list(extents))
    m.apply_translation(list(center))
    return mesh_item(name, m, color, opacity)


def cylinder(
    name: str,
    radius: float,
    height: float,
    color: tuple[int, int, int] = (120, 160, 220),
    center: Sequence[float] = (0, 0, 0),
    sections: int = 32,
    opacity: float = 1.0,
) -> MeshItem:
    m = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    m.apply_translation(list(center))
    return mesh_item(name, m, color, opacity)


def combine(
    name: str,
    meshes: Sequence[trimesh.Trimesh],
    color: tuple[int, int, int] = (120, 160, 220),
    opacity: float = 1.0,
) -> MeshItem:
    return mesh_item(name, trimesh.util.concatenate(list(meshes)), color, opacity)


def bounds_of(
    points: Array, pad: float = 0.1
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Axis-aligned bounds of finite points with a margin ``pad`` (relative, at least 0.05)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        pts = np.zeros((1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    m = max(float(np.max(hi - lo)) * pad, 0.05)
    return (tuple(float(v) for v in lo - m), tuple(float(v) for v in hi + m))  # type: ignore[return-value]


def param_vector(params: Mapping[str, Any], names: Sequence[str]) -> Array:
    return np.array([float(params[n]) for n in names], dtype=float)


__all__ = [
    "ConstrainedSystem",
    "IDENTITY_Q",
    "LagrangeModel",
    "OdeStepper",
    "ProgramStepper",
    "bounds_of",
    "box",
    "combine",
    "cylinder",
    "dynamicsymbols",
    "formula_derivatives",
    "integrate",
    "mesh_item",
    "numerical_second_derivative",
    "param_vector",
    "plain_symbols",
    "quat_wxyz",
    "recover_inputs",
    "quat_z",
    "sample_formulas",
    "segment_pose",
    "to_plain",
]
