"""Problem 2.3: the two-coordinate planar positioner, eqs (2.5)-(2.11).

An X-Y stage of total moving mass M moves along two independent coordinates x, y.  The
Lagrange equations of the 2nd kind (2.5) with ``T = M (x'^2 + y'^2)/2`` (2.6)-(2.7), the
potential energy of the layout (horizontal: U = 0 (2.8); vertical, Y up: U = M g y (2.9))
and the generalized forces from the virtual work (2.10) give (2.11) in its corrected
form: ``M x'' = -dU/dx + Q_x``, ``M y'' = -dU/dy + Q_y``.  Forward problem: Q_x(t), Q_y(t)
give the motion; inverse problem: x(t), y(t) give the forces.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.bodies import IDENTITY_Q, bounds_of, box
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Note,
    Param,
    Params,
    PlotSpec,
    Preset,
    SceneSpec,
    Series,
    at_most,
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


class Planar2Axis(PositionerLesson):
    """Problem 2.3: Lagrange equations (2.5) with T = M (x'^2 + y'^2)/2 (2.6)-(2.7), U by
    layout (2.8)/(2.9), Q by virtual work (2.10) -> corrected (2.11)."""

    id = "planar-2axis"
    title = "Two-coordinate planar positioner"
    problem = "Problem 2.3"
    source = "Textbook §2.1, Problem 2.3, eqs (2.5)-(2.11')"
    summary = (
        "An X-Y stage, horizontal (U = 0) or vertical (U = M g y): M x'' = -dU/dx + Q_x, M y'' = "
        "-dU/dy + Q_y."
    )
    order = 2.03
    coords = (Coord("x", "x", "m", 0.0, "0.2*sin(t)"), Coord("y", "y", "m", 0.0, "0.1*sin(2*t)"))
    inputs = (
        Input("Q_x", "force along X, Q_x", "N", "2*cos(t)"),
        Input("Q_y", "force along Y, Q_y", "N", "sin(2*t)"),
    )
    physical = ("M", "g")
    groups = positioner_groups("Stage")
    modes = ("problem", "layout")
    params = positioner_params(
        coords,
        inputs,
        (
            Param(
                "M",
                "float",
                4.0,
                label="total moving mass M",
                unit="kg",
                min=1e-3,
                max=1e4,
                group="body",
            ),
            Param("g", "float", 9.81, label="g", unit="m/s^2", min=0.0, max=100.0, group="body"),
        ),
        modes=(
            Param(
                "layout",
                "choice",
                "horizontal",
                label="layout",
                choices=("horizontal", "vertical"),
                group="mode",
                help="vertical: the Y axis points up and U = M g y (2.9)",
            ),
        ),
    )
    series = positioner_series(
        coords,
        inputs,
        (
            Series("v", "m/s", "speed v = sqrt(x'^2 + y'^2)"),
            Series("a", "m/s^2", "acceleration a = sqrt(x''^2 + y''^2)"),
        ),
    )
    readout = ("x", "y", "v", "a", "Q_x", "Q_y")
    presets = (
        Preset(
            "forward-horizontal",
            "Forward, horizontal: Q_x = 2 cos t, Q_y = sin 2t",
            {"problem": "forward", "layout": "horizontal"},
            t_end=10.0,
        ),
        Preset(
            "forward-vertical-hold",
            "Forward, vertical: Q_y = M g holds the weight",
            {"problem": "forward", "layout": "vertical", "Q_x": "2*cos(t)", "Q_y": "4*9.81"},
            t_end=10.0,
        ),
        Preset(
            "inverse-vertical-figure-eight",
            "Inverse, vertical: x = 0.2 sin t, y = 0.1 sin 2t",
            {"problem": "inverse", "layout": "vertical"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Coordinates", ("x", "y"), "m"),
        PlotSpec("Speed", ("x_dot", "y_dot", "v"), "m/s"),
        PlotSpec("Forces", ("Q_x", "Q_y"), "N"),
    )

    def model_key(self, params: Params) -> str:
        return str(params["layout"])

    def build_model(self, key: str) -> LagrangeModel:
        x, y = dynamicsymbols("x y")
        M, g = sym("M", positive=True), sym("g", nonnegative=True)
        Qx, Qy = sym("Q_x"), sym("Q_y")
        N = ReferenceFrame("N")
        P = Point("P")
        P.set_vel(N, x.diff(T_) * N.x + y.diff(T_) * N.y)
        T = M * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2
        U = M * g * y if key == "vertical" else sp.S.Zero
        return LagrangeModel.build(
            [x, y], T, U, T_, [M, g], [Qx, Qy], forcelist=[(P, Qx * N.x + Qy * N.y)], frame=N
        )

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        return {"v": np.hypot(qd[0], qd[1]), "a": np.hypot(qdd[0], qdd[1])}

    def notes(self, params: Params) -> list[Note]:
        return [
            Note(
                "corrected",
                "Equations (2.11) are used in their corrected form: the printed y-row has"
                " dU/dx and dA/dx, and the repeated form (2.11') a minus before dA.",
                "(2.11)",
                "the y-row must use dU/dy and Q_y = dA/dy as in (2.5) and (2.10)",
            )
        ]

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        x, y = m.q
        M, g = m.params
        T, U = sp.Symbol("T"), sp.Symbol("U")
        vert = params["layout"] == "vertical"
        steps = [
            DerivationStep(
                "Speed and acceleration",
                "",
                [
                    sp.Eq(sp.Symbol("v"), sp.sqrt(x.diff(T_) ** 2 + y.diff(T_) ** 2)),
                    sp.Eq(sp.Symbol("a"), sp.sqrt(x.diff(T_, 2) ** 2 + y.diff(T_, 2) ** 2)),
                ],
            ),
            DerivationStep(
                "Lagrange equations of the 2nd kind",
                "q1 = x, q2 = y.",
                (
                    r"\frac{d}{dt}\frac{\partial T}{\partial \dot q}-\frac{\partial T}{\partial "
                    r"q}=-\frac{\partial U}{\partial q}+Q_q,\quad q\in\{x,y\}"
                ),
                "(2.5)",
            ),
            DerivationStep(
                "Kinetic energy",
                "All points of the stage share the velocity (x', y').",
                sp.Eq(T, M * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2),
                "(2.6)-(2.7)",
            ),
            DerivationStep(
                "Potential energy",
                "Vertical layout: Y up, U = M g y (2.9)."
                if vert
                else "Horizontal layout: dU/dx = dU/dy = 0 (2.8).",
                sp.Eq(U, M * g * y if vert else 0),
                "(2.9)" if vert else "(2.8)",
            ),
            DerivationStep(
                "Generalized forces",
                "Coefficients of the virtual displacements in the virtual work.",
                r"Q_x=\frac{\delta A}{\delta x},\qquad Q_y=\frac{\delta A}{\delta y}",
                "(2.10)",
            ),
            DerivationStep(
                "Equations of motion (Lagrange equations of the 2nd kind)",
                (
                    "The printed y-row has dU/dx, dA/dx (typo) and (2.11') a minus before dA: "
                    "the corrected form is shown."
                ),
                m.equations(),
                "(2.11)",
                reconstructed="corrected: y-row uses dU/dy and Q_y = dA/dy; sign + before dA as in (2.11)",
            ),
        ]
        if params["problem"] == "inverse":
            Qx, Qy = m.inputs
            lx = params["x_t"].expr.subs(t_symbol, T_)
            ly = params["y_t"].expr.subs(t_symbol, T_)
            steps.append(
                DerivationStep(
                    "Inverse problem",
                    "",
                    [
                        sp.Eq(Qx, sp.simplify(M * sp.diff(lx, T_, 2))),
                        sp.Eq(Qy, sp.simplify(M * sp.diff(ly, T_, 2) + (M * g if vert else 0))),
                    ],
                    "(2.11)",
                )
            )
        return steps

    def _world(self, params: Params, x: Array | float, y: Array | float) -> Array:
        if params["layout"] == "vertical":
            return np.array([x, 0.0 * np.asarray(x), y], dtype=float).T
        return np.array([x, y, 0.0 * np.asarray(x)], dtype=float).T

    def scene_size(self, params: Params) -> float:
        return self._extent(params)[2]

    def _extent(self, params: Params) -> tuple[Array, Array, float]:
        """Lowest and highest corner of the default run and its span (once per values)."""
        return self.cached("extent", params, lambda: self._measure_extent(params))

    def _measure_extent(self, params: Params) -> tuple[Array, Array, float]:
        r = self.coarse_run(params)
        pts = self._world(params, r.series["x"], r.series["y"])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 0:
            pts = np.zeros((1, 3))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        return lo, hi, max(float(np.max(hi - lo)), 0.5)

    def scene(self, params: Params) -> SceneSpec:
        lo, hi, span = self._extent(params)
        s = 0.1 * span
        vert = params["layout"] == "vertical"
        c = (lo + hi) / 2
        L = hi - lo + 3 * s
        if vert:
            base = box(
                "base plate",
                (L[0], 0.2 * s, L[2]),
                (150, 150, 150),
                center=(c[0], -0.4 * s, c[2]),
                opacity=0.5,
            )
            slide = box("X slide", (0.6 * s, 0.3 * s, L[2]), (90, 120, 170))
            carriage = box("Y carriage", (s, 0.5 * s, s), (70, 160, 210))
        else:
            base = box(
                "base plate",
                (L[0], L[1], 0.2 * s),
                (150, 150, 150),
                center=(c[0], c[1], -0.4 * s),
                opacity=0.5,
            )
            slide = box("X slide", (0.6 * s, L[1], 0.3 * s), (90, 120, 170))
            carriage = box("Y carriage", (s, s, 0.5 * s), (70, 160, 210))
        pts = np.array([lo - 2 * s, hi + 2 * s])
        return SceneSpec(
            bounds=bounds_of(pts, 0.02),
            meshes=[base],
            bodies=[slide, carriage],
            moving_points={"carriage": (70, 160, 210)},
            moving_vectors={"Q": (40, 160, 60), "weight": (200, 60, 60)},
            planar=False,
        )

    def pose(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        p = self._world(params, float(q[0]), float(q[1]))
        lo, hi, _ = self._extent(params)
        c = (lo + hi) / 2
        vert = params["layout"] == "vertical"
        slide_pos = np.array([p[0], 0.0, c[2]]) if vert else np.array([p[0], c[1], 0.0])
        fr.poses["X slide"] = (slide_pos, IDENTITY_Q.copy())
        fr.poses["Y carriage"] = (p.copy(), IDENTITY_Q.copy())
        fr.points["carriage"] = p[None, :]
        F = self._world(params, scale * float(u[0]), scale * float(u[1]))
        fr.vectors["Q"] = arrow(p, F)
        w = float(params["M"]) * float(params["g"]) * scale if vert else 0.0
        fr.vectors["weight"] = arrow(p, [0, 0, -w])

    def claims(self) -> list[Claim]:
        def eq_ok(layout: str) -> Callable[[], bool]:
            def ok() -> bool:
                m = self.model(self.resolve({"layout": layout}))
                x, y = m.q
                M, g = m.params
                Qx, Qy = m.inputs
                dUdy = M * g if layout == "vertical" else 0
                return is_zero(m.eom()[0] - (M * x.diff(T_, 2) - Qx)) and is_zero(
                    m.eom()[1] - (M * y.diff(T_, 2) + dUdy - Qy)
                )

            return ok

        def hold() -> ClaimResult:
            r = self.run("forward-vertical-hold")
            return at_most(
                1e-9,
                float(np.max(np.abs(r.series["y"]))),
                "vertical stage with Q_y = M g: max |y| (m) ",
            )

        def inverse_weight() -> ClaimResult:
            r = self.run("inverse-vertical-figure-eight")
            t = r.t
            expected = 4.0 * (-0.4 * np.sin(2 * t)) + 4.0 * 9.81
            return at_most(
                1e-9,
                float(np.max(np.abs(r.series["Q_y"] - expected))),
                "max |Q_y - (M y'' + M g)| (N) ",
            )

        return [
            Claim(
                "eq-2.11-horizontal",
                "Horizontal layout (2.8): LagrangesMethod gives M x'' = Q_x, M y'' = Q_y",
                "(2.11)",
                symbolic_claim(eq_ok("horizontal"), "(2.11), U = 0"),
            ),
            Claim(
                "eq-2.11-vertical",
                (
                    "Vertical layout (2.9), U = M g y: M x'' = Q_x, M y'' = -M g + Q_y "
                    "(corrected (2.11))"
                ),
                "(2.11)",
                symbolic_claim(eq_ok("vertical"), "(2.11), U = M g y"),
            ),
            Claim(
                "vertical-hold",
                "Vertical stage: Q_y = M g keeps y = 0 (dU/dy balanced)",
                "(2.9), (2.11)",
                hold,
            ),
            Claim(
                "inverse-weight",
                "Inverse, vertical: Q_y(t) = M y'' + M g for y = 0.1 sin 2t",
                "(2.11)",
                inverse_weight,
            ),
            Claim(
                "round-trip-forward-inverse",
                (
                    "Forward then inverse recovers Q_x = 2 cos t, Q_y = 40 + sin 2t (within 1e-4 "
                    "of the peak)"
                ),
                "(2.11)",
                self.forward_inverse_check(
                    {"layout": "vertical", "Q_x": "2*cos(t)", "Q_y": "40 + sin(2*t)"},
                    "max |Q recovered - Q| ",
                ),
            ),
            Claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces x = 0.2 sin t, y = 0.1 sin 2t to 1e-8 m",
                "(2.11)",
                self.inverse_forward_check({"layout": "vertical"}, "max |q forward - q law| (m) "),
            ),
        ]


LESSON = Planar2Axis()
