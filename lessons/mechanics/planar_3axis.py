"""Problem 2.4: the three-coordinate planar motion system, eqs (2.12)-(2.16).

Two planar modules A and B carry a work table that translates and turns by phi.  B
follows A and the angle (2.12): ``x_B = x_A + AB (1 - cos phi)``, ``y_B = y_A + AB sin
phi``.  The source writes the Lagrange equations (2.13) for x_A, y_A only; the system has
three degrees of freedom, so this page uses the consistent model in ``q = (x_A, y_A,
phi)``: the kinetic energy (2.14)-(2.15) (its table term rebuilt) with (2.12) substituted
and the generalized forces (2.16) from the virtual work of the module forces and the
table moment.  The same mechanism with the loops opened is the third example of
:mod:`analyzer_lab.lessons.mechanics.constrained_dynamics`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.bodies import IDENTITY_Q, bounds_of, box, quat_z
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Note,
    Param,
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
    Coord,
    Input,
    PositionerLesson,
    arrow,
    is_zero,
    positioner_groups,
    positioner_params,
    positioner_series,
    sym,
    symbolic_claim,
)
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

Array = np.ndarray


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
    mA, mB, mAB, J, AB = (sym(n, positive=True) for n in ("m_A", "m_B", "m_AB", "J_A", "AB"))
    FAx, FAy, FBx, FBy, Mphi = (sym(n) for n in ("F_Ax", "F_Ay", "F_Bx", "F_By", "M_phi"))
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


def planar3_model(q: list[Any], xB: Any, yB: Any) -> LagrangeModel:
    """The Lagrange model of the mechanism in the coordinates ``q`` with module B at
    (``xB``, ``yB``): T (2.14)-(2.15) (the table term rebuilt), the module forces at A and
    B and the table moment M_phi (the virtual work of (2.16)).  B is either (2.12) of
    q = (x_A, y_A, phi) (this page) or two coordinates of its own (the loops opened,
    :mod:`analyzer_lab.lessons.mechanics.constrained_dynamics`)."""
    s = planar3_symbols()
    xA, yA, phi = s["xA"], s["yA"], s["phi"]
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
        q,
        T,
        sp.S.Zero,
        T_,
        [s["mA"], s["mB"], s["mAB"], s["J"], s["AB"]],
        [s["FAx"], s["FAy"], s["FBx"], s["FBy"], s["Mphi"]],
        forcelist=forces,
        frame=N,
    )


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
    groups = positioner_groups("Modules A, B and the table")
    params = positioner_params(
        coords,
        inputs,
        (
            Param(
                "m_A",
                "float",
                2.0,
                label="module A mass m_A",
                unit="kg",
                min=1e-3,
                max=1e4,
                group="body",
            ),
            Param(
                "m_B",
                "float",
                1.5,
                label="module B mass m_B",
                unit="kg",
                min=1e-3,
                max=1e4,
                group="body",
            ),
            Param(
                "m_AB",
                "float",
                3.0,
                label="table mass m_AB",
                unit="kg",
                min=0.0,
                max=1e4,
                group="body",
            ),
            Param(
                "J_A",
                "float",
                0.4,
                label="table inertia about A, J_A,pr",
                unit="kg m^2",
                min=1e-6,
                max=1e4,
                group="body",
            ),
            Param(
                "AB", "float", 0.5, label="distance AB", unit="m", min=1e-3, max=100.0, group="body"
            ),
        ),
    )
    series = positioner_series(
        coords,
        inputs,
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
        s = planar3_symbols()
        xB, yB = planar3_kinematics(s["xA"], s["yA"], s["phi"], s["AB"])  # (2.12)
        return planar3_model([s["xA"], s["yA"], s["phi"]], xB, yB)

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

    def _absolute(self, params: Params, q: Array) -> tuple[Array, Array]:
        AB = float(params["AB"])
        xB, yB = planar3_kinematics(q[0], q[1], q[2], AB, np)
        return np.array([q[0], q[1], 0.0]), np.array(
            [xB - AB, yB, 0.0]
        )  # A->B = AB(-cos phi, sin phi)

    def scene(self, params: Params) -> SceneSpec:
        AB = float(params["AB"])
        r = self.coarse_run(params)
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

    def pose(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        AB = float(params["AB"])
        xA, yA, phi = float(q[0]), float(q[1]), float(q[2])
        xB, yB = planar3_kinematics(xA, yA, phi, AB, math)
        h = 0.25 * AB * 0.3
        A, B = np.array([xA, yA, 0.0]), np.array([xB - AB, yB, 0.0])  # as :meth:`_absolute`
        mid = np.array([(xA + (xB - AB)) / 2, (yA + yB) / 2, h])  # the middle of AB, raised
        fr.poses["module A"] = (A, IDENTITY_Q.copy())
        fr.poses["module B"] = (B, IDENTITY_Q.copy())
        fr.poses["table"] = (mid, quat_z(np.pi - phi))
        fr.points["C (middle of AB)"] = mid[None, :]
        fr.vectors["F_A"] = arrow((xA, yA, 2 * h), (scale * u[0], scale * u[1], 0))
        fr.vectors["F_B"] = arrow((xB - AB, yB, 2 * h), (scale * u[2], scale * u[3], 0))
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
