"""What ``analyzer-lab run`` refuses before it starts, and the finiteness of what it ran.

Every limit is a count, so a run is refused or accepted alike on a quiet and on a busy
machine; stated in ``run --help`` and the README:

* fixed integration steps: ``t_end / h`` times the points of a family, at most
  :data:`MAX_POINT_STEPS`;
* computing: units of work, each an evaluation of the equations (a solver step's
  right-hand sides, a Gauss-Legendre step's stages, every substep, times the points)
  weighted by its known cost (about a microsecond a unit), at most :data:`MAX_WORK`.
  Before the run they are known from the lesson's fixed steps
  (:meth:`~analyzer_lab.lessons.kit.contract.Lesson.work_bound`) or counted on its first
  piece (at most :data:`PROBE_WORK` of them) and the whole run estimated from that count;
  during the run the count stops it where it passes the limit
  (:func:`analyzer_lab.lessons.kit.budget.work_limit`).  Building the model (deriving,
  lambdifying) is not stepping and is never counted;
* memory: samples times series of the result, at most :data:`MAX_VALUES` numbers.

A run that got through has every sample checked: the first value that is not finite
is named with its time (:func:`first_non_finite`).
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING, Any

from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.message import Message

if TYPE_CHECKING:  # imported where used: ``run --help`` reads the limits without the model
    from analyzer_lab.lessons.kit.contract import LessonSetup, RunResult

log = logging.getLogger(__name__)

#: Fixed integration steps of a run (``t_end / h`` times the points of a family).
MAX_POINT_STEPS = 10_000_000
#: Units of work of a run (evaluations of the equations over steps, substeps and points,
#: each weighted by its known cost: about a microsecond a unit).
MAX_WORK = 50_000_000
#: Units of work counted on the start of a run to estimate the whole.
PROBE_WORK = 500_000
#: Numbers in the result (samples times series): about 160 MB as floats.
MAX_VALUES = 20_000_000

#: What ``run --help`` says of the limits (numbers: :func:`limits_text`).
LIMITS = N_(
    "run refuses, before it starts, a run of more than {steps} fixed integration steps"
    " (t_end / h times the points of a family), one of more than {work} units of work"
    " (evaluations of the equations weighted by their known cost, counted over steps,"
    " substeps and points on a piece of the run, never timed: the same on a busy"
    " machine), or one whose result would hold more than {values} numbers (samples times"
    " series); a run that passes that count while it runs stops there; a run whose result"
    " is not finite somewhere exits with code 2 naming the quantity and time"
)


def limits_text(language: Language = ENGLISH) -> str:
    """:data:`LIMITS` in ``language``, its numbers grouped as the language groups them."""
    sep = "," if language.decimal == "." else "\u00a0"

    def grouped(n: int) -> str:
        return f"{n:,}".replace(",", sep)

    return language.gettext(LIMITS).format(
        steps=grouped(MAX_POINT_STEPS), work=grouped(MAX_WORK), values=grouped(MAX_VALUES)
    )


def _points(setup: LessonSetup) -> int:
    family = setup.lesson.family
    if family is not None and family in setup.params:
        return max(1, int(setup.params[family]))
    return 1


#: The option that shortens a run, as a refusal names it (``grade`` names the
#: assignment's ``t_end`` instead).
T_END_OPTION = "--t-end"


def refusal(setup: LessonSetup, t_end: float, option: str = T_END_OPTION) -> Message | None:
    """Why the run of ``setup`` up to ``t_end`` is refused (one line, a :class:`Message`
    the command line shows in its language), or None; ``option`` is what shortens the
    run."""
    lesson, params = setup.lesson, setup.params
    points = _points(setup)
    h = params.get("h")
    method = str(params.get("integrator", "gauss-legendre"))
    if isinstance(h, (int, float)) and h > 0 and method.startswith("gauss-legendre"):
        steps = math.ceil(t_end / float(h)) * points
        if steps > MAX_POINT_STEPS:
            return Message(
                N_(
                    "this run needs {steps:.3g} integration steps (t_end / h = {t_end:g} /"
                    " {h:g} times {points} point(s)); the limit is {limit:,}:"
                    " use a larger h, a shorter {option} or a smaller family"
                ),
                steps=steps,
                t_end=t_end,
                h=float(h),
                points=points,
                limit=MAX_POINT_STEPS,
                option=option,
            )
    bound = lesson.work_bound(params, t_end)
    if bound > MAX_WORK:
        return _too_much(bound, Message(N_("counted from its steps, stages and points")), option)
    grid = getattr(lesson, "run_grid", None)
    if callable(grid):
        samples = len(grid(params, t_end))
        values = samples * max(1, len(lesson.series_for(params)))
        if values > MAX_VALUES:
            return Message(
                N_(
                    "the result would hold {values:.3g} numbers ({samples} samples of"
                    " {series} series); the limit is {limit:,}:"
                    " use a shorter {option} or a smaller family"
                ),
                values=values,
                samples=samples,
                series=len(lesson.series_for(params)),
                limit=MAX_VALUES,
                option=option,
            )
    estimate = work_estimate(setup, t_end)
    if estimate is not None and estimate > MAX_WORK:
        if math.isinf(estimate):
            return Message(
                N_(
                    "this run's first piece alone needs more than {limit:,} units of"
                    " work (counted, not timed): use a larger step or tolerance, or gentler values"
                ),
                limit=10 * PROBE_WORK,
            )
        return _too_much(estimate, Message(N_("counted on a piece of it")), option)
    return None


def _too_much(work: float, how: Message, option: str) -> Message:
    return Message(
        N_(
            "this run needs about {work:.3g} units of work ({how}); the limit"
            " is {limit:,}: use a larger step or tolerance, a shorter {option} or a smaller"
            " family"
        ),
        work=work,
        how=how,
        limit=MAX_WORK,
        option=option,
    )


def work_estimate(setup: LessonSetup, t_end: float) -> float | None:
    """Evaluations of the whole run, from those counted while the setup's stepper runs its
    first pieces (it is advanced; at most :data:`PROBE_WORK` are counted, and the model's
    build is not); None when the piece could not be run (the run itself reports why)."""
    from analyzer_lab.lessons.kit.budget import WorkLimitError, work_limit

    span = min(t_end, setup.lesson.t_end)
    piece = span / 50
    used, covered = 0.0, 0.0
    try:
        stepper = setup.stepper  # the model is built here, outside the count
        with work_limit(PROBE_WORK * 10) as count:
            while stepper.t < span - 1e-12 * max(1.0, span) and count.used < PROBE_WORK:
                before = stepper.t
                stepper.advance(min(piece, span - stepper.t))
                if stepper.t <= before:
                    break
                used, covered = count.used, stepper.t
    except WorkLimitError:  # one piece alone counted more than ten probes
        return math.inf
    except (ValueError, ArithmeticError, RuntimeError):  # the run itself reports it
        log.debug("%s: the run was not counted", setup.lesson.id, exc_info=True)
        return None
    if covered <= 0:
        return None
    return used / covered * t_end


def run_within_limit(setup: LessonSetup, t_end: float) -> RunResult:
    """The lesson's run of ``setup`` up to ``t_end``, stopped by
    :class:`~analyzer_lab.lessons.kit.budget.WorkLimitError` where it passes
    :data:`MAX_WORK` evaluations."""
    from analyzer_lab.lessons.kit.budget import work_limit

    with work_limit(MAX_WORK):
        return setup.lesson.simulate(setup.params, t_end)


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
    "LIMITS",
    "MAX_POINT_STEPS",
    "MAX_VALUES",
    "MAX_WORK",
    "PROBE_WORK",
    "first_non_finite",
    "limits_text",
    "refusal",
    "run_within_limit",
    "work_estimate",
]
