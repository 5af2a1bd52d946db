"""The derivation pages of the self-study tasks C2.1-C2.6: statement, energies, equations.

For the task chosen: the task's statement with the textbook's numbers (and the reading
of a garbled formula in use), the generalized coordinates, T and U, the generalized
forces, the Lagrange equations (2.5), (2.13) as LagrangesMethod gives them (with the
constraints (2.17) and multipliers (2.25), (2.30)-(2.34) for C2.6) and the closed forms
the tasks allow (C2.1a, C2.1b, C2.1c's energy integral, C2.2 along the line).
Every arrangement beyond the figures' labels carries its reconstruction line
(:func:`caveat`), shown on the page and as a note.
"""

from __future__ import annotations

import sympy as sp
from analyzer_lab.lessons.kit.contract import DerivationStep, Params
from analyzer_lab.lessons.mechanics.manipulators.models import TIME, Model
from analyzer_lab.lessons.mechanics.manipulators.tasks import MC_READINGS, MG_READINGS, family

_FIGURE = {
    "C2.1": "Fig. 2.13",
    "C2.2": "Fig. 2.14",
    "C2.3": "Fig. 2.15",
    "C2.4": "Fig. 2.16",
    "C2.5": "Fig. 2.3",
    "C2.6": "Fig. 2.6",
}
_MG_LAWS = (
    r"M_g=\begin{cases}2\varphi,&0\le\varphi\le4\pi\\8\pi,&\varphi>4\pi\end{cases}",
    r"M_g=\begin{cases}2,&0\le\varphi\le4\pi\\8,&\varphi>4\pi\end{cases}",
    r"M_g=\begin{cases}2\varphi,&0\le\varphi\le\pi/4\\8\pi,&\varphi>\pi/4\end{cases}",
)
_MG_WHY = (
    "M_g read as 2 phi up to 4 pi and 8 pi beyond: token-consistent and continuous at 4 pi "
    "(alternatives: the constants 2 / 8, or a switch at pi/4)",
    "M_g read as the constants 2 and 8 N m (alternative: 2 phi / 8 pi, from the pi/phi tokens)",
    "M_g switch read as pi/4 (alternative: 4 pi, which makes M_g continuous)",
)


def source_of(task: str) -> str:
    return f"{task[:4]}, {_FIGURE[family(task)]}"


def caveat(params: Params) -> tuple[str, str]:
    """The reconstruction line of the task (what is read into the source) and its evidence."""
    task = params["task"]
    fam = family(task)
    if task == "C2.1b":
        if params["Mc_reading"] == MC_READINGS[0]:
            return (
                "M_c read as 0.1 phi (alternative: the constant 0.1 N m)",
                "three phi tokens, no dots",
            )
        return "M_c read as the constant 0.1 N m (alternative: 0.1 phi)", "the formula is garbled"
    if task == "C2.1c":
        why = _MG_WHY[list(MG_READINGS).index(params["Mg_reading"])]
        return why, "the formula of C2.1c survives only as tokens"
    texts = {
        "C2.1": "the model J phi'' = M_g - M_c (J and the plane of motion not stated) is a reading",
        "C2.2": "the model (coordinate x, forces along the line) and the role of l_AM are readings",
        "C2.3": "only the labels of Fig. 2.15 survive; the arrangement is a reading",
        "C2.4": "the stacking order X-Y-Z is a reading of the figure's axes",
        "C2.5": "the offset l of G from A is chosen to show the coupling",
        "C2.6": "table and leg kinetic energies of Problem 2.5 are not reconstructable; "
        "inductors as point masses",
    }
    return texts[fam], f"only the labels of {_FIGURE[fam]} survive"


def _c21_law(params: Params) -> str:
    task = params["task"]
    if task == "C2.1a":
        return r"M_g=2\ \mathrm{N\,m},\ M_c=0"
    if task == "C2.1b":
        mc = r"0.1\varphi" if params["Mc_reading"] == MC_READINGS[0] else "0.1"
        return rf"M_g=2\ \mathrm{{N\,m}},\ M_c={mc},\ \varphi_0=0,\ \varphi_k=180^\circ"
    law = _MG_LAWS[list(MG_READINGS).index(params["Mg_reading"])]
    return law + r",\ M_c=0.1\sin\varphi"


def _statement(params: Params) -> DerivationStep:
    task = params["task"]
    why = caveat(params)[0]
    src = source_of(task)
    if family(task) == "C2.1":
        text = (
            "Link 1 turns about O under the driving moment M_g and the resisting moment M_c; "
            "l_OM = 0.2 m, m1 = 0.4 kg, J0 = 0.01 kg m^2.  Whether J includes m1 l_OM^2 and "
            "whether the plane is vertical are not stated (choices 'inertia', 'vertical')."
        )
        return DerivationStep("Task", text, _c21_law(params), src, reconstructed=why)
    if family(task) == "C2.2":
        laws = {
            "C2.2a": r"F_g=5\ \mathrm{N},\ F_c=0",
            "C2.2b": r"F_g=2\sin t,\ F_c=0,\ t_0=0,\ t=10",
            "C2.2c": r"F_g=2\sin t,\ F_c=t,\ t_0=0,\ t=10",
        }[task]
        text = (
            "Point M of link 1 moves on y = x + 1; m = 0.5 kg, l_AM = 0.2 m. Forces act along "
            "the line; l_AM only sets the drawn link."
        )
        return DerivationStep("Task", text, laws, src, reconstructed=why)
    text = {
        "C2.3a": "Fig. 2.15a (S, M, phi): an arm turning by phi carries a slider M at radius S.",
        "C2.3b": "Fig. 2.15b (S1, M, S2): stage 1 moves along X by S1 and carries stage 2 "
        "moving along Y by S2.",
        "C2.3c": "Fig. 2.15c (M, phi, S): a carriage moving along X by S carries a link of "
        "length l turning by phi; M at its end.",
        "C2.4a": "one coordinate at a time",
        "C2.4b": "two coordinates at once",
        "C2.4c": "x, y and z together",
        "C2.5": "The moving element of the two-coordinate positioner (Fig. 2.3) also turns by "
        "phi in its plane: x, y of the drive point A and phi are independent; its centre of "
        "mass G lies l from A.",
        "C2.6a": "inductor A fixed at x_A = a, y_A = b, z_A = 0",
        "C2.6b": "A fixed at (a, b, 0) and B fixed at (c, d, 0)",
        "C2.6c": "A, B and C moving on one circle of radius R about x_O = y_O = z_O = 0",
    }[task]
    if family(task) == "C2.4":
        text = (
            "Fig. 2.16: the X stage (m1) carries the Y stage (m2) which carries the Z stage "
            f"(m3); {text} (moving: {params['axes']})."
        )
    elif family(task) == "C2.6":
        text = (
            f"Fig. 2.6 (Problem 2.5): {text}.  Only the inductors' energies T_A, T_B, T_C "
            "survive; the table and leg energies and the mechanism geometry are lost, so the "
            "table's share is left out."
        )
    return DerivationStep("Task", text + " Illustrative numbers.", None, src, reconstructed=why)


def _closed_forms(params: Params) -> list[DerivationStep]:
    task = params["task"]
    t = sp.Symbol("t", real=True)
    J = sp.Symbol("J", positive=True)
    t180 = sp.Symbol("t_180")
    if task == "C2.1a":
        return [
            DerivationStep(
                "Closed form (horizontal plane)",
                "J phi'' = 2 gives phi = t^2/J, so phi = pi at t = sqrt(pi J).",
                sp.Eq(t180, sp.sqrt(sp.pi * J)),
                "C2.1a",
            )
        ]
    if task == "C2.1b" and params["Mc_reading"] == MC_READINGS[0]:
        return [
            DerivationStep(
                "Closed form (horizontal plane, M_c = 0.1 phi)",
                "phi = 20 (1 - cos(sqrt(0.1/J) t)).",
                sp.Eq(t180, sp.acos(1 - sp.pi / 20) / sp.sqrt(sp.Rational(1, 10) / J)),
                "C2.1b",
            )
        ]
    if task == "C2.1b":
        return [
            DerivationStep(
                "Closed form (horizontal plane, M_c = 0.1 N m)",
                "J phi'' = 1.9 gives phi = 0.95 t^2/J, so phi = pi at t = sqrt(2 pi J/1.9).",
                sp.Eq(t180, sp.sqrt(2 * sp.pi * J / sp.Rational(19, 10))),
                "C2.1b",
            )
        ]
    if task == "C2.1c":
        slope, const, _, switch = MG_READINGS[params["Mg_reading"]]
        phi_s, w0 = sp.nsimplify(switch, [sp.pi]), sp.Symbol(r"\dot\varphi_0")
        work = sp.Rational(str(slope)) * phi_s**2 / 2 + sp.Rational(str(const)) * phi_s
        work -= sp.Rational(1, 10) * (1 - sp.cos(phi_s))
        return [
            DerivationStep(
                "Energy integral up to the switch (horizontal plane)",
                "J phi'^2/2 - J phi'(0)^2/2 = integral of (M_g - M_c) dphi from 0 to the switch "
                "angle: the speed with which the link reaches it.",
                sp.Eq(sp.Symbol(r"\dot\varphi_s") ** 2, w0**2 + 2 * work / J),
                "C2.1c",
            )
        ]
    if family(task) == "C2.2":
        m = sp.Symbol("m", positive=True)
        return [
            DerivationStep(
                "Along the line",
                "s = sqrt(2) x is the path length: m s'' = F_g - F_c (horizontal plane).",
                sp.Eq(
                    m * sp.Derivative(sp.Function("s")(t), (t, 2)),
                    sp.Function("F_g")(t) - sp.Function("F_c")(t),
                ),
                "C2.2",
            )
        ]
    return []


def derivation_steps(params: Params, model: Model) -> list[DerivationStep]:
    """The page of the task chosen, from its statement to its closed forms."""
    src = source_of(params["task"])
    steps = [
        _statement(params),
        DerivationStep("Generalized coordinates", ", ".join(model.coords), sp.Matrix(model.q), src),
        DerivationStep("Kinetic energy", "", sp.Eq(sp.Symbol("T"), sp.simplify(model.T)), src),
        DerivationStep(
            "Potential energy",
            "g_e = g when the plane is vertical, else 0.",
            sp.Eq(sp.Symbol("U"), model.U),
            src,
        ),
        DerivationStep("Generalized forces", model.forces_text, None, src),
        DerivationStep(
            "Lagrange equations of the 2nd kind",
            "d/dt ∂T/∂q' - ∂T/∂q = -∂U/∂q + Q (2.5), derived symbolically from T, U and Q.",
            r"\frac{d}{dt}\frac{\partial T}{\partial \dot q_i}-\frac{\partial T}{\partial q_i}"
            r"=-\frac{\partial U}{\partial q_i}+Q_i",
            "(2.5), (2.13)",
        ),
    ]
    equations = [sp.Eq(e, 0) for e in model.simplified]
    if model.constraints:
        steps += [
            DerivationStep(
                "Holonomic constraints",
                "f_i(q) = 0 (2.17); multipliers lambda_i enter as H^T lambda (2.25).",
                [sp.Eq(c, 0) for c in model.constraints],
                "(2.17)",
                reconstructed="the task states positions only; written as holonomic constraints "
                "of §2.2",
            ),
            DerivationStep(
                "Equations with multipliers",
                "A q'' = B + H^T lambda (2.25) with H q'' = -Phi (2.30); solved for q'' and "
                "lambda together.",
                equations,
                "(2.25), (2.30)-(2.34)",
            ),
        ]
    else:
        steps.append(DerivationStep("Equations of motion", "", equations, src))
    if not model.constraints and model.n == 1:
        rhs = sp.simplify(model.lm.mass_matrix.inv() * model.lm.forcing)
        steps.append(
            DerivationStep(
                "Solved for the accelerations",
                "",
                [sp.Eq(sp.diff(c, TIME, 2), r) for c, r in zip(model.q, rhs)],
                src,
            )
        )
    return steps + _closed_forms(params)
