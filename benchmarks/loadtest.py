"""Load test: N simultaneous sessions, each a real websocket client speaking viser's protocol.

    python -m benchmarks.loadtest --sessions 1 10 30 50 [--seconds 10] [--lesson sphere --preset example-1.1]

The server runs as a subprocess (``python -m app serve``).  Each client connects with
viser's subprotocol, sends a camera message (which makes it a connected client),
picks the preset and presses Play through GUI update messages, then counts what it
receives: websocket frames that carry an update of the moving point (updates/s)
and bytes (MB/s).  Server CPU comes from psutil on the server process.

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
from dataclasses import dataclass, field
from typing import Any

POINT_NODE = "/lab/live/point/point"


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


@dataclass
class ClientStats:
    frames: int = 0
    bytes: int = 0
    point_updates: int = 0
    gui: dict[str, str] = field(default_factory=dict)  # label -> uuid
    connected: float = 0.0
    played: float = 0.0  # when Play was sent
    playing_update: float = 0.0  # first point update well after Play
    error: str = ""


class LabClient:
    """One simulated student."""

    def __init__(self, url: str, preset: str | None, lesson_label: str | None) -> None:
        self.url = url
        self.preset = preset
        self.lesson_label = lesson_label
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
                started = False
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
                    point = False
                    for m in decode_frame(raw, dec):
                        t = m.get("type", "")
                        if (
                            t.startswith("Gui")
                            and t.endswith("Message")
                            and isinstance(m.get("props"), dict)
                        ):
                            label = m["props"].get("label")
                            if isinstance(label, str) and "uuid" in m:
                                self.stats.gui[label] = m["uuid"]
                        elif (
                            t == "SceneNodeUpdateMessage"
                            and m.get("name") == POINT_NODE
                            and "points" in m.get("updates", {})
                        ):
                            point = True
                    if self.measuring:
                        self.stats.frames += 1
                        self.stats.bytes += len(raw)
                        self.stats.point_updates += point
                    now = time.monotonic()
                    if (
                        point
                        and self.stats.played
                        and not self.stats.playing_update
                        and now > self.stats.played + 0.5
                    ):
                        self.stats.playing_update = now
                    if not started and all(
                        k in self.stats.gui for k in ("Run", "Preset", "pause at t_end")
                    ):
                        started = True
                        asyncio.get_running_loop().create_task(self._start(ws))
        except Exception as exc:  # reported in the table
            self.stats.error = f"{type(exc).__name__}: {exc}"

    async def _start(self, ws: Any) -> None:
        if self.lesson_label and "Lesson" in self.stats.gui:
            await ws.send(encode(gui_update(self.stats.gui["Lesson"], self.lesson_label)))
            await asyncio.sleep(1.0)
        if self.preset:
            await ws.send(encode(gui_update(self.stats.gui["Preset"], self.preset)))
            await asyncio.sleep(0.3)
        # keep playing past the textbook's 10 s
        await ws.send(encode(gui_update(self.stats.gui["pause at t_end"], False)))
        await asyncio.sleep(0.1)
        await ws.send(encode(gui_update(self.stats.gui["Run"], "Play")))
        self.stats.played = time.monotonic()


@dataclass
class RunFigures:
    sessions: int
    updates_per_s: list[float]
    mb_per_s: list[float]
    cpu_percent: float
    client_cpu: float
    machine_cpu: float
    errors: list[str]

    def row(self) -> str:
        u = self.updates_per_s or [0.0]
        b = self.mb_per_s or [0.0]
        return (
            f"{self.sessions:8d} {statistics.mean(u):10.1f} {min(u):9.1f} {statistics.mean(b):12.4f} {max(b):11.4f}"
            f" {self.cpu_percent:9.0f}% {self.client_cpu:9.0f}% {self.machine_cpu:8.0f}%  {len(self.errors)}"
        )


async def measure(
    url: str,
    n: int,
    seconds: float,
    preset: str | None,
    lesson_label: str | None,
    server_pid: int,
    settle: float,
) -> RunFigures:
    import psutil

    stop = asyncio.Event()
    clients = [LabClient(url, preset, lesson_label) for _ in range(n)]
    tasks = []
    for c in clients:
        tasks.append(asyncio.create_task(c.run(stop)))
        await asyncio.sleep(0.02)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not all(
        c.stats.playing_update or c.stats.error for c in clients
    ):
        await asyncio.sleep(0.2)
    await asyncio.sleep(settle)
    proc = psutil.Process(server_pid)
    me = psutil.Process()
    proc.cpu_percent(None)
    me.cpu_percent(None)
    psutil.cpu_percent(None)
    for c in clients:
        c.measuring = True
    t0 = time.monotonic()
    await asyncio.sleep(seconds)
    dt = time.monotonic() - t0
    for c in clients:
        c.measuring = False
    cpu = proc.cpu_percent(None)
    client_cpu = me.cpu_percent(None)
    machine = psutil.cpu_percent(None)
    stop.set()
    await asyncio.gather(*tasks, return_exceptions=True)
    return RunFigures(
        sessions=n,
        updates_per_s=[c.stats.point_updates / dt for c in clients if not c.stats.error],
        mb_per_s=[c.stats.bytes / dt / 1e6 for c in clients if not c.stats.error],
        cpu_percent=cpu,
        client_cpu=client_cpu,
        machine_cpu=machine,
        errors=[c.stats.error for c in clients if c.stats.error],
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
    ap.add_argument("--preset", default="example-1.1")
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
    if args.clients_only:
        for n in args.sessions:
            fig = asyncio.run(
                measure(
                    f"ws://127.0.0.1:{args.clients_only}/",
                    n,
                    args.seconds,
                    args.preset,
                    None,
                    args.server_pid or os.getpid(),
                    args.settle,
                )
            )
            print(fig.row(), flush=True)
            print(sorted(round(u, 1) for u in fig.updates_per_s))
        return 0
    port = free_port()
    log = open(args.server_log, "w") if args.server_log else subprocess.DEVNULL
    proc = start_server(
        port, args.lesson, log, extra_args=("--fps", str(args.fps)) if args.fps else ()
    )
    url = f"ws://127.0.0.1:{port}/"
    print(
        f"server pid {proc.pid} on port {port}; lesson {args.lesson}, preset {args.preset}; {os.cpu_count()} cores"
        + (f"; server at {args.fps:g} frames/s" if args.fps else "")
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
            fig = asyncio.run(
                measure(url, n, args.seconds, args.preset, None, proc.pid, args.settle)
            )
            print(fig.row(), flush=True)
            for e in fig.errors[:3]:
                print("   ", e)
            time.sleep(1.0)
    finally:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
