"""The heap is trimmed once pages stop closing (:mod:`analyzer_lab.serve.heap`)."""

from __future__ import annotations

import asyncio
import time
from typing import Any

from analyzer_lab.serve.heap import HeapTrim

from tests.support.client import ProtoClient
from tests.support.waiting import wait_until


class Clock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_nothing_closed_nothing_trimmed() -> None:
    clock = Clock()
    heap = HeapTrim(quiet=2.0, every=10.0, clock=clock)
    clock.t += 60.0
    assert not heap.poll(building=False) and heap.trims == 0


def test_a_burst_is_trimmed_once_when_it_is_over() -> None:
    clock = Clock()
    heap = HeapTrim(quiet=2.0, every=10.0, clock=clock)
    for _ in range(30):
        heap.page_closed()
        clock.t += 0.1
    assert not heap.poll(building=False)  # the last page closed 0.1 s ago
    clock.t += 2.0
    assert not heap.poll(building=True)  # pages are being built
    assert heap.poll(building=False) and heap.trims == 1
    clock.t += 5.0
    assert not heap.poll(building=False) and heap.trims == 1  # nothing closed since


def test_trims_are_at_least_every_seconds_apart() -> None:
    clock = Clock()
    heap = HeapTrim(quiet=2.0, every=10.0, clock=clock)
    heap.page_closed()
    clock.t += 2.0
    assert heap.poll(building=False)
    heap.page_closed()
    clock.t += 3.0
    assert not heap.poll(building=False)  # 3 s after the last trim
    clock.t += 7.0
    assert heap.poll(building=False) and heap.trims == 2


def test_the_server_trims_after_pages_leave_mid_build(lab: Any) -> None:
    url = f"ws://127.0.0.1:{lab.port}/"
    before = lab.heap.trims

    async def leave() -> None:
        c = await ProtoClient(url).start()
        await asyncio.sleep(0.05)  # the build has been asked for
        await c.close()

    async def go() -> None:
        await asyncio.gather(*(leave() for _ in range(20)))

    asyncio.run(go())
    wait_until(lambda: lab.heap.trims > before, timeout=60.0, what="a trim after the pages left")
    with lab._views_lock:
        assert lab._building == 0
    time.sleep(0.5)
    assert lab.heap.trims == before + 1  # once for the burst


def test_a_c_library_without_malloc_trim_counts_no_trim(monkeypatch: Any) -> None:
    import analyzer_lab.serve.heap as heap_module

    monkeypatch.setattr(heap_module, "return_free_memory", lambda: False)
    clock = Clock()
    heap = HeapTrim(quiet=2.0, every=10.0, clock=clock)
    heap.page_closed()
    clock.t += 2.0
    assert not heap.poll(building=False) and heap.trims == 0


def test_glibc_returns_the_free_memory() -> None:
    from analyzer_lab.limits import return_free_memory

    assert return_free_memory() is True
