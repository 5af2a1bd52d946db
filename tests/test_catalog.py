"""Every lesson in the catalog honours the lesson contract (a generic conformance test)."""

import json

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.contract import DerivationStep, Frame, RunResult, SceneSpec

LESSONS = all_lessons()
CASES = [(l.id, None) for l in LESSONS] + [(l.id, p.name) for l in LESSONS for p in l.presets]


def test_ids_unique_and_known():
    ids = [l.id for l in LESSONS]
    assert len(ids) == len(set(ids))
    assert "sphere" in ids
    with pytest.raises(KeyError, match="unknown lesson"):
        get_lesson("nope")


@pytest.mark.parametrize("lesson_id", [l.id for l in LESSONS])
def test_declarations(lesson_id):
    l = get_lesson(lesson_id)
    assert l.title and l.source and l.params
    names = [p.name for p in l.params]
    assert len(names) == len(set(names))
    for p in l.params:
        p.parse(p.default)  # defaults are valid
    json.dumps(l.describe(), default=str)


@pytest.mark.parametrize("lesson_id, preset", CASES)
def test_preset_runs_headless_and_live(lesson_id, preset):
    l = get_lesson(lesson_id)
    params = l.resolve(preset=preset)
    t_end = min(l.preset_t_end(preset), 2.0)
    res = l.simulate(params, t_end)
    assert isinstance(res, RunResult)
    assert len(res.t) >= 2 and np.all(np.isfinite(res.t))
    for name, series in res.series.items():
        assert len(series) == len(res.t), name
    json.dumps(res.to_json_dict())
    steps = l.derivation(params)
    assert steps and all(isinstance(s, DerivationStep) for s in steps)
    scene = l.scene(params)
    assert isinstance(scene, SceneSpec) and np.all(np.isfinite(np.array(scene.bounds, dtype=float)))
    st = l.stepper(params)
    f = st.advance(0.05)
    assert isinstance(f, Frame) and f.t > 0
    for name, pts in f.points.items():
        assert np.all(np.isfinite(pts)), name
    st.set_params(params)
    assert st.reset().t == 0.0


CHAPTER1 = [l for l in LESSONS if l.chapter == "1"]


@pytest.mark.parametrize("lesson_id, preset", [(l.id, p.name) for l in CHAPTER1 for p in l.presets])
def test_chapter1_run_json_has_positions_and_velocities(lesson_id, preset):
    """`analyzer-lab run LESSON --preset P --format json` carries x, y, z, vx, vy, vz."""
    l = get_lesson(lesson_id)
    doc = l.run(preset, t_end=min(l.preset_t_end(preset), 1.0)).to_json_dict()
    assert doc["preset"] == preset
    assert {"x", "y", "z", "vx", "vy", "vz"} <= set(doc["series"])
