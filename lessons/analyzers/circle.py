"""Problem 1.2: motion along a circle in the plane (textbook §1.3, eqs (1.34)-(1.41)).

Undetermined coefficients: with linear right-hand sides (1.35) the tangency condition
(1.36) on F = x² + y² - R² (1.34) becomes the identity (1.38), whose coefficients all
vanish (1.39): b0 = b1 = c0 = c2 = 0, b2 = -c1 = u.  The analyzer is

    dx/dφ = u y,   dy/dφ = -u x                                                  (1.40)

for any u (a number or a function of t: its form sets the speed); u = 1 gives (1.41),
whose circle has the radius √(x0² + y0²) (Fig. 1.13).  Fig. 1.14 sets the radius
explicitly: y0 = ±√(R² - x0²) (the figure shows the minus branch).
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.plane.conic import (
    PlanarModel,
    PlanarState,
    PlanarTrack,
    radius_growth_per_turn,
)
from analyzer_lab.lessons.analyzers.plane.lesson import DIGITAL, PlanarLesson, PlanarPrepared
from analyzer_lab.lessons.kit.contract import (
    INITIAL,
    MODE,
    Claim,
    ClaimResult,
    DerivationStep,
    Group,
    Note,
    Param,
    ParamError,
    Params,
    Preset,
    at_most,
)

RADIUS_MODES = (
    "start point",
    "explicit R, y0 = +sqrt(R^2 - x0^2)",
    "explicit R, y0 = -sqrt(R^2 - x0^2)",
)


def undetermined_coefficients() -> tuple[sp.Expr, dict[sp.Symbol, sp.Expr]]:
    """(1.38) and its solution (1.39), solved by sympy."""
    x, y = sp.symbols("x y", real=True)
    b0, b1, b2, c0, c1, c2 = sp.symbols("b0 b1 b2 c0 c1 c2")
    ident = sp.expand((2 * x * (b0 + b1 * x + b2 * y) + 2 * y * (c0 + c1 * x + c2 * y)) / 2)
    eqs = sp.Poly(ident, x, y).coeffs()
    sol = sp.solve(eqs, [b0, b1, c0, c1, c2], dict=True)[0]
    return ident, sol


class CircleLesson(PlanarLesson):
    id = "circle"
    title = "Motion along a circle"
    chapter = "1"
    problem = "Problem 1.2"
    source = "Textbook §1.3, Problem 1.2, eqs (1.34)-(1.41); Figs. 1.11-1.14"
    summary = (
        "Undetermined coefficients give the harmonic analyzer x' = u y, y' = -u x;"
        " the start point sets the radius."
    )
    order = 1.2
    t_end = 10.0
    groups = (
        MODE,
        Group("controls", "Control u(t) (1.40)", change="live"),
        INITIAL,
        Group("family", "Family (Fig. 1.12)", change="restart"),
        DIGITAL,
    )
    modes = ("radius_mode", "digital")
    family = "family"
    own_params = (
        Param(
            "u",
            "formula",
            "1",
            "u(t)",
            min=-20,
            max=20,
            step=0.1,
            group="controls",
            help="any formula of t: its form sets the speed along the circle",
        ),
        Param(
            "radius_mode",
            "choice",
            RADIUS_MODES[0],
            "radius set by",
            choices=RADIUS_MODES,
            group="mode",
            help="the start point (Fig. 1.13) or an explicit R with y0 = ±sqrt(R² - x0²) (Fig. 1.14)",
        ),
        Param(
            "R", "float", 5.0, "R (explicit radius)", min=1e-6, max=1e4, step=0.5, group="initial"
        ),
        Param("x0", "float", 3.0, "x0", min=-1e4, max=1e4, step=0.5, group="initial"),
        Param("y0", "float", 4.0, "y0", min=-1e4, max=1e4, step=0.5, group="initial"),
        Param(
            "family",
            "int",
            1,
            "circles in the family",
            min=1,
            max=12,
            step=1,
            group="family",
            help="start points x0 + k·step (or radii R + k·step with an explicit R): Fig. 1.12",
        ),
        Param(
            "family_step",
            "float",
            1.0,
            "family spacing",
            min=-1e3,
            max=1e3,
            step=0.5,
            group="family",
        ),
    )
    presets = (
        Preset(
            "fig-1.13",
            "Fig. 1.13: u = 1 from (3, 4): the circle of radius 5",
            {"u": "1", "x0": 3, "y0": 4},
            2 * np.pi,
            "the start point is illustrative (the source gives none)",
        ),
        Preset(
            "fig-1.12",
            "Fig. 1.12: circles for several start points",
            {"u": "1", "x0": 1, "y0": 0, "family": 5, "family_step": 1.0},
            2 * np.pi,
            "start points (1, 0) ... (5, 0) (illustrative: the source gives none)",
        ),
        Preset(
            "fig-1.14",
            "Fig. 1.14: explicit radius R = 5, y0 = -sqrt(R² - x0²)",
            {"u": "1", "radius_mode": RADIUS_MODES[2], "R": 5, "x0": 3},
            2 * np.pi,
            "x0 = 3 gives y0 = -4",
        ),
        Preset(
            "u-t",
            "u = t: the speed grows along the same circle",
            {"u": "t", "x0": 3, "y0": 4},
            5.0,
            "angle travelled t²/2",
        ),
        Preset(
            "u-sin",
            "u = sin t: back and forth on the circle",
            {"u": "sin(t)", "x0": 3, "y0": 4},
            10.0,
            "angle travelled 1 - cos t",
        ),
        Preset(
            "digital-simple",
            "Digital analyzer, simple additions: the circle spirals out by about πΔR per turn",
            {"u": "1", "x0": 5, "y0": 0, "digital": "simple", "delta": 0.01, "pulse": 0.001},
            2 * np.pi,
            "Δ = 0.01, R = 5: about 0.16 per turn",
        ),
        Preset(
            "digital-improved",
            "Digital analyzer, improved additions: a closed curve within ΔR/4",
            {"u": "1", "x0": 5, "y0": 0, "digital": "improved", "delta": 0.01, "pulse": 0.001},
            2 * np.pi,
            "Δ = 0.01, R = 5: within 0.0125",
        ),
        Preset(
            "digital-staircase",
            "Digital analyzer with coarse pulses: the staircase",
            {"u": "1", "x0": 5, "y0": 0, "digital": "improved", "delta": 0.02, "pulse": 0.25},
            2 * np.pi,
            "pulse length 0.25: the steps are visible",
        ),
    )

    block_figure = "Figs. 1.11, 1.13"

    def validate(self, params: Params) -> None:
        super().validate(params)
        if params["radius_mode"] != RADIUS_MODES[0]:
            k = int(params["family"])
            Rmin = min(
                float(params["R"]), float(params["R"]) + (k - 1) * float(params["family_step"])
            )
            if abs(float(params["x0"])) > Rmin:
                raise ParamError(
                    "x0",
                    f"|x0| = {abs(float(params['x0'])):g} exceeds R = {Rmin:g}: sqrt(R² - x0²) is not real",
                )

    def start_points(self, params: Params) -> np.ndarray:
        k = np.arange(int(params["family"]))
        step = float(params["family_step"])
        x0 = float(params["x0"])
        if params["radius_mode"] == RADIUS_MODES[0]:
            return np.stack([x0 + k * step, np.full(len(k), float(params["y0"]))], axis=1)
        R = float(params["R"]) + k * step
        sign = 1.0 if params["radius_mode"] == RADIUS_MODES[1] else -1.0
        return np.stack(
            [np.full(len(k), x0), sign * np.sqrt(np.maximum(R**2 - x0**2, 0.0))], axis=1
        )

    def planar_model(self, params: Params) -> tuple[PlanarModel, np.ndarray]:
        r0 = self.start_points(params)
        return PlanarModel.of([{"a11": 1.0, "a22": 1.0} for _ in r0], params["u"]), r0

    def notes(self, params: Params) -> list[Note]:
        r0 = self.start_points(params)
        if np.any(np.hypot(r0[:, 0], r0[:, 1]) == 0):
            return [
                Note(
                    "info",
                    "a start point is the centre (0, 0): the circle has radius 0"
                    " and the point does not move",
                )
            ]
        return []

    def extra_derivation(self, params: Params, prepared: PlanarPrepared) -> list[DerivationStep]:
        x, y, R, u = sp.symbols("x y R u", real=True)
        b0, b1, b2, c0, c1, c2 = sp.symbols("b0 b1 b2 c0 c1 c2")
        ident, sol = undetermined_coefficients()
        steps = [
            DerivationStep("The circle", "", sp.Eq(sp.Symbol("F"), x**2 + y**2 - R**2), "(1.34)"),
            DerivationStep(
                "Linear right-hand sides",
                "Undetermined coefficients b, c.",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), b0 + b1 * x + b2 * y),
                    sp.Eq(sp.Symbol("dy/dφ"), c0 + c1 * x + c2 * y),
                ],
                "(1.35)",
            ),
            DerivationStep(
                "Tangency",
                "Necessary for staying on the curve, for any parametrization.",
                sp.Eq(
                    sp.Symbol("F_x") * sp.Symbol("dx/dφ") + sp.Symbol("F_y") * sp.Symbol("dy/dφ"), 0
                ),
                "(1.36)",
            ),
            DerivationStep(
                "Partial derivatives",
                "",
                [sp.Eq(sp.Symbol("F_x"), 2 * x), sp.Eq(sp.Symbol("F_y"), 2 * y)],
                "(1.37)",
            ),
            DerivationStep(
                "An identity in x, y", "Substituted and divided by 2.", sp.Eq(ident, 0), "(1.38)"
            ),
            DerivationStep(
                "Every coefficient vanishes",
                "Solved symbolically: b2 stays free; call it u.",
                [sp.Eq(k, v) for k, v in sol.items()],
                "(1.39)",
            ),
            DerivationStep(
                "The circle analyzer",
                "u may be any function: its form sets the speed.",
                [sp.Eq(sp.Symbol("dx/dφ"), u * y), sp.Eq(sp.Symbol("dy/dφ"), -u * x)],
                "(1.40)",
            ),
            DerivationStep(
                "u = 1",
                "Radius √(x0² + y0²): the device works for any start point (Fig. 1.13).",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), y),
                    sp.Eq(sp.Symbol("dy/dφ"), -x),
                    sp.Eq(R, sp.sqrt(sp.Symbol("x0") ** 2 + sp.Symbol("y0") ** 2)),
                ],
                "(1.41)",
            ),
            DerivationStep(
                "With these numbers",
                f"u(t) = {params['u']}, φ = t.",
                prepared.model.equations(),
                "(1.40)",
            ),
        ]
        if params["radius_mode"] != RADIUS_MODES[0]:
            sign = 1 if params["radius_mode"] == RADIUS_MODES[1] else -1
            steps.append(
                DerivationStep(
                    "Explicit radius",
                    "The y0 input of the y integrator is computed from R and x0 (Fig. 1.14 shows the minus branch).",
                    sp.Eq(sp.Symbol("y0"), sign * sp.sqrt(R**2 - sp.Symbol("x0") ** 2)),
                    "Fig. 1.14",
                )
            )
        return steps

    def extra_metrics(
        self, params: Params, track: PlanarTrack, t: np.ndarray, state: PlanarState
    ) -> dict[str, object]:
        r = state.r
        rad = np.linalg.norm(r, axis=-1)
        R0 = np.linalg.norm(track.r0, axis=-1)
        return {
            "radius": float(R0[0]),
            "radius_error_max": float(np.max(np.abs(rad - R0[None, :]))),
            "x_end": float(r[-1, 0, 0]),
            "y_end": float(r[-1, 0, 1]),
        }

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "coefficients",
                "(1.38) forces b0 = b1 = c0 = c2 = 0 and c1 = -b2 (one free coefficient u)",
                "(1.38)-(1.39)",
                self._claim_coefficients,
            ),
            Claim(
                "radius",
                "The circle's radius is √(x0² + y0²) for any start point and any u(t) (to 1e-12 relative)",
                "(1.41), Fig. 1.13",
                self._claim_radius,
            ),
            Claim(
                "explicit-radius",
                "Fig. 1.14: R = 5, x0 = 3 gives y0 = -4 and a circle of radius 5",
                "Fig. 1.14",
                self._claim_explicit,
            ),
            Claim(
                "period",
                "u = 1: the point is back at its start after 2π, running clockwise",
                "(1.41)",
                self._claim_period,
            ),
            Claim(
                "digital-simple",
                "Digital analyzer, simple additions, Δ = 0.01, R = 5: the radius grows by"
                " πΔR ≈ 0.157 per turn (exactly R(e^(πΔ) − 1) = 0.1596)",
                "(1.25); derived, not in source",
                self._claim_dda_simple,
            ),
            Claim(
                "digital-improved",
                "Digital analyzer, improved additions, Δ = 0.01, R = 5: the distance from the"
                " circle stays within ΔR/4 = 0.0125 (no growth over 10 turns)",
                "(1.25); derived, not in source",
                self._claim_dda_improved,
            ),
        ]

    def _claim_coefficients(self) -> ClaimResult:
        _, sol = undetermined_coefficients()
        b0, b1, b2, c0, c1, c2 = sp.symbols("b0 b1 b2 c0 c1 c2")
        ok = sol == {b0: 0, b1: 0, c0: 0, c1: -b2, c2: 0}
        return ClaimResult("{b0: 0, b1: 0, c0: 0, c1: -b2, c2: 0}", str(sol), ok)

    def _claim_radius(self) -> ClaimResult:
        rng = np.random.default_rng(12)
        worst = 0.0
        for u in ("1", "t", "t^2", "sin(t)", "-2 + cos(3*t)"):
            p = rng.uniform(-5, 5, 2)
            res = self.run(None, {"u": u, "x0": p[0], "y0": p[1]}, t_end=5.0)
            worst = max(worst, res.metrics["radius_error_max"] / float(np.hypot(*p)))
        return at_most(1e-12, worst, "max ||r| - √(x0²+y0²)| / R ")

    def _claim_explicit(self) -> ClaimResult:
        res = self.run("fig-1.14")
        ok = (
            abs(res.series["y"][0] + 4.0) < 1e-12
            and abs(res.metrics["radius"] - 5.0) < 1e-12
            and res.metrics["radius_error_max"] < 1e-11
        )
        return ClaimResult(
            "y0 = -4, radius 5",
            f"y0 = {res.series['y'][0]:.12g}, radius {res.metrics['radius']:.12g}",
            ok,
        )

    def _claim_period(self) -> ClaimResult:
        res = self.run("fig-1.13")
        back = float(np.hypot(res.series["x"][-1] - 3.0, res.series["y"][-1] - 4.0))
        clockwise = (
            float(
                res.series["vx"][0] * res.series["y"][0] - res.series["vy"][0] * res.series["x"][0]
            )
            > 0
        )  # -(r x v)_z > 0
        return ClaimResult(
            "|r(2π) - r0| <= 1e-10, clockwise",
            f"{back:.3g}, clockwise = {clockwise}",
            back <= 1e-10 and clockwise,
        )

    def _claim_dda_simple(self) -> ClaimResult:
        res = self.run("digital-simple")
        r_end = float(np.hypot(res.series["x_dda"][-1], res.series["y_dda"][-1]))
        growth = r_end - 5.0
        expected = 5.0 * radius_growth_per_turn(0.01, "simple")
        ok = (
            abs(growth - expected) <= 0.002
            and abs(growth - np.pi * 0.01 * 5.0) <= 0.05 * np.pi * 0.01 * 5.0
        )
        return ClaimResult(
            f"growth ≈ πΔR = {np.pi * 0.05:.4f} (within 5%), R(e^(πΔ)-1) = {expected:.4f} (±0.002)",
            f"{growth:.4f}",
            ok,
        )

    def _claim_dda_improved(self) -> ClaimResult:
        res = self.run("digital-improved", t_end=20 * np.pi)
        rad = np.hypot(res.series["x_dda"], res.series["y_dda"])
        dev = float(np.max(np.abs(rad - 5.0)))
        ok = abs(dev - 0.0125) <= 0.0015
        return ClaimResult("max |r - R| = ΔR/4 = 0.0125 (±0.0015) over 10 turns", f"{dev:.5f}", ok)


LESSON = CircleLesson()
