"""The presets' boxes (app/view/extents.py): the table holds every preset's run and the
defaults' of every lesson, it is what the runs cover (recomputed here), and a page opening
a preset frames the whole run, not only its start."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.view import extents
from analyzer_lab.view.extents import DEFAULTS, EXTENTS_FILE, preset_extent, run_extent


def _table() -> dict[str, dict[str, list[list[float]]]]:
    return json.loads(EXTENTS_FILE.read_text())


def _close(box: list[list[float]], extent: extents.Extent) -> bool:
    lo, hi = np.asarray(box[0]), np.asarray(box[1])
    size = max(float(np.max(hi - lo)), 1e-12)
    return bool(
        np.allclose(lo, extent.lo, rtol=0, atol=1e-6 * size)
        and np.allclose(hi, extent.hi, rtol=0, atol=1e-6 * size)
    )


def test_the_table_holds_every_presets_run_and_the_defaults() -> None:
    table = _table()
    for lesson in all_lessons():
        expected = {DEFAULTS, *(p.name for p in lesson.presets)}
        assert set(table.get(lesson.id, {})) == expected, lesson.id
        for box in table[lesson.id].values():
            lo, hi = np.asarray(box[0]), np.asarray(box[1])
            assert np.all(np.isfinite(lo)) and np.all(lo <= hi)
    assert set(table) == {lesson.id for lesson in all_lessons()}
    # the written text is the table as the module writes it (one line per run)
    assert EXTENTS_FILE.read_text() == extents.table_text(table)


@pytest.mark.parametrize(
    ("lesson_id", "preset"),
    [
        ("planar-3axis", "forward-drives"),
        ("parabola", "figs-1.8-1.10"),
        ("carriage-forced-vibration", "example"),
        ("sphere", "example-1.2"),
    ],
)
def test_a_box_is_what_the_run_covers(lesson_id: str, preset: str) -> None:
    lesson = get_lesson(lesson_id)
    name = preset
    extent = run_extent(lesson, name)
    assert extent is not None
    assert _close(_table()[lesson_id][name], extent)
    # the run leaves the box of its start: the framing of the start alone would not hold it
    setup = lesson.open(None, name)
    start = extents.frame_points(setup.stepper.frame())
    lo0, hi0 = start.min(axis=0), start.max(axis=0)
    assert np.any(np.asarray(extent.lo) < lo0 - 1e-9) or np.any(np.asarray(extent.hi) > hi0 + 1e-9)


@pytest.mark.slow
def test_every_box_is_what_its_run_covers() -> None:
    """The whole table recomputed (about a minute): a change of a lesson that moves a
    preset's path shows here until the table is made again
    (``python -m analyzer_lab.view.extents``)."""
    fresh = extents.compute_table(list(all_lessons()))
    table = _table()
    stale = [
        (lesson_id, name)
        for lesson_id, runs in fresh.items()
        for name, box in runs.items()
        if not _close(
            table.get(lesson_id, {}).get(name, [[np.nan] * 3] * 2),
            extents.Extent(tuple(box[0]), tuple(box[1]), 0.0),  # type: ignore[arg-type]
        )
    ]
    assert stale == []


def test_a_preset_is_framed_on_its_whole_run() -> None:
    """The view's camera box for a preset holds the preset's whole path; edited values
    fall back to the scene's box."""
    from analyzer_lab.view.scene import SceneRenderer, scene_bounds

    lesson = get_lesson("planar-3axis")
    setup = lesson.open(None, "forward-drives")
    r: Any = SceneRenderer.__new__(SceneRenderer)
    r.run_box = preset_extent(lesson.id, "forward-drives")
    assert r.run_box is not None
    lo, hi, _ = scene_bounds(setup.scene)
    flo, fhi, size = r._framing_box(lo, hi)
    assert np.all(flo <= r.run_box[0]) and np.all(fhi >= r.run_box[1])
    assert np.all(flo <= lo) and np.all(fhi >= hi) and size == pytest.approx(np.max(fhi - flo))
    assert preset_extent(lesson.id, "no-such-preset") is None
    assert preset_extent("no-such-lesson", None) is None
