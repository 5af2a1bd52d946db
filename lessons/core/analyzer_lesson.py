"""Shared machinery of the analyzer lessons (Problems 1.3-1.6): a point driven by the
general analyzer (1.50) (or its constant-speed form (1.59)) on a quadric.

A concrete lesson supplies its surface (:meth:`AnalyzerLesson.surface`), its own
parameters and presets, extra derivation steps and claims; this base gives the
common parameters (controls, start point, family, integrator), the run, the live
stepper, the scene and the plots.
"""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from lessons.core.analyzer import (
    COEFF_NAMES,
    AnalyzerModel,
    AnalyzerRun,
    Controls,
    SpeedStepper,
    U,
    field_expr,
    integrate,
    quadric_expr,
)
from lessons.core.block_diagram import BlockDiagram, block_diagram, diagram_step
from lessons.core.contract import (
    DerivationStep,
    Frame,
    Lesson,
    MarkerItem,
    MeshItem,
    Param,
    ParamError,
    Params,
    PlotSpec,
    RunResult,
    SceneSpec,
    Stepper,
)
from lessons.core.formula import Formula
from lessons.core.integrators import apply_propagators, gl_linear, gl_propagators
from lessons.core.quadric import Quadric

METHODS = ("gauss-legendre-3", "gauss-legendre-2", "RK45", "DOP853")

CONTROL_PARAMS: tuple[Param, ...] = (
    Param(
        "u1",
        "formula",
        "5",
        "u1(t)",
        min=-20,
        max=20,
        step=0.1,
        group="controls",
        help="control u1: a number or a formula of t",
    ),
    Param("u2", "formula", "5", "u2(t)", min=-20, max=20, step=0.1, group="controls"),
    Param("u3", "formula", "5", "u3(t)", min=-20, max=20, step=0.1, group="controls"),
)
SPEED_PARAMS: tuple[Param, ...] = (
    Param(
        "V",
        "formula",
        "1",
        "V(t)",
        unit="units/s",
        min=0,
        max=20,
        step=0.1,
        group="controls",
        help="speed along the curve (1.58)",
    ),
    Param(
        "direction",
        "choice",
        "+",
        "direction (sign of omega)",
        choices=("+", "-"),
        group="controls",
    ),
)
START_PARAMS: tuple[Param, ...] = (
    Param("x0", "float", 1.0, "x0", min=-1e4, max=1e4, step=0.05, group="initial"),
    Param("y0", "float", 0.0, "y0", min=-1e4, max=1e4, step=0.05, group="initial"),
    Param("z0", "float", 0.0, "z0", min=-1e4, max=1e4, step=0.05, group="initial"),
    Param(
        "family",
        "int",
        1,
        "curves in the family",
        min=1,
        max=24,
        step=1,
        group="initial",
        help="several start points at once (Figs. 1.12, 1.26)",
    ),
    Param(
        "family_axis",
        "choice",
        "z",
        "family spread along",
        choices=("x", "y", "z"),
        group="initial",
    ),
    Param(
        "family_step", "float", 0.3, "family spacing", min=-1e3, max=1e3, step=0.05, group="initial"
    ),
)
METHOD_PARAMS: tuple[Param, ...] = (
    Param(
        "integrator",
        "choice",
        "gauss-legendre-3",
        "integrator",
        choices=METHODS,
        group="method",
        help="Gauss-Legendre keeps F to round-off; RK45/DOP853 are scipy's solve_ivp",
    ),
    Param(
        "h",
        "float",
        1e-2,
        "step h",
        unit="s",
        min=1e-5,
        max=0.1,
        step=1e-3,
        group="method",
        help="Gauss-Legendre step; order 6 (3 stages): 0.01 s keeps the textbook examples to ~1e-9",
    ),
    Param("rtol", "float", 1e-3, "solve_ivp rtol", min=1e-14, max=1e-1, group="method"),
    Param("atol", "float", 1e-6, "solve_ivp atol", min=1e-16, max=1e-1, group="method"),
)

ANALYZER_PLOTS = (
    PlotSpec("velocity components", ("vx", "vy", "vz")),
    PlotSpec("squared speed |v|^2", ("v2",)),
    PlotSpec("invariant drift |F - F0| / scale", ("drift",)),
)


@dataclass
class Prepared:
    """A lesson's parameters turned into a model and start points (with notes for the user)."""

    quadric: Quadric
    model: AnalyzerModel
    r0: np.ndarray  # (N, 3)
    messages: list[str] = field(default_factory=list)


class AnalyzerLesson(Lesson):
    """Base of the analyzer lessons; subclasses set ``surface_params`` and implement :meth:`surface`."""

    constant_speed: bool = False
    surface_params: tuple[Param, ...] = ()
    plots = ANALYZER_PLOTS

    def __init_subclass__(cls, **kw: object) -> None:
        super().__init_subclass__(**kw)
        speed = SPEED_PARAMS if cls.constant_speed else ()
        cls.params = (*cls.surface_params, *CONTROL_PARAMS, *speed, *START_PARAMS, *METHOD_PARAMS)

    # -- the model --------------------------------------------------------------

    @abstractmethod
    def surface(self, params: Params) -> Quadric:
        """The quadric F = 0 this lesson's analyzer keeps the point on."""

    def controls(self, params: Params) -> Controls:
        V = params["V"] if self.constant_speed else None
        sign = -1.0 if self.constant_speed and params["direction"] == "-" else 1.0
        return Controls(params["u1"], params["u2"], params["u3"], V=V, sign=sign)

    def keep_level(self, params: Params) -> bool:
        """True: the start point picks the level set F = F(r0) (the ellipsoid's (1.63));
        False: the start point is projected onto F = 0."""
        return False

    def start_points(self, params: Params) -> np.ndarray:
        base = np.array([params["x0"], params["y0"], params["z0"]], dtype=float)
        k = int(params["family"])
        axis = "xyz".index(params["family_axis"])
        offsets = (np.arange(k) - (k - 1) / 2.0) * float(params["family_step"])
        pts = np.repeat(base[None, :], k, axis=0)
        pts[:, axis] += offsets
        return pts

    def prepare(self, params: Params) -> Prepared:
        """Surface, model and start points; start points off the surface are projected (noted)."""
        quadric = self.surface(params)
        pts = self.start_points(params)
        messages: list[str] = []
        if self.keep_level(params):
            models = [quadric.level_through(p) for p in pts]
            coeffs = {n: np.array([getattr(q, n) for q in models]) for n in COEFF_NAMES}
            q0 = models[0]
        else:
            q0 = quadric
            scale = quadric.scale
            for i, p in enumerate(pts):
                if abs(float(quadric.F(p))) > 1e-9 * scale:
                    try:
                        newp = quadric.project(p)
                    except ValueError as exc:
                        raise ParamError(
                            "x0",
                            f"start point {tuple(np.round(p, 6))} cannot be put on the surface: {exc}",
                        ) from None
                    messages.append(
                        f"start point {_fmt(p)} is off the surface (F = {float(quadric.F(p)):.3g}); projected to {_fmt(newp)}"
                    )
                    pts[i] = newp
            coeffs = {n: np.full(len(pts), float(getattr(quadric, n))) for n in COEFF_NAMES}
        model = AnalyzerModel(coeffs, self.controls(params))
        g = model.half_gradient(pts)
        if np.any(np.linalg.norm(g, axis=-1) <= 1e-12 * max(1.0, quadric.scale)):
            messages.append(
                "the gradient of F is zero at the start point (a singular point of the surface): the analyzer field vanishes and the point cannot move"
            )
        return Prepared(q0, model, pts, messages)

    def validate(self, params: Params) -> None:
        controls = self.controls(params)
        try:
            controls.check_finite(self.t_end * 10)
        except ValueError as exc:
            raise ParamError("u1", str(exc)) from None

    # -- the page ---------------------------------------------------------------

    def general_derivation(self, params: Params, prepared: Prepared) -> list[DerivationStep]:
        """Steps shared by every analyzer lesson: (1.42), (1.45), (1.49), (1.50) on this surface."""
        F = quadric_expr()
        gx, gy, gz = sp.symbols("F_x F_y F_z")
        return [
            DerivationStep(
                "The second-order surface",
                "Any quadric in the textbook's indexing.",
                sp.Eq(sp.Symbol("F"), F),
                "(1.42)",
            ),
            DerivationStep(
                "Tangency",
                "The velocity must stay orthogonal to the gradient for every parametrization.",
                sp.Eq(
                    gx * sp.Symbol("dx/dφ") + gy * sp.Symbol("dy/dφ") + gz * sp.Symbol("dz/dφ"), 0
                ),
                "(1.44)",
            ),
            DerivationStep(
                "The general analyzer",
                "Three free controls u1, u2, u3; convention B, the common factor 2 of the gradient dropped.",
                _general_field_equations(),
                "(1.49)-(1.50)",
                reconstructed="the signs and the row layout were lost in the source; rebuilt so that the surviving (1.55), (1.57), (1.62), (1.63) come out exactly (convention B)",
            ),
            DerivationStep(
                "On this surface",
                f"{prepared.quadric.label or 'the surface'}: F = 0 with the numbers of this lesson, φ = t.",
                [
                    sp.Eq(prepared.model.surface_expr(), 0),
                    *prepared.model.equations(_control_exprs(params)),
                ],
                "(1.50)",
            ),
        ]

    def speed_derivation(self, params: Params) -> list[DerivationStep]:
        if not self.constant_speed:
            return []
        w = sp.Symbol("ω")
        return [
            DerivationStep(
                "Argument control for constant speed",
                "Put dφ = ω(t) dt and choose ω so that the speed is V; the sign of ω picks the direction. "
                "Where the field vanishes the formula divides by zero: the point holds and the lab says why.",
                sp.Eq(
                    w, sp.Symbol("±V") / sp.sqrt(sum(fi**2 for fi in field_expr(quadric_expr())))
                ),
                "(1.58)",
                reconstructed="only 'ω = ±' survived in the source; rebuilt from V² = vx² + vy² + vz²",
            ),
            DerivationStep(
                "The constant-speed analyzer",
                "The analyzer's right-hand sides multiplied by ω.",
                [sp.Eq(sp.Symbol(f"d{c}/dt"), w * sp.Symbol(f"(d{c}/dφ)")) for c in "xyz"],
                "(1.59)",
                reconstructed="lost in the source; follows from (1.58) and the text",
            ),
        ]

    def derivation(self, params: Params) -> list[DerivationStep]:
        prepared = self.prepare(params)
        return [
            *self.general_derivation(params, prepared),
            *self.speed_derivation(params),
            *self.extra_derivation(params, prepared),
            self.block_diagram_step(params, prepared),
        ]

    #: The textbook figure the block diagram corresponds to (a subclass may name it).
    block_figure: str = "Fig. 1.5 notation"

    def block_diagram(self, params: Params, prepared: Prepared | None = None) -> BlockDiagram:
        """The analyzer's block diagram (Fig. 1.5 notation) built from the integrated equations."""
        prepared = self.prepare(params) if prepared is None else prepared
        eqs = prepared.model.equations()
        if self.constant_speed:
            w = sp.Symbol("ω", real=True)
            eqs = [sp.Eq(e.lhs, w * e.rhs) for e in eqs]
        return block_diagram(
            eqs, signals=("u1", "u2", "u3", "ω"), title=f"{self.problem}: analyzer block diagram"
        )

    def block_diagram_step(self, params: Params, prepared) -> DerivationStep:
        """The diagram as a derivation step: ``svg`` is the self-contained SVG (escaped labels, no scripts)."""
        return diagram_step(
            self.block_diagram(params, prepared),
            self.block_figure,
            "the wiring is generated from the equations (the figure images are absent in the source)",
        )

    def extra_derivation(self, params: Params, prepared: Prepared) -> list[DerivationStep]:
        return []

    def run_analyzer(
        self, params: Params, t_end: float, samples: int | None = 2001
    ) -> tuple[Prepared, AnalyzerRun]:
        prepared = self.prepare(params)
        run = integrate(
            prepared.model,
            prepared.r0,
            t_end,
            h=float(params["h"]),
            method=str(params["integrator"]),
            samples=samples,
            rtol=float(params["rtol"]),
            atol=float(params["atol"]),
        )
        return prepared, run

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = self.t_end if t_end is None else float(t_end)
        prepared, run = self.run_analyzer(params, t_end)
        scale = float(max(prepared.quadric.scale, np.max(prepared.model.F_scale(run.r))))
        v2 = (run.v**2).sum(-1)
        series: dict[str, np.ndarray] = {}
        for k in range(run.r.shape[1]):
            suffix = "" if k == 0 else f"_{k + 1}"
            for j, c in enumerate("xyz"):
                series[c + suffix] = run.r[:, k, j]
            for j, c in enumerate("xyz"):
                series["v" + c + suffix] = run.v[:, k, j]
            series["v2" + suffix] = v2[:, k]
        series["drift"] = run.drift.max(axis=1) / scale
        messages = list(prepared.messages)
        if run.held.any():
            first = float(run.t[np.argmax(run.held.any(axis=1))])
            messages.append(
                f"the field vanished (|grad F x w| ~ 0) from t = {first:.4g}: omega = V/|field| is undefined there, the point held"
            )
        metrics = {
            "t_end": t_end,
            "method": run.method,
            "invariant_drift_max": float(run.drift.max()),
            "invariant_drift_rel": float(run.drift.max() / scale),
            "v2_min": float(v2.min()),
            "v2_max": float(v2.max()),
            "F0": float(run.F0[0]),
            "held_samples": int(run.held.sum()),
            "nfev": run.nfev,
        }
        metrics.update(self.extra_metrics(params, prepared, run))
        return RunResult(self.id, None, params.raw(), run.t, series, metrics, messages)

    def extra_metrics(
        self, params: Params, prepared: Prepared, run: AnalyzerRun
    ) -> dict[str, float]:
        return {}

    def stepper(self, params: Params) -> Stepper:
        return AnalyzerStepper(self, params)

    def scene(self, params: Params) -> SceneSpec:
        prepared = self.prepare(params)
        lo, hi = self.scene_bounds(params, prepared)
        mesh = prepared.quadric.mesh(bounds=(tuple(lo), tuple(hi)))
        meshes = []
        if len(mesh.faces):
            meshes.append(
                MeshItem(
                    "surface",
                    np.asarray(mesh.vertices),
                    np.asarray(mesh.faces),
                    (110, 150, 210),
                    0.45,
                )
            )
        return SceneSpec(
            bounds=(tuple(map(float, lo)), tuple(map(float, hi))),
            meshes=meshes,
            markers=[
                MarkerItem(
                    "start", prepared.r0, (230, 80, 60), 0.04 * float(np.max(hi - lo)) / 2, "start"
                )
            ],
            moving_points={"point": (220, 30, 30)},
            moving_vectors={"velocity": (30, 120, 30), "gradient": (60, 60, 200)},
        )

    def scene_bounds(self, params: Params, prepared: Prepared) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = (np.asarray(b, dtype=float) for b in prepared.quadric.default_bounds())
        lo = np.minimum(lo, prepared.r0.min(axis=0) - 0.1)
        hi = np.maximum(hi, prepared.r0.max(axis=0) + 0.1)
        return lo, hi


def _fmt(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(v):.4g}" for v in p) + ")"


def _general_field_equations() -> list[sp.Eq]:
    Fx, Fy, Fz = (sp.Symbol(f"∂F/∂{c}") for c in "xyz")
    u1, u2, u3 = U
    return [
        sp.Eq(sp.Symbol("dx/dφ"), u1 * Fy - u2 * Fz),
        sp.Eq(sp.Symbol("dy/dφ"), -u1 * Fx + u3 * Fz),
        sp.Eq(sp.Symbol("dz/dφ"), u2 * Fx - u3 * Fy),
    ]


def _control_exprs(params: Params) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    out = []
    for name in ("u1", "u2", "u3"):
        v = params[name]
        out.append(v.expr if isinstance(v, Formula) else sp.nsimplify(float(v)))
    return tuple(out)  # type: ignore[return-value]


_STEP_MAPS: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}


def _model_key(model: AnalyzerModel) -> tuple:
    """What a constant step map depends on besides h: the surface and the control values."""
    return (
        tuple(np.asarray(model.coeffs[n], dtype=float).tobytes() for n in COEFF_NAMES),
        tuple(float(v) for v in model.controls.at(np.zeros(1))[:, 0]),
    )


def _constant_step_map(
    model: AnalyzerModel, n_points: int, h: float, stages: int, model_key: tuple | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The Gauss-Legendre step map of a time-independent analyzer (cached, bounded)."""
    key = (
        model_key if model_key is not None else _model_key(model),
        n_points,
        round(h, 15),
        stages,
    )
    hit = _STEP_MAPS.get(key)
    if hit is None:
        hit = gl_propagators(lambda ts: model.linear_coeffs(ts, n_points), 0.0, h, 1, stages)
        if len(_STEP_MAPS) > 512:
            _STEP_MAPS.clear()
        _STEP_MAPS[key] = hit
    return hit


class AnalyzerStepper(Stepper):
    """Live run of an analyzer lesson: fixed GL steps of size h, parameters live."""

    def __init__(self, lesson: AnalyzerLesson, params: Params) -> None:
        self.lesson = lesson
        self._t = 0.0
        self.set_params(params)
        self.R = self.prepared.r0.copy()

    @property
    def t(self) -> float:
        return self._t

    def set_params(self, params: Params) -> None:
        """New controls/surface/speed take effect from the current state; a changed start
        point or family only applies on :meth:`reset`."""
        prepared = self.lesson.prepare(params)
        old = getattr(self, "prepared", None)
        self.params = params
        self.prepared = prepared
        self.h = float(params["h"])
        self.stages = 2 if params["integrator"] == "gauss-legendre-2" else 3
        if old is not None and hasattr(self, "R"):
            if len(self.R) != len(prepared.r0):
                self.R = prepared.r0.copy()
            else:
                # keep the state; if the surface changed, put the point back on it
                q = prepared.quadric
                if not self.lesson.keep_level(params) and np.any(
                    np.abs(q.F(self.R)) > 1e-9 * q.scale
                ):
                    self.R = np.array([q.project(p) for p in self.R])
        self.F0 = prepared.model.F(self.R if hasattr(self, "R") else prepared.r0)
        model = prepared.model
        self._constant = model.controls.V is None and model.controls.constant()
        self._model_key = _model_key(model) if self._constant else None

    def reset(self) -> Frame:
        self._t = 0.0
        self.R = self.prepared.r0.copy()
        self.F0 = self.prepared.model.F(self.R)
        return self.frame()

    def advance(self, dt: float) -> Frame:
        if not np.isfinite(dt) or dt <= 0:
            return self.frame()
        model = self.prepared.model
        n = max(1, int(np.ceil(dt / self.h - 1e-9)))
        h = dt / n
        if self._constant:
            # time-independent field: every step has the same map; build it once (shared by
            # every session running the same surface and controls)
            D, phi = _constant_step_map(model, len(self.R), h, self.stages, self._model_key)
            self.R = apply_propagators(
                np.broadcast_to(D, (n, *D.shape[1:])),
                np.broadcast_to(phi, (n, *phi.shape[1:])),
                self.R,
            )[-1]
        elif model.controls.V is None:
            _, states = gl_linear(
                lambda ts: model.linear_coeffs(ts, len(self.R)),
                self.R,
                self._t,
                self._t + n * h,
                h,
                self.stages,
            )
            self.R = states[-1]
        else:
            stepper = SpeedStepper(model, self.stages)
            _, states, _ = stepper.integrate(self.R, self._t, self._t + n * h, h)
            self.R = states[-1]
        self._t += n * h
        return self.frame()

    def frame(self) -> Frame:
        model = self.prepared.model
        v = model.velocity(self._t, self.R)
        g = model.half_gradient(self.R)
        q = self.prepared.quadric
        drift = float(np.max(np.abs(model.F(self.R) - self.F0))) / q.scale
        message = ""
        if model.controls.V is not None and np.any(np.linalg.norm(v, axis=-1) == 0):
            message = "the field vanishes here (|grad F x w| = 0): omega = V/|field| is undefined, the point holds until the controls change"
        elif np.any(np.linalg.norm(v, axis=-1) == 0):
            message = "the analyzer field is zero here: the point does not move"
        uu = model.controls.at(np.asarray(self._t))
        return Frame(
            t=self._t,
            points={"point": self.R.copy()},
            vectors={"velocity": (self.R.copy(), v), "gradient": (self.R.copy(), g)},
            scalars={
                "vx": float(v[0, 0]),
                "vy": float(v[0, 1]),
                "vz": float(v[0, 2]),
                "v2": float((v[0] ** 2).sum()),
                "drift": drift,
                "u1": float(uu[0]),
                "u2": float(uu[1]),
                "u3": float(uu[2]),
            },
            message=message,
        )
