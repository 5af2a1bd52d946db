"""The command line's parser in the command's language: argparse's refusals from the
lab's catalog, and ``--lang`` read before the parser is built."""

from __future__ import annotations

import pytest
from analyzer_lab.i18n import resolve
from analyzer_lab.serve.cli_help import REFUSALS, LabParser, lang_option, refusal

RU = resolve("ru")[0]
EN = resolve("en")[0]


def test_argparses_refusals_are_said_in_the_language_with_what_was_typed() -> None:
    message = "argument --format: invalid choice: 'x' (choose from 'json', 'csv')"
    assert refusal(message, RU) == (
        "аргумент --format: недопустимый вариант: 'x' (возможны: 'json', 'csv')"
    )
    assert refusal(message, EN) == message
    assert refusal("unrecognized arguments: --a b", RU) == "нераспознанные аргументы: --a b"
    # a refusal the lab does not know stays as argparse wrote it
    assert refusal("argument --x: something new", RU) == "аргумент --x: something new"
    assert refusal("something new", RU) == "something new"


def test_every_refusal_has_its_russian() -> None:
    for template in REFUSALS:
        assert RU.gettext(template) != template


@pytest.mark.parametrize(
    ("argv", "code"),
    [
        (["serve", "--lang", "ru"], "ru"),
        (["--lang=ru", "run", "sphere"], "ru"),
        (["--lang", "en", "serve", "--lang", "ru"], "ru"),
        (["run", "sphere", "--", "--lang", "ru"], None),
        (["serve", "--lang"], None),
        (["run", "sphere"], None),
    ],
)
def test_the_lang_option_is_read_before_parsing(argv: list[str], code: str | None) -> None:
    assert lang_option(argv) == code


def test_a_parser_in_russian_prints_its_help_in_russian(capsys: pytest.CaptureFixture) -> None:
    parser = LabParser(prog="analyzer-lab", language=RU)
    parser.add_argument("--json", action="store_true", help=RU.gettext("print the lessons as JSON"))
    with pytest.raises(SystemExit) as exc:
        parser.parse_args(["--json", "--nope"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err == (
        "использование: analyzer-lab [-h] [--json]\n"
        "analyzer-lab: ошибка: нераспознанные аргументы: --nope\n"
    )
    text = parser.format_help()
    assert "параметры:" in text and "показать эту справку и выйти" in text
    assert "вывести уроки в JSON" in text
