"""The pseudo-language ``pseudo``: every text a catalog gives is half as long again, in
Cyrillic words, so a layout that breaks when a translation is longer than the English
(Russian often is) breaks here first, before a translator sees it.  Placeholders, units
and numbers are kept; the decimal sign is the comma, as in Russian.  It is not offered in
the page's language picker: ``serve --lang pseudo`` and the tests use it."""

from __future__ import annotations

import math

from babel.support import NullTranslations

#: The pseudo-language's code.
CODE = "pseudo"
#: The page's ``<html lang>`` in the pseudo-language (BCP 47's pseudo-locale for long text).
HTML_LANG = "en-XA"
#: How much longer every text becomes (a share of its length).
GROWTH = 0.5
#: The word the texts are padded with (Cyrillic, about as wide as Russian prose).
FILLER = "Щиэъюя"


def pad(text: str) -> str:
    """``text`` followed by filler words adding :data:`GROWTH` of its length (empty and
    blank texts as they are)."""
    if not text.strip():
        return text
    words = math.ceil(GROWTH * len(text) / (len(FILLER) + 1))
    return text + " " + " ".join([FILLER] * words)


class PseudoTranslations(NullTranslations):
    """A catalog whose every message is :func:`pad`-ded; units (context ``unit``) stay."""

    def gettext(self, message: str) -> str:
        return pad(message)

    def ngettext(self, msgid1: str, msgid2: str, n: int) -> str:
        return pad(msgid1 if n == 1 else msgid2)

    def pgettext(self, context: str, message: str) -> str:
        return message if context == "unit" else pad(message)


__all__ = ["CODE", "FILLER", "GROWTH", "HTML_LANG", "PseudoTranslations", "pad"]
