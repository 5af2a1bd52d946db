"""Every derivation step of every lesson and preset, rendered as the page shows it: written
the way the textbook writes it (d²φ/dt², φ, x_A), no library or sympy names, no raw
function names, every statement a non-empty formula (never "True" or "False")."""

from __future__ import annotations

import html
import re
from functools import cache

import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.view.math import _as_list, formula_html, step_to_html

#: Text that must not appear in a step, anywhere (prose or formula), case-sensitive.
RAW = (
    "phi(",  # a function name as sympy spells it: φ is written
    "_a(",  # sympy's lower-cased class name of x_A(t)
    "d^2",
    "d²/d²",
    "True",
    "False",
)
#: Library names: sympy's classes and functions, the mechanics module's classes.
LIBRARY = re.compile(
    r"\w+Method\b|\bMethod\b|sympy|lambdify|dynamicsymbols|ReferenceFrame|Lagrangian\(|"
    r"\b(?:Derivative|Symbol|Function|Matrix|ImmutableDenseMatrix|MutableDenseMatrix|"
    r"Equality|Eq|Add|Mul|Pow|Integral|Subs|Piecewise|Abs)\(|"
    r"Boolean(?:True|False)|AppliedUndef|UndefinedFunction|\bDummy\b|\bzoo\b"
)


#: A denominator that starts with d² (sympy's d²/d²t): the power belongs on dt².
SQUARED_D = re.compile(r"<mfrac><mrow>.*?</mrow><mrow><msup><m[io][^>]*>(?:d|∂|&#8706;)</m[io]>")


def _text(markup: str) -> str:
    return html.unescape(re.sub(r"<[^>]+>", " ", markup))


def _cases() -> list[str]:
    return [lesson.id for lesson in all_lessons()]


@cache
def _steps(lesson_id: str) -> list[tuple[str, int, object, str]]:
    """(preset, number, step, its HTML) for the lesson's defaults and every preset; a
    step shown the same way under several presets once."""
    lesson = get_lesson(lesson_id)
    out, seen = [], set()
    for preset in [None, *(p.name for p in lesson.presets)]:
        for k, step in enumerate(lesson.derivation(lesson.open({}, preset).params), 1):
            markup = step_to_html(step, k)
            if markup not in seen:
                seen.add(markup)
                out.append((preset or "(defaults)", k, step, markup))
    return out


@pytest.mark.parametrize("lesson_id", _cases())
def test_every_step_reads_as_the_textbook_writes_it(lesson_id: str) -> None:
    bad = []
    for preset, k, _, markup in _steps(lesson_id):
        text = _text(markup)
        where = f"{lesson_id} [{preset}] step {k}"
        for raw in RAW:
            if raw in text or raw in markup:
                at = text.find(raw)
                bad.append(f"{where}: {raw!r} in ...{text[max(0, at - 40) : at + 40]}")
        if SQUARED_D.search(markup):
            bad.append(f"{where}: a derivative printed as d²/d²t")
        for m in LIBRARY.finditer(text):
            bad.append(f"{where}: library name {m.group(0)!r} in ...{text[m.start() - 40 :][:80]}")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("lesson_id", _cases())
def test_every_statement_is_a_non_empty_formula(lesson_id: str) -> None:
    import sympy as sp

    bad = []
    for preset, k, step, _ in _steps(lesson_id):
        where = f"{lesson_id} [{preset}] step {k}"
        for item in _as_list(step.math):  # type: ignore[attr-defined]
            if isinstance(item, (bool, sp.logic.boolalg.BooleanAtom)):
                bad.append(f"{where}: a truth value, not a formula")
                continue
            out = formula_html(item)
            shown = _text(re.sub(r"<mtext>.*?</mtext>", " ", out)).strip()
            if "<math" not in out or not shown:
                bad.append(f"{where}: an empty formula")
            if "<mtext>" in out and not isinstance(item, str):
                bad.append(f"{where}: printed as text, not as a formula: {str(item)[:60]}")
    assert not bad, "\n".join(bad)


def test_the_checks_catch_what_they_look_for() -> None:
    """The checks find the raw names the old printer produced."""
    import sympy as sp
    from analyzer_lab.lessons.kit.contract import DerivationStep

    t = sp.Symbol("t")
    step = DerivationStep("From LagrangesMethod", "x", sp.Eq(sp.Symbol("M"), sp.Matrix([1])))
    text = _text(step_to_html(step, 1))
    assert LIBRARY.search(text) and "False" in text
    old = "<mfrac><mrow><msup><mo>d</mo><mn>2</mn></msup></mrow><mrow><msup><mo>d</mo><mn>2</mn>"
    assert SQUARED_D.search(old)
    assert not SQUARED_D.search(formula_html(sp.Function("phi")(t).diff(t, 2)))
    good = _text(formula_html(sp.Function("phi")(t).diff(t, 2) + sp.Function("x_A")(t)))
    assert "phi" not in good and "_a(" not in good and "φ" in good
