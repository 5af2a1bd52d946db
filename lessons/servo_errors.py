"""Dynamic contouring errors of two-coordinate servo systems (K. Leppik, 1960), eqs (1)-(35).

A programming device (PU) generates the programmed curve x = f1(t), y = f2(t); two
servo channels (2) (T2^2 s^2 + T1 s + 1) x1 = x reproduce it.  The lesson shows the
programmed point, the reproduced point and the contour error magnified N times, the
article's closed forms next to the exact simulation, the program correction (7),
(21)-(22), (31)-(34), and the article's parabola table three ways: formula (13),
simulation and the printed values (which are 0.8 x (13) in every cell).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from lessons.core.contract import (
    Claim,
    ClaimResult,
    CurveItem,
    DerivationStep,
    Frame,
    Lesson,
    MarkerItem,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Stepper,
    at_most,
    close,
)
from lessons.core.servo import (
    Channel,
    Program,
    TableRow,
    TwoAxisServo,
    circle_axes_29_30,
    delta_line_5,
    delta_parabola_13,
    ellipse_distance,
    ellipse_program,
    f_transient,
    fit_centred_ellipse,
    format_table,
    line_distance,
    line_program,
    parabola_table,
    parabola_vertex_17,
    power_distance,
    power_program,
    table_ratio_interval,
)

CURVES = ("line", "parabola", "circle", "ellipse", "cubic", "quartic")
DEGREE = {"parabola": 2, "cubic": 3, "quartic": 4}
#: parameters whose change restarts the live run (they fix the start of the program)
RESTART = ("curve", "x0", "y0", "xc", "yc", "a", "b", "xdot0", "ydot0")
#: transient considered gone after this many slowest time constants (e^-10 = 4.5e-5)
SETTLE = 10.0


@lru_cache(maxsize=4)
def _table(v: float, p: float, omega: float) -> tuple[TableRow, ...]:
    return tuple(parabola_table(v, p, omega))


def table_rows(v: float = 50.0, p: float = 20.0, omega: float = 5.0) -> list[dict[str, Any]]:
    """The article's parabola table as plain rows: k, T, (13), simulation, printed, ratios."""
    return [dict(r.__dict__) for r in _table(v, p, omega)]


# ---------------------------------------------------------------- set-up from parameters


@dataclass
class Setup:
    """Everything a run needs, built from validated parameters."""

    curve: str
    cx: Channel
    cy: Channel
    program: Program
    system: TwoAxisServo
    params: Params
    article_value: float
    article_label: str
    messages: list[str]

    def contour(
        self, x1: np.ndarray, y1: np.ndarray, out: dict[str, np.ndarray]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Signed distance of (x1, y1) from the programmed curve (through the PU's current point), foot points."""
        P = self.params
        x, y = out["x"], out["y"]
        if self.curve == "line":
            return line_distance(x1, y1, x, y, float(P["angle"]))
        if self.curve in DEGREE:
            n = DEGREE[self.curve]
            xc, p = float(P["xc"]), float(P["p"])
            yc = y - (x - xc) ** n / p  # the curve through the PU's point (constant along a run)
            return power_distance(x1, y1, n, xc, yc, p, guess=x)
        xc, yc = float(P["xc"]), float(P["yc"])
        a, b = (float(P["a"]), float(P["b"])) if self.curve == "ellipse" else (1.0, 1.0)
        s = np.sqrt(((np.atleast_1d(x) - xc) / a) ** 2 + ((np.atleast_1d(y) - yc) / b) ** 2)
        scale = float(np.median(s))
        return ellipse_distance(x1, y1, xc, yc, a * scale, b * scale)


def channels(params: Params) -> tuple[Channel, Channel]:
    """x channel from (k, T) or (T1, T2); y channel scaled by gamma (T1y = gamma T1, T2y^2 = gamma T2^2)."""
    if params["channel"] == "k-T":
        cx = Channel.from_open_loop(float(params["k"]), float(params["T"]))
    else:
        cx = Channel(T1=float(params["T1"]), T2sq=float(params["T2"]) ** 2)
    return cx, cx.scaled(float(params["gamma"]))


def build_program(params: Params) -> Program:
    curve = params["curve"]
    x0, y0, xc, yc = (float(params[n]) for n in ("x0", "y0", "xc", "yc"))
    omega, p = float(params["omega"]), float(params["p"])
    if curve == "line":
        return line_program(x0, y0, float(params["v"]), float(params["angle"]))
    if curve in DEGREE:
        return power_program(DEGREE[curve], x0, xc, yc, p, omega)
    if curve == "circle":
        return ellipse_program(x0, y0, xc, yc, 1.0, 1.0, omega)
    return ellipse_program(x0, y0, xc, yc, float(params["a"]), float(params["b"]), omega)


def cubic_offset(omega: float, p: float, cx: Channel, cy: Channel) -> float:
    """Height of the reproduced cubic above the programmed inflection point (steady state)."""
    tau, T1, T2 = cx.T1, cy.T1, cy.T2sq
    return (
        omega**3
        * p**2
        * (tau**3 - 3 * (T1 * tau**2 + 2 * T2 * tau - 2 * T1**2 * tau + 2 * T1**3 - 4 * T1 * T2))
    )


def quartic_offset(omega: float, p: float, cx: Channel, cy: Channel) -> float:
    """Height of the reproduced quartic above the programmed vertex (corrected y1(t), steady state)."""
    tau, T1, T2 = cx.T1, cy.T1, cy.T2sq
    inner = (
        T1 * tau**3
        - 3 * (T1**2 - T2) * tau**2
        + 6 * (T1**3 - 2 * T1 * T2) * tau
        - 6 * (T1**4 - 3 * T1**2 * T2 + T2**2)
    )
    return omega**4 * p**3 * (tau**4 - 4 * inner)


def article_value(params: Params, program: Program, cx: Channel, cy: Channel) -> tuple[float, str]:
    """The article's closed form of the steady contour error for this case, and its label."""
    curve = params["curve"]
    if params["correction"] == "on":
        return 0.0, "0 (program corrected)"
    omega, p, gamma = float(params["omega"]), float(params["p"]), float(params["gamma"])
    if curve == "line":
        return delta_line_5(float(params["v"]), float(params["angle"]), cx.T1, gamma), "(5)"
    if curve == "parabola":
        if gamma == 1.0:
            return delta_parabola_13(omega, p, cx.T1, cx.T2sq), "(13)"
        return parabola_vertex_17(omega, p, cx.T1, cx.T2sq, gamma)[1], "(17) vertex height"
    if curve == "cubic":
        return cubic_offset(omega, p, cx, cy), "inflection shift"
    if curve == "quartic":
        return quartic_offset(omega, p, cx, cy), "vertex shift"
    xc, yc = float(params["xc"]), float(params["yc"])
    z0 = program.z0
    X, Y = z0[0] - xc, z0[1] - yc
    if curve == "circle":
        R0 = math.hypot(X, Y)
        if gamma == 1.0:
            return R0 * (1.0 - abs(cx.response(omega))), "(28)"
        P1, P2 = cx.response(omega), cy.response(omega)
        _, major, _ = circle_axes_29_30(
            R0 * abs(P1), R0 * abs(P2), float(np.angle(P2) - np.angle(P1))
        )
        return R0 - major, "R0 - a, (30)"
    a, b = float(params["a"]), float(params["b"])
    s = math.sqrt((X / a) ** 2 + (Y / b) ** 2)
    a, b = a * s, b * s
    if gamma == 1.0:
        return a * (1.0 - abs(cx.response(omega))), "a(1 - |Phi|)"
    P1, P2 = cx.response(omega), cy.response(omega)
    _, major, _ = circle_axes_29_30(a * abs(P1), b * abs(P2), float(np.angle(P2) - np.angle(P1)))
    return max(a, b) - major, "a - a', (30)"


def make_setup(params: Params) -> Setup:
    cx, cy = channels(params)
    program = build_program(params)
    system = TwoAxisServo(program, cx, cy, "on" if params["correction"] == "on" else "off")
    value, label = article_value(params, program, cx, cy)
    messages: list[str] = []
    if params["curve"] in DEGREE:
        y_start = float(program.z0[1])
        if abs(y_start - float(params["y0"])) > 1e-9 * (1.0 + abs(y_start)):
            messages.append(
                f"y0 is taken on the curve: the {params['curve']} starts at ({float(params['x0']):g}, {y_start:.6g}) mm."
            )
    return Setup(params["curve"], cx, cy, program, system, params, value, label, messages)


def natural_t_end(params: Params) -> float:
    """A run long enough to pass the transient and show the steady error."""
    cx, cy = channels(params)
    settle = SETTLE / max(min(cx.decay_rate(), cy.decay_rate()), 1e-6)
    curve = params["curve"]
    omega = float(params["omega"])
    if curve in DEGREE:
        speed = float(params["omega"]) * float(params["p"]) * (0.5 if curve == "parabola" else 1.0)
        gap = float(params["xc"]) - float(params["x0"])
        span = 2.0 * gap / speed if gap > 0 else settle + 1.0
        return float(min(max(span, 0.1), 600.0))
    if curve == "line":
        return float(min(settle * 1.5, 600.0))
    period = 2 * math.pi / omega
    return float(min(max(settle + 2 * period, 3 * period), 600.0))


# ---------------------------------------------------------------- stepper


class ServoStepper(Stepper):
    """Live run: the whole linear system is advanced exactly (matrix exponential) per frame."""

    def __init__(self, lesson: ServoErrorsLesson, params: Params) -> None:
        self._lesson = lesson
        self._params = params
        self._setup = make_setup(params)
        self._z = self._setup.system.initial_state(float(params["xdot0"]), float(params["ydot0"]))
        self._t = 0.0
        self._note = ""

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        s = self._setup
        out = s.system.outputs(self._z)
        d, fx, fy = s.contour(out["x1"], out["y1"], out)
        dss, _, _ = s.contour(out["x1ss"], out["y1ss"], out)
        N = float(self._params["magnify"])
        x1, y1 = float(out["x1"][0]), float(out["y1"][0])
        foot = np.array([float(fx[0]), float(fy[0]), 0.0])
        err = np.array([x1, y1, 0.0]) - foot
        points = {
            "programmed": np.array([[float(out["x"][0]), float(out["y"][0]), 0.0]]),
            "reproduced": np.array([[x1, y1, 0.0]]),
            "error x N": (foot + N * err)[None, :],
        }
        if self._params["correction"] == "on":
            points["corrected program"] = np.array(
                [[float(out["ux"][0]), float(out["uy"][0]), 0.0]]
            )
        message = self._note
        rate = s.system.decay_rate()
        if not message and self._t * rate < SETTLE:
            message = (
                f"transient: e^(-t/tau) = {math.exp(-self._t * rate):.2g} (tau = {1 / rate:.3g} s)"
            )
        return Frame(
            t=self._t,
            points=points,
            vectors={"error vector x N": (foot[None, :], (N * err)[None, :])},
            scalars={
                "x1 - x": float(out["x1"][0] - out["x"][0]),
                "y1 - y": float(out["y1"][0] - out["y"][0]),
                "delta": float(d[0]),
                "delta steady": float(dss[0]),
                "delta article": float(s.article_value),
            },
            message=message,
        )

    def advance(self, dt: float) -> Frame:
        if dt > 0 and math.isfinite(dt):
            self._z = self._setup.system.transition(float(dt)) @ self._z
            self._t += float(dt)
            self._note = ""
        return self.frame()

    def set_params(self, params: Params) -> None:
        old = self._params
        restart = any(old[n] != params[n] for n in RESTART)
        if params["curve"] in ("cubic", "quartic") and (
            old["omega"] != params["omega"] or old["p"] != params["p"]
        ):
            restart = True
        self._params = params
        self._setup = make_setup(params)
        if restart:
            self.reset()
            self._note = "program start changed: run restarted"

    def reset(self) -> Frame:
        self._setup = make_setup(self._params)
        self._z = self._setup.system.initial_state(
            float(self._params["xdot0"]), float(self._params["ydot0"])
        )
        self._t = 0.0
        self._note = ""
        return self.frame()


# ---------------------------------------------------------------- the lesson


def _sig(x: float) -> str:
    return f"{x:.6g}"


class ServoErrorsLesson(Lesson):
    id = "servo-errors"
    title = "Dynamic contouring errors of two-coordinate servo systems"
    chapter = "Articles"
    problem = "Leppik (1960)"
    source = "K. Leppik, On dynamic errors of two-coordinate servo systems with program control, eqs (1)-(35)"
    summary = (
        "A programming device draws lines, parabolas (degree 2, 3, 4), circles and ellipses; two second-order "
        "servo channels reproduce them.  Closed forms of the article next to the exact simulation, program "
        "correction, and the article's parabola table (printed values = 0.8 x formula (13))."
    )
    order = 200.0
    t_end = 5.0
    params = (
        Param(
            "curve",
            "choice",
            "parabola",
            "curve",
            choices=CURVES,
            group="surface",
            help="the article's programming devices",
        ),
        Param(
            "channel",
            "choice",
            "k-T",
            "channel given by",
            choices=("k-T", "T1-T2"),
            group="method",
            help="k-T: open loop W(s) = k/((Ts+1)s), so T2^2 = T/k, T1 = 1/k; T1-T2: directly",
        ),
        Param(
            "k", "float", 100.0, "k", "1/s", 1.0, 1e5, 1.0, group="method", help="open-loop gain"
        ),
        Param(
            "T",
            "float",
            0.1,
            "T",
            "s",
            1e-4,
            10.0,
            0.001,
            group="method",
            help="open-loop time constant",
        ),
        Param("T1", "float", 0.01, "T1", "s", 1e-5, 10.0, 0.001, group="method"),
        Param("T2", "float", 0.0316227766, "T2", "s", 1e-5, 10.0, 0.001, group="method"),
        Param(
            "gamma",
            "float",
            1.0,
            "gamma (y channel)",
            "",
            0.05,
            20.0,
            0.01,
            group="method",
            help="non-identical channels: T1y = gamma T1, T2y^2 = gamma T2^2",
        ),
        Param(
            "omega",
            "float",
            5.0,
            "omega",
            "1/s",
            1e-4,
            1000.0,
            0.1,
            help="PU rate (angular frequency for circles and ellipses)",
        ),
        Param(
            "p",
            "float",
            20.0,
            "p",
            "mm (mm^2, mm^3)",
            1e-3,
            1e9,
            1.0,
            group="surface",
            help="parabola parameter: y - yc = (x - xc)^n / p",
        ),
        Param("v", "float", 50.0, "v (line)", "mm/s", 0.0, 1e4, 1.0, help="path speed of the line"),
        Param("angle", "float", 45.0, "line angle", "deg", -180.0, 180.0, 1.0, group="surface"),
        Param(
            "x0",
            "float",
            -125.0,
            "x0",
            "mm",
            -1e5,
            1e5,
            1.0,
            group="initial",
            help="start of the program",
        ),
        Param(
            "y0",
            "float",
            781.25,
            "y0",
            "mm",
            -1e5,
            1e5,
            1.0,
            group="initial",
            help="start ordinate (line, circle, ellipse); parabolas start on their curve",
        ),
        Param(
            "xc", "float", 0.0, "xc", "mm", -1e5, 1e5, 1.0, group="surface", help="vertex / centre"
        ),
        Param(
            "yc", "float", 0.0, "yc", "mm", -1e5, 1e5, 1.0, group="surface", help="vertex / centre"
        ),
        Param("a", "float", 15.0, "a (ellipse)", "mm", 1e-3, 1e5, 1.0, group="surface"),
        Param("b", "float", 6.0, "b (ellipse)", "mm", 1e-3, 1e5, 1.0, group="surface"),
        Param(
            "xdot0",
            "float",
            0.0,
            "dx1/dt(0)",
            "mm/s",
            -1e4,
            1e4,
            1.0,
            group="initial",
            help="initial servo velocity",
        ),
        Param("ydot0", "float", 0.0, "dy1/dt(0)", "mm/s", -1e4, 1e4, 1.0, group="initial"),
        Param(
            "correction",
            "choice",
            "off",
            "program correction",
            choices=("off", "on"),
            group="method",
            help="feed (T2^2 s^2 + T1 s + 1) x: modified initial conditions and inputs (7), (21)-(22), (31)-(34)",
        ),
        Param(
            "magnify",
            "float",
            100.0,
            "error x N",
            "",
            1.0,
            1e6,
            1.0,
            group="controls",
            help="magnification of the contour error in the scene",
        ),
    )
    presets = (
        Preset(
            "table-parabola",
            "Table parabola: v = 50 mm/s, p = 20 mm, omega = 5, k = 100 1/s, T = 0.1 s",
            {
                "curve": "parabola",
                "channel": "k-T",
                "k": 100,
                "T": 0.1,
                "omega": 5,
                "p": 20,
                "v": 50,
                "x0": -125,
                "y0": 781.25,
                "xc": 0,
                "yc": 0,
                "gamma": 1,
                "correction": "off",
                "magnify": 100,
            },
            t_end=5.0,
            note="(13): -0.2375 mm; simulation -0.2375 mm; printed -0.19 mm = 0.8 x (13)",
        ),
        Preset(
            "parabola-corrected",
            "Parabola with program correction (22), k = 100 1/s, T = 0.1 s",
            {
                "curve": "parabola",
                "channel": "k-T",
                "k": 100,
                "T": 0.1,
                "omega": 5,
                "p": 20,
                "x0": -125,
                "y0": 781.25,
                "xc": 0,
                "yc": 0,
                "gamma": 1,
                "correction": "on",
                "magnify": 100,
            },
            t_end=5.0,
            note="the steady error vanishes; the transient from rest remains",
        ),
        Preset(
            "line-45",
            "Line at 45 deg, non-identical channels gamma = 1.2, k = 100 1/s, T = 0.05 s",
            {
                "curve": "line",
                "channel": "k-T",
                "k": 100,
                "T": 0.05,
                "v": 50,
                "angle": 45,
                "x0": 0,
                "y0": 0,
                "gamma": 1.2,
                "omega": 5,
                "correction": "off",
                "magnify": 200,
            },
            t_end=1.5,
            note="(5)/(6): 0.05 mm = v T1 (gamma - 1)/2",
        ),
        Preset(
            "line-transient",
            "Line at 45 deg, identical channels, initial velocity dx1/dt = 50 mm/s",
            {
                "curve": "line",
                "channel": "T1-T2",
                "T1": 0.01,
                "T2": 0.0223606798,
                "v": 50,
                "angle": 45,
                "x0": 0,
                "y0": 0,
                "gamma": 1,
                "xdot0": 50,
                "ydot0": 0,
                "correction": "off",
                "magnify": 50,
            },
            t_end=1.5,
            note="(4): transient error only; its peak ~ 1.05 T2^2/(T1 + T2) x (xdot0 xc - ydot0 yc)/|.|",
        ),
        Preset(
            "circle",
            "Circle R0 = 10 mm, omega = 5, identical channels k = 100 1/s, T = 0.1 s",
            {
                "curve": "circle",
                "channel": "k-T",
                "k": 100,
                "T": 0.1,
                "omega": 5,
                "x0": 0,
                "y0": 10,
                "xc": 0,
                "yc": 0,
                "gamma": 1,
                "correction": "off",
                "magnify": 20,
            },
            t_end=5.0,
            note="(28): R0 (1 - |Phi(j omega)|) = -0.24295 mm",
        ),
        Preset(
            "circle-nonidentical",
            "Circle R0 = 10 mm, omega = 10; x: k = 100, T = 0.1; y: k = 60, T = 0.1 (gamma = 5/3)",
            {
                "curve": "circle",
                "channel": "k-T",
                "k": 100,
                "T": 0.1,
                "omega": 10,
                "x0": 0,
                "y0": 10,
                "xc": 0,
                "yc": 0,
                "gamma": 5 / 3,
                "correction": "off",
                "magnify": 5,
            },
            t_end=5.0,
            note="(29): tilt 63.127 deg; corrected (30): 12.00691 / 10.78178 mm",
        ),
        Preset(
            "ellipse",
            "Ellipse a = 15, b = 6 mm, omega = 8, identical channels k = 100, T = 0.1",
            {
                "curve": "ellipse",
                "channel": "k-T",
                "k": 100,
                "T": 0.1,
                "omega": 8,
                "a": 15,
                "b": 6,
                "x0": 0,
                "y0": 6,
                "xc": 0,
                "yc": 0,
                "gamma": 1,
                "correction": "off",
                "magnify": 5,
            },
            t_end=5.0,
            note="semi-axes a|Phi| = 15.96743, b|Phi| = 6.38697 mm",
        ),
        Preset(
            "ellipse-nonidentical",
            "Ellipse a = 15, b = 6 mm, omega = 8; y channel k = 60 (gamma = 5/3)",
            {
                "curve": "ellipse",
                "channel": "k-T",
                "k": 100,
                "T": 0.1,
                "omega": 8,
                "a": 15,
                "b": 6,
                "x0": 0,
                "y0": 6,
                "xc": 0,
                "yc": 0,
                "gamma": 5 / 3,
                "correction": "off",
                "magnify": 5,
            },
            t_end=5.0,
            note="(29)/(30) with m = a|Phi1|, n = b|Phi2|: 15.97402 / 6.62696 mm, tilt 1.809 deg",
        ),
        Preset(
            "cubic",
            "Cubic parabola y = x^3/p, p = 400 mm^2, omega = 0.125, T1 = 0.01 s, T2^2 = 0.0005 s^2",
            {
                "curve": "cubic",
                "channel": "T1-T2",
                "T1": 0.01,
                "T2": 0.0223606798,
                "omega": 0.125,
                "p": 400,
                "x0": -50,
                "y0": -312.5,
                "xc": 0,
                "yc": 0,
                "gamma": 1,
                "correction": "off",
                "magnify": 200,
            },
            t_end=2.0,
            note="inflection shift 2 omega^3 p^2 (3 T1 T2^2 - T1^3) = 0.00875 mm",
        ),
        Preset(
            "quartic",
            "Quartic parabola y = x^4/p, p = 8000 mm^3, omega = 0.00625, T1 = 0.01 s, T2^2 = 0.0005 s^2",
            {
                "curve": "quartic",
                "channel": "T1-T2",
                "T1": 0.01,
                "T2": 0.0223606798,
                "omega": 0.00625,
                "p": 8000,
                "x0": -30,
                "y0": 101.25,
                "xc": 0,
                "yc": 0,
                "gamma": 1,
                "correction": "off",
                "magnify": 500,
            },
            t_end=1.2,
            note="vertex shift 3 omega^4 p^3 (3T1^4 + 8T2^4 - 12 T1^2 T2^2) = 0.00335 mm",
        ),
    )
    plots = (
        PlotSpec("Per-axis errors", ("x1 - x", "y1 - y"), "mm"),
        PlotSpec("Contour error", ("delta", "delta steady", "delta article"), "mm"),
    )

    # -- parameters -------------------------------------------------------------

    def validate(self, params: Params) -> None:
        curve = params["curve"]
        if curve in ("circle", "ellipse"):
            if float(params["x0"]) == float(params["xc"]) and float(params["y0"]) == float(
                params["yc"]
            ):
                raise ParamError(
                    "y0",
                    "the start point coincides with the centre (xc, yc); the radius would be 0",
                )
        if params["channel"] == "k-T":
            cx = Channel.from_open_loop(float(params["k"]), float(params["T"]))
        else:
            cx = Channel(float(params["T1"]), float(params["T2"]) ** 2)
        if cx.decay_rate() * 600.0 < 1.0:
            raise ParamError(
                "T",
                "the channel is too weakly damped (decay time above 600 s); raise T1 or lower T2",
            )

    # -- headless run -------------------------------------------------------------

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = natural_t_end(params) if t_end is None else float(t_end)
        s = make_setup(params)
        messages = list(s.messages)
        cx, cy = s.cx, s.cy
        w_fast = max(1.0 / math.sqrt(cx.T2sq), 1.0 / math.sqrt(cy.T2sq), float(params["omega"]))
        if not (t_end > 0 and math.isfinite(t_end)):
            messages.append("t_end must be positive; returning the initial state only")
            t = np.array([0.0])
        else:
            n = int(min(20001, max(2001, 20 * t_end * w_fast / (2 * math.pi))))
            t = np.linspace(0.0, t_end, n)
        Z = s.system.run(t, s.system.initial_state(float(params["xdot0"]), float(params["ydot0"])))
        out = s.system.outputs(Z)
        d, fx, fy = s.contour(out["x1"], out["y1"], out)
        dss, _, _ = s.contour(out["x1ss"], out["y1ss"], out)
        series = {
            "x": out["x"],
            "y": out["y"],
            "z": np.zeros_like(t),
            "x1": out["x1"],
            "y1": out["y1"],
            "ux": out["ux"],
            "uy": out["uy"],
            "ex": out["x1"] - out["x"],
            "ey": out["y1"] - out["y"],
            "delta": d,
            "delta_steady": dss,
            "delta_article": np.full_like(t, s.article_value),
        }
        rate = s.system.decay_rate()
        t_tr = SETTLE / rate
        metrics: dict[str, Any] = {
            "curve": s.curve,
            "T1x": cx.T1,
            "T2x_sq": cx.T2sq,
            "T1y": cy.T1,
            "T2y_sq": cy.T2sq,
            "zeta_x": cx.zeta,
            "zeta_y": cy.zeta,
            "t_transient": t_tr,
            "article_formula": s.article_label,
            "delta_article": s.article_value,
            "correction": params["correction"],
            "input_x0": float(out["ux"][0]),
            "input_y0": float(out["uy"][0]),
        }
        after = t >= t_tr
        if after.any():
            i = int(np.argmax(np.where(after, np.abs(d), -1.0)))
            metrics["delta_after_transient"] = float(d[i])
            metrics["delta_end"] = float(d[-1])
        else:
            metrics["delta_after_transient"] = float("nan")
            metrics["delta_end"] = float(d[-1])
            messages.append(
                f"the run ends before the transient has decayed (t_end {t_end:g} s < {t_tr:.3g} s)"
            )
        metrics["delta_steady_extreme"] = float(dss[int(np.argmax(np.abs(dss)))])
        self._curve_metrics(params, s, t, out, after, metrics)
        return RunResult(self.id, None, params.raw(), t, series, metrics, messages)

    def _curve_metrics(
        self,
        params: Params,
        s: Setup,
        t: np.ndarray,
        out: dict[str, np.ndarray],
        after: np.ndarray,
        metrics: dict[str, Any],
    ) -> None:
        omega, p = float(params["omega"]), float(params["p"])
        cx, cy = s.cx, s.cy
        if s.curve == "line":
            metrics["delta_5"] = delta_line_5(
                float(params["v"]), float(params["angle"]), cx.T1, float(params["gamma"])
            )
            metrics["v"] = float(params["v"])
        elif s.curve == "parabola":
            metrics["delta_13"] = delta_parabola_13(omega, p, cx.T1, cx.T2sq)
            metrics["v_vertex"] = omega * p / 2.0
            metrics["vertex_17_x"], metrics["vertex_17_y"] = parabola_vertex_17(
                omega, p, cx.T1, cx.T2sq, float(params["gamma"])
            )
            key = (float(params["k"]), float(params["T"]))
            if (
                params["channel"] == "k-T"
                and omega == 5.0
                and p == 20.0
                and any((r.k, r.T) == key for r in _table(50.0, 20.0, 5.0))
            ):
                row = next(r for r in _table(50.0, 20.0, 5.0) if (r.k, r.T) == key)
                metrics["table_printed"] = row.printed
                metrics["table_formula_13"] = row.formula_13
                metrics["table_simulated"] = row.simulated
                metrics["table_printed_over_13"] = row.printed_over_formula
                metrics["table_note"] = (
                    "the printed table is 0.8 x (13) in every cell; the simulation agrees with (13)"
                )
        elif s.curve in ("circle", "ellipse"):
            xc, yc = float(params["xc"]), float(params["yc"])
            X, Y = float(out["x"][0]) - xc, float(out["y"][0]) - yc
            if s.curve == "circle":
                A0 = B0 = math.hypot(X, Y)
                metrics["R0"] = A0
            else:
                sc = math.sqrt((X / float(params["a"])) ** 2 + (Y / float(params["b"])) ** 2)
                A0, B0 = float(params["a"]) * sc, float(params["b"]) * sc
                metrics["a"], metrics["b"] = A0, B0
            if s.curve == "circle":
                metrics["v"] = omega * A0
            P1, P2 = cx.response(omega), cy.response(omega)
            m, n = A0 * abs(P1), B0 * abs(P2)
            dphi = float(np.angle(P2) - np.angle(P1))
            alpha, major, minor = circle_axes_29_30(m, n, dphi)
            _, major_p, minor_p = circle_axes_29_30(m, n, dphi, printed=True)
            metrics.update(
                {
                    "m": m,
                    "n": n,
                    "phi2_minus_phi1_deg": math.degrees(dphi),
                    "tilt_29_deg": alpha,
                    "semi_major_30": major,
                    "semi_minor_30": minor,
                    "semi_major_30_printed": major_p,
                    "semi_minor_30_printed": minor_p,
                }
            )
            identical = float(params["gamma"]) == 1.0
            if s.curve == "circle" and identical:
                metrics["R0_minus_R_28"] = A0 * (1.0 - abs(P1))
            last = after & (t >= t[-1] - 2 * math.pi / omega)  # the most settled full period
            if last.sum() >= 16 and t[-1] - 2 * math.pi / omega >= t[0]:
                after = last
            if after.sum() >= 16:
                xs, ys = out["x1"][after] - xc, out["y1"][after] - yc
                a_s, b_s, ang = fit_centred_ellipse(xs, ys)
                metrics.update({"sim_semi_major": a_s, "sim_semi_minor": b_s})
                if not identical:
                    metrics["sim_tilt_deg"] = ang
                if s.curve == "circle" and identical:
                    r = np.hypot(xs, ys)
                    metrics["sim_R0_minus_R"] = A0 - float(np.mean(r))
        elif s.curve in ("cubic", "quartic"):
            metrics["v_x"] = omega * p

    # -- live --------------------------------------------------------------------

    def stepper(self, params: Params) -> Stepper:
        return ServoStepper(self, params)

    def scene(self, params: Params) -> SceneSpec:
        s = make_setup(params)
        t_end = natural_t_end(params)
        t = np.linspace(0.0, t_end, 801)
        Z = s.system.run(t, s.system.initial_state(float(params["xdot0"]), float(params["ydot0"])))
        out = s.system.outputs(Z)
        prog = np.column_stack([out["x"], out["y"], np.zeros_like(t)])
        N = float(params["magnify"])
        dss, fx, fy = s.contour(out["x1ss"], out["y1ss"], out)
        mag = np.column_stack(
            [fx + N * (out["x1ss"] - fx), fy + N * (out["y1ss"] - fy), np.zeros_like(t)]
        )
        pts = np.vstack([prog, mag])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        span = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-3))
        lo = lo - 0.05 * span
        hi = hi + 0.05 * span
        lo[2], hi[2] = -0.05 * span, 0.05 * span
        markers = [MarkerItem("start", prog[:1], (40, 160, 60), 0.01 * span, "start")]
        if s.curve != "line":
            markers.append(
                MarkerItem(
                    "vertex / centre",
                    np.array(
                        [
                            [
                                float(params["xc"]),
                                float(params["yc"])
                                if s.curve not in DEGREE
                                else float(
                                    out["y"][0]
                                    - (out["x"][0] - float(params["xc"])) ** DEGREE[s.curve]
                                    / float(params["p"])
                                ),
                                0.0,
                            ]
                        ]
                    ),
                    (120, 120, 120),
                    0.008 * span,
                    "vertex" if s.curve in DEGREE else "centre",
                )
            )
        moving = {
            "programmed": (40, 40, 200),
            "reproduced": (220, 60, 60),
            "error x N": (230, 150, 20),
        }
        if params["correction"] == "on":
            moving["corrected program"] = (150, 60, 200)
        return SceneSpec(
            bounds=(tuple(float(v) for v in lo), tuple(float(v) for v in hi)),
            curves=[
                CurveItem("programmed curve", prog, (40, 40, 200), 2.0),
                CurveItem(f"steady output, error x {N:g}", mag, (230, 150, 20), 1.5),
            ],
            markers=markers,
            moving_points=moving,
            moving_vectors={"error vector x N": (230, 150, 20)},
            planar=True,
        )

    # -- the page ---------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        cx, cy = channels(params)
        curve = params["curve"]
        steps = [
            DerivationStep(
                "Programming device (PU)",
                "The PU integrates the conic's field; F is conserved along its solution. With B = 0 (axes parallel "
                "to x, y) it is used throughout.",
                r"\frac{dx}{dt}=\pm\omega(Bx+Cy+E),\qquad \frac{dy}{dt}=\mp\omega(Ax+By+D)",
                "Fig. 1a",
            ),
            DerivationStep(
                "Servo channels",
                f"Each coordinate drives a second-order channel. From the open loop W(s) = k/((Ts+1)s): "
                f"T2^2 = T/k, T1 = 1/k. Here T1x = {_sig(cx.T1)} s, T2x^2 = {_sig(cx.T2sq)} s^2, "
                f"zeta = T1/(2 T2) = {_sig(cx.zeta)}.",
                r"(T_{2x}^2s^2+T_{1x}s+1)\,x_1=x,\quad (T_{2y}^2s^2+T_{1y}s+1)\,y_1=y,\qquad "
                r"\Phi=\frac{W}{1+W}=\frac{1}{\frac{T}{k}s^2+\frac{1}{k}s+1}",
                "(2)",
            ),
            DerivationStep(
                "Non-identical channels",
                f"The y channel is scaled by gamma = {_sig(float(params['gamma']))}: T1y = {_sig(cy.T1)} s, "
                f"T2y^2 = {_sig(cy.T2sq)} s^2.",
                r"T_{1y}=\gamma T_1,\qquad T_{2y}^2=\gamma T_2^2",
                "(16)",
                reconstructed="printed as 'non-identical (T_y != gamma T_x)'; the definition used everywhere else is T_y = gamma T_x",
            ),
        ]
        builder: dict[str, Callable[[Params, Channel, Channel], list[DerivationStep]]] = {
            "line": _steps_line,
            "parabola": _steps_parabola,
            "circle": _steps_circle,
            "ellipse": _steps_ellipse,
            "cubic": _steps_cubic,
            "quartic": _steps_quartic,
        }
        steps += builder[curve](params, cx, cy)
        steps.append(
            DerivationStep(
                "Conclusion: single-axis errors vs the contour error",
                "Feeding x + T1 dx/dt removes the x error but shifts the output parabola by -omega^2 p T2^2/2 instead of "
                "(13): a larger contour error whenever T1^2 < 4 T2^2.",
                r"\delta=-\frac{\omega^2p\,T_2^2}{2}\quad\text{vs}\quad \frac{\omega^2p}{4}(T_1^2-2T_2^2)",
                "Conclusions",
            )
        )
        return steps

    # -- claims -----------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "table-13",
                "The simulated parabola error after the transient equals (13) within 1 % in all 16 table cells "
                "(v = 50 mm/s, p = 20 mm, omega = 5; k = 100..1000 1/s, T = 0.01..1 s).",
                "(13), table",
                _claim_table_13,
            ),
            Claim(
                "table-0.8",
                "The printed table equals 0.8 x (13) in every cell (to its printed digits); the factor compatible "
                "with all cells lies in [0.7947, 0.8053] and excludes 1.",
                "table",
                _claim_table_08,
            ),
            Claim(
                "line-5-6",
                "Non-identical channels reproduce a line parallel to the programmed one at the distance (5) = (6): "
                "0.05 mm at 45 deg (gamma = 1.2), -0.064952 mm at 30 deg (gamma = 0.7), k = 100 1/s, T = 0.05 s.",
                "(5), (6)",
                _claim_line_5_6,
            ),
            Claim(
                "line-4",
                "Identical channels: the line is reproduced without error when starting at rest; with initial "
                "velocities the error is the transient (4), peaking near 1.05 T2^2/(T1 + T2) (within 5 %).",
                "(3), (4)",
                _claim_line_4,
            ),
            Claim(
                "circle-28",
                "Identical channels reproduce a circle of radius R0 |Phi(j omega)|: R0 - R = (28) to 1e-6 "
                "(-0.24295 mm for R0 = 10 mm, omega = 5, k = 100, T = 0.1).",
                "(27), (28)",
                _claim_circle_28,
            ),
            Claim(
                "circle-29-30",
                "Non-identical channels give an ellipse tilted by (29) with the semi-axes of (30) with "
                "cos^2 in the numerator (12.00691 / 10.78178 mm, 63.127 deg); the printed (30) is off.",
                "(29), (30)",
                _claim_circle_29_30,
            ),
            Claim(
                "ellipse",
                "An ellipse is reproduced with semi-axes a|Phi|, b|Phi| (identical) and, for non-identical "
                "channels, the tilt (29) and the corrected (30) with m = a|Phi1|, n = b|Phi2| (15.97402 / 6.62696 mm, 1.809 deg).",
                "I.6",
                _claim_ellipse,
            ),
            Claim(
                "parabola-17-18",
                "Non-identical channels: the output parabola is (17); its vertices lie on the corrected "
                "locus (18) (linear coefficient omega (T1^2 - T2^2)/T1).",
                "(16)-(18)",
                _claim_parabola_17_18,
            ),
            Claim(
                "correction",
                "The program correction (7), (21)-(22), (31)-(34) removes the steady error (line, parabola, "
                "circle, non-identical channels); the PU starts at the article's X0, Y0.",
                "(7), (22), (34)",
                _claim_correction,
            ),
            Claim(
                "parabola-24",
                "With the corrected program and the servo at rest, the error is the transient (24); for k = 100, "
                "T = 0.1 its peak is 0.562 mm at t = 0.25 s and it then vanishes.",
                "(24), (25)",
                _claim_parabola_24,
            ),
            Claim(
                "derivative-feed",
                "Feeding x + T1 dx/dt removes the x error but increases the contour error: -0.25 mm vs "
                "(13) -0.2375 mm (k = 100, T = 0.1).",
                "Conclusions",
                _claim_derivative,
            ),
            Claim(
                "beta-15",
                "(15): f(beta) = 1/beta^2 - 2/beta has its only stationary point at beta = 1 (a minimum, f = -1) "
                "and its zero at beta = 1/2 with slope -8.",
                "(15), Fig. 3",
                _claim_beta,
            ),
            Claim(
                "modulus-only",
                "Correcting only the moduli gives an ellipse at 45/135 deg with semi-axes R0 sqrt(1 +- |sin(phi2 - phi1)|) "
                "(12.346 / 6.897 mm: x k = 30, T = 0.01; y k = 200, T = 0.02; omega = 20, R0 = 10 mm); the printed form gives 13.379.",
                "after (35)",
                _claim_modulus_only,
            ),
            Claim(
                "alt-correction",
                "Shifting the program by -delta_max (corrected Y0 of the alternative correction) keeps the reproduced "
                "point on the programmed parabola although x != x1 (k = 100 1/s, T = 0.1 and 1 s).",
                "after (25)",
                _claim_alt_correction,
            ),
            Claim(
                "quartic-beta",
                "Quartic: y' opens downward for beta1 < 2; its vertex is above the programmed one for beta1 < 0.85 and "
                "beta1 > 3.15 (roots 0.8453, 3.1547 of 3 beta1^2 - 12 beta1 + 8); the line y'' rises for beta1 < 3.",
                "I.7",
                _claim_quartic_beta,
            ),
            Claim(
                "cubic-quartic",
                "Cubic and quartic outputs follow the corrected curve equations (cubic: '+' not '='; "
                "quartic: the printed curve), and the corrected quartic y1(t), not the printed one.",
                "I.7",
                _claim_cubic_quartic,
            ),
        ]

    # -- extras --------------------------------------------------------------------

    def table(self) -> list[dict[str, Any]]:
        """The parabola table: formula (13), simulation and the printed values, row by row."""
        return table_rows()


# ---------------------------------------------------------------- derivation pages per curve


def _steps_line(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    v, ang, g = float(params["v"]), float(params["angle"]), float(params["gamma"])
    d5 = delta_line_5(v, ang, cx.T1, g)
    return [
        DerivationStep(
            "Line: PU output",
            "x_c, y_c are direction constants; the path speed is omega sqrt(x_c^2 + y_c^2).",
            r"x=x_0+\omega y_c t,\qquad y=y_0+\omega x_c t",
            "(1)",
        ),
        DerivationStep(
            "Servo output (identical channels)",
            "The lag omega y_c T1 is along the line when starting at rest: no contour error.",
            r"x_1=x_0+\omega y_ct-\omega y_cT_1+\frac{\dot x_0}{\alpha_1-\alpha_2}(e^{\alpha_1t}-e^{\alpha_2t})"
            r"+\omega y_c\frac{\alpha_2^2e^{\alpha_1t}-\alpha_1^2e^{\alpha_2t}}{(\alpha_1-\alpha_2)\alpha_1\alpha_2}",
            "(3)",
        ),
        DerivationStep(
            "Transient error",
            "With initial velocities the error is transient; f(t) peaks near 1.05 T2^2/(T1 + T2) "
            "(within about 5 % for every damping).",
            r"\delta=\frac{\dot x_0x_c-\dot y_0y_c}{\sqrt{x_c^2+y_c^2}}\,\frac{e^{\alpha_1t}-e^{\alpha_2t}}{\alpha_1-\alpha_2},"
            r"\qquad f(t)_{\max}\approx\frac{1.05\,T_2^2}{T_1+T_2}",
            "(4)",
        ),
        DerivationStep(
            "Non-identical channels: a parallel line",
            f"Here delta = {_sig(d5)} mm.",
            r"\delta=\frac{\omega x_cy_cT_1(\gamma-1)}{\sqrt{x_c^2+y_c^2}}",
            "(5)",
        ),
        DerivationStep(
            "In terms of the speed",
            "Largest at 45 deg: v T1 (gamma - 1)/2.",
            r"\omega=\frac{v}{\sqrt{x_c^2+y_c^2}},\qquad \delta=\frac{v\,x_cy_cT_1(\gamma-1)}{x_c^2+y_c^2}",
            "(6)",
            reconstructed="printed omega = v/sqrt(x0^2 + y_c^2); the PU speed is omega sqrt(x_c^2 + y_c^2), and (6) follows from (5) only with x_c",
        ),
        DerivationStep(
            "Program correction",
            "New PU initial conditions (per channel T1x, T1y for non-identical channels) remove the steady error; "
            "the transient (4) remains.",
            r"X_0=x_0+\omega y_cT_{1x},\qquad Y_0=y_0+\omega x_cT_{1y}",
            "(7), (8)",
        ),
    ]


def _steps_parabola(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p, g = float(params["omega"]), float(params["p"]), float(params["gamma"])
    d13 = delta_parabola_13(omega, p, cx.T1, cx.T2sq)
    rows = list(_table(50.0, 20.0, 5.0))
    lo, hi = table_ratio_interval()
    return [
        DerivationStep(
            "Parabola: PU output",
            "p(y - y_c) = (x - x_c)^2; PU dx/dt = omega p/2, dy/dt = omega (x - x_c).",
            r"x=x_0+\frac{\omega p}{2}t,\qquad y=y_0+\omega(x_0-x_c)t+\frac{\omega^2p}{4}t^2",
            "(9)",
        ),
        DerivationStep(
            "Path speed",
            f"At the vertex v = omega p/2 = {_sig(omega * p / 2)} mm/s.",
            r"v=\omega\sqrt{(x-x_c)^2+\frac{p^2}{4}}",
            "(13)",
            reconstructed="printed omega = v/sqrt(y^2 + p^2/4); since dx/dt = omega p/2, dy/dt = omega x the speed involves x (both agree only at the vertex)",
        ),
        DerivationStep(
            "After the transient",
            "First terms of 1/(1 + T1 s + T2^2 s^2) = 1 - T1 s + (T1^2 - T2^2) s^2 - ... on the polynomial inputs.",
            r"x_1=x_0+\frac{\omega p}{2}t-\frac{\omega pT_{1x}}{2},\quad y_1=y+\frac{\omega^2p}{2}(T_{1y}^2-T_{2y}^2)-\omega(x_0-x_c)T_{1y}-\frac{\omega^2pT_{1y}}{2}t",
            "(11)",
        ),
        DerivationStep(
            "The same parabola, shifted along its axis",
            "",
            r"y_1=\frac{x_1^2}{p}+\frac{\omega^2p}{4}(T_1^2-2T_2^2)",
            "(12)",
        ),
        DerivationStep(
            "Largest error (between the vertices)",
            f"Here (13) = {_sig(d13)} mm (negative: the output lies outside, T1^2 < 2 T2^2).",
            r"\delta_{\max}=\frac{\omega^2p}{4}\left(T_1^2-2T_2^2\right)",
            "(13)",
        ),
        DerivationStep(
            "Error at an arbitrary point (approximate)",
            "From triangle abc of Fig. 2 (unnumbered; probably the missing (14)).",
            r"\delta\approx\frac{\Delta y'\Delta x'}{\sqrt{\Delta y'^2+\Delta x'^2}},\quad \Delta y'=\delta_{\max},\ \Delta x'=x-\sqrt{x^2-p\Delta y'}",
            "(14)",
            reconstructed="equation number (14) is missing in the print; this unnumbered formula is presumably it",
        ),
        DerivationStep(
            "Dependence on beta = T2^2/T1^2",
            "f(beta) = 1/beta^2 - 2/beta has a minimum f = -1 at beta = 1 (the largest error of negative sign) and crosses zero at beta = 1/2 with slope -8.",
            r"\delta_{\max}=\frac{\omega^2p}{4}\left(\frac1{\beta^2}-\frac2\beta\right)\frac{T_2^4}{T_1^2}",
            "(15)",
            reconstructed="the text calls beta = 1 a maximum of f; it is the minimum (largest |delta| of negative sign)",
        ),
        DerivationStep(
            "The table: formula (13), simulation and the printed values side by side",
            "v = 50 mm/s, p = 20 mm, omega = 5, rows k [1/s], columns T [s].  The simulation agrees with (13) in every "
            "cell; the printed values are 0.8 x (13) in every cell (to their printed digits: the factor compatible with "
            f"all cells lies in [{lo:.4f}, {hi:.4f}], so 1 is excluded). The cause is not stated in the article "
            "(omega^2 = 20 instead of 25 would give it).\n\n" + format_table(rows),
            r"\delta_{\text{printed}}=0.8\cdot\frac{\omega^2p}{4}(T_1^2-2T_2^2)=100\,(T_1^2-2T_2^2)\ \text{mm}",
            "table",
            reconstructed="the printed header is transposed (rows are k in 1/s, columns T in s); read literally (13) gives absurd values",
        ),
        DerivationStep(
            "Non-identical channels: output parabola",
            f"Vertex of the output parabola: {tuple(round(v, 6) for v in parabola_vertex_17(omega, p, cx.T1, cx.T2sq, g))} mm. "
            "The article's Fig. 4 remarks (for the vertical parabola the error grows for gamma < 1 and decreases for "
            "gamma > 1) are not reproduced with gamma scaling the y channel: with T1 = 0.01 s, T2^2 = 0.001 s^2 the "
            "largest normal distance grows for gamma > 1 too; the figure's parameters are not given.",
            r"y=\frac{x^2}{p}+\omega T_1(1-\gamma)x+\frac{\omega^2p}{4}\left[T_1^2(1-2\gamma+2\gamma^2)-2\gamma T_2^2\right]",
            "(17)",
        ),
        DerivationStep(
            "Locus of the vertices as gamma varies",
            "",
            r"y=\frac{x^2}{p}+\frac{\omega(T_1^2-T_2^2)}{T_1}x+\frac{\omega^2p}{4}(T_1^2-2T_2^2)",
            "(18)",
            reconstructed="printed linear coefficient omega (T1^2 - T2^2) is dimensionally wrong and misses the vertices; /T1 restores both",
        ),
        DerivationStep(
            "Program correction: required inputs",
            "Make (9) the particular solution of (2).",
            r"x=x_0+\frac{\omega pt}{2}+\frac{\omega pT_{1x}}{2},\quad y=y_0+\omega(x_0-x_c)T_{1y}+\left[\frac{\omega^2pT_{1y}}{2}+\omega(x_0-x_c)\right]t+\frac{\omega^2pt^2}{4}+\frac{\omega^2T_{2y}^2p}{2}",
            "(21)",
        ),
        DerivationStep(
            "Corrected PU",
            "New initial conditions and, for non-identical channels, an extra constant input omega^2 p (T1y - T1x)/2 in dy/dt.",
            r"X_0=x_0+\frac{\omega pT_{1x}}{2},\qquad Y_0=y_0+\omega(x_0-x_c)T_{1y}+\frac{\omega^2pT_{2y}^2}{2}",
            "(22)",
        ),
        DerivationStep(
            "Transient with the corrected program (servo from rest)",
            "",
            r"y_1-\frac{x_1^2}{p}=\frac{\omega^2p}{4}\left(2t-f\right)f,\qquad f=\frac{e^{\alpha_1t}-e^{\alpha_2t}}{\alpha_1-\alpha_2}",
            "(24), (25)",
        ),
        DerivationStep(
            "Alternative correction (point stays on the parabola, x != x1)",
            "For identical channels: shift the program by -delta_max.",
            r"Y_0=y_0+\frac{\omega^2pT_{1x}^2}{4}-\frac{\omega^2pT_{1x}T_{1y}}{2}+\frac{\omega^2pT_{2y}^2}{2}+\omega x_0(T_{1y}-T_{1x})",
            "after (25)",
            reconstructed="printed Y0 = y0 + omega^2 p T1x/4 + omega^2 p T1y/2 + omega x0 T1y is dimensionally inconsistent; re-derived for the PU with the extra input",
        ),
    ]


def _steps_circle(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega = float(params["omega"])
    P1 = cx.response(omega)
    return [
        DerivationStep(
            "Circle: PU output",
            "PU dx/dt = omega (y - y_c), dy/dt = -omega (x - x_c).",
            r"x-x_c=R_0\sin(\omega t+\varphi_0),\qquad y-y_c=R_0\cos(\omega t+\varphi_0)",
            "(26)",
        ),
        DerivationStep(
            "After the transient",
            "",
            r"x_1-x_c=R_0|\Phi_1(j\omega)|\sin(\omega t+\varphi_0+\varphi_1),\quad y_1-y_c=R_0|\Phi_2(j\omega)|\cos(\omega t+\varphi_0+\varphi_2)",
            "(27)",
        ),
        DerivationStep(
            "Identical channels: radius error",
            f"|Phi(j omega)| = {_sig(abs(P1))}.",
            r"\delta=R_0\left[1-|\Phi(j\omega)|\right],\qquad |\Phi(j\omega)|=\frac{1}{\sqrt{(1-T_2^2\omega^2)^2+T_1^2\omega^2}}",
            "(28)",
        ),
        DerivationStep(
            "Non-identical channels: an ellipse",
            "m = R0|Phi1|, n = R0|Phi2|.",
            r"\frac{x_1^2}{m^2}+\frac{y_1^2}{n^2}+\frac{2x_1y_1}{mn}\sin(\varphi_2-\varphi_1)=\cos^2(\varphi_2-\varphi_1),\qquad "
            r"\operatorname{ctg}2\alpha=\frac{n^2-m^2}{2mn\sin(\varphi_2-\varphi_1)}",
            "(29)",
        ),
        DerivationStep(
            "Semi-axes",
            "",
            r"a,b=\sqrt{\frac{\cos^2(\varphi_2-\varphi_1)}{\frac{m^2+n^2}{2m^2n^2}\pm\sqrt{\frac{(m^2+n^2)^2}{4m^4n^4}-\frac{\cos^2(\varphi_2-\varphi_1)}{m^2n^2}}}}",
            "(30)",
            reconstructed="printed numerator cos(phi2 - phi1); the semi-axes of x^T Q x = cos^2 need cos^2 (area pi m n |cos|); simulation confirms",
        ),
        DerivationStep(
            "Program correction: required input",
            "",
            r"x=\frac{R_0}{|\Phi_1(j\omega)|}\sin(\omega t+\varphi_0-\varphi_1),\qquad y=\frac{R_0}{|\Phi_2(j\omega)|}\cos(\omega t+\varphi_0-\varphi_2)",
            "before (31)",
            reconstructed="printed R0/|Phi|^2; (31) itself equals the unsquared form",
        ),
        DerivationStep(
            "Corrected input expanded",
            "",
            r"x=\frac{(y_0P_1+x_0Q_1)\sin\omega t+(x_0P_1-y_0Q_1)\cos\omega t}{|\Phi_1|^2},\quad y=\frac{(y_0Q_2-x_0P_2)\sin\omega t+(y_0P_2+x_0Q_2)\cos\omega t}{|\Phi_2|^2}",
            "(31)",
        ),
        DerivationStep(
            "Corrected PU",
            "A PU producing a constant-amplitude sinusoid needs a zero trace: m2 = -r2.",
            r"\frac{dx}{dt}=\omega\left[\frac{P_2Q_1-P_1Q_2}{P_1P_2+Q_1Q_2}x+\frac{|\Phi_2|^2}{P_1P_2+Q_1Q_2}y\right],\quad "
            r"\frac{dy}{dt}=\omega\left[-\frac{|\Phi_1|^2}{P_1P_2+Q_1Q_2}x+\frac{P_1Q_2-P_2Q_1}{P_1P_2+Q_1Q_2}y\right]",
            "(33)",
            reconstructed="printed P2^2 + Q2 (square lost) and the same sign on both diagonal terms, which makes the PU grow or decay",
        ),
        DerivationStep(
            "Corrected initial conditions",
            "",
            r"X_0=\frac{x_0P_1-y_0Q_1}{|\Phi_1|^2},\qquad Y_0=\frac{x_0Q_2+y_0P_2}{|\Phi_2|^2}",
            "(34)",
        ),
        DerivationStep(
            "Identical servo systems",
            "The PU structure is unchanged; only the initial conditions (34) change.",
            r"\frac{dx}{dt}=\omega y,\qquad \frac{dy}{dt}=-\omega x",
            "(35)",
            reconstructed="printed dy/dt = +omega x (a saddle, not an oscillator) and 'if the PU are identical' for 'servo systems'",
        ),
        DerivationStep(
            "Modulus-only correction",
            "Correcting only the moduli leaves a 45 deg ellipse (a circle only if phi1 = phi2).",
            r"\frac{dx}{dt}=\omega\frac{|\Phi_2|}{|\Phi_1|}y,\quad \frac{dy}{dt}=-\omega\frac{|\Phi_1|}{|\Phi_2|}x,\quad "
            r"X_0=\frac{x_0}{|\Phi_1|},\ Y_0=\frac{y_0}{|\Phi_2|};\qquad a,b=R_0\sqrt{1\pm|\sin(\varphi_2-\varphi_1)|}",
            "after (35)",
            reconstructed="printed X0 = (x0 - y0)/|Phi1|^2, Y0 = (x0 + y0)/|Phi2|^2 give sqrt(2) R0/|Phi| even for equal arguments; "
            "printed a, b = R0 sqrt(cos/(1 -+ sin)) miss the square as in (30)",
        ),
    ]


def _steps_ellipse(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    return [
        DerivationStep(
            "Ellipse: PU",
            "",
            r"\frac{dx}{dt}=\omega\frac ab(y-y_c),\qquad \frac{dy}{dt}=-\omega\frac ba(x-x_c)",
            "I.6",
        ),
        DerivationStep(
            "Servo output",
            "Identical channels: semi-axes a|Phi|, b|Phi|; errors a(1 - |Phi|), b(1 - |Phi|).",
            r"x_1-x_c=a|\Phi_1|\sin(\omega t+\varphi_0+\varphi_1),\qquad y_1-y_c=b|\Phi_2|\cos(\omega t+\varphi_0+\varphi_2)",
            "I.6",
        ),
        DerivationStep(
            "Non-identical channels",
            "Tilt (29), semi-axes (30) with cos^2, m = a|Phi1|, n = b|Phi2|.",
            r"m=a|\Phi_1(j\omega)|,\qquad n=b|\Phi_2(j\omega)|",
            "(29), (30)",
            reconstructed="printed 'm = n gives a circle': also phi1 = phi2 is needed; with m = n, phi1 != phi2 the output is a 45 deg ellipse",
        ),
    ] + _steps_circle(params, cx, cy)[4:5]


def _steps_cubic(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p = float(params["omega"]), float(params["p"])
    return [
        DerivationStep(
            "Cubic parabola: PU output",
            "The PU of Fig. 7 is not described; an integrator chain gives the same output.",
            r"x=\omega pt,\qquad y=\omega^3p^2t^3",
            "I.7",
        ),
        DerivationStep(
            "Servo output after the transient",
            "",
            r"x_1=\omega pt-\omega pT_1,\quad y_1=\omega^3p^2t^3-3\omega^3p^2(T_1t^2+2T_2^2t-2T_1^2t+2T_1^3-4T_1T_2^2)",
            "I.7",
        ),
        DerivationStep(
            "Output curve",
            f"Inflection shift here: {_sig(cubic_offset(omega, p, cx, cy))} mm.",
            r"y=\frac{x^3}{p}+3\omega^2p(T_1^2-2T_2^2)x+2\omega^3p^2(3T_1T_2^2-T_1^3)",
            "I.7",
            reconstructed="printed 'y = x^3/rho = 3 omega^2 p(...)': '=' must be '+', rho is p",
        ),
        DerivationStep(
            "Extrema (only for 2 T2^2 > T1^2)",
            "",
            r"x=\mp\omega p\sqrt{2T_2^2-T_1^2},\quad y=2\omega^3p^2\left[(3T_1T_2^2-T_1^3)\pm(2T_2^2-T_1^2)^{3/2}\right]",
            "I.7",
            reconstructed="printed with a spurious inner -+ under the root",
        ),
        _step_general_correction(),
    ]


def _steps_quartic(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p = float(params["omega"]), float(params["p"])
    return [
        DerivationStep(
            "Quartic parabola: PU output", "", r"x=\omega pt,\qquad y=\omega^4p^3t^4", "I.7"
        ),
        DerivationStep(
            "Servo output after the transient",
            "",
            r"y_1=\omega^4p^3t^4-4\omega^4p^3\left[T_1t^3-3(T_1^2-T_2^2)t^2+6(T_1^3-2T_1T_2^2)t-6(T_1^4-3T_1^2T_2^2+T_2^4)\right]",
            "I.7",
            reconstructed="printed with three sign errors and T1^2 for T1^3 in the t term (off by mm in simulation); the printed curve below is right",
        ),
        DerivationStep(
            "Output curve",
            f"Vertex shift here: {_sig(quartic_offset(omega, p, cx, cy))} mm. With beta1 = T1^2/T2^2 the "
            "parabola y' opens downward for beta1 < 2; its vertex is above the programmed one for beta1 < 0.845 and "
            "beta1 > 3.155; the line y'' rises for beta1 < 3.",
            r"y=\frac{x^4}{p}+6\omega^2p(T_1^2-2T_2^2)x^2+8\omega^3p^2(3T_2^2T_1-T_1^3)x+3\omega^4p^3(3T_1^4+8T_2^4-12T_1^2T_2^2)",
            "I.7",
        ),
        _step_general_correction(),
    ]


def _step_general_correction() -> DerivationStep:
    return DerivationStep(
        "Program correction for any PU",
        "Feed each channel with (T2^2 s^2 + T1 s + 1) applied to the programmed coordinate "
        "(the rule of (20)); for a linear PU dz/dt = A z, x = C z this is a new output map (new initial conditions of the PU).",
        r"u_x=C_x\left(I+T_{1x}A+T_{2x}^2A^2\right)z",
        "(20)",
        reconstructed="the article gives no correction for degree 3 and 4; this is its rule (20) applied to the integrator-chain PU",
    )


# ---------------------------------------------------------------- claim checks


def _run_steady(
    program: Program,
    cx: Channel,
    cy: Channel,
    correction: str = "off",
    xdot0: float = 0.0,
    ydot0: float = 0.0,
    window: float = 1.0,
    n: int = 2001,
    settle: float = 25.0,
) -> tuple[np.ndarray, dict[str, np.ndarray], TwoAxisServo]:
    """Outputs on [t_s, t_s + window] after ``settle`` slowest time constants."""
    system = TwoAxisServo(program, cx, cy, correction)  # type: ignore[arg-type]
    t_s = settle / system.decay_rate()
    z = system.transition(t_s) @ system.initial_state(xdot0, ydot0)
    t = np.linspace(0.0, window, n)
    return t_s + t, system.outputs(system.run(t, z)), system


def _claim_table_13() -> ClaimResult:
    rows = _table(50.0, 20.0, 5.0)
    worst = max(abs(r.simulated_over_formula - 1.0) for r in rows)
    return at_most(0.01, worst, "max |simulation/(13) - 1| ")


def _claim_table_08() -> ClaimResult:
    rows = _table(50.0, 20.0, 5.0)
    lo, hi = table_ratio_interval()
    ok = all(r.within_print_rounding for r in rows) and lo <= 0.8 <= hi and not (lo <= 1.0 <= hi)
    return ClaimResult(
        expected="every printed cell = 0.8 x (13) to its printed digits; 0.8 in the interval, 1 not",
        got=f"{sum(r.within_print_rounding for r in rows)}/16 cells; interval [{lo:.4f}, {hi:.4f}]",
        passed=ok,
    )


def _claim_line_5_6() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.05)
    worst = 0.0
    got = []
    for ang, g, expected in ((45.0, 1.2, 0.05), (30.0, 0.7, -0.0649519052838329)):
        _, out, _ = _run_steady(line_program(0.0, 0.0, 50.0, ang), ch, ch.scaled(g), n=11)
        d, _, _ = line_distance(out["x1"], out["y1"], out["x"], out["y"], ang)
        th = math.radians(ang)
        xc, yc = math.sin(th), math.cos(th)  # direction constants with omega = v
        d5 = 50.0 * xc * yc * ch.T1 * (g - 1) / math.hypot(xc, yc)
        d6 = 50.0 * xc * yc * ch.T1 * (g - 1) / (xc * xc + yc * yc)
        worst = max(
            worst, abs(d[-1] - expected), abs(d5 - expected), abs(d6 - expected), float(np.ptp(d))
        )
        got.append(f"{d[-1]:.6f}")
    return ClaimResult(
        "0.05, -0.0649519 mm (atol 1e-8)", ", ".join(got) + f" (worst {worst:.1e})", worst <= 1e-8
    )


def _claim_line_4() -> ClaimResult:
    ch = Channel(0.01, 0.0005)
    sysm = TwoAxisServo(line_program(0.0, 0.0, 50.0, 45.0), ch, ch)
    t = np.linspace(0.0, 1.0, 2001)
    out = sysm.outputs(sysm.run(t, sysm.initial_state()))
    d0, _, _ = line_distance(out["x1"], out["y1"], out["x"], out["y"], 45.0)
    out = sysm.outputs(sysm.run(t, sysm.initial_state(50.0, 0.0)))
    d, _, _ = line_distance(out["x1"], out["y1"], out["x"], out["y"], 45.0)
    th = math.radians(45.0)
    d4 = 50.0 * math.sin(th) * f_transient(t, ch)
    fmax = float(np.max(f_transient(np.linspace(0, 1, 20001), ch)))
    approx = 1.05 * ch.T2sq / (ch.T1 + math.sqrt(ch.T2sq))
    ok = (
        float(np.max(np.abs(d0))) < 1e-9
        and float(np.max(np.abs(d - d4))) < 1e-9
        and abs(approx / fmax - 1.0) <= 0.05
    )
    return ClaimResult(
        "at rest: 0; with xdot0: (4) to 1e-9 mm; 1.05 T2^2/(T1+T2) within 5 % of max f",
        f"at rest {np.max(np.abs(d0)):.1e}; |sim-(4)| {np.max(np.abs(d - d4)):.1e}; approx/exact {approx / fmax:.4f}",
        ok,
    )


def _claim_circle_28() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    _, out, _ = _run_steady(
        ellipse_program(0.0, 10.0, 0.0, 0.0, 1.0, 1.0, 5.0), ch, ch, window=2 * math.pi / 5
    )
    r = np.hypot(out["x1"], out["y1"])
    sim = 10.0 - float(np.mean(r))
    f28 = 10.0 * (1.0 - abs(ch.response(5.0)))
    res = close(f28, sim, rtol=1e-6)
    res.passed = res.passed and float(np.ptp(r)) < 1e-6 * 10.0
    return res


def _ellipse_case(
    a: float, b: float, omega: float, gamma: float
) -> tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]:
    ch = Channel.from_open_loop(100.0, 0.1)
    cy = ch.scaled(gamma)
    _, out, _ = _run_steady(
        ellipse_program(0.0, b, 0.0, 0.0, a, b, omega), ch, cy, window=2 * math.pi / omega
    )
    sim = fit_centred_ellipse(out["x1"], out["y1"])
    P1, P2 = ch.response(omega), cy.response(omega)
    m, n, dphi = a * abs(P1), b * abs(P2), float(np.angle(P2) - np.angle(P1))
    return sim, circle_axes_29_30(m, n, dphi), circle_axes_29_30(m, n, dphi, printed=True)


def _claim_circle_29_30() -> ClaimResult:
    (a_s, b_s, ang_s), (alpha, a30, b30), (_, a_p, b_p) = _ellipse_case(10.0, 10.0, 10.0, 5.0 / 3.0)
    err = max(abs(a_s / a30 - 1), abs(b_s / b30 - 1))
    ok = (
        err < 1e-6
        and abs(ang_s - alpha) < 1e-4
        and abs(a_p / a_s - 1) > 1e-3
        and abs(a30 - 12.00691) < 1e-5
        and abs(alpha - 63.127) < 1e-3
    )
    return ClaimResult(
        "sim = corrected (30) to 1e-6, tilt = (29) to 1e-4 deg; printed (30) off",
        f"sim {a_s:.5f}/{b_s:.5f} at {ang_s:.3f} deg; (30) {a30:.5f}/{b30:.5f}; (29) {alpha:.3f}; printed {a_p:.5f}/{b_p:.5f}",
        ok,
    )


def _claim_ellipse() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    (a1, b1, ang1), _, _ = _ellipse_case(15.0, 6.0, 8.0, 1.0)
    G = abs(ch.response(8.0))
    (a2, b2, ang2), (alpha, a30, b30), _ = _ellipse_case(15.0, 6.0, 8.0, 5.0 / 3.0)
    ok = (
        abs(a1 - 15 * G) < 1e-6 * a1
        and abs(b1 - 6 * G) < 1e-6 * b1
        and abs(a2 - a30) < 1e-6 * a2
        and abs(b2 - b30) < 1e-6 * b2
        and abs(((ang2 - alpha + 90) % 180) - 90) < 1e-4
        and abs(a2 - 15.97402) < 1e-5
        and abs(b2 - 6.62696) < 1e-5
    )
    return ClaimResult(
        "identical 15.96743/6.38697; non-identical 15.97402/6.62696 at 1.809 deg",
        f"identical {a1:.5f}/{b1:.5f}; non-identical {a2:.5f}/{b2:.5f} at {ang2:.3f} deg ((29) {alpha:.3f})",
        ok,
    )


def _claim_parabola_17_18() -> ClaimResult:
    T1, T2sq, omega, p = 0.01, 0.001, 5.0, 20.0
    ch = Channel(T1, T2sq)
    worst, worst18 = 0.0, 0.0
    for g in (0.5, 0.8, 1.5, 2.0):
        _, out, _ = _run_steady(
            power_program(2, -300.0, 0.0, 0.0, p, omega), ch, ch.scaled(g), window=2.0, n=401
        )
        x, y = out["x1"], out["y1"]
        y17 = (
            x**2 / p
            + omega * T1 * (1 - g) * x
            + omega**2 * p / 4 * (T1**2 * (1 - 2 * g + 2 * g * g) - 2 * g * T2sq)
        )
        worst = max(worst, float(np.max(np.abs(y - y17))))
        xv, yv = parabola_vertex_17(omega, p, T1, T2sq, g)
        y18 = xv**2 / p + omega * (T1**2 - T2sq) / T1 * xv + omega**2 * p / 4 * (T1**2 - 2 * T2sq)
        worst18 = max(worst18, abs(yv - y18))
    return ClaimResult(
        "|y1 - (17)| < 1e-7 mm, vertices on corrected (18) to 1e-12",
        f"{worst:.1e} mm, {worst18:.1e}",
        worst < 1e-7 and worst18 < 1e-12,
    )


def _claim_correction() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.05)
    worst = 0.0
    cases = [
        (line_program(0.0, 0.0, 50.0, 30.0), ch, ch.scaled(0.7)),
        (
            power_program(2, -200.0, 0.0, 0.0, 20.0, 5.0),
            Channel(0.01, 0.001),
            Channel(0.01, 0.001).scaled(2.0),
        ),
        (
            ellipse_program(0.0, 10.0, 0.0, 0.0, 1.0, 1.0, 10.0),
            Channel.from_open_loop(100.0, 0.1),
            Channel.from_open_loop(100.0, 0.1).scaled(5 / 3),
        ),
    ]
    for prog, cx, cy in cases:
        _, out, _ = _run_steady(prog, cx, cy, "on", n=201)
        worst = max(
            worst,
            float(np.max(np.abs(out["x1"] - out["x"]))),
            float(np.max(np.abs(out["y1"] - out["y"]))),
        )
    # the corrected program starts at the article's X0, Y0: (7), (22), (34)
    sysl = TwoAxisServo(cases[0][0], cases[0][1], cases[0][2], "on")
    z0 = cases[0][0].z0
    d7 = max(
        abs(sysl.Kx @ z0 - 50 * math.cos(math.radians(30)) * ch.T1),
        abs(sysl.Ky @ z0 - 50 * math.sin(math.radians(30)) * ch.scaled(0.7).T1),
    )
    sysp = TwoAxisServo(cases[1][0], cases[1][1], cases[1][2], "on")
    cx, cy = cases[1][1], cases[1][2]
    X0 = -200.0 + 5 * 20 * cx.T1 / 2
    Y0 = 2000.0 + 5 * (-200.0) * cy.T1 + 25 * 20 * cy.T2sq / 2
    z0 = cases[1][0].z0
    d22 = max(abs(sysp.Kx @ z0 - X0), abs(sysp.Ky @ z0 - Y0))
    sysc = TwoAxisServo(cases[2][0], cases[2][1], cases[2][2], "on")
    P1, P2 = cases[2][1].response(10.0), cases[2][2].response(10.0)
    x0, y0 = 0.0, 10.0
    X34 = (x0 * P1.real - y0 * P1.imag) / abs(P1) ** 2
    Y34 = (x0 * P2.imag + y0 * P2.real) / abs(P2) ** 2
    z0 = cases[2][0].z0
    d34 = max(abs(sysc.Kx @ z0 - X34), abs(sysc.Ky @ z0 - Y34))
    ok = worst < 1e-7 and max(d7, d22, d34) < 1e-10
    return ClaimResult(
        "steady |error| < 1e-7 mm; PU start = (7), (22), (34) to 1e-10",
        f"steady {worst:.1e} mm; start {max(d7, d22, d34):.1e}",
        ok,
    )


def _claim_parabola_24() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    sysm = TwoAxisServo(power_program(2, 0.0, 0.0, 0.0, 20.0, 5.0), ch, ch, "on")
    t = np.linspace(0.0, 3.0, 3001)
    out = sysm.outputs(sysm.run(t, sysm.initial_state()))
    dev = out["y1"] - out["x1"] ** 2 / 20.0
    f = f_transient(t, ch)
    d24 = 25.0 * 20.0 / 4.0 * (2 * t - f) * f
    i = int(np.argmax(d24))
    ok = (
        float(np.max(np.abs(dev - d24))) < 1e-8
        and abs(d24[i] - 0.56243) < 1e-4
        and abs(t[i] - 0.25) < 0.005
        and abs(dev[-1]) < 1e-5
    )
    return ClaimResult(
        "|sim - (24)| < 1e-8; peak 0.56243 mm at 0.25 s; -> 0",
        f"{np.max(np.abs(dev - d24)):.1e}; peak {d24[i]:.5f} at {t[i]:.3f} s; end {dev[-1]:.1e}",
        ok,
    )


def _claim_derivative() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    d = _vertex_error(ch, "derivative")
    d13 = delta_parabola_13(5.0, 20.0, ch.T1, ch.T2sq)
    ok = abs(d - (-0.25)) < 1e-6 and abs(d) > abs(d13)
    return ClaimResult(
        "-0.25 mm (= -omega^2 p T2^2/2), larger than |(13)| = 0.2375", f"{d:.7f} mm", ok
    )


def _vertex_error(ch: Channel, correction: str) -> float:
    from lessons.core.servo import simulate_parabola_vertex_error

    return simulate_parabola_vertex_error(ch, 5.0, 20.0, correction=correction)  # type: ignore[arg-type]


def _claim_beta() -> ClaimResult:
    b = sp.symbols("beta", positive=True)
    f = 1 / b**2 - 2 / b
    crit = sp.solve(sp.diff(f, b), b)
    zero = sp.solve(f, b)
    ok = (
        crit == [1]
        and f.subs(b, 1) == -1
        and sp.diff(f, b, 2).subs(b, 1) > 0
        and zero == [sp.Rational(1, 2)]
        and sp.diff(f, b).subs(b, sp.Rational(1, 2)) == -8
    )
    return ClaimResult(
        "stationary point beta = 1 (minimum, f = -1); zero 1/2, slope -8",
        f"stationary {crit}, f'' {sp.diff(f, b, 2).subs(b, 1)}; zero {zero}, slope {sp.diff(f, b).subs(b, sp.Rational(1, 2))}",
        ok,
    )


def _claim_cubic_quartic() -> ClaimResult:
    T1, T2 = 0.01, 0.0005
    ch = Channel(T1, T2)
    w, p = 0.125, 400.0
    t, out, _ = _run_steady(power_program(3, -100.0, 0.0, 0.0, p, w), ch, ch, window=2.0, n=401)
    x, y = out["x1"], out["y1"]
    yc = x**3 / p + 3 * w**2 * p * (T1**2 - 2 * T2) * x + 2 * w**3 * p**2 * (3 * T1 * T2 - T1**3)
    e3 = float(np.max(np.abs(y - yc)))
    w, p = 0.00625, 8000.0
    tq, out, sysq = _run_steady(power_program(4, -100.0, 0.0, 0.0, p, w), ch, ch, window=2.0, n=401)
    x, y = out["x1"], out["y1"]
    yq = (
        x**4 / p
        + 6 * w**2 * p * (T1**2 - 2 * T2) * x**2
        + 8 * w**3 * p**2 * (3 * T2 * T1 - T1**3) * x
        + 3 * w**4 * p**3 * (3 * T1**4 + 8 * T2**2 - 12 * T1**2 * T2)
    )
    e4 = float(np.max(np.abs(y - yq)))
    tau = out["x"] / (w * p)  # PU time measured from the vertex
    c = w**4 * p**3
    y_fix = c * tau**4 - 4 * c * (
        T1 * tau**3
        - 3 * (T1**2 - T2) * tau**2
        + 6 * (T1**3 - 2 * T1 * T2) * tau
        - 6 * (T1**4 - 3 * T1**2 * T2 + T2**2)
    )
    y_pr = c * tau**4 - 4 * c * (
        T1 * tau**3
        + 3 * (T1**2 - T2) * tau**2
        - 6 * (T1**2 - 2 * T2 * T1) * tau
        + 6 * T1**4
        - 18 * T2 * T1**2
        + 6 * T2**2
    )
    e_fix = float(np.max(np.abs(y - y_fix)))
    e_pr = float(np.max(np.abs(y - y_pr)))
    scale = float(np.max(np.abs(y)))
    tol = 1e-9 * max(scale, 1.0)
    ok = e3 < 1e-6 and e4 < tol + 1e-7 and e_fix < tol + 1e-7 and e_pr > 1e-3
    return ClaimResult(
        "cubic curve, quartic curve and corrected quartic y1(t) match; printed y1(t) does not",
        f"cubic {e3:.1e}, quartic {e4:.1e}, corrected y1 {e_fix:.1e}, printed y1 {e_pr:.2g} mm",
        ok,
    )


def _claim_modulus_only() -> ClaimResult:
    cx, cy, w, R0 = (
        Channel.from_open_loop(30.0, 0.01),
        Channel.from_open_loop(200.0, 0.02),
        20.0,
        10.0,
    )
    P1, P2 = cx.response(w), cy.response(w)
    g1, g2 = abs(P1), abs(P2)
    A = np.zeros((3, 3))
    A[0, 1], A[1, 0] = w * g2 / g1, -w * g1 / g2
    prog = Program(
        "circle", A, np.array([0.0, R0 / g2, 1.0]), np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    )
    _, out, _ = _run_steady(prog, cx, cy, window=2 * math.pi / w, n=801)
    a, b, ang = fit_centred_ellipse(out["x1"], out["y1"])
    D = abs(math.sin(float(np.angle(P2) - np.angle(P1))))
    a_fix, b_fix = R0 * math.sqrt(1 + D), R0 * math.sqrt(1 - D)
    ok = (
        abs(a - a_fix) < 1e-6 * a
        and abs(b - b_fix) < 1e-6 * b
        and min(abs(ang - 45), abs(ang - 135)) < 1e-4
        and abs(a - 12.34629) < 1e-5
    )
    return ClaimResult(
        "R0 sqrt(1 +- |sin|) = 12.34629 / 6.89704 mm at 45 or 135 deg",
        f"{a:.5f} / {b:.5f} mm at {ang:.3f} deg",
        ok,
    )


def _claim_alt_correction() -> ClaimResult:
    worst = 0.0
    for T in (0.1, 1.0):
        ch = Channel.from_open_loop(100.0, T)
        d13 = delta_parabola_13(5.0, 20.0, ch.T1, ch.T2sq)
        x0 = -50.0 * 25.0 / ch.decay_rate()
        prog = power_program(2, x0, 0.0, -d13, 20.0, 5.0)  # Y0 = y0 - delta_max
        _, out, _ = _run_steady(prog, ch, ch, window=0.2, n=401, settle=20.0)
        d, _, _ = power_distance(out["x1"], out["y1"], 2, 0.0, 0.0, 20.0, guess=out["x1"])
        worst = max(worst, float(np.max(np.abs(d))))
    return at_most(1e-6, worst, "max distance to y = x^2/p [mm] ")


def _claim_quartic_beta() -> ClaimResult:
    b = sp.symbols("beta_1", positive=True)
    T2 = sp.symbols("T_2", positive=True)
    T1 = sp.sqrt(b) * T2
    lead = sp.simplify((T1**2 - 2 * T2**2) / T2**2)  # sign of the x^2 coefficient of y'
    const = sp.expand((3 * T1**4 + 8 * T2**4 - 12 * T1**2 * T2**2) / T2**4)
    slope = sp.simplify((3 * T2**2 * T1 - T1**3) / T2**3)
    roots = sorted(float(r) for r in sp.solve(const, b))
    ok = (
        sp.solve(lead, b) == [2]
        and abs(roots[0] - 0.8453) < 1e-4
        and abs(roots[1] - 3.1547) < 1e-4
        and sp.solve(slope, b) == [3]
        and lead.subs(b, 1) < 0
        and slope.subs(b, 1) > 0
        and const.subs(b, 2) < 0
    )
    return ClaimResult(
        "opens down for beta1 < 2; constant term roots 0.8453, 3.1547; slope zero at 3",
        f"x^2 coefficient zero at {sp.solve(lead, b)}; roots {roots[0]:.4f}, {roots[1]:.4f}; slope zero at {sp.solve(slope, b)}",
        ok,
    )


LESSON = ServoErrorsLesson()
