"""A field's refusal in the page's language: a formula the parser refuses (``sin(``, an
unknown name) and a parameter's own refusal read Russian on a Russian page and as before
on an English one; real websockets to an in-process server."""

from __future__ import annotations

import asyncio
from typing import Any

import pytest
from analyzer_lab.i18n import language_of
from analyzer_lab.lessons.kit.formula import FormulaError, parse_formula
from analyzer_lab.lessons.kit.message import Message
from analyzer_lab.lessons.kit.params import Param, ParamError

from tests.support.client import ProtoClient, handled, open_page
from tests.support.waiting import until

pytestmark = pytest.mark.timeout(300)


def _field_error(c: ProtoClient) -> str:
    return next((h for h in c.html.values() if "al-field-error" in h), "")


async def _refused(c: ProtoClient, view: Any, label: str, text: str, expect: str) -> str:
    """Type ``text`` into ``label``; the field's error once it holds ``expect``."""
    await c.set(label, text)
    await handled(c, view)
    return await until(lambda: expect in _field_error(c) and _field_error(c), 10, expect)


def test_a_russian_page_refuses_a_formula_in_russian(labs: dict[str, Any]) -> None:
    async def go() -> None:
        c, view = await open_page(labs["ru"], "Движение")
        try:
            before = view.session.params["u1"].text
            shown = await _refused(c, view, "u1(t) =", "sin(", "не закрыта скобка")
            assert "unclosed" not in shown and "in &#x27;sin(&#x27;" not in shown
            shown = await _refused(c, view, "u1(t) =", "foo*t", "неизвестное имя")
            assert "&#x27;foo&#x27;" in shown and "допустимы: t, pi, e" in shown
            assert "в позиции 1" in shown and "unknown name" not in shown
            assert view.session.params["u1"].text == before  # nothing else changed
        finally:
            await c.close()

    asyncio.run(go())


def test_an_english_page_refuses_a_formula_as_before(labs: dict[str, Any]) -> None:
    async def go() -> None:
        c, view = await open_page(labs["en"], "Run")
        try:
            shown = await _refused(c, view, "u1(t) =", "sin(", "unclosed")
            assert "unclosed &#x27;(&#x27; in &#x27;sin(&#x27;" in shown
            shown = await _refused(c, view, "u1(t) =", "foo*t", "unknown name")
            assert "unknown name &#x27;foo&#x27; (allowed: t, pi, e) at column 1" in shown
        finally:
            await c.close()

    asyncio.run(go())


def test_the_refusals_keep_their_english_text_and_render_russian() -> None:
    ru = language_of("ru")
    with pytest.raises(FormulaError) as caught:
        parse_formula("2*t )")
    assert str(caught.value) == "unmatched ')' at column 5 in '2*t )'"
    assert ru.message(caught.value) == "лишняя скобка ')' в позиции 5 в '2*t )'"
    with pytest.raises(FormulaError) as caught:
        parse_formula("1e13*t")
    assert (
        str(caught.value) == "number 10000000000000.0 is larger than 1e+12 at column 1 in '1e13*t'"
    )
    assert ru.message(caught.value).startswith("число 10000000000000.0 больше 1e+12")
    cases = [
        (Param("n", "int", 0), True, "expected a number, got a boolean", "логическое"),
        (Param("f", "formula", "t"), [1], "expected a formula of t, got list", "формула"),
        (Param("b", "bool", False), "maybe", "expected on/off, got 'maybe'", "on или off"),
        (
            Param("m", "choice", "a", choices=("a", "b")),
            "c",
            "must be one of a, b; got 'c'",
            "должно быть одним из: a, b; получено 'c'",
        ),
        (Param("x", "float", 0.0), "1,5", "1,5 has a decimal comma", None),
    ]
    for param, raw, english, russian in cases:
        with pytest.raises(ParamError) as refused:
            param.parse(raw)
        assert isinstance(refused.value.args[0], Message)
        assert english in str(refused.value), str(refused.value)
        if russian is not None:
            assert russian in ru.message(refused.value), ru.message(refused.value)
