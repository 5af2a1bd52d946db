"""A live table sent by rows: one HTML element per row, so a changed row is the only
thing sent to the page (a class of 200 does not re-send 200 rows on every check).

Rows keep their order through the elements' ``order`` values, placed between two
bounds of their folder: a new or moved row takes a value between its neighbours, the
rows already in order keep theirs (they are not sent again)."""

from __future__ import annotations

import bisect
from collections.abc import Callable, Hashable, Sequence
from typing import Any

#: Smallest gap between two rows' order values before every row is renumbered.
MIN_GAP = 1e-9

#: ``add(content, order)`` -> a new HTML element of the table's folder.
AddRow = Callable[[str, float], Any]


def _kept(orders: Sequence[float | None]) -> set[int]:
    """Indices of the longest run of existing order values already increasing (they stay)."""
    tails: list[float] = []
    tail_index: list[int] = []
    parent: dict[int, int] = {}
    for i, o in enumerate(orders):
        if o is None:
            continue
        k = bisect.bisect_left(tails, o)
        if k > 0:
            parent[i] = tail_index[k - 1]
        if k == len(tails):
            tails.append(o)
            tail_index.append(i)
        else:
            tails[k] = o
            tail_index[k] = i
    kept: set[int] = set()
    i = tail_index[-1] if tail_index else -1
    while i >= 0:
        kept.add(i)
        i = parent.get(i, -1)
    return kept


class RowTable:
    """Rows by key; :meth:`show` sends only what changed and returns how many elements
    it sent (new, changed or moved rows)."""

    def __init__(self, add: AddRow, lo: float, hi: float) -> None:
        self.add = add
        self.lo, self.hi = lo, hi
        self.rows: dict[Hashable, tuple[Any, str, float]] = {}  # key -> element, html, order

    def clear(self) -> None:
        for handle, _, _ in self.rows.values():
            try:
                handle.remove()
            except RuntimeError:  # the page left meanwhile
                pass
        self.rows.clear()

    def show(self, rows: Sequence[tuple[Hashable, str]]) -> int:
        """Make the table show ``rows`` (key, HTML), in this order."""
        wanted = {key for key, _ in rows}
        for key in [k for k in self.rows if k not in wanted]:
            handle = self.rows.pop(key)[0]
            try:
                handle.remove()
            except RuntimeError:  # the page left meanwhile
                pass
        old = [self.rows[key][2] if key in self.rows else None for key, _ in rows]
        kept = _kept(old)
        orders = self._place(old, kept)
        if orders is None:  # no room left between two rows: every row renumbered
            orders = self._place([None] * len(rows), set())
            assert orders is not None
        sent = 0
        for (key, content), order in zip(rows, orders, strict=True):
            known = self.rows.get(key)
            if known is None:
                handle = self.add(content, order)
                sent += 1
            else:
                handle, shown, was = known
                if shown != content or was != order:
                    if was != order:
                        handle.order = order
                    if shown != content:
                        handle.content = content
                    sent += 1
            self.rows[key] = (handle, content, order)
        return sent

    def _place(self, old: Sequence[float | None], kept: set[int]) -> list[float] | None:
        """Order values: the kept ones stay, the others are spread between their kept
        neighbours (None when a gap is too small)."""
        out: list[float] = []
        n = len(old)
        i = 0
        low = self.lo
        while i < n:
            if i in kept:
                value = old[i]
                assert value is not None
                out.append(value)
                low = value
                i += 1
                continue
            j = i
            while j < n and j not in kept:
                j += 1
            high = old[j] if j < n and old[j] is not None else self.hi
            assert high is not None
            step = (high - low) / (j - i + 1)
            if step < MIN_GAP:
                return None
            out.extend(low + step * (k + 1) for k in range(j - i))
            i = j
        return out


__all__ = ["RowTable"]
