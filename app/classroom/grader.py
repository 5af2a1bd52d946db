"""Grading off the frame loop: the class's answers are checked one after another in a
worker process of their own, in the order they were sent, each within a CPU-time limit.

A check runs the lesson's model over the whole assignment time (for the costliest
assignments, many seconds of CPU); run in the server's process it would take the
interpreter from the frame loop of every page.  Here the server only queues the answer:
a :class:`Grader` hands it to a lower-priority worker process, tells each waiting page
its place in line, and calls back with a :class:`GradeOutcome`.  Limits: one answer in
line per student, :data:`STUDENT_RATE` checks a minute per student (a burst of
:data:`STUDENT_BURST`), at most :data:`MAX_WAITING` answers waiting for the class, and
:data:`CPU_SECONDS` of CPU time per check (counted by the worker's own CPU clock, so a
busy machine does not change the verdict).
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from analyzer_lab.lessons.assignments import Assignment, AssignmentError, Grade, grade
from analyzer_lab.lessons.assignments.spec import said
from analyzer_lab.lessons.kit.message import N_, Message
from analyzer_lab.token_bucket import TokenBucket

log = logging.getLogger(__name__)

#: CPU seconds one check may use (the costliest ready assignment takes a few).
CPU_SECONDS = 60.0
#: A worker that neither answers nor uses its CPU for this many times its CPU limit of
#: wall time is stopped (a hung worker, not a slow check).
WALL_FACTOR = 5.0
#: Answers that may wait for the class; a student's checks a minute, and at once.
MAX_WAITING = 200
STUDENT_RATE = 6.0
STUDENT_BURST = 3.0
#: How much lower the worker's scheduling priority is than the server's.
NICENESS = 10

PlaceCallback = Callable[[int], None]

#: What a student is told, each a template translated where the page shows it.
STOPPING = N_("the server is stopping: check again when it is back")
STOPPED = N_("the grader stopped while checking: check again")
#: Where a refusal of a student's answer says it is.
YOUR_ANSWER = N_("your answer")


@dataclass(frozen=True)
class GradeOutcome:
    """A check's result: the grade, or why there is none (``field``: the value refused;
    ``error`` a :class:`Message` when the grader says it)."""

    grade: Grade | None
    error: str = ""
    field: str | None = None


class GraderBusy(Exception):
    """An answer not taken into the line (its :class:`Message` says why, to the student)."""


@dataclass
class _Job:
    key: str
    owner: Any
    assignment: Assignment
    values: dict[str, Any]
    on_done: Callable[[GradeOutcome], None]
    on_place: PlaceCallback


class _OverTime(Exception):
    pass


def _over_time(signum: int, frame: Any) -> None:
    raise _OverTime


def _check(job: tuple[Assignment, dict[str, Any], float]) -> tuple[str, Any, Any]:
    assignment, values, cpu_seconds = job
    signal.setitimer(signal.ITIMER_PROF, cpu_seconds)
    try:
        return ("grade", grade(assignment, values, Message(YOUR_ANSWER)), None)
    except AssignmentError as exc:  # its Message: the page shows it in its language
        return ("refused", said(exc), exc.field)
    except _OverTime:
        return ("overtime", None, None)
    except Exception as exc:  # a fault of one check: said to its student, the worker goes on
        log.exception("checking an answer of %s failed", assignment.id)
        return (
            "failed",
            Message(
                N_("the answer could not be checked ({why})"), why=f"{type(exc).__name__}: {exc}"
            ),
            None,
        )
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


def _work(conn: Any, niceness: int) -> None:
    """The worker process: grade what arrives on ``conn`` until it closes."""
    try:
        os.nice(niceness)
    except OSError:  # a platform that refuses: the same priority then
        pass
    signal.signal(signal.SIGPROF, _over_time)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the server stops its worker itself
    while True:
        try:
            job = conn.recv()
        except (EOFError, OSError):
            return
        if job is None:
            return
        try:
            result = _check(job)
        except _OverTime:  # the timer fired just as the check ended
            result = ("overtime", None, None)
        conn.send(result)


class Grader:
    """One worker process and the class's line of answers (see the module's docstring)."""

    def __init__(
        self,
        cpu_seconds: float = CPU_SECONDS,
        max_waiting: int = MAX_WAITING,
        student_rate: float = STUDENT_RATE,
        student_burst: float = STUDENT_BURST,
    ) -> None:
        self.cpu_seconds = float(cpu_seconds)
        self.max_waiting = int(max_waiting)
        self.student_rate = float(student_rate)
        self.student_burst = float(student_burst)
        self._cond = threading.Condition()
        self._waiting: deque[_Job] = deque()
        self._current: _Job | None = None
        self._buckets: dict[str, TokenBucket] = {}
        self._stopped = False
        self._proc: Any = None
        self._conn: Any = None
        self._want_worker = False
        self.stats = {"graded": 0, "refused": 0, "overtime": 0, "failed": 0, "restarts": 0}
        self._thread = threading.Thread(target=self._run, name="analyzer-lab-grader", daemon=True)
        self._thread.start()

    # -- the line

    def submit(
        self,
        key: str,
        assignment: Assignment,
        values: dict[str, Any],
        on_done: Callable[[GradeOutcome], None],
        on_place: PlaceCallback,
        owner: Any = None,
    ) -> int:
        """Put an answer of ``key`` (a student) from ``owner`` (a page) in line; returns
        its place (1: next).  :class:`GraderBusy` says why it was not taken."""
        with self._cond:
            if self._stopped:
                raise GraderBusy(Message(STOPPING))
            if self._current is not None and self._current.key == key:
                raise GraderBusy(
                    Message(N_("your previous answer is being checked: wait for its verdict"))
                )
            for k, job in enumerate(self._waiting):
                if job.key == key:
                    raise GraderBusy(
                        Message(
                            N_(
                                "your previous answer is number {place} in line: wait for its verdict"
                            ),
                            place=k + 1,
                        )
                    )
            if len(self._waiting) >= self.max_waiting:
                raise GraderBusy(
                    Message(
                        N_(
                            "{count} answers of the class are waiting to be checked: "
                            "check again in a minute"
                        ),
                        count=len(self._waiting),
                    )
                )
            bucket = self._buckets.setdefault(
                key, TokenBucket(self.student_rate / 60.0, self.student_burst)
            )
            if not bucket.take():
                raise GraderBusy(
                    Message(
                        N_("at most {rate:g} checks a minute: check again in {wait:.0f} s"),
                        rate=self.student_rate,
                        wait=bucket.wait_time(),
                    )
                )
            self._waiting.append(_Job(key, owner, assignment, dict(values), on_done, on_place))
            self._cond.notify_all()
            return len(self._waiting)

    def place(self, key: str) -> int | None:
        """0 while ``key``'s answer is being checked, its place in line, or None."""
        with self._cond:
            if self._current is not None and self._current.key == key:
                return 0
            for k, job in enumerate(self._waiting):
                if job.key == key:
                    return k + 1
        return None

    def worker_pid(self) -> int | None:
        """The worker process's id (None until it has started)."""
        proc = self._proc
        return proc.pid if proc is not None and proc.is_alive() else None

    def cancel(self, owner: Any) -> None:
        """The page ``owner`` left: its answer waiting in line goes (one being checked
        finishes)."""
        with self._cond:
            self._waiting = deque(j for j in self._waiting if j.owner != owner)

    def warm(self) -> None:
        """Start the worker now (a page opened an assignment: a check may follow)."""
        with self._cond:
            self._want_worker = True
            self._cond.notify_all()

    def close(self) -> None:
        with self._cond:
            self._stopped = True
            self._waiting.clear()
            self._cond.notify_all()
        self._thread.join(timeout=5.0)
        self._stop_worker()

    # -- the worker

    def _start_worker(self) -> None:
        ctx = multiprocessing.get_context("spawn")
        parent, child = ctx.Pipe()
        proc = ctx.Process(
            target=_work, args=(child, NICENESS), name="analyzer-lab-grader", daemon=True
        )
        proc.start()
        child.close()
        self._proc, self._conn = proc, parent

    def _stop_worker(self) -> None:
        proc, conn = self._proc, self._conn
        self._proc = self._conn = None
        if conn is not None:
            try:
                conn.send(None)
            except (OSError, ValueError):
                pass
            conn.close()
        if proc is not None:
            proc.join(timeout=2.0)
            if proc.is_alive():
                proc.kill()
                proc.join(timeout=2.0)

    def _run(self) -> None:
        while self._serve_one():
            pass

    def _serve_one(self) -> bool:
        """Wait for the next answer (or a request to start the worker) and check it;
        False once the grader is stopped.  One call per answer: the thread then waits
        holding nothing of the last one (its callbacks hold the page and its session)."""
        with self._cond:
            while not self._stopped and not self._waiting and not self._want_worker:
                self._cond.wait()
            if self._stopped:
                return False
            job = self._waiting.popleft() if self._waiting else None
            self._current = job
            self._want_worker = False
            places = [(j.on_place, k + 1) for k, j in enumerate(self._waiting)]
        try:
            if self._proc is None or not self._proc.is_alive():
                if self._proc is not None:
                    self.stats["restarts"] += 1
                    self._stop_worker()
                self._start_worker()
            if job is None:
                return True
            _tell(job.on_place, 0)
            for tell, k in places:
                _tell(tell, k)
            outcome = self._grade(job)
        except Exception as exc:  # the grader's thread goes on; the student is told
            log.exception("grading failed")
            outcome = GradeOutcome(
                None, Message(N_("the answer could not be checked ({why})"), why=str(exc))
            )
        finally:
            with self._cond:
                self._current = None
        if job is not None:
            try:
                job.on_done(outcome)
            except Exception:  # a page's own fault: logged, the line goes on
                log.exception("a page could not be told its verdict")
        return True

    def _grade(self, job: _Job) -> GradeOutcome:
        conn = self._conn
        conn.send((job.assignment, job.values, self.cpu_seconds))
        deadline = time.monotonic() + self.cpu_seconds * WALL_FACTOR + 30.0
        while not conn.poll(0.25):
            if self._stopped:
                return GradeOutcome(None, Message(STOPPING))
            if not self._proc.is_alive() or time.monotonic() > deadline:
                self.stats["failed"] += 1
                self._stop_worker()
                return GradeOutcome(None, Message(STOPPED))
        try:
            kind, value, field = conn.recv()
        except (EOFError, OSError):
            self.stats["failed"] += 1
            self._stop_worker()
            return GradeOutcome(None, Message(STOPPED))
        if kind == "grade":
            self.stats["graded"] += 1
            return GradeOutcome(value)
        if kind == "overtime":
            self.stats["overtime"] += 1
            return GradeOutcome(
                None,
                Message(
                    N_(
                        "your answer needs more than {cpu:g} s of computing to check: "
                        "a run this costly is not graded"
                    ),
                    cpu=self.cpu_seconds,
                ),
            )
        self.stats["refused" if kind == "refused" else "failed"] += 1
        # its Message as it came: the page shows it in its own language
        return GradeOutcome(None, value if isinstance(value, Message) else str(value), field)


def _tell(on_place: PlaceCallback, place: int) -> None:
    try:
        on_place(place)
    except Exception:  # a page that left while waiting
        log.exception("a page could not be told its place in line")


__all__ = ["CPU_SECONDS", "GradeOutcome", "Grader", "GraderBusy", "MAX_WAITING"]
