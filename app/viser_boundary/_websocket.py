"""The websocket hardened: a size limit at the transport, an allow-list of message types,
pacing per connection and in total, and a connection held while its callbacks queue."""

from __future__ import annotations

import asyncio
import logging
import socket
import threading
from collections.abc import Callable
from typing import Any

from analyzer_lab.token_bucket import TokenBucket
from analyzer_lab.viser_boundary._callbacks import CONNECTION, MAX_PENDING_CALLBACKS, pending

#: Websocket: incoming messages per second and burst per connection, and for all
#: connections together; the largest message a page may send (bytes; the largest the app
#: needs is a saved state of at most 20 kB coming back from the browser's storage).
WS_RATE = 150.0
WS_BURST = 300.0
WS_TOTAL_RATE = 1000.0
WS_TOTAL_BURST = 1000.0
WS_MAX_BYTES = 64 * 1024
#: The kernel's send buffer per connection (bytes; the kernel doubles it): a page that
#: stops reading is behind after this much, not after the several megabytes the kernel
#: would otherwise grow the buffer to (a page takes a few kB per frame).
WS_SEND_BUFFER = 128 * 1024
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

_HARDENED = False
_HARDEN_LOCK = threading.Lock()
WS_STATS = {"dropped_oversized": 0, "paced": 0, "dropped_type": 0, "held": 0, "malformed": 0}
#: Message types dropped by the allow-list (type name -> count; names cut to 40 chars).
WS_DROPPED_TYPES: dict[str, int] = {}

log = logging.getLogger(__name__)


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


def _bound_send_buffer(websocket: Any) -> None:
    """Fix the connection's kernel send buffer at :data:`WS_SEND_BUFFER`."""
    sock = websocket.transport.get_extra_info("socket") if websocket.transport else None
    if sock is None:
        return
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, WS_SEND_BUFFER)
    except OSError:  # a socket that is already closing
        log.debug("send buffer not set", exc_info=True)


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
            _bound_send_buffer(websocket)
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
                except (msgspec.DecodeError, AttributeError):
                    WS_STATS["malformed"] += 1
                    continue
                if kind not in ALLOWED_MESSAGES:
                    WS_STATS["dropped_type"] += 1
                    name = str(kind)[:40]
                    if name in WS_DROPPED_TYPES or len(WS_DROPPED_TYPES) < 64:
                        WS_DROPPED_TYPES[name] = WS_DROPPED_TYPES.get(name, 0) + 1
                    continue
                try:
                    message = message_class.deserialize(raw)
                except Exception:  # malformed: counted, logged quietly, ignored
                    WS_STATS["malformed"] += 1
                    log.debug("malformed %.40s message dropped", kind, exc_info=True)
                    continue
                while pending(key) >= MAX_PENDING_CALLBACKS:
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


def dropped_types() -> str:
    """The message types the allow-list dropped, with counts (for the server's log)."""
    return ", ".join(f"{k} {v}" for k, v in sorted(WS_DROPPED_TYPES.items()))


def client_address(server: Any, client_id: int) -> str:
    """The network address (host) a page connected from ("" when not known)."""
    try:
        conn = server._websock_server._live_connections[client_id]
        addr = conn.remote_address
        return str(addr[0]) if isinstance(addr, (tuple, list)) and addr else str(addr or "")
    except (AttributeError, KeyError, TypeError):
        return ""
