"""Export: a run as CSV or JSON with the lesson's declared series, or an HTML replay.

Two kinds of table: the run on the textbook's grid (t = 0, dt, 2 dt, ... with the
current values, computed afresh: the numbers a homework asks for) and the frames the
page played (every frame since the last reset, live edits included).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

import numpy as np

from app.replay import MAX_REPLAY_FRAMES
from app.runlog import MAX_LOG
from app.session import LabError, Session
from lessons.core.contract import Lesson, RunResult
from lessons.core.formula import parse_number

#: Most rows of a grid export (the step is refused below t_end / MAX_GRID_ROWS).
MAX_GRID_ROWS = 20001
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
    stepper = s.lesson.stepper(s.params)
    names = [x.name for x in s.lesson.series_for(s.params)]
    columns: dict[str, list[float]] = {n: [] for n in names}
    for tk in grid:
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


def export_run(s: Session, kind: str, step: float | None = None) -> tuple[str, bytes]:
    """A file for ``kind``: ``csv``/``json`` on the grid, ``frames-csv``/``frames-json``
    of the played frames, ``html`` a replay.  Returns (file name, bytes)."""
    stem = f"analyzer-lab-{s.run_name()}"
    if kind in ("csv", "json"):
        result = grid_run(s, step)
    elif kind in ("frames-csv", "frames-json"):
        result = s.run_result()
        stem += "-frames"
    elif kind == "html":
        from app.replay import replay_html

        return stem + "-replay.html", replay_html(s).encode()
    else:
        raise LabError(f"unknown export {kind[:20]!r}")
    if kind.endswith("csv"):
        return stem + ".csv", result.to_csv().encode()
    return stem + ".json", json.dumps(result.to_json_dict(), indent=1).encode()


class ExportPanel:
    """The Export tab of one page: the grid step and the download buttons."""

    def __init__(
        self,
        gui: Any,
        guard: Callable[[Callable[[Any], None]], Callable[[Any], None]],
        session: Callable[[], Session],
        client: Any,
    ) -> None:
        self.session = session
        self.client = client
        gui.add_html(
            '<div style="font-size:0.9em">On the textbook\'s grid: t = 0, step, 2 step, ...'
            " up to the time played, with the current values.</div>"
        )
        self.grid_step = gui.add_text("grid step [s]", initial_value="")
        buttons = [("Download CSV (grid)", "csv"), ("Download JSON (grid)", "json")]
        for label, kind in buttons:
            gui.add_button(label).on_click(guard(lambda e, k=kind: self.export(k)))
        gui.add_html(
            '<div style="font-size:0.9em">Every frame played since the last reset (at most'
            f" {MAX_LOG} rows: a longer run keeps every 2nd, 4th, ... frame; the replay at most"
            f" {MAX_REPLAY_FRAMES} frames, thinned the same way):</div>"
        )
        for label, kind in (("Download CSV (frames)", "frames-csv"), ("HTML replay", "html")):
            gui.add_button(label).on_click(guard(lambda e, k=kind: self.export(k)))

    def show_default_step(self, lesson: Lesson, t_end: float) -> None:
        """The lesson's own sampling (or t_end / 100) as the proposed step."""
        self.grid_step.value = f"{lesson.sampling or t_end / 100.0:g}"

    def export(self, kind: str) -> None:
        """Send the run (grid or frames) as CSV/JSON, or the replay, as a download."""
        s = self.session()
        text = str(self.grid_step.value).strip()
        step = parse_step(text, grid_end(s)) if text else None
        name, data = export_run(s, kind, step)
        self.client.send_file_download(name, data, save_immediately=True)
        thinned = (
            f"; every {s.log.stride}{'nd' if s.log.stride == 2 else 'th'} frame of this long run"
            if kind.startswith("frames") and s.log.stride > 1
            else ""
        )
        s.notify(f"exported {name} ({len(data) / 1024:.1f} kB{thinned})")
