"""The languages: the catalogs as Babel reads them (complete, no fuzzy entries, the same
placeholders, Russian plurals), the template up to date with the code, and the fallbacks."""

from __future__ import annotations

import logging
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from analyzer_lab import i18n
from analyzer_lab.i18n import (
    KEYWORDS,
    LANGUAGES,
    LOCALE_DIR,
    CatalogError,
    catalog_path,
    compile_catalog,
    resolve,
)
from babel.messages.catalog import Catalog
from babel.messages.extract import extract_from_dir
from babel.messages.plurals import get_plural
from babel.messages.pofile import read_po

ROOT = Path(__file__).resolve().parent.parent
TEMPLATE = LOCALE_DIR / "analyzer_lab.pot"
#: ``{name}`` placeholders and ``%(name)s`` / ``%s`` ones.
PLACEHOLDER = re.compile(r"\{[^{}]*\}|%(?:\([^)]*\))?[#0 +-]*\d*(?:\.\d+)?[sdifgeExXrc%]")


def read(code: str) -> Catalog:
    with catalog_path(code).open("rb") as fh:
        return read_po(fh, locale=code)


def entries(catalog: Catalog) -> list:
    return [m for m in catalog if m.id]


def placeholders(text: str) -> list[str]:
    return sorted(PLACEHOLDER.findall(text))


@pytest.mark.parametrize("code", sorted(LANGUAGES))
def test_every_entry_is_translated_and_none_is_fuzzy(code: str) -> None:
    catalog = read(code)
    assert len(entries(catalog)) >= 60
    untranslated = [m.id for m in entries(catalog) if not m.string or not all(m.string)]
    fuzzy = [m.id for m in entries(catalog) if m.fuzzy]
    assert untranslated == []
    assert fuzzy == []
    assert not catalog.fuzzy  # the header too


@pytest.mark.parametrize("code", sorted(LANGUAGES))
def test_placeholders_are_the_same_in_every_translation(code: str) -> None:
    bad = []
    for m in entries(read(code)):
        ids = m.id if isinstance(m.id, tuple) else (m.id,)
        strings = m.string if isinstance(m.string, tuple) else (m.string,)
        want = placeholders(ids[0])
        bad += [(ids[0], s) for s in strings if placeholders(s) != want]
    assert bad == []


def test_the_russian_catalog_has_three_plural_forms_in_each_plural_entry() -> None:
    catalog = read("ru")
    assert catalog.num_plurals == 3
    assert catalog.plural_forms == get_plural("ru").plural_forms
    plural = [m for m in entries(catalog) if m.pluralizable]
    assert plural
    for m in plural:
        assert len(m.string) == 3 and all(m.string), m.id
    ru = resolve("ru")[0]
    shown = [ru.ngettext("... and {n} more", "... and {n} more", n).format(n=n) for n in (1, 3, 5)]
    assert shown == ["… и ещё 1 значение", "… и ещё 3 значения", "… и ещё 5 значений"]


def test_the_english_catalog_is_the_text_of_the_code() -> None:
    for m in entries(read("en")):
        assert m.string == m.id


def test_the_template_is_up_to_date_with_the_code() -> None:
    """What Babel extracts from app/ (and lessons/kit/params.py, formula.py, the assignments'
    spec.py, grading.py, library.py, variants.py and space.py) now is what the template and both catalogs hold (after an
    edit: pybabel extract, then pybabel update; see babel.cfg)."""
    keywords = {"_": None, "gettext": None, "ngettext": (1, 2), "pgettext": ((1, "c"), 2)}
    keywords.update({"tr": None, "N_": None, "NP_": ((1, "c"), 2)})
    assert {k.split(":")[0] for k in KEYWORDS} <= set(keywords)
    # app/, and the model's refusals a page shows in its language (see babel.cfg)
    sources = [
        (ROOT / "app", "**.py"),
        (ROOT / "lessons", "kit/params.py"),
        (ROOT / "lessons", "kit/formula.py"),
        (ROOT / "lessons", "assignments/spec.py"),
        (ROOT / "lessons", "assignments/grading.py"),
        (ROOT / "lessons", "assignments/library.py"),
        (ROOT / "lessons", "assignments/variants.py"),
        (ROOT / "lessons", "assignments/space.py"),
    ]
    found = {
        (context, msgid if isinstance(msgid, str) else msgid[0])
        for folder, pattern in sources
        for _, _, msgid, _, context in extract_from_dir(
            str(folder), method_map=[(pattern, "python")], keywords=keywords
        )
    }
    with TEMPLATE.open("rb") as fh:
        template = {
            (m.context, m.id if isinstance(m.id, str) else m.id[0]) for m in entries(read_po(fh))
        }
    assert found - template == set(), "strings in the code missing from the template"
    assert template - found == set(), "strings in the template no longer in the code"
    for code in LANGUAGES:
        held = {
            (m.context, m.id if isinstance(m.id, str) else m.id[0]) for m in entries(read(code))
        }
        assert held == template, code


def test_pybabel_update_check_agrees() -> None:
    """The documented check: ``pybabel update --check`` against the template."""
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "babel.messages.frontend",
            "update",
            "--check",
            "--ignore-pot-creation-date",
            "-D",
            "analyzer_lab",
            "-i",
            str(TEMPLATE),
            "-d",
            str(LOCALE_DIR),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 0, out.stdout + out.stderr


def test_an_unknown_language_falls_back_to_english_with_a_notice() -> None:
    lang, notice = resolve("de")
    assert lang.code == "en"
    assert notice is not None and "'de'" in notice and "English" in notice
    assert lang.gettext("Lesson") == "Lesson"
    for code in ("ru", "ru_RU.UTF-8", "RU", "ru-RU"):
        lang, notice = resolve(code)
        assert (lang.code, notice) == ("ru", None)
        assert lang.gettext("Lesson") == "Урок"
    for code in (None, "", "C", "POSIX", "en_US.UTF-8"):
        assert resolve(code) == (resolve("en")[0], None)


def test_a_catalog_that_fails_to_load_is_logged_and_the_language_is_english(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    broken = tmp_path / "ru" / "LC_MESSAGES" / "analyzer_lab.po"
    broken.parent.mkdir(parents=True)
    broken.write_text('msgid "Lesson"\nmsgstr "Урок"\nmsgid: "Plots"\n', encoding="utf-8")
    (tmp_path / "en" / "LC_MESSAGES").mkdir(parents=True)
    shutil.copy(catalog_path("en"), tmp_path / "en" / "LC_MESSAGES" / "analyzer_lab.po")
    for code in LANGUAGES:  # the lessons' texts load; only the broken catalog fails
        shutil.copy(catalog_path(code, "lessons"), tmp_path / code / "LC_MESSAGES")
    with pytest.raises(CatalogError):
        compile_catalog("ru", broken)
    monkeypatch.setattr(i18n, "LOCALE_DIR", tmp_path)
    i18n._load.cache_clear()
    try:
        with caplog.at_level(logging.ERROR, logger="analyzer_lab.i18n"):
            failed = i18n.load_all()
        assert len(failed) == 1 and "'ru'" in failed[0]
        assert any("'ru' catalog" in r.getMessage() for r in caplog.records)
        lang, notice = resolve("ru")
        assert lang.code == "en" and notice is not None and "English" in notice
        assert lang.gettext("Lesson") == "Lesson"  # English, not blank
    finally:
        monkeypatch.undo()
        i18n._load.cache_clear()
    assert resolve("ru")[0].gettext("Lesson") == "Урок"


def test_an_entry_without_translation_shows_its_english_text(tmp_path: Path) -> None:
    po = tmp_path / "ru.po"
    po.write_text(
        'msgid ""\nmsgstr "Content-Type: text/plain; charset=utf-8\\n"\n\n'
        'msgid "Lesson"\nmsgstr ""\n\n#, fuzzy\nmsgid "Plots"\nmsgstr "Графики"\n',
        encoding="utf-8",
    )
    catalog = compile_catalog("ru", po)
    assert catalog.gettext("Lesson") == "Lesson"
    assert catalog.gettext("Plots") == "Plots"  # a fuzzy entry is not used


def test_a_translation_with_other_placeholders_is_not_used(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    po = tmp_path / "ru.po"
    po.write_text(
        'msgid ""\nmsgstr "Content-Type: text/plain; charset=utf-8\\n"\n\n'
        'msgid "show {name}"\nmsgstr "показать {имя}"\n\n'
        'msgid "lesson: {lesson}"\nmsgstr "урок: {lesson}"\n',
        encoding="utf-8",
    )
    with caplog.at_level(logging.ERROR, logger="analyzer_lab.i18n"):
        catalog = compile_catalog("ru", po)
    assert catalog.gettext("show {name}").format(name="v") == "show v"
    assert catalog.gettext("lesson: {lesson}") == "урок: {lesson}"
    assert any("placeholders" in r.getMessage() for r in caplog.records)


def test_prose_numbers_units_and_typed_decimal_commas() -> None:
    ru, en = resolve("ru")[0], resolve("en")[0]
    assert ru.number(1.25) == "1,25" and en.number(1.25) == "1.25"
    assert ru.number(2.0, "8.3f") == "   2,000" and en.number(2.0, "8.3f") == "   2.000"
    assert ru.unit("s") == "с" and ru.unit("rad/s") == "рад/с" and ru.unit("mm") == "мм"
    assert en.unit("s") == "s" and ru.unit("units/s") == "units/s"
    assert ru.read_decimal("0,5") == "0.5"
    assert ru.read_decimal("0,5*sin(2,25*t) + 1") == "0.5*sin(2.25*t) + 1"
    assert en.read_decimal("0,5") == "0,5"  # the parser refuses it, with a message


def test_catalogs_are_package_data() -> None:
    import tomllib

    data = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = data["tool"]["setuptools"]["package-data"]["analyzer_lab"]
    for code in LANGUAGES:
        rel = catalog_path(code).relative_to(ROOT / "app")
        assert any(rel.match(p) for p in patterns), rel
    assert "babel" in " ".join(data["project"]["dependencies"])
