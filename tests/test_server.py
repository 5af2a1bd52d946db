"""The server: frame loop on viser's event loop, callbacks of one page in arrival order.

Pages are real websocket clients speaking viser's protocol against an in-process
:class:`analyzer_lab.serve.server.LabServer`.
"""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import pytest
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
from analyzer_lab.viser_boundary import CONNECTION, OrderedExecutor

from tests.support.client import ProtoClient
from tests.support.waiting import until
from tests.support.wire import gui_update

pytestmark = pytest.mark.timeout(120)


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lessons=[SPHERE], lesson="sphere", warm_up=False, restore=False)


def test_frame_loop_runs_on_the_event_loop_and_advances_sessions(lab: Any) -> None:
    async def go() -> None:
        before = set(lab.views)
        c = await ProtoClient(lab.url).start()
        await c.wait_for("Run")
        view = lab.views[max(await until(lambda: set(lab.views) - before, 10, "the view"))]
        c.measuring = True  # count point updates from now on
        await c.send(gui_update(c.gui["Run"], "Play"))
        await until(lambda: view.session.frame.t > 0.3, 10, "playback")
        await until(lambda: c.point_updates >= 10, 10, "point updates at the page")
        await c.close()

    asyncio.run(go())
    assert not [t for t in threading.enumerate() if t.name == "analyzer-lab-frames"]
    assert lab.stats.ticks > 0


def test_messages_of_one_page_apply_in_the_order_sent(lab: Any) -> None:
    """Preset, 'pause at t_end' off and Play sent back to back by 12 pages at once: every
    session ends with the preset, the box unticked and playing (the preset's slower
    callback used to run beside the checkbox's and show the old value over it)."""

    async def go() -> None:
        before = set(lab.views)
        pages = [await ProtoClient(lab.url).start() for _ in range(12)]
        for p in pages:
            await p.wait_for("pause at t_end")
        views = await until(
            lambda: (
                len(set(lab.views) - before) >= 12
                and [lab.views[k] for k in sorted(set(lab.views) - before)]
            ),
            15,
            "the views",
        )
        await asyncio.gather(*(_burst(p) for p in pages))
        for v in views:
            await until(lambda: v.session.playing, 10, "play")
        await asyncio.sleep(0.3)  # time for a late callback to show an old value over the new
        for v in views:
            s = v.session
            assert (s.preset, s.pause_at_end, s.playing) == ("example-1.3", False, True)
            assert v.pause_cb.value is False
        await asyncio.gather(*(p.close() for p in pages))

    async def _burst(p: ProtoClient) -> None:
        await p.send(gui_update(p.gui["Preset"], "example-1.3"))
        await p.send(gui_update(p.gui["pause at t_end"], False))
        await p.send(gui_update(p.gui["Run"], "Play"))

    asyncio.run(go())


def test_ordered_executor_keeps_order_per_connection_and_runs_connections_in_parallel() -> None:
    pool = ThreadPoolExecutor(max_workers=4)
    ex = OrderedExecutor(pool)
    log: list[tuple[str, int]] = []
    lock = threading.Lock()
    started_b = threading.Event()

    def job(tag: str, k: int, delay: float) -> int:
        if tag == "b":
            started_b.set()
        time.sleep(delay)  # a slow job: the next ones of its connection wait behind it
        with lock:
            log.append((tag, k))
        return k

    futures = []
    token = CONNECTION.set(1)
    try:
        futures += [
            ex.submit(job, "a", k, 0.05 if k == 0 else 0.0) for k in range(5)
        ]  # the first one is slow
    finally:
        CONNECTION.reset(token)
    token = CONNECTION.set(2)
    try:
        futures.append(ex.submit(job, "b", 0, 0.0))
    finally:
        CONNECTION.reset(token)
    outside = ex.submit(lambda: "direct")
    assert [f.result(5) for f in futures] == [0, 1, 2, 3, 4, 0]
    assert outside.result(5) == "direct"
    assert [k for tag, k in log if tag == "a"] == [0, 1, 2, 3, 4]
    assert started_b.is_set() and log.index(("b", 0)) < log.index(
        ("a", 0)
    )  # b did not wait behind a's slow job
    failing = ex.submit(lambda: 1 / 0)
    with pytest.raises(ZeroDivisionError):
        failing.result(5)
    assert ex.pending() == 0
    pool.shutdown()


def test_the_warm_up_waits_while_a_page_is_built_and_starts_with_the_first_page_lesson(
    make_lab: Callable[..., Any],
) -> None:
    from analyzer_lab.lessons.catalog import get_lesson

    lab = make_lab(
        lessons=[get_lesson("circle"), SPHERE], lesson="sphere", warm_up=False, restore=False
    )
    lab.derivations.warm()  # the derivations' processes running: what follows is lessons
    warming = threading.Thread(target=lab.warm_up, daemon=True)
    with lab.building_page():
        warming.start()
        time.sleep(1.0)
        assert lab.warmed == [] and warming.is_alive()  # the page comes first
    warming.join(120)
    assert lab.warmed == ["sphere", "circle"]


def test_the_warm_up_leaves_a_page_just_built_a_quiet_moment(
    make_lab: Callable[..., Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A page just built has its browser draw the panel on the cores the server shares:
    the warm-up waits :data:`WARM_UP_QUIET` seconds after a build before it goes on."""
    import analyzer_lab.serve.server as server_module
    from analyzer_lab.lessons.catalog import get_lesson

    monkeypatch.setattr(server_module, "WARM_UP_QUIET", 3.0)
    lab = make_lab(
        lessons=[get_lesson("circle"), SPHERE], lesson="sphere", warm_up=False, restore=False
    )
    lab.derivations.warm()  # the derivations' processes running: what follows is lessons
    warming = threading.Thread(target=lab.warm_up, daemon=True)
    with lab.building_page():
        pass  # a page was built just now
    built = time.monotonic()
    warming.start()
    time.sleep(1.0)
    assert lab.warmed == [] and warming.is_alive()  # the page's quiet moment
    warming.join(120)
    assert lab.warmed == ["sphere", "circle"] and time.monotonic() - built >= 3.0


def test_a_fault_of_the_deferred_work_repeated_every_pass_writes_a_few_lines(
    make_lab: Callable[..., Any], caplog: pytest.LogCaptureFixture
) -> None:
    from analyzer_lab.classroom.log_limit import LOG_BURST

    lab = make_lab(lessons=[SPHERE], lesson="sphere", warm_up=False, restore=False)
    passes: list[float] = []

    def failing(view: Any, now: float) -> None:
        passes.append(now)
        raise RuntimeError("cannot start a process")

    lab._slow_work = failing

    async def go() -> None:
        page = await ProtoClient(f"http://127.0.0.1:{lab.server.get_port()}/").start()
        await until(lambda: len(passes) > 3 * LOG_BURST, 60, "the slow loop's passes")
        await page.close()

    with caplog.at_level("WARNING", logger="analyzer_lab.serve.server"):
        asyncio.run(go())
    lines = [r for r in caplog.records if "deferred work failed" in r.getMessage()]
    assert 1 <= len(lines) <= LOG_BURST + 1 < len(passes)
    assert lines[0].exc_info is not None  # the first says what went wrong


def test_the_one_run_playing_gets_the_loop_time_nobody_else_needs(lab: Any) -> None:
    from analyzer_lab.session.pace import (
        SOLO_STEP_BUDGET,
        SOLO_WALL_BUDGET,
        STEP_BUDGET,
        STEP_WALL_BUDGET,
    )

    async def go() -> None:
        before = set(lab.views)
        pages = [await ProtoClient(lab.url).start() for _ in range(2)]
        for p in pages:
            await p.wait_for("Run")
        new = await until(lambda: len(set(lab.views) - before) == 2 and set(lab.views) - before)
        a, b = (lab.views[cid] for cid in sorted(new))
        await pages[0].send(gui_update(pages[0].gui["Run"], "Play"))
        await until(lambda: a.session.playing and a.session.frame.t > 0.1, 10, "a plays")
        await until(lambda: a.session.step_budget == SOLO_STEP_BUDGET, 5, "the solo budget")
        assert a.session.wall_budget == SOLO_WALL_BUDGET
        await pages[1].send(gui_update(pages[1].gui["Run"], "Play"))
        await until(lambda: b.session.playing and b.session.frame.t > 0.1, 10, "b plays")
        await until(
            lambda: a.session.step_budget == b.session.step_budget == STEP_BUDGET,
            5,
            "the shared budget",
        )
        assert a.session.wall_budget == b.session.wall_budget == STEP_WALL_BUDGET
        for p in pages:
            await p.close()

    asyncio.run(go())
