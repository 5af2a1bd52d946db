"""Played frames read in plain floats (``observe_one`` and the single-time paths of the
analyzer, planar and motion-program lessons): the same numbers as the observation on a
grid (``observe`` at several times at once), to round-off, at several times and states."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.curves.arclength import CubicHermite
from analyzer_lab.lessons.analyzers.plane.conic import (
    PlanarModel,
    PlanarState,
    PlanarTrack,
    _f1_f2,
    _f1_f2_one,
    embed,
)
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.lessons.kit.formula import parse_formula

LESSONS = {x.id: x for x in all_lessons()}


def assert_same(fast: dict[str, float], full: dict[str, np.ndarray], row: int, rel: float):
    assert list(fast) == list(full)
    for name, v in fast.items():
        ref = float(full[name][row])
        assert type(v) is float
        if np.isnan(ref):
            assert np.isnan(v), name
        else:
            assert abs(v - ref) <= rel * max(1.0, abs(ref)), (name, v, ref)


def presets(lesson_id: str) -> list[str]:
    return [p.name for p in LESSONS[lesson_id].presets]


ANALYZER = [
    (lid, preset)
    for lid in ("sphere", "quadric", "ellipsoid", "sphere-constant-speed")
    for preset in presets(lid)[:3]
]


@pytest.mark.parametrize(("lesson_id", "preset"), ANALYZER)
@pytest.mark.parametrize("family", [1, 3])
def test_analyzer_frames_equal_the_grid_observation(lesson_id, preset, family):
    lesson = LESSONS[lesson_id]
    params = lesson.resolve({"family": family}, preset)
    st = lesson.stepper(params)
    model = lesson.prepare(params).model
    assert lesson.observe_one(params, 0.0, {"r": st.R[None], "F0": st.F0[None]}) is None
    for _ in range(12):
        fr = st.advance(0.29)
        live = {"r": np.stack([st.R, st.R]), "F0": st.F0[None]}  # two times: the grid path
        full = lesson.observation(params, [st.t, st.t], live)
        assert_same(fr.scalars, full, 1, 1e-14)
        ref_v = model.velocities(np.array([st.t]), st.R[None])[0]
        np.testing.assert_allclose(fr.vectors["velocity"][1], ref_v, rtol=0, atol=1e-14)
        assert np.array_equal(fr.vectors["gradient"][1], model.half_gradient(st.R))


PLANAR = [
    (lid, preset) for lid in ("parabola", "circle", "self-study-1") for preset in presets(lid)
]


@pytest.mark.parametrize(("lesson_id", "preset"), PLANAR)
@pytest.mark.parametrize("digital", ["off", "improved"])
def test_planar_frames_equal_the_grid_observation(lesson_id, preset, digital):
    """The closed form at one time, the field and the series (the xy and xz planes, a
    family, a gain formula, the C1.5 surfaces) as the grid has them."""
    lesson = LESSONS[lesson_id]
    params = lesson.resolve({"digital": digital}, preset)
    st = lesson.stepper(params)
    for _ in range(8):
        fr = st.advance(0.377)
        one = st.track.at(np.array([st.t]))
        grid = st.track.at(np.array([0.0, st.t]))
        if isinstance(one, PlanarState):
            np.testing.assert_allclose(one.r[0], grid.r[1], rtol=1e-14, atol=1e-14)
            v = embed(one.model.velocity(st.t, grid.r[1]), lesson.plane_of(params))
            np.testing.assert_allclose(fr.vectors["velocity"][1], v, rtol=1e-14, atol=1e-14)
        full = lesson.observation(params, [0.0, st.t], grid)
        assert_same(fr.scalars, full, 1, 1e-13)


def test_planar_series_names_follow_the_digital_analyzer():
    lesson = LESSONS["parabola"]
    off = lesson.resolve({"family": 2})
    on = lesson.resolve({"family": 2, "digital": "simple"})
    assert "dda_error" not in lesson.series_names(off) and "dda_error" in lesson.series_names(on)
    assert lesson.series_names(off) == tuple(s.name for s in lesson.series_for(off))


def test_f1_f2_at_one_number_equal_the_arrays():
    q = np.concatenate([np.linspace(-50, 50, 401), np.geomspace(1e-12, 0.02, 40), [0.0, -1e6]])
    q = np.concatenate([q, -q])
    with np.errstate(all="ignore"):
        f1, f2 = _f1_f2(q)
    for k, v in enumerate(q):
        a, b = _f1_f2_one(float(v))
        assert a == pytest.approx(f1[k], rel=1e-14) and b == pytest.approx(f2[k], rel=1e-14)


@pytest.mark.parametrize(
    ("coeffs", "gain"),
    [
        ({"a11": 1.0, "a22": 1.0}, "sin(t)"),
        ({"a11": 0.025, "a12": 0.5, "a22": 10.0, "a13": -7.0, "a23": -5.0}, "1"),
        ({"a11": 1.0, "a22": -2.0, "a12": 0.3, "a13": 1.0}, "t"),
    ],
)
def test_the_closed_form_at_one_time_equals_the_grid(coeffs, gain):
    r0 = np.array([[1.0, 0.5], [0.2, -0.4]])
    model = PlanarModel.of([coeffs, coeffs], parse_formula(gain)).through(r0)
    track = PlanarTrack(model, r0, 0.25)
    t = np.linspace(0.25, 3.0, 12)
    grid = track.at(t).r
    for k, tk in enumerate(t):
        np.testing.assert_allclose(track.at(np.array([tk])).r[0], grid[k], rtol=1e-14, atol=1e-14)
        v, g = model.field_one(model.gain_one(float(tk)), grid[k])
        assert np.array_equal(v, model.velocity(tk, grid[k]))
        assert np.array_equal(g, model.half_gradient(grid[k]))
        drift = np.max(np.abs(model.F(grid[k : k + 1])), axis=1) / model.scale(grid[k : k + 1])
        assert model.drift_one(grid[k].tolist()) == pytest.approx(drift[0], rel=1e-14)
    bad = [[np.nan, 1.0], [0.0, 1.0]]
    assert np.isnan(model.drift_one(bad))


def test_a_cubic_hermite_at_one_point_equals_the_arrays():
    rng = np.random.default_rng(3)
    nodes = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1.0, 30))])
    for values, slopes in (
        (rng.normal(size=31), rng.normal(size=31)),
        (rng.normal(size=(31, 3)), rng.normal(size=(31, 3))),
    ):
        h = CubicHermite(nodes, values, slopes)
        xs = np.concatenate([[-1.0, nodes[-1] + 1], nodes, rng.uniform(0, nodes[-1], 50)])
        many = h(xs)
        for k, x in enumerate(xs):
            one = h(np.array([x]))
            assert one.shape == many[k : k + 1].shape
            np.testing.assert_allclose(one[0], many[k], rtol=1e-15, atol=1e-15)
        assert np.isnan(h(np.array([np.nan]))).all()


@pytest.mark.parametrize("preset", presets("motion-program"))
def test_motion_program_frames_equal_the_grid_observation(preset):
    """Every series at one time (the controls NaN in the window around the origin) as the
    grid has them, the ends of the helix (1.4) too (where |r'| is infinite)."""
    lesson = LESSONS["motion-program"]
    params = lesson.resolve({}, preset)
    st = lesson.stepper(params)
    prog = st._prog
    times = [*np.linspace(0.0, 1.05 * prog.T, 37), *prog.singular_t, prog.T]
    times += [a + 0.3 * (b - a) for a, b in prog.gaps]
    for t in times:
        Y = prog.solution(np.array([t]))
        grid = prog.solution(np.array([t, t]))
        assert np.array_equal(Y[0], grid[0], equal_nan=True)
        full = lesson.observation(params, [t, t], grid)
        assert_same(lesson.frame_scalars(params, t, Y), full, 0, 1e-14)
        tangent = prog.curve.arc.unit_tangent(np.array([full["phi"][0]] * 2))
        np.testing.assert_allclose(
            prog.curve.arc.unit_tangent(np.array([full["phi"][0]]))[0], tangent[0], atol=1e-15
        )
