"""Page callbacks in order: one connection's callbacks run in the order its messages
came, round-robin over connections within a CPU budget."""

from __future__ import annotations

import contextvars
import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

from analyzer_lab.limits import charged_by

log = logging.getLogger(__name__)

#: A connection's socket is not read while this many of its callbacks wait to run.
MAX_PENDING_CALLBACKS = 16
#: Page callbacks (GUI inputs of all pages together) may use this share of one core's
#: time (CPU seconds per second), with this much at once; the frame loop keeps the rest.
GUI_CPU_SHARE = 0.2
GUI_CPU_BURST = 0.2
#: Threads that run page callbacks (one connection's callbacks never run in parallel).
GUI_WORKERS = 12

_EXECUTORS: list[OrderedExecutor] = []

#: The connection whose message is being handled (set around viser's dispatch; the
#: asyncio tasks it creates copy the value).
CONNECTION: contextvars.ContextVar[int | None] = contextvars.ContextVar(
    "analyzer_lab_connection", default=None
)


class CpuBudget:
    """CPU seconds that callbacks may spend: ``share`` per second of wall time, up to
    ``burst`` saved; a callback may overdraw it by what it used since it was last charged
    (the next waits until it is paid)."""

    def __init__(self, share: float, burst: float) -> None:
        self.share = float(share)
        self.burst = float(burst)
        self.tokens = float(burst)
        self.t = time.monotonic()
        self.lock = threading.Lock()

    def _refill(self) -> None:
        now = time.monotonic()
        self.tokens = min(self.burst, self.tokens + (now - self.t) * self.share)
        self.t = now

    def wait_time(self) -> float:
        """Seconds until the budget is positive again (0 when it is)."""
        with self.lock:
            self._refill()
            return 0.0 if self.tokens > 0 else -self.tokens / self.share + 1e-3

    def spend(self, seconds: float) -> None:
        with self.lock:
            self._refill()
            self.tokens -= seconds

    def wait(self) -> float:
        """Sleep until the budget is positive again; the seconds slept."""
        slept = 0.0
        pause = self.wait_time()
        while pause > 0:
            time.sleep(min(pause, 0.05))
            slept += min(pause, 0.05)
            pause = self.wait_time()
        return slept


class RunningCharge:
    """The thread CPU time of one running callback, charged to ``budget`` as it runs:
    :meth:`charge` (called from the callback's long loops through
    :func:`~analyzer_lab.limits.charge_running`) charges what it used since the last
    mark, and waits while the budget is spent, so a long callback (an export) takes its
    share in turns with the other pages' callbacks instead of paying it all at its end
    (which held every page's controls for ``used / share`` seconds afterwards)."""

    def __init__(self, budget: CpuBudget) -> None:
        self.budget = budget
        self.mark = time.thread_time()
        self.used = 0.0
        self.waited = 0.0

    def charge(self, wait: bool = True) -> float:
        """Charge the CPU used since the last mark; wait (``wait``) while the budget is
        spent; the seconds waited."""
        now = time.thread_time()
        self.used += now - self.mark
        self.budget.spend(now - self.mark)
        self.mark = now  # the waiting's own CPU is charged next time
        waited = self.budget.wait() if wait else 0.0
        self.waited += waited
        return waited


#: The attribute of a viser ``GuiEvent`` that keeps the value its message carried.
SENT_VALUE = "_analyzer_lab_sent_value"


def keep_sent_value(event: Any) -> None:
    """Keep on ``event`` the value its widget has now: viser queues a GUI callback right
    after it stores the value a page sent, so this is the page's value, whatever the
    server sets the widget to before the callback runs."""
    target = getattr(event, "target", None)
    if target is None or not hasattr(event, "client_id"):
        return
    try:
        object.__setattr__(event, SENT_VALUE, target.value)
    except (AttributeError, TypeError):  # an event of another kind: read the widget
        log.debug("the value of an event was not kept", exc_info=True)


def sent_value(event: Any) -> Any:
    """The value the page sent with ``event`` (a GUI update), kept when its callback was
    queued: a page's own input, not what the server set the widget to meanwhile (a
    lesson change resetting the preset picker while the preset chosen next waits its
    turn).  An event made in the server (a replay, a test) reads the widget."""
    try:
        return object.__getattribute__(event, SENT_VALUE)
    except AttributeError:
        return event.target.value


class OrderedExecutor:
    """viser's callback pool, but the callbacks of one connection run one after the other
    in the order its messages arrived, connections take turns (round-robin), and all
    page callbacks together stay within a CPU budget (:data:`GUI_CPU_SHARE`).

    viser starts every GUI callback on a shared pool, so a preset choice and a checkbox
    ticked right after it could run in either order (and the slower preset callback
    could show the old checkbox value over the new one), and many pages' inputs could
    take the interpreter from the frame loop.  Here each connection has a queue; a few
    worker threads take one callback from the next connection in turn, and wait while
    the budget is spent.  A callback's thread CPU time is charged as it runs
    (:class:`RunningCharge`: its long loops call
    :func:`~analyzer_lab.limits.charge_running`, and wait there while the budget is
    spent) and the rest at its end.  Work submitted outside a connection's message
    (connect handlers, server code) goes to the pool."""

    def __init__(
        self,
        pool: Any,
        share: float = GUI_CPU_SHARE,
        burst: float = GUI_CPU_BURST,
        workers: int = GUI_WORKERS,
    ) -> None:
        self.pool = pool
        self.budget = CpuBudget(share, burst)
        self._cond = threading.Condition()
        self._queues: dict[Any, deque[tuple[Future, Callable[..., Any], tuple, dict]]] = {}
        self._ready: deque[Any] = deque()  # connections with work, not running, in turn
        self._stopped = False
        self.stats = {"run": 0, "waited": 0.0, "cpu": 0.0}
        self._workers = [
            threading.Thread(target=self._work, name=f"analyzer-lab-gui-{k}", daemon=True)
            for k in range(max(1, workers))
        ]
        for w in self._workers:
            w.start()

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        key = CONNECTION.get()
        if key is None:
            return self.pool.submit(fn, *args, **kwargs)
        for arg in args:
            keep_sent_value(arg)
        return self.submit_for(key, fn, *args, **kwargs)

    def submit_for(self, key: Any, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        """Queue ``fn`` as a callback of ``key`` (a connection, or any other input source)."""
        fut: Future = Future()
        with self._cond:
            queue = self._queues.get(key)
            if queue is None:
                queue = self._queues[key] = deque()
                self._ready.append(key)
                self._cond.notify()
            queue.append((fut, fn, args, kwargs))
        return fut

    def _work(self) -> None:
        while True:
            with self._cond:
                while not self._ready and not self._stopped:
                    self._cond.wait()
                if self._stopped:
                    return
                key = self._ready.popleft()
                fut, fn, args, kwargs = self._queues[key].popleft()
            self.stats["waited"] += self.budget.wait()
            if fut.set_running_or_notify_cancel():
                running = RunningCharge(self.budget)
                with charged_by(running.charge):
                    try:
                        fut.set_result(fn(*args, **kwargs))
                    except BaseException as exc:  # noqa: BLE001 - delivered to the future (viser logs it)
                        fut.set_exception(exc)
                running.charge(wait=False)  # the rest, paid by the next callback's wait
                self.stats["run"] += 1
                self.stats["cpu"] += running.used
                self.stats["waited"] += running.waited
            # the worker waits for its next callback holding nothing of this one: its
            # arguments (a GUI event, its handle, the page's view) would otherwise stay
            # alive as this thread's locals after the page left
            del fut, fn, args, kwargs
            with self._cond:
                queue = self._queues[key]
                if queue:
                    self._ready.append(key)  # its next callback, after the others' turn
                    self._cond.notify()
                else:
                    del self._queues[key]

    def pending(self, key: Any = None) -> int:
        """Callbacks queued (of one connection, or of all)."""
        with self._cond:
            if key is not None:
                q = self._queues.get(key)
                return len(q) if q is not None else 0
            return sum(len(q) for q in self._queues.values())

    def shutdown(self, wait: bool = True, **kwargs: Any) -> None:
        with self._cond:
            self._stopped = True
            self._cond.notify_all()
        if self in _EXECUTORS:
            _EXECUTORS.remove(self)
        self.pool.shutdown(wait=wait, **kwargs)


def order_callbacks(server: Any) -> OrderedExecutor:
    """Route a :class:`viser.ViserServer`'s callbacks through an :class:`OrderedExecutor`
    (before any client connects: per-client APIs copy the executor when created)."""
    ordered = OrderedExecutor(server._thread_executor)
    _EXECUTORS.append(ordered)
    server._thread_executor = ordered
    for api in (server.gui, server.scene):
        api._thread_executor = ordered
    return ordered


def pending(key: int) -> int:
    """Callbacks of connection ``key`` waiting to run, over every ordered executor."""
    return sum(ex.pending(key) for ex in list(_EXECUTORS))


def submit_callback(server: Any, key: Any, fn: Callable[..., Any], *args: Any) -> bool:
    """Run ``fn(*args)`` as a page callback of ``key`` (in its turn, within the callback
    budget); False when the server has no :class:`OrderedExecutor`."""
    ex = getattr(server, "_thread_executor", None)
    if not isinstance(ex, OrderedExecutor):
        return False
    ex.submit_for(key, fn, *args)
    return True
