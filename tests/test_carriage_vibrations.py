"""Problems 2.6 and 2.7: lessons/carriage_vibrations.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lessons.carriage_vibrations import (
    LESSONS,
    CarriageForcedVibration,
    CarriageFreeVibration,
    carriage_from_params,
)
from lessons.catalog import get_lesson
from lessons.core.contract import DerivationStep, ParamError
from lessons.core.vibration import closed_form_frequencies, eigen_frequencies

FREE, FORCED = CarriageFreeVibration(), CarriageForcedVibration()


def test_catalog_ids() -> None:
    assert get_lesson("carriage-free-vibration").id == FREE.id
    assert get_lesson("carriage-forced-vibration").id == FORCED.id
    assert [l.id for l in LESSONS] == [FREE.id, FORCED.id]


@pytest.mark.parametrize("lesson", [FREE, FORCED], ids=lambda l: l.id)
def test_every_claim_passes(lesson) -> None:
    for claim in lesson.claims():
        r = claim.check()
        assert r.passed, (claim.id, r.expected, r.got)


@pytest.mark.parametrize("preset", [p.name for p in FREE.presets])
def test_free_presets_run(preset: str) -> None:
    params = FREE.resolve(preset=preset)
    run = FREE.run(preset=preset)
    for name in ("x", "y", "z", "phi_x", "phi_y", "phi_z", "vx", "Fx", "E", "W"):
        assert run.series[name].shape == run.t.shape
        assert np.all(np.isfinite(run.series[name]))
    # conservative system: E + W constant
    tot = run.series["E_total"]
    assert np.ptp(tot) <= 1e-9 * np.max(tot)
    assert run.metrics["max_rel_err_closed_vs_eig"] <= 1e-9
    scene = FREE.scene(params)
    assert np.all(np.isfinite(np.array(scene.bounds)))
    assert [b.name for b in scene.bodies] == ["carriage"]
    steps = FREE.derivation(params)
    assert all(isinstance(s, DerivationStep) and s.source for s in steps)
    assert any(s.source == "(2.68)" and s.reconstructed for s in steps)


def test_mode_animation_is_a_pure_mode() -> None:
    params = FREE.resolve({"mode": "x-phi_y lower"}, preset="strong-coupling")
    p = carriage_from_params(params)
    w = closed_form_frequencies(p)["x-phi_y lower"]
    run = FREE.simulate(params, t_end=2 * math.pi / w)
    x, phi = run.series["x"], run.series["phi_y"]
    # one period later it is back; the ratio of x to phi_y is fixed
    assert x[-1] == pytest.approx(x[0], abs=1e-12)
    mask = np.abs(phi) > 1e-3 * np.max(np.abs(phi))
    ratio = x[mask] / phi[mask]
    assert np.ptp(ratio) <= 1e-8 * np.max(np.abs(ratio))
    assert run.series["y"] == pytest.approx(0.0, abs=1e-15)


def test_free_stepper_advance_set_params_reset() -> None:
    params = FREE.resolve()
    st = FREE.stepper(params)
    f0 = st.frame()
    pos0, quat0 = f0.poses["carriage"]
    assert quat0.shape == (4,) and pos0.shape == (3,)
    f1 = st.advance(0.1)  # view seconds; physical time = 0.1 / slowdown
    assert st.t == pytest.approx(0.1 / params["slowdown"])
    assert f1.scalars["phi_y"] != f0.scalars["phi_y"]
    origins, dirs = f1.vectors["springs"]
    assert origins.shape == dirs.shape == (6, 3)
    # stiffness change keeps the state, mode change restarts from the new shape
    q_before = dict(f1.scalars)
    st.set_params(FREE.resolve({"Cz": 6e7}))
    assert st.frame().scalars["phi_y"] == q_before["phi_y"]
    st.set_params(FREE.resolve({"mode": "z"}))
    assert st.frame().scalars["phi_y"] == 0.0 and st.frame().scalars["z"] != 0.0
    assert st.reset().t == 0.0


def test_free_validate_refuses_unstable_bearing() -> None:
    with pytest.raises(ParamError) as err:
        FREE.resolve({"Ky": 100.0, "h": 0.1})
    assert err.value.name == "Ky"


def test_default_frequencies_agree_with_eigh() -> None:
    p = carriage_from_params(FREE.resolve())
    cf = np.sort(list(closed_form_frequencies(p).values()))
    w, _ = eigen_frequencies(p)
    assert np.max(np.abs(cf - w) / w) <= 1e-9


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
    assert st.reset().scalars["q"] == params["q0"]
    assert "carriage" in f2.poses and "spring" in f2.vectors
