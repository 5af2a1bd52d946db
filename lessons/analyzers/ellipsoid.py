"""Problem 1.6: motion along a curve on an ellipsoid (textbook §1.3, eqs (1.60)-(1.63)).

The ellipsoid (1.60) x²/a² + y²/b² + z²/c² = 1 in the normalized coefficients
a11 = 1/a², a22 = 1/b², a33 = 1/c², a44 = -1 turns the general analyzer (1.50) into

    dx/dt = u1 y/b² - u2 z/c²,  dy/dt = -u1 x/a² + u3 z/c²,  dz/dt = u2 x/a² - u3 y/b²   (1.63)

(φ = t).  The analyzer keeps G = x²/a² + y²/b² + z²/c², so a, b, c set only the ratios of
the semi-axes: the start point picks the level set, and the actual semi-axes are
√G0 (a, b, c) (the textbook: start (0, 50, 0) with a, b, c = 10, 5, 1 gives 100, 50, 10).
(1.62) is (1.63) times a²b²c²: the same paths for constant controls, a different
motion for u(t), so the lesson integrates (1.63) as Fig. 1.30 does.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import x, y, z
from analyzer_lab.lessons.analyzers.field.lesson import AnalyzerLesson, Prepared
from analyzer_lab.lessons.analyzers.field.run import integrate
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Group,
    Param,
    Params,
    Preset,
    RunResult,
    at_most,
)

#: r(10) of the worked example (Fig. 1.31), computed at tight tolerance (RK45, rtol 1e-10).
R_END = (7.070763, -2.34397, -0.52941)
#: max |x|, |y|, |z| over the 10 s of Fig. 1.31 (tight tolerance).
EXTENTS = (7.706131, 5.0, 0.997768)
#: G drift of scipy RK45 at default tolerances on the worked example.
RK45_G_DRIFT = 9.001e-4


#: the worked example of Fig. 1.31: the surface, the controls and the start point
WORKED_EXAMPLE = {
    "a": 10,
    "b": 5,
    "c": 1,
    "u1": "5*t",
    "u2": "t/10",
    "u3": "5",
    "x0": 0,
    "y0": -5,
    "z0": 0,
}


class EllipsoidLesson(AnalyzerLesson):
    id = "ellipsoid"
    title = "Curve on an ellipsoid"
    chapter = "1"
    problem = "Problem 1.6"
    source = "Textbook §1.3, Problem 1.6, eqs (1.60)-(1.63); Figs. 1.30-1.31"
    summary = (
        "The ellipsoid analyzer (1.63): a, b, c fix the ratios of the semi-axes, the"
        " start point their size."
    )
    order = 1.6
    t_end = 10.0
    sampling = 1.0  # the worked example runs 10 s (Fig. 1.31)
    surface_groups = (Group("surface", "Ellipsoid: semi-axis ratios a, b, c"),)
    surface_params = (
        Param(
            "a",
            "float",
            10.0,
            "a (x semi-axis ratio)",
            min=1e-3,
            max=1e3,
            step=0.5,
            group="surface",
        ),
        Param(
            "b", "float", 5.0, "b (y semi-axis ratio)", min=1e-3, max=1e3, step=0.5, group="surface"
        ),
        Param(
            "c", "float", 1.0, "c (z semi-axis ratio)", min=1e-3, max=1e3, step=0.5, group="surface"
        ),
    )
    presets = (
        Preset(
            "example",
            "Worked example: u1 = 5t, u2 = t/10, u3 = 5; a, b, c = 10, 5, 1; start (0, -5, 0)",
            WORKED_EXAMPLE,
            10.0,
            "Fig. 1.31; G0 = 1, so the semi-axes are 10, 5, 1",
        ),
        Preset(
            "semi-axes-100-50-10",
            "Same analyzer started at (0, 50, 0): semi-axes 100, 50, 10",
            {**WORKED_EXAMPLE, "y0": 50},
            10.0,
            "a, b, c set only the ratios; G0 = 100 scales the ellipsoid by √G0 = 10",
        ),
        Preset(
            "constant-controls",
            "Constant controls u = (1, 1, 1): a plane curve on the ellipsoid",
            {"a": 10, "b": 5, "c": 1, "u1": "1", "u2": "1", "u3": "1", "x0": 0, "y0": -5, "z0": 0},
            10.0,
            "the plane-curve statement of Problem 1.3: u3 x + u2 y + u1 z stays constant",
        ),
    )

    block_figure = "Fig. 1.30"

    def surface(self, params: Params) -> Quadric:
        """(1.60) in the normalized coefficients of (1.63): 1/a², 1/b², 1/c², a44 = -1."""
        return Quadric.ellipsoid(float(params["a"]), float(params["b"]), float(params["c"]))

    def keep_level(self, params: Params) -> bool:
        return True

    def semi_axes(self, params: Params) -> np.ndarray:
        """The actual semi-axes √G0 (a, b, c) of the level set through the start point."""
        p = np.array([params["x0"], params["y0"], params["z0"]], dtype=float)
        abc = np.array([params["a"], params["b"], params["c"]], dtype=float)
        G0 = float(np.sum(p**2 / abc**2))
        return np.sqrt(G0) * abc

    def extra_derivation(self, params: Params, prepared: Prepared) -> list[DerivationStep]:
        a, b, c = sp.symbols("a b c", positive=True)
        u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
        sa = self.semi_axes(params)
        G0 = sp.Symbol("G0")
        return [
            DerivationStep(
                "The ellipsoid",
                "a, b, c are the semi-axes of F = 0.",
                sp.Eq(x**2 / a**2 + y**2 / b**2 + z**2 / c**2, 1),
                "(1.60)",
            ),
            DerivationStep(
                "Its coefficients",
                "Normalized so that (1.50) gives (1.63) directly (the other choice, a11 ="
                " b²c², ..., gives (1.62)).",
                [
                    sp.Eq(sp.Symbol("a11"), 1 / a**2),
                    sp.Eq(sp.Symbol("a22"), 1 / b**2),
                    sp.Eq(sp.Symbol("a33"), 1 / c**2),
                    sp.Eq(sp.Symbol("a44"), -1),
                ],
                "(1.61)",
                reconstructed="lost in the source; the normalized reading is what (1.63) integrates"
                " (the other reading gives (1.62))",
            ),
            DerivationStep(
                "The analyzer multiplied out",
                "(1.50) with a11 = b²c², a22 = a²c², a33 = a²b².",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), a**2 * c**2 * u1 * y - a**2 * b**2 * u2 * z),
                    sp.Eq(sp.Symbol("dy/dφ"), -(b**2) * c**2 * u1 * x + a**2 * b**2 * u3 * z),
                    sp.Eq(sp.Symbol("dz/dφ"), b**2 * c**2 * u2 * x - a**2 * c**2 * u3 * y),
                ],
                "(1.62)",
            ),
            DerivationStep(
                "The normalized analyzer (integrated here)",
                "(1.62) divided by a²b²c²; φ = t. With u(t) it is not interchangeable with (1.62).",
                [
                    sp.Eq(sp.Symbol("dx/dt"), u1 * y / b**2 - u2 * z / c**2),
                    sp.Eq(sp.Symbol("dy/dt"), -u1 * x / a**2 + u3 * z / c**2),
                    sp.Eq(sp.Symbol("dz/dt"), u2 * x / a**2 - u3 * y / b**2),
                ],
                "(1.63)",
            ),
            DerivationStep(
                "The start point sets the size",
                "G = x²/a² + y²/b² + z²/c² is a first integral; the actual semi-axes are"
                " √G0 (a, b, c). "
                f"Here G0 = {float(sa[0] / float(params['a'])) ** 2:.6g}: "
                f"semi-axes {sa[0]:.6g}, {sa[1]:.6g}, {sa[2]:.6g}.",
                [
                    sp.Eq(
                        G0,
                        sp.Symbol("x0") ** 2 / a**2
                        + sp.Symbol("y0") ** 2 / b**2
                        + sp.Symbol("z0") ** 2 / c**2,
                    ),
                    sp.Eq(
                        sp.Symbol("semi-axes"), sp.sqrt(G0) * sp.Matrix([a, b, c]), evaluate=False
                    ),
                ],
                "Problem 1.6 text",
            ),
        ]

    def extra_metrics(
        self, params: Params, prepared: Prepared, result: RunResult
    ) -> dict[str, float]:
        r = np.stack([result.series[c] for c in "xyz"], axis=1)
        sa = self.semi_axes(params)
        speed = result.series["speed"]
        return {
            "semi_axis_x": float(sa[0]),
            "semi_axis_y": float(sa[1]),
            "semi_axis_z": float(sa[2]),
            "max_abs_x": float(np.abs(r[:, 0]).max()),
            "max_abs_y": float(np.abs(r[:, 1]).max()),
            "max_abs_z": float(np.abs(r[:, 2]).max()),
            "x_end": float(r[-1, 0]),
            "y_end": float(r[-1, 1]),
            "z_end": float(r[-1, 2]),
            "speed_min": float(speed.min()),
            "speed_max": float(speed.max()),
            "G0": float(-prepared.quadric.a44),
        }

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "end-point",
                "Worked example: r(10) = (7.0708, -2.3440, -0.5294)",
                "Problem 1.6 worked example, Fig. 1.31",
                self._claim_end,
            ),
            Claim(
                "extents",
                "Worked example: max |x|, |y|, |z| over 10 s = 7.706, 5, 0.998 (inside 10, 5, 1)",
                "Problem 1.6 worked example, Fig. 1.31",
                self._claim_extents,
            ),
            Claim(
                "semi-axes",
                "Start (0, 50, 0) with a, b, c = 10, 5, 1 gives the semi-axes 100, 50, 10",
                "Problem 1.6 text",
                self._claim_semi_axes,
            ),
            Claim(
                "speed-range",
                "Worked example: |v| runs from 1.0 at t = 0 up to 8.72",
                "Problem 1.6 worked example, Fig. 1.31",
                self._claim_speed,
            ),
            Claim(
                "G-drift",
                "G stays constant to round-off (≤ 1e-12), while scipy RK45 at default"
                " tolerances drifts it by about 9.0e-4",
                "(1.60), (1.63); Problem 1.6 worked example",
                self._claim_drift,
            ),
        ]

    def _claim_example(self, keys: tuple[str, ...], want: tuple[float, ...], tol: float):
        m = self.run("example").metrics
        got = np.array([m[k] for k in keys])
        return at_most(tol, float(np.max(np.abs(got - np.array(want)))), f"max |{keys} - {want}| ")

    def _claim_end(self) -> ClaimResult:
        return self._claim_example(("x_end", "y_end", "z_end"), R_END, 5e-5)

    def _claim_extents(self) -> ClaimResult:
        return self._claim_example(("max_abs_x", "max_abs_y", "max_abs_z"), EXTENTS, 2e-3)

    def _claim_semi_axes(self) -> ClaimResult:
        res = self.run("semi-axes-100-50-10", t_end=2.0)
        m = res.metrics
        got = np.array([m["semi_axis_x"], m["semi_axis_y"], m["semi_axis_z"]])
        r = np.stack([res.series[k] for k in "xyz"], axis=1)
        G = (r[:, 0] / 100.0) ** 2 + (r[:, 1] / 50.0) ** 2 + (r[:, 2] / 10.0) ** 2
        err = max(
            float(np.max(np.abs(got - np.array([100.0, 50.0, 10.0])))),
            float(np.max(np.abs(G - 1.0))) * 100,
        )
        return at_most(1e-9, err, "max |semi-axes - (100, 50, 10)| and path on that ellipsoid ")

    def _claim_speed(self) -> ClaimResult:
        m = self.run("example").metrics
        ok = abs(m["speed_min"] - 1.0) <= 1e-9 and abs(m["speed_max"] - 8.7182) <= 1e-3
        return ClaimResult(
            "|v| from 1.0 to 8.7182 (±1e-3)", f"{m['speed_min']:.6f} .. {m['speed_max']:.6f}", ok
        )

    def _claim_drift(self) -> ClaimResult:
        params = self.resolve(preset="example")
        prepared = self.prepare(params)
        ours = integrate(prepared.model, prepared.r0, 10.0, h=1e-3)
        rk = integrate(prepared.model, prepared.r0, 10.0, method="RK45", samples=2001)
        d_ours, d_rk = float(ours.drift.max()), float(rk.drift.max())
        ok = d_ours <= 1e-12 and 0.5 * RK45_G_DRIFT <= d_rk <= 2 * RK45_G_DRIFT
        return ClaimResult(
            f"ours <= 1e-12; RK45 default within a factor 2 of {RK45_G_DRIFT:.3g}",
            f"ours {d_ours:.3g}; RK45 {d_rk:.3g}",
            ok,
        )


LESSON = EllipsoidLesson()
