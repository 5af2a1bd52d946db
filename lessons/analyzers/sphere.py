"""Problem 1.4: motion along a curve on a sphere (textbook §1.3, eqs (1.52)-(1.57)).

The sphere (1.52) x² + y² + z² = R² has the coefficients (1.53); the general analyzer
(1.50) then becomes the rotation (1.54)

    dx/dt = u1 y - u2 z,   dy/dt = -u1 x + u3 z,   dz/dt = u2 x - u3 y,

i.e. r' = w x r with w = -(u3, u2, u1).  Examples 1.1-1.3 drive it with constant,
linearly growing and periodic controls from (1, 0, 0) for 10 s (φ = t); Example 1.4
keeps the point in planes parallel to the coordinate planes (1.55)-(1.57).
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import AnalyzerModel, Controls, x, y, z
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

#: |v|² of Examples 1.2 and 1.3 at t = 0, 1, ..., 10 as plotted in Figs. 1.21 and 1.24
#: (computed at tight tolerance, 3 decimals).
V2_TABLE = {
    "example-1.2": (
        25.000,
        25.171,
        25.757,
        27.414,
        31.567,
        36.752,
        40.519,
        48.224,
        54.364,
        62.338,
        71.802,
    ),
    "example-1.3": (
        0.000,
        0.384,
        3.061,
        4.019,
        0.597,
        5.538,
        1.627,
        8.942,
        34.357,
        69.655,
        119.337,
    ),
}


class SphereLesson(AnalyzerLesson):
    block_figure = "Fig. 1.15"
    id = "sphere"
    title = "Curve on a sphere"
    chapter = "1"
    problem = "Problem 1.4"
    source = "Textbook §1.3, Problem 1.4, eqs (1.52)-(1.57); Examples 1.1-1.4"
    summary = (
        "The analyzer (1.54) turns the point about w = -(u3, u2, u1): constant"
        " controls draw circles, varying ones spirals."
    )
    order = 1.4
    t_end = 10.0
    sampling = 1.0  # Examples 1.1-1.3 run 10 s; their speeds are read at t = 0, 1, ..., 10
    surface_groups = (Group("surface", "Sphere"),)
    surface_params = (
        Param("R", "float", 1.0, "sphere radius R", min=1e-3, max=1e3, step=0.1, group="surface"),
    )
    presets = (
        Preset(
            "example-1.1",
            "Example 1.1: u1 = u2 = u3 = 5 (a circle)",
            {"u1": "5", "u2": "5", "u3": "5", "x0": 1, "y0": 0, "z0": 0},
            10.0,
            "constant equal controls: a circle; |v|² = 50 at all times (Figs. 1.16-1.18)",
        ),
        Preset(
            "example-1.2",
            "Example 1.2: u1 = t, u2 = u3 = 5 (circles travelling along a meridian)",
            {"u1": "t", "u2": "5", "u3": "5", "x0": 1, "y0": 0, "z0": 0},
            10.0,
            "a family of circles whose centre travels along a meridian (Figs. 1.19-1.21)",
        ),
        Preset(
            "example-1.3",
            "Example 1.3: u1 = sin 10t, u2 = t, u3 = 5",
            {"u1": "sin(10*t)", "u2": "t", "u3": "5", "x0": 1, "y0": 0, "z0": 0},
            10.0,
            "a non-cyclic trajectory; |v|² is not constant (Figs. 1.22-1.24)",
        ),
        Preset(
            "example-1.4-xy",
            "Example 1.4: circles in planes parallel to xy (u1 = 1)",
            {
                "u1": "1",
                "u2": "0",
                "u3": "0",
                "x0": 0.6,
                "y0": 0,
                "z0": 0.0,
                "family": 5,
                "family_axis": "z",
                "family_step": 0.35,
            },
            10.0,
            "z stays constant: (1.55); several heights as in Fig. 1.26 (start points are"
            " not given in the source)",
        ),
        Preset(
            "example-1.4-xz",
            "Example 1.4: circles in planes parallel to xz (u2 = 1)",
            {"u1": "0", "u2": "1", "u3": "0", "x0": 0.8, "y0": 0.6, "z0": 0},
            10.0,
            "y stays constant: (1.56)",
        ),
        Preset(
            "example-1.4-yz",
            "Example 1.4: circles in planes parallel to yz (u3 = 1)",
            {"u1": "0", "u2": "0", "u3": "1", "x0": 0.6, "y0": 0.8, "z0": 0},
            10.0,
            "x stays constant: (1.57)",
        ),
    )

    def surface(self, params: Params) -> Quadric:
        """(1.52) with the coefficients (1.53)."""
        return Quadric.sphere(float(params["R"]))

    def extra_derivation(self, params: Params, prepared: Prepared) -> list[DerivationStep]:
        R = sp.Symbol("R", positive=True)
        u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
        return [
            DerivationStep("The sphere", "", sp.Eq(x**2 + y**2 + z**2, R**2), "(1.52)"),
            DerivationStep(
                "Its coefficients",
                "a11 = a22 = a33 = 1, the mixed and linear ones zero, a44 = -R².",
                [
                    sp.Eq(sp.Symbol("a11"), 1),
                    sp.Eq(sp.Symbol("a22"), 1),
                    sp.Eq(sp.Symbol("a33"), 1),
                    sp.Eq(sp.Symbol("a44"), -(R**2)),
                ],
                "(1.53)",
                reconstructed="lost in the source; read off (1.52)",
            ),
            DerivationStep(
                "The sphere analyzer",
                "(1.50) with (1.53): a rotation r' = w × r, w = -(u3, u2, u1); the radius"
                " is set by the start point.",
                [
                    sp.Eq(sp.Symbol("dx/dt"), u1 * y - u2 * z),
                    sp.Eq(sp.Symbol("dy/dt"), -u1 * x + u3 * z),
                    sp.Eq(sp.Symbol("dz/dt"), u2 * x - u3 * y),
                ],
                "(1.54)",
                reconstructed="lost in the source; equals the surviving (1.63) with a = b = c = 1",
            ),
            DerivationStep(
                "Constant controls: plane curves",
                "For constant u the combination u3 x + u2 y + u1 z is a first integral, so"
                " the path is a circle in that plane.",
                sp.Eq(sp.Symbol("d/dt") * (u3 * x + u2 * y + u1 * z), 0),
                "Problem 1.3 text",
            ),
            DerivationStep(
                "Constant controls: constant speed",
                "|v|² = |u|²R² - (u3 x0 + u2 y0 + u1 z0)²; Example 1.1 gives 75 - 25 = 50.",
                sp.Eq(
                    sp.Symbol("|v|²"),
                    (u1**2 + u2**2 + u3**2) * R**2
                    - (u3 * sp.Symbol("x0") + u2 * sp.Symbol("y0") + u1 * sp.Symbol("z0")) ** 2,
                ),
                "Example 1.1",
                reconstructed="derived (not printed in the source); checks the statement"
                " that the speed stays constant",
            ),
            *(
                DerivationStep(
                    f"Planes parallel to {plane} ({u} = 1)",
                    text,
                    [
                        sp.Eq(sp.Symbol(f"d{a}/dt"), fa),
                        sp.Eq(sp.Symbol(f"d{b}/dt"), fb),
                        sp.Eq(sp.Symbol(kept), sp.Symbol(f"{kept}0")),
                    ],
                    eq,
                    reconstructed=why,
                )
                for plane, u, (a, fa), (b, fb), kept, eq, text, why in (
                    (
                        "xy",
                        "u1",
                        ("x", y),
                        ("y", -x),
                        "z",
                        "(1.55)",
                        "z = z0 stays; the general form (1.55) on the sphere gives x' = y, y' = -x.",
                        "rebuilt from surviving fragments (indices a11, a12, a31, z0, a14)",
                    ),
                    (
                        "xz",
                        "u2",
                        ("x", -z),
                        ("z", x),
                        "y",
                        "(1.56)",
                        "y = y0 stays.",
                        "lost in the source; (1.50) with u1 = u3 = 0, u2 = 1",
                    ),
                    (
                        "yz",
                        "u3",
                        ("y", z),
                        ("z", -y),
                        "x",
                        "(1.57)",
                        "x = x0 stays.",
                        "rebuilt from fragments; the printed sign of a24 is corrected"
                        " (it only matters when a24 ≠ 0)",
                    ),
                )
            ),
        ]

    def extra_metrics(
        self, params: Params, prepared: Prepared, result: RunResult
    ) -> dict[str, float]:
        radius = np.sqrt(sum(result.series[c] ** 2 for c in "xyz"))
        return {"radius_min": float(radius.min()), "radius_max": float(radius.max())}

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "ex1.1-speed",
                "Example 1.1: |v|² = 50 at every sample (to 1e-9)",
                "Example 1.1, Fig. 1.18",
                self._claim_ex11_speed,
            ),
            Claim(
                "ex1.1-circle",
                "Example 1.1: the path is the circle in the plane x + y + z = 1, centre"
                " (1/3, 1/3, 1/3), radius √(2/3)",
                "Example 1.1, Fig. 1.16",
                self._claim_ex11_circle,
            ),
            Claim(
                "const-speed",
                "Constant controls keep |v|² constant (random constants and start points)",
                "Example 1.1 text",
                self._claim_const_speed,
            ),
            Claim(
                "const-plane",
                "Constant controls give plane curves: u3 x + u2 y + u1 z stays constant",
                "Problem 1.3 text",
                self._claim_const_plane,
            ),
            Claim(
                "ex1.4-planes",
                "Example 1.4: u1 = 1 keeps z, u2 = 1 keeps y, u3 = 1 keeps x",
                "Example 1.4, (1.55)-(1.57)",
                self._claim_ex14,
            ),
            Claim(
                "ex1.2-speed-table",
                "Example 1.2: |v|² at t = 0..10 matches the tabulated 25.000 ... 71.802 (to 1e-3)",
                "Example 1.2, Fig. 1.21",
                lambda: self._claim_table("example-1.2"),
            ),
            Claim(
                "ex1.3-speed-table",
                "Example 1.3: |v|² at t = 0..10 matches the tabulated 0.000 ... 119.337 (to 1e-3)",
                "Example 1.3, Fig. 1.24",
                lambda: self._claim_table("example-1.3"),
            ),
            Claim(
                "invariant",
                "Ex. 1.3 over 10 s (10^4 steps): |F - F0| ≤ 1e-12 (the point stays on the sphere)",
                "(1.52)",
                self._claim_invariant,
            ),
        ]

    def _claim_ex11_speed(self) -> ClaimResult:
        res = self.run("example-1.1")
        err = float(np.max(np.abs(res.series["v2"] - 50.0)))
        return at_most(1e-9, err, "max |v² - 50| ")

    def _claim_ex11_circle(self) -> ClaimResult:
        res = self.run("example-1.1")
        r = np.stack([res.series[c] for c in "xyz"], axis=1)
        plane = np.abs(r.sum(axis=1) - 1.0).max()
        radius = np.abs(np.linalg.norm(r - 1.0 / 3.0, axis=1) - np.sqrt(2.0 / 3.0)).max()
        return at_most(1e-10, float(max(plane, radius)), "max deviation from the circle ")

    @staticmethod
    def _random_constant_runs(seed: int, count: int = 5):
        """Runs with random constant controls from random points of the unit sphere."""
        rng = np.random.default_rng(seed)
        for _ in range(count):
            u = rng.uniform(-5, 5, 3)
            p = rng.normal(size=3)
            p /= np.linalg.norm(p)
            model = AnalyzerModel.of(Quadric.sphere(1.0).coeffs(), Controls(*u))
            yield u, p, integrate(model, p, 5.0, h=1e-3, samples=501)

    def _claim_const_speed(self) -> ClaimResult:
        worst = 0.0
        for u, p, run in self._random_constant_runs(14):
            v2 = (run.v**2).sum(-1)
            expected = (u**2).sum() - (u[2] * p[0] + u[1] * p[1] + u[0] * p[2]) ** 2
            worst = max(worst, float(np.abs(v2 - expected).max()))
        return at_most(1e-9, worst, "max |v² - (|u|²R² - (u3x0+u2y0+u1z0)²)| ")

    def _claim_const_plane(self) -> ClaimResult:
        worst = 0.0
        for u, _, run in self._random_constant_runs(15):
            inv = run.r[:, 0, :] @ np.array([u[2], u[1], u[0]])
            worst = max(worst, float(np.ptp(inv)))
        return at_most(1e-10, worst, "spread of u3 x + u2 y + u1 z ")

    def _claim_ex14(self) -> ClaimResult:
        spreads = []
        for name, axis in (("example-1.4-xy", 2), ("example-1.4-xz", 1), ("example-1.4-yz", 0)):
            res = self.run(name)
            keys = [k for k in res.series if k[0] == "xyz"[axis] and (len(k) == 1 or k[1] == "_")]
            spreads.append(max(float(np.ptp(res.series[k])) for k in keys))
        return at_most(1e-12, max(spreads), "max spread of the kept coordinate ")

    def _claim_table(self, preset: str) -> ClaimResult:
        res = self.run(preset)
        t = res.t
        idx = [int(np.argmin(np.abs(t - k))) for k in range(11)]
        got = res.series["v2"][idx]
        err = float(np.max(np.abs(got - np.array(V2_TABLE[preset]))))
        return at_most(1e-3 / 2 + 1e-9, err, "max |v²(k) - table| ")

    def _claim_invariant(self) -> ClaimResult:
        res = self.run("example-1.3", t_end=10.0)
        return at_most(1e-12, float(res.metrics["invariant_drift_max"]), "max |F - F0| ")


LESSON = SphereLesson()
