"""Problem 1.1: motion along a parabola in the plane (textbook §1.3, eqs (1.21)-(1.33)).

The conic analyzer (1.30) with dφ = ω dt (1.31) gives the coordinate speeds (1.32);
for a parabola det[[a11, a12], [a12, a22]] = 0, so a11 = λ a12 and a22 = a12/λ, and

    dx/dt =  ω² (a12 x + (a12/λ) y + a23)
    dy/dt = -ω² (λ a12 x + a12 y + a13)                                        (1.33)

The worked example: ω = -1, a12 = 0.5, a13 = -7, a23 = -5, start (4, 10), λ = 0.05, 0.1
and 0.5 (Figs. 1.8-1.10).  a33 is not needed: the analyzer traces the level curve
through the start point.  The matrix of (1.33) is nilpotent, so x(t), y(t) are
quadratics in t (the double integrator (1.23)).  The simulation time is not given in
the source; the lab uses 10 s.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.plane.conic import (
    PlanarModel,
    PlanarState,
    PlanarTrack,
    conic_expr,
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

BOOK_LAMBDAS = (0.05, 0.1, 0.5)
BOOK = {"omega": -1.0, "a12": 0.5, "a13": -7.0, "a23": -5.0, "x0": 4.0, "y0": 10.0}
#: a33 of the parabola through (4, 10), v0 and A v0 of X(t) = X0 + t v0 + t²/2 A v0 for the
#: example's λ (computed from (1.33) with the example's numbers).
TABLE = {
    0.05: {"a33": -884.4, "v0": (97.0, 1.9), "Av0": (67.5, -3.375), "X10": (4349.0, -139.75)},
    0.1: {"a33": -384.8, "v0": (47.0, 1.8), "Av0": (32.5, -3.25), "X10": (2099.0, -134.5)},
    0.5: {"a33": 12.0, "v0": (7.0, 1.0), "Av0": (4.5, -2.25), "X10": (299.0, -92.5)},
}


def parabola_coeffs(lam: float, a12: float, a13: float, a23: float) -> dict[str, float]:
    """The coefficients of (1.33): a11 = λ a12, a22 = a12/λ (a33 free)."""
    return {"a11": lam * a12, "a12": a12, "a22": a12 / lam, "a13": a13, "a23": a23, "a33": 0.0}


class ParabolaLesson(PlanarLesson):
    id = "parabola"
    title = "Motion along a parabola"
    chapter = "1"
    problem = "Problem 1.1"
    source = "Textbook §1.3, Problem 1.1, eqs (1.21)-(1.33); Figs. 1.6-1.10"
    summary = "A two-integrator analyzer draws the parabola through the start point; x(t), y(t) come out quadratic."
    order = 1.1
    t_end = 10.0
    groups = (
        MODE,
        Group("curve", "Parabola (1.33)"),
        Group("controls", "Control ω (1.31)", change="live"),
        INITIAL,
        Group("family", "Family (Figs. 1.8-1.10)", change="restart"),
        DIGITAL,
    )
    modes = ("digital",)
    family = "family"
    own_params = (
        Param(
            "lambda",
            "float",
            0.5,
            "λ = a11/a12 = a12/a22",
            min=-100.0,
            max=100.0,
            step=0.01,
            group="curve",
        ),
        Param(
            "omega",
            "float",
            -1.0,
            "ω",
            min=-20.0,
            max=20.0,
            step=0.1,
            group="controls",
            help="enters (1.32)-(1.33) as ω²",
        ),
        Param("a12", "float", 0.5, "a12", min=-100.0, max=100.0, step=0.1, group="curve"),
        Param("a13", "float", -7.0, "a13", min=-1e3, max=1e3, step=0.5, group="curve"),
        Param("a23", "float", -5.0, "a23", min=-1e3, max=1e3, step=0.5, group="curve"),
        Param("x0", "float", 4.0, "x0", min=-1e4, max=1e4, step=0.5, group="initial"),
        Param("y0", "float", 10.0, "y0", min=-1e4, max=1e4, step=0.5, group="initial"),
        Param(
            "family",
            "int",
            1,
            "parabolas in the family",
            min=1,
            max=3,
            step=1,
            group="family",
            help="1: λ alone; 2: also λ2; 3: also λ3 (Figs. 1.8-1.10: 0.05, 0.1, 0.5)",
        ),
        Param("lambda_2", "float", 0.1, "λ2", min=-100.0, max=100.0, step=0.01, group="family"),
        Param("lambda_3", "float", 0.5, "λ3", min=-100.0, max=100.0, step=0.01, group="family"),
    )
    presets = (
        Preset(
            "figs-1.8-1.10",
            "Figs. 1.8-1.10: the family λ = 0.05, 0.1, 0.5",
            {**BOOK, "lambda": 0.05, "lambda_2": 0.1, "lambda_3": 0.5, "family": 3},
            10.0,
            "ω = -1, a12 = 0.5, a13 = -7, a23 = -5, start (4, 10);"
            " series x, y (λ = 0.05), x_2, y_2 (0.1), x_3, y_3 (0.5)",
        ),
        Preset("lambda-0.05", "λ = 0.05", {**BOOK, "lambda": 0.05}, 10.0, "a11 = 0.025, a22 = 10"),
        Preset("lambda-0.1", "λ = 0.1", {**BOOK, "lambda": 0.1}, 10.0, "a11 = 0.05, a22 = 5"),
        Preset("lambda-0.5", "λ = 0.5", {**BOOK, "lambda": 0.5}, 10.0, "a11 = 0.25, a22 = 1"),
        Preset(
            "digital-simple",
            "Digital analyzer (1.25), simple additions, λ = 0.5",
            {**BOOK, "lambda": 0.5, "digital": "simple", "delta": 0.01, "pulse": 0.01},
            3.0,
            "the staircase path of a CNC interpolator and its pulses per axis",
        ),
        Preset(
            "digital-improved",
            "Digital analyzer (1.25), improved additions, λ = 0.5",
            {**BOOK, "lambda": 0.5, "digital": "improved", "delta": 0.01, "pulse": 0.01},
            3.0,
            "the y addition uses the x already updated",
        ),
    )

    def validate(self, params: Params) -> None:
        for name, lam in zip(("lambda", "lambda_2", "lambda_3"), self.lambdas(params)):
            if lam == 0:
                raise ParamError(name, "λ must not be 0 (a22 = a12/λ)")
        if params["a12"] == 0:
            raise ParamError(
                "a12", "a12 must not be 0 (the parabola degenerates into parallel lines)"
            )

    def lambdas(self, params: Params) -> list[float]:
        """λ of the family's members (the first is ``lambda``)."""
        lams = [float(params[n]) for n in ("lambda", "lambda_2", "lambda_3")]
        return lams[: int(params["family"])]

    def planar_model(self, params: Params) -> tuple[PlanarModel, np.ndarray]:
        lams = self.lambdas(params)
        coeffs = [parabola_coeffs(l, params["a12"], params["a13"], params["a23"]) for l in lams]
        r0 = np.repeat(np.array([[params["x0"], params["y0"]]], dtype=float), len(lams), axis=0)
        return PlanarModel.of(coeffs, float(params["omega"]) ** 2), r0

    def notes(self, params: Params) -> list[Note]:
        lams = self.lambdas(params)
        if len(lams) == 1:
            return []
        members = "".join(f", _{k + 1} λ = {l:g}" for k, l in enumerate(lams[1:], 1))
        return [Note("info", f"family: series without suffix λ = {lams[0]:g}{members}")]

    block_figure = "Fig. 1.6"

    def diagram_equations(self, params: Params, prepared: PlanarPrepared) -> list[sp.Eq]:
        """(1.33) with this lesson's numbers and ω² kept as the gain after the summers (Fig. 1.6)."""
        return prepared.model.equations(sp.Symbol("ω", real=True) ** 2)

    def extra_derivation(self, params: Params, prepared: PlanarPrepared) -> list[DerivationStep]:
        lam, w = sp.Symbol("λ"), sp.Symbol("ω")
        a11, a12, a22, a13, a23 = sp.symbols("a11 a12 a22 a13 a23")
        x, y = sp.symbols("x y")
        A = w**2 * sp.Matrix([[a12, a12 / lam], [-lam * a12, -a12]])
        num = {
            k: sp.nsimplify(float(prepared.model.coeffs[k][0]), rational=True)
            for k in ("a11", "a12", "a22", "a13", "a23", "a33")
        }
        return [
            DerivationStep(
                "Coordinate speeds",
                "(1.30) with dφ = ω dt: ω appears squared, so its sign no longer sets the direction.",
                [
                    sp.Eq(sp.Symbol("dx/dt"), w**2 * (a12 * x + a22 * y + a23)),
                    sp.Eq(sp.Symbol("dy/dt"), -(w**2) * (a11 * x + a12 * y + a13)),
                ],
                "(1.32)",
                reconstructed=None,
            ),
            DerivationStep(
                "The parabola condition",
                "The quadratic part is degenerate.",
                [
                    sp.Eq(sp.Matrix([[a11, a12], [a12, a22]]).det(), 0),
                    sp.Eq(a11, lam * a12),
                    sp.Eq(a22, a12 / lam),
                ],
                "Problem 1.1",
            ),
            DerivationStep(
                "The parabola analyzer",
                "",
                [
                    sp.Eq(sp.Symbol("dx/dt"), w**2 * (a12 * x + a12 / lam * y + a23)),
                    sp.Eq(sp.Symbol("dy/dt"), -(w**2) * (lam * a12 * x + a12 * y + a13)),
                ],
                "(1.33)",
            ),
            DerivationStep(
                "With these numbers",
                f"λ = {float(params['lambda']):g}, ω = {float(params['omega']):g}; a33 is set by the start point.",
                [sp.Eq(conic_expr(num), 0), *prepared.model.equations()],
                "(1.33)",
            ),
            DerivationStep(
                "A double integrator",
                "The matrix of (1.33) is nilpotent, so x(t), y(t) are quadratics in t: X(t) = X0 + t v0 + t²/2 A v0.",
                sp.Eq(sp.MatMul(A, A, evaluate=False), sp.simplify(A * A)),
                "(1.23)",
                reconstructed="derived, not in source: explains the quadratic x(t), y(t) of Figs. 1.9-1.10",
            ),
        ]

    def extra_metrics(
        self, params: Params, track: PlanarTrack, t: np.ndarray, state: PlanarState
    ) -> dict[str, object]:
        c = track.model.coeffs
        return {
            "a11": float(c["a11"][0]),
            "a22": float(c["a22"][0]),
            "a33": float(c["a33"][0]),
            "x_end": float(state.r[-1, 0, 0]),
            "y_end": float(state.r[-1, 0, 1]),
        }

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "slope",
                "(1.29) is -F_x/F_y and the analyzer (1.30) is tangent to every conic (∇F·v ≡ 0)",
                "(1.29)-(1.30)",
                self._claim_symbolic,
            ),
            Claim(
                "nilpotent",
                "The matrix of (1.33) squares to zero for every λ, a12, ω",
                "(1.33), (1.23)",
                self._claim_nilpotent,
            ),
            Claim(
                "a33",
                "The parabolas through (4, 10) have a33 = -884.4, -384.8, 12 for λ = 0.05, 0.1, 0.5",
                "Problem 1.1, Figs. 1.8-1.10",
                self._claim_a33,
            ),
            Claim(
                "closed-form",
                "x(t), y(t) are X0 + t v0 + t²/2 A v0 with v0 = (97, 1.9), (47, 1.8), (7, 1);"
                " X(10) = (4349, -139.75), (2099, -134.5), (299, -92.5)",
                "Problem 1.1, Figs. 1.9-1.10",
                self._claim_closed_form,
            ),
            Claim(
                "on-parabola",
                "The point stays on its parabola: |F| / scale ≤ 1e-13 over 10 s for all three λ",
                "(1.21)",
                self._claim_invariant,
            ),
            Claim(
                "omega-sign",
                "ω = -1 and ω = +1 give identical runs (ω enters as ω²)",
                "(1.32)-(1.33), Fig. 1.6",
                self._claim_omega,
            ),
        ]

    def _claim_symbolic(self) -> ClaimResult:
        a = {n: sp.Symbol(n) for n in ("a11", "a12", "a22", "a13", "a23", "a33")}
        x, y, w = sp.symbols("x y omega")
        F = conic_expr(a, x, y)
        dx, dy = (
            w * (a["a12"] * x + a["a22"] * y + a["a23"]),
            -w * (a["a11"] * x + a["a12"] * y + a["a13"]),
        )
        tang = sp.expand(sp.diff(F, x) * dx + sp.diff(F, y) * dy)
        slope = sp.simplify(
            -(a["a11"] * x + a["a12"] * y + a["a13"]) / (a["a12"] * x + a["a22"] * y + a["a23"])
            + sp.diff(F, x) / sp.diff(F, y)
        )
        return ClaimResult("0 and 0", f"{tang} and {slope}", tang == 0 and slope == 0)

    def _claim_nilpotent(self) -> ClaimResult:
        lam, a12, w = sp.symbols("lambda a12 omega", nonzero=True)
        A = w**2 * sp.Matrix([[a12, a12 / lam], [-lam * a12, -a12]])
        sq = sp.simplify(A * A)
        return ClaimResult("zero matrix", str(sq.tolist()), sq == sp.zeros(2, 2))

    def _claim_a33(self) -> ClaimResult:
        params = self.resolve(preset="figs-1.8-1.10")
        prep = self.prepare(params)
        got = [float(v) for v in prep.model.coeffs["a33"]]
        err = max(abs(g - TABLE[l]["a33"]) for g, l in zip(got, self.lambdas(params)))
        return at_most(1e-9, err, f"a33 = {', '.join(f'{g:.6g}' for g in got)}; max error ")

    def _claim_closed_form(self) -> ClaimResult:
        worst = 0.0
        for lam in BOOK_LAMBDAS:
            res = self.run(f"lambda-{lam:g}")
            t = res.t
            X0 = np.array([4.0, 10.0])
            v0, Av0 = np.array(TABLE[lam]["v0"]), np.array(TABLE[lam]["Av0"])
            exact = X0 + t[:, None] * v0 + 0.5 * t[:, None] ** 2 * Av0
            got = np.stack([res.series["x"], res.series["y"]], axis=1)
            worst = max(
                worst,
                float(np.max(np.abs(got - exact))) / 4349.0,
                float(np.max(np.abs(got[-1] - np.array(TABLE[lam]["X10"])))) / 4349.0,
            )
        return at_most(1e-12, worst, "max |X - closed form| / 4349 ")

    def _claim_invariant(self) -> ClaimResult:
        res = self.run("figs-1.8-1.10")
        return at_most(1e-13, float(res.metrics["invariant_drift_rel"]), "max |F| / scale ")

    def _claim_omega(self) -> ClaimResult:
        a = self.run("lambda-0.1")
        b = self.run("lambda-0.1", {"omega": 1.0})
        d = max(float(np.max(np.abs(a.series[k] - b.series[k]))) for k in ("x", "y"))
        return at_most(0.0, d, "max |run(ω=-1) - run(ω=+1)| ")


LESSON = ParabolaLesson()
