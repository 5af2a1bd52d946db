"""The catalog: every lesson page of every domain.

A domain is a package of ``analyzer_lab.lessons`` (``analyzers``, ``mechanics``,
``vibration``, ``servo``, ``laser5``); ``kit`` and ``assignments`` are not domains. A page
is a module that stands directly in a domain and defines ``LESSON`` (one
:class:`~analyzer_lab.lessons.kit.contract.Lesson`) or ``LESSONS`` (a sequence of them);
a domain whose whole machinery serves one page is itself the page (its ``__init__``
defines ``LESSON``). Subpackages of a domain hold its machinery and are never pages.

Discovery is by module (:func:`all_lessons`); :data:`INDEX` says which module holds
each lesson, so that :func:`get_lesson` imports that one page only (a command that runs
one lesson does not import the others). A new lesson adds one line to the index; a test
holds the index equal to what discovery finds.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterator
from functools import lru_cache
from types import ModuleType
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the index is read without importing the model
    from analyzer_lab.lessons.kit.contract import Lesson

#: The packages of ``analyzer_lab.lessons`` that are not domains.
NOT_DOMAINS = frozenset({"kit", "assignments"})
_ROOT = "analyzer_lab.lessons"
#: Every lesson id and the page module that holds it, in catalog order (the order of
#: :func:`all_lessons`); equal to what discovery finds (tested).
INDEX: tuple[tuple[str, str], ...] = (
    ("motion-program", "analyzers.motion_program"),
    ("parabola", "analyzers.parabola"),
    ("circle", "analyzers.circle"),
    ("quadric", "analyzers.quadric"),
    ("sphere", "analyzers.sphere"),
    ("sphere-constant-speed", "analyzers.sphere_constant_speed"),
    ("ellipsoid", "analyzers.ellipsoid"),
    ("self-study-1", "analyzers.self_study_1"),
    ("linear-positioner", "mechanics.linear_positioner"),
    ("rotary-positioner", "mechanics.rotary_positioner"),
    ("planar-2axis", "mechanics.planar_2axis"),
    ("planar-3axis", "mechanics.planar_3axis"),
    ("table-6dof", "mechanics.table_6dof"),
    ("constrained-dynamics", "mechanics.constrained_dynamics"),
    ("carriage-free-vibration", "vibration.carriage_free_vibration"),
    ("carriage-forced-vibration", "vibration.carriage_forced_vibration"),
    ("self-study-2", "mechanics.self_study_2"),
    ("servo-errors", "servo"),
    ("laser-5axis", "laser5"),
)


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


def lesson_ids() -> tuple[str, ...]:
    """Every lesson id in catalog order, read from :data:`INDEX` (no page is imported)."""
    return tuple(lesson_id for lesson_id, _ in INDEX)


def page_of(lesson_id: str) -> ModuleType:
    """The page module holding ``lesson_id`` (that page alone is imported);
    ``KeyError`` with the known ids otherwise."""
    where = dict(INDEX).get(lesson_id) if isinstance(lesson_id, str) else None
    if where is None:
        known = ", ".join(lesson_ids())
        raise KeyError(f"unknown lesson {str(lesson_id)[:60]!r}; known: {known}")
    return importlib.import_module(f"{_ROOT}.{where}")


def get_lesson(lesson_id: str) -> Lesson:
    """The lesson with this id, importing its page only; ``KeyError`` with the known ids
    otherwise."""
    module = page_of(lesson_id)
    for lesson in (*getattr(module, "LESSONS", ()), getattr(module, "LESSON", None)):
        if lesson is not None and lesson.id == lesson_id:
            return lesson
    raise KeyError(f"lesson {lesson_id!r} is not in {module.__name__}, where the index puts it")
