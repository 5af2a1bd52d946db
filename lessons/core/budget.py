"""A work budget for live stepping: long loops of the model stop early once it is spent.

The live view gives each session a few milliseconds of computing per frame; it sets the
budget around a stepper call with :func:`work_budget`, and the model's loops whose work
grows with the time asked for (fixed steps of a small ``h``, adaptive steps at a tight
tolerance) ask :func:`spent` between two pieces of work and return what they have.
Without a budget (a headless run, the claims) :func:`spent` is always ``False``.

The clock is the thread's CPU time: another process loading the machine does not spend
a session's budget.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

_local = threading.local()


def clock() -> float:
    """CPU seconds of the calling thread."""
    return time.thread_time()


@contextmanager
def work_budget(seconds: float) -> Iterator[None]:
    """Within the block, :func:`spent` turns ``True`` after ``seconds`` of this thread's
    CPU time (nested budgets: the earlier deadline holds)."""
    previous = getattr(_local, "deadline", None)
    deadline = clock() + max(float(seconds), 0.0)
    _local.deadline = deadline if previous is None else min(previous, deadline)
    try:
        yield
    finally:
        _local.deadline = previous


def spent() -> bool:
    """Whether the calling thread's current budget is used up (never without one)."""
    deadline = getattr(_local, "deadline", None)
    return deadline is not None and clock() >= deadline


__all__ = ["clock", "spent", "work_budget"]
