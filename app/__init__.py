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
no view code, no viser, no sympy). ``al.lessons`` is the model package and, called,
:func:`analyzer_lab.api.lessons`.
"""

from __future__ import annotations

import types
from typing import TYPE_CHECKING, Any

from analyzer_lab import lessons  # the model package; its own __init__ imports nothing

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
        serve,
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
API_NAMES = frozenset(__all__) - {"lessons"}


class _CallableModel(types.ModuleType):
    """The model package, callable: ``analyzer_lab.lessons()`` lists the lessons."""

    def __call__(self, *ids: str) -> list[LessonInfo]:
        """The lessons (:func:`analyzer_lab.api.lessons`)."""
        from analyzer_lab.api import lessons as listing

        return listing(*ids)


lessons.__class__ = _CallableModel


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
