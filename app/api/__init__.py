"""Analyzer Lab from Python: the command line's calls, returning response objects.

>>> import analyzer_lab as al
>>> run = al.run("sphere", preset="example-1.2")
>>> sorted(run.series)[:4]
['drift', 'speed', 'u1', 'u2']

:func:`lessons` lists the lessons; :func:`run` runs one (a :class:`Run`: ``t``, named
series with units, metrics, messages, the values used; ``to_pandas()``, ``to_csv()``,
``plot()``, ``show()``); :func:`runs` makes a family that plots together; :func:`check`
checks lessons against their source's claims; :func:`grade` grades an answer to an
assignment; :func:`serve` starts a live lab page. What is refused raises
:class:`AnalyzerLabError` with the command line's one line. The same validation and the
same numbers as ``analyzer-lab run`` (tested against each other). The lab's layers put
this package beside :mod:`analyzer_lab.serve`, at the top: nothing below imports it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from analyzer_lab.api.calls import ClaimCheck, LessonInfo, check, grade, lessons, run, runs
from analyzer_lab.api.live import LiveLab, serve
from analyzer_lab.api.results import Run, Runs
from analyzer_lab.api.scene import Scene
from analyzer_lab.serve.headless import AnalyzerLabError

if TYPE_CHECKING:
    from analyzer_lab.lessons.assignments import Grade


def __getattr__(name: str) -> object:
    """``Grade`` (the assignments' verdict), imported on first use."""
    if name == "Grade":
        from analyzer_lab.lessons.assignments import Grade

        return Grade
    raise AttributeError(f"module 'analyzer_lab.api' has no attribute {name!r}")


__all__ = [
    "AnalyzerLabError",
    "ClaimCheck",
    "Grade",
    "LessonInfo",
    "LiveLab",
    "Run",
    "Runs",
    "Scene",
    "check",
    "grade",
    "lessons",
    "run",
    "runs",
    "serve",
]
