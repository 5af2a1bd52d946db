"""Grades out of the course record, as plain functions over plain records (no database):
Moodle's grade import CSV, Canvas's gradebook CSV and a long format.

The score rule: 1 for an assignment passed (any attempt whose every check passed), 0 for
one attempted and never passed; a student with no attempt at an assignment gets an empty
cell (ungraded) in the Moodle and Canvas files.  Text cells that a spreadsheet would read
as a formula (leading ``= + - @``) are defused with a leading apostrophe.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone

from analyzer_lab.classroom.store.records import Attempt, Student

FORMATS = ("moodle", "canvas", "long")


@dataclass(frozen=True)
class Standing:
    """One student on one assignment."""

    student: Student
    assignment: str
    score: float | None  # None: never attempted
    attempts: int
    first_pass: float | None  # epoch seconds
    last_attempt: float | None


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


def moodle_csv(
    students: Sequence[Student], table: list[Standing], assignments: Sequence[str]
) -> str:
    """Moodle's grade import: the user identifier columns (``ID number``, ``Email
    address``; map one of them at import), then one column per assignment."""
    grid = _grid(table)
    rows = [["ID number", "Email address", "Full name", *assignments]]
    for s in students:
        mine = grid.get(s.id, {})
        rows.append(
            [_cell(s.roster_id), _cell(s.email), _cell(s.name)]
            + [_score(mine[a].score) if a in mine else "" for a in assignments]
        )
    return _write(rows)


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
) -> str:
    """The class's grades in ``fmt`` (one of :data:`FORMATS`)."""
    names = list(assignments) or assignments_of(attempts)
    table = standings(students, attempts, names)
    if fmt == "moodle":
        return moodle_csv(students, table, names)
    if fmt == "canvas":
        return canvas_csv(students, table, names)
    if fmt == "long":
        return long_csv(table)
    raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {fmt[:40]!r}")


__all__ = [
    "FORMATS",
    "Standing",
    "assignments_of",
    "canvas_csv",
    "export",
    "long_csv",
    "moodle_csv",
    "standings",
]
