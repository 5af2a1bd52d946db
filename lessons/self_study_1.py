"""Self-study problems C1.1-C1.5 (textbook §1.3, end of chapter 1).

C1.1-C1.4 build the plane analyzer of a curve and run it for the four controls of the
source, (а) u = 1, (б) u = t, (в) u = t², (г) u = sin t (presets ``-a`` ... ``-d``):

* C1.1 the circle x² + z² = R² from x0 = 0, z0 = R:        x' = u z,  z' = -u x;
* C1.2 the parabola y² = 2x from (0, 0):                   x' = u y,  y' = u;
* C1.3 the line from A(0, 0) to B(4, 4):                   x' = 4u,   y' = 4u (B at Θ = 1);
       and the line y = kx + b:                            x' = u,    y' = k u;
* C1.4 the ellipse x²/2 + y² = 1 (DESIGN.md §3.6):          x' = u y,  y' = -u x/2;

with Θ(t) = ∫u dt = t, t²/2, t³/3, 1 - cos t.  C1.5 asks for the analyzers of the
cylinder, cone, paraboloid and one-sheet hyperboloid: (1.50) with their coefficients.
The answers are derived with the chapter's method (the source prints none).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from lessons.core.analyzer import field_expr
from lessons.core.analyzer_lesson import AnalyzerLesson
from lessons.core.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Lesson,
    Param,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Stepper,
    at_most,
)
from lessons.core.planar import PlanarModel
from lessons.core.planar_lesson import DIGITAL_PARAMS, PlanarLesson
from lessons.core.quadric import Quadric
from lessons.core.tangent_fields import analyze

PLANAR_TASKS = ("C1.1-circle", "C1.2-parabola", "C1.3-line-AB", "C1.3-line-kx+b", "C1.4-ellipse")
SURFACE_TASKS = ("C1.5a-cylinder", "C1.5b-cone", "C1.5c-paraboloid", "C1.5d-hyperboloid")
TASKS = (*PLANAR_TASKS, *SURFACE_TASKS)
#: The source's control options (а)-(г) and Θ(t) = ∫0^t u.
CONTROLS = {
    "a": ("1", lambda t: t),
    "b": ("t", lambda t: t**2 / 2),
    "c": ("t^2", lambda t: t**3 / 3),
    "d": ("sin(t)", lambda t: 1 - np.cos(t)),
}
#: The time at which Θ = 1 (the line reaches B) for each control.
T_AT_B = {"a": 1.0, "b": float(np.sqrt(2.0)), "c": float(3.0 ** (1 / 3)), "d": float(np.pi / 2)}

A, B = (0.0, 0.0), (4.0, 4.0)


def _sym(v: float) -> sp.Expr:
    return sp.nsimplify(v, rational=True)


def planar_task(task: str, params: Params) -> tuple[dict[str, float], tuple[float, float], str]:
    """Conic coefficients (2-D indexing), start point and the curve's equation text."""
    if task == "C1.1-circle":
        R = float(params["R"])
        return {"a11": 1.0, "a22": 1.0, "a33": -R * R}, (0.0, R), "x² + z² = R²"
    if task == "C1.2-parabola":
        return {"a22": 1.0, "a13": -1.0}, (0.0, 0.0), "y² = 2x"
    if task == "C1.3-line-AB":
        # F = 2(xB - xA)(y - yA) - 2(yB - yA)(x - xA): half gradient (-(yB - yA), xB - xA)
        return (
            {"a13": -(B[1] - A[1]), "a23": B[0] - A[0]},
            A,
            "(y - yA)/(yB - yA) = (x - xA)/(xB - xA)",
        )
    if task == "C1.3-line-kx+b":
        k, b = float(params["k"]), float(params["b_line"])
        return {"a13": -k, "a23": 1.0, "a33": -2 * b}, (0.0, b), "y = kx + b"
    if task == "C1.4-ellipse":
        return {"a11": 0.5, "a22": 1.0, "a33": -1.0}, (float(np.sqrt(2.0)), 0.0), "x²/2 + y² = 1"
    raise KeyError(task)


def surface_task(task: str, params: Params) -> tuple[Quadric, tuple[float, float, float]]:
    """The C1.5 surface in the source's form and a start point on it."""
    a, b, c, p = (float(params[n]) for n in ("a", "b", "c", "p"))
    if task == "C1.5a-cylinder":
        return Quadric.from_coeffs(
            label="cylinder x²/a² + y²/b² - 1 = 0", a11=1 / a**2, a22=1 / b**2, a44=-1.0
        ), (a, 0.0, 0.0)
    if task == "C1.5b-cone":
        return Quadric.from_coeffs(
            label="cone x²/a² + y²/b² - z²/c² = 0", a11=1 / a**2, a22=1 / b**2, a33=-1 / c**2
        ), (a, 0.0, c)
    if task == "C1.5c-paraboloid":
        return Quadric.from_coeffs(
            label="paraboloid x²/a² + y²/b² - 2pz = 0", a11=1 / a**2, a22=1 / b**2, a34=-p
        ), (a, 0.0, 1.0 / (2 * p))
    if task == "C1.5d-hyperboloid":
        return Quadric.from_coeffs(
            label="hyperboloid x²/a² + y²/b² - z²/c² - 1 = 0",
            a11=1 / a**2,
            a22=1 / b**2,
            a33=-1 / c**2,
            a44=-1.0,
        ), (a, 0.0, 0.0)
    raise KeyError(task)


class _PlanarTask(PlanarLesson):
    """The plane tasks; the outer lesson passes its own parameters through."""

    own_params = ()

    def planar_model(self, params: Params) -> tuple[PlanarModel, np.ndarray, list[str]]:
        coeffs, start, _ = planar_task(params["task"], params)
        return PlanarModel.of(coeffs, params["u"]), np.array([start], dtype=float), []

    def derivation(
        self, params: Params
    ) -> list[DerivationStep]:  # pragma: no cover - the outer lesson builds it
        return []

    def claims(self) -> list[Claim]:
        return []


class _PlanarTaskXY(_PlanarTask):
    id = "self-study-1"
    plane = "xy"


class _PlanarTaskXZ(_PlanarTask):
    id = "self-study-1"
    plane = "xz"


class _SurfaceTask(AnalyzerLesson):
    id = "self-study-1"

    def surface(self, params: Params) -> Quadric:
        return surface_task(params["task"], params)[0]

    def claims(self) -> list[Claim]:
        return []


def _with_task(inner: AnalyzerLesson, params: Params) -> Params:
    """The outer parameters mapped onto the analyzer lesson's (start point from the task)."""
    _, start = surface_task(params["task"], params)
    vals = {
        "u1": params["u1"],
        "u2": params["u2"],
        "u3": params["u3"],
        "x0": start[0],
        "y0": start[1],
        "z0": start[2],
        "h": params["h"],
    }
    out = inner.resolve(vals)
    for n in ("task", "a", "b", "c", "p"):
        out[n] = params[n]
    return out


def _presets() -> tuple[Preset, ...]:
    out = []
    for key, (u, _) in CONTROLS.items():
        out.append(
            Preset(
                f"C1.1-{key}",
                f"C1.1: circle x² + z² = R², u = {u}",
                {"task": "C1.1-circle", "u": u, "R": 1.0},
                10.0,
                "x0 = 0, z0 = R",
            )
        )
    for key, (u, _) in CONTROLS.items():
        out.append(
            Preset(
                f"C1.2-{key}",
                f"C1.2: parabola y² = 2x, u = {u}",
                {"task": "C1.2-parabola", "u": u},
                3.0,
                "x0 = y0 = 0",
            )
        )
    for key, (u, _) in CONTROLS.items():
        out.append(
            Preset(
                f"C1.3-{key}",
                f"C1.3: line from A(0, 0) to B(4, 4), u = {u}",
                {"task": "C1.3-line-AB", "u": u},
                T_AT_B[key],
                "the run ends when the point reaches B (Θ = 1)",
            )
        )
    out.append(
        Preset(
            "C1.3-kx+b",
            "C1.3: the line y = kx + b (k = 0.5, b = 1), u = 1",
            {"task": "C1.3-line-kx+b", "u": "1", "k": 0.5, "b_line": 1.0},
            4.0,
            "",
        )
    )
    for key, (u, _) in CONTROLS.items():
        out.append(
            Preset(
                f"C1.4-{key}",
                f"C1.4: ellipse x²/2 + y² = 1, u = {u}",
                {"task": "C1.4-ellipse", "u": u},
                10.0,
                "reading (i) of the source's ellipse (DESIGN §3.6); start (√2, 0)",
            )
        )
    for task in SURFACE_TASKS:
        out.append(
            Preset(
                task,
                f"C1.5: {task.split('-', 1)[1]}, constant controls",
                {"task": task, "u1": "1", "u2": "0.3", "u3": "0.2"},
                4.0 if task in ("C1.5b-cone", "C1.5d-hyperboloid") else 10.0,
                "a = b = c = 1, p = 0.5",
            )
        )
    return tuple(out)


class SelfStudy1Lesson(Lesson):
    id = "self-study-1"
    title = "Self-study C1.1-C1.5: analyzers for circles, parabolas, lines, ellipses and quadrics"
    chapter = "1"
    problem = "C1.1-C1.5"
    source = "Textbook §1.3, self-study problems C1.1-C1.5"
    summary = "The chapter's method on the self-study curves and surfaces, each with its analyzer and a live run."
    order = 1.9
    t_end = 10.0
    params = (
        Param("task", "choice", TASKS[0], "task", choices=TASKS, group="surface"),
        Param(
            "u",
            "formula",
            "1",
            "u(t) (C1.1-C1.4)",
            min=-20,
            max=20,
            step=0.1,
            group="controls",
            help="(а) 1, (б) t, (в) t², (г) sin t",
        ),
        Param("R", "float", 1.0, "R (C1.1)", min=1e-3, max=1e3, step=0.1, group="surface"),
        Param("k", "float", 0.5, "k (y = kx + b)", min=-1e3, max=1e3, step=0.1, group="surface"),
        Param(
            "b_line", "float", 1.0, "b (y = kx + b)", min=-1e3, max=1e3, step=0.1, group="surface"
        ),
        Param("a", "float", 1.0, "a (C1.5)", min=1e-3, max=1e3, step=0.1, group="surface"),
        Param("b", "float", 1.0, "b (C1.5)", min=1e-3, max=1e3, step=0.1, group="surface"),
        Param("c", "float", 1.0, "c (C1.5)", min=1e-3, max=1e3, step=0.1, group="surface"),
        Param(
            "p", "float", 0.5, "p (C1.5 paraboloid)", min=1e-3, max=1e3, step=0.1, group="surface"
        ),
        Param("u1", "formula", "1", "u1(t) (C1.5)", min=-20, max=20, step=0.1, group="controls"),
        Param("u2", "formula", "0.3", "u2(t) (C1.5)", min=-20, max=20, step=0.1, group="controls"),
        Param("u3", "formula", "0.2", "u3(t) (C1.5)", min=-20, max=20, step=0.1, group="controls"),
        *DIGITAL_PARAMS,
    )
    presets = _presets()
    plots = (
        PlotSpec("velocity components", ("vx", "vy", "vz")),
        PlotSpec("invariant drift |F - F0| / scale", ("drift",)),
        PlotSpec("digital analyzer: distance from the continuous path", ("dda_error",)),
    )

    def __init__(self) -> None:
        self._xy, self._xz, self._surf = _PlanarTaskXY(), _PlanarTaskXZ(), _SurfaceTask()

    def _inner(self, params: Params) -> tuple[Lesson, Params]:
        task = params["task"]
        if task in SURFACE_TASKS:
            return self._surf, _with_task(self._surf, params)
        return (self._xz if task == "C1.1-circle" else self._xy), params

    def validate(self, params: Params) -> None:
        for name in ("u", "u1", "u2", "u3"):
            try:
                params[name].check_finite(np.linspace(0.0, self.t_end * 10, 2001))
            except ValueError as exc:
                from lessons.core.contract import ParamError

                raise ParamError(name, str(exc)) from None

    # -- the page -----------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        task = params["task"]
        inner, ip = self._inner(params)
        if task in SURFACE_TASKS:
            q, start = surface_task(task, params)
            a, b, c, p = sp.symbols("a b c p", positive=True)
            x, y, z = sp.symbols("x y z", real=True)
            forms = {
                "C1.5a-cylinder": x**2 / a**2 + y**2 / b**2 - 1,
                "C1.5b-cone": x**2 / a**2 + y**2 / b**2 - z**2 / c**2,
                "C1.5c-paraboloid": x**2 / a**2 + y**2 / b**2 - 2 * p * z,
                "C1.5d-hyperboloid": x**2 / a**2 + y**2 / b**2 - z**2 / c**2 - 1,
            }
            F = forms[task]
            f = field_expr(F)
            rep = analyze(q)
            steps = [
                DerivationStep("The surface", "", sp.Eq(sp.Symbol("F"), F), task.split("-")[0]),
                DerivationStep(
                    "Its analyzer",
                    "(1.50) with these coefficients (the factor 2 of the gradient dropped).",
                    [sp.Eq(sp.Symbol(f"d{v}/dφ"), sp.simplify(fi)) for v, fi in zip("xyz", f)],
                    task.split("-")[0],
                    reconstructed="derived, not in source: the source asks for it as an exercise",
                ),
                DerivationStep(
                    "How many free coefficients",
                    f"(1.47) on this surface has rank {rep.rank}: {rep.nullity} free coefficients"
                    + (
                        ", of which (1.50) gives 3."
                        if rep.nullity != 3
                        else ", and (1.50) is the whole solution set."
                    ),
                    None,
                    "(1.47)",
                ),
            ]
            return [
                *inner.derivation(ip)[:4],
                *steps,
                inner.block_diagram_step(ip, inner.prepare(ip)),
            ]
        coeffs, start, eq = planar_task(task, params)
        model = PlanarModel.of(coeffs, params["u"])
        names = ("x", "z") if task == "C1.1-circle" else ("x", "y")
        s1, s2 = sp.symbols(names, real=True)
        cf = {n: _sym(coeffs.get(n, 0.0)) for n in ("a11", "a12", "a22", "a13", "a23", "a33")}
        Fexpr = (
            cf["a11"] * s1**2
            + 2 * cf["a12"] * s1 * s2
            + cf["a22"] * s2**2
            + 2 * cf["a13"] * s1
            + 2 * cf["a23"] * s2
            + cf["a33"]
        )
        u = sp.Symbol("u")
        t = sp.Symbol("t")
        theta = sp.Symbol("Θ")
        steps = [
            DerivationStep("The curve", eq, sp.Eq(Fexpr, 0), task.split("-")[0]),
            DerivationStep(
                "Its analyzer",
                "The conic analyzer (1.30) with ω replaced by the control u (as in (1.40)): x' = u F_2/2, second' = -u F_1/2.",
                model.equations(u, names),
                task.split("-")[0],
                reconstructed="derived, not in source: the source asks for it as an exercise",
            ),
            DerivationStep(
                "The run",
                f"u(t) = {params['u']}; the motion depends on u only through Θ(t) = ∫0^t u dt.",
                sp.Eq(
                    theta,
                    sp.Integral(
                        params["u"].expr.subs(sp.Symbol("t", real=True), t), (t, 0, sp.Symbol("τ"))
                    ),
                ),
                "C1.1-C1.4 (а)-(г)",
            ),
        ]
        return [
            *inner.general_derivation(ip),
            *steps,
            inner.block_diagram_step(ip, inner.prepare(ip)),
            *inner.digital_derivation(ip),
        ]

    def block_diagram(self, params: Params):
        """The task's analyzer block diagram (Fig. 1.5 notation)."""
        inner, ip = self._inner(params)
        return inner.block_diagram(ip)

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        inner, ip = self._inner(params)
        res = inner.simulate(ip, t_end)
        res.lesson, res.params = self.id, params.raw()
        return res

    def stepper(self, params: Params) -> Stepper:
        inner, ip = self._inner(params)
        return _TaskStepper(self, inner.stepper(ip), params["task"])

    def scene(self, params: Params) -> SceneSpec:
        inner, ip = self._inner(params)
        return inner.scene(ip)

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "C1.1",
                "C1.1: x = R sin Θ, z = R cos Θ for u = 1, t, t², sin t (to 1e-9)",
                "C1.1",
                self._claim_c11,
            ),
            Claim(
                "C1.2",
                "C1.2: y = Θ, x = Θ²/2 on y² = 2x for the four controls (to 1e-9)",
                "C1.2",
                self._claim_c12,
            ),
            Claim(
                "C1.3",
                "C1.3: the point runs from A(0, 0) along the line and reaches B(4, 4) at Θ = 1 for every control; y = kx + b is kept",
                "C1.3",
                self._claim_c13,
            ),
            Claim(
                "C1.4",
                "C1.4: x = √2 cos(Θ/√2), y = -sin(Θ/√2) on x²/2 + y² = 1 (to 1e-9)",
                "C1.4, DESIGN §3.6",
                self._claim_c14,
            ),
            Claim(
                "C1.5",
                "C1.5: the analyzers of the cylinder, cone, paraboloid and hyperboloid are tangent (∇F·v ≡ 0) and match the digest's table; the cylinder's (1.47) has rank 7",
                "C1.5; digest B8",
                self._claim_c15,
            ),
        ]

    def _track(self, preset: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        res = self.run(preset)
        return res.t, res.series["x"], res.series["y"], res.series["z"]

    def _claim_c11(self) -> ClaimResult:
        worst = 0.0
        for key, (_, Th) in CONTROLS.items():
            t, x, _, z = self._track(f"C1.1-{key}")
            worst = max(
                worst,
                float(np.max(np.abs(x - np.sin(Th(t))))),
                float(np.max(np.abs(z - np.cos(Th(t))))),
            )
        return at_most(1e-9, worst, "max error against R sin Θ, R cos Θ ")

    def _claim_c12(self) -> ClaimResult:
        worst = 0.0
        for key, (_, Th) in CONTROLS.items():
            t, x, y, _ = self._track(f"C1.2-{key}")
            worst = max(
                worst,
                float(np.max(np.abs(y - Th(t)))),
                float(np.max(np.abs(x - Th(t) ** 2 / 2))) / max(1.0, float(np.max(Th(t) ** 2 / 2))),
            )
        return at_most(1e-9, worst, "max error against y = Θ, x = Θ²/2 ")

    def _claim_c13(self) -> ClaimResult:
        worst = 0.0
        for key in CONTROLS:
            t, x, y, _ = self._track(f"C1.3-{key}")
            worst = max(
                worst, float(np.hypot(x[-1] - B[0], y[-1] - B[1])), float(np.max(np.abs(y - x)))
            )
        t, x, y, _ = self._track("C1.3-kx+b")
        worst = max(worst, float(np.max(np.abs(y - (0.5 * x + 1.0)))), abs(float(x[-1]) - 4.0))
        return at_most(1e-9, worst, "max |r(end) - B|, distance from the lines ")

    def _claim_c14(self) -> ClaimResult:
        worst = 0.0
        for key, (_, Th) in CONTROLS.items():
            t, x, y, _ = self._track(f"C1.4-{key}")
            th = Th(t) / np.sqrt(2.0)
            worst = max(
                worst,
                float(np.max(np.abs(x - np.sqrt(2.0) * np.cos(th)))),
                float(np.max(np.abs(y + np.sin(th)))),
            )
        return at_most(1e-9, worst, "max error against the closed form ")

    def _claim_c15(self) -> ClaimResult:
        a, b, c, p = sp.symbols("a b c p", positive=True)
        x, y, z = sp.symbols("x y z", real=True)
        u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
        cone = (
            u1 * y / b**2 + u2 * z / c**2,
            -u1 * x / a**2 - u3 * z / c**2,
            u2 * x / a**2 - u3 * y / b**2,
        )
        table = {
            "cylinder": (
                x**2 / a**2 + y**2 / b**2 - 1,
                (u1 * y / b**2, -u1 * x / a**2, u2 * x / a**2 - u3 * y / b**2),
            ),
            "cone": (x**2 / a**2 + y**2 / b**2 - z**2 / c**2, cone),
            "paraboloid": (
                x**2 / a**2 + y**2 / b**2 - 2 * p * z,
                (u1 * y / b**2 + p * u2, -u1 * x / a**2 - p * u3, u2 * x / a**2 - u3 * y / b**2),
            ),
            "hyperboloid": (x**2 / a**2 + y**2 / b**2 - z**2 / c**2 - 1, cone),
        }
        bad = []
        for name, (F, want) in table.items():
            f = field_expr(F)
            if any(sp.simplify(fi - wi) != 0 for fi, wi in zip(f, want)):
                bad.append(f"{name}: field differs")
            if sp.simplify(sum(sp.diff(F, v) * fi for v, fi in zip((x, y, z), f))) != 0:
                bad.append(f"{name}: not tangent")
        ranks = {
            t: analyze(surface_task(t, self.resolve({"task": t}))[0]).rank for t in SURFACE_TASKS
        }
        ok = not bad and ranks == {
            "C1.5a-cylinder": 7,
            "C1.5b-cone": 9,
            "C1.5c-paraboloid": 9,
            "C1.5d-hyperboloid": 9,
        }
        return ClaimResult(
            "all match and tangent; ranks 7, 9, 9, 9",
            f"{'; '.join(bad) or 'all match and tangent'}; ranks {list(ranks.values())}",
            ok,
        )


class _TaskStepper(Stepper):
    """Wraps the task's stepper; a change of task starts the new task's stepper."""

    def __init__(self, lesson: SelfStudy1Lesson, inner: Stepper, task: str) -> None:
        self.lesson, self.inner, self.task = lesson, inner, task

    @property
    def t(self) -> float:
        return self.inner.t

    def frame(self):
        return self.inner.frame()

    def advance(self, dt: float):
        return self.inner.advance(dt)

    def set_params(self, params: Params) -> None:
        inner, ip = self.lesson._inner(params)
        if params["task"] != self.task:
            self.inner = inner.stepper(ip)
        else:
            self.inner.set_params(ip)
        self.task = params["task"]

    def reset(self):
        return self.inner.reset()


LESSON = SelfStudy1Lesson()
