"""``analyzer-lab serve --workers N``: N worker processes and a front door.

Each worker is ``analyzer-lab serve`` on its own port (one core each), all joined by
the class bus (``--bus redis://HOST:PORT``, :mod:`analyzer_lab.classroom.bus`) and sharing one instructor
code.  The front door listens on the main port and answers every page request with a
redirect to the least-loaded running worker; the browser then loads the page from
that worker and opens its websocket there (viser's client connects to the address
the page came from), so the front door carries no frames.

Load is the page count each worker publishes on the bus every second plus the pages
the front door sent it in the last few seconds (a page may not have connected yet when
its worker reported).  A worker that exits loses only its own
pages: the front door stops sending pages to it and starts it again on the same port.
``GET /frontdoor/status`` answers the workers' figures as JSON.
"""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
import urllib.request
from dataclasses import dataclass, field
from http.client import HTTPException
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

from analyzer_lab.classroom.bus import Message, make_bus
from analyzer_lab.classroom.instructor_code import generate_code

STATUS_PATH = "/frontdoor/status"
#: Seconds before a worker that exited is started again.
RESTART_DELAY = 1.0
#: A worker's page report older than this is not trusted (only the front door's own count).
REPORT_TIMEOUT = 5.0
#: Seconds a page sent to a worker counts as its load on top of the worker's report.
PENDING = 3.0
_HOST_RE = re.compile(r"^[A-Za-z0-9.\-]+$|^\[[0-9A-Fa-f:.]+\]$")
_URL_RE = re.compile(r"Analyzer Lab: http://[^ ]*:(\d+)/")


def _free_port(host: str) -> int:
    with socket.socket() as s:
        s.bind((host if host not in ("", "0.0.0.0", "::") else "127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Worker:
    """One worker process and what the front door knows of it."""

    index: int
    name: str
    port: int
    proc: subprocess.Popen | None = None
    ready: bool = False
    pages: int = 0
    reported: float = 0.0
    recent: list[float] = field(default_factory=list)  # when pages were sent to it
    sent: int = 0
    restarts: int = 0
    died_at: float = 0.0
    log: list[str] = field(default_factory=list)

    @property
    def alive(self) -> bool:
        return self.proc is not None and self.proc.poll() is None and self.ready

    def load(self, now: float) -> int:
        self.recent = [t for t in self.recent if now - t < PENDING]
        return self.pages + len(self.recent)

    def figures(self) -> dict[str, Any]:
        return {
            "index": self.index,
            "name": self.name,
            "port": self.port,
            "alive": self.alive,
            "pid": self.proc.pid if self.proc is not None else None,
            "pages": self.pages,
            "sent": self.sent,
            "restarts": self.restarts,
        }


class FrontDoor:
    """The worker processes, the redirecting HTTP front door and the monitor."""

    def __init__(
        self,
        host: str,
        port: int,
        workers: int,
        bus_url: str,
        code: str,
        lesson: str | None = None,
        fps: float | None = None,
        restart: bool = True,
    ) -> None:
        self.host, self.bus_url, self.code = host, bus_url, code
        self.lesson, self.fps, self.restart = lesson, fps, restart
        self.lock = threading.Lock()
        self._stop = threading.Event()
        self._rr = 0
        self.httpd = ThreadingHTTPServer((host, port), self._handler())
        self.httpd.daemon_threads = True
        self.port = int(self.httpd.server_address[1])
        self.workers = [
            Worker(k, f"worker-{k}@{self.port}", self.port + k if port else _free_port(host))
            for k in range(1, workers + 1)
        ]
        self.bus = make_bus(bus_url, code, f"front-door@{self.port}")
        self.bus.listen(self._on_message)

    # ------------------------------------------------------------------ workers

    def _spawn(self, w: Worker) -> None:
        env = dict(os.environ)
        env["ANALYZER_LAB_INSTRUCTOR_CODE"] = self.code  # not on the command line (ps)
        env["ANALYZER_LAB_FRONT_DOOR_PID"] = str(os.getpid())
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
        args = [
            sys.executable,
            "-m",
            "analyzer_lab",
            "serve",
            "--host",
            self.host,
            "--port",
            str(w.port),
        ]
        args += ["--no-browser", "--bus", self.bus_url, "--worker-name", w.name]
        if self.lesson:
            args += ["--lesson", self.lesson]
        if self.fps:
            args += ["--fps", str(self.fps)]
        w.ready, w.pages, w.recent, w.reported = False, 0, [], 0.0
        w.proc = subprocess.Popen(
            args, env=env, stdout=subprocess.PIPE, stderr=None, text=True, bufsize=1
        )
        threading.Thread(
            target=self._read_output, args=(w, w.proc), name=f"worker-{w.index}-out", daemon=True
        ).start()

    def _read_output(self, w: Worker, proc: subprocess.Popen) -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            line = line.rstrip("\n")
            m = _URL_RE.search(line)
            if m:
                w.port = int(m.group(1))
                w.ready = True
            if line.startswith("Instructor code:"):
                continue  # the front door prints it once
            print(f"[worker {w.index}] {line}", flush=True)

    def _on_message(self, msg: Message) -> None:
        if msg.kind != "count":
            return
        pages = msg.body.get("pages")
        if not isinstance(pages, int) or isinstance(pages, bool) or not 0 <= pages < 10**6:
            return
        with self.lock:
            for w in self.workers:
                if w.name == msg.sender:
                    w.pages, w.reported = pages, time.monotonic()

    def _monitor(self) -> None:
        while not self._stop.wait(0.25):
            now = time.monotonic()
            for w in self.workers:
                if w.proc is None:
                    continue
                code = w.proc.poll()
                if code is not None and not w.died_at:
                    w.died_at = now
                    w.ready = False
                    print(
                        f"analyzer-lab: worker {w.index} (port {w.port}) stopped with code {code}: "
                        f"its pages are lost; the other workers go on"
                        + ("; restarting it" if self.restart else ""),
                        flush=True,
                    )
                if w.died_at and self.restart and now - w.died_at >= RESTART_DELAY:
                    w.died_at = 0.0
                    w.restarts += 1
                    self._spawn(w)
                if w.reported and now - w.reported > REPORT_TIMEOUT:
                    w.reported, w.pages = 0.0, 0  # stale: count only what the front door sent

    def pick(self) -> Worker | None:
        """The least-loaded running worker (ties: in turn)."""
        with self.lock:
            live = [w for w in self.workers if w.alive]
            if not live:
                return None
            self._rr += 1
            n, now = len(live), time.monotonic()
            best = min(range(n), key=lambda k: (live[k].load(now), (k - self._rr) % n))
            w = live[best]
            w.recent.append(now)
            w.sent += 1
            return w

    def status(self) -> dict[str, Any]:
        return {
            "port": self.port,
            "bus": self.bus.describe(),
            "workers": [w.figures() for w in self.workers],
        }

    # ------------------------------------------------------------------ HTTP

    def _handler(self) -> type[BaseHTTPRequestHandler]:
        door = self

        class Handler(BaseHTTPRequestHandler):
            server_version = "AnalyzerLabFrontDoor"

            def log_message(self, format: str, *args: Any) -> None:
                pass

            def do_HEAD(self) -> None:
                self.do_GET()

            def do_GET(self) -> None:
                if self.path.split("?")[0] == STATUS_PATH:
                    self._answer(200, json.dumps(door.status()), "application/json")
                    return
                w = door.pick()
                if w is None:
                    self._answer(
                        503, "No worker of the lab is running; try again in a few seconds.\n"
                    )
                    return
                host = (self.headers.get("Host") or "").strip()
                host = host.rsplit(":", 1)[0] if not host.endswith("]") else host
                if not _HOST_RE.match(host):
                    host = "127.0.0.1" if door.host in ("", "0.0.0.0", "::") else door.host
                path = self.path if self.path.startswith("/") else "/"
                self.send_response(302)
                self.send_header("Location", f"http://{host}:{w.port}{path}")
                self.send_header("Cache-Control", "no-store")
                self.send_header("Content-Length", "0")
                self.end_headers()

            def _answer(self, code: int, text: str, kind: str = "text/plain") -> None:
                data = text.encode("utf-8")
                self.send_response(code)
                self.send_header("Content-Type", f"{kind}; charset=utf-8")
                self.send_header("Cache-Control", "no-store")
                self.send_header("Content-Length", str(len(data)))
                if code == 503:
                    self.send_header("Retry-After", "3")
                self.end_headers()
                if self.command != "HEAD":
                    self.wfile.write(data)

        return Handler

    # ------------------------------------------------------------------ run

    def start(self, timeout: float = 90.0) -> bool:
        """Start the workers and wait until each answers (False if one never did)."""
        for w in self.workers:
            self._spawn(w)
        deadline = time.monotonic() + timeout
        for w in self.workers:
            while not w.ready and time.monotonic() < deadline:
                if w.proc is not None and w.proc.poll() is not None:
                    break
                time.sleep(0.1)
            if w.ready:
                try:
                    urllib.request.urlopen(f"http://127.0.0.1:{w.port}/", timeout=5).read(64)
                except (OSError, HTTPException):  # a first page only; the worker is up
                    pass
        threading.Thread(target=self._monitor, name="front-door-monitor", daemon=True).start()
        threading.Thread(target=self.httpd.serve_forever, name="front-door", daemon=True).start()
        return all(w.alive for w in self.workers)

    def stop(self) -> None:
        self._stop.set()
        self.httpd.shutdown()
        self.httpd.server_close()
        for w in self.workers:
            if w.proc is not None and w.proc.poll() is None:
                w.proc.send_signal(signal.SIGINT)
        for w in self.workers:
            if w.proc is None:
                continue
            try:
                w.proc.wait(5)
            except subprocess.TimeoutExpired:
                w.proc.kill()
                w.proc.wait(5)
        self.bus.close()


def _interrupt(signum: int, frame: Any) -> None:
    raise KeyboardInterrupt


def serve_workers(
    host: str,
    port: int,
    workers: int,
    bus_url: str,
    code: str | None,
    lesson: str | None,
    fps: float | None,
    open_browser: bool,
) -> int:
    """Run the front door and its workers until interrupted; returns the exit code."""
    code = code or os.environ.get("ANALYZER_LAB_INSTRUCTOR_CODE") or generate_code()
    try:
        door = FrontDoor(host, port, workers, bus_url, code, lesson, fps)
    except OSError as exc:
        print(f"analyzer-lab: error: cannot listen on {host}:{port}: {exc}", file=sys.stderr)
        return 2
    signal.signal(signal.SIGTERM, _interrupt)  # stop the workers on a plain kill too
    t0 = time.perf_counter()
    try:
        ok = door.start()
        shown = "127.0.0.1" if host in ("", "0.0.0.0", "::") else host
        ports = ", ".join(str(w.port) for w in door.workers)
        print(
            f"Analyzer Lab: http://{shown}:{door.port}/  (front door; {workers} workers on ports "
            f"{ports}; ready in {time.perf_counter() - t0:.1f} s; Ctrl-C stops)",
            flush=True,
        )
        print(f"Instructor code: {code}  (type it in a page's Instructor folder)", flush=True)
        if not ok:
            print("analyzer-lab: warning: not every worker started; see above", flush=True)
        if open_browser:
            import webbrowser

            url = f"http://{shown}:{door.port}/"
            threading.Thread(target=lambda: webbrowser.open(url), daemon=True).start()
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        print("analyzer-lab: stopping the workers", flush=True)
    finally:
        door.stop()
    return 0


__all__ = ["FrontDoor", "STATUS_PATH", "Worker", "serve_workers"]
