"""Problem 1.3: motion along a curve on a second-order surface (textbook §1.3, eqs (1.42)-(1.51)).

Two syntheses of the analyzer for any quadric (1.42):

* undetermined coefficients: the linear structure (1.43) must satisfy the tangency
  identity (1.44), i.e. the ten homogeneous equations (1.47) in twelve coefficients.
  Solved here by sympy for the chosen surface: rank 9 (three free coefficients, and the
  solution set is exactly (1.50)) for the non-degenerate quadrics, rank 7 for the
  cylinder (five free coefficients, of which (1.50) gives three);
* ψ-substitution (1.48) with undetermined λ1, λ2, giving the general analyzer (1.49)
  with three free controls u1, u2, u3, which for a quadric is (1.50).

For constant controls the analyzer draws plane curves: u3 x + u2 y + u1 z is constant.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import COEFF_NAMES, AnalyzerModel, Controls
from analyzer_lab.lessons.analyzers.field.lesson import AnalyzerLesson, Prepared
from analyzer_lab.lessons.analyzers.field.run import integrate
from analyzer_lab.lessons.analyzers.field.tangent_fields import (
    MONOMIALS,
    UNKNOWNS,
    analyze,
    exact_coeffs,
    field_150_vectors,
    psi_derivation,
    structure_143,
    system_147,
    x,
    y,
    z,
)
from analyzer_lab.lessons.analyzers.surfaces.quadric import CONSTRUCTORS, Quadric
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Group,
    Param,
    ParamError,
    Params,
    Preset,
    RunResult,
    at_most,
)

SURFACE_CHOICES = (*CONSTRUCTORS, "coefficients")


def _surfaces_using(name: str) -> tuple[str, ...]:
    """The surface types whose equation has the parameter ``name`` (R, a, b or c)."""
    return tuple(k for k, spec in CONSTRUCTORS.items() if name in spec.params)


#: A start point on each constructor's default surface.
STARTS = {
    "sphere": (1.0, 0.0, 0.0),
    "ellipsoid": (0.0, 2.0, 0.0),
    "elliptic-cylinder": (1.0, 0.0, 0.0),
    "elliptic-cone": (1.0, 0.0, 1.0),
    "elliptic-paraboloid": (1.0, 0.0, 1.0),
    "hyperbolic-paraboloid": (1.0, 0.0, 1.0),
    "hyperboloid-1": (1.0, 0.0, 0.0),
    "hyperboloid-2": (0.0, 0.0, 1.0),
}
#: A general quadric typed by its coefficients (a tilted, shifted ellipsoid).
GENERAL = {
    "a11": 2.0,
    "a22": 3.0,
    "a33": 1.0,
    "a12": 0.5,
    "a23": 0.0,
    "a31": 0.2,
    "a14": -1.0,
    "a24": 0.0,
    "a34": 0.5,
    "a44": -4.0,
}


def _surface_presets() -> tuple[Preset, ...]:
    out = []
    for sid, start in STARTS.items():
        spec = CONSTRUCTORS[sid]
        vals = {
            "surface": sid,
            **{k: v for k, v in spec.defaults.items()},
            "u1": "1",
            "u2": "0.3",
            "u3": "0.2",
            "x0": start[0],
            "y0": start[1],
            "z0": start[2],
        }
        note = (
            "rank of (1.47) = 7: five free coefficients, (1.50) gives three"
            if sid == "elliptic-cylinder"
            else "rank of (1.47) = 9: (1.50) is the whole solution set"
        )
        t_end = (
            4.0 if sid == "hyperbolic-paraboloid" else 10.0
        )  # its plane sections are hyperbolas: the point runs off exponentially
        out.append(
            Preset(
                sid,
                f"{spec.title.capitalize()} ({spec.equation}), constant controls",
                vals,
                t_end,
                note,
            )
        )
    return tuple(out)


class QuadricLesson(AnalyzerLesson):
    id = "quadric"
    title = "Curve on any second-order surface"
    chapter = "1"
    problem = "Problem 1.3"
    source = "Textbook §1.3, Problem 1.3, eqs (1.42)-(1.51)"
    summary = (
        "Undetermined coefficients (1.47) and the ψ-substitution (1.48) both give"
        " the analyzer (1.50) with three free controls."
    )
    order = 1.3
    t_end = 10.0
    modes = ("surface",)
    surface_groups = (
        Group("mode", "Surface type", change="restart"),
        Group("shape", "Surface parameters", when=("surface", tuple(CONSTRUCTORS))),
        Group("coefficients", "Coefficients a11 ... a44", when=("surface", ("coefficients",))),
    )
    surface_params = (
        Param(
            "surface",
            "choice",
            "sphere",
            "surface type",
            choices=SURFACE_CHOICES,
            group="mode",
            help="a type with its parameters, or 'coefficients' to type a11 ... a44",
        ),
        *(
            Param(
                n,
                "float",
                1.0,
                n,
                min=1e-3,
                max=1e3,
                step=0.1,
                group="shape",
                when=("surface", _surfaces_using(n)),
            )
            for n in ("R", "a", "b", "c")
        ),
        *(
            Param(
                n,
                "float",
                {"a11": 1.0, "a22": 1.0, "a33": 1.0, "a44": -1.0}.get(n, 0.0),
                n,
                min=-1e4,
                max=1e4,
                step=0.1,
                group="coefficients",
                help="used when surface = coefficients",
            )
            for n in COEFF_NAMES
        ),
    )
    presets = (
        *_surface_presets(),
        Preset(
            "coefficients",
            "Any quadric by its ten coefficients (a tilted, shifted ellipsoid)",
            {
                "surface": "coefficients",
                **GENERAL,
                "u1": "1",
                "u2": "0.5*sin(t)",
                "u3": "0.3",
                "x0": 1.5,
                "y0": 0.0,
                "z0": 0.0,
            },
            10.0,
            "the start point is projected onto the surface",
        ),
        Preset(
            "gradient-case",
            "The 'gradient' special case u1 = u2 = u3 = 1 on the ellipsoid",
            {
                "surface": "ellipsoid",
                "a": 3,
                "b": 2,
                "c": 1,
                "u1": "1",
                "u2": "1",
                "u3": "1",
                "x0": 0,
                "y0": 2,
                "z0": 0,
            },
            10.0,
            "dx = F_y - F_z, dy = F_z - F_x, dz = F_x - F_y (reconstructed): one"
            " trajectory per start point",
        ),
        Preset(
            "varying-controls",
            "Time-varying controls on the one-sheet hyperboloid",
            {
                "surface": "hyperboloid-1",
                "a": 1,
                "b": 1,
                "c": 1,
                "u1": "1 + 0.5*sin(t)",
                "u2": "0.3*cos(2*t)",
                "u3": "0.1*t",
                "x0": 1,
                "y0": 0,
                "z0": 0,
            },
            10.0,
            "not a plane curve any more; F is still kept to round-off",
        ),
    )

    def surface(self, params: Params) -> Quadric:
        sid = params["surface"]
        if sid == "coefficients":
            return Quadric.from_coeffs(
                label="quadric (typed coefficients)", **{n: float(params[n]) for n in COEFF_NAMES}
            )
        spec = CONSTRUCTORS[sid]
        return spec(**{k: float(params[k]) for k in spec.params})

    def validate(self, params: Params) -> None:
        super().validate(params)
        if params["surface"] == "coefficients":
            if all(float(params[n]) == 0 for n in COEFF_NAMES[:6]):
                raise ParamError(
                    "a11",
                    "the quadratic coefficients a11 ... a31 are all zero: not a"
                    " second-order surface",
                )
            kind = self.surface(params).classify().kind
            if kind in ("empty", "all-space"):
                raise ParamError(
                    "a44",
                    f"these coefficients describe {kind.replace('-', ' ')}: there is no"
                    f" surface to move on",
                )

    # -- the derivation ------------------------------------------------------------

    def structure_steps(self, q: Quadric) -> list[DerivationStep]:
        """(1.43)-(1.47) solved for this surface."""
        a = exact_coeffs(q)
        rep = analyze(q)
        fx, fy, fz = structure_143()
        unknowns = sp.Matrix(UNKNOWNS)
        general = system_147()
        rows_general = [sp.Eq(sp.expand((general[i, :] * unknowns)[0]), 0) for i in range(10)]
        rows_here = [sp.Eq(e, 0) for e in (rep.matrix * unknowns) if e != 0]
        _, pivots = rep.matrix.rref()
        free = [UNKNOWNS[j] for j in range(12) if j not in pivots]
        W = field_150_vectors(a)
        steps = [
            DerivationStep(
                "A linear structure",
                "Twelve undetermined coefficients.",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), fx),
                    sp.Eq(sp.Symbol("dy/dφ"), fy),
                    sp.Eq(sp.Symbol("dz/dφ"), fz),
                ],
                "(1.43)",
            ),
            DerivationStep(
                "Tangency for every parametrization",
                "",
                sp.Eq(
                    sp.Symbol("F_x") * sp.Symbol("dx/dφ")
                    + sp.Symbol("F_y") * sp.Symbol("dy/dφ")
                    + sp.Symbol("F_z") * sp.Symbol("dz/dφ"),
                    0,
                ),
                "(1.44)",
            ),
            DerivationStep(
                "Partial derivatives",
                "Each with its own variable first, as in the source.",
                [
                    sp.Eq(
                        sp.Symbol(f"F_{v}"),
                        2 * (sum(sp.Symbol(c) * w for c, w in terms) + sp.Symbol(linear)),
                    )
                    for v, terms, linear in (
                        ("x", (("a11", x), ("a12", y), ("a31", z)), "a14"),
                        ("y", (("a22", y), ("a12", x), ("a23", z)), "a24"),
                        ("z", (("a33", z), ("a23", y), ("a31", x)), "a34"),
                    )
                ],
                "(1.45)",
            ),
            DerivationStep(
                "Ten homogeneous equations",
                "(1.44) is an identity in x, y, z (1.46): the coefficient of every monomial "
                + ", ".join(str(m) for m in MONOMIALS)
                + " vanishes.",
                rows_general,
                "(1.46)-(1.47)",
            ),
            DerivationStep(
                "(1.47) on this surface",
                f"{q.label or 'this quadric'}: {len(rows_here)} non-trivial equations, rank"
                f" {rep.rank}, "
                f"so {rep.nullity} coefficients can be set arbitrarily"
                f" ({', '.join(map(str, free))} here).",
                rows_here or [sp.Eq(0, 0)],
                "(1.47)",
            ),
        ]
        if rep.family_is_150:
            text = (
                "The three (1.50) fields (u1, u2, u3) satisfy (1.47) and are independent;"
                " rank [nullspace | (1.50)] = 3 = nullity, "
                "so (1.50) is the whole solution set: the undetermined-coefficient method"
                " and the ψ-method give the same analyzer."
            )
        else:
            text = (
                f"The nullspace has dimension {rep.nullity} but (1.50) spans {rep.rank_150}"
                f" of it (combined rank {rep.rank_combined}): "
                "the extra fields move the point along the cylinder's axis (dz/dφ in"
                " the span of 1, x, y, z)."
            )
        steps.append(
            DerivationStep(
                "The solution family",
                text,
                [
                    sp.Eq(sp.Symbol(f"(1.50) for u{i + 1}"), W[:, i].T, evaluate=False)
                    for i in range(3)
                ],
                "(1.50)",
                reconstructed="derived, not in source: the rank check behind 'three"
                " coefficients can be set arbitrarily'",
            )
        )
        return steps

    def psi_steps(self) -> list[DerivationStep]:
        p = sp.symbols("psi1:7")
        l1, l2 = sp.symbols("lambda1 lambda2")
        Fx, Fy, Fz = sp.symbols("F_x F_y F_z")
        u1, u2, u3 = sp.symbols("u1 u2 u3")
        return [
            DerivationStep(
                "ψ-substitution",
                "λ1, λ2 undetermined, ψ1 ... ψ6 arbitrary functions.",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), l1 * p[0] + l2 * p[1]),
                    sp.Eq(sp.Symbol("dy/dφ"), l1 * p[2] + l2 * p[3]),
                    sp.Eq(sp.Symbol("dz/dφ"), l1 * p[4] + l2 * p[5]),
                ],
                "(1.48)",
            ),
            DerivationStep(
                "Into (1.44)",
                "",
                sp.Eq(
                    l1 * (Fx * p[0] + Fy * p[2] + Fz * p[4])
                    + l2 * (Fx * p[1] + Fy * p[3] + Fz * p[5]),
                    0,
                ),
                "(1.48)",
            ),
            DerivationStep(
                "An identity for",
                "",
                [
                    sp.Eq(l1, -(Fx * p[1] + Fy * p[3] + Fz * p[5])),
                    sp.Eq(l2, Fx * p[0] + Fy * p[2] + Fz * p[4]),
                ],
                "(1.48)",
                reconstructed="the λ1 line and all signs were lost; chosen so that the"
                " surviving u1, u2 and (1.62)/(1.63) come out",
            ),
            DerivationStep(
                "The general analyzer",
                "Any surface F = 0; the u's are the controls.",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), u1 * Fy - u2 * Fz),
                    sp.Eq(sp.Symbol("dy/dφ"), -u1 * Fx + u3 * Fz),
                    sp.Eq(sp.Symbol("dz/dφ"), u2 * Fx - u3 * Fy),
                    sp.Eq(u1, p[1] * p[2] - p[0] * p[3]),
                    sp.Eq(u2, p[0] * p[5] - p[1] * p[4]),
                    sp.Eq(u3, p[3] * p[4] - p[2] * p[5]),
                ],
                "(1.49)",
                reconstructed="signs rebuilt (convention B); the extracted u3 = ψ4ψ6 -"
                " ψ3ψ6 is impossible, ψ4ψ5 - ψ3ψ6 is used",
            ),
            DerivationStep(
                "The 'gradient' special case",
                "u1 = u2 = u3 = 1: F_x(F_y - F_z) + F_y(F_z - F_x) + F_z(F_x - F_y) ≡ 0;"
                " one trajectory per start point.",
                [
                    sp.Eq(sp.Symbol("dx/dφ"), Fy - Fz),
                    sp.Eq(sp.Symbol("dy/dφ"), Fz - Fx),
                    sp.Eq(sp.Symbol("dz/dφ"), Fx - Fy),
                ],
                "after (1.50)",
                reconstructed="the content was lost; u1 = u2 = u3 = 1 is the natural reading",
            ),
            DerivationStep(
                "Constant controls draw plane curves",
                "(u3, u2, u1)·v ≡ 0 for (1.50), so the path stays in a plane.",
                sp.Eq(
                    sp.Symbol("u3") * x + sp.Symbol("u2") * y + sp.Symbol("u1") * z,
                    sp.Symbol("const"),
                ),
                "Problem 1.3 text",
            ),
            DerivationStep(
                "More general substitutions",
                "Any numbers l1 ≥ 2 of undetermined coefficients λj and l2 of arbitrary"
                " functions ψk may be used (l1 ≥ 2 avoids the trivial field).",
                sp.Eq(
                    sp.Symbol("dx_i/dφ"),
                    sp.Sum(
                        sp.Symbol("λ_j") * sp.Symbol("ψ_ij"), (sp.Symbol("j"), 1, sp.Symbol("l1"))
                    ),
                ),
                "(1.51)",
                reconstructed="lost; only its description survives",
            ),
        ]

    def extra_derivation(self, params: Params, prepared: Prepared) -> list[DerivationStep]:
        return [*self.structure_steps(self.surface(params)), *self.psi_steps()]

    def extra_metrics(
        self, params: Params, prepared: Prepared, result: RunResult
    ) -> dict[str, float | str]:
        sr = result.series
        plane = sr["u3"] * sr["x"] + sr["u2"] * sr["y"] + sr["u1"] * sr["z"]
        return {
            "plane_invariant_spread": float(np.ptp(plane)),
            "surface_kind": self.surface(params).classify().kind,
        }

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "rank-9",
                "(1.47) has rank 9 (three free coefficients) for the sphere, ellipsoid,"
                " cone, paraboloids and hyperboloids, and its solutions are exactly (1.50)",
                "(1.47), Problem 1.3 text",
                self._claim_rank9,
            ),
            Claim(
                "rank-7-cylinder",
                "The cylinder x²/a² + y²/b² = 1 is the exception: rank 7, five free"
                " coefficients, (1.50) gives three of them",
                "(1.47); self-study C1.5 (a)",
                self._claim_rank7,
            ),
            Claim(
                "random-rank",
                "20 random quadrics with rational coefficients: rank 9 every time",
                "(1.47)",
                self._claim_random,
            ),
            Claim(
                "psi",
                "The ψ-substitution with the chosen λ1, λ2 satisfies (1.44) identically"
                " and gives (1.49); the literal u3 = ψ4ψ6 - ψ3ψ6 does not",
                "(1.48)-(1.49)",
                self._claim_psi,
            ),
            Claim(
                "plane-curves",
                "Constant controls give plane curves on every surface type: u3 x + u2 y +"
                " u1 z constant to 1e-10",
                "Problem 1.3 text",
                self._claim_plane,
            ),
            Claim(
                "on-surface",
                "Time-varying controls keep F to round-off on every surface type (|F - F0|"
                " ≤ 1e-12·scale)",
                "(1.44), (1.50)",
                self._claim_invariant,
            ),
        ]

    def _claim_rank9(self) -> ClaimResult:
        got = {}
        for sid in CONSTRUCTORS:
            if sid == "elliptic-cylinder":
                continue
            rep = analyze(CONSTRUCTORS[sid]())
            got[sid] = (rep.rank, rep.family_is_150)
        ok = all(v == (9, True) for v in got.values())
        return ClaimResult(
            "rank 9 and (1.50) = solution set for each",
            ", ".join(f"{k}: {r}{'' if f else ' (not 1.50)'}" for k, (r, f) in got.items()),
            ok,
        )

    def _claim_rank7(self) -> ClaimResult:
        rep = analyze(Quadric.elliptic_cylinder(2.0, 1.0))
        ok = rep.rank == 7 and rep.nullity == 5 and rep.rank_150 == 3 and rep.rank_combined == 5
        return ClaimResult(
            "rank 7, nullity 5, (1.50) rank 3 inside",
            f"rank {rep.rank}, nullity {rep.nullity}, (1.50) rank {rep.rank_150}, combined"
            f" {rep.rank_combined}",
            ok,
        )

    def _claim_random(self) -> ClaimResult:
        rng = np.random.default_rng(147)
        ranks = []
        for _ in range(20):
            vals = {
                n: sp.Rational(int(rng.integers(-9, 10)), int(rng.integers(1, 5)))
                for n in COEFF_NAMES
            }
            ranks.append(system_147(vals).rank())
        return ClaimResult("[9] * 20", str(ranks), all(r == 9 for r in ranks))

    def _claim_psi(self) -> ClaimResult:
        d = psi_derivation()
        ok = all(d[k] == 0 for k in ("tangency", "dx", "dy", "dz")) and d["u3_literal_dy"] != 0
        return ClaimResult(
            "0, 0, 0, 0 and non-zero",
            ", ".join(str(d[k]) for k in ("tangency", "dx", "dy", "dz", "u3_literal_dy")),
            ok,
        )

    def _runs(self, controls: Controls, t_end: float) -> float:
        worst = 0.0
        for sid, start in STARTS.items():
            q = CONSTRUCTORS[sid]()
            model = AnalyzerModel.of(q.coeffs(), controls)
            run = integrate(model, np.array(start), t_end, h=1e-2, samples=501)
            if controls.u1 == 1.0:
                u = np.array([1.0, 0.3, 0.2])
                inv = run.r[:, 0, :] @ np.array([u[2], u[1], u[0]])
                worst = max(worst, float(np.ptp(inv)) / max(1.0, float(np.abs(run.r).max())))
            else:
                size = max(q.scale, float(np.linalg.norm(q.Q, 2)) * float(np.abs(run.r).max()) ** 2)
                worst = max(worst, float(run.drift.max()) / size)
        return worst

    def _claim_plane(self) -> ClaimResult:
        return at_most(
            1e-10,
            self._runs(Controls(1.0, 0.3, 0.2), 5.0),
            "max spread of u3 x + u2 y + u1 z (relative) ",
        )

    def _claim_invariant(self) -> ClaimResult:
        from analyzer_lab.lessons.kit.formula import parse_formula

        ctl = Controls(
            parse_formula("1 + 0.5*sin(t)"), parse_formula("0.3*cos(2*t)"), parse_formula("0.1*t")
        )
        return at_most(1e-12, self._runs(ctl, 5.0), "max |F - F0| / scale ")


LESSON = QuadricLesson()
