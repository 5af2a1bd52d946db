"""Chapter 2, §2.1: dynamic models of coordinate positioners, Problems 2.1-2.5.

Every model is derived with ``sympy.physics.mechanics.LagrangesMethod`` from the kinetic
energy T, the potential energy U and the applied forces (the generalized forces are the
coefficients of the virtual work, (2.10)/(2.16)), then lambdified once.  Each lesson
solves the *forward* problem (forces given as formulas of t -> motion) and the *inverse*
problem (motion law given as formulas of t -> the drive forces), (2.1)-(2.16).

Problem 2.5 (six-DOF table) lives in :mod:`lessons.table_6dof_model` helpers below; its
geometry is reconstructed (the source gives it only in lost figures).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

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
    quat_z,
    recover_inputs,
    sample_formulas,
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
    "problem", "choice", "forward", label="problem", choices=("forward", "inverse"), group="method",
    help="forward: forces given, motion found; inverse: motion law given, drive forces found",
)


def positioner_params(coords: Sequence[Coord], inputs: Sequence[Input], physical: Sequence[Param], extra: Sequence[Param] = ()) -> tuple[Param, ...]:
    out: list[Param] = [PROBLEM, *extra, *physical]
    for i in inputs:
        out.append(Param(i.name, "formula", i.default, label=i.label + " (t)", unit=i.unit, help="used in the forward problem" + ("" if i.unknown else " and the inverse problem")))
    for c in coords:
        out.append(Param(f"{c.name}_t", "formula", c.law, label=f"{c.label}(t) law", unit=c.unit, help="motion law of the inverse problem"))
    for c in coords:
        out.append(Param(f"{c.name}0", "float", c.q0, label=f"{c.label}(0)", unit=c.unit, min=-1e3, max=1e3, group="initial"))
        out.append(Param(f"{c.name}_dot0", "float", 0.0, label=f"{c.label}'(0)", unit=f"{c.unit}/s", min=-1e3, max=1e3, group="initial"))
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
        return np.array([float(params[f"{c.name}0"]) for c in self.coords] + [float(params[f"{c.name}_dot0"]) for c in self.coords])

    def formulas_in_use(self, params: Params) -> list[tuple[str, Formula]]:
        if params["problem"] == "forward":
            return [(i.name, params[i.name]) for i in self.inputs]
        return [(i.name, params[i.name]) for i in self.inputs if not i.unknown] + [(f"{c.name}_t", params[f"{c.name}_t"]) for c in self.coords]

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
            U[:, k] = model.solve_inputs(q[:, k], qd[:, k], qdd[:, k], float(t[k]), p, U[:, k], self.unknown)
        return q, qd, qdd, U, ""

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        n_s = int(min(2001, max(201, 100 * t_end + 1)))
        t = np.linspace(0.0, t_end, n_s)
        msgs = self.check_formulas(params, t)
        if msgs:
            nan = np.full_like(t, np.nan)
            return RunResult(self.id, None, params.raw(), t, {k: nan for k in self.series_names()}, {"ok": False}, msgs)
        q, qd, qdd, U, msg = self.motion(params, t)
        series = self.series(params, t, q, qd, qdd, U)
        metrics: dict[str, Any] = {"ok": not msg, "problem": params["problem"]}
        for k, c in enumerate(self.coords):
            metrics[f"{c.name}_end"] = float(q[k, -1])
        for k, i in enumerate(self.inputs):
            metrics[f"{i.name}_max_abs"] = float(np.nanmax(np.abs(U[k]))) if np.any(np.isfinite(U[k])) else float("nan")
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

    def series(self, params: Params, t: Array, q: Array, qd: Array, qdd: Array, U: Array) -> dict[str, Array]:
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

    def frame_from(self, params: Params, t: float, q: Array, qd: Array, qdd: Array, u: Array, scale: float) -> Frame:
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

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:  # pragma: no cover
        raise NotImplementedError

    def stepper(self, params: Params) -> Stepper:
        if params["problem"] == "forward":
            def make(ps: Params) -> tuple[Array, Callable[[float, Array], Array], Callable[[float, Array], Frame]]:
                model, p, n, scale = self.model(ps), self.pvec(ps), len(self.coords), self.force_scale(ps)
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

    # -- claims helpers ---------------------------------------------------------------

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
        return ClaimResult(expected=f"{what}: simplify(difference) == 0", got="0" if passed else "non-zero", passed=passed)

    return check


def _arrow(origin: Sequence[float], direction: Sequence[float]) -> tuple[Array, Array]:
    return np.asarray([origin], dtype=float), np.asarray([direction], dtype=float)


# =============================================================================== Problem 2.1


class LinearPositioner(PositionerLesson):
    """Problem 2.1: d'Alembert (2.1) projected on X gives M x'' = sum F_x^A + sum N_x (2.2)."""

    id = "linear-positioner"
    title = "Problem 2.1 - single-coordinate linear positioner"
    problem = "Problem 2.1"
    source = "Textbook §2.1, Problem 2.1, eqs (2.1)-(2.2)"
    summary = "A carriage on a straight guide: M x'' = F_dv - R_sopr + N_x; forward and inverse problems."
    order = 2.01
    coords = (Coord("x", "x", "m", 0.0, "0.1*(1 - cos(pi*t/2))"),)
    inputs = (
        Input("F_dv", "driving force F_dv", "N", "2 + sin(3*t)"),
        Input("R_sopr", "resistance force R_sopr", "N", "0.5", unknown=False),
        Input("N_x", "reaction N_x (0 for ideal guides)", "N", "0", unknown=False),
    )
    physical = ("M",)
    params = positioner_params(coords, inputs, (Param("M", "float", 5.0, label="moving mass M", unit="kg", min=1e-3, max=1e4),))
    presets = (
        Preset("forward-constant-force", "Forward: constant drive 2 N against 0.5 N resistance", {"problem": "forward", "F_dv": "2", "R_sopr": "0.5"}, t_end=10.0),
        Preset("forward-harmonic", "Forward: F_dv = 2 + sin 3t", {"problem": "forward"}, t_end=10.0),
        Preset("inverse-cosine-move", "Inverse: x = 0.1 (1 - cos(pi t/2)) m", {"problem": "inverse"}, t_end=10.0),
    )
    plots = (PlotSpec("Coordinate", ("x",), "m"), PlotSpec("Velocity", ("x_dot",), "m/s"), PlotSpec("Forces", ("F_dv", "R_sopr", "N_x"), "N"))

    def build_model(self, key: str) -> LagrangeModel:
        x = dynamicsymbols("x")
        M, F, R, Nx = _sym("M", positive=True), _sym("F_dv"), _sym("R_sopr"), _sym("N_x")
        N = ReferenceFrame("N")
        P = Point("P")
        P.set_vel(N, x.diff(T_) * N.x)
        T = M * x.diff(T_) ** 2 / 2
        return LagrangeModel.build([x], T, sp.S.Zero, T_, [M], [F, R, Nx], forcelist=[(P, (F - R + Nx) * N.x)], frame=N)

    def textbook_eq(self) -> sp.Expr:
        x = dynamicsymbols("x")
        M, F, R, Nx = _sym("M", positive=True), _sym("F_dv"), _sym("R_sopr"), _sym("N_x")
        return M * x.diff(T_, 2) - (F - R + Nx)

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        x = m.q[0]
        M, F, R, Nx = m.params[0], *m.inputs
        Fa, Nn, mi, ai = sp.symbols("F^A N m_i a_i")
        steps = [
            DerivationStep("d'Alembert principle", "Active forces, constraint reactions and inertia forces are in equilibrium.", sp.Eq(sp.Symbol(r"\sum F^A") + sp.Symbol(r"\sum N") - sp.Symbol(r"\sum m_i a_i"), 0), "(2.1)"),
            DerivationStep("Kinetic energy", "All points have the same acceleration, so the moving mass M = sum m_i acts as one body.", sp.Eq(sp.Symbol("T"), M * x.diff(T_) ** 2 / 2)),
            DerivationStep("Generalized force", "Virtual work of the drive, the resistance and the guide reaction on dx.", sp.Eq(sp.Symbol("Q_x"), F - R + Nx), "(2.2)"),
            DerivationStep("Equation of motion (LagrangesMethod)", "Projection on the X axis.", m.equations()[0], "(2.2)"),
        ]
        if params["problem"] == "forward":
            steps.append(DerivationStep("Forward problem", "Forces known: the acceleration, then the motion by integration.", sp.Eq(x.diff(T_, 2), (F - R + Nx) / M)))
        else:
            law = params["x_t"].expr.subs(t_symbol, T_)
            steps.append(DerivationStep("Inverse problem", "Motion law given: the drive force it needs.", sp.Eq(F, sp.simplify(M * sp.diff(law, T_, 2) + R - Nx)), "(2.2)"))
        _ = (Fa, Nn, mi, ai)
        return steps

    def scene_size(self, params: Params) -> float:
        return 1.0

    def _range(self, params: Params) -> tuple[float, float]:
        r = self.simulate(params, self.t_end)
        x = r.series["x"]
        x = x[np.isfinite(x)]
        return (float(x.min()), float(x.max())) if len(x) else (0.0, 1.0)

    def scene(self, params: Params) -> SceneSpec:
        lo, hi = self._range(params)
        span = max(hi - lo, 0.5)
        s = 0.15 * span
        rail = box("guide", (span + 2 * s, 0.4 * s, 0.2 * s), (90, 90, 90), center=((lo + hi) / 2, 0, -0.1 * s))
        carriage = box("carriage", (s, 0.8 * s, 0.5 * s), (70, 130, 200))
        pts = np.array([[lo - s, -s, -s], [hi + s, s, s]])
        self._s = s
        return SceneSpec(bounds=bounds_of(pts), meshes=[rail], bodies=[carriage], moving_vectors={"F_dv": (40, 160, 60), "R_sopr": (200, 60, 60)}, moving_points={"carriage": (70, 130, 200)})

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        x = float(q[0])
        p = np.array([x, 0.0, 0.0])
        fr.poses["carriage"] = (p + [0, 0, 0.05], IDENTITY_Q.copy())
        fr.points["carriage"] = p[None, :]
        fr.vectors["F_dv"] = _arrow(p + [0, 0, 0.1], [scale * u[0], 0, 0])
        fr.vectors["R_sopr"] = _arrow(p + [0, 0, 0.1], [-scale * u[1], 0, 0])

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            return _is_zero(m.eom()[0] - self.textbook_eq())

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error({"M": 5.0, "F_dv": "2 + sin(3*t)", "R_sopr": "0.5"})
            return at_most(1e-4 * fmax, err, "max |F_dv recovered - F_dv| ")

        def inv_fwd() -> ClaimResult:
            return at_most(1e-8, self.inverse_forward_error({"M": 5.0}), "max |x forward - x law| (m) ")

        def constant_force() -> ClaimResult:
            r = self.run("forward-constant-force")
            return close(1.5 / 5.0 * 10.0**2 / 2, float(r.series["x"][-1]), rtol=1e-8)

        return [
            _claim("eq-2.2", "LagrangesMethod with T = M x'^2/2 and Q_x = F_dv - R_sopr + N_x gives (2.2): M x'' = F_dv - R_sopr + N_x", "(2.2)", _symbolic_claim(eq_ok, "(2.2)")),
            _claim("forward-constant", "Forward: F_dv = 2 N, R_sopr = 0.5 N, M = 5 kg from rest: x(10) = (1.5/5) 10^2/2 = 15 m", "(2.2)", constant_force),
            _claim("round-trip-forward-inverse", "Forward then inverse recovers the drive force F_dv = 2 + sin 3t (within 1e-4 of its peak)", "(2.2)", round_trip),
            _claim("round-trip-inverse-forward", "Inverse then forward reproduces the law x = 0.1(1 - cos(pi t/2)) to 1e-8 m", "(2.2)", inv_fwd),
        ]


# =============================================================================== Problem 2.2


class RotaryPositioner(PositionerLesson):
    """Problem 2.2: J_z,pr phi'' = sum M_z(F^e) (2.3), J_z,pr = sum m_i h_i^2 (2.4)."""

    id = "rotary-positioner"
    title = "Problem 2.2 - rotary positioner"
    problem = "Problem 2.2"
    source = "Textbook §2.1, Problem 2.2, eqs (2.3)-(2.4)"
    summary = "Three masses m_i at distances h_i from the axis Z: (sum m_i h_i^2) phi'' = M_dv - M_c."
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
        Preset("forward-harmonic-moment", "Forward: M_dv = 0.2 sin t", {"problem": "forward"}, t_end=10.0),
        Preset("forward-constant-moment", "Forward: M_dv = 0.1 N m, M_c = 0.02 N m", {"problem": "forward", "M_dv": "0.1", "M_c": "0.02"}, t_end=5.0),
        Preset("inverse-quarter-turn", "Inverse: a smooth quarter turn per 2 pi s", {"problem": "inverse"}, t_end=10.0),
    )
    plots = (PlotSpec("Angle", ("phi",), "rad"), PlotSpec("Angular velocity", ("phi_dot",), "rad/s"), PlotSpec("Moments", ("M_dv", "M_c"), "N m"))

    def validate(self, params: Params) -> None:
        J = sum(float(params[f"m{i}"]) * float(params[f"h{i}"]) ** 2 for i in (1, 2, 3))
        if J <= 0:
            from lessons.core.contract import ParamError

            raise ParamError("m1", "the reduced moment of inertia sum m_i h_i^2 is zero: give some mass a non-zero radius")

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
        return LagrangeModel.build([phi], sp.simplify(T), sp.S.Zero, T_, [*[v for pair in zip(ms, hs) for v in pair]], [Md, Mc], forcelist=[(R, (Md - Mc) * N.z)], frame=N)

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        phi = m.q[0]
        ms = [m.params[0], m.params[2], m.params[4]]
        hs = [m.params[1], m.params[3], m.params[5]]
        J = sp.Symbol(r"J_{z\,pr}")
        Md, Mc = m.inputs
        steps = [
            DerivationStep("Kinetic energy of the rotating masses", "Each point M_i moves on a circle of radius h_i about Z.", sp.Eq(sp.Symbol("T"), m.lagrangian)),
            DerivationStep("Reduced moment of inertia", "", sp.Eq(J, sum(mi * hi**2 for mi, hi in zip(ms, hs))), "(2.3)"),
            DerivationStep("Equation of rotation (LagrangesMethod)", "Moment of the drive and the resistance about Z.", m.equations()[0], "(2.4)"),
        ]
        if params["problem"] == "inverse":
            law = params["phi_t"].expr.subs(t_symbol, T_)
            steps.append(DerivationStep("Inverse problem", "The drive moment the law needs.", sp.Eq(Md, sp.simplify(sum(mi * hi**2 for mi, hi in zip(ms, hs)) * sp.diff(law, T_, 2) + Mc)), "(2.4)"))
        else:
            steps.append(DerivationStep("Forward problem", "", sp.Eq(phi.diff(T_, 2), (Md - Mc) / J), "(2.3)"))
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
            ball = trimesh.creation.icosphere(subdivisions=2, radius=0.04 * R * (1 + float(params[f"m{k + 1}"])) ** (1 / 3))
            ball.apply_translation(c * h)
            parts.append(ball)
        rotor = combine("rotor", parts, (200, 140, 60))
        axis = cylinder("axis Z", 0.01 * R, 1.2 * R, (60, 60, 60))
        pts = np.array([[-1.3 * R, -1.3 * R, -0.6 * R], [1.3 * R, 1.3 * R, 0.8 * R]])
        return SceneSpec(bounds=bounds_of(pts, 0.02), meshes=[axis], bodies=[rotor], moving_vectors={"M_dv": (40, 160, 60), "M_c": (200, 60, 60)}, moving_points={"M1": (200, 60, 60)})

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
            return at_most(1e-8, self.inverse_forward_error({}), "max |phi forward - phi law| (rad) ")

        return [
            _claim("eq-2.3-2.4", "LagrangesMethod on three point masses gives (sum m_i h_i^2) phi'' = M_dv - M_c, i.e. J_z,pr = sum m_i h_i^2", "(2.3)-(2.4)", _symbolic_claim(eq_ok, "(2.4)")),
            _claim("forward-constant", "Forward: M_dv - M_c = 0.08 N m on J = 0.105 kg m^2 from rest: phi(5) = 0.08/0.105 * 25/2 = 9.524 rad", "(2.3)", constant),
            _claim("round-trip-forward-inverse", "Forward then inverse recovers M_dv = 0.2 sin t (within 1e-4 of its peak)", "(2.4)", round_trip),
            _claim("round-trip-inverse-forward", "Inverse then forward reproduces the law phi(t) to 1e-8 rad", "(2.4)", inv_fwd),
        ]


# =============================================================================== Problem 2.3


class Planar2Axis(PositionerLesson):
    """Problem 2.3: Lagrange equations (2.5) with T = M (x'^2 + y'^2)/2 (2.6)-(2.7), U by
    layout (2.8)/(2.9), Q by virtual work (2.10) -> corrected (2.11)."""

    id = "planar-2axis"
    title = "Problem 2.3 - two-coordinate planar positioner"
    problem = "Problem 2.3"
    source = "Textbook §2.1, Problem 2.3, eqs (2.5)-(2.11')"
    summary = "An X-Y stage, horizontal (U = 0) or vertical (U = M g y): M x'' = -dU/dx + Q_x, M y'' = -dU/dy + Q_y."
    order = 2.03
    coords = (Coord("x", "x", "m", 0.0, "0.2*sin(t)"), Coord("y", "y", "m", 0.0, "0.1*sin(2*t)"))
    inputs = (Input("Q_x", "force along X, Q_x", "N", "2*cos(t)"), Input("Q_y", "force along Y, Q_y", "N", "sin(2*t)"))
    physical = ("M", "g")
    params = positioner_params(
        coords,
        inputs,
        (Param("M", "float", 4.0, label="total moving mass M", unit="kg", min=1e-3, max=1e4), Param("g", "float", 9.81, label="g", unit="m/s^2", min=0.0, max=100.0)),
        extra=(Param("layout", "choice", "horizontal", label="layout", choices=("horizontal", "vertical"), group="method", help="vertical: the Y axis points up and U = M g y (2.9)"),),
    )
    presets = (
        Preset("forward-horizontal", "Forward, horizontal: Q_x = 2 cos t, Q_y = sin 2t", {"problem": "forward", "layout": "horizontal"}, t_end=10.0),
        Preset("forward-vertical-hold", "Forward, vertical: Q_y = M g holds the weight", {"problem": "forward", "layout": "vertical", "Q_x": "2*cos(t)", "Q_y": "4*9.81"}, t_end=10.0),
        Preset("inverse-vertical-figure-eight", "Inverse, vertical: x = 0.2 sin t, y = 0.1 sin 2t", {"problem": "inverse", "layout": "vertical"}, t_end=10.0),
    )
    plots = (PlotSpec("Coordinates", ("x", "y"), "m"), PlotSpec("Speed", ("x_dot", "y_dot", "v"), "m/s"), PlotSpec("Forces", ("Q_x", "Q_y"), "N"))

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
        return LagrangeModel.build([x, y], T, U, T_, [M, g], [Qx, Qy], forcelist=[(P, Qx * N.x + Qy * N.y)], frame=N)

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
            DerivationStep("Speed and acceleration", "", [sp.Eq(sp.Symbol("v"), sp.sqrt(x.diff(T_) ** 2 + y.diff(T_) ** 2)), sp.Eq(sp.Symbol("a"), sp.sqrt(x.diff(T_, 2) ** 2 + y.diff(T_, 2) ** 2))]),
            DerivationStep("Lagrange equations of the 2nd kind", "q1 = x, q2 = y.", r"\frac{d}{dt}\frac{\partial T}{\partial \dot q}-\frac{\partial T}{\partial q}=-\frac{\partial U}{\partial q}+Q_q,\quad q\in\{x,y\}", "(2.5)"),
            DerivationStep("Kinetic energy", "All points of the stage share the velocity (x', y').", sp.Eq(T, M * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2), "(2.6)-(2.7)"),
            DerivationStep("Potential energy", "Vertical layout: Y up, U = M g y (2.9)." if vert else "Horizontal layout: dU/dx = dU/dy = 0 (2.8).", sp.Eq(U, M * g * y if vert else 0), "(2.9)" if vert else "(2.8)"),
            DerivationStep("Generalized forces", "Coefficients of the virtual displacements in the virtual work.", r"Q_x=\frac{\delta A}{\delta x},\qquad Q_y=\frac{\delta A}{\delta y}", "(2.10)"),
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
            steps.append(DerivationStep("Inverse problem", "", [sp.Eq(Qx, sp.simplify(M * sp.diff(lx, T_, 2))), sp.Eq(Qy, sp.simplify(M * sp.diff(ly, T_, 2) + (M * g if vert else 0)))], "(2.11)"))
        return steps

    def _world(self, params: Params, x: Array | float, y: Array | float) -> Array:
        if params["layout"] == "vertical":
            return np.array([x, 0.0 * np.asarray(x), y], dtype=float).T
        return np.array([x, y, 0.0 * np.asarray(x)], dtype=float).T

    def scene_size(self, params: Params) -> float:
        return self._extent(params)[2]

    def _extent(self, params: Params) -> tuple[Array, Array, float]:
        r = self.simulate(params, self.t_end)
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
            base = box("base plate", (L[0], 0.2 * s, L[2]), (150, 150, 150), center=(c[0], -0.4 * s, c[2]), opacity=0.5)
            slide = box("X slide", (0.6 * s, 0.3 * s, L[2]), (90, 120, 170))
            carriage = box("Y carriage", (s, 0.5 * s, s), (70, 160, 210))
        else:
            base = box("base plate", (L[0], L[1], 0.2 * s), (150, 150, 150), center=(c[0], c[1], -0.4 * s), opacity=0.5)
            slide = box("X slide", (0.6 * s, L[1], 0.3 * s), (90, 120, 170))
            carriage = box("Y carriage", (s, s, 0.5 * s), (70, 160, 210))
        self._center = c
        pts = np.array([lo - 2 * s, hi + 2 * s])
        return SceneSpec(bounds=bounds_of(pts, 0.02), meshes=[base], bodies=[slide, carriage], moving_points={"carriage": (70, 160, 210)}, moving_vectors={"Q": (40, 160, 60), "weight": (200, 60, 60)}, planar=False)

    def pose_frame(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        p = self._world(params, float(q[0]), float(q[1]))
        c = getattr(self, "_center", np.zeros(3))
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
                return _is_zero(m.eom()[0] - (M * x.diff(T_, 2) - Qx)) and _is_zero(m.eom()[1] - (M * y.diff(T_, 2) + dUdy - Qy))

            return ok

        def hold() -> ClaimResult:
            r = self.run("forward-vertical-hold")
            return at_most(1e-9, float(np.max(np.abs(r.series["y"]))), "vertical stage with Q_y = M g: max |y| (m) ")

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error({"layout": "vertical", "Q_x": "2*cos(t)", "Q_y": "40 + sin(2*t)"})
            return at_most(1e-4 * fmax, err, "max |Q recovered - Q| ")

        def inv_fwd() -> ClaimResult:
            return at_most(1e-8, self.inverse_forward_error({"layout": "vertical"}), "max |q forward - q law| (m) ")

        def inverse_weight() -> ClaimResult:
            r = self.run("inverse-vertical-figure-eight")
            t = r.t
            expected = 4.0 * (-0.4 * np.sin(2 * t)) + 4.0 * 9.81
            return at_most(1e-9, float(np.max(np.abs(r.series["Q_y"] - expected))), "max |Q_y - (M y'' + M g)| (N) ")

        return [
            _claim("eq-2.11-horizontal", "Horizontal layout (2.8): LagrangesMethod gives M x'' = Q_x, M y'' = Q_y", "(2.11)", _symbolic_claim(eq_ok("horizontal"), "(2.11), U = 0")),
            _claim("eq-2.11-vertical", "Vertical layout (2.9), U = M g y: M x'' = Q_x, M y'' = -M g + Q_y (corrected (2.11))", "(2.11)", _symbolic_claim(eq_ok("vertical"), "(2.11), U = M g y")),
            _claim("vertical-hold", "Vertical stage: Q_y = M g keeps y = 0 (dU/dy balanced)", "(2.9), (2.11)", hold),
            _claim("inverse-weight", "Inverse, vertical: Q_y(t) = M y'' + M g for y = 0.1 sin 2t", "(2.11)", inverse_weight),
            _claim("round-trip-forward-inverse", "Forward then inverse recovers Q_x = 2 cos t, Q_y = 40 + sin 2t (within 1e-4 of the peak)", "(2.11)", round_trip),
            _claim("round-trip-inverse-forward", "Inverse then forward reproduces x = 0.2 sin t, y = 0.1 sin 2t to 1e-8 m", "(2.11)", inv_fwd),
        ]


# =============================================================================== Problem 2.4


def planar3_kinematics(xA: Any, yA: Any, phi: Any, AB: Any, lib: Any = sp) -> tuple[Any, Any]:
    """Module-B coordinates (2.12): x_B = x_A + AB (1 - cos phi), y_B = y_A + AB sin phi."""
    return xA + AB * (1 - lib.cos(phi)), yA + AB * lib.sin(phi)


def planar3_phi(xA: float, yA: float, xB: float, yB: float, AB: float) -> tuple[float, float, float]:
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
    return dict(xA=xA, yA=yA, phi=phi, mA=mA, mB=mB, mAB=mAB, J=J, AB=AB, FAx=FAx, FAy=FAy, FBx=FBx, FBy=FBy, Mphi=Mphi)


class Planar3Axis(PositionerLesson):
    """Problem 2.4 as the consistent 3-DOF model q = (x_A, y_A, phi): (2.12)-(2.16) with
    the reconstructed T (2.15) and (2.12) substituted (DESIGN §3 item 8)."""

    id = "planar-3axis"
    title = "Problem 2.4 - three-coordinate planar motion system"
    problem = "Problem 2.4"
    source = "Textbook §2.1, Problem 2.4, eqs (2.12)-(2.16)"
    summary = "Two planar modules A and B carry a table that translates and turns by phi; consistent model in x_A, y_A, phi."
    order = 2.04
    coords = (Coord("x_A", "x_A", "m", 0.0, "0.1*sin(t)"), Coord("y_A", "y_A", "m", 0.0, "0.05*(1 - cos(t))"), Coord("phi", "phi", "rad", 0.0, "0.3*sin(t/2)"))
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
            Param("J_A", "float", 0.4, label="table inertia about A, J_A,pr", unit="kg m^2", min=1e-6, max=1e4),
            Param("AB", "float", 0.5, label="distance AB", unit="m", min=1e-3, max=100.0),
        ),
    )
    presets = (
        Preset("forward-drives", "Forward: drives on A, B pushes along Y", {"problem": "forward"}, t_end=10.0),
        Preset("inverse-program", "Inverse: x_A = 0.1 sin t, y_A = 0.05 (1 - cos t), phi = 0.3 sin(t/2); F_B = 0", {"problem": "inverse", "F_By": "0"}, t_end=10.0),
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
        T = s["mA"] * vA2 / 2 + s["mB"] * (xB.diff(T_) ** 2 + yB.diff(T_) ** 2) / 2 + s["mAB"] * vA2 / 2 + s["J"] * phi.diff(T_) ** 2 / 2  # (2.15)
        forces = [(PA, s["FAx"] * N.x + s["FAy"] * N.y), (PB, s["FBx"] * N.x + s["FBy"] * N.y), (Tab, -s["Mphi"] * N.z)]
        return LagrangeModel.build([xA, yA, phi], T, sp.S.Zero, T_, [s["mA"], s["mB"], s["mAB"], s["J"], AB], [s["FAx"], s["FAy"], s["FBx"], s["FBy"], s["Mphi"]], forcelist=forces, frame=N)

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
            mB * AB * (sp.sin(phi) * d(xA, 2) + sp.cos(phi) * d(yA, 2)) + (s["J"] + mB * AB**2) * d(phi, 2) - Qp,
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
            DerivationStep("Coupling of the module coordinates", "B follows A and the table angle.", [sp.Eq(xB, xA + AB * (1 - sp.cos(phi))), sp.Eq(yB, yA + AB * sp.sin(phi))], "(2.12)"),
            DerivationStep("Inverse kinematics", "Valid for |phi| <= pi/2 (arcsin) and phi in [0, pi] (arccos); atan2 covers the full range.", r"\varphi=\arcsin\frac{y_B-y_A}{AB}=\arccos\left(1-\frac{x_B-x_A}{AB}\right)=\operatorname{atan2}\left(y_B-y_A,\;AB-(x_B-x_A)\right)", "(2.12)"),
            DerivationStep("Lagrange equations", "The source writes them for q1 = x_A, q2 = y_A only; the system has three degrees of freedom, so phi is the third coordinate.", r"\frac{d}{dt}\frac{\partial T}{\partial \dot q}-\frac{\partial T}{\partial q}=-\frac{\partial U}{\partial q}+Q_q,\quad q\in\{x_A,y_A,\varphi\}", "(2.13)", reconstructed="consistent 3-DOF reading (ii) of the digest: phi added as a generalized coordinate"),
            DerivationStep(
                "Kinetic energy",
                "Module A, module B and the table (mass m_AB, inertia J_A,pr about A).",
                sp.Eq(T, s["mA"] * (xA.diff(T_) ** 2 + yA.diff(T_) ** 2) / 2 + s["mB"] * (xB.diff(T_) ** 2 + yB.diff(T_) ** 2) / 2 + s["mAB"] * (xA.diff(T_) ** 2 + yA.diff(T_) ** 2) / 2 + s["J"] * phi.diff(T_) ** 2 / 2),
                "(2.14)-(2.15)",
                reconstructed="T_AB lost in the extraction; rebuilt from the surviving symbols (exact when the table's centre of mass is at A)",
            ),
            DerivationStep("Generalized forces (virtual work)", "Drive forces F_A on A, F_B on B, moment M_phi on the table; dx_B = dx_A + AB sin(phi) dphi, dy_B = dy_A + AB cos(phi) dphi.", [sp.Eq(sp.Symbol("Q_x"), s["FAx"] + s["FBx"]), sp.Eq(sp.Symbol("Q_y"), s["FAy"] + s["FBy"]), sp.Eq(sp.Symbol(r"Q_\varphi"), s["Mphi"] + AB * (s["FBx"] * sp.sin(phi) + s["FBy"] * sp.cos(phi)))], "(2.16)"),
            DerivationStep("Equations of motion (LagrangesMethod)", "Not written out in the source; derived from (2.12), (2.15), (2.16).", m.equations(), "(2.13)-(2.16)", reconstructed="the source stops at 'substituting (2.15) and (2.16) into (2.13)'"),
        ]

    def scene_size(self, params: Params) -> float:
        return 2.0 * float(params["AB"]) + 0.5

    def _absolute(self, params: Params, q: Array) -> tuple[Array, Array]:
        AB = float(params["AB"])
        xB, yB = planar3_kinematics(q[0], q[1], q[2], AB, np)
        return np.array([q[0], q[1], 0.0]), np.array([xB - AB, yB, 0.0])  # A->B = AB(-cos phi, sin phi)

    def scene(self, params: Params) -> SceneSpec:
        AB = float(params["AB"])
        r = self.simulate(params, self.t_end)
        q = np.array([r.series["x_A"], r.series["y_A"], r.series["phi"]])
        ok = np.all(np.isfinite(q), axis=0)
        pts = [np.zeros(3), np.array([-AB, 0, 0])]
        for k in np.nonzero(ok)[0][::10]:
            a, b = self._absolute(params, q[:, k])
            pts += [a, b]
        s = 0.25 * AB
        floor = np.array(pts)
        lo, hi = floor.min(axis=0) - 2 * s, floor.max(axis=0) + 2 * s
        base = box("base", (hi[0] - lo[0], hi[1] - lo[1], 0.05 * s), (160, 160, 160), center=((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, -0.2 * s), opacity=0.4)
        modA = box("module A", (s, s, 0.3 * s), (70, 130, 200))
        modB = box("module B", (s, s, 0.3 * s), (200, 130, 70))
        table = box("table", (AB + 0.6 * s, 0.6 * s, 0.15 * s), (120, 190, 120))
        return SceneSpec(bounds=bounds_of(np.vstack([lo, hi, [0, 0, s]]), 0.02), meshes=[base], bodies=[modA, modB, table], moving_points={"C (middle of AB)": (120, 190, 120)}, moving_vectors={"F_A": (40, 160, 60), "F_B": (200, 60, 60), "M_phi": (140, 60, 200)})

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
            want = sp.Matrix([[1, 0, 1, 0, 0], [0, 1, 0, 1, 0], [0, 0, s["AB"] * sp.sin(s["phi"]), s["AB"] * sp.cos(s["phi"]), 1]])
            return all(_is_zero(e) for e in (G - want))

        def ik() -> ClaimResult:
            AB, phi = 0.5, 0.3
            xB, yB = planar3_kinematics(0.1, -0.2, phi, AB, np)
            a, b, c = planar3_phi(0.1, -0.2, float(xB), float(yB), AB)
            return close(phi, max(abs(a - phi), abs(b - phi), abs(c - phi)) + phi, atol=1e-12)

        def round_trip() -> ClaimResult:
            err, fmax = self.round_trip_error({"F_Ax": "2*sin(t)", "F_Ay": "1", "F_By": "0.5*cos(t)", "M_phi": "0.1*cos(2*t)"})
            return at_most(1e-4 * fmax, err, "max |(F_Ax, F_Ay, M_phi) recovered - applied| ")

        def inv_fwd() -> ClaimResult:
            return at_most(1e-8, self.inverse_forward_error({"F_By": "0.2"}), "max |q forward - q law| ")

        return [
            _claim("eq-3dof", "LagrangesMethod with (2.12) substituted in (2.15) gives the consistent 3-DOF equations in x_A, y_A, phi", "(2.12)-(2.16)", _symbolic_claim(eq_ok, "3-DOF equations")),
            _claim("q-phi", "Virtual work: Q_x = F_Ax + F_Bx, Q_y = F_Ay + F_By, Q_phi = M_phi + AB (F_Bx sin phi + F_By cos phi)", "(2.16)", _symbolic_claim(q_phi, "generalized forces")),
            _claim("inverse-kinematics", "phi = arcsin((y_B - y_A)/AB) = arccos(1 - (x_B - x_A)/AB) recovers phi = 0.3 (AB = 0.5)", "(2.12)", ik),
            _claim("round-trip-forward-inverse", "Forward then inverse recovers F_Ax, F_Ay, M_phi (F_B given) within 1e-4 of the peak", "(2.13)-(2.16)", round_trip),
            _claim("round-trip-inverse-forward", "Inverse then forward reproduces the program x_A, y_A, phi to 1e-8", "(2.13)-(2.16)", inv_fwd),
        ]


LESSONS: list[Lesson] = [LinearPositioner(), RotaryPositioner(), Planar2Axis(), Planar3Axis()]
