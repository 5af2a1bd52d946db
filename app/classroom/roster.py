"""The class's progress on assignments: per student (a typed name, no accounts) and
assignment, the attempts, whether it passed and the time to the first pass.

Plain bookkeeping (no viser): the instructor's live table and its CSV export are built
from it.  Names are user text: the table escapes them and the CSV defuses leading
``= + - @`` (spreadsheet formulas).
"""

from __future__ import annotations

import csv
import html
import io
import threading
import time
from dataclasses import dataclass

MAX_NAME = 40


def clean_name(text: object) -> str:
    """A student's typed name: one line, trimmed, at most :data:`MAX_NAME` characters;
    ``ValueError`` when empty."""
    if not isinstance(text, str):
        raise ValueError("type your name first")
    name = " ".join(text.split())[:MAX_NAME]
    if not name:
        raise ValueError("type your name first")
    return name


@dataclass
class Record:
    """One student's work on one assignment."""

    page: int
    name: str
    assignment: str
    opened: float
    attempts: int = 0
    passed: bool = False
    first_pass: float | None = None  # seconds from opening to the first pass
    last: str = ""  # the last verdict in words

    def row(self) -> list[str]:
        return [
            self.name,
            self.assignment,
            str(self.attempts),
            "yes" if self.passed else "no",
            "" if self.first_pass is None else f"{self.first_pass:.1f}",
        ]


HEADER = ["student", "assignment", "attempts", "passed", "seconds to first pass"]


class Roster:
    """Records by (page, assignment); thread-safe."""

    def __init__(self, clock=time.monotonic) -> None:
        self.clock = clock
        self.lock = threading.Lock()
        self.opened: dict[tuple[int, str], float] = {}
        self.records: dict[tuple[int, str], Record] = {}
        self.revision = 0

    def open(self, page: int, assignment: str, when: float | None = None) -> None:
        """A page opened an assignment (the time to first pass counts from here)."""
        with self.lock:
            self.opened.setdefault((page, assignment), self.clock() if when is None else when)

    def attempt(self, page: int, name: str, assignment: str, passed: bool, last: str) -> Record:
        """A graded attempt of a page (its name may change between attempts)."""
        now = self.clock()
        with self.lock:
            key = (page, assignment)
            opened = self.opened.setdefault(key, now)
            rec = self.records.get(key)
            if rec is None:
                rec = self.records[key] = Record(page, name, assignment, opened)
            rec.name = name
            rec.attempts += 1
            rec.last = last
            if passed and not rec.passed:
                rec.passed = True
                rec.first_pass = max(0.0, now - rec.opened)
            self.revision += 1
            return rec

    def forget_page(self, page: int) -> None:
        """A page left: its open times go (its records stay in the table)."""
        with self.lock:
            for key in [k for k in self.opened if k[0] == page and k not in self.records]:
                del self.opened[key]

    def rows(self, assignment: str | None = None) -> list[Record]:
        with self.lock:
            recs = [
                r for r in self.records.values() if assignment is None or r.assignment == assignment
            ]
        return sorted(recs, key=lambda r: (r.assignment, r.name.lower(), r.page))

    def to_csv(self, assignment: str | None = None) -> str:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(HEADER)
        for r in self.rows(assignment):
            cells = r.row()
            if cells[0][:1] in ("=", "+", "-", "@"):
                cells[0] = "'" + cells[0]
            w.writerow(cells)
        return buf.getvalue()

    def to_html(self, assignment: str | None = None) -> str:
        """The live table (every name escaped); one assignment's rows omit its column."""
        rows = self.rows(assignment)
        esc = html.escape
        keep = [0, 2, 3, 4] if assignment is not None else [0, 1, 2, 3, 4]
        short = ["student", "assignment", "attempts", "passed", "first pass [s]"]
        head = "".join(f"<th style='text-align:left;padding:2px 4px'>{short[k]}</th>" for k in keep)
        if not rows:
            body = (
                f"<tr><td colspan='{len(keep)}' style='color:#555;padding:2px 4px'>"
                "no answers checked yet</td></tr>"
            )
        else:
            body = ""
            for r in rows:
                colour = "#1b7a2e" if r.passed else "#a61b1b"
                cells = r.row()
                body += (
                    f"<tr class='al-roster-row' data-passed='{'yes' if r.passed else 'no'}'>"
                    + "".join(
                        f"<td style='padding:2px 4px{';color:' + colour if k == 3 else ''}'>"
                        f"{esc(cells[k])}</td>"
                        for k in keep
                    )
                    + "</tr>"
                )
        return (
            "<table class='al-roster' style='font-size:0.85em;border-collapse:collapse;"
            f"width:100%;word-break:break-word'><thead><tr>{head}</tr></thead>"
            f"<tbody>{body}</tbody></table>"
        )
