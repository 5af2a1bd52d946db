"""The classroom bus: how the instructor's demo, pushes, notices and page counts reach
every server process of a class.

Two buses with one interface (:class:`Bus`):

* :class:`LocalBus` (the default, ``--bus local``): in-process; the servers of one
  Python process share it (one ``serve`` process: there is nobody else to tell);
* :class:`RedisBus` (``--bus redis://HOST:PORT``): Redis pub/sub, for several worker
  processes and several machines.

Every message is a signed JSON envelope ``{"v", "from", "kind", "body", "sig"}``: the
signature is an HMAC-SHA256 keyed by the class's instructor code (every worker of a
class shares it), so a message written into Redis by anyone without the code is
refused before its body is looked at.  A signed body is still not trusted: the
receiver checks it like a page's input (:mod:`analyzer_lab.classroom.room`).  Oversized or
malformed messages are refused and counted; the bus never raises into its caller.

A Redis bus that is down or unreachable is reported (``status``, listeners), the
server keeps serving its own pages, and the bus reconnects in the background.
"""

from __future__ import annotations

import hashlib
import hmac
import json
import logging
import secrets
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any
from urllib.parse import urlsplit

log = logging.getLogger(__name__)

#: Largest message accepted from the bus (bytes of JSON).
MAX_MESSAGE_BYTES = 20000
#: The Redis channel of a class.
CHANNEL = "analyzer-lab:classroom"
#: Seconds between reconnection attempts (the first; then up to RETRY_MAX).
RETRY_FIRST = 0.5
RETRY_MAX = 5.0
KINDS = ("demo", "release", "push", "notice", "count")


class BusError(ValueError):
    """A bad ``--bus`` address or a refused message (one line for the user)."""


@dataclass
class Message:
    """A verified message from another server of the class."""

    sender: str
    kind: str
    body: dict[str, Any]


Listener = Callable[[Message], None]
StatusListener = Callable[[bool, str], None]


def bus_key(code: str) -> bytes:
    """The signing key of a class (derived from its instructor code)."""
    return hashlib.sha256(b"analyzer-lab-bus\0" + code.encode("utf-8")).digest()


def encode_message(key: bytes, sender: str, kind: str, body: dict[str, Any]) -> bytes:
    """A signed envelope (raises :class:`BusError` if the body is not plain JSON data)."""
    try:
        payload = json.dumps(
            {"from": sender, "kind": kind, "body": body}, sort_keys=True, allow_nan=False
        )
    except (TypeError, ValueError) as exc:
        raise BusError(f"not a bus message: {exc}") from None
    sig = hmac.new(key, payload.encode("utf-8"), hashlib.sha256).hexdigest()
    return json.dumps({"v": 1, "payload": payload, "sig": sig}).encode("utf-8")


def decode_message(key: bytes, raw: Any) -> Message:
    """Check size, shape and signature; raise :class:`BusError` naming what is wrong."""
    if isinstance(raw, str):
        raw = raw.encode("utf-8", "replace")
    if not isinstance(raw, (bytes, bytearray)):
        raise BusError("not a byte string")
    if len(raw) > MAX_MESSAGE_BYTES:
        raise BusError(f"too large ({len(raw)} bytes > {MAX_MESSAGE_BYTES})")
    try:
        outer = json.loads(raw)
    except (ValueError, RecursionError):
        raise BusError("not JSON") from None
    if not isinstance(outer, dict) or outer.get("v") != 1:
        raise BusError("not a version-1 envelope")
    payload, sig = outer.get("payload"), outer.get("sig")
    if not isinstance(payload, str) or not isinstance(sig, str):
        raise BusError("no payload or signature")
    good = hmac.new(key, payload.encode("utf-8"), hashlib.sha256).hexdigest()
    if not hmac.compare_digest(good, sig):
        raise BusError("bad signature (not signed with this class's instructor code)")
    try:
        inner = json.loads(payload)
    except (ValueError, RecursionError):
        raise BusError("payload is not JSON") from None
    if not isinstance(inner, dict):
        raise BusError("payload is not an object")
    sender, kind, body = inner.get("from"), inner.get("kind"), inner.get("body")
    if not isinstance(sender, str) or not sender or len(sender) > 80:
        raise BusError("no sender")
    if kind not in KINDS:
        raise BusError(f"unknown kind {str(kind)[:40]!r}")
    if not isinstance(body, dict):
        raise BusError("body is not an object")
    return Message(sender, kind, body)


class Bus:
    """Publish to / listen to the other servers of a class (never raises to callers)."""

    url = "local"

    def __init__(self, code: str, name: str | None = None) -> None:
        self.key = bus_key(code)
        self.name = name or secrets.token_hex(4)  # this server's name on the bus
        self.listeners: list[Listener] = []
        self.status_listeners: list[StatusListener] = []
        self.up = True
        self.reason = ""
        self.stats = {"sent": 0, "received": 0, "refused": 0, "dropped": 0}
        self.last_refusal = ""

    def listen(self, fn: Listener) -> None:
        self.listeners.append(fn)

    def on_status(self, fn: StatusListener) -> None:
        self.status_listeners.append(fn)

    def publish(self, kind: str, body: dict[str, Any]) -> bool:
        """Send to the other servers; False when the bus is down (the message is dropped)."""
        try:
            raw = encode_message(self.key, self.name, kind, body)
        except BusError:
            log.exception("a %s message was not sent", kind)
            return False
        ok = self._send(raw)
        self.stats["sent" if ok else "dropped"] += 1
        return ok

    def _send(self, raw: bytes) -> bool:
        raise NotImplementedError

    def deliver(self, raw: Any) -> None:
        """A raw message arrived: verify it and hand it to the listeners (not our own)."""
        try:
            msg = decode_message(self.key, raw)
        except BusError as exc:
            self.stats["refused"] += 1
            self.last_refusal = str(exc)
            print(f"[bus] refused a message: {exc}", file=sys.stderr, flush=True)
            return
        if msg.sender == self.name:
            return
        self.stats["received"] += 1
        for fn in list(self.listeners):
            try:
                fn(msg)
            except Exception:  # the bus goes on for the other listeners and messages
                log.exception("a listener failed on a %s message from %s", msg.kind, msg.sender)

    def refused(self, reason: str) -> None:
        """A listener refused a verified message's body (counted with the bus's refusals)."""
        self.stats["refused"] += 1
        self.last_refusal = reason
        print(f"[bus] refused a message: {reason}", file=sys.stderr, flush=True)

    def _set_status(self, up: bool, reason: str) -> None:
        if up == self.up and reason == self.reason:
            return
        self.up, self.reason = up, reason
        for fn in list(self.status_listeners):
            try:
                fn(up, reason)
            except Exception:  # the bus goes on for the other listeners
                log.exception("a listener failed on the bus going %s", "up" if up else "down")

    def describe(self) -> str:
        return f"{self.url} ({'connected' if self.up else 'down: ' + self.reason})"

    def close(self) -> None:
        pass


class LocalBus(Bus):
    """In-process bus: every :class:`LocalBus` sharing a ``hub`` hears the others
    (one ``serve`` process has one server: the embedded default, no service)."""

    def __init__(self, code: str, name: str | None = None, hub: list[LocalBus] | None = None):
        super().__init__(code, name)
        self.hub = hub if hub is not None else []
        self.hub.append(self)

    def _send(self, raw: bytes) -> bool:
        for bus in list(self.hub):
            if bus is not self:
                bus.deliver(raw)
        return True

    def close(self) -> None:
        if self in self.hub:
            self.hub.remove(self)


def parse_redis_url(url: str) -> tuple[str, int, int]:
    """``redis://HOST:PORT[/DB]`` -> (host, port, db); :class:`BusError` if malformed."""
    try:
        parts = urlsplit(url)
        port = parts.port or 6379
    except ValueError as exc:
        raise BusError(f"bad bus address {url[:80]!r}: {exc}") from None
    if parts.scheme != "redis" or not parts.hostname:
        raise BusError(f"the bus must be 'local' or redis://HOST:PORT, got {url[:80]!r}")
    db = parts.path.strip("/") or "0"
    if not db.isdigit():
        raise BusError(f"bad Redis database number {db[:20]!r} in {url[:80]!r}")
    return parts.hostname, int(port), int(db)


class RedisBus(Bus):
    """Redis pub/sub on :data:`CHANNEL`; a background thread listens and reconnects."""

    def __init__(self, url: str, code: str, name: str | None = None) -> None:
        super().__init__(code, name)
        import redis

        self.url = url
        host, port, db = parse_redis_url(url)
        #: what talking to Redis raises when it is down or unreachable
        self.failures: tuple[type[Exception], ...] = (redis.RedisError, OSError)
        self.up = False
        self.reason = "not connected yet"
        self._redis = redis.Redis(
            host=host,
            port=port,
            db=db,
            socket_connect_timeout=1.0,
            socket_timeout=2.0,
            health_check_interval=5,
        )
        self._stop = threading.Event()
        self._connected = threading.Event()
        self._thread = threading.Thread(target=self._run, name="analyzer-lab-bus", daemon=True)
        self._thread.start()

    def wait_connected(self, timeout: float) -> bool:
        """Wait for the first connection (``serve`` reports the outcome at start)."""
        return self._connected.wait(timeout)

    def _send(self, raw: bytes) -> bool:
        if not self.up:
            return False
        try:
            self._redis.publish(CHANNEL, raw)
            return True
        except self.failures as exc:
            self._set_status(False, _reason(exc))
            return False

    def _run(self) -> None:
        delay = RETRY_FIRST
        while not self._stop.is_set():
            pubsub = None
            try:
                pubsub = self._redis.pubsub(ignore_subscribe_messages=True)
                pubsub.subscribe(CHANNEL)
                self._redis.ping()
                self._set_status(True, "")
                self._connected.set()
                delay = RETRY_FIRST
                while not self._stop.is_set():
                    item = pubsub.get_message(timeout=0.5)
                    if item is not None and item.get("type") == "message":
                        self.deliver(item.get("data"))
            except self.failures as exc:
                self._set_status(False, _reason(exc))
                self._connected.set()
            except Exception as exc:  # the bus thread goes on: reported, then reconnecting
                log.exception("the class bus %s failed", self.url)
                self._set_status(False, _reason(exc))
                self._connected.set()
            finally:
                if pubsub is not None:
                    try:
                        pubsub.close()
                    except self.failures:
                        pass
            if self._stop.wait(delay):
                break
            delay = min(delay * 2, RETRY_MAX)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=3.0)
        try:
            self._redis.close()
        except self.failures:
            pass


def _reason(exc: Exception) -> str:
    return f"{type(exc).__name__}: {str(exc)[:160]}"


def make_bus(url: str | None, code: str, name: str | None = None) -> Bus:
    """``None``/``"local"`` -> :class:`LocalBus`; ``redis://...`` -> :class:`RedisBus`."""
    if url is None or url == "local":
        return LocalBus(code, name)
    parse_redis_url(url)  # a clear message before the client library is imported
    try:
        import redis  # noqa: F401
    except ImportError:
        raise BusError("the 'redis' Python package is needed for --bus redis://...") from None
    return RedisBus(url, code, name)


def wait_until(predicate: Callable[[], bool], timeout: float, step: float = 0.05) -> bool:
    """Poll ``predicate`` until true or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(step)
    return bool(predicate())


__all__ = [
    "Bus",
    "BusError",
    "CHANNEL",
    "LocalBus",
    "Message",
    "RedisBus",
    "bus_key",
    "decode_message",
    "encode_message",
    "make_bus",
    "parse_redis_url",
]
