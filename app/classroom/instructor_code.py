"""The instructor code: generated at start (or chosen: on the command line, in a file or
in the environment), typed in any case and spacing, compared in constant time, with
limits that slow guessing.  Every way in refuses a weak code with the same words
(:func:`code_problem`)."""

from __future__ import annotations

import hmac
import os
import secrets
import threading
import time
from typing import Any

from analyzer_lab.token_bucket import TokenBucket

#: Characters of generated codes (no 0/o, 1/l/i look-alikes).
CODE_ALPHABET = "abcdefghjkmnpqrstuvwxyz23456789"
MAX_CODE_LENGTH = 64
#: Letters/digits of a generated code (31**12 = 7.9e17 codes) and the fewest a code
#: chosen with ``--instructor-code`` may have.
CODE_LENGTH = 12
MIN_CODE_LENGTH = 12
#: Wrong codes: free tries per connection, then a doubling wait (s) capped at CODE_MAX_WAIT.
CODE_FREE_TRIES = 3
CODE_MAX_WAIT = 300.0
#: Wrong codes per network address (kept when its pages reconnect): a burst of 10, then
#: one per 6 s; past it, a page of that address that already gave a wrong code waits.
CODE_ADDRESS_BURST = 10
CODE_ADDRESS_RATE = 1.0 / 6.0
#: Addresses remembered at most (idle ones are forgotten first).
CODE_MAX_ADDRESSES = 4096
#: Where a worker (and anyone who prefers it to the command line) finds the code.
CODE_ENV = "ANALYZER_LAB_INSTRUCTOR_CODE"
#: Largest code file read (bytes).
MAX_CODE_FILE = 4096


class CodeError(ValueError):
    """An instructor code that may not be used, or a code file that cannot be read."""


def generate_code() -> str:
    """A :data:`CODE_LENGTH`-character code, shown as ``xxxx-xxxx-xxxx``."""
    raw = "".join(secrets.choice(CODE_ALPHABET) for _ in range(CODE_LENGTH))
    return "-".join(raw[k : k + 4] for k in range(0, CODE_LENGTH, 4))


def normalize_code(text: Any) -> str:
    """Case, spaces and dashes do not matter when typing the code."""
    if not isinstance(text, str):
        return ""
    return "".join(ch for ch in text[:MAX_CODE_LENGTH].lower() if ch.isalnum())


def code_problem(code: str) -> str | None:
    """Why an instructor code may not be used (too short to resist guessing), or None."""
    if len(normalize_code(code)) < MIN_CODE_LENGTH:
        return (
            f"the instructor code must have at least {MIN_CODE_LENGTH} letters or digits"
            " (a shorter one could be guessed)"
        )
    return None


def check_code_strength(code: str) -> str:
    """``code`` itself, or :class:`CodeError` saying why it may not be used."""
    problem = code_problem(code)
    if problem:
        raise CodeError(problem)
    return code


def read_code_file(path: str) -> str:
    """The code in a file (its first line; the rest is ignored); :class:`CodeError` if
    it cannot be read."""
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_CODE_FILE)
    except OSError as exc:
        raise CodeError(f"cannot read the instructor code file {path!r}: {exc.strerror}") from None
    lines = data.decode("utf-8", "replace").splitlines()
    return lines[0].strip() if lines else ""


def class_code(given: str | None = None, file: str | None = None) -> str:
    """The class's instructor code: ``--instructor-code``, else the first line of
    ``--instructor-code-file``, else :data:`CODE_ENV`, else a generated one; a weak one
    is refused (:class:`CodeError`) whichever way it came."""
    if given:
        return check_code_strength(given)
    if file:
        return check_code_strength(read_code_file(file))
    env = os.environ.get(CODE_ENV)
    if env:
        return check_code_strength(env)
    return generate_code()


class CodeGuard:
    """The instructor code, compared in constant time, with limits that slow guessing
    but never lock the right code out of a page that did not guess:

    * per connection: :data:`CODE_FREE_TRIES` wrong codes, then a doubling wait (only
      that page's own wrong codes make it wait);
    * per address: a bucket of :data:`CODE_ADDRESS_BURST` wrong codes refilled at
      :data:`CODE_ADDRESS_RATE`/s, kept across reconnects; while it is empty, a page of
      that address that gave a wrong code waits for it (a page that gave none is always
      checked, so students guessing from the instructor's address cannot refuse the
      instructor's code).

    There is no server-wide lock."""

    def __init__(self, code: str) -> None:
        self._norm = normalize_code(code).encode()
        self.wrong: dict[int, tuple[int, float]] = {}  # client -> (wrong count, locked until)
        self.addresses: dict[str, TokenBucket] = {}
        self.lock = threading.Lock()

    def forget(self, client_id: int) -> None:
        with self.lock:
            self.wrong.pop(client_id, None)

    def _address(self, address: str) -> TokenBucket:
        bucket = self.addresses.get(address)
        if bucket is None:
            if len(self.addresses) >= CODE_MAX_ADDRESSES:
                for key in [
                    k for k, b in self.addresses.items() if b.wait_time(CODE_ADDRESS_BURST) == 0
                ]:
                    del self.addresses[key]
                while len(self.addresses) >= CODE_MAX_ADDRESSES:
                    del self.addresses[next(iter(self.addresses))]
            bucket = self.addresses[address] = TokenBucket(CODE_ADDRESS_RATE, CODE_ADDRESS_BURST)
        return bucket

    def check(self, client_id: int, text: Any, address: str = "") -> tuple[bool, str]:
        """``(True, "ok")`` for the right code; else False and why (to the sender)."""
        now = time.monotonic()
        with self.lock:
            count, until = self.wrong.get(client_id, (0, 0.0))
            if now < until:
                return False, f"too many wrong codes: wait {until - now:.0f} s"
            bucket = self._address(address)
            if count and bucket.wait_time() > 0:
                wait = bucket.wait_time()
                self.wrong[client_id] = (count, now + wait)
                return False, f"too many wrong codes from your address: wait {wait:.0f} s"
            given = normalize_code(text).encode()
            if given and hmac.compare_digest(given, self._norm):
                self.wrong.pop(client_id, None)
                return True, "ok"
            bucket.take()
            count += 1
            wait = (
                0.0
                if count < CODE_FREE_TRIES
                else min(CODE_MAX_WAIT, 2.0 ** (count - CODE_FREE_TRIES + 1))
            )
            wait = max(wait, bucket.wait_time())
            self.wrong[client_id] = (count, now + wait)
        return False, "wrong code" + (f"; next try in {wait:.0f} s" if wait else "")


__all__ = [
    "CODE_ENV",
    "CodeError",
    "CodeGuard",
    "MIN_CODE_LENGTH",
    "check_code_strength",
    "class_code",
    "code_problem",
    "generate_code",
    "normalize_code",
    "read_code_file",
]
