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
``GET /frontdoor/status`` answers the workers' figures as JSON to the instructor only (the
code in an ``X-Instructor-Code`` header).

The front door is an asyncio server: a connection costs no thread, a request's head must
arrive within :data:`HEAD_TIMEOUT` seconds and fit in :data:`MAX_HEAD` bytes, at most
:data:`MAX_CONNECTIONS` are open at once (past that the oldest one still sending its head is
closed), and a redirect names only a host the front door was configured with
(:func:`allowed_hosts`), whatever ``Host`` header it was sent.
"""

from __future__ import annotations

import asyncio
import hmac
import json
import logging
import os
import re
import resource
import signal
import socket
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Iterable
from dataclasses import dataclass, field
from http.client import HTTPException
from typing import Any

from analyzer_lab.classroom.bus import Message, make_bus
from analyzer_lab.classroom.instructor_code import CODE_ENV, CodeError, class_code, normalize_code

STATUS_PATH = "/frontdoor/status"
#: Seconds before a worker that exited is started again.
RESTART_DELAY = 1.0
#: A worker's page report older than this is not trusted (only the front door's own count).
REPORT_TIMEOUT = 5.0
#: Seconds a page sent to a worker counts as its load on top of the worker's report (a
#: page built on a busy machine reaches the worker's report several seconds after it was
#: sent; counted twice for a while, it only spreads the next pages more).
PENDING = 10.0
#: A request's head (request line and headers): seconds to arrive, and bytes at most.
HEAD_TIMEOUT = 5.0
MAX_HEAD = 8192
#: Connections open at once; past it the oldest one still sending its head is closed.
MAX_CONNECTIONS = 512
WILDCARD = ("", "0.0.0.0", "::")
_URL_RE = re.compile(r"Analyzer Lab: http://[^ ]*:(\d+)/")

log = logging.getLogger(__name__)


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


def allowed_hosts(host: str, public_hosts: Iterable[str] = ()) -> tuple[str, ...]:
    """The host names a redirect may name, the first one the default: the configured
    public names, then the listening address (for a wildcard address: loopback, this
    machine's names and addresses)."""
    names: list[str] = [h.strip().lower() for h in public_hosts if h.strip()]
    if host in WILDCARD:
        names += ["127.0.0.1", "localhost", "[::1]"]
        for name in (socket.gethostname(), socket.getfqdn()):
            names.append(name.lower())
            try:
                infos = socket.getaddrinfo(name, None)
            except OSError:
                continue
            for info in infos:
                addr = str(info[4][0])
                names.append(f"[{addr}]" if ":" in addr else addr)
    else:
        names.append(f"[{host}]" if ":" in host and not host.startswith("[") else host.lower())
        if host in ("127.0.0.1", "localhost"):
            names += ["127.0.0.1", "localhost"]
    return tuple(dict.fromkeys(names))


def redirect_host(header: str, allowed: tuple[str, ...]) -> str:
    """The host of a redirect: the ``Host`` header's name when it is allowed, else the
    default (the first allowed name)."""
    header = header.strip().lower()
    name = header if header.endswith("]") else header.rsplit(":", 1)[0]
    return name if name in allowed else allowed[0]


def raise_open_file_limit() -> int:
    """Raise this process's soft limit of open files to its hard limit (connections are
    files); returns the limit in force."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if hard == resource.RLIM_INFINITY or hard > soft:
        target = 65536 if hard == resource.RLIM_INFINITY else hard
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (target, hard))
            soft = target
        except (ValueError, OSError) as exc:
            log.warning("open-file limit stays at %d: %s", soft, exc)
    return soft


@dataclass
class _Connection:
    """One open connection of the front door: when it came, whether its head arrived."""

    writer: asyncio.StreamWriter
    opened: float
    head_done: bool = False


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
        public_hosts: Iterable[str] = (),
    ) -> None:
        self.host, self.bus_url, self.code = host, bus_url, code
        self.lesson, self.fps, self.restart = lesson, fps, restart
        self.allowed = allowed_hosts(host, public_hosts)
        self.lock = threading.Lock()
        self._stop = threading.Event()
        self._rr = 0
        self.sock = socket.create_server(
            (host, port), family=socket.AF_INET6 if ":" in host else socket.AF_INET, backlog=512
        )
        self.port = int(self.sock.getsockname()[1])
        self.connections: dict[int, _Connection] = {}
        self.stats = {"requests": 0, "closed_slow": 0, "closed_full": 0, "refused_status": 0}
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: asyncio.Server | None = None
        self._http_thread: threading.Thread | None = None
        self.workers = [
            Worker(k, f"worker-{k}@{self.port}", self.port + k if port else _free_port(host))
            for k in range(1, workers + 1)
        ]
        self.bus = make_bus(bus_url, code, f"front-door@{self.port}")
        self.bus.listen(self._on_message)

    # ------------------------------------------------------------------ workers

    def _spawn(self, w: Worker) -> None:
        env = dict(os.environ)
        env[CODE_ENV] = self.code  # not on the command line (ps)
        env["ANALYZER_LAB_FRONT_DOOR_PID"] = str(os.getpid())
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
        """The workers' figures (for the instructor only: pids, ports, the bus)."""
        return {
            "port": self.port,
            "bus": self.bus.describe(),
            "workers": [w.figures() for w in self.workers],
            "connections": len(self.connections),
            "http": dict(self.stats),
        }

    def is_instructor(self, text: str) -> bool:
        """Whether ``text`` is the instructor code (compared in constant time)."""
        given, code = normalize_code(text), normalize_code(self.code)
        return bool(given) and hmac.compare_digest(given.encode(), code.encode())

    # ------------------------------------------------------------------ HTTP

    def _admit(self, conn: _Connection) -> None:
        """Keep the connections within :data:`MAX_CONNECTIONS`: close the oldest one still
        sending its head (a slow client), or the oldest of all."""
        if len(self.connections) < MAX_CONNECTIONS:
            return
        waiting = [c for c in self.connections.values() if not c.head_done]
        victim = min(waiting or self.connections.values(), key=lambda c: c.opened)
        self.stats["closed_full"] += 1
        victim.writer.transport.abort()
        self.connections.pop(id(victim.writer), None)

    async def _client(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        conn = _Connection(writer, time.monotonic())
        self._admit(conn)
        self.connections[id(writer)] = conn
        try:
            try:
                head = await asyncio.wait_for(reader.readuntil(b"\r\n\r\n"), HEAD_TIMEOUT)
            except (TimeoutError, asyncio.IncompleteReadError, asyncio.LimitOverrunError):
                self.stats["closed_slow"] += 1
                return
            conn.head_done = True
            self.stats["requests"] += 1
            await asyncio.wait_for(self._answer_request(head, writer), HEAD_TIMEOUT)
        except (ConnectionError, TimeoutError):
            pass  # the client went away or did not read its answer: nothing to tell it
        except Exception:
            log.exception("front door: a request failed")
        finally:
            self.connections.pop(id(writer), None)
            writer.close()

    async def _answer_request(self, head: bytes, writer: asyncio.StreamWriter) -> None:
        lines = head.decode("latin-1").split("\r\n")
        parts = lines[0].split(" ")
        method, target = (parts[0], parts[1]) if len(parts) >= 3 else ("", "/")
        headers: dict[str, str] = {}
        for line in lines[1:]:
            name, sep, value = line.partition(":")
            if sep:
                headers[name.strip().lower()] = value.strip()
        if method not in ("GET", "HEAD"):
            await self._send(writer, method, 405, "Only GET and HEAD are served here.\n")
            return
        if target.split("?")[0] == STATUS_PATH:
            if not self.is_instructor(headers.get("x-instructor-code", "")):
                self.stats["refused_status"] += 1
                await self._send(
                    writer,
                    method,
                    403,
                    "The front door's status is for the instructor: send the instructor code"
                    " in an X-Instructor-Code header.\n",
                )
                return
            await self._send(writer, method, 200, json.dumps(self.status()), "application/json")
            return
        w = self.pick()
        if w is None:
            await self._send(
                writer,
                method,
                503,
                "No worker of the lab is running; try again in a few seconds.\n",
            )
            return
        host = redirect_host(headers.get("host", ""), self.allowed)
        path = target if target.startswith("/") else "/"
        extra = {"Location": f"http://{host}:{w.port}{path}"}
        await self._send(writer, method, 302, "", extra=extra)

    @staticmethod
    async def _send(
        writer: asyncio.StreamWriter,
        method: str,
        code: int,
        text: str,
        kind: str = "text/plain",
        extra: dict[str, str] | None = None,
    ) -> None:
        reasons = {200: "OK", 302: "Found", 403: "Forbidden", 405: "Method Not Allowed"}
        data = text.encode("utf-8")
        head = [
            f"HTTP/1.1 {code} {reasons.get(code, 'Service Unavailable')}",
            "Server: AnalyzerLabFrontDoor",
            f"Content-Type: {kind}; charset=utf-8",
            "Cache-Control: no-store",
            f"Content-Length: {len(data)}",
            "Connection: close",
        ]
        if code == 503:
            head.append("Retry-After: 3")
        head += [f"{k}: {v}" for k, v in (extra or {}).items()]
        writer.write(("\r\n".join(head) + "\r\n\r\n").encode("latin-1"))
        if method != "HEAD":
            writer.write(data)
        await writer.drain()

    async def _shutdown(self) -> None:
        """Close the listening server and every open connection (in the server's loop)."""
        if self._server is not None:
            self._server.close()
        for conn in list(self.connections.values()):
            conn.writer.transport.abort()
        self.connections.clear()

    def _run_http(self, ready: threading.Event) -> None:
        loop = asyncio.new_event_loop()
        self._loop = loop
        asyncio.set_event_loop(loop)

        async def main() -> None:
            self._server = await asyncio.start_server(
                self._client, sock=self.sock, limit=MAX_HEAD, backlog=512
            )
            ready.set()
            async with self._server:
                await self._server.serve_forever()

        try:
            loop.run_until_complete(main())
        except asyncio.CancelledError:
            pass
        finally:
            loop.close()

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
                except (OSError, HTTPException) as exc:  # a first page only; the worker is up
                    log.warning(
                        "worker on port %d did not answer its first request: %s", w.port, exc
                    )
        threading.Thread(target=self._monitor, name="front-door-monitor", daemon=True).start()
        ready = threading.Event()
        self._http_thread = threading.Thread(
            target=self._run_http, args=(ready,), name="front-door", daemon=True
        )
        self._http_thread.start()
        ready.wait(10)
        return all(w.alive for w in self.workers)

    def stop(self) -> None:
        self._stop.set()
        if self._loop is not None and self._loop.is_running():
            done = asyncio.run_coroutine_threadsafe(self._shutdown(), self._loop)
            try:
                done.result(5)
            except (TimeoutError, asyncio.CancelledError):
                log.warning("front door: the HTTP server did not close in time")
        if self._http_thread is not None:
            self._http_thread.join(5)
        self.sock.close()
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
    public_hosts: Iterable[str] = (),
    code_file: str | None = None,
) -> int:
    """Run the front door and its workers until interrupted; returns the exit code."""
    try:
        code = class_code(code, code_file)
    except CodeError as exc:  # refused here, once, rather than by every worker in a restart loop
        print(f"analyzer-lab: error: {exc}", file=sys.stderr)
        return 2
    raise_open_file_limit()
    try:
        door = FrontDoor(host, port, workers, bus_url, code, lesson, fps, public_hosts=public_hosts)
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


__all__ = ["FrontDoor", "STATUS_PATH", "Worker", "allowed_hosts", "redirect_host", "serve_workers"]
