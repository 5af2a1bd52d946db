"""Names and units as the textbook writes them (the page's side; the model keeps ASCII)."""

from __future__ import annotations

import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.session.session import Session
from analyzer_lab.view.notation import SUB_STYLE, name_html, name_parts, name_text, unit_text
from analyzer_lab.view.readout import readout_html


@pytest.mark.parametrize(
    ("name", "letter", "sub"),
    [
        ("phi", "φ", ""),
        ("phi_dot", "φ\u0307", ""),
        ("x_ddot", "x\u0308", ""),
        ("x_A", "x", "A"),
        ("M_phi", "M", "φ"),
        ("phi_y", "φ", "y"),
        ("delta_steady", "δ", "steady"),
        ("F_Ax", "F", "Ax"),
        ("v2", "|v|²", ""),
        ("position_error", "position error", ""),
        ("axis_c", "axis c", ""),
        ("speed", "speed", ""),
    ],
)
def test_a_name_is_written_as_the_textbook_writes_it(name: str, letter: str, sub: str) -> None:
    assert name_parts(name) == (letter, sub)
    assert name_text(name) == letter + sub


def test_the_index_is_a_subscript_and_the_name_is_escaped() -> None:
    assert name_html("x_A") == f"x<sub{SUB_STYLE}>A</sub>"
    assert name_html("a<b_c>") == f"a&lt;b<sub{SUB_STYLE}>c&gt;</sub>"


def test_units_of_a_bare_length_are_left_out_and_micrometres_are_written_um() -> None:
    assert unit_text("units") == unit_text("units/s") == unit_text("units²/s²") == ""
    assert unit_text("um") == "µm" and unit_text("deg") == "°"
    assert unit_text("rad/s") == "rad/s" and unit_text("N·m") == "N·m"


def test_every_readout_name_of_every_lesson_reads_without_snake_case() -> None:
    for lesson in all_lessons():
        for name in lesson.readout:
            shown = name_text(name)
            assert "_" not in shown, (lesson.id, name, shown)


def test_the_sphere_readout_has_no_units_word_and_keeps_each_quantity_whole() -> None:
    s = Session(all_lessons(), "sphere")
    text = readout_html(s)
    assert " units" not in text
    assert "|v|² = " in text and 'style="white-space:nowrap"' in text
    assert text.count('class="al-quantity"') == sum(n in s.frame.scalars for n in s.lesson.readout)


def test_the_laser_readout_writes_micrometres() -> None:
    lesson = get_lesson("laser-5axis")
    s = Session([lesson], lesson.id)
    text = readout_html(s)
    assert "deviation = " in text and "µm" in text and " um" not in text


def test_every_quantity_named_in_words_is_in_the_catalogs_list() -> None:
    """A lesson's readout or series named in words is translated as a quantity: the list
    the catalogs are extracted from holds every one of them."""
    from analyzer_lab.i18n import language_of
    from analyzer_lab.lessons.catalog import all_lessons
    from analyzer_lab.view.notation import QUANTITY_WORDS

    seen: set[str] = set()

    def words(text: str) -> str:
        seen.add(text)
        return text

    for lesson in all_lessons():
        for name in {*lesson.readout, *(s.name for s in lesson.series)}:
            name_parts(name, words)
    assert seen == set(QUANTITY_WORDS)
    ru = language_of("ru")
    assert name_html("position_error", ru.quantity) == "ошибка положения"
    assert all(ru.quantity(w) != w for w in QUANTITY_WORDS)
