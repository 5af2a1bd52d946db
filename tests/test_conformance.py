"""One lesson, one truth: every lesson's live stepper and its headless run agree.

For every lesson and every preset the stepper is played the way the browser plays it
(frames of 1/36 s, the last one landing on a sample time) and its frame at that time is
compared with ``simulate`` at the same time: the same series names (the declared ones),
the same units, and the same values to 1e-9 relative to the series' size over the run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.lessons.kit.contract import Lesson

FRAME = 1.0 / 36.0
CASES = [(lesson, preset.name) for lesson in all_lessons() for preset in lesson.presets]


def _window(lesson: Lesson, preset: str) -> float:
    """The part of the preset's run compared: at most 2 s (enough for every kind of step)."""
    return min(lesson.preset_t_end(preset), 2.0)


@pytest.mark.parametrize("lesson", all_lessons(), ids=lambda lesson: lesson.id)
def test_declarations_are_consistent(lesson: Lesson) -> None:
    assert lesson.declaration_errors() == []
    assert lesson.series, "a lesson declares the series it observes"
    assert type(lesson).observe is not Lesson.observe, "a lesson implements observe()"
    for s in lesson.series:
        assert s.description, f"series {s.name} has no description"


@pytest.mark.parametrize(
    ("lesson", "preset"), CASES, ids=[f"{lesson.id}:{name}" for lesson, name in CASES]
)
def test_stepper_frame_equals_simulate(lesson: Lesson, preset: str) -> None:
    params = lesson.resolve(preset=preset)
    t_end = _window(lesson, preset)
    result = lesson.simulate(params, t_end)
    declared = lesson.series_for(params)
    names = [s.name for s in declared]
    assert list(result.series) == names
    assert result.units == {s.name: s.unit for s in declared}

    t = np.asarray(result.t)
    picks = sorted({len(t) // 3, (2 * len(t)) // 3, len(t) - 1})
    stepper = lesson.stepper(params)
    frame = stepper.frame()
    assert list(frame.scalars) == names
    for k in picks:
        target = float(t[k])
        while target - stepper.t > 1e-12 * max(1.0, abs(target)):
            frame = stepper.advance(min(FRAME, target - stepper.t))
        assert math.isclose(frame.t, target, rel_tol=1e-9, abs_tol=1e-12)
        assert list(frame.scalars) == names
        for name in names:
            column = np.asarray(result.series[name], dtype=float)
            want, got = float(column[k]), float(frame.scalars[name])
            if not math.isfinite(want):
                assert not math.isfinite(got), f"{name} at t = {target}: {got} vs {want}"
                continue
            finite = column[np.isfinite(column)]
            size = max(float(np.max(np.abs(finite))), 1e-300)
            assert abs(got - want) <= 1e-9 * size + 1e-12, (
                f"{name} at t = {target:g}: stepper {got!r}, simulate {want!r}"
            )


def test_run_json_names_units_like_the_declarations() -> None:
    lesson = next(lesson for lesson in all_lessons() if lesson.id == "sphere")
    data = lesson.run("example-1.1", t_end=1.0).to_json_dict()
    assert set(data["units"]) == set(data["series"])
