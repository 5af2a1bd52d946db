"""Problem 1.5: motion on a sphere at constant speed (textbook §1.3, eqs (1.58)-(1.59)).

The sphere analyzer (1.54) runs with a controlled argument, dφ = ω(t) dt, and

    ω = ± V / sqrt((u1 y - u2 z)² + (-u1 x + u3 z)² + (u2 x - u3 y)²)          (1.58)
    dx/dt = ω (u1 y - u2 z),  dy/dt = ω (-u1 x + u3 z),  dz/dt = ω (u2 x - u3 y)  (1.59)

so |v| = V whatever the controls u1, u2, u3; V may be a number or a speed profile V(t)
("in the last equation of (1.59) V may be constant or variable"), the sign of ω picks
the direction.  Where the field of (1.54) vanishes (r parallel to (u3, u2, u1)) the
formula divides by zero: the point holds only while the field stays zero there.  With the
controls of Example 1.3 from (1, 0, 0) that is the instant t = 0 alone: the velocity there
is shown as 0 and the point moves at speed V from t > 0.
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
from analyzer_lab.lessons.kit.formula import parse_formula

#: Drift of x² + y² + z² of scipy's RK45 at default tolerances on u = (5, 5, 5), V = 1,
#: 10 s from (1, 0, 0) (Fig. 1.28's setting); the Gauss-Legendre steps keep it to round-off.
RK45_DRIFT = 2.897e-2


def _preset(name: str, title: str, note: str, **changes: str) -> Preset:
    """A 10 s run from (1, 0, 0) with V = 1, u = (5, 5, 5), h = 0.05 s, except ``changes``."""
    base = {"V": "1", "direction": "+", "u1": "5", "u2": "5", "u3": "5"}
    start = {"x0": 1, "y0": 0, "z0": 0, "h": 0.05}
    return Preset(name, title, {**base, **changes, **start}, 10.0, note)


class SphereConstantSpeedLesson(AnalyzerLesson):
    id = "sphere-constant-speed"
    title = "Constant speed on a sphere"
    chapter = "1"
    problem = "Problem 1.5"
    source = "Textbook §1.3, Problem 1.5, eqs (1.58)-(1.59); Figs. 1.27-1.29"
    summary = (
        "Argument control dφ = ω dt with ω = ±V/|field| holds the speed at V for any"
        " controls u1, u2, u3."
    )
    order = 1.5
    t_end = 10.0
    constant_speed = True
    sampling = 1.0  # Figs. 1.28-1.29 run 10 s
    surface_groups = (Group("surface", "Sphere"),)
    surface_params = (
        Param("R", "float", 1.0, "sphere radius R", min=1e-3, max=1e3, step=0.1, group="surface"),
    )
    presets = (
        _preset(
            "fig-1.28",
            "Fig. 1.28: V = 1 with u1 = u2 = u3 = 5",
            "the source gives V = 1 only; controls and start point are illustrative",
        ),
        _preset(
            "varying-controls",
            "V = 1 with u1 = t, u2 = u3 = 5 (the controls of Example 1.2)",
            "the path of Example 1.2, now at constant speed: |v| = 1 while |v|² of Example"
            " 1.2 grows from 25 to 72",
            u1="t",
        ),
        _preset(
            "reverse",
            "Direction reversed: ω < 0 (the -1 scale block of Fig. 1.27)",
            "the same controls, the point runs the other way",
            u1="t",
            direction="-",
        ),
        _preset(
            "speed-profile",
            "A speed profile V(t) = 0.5 + 0.4 sin(t) (the speed setter of Fig. 1.27)",
            "|v| follows the profile V(t)",
            V="0.5 + 0.4*sin(t)",
        ),
        _preset(
            "example-1.3-zero-field",
            "Controls of Example 1.3 (u1 = sin 10t, u2 = t, u3 = 5): the field is zero at t = 0",
            "at t = 0 the field (0, -sin 10t, t) vanishes at (1, 0, 0): ω is undefined at that"
            " instant only (velocity shown as 0); from t > 0 the point moves at V = 1",
            u1="sin(10*t)",
            u2="t",
        ),
    )

    block_figure = "Fig. 1.27"

    def surface(self, params: Params) -> Quadric:
        """(1.52) with the coefficients (1.53)."""
        return Quadric.sphere(float(params["R"]))

    def extra_derivation(self, params: Params, prepared: Prepared) -> list[DerivationStep]:
        u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
        w, Vs = sp.Symbol("ω"), sp.Symbol("V")
        rows = (u1 * y - u2 * z, -u1 * x + u3 * z, u2 * x - u3 * y)
        return [
            DerivationStep(
                "Target speed",
                "The speed along the curve is fixed at V.",
                sp.Eq(Vs**2, sp.Symbol("v_x") ** 2 + sp.Symbol("v_y") ** 2 + sp.Symbol("v_z") ** 2),
                "Problem 1.5",
            ),
            DerivationStep(
                "ω on the sphere",
                "With dφ = ω dt the sphere analyzer (1.54) gives v = ω·(field); squaring:",
                sp.Eq(w**2, Vs**2 / sum(r**2 for r in rows)),
                "(1.58)",
                reconstructed="lost in the source; follows from V² = vx² + vy² + vz² with"
                " dφ = ω dt",
            ),
            DerivationStep(
                "The constant-speed sphere analyzer",
                "The last row is the argument ω; V may be a number or a profile V(t).",
                [
                    *(sp.Eq(sp.Symbol(f"d{c}/dt"), w * r) for c, r in zip("xyz", rows)),
                    sp.Eq(w, sp.Symbol("±") * Vs / sp.sqrt(sum(r**2 for r in rows))),
                ],
                "(1.59)",
                reconstructed="only 'φ' survived; rebuilt from (1.54) and (1.58)",
            ),
            DerivationStep(
                "Where ω is undefined",
                "The denominator vanishes where r ∥ (u3, u2, u1) (the field of (1.54) is zero):"
                " the point holds only while the field stays zero there, and the lab says so."
                " Example 1.3's controls make it vanish at (1, 0, 0) at the instant t = 0 only.",
                sp.Eq(sp.Symbol("|field|"), 0),
                "(1.58); Example 1.3",
            ),
        ]

    def extra_metrics(
        self, params: Params, prepared: Prepared, result: RunResult
    ) -> dict[str, float]:
        speed = result.series["speed"]
        V = prepared.model.controls.speed(result.t)
        moving = speed > 0
        err = float(np.max(np.abs(speed[moving] - np.abs(V[moving])))) if moving.any() else 0.0
        return {
            "speed_min": float(speed.min()),
            "speed_max": float(speed.max()),
            "speed_error_max": err,
        }

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "speed-held",
                "V = 1, u = (t, 5, 5): |v| = V at every sample to 1e-9",
                "(1.59), Fig. 1.29",
                self._claim_speed,
            ),
            Claim(
                "profile",
                "A speed profile V(t) = 0.5 + 0.4 sin t is followed: ||v| - V(t)| ≤ 1e-9",
                "(1.59) text: V may be variable",
                self._claim_profile,
            ),
            Claim(
                "direction",
                "The sign of ω reverses the direction: at t = 0 the velocities of '+' and"
                " '-' are opposite",
                "(1.58)",
                self._claim_direction,
            ),
            Claim(
                "on-sphere",
                "The point stays on the sphere: |x²+y²+z² - 1| ≤ 1e-12 over 10 s, while scipy's"
                " RK45 at default tolerances drifts it by about 2.9e-2 (u = (5, 5, 5), V = 1)",
                "(1.52), Fig. 1.28",
                self._claim_invariant,
            ),
            Claim(
                "zero-field",
                "Example 1.3 controls from (1, 0, 0): the field vanishes at the instant t = 0 only;"
                " |v(0)| = 0 (explained by a note), then |v| = 1 and the point leaves at once",
                "(1.58); Example 1.3",
                self._claim_zero_field,
            ),
        ]

    def _speed_err(self, preset: str) -> float:
        res = self.run(preset)
        return float(res.metrics["speed_error_max"])

    def _claim_speed(self) -> ClaimResult:
        return at_most(1e-9, self._speed_err("varying-controls"), "max ||v| - V| ")

    def _claim_profile(self) -> ClaimResult:
        return at_most(1e-9, self._speed_err("speed-profile"), "max ||v| - V(t)| ")

    def _claim_direction(self) -> ClaimResult:
        out = []
        for d in ("+", "-"):
            model = AnalyzerModel.of(
                Quadric.sphere(1.0).coeffs(),
                Controls(parse_formula("t"), 5.0, 5.0, V=1.0, sign=1.0 if d == "+" else -1.0),
            )
            out.append(model.velocity(0.0, np.array([1.0, 0.0, 0.0]))[0])
        return at_most(1e-12, float(np.linalg.norm(out[0] + out[1])), "|v+ + v-| ")

    def _claim_invariant(self) -> ClaimResult:
        ours = float(self.run("fig-1.28").metrics["invariant_drift_max"])
        params = self.resolve(preset="fig-1.28")
        prepared = self.prepare(params)
        rk = integrate(prepared.model, prepared.r0, 10.0, method="RK45", samples=1001)
        d_rk = float(rk.drift.max())
        ok = ours <= 1e-12 and 0.5 * RK45_DRIFT <= d_rk <= 2 * RK45_DRIFT
        return ClaimResult(
            f"ours <= 1e-12; RK45 default within a factor 2 of {RK45_DRIFT:.3g}",
            f"ours {ours:.3g}; RK45 {d_rk:.3g}",
            ok,
        )

    def _claim_zero_field(self) -> ClaimResult:
        res = self.run("example-1.3-zero-field")
        speed = res.series["speed"]
        r = np.stack([res.series[c] for c in "xyz"], axis=1)
        chord = float(np.linalg.norm(r[1] - r[0]))
        ok = (
            speed[0] == 0.0
            and bool(np.all(np.abs(speed[1:] - 1.0) <= 1e-9))
            and any("instant only" in m for m in res.messages)
            and chord >= 0.9 * float(res.t[1])
        )
        return ClaimResult(
            "|v(0)| = 0 (explained), |v(t>0)| = 1, |r(t1) - r0| ≈ t1",
            f"|v(0)| = {speed[0]:.3g}, max ||v|-1| for t>0 = {np.max(np.abs(speed[1:] - 1)):.3g},"
            f" |r(t1) - r0| = {chord:.4g} at t1 = {res.t[1]:g}",
            ok,
        )


LESSON = SphereConstantSpeedLesson()
