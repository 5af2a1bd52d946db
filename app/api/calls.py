"""The calls: :func:`lessons`, :func:`run`, :func:`runs`, :func:`check`, :func:`grade`.

Each goes through the command line's own path (:mod:`analyzer_lab.serve.headless`,
:mod:`analyzer_lab.serve.cli_assignments`, the assignments' grader), so the values are
validated the same way, the numbers are the same and a refusal is the same one line, raised
as :class:`~analyzer_lab.serve.headless.AnalyzerLabError`. Nothing given is evaluated as
code: formulas are parsed against the lab's whitelist.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from analyzer_lab.api.results import Run, Runs
from analyzer_lab.serve.headless import AnalyzerLabError, find_lesson

if TYPE_CHECKING:
    from analyzer_lab.lessons.assignments import Assignment, Grade
    from analyzer_lab.lessons.kit.contract import Lesson


@dataclass(frozen=True)
class LessonInfo:
    """What a lesson declares (an entry of ``analyzer-lab lessons --json``).

    Attributes
    ----------
    id : str
        The lesson's id, as :func:`run` takes it.
    title : str
        Its title.
    chapter : str
        The textbook's chapter (``"1"``, ``"2"``) or the article.
    problem : str
        The problem or section, e.g. ``"Problem 1.4"``.
    source : str
        Where it comes from, with the equations.
    params : tuple of str
        Its parameters' names (the keywords :func:`run` takes).
    presets : tuple of str
        Its textbook examples' names.
    series : dict of str to str
        Every series it observes and its unit.
    t_end : float
        The default run's length (seconds).
    declaration : dict
        Everything it declares (parameters with kinds, bounds and units, groups,
        presets with values, series with descriptions), as ``lessons --json`` prints it.
    """

    id: str
    title: str
    chapter: str
    problem: str
    source: str
    params: tuple[str, ...]
    presets: tuple[str, ...]
    series: dict[str, str]
    t_end: float
    declaration: dict[str, Any] = field(repr=False)

    @classmethod
    def of(cls, lesson: Lesson) -> LessonInfo:
        """The declaration of a lesson.

        Parameters
        ----------
        lesson : Lesson
            The lesson (from the catalog).

        Returns
        -------
        LessonInfo
            What it declares.
        """
        return cls(
            id=lesson.id,
            title=lesson.title,
            chapter=lesson.chapter,
            problem=lesson.problem,
            source=lesson.source,
            params=tuple(p.name for p in lesson.params),
            presets=tuple(p.name for p in lesson.presets),
            series={s.name: s.unit for s in lesson.series},
            t_end=float(lesson.t_end),
            declaration=lesson.describe(),
        )


def lessons(*ids: str) -> list[LessonInfo]:
    """The lessons, in the catalog's order (or those named).

    Parameters
    ----------
    *ids : str
        Lesson ids; none: every lesson.

    Returns
    -------
    list of LessonInfo
        Ids, titles, sources, parameters, presets and series with units.

    Raises
    ------
    AnalyzerLabError
        For an unknown id (the message lists the known ones).

    Examples
    --------
    >>> import analyzer_lab as al
    >>> sphere = al.lessons("sphere")[0]
    >>> sphere.problem, sphere.presets[:2]
    ('Problem 1.4', ('example-1.1', 'example-1.2'))
    >>> sphere.series["v2"]
    'units²/s²'
    """
    if ids:
        return [LessonInfo.of(find_lesson(i)) for i in ids]
    from analyzer_lab.lessons.catalog import all_lessons

    return [LessonInfo.of(lesson) for lesson in all_lessons()]


def _t_end(value: Any) -> float | None:
    """``t_end`` as a number, refused as the command line refuses ``--t-end``."""
    if value is None:
        return None
    try:
        if isinstance(value, bool):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise AnalyzerLabError(f"argument --t-end: invalid float value: {value!r}") from None


def run(
    lesson: str, /, preset: str | None = None, t_end: float | None = None, **values: Any
) -> Run:
    """Run a lesson headless: ``analyzer-lab run`` from Python.

    Parameters
    ----------
    lesson : str
        The lesson's id (:func:`lessons` lists them).
    preset : str, optional
        A textbook example to start from (default: the lesson's defaults).
    t_end : float, optional
        The run's length in seconds, in (0, 1e5] (default: the preset's).
    **values : str, float, int or bool
        Parameter values over the preset, named as in the textbook: numbers, formulas of
        ``t`` as text (``u1="sin(t)"``), choices, on/off. A name that is a Python
        keyword is passed as ``**{"lambda": 0.05}``.

    Returns
    -------
    Run
        The samples, series with units, metrics, messages and the values used.

    Raises
    ------
    AnalyzerLabError
        With the command line's one line: an unknown lesson, preset or parameter, a value
        out of its bounds or a formula outside the whitelist (naming the parameter and
        the limit), a run over the limits of ``run --help``, a result not finite
        somewhere.

    Examples
    --------
    >>> import analyzer_lab as al
    >>> run = al.run("sphere", preset="example-1.1")
    >>> float(run.t[-1]), run.units["v2"]
    (10.0, 'units²/s²')
    >>> round(float(run["v2"].max()), 9)  # |v|² of Example 1.1, constant
    50.0
    >>> al.run("sphere", u1="__import__('os')")
    Traceback (most recent call last):
      ...
    analyzer_lab.AnalyzerLabError: u1: function '__import__' is not allowed ...
    """
    page = find_lesson(lesson)
    chosen = None if preset is None else str(preset)
    length = _t_end(t_end)
    from analyzer_lab.serve.headless import run_lesson

    result = run_lesson(page, chosen, values, length)
    return Run(result, page.preset_t_end(chosen) if length is None else length, values)


def runs(items: Iterable[Run | Mapping[str, Any]]) -> Runs:
    """A family of runs, to plot together.

    Parameters
    ----------
    items : iterable of Run or mapping
        Runs, or the arguments of :func:`run` as mappings
        (``{"lesson": "sphere", "preset": "example-1.2", "u1": "t"}``).

    Returns
    -------
    Runs
        A list of :class:`Run` with ``plot()`` and ``to_pandas()``.

    Raises
    ------
    AnalyzerLabError
        As :func:`run` does, or for an item that is neither a run nor a mapping with a
        ``lesson``.

    Examples
    --------
    >>> import analyzer_lab as al
    >>> family = al.runs({"lesson": "sphere", "preset": p} for p in ("example-1.1", "example-1.2"))
    >>> [r.label for r in family]
    ['example-1.1', 'example-1.2']
    """
    out = Runs()
    for item in items:
        if isinstance(item, Run):
            out.append(item)
            continue
        if not isinstance(item, Mapping) or not isinstance(item.get("lesson"), str):
            raise AnalyzerLabError(
                "runs: each item is a Run or a mapping of run()'s arguments with a 'lesson',"
                f" got {type(item).__name__}"
            )
        args = {str(k): v for k, v in item.items()}
        name = args.pop("lesson")
        out.append(run(name, **args))
    return out


@dataclass(frozen=True)
class ClaimCheck:
    """One of the source's claims, computed and compared (a row of
    ``analyzer-lab check --json``).

    Attributes
    ----------
    lesson : str
        The lesson's id.
    claim : str
        The claim's id.
    statement : str
        What the source states.
    source : str
        Where (equation, table, figure).
    expected : str
        The source's value and the tolerance.
    got : str
        What the lesson computes.
    passed : bool
        Whether they agree.
    """

    lesson: str
    claim: str
    statement: str
    source: str
    expected: str
    got: str
    passed: bool


def check(*ids: str) -> list[ClaimCheck]:
    """Check lessons against their source's claims (``analyzer-lab check``).

    Parameters
    ----------
    *ids : str
        Lesson ids; none: every lesson.

    Returns
    -------
    list of ClaimCheck
        One per claim, in order.

    Raises
    ------
    AnalyzerLabError
        For an unknown id.

    Examples
    --------
    >>> import analyzer_lab as al
    >>> checks = al.check("sphere")
    >>> all(c.passed for c in checks), len(checks)
    (True, 8)
    """
    from analyzer_lab.serve.headless import check_claim, claim_jobs

    if ids:
        chosen = [find_lesson(i) for i in ids]
    else:
        from analyzer_lab.lessons.catalog import all_lessons

        chosen = list(all_lessons())
    out = []
    for lesson, claim in claim_jobs(chosen):
        row = check_claim(lesson, claim)
        out.append(
            ClaimCheck(
                lesson=row["lesson"],
                claim=row["claim"],
                statement=row["statement"],
                source=row["source"],
                expected=row["expected"],
                got=row["got"],
                passed=row["pass"],
            )
        )
    return out


def grade(
    assignment: str | os.PathLike[str] | Assignment,
    answer: Mapping[str, Any] | str | os.PathLike[str],
    folder: str | os.PathLike[str] | None = None,
) -> Grade:
    """Grade an answer to an assignment (``analyzer-lab grade``).

    Parameters
    ----------
    assignment : str, path or Assignment
        A ready assignment's id (``analyzer-lab assignments`` lists them), one in
        ``folder``, or an assignment file.
    answer : mapping or path
        The values of the parameters the assignment unlocks, or an answer file (one
        JSON object of them).
    folder : str or path, optional
        A folder of assignment files to look the id up in (default: the ready ones).

    Returns
    -------
    analyzer_lab.lessons.assignments.Grade
        ``passed``, and each check with what was measured, its bound and by how much it
        misses; ``to_json_dict()`` is what ``grade`` prints.

    Raises
    ------
    AnalyzerLabError
        With the command line's one line naming the file, the field and the problem (a
        locked parameter, a bad value, an unknown assignment).

    Examples
    --------
    >>> import analyzer_lab as al
    >>> al.grade("sphere-circle-plane", {"u1": "2", "u2": "2", "u3": "1"}).passed
    True
    >>> [c.id for c in al.grade("sphere-circle-plane", {"u1": "5"}).failed]
    ['plane', 'circle']
    """
    from analyzer_lab.lessons.assignments import Assignment, AssignmentError
    from analyzer_lab.lessons.assignments import grade as grade_answer
    from analyzer_lab.serve.cli_assignments import find_assignment, read_answer

    try:
        if isinstance(assignment, Assignment):
            task = assignment
        else:
            where = None if folder is None else os.fspath(folder)
            task = find_assignment(os.fspath(assignment), where)
        if isinstance(answer, Mapping):
            return grade_answer(task, dict(answer), "answer")
        values = read_answer(Path(answer), task)
        return grade_answer(task, values, os.fspath(answer))
    except AssignmentError as exc:
        raise AnalyzerLabError(str(exc)) from None


__all__ = ["ClaimCheck", "LessonInfo", "check", "grade", "lessons", "run", "runs"]
