"""The programmed paths of Leppik (1960): the programming devices (PU) and their contours.

Each path is a linear PU dz/dt = A z (z holds a constant 1) started on the curve: the
line (1), the vertical parabola (9) p(y - yc) = (x - xc)^2, the horizontal parabola
p(x - xc) = (y - yc)^2 of (19) (the PU of (9) with x and y exchanged), the circle (26),
the ellipse and the cubic/quartic parabolas (Fig. 7; its PU is not described, an
integrator chain gives the article's output x = omega p t, y = omega^n p^(n-1) t^n).
:class:`Path` measures the signed contour error of any point from the programmed curve
through the PU's current point.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from analyzer_lab.lessons.servo.geometry import (
    Distance,
    ellipse_distance,
    line_distance,
    power_distance,
)
from analyzer_lab.lessons.servo.model import Program, planar_program

CURVES = ("line", "parabola", "parabola-horizontal", "circle", "ellipse", "cubic", "quartic")
#: degree of the parabolas with their axis along y (the horizontal parabola is degree 2 too)
DEGREE = {"parabola": 2, "cubic": 3, "quartic": 4}


def line_program(x0: float, y0: float, v: float, angle_deg: float) -> Program:
    """(1): x = x0 + omega yc t, y = y0 + omega xc t, omega yc = v cos(angle), omega xc = v sin."""
    th = math.radians(angle_deg)
    A = np.zeros((3, 3))
    A[0, 2] = v * math.cos(th)
    A[1, 2] = v * math.sin(th)
    return planar_program(A, x0, y0)


def power_program(n: int, x0: float, xc: float, yc: float, p: float, omega: float) -> Program:
    """Parabola of degree n about the vertex/inflection (xc, yc): y - yc = (x - xc)^n / p.

    n = 2 is the article's PU (9): dx/dt = omega p/2, dy/dt = omega (x - xc).  For n = 3, 4
    the PU is an integrator chain producing x - xc = omega p tau, y - yc = omega^n p^(n-1)
    tau^n (tau = t + tau0).
    """
    if n == 2:
        A = np.zeros((3, 3))
        A[0, 2] = omega * p / 2.0
        A[1, 0] = omega
        A[1, 2] = -omega * xc
        return planar_program(A, x0, yc + (x0 - xc) ** 2 / p)
    dim = n + 2  # z = (x, y, y', ..., y^(n-1), 1)
    A = np.zeros((dim, dim))
    A[0, dim - 1] = omega * p
    for i in range(1, n):
        A[i, i + 1] = 1.0
    c = omega**n * p ** (n - 1)
    A[n, dim - 1] = math.factorial(n) * c
    tau0 = (x0 - xc) / (omega * p)
    z0 = np.zeros(dim)
    z0[0], z0[1], z0[dim - 1] = x0, yc, 1.0
    for j in range(n):  # y^(j)(tau0)
        z0[1 + j] += c * math.factorial(n) / math.factorial(n - j) * tau0 ** (n - j)
    Cx, Cy = np.zeros(dim), np.zeros(dim)
    Cx[0], Cy[1] = 1.0, 1.0
    return Program(A, z0, Cx, Cy)


def horizontal_parabola_program(y0: float, xc: float, yc: float, p: float, omega: float) -> Program:
    """The PU of (9) with x and y exchanged: dy/dt = omega p/2, dx/dt = omega (y - yc), so
    p(x - xc) = (y - yc)^2 and x = xc + (y0 - yc)^2/p at the start."""
    vertical = power_program(2, y0, yc, xc, p, omega)
    swap = [1, 0, 2]
    return planar_program(vertical.A[np.ix_(swap, swap)], vertical.z0[1], vertical.z0[0])


def ellipse_program(
    x0: float, y0: float, xc: float, yc: float, a: float, b: float, omega: float
) -> Program:
    """PU of the ellipse / circle (26) (a = b): dx/dt = omega (a/b)(y - yc),
    dy/dt = -omega (b/a)(x - xc)."""
    A = np.zeros((3, 3))
    A[0, 1] = omega * a / b
    A[0, 2] = -omega * a / b * yc
    A[1, 0] = -omega * b / a
    A[1, 2] = omega * b / a * xc
    return planar_program(A, x0, y0)


@dataclass(frozen=True)
class Path:
    """A programmed path: its PU and the signed contour error from its curve.

    ``g``: the path's numbers (x0, y0, xc, yc, p, omega, v, angle, a, b).
    """

    curve: str
    program: Program
    g: Mapping[str, float]

    @property
    def start(self) -> tuple[float, float]:
        """The programmed start point (parabolas start on their curve)."""
        z0 = self.program.z0
        return float(self.program.Cx @ z0), float(self.program.Cy @ z0)

    def contour(self, xq: np.ndarray, yq: np.ndarray, x: np.ndarray, y: np.ndarray) -> Distance:
        """Signed distance of (xq, yq) from the curve through the PU's point (x, y); foot points."""
        g = self.g
        if self.curve == "line":
            return line_distance(xq, yq, x, y, g["angle"])
        if self.curve in DEGREE:
            n = DEGREE[self.curve]
            yc = y - (x - g["xc"]) ** n / g["p"]  # constant along a run
            return power_distance(xq, yq, n, g["xc"], yc, g["p"], guess=x)
        if self.curve == "parabola-horizontal":
            xc = x - (y - g["yc"]) ** 2 / g["p"]
            d, fy, fx = power_distance(yq, xq, 2, g["yc"], xc, g["p"], guess=y)
            return d, fx, fy
        a, b = (g["a"], g["b"]) if self.curve == "ellipse" else (1.0, 1.0)
        scale = np.hypot((np.atleast_1d(x) - g["xc"]) / a, (np.atleast_1d(y) - g["yc"]) / b)
        return ellipse_distance(xq, yq, g["xc"], g["yc"], a * scale, b * scale)

    def vertex(self) -> tuple[str, tuple[float, float]] | None:
        """The programmed vertex, inflection point or centre (none for a line)."""
        g = self.g
        if self.curve == "line":
            return None
        if self.curve in DEGREE:
            x, y = self.start
            return "vertex", (g["xc"], y - (x - g["xc"]) ** DEGREE[self.curve] / g["p"])
        if self.curve == "parabola-horizontal":
            x, y = self.start
            return "vertex", (x - (y - g["yc"]) ** 2 / g["p"], g["yc"])
        return "centre", (g["xc"], g["yc"])

    def size(self) -> tuple[float, float]:
        """Semi-axes (A0, B0) of the programmed circle/ellipse through the start point."""
        x, y = self.start
        X, Y = x - self.g["xc"], y - self.g["yc"]
        if self.curve == "circle":
            return math.hypot(X, Y), math.hypot(X, Y)
        a, b = self.g["a"], self.g["b"]
        s = math.hypot(X / a, Y / b)
        return a * s, b * s


def make_path(curve: str, g: Mapping[str, float]) -> Path:
    """The path ``curve`` from its numbers ``g`` (see :class:`Path`)."""
    if curve == "line":
        program = line_program(g["x0"], g["y0"], g["v"], g["angle"])
    elif curve in DEGREE:
        program = power_program(DEGREE[curve], g["x0"], g["xc"], g["yc"], g["p"], g["omega"])
    elif curve == "parabola-horizontal":
        program = horizontal_parabola_program(g["y0"], g["xc"], g["yc"], g["p"], g["omega"])
    else:
        a, b = (g["a"], g["b"]) if curve == "ellipse" else (1.0, 1.0)
        program = ellipse_program(g["x0"], g["y0"], g["xc"], g["yc"], a, b, g["omega"])
    return Path(curve, program, dict(g))
