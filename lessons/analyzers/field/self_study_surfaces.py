"""Self-study C1.5: the analyzer (1.50) on the cylinder, cone, paraboloid and hyperboloid.

The four surfaces of C1.5 (а)-(г) in the source's form with a start point on each, the
derivation of their analyzers and the table of the answers (derived with the chapter's
method; the source prints none).  The run steps (1.50) with Gauss-Legendre on a fixed
grid (:class:`~analyzer_lab.lessons.analyzers.field.grid_flow.GridFlow`), which the headless run and the live
view of ``self-study-1`` both read.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import AnalyzerModel, field_expr
from analyzer_lab.lessons.analyzers.field.grid_flow import GridFlow
from analyzer_lab.lessons.analyzers.field.lesson import AnalyzerLesson
from analyzer_lab.lessons.analyzers.field.tangent_fields import analyze
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.contract import Claim, ClaimResult, DerivationStep, Frame, Params

SURFACE_TASKS = ("C1.5a-cylinder", "C1.5b-cone", "C1.5c-paraboloid", "C1.5d-hyperboloid")
a, b, c, p = sp.symbols("a b c p", positive=True)
x, y, z = sp.symbols("x y z", real=True)
u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
#: F of each surface as the source writes it.
FORMS = {
    "C1.5a-cylinder": x**2 / a**2 + y**2 / b**2 - 1,
    "C1.5b-cone": x**2 / a**2 + y**2 / b**2 - z**2 / c**2,
    "C1.5c-paraboloid": x**2 / a**2 + y**2 / b**2 - 2 * p * z,
    "C1.5d-hyperboloid": x**2 / a**2 + y**2 / b**2 - z**2 / c**2 - 1,
}
_CONE = (
    u1 * y / b**2 + u2 * z / c**2,
    -u1 * x / a**2 - u3 * z / c**2,
    u2 * x / a**2 - u3 * y / b**2,
)
#: The answers: dx/dφ, dy/dφ, dz/dφ of (1.50) on each surface (derived, not in the source).
ANSWERS = {
    "C1.5a-cylinder": (u1 * y / b**2, -u1 * x / a**2, u2 * x / a**2 - u3 * y / b**2),
    "C1.5b-cone": _CONE,
    "C1.5c-paraboloid": (
        u1 * y / b**2 + p * u2,
        -u1 * x / a**2 - p * u3,
        u2 * x / a**2 - u3 * y / b**2,
    ),
    "C1.5d-hyperboloid": _CONE,
}
#: The rank of (1.47) on each surface (the cylinder admits more tangent fields).
RANKS = {"C1.5a-cylinder": 7, "C1.5b-cone": 9, "C1.5c-paraboloid": 9, "C1.5d-hyperboloid": 9}
#: Step of the Gauss-Legendre grid (order 6: the examples to ~1e-12).
STEP = 0.01


def surface_task(task: str, params: Params) -> tuple[Quadric, tuple[float, float, float]]:
    """The C1.5 surface with the values of ``a, b, c, p`` and a start point on it."""
    av, bv, cv, pv = (float(params[n]) for n in ("a", "b", "c", "p"))
    num = {a: av, b: bv, c: cv, p: pv}
    F = sp.expand(FORMS[task].subs(num))
    poly = sp.Poly(F, x, y, z)
    coeff = {
        "a11": poly.coeff_monomial(x**2),
        "a22": poly.coeff_monomial(y**2),
        "a33": poly.coeff_monomial(z**2),
        "a34": poly.coeff_monomial(z) / 2,
        "a44": poly.coeff_monomial(1),
    }
    starts = {
        "C1.5a-cylinder": (av, 0.0, 0.0),
        "C1.5b-cone": (av, 0.0, cv),
        "C1.5c-paraboloid": (av, 0.0, 1.0 / (2 * pv)),
        "C1.5d-hyperboloid": (av, 0.0, 0.0),
    }
    label = f"{task.split('-', 1)[1]} {sp.sstr(FORMS[task])} = 0"
    return Quadric.from_coeffs(label=label, **{k: float(v) for k, v in coeff.items()}), starts[task]


class SurfaceAnalyzer(AnalyzerLesson):
    """The analyzer lesson of the C1.5 surface named by ``task`` (start point from the task)."""

    id = "self-study-1"
    problem = "C1.5"

    def surface(self, params: Params) -> Quadric:
        return surface_task(params["task"], params)[0]

    def claims(self) -> list[Claim]:
        return []

    def inner_params(self, params: Params) -> Params:
        """The self-study values mapped onto this lesson's (controls and the task's start)."""
        start = surface_task(params["task"], params)[1]
        values = {n: params[n] for n in ("u1", "u2", "u3")}
        values.update(zip(("x0", "y0", "z0"), start))
        out = self.resolve(values)
        for n in ("task", "a", "b", "c", "p"):
            out[n] = params[n]
        return out


@dataclass
class SurfaceState:
    model: AnalyzerModel
    scale: float
    F0: np.ndarray  # (N,) F at the anchor
    r: np.ndarray  # (m, N, 3)


@dataclass
class SurfaceTrack:
    model: AnalyzerModel
    scale: float
    flow: GridFlow

    def at(self, t: np.ndarray) -> SurfaceState:
        return SurfaceState(self.model, self.scale, self.F0, self.flow.at(t))

    @property
    def F0(self) -> np.ndarray:
        return self.model.F(self.flow.states[0])


def surface_track(
    inner: SurfaceAnalyzer, params: Params, t0: float = 0.0, r0: np.ndarray | None = None
) -> SurfaceTrack:
    """The run of the task's surface from ``r0`` at ``t0`` (the start point at 0 by default)."""
    prep = inner.prepare(inner.inner_params(params))
    start = prep.r0 if r0 is None else r0
    coeffs = lambda ts: prep.model.linear_coeffs(ts, len(start))  # noqa: E731
    return SurfaceTrack(prep.model, prep.quadric.scale, GridFlow(coeffs, start, t0, STEP))


def surface_observe(t: np.ndarray, state: SurfaceState) -> dict[str, np.ndarray]:
    """x, y, z, the velocity, the speed and the drift of F (member 1 only: no family)."""
    v = state.model.velocities(t, state.r)
    out = {c: state.r[:, 0, j] for j, c in enumerate("xyz")}
    out.update({"v" + c: v[:, 0, j] for j, c in enumerate("xyz")})
    out["speed"] = np.linalg.norm(v[:, 0], axis=-1)
    out["drift"] = np.max(np.abs(state.model.F(state.r) - state.F0), axis=1) / state.scale
    return out


def surface_frame(t: float, state: SurfaceState, scalars: dict[str, float]) -> Frame:
    r = state.r[0]
    v = state.model.velocities(np.array([t]), state.r)[0]
    return Frame(
        t=t,
        points={"point": r.copy()},
        vectors={"velocity": (r.copy(), v), "gradient": (r.copy(), state.model.half_gradient(r))},
        scalars=scalars,
    )


def surface_derivation(inner: SurfaceAnalyzer, params: Params) -> list[DerivationStep]:
    task = params["task"]
    ip = inner.inner_params(params)
    prep = inner.prepare(ip)
    Fx, Fy, Fz = (sp.Symbol(f"F_{v}") for v in "xyz")
    rep = analyze(prep.quadric)
    whole = (
        ", and (1.50) is the whole solution set."
        if rep.nullity == 3
        else ", of which (1.50) gives 3."
    )
    controls = tuple(ip[n].expr for n in ("u1", "u2", "u3"))
    numbers = field_expr(prep.model.surface_expr(), controls)
    return [
        DerivationStep(
            "The general analyzer",
            "Three free controls u1, u2, u3 keep the point on any surface F = 0"
            " (the common factor 2 of the gradient dropped).",
            [
                sp.Eq(sp.Symbol("dx/dφ"), (u1 * Fy - u2 * Fz) / 2),
                sp.Eq(sp.Symbol("dy/dφ"), (-u1 * Fx + u3 * Fz) / 2),
                sp.Eq(sp.Symbol("dz/dφ"), (u2 * Fx - u3 * Fy) / 2),
            ],
            "(1.49)-(1.50)",
        ),
        DerivationStep("The surface", "", sp.Eq(sp.Symbol("F"), FORMS[task]), task.split("-")[0]),
        DerivationStep(
            "Its analyzer",
            "(1.50) with these coefficients.",
            [sp.Eq(sp.Symbol(f"d{v}/dφ"), fi) for v, fi in zip("xyz", ANSWERS[task])],
            task.split("-")[0],
            reconstructed="derived, not in source: the source asks for it as an exercise",
        ),
        DerivationStep(
            "With these numbers",
            f"a = {ip['a']:g}, b = {ip['b']:g}, c = {ip['c']:g}, p = {ip['p']:g}; φ = t.",
            [sp.Eq(sp.Symbol(f"d{v}/dt"), sp.expand(fi)) for v, fi in zip("xyz", numbers)],
            "(1.50)",
        ),
        DerivationStep(
            "How many free coefficients",
            f"(1.47) on this surface has rank {rep.rank}: {rep.nullity} free coefficients{whole}",
            None,
            "(1.47)",
        ),
        inner.block_diagram_step(ip, prep),
    ]


def check_answers(resolve) -> ClaimResult:
    """The table's fields are (1.50) of each surface, tangent to it, with the ranks of (1.47)."""
    bad = []
    for task, F in FORMS.items():
        f = field_expr(F)
        if any(sp.simplify(fi - wi) != 0 for fi, wi in zip(f, ANSWERS[task])):
            bad.append(f"{task}: field differs")
        if sp.simplify(sum(sp.diff(F, v) * fi for v, fi in zip((x, y, z), f))) != 0:
            bad.append(f"{task}: not tangent")
    ranks = {t: analyze(surface_task(t, resolve({"task": t}))[0]).rank for t in SURFACE_TASKS}
    return ClaimResult(
        "all match and tangent; ranks 7, 9, 9, 9",
        f"{'; '.join(bad) or 'all match and tangent'}; ranks {list(ranks.values())}",
        not bad and ranks == RANKS,
    )
