"""A token bucket: a rate with a burst.

Every layer that limits what one page may do draws on it: the websocket pacing of
:mod:`analyzer_lab.viser_boundary`, the classroom's input gate and its guard on wrong
instructor codes.
"""

from __future__ import annotations

import threading
import time


class TokenBucket:
    """``rate`` tokens per second up to ``burst``; :meth:`take` spends them."""

    def __init__(self, rate: float, burst: float) -> None:
        self.rate = float(rate)
        self.burst = float(burst)
        self.tokens = float(burst)
        self.t = time.monotonic()
        self.lock = threading.Lock()

    def _refill(self, now: float) -> None:
        self.tokens = min(self.burst, self.tokens + (now - self.t) * self.rate)
        self.t = now

    def take(self, cost: float = 1.0) -> bool:
        with self.lock:
            self._refill(time.monotonic())
            if self.tokens >= cost:
                self.tokens -= cost
                return True
            return False

    def wait_time(self, cost: float = 1.0) -> float:
        """Seconds until ``cost`` tokens are there (0 if they are)."""
        with self.lock:
            self._refill(time.monotonic())
            return max(0.0, (cost - self.tokens) / self.rate) if self.rate > 0 else float("inf")


__all__ = ["TokenBucket"]
