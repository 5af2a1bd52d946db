"""Shared machinery of the analyzer lessons (Problems 1.3-1.6): a point driven by the
general analyzer (1.50) (or its constant-speed form (1.59)) on a quadric.

A concrete lesson supplies its surface (:meth:`AnalyzerLesson.surface`), its own
parameters, groups and presets, extra derivation steps, metrics and claims; this base
gives the common parameters (controls, start point, family, integrator), the
observation (one function for runs and live frames), the notes, the run, the live
stepper, the scene and the plots.  Runs and live steppers read one
:class:`~analyzer_lab.lessons.analyzers.field.run.Trajectory`, so they agree at every time.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import (
    COEFF_NAMES,
    AnalyzerModel,
    Controls,
    U,
    field_expr,
    observation_one,
    quadric_expr,
)
from analyzer_lab.lessons.analyzers.field.block_diagram import (
    BlockDiagram,
    block_diagram,
    diagram_step,
)
from analyzer_lab.lessons.analyzers.field.params import (
    ANALYZER_PLOTS,
    ANALYZER_SERIES,
    CONTROL_PARAMS,
    CONTROLS,
    DIRECTION,
    INITIAL,
    METHOD_PARAMS,
    SPEED_CONTROLS,
    SPEED_PARAMS,
    START_PARAMS,
)
from analyzer_lab.lessons.analyzers.field.run import WORK_PER_STAGE, Trajectory
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.contract import (
    METHOD,
    DerivationStep,
    Frame,
    Group,
    Lesson,
    MarkerItem,
    MeshItem,
    Note,
    Param,
    ParamError,
    Params,
    RunResult,
    SceneSpec,
    Stepper,
)
from analyzer_lab.lessons.kit.formula import Formula


@dataclass
class Prepared:
    """A lesson's parameters turned into a model and start points, with the notes on what
    was done with the values; ``F0`` is F at the start points, ``scale`` the size of F's
    terms there (the drift is measured against it)."""

    quadric: Quadric
    model: AnalyzerModel
    r0: np.ndarray  # (N, 3)
    notes: list[Note] = field(default_factory=list)
    F0: np.ndarray = field(default_factory=lambda: np.zeros(1))
    scale: float = 1.0


def state(r: np.ndarray, F0: np.ndarray) -> dict[str, np.ndarray]:
    """An analyzer lesson's state at times ``(m,)``: positions ``r (m, N, 3)`` and the
    values ``F0 (m, N)`` the drift is measured from (a frame adds the velocities ``v``
    it has already computed)."""
    r = np.asarray(r, dtype=float)
    return {"r": r, "F0": np.broadcast_to(F0, r.shape[:2])}


class AnalyzerLesson(Lesson):
    """Base of the analyzer lessons; subclasses set ``surface_params`` (in their
    ``surface_groups``) and implement :meth:`surface`."""

    constant_speed: bool = False
    surface_params: tuple[Param, ...] = ()
    surface_groups: tuple[Group, ...] = (Group("surface", "Surface"),)
    plots = ANALYZER_PLOTS
    series = ANALYZER_SERIES
    readout = ("x", "y", "z", "speed", "v2", "drift")
    start_point = ("x0", "y0", "z0")
    family = "family"

    def __init_subclass__(cls, **kw: object) -> None:
        super().__init_subclass__(**kw)
        speed = SPEED_PARAMS if cls.constant_speed else ()
        cls.params = (*speed, *cls.surface_params, *CONTROL_PARAMS, *START_PARAMS, *METHOD_PARAMS)
        cls.groups = (
            *((DIRECTION,) if cls.constant_speed else ()),
            *cls.surface_groups,
            SPEED_CONTROLS if cls.constant_speed else CONTROLS,
            INITIAL,
            METHOD,
        )
        if cls.constant_speed:
            cls.modes = ("direction", *cls.modes)
        cls._cache: dict[tuple, Prepared] = {}

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
        """Surface, model and start points (cached per parameter values); start points off
        the surface are projected onto it, and the notes say so."""
        last = self.__dict__.get("_last_prepared")
        if last is not None and last[0] is params:  # a frame asks with the same object
            return last[1]
        key = tuple(sorted((k, repr(v)) for k, v in params.raw().items()))
        hit = self._cache.get(key)
        if hit is None:
            hit = self._prepare(params)
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[key] = hit
        self.__dict__["_last_prepared"] = (params, hit)  # held: its id stays its own
        return hit

    def _prepare(self, params: Params) -> Prepared:
        quadric = self.surface(params)
        pts = self.start_points(params)
        notes: list[Note] = []
        if self.keep_level(params):
            models = [quadric.level_through(p) for p in pts]
            coeffs = {n: np.array([getattr(q, n) for q in models]) for n in COEFF_NAMES}
            q0 = models[0]
        else:
            q0 = quadric
            for i, p in enumerate(pts):
                if abs(float(quadric.F(p))) > 1e-9 * quadric.scale:
                    try:
                        pts[i] = quadric.project(p)
                    except ValueError as exc:
                        raise ParamError(
                            "x0", f"start point {_fmt(p)} cannot be put on the surface: {exc}"
                        ) from None
                    notes.append(
                        Note(
                            "info",
                            f"start point {_fmt(p)} is off the surface"
                            f" (F = {float(quadric.F(p)):.3g}); projected to {_fmt(pts[i])}",
                            "(1.42)",
                        )
                    )
            coeffs = {n: np.full(len(pts), float(getattr(quadric, n))) for n in COEFF_NAMES}
        model = AnalyzerModel(coeffs, self.controls(params))
        g = model.half_gradient(pts)
        if np.any(np.linalg.norm(g, axis=-1) <= 1e-12 * max(1.0, quadric.scale)):
            notes.append(
                Note(
                    "warning",
                    "the gradient of F is zero at the start point (a singular point of the"
                    " surface): the analyzer field vanishes and the point cannot move",
                    "(1.45), (1.50)",
                )
            )
        elif self.constant_speed:
            notes += self._hold_notes(model, pts)
        F0 = model.F(pts)
        scale = float(max(q0.scale, np.max(model.F_scale(pts[None]))))
        return Prepared(q0, model, pts, notes, F0, scale)

    def _hold_notes(self, model: AnalyzerModel, r0: np.ndarray) -> list[Note]:
        """Where the constant-speed analyzer's field vanishes at a start point: from t = 0
        for as long as it stays zero there (probed over the lesson's run time)."""
        probe = np.linspace(0.0, self.t_end, 2001)
        R = np.broadcast_to(r0, (len(probe), *r0.shape))
        A, c = model.linear_coeffs(probe, len(r0))
        norm = np.linalg.norm(np.einsum("mnij,mnj->mni", A, R) + c, axis=-1)
        umax = np.abs(model.controls.at(probe)).max(axis=0)[:, None]
        held = model.holds(norm, model.hold_size(R), umax)
        notes = []
        for k in np.flatnonzero(held[0]):
            moving = np.flatnonzero(~held[:, k])
            head = (
                f"The field of (1.50) vanishes at the start point {_fmt(r0[k])} at t = 0"
                " (grad F is parallel to (u3, u2, u1)): ω = ±V/|field| (1.58) divides by zero"
            )
            if not len(moving):
                text = f"{head} for the whole run, so the point holds there."
            elif moving[0] == 1:
                text = (
                    f"{head} at that instant only, so the velocity shown at t = 0 is 0;"
                    " from t > 0 the field is non-zero and the point moves at speed V."
                )
            else:
                text = (
                    f"{head} until t ≈ {probe[moving[0]]:.3g} s: the point holds while it"
                    " does, then moves at speed V."
                )
            notes.append(Note("info", text, "(1.58)-(1.59)"))
        return notes

    def validate(self, params: Params) -> None:
        """Each control (and V) finite over ten runs' length; a refusal names its field."""
        probe = np.linspace(0.0, max(self.t_end * 10, 1e-9), 2001)
        for name in ("u1", "u2", "u3", "V"):
            value = params.get(name)
            if isinstance(value, Formula):
                try:
                    value.check_finite(probe)
                except ValueError as exc:
                    raise ParamError(name, str(exc)) from None

    def notes(self, params: Params) -> list[Note]:
        return list(self.prepare(params).notes)

    # -- observation and runs -------------------------------------------------------

    def observe(self, params: Params, t: np.ndarray, state: Any) -> Mapping[str, Any]:
        prepared = self.prepare(params)
        model = prepared.model
        R = np.asarray(state["r"], dtype=float)
        v = state["v"] if "v" in state else model.velocities(t, R)
        v2 = (v**2).sum(-1)
        drift = (model.F(R) - state["F0"]) / prepared.scale
        uu = model.controls.at(t)
        out: dict[str, np.ndarray] = {"u1": uu[0], "u2": uu[1], "u3": uu[2]}
        for k in range(R.shape[1]):
            suffix = "" if k == 0 else f"_{k + 1}"
            for j, c in enumerate("xyz"):
                out[c + suffix] = R[:, k, j]
                out["v" + c + suffix] = v[:, k, j]
            out["v2" + suffix] = v2[:, k]
            out["speed" + suffix] = np.sqrt(v2[:, k])
            out["drift" + suffix] = drift[:, k]
        return out

    def observe_one(self, params: Params, t: float, state: Any) -> dict[str, float] | None:
        """A played frame's series from what the frame has computed (``v``, ``u``)."""
        if "v" not in state or "u" not in state:
            return None
        prepared = self.prepare(params)
        R, F0 = state["r"][0], np.broadcast_to(state["F0"][0], state["r"].shape[1:2])
        F = prepared.model.F_one(R)
        return observation_one(state["u"], R, state["v"][0], F, F0.tolist(), prepared.scale)

    def trajectory(
        self, params: Params, prepared: Prepared, t0: float = 0.0, r0: np.ndarray | None = None
    ) -> Trajectory:
        """The lesson's trajectory from ``(t0, r0)`` (the start points by default)."""
        return Trajectory(
            prepared.model,
            prepared.r0 if r0 is None else r0,
            t0,
            str(params["integrator"]),
            float(params["h"]),
            float(params["rtol"]),
            float(params["atol"]),
        )

    def run_grid(self, params: Params, t_end: float) -> np.ndarray:
        """The nodes ``k h`` up to ``t_end`` (at most ~2000 samples, keeping the multiples
        of the source's sampling step), and ``t_end``."""
        h = float(params["h"])
        n = int(np.floor(t_end / h + 1e-9))
        stride = max(1, n // 2000)
        if self.sampling:
            m = int(round(self.sampling / h))
            if m > 0 and abs(m * h - self.sampling) <= 1e-9 * self.sampling:
                while m % stride:
                    stride -= 1
        t = np.arange(0, n + 1, stride) * h
        if t_end - t[-1] > 1e-9 * max(1.0, t_end):
            t = np.append(t, t_end)
        return t

    def work_bound(self, params: Params, t_end: float) -> float:
        """A Gauss-Legendre run takes ``t_end / h`` steps of ``s`` stages for every point
        (the constant-speed form more: substeps and Newton iterations)."""
        method = str(params["integrator"])
        if not method.startswith("gauss-legendre"):
            return 0.0
        steps = math.ceil(float(t_end) / float(params["h"]))
        stages = int(method.rsplit("-", 1)[1])
        points = int(params[self.family]) if self.family is not None else 1
        return float(WORK_PER_STAGE * steps * stages * points)

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = self.t_end if t_end is None else float(t_end)
        prepared = self.prepare(params)
        traj = self.trajectory(params, prepared)
        t = self.run_grid(params, t_end)
        R = traj.at(t)
        messages = [n.text for n in prepared.notes]
        res = self.result(params, t, state(R, prepared.F0), messages=messages)
        members = [k for k in res.series if k.split("_")[0] == "speed"]
        speed = np.stack([res.series[k] for k in members], axis=1)
        v2 = speed**2
        held = np.zeros(speed.shape, dtype=bool)
        if self.constant_speed:
            held = (speed == 0.0) & (np.abs(prepared.model.controls.speed(t)) > 0)[:, None]
            # a point held from the start is explained by the notes; this is one that moved
            away = np.any(R != prepared.r0[None], axis=-1)
            later = (held & away).any(axis=1)
            if later.any():
                res.messages.append(
                    f"the field vanished along the path (first at t = {t[later][0]:.4g} s):"
                    " ω = V/|field| (1.58) is undefined there and the velocity is 0 at"
                    f" {int(later.sum())} samples"
                )
        drift = np.abs(np.stack([res.series[k.replace("speed", "drift")] for k in members], axis=1))
        res.metrics = {
            "t_end": t_end,
            "method": traj.method,
            "invariant_drift_max": float(drift.max() * prepared.scale),
            "invariant_drift_rel": float(drift.max()),
            "v2_min": float(v2.min()),
            "v2_max": float(v2.max()),
            "F0": float(prepared.F0[0]),
            "held_samples": int(held.sum()),
            "nfev": traj.nfev,
            **self.extra_metrics(params, prepared, res),
        }
        return res

    def extra_metrics(
        self, params: Params, prepared: Prepared, result: RunResult
    ) -> dict[str, float | str]:
        return {}

    def stepper(self, params: Params) -> Stepper:
        return AnalyzerStepper(self, params)

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
                reconstructed="the signs and the row layout were lost in the source; rebuilt so that"
                " the surviving (1.55), (1.57), (1.62), (1.63) come out exactly (convention B)",
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
                "Where the field vanishes the formula divides by zero: the point holds only"
                " while the field stays zero, and the lab says so.",
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

    # -- the page ---------------------------------------------------------------

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


class AnalyzerStepper(Stepper):
    """Live run of an analyzer lesson: reads the lesson's trajectory at the frame times.

    New controls, surface or speed take effect from the current state (a new trajectory
    starts there); a changed start point or family applies on :meth:`reset`.
    """

    def __init__(self, lesson: AnalyzerLesson, params: Params) -> None:
        self.lesson = lesson
        self.params = params
        self.prepared = lesson.prepare(params)
        self._start(0.0, self.prepared.r0, self.prepared.F0)

    def _start(self, t: float, R: np.ndarray, F0: np.ndarray) -> None:
        self._t, self.R, self.F0 = t, np.array(R, dtype=float), F0
        self.traj = self.lesson.trajectory(self.params, self.prepared, t, self.R)

    @property
    def t(self) -> float:
        return self._t

    def set_params(self, params: Params) -> None:
        prepared = self.lesson.prepare(params)
        R = self.R
        if len(R) != len(prepared.r0):
            R = prepared.r0
        elif not self.lesson.keep_level(params):
            # keep the state; if the surface changed, put the point back on it
            q = prepared.quadric
            if np.any(np.abs(q.F(R)) > 1e-9 * q.scale):
                R = np.array([q.project(p) for p in R])
        self.params, self.prepared = params, prepared
        self._start(self._t, R, prepared.model.F(R))

    def reset(self) -> Frame:
        self._start(0.0, self.prepared.r0, self.prepared.F0)
        return self.frame()

    @property
    def computing(self) -> bool:
        return self.traj.computing

    def advance(self, dt: float) -> Frame:
        """Move on by ``dt``, or less if the work budget runs out first
        (:meth:`Trajectory.reach`)."""
        if np.isfinite(dt) and dt > 0:
            self._t = max(self._t, self.traj.reach(self._t + dt))
            self.R = self.traj.at(self._t)[0]
        return self.frame()

    def frame(self) -> Frame:
        model = self.prepared.model
        R = self.R
        u, v, g = model.at_one(self._t, R)  # (1.50)/(1.59) and F_r/2 in plain floats
        live = {"r": R[None], "F0": self.F0.reshape(1, -1), "v": v[None], "u": u}
        message = ""
        if not np.all(v.any(axis=-1)):
            message = (
                "the field vanishes here (grad F is parallel to (u3, u2, u1)): ω = V/|field|"
                " (1.58) is undefined, the velocity is 0 at this instant"
                if model.controls.V is not None
                else "the analyzer field is zero here: the point does not move"
            )
        return Frame(
            t=self._t,
            points={"point": R.copy()},
            vectors={"velocity": (R.copy(), v), "gradient": (R.copy(), g)},
            scalars=self.lesson.frame_scalars(self.params, self._t, live),
            message=message,
        )
