"""Runs, frames and scene of the manipulator lesson: lessons/mechanics/manipulators/lesson.py."""

from __future__ import annotations

import time

import numpy as np
from analyzer_lab.lessons.mechanics.self_study_2 import LESSON


def test_run_on_the_sampling_grid_with_units_and_notes() -> None:
    run = LESSON.run(preset="c2-3a")
    assert np.allclose(np.diff(run.t), LESSON.sampling) and run.t[-1] == 5.0
    assert run.units["Q_phi"] == "N m" and run.units["S"] == "m"
    assert run.messages[0] == LESSON.notes(LESSON.resolve(preset="c2-3a"))[0].text
    assert run.metrics["n_coordinates"] == 2 and "S_end" in run.metrics


def test_frame_equals_the_run_and_is_cheap() -> None:
    params = LESSON.resolve(preset="c2-6c")
    run = LESSON.simulate(params, 1.0)
    st = LESSON.stepper(params)
    start = time.perf_counter()
    for _ in range(36):
        frame = st.advance(1 / 36)
    per_frame = (time.perf_counter() - start) / 36
    assert abs(frame.scalars["x_A"] - run.series["x_A"][-1]) < 1e-12
    assert per_frame < 0.05  # the segment's integration included


def test_scene_spans_the_motion() -> None:
    spec = LESSON.scene(LESSON.resolve(preset="c2-2a"))
    (lo, hi) = np.array(spec.bounds)
    run = LESSON.run(preset="c2-2a")
    assert lo[0] <= run.series["x"].min() and hi[1] >= run.series["y"].max()
    assert spec.planar and set(spec.moving_points) == {"M"}
