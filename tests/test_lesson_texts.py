"""The lessons' own texts as the gettext domain ``lessons``: the template covers every shown
field of every lesson and is not behind the lessons, the catalogs are complete (no
untranslated, no fuzzy entry), the Russian keeps placeholders and equation numbers and
writes Russian (symbols aside), and a page's language reads them with English as fallback."""

from __future__ import annotations

import logging
import re
import shutil
from pathlib import Path

import pytest
from analyzer_lab import i18n
from analyzer_lab.i18n import LANGUAGES, LESSONS_DOMAIN, LOCALE_DIR, catalog_path, resolve
from analyzer_lab.lesson_texts import collect, lesson_label, main, template
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.contract import Lesson
from analyzer_lab.session import session as session_module
from analyzer_lab.text_numbers import abstract
from babel.messages.catalog import Catalog, Message
from babel.messages.pofile import read_po

TEMPLATE = LOCALE_DIR / "lessons.pot"
#: An equation number as the book writes it: (1.58), (2.11'), (13).
EQUATION = re.compile(r"\((?:\d+\.)?\d+'?\)")
PLACEHOLDER = re.compile(r"\{[^{}]*\}")
CYRILLIC = re.compile(r"[А-Яа-яЁё]")
#: Words a Russian entry may keep without a Cyrillic letter: the lessons' symbols (Greek
#: letters spelled out, functions, solver options).  Any other word of three or more
#: letters is English left untranslated.
SYMBOL_WORDS = frozenset(
    {"alpha", "beta", "omega", "phi", "Phi", "varpi", "eps", "sin", "cos", "sqrt", "Delta"}
    | {"solve_ivp", "atol", "rtol"}
)


def read(path: Path, code: str | None = None) -> Catalog:
    with path.open("rb") as fh:
        return read_po(fh, locale=code)


def entries(catalog: Catalog) -> dict[str, Message]:
    return {m.id: m for m in catalog if m.id}


def shown_fields(lesson: Lesson) -> list[str]:
    """Every text field a page shows, walked here independently of the collector."""
    texts = [lesson.title, lesson.problem, lesson.source, lesson.summary]
    texts += [g.title for g in lesson.groups]
    for p in lesson.params:
        texts += [p.label, p.help]
    for pr in lesson.presets:
        texts += [pr.title, pr.note]
    texts += [spec.title for spec in lesson.plots]
    for s in lesson.series:
        texts += [s.description, s.undefined]
    return [t for t in texts if t and t.strip()]


def test_the_template_covers_every_shown_field_of_every_lesson() -> None:
    ids = entries(read(TEMPLATE))
    assert len(all_lessons()) >= 19
    missing = [(lesson.id, t) for lesson in all_lessons() for t in shown_fields(lesson)]
    missing = [(lid, t) for lid, t in missing if t not in ids]
    assert missing == []
    assert len(ids) >= 900
    sphere = get_lesson("sphere")
    radius = next(p for p in sphere.params if p.name == "R")
    assert f"{sphere.id}.param.R.label" in ids[radius.label].auto_comments


def test_the_committed_template_is_what_the_lessons_give_now() -> None:
    fresh = [(m.id, list(m.auto_comments)) for m in template() if m.id]
    committed = [(m.id, list(m.auto_comments)) for m in read(TEMPLATE) if m.id]
    assert committed == fresh, (
        "run python -m analyzer_lab.lesson_texts extract app/locale/lessons.pot"
    )


def test_the_extract_command_writes_the_same_template(tmp_path: Path) -> None:
    out = tmp_path / "lessons.pot"
    assert main(["extract", str(out)]) == 0
    assert list(entries(read(out))) == list(entries(read(TEMPLATE)))
    texts = collect()
    assert sorted(texts) == list(entries(read(out)))
    assert all(places == sorted(places) for places in texts.values())


@pytest.mark.parametrize("code", sorted(LANGUAGES))
def test_every_entry_is_translated_and_none_is_fuzzy(code: str) -> None:
    catalog = read(catalog_path(code, LESSONS_DOMAIN), code)
    found = entries(catalog)
    assert list(found) == list(entries(read(TEMPLATE)))  # the catalog follows the template
    assert [m.id for m in found.values() if not m.string] == []
    assert [m.id for m in found.values() if m.fuzzy] == []
    assert not catalog.fuzzy


def test_english_shows_the_lessons_as_written() -> None:
    catalog = read(catalog_path("en", LESSONS_DOMAIN), "en")
    assert [m.id for m in catalog if m.id and m.string != m.id] == []


def _russian() -> list[tuple[str, str]]:
    catalog = read(catalog_path("ru", LESSONS_DOMAIN), "ru")
    return [(m.id, m.string) for m in catalog if m.id]


def test_russian_keeps_placeholders_and_equation_numbers() -> None:
    bad = [
        (text, ru)
        for text, ru in _russian()
        if sorted(EQUATION.findall(text)) != sorted(EQUATION.findall(ru))
        or sorted(PLACEHOLDER.findall(text)) != sorted(PLACEHOLDER.findall(ru))
    ]
    assert bad == []
    numbered = [text for text, _ in _russian() if EQUATION.search(text)]
    assert len(numbered) > 100


def _symbolic(text: str) -> bool:
    """Only symbols: names of one or two letters (with digits or an index), and the
    symbol words."""
    for word in re.findall(r"[A-Za-z][A-Za-z0-9_]*", text):
        base = word if word in SYMBOL_WORDS else re.split(r"[_0-9]", word)[0]
        if len(base) > 2 and base not in SYMBOL_WORDS:
            return False
    return True


def test_russian_writes_russian_except_for_pure_symbols() -> None:
    cyrillic_free = [(text, ru) for text, ru in _russian() if not CYRILLIC.search(ru)]
    assert [(t, ru) for t, ru in cyrillic_free if not _symbolic(ru)] == []
    assert [(t, ru) for t, ru in cyrillic_free if ru != t] == []  # a symbol is kept as written
    assert len(cyrillic_free) < len(_russian()) / 5
    assert _symbolic("u1(t)") and _symbolic("phi_x(0)") and not _symbolic("speed profile")


def test_the_russian_names_the_problems_and_examples_as_the_book_does() -> None:
    ru = dict(_russian())
    assert ru["Problem 1.4"] == "Задача 1.4"
    assert ru["Curve on a sphere"] == "Перемещение по кривой на сфере"
    assert ru["Example 1.1: u1 = u2 = u3 = 5 (a circle)"].startswith("Пример 1.1:")
    assert "рис. 1.27-1.29" in ru["Textbook §1.3, Problem 1.5, eqs (1.58)-(1.59); Figs. 1.27-1.29"]
    assert "дифференциальн" in ru[get_lesson("parabola").summary].lower()


def test_a_language_reads_the_lessons_texts_with_english_as_fallback() -> None:
    ru, en = resolve("ru")[0], resolve("en")[0]
    sphere = get_lesson("sphere")
    assert ru.lesson_text(sphere.title) == "Перемещение по кривой на сфере"
    assert en.lesson_text(sphere.title) == sphere.title
    assert ru.lesson_text("a text no lesson has") == "a text no lesson has"
    assert ru.lesson_text("") == ""
    assert i18n.ENGLISH.lesson_text(sphere.title) == sphere.title


def test_the_lesson_picker_label_is_the_same_in_english_and_russian_in_russian() -> None:
    en, ru = resolve("en")[0], resolve("ru")[0]
    for lesson in all_lessons():
        assert lesson_label(lesson, en) == session_module.lesson_label(lesson)
    sphere = lesson_label(get_lesson("sphere"), ru)
    assert sphere == "Гл. 1 · Задача 1.4 · Перемещение по кривой на сфере"
    assert lesson_label(get_lesson("servo-errors"), ru).startswith("Статьи · Леппик (1960) · ")
    labels = [lesson_label(lesson, ru) for lesson in all_lessons()]
    assert len(set(labels)) == len(labels)  # the picker maps each label back to one lesson


def test_a_missing_lessons_catalog_is_logged_and_shows_english(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    for code in LANGUAGES:  # the chrome's catalogs only
        (tmp_path / code / "LC_MESSAGES").mkdir(parents=True)
        shutil.copy(catalog_path(code), tmp_path / code / "LC_MESSAGES")
    monkeypatch.setattr(i18n, "LOCALE_DIR", tmp_path)
    i18n._load.cache_clear()
    try:
        with caplog.at_level(logging.ERROR, logger="analyzer_lab.i18n"):
            failed = i18n.load_all()
        assert len(failed) == 2 and all("lessons.po" in why for why in failed)
        assert any("'ru' catalog" in r.getMessage() for r in caplog.records)
        lang, notice = resolve("ru")
        assert lang.code == "ru" and notice is None  # the chrome is still Russian
        assert lang.gettext("Lesson") == "Урок"
        assert lang.lesson_text("Curve on a sphere") == "Curve on a sphere"  # English
    finally:
        monkeypatch.undo()
        i18n._load.cache_clear()
    assert resolve("ru")[0].lesson_text("Curve on a sphere") == "Перемещение по кривой на сфере"


def _shown_remark(remark: str | None) -> str:
    """The remark as a page shows it: the text after ``corrected:``, else all of it."""
    remark = remark or ""
    corrected = remark.lower().startswith("corrected") and ":" in remark
    return remark.split(":", 1)[1].strip() if corrected else remark


def run_texts(lesson: Lesson) -> list[str]:
    """Every text a lesson writes per run (its derivation's step titles, prose, sources
    with words and remarks, its notes) with its defaults and with each preset, walked
    here independently of the collector."""
    texts = []
    for preset in (None, *(p.name for p in lesson.presets)):
        params = lesson.open(None, preset).params
        for step in lesson.derivation(params):
            texts += [step.title, step.text, _shown_remark(step.reconstructed)]
            caption = re.search(r'aria-label="([^"]*)"', step.svg or "")
            texts += [caption.group(1)] if caption else []
            if re.search("[A-Za-z]", step.source or ""):
                texts.append(step.source)
        texts += [note.text for note in lesson.notes(params)]
    return [t for t in texts if t and t.strip()]


def test_the_template_covers_every_derivation_and_note_of_every_lesson_and_preset() -> None:
    ids = entries(read(TEMPLATE))
    texts = [(lesson.id, t) for lesson in all_lessons() for t in run_texts(lesson)]
    assert len(texts) > 1000
    assert [(lid, t) for lid, t in texts if abstract(t)[0] not in ids] == []
    numbered = {abstract(t)[0] for _, t in texts if abstract(t)[1]}
    assert len(numbered) > 150  # one entry for the texts of every run
    sphere = ids["sphere R={0}: F = {1} with the numbers of this lesson, φ = t."]
    assert "sphere.derivation.4.text" in sphere.auto_comments


def test_a_run_with_other_numbers_reads_its_texts_in_russian_with_its_own_numbers() -> None:
    ru = resolve("ru")[0]
    sphere = get_lesson("sphere")
    steps = sphere.derivation(sphere.open({"R": 2.75}).params)
    text = next(s.text for s in steps if s.text.startswith("sphere R="))
    assert text.startswith("sphere R=2.75: F = ")
    assert text not in entries(read(TEMPLATE))  # only its template is in the catalog
    shown = ru.lesson_text(text)
    assert shown.startswith("сфера R=2.75: F = ") and shown.endswith(
        "с числами этого урока, φ = t."
    )
    assert abstract(shown)[1] == abstract(text)[1]  # the same numbers, with their dot
    assert ru.lesson_text("Here L = 0.125: the profile is a triangle.") == (
        "Здесь L = 0.125: профиль — треугольник."
    )
    titles = [ru.lesson_text(s.title) for s in steps]
    assert all(CYRILLIC.search(t) or _symbolic(t) for t in titles), titles
    assert resolve("en")[0].lesson_text(text) == text
    assert ru.lesson_text("Here L = 0.5 and more: a text no lesson has") == (
        "Here L = 0.5 and more: a text no lesson has"
    )


def test_every_remark_and_source_of_a_step_is_in_russian() -> None:
    """The remarks on rebuilt or corrected formulas and the step sources with words
    (``Fig. 1.15``, ``after (35)``) of every lesson and preset read in Russian."""
    ru = resolve("ru")[0]
    remarks, sources = set(), set()
    for lesson in all_lessons():
        for preset in (None, *(p.name for p in lesson.presets)):
            for step in lesson.derivation(lesson.open(None, preset).params):
                if step.reconstructed:
                    remarks.add(_shown_remark(step.reconstructed))
                if re.search("[A-Za-z]{2}", step.source or ""):
                    sources.add(step.source)
    assert len(remarks) >= 90 and len(sources) >= 40
    english = [t for t in remarks | sources if not CYRILLIC.search(ru.lesson_text(t))]
    assert english == []
    assert ru.lesson_text("Fig. 1.15") == "Рис. 1.15"
    assert ru.lesson_text("lost in the source; (1.50) with u1 = u3 = 0, u2 = 1") == (
        "в источнике утрачено; (1.50) при u1 = u3 = 0, u2 = 1"
    )
    assert ru.lesson_text("the source cites (2.30), which holds accelerations, not velocities")
    assert ru.lesson_text("C1.5: analyzer block diagram") == "С1.5: структурная схема анализатора"
    assert ru.gettext("reconstructed") == "восстановлено"
    assert ru.gettext("corrected") == "исправлено"
