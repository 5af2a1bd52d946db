"""``run``'s limits are counts, never timings: every preset of every lesson runs at its
own ``t_end``, a one-time model build is never counted as stepping, and a refusal is the
same on a busy machine as on a quiet one."""

from __future__ import annotations

import subprocess
import sys

import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.budget import WorkLimitError, charge, work_limit
from analyzer_lab.serve.headless import AnalyzerLabError, run_lesson
from analyzer_lab.serve.run_limits import MAX_WORK, refusal, work_estimate

pytestmark = pytest.mark.timeout(900)


def cli(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "analyzer_lab", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _presets() -> list[tuple[str, str | None]]:
    return [
        (lesson.id, preset)
        for lesson in all_lessons()
        for preset in [None, *(p.name for p in lesson.presets)]
    ]


@pytest.mark.slow
def test_every_preset_of_every_lesson_runs_at_its_own_t_end() -> None:
    failed = []
    for lesson_id, preset in _presets():
        try:
            result = run_lesson(get_lesson(lesson_id), preset, {}, None)
        except AnalyzerLabError as exc:
            failed.append(f"{lesson_id} {preset}: {exc}")
            continue
        assert len(result.t) > 1, (lesson_id, preset)
    assert failed == []


@pytest.mark.parametrize(
    "args",
    [
        ("table-6dof", "--preset", "inverse-program"),
        ("table-6dof", "--preset", "forward-tracking"),
        ("sphere-constant-speed", "--preset", "example-1.3-zero-field"),
    ],
)
def test_a_lessons_own_example_exits_0_from_the_command_line(args: tuple[str, ...]) -> None:
    out = cli("run", *args)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("{")


def test_the_model_build_is_not_counted() -> None:
    # the 6-DOF table's model is derived and lambdified when its first stepper is built
    # (seconds): its inverse program steps a closed form, counted as nothing
    setup = get_lesson("table-6dof").open({}, "inverse-program")
    assert work_estimate(setup, 10.0) == 0.0
    assert refusal(get_lesson("table-6dof").open({}, "inverse-program"), 10.0) is None


def test_the_count_stops_a_run_where_it_passes_the_limit() -> None:
    with work_limit(100) as count:
        charge(60)
        with pytest.raises(WorkLimitError) as exc:
            charge(60)
    assert count.used == 120
    assert "more than 100 units of work" in str(exc.value)
    charge(1e18)  # no limit outside: nothing is counted


def test_a_run_counted_past_the_limit_is_refused_while_it_runs(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import analyzer_lab.serve.run_limits as limits

    lesson = get_lesson("constrained-dynamics")
    monkeypatch.setattr(limits, "work_estimate", lambda setup, t_end: 0.0)
    monkeypatch.setattr(limits, "MAX_WORK", 10_000)
    with pytest.raises(AnalyzerLabError) as exc:
        run_lesson(lesson, "rheonomic-pendulum", {}, None)
    assert "more than 10,000 units of work" in str(exc.value)


def _refusal_line(args: tuple[str, ...]) -> tuple[int, str, str]:
    out = cli("run", *args)
    return out.returncode, out.stdout, out.stderr


BUSY = "import time\nend = time.monotonic() + 600\nwhile time.monotonic() < end:\n    pass\n"

REFUSED = [
    ("sphere-constant-speed", "--t-end", "99999"),
    ("sphere", "--set", "integrator=DOP853", "--set", "rtol=1e-14", "--t-end", "100000"),
]


@pytest.mark.slow
def test_refusals_are_the_same_on_a_busy_and_a_quiet_machine() -> None:
    quiet = [_refusal_line(args) for args in REFUSED]
    busy = [subprocess.Popen([sys.executable, "-c", BUSY]) for _ in range(2)]
    try:
        loaded = [_refusal_line(args) for args in REFUSED]
    finally:
        for proc in busy:
            proc.kill()
            proc.wait()
    assert loaded == quiet
    for code, stdout, stderr in quiet:
        assert code == 2 and stdout == ""
        assert "units of work" in stderr and f"{MAX_WORK:,}" in stderr
