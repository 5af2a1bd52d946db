"""A busy machine on demand: processes that keep the CPU busy while tests run.

``ANALYZER_LAB_BUSY=N`` makes the suite run the quick subset's tests (the model, the
command line, the in-process pages; not the live servers' measured attacks and loads)
beside N processes that spin on the CPU, as a machine shared with other work would: a
test that holds only on an idle machine fails there.
"""

from __future__ import annotations

import os
import subprocess
import sys

#: The environment variable that asks for busy processes (their number).
BUSY_ENV = "ANALYZER_LAB_BUSY"

_SPIN = "while True:\n    pass\n"


def busy_count() -> int:
    """The number of busy processes asked for (0: none; a value that is not a
    non-negative integer is refused)."""
    text = os.environ.get(BUSY_ENV, "").strip()
    if not text:
        return 0
    if not text.isdigit():
        raise ValueError(f"{BUSY_ENV}={text!r}: expected a number of processes (0, 1, 2, ...)")
    return int(text)


class BusyProcesses:
    """``count`` processes that spin on the CPU while :meth:`start`-ed."""

    def __init__(self, count: int) -> None:
        self.count = count
        self._procs: list[subprocess.Popen[bytes]] = []
        self.started = 0

    @property
    def pids(self) -> list[int]:
        return [p.pid for p in self._procs]

    @property
    def running(self) -> bool:
        return bool(self._procs)

    def start(self) -> None:
        if self._procs or self.count <= 0:
            return
        self._procs = [
            subprocess.Popen([sys.executable, "-c", _SPIN], stdin=subprocess.DEVNULL)
            for _ in range(self.count)
        ]
        self.started += 1

    def stop(self) -> None:
        for p in self._procs:
            p.kill()
        for p in self._procs:
            p.wait()
        self._procs = []
