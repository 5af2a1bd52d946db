"""The one place that reaches into viser's private internals.

viser 1.1.1 offers no public API for these, and each is checked by a test of its own
(``tests/test_viser_boundary.py``); :func:`check_viser_version` refuses to start on a
viser whose internals were not checked:

* :func:`make_viser_server`: our page title (a copy of viser's page), no share tunnel;
* :func:`harden_websocket`: oversized messages dropped before decoding, each connection
  paced (a flooding page waits on its own socket);
* :func:`order_callbacks`: one connection's callbacks run in the order its messages came;
* :class:`WakeBatch`: the messages of one frame-loop tick wake viser's loop once;
* :func:`fast_set`: one property of a handle set on the hot path;
* :func:`recording_scene`: a scene API whose messages are only recorded (HTML replay);
* :func:`event_loop`: the server's own event loop (the frame loop runs in it);
* :func:`guard_gui_updates`: a GUI value of the wrong type is refused with one message
  to its sender (viser would raise while casting it, a traceback per message).
"""

from __future__ import annotations

import asyncio
import contextvars
import tempfile
import threading
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

from app.limits import TokenBucket

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
            " app/viser_boundary.py patches its internals"
        )


#: Websocket: incoming messages per second and burst per connection; size limit.
WS_RATE = 150.0
WS_BURST = 300.0
WS_MAX_BYTES = 256 * 1024


_HARDENED = False
_HARDEN_LOCK = threading.Lock()
WS_STATS = {"dropped_oversized": 0, "paced": 0}


#: The connection whose message is being handled (set around viser's dispatch; the
#: asyncio tasks it creates copy the value).
CONNECTION: contextvars.ContextVar[int | None] = contextvars.ContextVar(
    "analyzer_lab_connection", default=None
)


class OrderedExecutor:
    """viser's callback pool, but the callbacks of one connection run one after the other
    in the order its messages arrived.

    viser starts every GUI callback on a shared pool, so a preset choice and a checkbox
    ticked right after it could run in either order (and the slower preset callback
    could show the old checkbox value over the new one).  Callbacks of different
    connections still run in parallel; work submitted outside a connection's message
    (connect handlers, server code) goes to the pool directly."""

    def __init__(self, pool: Any) -> None:
        self.pool = pool
        self._lock = threading.Lock()
        self._queues: dict[int, deque[tuple[Future, Callable[..., Any], tuple, dict]]] = {}

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        key = CONNECTION.get()
        if key is None:
            return self.pool.submit(fn, *args, **kwargs)
        fut: Future = Future()
        with self._lock:
            queue = self._queues.get(key)
            first = queue is None
            if first:
                queue = self._queues[key] = deque()
            queue.append((fut, fn, args, kwargs))  # type: ignore[union-attr]
        if first:
            self.pool.submit(self._drain, key)
        return fut

    def _drain(self, key: int) -> None:
        while True:
            with self._lock:
                queue = self._queues[key]
                if not queue:
                    del self._queues[key]
                    return
                fut, fn, args, kwargs = queue.popleft()
            if not fut.set_running_or_notify_cancel():
                continue
            try:
                fut.set_result(fn(*args, **kwargs))
            except BaseException as exc:  # delivered to the future's callbacks (viser logs it)
                fut.set_exception(exc)

    def pending(self) -> int:
        with self._lock:
            return sum(len(q) for q in self._queues.values())

    def shutdown(self, wait: bool = True, **kwargs: Any) -> None:
        self.pool.shutdown(wait=wait, **kwargs)


def order_callbacks(server: Any) -> OrderedExecutor:
    """Route a :class:`viser.ViserServer`'s callbacks through an :class:`OrderedExecutor`
    (before any client connects: per-client APIs copy the executor when created)."""
    ordered = OrderedExecutor(server._thread_executor)
    server._thread_executor = ordered
    for api in (server.gui, server.scene):
        api._thread_executor = ordered
    return ordered


def harden_websocket() -> None:
    """Replace viser's per-connection message consumer with one that drops messages
    larger than :data:`WS_MAX_BYTES` before decoding them and paces each connection
    to :data:`WS_RATE` messages/s (a flooding client waits on its own TCP window;
    the other clients are not slowed).  Idempotent; process-wide."""
    global _HARDENED
    with _HARDEN_LOCK:
        if _HARDENED:
            return
        import asyncio

        from viser.infra import _infra

        async def paced_consumer(
            websocket: Any, handle_message: Callable[[Any], None], message_class: Any
        ) -> None:
            bucket = TokenBucket(WS_RATE, WS_BURST)
            while True:
                raw = await websocket.recv()
                if not isinstance(raw, (bytes, bytearray)):
                    continue
                if len(raw) > WS_MAX_BYTES:
                    WS_STATS["dropped_oversized"] += 1
                    continue
                if not bucket.take():
                    WS_STATS["paced"] += 1
                    await asyncio.sleep(bucket.wait_time())
                    bucket.take()
                try:
                    message = message_class.deserialize(raw)
                except Exception:
                    continue  # malformed: ignore
                # the tasks viser creates for this message inherit the connection key
                token = CONNECTION.set(id(websocket))
                try:
                    handle_message(message)
                finally:
                    CONNECTION.reset(token)

        _infra._message_consumer = paced_consumer  # type: ignore[assignment]
        _HARDENED = True


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


def make_viser_server(host: str, port: int, verbose: bool) -> Any:
    """A ViserServer serving our page (title) whose share tunnel cannot be started."""
    import viser
    from viser import _messages, infra

    check_viser_version()
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
    harden_websocket()
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


#: Seconds between two log lines about refused GUI values (the count is kept).
REFUSED_LOG_EVERY = 10.0
REFUSED_UPDATES = {"count": 0, "logged": 0.0}


def value_problem(current: Any, value: Any) -> str | None:
    """Why ``value`` cannot replace a widget's ``current`` value (viser casts it with the
    current value's type), or None: numbers for numbers (finite), on/off for on/off,
    text (or a finite number, read as its text) for text, a tuple of the same length and
    kinds for a tuple."""
    import math

    if isinstance(current, bool):
        return None if isinstance(value, bool) else "expected on/off"
    if isinstance(current, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return "expected a number"
        return None if math.isfinite(value) else "expected a finite number"
    if isinstance(current, str):  # a number typed into a text field reads as its text
        if isinstance(value, str):
            return None
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return None if math.isfinite(value) else "expected a finite number"
        return "expected text"
    if isinstance(current, tuple):
        if not isinstance(value, (list, tuple)) or len(value) != len(current):
            return f"expected {len(current)} values"
        for c, v in zip(current, value):
            why = value_problem(c, v)
            if why is not None:
                return why
        return None
    return None


def guard_gui_updates(gui: Any, server: Any) -> None:
    """Check each GUI update's value against its widget before viser casts it: a wrong
    type (a list for a number, text for a checkbox, NaN) is refused with one notice to
    the sender and a log line at most every :data:`REFUSED_LOG_EVERY` seconds; nothing
    changes and nothing is sent to other pages.  ``gui``: the server's or a client's GUI
    API (each registers its own handler on its connection)."""
    import sys
    import time

    from viser import _messages

    ws = gui._websock_interface
    original = gui._handle_gui_updates

    async def checked(client_id: Any, message: Any) -> None:
        handle = gui._gui_input_handle_from_uuid.get(message.uuid, None)
        if handle is None or handle._impl.removed:
            return
        state = handle._impl
        updates = message.updates if isinstance(message.updates, dict) else {}
        why = None if updates else "an empty update"
        for name, value in updates.items():
            if name != "value":
                why = f"the page may only change a widget's value, not {str(name)[:30]!r}"
                break
            why = value_problem(state.value, value)
            if why is not None:
                break
        if why is None:
            await original(client_id, message)
            return
        label = str(getattr(handle, "label", "") or "a widget")[:60]
        REFUSED_UPDATES["count"] += 1
        now = time.monotonic()
        if now - REFUSED_UPDATES["logged"] >= REFUSED_LOG_EVERY:
            REFUSED_UPDATES["logged"] = now
            print(
                f"analyzer-lab: refused GUI values so far: {REFUSED_UPDATES['count']}"
                f" (latest: {label}: {why})",
                file=sys.stderr,
                flush=True,
            )
        client = server.get_clients().get(client_id)
        if client is not None:
            try:
                client.add_notification(
                    "Analyzer Lab",
                    f"{label}: value refused ({why})",
                    auto_close_seconds=6.0,
                    color="yellow",
                )
            except Exception:
                pass

    try:
        ws.unregister_handler(_messages.GuiUpdateMessage, original)
    except (AssertionError, ValueError):
        return  # viser's handler is not where it was checked: keep it
    ws.register_handler(_messages.GuiUpdateMessage, checked)
