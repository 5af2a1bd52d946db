"""Chapter 2, §2.2: the formalized algorithm for systems with constraints, (2.17)-(2.34).

The loops of a mechanism are opened; the opened system ``A q'' = B + B*`` gets the
constraint reactions ``H^T lambda`` (2.25); differentiating the holonomic constraints
twice (2.27) and the nonholonomic ones once (2.28) gives ``H q'' = -Phi`` (2.30), which
eliminates the multipliers (2.33) and leaves (2.34).  The solver is
:class:`lessons.core.mechanics.ConstrainedSystem`, in the corrected form of the digest
(``H`` is ``v2 x n``; initial velocities from (2.29)).  Integrating (2.34) lets the
constraints drift; Baumgarte stabilization (not in the source) holds them.

Examples: a pendulum in Cartesian coordinates (holonomic), a knife edge on an inclined
plane (nonholonomic) and Problem 2.4 written as five coordinates with the two holonomic
constraints (2.12).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

from lessons.core.bodies import (
    IDENTITY_Q,
    bounds_of,
    box,
    cylinder,
    mesh_item,
    quat_z,
    segment_pose,
)
from lessons.core.constrained import ConstrainedSystem
from lessons.core.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
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
from lessons.core.lagrange import LagrangeModel
from lessons.core.steppers import OdeStepper, integrate
from lessons.planar_3axis import Planar3Axis, planar3_kinematics, planar3_symbols

T_ = dynamicsymbols._t
Array = np.ndarray
EXAMPLES = ("pendulum", "knife-edge", "planar-3axis")


def _sym(name: str, **kw: Any) -> sp.Symbol:
    return sp.Symbol(name, real=True, **kw)


# ---------------------------------------------------------------- the three systems


def pendulum_system() -> tuple[LagrangeModel, ConstrainedSystem]:
    """Point mass m at (x, y), y up, on a massless rod of length L: f = x^2 + y^2 - L^2."""
    x, y = dynamicsymbols("x y")
    m, g, L = _sym("m", positive=True), _sym("g", nonnegative=True), _sym("L", positive=True)
    T = m * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2
    model = LagrangeModel.build([x, y], T, m * g * y, T_, [m, g, L])
    return model, ConstrainedSystem.from_lagrange(model, f_hol=[x**2 + y**2 - L**2])


def knife_edge_system() -> tuple[LagrangeModel, ConstrainedSystem]:
    """Skate (x, y, theta) on an inclined plane, downhill force F along X; the blade
    cannot slide sideways: g = -sin(theta) x' + cos(theta) y' = 0 (nonholonomic)."""
    x, y, th = dynamicsymbols("x y theta")
    m, J, F = _sym("m", positive=True), _sym("J", positive=True), _sym("F")
    N = ReferenceFrame("N")
    P = Point("P")
    P.set_vel(N, x.diff(T_) * N.x + y.diff(T_) * N.y)
    T = m * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2 + J * th.diff(T_) ** 2 / 2
    model = LagrangeModel.build(
        [x, y, th], T, sp.S.Zero, T_, [m, J, F], forcelist=[(P, F * N.x)], frame=N
    )
    return model, ConstrainedSystem.from_lagrange(
        model, a_nh=[[-sp.sin(th), sp.cos(th), 0]], a0_nh=[0]
    )


def planar3_constrained() -> tuple[LagrangeModel, ConstrainedSystem]:
    """Problem 2.4 opened: q = (x_A, y_A, x_B, y_B, phi), (2.12) as two holonomic constraints."""
    s = planar3_symbols()
    xA, yA, phi, AB = s["xA"], s["yA"], s["phi"], s["AB"]
    xB, yB = dynamicsymbols("x_B y_B")
    N = ReferenceFrame("N")
    Tab = ReferenceFrame("Tab")
    Tab.set_ang_vel(N, -phi.diff(T_) * N.z)
    PA, PB = Point("A"), Point("B")
    PA.set_vel(N, xA.diff(T_) * N.x + yA.diff(T_) * N.y)
    PB.set_vel(N, xB.diff(T_) * N.x + yB.diff(T_) * N.y)
    vA2 = xA.diff(T_) ** 2 + yA.diff(T_) ** 2
    T = (
        (s["mA"] + s["mAB"]) * vA2 / 2
        + s["mB"] * (xB.diff(T_) ** 2 + yB.diff(T_) ** 2) / 2
        + s["J"] * phi.diff(T_) ** 2 / 2
    )
    forces = [
        (PA, s["FAx"] * N.x + s["FAy"] * N.y),
        (PB, s["FBx"] * N.x + s["FBy"] * N.y),
        (Tab, -s["Mphi"] * N.z),
    ]
    model = LagrangeModel.build(
        [xA, yA, xB, yB, phi],
        T,
        sp.S.Zero,
        T_,
        [s["mA"], s["mB"], s["mAB"], s["J"], AB],
        [s["FAx"], s["FAy"], s["FBx"], s["FBy"], s["Mphi"]],
        forcelist=forces,
        frame=N,
    )
    f1 = xB - xA - AB * (1 - sp.cos(phi))
    f2 = yB - yA - AB * sp.sin(phi)
    return model, ConstrainedSystem.from_lagrange(model, f_hol=[f1, f2])


_SYSTEMS: dict[str, tuple[LagrangeModel, ConstrainedSystem]] = {}


def system(example: str) -> tuple[LagrangeModel, ConstrainedSystem]:
    if example not in _SYSTEMS:
        _SYSTEMS[example] = {
            "pendulum": pendulum_system,
            "knife-edge": knife_edge_system,
            "planar-3axis": planar3_constrained,
        }[example]()
    return _SYSTEMS[example]


# forces of the Problem 2.4 example (the forward preset of the planar-3axis lesson)
_P3_FORCES: tuple[Callable[[float], float], ...] = (
    lambda t: 2 * np.sin(t),
    lambda t: 1.0,
    lambda t: 0.0,
    lambda t: 0.5 * np.cos(t),
    lambda t: 0.1 * np.cos(2 * t),
)
_P3_FORCE_TEXT = "F_Ax = 2 sin t, F_Ay = 1, F_Bx = 0, F_By = 0.5 cos t, M_phi = 0.1 cos 2t (N, N m)"


def setup(example: str, params: Params) -> dict[str, Any]:
    """Parameter vector, input law, consistent initial state and energy function."""
    model, cs = system(example)
    if example == "pendulum":
        m, g, L, th0 = (float(params[k]) for k in ("m", "g", "L", "theta0"))
        p = np.array([m, g, L])
        q0, qd0 = np.array([L * np.sin(th0), -L * np.cos(th0)]), np.zeros(2)
        u = lambda t, q, qd: np.zeros(0)  # noqa: E731
        energy = lambda q, qd: 0.5 * m * np.sum(qd**2, axis=0) + m * g * q[1]  # noqa: E731
    elif example == "knife-edge":
        m, J, F, u0, w0 = (float(params[k]) for k in ("m", "J", "F", "u0", "omega0"))
        p = np.array([m, J, F])
        q0, qd0 = np.zeros(3), np.array([u0, 0.0, w0])
        u = lambda t, q, qd: np.zeros(0)  # noqa: E731
        energy = lambda q, qd: 0.5 * m * (qd[0] ** 2 + qd[1] ** 2) + 0.5 * J * qd[2] ** 2 - F * q[0]  # noqa: E731
    else:
        lesson = Planar3Axis()
        pp = lesson.resolve()
        p = lesson.pvec(pp)
        AB = float(p[4])
        xB, yB = planar3_kinematics(0.0, 0.0, 0.0, AB, np)
        q0, qd0 = np.array([0.0, 0.0, float(xB), float(yB), 0.0]), np.zeros(5)
        u = lambda t, q, qd: np.array([f(t) for f in _P3_FORCES])  # noqa: E731
        energy = None
    q0, qd0 = cs.consistent_initial(0.0, q0, qd0, p, u(0.0, q0, qd0))
    return {"model": model, "cs": cs, "p": p, "q0": q0, "qd0": qd0, "u": u, "energy": energy}


def run_constrained(example: str, params: Params, t: Array) -> dict[str, Any]:
    """Integrate (2.34) on the samples; residuals, multipliers, energy and reference error."""
    S = setup(example, params)
    cs, p, u = S["cs"], S["p"], S["u"]
    a = float(params["alpha"]) if params["stabilization"] else 0.0
    b = float(params["beta"]) if params["stabilization"] else 0.0
    n = cs.n
    rtol = float(params["rtol"])
    calls = [0]
    base = cs.rhs(p, u, a, b)

    def counted(tt: float, yy: Array) -> Array:
        calls[0] += 1
        return base(tt, yy)

    y, message = integrate(
        counted,
        np.concatenate([S["q0"], S["qd0"]]),
        t,
        rtol=rtol,
        atol=rtol,
        method=str(params["integrator"]),
    )
    good = int(np.sum(np.all(np.isfinite(y), axis=0)))
    q, qd = y[:n], y[n:]
    f = np.full((cs.n_hol, len(t)), np.nan)
    c = np.full((cs.v2, len(t)), np.nan)
    lam = np.full((cs.v2, len(t)), np.nan)
    for k in range(good):
        uk = u(t[k], q[:, k], qd[:, k])
        f[:, k], c[:, k] = cs.residuals(float(t[k]), q[:, k], qd[:, k], p, uk)
        lam[:, k] = cs.solve(float(t[k]), q[:, k], qd[:, k], p, uk, a, b)[1]
    out: dict[str, Any] = {
        "q": q,
        "qd": qd,
        "f": f,
        "c": c,
        "lam": lam,
        "nfev": calls[0],
        "message": message,
        "S": S,
    }
    if S["energy"] is not None:
        E = S["energy"](q, qd)
        out["dE"] = E - E[0]
    out["ref_err"] = reference_error(example, params, t, q, qd, S)
    return out


def reference_error(
    example: str, params: Params, t: Array, q: Array, qd: Array, S: dict[str, Any]
) -> Array:
    """Distance to an independent solution: the angle ODE (pendulum), the closed form
    u = u0 + (F/m) sin(omega0 t) along the blade (knife edge), the reduced 3-DOF Lagrange
    model (Problem 2.4)."""
    if example == "pendulum":
        m, g, L, th0 = (float(params[k]) for k in ("m", "g", "L", "theta0"))
        ref = solve_ivp(
            lambda tt, z: [z[1], -g / L * np.sin(z[0])],
            (t[0], t[-1]),
            [th0, 0.0],
            t_eval=t,
            method="DOP853",
            rtol=1e-12,
            atol=1e-12,
        )
        th = np.full(len(t), np.nan)
        th[: ref.y.shape[1]] = ref.y[0]
        return np.hypot(q[0] - L * np.sin(th), q[1] + L * np.cos(th))
    if example == "knife-edge":
        # along-blade speed against its closed form (theta' stays omega0, theta = omega0 t)
        m, F, u0, w0 = (float(params[k]) for k in ("m", "F", "u0", "omega0"))
        u = qd[0] * np.cos(q[2]) + qd[1] * np.sin(q[2])
        exact = u0 + (F / (m * w0) * np.sin(w0 * t) if abs(w0) > 1e-12 else F * t / m)
        return np.abs(u - exact)
    lesson = Planar3Axis()
    pp = lesson.resolve()
    model = lesson.model(pp)
    rhs = model.rhs(S["p"], lambda tt, qq, qqd: np.array([f(tt) for f in _P3_FORCES]))
    ref = solve_ivp(
        rhs, (t[0], t[-1]), np.zeros(6), t_eval=t, method="DOP853", rtol=1e-12, atol=1e-12
    )
    r = np.full((3, len(t)), np.nan)
    r[:, : ref.y.shape[1]] = ref.y[:3]
    return np.max(np.abs(np.array([q[0], q[1], q[4]]) - r), axis=0)


class ConstrainedDynamics(Lesson):
    """§2.2: generic solver with Lagrange multipliers, (2.17)-(2.34), and its drift."""

    id = "constrained-dynamics"
    title = "Constrained dynamics with Lagrange multipliers"
    chapter = "2"
    problem = "§2.2"
    source = "Textbook §2.2, eqs (2.17)-(2.34)"
    summary = "Opened loops plus constraints: A q'' = B + H^T lambda, H q'' = -Phi; drift of the constraints and Baumgarte stabilization."
    order = 2.1
    t_end = 20.0
    params = (
        Param(
            "example",
            "choice",
            "pendulum",
            label="example",
            choices=EXAMPLES,
            group="method",
            help="pendulum (holonomic), knife edge (nonholonomic), Problem 2.4 with the constraints (2.12)",
        ),
        Param(
            "stabilization",
            "bool",
            False,
            label="Baumgarte stabilization",
            group="method",
            help="Phi -> Phi + 2 alpha (H q' + psi) + beta^2 f (not in the source)",
        ),
        Param("alpha", "float", 5.0, label="alpha", unit="1/s", min=0.0, max=200.0, group="method"),
        Param("beta", "float", 5.0, label="beta", unit="1/s", min=0.0, max=200.0, group="method"),
        Param(
            "integrator",
            "choice",
            "RK45",
            label="integrator",
            choices=("RK45", "DOP853", "Radau"),
            group="method",
        ),
        Param(
            "rtol",
            "float",
            1e-6,
            label="tolerance (rtol = atol)",
            min=1e-12,
            max=1e-2,
            group="method",
        ),
        Param(
            "m",
            "float",
            1.0,
            label="mass m",
            unit="kg",
            min=1e-3,
            max=1e3,
            help="pendulum and knife edge",
        ),
        Param("g", "float", 9.81, label="g", unit="m/s^2", min=0.0, max=100.0, help="pendulum"),
        Param(
            "L", "float", 1.0, label="rod length L", unit="m", min=1e-3, max=100.0, help="pendulum"
        ),
        Param(
            "theta0",
            "float",
            1.0,
            label="initial angle theta0",
            unit="rad",
            min=-3.1,
            max=3.1,
            group="initial",
            help="pendulum, released from rest",
        ),
        Param(
            "J",
            "float",
            0.1,
            label="skate inertia J",
            unit="kg m^2",
            min=1e-4,
            max=1e3,
            help="knife edge",
        ),
        Param(
            "F",
            "float",
            2.0,
            label="downhill force m g sin(alpha)",
            unit="N",
            min=-1e3,
            max=1e3,
            help="knife edge",
        ),
        Param(
            "u0",
            "float",
            0.5,
            label="initial speed along the blade",
            unit="m/s",
            min=-100.0,
            max=100.0,
            group="initial",
            help="knife edge",
        ),
        Param(
            "omega0",
            "float",
            1.0,
            label="turning rate theta'",
            unit="rad/s",
            min=-100.0,
            max=100.0,
            group="initial",
            help="knife edge",
        ),
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
        ),
    )
    plots = (
        PlotSpec("Constraint drift", ("f", "f_dot"), ""),
        PlotSpec("Energy error", ("energy_error",), "J"),
        PlotSpec("Error against an independent solution", ("reference_error",), ""),
        PlotSpec("Multipliers", ("lambda_1", "lambda_2"), ""),
        PlotSpec("Coordinates", ("q1", "q2", "q3"), ""),
    )

    # -- derivation ---------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        _, cs = system(str(params["example"]))
        steps = [
            DerivationStep(
                "Holonomic constraints", "", r"f_i(q,t)=0,\quad i=1,\dots,v_1", "(2.17)"
            ),
            DerivationStep(
                "Nonholonomic constraints, linear in the velocities",
                "The source says 'for the function f_i'; it means g_i.",
                r"g_i=a_{i1}\dot q_1+\dots+a_{in}\dot q_n+a_i^{*}=0,\quad i=v_1+1,\dots,v_2",
                "(2.18)-(2.19)",
                reconstructed="wording corrected: g_i, not f_i",
            ),
            DerivationStep(
                "d'Alembert principle with multipliers, loops opened",
                "",
                r"\delta q^{T}\left(-A\ddot q+B+B^{*}+H^{T}\lambda\right)=0",
                "(2.22)-(2.24)",
            ),
            DerivationStep(
                "H stacks the constraint gradients",
                "H has v2 rows (one per constraint) and n columns; the source calls it n x n.",
                r"H=\left[f_1'^{T}\cdots f_{v_1}'^{T}\;a_{v_1+1}^{T}\cdots a_{v_2}^{T}\right]^{T}\in\mathbb{R}^{v_2\times n}",
                "(2.24)",
                reconstructed="size corrected from n x n to v2 x n",
            ),
            DerivationStep(
                "Equations with multipliers", "", r"A\ddot q=B+B^{*}+H^{T}\lambda", "(2.25)"
            ),
            DerivationStep(
                "Velocity level",
                "Initial velocities must satisfy this (the source cites (2.30)).",
                r"H\dot q=-\psi(q,t)",
                "(2.29)",
                reconstructed="initial velocities come from (2.29), not (2.30); psi renames the source's first Phi",
            ),
            DerivationStep(
                "Acceleration level", "", r"H\ddot q=-\Phi(q,\dot q,t)", "(2.27), (2.28), (2.30)"
            ),
            DerivationStep(
                "Multipliers",
                "",
                r"\lambda=-\left(HA^{-1}H^{T}\right)^{-1}\left(HA^{-1}(B+B^{*})+\Phi\right)",
                "(2.33)",
            ),
            DerivationStep(
                "Accelerations",
                "",
                r"\ddot q=A^{-1}\left\{B+B^{*}-H^{T}\left(HA^{-1}H^{T}\right)^{-1}\left[HA^{-1}(B+B^{*})+\Phi\right]\right\}",
                "(2.34)",
            ),
            DerivationStep(
                "This example: A (from LagrangesMethod)",
                "",
                sp.Eq(sp.Symbol("A"), cs.A, evaluate=False),
            ),
            DerivationStep(
                "This example: B",
                "Generalized forces plus the velocity and gravity terms of the Lagrange equations.",
                sp.Eq(sp.Symbol("B"), cs.B, evaluate=False),
            ),
            DerivationStep(
                "This example: H",
                f"{cs.v2} x {cs.n}",
                sp.Eq(sp.Symbol("H"), cs.H, evaluate=False),
                "(2.24)",
            ),
            DerivationStep(
                "This example: Phi",
                "",
                sp.Eq(sp.Symbol(r"\Phi"), sp.simplify(cs.Phi), evaluate=False),
                "(2.30)",
            ),
            DerivationStep(
                "Baumgarte stabilization (not in the source)",
                "Constraint errors obey a damped equation instead of drifting.",
                r"\Phi\to\Phi+2\alpha\left(H\dot q+\psi\right)+\beta^{2}f",
                reconstructed="addition of the digest: the source integrates (2.34) as it stands",
            ),
        ]
        return steps

    # -- runs -------------------------------------------------------------------------

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        t = np.linspace(0.0, t_end, int(min(2001, max(201, 40 * t_end + 1))))
        ex = str(params["example"])
        r = run_constrained(ex, params, t)
        series = self._series(ex, r, t)
        metrics = {
            "max_abs_f": float(np.nanmax(np.abs(r["f"]))) if r["f"].size else 0.0,
            "max_abs_velocity_constraint": float(np.nanmax(np.abs(r["c"]))),
            "max_reference_error": float(np.nanmax(r["ref_err"])),
            "nfev": r["nfev"],
            "H_shape": f"{r['S']['cs'].v2} x {r['S']['cs'].n}",
        }
        if "dE" in r:
            metrics["max_abs_energy_error"] = float(np.nanmax(np.abs(r["dE"])))
        return RunResult(
            self.id, None, params.raw(), t, series, metrics, [r["message"]] if r["message"] else []
        )

    def _series(self, ex: str, r: dict[str, Any], t: Array) -> dict[str, Array]:
        q, qd = r["q"], r["qd"]
        out: dict[str, Array] = {}
        for k in range(q.shape[0]):
            out[f"q{k + 1}"] = q[k]
            out[f"q{k + 1}_dot"] = qd[k]
        f = r["f"]
        out["f"] = np.nanmax(np.abs(f), axis=0) if f.size else np.zeros(len(t))
        out["f_dot"] = np.nanmax(np.abs(r["c"]), axis=0)
        out["energy_error"] = r.get("dE", np.zeros(len(t)))
        out["reference_error"] = r["ref_err"]
        for k in range(r["lam"].shape[0]):
            out[f"lambda_{k + 1}"] = r["lam"][k]
        if ex == "knife-edge":
            th = q[2]
            out["u_along_blade"] = qd[0] * np.cos(th) + qd[1] * np.sin(th)
        return out

    def stepper(self, params: Params) -> Stepper:
        def make(
            ps: Params,
        ) -> tuple[Array, Callable[[float, Array], Array], Callable[[float, Array], Frame]]:
            ex = str(ps["example"])
            S = setup(ex, ps)
            cs, p, u = S["cs"], S["p"], S["u"]
            a = float(ps["alpha"]) if ps["stabilization"] else 0.0
            b = float(ps["beta"]) if ps["stabilization"] else 0.0
            n = cs.n
            E0 = S["energy"](S["q0"], S["qd0"]) if S["energy"] else 0.0

            def frame_of(tt: float, y: Array) -> Frame:
                q, qd = y[:n], y[n:]
                uk = u(tt, q, qd)
                f, c = cs.residuals(tt, q, qd, p, uk)
                _, lam = cs.solve(tt, q, qd, p, uk, a, b)
                fr = Frame(t=float(tt))
                fr.scalars["f"] = float(np.max(np.abs(f))) if f.size else 0.0
                fr.scalars["f_dot"] = float(np.max(np.abs(c)))
                fr.scalars["energy_error"] = float(S["energy"](q, qd) - E0) if S["energy"] else 0.0
                for k in range(n):
                    fr.scalars[f"q{k + 1}"] = float(q[k])
                for k, lv in enumerate(lam):
                    fr.scalars[f"lambda_{k + 1}"] = float(lv)
                reaction = cs.parts(tt, q, qd, p, uk)["H"].T @ lam
                self._pose(ex, ps, fr, q, reaction)
                return fr

            return np.concatenate([S["q0"], S["qd0"]]), cs.rhs(p, u, a, b), frame_of

        return OdeStepper(
            make, params, rtol=float(params["rtol"]), method=str(params["integrator"])
        )

    # -- scene --------------------------------------------------------------------------

    def scene(self, params: Params) -> SceneSpec:
        ex = str(params["example"])
        if ex == "pendulum":
            L = float(params["L"])
            bob = mesh_item("bob", _sphere(0.06 * L), (200, 80, 60))
            rod = cylinder("rod", 0.01 * L, L, (90, 90, 90))
            pivot = box(
                "pivot", (0.1 * L, 0.1 * L, 0.05 * L), (60, 60, 60), center=(0, 0, 0.025 * L)
            )
            return SceneSpec(
                bounds=bounds_of(np.array([[-L, -0.2 * L, -L], [L, 0.2 * L, 0.2 * L]]), 0.05),
                meshes=[pivot],
                bodies=[bob, rod],
                moving_points={"bob": (200, 80, 60)},
                moving_vectors={"reaction": (60, 60, 200)},
            )
        if ex == "knife-edge":
            r = self.simulate(params, 10.0)
            xs, ys = r.series["q1"], r.series["q2"]
            ok = np.isfinite(xs) & np.isfinite(ys)
            lo = np.array([np.min(xs[ok], initial=0.0), np.min(ys[ok], initial=0.0)])
            hi = np.array([np.max(xs[ok], initial=0.0), np.max(ys[ok], initial=0.0)])
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
        lesson = Planar3Axis()
        spec = lesson.scene(lesson.resolve())
        spec.moving_vectors = {"reaction at B": (60, 60, 200)}
        spec.moving_points = {"C (middle of AB)": (120, 190, 120)}
        return spec

    def _pose(self, ex: str, ps: Params, fr: Frame, q: Array, reaction: Array) -> None:
        if ex == "pendulum":
            L = float(ps["L"])
            bob = np.array([q[0], 0.0, q[1]])
            fr.poses["bob"] = (bob, IDENTITY_Q.copy())
            fr.poses["rod"] = segment_pose(np.zeros(3), bob)
            fr.points["bob"] = bob[None, :]
            mg = float(ps["m"]) * max(float(ps["g"]), 1e-9)
            fr.vectors["reaction"] = (
                bob[None, :],
                (0.3 * L / mg) * np.array([[reaction[0], 0.0, reaction[1]]]),
            )
        elif ex == "knife-edge":
            p = np.array([q[0], q[1], 0.0])
            fr.poses["skate"] = (p, quat_z(float(q[2])))
            fr.points["skate"] = p[None, :]
            fr.vectors["reaction"] = (p[None, :], 0.1 * np.array([[reaction[0], reaction[1], 0.0]]))
        else:
            lesson = Planar3Axis()
            pp = lesson.resolve()
            AB = float(pp["AB"])
            A = np.array([q[0], q[1], 0.0])
            B = np.array([q[2] - AB, q[3], 0.0])
            h = 0.25 * AB * 0.3
            fr.poses["module A"] = (A, IDENTITY_Q.copy())
            fr.poses["module B"] = (B, IDENTITY_Q.copy())
            mid = (A + B) / 2
            fr.poses["table"] = (mid + [0, 0, h], quat_z(np.pi - float(q[4])))
            fr.points["C (middle of AB)"] = (mid + [0, 0, h])[None, :]
            fr.vectors["reaction at B"] = (
                (B + [0, 0, 2 * h])[None, :],
                0.05 * np.array([[reaction[2], reaction[3], 0.0]]),
            )

    # -- claims ---------------------------------------------------------------------------

    def claims(self) -> list[Claim]:
        def hand_forms() -> ClaimResult:
            _, cs = system("pendulum")
            x, y = cs.q
            xd, yd = cs.qd
            ok = (
                sp.simplify(cs.H - sp.Matrix([[2 * x, 2 * y]])) == sp.zeros(1, 2)
                and sp.simplify(cs.Phi[0] - 2 * (xd**2 + yd**2)) == 0
            )
            _, ck = system("knife-edge")
            th, thd = ck.q[2], ck.qd[2]
            ok2 = (
                sp.simplify(ck.Phi[0] + thd * (ck.qd[0] * sp.cos(th) + ck.qd[1] * sp.sin(th))) == 0
            )
            return ClaimResult(
                "H = [2x, 2y], Phi = 2(x'^2 + y'^2); knife edge Phi = -theta'(x' cos theta + y' sin theta)",
                "match" if ok and ok2 else "differ",
                bool(ok and ok2),
            )

        def shapes() -> ClaimResult:
            got = [f"{system(e)[1].v2}x{system(e)[1].n}" for e in EXAMPLES]
            want = ["1x2", "1x3", "2x5"]
            return ClaimResult(", ".join(want), ", ".join(got), got == want)

        def drift() -> ClaimResult:
            d = pendulum_drift()
            ok = d["free_max"] > 5e-5 and d["free_50"] > 3 * d["free_10"] and d["stab_max"] <= 1e-5
            return ClaimResult(
                "no stabilization: max|f| > 5e-5 and |f(50)| > 3 |f(10)| (measured 1.4e-4, 2.5e-5 -> 1.4e-4); alpha = beta = 5: max|f| <= 1e-5 (measured 2.3e-6)",
                f"max|f| = {d['free_max']:.3g} (|f(10)| = {d['free_10']:.3g}, |f(50)| = {d['free_50']:.3g}); stabilized max|f| = {d['stab_max']:.3g}",
                bool(ok),
            )

        def pendulum_accuracy() -> ClaimResult:
            d = pendulum_drift()
            return at_most(2e-3, d["stab_ref"], "stabilized position error vs angle ODE (m) ")

        def knife() -> ClaimResult:
            p = self.resolve({"example": "knife-edge", "integrator": "DOP853", "rtol": 1e-10})
            t = np.linspace(0, 10, 401)
            r = run_constrained("knife-edge", p, t)
            q, qd = r["q"], r["qd"]
            u_blade = qd[0] * np.cos(q[2]) + qd[1] * np.sin(q[2])
            err = float(np.max(np.abs(u_blade - (0.5 + 2.0 * np.sin(t)))))
            g = float(np.max(np.abs(r["c"])))
            wdev = float(np.max(np.abs(qd[2] - 1.0)))
            ok = err <= 1e-7 and g <= 1e-8 and wdev <= 1e-12
            return ClaimResult(
                "|u - (0.5 + 2 sin t)| <= 1e-7, |g| <= 1e-8, theta' = 1",
                f"{err:.3g}, {g:.3g}, {wdev:.3g}",
                ok,
            )

        def p24() -> ClaimResult:
            return at_most(
                1e-12, planar3_acceleration_difference(), "max |q'' (2.34) - q'' reduced 3-DOF| "
            )

        def p24_traj() -> ClaimResult:
            p = self.resolve(
                {
                    "example": "planar-3axis",
                    "stabilization": True,
                    "integrator": "DOP853",
                    "rtol": 1e-10,
                }
            )
            t = np.linspace(0, 10, 201)
            r = run_constrained("planar-3axis", p, t)
            return at_most(
                1e-7,
                float(np.nanmax(r["ref_err"])),
                "max |(x_A, y_A, phi) constrained - reduced| over 10 s ",
            )

        def init_vel() -> ClaimResult:
            _, cs = system("planar-3axis")
            lesson = Planar3Axis()
            pvec = lesson.pvec(lesson.resolve())
            q, qd = cs.consistent_initial(
                0.0,
                np.array([0.0, 0.0, 0.3, 0.1, 0.4]),
                np.array([1.0, -0.5, 0.2, 0.3, 0.7]),
                pvec,
                np.zeros(5),
            )
            f, c = cs.residuals(0.0, q, qd, pvec, np.zeros(5))
            return at_most(
                1e-12,
                float(max(np.max(np.abs(f)), np.max(np.abs(c)))),
                "|f| and |H q' + psi| after projection ",
            )

        def rheonomic() -> ClaimResult:
            x, y, xd, yd = (sp.Symbol(n, real=True) for n in ("x", "y", "x_d", "y_d"))
            L = 1 + sp.Rational(1, 5) * sp.sin(2 * T_)
            cs = ConstrainedSystem.build(
                [x, y], [xd, yd], T_, sp.eye(2), sp.Matrix([0, -1]), f_hol=[x**2 + y**2 - L**2]
            )
            ok = (
                sp.simplify(cs.psi[0] + 2 * L * L.diff(T_)) == 0
                and sp.simplify(
                    cs.Phi[0] - 2 * (xd**2 + yd**2) + 2 * (L.diff(T_) ** 2 + L * L.diff(T_, 2))
                )
                == 0
            )
            return ClaimResult(
                "psi = -2 L L', Phi = 2(x'^2 + y'^2) - 2(L'^2 + L L'') for L = 1 + 0.2 sin 2t",
                "match" if ok else "differ",
                bool(ok),
            )

        return [
            Claim(
                "rheonomic-terms",
                "Time-dependent constraint (pendulum of length L(t) = 1 + 0.2 sin 2t): the generic code produces the df/dt terms psi (2.29) and Phi (2.27)",
                "(2.26), (2.27), (2.29)",
                rheonomic,
            ),
            Claim(
                "hand-forms",
                "The generic code gives the hand-derived H and Phi of the pendulum and Phi of the knife edge",
                "(2.20), (2.27), (2.28)",
                hand_forms,
            ),
            Claim(
                "H-size",
                "H is v2 x n: 1x2 (pendulum), 1x3 (knife edge), 2x5 (Problem 2.4 opened)",
                "(2.24)",
                shapes,
            ),
            Claim(
                "pendulum-drift",
                "Pendulum, RK45 rtol = atol = 1e-6, 50 s from theta0 = 1 rad: without stabilization the constraint drifts and grows; Baumgarte alpha = beta = 5 keeps |f| <= 1e-5",
                "(2.34)",
                drift,
            ),
            Claim(
                "pendulum-accuracy",
                "Stabilized Cartesian pendulum (RK45, 1e-6) follows the angle ODE within 2e-3 m over 50 s (measured 1.6e-3: phase error of the integrator, which stabilization does not remove)",
                "(2.34)",
                pendulum_accuracy,
            ),
            Claim(
                "knife-edge",
                "Knife edge (F = 2 N, m = 1 kg, u0 = 0.5 m/s, theta' = 1 rad/s): speed along the blade u = 0.5 + 2 sin t, no side slip, theta' constant",
                "(2.18)-(2.19), (2.28), (2.34)",
                knife,
            ),
            Claim(
                "planar-3axis-accelerations",
                "Problem 2.4 as 5 coordinates + (2.12): (2.34) gives the accelerations of the reduced 3-DOF Lagrange model (5 random states)",
                "(2.12), (2.34)",
                p24,
            ),
            Claim(
                "planar-3axis-trajectory",
                "Problem 2.4 constrained run (DOP853, rtol 1e-10, alpha = beta = 5) follows the reduced model within 1e-7 over 10 s",
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


def _sphere(r: float) -> Any:
    import trimesh

    return trimesh.creation.icosphere(subdivisions=2, radius=r)


_DRIFT: dict[str, float] = {}


def pendulum_drift() -> dict[str, float]:
    """Pendulum, RK45 rtol = atol = 1e-6, 50 s, theta0 = 1: drift without and with
    Baumgarte (alpha = beta = 5).  Cached: two runs of ~7000 evaluations."""
    if not _DRIFT:
        lesson = ConstrainedDynamics()
        t = np.linspace(0, 50, 501)
        free = run_constrained(
            "pendulum", lesson.resolve({"example": "pendulum", "stabilization": False}), t
        )
        stab = run_constrained(
            "pendulum", lesson.resolve({"example": "pendulum", "stabilization": True}), t
        )
        f0, f1 = np.abs(free["f"][0]), np.abs(stab["f"][0])
        _DRIFT.update(
            free_max=float(np.max(f0)),
            free_10=float(f0[100]),
            free_50=float(f0[500]),
            stab_max=float(np.max(f1)),
            free_ref=float(np.max(free["ref_err"])),
            stab_ref=float(np.max(stab["ref_err"])),
        )
    return dict(_DRIFT)


def planar3_acceleration_difference(seed: int = 1) -> float:
    """max |q'' of (2.34) - q'' of the reduced model| over 5 random consistent states."""
    _, cs = system("planar-3axis")
    lesson = Planar3Axis()
    pp = lesson.resolve()
    red = lesson.model(pp)
    p = lesson.pvec(pp)
    AB = float(p[4])
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(5):
        xA, yA, phi = rng.normal(size=3)
        vxA, vyA, w = rng.normal(size=3)
        u = rng.normal(size=5)
        xB, yB = planar3_kinematics(xA, yA, phi, AB, np)
        vxB, vyB = vxA + AB * np.sin(phi) * w, vyA + AB * np.cos(phi) * w
        qdd, _ = cs.solve(
            0.0, np.array([xA, yA, xB, yB, phi]), np.array([vxA, vyA, vxB, vyB, w]), p, u
        )
        qr = red.accelerations(np.array([xA, yA, phi]), np.array([vxA, vyA, w]), 0.0, p, u)
        worst = max(worst, float(np.max(np.abs(qdd[[0, 1, 4]] - qr))))
    return worst


LESSON = ConstrainedDynamics()

__all__ = [
    "ConstrainedDynamics",
    "LESSON",
    "pendulum_drift",
    "planar3_acceleration_difference",
    "run_constrained",
    "system",
]
