"""Measuring what pages receive: simulated students (real websocket clients speaking
viser's protocol) pick a lesson and its preset in the page's pickers, untick "pause at
t_end", press Play and count what they receive: websocket frames that carry an update of
the lesson's live scene (any node under :data:`analyzer_lab.view.scene.LIVE_ROOT`: moving
points, trails, vectors, posed bodies), once per frame (updates/s), and bytes (MB/s).
Server CPU comes from psutil on the server process."""

from __future__ import annotations

import asyncio
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from analyzer_lab.view.page import LESSON_PICKER, PAUSE_AT_END, PRESET_PICKER
from analyzer_lab.view.transport import PLAY, RUN

from tests.support.wire import camera_message, decode_frame, encode, gui_update, live_update

T = TypeVar("T")


@dataclass(frozen=True)
class PagePlan:
    """What a page picks before it plays: the lesson (its picker label) and a preset."""

    lesson: str
    lesson_label: str
    preset: str | None


def page_plan(lesson_id: str, preset: str | None = None) -> PagePlan:
    """The plan for a lesson of the catalog: ``preset`` or the lesson's first one."""
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.session.session import lesson_label

    lesson = get_lesson(lesson_id)
    if preset is None and lesson.presets:
        preset = lesson.presets[0].name
    return PagePlan(lesson.id, lesson_label(lesson), preset)


@dataclass
class ClientStats:
    frames: int = 0
    bytes: int = 0
    updates: int = 0  # frames carrying an update of the live scene
    nodes: set[str] = field(default_factory=set)  # live nodes updated while measuring
    gui: dict[str, str] = field(default_factory=dict)  # label -> uuid
    values: dict[str, Any] = field(default_factory=dict)  # uuid -> value the server set
    connected: float = 0.0
    played: float = 0.0  # when Play was sent
    playing_update: float = 0.0  # first live update well after Play
    error: str = ""


class LabClient:
    """One simulated student."""

    def __init__(self, url: str, plan: PagePlan) -> None:
        self.url = url
        self.plan = plan
        self.stats = ClientStats()
        self.measuring = False
        self.ws: Any = None

    async def run(self, stop: asyncio.Event) -> None:
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
                self.stats.connected = time.monotonic()
                starting: asyncio.Task | None = None
                stopping = asyncio.get_running_loop().create_task(stop.wait())
                while not stop.is_set():
                    receiving = asyncio.get_running_loop().create_task(ws.recv())
                    await asyncio.wait((receiving, stopping), return_when=asyncio.FIRST_COMPLETED)
                    if not receiving.done():
                        receiving.cancel()
                        break
                    raw = receiving.result()
                    if not isinstance(raw, bytes):
                        continue
                    live = False
                    for m in decode_frame(raw, dec):
                        live = self._read(m) or live
                    if self.measuring:
                        self.stats.frames += 1
                        self.stats.bytes += len(raw)
                        self.stats.updates += live
                    now = time.monotonic()
                    if (
                        live
                        and self.stats.played
                        and not self.stats.playing_update
                        and now > self.stats.played + 0.5
                    ):
                        self.stats.playing_update = now
                    if starting is None and all(
                        k in self.stats.gui for k in (RUN, PRESET_PICKER, PAUSE_AT_END)
                    ):
                        starting = asyncio.get_running_loop().create_task(self._start(ws))
        except Exception as exc:  # reported in the table
            self.stats.error = f"{type(exc).__name__}: {exc}"

    def _read(self, m: dict[str, Any]) -> bool:
        """Note GUI elements and values; whether ``m`` updates the live scene."""
        t = m.get("type", "")
        if t == "GuiUpdateMessage":
            updates = m.get("updates", {})
            if "value" in updates:
                self.stats.values[m.get("uuid", "")] = updates["value"]
        elif t.startswith("Gui") and t.endswith("Message") and isinstance(m.get("props"), dict):
            label = m["props"].get("label")
            if isinstance(label, str) and "uuid" in m:
                self.stats.gui[label] = m["uuid"]
                if "value" in m:
                    self.stats.values[m["uuid"]] = m["value"]
        elif live_update(m):
            if self.measuring:
                self.stats.nodes.add(m["name"])
            return True
        return False

    async def _start(self, ws: Any) -> None:
        """Pick the lesson and the preset as a page does, untick "pause at t_end", play."""
        gui = self.stats.gui
        try:
            if self.stats.values.get(gui.get(LESSON_PICKER, "")) != self.plan.lesson_label:
                before = gui[PAUSE_AT_END]
                await ws.send(encode(gui_update(gui[LESSON_PICKER], self.plan.lesson_label)))
                # the page rebuilds the lesson's controls: a new checkbox
                deadline = time.monotonic() + 30
                while gui[PAUSE_AT_END] == before:
                    if time.monotonic() > deadline:
                        raise TimeoutError(f"lesson {self.plan.lesson!r} was not selected")
                    await asyncio.sleep(0.05)
                await asyncio.sleep(0.3)
            if self.plan.preset:
                await ws.send(encode(gui_update(gui[PRESET_PICKER], self.plan.preset)))
                await asyncio.sleep(0.3)
            # keep playing past the textbook's t_end
            await ws.send(encode(gui_update(gui[PAUSE_AT_END], False)))
            await asyncio.sleep(0.1)
            await ws.send(encode(gui_update(gui[RUN], PLAY)))
            self.stats.played = time.monotonic()
        except Exception as exc:
            self.stats.error = f"{type(exc).__name__}: {exc}"


@dataclass
class RunFigures:
    sessions: int
    updates_per_s: list[float]
    mb_per_s: list[float]
    cpu_percent: float
    client_cpu: float
    machine_cpu: float
    errors: list[str]
    plan: PagePlan | None = None
    #: the live nodes the pages saw updated while measuring
    nodes: set[str] = field(default_factory=set)
    #: the server's resident memory at the end of the window (MB)
    server_mb: float = 0.0

    def row(self) -> str:
        u = self.updates_per_s or [0.0]
        b = self.mb_per_s or [0.0]
        return (
            f"{self.sessions:8d} {statistics.mean(u):10.1f} {min(u):9.1f} {statistics.mean(b):12.4f} {max(b):11.4f}"
            f" {self.cpu_percent:9.0f}% {self.client_cpu:9.0f}% {self.machine_cpu:8.0f}%  {len(self.errors)}"
            f"  {self.server_mb:.0f} MB"
        )

    def markdown_row(self) -> str:
        u = self.updates_per_s or [0.0]
        b = self.mb_per_s or [0.0]
        lesson = self.plan.lesson if self.plan else ""
        preset = (self.plan.preset or "(defaults)") if self.plan else ""
        return (
            f"| {lesson} | {preset} | {self.sessions} | {statistics.mean(u):.1f} | {min(u):.1f} "
            f"| {statistics.mean(b):.4f} | {self.cpu_percent:.0f}% | {len(self.errors)} |"
        )


MARKDOWN_HEAD = (
    "| lesson | preset | pages | updates/s per page (mean) | (min) | MB/s per page "
    "| server CPU (1 core = 100%) | errors |\n|---|---|---:|---:|---:|---:|---:|---:|"
)


async def count_window(
    clients: Sequence[LabClient],
    seconds: float,
    settle: float,
    start_cpu: Callable[[], None],
    read_cpu: Callable[[], T],
    ready_timeout: float = 60.0,
) -> tuple[float, T]:
    """Start the clients, wait until each plays (or failed) and ``settle`` seconds more,
    count what they receive over ``seconds``; the window's length and ``read_cpu()``
    taken at its end (``start_cpu()`` at its start)."""
    stop = asyncio.Event()
    tasks = []
    for c in clients:
        tasks.append(asyncio.create_task(c.run(stop)))
        await asyncio.sleep(0.02)
    deadline = time.monotonic() + ready_timeout
    while time.monotonic() < deadline and not all(
        c.stats.playing_update or c.stats.error for c in clients
    ):
        await asyncio.sleep(0.2)
    await asyncio.sleep(settle)
    start_cpu()
    for c in clients:
        c.measuring = True
    t0 = time.monotonic()
    await asyncio.sleep(seconds)
    dt = time.monotonic() - t0
    for c in clients:
        c.measuring = False
    reading = read_cpu()
    stop.set()
    await asyncio.gather(*tasks, return_exceptions=True)
    return dt, reading


async def measure(
    url: str,
    n: int,
    seconds: float,
    plan: PagePlan,
    server_pid: int,
    settle: float,
) -> RunFigures:
    import psutil

    clients = [LabClient(url, plan) for _ in range(n)]
    procs = (psutil.Process(server_pid), psutil.Process())

    def start_cpu() -> None:
        for p in procs:
            p.cpu_percent(None)
        psutil.cpu_percent(None)

    def read_cpu() -> tuple[float, float, float, float]:
        return (
            procs[0].cpu_percent(None),
            procs[1].cpu_percent(None),
            psutil.cpu_percent(None),
            procs[0].memory_info().rss / 1e6,
        )

    dt, (cpu, client_cpu, machine, server_mb) = await count_window(
        clients, seconds, settle, start_cpu, read_cpu
    )
    ok = [c for c in clients if not c.stats.error]
    return RunFigures(
        sessions=n,
        updates_per_s=[c.stats.updates / dt for c in ok],
        mb_per_s=[c.stats.bytes / dt / 1e6 for c in ok],
        cpu_percent=cpu,
        client_cpu=client_cpu,
        machine_cpu=machine,
        errors=[c.stats.error for c in clients if c.stats.error],
        plan=plan,
        nodes=set().union(*(c.stats.nodes for c in ok)),
        server_mb=server_mb,
    )
