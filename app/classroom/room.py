"""Classroom: the instructor code, "follow me", release, push preset, notify all.

The instructor is the page that typed the code.  Everything instructor-only lives in
that page's ``client.gui`` (private to it); ``server.gui`` holds nothing of the
classroom, so no other page can see or press an instructor control, and a hand-made
client cannot address one (viser routes a client's GUI messages to that client's
own widgets only).

"Follow me" does not step one copy per student: every follower's
:class:`~analyzer_lab.view.page.SessionView` is pointed at the instructor's :class:`Session`; the
frame loop advances that session once per tick (:class:`~analyzer_lab.session.session.SharedClock`) and every
follower view draws the same frames.  Followers' own controls are refused while
following (the view's ``gate`` hook), their widgets show the demo's values, their
camera follows the instructor's.  "Release" gives every follower a fresh session
that continues from where the demo was (same lesson, preset, values, speed and
integrator state).

Hardening (DESIGN §5): the instructor code is compared with
:func:`hmac.compare_digest`, wrong codes are rate-limited per page and across the
server; every GUI input of every page passes a token bucket (formula edits cost
more; an input over the limit is not dropped but coalesced: the newest value is
applied when the bucket refills, :mod:`analyzer_lab.classroom.input_gate`); incoming websocket
messages are paced per connection and oversized ones dropped before viser decodes them
(:func:`analyzer_lab.viser_boundary.harden_websocket`).

The classroom is handed the server as a :class:`~analyzer_lab.classroom.ports.Lab` (it never
imports the server) and hands itself to its parts: the class link, the instructor's
controls and the assignment board, each through the protocol of its part
(:mod:`analyzer_lab.classroom.ports`).
"""

from __future__ import annotations

import copy
import gc
import hmac
import logging
import secrets
import sys
import threading
import time
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from analyzer_lab.classroom.assignments import AssignmentBoard
from analyzer_lab.classroom.bus import Bus, LocalBus
from analyzer_lab.classroom.course import Course
from analyzer_lab.classroom.input_gate import InputGate
from analyzer_lab.classroom.instructor import InstructorPanel, Presenter
from analyzer_lab.classroom.instructor_code import (
    CodeGuard,
    code_problem,
    generate_code,
)
from analyzer_lab.classroom.link import MAX_NOTICE_LENGTH, REMOTE, ClassLink
from analyzer_lab.classroom.ports import Camera, Lab
from analyzer_lab.session.session import LabError, Session, SharedClock
from analyzer_lab.viser_boundary import client_address

if TYPE_CHECKING:
    from analyzer_lab.view.page import SessionView

log = logging.getLogger(__name__)

#: Follower sync / camera pushes (Hz).
SYNC_HZ = 20.0
#: Seconds the class goes on following the demo after its instructor's page left (a
#: reload, a dropped connection): the instructor's page that comes back takes it over.
INSTRUCTOR_GRACE = 30.0
#: Where an instructor page keeps its role token (its own browser storage).
ROLE_KEY = "analyzer-lab-instructor"
#: What copying a demo's stepper can raise (a stepper holding a lock or a compiled
#: function that cannot be copied): the released page then starts its run afresh.
COPY_ERRORS = (TypeError, AttributeError, RecursionError, copy.Error)
#: What setting a follower's camera can raise: its browser has not reported a camera
#: yet, the camera is degenerate, or the page left.
CAMERA_ERRORS = (AssertionError, ValueError, RuntimeError)


class Classroom:
    """Instructor sign-in, follow/release, push, notify and presenter mode for the
    server it is handed (``lab.classroom``)."""

    def __init__(
        self,
        lab: Lab,
        code: str | None = None,
        bus: Bus | None = None,
        course: Course | None = None,
    ) -> None:
        self.lab = lab
        self.code = code if code else generate_code()
        problem = code_problem(self.code)
        if problem:
            raise LabError(problem)
        self.codes = CodeGuard(self.code)
        self.lock = threading.RLock()
        self.instructors: dict[int, InstructorPanel] = {}
        self.presenters: dict[int, Presenter] = {}
        self.entries: dict[int, tuple[Any, Any, Any]] = {}  # code folder, text, button
        self.broadcaster: int | None = None
        self.demo: Session | None = None
        #: when the demo is released if its instructor's page does not come back
        self.away_until: float | None = None
        self.instructor_grace = INSTRUCTOR_GRACE
        self.followers: dict[int, SessionView] = {}
        self._synced: dict[int, tuple[Any, ...]] = {}
        self.camera_dirty = False
        self._refused_note: dict[int, float] = {}
        self.all_sessions: weakref.WeakSet[Session] = weakref.WeakSet()
        self.tokens: set[str] = set()  # instructor pages' reload tokens (this server's life)
        self.stats = {
            "refused_follower": 0,
            "admitted": 0,
            "coalesced": 0,
            "replayed": 0,
            "superseded": 0,
            "wrong_codes": 0,
        }
        self._stop = threading.Event()
        self.wake = threading.Event()  # set by the bus: apply at once, not at the next period
        #: every page's token bucket and coalesced inputs
        self.inputs = InputGate(self.stats, lambda: self.lab.server)
        #: the other servers of the class (an in-process bus by default)
        self.link = ClassLink(self, bus if bus is not None else LocalBus(self.code))
        #: the assignments, the pushed one and the class's progress on them
        self.board = AssignmentBoard(self, {lesson.id for lesson in lab.lessons}, course)
        self._thread = threading.Thread(
            target=self._run, name="analyzer-lab-classroom", daemon=True
        )
        self._thread.start()

    # ------------------------------------------------------------------ pages

    def attach(self, view: SessionView) -> None:
        """A page connected (its view is built): gate, code entry, presenter, follow."""
        cid = view.client.client_id
        view.gate = self._gate
        view.language_hooks.append(self._relabel)  # what is built so far follows a switch
        self.all_sessions.add(view.session)
        self.inputs.open(cid)
        gui = view.client.gui
        tr = view.language.gettext
        folder = gui.add_folder(tr("Instructor"), expand_by_default=False)
        with folder:
            text = gui.add_text(
                tr("Instructor code"),
                initial_value="",
                hint=tr("the code printed when the lab started"),
            )
            btn = gui.add_button(tr("Become instructor"))
        btn.on_click(lambda e: self._on_code(view, e))
        self.entries[cid] = (folder, text, btn)
        self.presenters[cid] = Presenter(self, view)
        self.board.attach(view)  # after the gate: the board's gate wraps it
        if self.tokens and self._restore_role(view):
            return
        with self.lock:
            if self.broadcaster is not None and self.demo is not None:
                self._follow(view)

    def _relabel(self, view: SessionView) -> None:
        """The page's classroom folders in its language now (the page switched it; its
        session lock is held): the code entry, the presenter's folder, the instructor's
        panel."""
        cid = view.client.client_id
        tr = view.language.gettext
        entry = self.entries.get(cid)
        try:
            if entry is not None:
                folder, text, btn = entry
                folder.label = tr("Instructor")
                text.label = tr("Instructor code")
                text.hint = tr("the code printed when the lab started")
                btn.label = tr("Become instructor")
            for part in (self.presenters.get(cid), self.instructors.get(cid)):
                if part is not None:
                    part.relabel()
        except RuntimeError:  # the page left meanwhile
            log.info("page %s left while its classroom folders were relabelled", cid)

    def detach(self, client_id: int, view: SessionView | None) -> None:
        """A page left: forget it; if it was the broadcasting instructor, release."""
        with self.lock:
            self.entries.pop(client_id, None)
            self.presenters.pop(client_id, None)
            self.board.detach(client_id)
            self.inputs.forget(client_id)
            self.codes.forget(client_id)
            self._refused_note.pop(client_id, None)
            self._synced.pop(client_id, None)
            panel = self.instructors.pop(client_id, None)
            self.followers.pop(client_id, None)
            if panel is not None and self.broadcaster == client_id:
                # the class keeps the demo: another instructor page takes it over, or the
                # page that left comes back (a reload) within the grace
                heirs = [self.instructors[c].view for c in sorted(self.instructors)]
                if heirs and not heirs[-1].closed:
                    self._adopt(heirs[-1])
                else:
                    self.away_until = time.monotonic() + self.instructor_grace

    def is_instructor(self, client_id: int) -> bool:
        return client_id in self.instructors

    def is_following(self, client_id: int) -> bool:
        """Whether the page shows the demo (its own controls are paused)."""
        return client_id in self.followers

    def local_counts(self) -> tuple[int, int]:
        """(students, following) on this server."""
        ids = [v.client.client_id for v in self.lab.open_views()]
        students = sum(1 for c in ids if c not in self.instructors)
        return students, len(self.followers)

    def counts(self) -> tuple[int, int]:
        """(students, following) on every server of the class."""
        students, following = self.local_counts()
        more_students, more_following, _ = self.link.remote_totals()
        return students + more_students, following + more_following

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
        ok, message = self.check_code(cid, entry[1].value, client_address(self.lab.server, cid))
        entry[1].value = ""
        if not ok:
            client.add_notification(
                view.language.gettext("Instructor code"),
                message,
                auto_close_seconds=5.0,
                color="red",
            )
            return
        self._grant(view)
        token = secrets.token_urlsafe(24)
        self.tokens.add(token)
        try:  # the role survives a reload of this page (never another page's)
            client.local_storage.set_item(ROLE_KEY, token)
        except RuntimeError:  # the page left meanwhile
            pass
        client.add_notification(
            view.language.gettext("Instructor"),
            view.language.gettext("you are the instructor: the Instructor panel is at the top"),
            auto_close_seconds=5.0,
            color="green",
        )

    def project(self, view: SessionView, on: bool, show_class: bool = False) -> None:
        """Presenter mode on a page: its instructor panel and code entry are hidden while
        it is projected (the class sees the lesson, not the controls of the class), and so
        is the class's table of names and results unless the instructor asks for it
        (``show_class``)."""
        cid = view.client.client_id
        panel = self.instructors.get(cid)
        if panel is not None:
            panel.folder.visible = not on
        entry = self.entries.get(cid)
        if entry is not None:
            entry[0].visible = not on
        teacher = self.board.teachers.get(cid)
        if teacher is not None:
            teacher.folder.visible = not on or show_class

    def _grant(self, view: SessionView) -> None:
        """Make the page the instructor: its panel replaces the code entry."""
        cid = view.client.client_id
        with self.lock:
            entry = self.entries.pop(cid, None)
            if entry is not None:
                try:
                    entry[0].remove()
                except RuntimeError:  # the page left meanwhile
                    pass
            self.instructors[cid] = InstructorPanel(self, view, self.link)
            self.followers.pop(cid, None)
        self.board.grant(view)
        with self.lock:
            if self.away_until is not None and self.demo is not None:
                self._adopt(view)
        presenter = self.presenters.get(cid)
        if presenter is not None and presenter.on:  # signed in while projecting
            self.project(view, True, presenter.show_class)

    def _restore_role(self, view: SessionView) -> bool:
        """A page reloaded by the instructor gets the role back from the token it keeps."""
        try:
            token = view.client.local_storage.get_item(ROLE_KEY, timeout=2.0)
        except (RuntimeError, TimeoutError):  # the page left, blocks its storage or is silent
            return False
        if not isinstance(token, str) or not any(
            hmac.compare_digest(token, known) for known in list(self.tokens)
        ):
            return False
        self._grant(view)
        return True

    def check_code(self, client_id: int, text: Any, address: str = "") -> tuple[bool, str]:
        """Compare in constant time; refuse while this page (or, for a page that gave a
        wrong code, its address) must wait."""
        ok, message = self.codes.check(client_id, text, address)
        if not ok:
            self.stats["wrong_codes"] += 1
        return ok, message

    # ------------------------------------------------------------------ input gate

    def _gate(self, view: SessionView, event: Any, again: Callable[[Any], None] | None) -> bool:
        """Called by the view before any GUI callback: refuse followers' inputs (but their
        language), rate-limit (coalescing the newest value of a limited input)."""
        client = getattr(event, "client", None)
        cid = view.client.client_id
        if client is not None and client.client_id != cid:
            return False
        target = getattr(event, "target", None)
        # a follower keeps its own language: the one input a demo leaves to it
        own_language = target is not None and target is view.language_dd
        if cid in self.followers and not own_language:
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
                except RuntimeError:  # the page left meanwhile
                    pass
            with view.session.lock:
                view.sync_widgets(force=True)
            return False
        rebuilds = target is not None and (
            target is view.lesson_dd or target is view.preset_dd or own_language
        )
        return self.inputs.admit(cid, event, again, rebuilds)

    # ------------------------------------------------------------------ follow / release

    def start_follow(self, instructor: SessionView) -> None:
        cid = instructor.client.client_id
        if cid not in self.instructors:
            raise LabError("only the instructor can start a demo")
        with self.lock:
            if self.broadcaster is not None and self.broadcaster != cid:
                self.release()
            if self.broadcaster != cid:
                self.show_demo(instructor.session, cid)
                self.link.broadcast_started()
            self.follow_everyone()
            panel = self.instructors.get(cid)
            if panel is not None and panel.camera is not None:
                self.camera_dirty = True

    def _adopt(self, view: SessionView) -> None:
        """The instructor's page ``view`` takes over the demo whose page left: it shows
        the demo and broadcasts it (caller holds :attr:`lock`)."""
        demo = self.demo
        self.away_until = None
        if demo is None:
            return
        self.broadcaster = view.client.client_id
        with view.session.lock, demo.lock:
            view.show_session(demo)
        self.camera_dirty = True
        try:
            view.client.add_notification(
                "Instructor", "the class still follows your demo", auto_close_seconds=5.0
            )
        except RuntimeError:  # the page left meanwhile
            log.debug("page %s: the takeover notice was not shown", view.client.client_id)

    def show_demo(self, demo: Session, broadcaster: int) -> None:
        """``demo`` becomes the session the class follows, broadcast by the page
        ``broadcaster`` (:data:`~analyzer_lab.classroom.link.REMOTE`: another server's);
        it plays on the frame loop's clock (caller holds :attr:`lock`)."""
        self.broadcaster = broadcaster
        self.demo = demo
        demo.shared_clock = SharedClock(demo, lambda: self.lab.ticks, self.lab.fps)

    def follow_everyone(self) -> None:
        """Every page of this server that is not an instructor follows the demo."""
        for v in self.lab.open_views():
            if (
                v.client.client_id not in self.instructors
                and v.client.client_id not in self.followers
            ):
                self._follow(v)

    def _follow(self, view: SessionView) -> None:
        demo = self.demo
        if demo is None or view.closed:
            return
        own = view.session
        if own is demo or view.client.client_id in self.instructors:
            return
        with own.lock:
            with demo.lock:
                # the page's own session is dropped: release makes a fresh one
                view.show_session(demo)
                view.set_following(True)
                self.followers[view.client.client_id] = view
                self._synced[view.client.client_id] = self._signature(demo)
        self.camera_dirty = True
        try:
            view.client.add_notification(
                "Following the instructor",
                "you now see the instructor's demo",
                auto_close_seconds=4.0,
                color="blue",
            )
        except RuntimeError:  # the page left meanwhile
            pass
        presenter = self.presenters.get(view.client.client_id)
        if presenter is not None:
            presenter.update_bookmarks()

    def release(self, note: str = "", everywhere: bool = False) -> None:
        """Every follower gets its own session back, continuing from the demo;
        ``everywhere``: an instructor's "Release" (every server of the class)."""
        with self.lock:
            demo = self.demo
            followers = list(self.followers.values())
            self.followers.clear()
            self._synced.clear()
            if everywhere or self.broadcaster not in (None, REMOTE):
                self.link.broadcast_released(everywhere)
            self.broadcaster = None
            self.demo = None
            self.away_until = None
            if demo is not None:
                demo.shared_clock = None
        if demo is None:
            return
        for view in followers:
            if view.closed:
                continue
            own = self._copy_of(demo)
            with demo.lock, own.lock:
                view.show_session(own)
                view.set_following(False)
                self.board.released(view)
            try:
                view.client.add_notification(
                    "Released",
                    (note + ": " if note else "")
                    + "your own session continues from where the demo was",
                    auto_close_seconds=4.0,
                    color="green",
                )
            except RuntimeError:  # the page left meanwhile
                pass
            presenter = self.presenters.get(view.client.client_id)
            if presenter is not None:
                presenter.update_bookmarks()

    def _copy_of(self, demo: Session) -> Session:
        """A new session with the demo's state and, if it can be copied, its run
        position (integrator state and time) and the run so far (its log)."""
        with demo.lock:
            state = demo.state()
            stepper, frame, playing = demo.stepper, demo.frame, demo.playing
            try:
                stepper = copy.deepcopy(stepper)
                watched = copy.deepcopy(demo.log)  # what the page watched: its plots, exports
            except COPY_ERRORS:
                stepper = watched = None
        own = self.new_session(state.lesson)
        own.apply_state(state)
        own.notices.clear()
        if stepper is not None:
            own.reset(stepper=stepper, at=frame, playing=playing)
            if watched is not None:
                own.log = watched
        return own

    def new_session(self, lesson_id: str) -> Session:
        """A session of the server's lessons on ``lesson_id``, counted among the
        classroom's sessions (the soak test's figures)."""
        session = Session(tuple(self.lab.lessons), lesson_id)
        self.all_sessions.add(session)
        return session

    def push_preset(self, lesson_id: str, preset: str, relay: bool = True) -> None:
        """Every student (followers see it through the demo) gets lesson + preset;
        ``relay``: the other servers of the class too."""
        if relay:
            self.link.bus.publish("push", {"lesson": lesson_id, "preset": preset})
        for v in self.lab.open_views():
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
                    v.after_state_change()
                    v.refresh(heavy=True)
                except Exception as exc:  # the lesson's own code: the page says why, the log how
                    log.warning("page %s: the pushed preset failed", cid, exc_info=True)
                    v.session.notify(f"the pushed preset could not be loaded: {exc}", "warning")
            p = self.presenters.get(cid)
            if p is not None:
                p.update_bookmarks()

    def notify_all(self, text: str, relay: bool = True) -> None:
        if relay:
            self.link.bus.publish("notice", {"text": text[:MAX_NOTICE_LENGTH]})
        for v in self.lab.open_views():
            try:
                v.client.add_notification(
                    "Instructor", text[:MAX_NOTICE_LENGTH], auto_close_seconds=20.0, color="blue"
                )
            except RuntimeError:  # the page left meanwhile
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
        short holds of the one shared lock would make it skip followers often).  The
        widgets go out first; the derivation (tens of ms when new) follows."""
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
        redrawn = []
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
                    view.redraw()
                    view.derivation_due = None  # rendered once below, for every follower
                    redrawn.append(view)
                view.mark_dirty()
                self._synced[cid] = sig
                if old is None or old[1:3] != sig[1:3]:
                    changed_bookmarks.append(cid)
        derivation = self._derivation_of(demo) if redrawn else None
        if redrawn:
            with demo.lock:
                for view in redrawn:
                    if view.session is demo and not view.closed:
                        if derivation is None:
                            view.derivation_due = time.monotonic()  # the server's slow loop
                        else:
                            view.set_derivation(derivation)
        for cid in changed_bookmarks:
            p = self.presenters.get(cid)
            if p is not None:
                p.update_bookmarks()

    def _derivation_of(self, demo: Session) -> str | None:
        """The demo's derivation as HTML (the server's cache), outside the lock; None when
        it cannot be built here (the server's slow loop then builds it for each page)."""
        with demo.lock:
            lesson, params = demo.lesson, demo.params
        try:
            return self.lab.derivation_html(lesson, params)
        except Exception:  # the lesson's own code
            log.warning("the derivation of the demo (%s) failed", lesson.id, exc_info=True)
            return None

    def broadcaster_camera(self) -> Camera | None:
        """The broadcasting instructor's camera on this server, once reported after the
        last lesson change (None otherwise)."""
        panel = self.instructors.get(self.broadcaster) if self.broadcaster is not None else None
        return panel.fresh_camera() if panel is not None else None

    def camera_moved(self) -> None:
        """The demo's camera changed: the followers get it at the next sync."""
        self.camera_dirty = True

    def _push_camera(self) -> None:
        if not self.camera_dirty or self.broadcaster is None:
            return
        camera = self.broadcaster_camera()
        if self.broadcaster == REMOTE:
            camera = self.link.remote_camera
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
            except CAMERA_ERRORS:  # not reported yet, degenerate, or the page left
                pass

    def _run(self) -> None:
        period = 1.0 / SYNC_HZ
        k = 0
        every = self.lab.report_interval
        last_report = time.monotonic()
        while not self._stop.is_set():
            self.wake.wait(period)
            self.wake.clear()
            if self._stop.is_set():
                break
            k += 1
            try:  # the waiting inputs are replayed whatever else of this period fails
                self.inputs.replay()
            except Exception:  # the sync thread goes on
                log.exception("replaying the waiting inputs failed")
            try:
                with self.lock:
                    if self.away_until is not None and time.monotonic() >= self.away_until:
                        self.release("the instructor left")
                    self.link.tick()
                    self._sync_followers()
                    self._push_camera()
                if k % 5 == 0:
                    for panel in list(self.instructors.values()):
                        panel.update()
                    for cid, p in list(self.presenters.items()):
                        if cid not in self.followers:
                            p.update_bookmarks()
                if every and time.monotonic() - last_report >= max(every, 10.0):
                    last_report = time.monotonic()
                    self.report()
            except Exception:  # the sync thread goes on
                log.exception("classroom sync failed")
            panel = p = None  # type: ignore[assignment]  # no stale reference to a page that left

    def report(self) -> dict[str, int]:
        """Figures for the soak test (printed on stderr when ANALYZER_LAB_STATS is set)."""
        gc.collect()
        views = len(self.lab.open_views())
        figures = {
            "views": views,
            "sessions_alive": len(self.all_sessions),
            "followers": len(self.followers),
            "instructors": len(self.instructors),
            "presenters": len(self.presenters),
            "entries": len(self.entries),
            "buckets": len(self.inputs.buckets),
            "pending": len(self.inputs.pending),
        }
        print(
            "[classroom] " + " ".join(f"{k} {v}" for k, v in figures.items()),
            file=sys.stderr,
            flush=True,
        )
        return figures

    def stop(self) -> None:
        self._stop.set()
        self.wake.set()
        self.link.close()
        self.board.stop()


__all__ = ["Classroom"]
