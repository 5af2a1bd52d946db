"""The tests' waiting helpers: a condition's value once it holds, a failure naming what
was waited for once the deadline passes."""

from __future__ import annotations

import asyncio
import time

import pytest

from tests.support.waiting import until, wait_until


def test_wait_until_returns_the_value_and_fails_naming_what_it_waited_for() -> None:
    calls = iter([None, 0, "", "ready"])
    assert wait_until(lambda: next(calls), 5, "the third poll") == "ready"
    t0 = time.monotonic()
    with pytest.raises(AssertionError, match=r"timed out after 0.2 s waiting for the door"):
        wait_until(lambda: False, 0.2, "the door")
    assert 0.2 <= time.monotonic() - t0 < 2.0
    with pytest.raises(AssertionError, match="timed out after 0.2 s waiting for the door"):
        asyncio.run(until(lambda: [], 0.2, "the door"))
    flag: list[int] = []

    async def go() -> list[int]:
        asyncio.get_running_loop().call_later(0.1, flag.append, 1)
        return await until(lambda: flag, 5, "the loop's callback")

    assert asyncio.run(go()) == [1]  # the loop runs while it waits
