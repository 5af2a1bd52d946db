"""The formalized algorithm of §2.2 for systems with constraints, eqs (2.17)-(2.34).

:class:`ConstrainedSystem` opens the loops of a mechanism: the opened system
``A(q,t) q'' = B(q,q',t) + H^T lambda`` (2.25) with holonomic constraints (2.17) and
nonholonomic ones (2.18)-(2.19), in the corrected form: ``H`` is ``v2 x n``, the velocity
level (2.29) ``H q' = -psi`` gives the initial velocities, the acceleration level (2.30)
``H q'' = -Phi`` gives the multipliers (2.33) and the accelerations (2.34).  Optional
Baumgarte stabilization (not in the source) replaces ``Phi`` by
``Phi + 2 alpha (H q' + psi) + beta^2 f``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.mechanics.lagrange.model import LagrangeModel, plain_symbols

Array = np.ndarray


def args_of(cs: ConstrainedSystem) -> tuple[Any, ...]:
    """The arguments of the numeric functions: ``(q, q', t, params, inputs)``."""
    return (cs.q, cs.qd, cs.t, cs.params, cs.inputs)


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
    _many: dict[str, Any] = field(default_factory=dict, repr=False)

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
        qv = sp.Matrix(q)
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

    def part_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shape of each part at one state: ``A`` (n, n), ``B`` (n,), the holonomic
        residuals ``f``, ``H`` (v2, n), ``psi`` and ``Phi`` (v2,)."""
        n, v2 = self.n, self.v2
        return {
            "A": (n, n),
            "B": (n,),
            "f": (self.n_hol,),
            "H": (v2, n),
            "psi": (v2,),
            "Phi": (v2,),
        }

    def _lambdify(self) -> None:
        args = args_of(self)
        for name in ("A", "B", "f_hol", "H", "psi", "Phi"):
            self._num[name] = sp.lambdify(args, getattr(self, name), modules="numpy", cse=True)

    def parts_many(
        self,
        t: float,
        q: Array,
        qd: Array,
        p: Array,
        u: Array,
        names: Sequence[str] = ("A", "B", "f", "H", "psi", "Phi"),
    ) -> dict[str, Array]:
        """:meth:`parts` at ``N`` states at once: ``q``, ``qd`` are ``(N, n)``; each part
        gets a leading axis of length ``N`` (one vectorized evaluation of its entries)."""
        q, qd = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)
        N = q.shape[0]
        a = (list(q.T), list(qd.T), t, p, u)
        shapes = self.part_shapes()
        out: dict[str, Array] = {}
        for k in names:
            name = "f_hol" if k == "f" else k
            fns = self._many.get(name)
            if fns is None:
                fns = self._many[name] = self._lambdify_many(getattr(self, name))
            varying, fixed, per_state, once = fns
            flat = np.empty((N, int(np.prod(shapes[k]))))
            if len(varying):
                flat[:, varying] = np.stack(per_state(*a), axis=1)
            if len(fixed):
                flat[:, fixed] = once(*a)
            out[k] = flat.reshape((N, *shapes[k]))
        return out

    def _lambdify_many(
        self, m: sp.Matrix
    ) -> tuple[Array, Array, Callable[..., Any], Callable[..., Any]]:
        """The entries of ``m`` that vary with the state (``q``, ``q'``) and those that do
        not, each as one numeric function of all arguments returning a list."""
        entries = list(m)
        state = set(self.q) | set(self.qd)
        varying = [i for i, e in enumerate(entries) if e.free_symbols & state]
        fixed = [i for i in range(len(entries)) if i not in set(varying)]
        args = args_of(self)

        def fn(idx: list[int]) -> Callable[..., Any]:
            return sp.lambdify(args, [entries[i] for i in idx], modules="numpy", cse=True)

        return np.array(varying, dtype=int), np.array(fixed, dtype=int), fn(varying), fn(fixed)

    def _eval(self, name: str, shape: tuple[int, ...], *args: Any) -> Array:
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
        a, shapes = (q, qd, t, p, u), self.part_shapes()
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
