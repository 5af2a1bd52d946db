"""The headless command line: output shape and exit codes (run as a real subprocess)."""

import csv
import io
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

#: The environment variables of the user's language (the command line speaks it).
LANGUAGE_VARIABLES = ("LC_ALL", "LC_MESSAGES", "LANG", "ANALYZER_LAB_LANG")


def cli(*args, timeout=300, lang="C.UTF-8"):
    """``python -m analyzer_lab ...`` with ``LANG=lang`` (English unless told)."""
    env = {k: v for k, v in os.environ.items() if k not in LANGUAGE_VARIABLES}
    return subprocess.run(
        [sys.executable, "-m", "analyzer_lab", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**env, "LANG": lang},
    )


def test_lessons_json_lists_sphere():
    out = cli("lessons", "--json")
    assert out.returncode == 0, out.stderr
    items = json.loads(out.stdout)
    sphere = next(i for i in items if i["id"] == "sphere")
    assert "Problem 1.4" in sphere["problem"]
    assert {"u1", "u2", "u3", "x0", "y0", "z0", "R"} <= {p["name"] for p in sphere["params"]}
    assert "example-1.1" in {p["name"] for p in sphere["presets"]}


def test_run_json_example_1_1(tmp_path):
    out = cli("run", "sphere", "--preset", "example-1.1", "--format", "json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert set(doc) >= {"lesson", "preset", "params", "t", "series", "metrics"}
    assert doc["lesson"] == "sphere" and doc["preset"] == "example-1.1"
    assert {"x", "y", "z", "vx", "vy", "vz"} <= set(doc["series"])
    assert doc["t"][-1] == pytest.approx(10.0)
    v2 = (
        np.array(doc["series"]["vx"]) ** 2
        + np.array(doc["series"]["vy"]) ** 2
        + np.array(doc["series"]["vz"]) ** 2
    )
    assert np.abs(v2 - 50).max() < 1e-9


def test_run_csv_to_file_with_set(tmp_path):
    path = tmp_path / "run.csv"
    out = cli(
        "run",
        "sphere",
        "--set",
        "u1=t",
        "--set",
        "u2=2",
        "--t-end",
        "2",
        "--format",
        "csv",
        "--out",
        str(path),
    )
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(io.StringIO(path.read_text())))
    assert rows[0][:7] == ["t", "x", "y", "z", "vx", "vy", "vz"]
    assert float(rows[-1][0]) == pytest.approx(2.0)


@pytest.mark.parametrize(
    "args, needle",
    [
        (("run", "nosuch"), "unknown lesson"),
        (("run", "sphere", "--set", "bogus=1"), "unknown parameter"),
        (("run", "sphere", "--set", "u1=__import__('os')"), "u1"),
        (("run", "sphere", "--set", "x0=nan"), "x0"),
        (("run", "sphere", "--set", "R=inf"), "R"),
        (("run", "sphere", "--preset", "example-9"), "unknown preset"),
        (("run", "sphere", "--set", "novalue"), "NAME=VALUE"),
        (("run", "sphere", "--t-end", "nan"), "t-end"),
    ],
)
def test_run_bad_input_exit_2_one_line(args, needle):
    out = cli(*args)
    assert out.returncode == 2
    lines = [l for l in out.stderr.splitlines() if l.strip()]
    assert len(lines) == 1 and needle in lines[0], out.stderr
    assert out.stdout == ""


def test_run_off_surface_start_is_projected_with_note():
    out = cli("run", "sphere", "--set", "x0=2", "--set", "y0=0", "--set", "z0=0", "--t-end", "1")
    assert out.returncode == 0
    doc = json.loads(out.stdout)
    assert any("projected" in m for m in doc["messages"])
    assert doc["series"]["x"][0] == pytest.approx(1.0)
    assert "projected" in out.stderr


def test_check_sphere_passes_and_reports():
    out = cli("check", "sphere")
    assert out.returncode == 0, out.stdout + out.stderr
    assert "claims pass" in out.stdout and "FAIL" not in out.stdout
    assert "expected" in out.stdout and "got" in out.stdout


def test_check_unknown_lesson_exit_2():
    assert cli("check", "nosuch").returncode == 2


def test_serve_with_an_unknown_language_says_so_in_english(tmp_path):
    """The notice comes first; the command goes on (here to refuse the port)."""
    out = cli("serve", "--lang", "xx", "--port", "70000", "--no-browser", "--data", str(tmp_path))
    assert out.returncode == 2
    lines = out.stderr.splitlines()
    assert lines[0] == (
        "analyzer-lab: note: unknown language 'xx'; English is shown (known: en, ru)"
    )
    assert "port must be in 0..65535" in out.stderr
    ok = cli("serve", "--lang", "ru", "--port", "70000", "--no-browser", "--data", str(tmp_path))
    assert ok.returncode == 2 and "unknown language" not in ok.stderr


@pytest.mark.live
def test_serve_lang_ru_makes_new_pages_russian(serve):
    import asyncio

    from tests.support.client import ProtoClient

    live = serve("sphere", "--lang", "ru")

    async def go():
        c = await ProtoClient(live.url).start()
        try:
            await c.wait_for("Урок", timeout=60)
            await c.wait_for("Движение")
            assert "Lesson" not in c.gui and "Run" not in c.gui
        finally:
            await c.close()

    asyncio.run(go())


def test_the_command_line_speaks_russian_under_lang_ru_and_english_by_default(tmp_path):
    """``LANG=ru_RU.UTF-8`` (or ``serve --lang ru``): the command's messages and errors in
    Russian, numbers with a decimal comma; the data it writes stays machine-readable."""
    ru = cli("run", "sphere", "--set", "h=0.5", lang="ru_RU.UTF-8")
    assert ru.returncode == 2 and ru.stdout == ""
    assert ru.stderr.strip() == "analyzer-lab: ошибка: h: 0,5 больше максимума 0,1 с"
    en = cli("run", "sphere", "--set", "h=0.5")
    assert en.stderr.strip() == "analyzer-lab: error: h: 0.5 is above the maximum 0.1 s"
    # a language the lab does not speak: English, without a word about it
    de = cli("run", "sphere", "--set", "h=0.5", lang="de_DE.UTF-8")
    assert de.stderr == en.stderr
    workers = ["serve", "--workers", "99", "--no-browser", "--data", str(tmp_path)]
    ru = cli(*workers, "--lang", "ru")
    assert ru.returncode == 2
    assert "analyzer-lab: ошибка: --workers должно быть в 1..64, получено 99" in ru.stderr
    assert "error" not in ru.stderr
    en = cli(*workers)
    assert "analyzer-lab: error: --workers must be in 1..64, got 99" in en.stderr
    # the run's data is the same in both languages (a dot, the ASCII column names)
    args = ("run", "sphere", "--preset", "example-1.1", "--t-end", "1", "--format", "csv")
    ru_run, en_run = cli(*args, lang="ru_RU.UTF-8"), cli(*args)
    assert ru_run.returncode == 0 and ru_run.stdout == en_run.stdout
    assert ru_run.stdout.startswith("t,x,y,z")


def test_the_russian_readme_gives_the_two_start_commands_and_readme_links_it():
    """README.ru.md's start commands are commands the parser takes (serve, --lang ru)."""
    import pathlib
    import shlex

    from analyzer_lab.serve.cli import build_parser

    root = pathlib.Path(__file__).resolve().parents[1]
    text = (root / "README.ru.md").read_text(encoding="utf-8")
    commands = [l for l in text.splitlines() if l.startswith("analyzer-lab serve")]
    assert commands == [
        "analyzer-lab serve --no-browser",
        "analyzer-lab serve --lang ru --no-browser",
    ]
    langs = [build_parser().parse_args(shlex.split(c)[1:]).lang for c in commands]
    assert langs == [None, "ru"]
    assert "(README.ru.md)" in (root / "README.md").read_text(encoding="utf-8")


#: The commands whose help is checked (the main parser's is ``()``).
HELP_COMMANDS = [(), *[(c,) for c in ("serve", "grades", "lessons", "run", "check")]]
HELP_COMMANDS += [("assignments",), ("grade",)]
#: Latin words the Russian help keeps: the commands, option values, names and formats.
KEPT_WORDS = {
    *("serve", "grades", "lessons", "run", "check", "assignments", "grade", "analyzer", "lab"),
    *("en", "ru", "pseudo", "json", "csv", "moodle", "canvas", "local", "redis", "default"),
    *("sqlite", "postgresql", "email", "feedback", "assignment", "for", "t_end", "h", "s"),
    *("lesson", "class"),
}


def english_words(help_text: str) -> list[str]:
    """The Latin words of a help text that are not an option, a metavar, a path, an
    address, a placeholder or a kept word."""
    words = []
    for token in help_text.split():
        token = token.strip(".,;:()[]'\"")
        if token.startswith(("-", "$", "~", "{", "<")) or "://" in token or "/" in token:
            continue
        for word in re.findall(r"[A-Za-z_]+", token):
            if not word.isupper() and word.lower() not in KEPT_WORDS:
                words.append(word)
    return words


@pytest.mark.parametrize("command", HELP_COMMANDS, ids=lambda c: " ".join(c) or "main")
def test_the_help_is_russian_under_lang_ru(command):
    """``LANG=ru_RU.UTF-8 analyzer-lab [COMMAND] --help``: argparse's own words and every
    option's help in Russian; no English left but option names, metavars and kept words."""
    out = cli(*command, "--help", lang="ru_RU.UTF-8")
    assert out.returncode == 0, out.stderr
    text = out.stdout
    assert text.startswith("использование: analyzer-lab")
    assert "параметры:" in text and "показать эту справку и выйти" in text
    for english in ("usage:", "options:", "show this help", "positional arguments", "default"):
        assert english not in text.replace("'default'", "")
    assert english_words(text) == []
    # every argument has its help, in Russian (the list of commands aside)
    entries = re.split(r"\n(?=  \S|    \S)", text.split("\n\n", 1)[1])
    entries = [e for e in entries if e.startswith(" ") and not e.strip().startswith("{")]
    assert entries and [e for e in entries if not re.search("[а-я]", e)] == []
    assert english_words(cli(*command, "--help").stdout) != []  # the check sees English


def test_the_help_follows_the_lang_option_before_the_environment():
    """``--lang`` (the main parser's, or serve's) chooses the help's language over
    ``LANG``; English by default and for a language the lab does not speak."""
    ru = cli("--lang", "ru", "serve", "--help")
    assert ru.stdout.startswith("использование: analyzer-lab serve")
    assert "язык новых страниц и сообщений команды" in ru.stdout
    assert cli("serve", "--lang=ru", "--help").stdout == ru.stdout
    assert cli("serve", "--lang", "ru", "--help", lang="de_DE.UTF-8").stdout == ru.stdout
    en = cli("serve", "--help")
    assert cli("--lang", "en", "serve", "--help", lang="ru_RU.UTF-8").stdout == en.stdout
    assert cli("serve", "--help", lang="de_DE.UTF-8").stdout == en.stdout
    assert en.stdout.startswith("usage: analyzer-lab serve")
    assert "show this help message and exit" in en.stdout
    assert "the language of new pages" in en.stdout
    assert re.search("[а-яА-Я]", en.stdout) is None
    main = cli("--help").stdout
    assert "positional arguments:" in main and "options:" in main
    assert "start the browser lab" in main


def test_the_parsers_refusals_are_russian_under_lang_ru():
    """argparse's refusals (a wrong value, a missing argument, an unknown option) in the
    command's language; the option's name and the value as typed."""
    bad = cli("run", "sphere", "--format", "xml", lang="ru_RU.UTF-8")
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.startswith("использование: analyzer-lab run")
    last = bad.stderr.strip().splitlines()[-1]
    assert last == (
        "analyzer-lab run: ошибка: аргумент --format: недопустимый вариант: 'xml'"
        " (возможны: 'json', 'csv')"
    )
    missing = cli("--lang", "ru", "grade").stderr.strip().splitlines()[-1]
    assert missing == (
        "analyzer-lab grade: ошибка: не хватает обязательных аргументов: assignment,"
        " FOLDER_OR_FILES"
    )
    en = cli("run", "sphere", "--port", "1").stderr.strip().splitlines()[-1]
    assert en == "analyzer-lab: error: unrecognized arguments: --port 1"
    ru = cli("--lang", "ru", "run", "sphere", "--port", "1").stderr.strip().splitlines()[-1]
    assert ru == "analyzer-lab: ошибка: нераспознанные аргументы: --port 1"
