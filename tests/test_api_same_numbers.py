"""``al.run`` gives the numbers of ``analyzer-lab run --format json``: every preset of every
lesson, the command line run in a process of its own (one per lesson, beside the API's
runs), compared value for value (series, times, units, metrics, messages, values used).

Both sides first play each preset's stepper for a moment: ``run`` estimates a run's
computing from its stepper timed on a first piece, and a lesson that builds something once
(the 6-DOF table's inverse program: seconds of CPU) would otherwise be refused in a fresh
process and not in a warm one; what is built once gives the same numbers (tested here).
"""

from __future__ import annotations

import json
import subprocess
import sys

import analyzer_lab as al
import pytest
from analyzer_lab.lessons.catalog import INDEX, get_lesson

#: One process runs ``analyzer-lab run LESSON --preset P --format json`` for every preset of
#: a lesson (the command line's entry point) and prints what each printed, as one list.
CLI_RUNS = """
import contextlib, io, json, sys
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.serve.cli import main
lesson = get_lesson(sys.argv[1])
for preset in lesson.presets:
    lesson.stepper(lesson.resolve(preset=preset.name)).advance(0.01)
printed = []
for preset in lesson.presets:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["run", sys.argv[1], "--preset", preset.name, "--format", "json"])
    printed.append([code, out.getvalue()])
print(json.dumps(printed))
"""


def printed(child: subprocess.Popen[str]) -> list[dict[str, object]]:
    """What the command line printed for each preset (each exited 0)."""
    out, err = child.communicate(timeout=600)
    assert child.returncode == 0, err
    runs = json.loads(out.splitlines()[-1])
    assert [code for code, _ in runs] == [0] * len(runs), err
    return [json.loads(text) for _, text in runs]


@pytest.mark.slow
@pytest.mark.parametrize("lesson", [lesson_id for lesson_id, _ in INDEX])
def test_every_preset_gives_the_command_lines_numbers(lesson: str) -> None:
    child = subprocess.Popen(
        [sys.executable, "-c", CLI_RUNS, lesson],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        page = get_lesson(lesson)
        presets = al.lessons(lesson)[0].presets
        for preset in presets:
            page.stepper(page.resolve(preset=preset)).advance(0.01)
        runs = [al.run(lesson, preset=preset) for preset in presets]
        expected = printed(child)
    finally:
        child.kill()
    assert [doc["preset"] for doc in expected] == list(presets)
    for preset, run, doc in zip(presets, runs, expected):
        got = json.loads(json.dumps(run.to_dict()))  # as printed: NaN as null
        assert got["t"] == doc["t"], preset
        assert got["series"] == doc["series"], preset
        assert got["metrics"] == doc["metrics"], preset
        assert got == doc, preset
        assert run.t.tolist() == doc["t"] and run.units == doc["units"]
        assert run.values == doc["params"] and run.messages == doc["messages"]


def test_the_sphere_examples_give_the_command_lines_numbers() -> None:
    """The quick subset's share of the test above: one lesson."""
    test_every_preset_gives_the_command_lines_numbers("sphere")
