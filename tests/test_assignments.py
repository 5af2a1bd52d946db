"""Assignments: the file format's validation, the grader, the ready set and drafting."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest
from analyzer_lab.lessons.assignments import (
    AssignmentError,
    draft,
    grade,
    load_answer,
    load_assignment,
    load_folder,
    parse_assignment,
    ready_assignments,
)
from analyzer_lab.lessons.assignments.spec import MAX_CHECKS, MAX_FILE_BYTES
from analyzer_lab.lessons.catalog import all_lessons

READY = ready_assignments()

BASE = {
    "format": "analyzer-lab assignment",
    "version": 1,
    "id": "t-sphere",
    "title": "Equator",
    "lesson": "sphere",
    "preset": "example-1.1",
    "unlocked": ["u1", "u2", "u3"],
    "checks": [
        {"id": "plane", "kind": "in-plane", "normal": [0, 0, 1], "offset": 0, "tolerance": 1e-9},
        {
            "id": "radius",
            "kind": "within",
            "quantity": "x^2 + y^2 + z^2",
            "target": "1",
            "tolerance": 1e-9,
        },
    ],
    "task": "Stay on the equator.",
}


def variant(**changes: object) -> dict:
    d = copy.deepcopy(BASE)
    d.update(changes)
    return d


def refused(data: object) -> str:
    with pytest.raises(AssignmentError) as exc:
        parse_assignment(data, "hostile.json")
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("hostile.json")
    return msg


def test_ready_set_covers_every_lesson_with_25_or_more() -> None:
    assert len(READY) >= 25
    covered = {a.lesson for a in READY}
    assert covered == {l.id for l in all_lessons()}
    assert len({a.id for a in READY}) == len(READY)
    for a in READY:
        assert a.task and a.hint and a.reference
        assert set(a.answers) == {"correct", "wrong"}


@pytest.mark.parametrize("a", READY, ids=[a.id for a in READY])
def test_ready_correct_passes_wrong_fails_naming_check(a) -> None:
    right = grade(a, a.answers["correct"])
    assert right.passed, [c.message for c in right.failed]
    assert all(c.miss == 0.0 for c in right.checks)
    wrong = grade(a, a.answers["wrong"])
    assert not wrong.passed
    ids = {c.id for c in a.checks}
    for c in wrong.failed:
        assert c.id in ids
        assert c.miss > 0
        assert any(w in c.message for w in ("misses", "above the bound", "below the bound"))
        js = c.to_json_dict()
        assert js["pass"] is False and js["id"] == c.id


def test_grade_measures_by_how_much() -> None:
    a = parse_assignment(BASE, "base")
    g = grade(a, {"u1": "1", "u2": "0", "u3": "0"})
    assert g.passed
    g = grade(a, {"u1": "1", "u2": "1", "u3": "0"})
    plane = g.checks[0]
    assert not plane.passed and plane.id == "plane"
    # u = (1, 1, 0) turns about -(0, 1, 1)/.. : z reaches sqrt(1/2)
    assert plane.measured == pytest.approx(0.5**0.5, rel=1e-3)
    assert plane.miss == pytest.approx(plane.measured - 1e-9)
    assert g.checks[1].passed  # still on the sphere


def test_series_expression_uses_whitelist_and_series() -> None:
    a = parse_assignment(
        variant(
            checks=[
                {
                    "id": "s",
                    "kind": "within",
                    "quantity": "sqrt(v2)",
                    "target": "speed",
                    "tolerance": 1e-9,
                }
            ]
        ),
        "x",
    )
    assert grade(a, {"u1": "t"}).passed


@pytest.mark.parametrize(
    "expr",
    [
        "__import__('os').system('true')",
        "x.__class__",
        "open('/etc/passwd')",
        "lambda: 1",
        "[x for x in y]",
        "eval('1')",
        "x; y",
    ],
)
def test_code_in_expression_is_refused(expr: str) -> None:
    data = variant(checks=[{"id": "c", "kind": "within", "quantity": expr, "tolerance": 1}])
    msg = refused(data)
    assert "checks[0].quantity" in msg


def test_code_in_target_is_refused() -> None:
    data = variant(
        checks=[
            {"id": "c", "kind": "within", "quantity": "x", "target": "os.system", "tolerance": 1}
        ]
    )
    assert "checks[0].target" in refused(data)


@pytest.mark.parametrize(
    ("changes", "where", "words"),
    [
        ({"lesson": "no-such-lesson"}, "field lesson", "no lesson"),
        (
            {"unlocked": ["u1", "warp_drive"]},
            "field unlocked[1]",
            "not a parameter of lesson sphere",
        ),
        ({"start": {"warp": 1}}, "field start.warp", "not a parameter"),
        ({"preset": "example-9"}, "field preset", "no preset"),
        ({"version": 2}, "field version", "must be 1"),
        ({"version": True}, "field version", "must be 1"),
        ({"format": "other"}, "field format", "must be"),
        ({"id": "Bad Id!"}, "field id", "lowercase"),
        ({"title": 7}, "field title", "must be text"),
        ({"task": "x" * 5000}, "field task", "limit"),
        ({"unlocked": "u1"}, "field unlocked", "non-empty list"),
        ({"unlocked": []}, "field unlocked", "non-empty list"),
        ({"unlocked": ["u1", "u1"]}, "field unlocked", "twice"),
        ({"checks": []}, "field checks", "non-empty"),
        ({"script": "x"}, "field script", "not a field"),
        ({"t_end": -1}, "field t_end", "positive"),
        ({"t_end": 1e9}, "field t_end", "limit"),
        ({"t_end": "1e400"}, "field t_end", ""),
        ({"start": {"u1": "import os"}}, "field start", "u1"),
        ({"answers": {"correct": {"x0": 1}}}, "field answers.correct.x0", "locked"),
        ({"answers": {"maybe": {}}}, "field answers", "correct"),
    ],
)
def test_hostile_top_level_refused_naming_field(changes: dict, where: str, words: str) -> None:
    msg = refused(variant(**changes))
    assert where in msg and words in msg


@pytest.mark.parametrize(
    ("check", "where", "words"),
    [
        (
            {"id": "c", "kind": "within", "quantity": "x", "tolerance": [1e-3] * 100000},
            "checks[0].tolerance",
            "must be a number",
        ),
        (
            {"id": "c", "kind": "within", "quantity": "x", "tolerance": -1},
            "checks[0].tolerance",
            "positive",
        ),
        (
            {"id": "c", "kind": "within", "quantity": "x", "tolerance": "inf"},
            "checks[0].tolerance",
            "",
        ),
        (
            {"id": "c", "kind": "within", "quantity": "x", "tolerance": True},
            "checks[0].tolerance",
            "number",
        ),
        ({"id": "c", "kind": "run-code", "quantity": "x"}, "checks[0].kind", "not one of"),
        (
            {"id": "c", "kind": "within", "quantity": "warp", "tolerance": 1},
            "checks[0].quantity",
            "unknown name",
        ),
        (
            {"id": "c", "kind": "in-plane", "normal": [0, 0, 0], "tolerance": 1},
            "checks[0].normal",
            "zero",
        ),
        (
            {"id": "c", "kind": "in-plane", "normal": [0, 1], "tolerance": 1},
            "checks[0].normal",
            "3 numbers",
        ),
        (
            {
                "id": "c",
                "kind": "in-plane",
                "path": ["x", "warp"],
                "normal": [0, 1],
                "tolerance": 1,
            },
            "checks[0].path[1]",
            "not a series",
        ),
        (
            {"id": "c", "kind": "reaches", "point": [1, 0, 0], "tolerance": 1},
            "checks[0].by",
            "missing",
        ),
        (
            {"id": "c", "kind": "reaches", "point": [1, 0, 0], "by": 99, "tolerance": 1},
            "checks[0].by",
            "outside the run",
        ),
        ({"id": "c", "kind": "at-most", "bound": 1}, "checks[0]", "exactly one"),
        (
            {"id": "c", "kind": "at-most", "quantity": "x", "reduce": "sum", "bound": 1},
            "checks[0].reduce",
            "one of",
        ),
        (
            {"id": "c", "kind": "at-most", "metric": "a.b", "bound": 1},
            "checks[0].metric",
            "metric name",
        ),
        (
            {"id": "c", "kind": "within", "quantity": "x", "tolerance": 1, "code": "x"},
            "checks[0]",
            "unknown field",
        ),
        (
            {"id": "c", "kind": "within", "quantity": "x", "tolerance": 1, "from": 5, "to": 2},
            "checks[0].from",
            "after",
        ),
        ("x > 0", "checks[0]", "must be an object"),
    ],
)
def test_hostile_checks_refused_naming_field(check: object, where: str, words: str) -> None:
    msg = refused(variant(checks=[check]))
    assert where in msg and words in msg


def test_too_many_checks_refused() -> None:
    checks = [
        {"id": f"c{k}", "kind": "within", "quantity": "x", "tolerance": 1}
        for k in range(MAX_CHECKS + 1)
    ]
    assert "limit" in refused(variant(checks=checks))


def test_files_malformed_oversize_or_deep_refused(tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text("{ not json")
    with pytest.raises(AssignmentError, match=r"bad\.json: is not valid JSON .*line 1"):
        load_assignment(bad)
    big = tmp_path / "big.json"
    big.write_text(json.dumps(variant(hint="h" * (MAX_FILE_BYTES + 10))))
    with pytest.raises(AssignmentError, match="limit"):
        load_assignment(big)
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 20000 + "]" * 20000)
    with pytest.raises(AssignmentError, match="deep.json"):
        load_assignment(deep)
    with pytest.raises(AssignmentError, match="cannot be read"):
        load_assignment(tmp_path / "missing.json")


def test_folder_refuses_duplicate_ids_and_names_the_file(tmp_path: Path) -> None:
    (tmp_path / "a.json").write_text(json.dumps(BASE))
    (tmp_path / "b.json").write_text(json.dumps(BASE))
    with pytest.raises(AssignmentError, match=r"b\.json: field id"):
        load_folder(tmp_path)
    (tmp_path / "b.json").write_text(json.dumps(variant(id="other", lesson="nope")))
    with pytest.raises(AssignmentError, match=r"b\.json: field lesson"):
        load_folder(tmp_path)


@pytest.mark.parametrize(
    ("answer", "words"),
    [
        ('{"x0": 0.5}', "field x0: is locked"),
        ('{"warp": 1}', "field warp: is not a parameter"),
        ('{"u1": "__import__(\\"os\\")"}', "field u1"),
        ('{"u1": [1, 2]}', "field u1: must be"),
        ('{"u1": "1e999"}', "field u1"),
        ("[1, 2]", "JSON object"),
        ("{}", "no values"),
        ("{'u1': 1}", "not valid JSON"),
    ],
)
def test_bad_answers_refused_in_one_line(answer: str, words: str) -> None:
    a = parse_assignment(BASE, "base")
    with pytest.raises(AssignmentError) as exc:
        grade(a, load_answer(answer, a, "ans.json"), "ans.json")
    assert str(exc.value).startswith("ans.json") and words in str(exc.value)


def test_draft_from_state_round_trips() -> None:
    data = draft(
        "circle",
        {"u": "2", "x0": 3, "y0": 4},
        ["u"],
        ["speed", "x"],
        assignment_id="my-circle",
        title="Mine",
        task="Do it again",
        preset="fig-1.13",
    )
    text = json.dumps(data)
    a = parse_assignment(json.loads(text), "draft.json")
    assert a.unlocked == ("u",) and a.answers["correct"] == {"u": "2"}
    assert grade(a, {"u": "2"}).passed
    assert not grade(a, {"u": "1"}).passed
    data = draft(
        "carriage-forced-vibration",
        {"w0": 4.992},
        ["w0"],
        [],
        metrics=["A0"],
        assignment_id="res",
        title="Resonance",
        task="Find it",
    )
    a = parse_assignment(data, "draft.json")
    assert grade(a, {"w0": 4.992}).passed
    failed = grade(a, {"w0": 4.0}).failed
    assert [c.id for c in failed] == ["a0-min"] and failed[0].miss > 0.5
    with pytest.raises(AssignmentError, match="not a numeric metric"):
        draft("circle", {}, ["u"], [], metrics=["nope"], assignment_id="x", title="x", task="x")
    with pytest.raises(AssignmentError, match=r"unlocked\[1\]: 'warp' is not a parameter"):
        draft("circle", {}, ["u", "warp"], ["x"], assignment_id="x", title="x", task="x")
    with pytest.raises(AssignmentError, match="not a series"):
        draft("circle", {}, ["u"], ["warp"], assignment_id="x", title="x", task="x")
