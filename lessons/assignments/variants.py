"""Varied assignments: numbers drawn for each student, every variant checked before release.

A file declares its varied quantities under ``variables``, each a range with a step or a
list of choices::

    "variables": {"v": {"from": 4, "to": 12, "step": 2}, "m": {"choices": [2, 3, 5]}},
    "variants": {"sample": 12}

and uses them in any text or value of the file (start values, checks, targets, bounds,
task, hint, feedback, answers) as placeholders ``{expr}`` or ``{expr:.3g}``: ``expr`` is a
formula of the varied quantities, parsed by the whitelist of
:mod:`analyzer_lab.lessons.kit.formula` (never evaluated as code), and the placeholder
becomes its value as a plain number.  The space of variants is every combination of the
values; the variants handed out are all of them, or the declared ``sample`` of them (drawn
from the assignment's id, the same on every machine).

A student's variant is drawn from a seed that hashes (class, student, assignment) with
SHA-256 (:func:`seed`), so it is the same every time, in every process and Python version.
:func:`release` checks every variant that will be handed out with the assignment's own
reference answer (``answers.correct``: it must pass every check) and wrong answer
(``answers.wrong``: it must fail one); one that does not is refused, naming the variant, and
nothing is handed out.
"""

from __future__ import annotations

import hashlib
import keyword
import math
import re
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any

from analyzer_lab.lessons.assignments.grading import Grade, grade
from analyzer_lab.lessons.assignments.spec import (
    Assignment,
    AssignmentError,
    Variable,
    parse_concrete,
)
from analyzer_lab.lessons.kit.formula import (
    CONSTANTS,
    FUNCTIONS,
    Formula,
    FormulaError,
    parse_formula,
    parse_number,
)

MAX_VARIABLES = 6
MAX_VALUES = 1000
MAX_SPACE = 1_000_000
#: variants checked and handed out at most (a larger space declares a sample)
MAX_POOL = 200
#: the fields that are never varied
FIXED = frozenset({"format", "version", "id", "lesson", "preset", "unlocked"})
_PLACE = re.compile(r"\{([^{}]*)\}")
_FORMAT = re.compile(r"^\.?[0-9]{0,2}[efg]$")
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,19}$")


@dataclass(frozen=True)
class Variant:
    """One variant: its place in the space, its values and the assignment it makes."""

    index: int
    values: Mapping[str, float]
    assignment: Assignment

    @property
    def label(self) -> str:
        """The values in words, e.g. ``v = 6, m = 2`` (``(not varied)`` without any)."""
        if not self.values:
            return "(not varied)"
        return ", ".join(f"{k} = {v:.12g}" for k, v in self.values.items())

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


def _fail(where: str, fld: str, message: str) -> AssignmentError:
    return AssignmentError(where, fld, message)


def _number(v: Any, where: str, fld: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise _fail(where, fld, f"must be a number, got {type(v).__name__}")
    try:
        x = parse_number(v) if isinstance(v, str) else float(v)
    except FormulaError as exc:
        raise _fail(where, fld, str(exc)) from None
    if not math.isfinite(x) or abs(x) > 1e12:
        raise _fail(where, fld, f"must be a finite number of at most 1e12, got {x:g}")
    return x


def parse_variables(raw: Any, where: str) -> tuple[Variable, ...]:
    """The ``variables`` object: each name a range (``from``, ``to``, ``step``) or ``choices``."""
    if not isinstance(raw, dict) or not raw:
        raise _fail(where, "variables", "must be an object of varied quantities")
    if len(raw) > MAX_VARIABLES:
        raise _fail(where, "variables", f"has {len(raw)} quantities; the limit is {MAX_VARIABLES}")
    reserved = set(FUNCTIONS) | set(CONSTANTS) | {"t"}
    out: list[Variable] = []
    for name, spec in raw.items():
        fld = f"variables.{str(name)[:20]}"
        if not _NAME.match(name) or keyword.iskeyword(name) or name in reserved:
            raise _fail(
                where, fld, "must be a name of letters, digits and '_' (not t, pi, e or a function)"
            )
        if not isinstance(spec, dict):
            raise _fail(where, fld, "must be an object: from/to/step or choices")
        if set(spec) == {"choices"}:
            items = spec["choices"]
            if not isinstance(items, list) or not 1 <= len(items) <= MAX_VALUES:
                raise _fail(where, f"{fld}.choices", f"must be a list of 1 to {MAX_VALUES} numbers")
            values = tuple(_number(x, where, f"{fld}.choices[{i}]") for i, x in enumerate(items))
            if len(set(values)) != len(values):
                raise _fail(where, f"{fld}.choices", "names a value twice")
        elif set(spec) == {"from", "to", "step"}:
            lo = _number(spec["from"], where, f"{fld}.from")
            hi = _number(spec["to"], where, f"{fld}.to")
            step = _number(spec["step"], where, f"{fld}.step")
            if step <= 0:
                raise _fail(where, f"{fld}.step", f"must be positive, got {step:g}")
            if hi < lo:
                raise _fail(where, f"{fld}.to", f"{hi:g} is below 'from' ({lo:g})")
            count = int(math.floor((hi - lo) / step + 1e-9)) + 1
            if count > MAX_VALUES:
                raise _fail(where, fld, f"has {count} values; the limit is {MAX_VALUES}")
            values = tuple(float(f"{lo + k * step:.12g}") for k in range(count))
        else:
            raise _fail(where, fld, "must have exactly 'from', 'to' and 'step', or 'choices'")
        out.append(Variable(name, values))
    return tuple(out)


def space_size(variables: Sequence[Variable]) -> int:
    """How many variants the quantities make (every combination)."""
    return math.prod(len(v.values) for v in variables) if variables else 1


def values_at(variables: Sequence[Variable], index: int) -> dict[str, float]:
    """The values of variant ``index`` (the last quantity varies fastest)."""
    out: dict[str, float] = {}
    for v in reversed(variables):
        index, k = divmod(index, len(v.values))
        out[v.name] = v.values[k]
    return {v.name: out[v.name] for v in variables}


def _hash(*parts: str) -> int:
    text = "\x1f".join(("analyzer-lab variant", *parts)).encode("utf-8")
    return int.from_bytes(hashlib.sha256(text).digest()[:8], "big")


def seed(class_id: str, student: str, assignment_id: str) -> int:
    """The seed of a student's variant: SHA-256 of (class, student, assignment)."""
    return _hash(str(class_id), str(student), str(assignment_id))


def pool(a: Assignment) -> tuple[int, ...]:
    """The indices of the variants that are checked and handed out (sorted)."""
    size = space_size(a.variables)
    if a.sample is None:
        return tuple(range(size))
    chosen: set[int] = set()
    k = 0
    while len(chosen) < a.sample:
        chosen.add(_hash(a.id, "sample", str(k)) % size)
        k += 1
    return tuple(sorted(chosen))


@lru_cache(maxsize=512)
def _formula(text: str, names: tuple[str, ...]) -> Formula:
    return parse_formula(text, variables=names)


def _render(inner: str, values: Mapping[str, float]) -> str:
    expr, fmt = inner, ""
    if ":" in inner:
        expr, fmt = inner.rsplit(":", 1)
        if not _FORMAT.match(fmt):
            raise FormulaError(f"format {fmt[:10]!r} is not one of e.g. .3g, .2f, e")
    f = _formula(expr, tuple(values))
    x = float(f(*values.values())) if not f.is_constant else float(f.constant_value or 0.0)
    if not math.isfinite(x):
        raise FormulaError(f"{expr[:40]!r} is not finite")
    return format(x, fmt) if fmt else f"{x:.12g}"


def substitute(obj: Any, values: Mapping[str, float], where: str, fld: str) -> Any:
    """``obj`` with every ``{expr}`` placeholder in its texts replaced by its value."""
    if isinstance(obj, str):

        def one(m: re.Match[str]) -> str:
            try:
                return _render(m.group(1), values)
            except FormulaError as exc:
                raise _fail(where, fld, f"placeholder {{{m.group(1)[:40]}}}: {exc}") from None

        out = _PLACE.sub(one, obj)
        if "{" in out or "}" in out:
            raise _fail(where, fld, "has a '{' or '}' that is not a placeholder {expr}")
        return out
    if isinstance(obj, list):
        return [substitute(x, values, where, f"{fld}[{i}]") for i, x in enumerate(obj)]
    if isinstance(obj, dict):
        return {k: substitute(x, values, where, f"{fld}.{k}") for k, x in obj.items()}
    return obj


def instantiate(a: Assignment, index: int) -> Variant:
    """Variant ``index`` of ``a`` (validated as a whole assignment)."""
    if not a.varied:
        return Variant(0, {}, a)
    vals = values_at(a.variables, index)
    label = ", ".join(f"{k} = {v:.12g}" for k, v in vals.items())
    where = a.source
    concrete = {
        k: (v if k in FIXED else substitute(v, vals, where, k))
        for k, v in a.data.items()
        if k not in ("variables", "variants")
    }
    try:
        one = parse_concrete(concrete, where)
    except AssignmentError as exc:
        raise _fail(where, exc.field, f"variant {index} ({label}): {exc.message}") from None
    made = replace(one, data=a.data, variables=a.variables, sample=a.sample, variant=vals)
    return Variant(index, vals, made)


def parse_varied(data: Mapping[str, Any], where: str) -> Assignment:
    """A varied assignment, shown as the first variant it hands out."""
    variables = parse_variables(data.get("variables"), where)
    size = space_size(variables)
    if size > MAX_SPACE:
        raise _fail(where, "variables", f"make {size} variants; the limit is {MAX_SPACE}")
    raw = data.get("variants", {})
    if not isinstance(raw, dict) or set(raw) - {"sample"}:
        raise _fail(where, "variants", "must be an object with 'sample' (how many to hand out)")
    sample: int | None = None
    if "sample" in raw:
        n = raw["sample"]
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= min(size, MAX_POOL):
            raise _fail(
                where, "variants.sample", f"must be a whole number in [1, {min(size, MAX_POOL)}]"
            )
        sample = n
    elif size > MAX_POOL:
        raise _fail(
            where,
            "variants.sample",
            f"is needed: the quantities make {size} variants, more than {MAX_POOL} to check",
        )
    answers = data.get("answers")
    if not isinstance(answers, dict) or not {"correct", "wrong"} <= set(answers):
        raise _fail(
            where,
            "answers",
            "a varied assignment needs a 'correct' (reference) and a 'wrong' answer",
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
    return instantiate(template, pool(template)[0]).assignment


def variant_for(a: Assignment, class_id: str, student: str) -> Variant:
    """The variant ``student`` of ``class_id`` gets (unchecked: :func:`release` checks)."""
    if not a.varied:
        return Variant(0, {}, a)
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
            raise _fail(where, f"answers.{key}", f"variant {v.index} ({v.label}): {exc}") from None
    return out[0], out[1]


def release(a: Assignment) -> Release:
    """Check every variant that will be handed out; refuse (naming the variant) if one fails.

    Each variant's reference answer must pass every check and its wrong answer must fail
    at least one."""
    start = time.perf_counter()
    variants = [instantiate(a, i) for i in pool(a)] if a.varied else [Variant(0, {}, a)]
    runs = 0
    for v in variants:
        right, wrong = _verdicts(v, a.source)
        runs += (right is not None) + (wrong is not None)
        if right is not None and not right.passed:
            c = right.failed[0]
            raise _fail(
                a.source,
                "answers.correct",
                f"variant {v.index} ({v.label}): the reference answer fails check {c.id}"
                f" ({c.message})",
            )
        if wrong is not None and wrong.passed:
            raise _fail(
                a.source,
                "answers.wrong",
                f"variant {v.index} ({v.label}): the wrong answer passes every check",
            )
    return Release(a, tuple(variants), runs, time.perf_counter() - start)


__all__ = [
    "MAX_POOL",
    "Release",
    "Variant",
    "instantiate",
    "parse_variables",
    "pool",
    "release",
    "seed",
    "space_size",
    "substitute",
    "values_at",
    "variant_for",
]
