"""The three-coordinate planar motion system of Problem 2.4, eqs (2.12)-(2.16).

Two planar modules A and B carry a work table that translates and turns by phi.  B
follows A and the angle (2.12): ``x_B = x_A + AB (1 - cos phi)``, ``y_B = y_A + AB sin
phi``.  This module is the mechanism, read by the page of Problem 2.4
(:mod:`analyzer_lab.lessons.mechanics.planar_3axis`, the reduced coordinates ``q = (x_A,
y_A, phi)``) and by its loops-opened example of §2.2
(:mod:`analyzer_lab.lessons.mechanics.lagrange.examples`, five coordinates with (2.12) as
two constraints): its coordinates, drives and body with the page's values, the coupling
(2.12) and its inverse, the Lagrange model (the kinetic energy (2.14)-(2.15) with the
table term rebuilt, the virtual work (2.16)), and its bodies in the scene.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.bodies import IDENTITY_Q, bounds_of, box, quat_z
from analyzer_lab.lessons.kit.contract import Frame, Param, SceneSpec
from analyzer_lab.lessons.kit.formula import parse_formula
from analyzer_lab.lessons.kit.steppers import DenseSolution
from analyzer_lab.lessons.mechanics.lagrange.model import LagrangeModel
from analyzer_lab.lessons.mechanics.positioners.lesson import T_, Coord, Input, sym
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

Array = np.ndarray

#: the reduced coordinates, with the inverse problem's default motion law
COORDS = (
    Coord("x_A", "x_A", "m", 0.0, "0.1*sin(t)"),
    Coord("y_A", "y_A", "m", 0.0, "0.05*(1 - cos(t))"),
    Coord("phi", "phi", "rad", 0.0, "0.3*sin(t/2)"),
)
#: the drives: the module forces at A and B and the table moment (2.16)
INPUTS = (
    Input("F_Ax", "module A force F_Ax", "N", "2*sin(t)"),
    Input("F_Ay", "module A force F_Ay", "N", "1"),
    Input("F_Bx", "module B force F_Bx", "N", "0", unknown=False),
    Input("F_By", "module B force F_By", "N", "0.5*cos(t)", unknown=False),
    Input("M_phi", "table moment M_phi", "N m", "0"),
)
#: the body, in the model's parameter order
BODY = (
    Param("m_A", "float", 2.0, "module A mass m_A", "kg", 1e-3, 1e4, group="body"),
    Param("m_B", "float", 1.5, "module B mass m_B", "kg", 1e-3, 1e4, group="body"),
    Param("m_AB", "float", 3.0, "table mass m_AB", "kg", 0.0, 1e4, group="body"),
    Param("J_A", "float", 0.4, "table inertia about A, J_A,pr", "kg m^2", 1e-6, 1e4, group="body"),
    Param("AB", "float", 0.5, "distance AB", "m", 1e-3, 100.0, group="body"),
)


def body_values() -> Array:
    """The model's parameter vector at the body's default values."""
    return np.array([float(p.default) for p in BODY])


def body_value(name: str) -> float:
    """One of the body's default values, by name (``"AB"``, ...)."""
    return next(float(p.default) for p in BODY if p.name == name)


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
    """The coordinates x_A, y_A, phi (functions of t), the body and the drives."""
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
    q = (x_A, y_A, phi) (:func:`reduced_model`) or two coordinates of its own (the loops
    opened, :mod:`analyzer_lab.lessons.mechanics.lagrange.examples`)."""
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


@cache
def reduced_model() -> LagrangeModel:
    """The consistent 3-DOF model in q = (x_A, y_A, phi): (2.12) substituted in (2.15)."""
    s = planar3_symbols()
    xB, yB = planar3_kinematics(s["xA"], s["yA"], s["phi"], s["AB"])  # (2.12)
    return planar3_model([s["xA"], s["yA"], s["phi"]], xB, yB)


@cache
def default_trace() -> Array:
    """``(x_A, y_A, phi)`` every 0.1 s over 10 s of the forward problem at the default
    drives and body, from rest at the origin: the path the floor of the scene is sized by
    where no run of the page's own is at hand."""
    drives = [parse_formula(i.default) for i in INPUTS]
    u = lambda t, q, qd: np.array([float(f(t)) for f in drives])  # noqa: E731
    y0 = np.array([c.q0 for c in COORDS] + [0.0] * len(COORDS))
    solution = DenseSolution(reduced_model().rhs(body_values(), u), 0.0, y0)
    return solution(np.linspace(0.0, 10.0, 101))[:, : len(COORDS)].T


def module_positions(AB: float, xA: Any, yA: Any, xB: Any, yB: Any) -> tuple[Array, Array]:
    """Where modules A and B are drawn: A at (x_A, y_A), B at (x_B - AB, y_B) (the table
    from A to B is AB (-cos phi, sin phi))."""
    return np.array([xA, yA, 0.0]), np.array([xB - AB, yB, 0.0])


def planar3_scene(AB: float, trace: Array, vectors: dict[str, tuple[int, int, int]]) -> SceneSpec:
    """The floor under the path ``trace`` (``(x_A, y_A, phi)`` by column), modules A and
    B, the table, the point C in the middle of AB, and the moving ``vectors``."""
    pts = [np.zeros(3), np.array([-AB, 0, 0])]
    for xA, yA, phi in trace.T:
        xB, yB = planar3_kinematics(xA, yA, phi, AB, np)
        pts += module_positions(AB, xA, yA, xB, yB)
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
        moving_vectors=vectors,
    )


def pose_planar3(
    fr: Frame, AB: float, xA: float, yA: float, xB: float, yB: float, phi: float
) -> tuple[Array, Array, Array, float]:
    """Pose modules A and B, the table and C for one state; ``(A, B, C, h)`` with C the
    middle of AB raised to the modules' top ``h``, where the vectors are drawn from."""
    h = 0.3 * (0.25 * AB)
    A, B = module_positions(AB, xA, yA, xB, yB)
    mid = (A + B) / 2 + (0.0, 0.0, h)
    fr.poses["module A"] = (A, IDENTITY_Q.copy())
    fr.poses["module B"] = (B, IDENTITY_Q.copy())
    fr.poses["table"] = (mid, quat_z(np.pi - phi))
    fr.points["C (middle of AB)"] = mid[None, :]
    return A, B, mid, h
