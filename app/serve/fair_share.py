"""The frame loop's turns shared by network address: every address that has pages open
gets the same number of turns per tick, whatever number of pages it opened.

A class behind one address (a university's NAT) shares the loop as before; a page
from another address is not slowed by one address opening hundreds of pages."""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import TypeVar

V = TypeVar("V")


def fair_order(pages: Sequence[tuple[Hashable, V]], turn: int) -> list[V]:
    """The order in which ``pages`` (``(address, page)`` pairs) get their frame on tick
    ``turn``: one page of each address in turn, the addresses and the pages within each
    address rotated by ``turn`` (under overload, when the tick's time runs out before the
    end of the list, every page still gets its turn over the next ticks)."""
    groups: dict[Hashable, list[V]] = {}
    for address, page in pages:
        groups.setdefault(address, []).append(page)
    addresses = list(groups)
    if not addresses:
        return []
    start = turn % len(addresses)
    addresses = addresses[start:] + addresses[:start]
    rotated = []
    for address in addresses:
        group = groups[address]
        k = turn % len(group)
        rotated.append(group[k:] + group[:k])
    order: list[V] = []
    depth = max(len(g) for g in rotated)
    for i in range(depth):
        order.extend(g[i] for g in rotated if i < len(g))
    return order


__all__ = ["fair_order"]
