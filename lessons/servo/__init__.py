"""Dynamic contouring errors of two-coordinate servo systems (K. Leppik, 1960), eqs (1)-(35).

A programming device (PU) generates the programmed curve x = f1(t), y = f2(t); two servo
channels (2) (T2^2 s^2 + T1 s + 1) x1 = x reproduce it.  The page: the paths (line,
vertical and horizontal parabola, circle, ellipse, cubic, quartic), the servo channels
(k, T or T1, T2, and gamma for non-identical channels), the exact solution of the whole
linear system (its matrix exponential, so the live run and the headless run agree), the
article's closed forms beside it, the program correction (7), (21)-(22), (31)-(34) and the
derivative feed-forward of the conclusions, and the article's parabola table three ways:
formula (13), simulation and the printed values (0.8 x (13) in every cell).  The machinery
is the package's modules: :mod:`.model` (the linear model), :mod:`.paths` (the PU of each
path), :mod:`.setup` (a run from the values), :mod:`.formulas` (the closed forms),
:mod:`.geometry` (contour distances), :mod:`.table`, :mod:`.metrics`, :mod:`.notes`,
:mod:`.derivation` and :mod:`.claims` (the claims, by what they are about).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import (
    MODE,
    Claim,
    CurveItem,
    DerivationStep,
    Frame,
    Group,
    Lesson,
    MarkerItem,
    Note,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Series,
    Stepper,
)
from analyzer_lab.lessons.servo.claims import servo_claims
from analyzer_lab.lessons.servo.derivation import derivation_steps
from analyzer_lab.lessons.servo.metrics import curve_metrics
from analyzer_lab.lessons.servo.notes import servo_notes
from analyzer_lab.lessons.servo.paths import CURVES
from analyzer_lab.lessons.servo.setup import SETTLE, channels, natural_t_end, setup_for

#: parameters whose change restarts the live run (they fix the start of the program)
#: longest frame (s) carried from the previous state by a step map (longer: solved anew)
MAP_STEP = 0.5
#: frame lengths are rounded to 1 / MAP_GRAIN s to find their kept step map
MAP_GRAIN = 2.0**40
RESTART = ("curve", "x0", "y0", "xc", "yc", "a", "b", "xdot0", "ydot0")
START = Group("initial", "Start of the program", change="restart")
CHANNELS = Group("channels", "Servo channels", change="live")
PATH = Group("path", "Programmed path", change="restart")
VIEW = Group("controls", "View", change="live")
MM = "mm"
FEEDS = ("off", "on", "derivative")
FORMS = ("k-T", "T1-T2")


HELP = {
    "curve": "the article's programming devices",
    "correction": "on: feed (T2^2 s^2 + T1 s + 1) x, the program correction (7), (21)-(22),"
    " (31)-(34); derivative: feed x + T1 dx/dt (the conclusions)",
    "omega": "PU rate (angular frequency for circles and ellipses)",
    "p": "parabola parameter: y - yc = (x - xc)^n / p (horizontal: x - xc = (y - yc)^2/p)",
    "v": "path speed of the line",
    "xc": "vertex / centre",
    "yc": "vertex / centre",
    "x0": "start of the program (a horizontal parabola starts on its curve)",
    "y0": "start ordinate (a vertical parabola starts on its curve)",
    "xdot0": "initial servo velocity",
    "channel": "k-T: open loop W(s) = k/((Ts+1)s), so T2^2 = T/k, T1 = 1/k; T1-T2: directly",
    "k": "open-loop gain",
    "T": "open-loop time constant",
    "gamma": "non-identical channels: T1y = gamma T1, T2y^2 = gamma T2^2",
    "magnify": "magnification of the contour error in the scene",
}


def _param(name, kind, default, label, group, unit="", lo=None, hi=None, step=None, **kw):
    """A parameter of this page (its help text from :data:`HELP`)."""
    return Param(
        name, kind, default, label, unit, lo, hi, step, group=group, help=HELP.get(name, ""), **kw
    )


def _preset(name: str, title: str, t_end: float, note: str, **values: Any) -> Preset:
    return Preset(name, title, values, t_end=t_end, note=note)


FIG4B = {"curve": "parabola-horizontal", "x0": 781.25, "y0": -125}
TABLE_CELL = "k = 100 1/s, T = 0.1 s"


class ServoErrorsLesson(Lesson):
    id = "servo-errors"
    title = "Dynamic contouring errors of two-coordinate servo systems"
    chapter = "Articles"
    problem = "Leppik (1960)"
    source = (
        "K. Leppik, On dynamic errors of two-coordinate servo systems with program control,"
        " eqs (1)-(35)"
    )
    summary = (
        "A programming device draws lines, parabolas (degree 2, 3, 4; axis along y or x),"
        " circles and ellipses; two second-order servo channels reproduce them.  Closed forms"
        " of the article next to the exact simulation, program correction, and the article's"
        " parabola table (printed values = 0.8 x formula (13))."
    )
    order = 200.0
    t_end = 5.0
    groups = (MODE, PATH, START, CHANNELS, VIEW)
    modes = ("curve", "correction")
    params = (
        _param("curve", "choice", "parabola", "path", "mode", choices=CURVES),
        _param("correction", "choice", "off", "correction / feed-forward", "mode", choices=FEEDS),
        _param("omega", "float", 5.0, "omega", "path", "1/s", 1e-4, 1000.0, 0.1),
        _param("p", "float", 20.0, "p", "path", "mm (mm^2, mm^3)", 1e-3, 1e9, 1.0),
        _param("v", "float", 50.0, "v (line)", "path", "mm/s", 0.0, 1e4, 1.0),
        _param("angle", "float", 45.0, "line angle", "path", "deg", -180.0, 180.0, 1.0),
        _param("xc", "float", 0.0, "xc", "path", MM, -1e5, 1e5, 1.0),
        _param("yc", "float", 0.0, "yc", "path", MM, -1e5, 1e5, 1.0),
        _param("a", "float", 15.0, "a (ellipse)", "path", MM, 1e-3, 1e5, 1.0),
        _param("b", "float", 6.0, "b (ellipse)", "path", MM, 1e-3, 1e5, 1.0),
        _param("x0", "float", -125.0, "x0", "initial", MM, -1e5, 1e5, 1.0),
        _param("y0", "float", 781.25, "y0", "initial", MM, -1e5, 1e5, 1.0),
        _param("xdot0", "float", 0.0, "dx1/dt(0)", "initial", "mm/s", -1e4, 1e4, 1.0),
        _param("ydot0", "float", 0.0, "dy1/dt(0)", "initial", "mm/s", -1e4, 1e4, 1.0),
        _param("channel", "choice", "k-T", "channel given by", "channels", choices=FORMS),
        _param("k", "float", 100.0, "k", "channels", "1/s", 1.0, 1e5, 1.0),
        _param("T", "float", 0.1, "T", "channels", "s", 1e-4, 10.0, 0.001),
        _param("T1", "float", 0.01, "T1", "channels", "s", 1e-5, 10.0, 0.001),
        _param("T2", "float", 0.0316227766, "T2", "channels", "s", 1e-5, 10.0, 0.001),
        _param("gamma", "float", 1.0, "gamma (y channel)", "channels", "", 0.05, 20.0, 0.01),
        _param("magnify", "float", 100.0, "error x N", "controls", "", 1.0, 1e6, 1.0),
    )
    presets = (
        _preset(
            "table-parabola",
            f"Table parabola: v = 50 mm/s, p = 20 mm, omega = 5, {TABLE_CELL}",
            5.0,
            "(13): -0.2375 mm; simulation -0.2375 mm; printed -0.19 mm = 0.8 x (13)",
            curve="parabola",
            k=100,
            T=0.1,
        ),
        _preset(
            "parabola-corrected",
            f"Parabola with program correction (22), {TABLE_CELL}",
            5.0,
            "the steady error vanishes; the transient from rest remains",
            correction="on",
        ),
        _preset(
            "parabola-derivative",
            f"Parabola, derivative feed-forward x + T1 dx/dt, {TABLE_CELL}",
            5.0,
            "conclusions: -omega^2 p T2^2/2 = -0.25 mm, larger than (13) -0.2375 mm",
            correction="derivative",
        ),
        _preset(
            "fig4b-gamma-0.5",
            "Horizontal parabola x = y^2/p (Fig. 4b), gamma = 0.5",
            5.0,
            "(19): x = y^2/p - 0.025 y - 0.234375 mm; vertex (-0.2375, 0.25) mm",
            gamma=0.5,
            **FIG4B,
        ),
        _preset(
            "fig4b-gamma-1",
            "Horizontal parabola x = y^2/p (Fig. 4b), identical channels",
            5.0,
            "(19): x = y^2/p - 0.2375 mm; vertex (-0.2375, 0) mm",
            **FIG4B,
        ),
        _preset(
            "fig4b-gamma-2",
            "Horizontal parabola x = y^2/p (Fig. 4b), gamma = 2",
            5.0,
            "(19): x = y^2/p + 0.05 y - 0.225 mm; vertex (-0.2375, -0.5) mm",
            gamma=2,
            **FIG4B,
        ),
        _preset(
            "line-45",
            "Line at 45 deg, non-identical channels gamma = 1.2, k = 100, T = 0.05",
            1.5,
            "(5)/(6): 0.05 mm = v T1 (gamma - 1)/2",
            curve="line",
            T=0.05,
            x0=0,
            y0=0,
            gamma=1.2,
            magnify=200,
        ),
        _preset(
            "line-transient",
            "Line at 45 deg, identical channels, dx1/dt(0) = 50 mm/s",
            1.5,
            "(4): transient error only; its peak ~ 1.05 T2^2/(T1 + T2) x (xdot0 xc - ydot0 yc)/|.|",
            curve="line",
            channel="T1-T2",
            T2=0.0223606798,
            x0=0,
            y0=0,
            xdot0=50,
            magnify=50,
        ),
        _preset(
            "circle",
            "Circle R0 = 10 mm, omega = 5, identical channels k = 100, T = 0.1",
            5.0,
            "(28): R0 (1 - |Phi(j omega)|) = -0.24295 mm",
            curve="circle",
            x0=0,
            y0=10,
            magnify=20,
        ),
        _preset(
            "circle-nonidentical",
            "Circle R0 = 10 mm, omega = 10; y: k = 60 (gamma = 5/3)",
            5.0,
            "(29): tilt 63.127 deg; corrected (30): 12.00691 / 10.78178 mm",
            curve="circle",
            omega=10,
            x0=0,
            y0=10,
            gamma=5 / 3,
            magnify=5,
        ),
        _preset(
            "ellipse",
            "Ellipse a = 15, b = 6 mm, omega = 8, identical channels",
            5.0,
            "semi-axes a|Phi| = 15.96743, b|Phi| = 6.38697 mm",
            curve="ellipse",
            omega=8,
            x0=0,
            y0=6,
            magnify=5,
        ),
        _preset(
            "ellipse-nonidentical",
            "Ellipse a = 15, b = 6 mm, omega = 8; gamma = 5/3",
            5.0,
            "(29)/(30), m = a|Phi1|, n = b|Phi2|: 15.97402 / 6.62696 mm, tilt 1.809 deg",
            curve="ellipse",
            omega=8,
            x0=0,
            y0=6,
            gamma=5 / 3,
            magnify=5,
        ),
        _preset(
            "cubic",
            "Cubic y = x^3/p, p = 400 mm^2, omega = 0.125, T2^2 = 0.0005 s^2",
            2.0,
            "inflection shift 2 omega^3 p^2 (3 T1 T2^2 - T1^3) = 0.00875 mm",
            curve="cubic",
            channel="T1-T2",
            T2=0.0223606798,
            omega=0.125,
            p=400,
            x0=-50,
            y0=-312.5,
            magnify=200,
        ),
        _preset(
            "quartic",
            "Quartic y = x^4/p, p = 8000 mm^3, omega = 0.00625, T2^2 = 0.0005 s^2",
            1.2,
            "vertex shift 3 omega^4 p^3 (3T1^4 + 8T2^4 - 12 T1^2 T2^2) = 0.00335 mm",
            curve="quartic",
            channel="T1-T2",
            T2=0.0223606798,
            omega=0.00625,
            p=8000,
            x0=-30,
            y0=101.25,
            magnify=500,
        ),
    )
    series = (
        Series("x", MM, "programmed x (PU output)"),
        Series("y", MM, "programmed y (PU output)"),
        Series("x1", MM, "reproduced x (x servo output)"),
        Series("y1", MM, "reproduced y (y servo output)"),
        Series("input_x", MM, "x channel input (the corrected program when correction is on)"),
        Series("input_y", MM, "y channel input (the corrected program when correction is on)"),
        Series("error_x", MM, "x error x1 - x"),
        Series("error_y", MM, "y error y1 - y"),
        Series("delta", MM, "contour error: signed distance of (x1, y1) from the programmed curve"),
        Series("delta_steady", MM, "contour error of the steady (transient-free) output"),
        Series("delta_article", MM, "the article's closed form of the steady contour error"),
    )
    readout = ("delta", "delta_steady", "delta_article", "error_x", "error_y")
    sampling = 0.01
    plots = (
        PlotSpec("Per-axis errors", ("error_x", "error_y"), MM),
        PlotSpec("Contour error", ("delta", "delta_steady", "delta_article"), MM),
    )

    def validate(self, params: Params) -> None:
        if params["curve"] in ("circle", "ellipse") and (params["x0"], params["y0"]) == (
            params["xc"],
            params["yc"],
        ):
            raise ParamError(
                "y0", "the start point coincides with the centre (xc, yc); the radius would be 0"
            )
        if channels(params)[0].decay_rate() * 600.0 < 1.0:
            raise ParamError(
                "T",
                "the channel is too weakly damped (decay time above 600 s); raise T1 or lower T2",
            )

    def notes(self, params: Params) -> list[Note]:
        return servo_notes(params, setup_for(params).path.start)

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, np.ndarray]:
        s = setup_for(params)
        m = s.measure(np.asarray(state))
        return {
            "x": m["x"],
            "y": m["y"],
            "x1": m["x1"],
            "y1": m["y1"],
            "input_x": m["ux"],
            "input_y": m["uy"],
            "error_x": m["x1"] - m["x"],
            "error_y": m["y1"] - m["y"],
            "delta": m["delta"],
            "delta_steady": m["delta_steady"],
            "delta_article": np.full(len(t), s.article),
        }

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = natural_t_end(params) if t_end is None else float(t_end)
        s = setup_for(params)
        messages = [n.text for n in self.notes(params)]
        w_fast = max(1 / math.sqrt(s.cx.T2sq), 1 / math.sqrt(s.cy.T2sq), float(params["omega"]))
        if not (t_end > 0 and math.isfinite(t_end)):
            messages.append("t_end must be positive; returning the initial state only")
            t = np.array([0.0])
        else:
            t = np.linspace(0.0, t_end, int(min(20001, max(2001, 20 * t_end * w_fast / 6.3))))
        Z = s.system.states(
            t, s.system.initial_state(float(params["xdot0"]), float(params["ydot0"]))
        )
        out = s.measure(Z)
        d = out["delta"]
        t_tr = SETTLE / s.system.decay_rate()
        metrics: dict[str, Any] = {
            "curve": params["curve"],
            "T1x": s.cx.T1,
            "T2x_sq": s.cx.T2sq,
            "T1y": s.cy.T1,
            "T2y_sq": s.cy.T2sq,
            "zeta_x": s.cx.zeta,
            "zeta_y": s.cy.zeta,
            "t_transient": t_tr,
            "article_formula": s.label,
            "delta_article": s.article,
            "correction": params["correction"],
            "input_x0": float(out["ux"][0]),
            "input_y0": float(out["uy"][0]),
            "delta_end": float(d[-1]),
            "delta_after_transient": math.nan,
            "delta_steady_extreme": float(
                out["delta_steady"][np.argmax(np.abs(out["delta_steady"]))]
            ),
        }
        after = t >= t_tr
        if after.any():
            metrics["delta_after_transient"] = float(d[np.argmax(np.where(after, np.abs(d), -1.0))])
        else:
            messages.append(
                f"the run ends before the transient has decayed (t_end {t_end:g} s < {t_tr:.3g} s)"
            )
        metrics.update(curve_metrics(params, s.path, s.cx, s.cy, t, out, after))
        return self.result(params, t, Z, metrics, messages)

    def stepper(self, params: Params) -> Stepper:
        return ServoStepper(self, params)

    def scene(self, params: Params) -> SceneSpec:
        s = setup_for(params)
        t = np.linspace(0.0, natural_t_end(params), 801)
        out = s.measure(s.system.states(t, s.system.initial_state()))
        prog = np.column_stack([out["x"], out["y"], np.zeros_like(t)])
        N = float(params["magnify"])
        _, fx, fy = s.path.contour(out["x1ss"], out["y1ss"], out["x"], out["y"])
        mag = np.column_stack(
            [fx + N * (out["x1ss"] - fx), fy + N * (out["y1ss"] - fy), np.zeros_like(t)]
        )
        pts = np.vstack([prog, mag])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        span = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-3))
        lo, hi = lo - 0.05 * span, hi + 0.05 * span
        lo[2], hi[2] = -0.05 * span, 0.05 * span
        markers = [MarkerItem("start", prog[:1], (40, 160, 60), 0.01 * span, "start")]
        vertex = s.path.vertex()
        if vertex is not None:
            point = np.array([[*vertex[1], 0.0]])
            markers.append(
                MarkerItem("vertex / centre", point, (120, 120, 120), 0.008 * span, vertex[0])
            )
        moving = {
            "programmed": (40, 40, 200),
            "reproduced": (220, 60, 60),
            "error x N": (230, 150, 20),
        }
        if params["correction"] != "off":
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

    def derivation(self, params: Params) -> list[DerivationStep]:
        return derivation_steps(params, *channels(params))

    def claims(self) -> list[Claim]:
        return servo_claims()


class ServoStepper(Stepper):
    """Live run: the exact state exp(M (t - t_a)) z_a from the last anchor (t_a, z_a)
    (the start, or the state when a parameter changed while running)."""

    def __init__(self, lesson: ServoErrorsLesson, params: Params) -> None:
        self._lesson = lesson
        self._params = params
        self._last: tuple[float, np.ndarray] | None = None
        self.reset()

    @property
    def t(self) -> float:
        return self._t

    def _state(self) -> np.ndarray:
        """The state at the current time: exp(M (t - t_a)) z_a at the anchor, then the
        previous frame's state carried by the kept step map exp(M d) of the frame's length
        rounded to ``d = k 2**-40 s``, plus ``(dt - d) M z`` for the rest (below 1e-12 s:
        its second-order error is far below round-off), so that the few frame lengths of
        a played run share their maps whatever the clock's round-off."""
        last = self._last
        if last is not None and last[0] == self._t:
            return last[1]
        dt = self._t - last[0] if last is not None else 0.0
        if last is not None and 0.0 < dt <= MAP_STEP:
            system = self._setup.system
            d = round(dt * MAP_GRAIN) / MAP_GRAIN
            Z = last[1] @ system.step_map(d).T
            Z = Z + (dt - d) * (Z @ system.M.T)
        else:
            Z = self._setup.system.states([self._t], self._z_a, self._t_a)
        self._last = (self._t, Z)
        return Z

    def frame(self) -> Frame:
        s, Z = self._setup, self._state()
        m = s.measure(Z)
        N = float(self._params["magnify"])
        x1, y1 = float(m["x1"][0]), float(m["y1"][0])
        foot = np.array([float(m["foot_x"][0]), float(m["foot_y"][0]), 0.0])
        err = np.array([x1, y1, 0.0]) - foot
        points = {
            "programmed": np.array([[float(m["x"][0]), float(m["y"][0]), 0.0]]),
            "reproduced": np.array([[x1, y1, 0.0]]),
            "error x N": (foot + N * err)[None, :],
        }
        if self._params["correction"] != "off":
            points["corrected program"] = np.array([[float(m["ux"][0]), float(m["uy"][0]), 0.0]])
        message = self._note
        rate = self._rate
        if not message and self._t * rate < SETTLE:
            message = (
                f"transient: e^(-t/tau) = {math.exp(-self._t * rate):.2g} (tau = {1 / rate:.3g} s)"
            )
        return Frame(
            t=self._t,
            points=points,
            vectors={"error vector x N": (foot[None, :], (N * err)[None, :])},
            scalars=self._lesson.frame_scalars(self._params, self._t, Z),
            message=message,
        )

    def advance(self, dt: float) -> Frame:
        if dt > 0 and math.isfinite(dt):
            self._t += float(dt)
            self._note = ""
        return self.frame()

    def set_params(self, params: Params) -> None:
        old = self._params
        restart = any(old[n] != params[n] for n in RESTART) or (
            params["curve"] in ("cubic", "quartic")
            and (old["omega"], old["p"]) != (params["omega"], params["p"])
        )
        z = self._state()[0]
        self._params = params
        if restart:
            self.reset()
            self._note = "program start changed: run restarted"
        else:
            self._setup = setup_for(params)
            self._t_a, self._z_a = self._t, z
            self._last, self._rate = None, self._setup.system.decay_rate()

    def reset(self) -> Frame:
        p = self._params
        self._setup = setup_for(p)
        self._t_a, self._t = 0.0, 0.0
        self._z_a = self._setup.system.initial_state(float(p["xdot0"]), float(p["ydot0"]))
        self._last, self._rate = None, self._setup.system.decay_rate()
        self._note = ""
        return self.frame()


LESSON = ServoErrorsLesson()
