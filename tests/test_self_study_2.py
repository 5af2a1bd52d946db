"""Self-study tasks C2.1-C2.6: lessons/self_study_2.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lessons.catalog import get_lesson
from lessons.core.contract import DerivationStep, ParamError
from lessons.self_study_2 import LESSON, TASKS

PRESETS = [p.name for p in LESSON.presets]


def test_catalog_and_every_task_has_a_preset() -> None:
    assert get_lesson("self-study-2") is not None
    assert {LESSON.preset(p).values["task"] for p in PRESETS} == set(TASKS)


def test_every_claim_passes() -> None:
    for claim in LESSON.claims():
        r = claim.check()
        assert r.passed, (claim.id, r.expected, r.got)


@pytest.mark.parametrize("preset", PRESETS)
def test_preset_runs_and_draws(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    run = LESSON.run(preset=preset)
    model = LESSON.model(params)
    for name in model.coords:
        assert run.series[name].shape == run.t.shape and np.all(np.isfinite(run.series[name]))
    for k in ("q1", "v1", "Q1"):
        assert run.series[k].shape == run.t.shape
    steps = LESSON.derivation(params)
    assert all(isinstance(s, DerivationStep) and s.source for s in steps)
    assert any(s.title.startswith("Equations") for s in steps)
    scene = LESSON.scene(params)
    assert np.all(np.isfinite(np.array(scene.bounds)))
    st = LESSON.stepper(params)
    f = st.advance(0.02)
    assert {b.name for b in scene.bodies} == set(f.poses)
    assert set(scene.moving_points) == set(f.points)
    for pos, quat in f.poses.values():
        assert np.all(np.isfinite(pos)) and abs(np.linalg.norm(quat) - 1) < 1e-12


def test_textbook_numbers_in_presets() -> None:
    a = LESSON.resolve(preset="c2-1a")
    assert (a["l_OM"], a["m1"], a["J0"]) == (0.2, 0.4, 0.01)
    b2 = LESSON.resolve(preset="c2-2b")
    assert (b2["m"], b2["l_AM"], b2["F_g"].text, b2["F_c"].text) == (0.5, 0.2, "2*sin(t)", "0")
    assert LESSON.resolve(preset="c2-2c")["F_c"].text == "t"
    assert LESSON.preset("c2-2b").t_end == 10.0 and LESSON.preset("c2-2c").t_end == 10.0


def test_c21_times_to_180_degrees() -> None:
    run = LESSON.run(preset="c2-1a")
    assert run.metrics["t_180"] == pytest.approx(math.sqrt(math.pi * 0.01), abs=1e-8)
    assert run.series["phi"][-1] == pytest.approx(math.pi, abs=1e-9)
    b = LESSON.run(preset="c2-1b", values={"inertia": "J0 + m1 l_OM^2"})
    assert round(b.metrics["t_180"], 4) == 0.2897
    const = LESSON.run(preset="c2-1b", values={"Mc_reading": "0.1"})
    assert const.metrics["t_180"] == pytest.approx(math.sqrt(2 * math.pi * 0.01 / 1.9), abs=1e-8)


def test_c21_vertical_plane_adds_gravity() -> None:
    flat = LESSON.run(preset="c2-1a", values={"inertia": "J0 + m1 l_OM^2"})
    up = LESSON.run(preset="c2-1a", values={"inertia": "J0 + m1 l_OM^2", "vertical": True})
    assert up.metrics["t_180"] > flat.metrics["t_180"]


def test_c22_closed_form_along_the_line() -> None:
    run = LESSON.run(preset="c2-2b")
    s = math.sqrt(2) * run.series["x"]
    assert np.max(np.abs(s - 4 * (run.t - np.sin(run.t)))) < 1e-7


def test_c24_axes_validation() -> None:
    with pytest.raises(ParamError) as err:
        LESSON.resolve({"axes": "xy"}, preset="c2-4a")
    assert err.value.name == "axes"
    assert LESSON.model(LESSON.resolve({"axes": "y"}, preset="c2-4a")).coords == ("y",)


def test_c26_constraints_hold() -> None:
    run = LESSON.run(preset="c2-6c")
    r = np.hypot(run.series["x_B"], run.series["y_B"])
    assert np.max(np.abs(r - 0.15)) < 1e-8
    fixed = LESSON.run(preset="c2-6b")
    assert np.all(fixed.series["x_B"] == -0.1) and np.all(fixed.series["y_A"] == 0.1)
    with pytest.raises(ParamError):
        LESSON.resolve({"c": 0.1, "d": 0.1}, preset="c2-6b")


def test_stepper_set_params_and_reset() -> None:
    params = LESSON.resolve(preset="c2-2a")
    st = LESSON.stepper(params)
    for _ in range(10):
        f = st.advance(0.1)
    assert f.t == pytest.approx(1.0)
    run = LESSON.simulate(params, t_end=1.0)
    assert f.scalars["q1"] == pytest.approx(run.series["x"][-1], rel=1e-7)
    st.set_params(LESSON.resolve({"F_g": "0"}, preset="c2-2a"))  # same task: state kept, force gone
    f2 = st.advance(0.1)
    assert f2.scalars["v1"] == pytest.approx(f.scalars["v1"], rel=1e-9)
    st.set_params(LESSON.resolve(preset="c2-1a"))  # another task: restart
    assert st.t == 0.0
    for _ in range(5):
        f3 = st.advance(0.1)
    assert "180 deg" in f3.message and f3.t == pytest.approx(math.sqrt(math.pi * 0.01), abs=1e-8)
    assert st.reset().t == 0.0


def test_odd_formula_is_reported_not_raised() -> None:
    run = LESSON.run(preset="c2-2a", values={"F_g": "1/(t-0.5)"}, t_end=1.0)
    assert any("F_g" in m for m in run.messages)
