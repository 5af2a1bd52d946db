"""The checkable claims of Leppik (1960), each computed from the model and compared.

Every claim states the article's numbers (or the corrected ones, where the print is
wrong) and checks them against the exact simulation of lessons/servo/model.py and the
closed forms of lessons/servo/formulas.py: the line (4)-(6), the circle and ellipse
(28)-(30), the program corrections, the modulus-only correction and the cubic and quartic
parabolas here; the table and the parabolas (13), (15), (17)-(19), (24) and the
conclusions in lessons/servo/claims/parabola.py.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import Claim, ClaimResult, close
from analyzer_lab.lessons.servo.claims.parabola import (
    claim_alt_correction,
    claim_beta,
    claim_derivative,
    claim_parabola_17_18,
    claim_parabola_19,
    claim_parabola_19_error,
    claim_parabola_24,
    claim_table_08,
    claim_table_13,
)
from analyzer_lab.lessons.servo.formulas import (
    circle_axes_29_30,
    cubic_curve,
    f_transient,
    quartic_curve,
    quartic_y1,
)
from analyzer_lab.lessons.servo.geometry import fit_centred_ellipse, line_distance
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo, planar_program, settled
from analyzer_lab.lessons.servo.paths import (
    ellipse_program,
    line_program,
    power_program,
)

ARTICLE = "Leppik (1960)"


def claim_line_5_6() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.05)
    worst = 0.0
    got = []
    for ang, g, expected in ((45.0, 1.2, 0.05), (30.0, 0.7, -0.0649519052838329)):
        _, out = settled(line_program(0.0, 0.0, 50.0, ang), ch, ch.scaled(g), n=11)
        d, _, _ = line_distance(out["x1"], out["y1"], out["x"], out["y"], ang)
        th = math.radians(ang)
        xc, yc = math.sin(th), math.cos(th)  # direction constants with omega = v
        d5 = 50.0 * xc * yc * ch.T1 * (g - 1) / math.hypot(xc, yc)
        d6 = 50.0 * xc * yc * ch.T1 * (g - 1) / (xc * xc + yc * yc)
        worst = max(
            worst, abs(d[-1] - expected), abs(d5 - expected), abs(d6 - expected), float(np.ptp(d))
        )
        got.append(f"{d[-1]:.6f}")
    return ClaimResult(
        "0.05, -0.0649519 mm (atol 1e-8)", ", ".join(got) + f" (worst {worst:.1e})", worst <= 1e-8
    )


def claim_line_4() -> ClaimResult:
    ch = Channel(0.01, 0.0005)
    sysm = TwoAxisServo(line_program(0.0, 0.0, 50.0, 45.0), ch, ch)
    t = np.linspace(0.0, 1.0, 2001)
    out = sysm.outputs(sysm.states(t, sysm.initial_state()))
    d0, _, _ = line_distance(out["x1"], out["y1"], out["x"], out["y"], 45.0)
    out = sysm.outputs(sysm.states(t, sysm.initial_state(50.0, 0.0)))
    d, _, _ = line_distance(out["x1"], out["y1"], out["x"], out["y"], 45.0)
    th = math.radians(45.0)
    d4 = 50.0 * math.sin(th) * f_transient(t, ch)
    fmax = float(np.max(f_transient(np.linspace(0, 1, 20001), ch)))
    approx = 1.05 * ch.T2sq / (ch.T1 + math.sqrt(ch.T2sq))
    ok = (
        float(np.max(np.abs(d0))) < 1e-9
        and float(np.max(np.abs(d - d4))) < 1e-9
        and abs(approx / fmax - 1.0) <= 0.05
    )
    return ClaimResult(
        "at rest: 0; with xdot0: (4) to 1e-9 mm; 1.05 T2^2/(T1+T2) within 5 % of max f",
        f"at rest {np.max(np.abs(d0)):.1e}; |sim-(4)| {np.max(np.abs(d - d4)):.1e}; approx/exact "
        f"{approx / fmax:.4f}",
        ok,
    )


def claim_circle_28() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    _, out = settled(
        ellipse_program(0.0, 10.0, 0.0, 0.0, 1.0, 1.0, 5.0), ch, ch, window=2 * math.pi / 5
    )
    r = np.hypot(out["x1"], out["y1"])
    sim = 10.0 - float(np.mean(r))
    f28 = 10.0 * (1.0 - abs(ch.response(5.0)))
    res = close(f28, sim, rtol=1e-6)
    res.passed = res.passed and float(np.ptp(r)) < 1e-6 * 10.0
    return res


def _ellipse_case(
    a: float, b: float, omega: float, gamma: float
) -> tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]:
    ch = Channel.from_open_loop(100.0, 0.1)
    cy = ch.scaled(gamma)
    _, out = settled(
        ellipse_program(0.0, b, 0.0, 0.0, a, b, omega), ch, cy, window=2 * math.pi / omega
    )
    sim = fit_centred_ellipse(out["x1"], out["y1"])
    P1, P2 = ch.response(omega), cy.response(omega)
    m, n, dphi = a * abs(P1), b * abs(P2), float(np.angle(P2) - np.angle(P1))
    return sim, circle_axes_29_30(m, n, dphi), circle_axes_29_30(m, n, dphi, printed=True)


def _nonidentical(a: float, b: float, omega: float, axes: tuple[float, float, float]):
    """Simulated ellipse (y channel k = 60, x channel k = 100, T = 0.1) against (29), the
    corrected (30) and the expected (major, minor, tilt); the printed (30) must be off."""
    (a_s, b_s, ang_s), (alpha, a30, b30), (_, a_p, b_p) = _ellipse_case(a, b, omega, 5.0 / 3.0)
    ok = (
        max(abs(a_s / a30 - 1), abs(b_s / b30 - 1)) < 1e-6
        and abs(((ang_s - alpha + 90) % 180) - 90) < 1e-4
        and abs(a_p / a_s - 1) > 5e-4
        and max(abs(a30 - axes[0]), abs(b30 - axes[1])) < 1e-5
        and abs(alpha - axes[2]) < 1e-3
    )
    text = (
        f"sim {a_s:.5f}/{b_s:.5f} at {ang_s:.3f} deg; (30) {a30:.5f}/{b30:.5f}; (29) "
        f"{alpha:.3f}; printed {a_p:.5f}/{b_p:.5f}"
    )
    return ok, text


def claim_circle_29_30() -> ClaimResult:
    ok, text = _nonidentical(10.0, 10.0, 10.0, (12.00691, 10.78178, 63.127))
    expected = "sim = corrected (30) = 12.00691/10.78178 mm, tilt (29) = 63.127 deg; printed off"
    return ClaimResult(expected, text, ok)


def claim_ellipse() -> ClaimResult:
    G = abs(Channel.from_open_loop(100.0, 0.1).response(8.0))
    (a1, b1, _), _, _ = _ellipse_case(15.0, 6.0, 8.0, 1.0)
    ok, text = _nonidentical(15.0, 6.0, 8.0, (15.97402, 6.62696, 1.809))
    ok = ok and abs(a1 - 15 * G) < 1e-6 * a1 and abs(b1 - 6 * G) < 1e-6 * b1
    expected = "identical 15.96743/6.38697; non-identical 15.97402/6.62696 mm at 1.809 deg"
    return ClaimResult(expected, f"identical {a1:.5f}/{b1:.5f}; {text}", ok)


def claim_correction() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.05)
    worst = 0.0
    cases = [
        (line_program(0.0, 0.0, 50.0, 30.0), ch, ch.scaled(0.7)),
        (
            power_program(2, -200.0, 0.0, 0.0, 20.0, 5.0),
            Channel(0.01, 0.001),
            Channel(0.01, 0.001).scaled(2.0),
        ),
        (
            ellipse_program(0.0, 10.0, 0.0, 0.0, 1.0, 1.0, 10.0),
            Channel.from_open_loop(100.0, 0.1),
            Channel.from_open_loop(100.0, 0.1).scaled(5 / 3),
        ),
    ]
    for prog, cx, cy in cases:
        _, out = settled(prog, cx, cy, "on", n=201)
        worst = max(
            worst,
            float(np.max(np.abs(out["x1"] - out["x"]))),
            float(np.max(np.abs(out["y1"] - out["y"]))),
        )
    # the corrected program starts at the article's X0, Y0: (7), (22), (34)
    sysl = TwoAxisServo(cases[0][0], cases[0][1], cases[0][2], "on")
    z0 = cases[0][0].z0
    d7 = max(
        abs(sysl.Kx @ z0 - 50 * math.cos(math.radians(30)) * ch.T1),
        abs(sysl.Ky @ z0 - 50 * math.sin(math.radians(30)) * ch.scaled(0.7).T1),
    )
    sysp = TwoAxisServo(cases[1][0], cases[1][1], cases[1][2], "on")
    cx, cy = cases[1][1], cases[1][2]
    X0 = -200.0 + 5 * 20 * cx.T1 / 2
    Y0 = 2000.0 + 5 * (-200.0) * cy.T1 + 25 * 20 * cy.T2sq / 2
    z0 = cases[1][0].z0
    d22 = max(abs(sysp.Kx @ z0 - X0), abs(sysp.Ky @ z0 - Y0))
    sysc = TwoAxisServo(cases[2][0], cases[2][1], cases[2][2], "on")
    P1, P2 = cases[2][1].response(10.0), cases[2][2].response(10.0)
    x0, y0 = 0.0, 10.0
    X34 = (x0 * P1.real - y0 * P1.imag) / abs(P1) ** 2
    Y34 = (x0 * P2.imag + y0 * P2.real) / abs(P2) ** 2
    z0 = cases[2][0].z0
    d34 = max(abs(sysc.Kx @ z0 - X34), abs(sysc.Ky @ z0 - Y34))
    ok = worst < 1e-7 and max(d7, d22, d34) < 1e-10
    return ClaimResult(
        "steady |error| < 1e-7 mm; PU start = (7), (22), (34) to 1e-10",
        f"steady {worst:.1e} mm; start {max(d7, d22, d34):.1e}",
        ok,
    )


def claim_cubic_quartic() -> ClaimResult:
    T1, T2 = 0.01, 0.0005
    ch = Channel(T1, T2)
    w, p = 0.125, 400.0
    _, out = settled(power_program(3, -100.0, 0.0, 0.0, p, w), ch, ch, window=2.0, n=401)
    x, y = out["x1"], out["y1"]
    e3 = float(np.max(np.abs(y - cubic_curve(x, w, p, T1, T2))))
    w, p = 0.00625, 8000.0
    _, out = settled(power_program(4, -100.0, 0.0, 0.0, p, w), ch, ch, window=2.0, n=401)
    x, y = out["x1"], out["y1"]
    e4 = float(np.max(np.abs(y - quartic_curve(x, w, p, T1, T2))))
    tau = out["x"] / (w * p)  # PU time measured from the vertex
    e_fix = float(np.max(np.abs(y - quartic_y1(tau, w, p, T1, T2))))
    e_pr = float(np.max(np.abs(y - quartic_y1(tau, w, p, T1, T2, printed=True))))
    scale = float(np.max(np.abs(y)))
    tol = 1e-9 * max(scale, 1.0)
    ok = e3 < 1e-6 and e4 < tol + 1e-7 and e_fix < tol + 1e-7 and e_pr > 1e-3
    return ClaimResult(
        "cubic curve, quartic curve and corrected quartic y1(t) match; printed y1(t) does not",
        f"cubic {e3:.1e}, quartic {e4:.1e}, corrected y1 {e_fix:.1e}, printed y1 {e_pr:.2g} mm",
        ok,
    )


def claim_modulus_only() -> ClaimResult:
    cx, cy, w, R0 = (
        Channel.from_open_loop(30.0, 0.01),
        Channel.from_open_loop(200.0, 0.02),
        20.0,
        10.0,
    )
    P1, P2 = cx.response(w), cy.response(w)
    g1, g2 = abs(P1), abs(P2)
    A = np.zeros((3, 3))
    A[0, 1], A[1, 0] = w * g2 / g1, -w * g1 / g2
    prog = planar_program(A, 0.0, R0 / g2)
    _, out = settled(prog, cx, cy, window=2 * math.pi / w, n=801)
    a, b, ang = fit_centred_ellipse(out["x1"], out["y1"])
    D = abs(math.sin(float(np.angle(P2) - np.angle(P1))))
    a_fix, b_fix = R0 * math.sqrt(1 + D), R0 * math.sqrt(1 - D)
    ok = (
        abs(a - a_fix) < 1e-6 * a
        and abs(b - b_fix) < 1e-6 * b
        and min(abs(ang - 45), abs(ang - 135)) < 1e-4
        and abs(a - 12.34629) < 1e-5
    )
    return ClaimResult(
        "R0 sqrt(1 +- |sin|) = 12.34629 / 6.89704 mm at 45 or 135 deg",
        f"{a:.5f} / {b:.5f} mm at {ang:.3f} deg",
        ok,
    )


def claim_quartic_beta() -> ClaimResult:
    b = sp.symbols("beta_1", positive=True)
    T2 = sp.symbols("T_2", positive=True)
    T1 = sp.sqrt(b) * T2
    lead = sp.simplify((T1**2 - 2 * T2**2) / T2**2)  # sign of the x^2 coefficient of y'
    const = sp.expand((3 * T1**4 + 8 * T2**4 - 12 * T1**2 * T2**2) / T2**4)
    slope = sp.simplify((3 * T2**2 * T1 - T1**3) / T2**3)
    roots = sorted(float(r) for r in sp.solve(const, b))
    ok = (
        sp.solve(lead, b) == [2]
        and abs(roots[0] - 0.8453) < 1e-4
        and abs(roots[1] - 3.1547) < 1e-4
        and sp.solve(slope, b) == [3]
        and lead.subs(b, 1) < 0
        and slope.subs(b, 1) > 0
        and const.subs(b, 2) < 0
    )
    return ClaimResult(
        "opens down for beta1 < 2; constant term roots 0.8453, 3.1547; slope zero at 3",
        f"x^2 coefficient zero at {sp.solve(lead, b)}; roots {roots[0]:.4f}, {roots[1]:.4f}; "
        f"slope zero at {sp.solve(slope, b)}",
        ok,
    )


def servo_claims() -> list[Claim]:
    """The article's checkable statements, each with its numbers."""
    return [
        Claim(
            "table-13",
            "The simulated parabola error after the transient equals (13) within 1 % in all 16 "
            "table cells "
            "(v = 50 mm/s, p = 20 mm, omega = 5; k = 100..1000 1/s, T = 0.01..1 s).",
            "(13), table",
            claim_table_13,
        ),
        Claim(
            "table-0.8",
            "The printed table equals 0.8 x (13) in every cell (to its printed digits); the "
            "factor compatible "
            "with all cells lies in [0.7947, 0.8053] and excludes 1.",
            "table",
            claim_table_08,
        ),
        Claim(
            "line-5-6",
            "Non-identical channels reproduce a line parallel to the programmed one at the "
            "distance (5) = (6): "
            "0.05 mm at 45 deg (gamma = 1.2), -0.064952 mm at 30 deg (gamma = 0.7), k = 100 1/s, "
            "T = 0.05 s.",
            "(5), (6)",
            claim_line_5_6,
        ),
        Claim(
            "line-4",
            "Identical channels: the line is reproduced without error when starting at rest; "
            "with initial "
            "velocities the error is the transient (4), peaking near 1.05 T2^2/(T1 + T2) (within "
            "5 %).",
            "(3), (4)",
            claim_line_4,
        ),
        Claim(
            "circle-28",
            "Identical channels reproduce a circle of radius R0 |Phi(j omega)|: R0 - R = (28) to "
            "1e-6 "
            "(-0.24295 mm for R0 = 10 mm, omega = 5, k = 100, T = 0.1).",
            "(27), (28)",
            claim_circle_28,
        ),
        Claim(
            "circle-29-30",
            "Non-identical channels give an ellipse tilted by (29) with the semi-axes of (30) with "
            "cos^2 in the numerator (12.00691 / 10.78178 mm, 63.127 deg); the printed (30) is off.",
            "(29), (30)",
            claim_circle_29_30,
        ),
        Claim(
            "ellipse",
            "An ellipse is reproduced with semi-axes a|Phi|, b|Phi| (identical) and, for "
            "non-identical "
            "channels, the tilt (29) and the corrected (30) with m = a|Phi1|, n = b|Phi2| "
            "(15.97402 / 6.62696 mm, 1.809 deg).",
            f"{ARTICLE}, ellipses",
            claim_ellipse,
        ),
        Claim(
            "parabola-17-18",
            "Non-identical channels: the output parabola is (17); its vertices lie on the "
            "corrected "
            "locus (18) (linear coefficient omega (T1^2 - T2^2)/T1).",
            "(16)-(18)",
            claim_parabola_17_18,
        ),
        Claim(
            "parabola-19",
            "Horizontal parabola x = y^2/p (Fig. 4b: T1 = 0.01 s, T2^2 = 0.001 s^2, omega = 5, "
            "p = 20 mm): the simulated output follows (19) for gamma = 0.5, 0.8, 1, 1.25, 2, and its "
            "vertex is where (19) puts it: x_c = omega^2 p/4 (T1^2 - 2 T2^2) = -0.2375 mm for "
            "every gamma (the vertices lie on a straight line), y_c = -omega p T1 (gamma - 1)/2 = "
            "0.25 mm for gamma = 0.5 and -0.5 mm for gamma = 2.",
            "(19), Fig. 4b",
            claim_parabola_19,
        ),
        Claim(
            "parabola-19-error",
            "The error along the horizontal parabola per (19), largest over |y| <= 20 mm: 0.2375 mm "
            "for identical channels, growing for gamma < 1 and gamma > 1 (0.3448 mm on y > 0 for "
            "gamma = 0.5; 0.5533 mm on y < 0 and 0.3445 mm on y > 0 for gamma = 2); the simulated "
            "distances equal those of (19).",
            "(19), Fig. 4b",
            claim_parabola_19_error,
        ),
        Claim(
            "correction",
            "The program correction (7), (21)-(22), (31)-(34) removes the steady error (line, "
            "parabola, "
            "circle, non-identical channels); the PU starts at the article's X0, Y0.",
            "(7), (22), (34)",
            claim_correction,
        ),
        Claim(
            "parabola-24",
            "With the corrected program and the servo at rest, the error is the transient (24); "
            "for k = 100, "
            "T = 0.1 its peak is 0.562 mm at t = 0.25 s and it then vanishes.",
            "(24), (25)",
            claim_parabola_24,
        ),
        Claim(
            "derivative-feed",
            "Feeding x + T1 dx/dt removes the x error but increases the contour error: -0.25 mm vs "
            "(13) -0.2375 mm (k = 100, T = 0.1).",
            f"{ARTICLE}, conclusions",
            claim_derivative,
        ),
        Claim(
            "beta-15",
            "(15): f(beta) = 1/beta^2 - 2/beta has its only stationary point at beta = 1 (a "
            "minimum, f = -1) "
            "and its zero at beta = 1/2 with slope -8.",
            "(15), Fig. 3",
            claim_beta,
        ),
        Claim(
            "modulus-only",
            "Correcting only the moduli gives an ellipse at 45/135 deg with semi-axes R0 sqrt(1 "
            "+- |sin(phi2 - phi1)|) "
            "(12.346 / 6.897 mm: x k = 30, T = 0.01; y k = 200, T = 0.02; omega = 20, R0 = 10 "
            "mm); the printed form gives 13.379.",
            "after (35)",
            claim_modulus_only,
        ),
        Claim(
            "alt-correction",
            "Shifting the program by -delta_max (corrected Y0 of the alternative correction) "
            "keeps the reproduced "
            "point on the programmed parabola although x != x1 (k = 100 1/s, T = 0.1 and 1 s).",
            "after (25)",
            claim_alt_correction,
        ),
        Claim(
            "quartic-beta",
            "Quartic: y' opens downward for beta1 < 2; its vertex is above the programmed one "
            "for beta1 < 0.85 and "
            "beta1 > 3.15 (roots 0.8453, 3.1547 of 3 beta1^2 - 12 beta1 + 8); the line y'' rises "
            "for beta1 < 3.",
            f"{ARTICLE}, parabolas of degree 3 and 4",
            claim_quartic_beta,
        ),
        Claim(
            "cubic-quartic",
            "Cubic and quartic outputs follow the corrected curve equations (cubic: '+' not '='; "
            "quartic: the printed curve), and the corrected quartic y1(t), not the printed one.",
            f"{ARTICLE}, parabolas of degree 3 and 4",
            claim_cubic_quartic,
        ),
    ]
