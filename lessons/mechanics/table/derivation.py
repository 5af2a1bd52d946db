"""The derivation shown by the 6-DOF table lesson (Problem 2.5, geometry reconstructed)."""

from __future__ import annotations

import sympy as sp
from analyzer_lab.lessons.kit.contract import DerivationStep
from analyzer_lab.lessons.mechanics.table.model import table_model


def table_derivation() -> list[DerivationStep]:
    """The steps from the generalized coordinates to the closed-form equations."""
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


__all__ = ["table_derivation"]
