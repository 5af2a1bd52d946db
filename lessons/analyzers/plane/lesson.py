"""Shared machinery of the plane-curve lessons (Problems 1.1, 1.2, C1.1-C1.4).

A subclass declares its parameters (the digital analyzer's are appended) and supplies
:meth:`PlanarLesson.planar_model` (the conic analyzer and its start points); this base
gives the declared series, the one observation, the run and the live view (both read
the same :class:`~analyzer_lab.lessons.analyzers.plane.conic.PlanarTrack`: the closed-form continuous point and
the digital analyzer (1.24)-(1.25) when ``digital`` is ``simple`` or ``improved``), the
planar scene and the plots.  The scene is drawn in the plane ``xy`` (z = 0) or ``xz``
(y = 0).
"""

from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import dataclass

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.block_diagram import (
    BlockDiagram,
    block_diagram,
    diagram_step,
)
from analyzer_lab.lessons.analyzers.plane.conic import (
    DIGITAL_MODES,
    MAX_DIGITAL_ITERATIONS,
    ArgumentIntegral,
    DigitalAnalyzer,
    DigitalTrack,
    PlanarModel,
    PlanarState,
    PlanarTrack,
    embed,
)
from analyzer_lab.lessons.kit.contract import (
    CurveItem,
    DerivationStep,
    Frame,
    Group,
    Lesson,
    MarkerItem,
    Param,
    ParamError,
    Params,
    PlotSpec,
    RunResult,
    SceneSpec,
    Series,
    Stepper,
)
from analyzer_lab.lessons.kit.formula import Formula
from analyzer_lab.lessons.kit.tracked import TrackStepper

DIGITAL = Group("digital", "Digital analyzer (1.24)-(1.25)", expanded=False)

DIGITAL_PARAMS: tuple[Param, ...] = (
    Param(
        "digital",
        "choice",
        "off",
        "digital analyzer (1.25)",
        choices=DIGITAL_MODES,
        group="mode",
        help="replace integration by successive additions: simple (Euler) or improved"
        " (the y addition uses the new x)",
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
        group="digital",
    ),
    Param(
        "pulse",
        "float",
        0.01,
        "step pulse length (0: no position quantization)",
        min=0.0,
        max=100.0,
        step=0.001,
        group="digital",
    ),
)
PLANAR_SERIES: tuple[Series, ...] = (
    Series("x", "", "x of the point", member=True),
    Series("y", "", "y of the point (0 in the xz plane)", member=True),
    Series("z", "", "z of the point (0 in the xy plane)", member=True),
    Series("vx", "1/s", "velocity component dx/dt", member=True),
    Series("vy", "1/s", "velocity component dy/dt", member=True),
    Series("vz", "1/s", "velocity component dz/dt", member=True),
    Series("speed", "1/s", "speed |v| of the point", member=True),
    Series("drift", "", "invariant drift max |F| / scale over the family (0: on the curve)"),
)
DIGITAL_SERIES: tuple[Series, ...] = (
    Series("x_dda", "", "x of the digital analyzer (the staircase)", member=True),
    Series("y_dda", "", "y of the digital analyzer", member=True),
    Series("z_dda", "", "z of the digital analyzer", member=True),
    Series("nx", "", "step pulses on the first axis (x), cumulative and signed", member=True),
    Series(
        "ny",
        "",
        "step pulses on the second axis (y; z in the xz plane), cumulative and signed",
        member=True,
    ),
    Series(
        "dda_error",
        "",
        "distance of the digital point from the continuous one after the same additions",
        member=True,
    ),
)
DIGITAL_NAMES = frozenset(s.name for s in DIGITAL_SERIES)


@dataclass
class PlanarPrepared:
    model: PlanarModel  # with a33 through the start points
    r0: np.ndarray  # (N, 2)


class PlanarLesson(Lesson):
    """Base of the plane conic lessons."""

    plane: str = "xy"
    own_params: tuple[Param, ...] = ()
    series = (*PLANAR_SERIES, *DIGITAL_SERIES)
    readout = ("x", "y", "z", "speed", "drift")
    sampling = 0.01

    def __init_subclass__(cls, **kw: object) -> None:
        super().__init_subclass__(**kw)
        cls.params = (*cls.own_params, *DIGITAL_PARAMS)
        axes = ("x", "y") if cls.plane == "xy" else ("x", "z")
        cls.plots = (
            PlotSpec("coordinates", axes),
            PlotSpec("velocity components", tuple("v" + a for a in axes)),
            PlotSpec("invariant drift |F| / scale", ("drift",)),
            PlotSpec("digital analyzer: distance from the continuous path", ("dda_error",)),
            PlotSpec("digital analyzer: step pulses per axis (cumulative)", ("nx", "ny")),
        )

    # -- the model ----------------------------------------------------------------

    @abstractmethod
    def planar_model(self, params: Params) -> tuple[PlanarModel, np.ndarray]:
        """The analyzer (a33 may be anything) and its start points ``(N, 2)``."""

    def prepare(self, params: Params) -> PlanarPrepared:
        model, r0 = self.planar_model(params)
        r0 = np.atleast_2d(np.asarray(r0, dtype=float))
        return PlanarPrepared(model.through(r0), r0)

    def axis_names(self, params: Params) -> tuple[str, str]:
        return ("x", "y") if self.plane_of(params) == "xy" else ("x", "z")

    def plane_of(self, params: Params) -> str:
        """The plane the curve lies in (a lesson with several curves may override)."""
        return self.plane

    def series_for(self, params: Params) -> tuple[Series, ...]:
        """The declared series; the digital analyzer's only while it is on."""
        out = super().series_for(params)
        if params["digital"] != "off":
            return out
        return tuple(
            s
            for s in out
            if s.name not in DIGITAL_NAMES and s.name.rsplit("_", 1)[0] not in DIGITAL_NAMES
        )

    def series_key(self, params: Params) -> tuple[int, bool]:
        """The series depend on the family size and on whether the digital analyzer is on."""
        return int(super().series_key(params)), params["digital"] != "off"

    # -- the page -----------------------------------------------------------------

    def general_derivation(self, params: Params) -> list[DerivationStep]:
        a = {n: sp.Symbol(n) for n in ("a11", "a12", "a22", "a13", "a23", "a33")}
        x, y = sp.symbols("x y")
        w = sp.Symbol("ω")
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
        mode = params["digital"]
        xs, ys = (sp.Symbol(f"{s}_n") for s in self.axis_names(params))
        xs1, ys1 = (sp.Symbol(f"{s}_n+1") for s in self.axis_names(params))
        k, D = sp.Symbol("k"), sp.Symbol("Δ")
        a = {nm: sp.Symbol(nm) for nm in ("a11", "a12", "a22", "a13", "a23")}
        if mode != "off":
            second_x = xs1 if mode == "improved" else xs
            steps.append(
                DerivationStep(
                    f"The {mode} update",
                    (
                        "Both additions use the old coordinates (Euler): a circle spirals out"
                        " by about πΔR per turn."
                        if mode == "simple"
                        else "The second addition uses the x just updated (symplectic Euler):"
                        " on the circle x² + y² + Δxy is kept exactly, the error stays within ΔR/4."
                    )
                    + " Each coordinate emits a step pulse whenever its remainder register"
                    " passes half a pulse length.",
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
        return prepared.model.equations(gain, self.axis_names(params))

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
        if "u" in params and isinstance(params["u"], Formula):
            try:
                params["u"].check_finite(np.linspace(0.0, self.t_end * 10, 2001))
            except ValueError as exc:
                raise ParamError("u", str(exc)) from None

    # -- the solution -------------------------------------------------------------

    def track(self, params: Params) -> PlanarTrack:
        """The run of these values from t = 0 (shared by :meth:`simulate` and the live view)."""
        prep = self.prepare(params)
        return PlanarTrack(prep.model, prep.r0, 0.0, self._digital(params, prep.model, prep.r0, 0))

    def _digital(
        self, params: Params, model: PlanarModel, start: np.ndarray, k0: int
    ) -> DigitalTrack | None:
        if params["digital"] == "off":
            return None
        dda = DigitalAnalyzer(
            model, start, float(params["delta"]), float(params["pulse"]), params["digital"]
        )
        dda.k = k0
        return DigitalTrack(dda)

    def continue_track(
        self, old: Params, params: Params, t: float, state: PlanarState
    ) -> PlanarTrack | None:
        """New coefficients and controls act from the current point (the level curve through
        it); a new start point, family size or plane starts over."""
        prep = self.prepare(params)
        if len(prep.r0) != state.r.shape[1] or self.plane_of(old) != self.plane_of(params):
            return None
        r = state.r[0]
        model = prep.model.through(r)
        start, k0 = r, int(np.floor(t / float(params["delta"]) + 1e-9))
        if state.digital is not None and all(old[n] == params[n] for n in ("delta", "pulse")):
            start = state.digital[0]
        return PlanarTrack(model, r, t, self._digital(params, model, start, k0))

    def observe(self, params: Params, t: np.ndarray, state: PlanarState) -> dict[str, np.ndarray]:
        plane, model = self.plane_of(params), state.model
        v = state.v if state.v is not None else model.velocity(t, state.r)
        r3, v3 = embed(state.r, plane), embed(v, plane)
        speed = np.linalg.norm(v, axis=-1)
        out: dict[str, np.ndarray] = {}
        digital = params["digital"] != "off"
        if digital:
            d3 = embed(state.digital, plane)
            err = np.linalg.norm(state.digital - state.reference, axis=-1)
        for k in range(state.r.shape[1]):
            sfx = "" if k == 0 else f"_{k + 1}"
            for j, c in enumerate("xyz"):
                out[c + sfx] = r3[:, k, j]
                out["v" + c + sfx] = v3[:, k, j]
            out["speed" + sfx] = speed[:, k]
            if digital:
                for j, c in enumerate("xyz"):
                    out[f"{c}_dda{sfx}"] = d3[:, k, j]
                out["nx" + sfx], out["ny" + sfx] = state.counts[:, k, 0], state.counts[:, k, 1]
                out["dda_error" + sfx] = err[:, k]
        out["drift"] = np.max(np.abs(model.F(state.r)), axis=1) / model.scale(state.r)
        return out

    def observe_one(self, params: Params, t: float, state: PlanarState) -> dict[str, float] | None:
        """A played frame's series in plain floats (the continuous analyzer; with the
        digital one on, :meth:`observe`)."""
        if not isinstance(state, PlanarState) or state.v is None or state.digital is not None:
            return None
        xy = self.plane_of(params) == "xy"
        r = state.r[0].tolist()
        out: dict[str, float] = {}
        for k, ((x, y), (vx, vy)) in enumerate(zip(r, state.v[0].tolist())):
            sfx = "" if k == 0 else f"_{k + 1}"
            out["x" + sfx], out["vx" + sfx] = x, vx
            out["y" + sfx], out["vy" + sfx] = (y, vy) if xy else (0.0, 0.0)
            out["z" + sfx], out["vz" + sfx] = (0.0, 0.0) if xy else (y, vy)
            out["speed" + sfx] = math.sqrt(vx * vx + vy * vy)
        out["drift"] = state.model.drift_one(r)
        return out

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = self.t_end if t_end is None else float(t_end)
        track = self.track(params)
        t = self.sample_grid(t_end)
        state = track.at(t)
        messages = [n.text for n in self.notes(params)]
        metrics: dict[str, object] = {"t_end": t_end}
        if track.digital is not None:
            n_it = int(track.additions(np.array([t_end]))[0])
            if t_end / float(params["delta"]) > MAX_DIGITAL_ITERATIONS:
                messages.append(
                    f"the digital run is limited to {MAX_DIGITAL_ITERATIONS} additions:"
                    f" it holds from t = {n_it * float(params['delta']):.4g}"
                )
            track.digital.at(np.array([n_it]))
            counts = track.digital.counts[0][: n_it + 1]
            err = np.linalg.norm(state.digital - state.reference, axis=-1)
            level = np.abs(state.model.F(state.digital)) / state.model.scale(state.digital)[:, None]
            metrics.update(
                {
                    "dda_error_max": float(err.max()),
                    "dda_error_end": float(err[-1, 0]),
                    "dda_level_error_max": float(level.max()),
                    "pulses_x": int(np.abs(np.diff(counts[..., 0], axis=0)).sum()),
                    "pulses_y": int(np.abs(np.diff(counts[..., 1], axis=0)).sum()),
                    "additions": n_it,
                }
            )
        F = np.abs(state.model.F(state.r))
        v = state.model.velocity(t, state.r)
        metrics.update(
            {
                "invariant_drift_max": float(F.max()),
                "invariant_drift_rel": float(np.max(F.max(axis=1) / state.model.scale(state.r))),
                "speed_max": float(np.linalg.norm(v, axis=-1).max()),
            }
        )
        metrics.update(self.extra_metrics(params, track, t, state))
        return self.result(params, t, state, metrics, messages)

    def extra_metrics(
        self, params: Params, track: PlanarTrack, t: np.ndarray, state: PlanarState
    ) -> dict[str, object]:
        return {}

    def stepper(self, params: Params) -> Stepper:
        return TrackStepper(self, params)

    def make_frame(self, params: Params, t: float, state: PlanarState) -> Frame:
        plane, model = self.plane_of(params), state.model
        r = state.r[0]
        v, g = model.field_one(model.gain_one(t), r)  # plain floats, equal to round-off
        state.v = v[None]  # the observation reads it too
        p3 = embed(r, plane)
        points = {"point": p3}
        if state.digital is not None:
            points["digital"] = embed(state.digital[0], plane)
        moving = bool(np.any(np.abs(v) > 0))
        return Frame(
            t=t,
            points=points,
            vectors={"velocity": (p3, embed(v, plane)), "gradient": (p3, embed(g, plane))},
            scalars=self.frame_scalars(params, t, state),
            message="" if moving else "the analyzer field is zero here: the point does not move",
        )

    def scene(self, params: Params) -> SceneSpec:
        prep = self.prepare(params)
        plane, model = self.plane_of(params), prep.model
        c = model.coeffs
        D = c["a11"] * c["a22"] - c["a12"] ** 2
        reach = float(np.max(np.abs(ArgumentIntegral(model.gain)(np.linspace(0, self.t_end, 201)))))
        curves, pts = [], [prep.r0]
        for k in range(model.size):
            span = 2 * np.pi / np.sqrt(D[k]) if D[k] > 0 else max(reach, 1e-6)
            member = PlanarModel({n: v[k : k + 1] for n, v in c.items()}, 1.0)
            r = member.flow(prep.r0[k : k + 1], np.linspace(-span, span, 2001))[:, 0]
            r = r[np.all(np.isfinite(r), axis=1)]
            pts.append(r)
            curves.append(CurveItem(f"level-curve-{k + 1}", embed(r, plane), (60, 60, 60), 1.5))
        allp = np.concatenate(pts)
        lo2, hi2 = allp.min(axis=0), allp.max(axis=0)
        pad = 0.08 * max(float(np.max(hi2 - lo2)), 1e-6)
        lo2, hi2 = lo2 - pad, hi2 + pad
        lo3, hi3 = np.full(3, -pad), np.full(3, pad)
        j = 1 if plane == "xy" else 2
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
                    embed(prep.r0, plane),
                    (230, 80, 60),
                    0.02 * float(np.max(hi2 - lo2)),
                    "start",
                )
            ],
            moving_points=moving,
            moving_vectors={"velocity": (30, 120, 30), "gradient": (60, 60, 200)},
            planar=True,
        )
