"""The catalog: every lesson module under ``lessons/`` that defines ``LESSON`` (one
:class:`~lessons.core.contract.Lesson` instance) or ``LESSONS`` (a sequence of them).

Discovery is by module, so a new lesson needs no edit here.
"""

from __future__ import annotations

import importlib
import pkgutil
from functools import lru_cache

import lessons
from lessons.core.contract import Lesson


@lru_cache(maxsize=1)
def all_lessons() -> tuple[Lesson, ...]:
    """Every lesson, sorted by chapter order."""
    found: dict[str, Lesson] = {}
    for info in pkgutil.iter_modules(lessons.__path__):
        if info.name in ("core", "catalog") or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"lessons.{info.name}")
        items = list(getattr(module, "LESSONS", ()))
        if hasattr(module, "LESSON"):
            items.append(module.LESSON)
        for lesson in items:
            if lesson.id in found:
                raise RuntimeError(f"duplicate lesson id {lesson.id!r} in lessons.{info.name}")
            found[lesson.id] = lesson
    return tuple(sorted(found.values(), key=lambda l: (l.order, l.id)))


def get_lesson(lesson_id: str) -> Lesson:
    """The lesson with this id; ``KeyError`` with the known ids otherwise."""
    for lesson in all_lessons():
        if lesson.id == lesson_id:
            return lesson
    known = ", ".join(l.id for l in all_lessons())
    raise KeyError(f"unknown lesson {lesson_id[:60]!r}; known: {known}")
