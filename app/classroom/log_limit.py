"""Log lines rate-limited per cause: a flood of one fault writes a few lines, then one
line now and then saying how many like it were left out (a bounded log, whatever
arrives)."""

from __future__ import annotations

import logging
import threading

from analyzer_lab.token_bucket import TokenBucket

#: Lines per cause at once, then one per LOG_EVERY seconds.
LOG_BURST = 10
LOG_EVERY = 10.0
#: Causes remembered at most (callers name their causes from a short fixed list).
MAX_CAUSES = 64


class LogLimiter:
    """``warning(cause, ...)`` writes at most :data:`LOG_BURST` lines per cause, then one
    per :data:`LOG_EVERY` s, each naming how many lines of that cause were left out."""

    def __init__(self, logger: logging.Logger, burst: int = LOG_BURST, every: float = LOG_EVERY):
        self.logger = logger
        self.burst = burst
        self.every = every
        self.lock = threading.Lock()
        self.causes: dict[str, tuple[TokenBucket, int]] = {}
        self.written = 0
        self.left_out = 0

    def admit(self, cause: str) -> int | None:
        """Whether a line of ``cause`` may be written now: ``None`` when it is over its
        rate (counted as left out), else how many of its lines were left out before."""
        with self.lock:
            bucket, skipped = self.causes.get(cause, (None, 0))
            if bucket is None:
                if len(self.causes) >= MAX_CAUSES:
                    cause = "(other causes)"
                    bucket, skipped = self.causes.get(cause, (None, 0))
                if bucket is None:
                    bucket = TokenBucket(1.0 / self.every, self.burst)
            if not bucket.take():
                self.causes[cause] = (bucket, skipped + 1)
                self.left_out += 1
                return None
            self.causes[cause] = (bucket, 0)
            self.written += 1
            return skipped

    def warning(self, cause: str, message: str, *args: object) -> bool:
        """Log ``message % args`` unless ``cause`` is over its rate; True when written."""
        skipped = self.admit(cause)
        if skipped is None:
            return False
        if skipped:
            message += left_out_text(skipped)
        self.logger.warning(message, *args)
        return True


def left_out_text(skipped: int) -> str:
    """What a line says of the lines of its cause left out before it."""
    return f" ({skipped} more like it left out of the log)" if skipped else ""


__all__ = ["LogLimiter", "left_out_text"]
