"""Problem 1.5: constant speed on the sphere (1.58)-(1.59)."""

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.sphere_constant_speed import LESSON


def test_params():
    names = [p.name for p in LESSON.params]
    for n in ("R", "V", "direction", "u1", "u2", "u3", "x0", "y0", "z0"):
        assert n in names


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_short_run(preset):
    res = LESSON.run(preset, t_end=1.0)
    for k in ("x", "y", "z", "vx", "vy", "vz"):
        assert res.series[k].shape == res.t.shape and np.all(np.isfinite(res.series[k]))
    speed = np.sqrt(res.series["v2"])
    V = LESSON.resolve(preset=preset)["V"](res.t)
    moving = speed > 0
    assert np.max(np.abs(speed[moving] - V[moving])) < 1e-9
    assert res.metrics["invariant_drift_max"] < 1e-9


def test_speed_is_V_for_a_formula_profile():
    res = LESSON.run(
        None,
        {"V": "2 + t", "u1": "t", "u2": "1", "u3": "3", "x0": 0, "y0": 1, "z0": 0, "h": 0.05},
        t_end=2.0,
    )
    assert np.allclose(np.sqrt(res.series["v2"]), 2 + res.t, atol=1e-9)


def test_zero_field_holds_only_at_that_instant_and_says_so():
    params = LESSON.resolve(preset="example-1.3-zero-field")
    notes = LESSON.notes(params)
    assert len(notes) == 1 and "at that instant only" in notes[0].text
    assert notes[0].source == "(1.58)-(1.59)"
    res = LESSON.run("example-1.3-zero-field", t_end=0.5)
    assert res.series["v2"][0] == 0.0 and res.series["speed"][1] == pytest.approx(1.0)
    assert res.messages == [notes[0].text]
    assert np.hypot(res.series["y"][1], res.series["z"][1]) > 0.04  # moved in the first step
    st = LESSON.stepper(LESSON.resolve(preset="example-1.3-zero-field"))
    f0 = st.frame()
    assert "undefined" in f0.message
    f1 = st.advance(0.2)
    assert f1.message == "" and f1.scalars["v2"] == pytest.approx(1.0, abs=1e-9)


def test_direction_reverses():
    a = LESSON.stepper(LESSON.resolve(preset="fig-1.28")).frame().scalars
    b = LESSON.stepper(LESSON.resolve({"direction": "-"}, preset="fig-1.28")).frame().scalars
    assert (a["vx"], a["vy"], a["vz"]) == pytest.approx((-b["vx"], -b["vy"], -b["vz"]), abs=1e-15)


def test_stepper_set_params_reset_scene():
    params = LESSON.resolve(preset="fig-1.28")
    st = LESSON.stepper(params)
    st.advance(0.5)
    st.set_params(LESSON.resolve({"V": "3"}, preset="fig-1.28"))
    f = st.advance(0.1)
    assert f.scalars["v2"] == pytest.approx(9.0, rel=1e-9) and f.t == pytest.approx(0.6)
    assert st.reset().t == 0.0
    sc = LESSON.scene(params)
    assert np.all(np.isfinite(np.array(sc.bounds)))


def test_claims_pass():
    for c in LESSON.claims():
        r = c.check()
        assert r.passed, (c.id, r)


def test_held_for_the_whole_run_is_said_so():
    """u parallel to the start point's gradient and constant: the field stays zero there."""
    params = LESSON.resolve({"u1": "0", "u2": "0", "u3": "2"}, preset="fig-1.28")
    assert "for the whole run" in LESSON.notes(params)[0].text
    res = LESSON.simulate(params, 1.0)
    assert np.all(res.series["speed"] == 0.0) and res.series["x"][-1] == 1.0
    assert res.metrics["held_samples"] == len(res.t)


def test_groups_modes_and_readout():
    assert [g.name for g in LESSON.groups] == ["mode", "surface", "controls", "initial", "method"]
    assert LESSON.modes == ("direction",) and LESSON.param("direction").group == "mode"
    assert LESSON.group("method").expanded is False
    assert LESSON.readout == ("x", "y", "z", "speed", "v2", "drift")
    assert LESSON.declaration_errors() == []


@pytest.mark.parametrize("preset", ["varying-controls", "example-1.3-zero-field"])
def test_order_12_agrees_with_the_default_and_its_stepper_with_its_run(preset):
    """The integrator choice gauss-legendre-6 at the largest step, twice the presets': the
    same curve as order 6 at h = 0.001, speed V, F to round-off; live frames read the run."""
    params = LESSON.resolve({"integrator": "gauss-legendre-6", "h": 0.1}, preset=preset)
    res = LESSON.simulate(params, 3.0)
    ref = LESSON.simulate(LESSON.resolve({"h": 0.001}, preset=preset), 3.0)
    pick = np.searchsorted(ref.t, res.t - 1e-12)
    assert np.allclose(ref.t[pick], res.t)
    for c in "xyz":
        assert np.abs(res.series[c] - ref.series[c][pick]).max() < 1e-11
    assert np.abs(res.series["speed"][1:] - 1.0).max() < 1e-12
    assert res.metrics["invariant_drift_max"] < 1e-15
    st = LESSON.stepper(params)
    frame = st.advance(1.0)
    assert res.t[10] == pytest.approx(1.0)
    assert frame.scalars["x"] == pytest.approx(res.series["x"][10], abs=1e-12)
