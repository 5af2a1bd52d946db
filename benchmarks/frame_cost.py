"""Cost of one played frame per lesson: the stepper alone, first preset, one core.

    python -m benchmarks.frame_cost [--frames 360] [--lesson ID ...]

Each lesson's stepper is built for its first preset, warmed up for one second of
frames (tables, dense output and factorizations are built once per parameter set),
then ``--frames`` frames of 1/36 s are timed.  "50 x 36 fps" is the share of one core
that 50 pages playing that lesson would take for stepping alone.
"""

from __future__ import annotations

import argparse
import time

from lessons.catalog import all_lessons

FRAME = 1.0 / 36.0


def frame_cost(lesson_id: str, frames: int = 360) -> tuple[str, float]:
    """(preset, milliseconds per frame) for the lesson's first preset."""
    lesson = next(x for x in all_lessons() if x.id == lesson_id)
    preset = lesson.presets[0].name if lesson.presets else None
    params = lesson.resolve(preset=preset)
    stepper = lesson.stepper(params)
    dt = FRAME * lesson.time_scale
    for _ in range(36):
        stepper.advance(dt)
    t0 = time.perf_counter()
    for _ in range(frames):
        stepper.advance(dt)
    return preset or "(defaults)", 1e3 * (time.perf_counter() - t0) / frames


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.frame_cost", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--frames", type=int, default=360)
    ap.add_argument("--lesson", nargs="*", default=None)
    args = ap.parse_args(argv)
    ids = args.lesson or [x.id for x in all_lessons()]
    print("| lesson | preset | ms per frame | 50 x 36 fps |\n|---|---|---|---|")
    for lesson_id in ids:
        preset, ms = frame_cost(lesson_id, args.frames)
        print(f"| {lesson_id} | {preset} | {ms:.3f} | {ms * 50 * 36 / 10:.0f}% |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
