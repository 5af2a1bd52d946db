"""The course record in a database through SQLAlchemy Core: an SQLite file (WAL mode)
or a PostgreSQL server; the schema is brought to the newest Alembic revision on opening.

Every database failure becomes a :class:`~analyzer_lab.classroom.store.records.StoreError`
(the caller says so to the person concerned); a write is one transaction, so a failed
one leaves nothing half written.
"""

from __future__ import annotations

import logging
import math
import secrets
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import sqlalchemy as sa
from analyzer_lab.classroom.store.records import (
    Attempt,
    CheckRecord,
    ClassInfo,
    NewAttempt,
    RosterEntry,
    StoreError,
    Student,
)
from analyzer_lab.classroom.store.schema import attempts, classes, students
from sqlalchemy.pool import StaticPool

log = logging.getLogger(__name__)

MIGRATIONS = Path(__file__).resolve().parent / "migrations"
#: Letters of a generated join code (no 0/O, 1/I/L).
CODE_LETTERS = "ABCDEFGHJKMNPQRSTUVWXYZ23456789"
#: Seconds a page waits for a locked SQLite file or an unreachable server.
WAIT_SECONDS = 5


def generate_join_code(length: int = 6) -> str:
    return "".join(secrets.choice(CODE_LETTERS) for _ in range(length))


def _engine(url: str) -> sa.Engine:
    if url in ("sqlite://", "sqlite:///:memory:"):
        return sa.create_engine(
            "sqlite://", poolclass=StaticPool, connect_args={"check_same_thread": False}
        )
    if url.startswith("sqlite"):
        engine = sa.create_engine(
            url, connect_args={"timeout": WAIT_SECONDS, "check_same_thread": False}
        )

        @sa.event.listens_for(engine, "connect")
        def _pragmas(dbapi_connection: Any, record: Any) -> None:
            cur = dbapi_connection.cursor()
            cur.execute("PRAGMA journal_mode=WAL")
            cur.execute("PRAGMA synchronous=NORMAL")
            cur.execute("PRAGMA foreign_keys=ON")
            cur.close()

        return engine
    if url.startswith("postgresql://"):
        url = "postgresql+psycopg://" + url[len("postgresql://") :]
    return sa.create_engine(
        url,
        pool_pre_ping=True,
        pool_size=4,
        max_overflow=4,
        pool_timeout=WAIT_SECONDS,
        connect_args={"connect_timeout": WAIT_SECONDS},
    )


def _num(v: Any) -> float | None:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


class SqlStore:
    """The course record in one database (satisfies
    :class:`~analyzer_lab.classroom.ports.CourseStore`)."""

    def __init__(self, url: str, migrate: bool = True) -> None:
        self.url = url
        try:
            self.engine = _engine(url)
        except (sa.exc.ArgumentError, ImportError) as exc:
            raise StoreError(f"cannot use the database {redact(url)}: {exc}") from exc
        if migrate:
            self.upgrade()

    # ------------------------------------------------------------------ schema

    def upgrade(self) -> None:
        """Bring the schema to the newest revision (Alembic)."""
        from alembic import command
        from alembic.config import Config

        cfg = Config()
        cfg.set_main_option("script_location", str(MIGRATIONS))
        try:
            with self.engine.begin() as conn:
                cfg.attributes["connection"] = conn
                command.upgrade(cfg, "head")
        except sa.exc.SQLAlchemyError as exc:
            raise StoreError(
                f"cannot open the course record {redact(self.url)}: {_why(exc)}"
            ) from exc

    def revision(self) -> str | None:
        """The schema's Alembic revision."""
        with self._connect() as conn:
            return conn.execute(sa.text("SELECT version_num FROM alembic_version")).scalar()

    def close(self) -> None:
        self.engine.dispose()

    # ------------------------------------------------------------------ plumbing

    def _connect(self) -> Any:
        return _Guard(self, self.engine.connect)

    def _begin(self) -> Any:
        return _Guard(self, self.engine.begin)

    def ping(self) -> None:
        """Raise :class:`StoreError` unless the database answers."""
        with self._connect() as conn:
            conn.execute(sa.text("SELECT 1"))

    # ------------------------------------------------------------------ classes

    def get_class(self, name: str) -> ClassInfo | None:
        with self._connect() as conn:
            row = conn.execute(sa.select(classes).where(classes.c.name == name)).first()
        return None if row is None else _class(row)

    def open_class(
        self,
        name: str,
        roster: Sequence[RosterEntry] | None = None,
        join_code: str | None = None,
        code_lifetime: float | None = None,
    ) -> ClassInfo:
        """The class ``name``, made if new; a roster adds its students (a known roster id
        gets the row's name, email and group) and closes the class to everyone else.  A
        join code or a ``code_lifetime`` (seconds) given sets when the code expires: that
        long from now, or never when no lifetime is given; given neither, the code and its
        expiry stay.  One transaction: on any failure nothing changes."""
        now = time.time()
        expires = None if code_lifetime is None else now + float(code_lifetime)
        with self._begin() as conn:
            row = conn.execute(sa.select(classes).where(classes.c.name == name)).first()
            if row is None:
                conn.execute(
                    sa.insert(classes).values(
                        name=name,
                        join_code=join_code or generate_join_code(),
                        join_code_expires=expires,
                        closed=bool(roster),
                        created=now,
                    )
                )
            else:
                changes: dict[str, Any] = {}
                if join_code and join_code != row.join_code:
                    changes["join_code"] = join_code
                if (join_code or code_lifetime is not None) and expires != row.join_code_expires:
                    changes["join_code_expires"] = expires
                if roster and not row.closed:
                    changes["closed"] = True
                if changes:
                    conn.execute(sa.update(classes).where(classes.c.id == row.id).values(**changes))
            info = _class(conn.execute(sa.select(classes).where(classes.c.name == name)).one())
            if roster:
                known = {
                    r.roster_id: r.id
                    for r in conn.execute(
                        sa.select(students.c.id, students.c.roster_id).where(
                            students.c.class_id == info.id, students.c.roster_id != ""
                        )
                    )
                }
                for e in roster:
                    values = {"name": e.name, "email": e.email, "group": e.group}
                    if e.roster_id in known:
                        conn.execute(
                            sa.update(students)
                            .where(students.c.id == known[e.roster_id])
                            .values(**values)
                        )
                    else:
                        conn.execute(
                            sa.insert(students).values(
                                class_id=info.id, roster_id=e.roster_id, **values
                            )
                        )
        return info

    # ------------------------------------------------------------------ students

    def students(self, class_id: int) -> list[Student]:
        with self._connect() as conn:
            rows = conn.execute(
                sa.select(students).where(students.c.class_id == class_id).order_by(students.c.id)
            ).all()
        return [_student(r) for r in rows]

    def student(self, student_id: int) -> Student | None:
        with self._connect() as conn:
            row = conn.execute(sa.select(students).where(students.c.id == student_id)).first()
        return None if row is None else _student(row)

    def find_roster(self, class_id: int, roster_id: str) -> Student | None:
        with self._connect() as conn:
            row = conn.execute(
                sa.select(students).where(
                    students.c.class_id == class_id, students.c.roster_id == roster_id
                )
            ).first()
        return None if row is None else _student(row)

    def find_name(self, class_id: int, name: str) -> list[Student]:
        """The class's roster students called ``name`` (case-insensitive)."""
        with self._connect() as conn:
            rows = conn.execute(
                sa.select(students).where(
                    students.c.class_id == class_id,
                    students.c.roster_id != "",
                    sa.func.lower(students.c.name) == name.lower(),
                )
            ).all()
        return [_student(r) for r in rows]

    def enrol(self, class_id: int, name: str) -> Student:
        """A new student by name (open enrolment): two with one name are two students."""
        with self._begin() as conn:
            sid = conn.execute(
                sa.insert(students)
                .values(
                    class_id=class_id,
                    roster_id="",
                    name=name,
                    email="",
                    group="",
                    joined=time.time(),
                )
                .returning(students.c.id)
            ).scalar_one()
        student = self.student(int(sid))
        assert student is not None
        return student

    def claim(self, student_id: int) -> bool:
        """Mark a roster student as joined; False when a page already joined as them."""
        with self._begin() as conn:
            done = conn.execute(
                sa.update(students)
                .where(students.c.id == student_id, students.c.joined.is_(None))
                .values(joined=time.time())
            )
            return done.rowcount == 1

    # ------------------------------------------------------------------ attempts

    def record(self, attempt: NewAttempt) -> Attempt:
        """Write one attempt (committed when this returns)."""
        checks = [
            {
                "id": c.id,
                "passed": bool(c.passed),
                "measured": _num(c.measured),
                "miss": _num(c.miss),
            }
            for c in attempt.checks
        ]
        with self._begin() as conn:
            aid = conn.execute(
                sa.insert(attempts)
                .values(
                    student_id=attempt.student_id,
                    assignment=attempt.assignment,
                    variant=attempt.variant,
                    submitted=_jsonable(attempt.values),
                    checks=checks,
                    passed=bool(attempt.passed),
                    at=float(attempt.at),
                )
                .returning(attempts.c.id)
            ).scalar_one()
        return Attempt(
            int(aid),
            attempt.student_id,
            attempt.assignment,
            attempt.variant,
            _jsonable(attempt.values),
            tuple(CheckRecord(c["id"], c["passed"], c["measured"], c["miss"]) for c in checks),
            bool(attempt.passed),
            float(attempt.at),
        )

    def attempts(self, class_id: int, after: int = 0) -> list[Attempt]:
        """The class's attempts with an id above ``after``, oldest first."""
        with self._connect() as conn:
            rows = conn.execute(
                sa.select(attempts)
                .join(students, students.c.id == attempts.c.student_id)
                .where(students.c.class_id == class_id, attempts.c.id > after)
                .order_by(attempts.c.id)
            ).all()
        return [_attempt(r) for r in rows]


class _Guard:
    """A connection whose database errors come out as :class:`StoreError`."""

    def __init__(self, store: SqlStore, open_: Any) -> None:
        self.store, self.open_, self.cm = store, open_, None

    def __enter__(self) -> Any:
        try:
            self.cm = self.open_()
            return self.cm.__enter__()
        except sa.exc.SQLAlchemyError as exc:
            raise StoreError(_why(exc)) from exc

    def __exit__(self, kind: Any, exc: Any, tb: Any) -> bool:
        assert self.cm is not None
        try:
            self.cm.__exit__(kind, exc, tb)
        except sa.exc.SQLAlchemyError as err:
            raise StoreError(_why(err)) from err
        if isinstance(exc, sa.exc.SQLAlchemyError):
            raise StoreError(_why(exc)) from exc
        return False


#: PostgreSQL's SQLSTATE for a disk that is full.
PG_DISK_FULL = "53100"


def is_full(exc: BaseException) -> bool:
    """True when the database refused a write because it, or its disk, is full."""
    orig = getattr(exc, "orig", None) or exc
    if getattr(orig, "sqlite_errorname", "") == "SQLITE_FULL":
        return True
    if getattr(orig, "sqlstate", "") == PG_DISK_FULL:
        return True
    text = str(orig).lower()
    return "database or disk is full" in text or "no space left on device" in text


def _why(exc: BaseException) -> str:
    orig = getattr(exc, "orig", None)
    text = str(orig if orig is not None else exc).strip().splitlines()
    detail = text[0][:200] if text else type(exc).__name__
    if is_full(exc):
        return f"the course record is full ({detail}): the instructor must free space on its disk"
    return f"the course record is unreachable or refused the write ({detail})"


def redact(url: str) -> str:
    """``url`` without its password."""
    try:
        return sa.engine.make_url(url).render_as_string(hide_password=True)
    except sa.exc.ArgumentError:
        return "(an unreadable database URL)"


def _jsonable(values: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in values.items():
        if isinstance(v, bool) or v is None or isinstance(v, str):
            out[str(k)] = v
        elif isinstance(v, (int, float)):
            out[str(k)] = v if math.isfinite(float(v)) else str(v)
        else:
            out[str(k)] = str(v)[:200]
    return out


def _class(row: Any) -> ClassInfo:
    expires = row.join_code_expires
    return ClassInfo(
        int(row.id),
        row.name,
        row.join_code,
        bool(row.closed),
        None if expires is None else float(expires),
    )


def _student(row: Any) -> Student:
    return Student(int(row.id), int(row.class_id), row.roster_id, row.name, row.email, row.group)


def _attempt(row: Any) -> Attempt:
    return Attempt(
        int(row.id),
        int(row.student_id),
        row.assignment,
        row.variant,
        dict(row.submitted),
        tuple(
            CheckRecord(str(c["id"]), bool(c["passed"]), c.get("measured"), c.get("miss"))
            for c in row.checks
        ),
        bool(row.passed),
        float(row.at),
    )


__all__ = ["SqlStore", "generate_join_code", "is_full", "redact"]
