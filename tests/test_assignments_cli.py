"""``analyzer-lab assignments`` and ``grade``: output and exit codes (real subprocesses)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from analyzer_lab.lessons.assignments import ready_assignments


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "analyzer_lab", *args], capture_output=True, text=True, timeout=300
    )


def answer(tmp_path: Path, values: object, name: str = "answer.json") -> str:
    p = tmp_path / name
    p.write_text(values if isinstance(values, str) else json.dumps(values))
    return str(p)


def test_assignments_json_lists_every_ready_one() -> None:
    out = cli("assignments", "--json")
    assert out.returncode == 0, out.stderr
    items = json.loads(out.stdout)
    assert [i["id"] for i in items] == [a.id for a in ready_assignments()]
    first = items[0]
    assert {"id", "lesson", "unlocked", "checks", "task", "hint", "reference"} <= set(first)
    text = cli("assignments")
    assert text.returncode == 0 and f"{len(items)} assignments" in text.stdout


def test_grade_pass_exit_0_and_fail_exit_1_naming_the_check(tmp_path: Path) -> None:
    ok = cli("grade", "circle-radius-2", answer(tmp_path, {"x0": 2, "y0": 0}))
    assert ok.returncode == 0, ok.stderr
    doc = json.loads(ok.stdout)
    assert doc["pass"] is True and doc["checks"][0]["id"] == "on-circle"
    bad = cli("grade", "circle-radius-2", answer(tmp_path, {"x0": 3, "y0": 4}))
    assert bad.returncode == 1
    doc = json.loads(bad.stdout)
    assert doc["pass"] is False
    check = doc["checks"][0]
    assert check["pass"] is False and check["miss"] == pytest.approx(3.0, rel=1e-6)
    assert "FAIL on-circle" in bad.stderr


def test_grade_a_file_path_and_dir(tmp_path: Path) -> None:
    a = ready_assignments()[0]
    src = Path(a.source)
    out = cli("grade", str(src), answer(tmp_path, a.answers["correct"]))
    assert out.returncode == 0, out.stderr
    out = cli("grade", a.id, answer(tmp_path, a.answers["wrong"]), "--dir", str(src.parent))
    assert out.returncode == 1


@pytest.mark.parametrize(
    ("values", "words"),
    [
        ({"x0": "__import__('os').system('touch /tmp/pwned')"}, "answer.json: field x0:"),
        ({"u": "1"}, "answer.json: field u: is locked"),
        ({"R9": 1}, "answer.json: field R9: is not a parameter"),
        ("{broken", "answer.json: is not valid JSON"),
        ({"x0": 1e300}, "answer.json: field x0"),
        ([1], "answer.json: an answer is a JSON object"),
    ],
)
def test_grade_bad_answer_exit_2_one_line(tmp_path: Path, values: object, words: str) -> None:
    out = cli("grade", "circle-radius-2", answer(tmp_path, values))
    assert out.returncode == 2
    assert out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], out.stderr


def test_grade_bad_assignment_exit_2(tmp_path: Path) -> None:
    ans = answer(tmp_path, {"u1": "1"})
    out = cli("grade", "no-such-assignment", ans)
    assert out.returncode == 2 and "no such assignment" in out.stderr
    hostile = tmp_path / "hostile.json"
    hostile.write_text(
        json.dumps(
            {
                "format": "analyzer-lab assignment",
                "version": 1,
                "id": "h",
                "title": "h",
                "lesson": "sphere",
                "unlocked": ["u1"],
                "checks": [{"id": "c", "kind": "within", "quantity": "exec(t)", "tolerance": 1}],
                "task": "h",
            }
        )
    )
    out = cli("grade", str(hostile), ans)
    assert out.returncode == 2
    assert "hostile.json: field checks[0].quantity: function 'exec' is not allowed" in out.stderr
    out = cli("grade", "circle-radius-2", str(tmp_path / "missing.json"))
    assert out.returncode == 2 and "cannot be read" in out.stderr
    out = cli("assignments", "--dir", str(tmp_path / "nowhere"))
    assert out.returncode == 2 and "is not a folder" in out.stderr


def test_serve_refuses_invalid_assignment_folder(tmp_path: Path) -> None:
    (tmp_path / "bad.json").write_text('{"format": "analyzer-lab assignment", "version": 1}')
    out = cli("serve", "--no-browser", "--port", "1", "--assignments", str(tmp_path))
    assert out.returncode == 2
    assert "bad.json: field id: is missing" in out.stderr


# ------------------------------------------------------------------ many files in one call


def lines(out: subprocess.CompletedProcess) -> list[dict]:
    return [json.loads(line) for line in out.stdout.splitlines()]


def test_batch_grade_json_lines_and_exit_codes_over_the_batch(tmp_path: Path) -> None:
    folder = tmp_path / "answers"
    folder.mkdir()
    answer(folder, {"x0": 2, "y0": 0}, "a-right.json")
    answer(folder, {"x0": 0, "y0": -2}, "b-right.json")
    answer(folder, {"x0": 3, "y0": 4}, "c-wrong.json")
    answer(folder, "not json", "notes.txt")  # not an answer file: left out
    out = cli("grade", "circle-radius-2", str(folder))
    assert out.returncode == 1, out.stderr
    docs = lines(out)
    assert [Path(d["file"]).name for d in docs] == ["a-right.json", "b-right.json", "c-wrong.json"]
    assert [d["pass"] for d in docs] == [True, True, False]
    assert docs[2]["checks"][0]["miss"] == pytest.approx(3.0, rel=1e-6)
    assert "graded 3 file(s): 2 pass, 1 fail, 0 refused" in out.stderr
    # all pass: 0; a refused file anywhere: 2, and the others are still graded
    out = cli(
        "grade", "circle-radius-2", str(folder / "a-right.json"), str(folder / "b-right.json")
    )
    assert out.returncode == 0 and [d["pass"] for d in lines(out)] == [True, True]
    bad = answer(tmp_path, {"x0": "__import__('os')"}, "bad.json")
    out = cli("grade", "circle-radius-2", bad, str(folder))
    assert out.returncode == 2
    docs = lines(out)
    assert len(docs) == 4 and "error" in docs[0] and "field x0" in docs[0]["error"]
    assert [d.get("pass") for d in docs[1:]] == [True, True, False]
    assert "1 refused" in out.stderr
    out = cli("grade", "circle-radius-2", str(tmp_path / "none.json"), str(folder))
    assert out.returncode == 2 and "cannot be read" in lines(out)[0]["error"]


def test_batch_grade_of_a_varied_assignment_uses_each_students_variant(tmp_path: Path) -> None:
    from analyzer_lab.lessons.assignments import variant_for

    a = next(x for x in ready_assignments() if x.id == "self-study-circle-speed")
    students = [f"student-{k}" for k in range(6)]
    for name in students:  # each answers their own numbers in class mech-101
        v = variant_for(a, "mech-101", name)
        answer(tmp_path, dict(v.assignment.answers["correct"]), f"{name}.json")
    out = cli("grade", a.id, str(tmp_path), "--class", "mech-101")
    assert out.returncode == 0, out.stderr
    docs = lines(out)
    assert [d["student"] for d in docs] == students
    for d, name in zip(docs, students, strict=True):
        assert d["variant"] == dict(variant_for(a, "mech-101", name).values)
    # in another class the same files meet other numbers: exactly those whose variant differs fail
    out = cli("grade", a.id, str(tmp_path), "--class", "mech-202")
    expected = [
        variant_for(a, "mech-202", n).values == variant_for(a, "mech-101", n).values
        for n in students
    ]
    assert [d["pass"] for d in lines(out)] == expected
    assert out.returncode == (0 if all(expected) else 1)
    # --student names one student for every file
    one = cli("grade", a.id, str(tmp_path / "student-0.json"), "--student", "student-0")
    assert (
        one.returncode == 1
        or variant_for(a, "class", "student-0").values
        == variant_for(a, "mech-101", "student-0").values
    )
    assert json.loads(one.stdout)["student"] == "student-0"


def test_grade_holds_each_run_to_the_run_limits(tmp_path: Path) -> None:
    spec = {
        "format": "analyzer-lab assignment",
        "version": 1,
        "id": "long-run",
        "title": "Long run",
        "lesson": "sphere-constant-speed",
        "preset": "varying-controls",
        "t_end": 200,
        "unlocked": ["V", "h"],
        "checks": [
            {"id": "speed", "kind": "within", "quantity": "speed", "target": "1", "tolerance": 1e-6}
        ],
        "task": "Constant speed.",
    }
    path = tmp_path / "long-run.json"
    path.write_text(json.dumps(spec))
    small = answer(tmp_path, {"V": "1", "h": 1e-5}, "small-step.json")
    out = cli("grade", str(path), small, small)
    assert out.returncode == 2
    docs = lines(out)
    assert len(docs) == 2 and all("integration steps" in d["error"] for d in docs)
    assert "small-step.json" in docs[0]["error"] and "the limit is 10,000,000" in docs[0]["error"]


def test_grade_draws_for_the_same_default_class_as_the_board() -> None:
    from analyzer_lab.lessons.assignments.space import DEFAULT_CLASS
    from analyzer_lab.serve.cli_assignments import DEFAULT_CLASS as CLI_CLASS

    assert CLI_CLASS == DEFAULT_CLASS


def test_a_5000_digit_whole_number_is_a_clear_refusal(tmp_path: Path) -> None:
    out = cli("grade", "circle-radius-2", answer(tmp_path, '{"x0": ' + "9" * 5000 + "}"))
    assert out.returncode == 2, out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr
    assert "holds a whole number of 5000 digits; the limit is 100" in lines[0]
