"""Problem 1.6: the ellipsoid analyzer (1.63), the level set through the start point."""

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.ellipsoid import EXTENTS, LESSON, R_END


def test_params():
    names = [p.name for p in LESSON.params]
    for n in ("a", "b", "c", "u1", "u2", "u3", "x0", "y0", "z0"):
        assert n in names


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_runs(preset):
    res = LESSON.run(preset)
    for k in ("x", "y", "z", "vx", "vy", "vz"):
        assert res.series[k].shape == res.t.shape and np.all(np.isfinite(res.series[k]))
    assert res.metrics["invariant_drift_rel"] < 1e-12


def test_worked_example_numbers():
    m = LESSON.run("example").metrics
    assert (m["x_end"], m["y_end"], m["z_end"]) == pytest.approx(R_END, abs=5e-5)
    assert (m["max_abs_x"], m["max_abs_y"], m["max_abs_z"]) == pytest.approx(EXTENTS, abs=2e-3)
    assert (m["semi_axis_x"], m["semi_axis_y"], m["semi_axis_z"]) == pytest.approx((10, 5, 1))


def test_start_sets_the_size():
    res = LESSON.run("semi-axes-100-50-10", t_end=3.0)
    m = res.metrics
    assert (m["semi_axis_x"], m["semi_axis_y"], m["semi_axis_z"]) == pytest.approx((100, 50, 10))
    G = (res.series["x"] / 100) ** 2 + (res.series["y"] / 50) ** 2 + (res.series["z"] / 10) ** 2
    assert np.max(np.abs(G - 1)) < 1e-12
    # scaling the start by 10 scales the whole path by 10 (the field is linear)
    small = LESSON.run(
        None, {"x0": 0, "y0": 5, "z0": 0, "u1": "5*t", "u2": "t/10", "u3": "5"}, t_end=3.0
    )
    assert np.allclose(res.series["x"], 10 * small.series["x"], atol=1e-9)


def test_normalized_coefficients_and_derivation():
    params = LESSON.resolve(preset="example")
    q = LESSON.surface(params)
    assert (q.a11, q.a22, q.a33, q.a44) == pytest.approx((0.01, 0.04, 1.0, -1.0))
    steps = LESSON.derivation(params)
    assert any(s.source == "(1.63)" for s in steps) and any(
        s.source == "(1.61)" and s.reconstructed for s in steps
    )


def test_stepper_and_scene():
    params = LESSON.resolve(preset="semi-axes-100-50-10")
    st = LESSON.stepper(params)
    f = st.advance(0.5)
    assert f.scalars["drift"] < 1e-12
    st.set_params(LESSON.resolve({"u3": "1"}, preset="semi-axes-100-50-10"))
    f = st.advance(0.5)
    assert f.t == pytest.approx(1.0)
    assert st.reset().t == 0.0
    sc = LESSON.scene(params)
    lo, hi = np.array(sc.bounds)
    assert np.all(np.isfinite(lo)) and hi[0] >= 100 - 1e-6


def test_claims_pass():
    for c in LESSON.claims():
        r = c.check()
        assert r.passed, (c.id, r)
