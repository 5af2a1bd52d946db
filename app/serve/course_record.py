"""Opening the course record for ``serve``, ``grades`` and ``class``: the data folder,
the database (SQLite in the data folder unless ``--db``), the class, its roster and join
code.  What is resolved is put in the environment, so the workers of ``serve --workers
N`` open the same record."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

from analyzer_lab.classroom.course import Course
from analyzer_lab.classroom.store.location import (
    DEFAULT_CLASS,
    ENV_CLASS,
    ENV_DATA,
    ENV_DB,
    data_dir,
    database_url,
    server_secret,
)
from analyzer_lab.classroom.store.records import RosterError, StoreError
from analyzer_lab.classroom.store.roster_csv import read_roster
from analyzer_lab.classroom.store.sql_store import SqlStore, redact

MAX_CLASS_NAME = 80
#: The longest lifetime of a join code (a leap year), in hours.
MAX_CODE_HOURS = 8784.0


class CourseRecordError(ValueError):
    """The course record cannot be opened as asked (the message says why)."""


@dataclass(frozen=True)
class Where:
    """The resolved data folder, database URL and class name."""

    data: str
    db: str
    class_name: str


def resolve(data: str | None, db: str | None, class_name: str | None) -> Where:
    try:
        folder = data_dir(data)
        url = database_url(folder, db)
    except (OSError, ValueError) as exc:
        raise CourseRecordError(str(exc)) from exc
    name = (class_name or os.environ.get(ENV_CLASS) or DEFAULT_CLASS).strip()
    if not name or len(name) > MAX_CLASS_NAME or not name.isprintable():
        raise CourseRecordError(f"--class must be 1..{MAX_CLASS_NAME} printable characters")
    return Where(str(folder), url, name)


def open_course(
    where: Where,
    roster: str | None = None,
    join_code: str | None = None,
    create: bool = True,
    code_hours: float | None = None,
) -> Course:
    """The class's course record; a roster file is imported whole or not at all.
    ``code_hours``: the join code expires that many hours from now (given a code
    without it, the code never expires)."""
    entries = None
    if roster:
        try:
            entries = read_roster(roster)
        except RosterError as exc:
            raise CourseRecordError(str(exc)) from exc
    if join_code is not None:
        code = join_code.strip().upper()
        if not (4 <= len(code) <= 40 and code.isalnum() and code.isascii()):
            raise CourseRecordError("--join-code must be 4..40 letters or digits")
        join_code = code
    lifetime = None
    if code_hours is not None:
        hours = float(code_hours)
        if not (math.isfinite(hours) and 0 < hours <= MAX_CODE_HOURS):
            raise CourseRecordError(
                f"--join-code-hours must be a number of hours above 0 and at most "
                f"{MAX_CODE_HOURS:g}, got {code_hours!r}"
            )
        lifetime = hours * 3600.0
    try:
        store = SqlStore(where.db)
        if create or entries or join_code or lifetime is not None:
            info = store.open_class(where.class_name, entries, join_code, lifetime)
        else:
            found = store.get_class(where.class_name)
            if found is None:
                raise CourseRecordError(f"no class {where.class_name!r} in {redact(where.db)}")
            info = found
        secret = server_secret(Path(where.data))
    except StoreError as exc:
        raise CourseRecordError(f"{redact(where.db)}: {exc}") from exc
    except (OSError, ValueError) as exc:
        raise CourseRecordError(str(exc)) from exc
    return Course(store, info, secret)


def export_environment(where: Where) -> None:
    """The workers started from here open the same record."""
    os.environ[ENV_DATA] = where.data
    os.environ[ENV_DB] = where.db
    os.environ[ENV_CLASS] = where.class_name


__all__ = [
    "CourseRecordError",
    "Where",
    "export_environment",
    "open_course",
    "resolve",
]
