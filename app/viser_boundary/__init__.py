"""The one place that reaches into viser's private internals.

viser 1.1.1 offers no public API for these, and each is checked by a test of its own
(``tests/test_viser_boundary.py``); :func:`check_viser_version` refuses to start on a
viser whose internals were not checked:

* :func:`make_viser_server`: our page title (a copy of viser's page), no share tunnel;
* :func:`harden_websocket`: the websocket refuses messages over :data:`WS_MAX_BYTES` before
  reading them (the transport's ``max_size``), only :data:`ALLOWED_MESSAGES` reach viser's
  handlers, each connection is paced (a flooding page waits on its own socket) and waits
  while its callbacks queue up;
* :func:`order_callbacks`: one connection's callbacks run in the order its messages came,
  round-robin over connections within a CPU budget (:class:`OrderedExecutor`);
* :func:`client_address`: the network address a page connected from;
* :class:`WakeBatch`: the messages of one frame-loop tick wake viser's loop once;
* :func:`fast_set`: one property of a handle set on the hot path;
* :func:`recording_scene`: a scene API whose messages are only recorded (HTML replay);
* :func:`event_loop`: the server's own event loop (the frame loop runs in it).

The GUI value guard (:func:`~analyzer_lab.viser_boundary._gui_guard.guard_gui_updates`, a GUI value of the
wrong type refused with one message to its sender) is the second boundary module,
:mod:`analyzer_lab.viser_boundary._gui_guard` (:func:`make_viser_server` puts it on the server's GUI).
"""

from __future__ import annotations

import asyncio
import contextvars
import tempfile
import threading
import time
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

from analyzer_lab.token_bucket import TokenBucket
from analyzer_lab.viser_boundary._gui_guard import guard_gui_updates
from analyzer_lab.viser_boundary._gui_guard import (
    value_problem as value_problem,  # the guard's rule, here too
)

#: The viser version whose internals this module was written and tested against.
VISER_VERSION = "1.1.1"
PAGE_TITLE = "Analyzer Lab"
_PATCH_LOCK = threading.Lock()


def check_viser_version() -> None:
    """Refuse to run on a viser whose private internals were not checked."""
    import viser

    found = getattr(viser, "__version__", "unknown")
    if found != VISER_VERSION:
        raise RuntimeError(
            f"Analyzer Lab needs viser {VISER_VERSION} (found {found}):"
            " app/viser_boundary/__init__.py patches its internals"
        )


#: Websocket: incoming messages per second and burst per connection, and for all
#: connections together; the largest message a page may send (bytes; the largest the app
#: needs is a saved state of at most 20 kB coming back from the browser's storage).
WS_RATE = 150.0
WS_BURST = 300.0
WS_TOTAL_RATE = 1000.0
WS_TOTAL_BURST = 1000.0
WS_MAX_BYTES = 64 * 1024
#: The messages a page of the lab sends (viser 1.1.1's client -> server messages that the
#: app uses): its camera, values of its own widgets, command hotkeys (presenter mode),
#: clicks on scene surfaces and answers from the browser's storage.  Everything else
#: (form "dirty" flags that viser broadcasts to every page and keeps, share-tunnel
#: requests, uploads, renders, pointer and drag events) is dropped unread.
ALLOWED_MESSAGES = frozenset(
    {
        "ViewerCameraMessage",
        "GuiUpdateMessage",
        "CommandTriggerMessage",
        "SceneNodeClickMessage",
        "LocalStorageGetItemResponseMessage",
    }
)
#: A connection's socket is not read while this many of its callbacks wait to run.
MAX_PENDING_CALLBACKS = 16
#: Page callbacks (GUI inputs of all pages together) may use this share of one core's
#: time (CPU seconds per second), with this much at once; the frame loop keeps the rest.
GUI_CPU_SHARE = 0.2
GUI_CPU_BURST = 0.2
#: Threads that run page callbacks (one connection's callbacks never run in parallel).
GUI_WORKERS = 12


_HARDENED = False
_HARDEN_LOCK = threading.Lock()
WS_STATS = {"dropped_oversized": 0, "paced": 0, "dropped_type": 0, "held": 0}
#: Message types dropped by the allow-list (type name -> count; names cut to 40 chars).
WS_DROPPED_TYPES: dict[str, int] = {}
_EXECUTORS: list[OrderedExecutor] = []


#: The connection whose message is being handled (set around viser's dispatch; the
#: asyncio tasks it creates copy the value).
CONNECTION: contextvars.ContextVar[int | None] = contextvars.ContextVar(
    "analyzer_lab_connection", default=None
)


class CpuBudget:
    """CPU seconds that callbacks may spend: ``share`` per second of wall time, up to
    ``burst`` saved; one callback may overdraw it (the next waits until it is paid)."""

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


class OrderedExecutor:
    """viser's callback pool, but the callbacks of one connection run one after the other
    in the order its messages arrived, connections take turns (round-robin), and all
    page callbacks together stay within a CPU budget (:data:`GUI_CPU_SHARE`).

    viser starts every GUI callback on a shared pool, so a preset choice and a checkbox
    ticked right after it could run in either order (and the slower preset callback
    could show the old checkbox value over the new one), and many pages' inputs could
    take the interpreter from the frame loop.  Here each connection has a queue; a few
    worker threads take one callback from the next connection in turn, and wait while
    the budget is spent (a callback's thread CPU time is charged to it).  Work submitted
    outside a connection's message (connect handlers, server code) goes to the pool."""

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
            wait = self.budget.wait_time()
            while wait > 0:
                self.stats["waited"] += wait
                time.sleep(min(wait, 0.05))
                wait = self.budget.wait_time()
            if fut.set_running_or_notify_cancel():
                cpu = time.thread_time()
                try:
                    fut.set_result(fn(*args, **kwargs))
                except BaseException as exc:  # delivered to the future's callbacks (viser logs it)
                    fut.set_exception(exc)
                used = time.thread_time() - cpu
                self.budget.spend(used)
                self.stats["run"] += 1
                self.stats["cpu"] += used
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


class _Proxy:
    """A module seen through a proxy: some attributes replaced, the rest delegated."""

    def __init__(self, target: Any, **replaced: Any) -> None:
        self._target = target
        self.__dict__.update(replaced)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._target, name)


def _limited_serve(serve: Callable[..., Any]) -> Callable[..., Any]:
    """``websockets.asyncio.server.serve`` with our message size and queue limits: a frame
    longer than :data:`WS_MAX_BYTES` is refused from its header (the connection closes
    with 1009 "message too big") before its payload is read."""

    def limited(*args: Any, **kwargs: Any) -> Any:
        kwargs["max_size"] = WS_MAX_BYTES
        kwargs["max_queue"] = 4
        return serve(*args, **kwargs)

    limited.__name__ = "limited_serve"
    return limited


def _pending(key: int) -> int:
    return sum(ex.pending(key) for ex in list(_EXECUTORS))


def harden_websocket() -> None:
    """Patch viser's websocket server (before it starts): the transport refuses messages
    over :data:`WS_MAX_BYTES` unread; the per-connection message consumer drops every
    message type not in :data:`ALLOWED_MESSAGES` before any handler (or broadcast) sees
    it, paces each connection to :data:`WS_RATE` messages/s and all of them together to
    :data:`WS_TOTAL_RATE`, and stops reading a connection while
    :data:`MAX_PENDING_CALLBACKS` of its callbacks wait (a flooding client waits on its
    own TCP window; the other clients are not slowed).  Idempotent; process-wide."""
    global _HARDENED
    with _HARDEN_LOCK:
        if _HARDENED:
            return
        import msgspec
        import websockets.asyncio.server
        from viser.infra import _infra

        total = TokenBucket(WS_TOTAL_RATE, WS_TOTAL_BURST)

        async def paced_consumer(
            websocket: Any, handle_message: Callable[[Any], None], message_class: Any
        ) -> None:
            bucket = TokenBucket(WS_RATE, WS_BURST)
            key = id(websocket)
            while True:
                raw = await websocket.recv()
                if not isinstance(raw, (bytes, bytearray)):
                    continue
                if len(raw) > WS_MAX_BYTES:  # the transport refuses these already
                    WS_STATS["dropped_oversized"] += 1
                    continue
                if not bucket.take():
                    WS_STATS["paced"] += 1
                    await asyncio.sleep(bucket.wait_time())
                    bucket.take()
                while not total.take():
                    WS_STATS["paced"] += 1
                    await asyncio.sleep(max(total.wait_time(), 0.002))
                try:
                    kind = msgspec.msgpack.decode(raw).get("type")
                except Exception:
                    continue  # malformed: ignore
                if kind not in ALLOWED_MESSAGES:
                    WS_STATS["dropped_type"] += 1
                    name = str(kind)[:40]
                    if name in WS_DROPPED_TYPES or len(WS_DROPPED_TYPES) < 64:
                        WS_DROPPED_TYPES[name] = WS_DROPPED_TYPES.get(name, 0) + 1
                    continue
                try:
                    message = message_class.deserialize(raw)
                except Exception:
                    continue  # malformed: ignore
                while _pending(key) >= MAX_PENDING_CALLBACKS:
                    WS_STATS["held"] += 1
                    await asyncio.sleep(0.01)
                # the tasks viser creates for this message inherit the connection key
                token = CONNECTION.set(key)
                try:
                    handle_message(message)
                finally:
                    CONNECTION.reset(token)

        _infra._message_consumer = paced_consumer  # type: ignore[assignment]
        server_module = _Proxy(
            websockets.asyncio.server,
            serve=_limited_serve(websockets.asyncio.server.serve),
        )
        _infra.websockets = _Proxy(  # type: ignore[attr-defined]
            websockets, asyncio=_Proxy(websockets.asyncio, server=server_module)
        )
        _HARDENED = True


def submit_callback(server: Any, key: Any, fn: Callable[..., Any], *args: Any) -> bool:
    """Run ``fn(*args)`` as a page callback of ``key`` (in its turn, within the callback
    budget); False when the server has no :class:`OrderedExecutor`."""
    ex = getattr(server, "_thread_executor", None)
    if not isinstance(ex, OrderedExecutor):
        return False
    ex.submit_for(key, fn, *args)
    return True


def dropped_types() -> str:
    """The message types the allow-list dropped, with counts (for the server's log)."""
    return ", ".join(f"{k} {v}" for k, v in sorted(WS_DROPPED_TYPES.items()))


def client_address(server: Any, client_id: int) -> str:
    """The network address (host) a page connected from ("" when not known)."""
    try:
        conn = server._websock_server._live_connections[client_id]
        addr = conn.remote_address
        return str(addr[0]) if isinstance(addr, (tuple, list)) and addr else str(addr or "")
    except Exception:
        return ""


#: Keys typed into a field (arrows on a focused slider, letters in a formula) stay in that
#: field: they do not reach the page's camera controls, which listen further up.
KEYS_STAY_IN_FIELDS = """<script>
document.addEventListener("keydown", function (e) {
  var t = e.target;
  if (t && t.closest && t.closest('input, textarea, select, [role="slider"]')) {
    e.stopImmediatePropagation();
  }
}, false);
</script>"""


def _client_root() -> Path:
    """viser's client page with our title (and :data:`KEYS_STAY_IN_FIELDS`), in a private
    temporary directory."""
    import viser

    src = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"
    text = src.read_text(encoding="utf-8")
    text = text.replace("<title>Viser</title>", f"<title>{PAGE_TITLE}</title>", 1)
    text = text.replace('content="Viser client"', f'content="{PAGE_TITLE}"', 1)
    text = text.replace("</head>", KEYS_STAY_IN_FIELDS + "</head>", 1)
    root = Path(tempfile.mkdtemp(prefix="analyzer-lab-page-"))
    (root / "index.html").write_text(text, encoding="utf-8")
    return root


_PROP_HINTS: dict[type, dict[str, Any]] = {}


def share_prop_hints() -> None:
    """Every viser handle works out the type hints of its properties class once, on its
    first property write (``AssignablePropsBase._prop_hints``, ``typing.get_type_hints``,
    about 0.3 ms); a live trail makes a new line-segments node every chunk, so the
    frame loop paid it again and again.  The hints depend only on the class: they are
    worked out once per class.  Idempotent; process-wide."""
    from typing import get_type_hints

    from viser._assignable_props_api import AssignablePropsBase

    def hints(self: Any) -> dict[str, Any]:
        cls = type(self._impl.props)
        found = _PROP_HINTS.get(cls)
        if found is None:
            found = _PROP_HINTS[cls] = get_type_hints(cls)
        return found

    with _PATCH_LOCK:
        if not isinstance(AssignablePropsBase.__dict__.get("_prop_hints"), property):
            AssignablePropsBase._prop_hints = property(hints)  # type: ignore[assignment]


def make_viser_server(host: str, port: int, verbose: bool) -> Any:
    """A ViserServer serving our page (title) whose share tunnel cannot be started."""
    import viser
    from viser import _messages, infra

    check_viser_version()
    harden_websocket()  # before the server starts listening
    share_prop_hints()
    root = _client_root()
    original = infra.WebsockServer

    def factory(*args: Any, **kwargs: Any) -> Any:
        kwargs["http_server_root"] = root
        return original(*args, **kwargs)

    with _PATCH_LOCK:
        infra.WebsockServer = factory  # type: ignore[misc]
        try:
            server = viser.ViserServer(host=host, port=port, verbose=verbose)
        finally:
            infra.WebsockServer = original  # type: ignore[misc]
    # the share tunnel: drop the handlers any client could trigger, and the method
    ws = server._websock_server
    for msg in (_messages.ShareUrlRequest, _messages.ShareUrlDisconnect):
        try:
            ws.unregister_handler(msg)
        except (AssertionError, KeyError):
            pass
    server.request_share_url = lambda *a, **k: None  # type: ignore[method-assign]
    guard_gui_updates(server.gui, server)
    order_callbacks(server)  # one connection's callbacks run in the order its messages came
    server.gui.configure_theme(show_share_button=False, show_logo=False, control_width="large")
    server.gui.set_panel_label(PAGE_TITLE)
    return server


class WakeBatch:
    """Groups the messages of one loop tick for every client and wakes viser's event
    loop once for all of them (instead of once per client: each wake-up is a write to
    the loop's self-pipe).  Uses viser's message buffers directly; when they are not
    reachable, :meth:`hold` returns False and the view uses ``client.atomic()``."""

    def __init__(self, server: Any) -> None:
        self.loop = getattr(server._websock_server, "_background_event_loop", None)
        self.held: list[tuple[Any, int]] = []

    def hold(self, client: Any) -> bool:
        try:
            buf = client._websock_connection._state.message_buffer
            buf.atomic_start()
        except Exception:
            return False
        self.held.append((buf, buf.message_counter))
        return True

    def release(self) -> None:
        woken = []
        for buf, before in self.held:
            with buf.buffer_lock:
                buf.atomic_counter -= 1
                ready = buf.atomic_counter == 0
            if ready and buf.message_counter != before:
                woken.append(buf)
        self.held = []
        if woken and self.loop is not None:

            def wake() -> None:
                for b in woken:
                    b.message_event.set()

            try:
                self.loop.call_soon_threadsafe(wake)
            except RuntimeError:
                pass


def fast_set(handle: Any, name: str, value: Any) -> None:
    """Assign one property of a viser handle on the hot path: the value is already of
    the right type and dtype (fresh array), so viser's generic casting and comparison
    (``props_setattr``) are skipped; state and wire message are the same."""
    impl = handle._impl
    if impl.removed:
        return
    setattr(impl.props, name, value)
    handle._queue_update(name, value)


def _moved(current: Any, value: tuple[float, ...]) -> bool:
    """Whether ``value`` differs from ``current`` beyond ``np.allclose`` (viser's test
    for an unchanged pose, its default tolerances), compared number by number: equal
    infinities are unchanged, a NaN always moved."""
    for v, c in zip(value, current.tolist(), strict=True):
        if v != c and not abs(v - c) <= 1e-8 + 1e-5 * abs(c):
            return True
    return False


def set_pose(handle: Any, pos: Any, wxyz: Any) -> None:
    """Set a posed body's position and orientation as its ``position`` and ``wxyz``
    setters do (one message each, none for a part that did not move), without their
    generic casting and array comparison on the hot path."""
    from viser import _messages

    impl = handle._impl
    if impl.removed:
        return
    queue = impl.api._queue_scene_message
    p = tuple(map(float, pos))
    if _moved(impl.position, p):
        impl.position[:] = p
        queue(_messages.SetPositionMessage(impl.name, p))
    q = tuple(map(float, wxyz))
    if _moved(impl.wxyz, q):
        impl.wxyz[:] = q
        queue(_messages.SetOrientationMessage(impl.name, q))


class _NullBuffer:
    """Message buffer that drops everything (the recording keeps its own copy)."""

    def push(self, message: Any) -> None:
        pass

    def atomic_start(self) -> None:
        pass

    def atomic_end(self) -> None:
        pass

    def remove_entity_state_from_buffer(self, entity_type: str, entity_id: str) -> None:
        pass

    def flush(self) -> None:
        pass


def recording_scene() -> tuple[Any, Any]:
    """A SceneApi whose messages only reach a fresh StateSerializer."""
    from viser import infra
    from viser._scene_api import SceneApi

    class _Conn(infra.WebsockMessageHandler):
        def __init__(self) -> None:
            super().__init__()
            self._buffer = _NullBuffer()

        def get_message_buffer(self) -> Any:  # type: ignore[override]
            return self._buffer

    class _Server:
        _scene_lifecycle_lock = threading.RLock()
        _connected_clients: dict[int, Any] = {}

    class _Owner:
        client_id = 0

        def __init__(self) -> None:
            self._websock_connection = _Conn()
            self._viser_server = _Server()

        def flush(self) -> None:
            pass

    owner = _Owner()
    serializer = owner._websock_connection.get_message_serializer(
        filter=lambda m: getattr(m, "include_in_scene_serialization", True)
    )
    loop = asyncio.new_event_loop()
    scene = SceneApi(owner, thread_executor=ThreadPoolExecutor(max_workers=1), event_loop=loop)  # type: ignore[arg-type]
    return scene, serializer


def event_loop(server: Any) -> asyncio.AbstractEventLoop | None:
    """The event loop viser's websocket server runs in (``None`` if not reachable)."""
    return getattr(server._websock_server, "_background_event_loop", None)
