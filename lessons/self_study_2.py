"""Self-study tasks of chapter 2, C2.1-C2.6: the equations of simple manipulators.

Each task is a choice of ``task`` (and a preset with the textbook's numbers): its
Lagrange equations are derived by ``sympy.physics.mechanics.LagrangesMethod`` and run
live.  The figures (2.13)-(2.16) survive only as labels, so every arrangement beyond
the labels is a reading, marked ``reconstructed`` where it is shown.
C2.6 uses holonomic constraints with Lagrange multipliers, the route of §2.2
(2.25), (2.30)-(2.34), as LagrangesMethod builds it (``hol_coneqs``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from scipy.integrate import solve_ivp
from sympy.physics import mechanics as me

from lessons.core.contract import (
    Claim,
    ClaimResult,
    CurveItem,
    DerivationStep,
    Frame,
    Lesson,
    MarkerItem,
    MeshItem,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Stepper,
    close,
)

G = 9.81
TASKS = (
    "C2.1a",
    "C2.1b",
    "C2.1c",
    "C2.2a",
    "C2.2b",
    "C2.2c",
    "C2.3a",
    "C2.3b",
    "C2.3c",
    "C2.4a",
    "C2.4b",
    "C2.4c",
    "C2.5",
    "C2.6a",
    "C2.6b",
    "C2.6c",
)
AXES = ("x", "y", "z", "xy", "xz", "yz", "xyz")
TIME = me.dynamicsymbols._t


# ---------------------------------------------------------------- symbolic models


@dataclass
class Model:
    """One task's Lagrangian model, derived once and lambdified."""

    key: str
    coords: tuple[str, ...]
    q: list[Any]
    T: sp.Expr
    U: sp.Expr
    forces_text: str
    lm: me.LagrangesMethod
    consts: tuple[sp.Symbol, ...]
    inputs: tuple[sp.Symbol, ...]
    points: dict[str, sp.Matrix]
    angles: dict[str, sp.Expr]
    constraints: list[sp.Expr] = field(default_factory=list)
    equations: list[sp.Expr] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.equations = list(self.lm.form_lagranges_equations())
        qd = [sp.diff(c, TIME) for c in self.q]
        args = [TIME, self.q, qd, list(self.consts), list(self.inputs)]
        self._mm = sp.lambdify(args, self.lm.mass_matrix_full, "numpy")
        self._ff = sp.lambdify(args, self.lm.forcing_full, "numpy")
        self._pts = {
            k: sp.lambdify([self.q, list(self.consts)], list(v), "numpy")
            for k, v in self.points.items()
        }
        self._ang = {
            k: sp.lambdify([self.q, list(self.consts)], v, "numpy") for k, v in self.angles.items()
        }
        self._con = (
            sp.lambdify([self.q, list(self.consts)], self.constraints, "numpy")
            if self.constraints
            else None
        )

    @property
    def n(self) -> int:
        return len(self.q)

    @property
    def simplified(self) -> list[sp.Expr]:
        """The Lagrange equations, simplified once (for the derivation page)."""
        if not hasattr(self, "_simplified"):
            self._simplified = [sp.simplify(e) for e in self.equations]
        return self._simplified

    def accelerations(
        self, t: float, q: np.ndarray, qd: np.ndarray, consts: list[float], inputs: list[float]
    ) -> tuple[np.ndarray, np.ndarray]:
        """(q'', lambda) from (2.25) + (2.30): [M -H^T; H 0] [q''; lambda] = [B; -Phi]."""
        MM = np.asarray(self._mm(t, q, qd, consts, inputs), dtype=float)
        FF = np.asarray(self._ff(t, q, qd, consts, inputs), dtype=float).ravel()
        x = np.linalg.solve(MM, FF)
        n = self.n
        return x[n : 2 * n], x[2 * n :]

    def point(self, name: str, q: np.ndarray, consts: list[float]) -> np.ndarray:
        return np.array(self._pts[name](q, consts), dtype=float).ravel()

    def angle(self, name: str, q: np.ndarray, consts: list[float]) -> float:
        return float(self._ang[name](q, consts))

    def constraint_values(self, q: np.ndarray, consts: list[float]) -> np.ndarray:
        if self._con is None:
            return np.zeros(0)
        return np.array(self._con(q, consts), dtype=float).ravel()


def _vec(p: me.Point, O: me.Point, N: me.ReferenceFrame) -> sp.Matrix:
    return p.pos_from(O).to_matrix(N)


def _frame_setup() -> tuple[me.ReferenceFrame, me.Point]:
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    return N, O


def _c21() -> Model:
    """Fig. 2.13: link 1 about O, end point M; moments M_g (drive) and M_c (resistance)."""
    phi = me.dynamicsymbols("varphi")
    l, J0, m1e, ge = sp.symbols("l_OM J_0 m_1e g_e")
    Mg, Mc = sp.symbols("M_g M_c")
    N, O = _frame_setup()
    A = N.orientnew("A", "Axis", [phi, N.z])
    A.set_ang_vel(N, sp.diff(phi, TIME) * N.z)
    M = O.locatenew("M", l * A.x)
    M.v2pt_theory(O, N, A)
    link = me.RigidBody("link", O, A, 0, (me.inertia(A, 0, 0, J0), O))
    tip = me.Particle("tip", M, m1e)
    tip.potential_energy = m1e * ge * l * sp.sin(phi)
    link.potential_energy = 0
    L = me.Lagrangian(N, link, tip)
    lm = me.LagrangesMethod(L, [phi], forcelist=[(A, (Mg - Mc) * N.z)], frame=N)
    T = sp.Rational(1, 2) * (J0 + m1e * l**2) * sp.diff(phi, TIME) ** 2
    return Model(
        "C2.1",
        ("phi",),
        [phi],
        T,
        m1e * ge * l * sp.sin(phi),
        "moment (M_g - M_c) about O",
        lm,
        (l, J0, m1e, ge),
        (Mg, Mc),
        {"M": _vec(M, O, N)},
        {"link": phi},
    )


def _c22() -> Model:
    """Fig. 2.14: M moves on y = x + 1 under F_g (drive) and F_c (resistance) along the line."""
    x = me.dynamicsymbols("x")
    m, ge, lAM = sp.symbols("m g_e l_AM")
    Fg, Fc = sp.symbols("F_g F_c")
    N, O = _frame_setup()
    M = O.locatenew("M", x * N.x + (x + 1) * N.y)
    M.set_vel(N, M.pos_from(O).dt(N))
    e = (N.x + N.y) / sp.sqrt(2)
    body = me.Particle("M", M, m)
    body.potential_energy = m * ge * (x + 1)
    lm = me.LagrangesMethod(me.Lagrangian(N, body), [x], forcelist=[(M, (Fg - Fc) * e)], frame=N)
    A = M.locatenew("A", -lAM * e)
    return Model(
        "C2.2",
        ("x",),
        [x],
        body.kinetic_energy(N),
        m * ge * (x + 1),
        "force (F_g - F_c) along the line",
        lm,
        (m, ge, lAM),
        (Fg, Fc),
        {"M": _vec(M, O, N), "A": _vec(A, O, N)},
        {"line": sp.pi / 4},
    )


def _c23a() -> Model:
    """Fig. 2.15a (reading): arm rotating by phi about O carries a slider M at radius S."""
    phi, S = me.dynamicsymbols("varphi S")
    J, m2, ge = sp.symbols("J m_2 g_e")
    Q1, Q2 = sp.symbols("Q_1 Q_2")
    N, O = _frame_setup()
    A = N.orientnew("A", "Axis", [phi, N.z])
    A.set_ang_vel(N, sp.diff(phi, TIME) * N.z)
    M = O.locatenew("M", S * A.x)
    M.set_vel(N, M.pos_from(O).dt(N))
    arm = me.RigidBody("arm", O, A, 0, (me.inertia(A, 0, 0, J), O))
    slider = me.Particle("slider", M, m2)
    slider.potential_energy = m2 * ge * S * sp.sin(phi)
    arm.potential_energy = 0
    lm = me.LagrangesMethod(
        me.Lagrangian(N, arm, slider), [phi, S], forcelist=[(A, Q1 * N.z), (M, Q2 * A.x)], frame=N
    )
    T = sp.Rational(1, 2) * J * sp.diff(phi, TIME) ** 2 + slider.kinetic_energy(N)
    return Model(
        "C2.3a",
        ("phi", "S"),
        [phi, S],
        sp.simplify(T),
        m2 * ge * S * sp.sin(phi),
        "Q_1: moment on the arm; Q_2: force on the slider along the arm",
        lm,
        (J, m2, ge),
        (Q1, Q2),
        {"M": _vec(M, O, N)},
        {"arm": phi},
    )


def _c23b() -> Model:
    """Fig. 2.15b (reading): stage 1 moves S1 along X and carries stage 2 moving S2 along Y."""
    S1, S2 = me.dynamicsymbols("S_1 S_2")
    m1, m2, ge = sp.symbols("m_1 m_2 g_e")
    Q1, Q2 = sp.symbols("Q_1 Q_2")
    N, O = _frame_setup()
    P1 = O.locatenew("P1", S1 * N.x)
    P1.set_vel(N, P1.pos_from(O).dt(N))
    M = P1.locatenew("M", S2 * N.y)
    M.set_vel(N, M.pos_from(O).dt(N))
    b1, b2 = me.Particle("stage1", P1, m1), me.Particle("stage2", M, m2)
    b1.potential_energy = 0
    b2.potential_energy = m2 * ge * S2
    lm = me.LagrangesMethod(
        me.Lagrangian(N, b1, b2), [S1, S2], forcelist=[(P1, Q1 * N.x), (M, Q2 * N.y)], frame=N
    )
    return Model(
        "C2.3b",
        ("S1", "S2"),
        [S1, S2],
        b1.kinetic_energy(N) + b2.kinetic_energy(N),
        m2 * ge * S2,
        "Q_1: force on stage 1 along X; Q_2: force on stage 2 along Y",
        lm,
        (m1, m2, ge),
        (Q1, Q2),
        {"P1": _vec(P1, O, N), "M": _vec(M, O, N)},
        {},
    )


def _c23c() -> Model:
    """Fig. 2.15c (reading): a carriage translating S along X carries a link rotating by phi; M at its end."""
    S, phi = me.dynamicsymbols("S varphi")
    m1, m2, J, l, ge = sp.symbols("m_1 m_2 J l g_e")
    Q1, Q2 = sp.symbols("Q_1 Q_2")
    N, O = _frame_setup()
    C = O.locatenew("C", S * N.x)
    C.set_vel(N, sp.diff(S, TIME) * N.x)
    A = N.orientnew("A", "Axis", [phi, N.z])
    A.set_ang_vel(N, sp.diff(phi, TIME) * N.z)
    M = C.locatenew("M", l * A.x)
    M.v2pt_theory(C, N, A)
    carriage = me.Particle("carriage", C, m1)
    link = me.RigidBody("link", C, A, 0, (me.inertia(A, 0, 0, J), C))
    tip = me.Particle("tip", M, m2)
    carriage.potential_energy, link.potential_energy = 0, 0
    tip.potential_energy = m2 * ge * l * sp.sin(phi)
    lm = me.LagrangesMethod(
        me.Lagrangian(N, carriage, link, tip),
        [S, phi],
        forcelist=[(C, Q1 * N.x), (A, Q2 * N.z)],
        frame=N,
    )
    T = (
        carriage.kinetic_energy(N)
        + sp.Rational(1, 2) * J * sp.diff(phi, TIME) ** 2
        + tip.kinetic_energy(N)
    )
    return Model(
        "C2.3c",
        ("S", "phi"),
        [S, phi],
        sp.simplify(T),
        m2 * ge * l * sp.sin(phi),
        "Q_1: force on the carriage along X; Q_2: moment on the link",
        lm,
        (m1, m2, J, l, ge),
        (Q1, Q2),
        {"C": _vec(C, O, N), "M": _vec(M, O, N)},
        {"link": phi},
    )


def _c24(axes: str) -> Model:
    """Fig. 2.16: stacked Cartesian stages X (m_1) carries Y (m_2) carries Z (m_3); free axes ``axes``."""
    m1, m2, m3, ge = sp.symbols("m_1 m_2 m_3 g_e")
    Q = sp.symbols("Q_1 Q_2 Q_3")
    names = [a for a in "xyz" if a in axes]
    qs = (
        list(me.dynamicsymbols(" ".join(names)))
        if len(names) > 1
        else [me.dynamicsymbols(names[0])]
    )
    coord = {a: (qs[names.index(a)] if a in names else sp.Integer(0)) for a in "xyz"}
    N, O = _frame_setup()
    PX = O.locatenew("PX", coord["x"] * N.x)
    PY = PX.locatenew("PY", coord["y"] * N.y)
    PZ = PY.locatenew("PZ", coord["z"] * N.z)
    for P in (PX, PY, PZ):
        P.set_vel(N, P.pos_from(O).dt(N))
    bx, by, bz = me.Particle("X", PX, m1), me.Particle("Y", PY, m2), me.Particle("Z", PZ, m3)
    bx.potential_energy, by.potential_energy = 0, 0
    bz.potential_energy = m3 * ge * coord["z"]
    forces = [
        (P, Qk * u)
        for P, Qk, u, a in ((PX, Q[0], N.x, "x"), (PY, Q[1], N.y, "y"), (PZ, Q[2], N.z, "z"))
        if a in names
    ]
    lm = me.LagrangesMethod(me.Lagrangian(N, bx, by, bz), qs, forcelist=forces, frame=N)
    T = bx.kinetic_energy(N) + by.kinetic_energy(N) + bz.kinetic_energy(N)
    return Model(
        f"C2.4-{axes}",
        tuple(names),
        qs,
        sp.simplify(T),
        m3 * ge * coord["z"],
        "Q_1, Q_2, Q_3: drive forces of the X, Y, Z stages",
        lm,
        (m1, m2, m3, ge),
        Q,
        {"PX": _vec(PX, O, N), "PY": _vec(PY, O, N), "PZ": _vec(PZ, O, N)},
        {},
    )


def _c25() -> Model:
    """Fig. 2.3 with rotation: drive point A (x, y), element turned by phi, centre of mass G at l from A."""
    x, y, phi = me.dynamicsymbols("x y varphi")
    m1, J, l = sp.symbols("m_1 J l")
    Q1, Q2, Q3 = sp.symbols("Q_1 Q_2 Q_3")
    N, O = _frame_setup()
    B = N.orientnew("B", "Axis", [phi, N.z])
    B.set_ang_vel(N, sp.diff(phi, TIME) * N.z)
    A = O.locatenew("A", x * N.x + y * N.y)
    A.set_vel(N, sp.diff(x, TIME) * N.x + sp.diff(y, TIME) * N.y)
    Gp = A.locatenew("G", l * B.x)
    Gp.v2pt_theory(A, N, B)
    body = me.RigidBody("element", Gp, B, m1, (me.inertia(B, 0, 0, J), Gp))
    body.potential_energy = 0
    lm = me.LagrangesMethod(
        me.Lagrangian(N, body),
        [x, y, phi],
        forcelist=[(A, Q1 * N.x + Q2 * N.y), (B, Q3 * N.z)],
        frame=N,
    )
    return Model(
        "C2.5",
        ("x", "y", "phi"),
        [x, y, phi],
        sp.simplify(body.kinetic_energy(N)),
        sp.Integer(0),
        "Q_1, Q_2: drive forces at A along X, Y; Q_3: moment in the plane",
        lm,
        (m1, J, l),
        (Q1, Q2, Q3),
        {"A": _vec(A, O, N), "G": _vec(Gp, O, N)},
        {"element": phi},
    )


def _c26(case: str) -> Model:
    """Fig. 2.6: inductors A, B, C as point masses in the plane, q = (x_A, y_A, x_B, y_B, x_C, y_C) of
    Problem 2.5; case a: A fixed at (a, b); b: also B at (c, d); c: all three on the circle of radius R."""
    q = list(me.dynamicsymbols("x_A y_A x_B y_B x_C y_C"))
    mA, mB, mC, a, b, c, d, R, eps = sp.symbols("m_1 m_2 m_3 a b c d R epsilon")
    Q = sp.symbols("Q_1 Q_2 Q_3")
    N, O = _frame_setup()
    parts, forces, pts = [], [], {}
    for k, (name, m) in enumerate((("A", mA), ("B", mB), ("C", mC))):
        xk, yk = q[2 * k], q[2 * k + 1]
        P = O.locatenew(name, xk * N.x + yk * N.y)
        P.set_vel(N, P.pos_from(O).dt(N))
        part = me.Particle(name, P, m)
        part.potential_energy = 0
        parts.append(part)
        r = sp.sqrt(xk**2 + yk**2 + eps**2)
        forces.append((P, Q[k] * (-yk * N.x + xk * N.y) / r))  # drive along the tangent about O
        pts[name] = _vec(P, O, N)
    if case == "a":
        cons = [q[0] - a, q[1] - b]
    elif case == "b":
        cons = [q[0] - a, q[1] - b, q[2] - c, q[3] - d]
    else:
        cons = [q[2 * k] ** 2 + q[2 * k + 1] ** 2 - R**2 for k in range(3)]
    lm = me.LagrangesMethod(me.Lagrangian(N, *parts), q, forcelist=forces, frame=N, hol_coneqs=cons)
    T = sum(p.kinetic_energy(N) for p in parts)
    return Model(
        f"C2.6{case}",
        ("x_A", "y_A", "x_B", "y_B", "x_C", "y_C"),
        q,
        T,
        sp.Integer(0),
        "Q_1, Q_2, Q_3: drive forces of A, B, C along the tangent about O",
        lm,
        (mA, mB, mC, a, b, c, d, R, eps),
        Q,
        pts,
        {},
        cons,
    )


@cache
def model_for(task: str, axes: str = "xyz") -> Model:
    """The (cached) model of a task."""
    if task.startswith("C2.1"):
        return _c21()
    if task.startswith("C2.2"):
        return _c22()
    if task == "C2.3a":
        return _c23a()
    if task == "C2.3b":
        return _c23b()
    if task == "C2.3c":
        return _c23c()
    if task.startswith("C2.4"):
        return _c24(axes)
    if task == "C2.5":
        return _c25()
    if task.startswith("C2.6"):
        return _c26(task[-1])
    raise KeyError(task)


# ---------------------------------------------------------------- numeric set-up per task


def _consts(params: Params, model: Model) -> list[float]:
    """Numeric values of the model's constants, by symbol name, from the parameters."""
    g = G if params["vertical"] else 0.0
    p = params
    at_M = p["inertia"] == "J0 + m1 l_OM^2"
    table = {
        # C2.1: J_0 is the link's inertia about O; m1 is a point mass at M only in the reading J0 + m1 l_OM^2
        "l_OM": p["l_OM"],
        "J_0": p["J0"],
        "m_1e": p["m1"] if at_M else 0.0,
        "g_e": g,
        "m": p["m"],
        "l_AM": p["l_AM"],
        "J": p["J"],
        "m_1": p["m1"],
        "m_2": p["m2"],
        "m_3": p["m3"],
        "l": p["l"],
        "a": p["a"],
        "b": p["b"],
        "c": p["c"],
        "d": p["d"],
        "R": p["R"],
        "epsilon": 1e-9,
    }
    return [float(table[s.name]) for s in model.consts]


def _c21_moments(task: str, reading: str, phi: float) -> tuple[float, float]:
    """M_g, M_c of C2.1a-c (textbook numbers; C2.1b/c readings of the digest)."""
    if task == "C2.1a":
        return 2.0, 0.0
    if task == "C2.1b":
        return 2.0, (0.1 * phi if reading == "0.1 phi" else 0.1)
    Mg = 2.0 * phi if phi <= 4 * math.pi else 8 * math.pi
    return Mg, 0.1 * math.sin(phi)


def _inputs(params: Params, t: float, q: np.ndarray) -> list[float]:
    task = params["task"]
    if task.startswith("C2.1"):
        return list(_c21_moments(task, params["Mc_reading"], float(q[0])))
    if task.startswith("C2.2"):
        return [float(params["F_g"](t)), float(params["F_c"](t))]
    return [float(params["Q1"](t)), float(params["Q2"](t)), float(params["Q3"](t))][
        : 3 if task in ("C2.5",) or task.startswith(("C2.4", "C2.6")) else 2
    ]


def _initial(params: Params, model: Model) -> tuple[np.ndarray, np.ndarray]:
    task, p = params["task"], params
    n = model.n
    q, v = np.zeros(n), np.zeros(n)
    if task.startswith("C2.1"):
        q[0], v[0] = p["phi0"], p["phidot0"]
    elif task.startswith("C2.2"):
        q[0] = 0.0
    elif task == "C2.3a":
        q[:] = [0.0, p["l"]]
    elif task == "C2.3c":
        q[:] = [0.0, 0.0]
    elif task.startswith("C2.6"):
        if task == "C2.6c":
            ang = np.radians([90.0, 210.0, 330.0])
            q[:] = np.column_stack([p["R"] * np.cos(ang), p["R"] * np.sin(ang)]).ravel()
        else:
            q[:] = [p["a"], p["b"], p["c"], p["d"], 0.0, -0.12]
    return q, v


def _plot_coords(task: str, q: np.ndarray) -> np.ndarray:
    """q1..q3 shown in the plots: the coordinates, or for C2.6 the polar angles of A, B, C."""
    if task.startswith("C2.6"):
        return np.arctan2(q[1::2], q[0::2])
    out = np.full(3, np.nan)
    out[: min(3, len(q))] = q[:3]
    return out


# ---------------------------------------------------------------- the lesson


def _p(
    name: str,
    kind: str,
    default: Any,
    label: str,
    unit: str = "",
    lo: float | None = None,
    hi: float | None = None,
    step: float | None = None,
    group: str = "controls",
    help: str = "",
    choices: tuple[str, ...] = (),
) -> Param:
    return Param(name, kind, default, label, unit, lo, hi, step, choices, group, help)


def _task_preset(
    task: str, title: str, values: dict[str, Any], t_end: float, note: str = ""
) -> Preset:
    return Preset(
        task.lower().replace(".", "-"), f"{task}: {title}", {"task": task, **values}, t_end, note
    )


class SelfStudy2(Lesson):
    id = "self-study-2"
    title = "Self-study C2.1-C2.6: equations of simple manipulators"
    chapter = "2"
    problem = "C2.1-C2.6"
    source = "Textbook chapter 2, self-study tasks C2.1-C2.6 (Figs 2.13-2.16, 2.3, 2.6)"
    summary = (
        "Each task's Lagrange equations derived with sympy (LagrangesMethod) and integrated live: "
        "a rotating link, a slider on a line, two-DOF arms, a Cartesian 3-axis stage, a planar "
        "positioner with rotation, and the three-inductor table with fixed or circular inductors."
    )
    order = 2.99
    t_end = 2.0
    params = (
        _p("task", "choice", "C2.1a", "task", choices=TASKS),
        _p(
            "vertical",
            "bool",
            False,
            "motion plane vertical (gravity along -Y; -Z for C2.4)",
            help="the figures do not say; off = horizontal plane",
        ),
        _p(
            "inertia",
            "choice",
            "J0",
            "C2.1: moment of inertia J",
            choices=("J0", "J0 + m1 l_OM^2"),
            group="method",
            help="J0 alone, or J0 plus m1 concentrated at M (the source does not say)",
        ),
        _p(
            "Mc_reading",
            "choice",
            "0.1 phi",
            "C2.1b: reading of M_c",
            choices=("0.1 phi", "0.1"),
            group="method",
        ),
        _p("l_OM", "float", 0.2, "C2.1: l_OM", "m", 0.001, 10.0, 0.01),
        _p("m1", "float", 0.4, "C2.1: m1; C2.3-C2.6: first body mass", "kg", 0.001, 1e4, 0.01),
        _p("J0", "float", 0.01, "C2.1: J0", "kg m^2", 1e-6, 1e3, 0.001),
        _p("phi0", "float", 0.0, "C2.1: phi(0)", "rad", -100.0, 100.0, 0.01, "initial"),
        _p("phidot0", "float", 0.0, "C2.1: phi'(0)", "rad/s", -1e3, 1e3, 0.1, "initial"),
        _p("m", "float", 0.5, "C2.2: m", "kg", 0.001, 1e4, 0.01),
        _p("l_AM", "float", 0.2, "C2.2: l_AM (drawn link)", "m", 0.0, 10.0, 0.01),
        _p("F_g", "formula", "5", "C2.2: driving force F_g(t)", "N"),
        _p("F_c", "formula", "0", "C2.2: resistance F_c(t)", "N"),
        _p("m2", "float", 0.3, "C2.3-C2.6: second body mass", "kg", 0.001, 1e4, 0.01),
        _p("m3", "float", 0.2, "C2.4, C2.6: third body mass", "kg", 0.001, 1e4, 0.01),
        _p("J", "float", 0.005, "C2.3, C2.5: link / element inertia", "kg m^2", 1e-6, 1e3, 0.001),
        _p("l", "float", 0.2, "C2.3: link length; C2.5: A to centre of mass", "m", 0.0, 10.0, 0.01),
        _p("Q1", "formula", "0.5", "C2.3-C2.6: generalized force Q1(t)"),
        _p("Q2", "formula", "0.2*sin(t)", "C2.3-C2.6: generalized force Q2(t)"),
        _p("Q3", "formula", "0", "C2.4-C2.6: generalized force Q3(t)"),
        _p("axes", "choice", "xyz", "C2.4: moving axes", choices=AXES),
        _p("a", "float", 0.1, "C2.6: x_A = a", "m", -10.0, 10.0, 0.01),
        _p("b", "float", 0.1, "C2.6: y_A = b", "m", -10.0, 10.0, 0.01),
        _p("c", "float", -0.1, "C2.6: x_B = c", "m", -10.0, 10.0, 0.01),
        _p("d", "float", 0.1, "C2.6: y_B = d", "m", -10.0, 10.0, 0.01),
        _p("R", "float", 0.15, "C2.6c: circle radius R", "m", 0.001, 10.0, 0.01),
    )
    presets = (
        _task_preset(
            "C2.1a",
            "M_g = 2 N m, M_c = 0",
            {},
            0.5,
            "l_OM = 0.2 m, m1 = 0.4 kg, J0 = 0.01 kg m^2; runs to phi = 180 deg.",
        ),
        _task_preset(
            "C2.1b",
            "M_g = 2 N m, M_c = 0.1 phi, phi from 0 to 180 deg",
            {},
            0.5,
            "M_c = 0.1 phi is the digest's reading (alternative 0.1).",
        ),
        _task_preset(
            "C2.1c",
            "M_g = 2 phi (phi <= 4 pi), 8 pi beyond; M_c = 0.1 sin phi",
            {"phidot0": 1.0},
            1.0,
            "phi = 0 at rest is an equilibrium; the source gives no start, phi'(0) = 1 rad/s is chosen here.",
        ),
        _task_preset(
            "C2.2a",
            "F_g = 5 N, F_c = 0",
            {"F_g": "5", "F_c": "0"},
            2.0,
            "m = 0.5 kg, l_AM = 0.2 m, line y = x + 1.",
        ),
        _task_preset(
            "C2.2b", "F_g = 2 sin t, F_c = 0, t from 0 to 10", {"F_g": "2*sin(t)", "F_c": "0"}, 10.0
        ),
        _task_preset(
            "C2.2c", "F_g = 2 sin t, F_c = t, t from 0 to 10", {"F_g": "2*sin(t)", "F_c": "t"}, 10.0
        ),
        _task_preset(
            "C2.3a",
            "rotation phi and translation S (polar arm)",
            {"Q1": "0.02", "Q2": "-0.05"},
            5.0,
            "Illustrative masses and forces; the figure's arrangement is a reading.",
        ),
        _task_preset(
            "C2.3b",
            "two translations S1, S2",
            {"Q1": "0.3*sin(t)", "Q2": "0.2"},
            5.0,
            "Illustrative masses and forces.",
        ),
        _task_preset(
            "C2.3c",
            "translation S carrying a rotating link phi",
            {"Q1": "0.5*sin(2*t)", "Q2": "0.02"},
            5.0,
            "Illustrative masses and forces.",
        ),
        _task_preset(
            "C2.4a",
            "one axis at a time (here Z, vertical)",
            {"axes": "z", "vertical": True, "Q3": "2.5"},
            2.0,
            "Illustrative masses and forces.",
        ),
        _task_preset(
            "C2.4b",
            "two axes together (here x and y)",
            {"axes": "xy", "Q1": "0.5", "Q2": "0.3*sin(2*t)"},
            3.0,
        ),
        _task_preset(
            "C2.4c",
            "x, y and z together",
            {"axes": "xyz", "vertical": True, "Q1": "0.5", "Q2": "0.3*sin(2*t)", "Q3": "2.2"},
            3.0,
        ),
        _task_preset(
            "C2.5",
            "x, y and the rotation phi of the moving element",
            {"Q1": "0", "Q2": "0.4", "Q3": "0"},
            3.0,
            "A force at A across the offset l only: the element both moves and turns.",
        ),
        _task_preset(
            "C2.6a",
            "inductor A fixed at (a, b, 0)",
            {"Q1": "0.2", "Q2": "0.05", "Q3": "-0.05"},
            2.0,
        ),
        _task_preset(
            "C2.6b",
            "A fixed at (a, b, 0), B fixed at (c, d, 0)",
            {"Q1": "0.2", "Q2": "0.2", "Q3": "0.05"},
            2.0,
        ),
        _task_preset(
            "C2.6c",
            "A, B, C on the circle of radius R about O",
            {"Q1": "0.05", "Q2": "0.1*sin(t)", "Q3": "0"},
            5.0,
        ),
    )
    plots = (
        PlotSpec("Coordinates q1, q2, q3", ("q1", "q2", "q3")),
        PlotSpec("Velocities", ("v1", "v2", "v3")),
        PlotSpec("Forces and moments", ("Q1", "Q2", "Q3")),
        PlotSpec("Constraint multipliers (C2.6)", ("lambda1", "lambda2", "lambda3")),
    )

    # -- checks -------------------------------------------------------------------

    def validate(self, params: Params) -> None:
        task, axes = params["task"], params["axes"]
        need = {"C2.4a": 1, "C2.4b": 2, "C2.4c": 3}.get(task)
        if need is not None and len(axes) != need:
            raise ParamError(
                "axes",
                f"{task} moves {need} axis{'es' if need > 1 else ''} at a time; choose "
                + ", ".join(a for a in AXES if len(a) == need),
            )
        if (
            task == "C2.6b"
            and math.hypot(params["a"] - params["c"], params["b"] - params["d"]) < 1e-6
        ):
            raise ParamError("c", "A and B cannot be fixed at the same point")

    def model(self, params: Params) -> Model:
        return model_for(
            params["task"], params["axes"] if params["task"].startswith("C2.4") else "xyz"
        )

    # -- numerics -----------------------------------------------------------------

    def rhs(self, params: Params) -> Callable[[float, np.ndarray], np.ndarray]:
        model = self.model(params)
        consts = _consts(params, model)
        n = model.n

        def f(t: float, y: np.ndarray) -> np.ndarray:
            qdd, _ = model.accelerations(t, y[:n], y[n:], consts, _inputs(params, t, y[:n]))
            return np.concatenate([y[n:], qdd])

        return f

    def _terminal(self, params: Params) -> Callable[[float, np.ndarray], float] | None:
        if params["task"] in ("C2.1a", "C2.1b"):

            def reach(t: float, y: np.ndarray) -> float:
                return y[0] - math.pi

            reach.terminal = True  # type: ignore[attr-defined]
            reach.direction = 1  # type: ignore[attr-defined]
            return reach
        return None

    def integrate(
        self,
        params: Params,
        t0: float,
        y0: np.ndarray,
        t1: float,
        t_eval: np.ndarray | None = None,
        rtol: float = 1e-10,
    ):
        ev = self._terminal(params)
        return solve_ivp(
            self.rhs(params),
            (t0, t1),
            y0,
            method="DOP853",
            rtol=rtol,
            atol=1e-12,
            t_eval=t_eval,
            events=[ev] if ev else None,
            dense_output=False,
        )

    def observables(self, params: Params, t: np.ndarray, Y: np.ndarray) -> dict[str, np.ndarray]:
        """Named series over samples (Y of shape (2n, N))."""
        model = self.model(params)
        consts = _consts(params, model)
        n = model.n
        out: dict[str, list[float]] = {}
        for j, tj in enumerate(t):
            q, qd = Y[:n, j], Y[n:, j]
            inp = _inputs(params, float(tj), q)
            lam = (
                model.accelerations(float(tj), q, qd, consts, inp)[1]
                if model.constraints
                else np.zeros(0)
            )
            row: dict[str, float] = {}
            for i, name in enumerate(model.coords):
                row[name], row[f"{name}_dot"] = q[i], qd[i]
            pc = _plot_coords(params["task"], q)
            if params["task"].startswith("C2.6"):
                xs, ys, vxs, vys = q[0::2], q[1::2], qd[0::2], qd[1::2]
                pv = (xs * vys - ys * vxs) / np.maximum(xs**2 + ys**2, 1e-300)
            else:
                pv = np.array([qd[i] if i < n else np.nan for i in range(3)])
            for i in range(3):
                row[f"q{i + 1}"], row[f"v{i + 1}"] = pc[i], pv[i]
            for i in range(3):
                row[f"Q{i + 1}"] = inp[i] if i < len(inp) else np.nan
                row[f"lambda{i + 1}"] = lam[i] if i < len(lam) else np.nan
            names = [s.name for s in model.inputs]
            for nm, val in zip(names, inp):
                row[nm] = val
            for k, lv in enumerate(lam):
                row[f"lambda_{k + 1}"] = lv
            if model.constraints:
                row["constraint_error"] = float(np.max(np.abs(model.constraint_values(q, consts))))
            for pname in model.points:
                P = model.point(pname, q, consts)
                row[f"{pname}_x"], row[f"{pname}_y"], row[f"{pname}_z"] = P
            for k, v in row.items():
                out.setdefault(k, []).append(float(v))
        return {k: np.asarray(v) for k, v in out.items()}

    def simulate(
        self, params: Params, t_end: float | None = None, samples: int = 1001
    ) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        model = self.model(params)
        q0, v0 = _initial(params, model)
        t_eval = np.linspace(0.0, t_end, samples)
        messages: list[str] = []
        used = (
            ("F_g", "F_c")
            if params["task"].startswith("C2.2")
            else ()
            if params["task"].startswith("C2.1")
            else ("Q1", "Q2", "Q3")
        )
        for name in used:
            vals = np.asarray(params[name](t_eval), dtype=float) * np.ones_like(t_eval)
            bad = ~np.isfinite(vals)
            if bad.any():
                k = int(np.argmax(bad))
                messages.append(
                    f"{name} = {params[name].text} is not finite at t = {t_eval[k]:.6g} s; the run stops before it."
                )
                t_eval = t_eval[: max(k - 1, 1)]
        t_end = float(t_eval[-1])
        if t_end <= 0.0:
            t_eval = np.zeros(1)
        y0 = np.concatenate([q0, v0])
        if t_end <= 0.0:
            sol = None
            t, Y = np.zeros(1), y0[:, None]
        else:
            sol = self.integrate(params, 0.0, y0, t_end, t_eval)
            if sol.status == -1:
                messages.append(f"integration stopped: {sol.message}")
            t, Y = sol.t, sol.y
        if params["task"].startswith("C2.1") and params["vertical"] and params["inertia"] == "J0":
            messages.append(
                "With J = J0 the place of m1 is not known, so no gravity moment is applied; choose J0 + m1 l_OM^2 for a vertical plane."
            )
        metrics: dict[str, Any] = {
            "task": params["task"],
            "n_coordinates": model.n,
            "n_constraints": len(model.constraints),
        }
        if params["task"] in ("C2.1a", "C2.1b"):
            if sol is not None and sol.t_events and len(sol.t_events[0]):
                t_hit = float(sol.t_events[0][0])
                t = np.append(t, t_hit)
                Y = np.column_stack([Y, sol.y_events[0][0]])
                metrics["t_180"] = t_hit
                messages.append(
                    f"phi reaches 180 deg (phi_k) at t = {t_hit:.6g} s; the run stops there."
                )
            else:
                messages.append("phi does not reach 180 deg within the run.")
        series = self.observables(params, t, Y)
        if "constraint_error" in series:
            metrics["max_constraint_error"] = float(np.max(series["constraint_error"]))
        for name in model.coords:
            metrics[f"{name}_end"] = float(series[name][-1])
        return RunResult(self.id, None, params.raw(), t, series, metrics, messages)

    def stepper(self, params: Params) -> Stepper:
        return _SelfStudyStepper(self, params)

    # -- scene --------------------------------------------------------------------

    def scene(self, params: Params) -> SceneSpec:
        task = params["task"]
        run = self.simulate(params, self.preset_t_end(_preset_of(task)), samples=201)
        model = self.model(params)
        pts = np.vstack(
            [
                np.column_stack([run.series[f"{p}_x"], run.series[f"{p}_y"], run.series[f"{p}_z"]])
                for p in model.points
            ]
        )
        pts = np.vstack([pts, np.zeros((1, 3))])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        span = max(float(np.max(np.abs(pts))) if len(pts) else 1.0, 0.2)
        size = 0.08 * min(span, 1.0) if span < 5 else 0.08 * span**0.5
        lo, hi = pts.min(axis=0) - 2 * size, pts.max(axis=0) + 2 * size
        lo[2], hi[2] = min(lo[2], -size), max(hi[2], size)
        bodies, curves, markers = _drawing(params, model, size, lo, hi)
        return SceneSpec(
            bounds=(tuple(lo.tolist()), tuple(hi.tolist())),
            meshes=[],
            curves=curves,
            markers=markers,
            moving_points=self.scene_points(params),
            moving_vectors={},
            bodies=bodies,
            planar=not task.startswith("C2.4"),
        )

    def scene_points(self, params: Params) -> dict[str, tuple[int, int, int]]:
        """Moving points (with trails) of the task: model point name -> colour."""
        task = params["task"]
        if task.startswith("C2.4"):
            return {"PZ": (220, 60, 60)}
        if task == "C2.5":
            return {"A": (60, 60, 220), "G": (220, 60, 60)}
        if task.startswith("C2.6"):
            return {"A": (220, 60, 60), "B": (60, 160, 60), "C": (60, 60, 220)}
        return {"M": (220, 60, 60)}

    # -- page ---------------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        task = params["task"]
        model = self.model(params)
        T, U = sp.Symbol("T"), sp.Symbol("U")
        qd = [sp.diff(c, TIME) for c in model.q]
        steps = [_statement(task, params)]
        steps.append(
            DerivationStep(
                "Generalized coordinates",
                ", ".join(model.coords),
                sp.Matrix(model.q),
                _source(task),
            )
        )
        steps.append(
            DerivationStep("Kinetic energy", "", sp.Eq(T, sp.simplify(model.T)), _source(task))
        )
        steps.append(
            DerivationStep(
                "Potential energy",
                "g_e = g when the plane is vertical, else 0.",
                sp.Eq(U, model.U),
                _source(task),
            )
        )
        steps.append(DerivationStep("Generalized forces", model.forces_text, None, _source(task)))
        steps.append(
            DerivationStep(
                "Lagrange equations of the 2nd kind",
                r"d/dt dT/dq' - dT/dq = -dU/dq + Q (2.5), derived by sympy.physics.mechanics.LagrangesMethod.",
                r"\frac{d}{dt}\frac{\partial T}{\partial \dot q_i}-\frac{\partial T}{\partial q_i}=-\frac{\partial U}{\partial q_i}+Q_i",
                "(2.5), (2.13)",
            )
        )
        if model.constraints:
            steps.append(
                DerivationStep(
                    "Holonomic constraints",
                    "f_i(q) = 0 (2.17); multipliers lambda_i enter as H^T lambda (2.25).",
                    [sp.Eq(c, 0) for c in model.constraints],
                    "(2.17)",
                    reconstructed="the task states positions only; written as holonomic constraints of §2.2",
                )
            )
            steps.append(
                DerivationStep(
                    "Equations with multipliers",
                    "A q'' = B + H^T lambda (2.25) with H q'' = -Phi (2.30); solved for q'' and lambda together.",
                    [sp.Eq(e, 0) for e in model.simplified],
                    "(2.25), (2.30)-(2.34)",
                )
            )
        else:
            steps.append(
                DerivationStep(
                    "Equations of motion",
                    "",
                    [sp.Eq(e, 0) for e in model.simplified],
                    _source(task),
                )
            )
        rhs = (
            sp.simplify(model.lm.mass_matrix.inv() * model.lm.forcing)
            if not model.constraints and model.n == 1
            else None
        )
        if rhs is not None:
            steps.append(
                DerivationStep(
                    "Solved for the accelerations",
                    "",
                    [sp.Eq(sp.diff(c, TIME, 2), r) for c, r in zip(model.q, rhs)],
                    _source(task),
                )
            )
        steps.extend(_closed_forms(task, params))
        _ = qd
        return steps

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "c2-1-numbers",
                "C2.1: l_OM = 0.2 m, m1 = 0.4 kg, J0 = 0.01 kg m^2 (presets); J0 + m1 l_OM^2 = 0.026 kg m^2.",
                "C2.1",
                _check_c21_numbers,
            ),
            Claim(
                "c2-1-equation",
                "C2.1 (horizontal plane): LagrangesMethod gives J phi'' = M_g - M_c.",
                "C2.1",
                _check_c21_equation,
            ),
            Claim(
                "c2-1a-time",
                "C2.1a: phi reaches 180 deg at t = sqrt(pi J) = 0.1772 s (J0) or 0.2858 s (J0 + m1 l^2).",
                "C2.1a",
                _check_c21a,
            ),
            Claim(
                "c2-1b-time",
                "C2.1b (M_c = 0.1 phi): phi reaches 180 deg at 0.1797 s (J0) or 0.2897 s (J0 + m1 l^2).",
                "C2.1b",
                _check_c21b,
            ),
            Claim(
                "c2-1c-equilibrium",
                "C2.1c: M_g is continuous at 4 pi (2 * 4 pi = 8 pi) and phi = 0 at rest is an equilibrium.",
                "C2.1c",
                _check_c21c,
            ),
            Claim(
                "c2-2-equation",
                "C2.2: 2 m x'' = sqrt(2) (F_g - F_c) - m g [vertical]; on the line s = sqrt(2) x.",
                "C2.2",
                _check_c22_equation,
            ),
            Claim(
                "c2-2-runs",
                "C2.2 with m = 0.5 kg: (a) s(1 s) = 5 m; (b) s(10 s) = 4 (10 - sin 10) = 42.176 m; (c) s(10 s) = 42.176 - 1000/3 = -291.157 m.",
                "C2.2a-c",
                _check_c22_runs,
            ),
            Claim(
                "c2-3-equations",
                "C2.3a-c: LagrangesMethod reproduces the hand-derived equations of the three arrangements.",
                "C2.3",
                _check_c23,
            ),
            Claim(
                "c2-4-equations",
                "C2.4: (m1+m2+m3) x'' = Q1, (m2+m3) y'' = Q2, m3 z'' = Q3 - m3 g; a locked axis drops its equation.",
                "C2.4",
                _check_c24,
            ),
            Claim(
                "c2-5-equations",
                "C2.5: the x, y, phi equations couple through the offset l of the centre of mass from A.",
                "C2.5",
                _check_c25,
            ),
            Claim(
                "c2-6-constraints",
                "C2.6: fixed inductors stay at (a, b) and (c, d), the circle keeps radius R (error <= 1e-8 over the run), "
                "and on the circle the multiplier gives the centripetal force m v^2/R.",
                "C2.6, (2.17), (2.25)-(2.34)",
                _check_c26,
            ),
        ]


def _preset_of(task: str) -> str:
    return task.lower().replace(".", "-")


def _source(task: str) -> str:
    return {
        "C2.1": "C2.1, Fig. 2.13",
        "C2.2": "C2.2, Fig. 2.14",
        "C2.3": "C2.3, Fig. 2.15",
        "C2.4": "C2.4, Fig. 2.16",
        "C2.5": "C2.5, Fig. 2.3",
        "C2.6": "C2.6, Fig. 2.6",
    }[task[:4]]


def _statement(task: str, params: Params) -> DerivationStep:
    src = _source(task)
    if task.startswith("C2.1"):
        laws = {
            "C2.1a": r"M_g=2\ \mathrm{N\,m},\ M_c=0",
            "C2.1b": r"M_g=2\ \mathrm{N\,m},\ M_c=0.1\varphi,\ \varphi_0=0,\ \varphi_k=180^\circ",
            "C2.1c": r"M_g=\begin{cases}2\varphi,&0\le\varphi\le4\pi\\8\pi,&\varphi>4\pi\end{cases},\ M_c=0.1\sin\varphi",
        }[task]
        why = {
            "C2.1a": None,
            "C2.1b": "M_c = 0.1 phi read from three phi tokens and no dots (alternative: constant 0.1)",
            "C2.1c": "token-consistent reading, continuous at 4 pi (alternatives: 2 / 8, or a switch at pi/4)",
        }[task]
        return DerivationStep(
            "Task",
            "Link 1 turns about O under the driving moment M_g and the resisting moment M_c; "
            "l_OM = 0.2 m, m1 = 0.4 kg, J0 = 0.01 kg m^2.  Whether J includes m1 l_OM^2 and whether the plane is vertical "
            "are not stated (choices 'inertia', 'vertical').",
            laws,
            src,
            reconstructed=why,
        )
    if task.startswith("C2.2"):
        laws = {
            "C2.2a": r"F_g=5\ \mathrm{N},\ F_c=0",
            "C2.2b": r"F_g=2\sin t,\ F_c=0,\ t_0=0,\ t=10",
            "C2.2c": r"F_g=2\sin t,\ F_c=t,\ t_0=0,\ t=10",
        }[task]
        return DerivationStep(
            "Task",
            "Point M of link 1 moves on y = x + 1; m = 0.5 kg, l_AM = 0.2 m. Forces act along the line; "
            "l_AM only sets the drawn link.",
            laws,
            src,
            reconstructed="the model (coordinate x, forces along the line) and the role of l_AM are readings; the figure is lost",
        )
    if task.startswith("C2.3"):
        text = {
            "C2.3a": "Fig. 2.15a (S, M, phi): an arm turning by phi carries a slider M at radius S.",
            "C2.3b": "Fig. 2.15b (S1, M, S2): stage 1 moves along X by S1 and carries stage 2 moving along Y by S2.",
            "C2.3c": "Fig. 2.15c (M, phi, S): a carriage moving along X by S carries a link of length l turning by phi; M at its end.",
        }[task]
        return DerivationStep(
            "Task",
            text + " Masses and forces are illustrative.",
            None,
            src,
            reconstructed="only the labels of Fig. 2.15 survive; the arrangement is a reading",
        )
    if task.startswith("C2.4"):
        text = {
            "C2.4a": "one coordinate at a time",
            "C2.4b": "two coordinates at once",
            "C2.4c": "x, y and z together",
        }[task]
        return DerivationStep(
            "Task",
            f"Fig. 2.16: the X stage (m1) carries the Y stage (m2) which carries the Z stage (m3); {text} "
            f"(moving: {params['axes']}). Masses and forces are illustrative.",
            None,
            src,
            reconstructed="the stacking order X-Y-Z is a reading of the figure's axes",
        )
    if task == "C2.5":
        return DerivationStep(
            "Task",
            "The moving element of the two-coordinate positioner (Fig. 2.3) also turns by phi in its plane: "
            "x, y of the drive point A and phi are independent; its centre of mass G lies l from A. "
            "Illustrative numbers.",
            None,
            src,
            reconstructed="the offset l of G from A is chosen to show the coupling",
        )
    text = {
        "C2.6a": "inductor A fixed at x_A = a, y_A = b, z_A = 0",
        "C2.6b": "A fixed at (a, b, 0) and B fixed at (c, d, 0)",
        "C2.6c": "A, B and C moving on one circle of radius R about x_O = y_O = z_O = 0",
    }[task]
    return DerivationStep(
        "Task",
        f"Fig. 2.6 (Problem 2.5): {text}.  Only the inductors' energies T_A, T_B, T_C survive; the table and "
        "leg energies and the mechanism geometry are lost, so the table's share is left out.",
        None,
        src,
        reconstructed="table and leg kinetic energies of Problem 2.5 are not reconstructable; inductors as point masses",
    )


def _closed_forms(task: str, params: Params) -> list[DerivationStep]:
    phi, t = sp.symbols("varphi t", real=True)
    J = sp.Symbol("J", positive=True)
    if task == "C2.1a":
        return [
            DerivationStep(
                "Closed form (horizontal plane)",
                "J phi'' = 2 gives phi = t^2/J, so phi = pi at t = sqrt(pi J).",
                sp.Eq(sp.Symbol("t_180"), sp.sqrt(sp.pi * J)),
                "C2.1a",
            )
        ]
    if task == "C2.1b":
        return [
            DerivationStep(
                "Closed form (horizontal plane, M_c = 0.1 phi)",
                "phi = 20 (1 - cos(sqrt(0.1/J) t)).",
                sp.Eq(
                    sp.Symbol("t_180"), sp.acos(1 - sp.pi / 20) / sp.sqrt(sp.Rational(1, 10) / J)
                ),
                "C2.1b",
            )
        ]
    if task.startswith("C2.2"):
        m = sp.Symbol("m", positive=True)
        Fg = sp.Function("F_g")(t)
        Fc = sp.Function("F_c")(t)
        return [
            DerivationStep(
                "Along the line",
                "s = sqrt(2) x is the path length: m s'' = F_g - F_c (horizontal plane).",
                sp.Eq(m * sp.Derivative(sp.Function("s")(t), (t, 2)), Fg - Fc),
                "C2.2",
            )
        ]
    return []


# ---------------------------------------------------------------- drawing


def _mesh(
    name: str, mesh: trimesh.Trimesh, color: tuple[int, int, int], opacity: float = 0.8
) -> MeshItem:
    return MeshItem(
        name,
        np.asarray(mesh.vertices, dtype=float),
        np.asarray(mesh.faces, dtype=np.int64),
        color,
        opacity,
    )


def _zquat(angle: float) -> np.ndarray:
    return np.array([math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)])


def _drawing(
    params: Params, model: Model, size: float, lo: np.ndarray, hi: np.ndarray
) -> tuple[list[MeshItem], list[CurveItem], list[MarkerItem]]:
    task = params["task"]
    s = size
    bodies: list[MeshItem] = []
    curves: list[CurveItem] = []
    markers: list[MarkerItem] = [MarkerItem("O", np.zeros((1, 3)), (40, 40, 40), 0.3 * s, "O")]
    if task.startswith("C2.1"):
        L = params["l_OM"]
        link = trimesh.creation.box(extents=(L, 0.15 * L, 0.05 * L))
        link.apply_translation((L / 2, 0, 0))
        bodies.append(_mesh("link", link, (120, 160, 220)))
        ring = np.array(
            [[L * math.cos(a), L * math.sin(a), 0] for a in np.linspace(0, 2 * math.pi, 121)]
        )
        curves.append(CurveItem("circle of M", ring, (160, 160, 160), 1.0))
    elif task.startswith("C2.2"):
        xs = np.array([lo[0], hi[0]])
        curves.append(
            CurveItem("y = x + 1", np.column_stack([xs, xs + 1, np.zeros(2)]), (80, 80, 80))
        )
        L = max(params["l_AM"], 1e-3)
        link = trimesh.creation.box(extents=(L, 0.1 * L, 0.05 * L))
        link.apply_translation((-L / 2, 0, 0))
        bodies.append(_mesh("link AM", link, (120, 160, 220)))
        bodies.append(
            _mesh(
                "slider M",
                trimesh.creation.box(extents=(0.3 * L, 0.2 * L, 0.1 * L)),
                (220, 120, 60),
            )
        )
    elif task == "C2.3a":
        L = max(float(hi[0] - lo[0]), float(hi[1] - lo[1])) / 2
        arm = trimesh.creation.box(extents=(L, 0.05 * L, 0.02 * L))
        arm.apply_translation((L / 2, 0, 0))
        bodies.append(_mesh("arm", arm, (120, 160, 220)))
        bodies.append(
            _mesh("slider", trimesh.creation.box(extents=(2 * s, 1.2 * s, 0.8 * s)), (220, 120, 60))
        )
    elif task == "C2.3b":
        bodies.append(
            _mesh(
                "stage 1", trimesh.creation.box(extents=(3 * s, 1.5 * s, 0.5 * s)), (120, 160, 220)
            )
        )
        bodies.append(
            _mesh(
                "stage 2", trimesh.creation.box(extents=(1.5 * s, 1.5 * s, 0.6 * s)), (220, 120, 60)
            )
        )
        curves.append(CurveItem("X guide", np.array([[lo[0], 0, 0], [hi[0], 0, 0]]), (80, 80, 80)))
    elif task == "C2.3c":
        L = params["l"]
        link = trimesh.creation.box(
            extents=(max(L, 1e-3), 0.08 * max(L, 1e-3), 0.04 * max(L, 1e-3))
        )
        link.apply_translation((L / 2, 0, 0))
        bodies.append(
            _mesh(
                "carriage", trimesh.creation.box(extents=(3 * s, 1.5 * s, 0.6 * s)), (120, 160, 220)
            )
        )
        bodies.append(_mesh("link", link, (220, 120, 60)))
        curves.append(CurveItem("X guide", np.array([[lo[0], 0, 0], [hi[0], 0, 0]]), (80, 80, 80)))
    elif task.startswith("C2.4"):
        bodies.append(
            _mesh("X stage", trimesh.creation.box(extents=(3 * s, 3 * s, 0.4 * s)), (120, 160, 220))
        )
        bodies.append(
            _mesh("Y stage", trimesh.creation.box(extents=(2 * s, 2 * s, 0.4 * s)), (120, 200, 120))
        )
        bodies.append(
            _mesh(
                "Z stage", trimesh.creation.box(extents=(0.8 * s, 0.8 * s, 2 * s)), (220, 120, 60)
            )
        )
    elif task == "C2.5":
        L = max(params["l"], 2 * s)
        plate = trimesh.creation.box(extents=(2 * L, L, 0.2 * L))
        bodies.append(_mesh("element", plate, (120, 160, 220), 0.6))
    else:
        for name, col in (("A", (220, 60, 60)), ("B", (60, 160, 60)), ("C", (60, 60, 220))):
            bodies.append(
                _mesh(
                    f"inductor {name}",
                    trimesh.creation.box(extents=(1.2 * s, 1.2 * s, 0.5 * s)),
                    col,
                )
            )
        if task == "C2.6c":
            R = params["R"]
            curves.append(
                CurveItem(
                    "circle R",
                    np.array(
                        [
                            [R * math.cos(a), R * math.sin(a), 0]
                            for a in np.linspace(0, 2 * math.pi, 181)
                        ]
                    ),
                    (80, 80, 80),
                )
            )
        else:
            fixed = [[params["a"], params["b"], 0.0]] + (
                [[params["c"], params["d"], 0.0]] if task == "C2.6b" else []
            )
            markers.append(
                MarkerItem("fixed inductors", np.array(fixed), (0, 0, 0), 0.5 * s, "fixed")
            )
    return bodies, curves, markers


def _poses(
    params: Params, model: Model, q: np.ndarray, consts: list[float]
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    task = params["task"]
    P = lambda name: model.point(name, q, consts)  # noqa: E731
    ident = np.array([1.0, 0.0, 0.0, 0.0])
    if task.startswith("C2.1"):
        return {"link": (np.zeros(3), _zquat(q[0]))}
    if task.startswith("C2.2"):
        qz = _zquat(math.pi / 4)
        return {"link AM": (P("M"), qz), "slider M": (P("M"), qz)}
    if task == "C2.3a":
        return {"arm": (np.zeros(3), _zquat(q[0])), "slider": (P("M"), _zquat(q[0]))}
    if task == "C2.3b":
        return {"stage 1": (P("P1"), ident), "stage 2": (P("M"), ident)}
    if task == "C2.3c":
        return {"carriage": (P("C"), ident), "link": (P("C"), _zquat(q[1]))}
    if task.startswith("C2.4"):
        return {
            "X stage": (P("PX"), ident),
            "Y stage": (P("PY"), ident),
            "Z stage": (P("PZ"), ident),
        }
    if task == "C2.5":
        return {"element": (P("G"), _zquat(q[2]))}
    return {f"inductor {n}": (P(n), _zquat(math.atan2(P(n)[1], P(n)[0]))) for n in "ABC"}


class _SelfStudyStepper(Stepper):
    def __init__(self, lesson: SelfStudy2, params: Params) -> None:
        self.lesson = lesson
        self._load(params)
        self.reset()

    def _load(self, params: Params) -> None:
        self.params = params
        self.model = self.lesson.model(params)
        self.consts = _consts(params, self.model)

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        n = self.model.n
        q, qd = self.y[:n], self.y[n:]
        obs = self.lesson.observables(self.params, np.array([self._t]), self.y[:, None])
        scalars = {
            k: float(v[0])
            for k, v in obs.items()
            if k[:-1] in ("q", "v", "Q", "lambda") and k[-1].isdigit()
        }
        names = list(self.lesson.scene_points(self.params))
        points = {nm: self.model.point(nm, q, self.consts)[None, :] for nm in names}
        _ = qd
        return Frame(
            t=self._t,
            points=points,
            poses=_poses(self.params, self.model, q, self.consts),
            scalars=scalars,
            message=self.message,
        )

    def advance(self, dt: float) -> Frame:
        if self.stopped or dt <= 0:
            return self.frame()
        try:
            sol = self.lesson.integrate(
                self.params, self._t, self.y, self._t + float(dt), rtol=1e-9
            )
        except (ValueError, np.linalg.LinAlgError) as exc:
            self.message = f"integration failed: {exc}"
            self.stopped = True
            return self.frame()
        self.y = sol.y[:, -1].copy()
        self._t = float(sol.t[-1])
        if sol.status == 1:
            self.y = sol.y_events[0][0].copy()
            self._t = float(sol.t_events[0][0])
            self.stopped = True
            self.message = f"phi_k = 180 deg reached at t = {self._t:.5g} s"
        elif sol.status == -1 or not np.all(np.isfinite(self.y)):
            self.stopped = True
            self.message = f"integration stopped: {sol.message}"
        return self.frame()

    def set_params(self, params: Params) -> None:
        same = params["task"] == self.params["task"] and params["axes"] == self.params["axes"]
        self._load(params)
        if not same:
            self.reset()

    def reset(self) -> Frame:
        q0, v0 = _initial(self.params, self.model)
        self.y = np.concatenate([q0, v0])
        self._t = 0.0
        self.stopped = False
        self.message = ""
        return self.frame()


# ---------------------------------------------------------------- claim checks


LESSON = SelfStudy2()


def _check_c21_numbers() -> ClaimResult:
    vals = [LESSON.resolve(preset=p) for p in ("c2-1a", "c2-1b", "c2-1c")]
    ok = all(v["l_OM"] == 0.2 and v["m1"] == 0.4 and v["J0"] == 0.01 for v in vals)
    J = vals[0]["J0"] + vals[0]["m1"] * vals[0]["l_OM"] ** 2
    r = close(0.026, J, atol=1e-15)
    return ClaimResult(f"presets 0.2, 0.4, 0.01; J = {r.expected}", f"J = {r.got}", ok and r.passed)


def _check_c21_equation() -> ClaimResult:
    m = model_for("C2.1a")
    phi = m.q[0]
    l, J0, m1e, ge = m.consts
    Mg, Mc = m.inputs
    eq = m.equations[0].subs(ge, 0)
    d = sp.simplify(eq - ((J0 + m1e * l**2) * sp.diff(phi, TIME, 2) - (Mg - Mc)))
    return ClaimResult("difference 0", str(d), d == 0)


def _t180(task: str, inertia: str, reading: str = "0.1 phi") -> float:
    run = LESSON.run(preset=_preset_of(task), values={"inertia": inertia, "Mc_reading": reading})
    return float(run.metrics.get("t_180", float("nan")))


def _check_c21a() -> ClaimResult:
    a, b = _t180("C2.1a", "J0"), _t180("C2.1a", "J0 + m1 l_OM^2")
    ok = (
        abs(a - math.sqrt(math.pi * 0.01)) < 1e-7
        and abs(b - math.sqrt(math.pi * 0.026)) < 1e-7
        and round(a, 4) == 0.1772
        and round(b, 4) == 0.2858
    )
    return ClaimResult("0.1772 s, 0.2858 s", f"{a:.6f} s, {b:.6f} s", ok)


def _check_c21b() -> ClaimResult:
    a, b = _t180("C2.1b", "J0"), _t180("C2.1b", "J0 + m1 l_OM^2")
    fa = math.acos(1 - math.pi / 20) / math.sqrt(0.1 / 0.01)
    fb = math.acos(1 - math.pi / 20) / math.sqrt(0.1 / 0.026)
    ok = (
        abs(a - fa) < 1e-7
        and abs(b - fb) < 1e-7
        and round(a, 4) == 0.1797
        and round(b, 4) == 0.2897
    )
    return ClaimResult("0.1797 s, 0.2897 s", f"{a:.6f} s, {b:.6f} s", ok)


def _check_c21c() -> ClaimResult:
    left = _c21_moments("C2.1c", "", 4 * math.pi)[0]
    right = _c21_moments("C2.1c", "", 4 * math.pi + 1e-12)[0]
    rest = LESSON.run(preset="c2-1c", values={"phidot0": 0.0, "phi0": 0.0}, t_end=1.0)
    moved = float(np.max(np.abs(rest.series["phi"])))
    ok = abs(left - right) < 1e-10 and abs(left - 8 * math.pi) < 1e-12 and moved == 0.0
    return ClaimResult(
        "M_g(4 pi) = 8 pi on both sides; phi stays 0",
        f"{left:.10g} / {right:.10g}; max |phi| = {moved:.3g}",
        ok,
    )


def _check_c22_equation() -> ClaimResult:
    m = model_for("C2.2a")
    x = m.q[0]
    mm, ge, _ = m.consts
    Fg, Fc = m.inputs
    d = sp.simplify(
        m.equations[0] - (2 * mm * sp.diff(x, TIME, 2) - sp.sqrt(2) * (Fg - Fc) + mm * ge)
    )
    return ClaimResult("difference 0", str(d), d == 0)


def _check_c22_runs() -> ClaimResult:
    got = []
    for preset, t_end in (("c2-2a", 1.0), ("c2-2b", 10.0), ("c2-2c", 10.0)):
        run = LESSON.run(preset=preset, t_end=t_end)
        got.append(math.sqrt(2) * float(run.series["x"][-1]))
    want = [5.0, 4 * (10 - math.sin(10)), 4 * (10 - math.sin(10)) - 1000 / 3]
    ok = all(abs(g - w) <= 1e-7 * max(1.0, abs(w)) for g, w in zip(got, want))
    return ClaimResult(
        ", ".join(f"{w:.6f}" for w in want) + " m", ", ".join(f"{g:.6f}" for g in got) + " m", ok
    )


def _check_c23() -> ClaimResult:
    diffs = []
    a = model_for("C2.3a")
    phi, S = a.q
    J, m2, ge = a.consts
    Q1, Q2 = a.inputs
    d = lambda f, k=1: sp.diff(f, TIME, k)  # noqa: E731
    hand_a = [
        (J + m2 * S**2) * d(phi, 2) + 2 * m2 * S * d(S) * d(phi) + m2 * ge * S * sp.cos(phi) - Q1,
        m2 * d(S, 2) - m2 * S * d(phi) ** 2 + m2 * ge * sp.sin(phi) - Q2,
    ]
    diffs += [sp.simplify(e - h) for e, h in zip(a.equations, hand_a)]
    b = model_for("C2.3b")
    S1, S2 = b.q
    m1, m2b, geb = b.consts
    diffs += [
        sp.simplify(b.equations[0] - ((m1 + m2b) * d(S1, 2) - b.inputs[0])),
        sp.simplify(b.equations[1] - (m2b * d(S2, 2) + m2b * geb - b.inputs[1])),
    ]
    c = model_for("C2.3c")
    Sc, ph = c.q
    m1c, m2c, Jc, l, gec = c.consts
    hand_c = [
        (m1c + m2c) * d(Sc, 2)
        - m2c * l * sp.sin(ph) * d(ph, 2)
        - m2c * l * sp.cos(ph) * d(ph) ** 2
        - c.inputs[0],
        (Jc + m2c * l**2) * d(ph, 2)
        - m2c * l * sp.sin(ph) * d(Sc, 2)
        + m2c * gec * l * sp.cos(ph)
        - c.inputs[1],
    ]
    diffs += [sp.simplify(e - h) for e, h in zip(c.equations, hand_c)]
    return ClaimResult("all differences 0", str(diffs), all(x == 0 for x in diffs))


def _check_c24() -> ClaimResult:
    m = model_for("C2.4c", "xyz")
    x, y, z = m.q
    m1, m2, m3, ge = m.consts
    Q = m.inputs
    d2 = lambda f: sp.diff(f, TIME, 2)  # noqa: E731
    hand = [(m1 + m2 + m3) * d2(x) - Q[0], (m2 + m3) * d2(y) - Q[1], m3 * d2(z) + m3 * ge - Q[2]]
    diffs = [sp.simplify(e - h) for e, h in zip(m.equations, hand)]
    single = model_for("C2.4a", "y")
    ok_single = (
        single.n == 1
        and sp.simplify(single.equations[0] - ((m2 + m3) * d2(single.q[0]) - Q[1])) == 0
    )
    return ClaimResult(
        "differences 0; axis y alone: (m2+m3) y'' = Q2",
        f"{diffs}; {ok_single}",
        all(x == 0 for x in diffs) and ok_single,
    )


def _check_c25() -> ClaimResult:
    m = model_for("C2.5")
    x, y, phi = m.q
    m1, J, l = m.consts
    Q1, Q2, Q3 = m.inputs
    d = lambda f, k=1: sp.diff(f, TIME, k)  # noqa: E731
    hand = [
        m1 * d(x, 2) - m1 * l * (sp.sin(phi) * d(phi, 2) + sp.cos(phi) * d(phi) ** 2) - Q1,
        m1 * d(y, 2) + m1 * l * (sp.cos(phi) * d(phi, 2) - sp.sin(phi) * d(phi) ** 2) - Q2,
        (J + m1 * l**2) * d(phi, 2)
        + m1 * l * (-sp.sin(phi) * d(x, 2) + sp.cos(phi) * d(y, 2))
        - Q3,
    ]
    diffs = [sp.simplify(e - h) for e, h in zip(m.equations, hand)]
    run = LESSON.run(preset="c2-5")
    turned = abs(float(run.series["phi"][-1])) > 1e-3
    return ClaimResult(
        "differences 0; a force at A alone turns the element",
        f"{diffs}; phi(end) = {run.series['phi'][-1]:.4g}",
        all(v == 0 for v in diffs) and turned,
    )


def _check_c26() -> ClaimResult:
    errs, fixed = [], []
    for preset in ("c2-6a", "c2-6b", "c2-6c"):
        run = LESSON.run(preset=preset)
        errs.append(float(run.metrics["max_constraint_error"]))
        if preset != "c2-6c":
            fixed.append(
                float(
                    np.max(np.abs(run.series["x_A"] - 0.1))
                    + np.max(np.abs(run.series["y_A"] - 0.1))
                )
            )
    run = LESSON.run(preset="c2-6c")
    # constraint force on A: H^T lambda = 2 lambda_1 (x_A, y_A); radial magnitude 2 |lambda_1| R = m v^2 / R (no radial drive)
    p = LESSON.resolve(preset="c2-6c")
    v2 = run.series["x_A_dot"] ** 2 + run.series["y_A_dot"] ** 2
    radial = 2 * np.abs(run.series["lambda_1"]) * p["R"]
    cent = p["m1"] * v2 / p["R"]
    rel = float(np.max(np.abs(radial - cent)) / max(float(np.max(cent)), 1e-300))
    ok = max(errs) <= 1e-8 and max(fixed) <= 1e-12 and rel <= 1e-6
    return ClaimResult(
        "constraint error <= 1e-8; fixed points exact; |reaction| = m v^2/R",
        f"errors {', '.join(f'{e:.1e}' for e in errs)}; fixed drift {max(fixed):.1e}; reaction vs m v^2/R {rel:.1e}",
        ok,
    )
