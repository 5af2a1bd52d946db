"""Bodies and poses of C2.1-C2.6: lessons/mechanics/manipulators/scene.py."""

from __future__ import annotations

import math

import analyzer_lab.lessons.mechanics.manipulators.tasks as tasks
import numpy as np
import pytest
from analyzer_lab.lessons.mechanics.manipulators.scene import drawing, moving_points, poses
from analyzer_lab.lessons.mechanics.self_study_2 import LESSON


@pytest.mark.parametrize("task", tasks.TASKS)
def test_every_body_drawn_is_posed(task: str) -> None:
    preset = next(p.name for p in LESSON.presets if p.values["task"] == task)
    params = LESSON.resolve(preset=preset)
    model = tasks.model_of(params)
    bodies, _, markers = drawing(params, 0.05, -np.ones(3), np.ones(3))
    q = tasks.initial_state(params, model)[: model.n]
    posed = poses(params, model, q, tasks.constants(params, model))
    assert {b.name for b in bodies} == set(posed)
    assert set(moving_points(task)) <= set(model.points)
    assert markers[0].name == "O"


def test_link_of_c21_turns_with_phi() -> None:
    params = LESSON.resolve({"phi0": math.pi / 2}, preset="c2-1a")
    model = tasks.model_of(params)
    (position, wxyz) = poses(params, model, np.array([math.pi / 2]), [0.2, 0.01, 0.0, 0.0])["link"]
    assert np.allclose(position, 0.0)
    assert np.allclose(wxyz, [math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)])
