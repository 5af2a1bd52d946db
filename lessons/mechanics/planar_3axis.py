"""Problem 2.4: the three-coordinate planar motion system, eqs (2.12)-(2.16).

Two planar modules A and B carry a work table that translates and turns by phi.  B
follows A and the angle (2.12): ``x_B = x_A + AB (1 - cos phi)``, ``y_B = y_A + AB sin
phi``.  The source writes the Lagrange equations (2.13) for x_A, y_A only; the system has
three degrees of freedom, so this page uses the consistent model in ``q = (x_A, y_A,
phi)``: the kinetic energy (2.14)-(2.15) (its table term rebuilt) with (2.12) substituted
and the generalized forces (2.16) from the virtual work of the module forces and the
table moment.  The mechanism (its coordinates, drives, body, model and bodies in the
scene) is :mod:`analyzer_lab.lessons.mechanics.positioners.planar3`; the same mechanism
with the loops opened is the fourth example of
:mod:`analyzer_lab.lessons.mechanics.constrained_dynamics`.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Note,
    Params,
    PlotSpec,
    Preset,
    SceneSpec,
    Series,
    at_most,
)
from analyzer_lab.lessons.mechanics.lagrange.model import LagrangeModel
from analyzer_lab.lessons.mechanics.positioners.lesson import (
    T_,
    PositionerLesson,
    arrow,
    is_zero,
    positioner_groups,
    positioner_params,
    positioner_series,
    symbolic_claim,
)
from analyzer_lab.lessons.mechanics.positioners.planar3 import (
    BODY,
    COORDS,
    INPUTS,
    planar3_kinematics,
    planar3_phi,
    planar3_scene,
    planar3_symbols,
    pose_planar3,
    reduced_model,
)
from sympy.physics.mechanics import dynamicsymbols

Array = np.ndarray


class Planar3Axis(PositionerLesson):
    """Problem 2.4 as the consistent 3-DOF model q = (x_A, y_A, phi): (2.12)-(2.16) with
    the reconstructed T (2.15) and (2.12) substituted."""

    id = "planar-3axis"
    title = "Three-coordinate planar motion system"
    problem = "Problem 2.4"
    source = "Textbook §2.1, Problem 2.4, eqs (2.12)-(2.16)"
    summary = (
        "Two planar modules A and B carry a table that translates and turns by phi; consistent "
        "model in x_A, y_A, phi."
    )
    order = 2.04
    coords = COORDS
    inputs = INPUTS
    physical = tuple(p.name for p in BODY)
    groups = positioner_groups("Modules A, B and the table")
    params = positioner_params(COORDS, INPUTS, BODY)
    series = positioner_series(
        COORDS,
        INPUTS,
        (
            Series("x_B", "m", "module B coordinate x_B (2.12)"),
            Series("y_B", "m", "module B coordinate y_B (2.12)"),
        ),
    )
    readout = ("x_A", "y_A", "phi", "x_B", "y_B", "F_Ax", "F_Ay", "M_phi")
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
        return reduced_model()

    def three_dof_equations(self) -> list[sp.Expr]:
        """The consistent 3-DOF equations written out by hand (left - right), Problem 2.4."""
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

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        xB, yB = planar3_kinematics(q[0], q[1], q[2], float(params["AB"]), np)
        return {"x_B": xB, "y_B": yB}

    def notes(self, params: Params) -> list[Note]:
        return [
            Note(
                "reconstructed",
                "Three generalized coordinates x_A, y_A, phi: the source writes (2.13) for"
                " x_A, y_A only, but the table also turns.",
                "(2.13)",
                "(2.12) ties x_B, y_B to x_A, y_A and phi: three degrees of freedom",
            ),
            Note(
                "reconstructed",
                "The table's kinetic energy T_AB in (2.15) is lost in the extraction: rebuilt"
                " as m_AB v_A^2/2 + J_A phi'^2/2 (exact when its centre of mass is at A).",
                "(2.15)",
                "only the symbols m_AB and J_A,pr survive",
            ),
        ]

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
                (
                    "Valid for |phi| <= pi/2 (arcsin) and phi in [0, pi] (arccos); atan2 covers "
                    "the full range."
                ),
                (
                    r"\varphi=\arcsin\frac{y_B-y_A}{AB}=\arccos\left(1-\frac{x_B-x_A}{AB}\right)="
                    r"\operatorname{atan2}\left(y_B-y_A,\;AB-(x_B-x_A)\right)"
                ),
                "(2.12)",
            ),
            DerivationStep(
                "Lagrange equations",
                (
                    "The source writes them for q1 = x_A, q2 = y_A only; the system has three "
                    "degrees of freedom, so phi is the third coordinate."
                ),
                (
                    r"\frac{d}{dt}\frac{\partial T}{\partial \dot q}-\frac{\partial T}{\partial "
                    r"q}=-\frac{\partial U}{\partial q}+Q_q,\quad q\in\{x_A,y_A,\varphi\}"
                ),
                "(2.13)",
                reconstructed=(
                    "consistent 3-DOF reading: phi added as a generalized coordinate, (2.13) has "
                    "only x_A, y_A"
                ),
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
                reconstructed=(
                    "T_AB lost in the extraction; rebuilt from the surviving symbols (exact when "
                    "the table's centre of mass is at A)"
                ),
            ),
            DerivationStep(
                "Generalized forces (virtual work)",
                (
                    "Drive forces F_A on A, F_B on B, moment M_phi on the table; dx_B = dx_A + "
                    "AB sin(phi) dphi, dy_B = dy_A + AB cos(phi) dphi."
                ),
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
                "Equations of motion (Lagrange equations of the 2nd kind)",
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
                else (
                    "x_A(t), y_A(t), phi(t) given: x_B, y_B from (2.12); with F_B given, the "
                    "left-hand sides give Q_x, Q_y, Q_phi and so F_Ax, F_Ay, M_phi."
                ),
                r"\ddot q=M(q)^{-1}\left(F(q,\dot q)+Q(t)\right)"
                if params["problem"] == "forward"
                else (
                    r"Q=M(q)\ddot q-F(q,\dot q),\quad "
                    r"F_{Ax}=Q_x-F_{Bx},\;F_{Ay}=Q_y-F_{By},\;M_\varphi=Q_\varphi-AB\,(F_{Bx}\sin"
                    r"\varphi+F_{By}\cos\varphi)"
                ),
                "(2.13)-(2.16)",
            ),
        ]

    def scene_size(self, params: Params) -> float:
        return 2.0 * float(params["AB"]) + 0.5

    def scene(self, params: Params) -> SceneSpec:
        r = self.coarse_run(params)
        q = np.array([r.series["x_A"], r.series["y_A"], r.series["phi"]])
        trace = q[:, np.nonzero(np.all(np.isfinite(q), axis=0))[0][::10]]
        vectors = {"F_A": (40, 160, 60), "F_B": (200, 60, 60), "M_phi": (140, 60, 200)}
        return planar3_scene(float(params["AB"]), trace, vectors)

    def pose(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        AB = float(params["AB"])
        xA, yA, phi = float(q[0]), float(q[1]), float(q[2])
        xB, yB = planar3_kinematics(xA, yA, phi, AB, math)
        A, B, mid, h = pose_planar3(fr, AB, xA, yA, xB, yB, phi)
        fr.vectors["F_A"] = arrow(A + (0.0, 0.0, 2 * h), (scale * u[0], scale * u[1], 0))
        fr.vectors["F_B"] = arrow(B + (0.0, 0.0, 2 * h), (scale * u[2], scale * u[3], 0))
        fr.vectors["M_phi"] = arrow(mid + (0.0, 0.0, h), (0, 0, -scale * u[4]))

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            return all(is_zero(a - b) for a, b in zip(m.eom(), self.three_dof_equations()))

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
            return all(is_zero(e) for e in (G - want))

        def ik() -> ClaimResult:
            AB, phi = 0.5, 0.3
            xB, yB = planar3_kinematics(0.1, -0.2, phi, AB, np)
            a, b, c = planar3_phi(0.1, -0.2, float(xB), float(yB), AB)
            return at_most(
                1e-12,
                max(abs(a - phi), abs(b - phi), abs(c - phi)),
                "max |phi recovered - 0.3| (arcsin, arccos, atan2) ",
            )

        return [
            Claim(
                "eq-3dof",
                (
                    "LagrangesMethod with (2.12) substituted in (2.15) gives the consistent "
                    "3-DOF equations in x_A, y_A, phi"
                ),
                "(2.12)-(2.16)",
                symbolic_claim(eq_ok, "3-DOF equations"),
            ),
            Claim(
                "q-phi",
                (
                    "Virtual work: Q_x = F_Ax + F_Bx, Q_y = F_Ay + F_By, Q_phi = M_phi + AB "
                    "(F_Bx sin phi + F_By cos phi)"
                ),
                "(2.16)",
                symbolic_claim(q_phi, "generalized forces"),
            ),
            Claim(
                "inverse-kinematics",
                (
                    "phi = arcsin((y_B - y_A)/AB) = arccos(1 - (x_B - x_A)/AB) recovers phi = "
                    "0.3 (AB = 0.5)"
                ),
                "(2.12)",
                ik,
            ),
            Claim(
                "round-trip-forward-inverse",
                (
                    "Forward then inverse recovers F_Ax, F_Ay, M_phi (F_B given) within 1e-4 of "
                    "the peak"
                ),
                "(2.13)-(2.16)",
                self.forward_inverse_check(
                    {
                        "F_Ax": "2*sin(t)",
                        "F_Ay": "1",
                        "F_By": "0.5*cos(t)",
                        "M_phi": "0.1*cos(2*t)",
                    },
                    "max |(F_Ax, F_Ay, M_phi) recovered - applied| ",
                ),
            ),
            Claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces the program x_A, y_A, phi to 1e-8",
                "(2.13)-(2.16)",
                self.inverse_forward_check({"F_By": "0.2"}, "max |q forward - q law| "),
            ),
        ]


LESSON = Planar3Axis()
