"""A message for a person that a page can show in its own language.

A :class:`Message` is its English text (it *is* a ``str``: logs, exports, the API and the
command line read it as before) that also keeps its template and values, so a page
translates the template and formats the values as its language writes numbers.  The
template is marked where it is written with :func:`N_` (extracted into the catalog
``analyzer_lab``); numbers are formatted by the template's own spec (``{t:.4g}``), or as a
person types them (``{t}``: ``0.25``, ``10``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol


def N_(message: str) -> str:
    """Mark ``message`` (a template) for extraction; it is translated where it is shown."""
    return message


def _plain(value: float) -> str:
    """A number as a person types it (``0.25``, ``3``; as ``plain_number`` of the formula
    parser, without importing it)."""
    x = float(value)
    return str(int(x)) if x.is_integer() and abs(x) < 1e16 else repr(x)


class Number:
    """A number placed in a template: ``format(n, spec)`` with the decimal sign given (and
    thousands, ``{n:,}``, grouped with a space where the decimal sign is a comma)."""

    __slots__ = ("decimal", "value")

    def __init__(self, value: float, decimal: str = ".") -> None:
        self.value = value
        self.decimal = decimal

    def __format__(self, spec: str) -> str:
        text = format(self.value, spec) if spec else _plain(self.value)
        if self.decimal == ".":
            return text
        if "," in spec:  # thousands: a language with a decimal comma groups with a space
            text = text.replace(",", "\u00a0")
        return text.replace(".", self.decimal)


class Unit(str):
    """A unit placed in a template (``m``, ``rad/s``): shown as the language writes it."""


class Speaker(Protocol):
    """How a language shows a message: its catalog, its units and its decimal sign."""

    decimal: str

    def gettext(self, message: str) -> str: ...

    def unit(self, unit: str) -> str: ...


class _English:
    decimal = "."

    def gettext(self, message: str) -> str:
        return message

    def unit(self, unit: str) -> str:
        return unit


ENGLISH: Speaker = _English()


class Message(str):
    """English text with its template and values (see the module)."""

    template: str
    values: Mapping[str, Any]

    def __new__(cls, template: str, /, **values: Any) -> Message:
        self = super().__new__(cls, cls._render(template, values, ENGLISH))
        self.template = template
        self.values = values
        return self

    @property
    def text(self) -> str:
        """The English text as a plain ``str``."""
        return str.__str__(self)

    def render(self, language: Speaker) -> str:
        """The message in ``language``: its template translated, numbers with its decimal
        sign, units as it writes them, a value that is itself a message rendered the
        same way.  A translation that fails to format shows the English text."""
        try:
            return self._render(language.gettext(self.template), self.values, language)
        except (KeyError, IndexError, ValueError):
            return self.text

    @staticmethod
    def _render(template: str, values: Mapping[str, Any], language: Speaker) -> str:
        shown: dict[str, Any] = {}
        for name, v in values.items():
            if isinstance(v, Message):
                shown[name] = v.render(language)
            elif isinstance(v, Unit):
                shown[name] = language.unit(str(v)) if v else ""
            elif isinstance(v, (int, float)) and not isinstance(v, bool):
                shown[name] = Number(v, language.decimal)
            else:
                shown[name] = v
        return template.format(**shown)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self.template, dict(self.values)))


def _rebuild(template: str, values: dict[str, Any]) -> Message:
    return Message(template, **values)


__all__ = ["ENGLISH", "Message", "N_", "Number", "Speaker", "Unit"]
