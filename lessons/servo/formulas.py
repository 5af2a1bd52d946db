"""The closed forms of Leppik (1960), with the misprints corrected where the article is wrong.

Each function is one equation of the article, named by its number: the transient shape
of (4), (8), (24); the line offset (5)/(6); the parabola errors (13), (17)-(19), (24);
the circle and ellipse axes (28)-(30); the cubic and quartic output curves (section on
parabolas of degree 3 and 4).  Where the printed form is wrong the function computes the
corrected one (the derivation steps of the lesson say which and why); a ``printed`` flag
gives the printed form where the lesson compares both.  :func:`article_error` picks the
article's steady contour error for a path.
"""

from __future__ import annotations

import math

import numpy as np
from analyzer_lab.lessons.servo.model import Channel
from analyzer_lab.lessons.servo.paths import Path


def f_transient(t: np.ndarray, ch: Channel) -> np.ndarray:
    """f(t) = (e^{a1 t} - e^{a2 t})/(a1 - a2), the transient shape in (4), (8), (24)."""
    a1, a2 = ch.roots()
    t = np.asarray(t, dtype=float)
    if abs(a1 - a2) < 1e-12 * (abs(a1) + abs(a2)):
        return (t * np.exp(a1.real * t)).real
    return ((np.exp(a1 * t) - np.exp(a2 * t)) / (a1 - a2)).real


def delta_line_5(v: float, angle_deg: float, T1: float, gamma: float) -> float:
    """(5)/(6): delta = v xc yc T1 (gamma - 1)/(xc^2 + yc^2), (yc, xc) ~ (cos, sin) of the angle."""
    th = math.radians(angle_deg)
    return v * math.sin(th) * math.cos(th) * T1 * (gamma - 1.0)


def delta_parabola_13(omega: float, p: float, T1: float, T2sq: float) -> float:
    """(13): delta_max = omega^2 p/4 (T1^2 - 2 T2^2) (also the vertex of (12) and (19))."""
    return omega**2 * p / 4.0 * (T1**2 - 2.0 * T2sq)


def deviation_24(t: np.ndarray, omega: float, p: float, ch: Channel) -> np.ndarray:
    """(24): y1 - x1^2/p with the corrected program and the servo starting at rest."""
    f = f_transient(t, ch)
    return omega**2 * p / 4.0 * (2.0 * np.asarray(t) - f) * f


def curve_17(x: np.ndarray, omega: float, p: float, T1: float, T2sq: float, gamma: float):
    """(17): the output parabola y(x) of the vertical parabola, y channel scaled by gamma."""
    c = T1**2 * (1 - 2 * gamma + 2 * gamma**2) - 2 * gamma * T2sq
    return x**2 / p + omega * T1 * (1 - gamma) * x + omega**2 * p / 4 * c


def parabola_vertex_17(
    omega: float, p: float, T1: float, T2sq: float, gamma: float
) -> tuple[float, float]:
    """Vertex of the output parabola (17) relative to the programmed vertex."""
    return (
        -omega * p * T1 * (1.0 - gamma) / 2.0,
        omega**2 * p / 4.0 * (gamma**2 * T1**2 - 2.0 * gamma * T2sq),
    )


def locus_18(x: float, omega: float, p: float, T1: float, T2sq: float, printed: bool = False):
    """(18): the locus of the vertices of (17) as gamma varies (corrected: the linear
    coefficient is omega (T1^2 - T2^2)/T1; ``printed=True``: without /T1)."""
    slope = omega * (T1**2 - T2sq) / (1.0 if printed else T1)
    return x**2 / p + slope * x + omega**2 * p / 4 * (T1**2 - 2 * T2sq)


def curve_19(y: np.ndarray, omega: float, p: float, T1: float, T2sq: float, gamma: float):
    """(19): the output parabola x(y) of the horizontal parabola x = y^2/p, y channel
    scaled by gamma."""
    c = T1**2 * (2 + gamma**2 - 2 * gamma) - 2 * T2sq
    return y**2 / p + omega * T1 * y * (gamma - 1) + omega**2 * p / 4 * c


def parabola_vertex_19(
    omega: float, p: float, T1: float, T2sq: float, gamma: float
) -> tuple[float, float]:
    """Vertex of (19): x_c = omega^2 p/4 (T1^2 - 2 T2^2) for every gamma (the vertices lie
    on a straight line), y_c = -omega p T1 (gamma - 1)/2."""
    return delta_parabola_13(omega, p, T1, T2sq), -omega * p * T1 * (gamma - 1.0) / 2.0


def circle_axes_29_30(
    m: float, n: float, dphi: float, printed: bool = False
) -> tuple[float, float, float]:
    """(29) tilt alpha [deg] of the major axis and (30) semi-axes (major, minor).

    Corrected (30): numerator cos^2(phi2 - phi1); ``printed=True`` uses the printed cos.
    (29) fixes the axes modulo 90 deg; the major one is picked from the quadratic form.
    """
    num = math.cos(dphi) if printed else math.cos(dphi) ** 2
    s = (m * m + n * n) / (2 * m * m * n * n)
    r = math.sqrt(
        max((m * m + n * n) ** 2 / (4 * m**4 * n**4) - math.cos(dphi) ** 2 / (m * m * n * n), 0.0)
    )
    major = math.sqrt(num / (s - r)) if s - r > 0 and num >= 0 else math.nan
    minor = math.sqrt(num / (s + r)) if num >= 0 else math.nan  # the printed cos can be < 0
    two_alpha = math.atan2(2 * m * n * math.sin(dphi), n * n - m * m)
    alpha = math.degrees(two_alpha / 2.0)
    Q = np.array([[1 / m**2, math.sin(dphi) / (m * n)], [math.sin(dphi) / (m * n), 1 / n**2]])
    u = np.array([math.cos(math.radians(alpha)), math.sin(math.radians(alpha))])
    lam_min = float(np.linalg.eigvalsh(Q)[0])
    if abs(float(u @ Q @ u) - lam_min) > 1e-9 * abs(lam_min):
        alpha += 90.0
    return alpha % 180.0, major, minor


def cubic_curve(x: np.ndarray, omega: float, p: float, T1: float, T2sq: float):
    """The reproduced cubic: y = x^3/p + 3 omega^2 p (T1^2 - 2T2^2) x + 2 omega^3 p^2 (3 T1
    T2^2 - T1^3) (printed with '=' for the first '+')."""
    return (
        x**3 / p
        + 3 * omega**2 * p * (T1**2 - 2 * T2sq) * x
        + 2 * omega**3 * p**2 * (3 * T1 * T2sq - T1**3)
    )


def quartic_curve(x: np.ndarray, omega: float, p: float, T1: float, T2sq: float):
    """The reproduced quartic (printed correctly)."""
    return (
        x**4 / p
        + 6 * omega**2 * p * (T1**2 - 2 * T2sq) * x**2
        + 8 * omega**3 * p**2 * (3 * T2sq * T1 - T1**3) * x
        + 3 * omega**4 * p**3 * (3 * T1**4 + 8 * T2sq**2 - 12 * T1**2 * T2sq)
    )


def quartic_y1(tau: np.ndarray, omega: float, p: float, T1: float, T2sq: float, printed=False):
    """The quartic's steady y1(t) (tau: PU time from the vertex); corrected, or as printed
    (three signs flipped and T1^2 for T1^3 in the t term)."""
    c = omega**4 * p**3
    if printed:
        inner = (
            T1 * tau**3
            + 3 * (T1**2 - T2sq) * tau**2
            - 6 * (T1**2 - 2 * T2sq * T1) * tau
            + 6 * T1**4
            - 18 * T2sq * T1**2
            + 6 * T2sq**2
        )
    else:
        inner = (
            T1 * tau**3
            - 3 * (T1**2 - T2sq) * tau**2
            + 6 * (T1**3 - 2 * T1 * T2sq) * tau
            - 6 * (T1**4 - 3 * T1**2 * T2sq + T2sq**2)
        )
    return c * tau**4 - 4 * c * inner


def cubic_offset(omega: float, p: float, cx: Channel, cy: Channel) -> float:
    """Height of the reproduced cubic above the programmed inflection point (steady state)."""
    tau, T1, T2 = cx.T1, cy.T1, cy.T2sq
    inner = T1 * tau**2 + 2 * T2 * tau - 2 * T1**2 * tau + 2 * T1**3 - 4 * T1 * T2
    return omega**3 * p**2 * (tau**3 - 3 * inner)


def quartic_offset(omega: float, p: float, cx: Channel, cy: Channel) -> float:
    """Height of the reproduced quartic above the programmed vertex (corrected y1(t))."""
    return float(quartic_y1(cx.T1, omega, p, cy.T1, cy.T2sq))


def article_error(path: Path, cx: Channel, cy: Channel, gamma: float) -> tuple[float, str]:
    """The article's closed form of the steady contour error for this path, and its label."""
    g, curve = path.g, path.curve
    omega, p = g["omega"], g["p"]
    if curve == "line":
        return delta_line_5(g["v"], g["angle"], cx.T1, gamma), "(5)"
    if curve == "parabola":
        if gamma == 1.0:
            return delta_parabola_13(omega, p, cx.T1, cx.T2sq), "(13)"
        return parabola_vertex_17(omega, p, cx.T1, cx.T2sq, gamma)[1], "(17) vertex height"
    if curve == "parabola-horizontal":
        return parabola_vertex_19(omega, p, cx.T1, cx.T2sq, gamma)[0], "(19) vertex"
    if curve == "cubic":
        return cubic_offset(omega, p, cx, cy), "inflection shift"
    if curve == "quartic":
        return quartic_offset(omega, p, cx, cy), "vertex shift"
    A0, B0 = path.size()
    P1, P2 = cx.response(omega), cy.response(omega)
    if gamma == 1.0:
        return A0 * (1.0 - abs(P1)), "(28)" if curve == "circle" else "a(1 - |Phi|)"
    _, major, _ = circle_axes_29_30(A0 * abs(P1), B0 * abs(P2), float(np.angle(P2) - np.angle(P1)))
    return max(A0, B0) - major, "R0 - a, (30)" if curve == "circle" else "a - a', (30)"
