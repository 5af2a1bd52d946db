"""The four examples of the §2.2 lesson: their systems, runs and observed quantities.

* a pendulum in Cartesian coordinates, f = x^2 + y^2 - L^2 (holonomic, (2.17));
* the same pendulum on a rod whose length is prescribed in time,
  L(t) = L (1 + epsilon sin nu t) (rheonomic: df/dt enters (2.29) and (2.27));
* a knife edge on an inclined plane, -sin(theta) x' + cos(theta) y' = 0 (nonholonomic,
  (2.18)-(2.19));
* Problem 2.4 written as five coordinates with the two holonomic constraints (2.12).

Each is built once as a :class:`analyzer_lab.lessons.mechanics.lagrange.constrained.ConstrainedSystem` (corrected
form: ``H`` is ``v2 x n``) and evaluated by
:class:`analyzer_lab.lessons.mechanics.lagrange.constraint_eval.ConstraintEval`.
An :class:`ExampleRun` is one dense solution of (2.34) per parameter set
(:mod:`analyzer_lab.lessons.kit.dense_solution`; its right-hand side is (2.34) generated once on plain
floats, :meth:`ConstraintEval.accelerations`), shared by the lesson's headless run and its
live stepper, next to an independent reference solution (a closed form where there is
one); :func:`observe_example` computes
every quantity the lesson declares from that state.
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import numpy as np
import scipy.special
import sympy as sp
from analyzer_lab.lessons.kit.contract import Params, Series
from analyzer_lab.lessons.kit.dense_solution import DenseSolution
from analyzer_lab.lessons.mechanics.lagrange.constrained import ConstrainedSystem
from analyzer_lab.lessons.mechanics.lagrange.constraint_eval import ConstraintEval
from analyzer_lab.lessons.mechanics.lagrange.model import LagrangeModel
from analyzer_lab.lessons.mechanics.positioners.planar3 import (
    body_value,
    body_values,
    planar3_kinematics,
    planar3_model,
    planar3_symbols,
    reduced_model,
)
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

T_ = dynamicsymbols._t
Array = np.ndarray
PENDULUMS = ("pendulum", "rheonomic-pendulum")
EXAMPLES = (*PENDULUMS, "knife-edge", "planar-3axis")
COORDS = {
    "pendulum": ("x", "y"),
    "rheonomic-pendulum": ("x", "y"),
    "knife-edge": ("x", "y", "theta"),
    "planar-3axis": ("x_A", "y_A", "x_B", "y_B", "phi"),
}


def _sym(name: str, **kw: Any) -> sp.Symbol:
    return sp.Symbol(name, real=True, **kw)


# ---------------------------------------------------------------- the four systems


def pendulum_system(rheonomic: bool) -> tuple[LagrangeModel, ConstrainedSystem]:
    """Point mass m at (x, y), y up, on a massless rod: f = x^2 + y^2 - L^2, with
    L(t) = L (1 + epsilon sin nu t) when ``rheonomic`` (the constraint depends on t)."""
    x, y = dynamicsymbols("x y")
    m, g, L = _sym("m", positive=True), _sym("g", nonnegative=True), _sym("L", positive=True)
    eps, nu = _sym("epsilon"), _sym("nu")
    T = m * (x.diff(T_) ** 2 + y.diff(T_) ** 2) / 2
    model = LagrangeModel.build(
        [x, y], T, m * g * y, T_, [m, g, L, eps, nu][: 5 if rheonomic else 3]
    )
    length = L * (1 + eps * sp.sin(nu * T_)) if rheonomic else L
    return model, ConstrainedSystem.from_lagrange(model, f_hol=[x**2 + y**2 - length**2])


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
    model = planar3_model([xA, yA, xB, yB, phi], xB, yB)
    coupled = planar3_kinematics(xA, yA, phi, AB)  # (2.12)
    return model, ConstrainedSystem.from_lagrange(model, f_hol=[xB - coupled[0], yB - coupled[1]])


@cache
def system(example: str) -> tuple[LagrangeModel, ConstrainedSystem]:
    if example in PENDULUMS:
        return pendulum_system(example == "rheonomic-pendulum")
    return knife_edge_system() if example == "knife-edge" else planar3_constrained()


@cache
def evaluator(example: str) -> ConstraintEval:
    return ConstraintEval(system(example)[1])


# forces of the Problem 2.4 example (the forward preset of the planar-3axis lesson)
P3_FORCE_TEXT = "F_Ax = 2 sin t, F_Ay = 1, F_Bx = 0, F_By = 0.5 cos t, M_phi = 0.1 cos 2t (N, N m)"


def inputs_of(example: str, t: Array) -> Array:
    """The inputs (forces) of the example at the times ``t``: shape (k, len(t))."""
    if example != "planar-3axis":
        return np.zeros((0, len(t)))
    one = np.ones(len(t))
    return np.array([2 * np.sin(t), one, 0 * one, 0.5 * np.cos(t), 0.1 * np.cos(2 * t)])


def inputs_at(example: str, t: float) -> list[float]:
    """:func:`inputs_of` at one time, on plain floats (the integrator asks thousands of times)."""
    if example != "planar-3axis":
        return []
    return [2 * math.sin(t), 1.0, 0.0, 0.5 * math.cos(t), 0.1 * math.cos(2 * t)]


def physical(params: Params) -> Array:
    """The parameter vector of the example's system."""
    ex = str(params["example"])
    if ex == "planar-3axis":
        return body_values()
    names = {"pendulum": "m g L", "rheonomic-pendulum": "m g L eps nu", "knife-edge": "m J F"}
    return np.array([float(params[k]) for k in names[ex].split()])


def rod_length(params: Params, t: Array) -> tuple[Array, Array]:
    """L(t) and L'(t) of the pendulums (constant L unless rheonomic)."""
    L, eps, nu = float(params["L"]), float(params["eps"]), float(params["nu"])
    if params["example"] != "rheonomic-pendulum":
        return np.full(np.shape(t), L), np.zeros(np.shape(t))
    return L * (1 + eps * np.sin(nu * t)), L * eps * nu * np.cos(nu * t)


def stabilization(params: Params) -> tuple[float, float]:
    on = bool(params["stabilization"])
    return (float(params["alpha"]), float(params["beta"])) if on else (0.0, 0.0)


def start_state(params: Params, t0: float) -> tuple[Array, Array]:
    """The example's start (before the projection onto (2.17) and (2.29))."""
    ex = str(params["example"])
    if ex in PENDULUMS:
        L, _ = rod_length(params, np.array([t0]))
        th0 = float(params["theta0"])
        return L[0] * np.array([np.sin(th0), -np.cos(th0)]), np.zeros(2)
    if ex == "knife-edge":
        return np.zeros(3), np.array([float(params["u0"]), 0.0, float(params["omega0"])])
    xB, yB = planar3_kinematics(0.0, 0.0, 0.0, body_value("AB"), np)
    return np.array([0.0, 0.0, float(xB), float(yB), 0.0]), np.zeros(5)


class KnifeReference:
    """Closed form of the knife edge from a state at t0: theta' stays omega, and the speed
    along the blade is u = u(t0) + F/(m omega) (sin theta(t) - sin theta(t0))."""

    failure = ""
    t_covered = np.inf

    def __init__(self, params: Params, t0: float, q: Array, qd: Array) -> None:
        self.F_m = float(params["F"]) / float(params["m"])
        self.t0, self.th0, self.w = t0, float(q[2]), float(qd[2])
        self.u0 = float(qd[0] * np.cos(q[2]) + qd[1] * np.sin(q[2]))

    def extend(self, t: float) -> None:
        """Nothing to compute: a closed form covers every time."""

    def state(self, t: Array) -> Array:
        s = np.asarray(t, dtype=float) - self.t0
        if abs(self.w) > 1e-12:
            turn = (np.sin(self.th0 + self.w * s) - np.sin(self.th0)) / self.w
        else:
            turn = np.cos(self.th0) * s
        return (self.u0 + self.F_m * turn)[:, None]


class PendulumReference:
    """Closed form of the angle ODE theta'' = -(g/L) sin(theta) from ``(theta, theta')``
    at t0, by Jacobi's elliptic functions with k^2 = sin^2(theta/2) + (theta'/2 w0)^2,
    w0 = sqrt(g/L): swinging (k < 1) sin(theta/2) = k sn(u | k^2), theta' = 2 k w0 cn,
    u = w0 (t - t0) + u0; going over the top (k >= 1) theta/2 = am(v | 1/k^2), theta' =
    2 k w0 dn, v = k w0 (t - t0) + v0 (signed by the direction of turning)."""

    failure = ""
    t_covered = np.inf

    def __init__(self, g: float, L: float, t0: float, theta: float, omega: float) -> None:
        self.t0, self.theta, self.omega = t0, theta, omega
        self.w0 = math.sqrt(g / L)
        if self.w0 == 0.0:
            return
        half = math.remainder(theta, 2 * math.pi) / 2  # in [-pi/2, pi/2]
        self.k = math.sqrt(math.sin(half) ** 2 + (omega / (2 * self.w0)) ** 2)
        self.sign = 1.0 if omega >= 0 else -1.0
        if self.k < 1.0:
            m = self.k**2
            s0 = min(max(math.sin(half) / self.k, -1.0), 1.0) if self.k > 0 else 0.0
            u0 = float(scipy.special.ellipkinc(math.asin(s0), m))
            self.u0 = u0 if omega >= 0 else 2 * float(scipy.special.ellipk(m)) - u0
        else:
            self.v0 = float(scipy.special.ellipkinc(self.sign * theta / 2, 1 / self.k**2))

    def extend(self, t: float) -> None:
        """Nothing to compute: a closed form covers every time."""

    def state(self, t: Array) -> Array:
        """``(theta, theta')`` at the times ``t``: shape ``(len(t), 2)``."""
        s = np.asarray(t, dtype=float) - self.t0
        if self.w0 == 0.0:  # no gravity: turning at a constant rate
            return np.column_stack([self.theta + self.omega * s, np.full_like(s, self.omega)])
        if self.k < 1.0:
            sn, cn, _, _ = scipy.special.ellipj(self.w0 * s + self.u0, self.k**2)
            th = 2 * np.arcsin(self.k * sn)
            return np.column_stack([th, 2 * self.k * self.w0 * cn])
        _, _, dn, am = scipy.special.ellipj(self.k * self.w0 * s + self.v0, 1 / self.k**2)
        return np.column_stack([2 * self.sign * am, 2 * self.sign * self.k * self.w0 * dn])


def reference(
    params: Params, t0: float, q: Array, qd: Array
) -> DenseSolution | KnifeReference | PendulumReference:
    """An independent solution from the same state: the angle ODE of the pendulum (polar
    coordinates; its closed form for a fixed rod, DOP853 at rtol = atol = 1e-12 for the rod
    length L(t)), the closed form of the knife edge, the reduced 3-DOF Lagrange model of
    Problem 2.4 (DOP853, rtol = atol = 1e-12)."""
    ex = str(params["example"])
    if ex == "knife-edge":
        return KnifeReference(params, t0, q, qd)
    if ex in PENDULUMS:
        r2 = q[0] ** 2 + q[1] ** 2
        th0, w0 = float(np.arctan2(q[0], -q[1])), float((q[0] * qd[1] - q[1] * qd[0]) / r2)
        g, L0 = float(params["g"]), float(params["L"])
        if ex == "pendulum":
            return PendulumReference(g, L0, t0, th0, w0)
        eps, nu = float(params["eps"]), float(params["nu"])

        def angle(t: float, z: Array) -> Array:
            # rod_length at one time, on floats (the integrator asks thousands of times)
            th, w = float(z[0]), float(z[1])
            L, Ld = L0 * (1 + eps * math.sin(nu * t)), L0 * eps * nu * math.cos(nu * t)
            return np.array([w, -(g * math.sin(th) + 2 * Ld * w) / L])

        return DenseSolution(angle, t0, np.array([th0, w0]), "DOP853", 1e-12, 1e-12)
    u = lambda t, qq, qqd: inputs_of(ex, np.array([t]))[:, 0]  # noqa: E731
    rhs = reduced_model().rhs(body_values(), u)
    y0 = np.concatenate([q[[0, 1, 4]], qd[[0, 1, 4]]])
    return DenseSolution(rhs, t0, y0, "DOP853", 1e-12, 1e-12)


class ExampleRun:
    """One run from ``(t0, state)`` (the example's start when ``start`` is None): the
    state projected onto (2.17) and (2.29), (2.34) integrated densely, and the reference
    from the same state.  ``state(t)`` is ``[q, q', reference]`` at the times ``t``."""

    def __init__(self, params: Params, t0: float = 0.0, start: Array | None = None) -> None:
        ex = str(params["example"])
        _, cs = system(ex)
        ev, p, n = evaluator(ex), physical(params), cs.n
        a, b = stabilization(params)
        q0, qd0 = start_state(params, t0) if start is None else (start[:n], start[n : 2 * n])
        q0, qd0 = cs.consistent_initial(t0, q0, qd0, p, inputs_of(ex, np.array([t0]))[:, 0])

        acc, pl = ev.accelerations(), p.tolist()

        def rhs(t: float, y: Array) -> Array:
            # (2.34) on plain floats, generated once per example
            yl = y.tolist()
            q, qd = yl[:n], yl[n:]
            try:
                qdd = acc(q, qd, t, pl, inputs_at(ex, t), a, b)
            except ArithmeticError:  # a singular position: the solution ends here
                return np.full(2 * n, np.nan)
            return np.array(qd + qdd)

        rtol, method = float(params["rtol"]), str(params["integrator"])
        self.main = DenseSolution(rhs, t0, np.concatenate([q0, qd0]), method, rtol, rtol)
        self.reference = reference(params, t0, q0, qd0)

    @property
    def failure(self) -> str:
        return self.main.failure or self.reference.failure

    @property
    def t_covered(self) -> float:
        return min(self.main.t_covered, self.reference.t_covered)

    def extend(self, t: float) -> None:
        self.main.extend(t)
        self.reference.extend(t)

    def state(self, t: Array) -> Array:
        return np.hstack([self.main.state(t), self.reference.state(t)])


# ---------------------------------------------------------------- what is observed


def _s(name: str, unit: str, text: str) -> Series:
    return Series(name, unit, text)


_LENGTHS = ("x", "y", "x_A", "y_A", "x_B", "y_B")
_GREEK = {"theta": "θ", "phi": "φ"}
SERIES = (
    *(_s(c, "m", f"coordinate {c}") for c in _LENGTHS),
    *(_s(c, "rad", f"coordinate {_GREEK[c]}") for c in ("theta", "phi")),
    *(_s(f"{c}_dot", "m/s", f"velocity {c[0]}\u0307{c[1:]}") for c in _LENGTHS),
    *(_s(f"{c}_dot", "rad/s", f"angular velocity {_GREEK[c]}\u0307") for c in ("theta", "phi")),
    _s("length", "m", "prescribed rod length L(t) = L (1 + ε sin νt)"),
    _s("f", "m^2", "constraint residual f = x² + y² - L(t)² (2.17)"),
    _s("f_dot", "m^2/s", "velocity-level residual H q̇ + ψ (2.26)"),
    _s("g", "m/s", "side slip of the blade g = -sin θ ẋ + cos θ ẏ (2.19)"),
    _s("f_1", "m", "residual of x_B = x_A + AB (1 - cos φ) (2.12)"),
    _s("f_2", "m", "residual of y_B = y_A + AB sin φ (2.12)"),
    _s("f_1_dot", "m/s", "velocity-level residual of f_1 (2.26)"),
    _s("f_2_dot", "m/s", "velocity-level residual of f_2 (2.26)"),
    _s("lambda", "N/m", "multiplier of the rod (2.33); the reaction is 2λ (x, y)"),
    _s("lambda_1", "N", "first multiplier (2.33)"),
    _s("lambda_2", "N", "second multiplier (2.33)"),
    _s("energy_error", "J", "total energy minus its value at the start"),
    _s("position_error", "m", "distance to the independent reference solution"),
    _s("phi_error", "rad", "|φ - φ of the reduced 3-DOF model|"),
    _s("u_along_blade", "m/s", "speed along the blade ẋ cos θ + ẏ sin θ"),
    _s("speed_error", "m/s", "|u - its closed form u₀ + F/(mω) sin ωt|"),
)


def series_names(example: str) -> set[str]:
    """The series an example has: its coordinates and velocities, then its own."""
    own = {
        "pendulum": ("f", "f_dot", "lambda", "position_error", "energy_error"),
        "rheonomic-pendulum": ("f", "f_dot", "lambda", "position_error", "length"),
        "knife-edge": ("g", "lambda_1", "energy_error", "u_along_blade", "speed_error"),
        "planar-3axis": (
            *("f_1", "f_2", "f_1_dot", "f_2_dot", "lambda_1", "lambda_2"),
            *("position_error", "phi_error"),
        ),
    }[example]
    return {*COORDS[example], *(f"{c}_dot" for c in COORDS[example]), *own}


def observe_example(params: Params, t: Array, state: Array) -> dict[str, Array]:
    """Every series of the example at the times ``t`` from ``state = [q, q', reference]``:
    residuals (2.17)/(2.26), multipliers (2.33), energy and the reference errors."""
    ex = str(params["example"])
    ev, coords = evaluator(ex), COORDS[ex]
    n = len(coords)
    q, qd, ref = state[:, :n].T, state[:, n : 2 * n].T, state[:, 2 * n :]
    P = ev.parts(t, q, qd, physical(params), inputs_of(ex, t))
    f, c = ev.residuals(P, qd)
    lam = ev.solve(P, qd, *stabilization(params))[1]
    out = {name: q[k] for k, name in enumerate(coords)}
    out.update({f"{name}_dot": qd[k] for k, name in enumerate(coords)})
    m = float(params["m"])
    if ex in PENDULUMS:
        L, _ = rod_length(params, t)
        th = ref[:, 0]
        out.update({"f": f[:, 0], "f_dot": c[:, 0], "lambda": lam[:, 0]})
        out["position_error"] = np.hypot(q[0] - L * np.sin(th), q[1] + L * np.cos(th))
        if ex == "rheonomic-pendulum":
            out["length"] = L
        else:  # released from rest at theta0
            mg, th0 = m * float(params["g"]), float(params["theta0"])
            E = 0.5 * m * (qd[0] ** 2 + qd[1] ** 2) + mg * q[1]
            out["energy_error"] = E + mg * L * np.cos(th0)
    elif ex == "knife-edge":
        u = qd[0] * np.cos(q[2]) + qd[1] * np.sin(q[2])
        J, F, u0, w0 = (float(params[k]) for k in ("J", "F", "u0", "omega0"))
        E = 0.5 * m * (qd[0] ** 2 + qd[1] ** 2) + 0.5 * J * qd[2] ** 2 - F * q[0]
        out.update({"g": c[:, 0], "lambda_1": lam[:, 0], "u_along_blade": u})
        out["energy_error"] = E - 0.5 * (m * u0**2 + J * w0**2)
        out["speed_error"] = np.abs(u - ref[:, 0])
    else:
        out.update({"f_1": f[:, 0], "f_2": f[:, 1], "f_1_dot": c[:, 0], "f_2_dot": c[:, 1]})
        out.update({"lambda_1": lam[:, 0], "lambda_2": lam[:, 1]})
        out["position_error"] = np.maximum(np.abs(q[0] - ref[:, 0]), np.abs(q[1] - ref[:, 1]))
        out["phi_error"] = np.abs(q[4] - ref[:, 2])
    return out


def planar3_acceleration_difference(seed: int = 1) -> float:
    """max |q'' of (2.34) - q'' of the reduced model| over 5 random consistent states."""
    red, p = reduced_model(), body_values()
    rng = np.random.default_rng(seed)
    xA, yA, phi, vxA, vyA, w = rng.normal(size=(6, 5))
    u = rng.normal(size=(5, 5))
    AB = float(p[4])
    xB, yB = planar3_kinematics(xA, yA, phi, AB, np)
    vxB, vyB = vxA + AB * np.sin(phi) * w, vyA + AB * np.cos(phi) * w
    q, qd = np.array([xA, yA, xB, yB, phi]), np.array([vxA, vyA, vxB, vyB, w])
    ev = evaluator("planar-3axis")
    qdd, _ = ev.solve(ev.parts(np.zeros(5), q, qd, p, u), qd)
    worst = 0.0
    for k in range(5):
        qr = red.accelerations(q[[0, 1, 4], k], qd[[0, 1, 4], k], 0.0, p, u[:, k])
        worst = max(worst, float(np.max(np.abs(qdd[k, [0, 1, 4]] - qr))))
    return worst
