"""The checkable claims of Leppik (1960), each computed from the model and compared.

Every claim states the article's numbers (or the corrected ones, where the print is
wrong) and checks them against the exact simulation of
:mod:`analyzer_lab.lessons.servo.model` and the closed forms of
:mod:`analyzer_lab.lessons.servo.formulas`.  :func:`servo_claims` lists them in the
article's order; the checks are grouped by what they are about: the line, the circle and
the ellipse (:mod:`.contours`), the parabolas (:mod:`.parabola`) and the corrections
(:mod:`.correction`).
"""

from __future__ import annotations

from analyzer_lab.lessons.kit.contract import Claim
from analyzer_lab.lessons.servo.claims.contours import (
    claim_circle_28,
    claim_circle_29_30,
    claim_ellipse,
    claim_line_4,
    claim_line_5_6,
)
from analyzer_lab.lessons.servo.claims.correction import (
    claim_alt_correction,
    claim_correction,
    claim_derivative,
    claim_modulus_only,
)
from analyzer_lab.lessons.servo.claims.parabola import (
    claim_beta,
    claim_cubic_quartic,
    claim_parabola_17_18,
    claim_parabola_19,
    claim_parabola_19_error,
    claim_parabola_24,
    claim_quartic_beta,
    claim_table_08,
    claim_table_13,
)

ARTICLE = "Leppik (1960)"


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
