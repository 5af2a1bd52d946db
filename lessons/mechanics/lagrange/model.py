"""Lagrange equations of the 2nd kind for chapter 2: symbolic models and the inverse problem.

:class:`LagrangeModel` wraps ``sympy.physics.mechanics.LagrangesMethod``: from a
Lagrangian ``L = T - U`` and the applied forces (their virtual work gives the generalized
forces, (2.10)/(2.16)) it keeps the symbolic equations ``M(q) q'' = F(q, q', t, u)`` and
lambdifies them once, for the forward problem (accelerations from forces) and the inverse
problem (forces from a motion law, :meth:`LagrangeModel.solve_inputs`).  Motion laws typed
as formulas of t are differentiated exactly (:func:`formula_derivatives`); a sampled motion
is differentiated numerically (:func:`recover_inputs`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, msubs

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
        # M and F as nested lists of plain floats from one function (shared subexpressions
        # once): one sample at a time, as the integration and a played frame ask
        self._num["MF"] = sp.lambdify(
            args, [M.tolist(), list(F)], modules=["math", "numpy"], cse=True
        )
        self._num["MFG"] = sp.lambdify(
            args, [M.tolist(), list(F), G.tolist()], modules=["math", "numpy"], cse=True
        )

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

    def acceleration_list(
        self,
        q: Sequence[float],
        qd: Sequence[float],
        t: float,
        p: Sequence[float],
        u: Sequence[float],
    ) -> list[float]:
        """``q''`` from ``M q'' = F`` on plain floats (one sample; lists are fastest): ``M``
        and ``F`` from one function with the ``math`` module, solved by
        :func:`solve_small`; equal to :meth:`accelerations` to round-off.  Where the
        arrays would give inf or NaN (a math domain error, a division by zero) it gives
        NaN."""
        try:
            M, F = self._num["MF"](q, qd, t, p, u)
        except (ValueError, ZeroDivisionError, OverflowError):
            return [math.nan] * self.n
        return solve_small(M, F)

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

    def input_list(
        self,
        q: Sequence[float],
        qd: Sequence[float],
        qdd: Sequence[float],
        t: float,
        p: Sequence[float],
        u_known: Sequence[float],
        unknown: Sequence[int],
    ) -> list[float]:
        """:meth:`solve_inputs` on plain floats (one sample): ``M``, ``F`` and ``G`` from
        one function with the ``math`` module; as many unknown inputs as equations are
        solved by :func:`solve_small` (a singular or non-square system by least squares,
        as :meth:`solve_inputs`).  NaN where the arrays would give inf or NaN."""
        u0 = [float(v) for v in u_known]
        for k in unknown:
            u0[k] = 0.0
        try:
            M, F, G = self._num["MFG"](q, qd, t, p, u0)
        except (ValueError, ZeroDivisionError, OverflowError):
            return [math.nan] * len(u0)
        n = self.n
        resid = [sum(M[i][j] * qdd[j] for j in range(n)) - F[i] for i in range(n)]
        Gu = [[G[i][k] for k in unknown] for i in range(n)]
        try:
            if len(unknown) != n:
                raise np.linalg.LinAlgError("not square")
            sol = solve_small(Gu, resid)
        except np.linalg.LinAlgError:
            A = np.array(Gu, dtype=float).reshape(n, len(unknown))
            sol = np.linalg.lstsq(A, np.array(resid, dtype=float), rcond=None)[0].tolist()
        for k, v in zip(unknown, sol):
            u0[k] = v
        return u0


def solve_small(M: Sequence[Sequence[float]], b: Sequence[float]) -> list[float]:
    """``M x = b`` for a small dense system on plain numbers: Gaussian elimination with
    partial pivoting (as LAPACK's ``gesv``, equal to it to round-off); a zero pivot
    raises :class:`numpy.linalg.LinAlgError` as it does."""
    n = len(b)
    if n == 1:
        if M[0][0] == 0:
            raise np.linalg.LinAlgError("Singular matrix")
        return [b[0] / M[0][0]]
    A = [[*row, bi] for row, bi in zip(M, b)]
    for k in range(n):
        piv, big = k, abs(A[k][k])
        for i in range(k + 1, n):
            if abs(A[i][k]) > big:
                piv, big = i, abs(A[i][k])
        if A[piv][k] == 0:
            raise np.linalg.LinAlgError("Singular matrix")
        A[k], A[piv] = A[piv], A[k]
        rk, d = A[k], A[k][k]
        for i in range(k + 1, n):
            ri = A[i]
            f = ri[k] / d
            for j in range(k + 1, n + 1):
                ri[j] -= f * rk[j]
    x = [0.0] * n
    for k in range(n - 1, -1, -1):
        rk = A[k]
        acc = rk[n]
        for j in range(k + 1, n):
            acc -= rk[j] * x[j]
        x[k] = acc / rk[k]
    return x


# ---------------------------------------------------------------- motion laws


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
            if not shape:
                return tuple(np.array([float(f(tt)) for f in row]) for row in fns)  # type: ignore[return-value]
            if shape == (1,):  # a live frame: one time
                x = np.asarray(tt, dtype=float)[0]  # numpy's scalar: 1/0 is inf, as in arrays
                return tuple(np.array([[float(f(x))] for f in row]) for row in fns)  # type: ignore[return-value]
            return tuple(
                np.array(
                    [np.broadcast_to(np.asarray(f(tt), dtype=float), shape) for f in row],
                    dtype=float,
                )
                for row in fns
            )  # type: ignore[return-value]

    return ev


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
