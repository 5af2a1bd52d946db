"""The class bus: signed envelopes, refusals, the in-process bus, and a real Redis bus
(redis-server started here on a free loopback port; skipped without it, failing under CI=true)."""

from __future__ import annotations

import json
import time
from typing import Any

import pytest
from analyzer_lab.classroom.bus import (
    CHANNEL,
    MAX_MESSAGE_BYTES,
    REPLAY_WINDOW,
    BusError,
    LocalBus,
    Message,
    class_key,
    decode_message,
    encode_message,
    make_bus,
    parse_redis_url,
    wait_until,
)

from tests.support.redis_server import RedisServer

KEY = class_key("code-1234-abcd", b"salt-of-the-class")


def test_a_signed_message_round_trips() -> None:
    raw = encode_message(KEY, "w1", "notice", {"text": "hello"}, 7, 1000.5)
    msg = decode_message(KEY, raw)
    assert msg == Message("w1", "notice", {"text": "hello"}, 7, 1000.5)


@pytest.mark.parametrize(
    ("raw", "reason"),
    [
        (b"not json", "version-2"),
        (json.dumps({"v": 1, "payload": "{}", "sig": "00"}).encode(), "version-2"),
        (b"AL2|w1|1|1000.0|" + b"0" * 64 + b"|{}", "bad signature"),
        (b"AL2|w1|x|1000.0|" + b"0" * 64 + b"|{}", "sequence number"),
        (b"x" * (MAX_MESSAGE_BYTES + 1), "too large"),
        (12, "not a byte string"),
    ],
)
def test_malformed_or_unsigned_messages_are_refused(raw: object, reason: str) -> None:
    with pytest.raises(BusError, match=reason):
        decode_message(KEY, raw)


def test_another_class_s_key_or_a_bad_kind_is_refused() -> None:
    raw = encode_message(class_key("other-class-1234", b"salt"), "w1", "notice", {"text": "x"})
    with pytest.raises(BusError, match="bad signature"):
        decode_message(KEY, raw)
    with pytest.raises(BusError, match="unknown kind"):
        decode_message(KEY, encode_message(KEY, "w1", "shell", {}))
    with pytest.raises(BusError, match="not a bus message"):
        encode_message(KEY, "w1", "notice", {"x": float("nan")})
    with pytest.raises(BusError, match="bad sender"):
        encode_message(KEY, "w|1", "notice", {})
    # the key is not the code: another salt (another class) gives another key
    assert class_key("code-1234-abcd", b"another salt") != KEY
    assert class_key("CODE 1234-ABCD", b"salt-of-the-class") == KEY  # as typed


def test_the_local_bus_delivers_to_the_others_of_its_hub_only() -> None:
    hub: list[LocalBus] = []
    a, b = LocalBus("code-1234-abcd", "a", hub), LocalBus("code-1234-abcd", "b", hub)
    other = LocalBus("another-code-12", "c", hub)
    got: dict[str, list[Message]] = {"a": [], "b": [], "c": []}
    a.listen(got["a"].append)
    b.listen(got["b"].append)
    other.listen(got["c"].append)
    assert a.publish("count", {"students": 1, "following": 0, "pages": 1})
    assert got["a"] == [] and [m.sender for m in got["b"]] == ["a"]
    assert got["c"] == [] and other.stats["refused"] == 1  # not signed with its code
    a.close()
    b.publish("release", {})
    assert got["a"] == []


@pytest.mark.parametrize(
    ("url", "ok"),
    [
        ("redis://127.0.0.1:6379", ("127.0.0.1", 6379, 0)),
        ("redis://host/2", ("host", 6379, 2)),
        ("http://host:1", None),
        ("redis://:1", None),
        ("redis://h:99999", None),
        ("redis://h:1/x", None),
    ],
)
def test_bus_addresses(url: str, ok: tuple[str, int, int] | None) -> None:
    if ok is None:
        with pytest.raises(BusError):
            parse_redis_url(url)
    else:
        assert parse_redis_url(url) == ok
    assert isinstance(make_bus(None, "code-1234-abcd"), LocalBus)


def test_a_redis_bus_delivers_reports_a_drop_and_reconnects(redis_server: RedisServer) -> None:
    server = redis_server
    a = make_bus(server.url, "code-1234-abcd", "a")
    b = make_bus(server.url, "code-1234-abcd", "b")
    try:
        got: list[Message] = []
        changes: list[tuple[bool, str]] = []
        b.listen(got.append)
        b.on_status(lambda up, why: changes.append((up, why)))
        assert wait_until(lambda: a.up and b.up, 10)
        assert a.publish("notice", {"text": "one"})
        assert wait_until(lambda: len(got) == 1, 5) and got[0].body == {"text": "one"}
        server.stop()
        assert wait_until(lambda: not b.up, 10) and changes[-1][0] is False
        assert not a.publish("notice", {"text": "lost"}) or not a.up  # dropped, no exception
        server.start()  # same port
        assert wait_until(lambda: a.up and b.up, 20), (a.reason, b.reason)
        assert changes[-1] == (True, "")
        assert wait_until(lambda: server.subscribers(CHANNEL) == 2, 5)  # both listen again
        assert a.publish("notice", {"text": "two"})
        assert wait_until(lambda: got[-1].body == {"text": "two"}, 5)
        assert "lost" not in [m.body.get("text") for m in got]
    finally:
        a.close()
        b.close()


def _pair() -> tuple[LocalBus, LocalBus, list[Message]]:
    hub: list[LocalBus] = []
    a, b = LocalBus("code-1234-abcd", "a", hub), LocalBus("code-1234-abcd", "b", hub)
    got: list[Message] = []
    b.listen(got.append)
    return a, b, got


def test_a_replayed_message_has_no_effect() -> None:
    a, b, got = _pair()
    captured: list[bytes] = []
    a.hub.append(type("Tap", (), {"deliver": captured.append})())  # type: ignore[arg-type]
    a.publish("notice", {"text": "look"})
    a.publish("release", {"all": True})
    assert [m.kind for m in got] == ["notice", "release"]
    for _ in range(100):
        b.deliver(captured[0])  # the notice, 100 times
    for _ in range(10):
        b.deliver(captured[1])  # the release, 10 times
    assert [m.kind for m in got] == ["notice", "release"]
    assert b.stats["replayed"] == 110 and b.stats["received"] == 2
    a.publish("notice", {"text": "new"})  # the sender's next message still arrives
    assert got[-1].body == {"text": "new"}


def test_old_or_future_messages_are_dropped() -> None:
    a, b, got = _pair()
    key = a.key
    now = time.time()
    for t in (now - REPLAY_WINDOW - 5, now + REPLAY_WINDOW + 5):
        b.deliver(encode_message(key, "a", "notice", {"text": "old"}, time.time_ns(), t))
    assert got == [] and b.stats["stale"] == 2
    b.deliver(encode_message(key, "a", "notice", {"text": "now"}, time.time_ns(), now))
    assert [m.body["text"] for m in got] == ["now"]


def test_a_junk_flood_is_dropped_cheaply_with_bounded_logging(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """20,000 junk messages of every shape: all dropped, a few log lines per cause, the
    real sender's messages still arrive, and each junk message costs microseconds."""
    a, b, got = _pair()
    forger = class_key("wrong-code-9876", b"salt")
    junk = [
        b"\xff" * 300,
        b"x" * (MAX_MESSAGE_BYTES + 1),
        json.dumps({"v": 1, "payload": "{}", "sig": "0" * 64}).encode(),
        b"AL2|b|1|1.0|" + b"0" * 64 + b"|{}",
    ]
    caplog.set_level("WARNING", logger="analyzer_lab.classroom.bus")
    t0 = time.perf_counter()
    n = 0
    for k in range(5000):
        for raw in junk:
            b.deliver(raw)
            n += 1
        # fresh-looking forgeries under one name and under ever new names
        b.deliver(encode_message(forger, "mallory", "notice", {}, time.time_ns()))
        b.deliver(encode_message(forger, f"m{k}", "notice", {}, time.time_ns()))
        n += 2
        if k % 500 == 0:
            a.publish("count", {"students": 1, "following": 0, "pages": 1})
    per_message = (time.perf_counter() - t0) / n
    assert [m.kind for m in got] == ["count"] * 10
    lines = [r for r in caplog.records if "refused a message" in r.getMessage()]
    assert len(lines) <= 60, len(lines)  # 10 per cause at most in a burst
    assert b.stats["flooded"] >= 4000  # mallory's forgeries past its rate: not even verified
    assert len(b.buckets) <= 64 and len(b.last_seq) == 1
    assert per_message < 200e-6, per_message
    print(f"\n[bus] junk: {n} messages, {per_message * 1e6:.1f} us each, {len(lines)} log lines")


def test_a_weak_code_is_refused_by_every_way_in(tmp_path: Any, monkeypatch: Any) -> None:
    from analyzer_lab.classroom.instructor_code import CODE_ENV, CodeError, class_code

    weak = "abc-123"
    monkeypatch.delenv(CODE_ENV, raising=False)
    with pytest.raises(BusError, match="at least 12 letters or digits"):
        LocalBus(weak)
    with pytest.raises(CodeError, match="at least 12 letters or digits"):
        class_code(weak)
    path = tmp_path / "code"
    path.write_text(weak + "\n")
    with pytest.raises(CodeError, match="at least 12 letters or digits"):
        class_code(None, str(path))
    monkeypatch.setenv(CODE_ENV, weak)
    with pytest.raises(CodeError, match="at least 12 letters or digits"):
        class_code()
    path.write_text("good-code-4821-xk\nignored\n")
    assert class_code(None, str(path)) == "good-code-4821-xk"
    with pytest.raises(CodeError, match="cannot read"):
        class_code(None, str(tmp_path / "missing"))


def test_serve_reads_the_code_from_a_file_and_refuses_a_weak_one(tmp_path: Any) -> None:
    import subprocess
    import sys

    path = tmp_path / "code"
    path.write_text("abc\n")
    out = subprocess.run(
        [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port", "0"]
        + ["--instructor-code-file", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2 and "at least 12 letters or digits" in out.stderr, out
    assert "abc" not in out.stdout
