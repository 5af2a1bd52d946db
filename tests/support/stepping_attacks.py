"""Attacks on the stepping: a normal page plays the sphere's Example 1.1 and counts the
moving point's updates per second before, while and after an attacker page on the same
server plays allowed but expensive values or values that turn non-finite; the server's
memory (RSS) before and after (run by ``tests/test_attacks_stepping.py`` and by
``python -m benchmarks.attacks_stepping``)."""

from __future__ import annotations

import asyncio
import os
import re
import statistics
import time
from collections.abc import Iterator
from typing import Any

from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.session.session import lesson_label

from tests.support.wire import POINT_NODE, camera_message, decode_frame, encode, gui_update

#: Texts that only the attacker's actions produce (the tiny step 1e-05 as a number of its
#: own, not the tail of a coordinate such as 8.70071e-05 in the normal page's readout).
ATTACK_WORDS = re.compile(
    r"the step is too small|not finite|5\*sin\(t\)|sqrt\(101-t\)|value refused"
    r"|(?<![\d.])1e-05"
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


class WatchedPage:
    """One browser page: its widgets (label -> uuid), the moving point's updates it
    received, and every received text that :data:`ATTACK_WORDS` matches."""

    def __init__(self, url: str) -> None:
        self.url = url
        self.gui: dict[str, str] = {}
        self.point_updates = 0
        self.texts: list[str] = []
        self.ws: Any = None
        self.stop = asyncio.Event()
        self.task: asyncio.Task | None = None

    async def open(self) -> WatchedPage:
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
                        if ATTACK_WORDS.search(s):
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

    async def warmed_up(self, updates: int = 60, timeout: float = 60.0) -> None:
        """Wait until the page plays steadily: ``updates`` point updates received, then two
        one-second windows whose rates differ by less than a quarter (the server's first
        frames of a lesson, and a loaded machine's, come slower)."""
        end = time.monotonic() + timeout
        while self.point_updates < updates:
            assert time.monotonic() < end, f"{self.point_updates} updates after {timeout} s"
            await asyncio.sleep(0.1)
        previous = await self.rate(1.0, 2)
        while time.monotonic() < end:
            now = await self.rate(1.0, 2)
            if previous > 0 and abs(now - previous) < 0.25 * previous:
                return
            previous = now

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


async def normal_page(url: str) -> WatchedPage:
    page = await WatchedPage(url).open()
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
    log_path: str | None = None,
) -> dict[str, Any]:
    """Baseline, during and after rates of a normal page around one attacker page
    (``proc``: the server's psutil process; ``log_at``: the size of its log before)."""
    log_at = os.path.getsize(log_path) if log_path else 0
    normal = await normal_page(url)
    await normal.warmed_up()
    # what the normal page was told before any attacker existed is its own (a slow notice
    # while the server warmed up on a loaded machine): a leak is what arrives after this
    quiet_at = len(normal.texts)
    baseline = await normal.rate(window)
    mem_before = rss_mb(proc)
    attacker = await WatchedPage(url).open()
    if lesson_id != "sphere":
        old = attacker.gui["u1(t) ="]
        await attacker.set("Lesson", lesson_label(get_lesson(lesson_id)), 0.5)
        end = time.monotonic() + 20
        while attacker.gui.get("u1(t) =") == old:
            assert time.monotonic() < end, "the lesson did not change"
            await asyncio.sleep(0.1)
        await asyncio.sleep(0.5)  # the new lesson's controls settle
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
    await asyncio.sleep(0.5)  # the attack under way before its window
    during = await normal.rate(window)
    await attacker.close()
    await asyncio.sleep(1.5)  # settled after the attacker left
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
        "normal": normal.texts[quiet_at:],
        "normal_before": normal.texts[:quiet_at],
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
