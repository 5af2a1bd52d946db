"""Analyzer Lab: programmed motion of mechatronic systems, in the browser and headless.

The model is :mod:`analyzer_lab.lessons` (numpy, scipy, sympy; it never imports the view);
the view and the command line are the other subpackages: :mod:`analyzer_lab.serve` (the
server, the front door, the command line), :mod:`analyzer_lab.session` (one page's state
and clock), :mod:`analyzer_lab.view` (what a page shows), :mod:`analyzer_lab.classroom`
(the instructor, the class and its bus) and :mod:`analyzer_lab.viser_boundary` (the one
place that reaches into viser's internals). :mod:`analyzer_lab.api` is the lab from
Python, and this package's face::

    import analyzer_lab as al

    run = al.run("sphere", preset="example-1.1")
    run.plot("v2")

The face is light: its names are imported on first use (``import analyzer_lab`` imports
no view code, no viser, no sympy). Two names are packages and calls at once:
``al.lessons`` is the model package and, called, :func:`analyzer_lab.api.lessons`;
``al.serve`` is the serving package and, called, :func:`analyzer_lab.api.serve`.
"""

from __future__ import annotations

import types
from typing import TYPE_CHECKING, Any

# the model package and the serving package (their own __init__ import nothing)
from analyzer_lab import lessons, serve

if TYPE_CHECKING:
    from analyzer_lab.api import (
        AnalyzerLabError,
        ClaimCheck,
        Grade,
        LessonInfo,
        LiveLab,
        Run,
        Runs,
        Scene,
        check,
        grade,
        run,
        runs,
    )

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
#: The names of :mod:`analyzer_lab.api` this face offers (imported on first use).
API_NAMES = frozenset(__all__) - {"lessons", "serve"}


class _CallablePackage(types.ModuleType):
    """A subpackage whose name is also a call of the API: ``analyzer_lab.lessons`` is the
    model package and ``al.lessons()`` lists the lessons; ``analyzer_lab.serve`` is the
    serving package and ``al.serve(...)`` starts a live page."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        """The API's call of this name (:func:`analyzer_lab.api.lessons`,
        :func:`analyzer_lab.api.serve`)."""
        import analyzer_lab.api as api

        return getattr(api, self.__name__.rpartition(".")[2])(*args, **kwargs)


for _package in (lessons, serve):
    _package.__class__ = _CallablePackage


def __getattr__(name: str) -> Any:
    """The API's names, imported on first use (PEP 562)."""
    if name in API_NAMES:
        import analyzer_lab.api as api

        value = getattr(api, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'analyzer_lab' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *API_NAMES})
