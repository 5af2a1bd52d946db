"""Chapter 2, §2.2: the formalized algorithm for systems with constraints, (2.17)-(2.34).

The loops of a mechanism are opened; the opened system ``A q'' = B + B*`` gets the
constraint reactions ``H^T lambda`` (2.25); differentiating the holonomic constraints
twice (2.27) and the nonholonomic ones once (2.28) gives ``H q'' = -Phi`` (2.30), which
eliminates the multipliers (2.33) and leaves (2.34).  The algorithm is shown in its
corrected form (``H`` is ``v2 x n``, one multiplier per constraint, initial velocities
from (2.29)); integrating (2.34) lets the constraints drift, and Baumgarte stabilization
(not in the source) holds them.  The examples (a pendulum, a pendulum on a rod of
prescribed length, a knife edge, Problem 2.4 opened) are in
:mod:`analyzer_lab.lessons.mechanics.lagrange.examples`; a run is one dense solution per parameter set,
played by the live stepper as it is sampled by the headless run.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from analyzer_lab.lessons.kit.bodies import IDENTITY_Q, bounds_of, box, cylinder, mesh_item, quat_z
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Group,
    Lesson,
    Note,
    Param,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Series,
    Stepper,
    at_most,
)
from analyzer_lab.lessons.kit.dense_solution import SOLVERS, RunStepper
from analyzer_lab.lessons.mechanics.lagrange.constraint_eval import (
    algorithm_steps,
    correction_notes,
)
from analyzer_lab.lessons.mechanics.lagrange.examples import (
    COORDS,
    EXAMPLES,
    P3_FORCE_TEXT,
    SERIES,
    ExampleRun,
    inputs_of,
    observe_example,
    physical,
    planar3_acceleration_difference,
    series_names,
    start_state,
    system,
)
from analyzer_lab.lessons.mechanics.positioners.planar3 import (
    body_value,
    default_trace,
    planar3_scene,
    pose_planar3,
)

Array = np.ndarray


class ConstrainedDynamics(Lesson):
    """§2.2: generic solver with Lagrange multipliers, (2.17)-(2.34), and its drift."""

    id = "constrained-dynamics"
    title = "Constrained dynamics with Lagrange multipliers"
    chapter = "2"
    problem = "§2.2"
    source = "Textbook §2.2, eqs (2.17)-(2.34)"
    summary = (
        "Opened loops plus constraints: A q'' = B + H^T lambda, H q'' = -Phi; drift of the "
        "constraints and Baumgarte stabilization."
    )
    order = 2.1
    t_end = 20.0
    sampling = 0.025
    groups = (
        Group("mode", "Example and stabilization", change="restart"),
        Group("pendulum", "Pendulum"),
        Group("skate", "Knife edge"),
        Group("initial", "Start state", change="restart"),
        Group("baumgarte", "Baumgarte stabilization"),
        Group("method", "Integrator", expanded=False, change="live"),
    )
    modes = ("example", "stabilization")
    series = SERIES
    readout = ("f", "g", "f_1", "f_2", "position_error", "speed_error")
    params = (
        Param(
            "example",
            "choice",
            "pendulum",
            label="example",
            choices=EXAMPLES,
            group="mode",
            help="pendulum (holonomic), pendulum on a rod of prescribed length (rheonomic), "
            "knife edge (nonholonomic), Problem 2.4 with the constraints (2.12)",
        ),
        Param(
            "stabilization",
            "bool",
            False,
            label="Baumgarte stabilization",
            group="mode",
            help="Phi -> Phi + 2 alpha (H q' + psi) + beta^2 f (not in the source)",
        ),
        Param("m", "float", 1.0, "mass m (bob, skate)", "kg", 1e-3, 1e3, group="pendulum"),
        Param("g", "float", 9.81, "g", "m/s^2", 0.0, 100.0, group="pendulum"),
        Param("L", "float", 1.0, "rod length L", "m", 1e-3, 100.0, group="pendulum"),
        Param(
            "eps", "float", 0.2, "L(t) = L (1 + eps sin nu t): eps", "", 0, 0.9, group="pendulum"
        ),
        Param("nu", "float", 2.0, "length frequency nu", "rad/s", 0.0, 100.0, group="pendulum"),
        Param("J", "float", 0.1, "skate inertia J", "kg m^2", 1e-4, 1e3, group="skate"),
        Param("F", "float", 2.0, "downhill force m g sin(alpha)", "N", -1e3, 1e3, group="skate"),
        Param("theta0", "float", 1.0, "pendulum angle theta0", "rad", -3.1, 3.1, group="initial"),
        Param("u0", "float", 0.5, "skate speed u0", "m/s", -100.0, 100.0, group="initial"),
        Param("omega0", "float", 1.0, "skate turning rate", "rad/s", -100, 100, group="initial"),
        Param("alpha", "float", 5.0, "alpha", "1/s", 0.0, 200.0, group="baumgarte"),
        Param("beta", "float", 5.0, "beta", "1/s", 0.0, 200.0, group="baumgarte"),
        Param("integrator", "choice", "RK45", choices=tuple(SOLVERS), group="method"),
        Param("rtol", "float", 1e-6, "tolerance (rtol = atol)", "", 1e-12, 1e-2, group="method"),
    )
    presets = (
        Preset(
            "pendulum-drift",
            "Pendulum, no stabilization: the constraint drifts",
            {"example": "pendulum", "stabilization": False},
            t_end=50.0,
        ),
        Preset(
            "pendulum-baumgarte",
            "Pendulum, Baumgarte alpha = beta = 5 1/s",
            {"example": "pendulum", "stabilization": True},
            t_end=50.0,
        ),
        Preset(
            "rheonomic-pendulum",
            "Rod of prescribed length L(t) = 1 + 0.2 sin 2t m: the constraint depends on t",
            {"example": "rheonomic-pendulum", "stabilization": False},
            t_end=20.0,
            note="(2.17) with f(q, t): psi = df/dt enters (2.29), d2f/dt2 enters (2.27).",
        ),
        Preset(
            "rheonomic-baumgarte",
            "Rod of prescribed length, Baumgarte alpha = beta = 10 1/s",
            {"example": "rheonomic-pendulum", "stabilization": True, "alpha": 10.0, "beta": 10.0},
            t_end=20.0,
        ),
        Preset(
            "knife-edge",
            "Knife edge on an inclined plane (nonholonomic)",
            {"example": "knife-edge"},
            t_end=10.0,
        ),
        Preset(
            "planar-3axis",
            "Problem 2.4 as 5 coordinates + 2 constraints (2.12)",
            {
                "example": "planar-3axis",
                "stabilization": True,
                "integrator": "DOP853",
                "rtol": 1e-10,
            },
            t_end=10.0,
            note=f"Forces {P3_FORCE_TEXT}; masses of the planar-3axis lesson (Problem 2.4).",
        ),
    )
    plots = (
        PlotSpec("Constraint drift", ("f", "f_1", "f_2", "g"), ""),
        PlotSpec("Velocity-level drift", ("f_dot", "f_1_dot", "f_2_dot"), ""),
        PlotSpec("Energy error", ("energy_error",), "J"),
        PlotSpec("Error against an independent solution", ("position_error", "speed_error"), ""),
        PlotSpec("Multipliers", ("lambda", "lambda_1", "lambda_2"), ""),
        PlotSpec("Rod length", ("length",), "m"),
        PlotSpec("Coordinates", ("x", "y", "theta", "x_A", "y_A", "phi"), ""),
    )

    # -- observation and runs ---------------------------------------------------------

    def series_for(self, params: Params) -> tuple[Series, ...]:
        """The example's coordinates and velocities, then its own quantities."""
        names = series_names(str(params["example"]))
        return tuple(s for s in self.series if s.name in names)

    def observe(self, params: Params, t: Array, state: Any) -> dict[str, Array]:
        return observe_example(params, t, np.asarray(state, dtype=float))

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        t = self.sample_grid(t_end)
        run = ExampleRun(params)
        r = self.result(params, t, run.state(t), messages=[run.failure] if run.failure else [])
        _, cs = system(str(params["example"]))
        r.metrics.update(
            {
                "H_shape": f"{cs.v2} x {cs.n}",
                "steps": run.main.steps,
                "nfev": run.main.evaluations,
            }
        )
        for name in ("f", "f_1", "f_2", "g", "energy_error", "position_error", "speed_error"):
            if name in r.series:
                r.metrics[f"max_abs_{name}"] = float(np.nanmax(np.abs(r.series[name])))
        return r

    def stepper(self, params: Params) -> Stepper:
        return RunStepper(
            lambda ps, t0, state: ExampleRun(ps, t0, state),
            self._frame,
            params,
            block=2.0,
            observe=self.observe,
            names=lambda ps: tuple(s.name for s in self.series_for(ps)),
        )

    def _frame(
        self, params: Params, t: float, state: Array, scalars: dict[str, float] | None = None
    ) -> Frame:
        s = self.frame_scalars(params, t, state) if scalars is None else scalars
        fr = Frame(t=float(t), scalars=s)
        ex = str(params["example"])
        q = np.array([s[c] for c in COORDS[ex]])
        if ex == "knife-edge":
            p = np.array([q[0], q[1], 0.0])
            fr.poses["skate"] = (p, quat_z(float(q[2])))
            fr.points["skate"] = p[None, :]
            r = s["lambda_1"] * np.array([-np.sin(q[2]), np.cos(q[2]), 0.0])
            fr.vectors["reaction"] = (p[None, :], 0.1 * r[None, :])
        elif ex == "planar-3axis":  # q = (x_A, y_A, x_B, y_B, phi)
            _, B, _, h = pose_planar3(fr, body_value("AB"), *(float(v) for v in q))
            reaction = 0.05 * np.array([[s["lambda_1"], s["lambda_2"], 0.0]])
            fr.vectors["reaction at B"] = ((B + [0, 0, 2 * h])[None, :], reaction)
        else:
            L = float(params["L"])
            bob = np.array([q[0], 0.0, q[1]])
            fr.poses["bob"] = (bob, IDENTITY_Q.copy())
            half = 0.5 * np.arctan2(q[0], q[1])  # the rod (a mesh along +Z) turned about Y
            fr.poses["rod"] = (bob / 2, np.array([np.cos(half), 0.0, np.sin(half), 0.0]))
            fr.points["bob"] = bob[None, :]
            scale = 0.6 * L / (float(params["m"]) * max(float(params["g"]), 1e-9))
            fr.vectors["reaction"] = (bob[None, :], scale * s["lambda"] * bob[None, :])
        return fr

    # -- scene --------------------------------------------------------------------------

    def scene(self, params: Params) -> SceneSpec:
        ex = str(params["example"])
        if ex == "knife-edge":
            t = np.linspace(0.0, 10.0, 201)
            xy = ExampleRun(params).state(t)[:, :2]
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            lo, hi = np.min(xy, axis=0, initial=0.0), np.max(xy, axis=0, initial=0.0)
            span = max(float(np.max(hi - lo)), 1.0)
            c = (lo + hi) / 2
            plane = box(
                "inclined plane (downhill = +X)",
                (span * 1.4, span * 1.4, 0.01 * span),
                (170, 170, 170),
                center=(c[0], c[1], -0.01 * span),
                opacity=0.4,
            )
            blade = box("skate", (0.12 * span, 0.02 * span, 0.04 * span), (70, 130, 200))
            pts = np.array(
                [
                    [lo[0] - 0.3 * span, lo[1] - 0.3 * span, -0.05 * span],
                    [hi[0] + 0.3 * span, hi[1] + 0.3 * span, 0.1 * span],
                ]
            )
            return SceneSpec(
                bounds=bounds_of(pts, 0.02),
                meshes=[plane],
                bodies=[blade],
                moving_points={"skate": (70, 130, 200)},
                moving_vectors={"reaction": (60, 60, 200)},
            )
        if ex == "planar-3axis":  # the floor of Problem 2.4's page at its defaults
            return planar3_scene(
                body_value("AB"), default_trace(), {"reaction at B": (60, 60, 200)}
            )
        L = float(params["L"]) * (1 + float(params["eps"]) * (ex == "rheonomic-pendulum"))
        bob = mesh_item("bob", trimesh.creation.icosphere(2, 0.06 * L), (200, 80, 60))
        rod = cylinder("rod", 0.01 * L, L, (90, 90, 90))
        pivot = box("pivot", (0.1 * L, 0.1 * L, 0.05 * L), (60, 60, 60), center=(0, 0, 0.025 * L))
        return SceneSpec(
            bounds=bounds_of(np.array([[-L, -0.2 * L, -L], [L, 0.2 * L, 0.2 * L]]), 0.05),
            meshes=[pivot],
            bodies=[bob, rod],
            moving_points={"bob": (200, 80, 60)},
            moving_vectors={"reaction": (60, 60, 200)},
        )

    # -- the page ------------------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        ex = str(params["example"])
        _, cs = system(ex)
        steps = algorithm_steps()
        sym = lambda name, value: sp.Eq(sp.Symbol(name), value, evaluate=False)  # noqa: E731
        steps += [
            DerivationStep("This example: A (from the Lagrange equations)", "", sym("A", cs.A)),
            DerivationStep(
                "This example: B",
                "Generalized forces plus the velocity and gravity terms of the Lagrange equations.",
                sym("B", cs.B),
            ),
            DerivationStep("This example: H", f"{cs.v2} x {cs.n}", sym("H", cs.H), "(2.24)"),
            DerivationStep("This example: psi", "", sym(r"\psi", sp.simplify(cs.psi)), "(2.29)"),
            DerivationStep("This example: Phi", "", sym(r"\Phi", sp.simplify(cs.Phi)), "(2.30)"),
        ]
        return steps

    def notes(self, params: Params) -> list[Note]:
        ex = str(params["example"])
        _, cs = system(ex)
        q0, qd0 = start_state(params, 0.0)
        u0 = inputs_of(ex, np.zeros(1))[:, 0]
        q, qd = cs.consistent_initial(0.0, q0, qd0, physical(params), u0)
        out = []
        moved = float(np.max(np.abs(np.concatenate([q - q0, qd - qd0]))))
        if moved > 1e-12:
            out.append(
                Note(
                    "info",
                    f"The start state was projected onto (2.17) and (2.29) (solution steps 2-3): "
                    f"q'(0) = ({', '.join(f'{v:.4g}' for v in qd)}), moved by {moved:.3g}.",
                    "(2.17), (2.29)",
                )
            )
        if params["stabilization"]:
            out.append(
                Note(
                    "info",
                    "Baumgarte stabilization is not in the source: the source integrates (2.34).",
                )
            )
        if ex == "planar-3axis":
            out.append(Note("info", f"Problem 2.4 forces: {P3_FORCE_TEXT}.", "Problem 2.4"))
        return out + correction_notes()

    # -- claims ---------------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        def hand_forms() -> ClaimResult:
            cs = system("pendulum")[1]
            (x, y), (xd, yd) = cs.q, cs.qd
            ok = sp.simplify(cs.H - sp.Matrix([[2 * x, 2 * y]])) == sp.zeros(1, 2)
            ok = ok and sp.simplify(cs.Phi[0] - 2 * (xd**2 + yd**2)) == 0
            ck = system("knife-edge")[1]
            th, thd = ck.q[2], ck.qd[2]
            ok = (
                ok
                and sp.simplify(ck.Phi[0] + thd * (ck.qd[0] * sp.cos(th) + ck.qd[1] * sp.sin(th)))
                == 0
            )
            return ClaimResult(
                "H = [2x, 2y], Phi = 2(x'^2 + y'^2); knife edge Phi = -theta'(x' cos theta + y' sin theta)",
                "match" if ok else "differ",
                bool(ok),
            )

        def shapes() -> ClaimResult:
            got = [f"{system(e)[1].v2}x{system(e)[1].n}" for e in EXAMPLES]
            want = ["1x2", "1x2", "1x3", "2x5"]
            return ClaimResult(", ".join(want), ", ".join(got), got == want)

        def drift() -> ClaimResult:
            d = pendulum_drift()
            ok = d["free_max"] > 5e-5 and d["free_50"] > 3 * d["free_10"] and d["stab_max"] <= 1e-5
            return ClaimResult(
                "no stabilization: max|f| > 5e-5 and |f(50)| > 3 |f(10)|; alpha = beta = 5: max|f| <= 1e-5",
                f"max|f| = {d['free_max']:.3g} (|f(10)| = {d['free_10']:.3g}, |f(50)| = "
                f"{d['free_50']:.3g}); stabilized max|f| = {d['stab_max']:.3g}",
                bool(ok),
            )

        def pendulum_accuracy() -> ClaimResult:
            d = pendulum_drift()
            return at_most(2e-3, d["stab_ref"], "stabilized position error vs angle ODE (m) ")

        def rheonomic_terms() -> ClaimResult:
            cs = system("rheonomic-pendulum")[1]
            (xd, yd), t = cs.qd, cs.t
            L0, eps, nu = cs.params[2:5]
            L = L0 * (1 + eps * sp.sin(nu * t))
            ok = sp.simplify(cs.psi[0] + 2 * L * L.diff(t)) == 0
            phi = 2 * (xd**2 + yd**2) - 2 * (L.diff(t) ** 2 + L * L.diff(t, 2))
            ok = ok and sp.simplify(cs.Phi[0] - phi) == 0
            book = {L0: 1, eps: sp.Rational(1, 5), nu: 2}
            want = -4 * (sp.sin(2 * t) + 5) * sp.cos(2 * t) / 25
            ok = ok and sp.simplify(cs.psi[0].subs(book) - want) == 0
            return ClaimResult(
                "psi = -2 L L' = -4 (sin 2t + 5) cos 2t / 25, Phi = 2(x'^2 + y'^2) - 2(L'^2 + L L'')",
                "match" if ok else "differ",
                bool(ok),
            )

        def rheonomic_drift() -> ClaimResult:
            d = rheonomic_drift_numbers()
            ok = (
                5e-5 <= d["free_f"] <= 1e-3
                and 1e-4 <= d["free_err"] <= 3e-3
                and d["stab_f"] <= min(1e-6, d["free_f"] / 100)
                and d["stab_err"] <= d["free_err"] / 10
            )
            return ClaimResult(
                "free: 5e-5 <= max|f| <= 1e-3 m^2, 1e-4 <= error <= 3e-3 m; alpha = beta = 10: "
                "max|f| <= 1e-6 and 100x smaller, error 10x smaller",
                ", ".join(f"{k} {v:.3g}" for k, v in d.items()),
                bool(ok),
            )

        def knife() -> ClaimResult:
            values = {"example": "knife-edge", "integrator": "DOP853", "rtol": 1e-10}
            t = np.linspace(0, 10, 401)
            s = samples(values, t)
            err = float(np.max(np.abs(s["u_along_blade"] - (0.5 + 2.0 * np.sin(t)))))
            g = float(np.max(np.abs(s["g"])))
            wdev = float(np.max(np.abs(s["theta_dot"] - 1.0)))
            return ClaimResult(
                "|u - (0.5 + 2 sin t)| <= 1e-7, |g| <= 1e-8, theta' = 1",
                f"{err:.3g}, {g:.3g}, {wdev:.3g}",
                err <= 1e-7 and g <= 1e-8 and wdev <= 1e-12,
            )

        def p24() -> ClaimResult:
            return at_most(
                1e-12, planar3_acceleration_difference(), "max |q'' (2.34) - q'' reduced 3-DOF| "
            )

        def p24_traj() -> ClaimResult:
            preset = dict(self.preset("planar-3axis").values)
            s = samples(preset, np.linspace(0, 10, 201))
            worst = float(max(np.max(s["position_error"]), np.max(s["phi_error"])))
            return at_most(1e-7, worst, "max |(x_A, y_A, phi) constrained - reduced| over 10 s ")

        def init_vel() -> ClaimResult:
            _, cs = system("planar-3axis")
            pvec = physical(self.resolve({"example": "planar-3axis"}))
            q0 = np.array([0.0, 0.0, 0.3, 0.1, 0.4])
            qd0 = np.array([1.0, -0.5, 0.2, 0.3, 0.7])
            q, qd = cs.consistent_initial(0.0, q0, qd0, pvec, np.zeros(5))
            f, c = cs.residuals(0.0, q, qd, pvec, np.zeros(5))
            worst = float(max(np.max(np.abs(f)), np.max(np.abs(c))))
            return at_most(1e-12, worst, "|f| and |H q' + psi| after projection ")

        def multipliers() -> ClaimResult:
            got = [f"{len(self.series_for(self.resolve({'example': e})))}" for e in EXAMPLES]
            lam = [sum(n.startswith("lambda") for n in series_names(e)) for e in EXAMPLES]
            v2 = [system(e)[1].v2 for e in EXAMPLES]
            return ClaimResult(
                f"multipliers = v2 = {v2}", f"{lam} ({', '.join(got)} series)", lam == v2
            )

        return [
            Claim(
                "rheonomic-terms",
                "Time-dependent constraint (rod of length L(t) = 1 + 0.2 sin 2t): the generic code "
                "produces the df/dt terms psi (2.29) and Phi (2.27)",
                "(2.26), (2.27), (2.29)",
                rheonomic_terms,
            ),
            Claim(
                "rheonomic-drift",
                "Rod of prescribed length, RK45 rtol = atol = 1e-6, 20 s from theta0 = 1 rad: "
                "without stabilization the constraint drifts (max|f| 2.5e-4 m^2, error against the "
                "polar solution 7.6e-4 m); alpha = beta = 10 1/s holds it (5.9e-7 m^2, 3.4e-5 m)",
                "(2.27), (2.29), (2.34)",
                rheonomic_drift,
            ),
            Claim(
                "hand-forms",
                "The generic code gives the hand-derived H and Phi of the pendulum and Phi of the knife edge",
                "(2.20), (2.27), (2.28)",
                hand_forms,
            ),
            Claim(
                "H-size",
                "H is v2 x n: 1x2 (pendulums), 1x3 (knife edge), 2x5 (Problem 2.4 opened)",
                "(2.24)",
                shapes,
            ),
            Claim(
                "multipliers-v2",
                "One multiplier per constraint, lambda_1..lambda_v2 (not v1): 1, 1, 1, 2",
                "(2.24), (2.33)",
                multipliers,
            ),
            Claim(
                "pendulum-drift",
                "Pendulum, RK45 rtol = atol = 1e-6, 50 s from theta0 = 1 rad: without stabilization "
                "the constraint drifts and grows; Baumgarte alpha = beta = 5 keeps |f| <= 1e-5",
                "(2.34)",
                drift,
            ),
            Claim(
                "pendulum-accuracy",
                "Stabilized Cartesian pendulum (RK45, 1e-6) follows the angle ODE within 2e-3 m "
                "over 50 s (phase error of the integrator, which stabilization does not remove)",
                "(2.34)",
                pendulum_accuracy,
            ),
            Claim(
                "knife-edge",
                "Knife edge (F = 2 N, m = 1 kg, u0 = 0.5 m/s, theta' = 1 rad/s): speed along the "
                "blade u = 0.5 + 2 sin t, no side slip, theta' constant",
                "(2.18)-(2.19), (2.28), (2.34)",
                knife,
            ),
            Claim(
                "planar-3axis-accelerations",
                "Problem 2.4 as 5 coordinates + (2.12): (2.34) gives the accelerations of the "
                "reduced 3-DOF Lagrange model (5 random states)",
                "(2.12), (2.34)",
                p24,
            ),
            Claim(
                "planar-3axis-trajectory",
                "Problem 2.4 constrained run (DOP853, rtol 1e-10, alpha = beta = 5) follows the "
                "reduced model within 1e-7 over 10 s",
                "(2.34)",
                p24_traj,
            ),
            Claim(
                "initial-velocities",
                "Initial state projected onto (2.17) and velocities onto (2.29): residuals below 1e-12",
                "(2.17), (2.29)",
                init_vel,
            ),
        ]


def samples(values: dict[str, Any], t: Array) -> dict[str, Array]:
    """The series of a run with these values at the times ``t``."""
    params = LESSON.resolve(values)
    return LESSON.observation(params, t, ExampleRun(params).state(t))


@lru_cache(maxsize=1)
def pendulum_drift() -> dict[str, float]:
    """Pendulum, RK45 rtol = atol = 1e-6, 50 s, theta0 = 1: drift without and with
    Baumgarte (alpha = beta = 5)."""
    t = np.linspace(0, 50, 501)
    free = samples({"example": "pendulum", "stabilization": False}, t)
    stab = samples({"example": "pendulum", "stabilization": True}, t)
    f0, f1 = np.abs(free["f"]), np.abs(stab["f"])
    return {
        "free_max": float(np.max(f0)),
        "free_10": float(f0[100]),
        "free_50": float(f0[500]),
        "stab_max": float(np.max(f1)),
        "free_ref": float(np.max(free["position_error"])),
        "stab_ref": float(np.max(stab["position_error"])),
    }


@lru_cache(maxsize=1)
def rheonomic_drift_numbers() -> dict[str, float]:
    """Rod of prescribed length, RK45 rtol = atol = 1e-6, 20 s: max|f| and the position
    error against the polar reference, without and with alpha = beta = 10."""
    t = np.linspace(0, 20, 801)
    out = {}
    for tag, preset in (("free", "rheonomic-pendulum"), ("stab", "rheonomic-baumgarte")):
        s = samples(dict(LESSON.preset(preset).values), t)
        out[f"{tag}_f"] = float(np.max(np.abs(s["f"])))
        out[f"{tag}_err"] = float(np.max(s["position_error"]))
    return out


LESSON = ConstrainedDynamics()
