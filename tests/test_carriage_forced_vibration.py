"""Problem 2.7: lessons/vibration/carriage_forced_vibration.py."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.lessons.vibration.carriage_forced_vibration import (
    CarriageForcedVibration,
    oscillator_from_params,
)

FORCED = CarriageForcedVibration()


def test_catalog_id() -> None:
    assert get_lesson("carriage-forced-vibration").id == FORCED.id


def test_every_claim_passes() -> None:
    for claim in FORCED.claims():
        r = claim.check()
        assert r.passed, (claim.id, r.expected, r.got)


def test_groups() -> None:
    assert [g.title for g in FORCED.groups] == ["Carriage", "Air bearing", "Forcing", "Start state"]
    changes = {g.name: g.change for g in FORCED.groups}
    assert changes == {
        "carriage": "scene",
        "bearing": "scene",
        "forcing": "live",
        "initial": "restart",
    }
    assert FORCED.param("F0").group == "forcing" and FORCED.param("b").group == "bearing"


def test_forced_params_exact() -> None:
    assert [p.name for p in FORCED.params] == ["m", "b", "c", "F0", "w0", "q0", "v0"]


@pytest.mark.parametrize("preset", [p.name for p in FORCED.presets])
def test_forced_presets_run(preset: str) -> None:
    params = FORCED.resolve(preset=preset)
    run = FORCED.run(preset=preset)
    for name in ("q", "v", "q_steady", "F_drive"):
        assert run.series[name].shape == run.t.shape and np.all(np.isfinite(run.series[name]))
    assert run.series["q"][0] == pytest.approx(params["q0"]) and run.series["v"][
        0
    ] == pytest.approx(params["v0"])
    js = run.to_json_dict()
    assert set(js["series"]) >= {"q", "v"} and len(js["t"]) == len(js["series"]["q"])
    assert np.all(np.isfinite(np.array(FORCED.scene(params).bounds)))
    assert FORCED.derivation(params)[-1].math.startswith(r"\begin{array}")


def test_forced_headless_run_example_numbers() -> None:
    run = FORCED.run(
        values={"m": 2, "b": 0.8, "c": 50, "F0": 3, "w0": 4, "q0": 0.05, "v0": 0}, t_end=10
    )
    assert run.metrics["A0"] == pytest.approx(0.164094, abs=5e-7)
    assert run.metrics["phi1"] == pytest.approx(-0.175940, abs=5e-7)
    assert run.metrics["regime"] == "underdamped"
    # the transient stays inside its envelope A e^{-f t} (2.80) and touches it
    env = run.metrics["A"] * np.exp(-run.metrics["f"] * run.t)
    assert np.all(np.abs(run.series["q_transient"]) <= env + 1e-12)
    assert np.max(np.abs(run.series["q_transient"]) / env) > 0.999


def test_forced_stepper_matches_simulate() -> None:
    params = FORCED.resolve()
    st = FORCED.stepper(params)
    for _ in range(100):
        f = st.advance(0.05)
    run = FORCED.simulate(params, t_end=5.0)
    assert f.scalars["q"] == pytest.approx(run.series["q"][-1], abs=1e-12)
    st.set_params(FORCED.resolve({"b": 4.0}))
    assert st.frame().scalars["q"] == f.scalars["q"]  # state kept
    f2 = st.advance(0.05)
    assert f2.t == pytest.approx(5.05)
    assert st.reset().scalars["q"] == pytest.approx(params["q0"], abs=1e-15)
    assert "carriage" in f2.poses and "spring" in f2.vectors
    assert any(n.kind == "corrected" for n in FORCED.notes(params))


def test_live_forcing_change_continues_from_the_state() -> None:
    """A changed forcing acts at once: the run goes on from the current (q, q') with the
    closed form (2.92) of the new values."""
    params = FORCED.resolve()
    st = FORCED.stepper(params)
    for _ in range(36):
        f1 = st.advance(1 / 36)
    new = FORCED.resolve({"w0": 6.0, "F0": 1.0})
    st.set_params(new)
    q1, v1 = f1.scalars["q"], f1.scalars["v"]
    f2 = st.advance(0.5)
    o = oscillator_from_params(new)
    q_want, _ = o.response(np.array([1.5]), q1, v1, 1.0)
    assert f2.scalars["q"] == pytest.approx(float(q_want[0]), abs=1e-12)
    assert f2.scalars["F_drive"] == pytest.approx(np.sin(6.0 * 1.5), abs=1e-12)


def test_time_scale_shows_about_one_or_two_periods_per_second() -> None:
    params = FORCED.resolve()
    per_wall_second = oscillator_from_params(params).omega / (2 * np.pi) * FORCED.time_scale
    assert 1.0 <= per_wall_second <= 3.0
    assert FORCED.t_end / FORCED.time_scale == pytest.approx(10.0)


@pytest.mark.parametrize("preset", [p.name for p in CarriageForcedVibration.presets])
def test_live_frames_read_the_table_as_the_run_is_sampled(preset: str) -> None:
    """Played frames on the grain read a block of the observation evaluated at once; off
    the grain a frame is observed alone; both are the headless run's values."""
    lesson = CarriageForcedVibration()
    params = lesson.resolve(preset=preset)
    st = lesson.stepper(params)
    run = lesson.run_from(params, 0.0, None)
    grain = lesson.time_scale / 600.0
    for dt in [17 * grain, 16 * grain, 0.37 * grain, 17 * grain, 900 * grain]:
        fr = st.advance(dt)
        want = lesson.observation(params, np.array([fr.t]), run.state(np.array([fr.t])))
        assert set(fr.scalars) == set(want)
        for name, v in want.items():
            assert fr.scalars[name] == pytest.approx(float(v[0]), rel=1e-12, abs=1e-14), name
    assert st._table is not None and st._table.builds >= 1
