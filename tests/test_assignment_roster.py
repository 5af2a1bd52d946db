"""The class's progress table folded from the course record: attempts, first pass,
escaping and the CSV."""

from __future__ import annotations

import csv
import io

import pytest
from analyzer_lab.classroom.roster import Progress, clean_name, head_html, row_html
from analyzer_lab.classroom.store.records import Attempt, CheckRecord


def _attempt(aid: int, student: int, assignment: str, passed: bool, at: float) -> Attempt:
    checks = (CheckRecord("speed", passed, 10.0, 0.0 if passed else 5.0),)
    return Attempt(aid, student, assignment, "", {"u": "2"}, checks, passed, at)


def test_attempts_first_pass_and_rows() -> None:
    p = Progress()
    names = {1: "Ann", 2: "Bob"}
    new = p.fold(
        [
            _attempt(1, 1, "a", True, 110.0),
            _attempt(2, 2, "a", False, 115.0),
            _attempt(3, 2, "a", True, 145.0),
            _attempt(4, 2, "a", False, 150.0),  # a later failure keeps the pass
        ],
        names,
    )
    assert new == 4
    rows = p.rows("a")
    assert [(x.name, x.attempts, x.passed, x.first_pass) for x in rows] == [
        ("Ann", 1, True, 0.0),
        ("Bob", 3, True, 30.0),
    ]
    assert rows[1].last == "speed: miss 5"  # not: the pass came before
    assert p.rows("other") == []
    # folding again what was already read adds nothing
    assert p.fold([_attempt(4, 2, "a", False, 150.0)], names) == 0
    assert p.rows("a")[1].attempts == 3


def test_two_students_with_one_name_stay_two_rows() -> None:
    p = Progress()
    p.fold([_attempt(1, 1, "a", True, 1.0), _attempt(2, 2, "a", False, 2.0)], {1: "Ann", 2: "Ann"})
    assert [(r.student, r.name) for r in p.rows("a")] == [(1, "Ann"), (2, "Ann")]


def test_names_are_escaped_and_csv_defused() -> None:
    p = Progress()
    p.fold(
        [_attempt(1, 1, "a", False, 1.0), _attempt(2, 2, "a", True, 2.0)],
        {1: "<img src=x onerror=alert(1)>", 2: '=HYPERLINK("x")'},
    )
    page = "".join(row_html(x, "a") for x in p.rows("a"))
    assert "<img" not in page and "&lt;img src=x onerror=alert(1)&gt;" in page
    table = list(csv.reader(io.StringIO(p.to_csv("a"))))
    assert table[0] == ["student", "assignment", "attempts", "passed", "seconds to first pass"]
    names = sorted(row[0] for row in table[1:])
    assert '\'=HYPERLINK("x")' in names and "<img src=x onerror=alert(1)>" in names
    assert "no answers checked yet" in head_html("a", True)


@pytest.mark.parametrize("name", ["x;=1+1", "x;=cmd|' /C calc'!A0", "x,+1", "x|@SUM(1)", "x\t-1"])
def test_a_formula_after_any_locales_separator_is_defused(name: str) -> None:
    p = Progress()
    p.fold([_attempt(1, 1, "a", False, 1.0)], {1: name})
    text = p.to_csv("a")
    stored = next(csv.reader(io.StringIO(text.splitlines()[1])))[0]
    for delimiter in ",;|\t":  # a spreadsheet of any locale splits the line into cells
        for line in text.splitlines()[1:]:
            for cell in line.split(delimiter):
                cell = cell.strip().strip('"').strip()
                assert cell[:1] not in ("=", "+", "-", "@"), (delimiter, cell)
    assert stored.replace("'", "") == name.replace("'", "")
    assert text.splitlines()[1].startswith('"')  # every cell quoted: one cell per name


@pytest.mark.parametrize(("text", "ok"), [("  Ann   Lee ", "Ann Lee"), ("x" * 99, "x" * 40)])
def test_clean_name(text: str, ok: str) -> None:
    assert clean_name(text) == ok


@pytest.mark.parametrize("text", ["", "   ", None, 5])
def test_clean_name_refuses_empty(text: object) -> None:
    with pytest.raises(ValueError, match="type your name"):
        clean_name(text)
