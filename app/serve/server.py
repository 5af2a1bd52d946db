"""``analyzer-lab serve``: the viser server, one session per browser tab, one frame loop.

:class:`LabServer` owns the :class:`viser.ViserServer` (loopback by default, share
tunnel disabled, page titled "Analyzer Lab"), creates a :class:`~analyzer_lab.session.session.Session`
and a :class:`~analyzer_lab.view.page.SessionView` for every tab that connects (restoring the
state the tab saved before a reload) and frees them when the tab closes.

ONE loop thread steps every session at a fixed rate (``fps``) and pushes the
frames; a second, slow thread computes deferred scene updates outside the session
locks, so a slider drag never stalls the animation, and starts each page's derivation
in a child process with time and size limits (:mod:`analyzer_lab.serve.derivation_jobs`), so a slow
derivation never delays another page's.

The server is where the lab is composed: it builds the
:class:`~analyzer_lab.classroom.room.Classroom` and hands it itself as the
:class:`~analyzer_lab.classroom.ports.Lab` the classroom needs (the views of the open
pages, the frame loop's clock, the derivation cache).
"""

from __future__ import annotations

import contextlib
import html
import logging
import math
import os
import sys
import threading
import time
from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

from analyzer_lab.classroom.bus import Bus, BusError, make_bus
from analyzer_lab.classroom.course import Course
from analyzer_lab.classroom.instructor_code import CodeError, class_code
from analyzer_lab.classroom.log_limit import LogLimiter, left_out_text
from analyzer_lab.classroom.room import Classroom
from analyzer_lab.classroom.store.sql_store import redact
from analyzer_lab.i18n import ENGLISH, Language
from analyzer_lab.i18n import load_all as load_catalogs
from analyzer_lab.i18n import resolve as resolve_language
from analyzer_lab.lessons.kit.contract import Lesson, Params
from analyzer_lab.limits import prefer_returned_memory
from analyzer_lab.serve.back_pressure import PAUSED_NOTICE, BackPressure, Turn
from analyzer_lab.serve.course_record import CourseRecordError, open_course, resolve
from analyzer_lab.serve.derivation_jobs import DerivationJobs, build
from analyzer_lab.serve.fair_share import fair_order
from analyzer_lab.serve.heap import HeapTrim
from analyzer_lab.serve.page_opens import WAIT_NOTICE, PageOpens
from analyzer_lab.session.runlog import LRUCache, lesson_scene, params_key
from analyzer_lab.session.session import (
    SOLO_STEP_BUDGET,
    SOLO_WALL_BUDGET,
    STEP_BUDGET,
    STEP_WALL_BUDGET,
    LabError,
    Session,
)
from analyzer_lab.view.math import derivation_to_html
from analyzer_lab.view.page import SessionView, ViewConfig
from analyzer_lab.view.persistence import restore_state
from analyzer_lab.viser_boundary import (
    PAGE_TITLE,
    WakeBatch,
    client_address,
    dropped_types,
    event_loop,
    guard_gui_updates,
    make_viser_server,
    send_progress,
)

log = logging.getLogger(__name__)

#: Frames per second of the live view: a little above 30 so that every page still gets
#: 30 updates a second when a tick comes late (measured: 50 pages get 34/s at 36 fps,
#: 28.7/s at 30 fps).
DEFAULT_FPS = 36.0
#: Seconds the warm-up waits at a time while a page is being built.
WARM_UP_YIELD = 0.05
#: Seconds after a page was built during which the warm-up leaves the machine to it:
#: the browser draws the panel it was just sent on the same two cores as the server.
#: (viser connects a page once its canvas is drawn: the build comes after that.)
WARM_UP_QUIET = 3.0
#: Seconds the start line waits at most for the lesson new pages open with to be built.
FIRST_LESSON_WAIT = 60.0
DERIVATION_CACHE = LRUCache(64)


@dataclass
class LoopStats:
    """Frame-loop figures (for the load test and the log)."""

    ticks: int = 0
    busy: float = 0.0  # seconds spent stepping/drawing
    load: float = 0.0  # moving average of busy / period
    skipped: int = 0  # session frames skipped because a callback held the session
    started: float = field(default_factory=time.monotonic)


class LabServer:
    """The lab: viser server, sessions by client id, the frame loop."""

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        lesson: str | None = None,
        fps: float = DEFAULT_FPS,
        lessons: Sequence[Lesson] | None = None,
        verbose: bool = False,
        restore: bool = True,
        config: ViewConfig | None = None,
        warm_up: bool = True,
        instructor_code: str | None = None,
        bus: Bus | None = None,
        course: Course | None = None,
        server: Any | None = None,
        language: str | None = None,
    ) -> None:
        """``server``: a viser server already listening (``serve`` starts one before it
        imports the lessons, so that a browser gets the page at once); default: one made
        here on ``host`` and ``port``."""
        prefer_returned_memory()
        #: the language of new pages (``serve --lang``); an unknown code is English, logged
        self.language, notice = resolve_language(language)
        if notice:
            log.warning("%s", notice)
        self.fps = float(fps)
        self.restore = restore
        self.config = config or ViewConfig(fps=self.fps)
        self.host = host
        self.requested_port = port
        # HTTP first (a browser gets the page while the lessons are imported)
        self.server = server if server is not None else make_viser_server(host, port, verbose)
        self.port: int = int(self.server.get_port())
        if lessons is None:
            from analyzer_lab.lessons.catalog import all_lessons

            lessons = all_lessons()
        self.lessons = tuple(lessons)
        ids = {l.id for l in self.lessons}
        if lesson is not None and lesson not in ids:
            self.server.stop()
            raise LabError(f"unknown lesson {lesson[:60]!r}; known: {', '.join(sorted(ids))}")
        self.default_lesson = lesson
        self.views: dict[int, SessionView] = {}
        #: the network address each page connected from (the loop's turns are shared by address)
        self._addresses: dict[int, str] = {}
        #: pages whose connection does not take its updates get no new frames
        self.back_pressure = BackPressure()
        self._views_lock = threading.Lock()
        self.stats = LoopStats()
        self._stop = threading.Event()
        self.duty = 0.85  # share of each frame period the loop may spend on sessions
        self._rr = 0
        # shorter interpreter switch interval: the frame loop and viser's event loop
        # (which sends the frames) alternate often enough for smooth delivery
        if sys.getswitchinterval() > 0.002:
            sys.setswitchinterval(0.002)
        every = os.environ.get("ANALYZER_LAB_STATS", "")
        self._report_every = (
            int(float(every) * self.fps) if every.replace(".", "", 1).isdigit() else 0
        )
        self._report_t, self._report_busy, self._report_steps, self._report_ticks = (
            time.monotonic(),
            0.0,
            0.0,
            0,
        )
        self._report_draws = 0.0
        #: the classroom, handed this server as its Lab
        self.classroom = Classroom(self, instructor_code, bus, course)
        # pages are built and freed on a pool of their own (building one waits up to 2 s
        # for the browser's saved state), not in the turns of the page callbacks
        self._gone: set[int] = set()  # pages that left while being built
        self._building = 0  # pages being built now
        self.heap = HeapTrim()  # the memory of closed pages goes back to the system
        self._page_built_at = -math.inf  # when the latest page was built (monotonic)
        #: the lessons the warm-up built, in its order
        self.warmed: list[str] = []
        #: page builds admitted by network address (a rate with a burst, then a queue)
        self.page_opens = PageOpens()
        self._page_pool = ThreadPoolExecutor(max_workers=16, thread_name_prefix="analyzer-lab-page")

        async def connect(client: Any) -> None:
            address = client_address(self.server, client.client_id)
            if self.page_opens.admit(address, client.client_id, client):
                self._page_pool.submit(self._guarded, self._on_connect, client)
            else:
                self._page_pool.submit(self._guarded, self._tell_to_wait, client)

        async def disconnect(client: Any) -> None:
            if not self._stop.is_set():  # pages closed by the server's stop need no freeing
                self._page_pool.submit(self._guarded, self._on_disconnect, client)

        self.server.on_client_connect(connect)
        self.server.on_client_disconnect(disconnect)
        self._loop_done = threading.Event()
        loop = event_loop(self.server)
        if loop is None:
            self.server.stop()
            raise LabError("the web server's event loop is not available: cannot run frames")
        import asyncio

        asyncio.run_coroutine_threadsafe(self._async_loop(), loop)
        self.derivations = DerivationJobs()
        self._deriving: dict[
            int, tuple[SessionView, int, Any]
        ] = {}  # id(view) -> (view, revision, key)
        self._slow_log = LogLimiter(log)  # a fault repeated every pass: a few lines, then counts
        self._slow_thread = threading.Thread(
            target=self._slow_loop, name="analyzer-lab-slow", daemon=True
        )
        self._slow_thread.start()
        #: Set once the lesson new pages open with is built (or no warm-up runs): the
        #: start line says "ready" then, and a page opened from it is drawn at once.
        self.first_lesson_warm = threading.Event()
        if warm_up:
            threading.Thread(target=self.warm_up, name="analyzer-lab-warmup", daemon=True).start()
        else:
            self.first_lesson_warm.set()

    @property
    def url(self) -> str:
        host = (
            "127.0.0.1"
            if self.host in ("0.0.0.0", "")
            else ("[::1]" if self.host == "::" else self.host)
        )
        return f"http://{host}:{self.port}/"

    @property
    def ticks(self) -> int:
        """Frame-loop ticks so far."""
        return self.stats.ticks

    @property
    def report_interval(self) -> float:
        """Seconds between loop figures on stderr (``ANALYZER_LAB_STATS``; 0: none)."""
        return self._report_every / self.fps if self._report_every else 0.0

    # -- sessions ---------------------------------------------------------------------

    @staticmethod
    def _guarded(fn: Any, client: Any) -> None:
        try:
            fn(client)
        except Exception:  # a page's connection: the server goes on
            log.exception("page %s: %s failed", client.client_id, fn.__name__)

    @staticmethod
    def _tell_to_wait(client: Any) -> None:
        client.add_notification("Please wait", WAIT_NOTICE, auto_close_seconds=5.0)

    @contextlib.contextmanager
    def building_page(self) -> Iterator[None]:
        """A page is being built meanwhile: the warm-up waits (the page comes first)."""
        with self._views_lock:
            self._building += 1
        try:
            yield
        finally:
            with self._views_lock:
                self._building -= 1
                self._page_built_at = time.monotonic()

    def _on_connect(self, client: Any) -> None:
        with self.building_page():
            self._build_page(client)

    def _build_page(self, client: Any) -> None:
        cid = client.client_id
        with self._views_lock:
            if cid in self._gone:  # it left before its build began: nothing to build
                self._gone.discard(cid)
                return
        guard_gui_updates(client.gui, self.server)  # wrong-typed values: one message
        session = Session(self.lessons, self.default_lesson)
        language, chosen = self.language, False
        if self.restore:  # its state, and the language this browser chose on an earlier page
            saved = restore_state(client, session)
            if saved:
                found, notice = resolve_language(saved)
                if notice is None:
                    language, chosen = found, True
        view = SessionView(client, session, self.config, language=language, language_chosen=chosen)
        view.last_tick = time.monotonic()  # type: ignore[attr-defined]
        with self._views_lock:
            gone = cid in self._gone  # the page left while it was being built
            self._gone.discard(cid)
            if not gone:
                self.views[cid] = view
                self._addresses[cid] = client_address(self.server, cid)
        if gone:
            view.close()
            return
        self.classroom.attach(view)  # classroom hook
        with self._views_lock:
            left = cid not in self.views
        if left:  # left while the classroom attached it
            self.classroom.detach(cid, view)

    def _on_disconnect(self, client: Any) -> None:
        if self.page_opens.drop(client.client_id):
            return  # it left while waiting its turn: it was never built
        with self._views_lock:
            view = self.views.pop(client.client_id, None)
            self._addresses.pop(client.client_id, None)
            self.back_pressure.forget(client.client_id)
            if view is None:
                self._gone.add(client.client_id)
        self.classroom.detach(client.client_id, view)  # classroom hook
        if view is not None:
            view.close()
        self.heap.page_closed()

    def sessions(self) -> list[Session]:
        with self._views_lock:
            return [v.session for v in self.views.values()]

    def open_views(self) -> list[SessionView]:
        """The views of the pages open now (a copy: pages come and go meanwhile)."""
        with self._views_lock:
            return list(self.views.values())

    def view_of(self, client_id: int) -> SessionView | None:
        with self._views_lock:
            return self.views.get(client_id)

    # -- loops ------------------------------------------------------------------------

    async def _async_loop(self) -> None:
        """The frame loop inside viser's event loop: stepping, drawing and sending run on
        one thread, one after the other, instead of two threads handing the interpreter
        lock back and forth for every websocket write."""
        import asyncio

        period = 1.0 / self.fps
        next_t = time.monotonic()
        while not self._stop.is_set():
            try:
                self._tick_all(period)
            except Exception:  # the frame loop goes on
                log.exception("a frame tick failed")
            # a late tick is followed by the next after a short gap, not at once: a frame
            # pushed right behind another would replace it in the send buffer unsent
            now = time.monotonic()
            next_t += period
            if next_t < now - period:
                next_t = now  # far behind: do not try to catch up with a burst
            await asyncio.sleep(max(next_t - now, 0.25 * period))
        self._loop_done.set()

    def _tick_all(self, period: float) -> None:
        """One frame for every session (round-robin, within the time budget)."""
        start = time.monotonic()
        with self._views_lock:
            pages = [(self._addresses.get(cid, ""), v) for cid, v in self.views.items()]
        ordered = fair_order(pages, self._rr)
        address_of = {id(v): a for a, v in pages}
        # pages that play first: a tick cut short by its budget leaves out paused pages
        # (whose turn only redraws what changed), not the frames of a playing one
        views = [v for v in ordered if v.session.playing]
        # one run playing (a page alone, or a demo its followers share) steps in the
        # loop's time nobody else needs; several share it on the common budget
        solo = len({id(v.session) for v in views}) == 1
        cpu_budget, wall_budget = (
            (SOLO_STEP_BUDGET, SOLO_WALL_BUDGET) if solo else (STEP_BUDGET, STEP_WALL_BUDGET)
        )
        views += [v for v in ordered if not v.session.playing]
        substeps = 8 if self.stats.load < 0.5 else 4 if self.stats.load < 0.8 else 1
        batch = WakeBatch(self.server)
        # round-robin with a time budget: under overload every session still gets
        # its turn and viser's sending keeps its share of the interpreter
        budget = start + self.duty * period
        # each address's pages get at most an equal share of the tick's time: pages that
        # are dear to step (a family of curves at 8x) from one address do not make the
        # ticks of every other address's pages late
        share = self.duty * period / max(1, len(set(address_of.values())))
        spent: dict[str, float] = {}
        n = len(views)
        done = 0
        for k, view in enumerate(views):
            if k and time.monotonic() > budget:
                break
            done += 1
            address = address_of.get(id(view), "")
            if spent.get(address, 0.0) >= share:
                continue  # this address's share of the tick is used: its next pages wait
            session = view.session
            now = time.monotonic()
            lag, taken = send_progress(self.server, view.client.client_id)
            turn = self.back_pressure.turn(view.client.client_id, lag, now, session.playing, taken)
            if turn is not Turn.DRAW:
                view.last_tick = now  # type: ignore[attr-defined]  # its clock waits too
                if turn is Turn.PAUSE and session.lock.acquire(blocking=False):
                    try:
                        session.playing = False
                        session.notify(PAUSED_NOTICE, "warning")
                    finally:
                        session.lock.release()
                continue
            if not session.lock.acquire(blocking=False):
                self.stats.skipped += 1
                continue
            if view.session is not session:  # classroom hook: switched (follow/release) meanwhile
                session.lock.release()
                continue
            try:
                now = time.monotonic()
                dt = now - getattr(view, "last_tick", now)
                view.last_tick = now  # type: ignore[attr-defined]
                session.max_substeps = substeps
                session.step_budget, session.wall_budget = cpu_budget, wall_budget
                grouped = batch.hold(view.client)
                view.tick(dt, atomic=not grouped)
            except Exception as exc:  # the frame loop goes on; the page pauses and says why
                log.exception("page %s: a frame failed", view.client.client_id)
                session.playing = False
                session.notify(
                    f"internal error, playback paused: {type(exc).__name__}: {exc}", "error"
                )
            finally:
                session.lock.release()
                spent[address] = spent.get(address, 0.0) + time.monotonic() - now
        self._rr = self._rr + done if n else 0
        batch.release()
        view = session = None  # type: ignore[assignment]  # classroom hook: no stale reference once every tab left
        busy = time.monotonic() - start
        if self._report_every and self.stats.ticks % self._report_every == 0 and self.stats.ticks:
            self._report(views)
        self.stats.ticks += 1
        self.stats.busy += busy
        self.stats.load = 0.9 * self.stats.load + 0.1 * (busy / period)

    def _report(self, views: list[SessionView]) -> None:
        """One line of loop figures on stderr (ANALYZER_LAB_STATS=seconds)."""
        now = time.monotonic()
        span = now - self._report_t
        steps = sum(v.step_seconds for v in views)
        draws = sum(v.draw_seconds for v in views)
        busy = self.stats.busy - self._report_busy
        print(
            f"[loop] sessions {len(views)} ticks/s {(self.stats.ticks - self._report_ticks) / span:.1f} "
            f"busy {busy / span:.0%} stepping {(steps - self._report_steps) / span:.0%} "
            f"drawing {(draws - self._report_draws) / span:.0%} load {self.stats.load:.2f} "
            f"skipped {self.stats.skipped} dropped {dropped_types() or '-'} "
            f"warm {len(self.warmed)}/{len(self.lessons)} trims {self.heap.trims}",
            file=sys.stderr,
            flush=True,
        )
        self._report_t, self._report_busy, self._report_steps, self._report_ticks = (
            now,
            self.stats.busy,
            steps,
            self.stats.ticks,
        )
        self._report_draws = draws

    def _slow_loop(self) -> None:
        """Derivations and deferred scenes, computed outside the session locks."""
        while not self._stop.wait(0.15):
            self._open_due_pages()
            views = self.open_views()
            now = time.monotonic()
            for owner in [k for k, v in self._deriving.items() if v[0].closed]:
                self._deriving.pop(owner, None)
                self.derivations.cancel(owner)
            for view in views:
                try:
                    self._slow_work(view, now)
                    self._derivation_work(view, now)
                except Exception as exc:  # the slow loop goes on; a repeated fault: a few lines
                    skipped = self._slow_log.admit(f"deferred work: {type(exc).__name__}")
                    if skipped is not None:
                        log.exception(
                            "page %s: deferred work failed%s",
                            view.client.client_id,
                            left_out_text(skipped),
                        )
            views = view = None  # type: ignore[assignment]  # classroom hook: no stale reference
            with self._views_lock:
                building = self._building > 0
            self.heap.poll(building or self.page_opens.waiting() > 0)
        self.derivations.stop()
        self._deriving.clear()

    def _open_due_pages(self) -> None:
        """Build the pages whose turn to open has come (in a call of its own: the slow
        loop keeps no reference to the last of them, which would keep its session alive
        after it left)."""
        for client in self.page_opens.due():
            self._page_pool.submit(self._guarded, self._on_connect, client)

    def _slow_work(self, view: SessionView, now: float) -> None:

        session = view.session
        if session.scene_due is not None and now >= session.scene_due:
            with session.lock:
                lesson, params, rev = session.lesson, session.params, session.revision
            try:
                spec = lesson_scene(lesson, params)
            except Exception as exc:  # the lesson's own code: the page says why, the log how
                log.warning("page %s: the scene failed", view.client.client_id, exc_info=True)
                spec = None
                with session.lock:
                    session.notify(f"the scene could not be drawn: {exc}", "warning")
            with session.lock:
                if session.revision == rev:
                    session.scene_due = None
                    if spec is not None:
                        session.accept_scene(spec)

    def _derivation_work(self, view: SessionView, now: float) -> None:
        """Show a finished derivation, or start the page's next one (cached, in a child
        process, or here for a lesson outside the catalog)."""
        session = view.session
        owner = id(view)
        running = self._deriving.get(owner)
        if running is not None:
            content = self.derivations.poll(owner)
            if content is None:
                return
            del self._deriving[owner]
            _, rev, key = running
            DERIVATION_CACHE.put(key, content)
            with session.lock:  # a page switched to another language builds it again
                if session.revision == rev and not view.closed and key[1] == view.language.code:
                    view.derivation_due = None
                    view.set_derivation(content)
            return
        if view.derivation_due is None or now < view.derivation_due or view.closed:
            return
        with session.lock:
            lesson, params, rev = session.lesson, session.params, session.revision
            values = session.raw_values()
        code = view.language.code
        key = (params_key(lesson, params), code)
        content = DERIVATION_CACHE.get(key)
        if content is None and DerivationJobs.can_run(lesson):
            if not self.derivations.full():
                self.derivations.start(owner, lesson.id, values, code)
                self._deriving[owner] = (view, rev, key)
            return
        if content is None:
            try:
                content = DERIVATION_CACHE.get_or_make(key, lambda: build(lesson, values, code))
            except Exception as exc:  # the lesson's own code: the page says why, the log how
                log.warning("page %s: the derivation failed", view.client.client_id, exc_info=True)
                content = f'<div class="al-error">The derivation could not be built: {html.escape(str(exc))}</div>'
        with session.lock:
            if session.revision == rev and not view.closed:
                view.derivation_due = None
                view.set_derivation(content)

    def derivation_html(self, lesson: Lesson, params: Params, language: Language = ENGLISH) -> str:
        """The derivation of ``lesson`` at ``params`` as HTML in ``language``, from the
        cache the pages share (keyed by the values and the language; built in the calling
        thread when it is not there)."""
        return DERIVATION_CACHE.get_or_make(
            (params_key(lesson, params), language.code),
            lambda: derivation_to_html(
                lesson.derivation(params), text=language.lesson_text, tr=language.gettext
            ),
        )

    def warm_up(self) -> None:
        """Build each lesson once (lambdify caches, meshes) so the first tab is quick:
        the lesson new pages open first, and never while a page is being built or in
        the :data:`WARM_UP_QUIET` seconds after (the page a student just opened comes
        before the lessons nobody opened yet)."""
        try:
            self._warm_up()
        finally:
            self.first_lesson_warm.set()

    def _warm_up(self) -> None:
        first = self.default_lesson or (self.lessons[0].id if self.lessons else None)
        for k, lesson in enumerate(sorted(self.lessons, key=lambda l: l.id != first)):
            if k == 1:
                self.first_lesson_warm.set()
            while self._page_comes_first() and not self._stop.is_set():
                time.sleep(WARM_UP_YIELD)
            if self._stop.is_set():
                return
            if k == 1:  # after the lesson pages open with, and once they are drawn
                try:
                    self.derivations.warm()
                except Exception:  # the derivations' child processes; a page starts them again
                    log.exception("warming up the derivation processes failed")
            try:
                setup = lesson.open(scene_of=lesson_scene)
                setup.stepper.advance(0.01)
                setup.scene  # built once here and kept in the scene cache for the first page
                key = (params_key(lesson, setup.params), self.language.code)
                if k > 0 and self.derivations.can_run(lesson):
                    if DERIVATION_CACHE.get(key) is None:
                        self._warm_derivation(lesson, key)
                else:  # the lesson pages open with: here, before the start line
                    DERIVATION_CACHE.get_or_make(key, lambda: build(lesson, {}, key[1]))
            except Exception:  # the lesson's own code: its first page says what is wrong
                log.warning("warming up the lesson %s failed", lesson.id, exc_info=True)
            self.warmed.append(lesson.id)

    def _warm_derivation(self, lesson: Lesson, key: tuple[Any, str]) -> None:
        """Build ``lesson``'s derivation (default values) in a derivation process, at the
        lower CPU priority the pages' derivations get, and keep it in the cache: the
        interpreter stays free for the pages opening meanwhile."""
        owner = ("warm-up", lesson.id)
        while self.derivations.full() and not self._stop.is_set():
            time.sleep(WARM_UP_YIELD)
        if self._stop.is_set():
            return
        self.derivations.start(owner, lesson.id, {}, key[1])
        while (content := self.derivations.poll(owner)) is None and not self._stop.is_set():
            time.sleep(WARM_UP_YIELD)
        if self._stop.is_set():
            self.derivations.cancel(owner)
        elif content is not None and not content.startswith('<div class="al-error">'):
            DERIVATION_CACHE.put(key, content)

    def _page_comes_first(self) -> bool:
        """Whether a page is being built or was built less than :data:`WARM_UP_QUIET`
        s ago (then the warm-up waits)."""
        with self._views_lock:
            quiet = time.monotonic() - self._page_built_at < WARM_UP_QUIET
            return self._building > 0 or quiet

    def stop(self) -> None:
        self._stop.set()
        self.classroom.stop()
        with self._views_lock:
            views = list(self.views.values())
            self.views.clear()
        for v in views:
            v.close()
        self._loop_done.wait(timeout=2.0)
        self._page_pool.shutdown(wait=False, cancel_futures=True)
        try:
            self.server.stop()
        except Exception:  # the web server's own threads: stopping goes on
            log.warning("the web server did not stop cleanly", exc_info=True)


def _start_up(t0: float, started: tuple[float, float] | None) -> str:
    """How long the start took: from the command's start when it is known (the page
    served, the lessons ready), else from ``t0``."""
    if started is None:
        return f"ready in {time.perf_counter() - t0:.1f} s"
    begin, served = started
    return f"page served after {served:.1f} s, ready in {time.perf_counter() - begin:.1f} s"


def _refused(message: str, server: Any | None) -> int:
    """Say why the lab cannot start; the viser server started for it stops."""
    print(message, file=sys.stderr)
    if server is not None:
        server.stop()
    return 2


def serve(
    host: str = "127.0.0.1",
    port: int = 8080,
    lesson: str | None = None,
    instructor_code: str | None = None,
    open_browser: bool = True,
    fps: float = DEFAULT_FPS,
    bus_url: str | None = None,
    worker_name: str | None = None,
    instructor_code_file: str | None = None,
    data: str | None = None,
    db: str | None = None,
    class_name: str | None = None,
    roster: str | None = None,
    join_code: str | None = None,
    join_code_hours: float | None = None,
    server: Any | None = None,
    started: tuple[float, float] | None = None,
    lang: str | None = None,
) -> int:
    """Run the lab until interrupted; returns the exit code.  ``server``: a viser server
    already listening on ``host`` and ``port`` (stopped here when the lab cannot start);
    ``started``: when the command started (``time.perf_counter()``) and how many seconds
    later that server listened, for the start-up report.
    The course record: the
    class ``class_name`` in ``db`` (default: the SQLite file in the data folder ``data``),
    ``roster`` a CSV file of its students, ``join_code`` and its lifetime ``join_code_hours``
    (:mod:`analyzer_lab.serve.course_record`).  ``bus_url``: the class bus
    shared with other servers (``redis://HOST:PORT``; default in-process); the code comes
    from ``instructor_code``, ``instructor_code_file`` or the environment
    (:func:`~analyzer_lab.classroom.instructor_code.class_code`).  ``lang``: the language
    of new pages (``en`` by default; an unknown code: English, with a notice)."""
    if not (0 <= int(port) <= 65535):
        return _refused(f"analyzer-lab: error: port must be in 0..65535, got {port}", server)
    if not (math.isfinite(fps) and 1.0 <= fps <= 120.0):  # classroom hook (serve --fps)
        return _refused(f"analyzer-lab: error: --fps must be in 1..120, got {fps}", server)
    t0 = time.perf_counter()
    language, notice = resolve_language(lang)
    if notice:
        print(f"analyzer-lab: note: {notice}", file=sys.stderr, flush=True)
    for failed in load_catalogs():  # reported at start; those pages show English
        print(f"analyzer-lab: warning: {failed}; English is shown", file=sys.stderr, flush=True)
    try:
        code = class_code(instructor_code, instructor_code_file)
    except CodeError as exc:
        return _refused(f"analyzer-lab: error: {exc}", server)
    try:
        bus = make_bus(bus_url, code, worker_name)
    except BusError as exc:
        return _refused(f"analyzer-lab: error: {exc}", server)
    try:
        record = resolve(data, db, class_name)
        course = open_course(record, roster, join_code, code_hours=join_code_hours)
    except CourseRecordError as exc:
        return _refused(f"analyzer-lab: error: {exc}", server)
    try:
        lab = LabServer(
            host=host,
            port=port,
            lesson=lesson,
            fps=fps,
            instructor_code=code,
            bus=bus,
            course=course,
            server=server,
            language=language.code,
        )
    except LabError as exc:
        return _refused(f"analyzer-lab: error: {exc}", server)
    except OSError as exc:
        return _refused(f"analyzer-lab: error: cannot listen on {host}:{port}: {exc}", server)
    if lab.port != port and port != 0:
        print(f"analyzer-lab: port {port} is in use; using {lab.port}", flush=True)
    lab.first_lesson_warm.wait(FIRST_LESSON_WAIT)
    where = "every interface" if host in ("0.0.0.0", "::", "") else host
    print(
        f"Analyzer Lab: {lab.url}  (listening on {where}, port {lab.port}; "
        f"{_start_up(t0, started)}; Ctrl-C stops)",
        flush=True,
    )
    print(
        f"Instructor code: {lab.classroom.code}  (type it in a page's Instructor folder)",
        flush=True,
    )  # classroom hook
    print(
        f"Course record: {redact(record.db)}, class {record.class_name!r}, "
        f"join code {course.info.join_code}{course.code_expiry()}",
        flush=True,
    )
    _report_bus(bus)
    if host in ("0.0.0.0", "::", ""):
        print(
            "analyzer-lab: note: bound to every interface: anyone on your network can open the lab",
            flush=True,
        )
    if open_browser:
        import webbrowser

        threading.Thread(target=lambda: webbrowser.open(lab.url), daemon=True).start()
    parent = os.environ.get("ANALYZER_LAB_FRONT_DOOR_PID", "")
    try:
        while True:
            time.sleep(1.0)
            if parent and str(os.getppid()) != parent:  # a worker outlives no front door
                print("analyzer-lab: the front door stopped; stopping", flush=True)
                break
    except KeyboardInterrupt:
        print("analyzer-lab: stopping", flush=True)
    finally:
        lab.stop()
    return 0


def _report_bus(bus: Bus) -> None:
    """Say at start whether the class bus is there (a Redis bus connects meanwhile)."""
    wait = getattr(bus, "wait_connected", None)
    if wait is None:
        return
    wait(3.0)
    if bus.up:
        print(f"Class bus: {bus.url} (connected; this server is {bus.name})", flush=True)
    else:
        print(
            f"analyzer-lab: warning: the class bus {bus.url} is unreachable ({bus.reason}): "
            "serving this server's own pages; reconnecting in the background",
            flush=True,
        )


__all__ = ["LabServer", "PAGE_TITLE", "serve"]
