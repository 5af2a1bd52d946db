"""Limits on what the server's work may take: the CPU of a long computation (an export),
charged as it runs to the budget of the page callback it is part of, and the memory it
leaves behind."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

#: This thread's running page callback: ``charge`` charges the CPU it used since it was
#: last charged to its budget and waits while that budget is spent (set by the callback
#: executor, :class:`~analyzer_lab.viser_boundary.OrderedExecutor`).
_RUNNING = threading.local()


def charge_running() -> float:
    """Charge the CPU the page callback running on this thread used so far to its budget,
    waiting while the budget is spent (other pages' callbacks take their turn
    meanwhile); the seconds waited (0, and nothing charged, outside a page callback)."""
    charge: Callable[[], float] | None = getattr(_RUNNING, "charge", None)
    return charge() if charge is not None else 0.0


@contextmanager
def charged_by(charge: Callable[[], float]) -> Iterator[None]:
    """Within: :func:`charge_running` on this thread calls ``charge`` (a page callback
    runs)."""
    outer = getattr(_RUNNING, "charge", None)
    _RUNNING.charge = charge
    try:
        yield
    finally:
        _RUNNING.charge = outer


class Pacer:
    """Spreads a long computation (an export) thin: after ``work`` seconds of the calling
    thread's CPU, :meth:`__call__` charges them to the running page callback's budget
    (:func:`charge_running`) and rests at least ``rest`` seconds, so the frame loop gets
    the interpreter at once instead of waiting behind it (a third of one core at most,
    less when the callbacks' budget is spent)."""

    def __init__(self, work: float = 0.004, rest: float = 0.008) -> None:
        self.work = work
        self.rest = rest
        self.t = time.thread_time()
        self.rested = 0.0

    def __call__(self) -> None:
        if time.thread_time() - self.t >= self.work:
            waited = charge_running()
            if waited < self.rest:
                time.sleep(self.rest - waited)
            self.rested += max(waited, self.rest)
            self.t = time.thread_time()


def prefer_returned_memory() -> None:
    """Large buffers (>= 64 kB: export files, a long run's columns) are mapped on their own
    and given back to the system when freed (glibc otherwise raises this threshold after
    the first large free and keeps such buffers in its heap).  Linux/glibc only."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6").mallopt(-3, 64 * 1024)  # M_MMAP_THRESHOLD
    except (OSError, AttributeError):
        pass


def return_free_memory() -> bool:
    """Give the heap's free memory back to the system (after an export); False where the
    C library has no ``malloc_trim`` (not glibc), which leaves the heap as it is."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        return False
    return True
