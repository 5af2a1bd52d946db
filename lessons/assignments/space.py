"""The space of an assignment's variants: varied quantities, placeholders, the draws.

Pure data and hashing; nothing here runs a lesson.  A file declares its varied
quantities under ``variables``, each a range with a step or a list of choices::

    "variables": {"v": {"from": 4, "to": 12, "step": 2}, "m": {"choices": [2, 3, 5]}},
    "variants": {"sample": 12}

and uses them in any text or value of the file (start values, checks, targets, bounds,
task, hint, feedback, answers) as placeholders ``{expr}`` or ``{expr:.3g}``: ``expr`` is a
formula of the varied quantities, parsed by the whitelist of
:mod:`analyzer_lab.lessons.kit.formula` (never evaluated as code); the placeholder becomes
its value as a plain number.  The space is every combination of the values; the variants
handed out are all of them, or the declared ``sample`` (drawn from the assignment's id).
A student's draw hashes (class, student, assignment) with SHA-256 (:func:`seed`): the
same in every process, on every machine and Python version.
"""

from __future__ import annotations

import hashlib
import keyword
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from analyzer_lab.lessons.kit.formula import (
    CONSTANTS,
    FUNCTIONS,
    Formula,
    FormulaError,
    parse_formula,
    parse_number,
)
from analyzer_lab.lessons.kit.message import N_, Message

#: the class a variant is drawn for when none is named
DEFAULT_CLASS = "class"
MAX_VARIABLES = 6
MAX_VALUES = 1000
MAX_SPACE = 1_000_000
#: variants checked and handed out at most (a larger space declares a sample)
MAX_POOL = 200
#: the fields of a file that are never varied
FIXED = frozenset({"format", "version", "id", "lesson", "preset", "unlocked"})
_PLACE = re.compile(r"\{([^{}]*)\}")
_FORMAT = re.compile(r"^\.?[0-9]{0,2}[efg]$")
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,19}$")


def _said(exc: BaseException) -> str:
    """What ``exc`` says: its :class:`Message` when it carries one, else its text."""
    return exc.args[0] if exc.args and isinstance(exc.args[0], Message) else str(exc)


class SpaceError(ValueError):
    """A refused declaration or placeholder: the field and what is wrong."""

    def __init__(self, field_name: str, message: str) -> None:
        super().__init__(message)
        self.field = field_name
        self.message = message


@dataclass(frozen=True)
class Variable:
    """A varied quantity: its name (usable in ``{...}`` placeholders) and its values."""

    name: str
    values: tuple[float, ...]


def _number(v: Any, fld: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise SpaceError(fld, Message(N_("must be a number, got {got}"), got=type(v).__name__))
    try:
        x = parse_number(v) if isinstance(v, str) else float(v)
    except FormulaError as exc:
        raise SpaceError(fld, _said(exc)) from None
    if not math.isfinite(x) or abs(x) > 1e12:
        raise SpaceError(
            fld, Message(N_("must be a finite number of at most 1e12, got {x:g}"), x=x)
        )
    return x


def parse_variables(raw: Any) -> tuple[Variable, ...]:
    """The ``variables`` object: each name a range (``from``, ``to``, ``step``) or ``choices``."""
    if not isinstance(raw, dict) or not raw:
        raise SpaceError("variables", Message(N_("must be an object of varied quantities")))
    if len(raw) > MAX_VARIABLES:
        raise SpaceError(
            "variables",
            Message(
                N_("has {count} quantities; the limit is {limit}"),
                count=len(raw),
                limit=MAX_VARIABLES,
            ),
        )
    reserved = set(FUNCTIONS) | set(CONSTANTS) | {"t"}
    out: list[Variable] = []
    for name, spec in raw.items():
        fld = f"variables.{str(name)[:20]}"
        if not _NAME.match(name) or keyword.iskeyword(name) or name in reserved:
            raise SpaceError(
                fld,
                Message(
                    N_("must be a name of letters, digits and '_' (not t, pi, e or a function)")
                ),
            )
        if not isinstance(spec, dict):
            raise SpaceError(fld, Message(N_("must be an object: from/to/step or choices")))
        if set(spec) == {"choices"}:
            items = spec["choices"]
            if not isinstance(items, list) or not 1 <= len(items) <= MAX_VALUES:
                raise SpaceError(
                    f"{fld}.choices",
                    Message(N_("must be a list of 1 to {limit} numbers"), limit=MAX_VALUES),
                )
            values = tuple(_number(x, f"{fld}.choices[{i}]") for i, x in enumerate(items))
            if len(set(values)) != len(values):
                raise SpaceError(f"{fld}.choices", Message(N_("names a value twice")))
        elif set(spec) == {"from", "to", "step"}:
            lo = _number(spec["from"], f"{fld}.from")
            hi = _number(spec["to"], f"{fld}.to")
            step = _number(spec["step"], f"{fld}.step")
            if step <= 0:
                raise SpaceError(f"{fld}.step", Message(N_("must be positive, got {x:g}"), x=step))
            if hi < lo:
                raise SpaceError(
                    f"{fld}.to", Message(N_("{v:g} is below 'from' ({low:g})"), v=hi, low=lo)
                )
            count = int(math.floor((hi - lo) / step + 1e-9)) + 1
            if count > MAX_VALUES:
                raise SpaceError(
                    fld,
                    Message(
                        N_("has {count} values; the limit is {limit}"),
                        count=count,
                        limit=MAX_VALUES,
                    ),
                )
            values = tuple(float(f"{lo + k * step:.12g}") for k in range(count))
        else:
            raise SpaceError(
                fld, Message(N_("must have exactly 'from', 'to' and 'step', or 'choices'"))
            )
        out.append(Variable(name, values))
    return tuple(out)


def parse_sample(raw: Any, size: int) -> int | None:
    """The ``variants`` object: how many of ``size`` variants to hand out (None: all)."""
    if not isinstance(raw, dict) or set(raw) - {"sample"}:
        raise SpaceError(
            "variants", Message(N_("must be an object with 'sample' (how many to hand out)"))
        )
    if size > MAX_SPACE:
        raise SpaceError(
            "variables",
            Message(N_("make {count} variants; the limit is {limit}"), count=size, limit=MAX_SPACE),
        )
    if "sample" in raw:
        n = raw["sample"]
        top = min(size, MAX_POOL)
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= top:
            raise SpaceError(
                "variants.sample", Message(N_("must be a whole number in [1, {top}]"), top=top)
            )
        return n
    if size > MAX_POOL:
        raise SpaceError(
            "variants.sample",
            Message(
                N_("is needed: the quantities make {count} variants, more than {limit} to check"),
                count=size,
                limit=MAX_POOL,
            ),
        )
    return None


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


def label(values: Mapping[str, float]) -> str:
    """Values in words, e.g. ``v = 6, m = 2``."""
    return ", ".join(f"{k} = {v:.12g}" for k, v in values.items())


def _hash(*parts: str) -> int:
    text = "\x1f".join(("analyzer-lab variant", *parts)).encode("utf-8")
    return int.from_bytes(hashlib.sha256(text).digest()[:8], "big")


def seed(class_id: str, student: str, assignment_id: str) -> int:
    """The seed of a student's variant: SHA-256 of (class, student, assignment)."""
    return _hash(str(class_id), str(student), str(assignment_id))


def pool_indices(assignment_id: str, size: int, sample: int | None) -> tuple[int, ...]:
    """The indices of the variants checked and handed out (sorted): all, or the sample."""
    if sample is None:
        return tuple(range(size))
    chosen: set[int] = set()
    k = 0
    while len(chosen) < sample:
        chosen.add(_hash(assignment_id, "sample", str(k)) % size)
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
    x = float(f.constant_value or 0.0) if f.is_constant else float(f(*values.values()))
    if not math.isfinite(x):
        raise FormulaError(f"{expr[:40]!r} is not finite")
    return format(x, fmt) if fmt else f"{x:.12g}"


def substitute(obj: Any, values: Mapping[str, float], fld: str) -> Any:
    """``obj`` with every ``{expr}`` placeholder in its texts replaced by its value."""
    if isinstance(obj, str):

        def one(m: re.Match[str]) -> str:
            try:
                return _render(m.group(1), values)
            except FormulaError as exc:
                raise SpaceError(
                    fld,
                    Message(
                        N_("placeholder {name}: {why}"),
                        name="{" + m.group(1)[:40] + "}",
                        why=_said(exc),
                    ),
                ) from None

        out = _PLACE.sub(one, obj)
        if "{" in out or "}" in out:
            raise SpaceError(
                fld,
                Message(
                    N_("has a {open} or {close} that is not a placeholder {example}"),
                    open="'{'",
                    close="'}'",
                    example="{expr}",
                ),
            )
        return out
    if isinstance(obj, list):
        return [substitute(x, values, f"{fld}[{i}]") for i, x in enumerate(obj)]
    if isinstance(obj, dict):
        return {k: substitute(x, values, f"{fld}.{k}") for k, x in obj.items()}
    return obj


def concrete_data(data: Mapping[str, Any], values: Mapping[str, float]) -> dict[str, Any]:
    """A varied file's data for one variant: placeholders replaced, no declarations."""
    return {
        k: (v if k in FIXED else substitute(v, values, k))
        for k, v in data.items()
        if k not in ("variables", "variants")
    }


__all__ = [
    "DEFAULT_CLASS",
    "MAX_POOL",
    "SpaceError",
    "Variable",
    "concrete_data",
    "label",
    "parse_sample",
    "parse_variables",
    "pool_indices",
    "seed",
    "space_size",
    "substitute",
    "values_at",
]
