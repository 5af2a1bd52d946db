"""The class bus: signed envelopes, refusals, the in-process bus, and a real Redis bus
(redis-server started here on a free loopback port; skipped without it, failing under CI=true)."""

from __future__ import annotations

import json

import pytest
from analyzer_lab.classroom.bus import (
    CHANNEL,
    MAX_MESSAGE_BYTES,
    BusError,
    LocalBus,
    Message,
    bus_key,
    decode_message,
    encode_message,
    make_bus,
    parse_redis_url,
    wait_until,
)

from tests.support.redis_server import RedisServer

KEY = bus_key("code-1234")


def test_a_signed_message_round_trips() -> None:
    raw = encode_message(KEY, "w1", "notice", {"text": "hello"})
    msg = decode_message(KEY, raw)
    assert msg == Message("w1", "notice", {"text": "hello"})


@pytest.mark.parametrize(
    ("raw", "reason"),
    [
        (b"not json", "not JSON"),
        (json.dumps({"v": 2}).encode(), "version-1"),
        (json.dumps({"v": 1, "payload": "{}", "sig": "00"}).encode(), "bad signature"),
        (b"x" * (MAX_MESSAGE_BYTES + 1), "too large"),
        (12, "not a byte string"),
    ],
)
def test_malformed_or_unsigned_messages_are_refused(raw: object, reason: str) -> None:
    with pytest.raises(BusError, match=reason):
        decode_message(KEY, raw)


def test_another_class_s_key_or_a_bad_kind_is_refused() -> None:
    raw = encode_message(bus_key("other-class"), "w1", "notice", {"text": "x"})
    with pytest.raises(BusError, match="bad signature"):
        decode_message(KEY, raw)
    with pytest.raises(BusError, match="unknown kind"):
        decode_message(KEY, encode_message(KEY, "w1", "shell", {}))
    with pytest.raises(BusError, match="not a bus message"):
        encode_message(KEY, "w1", "notice", {"x": float("nan")})


def test_the_local_bus_delivers_to_the_others_of_its_hub_only() -> None:
    hub: list[LocalBus] = []
    a, b = LocalBus("code-1234", "a", hub), LocalBus("code-1234", "b", hub)
    other = LocalBus("another-code", "c", hub)
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
    assert isinstance(make_bus(None, "code-1234"), LocalBus)


def test_a_redis_bus_delivers_reports_a_drop_and_reconnects(redis_server: RedisServer) -> None:
    server = redis_server
    a = make_bus(server.url, "code-1234", "a")
    b = make_bus(server.url, "code-1234", "b")
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
