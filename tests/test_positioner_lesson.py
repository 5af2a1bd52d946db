"""Tests of analyzer_lab.lessons.mechanics.positioners.lesson: what Problems 2.1-2.5 share."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.lessons.kit.contract import Lesson
from analyzer_lab.lessons.mechanics.linear_positioner import LESSON as LINEAR
from analyzer_lab.lessons.mechanics.planar_2axis import LESSON as PLANAR2
from analyzer_lab.lessons.mechanics.planar_3axis import LESSON as PLANAR3
from analyzer_lab.lessons.mechanics.rotary_positioner import LESSON as ROTARY
from analyzer_lab.lessons.mechanics.table_6dof import LESSON as TABLE

LESSONS = [LINEAR, ROTARY, PLANAR2, PLANAR3, TABLE]
BY_ID = {l.id: l for l in LESSONS}
SMALL = ["linear-positioner", "rotary-positioner", "planar-2axis", "planar-3axis"]


def test_ids_in_catalog() -> None:
    ids = {l.id for l in all_lessons()}
    assert {
        "linear-positioner",
        "rotary-positioner",
        "planar-2axis",
        "planar-3axis",
        "table-6dof",
    } <= ids


@pytest.mark.parametrize("lesson", LESSONS, ids=lambda l: l.id)
def test_declarations(lesson: Lesson) -> None:
    assert lesson.declaration_errors() == []
    assert lesson.modes[0] == "problem" and lesson.groups[0].name == "mode"
    assert [g.name for g in lesson.groups][1] == "body"
    for problem in ("forward", "inverse"):
        assert all(n.text for n in lesson.notes(lesson.resolve({"problem": problem})))


@pytest.mark.parametrize("lesson", LESSONS, ids=lambda l: l.id)
def test_claims_pass(lesson: Lesson) -> None:
    for claim in lesson.claims():
        res = claim.check()
        assert res.passed, f"{lesson.id}/{claim.id}: expected {res.expected}, got {res.got}"


@pytest.mark.parametrize("lid", SMALL)
def test_presets_simulate(lid: str) -> None:
    lesson = BY_ID[lid]
    for preset in lesson.presets:
        params = lesson.resolve(preset=preset.name)
        r = lesson.simulate(params, 2.0)
        assert not r.messages
        for c in lesson.coords:  # type: ignore[attr-defined]
            for name in (c.name, f"{c.name}_dot", f"{c.name}_ddot"):
                assert r.series[name].shape == r.t.shape and np.all(np.isfinite(r.series[name]))
        for i in lesson.inputs:  # type: ignore[attr-defined]
            assert np.all(np.isfinite(r.series[i.name]))


@pytest.mark.parametrize("lid", SMALL)
def test_stepper_and_scene(lid: str) -> None:
    lesson = BY_ID[lid]
    for problem in ("forward", "inverse"):
        params = lesson.resolve({"problem": problem})
        st = lesson.stepper(params)
        f1 = st.advance(0.1)
        st.set_params(lesson.resolve({"problem": problem}))
        f2 = st.advance(0.1)
        assert f2.t == pytest.approx(0.2) and f1.poses and f1.scalars
        assert list(f2.scalars) == [s.name for s in lesson.series]
        for name in lesson.scene(params).bodies:
            assert name.name in f2.poses
        f0 = st.reset()
        assert f0.t == 0.0
        sc = lesson.scene(params)
        assert np.all(np.isfinite(np.array(sc.bounds)))
        names = {s for p in lesson.plots for s in p.series}
        assert names <= set(f2.scalars)
        steps = lesson.derivation(params)
        assert steps and all(s.title for s in steps)


def test_set_params_keeps_the_forward_state() -> None:
    params = LINEAR.resolve({"F_dv": "1", "R_sopr": "0"})
    st = LINEAR.stepper(params)
    x1 = st.advance(1.0).scalars["x"]  # 1/5 * 1^2 / 2 = 0.1 m
    st.set_params(LINEAR.resolve({"F_dv": "0", "R_sopr": "0"}))
    f = st.advance(1.0)
    assert x1 == pytest.approx(0.1, rel=1e-9)
    assert f.scalars["x"] == pytest.approx(0.1 + 0.2, rel=1e-9)  # coasting at 0.2 m/s


def test_answers_are_kept_by_values_and_by_parameter_object() -> None:
    params = PLANAR2.resolve(preset=PLANAR2.presets[0].name)
    builds: list[int] = []

    def build() -> int:
        builds.append(1)
        return len(builds)

    assert PLANAR2.cached("probe", params, build) == 1
    assert PLANAR2.cached("probe", params, build) == 1  # the same object: kept
    same = PLANAR2.resolve(preset=PLANAR2.presets[0].name)
    assert same is not params and PLANAR2.cached("probe", same, build) == 1  # same values
    other = PLANAR2.resolve(preset=PLANAR2.presets[0].name, values={"g": 7.5})
    assert PLANAR2.cached("probe", other, build) == 2 and len(builds) == 2  # new values
    # the scene extent a frame reads is the one of its values
    lo, hi, span = PLANAR2._extent(params)
    assert PLANAR2._extent(params)[2] == span and span >= 0.5


def test_table_physical_values_are_shared_read_only() -> None:
    params = TABLE.resolve()
    p = TABLE.pvec(params)
    assert TABLE.pvec(params) is p and not p.flags.writeable
    with pytest.raises(ValueError):
        p[0] = 1.0


@pytest.mark.parametrize("lid", SMALL)
def test_played_frames_read_the_numbers_of_the_grid(lid: str) -> None:
    """A played frame's scalars (worked out on floats, :meth:`observe_one`) are the
    observation of a grid run at the same times, and that of the one time through the
    arrays."""
    lesson = BY_ID[lid]
    for preset in lesson.presets:
        params = lesson.resolve(preset=preset.name)
        st = lesson.stepper(params)
        frames = [st.advance(dt) for dt in (0.013, 0.25, 1.0 / 36, 1.7, 0.4, 1.0 / 36)]
        t = np.array([fr.t for fr in frames])
        states = lesson.solution(params)(t)
        grid = lesson.observation(params, t, states)
        for k, fr in enumerate(frames):
            general = Lesson.observation(lesson, params, np.array([fr.t]), states[k : k + 1])
            general = {name: float(v[0]) for name, v in general.items()}
            assert list(fr.scalars) == list(general) == list(grid)
            one = lesson.observe_one(params, fr.t, states[k : k + 1])
            assert one == fr.scalars  # the frame read them on floats
            for name, v in fr.scalars.items():
                for want in (grid[name][k], general[name]):
                    assert abs(v - want) <= 1e-12 * (abs(want) + 1.0), (preset.name, name, k)


@pytest.mark.parametrize("lid", SMALL)
def test_accelerations_on_plain_numbers_equal_the_matrix_solve(lid: str) -> None:
    lesson = BY_ID[lid]
    params = lesson.resolve(preset=lesson.presets[0].name)
    model, p = lesson.model(params), lesson.pvec(params)  # type: ignore[attr-defined]
    n, m = model.n, len(model.inputs)
    rng = np.random.default_rng(3)
    for _ in range(20):
        q, qd, u = rng.normal(size=n), rng.normal(size=n), 10 * rng.normal(size=m)
        t = float(rng.uniform(0, 10))
        want = model.accelerations(q, qd, t, p, u)
        got = model.acceleration_list(q, qd, t, p, list(u))
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


def test_inputs_at_one_time_are_the_formulas_on_the_grid() -> None:
    """The force formulas read one time at a time on floats are the grid's values, with
    its inf and NaN where a formula is singular or undefined."""
    for values in (
        {"F_dv": "1/(t-1)", "R_sopr": "sqrt(t - 2) + 3"},
        {"F_dv": "2*sin(3*t) + t**2", "R_sopr": "0.5"},
        {"F_dv": "4", "R_sopr": "-1.5"},
    ):
        params = LINEAR.resolve(values)
        t = np.array([0.0, 0.5, 1.0, 1.0 + 1e-9, 2.0, 2.25, 3.7])
        grid = LINEAR.forces(params, t)
        at = LINEAR.inputs_at(params)
        for k, tk in enumerate(t):
            for x in (float(tk), np.float64(tk)):
                got = np.array(at(x))
                assert np.allclose(got, grid[:, k], rtol=1e-14, atol=0.0, equal_nan=True), values
                assert np.array_equal(np.isinf(got), np.isinf(grid[:, k]))


@pytest.mark.parametrize("lid", SMALL)
def test_inverse_inputs_on_plain_numbers_equal_the_least_squares(lid: str) -> None:
    lesson = BY_ID[lid]
    params = lesson.resolve({"problem": "inverse"})
    model, p = lesson.model(params), lesson.pvec(params)  # type: ignore[attr-defined]
    unknown = lesson.unknown  # type: ignore[attr-defined]
    n, m = model.n, len(model.inputs)
    rng = np.random.default_rng(4)
    for _ in range(20):
        q, qd, qdd = rng.normal(size=n), rng.normal(size=n), rng.normal(size=n)
        u = 10 * rng.normal(size=m)
        t = float(rng.uniform(0, 10))
        want = model.solve_inputs(q, qd, qdd, t, p, u, unknown)
        got = model.input_list(list(q), list(qd), list(qdd), t, list(p), list(u), unknown)
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    # more unknowns than equations: the least squares' minimum norm, as solve_inputs
    every = list(range(m))
    if m > n:
        want = model.solve_inputs(q, qd, qdd, 0.5, p, u, every)
        got = model.input_list(list(q), list(qd), list(qdd), 0.5, list(p), list(u), every)
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
