"""The input gate of every page: one token bucket per page (DESIGN §5).

Every GUI input of a page takes tokens from that page's bucket (a text edit, which may
be a formula to parse, costs :data:`TEXT_COST`; a choice that rebuilds the page, a
lesson or a preset, costs :data:`REBUILD_COST`).  An input over the limit
is not dropped but coalesced: the newest value of each widget waits and is applied when
the page's bucket has refilled, through the page's callbacks again (in its turn of the
callback budget, :func:`analyzer_lab.viser_boundary.submit_callback`).  A replayed
input that a newer input of the same widget has overtaken meanwhile is dropped: the
replay runs beside the page's own queue, and the older value must not land last.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from analyzer_lab.token_bucket import TokenBucket
from analyzer_lab.viser_boundary import submit_callback

log = logging.getLogger(__name__)

#: GUI inputs per page: tokens per second and burst; a text (formula) edit costs more.
INPUT_RATE = 20.0
INPUT_BURST = 20.0
TEXT_COST = 4.0
REBUILD_COST = 10.0

Callback = Callable[[Any], None]


class InputGate:
    """Token buckets and coalesced inputs of the pages of one server.  ``stats`` gets
    the counts ``admitted``, ``coalesced``, ``replayed`` and ``superseded``; ``server()`` is the viser
    server whose callback queue replays an input (``None``: replayed in place)."""

    def __init__(self, stats: dict[str, int], server: Callable[[], Any]) -> None:
        self.stats = stats
        self.server = server
        self.buckets: dict[int, TokenBucket] = {}
        #: (page, widget) -> the newest coalesced input: its callback, event and cost
        self.pending: dict[tuple[int, str], tuple[Callback, Any, float]] = {}
        #: (page, widget) -> the newest input that arrived (a replay of any other is stale)
        self.newest: dict[tuple[int, str], Any] = {}

    def open(self, client_id: int) -> None:
        """A page connected: a full bucket."""
        self.buckets[client_id] = TokenBucket(INPUT_RATE, INPUT_BURST)

    def forget(self, client_id: int) -> None:
        """A page left: its bucket and waiting inputs go."""
        self.buckets.pop(client_id, None)
        for key in [k for k in self.pending if k[0] == client_id]:
            self.pending.pop(key, None)
        for key in [k for k in self.newest if k[0] == client_id]:
            self.newest.pop(key, None)

    def admit(
        self, client_id: int, event: Any, again: Callback | None, rebuilds: bool = False
    ) -> bool:
        """Whether the input may run now; if not and ``again`` is given, it is kept
        (replacing an older input of the same widget) for :meth:`replay`.  ``rebuilds``:
        the input rebuilds the page (it costs :data:`REBUILD_COST`)."""
        bucket = self.buckets.get(client_id)
        if bucket is None:
            return True
        target = getattr(event, "target", None)
        key = (client_id, str(getattr(target, "id", id(target))))
        if target is not None:
            self.newest[key] = event
        if rebuilds:
            cost = REBUILD_COST
        elif type(target).__name__ == "GuiTextHandle":
            cost = TEXT_COST
        else:
            cost = 1.0
        if bucket.take(cost):
            self.stats["admitted"] += 1
            self.pending.pop(key, None)  # an older waiting value of this widget is overtaken
            return True
        if again is not None and target is not None:
            self.stats["coalesced"] += 1
            self.pending[key] = (again, event, cost)
        return False

    def replay(self) -> None:
        """Send the waiting inputs of every page whose bucket has refilled."""
        for key in list(self.pending):
            bucket = self.buckets.get(key[0])
            if bucket is None:
                self.pending.pop(key, None)
                continue
            item = self.pending.get(key)
            if item is None or bucket.wait_time(item[2]) > 0:
                continue
            item = self.pending.pop(key, None)
            if item is not None:
                self.stats["replayed"] += 1
                # goes through the gate again, in the page's turn of the callback budget
                again, event, _ = item
                if not submit_callback(
                    self.server(), ("replay", key[0]), self.run_replayed, key, again, event
                ):
                    try:
                        self.run_replayed(key, again, event)
                    except Exception:  # a page callback, run here
                        log.exception("page %s: a replayed input failed", key[0])

    def run_replayed(self, key: tuple[int, str], again: Callback, event: Any) -> None:
        """Run a waiting input unless a newer input of its widget arrived meanwhile."""
        if self.newest.get(key) is not event:
            self.stats["superseded"] += 1
            return
        again(event)


__all__ = ["InputGate"]
