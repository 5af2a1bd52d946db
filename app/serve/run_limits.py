"""What ``analyzer-lab run`` refuses before it starts, and the finiteness of what it ran.

Three limits, stated in ``run --help`` and the README:

* fixed integration steps: ``t_end / h`` times the points of a family, at most
  :data:`MAX_POINT_STEPS`;
* computing: the lesson's own stepper is timed on a short piece of the run (at most
  :data:`PROBE_CPU` seconds) and the whole run is estimated from it; at most
  :data:`MAX_CPU_SECONDS`;
* memory: samples times series of the result, at most :data:`MAX_VALUES` numbers.

A run that got through has every sample checked: the first value that is not finite
is named with its time (:func:`first_non_finite`).
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # imported where used: ``run --help`` reads the limits without the model
    from analyzer_lab.lessons.kit.contract import LessonSetup, RunResult

log = logging.getLogger(__name__)

#: Fixed integration steps of a run (``t_end / h`` times the points of a family).
MAX_POINT_STEPS = 10_000_000
#: Estimated CPU seconds of a run.
MAX_CPU_SECONDS = 120.0
#: Numbers in the result (samples times series): about 160 MB as floats.
MAX_VALUES = 20_000_000
#: CPU seconds spent timing the lesson's stepper before the run.
PROBE_CPU = 0.5

LIMITS_TEXT = (
    f"run refuses, before it starts, a run of more than {MAX_POINT_STEPS:,} fixed"
    f" integration steps (t_end / h times the points of a family), one estimated (from a"
    f" timed piece of the run) to compute for more than {MAX_CPU_SECONDS:g} s, or one whose"
    f" result would hold more than {MAX_VALUES:,} numbers (samples times series); a run"
    " whose result is not finite somewhere exits with code 2 naming the quantity and time"
)


def _points(setup: LessonSetup) -> int:
    family = setup.lesson.family
    if family is not None and family in setup.params:
        return max(1, int(setup.params[family]))
    return 1


def refusal(setup: LessonSetup, t_end: float) -> str | None:
    """Why the run of ``setup`` up to ``t_end`` is refused (one line), or None."""
    lesson, params = setup.lesson, setup.params
    points = _points(setup)
    h = params.get("h")
    method = str(params.get("integrator", "gauss-legendre"))
    if isinstance(h, (int, float)) and h > 0 and method.startswith("gauss-legendre"):
        steps = math.ceil(t_end / float(h)) * points
        if steps > MAX_POINT_STEPS:
            return (
                f"this run needs {steps:.3g} integration steps (t_end / h = {t_end:g} /"
                f" {float(h):g} times {points} point(s)); the limit is {MAX_POINT_STEPS:,}:"
                " use a larger h, a shorter --t-end or a smaller family"
            )
    grid = getattr(lesson, "run_grid", None)
    if callable(grid):
        samples = len(grid(params, t_end))
        values = samples * max(1, len(lesson.series_for(params)))
        if values > MAX_VALUES:
            return (
                f"the result would hold {values:.3g} numbers ({samples} samples of"
                f" {len(lesson.series_for(params))} series); the limit is {MAX_VALUES:,}:"
                " use a shorter --t-end or a smaller family"
            )
    estimate = cpu_estimate(setup, t_end)
    if estimate is not None and estimate > MAX_CPU_SECONDS:
        return (
            f"this run would compute for about {estimate:.3g} s (timed on a piece of it);"
            f" the limit is {MAX_CPU_SECONDS:g} s: use a larger step or tolerance, or a"
            " shorter --t-end"
        )
    return None


def cpu_estimate(setup: LessonSetup, t_end: float) -> float | None:
    """CPU seconds of the whole run, from the setup's stepper timed on its first piece
    (it is advanced; None when the piece could not be run: the run itself reports why)."""
    from analyzer_lab.lessons.kit.budget import clock, work_budget

    span = min(t_end, setup.lesson.t_end)
    piece = span / 50
    try:
        stepper = setup.stepper
        start = clock()
        with work_budget(PROBE_CPU):
            while stepper.t < span - 1e-12 * max(1.0, span) and clock() - start < PROBE_CPU:
                before = stepper.t
                stepper.advance(min(piece, span - stepper.t))
                if stepper.t <= before:
                    break
        used, covered = clock() - start, stepper.t
    except (ValueError, ArithmeticError, RuntimeError):  # the run itself reports it
        log.debug("%s: the run was not timed", setup.lesson.id, exc_info=True)
        return None
    if covered <= 0:
        return None
    return used / covered * t_end


def may_be_undefined(setup: LessonSetup) -> frozenset[str]:
    """The columns (with family members) of the series the lesson declares undefined
    somewhere (``Series.undefined``), for the setup's values."""
    return frozenset(s.name for s in setup.lesson.series_for(setup.params) if s.undefined)


def first_non_finite(
    result: RunResult, allowed: frozenset[str] = frozenset()
) -> tuple[str, float] | None:
    """The first (in time) series value that is not finite: (series, time), or None;
    ``allowed``: series a lesson declares undefined somewhere (:func:`may_be_undefined`)."""
    import numpy as np

    first: tuple[str, float] | None = None
    t = np.asarray(result.t, dtype=float)
    for name, values in result.series.items():
        if name in allowed:
            continue
        v = np.asarray(values, dtype=float)
        bad = ~np.isfinite(v)
        if v.ndim > 1:
            bad = bad.reshape(len(v), -1).any(axis=1)
        if bad.any():
            k = int(np.argmax(bad))
            if first is None or t[k] < first[1]:
                first = (name, float(t[k]))
    if not np.all(np.isfinite(t)):
        return ("t", float("nan"))
    return first


__all__: list[Any] = [
    "LIMITS_TEXT",
    "MAX_CPU_SECONDS",
    "MAX_POINT_STEPS",
    "MAX_VALUES",
    "cpu_estimate",
    "first_non_finite",
    "refusal",
]
