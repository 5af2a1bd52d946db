"""Problem 1.4 (sphere): presets, claims with numbers, live stepper, bad input."""

import numpy as np
import pytest

from lessons.core.contract import ParamError
from lessons.sphere import LESSON, V2_TABLE


def test_example_1_1_speed_and_circle():
    res = LESSON.run("example-1.1")
    assert res.t[-1] == pytest.approx(10.0)
    v2 = res.series["vx"] ** 2 + res.series["vy"] ** 2 + res.series["vz"] ** 2
    assert np.abs(v2 - 50.0).max() < 1e-9
    r = np.stack([res.series[c] for c in "xyz"], axis=1)
    assert np.abs(r.sum(axis=1) - 1.0).max() < 1e-10  # plane x + y + z = 1
    assert np.abs(np.linalg.norm(r - 1 / 3, axis=1) - np.sqrt(2 / 3)).max() < 1e-10


@pytest.mark.parametrize("preset", sorted(V2_TABLE))
def test_speed_tables(preset):
    res = LESSON.run(preset)
    idx = [int(np.argmin(np.abs(res.t - k))) for k in range(11)]
    assert res.series["v2"][idx] == pytest.approx(V2_TABLE[preset], abs=5e-4)


def test_example_1_2_speed_range():
    res = LESSON.run("example-1.2")
    assert res.metrics["v2_min"] == pytest.approx(23.09, abs=0.01)
    assert res.metrics["v2_max"] == pytest.approx(71.80, abs=0.01)


def test_example_1_4_family_of_heights():
    res = LESSON.run("example-1.4-xy")
    zs = [res.series[k] for k in res.series if k == "z" or k.startswith("z_")]
    assert len(zs) == 5
    assert max(float(np.ptp(z)) for z in zs) < 1e-12


def test_every_claim_passes():
    for claim in LESSON.claims():
        res = claim.check()
        assert res.passed, (claim.id, res.expected, res.got)


def test_stepper_live_change_and_reset():
    params = LESSON.resolve(preset="example-1.1")
    st = LESSON.stepper(params)
    f0 = st.frame()
    assert f0.t == 0 and np.allclose(f0.points["point"], [[1, 0, 0]])
    f1 = st.advance(0.5)
    assert f1.t == pytest.approx(0.5) and f1.scalars["v2"] == pytest.approx(50.0)
    st.set_params(LESSON.resolve({"u1": "t"}, "example-1.1"))
    f2 = st.advance(0.5)
    assert f2.t == pytest.approx(1.0)
    assert f2.scalars["v2"] != pytest.approx(50.0)  # the motion changed without a restart
    assert abs(np.linalg.norm(f2.points["point"]) - 1.0) < 1e-13
    assert st.reset().t == 0.0


@pytest.mark.parametrize(
    "values",
    [
        {"R": 0},
        {"R": "nan"},
        {"x0": "inf"},
        {"u1": "__import__('os')"},
        {"u2": "1/0"},
        {"u3": "log(t)"},
        {"family": 1000},
    ],
)
def test_bad_input_refused(values):
    with pytest.raises(ParamError):
        LESSON.resolve(values)


def test_start_off_surface_is_projected_with_message():
    res = LESSON.run(values={"x0": 3, "y0": 4, "z0": 0}, t_end=0.5)
    assert any("projected" in m for m in res.messages)
    assert (res.series["x"][0], res.series["y"][0]) == pytest.approx((0.6, 0.8))


def test_start_at_centre_is_refused():
    with pytest.raises(ParamError, match="cannot be put on the surface"):
        LESSON.prepare(LESSON.resolve({"x0": 0, "y0": 0, "z0": 0}))


def test_derivation_has_sources_and_reconstructed_tags():
    steps = LESSON.derivation(LESSON.resolve(preset="example-1.1"))
    sources = {s.source for s in steps}
    assert {"(1.52)", "(1.53)", "(1.54)", "(1.55)", "(1.56)", "(1.57)"} <= sources
    assert any(s.reconstructed for s in steps if s.source == "(1.54)")


def test_scene_has_surface_and_point():
    scene = LESSON.scene(LESSON.resolve(preset="example-1.1"))
    assert scene.meshes and len(scene.meshes[0].faces) > 100
    assert "point" in scene.moving_points
    assert np.all(np.isfinite(np.array(scene.bounds)))
