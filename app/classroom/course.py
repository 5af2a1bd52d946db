"""One class's course record as the pages use it: who a page is (joining with the join
code, or the signed token its browser kept), and its attempts written to the store.

The identity of a page is decided here, on the server: a page names a student only
through a token this server signed, or by joining with the class's join code (a roster
student joins once; open enrolment by name makes a new student every time).
"""

from __future__ import annotations

import hmac
import logging
import secrets
import time
from collections.abc import Sequence

from analyzer_lab.classroom.ports import CourseStore
from analyzer_lab.classroom.store import tokens
from analyzer_lab.classroom.store.records import (
    Attempt,
    CheckRecord,
    ClassInfo,
    JoinError,
    NewAttempt,
    StoreError,
    Student,
)
from analyzer_lab.lessons.assignments import Grade
from analyzer_lab.lessons.kit.message import N_, Message

log = logging.getLogger(__name__)

#: Where a page keeps its student token (its own browser storage).
TOKEN_KEY = "analyzer-lab-student"
#: What a student typing the class's code after its lifetime is told (a page that joined
#: before keeps its token, which does not expire with the code).  The refusals here are
#: :class:`Message` s: a page shows them in its language.
EXPIRED = Message(N_("this join code has expired: ask the instructor for a new one"))


class Course:
    """The class ``info`` in ``store``, tokens signed with ``secret``."""

    def __init__(self, store: CourseStore, info: ClassInfo, secret: bytes) -> None:
        self.store = store
        self.info = info
        self.secret = secret

    @classmethod
    def in_memory(cls) -> Course:
        """A class in an in-memory SQLite store, open to anyone by name (no join code):
        what a server started without a data folder records to."""
        from analyzer_lab.classroom.store.sql_store import SqlStore

        store = SqlStore("sqlite://")
        info = store.open_class("default", join_code="-")
        return cls(store, ClassInfo(info.id, info.name, "", info.closed), secrets.token_bytes(32))

    @property
    def needs_code(self) -> bool:
        return bool(self.info.join_code)

    def code_expiry(self, now: float | None = None) -> str:
        """When the join code expires, as the instructor is told it (empty: never)."""
        expires = self.info.join_code_expires
        if expires is None:
            return ""
        when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(expires))
        if self.info.code_expired(time.time() if now is None else now):
            return f" (expired {when}: give a new one with --join-code)"
        return f" (expires {when})"

    def token(self, student: Student) -> str:
        return tokens.sign(self.secret, self.info.id, student.id)

    def restore(self, token: object) -> Student:
        """The student a saved token names; :class:`JoinError` saying why not."""
        sid = tokens.verify(self.secret, token, self.info.id)
        student = self.store.student(sid)
        if student is None or student.class_id != self.info.id:
            raise JoinError(Message(N_("the saved student token names no student of this class")))
        return student

    def join(self, code: object, who: object) -> Student:
        """Join with the class's join code as ``who`` (a roster id, or a name)."""
        from analyzer_lab.classroom.roster import clean_name

        if self.needs_code:
            if not isinstance(code, str) or not code.strip():
                raise JoinError(Message(N_("type the join code the instructor gave you")))
            if not hmac.compare_digest(code.strip().upper(), self.info.join_code.upper()):
                raise JoinError(Message(N_("unknown join code: check it with the instructor")))
            if self.info.code_expired(time.time()):
                raise JoinError(EXPIRED)
        try:
            name = clean_name(who)
        except ValueError:
            raise JoinError(Message(N_("type your name first (or your student id)"))) from None
        student = self.store.find_roster(self.info.id, name)
        if student is None and self.info.closed:
            named = self.store.find_name(self.info.id, name)
            if len(named) > 1:
                raise JoinError(
                    Message(
                        N_("{count} students are called {name!r}: type your student id"),
                        count=len(named),
                        name=name,
                    )
                )
            student = named[0] if named else None
            if student is None:
                raise JoinError(
                    Message(
                        N_("{name!r} is not on this class's roster: type your student id"),
                        name=name,
                    )
                )
        if student is None:
            return self.store.enrol(self.info.id, name)
        if not self.store.claim(student.id):
            raise JoinError(
                Message(
                    N_(
                        "student {roster_id} has already joined on another page; open the lab "
                        "in the browser where you joined, or ask the instructor"
                    ),
                    roster_id=student.roster_id,
                )
            )
        return student

    def record(self, student: Student, grade: Grade, values: dict, variant: str = "") -> Attempt:
        """Write the attempt (before its page is told the verdict); :class:`StoreError`
        when it cannot be recorded."""
        return self.store.record(
            NewAttempt(
                student.id,
                grade.assignment,
                dict(values),
                tuple(CheckRecord(c.id, c.passed, c.measured, c.miss) for c in grade.checks),
                grade.passed,
                time.time(),
                variant,
            )
        )

    def students(self) -> Sequence[Student]:
        return self.store.students(self.info.id)

    def attempts(self, after: int = 0) -> list[Attempt]:
        return self.store.attempts(self.info.id, after)


__all__ = ["EXPIRED", "Course", "JoinError", "StoreError", "TOKEN_KEY"]
