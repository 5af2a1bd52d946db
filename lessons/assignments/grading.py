"""Grading: an answer (the unlocked parameters' values) is run by the lesson's own model
and every declared check of the assignment is measured on that run.

Results are plain data: :class:`Grade` with one :class:`CheckOutcome` per check, each
saying whether it passes, what was measured, the bound it was held to and by how much it
misses.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from analyzer_lab.lessons.assignments.spec import (
    LOCKED,
    MAX_ANSWER_BYTES,
    Assignment,
    AssignmentError,
    Check,
    Quantity,
    decode_json,
    reduction_text,
    said,
)
from analyzer_lab.lessons.kit.contract import ParamError, RunResult
from analyzer_lab.lessons.kit.message import N_, Message


@dataclass
class CheckOutcome:
    """One check measured on one run: ``miss`` > 0 by how much it fails (0 when it passes)."""

    id: str
    kind: str
    text: str
    passed: bool
    measured: float
    bound: float
    miss: float
    message: str
    #: the author's feedback for this outcome (on failure, or on a pass when given)
    feedback: str = ""

    def to_json_dict(self) -> dict[str, Any]:
        def num(v: float) -> float | None:
            return float(v) if math.isfinite(v) else None

        return {
            "id": self.id,
            "kind": self.kind,
            "text": self.text,
            "pass": self.passed,
            "measured": num(self.measured),
            "bound": num(self.bound),
            "miss": num(self.miss),
            "message": self.message,
            "feedback": self.feedback,
        }


@dataclass
class Grade:
    """The whole verdict on one answer."""

    assignment: str
    lesson: str
    passed: bool
    checks: list[CheckOutcome]
    values: dict[str, Any] = field(default_factory=dict)
    messages: list[str] = field(default_factory=list)
    #: the variant's values of the varied quantities (empty when not varied)
    variant: dict[str, float] = field(default_factory=dict)

    def to_json_dict(self) -> dict[str, Any]:
        return {
            "assignment": self.assignment,
            "lesson": self.lesson,
            "pass": self.passed,
            "variant": dict(self.variant),
            "values": dict(self.values),
            "checks": [c.to_json_dict() for c in self.checks],
            "messages": list(self.messages),
        }

    @property
    def failed(self) -> list[CheckOutcome]:
        return [c for c in self.checks if not c.passed]


#: Where a refusal of an answer says it is, when the caller names no file.
ANSWER = N_("answer")


def check_answer_values(a: Assignment, values: Any, where: str = ANSWER) -> dict[str, Any]:
    """The answer's values, refused (one line) if not an object of unlocked parameters."""
    where = _where(where)
    unlocked = ", ".join(a.unlocked)
    if not isinstance(values, dict):
        raise AssignmentError(
            where, "", Message(N_("an answer is a JSON object of parameter values"))
        )
    if not values:
        raise AssignmentError(
            where, "", Message(N_("gives no values; set some of {names}"), names=unlocked)
        )
    for k, v in values.items():
        if k not in a.unlocked:
            what = Message(LOCKED if _known(a, k) else N_("is not a parameter"))
            raise AssignmentError(
                where,
                str(k)[:40],
                Message(N_("{what} (you may set {names})"), what=what, names=unlocked),
            )
        if not isinstance(v, (str, int, float, bool)) or (isinstance(v, str) and len(v) > 400):
            raise AssignmentError(
                where, k, Message(N_("must be a number, a formula text or true/false"))
            )
    return dict(values)


def _where(where: str) -> str:
    """``where`` as a refusal names it: the default ``answer`` in the page's language."""
    return Message(ANSWER) if where == ANSWER and not isinstance(where, Message) else where


def _known(a: Assignment, name: str) -> bool:
    from analyzer_lab.lessons.catalog import get_lesson

    return any(p.name == name for p in get_lesson(a.lesson).params)


def load_answer(text: str | bytes, a: Assignment, where: str) -> dict[str, Any]:
    """Decode and check an answer file's text."""
    return check_answer_values(a, decode_json(text, where, MAX_ANSWER_BYTES), where)


def run_answer(a: Assignment, values: Mapping[str, Any], where: str = ANSWER) -> RunResult:
    """Resolve the answer over the assignment's start and simulate (refusals name the value)."""
    from analyzer_lab.lessons.catalog import get_lesson

    lesson = get_lesson(a.lesson)
    where = _where(where)
    try:
        params = lesson.resolve({**a.start, **values}, a.preset)
        return lesson.simulate(params, a.t_end)
    except ParamError as exc:
        raise AssignmentError(where, exc.name, exc.message) from None
    except ValueError as exc:
        raise AssignmentError(where, "", said(exc)) from None


def grade(a: Assignment, values: Mapping[str, Any], where: str = ANSWER) -> Grade:
    """Check ``values`` against every check of ``a`` (raises :class:`AssignmentError` on bad input)."""
    vals = check_answer_values(a, dict(values), where)
    run = run_answer(a, vals, where)
    outcomes = [measure(c, run) for c in a.checks]
    for c, o in zip(a.checks, outcomes):
        o.feedback = c.feedback_pass if o.passed else c.feedback
    return Grade(
        assignment=a.id,
        lesson=a.lesson,
        passed=all(o.passed for o in outcomes),
        checks=outcomes,
        values=vals,
        messages=list(run.messages),
        variant=dict(a.variant),
    )


def _eval(q: Quantity, run: RunResult) -> np.ndarray:
    t = np.asarray(run.t, dtype=float)
    if q.series is not None:
        return np.asarray(run.series[q.series], dtype=float)
    assert q.formula is not None
    args = [t] + [np.asarray(run.series[v], dtype=float) for v in q.formula.variables[1:]]
    return np.broadcast_to(np.asarray(q.formula(*args), dtype=float), t.shape).astype(float)


def _window(c: Check, t: np.ndarray) -> np.ndarray:
    lo = -np.inf if c.t_from is None else c.t_from - 1e-9
    hi = np.inf if c.t_to is None else c.t_to + 1e-9
    if c.by is not None:
        hi = c.by + 1e-9
    mask = (t >= lo) & (t <= hi)
    if not mask.any():
        mask[int(np.argmin(np.abs(t - (lo if np.isfinite(lo) else hi))))] = True
    return mask


def _undefined(values: np.ndarray, t: np.ndarray) -> Message | str:
    bad = ~np.isfinite(values)
    if bad.any():
        return Message(N_("not defined from t = {t:g}"), t=float(t[int(np.argmax(bad))]))
    return ""


def _reduce(how: str, v: np.ndarray) -> float:
    if how == "max-abs":
        return float(np.max(np.abs(v)))
    if how == "max":
        return float(np.max(v))
    if how == "min":
        return float(np.min(v))
    if how == "final":
        return float(v[-1])
    if how == "mean":
        return float(np.mean(v))
    return float(np.sqrt(np.mean(v * v)))


def _points(c: Check, run: RunResult) -> np.ndarray:
    return np.stack([np.asarray(run.series[n], dtype=float) for n in c.path], axis=1)


def measure(c: Check, run: RunResult) -> CheckOutcome:
    """Measure one check on a finished run."""
    t = np.asarray(run.t, dtype=float)
    text = c.describe()
    if c.kind in ("at-most", "at-least") and c.metric is not None:
        raw = run.metrics.get(c.metric)
        if isinstance(raw, bool) or not isinstance(raw, (int, float, np.floating, np.integer)):
            return _outcome(
                c,
                text,
                math.inf,
                float(c.bound or 0),
                Message(N_("the run has no metric {metric}"), metric=c.metric),
            )
        return _bound(c, text, float(raw), Message(N_("metric {metric}"), metric=c.metric))
    mask = _window(c, t)
    tw = t[mask]
    if c.kind == "within":
        assert c.quantity is not None and c.target is not None and c.tolerance is not None
        diff = _eval(c.quantity, run) - _eval(c.target, run)
        if c.at is not None:
            if not np.isfinite(diff).all():
                return _outcome(c, text, math.inf, c.tolerance, _undefined(diff, t))
            d = abs(float(np.interp(c.at, t, diff)))
            when = N_("|{quantity} - ({target})| = {value:.4g} at t = {t:g}")
            at = c.at
        else:
            dw = diff[mask]
            if not np.isfinite(dw).all():
                return _outcome(c, text, math.inf, c.tolerance, _undefined(dw, tw))
            k = int(np.argmax(np.abs(dw)))
            d = float(abs(dw[k]))
            when = N_("|{quantity} - ({target})| = {value:.4g} largest at t = {t:g}")
            at = float(tw[k])
        detail = Message(when, quantity=c.quantity.text, target=c.target.text, value=d, t=at)
        return _outcome(c, text, d, c.tolerance, detail)
    if c.kind in ("at-most", "at-least"):
        assert c.quantity is not None
        v = _eval(c.quantity, run)[mask]
        if not np.isfinite(v).all():
            return _outcome(c, text, math.inf, float(c.bound or 0), _undefined(v, tw))
        return _bound(c, text, _reduce(c.reduce, v), reduction_text(c.reduce, c.quantity.text))
    assert c.tolerance is not None
    pts = _points(c, run)
    if c.kind == "reaches":
        pw = pts[mask]
        if not np.isfinite(pw).all():
            return _outcome(c, text, math.inf, c.tolerance, _undefined(pw.sum(axis=1), tw))
        dist = np.linalg.norm(pw - np.asarray(c.point), axis=1)
        return _at(
            c, text, dist, tw, int(np.argmin(dist)), N_("closest approach {value:.4g} at t = {t:g}")
        )
    if not np.isfinite(pts).all():
        return _outcome(c, text, math.inf, c.tolerance, _undefined(pts.sum(axis=1), t))
    if c.kind == "in-plane":
        n = np.asarray(c.normal, dtype=float)
        nn = float(np.linalg.norm(n))
        dev = np.abs(pts @ n - c.offset) / nn
        far = N_("farthest from the plane by {value:.4g} at t = {t:g}")
        return _at(c, text, dev, t, int(np.argmax(dev)), far)
    # on-circle
    centre = np.asarray(c.center, dtype=float)
    rel = pts - centre
    dev = np.abs(np.linalg.norm(rel, axis=1) - float(c.radius or 0))
    if c.normal is not None:
        n = np.asarray(c.normal, dtype=float) / float(np.linalg.norm(c.normal))
        off = rel @ n
        dev = np.hypot(
            np.abs(np.linalg.norm(rel - np.outer(off, n), axis=1) - float(c.radius or 0)), off
        )
    far = N_("farthest from the circle by {value:.4g} at t = {t:g}")
    return _at(c, text, dev, t, int(np.argmax(dev)), far)


def _bound(c: Check, text: str, value: float, what: Message) -> CheckOutcome:
    bound = float(c.bound if c.bound is not None else 0.0)
    if not math.isfinite(value):
        return _outcome(c, text, math.inf, bound, Message(N_("{what} is not finite"), what=what))
    above = c.kind == "at-most"
    miss = max(0.0, value - bound) if above else max(0.0, bound - value)
    if not miss:
        detail = Message(N_("{what} = {value:.4g}"), what=what, value=value)
    elif above:
        detail = Message(
            N_("{what} = {value:.4g}, {miss:.3g} above the bound {bound:g}"),
            what=what,
            value=value,
            miss=miss,
            bound=bound,
        )
    else:
        detail = Message(
            N_("{what} = {value:.4g}, {miss:.3g} below the bound {bound:g}"),
            what=what,
            value=value,
            miss=miss,
            bound=bound,
        )
    return CheckOutcome(c.id, c.kind, text, miss == 0.0, value, bound, miss, detail)


def _at(
    c: Check, text: str, values: np.ndarray, t: np.ndarray, k: int, template: str
) -> CheckOutcome:
    """The deviation ``values[k]`` at the time ``t[k]`` checked against the tolerance
    (``template`` says it in words with ``{value}`` and ``{t}``)."""
    assert c.tolerance is not None
    v = float(values[k])
    return _outcome(c, text, v, c.tolerance, Message(template, value=v, t=float(t[k])))


def _outcome(
    c: Check, text: str, measured: float, tol: float, detail: Message | str
) -> CheckOutcome:
    """A deviation checked against a tolerance (``measured`` <= ``tol`` passes); the
    detail a :class:`Message` (shown in a page's language)."""
    miss = max(0.0, measured - tol) if math.isfinite(measured) else math.inf
    passed = bool(math.isfinite(measured) and measured <= tol)
    msg = (
        detail
        if passed
        else Message(
            N_("{detail}; misses the tolerance {tolerance:g} by {miss:.3g}"),
            detail=detail,
            tolerance=tol,
            miss=miss,
        )
    )
    return CheckOutcome(c.id, c.kind, text, passed, measured, tol, miss, msg)
