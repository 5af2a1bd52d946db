"""A class roster from a CSV file: columns student id, name, email, group (a header row
names them; ``group`` and ``email`` may be empty).  A malformed file is refused whole,
with the file, row and field named."""

from __future__ import annotations

import csv
import io
from pathlib import Path

from analyzer_lab.classroom.store.records import RosterEntry, RosterError

#: Accepted header spellings of each column.
COLUMNS = {
    "roster_id": ("student id", "student_id", "id", "id number", "sis user id"),
    "name": ("name", "full name", "student"),
    "email": ("email", "e-mail", "email address"),
    "group": ("group", "section"),
}
REQUIRED = ("roster_id", "name")
MAX_BYTES = 5_000_000
MAX_FIELD = {"roster_id": 80, "name": 120, "email": 200, "group": 80}


def parse_roster(data: bytes, source: str = "roster") -> list[RosterEntry]:
    """The roster's rows; :class:`RosterError` naming ``source``, the row and the field."""
    if len(data) > MAX_BYTES:
        raise RosterError(f"{source}: larger than {MAX_BYTES} bytes")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise RosterError(f"{source}: row {line}: not UTF-8 text (byte {exc.start})") from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        raise RosterError(f"{source}: empty file (the header row is missing)")
    header = [h.strip().lower() for h in rows[0]]
    where: dict[str, int] = {}
    for key, names in COLUMNS.items():
        for k, h in enumerate(header):
            if h in names:
                where[key] = k
                break
    for key in REQUIRED:
        if key not in where:
            raise RosterError(
                f"{source}: row 1: missing column {COLUMNS[key][0]!r} (header: {', '.join(header)[:200]})"
            )
    out: list[RosterEntry] = []
    seen: dict[str, int] = {}
    for n, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        values: dict[str, str] = {}
        for key, k in where.items():
            value = row[k].strip() if k < len(row) else ""
            if any(ord(ch) < 32 for ch in value):
                raise RosterError(
                    f"{source}: row {n}: field {COLUMNS[key][0]!r} has control characters"
                )
            if len(value) > MAX_FIELD[key]:
                raise RosterError(
                    f"{source}: row {n}: field {COLUMNS[key][0]!r} longer than {MAX_FIELD[key]}"
                )
            values[key] = value
        for key in REQUIRED:
            if not values.get(key):
                raise RosterError(f"{source}: row {n}: field {COLUMNS[key][0]!r} is empty")
        rid = values["roster_id"]
        if rid in seen:
            raise RosterError(
                f"{source}: row {n}: field 'student id': duplicate id {rid!r} (also on row {seen[rid]})"
            )
        seen[rid] = n
        out.append(
            RosterEntry(rid, values["name"], values.get("email", ""), values.get("group", ""))
        )
    if not out:
        raise RosterError(f"{source}: no students below the header row")
    return out


def read_roster(path: str | Path) -> list[RosterEntry]:
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise RosterError(f"{p}: cannot be read ({exc.strerror})") from None
    return parse_roster(data, str(p))


__all__ = ["parse_roster", "read_roster"]
