"""Assignments: a task over one lesson, an answer checked by the lesson's own model.

:mod:`~analyzer_lab.lessons.assignments.spec` is the file format and its validation,
:mod:`~analyzer_lab.lessons.assignments.grading` runs an answer and measures the checks,
:mod:`~analyzer_lab.lessons.assignments.library` loads folders and drafts assignments from a state,
:mod:`~analyzer_lab.lessons.assignments.space` declares varied quantities and their placeholders,
:mod:`~analyzer_lab.lessons.assignments.variants` draws each student's variant and checks
every variant before release.
The model side only: nothing here imports the view.
"""

from analyzer_lab.lessons.assignments.grading import CheckOutcome, Grade, grade, load_answer
from analyzer_lab.lessons.assignments.library import (
    READY_DIR,
    draft,
    load_folder,
    ready_assignments,
)
from analyzer_lab.lessons.assignments.spec import (
    FORMAT,
    VERSION,
    Assignment,
    AssignmentError,
    Check,
    load_assignment,
    parse_assignment,
)
from analyzer_lab.lessons.assignments.variants import Release, Variant, release, variant_for

__all__ = [
    "FORMAT",
    "READY_DIR",
    "VERSION",
    "Assignment",
    "AssignmentError",
    "Check",
    "CheckOutcome",
    "Grade",
    "draft",
    "grade",
    "load_answer",
    "load_assignment",
    "load_folder",
    "parse_assignment",
    "ready_assignments",
    "release",
    "variant_for",
    "Release",
    "Variant",
]
