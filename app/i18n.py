"""The languages of the lab: gettext catalogs (domains ``analyzer_lab`` and ``lessons``)
read with Babel.

The catalogs are the ``.po`` files under ``locale/`` (package data, so an installed wheel
has them).  They are compiled in memory when first used (:func:`babel.messages.pofile.read_po`
then :func:`babel.messages.mofile.write_mo`): the ``.po`` file stays the one source, no
compiled ``.mo`` can fall behind it, there is no build step, and compiling both catalogs
takes a few milliseconds.  A catalog that fails to load is logged (at start, by
:func:`load_all`) and its language falls back to English, never to blank text; an entry
without a translation shows its English text.

Strings are marked for extraction where they are written (see :data:`KEYWORDS`):
``language.gettext("...")`` or its short name ``tr("...")`` and ``language.ngettext(...)``
at the call, :func:`N_` for a label kept in a constant, :func:`NP_` for a unit.  The
lessons' own texts (titles, labels, hints, preset notes, plot titles) are the second domain,
``lessons``, collected from the lesson catalog by :mod:`analyzer_lab.lesson_texts` and shown
with :meth:`Language.lesson_text`.
"""

from __future__ import annotations

import functools
import io
import logging
import re
from dataclasses import dataclass, field
from pathlib import Path

from analyzer_lab.lessons.kit.message import Message
from analyzer_lab.pseudo import CODE as PSEUDO
from analyzer_lab.pseudo import HTML_LANG as PSEUDO_HTML_LANG
from analyzer_lab.pseudo import PseudoTranslations
from analyzer_lab.text_numbers import abstract, restore, with_decimal
from babel.messages.catalog import Catalog
from babel.messages.mofile import write_mo
from babel.messages.pofile import PoFileError, read_po
from babel.numbers import get_decimal_symbol
from babel.support import NullTranslations, Translations

log = logging.getLogger(__name__)

DOMAIN = "analyzer_lab"
#: The domain of the lessons' own texts (see :mod:`analyzer_lab.lesson_texts`).
LESSONS_DOMAIN = "lessons"
#: The folder of the catalogs (``<code>/LC_MESSAGES/analyzer_lab.po``) and the template.
LOCALE_DIR = Path(__file__).resolve().parent / "locale"
#: The languages the lab speaks, by code, with their own names.
LANGUAGES: dict[str, str] = {"en": "English", "ru": "Русский"}
DEFAULT = "en"
#: The environment variable that carries ``serve --lang`` to a front door's workers.
LANGUAGE_ENV = "ANALYZER_LAB_LANG"


#: The extraction keywords beyond Babel's defaults (``pybabel extract -k`` each).
KEYWORDS = ("tr", "N_", "NP_:1c,2")


def N_(message: str) -> str:
    """Mark ``message`` for extraction; it is translated where it is shown."""
    return message


def NP_(context: str, message: str) -> str:
    """Mark ``message`` with its context (e.g. ``unit``) for extraction."""
    return message


#: The units the chrome and the readout write (translated with the context ``unit``).
UNITS = (
    NP_("unit", "s"),
    NP_("unit", "m"),
    NP_("unit", "mm"),
    NP_("unit", "rad"),
    NP_("unit", "rad/s"),
    NP_("unit", "m/s"),
    NP_("unit", "mm/s"),
    NP_("unit", "kg"),
    NP_("unit", "N"),
    NP_("unit", "1/s"),
    NP_("unit", "J"),
    NP_("unit", "N m"),
    NP_("unit", "N m/rad"),
    NP_("unit", "N s/m"),
    NP_("unit", "N/m"),
    NP_("unit", "kg m^2"),
    NP_("unit", "m/s^2"),
    NP_("unit", "m^2"),
    NP_("unit", "m^2/s"),
    NP_("unit", "mm (mm^2, mm^3)"),
    NP_("unit", "rad/s^2"),
    NP_("unit", "µm"),
)

_PLACEHOLDER = re.compile(r"\{[^{}]*\}")
#: A comma between two digits: a decimal comma (``0,5``).
_DECIMAL_COMMA = re.compile(r"(?<=\d),(?=\d)")


class CatalogError(RuntimeError):
    """A catalog could not be read."""


def catalog_path(code: str, domain: str = DOMAIN) -> Path:
    return LOCALE_DIR / code / "LC_MESSAGES" / f"{domain}.po"


def compile_catalog(code: str, path: Path | None = None, domain: str = DOMAIN) -> Translations:
    """The catalog of ``code`` read strictly from its ``.po`` file (a malformed line is an
    error, not a skipped entry) and compiled in memory; fuzzy entries are left out, as
    ``msgfmt`` does."""
    path = path or catalog_path(code, domain)
    try:
        with path.open("rb") as fh:
            catalog = read_po(fh, locale=code, domain=domain, abort_invalid=True)
        _drop_mismatched(catalog, code)
        buf = io.BytesIO()
        write_mo(buf, catalog, use_fuzzy=False)
    except (OSError, ValueError, SyntaxError, PoFileError) as exc:
        raise CatalogError(f"the {code!r} catalog {path} could not be read: {exc}") from exc
    buf.seek(0)
    return Translations(buf, domain=domain)


def placeholders(text: str) -> list[str]:
    """The ``{name}`` placeholders of a message, sorted (``{{`` is a literal brace)."""
    return sorted(_PLACEHOLDER.findall(text.replace("{{", "").replace("}}", "")))


def _drop_mismatched(catalog: Catalog, code: str) -> None:
    """Blank (English is then shown) every translation whose placeholders differ from its
    message's: ``str.format`` would fail on the page."""
    for m in catalog:
        if not m.id or not m.string:
            continue
        want = placeholders(m.id[0] if isinstance(m.id, tuple) else m.id)
        strings = m.string if isinstance(m.string, tuple) else (m.string,)
        if any(s and placeholders(s) != want for s in strings):
            log.error("the %r catalog: the placeholders of %r differ; English is shown", code, m.id)
            m.string = tuple("" for _ in strings) if isinstance(m.string, tuple) else ""


@functools.cache
def _load(code: str, domain: str = DOMAIN) -> tuple[NullTranslations, str | None]:
    """(catalog, None), or (no translation, why) when it fails to load."""
    try:
        return compile_catalog(code, domain=domain), None
    except CatalogError as exc:
        log.error("%s; the pages show English instead", exc)
        return NullTranslations(), str(exc)


def translations(lang: str) -> NullTranslations:
    """The catalog of ``lang`` (English text for an unknown code or a catalog that
    failed to load)."""
    if lang not in LANGUAGES:
        lang = DEFAULT
    return _load(lang)[0]


def load_all() -> list[str]:
    """Load every catalog now (at the server's start); returns what failed, each logged."""
    loaded = (_load(code, domain)[1] for code in LANGUAGES for domain in (DOMAIN, LESSONS_DOMAIN))
    return [why for why in loaded if why is not None]


@dataclass(frozen=True)
class Language:
    """One language of the page: its code, its catalog, how its prose writes numbers and
    the catalog of the lessons' own texts (English when it is missing or failed to load)."""

    code: str
    catalog: NullTranslations
    decimal: str = "."
    lessons: NullTranslations = field(default_factory=NullTranslations)

    def lesson_text(self, text: str) -> str:
        """A lesson's own text (title, label, hint, preset note, a derivation's step, a
        note...) in this language; the English text when the catalog has none (or for an
        empty text).  A text written per run is found by its numbers taken out
        (:func:`analyzer_lab.text_numbers.abstract`) and gets its own numbers back."""
        if not text:
            return text
        found = self.lessons.gettext(text)
        if found != text:
            return found
        key, numbers = abstract(text)
        if key == text:
            return text
        found = self.lessons.gettext(key)
        return text if found == key else restore(found, numbers)

    def prose(self, text: str) -> str:
        """A lesson's prose shown as prose (a note, a preset's note, a frame's message):
        :meth:`lesson_text` with its numbers written as the language writes them (the
        decimal comma in Russian); formulas and exports keep the dot."""
        return with_decimal(self.lesson_text(text), self.decimal)

    def gettext(self, message: str) -> str:
        return self.catalog.gettext(message)

    def ngettext(self, singular: str, plural: str, n: int) -> str:
        return self.catalog.ngettext(singular, plural, n)

    def message(self, text: object) -> str:
        """A message in this language: a :class:`Message` (a session's notice, the refusal
        an error carries) with its template translated and its numbers written as the
        language writes them; other text (or an error's) as it is."""
        if isinstance(text, BaseException) and text.args and isinstance(text.args[0], Message):
            text = text.args[0]
        if isinstance(text, Message):
            return text.render(self)
        return str(text)

    def notice(self, text: object) -> str:
        """A notice a page shows in this language: a session's :class:`Message`
        (:meth:`message`), or a lesson's note (:meth:`prose`)."""
        if isinstance(text, Message) or isinstance(text, BaseException):
            return self.message(text)
        return self.prose(str(text))

    @property
    def html_lang(self) -> str:
        """The page's ``<html lang>`` in this language (a BCP 47 tag)."""
        return PSEUDO_HTML_LANG if self.code == PSEUDO else self.code

    def quantity(self, words: str) -> str:
        """A quantity named in words (``position error``) as the language writes it."""
        return self.catalog.pgettext("quantity", words) if words else words

    def unit(self, unit: str) -> str:
        """A unit as the language writes it (``s`` is ``с`` in Russian); others as given."""
        return self.catalog.pgettext("unit", unit) if unit else unit

    def number(self, value: float, spec: str = ".6g") -> str:
        """``value`` formatted with ``spec`` and the language's decimal sign (prose: the
        readout, messages; exports keep the dot)."""
        text = format(value, spec)
        return text.replace(".", self.decimal) if self.decimal != "." else text

    def read_decimal(self, text: str) -> str:
        """Typed text with the language's decimal comma turned into the dot the formula
        parser reads (``0,5`` is ``0.5`` in Russian); unchanged in a language that writes a
        dot, where the parser refuses the comma with a message."""
        if self.decimal != ",":
            return text
        return _DECIMAL_COMMA.sub(".", text)


def language_of(code: str) -> Language:
    """The :class:`Language` of a known ``code`` (its catalog loaded once), or of the
    pseudo-language (:mod:`analyzer_lab.pseudo`)."""
    if code == PSEUDO:
        return Language(PSEUDO, PseudoTranslations(), ",", PseudoTranslations())
    catalog, failed = _load(code)
    if failed is not None:
        return Language(DEFAULT, translations(DEFAULT), ".")
    return Language(code, catalog, get_decimal_symbol(code), _load(code, LESSONS_DOMAIN)[0])


def resolve(code: str | None) -> tuple[Language, str | None]:
    """The language of ``code`` (``ru``, ``ru_RU.UTF-8``, ``en-GB``, ``None`` for the
    default), and a notice when English is shown instead: an unknown code, or a catalog
    that failed to load."""
    raw = (code or DEFAULT).strip()
    base = re.split(r"[_.@-]", raw, maxsplit=1)[0].lower()
    if base in ("c", "posix", ""):
        base = DEFAULT
    if base == PSEUDO:
        return language_of(PSEUDO), None
    if base not in LANGUAGES:
        known = ", ".join(LANGUAGES)
        return language_of(
            DEFAULT
        ), f"unknown language {raw[:20]!r}; English is shown (known: {known})"
    lang = language_of(base)
    if lang.code != base:
        return lang, f"the {LANGUAGES[base]} catalog failed to load; English is shown"
    return lang, None


ENGLISH = Language(DEFAULT, NullTranslations(), ".")


def picker_languages(code: str) -> dict[str, str]:
    """The languages a page's picker offers, by code: :data:`LANGUAGES`, and the
    pseudo-language too on a page that shows it."""
    return {**LANGUAGES, PSEUDO: "Pseudo"} if code == PSEUDO else dict(LANGUAGES)


__all__ = [
    "DEFAULT",
    "DOMAIN",
    "ENGLISH",
    "LANGUAGES",
    "LANGUAGE_ENV",
    "LESSONS_DOMAIN",
    "KEYWORDS",
    "LOCALE_DIR",
    "CatalogError",
    "Language",
    "N_",
    "NP_",
    "compile_catalog",
    "language_of",
    "load_all",
    "picker_languages",
    "placeholders",
    "resolve",
    "translations",
]
