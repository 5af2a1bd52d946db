"""The assignment file format (version 1): a task over one lesson, checked by its model.

An assignment is plain JSON data (see the README section "Assignments"):

* ``format`` = ``"analyzer-lab assignment"``, ``version`` = 1, ``id`` (a slug), ``title``;
* ``lesson``, ``preset`` (or null), ``start`` (values over the preset), ``t_end``;
* ``unlocked``: the parameters the student may change (every other one is locked);
* ``checks``: declared checks over the run (``within``, ``at-most``, ``at-least``,
  ``in-plane``, ``on-circle``, ``reaches``); expressions go through the formula whitelist
  of :mod:`analyzer_lab.lessons.kit.formula` with ``t`` and the lesson's series as variables;
* ``task``, ``hint``, ``reference`` (text), ``title_ru``, ``task_ru``, ``hint_ru`` (the
  title, task and hint in Russian, shown on a Russian page; English when absent),
  ``answers`` (``correct``/``wrong`` values);
* each check may carry ``feedback`` (shown when it fails) and ``feedback_pass`` (when it passes),
  and in Russian ``feedback_ru``, ``feedback_pass_ru``;
* ``variables`` and ``variants``: varied quantities, one variant per student (see
  :mod:`analyzer_lab.lessons.assignments.space`).

Loading validates everything; the first problem raises :class:`AssignmentError`, whose
message is one line naming the file, the field and what is wrong.  Nothing in a file is
ever evaluated as code.
"""

from __future__ import annotations

import json
import keyword
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from analyzer_lab.lessons.assignments.space import (
    SpaceError,
    Variable,
    concrete_data,
    label,
    parse_sample,
    parse_variables,
    pool_indices,
    space_size,
    values_at,
)
from analyzer_lab.lessons.kit.contract import Lesson, ParamError, Params
from analyzer_lab.lessons.kit.formula import (
    CONSTANTS,
    FUNCTIONS,
    Formula,
    FormulaError,
    parse_formula,
)
from analyzer_lab.lessons.kit.formula import parse_number as _parse_number
from analyzer_lab.lessons.kit.message import N_, Message

FORMAT = "analyzer-lab assignment"
VERSION = 1
MAX_FILE_BYTES = 64 * 1024
MAX_ANSWER_BYTES = 16 * 1024
MAX_CHECKS = 8
MAX_UNLOCKED = 24
MAX_TEXT = 2000
MAX_SHORT = 160
MAX_FEEDBACK = 600
MAX_T_END = 1e4
KINDS = ("within", "at-most", "at-least", "in-plane", "on-circle", "reaches")
REDUCTIONS = ("max-abs", "max", "min", "final", "mean", "rms")
_SLUG = re.compile(r"^[a-z0-9][a-z0-9.-]{0,59}$")
_TOP = {
    "format",
    "version",
    "id",
    "title",
    "lesson",
    "preset",
    "start",
    "t_end",
    "unlocked",
    "checks",
    "task",
    "hint",
    "title_ru",
    "task_ru",
    "hint_ru",
    "reference",
    "answers",
    "variables",
    "variants",
}
_CHECK_FIELDS: dict[str, set[str]] = {
    "within": {"quantity", "target", "tolerance", "from", "to", "at"},
    "at-most": {"quantity", "metric", "reduce", "bound", "from", "to"},
    "at-least": {"quantity", "metric", "reduce", "bound", "from", "to"},
    "in-plane": {"path", "normal", "offset", "tolerance"},
    "on-circle": {"path", "center", "radius", "normal", "tolerance"},
    "reaches": {"path", "point", "by", "tolerance"},
}


#: What every check may carry besides its kind's fields.
_FEEDBACK_FIELDS = {
    "id",
    "kind",
    "label",
    "feedback",
    "feedback_pass",
    "feedback_ru",
    "feedback_pass_ru",
}


#: How a refusal names its file and field (``where: field f: problem``), by which it gives.
_REFUSALS = {
    (True, True): N_("{where}: field {field}: {message}"),
    (True, False): N_("{where}: {message}"),
    (False, True): N_("field {field}: {message}"),
    (False, False): "{message}",
}


class AssignmentError(ValueError):
    """An assignment or answer was refused: ``str(err)`` is one line (file, field, problem).

    Its argument is a :class:`Message` (the same English text), so a page or the command
    line shows the refusal in its own language; ``message`` is the problem alone."""

    def __init__(self, where: str, field_name: str, message: str) -> None:
        loc = f"{where}: " if where else ""
        fld = f"field {field_name}: " if field_name else ""
        english = f"{loc}{fld}{message}".replace("\n", " ")
        said = message if isinstance(message, Message) else str(message).replace("\n", " ")
        shown: str = Message(
            _REFUSALS[bool(where), bool(field_name)], where=where, field=field_name, message=said
        )
        super().__init__(shown if shown == english else english)
        self.where = where
        self.field = field_name
        self.message = message


def said(exc: BaseException) -> str:
    """What ``exc`` says: its :class:`Message` when it carries one (shown in a page's
    language), else its text."""
    return exc.args[0] if exc.args and isinstance(exc.args[0], Message) else str(exc)


@dataclass(frozen=True)
class Quantity:
    """A run quantity: one series by name, or a whitelisted formula of t and the series."""

    text: str
    series: str | None = None
    formula: Formula | None = None


@dataclass(frozen=True)
class Check:
    """One declared check; the fields used depend on ``kind`` (see the module doc)."""

    id: str
    kind: str
    label: str = ""
    quantity: Quantity | None = None
    target: Quantity | None = None
    metric: str | None = None
    reduce: str = "max-abs"
    bound: float | None = None
    tolerance: float | None = None
    t_from: float | None = None
    t_to: float | None = None
    at: float | None = None
    path: tuple[str, ...] = ()
    normal: tuple[float, ...] | None = None
    offset: float = 0.0
    center: tuple[float, ...] = ()
    radius: float | None = None
    point: tuple[float, ...] = ()
    by: float | None = None
    feedback: str = ""
    feedback_pass: str = ""
    #: the feedback in Russian (empty: the English one is shown)
    feedback_ru: str = ""
    feedback_pass_ru: str = ""

    def feedback_in(self, code: str, passed: bool) -> str:
        """The feedback for this outcome in the language ``code``, English when not given."""
        if passed:
            return (self.feedback_pass_ru if code == "ru" else "") or self.feedback_pass
        return (self.feedback_ru if code == "ru" else "") or self.feedback

    def describe(self) -> str:
        """One line in words: a :class:`Message` (shown in a page's language; its English
        text is what grades and exports hold), or the ``label`` when the file gives one."""
        if self.label:
            return self.label
        window = _window_text(self.t_from, self.t_to)
        if self.kind == "within":
            assert self.quantity is not None and self.target is not None
            what = {"quantity": self.quantity.text, "target": self.target.text}
            if self.at is not None:
                return Message(
                    N_("{quantity} stays within {tolerance:g} of {target} at t = {at:g}"),
                    tolerance=self.tolerance,
                    at=self.at,
                    **what,
                )
            if window:
                return Message(
                    N_("{quantity} stays within {tolerance:g} of {target} {window}"),
                    tolerance=self.tolerance,
                    window=window,
                    **what,
                )
            return Message(
                N_("{quantity} stays within {tolerance:g} of {target}"),
                tolerance=self.tolerance,
                **what,
            )
        if self.kind in ("at-most", "at-least"):
            most = self.kind == "at-most"
            if self.metric:
                return Message(
                    N_("metric {metric} <= {bound:g}")
                    if most
                    else N_("metric {metric} >= {bound:g}"),
                    metric=self.metric,
                    bound=self.bound,
                )
            reduction = reduction_text(self.reduce, self.quantity.text if self.quantity else "")
            if window:
                return Message(
                    N_("{reduction} {window} <= {bound:g}")
                    if most
                    else N_("{reduction} {window} >= {bound:g}"),
                    reduction=reduction,
                    window=window,
                    bound=self.bound,
                )
            return Message(
                N_("{reduction} <= {bound:g}") if most else N_("{reduction} >= {bound:g}"),
                reduction=reduction,
                bound=self.bound,
            )
        path = ", ".join(self.path)
        if self.kind == "in-plane":
            terms = [Message(f"{{c:+g}}*{a}", c=c) for c, a in zip(self.normal or (), "xyz")]
            return Message(
                N_(
                    "the path ({path}) lies in the plane {normal} = {offset:g}"
                    " (within {tolerance:g})"
                ),
                path=path,
                normal=_joined(" ", terms),
                offset=self.offset,
                tolerance=self.tolerance,
            )
        if self.kind == "on-circle":
            return Message(
                N_(
                    "the path ({path}) lies on the circle centre ({center}), radius {radius:g}"
                    " (within {tolerance:g})"
                ),
                path=path,
                center=coordinates(self.center),
                radius=self.radius,
                tolerance=self.tolerance,
            )
        return Message(
            N_("the path ({path}) reaches ({point}) by t = {by:g} (within {tolerance:g})"),
            path=path,
            point=coordinates(self.point),
            by=self.by,
            tolerance=self.tolerance,
        )


@dataclass(frozen=True)
class Assignment:
    """A validated assignment (see :func:`parse_assignment`)."""

    id: str
    title: str
    lesson: str
    preset: str | None
    start: Mapping[str, Any]
    t_end: float
    unlocked: tuple[str, ...]
    checks: tuple[Check, ...]
    task: str
    hint: str = ""
    reference: str = ""
    #: the title, task and hint in Russian (empty: the page shows the English ones)
    title_ru: str = ""
    task_ru: str = ""
    hint_ru: str = ""
    answers: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    source: str = ""
    data: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)
    #: the varied quantities (none: every student gets the same numbers)
    variables: tuple[Variable, ...] = ()
    #: how many variants of the space are checked and handed out (None: all of them)
    sample: int | None = None
    #: this variant's values of the varied quantities (empty when not varied)
    variant: Mapping[str, float] = field(default_factory=dict)

    def title_in(self, code: str) -> str:
        """The title in the language ``code`` (``"ru"``), the English one when not given."""
        return (self.title_ru if code == "ru" else "") or self.title

    def task_in(self, code: str) -> str:
        """The task in the language ``code`` (``"ru"``), the English one when not given."""
        return (self.task_ru if code == "ru" else "") or self.task

    def hint_in(self, code: str) -> str:
        """The hint in the language ``code``, the English one when not given."""
        return (self.hint_ru if code == "ru" else "") or self.hint

    @property
    def varied(self) -> bool:
        """Whether students get different numbers."""
        return bool(self.variables)

    def summary(self) -> dict[str, Any]:
        """JSON-friendly listing entry."""
        return {
            "id": self.id,
            "title": self.title,
            "lesson": self.lesson,
            "preset": self.preset,
            "unlocked": list(self.unlocked),
            "checks": [{"id": c.id, "kind": c.kind, "text": c.describe()} for c in self.checks],
            "task": self.task,
            "hint": self.hint,
            "title_ru": self.title_ru,
            "task_ru": self.task_ru,
            "hint_ru": self.hint_ru,
            "reference": self.reference,
            "source": self.source,
            "variables": {v.name: list(v.values) for v in self.variables},
        }


#: Each reduction of a quantity in words (``max-abs of e``), by the name a file gives.
_REDUCTIONS: dict[str, str] = {
    "max-abs": N_("max-abs of {quantity}"),
    "max": N_("max of {quantity}"),
    "min": N_("min of {quantity}"),
    "final": N_("final of {quantity}"),
    "mean": N_("mean of {quantity}"),
    "rms": N_("rms of {quantity}"),
}


def reduction_text(how: str, quantity: str) -> Message:
    """The reduction ``how`` (one of :data:`REDUCTIONS`) of ``quantity`` in words."""
    return Message(_REDUCTIONS[how], quantity=quantity)


def _joined(separator: str, parts: list[Message]) -> Message:
    """``parts`` side by side (each shown in the page's language), ``separator`` between."""
    template = (
        separator.replace("{", "{{").replace("}", "}}").join(f"{{p{i}}}" for i in range(len(parts)))
    )
    return Message(template, **{f"p{i}": part for i, part in enumerate(parts)})


def coordinates(values: tuple[float, ...]) -> Message | str:
    """A point's coordinates (``1, 2.5``), each as the page's language writes a number and
    separated as it separates them (``1; 2,5`` in Russian)."""
    numbers = [Message("{v:g}", v=float(v)) for v in values]
    if not numbers:
        return ""
    shown = numbers[0]
    for n in numbers[1:]:
        shown = Message(N_("{first}, {next}"), first=shown, next=n)
    return shown


def _window_text(a: float | None, b: float | None) -> Message | str:
    """The time window of a check in words (empty: the whole run)."""
    if a is None and b is None:
        return ""
    if a is None:
        return Message(N_("for t in [0, {end:g}]"), end=b)
    if b is None:
        return Message(N_("for t in [{start:g}, end]"), start=a)
    return Message(N_("for t in [{start:g}, {end:g}]"), start=a, end=b)


class _Reader:
    """Typed access to one JSON object, every refusal naming the file and field."""

    def __init__(self, where: str, lesson: Lesson | None = None) -> None:
        self.where = where
        self.lesson = lesson

    def fail(self, fld: str, message: str) -> AssignmentError:
        return AssignmentError(self.where, fld, message)

    def text(self, obj: Mapping[str, Any], key: str, fld: str, limit: int, required: bool) -> str:
        v = obj.get(key)
        if v is None:
            if required:
                raise self.fail(fld, Message(N_("is missing")))
            return ""
        if not isinstance(v, str):
            raise self.fail(fld, Message(N_("must be text, got {got}"), got=_type(v)))
        if len(v) > limit:
            raise self.fail(
                fld,
                Message(
                    N_("is {count} characters long; the limit is {limit}"),
                    count=len(v),
                    limit=limit,
                ),
            )
        return v

    def number(self, v: Any, fld: str, positive: bool = False) -> float:
        if isinstance(v, bool) or v is None:
            raise self.fail(fld, Message(_NOT_NUMBER, got=_type(v)))
        if isinstance(v, (int, float)):
            x = float(v)
        elif isinstance(v, str):
            try:
                x = _parse_number(v)
            except FormulaError as exc:
                raise self.fail(fld, said(exc)) from None
        else:
            raise self.fail(fld, Message(_NOT_NUMBER, got=_type(v)))
        if not math.isfinite(x) or abs(x) > 1e12:
            raise self.fail(
                fld, Message(N_("must be a finite number of at most 1e12, got {x:g}"), x=x)
            )
        if positive and x <= 0:
            raise self.fail(fld, Message(N_("must be positive, got {x:g}"), x=x))
        return x

    def numbers(self, v: Any, fld: str, n: int) -> tuple[float, ...]:
        if not isinstance(v, list):
            raise self.fail(
                fld,
                Message(N_("must be a list of {count} numbers, got {got}"), count=n, got=_type(v)),
            )
        if len(v) != n:
            raise self.fail(
                fld,
                Message(
                    N_("must have {count} numbers (one per path coordinate), got {got}"),
                    count=n,
                    got=len(v),
                ),
            )
        return tuple(self.number(x, f"{fld}[{i}]") for i, x in enumerate(v))


_NOT_NUMBER = N_("must be a number, got {got}")
_NOT_SLUG = N_("must be lowercase letters, digits, '-' or '.' (1-60)")
_NOT_PARAM = N_("is not a parameter of lesson {lesson}")
#: A value an answer (or a file's answers) gives for a parameter the student may not set.
LOCKED = N_("is locked in this assignment")
#: A refusal of one variant of a varied assignment, naming it.
VARIANT = N_("variant {index} ({values}): {message}")


def _type(v: Any) -> str:
    """What a JSON value is, in words (a :class:`Message`; the value's own text quoted)."""
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true/false"
    if isinstance(v, (list, tuple)):
        return Message(N_("a list of {count}"), count=len(v))
    if isinstance(v, dict):
        return Message(N_("an object"))
    if isinstance(v, str):
        return Message(N_("text {text}"), text=repr(v[:30]))
    return type(v).__name__


def expression_names(lesson: Lesson, params: Params) -> tuple[str, ...]:
    """The series names usable as variables of an expression (identifiers only)."""
    reserved = set(FUNCTIONS) | set(CONSTANTS) | {"t"}
    return tuple(
        s.name
        for s in lesson.series_for(params)
        if s.name.isidentifier() and not keyword.iskeyword(s.name) and s.name not in reserved
    )


def parse_quantity(
    text: Any, lesson: Lesson, params: Params, reader: _Reader, fld: str
) -> Quantity:
    """A series name or a whitelisted formula of ``t`` and the lesson's series."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        text = repr(float(text))
    if not isinstance(text, str):
        raise reader.fail(
            fld, Message(N_("must be a series name or a formula, got {got}"), got=_type(text))
        )
    series = {s.name for s in lesson.series_for(params)}
    if text.strip() in series:
        return Quantity(text.strip(), series=text.strip())
    try:
        f = parse_formula(text, variables=("t", *expression_names(lesson, params)))
    except FormulaError as exc:
        raise reader.fail(fld, said(exc)) from None
    return Quantity(f.text, formula=f)


def _path(
    obj: Mapping[str, Any], lesson: Lesson, params: Params, r: _Reader, fld: str
) -> tuple[str, ...]:
    series = [s.name for s in lesson.series_for(params)]
    raw = obj.get("path")
    if raw is None:
        raw = [n for n in ("x", "y", "z") if n in series]
    if not isinstance(raw, list) or not 1 <= len(raw) <= 3:
        raise r.fail(
            fld, Message(N_("must be a list of 1 to 3 series names, got {got}"), got=_type(raw))
        )
    for i, n in enumerate(raw):
        if not isinstance(n, str) or n not in series:
            raise r.fail(
                f"{fld}[{i}]",
                Message(
                    N_("{what} is not a series of lesson {lesson}"), what=_type(n), lesson=lesson.id
                ),
            )
    return tuple(raw)


def _times(obj: Mapping[str, Any], r: _Reader, fld: str, t_end: float) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, name in (("from", "t_from"), ("to", "t_to"), ("at", "at"), ("by", "by")):
        if obj.get(key) is not None:
            v = r.number(obj[key], f"{fld}.{key}")
            if not 0 <= v <= t_end + 1e-9:
                raise r.fail(
                    f"{fld}.{key}",
                    Message(N_("{v:g} is outside the run [0, {end:g}]"), v=v, end=t_end),
                )
            out[name] = v
    if out.get("t_from", 0.0) > out.get("t_to", t_end):
        raise r.fail(f"{fld}.from", Message(N_("is after 'to'")))
    return out


def parse_check(
    obj: Any, index: int, lesson: Lesson, params: Params, t_end: float, r: _Reader
) -> Check:
    """One check object (validated against the lesson and its series)."""
    fld = f"checks[{index}]"
    if not isinstance(obj, dict):
        raise r.fail(fld, Message(N_("must be an object, got {got}"), got=_type(obj)))
    cid = r.text(obj, "id", f"{fld}.id", 60, True)
    if not _SLUG.match(cid):
        raise r.fail(f"{fld}.id", Message(_NOT_SLUG))
    kind = r.text(obj, "kind", f"{fld}.kind", 20, True)
    if kind not in KINDS:
        raise r.fail(
            f"{fld}.kind",
            Message(
                N_("{kind} is not one of {kinds}"), kind=repr(kind[:20]), kinds=", ".join(KINDS)
            ),
        )
    extra = set(obj) - _CHECK_FIELDS[kind] - _FEEDBACK_FIELDS
    if extra:
        raise r.fail(
            f"{fld}",
            Message(
                N_("unknown field {name} for a {kind} check"),
                name=repr(sorted(extra)[0][:30]),
                kind=kind,
            ),
        )
    label = r.text(obj, "label", f"{fld}.label", MAX_SHORT, False)
    kw: dict[str, Any] = {"id": cid, "kind": kind, "label": label}
    kw["feedback"] = r.text(obj, "feedback", f"{fld}.feedback", MAX_FEEDBACK, False)
    kw["feedback_pass"] = r.text(obj, "feedback_pass", f"{fld}.feedback_pass", MAX_FEEDBACK, False)
    for key in ("feedback_ru", "feedback_pass_ru"):
        kw[key] = r.text(obj, key, f"{fld}.{key}", MAX_FEEDBACK, False)
    kw.update(_times(obj, r, fld, t_end))
    if kind == "within":
        kw["quantity"] = parse_quantity(obj.get("quantity"), lesson, params, r, f"{fld}.quantity")
        kw["target"] = parse_quantity(obj.get("target", "0"), lesson, params, r, f"{fld}.target")
        kw["tolerance"] = r.number(obj.get("tolerance"), f"{fld}.tolerance", positive=True)
    elif kind in ("at-most", "at-least"):
        if ("metric" in obj) == ("quantity" in obj):
            raise r.fail(fld, Message(N_("needs exactly one of 'metric' or 'quantity'")))
        if "metric" in obj:
            m = r.text(obj, "metric", f"{fld}.metric", 60, True)
            if not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", m):
                raise r.fail(f"{fld}.metric", Message(N_("must be a metric name")))
            kw["metric"] = m
        else:
            kw["quantity"] = parse_quantity(obj["quantity"], lesson, params, r, f"{fld}.quantity")
            red = obj.get("reduce", "max-abs")
            if red not in REDUCTIONS:
                raise r.fail(
                    f"{fld}.reduce",
                    Message(N_("must be one of {names}"), names=", ".join(REDUCTIONS)),
                )
            kw["reduce"] = red
        kw["bound"] = r.number(obj.get("bound"), f"{fld}.bound")
    else:
        path = _path(obj, lesson, params, r, f"{fld}.path")
        kw["path"] = path
        kw["tolerance"] = r.number(obj.get("tolerance"), f"{fld}.tolerance", positive=True)
        if kind == "in-plane":
            n = r.numbers(obj.get("normal"), f"{fld}.normal", len(path))
            if math.hypot(*n) == 0:
                raise r.fail(f"{fld}.normal", Message(N_("must not be zero")))
            kw["normal"] = n
            kw["offset"] = r.number(obj.get("offset", 0), f"{fld}.offset")
        elif kind == "on-circle":
            if len(path) < 2:
                raise r.fail(f"{fld}.path", Message(N_("a circle needs 2 or 3 coordinates")))
            kw["center"] = r.numbers(obj.get("center"), f"{fld}.center", len(path))
            kw["radius"] = r.number(obj.get("radius"), f"{fld}.radius", positive=True)
            if obj.get("normal") is not None:
                n = r.numbers(obj["normal"], f"{fld}.normal", len(path))
                if math.hypot(*n) == 0:
                    raise r.fail(f"{fld}.normal", Message(N_("must not be zero")))
                kw["normal"] = n
        else:
            kw["point"] = r.numbers(obj.get("point"), f"{fld}.point", len(path))
            if "by" not in kw:
                raise r.fail(f"{fld}.by", Message(N_("is missing")))
    return Check(**kw)


def _values(v: Any, r: _Reader, fld: str, lesson: Lesson) -> dict[str, Any]:
    if not isinstance(v, dict):
        raise r.fail(
            fld, Message(N_("must be an object of parameter values, got {got}"), got=_type(v))
        )
    if len(v) > 64:
        raise r.fail(
            fld, Message(N_("has {count} entries; the limit is {limit}"), count=len(v), limit=64)
        )
    known = {p.name for p in lesson.params}
    for k, x in v.items():
        if k not in known:
            raise r.fail(f"{fld}.{k[:40]}", Message(_NOT_PARAM, lesson=lesson.id))
        if not isinstance(x, (str, int, float, bool)) or (isinstance(x, str) and len(x) > 400):
            raise r.fail(
                f"{fld}.{k}",
                Message(N_("must be a number, text or true/false, got {got}"), got=_type(x)),
            )
    return dict(v)


def parse_assignment(data: Any, where: str = "") -> Assignment:
    """Validate decoded JSON as an assignment; raise :class:`AssignmentError`."""
    r = _Reader(where)
    if not isinstance(data, dict):
        raise r.fail("", Message(N_("an assignment is a JSON object, got {got}"), got=_type(data)))
    if "variables" in data or "variants" in data:
        return _parse_varied(data, where)
    return parse_concrete(data, where)


def _parse_varied(data: Mapping[str, Any], where: str) -> Assignment:
    """A varied assignment, shown as the first variant it hands out."""
    try:
        variables = parse_variables(data.get("variables"))
        sample = parse_sample(data.get("variants", {}), space_size(variables))
    except SpaceError as exc:
        raise AssignmentError(where, exc.field, exc.message) from None
    answers = data.get("answers")
    if not isinstance(answers, dict) or not {"correct", "wrong"} <= set(answers):
        raise AssignmentError(
            where,
            "answers",
            Message(N_("a varied assignment needs a 'correct' (reference) and a 'wrong' answer")),
        )
    template = Assignment(
        id=str(data.get("id", ""))[:60],
        title="",
        lesson="",
        preset=None,
        start={},
        t_end=0.0,
        unlocked=(),
        checks=(),
        task="",
        source=where,
        data=data,
        variables=variables,
        sample=sample,
    )
    return variant_assignment(template, pool(template)[0])


def pool(a: Assignment) -> tuple[int, ...]:
    """The indices of the variants of ``a`` that are checked and handed out."""
    return pool_indices(a.id, space_size(a.variables), a.sample) if a.varied else (0,)


def variant_assignment(a: Assignment, index: int) -> Assignment:
    """Variant ``index`` of a varied assignment, validated as a whole assignment (a
    refusal names the variant)."""
    vals = values_at(a.variables, index)
    try:
        one = parse_concrete(concrete_data(a.data, vals), a.source)
    except (SpaceError, AssignmentError) as exc:
        raise AssignmentError(
            a.source,
            exc.field,
            Message(
                VARIANT,
                index=index,
                values=label(vals),
                message=exc.message,
            ),
        ) from None
    return replace(one, data=a.data, variables=a.variables, sample=a.sample, variant=vals)


def parse_concrete(data: Mapping[str, Any], where: str = "") -> Assignment:
    """Validate an assignment without varied quantities (or one variant of a varied one)."""
    from analyzer_lab.lessons.catalog import get_lesson

    r = _Reader(where)
    if data.get("format") != FORMAT:
        raise r.fail("format", Message(N_("must be {value}"), value=repr(FORMAT)))
    if data.get("version") != VERSION or isinstance(data.get("version"), bool):
        raise r.fail(
            "version",
            Message(
                N_("must be {value}, got {got}"), value=VERSION, got=_type(data.get("version"))
            ),
        )
    extra = set(data) - _TOP
    if extra:
        raise r.fail(sorted(extra)[0][:40], Message(N_("is not a field of an assignment")))
    aid = r.text(data, "id", "id", 60, True)
    if not _SLUG.match(aid):
        raise r.fail("id", Message(_NOT_SLUG))
    title = r.text(data, "title", "title", MAX_SHORT, True)
    lesson_id = r.text(data, "lesson", "lesson", 60, True)
    try:
        lesson = get_lesson(lesson_id)
    except KeyError:
        raise r.fail(
            "lesson",
            Message(
                N_("no lesson {lesson} (see 'analyzer-lab lessons')"), lesson=repr(lesson_id[:40])
            ),
        ) from None
    preset = data.get("preset")
    if preset is not None:
        preset = r.text(data, "preset", "preset", 60, True)
        if preset not in {p.name for p in lesson.presets}:
            raise r.fail(
                "preset",
                Message(
                    N_("lesson {lesson} has no preset {preset}"),
                    lesson=lesson.id,
                    preset=repr(preset[:40]),
                ),
            )
    start = _values(data.get("start", {}), r, "start", lesson)
    t_end = lesson.preset_t_end(preset)
    if data.get("t_end") is not None:
        t_end = r.number(data["t_end"], "t_end", positive=True)
        if t_end > MAX_T_END:
            raise r.fail(
                "t_end",
                Message(N_("{v:g} is above the limit {limit:g}"), v=t_end, limit=MAX_T_END),
            )
    try:
        params = lesson.resolve(start, preset)
    except (ParamError, ValueError) as exc:
        raise r.fail("start", said(exc)) from None
    unlocked_raw = data.get("unlocked")
    if not isinstance(unlocked_raw, list) or not unlocked_raw:
        raise r.fail(
            "unlocked",
            Message(
                N_("must be a non-empty list of parameter names, got {got}"),
                got=_type(unlocked_raw),
            ),
        )
    if len(unlocked_raw) > MAX_UNLOCKED:
        raise r.fail(
            "unlocked",
            Message(
                N_("has {count} names; the limit is {limit}"),
                count=len(unlocked_raw),
                limit=MAX_UNLOCKED,
            ),
        )
    known = {p.name for p in lesson.params}
    for i, n in enumerate(unlocked_raw):
        if not isinstance(n, str) or n not in known:
            raise r.fail(
                f"unlocked[{i}]",
                Message(
                    N_("{what} is not a parameter of lesson {lesson}"),
                    what=_type(n),
                    lesson=lesson.id,
                ),
            )
    if len(set(unlocked_raw)) != len(unlocked_raw):
        raise r.fail("unlocked", Message(N_("names a parameter twice")))
    checks_raw = data.get("checks")
    if not isinstance(checks_raw, list) or not checks_raw:
        raise r.fail(
            "checks",
            Message(N_("must be a non-empty list of checks, got {got}"), got=_type(checks_raw)),
        )
    if len(checks_raw) > MAX_CHECKS:
        raise r.fail(
            "checks",
            Message(
                N_("has {count} checks; the limit is {limit}"),
                count=len(checks_raw),
                limit=MAX_CHECKS,
            ),
        )
    checks = tuple(parse_check(c, i, lesson, params, t_end, r) for i, c in enumerate(checks_raw))
    if len({c.id for c in checks}) != len(checks):
        raise r.fail("checks", Message(N_("two checks have the same id")))
    answers_raw = data.get("answers", {})
    if not isinstance(answers_raw, dict) or set(answers_raw) - {"correct", "wrong"}:
        raise r.fail("answers", Message(N_("must be an object with 'correct' and/or 'wrong'")))
    answers = {k: _values(v, r, f"answers.{k}", lesson) for k, v in answers_raw.items()}
    for k, v in answers.items():
        locked = [n for n in v if n not in unlocked_raw]
        if locked:
            raise r.fail(f"answers.{k}.{locked[0]}", Message(LOCKED))
    return Assignment(
        id=aid,
        title=title,
        lesson=lesson.id,
        preset=preset,
        start=start,
        t_end=t_end,
        unlocked=tuple(unlocked_raw),
        checks=checks,
        task=r.text(data, "task", "task", MAX_TEXT, True),
        hint=r.text(data, "hint", "hint", MAX_TEXT, False),
        title_ru=r.text(data, "title_ru", "title_ru", MAX_SHORT, False),
        task_ru=r.text(data, "task_ru", "task_ru", MAX_TEXT, False),
        hint_ru=r.text(data, "hint_ru", "hint_ru", MAX_TEXT, False),
        reference=r.text(data, "reference", "reference", MAX_SHORT, False),
        answers=answers,
        source=where,
        data=data,
    )


#: Most digits of a whole number in a JSON file (a float has 17 significant ones).
MAX_INT_DIGITS = 100


class _LongNumber(ValueError):
    """A whole number of more than :data:`MAX_INT_DIGITS` digits."""


def _whole_number(digits: str) -> int:
    if len(digits.lstrip("-")) > MAX_INT_DIGITS:
        raise _LongNumber(len(digits.lstrip("-")))
    return int(digits)


def decode_json(text: str | bytes, where: str, limit: int) -> Any:
    """JSON text -> data, refusing oversize or malformed input (and whole numbers of more
    than :data:`MAX_INT_DIGITS` digits) in one line."""
    if len(text) > limit:
        raise AssignmentError(
            where,
            "",
            Message(N_("is {count} bytes; the limit is {limit}"), count=len(text), limit=limit),
        )
    try:
        return json.loads(text, parse_int=_whole_number)
    except _LongNumber as exc:
        raise AssignmentError(
            where,
            "",
            Message(
                N_("holds a whole number of {count} digits; the limit is {limit}"),
                count=exc.args[0],
                limit=MAX_INT_DIGITS,
            ),
        ) from None
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
        msg = exc.msg if isinstance(exc, json.JSONDecodeError) else type(exc).__name__
        if isinstance(exc, json.JSONDecodeError):
            why = Message(
                N_("is not valid JSON ({why} at line {line}, column {column})"),
                why=msg,
                line=exc.lineno,
                column=exc.colno,
            )
        else:
            why = Message(N_("is not valid JSON ({why})"), why=msg)
        raise AssignmentError(where, "", why) from None


def load_assignment(path: str | Path) -> Assignment:
    """Read and validate one assignment file."""
    p = Path(path)
    try:
        raw = p.read_bytes()[: MAX_FILE_BYTES + 1]
    except OSError as exc:
        raise AssignmentError(
            str(p), "", Message(N_("cannot be read ({why})"), why=str(exc.strerror))
        ) from None
    return parse_assignment(decode_json(raw, str(p), MAX_FILE_BYTES), str(p))
