"""Principle of building a motion program: textbook §1.1, eqs (1.1)-(1.15)
(= the motion-program journal article, (1)-(15)).

A space curve l is typed as x = f1(phi), y = f2(phi), z = f3(phi), phi in [phi0, phi1]
(1.1).  It is reparametrized by arc length (1.12), (1.13), (1.6), then by time with the
speed-limit law v(t) (1.7): a trapezoid (1.8) or, when L <= 0, the minimum-time
triangle (1.9).  The result is the time law X(t), Y(t), Z(t) (1.10), (1.11).  The
controls of the linear system (1.5) are the rank-one matrix (1.15)

    u_ij(t) = Xdot_i(t) X_j(t) / D(t),    D = X^2 + Y^2 + Z^2 != 0   (1.14),

so that U(t) X(t) = Xdot(t): the curve is a phase curve of (1.5).  (1.5) is solved with
these u_ij once per parameter set (classical RK4, dense output:
:mod:`analyzer_lab.lessons.analyzers.curves.motion_law`) and compared with X(t).  Where
the curve passes through the origin (1.15) divides by zero and (1.5) cannot reach or
leave the origin: its solution is left undefined in a short window and restarts from the
curve, and the run says so.  The source's example, a helix typed three ways (1.2)-(1.4),
and the claims checked on it are :mod:`analyzer_lab.lessons.analyzers.curves.helix`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.curves.helix import HELIX_12, HELIX_13, HELIX_14, helix_claims
from analyzer_lab.lessons.analyzers.curves.motion_law import (
    STEP_ANGLE,
    Program,
    ProgramStepper,
    motion_program,
)
from analyzer_lab.lessons.analyzers.curves.profiles import PROFILE_CHOICES, triangle_symbolic
from analyzer_lab.lessons.analyzers.curves.space_curve import PHI, CurveFormulaParam
from analyzer_lab.lessons.kit.contract import (
    Claim,
    CurveItem,
    DerivationStep,
    Group,
    Lesson,
    MarkerItem,
    Note,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Series,
    Stepper,
)
from analyzer_lab.lessons.kit.formula import parse_formula

#: at most this many samples in a run (the sampling step grows for a long motion)
MAX_SAMPLES = 4000

# ------------------------------------------------------------------ presets

PRESETS = tuple(
    Preset(
        name,
        title,
        {
            **dict(zip(("x", "y", "z", "phi0", "phi1"), curve)),
            **dict(zip(("v0", "Delta0", "Delta1"), law)),
        },
        t_end=t_end,
        note=note,
    )
    for name, title, curve, law, t_end, note in (
        (
            "helix-1.2",
            "Helix half-turn (1.2): x = sin phi, y = cos phi, z = phi",
            HELIX_12,
            (1.0, 1.0, 1.0),
            6.0,
            "The source gives no speed-profile numbers; v0 = 1, Delta0 = Delta1 = 1 are"
            " illustrative (trapezoid, T = 5.443).",
        ),
        (
            "helix-1.3",
            "Same helix, form (1.3): x = 2 sin phi cos phi, y = 2 cos^2 phi - 1, z = 2 phi",
            HELIX_13,
            (1.0, 1.0, 1.0),
            6.0,
            "(1.3)(phi) = (1.2)(2 phi): the same point set and the same motion.",
        ),
        (
            "helix-1.4",
            "Same helix, form (1.4): x = sqrt(1 - phi^2), y = phi, z = arccos phi",
            HELIX_14,
            (1.0, 1.0, 1.0),
            6.0,
            "(1.4)(phi) = (1.2)(arccos phi): same point set, run in the opposite direction;"
            " |r'|^2 = 2/(1 - phi^2) is singular (integrably) at both ends.",
        ),
        (
            "helix-triangle",
            "Helix (1.2) with a short-curve speed law: triangle (1.9)",
            HELIX_12,
            (4.0, 2.0, 2.0),
            3.5,
            "L = -3.557 < 0: minimum-time triangle, t1 = 1.4905, tau = v1 = 2.9809"
            " (illustrative numbers).",
        ),
        (
            "circle",
            "Circle of radius 2 in the plane z = 1",
            ("2*cos(phi)", "2*sin(phi)", "1", "0", "2*pi"),
            (2.0, 1.0, 1.0),
            8.0,
            "",
        ),
        (
            "spiral",
            "Conical spiral, two turns",
            ("(1 + phi/5)*cos(phi)", "(1 + phi/5)*sin(phi)", "phi/10", "0", "4*pi"),
            (2.0, 1.0, 1.0),
            16.0,
            "",
        ),
        (
            "line",
            "Straight segment from (1, 2, 0) to (3, 0, 1)",
            ("1 + phi", "2 - phi", "phi/2", "0", "2"),
            (1.0, 0.5, 0.5),
            4.0,
            "",
        ),
        (
            "line-through-origin",
            "Segment through the origin: (1.14) fails, (1.15) divides by zero",
            ("phi", "phi", "phi", "-1", "1"),
            (1.0, 0.5, 0.5),
            4.5,
            "X(t) passes through 0 at t = 1.982: no phase curve of (1.5) can pass the origin.",
        ),
    )
)

#: Where the analyzer's quantities are undefined: (1.15) divides by D = |X|^2.
AT_ORIGIN = "where X(t) passes the origin: the controls (1.15) divide by D = 0"
U_NAMES = tuple(f"u{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3))


def program_of(params: Params) -> Program:
    """The program of these values (cached); a bad value raises ParamError naming it."""
    return motion_program(
        *(params[c].text for c in "xyz"),
        *(float(params[n]) for n in ("phi0", "phi1", "v0", "Delta0", "Delta1")),
        params["profile"],
    )


def _curve_param(name: str) -> CurveFormulaParam:
    k = "xyz".index(name)
    label = f"{name} = f{k + 1}(phi)"
    return CurveFormulaParam(name, "formula", HELIX_12[k], label, group="curve", help="(1.1)")


def _range_param(name: str, default: str, help: str) -> Param:
    return Param(name, "float", default, name, "", -1000.0, 1000.0, 0.01, group="curve", help=help)


def _law_param(name: str, default: float, unit: str, low: float, help: str) -> Param:
    return Param(name, "float", default, name, unit, low, 1000.0, 0.01, group="law", help=help)


# ------------------------------------------------------------------ the lesson


class MotionProgramLesson(Lesson):
    id = "motion-program"
    title = "Building a motion program along a space curve"
    chapter = "1"
    problem = "§1.1"
    source = "Textbook §1.1, eqs (1.1)-(1.15); the motion-program journal article, eqs (1)-(15)"
    summary = (
        "A curve given by any parameter phi is reparametrized by arc length, then by time with a "
        "trapezoid or triangle speed law; the rank-one controls u_ij = Xdot_i X_j / D make the "
        "linear system (1.5) reproduce it."
    )
    order = 1.1
    t_end = 6.0
    groups = (
        Group("mode", "Speed profile", change="restart"),
        Group("curve", "The curve l (1.1)", change="restart"),
        Group("law", "Speed law v(t) (1.8), (1.9)", change="restart"),
    )
    modes = ("profile",)
    params = (
        Param(
            "profile",
            "choice",
            "auto",
            "speed profile",
            choices=PROFILE_CHOICES,
            group="mode",
            help="auto: trapezoid (1.8) if L > 0, else the minimum-time triangle (1.9)",
        ),
        *(_curve_param(n) for n in "xyz"),
        _range_param("phi0", "0", "start of the range I"),
        _range_param("phi1", "pi", "end of the range I"),
        _law_param("v0", 1.0, "m/s", 1e-3, "speed of the constant segment"),
        _law_param("Delta0", 1.0, "s", 0.0, "acceleration time"),
        _law_param("Delta1", 1.0, "s", 0.0, "deceleration time"),
    )
    presets = PRESETS
    series = (
        Series("s", "m", "path covered s(t), (1.7)"),
        Series("v_limit", "m/s", "the speed law v(t), (1.8)/(1.9)"),
        Series("phi", "", "curve parameter phi = omega(s(t)), (1.13)"),
        *(Series(c, "m", f"{c.upper()}(t) of the program, (1.11)") for c in "xyz"),
        *(Series(f"v{c}", "m/s", f"d{c.upper()}/dt = r'/|r'| v(t) of the program") for c in "xyz"),
        *(
            Series(
                f"{c}_analyzer",
                "m",
                f"{c} of the solution of (1.5) with the controls (1.15)",
                undefined=AT_ORIGIN,
            )
            for c in "xyz"
        ),
        Series("speed", "m/s", "speed |U X| of the solution of (1.5)", undefined=AT_ORIGIN),
        Series(
            "error",
            "m",
            "reproduction error: distance of the solution of (1.5) from X(t)",
            undefined=AT_ORIGIN,
        ),
        Series("dist_sq", "m^2", "D = X^2 + Y^2 + Z^2, (1.14)"),
        *(Series(n, "1/s", f"control u_{n[1:]}(t), (1.15)", undefined=AT_ORIGIN) for n in U_NAMES),
    )
    readout = ("s", "v_limit", "x", "y", "z", "speed", "error")
    sampling = 0.01
    plots = (
        PlotSpec("Speed |v| of (1.5) and the limit v(t)", ("speed", "v_limit"), "m/s"),
        PlotSpec("Arc length s(t) (1.7)", ("s",), "m"),
        PlotSpec("Coordinates X(t), Y(t), Z(t) (1.11)", ("x", "y", "z"), "m"),
        PlotSpec("Controls u_ij(t) (1.15)", U_NAMES, "1/s"),
        PlotSpec("Reproduction error of (1.5)", ("error",), "m"),
    )

    def validate(self, params: Params) -> None:
        if not float(params["phi1"]) > float(params["phi0"]):
            raise ParamError("phi1", f"must be greater than phi0 = {float(params['phi0']):g}")
        program_of(params)  # raises ParamError naming the coordinate or the profile

    def notes(self, params: Params) -> list[Note]:
        prog = program_of(params)
        cm, prof = prog.curve, prog.profile
        out = [Note("info", f"L = {prof.L:.6g}: {prof.kind}, T = {prof.T:.6g} s (1.8), (1.9)")]
        if prof.kind == "triangle":
            text = "the triangle's slopes are the trapezoid's: k1 = v0/Delta0, k2 = v0/Delta1"
            evidence = "the source gives only k1 = tg alpha, k2 = tg beta (Fig. 1.2)"
            out.append(Note("reconstructed", f"{text}; v1 = {prof.v1:.6g}", "(1.9)", evidence))
        warnings = []
        if prof.v1 > prof.v0 * (1 + 1e-12):
            warnings.append(
                f"L > 0 but the triangle is forced: its peak v1 = {prof.v1:.6g} exceeds"
                f" v0 = {prof.v0:g} (the source uses (1.9) only for L <= 0)"
            )
        if cm.arc.table.accuracy > 1e-9 * max(1.0, cm.arc.S_l):
            warnings.append(
                f"arc length (1.12) settled only to {cm.arc.table.accuracy:.2g}:"
                " the curve is hard to integrate"
            )
        warnings += [
            f"X(t) = 0 at t = {ts:.6g}: (1.14) fails and (1.15) divides by zero there; the zero"
            " solution of (1.5) cannot be left or reached, so (1.5) is suspended on"
            f" ({max(g0, 0):.4g}, {g1:.4g}) and restarted from the curve"
            for ts, (g0, g1) in zip(prog.singular_t, prog.gaps)
        ]
        warnings += [
            f"r'(phi) = 0 at t = {tc:.6g}: the curve is not regular there (a cusp);"
            " the RK4 steps are split there"
            for tc in prog.cusp_t
        ]
        if cm.nonsmooth:
            warnings.append(
                "the curve uses abs(): its tangent may jump; RK4 loses accuracy on a step"
                " across a corner (see the error)"
            )
        if not prog.singular_t and cm.min_radius < 1e-3 * cm.scale:
            warnings.append(
                f"the curve passes at {cm.min_radius:.3g} from the origin (curve size"
                f" {cm.scale:.3g}): |u_ij| ~ v/|X| is large there"
            )
        return out + [Note("warning", w) for w in warnings]

    # -- observation and simulation -----------------------------------------------------

    def observe(self, params: Params, t: np.ndarray, state: np.ndarray) -> dict[str, Any]:
        """Every series at the times ``t`` from the solution of (1.5) there (``state``, (N, 3))
        and the program (1.11), (1.15) at those times."""
        prog = program_of(params)
        law = prog.law(t)
        X, V, Y = law["X"], law["V"], state
        U = prog.controls(law)
        U[prog.in_gap(t)] = np.nan  # unbounded near the origin: left out
        out = {"s": law["s"], "v_limit": law["v"], "phi": law["phi"]}
        for k, c in enumerate("xyz"):
            out[c] = X[:, k]
            out[f"v{c}"] = V[:, k]
            out[f"{c}_analyzer"] = Y[:, k]
        UY, E = np.einsum("nij,nj->ni", U, Y), Y - X
        out["speed"] = np.sqrt(np.einsum("ij,ij->i", UY, UY))
        out["error"] = np.sqrt(np.einsum("ij,ij->i", E, E))
        out["dist_sq"] = law["D"]
        for k, name in enumerate(U_NAMES):
            out[name] = U[:, k // 3, k % 3]
        return out

    def observe_one(self, params: Params, t: float, state: np.ndarray) -> dict[str, float]:
        """:meth:`observe` at one time in plain floats (a played frame; equal to round-off)."""
        prog = program_of(params)
        law = prog.law(np.array([float(t)]))
        X, V = law["X"][0].tolist(), law["V"][0].tolist()
        Y = np.asarray(state, dtype=float).reshape(3).tolist()
        D = float(law["D"][0])
        out = {"s": float(law["s"][0]), "v_limit": float(law["v"][0]), "phi": float(law["phi"][0])}
        for k, c in enumerate("xyz"):
            out[c], out[f"v{c}"], out[f"{c}_analyzer"] = X[k], V[k], Y[k]
        gap = D <= 0 or any(a < t < b for a, b in prog.gaps)  # (1.15) undefined there
        U = [[math.nan if gap else vi * xj / D for xj in X] for vi in V]
        UY = [sum(u * y for u, y in zip(row, Y)) for row in U]
        out["speed"] = math.sqrt(sum(w * w for w in UY))
        out["error"] = math.sqrt(sum((y - x) ** 2 for x, y in zip(X, Y)))
        out["dist_sq"] = D
        out.update((name, U[k // 3][k % 3]) for k, name in enumerate(U_NAMES))
        return out

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        prog = program_of(params)
        prof, cm = prog.profile, prog.curve
        t_end = prof.T if t_end is None else float(t_end)
        if not t_end > 0:
            raise ParamError("t_end", f"must be positive, got {t_end:g}")
        messages = [n.text for n in self.notes(params)]
        if t_end < prof.T:
            messages.append(
                f"stopped at t = {t_end:g} before the end of the motion (T = {prof.T:.6g})"
            )
        # the sampling, plus the kinks of v(t) and the passes through the origin
        t = self.sample_grid(t_end, max(self.sampling, t_end / MAX_SAMPLES))
        marks = [m for m in (*prog.kinks, *prog.singular_t) if 0 < m < t_end]
        t = np.unique(np.concatenate([t, marks]))
        # accuracy measured at every RK4 step
        law = prog.law(prog.steps)
        err = np.linalg.norm(prog.Y - law["X"], axis=1)
        excess = np.linalg.norm(prog.F, axis=1) - law["v"]
        U = prog.controls(law)
        U[prog.in_gap(prog.steps)] = np.nan
        max_err = float(np.nanmax(err))
        metrics = {
            "S_l": cm.arc.S_l,
            **{k: getattr(prof, k) for k in ("T", "L", "Delta", "t1", "tau", "v1", "k1", "k2")},
            "profile": prof.kind,
            "max_error": max_err,
            "max_error_relative": max_err / cm.scale,
            "max_speed_excess": float(np.nanmax(excess)),
            "max_speed_excess_program": float(np.max(np.linalg.norm(law["V"], axis=1) - law["v"])),
            "min_D": float(np.min(law["D"])),
            "max_abs_u": float(np.nanmax(np.abs(U))) if np.isfinite(U).any() else math.nan,
            "singular_times": list(prog.singular_t),
            "integrator": "classical RK4 (order 4), one fixed step grid on [0, T] with"
            f" h max(|U|, tangent turning rate) <= {STEP_ANGLE}, aligned with the kinks of v(t)"
            " and the cusps of l; cubic Hermite between the steps",
            "rk4_steps": len(prog.steps) - 1,
        }
        return self.result(params, t, prog.solution(t), metrics, messages)

    # -- live -------------------------------------------------------------------------

    def stepper(self, params: Params) -> Stepper:
        return ProgramStepper(params, program_of, self.frame_scalars)

    def scene(self, params: Params) -> SceneSpec:
        pts = program_of(params).curve.samples
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pad = 0.1 * max(float(np.max(hi - lo)), 1.0)
        return SceneSpec(
            bounds=(tuple(float(v) for v in lo - pad), tuple(float(v) for v in hi + pad)),  # type: ignore[arg-type]
            curves=[CurveItem("curve l (1.1)", pts.copy(), color=(40, 40, 40), width=2.0)],
            markers=[
                MarkerItem("start", pts[:1].copy(), (30, 160, 60), 0.06, "start r(phi0)"),
                MarkerItem("end", pts[-1:].copy(), (200, 60, 60), 0.05, "end r(phi1)"),
                MarkerItem("origin", np.zeros((1, 3)), (120, 120, 120), 0.04, "O"),
            ],
            moving_points={"point": (220, 60, 60), "analyzer": (40, 90, 220)},
            moving_vectors={"velocity": (240, 150, 20)},
        )

    # -- derivation -------------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        prog = program_of(params)
        cm, prof = prog.curve, prog.profile
        x, y, z, s, t = sp.symbols("x y z s t", real=True)
        phi0 = sp.Symbol("phi_0", real=True)
        S_l, v0, D0, D1, L = sp.symbols("S_l v_0 Delta_0 Delta_1 L", positive=True)
        k1, k2, t1, tau, v1 = sp.symbols("k_1 k_2 t_1 tau v_1", positive=True)
        X, Y, Z = (sp.Function(n)(t) for n in ("X", "Y", "Z"))
        Xv = sp.Matrix([X, Y, Z])
        Dsym = sp.Symbol("D", positive=True)
        speed2 = sum(sp.diff(e, PHI) ** 2 for e in cm.exprs)
        if sp.count_ops(speed2) <= 40:
            speed2 = sp.simplify(speed2)
        tri = triangle_symbolic()

        def curve_eqs(exprs):
            return [sp.Eq(a, e) for a, e in zip((x, y, z), exprs)]

        def form(c):
            return curve_eqs([parse_formula(f, variables=("phi",)).expr for f in c[:3]])

        min_D = float(np.min(prog.law(np.linspace(0, prof.T, 401))["D"]))
        meets = ", ".join(f"{v:.6g}" for v in prog.singular_t)
        f_i = [sp.Derivative(sp.Function(f"f_{i}")(PHI), PHI) for i in (1, 2, 3)]
        s_of_phi = sp.Integral(sp.sqrt(sum(d**2 for d in f_i)), (PHI, phi0, PHI))
        xi = sp.Symbol("xi")
        U = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"u_{i + 1}{j + 1}"))
        rows = [
            (
                "The curve l",
                "A space curve with an arbitrary parameter phi on I = [phi0, phi1];"
                " here the typed one.",
                curve_eqs(cm.exprs),
                "(1.1)",
                "lost in extraction; the form follows from the text and from (1.13)",
            ),
            ("Example: a helix half-turn", "phi in [0, pi].", form(HELIX_12), "(1.2)", None),
            (
                "The same helix, second form",
                "phi in [0, pi/2]; (1.3)(phi) = (1.2)(2 phi).",
                form(HELIX_13),
                "(1.3)",
                None,
            ),
            (
                "The same helix, third form",
                "phi in [-1, 1]; (1.4)(phi) = (1.2)(arccos phi): the"
                " same point set, traversed in the opposite direction, with |r'|^2 = 2/(1 - phi^2)"
                " integrably singular at both ends.",
                form(HELIX_14),
                "(1.4)",
                "the square root over 1 - phi^2 was lost; without it x^2 + y^2 != 1",
            ),
            (
                "The differential analyzer",
                "A linear system of the 3rd order whose coefficients"
                " u_ij(t) are the controls; its phase curve must start at r(phi0), describe l and"
                " only l, and never exceed v(t).",
                sp.Eq(Xv.diff(t), U * Xv),
                "(1.5)",
                "lost in extraction; rebuilt from the text, the journal article and (1.15)",
            ),
            (
                "Arc length",
                f"For this curve |r'(phi)|^2 is shown below; S_l = s(phi1) ="
                f" {cm.arc.S_l:.12g}. Numerically: the substitution phi = phi0 + (phi1 - phi0)"
                " sin^2(theta/2) removes end-point singularities such as that of (1.4).",
                [sp.Eq(sp.Function("s")(PHI), s_of_phi), sp.Eq(sp.Symbol("|r'|^2"), speed2)],
                "(1.12)",
                "decoded from the scrambled extraction; the radical sign was restored",
            ),
            (
                "Arc-length form",
                "s(phi) increases, so phi = omega(s) exists and x = f1(omega(s)) = x(s), ...",
                [
                    sp.Eq(x, sp.Function("f_1")(sp.Function("omega")(s))),
                    sp.Eq(x, sp.Function("x")(s)),
                ],
                "(1.13), (1.6)",
                None,
            ),
            (
                "Path covered in time",
                "",
                sp.Eq(sp.Function("s")(t), sp.Integral(sp.Function("v")(xi), (xi, 0, t))),
                "(1.7)",
                None,
            ),
            (
                "Length left for the constant speed",
                f"Here L = {prof.L:.6g}: the profile is a {prof.kind}.",
                sp.Eq(L, S_l - v0 / 2 * (D0 + D1)),
                "(1.8)",
                None,
            ),
            (
                "Trapezoid (L > 0)",
                "Constant segment Delta = L/v0, total time"
                f" T = Delta0 + Delta + Delta1 (here T = {prof.T:.6g}).",
                [sp.Eq(sp.Symbol("Delta"), L / v0), sp.Eq(sp.Symbol("T"), D0 + L / v0 + D1)],
                "(1.8)",
                None,
            ),
            (
                "Triangle (L <= 0): minimum time",
                "v1 = k1 t1 = k2 (tau - t1) and v1 tau / 2 = S_l give (1.9).",
                [sp.Eq(t1, tri["t_1"]), sp.Eq(tau, tri["tau"]), sp.Eq(v1, tri["v_1"])],
                "(1.9)",
                "scrambled in the extraction; re-derived (its symbol multiset matches)",
            ),
            (
                "Slopes of the triangle",
                "The source says only k1 = tg alpha, k2 = tg beta; the"
                " lab takes the trapezoid's ramps, so v1^2 = 2 S_l v0 / (Delta0 + Delta1),"
                " L <= 0 iff v1 <= v0, and the two cases join at L = 0.",
                [sp.Eq(k1, v0 / D0), sp.Eq(k2, v0 / D1)],
                "(1.9)",
                "slopes not given in the source (Fig. 1.2 names only the angles); chosen so that"
                " the two laws join at L = 0",
            ),
            (
                "s(t) in closed form",
                "Trapezoid: s = v0 t^2/(2 Delta0) on the ramp,"
                " v0 Delta0/2 + v0 (t - Delta0) on the plateau, S_l - v0 (T - t)^2/(2 Delta1) at the"
                " end. Triangle: s = k1 t^2/2, then S_l - k2 (tau - t)^2/2.",
                sp.Eq(sp.Function("s")(t), v0 * t**2 / (2 * D0)),
                "(1.7)",
                "the source only says 'integrate (1.7)'; the closed form is derived",
            ),
            (
                "The time law",
                "x(s(t)) = X(t), y(s(t)) = Y(t), z(s(t)) = Z(t): the motion along l"
                " at the speed v(t).",
                [sp.Eq(x, X), sp.Eq(y, Y), sp.Eq(z, Z)],
                "(1.10), (1.11)",
                None,
            ),
            (
                "Velocity without numerical differentiation",
                "The unit tangent times the speed law.",
                sp.Eq(
                    Xv.diff(t),
                    sp.Function("r'")(PHI) / sp.Abs(sp.Function("r'")(PHI)) * sp.Function("v")(t),
                    evaluate=False,
                ),
                "(1.11)",
                "implementation detail, not printed in the source",
            ),
            (
                "No phase curve through the origin",
                "(1.5) has the zero solution and unique"
                f" solutions. Here min D = {min_D:.6g}"
                + (f"; the curve meets the origin at t = {meets}." if meets else "."),
                sp.Ne(X**2 + Y**2 + Z**2, 0),
                "(1.14)",
                None,
            ),
            (
                "The controls",
                "u_ij = Ẋ_i X_j / D with D = X² + Y² + Z²: a rank-one matrix"
                " with U X = Ẋ, so X(t) solves (1.5). The dot belongs to the row variable (the"
                " other reading fails U X = Ẋ).",
                [
                    sp.Eq(sp.Symbol("U"), Xv.diff(t) * Xv.T / Dsym, evaluate=False),
                    sp.Eq(Dsym, X**2 + Y**2 + Z**2),
                ],
                "(1.15)",
                None,
            ),
        ]
        return [DerivationStep(*row[:4], reconstructed=row[4]) for row in rows]

    # -- claims -----------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        return helix_claims()


LESSON = MotionProgramLesson()
