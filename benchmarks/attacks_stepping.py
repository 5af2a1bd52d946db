"""Attacks on the stepping (issue 14, attacks 1 and 7-10), measured as ratios in one run.

    python -m benchmarks.attacks_stepping [--window 4]

The server runs as a subprocess (``python -m app serve``); pages are real websocket
clients speaking viser's protocol.  A normal page plays the sphere's Example 1.1 and
counts the moving point's updates per second: its baseline, then while an attacker page
plays allowed but expensive values (attack 1: u1 = 5 sin t with the smallest step
h = 1e-5 at 8x, "pause at t_end" off, on the sphere and on the constant-speed sphere) or
values that turn non-finite (attack 7: u1 = sqrt(101 - t) past t = 101 s), then after
the attacker left; the server's memory (RSS) before and after.  The command line's attacks
(8-10) are timed with their peak memory.  Prints one README table row per attack.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from typing import Any

from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.session.session import lesson_label

from benchmarks.loadtest import (
    POINT_NODE,
    camera_message,
    decode_frame,
    encode,
    free_port,
    gui_update,
    start_server,
)

#: Texts that only the attacker's actions produce.
ATTACK_WORDS = (
    "the step is too small",
    "not finite",
    "5*sin(t)",
    "sqrt(101-t)",
    "value refused",
    "1e-05",
)
WINDOW = 4.0  # seconds of each measuring window


def strings(obj: Any) -> Iterator[str]:
    """Every string inside a decoded message."""
    if isinstance(obj, str):
        yield obj
    elif isinstance(obj, dict):
        for v in obj.values():
            yield from strings(v)
    elif isinstance(obj, (list, tuple)):
        for v in obj:
            yield from strings(v)


class Page:
    """One browser page: its widgets (label -> uuid), the moving point's updates it
    received, and every received text that contains one of :data:`ATTACK_WORDS`."""

    def __init__(self, url: str) -> None:
        self.url = url
        self.gui: dict[str, str] = {}
        self.point_updates = 0
        self.texts: list[str] = []
        self.ws: Any = None
        self.stop = asyncio.Event()
        self.task: asyncio.Task | None = None

    async def open(self) -> Page:
        import viser
        import websockets

        self.ws = await websockets.connect(
            self.url,
            subprotocols=[f"viser-v{viser.__version__}"],
            max_size=None,
            compression=None,
            open_timeout=30,
        )
        await self.ws.send(encode(camera_message()))
        self.task = asyncio.create_task(self._receive())
        await self.wait_for("Run", "Preset", "pause at t_end", "step h [s]")
        return self

    async def _receive(self) -> None:
        import zstandard

        dec = zstandard.ZstdDecompressor()
        try:
            async for raw in self.ws:
                if not isinstance(raw, bytes):
                    continue
                for m in decode_frame(raw, dec):
                    t = m.get("type", "")
                    props = m.get("props")
                    if t.startswith("Gui") and isinstance(props, dict) and "uuid" in m:
                        label = props.get("label")
                        if isinstance(label, str):
                            self.gui[label] = m["uuid"]
                    if (
                        t == "SceneNodeUpdateMessage"
                        and m.get("name") == POINT_NODE
                        and "points" in m.get("updates", {})
                    ):
                        self.point_updates += 1
                    for s in strings(m):
                        if any(w in s for w in ATTACK_WORDS):
                            self.texts.append(s)
        except Exception:
            pass

    async def wait_for(self, *labels: str, timeout: float = 30.0) -> None:
        end = time.monotonic() + timeout
        while not all(label in self.gui for label in labels):
            assert time.monotonic() < end, f"no widgets {labels} after {timeout} s"
            await asyncio.sleep(0.05)

    async def set(self, label: str, value: Any, pause: float = 0.15) -> None:
        await self.ws.send(encode(gui_update(self.gui[label], value)))
        await asyncio.sleep(pause)

    async def rate(self, seconds: float, pieces: int = 8) -> float:
        """Point updates per second over the next ``seconds``: the median of ``pieces``
        windows (a burst of load from other processes on the machine moves one window,
        not the figure)."""
        rates = []
        for _ in range(pieces):
            n0, t0 = self.point_updates, time.monotonic()
            await asyncio.sleep(seconds / pieces)
            rates.append((self.point_updates - n0) / (time.monotonic() - t0))
        return statistics.median(rates)

    async def close(self) -> None:
        await self.ws.close()
        if self.task is not None:
            await asyncio.wait_for(self.task, 10)


def rss_mb(proc: Any) -> float:
    return proc.memory_info().rss / 1e6


async def normal_page(url: str) -> Page:
    page = await Page(url).open()
    await page.set("Preset", "example-1.1", 0.5)
    await page.set("pause at t_end", False)
    await page.set("Run", "Play", 1.0)
    return page


async def attack(
    url: str,
    proc: Any,
    lesson_id: str,
    moves: list[tuple[str, Any]],
    told: str,
    window: float = WINDOW,
) -> dict[str, Any]:
    """Baseline, during and after rates of a normal page around one attacker page."""
    log_at = os.path.getsize(proc.log_path) if hasattr(proc, "log_path") else 0
    normal = await normal_page(url)
    await asyncio.sleep(1.0)
    baseline = await normal.rate(window)
    mem_before = rss_mb(proc)
    attacker = await Page(url).open()
    if lesson_id != "sphere":
        old = attacker.gui["u1(t) ="]
        await attacker.set("Lesson", lesson_label(get_lesson(lesson_id)), 0.5)
        end = time.monotonic() + 20
        while attacker.gui.get("u1(t) =") == old:
            assert time.monotonic() < end, "the lesson did not change"
            await asyncio.sleep(0.1)
        await asyncio.sleep(0.5)
    for label, value in moves:
        await attacker.set(label, value)
    # values of the wrong type: refused with a notice, no traceback on the server
    for label, value in (("step h [s]", [1, 2]), ("pause at t_end", "yes"), ("Speed", None)):
        await attacker.set(label, value, 0.05)
    # the attack is under way once its page is told (its setup, a lesson change or a
    # "go to t", is one-off work of its own page's callbacks, not the attack measured)
    end = time.monotonic() + 20
    while not any(told in s for s in attacker.texts):
        assert time.monotonic() < end, f"the attacker was not told {told!r}: {attacker.texts}"
        await asyncio.sleep(0.2)
    await asyncio.sleep(0.5)
    during = await normal.rate(window)
    await attacker.close()
    await asyncio.sleep(1.5)
    after = await normal.rate(window)
    mem_after = rss_mb(proc)
    await normal.close()
    return {
        "baseline": baseline,
        "during": during,
        "after": after,
        "mem_before": mem_before,
        "mem_after": mem_after,
        "attacker": attacker.texts,
        "normal": normal.texts,
        "log_at": log_at,
    }


TINY_STEP = [
    ("u1(t) =", "5*sin(t)"),
    ("step h [s]", "1e-5"),  # the stated minimum, typed as printed
    ("pause at t_end", False),
    ("Speed", "8x"),
    ("Run", "Play"),
]
NOT_FINITE = [
    ("u1(t) =", "sqrt(101-t)"),
    ("pause at t_end", False),
    ("Speed", "8x"),
    ("go to t [s]", "100"),
    ("Run", "Play"),
]
#: The command line's attacks: (row, arguments of ``analyzer-lab run``).
CLI_ATTACKS = [
    (
        "8: run sphere --set u1=exp(t) --t-end 1000",
        ("sphere", "--set", "u1=exp(t)", "--t-end", "1000"),
    ),
    (
        "9: run sphere --set h=1.1e-5 --t-end 100000",
        ("sphere", "--set", "h=1.1e-5", "--t-end", "100000"),
    ),
    (
        "9: run sphere --set family=24 --t-end 100000",
        ("sphere", "--set", "family=24", "--t-end", "100000"),
    ),
    (
        "9: run sphere DOP853 rtol 1e-14 --t-end 100000",
        ("sphere", "--set", "integrator=DOP853", "--set", "rtol=1e-14", "--t-end", "100000"),
    ),
    ("10: run sphere --set h=1e-5", ("sphere", "--set", "h=1e-5")),
]


def run_cli(args: tuple[str, ...]) -> tuple[int, float, float, str]:
    """``python -m app run ARGS``: exit code, seconds, peak RSS (MB), its last stderr line."""
    import psutil

    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    t0 = time.monotonic()
    proc = subprocess.Popen(
        [sys.executable, "-m", "analyzer_lab", "run", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        cwd=root,
    )
    ps = psutil.Process(proc.pid)
    peak = 0.0
    while proc.poll() is None:
        try:
            peak = max(peak, ps.memory_info().rss / 1e6)
        except psutil.Error:
            break
        time.sleep(0.05)
    err = proc.stderr.read() if proc.stderr else ""
    lines = err.strip().splitlines()
    return proc.wait(), time.monotonic() - t0, peak, lines[-1] if lines else ""


def start(log_path: str) -> tuple[str, Any, subprocess.Popen]:
    import psutil

    port = free_port()
    log = open(log_path, "w")
    proc = start_server(port, "sphere", log=log)
    server_process = psutil.Process(proc.pid)
    server_process.log_path = log_path  # type: ignore[attr-defined]
    return f"ws://127.0.0.1:{port}", server_process, proc


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.attacks_stepping", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--window", type=float, default=WINDOW, help="seconds of each window")
    args = ap.parse_args(argv)
    log_path = os.path.join(tempfile.mkdtemp(prefix="analyzer-lab-attack-"), "server.log")
    url, ps, proc = start(log_path)
    print("| attack | baseline (updates/s) | during | after | memory before/after (MB) |")
    print("|---|---|---|---|---|")
    try:
        for row, lesson_id, moves, told in (
            ("1: h = 1e-5, u1 = 5 sin t, 8x, sphere", "sphere", TINY_STEP, "the step is too small"),
            (
                "1: the same on sphere-constant-speed",
                "sphere-constant-speed",
                TINY_STEP,
                "the step is too small",
            ),
            ("7: u1 = sqrt(101 - t), 8x, past t = 101 s", "sphere", NOT_FINITE, "is not finite"),
        ):
            f = asyncio.run(attack(url, ps, lesson_id, moves, told, args.window))
            print(
                f"| {row} | {f['baseline']:.1f} | {f['during']:.1f}"
                f" ({f['during'] / f['baseline']:.0%}) | {f['after']:.1f}"
                f" ({f['after'] / f['baseline']:.0%}) | {f['mem_before']:.0f} / {f['mem_after']:.0f} |",
                flush=True,
            )
    finally:
        proc.terminate()
        proc.wait(10)
    for row, cli_args in CLI_ATTACKS:
        code, seconds, peak, line = run_cli(cli_args)
        what = f"exit {code} in {seconds:.1f} s" + (f": {line[:90]}" if code else "")
        print(f"| {row} | command line: {what} | - | - | peak {peak:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
