"""Classroom load benchmark with real websocket clients speaking viser's protocol.

    python -m benchmarks.classroom_load [--students 50] [--seconds 10]

Two scenarios against one server subprocess (``python -m analyzer_lab serve``):

* follow: one instructor (enters the code, plays example 1.1, presses "Follow me",
  changes u1 every 2 s) and N students following the demo;
* explore: N students each playing their own session.

Each is reported as updates/s of the moving point per student (mean and minimum),
MB/s per student, and server CPU (psutil; 100% = one core).

:class:`tests.support.client.ProtoClient` is each page (the hand-made client of the
hardening tests).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import subprocess
import time
from dataclasses import dataclass, field
from typing import Any

from tests.support.client import ProtoClient, play
from tests.support.servers import free_port
from tests.support.servers import start_server as _start_server

BENCH_CODE = "bench-code-2718"


@dataclass
class Figures:
    scenario: str
    students: int
    updates: list[float] = field(default_factory=list)
    mb: list[float] = field(default_factory=list)
    cpu: float = 0.0
    errors: list[str] = field(default_factory=list)

    def row(self) -> str:
        u = self.updates or [0.0]
        b = self.mb or [0.0]
        return (
            f"{self.scenario:8s} {self.students:8d} {statistics.mean(u):10.1f} {min(u):8.1f} {statistics.mean(b):12.4f}"
            f" {self.cpu:10.0f}%  {len(self.errors)}"
        )


async def _measure(
    students: list[ProtoClient], seconds: float, pid: int
) -> tuple[list[float], list[float], float]:
    import psutil

    proc = psutil.Process(pid)
    proc.cpu_percent(None)
    for c in students:
        c.point_updates = c.bytes = c.frames = 0
        c.measuring = True
    t0 = time.monotonic()
    await asyncio.sleep(seconds)
    dt = time.monotonic() - t0
    for c in students:
        c.measuring = False
    cpu = proc.cpu_percent(None)
    ok = [c for c in students if not c.error]
    return [c.point_updates / dt for c in ok], [c.bytes / dt / 1e6 for c in ok], cpu


async def follow_scenario(
    url: str, n: int, seconds: float, pid: int, code: str = BENCH_CODE
) -> Figures:
    fig = Figures("follow", n)
    inst = await ProtoClient(url).start()
    await inst.become_instructor(code)
    await play(inst)
    students = []
    for _ in range(n):
        students.append(await ProtoClient(url).start())
        await asyncio.sleep(0.02)
    await asyncio.sleep(2.0)
    await inst.click("Follow me")
    await asyncio.sleep(4.0)

    async def wiggle() -> None:
        k = 0
        while True:
            await asyncio.sleep(2.0)
            k += 1
            await inst.set("u1", 5.0 + (k % 3), 0)

    w = asyncio.create_task(wiggle())
    fig.updates, fig.mb, fig.cpu = await _measure(students, seconds, pid)
    w.cancel()
    await inst.click("Release", 0.5)
    fig.errors = [c.error for c in students if c.error]
    for c in [inst, *students]:
        await c.close()
    return fig


async def explore_scenario(url: str, n: int, seconds: float, pid: int) -> Figures:
    fig = Figures("explore", n)
    students = []
    for _ in range(n):
        c = await ProtoClient(url).start()
        students.append(c)
        await asyncio.sleep(0.02)
    await asyncio.gather(*(c.wait_for("Run") for c in students))
    for c in students:
        await play(c)
    await asyncio.sleep(4.0)
    fig.updates, fig.mb, fig.cpu = await _measure(students, seconds, pid)
    fig.errors = [c.error for c in students if c.error]
    for c in students:
        await c.close()
    return fig


def start_server(
    port: int,
    code: str = BENCH_CODE,
    lesson: str = "sphere",
    log: Any = subprocess.DEVNULL,
    fps: float = 36.0,
) -> subprocess.Popen:
    """``python -m analyzer_lab serve`` with an instructor code; returns when HTTP answers."""
    return _start_server(port, lesson, log, ("--instructor-code", code, "--fps", str(fps)))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.classroom_load", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--students", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument(
        "--scenarios", nargs="+", default=["follow", "explore"], choices=["follow", "explore"]
    )
    ap.add_argument("--server-log", default="")
    ap.add_argument(
        "--fps",
        type=float,
        default=36.0,
        help="the server's frame rate (serve --fps; default 36, as serve)",
    )
    args = ap.parse_args(argv)
    port = free_port()
    log = open(args.server_log, "w") if args.server_log else subprocess.DEVNULL
    proc = start_server(port, log=log, fps=args.fps)
    url = f"ws://127.0.0.1:{port}/"
    print(
        f"server pid {proc.pid}; {os.cpu_count()} cores; lesson sphere, example-1.1; server at {args.fps:g} frames/s"
    )
    print(
        f"{'scenario':8s} {'students':>8} {'updates/s':>10} {'min':>8} {'MB/s/client':>12} {'server CPU':>11}  errors"
    )
    try:
        for name in args.scenarios:
            if name == "follow":
                fig = asyncio.run(follow_scenario(url, args.students, args.seconds, proc.pid))
            else:
                fig = asyncio.run(explore_scenario(url, args.students, args.seconds, proc.pid))
            print(fig.row(), flush=True)
            for e in fig.errors[:3]:
                print("   ", e)
            time.sleep(2.0)
    finally:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
