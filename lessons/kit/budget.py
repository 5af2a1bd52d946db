"""A work budget for live stepping: long loops of the model stop early once it is spent.

The live view gives each session a few milliseconds of computing per frame; it sets the
budget around a stepper call with :func:`work_budget`, and the model's loops whose work
grows with the time asked for (fixed steps of a small ``h``, adaptive steps at a tight
tolerance) ask :func:`spent` between two pieces of work and return what they have.
Without a budget (a headless run, the claims) :func:`spent` is always ``False``.

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


__all__ = ["clock", "left", "spent", "work_budget"]
