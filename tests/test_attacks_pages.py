"""Attacks by pages from another address (127.0.0.2) against ``python -m analyzer_lab
serve`` in a subprocess, measured like :mod:`tests.test_attacks_transport` (a normal page's
updates/s before, during and after; the server's memory), on a server of their own: pages
that leave while their GUI is built, and pages that stop reading their websocket.
(:mod:`tests.test_back_pressure` holds what one page that stops reading is told.)"""

from __future__ import annotations

import asyncio
import re
import subprocess
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from tests.support.servers import ServeProcess
from tests.support.waiting import until
from tests.test_attacks_transport import ROWS, STALLED_PAGES, _measured, _rss, warmed_server


@pytest.fixture(scope="module")
def live(serve: Callable[..., ServeProcess]) -> Iterator[ServeProcess]:
    served = warmed_server(serve)
    yield served
    for row in ROWS:
        print(row)


@pytest.fixture(scope="module")
def server(live: ServeProcess) -> tuple[str, subprocess.Popen]:
    return live.url, live.proc


def _reports(live: ServeProcess, kind: str) -> list[dict[str, int]]:
    """The server's ``[loop]`` or ``[classroom]`` lines so far (``ANALYZER_LAB_STATS``),
    each as its numbers by name."""
    found = []
    for line in live.log_path.read_text(errors="replace").splitlines():
        if line.startswith(f"[{kind}] "):
            pairs = re.findall(r"([a-z_/]+) (-?\d+)\b", line[len(kind) + 3 :])
            found.append({k: int(v) for k, v in pairs})
    return found


def test_pages_leaving_mid_build_do_not_slow_the_class(server: Any) -> None:
    async def go() -> None:
        _, figures, _ = await _measured(server, "churn: 300 pages leave mid-build", 15.0)
        assert figures["aborted"] >= 300, figures

    asyncio.run(go())


def test_pages_that_stop_reading_do_not_slow_the_class_or_keep_memory(
    live: ServeProcess,
) -> None:
    """100 pages from another address play a family of 24 curves at 8x, stop reading
    their websocket, and drop off after a while: the normal page plays on, the server
    counts only the pages still connected and gives their memory back."""
    seen: dict[str, Any] = {}

    async def settled() -> None:
        # the pages have left: wait for the server's own figures to say so (a classroom
        # report made after they left counts one view and one live session, the normal
        # page's) and for the heap to be trimmed once after that
        classroom0, trims0 = len(_reports(live, "classroom")), _reports(live, "loop")[-1]["trims"]

        def back() -> dict[str, int] | None:
            rooms, loops = _reports(live, "classroom")[classroom0:], _reports(live, "loop")
            if not rooms or loops[-1]["trims"] <= trims0:
                return None
            last = rooms[-1]
            return last if last["views"] == 1 and last["sessions_alive"] == 1 else None

        try:
            seen["left"] = await until(back, 90.0, "the server to count only the normal page")
        except AssertionError as exc:
            last = _reports(live, "classroom")[-1:], _reports(live, "loop")[-1:]
            raise AssertionError(f"{exc}; its last figures: {last}") from None

    async def set_up(normal: Any) -> None:
        # the attackers' pages are open and their settings sent: the baseline is measured
        # once the server has built them all and run the inputs they sent (two reports)
        reports = len(_reports(live, "classroom"))

        def quiet() -> bool:
            rooms = _reports(live, "classroom")[reports:]
            return len(rooms) >= 2 and all(
                r["views"] == r["sessions_alive"] == STALLED_PAGES + 1 and r["pending"] == 0
                for r in rooms[-2:]
            )

        await until(quiet, 180.0, "the attackers' pages to be built and set up")

    async def go() -> None:
        seen["opened"] = _rss(live.proc)  # before the attackers' pages open
        _, figures, rates = await _measured(
            (live.url, live.proc),
            f"stalled: {STALLED_PAGES} pages stop reading",
            20.0,
            settled=settled,
            before=set_up,
            ready_timeout=240.0,
        )
        assert figures["pages"] == STALLED_PAGES, figures
        print(
            "after they left:",
            seen["left"],
            rates,
            f"before they opened: {seen['opened']:.0f} MB",
            flush=True,
        )
        left = seen["left"]
        assert left["followers"] == 0 and left["presenters"] == left["entries"] == 1, left

    asyncio.run(go())
