"""Problem 2.5: the work table with six degrees of freedom (Figs 2.6-2.9).

Three planar inductors A, B, C move in the floor plane; rigid legs join them to the
joints A', B', C' of a table that translates, turns and tilts.  The generalized
coordinates of the source are the six inductor coordinates; its kinetic energy is the
sum of the table's, the inductors' and the legs' (T = T_c + T_A + ... + T_CC'), and the
generalized forces are the inductor forces.  The mechanism survives only in figures lost
in the extraction, so its geometry is **reconstructed** (:mod:`analyzer_lab.lessons.mechanics.table.model`);
the equations come from opening the loops at the legs and closing them with the
algorithm of §2.2, (2.25)-(2.34).  Inverse problem: a table pose program gives the
inductor coordinates and forces; forward problem: the program's forces (feedforward) plus
the holding stiffness of the linear stepper motors drive the table.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import (
    MODE,
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Group,
    Note,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    SceneSpec,
    Series,
    at_most,
    close,
)
from analyzer_lab.lessons.kit.formula import Formula, t_symbol
from analyzer_lab.lessons.kit.steppers import ClosedForm, DenseSolution, Solution
from analyzer_lab.lessons.mechanics.lagrange.model import (
    formula_derivatives,
    numerical_second_derivative,
)
from analyzer_lab.lessons.mechanics.positioners.dynamics import PROBLEM, DynamicsLesson
from analyzer_lab.lessons.mechanics.table.derivation import table_derivation
from analyzer_lab.lessons.mechanics.table.frames import InverseTable, pose_row, pose_rows
from analyzer_lab.lessons.mechanics.table.model import (
    COORDS,
    FORCES,
    INDUCTORS,
    PHYSICAL,
    POSE,
    axis_displacements,
    constraint_residuals,
    inverse_dynamics,
    inverse_observed,
    plane_through_joints,
    pose_table,
    program_state,
    table_model,
    table_scene,
    zero_tilt_energy_is_the_sources,
)

Array = np.ndarray
POSE_LAWS = {
    "x_D": "0.02*sin(t)",
    "y_D": "0.02*(1 - cos(t))",
    "z_D": "0.2 + 0.01*sin(2*t)",
    "alpha": "0.05*sin(t)",
    "beta": "0.03*sin(2*t)",
    "phi": "0.1*sin(t/2)",
}
POSE_UNITS = {"x_D": "m", "y_D": "m", "z_D": "m", "alpha": "rad", "beta": "rad", "phi": "rad"}
BAUMGARTE = 10.0  # 1/s, alpha = beta of the stabilized forward runs
REST = {f"{n}_t": "0" for n in POSE} | {"z_D_t": "0.2"}

#: Work counted per evaluation of the table's equations of motion (a 12-coordinate
#: multibody model: about 25 times a small model's; see
#: :func:`analyzer_lab.lessons.kit.budget.charge`).
WORK_PER_EVALUATION = 500.0


def _number(
    name: str, default: float, label: str, unit: str, lo: float, hi: float, group: str = "body"
) -> Param:
    return Param(name, "float", default, label=label, unit=unit, min=lo, max=hi, group=group)


def _frozen(values: list[float]) -> Array:
    """A read-only array (shared by every frame of one parameter set)."""
    out = np.array(values, dtype=float)
    out.setflags(write=False)
    return out


class Table6DOF(DynamicsLesson):
    """Problem 2.5: six-DOF work table on three planar inductors, geometry reconstructed
    (see :mod:`analyzer_lab.lessons.mechanics.table.model`); loops opened and closed by the §2.2 algorithm.

    State: forward ``[q, q']`` (12 + 12, integrated); inverse ``[q, q', q'']`` of the
    program (closed form, NaN where a leg cannot reach)."""

    id = "table-6dof"
    title = "Work table with six degrees of freedom"
    problem = "Problem 2.5"
    source = "Textbook §2.1, Problem 2.5 (Figs 2.6-2.9); geometry reconstructed"
    summary = (
        "Three planar inductors A, B, C move in the floor plane; legs carry a table that"
        " translates, turns and tilts."
    )
    order = 2.05
    t_end = 5.0
    sampling = 0.025
    undefined = "a leg cannot reach the table joint (joint higher than l)"
    groups = (
        MODE,
        Group("body", "Table, inductors and legs"),
        Group("program", "Table pose program"),
        Group("forces", "Extra inductor forces (forward problem)"),
        Group("hold", "Stepper-motor holding F = -k (r - r_prog) - b (v - v_prog)"),
    )
    modes = ("problem", "feedforward")
    params = (
        PROBLEM,
        Param(
            "feedforward",
            "bool",
            True,
            label="add the program's inverse-dynamics forces",
            group="mode",
            help="forward problem: the inductors also get the forces the inverse problem finds",
        ),
        _number("M_c", 10.0, "table mass M_c", "kg", 0.01, 1e4),
        _number("J_D", 0.2, "table inertia about its tilt axes J_D", "kg m^2", 1e-5, 1e4),
        _number("J_Dz", 0.4, "table inertia about its normal J_Dz", "kg m^2", 1e-5, 1e4),
        _number("m_A", 2.0, "inductor mass m_A", "kg", 1e-3, 1e4),
        _number("m_B", 2.0, "inductor mass m_B", "kg", 1e-3, 1e4),
        _number("m_C", 2.0, "inductor mass m_C", "kg", 1e-3, 1e4),
        _number("m_l", 0.5, "leg mass m_l", "kg", 0.0, 1e3),
        _number("l", 0.3, "leg length l (reconstructed)", "m", 0.01, 10.0),
        _number("r_t", 0.15, "table joint radius r_t (reconstructed)", "m", 0.01, 10.0),
        _number("g", 9.81, "g", "m/s^2", 0.0, 100.0),
        *[
            Param(
                f"{n}_t",
                "formula",
                law,
                label=f"{n}(t) program",
                unit=POSE_UNITS[n],
                group="program",
                help="table pose program: inverse problem; reference of the forward problem",
            )
            for n, law in POSE_LAWS.items()
        ],
        *[Param(f, "formula", "0", label=f"{f} (t)", unit="N", group="forces") for f in FORCES],
        _number("k_hold", 1e4, "inductor holding stiffness k", "N/m", 0.0, 1e7, "hold"),
        _number("b_hold", 200.0, "inductor holding damping b", "N s/m", 0.0, 1e6, "hold"),
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
            {"problem": "forward", "feedforward": False, **REST},
            t_end=3.0,
        ),
        Preset(
            "forward-open-loop",
            "Forward: program forces only (k = 0): the open chain drifts away",
            {"problem": "forward", "k_hold": 0.0, "b_hold": 0.0},
            t_end=3.0,
        ),
    )
    series = (
        *[Series(n, POSE_UNITS.get(n, "m"), f"coordinate {n}") for n in COORDS],
        *[Series(f"{n}_dot", f"{POSE_UNITS.get(n, 'm')}/s", f"velocity {n}'") for n in COORDS],
        *[Series(f, "N", f"inductor force {f}") for f in FORCES],
        Series("constraint_residual", "m", "largest leg-constraint violation (2.17)"),
        Series("position_error", "m", "distance of D from its programmed position"),
        Series("angle_error", "rad", "largest deviation of alpha, beta, phi from the program"),
    )
    readout = ("x_D", "y_D", "z_D", "phi", "position_error", "constraint_residual")
    plots = (
        PlotSpec("Table position", ("x_D", "y_D", "z_D"), "m"),
        PlotSpec("Table angles", ("alpha", "beta", "phi"), "rad"),
        PlotSpec("Table velocities", ("x_D_dot", "y_D_dot", "z_D_dot"), "m/s"),
        PlotSpec("Table angular rates", ("alpha_dot", "beta_dot", "phi_dot"), "rad/s"),
        PlotSpec("Inductor coordinates", INDUCTORS, "m"),
        PlotSpec("Inductor velocities", tuple(f"{n}_dot" for n in INDUCTORS), "m/s"),
        PlotSpec("Inductor forces", FORCES, "N"),
        PlotSpec("Tracking error", ("position_error", "constraint_residual"), "m"),
        PlotSpec("Angle error", ("angle_error",), "rad"),
    )

    # -- pieces -------------------------------------------------------------------------

    def pvec(self, params: Params) -> Array:
        return self.cached("pvec", params, lambda: _frozen([float(params[n]) for n in PHYSICAL]))

    def program(self, params: Params) -> Callable[[Array | float], tuple[Array, Array, Array]]:
        """The pose program: ``t -> (pose, pose', pose'')`` by exact differentiation."""
        return self.cached(
            "program",
            params,
            lambda: formula_derivatives([params[f"{n}_t"].expr for n in POSE], t_symbol),
        )

    def validate(self, params: Params) -> None:
        z, l = float(params["z_D_t"](0.0)), float(params["l"])
        if not np.isfinite(z) or z <= 0 or z >= l:
            raise ParamError(
                "z_D_t",
                "the table height at t = 0 must lie between 0 and the leg length"
                f" l = {l:g} m; got {z:g}",
            )

    def formulas_in_use(self, params: Params) -> list[tuple[str, Formula]]:
        out = [(f"{n}_t", params[f"{n}_t"]) for n in POSE]
        if params["problem"] == "forward":
            out += [(f, params[f]) for f in FORCES]
        return out

    def forces_of(self, params: Params) -> Callable[[float, Array, Array], Array]:
        """Forward problem: inductor forces = extra formulas + program feedforward +
        holding stiffness about the programmed inductor positions."""
        ext = [params[f] for f in FORCES]
        ev, p = self.program(params), self.pvec(params)
        ff, k, b = bool(params["feedforward"]), float(params["k_hold"]), float(params["b_hold"])

        def u(tt: float, q: Array, qd: Array) -> Array:
            F = np.array([float(f(tt)) for f in ext])
            if ff or k or b:
                qp, qdp, qddp, _ = program_state(*ev(float(tt)), p)
                if ff:
                    F = F + inverse_dynamics(qp, qdp, qddp, p)[0]
                F = F - k * (q[6:] - qp[6:]) - b * (qd[6:] - qdp[6:])
            return F

        return u

    # -- one solution, one observation ------------------------------------------------

    def start(self, params: Params, t0: float, y: Array | None) -> Solution:
        p, ev = self.pvec(params), self.program(params)
        if params["problem"] == "inverse":
            return ClosedForm(self.inverse_table(params).states)
        if y is None:
            q0, qd0, _, _ = program_state(*ev(0.0), p)
            y = np.concatenate([q0, qd0])
        rhs = table_model().system.rhs(p, self.forces_of(params), BAUMGARTE, BAUMGARTE)
        return DenseSolution(rhs, t0, y, rtol=1e-7, atol=1e-9, work=WORK_PER_EVALUATION)

    def inverse_table(self, params: Params) -> InverseTable:
        """The inverse problem's table for played frames (one per parameter set)."""
        return self.cached(
            "inverse_table",
            params,
            lambda: InverseTable(
                self.program(params),
                self.pvec(params),
                lambda t, s: self.observe(params, t, s),
                self.series_names(params),
                lambda s, obs: pose_rows(
                    np.nan_to_num(s[:, :12]),
                    self.arrow_scale(params)
                    * np.nan_to_num(np.column_stack([obs[f] for f in FORCES])),
                    float(params["r_t"]),
                ),
            ),
        )

    def observe_one(self, params: Params, t: float, state: Any) -> dict[str, float] | None:
        """The inverse problem's played frames read their scalars from its table."""
        if params["problem"] == "inverse" and np.shape(state)[0] == 1:
            return self.inverse_table(params).scalars(float(t), np.asarray(state)[0])
        return None

    def observe(self, params: Params, t: Array, state: Any) -> dict[str, Array]:
        state = np.asarray(state, dtype=float)
        q, qd = state[:, :12], state[:, 12:24]
        p = self.pvec(params)
        ok = np.all(np.isfinite(state), axis=1)
        F = np.full((len(t), 6), np.nan)
        resid = np.full(len(t), np.nan)
        if params["problem"] == "inverse":
            F, resid = inverse_observed(state, p)
        else:
            u = self.forces_of(params)
            for k in np.nonzero(ok)[0]:
                F[k] = u(float(t[k]), q[k], qd[k])
            if ok.any():
                resid[ok] = constraint_residuals(q[ok], p)
        prog = self.program(params)(t)[0]
        out = {n: q[:, k] for k, n in enumerate(COORDS)}
        out.update({f"{n}_dot": qd[:, k] for k, n in enumerate(COORDS)})
        out.update({f: F[:, k] for k, f in enumerate(FORCES)})
        out["constraint_residual"] = resid
        out["position_error"] = np.linalg.norm(q[:, :3] - prog[:3].T, axis=1)
        out["angle_error"] = np.max(np.abs(q[:, 3:6] - prog[3:].T), axis=1)
        return out

    def run_metrics(self, params: Params, series: dict[str, Array]) -> dict[str, Any]:
        def peak(*names: str) -> float:
            v = np.abs(np.array([series[n] for n in names]))
            return float(np.nanmax(v)) if np.any(np.isfinite(v)) else float("nan")

        return {
            "max_constraint_residual": peak("constraint_residual"),
            "max_position_error": peak("position_error"),
            "max_angle_error": peak("angle_error"),
            "max_inductor_force": peak(*FORCES),
        }

    def notes(self, params: Params) -> list[Note]:
        out = [
            Note(
                "reconstructed",
                "The mechanism (inductor plane, legs of length l with hinges on a table"
                " triangle of radius r_t) is rebuilt from the text: Figs 2.6-2.9 are lost.",
                "Problem 2.5, Figs 2.6-2.9",
                "the text names the virtual axes n (eta), tau, rho and S = f(Z')",
            )
        ]
        if params["problem"] == "forward":
            out.append(
                Note(
                    "info",
                    "Forward problem: the holding stiffness k, b of the stepper motors and the"
                    " Baumgarte stabilization (10 1/s) are not in the source.",
                    "(2.34)",
                )
            )
        return out

    # -- live -----------------------------------------------------------------------

    def arrow_scale(self, params: Params) -> float:
        """Length of the inductor force arrows per newton."""
        return 0.1 / max(float(params["M_c"]) * max(float(params["g"]), 1.0) / 3.0, 1e-9)

    def pose_frame(self, params: Params, fr: Frame, state: Array) -> None:
        if params["problem"] == "inverse":
            hit = self.inverse_table(params).drawn(fr.t, state)
            if hit is not None:
                pose_row(fr, *hit)
                return
        F = np.array([fr.scalars[f] for f in FORCES])
        F = F if np.isfinite(F).all() else np.nan_to_num(F)
        q = state[:12] if np.isfinite(state[:12]).all() else np.nan_to_num(state[:12])
        pose_table(fr, q, self.arrow_scale(params) * F, float(params["r_t"]))

    def scene(self, params: Params) -> SceneSpec:
        return table_scene(float(params["l"]), float(params["r_t"]))

    def derivation(self, params: Params) -> list[DerivationStep]:
        return table_derivation()

    # -- claims -------------------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        p0 = lambda **kw: self.pvec(self.resolve(kw))  # noqa: E731
        rest = np.array([0, 0, 0.2, 0, 0, 0.0])  # table at rest, zero tilt, z_D = 0.2 m
        tilted = np.array([0.01, 0.02, 0.19, 0.08, -0.05, 0.4])

        def dof() -> ClaimResult:
            q, qd, _, _ = program_state(rest, np.zeros(6), np.zeros(6), p0())
            H = table_model().system.parts(0.0, q, qd, p0(), np.zeros(6))["H"]
            r = int(np.linalg.matrix_rank(H))
            return ClaimResult(
                "rank H = 6, 12 - 6 = 6 degrees of freedom", f"rank H = {r}, {12 - r} DOF", r == 6
            )

        def axis_displacement() -> ClaimResult:
            S = axis_displacements(np.array([0.01, -0.02, 0.2, 0, 0, 0.3]), 0.3, 0.15)
            want = np.sqrt(0.3**2 - 0.2**2)
            return close(want, float(max(S, key=lambda v: abs(v - want))), atol=1e-12)

        def ik_constraints() -> ClaimResult:
            p, pose_d = p0(), np.array([0.1, 0, 0.02, 0.1, 0.1, 0.3])
            q, qd, _, _ = program_state(tilted, pose_d, np.zeros(6), p)
            f, c = table_model().system.residuals(0.0, q, qd, p, np.zeros(6))
            return at_most(
                1e-12,
                float(max(np.max(np.abs(f)), np.max(np.abs(c)))),
                "leg constraints and (2.29) at a tilted pose ",
            )

        def plane() -> ClaimResult:
            det, nf = plane_through_joints(tilted, 0.15)
            return at_most(1e-12, max(abs(det), abs(nf)), "|mixed product|, |normal form at D| ")

        def energy_form() -> ClaimResult:
            ok = zero_tilt_energy_is_the_sources()
            want = "T_c = M_c v_D^2/2 + J_D (alpha'^2 + beta'^2 + phi'^2)/2 at zero tilt"
            return ClaimResult(want, "equal" if ok else "differ", ok)

        def static_force() -> ClaimResult:
            p = p0(m_l=0.0)
            q, qd, qdd, _ = program_state(rest, np.zeros(6), np.zeros(6), p)
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
            q = self.solution(ps)(t)[:, :6]
            return at_most(
                1e-6,
                float(np.max(np.abs(q - self.program(ps)(t)[0].T))),
                "max |pose forward - program| over 1.5 s ",
            )

        def fwd_inv() -> ClaimResult:
            ps = self.resolve({"problem": "forward", "F_Ax": "5*sin(3*t)"})
            t = np.linspace(0.0, 1.0, 1001)
            y = self.solution(ps)(t)
            qdd = numerical_second_derivative(t, y[:, 12:].T).T
            p, u, ks = self.pvec(ps), self.forces_of(ps), range(5, len(t) - 5, 10)
            U = np.array([u(float(t[k]), y[k, :12], y[k, 12:]) for k in ks])
            rec = np.array([inverse_dynamics(y[k, :12], y[k, 12:], qdd[k], p)[0] for k in ks])
            return at_most(
                1e-3 * float(np.max(np.abs(U))),
                float(np.max(np.abs(rec - U))),
                "max |F recovered - F applied| (N) ",
            )

        return [
            Claim(
                "six-dof",
                (
                    "Three inductors with two coordinates each and three legs give the table six "
                    "degrees of freedom"
                ),
                "Problem 2.5",
                dof,
            ),
            Claim(
                "axis-displacement",
                (
                    "Zero tilt, z_D = 0.2 m, l = 0.3 m: each inductor sits at S = sqrt(l^2 - "
                    "Z'^2) = 0.2236 m from its joint along its virtual axis"
                ),
                "Problem 2.5, Fig. 2.9 (reconstructed geometry)",
                axis_displacement,
            ),
            Claim(
                "ik-constraints",
                (
                    "The inverse kinematics satisfies the six leg constraints and the velocities "
                    "satisfy (2.29) at a tilted, turned pose"
                ),
                "(2.17), (2.29)",
                ik_constraints,
            ),
            Claim(
                "table-plane",
                "The table plane through A', B', C' (mixed product = 0, normal form) contains D",
                "Problem 2.5",
                plane,
            ),
            Claim(
                "table-energy",
                (
                    "At zero tilt with J_Dz = J_D the table's kinetic energy has the source's "
                    "form 1/2 M (x'^2+y'^2+z'^2) + 1/2 Z_D (alpha'^2+beta'^2+gamma'^2)"
                ),
                "Problem 2.5",
                energy_form,
            ),
            Claim(
                "static-holding-force",
                (
                    "Massless legs, table at rest at z = 0.2 m: each inductor must push inward "
                    "with M g sqrt(l^2 - z^2)/(3 z) = 36.56 N"
                ),
                "Problem 2.5, virtual work",
                static_force,
            ),
            Claim(
                "round-trip-inverse-forward",
                (
                    "The inverse problem's forces, applied open-loop (k = 0), reproduce the pose "
                    "program within 1e-6 over 1.5 s"
                ),
                "(2.34)",
                inv_fwd,
            ),
            Claim(
                "round-trip-forward-inverse",
                (
                    "Forward run with holding stiffness and a 5 sin 3t N push: the inverse "
                    "problem on the sampled motion recovers the six inductor forces within 1e-3 "
                    "of the peak"
                ),
                "(2.34)",
                fwd_inv,
            ),
        ]


LESSON = Table6DOF()
