"""The frame loop's turns shared by network address."""

from __future__ import annotations

from analyzer_lab.serve.fair_share import fair_order


def test_every_address_gets_a_turn_before_any_gets_a_second() -> None:
    pages = [("a", f"a{k}") for k in range(5)] + [("b", "b0")]
    order = fair_order(pages, 0)
    assert sorted(order) == sorted(p for _, p in pages)
    assert set(order[:2]) == {"a0", "b0"}


def test_a_lone_page_is_within_the_first_two_on_every_tick() -> None:
    pages = [("crowd", f"c{k}") for k in range(300)] + [("normal", "n")]
    for turn in range(0, 2000, 7):
        assert fair_order(pages, turn).index("n") <= 1


def test_rotation_lets_every_page_of_a_crowd_go_first_in_turn() -> None:
    pages = [("crowd", f"c{k}") for k in range(4)]
    firsts = {fair_order(pages, turn)[0] for turn in range(4)}
    assert firsts == {"c0", "c1", "c2", "c3"}


def test_no_pages_no_order() -> None:
    assert fair_order([], 3) == []
