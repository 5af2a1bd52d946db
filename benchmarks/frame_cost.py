"""Cost of one played frame per lesson: what the server does per frame, first preset, one core.

    python -m benchmarks.frame_cost [--frames 360] [--lesson ID ...]

Each lesson is played in a real :class:`analyzer_lab.session.session.Session` (the object the server's
frame loop ticks): ``tick(1/36 s)`` advances the lesson time in the session's quanta
(:data:`analyzer_lab.session.session.TIME_QUANTUM`) through the stepper, which steps and observes (the
frame's points, vectors, poses and the scalars the view reads), and keeps the frame in
the run log; this is the time the server counts as stepping (``step_seconds``).  The
session is warmed up for one second of frames (tables, dense output and factorizations
are built once per parameter set), then ``--frames`` frames are timed three times in a row (CPU time of this process,
the least of the three: other processes on the machine do not count).  "50 x 36 fps" is
the share of one core that 50 pages playing that lesson would take for stepping alone.
"stepper only" is the same frames without the session (the lesson's own part).  The math
libraries run one thread per call, as in the server (:mod:`analyzer_lab.serve.threads`).
"""

from __future__ import annotations

import argparse
import time

from analyzer_lab.serve.threads import one_math_thread

one_math_thread()  # as the server runs (before numpy loads)

from analyzer_lab.lessons.catalog import all_lessons  # noqa: E402
from analyzer_lab.session.session import Session  # noqa: E402

FRAME = 1.0 / 36.0
#: timed runs of ``--frames`` frames each; the least CPU time is reported
REPEATS = 3


def frame_cost(lesson_id: str, frames: int = 360) -> tuple[str, float, float]:
    """(preset, ms per played frame, ms of it in the stepper) for the first preset."""
    lessons = all_lessons()
    lesson = next(x for x in lessons if x.id == lesson_id)
    preset = lesson.presets[0].name if lesson.presets else None
    session = Session(lessons, lesson_id, preset)
    session.pause_at_end = False
    session.play()
    for _ in range(36):
        session.tick(FRAME)
    inner = session.stepper
    spent = [0.0]

    class Timed:
        """The session's stepper, timed."""

        def __getattr__(self, name: str) -> object:
            return getattr(inner, name)

        def advance(self, dt: float) -> object:
            t0 = time.process_time()
            fr = inner.advance(dt)
            spent[0] += time.process_time() - t0
            return fr

    session.stepper = Timed()  # type: ignore[assignment]
    best, best_inner = float("inf"), float("inf")
    for _ in range(REPEATS):  # the least CPU time of a few runs: the machine may be busy
        spent[0] = 0.0
        t0 = time.process_time()
        for _ in range(frames):
            session.tick(FRAME)
        total = time.process_time() - t0
        if total < best:
            best, best_inner = total, spent[0]
    session.stepper = inner
    total = best
    spent[0] = best_inner
    return preset or "(defaults)", 1e3 * total / frames, 1e3 * spent[0] / frames


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.frame_cost", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--frames", type=int, default=360)
    ap.add_argument("--lesson", nargs="*", default=None)
    args = ap.parse_args(argv)
    ids = args.lesson or [x.id for x in all_lessons()]
    print("| lesson | preset | ms per frame | stepper only | 50 x 36 fps |\n|---|---|---|---|---|")
    for lesson_id in ids:
        preset, ms, inner = frame_cost(lesson_id, args.frames)
        print(f"| {lesson_id} | {preset} | {ms:.3f} | {inner:.3f} | {ms * 50 * 36 / 10:.0f}% |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
