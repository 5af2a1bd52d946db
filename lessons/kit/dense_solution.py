"""A dense ODE solution built once per parameter set and shared by a run and a stepper.

:class:`DenseSolution` steps one of scipy's solvers (RK45, DOP853, Radau) forward from
``t0`` and keeps the interpolant of every step, so the solution at any time already
covered is one evaluation.  The step sequence depends only on the equations, the start
and the tolerances, never on how far anyone asks: a lesson's :meth:`simulate` and its
live stepper that build the solution from the same values get the same numbers at the
same times.  :class:`RunStepper` plays such a solution: ``advance(dt)`` moves the
lesson time by ``dt``, extends the solution when needed (in blocks, so a frame usually
only evaluates) and observes; ``set_params`` builds a new solution from the current
state.  A closed-form run plays the same way (it covers every time).  Given the lesson's
observation, a played frame on the session's time grain reads a row of a
:class:`FrameTable`: the states and the observation of a block of grain times, evaluated
at once.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable, Sequence
from typing import Any, Protocol

import numpy as np
from analyzer_lab.lessons.kit.budget import charge, spent
from analyzer_lab.lessons.kit.contract import Frame, Lesson, Params, Stepper
from scipy.integrate import DOP853, RK45, Radau

Array = np.ndarray
SOLVERS = {"RK45": RK45, "DOP853": DOP853, "Radau": Radau}
#: far end handed to the solver: the solution is open-ended and extended on demand
_T_BOUND = 1e9
#: lesson seconds between the times a played frame falls on at time scale 1 (the session's
#: time quanta)
FRAME_GRAIN = 1.0 / 600.0
#: grain times of one block of a :class:`FrameTable`
TABLE_BLOCK = 240
#: Solver steps a solution keeps (a long live run): past it the older half is dropped, and a
#: read before the steps kept replays the solution from its start (the same steps).
KEEP_STEPS = 20_000
#: Work counted per evaluation of the right-hand side by default
#: (:func:`analyzer_lab.lessons.kit.budget.charge`, about a microsecond a unit).
WORK_PER_EVALUATION = 20.0


class DenseSolution:
    """``y' = rhs(t, y)`` from ``(t0, y0)``, stepped on demand; ``state(t)`` evaluates.

    A non-finite derivative or a failed step ends the solution: ``failure`` then says
    where, and later times evaluate to NaN.
    """

    def __init__(
        self,
        rhs: Callable[[float, Array], Array],
        t0: float,
        y0: Array,
        method: str = "DOP853",
        rtol: float = 1e-9,
        atol: float = 1e-11,
        work: float = WORK_PER_EVALUATION,
    ) -> None:
        self._rhs = rhs
        #: work counted per evaluation of ``rhs`` (a dear model declares more)
        self.work = float(work)
        self._start = (np.array(y0, dtype=float), method, rtol, atol)
        #: solver steps dropped from the front (:data:`KEEP_STEPS`)
        self.dropped = 0
        self._replay: DenseSolution | None = None
        self.t0 = float(t0)
        self.dim = len(y0)
        self.failure = ""
        self._ts = [self.t0]
        self._steps: list[Any] = []
        self._solver = SOLVERS[method](
            self._guarded, self.t0, np.asarray(y0, dtype=float), _T_BOUND, rtol=rtol, atol=atol
        )

    def _guarded(self, t: float, y: Array) -> Array:
        out = np.asarray(self._rhs(t, y), dtype=float)
        if not np.isfinite(out).all():
            raise FloatingPointError(f"the equations gave a non-finite value at t = {t:.4g}")
        return out

    @property
    def t_covered(self) -> float:
        return self._ts[-1]

    @property
    def steps(self) -> int:
        """The solver steps taken so far."""
        return self.dropped + len(self._steps)

    @property
    def kept(self) -> int:
        """The solver steps kept (at most :data:`KEEP_STEPS`)."""
        return len(self._steps)

    @property
    def evaluations(self) -> int:
        """The evaluations of the right-hand side so far."""
        return int(self._solver.nfev)

    def extend(self, t: float) -> None:
        """Step until the solution covers ``t`` (or fails), or until the work budget
        (:mod:`analyzer_lab.lessons.kit.budget`) is spent, after at least one step."""
        taken = False
        while self._ts[-1] < t and not self.failure:
            if taken and spent():
                return
            taken = True
            before = int(self._solver.nfev)
            try:
                message = self._solver.step()
            except (np.linalg.LinAlgError, ZeroDivisionError, FloatingPointError) as exc:
                message = str(exc)
            if self._solver.status == "failed" or message:
                self.failure = f"integration stopped at t = {self._ts[-1]:.4g}: {message}"
                return
            self._steps.append(self._solver.dense_output())
            self._ts.append(float(self._solver.t))
            if len(self._steps) > KEEP_STEPS:  # a long run keeps a window of steps
                n = KEEP_STEPS // 2
                del self._steps[:n], self._ts[:n]
                self.dropped += n
            charge(self.work * (int(self._solver.nfev) - before))

    def _replayed(self, t: Array) -> Array:
        """The states at times before the steps kept: the solution stepped again from its
        start (a solver's steps depend only on the equations, start and tolerances)."""
        if self._replay is None or self._replay._ts[0] > float(np.min(t)):
            y0, method, rtol, atol = self._start
            self._replay = DenseSolution(self._rhs, self.t0, y0, method, rtol, atol, self.work)
        return self._replay.state(t)

    def state(self, t: Array) -> Array:
        """The solution at the times ``t`` (1-D): shape ``(len(t), dim)``, NaN where it
        is not defined (before ``t0`` or after a failure)."""
        t = np.asarray(t, dtype=float)
        self.extend(float(np.max(t, initial=self.t0)))
        out = np.full((len(t), self.dim), np.nan)
        if not self._steps:
            out[t == self.t0] = self._solver.y
            return out
        early = (t >= self.t0) & (t < self._ts[0])
        if early.any():
            out[early] = self._replayed(t[early])
        if len(t) == 1:  # a frame: one lookup
            k = bisect.bisect_right(self._ts, float(t[0])) - 1
            k = min(k, len(self._steps) - 1)
            if t[0] >= self._ts[0] and t[0] <= self._ts[-1]:
                out[0] = self._steps[k](float(t[0]))
            return out
        idx = np.clip(np.searchsorted(self._ts, t, side="right") - 1, 0, len(self._steps) - 1)
        ok = (t >= self._ts[0]) & (t <= self._ts[-1])
        for k in np.unique(idx[ok]):
            sel = ok & (idx == k)
            out[sel] = self._steps[k](t[sel]).T
        return out


class Run(Protocol):
    """What :class:`RunStepper` plays: the state at any time (a closed form, or dense
    solutions extended on demand up to ``t_covered``) and why it ended, if it did."""

    failure: str

    @property
    def t_covered(self) -> float: ...

    def extend(self, t: float) -> None: ...

    def state(self, t: Array) -> Array: ...


class FrameTable:
    """States and observation of one run at blocks of :data:`TABLE_BLOCK` grain times
    (multiples of ``grain``), each block evaluated in one vectorized call when a frame
    first reaches it: a played frame reads a row.  ``observe(t, states)`` is the lesson's
    observation (the same function a headless run samples), ``names`` its scalars."""

    def __init__(
        self,
        run: Run,
        observe: Callable[[Array, Array], dict[str, Array]],
        names: Sequence[str],
        grain: float = FRAME_GRAIN,
    ) -> None:
        self._run, self._observe, self.names, self.grain = run, observe, tuple(names), grain
        #: (block, states (TABLE_BLOCK, dim), scalars as lists of floats per row)
        self._block: tuple[int, Array, list[list[float]]] | None = None
        self.builds = 0  # blocks evaluated so far

    def on_grain(self, t: float) -> float:
        """``t`` moved onto the grain time it rounds to (by far less than the session's
        tolerance), or ``t`` itself off the grain."""
        j = round(t / self.grain)
        return j * self.grain if j >= 0 and abs(t / self.grain - j) <= 1e-9 else t

    def row(self, t: float) -> tuple[Array, dict[str, float]] | None:
        """The state (leading axis of length 1) and the scalars at the grain time ``t``;
        None off the grain or where the run does not cover the whole block."""
        j = round(t / self.grain)
        if j < 0 or t != j * self.grain:
            return None
        b, i = divmod(j, TABLE_BLOCK)
        if self._block is None or self._block[0] != b:
            tt = (b * TABLE_BLOCK + np.arange(TABLE_BLOCK)) * self.grain
            run = self._run
            if not run.failure and run.t_covered < tt[-1]:
                run.extend(float(tt[-1]))
            if run.failure or run.t_covered < tt[-1]:
                return None
            S = run.state(tt)
            obs = self._observe(tt, S)
            rows = np.column_stack([np.broadcast_to(obs[n], tt.shape) for n in self.names])
            self._block = (b, S, rows.tolist())
            self.builds += 1
        return self._block[1][i : i + 1], dict(zip(self.names, self._block[2][i]))


class RunStepper(Stepper):
    """Live view of a :class:`Run`: ``build(params, t0, state_or_None)`` makes the run
    (from the current state after a parameter change), ``frame_of(params, t, state)``
    the frame (``state`` with a leading time axis of length 1).  The run is extended
    ``block`` lesson seconds ahead at a time.  With the lesson's ``observe(params, t,
    states)`` and its scalar ``names(params)``, frames on the grain read a
    :class:`FrameTable` and ``frame_of(params, t, state, scalars)`` gets the scalars
    (None off the grain)."""

    def __init__(
        self,
        build: Callable[[Params, float, Array | None], Run],
        frame_of: Callable[..., Frame],
        params: Params,
        block: float = 2.0,
        observe: Callable[[Params, Array, Array], dict[str, Array]] | None = None,
        names: Callable[[Params], Sequence[str]] | None = None,
        grain: float = FRAME_GRAIN,
    ) -> None:
        self._build, self._frame_of, self._block = build, frame_of, float(block)
        self._observe, self._names, self._grain = observe, names, grain
        self._params = params
        self._t = 0.0
        self._run = build(params, 0.0, None)
        self._table = self._new_table()

    @classmethod
    def for_lesson(
        cls,
        lesson: Lesson,
        params: Params,
        build: Callable[[Params, float, Array | None], Run],
        frame_of: Callable[..., Frame],
    ) -> RunStepper:
        """``lesson``'s run played live: frames on the grain of its time scale read its
        observation (:meth:`~Lesson.observe`, :meth:`~Lesson.series_names`) from a table."""
        return cls(
            build,
            frame_of,
            params,
            observe=lesson.observe,
            names=lesson.series_names,
            grain=FRAME_GRAIN * lesson.time_scale,
        )

    def _new_table(self) -> FrameTable | None:
        if self._observe is None or self._names is None:
            return None
        observe, params = self._observe, self._params
        return FrameTable(
            self._run, lambda t, S: observe(params, t, S), self._names(params), self._grain
        )

    @property
    def t(self) -> float:
        return self._t

    def _read(self) -> tuple[Array, dict[str, float] | None]:
        """The state at the current time (leading axis of length 1) and, from the table,
        its scalars (None: not read from the table)."""
        hit = self._table.row(self._t) if self._table is not None else None
        return hit if hit is not None else (self._run.state(np.array([self._t])), None)

    def frame(self) -> Frame:
        if not self._run.failure and self._t > self._run.t_covered:
            self._run.extend(self._t + self._block)
        state, scalars = self._read()
        if self._table is None:
            fr = self._frame_of(self._params, self._t, state)
        else:
            fr = self._frame_of(self._params, self._t, state, scalars)
        if self._run.failure and not fr.message:
            fr.message = self._run.failure
        return fr

    def advance(self, dt: float) -> Frame:
        """Move on by ``dt``, or less if the work budget runs out while the run is
        extended (the time then stops where the solution is known)."""
        target = self._t + max(float(dt), 0.0)
        run = self._run
        if not run.failure and target > run.t_covered:
            run.extend(target + self._block)
            if not run.failure:
                target = min(target, run.t_covered)
        self._t = max(self._t, target)
        if self._table is not None:  # accumulated round-off: the time the table holds
            on = self._table.on_grain(self._t)
            self._t = on if on <= run.t_covered else self._t
        return self.frame()

    def set_params(self, params: Params) -> None:
        state, _ = self._read()  # the state the last frame showed
        self._params = params
        self._run = self._build(params, self._t, state[0] if np.all(np.isfinite(state)) else None)
        self._table = self._new_table()

    def reset(self) -> Frame:
        self._t = 0.0
        self._run = self._build(self._params, 0.0, None)
        self._table = self._new_table()
        return self.frame()


class ClosedFormRun:
    """A run given in closed form: ``state(t)`` is ``solution(t)`` (every time covered)."""

    failure = ""
    t_covered = np.inf

    def __init__(self, solution: Callable[[Array], Array]) -> None:
        self.state = solution

    def extend(self, t: float) -> None:
        """Nothing to compute: a closed form covers every time."""
