"""The headless commands' work, shared by the command line and the Python API.

``analyzer-lab run`` and :func:`analyzer_lab.api.run` validate and run a lesson by
:func:`run_lesson`; ``analyzer-lab check`` and :func:`analyzer_lab.api.check` check the
source's claims by :func:`check_claim`. What either refuses is an
:class:`AnalyzerLabError` whose text is the one line the command line prints after
``analyzer-lab: error:``. Only the lesson asked for is imported (the catalog's index).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from analyzer_lab.lessons.kit.contract import Claim, Lesson, RunResult

log = logging.getLogger(__name__)

#: The longest run ``run`` accepts (lesson seconds).
MAX_T_END = 1e5


class AnalyzerLabError(Exception):
    """Refused input or a refused run: ``str(error)`` is one line naming the value and
    the limit, the same line the command line prints."""


AnalyzerLabError.__module__ = "analyzer_lab"  # its public name: ``analyzer_lab.AnalyzerLabError``


def find_lesson(lesson_id: str) -> Lesson:
    """The lesson with this id (its page alone is imported).

    Parameters
    ----------
    lesson_id : str
        The lesson's id.

    Returns
    -------
    Lesson
        The lesson.

    Raises
    ------
    AnalyzerLabError
        For an unknown id, listing the known ones.
    """
    from analyzer_lab.lessons.catalog import get_lesson

    try:
        return get_lesson(lesson_id)
    except KeyError as exc:
        raise AnalyzerLabError(str(exc.args[0])) from None


def run_lesson(
    lesson: Lesson, preset: str | None, values: Mapping[str, Any], t_end: float | None
) -> RunResult:
    """Resolve ``values`` over the preset, refuse what ``run`` refuses, simulate, and
    check every sample (see :mod:`analyzer_lab.serve.run_limits`).

    Parameters
    ----------
    lesson : Lesson
        The lesson to run.
    preset : str or None
        The preset to start from (``None``: the defaults).
    values : mapping of str to Any
        Parameter values over the preset (text as typed, or numbers).
    t_end : float or None
        The run's length (``None``: the preset's).

    Returns
    -------
    RunResult
        The finished run, every sample finite (or declared undefined there).

    Raises
    ------
    AnalyzerLabError
        For a bad value, a refused run or a result that is not finite somewhere.
    """
    import warnings

    import numpy as np
    from analyzer_lab.lessons.kit.contract import ParamError
    from analyzer_lab.serve.run_limits import (
        first_non_finite,
        may_be_undefined,
        refusal,
        run_within_limit,
    )

    try:
        setup = lesson.open(values, preset)
    except (ParamError, ValueError) as exc:
        # the refusal as it is (a message the command line shows in its language)
        raise AnalyzerLabError(exc.args[0] if exc.args else str(exc)) from None
    t_end = setup.t_end if t_end is None else t_end
    if not math.isfinite(t_end) or t_end <= 0 or t_end > MAX_T_END:
        raise AnalyzerLabError(f"--t-end must be a finite number in (0, 1e5], got {t_end}")
    # overflow and tolerance warnings are summed up in one line below, not printed
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        why = refusal(setup, t_end)
        if why is not None:
            raise AnalyzerLabError(why)
        try:
            result = run_within_limit(setup, t_end)
        except (ParamError, ValueError, ArithmeticError, RuntimeError) as exc:
            raise AnalyzerLabError(str(exc)) from None
    bad = first_non_finite(result, may_be_undefined(setup))
    if bad is not None:
        name, at = bad
        raise AnalyzerLabError(
            f"{name} is not finite (NaN or infinite) from t = {at:.6g} s on:"
            " the run is not defined there (shorten --t-end or change the values)"
        )
    result.preset = preset
    return result


def claim_jobs(lessons: Sequence[Lesson]) -> list[tuple[Lesson, Claim]]:
    """Every claim of these lessons, in order.

    Parameters
    ----------
    lessons : sequence of Lesson
        The lessons to check.

    Returns
    -------
    list of (Lesson, Claim)
        Each claim with its lesson.
    """
    return [(lesson, claim) for lesson in lessons for claim in lesson.claims()]


def check_claim(lesson: Lesson, claim: Claim) -> dict[str, Any]:
    """One claim computed and compared.

    Parameters
    ----------
    lesson : Lesson
        The claim's lesson.
    claim : Claim
        The claim.

    Returns
    -------
    dict
        The row ``analyzer-lab check --json`` prints: ``lesson``, ``claim``,
        ``statement``, ``source``, ``expected``, ``got``, ``pass``. A claim that raises is
        a failed claim, reported with the exception.
    """
    try:
        res = claim.check()
        ok, expected, got = res.passed, res.expected, res.got
    except Exception as exc:  # a claim that crashes is a failed claim, reported
        log.warning("claim %s of %s raised", claim.id, lesson.id, exc_info=True)
        ok, expected, got = False, "(no exception)", f"{type(exc).__name__}: {exc}"
    return {
        "lesson": lesson.id,
        "claim": claim.id,
        "statement": claim.statement,
        "source": claim.source,
        "expected": expected,
        "got": got,
        "pass": ok,
    }


__all__ = [
    "MAX_T_END",
    "AnalyzerLabError",
    "check_claim",
    "claim_jobs",
    "find_lesson",
    "run_lesson",
]
