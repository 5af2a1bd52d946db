"""A text with its numbers taken out: the key a text built per run is translated by.

A lesson writes texts with the values of a run in them ("Here L = 0.5: the profile is a
trapezoid.").  :func:`abstract` turns each standalone number into a Python-format
placeholder (``Here L = {0}: the profile is a trapezoid.``) so that one catalog entry
covers every run; :func:`restore` puts a run's numbers back as they were written (with
their dot: a derivation's numbers are formula-like).  Numbers that belong to a name
(``u1``, ``x0``, ``C1.4``), an equation number (``(1.58)``), a section (``§1.3``), a
numbered example, problem or figure (``Example 1.2``, ``Figs. 1.27-1.29``), an ordinal
(``2nd``) or an exponent (``x**2``, ``T2^2``) are part of the text and stay in it (so are
the Russian ones: ``Пример 1.2``, ``рис. 1.27``).  :func:`with_decimal` writes a prose
text's numbers with a language's decimal sign.
"""

from __future__ import annotations

import re

_PROTECTED = r"""
  \((?:[1-9]\d*\.)?\d+'?[a-z]?\)
| §\s*\d+(?:\.\d+)*
| \b(?:Examples?|Problems?|Figs?\.|Figures?|[Ee]qs?\.?|Sections?|Chapters?|Ch\.|Tables?|pp?\.)
  \s*\d+(?:\.\d+)*[a-z]?(?:\s*(?:[-–,]|and)\s*\d+(?:\.\d+)*[a-z]?)*
| \b(?:[Пп]ример|[Зз]адач|[Рр]ис|[Гг]лав|[Рр]аздел|[Тт]абл|[Уу]равнени|[Фф]ормул)[а-яё]*\.?
  \s*\d+(?:\.\d+)*[a-z]?(?:\s*(?:[-–,]|и)\s*\d+(?:\.\d+)*[a-z]?)*
| [A-Za-z_][A-Za-z_0-9]*(?:\.\d+)*
"""
#: A standalone number: 0.05, 1e-05, -3, 2.4e+08 (a minus only where it is a sign).
_NUMBER = (
    r"(?:(?<![\w)\]}.])-)?(?<![\w.^*])\d+(?:\.\d+)?(?:[eE][+-]?\d+)?"
    r"(?![\w.]*\d)(?![A-Za-z_])"
)
_TOKEN = re.compile(f"(?P<keep>{_PROTECTED})|(?P<num>{_NUMBER})", re.VERBOSE)


def _braces(text: str) -> str:
    return text.replace("{", "{{").replace("}", "}}")


def abstract(text: str) -> tuple[str, list[str]]:
    """``text`` with each standalone number replaced by ``{0}``, ``{1}``... (literal
    braces doubled), and the numbers as written; ``restore(*abstract(text)) == text``."""
    numbers: list[str] = []
    out: list[str] = []
    pos = 0
    for m in _TOKEN.finditer(text):
        if m.group("num") is None:
            continue
        out.append(_braces(text[pos : m.start()]))
        out.append(f"{{{len(numbers)}}}")
        numbers.append(m.group())
        pos = m.end()
    out.append(_braces(text[pos:]))
    return "".join(out), numbers


def restore(template: str, numbers: list[str]) -> str:
    """``template`` (an abstracted text or its translation) with ``numbers`` put back."""
    return template.format(*numbers)


def with_decimal(text: str, sign: str) -> str:
    """``text`` with its standalone numbers (as :func:`abstract` finds them) written with
    the decimal ``sign`` (``0,05`` in Russian prose); names, equation, section, example and
    figure numbers keep their dot."""
    if sign == ".":
        return text
    return _TOKEN.sub(
        lambda m: m.group() if m.group("num") is None else m.group().replace(".", sign), text
    )


__all__ = ["abstract", "restore", "with_decimal"]
