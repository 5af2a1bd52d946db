"""Live plots: the lesson's declared plots as uPlot charts of the whole run so far.

Each chart is drawn from the session's run log (every frame played, not a sample of
them), decimated on the server by min/max per pixel column
(:func:`~analyzer_lab.view.decimation.minmax_indices`), with the x axis spanning the run
so far.  A chart shows only the series the lesson defines for the current values; a
chart with none is not drawn, and one line above the charts names them.
"""

from __future__ import annotations

import html
import math
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.contract import Frame, Lesson, Params, PlotSpec
from analyzer_lab.session.runlog import RunLog
from analyzer_lab.view.decimation import minmax_indices
from analyzer_lab.view.notation import name_text, unit_text
from analyzer_lab.viser_boundary import fast_set

if TYPE_CHECKING:
    import viser

PLOT_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b")
#: seconds after the charts are created during which no data is sent (a busy browser
#: can take a while; an early update is reported as an update of a missing component)
FRESH_DELAY = 1.5
#: Pixel columns the run is decimated to (a chart in the panel is about 350 px wide).
COLUMNS = 360
#: The folder of the charts.
FOLDER = N_("Live plots (the whole run)")


def units_of(lesson: Lesson, names: Sequence[str]) -> str:
    """The plot's unit when all its series share one (from the lesson's declarations)."""
    units = {x.name: x.unit for x in lesson.series}
    found = {units.get(n, "") for n in names}
    return found.pop() if len(found) == 1 else ""


def chart_series(spec: PlotSpec, defined: Iterable[str]) -> tuple[str, ...]:
    """The series of ``spec`` that the run has (of the names ``defined``), in its order."""
    names = set(defined)
    return tuple(n for n in spec.series if n in names)


def defined_series(lesson: Lesson, params: Params, frame: Frame) -> frozenset[str]:
    """The series a run of ``lesson`` with ``params`` has: those the lesson declares for
    these values, and those its frames carry."""
    return frozenset(s.name for s in lesson.series_for(params)) | frozenset(frame.scalars)


def scale_of(columns: Sequence[np.ndarray]) -> int:
    """The power of ten the values are shown in (0 for ordinary sizes): a drift of
    1e-16 is plotted in units of 1e-16 so that its ticks read."""
    tops = [float(np.nanmax(np.abs(c))) for c in columns if c.size and np.isfinite(c).any()]
    finite = [x for x in tops if math.isfinite(x)]
    top = max(finite) if finite else 0.0
    if top == 0.0 or 1e-3 <= top < 1e5:
        return 0
    return int(math.floor(math.log10(top)))


@dataclass(frozen=True)
class ChartData:
    """What one chart draws: the times, the series (in units of 10^``exponent``) and the
    x range (the run so far)."""

    t: np.ndarray
    values: tuple[np.ndarray, ...]
    exponent: int
    x_range: tuple[float, float]

    def arrays(self) -> tuple[np.ndarray, ...]:
        return (self.t, *self.values)


def chart_data(
    log: RunLog, names: Sequence[str], columns: int = COLUMNS, min_span: float = 1.0
) -> ChartData:
    """The series ``names`` of the whole run ``log``, decimated to ``columns`` pixel
    columns by min/max; a series the log lacks is NaN (a gap).  A run of one instant
    spans ``min_span`` seconds."""
    t = log.t
    if not len(t):
        t = np.zeros(1)
    known = set(log.scalar_names) if len(log) else set()
    full = [log.scalar(n) if n in known else np.full(len(t), np.nan) for n in names]
    keep = minmax_indices(t, full, columns)
    kept_t = np.ascontiguousarray(t[keep])
    kept = [np.ascontiguousarray(v[keep]) for v in full]
    exponent = scale_of(kept)
    if exponent:
        kept = [v * 10.0**-exponent for v in kept]
    t0, t1 = float(kept_t[0]), float(kept_t[-1])
    if not t1 > t0:
        t1 = t0 + min_span
    return ChartData(kept_t, tuple(kept), exponent, (t0, t1))


def scales(data: ChartData) -> dict[str, Any]:
    """uPlot's scales: x fixed to the run so far, y fitted to the values."""
    return {"x": {"time": False, "range": data.x_range}, "y": {"auto": True}}


@dataclass
class Chart:
    """One chart on the page: its series and the log state it shows."""

    spec: PlotSpec
    names: tuple[str, ...]
    units: str
    handle: Any
    exponent: int = 0
    shown: tuple[int, int] | None = None  # (id of the log, its revision) uploaded


class PlotPanel:
    """The lesson's plots in one page: charts drawn from the session's run log,
    uploaded round-robin when the log has moved on."""

    def __init__(self, gui: viser.GuiApi, columns: int = COLUMNS) -> None:
        self.gui = gui
        self.columns = columns
        self.charts: list[Chart] = []
        #: the series of every chart (empty: not defined), as built
        self.layout: tuple[tuple[str, ...], ...] = ()
        self.note: Any = None
        self.missing: list[str] = []  # the titles of the charts not defined
        self.time_scale = 1.0
        self.language = ENGLISH  # the language of the charts' chrome, as built
        self._rr = 0
        self._fresh_until = 0.0

    @staticmethod
    def layout_for(lesson: Lesson, params: Params, frame: Frame) -> tuple[tuple[str, ...], ...]:
        """The series every chart of ``lesson`` shows for ``params`` (empty: none)."""
        defined = defined_series(lesson, params, frame)
        return tuple(chart_series(spec, defined) for spec in lesson.plots)

    def build(
        self,
        lesson: Lesson,
        params: Params,
        log: RunLog,
        frame: Frame,
        preset: str | None,
        language: Language = ENGLISH,
    ) -> Any:
        """Create the charts of ``lesson`` in a new folder (inside the caller's
        container), drawn from ``log``; returns the folder.  Charts without a series
        for these values are left out and named in one line above the others.  The
        titles are shown in ``language``."""
        self.charts = []
        self.layout = self.layout_for(lesson, params, frame)
        self.time_scale = lesson.time_scale
        self.language = language
        folder = self.gui.add_folder(language.gettext(FOLDER))
        title = language.lesson_text
        missing = [title(spec.title) for spec, names in zip(lesson.plots, self.layout) if not names]
        with folder:
            # first, so that the page says at once why a chart is not there
            self.note = (
                self.gui.add_html(_missing_html(missing, preset, language)) if missing else None
            )
            for spec, names in zip(lesson.plots, self.layout):
                if not names:
                    continue
                units = spec.units or units_of(lesson, names)
                data = chart_data(log, names, self.columns, lesson.time_scale)
                series = [{"label": "t"}] + [
                    {
                        "label": name_text(name, language.quantity),
                        "stroke": PLOT_COLORS[i % len(PLOT_COLORS)],
                        "width": 1.5,
                    }
                    for i, name in enumerate(names)
                ]
                handle = self.gui.add_uplot(
                    data.arrays(),
                    tuple(series),
                    title=title(spec.title),
                    scales=scales(data),
                    axes=self._axes(units, data.exponent),
                    aspect=1.6,
                )
                self.charts.append(Chart(spec, names, units, handle, data.exponent, _key(log)))
        self.missing = missing
        self._fresh_until = time.monotonic() + FRESH_DELAY
        return folder

    def show_preset(self, preset: str | None) -> None:
        """Say whether the charts left out are not defined for a preset or for values."""
        if self.note is not None:
            content = _missing_html(self.missing, preset, self.language)
            if self.note.content != content:
                self.note.content = content

    def _axes(self, units: str, exponent: int) -> tuple[dict[str, str], dict[str, str]]:
        """The axes' labels: time (``t [s]``, ``t [с]`` in Russian) and the values."""
        language = self.language
        return {"label": f"t [{language.unit('s')}]"}, {"label": self._y_label(units, exponent)}

    def _y_label(self, units: str, exponent: int) -> str:
        units = self.language.unit(unit_text(units))
        if exponent:
            return f"× 1e{exponent} {units}".strip()
        return units or self.language.gettext("value")

    def _upload(self, chart: Chart, log: RunLog) -> None:
        data = chart_data(log, chart.names, self.columns, self.time_scale)
        handle = chart.handle
        if data.exponent != chart.exponent:
            chart.exponent = data.exponent
            handle.axes = self._axes(chart.units, data.exponent)
        fast_set(handle, "data", data.arrays())
        fast_set(handle, "scales", scales(data))
        chart.shown = _key(log)

    def behind(self, log: RunLog) -> bool:
        """Whether a chart does not show ``log`` yet and may be sent now."""
        if not self.charts or time.monotonic() < self._fresh_until:
            return False
        key = _key(log)
        return any(chart.shown != key for chart in self.charts)

    def send(self, log: RunLog, all_plots: bool = False) -> None:
        """Upload one chart whose run moved on (round-robin), or every one."""
        if not self.charts or time.monotonic() < self._fresh_until:
            return
        key = _key(log)
        if all_plots:
            for chart in self.charts:
                if chart.shown != key:
                    self._upload(chart, log)
            return
        for _ in range(len(self.charts)):
            self._rr = (self._rr + 1) % len(self.charts)
            chart = self.charts[self._rr]
            if chart.shown != key:
                self._upload(chart, log)
                return


def _key(log: RunLog) -> tuple[int, int]:
    return id(log), log.revision


def _missing_html(titles: Sequence[str], preset: str | None, language: Language = ENGLISH) -> str:
    template = (
        N_("Not defined for this preset: {names}.")
        if preset
        else N_("Not defined for these values: {names}.")
    )
    names = ", ".join(f"“{t}”" for t in titles)
    text = language.gettext(template).format(names=names)
    return (
        f'<div class="al-plots-undefined" style="font-size:0.9em;color:#444">'
        f"{html.escape(text)}</div>"
    )


__all__ = [
    "COLUMNS",
    "ChartData",
    "PlotPanel",
    "chart_data",
    "chart_series",
    "defined_series",
    "scale_of",
    "units_of",
]
