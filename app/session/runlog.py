"""The recorded run and the caches a session uses: the run log (exported as CSV/JSON),
parameter keys and the scene cache."""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, Lesson, Params, SceneSpec
from analyzer_lab.lessons.kit.formula import Formula

#: Samples of the recorded run kept for export (older ones are thinned out).
MAX_LOG = 20000


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
    from then on only every ``stride``-th frame is kept.  The scalars are the columns of
    one table (a frame's row is written at once when it has the same names as the last)."""

    def __init__(self, limit: int = MAX_LOG) -> None:
        self.limit = max(2, int(limit))
        #: bumped by every change of the rows (a row added, the log cleared or thinned)
        self.revision = 0
        self.clear()

    def clear(self) -> None:
        self.revision += 1
        self.count = 0
        self.stride = 1
        self._skip = 0
        self._cap = 0
        self._t = np.empty(0)
        self._points: dict[str, np.ndarray] = {}  # name -> (cap, members, 3)
        self._sc = np.empty((0, 0))  # (cap, scalars): the column of each name
        self._columns: dict[str, int] = {}  # scalar name -> its column in _sc
        #: the names of the last frame's scalars (in order) and their columns (None: all
        #: the columns, in order)
        self._names: tuple[str, ...] = ()
        self._where: list[int] | None = None

    def _grow(self) -> None:
        cap = min(self.limit, max(64, 2 * self._cap))

        def grown(a: np.ndarray) -> np.ndarray:
            out = np.full((cap, *a.shape[1:]), np.nan)
            out[: self.count] = a[: self.count]
            return out

        self._t = grown(self._t)
        self._points = {k: grown(v) for k, v in self._points.items()}
        self._sc = grown(self._sc)
        self._cap = cap

    def _scalar_columns(self, names: tuple[str, ...]) -> None:
        """Columns for the names of a frame's scalars (new names get a column of NaN)."""
        new = [n for n in names if n not in self._columns]
        if new:
            for n in new:
                self._columns[n] = len(self._columns)
            extra = np.full((self._sc.shape[0], len(new)), np.nan)
            self._sc = np.concatenate([self._sc, extra], axis=1)
        where = [self._columns[n] for n in names]
        self._names = names
        self._where = None if where == list(range(len(self._columns))) else where

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
            col = self._points.get(name)
            if (
                col is not None
                and type(value) is np.ndarray
                and value.shape == (col.shape[1], 3)
                and value.dtype == np.float64
            ):
                col[i] = value  # the same members as the column: one copy
                continue
            pts = np.asarray(value, dtype=float).reshape(-1, 3)
            if col is None:
                col = self._points[name] = np.full((self._cap, len(pts), 3), np.nan)
            n = min(len(pts), col.shape[1])
            col[i, :n] = pts[:n]
            col[i, n:] = np.nan
        if len(self._points) > len(frame.points):
            for name, col in self._points.items():
                if name not in frame.points:
                    col[i] = np.nan
        scalars = frame.scalars
        names = tuple(scalars)
        if names != self._names:
            self._scalar_columns(names)
        row = self._sc[i]
        values: list[Any] = list(scalars.values())
        if self._where is not None:
            row[:] = np.nan
        try:
            row[self._where if self._where is not None else slice(None)] = values
        except (TypeError, ValueError):  # not plain numbers: each as float() reads it
            values = [float(v) for v in values]
            row[self._where if self._where is not None else slice(None)] = values
        self.count += 1
        self.revision += 1
        if self.count >= self.limit:
            keep = np.arange(0, self.count, 2)
            m = len(keep)
            self._t[:m] = self._t[keep]
            for col in (*self._points.values(), self._sc):
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
        return self._sc[: self.count, self._columns[name]].copy()

    @property
    def point_names(self) -> list[str]:
        return list(self._points)

    @property
    def scalar_names(self) -> list[str]:
        return list(self._columns)

    def sample(self, i: int) -> LogSample:
        """Row ``i`` as a :class:`LogSample` (a point missing from that frame is left out)."""
        pts = {k: v[i].copy() for k, v in self._points.items() if not np.all(np.isnan(v[i]))}
        row = self._sc[i]
        sc = {k: float(row[j]) for k, j in self._columns.items() if not np.isnan(row[j])}
        return LogSample(float(self._t[i]), pts, sc)

    @property
    def samples(self) -> list[LogSample]:
        """Every row as a :class:`LogSample` (:meth:`sample` builds only the rows needed)."""
        return [self.sample(i) for i in range(self.count)]

    @property
    def nbytes(self) -> int:
        return int(self._t.nbytes + sum(v.nbytes for v in self._points.values()) + self._sc.nbytes)

    def __len__(self) -> int:
        return self.count


class LRUCache:
    """A small thread-safe LRU cache (scenes and derivations are pure functions of
    the lesson and its parameters; many students share the same values)."""

    def __init__(self, maxsize: int = 64) -> None:

        self.maxsize = maxsize
        self._data: OrderedDict[Any, Any] = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key: Any) -> Any:
        """The value of ``key`` (``None`` when not cached)."""
        with self._lock:
            if key in self._data:
                self._data.move_to_end(key)
                return self._data[key]
        return None

    def put(self, key: Any, value: Any) -> None:
        with self._lock:
            self._data[key] = value
            while len(self._data) > self.maxsize:
                self._data.popitem(last=False)

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
    except (TypeError, ValueError):  # not arrays of one shape (e.g. ragged lists)
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
