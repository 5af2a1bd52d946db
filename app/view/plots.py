"""Live plots: the lesson's declared plots as uPlot charts, with axis titles and units."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, Lesson, PlotSpec
from analyzer_lab.viser_boundary import fast_set

if TYPE_CHECKING:
    import viser

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
    """The whole run of one :class:`PlotSpec`'s series, decimated for the wire: at most
    ``capacity`` samples; when full, every other sample is dropped and samples are
    taken half as often, so the plot always spans t = 0 to now."""

    def __init__(self, spec: PlotSpec, capacity: int) -> None:
        self.spec = spec
        self.capacity = max(8, capacity - capacity % 2)
        self.t: list[float] = []
        self.values: dict[str, list[float]] = {name: [] for name in spec.series}
        self.stride = 1  # frames offered per sample kept
        self._offered = 0
        self.dirty = False

    def clear(self) -> None:
        self.t.clear()
        for v in self.values.values():
            v.clear()
        self.stride = 1
        self._offered = 0
        self.dirty = True

    def add(self, frame: Frame) -> None:
        self._offered += 1
        if self._offered % self.stride and self.t:
            return
        self.t.append(float(frame.t))
        for name, buf in self.values.items():
            v = frame.scalars.get(name, math.nan)
            buf.append(float(v) if v is not None and math.isfinite(float(v)) else math.nan)
        if len(self.t) > self.capacity:
            self.t[:] = self.t[::2]
            for buf in self.values.values():
                buf[:] = buf[::2]
            self.stride *= 2
        self.dirty = True

    def scale(self) -> int:
        """The power of ten the values are shown in (0 for ordinary sizes): a drift of
        1e-16 is plotted in units of 1e-16 so that its ticks read."""
        values = np.abs(np.asarray([x for v in self.values.values() for x in v], dtype=float))
        finite = values[np.isfinite(values)]
        top = float(finite.max()) if finite.size else 0.0
        if top == 0.0 or 1e-3 <= top < 1e5:
            return 0
        return int(math.floor(math.log10(top)))

    def data(self, exponent: int = 0) -> tuple[np.ndarray, ...]:
        if not self.t:
            return (np.zeros(1),) + tuple(np.zeros(1) for _ in self.values)
        k = 10.0**-exponent
        return (np.asarray(self.t, dtype=float),) + tuple(
            np.asarray(v, dtype=float) * k for v in self.values.values()
        )


class PlotPanel:
    """The lesson's plots in one page: buffers fed by frames, uploads round-robin."""

    def __init__(self, gui: viser.GuiApi, window: int) -> None:
        self.gui = gui
        self.window = window
        self.plots: list[tuple[PlotBuffer, Any]] = []
        self.units: list[str] = []
        self.exponents: list[int] = []
        self._rr = 0
        self._fresh_until = 0.0

    def build(self, lesson: Lesson) -> None:
        """Create the charts of ``lesson`` (inside the caller's folder): the series'
        names in the legend, t and the unit on the axes."""
        self.plots = []
        self.units = []
        self.exponents: list[int] = []
        for spec in lesson.plots:
            buf = PlotBuffer(spec, self.window)
            series = [{"label": "t"}] + [
                {"label": name, "stroke": PLOT_COLORS[i % len(PLOT_COLORS)], "width": 1.5}
                for i, name in enumerate(spec.series)
            ]
            units = spec.units or units_of(lesson, spec.series)
            handle = self.gui.add_uplot(
                buf.data(),
                tuple(series),
                title=spec.title,
                scales={"x": {"time": False}, "y": {"auto": True}},
                axes=({"label": "t [s]"}, {"label": units or "value"}),
                aspect=1.6,
            )
            buf.dirty = False
            self.plots.append((buf, handle))
            self.units.append(units)
            self.exponents.append(0)
        self._fresh_until = time.monotonic() + FRESH_DELAY

    def _upload(self, k: int) -> None:
        buf, handle = self.plots[k]
        exponent = buf.scale()
        if exponent != self.exponents[k]:
            self.exponents[k] = exponent
            label = self.units[k] or "value"
            if exponent:
                label = f"× 1e{exponent} {self.units[k]}".strip()
            handle.axes = ({"label": "t [s]"}, {"label": label})
        fast_set(handle, "data", buf.data(exponent))
        buf.dirty = False

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
            for k, (buf, _) in enumerate(self.plots):
                if buf.dirty:
                    self._upload(k)
            return
        for _ in range(len(self.plots)):
            self._rr = (self._rr + 1) % len(self.plots)
            if self.plots[self._rr][0].dirty:
                self._upload(self._rr)
                return


__all__ = ["PlotBuffer", "PlotPanel", "units_of"]
