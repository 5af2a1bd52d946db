"""Each student's variant, and the release check of every variant handed out.

The space of variants (declarations, placeholders, draws) is
:mod:`analyzer_lab.lessons.assignments.space`.  A student's variant is drawn from a seed
that hashes (class, student, assignment) with SHA-256, so it is the same every time, in
every process.  :func:`release` checks every variant that will be handed out with the
assignment's own reference answer (``answers.correct``: it must pass every check) and wrong
answer (``answers.wrong``: it must fail one), like STACK's question tests; one that does
not is refused, naming the variant, and nothing is handed out.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from analyzer_lab.lessons.assignments.grading import Grade, grade
from analyzer_lab.lessons.assignments.space import DEFAULT_CLASS, label, seed, values_at
from analyzer_lab.lessons.assignments.spec import (
    VARIANT,
    Assignment,
    AssignmentError,
    pool,
    said,
    variant_assignment,
)
from analyzer_lab.lessons.kit.message import N_, Message


@dataclass(frozen=True)
class Variant:
    """One variant: its place in the space, its values and the assignment it makes."""

    index: int
    values: Mapping[str, float]
    assignment: Assignment

    @property
    def label(self) -> str:
        """The values in words, e.g. ``v = 6, m = 2`` (``(not varied)`` without any)."""
        return label(self.values) if self.values else "(not varied)"

    def to_json_dict(self) -> dict[str, Any]:
        return {"index": self.index, "values": dict(self.values)}


@dataclass(frozen=True)
class Release:
    """An assignment whose variants all passed their checks: only these are handed out."""

    assignment: Assignment
    variants: tuple[Variant, ...]
    runs: int
    seconds: float

    def for_student(self, class_id: str, student: str) -> Variant:
        """The variant of ``student`` in ``class_id`` (the same every time)."""
        if len(self.variants) == 1:
            return self.variants[0]
        k = seed(class_id, student, self.assignment.id) % len(self.variants)
        return self.variants[k]


def instantiate(a: Assignment, index: int) -> Variant:
    """Variant ``index`` of ``a`` (an assignment that is not varied is its only variant)."""
    if not a.varied:
        return Variant(0, {}, a)
    made = variant_assignment(a, index)
    return Variant(index, dict(made.variant), made)


def variant_for(a: Assignment, class_id: str, student: str) -> Variant:
    """The variant ``student`` of ``class_id`` gets (the draw :class:`Release` makes too;
    this one is not checked: :func:`release` checks)."""
    indices = pool(a)
    return instantiate(a, indices[seed(class_id, student, a.id) % len(indices)])


def _verdicts(v: Variant, where: str) -> tuple[Grade | None, Grade | None]:
    a = v.assignment
    out: list[Grade | None] = []
    for key in ("correct", "wrong"):
        values = a.answers.get(key)
        if values is None:
            out.append(None)
            continue
        try:
            out.append(grade(a, values, f"answers.{key}"))
        except AssignmentError as exc:
            raise AssignmentError(
                where,
                f"answers.{key}",
                Message(VARIANT, index=v.index, values=v.label, message=said(exc)),
            ) from None
    return out[0], out[1]


def release(a: Assignment) -> Release:
    """Check every variant that will be handed out; refuse (naming the variant) if one fails.

    Each variant's reference answer must pass every check and its wrong answer must fail
    at least one."""
    start = time.perf_counter()
    variants = [instantiate(a, i) for i in pool(a)]
    runs = 0
    for v in variants:
        right, wrong = _verdicts(v, a.source)
        runs += (right is not None) + (wrong is not None)
        if right is not None and not right.passed:
            c = right.failed[0]
            raise AssignmentError(
                a.source,
                "answers.correct",
                Message(
                    VARIANT,
                    index=v.index,
                    values=v.label,
                    message=Message(
                        N_("the reference answer fails check {check} ({why})"),
                        check=c.id,
                        why=c.message,
                    ),
                ),
            )
        if wrong is not None and wrong.passed:
            raise AssignmentError(
                a.source,
                "answers.wrong",
                Message(
                    VARIANT,
                    index=v.index,
                    values=v.label,
                    message=Message(N_("the wrong answer passes every check")),
                ),
            )
    return Release(a, tuple(variants), runs, time.perf_counter() - start)


def variant_labelled(a: Assignment, text: str) -> Variant | None:
    """The variant of ``a`` whose label is ``text`` (as an attempt records it); None when
    no variant handed out has it.  An assignment that is not varied is its own variant."""
    if not a.varied:
        return instantiate(a, 0)
    for index in pool(a):
        if label(values_at(a.variables, index)) == text:
            return instantiate(a, index)
    return None


__all__ = [
    "DEFAULT_CLASS",
    "Release",
    "Variant",
    "instantiate",
    "pool",
    "release",
    "variant_for",
    "variant_labelled",
]
