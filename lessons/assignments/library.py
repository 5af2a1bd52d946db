"""Folders of assignment files, and assignments drafted from a lesson's current state."""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from analyzer_lab.lessons.assignments.spec import (
    FORMAT,
    VERSION,
    Assignment,
    AssignmentError,
    expression_names,
    load_assignment,
    parse_assignment,
)
from analyzer_lab.lessons.kit.message import N_, Message

#: The ready assignments shipped with the lab (one or more per lesson): the source tree's
#: ``assets/assignments``, or where an installed wheel puts them.
_SOURCE_READY = Path(__file__).resolve().parents[2] / "assets" / "assignments"
_INSTALLED_READY = Path(sys.prefix) / "share" / "analyzer-lab" / "assignments"
READY_DIR = _SOURCE_READY if _SOURCE_READY.is_dir() else _INSTALLED_READY
MAX_FILES = 500
#: Where a refusal of a drafted assignment says it is.
DRAFT = Message(N_("draft"))


def load_folder(folder: str | Path) -> list[Assignment]:
    """Every ``*.json`` assignment in ``folder`` (sorted by lesson order, then id).

    The first invalid file raises :class:`AssignmentError` naming it; two files with one
    id are refused too."""
    from analyzer_lab.lessons.catalog import all_lessons

    d = Path(folder)
    if not d.is_dir():
        raise AssignmentError(str(d), "", Message(N_("is not a folder")))
    files = sorted(d.glob("*.json"))
    if len(files) > MAX_FILES:
        raise AssignmentError(
            str(d),
            "",
            Message(
                N_("holds {count} files; the limit is {limit}"), count=len(files), limit=MAX_FILES
            ),
        )
    out: dict[str, Assignment] = {}
    for f in files:
        a = load_assignment(f)
        if a.id in out:
            raise AssignmentError(
                str(f),
                "id",
                Message(
                    N_("{id} is also the id of {source}"), id=repr(a.id), source=out[a.id].source
                ),
            )
        out[a.id] = a
    order = {l.id: k for k, l in enumerate(all_lessons())}
    return sorted(out.values(), key=lambda a: (order.get(a.lesson, 999), a.id))


def ready_assignments() -> list[Assignment]:
    """The shipped assignments (``assets/assignments``)."""
    return load_folder(READY_DIR)


def draft(
    lesson_id: str,
    values: Mapping[str, Any],
    unlocked: Sequence[str],
    series: Sequence[str],
    *,
    assignment_id: str,
    title: str,
    task: str,
    preset: str | None = None,
    t_end: float | None = None,
    hint: str = "",
    reference: str = "",
    margin: float = 0.05,
    metrics: Sequence[str] = (),
) -> dict[str, Any]:
    """An assignment (as JSON data) authored from a lesson state.

    ``values`` are the current parameter values (the state's run becomes the goal and
    the unlocked ones its correct answer); for every name in ``series`` the goal is "stays
    within a tolerance of the current run's value" at its end and "its largest size stays
    at most the current one (plus ``margin``)".  The result is validated like any file.
    """
    from analyzer_lab.lessons.catalog import get_lesson

    lesson = get_lesson(lesson_id)
    known = {p.name for p in lesson.params}
    for i, name in enumerate(unlocked):
        if name not in known:
            raise AssignmentError(
                DRAFT,
                f"unlocked[{i}]",
                Message(
                    N_("{name} is not a parameter of {lesson}"),
                    name=repr(name[:40]),
                    lesson=lesson.id,
                ),
            )
    params = lesson.resolve(dict(values), preset)
    te = float(t_end if t_end is not None else lesson.preset_t_end(preset))
    run = lesson.simulate(params, te)
    usable = set(expression_names(lesson, params)) | set(run.series)
    checks: list[dict[str, Any]] = []
    for name in series:
        if name not in usable or name not in run.series:
            raise AssignmentError(
                DRAFT,
                "series",
                Message(
                    N_("{name} is not a series of {lesson}"), name=repr(name[:40]), lesson=lesson.id
                ),
            )
        v = np.asarray(run.series[name], dtype=float)
        if not np.isfinite(v).all():
            raise AssignmentError(
                DRAFT, "series", Message(N_("{name} is not finite on the whole run"), name=name)
            )
        size = float(np.max(np.abs(v)))
        scale = max(size, 1e-9)
        checks.append(
            {
                "id": f"{name.lower().replace('_', '-')}-end",
                "kind": "within",
                "quantity": name,
                "target": repr(float(v[-1])),
                "tolerance": float(f"{margin * scale:.3g}"),
                "at": te,
            }
        )
        checks.append(
            {
                "id": f"{name.lower().replace('_', '-')}-size",
                "kind": "at-most",
                "quantity": name,
                "reduce": "max-abs",
                "bound": float(f"{size * (1 + margin) + 1e-12:.4g}"),
            }
        )
    for name in metrics:
        value = run.metrics.get(name)
        if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
            raise AssignmentError(
                DRAFT,
                "metrics",
                Message(
                    N_("{name} is not a numeric metric of {lesson}"),
                    name=repr(name[:40]),
                    lesson=lesson.id,
                ),
            )
        value = float(value)
        if not np.isfinite(value):
            raise AssignmentError(
                DRAFT, "metrics", Message(N_("{name} is not finite in this run"), name=name)
            )
        slack = margin * max(abs(value), 1e-9)
        slug = name.lower().replace("_", "-")
        checks.append(
            {"id": f"{slug}-max", "kind": "at-most", "metric": name, "bound": value + slack}
        )
        checks.append(
            {"id": f"{slug}-min", "kind": "at-least", "metric": name, "bound": value - slack}
        )
    raw = params.raw()
    start = {k: _plain(v) for k, v in raw.items() if k not in unlocked}
    correct = {k: _plain(raw[k]) for k in unlocked}
    data = {
        "format": FORMAT,
        "version": VERSION,
        "id": assignment_id,
        "title": title,
        "lesson": lesson.id,
        "preset": preset,
        "start": start,
        "t_end": te,
        "unlocked": list(unlocked),
        "checks": checks,
        "task": task,
        "hint": hint,
        "reference": reference or lesson.source,
        "answers": {"correct": correct},
    }
    parse_assignment(data, DRAFT)
    return data


def _plain(v: Any) -> Any:
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    return v
