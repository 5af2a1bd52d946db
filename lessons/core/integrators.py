"""Integrators that keep a quadratic first integral to round-off.

Gauss–Legendre collocation (s stages, order 2s) conserves every quadratic invariant
of the field exactly in exact arithmetic, whatever the field's time dependence
(Cooper 1987); explicit Runge–Kutta methods do not.  The analyzer fields of chapter 1
keep ``F(r)`` (quadratic) constant, so these are the lab's default.

Two entry points, both vectorized over ``N`` points of a family (state ``(N, d)``):

* :func:`gl_linear` for affine fields ``r' = A(t) r + c(t)`` (the analyzers (1.30),
  (1.40), (1.50), (1.54), (1.63)): the stage equations are linear, so each step is an
  exact propagator ``r_{n+1} = Phi_n r_n + phi_n``; all propagators of a run are built in
  one batched solve, then applied in sequence.
* :class:`GLStepper` for any field ``f(t, r)`` (the constant-speed analyzer (1.59)):
  stages solved by a simplified Newton iteration to round-off.

:func:`solve_ivp_reference` runs scipy's ``solve_ivp`` on the same field so a lesson can
show what a generic solver does.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.integrate import solve_ivp

LinearCoeffs = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
"""``coeffs(t)`` with ``t`` of shape ``(m,)`` -> ``A`` of shape ``(m, N, d, d)`` and ``c`` of shape ``(m, N, d)``."""

Field = Callable[[float, np.ndarray], np.ndarray]
"""``f(t, R)`` with ``R`` of shape ``(N, d)`` -> ``(N, d)``."""


@lru_cache(maxsize=8)
def gauss_legendre(s: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Butcher tableau ``(a, b, c)`` of the s-stage Gauss–Legendre method (order 2s)."""
    if s not in (1, 2, 3):
        raise ValueError("Gauss-Legendre stages must be 1, 2 or 3")
    x, _ = np.polynomial.legendre.leggauss(s)
    c = (x + 1.0) / 2.0
    # a_ij = int_0^{c_i} l_j(tau) d tau, b_j = int_0^1 l_j; Lagrange basis on the nodes c.
    a = np.zeros((s, s))
    b = np.zeros(s)
    for j in range(s):
        others = [c[k] for k in range(s) if k != j]
        poly = np.poly1d([1.0])
        for ck in others:
            poly = poly * np.poly1d([1.0, -ck]) / (c[j] - ck)
        integ = poly.integ()
        b[j] = integ(1.0) - integ(0.0)
        for i in range(s):
            a[i, j] = integ(c[i]) - integ(0.0)
    return a, b, c


def gl_propagators(
    coeffs: LinearCoeffs, t0: float, h: float, n_steps: int, stages: int = 3
) -> tuple[np.ndarray, np.ndarray]:
    """Step maps of Gauss–Legendre for ``r' = A(t) r + c(t)`` in increment form.

    ``r_{n+1} = r_n + (D_n r_n + phi_n)`` with ``D (n, N, d, d)`` and ``phi (n, N, d)`` both
    O(h): applying the small increment (with compensated summation) keeps round-off
    from accumulating systematically when the same step map repeats (constant controls).
    """
    a, b, c = gauss_legendre(stages)
    s = stages
    ts = t0 + h * (np.arange(n_steps)[:, None] + c[None, :])  # (n, s)
    A, cc = coeffs(ts.ravel())
    m, N, d, _ = A.shape
    A = A.reshape(n_steps, s, N, d, d).transpose(0, 2, 1, 3, 4)  # (n, N, s, d, d)
    cc = cc.reshape(n_steps, s, N, d).transpose(0, 2, 1, 3)  # (n, N, s, d)
    eye = np.eye(d)
    # M_{ij} = delta_ij I - h a_ij A_i
    M = np.zeros((n_steps, N, s * d, s * d))
    rhs = np.zeros((n_steps, N, s * d, d + 1))
    for i in range(s):
        for j in range(s):
            block = -h * a[i, j] * A[:, :, i]
            if i == j:
                block = block + eye
            M[:, :, i * d : (i + 1) * d, j * d : (j + 1) * d] = block
        rhs[:, :, i * d : (i + 1) * d, :d] = A[:, :, i]
        rhs[:, :, i * d : (i + 1) * d, d] = cc[:, :, i]
    K = np.linalg.solve(M, rhs)  # (n, N, s*d, d+1): stage slopes per unit r and for c
    weighted = sum(b[i] * K[:, :, i * d : (i + 1) * d, :] for i in range(s)) * h
    return weighted[..., :d], weighted[..., d]


def apply_propagators(D: np.ndarray, phi: np.ndarray, r0: np.ndarray) -> np.ndarray:
    """Apply increment maps in sequence (Kahan-compensated): ``(n+1, N, d)`` states from ``r0 (N, d)``."""
    n = D.shape[0]
    out = np.empty((n + 1, *r0.shape))
    out[0] = r = np.array(r0, dtype=float)
    comp = np.zeros_like(r)
    for k in range(n):
        inc = (D[k] @ r[:, :, None])[:, :, 0] + phi[k] - comp
        new = r + inc
        comp = (new - r) - inc
        r = new
        out[k + 1] = r
    return out


def gl_linear(
    coeffs: LinearCoeffs,
    r0: np.ndarray,
    t0: float,
    t_end: float,
    h: float,
    stages: int = 3,
    chunk: int = 20000,
) -> tuple[np.ndarray, np.ndarray]:
    """Integrate ``r' = A(t) r + c(t)`` from ``t0`` to ``t_end`` with step ``h`` (last step shortened).

    Returns ``t (n+1,)`` and states ``(n+1, N, d)``.  Work is done in chunks of steps
    to bound memory.
    """
    r0 = np.atleast_2d(np.asarray(r0, dtype=float))
    span = t_end - t0
    if span < 0 or h <= 0:
        raise ValueError("need t_end >= t0 and h > 0")
    n_full = int(np.floor(span / h + 1e-9))
    rest = span - n_full * h
    ts = [np.array([t0])]
    states = [r0[None]]
    r = r0
    t = t0
    done = 0
    while done < n_full:
        m = min(chunk, n_full - done)
        Phi, phi = gl_propagators(coeffs, t, h, m, stages)
        seq = apply_propagators(Phi, phi, r)
        states.append(seq[1:])
        ts.append(t + h * np.arange(1, m + 1))
        r = seq[-1]
        t = t + m * h
        done += m
    if rest > 1e-12 * max(1.0, abs(h)):
        Phi, phi = gl_propagators(coeffs, t, rest, 1, stages)
        seq = apply_propagators(Phi, phi, r)
        states.append(seq[1:])
        ts.append(np.array([t0 + span]))
    return np.concatenate(ts), np.concatenate(states)


@dataclass
class StepStats:
    iterations: int = 0
    steps: int = 0
    evaluations: int = 0


class GLStepper:
    """Gauss–Legendre steps for a general field, stages by simplified Newton to round-off.

    ``jac(t, R) -> (N, d, d)`` approximates the field's Jacobian (used only to
    precondition the iteration; the converged stages solve the exact equations).
    """

    def __init__(
        self,
        field: Field,
        jac: Callable[[float, np.ndarray], np.ndarray],
        stages: int = 3,
        max_iter: int = 40,
    ) -> None:
        self.field = field
        self.jac = jac
        self.stages = stages
        self.max_iter = max_iter
        self.stats = StepStats()

    def step(self, t: float, R: np.ndarray, h: float) -> np.ndarray:
        a, b, c = gauss_legendre(self.stages)
        s = self.stages
        N, d = R.shape
        J = self.jac(t + h / 2, R)  # (N, d, d)
        eye = np.eye(d)
        M = np.zeros((N, s * d, s * d))
        for i in range(s):
            for j in range(s):
                blk = -h * a[i, j] * J
                if i == j:
                    blk = blk + eye
                M[:, i * d : (i + 1) * d, j * d : (j + 1) * d] = blk
        Minv = np.linalg.inv(M)
        K = np.repeat(self.field(t + c[0] * h, R)[:, None, :], s, axis=1)  # (N, s, d)
        self.stats.evaluations += 1
        prev = np.inf
        for it in range(self.max_iter):
            Y = R[:, None, :] + h * np.einsum("ij,njd->nid", a, K)
            F = np.stack([self.field(t + c[i] * h, Y[:, i]) for i in range(s)], axis=1)
            self.stats.evaluations += s
            G = (K - F).reshape(N, s * d)
            dK = -np.einsum("nij,nj->ni", Minv, G).reshape(N, s, d)
            K = K + dK
            size = float(np.max(np.abs(dK)))
            scale = float(np.max(np.abs(K))) + 1e-300
            self.stats.iterations += 1
            if size <= 1e-15 * scale or (size >= prev and size <= 1e-13 * scale):
                break
            prev = size
        self.stats.steps += 1
        return R + h * np.einsum("i,nid->nd", b, K)

    def integrate(
        self, R0: np.ndarray, t0: float, t_end: float, h: float, record_every: int = 1
    ) -> tuple[np.ndarray, np.ndarray]:
        """Fixed steps from ``t0`` to ``t_end`` (last step shortened); states every ``record_every`` steps."""
        R = np.atleast_2d(np.asarray(R0, dtype=float))
        n_full = int(np.floor((t_end - t0) / h + 1e-9))
        ts, out = [t0], [R.copy()]
        t = t0
        for k in range(n_full):
            R = self.step(t, R, h)
            t = t0 + (k + 1) * h
            if (k + 1) % record_every == 0:
                ts.append(t)
                out.append(R.copy())
        rest = t_end - t
        if rest > 1e-12 * max(1.0, h):
            R = self.step(t, R, rest)
            ts.append(t_end)
            out.append(R.copy())
        elif ts[-1] != t:
            ts.append(t)
            out.append(R.copy())
        return np.asarray(ts), np.stack(out)


def solve_ivp_reference(
    field: Field,
    R0: np.ndarray,
    t0: float,
    t_end: float,
    t_eval: np.ndarray,
    method: str = "RK45",
    rtol: float = 1e-3,
    atol: float = 1e-6,
) -> tuple[np.ndarray, np.ndarray, int]:
    """The same field through scipy's ``solve_ivp``: ``(t, states (m, N, d), nfev)``."""
    R0 = np.atleast_2d(np.asarray(R0, dtype=float))
    shape = R0.shape

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return field(t, y.reshape(shape)).ravel()

    sol = solve_ivp(
        rhs, (t0, t_end), R0.ravel(), method=method, rtol=rtol, atol=atol, t_eval=t_eval
    )
    if not sol.success:
        raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
    return sol.t, sol.y.T.reshape(len(sol.t), *shape), int(sol.nfev)
