"""The course record's plain data: what the store returns and what the exports read."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


class StoreError(RuntimeError):
    """The store cannot be reached or refused a write: nothing was recorded."""


class RosterError(ValueError):
    """A roster file that cannot be imported (the message names the file, row and field)."""


class JoinError(ValueError):
    """A student who cannot join or act (unknown code, unknown student, forged token)."""


@dataclass(frozen=True)
class ClassInfo:
    """One class: its name, join code (and when that expires) and whether only its
    roster may join."""

    id: int
    name: str
    join_code: str
    closed: bool  # True: a roster was imported, only its students join
    join_code_expires: float | None = None  # epoch seconds; None: the code never expires

    def code_expired(self, now: float) -> bool:
        return self.join_code_expires is not None and now >= self.join_code_expires


@dataclass(frozen=True)
class RosterEntry:
    """One row of a roster file."""

    roster_id: str
    name: str
    email: str = ""
    group: str = ""


@dataclass(frozen=True)
class Student:
    """A student of a class (``roster_id`` empty for open enrolment by name)."""

    id: int
    class_id: int
    roster_id: str
    name: str
    email: str = ""
    group: str = ""


@dataclass(frozen=True)
class CheckRecord:
    """One check of one attempt: its verdict, what was measured and by how much it missed
    (None: not a finite number)."""

    id: str
    passed: bool
    measured: float | None
    miss: float | None


@dataclass(frozen=True)
class Attempt:
    """One graded answer, as written before its page was told the verdict."""

    id: int
    student_id: int
    assignment: str
    variant: str
    values: dict[str, Any]
    checks: tuple[CheckRecord, ...]
    passed: bool
    at: float  # seconds since the epoch (UTC)


@dataclass(frozen=True)
class NewAttempt:
    """An attempt to record (the store gives it its id)."""

    student_id: int
    assignment: str
    values: dict[str, Any]
    checks: tuple[CheckRecord, ...]
    passed: bool
    at: float
    variant: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


__all__ = [
    "Attempt",
    "CheckRecord",
    "ClassInfo",
    "JoinError",
    "NewAttempt",
    "RosterEntry",
    "RosterError",
    "Student",
    "StoreError",
]
