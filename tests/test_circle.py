"""Problem 1.2: undetermined coefficients (1.38)-(1.39), the circle analyzer (1.40)-(1.41)."""

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.circle import LESSON, RADIUS_MODES
from analyzer_lab.lessons.kit.contract import ParamError


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_runs(preset):
    res = LESSON.run(preset)
    for k in ("x", "y", "z", "vx", "vy", "vz"):
        assert res.series[k].shape == res.t.shape and np.all(np.isfinite(res.series[k]))


@pytest.mark.parametrize("u", ["1", "t", "t^2", "sin(t)"])
def test_radius_is_start_distance(u):
    res = LESSON.run(None, {"u": u, "x0": -1.5, "y0": 2.0}, t_end=4.0)
    r = np.hypot(res.series["x"], res.series["y"])
    assert np.max(np.abs(r - 2.5)) < 1e-12


def test_u_t_angle_is_t_squared_over_2():
    res = LESSON.run("u-t", t_end=2.0)
    ang = -np.unwrap(np.arctan2(res.series["y"], res.series["x"]))
    assert ang[-1] - ang[0] == pytest.approx(2.0, abs=1e-10)


def test_explicit_radius_branches():
    plus = LESSON.resolve({"radius_mode": RADIUS_MODES[1], "R": 5, "x0": 3})
    minus = LESSON.resolve({"radius_mode": RADIUS_MODES[2], "R": 5, "x0": 3})
    assert LESSON.start_points(plus)[0] == pytest.approx([3, 4])
    assert LESSON.start_points(minus)[0] == pytest.approx([3, -4])
    with pytest.raises(ParamError):
        LESSON.resolve({"radius_mode": RADIUS_MODES[2], "R": 2, "x0": 3})


def test_family_fig_1_12():
    res = LESSON.run("fig-1.12")
    for k in range(1, 6):
        sfx = "" if k == 1 else f"_{k}"
        assert np.allclose(
            np.hypot(res.series["x" + sfx], res.series["y" + sfx]), float(k), atol=1e-12
        )


def test_stepper_and_scene():
    params = LESSON.resolve(preset="fig-1.13")
    st = LESSON.stepper(params)
    f = st.advance(np.pi)
    assert f.points["point"][0, :2] == pytest.approx([-3, -4], abs=1e-10)
    st.set_params(LESSON.resolve({"u": "2"}, preset="fig-1.13"))
    f = st.advance(np.pi / 2)
    assert f.points["point"][0, :2] == pytest.approx([3, 4], abs=1e-10)
    assert st.reset().points["point"][0, :2] == pytest.approx([3, 4])
    sc = LESSON.scene(params)
    assert sc.planar and np.all(np.isfinite(np.array(sc.bounds)))


def test_claims_pass():
    for c in LESSON.claims():
        r = c.check()
        assert r.passed, (c.id, r)


def test_declarations():
    assert LESSON.modes == ("radius_mode", "digital") and LESSON.family == "family"
    assert LESSON.declaration_errors() == []
    notes = LESSON.notes(LESSON.resolve({"x0": 0, "y0": 0}))
    assert notes and "centre" in notes[0].text
    assert LESSON.run(None, {"x0": 0, "y0": 0}, t_end=1.0).messages == [notes[0].text]
