"""``python -m analyzer_lab serve`` in subprocesses on free loopback ports."""

from __future__ import annotations

import http.client
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

#: What ``serve`` prints once its lessons are loaded and it takes pages.
READY = "Analyzer Lab: http://"
#: The repository (the servers run from it).
ROOT = Path(__file__).resolve().parents[2]


def free_port() -> int:
    """A TCP port free on 127.0.0.1 now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def start_server(
    port: int,
    lesson: str,
    log: Any = subprocess.DEVNULL,
    extra_args: tuple[str, ...] = (),
    ready_within: float = 30.0,
) -> subprocess.Popen:
    """``python -m analyzer_lab serve`` (plus ``extra_args``) in a subprocess, its stderr to
    ``log``; returns when it said it is ready and its HTTP answers (polled, at most
    ``ready_within`` s; the page is served before the lessons are loaded)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("ANALYZER_LAB_STATS", "5")
    out = tempfile.TemporaryFile("w+", encoding="utf-8")
    proc = subprocess.Popen(
        [sys.executable, "-m", "analyzer_lab", "serve", "--host", "127.0.0.1"]
        + ["--port", str(port), "--no-browser", "--lesson", lesson, *extra_args],
        env=env,
        stdout=out,
        stderr=log,
        cwd=ROOT,
    )
    deadline = time.monotonic() + ready_within
    try:
        while time.monotonic() < deadline:
            out.seek(0)
            if READY in out.read():
                try:
                    urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1).read(100)
                    return proc
                except (OSError, http.client.HTTPException):
                    pass
            if proc.poll() is not None:
                raise RuntimeError(f"the server exited with code {proc.returncode}")
            time.sleep(0.1)
    finally:
        out.close()
    proc.kill()
    raise RuntimeError(f"the server was not ready within {ready_within:g} s")


def stop_process(proc: subprocess.Popen) -> None:
    """Terminate ``proc`` (killed when it does not end within 5 s)."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(5)


def start_worker(
    port: int, bus: str, name: str, code: str, log: Any, lesson: str = "sphere"
) -> subprocess.Popen:
    """``serve --bus BUS --worker-name NAME --instructor-code CODE`` (stderr to ``log``)."""
    return start_server(
        port, lesson, log, ("--bus", bus, "--worker-name", name, "--instructor-code", code)
    )


@dataclass
class ServeProcess:
    """A running ``python -m analyzer_lab serve`` and the file its stderr goes to."""

    proc: subprocess.Popen
    port: int
    log_path: Path
    log: IO[str]

    @classmethod
    def start(cls, lesson: str, flags: tuple[str, ...], log_path: Path) -> ServeProcess:
        port = free_port()
        log = open(log_path, "w", encoding="utf-8")
        try:
            proc = start_server(port, lesson, log, flags)
        except BaseException:
            log.close()
            raise
        return cls(proc, port, log_path, log)

    @property
    def url(self) -> str:
        """Where a page's websocket connects."""
        return f"ws://127.0.0.1:{self.port}/"

    @property
    def pid(self) -> int:
        return self.proc.pid

    def wait_warm(self, timeout: float = 240.0) -> None:
        """Wait until the server's loop figures say every lesson is warmed up (the
        ``warm k/n`` of its ``[loop]`` lines; ``ANALYZER_LAB_STATS`` is set): the memory a
        test measures afterwards is the class's, not the warm-up's."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            warm = re.findall(r"^\[loop\].* warm (\d+)/(\d+) ", self.log_path.read_text(), re.M)
            if warm and warm[-1][0] == warm[-1][1]:
                return
            if self.proc.poll() is not None:
                raise RuntimeError(f"the server exited with code {self.proc.returncode}")
            time.sleep(0.5)
        raise RuntimeError(f"the lessons were not warmed up within {timeout:.0f} s")

    def stop(self) -> None:
        stop_process(self.proc)
        self.log.close()
