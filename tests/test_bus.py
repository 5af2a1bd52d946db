"""The class bus: signed envelopes, refusals, the in-process bus, and a real Redis bus
(redis-server started here on a free loopback port; skipped without it, failing under CI=true)."""

from __future__ import annotations

import json
import time

import pytest
from analyzer_lab.classroom.bus import (
    MAX_MESSAGE_BYTES,
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

from tests.helpers import RedisServer

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


def test_a_redis_bus_delivers_reports_a_drop_and_reconnects() -> None:
    server = RedisServer().start()
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
        time.sleep(0.2)
        assert a.publish("notice", {"text": "two"})
        assert wait_until(lambda: got[-1].body == {"text": "two"}, 5)
        assert "lost" not in [m.body.get("text") for m in got]
    finally:
        a.close()
        b.close()
        server.stop()
