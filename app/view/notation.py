"""Names and units as the textbook writes them: the model keeps plain ASCII names
(``phi_dot``, ``x_A``, unit ``um``: what exports and the Python API carry), the page
shows φ̇, x<sub>A</sub> and µm."""

from __future__ import annotations

import html
import re

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

#: A subscript never smaller than the panel's smallest text.
SUB_STYLE = ' style="font-size:max(11px,0.8em)"'

_WORD = re.compile(r"[A-Za-z]{3,}")


def _symbol(part: str) -> str:
    return GREEK.get(part, part)


def name_parts(name: str) -> tuple[str, str]:
    """A name as (letter, subscript): ``phi_dot`` -> ("φ̇", ""), ``x_A`` -> ("x", "A"),
    ``M_phi`` -> ("M", "φ"); a name of words (``position_error``) -> ("position error", "")."""
    if name in SPECIAL:
        return SPECIAL[name], ""
    parts = name.split("_")
    head, rest = parts[0], parts[1:]
    if head not in GREEK and _WORD.fullmatch(head):  # words, not a letter with an index
        return " ".join(parts), ""
    letter = _symbol(head)
    while rest and rest[-1] in DOTS:  # x_dot, phi_ddot: the dots go over the letter
        letter += DOTS[rest.pop()]
    return letter, " ".join(_symbol(p) for p in rest)


def name_html(name: str) -> str:
    """The name as the page shows it (escaped HTML, the index as a subscript)."""
    letter, sub = name_parts(name)
    esc = html.escape
    return esc(letter) + (f"<sub{SUB_STYLE}>{esc(sub)}</sub>" if sub else "")


def name_text(name: str) -> str:
    """The name as plain text (what a reader sees of :func:`name_html`)."""
    letter, sub = name_parts(name)
    return letter + sub


def unit_text(unit: str) -> str:
    """The unit as the page writes it ("" for a bare number)."""
    return UNITS.get(unit, unit)


__all__ = ["GREEK", "UNITS", "name_html", "name_parts", "name_text", "unit_text"]
