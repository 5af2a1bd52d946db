"""The analyzer's trajectory r(t): one fixed step sequence from the start, shared by runs
and live steppers.

A :class:`Trajectory` integrates one analyzer (1.50) or its constant-speed form (1.59)
from ``(t0, r0)``.  Gauss-Legendre runs take fixed steps on the grid ``t0 + k h`` (the
nodes are computed in blocks of steps; for (1.50) each block's step maps in one batched
solve, for (1.59) by :class:`SpeedStepper`, or, with constant controls on a skew field, as
the time change of (1.50) of :class:`lessons.core.speed_flow.UniformSpeed` by kept step
maps); scipy's solvers run in pieces of :data:`PIECE` seconds and are read through their
dense output.  Between two nodes the state is one shortened step from the earlier node (for
(1.59), from the latest substep end where that step would be cut into many substeps, see
:meth:`Trajectory._from_substep_ends`).  So every time has one value however
the run is sampled: ``simulate`` on its grid and the live stepper frame by frame read the
same trajectory.  :func:`integrate` samples one for the claims and the benchmark.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.integrate

from lessons.core.analyzer import HOLD_TOL, AnalyzerModel
from lessons.core.budget import spent
from lessons.core.integrators import apply_propagators, gauss_legendre, gl_propagators
from lessons.core.speed_flow import UniformSpeed

#: Gauss-Legendre steps per block of nodes: (1.50) (one batched solve), (1.59) (Newton).
BLOCK = 256
SPEED_BLOCK = 32
#: Length (s) of one piece of a scipy ``solve_ivp`` run.
PIECE = 10.0
#: Shortened steps of a time-independent field: their lengths are rounded to h / SHORT_GRAIN
#: and at most SHORT_MAPS step maps are kept (see :meth:`Trajectory._short_map`).
SHORT_GRAIN = 2**40
SHORT_MAPS = 256
#: (1.59): a shortened step cut into more substeps than this reads the kept substep ends
#: of its whole step (see :meth:`Trajectory._from_substep_ends`).
KEEP_SUBSTEPS = 16


class SpeedStepper:
    """Gauss-Legendre steps of the constant-speed analyzer (1.59), vectorized over points.

    The field is ``omega (A(t) r + c(t))`` with ``A, c`` from the lambdified (1.50) and
    ``omega = sigma V / |A r + c|`` (1.58); the stages are solved by simplified Newton to
    round-off (warm-started from the previous step), so F is kept to round-off.  A stage
    where ``|A r + c|`` vanishes (:meth:`AnalyzerModel.holds`) has slope zero: the point
    holds only while the field is zero (the Gauss nodes lie inside the step, so a field
    that vanishes only at the step's start, as Example 1.3's at t = 0, does not stop it).
    """

    #: Largest turn of the velocity per substep (rad), see :meth:`step_substeps`.
    max_turn = 0.03

    def __init__(self, model: AnalyzerModel, stages: int = 3, max_iter: int = 30) -> None:
        self.model = model
        self.a, self.b, self.c = gauss_legendre(stages)
        self.s = stages
        self._eye3, self._eye3s = np.eye(3), np.eye(3 * stages)
        self.max_iter = max_iter
        self.evaluations = 0
        self.K: np.ndarray | None = None
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
    ) -> np.ndarray:
        """One step of size ``h`` from ``R (N, 3)`` with the stage coefficients ``coeffs``.

        ``before``: the stage slopes and length of the step that ended at ``R``; the
        stages then start from its extrapolated collocation polynomial; ``covering``: those
        of a longer step from ``R`` (its polynomial inside); otherwise from the last step's
        slopes.  Either way they are solved to round-off: the iteration stops when the
        correction, or the sum of the corrections its rate of convergence leaves to come,
        is below 2e-16 of the slopes."""
        s, a = self.s, self.a
        N = len(R)
        A, cc, Vs, umax = coeffs
        mid = s // 2
        # simplified Newton matrix from the middle stage at R: J = omega (I - nn^T) A
        nm = np.einsum("nij,nj->ni", A[mid], R) + cc[mid]
        norm_m = np.sqrt((nm * nm).sum(-1))
        moving = norm_m > 0
        safe = np.where(moving, norm_m, 1.0)
        nh = nm / safe[:, None]
        P = self._eye3 - nh[:, :, None] * nh[:, None, :]
        J = (np.where(moving, Vs[mid], 0.0) / safe)[:, None, None] * (P @ A[mid])
        M = self._eye3s - h * (a[None, :, None, :, None] * J[:, None, :, None, :]).reshape(
            N, 3 * s, 3 * s
        )
        Minv = np.linalg.inv(M)
        if covering is not None and covering[0].shape == (N, s, 3):
            K = np.einsum("ij,njd->nid", self.extrapolation(h / covering[1], 0.0), covering[0])
        elif before is not None and before[0].shape == (N, s, 3):
            K = np.einsum("ij,njd->nid", self.extrapolation(h / before[1]), before[0])
        elif self.K is not None and self.K.shape == (N, s, 3):
            K = self.K.copy()
        else:
            K = np.repeat((nm * (Vs[mid] / safe)[:, None])[:, None, :], s, axis=1)
        At = A.transpose(1, 0, 2, 3)  # (N, s, 3, 3)
        ct = cc.transpose(1, 0, 2)
        ha = h * a
        size = self.model.hold_size(R)[:, None]  # the field's size barely changes in a step
        # AnalyzerModel.holds, its bound computed once for the step
        bound = HOLD_TOL * (umax[None, :] + 1e-300) * (size + 1e-300)
        previous = np.inf
        for _ in range(self.max_iter):
            Y = R[:, None, :] + ha @ K  # (N, s, 3)
            n = (At @ Y[..., None])[..., 0] + ct
            norm = np.sqrt((n * n).sum(-1))
            f = (
                n
                * np.where(norm <= bound, 0.0, Vs[None, :] / np.where(norm > 0, norm, 1.0))[
                    ..., None
                ]
            )
            self.evaluations += s
            dK = -(Minv @ (K - f).reshape(N, 3 * s, 1)).reshape(N, s, 3)
            K += dK
            step, tol = float(np.abs(dK).max()), 2e-16 * (float(np.abs(K).max()) + 1e-300)
            rate = step / previous  # after the first correction: its rate of convergence
            if step <= tol or (0.0 < rate < 0.5 and rate / (1.0 - rate) * step <= tol):
                break
            previous = step
        self.K = K
        return R + h * np.einsum("i,nid->nd", self.b, K)

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
        analyzer's field is small the point turns quickly; the step is cut so that
        ``rate * substep <= max_turn`` (each substep is still a Gauss-Legendre step).
        ``coeffs``: the step's stage coefficients, if already computed (:meth:`coefficients`);
        ``before``/``covering``: the slopes and length of the (sub)step that ended at ``R``
        or of a longer one from ``R`` (see :meth:`step`).  Afterwards :attr:`last` holds
        those of this step's last substep.
        """
        if coeffs is None:
            coeffs = tuple(x[0] for x in self.coefficients(t, h, 1, len(R)))
        A, cc, Vs, _ = coeffs
        n0 = np.einsum("nij,nj->ni", A[0], R) + cc[0]
        norm0 = np.sqrt((n0 * n0).sum(-1))
        rate = (
            np.abs(Vs).max() * np.sqrt((A[0] ** 2).sum(axis=(-1, -2))) / np.maximum(norm0, 1e-300)
        )
        m = int(np.ceil(float(np.max(np.where(norm0 > 0, rate, 0.0))) * h / self.max_turn - 1e-12))
        if m <= 1:
            out = self.step(R, h, coeffs, before, covering)
            self.last = (self.K, h)
            return out
        m = min(m, 10_000)
        hs = h / m
        batch = self.coefficients(t, hs, m, len(R))
        comp = np.zeros_like(R)
        for j in range(m):
            inc = (self.step(R, hs, tuple(x[j] for x in batch), before, covering) - R) - comp
            before, covering = (self.K, hs), None
            nxt = R + inc
            comp = (nxt - R) - inc
            R = nxt
        self.last = before
        return R


class Trajectory:
    """r(t) of one analyzer from ``(t0, r0 (N, 3))``, read forward in time by :meth:`at`.

    ``method``: ``gauss-legendre-2``/``-3`` (fixed step ``h``, F kept to round-off) or a
    ``solve_ivp`` method (``RK45``, ``DOP853``, ...) with ``rtol``/``atol``.
    """

    def __init__(
        self,
        model: AnalyzerModel,
        r0: np.ndarray,
        t0: float = 0.0,
        method: str = "gauss-legendre-3",
        h: float = 1e-2,
        rtol: float = 1e-3,
        atol: float = 1e-6,
    ) -> None:
        self.model = model
        self.t0 = float(t0)
        self.r0 = np.atleast_2d(np.asarray(r0, dtype=float)).copy()
        self.method = method
        self.h = float(h)
        self.rtol, self.atol = rtol, atol
        self.nfev = 0
        N = len(self.r0)
        self._coeffs = lambda ts: model.linear_coeffs(ts, N)
        self._speed: SpeedStepper | None = None
        self._uniform: UniformSpeed | None = None
        self._map: tuple[np.ndarray, np.ndarray] | None = None
        self._short_maps: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        if method.startswith("gauss-legendre"):
            self.stages = int(method.rsplit("-", 1)[1])
            if model.controls.V is not None:
                # constant u, V and a skew A: (1.59) is (1.50) at a constant rate per point
                self._uniform = UniformSpeed.of(model, self.r0, SpeedStepper.max_turn)
                if self._uniform is None:
                    self._speed = SpeedStepper(model, self.stages)
                else:
                    self._coeffs = self._uniform.coeffs
                    self._map = self._uniform.step_map(self.h, self.stages)
            elif model.controls.constant():
                # time-independent field: every full step has the same map
                self._map = gl_propagators(self._coeffs, self.t0, self.h, 1, self.stages)
        # nodes k0 .. k0 + len(nodes) - 1 of the current block (GL), or the current piece
        self._k0 = 0
        self._nodes = self.r0[None].copy()
        self._comp = np.zeros_like(self.r0)
        self._piece = -1
        self._solver: Any = None  # scipy OdeSolver of the current piece
        self._nfev0 = 0  # evaluations of the pieces before the current one
        self._ends: list[float] = []  # end times of the current piece's steps
        self._steps: list[Any] = []  # their dense outputs
        #: (1.59): per node of the block, the slopes and length of the substep ending there
        self._incoming: list[tuple[np.ndarray, float] | None] = [None]
        #: (1.59): node time, substep length, states and incoming slopes of one whole step
        self._substep_ends: tuple[float, float, list[np.ndarray], list[Any]] | None = None

    @property
    def gauss_legendre(self) -> bool:
        return self.method.startswith("gauss-legendre")

    def at(self, times: np.ndarray) -> np.ndarray:
        """The states ``(m, N, 3)`` at the non-decreasing ``times`` (none before the last
        block read)."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        out = np.empty((len(times), *self.r0.shape))
        for i, t in enumerate(times):
            out[i] = self._state(float(t)) if self.gauss_legendre else self._dense(float(t))
        return out

    def reach(self, t: float) -> float:
        """Compute ahead towards time ``t`` and return the time up to which :meth:`at` can
        read without computing more: ``t``, or less once the work budget
        (:mod:`lessons.core.budget`) is spent (at least one block or solver step is taken
        per call, so a live run always moves on)."""
        t = float(t)
        if self.gauss_legendre:
            k = max(0, int(np.floor((t - self.t0) / self.h + 1e-9)))
            if k < self._k0:
                raise ValueError(f"trajectory read backwards (step {k} < {self._k0})")
            taken = False
            while k >= self._k0 + len(self._nodes):
                if taken and spent():
                    return self.t0 + (self._k0 + len(self._nodes) - 1) * self.h
                self._next_block()
                taken = True
            return t
        return self._cover(t)

    # -- Gauss-Legendre ------------------------------------------------------------------

    def _state(self, t: float) -> np.ndarray:
        k = max(0, int(np.floor((t - self.t0) / self.h + 1e-9)))
        node = self._node(k)
        tk = self.t0 + k * self.h
        rest = t - tk
        if rest <= 1e-12 * max(1.0, abs(t)):
            return node
        return self._short_step(tk, node, rest)

    def _node(self, k: int) -> np.ndarray:
        if k < self._k0:
            raise ValueError(f"trajectory read backwards (step {k} < {self._k0})")
        while k >= self._k0 + len(self._nodes):
            self._next_block()
        return self._nodes[k - self._k0]

    def _next_block(self) -> None:
        k0 = self._k0 + len(self._nodes) - 1
        t = self.t0 + k0 * self.h
        r = self._nodes[-1]
        if self._speed is not None:
            nodes = np.empty((SPEED_BLOCK + 1, *r.shape))
            nodes[0] = r
            batch = self._speed.coefficients(t, self.h, SPEED_BLOCK, len(r))
            incoming = [self._incoming[-1]]
            for j in range(SPEED_BLOCK):
                coeffs = tuple(x[j] for x in batch)
                step = self._speed.step_substeps(t + j * self.h, r, self.h, coeffs, incoming[-1])
                incoming.append(self._speed.last)
                inc = (step - r) - self._comp
                nxt = r + inc
                self._comp = (nxt - r) - inc
                r = nodes[j + 1] = nxt
            self._incoming = incoming
            self.nfev = self._speed.evaluations
        else:
            if self._map is not None:
                D, phi = (np.broadcast_to(m, (BLOCK, *m.shape[1:])) for m in self._map)
            else:
                D, phi = gl_propagators(self._coeffs, t, self.h, BLOCK, self.stages)
            nodes, self._comp = apply_propagators(D, phi, r, self._comp)
        self._k0, self._nodes = k0, nodes

    def _short_step(self, tk: float, r: np.ndarray, rest: float) -> np.ndarray:
        """One Gauss-Legendre step of length ``rest < h`` from the node ``(tk, r)``; for
        (1.59), one cut into more than :data:`KEEP_SUBSTEPS` substeps reads the substep
        ends of the whole step instead (:meth:`_from_substep_ends`)."""
        if self._speed is not None:
            warm = self._speed.K, self._speed.last
            # from the slopes of the step that ended at the node: a few iterations
            j = int(round((tk - self.t0) / self.h)) - self._k0
            before = self._incoming[j]
            coeffs = tuple(x[0] for x in self._speed.coefficients(tk, rest, 1, len(r)))
            if self._cuts(coeffs, r, rest) > KEEP_SUBSTEPS:
                out = self._from_substep_ends(tk, r, rest, before)
            else:
                # the step from the node, if taken whole (its block is computed ahead)
                nxt = self._incoming[j + 1] if j + 1 < len(self._incoming) else None
                covering = nxt if nxt is not None and nxt[1] == self.h else None
                out = self._speed.step_substeps(tk, r, rest, coeffs, before, covering)
            self._speed.K, self._speed.last = warm  # as if this step was not taken
            return out
        if self._map is not None:
            D, phi = self._short_map(rest)
        else:
            D, phi = gl_propagators(self._coeffs, tk, rest, 1, self.stages)
        return r + (D[0] @ r[:, :, None])[:, :, 0] + phi[0]

    def _cuts(self, coeffs: tuple[np.ndarray, ...], r: np.ndarray, length: float) -> int:
        """The substeps :meth:`SpeedStepper.step_substeps` cuts a step of ``length`` from
        ``r`` into (its turning-rate bound ``V |A| / |A r + c|`` at the first stage)."""
        assert self._speed is not None
        A, cc, Vs, _ = coeffs
        n0 = np.einsum("nij,nj->ni", A[0], r) + cc[0]
        norm0 = np.sqrt((n0 * n0).sum(-1))
        rate = (
            np.abs(Vs).max() * np.sqrt((A[0] ** 2).sum(axis=(-1, -2))) / np.maximum(norm0, 1e-300)
        )
        turn = float(np.max(np.where(norm0 > 0, rate, 0.0))) * length / self._speed.max_turn
        return min(max(int(np.ceil(turn - 1e-12)), 1), 10_000)

    def _from_substep_ends(
        self, tk: float, r: np.ndarray, rest: float, before: tuple[np.ndarray, float] | None
    ) -> np.ndarray:
        """(1.59) at ``tk + rest``, read from the ends of the ``m`` equal substeps of the whole
        step from the node ``(tk, r)`` (kept for one node): one shortened substep from the
        latest end.  Where the field is small at a node (Example 1.3's start) a shortened
        step is cut into about as many substeps as the whole one, however short it is; a
        frame then costs one substep, not all of them."""
        assert self._speed is not None
        kept = self._substep_ends
        if kept is None or kept[0] != tk:
            coeffs = tuple(x[0] for x in self._speed.coefficients(tk, self.h, 1, len(r)))
            m = self._cuts(coeffs, r, self.h)
            hs = self.h / m
            batch = self._speed.coefficients(tk, hs, m, len(r))
            ends, slopes = [r], [before]
            comp = np.zeros_like(r)
            for i in range(m):
                step = self._speed.step(r, hs, tuple(x[i] for x in batch), slopes[-1])
                slopes.append((self._speed.K, hs))
                inc = (step - r) - comp
                nxt = r + inc
                comp = (nxt - r) - inc
                r = nxt
                ends.append(r)
            kept = self._substep_ends = (tk, hs, ends, slopes)
        _, hs, ends, slopes = kept
        i = min(int(np.floor(rest / hs)), len(ends) - 2)
        d = rest - i * hs
        if d <= 1e-12 * max(1.0, abs(tk)):
            return ends[i]
        covering = slopes[i + 1]
        return self._speed.step_substeps(tk + i * hs, ends[i], d, None, slopes[i], covering)

    def _short_map(self, rest: float) -> tuple[np.ndarray, np.ndarray]:
        """The step map of a shortened step of a time-independent field (1.50), or of (1.59)
        as its time change (:class:`UniformSpeed`), kept per length: played frames fall on
        a few offsets from the nodes (the session's time quanta), so a frame reads a kept
        map.  ``rest`` is rounded to ``h / 2**40`` first,
        so that a time has one value however often it is read."""
        key = round(rest / self.h * SHORT_GRAIN)
        hit = self._short_maps.get(key)
        if hit is None:
            if len(self._short_maps) >= SHORT_MAPS:
                self._short_maps.clear()
            length = key * self.h / SHORT_GRAIN
            if self._uniform is not None:
                hit = self._uniform.short_map(length, self.h, self.stages)
            else:
                hit = gl_propagators(self._coeffs, self.t0, length, 1, self.stages)
            self._short_maps[key] = hit
        return hit

    # -- scipy ---------------------------------------------------------------------------

    def _dense(self, t: float) -> np.ndarray:
        self._cover(t, budget=False)
        i = min(bisect.bisect_left(self._ends, t), len(self._steps) - 1)
        if i < 0:
            return np.asarray(self._solver.y, dtype=float).reshape(self.r0.shape)
        return np.asarray(self._steps[i](t), dtype=float).reshape(self.r0.shape)

    def _cover(self, t: float, budget: bool = True) -> float:
        """Step the scipy solver (pieces of :data:`PIECE` seconds, each a fresh solver as
        ``solve_ivp`` would run it) until ``t`` is covered; with ``budget``, stop once the
        work budget is spent and return the time covered."""
        j = max(0, int(np.floor((t - self.t0) / PIECE)))
        if j < self._piece:
            raise ValueError("trajectory read backwards")
        taken = False
        while True:
            solver = self._solver
            if solver is None or (self._piece < j and solver.status == "finished"):
                start = self.t0 + (self._piece + 1) * PIECE
                r = self.r0 if solver is None else np.asarray(solver.y).reshape(self.r0.shape)
                self._nfev0 += 0 if solver is None else int(solver.nfev)
                self._new_piece(start, r)
                continue
            if self._piece == j and (solver.t >= t or solver.status == "finished"):
                return t
            if solver.status == "failed":
                raise RuntimeError(f"the {self.method} solver failed at t = {solver.t:.6g} s")
            if budget and taken and spent():
                return float(solver.t)
            solver.step()
            taken = True
            if solver.status == "failed":
                raise RuntimeError(f"the {self.method} solver failed at t = {solver.t:.6g} s")
            self._ends.append(float(solver.t))
            self._steps.append(solver.dense_output())
            self.nfev = self._nfev0 + int(solver.nfev)

    def _new_piece(self, start: float, r: np.ndarray) -> None:
        shape = self.r0.shape

        def rhs(tt: float, yy: np.ndarray) -> np.ndarray:
            return self.model.velocity(tt, yy.reshape(shape)).ravel()

        method = getattr(scipy.integrate, self.method)
        self._solver = method(rhs, start, r.ravel(), start + PIECE, rtol=self.rtol, atol=self.atol)
        self._piece += 1
        self._ends, self._steps = [], []


@dataclass
class AnalyzerRun:
    """A sampled analyzer run: ``t``, positions ``r (m, N, 3)``, velocities, invariant."""

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
    samples: int | None = None,
    rtol: float = 1e-3,
    atol: float = 1e-6,
) -> AnalyzerRun:
    """Run the analyzer from ``r0 (N, 3)`` over ``[0, t_end]`` (see :class:`Trajectory`).

    Sampled at ``samples`` evenly spaced times, or by default at every Gauss-Legendre node
    (every ``h`` for scipy's solvers) and at ``t_end``.
    """
    traj = Trajectory(model, r0, 0.0, method, h, rtol, atol)
    if samples is not None:
        t = np.linspace(0.0, t_end, max(int(samples), 2))
    else:
        t = np.arange(int(np.floor(t_end / h + 1e-9)) + 1) * h
        if t_end - t[-1] > 1e-9 * max(1.0, t_end):
            t = np.append(t, t_end)
    r = traj.at(t)
    v = model.velocities(t, r)
    held = np.zeros(r.shape[:2], dtype=bool)
    if model.controls.V is not None:
        held = np.linalg.norm(v, axis=-1) == 0.0
    return AnalyzerRun(t, r, v, model.F(r), model.F(traj.r0), held, method, traj.nfev)
