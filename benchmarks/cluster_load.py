"""A class on several workers: ``serve --workers N`` behind its front door, joined by Redis.

    python -m benchmarks.cluster_load [--workers 2] [--pages 100] [--students 100] [--seconds 10]

Starts its own ``redis-server`` (Debian's, on a free loopback port) and
``python -m analyzer_lab serve --workers N --bus redis://...``; every client asks the front door
for a page (HTTP, the redirect is not followed), then opens its websocket at the worker
it was sent to, as a browser does.  Two scenarios:

* pages: N pages each playing its own session (sphere, example 1.1): updates/s per page
  (mean, min), server CPU per worker, of the front door and in total (psutil; 100% = one core);
* classroom: one instructor and S following students (spread over the workers by the front
  door); the instructor changes u1(t) every 2 s: followers' updates/s, and the lag from the
  instructor's change to each follower's page showing it (median and worst, over all
  followers and changes), per worker.
"""

from __future__ import annotations

import argparse
import asyncio
import http.client
import json
import os
import signal
import statistics
import subprocess
import sys
import time
from collections import Counter
from typing import Any

from tests.support.client import ProtoClient
from tests.support.load import LabClient, count_window, page_plan
from tests.support.servers import free_port

CODE = "cluster-bench-6613"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def start_redis(port: int) -> subprocess.Popen:
    """Debian's redis-server on 127.0.0.1:port, no persistence; returns when it answers."""
    import redis

    proc = subprocess.Popen(
        ["redis-server", "--port", str(port), "--bind", "127.0.0.1", "--save", ""]
        + ["--appendonly", "no"],
        stdout=subprocess.DEVNULL,
    )
    client = redis.Redis(host="127.0.0.1", port=port)
    deadline = time.monotonic() + 10
    while True:
        try:
            client.ping()
            return proc
        except Exception:
            if time.monotonic() > deadline:
                proc.kill()
                raise RuntimeError("redis-server did not start") from None
            time.sleep(0.05)


def start_front_door(
    port: int, workers: int, bus: str, log: Any, extra: tuple[str, ...] = ()
) -> subprocess.Popen:
    """``python -m analyzer_lab serve --workers N --bus BUS`` (and ``extra`` options);
    returns when every worker runs."""
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.setdefault("ANALYZER_LAB_STATS", "5")
    proc = subprocess.Popen(
        [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port", str(port)]
        + ["--workers", str(workers), "--bus", bus, "--instructor-code", CODE, *extra],
        stdout=log,
        stderr=log,
        env=env,
        cwd=ROOT,
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        try:
            st = status(port)
            if all(w["alive"] for w in st["workers"]):
                return proc
        except Exception:
            pass
        if proc.poll() is not None:
            raise RuntimeError(f"serve --workers exited with code {proc.returncode}")
        time.sleep(0.2)
    proc.kill()
    raise RuntimeError("the workers did not start within 120 s")


def stop_front_door(door: subprocess.Popen, redis_proc: subprocess.Popen) -> None:
    """Stop the front door (its workers with it) as Ctrl+C does, then Redis."""
    door.send_signal(signal.SIGINT)
    try:
        door.wait(15)
    except subprocess.TimeoutExpired:
        door.kill()
    redis_proc.terminate()
    redis_proc.wait(5)


def status(port: int) -> dict[str, Any]:
    """The front door's status, asked as the instructor."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
    conn.request("GET", "/frontdoor/status", headers={"X-Instructor-Code": CODE})
    data = json.loads(conn.getresponse().read())
    conn.close()
    return data


def page_url(port: int) -> str:
    """Ask the front door for a page; the websocket address of the worker it names."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    conn.request("GET", "/")
    resp = conn.getresponse()
    where = resp.getheader("Location") or ""
    conn.close()
    if resp.status != 302 or not where.startswith("http://"):
        raise RuntimeError(f"the front door answered {resp.status} {where!r}")
    return "ws://" + where[len("http://") :]


class CPU:
    """CPU of the front door and each worker over a window (psutil; 100% = one core)."""

    def __init__(self, door_pid: int, worker_pids: list[int]) -> None:
        import psutil

        self.procs = [psutil.Process(door_pid)] + [psutil.Process(p) for p in worker_pids]
        self.procs.append(psutil.Process())  # the clients (this process)
        self.clients = 0.0
        self.machine = psutil.cpu_percent
        #: each worker's resident memory (MB) when last read
        self.memory: list[float] = []

    def start(self) -> None:
        for p in self.procs:
            p.cpu_percent(None)
        self.machine(None)

    def settle(self, limit: float = 12.0, timeout: float = 90.0) -> float:
        """Wait until every worker has finished warming up (CPU under ``limit``% for 1 s)."""
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout:
            self.start()
            time.sleep(1.0)
            if max(p.cpu_percent(None) for p in self.procs[1:-1]) < limit:
                break
        return time.monotonic() - t0

    def read(self) -> tuple[float, list[float], float]:
        values = [p.cpu_percent(None) for p in self.procs]
        self.clients = values[-1]
        self.memory = [p.memory_info().rss / 1e6 for p in self.procs[1:-1]]
        return values[0], values[1:-1], self.machine(None)


def _cpu_text(door: float, workers: list[float], machine: float, clients: float = 0.0) -> str:
    each = ", ".join(f"{c:.0f}%" for c in workers)
    return (
        f"server CPU per worker {each}; front door {door:.0f}%; total {sum(workers) + door:.0f}% "
        f"(clients {clients:.0f}%; machine, all cores: {machine:.0f}%)"
    )


async def pages_scenario(port: int, n: int, seconds: float, cpu: CPU) -> str:
    urls = [page_url(port) for _ in range(n)]
    clients = [LabClient(u, page_plan("sphere", "example-1.1")) for u in urls]
    dt, (door, workers, machine) = await count_window(
        clients, seconds, 3.0, cpu.start, cpu.read, ready_timeout=90.0
    )
    ok = [c.stats.updates / dt for c in clients if not c.stats.error]
    errors = [c.stats.error for c in clients if c.stats.error]
    spread = Counter(u.rsplit(":", 1)[1].strip("/") for u in urls)
    u = ok or [0.0]
    return (
        f"pages: {n} pages (per worker port: {dict(spread)}): updates/s per page mean "
        f"{statistics.mean(u):.1f}, min {min(u):.1f}; {_cpu_text(door, workers, machine, cpu.clients)}; "
        f"memory per worker {', '.join(f'{m:.0f} MB' for m in cpu.memory)}; "
        f"errors {len(errors)}" + (f" ({errors[0]})" if errors else "")
    )


async def classroom_scenario(port: int, n: int, seconds: float, cpu: CPU) -> str:
    inst_url = page_url(port)
    inst = await ProtoClient(inst_url).start()
    await inst.become_instructor(CODE)
    await inst.set("Preset", "example-1.1", 0.3)
    await inst.set("pause at t_end", False, 0.1)
    await inst.set("Run", "Play", 0.1)
    students: list[tuple[str, ProtoClient]] = []
    for _ in range(n):
        url = page_url(port)
        students.append((url, await ProtoClient(url).start()))
        await asyncio.sleep(0.02)
    await asyncio.gather(*(c.wait_for("u1(t) =") for _, c in students))
    await asyncio.sleep(2.0)
    await inst.click("Follow me")
    await asyncio.sleep(5.0)
    label = "u1(t) ="
    lags: list[float] = []
    by_worker: dict[str, list[float]] = {}
    missed = 0
    cpu.start()
    for _, c in students:
        c.point_updates = c.bytes = c.frames = 0
        c.measuring = True
    t0 = time.monotonic()
    values = ["3", "4", "6", "7"]
    k = 0
    while time.monotonic() - t0 < seconds:
        value = values[k % len(values)]
        k += 1
        sent = time.monotonic()
        await inst.set(label, value, 0)
        deadline = sent + 5.0
        pending = {id(c): (u, c) for u, c in students if not c.error}
        while pending and time.monotonic() < deadline:
            for key, (u, c) in list(pending.items()):
                uuid = c.gui.get(label, "")
                if c.values.get(uuid) == value:
                    lag = c.stamps[uuid] - sent
                    lags.append(lag)
                    by_worker.setdefault(u.rsplit(":", 1)[1].strip("/"), []).append(lag)
                    pending.pop(key)
            await asyncio.sleep(0.01)
        missed += len(pending)
        await asyncio.sleep(max(0.0, sent + 2.0 - time.monotonic()))
    dt = time.monotonic() - t0
    for _, c in students:
        c.measuring = False
    door, workers, machine = cpu.read()
    ok = [c.point_updates / dt for _, c in students if not c.error]
    errors = [c.error for _, c in students if c.error]
    await inst.click("Release", 0.5)
    for c in [inst, *(c for _, c in students)]:
        await c.close()
    u = ok or [0.0]
    lags_ms = sorted(x * 1000 for x in lags) or [float("nan")]
    per = "; ".join(
        f"port {p}: {len(v) // max(k, 1)} followers, median {statistics.median(v) * 1000:.0f} ms, "
        f"worst {max(v) * 1000:.0f} ms"
        for p, v in sorted(by_worker.items())
    )
    return (
        f"classroom: instructor on port {inst_url.rsplit(':', 1)[1].strip('/')}, {n} followers: "
        f"updates/s per follower mean {statistics.mean(u):.1f}, min {min(u):.1f}; lag from the "
        f"instructor's change to every follower's page over {k} changes: median "
        f"{statistics.median(lags_ms):.0f} ms, worst {max(lags_ms):.0f} ms ({per}); "
        f"missed {missed}; {_cpu_text(door, workers, machine, cpu.clients)}; errors {len(errors)}"
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.cluster_load", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--pages", type=int, default=100)
    ap.add_argument("--students", type=int, default=100)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument(
        "--scenarios", nargs="+", default=["pages", "classroom"], choices=["pages", "classroom"]
    )
    ap.add_argument("--server-log", default="")
    args = ap.parse_args(argv)
    rport, port = free_port(), free_port()
    log = open(args.server_log, "w") if args.server_log else subprocess.DEVNULL
    redis_proc = start_redis(rport)
    door = start_front_door(port, args.workers, f"redis://127.0.0.1:{rport}", log)
    try:
        pids = [w["pid"] for w in status(port)["workers"]]
        print(
            f"front door pid {door.pid} on port {port}; workers {pids}; redis on port {rport}; "
            f"{os.cpu_count()} cores; load average {os.getloadavg()[0]:.2f}",
            flush=True,
        )
        cpu = CPU(door.pid, pids)
        print(f"workers warmed up in {cpu.settle():.0f} s", flush=True)
        for name in args.scenarios:
            if name == "pages":
                print(asyncio.run(pages_scenario(port, args.pages, args.seconds, cpu)), flush=True)
            else:
                text = asyncio.run(classroom_scenario(port, args.students, args.seconds, cpu))
                print(text, flush=True)
            time.sleep(3.0)
    finally:
        stop_front_door(door, redis_proc)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
