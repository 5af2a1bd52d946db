"""The helix of §1.1 and the claims of the section, checked on it.

The source's example is one half-turn of a helix typed three ways: (1.2) x = sin phi,
y = cos phi, z = phi on [0, pi]; (1.3) = (1.2)(2 phi) on [0, pi/2]; (1.4) =
(1.2)(arccos phi) on [-1, 1], traversed the other way, with |r'|^2 = 2/(1 - phi^2)
integrably singular at both ends.  Its arc length is pi sqrt(2) (1.12); with the speed
laws (1.8) and (1.9) and the controls (1.15) the analyzer (1.5) reproduces it.
:func:`helix_claims` are the claims of
:mod:`analyzer_lab.lessons.analyzers.motion_program`.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.curves.arclength import ArcLengthCurve
from analyzer_lab.lessons.analyzers.curves.motion_law import (
    Program,
    check_controls,
    motion_program,
)
from analyzer_lab.lessons.analyzers.curves.profiles import (
    check_covers,
    check_join,
    check_numbers,
    check_triangle_formulas,
    speed_profile,
)
from analyzer_lab.lessons.analyzers.curves.space_curve import PHI, curve_model, hausdorff
from analyzer_lab.lessons.kit.contract import Claim, ClaimResult, at_most, close
from analyzer_lab.lessons.kit.formula import parse_formula, parse_number

#: the helix's arc length pi sqrt(2)
SQRT2PI = math.pi * math.sqrt(2.0)
#: the three forms (x, y, z, phi0, phi1)
HELIX_12 = ("sin(phi)", "cos(phi)", "phi", "0", "pi")
HELIX_13 = ("2*sin(phi)*cos(phi)", "2*cos(phi)^2 - 1", "2*phi", "0", "pi/2")
HELIX_14 = ("sqrt(1 - phi^2)", "phi", "acos(phi)", "-1", "1")


def helix_claims() -> list[Claim]:
    """The claims of §1.1, (1.2)-(1.15)."""
    return [
        Claim(
            "helix-length-1.2",
            "(1.2) has arc length pi sqrt(2) = 4.442883",
            "(1.2), (1.12)",
            lambda: close(SQRT2PI, helix_arc(HELIX_12).S_l, atol=1e-9),
        ),
        Claim(
            "helix-length-1.3",
            "(1.3) has arc length pi sqrt(2)",
            "(1.3), (1.12)",
            lambda: close(SQRT2PI, helix_arc(HELIX_13).S_l, atol=1e-9),
        ),
        Claim(
            "helix-length-1.4",
            "(1.4) has arc length pi sqrt(2) despite |r'|^2 = 2/(1 - phi^2)",
            "(1.4), (1.12)",
            lambda: close(SQRT2PI, helix_arc(HELIX_14).S_l, atol=1e-9),
        ),
        Claim(
            "helix-same-curve",
            "(1.2), (1.3), (1.4) are one point set (sampled Hausdorff distance <= 1e-9)",
            "(1.2)-(1.4)",
            lambda: at_most(1e-9, helix_hausdorff(), "Hausdorff "),
        ),
        Claim(
            "helix-speeds",
            "|r'|^2 = 2, 8 and 2/(1 - phi^2) for (1.2), (1.3), (1.4);"
            " (1.3)(phi) = (1.2)(2 phi), (1.4)(phi) = (1.2)(arccos phi)",
            "(1.2)-(1.4)",
            check_helix_symbolic,
        ),
        Claim(
            "helix-1.4-reversed",
            "(1.4) runs the other way: r_(1.4)(s) = r_(1.2)(S_l - s), start (0, -1, pi)",
            "(1.4)",
            lambda: at_most(1e-9, helix_reversal_gap(), "max distance "),
        ),
        Claim(
            "helix-1.4-radical",
            "with the root x^2 + y^2 = 1 on (1.4); without it (x = 1 - phi^2)"
            " x^2 + y^2 = 0.8125 at phi = 0.5",
            "(1.4)",
            check_radical,
        ),
        Claim(
            "trapezoid-numbers",
            "v0 = 1, Delta0 = Delta1 = 1 on the helix: L = 3.442883, T = 5.442883",
            "(1.8)",
            lambda: check_numbers(
                speed_profile(SQRT2PI, 1.0, 1.0, 1.0),
                kind="trapezoid",
                L=3.442882938158366,
                T=5.442882938158366,
            ),
        ),
        Claim(
            "trapezoid-covers",
            "the trapezoid law covers exactly S_l: integral of v = s(T) = S_l,"
            " v <= v0, slopes v0/Delta",
            "(1.7), (1.8)",
            lambda: check_covers(SQRT2PI, 1.0, 1.0, 1.0),
        ),
        Claim(
            "triangle-numbers",
            "v0 = 4, Delta0 = Delta1 = 2 on the helix: L = -3.557117,"
            " t1 = 1.490450, tau = v1 = 2.980900",
            "(1.9)",
            lambda: check_numbers(
                speed_profile(SQRT2PI, 4.0, 2.0, 2.0),
                kind="triangle",
                L=-3.557117061841634,
                t1=1.4904500894290902,
                tau=2.9809001788581804,
                v1=2.9809001788581804,
            ),
        ),
        Claim(
            "triangle-covers",
            "the triangle law covers exactly S_l with v1 <= v0 and the ramps' slopes",
            "(1.7), (1.9)",
            lambda: check_covers(SQRT2PI, 4.0, 1.0, 3.0),
        ),
        Claim(
            "triangle-formulas",
            "(1.9) solves v1 = k1 t1 = k2 (tau - t1), v1 tau/2 = S_l",
            "(1.9)",
            check_triangle_formulas,
        ),
        Claim(
            "profiles-join",
            "at L = 0 the triangle has v1 = v0 and equals the trapezoid (Delta = 0)",
            "(1.8), (1.9)",
            check_join,
        ),
        Claim(
            "controls-identity",
            "U X = Xdot for u_ij = Xdot_i X_j / D; the reading X_i Xdot_j / D fails",
            "(1.15)",
            check_controls,
        ),
        Claim(
            "reproduce-trapezoid",
            "(1.5) with (1.15) reproduces the helix, trapezoid law, to 1e-6 (RK4)",
            "(1.5), (1.15)",
            lambda: at_most(1e-6, reproduction_error(1.0, 1.0, 1.0), "max |X5 - X| "),
        ),
        Claim(
            "reproduce-triangle",
            "(1.5) with (1.15) reproduces the helix, triangle law, to 1e-6 (RK4)",
            "(1.5), (1.15)",
            lambda: at_most(1e-6, reproduction_error(4.0, 2.0, 2.0), "max |X5 - X| "),
        ),
        Claim(
            "speed-limit",
            "the speed of (1.5) never exceeds v(t) (within 1e-6)",
            "(1.5), (1.15)",
            lambda: at_most(1e-6, speed_excess(), "max(|U X5| - v) "),
        ),
        Claim(
            "end-point",
            "the motion ends at (0, -1, pi), the end of the helix",
            "(1.2), (1.11)",
            check_end_point,
        ),
        Claim(
            "helix-D",
            "(1.14) holds on the helix: D = 1 + Z^2 >= 1",
            "(1.14)",
            lambda: close(1.0, helix_min_D(), atol=1e-12),
        ),
    ]


def helix_arc(c: tuple[str, str, str, str, str]) -> ArcLengthCurve:
    """The arc length (1.12) of one form of the helix."""
    return curve_model(*c[:3], parse_number(c[3]), parse_number(c[4])).arc


def helix_program(v0: float, Delta0: float, Delta1: float) -> Program:
    """The program of the helix (1.2) with the speed law ``(v0, Delta0, Delta1)``."""
    return motion_program(*HELIX_12[:3], 0.0, math.pi, v0, Delta0, Delta1)


def helix_hausdorff() -> float:
    """The sampled Hausdorff distance between the point sets of (1.2), (1.3), (1.4)."""
    return hausdorff([helix_arc(c) for c in (HELIX_12, HELIX_13, HELIX_14)])


def helix_reversal_gap() -> float:
    """max |r_(1.4)(s) - r_(1.2)(S_l - s)| on 2001 samples, and the start point of (1.4)."""
    a12, a14 = helix_arc(HELIX_12), helix_arc(HELIX_14)
    s = np.linspace(0.0, a12.S_l, 2001)
    gap = float(np.max(np.linalg.norm(a14.point_of_s(s) - a12.point_of_s(a12.S_l - s), axis=1)))
    start = a14.r(np.array([-1.0]))[0]
    return max(gap, float(np.linalg.norm(start - np.array([0.0, -1.0, math.pi]))))


def check_helix_symbolic() -> ClaimResult:
    """|r'|^2 of the three forms, and (1.3), (1.4) as (1.2) of 2 phi and of arccos phi."""
    f12, f13, f14 = (
        sp.Matrix([parse_formula(f, variables=("phi",)).expr for f in c[:3]])
        for c in (HELIX_12, HELIX_13, HELIX_14)
    )
    sq = [sp.simplify(sum(d**2 for d in f.diff(PHI))) for f in (f12, f13, f14)]
    ok_sq = [sp.simplify(a - b) == 0 for a, b in zip(sq, (2, 8, 2 / (1 - PHI**2)))]
    ok_13 = all(
        sp.simplify(sp.expand_trig(a - b)) == 0 for a, b in zip(f13, f12.subs(PHI, 2 * PHI))
    )
    ok_14 = all(sp.simplify(a - b) == 0 for a, b in zip(f14, f12.subs(PHI, sp.acos(PHI))))
    return ClaimResult(
        "|r'|^2 = 2, 8, 2/(1-phi^2); both substitutions exact",
        f"{sq}; (1.3)~(1.2): {ok_13}; (1.4)~(1.2): {ok_14}",
        bool(all(ok_sq) and ok_13 and ok_14),
    )


def check_radical() -> ClaimResult:
    """(1.4) lies on x^2 + y^2 = 1 with the square root, not without it."""
    phi = np.linspace(-1.0, 1.0, 201)
    dev = float(np.max(np.abs(helix_arc(HELIX_14).r(phi)[:, 0] ** 2 + phi**2 - 1.0)))
    without = parse_formula("1 - phi^2", variables=("phi",)).value(0.5) ** 2 + 0.5**2
    return ClaimResult(
        "max |x^2 + y^2 - 1| < 1e-14 with the root; 0.8125 without",
        f"{dev:.2g}; {without:.10g}",
        dev < 1e-14 and abs(without - 0.8125) < 1e-15,
    )


def reproduction_error(v0: float, Delta0: float, Delta1: float) -> float:
    """max |X5 - X| over the RK4 steps: (1.5) with (1.15) against the program."""
    prog = helix_program(v0, Delta0, Delta1)
    return float(np.max(np.linalg.norm(prog.Y - prog.law(prog.steps)["X"], axis=1)))


def speed_excess() -> float:
    """max(|U X5| - v, |Xdot| - v) over the RK4 steps of three helix runs."""
    worst = -math.inf
    for law in ((1.0, 1.0, 1.0), (4.0, 2.0, 2.0), (4.0, 1.0, 3.0)):
        prog = helix_program(*law)
        st = prog.law(prog.steps)
        for V in (prog.F, st["V"]):
            worst = max(worst, float(np.max(np.linalg.norm(V, axis=1) - st["v"])))
    return worst


def check_end_point() -> ClaimResult:
    """The solution of (1.5) ends at the helix's end (0, -1, pi) for both speed laws."""
    end = np.array([0.0, -1.0, math.pi])
    errs = [
        float(np.linalg.norm(helix_program(*law).Y[-1] - end)) for law in ((1, 1, 1), (4, 2, 2))
    ]
    return at_most(1e-6, max(errs), "|X5(T) - (0, -1, pi)| ")


def helix_min_D() -> float:
    """min D = X^2 + Y^2 + Z^2 (1.14) along the helix's motion."""
    prog = helix_program(1.0, 1.0, 1.0)
    return float(np.min(prog.law(np.linspace(0.0, prog.T, 2001))["D"]))
