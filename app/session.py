"""One student's state, independent of the view: lesson, parameters, stepper, playback.

A :class:`Session` holds the validated parameters of one lesson, a live
:class:`~lessons.core.contract.Stepper` and the playback state (playing, speed,
time), and records the run it has shown (:meth:`Session.run_result`).  Every value
that reaches it is validated with :meth:`Param.parse` / :meth:`Lesson.resolve`; a
refused value raises :class:`ParamError` and leaves the session as it was.

The whole state that matters to a student is :class:`SessionState` (plain JSON
data): it is saved in the browser, restored on reload, and can be copied from
one session to another (:meth:`Session.state` / :meth:`Session.apply_state`).
"""

from __future__ import annotations

import json
import math
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from lessons.core.contract import (
    Frame,
    Lesson,
    ParamError,
    Params,
    RunResult,
    SceneSpec,
    Stepper,
)
from lessons.core.formula import Formula

#: Playback speeds offered (lesson seconds per wall-clock second).
SPEEDS: tuple[float, ...] = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0)
#: Lesson time of one "single step" press, at speed 1 (scaled by the speed).
STEP_DT = 1.0 / 30.0
#: Longest lesson-time piece a frame advances in one stepper call (the trail gets a
#: point per piece); a frame makes at most MAX_SUBSTEPS pieces.
SUBSTEP_DT = 1.0 / 30.0
TIME_QUANTUM = 1.0 / 600.0  # lesson seconds: the grain of a played tick
MAX_SUBSTEPS = 8
#: Samples of the recorded run kept for export (older ones are thinned out).
MAX_LOG = 20000
#: Parameter groups whose changes do not redraw the scene at once (debounced).
LIVE_GROUPS = frozenset({"controls", "method"})
SCENE_DEBOUNCE = 0.3
#: Size limit of a saved state (bytes of JSON) accepted from a browser.
MAX_STATE_BYTES = 20000


class LabError(ValueError):
    """A refused request; ``str(err)`` is one line for the user."""


@dataclass
class SessionState:
    """What a student set: enough to rebuild the session (JSON-friendly)."""

    lesson: str
    preset: str | None = None
    values: dict[str, Any] = field(default_factory=dict)
    speed: float = 1.0
    pause_at_end: bool = True
    visible_vectors: list[str] | None = None

    def to_json(self) -> str:
        return json.dumps(asdict(self), allow_nan=False, default=str)

    @classmethod
    def from_json(cls, text: str) -> SessionState:
        """Parse a saved state; raise :class:`LabError` on anything malformed."""
        if not isinstance(text, str) or len(text) > MAX_STATE_BYTES:
            raise LabError("saved state is missing or too large")
        try:
            data = json.loads(text)
        except (ValueError, RecursionError) as exc:
            raise LabError(f"saved state is not valid JSON: {exc}") from None
        if not isinstance(data, dict) or not isinstance(data.get("lesson"), str):
            raise LabError("saved state has no lesson")
        values = data.get("values") or {}
        if not isinstance(values, dict) or not all(isinstance(k, str) for k in values):
            raise LabError("saved state: values must be an object")
        clean: dict[str, Any] = {}
        for k, v in values.items():
            if isinstance(v, (str, int, float, bool)) and not (isinstance(v, str) and len(v) > 400):
                clean[k] = v
        preset = data.get("preset")
        speed = data.get("speed", 1.0)
        vectors = data.get("visible_vectors")
        return cls(
            lesson=data["lesson"][:80],
            preset=preset[:80] if isinstance(preset, str) else None,
            values=clean,
            speed=float(speed)
            if isinstance(speed, (int, float)) and not isinstance(speed, bool)
            else 1.0,
            pause_at_end=bool(data.get("pause_at_end", True)),
            visible_vectors=[str(v)[:40] for v in vectors][:20]
            if isinstance(vectors, list)
            else None,
        )


def raw_value(value: Any) -> Any:
    """A validated value as JSON-friendly raw data (formulas as their text)."""
    if isinstance(value, Formula):
        return value.text
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    return value


@dataclass
class LogSample:
    t: float
    points: dict[str, np.ndarray]
    scalars: dict[str, float]


class RunLog:
    """The samples a session has shown, for export: columns of preallocated arrays that
    grow by doubling up to ``limit`` rows; when full, every second row is dropped and
    from then on only every ``stride``-th frame is kept."""

    def __init__(self, limit: int = MAX_LOG) -> None:
        self.limit = max(2, int(limit))
        self.clear()

    def clear(self) -> None:
        self.count = 0
        self.stride = 1
        self._skip = 0
        self._cap = 0
        self._t = np.empty(0)
        self._points: dict[str, np.ndarray] = {}  # name -> (cap, members, 3)
        self._scalars: dict[str, np.ndarray] = {}  # name -> (cap,)

    def _grow(self) -> None:
        cap = min(self.limit, max(64, 2 * self._cap))

        def grown(a: np.ndarray) -> np.ndarray:
            out = np.full((cap, *a.shape[1:]), np.nan)
            out[: self.count] = a[: self.count]
            return out

        self._t = grown(self._t)
        self._points = {k: grown(v) for k, v in self._points.items()}
        self._scalars = {k: grown(v) for k, v in self._scalars.items()}
        self._cap = cap

    def add(self, frame: Frame) -> None:
        if self._skip:
            self._skip -= 1
            return
        self._skip = self.stride - 1
        if self.count == self._cap:
            self._grow()
        i = self.count
        self._t[i] = float(frame.t)
        for name, value in frame.points.items():
            pts = np.asarray(value, dtype=float).reshape(-1, 3)
            col = self._points.get(name)
            if col is None:
                col = self._points[name] = np.full((self._cap, len(pts), 3), np.nan)
            n = min(len(pts), col.shape[1])
            col[i, :n] = pts[:n]
            col[i, n:] = np.nan
        for name, col in self._points.items():
            if name not in frame.points:
                col[i] = np.nan
        for name, value in frame.scalars.items():
            col = self._scalars.get(name)
            if col is None:
                col = self._scalars[name] = np.full(self._cap, np.nan)
            col[i] = float(value)
        for name, col in self._scalars.items():
            if name not in frame.scalars:
                col[i] = np.nan
        self.count += 1
        if self.count >= self.limit:
            keep = np.arange(0, self.count, 2)
            m = len(keep)
            self._t[:m] = self._t[keep]
            for col in (*self._points.values(), *self._scalars.values()):
                col[:m] = col[keep]
                col[m:] = np.nan
            self.count = m
            self.stride *= 2

    @property
    def t(self) -> np.ndarray:
        return self._t[: self.count].copy()

    def points(self, name: str) -> np.ndarray:
        """``(samples, members, 3)``."""
        return self._points[name][: self.count].copy()

    def scalar(self, name: str) -> np.ndarray:
        return self._scalars[name][: self.count].copy()

    @property
    def point_names(self) -> list[str]:
        return list(self._points)

    @property
    def scalar_names(self) -> list[str]:
        return list(self._scalars)

    @property
    def samples(self) -> list[LogSample]:
        """The rows as :class:`LogSample` objects (a point missing from a frame is left out)."""
        out = []
        for i in range(self.count):
            pts = {k: v[i].copy() for k, v in self._points.items() if not np.all(np.isnan(v[i]))}
            sc = {k: float(v[i]) for k, v in self._scalars.items() if not np.isnan(v[i])}
            out.append(LogSample(float(self._t[i]), pts, sc))
        return out

    @property
    def nbytes(self) -> int:
        return int(
            self._t.nbytes
            + sum(v.nbytes for v in self._points.values())
            + sum(v.nbytes for v in self._scalars.values())
        )

    def __len__(self) -> int:
        return self.count


class LRUCache:
    """A small thread-safe LRU cache (scenes and derivations are pure functions of
    the lesson and its parameters; many students share the same values)."""

    def __init__(self, maxsize: int = 64) -> None:
        from collections import OrderedDict

        self.maxsize = maxsize
        self._data: OrderedDict[Any, Any] = OrderedDict()
        self._lock = threading.Lock()

    def get_or_make(self, key: Any, make: Callable[[], Any]) -> Any:
        with self._lock:
            if key in self._data:
                self._data.move_to_end(key)
                return self._data[key]
        value = make()
        with self._lock:
            self._data[key] = value
            while len(self._data) > self.maxsize:
                self._data.popitem(last=False)
        return value


def params_key(lesson: Lesson, params: Mapping[str, Any]) -> tuple:
    """A hashable key of a lesson's validated parameters."""
    return (lesson.id, tuple(sorted((k, repr(raw_value(v))) for k, v in params.items())))


SCENE_CACHE = LRUCache(64)


def lesson_scene(lesson: Lesson, params: Params) -> SceneSpec:
    """``lesson.scene(params)``, shared between sessions with the same values."""
    return SCENE_CACHE.get_or_make(params_key(lesson, params), lambda: lesson.scene(params))


def _arrays_equal(a: Any, b: Any) -> bool:
    try:
        return bool(np.array_equal(np.asarray(a), np.asarray(b)))
    except Exception:
        return False


def scenes_equal(a: SceneSpec, b: SceneSpec) -> bool:
    """Same drawing (static items, moving item names/colours, bounds)."""
    if a is b:
        return True
    if not _arrays_equal(a.bounds, b.bounds) or a.planar != b.planar:
        return False
    if a.moving_points != b.moving_points or a.moving_vectors != b.moving_vectors:
        return False
    for xs, ys in ((a.meshes, b.meshes), (a.bodies, b.bodies)):
        if len(xs) != len(ys):
            return False
        for x, y in zip(xs, ys):
            if (x.name, tuple(x.color), x.opacity, x.wireframe) != (
                y.name,
                tuple(y.color),
                y.opacity,
                y.wireframe,
            ):
                return False
            if not (_arrays_equal(x.vertices, y.vertices) and _arrays_equal(x.faces, y.faces)):
                return False
    if len(a.curves) != len(b.curves) or len(a.markers) != len(b.markers):
        return False
    for x, y in zip(a.curves, b.curves):
        if (x.name, tuple(x.color), x.width) != (
            y.name,
            tuple(y.color),
            y.width,
        ) or not _arrays_equal(x.points, y.points):
            return False
    for x, y in zip(a.markers, b.markers):
        if (x.name, tuple(x.color), x.size, x.label) != (
            y.name,
            tuple(y.color),
            y.size,
            y.label,
        ) or not _arrays_equal(x.points, y.points):
            return False
    return True


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

    def __init__(
        self, lessons: Sequence[Lesson], lesson_id: str | None = None, preset: str | None = None
    ) -> None:
        if not lessons:
            raise LabError("no lessons are installed")
        self.lessons: dict[str, Lesson] = {l.id: l for l in lessons}
        self.lock = threading.RLock()
        self.notices: deque[tuple[str, str]] = deque(maxlen=20)
        self.playing = False
        self.speed = 1.0
        self.pause_at_end = True
        self.visible_vectors: set[str] | None = None
        self.log = RunLog()
        self.max_substeps = MAX_SUBSTEPS  # lowered by the server under load
        self._time_debt = 0.0  # lesson time owed to the next played tick (< TIME_QUANTUM / 2)
        self.scene_due: float | None = None  # when a deferred scene rebuild is due (monotonic time)
        self.revision = (
            0  # bumped on any change of lesson/params (the view re-renders what it needs)
        )
        self.scene_revision = 0  # bumped when the static scene must be redrawn
        self.reset_revision = 0  # bumped when the run restarts (trail cleared)
        self.on_change: Callable[[str], None] | None = None
        first = lesson_id if lesson_id in self.lessons else next(iter(self.lessons))
        if lesson_id is not None and lesson_id not in self.lessons:
            self.notify(f"unknown lesson {lesson_id[:60]!r}; showing {first}", "warning")
        self._load(self.lessons[first], preset if preset is not None else None, {})

    # -- notices --------------------------------------------------------------------

    def notify(self, text: str, level: str = "info") -> None:
        """A message for the user (the view shows the newest)."""
        self.notices.append((level, str(text)[:500]))

    # -- lesson and parameters ------------------------------------------------------------

    @property
    def lesson_id(self) -> str:
        return self.lesson.id

    def _build(
        self, lesson: Lesson, preset: str | None, values: Mapping[str, Any]
    ) -> tuple[Params, Stepper, SceneSpec]:
        params = lesson.resolve(values, preset)
        try:
            stepper = lesson.stepper(params)
            scene = lesson_scene(lesson, params)
        except ParamError:
            raise
        except (ValueError, ArithmeticError) as exc:
            raise ParamError("params", str(exc)) from None
        return params, stepper, scene

    def _load(self, lesson: Lesson, preset: str | None, values: Mapping[str, Any]) -> None:
        params, stepper, scene = self._build(lesson, preset, values)
        self.lesson = lesson
        self.preset = preset
        self.params = params
        self.stepper = stepper
        self.scene = scene
        self.frame = stepper.reset()
        self.t_end = lesson.preset_t_end(preset)
        self.log.clear()
        self.log.add(self.frame)
        self.revision += 1
        self.scene_revision += 1
        self.reset_revision += 1
        self._messages_of(lesson, params)

    def _messages_of(self, lesson: Lesson, params: Params) -> None:
        """Surface the lesson's own notes on these values (e.g. a projected start point)."""
        for note in lesson.notes(params):
            if note.kind in ("info", "warning"):
                self.notify(note.text, note.kind)

    def select_lesson(self, lesson_id: str, preset: str | None = None) -> None:
        """Switch lesson (defaults, or the given preset); refuses unknown ids."""
        if not isinstance(lesson_id, str) or lesson_id not in self.lessons:
            raise LabError(
                f"unknown lesson {str(lesson_id)[:60]!r}; known: {', '.join(self.lessons)}"
            )
        lesson = self.lessons[lesson_id]
        if preset is not None:
            lesson.preset(preset)  # raises ParamError for an unknown preset
        self.playing = False
        self._load(lesson, preset, {})

    def apply_preset(self, name: str | None) -> None:
        """Load one of the textbook's examples (``None``: the defaults); the run restarts."""
        if name is not None:
            self.lesson.preset(name)
        self._load(self.lesson, name, {})

    def raw_values(self) -> dict[str, Any]:
        return {k: raw_value(v) for k, v in self.params.items()}

    def set_values(self, changes: Mapping[str, Any]) -> None:
        """Change parameters live; raises :class:`ParamError` (nothing changes) if refused.

        Controls and surface parameters take effect while running (the stepper keeps
        its state); a changed start point restarts the run from the new point.
        """
        if not changes:
            return
        for name in changes:
            self.lesson.param(name)  # unknown names are refused
        raw = self.raw_values()
        raw.update(changes)
        params = self.lesson.resolve(raw)
        changed = [n for n in changes if params[n] != self.params.get(n)]
        if not changed:
            return
        groups = {self.lesson.param(n).group for n in changed}
        live_only = groups <= LIVE_GROUPS
        try:
            scene = self.scene if live_only else lesson_scene(self.lesson, params)
            if "initial" in groups:
                stepper = self.lesson.stepper(params)
            else:
                stepper = self.stepper
                stepper.set_params(params)
        except ParamError:
            raise
        except (ValueError, ArithmeticError) as exc:
            raise ParamError(changed[0], str(exc)) from None
        self.params = params
        self.stepper = stepper
        self.scene = scene
        self.revision += 1
        if live_only:
            # controls rarely change the drawing: rebuild it later, off the hot path
            self.scene_due = time.monotonic() + SCENE_DEBOUNCE
        else:
            self.scene_revision += 1
            self.scene_due = None
        if "initial" in groups:
            self.frame = stepper.reset()
            self.log.clear()
            self.log.add(self.frame)
            self.reset_revision += 1
        else:
            self.frame = stepper.frame()
        self._messages_of(self.lesson, params)

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
            raise LabError("this lesson has no start point")
        return names

    def snap_start(self) -> tuple[float, float, float] | None:
        """Put the start point exactly where the lesson places it (on the surface): the
        first moving point of a fresh run."""
        names = self._start_names()
        fresh = self.lesson.stepper(self.params).reset()
        if not fresh.points:
            raise LabError("this lesson has no moving point")
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
            raise LabError("the clicked point is not finite")
        self.set_values(dict(zip(names, p)))

    # -- playback -------------------------------------------------------------------

    def play(self) -> None:
        if self.pause_at_end and self.frame.t >= self.t_end - 1e-9:
            self.reset()
        self.playing = True

    def pause(self) -> None:
        self.playing = False

    def set_speed(self, speed: Any) -> None:
        try:
            value = float(speed)
        except (TypeError, ValueError):
            raise LabError(f"speed must be one of {', '.join(f'{s:g}x' for s in SPEEDS)}") from None
        if not any(abs(value - s) < 1e-9 for s in SPEEDS):
            raise LabError(
                f"speed must be one of {', '.join(f'{s:g}x' for s in SPEEDS)}; got {value!r}"
            )
        self.speed = value

    def reset(self) -> Frame:
        self.frame = self.stepper.reset()
        self.log.clear()
        self.log.add(self.frame)
        self.reset_revision += 1
        return self.frame

    def _advance(self, dt: float) -> list[Frame]:
        frames: list[Frame] = []
        if dt <= 0 or not math.isfinite(dt):
            return frames
        t_before = self.stepper.t
        n = max(1, min(self.max_substeps, int(math.ceil(dt / SUBSTEP_DT - 1e-9))))
        piece = dt / n
        for _ in range(n):
            remaining = self.t_end - self.stepper.t if self.pause_at_end else math.inf
            d = min(piece, remaining)
            if d <= 1e-12:
                break
            try:
                frame = self.stepper.advance(d)
            except (ValueError, ArithmeticError, FloatingPointError) as exc:
                self.playing = False
                self.notify(f"the integration stopped: {exc}", "error")
                break
            frames.append(frame)
            self.log.add(frame)
        if frames:
            self.frame = frames[-1]
            if self.stepper.t <= t_before and self.playing:
                # the lesson's run cannot go on (e.g. an end condition was reached)
                self.playing = False
                self.notify(
                    f"the run stopped at t = {self.stepper.t:.4g} s"
                    + (f": {self.frame.message}" if self.frame.message else ""),
                    "info",
                )
        if self.pause_at_end and self.stepper.t >= self.t_end - 1e-9 and self.playing:
            self.playing = False
            self.notify(
                f"t = {self.t_end:g} s reached (the textbook's run); press play to run again,"
                " or untick 'pause at t_end'",
                "info",
            )
        return frames

    def tick(self, wall_dt: float) -> list[Frame]:
        """Advance by ``wall_dt`` seconds of wall time times the speed (when playing)."""
        if not self.playing:
            return []
        # lesson time goes forward in whole quanta (the remainder is carried to the next
        # tick): the same few step sizes recur, so cached step maps are reused
        want = min(wall_dt, 0.25) * self.speed + self._time_debt
        k = int(math.floor(want / TIME_QUANTUM + 0.5))
        self._time_debt = want - k * TIME_QUANTUM
        if k <= 0:
            return []
        return self._advance(k * TIME_QUANTUM)

    def step(self) -> list[Frame]:
        """One single step (paused): ``STEP_DT`` lesson seconds times the speed."""
        self.playing = False
        if self.pause_at_end and self.stepper.t >= self.t_end - 1e-9:
            self.notify(
                f"t_end = {self.t_end:g} s reached; reset or untick 'pause at t_end'", "info"
            )
            return []
        return self._advance(STEP_DT * self.speed)

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
            raise LabError(f"unknown lesson {state.lesson[:60]!r}")
        preset = state.preset
        if preset is not None and preset not in {p.name for p in lesson.presets}:
            problems.append(f"unknown preset {preset[:60]!r} dropped")
            preset = None
        known = {p.name for p in lesson.params}
        values = {k: v for k, v in state.values.items() if k in known}
        # drop bad values one by one so the good ones survive
        while True:
            try:
                params, stepper, scene = self._build(lesson, preset, values)
                break
            except ParamError as exc:
                if exc.name in values:
                    problems.append(f"{exc}: value dropped")
                    values.pop(exc.name)
                elif values:
                    problems.append(f"{exc}: saved values dropped")
                    values = {}
                else:
                    raise LabError(str(exc)) from None
        self.playing = False
        self.lesson, self.preset, self.params, self.stepper, self.scene = (
            lesson,
            preset,
            params,
            stepper,
            scene,
        )
        self.frame = stepper.reset()
        self.t_end = lesson.preset_t_end(preset)
        self.log.clear()
        self.log.add(self.frame)
        self.revision += 1
        self.scene_revision += 1
        self.reset_revision += 1
        try:
            self.set_speed(state.speed)
        except LabError as exc:
            problems.append(str(exc))
        self.pause_at_end = bool(state.pause_at_end)
        self.visible_vectors = (
            set(state.visible_vectors) if state.visible_vectors is not None else None
        )
        for p in problems:
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


__all__ = ["LabError", "RunLog", "SPEEDS", "Session", "SessionState", "lesson_label", "raw_value"]
