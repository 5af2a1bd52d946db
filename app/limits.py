"""Limits on what the server's work may take: the CPU of a long computation (an export)
and the memory it leaves behind."""

from __future__ import annotations

import time


class Pacer:
    """Spreads a long computation (an export) thin: after ``work`` seconds of the calling
    thread's CPU, :meth:`__call__` sleeps ``rest`` seconds, so the frame loop gets the
    interpreter at once instead of waiting behind it (a third of one core at most)."""

    def __init__(self, work: float = 0.004, rest: float = 0.008) -> None:
        self.work = work
        self.rest = rest
        self.t = time.thread_time()
        self.rested = 0.0

    def __call__(self) -> None:
        if time.thread_time() - self.t >= self.work:
            time.sleep(self.rest)
            self.rested += self.rest
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
