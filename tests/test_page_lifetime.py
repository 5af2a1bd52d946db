"""Pages come and go: after everyone leaves (some while their GUI was still being built,
some after playing and changing controls), the server counts no view, no classroom
entry, and the garbage collector finds no session of theirs alive."""

from __future__ import annotations

import asyncio
import gc
import time
from collections.abc import Callable
from typing import Any

import pytest

from tests.support.client import ProtoClient, play
from tests.support.waiting import until, wait_until

pytestmark = pytest.mark.live


@pytest.fixture(scope="module")
def churn_lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lesson="sphere")


def _alive(lab: Any) -> dict[str, int]:
    gc.collect()
    room = lab.classroom
    return {
        "views": len(lab.open_views()),
        "sessions": len(room.all_sessions),
        "followers": len(room.followers),
        "presenters": len(room.presenters),
        "instructors": len(room.instructors),
        "entries": len(room.entries),
    }


def _when(counts: dict[str, int], ok: Callable[[dict[str, int]], bool]) -> dict[str, int] | None:
    return counts if ok(counts) else None


async def _aborted(url: str) -> None:
    """A page that leaves while its GUI is being built."""
    c = await ProtoClient(url).start()
    await asyncio.sleep(0.05)  # the build has started
    await c.close()


async def _played(url: str) -> None:
    """A page that plays, changes a control and leaves."""
    c = await ProtoClient(url).start()
    await c.wait_for("Run", 30)
    await play(c)
    await c.set("Speed", "8x", 0.3)
    await c.close()


def test_no_session_outlives_its_page(churn_lab: Any) -> None:
    url = f"ws://127.0.0.1:{churn_lab.port}/"

    async def waves() -> int:
        opened = 0
        for _ in range(2):
            await asyncio.gather(*(_aborted(url) for _ in range(20)))
            await asyncio.gather(*(_played(url) for _ in range(8)))
            opened += 28
        return opened

    opened = asyncio.run(waves())
    assert opened == 56
    left = wait_until(
        lambda: _when(_alive(churn_lab), lambda a: not any(a.values())),
        timeout=30.0,
        what="every page's view, entry and session to be released",
    )
    assert left == dict.fromkeys(left, 0)


def test_a_page_whose_answer_was_checked_leaves_nothing(make_lab: Callable[..., Any]) -> None:
    from analyzer_lab.classroom.course import Course
    from analyzer_lab.classroom.store.sql_store import SqlStore

    store = SqlStore("sqlite://")
    course = Course(store, store.open_class("lifetime", join_code="LIFE42"), b"l" * 32)
    lab = make_lab(lesson="sphere", course=course, warm_up=False)
    url = f"ws://127.0.0.1:{lab.port}/"

    async def checked(k: int) -> None:
        c = await ProtoClient(url).start()
        await c.wait_for("Check my answer", 60)
        await c.set("Assignment", "sphere-equator", 0.3)
        await c.set("Join code", "LIFE42", 0.1)
        await c.set("Your name", f"Student {k}", 0.1)
        await c.click("Check my answer", 0.0)
        await until(
            lambda: any("al-check" in h for h in c.html.values() if "al-assignment" in h),
            90,
            "the verdict",
        )
        await c.close()

    async def go() -> None:
        await asyncio.gather(*(checked(k) for k in range(3)))

    asyncio.run(go())
    assert len(store.attempts(course.info.id)) == 3  # recorded before each page was told
    left = wait_until(
        lambda: _when(_alive(lab), lambda a: not any(a.values())),
        timeout=30.0,
        what="the checked pages' views, entries and sessions to be released",
    )
    assert left == dict.fromkeys(left, 0)


def test_a_page_that_stays_keeps_its_session(churn_lab: Any) -> None:
    url = f"ws://127.0.0.1:{churn_lab.port}/"

    async def one_stays() -> dict[str, int]:
        stay = await ProtoClient(url).start()
        await stay.wait_for("Run", 30)
        await asyncio.gather(*(_aborted(url) for _ in range(10)))
        counts = await asyncio.get_running_loop().run_in_executor(
            None,
            lambda: wait_until(
                lambda: _when(_alive(churn_lab), lambda a: a["views"] == a["sessions"] == 1),
                timeout=30.0,
                what="only the staying page's view and session",
            ),
        )
        await stay.close()
        return counts

    counts = asyncio.run(one_stays())
    assert counts["views"] == 1 and counts["sessions"] == 1


def test_pages_opened_in_hundreds_from_one_address_wait_others_open_at_once(
    churn_lab: Any,
) -> None:
    url = f"ws://127.0.0.1:{churn_lab.port}/"
    opens = churn_lab.page_opens
    queued = opens.queued

    async def flood_then_one() -> float:
        async def aborted_from_another_machine() -> None:
            c = await ProtoClient(url, source="127.0.0.2").start()
            await asyncio.sleep(0.05)  # the build has been asked for
            await c.close()

        await asyncio.gather(*(aborted_from_another_machine() for _ in range(120)))
        t = time.monotonic()
        normal = await ProtoClient(url).start()
        await normal.wait_for("Run", 60)
        took = time.monotonic() - t
        await normal.close()
        return took

    took = asyncio.run(flood_then_one())
    assert opens.queued > queued  # the flood went over the burst and waited
    assert took < 20.0
    left = wait_until(
        lambda: _when(_alive(churn_lab), lambda a: not any(a.values()) and not opens.waiting()),
        timeout=60.0,
        what="the flood's pages to be dropped or released",
    )
    assert left == dict.fromkeys(left, 0)
