"""A live lab page from Python: ``analyzer-lab serve`` in a process of its own, shown
inline in Jupyter (an ``iframe``) and stopped by :meth:`LiveLab.stop`."""

from __future__ import annotations

import atexit
import html
import logging
import os
import re
import signal
import subprocess
import sys
import threading
import weakref
from collections import deque

from analyzer_lab.serve.headless import AnalyzerLabError

log = logging.getLogger(__name__)

#: The line ``serve`` prints when the page answers, and its instructor code line.
READY = re.compile(r"^Analyzer Lab: (?P<url>http://\S+)")
CODE = re.compile(r"^Instructor code: (?P<code>\S+)")
ERROR_PREFIX = "analyzer-lab: error: "
#: Lines of the server's output kept (:attr:`LiveLab.output`).
KEEP_LINES = 200

_running: weakref.WeakSet[LiveLab] = weakref.WeakSet()


class LiveLab:
    """A live lab page served by a background process (made by :func:`serve`).

    Attributes
    ----------
    url : str
        The page's address (loopback unless another host was asked for).
    instructor_code : str
        The code that makes a page the instructor.
    height : int
        The height in pixels of the page shown in a notebook.
    """

    def __init__(self, process: subprocess.Popen[str], height: int) -> None:
        self._process = process
        self._lines: deque[str] = deque(maxlen=KEEP_LINES)
        self._ready = threading.Event()
        self.url = ""
        self.instructor_code = ""
        self.height = int(height)
        self._reader = threading.Thread(target=self._read, name="analyzer-lab-live", daemon=True)
        self._reader.start()

    def _read(self) -> None:
        """Keep the server's output (so its pipe never fills) and find its address."""
        assert self._process.stdout is not None
        for line in self._process.stdout:
            line = line.rstrip("\n")
            self._lines.append(line)
            code = CODE.match(line)
            if code:
                self.instructor_code = code["code"]
                self._ready.set()  # printed right after the address
            ready = READY.match(line)
            if ready:
                self.url = ready["url"]
        self._ready.set()

    def _wait_ready(self, timeout: float) -> None:
        if not self._ready.wait(timeout):
            self.stop()
            raise AnalyzerLabError(f"serve: the lab did not start within {timeout:g} s")
        if not self.url:
            self._process.wait(timeout=10)
            errors = [line for line in self._lines if line.startswith(ERROR_PREFIX)]
            why = errors[-1][len(ERROR_PREFIX) :] if errors else "\n".join(self._lines)
            raise AnalyzerLabError(why or f"serve: the lab exited with {self._process.returncode}")

    @property
    def running(self) -> bool:
        """Whether the server still runs."""
        return self._process.poll() is None

    @property
    def output(self) -> list[str]:
        """The server's latest output lines."""
        return list(self._lines)

    def stop(self, timeout: float = 10.0) -> None:
        """Stop the server (as Ctrl-C stops ``analyzer-lab serve``); safe to call twice.

        Parameters
        ----------
        timeout : float
            Seconds to wait for it to stop before it is killed.
        """
        if self._process.poll() is None:
            try:
                self._process.send_signal(signal.SIGINT)
                self._process.wait(timeout)
            except subprocess.TimeoutExpired:
                log.warning("the lab at %s did not stop in %g s: killed", self.url, timeout)
                self._process.kill()
                self._process.wait(timeout)
        _running.discard(self)

    def __enter__(self) -> LiveLab:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def __repr__(self) -> str:
        state = "running" if self.running else "stopped"
        return f"LiveLab({self.url!r}, {state})"

    def _repr_html_(self) -> str:
        """The live page in an ``iframe``: Jupyter shows it inline."""
        url = html.escape(self.url, quote=True)
        return (
            f'<iframe src="{url}" width="100%" height="{self.height}"'
            ' style="border:1px solid #ddd" title="Analyzer Lab"></iframe>'
            f'<div style="font-size:0.9em">Analyzer Lab at <a href="{url}" target="_blank">'
            f"{url}</a> (<code>.stop()</code> stops it)</div>"
        )


def serve(
    lesson: str | None = None,
    *,
    port: int = 0,
    host: str = "127.0.0.1",
    instructor_code: str | None = None,
    assignments: str | os.PathLike[str] | None = None,
    fps: float = 36.0,
    height: int = 640,
    timeout: float = 120.0,
) -> LiveLab:
    """Start a live lab page (``analyzer-lab serve``) in a background process.

    In Jupyter the returned object shows the page inline; ``.stop()`` stops it, and so
    does the end of this Python process.

    Parameters
    ----------
    lesson : str, optional
        The lesson a new page shows first (default: the sphere).
    port : int
        The port to listen on; ``0``: a free one.
    host : str
        The interface to bind (default: loopback only).
    instructor_code : str, optional
        The code that makes a page the instructor (generated when ``None``; at least 12
        characters when given).
    assignments : str or path, optional
        A folder of assignment files to offer besides the ready ones.
    fps : float
        Frames per second of the live view, in 1..120.
    height : int
        The height in pixels of the page shown in a notebook.
    timeout : float
        Seconds to wait for the page to answer.

    Returns
    -------
    LiveLab
        ``url``, ``instructor_code``, ``stop()``; shown inline by Jupyter.

    Raises
    ------
    AnalyzerLabError
        With ``serve``'s one line: an unknown lesson, a bad port, fps or code, a folder
        of assignments with a bad file; or when the page does not answer in time.
    """
    command = [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser"]
    command += ["--host", str(host), "--port", str(int(port)), "--fps", repr(float(fps))]
    if lesson is not None:
        command += ["--lesson", str(lesson)]
    if assignments is not None:
        command += ["--assignments", os.fspath(assignments)]
    env = dict(os.environ)
    # the server stops when this process is gone (the watch a worker keeps on its front door)
    env["ANALYZER_LAB_FRONT_DOOR_PID"] = str(os.getpid())
    env["PYTHONUNBUFFERED"] = "1"
    if instructor_code is not None:
        env["ANALYZER_LAB_INSTRUCTOR_CODE"] = str(instructor_code)
    process = subprocess.Popen(
        command,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )
    lab = LiveLab(process, height)
    lab._wait_ready(timeout)
    _running.add(lab)
    return lab


@atexit.register
def _stop_all() -> None:
    for lab in list(_running):
        lab.stop()


__all__ = ["LiveLab", "serve"]
