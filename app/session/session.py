"""One student's state, independent of the view: lesson, parameters, stepper, playback.

A :class:`Session` holds the validated parameters of one lesson, a live
:class:`~analyzer_lab.lessons.kit.contract.Stepper` and the playback state (playing, speed,
time), and records the run it has shown (:meth:`Session.run_result`).  A new lesson,
preset, state or value is one :meth:`Lesson.open` (values validated, preset looked up
once), taken in one sequence (:meth:`Session._take`, the run starting again with
:meth:`Session.reset`); a refused value raises :class:`ParamError` and leaves the
session as it was.  Its playback keeps pace through a :class:`~analyzer_lab.session.pace.Pace`.

The whole state that matters to a student is :class:`SessionState` (plain JSON
data): it is saved in the browser, restored on reload, and can be copied from
one session to another (:meth:`Session.state` / :meth:`Session.apply_state`).
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.budget import clock, left, work_budget
from analyzer_lab.lessons.kit.contract import (
    Frame,
    Lesson,
    LessonSetup,
    ParamError,
    Params,
    RunResult,
    SceneSpec,
    Stepper,
)
from analyzer_lab.lessons.kit.formula import plain_number as plain
from analyzer_lab.lessons.kit.message import N_, Message
from analyzer_lab.session.pace import (
    SOLO_STEP_BUDGET,
    SOLO_WALL_BUDGET,
    STEP_BUDGET,
    STEP_WALL_BUDGET,
    TIME_QUANTUM,
    Pace,
)
from analyzer_lab.session.runlog import RunLog, lesson_scene, raw_value, scenes_equal
from analyzer_lab.session.state import LabError, SessionState

log = logging.getLogger(__name__)

#: Playback speeds offered (lesson seconds per wall-clock second).
SPEEDS: tuple[float, ...] = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0)
#: Lesson time of one "single step" press, at speed 1 (scaled by the speed).
STEP_DT = 1.0 / 30.0
#: Longest lesson-time piece a frame advances in one stepper call (the trail gets a
#: point per piece); a frame makes at most MAX_SUBSTEPS pieces.
SUBSTEP_DT = 1.0 / 30.0
MAX_SUBSTEPS = 8
#: Seconds after a "live" change before the scene is redrawn (debounced).
SCENE_DEBOUNCE = 0.3
#: "Go to t" reaches at most this many times the lesson's t_end.
MAX_GO_TO = 10
#: CPU seconds one "go to t" or single step may compute before it stops where it got.
GO_TO_BUDGET = 0.5


@dataclass(frozen=True)
class Change:
    """What a new setup (a lesson with a preset and values) does to a session: ``restart``
    the run (a new stepper from its start; else the running stepper takes the values),
    draw the ``scene`` at once (else a little later, off the hot path), ``pause`` the
    playback, ``reframe`` the camera, show the lesson's ``notes`` on the values."""

    restart: bool
    scene: bool = True
    pause: bool = False
    reframe: bool = False
    notes: bool = True


#: Another lesson; a preset; a saved or copied state; values of a ``restart``, a
#: ``scene`` or a ``live`` group (the group's declared change).
LESSON = Change(restart=True, pause=True, reframe=True)
PRESET = Change(restart=True, reframe=True)
STATE = Change(restart=True, pause=True, notes=False)
RESTART = Change(restart=True)
SCENE = Change(restart=False)
LIVE = Change(restart=False, scene=False)


def lesson_label(lesson: Lesson) -> str:
    """Picker label: chapter, problem, title."""
    bits = []
    if lesson.chapter:
        bits.append(f"Ch. {lesson.chapter}" if lesson.chapter.isdigit() else lesson.chapter)
    if lesson.problem:
        bits.append(lesson.problem)
    bits.append(lesson.title or lesson.id)
    return " · ".join(bits)


class Session:
    """One student's lesson, parameters, stepper and playback (no view code).

    Thread-safety: the owner serializes access with :attr:`lock` (GUI callbacks run
    on a thread pool, frames on the server's loop thread).
    """

    lesson: Lesson
    preset: str | None
    params: Params
    stepper: Stepper
    scene: SceneSpec
    t_end: float
    frame: Frame

    def __init__(
        self, lessons: Sequence[Lesson], lesson_id: str | None = None, preset: str | None = None
    ) -> None:
        if not lessons:
            raise LabError("no lessons are installed")
        self.lessons: dict[str, Lesson] = {l.id: l for l in lessons}
        self.lock = threading.RLock()
        self.notices: deque[tuple[str, str]] = deque(maxlen=20)
        self._run_notice: tuple[str, str] | None = None  # the newest notice if about the run
        self._withdrawn: tuple[str, str] | None = None  # a notice a reset took off the page
        self.playing = False
        self.speed = 1.0
        self.pause_at_end = True
        self.visible_vectors: set[str] | None = None
        self.log = RunLog()
        #: the budget of one tick: pieces, CPU seconds and (the live server sets it; None:
        #: CPU only) wall seconds of stepping; the server lowers the pieces under load
        self.max_substeps = MAX_SUBSTEPS
        self.step_budget = STEP_BUDGET
        self.wall_budget: float | None = None
        self.pace = Pace()
        #: (lesson, params, the series that may be undefined) of the last frame checked
        self._allowed_for: tuple[Lesson, Params, frozenset[str]] | None = None
        self._time_debt = 0.0  # lesson time owed to the next played tick (< TIME_QUANTUM / 2)
        #: a clock shared by the pages that show this session (the classroom's demo)
        self.shared_clock: Callable[[float], list[Frame]] | None = None
        self.scene_due: float | None = None  # when a deferred scene rebuild is due (monotonic time)
        #: bumped on any change of lesson/params (the view re-renders what it needs)
        self.revision = 0
        self.scene_revision = 0  # bumped when the static scene must be redrawn
        self.reset_revision = 0  # bumped when the run restarts (trail cleared)
        #: bumped when the camera should frame the scene again (lesson, preset, reset)
        self.camera_revision = 0
        self.on_change: Callable[[str], None] | None = None
        first = lesson_id if lesson_id in self.lessons else next(iter(self.lessons))
        if lesson_id is not None and lesson_id not in self.lessons:
            self.notify(
                Message(
                    N_("unknown lesson {lesson}; showing {first}"),
                    lesson=repr(lesson_id[:60]),
                    first=first,
                ),
                "warning",
            )
        self._take(self._open(self.lessons[first], None, preset), LESSON)

    # -- notices --------------------------------------------------------------------

    def notify(self, text: str, level: str = "info", about_run: bool = False) -> None:
        """A message for the user (the view shows the newest, :attr:`notice`): a
        :class:`Message` is kept as it is (the page shows it in its own language), other
        (or longer) text as one line of at most 500 characters.

        ``about_run``: it speaks of the run now on screen (its end was reached): a reset
        withdraws it, so a run started again is not told it ended."""
        entry = (
            level,
            text if isinstance(text, Message) and len(text) <= 500 else str(text)[:500],
        )
        self.notices.append(entry)
        self._run_notice = entry if about_run else None

    @property
    def notice(self) -> tuple[str, str] | None:
        """The notice the page shows: the newest, unless a reset withdrew it."""
        newest = self.notices[-1] if self.notices else None
        return None if newest is not None and newest is self._withdrawn else newest

    # -- lesson and parameters ------------------------------------------------------------

    @property
    def lesson_id(self) -> str:
        return self.lesson.id

    def _open(
        self, lesson: Lesson, values: Mapping[str, Any] | None, preset: str | None
    ) -> LessonSetup:
        """``lesson`` with ``values`` over ``preset``, its scenes shared with the other
        sessions showing the same values (:func:`lesson_scene`)."""
        return lesson.open(values, preset, scene_of=lesson_scene)

    def _take(self, setup: LessonSetup, change: Change, field: str = "params") -> None:
        """Show ``setup``: the one sequence every new lesson, preset, state or value goes
        through.  What ``change`` needs is built first (a failure is a refused value of
        ``field``, and nothing changes); then the session takes the setup, and the run
        starts again (:meth:`reset`) if ``change.restart``."""
        try:
            if change.restart:
                stepper = setup.stepper
                scene = setup.scene
            else:
                scene = setup.scene if change.scene else self.scene
                stepper = self.stepper
                stepper.set_params(setup.params)
        except ParamError:
            raise
        except (ValueError, ArithmeticError) as exc:
            raise ParamError(field, str(exc)) from None
        self.lesson, self.preset, self.params = setup.lesson, setup.preset, setup.params
        self.t_end = setup.t_end
        self.scene = scene
        self.revision += 1
        if change.scene:
            self.scene_revision += 1
            self.scene_due = None
        else:
            # controls rarely change the drawing: rebuild it later, off the hot path
            self.scene_due = time.monotonic() + SCENE_DEBOUNCE
        if change.restart:
            self.reset(
                stepper=stepper, playing=False if change.pause else None, reframe=change.reframe
            )
        else:
            self.frame = stepper.frame()
        if change.notes:
            # the lesson's own notes on these values (e.g. a projected start point)
            for note in setup.notes:
                if note.kind in ("info", "warning"):
                    self.notify(note.text, note.kind)

    def select_lesson(self, lesson_id: str, preset: str | None = None) -> None:
        """Switch lesson (defaults, or the given preset); refuses unknown ids."""
        if not isinstance(lesson_id, str) or lesson_id not in self.lessons:
            raise LabError(
                Message(
                    N_("unknown lesson {lesson}; known: {known}"),
                    lesson=repr(str(lesson_id)[:60]),
                    known=", ".join(self.lessons),
                )
            )
        self._take(self._open(self.lessons[lesson_id], None, preset), LESSON)

    def apply_preset(self, name: str | None) -> None:
        """Load one of the textbook's examples (``None``: the defaults); the run restarts."""
        self._take(self._open(self.lesson, None, name), PRESET)

    def edits(self) -> dict[str, tuple[Any, Any]]:
        """The values that differ from the preset (or the defaults): name -> (the
        preset's value, the current value), as raw data."""
        base = self.lesson.resolve(preset=self.preset)
        now = self.raw_values()
        return {k: (raw_value(v), now[k]) for k, v in base.items() if raw_value(v) != now.get(k)}

    def run_name(self) -> str:
        """What was run, for file names: the lesson, the preset, "custom" once edited."""
        name = self.lesson.id + (f"-{self.preset}" if self.preset else "")
        return name + ("-custom" if self.edits() else "")

    def raw_values(self) -> dict[str, Any]:
        return {k: raw_value(v) for k, v in self.params.items()}

    def set_values(self, changes: Mapping[str, Any]) -> None:
        """Change parameters live; raises :class:`ParamError` (nothing changes) if refused.

        What a change does follows its group's declared ``change``: ``live`` and
        ``scene`` values take effect while running (the stepper keeps its state),
        ``restart`` values (a start point, a mode) start the run again.
        """
        if not changes:
            return
        raw = self.raw_values()
        raw.update(changes)
        setup = self._open(self.lesson, raw, self.preset)  # unknown names are refused
        changed = [n for n in changes if setup.params[n] != self.params.get(n)]
        if not changed:
            return
        effects = {self.lesson.group(self.lesson.param(n).group).change for n in changed}
        change = RESTART if "restart" in effects else LIVE if effects == {"live"} else SCENE
        self._take(setup, change, changed[0])
        start = self.lesson.start_point
        if change.restart and start is not None and set(changed) & set(start):
            self._show_projected_start()

    def _show_projected_start(self) -> None:
        """A typed start point off the surface is projected by the lesson: show the
        point it really starts from in the fields (not the typed one)."""
        names = self._start_names()
        typed = np.array([float(self.params[n]) for n in names])
        try:
            snapped = np.array(self.snap_start() or typed)
        except LabError:
            return
        if not np.allclose(snapped, typed, rtol=1e-9, atol=1e-12):
            self.notify(
                Message(
                    N_("start point moved onto the surface: ({x:.6g}, {y:.6g}, {z:.6g})"),
                    x=float(snapped[0]),
                    y=float(snapped[1]),
                    z=float(snapped[2]),
                ),
                "warning",
            )

    def accept_scene(self, spec: SceneSpec) -> bool:
        """Take a (deferred) scene; redraw only if it differs from the one shown."""
        if scenes_equal(spec, self.scene):
            return False
        self.scene = spec
        self.scene_revision += 1
        return True

    def refresh_scene(self) -> bool:
        """Rebuild the deferred scene now (tests; the server does it off the lock)."""
        self.scene_due = None
        return self.accept_scene(lesson_scene(self.lesson, self.params))

    def set_value(self, name: str, raw: Any) -> None:
        self.set_values({name: raw})

    def _start_names(self) -> tuple[str, str, str]:
        names = self.lesson.start_point
        if names is None:
            raise LabError(Message(N_("this lesson has no start point")))
        return names

    def snap_start(self) -> tuple[float, float, float] | None:
        """Put the start point exactly where the lesson places it (on the surface): the
        first moving point of a fresh run."""
        names = self._start_names()
        fresh = self._open(self.lesson, self.params, self.preset).stepper.reset()
        if not fresh.points:
            raise LabError(Message(N_("this lesson has no moving point")))
        pts = np.asarray(next(iter(fresh.points.values())), dtype=float).reshape(-1, 3)
        p = pts[0]
        family = self.lesson.family
        if family is not None and int(self.params[family]) > 1:
            # the family is spread around the base point: snap the base point itself
            p = pts[len(pts) // 2] if len(pts) % 2 else pts.mean(axis=0)
        values = {n: round(float(v), 12) for n, v in zip(names, p)}
        self.set_values(values)
        return values[names[0]], values[names[1]], values[names[2]]

    def set_start(self, point: Sequence[float]) -> None:
        """Start point from the scene (a click on the surface)."""
        names = self._start_names()
        p = [float(v) for v in point]
        if len(p) != 3 or not all(math.isfinite(v) for v in p):
            raise LabError(Message(N_("the clicked point is not finite")))
        self.set_values(dict(zip(names, p)))

    # -- playback -------------------------------------------------------------------

    def play(self) -> None:
        if self.pause_at_end and self.frame.t >= self.t_end - 1e-9:
            self.reset()
        self.playing = True
        self.pace.restart()

    def pause(self) -> None:
        self.playing = False

    def set_speed(self, speed: Any) -> None:
        # the speeds as numbers (a page writes them with its decimal sign)
        speeds = Message(
            ", ".join(f"{{s{i}:g}}x" for i in range(len(SPEEDS))),
            **{f"s{i}": s for i, s in enumerate(SPEEDS)},
        )
        try:
            value = float(speed)
        except (TypeError, ValueError):
            raise LabError(Message(N_("speed must be one of {speeds}"), speeds=speeds)) from None
        if not any(abs(value - s) < 1e-9 for s in SPEEDS):
            raise LabError(
                Message(
                    N_("speed must be one of {speeds}; got {speed}"), speeds=speeds, speed=value
                )
            )
        self.speed = value

    def reset(
        self,
        *,
        stepper: Stepper | None = None,
        at: Frame | None = None,
        playing: bool | None = None,
        reframe: bool = False,
    ) -> Frame:
        """The run starts again: the one reset of every path (the Reset button, a new
        lesson, preset, state or start value, a run copied from another session).

        ``stepper``: the run's new stepper (default: the current one), from its initial
        state, or from ``at``, the frame where a copied stepper stands.  The run log keeps
        only that frame and the pages clear their trails and plots (:attr:`reset_revision`);
        ``playing``: the playback from now (``None``: as it was); ``reframe``: the pages
        frame the scene again (:attr:`camera_revision`).
        """
        if stepper is not None:
            self.stepper = stepper
        self.frame = self.stepper.reset() if at is None else at
        self.log.clear()
        self.log.add(self.frame)
        self.reset_revision += 1
        if self._run_notice is not None and self.notices and self.notices[-1] is self._run_notice:
            self._withdrawn = self._run_notice
        if reframe:
            self.camera_revision += 1
        if playing is not None:
            self.playing = playing
        return self.frame

    def _advance(self, dt: float) -> list[Frame]:
        frames: list[Frame] = []
        if dt <= 0 or not math.isfinite(dt):
            return frames
        t_before = self.stepper.t
        substep = SUBSTEP_DT * self.lesson.time_scale
        n = max(1, min(self.max_substeps, int(math.ceil(dt / substep - 1e-9))))
        piece = dt / n
        quantum = TIME_QUANTUM * self.lesson.time_scale  # the grain of a piece
        target = t_before + dt
        cpu_start = clock()
        with work_budget(self.step_budget, self.wall_budget):
            while True:
                remaining = target - self.stepper.t
                if self.pause_at_end:
                    remaining = min(remaining, self.t_end - self.stepper.t)
                if remaining <= 1e-12 * max(1.0, abs(target)):
                    break
                budget_left = left()
                if frames and (budget_left <= 0 or len(frames) >= 2 * n + 2):
                    # the budget of this tick is spent: the rest of dt is dropped
                    self.pace.cut(clock() - cpu_start, self.step_budget)
                    break
                d = min(self.pace.piece_size(piece, budget_left, quantum), remaining)
                t_prev = self.stepper.t
                frame, stop = self.pace.step(self.stepper, d, self._allowed())
                if frame is None:
                    self.playing = False
                    self.notify(stop, "error")
                    break
                if self.stepper.t <= t_prev and self.stepper.computing:
                    break  # work paused at the budget: the time moves at a later tick
                frames.append(frame)
                self.log.add(frame)
                if self.stepper.t <= t_prev:
                    break  # the lesson's run cannot go on (checked below)
        if frames:
            self.frame = frames[-1]
            if self.stepper.t <= t_before and self.playing:
                # the lesson's run cannot go on (e.g. an end condition was reached)
                self.playing = False
                stopped = (
                    Message(
                        N_("the run stopped at t = {t:.4g} s: {why}"),
                        t=self.stepper.t,
                        why=self.frame.message,
                    )
                    if self.frame.message
                    else Message(N_("the run stopped at t = {t:.4g} s"), t=self.stepper.t)
                )
                self.notify(stopped, "info", about_run=True)
        if self.pause_at_end and self.stepper.t >= self.t_end - 1e-9 and self.playing:
            self.playing = False
            self.notify(
                Message(
                    N_(
                        "t = {t_end} s reached (the textbook's run); press play to run again,"
                        " or untick 'pause at t_end'"
                    ),
                    t_end=self.t_end,
                ),
                "info",
                about_run=True,
            )
        return frames

    def tick(self, wall_dt: float) -> list[Frame]:
        """Advance by ``wall_dt`` seconds of wall time times the speed (when playing);
        a session shown by several pages advances once per loop tick through its
        :attr:`shared_clock`."""
        if self.shared_clock is not None:
            return self.shared_clock(wall_dt)
        return self.advance_wall(wall_dt)

    def advance_wall(self, wall_dt: float) -> list[Frame]:
        """Advance by ``wall_dt`` seconds of wall time times the speed (when playing)."""
        if not self.playing:
            return []
        # lesson time goes forward in whole quanta (the remainder is carried to the next
        # tick): the same few step sizes recur, so cached step maps are reused
        scale = self.lesson.time_scale
        want = min(wall_dt, 0.25) * self.speed * scale + self._time_debt
        quantum = TIME_QUANTUM * scale
        k = int(math.floor(want / quantum + 0.5))
        self._time_debt = want - k * quantum
        if k <= 0:
            return []
        t0 = self.stepper.t
        frames = self._advance(k * quantum)
        moved = self.stepper.t - t0
        if moved < k * quantum - 1e-9 * max(1.0, abs(t0)):
            self._time_debt = 0.0  # what the budget cut is dropped, not owed
        if self.playing and not (self.pause_at_end and self.stepper.t >= self.t_end - 1e-9):
            # (not at t_end, where it stopped on purpose)
            news = self.pace.follow(k * quantum, moved, min(wall_dt, 0.25))
            if news == "back":
                self.notify(Message(N_("playing at {speed}x again"), speed=self.speed), "info")
            elif news == "slow":
                self.notify(self.slow_text(), "warning")
        return frames

    @property
    def slowed(self) -> bool:
        """The run cannot keep up with the asked speed (its page says so)."""
        return self.pace.slowed

    def effective_speed(self) -> float:
        """The speed the run keeps up with (the asked speed unless :attr:`slowed`)."""
        return self.pace.effective_speed(self.speed)

    def slow_text(self) -> str:
        """What the page says while the run cannot keep up with the asked speed."""
        return self.pace.slow_text(self.speed, self.lesson)

    def _allowed(self) -> frozenset[str]:
        """The series of the lesson that may be undefined (``Series.undefined``), kept for
        the current lesson and parameters."""
        key = self._allowed_for
        if key is None or key[0] is not self.lesson or key[1] is not self.params:
            names = frozenset(s.name for s in self.lesson.series_for(self.params) if s.undefined)
            key = self._allowed_for = (self.lesson, self.params, names)
        return key[2]

    def step(self) -> list[Frame]:
        """One single step (paused): the lesson's sampling step (the source's table of
        t = 0, 1, 2, ...), else ``STEP_DT`` seconds times the speed and time scale."""
        self.playing = False
        if self.pause_at_end and self.stepper.t >= self.t_end - 1e-9:
            self.notify(
                Message(
                    N_("t_end = {t_end:g} s reached; reset or untick 'pause at t_end'"),
                    t_end=self.t_end,
                ),
                "info",
            )
            return []
        step = self.lesson.sampling or STEP_DT * self.speed * self.lesson.time_scale
        target = (math.floor(self.stepper.t / step + 1e-9) + 1) * step  # on the grid
        return self.go_to(target)

    def go_to(self, t: float) -> list[Frame]:
        """Pause and show the run at lesson time ``t`` (from the start if ``t`` is
        earlier than now); the frames on the way are recorded as when played."""
        if not (isinstance(t, (int, float)) and math.isfinite(t)) or t < 0:
            raise LabError(Message(N_("go to t: must be a time >= 0 s, got {t}"), t=plain(t)))
        limit = MAX_GO_TO * max(self.t_end, 1e-9)
        if t > limit:
            raise LabError(
                Message(
                    N_("go to t: {t:g} s is beyond {limit:g} s ({times} x t_end)"),
                    t=t,
                    limit=limit,
                    times=MAX_GO_TO,
                )
            )
        self.playing = False
        if t < self.stepper.t - 1e-12:
            self.reset()
        frames: list[Frame] = []
        piece = SUBSTEP_DT * self.lesson.time_scale
        with work_budget(GO_TO_BUDGET):
            while t - self.stepper.t > 1e-12 * max(1.0, t):
                if left() <= 0:
                    self.notify(
                        Message(
                            N_(
                                "go to t: stopped at t = {t:.6g} s after {budget} s of computing"
                                " (the step is too small to go further at once); go to t again"
                                " to go on"
                            ),
                            t=self.stepper.t,
                            budget=GO_TO_BUDGET,
                        ),
                        "warning",
                    )
                    break
                t_prev = self.stepper.t
                frame, stop = self.pace.step(
                    self.stepper, min(piece, t - self.stepper.t), self._allowed()
                )
                if frame is None:
                    self.notify(stop, "error")
                    break
                frames.append(frame)
                self.log.add(frame)
                if self.stepper.t <= t_prev:
                    break
        if frames:
            self.frame = frames[-1]
        return frames

    # -- state ----------------------------------------------------------------------

    def state(self) -> SessionState:
        """The copyable state (lesson, preset, values, playback settings)."""
        return SessionState(
            lesson=self.lesson.id,
            preset=self.preset,
            values=self.raw_values(),
            speed=self.speed,
            pause_at_end=self.pause_at_end,
            visible_vectors=sorted(self.visible_vectors)
            if self.visible_vectors is not None
            else None,
        )

    def apply_state(self, state: SessionState) -> list[str]:
        """Rebuild from a (possibly stale or hand-made) state: unknown lessons/presets
        and bad values are dropped with a message; returns the messages."""
        problems: list[str] = []
        lesson = self.lessons.get(state.lesson)
        if lesson is None:
            raise LabError(Message(N_("unknown lesson {lesson}"), lesson=repr(state.lesson[:60])))
        preset = state.preset
        if preset is not None and preset not in {p.name for p in lesson.presets}:
            problems.append(
                Message(N_("unknown preset {preset} dropped"), preset=repr(preset[:60]))
            )
            preset = None
        known = {p.name for p in lesson.params}
        values = {k: v for k, v in state.values.items() if k in known}
        # drop bad values one by one so the good ones survive
        while True:
            try:
                self._take(self._open(lesson, values, preset), STATE)
                break
            except ParamError as exc:
                if exc.name in values:
                    problems.append(Message(N_("{error}: value dropped"), error=str(exc)))
                    values.pop(exc.name)
                elif values:
                    problems.append(Message(N_("{error}: saved values dropped"), error=str(exc)))
                    values = {}
                else:
                    raise LabError(str(exc)) from None
        try:
            self.set_speed(state.speed)
        except LabError as exc:
            problems.append(exc.args[0] if isinstance(exc.args[0], Message) else str(exc))
        self.pause_at_end = bool(state.pause_at_end)
        self.visible_vectors = (
            set(state.visible_vectors) if state.visible_vectors is not None else None
        )
        for p in problems:
            log.info("state of %s restored without: %s", lesson.id, p)
            self.notify(p, "warning")
        return problems

    def copy_from(self, other: Session) -> None:
        """Take another session's state (lesson, values, playback settings)."""
        self.apply_state(other.state())

    # -- export ---------------------------------------------------------------------

    def run_result(self) -> RunResult:
        """The run shown so far as a :class:`RunResult`: the lesson's declared series (the
        same columns and units as ``analyzer-lab run``), sampled at the played frames."""
        log = self.log
        if not len(log):
            log = RunLog(2)
            log.add(self.frame)
        t = log.t
        declared = self.lesson.series_for(self.params)
        series = {s.name: log.scalar(s.name) for s in declared if s.name in log.scalar_names}
        metrics: dict[str, Any] = {
            "t_end": float(t[-1]),
            "samples": len(t),
            "source": "live run",
            "speed": self.speed,
        }
        messages = [text for _, text in self.notices]
        units = {s.name: s.unit for s in declared}
        return RunResult(
            self.lesson.id, self.preset, self.raw_values(), t, series, metrics, messages, units
        )


class SharedClock:
    """A session's :attr:`Session.shared_clock` while several pages show it (the
    classroom's demo): the first page that ticks it in a loop tick advances it (by the
    wall time since the last advance); the other pages of that tick get the same frames."""

    def __init__(self, session: Session, tick_count: Callable[[], int], fps: float) -> None:
        self.session = session
        self.tick_count = tick_count
        self.fps = fps
        self.key = -1
        self.frames: list[Frame] = []
        self.last = time.monotonic()
        self.calls = 0
        self.advances = 0

    def __call__(self, wall_dt: float) -> list[Frame]:
        self.calls += 1
        key = self.tick_count()
        if key != self.key:
            self.key = key
            now = time.monotonic()
            dt = now - self.last
            self.last = now
            if dt > 3.0 / self.fps:  # was paused (no ticks): one frame period
                dt = 1.0 / self.fps
            self.advances += 1
            self.frames = self.session.advance_wall(dt)
        return self.frames


__all__ = [
    "TIME_QUANTUM",
    "LabError",
    "SPEEDS",
    "SOLO_STEP_BUDGET",
    "SOLO_WALL_BUDGET",
    "STEP_BUDGET",
    "STEP_WALL_BUDGET",
    "Session",
    "SessionState",
    "SharedClock",
    "lesson_label",
]
