"""A message that a page shows in its own language: the English text (a ``str``), its
template and values, rendered with a language's catalog, decimal sign and units."""

from __future__ import annotations

import json
import pickle

from analyzer_lab.i18n import ENGLISH, language_of
from analyzer_lab.lessons.kit.message import Message, Unit
from analyzer_lab.lessons.kit.params import Param, ParamError

RU = language_of("ru")


def test_a_message_is_its_english_text() -> None:
    m = Message("the run stopped at t = {t:.4g} s", t=2.5)
    assert m == "the run stopped at t = 2.5 s" and m.text == m
    assert "stopped" in m and json.loads(json.dumps([m])) == [m]
    assert Message("playing at {speed}x again", speed=8.0) == "playing at 8x again"
    assert ENGLISH.message(m) == "the run stopped at t = 2.5 s"


def test_a_page_renders_it_in_russian_with_a_decimal_comma() -> None:
    m = Message("the run stopped at t = {t:.4g} s", t=2.5)
    assert RU.message(m) == "прогон остановлен при t = 2,5 с"
    reached = Message(
        "t = {t_end} s reached (the textbook's run); press play to run again,"
        " or untick 'pause at t_end'",
        t_end=12.5,
    )
    assert RU.message(reached).startswith("достигнуто t = 12,5 с")


def test_a_nested_message_and_a_unit_are_rendered_too() -> None:
    m = Message("{value} is above the maximum {high} {unit}", value=0.5, high=0.1, unit=Unit("s"))
    assert m == "0.5 is above the maximum 0.1 s"
    assert RU.message(m) == "0,5 больше максимума 0,1 с"
    err = ParamError("h", m)
    assert str(err) == "h: 0.5 is above the maximum 0.1 s"
    assert RU.message(err) == "h: 0,5 больше максимума 0,1 с"


def test_a_refused_parameter_says_why_in_both_languages() -> None:
    p = Param("h", "float", 0.01, min=1e-5, max=0.1, unit="s")
    for raw, english, russian in [
        ("0.5", "h: 0.5 is above the maximum 0.1 s", "h: 0,5 больше максимума 0,1 с"),
        (
            float("nan"),
            "h: must be a finite number, got nan",
            "h: должно быть конечным числом, получено nan",
        ),
        (
            float("inf"),
            "h: must be a finite number, got inf",
            "h: должно быть конечным числом, получено inf",
        ),
    ]:
        try:
            p.parse(raw)
        except ParamError as exc:
            assert str(exc) == english
            assert RU.message(exc) == russian
        else:
            raise AssertionError(f"{raw} was accepted")


def test_it_survives_pickling_and_plain_text_is_shown_as_it_is() -> None:
    m = Message("unknown lesson {lesson}", lesson="'x'")
    back = pickle.loads(pickle.dumps(m))
    assert isinstance(back, Message) and back == m and back.values == {"lesson": "'x'"}
    assert RU.message("plain text") == "plain text"
    assert RU.message(ValueError("plain error")) == "plain error"


class _Broken:
    """A language whose translation drops a placeholder's name."""

    decimal = ","

    def gettext(self, message: str) -> str:
        return "{nope}"

    def unit(self, unit: str) -> str:
        return unit


def test_a_translation_that_fails_to_format_shows_the_english_text() -> None:
    m = Message("the run stopped at t = {t:.4g} s", t=2.5)
    assert m.render(_Broken()) == "the run stopped at t = 2.5 s"


def test_a_notice_is_a_session_message_or_a_lesson_note() -> None:
    """What the page shows as its notice: a session's Message by its template, a lesson's
    note (plain text) by the lessons' catalog, other text as it is."""
    m = Message("the run stopped at t = {t:.4g} s", t=2.5)
    assert RU.notice(m) == "прогон остановлен при t = 2,5 с"
    note = "Example 1.2: u1 = t, u2 = u3 = 5 (circles travelling along a meridian)"
    assert RU.notice(note) == RU.lesson_text(note) != note
    assert RU.notice("no such text") == "no such text"
    assert ENGLISH.notice(m) == "the run stopped at t = 2.5 s" and ENGLISH.notice(note) == note
