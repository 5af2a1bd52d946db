"""The pseudo-language (app/pseudo.py): every text half as long again in Cyrillic words,
placeholders and units kept, the decimal comma; chosen by ``--lang pseudo`` and offered in
a page's picker only on a page that shows it."""

from __future__ import annotations

from analyzer_lab.i18n import LANGUAGES, picker_languages, placeholders, resolve
from analyzer_lab.lessons.kit.message import Message
from analyzer_lab.pseudo import CODE, FILLER, GROWTH, pad


def test_every_text_is_half_as_long_again_with_its_placeholders() -> None:
    for text in ("Lesson", "t = {t_end} s reached", "Play", "a" * 200):
        padded = pad(text)
        assert padded.startswith(text + " " + FILLER)
        assert len(padded) >= (1 + GROWTH) * len(text)
        assert placeholders(padded) == placeholders(text)
    assert pad("") == "" and pad("  ") == "  "


def test_the_pseudo_language_pads_the_chrome_the_lessons_and_messages() -> None:
    lang, notice = resolve(CODE)
    assert notice is None and lang.code == CODE and lang.decimal == ","
    assert lang.html_lang == "en-XA" and resolve("ru")[0].html_lang == "ru"
    assert lang.gettext("Lesson") == pad("Lesson")
    assert lang.lesson_text("Curve on a sphere") == pad("Curve on a sphere")
    assert lang.unit("s") == "s"  # units as they are
    m = Message("the run stopped at t = {t:.4g} s", t=2.5)
    shown = lang.message(m)
    assert shown.startswith("the run stopped at t = 2,5 s ") and FILLER in shown
    assert lang.ngettext("{n} page", "{n} pages", 2) == pad("{n} pages")


def test_the_picker_offers_it_only_on_a_page_that_shows_it() -> None:
    assert picker_languages("en") == LANGUAGES == picker_languages("ru")
    assert CODE in picker_languages(CODE) and set(LANGUAGES) < set(picker_languages(CODE))
    assert CODE not in LANGUAGES
