"""The integrator benchmark's problems, shared with the tests of the analyzers' integrators."""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.analyzers.field.analyzer import Controls
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.formula import parse_formula


def problems() -> list[tuple[str, Quadric, Controls, np.ndarray]]:
    """The benchmark problems: an ellipsoid and a one-sheet hyperboloid, time-varying u, both speed modes."""
    ell = Quadric.ellipsoid(10.0, 5.0, 1.0)
    hyp = Quadric.hyperboloid_one_sheet(1.0, 1.0, 1.0)
    f = parse_formula
    u_ell = (f("1 + 0.5*sin(t)"), f("0.2"), f("2*cos(t/3)"))
    u_hyp = (f("1 + 0.5*sin(t)"), f("0.3*cos(t)"), f("0.2"))
    start_ell = np.array([0.0, -5.0, 0.0])
    start_hyp = np.array([1.0, 0.0, 0.0])
    return [
        ("ellipsoid 10,5,1, u(t)", ell, Controls(*u_ell), start_ell),
        ("ellipsoid 10,5,1, u(t), V = 1", ell, Controls(*u_ell, V=1.0), start_ell),
        ("hyperboloid 1 sheet, u(t)", hyp, Controls(*u_hyp), start_hyp),
    ]
