"""Live plots: the lesson's declared plots as uPlot charts, with axis titles and units."""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Sequence
from typing import Any

import numpy as np

from app.viser_boundary import fast_set
from lessons.core.contract import Frame, Lesson, PlotSpec

PLOT_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b")
#: seconds after the charts are created during which no data is sent (a busy browser
#: can take a while; an early update is reported as an update of a missing component)
FRESH_DELAY = 1.5


def units_of(lesson: Lesson, names: Sequence[str]) -> str:
    """The plot's unit when all its series share one (from the lesson's declarations)."""
    units = {x.name: x.unit for x in lesson.series}
    found = {units.get(n, "") for n in names}
    return found.pop() if len(found) == 1 else ""


class PlotBuffer:
    """Sliding window of frame scalars for one :class:`PlotSpec`."""

    def __init__(self, spec: PlotSpec, window: int) -> None:
        self.spec = spec
        self.t: deque[float] = deque(maxlen=window)
        self.values = {name: deque(maxlen=window) for name in spec.series}
        self.dirty = False

    def clear(self) -> None:
        self.t.clear()
        for v in self.values.values():
            v.clear()
        self.dirty = True

    def add(self, frame: Frame) -> None:
        self.t.append(float(frame.t))
        for name, buf in self.values.items():
            v = frame.scalars.get(name, math.nan)
            buf.append(float(v) if v is not None and math.isfinite(float(v)) else math.nan)
        self.dirty = True

    def data(self) -> tuple[np.ndarray, ...]:
        if len(self.t) == 0:
            return (np.zeros(1),) + tuple(np.zeros(1) for _ in self.values)
        return (np.fromiter(self.t, float, len(self.t)),) + tuple(
            np.fromiter(v, float, len(v)) for v in self.values.values()
        )


class PlotPanel:
    """The lesson's plots in one page: buffers fed by frames, uploads round-robin."""

    def __init__(self, gui: Any, window: int) -> None:
        self.gui = gui
        self.window = window
        self.plots: list[tuple[PlotBuffer, Any]] = []
        self._rr = 0
        self._fresh_until = 0.0

    def build(self, lesson: Lesson) -> None:
        """Create the charts of ``lesson`` (inside the caller's folder)."""
        self.plots = []
        for spec in lesson.plots:
            buf = PlotBuffer(spec, self.window)
            series = [{"label": "t"}] + [
                {"label": name, "stroke": PLOT_COLORS[i % len(PLOT_COLORS)], "width": 1.5}
                for i, name in enumerate(spec.series)
            ]
            units = spec.units or units_of(lesson, spec.series)
            title = spec.title + (f" [{units}]" if units else "")
            handle = self.gui.add_uplot(
                buf.data(),
                tuple(series),
                title=title,
                scales={"x": {"time": False}, "y": {"auto": True}},
                aspect=2.0,
            )
            buf.dirty = False
            self.plots.append((buf, handle))
        self._fresh_until = time.monotonic() + FRESH_DELAY

    def clear(self) -> None:
        for buf, _ in self.plots:
            buf.clear()

    def add(self, frame: Frame, always: bool = False) -> None:
        """Sample ``frame`` into every plot (``always``: even if it has that time)."""
        for buf, _ in self.plots:
            if always or not buf.t or buf.t[-1] != frame.t:
                buf.add(frame)

    def send(self, all_plots: bool = False) -> None:
        """Upload one changed plot (round-robin), or every changed one."""
        if not self.plots or time.monotonic() < self._fresh_until:
            return
        if all_plots:
            for buf, handle in self.plots:
                if buf.dirty:
                    fast_set(handle, "data", buf.data())
                    buf.dirty = False
            return
        for _ in range(len(self.plots)):
            self._rr = (self._rr + 1) % len(self.plots)
            buf, handle = self.plots[self._rr]
            if buf.dirty:
                fast_set(handle, "data", buf.data())
                buf.dirty = False
                return


__all__ = ["PlotBuffer", "PlotPanel", "units_of"]
