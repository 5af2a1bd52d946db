"""``serve --workers N``: the front door, its workers, a worker that dies; and the
reverse-proxy form (Debian's nginx, the README's configuration) when nginx is installed.

The workers share a real redis-server started here (skipped without it; failing under
CI=true).  Pages are real websocket clients speaking viser's protocol.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path
from typing import Any

import pytest

from tests.support.client import ProtoClient
from tests.support.redis_server import RedisServer
from tests.support.servers import free_port, start_server, start_worker, stop_process
from tests.support.waiting import until, wait_until

pytestmark = pytest.mark.timeout(300)
ROOT = Path(__file__).resolve().parent.parent
CODE = "door-4417-front"


class Door:
    """``python -m analyzer_lab serve --workers 2 --bus redis://...`` in a subprocess."""

    def __init__(self, bus: str, workers: int = 2) -> None:
        self.port = free_port()
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        self.proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "analyzer_lab",
                "serve",
                "--no-browser",
                "--port",
                str(self.port),
            ]
            + ["--workers", str(workers), "--bus", bus, "--instructor-code", CODE],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            env=env,
            cwd=ROOT,
        )
        self.lines: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        deadline = time.monotonic() + 90
        while not any("(front door;" in line for line in self.lines):
            assert self.proc.poll() is None, "".join(self.lines)
            assert time.monotonic() < deadline, "".join(self.lines)
            time.sleep(0.1)

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line)

    def status(self) -> dict[str, Any]:
        """The front door's status, asked as the instructor (the code in a header)."""
        req = urllib.request.Request(
            f"http://127.0.0.1:{self.port}/frontdoor/status", headers={"X-Instructor-Code": CODE}
        )
        return json.loads(urllib.request.urlopen(req, timeout=5).read())

    def location(self, host: str | None = None) -> str:
        """Where the front door sends a new page (the redirect is not followed)."""
        import http.client

        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=5)
        conn.request("GET", "/", headers={"Host": host} if host else {})
        resp = conn.getresponse()
        assert resp.status == 302, resp.status
        where = resp.getheader("Location") or ""
        conn.close()
        return where

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.proc.kill()


@pytest.fixture()
def redis_url(redis_server: RedisServer) -> str:
    return redis_server.url


async def _page(location: str) -> ProtoClient:
    c = await ProtoClient(location.replace("http://", "ws://")).start()
    await c.wait_for("Run")
    return c


def _port(location: str) -> int:
    m = re.match(r"http://127\.0\.0\.1:(\d+)/$", location)
    assert m, location
    return int(m.group(1))


def test_the_front_door_sends_pages_to_both_workers_and_survives_one(redis_url: str) -> None:
    door = Door(redis_url)
    try:
        workers = {w["port"]: w for w in door.status()["workers"]}
        assert len(workers) == 2 and all(w["alive"] for w in workers.values())

        async def run() -> None:
            pages = []
            for _ in range(4):
                where = door.location()
                pages.append((_port(where), await _page(where)))
            ports = [p for p, _ in pages]
            assert sorted(ports) == sorted(list(workers) * 2), ports  # least-loaded: 2 and 2
            # the workers report their pages (through the bus) to the front door
            await until(
                lambda: [w["pages"] for w in door.status()["workers"]] == [2, 2], 10, "reports"
            )
            for _, c in pages:
                await c.set("Run", "Play", 0.05)
            # one worker dies: its pages are lost, the other's go on
            dead = door.status()["workers"][0]
            os.kill(dead["pid"], signal.SIGKILL)
            lost = [c for p, c in pages if p == dead["port"]]
            kept = [c for p, c in pages if p != dead["port"]]
            await until(
                lambda: all(c.ws.close_code is not None or c.error for c in lost), 10, "lost"
            )
            await until(lambda: not door.status()["workers"][0]["alive"], 5, "seen dead")
            for c in kept:
                c.measuring = True
            await until(
                lambda: all(c.point_updates >= 10 or c.error for c in kept), 10, "the kept pages"
            )
            assert all(c.point_updates >= 10 and not c.error for c in kept)
            # while it is down, new pages go to the live worker only
            if not door.status()["workers"][0]["alive"]:
                assert _port(door.location()) != dead["port"]
            # it is started again on its port and gets new pages again (least loaded)
            await until(
                lambda: (
                    door.status()["workers"][0]["alive"]
                    and door.status()["workers"][0]["restarts"] == 1
                ),
                60,
                "restarted",
            )
            back = [_port(door.location()) for _ in range(2)]
            assert dead["port"] in back
            assert any("worker 1" in line and "stopped" in line for line in door.lines)
            for _, c in pages:
                await c.close()

        asyncio.run(run())
        # a forged Host header is not echoed into the redirect
        assert door.location('evil.example"><script>').startswith("http://127.0.0.1:")
    finally:
        door.stop()
    assert door.proc.returncode is not None


def test_workers_stop_with_the_front_door(redis_url: str) -> None:
    door = Door(redis_url)
    pids = [w["pid"] for w in door.status()["workers"]]
    door.stop()
    import psutil

    wait_until(
        lambda: (
            not any(psutil.pid_exists(p) and psutil.Process(p).status() != "zombie" for p in pids)
        ),
        15,
        "the workers to stop with the front door",
    )


def test_one_worker_needs_no_redis_and_several_need_a_bus() -> None:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    cmd = [
        sys.executable,
        "-m",
        "analyzer_lab",
        "serve",
        "--no-browser",
        "--port",
        str(free_port()),
    ]
    out = subprocess.run(cmd + ["--workers", "2"], capture_output=True, text=True, env=env)
    assert out.returncode == 2 and "add --bus redis://HOST:PORT" in out.stderr
    out = subprocess.run(
        cmd + ["--bus", "http://x:1"], capture_output=True, text=True, env=env, timeout=60
    )
    assert out.returncode == 2 and "redis://HOST:PORT" in out.stderr
    out = subprocess.run(cmd + ["--workers", "0"], capture_output=True, text=True, env=env)
    assert out.returncode == 2 and "--workers must be in 1..64" in out.stderr
    # --workers 1 (the default) with no Redis anywhere: one process serves pages
    port = free_port()
    proc = start_server(port, "sphere", subprocess.DEVNULL, ("--workers", "1"))
    try:

        async def run() -> None:
            c = await _page(f"http://127.0.0.1:{port}/")
            await c.set("Run", "Play", 0.1)
            c.measuring = True
            await until(lambda: c.point_updates >= 5 or c.error, 10, "the page's frames")
            assert c.point_updates >= 5 and not c.error
            await c.close()

        asyncio.run(run())
    finally:
        stop_process(proc)


def test_the_front_door_holds_slow_clients_forged_hosts_and_strangers(redis_url: str) -> None:
    """Slowloris, a forged Host header and a stranger asking for the status (hardening,
    round 3, item 9): new pages are still sent on at once, the redirect names only the
    front door's own hosts, the status tells a stranger nothing, and the front door's
    threads and open files stay bounded."""
    import http.client
    import resource
    import socket

    import psutil
    from analyzer_lab.serve.frontdoor import HEAD_TIMEOUT, MAX_CONNECTIONS

    door = Door(redis_url)
    try:
        assert door.location("evil.example").startswith("http://127.0.0.1:")
        assert door.location(f"evil.example:{door.port}").startswith("http://127.0.0.1:")
        assert door.location(f"localhost:{door.port}").startswith("http://localhost:")
        # the status: to the instructor only
        conn = http.client.HTTPConnection("127.0.0.1", door.port, timeout=5)
        conn.request("GET", "/frontdoor/status", headers={"X-Instructor-Code": "wrong-code-123"})
        resp = conn.getresponse()
        body = resp.read().decode()
        conn.close()
        assert resp.status == 403 and "instructor code" in body
        assert "pid" not in body and "redis" not in body and str(door.port + 1) not in body
        assert door.status()["workers"][0]["pid"] > 0
        # slow clients: more half-sent requests than the front door keeps open
        soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, min(hard, 8192)), hard))
        slow = []
        try:
            for _ in range(MAX_CONNECTIONS + 300):
                s = socket.create_connection(("127.0.0.1", door.port), timeout=5)
                s.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # the head never ends
                slow.append(s)
            t0 = time.monotonic()
            assert _port(door.location()) in {w["port"] for w in door.status()["workers"]}
            assert time.monotonic() - t0 < 3.0, "a new page waited behind slow clients"
            proc = psutil.Process(door.proc.pid)
            assert proc.num_threads() < 20, proc.num_threads()
            assert proc.num_fds() < MAX_CONNECTIONS + 100, proc.num_fds()
            # the slow ones are closed once their time for a head is over
            until_sync(
                lambda: door.status()["connections"] <= 2, HEAD_TIMEOUT + 10, "slow ones closed"
            )
            figures = door.status()["http"]
            assert figures["closed_slow"] + figures["closed_full"] >= 300, figures
        finally:
            for s in slow:
                s.close()
    finally:
        door.stop()


def test_a_weak_instructor_code_is_refused_before_any_worker_starts() -> None:
    cmd = [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port"]
    cmd += [str(free_port()), "--workers", "2", "--bus", "redis://127.0.0.1:1"]
    t0 = time.monotonic()
    out = subprocess.run(
        cmd + ["--instructor-code", "abc"], capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 2, out
    assert "at least 12 letters or digits" in out.stderr
    assert "worker" not in out.stdout
    assert time.monotonic() - t0 < 30


def until_sync(check: Any, timeout: float, what: str) -> None:
    """Wait until ``check()`` holds, polling; fail naming ``what`` after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not check():
        assert time.monotonic() < deadline, f"timed out waiting for: {what}"
        time.sleep(0.2)


NGINX = shutil.which("nginx") or "/usr/sbin/nginx"


def _readme_nginx(ports: dict[str, int]) -> str:
    text = (ROOT / "README.md").read_text()
    m = re.search(r"<!-- nginx-config -->\s*```nginx\n(.*?)```", text, re.S)
    assert m, "README has no nginx configuration block"
    conf = m.group(1)
    for old, new in ports.items():
        conf = conf.replace(old, str(new))
    return conf


def test_nginx_with_one_path_per_worker_from_the_readme(redis_url: str, tmp_path: Path) -> None:
    if not os.path.exists(NGINX):
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail("nginx is missing under CI: .ci/run installs Debian's nginx-light")
        pytest.skip("nginx not installed (apt-get install nginx-light); the README documents it")
    front, p1, p2 = free_port(), free_port(), free_port()
    conf = _readme_nginx(
        {"8080": front, "127.0.0.1:8081": f"127.0.0.1:{p1}", "127.0.0.1:8082": f"127.0.0.1:{p2}"}
    )
    (tmp_path / "logs").mkdir()
    (tmp_path / "nginx.conf").write_text("events {}\nhttp {\naccess_log off;\n" + conf + "\n}\n")
    logs = [open(tmp_path / f"w{k}.log", "w") for k in (1, 2)]
    workers = [
        start_worker(p, redis_url, f"w{k}", CODE, logs[k - 1]) for k, p in ((1, p1), (2, p2))
    ]
    nginx = subprocess.Popen(
        [
            NGINX,
            "-p",
            str(tmp_path),
            "-c",
            str(tmp_path / "nginx.conf"),
            "-g",
            f"daemon off; pid {tmp_path}/nginx.pid; error_log {tmp_path}/error.log;",
        ],
        stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 10
        while True:
            try:
                html = urllib.request.urlopen(f"http://127.0.0.1:{front}/w/2/", timeout=2).read()
                break
            except Exception:
                assert nginx.poll() is None, nginx.stderr.read() if nginx.stderr else ""
                assert time.monotonic() < deadline
                time.sleep(0.1)
        # viser's client comes whole in the page (no asset path to rewrite)
        assert b"<html" in html.lower() and len(html) > 100_000
        # the front page sends a new page to one of the workers' paths
        import http.client

        conn = http.client.HTTPConnection("127.0.0.1", front, timeout=5)
        conn.request("GET", "/")
        resp = conn.getresponse()
        assert resp.status == 302 and re.search(r"/w/[12]/$", resp.getheader("Location") or "")

        async def run() -> None:
            inst = await _page(f"http://127.0.0.1:{front}/w/1/")
            student = await _page(f"http://127.0.0.1:{front}/w/2/")
            await inst.become_instructor(CODE)
            await inst.set("Preset", "example-1.2", 0.4)
            await inst.set("Run", "Play", 0.1)
            await inst.click("Follow me", 0.2)
            await until(
                lambda: student.values.get(student.gui.get("Preset", "")) == "example-1.2",
                15,
                "the demo through nginx",
            )
            student.measuring = True
            await until(
                lambda: student.point_updates >= 10 or student.error, 10, "the demo's frames"
            )
            assert student.point_updates >= 10 and not student.error
            for c in (inst, student):
                await c.close()

        asyncio.run(run())
    finally:
        nginx.send_signal(signal.SIGQUIT)
        try:
            nginx.wait(10)
        except subprocess.TimeoutExpired:
            nginx.kill()
        for w in workers:
            stop_process(w)
