"""A text with its numbers taken out: standalone numbers become placeholders, numbers
that belong to a name, an equation, a section, a numbered example or figure, an ordinal or
an exponent stay, and the numbers come back as written."""

from __future__ import annotations

import pytest
from analyzer_lab.text_numbers import abstract, restore, with_decimal


@pytest.mark.parametrize(
    ("text", "key", "numbers"),
    [
        (
            "Here L = 0.5: the profile is a trapezoid.",
            "Here L = {0}: the profile is a trapezoid.",
            ["0.5"],
        ),
        (
            "tol 1e-05, gain 2.4e+08, t = -3",
            "tol {0}, gain {1}, t = {2}",
            ["1e-05", "2.4e+08", "-3"],
        ),
        ("u1 = u2 = 5, x0 and C1.4", "u1 = u2 = {0}, x0 and C1.4", ["5"]),
        ("(1.58) with (13) and (2.11'), §1.3", "(1.58) with (13) and (2.11'), §1.3", []),
        (
            "Example 1.2, Problem 2.5, Figs. 1.27-1.29, Fig. 5c",
            "Example 1.2, Problem 2.5, Figs. 1.27-1.29, Fig. 5c",
            [],
        ),
        (
            "Lagrange equations of the 2nd kind, x**2 + T2^2",
            "Lagrange equations of the 2nd kind, x**2 + T2^2",
            [],
        ),
        ("a - 3 and a-3 and (-3, 4)", "a - {0} and a-{1} and ({2}, {3})", ["3", "3", "-3", "4"]),
        ("F = {x} at 0.25", "F = {{x}} at {0}", ["0.25"]),
        ("T = 2.0 s.", "T = {0} s.", ["2.0"]),
    ],
)
def test_standalone_numbers_become_placeholders_and_come_back(
    text: str, key: str, numbers: list[str]
) -> None:
    assert abstract(text) == (key, numbers)
    assert restore(key, numbers) == text


def test_a_translation_gets_the_numbers_of_its_own_run() -> None:
    key, numbers = abstract("Here delta = 0.125 mm.")
    assert key == "Here delta = {0} mm."
    assert restore("Здесь delta = {0} мм.", numbers) == "Здесь delta = 0.125 мм."
    assert restore("Здесь delta = {0} мм.", abstract("Here delta = -7e-06 mm.")[1]) == (
        "Здесь delta = -7e-06 мм."
    )


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        (
            "L = 3.44288: трапеция, T = 5.4 с (1.8), (1.9)",
            "L = 3,44288: трапеция, T = 5,4 с (1.8), (1.9)",
        ),
        (
            "Пример 1.2 и рис. 1.27, задача 2.5: шаг 0.05",
            "Пример 1.2 и рис. 1.27, задача 2.5: шаг 0,05",
        ),
        ("u1 = 0.5, C1.4, §1.3, tol 1e-05, -0.25", "u1 = 0,5, C1.4, §1.3, tol 1e-05, -0,25"),
        ("Example 1.1 at 2.5 m", "Example 1.1 at 2,5 m"),
    ],
)
def test_prose_numbers_with_the_decimal_comma(text: str, shown: str) -> None:
    assert with_decimal(text, ",") == shown
    assert with_decimal(text, ".") == text
