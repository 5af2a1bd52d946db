"""The claims of Leppik (1960) on correcting the error: the corrected program (7),
(21)-(22), (31)-(34) that removes the steady error of the line, the parabola and the
circle; the alternative correction after (25) (the parabola shifted by -delta_max); the
derivative feed of the conclusions; and correcting the moduli only, after (35).
"""

from __future__ import annotations

import math

import numpy as np
from analyzer_lab.lessons.kit.contract import ClaimResult, at_most
from analyzer_lab.lessons.servo.formulas import delta_parabola_13
from analyzer_lab.lessons.servo.geometry import fit_centred_ellipse, power_distance
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo, planar_program, settled
from analyzer_lab.lessons.servo.paths import ellipse_program, line_program, power_program
from analyzer_lab.lessons.servo.table import simulate_parabola_vertex_error


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


def claim_alt_correction() -> ClaimResult:
    worst = 0.0
    for T in (0.1, 1.0):
        ch = Channel.from_open_loop(100.0, T)
        d13 = delta_parabola_13(5.0, 20.0, ch.T1, ch.T2sq)
        x0 = -50.0 * 25.0 / ch.decay_rate()
        prog = power_program(2, x0, 0.0, -d13, 20.0, 5.0)  # Y0 = y0 - delta_max
        _, out = settled(prog, ch, ch, window=0.2, n=401, settle=20.0)
        d, _, _ = power_distance(out["x1"], out["y1"], 2, 0.0, 0.0, 20.0, guess=out["x1"])
        worst = max(worst, float(np.max(np.abs(d))))
    return at_most(1e-6, worst, "max distance to y = x^2/p [mm] ")


def claim_derivative() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    d = simulate_parabola_vertex_error(ch, 5.0, 20.0, "derivative")
    d13 = delta_parabola_13(5.0, 20.0, ch.T1, ch.T2sq)
    ok = abs(d - (-0.25)) < 1e-6 and abs(d) > abs(d13)
    return ClaimResult(
        "-0.25 mm (= -omega^2 p T2^2/2), larger than |(13)| = 0.2375", f"{d:.7f} mm", ok
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
