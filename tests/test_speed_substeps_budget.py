"""The constant-speed analyzer's substeps are charged as they run: one step cut into
thousands of substeps (V(t) = 1e4 typed in ``varying-controls``) pauses where a live
budget runs out and goes on from there, with the numbers of an unbudgeted run."""

from __future__ import annotations

import gc
import time

from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.lessons.kit.budget import work_budget

BUDGET = 0.005  # CPU seconds per frame, as a session's tick gives


def test_a_step_of_thousands_of_substeps_keeps_every_frame_within_its_budget() -> None:
    lesson = get_lesson("sphere-constant-speed")
    stepper = lesson.open({"V": "1e4"}, "varying-controls").stepper
    worst, frames = 0.0, 0
    # a collection of the whole test process's heap (hundreds of MB when the suite ran
    # before) is not the stepper's work: it is left out of the frames measured
    gc.collect()
    gc.disable()
    try:
        start = time.thread_time()
        while stepper.t <= 0.0 and time.thread_time() - start < 60.0:
            used = time.thread_time()
            with work_budget(BUDGET):
                stepper.advance(1 / 36)
            worst = max(worst, time.thread_time() - used)
            frames += 1
    finally:
        gc.enable()
    # one Newton-solved substep past the budget at most (a few milliseconds), never a
    # whole step (seconds) or a block of steps (a minute)
    assert worst < BUDGET + 0.05, worst
    assert frames > 20  # the first step alone is many frames' work
    assert stepper.t > 0.0  # and the clock moves on once it is done


def test_paused_substeps_give_the_numbers_of_an_unpaused_run() -> None:
    lesson = get_lesson("sphere-constant-speed")
    paused = lesson.open({"V": "40", "h": "0.0625"}, "varying-controls").stepper
    whole = lesson.open({"V": "40", "h": "0.0625"}, "varying-controls").stepper
    calls = 0
    for target in (0.0625, 0.15625, 0.25, 0.3125):  # nodes (h = 1/16) and between
        while paused.t < target:
            with work_budget(0.0):  # spent at once: every call pauses after one substep
                paused.advance(target - paused.t)
            calls += 1
        whole.advance(target - whole.t)
        assert paused.t == whole.t == target
        got, want = paused.frame().scalars, whole.frame().scalars
        assert [got[n] for n in ("x", "y", "z")] == [want[n] for n in ("x", "y", "z")]
    assert calls > 8  # it did pause
