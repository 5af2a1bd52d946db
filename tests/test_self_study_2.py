"""Self-study tasks C2.1-C2.6: lessons/mechanics/self_study_2.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.lessons.kit.contract import DerivationStep, ParamError
from analyzer_lab.lessons.mechanics.manipulators.tasks import (
    MG_READINGS,
    TASKS,
    c21_moments,
    model_of,
)
from analyzer_lab.lessons.mechanics.self_study_2 import LESSON

PRESETS = [p.name for p in LESSON.presets]


def test_catalog_declarations_and_every_task_has_a_preset() -> None:
    assert get_lesson("self-study-2") is LESSON
    assert LESSON.declaration_errors() == []
    assert {LESSON.preset(p).values["task"] for p in PRESETS} == set(TASKS)
    assert LESSON.modes == ("task",) and LESSON.param("task").group == "mode"
    assert LESSON.param("Mg_reading").group == "c2_1" and LESSON.param("c26_QA").group == "c2_6"


def test_every_claim_passes() -> None:
    for claim in LESSON.claims():
        r = claim.check()
        assert r.passed, (claim.id, r.expected, r.got)


@pytest.mark.parametrize("preset", PRESETS)
def test_preset_runs_and_draws(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    run = LESSON.run(preset=preset)
    model = model_of(params)
    declared = [s.name for s in LESSON.series_for(params)]
    assert list(run.series) == declared and set(run.units) == set(declared)
    for name in (*model.coords, *(f"{c}_dot" for c in model.coords)):
        assert np.all(np.isfinite(run.series[name]))
    steps = LESSON.derivation(params)
    assert all(isinstance(s, DerivationStep) and s.source for s in steps)
    assert any(s.title.startswith("Equations") for s in steps)
    scene = LESSON.scene(params)
    assert np.all(np.isfinite(np.array(scene.bounds)))
    f = LESSON.stepper(params).advance(0.02)
    assert {b.name for b in scene.bodies} == set(f.poses)
    assert set(scene.moving_points) == set(f.points)
    for pos, quat in f.poses.values():
        assert np.all(np.isfinite(pos)) and abs(np.linalg.norm(quat) - 1) < 1e-12


def test_series_follow_the_task() -> None:
    z_only = {s.name for s in LESSON.series_for(LESSON.resolve(preset="c2-4a"))}
    assert z_only == {"z", "z_dot", "Q_z"}
    arm = {s.name: s.unit for s in LESSON.series_for(LESSON.resolve(preset="c2-3a"))}
    assert arm["Q_phi"] == "N m" and arm["Q_S"] == "N" and arm["phi_dot"] == "rad/s"
    circle = {s.name: s.unit for s in LESSON.series_for(LESSON.resolve(preset="c2-6c"))}
    assert circle["lambda_A"] == "N/m" and circle["constraint_error"] == "m"
    assert "lambda_1" not in circle


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
    assert any("180 deg" in m for m in run.messages)
    b = LESSON.run(preset="c2-1b", values={"inertia": "J0 + m1 l_OM^2"})
    assert round(b.metrics["t_180"], 4) == 0.2897
    const = LESSON.run(preset="c2-1b-constant")
    assert const.metrics["t_180"] == pytest.approx(math.sqrt(2 * math.pi * 0.01 / 1.9), abs=1e-8)
    assert round(const.metrics["t_180"], 4) == 0.1818


def test_c21_vertical_plane_adds_gravity() -> None:
    flat = LESSON.run(preset="c2-1a", values={"inertia": "J0 + m1 l_OM^2"})
    up = LESSON.run(preset="c2-1a", values={"inertia": "J0 + m1 l_OM^2", "vertical": True})
    assert up.metrics["t_180"] > flat.metrics["t_180"]
    alone = LESSON.resolve({"vertical": True}, preset="c2-1a")
    assert any(n.kind == "warning" and "J = J0" in n.text for n in LESSON.notes(alone))


@pytest.mark.parametrize(
    ("preset", "switch", "below", "above", "speed"),
    [
        ("c2-1c", 4 * math.pi, 8 * math.pi, 8 * math.pi, math.sqrt(1 + 3200 * math.pi**2)),
        ("c2-1c-constants", 4 * math.pi, 2.0, 8.0, math.sqrt(1600 * math.pi)),
        (
            "c2-1c-switch-pi-4",
            math.pi / 4,
            math.pi / 2,
            8 * math.pi,
            math.sqrt(1 + 200 * (math.pi**2 / 16 - 0.1 * (1 - math.cos(math.pi / 4)))),
        ),
    ],
)
def test_c21c_readings_of_m_g(
    preset: str, switch: float, below: float, above: float, speed: float
) -> None:
    """Each reading of M_g: its jump at the switch angle, and the energy integral
    J phi'^2/2 = J phi'(0)^2/2 + integral of (M_g - M_c) dphi (J = J0 = 0.01) along the run
    up to the switch, which gives the speed there."""
    params = LESSON.resolve(preset=preset)
    slope, const, _, _ = MG_READINGS[params["Mg_reading"]]
    jump = c21_moments(params, np.array([switch, switch * (1 + 1e-12)]))[0]
    assert jump == pytest.approx([below, above], abs=1e-9)
    run = LESSON.run(preset=preset)
    phi, rate = run.series["phi"], run.series["phi_dot"]
    before = phi <= switch
    work = slope * phi**2 / 2 + const * phi - 0.1 * (1 - np.cos(phi))
    w0 = params["phidot0"]
    assert np.allclose(rate[before] ** 2, w0**2 + 2 * work[before] / 0.01, rtol=1e-8)
    w_switch = slope * switch**2 / 2 + const * switch - 0.1 * (1 - math.cos(switch))
    assert math.sqrt(w0**2 + 2 * w_switch / 0.01) == pytest.approx(speed, rel=1e-12)
    printed = {"c2-1c": 177.718, "c2-1c-constants": 70.898, "c2-1c-switch-pi-4": 10.886}
    assert speed == pytest.approx(printed[preset], abs=1e-3)


def test_c21c_start_at_rest_depends_on_the_reading() -> None:
    still = LESSON.run(preset="c2-1c", values={"phidot0": 0.0}, t_end=0.5)
    assert np.all(still.series["phi"] == 0.0)
    assert any("equilibrium" in m for m in still.messages)
    moves = LESSON.run(preset="c2-1c-constants", t_end=0.1)
    assert 0.99 < moves.series["phi"][-1] < 100 * 0.1**2  # M_g alone: 2/0.01 t^2 / 2 = 1 rad
    assert LESSON.resolve(preset="c2-1c-constants")["Mg_reading"] == list(MG_READINGS)[1]


def test_c22_closed_form_along_the_line() -> None:
    run = LESSON.run(preset="c2-2b")
    assert np.max(np.abs(run.series["s"] - 4 * (run.t - np.sin(run.t)))) < 1e-7
    assert np.allclose(run.series["y"], run.series["x"] + 1.0)


def test_c24_axes_validation() -> None:
    with pytest.raises(ParamError) as err:
        LESSON.resolve({"axes": "xy"}, preset="c2-4a")
    assert err.value.name == "axes"
    assert model_of(LESSON.resolve({"axes": "y"}, preset="c2-4a")).coords == ("y",)


def test_c26_constraints_hold() -> None:
    run = LESSON.run(preset="c2-6c")
    r = np.hypot(run.series["x_B"], run.series["y_B"])
    assert np.max(np.abs(r - 0.15)) < 1e-8
    assert np.max(run.series["constraint_error"]) < 1e-8
    fixed = LESSON.run(preset="c2-6b")
    assert np.all(fixed.series["x_B"] == -0.1) and np.all(fixed.series["y_A"] == 0.1)
    with pytest.raises(ParamError) as err:
        LESSON.resolve({"c": 0.1, "d": 0.1}, preset="c2-6b")
    assert err.value.name == "c"


def test_stepper_set_params_and_reset() -> None:
    params = LESSON.resolve(preset="c2-2a")
    st = LESSON.stepper(params)
    for _ in range(10):
        f = st.advance(0.1)
    assert f.t == pytest.approx(1.0)
    run = LESSON.simulate(params, t_end=1.0)
    assert f.scalars["x"] == pytest.approx(run.series["x"][-1], rel=1e-12)
    st.set_params(LESSON.resolve({"F_g": "0"}, preset="c2-2a"))  # same task: state kept
    f2 = st.advance(0.1)
    assert f2.scalars["x_dot"] == pytest.approx(f.scalars["x_dot"], rel=1e-9)
    assert f2.scalars["F_g"] == 0.0
    st.set_params(LESSON.resolve(preset="c2-1a"))  # another task: restart
    assert st.t == 0.0
    for _ in range(5):
        f3 = st.advance(0.1)
    assert "180 deg" in f3.message and f3.scalars["phi"] == pytest.approx(math.pi, abs=1e-9)
    assert st.reset().t == 0.0


def test_odd_formula_is_reported_not_raised() -> None:
    run = LESSON.run(preset="c2-2a", values={"F_g": "1/(t-0.5)"}, t_end=1.0)
    assert any("F_g" in m for m in run.messages)
    assert not np.isfinite(run.series["x"][-1])
    assert any(m.startswith("x is not defined from") for m in run.messages)
