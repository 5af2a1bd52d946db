"""Grades out of the course record, as plain functions over plain records (no database):
Moodle's grade import CSV, Canvas's gradebook CSV and a long format.

The score rule: 1 for an assignment passed (any attempt whose every check passed), 0 for
one attempted and never passed; a student with no attempt at an assignment gets an empty
cell (ungraded) in the Moodle and Canvas files.  Text cells that a spreadsheet would read
as a formula (leading ``= + - @``) are defused with a leading apostrophe.

Moodle's file may carry a feedback column after each assignment's, named as Moodle's own
export names one (``<assignment> (Feedback)``; at import it is mapped to "Feedback for
<assignment>"): what the student's best attempt missed, each failed check with its miss
and the author's feedback text for it.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from typing import TYPE_CHECKING

from analyzer_lab.classroom.store.records import Attempt, Student

if TYPE_CHECKING:
    from analyzer_lab.lessons.assignments import Assignment

FORMATS = ("moodle", "canvas", "long")
#: (assignment id, variant label) -> each check's feedback text for a failure, by check id
Feedback = Callable[[str, str], Mapping[str, str]]
#: The feedback cell of an assignment passed.
ALL_PASS = "all checks pass"


@dataclass(frozen=True)
class Standing:
    """One student on one assignment."""

    student: Student
    assignment: str
    score: float | None  # None: never attempted
    attempts: int
    first_pass: float | None  # epoch seconds
    last_attempt: float | None
    best: Attempt | None = None  # a passing attempt, else one with the most checks passed


def _rank(a: Attempt) -> tuple[bool, int, float, int]:
    """Better attempts rank higher: passed, then more checks passed, then the newer."""
    return (a.passed, sum(c.passed for c in a.checks), a.at, a.id)


def standings(
    students: Sequence[Student], attempts: Iterable[Attempt], assignments: Sequence[str]
) -> list[Standing]:
    """Every (student, assignment) pair, students in the given order."""
    by: dict[tuple[int, str], list[Attempt]] = {}
    for a in attempts:
        by.setdefault((a.student_id, a.assignment), []).append(a)
    out = []
    for s in students:
        for aid in assignments:
            mine = sorted(by.get((s.id, aid), []), key=lambda a: (a.at, a.id))
            passes = [a.at for a in mine if a.passed]
            out.append(
                Standing(
                    s,
                    aid,
                    None if not mine else (1.0 if passes else 0.0),
                    len(mine),
                    passes[0] if passes else None,
                    mine[-1].at if mine else None,
                    max(mine, key=_rank) if mine else None,
                )
            )
    return out


def assignments_of(attempts: Iterable[Attempt], also: Iterable[str] = ()) -> list[str]:
    """The assignments attempted (and ``also``), sorted."""
    return sorted({a.assignment for a in attempts} | set(also))


def _cell(text: str) -> str:
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


def _score(v: float | None) -> str:
    return "" if v is None else f"{v:g}"


def _when(t: float | None) -> str:
    if t is None:
        return ""
    return datetime.fromtimestamp(t, timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def _write(rows: list[list[str]]) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows(rows)
    return buf.getvalue()


def _grid(table: list[Standing]) -> dict[int, dict[str, Standing]]:
    grid: dict[int, dict[str, Standing]] = {}
    for st in table:
        grid.setdefault(st.student.id, {})[st.assignment] = st
    return grid


def feedback_column(assignment: str) -> str:
    """The header of an assignment's feedback column (as Moodle's export names it)."""
    return f"{assignment} (Feedback)"


def _miss(v: float | None) -> str:
    return "failed" if v is None else f"missed by {v:.4g}"


def feedback_text(st: Standing, feedback: Feedback) -> str:
    """What the best attempt missed: each failed check (its id and miss) with the author's
    feedback text; :data:`ALL_PASS` when it passed; empty when never attempted."""
    best = st.best
    if best is None:
        return ""
    if best.passed:
        return ALL_PASS
    texts = feedback(st.assignment, best.variant)
    parts = []
    for c in best.checks:
        if not c.passed:
            text = texts.get(c.id, "").strip()
            parts.append(f"{c.id} {_miss(c.miss)}" + (f": {text}" if text else ""))
    return "; ".join(parts) or "not passed"


def moodle_csv(
    students: Sequence[Student],
    table: list[Standing],
    assignments: Sequence[str],
    feedback: Feedback | None = None,
) -> str:
    """Moodle's grade import: the user identifier columns (``ID number``, ``Email
    address``; map one of them at import), then one column per assignment, each followed
    by its feedback column when ``feedback`` is given."""
    grid = _grid(table)
    head = ["ID number", "Email address", "Full name"]
    for a in assignments:
        head += [a, feedback_column(a)] if feedback is not None else [a]
    rows = [head]
    for s in students:
        mine = grid.get(s.id, {})
        row = [_cell(s.roster_id), _cell(s.email), _cell(s.name)]
        for a in assignments:
            st = mine.get(a)
            row.append(_score(st.score) if st is not None else "")
            if feedback is not None:
                row.append(_cell(feedback_text(st, feedback)) if st is not None else "")
        rows.append(row)
    return _write(rows)


def feedback_from(assignments: Mapping[str, Assignment]) -> Feedback:
    """Each check's feedback text from the assignment files, for the variant an attempt
    was on (its numbers in the text); an unknown assignment or variant has none."""
    from analyzer_lab.lessons.assignments.variants import variant_labelled

    cache: dict[tuple[str, str], Mapping[str, str]] = {}

    def texts(assignment: str, variant: str) -> Mapping[str, str]:
        key = (assignment, variant)
        if key not in cache:
            a = assignments.get(assignment)
            v = None if a is None else variant_labelled(a, variant)
            checks = () if v is None else v.assignment.checks
            cache[key] = {c.id: c.feedback for c in checks if c.feedback}
        return cache[key]

    return texts


def canvas_csv(
    students: Sequence[Student], table: list[Standing], assignments: Sequence[str]
) -> str:
    """Canvas's gradebook: Student, ID, SIS User ID, SIS Login ID, Section, then one
    column per assignment (ID is Canvas's own and left empty: Canvas matches the SIS User
    ID, the roster id)."""
    grid = _grid(table)
    rows = [["Student", "ID", "SIS User ID", "SIS Login ID", "Section", *assignments]]
    for s in students:
        mine = grid.get(s.id, {})
        rows.append(
            [_cell(s.name), "", _cell(s.roster_id), _cell(s.email), _cell(s.group)]
            + [_score(mine[a].score) if a in mine else "" for a in assignments]
        )
    return _write(rows)


def long_csv(table: list[Standing]) -> str:
    """One row per student and assignment: best score, attempts, first pass time and last
    attempt time (ISO 8601, UTC)."""
    rows = [
        [
            "student",
            "name",
            "assignment",
            "best score",
            "attempts",
            "first pass time",
            "last attempt time",
        ]
    ]
    for st in table:
        s = st.student
        rows.append(
            [
                _cell(s.roster_id or f"#{s.id}"),
                _cell(s.name),
                st.assignment,
                _score(st.score if st.score is not None else 0.0),
                str(st.attempts),
                _when(st.first_pass),
                _when(st.last_attempt),
            ]
        )
    return _write(rows)


def export(
    fmt: str,
    students: Sequence[Student],
    attempts: Sequence[Attempt],
    assignments: Sequence[str] = (),
    feedback: Feedback | None = None,
) -> str:
    """The class's grades in ``fmt`` (one of :data:`FORMATS`); ``feedback``: Moodle's
    feedback columns, with these texts."""
    if feedback is not None and fmt != "moodle":
        raise ValueError("feedback columns are for the moodle format only")
    names = list(assignments) or assignments_of(attempts)
    table = standings(students, attempts, names)
    if fmt == "moodle":
        return moodle_csv(students, table, names, feedback)
    if fmt == "canvas":
        return canvas_csv(students, table, names)
    if fmt == "long":
        return long_csv(table)
    raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {fmt[:40]!r}")


__all__ = [
    "ALL_PASS",
    "FORMATS",
    "Feedback",
    "Standing",
    "assignments_of",
    "canvas_csv",
    "export",
    "feedback_column",
    "feedback_from",
    "feedback_text",
    "long_csv",
    "moodle_csv",
    "standings",
]
