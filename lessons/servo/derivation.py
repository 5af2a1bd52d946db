"""The derivation page of the servo-error lesson (Leppik 1960).

The article's equations step by step for the chosen path, with the numbers of the chosen
values: the PU and the servo channels (2), the line (1)-(8), the vertical parabola
(9)-(25) with the table, the horizontal parabola (19) (Fig. 4b), the circle (26)-(35),
the ellipse, the cubic and quartic parabolas and the conclusions.  Every misprint is
shown in its corrected form with a one-line reason (``reconstructed``); the notes (what
the lesson did with the values) are :mod:`analyzer_lab.lessons.servo.notes`.
"""

from __future__ import annotations

from analyzer_lab.lessons.kit.contract import DerivationStep, Params
from analyzer_lab.lessons.servo.formulas import (
    cubic_offset,
    delta_line_5,
    delta_parabola_13,
    parabola_vertex_17,
    parabola_vertex_19,
    quartic_offset,
)
from analyzer_lab.lessons.servo.model import Channel
from analyzer_lab.lessons.servo.table import format_table, parabola_table, table_ratio_interval


def _sig(x: float) -> str:
    return f"{x:.6g}"


def _steps_line(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    v, ang, g = float(params["v"]), float(params["angle"]), float(params["gamma"])
    d5 = delta_line_5(v, ang, cx.T1, g)
    return [
        DerivationStep(
            "Line: PU output",
            "x_c, y_c are direction constants; the path speed is omega sqrt(x_c^2 + y_c^2).",
            r"x=x_0+\omega y_c t,\qquad y=y_0+\omega x_c t",
            "(1)",
        ),
        DerivationStep(
            "Servo output (identical channels)",
            "The lag omega y_c T1 is along the line when starting at rest: no contour error.",
            r"x_1=x_0+\omega y_ct-\omega y_cT_1+\frac{\dot "
            r"x_0}{\alpha_1-\alpha_2}(e^{\alpha_1t}-e^{\alpha_2t})"
            r"+\omega y_c\frac{\alpha_2^2e^{\alpha_1t}-\alpha_1^2e^{\alpha_2t}}{(\alpha_1-\alpha_2)\alpha_1\alpha_2}",
            "(3)",
        ),
        DerivationStep(
            "Transient error",
            "With initial velocities the error is transient; f(t) peaks near 1.05 T2^2/(T1 + T2) "
            "(within about 5 % for every damping).",
            r"\delta=\frac{\dot x_0x_c-\dot "
            r"y_0y_c}{\sqrt{x_c^2+y_c^2}}\,\frac{e^{\alpha_1t}-e^{\alpha_2t}}{\alpha_1-\alpha_2},"
            r"\qquad f(t)_{\max}\approx\frac{1.05\,T_2^2}{T_1+T_2}",
            "(4)",
        ),
        DerivationStep(
            "Non-identical channels: a parallel line",
            f"Here delta = {_sig(d5)} mm.",
            r"\delta=\frac{\omega x_cy_cT_1(\gamma-1)}{\sqrt{x_c^2+y_c^2}}",
            "(5)",
        ),
        DerivationStep(
            "In terms of the speed",
            "Largest at 45 deg: v T1 (gamma - 1)/2.",
            r"\omega=\frac{v}{\sqrt{x_c^2+y_c^2}},\qquad "
            r"\delta=\frac{v\,x_cy_cT_1(\gamma-1)}{x_c^2+y_c^2}",
            "(6)",
            reconstructed="printed omega = v/sqrt(x0^2 + y_c^2); the PU speed is omega "
            "sqrt(x_c^2 + y_c^2), and (6) follows from (5) only with x_c",
        ),
        DerivationStep(
            "Program correction",
            "New PU initial conditions (per channel T1x, T1y for non-identical channels) remove "
            "the steady error; "
            "the transient (4) remains.",
            r"X_0=x_0+\omega y_cT_{1x},\qquad Y_0=y_0+\omega x_cT_{1y}",
            "(7), (8)",
        ),
    ]


def _steps_parabola(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p, g = float(params["omega"]), float(params["p"]), float(params["gamma"])
    d13 = delta_parabola_13(omega, p, cx.T1, cx.T2sq)
    rows = parabola_table()
    lo, hi = table_ratio_interval()
    return [
        DerivationStep(
            "Parabola: PU output",
            "p(y - y_c) = (x - x_c)^2; PU dx/dt = omega p/2, dy/dt = omega (x - x_c).",
            r"x=x_0+\frac{\omega p}{2}t,\qquad y=y_0+\omega(x_0-x_c)t+\frac{\omega^2p}{4}t^2",
            "(9)",
        ),
        DerivationStep(
            "Path speed",
            f"At the vertex v = omega p/2 = {_sig(omega * p / 2)} mm/s.",
            r"v=\omega\sqrt{(x-x_c)^2+\frac{p^2}{4}}",
            "(13)",
            reconstructed="printed omega = v/sqrt(y^2 + p^2/4); since dx/dt = omega p/2, dy/dt = "
            "omega x the speed involves x (both agree only at the vertex)",
        ),
        DerivationStep(
            "After the transient",
            "First terms of 1/(1 + T1 s + T2^2 s^2) = 1 - T1 s + (T1^2 - T2^2) s^2 - ... on the "
            "polynomial inputs.",
            r"x_1=x_0+\frac{\omega p}{2}t-\frac{\omega pT_{1x}}{2},\quad "
            r"y_1=y+\frac{\omega^2p}{2}(T_{1y}^2-T_{2y}^2)-\omega(x_0-x_c)T_{1y}-\frac{\omega^2pT_{1y}}{2}t",
            "(11)",
        ),
        DerivationStep(
            "The same parabola, shifted along its axis",
            "",
            r"y_1=\frac{x_1^2}{p}+\frac{\omega^2p}{4}(T_1^2-2T_2^2)",
            "(12)",
        ),
        DerivationStep(
            "Largest error (between the vertices)",
            f"Here (13) = {_sig(d13)} mm (negative: the output lies outside, T1^2 < 2 T2^2).",
            r"\delta_{\max}=\frac{\omega^2p}{4}\left(T_1^2-2T_2^2\right)",
            "(13)",
        ),
        DerivationStep(
            "Error at an arbitrary point (approximate)",
            "From triangle abc of Fig. 2 (unnumbered; probably the missing (14)).",
            r"\delta\approx\frac{\Delta y'\Delta x'}{\sqrt{\Delta y'^2+\Delta x'^2}},\quad "
            r"\Delta y'=\delta_{\max},\ \Delta x'=x-\sqrt{x^2-p\Delta y'}",
            "(14)",
            reconstructed="equation number (14) is missing in the print; this unnumbered formula "
            "is presumably it",
        ),
        DerivationStep(
            "Dependence on beta = T2^2/T1^2",
            "f(beta) = 1/beta^2 - 2/beta has a minimum f = -1 at beta = 1 (the largest error of "
            "negative sign) and crosses zero at beta = 1/2 with slope -8.",
            r"\delta_{\max}=\frac{\omega^2p}{4}\left(\frac1{\beta^2}-\frac2\beta\right)\frac{T_2^4}{T_1^2}",
            "(15)",
            reconstructed="the text calls beta = 1 a maximum of f; it is the minimum (largest "
            "|delta| of negative sign)",
        ),
        DerivationStep(
            "The table: formula (13), simulation and the printed values side by side",
            "v = 50 mm/s, p = 20 mm, omega = 5, rows k [1/s], columns T [s].  The simulation "
            "agrees with (13) in every "
            "cell; the printed values are 0.8 x (13) in every cell (to their printed digits: the "
            "factor compatible with "
            f"all cells lies in [{lo:.4f}, {hi:.4f}], so 1 is excluded). The cause is not stated "
            f"in the article "
            "(omega^2 = 20 instead of 25 would give it).\n\n" + format_table(rows),
            r"\delta_{\text{printed}}=0.8\cdot\frac{\omega^2p}{4}(T_1^2-2T_2^2)=100\,(T_1^2-2T_2^2)\ \text{mm}",
            "table",
            reconstructed="the printed header is transposed (rows are k in 1/s, columns T in s); "
            "read literally (13) gives absurd values",
        ),
        DerivationStep(
            "Non-identical channels: output parabola",
            f"Vertex of the output parabola: "
            f"{tuple(round(v, 6) for v in parabola_vertex_17(omega, p, cx.T1, cx.T2sq, g))} mm. "
            "The article's Fig. 4 remarks (for the vertical parabola the error grows for gamma < "
            "1 and decreases for "
            "gamma > 1) are not reproduced with gamma scaling the y channel: with T1 = 0.01 s, "
            "T2^2 = 0.001 s^2 the "
            "largest normal distance grows for gamma > 1 too; the figure's parameters are not "
            "given.",
            r"y=\frac{x^2}{p}+\omega "
            r"T_1(1-\gamma)x+\frac{\omega^2p}{4}\left[T_1^2(1-2\gamma+2\gamma^2)-2\gamma "
            r"T_2^2\right]",
            "(17)",
        ),
        DerivationStep(
            "Locus of the vertices as gamma varies",
            "",
            r"y=\frac{x^2}{p}+\frac{\omega(T_1^2-T_2^2)}{T_1}x+\frac{\omega^2p}{4}(T_1^2-2T_2^2)",
            "(18)",
            reconstructed="printed linear coefficient omega (T1^2 - T2^2) is dimensionally wrong "
            "and misses the vertices; /T1 restores both",
        ),
        DerivationStep(
            "Program correction: required inputs",
            "Make (9) the particular solution of (2).",
            r"x=x_0+\frac{\omega pt}{2}+\frac{\omega pT_{1x}}{2},\quad "
            r"y=y_0+\omega(x_0-x_c)T_{1y}+\left[\frac{\omega^2pT_{1y}}{2}+\omega(x_0-x_c)\right]t+\frac{\omega^2pt^2}{4}+\frac{\omega^2T_{2y}^2p}{2}",
            "(21)",
        ),
        DerivationStep(
            "Corrected PU",
            "New initial conditions and, for non-identical channels, an extra constant input "
            "omega^2 p (T1y - T1x)/2 in dy/dt.",
            r"X_0=x_0+\frac{\omega pT_{1x}}{2},\qquad "
            r"Y_0=y_0+\omega(x_0-x_c)T_{1y}+\frac{\omega^2pT_{2y}^2}{2}",
            "(22)",
        ),
        DerivationStep(
            "Transient with the corrected program (servo from rest)",
            "",
            r"y_1-\frac{x_1^2}{p}=\frac{\omega^2p}{4}\left(2t-f\right)f,\qquad "
            r"f=\frac{e^{\alpha_1t}-e^{\alpha_2t}}{\alpha_1-\alpha_2}",
            "(24), (25)",
        ),
        DerivationStep(
            "Alternative correction (point stays on the parabola, x != x1)",
            "For identical channels: shift the program by -delta_max.",
            r"Y_0=y_0+\frac{\omega^2pT_{1x}^2}{4}-\frac{\omega^2pT_{1x}T_{1y}}{2}"
            r"+\frac{\omega^2pT_{2y}^2}{2}+\omega x_0(T_{1y}-T_{1x})",
            "after (25)",
            reconstructed="printed Y0 = y0 + omega^2 p T1x/4 + omega^2 p T1y/2 + omega x0 T1y is "
            "dimensionally inconsistent; re-derived for the PU with the extra input",
        ),
    ]


def _steps_horizontal_parabola(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p, g = float(params["omega"]), float(params["p"]), float(params["gamma"])
    T1, T2sq = cx.T1, cx.T2sq
    lin = omega * T1 * (g - 1.0)
    const = omega**2 * p / 4.0 * (T1**2 * (2 + g * g - 2 * g) - 2 * T2sq)
    xv, yv = parabola_vertex_19(omega, p, T1, T2sq, g)
    return [
        DerivationStep(
            "Horizontal parabola: PU output",
            "p(x - x_c) = (y - y_c)^2: the PU of (9) with x and y exchanged, "
            "dy/dt = omega p/2, dx/dt = omega (y - y_c).",
            r"y=y_0+\frac{\omega p}{2}t,\qquad x=x_0+\omega(y_0-y_c)t+\frac{\omega^2p}{4}t^2",
            "(9), (19)",
            reconstructed="the article states only the result (19); its PU is that of (9) with "
            "x, y "
            "exchanged",
        ),
        DerivationStep(
            "Path speed",
            f"At the vertex v = omega p/2 = {_sig(omega * p / 2)} mm/s; for this parabola the "
            f"printed "
            "form of the speed under (13) holds as it stands (y measured from the vertex).",
            r"v=\omega\sqrt{(y-y_c)^2+\frac{p^2}{4}}",
            "(13)",
        ),
        DerivationStep(
            "After the transient",
            "The first terms of 1/(1 + T1 s + T2^2 s^2) on the polynomial inputs, as in (11); "
            "the y channel has T1y = gamma T1.",
            r"x_1=x-T_1\dot x+(T_1^2-T_2^2)\ddot x,\qquad y_1=y-\gamma T_1\dot y",
            "(11), (19)",
        ),
        DerivationStep(
            "Output parabola",
            f"Eliminating t (x_c = y_c = 0): here x = y^2/p {lin:+.6g} y {const:+.6g} mm.",
            r"x=\frac{y^2}{p}+\omega T_1y(\gamma-1)+\frac{\omega^2p}{4}"
            r"\left[T_1^2(2+\gamma^2-2\gamma)-2T_2^2\right]",
            "(19)",
        ),
        DerivationStep(
            "Vertex of the output parabola",
            f"Here ({_sig(xv)}, {_sig(yv)}) mm. x_c does not depend on gamma: as gamma varies the "
            "vertices lie on a straight line, at the distance (13) from the programmed vertex "
            "(x_c, y_c name the output vertex here).",
            r"x_c=\frac{\omega^2p}{4}(T_1^2-2T_2^2),\qquad y_c=-\frac{\omega pT_1(\gamma-1)}{2}",
            "(19)",
        ),
        DerivationStep(
            "Error along the parabola (Fig. 4b)",
            "The contour error is the normal distance between the two parabolas: the gap along x "
            "divided by the slope factor.  Far from the vertex it tends to |omega T1 (1 - "
            "gamma)| p/2 "
            f"(here {_sig(abs(omega * T1 * (1 - g)) * p / 2)} mm).  Fig. 4b: the error grows for "
            "gamma > 1 and for gamma < 1 (with T1 = 0.01 s, T2^2 = 0.001 s^2, omega = 5, p = 20 mm "
            "the largest distance over |y| <= 20 mm is 0.2375 mm for gamma = 1, 0.3448 mm for 0.5 "
            "and 0.5533 mm for 2); the figure's parameters are not given.",
            r"\delta(y)=\frac{x_{(19)}(y)-y^2/p}{\sqrt{1+(2y/p)^2}}\ \text{(to first order)}",
            "(19), Fig. 4b",
            reconstructed="the article gives only (19) and Fig. 4b; the distance is computed "
            "from (19)",
        ),
    ]


def _steps_circle(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega = float(params["omega"])
    P1 = cx.response(omega)
    return [
        DerivationStep(
            "Circle: PU output",
            "PU dx/dt = omega (y - y_c), dy/dt = -omega (x - x_c).",
            r"x-x_c=R_0\sin(\omega t+\varphi_0),\qquad y-y_c=R_0\cos(\omega t+\varphi_0)",
            "(26)",
        ),
        DerivationStep(
            "After the transient",
            "",
            r"x_1-x_c=R_0|\Phi_1(j\omega)|\sin(\omega t+\varphi_0+\varphi_1),\quad "
            r"y_1-y_c=R_0|\Phi_2(j\omega)|\cos(\omega t+\varphi_0+\varphi_2)",
            "(27)",
        ),
        DerivationStep(
            "Identical channels: radius error",
            f"|Phi(j omega)| = {_sig(abs(P1))}.",
            r"\delta=R_0\left[1-|\Phi(j\omega)|\right],\qquad "
            r"|\Phi(j\omega)|=\frac{1}{\sqrt{(1-T_2^2\omega^2)^2+T_1^2\omega^2}}",
            "(28)",
        ),
        DerivationStep(
            "Non-identical channels: an ellipse",
            "m = R0|Phi1|, n = R0|Phi2|.",
            r"\frac{x_1^2}{m^2}+\frac{y_1^2}{n^2}+\frac{2x_1y_1}{mn}\sin(\varphi_2-\varphi_1)"
            r"=\cos^2(\varphi_2-\varphi_1),\qquad "
            r"\operatorname{ctg}2\alpha=\frac{n^2-m^2}{2mn\sin(\varphi_2-\varphi_1)}",
            "(29)",
        ),
        DerivationStep(
            "Semi-axes",
            "",
            r"a,b=\sqrt{\frac{\cos^2(\varphi_2-\varphi_1)}{\frac{m^2+n^2}{2m^2n^2}\pm\sqrt{\frac{(m^2+n^2)^2}{4m^4n^4}-\frac{\cos^2(\varphi_2-\varphi_1)}{m^2n^2}}}}",
            "(30)",
            reconstructed="printed numerator cos(phi2 - phi1); the semi-axes of x^T Q x = cos^2 "
            "need cos^2 (area pi m n |cos|); simulation confirms",
        ),
        DerivationStep(
            "Program correction: required input",
            "",
            r"x=\frac{R_0}{|\Phi_1(j\omega)|}\sin(\omega t+\varphi_0-\varphi_1),\qquad "
            r"y=\frac{R_0}{|\Phi_2(j\omega)|}\cos(\omega t+\varphi_0-\varphi_2)",
            "before (31)",
            reconstructed="printed R0/|Phi|^2; (31) itself equals the unsquared form",
        ),
        DerivationStep(
            "Corrected input expanded",
            "",
            r"x=\frac{(y_0P_1+x_0Q_1)\sin\omega t+(x_0P_1-y_0Q_1)\cos\omega t}{|\Phi_1|^2},\quad "
            r"y=\frac{(y_0Q_2-x_0P_2)\sin\omega t+(y_0P_2+x_0Q_2)\cos\omega t}{|\Phi_2|^2}",
            "(31)",
        ),
        DerivationStep(
            "Corrected PU",
            "A PU producing a constant-amplitude sinusoid needs a zero trace: m2 = -r2.",
            r"\frac{dx}{dt}=\omega\left[\frac{P_2Q_1-P_1Q_2}{P_1P_2+Q_1Q_2}x"
            r"+\frac{|\Phi_2|^2}{P_1P_2+Q_1Q_2}y\right],\quad "
            r"\frac{dy}{dt}=\omega\left[-\frac{|\Phi_1|^2}{P_1P_2+Q_1Q_2}x+\frac{P_1Q_2-P_2Q_1}{P_1P_2+Q_1Q_2}y\right]",
            "(33)",
            reconstructed="printed P2^2 + Q2 (square lost) and the same sign on both diagonal "
            "terms, which makes the PU grow or decay",
        ),
        DerivationStep(
            "Corrected initial conditions",
            "",
            r"X_0=\frac{x_0P_1-y_0Q_1}{|\Phi_1|^2},\qquad Y_0=\frac{x_0Q_2+y_0P_2}{|\Phi_2|^2}",
            "(34)",
        ),
        DerivationStep(
            "Identical servo systems",
            "The PU structure is unchanged; only the initial conditions (34) change.",
            r"\frac{dx}{dt}=\omega y,\qquad \frac{dy}{dt}=-\omega x",
            "(35)",
            reconstructed="printed dy/dt = +omega x (a saddle, not an oscillator) and 'if the PU "
            "are identical' for 'servo systems'",
        ),
        DerivationStep(
            "Modulus-only correction",
            "Correcting only the moduli leaves a 45 deg ellipse (a circle only if phi1 = phi2).",
            r"\frac{dx}{dt}=\omega\frac{|\Phi_2|}{|\Phi_1|}y,\quad "
            r"\frac{dy}{dt}=-\omega\frac{|\Phi_1|}{|\Phi_2|}x,\quad "
            r"X_0=\frac{x_0}{|\Phi_1|},\ Y_0=\frac{y_0}{|\Phi_2|};\qquad "
            r"a,b=R_0\sqrt{1\pm|\sin(\varphi_2-\varphi_1)|}",
            "after (35)",
            reconstructed="printed X0 = (x0 - y0)/|Phi1|^2, Y0 = (x0 + y0)/|Phi2|^2 give sqrt(2) "
            "R0/|Phi| even for equal arguments; "
            "printed a, b = R0 sqrt(cos/(1 -+ sin)) miss the square as in (30)",
        ),
    ]


def _steps_ellipse(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    return [
        DerivationStep(
            "Ellipse: PU",
            "",
            r"\frac{dx}{dt}=\omega\frac ab(y-y_c),\qquad \frac{dy}{dt}=-\omega\frac ba(x-x_c)",
            "Leppik (1960), ellipses",
        ),
        DerivationStep(
            "Servo output",
            "Identical channels: semi-axes a|Phi|, b|Phi|; errors a(1 - |Phi|), b(1 - |Phi|).",
            r"x_1-x_c=a|\Phi_1|\sin(\omega t+\varphi_0+\varphi_1),\qquad "
            r"y_1-y_c=b|\Phi_2|\cos(\omega t+\varphi_0+\varphi_2)",
            "Leppik (1960), ellipses",
        ),
        DerivationStep(
            "Non-identical channels",
            "Tilt (29), semi-axes (30) with cos^2, m = a|Phi1|, n = b|Phi2|.",
            r"m=a|\Phi_1(j\omega)|,\qquad n=b|\Phi_2(j\omega)|",
            "(29), (30)",
            reconstructed="printed 'm = n gives a circle': also phi1 = phi2 is needed; with m = "
            "n, phi1 != phi2 the output is a 45 deg ellipse",
        ),
    ] + _steps_circle(params, cx, cy)[4:5]


def _deg34(title: str, text: str, math: str, why: str | None = None) -> DerivationStep:
    """A step of the article's section on the parabolas of degree 3 and 4."""
    return DerivationStep(title, text, math, "Leppik (1960), parabolas of degree 3 and 4", why)


def _steps_cubic(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p = float(params["omega"]), float(params["p"])
    return [
        _deg34(
            "Cubic parabola: PU output",
            "The PU of Fig. 7 is not described; an integrator chain gives the same output.",
            r"x=\omega pt,\qquad y=\omega^3p^2t^3",
        ),
        _deg34(
            "Servo output after the transient",
            "",
            r"x_1=\omega pt-\omega pT_1,\quad "
            r"y_1=\omega^3p^2t^3-3\omega^3p^2(T_1t^2+2T_2^2t-2T_1^2t+2T_1^3-4T_1T_2^2)",
        ),
        _deg34(
            "Output curve",
            f"Inflection shift here: {_sig(cubic_offset(omega, p, cx, cy))} mm.",
            r"y=\frac{x^3}{p}+3\omega^2p(T_1^2-2T_2^2)x+2\omega^3p^2(3T_1T_2^2-T_1^3)",
            why="printed 'y = x^3/rho = 3 omega^2 p(...)': '=' must be '+', rho is p",
        ),
        _deg34(
            "Extrema (only for 2 T2^2 > T1^2)",
            "",
            r"x=\mp\omega p\sqrt{2T_2^2-T_1^2},\quad "
            r"y=2\omega^3p^2\left[(3T_1T_2^2-T_1^3)\pm(2T_2^2-T_1^2)^{3/2}\right]",
            why="printed with a spurious inner -+ under the root",
        ),
        _step_general_correction(),
    ]


def _steps_quartic(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    omega, p = float(params["omega"]), float(params["p"])
    return [
        _deg34(
            "Quartic parabola: PU output",
            "",
            r"x=\omega pt,\qquad y=\omega^4p^3t^4",
        ),
        _deg34(
            "Servo output after the transient",
            "",
            r"y_1=\omega^4p^3t^4-4\omega^4p^3\left[T_1t^3-3(T_1^2-T_2^2)t^2+6(T_1^3-2T_1T_2^2)t-6(T_1^4-3T_1^2T_2^2+T_2^4)\right]",
            why="printed with three sign errors and T1^2 for T1^3 in the t term (off "
            "by mm in simulation); the printed curve below is right",
        ),
        _deg34(
            "Output curve",
            f"Vertex shift here: {_sig(quartic_offset(omega, p, cx, cy))} mm. With beta1 = "
            f"T1^2/T2^2 the "
            "parabola y' opens downward for beta1 < 2; its vertex is above the programmed one "
            "for beta1 < 0.845 and "
            "beta1 > 3.155; the line y'' rises for beta1 < 3.",
            r"y=\frac{x^4}{p}+6\omega^2p(T_1^2-2T_2^2)x^2+8\omega^3p^2(3T_2^2T_1-T_1^3)x+3\omega^4p^3(3T_1^4+8T_2^4-12T_1^2T_2^2)",
        ),
        _step_general_correction(),
    ]


def _step_general_correction() -> DerivationStep:
    return DerivationStep(
        "Program correction for any PU",
        "Feed each channel with (T2^2 s^2 + T1 s + 1) applied to the programmed coordinate "
        "(the rule of (20)); for a linear PU dz/dt = A z, x = C z this is a new output map (new "
        "initial conditions of the PU).",
        r"u_x=C_x\left(I+T_{1x}A+T_{2x}^2A^2\right)z",
        "(20)",
        reconstructed="the article gives no correction for degree 3 and 4; this is its rule (20) "
        "applied to the integrator-chain PU",
    )


# ---------------------------------------------------------------- claim checks


STEPS = {
    "line": _steps_line,
    "parabola": _steps_parabola,
    "parabola-horizontal": _steps_horizontal_parabola,
    "circle": _steps_circle,
    "ellipse": _steps_ellipse,
    "cubic": _steps_cubic,
    "quartic": _steps_quartic,
}


def derivation_steps(params: Params, cx: Channel, cy: Channel) -> list[DerivationStep]:
    """The page for the chosen path: the PU, the channels, the path's steps, the conclusions."""
    curve = params["curve"]
    steps = [
        DerivationStep(
            "Programming device (PU)",
            "The PU integrates the conic's field; F is conserved along its solution. With B = 0 "
            "(axes parallel "
            "to x, y) it is used throughout.",
            r"\frac{dx}{dt}=\pm\omega(Bx+Cy+E),\qquad \frac{dy}{dt}=\mp\omega(Ax+By+D)",
            "Fig. 1a",
        ),
        DerivationStep(
            "Servo channels",
            f"Each coordinate drives a second-order channel. From the open loop W(s) = "
            f"k/((Ts+1)s): "
            f"T2^2 = T/k, T1 = 1/k. Here T1x = {_sig(cx.T1)} s, T2x^2 = {_sig(cx.T2sq)} s^2, "
            f"zeta = T1/(2 T2) = {_sig(cx.zeta)}.",
            r"(T_{2x}^2s^2+T_{1x}s+1)\,x_1=x,\quad (T_{2y}^2s^2+T_{1y}s+1)\,y_1=y,\qquad "
            r"\Phi=\frac{W}{1+W}=\frac{1}{\frac{T}{k}s^2+\frac{1}{k}s+1}",
            "(2)",
        ),
        DerivationStep(
            "Non-identical channels",
            f"The y channel is scaled by gamma = {_sig(float(params['gamma']))}: T1y = "
            f"{_sig(cy.T1)} s, "
            f"T2y^2 = {_sig(cy.T2sq)} s^2.",
            r"T_{1y}=\gamma T_1,\qquad T_{2y}^2=\gamma T_2^2",
            "(16)",
            reconstructed="printed as 'non-identical (T_y != gamma T_x)'; the definition used "
            "everywhere else is T_y = gamma T_x",
        ),
    ]
    steps += STEPS[curve](params, cx, cy)
    steps.append(
        DerivationStep(
            "Conclusion: single-axis errors vs the contour error",
            "Feeding x + T1 dx/dt removes the x error but shifts the output parabola by -omega^2 "
            "p T2^2/2 instead of "
            "(13): a larger contour error whenever T1^2 < 4 T2^2.",
            r"\delta=-\frac{\omega^2p\,T_2^2}{2}\quad\text{vs}\quad "
            r"\frac{\omega^2p}{4}(T_1^2-2T_2^2)",
            "Leppik (1960), conclusions",
        )
    )
    return steps
