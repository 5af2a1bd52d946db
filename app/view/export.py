"""Export: a run as CSV or JSON with the lesson's declared series, or an HTML replay.

Two kinds of table: the run on the textbook's grid (t = 0, dt, 2 dt, ... with the
current values, computed afresh: the numbers a homework asks for) and the frames the
page played (every frame since the last reset, live edits included).
"""

from __future__ import annotations

import csv
import html
import io
import json
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.contract import Lesson, RunResult
from analyzer_lab.lessons.kit.formula import parse_number
from analyzer_lab.limits import Pacer, return_free_memory
from analyzer_lab.session.runlog import MAX_LOG
from analyzer_lab.session.session import LabError, Session
from analyzer_lab.view.replay import MAX_REPLAY_FRAMES

#: The download buttons' labels by export kind (English; each page shows its language's).
BUTTONS = {
    "csv": N_("Download CSV (grid)"),
    "json": N_("Download JSON (grid)"),
    "frames-csv": N_("Download CSV (frames)"),
    "html": N_("HTML replay"),
}
#: Most rows of a grid export (the step is refused below t_end / MAX_GRID_ROWS).
MAX_GRID_ROWS = 20001
#: Most values (rows x columns) in one CSV or JSON export (about 8 MB of CSV): a grid
#: step that gives more is refused; the frames of a longer run are thinned (every 2nd,
#: 3rd, ... frame) and the file and the page say so.
MAX_EXPORT_VALUES = 400_000
#: Lesson seconds a fresh stepper advances in one call while sampling the grid.
GRID_CHUNK = 1.0 / 36.0


def parse_step(text: str, t_end: float) -> float:
    """The grid step typed by the student (a number or a constant expression)."""
    try:
        step = parse_number(str(text))
    except ValueError as exc:
        raise LabError(f"grid step: {exc}") from None
    if not step > 0:
        raise LabError(f"grid step: must be positive, got {step:g}")
    if t_end / step + 1 > MAX_GRID_ROWS:
        raise LabError(
            f"grid step: {step:g} s gives more than {MAX_GRID_ROWS} rows up to t = {t_end:g} s;"
            f" the smallest step is {t_end / (MAX_GRID_ROWS - 1):.3g} s"
        )
    return step


def grid_end(s: Session) -> float:
    """Up to where the grid runs: the time played, or the lesson's t_end before play."""
    return float(s.frame.t) if s.frame.t > 0 else float(s.t_end)


def grid_run(s: Session, step: float | None = None) -> RunResult:
    """The run with the session's values sampled at t = 0, step, 2 step, ... (default
    step: the lesson's sampling); the same stepper the page plays, started afresh."""
    t_end = grid_end(s)
    grid = s.lesson.sample_grid(t_end, step)
    if len(grid) > MAX_GRID_ROWS:
        raise LabError(f"grid step: more than {MAX_GRID_ROWS} rows; choose a larger step")
    names = [x.name for x in s.lesson.series_for(s.params)]
    if len(grid) * (len(names) + 1) > MAX_EXPORT_VALUES:
        rows = MAX_EXPORT_VALUES // (len(names) + 1)
        raise LabError(
            f"grid step: {len(grid)} rows x {len(names) + 1} columns is more than"
            f" {MAX_EXPORT_VALUES} values; with these columns the smallest step is"
            f" {t_end / max(rows - 1, 1):.3g} s"
        )
    stepper = s.lesson.open(s.params, s.preset).stepper
    columns: dict[str, list[float]] = {n: [] for n in names}
    pace = Pacer()
    for tk in grid:
        pace()
        frame = stepper.frame()
        while tk - stepper.t > 1e-12 * max(1.0, abs(tk)):
            frame = stepper.advance(min(GRID_CHUNK, tk - stepper.t))
        for n in names:
            columns[n].append(float(frame.scalars.get(n, float("nan"))))
    result = RunResult(
        s.lesson.id,
        s.preset,
        s.raw_values(),
        grid,
        {n: np.asarray(v) for n, v in columns.items()},
        {"t_end": t_end, "step": float(grid[1] - grid[0]) if len(grid) > 1 else 0.0},
        [f"sampled on the grid t = 0, {grid[1] if len(grid) > 1 else 0:g}, ... {t_end:g} s"],
        {x.name: x.unit for x in s.lesson.series_for(s.params)},
    )
    return result


def export_run(
    s: Session, kind: str, step: float | None = None, language: Language = ENGLISH
) -> tuple[str, bytes]:
    """A file for ``kind``: ``csv``/``json`` on the grid, ``frames-csv``/``frames-json``
    of the played frames, ``html`` a replay (its captions in ``language``; the data
    machine-readable in every language).  Returns (file name, bytes)."""
    stem = f"analyzer-lab-{s.run_name()}"
    if kind in ("csv", "json"):
        result = grid_run(s, step)
    elif kind in ("frames-csv", "frames-json"):
        result = thinned(s.run_result())
        stem += "-frames"
    elif kind == "html":
        from analyzer_lab.view.replay import replay_html

        return stem + "-replay.html", replay_html(s, language).encode()
    else:
        raise LabError(f"unknown export {kind[:20]!r}")
    if kind.endswith("csv"):
        return stem + ".csv", paced_csv(result).encode()
    return stem + ".json", paced_json(result.to_json_dict()).encode()


def thinned(result: RunResult) -> RunResult:
    """The run with every k-th row only when it has more than :data:`MAX_EXPORT_VALUES`
    values (a note in its messages says so)."""
    cols = [k for k, v in result.series.items() if np.ndim(v) == 1 and len(v) == len(result.t)]
    values = len(result.t) * (len(cols) + 1)
    if values <= MAX_EXPORT_VALUES:
        return result
    k = int(np.ceil(values / MAX_EXPORT_VALUES))
    series = {
        name: (np.asarray(v)[::k] if name in cols else v) for name, v in result.series.items()
    }
    note = (
        f"every {k}{'nd' if k == 2 else 'rd' if k == 3 else 'th'} of {len(result.t)} frames"
        f" exported (at most {MAX_EXPORT_VALUES} values)"
    )
    return replace(
        result, t=np.asarray(result.t)[::k], series=series, messages=[*result.messages, note]
    )


def paced_csv(result: RunResult) -> str:
    """``result.to_csv()``, written with pauses (:class:`~analyzer_lab.limits.Pacer`)."""
    names = [k for k, v in result.series.items() if np.ndim(v) == 1 and len(v) == len(result.t)]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["t", *names])
    cols = [np.asarray(result.t, dtype=float)] + [
        np.asarray(result.series[n], dtype=float) for n in names
    ]
    pace = Pacer()
    for row in zip(*cols):
        w.writerow([repr(float(x)) for x in row])
        pace()
    return buf.getvalue()


#: JSON pieces (keys, numbers, brackets) written between two looks at the pacer.
JSON_SLICE = 512


def paced_json(data: Any) -> str:
    """``json.dumps(data, indent=1)`` (the same text), written in slices with pauses
    (:class:`~analyzer_lab.limits.Pacer`)."""
    parts: list[str] = []
    pace = Pacer()
    for k, part in enumerate(json.JSONEncoder(indent=1).iterencode(data)):
        parts.append(part)
        if k % JSON_SLICE == 0:
            pace()
    return "".join(parts)


class ExportPanel:
    """The Export tab of one page: the grid step and the download buttons."""

    def __init__(
        self,
        gui: Any,
        guard: Callable[[Callable[[Any], None]], Callable[[Any], None]],
        session: Callable[[], Session],
        client: Any,
        language: Language = ENGLISH,
    ) -> None:
        self.session = session
        self.client = client
        self.language = language
        tr = language.gettext
        grid, frames = self._notes(language)
        self.grid_note = gui.add_html(grid)
        self.grid_step = gui.add_text(self._step_label(language), initial_value="")
        #: the download buttons by kind, in the order shown
        self.buttons: dict[str, Any] = {}
        for kind in ("csv", "json"):
            self.buttons[kind] = gui.add_button(tr(BUTTONS[kind]))
        self.frames_note = gui.add_html(frames)
        for kind in ("frames-csv", "html"):
            self.buttons[kind] = gui.add_button(tr(BUTTONS[kind]))
        for kind, button in self.buttons.items():
            button.on_click(guard(lambda e, k=kind: self.export(k)))

    @staticmethod
    def _step_label(language: Language) -> str:
        return language.gettext("grid step [{unit}]").format(unit=language.unit("s"))

    @staticmethod
    def _notes(language: Language) -> tuple[str, str]:
        """The notes above the grid's and the frames' buttons (HTML)."""
        tr = language.gettext
        grid = tr(
            "On the textbook's grid: t = 0, step, 2 step, ... up to the time played,"
            " with the current values."
        )
        frames = tr(
            "Every frame played since the last reset (at most {rows} rows: a longer run keeps"
            " every 2nd, 4th, ... frame; the replay at most {frames} frames, thinned the same"
            " way):"
        ).format(rows=MAX_LOG, frames=MAX_REPLAY_FRAMES)
        note = '<div style="font-size:0.9em">{}</div>'
        return note.format(html.escape(grid, quote=False)), note.format(
            html.escape(frames, quote=False)
        )

    def set_language(self, language: Language) -> None:
        """Write the tab's notes and labels in ``language``."""
        self.language = language
        for note, content in zip(
            (self.grid_note, self.frames_note), self._notes(language), strict=True
        ):
            if note.content != content:
                note.content = content
        labels = [(self.grid_step, self._step_label(language))]
        labels += [(self.buttons[k], language.gettext(v)) for k, v in BUTTONS.items()]
        for widget, label in labels:
            if widget.label != label:
                widget.label = label

    def show_default_step(self, lesson: Lesson, t_end: float) -> None:
        """The lesson's own sampling (or t_end / 100) as the proposed step."""
        self.grid_step.value = f"{lesson.sampling or t_end / 100.0:g}"

    def export(self, kind: str) -> None:
        """Send the run (grid or frames) as CSV/JSON, or the replay, as a download."""
        s = self.session()
        text = self.language.read_decimal(str(self.grid_step.value).strip())
        step = parse_step(text, grid_end(s)) if text else None
        name, data = export_run(s, kind, step, self.language)
        self.client.send_file_download(name, data, save_immediately=True)
        size = len(data)
        del data
        return_free_memory()
        tr = self.language.gettext
        fewer = (
            tr("; a long run: not every frame is in it (see the file's notes)")
            if kind.startswith("frames")
            and (
                s.log.stride > 1
                or len(s.log) * (len(s.lesson.series_for(s.params)) + 1) > MAX_EXPORT_VALUES
            )
            else ""
        )
        s.notify(
            tr("exported {name} ({size} kB{fewer})").format(
                name=name, size=self.language.number(size / 1024, ".1f"), fewer=fewer
            )
        )
