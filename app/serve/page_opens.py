"""Pages opened per network address: a rate with a burst, and a queue for the rest.

A class behind one address (a university's NAT) opens its pages at once within the
burst; an address that opens hundreds of pages has them built at the rate, in the order
they came, while pages from other addresses are built at once.  A page that leaves while
it waits is dropped from the queue and never built."""

from __future__ import annotations

import threading
from collections import OrderedDict, deque
from typing import Any

from analyzer_lab.token_bucket import TokenBucket

#: Pages one address may open per second, and at once.
OPEN_RATE = 5.0
OPEN_BURST = 60.0
#: Addresses whose rate is remembered (the least recently seen are forgotten first).
MAX_ADDRESSES = 4096

WAIT_NOTICE = "Many pages were opened from your network address: this page opens in a few seconds."


class PageOpens:
    """Admission of page builds by address."""

    def __init__(
        self, rate: float = OPEN_RATE, burst: float = OPEN_BURST, max_addresses: int = MAX_ADDRESSES
    ) -> None:
        self.rate = rate
        self.burst = burst
        self.max_addresses = max_addresses
        self._lock = threading.Lock()
        self._buckets: OrderedDict[str, TokenBucket] = OrderedDict()
        self._waiting: dict[str, deque[tuple[int, Any]]] = {}
        self.queued = 0

    def _bucket(self, address: str) -> TokenBucket:
        bucket = self._buckets.pop(address, None)
        if bucket is None:
            bucket = TokenBucket(self.rate, self.burst)
        self._buckets[address] = bucket  # the most recently seen last
        while len(self._buckets) > self.max_addresses:
            oldest = next(iter(self._buckets))
            if oldest in self._waiting:
                break  # an address with pages waiting keeps its bucket
            del self._buckets[oldest]
        return bucket

    def admit(self, address: str, page_id: int, page: Any) -> bool:
        """True: build the page now; False: it waits its turn (see :meth:`due`)."""
        with self._lock:
            if address not in self._waiting and self._bucket(address).take():
                return True
            self._waiting.setdefault(address, deque()).append((page_id, page))
            self.queued += 1
            return False

    def due(self) -> list[Any]:
        """The waiting pages whose turn has come (in the order they came, per address)."""
        ready: list[Any] = []
        with self._lock:
            for address in list(self._waiting):
                queue = self._waiting[address]
                bucket = self._bucket(address)
                while queue and bucket.take():
                    ready.append(queue.popleft()[1])
                if not queue:
                    del self._waiting[address]
        return ready

    def drop(self, page_id: int) -> bool:
        """The page left; True when it was still waiting (it will never be built)."""
        with self._lock:
            for address, queue in list(self._waiting.items()):
                for item in queue:
                    if item[0] == page_id:
                        queue.remove(item)
                        if not queue:
                            del self._waiting[address]
                        return True
        return False

    def waiting(self) -> int:
        """Pages waiting now."""
        with self._lock:
            return sum(len(q) for q in self._waiting.values())


__all__ = ["OPEN_BURST", "OPEN_RATE", "WAIT_NOTICE", "PageOpens"]
