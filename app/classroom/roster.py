"""The class's progress on assignments: per student and assignment, the attempts,
whether it passed and the time from the first attempt to the first pass, folded from the
course record's attempts (:mod:`analyzer_lab.classroom.store`).

Plain bookkeeping (no viser): the instructor's live table and its CSV export are built
from it.  Names are user text: the table escapes them and the CSV defuses every
``= + - @`` that would start a cell (spreadsheet formulas), at the start of a text and
after a separator of any locale (``, ; | tab``), and quotes every cell.
"""

from __future__ import annotations

import csv
import html
import io
import re
import threading
import unicodedata
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from analyzer_lab.classroom.store.records import Attempt
from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.message import Message

MAX_NAME = 40
#: Longest text looked at (a name is cut to MAX_NAME after cleaning).
MAX_NAME_INPUT = 1000
#: Unicode categories removed from names: controls (NUL included), format characters
#: (direction overrides and marks such as U+202E, zero-width characters), surrogates,
#: private use and unassigned code points.
REMOVED_CATEGORIES = frozenset({"Cc", "Cf", "Cs", "Co", "Cn"})


#: A formula start: ``= + - @`` (after spaces) at the start of a cell or after a separator
#: a spreadsheet of some locale splits on (``,`` ``;`` ``|`` tab).
_FORMULA_START = re.compile(r"(^|[,;|\t])(\s*)(?=[=+\-@])")


def defuse(cell: str) -> str:
    """``cell`` with a ``'`` before every ``= + - @`` that would start a spreadsheet cell
    in some locale (``x;=1+1`` -> ``x;'=1+1``): read as text, never as a formula."""
    return _FORMULA_START.sub(lambda m: m.group(1) + m.group(2) + "'", cell)


def clean_name(text: object) -> str:
    """A student's typed name as it is stored and shown: control, format and direction
    characters removed, whitespace collapsed to single spaces, at most
    :data:`MAX_NAME` characters; ``ValueError`` when nothing is left."""
    if not isinstance(text, str):
        raise ValueError(Message(N_("type your name first")))
    text = unicodedata.normalize("NFC", text[:MAX_NAME_INPUT])
    kept = "".join(
        " " if ch.isspace() else ch
        for ch in text
        if ch.isspace() or unicodedata.category(ch) not in REMOVED_CATEGORIES
    )
    name = " ".join(kept.split())[:MAX_NAME].rstrip()
    if not name:
        raise ValueError(Message(N_("type your name first")))
    return name


@dataclass
class Record:
    """One student's work on one assignment, folded from the course record."""

    student: int
    name: str
    assignment: str
    first: float  # the first attempt's time (epoch seconds)
    attempts: int = 0
    passed: bool = False
    first_pass: float | None = None  # seconds from the first attempt to the first pass
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


def verdict_words(a: Attempt) -> str:
    if a.passed:
        return "pass"
    return "; ".join(
        f"{c.id}: miss {c.miss:.3g}" for c in a.checks if not c.passed and c.miss is not None
    )


class Progress:
    """The class's progress by (student, assignment), folded from the store's attempts
    (each read once: :meth:`fold` takes the ones after :attr:`last_id`); thread-safe."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.records: dict[tuple[int, str], Record] = {}
        self.names: dict[int, str] = {}  # student id -> name, as read from the record
        self.last_id = 0

    def fold(self, attempts: Iterable[Attempt], names: Mapping[int, str]) -> int:
        """Add attempts (oldest first); returns how many were new."""
        n = 0
        with self.lock:
            for a in attempts:
                if a.id <= self.last_id:
                    continue
                self.last_id = a.id
                n += 1
                key = (a.student_id, a.assignment)
                rec = self.records.get(key)
                if rec is None:
                    name = names.get(a.student_id, f"student #{a.student_id}")
                    rec = self.records[key] = Record(a.student_id, name, a.assignment, a.at)
                rec.attempts += 1
                rec.last = verdict_words(a)
                if a.passed and not rec.passed:
                    rec.passed = True
                    rec.first_pass = max(0.0, a.at - rec.first)
        return n

    def rows(self, assignment: str | None = None) -> list[Record]:
        with self.lock:
            recs = [
                r for r in self.records.values() if assignment is None or r.assignment == assignment
            ]
        return sorted(recs, key=lambda r: (r.assignment, r.name.lower(), r.student))

    def to_csv(self, assignment: str | None = None) -> str:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n", quoting=csv.QUOTE_ALL)
        w.writerow(HEADER)
        for r in self.rows(assignment):
            cells = r.row()
            cells[0] = defuse(cells[0])
            w.writerow(cells)
        return buf.getvalue()


#: Columns shown (indices of :meth:`Record.row`) and their widths, with and without the
#: assignment column; each row is its own table with these widths, so they line up (each
#: header word fits its column in the panel's width).
_COLUMNS = {
    True: ((0, 2, 3, 4), ("36%", "22%", "18%", "24%")),
    False: ((0, 1, 2, 3, 4), ("26%", "22%", "19%", "15%", "18%")),
}
_SHORT = [N_("student"), N_("assignment"), N_("attempts"), N_("passed"), N_("first pass [s]")]
_TABLE = (
    "<table class='al-roster' style='font-size:0.85em;border-collapse:collapse;"
    "width:100%;table-layout:fixed;word-break:break-word'>"
)


def _cols(assignment: str | None) -> tuple[tuple[int, ...], str]:
    keep, widths = _COLUMNS[assignment is not None]
    return keep, "<colgroup>" + "".join(f"<col style='width:{w}'>" for w in widths) + "</colgroup>"


def head_html(assignment: str | None, empty: bool, language: Language = ENGLISH) -> str:
    """The table's head in ``language`` (one assignment's table omits its column);
    ``empty``: with the line saying no answer was checked yet."""
    tr = language.gettext
    keep, cols = _cols(assignment)
    head = "".join(
        f"<th style='text-align:left;padding:2px 4px'>{html.escape(tr(_SHORT[k]))}</th>"
        for k in keep
    )
    none_yet = html.escape(tr("no answers checked yet"))
    body = (
        f"<tbody><tr><td colspan='{len(keep)}' style='color:#555;padding:2px 4px'>"
        f"{none_yet}</td></tr></tbody>"
        if empty
        else ""
    )
    return f"{_TABLE}{cols}<thead><tr>{head}</tr></thead>{body}</table>"


def row_html(r: Record, assignment: str | None, language: Language = ENGLISH) -> str:
    """One student's row in ``language``, alone (every cell escaped); it lines up with
    :func:`head_html`."""
    keep, cols = _cols(assignment)
    colour = "#1b7a2e" if r.passed else "#a61b1b"
    cells = r.row()
    cells[3] = language.gettext("yes") if r.passed else language.gettext("no")
    tds = "".join(
        f"<td style='padding:2px 4px{';color:' + colour if k == 3 else ''}'>"
        f"{html.escape(cells[k])}</td>"
        for k in keep
    )
    passed = "yes" if r.passed else "no"
    return f"{_TABLE}{cols}<tbody><tr class='al-roster-row' data-passed='{passed}'>{tds}</tr></tbody></table>"
