"""Batched numbers of the §2.2 algorithm: (2.29), (2.30), (2.33), (2.34) at many states.

A :class:`ConstraintEval` takes the symbolic matrices of a constrained system
(``A, B, f, H, psi, Phi`` in the plain symbols ``q, q', t``, its parameters and
inputs, as :class:`analyzer_lab.lessons.mechanics.lagrange.constrained.ConstrainedSystem` keeps them) and lambdifies
them once into one function of whole arrays of states.  The multipliers (2.33) and the
accelerations (2.34) then come from stacked solves: one call serves the integrator (one
state), a live frame (one state) and a headless run (every sample at once), with the
same formulas.  :meth:`ConstraintEval.accelerations` is (2.34) eliminated symbolically once
and generated as code on plain floats, for the integrator's one state at a time.
Baumgarte stabilization (not in the source) replaces ``Phi`` by
``Phi + 2 alpha (H q' + psi) + beta^2 f``.  The module also holds the algorithm as the
page shows it (:func:`algorithm_steps`) with the source's slips corrected
(:data:`CORRECTIONS`, each with one line of evidence).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import DerivationStep, Note

Array = np.ndarray
_NAMES = ("A", "B", "f", "H", "psi", "Phi")


@dataclass
class Parts:
    """``A (N,n,n), B (N,n), f (N,v1), H (N,v2,n), psi (N,v2), Phi (N,v2)`` at N states."""

    A: Array
    B: Array
    f: Array
    H: Array
    psi: Array
    Phi: Array


class ConstraintEval:
    """Numeric (2.25)-(2.34) of a constrained system, vectorized over states."""

    def __init__(self, system: Any) -> None:
        self.n, self.v2, self.n_hol = len(system.q), int(system.H.rows), int(system.n_hol)
        mats = [system.A, system.B, system.f_hol, system.H, system.psi, system.Phi]
        self._shapes = [
            (self.n, self.n),
            (self.n,),
            (self.n_hol,),
            (self.v2, self.n),
            (self.v2,),
            (self.v2,),
        ]
        self._sizes = [int(np.prod(shape)) for shape in self._shapes]
        flat = [e for m in mats for e in m]
        args = (system.q, system.qd, system.t, system.params, system.inputs)
        self._fn = sp.lambdify(args, flat, modules="numpy", cse=True)
        self._size = len(flat)
        self._system = system
        self._accelerations: Callable[..., list[float]] | None = None

    def accelerations(self) -> Callable[..., list[float]]:
        """(2.34) at one state on plain floats, ``fn(q, q', t, p, u, alpha, beta) -> q''``
        (lists of floats): (2.31)-(2.33) eliminated symbolically, with Baumgarte's terms,
        and generated once (common subexpressions shared).  The same numbers as
        :meth:`solve` to round-off."""
        if self._accelerations is None:
            self._accelerations = _accelerations_code(self._system)
        return self._accelerations

    def parts(self, t: Array, q: Array, qd: Array, p: Array, u: Array) -> Parts:
        """The matrices at the states ``q, qd`` of shape ``(n, N)`` and times ``t`` (N,);
        ``u`` the inputs ``(k, N)``."""
        N = len(t)
        values = self._fn(list(q), list(qd), t, list(p), list(u))
        flat = np.empty((self._size, N))
        for i, v in enumerate(values):
            flat[i] = v
        out, k = [], 0
        for shape, size in zip(self._shapes, self._sizes):
            out.append(flat[k : k + size].T.reshape(N, *shape))
            k += size
        return Parts(*out)

    def residuals(self, P: Parts, qd: Array) -> tuple[Array, Array]:
        """``f`` (2.17) and the velocity rows ``H q' + psi`` ((2.26), (2.19)): (N, v1), (N, v2)."""
        return P.f, np.einsum("kij,jk->ki", P.H, qd) + P.psi

    def solve(
        self, P: Parts, qd: Array, alpha: float = 0.0, beta: float = 0.0
    ) -> tuple[Array, Array]:
        """Accelerations (2.34) and multipliers (2.33): ``(N, n)``, ``(N, v2)``."""
        X = np.linalg.solve(P.A, np.concatenate([P.B[:, :, None], np.swapaxes(P.H, 1, 2)], axis=2))
        AinvB, AinvHT = X[:, :, 0], X[:, :, 1:]  # A^-1 [B | H^T]
        Phi = P.Phi
        if alpha or beta:
            _, c = self.residuals(P, qd)
            Phi = Phi + 2.0 * alpha * c
            Phi[:, : self.n_hol] += beta**2 * P.f
        S = P.H @ AinvHT  # H A^-1 H^T (2.32)
        rhs = np.einsum("kij,kj->ki", P.H, AinvB) + Phi
        lam = -np.linalg.solve(S, rhs[:, :, None])[:, :, 0]  # (2.33)
        return AinvB + np.einsum("kij,kj->ki", AinvHT, lam), lam  # (2.31)/(2.34)


def _accelerations_code(system: Any) -> Callable[..., list[float]]:
    """(2.31)-(2.34) solved symbolically (LU) and lambdified on the ``math`` module."""
    alpha, beta = sp.Dummy("alpha"), sp.Dummy("beta")
    A, B, H = system.A, system.B, system.H
    if H.rows == 0:
        qdd = A.LUsolve(B)
    else:
        n_hol = int(system.n_hol)
        f = [*system.f_hol, *[sp.S.Zero] * (H.rows - n_hol)]
        c = H * sp.Matrix(system.qd) + system.psi  # H q' + psi
        Phi = system.Phi + 2 * alpha * c + beta**2 * sp.Matrix(f)
        X = A.LUsolve(B.row_join(H.T))  # A^-1 [B | H^T]
        AinvB, AinvHT = X[:, 0], X[:, 1:]
        lam = -(H * AinvHT).LUsolve(H * AinvB + Phi)  # (2.32), (2.33)
        qdd = AinvB + AinvHT * lam  # (2.31)/(2.34)
    args = (system.q, system.qd, system.t, system.params, system.inputs, alpha, beta)
    fn: Callable[..., list[float]] = sp.lambdify(args, list(qdd), modules="math", cse=True)
    return fn


# ---------------------------------------------------------------- the algorithm as the page shows it

#: The source's slips in §2.2 and in its solution sequence, shown corrected:
#: (equation or step, what is used, one line of evidence).
CORRECTIONS: tuple[tuple[str, str, str], ...] = (
    (
        "(2.19)",
        "g_i (the nonholonomic constraint) is linear in the velocities",
        "the source says 'for the function f_i'; (2.18) names the nonholonomic ones g_i",
    ),
    (
        "(2.24)",
        "multipliers lambda_1..lambda_v2, one per constraint",
        "the source writes lambda_1..lambda_v1; H has v2 rows, and the nonholonomic rows "
        "v1+1..v2 need multipliers too",
    ),
    (
        "(2.24)",
        "H is v2 x n",
        "the source calls H 'rectangular n x n'; it stacks v2 rows of n derivatives",
    ),
    (
        "§2.2, solution step 2",
        "initial positions from (2.17)",
        "the source cites (2.17) and (2.18); (2.18) restricts velocities, not positions",
    ),
    (
        "§2.2, solution step 3",
        "initial velocities from (2.29): H q'0 = -psi",
        "the source cites (2.30), which holds accelerations, not velocities",
    ),
    (
        "§2.2, solution step 4",
        "multipliers eliminated with (2.25) and (2.30)",
        "the source cites (2.22) and (2.23), the forms before the multipliers are chosen; "
        "(2.31)-(2.33) use (2.25) and (2.30)",
    ),
)


def corrected(source: str) -> str:
    """The evidence lines of the corrections of ``source``, each tagged 'corrected'."""
    return "; ".join(f"corrected: {ev}" for src, _, ev in CORRECTIONS if src == source)


def correction_notes() -> list[Note]:
    """The corrections as notes (kind 'corrected', the equation, one line of evidence)."""
    return [Note("corrected", f"{src}: {text}", src, ev) for src, text, ev in CORRECTIONS]


def algorithm_steps() -> list[DerivationStep]:
    """(2.17)-(2.34) and the solution sequence of §2.2, in the corrected form."""
    return [
        DerivationStep("Holonomic constraints", "", r"f_i(q,t)=0,\quad i=1,\dots,v_1", "(2.17)"),
        DerivationStep(
            "Nonholonomic constraints, linear in the velocities",
            "",
            r"g_i=a_{i1}\dot q_1+\dots+a_{in}\dot q_n+a_i^{*}=0,\quad i=v_1+1,\dots,v_2",
            "(2.19)",
            reconstructed=corrected("(2.19)"),
        ),
        DerivationStep(
            "d'Alembert principle with multipliers, loops opened",
            "One multiplier per constraint: lambda = [lambda_1 ... lambda_v2]^T; H has v2 rows "
            "(one per constraint) and n columns.",
            r"\delta q^{T}\left(-A\ddot q+B+B^{*}+H^{T}\lambda\right)=0,\quad"
            r"\lambda=\left[\lambda_1\;\cdots\;\lambda_{v_2}\right]^{T},\quad "
            r"H=\left[f_1'^{T}\cdots f_{v_1}'^{T}\;a_{v_1+1}^{T}\cdots a_{v_2}^{T}\right]^{T}"
            r"\in\mathbb{R}^{v_2\times n}",
            "(2.24)",
            reconstructed=corrected("(2.24)"),
        ),
        DerivationStep(
            "Equations with multipliers", "", r"A\ddot q=B+B^{*}+H^{T}\lambda", "(2.25)"
        ),
        DerivationStep(
            "Velocity level",
            "psi renames the source's first Phi (it holds df_i/dt and a_i*).",
            r"H\dot q=-\psi(q,t)",
            "(2.26), (2.29)",
        ),
        DerivationStep(
            "Acceleration level", "", r"H\ddot q=-\Phi(q,\dot q,t)", "(2.27), (2.28), (2.30)"
        ),
        DerivationStep(
            "Multipliers",
            "",
            r"\lambda=-\left(HA^{-1}H^{T}\right)^{-1}\left(HA^{-1}(B+B^{*})+\Phi\right)",
            "(2.33)",
        ),
        DerivationStep(
            "Accelerations",
            "",
            r"\ddot q=A^{-1}\left\{B+B^{*}-H^{T}\left(HA^{-1}H^{T}\right)^{-1}"
            r"\left[HA^{-1}(B+B^{*})+\Phi\right]\right\}",
            "(2.34)",
        ),
        DerivationStep(
            "Solution step 2: initial positions",
            "Choose q^0 at t_0 on the holonomic constraints (here: projected by Gauss-Newton).",
            r"f_i(q^0,t_0)=0,\quad i=1,\dots,v_1",
            "§2.2, solution step 2",
            reconstructed=corrected("§2.2, solution step 2"),
        ),
        DerivationStep(
            "Solution step 3: initial velocities",
            "The velocities satisfy the velocity level (here: projected by the pseudo-inverse).",
            r"H(q^0,t_0)\,\dot q^0=-\psi(q^0,t_0)",
            "§2.2, solution step 3",
            reconstructed=corrected("§2.2, solution step 3"),
        ),
        DerivationStep(
            "Solution step 4: eliminate the multipliers",
            "Solve (2.25) for q'' (2.31), substitute into (2.30) (2.32): (2.33), then (2.34).",
            r"\ddot q=A^{-1}\left(B+B^{*}+H^{T}\lambda\right),\quad H\ddot q=-\Phi",
            "§2.2, solution step 4",
            reconstructed=corrected("§2.2, solution step 4"),
        ),
        DerivationStep(
            "Baumgarte stabilization (not in the source)",
            "Constraint errors obey a damped equation instead of drifting.",
            r"\Phi\to\Phi+2\alpha\left(H\dot q+\psi\right)+\beta^{2}f",
            reconstructed="an addition: the source integrates (2.34) as it stands",
        ),
    ]
