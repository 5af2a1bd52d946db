"""Integrators that keep a quadratic first integral to round-off.

Gauss–Legendre collocation (s stages, order 2s) conserves every quadratic invariant
of the field exactly in exact arithmetic, whatever the field's time dependence
(Cooper 1987); explicit Runge–Kutta methods do not.  The analyzer fields of chapter 1
keep ``F(r)`` (quadratic) constant, so these are the lab's default.

For affine fields ``r' = A(t) r + c(t)`` (the analyzers (1.30), (1.40), (1.50), (1.54),
(1.63)) the stage equations are linear, so each step is an exact propagator
``r_{n+1} = r_n + D_n r_n + phi_n``: :func:`gl_propagators` builds the propagators of many
steps in one batched solve, :func:`apply_propagators` applies them in sequence and
:func:`gl_linear` does both over a run; all are vectorized over ``N`` points of a family
(state ``(N, d)``).  The nonlinear constant-speed analyzer (1.59) is stepped by
:class:`analyzer_lab.lessons.analyzers.field.speed_stepper.SpeedStepper` (the same tableau, stages by simplified
Newton to round-off).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

import numpy as np

#: The most stages :func:`gauss_legendre` builds (order 12).
MAX_STAGES = 6

LinearCoeffs = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
"""``coeffs(t)`` with ``t`` of shape ``(m,)`` -> ``A`` of shape ``(m, N, d, d)`` and ``c`` of shape ``(m, N, d)``."""


@lru_cache(maxsize=8)
def gauss_legendre(s: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Butcher tableau ``(a, b, c)`` of the s-stage Gauss–Legendre method (order 2s),
    ``1 <= s <= MAX_STAGES``.

    ``c``: the Gauss nodes on [0, 1]; ``b``: their quadrature weights; ``a_ij``: the
    integral of the Lagrange basis polynomial ``l_j`` on the nodes over ``[0, c_i]``,
    taken by the same s-point rule on ``[0, c_i]`` (exact for its degree s - 1)."""
    if not 1 <= s <= MAX_STAGES:
        raise ValueError(f"Gauss-Legendre stages must be 1 to {MAX_STAGES}")
    x, w = np.polynomial.legendre.leggauss(s)
    c, b = (x + 1.0) / 2.0, w / 2.0
    tau = c[:, None] * c[None, :]  # (i, q): the rule's points on [0, c_i]
    basis = np.ones((s, s, s))  # (i, q, j): l_j(tau_iq)
    for j in range(s):
        for k in range(s):
            if k != j:
                basis[:, :, j] *= (tau - c[k]) / (c[j] - c[k])
    a = c[:, None] * np.einsum("q,iqj->ij", b, basis)
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
    # M_{ij} = delta_ij I - h a_ij A_i, built as (n, N, s, d, s, d) in one broadcast
    M = -h * a[None, None, :, None, :, None] * A[:, :, :, :, None, :]
    M = M + np.eye(s * d).reshape(s, d, s, d)
    rhs = np.concatenate([A, cc[..., None]], axis=-1)  # (n, N, s, d, d+1)
    K = np.linalg.solve(M.reshape(n_steps, N, s * d, s * d), rhs.reshape(n_steps, N, s * d, d + 1))
    K = K.reshape(n_steps, N, s, d, d + 1)
    weighted = sum(b[i] * K[:, :, i] for i in range(s)) * h
    return weighted[..., :d], weighted[..., d]


def apply_propagators(
    D: np.ndarray, phi: np.ndarray, r0: np.ndarray, comp: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Apply increment maps in sequence (Kahan-compensated): ``(n+1, N, d)`` states from
    ``r0 (N, d)``, and the compensation to carry into the next sequence (``comp``)."""
    n = D.shape[0]
    out = np.empty((n + 1, *r0.shape))
    out[0] = r = np.array(r0, dtype=float)
    comp = np.zeros_like(r) if comp is None else comp
    for k in range(n):
        inc = (D[k] @ r[:, :, None])[:, :, 0] + phi[k] - comp
        new = r + inc
        comp = (new - r) - inc
        r = new
        out[k + 1] = r
    return out, comp


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
        seq, _ = apply_propagators(Phi, phi, r)
        states.append(seq[1:])
        ts.append(t + h * np.arange(1, m + 1))
        r = seq[-1]
        t = t + m * h
        done += m
    if rest > 1e-12 * max(1.0, abs(h)):
        Phi, phi = gl_propagators(coeffs, t, rest, 1, stages)
        seq, _ = apply_propagators(Phi, phi, r)
        states.append(seq[1:])
        ts.append(np.array([t0 + span]))
    return np.concatenate(ts), np.concatenate(states)
