"""``run`` refuses runs over its stated limits before it starts, exits 2 on a result that
is not finite anywhere in the requested run, and bounds can be typed as printed."""

from __future__ import annotations

import subprocess
import sys
import time

import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.formula import plain_number
from analyzer_lab.lessons.kit.params import ParamError
from analyzer_lab.serve.run_limits import MAX_POINT_STEPS, MAX_VALUES, MAX_WORK, refusal


def cli(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "analyzer_lab", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def one_error_line(out: subprocess.CompletedProcess) -> str:
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert lines[0].startswith("analyzer-lab: error: ")
    return lines[0]


def test_a_result_not_finite_past_ten_t_end_exits_2_naming_quantity_and_time() -> None:
    out = cli("run", "sphere", "--set", "u1=exp(t)", "--t-end", "1000")
    assert out.returncode == 2 and out.stdout == ""
    line = one_error_line(out)
    assert "is not finite (NaN or infinite) from t = " in line
    name = line.split("error: ", 1)[1].split(" ", 1)[0]
    assert name in {"x", "y", "z", "vx", "vy", "vz", "speed", "v2", "drift"}
    at = float(line.split("from t = ", 1)[1].split(" s", 1)[0])
    assert 100 < at < 1000  # beyond 10 x t_end, within the requested run


@pytest.mark.parametrize(
    "args,words",
    [
        (("--set", "h=1.1e-5", "--t-end", "100000"), "integration steps"),
        (("--set", "family=24", "--t-end", "100000"), "integration steps"),
        (
            ("--set", "integrator=DOP853", "--set", "rtol=1e-14", "--t-end", "100000"),
            "units of work (counted on a piece of it)",
        ),
    ],
)
def test_runs_over_the_limits_are_refused_before_they_start(args: tuple, words: str) -> None:
    t0 = time.monotonic()
    out = cli("run", "sphere", *args)
    assert out.returncode == 2 and out.stdout == ""
    assert words in one_error_line(out)
    assert time.monotonic() - t0 < 30  # refused up front, not after hours


def test_the_limits_are_stated_in_help() -> None:
    out = cli("run", "--help")
    text = " ".join(out.stdout.split())
    assert out.returncode == 0
    assert f"{MAX_POINT_STEPS:,} fixed integration steps" in text
    assert f"more than {MAX_WORK:,} units of work" in text
    assert f"more than {MAX_VALUES:,} numbers" in text


def test_the_memory_limit_counts_samples_times_series(monkeypatch: pytest.MonkeyPatch) -> None:
    import analyzer_lab.serve.run_limits as limits

    lesson = get_lesson("sphere")
    assert refusal(lesson.open({"family": 24}), 10.0) is None
    monkeypatch.setattr(limits, "MAX_VALUES", 100_000)  # 1001 samples x 219 series
    why = refusal(lesson.open({"family": 24}), 10.0)
    assert why is not None and "1001 samples of 219 series" in why


def test_lessons_that_declare_undefined_values_still_run() -> None:
    out = cli("run", "motion-program", "--preset", "line-through-origin")
    assert out.returncode == 0, out.stderr


def test_the_stated_minimum_step_can_be_typed() -> None:
    out = cli("run", "sphere", "--set", "h=1e-5", "--t-end", "0.05")
    assert out.returncode == 0, out.stderr
    out = cli("run", "sphere", "--set", "h=9e-6", "--t-end", "0.05")
    assert out.returncode == 2
    assert "below the minimum 1e-05 s" in one_error_line(out)


def _bounded() -> list:
    return [
        (lesson, p)
        for lesson in all_lessons()
        for p in lesson.params
        if p.kind in ("float", "int") and (p.min is not None or p.max is not None)
    ]


@pytest.mark.parametrize("lesson,p", _bounded(), ids=lambda x: getattr(x, "id", None) or x.name)
def test_every_printed_bound_parses_back_to_the_bound(lesson, p) -> None:
    for bound in (p.min, p.max):
        if bound is None:
            continue
        text = plain_number(bound)
        assert p.parse(text) == bound
        assert p.parse(float(text)) == bound
    if p.min is not None and p.min != 0:
        below = p.min - 1 if p.kind == "int" else p.min - abs(p.min) * 1e-6
        with pytest.raises(ParamError) as exc:
            p.parse(plain_number(below))
        printed = str(exc.value).split("minimum ", 1)[1].split(" ", 1)[0]
        assert p.parse(printed) == p.min  # the printed minimum can be typed


@pytest.mark.parametrize(
    "value,text", [(1e-5, "1e-05"), (0.25, "0.25"), (3.0, "3"), (1.1e-5, "1.1e-05")]
)
def test_plain_numbers(value: float, text: str) -> None:
    import numpy as np

    assert plain_number(value) == text
    assert plain_number(np.float64(value)) == text


def test_out_refuses_a_symbolic_link_and_writes_nothing_through_it(tmp_path) -> None:
    target = tmp_path / "elsewhere.json"
    target.write_text("kept")
    link = tmp_path / "out.json"
    link.symlink_to(target)
    out = cli("run", "circle", "--out", str(link))
    assert out.returncode == 2 and "is a symbolic link; refused" in one_error_line(out)
    assert target.read_text() == "kept"
    dangling = tmp_path / "dangling.json"
    dangling.symlink_to(tmp_path / "new.json")
    out = cli("run", "circle", "--out", str(dangling))
    assert out.returncode == 2 and not (tmp_path / "new.json").exists()
    plain = tmp_path / "plain.json"
    out = cli("run", "circle", "--out", str(plain))
    assert out.returncode == 0, out.stderr
    assert plain.read_text().startswith("{")
