"""The classroom bus: how the instructor's demo, pushes, notices and page counts reach
every server process of a class.

Two buses with one interface (:class:`Bus`):

* :class:`LocalBus` (the default, ``--bus local``): in-process; the servers of one
  Python process share it (one ``serve`` process: there is nobody else to tell);
* :class:`RedisBus` (``--bus redis://HOST:PORT``): Redis pub/sub, for several worker
  processes and several machines.

Every message is a signed envelope ``AL2|sender|seq|time|sig|payload``: the signature is
an HMAC-SHA256 over everything but itself (sender, sequence number, time and the JSON
payload), keyed by the class's bus key.  The key is not the instructor code: on Redis
it is derived from the code with scrypt and the class's salt (a random value the first
server of the class stores in Redis), once per process, so a captured message does not
let anyone test codes quickly; the in-process bus keys it with a secret of the process.
A message written into Redis by anyone without the code is refused before its body is
looked at.

A message cannot be replayed: a receiver drops anything older than
:data:`REPLAY_WINDOW` seconds (or as far in the future) and anything whose sequence
number is not above the last one it accepted from that sender.  These checks read the
envelope's plain head, so replays and junk cost no JSON decoding; what passes them is
rate-limited per sender before its signature is checked and its payload decoded.  A
signed body is still not trusted: the receiver checks it like a page's input
(:mod:`analyzer_lab.classroom.link`).  Refusals are counted and logged at a bounded rate
per cause; the bus never raises into its caller.

A Redis bus that is down or unreachable is reported (``status``, listeners), the
server keeps serving its own pages, and the bus reconnects in the background.
"""

from __future__ import annotations

import hashlib
import hmac
import json
import logging
import math
import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any
from urllib.parse import urlsplit

from analyzer_lab.classroom.instructor_code import code_problem, normalize_code
from analyzer_lab.classroom.log_limit import LogLimiter
from analyzer_lab.token_bucket import TokenBucket

log = logging.getLogger(__name__)

#: Largest message accepted from the bus (bytes).
MAX_MESSAGE_BYTES = 20000
#: The Redis channel of a class, and the Redis key of its salt.
CHANNEL = "analyzer-lab:classroom"
SALT_KEY = "analyzer-lab:classroom:salt"
#: Seconds between reconnection attempts (the first; then up to RETRY_MAX).
RETRY_FIRST = 0.5
RETRY_MAX = 5.0
KINDS = ("demo", "release", "push", "notice", "count")
MAGIC = b"AL2"
MAX_SENDER = 80
#: Seconds a message stays acceptable (either side of the receiver's clock).
REPLAY_WINDOW = 10.0
#: Messages per second (and at once) a sender may send before the excess is dropped
#: unread; senders with a bucket at most (idle ones never verified are forgotten; new
#: senders past it share one bucket).
SENDER_RATE = 50.0
SENDER_BURST = 200.0
MAX_SENDERS = 64
#: scrypt's cost for the bus key (about 0.1-0.3 s once per process, 32 MB).
SCRYPT_N = 2**15
SCRYPT_R = 8
#: The in-process bus's key secret (its messages never leave the process).
_PROCESS_SECRET = secrets.token_bytes(32)
_KEYS: dict[tuple[str, bytes], bytes] = {}
_KEYS_LOCK = threading.Lock()


class BusError(ValueError):
    """A bad ``--bus`` address or a refused message (one line for the user); ``cause``
    names the kind of refusal (the log is rate-limited per cause)."""

    def __init__(self, message: str, cause: str = "refused") -> None:
        super().__init__(message)
        self.cause = cause


@dataclass
class Message:
    """A verified message from another server of the class."""

    sender: str
    kind: str
    body: dict[str, Any]
    seq: int = 0
    t: float = 0.0


@dataclass(frozen=True)
class Head:
    """The plain head of an envelope, read without decoding its payload."""

    sender: str
    seq: int
    t: float
    sig: bytes
    signed: bytes  # what the signature covers
    payload: bytes


Listener = Callable[[Message], None]
StatusListener = Callable[[bool, str], None]


def class_key(code: str, salt: bytes) -> bytes:
    """The bus key of a class: scrypt of its instructor code (as typed: case, spaces and
    dashes do not matter) with the class's salt; computed once per process and salt."""
    norm = normalize_code(code)
    with _KEYS_LOCK:
        key = _KEYS.get((norm, salt))
        if key is None:
            key = hashlib.scrypt(
                norm.encode("utf-8"),
                salt=b"analyzer-lab-bus\0" + salt,
                n=SCRYPT_N,
                r=SCRYPT_R,
                p=1,
                maxmem=64 * 2**20,
                dklen=32,
            )
            _KEYS[(norm, salt)] = key
    return key


def local_key(code: str) -> bytes:
    """The in-process bus's key: keyed by a secret of this process (nothing outside the
    process sees its messages, so no slow derivation is needed)."""
    return hmac.new(_PROCESS_SECRET, normalize_code(code).encode("utf-8"), hashlib.sha256).digest()


def encode_message(
    key: bytes,
    sender: str,
    kind: str,
    body: dict[str, Any],
    seq: int = 1,
    t: float | None = None,
) -> bytes:
    """A signed envelope (raises :class:`BusError` if the body is not plain JSON data or
    the sender's name cannot travel in the head)."""
    if not 0 < len(sender) <= MAX_SENDER or "|" in sender or not sender.isascii():
        raise BusError(f"bad sender name {sender[:MAX_SENDER]!r}")
    if not sender.isprintable():
        raise BusError(f"bad sender name {sender[:MAX_SENDER]!r}")
    name = sender.encode("ascii")
    try:
        payload = json.dumps({"kind": kind, "body": body}, sort_keys=True, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise BusError(f"not a bus message: {exc}") from None
    when = time.time() if t is None else t
    signed = b"|".join((MAGIC, name, b"%d" % seq, b"%.6f" % when, b"")) + payload.encode("utf-8")
    sig = hmac.new(key, signed, hashlib.sha256).hexdigest().encode("ascii")
    return b"|".join((MAGIC, name, b"%d" % seq, b"%.6f" % when, sig, payload.encode("utf-8")))


def read_head(raw: Any) -> Head:
    """Size and head of an envelope, without decoding its payload (:class:`BusError`)."""
    if isinstance(raw, str):
        raw = raw.encode("utf-8", "replace")
    if not isinstance(raw, (bytes, bytearray)):
        raise BusError("not a byte string", "malformed")
    if len(raw) > MAX_MESSAGE_BYTES:
        raise BusError(f"too large ({len(raw)} bytes > {MAX_MESSAGE_BYTES})", "too large")
    parts = bytes(raw).split(b"|", 5)
    if len(parts) != 6 or parts[0] != MAGIC:
        raise BusError("not a version-2 envelope", "malformed")
    magic, name, seq, when, sig, payload = parts
    if not 0 < len(name) <= MAX_SENDER or not name.isascii() or not name.decode().isprintable():
        raise BusError("no sender", "malformed")
    if not 0 < len(seq) <= 20 or not seq.isdigit() or len(when) > 24 or len(sig) != 64:
        raise BusError("no sequence number, time or signature", "malformed")
    try:
        t = float(when)
    except ValueError:
        raise BusError("no time", "malformed") from None
    if not math.isfinite(t):
        raise BusError("no time", "malformed")
    signed = b"|".join((magic, name, seq, when, b"")) + payload
    return Head(name.decode(), int(seq), t, sig, signed, payload)


def verify(key: bytes, head: Head) -> Message:
    """Check the signature, then decode the payload (:class:`BusError` naming what is wrong)."""
    good = hmac.new(key, head.signed, hashlib.sha256).hexdigest().encode("ascii")
    if not hmac.compare_digest(good, head.sig):
        raise BusError(
            "bad signature (not signed with this class's instructor code)", "bad signature"
        )
    try:
        inner = json.loads(head.payload)
    except (ValueError, RecursionError):
        raise BusError("payload is not JSON", "malformed") from None
    if not isinstance(inner, dict):
        raise BusError("payload is not an object", "malformed")
    kind, body = inner.get("kind"), inner.get("body")
    if kind not in KINDS:
        raise BusError(f"unknown kind {str(kind)[:40]!r}", "unknown kind")
    if not isinstance(body, dict):
        raise BusError("body is not an object", "malformed")
    return Message(head.sender, kind, body, head.seq, head.t)


def decode_message(key: bytes, raw: Any) -> Message:
    """Check size, head and signature and decode (no freshness: :meth:`Bus.deliver` does)."""
    return verify(key, read_head(raw))


class Bus:
    """Publish to / listen to the other servers of a class (never raises to callers)."""

    url = "local"

    def __init__(self, code: str, name: str | None = None) -> None:
        problem = code_problem(code)
        if problem:
            raise BusError(problem)
        self.code = code
        self.key = local_key(code)
        self.name = name or secrets.token_hex(4)  # this server's name on the bus
        self.listeners: list[Listener] = []
        self.status_listeners: list[StatusListener] = []
        self.up = True
        self.reason = ""
        self.stats = {
            "sent": 0,
            "received": 0,
            "refused": 0,
            "dropped": 0,
            "replayed": 0,
            "stale": 0,
            "flooded": 0,
        }
        self.last_refusal = ""
        self.logs = LogLimiter(log)
        self._seq = 0
        self._send_lock = threading.Lock()
        #: the last sequence number accepted from each sender, and its time
        self.last_seq: dict[str, tuple[int, float]] = {}
        self.buckets: dict[str, TokenBucket] = {}
        self._strangers = TokenBucket(SENDER_RATE, SENDER_BURST)

    def listen(self, fn: Listener) -> None:
        self.listeners.append(fn)

    def on_status(self, fn: StatusListener) -> None:
        self.status_listeners.append(fn)

    def publish(self, kind: str, body: dict[str, Any]) -> bool:
        """Send to the other servers; False when the bus is down (the message is dropped)."""
        with self._send_lock:
            # microseconds of the wall clock, always rising: a restarted server of the
            # same name goes on above its last number
            self._seq = max(self._seq + 1, time.time_ns() // 1000)
            seq = self._seq
        try:
            raw = encode_message(self.key, self.name, kind, body, seq)
        except BusError:
            log.exception("a %s message was not sent", kind)
            return False
        ok = self._send(raw)
        self.stats["sent" if ok else "dropped"] += 1
        return ok

    def _send(self, raw: bytes) -> bool:
        raise NotImplementedError

    def _bucket(self, sender: str) -> TokenBucket:
        bucket = self.buckets.get(sender)
        if bucket is None:
            if len(self.buckets) >= MAX_SENDERS:  # forget idle senders never verified
                for name in [
                    n
                    for n, b in self.buckets.items()
                    if n not in self.last_seq and b.wait_time(SENDER_BURST) == 0
                ]:
                    del self.buckets[name]
            if len(self.buckets) >= MAX_SENDERS:
                return self._strangers
            bucket = self.buckets[sender] = TokenBucket(SENDER_RATE, SENDER_BURST)
        return bucket

    def _drop(self, stat: str, exc: BusError) -> None:
        self.stats[stat] += 1
        self.last_refusal = str(exc)
        self.logs.warning(exc.cause, "[bus] refused a message: %s", exc)

    def deliver(self, raw: Any) -> None:
        """A raw message arrived: size and head, freshness, the sender's rate, then the
        signature and the payload; a verified message goes to the listeners."""
        try:
            head = read_head(raw)
        except BusError as exc:
            self._drop("refused", exc)
            return
        if head.sender == self.name:
            return  # our own (Redis echoes it), or someone using our name
        now = time.time()
        if abs(now - head.t) > REPLAY_WINDOW:
            age = now - head.t
            when = f"{age:.0f} s old" if age > 0 else f"{-age:.0f} s ahead of this clock"
            self._drop("stale", BusError(f"from {head.sender[:20]}: {when}", "stale"))
            return
        last = self.last_seq.get(head.sender)
        if last is not None and head.seq <= last[0]:
            self._drop(
                "replayed",
                BusError(f"from {head.sender[:20]}: number {head.seq} already seen", "replayed"),
            )
            return
        if not self._bucket(head.sender).take():
            self._drop(
                "flooded",
                BusError(f"from {head.sender[:20]}: over {SENDER_RATE:.0f} a second", "flooded"),
            )
            return
        try:
            msg = verify(self.key, head)
        except BusError as exc:
            self._drop("refused", exc)
            return
        self._seen(head.sender, head.seq, head.t, now)
        self.stats["received"] += 1
        for fn in list(self.listeners):
            try:
                fn(msg)
            except Exception:  # the bus goes on for the other listeners and messages
                log.exception("a listener failed on a %s message from %s", msg.kind, msg.sender)

    def _seen(self, sender: str, seq: int, t: float, now: float) -> None:
        """Remember the sender's last number (senders silent past the window are
        forgotten: anything they sent before is stale by then)."""
        if sender not in self.last_seq and len(self.last_seq) >= MAX_SENDERS:
            for name in [n for n, v in self.last_seq.items() if now - v[1] > 2 * REPLAY_WINDOW]:
                del self.last_seq[name]
        self.last_seq[sender] = (seq, t)

    def refused(self, reason: str, cause: str = "refused") -> None:
        """A listener refused a verified message's body (counted with the bus's refusals)."""
        self.stats["refused"] += 1
        self.last_refusal = reason
        self.logs.warning(cause, "[bus] refused a message: %s", reason)

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

    def _class_salt(self) -> bytes:
        """The class's salt: set by the first server of the class, read by the others."""
        self._redis.set(SALT_KEY, secrets.token_bytes(16), nx=True)
        salt = self._redis.get(SALT_KEY)
        if not isinstance(salt, bytes) or not salt:
            raise BusError("the class's salt is missing from Redis")
        return salt

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
                self.key = class_key(self.code, self._class_salt())
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
    "class_key",
    "decode_message",
    "encode_message",
    "local_key",
    "make_bus",
    "parse_redis_url",
    "read_head",
    "verify",
]
