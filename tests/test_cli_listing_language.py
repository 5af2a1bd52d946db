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
