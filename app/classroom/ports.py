"""The classroom's seams: what it needs of the server it runs in, and what each of its
parts needs of it.

The classroom is the lower layer: it never imports the server.  The server satisfies
:class:`Lab` and hands itself to the :class:`~analyzer_lab.classroom.room.Classroom` where
it is composed; the classroom hands itself to its parts (the class link, the instructor's
controls, the assignment board), which know it only through the protocol of their part.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

if TYPE_CHECKING:
    from collections.abc import Sequence

    from analyzer_lab.classroom.store.records import (
        Attempt,
        ClassInfo,
        NewAttempt,
        RosterEntry,
        Student,
    )
    from analyzer_lab.lessons.kit.contract import Lesson, Params
    from analyzer_lab.session.session import Session
    from analyzer_lab.view.page import SessionView

#: A camera as the followers get it: position, look-at point and up direction.
Camera = tuple[Any, ...]


@runtime_checkable
class Lab(Protocol):
    """The server, as the classroom sees it."""

    @property
    def lessons(self) -> tuple[Lesson, ...]:
        """The lessons this server offers."""
        ...

    @property
    def fps(self) -> float:
        """Frames per second of the frame loop."""
        ...

    @property
    def port(self) -> int:
        """The port the server listens on."""
        ...

    @property
    def server(self) -> Any:
        """The viser server (the pages' addresses, the queue of page callbacks)."""
        ...

    @property
    def ticks(self) -> int:
        """Frame-loop ticks so far (the clock of a demo shared by several pages)."""
        ...

    @property
    def report_interval(self) -> float:
        """Seconds between figures on stderr (0: none)."""
        ...

    def open_views(self) -> list[SessionView]:
        """The views of the pages open now."""
        ...

    def derivation_html(self, lesson: Lesson, params: Params) -> str:
        """The derivation of ``lesson`` at ``params`` as HTML, from the server's cache."""
        ...


@runtime_checkable
class RoomForLink(Protocol):
    """The classroom, as the class link (:mod:`analyzer_lab.classroom.link`) sees it."""

    @property
    def lab(self) -> Lab: ...

    @property
    def broadcaster(self) -> int | None:
        """The page whose session is the demo (``REMOTE``: another server's), or None."""
        ...

    @property
    def demo(self) -> Session | None: ...

    @property
    def wake(self) -> threading.Event:
        """Set it to have what arrived applied at once, not at the next period."""
        ...

    def local_counts(self) -> tuple[int, int]: ...

    def broadcaster_camera(self) -> Camera | None: ...

    def camera_moved(self) -> None: ...

    def new_session(self, lesson_id: str) -> Session: ...

    def show_demo(self, demo: Session, broadcaster: int) -> None: ...

    def follow_everyone(self) -> None: ...

    def release(self, note: str = "", everywhere: bool = False) -> None: ...

    def push_preset(self, lesson_id: str, preset: str, relay: bool = True) -> None: ...

    def notify_all(self, text: str, relay: bool = True) -> None: ...


@runtime_checkable
class RoomForPanels(Protocol):
    """The classroom, as the instructor panel and presenter mode
    (:mod:`analyzer_lab.classroom.instructor`) see it."""

    @property
    def broadcaster(self) -> int | None: ...

    def counts(self) -> tuple[int, int]: ...

    def start_follow(self, instructor: SessionView) -> None: ...

    def release(self, note: str = "", everywhere: bool = False) -> None: ...

    def push_preset(self, lesson_id: str, preset: str, relay: bool = True) -> None: ...

    def notify_all(self, text: str, relay: bool = True) -> None: ...

    def camera_moved(self) -> None: ...

    def project(self, view: SessionView, on: bool, show_class: bool = False) -> None: ...


@runtime_checkable
class RoomForBoard(Protocol):
    """The classroom, as the assignment board (:mod:`analyzer_lab.classroom.assignments`)
    sees it."""

    def is_instructor(self, client_id: int) -> bool: ...

    def is_following(self, client_id: int) -> bool: ...


@runtime_checkable
class CourseStore(Protocol):
    """The course record (:mod:`analyzer_lab.classroom.store`): classes, students and
    attempts, returned as plain data; every method raises
    :class:`~analyzer_lab.classroom.store.records.StoreError` when the database cannot be
    reached or refuses."""

    def ping(self) -> None: ...

    def get_class(self, name: str) -> ClassInfo | None: ...

    def open_class(
        self,
        name: str,
        roster: Sequence[RosterEntry] | None = None,
        join_code: str | None = None,
        code_lifetime: float | None = None,
    ) -> ClassInfo: ...

    def students(self, class_id: int) -> list[Student]: ...

    def student(self, student_id: int) -> Student | None: ...

    def find_roster(self, class_id: int, roster_id: str) -> Student | None: ...

    def find_name(self, class_id: int, name: str) -> list[Student]: ...

    def enrol(self, class_id: int, name: str) -> Student: ...

    def claim(self, student_id: int) -> bool: ...

    def record(self, attempt: NewAttempt) -> Attempt:
        """Write one attempt; committed when this returns."""
        ...

    def attempts(self, class_id: int, after: int = 0) -> list[Attempt]:
        """The class's attempts with an id above ``after``, oldest first."""
        ...


__all__ = ["Camera", "CourseStore", "Lab", "RoomForBoard", "RoomForLink", "RoomForPanels"]
