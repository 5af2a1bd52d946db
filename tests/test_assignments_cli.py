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


def test_a_5000_digit_whole_number_is_a_clear_refusal(tmp_path: Path) -> None:
    out = cli("grade", "circle-radius-2", answer(tmp_path, '{"x0": ' + "9" * 5000 + "}"))
    assert out.returncode == 2, out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr
    assert "holds a whole number of 5000 digits; the limit is 100" in lines[0]
