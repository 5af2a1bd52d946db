"""Gauss-Legendre steps of the constant-speed analyzer (1.59), vectorized over points.

The field of (1.59) is ``omega (A(t) r + c(t))`` with ``omega = sigma V / |A r + c|`` (1.58):
nonlinear in ``r``, so each step's stages are solved by Newton's method to round-off (F is
then kept to round-off, as by the affine steps of (1.50)); the step is cut into substeps
where the point turns fast.  :class:`analyzer_lab.lessons.analyzers.field.run.Trajectory` takes its nodes
and shortened steps with a :class:`SpeedStepper`.
"""

from __future__ import annotations

from collections.abc import Generator

import numpy as np
from analyzer_lab.lessons.analyzers.field.analyzer import HOLD_TOL, AnalyzerModel
from analyzer_lab.lessons.kit.budget import charge
from analyzer_lab.lessons.kit.integrators import gauss_legendre

#: Largest turning rate times substep (rad) of the constant-speed analyzer per number of
#: Gauss-Legendre stages (:meth:`SpeedStepper.step_substeps`).  A higher order takes a larger
#: turn to the same error: these keep the benchmark's V = 1 run (benchmarks/integrators.py,
#: h = 0.05 for 4 stages, 0.1 for 5 and 6) to about 1e-13 along the curve, as 0.03 does for 3
#: stages at h = 0.0125.
MAX_TURNS = {1: 0.03, 2: 0.03, 3: 0.03, 4: 0.1, 5: 0.15, 6: 0.25}
#: How far a stage may exceed that limit before the step is taken again in more substeps.
#: Steps of order 6 or less are short (h ~ 0.01 s): the rate at the start holds over the
#: step, and twice the limit catches what it did not see.  Steps of order 8 to 12 are long
#: (h ~ 0.1 s), the start says little about the end: the limit holds at every stage.
RECHECKS = {1: 2.0, 2: 2.0, 3: 2.0, 4: 1.0, 5: 1.0, 6: 1.0}
#: Most substeps of one step of the constant-speed analyzer (:meth:`SpeedStepper.step_substeps`).
MAX_SUBSTEPS = 10_000
#: Work counted per stage and point of one Newton iteration (see
#: :func:`analyzer_lab.lessons.kit.budget.charge`: about a microsecond a unit).
WORK_PER_STAGE = 20


class SpeedStepper:
    """Gauss-Legendre steps of the constant-speed analyzer (1.59), vectorized over points.

    The field is ``omega (A(t) r + c(t))`` with ``A, c`` from the lambdified (1.50) and
    ``omega = sigma V / |A r + c|`` (1.58); the stages are solved by simplified Newton to
    round-off (warm-started from the previous step), so F is kept to round-off.  A stage
    where ``|A r + c|`` vanishes (:meth:`AnalyzerModel.holds`) has slope zero: the point
    holds only while the field is zero (the Gauss nodes lie inside the step, so a field
    that vanishes only at the step's start, as Example 1.3's at t = 0, does not stop it).
    """

    def __init__(
        self,
        model: AnalyzerModel,
        stages: int = 3,
        max_iter: int = 30,
        *,
        max_turn: float | None = None,
        recheck: float | None = None,
    ) -> None:
        self.model = model
        self.a, self.b, self.c = gauss_legendre(stages)
        #: largest turning rate times substep (rad), :data:`MAX_TURNS` by default
        self.max_turn = MAX_TURNS[stages] if max_turn is None else float(max_turn)
        #: a stage may reach ``recheck * max_turn`` (:data:`RECHECKS` by default)
        self.recheck = RECHECKS[stages] if recheck is None else float(recheck)
        self.s = stages
        self._eye3s = np.eye(3 * stages)
        self.max_iter = max_iter
        self.evaluations = 0
        #: whether the last step's stages were solved to round-off (see :meth:`step`)
        self.converged = True
        self.K: np.ndarray | None = None
        #: per point, the largest turning rate at a stage of the last step
        self.rates = np.zeros(0)
        #: stage slopes and length of the last substep of :meth:`step_substeps`
        self.last: tuple[np.ndarray, float] | None = None

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

    def extrapolation(self, ratio: float, offset: float = 1.0) -> np.ndarray:
        """``E (s, s)``: the stage slopes of a step of ``ratio`` times the length of the
        step before it, predicted from that step's slopes ``K`` as ``E @ K`` (its
        collocation polynomial's derivative, of degree s - 1, at the new stage times).
        ``offset = 0``: the new step starts where that step starts (a shorter step inside
        it: interpolation)."""
        cache = self.__dict__.setdefault("_extrapolations", {})
        E = cache.get((ratio, offset))
        if E is None:
            if len(cache) >= 64:
                cache.clear()
            x = offset + self.c * ratio
            E = np.ones((self.s, self.s))
            for j in range(self.s):
                for k in range(self.s):
                    if k != j:
                        E[:, j] *= (x - self.c[k]) / (self.c[j] - self.c[k])
            cache[(ratio, offset)] = E
        return E

    def step(
        self,
        R: np.ndarray,
        h: float,
        coeffs: tuple[np.ndarray, ...],
        before: tuple[np.ndarray, float] | None = None,
        covering: tuple[np.ndarray, float] | None = None,
        *,
        size: np.ndarray | None = None,
    ) -> np.ndarray:
        """One step of size ``h`` from ``R (N, 3)`` with the stage coefficients ``coeffs``.

        ``before``: the stage slopes and length of the step that ended at ``R``; the
        stages then start from its extrapolated collocation polynomial; ``covering``: those
        of a longer step from ``R`` (its polynomial inside); otherwise from the last step's
        slopes.  Either way they are solved to round-off by simplified Newton, its matrix
        built from each stage's own Jacobian ``omega (I - nn^T) A`` at the predicted stage
        values.  The iteration stops when the correction, or the sum of the corrections its
        rate of convergence leaves to come, is below 2e-16 of the slopes (:attr:`converged`;
        false if ``max_iter`` iterations did not get there).  ``size``:
        :meth:`AnalyzerModel.hold_size` near ``R`` (at ``R`` by default)."""
        s = self.s
        N = len(R)
        A, cc, Vs, umax = coeffs
        At = A.transpose(1, 0, 2, 3)  # (N, s, 3, 3)
        ct = cc.transpose(1, 0, 2)
        if covering is not None and covering[0].shape == (N, s, 3):
            K = np.einsum("ij,njd->nid", self.extrapolation(h / covering[1], 0.0), covering[0])
        elif before is not None and before[0].shape == (N, s, 3):
            K = np.einsum("ij,njd->nid", self.extrapolation(h / before[1]), before[0])
        elif self.K is not None and self.K.shape == (N, s, 3):
            K = self.K.copy()
        else:  # the field at R, at the middle stage's time
            mid = s // 2
            n0 = np.einsum("nij,nj->ni", A[mid], R) + cc[mid]
            norm0 = np.sqrt((n0 * n0).sum(-1))
            w0 = np.where(norm0 > 0, Vs[mid] / np.where(norm0 > 0, norm0, 1.0), 0.0)
            K = np.repeat((n0 * w0[:, None])[:, None, :], s, axis=1)
        ha = h * self.a
        if size is None:
            size = self.model.hold_size(R)
        # AnalyzerModel.holds, its bound computed once for the step (the field's size
        # barely changes in a step)
        bound = HOLD_TOL * (umax[None, :] + 1e-300) * (size[:, None] + 1e-300)
        previous, Minv = np.inf, None
        self.converged = False
        for _ in range(self.max_iter):
            Y = R[:, None, :] + ha @ K  # (N, s, 3)
            n = (At @ Y[..., None])[..., 0] + ct
            norm = np.sqrt((n * n).sum(-1))
            w = np.where(norm <= bound, 0.0, Vs[None, :] / np.where(norm > 0, norm, 1.0))
            f = n * w[..., None]
            self.evaluations += s
            charge(WORK_PER_STAGE * s * N)
            if Minv is None:
                Minv = self._newton_inverse(At, n, norm, w, h)
            dK = -(Minv @ (K - f).reshape(N, 3 * s, 1)).reshape(N, s, 3)
            K += dK
            step, tol = float(np.abs(dK).max()), 2e-16 * (float(np.abs(K).max()) + 1e-300)
            rate = step / previous  # after the first correction: its rate of convergence
            if step <= tol or (0.0 < rate < 0.5 and rate / (1.0 - rate) * step <= tol):
                self.converged = True
                break
            previous = step
        self.K = K
        # the turning rate |V| |A| / |A r + c| at the stages that move (see step_substeps)
        self.rates = (
            np.abs(Vs)[None, :]
            * np.sqrt((At * At).sum(axis=(-1, -2)))
            * np.where(w != 0.0, 1.0 / np.where(norm > 0, norm, 1.0), 0.0)
        ).max(axis=-1)
        return R + h * np.einsum("i,nid->nd", self.b, K)

    def _newton_inverse(
        self, At: np.ndarray, n: np.ndarray, norm: np.ndarray, w: np.ndarray, h: float
    ) -> np.ndarray:
        """``(I - h (a x I) diag(J_j))^-1 (N, 3s, 3s)`` with the stage Jacobians
        ``J_j = w_j (I - n_j n_j^T / |n_j|^2) A_j`` of (1.59) at the stage fields ``n``."""
        s, N = self.s, len(n)
        nh = n / np.where(norm > 0, norm, 1.0)[..., None]
        J = w[..., None, None] * (At - nh[..., :, None] * (nh[..., None, :] @ At))
        M = self._eye3s - (
            h * self.a[None, :, None, :, None] * J.transpose(0, 2, 1, 3)[:, None]
        ).reshape(N, 3 * s, 3 * s)
        return np.linalg.inv(M)

    def step_substeps(
        self,
        t: float,
        R: np.ndarray,
        h: float,
        coeffs: tuple[np.ndarray, ...] | None = None,
        before: tuple[np.ndarray, float] | None = None,
        covering: tuple[np.ndarray, float] | None = None,
    ) -> np.ndarray:
        """One output step of size ``h`` from ``(t, R)``, split into equal substeps where the
        curve turns fast.

        The turning rate of (1.59) is ``omega |A| = V |A| / |A r + c|``: near points where the
        analyzer's field is small the point turns quickly (its reciprocal is about the time
        to the nearest zero of the field, which sets the error of a high order step); the
        step is cut so that ``rate * substep <= max_turn`` at its start, and where then at a
        stage of a substep it exceeds ``recheck * max_turn``, the step is taken again in as
        many substeps as that stage's rate asks for (each substep is still a Gauss-Legendre
        step).  So it is, in twice the substeps, where a substep's stages were not solved to
        round-off (:attr:`converged`), which keeps F to round-off.  A point whose field is
        zero at ``(t, R)`` (:meth:`zero_field`; Example 1.3's start) moves off along the
        field's derivative, turning slowly (the rate's bound, about ``1 / (time since t)``,
        does not show it): its stages do not count in this step.
        ``coeffs``: the step's stage coefficients, if already computed (:meth:`coefficients`);
        ``before``/``covering``: the slopes and length of the (sub)step that ended at ``R``
        or of a longer one from ``R`` (see :meth:`step`).  Afterwards :attr:`last` holds
        those of this step's last substep.
        """
        work = self.substepping(t, R, h, coeffs, before, covering)
        while True:
            try:
                next(work)
            except StopIteration as done:
                return done.value

    def substepping(
        self,
        t: float,
        R: np.ndarray,
        h: float,
        coeffs: tuple[np.ndarray, ...] | None = None,
        before: tuple[np.ndarray, float] | None = None,
        covering: tuple[np.ndarray, float] | None = None,
    ) -> Generator[None, None, np.ndarray]:
        """:meth:`step_substeps` as work that pauses after every substep (a live run's
        budget is checked there, and the step goes on where it paused); returns the end."""
        if coeffs is None:
            coeffs = tuple(x[0] for x in self.coefficients(t, h, 1, len(R)))
        m = self.cuts(coeffs, R, h)
        counted: np.ndarray | None = None  # the points not starting at a zero of the field
        while True:
            out, peaks, solved, last = yield from self._substeps(
                t, R, h, m, coeffs, before, covering
            )
            turned = peaks * h / m > self.max_turn * self.recheck
            if turned.any() and counted is None:
                counted = ~self.zero_field(t, R)
            if counted is not None:
                peaks = np.where(counted, peaks, 0.0)
                turned &= counted
            if (solved and not turned.any()) or m == MAX_SUBSTEPS:
                break
            need = int(np.ceil(float(peaks.max()) * h / self.max_turn))
            m = min(MAX_SUBSTEPS, max(m + 1 if solved else 2 * m, need))
        self.last = last
        return out

    def cuts(self, coeffs: tuple[np.ndarray, ...], R: np.ndarray, h: float) -> int:
        """The substeps a step of length ``h`` from ``R`` starts with: ``rate * substep <=
        max_turn`` for the turning rate ``V |A| / |A r + c|`` at the first stage (at least
        one, at most :data:`MAX_SUBSTEPS`; :meth:`step_substeps` may take more)."""
        A, cc, Vs, _ = coeffs
        n0 = np.einsum("nij,nj->ni", A[0], R) + cc[0]
        norm0 = np.sqrt((n0 * n0).sum(-1))
        rate = (
            np.abs(Vs).max() * np.sqrt((A[0] ** 2).sum(axis=(-1, -2))) / np.maximum(norm0, 1e-300)
        )
        m = int(np.ceil(float(np.max(np.where(norm0 > 0, rate, 0.0))) * h / self.max_turn - 1e-12))
        return min(max(m, 1), MAX_SUBSTEPS)

    def zero_field(self, t: float, R: np.ndarray) -> np.ndarray:
        """``(N,)``: where the analyzer's field is zero at ``(t, R)``
        (:meth:`AnalyzerModel.holds`)."""
        A, c = self.model.linear_coeffs(np.array([float(t)]), len(R))
        n = np.einsum("nij,nj->ni", A[0], R) + c[0]
        umax = float(np.abs(self.model.controls.at(np.array([float(t)]))).max())
        return self.model.holds(np.sqrt((n * n).sum(-1)), self.model.hold_size(R), umax)

    def _substeps(
        self,
        t: float,
        R: np.ndarray,
        h: float,
        m: int,
        coeffs: tuple[np.ndarray, ...],
        before: tuple[np.ndarray, float] | None,
        covering: tuple[np.ndarray, float] | None,
    ) -> Generator[None, None, tuple[np.ndarray, np.ndarray, bool, tuple[np.ndarray, float]]]:
        """``m`` equal substeps over ``[t, t + h]``: the end, per point the largest turning
        rate at a stage (:attr:`rates`), whether every substep :attr:`converged`, and the
        slopes and length of the last substep; pauses (yields) after each substep, once what
        the substep left in the stepper's attributes has been read."""
        size = self.model.hold_size(R)  # for every substep: see step
        if m == 1:
            out = self.step(R, h, coeffs, before, covering, size=size)
            return out, self.rates, self.converged, (self.K, h)
        hs = h / m
        batch = self.coefficients(t, hs, m, len(R))
        comp = np.zeros_like(R)
        peaks, solved = np.zeros(len(R)), True
        for j in range(m):
            out = self.step(R, hs, tuple(x[j] for x in batch), before, covering, size=size)
            inc = (out - R) - comp
            before, covering = (self.K, hs), None
            peaks = np.maximum(peaks, self.rates)
            solved = solved and self.converged
            nxt = R + inc
            comp = (nxt - R) - inc
            R = nxt
            yield
        return R, peaks, solved, before
