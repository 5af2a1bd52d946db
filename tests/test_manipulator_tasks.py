"""Numbers, solution and stepper of C2.1-C2.6: lessons/mechanics/manipulators/tasks.py."""

from __future__ import annotations

import math

import analyzer_lab.lessons.mechanics.manipulators.tasks as tasks
import numpy as np
import pytest
from analyzer_lab.lessons.mechanics.self_study_2 import LESSON


def _solution(preset: str, **values: object) -> tasks.Solution:
    params = LESSON.resolve(values, preset=preset)
    return tasks.Solution(params, 0.0, tasks.initial_state(params, tasks.model_of(params)))


def test_every_task_observes_declared_series() -> None:
    declared = {s.name for s in tasks.SERIES}
    for preset in LESSON.presets:
        params = LESSON.resolve(preset=preset.name)
        assert tasks.series_names(params) <= declared


def test_c21_moments_in_every_reading() -> None:
    phi = np.array([0.0, math.pi / 8, math.pi, 5 * math.pi])
    b = LESSON.resolve(preset="c2-1b")
    assert np.allclose(tasks.c21_moments(b, phi)[1], 0.1 * phi)
    const = LESSON.resolve(preset="c2-1b-constant")
    assert np.allclose(tasks.c21_moments(const, phi)[1], 0.1)
    expected = {
        "c2-1c": [0.0, math.pi / 4, 2 * math.pi, 8 * math.pi],
        "c2-1c-constants": [2.0, 2.0, 2.0, 8.0],
        "c2-1c-switch-pi-4": [0.0, math.pi / 4, 8 * math.pi, 8 * math.pi],
    }
    for preset, m_g in expected.items():
        got_g, got_c = tasks.c21_moments(LESSON.resolve(preset=preset), phi)
        assert np.allclose(got_g, m_g) and np.allclose(got_c, 0.1 * np.sin(phi))


def test_solution_is_the_same_however_it_is_asked() -> None:
    t = np.linspace(0.0, 2.5, 91)  # three segments
    whole = _solution("c2-3c")(t)
    one_by_one = _solution("c2-3c")
    again = np.vstack([one_by_one(np.array([tk])) for tk in t])
    assert np.array_equal(whole, again)


def test_solution_holds_at_phi_k_and_says_so() -> None:
    solution = _solution("c2-1a")
    Y = solution(np.array([0.1, 0.3, 5.0]))
    assert solution.reached and solution.stop == pytest.approx(math.sqrt(math.pi * 0.01), abs=1e-9)
    assert Y[1, 0] == pytest.approx(math.pi, abs=1e-9) and np.array_equal(Y[1], Y[2])
    assert solution.message(0.1) == "" and "180 deg" in solution.message(0.3)


def test_solution_stops_at_a_non_finite_force() -> None:
    solution = _solution("c2-2a", F_g="1/(t-0.5)")
    Y = solution(np.array([0.25, 0.75]))
    assert np.all(np.isfinite(Y[0])) and np.all(np.isnan(Y[1]))
    assert 0.49 < solution.stop <= 0.5 and "integration stopped" in solution.message(0.75)
    assert np.all(np.isfinite(solution.last))


def test_stepper_after_a_failure_draws_the_last_state_and_restarts_on_new_values() -> None:
    params = LESSON.resolve({"F_g": "1/(t-0.5)"}, preset="c2-2a")
    st = LESSON.stepper(params)
    f = st.advance(0.8)
    assert math.isnan(f.scalars["x"]) and "integration stopped" in f.message
    assert all(np.all(np.isfinite(p)) for p in f.points.values())
    st.set_params(LESSON.resolve(preset="c2-2a"))
    assert st.t == 0.0 and st.frame().message == ""
