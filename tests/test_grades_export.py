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


ATTEMPTS = [
    _a(1, 1, "circle-speed", False, 0.0),
    _a(2, 1, "circle-speed", True, 60.0),
    _a(3, 1, "sphere-equator", True, 120.0),
    _a(4, 2, "circle-speed", False, 30.0),
    _a(5, 2, "circle-speed", False, 90.0),
    _a(6, 1, "circle-speed", False, 200.0),  # after the pass: the best score stays 1
]


@pytest.mark.parametrize("fmt", FORMATS)
def test_export_matches_the_expected_file(fmt: str) -> None:
    got = export(fmt, STUDENTS, ATTEMPTS, ["circle-speed", "sphere-equator"])
    assert got == (EXPECTED / f"{fmt}.csv").read_text(encoding="utf-8")


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
