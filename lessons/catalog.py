"""The catalog: every lesson page of every domain.

A domain is a package of ``analyzer_lab.lessons`` (``analyzers``, ``mechanics``,
``vibration``, ``servo``, ``laser5``); ``kit`` and ``assignments`` are not domains. A page
is a module that stands directly in a domain and defines ``LESSON`` (one
:class:`~analyzer_lab.lessons.kit.contract.Lesson`) or ``LESSONS`` (a sequence of them);
a domain whose whole machinery serves one page is itself the page (its ``__init__``
defines ``LESSON``). Subpackages of a domain hold its machinery and are never pages.

Discovery is by module, so a new lesson needs no edit here.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterator
from functools import lru_cache
from types import ModuleType

from analyzer_lab.lessons.kit.contract import Lesson

#: The packages of ``analyzer_lab.lessons`` that are not domains.
NOT_DOMAINS = frozenset({"kit", "assignments"})
_ROOT = "analyzer_lab.lessons"


def domains() -> tuple[str, ...]:
    """The domain packages' short names, in file order."""
    root = importlib.import_module(_ROOT)
    return tuple(
        sorted(
            info.name
            for info in pkgutil.iter_modules(root.__path__)
            if info.ispkg and info.name not in NOT_DOMAINS and not info.name.startswith("_")
        )
    )


def page_modules() -> Iterator[ModuleType]:
    """Every page module: a domain that is one page, or the plain modules of a domain."""
    for domain in domains():
        package = importlib.import_module(f"{_ROOT}.{domain}")
        if hasattr(package, "LESSON") or hasattr(package, "LESSONS"):
            yield package
            continue
        for info in pkgutil.iter_modules(package.__path__):
            if info.ispkg or info.name.startswith("_"):
                continue
            yield importlib.import_module(f"{package.__name__}.{info.name}")


@lru_cache(maxsize=1)
def all_lessons() -> tuple[Lesson, ...]:
    """Every lesson, sorted by chapter order."""
    found: dict[str, Lesson] = {}
    for module in page_modules():
        items = list(getattr(module, "LESSONS", ()))
        if hasattr(module, "LESSON"):
            items.append(module.LESSON)
        for lesson in items:
            if lesson.id in found:
                raise RuntimeError(f"duplicate lesson id {lesson.id!r} in {module.__name__}")
            found[lesson.id] = lesson
    return tuple(sorted(found.values(), key=lambda l: (l.order, l.id)))


def get_lesson(lesson_id: str) -> Lesson:
    """The lesson with this id; ``KeyError`` with the known ids otherwise."""
    for lesson in all_lessons():
        if lesson.id == lesson_id:
            return lesson
    known = ", ".join(l.id for l in all_lessons())
    raise KeyError(f"unknown lesson {lesson_id[:60]!r}; known: {known}")
