"""Results as plain data: a finished run (a response object) and the source's claims.

Part of the lesson contract (:mod:`analyzer_lab.lessons.kit.contract` re-exports every name).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.formula import Formula


@dataclass
class ClaimResult:
    expected: str
    got: str
    passed: bool


@dataclass(frozen=True)
class Claim:
    """A checkable statement of the source: ``check()`` computes and compares."""

    id: str
    statement: str
    source: str
    check: Callable[[], ClaimResult]


@dataclass
class RunResult:
    """A finished run: samples, named series and scalar metrics (a response object)."""

    lesson: str
    preset: str | None
    params: dict[str, Any]
    t: np.ndarray
    series: dict[str, np.ndarray]
    metrics: dict[str, Any] = field(default_factory=dict)
    messages: list[str] = field(default_factory=list)
    #: series name -> unit (from the lesson's declarations; "" for a pure number)
    units: dict[str, str] = field(default_factory=dict)

    def to_json_dict(self) -> dict[str, Any]:
        def clean(v: Any) -> Any:
            if isinstance(v, np.ndarray):
                return [clean(x) for x in v.tolist()]
            if isinstance(v, (np.floating, float)):
                f = float(v)
                return f if math.isfinite(f) else None
            if isinstance(v, (np.integer,)):
                return int(v)
            if isinstance(v, np.bool_):
                return bool(v)
            if isinstance(v, Formula):
                return v.text
            if isinstance(v, dict):
                return {str(k): clean(x) for k, x in v.items()}
            if isinstance(v, (list, tuple)):
                return [clean(x) for x in v]
            return v

        return {
            "lesson": self.lesson,
            "preset": self.preset,
            "params": clean(self.params),
            "t": clean(np.asarray(self.t, dtype=float)),
            "series": {k: clean(np.asarray(v, dtype=float)) for k, v in self.series.items()},
            "units": {k: self.units.get(k, "") for k in self.series},
            "metrics": clean(self.metrics),
            "messages": list(self.messages),
        }

    def to_csv(self) -> str:
        """One row per sample: ``t`` then every series (1-D series only)."""
        names = [k for k, v in self.series.items() if np.ndim(v) == 1 and len(v) == len(self.t)]
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["t", *names])
        cols = [np.asarray(self.t, dtype=float)] + [
            np.asarray(self.series[n], dtype=float) for n in names
        ]
        for row in zip(*cols):
            w.writerow([repr(float(x)) for x in row])
        return buf.getvalue()


def close(expected: float, got: float, rtol: float = 0.0, atol: float = 0.0) -> ClaimResult:
    """A numeric claim result: ``|got - expected| <= atol + rtol |expected|``."""
    ok = bool(np.isfinite(got) and abs(got - expected) <= atol + rtol * abs(expected))
    tol = f" (atol {atol:g}, rtol {rtol:g})"
    return ClaimResult(expected=f"{expected:.10g}{tol}", got=f"{got:.10g}", passed=ok)


def at_most(bound: float, got: float, what: str = "") -> ClaimResult:
    """A bound claim result: ``got <= bound``."""
    ok = bool(np.isfinite(got) and got <= bound)
    return ClaimResult(expected=f"{what}<= {bound:.3g}", got=f"{got:.3g}", passed=ok)
