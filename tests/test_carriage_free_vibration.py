"""Problem 2.6: lessons/vibration/carriage_free_vibration.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.lessons.kit.contract import DerivationStep, ParamError
from analyzer_lab.lessons.vibration.carriage.model import (
    MODE_KEYS,
    closed_form_frequencies,
    eigen_frequencies,
    mode_shape,
)
from analyzer_lab.lessons.vibration.carriage_free_vibration import (
    CarriageFreeVibration,
    carriage_from_params,
    geometry_from_params,
)

FREE = CarriageFreeVibration()


def test_catalog_ids() -> None:
    assert get_lesson("carriage-free-vibration").id == FREE.id


def test_every_claim_passes() -> None:
    for claim in FREE.claims():
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


def test_free_stepper_advances_lesson_time_exactly() -> None:
    params = FREE.resolve(preset="free-response")
    st = FREE.stepper(params)
    f0 = st.frame()
    assert f0.poses["carriage"][1].shape == (4,)
    for _ in range(10):
        f1 = st.advance(0.005)
    assert st.t == pytest.approx(0.05, abs=1e-15)
    run = FREE.simulate(params, t_end=0.05)
    assert f1.scalars["phi_y"] == pytest.approx(run.series["phi_y"][-1], abs=1e-12)
    origins, dirs = f1.vectors["springs"]
    assert origins.shape == dirs.shape == (6, 3)
    q_before = dict(f1.scalars)
    st.set_params(FREE.resolve({"Cz": 6e7}, preset="free-response"))  # state kept
    assert st.frame().scalars["phi_y"] == pytest.approx(q_before["phi_y"], abs=1e-15)
    assert st.reset().t == 0.0


def test_free_groups_notes_and_english_labels() -> None:
    assert [g.title for g in FREE.groups] == ["Mode", "Carriage", "Air bearing", "Start state"]
    # the mode and the start state pick the initial state; carriage and bearing the modes
    assert {g.change for g in FREE.groups} == {"restart"}
    assert FREE.modes == ("mode",) and FREE.param("mode").group == "mode"
    assert FREE.param("m").group == "carriage" and FREE.param("Cz").group == "bearing"
    kinds = {n.kind for n in FREE.notes(FREE.resolve())}
    assert {"info", "corrected"} <= kinds
    labels = [m.label + m.name for m in FREE.scene(FREE.resolve()).markers]
    assert all(ch.isascii() for text in labels for ch in text)


def test_free_validate_refuses_unstable_bearing() -> None:
    with pytest.raises(ParamError) as err:
        FREE.resolve({"Ky": 100.0, "h": 0.1})
    assert err.value.name == "Ky"


def test_default_frequencies_agree_with_eigh() -> None:
    p = carriage_from_params(FREE.resolve())
    cf = np.sort(list(closed_form_frequencies(p).values()))
    w, _ = eigen_frequencies(p)
    assert np.max(np.abs(cf - w) / w) <= 1e-9


@pytest.mark.parametrize("mode", MODE_KEYS)
def test_stepper_starts_from_the_chosen_mode_shape(mode: str) -> None:
    """A changed mode restarts the session: the new stepper starts from the new shape,
    scaled so that the largest corner moves by ``amplitude``, at rest."""
    params = FREE.resolve({"mode": mode})
    scalars = FREE.stepper(params).frame().scalars
    state = np.array([scalars[c] for c in ("x", "y", "z", "phi_x", "phi_y", "phi_z")])
    shape = mode_shape(carriage_from_params(params), mode)
    d = geometry_from_params(params).max_corner_displacement(shape)
    assert state == pytest.approx(shape * params["amplitude"] / d, abs=1e-15)
    assert geometry_from_params(params).max_corner_displacement(state) == pytest.approx(
        params["amplitude"], rel=1e-12
    )
    assert [scalars[f"v{c}"] for c in "xyz"] == [0.0, 0.0, 0.0]


def test_set_params_then_reset_starts_the_new_mode() -> None:
    st = FREE.stepper(FREE.resolve({"mode": "z"}))
    st.advance(0.003)
    new = FREE.resolve({"mode": "phi_z"})
    st.set_params(new)  # state kept (what a "scene" change would do) ...
    assert st.frame().scalars["phi_z"] == 0.0 and st.frame().scalars["z"] != 0.0
    fr = st.reset()  # ... the session restarts a mode change: the new mode's shape
    assert fr.t == 0.0 and fr.scalars["z"] == 0.0 and fr.scalars["phi_z"] != 0.0


def test_time_scale_shows_a_few_periods_per_second() -> None:
    for preset in FREE.presets:
        f_hz = eigen_frequencies(carriage_from_params(FREE.resolve(preset=preset.name)))[0]
        per_wall_second = f_hz / (2 * math.pi) * FREE.time_scale
        assert 0.3 <= per_wall_second.min() and per_wall_second.max() <= 5.0
    assert FREE.t_end / FREE.time_scale == pytest.approx(10.0)


@pytest.mark.parametrize("preset", [p.name for p in CarriageFreeVibration.presets])
def test_live_frames_read_the_table_as_the_run_is_sampled(preset: str) -> None:
    """Played frames on the grain (session quanta times the time scale) read a block of
    the observation evaluated at once; off the grain a frame is observed alone; both are
    the headless run's values, and the drawing is that of the state."""
    lesson = CarriageFreeVibration()
    params = lesson.resolve(preset=preset)
    st = lesson.stepper(params)
    run = lesson.run_from(params, 0.0, None)
    grain = lesson.time_scale / 600.0
    geom = geometry_from_params(params)
    for dt in [17 * grain, 16 * grain, 0.37 * grain, 17 * grain, 900 * grain]:
        fr = st.advance(dt)
        state = run.state(np.array([fr.t]))
        want = lesson.observation(params, np.array([fr.t]), state)
        assert set(fr.scalars) == set(want)
        for name, v in want.items():
            assert fr.scalars[name] == pytest.approx(float(v[0]), rel=1e-12, abs=1e-15), name
        pos, quat = geom.pose(state[0, :6])
        assert fr.poses["carriage"][0] == pytest.approx(pos, abs=1e-15)
        assert fr.poses["carriage"][1] == pytest.approx(quat, abs=1e-13)
        assert fr.points["corner"][0] == pytest.approx(geom.corner(state[0, :6]), abs=1e-15)
        assert fr.vectors["springs"][1] == pytest.approx(
            geom.spring_vectors(state[0, :6])[1], abs=1e-15
        )
    assert st._table is not None and st._table.builds >= 1
