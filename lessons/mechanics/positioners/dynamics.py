"""A chapter-2 page solved once per parameter set: forward and inverse problems.

Every such page (the positioners of Problems 2.1-2.4, the 6-DOF table of Problem 2.5) is
solved two ways: the *forward* problem (forces given as formulas of t -> the motion) and
the *inverse* problem (a motion law given -> the drive forces).  :class:`DynamicsLesson`
holds what they share: the solution of a parameter set, read by the headless run and by
the live stepper alike, the run with its failure messages, and the answers kept per
parameter set (the cached coarse run that sizes the scene among them) for every page of
the server.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, Lesson, Param, Params, RunResult, Stepper
from analyzer_lab.lessons.kit.formula import Formula, FormulaError
from analyzer_lab.lessons.kit.steppers import Solution, SolutionStepper

Array = np.ndarray

PROBLEM = Param(
    "problem",
    "choice",
    "forward",
    label="problem",
    choices=("forward", "inverse"),
    group="mode",
    help="forward: forces given, motion found; inverse: motion law given, drive forces found",
)

#: The answers kept per parameter set are shared by every page of the server, whose pages
#: are built and played on several threads.
_CACHE_LOCK = threading.Lock()
_MISSING = object()


def check_formulas(formulas: Sequence[tuple[str, Formula]], t: Array) -> list[str]:
    """One message per formula that is not finite on the samples ``t``."""
    msgs = []
    for name, f in formulas:
        try:
            f.check_finite(t)
        except FormulaError as exc:
            msgs.append(f"{name}: {exc}")
    return msgs


class DynamicsLesson(Lesson):
    """A page solved once per parameter set: the run and the live frames read one solution.

    Subclasses give :meth:`formulas_in_use`, :meth:`start` (the solution from a time and
    a state), :meth:`observe` and :meth:`pose_frame`.
    """

    chapter = "2"
    modes = ("problem",)
    #: what a frame says where the state is not defined
    undefined = "the motion is not defined"
    _cache: dict[tuple[str, str], Any] = {}
    #: id(params) -> (params, {what: value}): the same answers by parameter object
    _by_object: dict[int, tuple[Params, dict[str, Any]]] = {}

    def formulas_in_use(self, params: Params) -> list[tuple[str, Formula]]:
        raise NotImplementedError

    def start(self, params: Params, t0: float, y: Array | None) -> Solution:
        """The solution of these parameters from ``(t0, y)`` (``y`` None: the lesson's own
        start at t = 0)."""
        raise NotImplementedError

    def pose_frame(self, params: Params, fr: Frame, state: Array) -> None:
        """Poses, points and vectors of the scene for one state (scalars already set)."""
        raise NotImplementedError

    def cached(self, what: str, params: Params, build: Callable[[], Any]) -> Any:
        """``build()`` once per lesson, ``what`` and parameter values.

        A frame asks with the same ``params`` object again and again: its answers are
        also kept by that object (held, so its ``id`` stays its own), which spares
        spelling out the values each time."""
        memo = self._by_object.get(id(params))
        if memo is not None and memo[0] is params and what in memo[1]:
            return memo[1][what]
        key = (f"{self.id}:{what}", repr(sorted(params.raw().items())))
        with _CACHE_LOCK:
            hit = self._cache.get(key, _MISSING)
        if hit is _MISSING:
            built = build()  # outside the lock: a long build does not hold up other pages
            with _CACHE_LOCK:  # the first built is the one every page shares
                hit = self._cache.get(key, _MISSING)
                if hit is _MISSING:
                    if len(self._cache) > 64:
                        self._cache.clear()
                    hit = self._cache[key] = built
        with _CACHE_LOCK:
            memo = self._by_object.get(id(params))
            if memo is None or memo[0] is not params:
                if len(self._by_object) > 64:
                    self._by_object.clear()
                memo = self._by_object[id(params)] = (params, {})
            memo[1][what] = hit
        return hit

    def solution(self, params: Params) -> Solution:
        """The solution from t = 0 that runs and live frames share (once per parameter set)."""
        return self.cached("solution", params, lambda: self.start(params, 0.0, None))

    def coarse_run(self, params: Params) -> RunResult:
        """A run over the lesson's default time (scene extents, force scale)."""
        return self.cached("run", params, lambda: self.simulate(params, self.t_end))

    def run_metrics(self, params: Params, series: dict[str, Array]) -> dict[str, Any]:
        return {}

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t = self.sample_grid(float(self.t_end if t_end is None else t_end))
        msgs = check_formulas(self.formulas_in_use(params), t)
        sol = self.solution(params)
        if msgs:
            state = np.full((len(t), sol(np.zeros(1)).shape[1]), np.nan)
        else:
            state = sol(t)
            msgs += [sol.message] if sol.message else []
        series = self.observation(params, t, state)
        metrics = {"ok": not msgs, "problem": params["problem"]}
        metrics.update(self.run_metrics(params, series))
        return self.result(params, t, state, metrics, msgs)

    def frame_at(self, params: Params, t: float, state: Array) -> Frame:
        fr = Frame(t=float(t), scalars=self.frame_scalars(params, t, state[None, :]))
        self.pose_frame(params, fr, state)
        if not np.all(np.isfinite(state)):
            fr.message = f"{self.undefined} at t = {t:g}"
        return fr

    def stepper(self, params: Params) -> Stepper:
        def start(
            ps: Params, t0: float, y: Array | None
        ) -> tuple[Solution, Callable[[float, Array], Frame]]:
            sol = self.solution(ps) if y is None else self.start(ps, t0, y)
            return sol, lambda tt, state: self.frame_at(ps, tt, state)

        return SolutionStepper(start, params)
