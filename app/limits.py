"""Limits on what one page may do: the instructor code and token buckets."""

from __future__ import annotations

import hmac
import secrets
import threading
import time
from typing import Any

#: Characters of generated codes (no 0/o, 1/l/i look-alikes).
CODE_ALPHABET = "abcdefghjkmnpqrstuvwxyz23456789"
MAX_CODE_LENGTH = 64
#: Wrong codes: free tries per page, then a doubling wait (s) capped at CODE_MAX_WAIT.
CODE_FREE_TRIES = 3
CODE_MAX_WAIT = 300.0
#: Wrong codes across the whole server: a burst of 10, then one per 6 s.
CODE_GLOBAL_BURST = 10
CODE_GLOBAL_RATE = 1.0 / 6.0
#: GUI inputs per page: tokens per second and burst; a text (formula) edit costs more.
INPUT_RATE = 20.0
INPUT_BURST = 20.0
TEXT_COST = 4.0
MAX_NOTICE_LENGTH = 300


def generate_code() -> str:
    """An 8-character code, shown as ``xxxx-xxxx``."""
    raw = "".join(secrets.choice(CODE_ALPHABET) for _ in range(8))
    return f"{raw[:4]}-{raw[4:]}"


def normalize_code(text: Any) -> str:
    """Case, spaces and dashes do not matter when typing the code."""
    if not isinstance(text, str):
        return ""
    return "".join(ch for ch in text[:MAX_CODE_LENGTH].lower() if ch.isalnum())


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


class CodeGuard:
    """The instructor code: compared in constant time; wrong codes cost a page a doubling
    wait after :data:`CODE_FREE_TRIES`, and the server a bucket of wrong codes."""

    def __init__(self, code: str) -> None:
        self._norm = normalize_code(code).encode()
        self.wrong: dict[int, tuple[int, float]] = {}  # client -> (wrong count, locked until)
        self.server = TokenBucket(CODE_GLOBAL_RATE, CODE_GLOBAL_BURST)

    def forget(self, client_id: int) -> None:
        self.wrong.pop(client_id, None)

    def check(self, client_id: int, text: Any) -> tuple[bool, str]:
        """``(True, "ok")`` for the right code; else False and why (to the sender)."""
        now = time.monotonic()
        count, until = self.wrong.get(client_id, (0, 0.0))
        if now < until:
            return False, f"too many wrong codes: wait {until - now:.0f} s"
        if self.server.wait_time() > 0:
            return (
                False,
                f"too many wrong codes on this server: wait {self.server.wait_time():.0f} s",
            )
        given = normalize_code(text).encode()
        if given and hmac.compare_digest(given, self._norm):
            self.wrong.pop(client_id, None)
            return True, "ok"
        self.server.take()
        count += 1
        wait = (
            0.0
            if count < CODE_FREE_TRIES
            else min(CODE_MAX_WAIT, 2.0 ** (count - CODE_FREE_TRIES + 1))
        )
        self.wrong[client_id] = (count, now + wait)
        return False, "wrong code" + (f"; next try in {wait:.0f} s" if wait else "")
