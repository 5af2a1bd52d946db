"""Self-study problems C1.1-C1.5 (textbook §1.3, end of chapter 1).

C1.1-C1.4 build the plane analyzer of a curve and run it for the four controls of the
source, (а) u = 1, (б) u = t, (в) u = t², (г) u = sin t (presets ``-a`` ... ``-d``):

* C1.1 the circle x² + z² = R² from x0 = 0, z0 = R:        x' = u z,  z' = -u x;
* C1.2 the parabola y² = 2x from (0, 0):                   x' = u y,  y' = u;
* C1.3 the line from A(0, 0) to B(4, 4):                   x' = 4u,   y' = 4u (B at Θ = 1);
       and the line y = kx + b:                            x' = u,    y' = k u;
* C1.4 the ellipse x²/α + y²/β = 1 from (a, 0), α = a², β = b²: x' = u y/β, y' = -u x/α.
  The printed denominators allow three readings, (i) x²/2 + y² = 1 (the default),
  (ii) x² + y²/2 = 1, (iii) x²/12 + y² = 1; a fourth choice takes
  a and b as given.  The solution is x = a cos(Θ/ab), y = -b sin(Θ/ab);

with Θ(t) = ∫u dt = t, t²/2, t³/3, 1 - cos t.  C1.5 asks for the analyzers of the
cylinder, cone, paraboloid and one-sheet hyperboloid: (1.50) with their coefficients
(:mod:`analyzer_lab.lessons.analyzers.field.self_study_surfaces`).  The answers are derived with the chapter's
method (the source prints none).

Each task's parameters are in the group named after it (``c1_1`` ... ``c1_5``); the
task selector ``task`` and the digital analyzer's ``digital`` are the modes.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.field.self_study_surfaces import (
    SURFACE_TASKS,
    SurfaceAnalyzer,
    SurfaceState,
    check_answers,
    surface_derivation,
    surface_frame,
    surface_observe,
    surface_track,
)
from analyzer_lab.lessons.analyzers.plane.conic import (
    CONIC_NAMES,
    PlanarModel,
    PlanarState,
    conic_expr,
)
from analyzer_lab.lessons.analyzers.plane.lesson import DIGITAL, PLANAR_SERIES, PlanarLesson
from analyzer_lab.lessons.kit.contract import (
    MODE,
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Group,
    Param,
    ParamError,
    Params,
    Preset,
    RunResult,
    SceneSpec,
    Series,
    at_most,
)

PLANAR_TASKS = ("C1.1-circle", "C1.2-parabola", "C1.3-line-AB", "C1.3-line-kx+b", "C1.4-ellipse")
TASKS = (*PLANAR_TASKS, *SURFACE_TASKS)

#: The tasks whose parameters each group holds (the view shows the selected task's).
C1_1 = tuple(t for t in TASKS if t.startswith("C1.1"))
C1_3 = tuple(t for t in TASKS if t.startswith("C1.3"))
C1_4 = tuple(t for t in TASKS if t.startswith("C1.4"))
C1_5 = tuple(t for t in TASKS if t.startswith("C1.5"))
NON_SURFACE = tuple(t for t in TASKS if not t.startswith("C1.5"))
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
#: The readings of the C1.4 ellipse and their semi-axes (a, b); None: a and b as given.
READINGS = {
    "(i) x²/2 + y² = 1": (float(np.sqrt(2.0)), 1.0),
    "(ii) x² + y²/2 = 1": (1.0, float(np.sqrt(2.0))),
    "(iii) x²/12 + y² = 1": (float(np.sqrt(12.0)), 1.0),
    "x²/a² + y²/b² = 1": None,
}
READING_NAMES = tuple(READINGS)


def semi_axes(params: Params) -> tuple[float, float]:
    """The C1.4 ellipse's semi-axes (a, b) in the chosen reading."""
    fixed = READINGS[params["reading"]]
    return fixed if fixed is not None else (float(params["ellipse_a"]), float(params["ellipse_b"]))


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
    a, b = semi_axes(params)
    return {"a11": 1 / a**2, "a22": 1 / b**2, "a33": -1.0}, (a, 0.0), "x²/a² + y²/b² = 1"


def _formula(name: str, default: str, label: str, group: str, help: str = "") -> Param:
    return Param(name, "formula", default, label, min=-20, max=20, step=0.1, group=group, help=help)


def _length(
    name: str,
    default: float,
    label: str,
    group: str,
    when: tuple[str, tuple[str, ...]] | None = None,
) -> Param:
    return Param(name, "float", default, label, min=1e-3, max=1e3, step=0.1, group=group, when=when)


def _presets() -> tuple[Preset, ...]:
    out = []
    for key, (u, _) in CONTROLS.items():
        out += [
            Preset(
                f"C1.1-{key}",
                f"C1.1: circle x² + z² = R², u = {u}",
                {"task": "C1.1-circle", "u": u, "R": 1.0},
                10.0,
                "x0 = 0, z0 = R",
            ),
            Preset(
                f"C1.2-{key}",
                f"C1.2: parabola y² = 2x, u = {u}",
                {"task": "C1.2-parabola", "u": u},
                3.0,
                "x0 = y0 = 0",
            ),
            Preset(
                f"C1.3-{key}",
                f"C1.3: line from A(0, 0) to B(4, 4), u = {u}",
                {"task": "C1.3-line-AB", "u": u},
                T_AT_B[key],
                "the run ends when the point reaches B (Θ = 1)",
            ),
            Preset(
                f"C1.4-{key}",
                f"C1.4: ellipse x²/2 + y² = 1, u = {u}",
                {"task": "C1.4-ellipse", "u": u, "reading": READING_NAMES[0]},
                10.0,
                "reading (i) of the printed denominators, the lab's default; start (√2, 0)",
            ),
        ]
    out.append(
        Preset(
            "C1.3-kx+b",
            "C1.3: the line y = kx + b (k = 0.5, b = 1), u = 1",
            {"task": "C1.3-line-kx+b", "u": "1", "k": 0.5, "b_line": 1.0},
            4.0,
        )
    )
    for name, reading, t_end, note in (
        ("C1.4-ii", READING_NAMES[1], 2 * np.pi * np.sqrt(2.0), "one turn: Θ = 2πab = 2π√2"),
        ("C1.4-iii", READING_NAMES[2], 2 * np.pi * np.sqrt(12.0), "one turn: Θ = 2π√12"),
        ("C1.4-ab", READING_NAMES[3], 4 * np.pi, "a = 2, b = 1: one turn at Θ = 2πab = 4π"),
    ):
        values = {"task": "C1.4-ellipse", "u": "1", "reading": reading}
        if name == "C1.4-ab":
            values.update({"ellipse_a": 2.0, "ellipse_b": 1.0})
        out.append(Preset(name, f"C1.4: ellipse {reading}, u = 1", values, float(t_end), note))
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


class SelfStudy1Lesson(PlanarLesson):
    id = "self-study-1"
    title = "Self-study C1.1-C1.5: analyzers for circles, parabolas, lines, ellipses and quadrics"
    chapter = "1"
    problem = "C1.1-C1.5"
    source = "Textbook §1.3, self-study problems C1.1-C1.5"
    summary = (
        "The chapter's method on the self-study curves and surfaces,"
        " each with its analyzer and a live run."
    )
    order = 1.9
    t_end = 10.0
    groups = (
        MODE,
        Group(
            "controls", "Control u(t) (a)-(d), C1.1-C1.4", change="live", when=("task", NON_SURFACE)
        ),
        Group("c1_1", "C1.1: circle x² + z² = R²", when=("task", C1_1)),
        Group("c1_3", "C1.3: line y = kx + b", when=("task", C1_3)),
        Group("c1_4", "C1.4: ellipse", when=("task", C1_4)),
        Group("c1_5", "C1.5: surfaces and controls", when=("task", C1_5)),
        DIGITAL,
    )
    modes = ("task", "digital")
    own_params = (
        Param("task", "choice", TASKS[0], "task", choices=TASKS, group="mode"),
        _formula("u", "1", "u(t)", "controls", "(а) 1, (б) t, (в) t², (г) sin t"),
        _length("R", 1.0, "R", "c1_1"),
        Param("k", "float", 0.5, "k", min=-1e3, max=1e3, step=0.1, group="c1_3"),
        Param("b_line", "float", 1.0, "b", min=-1e3, max=1e3, step=0.1, group="c1_3"),
        Param(
            "reading",
            "choice",
            READING_NAMES[0],
            "reading of the printed ellipse",
            choices=READING_NAMES,
            group="c1_4",
            help="the printed denominators allow (i), (ii) or (iii); the last choice uses a and b",
        ),
        _length("ellipse_a", 2.0, "a (semi-axis along x)", "c1_4"),
        _length("ellipse_b", 1.0, "b (semi-axis along y)", "c1_4"),
        _length("a", 1.0, "a", "c1_5"),
        _length("b", 1.0, "b", "c1_5"),
        _length("c", 1.0, "c", "c1_5", when=("task", ("C1.5b-cone", "C1.5d-hyperboloid"))),
        _length("p", 0.5, "p", "c1_5", when=("task", ("C1.5c-paraboloid",))),
        _formula("u1", "1", "u1(t)", "c1_5"),
        _formula("u2", "0.3", "u2(t)", "c1_5"),
        _formula("u3", "0.2", "u3(t)", "c1_5"),
    )
    presets = _presets()

    def __init__(self) -> None:
        self._surf = SurfaceAnalyzer()

    @staticmethod
    def on_surface(params: Params) -> bool:
        return params["task"] in SURFACE_TASKS

    def plane_of(self, params: Params) -> str:
        return "xz" if params["task"] == "C1.1-circle" else "xy"

    def planar_model(self, params: Params) -> tuple[PlanarModel, np.ndarray]:
        coeffs, start, _ = planar_task(params["task"], params)
        return PlanarModel.of(coeffs, params["u"]), np.array([start], dtype=float)

    def validate(self, params: Params) -> None:
        for name in ("u", "u1", "u2", "u3"):
            try:
                params[name].check_finite(np.linspace(0.0, self.t_end * 10, 2001))
            except ValueError as exc:
                raise ParamError(name, str(exc)) from None

    def series_for(self, params: Params) -> tuple[Series, ...]:
        return PLANAR_SERIES if self.on_surface(params) else super().series_for(params)

    # -- the run: the plane tasks by the base, the C1.5 surfaces by their own track ---

    def track(self, params: Params):
        return (
            surface_track(self._surf, params) if self.on_surface(params) else super().track(params)
        )

    def continue_track(self, old: Params, params: Params, t: float, state):
        if old["task"] != params["task"]:
            return None
        if self.on_surface(params):
            return surface_track(self._surf, params, t, state.r[0])
        return super().continue_track(old, params, t, state)

    def observe(self, params: Params, t: np.ndarray, state: PlanarState | SurfaceState):
        if self.on_surface(params):
            return surface_observe(t, state)
        return super().observe(params, t, state)

    def make_frame(self, params: Params, t: float, state: PlanarState | SurfaceState) -> Frame:
        if self.on_surface(params):
            return surface_frame(t, state, self.frame_scalars(params, t, state))
        return super().make_frame(params, t, state)

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        if not self.on_surface(params):
            return super().simulate(params, t_end)
        t = self.sample_grid(self.t_end if t_end is None else float(t_end))
        state = self.track(params).at(t)
        drift = surface_observe(t, state)["drift"]
        return self.result(params, t, state, {"invariant_drift_rel": float(drift.max())})

    def scene(self, params: Params) -> SceneSpec:
        if self.on_surface(params):
            return self._surf.scene(self._surf.inner_params(params))
        return super().scene(params)

    # -- the page -----------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        if self.on_surface(params):
            return surface_derivation(self._surf, params)
        task = params["task"]
        coeffs, _, eq = planar_task(task, params)
        prepared = self.prepare(params)
        names = self.axis_names(params)
        s1, s2 = sp.symbols(names, real=True)
        cf = {n: sp.nsimplify(coeffs.get(n, 0.0), rational=True) for n in CONIC_NAMES}
        u, t, tau = sp.Symbol("u"), sp.Symbol("t"), sp.Symbol("τ")
        steps = [
            DerivationStep("The curve", eq, sp.Eq(conic_expr(cf, s1, s2), 0), task.split("-")[0]),
            DerivationStep(
                "Its analyzer",
                f"The conic analyzer (1.30) with ω replaced by the control u, as in (1.40):"
                f" d{names[0]}/dt = u F_{names[1]}/2, d{names[1]}/dt = -u F_{names[0]}/2.",
                prepared.model.equations(u, names),
                task.split("-")[0],
                reconstructed="derived, not in source: the source asks for it as an exercise",
            ),
            DerivationStep(
                "The run",
                f"u(t) = {params['u']}; the motion depends on u only through Θ, the integral"
                " of u from 0 to τ.",
                sp.Eq(
                    sp.Symbol("Θ"),
                    sp.Integral(params["u"].expr.subs(sp.Symbol("t", real=True), t), (t, 0, tau)),
                ),
                "C1.1-C1.4 (а)-(г)",
            ),
        ]
        return [
            *self.general_derivation(params),
            *steps,
            self.block_diagram_step(params, prepared),
            *self.digital_derivation(params),
        ]

    def block_diagram(self, params: Params, prepared=None):
        """The task's analyzer block diagram (Fig. 1.5 notation)."""
        if self.on_surface(params):
            return self._surf.block_diagram(self._surf.inner_params(params))
        return super().block_diagram(params, prepared)

    # -- claims -------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        readings = [
            Claim(
                f"C1.4-{key}",
                f"C1.4, reading {name}: x' = u y/β, y' = -u x/α with α = {alpha}, β = {beta};"
                f" from ({start}, 0) the point follows x = a cos(Θ/ab), y = -b sin(Θ/ab)"
                f" (to 1e-9) and is back at the start after Θ = 2πab = {period}",
                "C1.4",
                lambda key=key: self._claim_reading(f"C1.4-{key}"),
            )
            for key, name, alpha, beta, start, period in (
                ("ii", READING_NAMES[1], "1", "2", "1", "8.886"),
                ("iii", READING_NAMES[2], "12", "1", "√12", "21.77"),
                ("ab", "x²/a² + y²/b² = 1, a = 2, b = 1", "4", "1", "2", "12.57"),
            )
        ]
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
                "C1.3: the point runs from A(0, 0) along the line and reaches B(4, 4) at Θ = 1"
                " for every control; y = kx + b is kept",
                "C1.3",
                self._claim_c13,
            ),
            Claim(
                "C1.4",
                "C1.4, reading (i): x' = u y, y' = -u x/2; x = √2 cos(Θ/√2), y = -sin(Θ/√2)"
                " on x²/2 + y² = 1 for the four controls (to 1e-9)",
                "C1.4",
                self._claim_c14,
            ),
            *readings,
            Claim(
                "C1.5",
                "C1.5: the analyzers of the cylinder, cone, paraboloid and hyperboloid are"
                " tangent (∇F·v ≡ 0) and match the table of lessons/analyzers/field/self_study_surfaces.py;"
                " (1.47) has rank 7 on the cylinder, 9 on the others",
                "C1.5, (1.47), (1.50)",
                lambda: check_answers(self.resolve),
            ),
        ]

    def _worst(self, prefix: str, exact) -> float:
        """Largest distance of the runs ``prefix-a .. -d`` from ``exact(Θ) -> (first, second)``."""
        worst = 0.0
        for key, (_, Th) in CONTROLS.items():
            res = self.run(f"{prefix}-{key}")
            names = self.axis_names(self.resolve(preset=f"{prefix}-{key}"))
            for got, want in zip((res.series[n] for n in names), exact(Th(res.t))):
                worst = max(worst, float(np.max(np.abs(got - want))))
        return worst

    def _claim_c11(self) -> ClaimResult:
        worst = self._worst("C1.1", lambda th: (np.sin(th), np.cos(th)))
        return at_most(1e-9, worst, "max error against R sin Θ, R cos Θ ")

    def _claim_c12(self) -> ClaimResult:
        worst = self._worst("C1.2", lambda th: (th**2 / 2, th))
        return at_most(1e-9, worst, "max error against y = Θ, x = Θ²/2 ")

    def _claim_c13(self) -> ClaimResult:
        worst = 0.0
        for key in CONTROLS:
            res = self.run(f"C1.3-{key}")
            x, y = res.series["x"], res.series["y"]
            worst = max(
                worst, float(np.hypot(x[-1] - B[0], y[-1] - B[1])), float(np.max(np.abs(y - x)))
            )
        res = self.run("C1.3-kx+b")
        x, y = res.series["x"], res.series["y"]
        worst = max(worst, float(np.max(np.abs(y - (0.5 * x + 1.0)))), abs(float(x[-1]) - 4.0))
        return at_most(1e-9, worst, "max |r(end) - B|, distance from the lines ")

    def _claim_c14(self) -> ClaimResult:
        r2 = np.sqrt(2.0)
        worst = self._worst("C1.4", lambda th: (r2 * np.cos(th / r2), -np.sin(th / r2)))
        return at_most(1e-9, worst, "max error against the closed form ")

    def _claim_reading(self, preset: str) -> ClaimResult:
        params = self.resolve(preset=preset)
        a, b = semi_axes(params)
        u, x, y = sp.symbols("u x y", real=True)
        want = [u * y / sp.nsimplify(b**2), -u * x / sp.nsimplify(a**2)]
        rhs = [
            sp.nsimplify(e.rhs, tolerance=1e-12) for e in self.prepare(params).model.equations(u)
        ]
        res = self.run(preset)
        th = res.t / (a * b)  # u = 1: Θ = t
        worst = max(
            float(np.max(np.abs(res.series["x"] - a * np.cos(th)))),
            float(np.max(np.abs(res.series["y"] + b * np.sin(th)))),
            float(np.hypot(res.series["x"][-1] - a, res.series["y"][-1])),
        )
        ok = all(sp.simplify(g - w) == 0 for g, w in zip(rhs, want)) and worst <= 1e-9
        return ClaimResult(
            f"x' = {want[0]}, y' = {want[1]}; error <= 1e-09",
            f"x' = {rhs[0]}, y' = {rhs[1]}; error {worst:.3g}",
            ok,
        )


LESSON = SelfStudy1Lesson()
