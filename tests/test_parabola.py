"""Problem 1.1: the parabola analyzer (1.33), the textbook's family λ = 0.05, 0.1, 0.5."""

import json

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.parabola import LESSON, TABLE
from analyzer_lab.lessons.kit.contract import ParamError


def test_params_are_the_textbooks():
    names = [p.name for p in LESSON.params]
    assert names[:7] == ["lambda", "omega", "a12", "a13", "a23", "x0", "y0"]


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_runs_with_series(preset):
    res = LESSON.run(preset)
    for k in ("x", "y", "z", "vx", "vy", "vz"):
        assert res.series[k].shape == res.t.shape
        assert np.all(np.isfinite(res.series[k]))
    assert np.all(res.series["z"] == 0) and np.all(res.series["vz"] == 0)
    json.dumps(res.to_json_dict())


@pytest.mark.parametrize("lam", [0.05, 0.1, 0.5])
def test_closed_form_and_a33(lam):
    res = LESSON.run(f"lambda-{lam:g}")
    t = res.t
    exact = (
        np.array([4.0, 10.0])
        + t[:, None] * np.array(TABLE[lam]["v0"])
        + 0.5 * t[:, None] ** 2 * np.array(TABLE[lam]["Av0"])
    )
    assert np.allclose(np.stack([res.series["x"], res.series["y"]], 1), exact, rtol=0, atol=1e-9)
    assert res.metrics["a33"] == pytest.approx(TABLE[lam]["a33"], abs=1e-9)
    assert (res.metrics["x_end"], res.metrics["y_end"]) == pytest.approx(
        TABLE[lam]["X10"], abs=1e-8
    )
    assert res.metrics["a11"] == pytest.approx(lam * 0.5) and res.metrics["a22"] == pytest.approx(
        0.5 / lam
    )


def test_family_series_and_invariant():
    res = LESSON.run("figs-1.8-1.10")
    assert {"x_2", "y_2", "x_3", "y_3"} <= set(res.series)
    assert res.series["x_3"][-1] == pytest.approx(299.0, abs=1e-8)
    assert res.metrics["invariant_drift_rel"] < 1e-13


def test_omega_enters_squared():
    a = LESSON.run("lambda-0.5", {"omega": 2.0}, t_end=1.0)
    # ω² = 4: the same path as ω = 1 at four times the time
    b = LESSON.run("lambda-0.5", {"omega": 1.0}, t_end=4.0)
    assert a.series["x"][-1] == pytest.approx(b.series["x"][-1], rel=1e-12)


def test_bad_lambda_refused():
    with pytest.raises(ParamError):
        LESSON.resolve({"lambda": 0})


def test_stepper_scene_claims():
    params = LESSON.resolve(preset="lambda-0.5")
    st = LESSON.stepper(params)
    f = st.advance(1.0)
    assert f.points["point"][0, :2] == pytest.approx([4 + 7 + 2.25, 10 + 1 - 1.125], abs=1e-10)
    st.set_params(LESSON.resolve({"lambda": 0.1}, preset="lambda-0.5"))
    f2 = st.advance(0.1)
    assert f2.t == pytest.approx(1.1) and f2.scalars["drift"] < 1e-12
    assert st.reset().t == 0.0
    sc = LESSON.scene(params)
    assert sc.planar and np.all(np.isfinite(np.array(sc.bounds)))
    for c in LESSON.claims():
        assert c.check().passed, c.id


def test_family_members_are_lambda_2_and_3():
    params = LESSON.resolve({"family": 2, "lambda": 0.3, "lambda_2": 0.7})
    assert LESSON.lambdas(params) == [0.3, 0.7]
    names = [s.name for s in LESSON.series_for(params)]
    assert "x_2" in names and "x_3" not in names and "x_dda" not in names
    with pytest.raises(ParamError, match="lambda_2"):
        LESSON.resolve({"family": 2, "lambda_2": 0})
    assert LESSON.family == "family" and LESSON.modes == ("digital",)
    assert LESSON.declaration_errors() == []


def test_frame_reads_its_velocities_once_and_equals_the_observation() -> None:
    params = LESSON.resolve(preset=LESSON.presets[0].name)
    st = LESSON.stepper(params)
    fr = st.advance(17 / 600.0)
    state = st.track.at(np.array([st.t]))
    assert state.v is None  # a fresh state: the observation computes the field itself
    full = LESSON.observation(params, [st.t], state)
    assert fr.scalars == {k: float(v[0]) for k, v in full.items()}
