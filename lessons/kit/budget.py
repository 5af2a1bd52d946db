"""A work budget for live stepping: long loops of the model stop early once it is spent.

The live view gives each session a few milliseconds of computing per frame; it sets the
budget around a stepper call with :func:`work_budget`, and the model's loops whose work
grows with the time asked for (fixed steps of a small ``h``, adaptive steps at a tight
tolerance) ask :func:`spent` between two pieces of work and return what they have.
Without a budget (a headless run, the claims) :func:`spent` is always ``False``.

A headless run is bounded by counts instead, the same on every machine however busy it
is: within :func:`work_limit`, the model's loops :func:`charge` what they compute (in
evaluations of one point's equations: a solver step's right-hand sides, a Gauss-Legendre
step's stages times its points, every substep) and the count past the limit raises
:class:`WorkLimitError` where it is reached.  Building a model (lambdifying, deriving)
is never charged: only stepping is.  A unit is about a microsecond of computing: each loop
charges its count times a weight known for it (a dear right-hand side, such as a
multibody model's, is declared by its lesson).

The clock is the thread's CPU time (another process loading the machine does not spend
a session's budget), and, where a wall-clock limit is given too (the live server), also
the wall time: on a busy machine a session then steps less rather than making the frame
late for every page.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

_local = threading.local()


def clock() -> float:
    """CPU seconds of the calling thread."""
    return time.thread_time()


@contextmanager
def work_budget(seconds: float, wall_seconds: float | None = None) -> Iterator[None]:
    """Within the block, :func:`spent` turns ``True`` after ``seconds`` of this thread's
    CPU time, or after ``wall_seconds`` of wall-clock time if given (a live server on a
    busy machine: time the thread waited counts too).  Nested budgets: the earlier
    deadlines hold."""
    previous = getattr(_local, "deadline", None)
    cpu = clock() + max(float(seconds), 0.0)
    wall = math.inf if wall_seconds is None else time.monotonic() + max(float(wall_seconds), 0.0)
    if previous is not None:
        cpu, wall = min(previous[0], cpu), min(previous[1], wall)
    _local.deadline = (cpu, wall)
    try:
        yield
    finally:
        _local.deadline = previous


def spent() -> bool:
    """Whether the calling thread's current budget is used up (never without one)."""
    deadline = getattr(_local, "deadline", None)
    if deadline is None:
        return False
    return clock() >= deadline[0] or time.monotonic() >= deadline[1]


def left() -> float:
    """Seconds left of the calling thread's current budget (CPU or wall, the fewer);
    infinite without one."""
    deadline = getattr(_local, "deadline", None)
    if deadline is None:
        return math.inf
    return min(deadline[0] - clock(), deadline[1] - time.monotonic())


class WorkLimitError(RuntimeError):
    """A run that computed more than its :func:`work_limit` (a count, not a time)."""

    def __init__(self, limit: float) -> None:
        super().__init__(
            f"this run needs more than {limit:,.0f} units of work (evaluations of the"
            " equations counted over its steps, substeps and points); that is the limit:"
            " use a larger step or tolerance, a shorter --t-end or a smaller family"
        )
        self.limit = limit


class _Count:
    __slots__ = ("limit", "used")

    def __init__(self, limit: float) -> None:
        self.limit, self.used = limit, 0.0


@contextmanager
def work_limit(units: float) -> Iterator[_Count]:
    """Within the block, :func:`charge` past ``units`` raises :class:`WorkLimitError`;
    the count (``.used``) is read from the object yielded.  Nested limits: the inner one
    counts, and what it counted is charged to the outer one when it ends."""
    previous = getattr(_local, "count", None)
    count = _local.count = _Count(float(units))
    try:
        yield count
    finally:
        _local.count = previous
        if previous is not None:
            previous.used += count.used


def charge(units: float) -> None:
    """Count ``units`` evaluations against the calling thread's :func:`work_limit`
    (nothing without one); raises :class:`WorkLimitError` once past it."""
    count = getattr(_local, "count", None)
    if count is None:
        return
    count.used += units
    if count.used > count.limit:
        raise WorkLimitError(count.limit)


__all__ = ["WorkLimitError", "charge", "clock", "left", "spent", "work_budget", "work_limit"]
