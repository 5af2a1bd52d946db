"""Load test: N simultaneous sessions, each a real websocket client speaking viser's protocol.

    python -m benchmarks.loadtest --sessions 1 10 30 50 [--seconds 10] [--lesson sphere] [--preset P]
    python -m benchmarks.loadtest --all-lessons --sessions 50 [--seconds 10]

The server runs as a subprocess (``python -m app serve``).  Each client connects with
viser's subprotocol, sends a camera message (which makes it a connected client),
selects the lesson and its preset (the lesson's first unless ``--preset``) in the
page's pickers, unticks "pause at t_end" and presses Play through GUI update messages,
then counts what it receives: websocket frames that carry an update of the lesson's
live scene (any node under :data:`analyzer_lab.view.scene.LIVE_ROOT`: moving points, trails,
vectors, posed bodies), once per frame (updates/s), and bytes (MB/s).  Server CPU
comes from psutil on the server process.  ``--all-lessons`` measures every lesson of
the catalog in turn, each on a fresh server, and prints one markdown table.

Wire format of a server frame (viser ``_message_producer``): 8 bytes msgpack length,
8 bytes compressed length, a zstd-compressed msgpack ``{"messages": [...]}``, then
raw binary buffers.  Client messages are plain msgpack dicts with a ``type``.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from analyzer_lab.view.page import LESSON_PICKER, PAUSE_AT_END, PRESET_PICKER
from analyzer_lab.view.scene import LIVE_ROOT, live_node
from analyzer_lab.view.transport import PLAY, RUN

#: The moving point of the quadric lessons (sphere, example 1.1), as the classroom counts it.
POINT_NODE = live_node("point", "point")
#: Messages that change an existing scene node (besides the messages that create one).
NODE_UPDATES = frozenset({"SceneNodeUpdateMessage", "SetPositionMessage", "SetOrientationMessage"})

T = TypeVar("T")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def encode(message: Any) -> bytes:
    import msgspec

    return msgspec.msgpack.encode(message.as_serializable_dict())


def camera_message() -> Any:
    from viser import _messages

    return _messages.ViewerCameraMessage(
        wxyz=(1.0, 0.0, 0.0, 0.0),
        position=(3.0, 3.0, 3.0),
        fov=1.0,
        near=0.01,
        far=100.0,
        image_height=720,
        image_width=1280,
        look_at=(0.0, 0.0, 0.0),
        up_direction=(0.0, 0.0, 1.0),
    )


def gui_update(uuid: str, value: Any) -> Any:
    from viser import _messages

    return _messages.GuiUpdateMessage(uuid=uuid, updates={"value": value})


def decode_frame(raw: bytes, decompressor: Any = None) -> list[dict[str, Any]]:
    """The messages of one server frame (binary buffers are not decoded)."""
    import msgspec
    import zstandard

    inner = int.from_bytes(raw[0:8], "little")
    comp = int.from_bytes(raw[8:16], "little")
    payload = (decompressor or zstandard.ZstdDecompressor()).decompress(
        raw[16 : 16 + comp], max_output_size=inner
    )
    return list(msgspec.msgpack.decode(payload).get("messages", ()))


def live_update(message: dict[str, Any]) -> bool:
    """Does this message draw part of a played frame (create or update a node under
    :data:`LIVE_ROOT`)?  Removals do not count."""
    name = message.get("name")
    if not isinstance(name, str) or not name.startswith(LIVE_ROOT + "/"):
        return False
    kind = message.get("type", "")
    return kind in NODE_UPDATES or (
        kind.endswith("Message") and isinstance(message.get("props"), dict)
    )


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

    def row(self) -> str:
        u = self.updates_per_s or [0.0]
        b = self.mb_per_s or [0.0]
        return (
            f"{self.sessions:8d} {statistics.mean(u):10.1f} {min(u):9.1f} {statistics.mean(b):12.4f} {max(b):11.4f}"
            f" {self.cpu_percent:9.0f}% {self.client_cpu:9.0f}% {self.machine_cpu:8.0f}%  {len(self.errors)}"
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

    def read_cpu() -> tuple[float, float, float]:
        return procs[0].cpu_percent(None), procs[1].cpu_percent(None), psutil.cpu_percent(None)

    dt, (cpu, client_cpu, machine) = await count_window(
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
    )


def start_server(
    port: int, lesson: str, log: Any = subprocess.DEVNULL, extra_args: tuple[str, ...] = ()
) -> subprocess.Popen:
    """``python -m app serve`` (plus ``extra_args``) in a subprocess; returns when HTTP answers."""
    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("ANALYZER_LAB_STATS", "5")
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "app",
            "serve",
            "--host",
            "127.0.0.1",
            "--port",
            str(port),
            "--no-browser",
            "--lesson",
            lesson,
            *extra_args,
        ],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=log,
        cwd=root,
    )
    import urllib.request

    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        try:
            urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1).read(100)
            return proc
        except Exception:
            if proc.poll() is not None:
                raise RuntimeError(f"the server exited with code {proc.returncode}")
            time.sleep(0.1)
    proc.kill()
    raise RuntimeError("the server did not answer within 30 s")


def stop_server(proc: subprocess.Popen) -> None:
    proc.terminate()
    try:
        proc.wait(5)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(5)


def all_lessons_table(
    sessions: Sequence[int], seconds: float, settle: float, fps: float | None, log: Any
) -> None:
    """Every lesson of the catalog with its first preset, each on a fresh server: one
    markdown table (a row per lesson and number of pages)."""
    from analyzer_lab.lessons.catalog import all_lessons

    extra = ("--fps", str(fps)) if fps else ()
    print(f"{os.cpu_count()} cores; {seconds:g} s per run" + (f"; {fps:g} frames/s" if fps else ""))
    print(MARKDOWN_HEAD, flush=True)
    for lesson in all_lessons():
        plan = page_plan(lesson.id)
        port = free_port()
        proc = start_server(port, lesson.id, log, extra_args=extra)
        try:
            for n in sessions:
                fig = asyncio.run(
                    measure(f"ws://127.0.0.1:{port}/", n, seconds, plan, proc.pid, settle)
                )
                print(fig.markdown_row(), flush=True)
                for e in fig.errors[:3]:
                    print("   ", e, file=sys.stderr)
                time.sleep(1.0)
        finally:
            stop_server(proc)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.loadtest", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--sessions", type=int, nargs="+", default=[1, 10, 30, 50])
    ap.add_argument("--seconds", type=float, default=10.0, help="measuring window per run")
    ap.add_argument(
        "--settle", type=float, default=3.0, help="seconds after the last client started playing"
    )
    ap.add_argument("--lesson", default="sphere")
    ap.add_argument("--preset", default=None, help="default: the lesson's first preset")
    ap.add_argument(
        "--all-lessons",
        action="store_true",
        help="every lesson in turn (its first preset), a fresh server each; one markdown table",
    )
    ap.add_argument(
        "--fps",
        type=float,
        default=None,
        help="the server's frame rate (serve --fps; default: its own)",
    )
    ap.add_argument(
        "--server-log", default="", help="file for the server's stderr (loop figures every 5 s)"
    )
    ap.add_argument(
        "--clients-only",
        type=int,
        default=0,
        metavar="PORT",
        help="measure a server already running on this port (with --server-pid for its CPU)",
    )
    ap.add_argument("--server-pid", type=int, default=0)
    args = ap.parse_args(argv)
    log = open(args.server_log, "w") if args.server_log else subprocess.DEVNULL
    if args.all_lessons:
        all_lessons_table(args.sessions, args.seconds, args.settle, args.fps, log)
        return 0
    plan = page_plan(args.lesson, args.preset)
    if args.clients_only:
        for n in args.sessions:
            fig = asyncio.run(
                measure(
                    f"ws://127.0.0.1:{args.clients_only}/",
                    n,
                    args.seconds,
                    plan,
                    args.server_pid or os.getpid(),
                    args.settle,
                )
            )
            print(fig.row(), flush=True)
            print(sorted(round(u, 1) for u in fig.updates_per_s))
        return 0
    port = free_port()
    proc = start_server(
        port, args.lesson, log, extra_args=("--fps", str(args.fps)) if args.fps else ()
    )
    url = f"ws://127.0.0.1:{port}/"
    print(
        f"server pid {proc.pid} on port {port}; lesson {plan.lesson}, preset {plan.preset}; "
        f"{os.cpu_count()} cores" + (f"; server at {args.fps:g} frames/s" if args.fps else "")
    )
    print(
        f"{'sessions':>8} {'updates/s':>10} {'min':>9} {'MB/s/client':>12} {'max MB/s':>11} "
        f"{'server CPU':>10} {'clients':>10} {'machine':>9}  errors"
    )
    print(
        f"{'':>8} {'(mean)':>10} {'':>9} {'(mean)':>12} {'':>11} {'(1 core=100%)':>10} {'CPU':>10} {'(all cores)':>9}"
    )
    try:
        for n in args.sessions:
            fig = asyncio.run(measure(url, n, args.seconds, plan, proc.pid, args.settle))
            print(fig.row(), flush=True)
            for e in fig.errors[:3]:
                print("   ", e)
            time.sleep(1.0)
    finally:
        stop_server(proc)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
