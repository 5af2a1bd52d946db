"""Problem 2.5: the work table with six degrees of freedom (Figs 2.6-2.9).

Three planar inductors A, B, C move in the floor plane; rigid legs join them to the
joints A', B', C' of a table that translates, turns and tilts.  The generalized
coordinates of the source are the six inductor coordinates; its kinetic energy is the
sum of the table's, the inductors' and the legs' (T = T_c + T_A + ... + T_CC'), and the
generalized forces are the inductor forces.  The mechanism survives only in figures lost
in the extraction, so its geometry is **reconstructed** (:mod:`lessons.core.table6dof`);
the equations come from opening the loops at the legs and closing them with the
algorithm of §2.2, (2.25)-(2.34).  Inverse problem: a table pose program gives the
inductor coordinates and forces; forward problem: the program's forces (feedforward) plus
the holding stiffness of the linear stepper motors drive the table.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import sympy as sp

from lessons.core.contract import (
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
from lessons.core.formula import Formula, t_symbol
from lessons.core.lagrange import formula_derivatives, numerical_second_derivative
from lessons.core.positioner_lesson import MODE, PROBLEM, DynamicsLesson
from lessons.core.steppers import ClosedForm, DenseSolution, Solution
from lessons.core.table6dof import (
    COORDS,
    FORCES,
    INDUCTORS,
    PHYSICAL,
    POSE,
    axis_displacements,
    constraint_residual,
    inverse_dynamics,
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
    (see :mod:`lessons.core.table6dof`); loops opened and closed by the §2.2 algorithm.

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

            def states(t: Array) -> Array:
                out = np.full((len(t), 36), np.nan)
                pose = ev(t)
                for k in range(len(t)):
                    q, qd, qdd, ok = program_state(*(a[:, k] for a in pose), p)
                    if ok:
                        out[k] = np.concatenate([q, qd, qdd])
                return out

            return ClosedForm(states)
        if y is None:
            q0, qd0, _, _ = program_state(*ev(0.0), p)
            y = np.concatenate([q0, qd0])
        rhs = table_model().system.rhs(p, self.forces_of(params), BAUMGARTE, BAUMGARTE)
        return DenseSolution(rhs, t0, y, rtol=1e-7, atol=1e-9)

    def observe(self, params: Params, t: Array, state: Any) -> dict[str, Array]:
        state = np.asarray(state, dtype=float)
        q, qd = state[:, :12], state[:, 12:24]
        p = self.pvec(params)
        ok = np.all(np.isfinite(state), axis=1)
        F = np.full((len(t), 6), np.nan)
        resid = np.full(len(t), np.nan)
        u = self.forces_of(params) if params["problem"] == "forward" else None
        for k in np.nonzero(ok)[0]:
            if u is None:
                F[k] = inverse_dynamics(q[k], qd[k], state[k, 24:], p)[0]
            else:
                F[k] = u(float(t[k]), q[k], qd[k])
            resid[k] = constraint_residual(q[k], p)
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

    def pose_frame(self, params: Params, fr: Frame, state: Array) -> None:
        F = np.nan_to_num(np.array([fr.scalars[f] for f in FORCES]))
        scale = 0.1 / max(float(params["M_c"]) * max(float(params["g"]), 1.0) / 3.0, 1e-9)
        pose_table(fr, np.nan_to_num(state[:12]), scale * F, float(params["r_t"]))

    def scene(self, params: Params) -> SceneSpec:
        return table_scene(float(params["l"]), float(params["r_t"]))

    def derivation(self, params: Params) -> list[DerivationStep]:
        tm = table_model()
        ge = (
            r"\frac{d}{dt}\frac{\partial T}{\partial \dot q_i}-\frac{\partial T}{\partial "
            r"q_i}=-\frac{\partial U}{\partial q_i}+Q_{q_i},\quad i=1,\dots,6"
        )
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
                (
                    "Each rigid leg of length l joins inductor k (ball joint) to table joint "
                    "A'_k (hinge parallel to the opposite side of the table triangle): the "
                    "inductor moves along the virtual axis n (eta), tau, rho perpendicular to "
                    "that side."
                ),
                (
                    r"(\vec r_{A}-\vec r_{A'})\cdot R\,\vec e_A=0,\qquad |\vec r_{A}-\vec "
                    r"r_{A'}|^2-l^2=0\quad(\text{and likewise } B, C)"
                ),
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
                (
                    r"(\vec r_{A'}-\vec r_0)\cdot\left[(\vec r_{B'}-\vec r_0)\times(\vec "
                    r"r_{C'}-\vec r_0)\right]=0,\qquad x\cos\alpha+y\cos\beta+z\cos\gamma-h=0"
                ),
                "Problem 2.5",
            ),
            DerivationStep(
                "Kinetic energy", "", r"T=T_c+T_A+T_B+T_C+T_{AA'}+T_{BB'}+T_{CC'}", "Problem 2.5"
            ),
            DerivationStep(
                "Table: translation of D and rotation about D",
                (
                    "R = Rz(phi) Ry(beta) Rx(alpha); at zero tilt and J_Dz = J_D this is the "
                    "source's 1/2 M (x'^2+y'^2+z'^2) + 1/2 Z_D (alpha'^2+beta'^2+gamma'^2)."
                ),
                sp.Eq(sp.Symbol("T_c"), sp.simplify(tm.T_table)),
                "Problem 2.5",
                reconstructed=(
                    "the isotropic coefficient printed 'Z_D' read as the table inertia; angular "
                    "velocity of the ZYX angles"
                ),
            ),
            DerivationStep(
                "Inductors",
                "",
                (
                    r"T_A=\tfrac12 m_A(\dot x_A^2+\dot y_A^2),\;T_B=\tfrac12 m_B(\dot x_B^2+\dot "
                    r"y_B^2),\;T_C=\tfrac12 m_C(\dot x_C^2+\dot y_C^2)"
                ),
                "Problem 2.5",
            ),
            DerivationStep(
                "Legs (slender rods)",
                "End velocities v_A (inductor) and v_A' (table joint).",
                (
                    r"T_{AA'}=\frac{m_l}{6}\left(v_A^2+\vec v_A\cdot\vec "
                    r"v_{A'}+v_{A'}^2\right)\quad(\text{and likewise } BB', CC')"
                ),
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
                (
                    "12 coordinates (table pose + inductors), six leg constraints, multipliers "
                    "eliminated by (2.33)-(2.34): the six equations of the source in closed form."
                ),
                (
                    r"A\ddot q=B+S F+H^{T}\lambda,\quad H\ddot q=-\Phi,\quad "
                    r"H\in\mathbb{R}^{6\times 12}"
                ),
                "(2.25), (2.30), (2.34)",
            ),
        ]

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
