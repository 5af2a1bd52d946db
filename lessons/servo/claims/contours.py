"""The claims of Leppik (1960) on the line and the circle: the distance (5) = (6) of the
line reproduced by non-identical channels and the transient (4) of identical ones, the
circle of radius R0 |Phi(j omega)| (28), and the ellipse of non-identical channels with
the tilt (29) and the semi-axes of the corrected (30); each computed from the exact model
and compared with the article's numbers.
"""

from __future__ import annotations

import math

import numpy as np
from analyzer_lab.lessons.kit.contract import ClaimResult, close
from analyzer_lab.lessons.servo.formulas import circle_axes_29_30, f_transient
from analyzer_lab.lessons.servo.geometry import fit_centred_ellipse, line_distance
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo, settled
from analyzer_lab.lessons.servo.paths import ellipse_program, line_program


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
