"""A long page callback against the shared GUI budget, with real websocket pages (viser's
protocol) on ``python -m analyzer_lab serve`` in a subprocess.

One page plays a family of 24 curves at 8x, then downloads its grid as CSV and as JSON
(two exports of a few CPU seconds each); another page keeps using its controls (a
negative grid step typed and refused: a page callback answered by a notice).  The export
is charged to the budget as it runs, so the other page's controls answer within a second
during the export and right after it (charged only at its end, the export left the
budget spent for its CPU seconds / 0.2 afterwards: every page's controls waited that
long).  Prints one row of the README's table (``pytest -s``).
"""

from __future__ import annotations

import asyncio
import itertools
import statistics
import time
from collections.abc import Callable, Iterator

import pytest

from tests.support.client import ProtoClient
from tests.support.servers import ServeProcess
from tests.support.waiting import until

pytestmark = [pytest.mark.live, pytest.mark.timeout(600)]

STEP = "grid step [s]"
CSV = "Download CSV (grid)"
JSON = "Download JSON (grid)"
DOWNLOAD = "FileTransferStartDownload"


@pytest.fixture(scope="module")
def server(serve: Callable[..., ServeProcess]) -> Iterator[ServeProcess]:
    live = serve("sphere")
    live.wait_warm()
    yield live


async def _page(url: str) -> ProtoClient:
    c = await ProtoClient(url).start()
    await c.wait_for(STEP, 60)
    return c


_PROBES = itertools.count(1)


async def _answer(c: ProtoClient) -> float:
    """Seconds from a click on "Download CSV (grid)" with a negative grid step (a new one
    each time: a page shows a refusal once) to the refusal's notice."""
    step = f"-{next(_PROBES)}"
    await c.set(STEP, step, 0)
    seen = len(c.notifications)
    t = time.monotonic()
    await c.click(CSV, 0)
    await until(lambda: any(f"got {step}" in n for n in c.notifications[seen:]), 120, "the refusal")
    return time.monotonic() - t


def test_a_long_export_leaves_other_pages_controls_answering(server: ServeProcess) -> None:
    async def go() -> None:
        exporter = await _page(server.url)
        await exporter.set("Preset", "example-1.1", 0.3)
        await exporter.set("curves in the family", 24, 0.2)
        await exporter.set("Speed", "8x", 0.1)
        await exporter.set("pause at t_end", False, 0.1)
        await exporter.set("Run", "Play", 0.1)
        other = await _page(server.url)
        base = [await _answer(other) for _ in range(5)]
        await asyncio.sleep(6.0)  # the family plays on (about 48 s of the lesson at 8x)
        await exporter.set("Run", "Pause", 0.3)
        # at most 64 s / 0.04 s = 1600 rows x 220 columns (under the 400,000 values)
        await exporter.set(STEP, "0.04", 0.2)
        before = exporter.seen.get(DOWNLOAD, 0)
        t0 = time.monotonic()
        await exporter.click(CSV, 0)
        await exporter.click(JSON, 0)
        during: list[float] = []
        while exporter.seen.get(DOWNLOAD, 0) < before + 2:
            assert time.monotonic() - t0 < 400, "the exports did not arrive"
            during.append(await _answer(other))
            await asyncio.sleep(0.2)  # the page's next input
        took = time.monotonic() - t0
        after = [await _answer(other) for _ in range(8)]
        row = (
            f"| a long export (grid CSV + JSON, family of 24 at 8x, {took:.1f} s) against"
            f" another page's controls | {statistics.median(base):.2f} s"
            f" | {max(during):.2f} s (median {statistics.median(during):.2f})"
            f" | {max(after):.2f} s (first {after[0]:.2f}) |"
        )
        print(row, flush=True)
        assert exporter.error == "" and other.error == "", (exporter.error, other.error)
        assert len(during) >= 3, row
        slowest = max(during + after)
        # about a second, whatever the export's length (and at most a small part of it:
        # paid at its end, the export held them for most of its own time afterwards)
        assert slowest < max(2.0, 3 * statistics.median(base)), row
        assert slowest < 0.3 * took, row
        await exporter.close()
        await other.close()

    asyncio.run(go())
