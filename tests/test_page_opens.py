"""Page builds admitted by network address: a burst at once, the rest at the rate."""

from __future__ import annotations

import time

from analyzer_lab.serve.page_opens import PageOpens


def test_a_burst_is_built_at_once_the_rest_waits_in_order() -> None:
    opens = PageOpens(rate=1000.0, burst=3.0)
    assert [opens.admit("a", k, f"a{k}") for k in range(3)] == [True] * 3
    assert opens.admit("a", 3, "a3") is False
    assert opens.admit("a", 4, "a4") is False
    assert opens.admit("b", 0, "b0") is True  # another address is not concerned
    time.sleep(0.01)  # 10 tokens at 1000/s
    assert opens.due() == ["a3", "a4"]
    assert opens.waiting() == 0 and opens.queued == 2


def test_a_page_waiting_its_turn_keeps_its_place_behind_the_queue() -> None:
    opens = PageOpens(rate=1e-6, burst=1.0)
    assert opens.admit("a", 1, "p1")
    assert not opens.admit("a", 2, "p2")
    assert opens.due() == []  # no token yet
    assert opens.waiting() == 1


def test_a_page_that_leaves_while_waiting_is_never_built() -> None:
    opens = PageOpens(rate=1e-6, burst=1.0)
    opens.admit("a", 1, "p1")
    opens.admit("a", 2, "p2")
    opens.admit("a", 3, "p3")
    assert opens.drop(2) is True
    assert opens.drop(2) is False  # once
    assert opens.drop(1) is False  # built already, not waiting
    assert opens.waiting() == 1


def test_the_addresses_remembered_are_bounded() -> None:
    opens = PageOpens(rate=1.0, burst=1.0, max_addresses=10)
    for k in range(100):
        opens.admit(f"10.0.0.{k}", k, k)
    assert len(opens._buckets) == 10
