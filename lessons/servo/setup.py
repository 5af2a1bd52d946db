"""Runs of the servo-error lesson (Leppik 1960) built from its parameter values.

:func:`setup_for` turns validated values into the channels (k, T or T1, T2, scaled by
gamma for the y channel), the programmed path, the two-axis system (with the program
correction or the derivative feed-forward when chosen) and the article's closed form of
the steady contour error; it is built once per parameter set and shared by the headless
run, the live stepper and the scene.  :meth:`Setup.measure` is the one measurement of
the states: outputs, contour errors and foot points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Params
from analyzer_lab.lessons.servo.formulas import article_error
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo
from analyzer_lab.lessons.servo.paths import DEGREE, Path, make_path

#: transient considered gone after this many slowest time constants (e^-10 = 4.5e-5)
SETTLE = 10.0
PATH_NUMBERS = ("x0", "y0", "xc", "yc", "p", "omega", "v", "angle", "a", "b")


def channels(params: Params) -> tuple[Channel, Channel]:
    """x channel from (k, T) or (T1, T2); y channel T1y = gamma T1, T2y^2 = gamma T2^2."""
    if params["channel"] == "k-T":
        cx = Channel.from_open_loop(float(params["k"]), float(params["T"]))
    else:
        cx = Channel(T1=float(params["T1"]), T2sq=float(params["T2"]) ** 2)
    return cx, cx.scaled(float(params["gamma"]))


@dataclass
class Setup:
    """Everything a run needs, built once per parameter set."""

    path: Path
    cx: Channel
    cy: Channel
    system: TwoAxisServo
    article: float
    label: str
    #: the last measurement (states' bytes, result): a live frame measures its state once
    last: tuple[bytes, dict[str, np.ndarray]] = (b"", {})

    def measure(self, Z: np.ndarray) -> dict[str, np.ndarray]:
        """Outputs of the states Z, the contour errors and the foot points of (x1, y1)."""
        key = np.ascontiguousarray(Z, dtype=float).tobytes()
        last_key, last = self.last
        if key == last_key:
            return dict(last)
        out = self.system.outputs(Z)
        x, y = out["x"], out["y"]
        out["delta"], out["foot_x"], out["foot_y"] = self.path.contour(out["x1"], out["y1"], x, y)
        out["delta_steady"] = self.path.contour(out["x1ss"], out["y1ss"], x, y)[0]
        self.last = (key, out)
        return dict(out)


@lru_cache(maxsize=16)
def _setup(key: tuple[tuple[str, Any], ...]) -> Setup:
    params = Params(key)
    cx, cy = channels(params)
    path = make_path(params["curve"], {n: float(params[n]) for n in PATH_NUMBERS})
    system = TwoAxisServo(path.program, cx, cy, params["correction"])
    gamma = float(params["gamma"])
    if params["correction"] == "on":
        value, label = 0.0, "0 (program corrected)"
    elif params["correction"] == "derivative":
        identical = params["curve"] == "parabola" and gamma == 1.0
        value = -(float(params["omega"]) ** 2) * float(params["p"]) * cx.T2sq / 2.0
        value, label = (value, "conclusions") if identical else (math.nan, "not in the article")
    else:
        value, label = article_error(path, cx, cy, gamma)
    return Setup(path, cx, cy, system, value, label)


def setup_for(params: Params) -> Setup:
    return _setup(tuple(sorted(params.raw().items())))


def natural_t_end(params: Params) -> float:
    """A run long enough to pass the transient and show the steady error."""
    cx, cy = channels(params)
    settle = SETTLE / max(min(cx.decay_rate(), cy.decay_rate()), 1e-6)
    curve, omega, p = params["curve"], float(params["omega"]), float(params["p"])
    if curve in DEGREE or curve == "parabola-horizontal":
        speed = omega * p * (1.0 if curve in ("cubic", "quartic") else 0.5)
        along = ("yc", "y0") if curve == "parabola-horizontal" else ("xc", "x0")
        gap = float(params[along[0]]) - float(params[along[1]])
        span = 2.0 * gap / speed if gap > 0 else settle + 1.0
        return float(min(max(span, 0.1), 600.0))
    if curve == "line":
        return float(min(settle * 1.5, 600.0))
    period = 2 * math.pi / omega
    return float(min(max(settle + 2 * period, 3 * period), 600.0))
