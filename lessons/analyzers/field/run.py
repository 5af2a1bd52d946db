"""The analyzer's trajectory r(t): one fixed step sequence from the start, shared by runs
and live steppers.

A :class:`Trajectory` integrates one analyzer (1.50) or its constant-speed form (1.59)
from ``(t0, r0)``.  Gauss-Legendre runs take fixed steps on the grid ``t0 + k h`` (the
nodes are computed in blocks of steps; for (1.50) each block's step maps in one batched
solve, for (1.59) by :class:`SpeedStepper`, or, with constant controls on a skew field, as
the time change of (1.50) of :class:`analyzer_lab.lessons.analyzers.field.speed_flow.UniformSpeed` by kept step
maps); scipy's solvers run in pieces of :data:`PIECE` seconds and are read through their
dense output.  Between two nodes the state is one shortened step from the earlier node (for
(1.59), from the latest substep end where that step would be cut into many substeps, see
:meth:`Trajectory._from_substep_ends`).  So every time has one value however
the run is sampled: ``simulate`` on its grid and the live stepper frame by frame read the
same trajectory.  :func:`integrate` samples one for the claims and the benchmark.
"""

from __future__ import annotations

import bisect
from collections.abc import Generator
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.integrate
from analyzer_lab.lessons.analyzers.field.analyzer import AnalyzerModel
from analyzer_lab.lessons.analyzers.field.speed_flow import UniformSpeed
from analyzer_lab.lessons.analyzers.field.speed_stepper import MAX_TURNS, SpeedStepper
from analyzer_lab.lessons.kit.budget import charge, spent
from analyzer_lab.lessons.kit.integrators import apply_propagators, gl_propagators

__all__ = ["MAX_TURNS", "AnalyzerRun", "SpeedStepper", "Trajectory", "integrate"]

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
#: Work counted (:func:`analyzer_lab.lessons.kit.budget.charge`, about a microsecond a
#: unit) per stage and point of a Gauss-Legendre step of (1.50), and per evaluation and
#: point of a scipy solver.
WORK_PER_STAGE = 4
WORK_PER_EVALUATION = 10


class Trajectory:
    """r(t) of one analyzer from ``(t0, r0 (N, 3))``, read forward in time by :meth:`at`.

    ``method``: ``gauss-legendre-s`` with s = 1 to 6 stages (order 2s; fixed step ``h``, F
    kept to round-off; the lessons offer 2, 3 and 6) or a
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
                self._uniform = UniformSpeed.of(model, self.r0, MAX_TURNS[self.stages])
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
        #: (1.59): the next block being computed, paused where a live budget ran out
        self._building: Generator[None, None, None] | None = None
        #: (1.59): a node's substep ends being computed, paused likewise
        self._ending: tuple[float, Generator[None, None, None]] | None = None

    @property
    def computing(self) -> bool:
        """(1.59): whether a block or a node's substep ends paused at the budget."""
        return self._building is not None or self._ending is not None

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
        (:mod:`analyzer_lab.lessons.kit.budget`) is spent (at least one block or solver step is taken
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
                if self._speed is None:
                    self._next_block()
                    taken = True
                    continue
                # (1.59): one step may be cut into thousands of substeps; the block goes
                # on substep by substep, and pauses where the budget runs out
                work = self._building = self._building or self._speed_block()
                for _ in work:
                    if spent():
                        return self.t0 + (self._k0 + len(self._nodes) - 1) * self.h
                self._building = None
                taken = True
            if self._speed is not None and not self._ends_ready(k, t):
                return self.t0 + k * self.h
            return t
        return self._cover(t)

    def _ends_ready(self, k: int, t: float) -> bool:
        """(1.59): whether ``t`` can be read from the node ``k`` within the budget: on the
        node, a shortened step of few substeps, or the kept substep ends of that node's
        step (computed here substep by substep, pausing where the budget runs out)."""
        assert self._speed is not None
        tk = self.t0 + k * self.h
        if t - tk <= 1e-12 * max(1.0, abs(t)):
            return True
        kept = self._substep_ends
        if kept is not None and kept[0] == tk:
            return True
        r = self._nodes[k - self._k0]
        if self._ending is None or self._ending[0] != tk:
            coeffs = tuple(x[0] for x in self._speed.coefficients(tk, t - tk, 1, len(r)))
            if self._cuts(coeffs, r, t - tk) <= KEEP_SUBSTEPS:
                return True
            before = self._incoming[k - self._k0]
            self._ending = (tk, self._keeping_ends(tk, r, before))
        for _ in self._ending[1]:
            if spent():
                return False
        self._ending = None
        return True

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

    def _speed_block(self) -> Generator[None, None, None]:
        """(1.59): the next block of nodes, pausing after every substep; the block (and the
        compensation of its sums) is taken only when it is whole."""
        assert self._speed is not None
        k0 = self._k0 + len(self._nodes) - 1
        t = self.t0 + k0 * self.h
        r = self._nodes[-1]
        comp = self._comp
        nodes = np.empty((SPEED_BLOCK + 1, *r.shape))
        nodes[0] = r
        batch = self._speed.coefficients(t, self.h, SPEED_BLOCK, len(r))
        incoming = [self._incoming[-1]]
        for j in range(SPEED_BLOCK):
            coeffs = tuple(x[j] for x in batch)
            work = self._speed.substepping(t + j * self.h, r, self.h, coeffs, incoming[-1])
            step = yield from work
            incoming.append(self._speed.last)
            inc = (step - r) - comp
            nxt = r + inc
            comp = (nxt - r) - inc
            r = nodes[j + 1] = nxt
            # every whole step is taken at once: a live run shows it while the block goes on
            self._incoming = list(incoming)
            self.nfev = self._speed.evaluations
            self._comp = comp
            self._k0, self._nodes = k0, nodes[: j + 2]

    def _next_block(self) -> None:
        if self._speed is not None:
            work = self._building = self._building or self._speed_block()
            for _ in work:
                pass
            self._building = None
            return
        k0 = self._k0 + len(self._nodes) - 1
        t = self.t0 + k0 * self.h
        r = self._nodes[-1]
        charge(WORK_PER_STAGE * BLOCK * self.stages * len(r))
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
        """The substeps :meth:`SpeedStepper.step_substeps` starts a step of ``length`` from
        ``r`` with (:meth:`SpeedStepper.cuts`)."""
        assert self._speed is not None
        return self._speed.cuts(coeffs, r, length)

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
            if self._ending is None or self._ending[0] != tk:
                self._ending = (tk, self._keeping_ends(tk, r, before))
            for _ in self._ending[1]:
                pass
            self._ending = None
            kept = self._substep_ends
            assert kept is not None
        _, hs, ends, slopes = kept
        i = min(int(np.floor(rest / hs)), len(ends) - 2)
        d = rest - i * hs
        if d <= 1e-12 * max(1.0, abs(tk)):
            return ends[i]
        covering = slopes[i + 1]
        return self._speed.step_substeps(tk + i * hs, ends[i], d, None, slopes[i], covering)

    def _keeping_ends(
        self, tk: float, r: np.ndarray, before: tuple[np.ndarray, float] | None
    ) -> Generator[None, None, None]:
        """Keeps the ends of the ``m`` equal substeps of the whole step from the node
        ``(tk, r)`` (:meth:`_from_substep_ends`), pausing after each; the stepper's warm
        start is left as it was (a block paused meanwhile goes on from its own)."""
        assert self._speed is not None
        speed = self._speed
        coeffs = tuple(x[0] for x in speed.coefficients(tk, self.h, 1, len(r)))
        m = self._cuts(coeffs, r, self.h)
        hs = self.h / m
        batch = speed.coefficients(tk, hs, m, len(r))
        ends, slopes = [r], [before]
        comp = np.zeros_like(r)
        for i in range(m):
            warm = speed.K, speed.last
            step = speed.step(r, hs, tuple(x[i] for x in batch), slopes[-1])
            slopes.append((speed.K, hs))
            speed.K, speed.last = warm
            inc = (step - r) - comp
            nxt = r + inc
            comp = (nxt - r) - inc
            r = nxt
            ends.append(r)
            yield
        self._substep_ends = (tk, hs, ends, slopes)

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
            before = int(solver.nfev)
            solver.step()
            taken = True
            charge(WORK_PER_EVALUATION * (int(solver.nfev) - before) * len(self.r0))
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
