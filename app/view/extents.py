"""What a preset's run covers: the box of its moving points and bodies from t = 0 to its
``t_end``, computed once ahead of time (``python -m analyzer_lab.view.extents``) and kept in
``preset_extents.json`` beside this module.  A page opening a preset frames its camera on
this box joined with the scene's, so the whole run is in view from the start; a run with
other values is framed on the scene and re-framed when it leaves the box
(:meth:`~analyzer_lab.view.scene.SceneRenderer.follow_run`)."""

from __future__ import annotations

import argparse
import functools
import json
import logging
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, Lesson

log = logging.getLogger(__name__)

#: The table of every preset's box, by lesson id and preset name.
EXTENTS_FILE = Path(__file__).resolve().parent / "preset_extents.json"
#: Frames sampled over a run (its trail is drawn from as many or fewer).
SAMPLES = 1500
#: CPU seconds one preset's run may take when the table is made; a longer one is left out
#: (its page frames the scene and follows the run).
RUN_BUDGET = 120.0
#: The table's key of a lesson's run with its default values (no preset).
DEFAULTS = ""


@dataclass(frozen=True)
class Extent:
    """A run's box: low and high corners (3,), and the lesson time it reached."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    t_end: float


def frame_points(frame: Frame) -> np.ndarray:
    """The finite positions of a frame's moving points and bodies, (N, 3)."""
    pts = [np.asarray(p, dtype=float).reshape(-1, 3) for p in frame.points.values()]
    pts += [np.asarray(pos, dtype=float).reshape(-1, 3) for pos, _ in frame.poses.values()]
    if not pts:
        return np.zeros((0, 3))
    run = np.concatenate(pts, axis=0)
    return run[np.all(np.isfinite(run), axis=1)]


def run_extent(lesson: Lesson, preset: str | None, budget: float = RUN_BUDGET) -> Extent | None:
    """Step ``preset``'s run (``None``: the defaults) to its ``t_end`` in :data:`SAMPLES` pieces and return the box
    of everything that moved (``None``: nothing moves, or the run took over ``budget``
    CPU seconds or stopped before its end)."""
    setup = lesson.open(None, preset)
    stepper = setup.stepper
    t_end = float(setup.t_end)
    piece = t_end / SAMPLES
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    start = time.process_time()
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        frame = stepper.frame()
        while True:
            run = frame_points(frame)
            if len(run):
                lo = np.minimum(lo, run.min(axis=0))
                hi = np.maximum(hi, run.max(axis=0))
            if stepper.t >= t_end * (1 - 1e-9):
                break
            if time.process_time() - start > budget:
                log.warning("%s %s: over %s CPU s at t = %g", lesson.id, preset, budget, stepper.t)
                return None
            t_before = stepper.t
            frame = stepper.advance(min(piece, t_end - stepper.t))
            if stepper.t <= t_before and not stepper.computing:
                return None
    if not np.all(np.isfinite(lo)):
        return None
    return Extent(tuple(map(float, lo)), tuple(map(float, hi)), t_end)  # type: ignore[arg-type]


def compute_table(lessons: Sequence[Lesson]) -> dict[str, dict[str, list[list[float]]]]:
    """Every preset's box of ``lessons``, and the defaults' under :data:`DEFAULTS` (the
    presets whose run has none are left out)."""
    table: dict[str, dict[str, list[list[float]]]] = {}
    for lesson in lessons:
        for preset in (None, *(p.name for p in lesson.presets)):
            extent = run_extent(lesson, preset)
            if extent is not None:
                key = DEFAULTS if preset is None else preset
                table.setdefault(lesson.id, {})[key] = [list(extent.lo), list(extent.hi)]
    return table


def table_text(table: dict[str, dict[str, list[list[float]]]]) -> str:
    """The table as JSON, a lesson a block and a run a line, corners to 9 digits."""

    def corner(c: list[float]) -> str:
        return "[" + ", ".join(format(v + 0.0, ".9g") for v in c) + "]"  # no -0

    blocks = []
    for lesson_id in sorted(table):
        runs = table[lesson_id]
        lines = [
            f"  {json.dumps(k)}: [{corner(b[0])}, {corner(b[1])}]" for k, b in sorted(runs.items())
        ]
        blocks.append(f" {json.dumps(lesson_id)}: {{\n" + ",\n".join(lines) + "\n }")
    return "{\n" + ",\n".join(blocks) + "\n}\n"


@functools.cache
def _table() -> dict[str, dict[str, list[list[float]]]]:
    try:
        return json.loads(EXTENTS_FILE.read_text())
    except (OSError, ValueError):
        log.exception("the presets' boxes were not read from %s", EXTENTS_FILE)
        return {}


def preset_extent(lesson_id: str, preset: str | None) -> tuple[np.ndarray, np.ndarray] | None:
    """The box ``preset``'s run (``None``: the defaults') covers, low and high corners,
    from the table; ``None`` for a run the table does not hold."""
    box = _table().get(lesson_id, {}).get(DEFAULTS if preset is None else preset)
    if box is None:
        return None
    return np.asarray(box[0], dtype=float), np.asarray(box[1], dtype=float)


def main(argv: Sequence[str] | None = None) -> int:
    from analyzer_lab.lessons.catalog import all_lessons, get_lesson

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=EXTENTS_FILE)
    parser.add_argument("lessons", nargs="*", help="lesson ids (default: every lesson)")
    args = parser.parse_args(argv)
    lessons = [get_lesson(i) for i in args.lessons] if args.lessons else list(all_lessons())
    start = time.perf_counter()
    table = compute_table(lessons)
    if args.lessons and args.out.exists():
        table = {**json.loads(args.out.read_text()), **table}
    args.out.write_text(table_text(table))
    count = sum(len(v) for v in table.values())
    print(f"{count} presets' boxes in {args.out} ({time.perf_counter() - start:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
