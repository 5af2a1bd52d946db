"""Classroom load benchmark with real websocket clients speaking viser's protocol.

    python -m benchmarks.classroom_load [--students 50] [--seconds 10]

Two scenarios against one server subprocess (``python -m app serve``):

* follow: one instructor (enters the code, plays example 1.1, presses "Follow me",
  changes u1 every 2 s) and N students following the demo;
* explore: N students each playing their own session.

Each is reported as updates/s of the moving point per student (mean and minimum),
MB/s per student, and server CPU (psutil; 100% = one core).

:class:`ProtoClient` is also the hand-made client of the hardening tests: it learns
the GUI (label -> uuid) from the server's messages and can send any message.
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

from benchmarks.loadtest import (
    POINT_NODE,
    camera_message,
    decode_frame,
    encode,
    free_port,
    gui_update,
)
from benchmarks.loadtest import start_server as _start_server

BENCH_CODE = "bench-code-2718"


class ProtoClient:
    """One page as a websocket client: GUI by label, point updates, bytes."""

    def __init__(self, url: str) -> None:
        self.url = url if url.startswith("ws") else url.replace("http", "ws", 1)
        self.gui: dict[str, str] = {}  # label -> uuid (the newest element with that label)
        self.values: dict[str, Any] = {}  # uuid -> value the server set
        self.stamps: dict[str, float] = {}  # uuid -> when the server last set its value
        self.html: dict[str, str] = {}  # uuid -> content of html elements
        self.notifications: list[str] = []
        self.seen: dict[str, int] = {}  # message type -> count
        self.last: dict[str, dict[str, Any]] = {}  # message type -> the newest of that type
        self.point_updates = 0
        self.frames = 0
        self.bytes = 0
        self.measuring = False
        self.last_points: Any = None
        self.ws: Any = None
        self.error = ""
        self.connected = asyncio.Event()
        self._task: asyncio.Task | None = None

    async def start(self) -> ProtoClient:
        self._task = asyncio.create_task(self._run())
        await asyncio.wait_for(self.connected.wait(), 30)
        return self

    async def _run(self) -> None:
        import viser
        import websockets
        import zstandard

        dec = zstandard.ZstdDecompressor()
        try:
            async with websockets.connect(
                self.url,
                subprotocols=[f"viser-v{viser.__version__}"],
                max_size=None,
                compression=None,
                open_timeout=30,
            ) as ws:
                self.ws = ws
                await ws.send(encode(camera_message()))
                self.connected.set()
                async for raw in ws:
                    if not isinstance(raw, bytes):
                        continue
                    point = False
                    for m in decode_frame(raw, dec):
                        t = m.get("type", "")
                        self.seen[t] = self.seen.get(t, 0) + 1
                        self.last[t] = m
                        if t == "SceneNodeUpdateMessage":
                            if m.get("name") == POINT_NODE and "points" in m.get("updates", {}):
                                point = True
                        elif t == "GuiUpdateMessage":
                            upd = m.get("updates", {})
                            if "value" in upd:
                                self.values[m.get("uuid")] = upd["value"]
                                self.stamps[m.get("uuid")] = time.monotonic()
                            if "content" in upd:
                                self.html[m.get("uuid")] = upd["content"]
                        elif (
                            t.startswith("Gui") and isinstance(m.get("props"), dict) and "uuid" in m
                        ):
                            props = m["props"]
                            label = props.get("label")
                            if isinstance(label, str):
                                self.gui[label] = m["uuid"]
                            if "value" in m:
                                self.values[m["uuid"]] = m["value"]
                            if "content" in props:
                                self.html[m["uuid"]] = props["content"]
                        elif t == "NotificationShowMessage":
                            props = m.get("props", {}) if isinstance(m.get("props"), dict) else m
                            self.notifications.append(
                                f"{props.get('title', '')}: {props.get('body', '')}"
                            )
                    if self.measuring:
                        self.frames += 1
                        self.bytes += len(raw)
                        self.point_updates += point
        except Exception as exc:
            self.error = f"{type(exc).__name__}: {exc}"
            self.connected.set()

    async def wait_for(self, label: str, timeout: float = 20.0) -> str:
        deadline = time.monotonic() + timeout
        while label not in self.gui:
            if time.monotonic() > deadline or self.error:
                raise TimeoutError(f"no GUI element {label!r} ({self.error})")
            await asyncio.sleep(0.05)
        return self.gui[label]

    async def send(self, message: Any) -> None:
        await self.ws.send(encode(message))

    async def set(self, label: str, value: Any, pause: float = 0.06) -> None:
        """Set a GUI value (a click for buttons: value True) as the browser would."""
        uuid = await self.wait_for(label)
        await self.send(gui_update(uuid, value))
        if pause:
            await asyncio.sleep(pause)

    async def click(self, label: str, pause: float = 0.06) -> None:
        await self.set(label, True, pause)

    async def become_instructor(self, code: str) -> None:
        await self.set("Instructor code", code, 0.1)
        await self.click("Become instructor")
        await self.wait_for("Follow me")

    async def close(self) -> None:
        if self.ws is not None:
            await self.ws.close()
        if self._task is not None:
            await asyncio.gather(self._task, return_exceptions=True)


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


async def _play(c: ProtoClient, preset: str = "example-1.1") -> None:
    await c.set("Preset", preset, 0.3)
    await c.set("pause at t_end", False, 0.1)
    await c.set("Run", "Play", 0.1)


async def follow_scenario(
    url: str, n: int, seconds: float, pid: int, code: str = BENCH_CODE
) -> Figures:
    fig = Figures("follow", n)
    inst = await ProtoClient(url).start()
    await inst.become_instructor(code)
    await _play(inst)
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
        await _play(c)
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
    """``python -m app serve`` with an instructor code; returns when HTTP answers."""
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
