"""Problem 2.1: the single-coordinate linear positioner, eqs (2.1)-(2.2).

A carriage of mass M on a straight guide.  D'Alembert's principle (2.1), projected on the
guide's axis X, gives (2.2): ``M x'' = F_dv - R_sopr + N_x`` (drive force, resistance,
guide reaction; N_x = 0 for ideal guides).  Here the equation is derived by
``LagrangesMethod`` from ``T = M x'^2/2`` and the virtual work of the three forces.
Forward problem: the forces as formulas of t give the motion; inverse problem: a motion
law x(t) gives the drive force F_dv.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.bodies import IDENTITY_Q, bounds_of, box
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Param,
    Params,
    PlotSpec,
    Preset,
    SceneSpec,
    close,
)
from analyzer_lab.lessons.kit.formula import t_symbol
from analyzer_lab.lessons.mechanics.lagrange.model import LagrangeModel
from analyzer_lab.lessons.mechanics.positioners.lesson import (
    T_,
    Coord,
    Input,
    PositionerLesson,
    arrow,
    is_zero,
    positioner_groups,
    positioner_params,
    positioner_series,
    sym,
    symbolic_claim,
)
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

Array = np.ndarray


class LinearPositioner(PositionerLesson):
    """Problem 2.1: d'Alembert (2.1) projected on X gives M x'' = sum F_x^A + sum N_x (2.2)."""

    id = "linear-positioner"
    title = "Single-coordinate linear positioner"
    problem = "Problem 2.1"
    source = "Textbook §2.1, Problem 2.1, eqs (2.1)-(2.2)"
    summary = (
        "A carriage on a straight guide: M x'' = F_dv - R_sopr + N_x; forward and inverse problems."
    )
    order = 2.01
    coords = (Coord("x", "x", "m", 0.0, "0.1*(1 - cos(pi*t/2))"),)
    inputs = (
        Input("F_dv", "driving force F_dv", "N", "2 + sin(3*t)"),
        Input("R_sopr", "resistance force R_sopr", "N", "0.5", unknown=False),
        Input("N_x", "reaction N_x (0 for ideal guides)", "N", "0", unknown=False),
    )
    physical = ("M",)
    groups = positioner_groups("Carriage")
    params = positioner_params(
        coords,
        inputs,
        (
            Param(
                "M", "float", 5.0, label="moving mass M", unit="kg", min=1e-3, max=1e4, group="body"
            ),
        ),
    )
    series = positioner_series(coords, inputs)
    readout = ("x", "x_dot", "x_ddot", "F_dv")
    presets = (
        Preset(
            "forward-constant-force",
            "Forward: constant drive 2 N against 0.5 N resistance",
            {"problem": "forward", "F_dv": "2", "R_sopr": "0.5"},
            t_end=10.0,
        ),
        Preset(
            "forward-harmonic", "Forward: F_dv = 2 + sin 3t", {"problem": "forward"}, t_end=10.0
        ),
        Preset(
            "inverse-cosine-move",
            "Inverse: x = 0.1 (1 - cos(pi t/2)) m",
            {"problem": "inverse"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Coordinate", ("x",), "m"),
        PlotSpec("Velocity", ("x_dot",), "m/s"),
        PlotSpec("Forces", ("F_dv", "R_sopr", "N_x"), "N"),
    )

    problem_notes = (
        "Inverse problem: R_sopr and N_x stay as given; F_dv is the force the law x(t)"
        " needs, (2.2).",
        "Forward problem: the motion law x(t) is not used.",
        "(2.2)",
    )

    def build_model(self, key: str) -> LagrangeModel:
        x = dynamicsymbols("x")
        M, F, R, Nx = sym("M", positive=True), sym("F_dv"), sym("R_sopr"), sym("N_x")
        N = ReferenceFrame("N")
        P = Point("P")
        P.set_vel(N, x.diff(T_) * N.x)
        T = M * x.diff(T_) ** 2 / 2
        return LagrangeModel.build(
            [x], T, sp.S.Zero, T_, [M], [F, R, Nx], forcelist=[(P, (F - R + Nx) * N.x)], frame=N
        )

    def textbook_eq(self) -> sp.Expr:
        x = dynamicsymbols("x")
        M, F, R, Nx = sym("M", positive=True), sym("F_dv"), sym("R_sopr"), sym("N_x")
        return M * x.diff(T_, 2) - (F - R + Nx)

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        x = m.q[0]
        M, F, R, Nx = m.params[0], *m.inputs
        steps = [
            DerivationStep(
                "d'Alembert principle",
                "Active forces, constraint reactions and inertia forces are in equilibrium.",
                r"\sum \vec F^{A}+\sum \vec N-\sum m_i\vec a_i=0",
                "(2.1)",
            ),
            DerivationStep(
                "Kinetic energy",
                (
                    "All points have the same acceleration, so the moving mass M = sum m_i acts "
                    "as one body."
                ),
                sp.Eq(sp.Symbol("T"), M * x.diff(T_) ** 2 / 2),
            ),
            DerivationStep(
                "Generalized force",
                "Virtual work of the drive, the resistance and the guide reaction on dx.",
                sp.Eq(sp.Symbol("Q_x"), F - R + Nx),
                "(2.2)",
            ),
            DerivationStep(
                "Equation of motion (Lagrange equation of the 2nd kind)",
                "Projection on the X axis.",
                m.equations()[0],
                "(2.2)",
            ),
        ]
        if params["problem"] == "forward":
            steps.append(
                DerivationStep(
                    "Forward problem",
                    "Forces known: the acceleration, then the motion by integration.",
                    sp.Eq(x.diff(T_, 2), (F - R + Nx) / M),
                )
            )
        else:
            law = params["x_t"].expr.subs(t_symbol, T_)
            steps.append(
                DerivationStep(
                    "Inverse problem",
                    "Motion law given: the drive force it needs.",
                    sp.Eq(F, sp.simplify(M * sp.diff(law, T_, 2) + R - Nx)),
                    "(2.2)",
                )
            )
        return steps

    def scene_size(self, params: Params) -> float:
        lo, hi = self._range(params)
        return max(hi - lo, 0.5)

    def _range(self, params: Params) -> tuple[float, float]:
        """Lowest and highest x of the default run (once per values)."""
        return self.cached("range", params, lambda: self._measure_range(params))

    def _measure_range(self, params: Params) -> tuple[float, float]:
        r = self.coarse_run(params)
        x = r.series["x"]
        x = x[np.isfinite(x)]
        return (float(x.min()), float(x.max())) if len(x) else (0.0, 1.0)

    def scene(self, params: Params) -> SceneSpec:
        lo, hi = self._range(params)
        span = max(hi - lo, 0.5)
        s = 0.15 * span
        rail = box(
            "guide",
            (span + 2 * s, 0.4 * s, 0.2 * s),
            (90, 90, 90),
            center=((lo + hi) / 2, 0, -0.1 * s),
        )
        carriage = box(
            "carriage", (s, 0.8 * s, 0.5 * s), (70, 130, 200)
        )  # posed 0.25 s above the guide
        pts = np.array([[lo - s, -s, -s], [hi + s, s, s]])
        return SceneSpec(
            bounds=bounds_of(pts),
            meshes=[rail],
            bodies=[carriage],
            moving_vectors={"F_dv": (40, 160, 60), "R_sopr": (200, 60, 60)},
            moving_points={"carriage": (70, 130, 200)},
        )

    def pose(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        x = float(q[0])
        s = 0.15 * self.scene_size(params)
        p = np.array([x, 0.0, 0.0])
        fr.poses["carriage"] = (p + [0, 0, 0.25 * s], IDENTITY_Q.copy())
        fr.points["carriage"] = p[None, :]
        fr.vectors["F_dv"] = arrow(p + [0, 0, 0.6 * s], [scale * u[0], 0, 0])
        fr.vectors["R_sopr"] = arrow(p + [0, 0, 0.6 * s], [-scale * u[1], 0, 0])

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            return is_zero(m.eom()[0] - self.textbook_eq())

        def constant_force() -> ClaimResult:
            r = self.run("forward-constant-force")
            return close(1.5 / 5.0 * 10.0**2 / 2, float(r.series["x"][-1]), rtol=1e-8)

        return [
            Claim(
                "eq-2.2",
                (
                    "LagrangesMethod with T = M x'^2/2 and Q_x = F_dv - R_sopr + N_x gives "
                    "(2.2): M x'' = F_dv - R_sopr + N_x"
                ),
                "(2.2)",
                symbolic_claim(eq_ok, "(2.2)"),
            ),
            Claim(
                "forward-constant",
                (
                    "Forward: F_dv = 2 N, R_sopr = 0.5 N, M = 5 kg from rest: x(10) = (1.5/5) "
                    "10^2/2 = 15 m"
                ),
                "(2.2)",
                constant_force,
            ),
            Claim(
                "round-trip-forward-inverse",
                (
                    "Forward then inverse recovers the drive force F_dv = 2 + sin 3t (within "
                    "1e-4 of its peak)"
                ),
                "(2.2)",
                self.forward_inverse_check(
                    {"M": 5.0, "F_dv": "2 + sin(3*t)", "R_sopr": "0.5"},
                    "max |F_dv recovered - F_dv| ",
                ),
            ),
            Claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces the law x = 0.1(1 - cos(pi t/2)) to 1e-8 m",
                "(2.2)",
                self.inverse_forward_check({"M": 5.0}, "max |x forward - x law| (m) "),
            ),
        ]


LESSON = LinearPositioner()
