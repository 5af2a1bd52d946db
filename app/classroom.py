"""Classroom: the instructor code, "follow me", release, push preset, notify all.

The instructor is the page that typed the code.  Everything instructor-only lives in
that page's ``client.gui`` (private to it); ``server.gui`` holds nothing of the
classroom, so no other page can see or press an instructor control, and a hand-made
client cannot address one (viser routes a client's GUI messages to that client's
own widgets only).

"Follow me" does not step one copy per student: every follower's
:class:`~app.view.SessionView` is pointed at the instructor's :class:`Session`; the
frame loop advances that session once per tick (:class:`SharedTick`) and every
follower view draws the same frames.  Followers' own controls are refused while
following (the view's ``gate`` hook), their widgets show the demo's values, their
camera follows the instructor's.  "Release" gives every follower a fresh session
that continues from where the demo was (same lesson, preset, values, speed and
integrator state).

Hardening (DESIGN §5): the instructor code is compared with
:func:`hmac.compare_digest`, wrong codes are rate-limited per page and across the
server; every GUI input of every page passes a token bucket (formula edits cost
more; an input over the limit is not dropped but coalesced: the newest value is
applied when the bucket refills); incoming websocket messages are paced per
connection and oversized ones dropped before viser decodes them
(:func:`harden_websocket`).
"""

from __future__ import annotations

import contextvars
import copy
import gc
import hmac
import html
import secrets
import sys
import threading
import time
import traceback
import weakref
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future
from typing import TYPE_CHECKING, Any

from app.session import LabError, Session

if TYPE_CHECKING:
    from app.server import LabServer
    from app.view import SessionView

#: Characters of generated codes (no 0/o, 1/l/i look-alikes).
CODE_ALPHABET = "abcdefghjkmnpqrstuvwxyz23456789"
MAX_CODE_LENGTH = 64
#: Wrong codes: free tries per page, then a doubling wait (s) capped at CODE_MAX_WAIT.
CODE_FREE_TRIES = 3
CODE_MAX_WAIT = 300.0
#: Wrong codes across the whole server: a burst of 10, then one per 6 s.
CODE_GLOBAL_BURST = 10
CODE_GLOBAL_RATE = 1.0 / 6.0
#: GUI inputs per page: tokens per second and burst; a text (formula) edit costs more.
INPUT_RATE = 20.0
INPUT_BURST = 20.0
TEXT_COST = 4.0
MAX_NOTICE_LENGTH = 300
#: Websocket: incoming messages per second and burst per connection; size limit.
WS_RATE = 150.0
WS_BURST = 300.0
WS_MAX_BYTES = 256 * 1024
#: Follower sync / camera pushes (Hz).
SYNC_HZ = 20.0


def generate_code() -> str:
    """An 8-character code, shown as ``xxxx-xxxx``."""
    raw = "".join(secrets.choice(CODE_ALPHABET) for _ in range(8))
    return f"{raw[:4]}-{raw[4:]}"


def normalize_code(text: Any) -> str:
    """Case, spaces and dashes do not matter when typing the code."""
    if not isinstance(text, str):
        return ""
    return "".join(ch for ch in text[:MAX_CODE_LENGTH].lower() if ch.isalnum())


class TokenBucket:
    """``rate`` tokens per second up to ``burst``; :meth:`take` spends them."""

    def __init__(self, rate: float, burst: float) -> None:
        self.rate = float(rate)
        self.burst = float(burst)
        self.tokens = float(burst)
        self.t = time.monotonic()
        self.lock = threading.Lock()

    def _refill(self, now: float) -> None:
        self.tokens = min(self.burst, self.tokens + (now - self.t) * self.rate)
        self.t = now

    def take(self, cost: float = 1.0) -> bool:
        with self.lock:
            self._refill(time.monotonic())
            if self.tokens >= cost:
                self.tokens -= cost
                return True
            return False

    def wait_time(self, cost: float = 1.0) -> float:
        """Seconds until ``cost`` tokens are there (0 if they are)."""
        with self.lock:
            self._refill(time.monotonic())
            return max(0.0, (cost - self.tokens) / self.rate) if self.rate > 0 else float("inf")


# ------------------------------------------------------------------ websocket pacing

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


# ------------------------------------------------------------------ shared stepping


class SharedTick:
    """Installed as ``session.tick`` of the demo: the first view that ticks the demo
    in a loop tick advances it (by the wall time since the last advance); the other
    views of that tick get the same frames."""

    def __init__(self, session: Session, lab: LabServer) -> None:
        self.session = session
        self.lab = lab
        self.key = -1
        self.frames: list[Any] = []
        self.last = time.monotonic()
        self.calls = 0
        self.advances = 0

    def __call__(self, wall_dt: float) -> list[Any]:
        self.calls += 1
        key = self.lab.stats.ticks
        if key != self.key:
            self.key = key
            now = time.monotonic()
            dt = now - self.last
            self.last = now
            if dt > 3.0 / self.lab.fps:  # was paused (no ticks): one frame period
                dt = 1.0 / self.lab.fps
            self.advances += 1
            self.frames = Session.tick(self.session, dt)
        return self.frames


def _reset_drawn(view: SessionView) -> None:
    """Make the view redraw everything from its (new) session.  The lesson's GUI
    (controls, plots) is rebuilt only when the lesson differs: the widgets are
    re-synced instead (rebuilding plots while frames stream to them leaves updates
    for removed components in flight)."""
    if view._drawn_lesson != view.session.lesson.id:
        view._drawn_lesson = None
    view._drawn_scene_rev = -1
    view._drawn_reset_rev = -1
    view._visible_cache = None
    view._vector_names = ()
    view._frame_dirty = True
    view._shown_notice = view.session.notices[-1] if view.session.notices else None


def _show(view: SessionView) -> None:
    """Rebuild the view from its session (caller holds the session lock)."""
    view.refresh(heavy=True)
    view._sync_widgets(force=True)
    view.derivation_due = time.monotonic()


class Presenter:
    """Presenter mode of one page: large fonts, docked (collapsible) panel, the
    lesson's presets as bookmarks stepped with "◀ Previous" / "Next ▶" and with the
    PageUp/PageDown keys (a presentation clicker) or P/N (viser commands with
    hotkeys; viser ignores them while a text field has focus)."""

    CSS = (
        "<style>html{font-size:150%!important}:root{--mantine-scale:1.45}"
        ".al-readout{font-size:1.4em!important}</style>"
    )

    def __init__(self, room: Classroom, view: SessionView) -> None:
        self.room = room
        self.view = view
        gui = view.client.gui
        self.folder = gui.add_folder("Presenter", expand_by_default=False)
        with self.folder:
            self.toggle = gui.add_checkbox(
                "Presenter mode",
                initial_value=False,
                hint="large fonts for a projector; presets become bookmarks",
            )
            self.bookmarks = gui.add_html("")
            self.prev_btn = gui.add_button("◀ Previous")
            self.next_btn = gui.add_button("Next ▶")
            gui.add_html(
                '<div style="font-size:0.8em;color:#555">Keys: PageDown / N = next, PageUp / P = previous '
                "(also in the command palette).</div>"
            )
        self.style = gui.add_html("")
        self.commands: list[Any] = []
        self.toggle.on_update(lambda e: self._on_toggle(e))
        self.prev_btn.on_click(view._guard(lambda e: self.step(-1)))
        self.next_btn.on_click(view._guard(lambda e: self.step(+1)))
        self.on = False
        self.update_bookmarks()

    def _on_toggle(self, event: Any) -> None:
        if getattr(event, "client", None) is None:
            return
        self.set_mode(bool(self.toggle.value))

    def set_mode(self, on: bool) -> None:
        gui = self.view.client.gui
        self.on = on
        self.style.content = self.CSS if on else ""
        for c in self.commands:
            try:
                c.remove()
            except Exception:
                pass
        self.commands = []
        if on:
            for label, key, step in (
                ("Next bookmark", "pagedown", 1),
                ("Previous bookmark", "pageup", -1),
                ("Next bookmark (N)", "N", 1),
                ("Previous bookmark (P)", "P", -1),
            ):
                cmd = gui.add_command(
                    label,
                    hotkey=key,
                    description="presenter mode: step through the lesson's presets",
                )
                cmd.on_trigger(self.view._guard(lambda e, s=step: self.step(s)))
                self.commands.append(cmd)
            try:
                gui.main_panel.dock_right()
                gui.main_panel.set_width(560)
            except Exception:
                pass
            self.folder.expand_by_default = True
        else:
            try:
                gui.main_panel.float()
            except Exception:
                pass
        self.update_bookmarks()

    def step(self, direction: int) -> None:
        """Next/previous preset of the page's lesson (caller holds the session lock)."""
        s = self.view.session
        names = [p.name for p in s.lesson.presets]
        if not names:
            raise LabError("this lesson has no presets to step through")
        k = names.index(s.preset) if s.preset in names else (-1 if direction > 0 else len(names))
        k = min(max(k + direction, 0), len(names) - 1)
        if names[k] != s.preset:
            s.apply_preset(names[k])
            s.notify(f"bookmark {k + 1}/{len(names)}: {names[k]}")
            self.view._after_state_change()
        self.update_bookmarks()

    def update_bookmarks(self) -> None:
        s = self.view.session
        items = []
        for k, p in enumerate(s.lesson.presets):
            cur = p.name == s.preset
            style = "font-weight:bold;color:#1c4f8a" if cur else "color:#444"
            items.append(
                f'<li class="al-bookmark{" al-current" if cur else ""}" style="{style}">'
                f"{html.escape(p.name)}: {html.escape(p.title)}</li>"
            )
        content = (
            f'<ol class="al-bookmarks" style="font-size:0.85em;padding-left:1.4em">{"".join(items)}</ol>'
            if items
            else '<div class="al-bookmarks" style="font-size:0.85em">(this lesson has no presets)</div>'
        )
        if self.bookmarks.content != content:
            self.bookmarks.content = content


class InstructorPanel:
    """The instructor's controls, in that page's ``client.gui`` only."""

    def __init__(self, room: Classroom, view: SessionView) -> None:
        self.room = room
        self.view = view
        gui = view.client.gui
        self.folder = gui.add_folder("Instructor panel", order=-1000.0)
        with self.folder:
            self.counts = gui.add_html("")
            self.follow_btn = gui.add_button(
                "Follow me",
                hint="every student sees this page's lesson, values, play state and camera",
            )
            self.release_btn = gui.add_button(
                "Release", hint="students get their own session back, from where the demo is"
            )
            self.push_dd = gui.add_dropdown("Preset for all", ("(choose)",))
            self.push_btn = gui.add_button("Push preset to all")
            self.message = gui.add_text("Message", initial_value="")
            self.notify_btn = gui.add_button("Notify all")
        self.follow_btn.on_click(self._cb(lambda: room.start_follow(view)))
        self.release_btn.on_click(self._cb(room.release))
        self.push_btn.on_click(self._cb(self._push))
        self.notify_btn.on_click(self._cb(self._notify))
        self.camera: tuple[Any, ...] | None = None
        self.camera_t = 0.0  # when the instructor's browser last reported its camera
        self.lesson_t = (
            time.monotonic()
        )  # when the instructor's lesson last changed (the view framed it)
        self._lesson = view.session.lesson.id
        view.client.camera.on_update(self._on_camera)
        self.update()

    def _cb(self, fn: Callable[[], None]) -> Callable[[Any], None]:
        def wrapped(event: Any) -> None:
            if (
                getattr(event, "client", None) is None
                or event.client.client_id != self.view.client.client_id
            ):
                return
            try:
                fn()
            except LabError as exc:
                self.view.client.add_notification(
                    "Instructor", f"refused: {exc}", auto_close_seconds=5.0, color="red"
                )
            except Exception as exc:
                traceback.print_exc()
                self.view.client.add_notification(
                    "Instructor", f"internal error: {exc}", auto_close_seconds=5.0, color="red"
                )
            self.update()

        return wrapped

    def _on_camera(self, cam: Any) -> None:
        try:
            self.camera = (
                tuple(map(float, cam.position)),
                tuple(map(float, cam.look_at)),
                tuple(map(float, cam.up_direction)),
            )
        except Exception:
            return
        self.camera_t = time.monotonic()
        self.room.camera_dirty = True

    def fresh_camera(self) -> tuple[Any, ...] | None:
        """The instructor's camera if it was reported after the last lesson change
        (before that, each follower frames the same lesson the same way itself)."""
        if self.view.session.lesson.id != self._lesson:
            self._lesson = self.view.session.lesson.id
            self.lesson_t = time.monotonic()
        return self.camera if self.camera is not None and self.camera_t > self.lesson_t else None

    def _push(self) -> None:
        name = self.push_dd.value
        s = self.view.session
        if name not in {p.name for p in s.lesson.presets}:
            raise LabError("choose one of this lesson's presets")
        self.room.push_preset(s.lesson.id, name)

    def _notify(self) -> None:
        text = self.message.value
        if not isinstance(text, str) or not text.strip():
            raise LabError("type a message first")
        self.room.notify_all(text.strip()[:MAX_NOTICE_LENGTH])
        self.message.value = ""

    def update(self) -> None:
        """Counts and the preset list (cheap; called a few times a second)."""
        students, following = self.room.counts()
        mode = (
            "following you"
            if self.room.broadcaster == self.view.client.client_id
            else "exploring on their own"
        )
        content = (
            f'<div class="al-class-counts" style="font-size:0.9em"><b>{students}</b> student(s) connected, '
            f'<b class="al-following">{following}</b> following; mode: {mode}</div>'
        )
        if self.counts.content != content:
            self.counts.content = content
        opts = ("(choose)", *(p.name for p in self.view.session.lesson.presets))
        if tuple(self.push_dd.options) != opts:
            self.push_dd.options = opts

    def remove(self) -> None:
        try:
            self.folder.remove()
        except Exception:
            pass


class Classroom:
    """Instructor sign-in, follow/release, push, notify and presenter mode for a
    :class:`~app.server.LabServer` (``lab.classroom``)."""

    def __init__(self, lab: LabServer, code: str | None = None) -> None:
        self.lab = lab
        self.code = code if code else generate_code()
        self._code_norm = normalize_code(self.code).encode()
        if len(self._code_norm) < 4:
            raise LabError("the instructor code must have at least 4 letters or digits")
        self.lock = threading.RLock()
        self.instructors: dict[int, InstructorPanel] = {}
        self.presenters: dict[int, Presenter] = {}
        self.entries: dict[int, tuple[Any, Any, Any]] = {}  # code folder, text, button
        self.broadcaster: int | None = None
        self.demo: Session | None = None
        self.followers: dict[int, SessionView] = {}
        self._synced: dict[int, tuple[Any, ...]] = {}
        self.camera_dirty = False
        self.wrong: dict[int, tuple[int, float]] = {}  # client -> (wrong count, locked until)
        self.global_wrong = TokenBucket(CODE_GLOBAL_RATE, CODE_GLOBAL_BURST)
        self.buckets: dict[int, TokenBucket] = {}
        self.pending: dict[tuple[int, str], tuple[Callable[[Any], None], Any]] = {}
        self._refused_note: dict[int, float] = {}
        self.all_sessions: weakref.WeakSet[Session] = weakref.WeakSet()
        self.stats = {
            "refused_follower": 0,
            "admitted": 0,
            "coalesced": 0,
            "replayed": 0,
            "wrong_codes": 0,
        }
        self._stop = threading.Event()
        self._thread = threading.Thread(
            target=self._run, name="analyzer-lab-classroom", daemon=True
        )
        self._thread.start()

    # ------------------------------------------------------------------ pages

    def attach(self, view: SessionView) -> None:
        """A page connected (its view is built): gate, code entry, presenter, follow."""
        cid = view.client.client_id
        view.gate = self._gate  # type: ignore[attr-defined]
        self.all_sessions.add(view.session)
        self.buckets[cid] = TokenBucket(INPUT_RATE, INPUT_BURST)
        gui = view.client.gui
        folder = gui.add_folder("Instructor", expand_by_default=False)
        with folder:
            text = gui.add_text(
                "Instructor code", initial_value="", hint="the code printed when the lab started"
            )
            btn = gui.add_button("Become instructor")
        btn.on_click(lambda e: self._on_code(view, e))
        self.entries[cid] = (folder, text, btn)
        self.presenters[cid] = Presenter(self, view)
        with self.lock:
            if self.broadcaster is not None and self.demo is not None:
                self._follow(view)

    def detach(self, client_id: int, view: SessionView | None) -> None:
        """A page left: forget it; if it was the broadcasting instructor, release."""
        with self.lock:
            self.entries.pop(client_id, None)
            self.presenters.pop(client_id, None)
            self.buckets.pop(client_id, None)
            self.wrong.pop(client_id, None)
            self._refused_note.pop(client_id, None)
            self._synced.pop(client_id, None)
            for key in [k for k in self.pending if k[0] == client_id]:
                self.pending.pop(key, None)
            panel = self.instructors.pop(client_id, None)
            self.followers.pop(client_id, None)
            if panel is not None and self.broadcaster == client_id:
                self.release()

    def is_instructor(self, client_id: int) -> bool:
        return client_id in self.instructors

    def counts(self) -> tuple[int, int]:
        with self.lab._views_lock:
            ids = list(self.lab.views)
        students = sum(1 for c in ids if c not in self.instructors)
        return students, len(self.followers)

    # ------------------------------------------------------------------ the code

    def _on_code(self, view: SessionView, event: Any) -> None:
        client = getattr(event, "client", None)
        if client is None or client.client_id != view.client.client_id:
            return
        cid = client.client_id
        if cid in self.instructors:
            return
        entry = self.entries.get(cid)
        if entry is None:
            return
        ok, message = self.check_code(cid, entry[1].value)
        entry[1].value = ""
        if not ok:
            client.add_notification("Instructor code", message, auto_close_seconds=5.0, color="red")
            return
        with self.lock:
            try:
                entry[0].remove()
            except Exception:
                pass
            self.instructors[cid] = InstructorPanel(self, view)
            self.entries.pop(cid, None)
            self.followers.pop(cid, None)
        client.add_notification(
            "Instructor",
            "you are the instructor: the Instructor panel is at the top",
            auto_close_seconds=5.0,
            color="green",
        )

    def check_code(self, client_id: int, text: Any) -> tuple[bool, str]:
        """Compare in constant time; refuse while this page or the server is locked out."""
        now = time.monotonic()
        count, until = self.wrong.get(client_id, (0, 0.0))
        if now < until:
            return False, f"too many wrong codes: wait {until - now:.0f} s"
        if self.global_wrong.wait_time() > 0:
            return (
                False,
                f"too many wrong codes on this server: wait {self.global_wrong.wait_time():.0f} s",
            )
        given = normalize_code(text).encode()
        if given and hmac.compare_digest(given, self._code_norm):
            self.wrong.pop(client_id, None)
            return True, "ok"
        self.stats["wrong_codes"] += 1
        self.global_wrong.take()
        count += 1
        wait = (
            0.0
            if count < CODE_FREE_TRIES
            else min(CODE_MAX_WAIT, 2.0 ** (count - CODE_FREE_TRIES + 1))
        )
        self.wrong[client_id] = (count, now + wait)
        return False, "wrong code" + (f"; next try in {wait:.0f} s" if wait else "")

    # ------------------------------------------------------------------ input gate

    def _gate(self, view: SessionView, event: Any, again: Callable[[Any], None] | None) -> bool:
        """Called by the view before any GUI callback: refuse followers' inputs,
        rate-limit (coalescing the newest value of a limited input)."""
        client = getattr(event, "client", None)
        cid = view.client.client_id
        if client is not None and client.client_id != cid:
            return False
        if cid in self.followers:
            self.stats["refused_follower"] += 1
            now = time.monotonic()
            if now - self._refused_note.get(cid, 0.0) > 3.0:
                self._refused_note[cid] = now
                try:
                    view.client.add_notification(
                        "Following the instructor",
                        "your controls are paused while you follow the demo; they return on release",
                        auto_close_seconds=4.0,
                        color="blue",
                    )
                except Exception:
                    pass
            with view.session.lock:
                view._sync_widgets(force=True)
            return False
        bucket = self.buckets.get(cid)
        if bucket is None:
            return True
        target = getattr(event, "target", None)
        cost = TEXT_COST if type(target).__name__ == "GuiTextHandle" else 1.0
        if bucket.take(cost):
            self.stats["admitted"] += 1
            return True
        if again is not None and target is not None:
            self.stats["coalesced"] += 1
            self.pending[(cid, str(getattr(target, "id", id(target))))] = (again, event)
        return False

    def _replay_pending(self) -> None:
        for key in list(self.pending):
            cid = key[0]
            bucket = self.buckets.get(cid)
            if bucket is None:
                self.pending.pop(key, None)
                continue
            if bucket.wait_time(TEXT_COST) > 0:
                continue
            item = self.pending.pop(key, None)
            if item is not None:
                self.stats["replayed"] += 1
                try:
                    item[0](item[1])  # goes through the gate again
                except Exception:
                    traceback.print_exc()

    # ------------------------------------------------------------------ follow / release

    def start_follow(self, instructor: SessionView) -> None:
        cid = instructor.client.client_id
        if cid not in self.instructors:
            raise LabError("only the instructor can start a demo")
        with self.lock:
            if self.broadcaster is not None and self.broadcaster != cid:
                self.release()
            demo = instructor.session
            if self.broadcaster != cid:
                self.broadcaster = cid
                self.demo = demo
                demo.tick = SharedTick(demo, self.lab)  # type: ignore[method-assign]
            with self.lab._views_lock:
                views = list(self.lab.views.values())
            for v in views:
                if (
                    v.client.client_id not in self.instructors
                    and v.client.client_id not in self.followers
                ):
                    self._follow(v)
            panel = self.instructors.get(cid)
            if panel is not None and panel.camera is not None:
                self.camera_dirty = True

    def _follow(self, view: SessionView) -> None:
        demo = self.demo
        if demo is None or view.closed:
            return
        own = view.session
        if own is demo or view.client.client_id in self.instructors:
            return
        with own.lock:
            with demo.lock:
                view.session = demo  # the page's own session is dropped: release makes a fresh one
                self.followers[view.client.client_id] = view
                _reset_drawn(view)
                _show(view)
                self._synced[view.client.client_id] = self._signature(demo)
        self.camera_dirty = True
        try:
            view.client.add_notification(
                "Following the instructor",
                "you now see the instructor's demo",
                auto_close_seconds=4.0,
                color="blue",
            )
        except Exception:
            pass
        presenter = self.presenters.get(view.client.client_id)
        if presenter is not None:
            presenter.update_bookmarks()

    def release(self) -> None:
        """Every follower gets its own session back, continuing from the demo."""
        with self.lock:
            demo = self.demo
            followers = list(self.followers.values())
            self.followers.clear()
            self._synced.clear()
            self.broadcaster = None
            self.demo = None
            if demo is not None:
                demo.__dict__.pop("tick", None)
        if demo is None:
            return
        for view in followers:
            if view.closed:
                continue
            own = self._copy_of(demo)
            with demo.lock:
                view.session = own
                with own.lock:
                    _reset_drawn(view)
                    _show(view)
            try:
                view.client.add_notification(
                    "Released",
                    "your own session continues from where the demo was",
                    auto_close_seconds=4.0,
                    color="green",
                )
            except Exception:
                pass
            presenter = self.presenters.get(view.client.client_id)
            if presenter is not None:
                presenter.update_bookmarks()

    def _copy_of(self, demo: Session) -> Session:
        """A new session with the demo's state and, if it can be copied, its run
        position (integrator state and time)."""
        with demo.lock:
            state = demo.state()
            stepper, frame, playing = demo.stepper, demo.frame, demo.playing
            try:
                stepper = copy.deepcopy(stepper)
            except Exception:
                stepper = None
        own = Session(tuple(self.lab.lessons), state.lesson)
        own.apply_state(state)
        own.notices.clear()
        if stepper is not None:
            own.stepper = stepper
            own.frame = frame
            own.log.clear()
            own.log.add(frame)
            own.playing = playing
        self.all_sessions.add(own)
        return own

    def push_preset(self, lesson_id: str, preset: str) -> None:
        """Every student (followers see it through the demo) gets lesson + preset."""
        with self.lab._views_lock:
            views = list(self.lab.views.values())
        for v in views:
            cid = v.client.client_id
            if cid in self.followers or v.closed:
                continue
            with v.session.lock:
                try:
                    if v.session.lesson.id != lesson_id:
                        v.session.select_lesson(lesson_id, preset)
                    else:
                        v.session.apply_preset(preset)
                    v.session.notify(f"the instructor pushed preset {preset}")
                    v._after_state_change()
                    v.refresh(heavy=True)
                except Exception as exc:
                    v.session.notify(f"the pushed preset could not be loaded: {exc}", "warning")
            p = self.presenters.get(cid)
            if p is not None:
                p.update_bookmarks()

    def notify_all(self, text: str) -> None:
        with self.lab._views_lock:
            views = list(self.lab.views.values())
        for v in views:
            try:
                v.client.add_notification(
                    "Instructor", text[:MAX_NOTICE_LENGTH], auto_close_seconds=20.0, color="blue"
                )
            except Exception:
                pass

    # ------------------------------------------------------------------ the sync thread

    @staticmethod
    def _signature(s: Session) -> tuple[Any, ...]:
        vis = tuple(sorted(s.visible_vectors)) if s.visible_vectors is not None else None
        return (
            s.revision,
            s.lesson.id,
            s.preset,
            s.speed,
            s.pause_at_end,
            vis,
            s.playing,
            None if s.playing else id(s.frame),
        )

    def _sync_followers(self) -> None:
        """Bring every follower in line with the demo after a change.  All followers
        are done under ONE acquisition of the demo's lock, and their derivation is
        rendered once, here (the frame loop skips a view whose lock is taken: many
        short holds of the one shared lock would make it skip followers often)."""
        demo = self.demo
        if demo is None:
            return
        sig = self._signature(demo)
        stale = [
            (cid, v)
            for cid, v in list(self.followers.items())
            if self._synced.get(cid) != sig and not v.closed
        ]
        if not stale:
            return
        derivation = (
            self._derivation_of(demo)
            if any((self._synced.get(cid) or (None,) * 6)[:6] != sig[:6] for cid, _ in stale)
            else None
        )
        changed_bookmarks = []
        with demo.lock:
            for cid, view in stale:
                old = self._synced.get(cid)
                if view.session is not demo:
                    continue
                if old is None or old[1] != sig[1]:
                    panel = self.instructors.get(self.broadcaster or -1)
                    if panel is not None:
                        panel.fresh_camera()  # a new lesson: the followers' views frame it themselves
                if old is None or old[:6] != sig[:6]:
                    view._visible_cache = None
                    view._vector_names = ()
                    _show(view)
                    if derivation is not None:
                        view.set_derivation(derivation)
                        view.derivation_due = None
                view._frame_dirty = True
                self._synced[cid] = sig
                if old is None or old[1:3] != sig[1:3]:
                    changed_bookmarks.append(cid)
        for cid in changed_bookmarks:
            p = self.presenters.get(cid)
            if p is not None:
                p.update_bookmarks()

    @staticmethod
    def _derivation_of(demo: Session) -> str | None:
        """The demo's derivation as HTML (shared cache with the server), outside the lock."""
        try:
            from app.math_render import derivation_to_html
            from app.server import DERIVATION_CACHE
            from app.session import params_key

            with demo.lock:
                lesson, params = demo.lesson, demo.params
            return DERIVATION_CACHE.get_or_make(
                params_key(lesson, params), lambda: derivation_to_html(lesson.derivation(params))
            )
        except Exception:
            return None

    def _push_camera(self) -> None:
        if not self.camera_dirty or self.broadcaster is None:
            return
        panel = self.instructors.get(self.broadcaster)
        camera = panel.fresh_camera() if panel is not None else None
        if camera is None:
            return
        self.camera_dirty = False
        pos, look, up = camera
        for view in list(self.followers.values()):
            try:
                with view.client.atomic():
                    cam = view.client.camera
                    cam.up_direction = up
                    cam.position = pos
                    cam.look_at = look
            except Exception:
                pass

    def _run(self) -> None:
        period = 1.0 / SYNC_HZ
        k = 0
        every = (
            self.lab._report_every / self.lab.fps if getattr(self.lab, "_report_every", 0) else 0.0
        )
        last_report = time.monotonic()
        while not self._stop.wait(period):
            k += 1
            try:
                with self.lock:
                    self._sync_followers()
                    self._push_camera()
                self._replay_pending()
                if k % 5 == 0:
                    for panel in list(self.instructors.values()):
                        panel.update()
                    for cid, p in list(self.presenters.items()):
                        if cid not in self.followers:
                            p.update_bookmarks()
                if every and time.monotonic() - last_report >= max(every, 10.0):
                    last_report = time.monotonic()
                    self.report()
            except Exception:
                traceback.print_exc()
            panel = p = None  # type: ignore[assignment]  # no stale reference to a page that left

    def report(self) -> dict[str, int]:
        """Figures for the soak test (printed on stderr when ANALYZER_LAB_STATS is set)."""
        gc.collect()
        with self.lab._views_lock:
            views = len(self.lab.views)
        figures = {
            "views": views,
            "sessions_alive": len(self.all_sessions),
            "followers": len(self.followers),
            "instructors": len(self.instructors),
            "presenters": len(self.presenters),
            "entries": len(self.entries),
            "buckets": len(self.buckets),
            "pending": len(self.pending),
        }
        print(
            "[classroom] " + " ".join(f"{k} {v}" for k, v in figures.items()),
            file=sys.stderr,
            flush=True,
        )
        return figures

    def stop(self) -> None:
        self._stop.set()


__all__ = [
    "CONNECTION",
    "OrderedExecutor",
    "order_callbacks",
    "Classroom",
    "SharedTick",
    "TokenBucket",
    "generate_code",
    "harden_websocket",
    "normalize_code",
]
