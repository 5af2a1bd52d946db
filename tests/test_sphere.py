"""Problem 1.4 (sphere): presets, claims with numbers, live stepper, bad input."""

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.sphere import LESSON, V2_TABLE
from analyzer_lab.lessons.kit.contract import ParamError


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


def test_declared_series_units_and_family_members():
    params = LESSON.resolve(preset="example-1.4-xy")
    names = [s.name for s in LESSON.series_for(params)]
    assert names[:12] == [
        *("x", "y", "z", "vx", "vy", "vz", "v2", "speed", "drift", "u1", "u2", "u3")
    ]
    assert "z_5" in names and "drift_5" in names and "u1_2" not in names
    res = LESSON.simulate(params, 1.0)
    assert res.units["v2"] == "units²/s²" and res.units["speed"] == "units/s"
    assert np.all(res.series["z_5"] == res.series["z_5"][0])
    assert LESSON.readout == ("x", "y", "z", "speed", "v2", "drift")
    assert LESSON.start_point == ("x0", "y0", "z0") and LESSON.family == "family"


def test_run_grid_keeps_the_textbook_sampling():
    """Every node of h = 0.01 s over 10 s, among them the tabulated t = 0, 1, ..., 10."""
    res = LESSON.run("example-1.2")
    assert LESSON.sampling == 1.0 and len(res.t) == 1001
    assert np.allclose(res.t[::100], np.arange(11), atol=1e-12)
    long = LESSON.run_grid(LESSON.resolve(preset="example-1.2"), 500.0)
    assert len(long) == 2001 and np.allclose(long[::4], np.arange(501.0))


def test_projection_is_a_note():
    params = LESSON.resolve({"x0": 0.6, "y0": 0.8, "z0": 0.5})
    (note,) = LESSON.notes(params)
    assert note.kind == "info" and "projected" in note.text and note.source == "(1.42)"


def test_a_bad_control_is_refused_naming_itself() -> None:
    from analyzer_lab.lessons.kit.contract import ParamError

    for name in ("u1", "u2", "u3"):
        with pytest.raises(ParamError, match=f"^{name}: '1/\\(t-3\\)' is not finite at t = 3"):
            LESSON.resolve({name: "1/(t-3)"})


def test_prepared_once_per_values_and_read_again_by_object() -> None:
    params = LESSON.resolve(preset="example-1.1")
    first = LESSON.prepare(params)
    assert LESSON.prepare(params) is first  # the same object
    assert LESSON.prepare(LESSON.resolve(preset="example-1.1")) is first  # the same values
    other = LESSON.prepare(LESSON.resolve(preset="example-1.1", values={"u1": "2"}))
    assert other is not first and LESSON.prepare(params) is first
    # a frame's observation of the values it was built with
    st = LESSON.stepper(params)
    fr = st.advance(17 / 600.0)
    assert fr.scalars["u1"] == 5.0 and abs(fr.scalars["drift"]) < 1e-12
