"""Tests for the LSP-2000 lesson (lessons/laser5/__init__.py): values, runs, frames, page."""

from __future__ import annotations

import json

import numpy as np
import pytest
from analyzer_lab.lessons.kit.contract import ParamError
from analyzer_lab.lessons.laser5 import LESSON

SERIES = (
    "x y z deviation tolerance speed feed off_normal travel_linear travel_tool"
    " axis_x axis_y axis_z axis_c axis_b move"
).split()


def test_declarations() -> None:
    assert LESSON.declaration_errors() == []
    assert [s.name for s in LESSON.series] == SERIES
    units = {s.name: s.unit for s in LESSON.series}
    assert units["deviation"] == units["tolerance"] == "um" and units["axis_c"] == "deg"
    assert LESSON.modes == ("method", "limits")
    assert [g.name for g in LESSON.groups][:2] == ["interpolation", "limits"]
    assert {LESSON.param(n).group for n in ("R_C", "R_B")} == {"machine"}


def test_every_claim_passes() -> None:
    for claim in LESSON.claims():
        result = claim.check()
        assert result.passed, (claim.id, result.expected, result.got)


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_presets_resolve_and_run(preset: str) -> None:
    params = LESSON.resolve(preset=preset)
    assert params["delta_p"] == 20.0
    run = LESSON.run(preset)
    assert list(run.series) == SERIES
    for key in SERIES:
        assert run.series[key].shape == run.t.shape and np.isfinite(run.series[key]).all()
    for key in ("deviation_max_um", "moves", "axis_travel_mm"):
        assert key in run.metrics
    assert run.t[-1] == pytest.approx(LESSON.preset(preset).t_end)
    json.dumps(run.to_json_dict())


def test_run_by_method() -> None:
    base = {"path": "line", "segments": 1, "u0": 300, "v0": 0, "u1": 300, "v1": 60, "V": 10}
    lin, bis, nl, fn = (
        LESSON.simulate(LESSON.resolve({**base, "method": m}))
        for m in ("linear", "bisection", "nonlinear", "fixed-normal")
    )
    assert nl.t[-1] == pytest.approx(6.0027, abs=1e-4)
    assert lin.metrics["deviation_max_um"] == pytest.approx(1398.0, abs=1.0)
    assert bis.metrics["moves"] == 16 and bis.metrics["deviation_max_um"] <= 20.0
    assert bis.series["move"][-1] == 16.0
    assert nl.metrics["deviation_max_um"] <= 1e-6
    assert nl.series["speed"] == pytest.approx(10.0, rel=1e-9)
    assert fn.metrics["off_normal_max_deg"] == pytest.approx(1.645, abs=1e-3)
    assert max(lin.series["deviation"]) == pytest.approx(1398.0, abs=2.0)
    assert lin.units["deviation"] == "um"


def test_improved_limits_remove_the_wrap() -> None:
    orig = LESSON.run("circle-original")
    impr = LESSON.run("circle-improved")
    assert orig.metrics["deviation_max_um"] > 1e5
    assert impr.metrics["deviation_max_um"] == pytest.approx(1378.0, abs=2.0)


def test_t_end_truncates_and_holds() -> None:
    params = LESSON.resolve(preset="segment-linear")
    short = LESSON.simulate(params, 2.0)
    assert short.t[-1] == pytest.approx(2.0) and "run stops" in short.messages[-1]
    long = LESSON.simulate(params, 10.0)
    assert long.t[-1] == pytest.approx(10.0) and long.series["x"][-1] == long.series["x"][-2]
    assert long.series["speed"][-1] == 0.0 and "holds" in long.messages[-1]


def test_validation_names_the_field() -> None:
    cases = [
        ({"method": "spline"}, "method"),
        ({"path": "line", "u0": 10, "v0": 0, "u1": 10, "v1": 0}, "u1"),
        ({"limits": "improved", "radius": 1000}, "limits"),  # 45 deg tilt at r = 2F
        ({"surface": "sphere", "radius": 900}, "radius"),
        ({"segments": 2}, "segments"),  # a circle of two segments
        ({"method": "nonlinear", "segments": 200, "sub_moves": 256}, "sub_moves"),
        ({"delta_p": 0.5}, "delta_p"),
    ]
    for values, field in cases:
        with pytest.raises(ParamError) as err:
            LESSON.resolve(values)
        assert err.value.name == field
    LESSON.resolve({"R_C": 0.0, "R_B": 10.0, "k_C1": "-1", "k_C2": 0.5})


def test_stepper_advance_set_params_reset() -> None:
    params = LESSON.resolve(preset="segment-linear")
    st = LESSON.stepper(params)
    f0 = st.frame()
    assert f0.t == 0.0 and f0.scalars["deviation"] == pytest.approx(0.0, abs=1e-3)
    assert list(f0.scalars) == SERIES
    f = st.advance(3.0)
    assert f.t == pytest.approx(3.0)
    assert f.scalars["deviation"] == pytest.approx(1397.8, abs=2.0)
    assert set(f.poses) == {"portal_X", "portal_Y", "portal_Z", "lever_C", "lever_B"}
    st.set_params(LESSON.resolve({"method": "nonlinear"}, preset="segment-linear"))
    f = st.frame()
    assert f.t == pytest.approx(3.0) and f.scalars["deviation"] < 1e-3
    assert f.scalars["speed"] == pytest.approx(10.0, rel=1e-9)
    f = st.advance(1e3)
    assert f.message == "task finished"
    assert st.reset().t == 0.0


def test_derivation_marks_reconstructions() -> None:
    steps = LESSON.derivation(LESSON.resolve())
    by_source = {s.source: s for s in steps}
    for src in ("(1a)", "(1b)", "(2)", "(3)"):
        assert by_source[src].reconstructed
    assert not by_source["(4)"].reconstructed
    assert all("digest" not in (s.source + s.text + (s.reconstructed or "")) for s in steps)


def test_notes() -> None:
    notes = LESSON.notes(LESSON.resolve(preset="segment-fixed-normal"))
    assert [n.kind for n in notes] == ["reconstructed", "info", "info"]
    assert "switched off and on" in notes[-1].text
    sphere = LESSON.notes(LESSON.resolve(preset="sphere-dome"))
    assert [n.kind for n in sphere] == ["reconstructed"]


def test_vertical_start_takes_next_c() -> None:
    """A task starting at the apex (vertical beam) takes C from the next pose: no lever swing."""
    values = {"path": "line", "u0": 0, "v0": 0, "u1": 100, "v1": 0, "segments": 4}
    params = LESSON.resolve({**values, "method": "bisection", "limits": "original"})
    run = LESSON.simulate(params)
    assert run.series["axis_c"][0] == pytest.approx(90.0) and run.series["axis_b"][0] == 0.0
    assert run.metrics["converged"] and run.metrics["moves"] == 8
    assert any("vertical beam" in m for m in run.messages)


def test_line_through_apex_needs_improved_limits() -> None:
    """Across the apex the azimuth jumps by pi: C in [0, 2pi) must swing the lever."""
    base = {"path": "line", "u0": -100, "v0": 0, "u1": 100, "v1": 0, "segments": 1}
    orig = LESSON.simulate(LESSON.resolve({**base, "method": "bisection", "limits": "original"}))
    impr = LESSON.simulate(LESSON.resolve({**base, "method": "bisection", "limits": "improved"}))
    assert not orig.metrics["converged"] and orig.metrics["deviation_max_um"] > 1e5
    assert any("bisection stopped" in m for m in orig.messages)
    assert impr.metrics["converged"] and impr.metrics["deviation_max_um"] <= 20.0
    assert impr.series["axis_b"].min() < 0.0 < impr.series["axis_b"].max()


def test_program_size_limit() -> None:
    params = {"method": "bisection", "delta_p": 1, "segments": 3, "radius": 900}
    run = LESSON.simulate(LESSON.resolve(params))
    assert run.metrics["converged"] and run.metrics["deviation_max_um"] <= 1.0
    assert run.metrics["moves"] <= 4096
