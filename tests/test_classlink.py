"""The classroom across server processes: two ``serve`` processes joined by a real
redis-server (started here on a free loopback port), pages as real websocket clients.

Skipped without redis-server (``apt-get install redis-server``); failing under CI=true.
"""

from __future__ import annotations

import asyncio
import json
import statistics
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.support.client import ProtoClient
from tests.support.redis_server import RedisServer
from tests.support.servers import free_port, start_worker, stop_process
from tests.support.waiting import until, wait_until

pytestmark = pytest.mark.timeout(300)
CODE = "class-5821-bus7"


class Pair:
    """Two workers of one class on one Redis."""

    def __init__(self, tmp: Path, redis: RedisServer) -> None:
        self.redis = redis
        self.logs = [tmp / "w1.log", tmp / "w2.log"]
        self.ports = [free_port(), free_port()]
        self.procs = [
            start_worker(p, self.redis.url, f"w{k + 1}", CODE, open(self.logs[k], "w"))
            for k, p in enumerate(self.ports)
        ]

    def url(self, k: int) -> str:
        return f"ws://127.0.0.1:{self.ports[k]}/"

    def log(self, k: int) -> str:
        return self.logs[k].read_text()

    def stop(self) -> None:
        for p in self.procs:
            stop_process(p)


@pytest.fixture()
def pair(tmp_path: Path, redis_server: RedisServer) -> Iterator[Pair]:
    p = Pair(tmp_path, redis_server)
    yield p
    p.stop()


def _value(c: ProtoClient, label: str) -> Any:
    return c.values.get(c.gui.get(label, ""))


def _field_error(c: ProtoClient) -> bool:
    """The page shows a field's refusal (its own controls answer, it does not follow)."""
    return any("al-field-error" in h and "u1" in h for h in c.html.values())


def _counts(c: ProtoClient) -> str:
    return " ".join(h for h in c.html.values() if "al-class-counts" in h)


async def _demo(pair: Pair) -> tuple[ProtoClient, ProtoClient, ProtoClient]:
    """Instructor and one student on worker 1, one student on worker 2, following."""
    inst = await ProtoClient(pair.url(0)).start()
    local = await ProtoClient(pair.url(0)).start()
    remote = await ProtoClient(pair.url(1)).start()
    for c in (inst, local, remote):
        await c.wait_for("Run")
    await inst.become_instructor(CODE)
    await inst.set("Preset", "example-1.2", 0.4)
    await inst.set("pause at t_end", False, 0.1)
    await inst.set("Run", "Play", 0.2)
    await inst.click("Follow me", 0.2)
    await until(lambda: _value(remote, "Preset") == "example-1.2", 15, "the demo's preset on w2")
    return inst, local, remote


def test_a_follower_on_another_worker_follows_the_instructor(pair: Pair) -> None:
    async def run() -> None:
        inst, local, remote = await _demo(pair)
        # the remote follower gets the demo's frames, and the instructor's edits
        remote.measuring = True
        await until(lambda: remote.point_updates >= 10, 10, "the demo's frames on w2")
        remote.measuring = False
        assert remote.point_updates >= 10, (
            remote.point_updates
        )  # frames flow (a loaded machine: no rate)
        await inst.set("u1(t) =", "3", 0.1)
        await until(lambda: _value(remote, "u1(t) =") == "3", 10, "u1 on the remote follower")
        await until(lambda: _value(local, "u1(t) =") == "3", 10, "u1 on the local follower")
        # the instructor's camera reaches the remote follower
        from viser import _messages

        await inst.send(
            _messages.ViewerCameraMessage(
                wxyz=(1.0, 0.0, 0.0, 0.0),
                position=(5.0, -4.0, 2.0),
                fov=1.0,
                near=0.01,
                far=100.0,
                image_height=720,
                image_width=1280,
                look_at=(0.5, 0.0, 0.0),
                up_direction=(0.0, 0.0, 1.0),
            )
        )

        def camera_at(c: ProtoClient) -> Any:
            m = c.last.get("SetCameraPositionMessage")
            return m is not None and [round(float(x), 3) for x in m["position"]] == [5, -4, 2]

        await until(lambda: camera_at(remote) and camera_at(local), 10, "the camera on w2")
        # the play state: the instructor pauses, the remote follower's point stops
        await inst.set("Run", "Pause", 0.5)
        remote.point_updates = 0
        remote.measuring = True
        await asyncio.sleep(1.5)  # a paused demo: no frames may come meanwhile
        remote.measuring = False
        assert remote.point_updates <= 2, remote.point_updates
        await inst.set("Run", "Play", 0.1)
        # its controls are refused while following
        await remote.set("u1(t) =", "9", 0.5)
        assert _value(remote, "u1(t) =") == "3"
        # counts from both workers reach the instructor's panel
        await until(
            lambda: "<b>2</b> student(s) connected on 2 servers" in _counts(inst), 10, "counts"
        )
        assert '<b class="al-following">2</b>' in _counts(inst)
        # notices and release cross too
        await inst.set("Message", "look at the pole", 0.1)
        await inst.click("Notify all", 0.2)
        await until(
            lambda: any("look at the pole" in n for n in remote.notifications), 10, "notice"
        )
        await inst.click("Release", 0.2)
        await until(
            lambda: any(n.startswith("Released") for n in remote.notifications), 10, "release"
        )
        assert not _field_error(remote)
        await remote.set("u1(t) =", "7 +", 0.1)
        await until(lambda: _field_error(remote), 10, "own control back after release")
        for c in (inst, local, remote):
            assert not c.error, c.error
            await c.close()

    asyncio.run(run())


def test_killing_a_worker_leaves_the_other_and_the_demo_running(pair: Pair) -> None:
    async def run() -> None:
        inst, local, remote = await _demo(pair)
        stop_process(pair.procs[1])  # worker 2 and its page go
        await until(lambda: remote.error or remote.ws.close_code is not None, 10, "w2's page lost")
        local.measuring = True
        inst.measuring = True
        await until(
            lambda: local.point_updates >= 10 and inst.point_updates >= 10, 10, "frames on w1"
        )
        assert local.point_updates >= 10 and inst.point_updates >= 10, (
            local.point_updates,
            inst.point_updates,
        )
        await inst.set("u1(t) =", "6", 0.1)
        await until(lambda: _value(local, "u1(t) =") == "6", 10, "the demo goes on on worker 1")
        # worker 2's count ages out of the instructor's panel
        await until(lambda: "on 2 servers" not in _counts(inst), 15, "w2 gone from the counts")
        for c in (inst, local):
            assert not c.error, c.error
            await c.close()

    asyncio.run(run())


def test_a_dead_instructor_worker_releases_its_followers_elsewhere(pair: Pair) -> None:
    async def run() -> None:
        inst, local, remote = await _demo(pair)
        stop_process(pair.procs[0])
        await until(
            lambda: any("no longer reaches" in n for n in remote.notifications), 15, "released"
        )
        remote.measuring = True
        await until(lambda: remote.point_updates >= 10, 10, "the page's own frames")
        assert remote.point_updates >= 10  # the page's own session goes on playing
        await remote.set("u1(t) =", "8 +", 0.1)
        await until(lambda: _field_error(remote), 10, "its own controls")
        await remote.close()

    asyncio.run(run())


def _publish(url: str, raw: bytes) -> None:
    import redis
    from analyzer_lab.classroom.bus import CHANNEL

    port = int(url.rsplit(":", 1)[1])
    client = redis.Redis(host="127.0.0.1", port=port)
    assert client.publish(CHANNEL, raw) >= 2  # both workers are subscribed
    client.close()


def _class_key(url: str) -> bytes:
    """The class's bus key (what a holder of the code derives with the salt in Redis)."""
    import redis
    from analyzer_lab.classroom.bus import SALT_KEY, class_key

    client = redis.Redis(host="127.0.0.1", port=int(url.rsplit(":", 1)[1]))
    salt = client.get(SALT_KEY)
    client.close()
    assert isinstance(salt, bytes)
    return class_key(CODE, salt)


def test_forged_messages_from_the_bus_are_refused(pair: Pair) -> None:
    from analyzer_lab.classroom.bus import encode_message

    async def run() -> None:
        inst, local, remote = await _demo(pair)
        state = {"lesson": "sphere", "preset": "example-1.2", "values": {}, "speed": 1.0}
        good = {"state": state, "playing": True, "t": 0.5, "started": time.time() + 100}
        # unsigned (written by someone without the class's code)
        payload = json.dumps({"kind": "demo", "body": good}).encode()
        _publish(
            pair.redis.url,
            b"AL2|w1|%d|%.6f|" % (time.time_ns(), time.time()) + b"0" * 64 + b"|" + payload,
        )
        key = _class_key(pair.redis.url)
        forged = [
            {**good, "state": {**state, "values": {"u1": "__import__('os').system('true')"}}},
            {**good, "state": {**state, "values": {"not_a_param": "1"}}},
            {**good, "state": {**state, "lesson": "no-such-lesson"}},
            {**good, "state": {**state, "speed": 3.0}},
            {**good, "t": 1e9},
            {**good, "camera": [[1e300, 0, 0], [0, 0, 0], [0, 0, 1]]},
        ]
        for k, body in enumerate(forged):  # each a new number: signed, fresh, refused by content
            _publish(pair.redis.url, encode_message(key, "mallory", "demo", body, k + 1))
        notice = encode_message(key, "mallory", "notice", {"text": "x" * 5000}, 99)
        _publish(pair.redis.url, notice)
        _publish(pair.redis.url, b"\xff" * 30000)
        await until(lambda: pair.log(1).count("[bus] refused a message") >= 9, 10, "refusals")
        log = pair.log(1)
        assert "bad signature" in log and "declares no parameter 'not_a_param'" in log
        assert "unknown lesson" in log and "speed" in log and "too large" in log
        assert "the time is not within the run" in log and "camera coordinate" in log
        # the followers still show the instructor's demo, not the forged one
        await inst.set("u1(t) =", "4", 0.1)
        await until(lambda: _value(remote, "u1(t) =") == "4", 10, "the real demo still arrives")
        assert not any("x" * 100 in n for n in remote.notifications)
        for c in (inst, local, remote):
            assert not c.error, c.error
            await c.close()

    asyncio.run(run())


def test_a_bus_that_is_down_is_reported_and_reconnects(tmp_path: Path) -> None:
    redis_server = RedisServer()  # its port is free: nothing listens yet
    port = free_port()
    log_path = tmp_path / "w.log"
    proc = start_worker(port, redis_server.url, "w1", CODE, open(log_path, "w"))
    try:

        async def run() -> None:
            inst = await ProtoClient(f"ws://127.0.0.1:{port}/").start()
            await inst.wait_for("Run")  # serves its own pages meanwhile
            await inst.become_instructor(CODE)
            await until(lambda: "al-bus-down" in _counts(inst), 20, "down on the panel")
            await until(
                lambda: "[bus] redis://127.0.0.1" in log_path.read_text(), 20, "down in the log"
            )
            redis_server.start()
            await until(lambda: "[bus] connected" in log_path.read_text(), 20, "reconnected")
            await until(lambda: "al-bus-down" not in _counts(inst), 20, "panel clear")
            redis_server.stop()  # drops while serving
            await until(lambda: "al-bus-down" in _counts(inst), 20, "the drop on the panel")
            await inst.set("Run", "Play", 0.1)
            inst.measuring = True
            await until(lambda: inst.point_updates >= 5, 10, "the page's frames")
            assert inst.point_updates >= 5
            assert not inst.error
            await inst.close()

        asyncio.run(run())
    finally:
        stop_process(proc)
        redis_server.stop()


def test_serve_reports_an_unreachable_bus_at_start() -> None:
    import subprocess
    import sys

    port = free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port", str(free_port())]
        + ["--bus", f"redis://127.0.0.1:{port}", "--lesson", "sphere"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        lines = []
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            line = proc.stdout.readline() if proc.stdout else ""
            lines.append(line)
            if "class bus" in line:
                break
        text = "".join(lines)
        assert f"the class bus redis://127.0.0.1:{port} is unreachable" in text, text
        assert "serving this server's own pages; reconnecting" in text
        assert proc.poll() is None
    finally:
        stop_process(proc)


def test_two_servers_in_one_process_share_the_in_process_bus() -> None:
    """The embedded default: a demo crosses a LocalBus hub; the mirror is rebuilt only
    when the demo's state changes (not at every heartbeat) and follows its time."""
    from analyzer_lab.classroom.bus import LocalBus
    from analyzer_lab.classroom.link import REMOTE
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.serve.server import LabServer
    from analyzer_lab.session.session import Session

    hub: list[LocalBus] = []
    lessons = [get_lesson("sphere"), get_lesson("ellipsoid")]
    a, b = (
        LabServer(
            port=0,
            lessons=lessons,
            instructor_code=CODE,
            bus=LocalBus(CODE, name, hub),
            warm_up=False,
        )
        for name in ("a", "b")
    )
    try:
        demo = Session(a.lessons, "sphere")
        demo.apply_preset("example-1.2")
        demo.pause_at_end = False
        demo.play()
        with a.classroom.lock:
            a.classroom.broadcaster, a.classroom.demo = 7, demo  # a page's id on server a
            a.classroom.link.broadcast_started()
        for _ in range(20):
            with demo.lock:
                demo.advance_wall(0.1)
            time.sleep(0.1)  # the demo plays 2 s: heartbeats cross the bus meanwhile
        link = b.classroom.link
        assert b.classroom.broadcaster == REMOTE and link.mirror is b.classroom.demo
        assert link.stats["rebuilds"] == 1 and link.stats["demos_applied"] >= 3
        mirror = link.mirror
        assert mirror is not None and mirror.preset == "example-1.2"
        assert abs(mirror.frame.t - demo.frame.t) < 0.8
        with demo.lock:
            demo.set_values({"u1": "3"})
        wait_until(lambda: mirror.raw_values().get("u1") == "3", 5, "the change to cross")
        assert link.stats["rebuilds"] == 1 and link.stats["live_changes"] == 1  # as the demo did
        with a.classroom.lock:
            a.classroom.release()
        wait_until(lambda: b.classroom.broadcaster is None, 5, "the release to cross")
        # an instructor's "Release" on any server releases the demo of another server too
        with a.classroom.lock:
            a.classroom.broadcaster, a.classroom.demo = 7, demo
            a.classroom.link.broadcast_started()
        wait_until(lambda: b.classroom.broadcaster == REMOTE, 5, "the second demo to cross")
        with b.classroom.lock:
            b.classroom.release(everywhere=True)
        wait_until(lambda: a.classroom.broadcaster is None, 5, "the release everywhere to reach a")
    finally:
        a.stop()
        b.stop()


class Tap:
    """Everything on the class's channel, as someone with access to Redis (not the
    code) captures it."""

    def __init__(self, url: str) -> None:
        import threading

        import redis
        from analyzer_lab.classroom.bus import CHANNEL

        self.client = redis.Redis(host="127.0.0.1", port=int(url.rsplit(":", 1)[1]))
        self.pubsub = self.client.pubsub(ignore_subscribe_messages=True)
        self.pubsub.subscribe(CHANNEL)
        self.raw: list[bytes] = []
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        while not self.stop.is_set():
            item = self.pubsub.get_message(timeout=0.2)
            if item is not None and item.get("type") == "message":
                self.raw.append(item["data"])

    def of(self, kind: str) -> list[bytes]:
        return [r for r in self.raw if b'"kind": "' + kind.encode() + b'"' in r]

    def close(self) -> None:
        self.stop.set()
        self.thread.join(2)
        self.pubsub.close()
        self.client.close()


def _count(c: ProtoClient, start: str) -> int:
    return sum(1 for n in c.notifications if n.startswith(start))


def test_replayed_bus_messages_have_no_effect(pair: Pair) -> None:
    """A captured demo, a notice replayed 100 times and a release replayed 10 times
    change nothing on the other worker's page."""
    tap = Tap(pair.redis.url)

    async def run() -> None:
        inst, local, remote = await _demo(pair)
        await inst.set("Message", "look at the pole", 0.1)
        await inst.click("Notify all", 0.2)
        await until(lambda: _count(remote, "Instructor: look at the pole") == 1, 10, "notice")
        await inst.click("Release", 0.2)
        await until(lambda: _count(remote, "Released") == 1, 10, "release")
        demos, notices, releases = tap.of("demo"), tap.of("notice"), tap.of("release")
        assert demos and len(notices) == 1 and len(releases) == 1
        following = _count(remote, "Following the instructor")
        # an old demo replayed while the page has its own session: it does not follow
        for raw in demos[-20:]:
            _publish(pair.redis.url, raw)
        await asyncio.sleep(2.0)
        assert _count(remote, "Following the instructor") == following
        # a new demo; the old notice 100 times and the old release 10 times
        await inst.click("Follow me", 0.2)
        await until(
            lambda: _count(remote, "Following the instructor") == following + 1, 15, "follows"
        )
        for _ in range(100):
            _publish(pair.redis.url, notices[0])
        for _ in range(10):
            _publish(pair.redis.url, releases[0])
        await until(lambda: "already seen" in pair.log(1), 10, "the replays refused")
        await asyncio.sleep(2.0)
        assert _count(remote, "Instructor: look at the pole") == 1
        assert _count(remote, "Released") == 1  # still following the new demo
        await inst.set("u1(t) =", "5", 0.1)
        await until(lambda: _value(remote, "u1(t) =") == "5", 10, "the real demo still arrives")
        log = pair.log(1)
        assert log.count("[bus] refused a message") <= 40, log[-2000:]
        for c in (inst, local, remote):
            assert not c.error, c.error
            await c.close()

    try:
        asyncio.run(run())
    finally:
        tap.close()


FLOOD = """
import sys, time, redis
from analyzer_lab.classroom.bus import CHANNEL
port, rate, seconds, path = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
raws = [bytes.fromhex(line) for line in open(path).read().split()]
client = redis.Redis(host="127.0.0.1", port=port)
sent, t0 = 0, time.monotonic()
while time.monotonic() - t0 < seconds:
    pipe = client.pipeline(transaction=False)
    for k in range(int(rate / 20)):
        pipe.publish(CHANNEL, raws[(sent + k) % len(raws)])
    pipe.execute()
    sent += int(rate / 20)
    time.sleep(max(0.0, t0 + sent / rate - time.monotonic()))
print(sent)
"""


async def _rates(c: ProtoClient, seconds: float) -> list[float]:
    """Updates/s of ``c`` in half-second windows."""
    out = []
    c.measuring = True
    for _ in range(int(seconds / 0.5)):
        c.point_updates = 0
        await asyncio.sleep(0.5)
        out.append(c.point_updates / 0.5)
    c.measuring = False
    return out


def test_a_replay_and_junk_flood_keeps_the_follower_on_the_other_worker(
    pair: Pair, tmp_path: Path
) -> None:
    """Captured messages replayed (and junk) at 1,000 a second: the follower on the
    other worker keeps >= 90% of its baseline updates/s, the log stays short."""
    import subprocess
    import sys

    import psutil

    tap = Tap(pair.redis.url)

    async def run() -> None:
        inst, local, remote = await _demo(pair)
        await asyncio.sleep(1.0)
        captured = tap.raw[-50:] + [b"\xff" * 500, b"AL2|w1|1|1.0|" + b"0" * 64 + b"|{}"]
        path = tmp_path / "captured.hex"
        path.write_text("\n".join(r.hex() for r in captured))
        worker = psutil.Process(pair.procs[1].pid)
        base = await _rates(remote, 4.0)
        mb_before = worker.memory_info().rss / 2**20
        lines_before = pair.log(1).count("\n")
        flood = subprocess.Popen(
            [sys.executable, "-c", FLOOD, pair.redis.url.rsplit(":", 1)[1], "1000", "6"]
            + [str(path)],
            stdout=subprocess.PIPE,
            text=True,
        )
        await asyncio.sleep(1.0)
        during = await _rates(remote, 4.0)
        sent = int((flood.communicate(timeout=60)[0] or "0").strip())
        after = await _rates(remote, 4.0)
        mb_after = worker.memory_info().rss / 2**20
        lines = pair.log(1).count("\n") - lines_before
        ratio = statistics.median(during) / statistics.median(base)
        print(
            f"\n[bus flood] {sent} replays+junk in 6 s; follower {statistics.median(base):.1f}"
            f" -> {statistics.median(during):.1f} ({ratio:.0%})"
            f" -> {statistics.median(after):.1f} updates/s; {lines} log lines;"
            f" worker {mb_before:.0f} -> {mb_after:.0f} MB"
        )
        assert sent >= 3000
        assert ratio >= 0.9, (base, during)
        assert statistics.median(after) >= 0.9 * statistics.median(base), (base, after)
        assert mb_after <= 1.1 * mb_before, (mb_before, mb_after)
        assert lines <= 60, pair.log(1)[-3000:]
        assert _count(remote, "Released") == 0
        for c in (inst, local, remote):
            assert not c.error, c.error
            await c.close()

    try:
        asyncio.run(run())
    finally:
        tap.close()
