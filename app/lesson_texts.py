"""The texts of the lessons a page shows, as the gettext domain ``lessons``.

The lessons (the model) are written in English and never import the view; their shown
texts are collected here by walking the catalog, not by scanning source: each lesson's
title, problem, source line and summary, a chapter named in words, its groups' titles, its parameters' labels and
hints, its presets' titles and notes, its plots' titles and its series' descriptions.
The page translates them with :meth:`analyzer_lab.i18n.Language.lesson_text` (the picker's label with
:func:`lesson_label`).

The texts a lesson writes per run (its derivation's step titles and prose, its notes) are
collected by opening every lesson with its defaults and with each preset
(:func:`run_fields`), also each step's source words (``Fig. 1.14``, ``after (35)``), its
remark on a formula rebuilt or corrected (:func:`remark_parts`) and its figure's caption,
each with its numbers taken out (:func:`analyzer_lab.text_numbers.abstract`): one entry,
``Here L = {0}: the profile is a trapezoid.``, covers every run.  The source's claims are
checked by the command line and are not shown on a page, so they are not collected.

``python -m analyzer_lab.lesson_texts extract OUT.pot`` writes the template; the
catalogs follow it with ``pybabel update -D lessons -i OUT.pot -d app/locale``.
"""

from __future__ import annotations

import argparse
import functools
import html
import re
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path

from analyzer_lab.i18n import ENGLISH, Language
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.lessons.kit.contract import Lesson
from analyzer_lab.text_numbers import abstract
from babel.messages.catalog import Catalog
from babel.messages.pofile import write_po

DOMAIN = "lessons"


def lesson_fields(lesson: Lesson) -> Iterator[tuple[str, str]]:
    """``(where, text)`` for each shown text of ``lesson`` (``where`` names the lesson and
    the field, e.g. ``sphere_1_4.param.R.label``); empty texts are left out."""
    lid = lesson.id
    for name in ("title", "problem", "source", "summary"):
        yield f"{lid}.{name}", getattr(lesson, name)
    if not lesson.chapter.isdigit():  # "Articles"; a number is shown as "Ch. 1"
        yield f"{lid}.chapter", lesson.chapter
    for group in lesson.groups:
        yield f"{lid}.group.{group.name}.title", group.title
    for p in lesson.params:
        yield f"{lid}.param.{p.name}.label", p.label
        yield f"{lid}.param.{p.name}.help", p.help
    for preset in lesson.presets:
        yield f"{lid}.preset.{preset.name}.title", preset.title
        yield f"{lid}.preset.{preset.name}.note", preset.note
    for i, plot in enumerate(lesson.plots):
        yield f"{lid}.plot.{i}.title", plot.title
    for s in lesson.series:
        yield f"{lid}.series.{s.name}.description", s.description
        yield f"{lid}.series.{s.name}.undefined", s.undefined


def remark_parts(note: str | None) -> tuple[str, str]:
    """A step's remark (:attr:`DerivationStep.reconstructed`) as ``(kind, why)``:
    ``("corrected", why)`` for a misprint put right (``corrected: why``),
    ``("reconstructed", why)`` for a formula rebuilt from the text, ``("", "")`` for a
    formula as printed.  ``why`` is the text a page shows (and translates)."""
    if not note:
        return "", ""
    if note.lower().startswith("corrected"):
        return "corrected", note.split(":", 1)[1].strip() if ":" in note else note
    return "reconstructed", note


#: A figure's caption: its ``aria-label`` (a block diagram also draws it as its first line).
_CAPTION = re.compile(r'<svg\b[^>]*\baria-label="([^"]*)"')


def figure_caption(svg: str | None) -> str:
    """The caption of a step's figure as written (e.g. ``Problem 1.4: analyzer block
    diagram``); ``""`` without a figure or a caption."""
    found = _CAPTION.search(svg or "")
    return html.unescape(found.group(1)) if found else ""


def run_fields(lesson: Lesson) -> Iterator[tuple[str, str]]:
    """``(where, text)`` for each text ``lesson`` writes per run, opened with its defaults
    and with each preset: its derivation's step titles, prose, source words, remarks
    (:func:`remark_parts`) and figure captions (:func:`figure_caption`), its notes; each
    text with its numbers taken out (``where`` is e.g. ``sphere.derivation.3.title``).  A
    source that is only equation numbers (``(1.58)``) has no words and is left out."""
    lid = lesson.id
    for preset in (None, *(p.name for p in lesson.presets)):
        params = lesson.open(None, preset).params
        for i, step in enumerate(lesson.derivation(params), 1):
            yield f"{lid}.derivation.{i}.title", abstract(step.title)[0]
            yield f"{lid}.derivation.{i}.text", abstract(step.text)[0]
            if step.source and _has_words(step.source):
                yield f"{lid}.derivation.{i}.source", abstract(step.source)[0]
            yield f"{lid}.derivation.{i}.remark", abstract(remark_parts(step.reconstructed)[1])[0]
            yield f"{lid}.derivation.{i}.figure", abstract(figure_caption(step.svg))[0]
        for note in lesson.notes(params):
            yield f"{lid}.note", abstract(note.text)[0]
        for marker in lesson.scene(params).markers:
            yield f"{lid}.scene.label", abstract(marker.label)[0]
        message = lesson.open(None, preset).stepper.frame().message
        if message:
            yield f"{lid}.frame.message", abstract(message)[0]


def _has_words(text: str) -> bool:
    """Whether ``text`` has a letter (``Fig. 1.14``), not only numbers (``(1.58)``)."""
    return re.search(r"[^\W\d_]", text) is not None


@functools.cache
def _run_texts(lesson: Lesson) -> tuple[tuple[str, str], ...]:
    """:func:`run_fields` of ``lesson`` once per process (building every derivation of
    every preset takes half a minute)."""
    return tuple(run_fields(lesson))


def lesson_label(lesson: Lesson, language: Language = ENGLISH) -> str:
    """The lesson picker's label in ``language``: chapter, problem, title (in English
    the same as :func:`analyzer_lab.session.session.lesson_label`)."""
    text = language.lesson_text
    bits = []
    if lesson.chapter:
        bits.append(
            language.gettext("Ch. {chapter}").format(chapter=lesson.chapter)
            if lesson.chapter.isdigit()
            else text(lesson.chapter)
        )
    if lesson.problem:
        bits.append(text(lesson.problem))
    bits.append(text(lesson.title) if lesson.title else lesson.id)
    return " · ".join(bits)


def collect(lessons: Iterable[Lesson] | None = None) -> dict[str, list[str]]:
    """Each distinct non-empty text of the lessons -> the sorted places it is shown."""
    texts: dict[str, set[str]] = {}
    for lesson in all_lessons() if lessons is None else lessons:
        for where, text in (*lesson_fields(lesson), *_run_texts(lesson)):
            if text and text.strip():
                texts.setdefault(text, set()).add(where)
    return {text: sorted(places) for text, places in texts.items()}


def template(lessons: Iterable[Lesson] | None = None) -> Catalog:
    """The ``lessons`` template: one entry per text, sorted, each with its places as
    comments (no dates that change from one extraction to the next)."""
    catalog = Catalog(
        domain=DOMAIN,
        project="analyzer-lab",
        version="0.1.0",
        copyright_holder="Analyzer Lab",
        msgid_bugs_address="EMAIL@ADDRESS",
        charset="utf-8",
        fuzzy=False,
    )
    for text, places in sorted(collect(lessons).items()):
        catalog.add(text, auto_comments=places)
    return catalog


def write_template(out: Path, lessons: Iterable[Lesson] | None = None) -> int:
    """Write the template to ``out``; returns the number of entries."""
    catalog = template(lessons)
    with out.open("wb") as fh:
        write_po(fh, catalog, omit_header=False, sort_output=True, no_location=True)
    return len(catalog)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m analyzer_lab.lesson_texts", description=__doc__.splitlines()[0]
    )
    sub = parser.add_subparsers(dest="command", required=True)
    extract = sub.add_parser("extract", help="write the template of the lessons' texts")
    extract.add_argument("out", type=Path, help="the .pot file to write")
    args = parser.parse_args(argv)
    n = write_template(args.out)
    print(f"{n} texts of {len(all_lessons())} lessons written to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
