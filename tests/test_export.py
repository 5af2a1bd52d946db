"""The export part on its own (no browser): tables on the textbook's grid, the frames
played, file names after what was run, and the HTML replay's caption and size cap."""

from __future__ import annotations

import csv
import io
import re

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.sphere import V2_TABLE
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.session.session import LabError, Session
from analyzer_lab.view.export import export_run, grid_run, paced_json, parse_step, thinned


def _session(lesson: str, preset: str) -> Session:
    s = Session(all_lessons(), lesson)
    s.apply_preset(preset)
    return s


def _rows(data: bytes) -> list[dict[str, float]]:
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(io.StringIO(data.decode()))]


def test_example_1_2_squared_speed_on_the_textbook_grid() -> None:
    s = _session("sphere", "example-1.2")  # not played: the grid runs to t_end = 10
    name, data = export_run(s, "csv")
    assert name == "analyzer-lab-sphere-example-1.2.csv"
    rows = _rows(data)
    assert [r["t"] for r in rows] == list(range(11))
    got = np.array([r["v2"] for r in rows])
    assert np.max(np.abs(got - np.array(V2_TABLE["example-1.2"]))) <= 5e-4


def test_the_grid_equals_the_headless_run() -> None:
    s = _session("servo-errors", "circle")
    grid = grid_run(s, 0.05)
    lesson = s.lesson
    run = lesson.simulate(s.params, float(grid.t[-1]))
    assert list(grid.series) == list(run.series) and grid.units == run.units
    for k, tk in enumerate(grid.t):
        j = int(np.argmin(np.abs(run.t - tk)))
        if abs(run.t[j] - tk) < 1e-12:
            for n in run.series:
                assert grid.series[n][k] == pytest.approx(run.series[n][j], rel=1e-9, abs=1e-12)


def test_step_limits_name_the_field() -> None:
    assert parse_step("pi/10", 10.0) == pytest.approx(np.pi / 10)
    with pytest.raises(LabError, match="grid step: must be positive"):
        parse_step("0", 10.0)
    with pytest.raises(LabError, match="grid step: .* more than 20001 rows"):
        parse_step("1e-5", 10.0)
    with pytest.raises(LabError, match="grid step: syntax error"):
        parse_step("import os", 10.0)


def test_an_edited_run_is_named_custom_and_frames_keep_every_frame() -> None:
    s = _session("sphere", "example-1.1")
    s.set_value("u1", "4")
    s.play()
    for _ in range(20):
        s.tick(1 / 36)
    name, data = export_run(s, "frames-csv")
    assert name == "analyzer-lab-sphere-example-1.1-custom-frames.csv"
    assert len(_rows(data)) == len(s.log)
    assert s.edits() == {"u1": ("5", "4")}


def test_replay_is_titled_captioned_and_capped() -> None:
    s = _session("sphere", "example-1.4-xy")  # a family of curves
    s.set_value("family", 24)
    s.set_speed(8)
    s.play()
    for _ in range(400):
        s.tick(1 / 36)
    name, data = export_run(s, "html")
    page = data.decode()
    assert name.endswith("-replay.html")
    assert "<title>Analyzer Lab replay: Problem 1.4 Curve on a sphere</title>" in page
    assert 'id="al-caption"' in page and "family" in page and "<svg" in page
    assert len(data) < 25e6


def test_a_russian_replay_has_russian_captions_and_the_same_data() -> None:
    from analyzer_lab.i18n import language_of

    s = _session("sphere", "example-1.4-xy")
    s.play()
    for _ in range(60):
        s.tick(1 / 36)
    english = export_run(s, "html")[1].decode()
    russian = export_run(s, "html", language=language_of("ru"))[1].decode()
    assert '<html lang="ru"' in russian and '<html lang="ru"' not in english
    assert "<title>Повтор Analyzer Lab: Задача 1.4" in russian
    assert "пример: example-1.4-xy" in russian and "preset: example-1.4-xy" in english
    assert re.search(r"t = 0 \.\.\. \d+,\d+ с", russian)
    assert re.search(r"t = 0 \.\.\. \d+\.\d+ s", english)
    # the exports of data stay machine-readable: CSV the same in every language
    assert export_run(s, "csv") == export_run(s, "csv", language=language_of("ru"))


def test_a_long_family_run_is_thinned_to_the_value_cap_and_says_so() -> None:
    from analyzer_lab.view.export import MAX_EXPORT_VALUES, paced_csv, thinned

    s = _session("sphere", "example-1.1")
    s.set_values({"family": 24})
    s.pause_at_end = False
    s.speed = 8.0
    s.play()
    while len(s.log) < 2000:
        s.tick(1 / 36)
    full = s.run_result()
    cols = 1 + sum(1 for v in full.series.values() if np.ndim(v) == 1)
    assert len(full.t) * cols > MAX_EXPORT_VALUES  # 220 columns
    small = thinned(full)
    assert len(small.t) * cols <= MAX_EXPORT_VALUES and len(small.t) > 1
    assert small.messages[-1].startswith("every ") and "frames exported" in small.messages[-1]
    k = int(np.ceil(len(full.t) * cols / MAX_EXPORT_VALUES))
    assert np.array_equal(small.t, full.t[::k])
    text = paced_csv(small)
    assert text == small.to_csv()  # the paced writer writes the same file
    name, data = export_run(s, "frames-csv")
    assert data.decode() == text and name.endswith("-frames.csv")


def test_a_grid_with_too_many_values_is_refused_naming_the_smallest_step() -> None:
    s = _session("sphere", "example-1.1")
    s.set_values({"family": 24})
    with pytest.raises(
        LabError, match="more than 400000 values; with these columns the smallest step"
    ):
        export_run(s, "csv", 0.001)


def test_the_pacer_rests_after_its_share_of_work() -> None:
    import time

    from analyzer_lab.limits import Pacer

    pace = Pacer(work=0.002, rest=0.004)
    t0 = time.monotonic()
    end = time.thread_time() + 0.05
    while time.thread_time() < end:
        pace()
    assert pace.rested >= 0.04  # about twice the 50 ms of work
    assert time.monotonic() - t0 >= 0.09


@pytest.mark.parametrize(
    ("lesson", "preset", "kind"),
    [
        ("sphere", "example-1.2", "json"),
        ("servo-errors", "circle", "json"),
        ("sphere", "example-1.1", "frames-json"),
        ("servo-errors", "circle", "frames-json"),
    ],
)
def test_the_json_is_written_in_slices_byte_for_byte_as_one_dump(
    lesson: str, preset: str, kind: str
) -> None:
    import json

    s = _session(lesson, preset)
    if kind.startswith("frames"):
        s.go_to(2.0)
        result = thinned(s.run_result())
    else:
        result = grid_run(s, None)
    expected = json.dumps(result.to_json_dict(), indent=1).encode()
    name, data = export_run(s, kind)
    assert name.endswith(".json") and len(data) > 1000
    assert data == expected


def test_the_paced_json_writer_matches_json_dumps_and_is_charged_as_it_goes() -> None:
    import json

    from analyzer_lab.limits import charged_by

    data = {
        "a": [1.5, float("nan"), float("inf"), -0.0, 10**20, 'é\u202e"\\'],
        "b": {"c": [], "d": {}, "e": [[1, 2], [None, True, False]]},
        "t": [k / 7 for k in range(100_000)],
    }
    charges: list[int] = []
    with charged_by(lambda: float(charges.append(1) or 0.0)):
        text = paced_json(data)
    assert text == json.dumps(data, indent=1)
    # the page callback's budget was charged between slices (every 4 ms of CPU), not once
    assert len(charges) >= 3, charges
    assert paced_json([]) == "[]" and paced_json(3.25) == "3.25"
