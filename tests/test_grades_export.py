"""Grades out: Moodle's import CSV, Canvas's gradebook CSV and the long format for a class
of 3 students and 2 assignments, compared with expected files (no database: the export
is a function over plain records)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import pytest
from analyzer_lab.classroom.store.grades import FORMATS, export, standings
from analyzer_lab.classroom.store.records import Attempt, CheckRecord, Student

EXPECTED = Path(__file__).parent / "expected" / "grades"
T0 = 1_790_000_000.0  # 2026-09-21T14:13:20Z

STUDENTS = [
    Student(1, 1, "s1", "Ann Lee", "ann@uni.example", "G1"),
    Student(2, 1, "s2", "=cmd|' /C calc'!A0", "bob@uni.example", "G2"),
    Student(3, 1, "s3", "Chen Wei", "", "G1"),
]


def _a(aid: int, student: int, assignment: str, passed: bool, dt: float) -> Attempt:
    check = CheckRecord("speed", passed, 10.0, 0.0 if passed else 5.0)
    return Attempt(aid, student, assignment, "", {"u": "2"}, (check,), passed, T0 + dt)


def _two(aid: int, student: int, equator: bool, miss: float | None, dt: float) -> Attempt:
    """An attempt at the two checks of sphere-equator (speed fails, missing by ``miss``)."""
    checks = (
        CheckRecord("equator", equator, 0.0, 0.0 if equator else 0.5),
        CheckRecord("speed", False, None, miss),
    )
    return Attempt(aid, student, "sphere-equator", "s = 2", {"u1": "1"}, checks, False, T0 + dt)


ATTEMPTS = [
    _a(1, 1, "circle-speed", False, 0.0),
    _a(2, 1, "circle-speed", True, 60.0),
    _a(3, 1, "sphere-equator", True, 120.0),
    _a(4, 2, "circle-speed", False, 30.0),
    _a(5, 2, "circle-speed", False, 90.0),
    _a(6, 1, "circle-speed", False, 200.0),  # after the pass: the best score stays 1
    _two(7, 3, True, 0.25, 40.0),  # Chen's best attempt: one of two checks passed
    _two(8, 3, False, None, 80.0),  # later, but worse
]
#: the checks' feedback texts the export is given (sphere-equator's speed check has none)
TEXTS = {
    "circle-speed": {"speed": "Which control sets the speed?"},
    "sphere-equator": {"equator": "Which control turns the point about z only?"},
}


def _texts(assignment: str, variant: str) -> dict[str, str]:
    return TEXTS.get(assignment, {})


@pytest.mark.parametrize("fmt", FORMATS)
def test_export_matches_the_expected_file(fmt: str) -> None:
    got = export(fmt, STUDENTS, ATTEMPTS, ["circle-speed", "sphere-equator"])
    assert got == (EXPECTED / f"{fmt}.csv").read_text(encoding="utf-8")


def test_moodle_with_feedback_columns_matches_the_expected_file() -> None:
    got = export("moodle", STUDENTS, ATTEMPTS, ["circle-speed", "sphere-equator"], _texts)
    assert got == (EXPECTED / "moodle-feedback.csv").read_text(encoding="utf-8")
    rows = list(csv.reader(io.StringIO(got)))
    assert rows[0] == [
        "ID number",
        "Email address",
        "Full name",
        "circle-speed",
        "circle-speed (Feedback)",
        "sphere-equator",
        "sphere-equator (Feedback)",
    ]
    # the best attempt's failed checks, their misses and texts; a pass; never attempted
    chen, bob, ann = rows[3], rows[2], rows[1]
    assert chen[6] == "speed missed by 0.25" and chen[5] == "0"
    assert bob[4] == "speed missed by 5: Which control sets the speed?"
    assert ann[4] == ann[6] == "all checks pass" and bob[6] == chen[4] == ""


def test_feedback_columns_only_in_moodle() -> None:
    with pytest.raises(ValueError, match="for the moodle format only"):
        export("canvas", STUDENTS, ATTEMPTS, feedback=_texts)


def test_feedback_texts_come_from_the_variant_the_attempt_was_on() -> None:
    from analyzer_lab.classroom.store.grades import feedback_from
    from analyzer_lab.lessons.assignments import ready_assignments

    found = {a.id: a for a in ready_assignments()}
    texts = feedback_from(found)
    turn = found["circle-quarter-turn"]
    (check,) = [c for c in turn.checks if c.feedback]
    assert "must be done in 3 s" in texts("circle-quarter-turn", "T = 3")[check.id]
    assert texts("circle-quarter-turn", "T = 99") == {}  # a variant never handed out
    assert texts("no-such-assignment", "") == {}
    assert texts("sphere-equator", "s = 2.5")["speed"].startswith("On the unit sphere")


def test_gradebook_columns_as_documented() -> None:
    canvas = list(csv.reader(io.StringIO(export("canvas", STUDENTS, ATTEMPTS))))
    assert canvas[0] == [
        "Student",
        "ID",
        "SIS User ID",
        "SIS Login ID",
        "Section",
        "circle-speed",
        "sphere-equator",
    ]
    moodle = list(csv.reader(io.StringIO(export("moodle", STUDENTS, ATTEMPTS))))
    assert moodle[0][:2] == ["ID number", "Email address"]
    assert [r[0] for r in moodle[1:]] == ["s1", "s2", "s3"]
    # a formula-like name is defused, not executed by a spreadsheet
    assert canvas[2][0].startswith("'=")


def test_the_score_rule() -> None:
    table = {
        (s.student.id, s.assignment): s
        for s in standings(STUDENTS, ATTEMPTS, ["circle-speed", "sphere-equator"])
    }
    assert table[1, "circle-speed"].score == 1.0 and table[1, "circle-speed"].attempts == 3
    assert table[1, "circle-speed"].first_pass == T0 + 60.0
    assert table[1, "circle-speed"].last_attempt == T0 + 200.0
    assert table[2, "circle-speed"].score == 0.0
    assert table[2, "sphere-equator"].score is None and table[3, "circle-speed"].attempts == 0


def test_unknown_format_is_refused() -> None:
    with pytest.raises(ValueError, match="format must be one of moodle, canvas, long"):
        export("excel", STUDENTS, ATTEMPTS)
