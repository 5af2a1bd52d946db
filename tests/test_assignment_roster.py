"""The class's progress table: attempts, first pass, escaping and the CSV."""

from __future__ import annotations

import csv
import io

import pytest
from analyzer_lab.classroom.roster import Roster, clean_name, head_html, row_html


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_attempts_first_pass_and_rows() -> None:
    clock = Clock()
    r = Roster(clock)
    r.open(1, "a")
    r.open(2, "a")
    clock.now = 110.0
    r.attempt(1, "Ann", "a", True, "pass")
    clock.now = 115.0
    r.attempt(2, "Bob", "a", False, "speed: miss 5")
    clock.now = 130.0
    r.attempt(2, "Bob", "a", True, "pass")
    r.attempt(2, "Bob", "a", False, "speed: miss 1")  # a later failure keeps the pass
    rows = r.rows("a")
    assert [(x.name, x.attempts, x.passed, x.first_pass) for x in rows] == [
        ("Ann", 1, True, 10.0),
        ("Bob", 3, True, 30.0),
    ]
    assert r.rows("other") == []


def test_names_are_escaped_and_csv_defused() -> None:
    r = Roster(Clock())
    r.attempt(1, "<img src=x onerror=alert(1)>", "a", False, "")
    r.attempt(2, '=HYPERLINK("x")', "a", True, "")
    page = "".join(row_html(x, "a") for x in r.rows("a"))
    assert "<img" not in page and "&lt;img src=x onerror=alert(1)&gt;" in page
    table = list(csv.reader(io.StringIO(r.to_csv("a"))))
    assert table[0] == ["student", "assignment", "attempts", "passed", "seconds to first pass"]
    names = sorted(row[0] for row in table[1:])
    assert '\'=HYPERLINK("x")' in names and "<img src=x onerror=alert(1)>" in names
    assert "no answers checked yet" in head_html("a", True)


@pytest.mark.parametrize("name", ["x;=1+1", "x;=cmd|' /C calc'!A0", "x,+1", "x|@SUM(1)", "x\t-1"])
def test_a_formula_after_any_locales_separator_is_defused(name: str) -> None:
    r = Roster(Clock())
    r.attempt(1, name, "a", False, "")
    text = r.to_csv("a")
    stored = next(csv.reader(io.StringIO(text.splitlines()[1])))[0]
    for delimiter in ",;|\t":  # a spreadsheet of any locale splits the line into cells
        for line in text.splitlines()[1:]:
            for cell in line.split(delimiter):
                cell = cell.strip().strip('"').strip()
                assert cell[:1] not in ("=", "+", "-", "@"), (delimiter, cell)
    assert stored.replace("'", "") == clean_name(name).replace("'", "")
    assert text.splitlines()[1].startswith('"')  # every cell quoted: one cell per name


@pytest.mark.parametrize(("text", "ok"), [("  Ann   Lee ", "Ann Lee"), ("x" * 99, "x" * 40)])
def test_clean_name(text: str, ok: str) -> None:
    assert clean_name(text) == ok


@pytest.mark.parametrize("text", ["", "   ", None, 5])
def test_clean_name_refuses_empty(text: object) -> None:
    with pytest.raises(ValueError, match="type your name"):
        clean_name(text)
