"""Names and units as the textbook writes them: the model keeps plain ASCII names
(``phi_dot``, ``x_A``, unit ``um``: what exports and the Python API carry), the page
shows φ̇, x<sub>A</sub> and µm."""

from __future__ import annotations

import html
import re
from collections.abc import Callable

from analyzer_lab.i18n import NP_
from analyzer_lab.view.math import GREEK_WORDS

#: Greek letters spelled out in the models' names (the derivations' prose reads the same).
GREEK = GREEK_WORDS
#: Time derivatives written with dots over the letter (d/dt, d²/dt²).
DOTS = {"dot": "\u0307", "ddot": "\u0308"}
#: Names whose textbook form is not built by the rules below.
SPECIAL = {"v2": "|v|²"}
#: Units as the page writes them.  A surface of the analyzer lessons is given in lengths
#: without a unit (R = 1): its coordinates, speeds and squared speeds are shown bare.
UNITS = {
    "units": "",
    "units/s": "",
    "units²/s²": "",
    "um": "µm",
    "um/s": "µm/s",
    "deg": "°",
    "deg/s": "°/s",
}

#: The lessons' quantities named in words (``position_error``), translated with the
#: context ``quantity`` (:meth:`~analyzer_lab.i18n.Language.quantity`); a test keeps the
#: list complete.
QUANTITY_WORDS = (
    NP_("quantity", "angle error"),
    NP_("quantity", "axis b"),
    NP_("quantity", "axis c"),
    NP_("quantity", "axis x"),
    NP_("quantity", "axis y"),
    NP_("quantity", "axis z"),
    NP_("quantity", "constraint error"),
    NP_("quantity", "constraint residual"),
    NP_("quantity", "dda error"),
    NP_("quantity", "deviation"),
    NP_("quantity", "dist sq"),
    NP_("quantity", "drift"),
    NP_("quantity", "energy error"),
    NP_("quantity", "error"),
    NP_("quantity", "error x"),
    NP_("quantity", "error y"),
    NP_("quantity", "feed"),
    NP_("quantity", "input x"),
    NP_("quantity", "input y"),
    NP_("quantity", "length"),
    NP_("quantity", "move"),
    NP_("quantity", "off normal"),
    NP_("quantity", "position error"),
    NP_("quantity", "speed"),
    NP_("quantity", "speed error"),
    NP_("quantity", "tolerance"),
    NP_("quantity", "travel linear"),
    NP_("quantity", "travel tool"),
    # words as an index: q_steady, F_drive, v_limit
    NP_("quantity", "along"),
    NP_("quantity", "analyzer"),
    NP_("quantity", "article"),
    NP_("quantity", "blade"),
    NP_("quantity", "damper"),
    NP_("quantity", "dda"),
    NP_("quantity", "drive"),
    NP_("quantity", "limit"),
    NP_("quantity", "sopr"),
    NP_("quantity", "spring"),
    NP_("quantity", "steady"),
    NP_("quantity", "total"),
    NP_("quantity", "transient"),
)

#: A subscript never smaller than the panel's smallest text.
SUB_STYLE = ' style="font-size:max(11px,0.8em)"'

_WORD = re.compile(r"[A-Za-z]{3,}")


def _symbol(part: str) -> str:
    return GREEK.get(part, part)


def name_parts(name: str, words: Callable[[str], str] | None = None) -> tuple[str, str]:
    """A name as (letter, subscript): ``phi_dot`` -> ("φ̇", ""), ``x_A`` -> ("x", "A"),
    ``M_phi`` -> ("M", "φ"); a name of words (``position_error``) -> ("position error", ""),
    in a language through ``words`` (one of :data:`QUANTITY_WORDS`)."""
    if name in SPECIAL:
        return SPECIAL[name], ""
    parts = name.split("_")
    head, rest = parts[0], parts[1:]
    if head not in GREEK and _WORD.fullmatch(head):  # words, not a letter with an index
        text = " ".join(parts)
        return (words(text) if words is not None else text), ""
    letter = _symbol(head)
    while rest and rest[-1] in DOTS:  # x_dot, phi_ddot: the dots go over the letter
        letter += DOTS[rest.pop()]

    def index(part: str) -> str:  # a word as an index (q_steady) in the language
        if part not in GREEK and _WORD.fullmatch(part) and words is not None:
            return words(part)
        return _symbol(part)

    return letter, " ".join(index(p) for p in rest)


def name_html(name: str, words: Callable[[str], str] | None = None) -> str:
    """The name as the page shows it (escaped HTML, the index as a subscript)."""
    letter, sub = name_parts(name, words)
    esc = html.escape
    return esc(letter) + (f"<sub{SUB_STYLE}>{esc(sub)}</sub>" if sub else "")


def name_text(name: str, words: Callable[[str], str] | None = None) -> str:
    """The name as plain text (what a reader sees of :func:`name_html`)."""
    letter, sub = name_parts(name, words)
    return letter + sub


def unit_text(unit: str) -> str:
    """The unit as the page writes it ("" for a bare number)."""
    return UNITS.get(unit, unit)


__all__ = ["GREEK", "QUANTITY_WORDS", "UNITS", "name_html", "name_parts", "name_text", "unit_text"]
