"""Chapter 2, §2.1: dynamic models of coordinate positioners, Problems 2.1-2.5.

Every model is derived with ``sympy.physics.mechanics.LagrangesMethod`` from the kinetic
energy T, the potential energy U and the applied forces (the generalized forces are the
coefficients of the virtual work, (2.10)/(2.16)), then lambdified once.  Each lesson
solves the *forward* problem (forces given as formulas of t -> motion) and the *inverse*
problem (motion law given as formulas of t -> the drive forces), (2.1)-(2.16).

Problem 2.5 (six-DOF table) uses :mod:`lessons.core.table6dof`; its geometry is
reconstructed (the source gives it only in figures lost in the extraction).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

from lessons.core.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Lesson,
    MeshItem,
    Param,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Stepper,
    at_most,
    close,
)
from lessons.core.formula import Formula, FormulaError, t_symbol
from lessons.core.mechanics import (
    IDENTITY_Q,
    LagrangeModel,
    OdeStepper,
    ProgramStepper,
    bounds_of,
    box,
    combine,
    cylinder,
    formula_derivatives,
    integrate,
    numerical_second_derivative,
    quat_wxyz,
    quat_z,
    recover_inputs,
    sample_formulas,
    segment_pose,
)
from lessons.core.table6dof import (
    COORDS,
    FORCES,
    INDUCTORS,
    PHYSICAL,
    POSE,
    inverse_dynamics,
    inverse_kinematics,
    plane_through_joints,
    program_state,
    rotation,
    table_joints,
    table_model,
)

T_ = dynamicsymbols._t  # the time of the sympy models
Array = np.ndarray


def _sym(name: str, **kw: Any) -> sp.Symbol:
    return sp.Symbol(name, real=True, **kw)


def _is_zero(expr: sp.Expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


@dataclass(frozen=True)
class Coord:
    """A generalized coordinate: name (as in the textbook), unit, defaults."""

    name: str
    label: str
    unit: str
    q0: float = 0.0
    law: str = "0"


@dataclass(frozen=True)
class Input:
    """A force/moment entering the generalized forces; ``unknown``: solved for in the
    inverse problem (otherwise a given formula in both problems)."""

    name: str
    label: str
    unit: str
    default: str
    unknown: bool = True


PROBLEM = Param(
    "problem",
    "choice",
    "forward",
    label="problem",
    choices=("forward", "inverse"),
    group="method",
    help="forward: forces given, motion found; inverse: motion law given, drive forces found",
)


def positioner_params(
    coords: Sequence[Coord],
    inputs: Sequence[Input],
    physical: Sequence[Param],
    extra: Sequence[Param] = (),
) -> tuple[Param, ...]:
    out: list[Param] = [PROBLEM, *extra, *physical]
    for i in inputs:
        out.append(
            Param(
                i.name,
                "formula",
                i.default,
                label=i.label + " (t)",
                unit=i.unit,
                help="used in the forward problem"
                + ("" if i.unknown else " and the inverse problem"),
            )
        )
    for c in coords:
        out.append(
            Param(
                f"{c.name}_t",
                "formula",
                c.law,
                label=f"{c.label}(t) law",
                unit=c.unit,
                help="motion law of the inverse problem",
            )
        )
    for c in coords:
        out.append(
            Param(
                f"{c.name}0",
                "float",
                c.q0,
                label=f"{c.label}(0)",
                unit=c.unit,
                min=-1e3,
                max=1e3,
                group="initial",
            )
        )
        out.append(
            Param(
                f"{c.name}_dot0",
                "float",
                0.0,
                label=f"{c.label}'(0)",
                unit=f"{c.unit}/s",
                min=-1e3,
                max=1e3,
                group="initial",
            )
        )
    return tuple(out)


class PositionerLesson(Lesson):
    """Common machinery: forward/inverse runs on a :class:`LagrangeModel`."""

    chapter = "2"
    coords: tuple[Coord, ...] = ()
    inputs: tuple[Input, ...] = ()
    physical: tuple[str, ...] = ()  # model parameter names, in the model's order
    t_end = 10.0

    # -- model ------------------------------------------------------------------

    def model(self, params: Params) -> LagrangeModel:
        return _model_cache(type(self).__name__, self.model_key(params), self)

    def model_key(self, params: Params) -> str:
        return ""

    def build_model(self, key: str) -> LagrangeModel:  # pragma: no cover - abstract
        raise NotImplementedError

    def pvec(self, params: Params) -> Array:
        return np.array([float(params[n]) for n in self.physical], dtype=float)

    @property
    def unknown(self) -> list[int]:
        return [k for k, i in enumerate(self.inputs) if i.unknown]

    def y0(self, params: Params) -> Array:
        return np.array(
            [float(params[f"{c.name}0"]) for c in self.coords]
            + [float(params[f"{c.name}_dot0"]) for c in self.coords]
        )

    def formulas_in_use(self, params: Params) -> list[tuple[str, Formula]]:
        if params["problem"] == "forward":
            return [(i.name, params[i.name]) for i in self.inputs]
        return [(i.name, params[i.name]) for i in self.inputs if not i.unknown] + [
            (f"{c.name}_t", params[f"{c.name}_t"]) for c in self.coords
        ]

    def check_formulas(self, params: Params, t: Array) -> list[str]:
        msgs = []
        for name, f in self.formulas_in_use(params):
            try:
                f.check_finite(t)
            except FormulaError as exc:
                msgs.append(f"{name}: {exc}")
        return msgs

    # -- runs ---------------------------------------------------------------------

    def _u_of_t(self, params: Params) -> Callable[[float, Array, Array], Array]:
        fs = [params[i.name] for i in self.inputs]
        return lambda tt, q, qd: np.array([float(f(tt)) for f in fs])

    def _known_inputs(self, params: Params, t: Array) -> Array:
        U = np.zeros((len(self.inputs), len(t)))
        for k, i in enumerate(self.inputs):
            if not i.unknown:
                U[k] = np.broadcast_to(np.asarray(params[i.name](t), dtype=float), t.shape)
        return U

    def motion(self, params: Params, t: Array) -> tuple[Array, Array, Array, Array, str]:
        """``(q, q', q'', u)`` on the samples for the chosen problem, and a message."""
        model, p, n = self.model(params), self.pvec(params), len(self.coords)
        if params["problem"] == "forward":
            y, msg = integrate(model.rhs(p, self._u_of_t(params)), self.y0(params), t)
            q, qd = y[:n], y[n:]
            U = sample_formulas([params[i.name] for i in self.inputs], t)
            qdd = np.full_like(q, np.nan)
            for k in range(len(t)):
                if np.all(np.isfinite(y[:, k])):
                    qdd[:, k] = model.accelerations(q[:, k], qd[:, k], float(t[k]), p, U[:, k])
            return q, qd, qdd, U, msg
        ev = formula_derivatives([params[f"{c.name}_t"].expr for c in self.coords], t_symbol)
        q, qd, qdd = ev(t)
        U = self._known_inputs(params, t)
        for k in range(len(t)):
            U[:, k] = model.solve_inputs(
                q[:, k], qd[:, k], qdd[:, k], float(t[k]), p, U[:, k], self.unknown
            )
        return q, qd, qdd, U, ""

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        n_s = int(min(2001, max(201, 100 * t_end + 1)))
        t = np.linspace(0.0, t_end, n_s)
        msgs = self.check_formulas(params, t)
        if msgs:
            nan = np.full_like(t, np.nan)
            return RunResult(
                self.id,
                None,
                params.raw(),
                t,
                {k: nan for k in self.series_names()},
                {"ok": False},
                msgs,
            )
        q, qd, qdd, U, msg = self.motion(params, t)
        series = self.series(params, t, q, qd, qdd, U)
        metrics: dict[str, Any] = {"ok": not msg, "problem": params["problem"]}
        for k, c in enumerate(self.coords):
            metrics[f"{c.name}_end"] = float(q[k, -1])
        for k, i in enumerate(self.inputs):
            metrics[f"{i.name}_max_abs"] = (
                float(np.nanmax(np.abs(U[k]))) if np.any(np.isfinite(U[k])) else float("nan")
            )
        return RunResult(self.id, None, params.raw(), t, series, metrics, [msg] if msg else [])

    def series_names(self) -> list[str]:
        names = []
        for c in self.coords:
            names += [c.name, f"{c.name}_dot", f"{c.name}_ddot"]
        return names + [i.name for i in self.inputs] + list(self.extra_names())

    def extra_names(self) -> Sequence[str]:
        return ()

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        return {}

    def series(
        self, params: Params, t: Array, q: Array, qd: Array, qdd: Array, U: Array
    ) -> dict[str, Array]:
        out: dict[str, Array] = {}
        for k, c in enumerate(self.coords):
            out[c.name], out[f"{c.name}_dot"], out[f"{c.name}_ddot"] = q[k], qd[k], qdd[k]
        for k, i in enumerate(self.inputs):
            out[i.name] = U[k]
        out.update(self.extra_series(params, q, qd, qdd))
        return out

    # -- live -----------------------------------------------------------------------

    def force_scale(self, params: Params) -> float:
        """Arrow length per unit force: the largest force of a coarse run maps to
        a quarter of the scene size."""
        t = np.linspace(0.0, self.t_end, 101)
        try:
            if self.check_formulas(params, t):
                return 0.0
            if params["problem"] == "forward":
                U = sample_formulas([params[i.name] for i in self.inputs], t)
            else:
                _, _, _, U, _ = self.motion(params, t)
            fmax = float(np.nanmax(np.abs(U))) if np.any(np.isfinite(U)) else 0.0
        except (ValueError, np.linalg.LinAlgError):
            return 0.0
        return 0.25 * self.scene_size(params) / fmax if fmax > 0 else 0.0

    def scene_size(self, params: Params) -> float:
        return 1.0

    def frame_from(
        self, params: Params, t: float, q: Array, qd: Array, qdd: Array, u: Array, scale: float
    ) -> Frame:
        fr = Frame(t=float(t))
        for k, c in enumerate(self.coords):
            fr.scalars[c.name] = float(q[k])
            fr.scalars[f"{c.name}_dot"] = float(qd[k])
            fr.scalars[f"{c.name}_ddot"] = float(qdd[k])
        for k, i in enumerate(self.inputs):
            fr.scalars[i.name] = float(u[k])
        for name, v in self.extra_series(params, q[:, None], qd[:, None], qdd[:, None]).items():
            fr.scalars[name] = float(np.asarray(v).ravel()[0])
        self.pose_frame(params, fr, q, u, scale)
        return fr

    def pose_frame(
        self, params: Params, fr: Frame, q: Array, u: Array, scale: float
    ) -> None:  # pragma: no cover
        raise NotImplementedError

    def stepper(self, params: Params) -> Stepper:
        if params["problem"] == "forward":

            def make(
                ps: Params,
            ) -> tuple[Array, Callable[[float, Array], Array], Callable[[float, Array], Frame]]:
                model, p, n, scale = (
                    self.model(ps),
                    self.pvec(ps),
                    len(self.coords),
                    self.force_scale(ps),
                )
                u_of_t = self._u_of_t(ps)

                def frame_of(tt: float, y: Array) -> Frame:
                    u = u_of_t(tt, y[:n], y[n:])
                    with np.errstate(all="ignore"):
                        try:
                            qdd = model.accelerations(y[:n], y[n:], tt, p, u)
                        except np.linalg.LinAlgError:
                            qdd = np.full(n, np.nan)
                    return self.frame_from(ps, tt, y[:n], y[n:], qdd, u, scale)

                return self.y0(ps), model.rhs(p, u_of_t), frame_of

            return OdeStepper(make, params)

        def make_program(ps: Params) -> Callable[[float], Frame]:
            model, p, scale = self.model(ps), self.pvec(ps), self.force_scale(ps)
            ev = formula_derivatives([ps[f"{c.name}_t"].expr for c in self.coords], t_symbol)

            def frame_at(tt: float) -> Frame:
                q, qd, qdd = ev(float(tt))
                u = self._known_inputs(ps, np.array([tt]))[:, 0]
                msg = ""
                if np.all(np.isfinite(np.concatenate([q, qd, qdd, u]))):
                    u = model.solve_inputs(q, qd, qdd, float(tt), p, u, self.unknown)
                else:
                    msg = f"the motion law is not finite at t = {tt:g}"
                fr = self.frame_from(ps, tt, q, qd, qdd, u, scale)
                fr.message = msg
                return fr

            return frame_at

        return ProgramStepper(make_program, params)

    # -- claims support ---------------------------------------------------------------

    def round_trip_error(self, values: dict[str, Any], t_end: float = 5.0) -> tuple[float, float]:
        """Forward run with the given forces, then the inverse problem on the sampled
        motion (accelerations by differences): ``(max |u_rec - u|, max |u|)`` over the
        unknown inputs, away from the two end samples."""
        params = self.resolve({**values, "problem": "forward"})
        t = np.linspace(0.0, t_end, 2001)
        q, qd, _, U, _ = self.motion(params, t)
        known = U.copy()
        rec = recover_inputs(self.model(params), t, q, qd, self.pvec(params), known, self.unknown)
        idx = self.unknown
        err = float(np.max(np.abs(rec[idx, 2:-2] - U[idx, 2:-2])))
        return err, float(np.max(np.abs(U[idx])))

    def inverse_forward_error(self, values: dict[str, Any], t_end: float = 5.0) -> float:
        """Inverse problem on a motion law, then the forward problem driven by the
        forces found (interpolated): max |q_forward - q_law| over the coordinates."""
        params = self.resolve({**values, "problem": "inverse"})
        t = np.linspace(0.0, t_end, 4001)
        q_law, qd_law, _, _, _ = self.motion(params, t)
        model, p, n = self.model(params), self.pvec(params), len(self.coords)
        # the forces are the inverse problem solved at each evaluation instant
        ev = formula_derivatives([params[f"{c.name}_t"].expr for c in self.coords], t_symbol)

        def u_exact(tt: float, q: Array, qd: Array) -> Array:
            ql, qdl, qddl = ev(tt)
            u0 = self._known_inputs(params, np.array([tt]))[:, 0]
            return model.solve_inputs(ql, qdl, qddl, tt, p, u0, self.unknown)

        y0 = np.concatenate([q_law[:, 0], qd_law[:, 0]])
        y, _ = integrate(model.rhs(p, u_exact), y0, t[::40])
        return float(np.max(np.abs(y[:n] - q_law[:, ::40])))


_MODELS: dict[tuple[str, str], LagrangeModel] = {}
_RUNS: dict[tuple[str, str], RunResult] = {}


def _coarse_run(lesson: PositionerLesson, params: Params) -> RunResult:
    """A run over the lesson's default time, cached by parameter values (scene extents)."""
    key = (lesson.id, repr(sorted(params.raw().items())))
    if key not in _RUNS:
        if len(_RUNS) > 64:
            _RUNS.clear()
        _RUNS[key] = lesson.simulate(params, lesson.t_end)
    return _RUNS[key]


def _model_cache(cls_name: str, key: str, lesson: PositionerLesson) -> LagrangeModel:
    k = (cls_name, key)
    if k not in _MODELS:
        _MODELS[k] = lesson.build_model(key)
    return _MODELS[k]


def _claim(id_: str, statement: str, source: str, check: Callable[[], ClaimResult]) -> Claim:
    return Claim(id=id_, statement=statement, source=source, check=check)


def _symbolic_claim(ok: Callable[[], bool], what: str) -> Callable[[], ClaimResult]:
    def check() -> ClaimResult:
        passed = bool(ok())
        return ClaimResult(
            expected=f"{what}: simplify(difference) == 0",
            got="0" if passed else "non-zero",
            passed=passed,
        )

    return check


def _arrow(origin: Sequence[float], direction: Sequence[float]) -> tuple[Array, Array]:
    return np.asarray([origin], dtype=float), np.asarray([direction], dtype=float)


# =============================================================================== Problem 2.1


class LinearPositioner(PositionerLesson):
    """Problem 2.1: d'Alembert (2.1) projected on X gives M x'' = sum F_x^A + sum N_x (2.2)."""

    id = "linear-positioner"
    title = "Single-coordinate linear positioner"
    problem = "Problem 2.1"
    source = "Textbook §2.1, Problem 2.1, eqs (2.1)-(2.2)"
    summary = (
        "A carriage on a straight guide: M x'' = F_dv - R_sopr + N_x; forward and inverse problems."
    )
    order = 2.01
    coords = (Coord("x", "x", "m", 0.0, "0.1*(1 - cos(pi*t/2))"),)
    inputs = (
        Input("F_dv", "driving force F_dv", "N", "2 + sin(3*t)"),
        Input("R_sopr", "resistance force R_sopr", "N", "0.5", unknown=False),
        Input("N_x", "reaction N_x (0 for ideal guides)", "N", "0", unknown=False),
    )
    physical = ("M",)
    params = positioner_params(
        coords,
        inputs,
        (Param("M", "float", 5.0, label="moving mass M", unit="kg", min=1e-3, max=1e4),),
    )
    presets = (
        Preset(
            "forward-constant-force",
            "Forward: constant drive 2 N against 0.5 N resistance",
            {"problem": "forward", "F_dv": "2", "R_sopr": "0.5"},
            t_end=10.0,
        ),
        Preset(
            "forward-harmonic", "Forward: F_dv = 2 + sin 3t", {"problem": "forward"}, t_end=10.0
        ),
        Preset(
            "inverse-cosine-move",
            "Inverse: x = 0.1 (1 - cos(pi t/2)) m",
            {"problem": "inverse"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Coordinate", ("x",), "m"),
        PlotSpec("Velocity", ("x_dot",), "m/s"),
        PlotSpec("Forces", ("F_dv", "R_sopr", "N_x"), "N"),
    )

    def build_model(self, key: str) -> LagrangeModel:
        x = dynamicsymbols("x")
        M, F, R, Nx = _sym("M", positive=True), _sym("F_dv"), _sym("R_sopr"), _sym("N_x")
        N = ReferenceFrame("N")
        P = Point("P")
        P.set_vel(N, x.diff(T_) * N.x)
        T = M * x.diff(T_) ** 2 / 2
        return LagrangeModel.build(
            [x], T, sp.S.Zero, T_, [M], [F, R, Nx], forcelist=[(P, (F - R + Nx) * N.x)], frame=N
        )

    def textbook_eq(self) -> sp.Expr:
        x = dynamicsymbols("x")
        M, F, R, Nx = _sym("M", positive=True), _sym("F_dv"), _sym("R_sopr"), _sym("N_x")
        return M * x.diff(T_, 2) - (F - R + Nx)

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        x = m.q[0]
        M, F, R, Nx = m.params[0], *m.inputs
        steps = [
            DerivationStep(
                "d'Alembert principle",
                "Active forces, constraint reactions and inertia forces are in equilibrium.",
                r"\sum \vec F^{A}+\sum \vec N-\sum m_i\vec a_i=0",
                "(2.1)",
            ),
            DerivationStep(
                "Kinetic energy",
                "All points have the same acceleration, so the moving mass M = sum m_i acts as one body.",
                sp.Eq(sp.Symbol("T"), M * x.diff(T_) ** 2 / 2),
            ),
            DerivationStep(
                "Generalized force",
                "Virtual work of the drive, the resistance and the guide reaction on dx.",
                sp.Eq(sp.Symbol("Q_x"), F - R + Nx),
                "(2.2)",
            ),
            DerivationStep(
                "Equation of motion (LagrangesMethod)",
                "Projection on the X axis.",
                m.equations()[0],
                "(2.2)",
            ),
        ]
        if params["problem"] == "forward":
            steps.append(
                DerivationStep(
                    "Forward problem",
                    "Forces known: the acceleration, then the motion by integration.",
                    sp.Eq(x.diff(T_, 2), (F - R + Nx) / M),
                )
            )
        else:
            law = params["x_t"].expr.subs(t_symbol, T_)
            steps.append(
                DerivationStep(
                    "Inverse problem",
                    "Motion law given: the drive force it needs.",
                    sp.Eq(F, sp.simplify(M * sp.diff(law, T_, 2) + R - Nx)),
                    "(2.2)",
                )
            )
        return steps

    def scene_size(self, params: Params) -> float:
        lo, hi = self._range(params)
        return max(hi - lo, 0.5)

    def _range(self, params: Params) -> tuple[float, float]:
        r = _coarse_run(self, params)
        x = r.series["x"]
        x = x[np.isfinite(x)]
        return (float(x.min()), float(x.max())) if len(x) else (0.0, 1.0)

    def scene(self, params: Params) -> SceneSpec:
        lo, hi = self._range(params)
        span = max(hi - lo, 0.5)
        s = 0.15 * span
        rail = box(
            "guide",
            (span + 2 * s, 0.4 * s, 0.2 * s),
            (90, 90, 90),
            center=((lo + hi) / 2, 0, -0.1 * s),
        )
        carriage = box(
            "carriage", (s, 0.8 * s, 0.5 * s), (70, 130, 200)
        )  # posed 0.25 s above the guide
        pts = np.array([[lo - s, -s, -s], [hi + s, s, s]])
        return SceneSpec(
            bounds=bounds_of(pts),
            meshes=[rail],
            bodies=[carriage],
            moving_vectors={"F_dv": (40, 160, 60), "R_sopr": (200, 60, 60)},
            moving_points={"carriage": (70, 130, 200)},
        )

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        x = float(q[0])
        s = 0.15 * self.scene_size(params)
        p = np.array([x, 0.0, 0.0])
        fr.poses["carriage"] = (p + [0, 0, 0.25 * s], IDENTITY_Q.copy())
        fr.points["carriage"] = p[None, :]
        fr.vectors["F_dv"] = _arrow(p + [0, 0, 0.6 * s], [scale * u[0], 0, 0])
        fr.vectors["R_sopr"] = _arrow(p + [0, 0, 0.6 * s], [-scale * u[1], 0, 0])

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            return _is_zero(m.eom()[0] - self.textbook_eq())

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error({"M": 5.0, "F_dv": "2 + sin(3*t)", "R_sopr": "0.5"})
            return at_most(1e-4 * fmax, err, "max |F_dv recovered - F_dv| ")

        def inv_fwd() -> ClaimResult:
            return at_most(
                1e-8, self.inverse_forward_error({"M": 5.0}), "max |x forward - x law| (m) "
            )

        def constant_force() -> ClaimResult:
            r = self.run("forward-constant-force")
            return close(1.5 / 5.0 * 10.0**2 / 2, float(r.series["x"][-1]), rtol=1e-8)

        return [
            _claim(
                "eq-2.2",
                "LagrangesMethod with T = M x'^2/2 and Q_x = F_dv - R_sopr + N_x gives (2.2): M x'' = F_dv - R_sopr + N_x",
                "(2.2)",
                _symbolic_claim(eq_ok, "(2.2)"),
            ),
            _claim(
                "forward-constant",
                "Forward: F_dv = 2 N, R_sopr = 0.5 N, M = 5 kg from rest: x(10) = (1.5/5) 10^2/2 = 15 m",
                "(2.2)",
                constant_force,
            ),
            _claim(
                "round-trip-forward-inverse",
                "Forward then inverse recovers the drive force F_dv = 2 + sin 3t (within 1e-4 of its peak)",
                "(2.2)",
                round_trip,
            ),
            _claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces the law x = 0.1(1 - cos(pi t/2)) to 1e-8 m",
                "(2.2)",
                inv_fwd,
            ),
        ]


# =============================================================================== Problem 2.2


class RotaryPositioner(PositionerLesson):
    """Problem 2.2: J_z,pr phi'' = sum M_z(F^e) (2.3), J_z,pr = sum m_i h_i^2 (2.4)."""

    id = "rotary-positioner"
    title = "Rotary positioner"
    problem = "Problem 2.2"
    source = "Textbook §2.1, Problem 2.2, eqs (2.3)-(2.4)"
    summary = (
        "Three masses m_i at distances h_i from the axis Z: (sum m_i h_i^2) phi'' = M_dv - M_c."
    )
    order = 2.02
    coords = (Coord("phi", "phi", "rad", 0.0, "pi/2*(t - sin(t))/(2*pi)"),)
    inputs = (
        Input("M_dv", "drive moment M_dv", "N m", "0.2*sin(t)"),
        Input("M_c", "resisting moment M_c", "N m", "0", unknown=False),
    )
    physical = ("m1", "h1", "m2", "h2", "m3", "h3")
    params = positioner_params(
        coords,
        inputs,
        (
            Param("m1", "float", 1.0, label="m1", unit="kg", min=0.0, max=1e3),
            Param("h1", "float", 0.2, label="h1", unit="m", min=0.0, max=10.0),
            Param("m2", "float", 0.5, label="m2", unit="kg", min=0.0, max=1e3),
            Param("h2", "float", 0.3, label="h2", unit="m", min=0.0, max=10.0),
            Param("m3", "float", 2.0, label="m3", unit="kg", min=0.0, max=1e3),
            Param("h3", "float", 0.1, label="h3", unit="m", min=0.0, max=10.0),
        ),
    )
    presets = (
        Preset(
            "forward-harmonic-moment",
            "Forward: M_dv = 0.2 sin t",
            {"problem": "forward"},
            t_end=10.0,
        ),
        Preset(
            "forward-constant-moment",
            "Forward: M_dv = 0.1 N m, M_c = 0.02 N m",
            {"problem": "forward", "M_dv": "0.1", "M_c": "0.02"},
            t_end=5.0,
        ),
        Preset(
            "inverse-quarter-turn",
            "Inverse: a smooth quarter turn per 2 pi s",
            {"problem": "inverse"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Angle", ("phi",), "rad"),
        PlotSpec("Angular velocity", ("phi_dot",), "rad/s"),
        PlotSpec("Moments", ("M_dv", "M_c"), "N m"),
    )

    def validate(self, params: Params) -> None:
        J = sum(float(params[f"m{i}"]) * float(params[f"h{i}"]) ** 2 for i in (1, 2, 3))
        if J <= 0:
            from lessons.core.contract import ParamError

            raise ParamError(
                "m1",
                "the reduced moment of inertia sum m_i h_i^2 is zero: give some mass a non-zero radius",
            )

    def build_model(self, key: str) -> LagrangeModel:
        phi = dynamicsymbols("phi")
        ms = [_sym(f"m{i}", nonnegative=True) for i in (1, 2, 3)]
        hs = [_sym(f"h{i}", nonnegative=True) for i in (1, 2, 3)]
        Md, Mc = _sym("M_dv"), _sym("M_c")
        N = ReferenceFrame("N")
        R = N.orientnew("R", "Axis", [phi, N.z])
        R.set_ang_vel(N, phi.diff(T_) * N.z)
        O = Point("O")
        O.set_vel(N, 0)
        T = sp.S.Zero
        for k, (m, h) in enumerate(zip(ms, hs)):
            ang = 2 * sp.pi * k / 3
            P = O.locatenew(f"P{k}", h * (sp.cos(ang) * R.x + sp.sin(ang) * R.y))
            P.v2pt_theory(O, N, R)
            T += m * P.vel(N).dot(P.vel(N)) / 2
        return LagrangeModel.build(
            [phi],
            sp.simplify(T),
            sp.S.Zero,
            T_,
            [*[v for pair in zip(ms, hs) for v in pair]],
            [Md, Mc],
            forcelist=[(R, (Md - Mc) * N.z)],
            frame=N,
        )

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        phi = m.q[0]
        ms = [m.params[0], m.params[2], m.params[4]]
        hs = [m.params[1], m.params[3], m.params[5]]
        J = sp.Symbol(r"J_{z\,pr}")
        Md, Mc = m.inputs
        steps = [
            DerivationStep(
                "Kinetic energy of the rotating masses",
                "Each point M_i moves on a circle of radius h_i about Z.",
                sp.Eq(sp.Symbol("T"), m.lagrangian),
            ),
            DerivationStep(
                "Reduced moment of inertia",
                "",
                sp.Eq(J, sum(mi * hi**2 for mi, hi in zip(ms, hs))),
                "(2.3)",
            ),
            DerivationStep(
                "Equation of rotation (LagrangesMethod)",
                "Moment of the drive and the resistance about Z.",
                m.equations()[0],
                "(2.4)",
            ),
        ]
        if params["problem"] == "inverse":
            law = params["phi_t"].expr.subs(t_symbol, T_)
            steps.append(
                DerivationStep(
                    "Inverse problem",
                    "The drive moment the law needs.",
                    sp.Eq(
                        Md,
                        sp.simplify(
                            sum(mi * hi**2 for mi, hi in zip(ms, hs)) * sp.diff(law, T_, 2) + Mc
                        ),
                    ),
                    "(2.4)",
                )
            )
        else:
            steps.append(
                DerivationStep(
                    "Forward problem", "", sp.Eq(phi.diff(T_, 2), (Md - Mc) / J), "(2.3)"
                )
            )
        return steps

    def scene_size(self, params: Params) -> float:
        return 2.6 * max(float(params[f"h{i}"]) for i in (1, 2, 3))

    def scene(self, params: Params) -> SceneSpec:
        R = max(float(params[f"h{i}"]) for i in (1, 2, 3))
        parts = [trimesh.creation.cylinder(radius=0.08 * R, height=0.2 * R)]
        for k in range(3):
            h = float(params[f"h{k + 1}"])
            ang = 2 * np.pi * k / 3
            c = np.array([np.cos(ang), np.sin(ang), 0.0])
            if h > 0:
                arm = trimesh.creation.box(extents=[h, 0.03 * R, 0.03 * R])
                arm.apply_transform(trimesh.transformations.rotation_matrix(ang, [0, 0, 1]))
                arm.apply_translation(c * h / 2)
                parts.append(arm)
            ball = trimesh.creation.icosphere(
                subdivisions=2, radius=0.04 * R * (1 + float(params[f"m{k + 1}"])) ** (1 / 3)
            )
            ball.apply_translation(c * h)
            parts.append(ball)
        rotor = combine("rotor", parts, (200, 140, 60))
        axis = cylinder("axis Z", 0.01 * R, 1.2 * R, (60, 60, 60))
        pts = np.array([[-1.3 * R, -1.3 * R, -0.6 * R], [1.3 * R, 1.3 * R, 0.8 * R]])
        return SceneSpec(
            bounds=bounds_of(pts, 0.02),
            meshes=[axis],
            bodies=[rotor],
            moving_vectors={"M_dv": (40, 160, 60), "M_c": (200, 60, 60)},
            moving_points={"M1": (200, 60, 60)},
        )

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        phi = float(q[0])
        R = max(float(params[f"h{i}"]) for i in (1, 2, 3))
        fr.poses["rotor"] = (np.zeros(3), quat_z(phi))
        h1 = float(params["h1"])
        fr.points["M1"] = np.array([[h1 * np.cos(phi), h1 * np.sin(phi), 0.0]])
        fr.vectors["M_dv"] = _arrow([0, 0, 0.15 * R], [0, 0, scale * u[0]])
        fr.vectors["M_c"] = _arrow([0.02 * R, 0, 0.15 * R], [0, 0, -scale * u[1]])

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            phi = m.q[0]
            J = sum(m.params[2 * k] * m.params[2 * k + 1] ** 2 for k in range(3))
            return _is_zero(m.eom()[0] - (J * phi.diff(T_, 2) - (m.inputs[0] - m.inputs[1])))

        def constant() -> ClaimResult:
            r = self.run("forward-constant-moment")
            J = 1.0 * 0.04 + 0.5 * 0.09 + 2.0 * 0.01
            return close(0.08 / J * 25 / 2, float(r.series["phi"][-1]), rtol=1e-8)

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error({"M_dv": "0.2*sin(t)", "M_c": "0.01"})
            return at_most(1e-4 * fmax, err, "max |M_dv recovered - M_dv| ")

        def inv_fwd() -> ClaimResult:
            return at_most(
                1e-8, self.inverse_forward_error({}), "max |phi forward - phi law| (rad) "
            )

        return [
            _claim(
                "eq-2.3-2.4",
                "LagrangesMethod on three point masses gives (sum m_i h_i^2) phi'' = M_dv - M_c, i.e. J_z,pr = sum m_i h_i^2",
                "(2.3)-(2.4)",
                _symbolic_claim(eq_ok, "(2.4)"),
            ),
            _claim(
                "forward-constant",
                "Forward: M_dv - M_c = 0.08 N m on J = 0.105 kg m^2 from rest: phi(5) = 0.08/0.105 * 25/2 = 9.524 rad",
                "(2.3)",
                constant,
            ),
            _claim(
                "round-trip-forward-inverse",
                "Forward then inverse recovers M_dv = 0.2 sin t (within 1e-4 of its peak)",
                "(2.4)",
                round_trip,
            ),
            _claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces the law phi(t) to 1e-8 rad",
                "(2.4)",
                inv_fwd,
            ),
        ]


# =============================================================================== Problem 2.3


class Planar2Axis(PositionerLesson):
    """Problem 2.3: Lagrange equations (2.5) with T = M (x'^2 + y'^2)/2 (2.6)-(2.7), U by
    layout (2.8)/(2.9), Q by virtual work (2.10) -> corrected (2.11)."""

    id = "planar-2axis"
    title = "Two-coordinate planar positioner"
    problem = "Problem 2.3"
    source = "Textbook §2.1, Problem 2.3, eqs (2.5)-(2.11')"
    summary = "An X-Y stage, horizontal (U = 0) or vertical (U = M g y): M x'' = -dU/dx + Q_x, M y'' = -dU/dy + Q_y."
    order = 2.03
    coords = (Coord("x", "x", "m", 0.0, "0.2*sin(t)"), Coord("y", "y", "m", 0.0, "0.1*sin(2*t)"))
    inputs = (
        Input("Q_x", "force along X, Q_x", "N", "2*cos(t)"),
        Input("Q_y", "force along Y, Q_y", "N", "sin(2*t)"),
    )
    physical = ("M", "g")
    params = positioner_params(
        coords,
        inputs,
        (
            Param("M", "float", 4.0, label="total moving mass M", unit="kg", min=1e-3, max=1e4),
            Param("g", "float", 9.81, label="g", unit="m/s^2", min=0.0, max=100.0),
        ),
        extra=(
            Param(
                "layout",
                "choice",
                "horizontal",
                label="layout",
                choices=("horizontal", "vertical"),
                group="method",
                help="vertical: the Y axis points up and U = M g y (2.9)",
            ),
        ),
    )
    presets = (
        Preset(
            "forward-horizontal",
            "Forward, horizontal: Q_x = 2 cos t, Q_y = sin 2t",
            {"problem": "forward", "layout": "horizontal"},
            t_end=10.0,
        ),
        Preset(
            "forward-vertical-hold",
            "Forward, vertical: Q_y = M g holds the weight",
            {"problem": "forward", "layout": "vertical", "Q_x": "2*cos(t)", "Q_y": "4*9.81"},
            t_end=10.0,
        ),
        Preset(
            "inverse-vertical-figure-eight",
            "Inverse, vertical: x = 0.2 sin t, y = 0.1 sin 2t",
            {"problem": "inverse", "layout": "vertical"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Coordinates", ("x", "y"), "m"),
        PlotSpec("Speed", ("x_dot", "y_dot", "v"), "m/s"),
        PlotSpec("Forces", ("Q_x", "Q_y"), "N"),
    )

    def model_key(self, params: Params) -> str:
        return str(params["layout"])

    def build_model(self, key: str) -> LagrangeModel:
        x, y = dynamicsymbols("x y")
        M, g = _sym("M", positive=True), _sym("g", nonnegative=True)
        Qx, Qy = _sym("Q_x"), _sym("Q_y")
        N = ReferenceFrame("N")
        P = Point("P")
        P.set_vel(N, x.diff(T_) * N.x + y.diff(T_) * N.y)
        T = M * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2
        U = M * g * y if key == "vertical" else sp.S.Zero
        return LagrangeModel.build(
            [x, y], T, U, T_, [M, g], [Qx, Qy], forcelist=[(P, Qx * N.x + Qy * N.y)], frame=N
        )

    def extra_names(self) -> Sequence[str]:
        return ("v", "a")

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        return {"v": np.hypot(qd[0], qd[1]), "a": np.hypot(qdd[0], qdd[1])}

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        x, y = m.q
        M, g = m.params
        T, U = sp.Symbol("T"), sp.Symbol("U")
        vert = params["layout"] == "vertical"
        steps = [
            DerivationStep(
                "Speed and acceleration",
                "",
                [
                    sp.Eq(sp.Symbol("v"), sp.sqrt(x.diff(T_) ** 2 + y.diff(T_) ** 2)),
                    sp.Eq(sp.Symbol("a"), sp.sqrt(x.diff(T_, 2) ** 2 + y.diff(T_, 2) ** 2)),
                ],
            ),
            DerivationStep(
                "Lagrange equations of the 2nd kind",
                "q1 = x, q2 = y.",
                r"\frac{d}{dt}\frac{\partial T}{\partial \dot q}-\frac{\partial T}{\partial q}=-\frac{\partial U}{\partial q}+Q_q,\quad q\in\{x,y\}",
                "(2.5)",
            ),
            DerivationStep(
                "Kinetic energy",
                "All points of the stage share the velocity (x', y').",
                sp.Eq(T, M * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2),
                "(2.6)-(2.7)",
            ),
            DerivationStep(
                "Potential energy",
                "Vertical layout: Y up, U = M g y (2.9)."
                if vert
                else "Horizontal layout: dU/dx = dU/dy = 0 (2.8).",
                sp.Eq(U, M * g * y if vert else 0),
                "(2.9)" if vert else "(2.8)",
            ),
            DerivationStep(
                "Generalized forces",
                "Coefficients of the virtual displacements in the virtual work.",
                r"Q_x=\frac{\delta A}{\delta x},\qquad Q_y=\frac{\delta A}{\delta y}",
                "(2.10)",
            ),
            DerivationStep(
                "Equations of motion (LagrangesMethod)",
                "The printed y-row has dU/dx, dA/dx (typo) and (2.11') a minus before dA: the corrected form is shown.",
                m.equations(),
                "(2.11)",
                reconstructed="corrected: y-row uses dU/dy and Q_y = dA/dy; sign + before dA as in (2.11)",
            ),
        ]
        if params["problem"] == "inverse":
            Qx, Qy = m.inputs
            lx = params["x_t"].expr.subs(t_symbol, T_)
            ly = params["y_t"].expr.subs(t_symbol, T_)
            steps.append(
                DerivationStep(
                    "Inverse problem",
                    "",
                    [
                        sp.Eq(Qx, sp.simplify(M * sp.diff(lx, T_, 2))),
                        sp.Eq(Qy, sp.simplify(M * sp.diff(ly, T_, 2) + (M * g if vert else 0))),
                    ],
                    "(2.11)",
                )
            )
        return steps

    def _world(self, params: Params, x: Array | float, y: Array | float) -> Array:
        if params["layout"] == "vertical":
            return np.array([x, 0.0 * np.asarray(x), y], dtype=float).T
        return np.array([x, y, 0.0 * np.asarray(x)], dtype=float).T

    def scene_size(self, params: Params) -> float:
        return self._extent(params)[2]

    def _extent(self, params: Params) -> tuple[Array, Array, float]:
        r = _coarse_run(self, params)
        pts = self._world(params, r.series["x"], r.series["y"])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 0:
            pts = np.zeros((1, 3))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        return lo, hi, max(float(np.max(hi - lo)), 0.5)

    def scene(self, params: Params) -> SceneSpec:
        lo, hi, span = self._extent(params)
        s = 0.1 * span
        vert = params["layout"] == "vertical"
        c = (lo + hi) / 2
        L = hi - lo + 3 * s
        if vert:
            base = box(
                "base plate",
                (L[0], 0.2 * s, L[2]),
                (150, 150, 150),
                center=(c[0], -0.4 * s, c[2]),
                opacity=0.5,
            )
            slide = box("X slide", (0.6 * s, 0.3 * s, L[2]), (90, 120, 170))
            carriage = box("Y carriage", (s, 0.5 * s, s), (70, 160, 210))
        else:
            base = box(
                "base plate",
                (L[0], L[1], 0.2 * s),
                (150, 150, 150),
                center=(c[0], c[1], -0.4 * s),
                opacity=0.5,
            )
            slide = box("X slide", (0.6 * s, L[1], 0.3 * s), (90, 120, 170))
            carriage = box("Y carriage", (s, s, 0.5 * s), (70, 160, 210))
        pts = np.array([lo - 2 * s, hi + 2 * s])
        return SceneSpec(
            bounds=bounds_of(pts, 0.02),
            meshes=[base],
            bodies=[slide, carriage],
            moving_points={"carriage": (70, 160, 210)},
            moving_vectors={"Q": (40, 160, 60), "weight": (200, 60, 60)},
            planar=False,
        )

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        p = self._world(params, float(q[0]), float(q[1]))
        lo, hi, _ = self._extent(params)
        c = (lo + hi) / 2
        vert = params["layout"] == "vertical"
        slide_pos = np.array([p[0], 0.0, c[2]]) if vert else np.array([p[0], c[1], 0.0])
        fr.poses["X slide"] = (slide_pos, IDENTITY_Q.copy())
        fr.poses["Y carriage"] = (p.copy(), IDENTITY_Q.copy())
        fr.points["carriage"] = p[None, :]
        F = self._world(params, scale * float(u[0]), scale * float(u[1]))
        fr.vectors["Q"] = _arrow(p, F)
        w = float(params["M"]) * float(params["g"]) * scale if vert else 0.0
        fr.vectors["weight"] = _arrow(p, [0, 0, -w])

    def claims(self) -> list[Claim]:
        def eq_ok(layout: str) -> Callable[[], bool]:
            def ok() -> bool:
                m = self.model(self.resolve({"layout": layout}))
                x, y = m.q
                M, g = m.params
                Qx, Qy = m.inputs
                dUdy = M * g if layout == "vertical" else 0
                return _is_zero(m.eom()[0] - (M * x.diff(T_, 2) - Qx)) and _is_zero(
                    m.eom()[1] - (M * y.diff(T_, 2) + dUdy - Qy)
                )

            return ok

        def hold() -> ClaimResult:
            r = self.run("forward-vertical-hold")
            return at_most(
                1e-9,
                float(np.max(np.abs(r.series["y"]))),
                "vertical stage with Q_y = M g: max |y| (m) ",
            )

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error(
                {"layout": "vertical", "Q_x": "2*cos(t)", "Q_y": "40 + sin(2*t)"}
            )
            return at_most(1e-4 * fmax, err, "max |Q recovered - Q| ")

        def inv_fwd() -> ClaimResult:
            return at_most(
                1e-8,
                self.inverse_forward_error({"layout": "vertical"}),
                "max |q forward - q law| (m) ",
            )

        def inverse_weight() -> ClaimResult:
            r = self.run("inverse-vertical-figure-eight")
            t = r.t
            expected = 4.0 * (-0.4 * np.sin(2 * t)) + 4.0 * 9.81
            return at_most(
                1e-9,
                float(np.max(np.abs(r.series["Q_y"] - expected))),
                "max |Q_y - (M y'' + M g)| (N) ",
            )

        return [
            _claim(
                "eq-2.11-horizontal",
                "Horizontal layout (2.8): LagrangesMethod gives M x'' = Q_x, M y'' = Q_y",
                "(2.11)",
                _symbolic_claim(eq_ok("horizontal"), "(2.11), U = 0"),
            ),
            _claim(
                "eq-2.11-vertical",
                "Vertical layout (2.9), U = M g y: M x'' = Q_x, M y'' = -M g + Q_y (corrected (2.11))",
                "(2.11)",
                _symbolic_claim(eq_ok("vertical"), "(2.11), U = M g y"),
            ),
            _claim(
                "vertical-hold",
                "Vertical stage: Q_y = M g keeps y = 0 (dU/dy balanced)",
                "(2.9), (2.11)",
                hold,
            ),
            _claim(
                "inverse-weight",
                "Inverse, vertical: Q_y(t) = M y'' + M g for y = 0.1 sin 2t",
                "(2.11)",
                inverse_weight,
            ),
            _claim(
                "round-trip-forward-inverse",
                "Forward then inverse recovers Q_x = 2 cos t, Q_y = 40 + sin 2t (within 1e-4 of the peak)",
                "(2.11)",
                round_trip,
            ),
            _claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces x = 0.2 sin t, y = 0.1 sin 2t to 1e-8 m",
                "(2.11)",
                inv_fwd,
            ),
        ]


# =============================================================================== Problem 2.4


def planar3_kinematics(xA: Any, yA: Any, phi: Any, AB: Any, lib: Any = sp) -> tuple[Any, Any]:
    """Module-B coordinates (2.12): x_B = x_A + AB (1 - cos phi), y_B = y_A + AB sin phi."""
    return xA + AB * (1 - lib.cos(phi)), yA + AB * lib.sin(phi)


def planar3_phi(
    xA: float, yA: float, xB: float, yB: float, AB: float
) -> tuple[float, float, float]:
    """Inverse of (2.12): arcsin form, arccos form and the full-range atan2 form."""
    return (
        float(np.arcsin((yB - yA) / AB)),
        float(np.arccos(1 - (xB - xA) / AB)),
        float(np.arctan2(yB - yA, AB - (xB - xA))),
    )


def planar3_symbols() -> dict[str, Any]:
    xA, yA, phi = dynamicsymbols("x_A y_A phi")
    mA, mB, mAB, J, AB = (_sym(n, positive=True) for n in ("m_A", "m_B", "m_AB", "J_A", "AB"))
    FAx, FAy, FBx, FBy, Mphi = (_sym(n) for n in ("F_Ax", "F_Ay", "F_Bx", "F_By", "M_phi"))
    return dict(
        xA=xA,
        yA=yA,
        phi=phi,
        mA=mA,
        mB=mB,
        mAB=mAB,
        J=J,
        AB=AB,
        FAx=FAx,
        FAy=FAy,
        FBx=FBx,
        FBy=FBy,
        Mphi=Mphi,
    )


class Planar3Axis(PositionerLesson):
    """Problem 2.4 as the consistent 3-DOF model q = (x_A, y_A, phi): (2.12)-(2.16) with
    the reconstructed T (2.15) and (2.12) substituted (DESIGN §3 item 8)."""

    id = "planar-3axis"
    title = "Three-coordinate planar motion system"
    problem = "Problem 2.4"
    source = "Textbook §2.1, Problem 2.4, eqs (2.12)-(2.16)"
    summary = "Two planar modules A and B carry a table that translates and turns by phi; consistent model in x_A, y_A, phi."
    order = 2.04
    coords = (
        Coord("x_A", "x_A", "m", 0.0, "0.1*sin(t)"),
        Coord("y_A", "y_A", "m", 0.0, "0.05*(1 - cos(t))"),
        Coord("phi", "phi", "rad", 0.0, "0.3*sin(t/2)"),
    )
    inputs = (
        Input("F_Ax", "module A force F_Ax", "N", "2*sin(t)"),
        Input("F_Ay", "module A force F_Ay", "N", "1"),
        Input("F_Bx", "module B force F_Bx", "N", "0", unknown=False),
        Input("F_By", "module B force F_By", "N", "0.5*cos(t)", unknown=False),
        Input("M_phi", "table moment M_phi", "N m", "0"),
    )
    physical = ("m_A", "m_B", "m_AB", "J_A", "AB")
    params = positioner_params(
        coords,
        inputs,
        (
            Param("m_A", "float", 2.0, label="module A mass m_A", unit="kg", min=1e-3, max=1e4),
            Param("m_B", "float", 1.5, label="module B mass m_B", unit="kg", min=1e-3, max=1e4),
            Param("m_AB", "float", 3.0, label="table mass m_AB", unit="kg", min=0.0, max=1e4),
            Param(
                "J_A",
                "float",
                0.4,
                label="table inertia about A, J_A,pr",
                unit="kg m^2",
                min=1e-6,
                max=1e4,
            ),
            Param("AB", "float", 0.5, label="distance AB", unit="m", min=1e-3, max=100.0),
        ),
    )
    presets = (
        Preset(
            "forward-drives",
            "Forward: drives on A, B pushes along Y",
            {"problem": "forward"},
            t_end=10.0,
        ),
        Preset(
            "inverse-program",
            "Inverse: x_A = 0.1 sin t, y_A = 0.05 (1 - cos t), phi = 0.3 sin(t/2); F_B = 0",
            {"problem": "inverse", "F_By": "0"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Coordinates", ("x_A", "y_A", "x_B", "y_B"), "m"),
        PlotSpec("Angle", ("phi",), "rad"),
        PlotSpec("Velocities", ("x_A_dot", "y_A_dot", "phi_dot"), "m/s, rad/s"),
        PlotSpec("Forces", ("F_Ax", "F_Ay", "F_Bx", "F_By", "M_phi"), "N, N m"),
    )

    def build_model(self, key: str) -> LagrangeModel:
        s = planar3_symbols()
        xA, yA, phi, AB = s["xA"], s["yA"], s["phi"], s["AB"]
        xB, yB = planar3_kinematics(xA, yA, phi, AB)  # (2.12)
        N = ReferenceFrame("N")
        Tab = ReferenceFrame("Tab")
        Tab.set_ang_vel(N, -phi.diff(T_) * N.z)  # A->B turns by -phi (clockwise): (2.12)
        PA, PB = Point("A"), Point("B")
        PA.set_vel(N, xA.diff(T_) * N.x + yA.diff(T_) * N.y)
        PB.set_vel(N, xB.diff(T_) * N.x + yB.diff(T_) * N.y)
        vA2 = xA.diff(T_) ** 2 + yA.diff(T_) ** 2
        T = (
            s["mA"] * vA2 / 2
            + s["mB"] * (xB.diff(T_) ** 2 + yB.diff(T_) ** 2) / 2
            + s["mAB"] * vA2 / 2
            + s["J"] * phi.diff(T_) ** 2 / 2
        )  # (2.15)
        forces = [
            (PA, s["FAx"] * N.x + s["FAy"] * N.y),
            (PB, s["FBx"] * N.x + s["FBy"] * N.y),
            (Tab, -s["Mphi"] * N.z),
        ]
        return LagrangeModel.build(
            [xA, yA, phi],
            T,
            sp.S.Zero,
            T_,
            [s["mA"], s["mB"], s["mAB"], s["J"], AB],
            [s["FAx"], s["FAy"], s["FBx"], s["FBy"], s["Mphi"]],
            forcelist=forces,
            frame=N,
        )

    def digest_equations(self) -> list[sp.Expr]:
        """The consistent 3-DOF equations as written in the digest (left - right)."""
        s = planar3_symbols()
        xA, yA, phi, AB, mB = s["xA"], s["yA"], s["phi"], s["AB"], s["mB"]
        m = s["mA"] + s["mAB"] + mB
        d = lambda e, k=1: e.diff(T_, k)  # noqa: E731
        Qx = s["FAx"] + s["FBx"]
        Qy = s["FAy"] + s["FBy"]
        Qp = s["Mphi"] + AB * (s["FBx"] * sp.sin(phi) + s["FBy"] * sp.cos(phi))
        return [
            m * d(xA, 2) + mB * AB * (sp.sin(phi) * d(phi, 2) + sp.cos(phi) * d(phi) ** 2) - Qx,
            m * d(yA, 2) + mB * AB * (sp.cos(phi) * d(phi, 2) - sp.sin(phi) * d(phi) ** 2) - Qy,
            mB * AB * (sp.sin(phi) * d(xA, 2) + sp.cos(phi) * d(yA, 2))
            + (s["J"] + mB * AB**2) * d(phi, 2)
            - Qp,
        ]

    def extra_names(self) -> Sequence[str]:
        return ("x_B", "y_B")

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        xB, yB = planar3_kinematics(q[0], q[1], q[2], float(params["AB"]), np)
        return {"x_B": xB, "y_B": yB}

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        s = planar3_symbols()
        xA, yA, phi, AB = s["xA"], s["yA"], s["phi"], s["AB"]
        xB, yB = dynamicsymbols("x_B y_B")
        T = sp.Symbol("T")
        return [
            DerivationStep(
                "Coupling of the module coordinates",
                "B follows A and the table angle.",
                [sp.Eq(xB, xA + AB * (1 - sp.cos(phi))), sp.Eq(yB, yA + AB * sp.sin(phi))],
                "(2.12)",
            ),
            DerivationStep(
                "Inverse kinematics",
                "Valid for |phi| <= pi/2 (arcsin) and phi in [0, pi] (arccos); atan2 covers the full range.",
                r"\varphi=\arcsin\frac{y_B-y_A}{AB}=\arccos\left(1-\frac{x_B-x_A}{AB}\right)=\operatorname{atan2}\left(y_B-y_A,\;AB-(x_B-x_A)\right)",
                "(2.12)",
            ),
            DerivationStep(
                "Lagrange equations",
                "The source writes them for q1 = x_A, q2 = y_A only; the system has three degrees of freedom, so phi is the third coordinate.",
                r"\frac{d}{dt}\frac{\partial T}{\partial \dot q}-\frac{\partial T}{\partial q}=-\frac{\partial U}{\partial q}+Q_q,\quad q\in\{x_A,y_A,\varphi\}",
                "(2.13)",
                reconstructed="consistent 3-DOF reading (ii) of the digest: phi added as a generalized coordinate",
            ),
            DerivationStep(
                "Kinetic energy",
                "Module A, module B and the table (mass m_AB, inertia J_A,pr about A).",
                sp.Eq(
                    T,
                    s["mA"] * (xA.diff(T_) ** 2 + yA.diff(T_) ** 2) / 2
                    + s["mB"] * (xB.diff(T_) ** 2 + yB.diff(T_) ** 2) / 2
                    + s["mAB"] * (xA.diff(T_) ** 2 + yA.diff(T_) ** 2) / 2
                    + s["J"] * phi.diff(T_) ** 2 / 2,
                ),
                "(2.14)-(2.15)",
                reconstructed="T_AB lost in the extraction; rebuilt from the surviving symbols (exact when the table's centre of mass is at A)",
            ),
            DerivationStep(
                "Generalized forces (virtual work)",
                "Drive forces F_A on A, F_B on B, moment M_phi on the table; dx_B = dx_A + AB sin(phi) dphi, dy_B = dy_A + AB cos(phi) dphi.",
                [
                    sp.Eq(sp.Symbol("Q_x"), s["FAx"] + s["FBx"]),
                    sp.Eq(sp.Symbol("Q_y"), s["FAy"] + s["FBy"]),
                    sp.Eq(
                        sp.Symbol(r"Q_\varphi"),
                        s["Mphi"] + AB * (s["FBx"] * sp.sin(phi) + s["FBy"] * sp.cos(phi)),
                    ),
                ],
                "(2.16)",
            ),
            DerivationStep(
                "Equations of motion (LagrangesMethod)",
                "Not written out in the source; derived from (2.12), (2.15), (2.16).",
                m.equations(),
                "(2.13)-(2.16)",
                reconstructed="the source stops at 'substituting (2.15) and (2.16) into (2.13)'",
            ),
            DerivationStep(
                "Forward problem"
                if params["problem"] == "forward"
                else "Inverse problem (program motion)",
                "Drive forces given: integrate the three equations."
                if params["problem"] == "forward"
                else "x_A(t), y_A(t), phi(t) given: x_B, y_B from (2.12); with F_B given, the left-hand sides give Q_x, Q_y, Q_phi and so F_Ax, F_Ay, M_phi.",
                r"\ddot q=M(q)^{-1}\left(F(q,\dot q)+Q(t)\right)"
                if params["problem"] == "forward"
                else r"Q=M(q)\ddot q-F(q,\dot q),\quad F_{Ax}=Q_x-F_{Bx},\;F_{Ay}=Q_y-F_{By},\;M_\varphi=Q_\varphi-AB\,(F_{Bx}\sin\varphi+F_{By}\cos\varphi)",
                "(2.13)-(2.16)",
            ),
        ]

    def scene_size(self, params: Params) -> float:
        return 2.0 * float(params["AB"]) + 0.5

    def _absolute(self, params: Params, q: Array) -> tuple[Array, Array]:
        AB = float(params["AB"])
        xB, yB = planar3_kinematics(q[0], q[1], q[2], AB, np)
        return np.array([q[0], q[1], 0.0]), np.array(
            [xB - AB, yB, 0.0]
        )  # A->B = AB(-cos phi, sin phi)

    def scene(self, params: Params) -> SceneSpec:
        AB = float(params["AB"])
        r = _coarse_run(self, params)
        q = np.array([r.series["x_A"], r.series["y_A"], r.series["phi"]])
        ok = np.all(np.isfinite(q), axis=0)
        pts = [np.zeros(3), np.array([-AB, 0, 0])]
        for k in np.nonzero(ok)[0][::10]:
            a, b = self._absolute(params, q[:, k])
            pts += [a, b]
        s = 0.25 * AB
        floor = np.array(pts)
        lo, hi = floor.min(axis=0) - 2 * s, floor.max(axis=0) + 2 * s
        base = box(
            "base",
            (hi[0] - lo[0], hi[1] - lo[1], 0.05 * s),
            (160, 160, 160),
            center=((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, -0.2 * s),
            opacity=0.4,
        )
        modA = box("module A", (s, s, 0.3 * s), (70, 130, 200))
        modB = box("module B", (s, s, 0.3 * s), (200, 130, 70))
        table = box("table", (AB + 0.6 * s, 0.6 * s, 0.15 * s), (120, 190, 120))
        return SceneSpec(
            bounds=bounds_of(np.vstack([lo, hi, [0, 0, s]]), 0.02),
            meshes=[base],
            bodies=[modA, modB, table],
            moving_points={"C (middle of AB)": (120, 190, 120)},
            moving_vectors={"F_A": (40, 160, 60), "F_B": (200, 60, 60), "M_phi": (140, 60, 200)},
        )

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        A, B = self._absolute(params, q)
        AB = float(params["AB"])
        h = 0.25 * AB * 0.3
        fr.poses["module A"] = (A, IDENTITY_Q.copy())
        fr.poses["module B"] = (B, IDENTITY_Q.copy())
        mid = (A + B) / 2
        fr.poses["table"] = (mid + [0, 0, h], quat_z(np.pi - float(q[2])))
        fr.points["C (middle of AB)"] = (mid + [0, 0, h])[None, :]
        fr.vectors["F_A"] = _arrow(A + [0, 0, 2 * h], [scale * u[0], scale * u[1], 0])
        fr.vectors["F_B"] = _arrow(B + [0, 0, 2 * h], [scale * u[2], scale * u[3], 0])
        fr.vectors["M_phi"] = _arrow(mid + [0, 0, 2 * h], [0, 0, -scale * u[4]])

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            return all(_is_zero(a - b) for a, b in zip(m.eom(), self.digest_equations()))

        def q_phi() -> bool:
            m = self.model(self.resolve())
            s = planar3_symbols()
            G = m.forcing.jacobian(m.inputs)
            want = sp.Matrix(
                [
                    [1, 0, 1, 0, 0],
                    [0, 1, 0, 1, 0],
                    [0, 0, s["AB"] * sp.sin(s["phi"]), s["AB"] * sp.cos(s["phi"]), 1],
                ]
            )
            return all(_is_zero(e) for e in (G - want))

        def ik() -> ClaimResult:
            AB, phi = 0.5, 0.3
            xB, yB = planar3_kinematics(0.1, -0.2, phi, AB, np)
            a, b, c = planar3_phi(0.1, -0.2, float(xB), float(yB), AB)
            return at_most(
                1e-12,
                max(abs(a - phi), abs(b - phi), abs(c - phi)),
                "max |phi recovered - 0.3| (arcsin, arccos, atan2) ",
            )

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error(
                {"F_Ax": "2*sin(t)", "F_Ay": "1", "F_By": "0.5*cos(t)", "M_phi": "0.1*cos(2*t)"}
            )
            return at_most(1e-4 * fmax, err, "max |(F_Ax, F_Ay, M_phi) recovered - applied| ")

        def inv_fwd() -> ClaimResult:
            return at_most(
                1e-8, self.inverse_forward_error({"F_By": "0.2"}), "max |q forward - q law| "
            )

        return [
            _claim(
                "eq-3dof",
                "LagrangesMethod with (2.12) substituted in (2.15) gives the consistent 3-DOF equations in x_A, y_A, phi",
                "(2.12)-(2.16)",
                _symbolic_claim(eq_ok, "3-DOF equations"),
            ),
            _claim(
                "q-phi",
                "Virtual work: Q_x = F_Ax + F_Bx, Q_y = F_Ay + F_By, Q_phi = M_phi + AB (F_Bx sin phi + F_By cos phi)",
                "(2.16)",
                _symbolic_claim(q_phi, "generalized forces"),
            ),
            _claim(
                "inverse-kinematics",
                "phi = arcsin((y_B - y_A)/AB) = arccos(1 - (x_B - x_A)/AB) recovers phi = 0.3 (AB = 0.5)",
                "(2.12)",
                ik,
            ),
            _claim(
                "round-trip-forward-inverse",
                "Forward then inverse recovers F_Ax, F_Ay, M_phi (F_B given) within 1e-4 of the peak",
                "(2.13)-(2.16)",
                round_trip,
            ),
            _claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces the program x_A, y_A, phi to 1e-8",
                "(2.13)-(2.16)",
                inv_fwd,
            ),
        ]


# =============================================================================== Problem 2.5

_POSE_LAWS = {
    "x_D": "0.02*sin(t)",
    "y_D": "0.02*(1 - cos(t))",
    "z_D": "0.2 + 0.01*sin(2*t)",
    "alpha": "0.05*sin(t)",
    "beta": "0.03*sin(2*t)",
    "phi": "0.1*sin(t/2)",
}
_POSE_UNITS = {"x_D": "m", "y_D": "m", "z_D": "m", "alpha": "rad", "beta": "rad", "phi": "rad"}
_BAUMGARTE = 10.0  # 1/s, alpha = beta of the stabilized forward runs


class Table6DOF(Lesson):
    """Problem 2.5: six-DOF work table on three planar inductors, geometry reconstructed
    (see :mod:`lessons.core.table6dof`); loops opened and closed by the §2.2 algorithm."""

    id = "table-6dof"
    title = "Work table with six degrees of freedom"
    chapter = "2"
    problem = "Problem 2.5"
    source = "Textbook §2.1, Problem 2.5 (Figs 2.6-2.9); geometry reconstructed"
    summary = "Three planar inductors A, B, C move in the floor plane; legs carry a table that translates, turns and tilts."
    order = 2.05
    t_end = 5.0
    params = (
        PROBLEM,
        Param("M_c", "float", 10.0, label="table mass M_c", unit="kg", min=0.01, max=1e4),
        Param(
            "J_D",
            "float",
            0.2,
            label="table inertia about its tilt axes J_D",
            unit="kg m^2",
            min=1e-5,
            max=1e4,
            help="the source's isotropic Z_D when J_Dz = J_D",
        ),
        Param(
            "J_Dz",
            "float",
            0.4,
            label="table inertia about its normal J_Dz",
            unit="kg m^2",
            min=1e-5,
            max=1e4,
        ),
        Param("m_A", "float", 2.0, label="inductor mass m_A", unit="kg", min=1e-3, max=1e4),
        Param("m_B", "float", 2.0, label="inductor mass m_B", unit="kg", min=1e-3, max=1e4),
        Param("m_C", "float", 2.0, label="inductor mass m_C", unit="kg", min=1e-3, max=1e4),
        Param("m_l", "float", 0.5, label="leg mass m_l", unit="kg", min=0.0, max=1e3),
        Param(
            "l", "float", 0.3, label="leg length l (reconstructed)", unit="m", min=0.01, max=10.0
        ),
        Param(
            "r_t",
            "float",
            0.15,
            label="table joint radius r_t (reconstructed)",
            unit="m",
            min=0.01,
            max=10.0,
        ),
        Param("g", "float", 9.81, label="g", unit="m/s^2", min=0.0, max=100.0),
        *[
            Param(
                f"{n}_t",
                "formula",
                law,
                label=f"{n}(t) program",
                unit=_POSE_UNITS[n],
                help="table pose program: inverse problem; reference of the forward problem",
            )
            for n, law in _POSE_LAWS.items()
        ],
        *[
            Param(
                f,
                "formula",
                "0",
                label=f"{f} (t)",
                unit="N",
                help="extra inductor force (forward problem)",
            )
            for f in ("F_Ax", "F_Ay", "F_Bx", "F_By", "F_Cx", "F_Cy")
        ],
        Param(
            "feedforward",
            "bool",
            True,
            label="add the program's inverse-dynamics forces",
            group="method",
        ),
        Param(
            "k_hold",
            "float",
            1e4,
            label="inductor holding stiffness k",
            unit="N/m",
            min=0.0,
            max=1e7,
            group="method",
            help="linear stepper motors hold their commanded position: F = -k (r - r_program) - b (v - v_program)",
        ),
        Param(
            "b_hold",
            "float",
            200.0,
            label="inductor holding damping b",
            unit="N s/m",
            min=0.0,
            max=1e6,
            group="method",
        ),
    )
    presets = (
        Preset(
            "inverse-program",
            "Inverse: pose program -> inductor coordinates and forces",
            {"problem": "inverse"},
            t_end=5.0,
        ),
        Preset(
            "forward-tracking",
            "Forward: program forces + holding stiffness",
            {"problem": "forward"},
            t_end=5.0,
        ),
        Preset(
            "forward-disturbance",
            "Forward: a 5 N push on inductor A along X",
            {"problem": "forward", "F_Ax": "5*sin(3*t)"},
            t_end=5.0,
        ),
        Preset(
            "forward-weight-only",
            "Forward: no feedforward, the stepper stiffness alone carries the table",
            {
                "problem": "forward",
                "feedforward": False,
                "z_D_t": "0.2",
                "x_D_t": "0",
                "y_D_t": "0",
                "alpha_t": "0",
                "beta_t": "0",
                "phi_t": "0",
            },
            t_end=3.0,
        ),
        Preset(
            "forward-open-loop",
            "Forward: program forces only (k = 0): the open chain drifts away",
            {"problem": "forward", "k_hold": 0.0, "b_hold": 0.0},
            t_end=3.0,
        ),
    )
    plots = (
        PlotSpec("Table position", ("x_D", "y_D", "z_D"), "m"),
        PlotSpec("Table angles", ("alpha", "beta", "phi"), "rad"),
        PlotSpec(
            "Table velocities",
            ("x_D_dot", "y_D_dot", "z_D_dot", "alpha_dot", "beta_dot", "phi_dot"),
            "m/s, rad/s",
        ),
        PlotSpec("Inductor coordinates", INDUCTORS, "m"),
        PlotSpec("Inductor velocities", tuple(f"{n}_dot" for n in INDUCTORS), "m/s"),
        PlotSpec("Inductor forces", FORCES, "N"),
        PlotSpec(
            "Constraint residual and tracking error", ("constraint_residual", "tracking_error"), ""
        ),
    )

    # -- pieces -------------------------------------------------------------------------

    def pvec(self, params: Params) -> Array:
        return np.array([float(params[n]) for n in PHYSICAL], dtype=float)

    def program(self, params: Params) -> Callable[[Array | float], tuple[Array, Array, Array]]:
        return formula_derivatives([params[f"{n}_t"].expr for n in POSE], t_symbol)

    def validate(self, params: Params) -> None:
        from lessons.core.contract import ParamError

        z = float(params["z_D_t"](0.0))
        if not np.isfinite(z) or z <= 0 or z >= float(params["l"]):
            raise ParamError(
                "z_D_t",
                f"the table height at t = 0 must lie between 0 and the leg length l = {float(params['l']):g} m; got {z:g}",
            )

    def formulas(self, params: Params) -> list[tuple[str, Formula]]:
        out = [(f"{n}_t", params[f"{n}_t"]) for n in POSE]
        if params["problem"] == "forward":
            out += [(f, params[f]) for f in FORCES]
        return out

    def program_at(self, params: Params, t: float) -> tuple[Array, Array, Array, bool]:
        pose, pose_d, pose_dd = self.program(params)(float(t))
        return program_state(pose, pose_d, pose_dd, self.pvec(params))

    def forces_of(self, params: Params) -> Callable[[float, Array, Array], Array]:
        """Forward problem: inductor forces = extra formulas + program feedforward +
        holding stiffness about the programmed inductor positions."""
        ext = [params[f] for f in FORCES]
        ev = self.program(params)
        p = self.pvec(params)
        ff, k, b = bool(params["feedforward"]), float(params["k_hold"]), float(params["b_hold"])

        def u(tt: float, q: Array, qd: Array) -> Array:
            F = np.array([float(f(tt)) for f in ext])
            if ff or k or b:
                pose, pose_d, pose_dd = ev(float(tt))
                qp, qdp, qddp, _ = program_state(pose, pose_d, pose_dd, p)
                if ff:
                    F = F + inverse_dynamics(qp, qdp, qddp, p)[0]
                F = F - k * (q[6:] - qp[6:]) - b * (qd[6:] - qdp[6:])
            return F

        return u

    def _forward(self, params: Params, t: Array) -> tuple[Array, Array, Array, str]:
        cs = table_model().system
        p = self.pvec(params)
        q0, qd0, _, _ = self.program_at(params, 0.0)
        u = self.forces_of(params)
        y, msg = integrate(
            cs.rhs(p, u, _BAUMGARTE, _BAUMGARTE), np.concatenate([q0, qd0]), t, rtol=1e-7, atol=1e-9
        )
        U = np.full((6, len(t)), np.nan)
        for k in range(len(t)):
            if np.all(np.isfinite(y[:, k])):
                U[:, k] = u(float(t[k]), y[:12, k], y[12:, k])
        return y[:12], y[12:], U, msg

    def _inverse(self, params: Params, t: Array) -> tuple[Array, Array, Array, str]:
        p = self.pvec(params)
        ev = self.program(params)
        pose, pose_d, pose_dd = ev(t)
        q = np.full((12, len(t)), np.nan)
        qd = np.full_like(q, np.nan)
        U = np.full((6, len(t)), np.nan)
        msg = ""
        for k in range(len(t)):
            qk, qdk, qddk, ok = program_state(pose[:, k], pose_d[:, k], pose_dd[:, k], p)
            if not ok:
                msg = f"a leg cannot reach the table joint at t = {t[k]:.4g} (joint higher than l): stopped"
                break
            q[:, k], qd[:, k] = qk, qdk
            U[:, k] = inverse_dynamics(qk, qdk, qddk, p)[0]
        return q, qd, U, msg

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        t = np.linspace(0.0, t_end, int(min(1001, max(101, 40 * t_end + 1))))
        msgs = []
        for name, f in self.formulas(params):
            try:
                f.check_finite(t)
            except FormulaError as exc:
                msgs.append(f"{name}: {exc}")
        if msgs:
            nan = np.full_like(t, np.nan)
            return RunResult(
                self.id,
                None,
                params.raw(),
                t,
                {n: nan for n in (*COORDS, *FORCES)},
                {"ok": False},
                msgs,
            )
        if params["problem"] == "forward":
            q, qd, U, msg = self._forward(params, t)
        else:
            q, qd, U, msg = self._inverse(params, t)
        series = {n: q[k] for k, n in enumerate(COORDS)}
        series.update({f"{n}_dot": qd[k] for k, n in enumerate(COORDS)})
        series.update({f: U[k] for k, f in enumerate(FORCES)})
        cs, p = table_model().system, self.pvec(params)
        resid = np.full(len(t), np.nan)
        for k in range(len(t)):
            if np.all(np.isfinite(q[:, k])):
                resid[k] = float(
                    np.max(np.abs(cs.residuals(float(t[k]), q[:, k], qd[:, k], p, np.zeros(6))[0]))
                )
        series["constraint_residual"] = resid
        prog, _, _ = self.program(params)(t)
        series["tracking_error"] = np.max(np.abs(q[:6] - prog), axis=0)
        metrics: dict[str, Any] = {
            "ok": not msg,
            "problem": params["problem"],
            "max_constraint_residual": float(np.nanmax(resid))
            if np.any(np.isfinite(resid))
            else float("nan"),
            "max_tracking_error": float(np.nanmax(series["tracking_error"]))
            if np.any(np.isfinite(series["tracking_error"]))
            else float("nan"),
            "max_inductor_force": float(np.nanmax(np.abs(U)))
            if np.any(np.isfinite(U))
            else float("nan"),
        }
        return RunResult(self.id, None, params.raw(), t, series, metrics, [msg] if msg else [])

    # -- live ---------------------------------------------------------------------------

    def stepper(self, params: Params) -> Stepper:
        if params["problem"] == "forward":

            def make(
                ps: Params,
            ) -> tuple[Array, Callable[[float, Array], Array], Callable[[float, Array], Frame]]:
                cs, p = table_model().system, self.pvec(ps)
                q0, qd0, _, _ = self.program_at(ps, 0.0)
                u = self.forces_of(ps)
                ev = self.program(ps)

                def frame_of(tt: float, y: Array) -> Frame:
                    F = u(tt, y[:12], y[12:])
                    fr = self._frame(ps, tt, y[:12], y[12:], F)
                    fr.scalars["constraint_residual"] = float(
                        np.max(np.abs(cs.residuals(tt, y[:12], y[12:], p, F)[0]))
                    )
                    fr.scalars["tracking_error"] = float(np.max(np.abs(y[:6] - ev(float(tt))[0])))
                    return fr

                return np.concatenate([q0, qd0]), cs.rhs(p, u, _BAUMGARTE, _BAUMGARTE), frame_of

            return OdeStepper(make, params, rtol=1e-7)

        def make_program(ps: Params) -> Callable[[float], Frame]:
            p = self.pvec(ps)

            def frame_at(tt: float) -> Frame:
                q, qd, qdd, ok = self.program_at(ps, tt)
                F = inverse_dynamics(q, qd, qdd, p)[0]
                fr = self._frame(ps, tt, q, qd, F)
                fr.scalars["constraint_residual"] = 0.0
                fr.scalars["tracking_error"] = 0.0
                if not ok:
                    fr.message = f"a leg cannot reach the table joint at t = {tt:.4g}"
                return fr

            return frame_at

        return ProgramStepper(make_program, params)

    def _frame(self, ps: Params, tt: float, q: Array, qd: Array, F: Array) -> Frame:
        fr = Frame(t=float(tt))
        for k, n in enumerate(COORDS):
            fr.scalars[n] = float(q[k])
            fr.scalars[f"{n}_dot"] = float(qd[k])
        for k, f in enumerate(FORCES):
            fr.scalars[f] = float(F[k])
        R = rotation(q[3], q[4], q[5])
        fr.poses["table"] = (q[:3].copy(), quat_wxyz(R))
        joints = table_joints(q[:6], float(ps["r_t"]))
        scale = 0.1 / max(float(ps["M_c"]) * max(float(ps["g"]), 1.0) / 3.0, 1e-9)
        for k, name in enumerate("ABC"):
            A = np.array([q[6 + 2 * k], q[7 + 2 * k], 0.0])
            fr.poses[f"inductor {name}"] = (A.copy(), quat_z(float(q[5])))
            fr.poses[f"leg {name}{name}'"] = segment_pose(A, joints[k])
            fr.vectors[f"F_{name}"] = (
                A[None, :] + [0, 0, 0.03],
                scale * np.array([[F[2 * k], F[2 * k + 1], 0.0]]),
            )
        fr.points["D"] = q[None, :3].copy()
        return fr

    def scene(self, params: Params) -> SceneSpec:
        l, rt = float(params["l"]), float(params["r_t"])
        R0 = rt + l
        floor = box(
            "floor (inductor plane z = 0)",
            (3 * R0, 3 * R0, 0.01 * R0),
            (170, 170, 170),
            center=(0, 0, -0.03),
            opacity=0.35,
        )
        plate = trimesh.creation.cylinder(radius=1.15 * rt, height=0.08 * rt, sections=3)
        plate.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1]))
        table = combine("table", [plate], (120, 190, 120))
        bodies: list[MeshItem] = [table]
        colors = ((70, 130, 200), (200, 130, 70), (160, 90, 200))
        for k, name in enumerate("ABC"):
            bodies.append(
                box(
                    f"inductor {name}",
                    (0.25 * rt, 0.25 * rt, 0.12 * rt),
                    colors[k],
                    center=(0, 0, -0.0),
                )
            )
            bodies.append(cylinder(f"leg {name}{name}'", 0.04 * rt, l, (90, 90, 90), sections=12))
        ext = 1.6 * R0
        return SceneSpec(
            bounds=bounds_of(np.array([[-ext, -ext, -0.05], [ext, ext, l + 0.3 * rt]]), 0.02),
            meshes=[floor],
            bodies=bodies,
            moving_points={"D": (120, 190, 120)},
            moving_vectors={"F_A": colors[0], "F_B": colors[1], "F_C": colors[2]},
        )

    # -- derivation ------------------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        tm = table_model()
        ge = r"\frac{d}{dt}\frac{\partial T}{\partial \dot q_i}-\frac{\partial T}{\partial q_i}=-\frac{\partial U}{\partial q_i}+Q_{q_i},\quad i=1,\dots,6"
        why = "the mechanism is only in the lost Figs 2.6-2.9; rebuilt consistently from the text"
        return [
            DerivationStep(
                "Generalized coordinates",
                "The planar coordinates of the three inductors.",
                r"q_1=x_A,\;q_2=y_A,\;q_3=x_B,\;q_4=y_B,\;q_5=x_C,\;q_6=y_C",
                "Problem 2.5",
            ),
            DerivationStep(
                "Six Lagrange equations",
                "The 'natural coordinates' form was lost in the extraction.",
                ge,
                "Problem 2.5",
            ),
            DerivationStep(
                "Legs and joints",
                "Each rigid leg of length l joins inductor k (ball joint) to table joint A'_k (hinge parallel to the opposite side of the table triangle): the inductor moves along the virtual axis n (eta), tau, rho perpendicular to that side.",
                r"(\vec r_{A}-\vec r_{A'})\cdot R\,\vec e_A=0,\qquad |\vec r_{A}-\vec r_{A'}|^2-l^2=0\quad(\text{and likewise } B, C)",
                "Figs 2.6-2.9",
                reconstructed=why,
            ),
            DerivationStep(
                "Displacement along a virtual axis",
                "At zero tilt the joint height Z' sets the inductor displacement along its axis.",
                r"S_A=\sqrt{l^2-Z_{A'}^2}",
                "Fig. 2.9",
                reconstructed=why,
            ),
            DerivationStep(
                "Table plane through A', B', C'",
                "Vanishing mixed product; D lies on the plane.",
                r"(\vec r_{A'}-\vec r_0)\cdot\left[(\vec r_{B'}-\vec r_0)\times(\vec r_{C'}-\vec r_0)\right]=0,\qquad x\cos\alpha+y\cos\beta+z\cos\gamma-h=0",
                "Problem 2.5",
            ),
            DerivationStep(
                "Kinetic energy", "", r"T=T_c+T_A+T_B+T_C+T_{AA'}+T_{BB'}+T_{CC'}", "Problem 2.5"
            ),
            DerivationStep(
                "Table: translation of D and rotation about D",
                "R = Rz(phi) Ry(beta) Rx(alpha); at zero tilt and J_Dz = J_D this is the source's 1/2 M (x'^2+y'^2+z'^2) + 1/2 Z_D (alpha'^2+beta'^2+gamma'^2).",
                sp.Eq(sp.Symbol("T_c"), sp.simplify(tm.T_table)),
                "Problem 2.5",
                reconstructed="the isotropic coefficient printed 'Z_D' read as the table inertia; angular velocity of the ZYX angles",
            ),
            DerivationStep(
                "Inductors",
                "",
                r"T_A=\tfrac12 m_A(\dot x_A^2+\dot y_A^2),\;T_B=\tfrac12 m_B(\dot x_B^2+\dot y_B^2),\;T_C=\tfrac12 m_C(\dot x_C^2+\dot y_C^2)",
                "Problem 2.5",
            ),
            DerivationStep(
                "Legs (slender rods)",
                "End velocities v_A (inductor) and v_A' (table joint).",
                r"T_{AA'}=\frac{m_l}{6}\left(v_A^2+\vec v_A\cdot\vec v_{A'}+v_{A'}^2\right)\quad(\text{and likewise } BB', CC')",
                "Problem 2.5",
                reconstructed="leg energies lost in the extraction (only the factors 1/2 survive)",
            ),
            DerivationStep(
                "Potential energy",
                "The inductors move in the horizontal plane: U_A = U_B = U_C = 0.",
                r"U=M_c g z_D+\sum_k m_l g \frac{z_{A'_k}}{2}",
                "Problem 2.5",
            ),
            DerivationStep(
                "Generalized forces",
                "Virtual work of the inductor forces on their own coordinates.",
                r"Q_{q_i}=\frac{\delta A^e_{q_i}}{\delta q_i}=F_{q_i}",
                "Problem 2.5",
            ),
            DerivationStep(
                "Loops opened (§2.2)",
                "12 coordinates (table pose + inductors), six leg constraints, multipliers eliminated by (2.33)-(2.34): the six equations of the source in closed form.",
                r"A\ddot q=B+S F+H^{T}\lambda,\quad H\ddot q=-\Phi,\quad H\in\mathbb{R}^{6\times 12}",
                "(2.25), (2.30), (2.34)",
            ),
        ]

    # -- claims -------------------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        p0 = lambda **kw: self.pvec(self.resolve(kw))  # noqa: E731

        def dof() -> ClaimResult:
            p = p0()
            q, qd, _, _ = program_state(
                np.array([0, 0, 0.2, 0, 0, 0.0]), np.zeros(6), np.zeros(6), p
            )
            H = table_model().system.parts(0.0, q, qd, p, np.zeros(6))["H"]
            r = int(np.linalg.matrix_rank(H))
            return ClaimResult(
                "rank H = 6, 12 - 6 = 6 degrees of freedom", f"rank H = {r}, {12 - r} DOF", r == 6
            )

        def axis_displacement() -> ClaimResult:
            pose = np.array([0.01, -0.02, 0.2, 0, 0, 0.3])
            ind, _ = inverse_kinematics(pose, 0.3, 0.15)
            J = table_joints(pose, 0.15)
            S = [float(np.hypot(ind[2 * k] - J[k, 0], ind[2 * k + 1] - J[k, 1])) for k in range(3)]
            return close(
                np.sqrt(0.3**2 - 0.2**2), max(S, key=lambda v: abs(v - np.sqrt(0.05))), atol=1e-12
            )

        def ik_constraints() -> ClaimResult:
            p = p0()
            pose = np.array([0.01, 0.02, 0.19, 0.08, -0.05, 0.4])
            q, qd, _, _ = program_state(
                pose, np.array([0.1, 0, 0.02, 0.1, 0.1, 0.3]), np.zeros(6), p
            )
            f, c = table_model().system.residuals(0.0, q, qd, p, np.zeros(6))
            return at_most(
                1e-12,
                float(max(np.max(np.abs(f)), np.max(np.abs(c)))),
                "leg constraints and (2.29) at a tilted pose ",
            )

        def plane() -> ClaimResult:
            det, nf = plane_through_joints(np.array([0.01, 0.02, 0.19, 0.08, -0.05, 0.4]), 0.15)
            return at_most(1e-12, max(abs(det), abs(nf)), "|mixed product|, |normal form at D| ")

        def energy_form() -> ClaimResult:
            tm = table_model()
            xD, yD, zD, al, be, ph = tm.q[:6]
            Mc, JD, JDz = (sp.Symbol(n, real=True, positive=True) for n in ("M_c", "J_D", "J_Dz"))
            d = lambda e: e.diff(T_)  # noqa: E731
            want = (
                Mc * (d(xD) ** 2 + d(yD) ** 2 + d(zD) ** 2) / 2
                + JD * (d(al) ** 2 + d(be) ** 2 + d(ph) ** 2) / 2
            )
            rates = {qi.diff(T_): sp.Symbol(f"{qi.func}_rate", real=True) for qi in tm.q[:6]}
            got = tm.T_table.subs(JDz, JD).xreplace(rates).subs({al: 0, be: 0})
            want = want.xreplace(rates)
            ok = sp.simplify(got - want) == 0
            return ClaimResult(
                "T_c = 1/2 M_c (x_D'^2 + y_D'^2 + z_D'^2) + 1/2 J_D (alpha'^2 + beta'^2 + phi'^2) at zero tilt",
                "equal" if ok else "differ",
                bool(ok),
            )

        def static_force() -> ClaimResult:
            p = p0(m_l=0.0)
            q, qd, qdd, _ = program_state(
                np.array([0, 0, 0.2, 0, 0, 0.0]), np.zeros(6), np.zeros(6), p
            )
            F, _ = inverse_dynamics(q, qd, qdd, p)
            mags = [float(np.hypot(F[2 * k], F[2 * k + 1])) for k in range(3)]
            inward = all(F[2 * k : 2 * k + 2] @ q[6 + 2 * k : 8 + 2 * k] < 0 for k in range(3))
            want = 10.0 * 9.81 * np.sqrt(0.3**2 - 0.2**2) / (3 * 0.2)
            r = close(want, max(mags, key=lambda v: abs(v - want)), rtol=1e-12)
            r.passed = r.passed and inward
            r.got += " (inward)" if inward else " (not inward)"
            return r

        def inv_fwd() -> ClaimResult:
            ps = self.resolve({"problem": "forward", "k_hold": 0.0, "b_hold": 0.0})
            t = np.linspace(0.0, 1.5, 61)
            q, _, _, _ = self._forward(ps, t)
            prog, _, _ = self.program(ps)(t)
            return at_most(
                1e-6,
                float(np.max(np.abs(q[:6] - prog))),
                "max |pose forward - program| over 1.5 s ",
            )

        def fwd_inv() -> ClaimResult:
            ps = self.resolve({"problem": "forward", "F_Ax": "5*sin(3*t)"})
            t = np.linspace(0.0, 1.0, 1001)
            q, qd, U, _ = self._forward(ps, t)
            qdd = numerical_second_derivative(t, qd)
            p = self.pvec(ps)
            rec = np.array(
                [
                    inverse_dynamics(q[:, k], qd[:, k], qdd[:, k], p)[0]
                    for k in range(5, len(t) - 5, 10)
                ]
            ).T
            err = float(np.max(np.abs(rec - U[:, 5:-5:10])))
            return at_most(
                1e-3 * float(np.max(np.abs(U))), err, "max |F recovered - F applied| (N) "
            )

        return [
            _claim(
                "six-dof",
                "Three inductors with two coordinates each and three legs give the table six degrees of freedom",
                "Problem 2.5",
                dof,
            ),
            _claim(
                "axis-displacement",
                "Zero tilt, z_D = 0.2 m, l = 0.3 m: each inductor sits at S = sqrt(l^2 - Z'^2) = 0.2236 m from its joint along its virtual axis",
                "Problem 2.5, Fig. 2.9 (reconstructed geometry)",
                axis_displacement,
            ),
            _claim(
                "ik-constraints",
                "The inverse kinematics satisfies the six leg constraints and the velocities satisfy (2.29) at a tilted, turned pose",
                "(2.17), (2.29)",
                ik_constraints,
            ),
            _claim(
                "table-plane",
                "The table plane through A', B', C' (mixed product = 0, normal form) contains D",
                "Problem 2.5",
                plane,
            ),
            _claim(
                "table-energy",
                "At zero tilt with J_Dz = J_D the table's kinetic energy has the source's form 1/2 M (x'^2+y'^2+z'^2) + 1/2 Z_D (alpha'^2+beta'^2+gamma'^2)",
                "Problem 2.5",
                energy_form,
            ),
            _claim(
                "static-holding-force",
                "Massless legs, table at rest at z = 0.2 m: each inductor must push inward with M g sqrt(l^2 - z^2)/(3 z) = 36.56 N",
                "Problem 2.5, virtual work",
                static_force,
            ),
            _claim(
                "round-trip-inverse-forward",
                "The inverse problem's forces, applied open-loop (k = 0), reproduce the pose program within 1e-6 over 1.5 s",
                "(2.34)",
                inv_fwd,
            ),
            _claim(
                "round-trip-forward-inverse",
                "Forward run with holding stiffness and a 5 sin 3t N push: the inverse problem on the sampled motion recovers the six inductor forces within 1e-3 of the peak",
                "(2.34)",
                fwd_inv,
            ),
        ]


LESSONS: list[Lesson] = [
    LinearPositioner(),
    RotaryPositioner(),
    Planar2Axis(),
    Planar3Axis(),
    Table6DOF(),
]
