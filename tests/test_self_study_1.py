"""Self-study C1.1-C1.5: every task runs with the textbook's parameters; closed forms and derived analyzers."""

import json

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.self_study_1 import (
    LESSON,
    READING_NAMES,
    SURFACE_TASKS,
    TASKS,
    semi_axes,
)


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_runs(preset):
    res = LESSON.run(preset, t_end=min(LESSON.preset_t_end(preset), 3.0))
    for k in ("x", "y", "z", "vx", "vy", "vz"):
        assert res.series[k].shape == res.t.shape and np.all(np.isfinite(res.series[k]))
    assert res.lesson == "self-study-1"
    json.dumps(res.to_json_dict())


def test_c11_runs_in_the_xz_plane():
    res = LESSON.run("C1.1-a", t_end=np.pi / 2)
    assert np.all(res.series["y"] == 0)
    assert (res.series["x"][-1], res.series["z"][-1]) == pytest.approx((1.0, 0.0), abs=1e-12)
    assert LESSON.scene(LESSON.resolve(preset="C1.1-a")).planar


def test_line_reaches_B_with_each_control():
    for key in "abcd":
        res = LESSON.run(f"C1.3-{key}")
        assert (res.series["x"][-1], res.series["y"][-1]) == pytest.approx((4.0, 4.0), abs=1e-9)


def test_ellipse_is_reading_i():
    res = LESSON.run("C1.4-a")
    assert np.max(np.abs(res.series["x"] ** 2 / 2 + res.series["y"] ** 2 - 1)) < 1e-13


@pytest.mark.parametrize("task", TASKS)
def test_derivation_per_task(task):
    steps = LESSON.derivation(LESSON.resolve({"task": task}))
    assert any("derived, not in source" in (s.reconstructed or "") for s in steps)


def test_stepper_switches_task():
    st = LESSON.stepper(LESSON.resolve(preset="C1.2-a"))
    f = st.advance(1.0)
    assert f.points["point"][0, :2] == pytest.approx([0.5, 1.0], abs=1e-12)
    st.set_params(LESSON.resolve(preset="C1.5a-cylinder"))
    f = st.advance(0.5)
    assert f.scalars["drift"] < 1e-12
    assert st.reset().t == 0.0
    for task in SURFACE_TASKS:
        assert np.all(np.isfinite(np.array(LESSON.scene(LESSON.resolve({"task": task})).bounds)))


def test_digital_switch_on_a_task():
    res = LESSON.run("C1.4-a", {"digital": "improved", "delta": 0.01, "pulse": 0.001}, t_end=10.0)
    assert res.metrics["dda_error_max"] < 0.05


def test_claims_pass():
    for c in LESSON.claims():
        r = c.check()
        assert r.passed, (c.id, r)


@pytest.mark.parametrize(
    ("preset", "axes", "period"),
    [
        ("C1.4-ii", (1.0, np.sqrt(2.0)), 2 * np.pi * np.sqrt(2.0)),
        ("C1.4-iii", (np.sqrt(12.0), 1.0), 2 * np.pi * np.sqrt(12.0)),
        ("C1.4-ab", (2.0, 1.0), 4 * np.pi),
    ],
)
def test_ellipse_readings(preset, axes, period):
    a, b = axes
    res = LESSON.run(preset)
    x, y = res.series["x"], res.series["y"]
    assert np.max(np.abs(x**2 / a**2 + y**2 / b**2 - 1)) < 1e-12
    assert res.t[-1] == pytest.approx(period)
    assert (x[-1], y[-1]) == pytest.approx((a, 0.0), abs=1e-9)
    assert x[0] == pytest.approx(a)


def test_ellipse_a_b_used_only_by_the_general_reading():
    general = LESSON.resolve({"task": "C1.4-ellipse", "reading": READING_NAMES[3]})
    general.update({"ellipse_a": 3.0, "ellipse_b": 0.5})
    assert semi_axes(general) == (3.0, 0.5)
    fixed = LESSON.resolve({"task": "C1.4-ellipse", "ellipse_a": 3.0})
    assert semi_axes(fixed) == pytest.approx((np.sqrt(2.0), 1.0))


def test_each_task_has_its_group_and_the_task_is_a_mode():
    groups = {p.name: p.group for p in LESSON.params}
    assert LESSON.modes == ("task", "digital") and groups["task"] == "mode"
    assert groups["R"] == "c1_1" and groups["k"] == "c1_3" and groups["reading"] == "c1_4"
    assert {groups[n] for n in ("a", "b", "c", "p", "u1", "u2", "u3")} == {"c1_5"}
    assert LESSON.declaration_errors() == []


def test_series_per_task_and_mode():
    names = lambda **v: [s.name for s in LESSON.series_for(LESSON.resolve(v))]  # noqa: E731
    assert "x_dda" not in names(task="C1.2-parabola")
    assert "dda_error" in names(task="C1.2-parabola", digital="simple")
    assert names(task="C1.5b-cone", digital="simple") == [
        "x", "y", "z", "vx", "vy", "vz", "speed", "drift"
    ]  # fmt: skip
