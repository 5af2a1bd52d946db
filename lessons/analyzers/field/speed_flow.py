"""The constant-speed analyzer (1.59) as a time change of (1.50), where that is exact.

(1.59) runs the analyzer (1.50) ``dr/dphi = A r + c`` with its argument driven by

    dphi/dt = omega = sigma V / |A r + c|                                   (1.58)

so ``dr/dt = omega (A r + c)``.  When u1, u2, u3 and V do not depend on t and ``A`` is
skew (``A + A^T = 0``: the sphere (1.54) with any constant controls, or a quadric whose
controls turn it about an axis of symmetry), the field ``n = A r + c`` moves by
``dn/dphi = A n``, so ``d|n|^2/dphi = n^T (A + A^T) n = 0``: |n| keeps its starting value
``|n0|`` along the path, ``omega`` is a constant per point and

    phi(t) = sigma V (t - t0) / |n0|,   r(t) = r_(1.50)(phi(t)).

(1.59) is then the affine field ``omega (A r + c)`` with a fixed ``omega``: its
Gauss-Legendre step maps (:func:`analyzer_lab.lessons.kit.integrators.gl_propagators`) keep F to
round-off (GL keeps every quadratic invariant of a field) and repeat from step to step, so
a run applies one kept map per node and per shortened step, as for a constant (1.50).  A
point where the field vanishes (:meth:`AnalyzerModel.holds`) keeps ``omega = 0``: it holds
for the whole run, as the stage-by-stage solve of
:class:`analyzer_lab.lessons.analyzers.field.speed_stepper.SpeedStepper` holds it.  The steps are cut into the
substeps that stepper takes (a turn of at most ``max_turn`` each), so the two agree to
round-off of the run (about 1e-14 over Fig. 1.28's 10 s).

A shortened step (a frame between two nodes) of length ``L`` is the kept Gauss-Legendre map
of the nearest multiple ``Lc`` of ``h / COARSE_GRAIN`` after the exact flow over the rest
``L - Lc`` (a few nanoseconds: ``exp(d M) = I + d M + (d M)^2 / 2`` to round-off): played
times drift off the session's quanta by round-off of their sum, which would otherwise ask
for a new Gauss-Legendre solve every few frames.
"""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.analyzers.field.analyzer import AnalyzerModel
from analyzer_lab.lessons.kit.integrators import LinearCoeffs, gl_propagators

#: Largest symmetric part ``|A + A^T|`` (relative to ``|A|``) counted as skew: round-off.
SKEW_TOL = 1e-15
#: Shortened steps are kept Gauss-Legendre maps of lengths on the grid ``h / COARSE_GRAIN``
#: (at most COARSE_MAPS of them), followed by the exact flow over the rest, used while the
#: turn over a grid cell is below TAYLOR_TURN (its Taylor series' next term is then ~1e-25).
COARSE_GRAIN = 2**24
COARSE_MAPS = 256
TAYLOR_TURN = 1e-8

Map = tuple[np.ndarray, np.ndarray]


class UniformSpeed:
    """(1.59) from ``r0 (N, 3)`` as the affine field ``omega (A r + c)`` with constant
    ``omega`` per point (see the module docstring); :meth:`of` builds it where exact."""

    def __init__(self, model: AnalyzerModel, omega: np.ndarray, rate: float, max_turn: float):
        self.model = model
        #: omega (1.58) per point, constant along its path
        self.omega = omega
        #: the largest turning rate ``omega |A|_F`` (rad/s) of the points
        self.rate = rate
        self.max_turn = max_turn
        N = len(omega)
        A, c = model.linear_coeffs(np.zeros(1), N)
        self._A = omega[:, None, None] * A[0]
        self._c = omega[:, None] * c[0]
        self._coarse: dict[tuple[float, int], Map] = {}

    @classmethod
    def of(cls, model: AnalyzerModel, r0: np.ndarray, max_turn: float) -> UniformSpeed | None:
        """The time change of (1.59) from ``r0``, or None when it is not exact (time-varying
        u or V, or ``A`` not skew)."""
        controls = model.controls
        if controls.V is None or not controls.constant():
            return None
        r0 = np.atleast_2d(np.asarray(r0, dtype=float))
        A, c = model.linear_coeffs(np.zeros(1), len(r0))
        A, c = A[0], c[0]
        if np.abs(A + A.transpose(0, 2, 1)).max() > SKEW_TOL * np.abs(A).max():
            return None
        n0 = np.einsum("nij,nj->ni", A, r0) + c
        norm0 = np.sqrt((n0 * n0).sum(-1))
        V = float(controls.speed(np.zeros(1))[0])
        umax = float(np.abs(controls.at(np.zeros(1))).max())
        moving = ~model.holds(norm0, model.hold_size(r0), np.asarray(umax))
        safe = np.where(moving, norm0, 1.0)
        omega = np.where(moving, controls.sign * V / safe, 0.0)
        rate = float(np.max(np.abs(omega) * np.sqrt((A * A).sum(axis=(-1, -2)))))
        return cls(model, omega, rate, max_turn)

    @property
    def coeffs(self) -> LinearCoeffs:
        """``omega A`` and ``omega c`` at times ``t (m,)`` (the same at every time)."""
        A, c = self._A, self._c
        return lambda ts: (
            np.broadcast_to(A, (len(ts), *A.shape)),
            np.broadcast_to(c, (len(ts), *c.shape)),
        )

    def substeps(self, length: float) -> int:
        """Substeps of a step of ``length`` s: those of
        :meth:`~analyzer_lab.lessons.analyzers.field.speed_stepper.SpeedStepper.step_substeps`,
        ``ceil(rate length / max_turn)`` (at least one, at most 10 000)."""
        m = int(np.ceil(self.rate * length / self.max_turn - 1e-12))
        return min(max(m, 1), 10_000)

    def step_map(self, length: float, stages: int) -> Map:
        """The map ``r -> r + D r + phi`` (``D (1, N, 3, 3)``, ``phi (1, N, 3)``) of one step
        of ``length`` s: :meth:`substeps` equal Gauss-Legendre steps composed."""
        m = self.substeps(length)
        D, phi = gl_propagators(self.coeffs, 0.0, length / m, 1, stages)
        return compose_power(D, phi, m)

    def short_map(self, length: float, h: float, stages: int) -> Map:
        """The map of a shortened step of ``length`` s inside a step of ``h``: the exact flow
        over ``d = length - Lc``, then :meth:`step_map` of ``Lc``, the nearest multiple of
        ``h / COARSE_GRAIN`` (kept per ``Lc``).  Where a cell of that grid turns the point
        by more than :data:`TAYLOR_TURN`, :meth:`step_map` of ``length`` itself."""
        cell = h / COARSE_GRAIN
        if self.rate * cell > TAYLOR_TURN:
            return self.step_map(length, stages)
        k = round(length / cell)
        base = self._coarse.get((h, k))
        if base is None:
            if len(self._coarse) >= COARSE_MAPS:
                self._coarse.clear()
            base = self._coarse[(h, k)] = self.step_map(k * cell, stages)
        d = length - k * cell
        if d == 0.0:
            return base
        # exp(d M) for the affine field: r -> r + d (A r + c) + d^2/2 A (A r + c)
        A, c = self._A, self._c
        D = d * A + (0.5 * d * d) * (A @ A)
        phi = d * c + (0.5 * d * d) * (A @ c[..., None])[..., 0]
        return compose((D[None], phi[None]), base)


def compose(first: Map, second: Map) -> Map:
    """The increment map of ``first`` then ``second`` (each ``r -> r + D r + phi``)."""
    (D1, p1), (D2, p2) = first, second
    return D1 + D2 + D2 @ D1, p1 + p2 + (D2 @ p1[..., None])[..., 0]


def compose_power(D: np.ndarray, phi: np.ndarray, m: int) -> Map:
    """The increment map ``r -> r + D r + phi`` applied ``m`` times, in increment form
    (``D`` stays a small matrix, not ``I + D`` less ``I``), by repeated squaring."""
    if m < 1:
        raise ValueError(f"need m >= 1 applications, not {m}")
    result: Map | None = None
    power = (D, phi)
    while True:
        if m & 1:
            result = power if result is None else compose(result, power)
        m >>= 1
        if not m:
            break
        power = compose(power, power)
    return result  # type: ignore[return-value]
