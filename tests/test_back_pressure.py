"""Back-pressure per page: the decision (unit) and a real page that stops reading its
websocket (in-process server, real websocket clients)."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from typing import Any

import pytest
from analyzer_lab.serve.back_pressure import (
    LAG_SKIP,
    PAUSED_NOTICE,
    STALL_LAG,
    BackPressure,
    Turn,
)
from analyzer_lab.viser_boundary import send_lag

from tests.support.client import ProtoClient, play
from tests.support.waiting import until


def test_a_page_behind_is_skipped_then_paused_and_forgiven_when_it_reads() -> None:
    bp = BackPressure(skip_lag=100, pause_after=5.0)
    assert bp.turn(1, 99, 0.0, True) is Turn.DRAW
    assert bp.turn(1, 100, 1.0, True) is Turn.SKIP
    assert bp.turn(1, 500, 5.9, True) is Turn.SKIP
    assert bp.turn(1, 500, 6.0, True) is Turn.PAUSE
    assert bp.turn(1, 500, 7.0, False) is Turn.SKIP  # paused already: only skipped
    assert bp.turn(1, 3, 8.0, False) is Turn.DRAW  # it reads again
    assert bp.turn(1, 100, 9.0, True) is Turn.SKIP  # behind again: the clock starts over
    assert bp.turn(2, 0, 9.0, True) is Turn.DRAW  # another page is not concerned
    bp.forget(1)
    assert bp.behind_since == {}


def test_a_page_whose_sender_takes_nothing_is_behind_long_before_the_lag_limit() -> None:
    bp = BackPressure(skip_lag=2000, stall_lag=100, stall_after=1.0, pause_after=5.0)
    # a reading page: its sender takes messages, whatever is waiting
    for k in range(20):
        assert bp.turn(1, 500, 0.1 * k, True, taken=10 * k) is Turn.DRAW
    # it stops reading: messages wait and the sender takes none
    assert bp.turn(1, 150, 2.0, True, taken=190) is Turn.DRAW
    assert bp.turn(1, 300, 2.9, True, taken=190) is Turn.DRAW
    assert bp.turn(1, 320, 3.0, True, taken=190) is Turn.SKIP
    assert bp.turn(1, 320, 7.9, True, taken=190) is Turn.SKIP
    assert bp.turn(1, 320, 8.0, True, taken=190) is Turn.PAUSE
    # it reads again: drawn at once
    assert bp.turn(1, 320, 8.1, False, taken=200) is Turn.DRAW
    # an idle page (nothing waits) is never behind, and a burst after a long idle time
    # starts the stall clock afresh
    assert bp.turn(2, 0, 0.0, True, taken=5) is Turn.DRAW
    assert bp.turn(2, 99, 50.0, True, taken=5) is Turn.DRAW
    assert bp.turn(2, 400, 50.1, True, taken=5) is Turn.DRAW
    assert bp.turn(2, 400, 51.1, True, taken=5) is Turn.SKIP
    bp.forget(2)
    assert 2 not in bp.taken


@pytest.fixture(scope="module")
def pressure_lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lesson="sphere")


@pytest.mark.live
def test_a_page_that_stops_reading_is_held_back_and_paused_others_play_on(
    pressure_lab: Any,
) -> None:
    lab = pressure_lab
    url = f"ws://127.0.0.1:{lab.port}/"

    async def go() -> None:
        normal = await ProtoClient(url).start()
        await normal.wait_for("Run", 30)
        await play(normal)
        # another machine's page that draws a lot, then never reads again
        stalled = await ProtoClient(url, source="127.0.0.2", rcvbuf=4096).start()
        await stalled.wait_for("Run", 30)
        await stalled.set("curves in the family", 24, 0.2)
        await play(stalled)
        await stalled.set("Speed", "8x", 0.3)
        ids = {v.session: cid for cid, v in lab.views.items()}
        stalled_id = max(lab.views)
        assert lab._addresses[stalled_id] == "127.0.0.2"
        stalled.stop_reading()
        view = lab.views[stalled_id]
        await until(lambda: not view.session.playing, 90.0, "the stalled page to be paused")
        # held back: nothing more is queued for it
        lag = send_lag(lab.server, stalled_id)
        assert STALL_LAG <= lag <= LAG_SKIP + 100, lag
        t_sim = view.session.stepper.t
        normal.measuring = True
        before = normal.point_updates
        await asyncio.sleep(2.0)  # the normal page plays meanwhile
        assert normal.point_updates - before > 10
        assert send_lag(lab.server, stalled_id) <= lag + 20
        assert view.session.stepper.t == t_sim
        assert lab.back_pressure.paused >= 1
        assert all(s.playing for s, cid in ids.items() if cid != stalled_id)
        # the page reads again: it is told why it was paused
        stalled.ws.transport.resume_reading()
        start = time.monotonic()
        await until(
            lambda: any("has not been taking its updates" in n for n in stalled.notifications),
            30.0,
            "the paused page's notice",
        )
        assert time.monotonic() - start < 30.0
        assert PAUSED_NOTICE.startswith("Playback paused")
        await stalled.close()
        await normal.close()

    asyncio.run(go())
