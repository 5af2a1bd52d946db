"""Varied assignments: each student's variant, the release check, placeholders and feedback."""

from __future__ import annotations

import copy
import json
import subprocess
import sys

import pytest
from analyzer_lab.lessons.assignments import (
    AssignmentError,
    grade,
    parse_assignment,
    ready_assignments,
    release,
    variant_for,
)
from analyzer_lab.lessons.assignments.space import MAX_POOL, seed, space_size
from analyzer_lab.lessons.assignments.variants import pool

READY = ready_assignments()
VARIED = [a for a in READY if a.varied]

SPEED = {
    "format": "analyzer-lab assignment",
    "version": 1,
    "id": "t-speed",
    "title": "Speed {v}",
    "lesson": "circle",
    "preset": "fig-1.13",
    "unlocked": ["u"],
    "checks": [
        {
            "id": "speed",
            "kind": "within",
            "quantity": "speed",
            "target": "{v}",
            "tolerance": 1e-6,
            "feedback": "The speed is |u| R <b>with</b> R = 5: aim at {v} m/s.",
            "feedback_pass": "Right: u = v / R.",
        }
    ],
    "task": "Make the speed {v} m/s (u = {v/5:.2f} would do).",
    "answers": {"correct": {"u": "{v/5}"}, "wrong": {"u": "{v/10}"}},
    "variables": {"v": {"from": 4, "to": 14, "step": 2}},
}


def speed(**changes: object) -> dict:
    d = copy.deepcopy(SPEED)
    d.update(changes)
    return d


def refused(data: dict) -> str:
    with pytest.raises(AssignmentError) as exc:
        a = parse_assignment(data, "broken.json")
        release(a)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("broken.json")
    return msg


def test_ten_or_more_ready_assignments_are_varied() -> None:
    assert len(VARIED) >= 10
    for a in VARIED:
        assert set(a.answers) == {"correct", "wrong"}
        assert len(pool(a)) >= 3, a.id


def test_two_students_get_different_numbers_one_student_the_same_twice() -> None:
    a = next(x for x in READY if x.id == "self-study-circle-speed")
    seen = {variant_for(a, "mech-101", f"student-{k}").index for k in range(40)}
    assert len(seen) >= 4  # 7 variants, 40 students
    first = variant_for(a, "mech-101", "ada")
    other = next(
        variant_for(a, "mech-101", f"student-{k}")
        for k in range(40)
        if variant_for(a, "mech-101", f"student-{k}").index != first.index
    )
    assert other.values != first.values
    assert other.assignment.checks[0].target != first.assignment.checks[0].target
    again = variant_for(a, "mech-101", "ada")
    assert again.values == first.values and again.assignment.task == first.assignment.task
    # the same numbers in another process (the seed is SHA-256, not Python's hash)
    code = (
        "import json; from analyzer_lab.lessons.assignments import ready_assignments, variant_for;"
        "a = [x for x in ready_assignments() if x.id == 'self-study-circle-speed'][0];"
        "print(json.dumps(variant_for(a, 'mech-101', 'ada').values))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=300,
        env={"PYTHONHASHSEED": "12345", "PATH": "/usr/bin:/bin"},
    )
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == dict(first.values)
    # another class or another assignment draws again
    assert seed("mech-101", "ada", a.id) != seed("mech-102", "ada", a.id)
    assert seed("mech-101", "ada", a.id) != seed("mech-101", "ada", "other")


def test_the_task_and_answers_carry_the_variant_numbers() -> None:
    a = parse_assignment(speed(), "speed.json")
    v = variant_for(a, "c", "ada")
    n = v.values["v"]
    assert v.assignment.task == f"Make the speed {n:g} m/s (u = {n / 5:.2f} would do)."
    assert v.assignment.title == f"Speed {n:g}"
    assert v.assignment.answers["correct"] == {"u": f"{n / 5:.12g}"}


@pytest.mark.parametrize("a", VARIED, ids=[a.id for a in VARIED])
def test_every_released_variant_passes_reference_and_fails_wrong(a) -> None:
    r = release(a)
    assert [v.index for v in r.variants] == list(pool(a))
    assert len({tuple(v.values.items()) for v in r.variants}) == len(r.variants)
    for v in r.variants:
        right = grade(v.assignment, v.assignment.answers["correct"])
        assert right.passed, (v.label, [c.message for c in right.failed])
        assert right.variant == dict(v.values)
        wrong = grade(v.assignment, v.assignment.answers["wrong"])
        assert not wrong.passed, v.label
    # a student only ever gets a released variant
    for k in range(12):
        got = r.for_student("mech-101", f"s{k}")
        assert got in r.variants
        assert got.index == variant_for(a, "mech-101", f"s{k}").index


def test_broken_space_refused_naming_the_variant() -> None:
    # the reference answer is right only for v = 4 and v = 14
    broken = speed(answers={"correct": {"u": "{4/5 + (v - 4)*(v - 14)}"}, "wrong": {"u": "{v/10}"}})
    msg = refused(broken)
    assert "field answers.correct" in msg
    assert "variant 1 (v = 6): the reference answer fails check speed" in msg
    # a wrong answer that is right for one variant
    msg = refused(speed(answers={"correct": {"u": "{v/5}"}, "wrong": {"u": "{8/5}"}}))
    assert "field answers.wrong" in msg and "variant 2 (v = 8): the wrong answer passes" in msg
    # a variant that is not even a valid assignment (negative tolerance for v = 14)
    bad = speed()
    bad["checks"] = [dict(SPEED["checks"][0], tolerance="{14.5 - v}")]
    bad["variables"] = {"v": {"choices": [14, 15]}}
    msg = refused(bad)
    assert "field checks[0].tolerance: variant 1 (v = 15): must be positive" in msg


@pytest.mark.parametrize(
    ("changes", "words"),
    [
        (
            {"task": "{__import__('os').system('touch /tmp/pwned')}"},
            "field task: variant 0 (v = 4): placeholder",
        ),
        ({"task": "{v; import os}"}, "not allowed"),
        ({"task": "{w}"}, "unknown name 'w'"),
        ({"task": "{v:!r}"}, "format"),
        ({"task": "a { brace"}, "not a placeholder"),
        ({"variables": {"v": {"from": 1, "to": 2, "step": 0}}}, "field variables.v.step"),
        ({"variables": {"v": {"from": 3, "to": 2, "step": 1}}}, "field variables.v.to"),
        ({"variables": {"t": {"choices": [1]}}}, "field variables.t"),
        ({"variables": {"v": {"choices": [1, 1]}}}, "names a value twice"),
        ({"variables": {"v": {"range": [1, 2]}}}, "from', 'to' and 'step', or 'choices'"),
        ({"variables": {"v": {"choices": ["exec(1)"]}}}, "field variables.v.choices[0]"),
        ({"variables": {"v": {"from": 1, "to": 300, "step": 1}}}, "variants.sample"),
        ({"variants": {"sample": 7}}, "field variants.sample"),
        ({"answers": {"correct": {"u": "{v/5}"}}}, "a 'correct' (reference) and a 'wrong'"),
    ],
)
def test_bad_variables_and_placeholders_refused_in_one_line(changes: dict, words: str) -> None:
    msg = refused(speed(**changes))
    assert words in msg, msg
    assert "Traceback" not in msg


def test_a_declared_sample_is_what_is_checked_and_handed_out() -> None:
    a = parse_assignment(
        speed(variables={"v": {"from": 1, "to": 300, "step": 1}}, variants={"sample": 5}),
        "s.json",
    )
    assert space_size(a.variables) == 300 > MAX_POOL
    indices = pool(a)
    assert len(indices) == 5 and len(set(indices)) == 5
    assert indices == pool(parse_assignment(copy.deepcopy(a.data), "again.json"))
    r = release(a)
    assert [v.index for v in r.variants] == list(indices)
    assert {variant_for(a, "c", f"s{k}").index for k in range(30)} <= set(indices)


def test_feedback_with_the_measured_miss() -> None:
    a = parse_assignment(speed(variables={"v": {"choices": [6]}}), "f.json")
    wrong = grade(a, {"u": "0.6"})
    out = wrong.checks[0]
    assert not out.passed and out.miss == pytest.approx(3.0, rel=1e-6)
    assert out.feedback == "The speed is |u| R <b>with</b> R = 5: aim at 6 m/s."
    assert wrong.to_json_dict()["checks"][0]["feedback"] == out.feedback
    right = grade(a, {"u": "1.2"})
    assert right.checks[0].feedback == "Right: u = v / R."
    from analyzer_lab.classroom.assignments import verdict_html

    page = verdict_html(wrong)
    assert "&lt;b&gt;with&lt;/b&gt;" in page and "<b>with</b>" not in page
    assert "misses the tolerance 1e-06 by 3" in page
    assert "al-check-feedback" in page
    assert "Right: u = v / R." in verdict_html(right)


def test_unvaried_assignments_are_their_own_only_variant() -> None:
    a = next(x for x in READY if x.id == "circle-radius-2")
    assert not a.varied and pool(a) == (0,)
    v = variant_for(a, "c", "anyone")
    assert v.assignment is a and v.values == {}
    r = release(a)
    assert r.for_student("c", "x").assignment is a and r.runs == 2
