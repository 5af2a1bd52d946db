"""The common page of chapter 2's positioners (Problems 2.1-2.4): forward and inverse runs.

Every positioner is solved two ways, (2.1)-(2.16): the *forward* problem (forces given
as formulas of t -> the motion, integrated once per parameter set as a
:class:`~analyzer_lab.lessons.kit.steppers.DenseSolution`) and the *inverse* problem (a
motion law given as formulas of t -> the drive forces, in closed form), on a page solved
once per parameter set
(:class:`~analyzer_lab.lessons.mechanics.positioners.dynamics.DynamicsLesson`).
:class:`PositionerLesson` adds the Lagrange models of Problems 2.1-2.4
(:class:`~analyzer_lab.lessons.mechanics.lagrange.model.LagrangeModel`): parameters,
series, observation and the round-trip claims from generalized coordinates and forces.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import (
    MODE,
    ClaimResult,
    Frame,
    Group,
    Note,
    Param,
    Params,
    Series,
    at_most,
)
from analyzer_lab.lessons.kit.formula import Formula, t_symbol
from analyzer_lab.lessons.kit.steppers import ClosedForm, DenseSolution, Solution, integrate
from analyzer_lab.lessons.mechanics.lagrange.model import (
    LagrangeModel,
    formula_derivatives,
    recover_inputs,
)
from analyzer_lab.lessons.mechanics.positioners.dynamics import PROBLEM, DynamicsLesson
from sympy.physics.mechanics import dynamicsymbols

T_ = dynamicsymbols._t  # the time of the sympy models
Array = np.ndarray

FORCES = Group("forces", "Forces and moments")
PROGRAM = Group("program", "Motion law (inverse problem)", when=("problem", ("inverse",)))
START = Group("initial", "Start state (forward problem)", change="restart")


def sym(name: str, **kw: Any) -> sp.Symbol:
    return sp.Symbol(name, real=True, **kw)


def is_zero(expr: sp.Expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


def symbolic_claim(ok: Callable[[], bool], what: str) -> Callable[[], ClaimResult]:
    """A claim check: ``ok()`` is a symbolic identity ``simplify(difference) == 0``."""

    def check() -> ClaimResult:
        passed = bool(ok())
        return ClaimResult(
            expected=f"{what}: simplify(difference) == 0",
            got="0" if passed else "non-zero",
            passed=passed,
        )

    return check


def arrow(origin: Sequence[float], direction: Sequence[float]) -> tuple[Array, Array]:
    """One moving vector of a frame (origin, direction)."""
    return np.asarray([origin], dtype=float), np.asarray([direction], dtype=float)


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


def positioner_groups(body: str) -> tuple[Group, ...]:
    """The panel of a positioner: mode, the body (titled ``body``), forces, law, start."""
    return (MODE, Group("body", body), FORCES, PROGRAM, START)


def positioner_params(
    coords: Sequence[Coord],
    inputs: Sequence[Input],
    body: Sequence[Param],
    modes: Sequence[Param] = (),
) -> tuple[Param, ...]:
    """Problem, extra modes, the body (group "body"), force formulas, laws, start state."""
    out: list[Param] = [PROBLEM, *modes, *body]
    for i in inputs:
        out.append(
            Param(
                i.name,
                "formula",
                i.default,
                label=i.label + " (t)",
                unit=i.unit,
                group="forces",
                help="given in the forward problem"
                + (", found in the inverse problem" if i.unknown else " and the inverse problem"),
                when=("problem", ("forward",)) if i.unknown else None,
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
                group="program",
                help="motion law of the inverse problem",
            )
        )
    for c in coords:
        for name, label, unit, v in (
            (f"{c.name}0", f"{c.label}(0)", c.unit, c.q0),
            (f"{c.name}_dot0", f"{c.label}'(0)", f"{c.unit}/s", 0.0),
        ):
            out.append(
                Param(name, "float", v, label=label, unit=unit, min=-1e3, max=1e3, group="initial")
            )
    return tuple(out)


def positioner_series(
    coords: Sequence[Coord], inputs: Sequence[Input], extra: Sequence[Series] = ()
) -> tuple[Series, ...]:
    """Each coordinate with its velocity and acceleration, each force, then ``extra``."""
    out: list[Series] = []
    for c in coords:
        out += [
            Series(c.name, c.unit, f"coordinate {c.label}"),
            Series(f"{c.name}_dot", f"{c.unit}/s", f"velocity {c.label}'"),
            Series(f"{c.name}_ddot", f"{c.unit}/s^2", f"acceleration {c.label}''"),
        ]
    out += [Series(i.name, i.unit, i.label) for i in inputs]
    return (*out, *extra)


class PositionerLesson(DynamicsLesson):
    """Problems 2.1-2.4: forward/inverse runs on a :class:`LagrangeModel`.

    The state is ``[q, q']`` (forward: integrated; inverse: the law's closed form).
    """

    coords: tuple[Coord, ...] = ()
    inputs: tuple[Input, ...] = ()
    physical: tuple[str, ...] = ()  # model parameter names, in the model's order
    t_end = 10.0
    sampling = 0.01
    #: ``(inverse, forward, source)``: the note :meth:`notes` gives for each problem
    problem_notes: tuple[str, str, str] | None = None

    def notes(self, params: Params) -> list[Note]:
        if self.problem_notes is None:
            return []
        inverse, forward, source = self.problem_notes
        return [Note("info", inverse if params["problem"] == "inverse" else forward, source)]

    # -- model ------------------------------------------------------------------

    _models: dict[tuple[str, str], LagrangeModel] = {}

    def model(self, params: Params) -> LagrangeModel:
        """The Lagrange model (built and lambdified once per lesson and model key)."""
        key = (self.id, self.model_key(params))
        if key not in self._models:
            self._models[key] = self.build_model(key[1])
        return self._models[key]

    def model_key(self, params: Params) -> str:
        return ""

    def build_model(self, key: str) -> LagrangeModel:
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

    def law_at(self, params: Params) -> Callable[[Array | float], tuple[Array, Array, Array]]:
        """:meth:`law` (once per parameter set)."""
        return self.cached("law", params, lambda: self.law(params))

    def law(self, params: Params) -> Callable[[Array | float], tuple[Array, Array, Array]]:
        """The inverse problem's law: ``t -> (q, q', q'')`` by exact differentiation."""
        return formula_derivatives([params[f"{c.name}_t"].expr for c in self.coords], t_symbol)

    def formulas_in_use(self, params: Params) -> list[tuple[str, Formula]]:
        if params["problem"] == "forward":
            return [(i.name, params[i.name]) for i in self.inputs]
        return [(i.name, params[i.name]) for i in self.inputs if not i.unknown] + [
            (f"{c.name}_t", params[f"{c.name}_t"]) for c in self.coords
        ]

    def forces(self, params: Params, t: Array, known_only: bool = False) -> Array:
        """The force formulas on the samples ``t``: ``(n_inputs, len(t))`` (the unknown
        inputs of the inverse problem are 0 with ``known_only``)."""
        U = np.zeros((len(self.inputs), len(t)))
        for k, i in enumerate(self.inputs):
            if not (known_only and i.unknown):
                with np.errstate(all="ignore"):
                    U[k] = np.broadcast_to(np.asarray(params[i.name](t), dtype=float), t.shape)
        return U

    # -- one solution, one observation ------------------------------------------------

    def start(self, params: Params, t0: float, y: Array | None) -> Solution:
        if params["problem"] == "inverse":
            ev = self.law_at(params)
            return ClosedForm(lambda t: np.vstack(ev(t)[:2]).T)
        n, p = len(self.coords), self.plain_p(params)
        acc, u_at = self.model(params).acceleration_list, self.inputs_at(params)

        def rhs(tt: float, yy: Array) -> Array:
            """``[q, q'] -> [q', q'']`` with ``q''`` from the Lagrange equations."""
            ys = yy.tolist()
            out = np.empty(2 * n)
            out[:n] = yy[n:]
            out[n:] = acc(ys[:n], ys[n:], tt, p, u_at(tt))
            return out

        y_start = self.y0(params) if y is None else y
        return DenseSolution(rhs, t0, y_start)

    def plain_p(self, params: Params) -> list[float]:
        """:meth:`pvec` as a list of floats (once per parameter set)."""
        return self.cached("plain p", params, lambda: self.pvec(params).tolist())

    def inputs_at(self, params: Params) -> Callable[[Any], list[float]]:
        """``t -> [u_1(t), ...]``: the force formulas at one time as floats (once per
        parameter set): the constant ones read once, the others in one function on
        floats; where that fails (1/0, a root of a negative number) the formulas give
        their inf or NaN as on the grid."""

        def build() -> Callable[[Any], list[float]]:
            fs = [params[i.name] for i in self.inputs]
            base = [float(f.constant_value or 0.0) for f in fs]
            varying = [k for k, f in enumerate(fs) if f.constant_value is None]
            if not varying:
                return lambda tt: list(base)
            names = {fs[k].variables for k in varying}
            fn = (
                sp.lambdify(
                    [sym(v) for v in next(iter(names))],
                    [fs[k].expr for k in varying],
                    modules=["math", "numpy"],
                )
                if len(names) == 1
                else None
            )

            def at(tt: Any) -> list[float]:
                out = list(base)
                try:
                    vals = [float(v) for v in fn(float(tt))]  # type: ignore[misc]
                except (ValueError, ZeroDivisionError, OverflowError, TypeError):
                    vals = [float(fs[k](np.float64(tt))) for k in varying]
                for k, v in zip(varying, vals):
                    out[k] = v
                return out

            return at

        return self.cached("inputs at", params, build)

    def motion(self, params: Params, t: Array, state: Array) -> tuple[Array, Array, Array, Array]:
        """``(q, q', q'', u)`` on the samples from the state ``[q, q']`` at those times."""
        n, model = len(self.coords), self.model(params)
        q, qd = state[:, :n].T, state[:, n:].T
        ok = np.all(np.isfinite(state), axis=1)
        if params["problem"] == "forward":
            U = self.forces(params, t)
            qdd = np.full_like(q, np.nan)
            acc, pl = model.acceleration_list, self.plain_p(params)
            for k in np.nonzero(ok & np.all(np.isfinite(U), axis=0))[0]:
                qdd[:, k] = acc(
                    q[:, k].tolist(), qd[:, k].tolist(), float(t[k]), pl, U[:, k].tolist()
                )
            return q, qd, qdd, U
        with np.errstate(all="ignore"):
            qdd = self.law_at(params)(t)[2]
        U = self.forces(params, t, known_only=True)
        good = ok & np.all(np.isfinite(qdd), axis=0) & np.all(np.isfinite(U), axis=0)
        U[:, ~good] = np.nan
        solve, pl, unknown = model.input_list, self.plain_p(params), self.unknown
        for k in np.nonzero(good)[0]:
            U[:, k] = solve(
                q[:, k].tolist(),
                qd[:, k].tolist(),
                qdd[:, k].tolist(),
                float(t[k]),
                pl,
                U[:, k].tolist(),
                unknown,
            )
        return q, qd, qdd, U

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        return {}

    def observe(self, params: Params, t: Array, state: Any) -> dict[str, Array]:
        q, qd, qdd, U = self.motion(params, t, np.asarray(state, dtype=float))
        out: dict[str, Array] = {}
        for k, c in enumerate(self.coords):
            out[c.name], out[f"{c.name}_dot"], out[f"{c.name}_ddot"] = q[k], qd[k], qdd[k]
        for k, i in enumerate(self.inputs):
            out[i.name] = U[k]
        out.update(self.extra_series(params, q, qd, qdd))
        return out

    def observe_one(self, params: Params, t: float, state: Any) -> dict[str, float] | None:
        """A played frame: :meth:`observe`'s numbers at ``[t]``, worked out on floats (the
        same functions sample by sample, no arrays of one sample)."""
        y = np.asarray(state, dtype=float)
        if y.shape[0] != 1:
            return None
        n, model, p = len(self.coords), self.model(params), self.plain_p(params)
        x = np.float64(t)  # numpy's scalar: 1/0 is inf, as on the grid
        u = self.inputs_at(params)(x)
        ys = y[0].tolist()
        q, qd = ys[:n], ys[n:]
        if params["problem"] == "forward":
            if all(math.isfinite(v) for v in (*ys, *u)):
                qdd = model.acceleration_list(q, qd, float(t), p, u)
            else:
                qdd = [math.nan] * n
        else:
            qdd = self.law_at(params)(np.array([x]))[2][:, 0].tolist()
            for k in self.unknown:
                u[k] = 0.0
            if all(math.isfinite(v) for v in (*ys, *qdd, *u)):
                u = model.input_list(q, qd, qdd, float(t), p, u, self.unknown)
            else:
                u = [math.nan] * len(u)
        out: dict[str, float] = {}
        for k, c in enumerate(self.coords):
            out[c.name], out[f"{c.name}_dot"], out[f"{c.name}_ddot"] = q[k], qd[k], qdd[k]
        for k, i in enumerate(self.inputs):
            out[i.name] = u[k]
        col = lambda v: np.array(v)[:, None]  # noqa: E731  (one sample of the grid's shape)
        extra = self.extra_series(params, col(q), col(qd), col(qdd))
        out.update({name: float(v[0]) for name, v in extra.items()})
        return out

    def run_metrics(self, params: Params, series: dict[str, Array]) -> dict[str, Any]:
        out: dict[str, Any] = {f"{c.name}_end": float(series[c.name][-1]) for c in self.coords}
        for i in self.inputs:
            u = series[i.name]
            out[f"{i.name}_max_abs"] = (
                float(np.nanmax(np.abs(u))) if np.any(np.isfinite(u)) else float("nan")
            )
        return out

    # -- live -----------------------------------------------------------------------

    def force_scale(self, params: Params) -> float:
        """Arrow length per unit force: the largest force of the default run maps to a
        quarter of the scene size."""
        return float(self.cached("force scale", params, lambda: self._force_scale(params)))

    def _force_scale(self, params: Params) -> float:
        r = self.coarse_run(params)
        U = np.array([r.series[i.name] for i in self.inputs])
        fmax = float(np.nanmax(np.abs(U))) if np.any(np.isfinite(U)) else 0.0
        return 0.25 * self.scene_size(params) / fmax if fmax > 0 else 0.0

    def scene_size(self, params: Params) -> float:
        return 1.0

    def pose_frame(self, params: Params, fr: Frame, state: Array) -> None:
        u = np.array(
            [v if math.isfinite(v) else 0.0 for v in (fr.scalars[i.name] for i in self.inputs)]
        )
        self.pose(params, fr, state[: len(self.coords)], u, self.force_scale(params))

    def pose(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        raise NotImplementedError

    # -- claims support ---------------------------------------------------------------

    def forward_inverse_check(self, values: dict[str, Any], what: str) -> Callable[[], ClaimResult]:
        """Claim check: forward then inverse recovers the unknown inputs within 1e-4 of
        their peak (:meth:`round_trip_error`)."""

        def check() -> ClaimResult:
            err, fmax = self.round_trip_error(values)
            return at_most(1e-4 * fmax, err, what)

        return check

    def inverse_forward_check(self, values: dict[str, Any], what: str) -> Callable[[], ClaimResult]:
        """Claim check: inverse then forward reproduces the motion law to 1e-8
        (:meth:`inverse_forward_error`)."""
        return lambda: at_most(1e-8, self.inverse_forward_error(values), what)

    def round_trip_error(self, values: dict[str, Any], t_end: float = 5.0) -> tuple[float, float]:
        """Forward run with the given forces, then the inverse problem on the sampled
        motion (accelerations by differences): ``(max |u_rec - u|, max |u|)`` over the
        unknown inputs, away from the two end samples."""
        params = self.resolve({**values, "problem": "forward"})
        t = np.linspace(0.0, t_end, 2001)
        q, qd, _, U = self.motion(params, t, self.solution(params)(t))
        rec = recover_inputs(self.model(params), t, q, qd, self.pvec(params), U, self.unknown)
        idx = self.unknown
        err = float(np.max(np.abs(rec[idx, 2:-2] - U[idx, 2:-2])))
        return err, float(np.max(np.abs(U[idx])))

    def inverse_forward_error(self, values: dict[str, Any], t_end: float = 5.0) -> float:
        """Inverse problem on a motion law, then the forward problem driven by the
        forces found (the inverse problem solved at each evaluation instant):
        max |q_forward - q_law| over the coordinates."""
        params = self.resolve({**values, "problem": "inverse"})
        t = np.linspace(0.0, t_end, 101)
        model, p, n = self.model(params), self.pvec(params), len(self.coords)
        ev = self.law(params)

        def u_exact(tt: float, q: Array, qd: Array) -> Array:
            ql, qdl, qddl = ev(tt)
            u0 = self.forces(params, np.array([tt]), known_only=True)[:, 0]
            return model.solve_inputs(ql, qdl, qddl, tt, p, u0, self.unknown)

        q_law, qd_law, _ = ev(t)
        y, _ = integrate(model.rhs(p, u_exact), np.concatenate([q_law[:, 0], qd_law[:, 0]]), t)
        return float(np.max(np.abs(y[:n] - q_law)))
