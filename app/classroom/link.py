"""The classroom across server processes: what one classroom
(:class:`~analyzer_lab.classroom.ports.RoomForLink`) tells the others over the bus
(:mod:`analyzer_lab.classroom.bus`) and how it applies what they tell it.

* The server whose page is the broadcasting instructor publishes the demo (lesson,
  preset, values, speed, play state, time, camera) on every change and twice a second.
* Every other server keeps a *mirror* :class:`~analyzer_lab.session.session.Session` of that demo and
  points its own pages at it exactly as at a local demo ("follow me" without a local
  instructor); the mirror plays on the local frame loop and is put back in step when
  its time drifts from the instructor's.
* Pushes, notices and release are relayed; page counts are published every second
  and summed on the instructor's panel.

Nothing from the bus is trusted: a demo is checked against the lesson's declarations
(known lesson, known preset, declared parameters that :meth:`Lesson.resolve` accepts,
a listed speed, a time within the run, a finite camera) and refused whole otherwise,
like a page's input; a refusal is counted and logged.  Messages are queued by the
bus and applied on the classroom's sync thread (never under another server's lock).
"""

from __future__ import annotations

import html
import math
import secrets
import sys
import time
from collections import deque
from typing import Any

from analyzer_lab.classroom.bus import Bus, Message
from analyzer_lab.classroom.ports import RoomForLink
from analyzer_lab.lessons.kit.contract import ParamError
from analyzer_lab.session.session import SPEEDS, LabError, Session, SessionState

#: ``Classroom.broadcaster`` while the demo comes from another server.
REMOTE = -1
#: Longest notice to every page (characters; a longer one from the bus is refused).
MAX_NOTICE_LENGTH = 300
#: Seconds between demo publications when nothing changed (the heartbeat).
HEARTBEAT = 0.5
#: A remote demo not heard of for this long is released (its server stopped).
DEMO_TIMEOUT = 5.0
#: Page counts: published every COUNT_EVERY s, forgotten after COUNT_TIMEOUT s.
COUNT_EVERY = 1.0
COUNT_TIMEOUT = 5.0
#: Wall seconds of drift between a mirror and its demo before the mirror is re-seeked.
DRIFT = 0.3
MAX_COORD = 1e4
#: Longest demo time accepted (s of lesson time; a demo may play far past t_end).
MAX_TIME = 1e6


def _vec3(v: Any) -> tuple[float, float, float]:
    if not isinstance(v, (list, tuple)) or len(v) != 3:
        raise LabError("a camera vector must have 3 numbers")
    out = []
    for x in v:
        if isinstance(x, bool) or not isinstance(x, (int, float)):
            raise LabError("a camera coordinate must be a number")
        if not math.isfinite(x) or abs(x) > MAX_COORD:
            raise LabError("a camera coordinate must be finite and within 1e4")
        out.append(float(x))
    return out[0], out[1], out[2]


class ClassLink:
    """The bus side of one classroom (``room.link``)."""

    def __init__(self, room: RoomForLink, bus: Bus) -> None:
        self.room = room
        self.bus = bus
        self.inbox: deque[Message] = deque(maxlen=256)
        self.remote_counts: dict[str, tuple[int, int, int, float]] = {}
        self.mirror: Session | None = None
        self.mirror_from: str | None = None
        self.mirror_started = 0.0
        self.mirror_seen = 0.0
        self.remote_camera: tuple[Any, ...] | None = None
        self.started = 0.0  # wall time our own broadcast started (newest demo wins)
        self._sent_sig: tuple[Any, ...] | None = None
        self._sent_at = 0.0
        self._count_at = 0.0
        self.stats = {
            "demos_applied": 0,
            "refused": 0,
            "rebuilds": 0,
            "live_changes": 0,
            "reseeks": 0,
            "holds": 0,
        }
        bus.listen(self._arrived)
        bus.on_status(self._on_status)

    def _arrived(self, msg: Message) -> None:
        self.inbox.append(msg)
        self.room.wake.set()

    def lessons(self) -> dict[str, Any]:
        return {l.id: l for l in self.room.lab.lessons}

    # ------------------------------------------------------------------ status

    def _on_status(self, up: bool, reason: str) -> None:
        if up:
            print(f"[bus] connected to {self.bus.url}", file=sys.stderr, flush=True)
        else:
            print(
                f"[bus] {self.bus.url} is down ({reason}): serving this server's own pages, "
                "reconnecting",
                file=sys.stderr,
                flush=True,
            )

    def panel_note(self) -> str:
        """HTML for the instructor's panel when the bus is down (empty when it is up)."""
        if self.bus.up:
            return ""
        return (
            '<div class="al-bus-down" style="color:#a33;font-size:0.85em">'
            f"The class bus {html.escape(self.bus.url)} is down ({html.escape(self.bus.reason)}): "
            "only this server's pages follow you; reconnecting.</div>"
        )

    def remote_totals(self) -> tuple[int, int, int]:
        """(students, following, servers) reported by the other servers of the class."""
        now = time.monotonic()
        fresh = [v for v in self.remote_counts.values() if now - v[3] < COUNT_TIMEOUT]
        return sum(v[0] for v in fresh), sum(v[1] for v in fresh), len(fresh)

    # ------------------------------------------------------------------ publishing

    def demo_body(self) -> dict[str, Any] | None:
        room = self.room
        demo = room.demo
        if demo is None or room.broadcaster in (None, REMOTE):
            return None
        with demo.lock:
            state = demo.state()
            body: dict[str, Any] = {
                "state": {
                    "lesson": state.lesson,
                    "preset": state.preset,
                    "values": state.values,
                    "speed": state.speed,
                    "pause_at_end": state.pause_at_end,
                    "visible_vectors": state.visible_vectors,
                },
                "playing": bool(demo.playing),
                "t": float(demo.frame.t),
                "started": self.started,
            }
        camera = room.broadcaster_camera()
        body["camera"] = [list(v) for v in camera] if camera is not None else None
        return body

    def publish_demo(self, force: bool = False) -> None:
        body = self.demo_body()
        if body is None:
            return
        sig = (repr(body["state"]), body["playing"], repr(body["camera"]))
        now = time.monotonic()
        if force or sig != self._sent_sig or now - self._sent_at >= HEARTBEAT:
            self._sent_sig, self._sent_at = sig, now
            self.bus.publish("demo", body)

    def broadcast_started(self) -> None:
        self.started = time.time()
        self.publish_demo(force=True)

    def broadcast_released(self, everywhere: bool = False) -> None:
        self._sent_sig = None
        self.bus.publish("release", {"all": bool(everywhere)})

    def publish_counts(self) -> None:
        students, following = self.room.local_counts()
        pages = len(self.room.lab.open_views())
        self.bus.publish(
            "count",
            {
                "students": students,
                "following": following,
                "pages": pages,
                "port": int(self.room.lab.port),
            },
        )

    # ------------------------------------------------------------------ the sync thread

    def tick(self) -> None:
        """Apply what arrived, publish what changed (the room's lock is held)."""
        while self.inbox:
            msg = self.inbox.popleft()
            try:
                self.apply(msg)
            except LabError as exc:
                self.stats["refused"] += 1
                self.bus.refused(f"{msg.kind} from {msg.sender[:20]}: {exc}", f"bad {msg.kind}")
        room = self.room
        now = time.monotonic()
        if room.broadcaster == REMOTE and now - self.mirror_seen > DEMO_TIMEOUT:
            self.mirror_from = None
            room.release(note="the instructor's demo no longer reaches this server")
        self.publish_demo()
        if now - self._count_at >= COUNT_EVERY:
            self._count_at = now
            self.publish_counts()

    def apply(self, msg: Message) -> None:
        body = msg.body
        if msg.kind == "count":
            nums = [body.get(k) for k in ("students", "following", "pages")]
            if not all(
                isinstance(n, int) and not isinstance(n, bool) and 0 <= n < 10**6 for n in nums
            ):
                raise LabError("counts must be whole numbers")
            self.remote_counts[msg.sender] = (nums[0], nums[1], nums[2], time.monotonic())
        elif msg.kind == "demo":
            self._apply_demo(msg.sender, body)
        elif msg.kind == "release":
            everywhere = body.get("all") is True
            if self.room.broadcaster is not None and (
                everywhere or (self.mirror_from == msg.sender and self.room.broadcaster == REMOTE)
            ):
                self.mirror_from = None
                self.room.release()
        elif msg.kind == "push":
            lesson_id, preset = body.get("lesson"), body.get("preset")
            lesson = self.lessons().get(lesson_id) if isinstance(lesson_id, str) else None
            if lesson is None:
                raise LabError("push: unknown lesson")
            if preset not in {p.name for p in lesson.presets}:
                raise LabError("push: unknown preset")
            self.room.push_preset(lesson.id, str(preset), relay=False)
        elif msg.kind == "notice":
            text = body.get("text")
            if not isinstance(text, str) or not text.strip() or len(text) > MAX_NOTICE_LENGTH:
                raise LabError("notice: the text must be 1..MAX_NOTICE_LENGTH characters")
            self.room.notify_all(text, relay=False)

    def check_demo(self, body: dict[str, Any]) -> tuple[SessionState, bool, float, Any, float]:
        """Validate a demo like a page's input; raise :class:`LabError` naming the fault."""
        import json

        raw = body.get("state")
        if not isinstance(raw, dict):
            raise LabError("demo: no state")
        state = SessionState.from_json(json.dumps(raw))
        if set(raw.get("values") or {}) != set(state.values):
            raise LabError("demo: a value is not a short number, text or switch")
        lesson = self.lessons().get(state.lesson)
        if lesson is None:
            raise LabError(f"demo: unknown lesson {state.lesson[:60]!r}")
        if state.preset is not None and state.preset not in {p.name for p in lesson.presets}:
            raise LabError(f"demo: {lesson.id} has no preset {state.preset[:60]!r}")
        declared = {p.name for p in lesson.params}
        extra = sorted(set(state.values) - declared)
        if extra:
            raise LabError(f"demo: {lesson.id} declares no parameter {extra[0][:40]!r}")
        try:
            lesson.resolve(state.values, state.preset)
        except (ParamError, ValueError, ArithmeticError) as exc:
            raise LabError(f"demo: {exc}") from None
        if not any(
            isinstance(state.speed, float) and abs(state.speed - s) < 1e-9 for s in SPEEDS
        ) or isinstance(raw.get("speed"), bool):
            raise LabError("demo: the speed is not one of the listed speeds")
        playing, t, started = body.get("playing"), body.get("t"), body.get("started")
        if not isinstance(playing, bool):
            raise LabError("demo: play state must be true or false")
        if (
            isinstance(t, bool)
            or not isinstance(t, (int, float))
            or not math.isfinite(t)
            or not 0 <= t <= MAX_TIME
        ):
            raise LabError("demo: the time is not within the run")
        if isinstance(started, bool) or not isinstance(started, (int, float)):
            raise LabError("demo: no start time")
        camera = body.get("camera")
        if camera is not None:
            if not isinstance(camera, list) or len(camera) != 3:
                raise LabError("demo: the camera must be position, look-at and up")
            camera = tuple(_vec3(v) for v in camera)
        return state, playing, float(t), camera, float(started)

    def _apply_demo(self, sender: str, body: dict[str, Any]) -> None:
        state, playing, t, camera, started = self.check_demo(body)
        room = self.room
        if room.broadcaster not in (None, REMOTE) and started < self.started:
            return  # our own instructor's demo is newer
        if (
            room.broadcaster == REMOTE
            and self.mirror_from != sender
            and started < self.mirror_started
        ):
            return  # an older demo of another server still heartbeating
        mirror = self.mirror
        if mirror is None or mirror is not room.demo:
            mirror = room.new_session(state.lesson)
            mirror.notices.clear()
        with mirror.lock:
            hold = False
            if mirror is self.mirror and mirror.state() != state:
                self._change(mirror, state)
            if mirror.state() != state or mirror is not self.mirror:
                self.stats["rebuilds"] += 1
                mirror.apply_state(state)
                mirror.notices.clear()
                self._seek(mirror, t)
            else:
                drift = mirror.frame.t - t
                tol = DRIFT * mirror.speed * mirror.lesson.time_scale
                if drift < -tol or (drift > tol and t <= 2 * mirror.t_end):
                    self.stats["reseeks"] += 1
                    self._seek(mirror, t)
                elif drift > tol:  # ahead, far into the run: wait for the demo
                    self.stats["holds"] += 1
                    hold = True
            mirror.playing = playing and not hold
        self.mirror, self.mirror_from, self.mirror_started = mirror, sender, started
        self.mirror_seen = time.monotonic()
        self.stats["demos_applied"] += 1
        if camera is not None and camera != self.remote_camera:
            self.remote_camera = camera
            room.camera_moved()
        if room.broadcaster != REMOTE or room.demo is not mirror:
            if room.broadcaster is not None:
                room.release()
            room.show_demo(mirror, REMOTE)
            room.follow_everyone()

    def _change(self, mirror: Session, state: SessionState) -> None:
        """Same lesson and preset: change what changed as the instructor's session did
        (a live value keeps the run going; no replay from the start)."""
        cur = mirror.state()
        if (cur.lesson, cur.preset, set(cur.values)) != (
            state.lesson,
            state.preset,
            set(state.values),
        ):
            return
        changes = {k: v for k, v in state.values.items() if cur.values.get(k) != v}
        try:
            if changes:
                mirror.set_values(changes)
                self.stats["live_changes"] += 1
            if cur.speed != state.speed:
                mirror.set_speed(state.speed)
        except (ParamError, LabError):
            return  # rebuilt from the state instead
        mirror.pause_at_end = state.pause_at_end
        vectors = state.visible_vectors
        mirror.visible_vectors = set(vectors) if vectors is not None else None

    @staticmethod
    def _seek(mirror: Session, t: float) -> None:
        """Put the mirror at the demo's time (from the start if it is ahead)."""
        try:
            if abs(t - mirror.frame.t) > 1e-9:
                mirror.go_to(t)
        except LabError:  # beyond what "go to t" replays: the mirror goes on from its time
            pass

    def close(self) -> None:
        self.bus.close()


def new_worker_name() -> str:
    return f"w-{secrets.token_hex(3)}"


__all__ = ["ClassLink", "REMOTE"]
