"""Solutions of the equations of motion as functions of time, and the live steppers on them.

One truth for a headless run and the live view: :class:`DenseSolution` integrates
``y' = rhs(t, y)`` from ``(t0, y0)`` in fixed chunks of time, on demand, keeping the
solver's dense output, so that a run's samples and a live frame at the same time read the
same solution (computed once per parameter set).  :class:`ClosedForm` does the same for a
state known in closed form (a prescribed motion law).  :class:`SolutionStepper` plays a
solution in the live view: ``advance`` only moves the time; new parameters restart the
solution from the current state.  :func:`integrate` samples a :class:`DenseSolution`.
"""

from __future__ import annotations

import bisect
import math
import threading
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.integrate
from analyzer_lab.lessons.kit.budget import charge, spent
from analyzer_lab.lessons.kit.contract import Frame, Params, Stepper
from scipy.integrate import OdeSolution, solve_ivp

Array = np.ndarray
Rhs = Callable[[float, Array], Array]
#: lesson time covered by one solve_ivp call of a :class:`DenseSolution` (s)
CHUNK = 2.0
#: Solver steps a solution keeps (a long live run): past it the oldest pieces are dropped
#: down to half of it, and a read before the pieces kept solves again from the start (the
#: same chunks, the same steps).
KEEP_STEPS = 20_000
#: Work counted per evaluation of the right-hand side by default
#: (:func:`analyzer_lab.lessons.kit.budget.charge`, about a microsecond a unit).
WORK_PER_EVALUATION = 20.0
_FAILURES = (np.linalg.LinAlgError, ZeroDivisionError, FloatingPointError, ValueError)


class DenseSolution:
    """``y(t)`` of ``y' = rhs(t, y)``, ``y(t0) = y0``, solved chunk by chunk as far as asked.

    Calling it with times ``t`` (1-D) gives the states ``(len(t), n)``.  Where the
    equations give a non-finite value (a singular position, a force formula that blows
    up) the solution stops: later states are NaN, :attr:`stopped_at` is the last good
    time and :attr:`message` says why.
    """

    def __init__(
        self,
        rhs: Rhs,
        t0: float,
        y0: Array,
        rtol: float = 1e-9,
        atol: float = 1e-11,
        method: str = "DOP853",
        chunk: float = CHUNK,
        work: float = WORK_PER_EVALUATION,
    ) -> None:
        self._rhs, self._tol, self._method = rhs, (rtol, atol), method
        #: work counted per evaluation of ``rhs``
        self.work = float(work)
        self._chunk = float(chunk)
        #: finished pieces: first and last time, the solution on them
        self._pieces: list[tuple[float, float, OdeSolution]] = []
        self._starts: list[float] = []  # the pieces' first times (ascending)
        self._t0, self._y0 = float(t0), np.array(y0, dtype=float)
        self._t_end, self._y_end = self._t0, self._y0
        self._open: _Chunk | None = None  # the chunk being stepped, if any
        #: solver steps in the pieces kept; steps dropped from the front (:data:`KEEP_STEPS`)
        self.kept = 0
        self.dropped = 0
        self._replay: DenseSolution | None = None
        self.stopped_at = math.inf
        self.message = ""
        #: one solution serves every page with these values, on several threads
        self._lock = threading.RLock()

    def reach(self, t: float) -> float:
        """Solve towards ``t``; the time solved up to: ``t``, or less once the work budget
        (:mod:`analyzer_lab.lessons.kit.budget`) is spent (at least one solver step is taken per call)."""
        with self._lock:
            return self._reach(t)

    def _reach(self, t: float) -> float:
        self._extend(t, budget=True)
        if self.message:
            return t
        covered = self._open.solver.t if self._open is not None else self._t_end
        return min(t, max(covered, self._t_end))

    def _extend(self, t_max: float, budget: bool = False) -> None:
        """Solve chunk by chunk until ``t_max`` is covered.  A chunk is stepped as
        ``solve_ivp`` would step it (the same steps however far anyone asks), and may be
        left open between two calls when the work budget is spent."""
        taken = False
        while self._t_end < t_max and not self.message:
            ch = self._open
            if ch is None:
                ch = self._open = _Chunk(self, self._t_end, self._t_end + self._chunk)
            while ch.solver.status == "running" and not ch.bad and ch.solver.t < t_max:
                if budget and taken and spent():
                    return
                ch.step()
                taken = True
            if ch.solver.status == "running" and not ch.bad:
                return  # t_max is covered inside the open chunk
            self._open = None
            self._close(ch)

    def _close(self, ch: _Chunk) -> None:
        """A finished chunk becomes a piece; after a non-finite value it is solved again,
        halfway from its last good step to the bad time, and ends there."""
        a = ch.a
        if not ch.bad and ch.solver.status == "finished":
            b = float(ch.solver.t)
            if b > a:
                self._keep(a, b, OdeSolution(ch.ts, ch.interpolants))
                self._y_end = np.asarray(ch.solver.y, dtype=float)
            self._t_end = b
            return
        if not ch.bad:  # the solver failed (step size too small, ...)
            b = ch.ts[-1]
            if b > a:
                self._keep(a, b, OdeSolution(ch.ts, ch.interpolants))
                self._y_end = np.asarray(ch.interpolants[-1](b), dtype=float)
            self.message = f"integration stopped at t = {b:.4g}: {ch.failure}"
            self._t_end = self.stopped_at = b
            return
        bad: float | None = ch.bad[0]
        first_bad = bad
        times = np.array(ch.ts)
        sol: Any = None
        for _ in range(40):  # solved again, halfway from its last good step to the bad time
            if bad is None or bad <= a:
                break
            clean = float(np.max(times[times < bad], initial=a))
            sol, bad = self._solve(a, clean + 0.5 * (bad - clean))
            times = sol.t
        if bad is not None:  # still failing: keep the steps before the bad time
            b = float(np.max(times[times < bad], initial=a))
        else:
            b = float(times[-1])
        if b > a and sol is not None:
            self._keep(a, b, sol.sol)
            self._y_end = np.asarray(sol.sol(b), dtype=float)
        if first_bad is not None:
            self.message = (
                f"integration stopped at t = {first_bad:.4g}: the equations gave a"
                " non-finite value (singular position or force)"
            )
        self._t_end = b
        self.stopped_at = b

    def _keep(self, a: float, b: float, sol: Any) -> None:
        """A finished piece; past :data:`KEEP_STEPS` the oldest pieces go."""
        self._pieces.append((a, b, sol))
        self._starts.append(a)
        self.kept += len(sol.interpolants)
        if self.kept <= KEEP_STEPS:
            return
        while self.kept > KEEP_STEPS // 2 and len(self._pieces) > 1:
            n = len(self._pieces[0][2].interpolants)
            del self._pieces[0], self._starts[0]
            self.kept -= n
            self.dropped += n

    @property
    def kept_from(self) -> float:
        """The first time the pieces kept cover (``t0`` until any were dropped)."""
        return self._pieces[0][0] if self.dropped and self._pieces else self._t0

    def _replayed(self, tt: Array) -> Array:
        """The states at times before the pieces kept: solved again from the start (the
        chunks and their steps depend only on the equations, start and tolerances)."""
        if self._replay is None or self._replay.kept_from > float(np.min(tt)):
            self._replay = DenseSolution(
                self._rhs, self._t0, self._y0, *self._tol, self._method, self._chunk, self.work
            )
        return self._replay(tt)

    def _solve(self, a: float, b: float) -> tuple[Any, float | None]:
        """solve_ivp over ``[a, b]`` with dense output; the first time the equations gave a
        non-finite value (then the rest of the span is frozen), or None."""
        bad: list[float] = []

        def guarded(tt: float, yy: Array) -> Array:
            # a non-finite derivative would make the step control loop forever:
            # freeze the state (the span then ends at once); the span is solved again
            if bad:
                return np.zeros_like(yy)
            try:
                out = np.asarray(self._rhs(tt, yy), dtype=float)
            except _FAILURES:
                out = np.array([np.nan])
            if not np.all(np.isfinite(out)):
                bad.append(tt)
                return np.zeros_like(yy)
            return out

        sol = solve_ivp(
            guarded,
            (a, b),
            self._y_end,
            method=self._method,
            rtol=self._tol[0],
            atol=self._tol[1],
            dense_output=True,
        )
        charge(self.work * int(sol.nfev))
        return sol, (bad[0] if bad else None)

    def __call__(self, t: Array) -> Array:
        with self._lock:
            return self._at(t)

    def _at(self, t: Array) -> Array:
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        if len(tt) == 1:  # a frame: one lookup
            return self._one(tt)
        self._extend(float(np.max(tt, initial=self._t_end)))
        out = np.full((len(tt), len(self._y0)), np.nan)
        out[tt == self._t0] = self._y0
        early = (tt > self._t0) & (tt < self.kept_from)
        if early.any():
            out[early] = self._replayed(tt[early])
        ch = self._open
        pieces = list(self._pieces)
        if ch is not None and ch.interpolants:
            pieces.append((ch.a, float(ch.solver.t), OdeSolution(ch.ts, ch.interpolants)))
        for a, b, sol in pieces:
            k = (tt >= a) & (tt <= b)
            if np.any(k):
                out[k] = np.asarray(sol(tt[k]), dtype=float).T
        return out

    def _one(self, tt: Array) -> Array:
        """The state at the one time of ``tt`` (``(1, n)``): the step that holds it, as
        :class:`~scipy.integrate.OdeSolution` picks it, read without building one."""
        x = float(tt[0])
        if x > self._t_end:
            self._extend(x)
        if self._t0 < x < self.kept_from:
            return self._replayed(tt)
        ch = self._open
        if ch is not None and ch.interpolants and ch.a <= x <= float(ch.solver.t):
            return _step_at(ch.ts, ch.interpolants, x, tt)
        if self._pieces:
            # pieces share their ends: the last that holds x, as the grid read leaves it
            k = bisect.bisect_right(self._starts, x) - 1
            if k >= 0 and self._pieces[k][0] <= x <= self._pieces[k][1]:
                sol = self._pieces[k][2]
                return _step_at(sol.ts, sol.interpolants, x, tt)
        out = np.full((1, len(self._y0)), np.nan)
        if x == self._t0:
            out[0] = self._y0
        return out


def _step_at(ts: Any, interpolants: list[Any], x: float, tt: Array) -> Array:
    """``OdeSolution(ts, interpolants)(tt).T`` for the one time ``x`` of ``tt``: the same
    step (the lower one at a shared step end) and the same numbers.  DOP853's dense
    output does the same elementwise arithmetic on one time as on an array of times, so
    it is read at ``x`` itself (half the cost of an array of one)."""
    k = min(max(bisect.bisect_left(ts, x) - 1, 0), len(interpolants) - 1)
    step = interpolants[k]
    if type(step).__name__ == "Dop853DenseOutput":  # scipy's DOP853 (others: any time array)
        return np.asarray(step(x), dtype=float)[None, :]
    return np.asarray(step(tt), dtype=float).T


class _Chunk:
    """One chunk of a :class:`DenseSolution` being stepped: the solver ``solve_ivp``
    would make for ``[a, b]`` (same method, tolerances and steps), its step times and
    dense outputs, and the first time the equations gave a non-finite value."""

    def __init__(self, owner: DenseSolution, a: float, b: float) -> None:
        self.a, self.b = a, b
        self.bad: list[float] = []
        self.failure = ""
        self.ts: list[float] = [a]
        self.interpolants: list[Any] = []
        rhs = owner._rhs

        def guarded(tt: float, yy: Array) -> Array:
            if self.bad:
                return np.zeros_like(yy)
            try:
                out = np.asarray(rhs(tt, yy), dtype=float)
            except _FAILURES:
                out = np.array([np.nan])
            if not np.all(np.isfinite(out)):
                self.bad.append(tt)
                return np.zeros_like(yy)
            return out

        self.work = owner.work
        method = getattr(scipy.integrate, owner._method)
        self.solver = method(guarded, a, owner._y_end, b, rtol=owner._tol[0], atol=owner._tol[1])

    def step(self) -> None:
        before = int(self.solver.nfev)
        message = self.solver.step()
        if self.solver.status == "failed" or self.bad:
            self.failure = str(message or "the solver failed")
        else:
            self.ts.append(float(self.solver.t))
            self.interpolants.append(self.solver.dense_output())
        charge(self.work * (int(self.solver.nfev) - before))


class ClosedForm:
    """A state known in closed form, ``t -> (len(t), n)`` states (never stops)."""

    stopped_at = math.inf
    message = ""

    def __init__(self, states: Callable[[Array], Array]) -> None:
        self._states = states

    def reach(self, t: float) -> float:
        """Every time is known: ``t``."""
        return t

    def __call__(self, t: Array) -> Array:
        return self._states(np.atleast_1d(np.asarray(t, dtype=float)))


Solution = DenseSolution | ClosedForm
#: ``start(params, t0, y)``: the solution of these parameters from ``(t0, y)`` (``y`` None:
#: the lesson's own start at t = 0), and ``frame_of(t, state)`` drawing one state
Start = Callable[[Params, float, "Array | None"], tuple[Solution, Callable[[float, Array], Frame]]]


def integrate(
    rhs: Rhs,
    y0: Array,
    t: Array,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str = "DOP853",
) -> tuple[Array, str]:
    """A :class:`DenseSolution` from ``t[0]`` on the sample times: ``(y (n, len(t)),
    message)``; after a failure the samples are NaN and the message says where it stopped."""
    span = max(float(t[-1]) - float(t[0]), 1e-12)  # one piece: one step-size history
    sol = DenseSolution(rhs, float(t[0]), y0, rtol, atol, method, chunk=span)
    return sol(t).T, sol.message


class SolutionStepper(Stepper):
    """Live run of a :data:`Solution`: ``advance`` moves the time and reads the state.

    ``set_params`` restarts from the current state with the new parameters; ``reset``
    starts again at t = 0 (the solution a headless run with these parameters reads).
    After the solution stopped, the time holds at its last good value with its message.
    """

    def __init__(self, start: Start, params: Params) -> None:
        self._start = start
        self._params = params
        self._t = 0.0
        self._sol, self._frame_of = start(params, 0.0, None)
        self._y: tuple[float, Array] | None = None

    @property
    def t(self) -> float:
        return self._t

    def state(self) -> Array:
        """The state at the current time (read once per time)."""
        if self._y is None or self._y[0] != self._t:
            self._y = (self._t, self._sol(np.array([self._t]))[0])
        return self._y[1]

    def frame(self) -> Frame:
        fr = self._frame_of(self._t, self.state())
        if self._sol.message and self._t >= self._sol.stopped_at and not fr.message:
            fr.message = self._sol.message
        return fr

    def advance(self, dt: float) -> Frame:
        target = self._sol.reach(self._t + max(float(dt), 0.0))
        y = self._sol(np.array([target]))[0]
        self._t = min(target, max(self._t, self._sol.stopped_at))
        self._y = (target, y) if self._t == target else None
        return self.frame()

    def set_params(self, params: Params) -> None:
        y = self.state()
        self._params = params
        self._sol, self._frame_of = self._start(params, self._t, y)
        self._y = None

    def reset(self) -> Frame:
        self._t = 0.0
        self._sol, self._frame_of = self._start(self._params, 0.0, None)
        self._y = None
        return self.frame()


class OdeStepper(SolutionStepper):
    """Live run of ``y' = rhs(t, y)``; ``make(params)`` gives ``(y0, rhs, frame_of(t, y))``."""

    def __init__(
        self,
        make: Callable[[Params], tuple[Array, Rhs, Callable[[float, Array], Frame]]],
        params: Params,
        rtol: float = 1e-8,
        method: str = "DOP853",
    ) -> None:
        def start(
            ps: Params, t0: float, y: Array | None
        ) -> tuple[Solution, Callable[[float, Array], Frame]]:
            y0, rhs, frame_of = make(ps)
            sol = DenseSolution(rhs, t0, y0 if y is None else y, rtol, rtol * 1e-2, method)
            return sol, frame_of

        super().__init__(start, params)


__all__ = [
    "CHUNK",
    "ClosedForm",
    "DenseSolution",
    "OdeStepper",
    "Solution",
    "SolutionStepper",
    "integrate",
]
