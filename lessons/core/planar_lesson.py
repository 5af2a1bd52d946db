"""Shared machinery of the plane-curve lessons (Problems 1.1, 1.2, C1.1-C1.4).

A subclass declares its parameters (the common ones below appended) and supplies
:meth:`PlanarLesson.planar_model` (the conic analyzer and start points); this base
gives the run (continuous Gauss-Legendre, and the digital analyzer (1.24)-(1.25) when
``digital`` is ``simple`` or ``improved``), the live stepper, the planar scene and the
plots.  The scene is drawn in the plane ``xy`` (z = 0) or ``xz`` (y = 0).
"""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from lessons.core.block_diagram import BlockDiagram, block_diagram, diagram_step
from lessons.core.contract import (
    CurveItem,
    DerivationStep,
    Frame,
    Lesson,
    MarkerItem,
    Param,
    ParamError,
    Params,
    PlotSpec,
    RunResult,
    SceneSpec,
    Stepper,
)
from lessons.core.formula import Formula
from lessons.core.planar import (
    DIGITAL_MODES,
    MAX_DIGITAL_ITERATIONS,
    DigitalAnalyzer,
    PlanarModel,
    embed,
)

DIGITAL_PARAMS: tuple[Param, ...] = (
    Param(
        "digital",
        "choice",
        "off",
        "digital analyzer (1.25)",
        choices=DIGITAL_MODES,
        group="method",
        help="replace integration by successive additions: simple (Euler) or improved (the y addition uses the new x)",
    ),
    Param(
        "delta",
        "float",
        0.01,
        "quantum Δ of the argument",
        unit="s",
        min=1e-5,
        max=0.5,
        step=0.001,
        group="method",
    ),
    Param(
        "pulse",
        "float",
        0.01,
        "step pulse length (0: no position quantization)",
        min=0.0,
        max=100.0,
        step=0.001,
        group="method",
    ),
    Param(
        "h",
        "float",
        1e-3,
        "step h (continuous run)",
        unit="s",
        min=1e-5,
        max=0.1,
        step=1e-4,
        group="method",
    ),
)
MAX_SAMPLES = 4001


@dataclass
class PlanarPrepared:
    model: PlanarModel  # with a33 through the start points
    r0: np.ndarray  # (N, 2)
    messages: list[str] = field(default_factory=list)


def _thin(n: int, samples: int = MAX_SAMPLES) -> np.ndarray:
    return np.unique(np.linspace(0, n - 1, min(n, samples)).round().astype(int))


class PlanarLesson(Lesson):
    """Base of the plane conic lessons."""

    plane: str = "xy"
    own_params: tuple[Param, ...] = ()

    def __init_subclass__(cls, **kw: object) -> None:
        super().__init_subclass__(**kw)
        cls.params = (*cls.own_params, *DIGITAL_PARAMS)
        cls.plots = (
            PlotSpec("coordinates", ("x", "y") if cls.plane == "xy" else ("x", "z")),
            PlotSpec("velocity components", ("vx", "vy") if cls.plane == "xy" else ("vx", "vz")),
            PlotSpec("invariant drift |F - F0| / scale", ("drift",)),
            PlotSpec("digital analyzer: distance from the continuous path", ("dda_error",)),
            PlotSpec("digital analyzer: step pulses per axis (cumulative)", ("nx", "ny")),
        )

    # -- the model ----------------------------------------------------------------

    @abstractmethod
    def planar_model(self, params: Params) -> tuple[PlanarModel, np.ndarray, list[str]]:
        """The analyzer (a33 may be anything), start points ``(N, 2)`` and notes."""

    def prepare(self, params: Params) -> PlanarPrepared:
        model, r0, notes = self.planar_model(params)
        r0 = np.atleast_2d(np.asarray(r0, dtype=float))
        return PlanarPrepared(model.through(r0), r0, list(notes))

    def axis_names(self) -> tuple[str, str]:
        return ("x", "y") if self.plane == "xy" else ("x", "z")

    # -- the page -----------------------------------------------------------------

    def general_derivation(self, params: Params) -> list[DerivationStep]:
        a = {n: sp.Symbol(n) for n in ("a11", "a12", "a22", "a13", "a23", "a33")}
        x, y = sp.symbols("x y")
        w, phi = sp.Symbol("ω"), sp.Symbol("φ")
        return [
            DerivationStep(
                "The plane conic",
                "",
                sp.Eq(
                    a["a11"] * x**2
                    + 2 * a["a12"] * x * y
                    + a["a22"] * y**2
                    + 2 * a["a13"] * x
                    + 2 * a["a23"] * y
                    + a["a33"],
                    0,
                ),
                "(1.21)",
            ),
            DerivationStep(
                "Its slope",
                "Differentiating (1.21) along the curve.",
                sp.Eq(
                    sp.Symbol("dy/dx"),
                    -(a["a11"] * x + a["a12"] * y + a["a13"])
                    / (a["a12"] * x + a["a22"] * y + a["a23"]),
                ),
                "(1.29)",
            ),
            DerivationStep(
                "The conic analyzer",
                "Numerator and denominator of (1.29) become the two integrator inputs; ω sets speed and direction.",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), w * (a["a12"] * x + a["a22"] * y + a["a23"])),
                    sp.Eq(sp.Symbol("dy/dφ"), -w * (a["a11"] * x + a["a12"] * y + a["a13"])),
                ],
                "(1.30)",
            ),
            DerivationStep(
                "The argument",
                "The control action: the argument runs at rate ω.",
                sp.Eq(sp.Symbol("dφ"), w * sp.Symbol("dt")),
                "(1.31)",
            ),
        ]

    def digital_derivation(self, params: Params) -> list[DerivationStep]:
        y, y0, z, c = sp.symbols("y y0 z c")
        dx, dy, dz = sp.symbols("dx dy dz")
        Dx, Dy, Dz = sp.symbols("Δx Δy Δz")
        steps = [
            DerivationStep(
                "Integration by successive additions",
                "A digital device replaces the integrator by sums (the digital differential analyzer).",
                [sp.Eq(y, y0 + sp.Integral(1, y), evaluate=False), sp.Eq(dz, c * y * dx)],
                "(1.24)",
            ),
            DerivationStep(
                "The digital integrator",
                "Separate inputs for the integrand increment Δy and the argument increment Δx; the output is Δz.",
                [
                    sp.Eq(y, y0 + sp.Sum(Dy, (sp.Symbol("k"), 1, sp.Symbol("n")))),
                    sp.Eq(Dz, c * y * Dx),
                ],
                "(1.25)",
            ),
        ]
        mode = params["digital"] if "digital" in params else "off"
        n = sp.Symbol("n")
        xs, ys = (sp.Symbol(f"{s}_n") for s in self.axis_names())
        xs1, ys1 = (sp.Symbol(f"{s}_n+1") for s in self.axis_names())
        k, D = sp.Symbol("k"), sp.Symbol("Δ")
        a = {nm: sp.Symbol(nm) for nm in ("a11", "a12", "a22", "a13", "a23")}
        if mode != "off":
            second_x = xs1 if mode == "improved" else xs
            steps.append(
                DerivationStep(
                    f"The {mode} update",
                    (
                        "Both additions use the old coordinates (Euler): a circle spirals out by about πΔR per turn."
                        if mode == "simple"
                        else "The second addition uses the x just updated (symplectic Euler): on the circle x² + y² + Δxy is kept exactly, the error stays within ΔR/4."
                    )
                    + " Each coordinate emits a step pulse whenever its remainder register passes half a pulse length.",
                    [
                        sp.Eq(xs1, xs + k * D * (a["a12"] * xs + a["a22"] * ys + a["a23"])),
                        sp.Eq(ys1, ys - k * D * (a["a11"] * second_x + a["a12"] * ys + a["a13"])),
                    ],
                    "(1.25) applied to (1.30)",
                    reconstructed="derived, not in source: the source gives the digital integrator (1.25) only",
                )
            )
        return steps

    def extra_derivation(self, params: Params, prepared: PlanarPrepared) -> list[DerivationStep]:
        return []

    def derivation(self, params: Params) -> list[DerivationStep]:
        prepared = self.prepare(params)
        return [
            *self.general_derivation(params),
            *self.extra_derivation(params, prepared),
            self.block_diagram_step(params, prepared),
            *self.digital_derivation(params),
        ]

    #: The textbook figure the block diagram corresponds to.
    block_figure: str = "Fig. 1.5 notation"

    def diagram_equations(self, params: Params, prepared: PlanarPrepared) -> list[sp.Eq]:
        """The equations the diagram is drawn from: the integrated ones, a time-varying gain as the control u."""
        g = prepared.model.gain
        const = not isinstance(g, Formula) or g.is_constant
        gain = (
            (
                sp.nsimplify(
                    float(g.value(0.0)) if isinstance(g, Formula) else float(g), rational=True
                )
            )
            if const
            else sp.Symbol("u", real=True)
        )
        return prepared.model.equations(gain, self.axis_names())

    def block_diagram(self, params: Params, prepared: PlanarPrepared | None = None) -> BlockDiagram:
        """The analyzer's block diagram (Fig. 1.5 notation) built from :meth:`diagram_equations`."""
        prepared = self.prepare(params) if prepared is None else prepared
        return block_diagram(
            self.diagram_equations(params, prepared),
            signals=("u",),
            title=f"{self.problem}: analyzer block diagram",
        )

    def block_diagram_step(self, params: Params, prepared) -> DerivationStep:
        """The diagram as a derivation step: ``svg`` is the self-contained SVG (escaped labels, no scripts)."""
        return diagram_step(
            self.block_diagram(params, prepared),
            self.block_figure,
            "the wiring is generated from the equations; the figure's layout is not reproduced",
        )

    def validate(self, params: Params) -> None:
        for name in ("u",):
            if name in params and isinstance(params[name], Formula):
                try:
                    params[name].check_finite(np.linspace(0.0, self.t_end * 10, 2001))
                except ValueError as exc:
                    raise ParamError(name, str(exc)) from None

    # -- the run ------------------------------------------------------------------

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = self.t_end if t_end is None else float(t_end)
        prep = self.prepare(params)
        model, r0 = prep.model, prep.r0
        messages = list(prep.messages)
        mode = params["digital"]
        h = float(params["h"])
        series: dict[str, np.ndarray] = {}
        metrics: dict[str, object] = {"t_end": t_end}
        if mode == "off":
            t, r = model.integrate(r0, t_end, h)
            idx = _thin(len(t))
            t, r = t[idx], r[idx]
        else:
            delta = float(params["delta"])
            n_it = int(np.ceil(t_end / delta - 1e-9))
            if n_it > MAX_DIGITAL_ITERATIONS:
                n_it = MAX_DIGITAL_ITERATIONS
                messages.append(
                    f"the digital run is limited to {MAX_DIGITAL_ITERATIONS} additions: it stops at t = {n_it * delta:.4g}"
                )
            dda = DigitalAnalyzer(model, r0, delta, float(params["pulse"]), mode)
            pos, pul = dda.run(n_it)
            pos = np.concatenate([r0[None], pos])
            pul = np.concatenate([np.zeros((1, *r0.shape), dtype=np.int64), pul])
            m = max(1, int(np.ceil(delta / h - 1e-9)))
            tc, rc = model.integrate(r0, n_it * delta, delta / m)
            rc = rc[::m][: n_it + 1]
            t = np.arange(n_it + 1) * delta
            idx = _thin(len(t))
            counts = np.cumsum(pul, axis=0)
            t, r, pos, counts = t[idx], rc[idx], pos[idx], counts[idx]
            err = np.linalg.norm(pos - r, axis=-1)
            p3 = embed(pos, self.plane)
            for k in range(r.shape[1]):
                sfx = "" if k == 0 else f"_{k + 1}"
                for j, c in enumerate("xyz"):
                    series[f"{c}_dda{sfx}"] = p3[:, k, j]
                series["nx" + sfx] = counts[:, k, 0].astype(float)
                series["ny" + sfx] = counts[:, k, 1].astype(float)
                series["dda_error" + sfx] = err[:, k]
            scaleF = model.scale(pos)
            metrics.update(
                {
                    "dda_error_max": float(err.max()),
                    "dda_error_end": float(err[-1, 0]),
                    "dda_level_error_max": float(np.abs(model.F(pos)).max() / scaleF),
                    "pulses_x": int(np.abs(pul[..., 0]).sum()),
                    "pulses_y": int(np.abs(pul[..., 1]).sum()),
                    "additions": n_it,
                }
            )
        v = model.velocity(t, r)
        r3, v3 = embed(r, self.plane), embed(v, self.plane)
        for k in range(r.shape[1]):
            sfx = "" if k == 0 else f"_{k + 1}"
            for j, c in enumerate("xyz"):
                series[c + sfx] = r3[:, k, j]
            for j, c in enumerate("xyz"):
                series["v" + c + sfx] = v3[:, k, j]
        F = model.F(r)
        scale = model.scale(r)
        series["drift"] = np.abs(F).max(axis=1) / scale
        metrics.update(
            {
                "invariant_drift_max": float(np.abs(F).max()),
                "invariant_drift_rel": float(np.abs(F).max() / scale),
                "speed_max": float(np.linalg.norm(v, axis=-1).max()),
            }
        )
        metrics.update(self.extra_metrics(params, prep, t, r, v))
        return RunResult(self.id, None, params.raw(), t, series, metrics, messages)

    def extra_metrics(
        self, params: Params, prep: PlanarPrepared, t: np.ndarray, r: np.ndarray, v: np.ndarray
    ) -> dict[str, object]:
        return {}

    def stepper(self, params: Params) -> Stepper:
        return PlanarStepper(self, params)

    def scene(self, params: Params) -> SceneSpec:
        prep = self.prepare(params)
        T = float(self.t_end)
        curves = []
        pts = [prep.r0]
        for sgn in (1, -1):
            t, r = prep.model.integrate(prep.r0, sgn * T, max(float(params["h"]), T / 4000))
            pts.append(r.reshape(-1, 2))
            for k in range(r.shape[1]):
                curves.append(
                    CurveItem(
                        f"level-curve-{'fwd' if sgn > 0 else 'back'}-{k + 1}",
                        embed(r[:, k], self.plane),
                        (60, 60, 60),
                        1.5,
                    )
                )
        allp = np.concatenate(pts)
        allp = allp[np.all(np.isfinite(allp), axis=1)]
        lo2, hi2 = allp.min(axis=0), allp.max(axis=0)
        pad = 0.08 * max(float(np.max(hi2 - lo2)), 1e-6)
        lo2, hi2 = lo2 - pad, hi2 + pad
        lo3, hi3 = np.full(3, -pad), np.full(3, pad)
        j = 1 if self.plane == "xy" else 2
        lo3[0], hi3[0], lo3[j], hi3[j] = lo2[0], hi2[0], lo2[1], hi2[1]
        moving = {"point": (220, 30, 30)}
        if params["digital"] != "off":
            moving["digital"] = (30, 30, 220)
        return SceneSpec(
            bounds=(tuple(map(float, lo3)), tuple(map(float, hi3))),
            curves=curves,
            markers=[
                MarkerItem(
                    "start",
                    embed(prep.r0, self.plane),
                    (230, 80, 60),
                    0.02 * float(np.max(hi2 - lo2)),
                    "start",
                )
            ],
            moving_points=moving,
            moving_vectors={"velocity": (30, 120, 30), "gradient": (60, 60, 200)},
            planar=True,
        )


class PlanarStepper(Stepper):
    """Live run: Gauss-Legendre steps of the continuous analyzer, and the digital analyzer beside it."""

    def __init__(self, lesson: PlanarLesson, params: Params) -> None:
        self.lesson = lesson
        self._t = 0.0
        self.dda: DigitalAnalyzer | None = None
        self.set_params(params)
        self.R = self.prep.r0.copy()

    @property
    def t(self) -> float:
        return self._t

    def set_params(self, params: Params) -> None:
        """New coefficients and controls act from the current state (the level curve through
        the current point); a new start point or family size applies on :meth:`reset`."""
        prep = self.lesson.prepare(params)
        self.params, self.h = params, float(params["h"])
        if hasattr(self, "R") and len(self.R) == len(prep.r0):
            prep = PlanarPrepared(prep.model.through(self.R), prep.r0, prep.messages)
        elif hasattr(self, "R"):
            self.R = prep.r0.copy()
            self._t = 0.0
        self.prep = prep
        mode = params["digital"]
        if mode == "off":
            self.dda = None
        elif (
            self.dda is None
            or self.dda.mode != mode
            or self.dda.delta != float(params["delta"])
            or self.dda.pulse != float(params["pulse"])
        ):
            start = self.R if hasattr(self, "R") else prep.r0
            self.dda = DigitalAnalyzer(
                prep.model, start, float(params["delta"]), float(params["pulse"]), mode
            )
            self.dda.k = int(round(self._t / float(params["delta"])))
        else:
            self.dda.model = prep.model

    def reset(self) -> Frame:
        self._t = 0.0
        self.prep = self.lesson.prepare(self.params)
        self.R = self.prep.r0.copy()
        if self.dda is not None:
            self.dda = DigitalAnalyzer(
                self.prep.model, self.prep.r0, self.dda.delta, self.dda.pulse, self.dda.mode
            )
        return self.frame()

    def advance(self, dt: float) -> Frame:
        if not np.isfinite(dt) or dt <= 0:
            return self.frame()
        n = max(1, int(np.ceil(dt / self.h - 1e-9)))
        _, states = self.prep.model.integrate(self.R, self._t + dt, dt / n, t0=self._t)
        self.R = states[-1]
        self._t += dt
        if self.dda is not None:
            todo = int(np.floor(self._t / self.dda.delta + 1e-9)) - self.dda.k
            if todo > 0:
                self.dda.run(min(todo, MAX_DIGITAL_ITERATIONS))
        return self.frame()

    def frame(self) -> Frame:
        model = self.prep.model
        v = model.velocity(self._t, self.R)
        g = model.half_gradient(self.R)
        plane = self.lesson.plane
        p3 = embed(self.R, plane)
        drift = float(np.max(np.abs(model.F(self.R)))) / model.scale(self.R)
        v3 = embed(v, plane)
        scalars = {
            "x": float(p3[0, 0]),
            "y": float(p3[0, 1]),
            "z": float(p3[0, 2]),
            "vx": float(v3[0, 0]),
            "vy": float(v3[0, 1]),
            "vz": float(v3[0, 2]),
            "drift": drift,
        }
        points = {"point": p3}
        message = (
            ""
            if np.any(np.linalg.norm(v, axis=-1) > 0)
            else "the analyzer field is zero here: the point does not move"
        )
        if self.dda is not None:
            pos = self.dda.position
            points["digital"] = embed(pos, plane)
            scalars["dda_error"] = float(np.linalg.norm(pos[0] - self.R[0]))
            scalars["nx"], scalars["ny"] = float(self.dda.n[0, 0]), float(self.dda.n[0, 1])
        return Frame(
            t=self._t,
            points=points,
            vectors={"velocity": (p3, v3), "gradient": (p3, embed(g, plane))},
            scalars=scalars,
            message=message,
        )
