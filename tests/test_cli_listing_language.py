"""The listings of ``lessons`` and ``assignments`` and the refusals of ``grade`` in the
command's language (``--lang``, else the environment's); real subprocesses."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.timeout(300)


def cli(*args: str, lang: str = "C.UTF-8") -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("LC_ALL", "LC_MESSAGES", "LANG")}
    env["LANG"] = lang
    return subprocess.run(
        [sys.executable, "-m", "analyzer_lab", *args],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )


def test_lessons_lists_params_and_presets_in_the_environment_language() -> None:
    ru = cli("lessons", lang="ru_RU.UTF-8")
    assert ru.returncode == 0, ru.stderr
    assert "параметры: " in ru.stdout and "примеры: " in ru.stdout
    assert "params:" not in ru.stdout and "presets:" not in ru.stdout
    en = cli("lessons")
    assert "params: " in en.stdout and "параметры" not in en.stdout


def test_assignments_lists_in_russian_with_lang() -> None:
    ru = cli("--lang", "ru", "assignments")
    assert ru.returncode == 0, ru.stderr
    count = len(json.loads(cli("assignments", "--json").stdout))
    assert ru.stdout.rstrip().endswith(f"заданий: {count}")
    assert "вы задаёте: " in ru.stdout and "; проверки: " in ru.stdout
    assert "you set:" not in ru.stdout and "assignments\n" not in ru.stdout
    en = cli("--lang", "en", "assignments", lang="ru_RU.UTF-8")  # --lang wins
    assert en.stdout.rstrip().endswith(f"{count} assignments")


def test_grade_refusals_in_russian(tmp_path: Path) -> None:
    unknown = cli("--lang", "ru", "grade", "no-such-task", "a.json")
    assert unknown.returncode == 2
    assert unknown.stderr.strip() == (
        "analyzer-lab: ошибка: 'no-such-task': такого задания нет "
        "(их перечисляет 'analyzer-lab assignments')"
    )
    missing = tmp_path / "missing.json"
    gone = cli("grade", "sphere-equator", str(missing), lang="ru_RU.UTF-8")
    assert gone.returncode == 2
    assert f"{missing}: не читается (" in gone.stderr and "cannot be read" not in gone.stderr
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"u1": [1]}))
    many = cli("--lang", "ru", "grade", "sphere-equator", str(bad), str(bad))
    assert many.returncode == 2
    assert f"analyzer-lab: ошибка: {bad}: поле u1: " in many.stderr
    assert "проверено файлов: 2; пройдено: 0, не пройдено: 0, отклонено: 2" in many.stderr
    english = cli("grade", "no-such-task", "a.json")
    assert "no such assignment" in english.stderr and "error:" in english.stderr


def test_grade_fail_lines_in_russian(tmp_path: Path) -> None:
    """A real ``--lang ru grade``: each failing check's line in Russian (decimal commas),
    the JSON verdict's English text unchanged; the same answer in English."""
    answer = tmp_path / "s1.json"
    answer.write_text(json.dumps({"u1": "0.5", "u2": 0, "u3": 0}))
    ru = cli("--lang", "ru", "grade", "sphere-equator", str(answer))
    assert ru.returncode == 1, ru.stderr
    fails = [line for line in ru.stderr.splitlines() if line.strip()]
    assert fails and all(line.startswith("НЕ ПРОЙДЕНА ") for line in fails), fails
    speed = next(line for line in fails if line.startswith("НЕ ПРОЙДЕНА speed: "))
    assert "наибольшее при t = " in speed and "превышает допуск 1e-06 на " in speed, speed
    assert "FAIL" not in ru.stderr and "misses the tolerance" not in ru.stderr
    message = next(c["message"] for c in json.loads(ru.stdout)["checks"] if c["id"] == "speed")
    assert "misses the tolerance 1e-06 by " in message  # the verdict's data stays English
    en = cli("grade", "sphere-equator", str(answer))
    assert en.returncode == 1 and f"FAIL speed: {message}" in en.stderr.splitlines()


def test_grade_run_limit_and_answer_refusals_in_russian(tmp_path: Path) -> None:
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
    small = tmp_path / "small-step.json"
    small.write_text(json.dumps({"V": "1", "h": 1e-5}))
    ru = cli("--lang", "ru", "grade", str(path), str(small))
    assert ru.returncode == 2
    assert ru.stderr.startswith(f"analyzer-lab: ошибка: {small}: этому расчёту нужно 2e+07 ")
    assert "шагов интегрирования" in ru.stderr and "предел 10\u00a0000\u00a0000" in ru.stderr
    assert "уменьшите t_end задания" in ru.stderr and "integration steps" not in ru.stderr
    en = cli("grade", str(path), str(small))
    assert "the limit is 10,000,000: use a larger h, a shorter the assignment's t_end" in en.stderr
    locked = tmp_path / "locked.json"
    locked.write_text(json.dumps({"u1": 1, "zz": 0}))
    ru = cli("--lang", "ru", "grade", "sphere-equator", str(locked))
    assert ru.stderr.strip() == (
        f"analyzer-lab: ошибка: {locked}: поле zz: не является параметром (можно задать u1, u2, u3)"
    )
    en = cli("grade", "sphere-equator", str(locked))
    assert en.stderr.strip() == (
        f"analyzer-lab: error: {locked}: field zz: is not a parameter (you may set u1, u2, u3)"
    )


def test_assignments_list_their_russian_titles() -> None:
    ru = cli("--lang", "ru", "assignments")
    assert ru.returncode == 0, ru.stderr
    assert "Окружность радиуса 2" in ru.stdout and "A circle of radius 2" not in ru.stdout
    en = cli("assignments")
    assert "A circle of radius 2" in en.stdout and "Окружность радиуса 2" not in en.stdout
    titles = {a["id"]: a["title_ru"] for a in json.loads(cli("assignments", "--json").stdout)}
    assert all(titles.values()), [k for k, v in titles.items() if not v]
