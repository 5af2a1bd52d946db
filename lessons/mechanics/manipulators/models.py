"""Lagrangian models of the simple manipulators of chapter 2, self-study tasks C2.1-C2.6.

One :class:`Model` per task, built with ``sympy.physics.mechanics.LagrangesMethod`` from
the kinetic and potential energy and the generalized forces of the task's figure
(Figs 2.13-2.16, 2.3, 2.6), and lambdified once (:func:`model_for` caches it).  The
integrated equations are the Lagrange equations of the 2nd kind (2.5), (2.13); C2.6
adds holonomic constraints with multipliers, the route of §2.2 (2.17), (2.25),
(2.30)-(2.34), as LagrangesMethod builds it (``hol_coneqs``): the mass matrix
``[M -H^T; H 0]`` is solved for the accelerations and the multipliers together.
The figures survive only as labels, so every arrangement beyond the labels is a reading.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.once import once
from sympy.physics import mechanics as me

TIME = me.dynamicsymbols._t


@dataclass
class Model:
    """One task's Lagrangian model, derived once and lambdified.

    ``points`` are the named points drawn and observed (position vectors in the fixed
    frame N); ``constraints`` the holonomic constraints ``f_i(q) = 0`` (2.17), if any.
    """

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

    @property
    def n(self) -> int:
        return len(self.q)

    @once
    def simplified(self) -> list[sp.Expr]:
        """The Lagrange equations, simplified once (for the derivation page)."""
        return [sp.simplify(e) for e in self.equations]

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
        """The point ``name`` for coordinates ``q`` of shape ``(n,)`` or ``(n, N)``:
        shape ``(3,)`` or ``(N, 3)``."""
        q = np.asarray(q, dtype=float)
        xyz = self._pts[name](list(q), consts)
        return np.stack([np.broadcast_to(np.asarray(c, dtype=float), q.shape[1:]) for c in xyz], -1)


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
    )


def _c22() -> Model:
    """Fig. 2.14: M moves on y = x + 1 under F_g (drive) and F_c (resistance) along the line."""
    x = me.dynamicsymbols("x")
    m, ge = sp.symbols("m g_e")
    Fg, Fc = sp.symbols("F_g F_c")
    N, O = _frame_setup()
    M = O.locatenew("M", x * N.x + (x + 1) * N.y)
    M.set_vel(N, M.pos_from(O).dt(N))
    e = (N.x + N.y) / sp.sqrt(2)
    body = me.Particle("M", M, m)
    body.potential_energy = m * ge * (x + 1)
    lm = me.LagrangesMethod(me.Lagrangian(N, body), [x], forcelist=[(M, (Fg - Fc) * e)], frame=N)
    return Model(
        "C2.2",
        ("x",),
        [x],
        body.kinetic_energy(N),
        m * ge * (x + 1),
        "force (F_g - F_c) along the line",
        lm,
        (m, ge),
        (Fg, Fc),
        {"M": _vec(M, O, N)},
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


def by_hand(model: Model) -> list[sp.Expr]:
    """The task's equations derived by hand from T, U and Q of its figure, each as
    ``lhs - Q = 0`` in the model's coordinates: what LagrangesMethod must reproduce (2.5)."""
    q, c, u = model.q, model.consts, model.inputs

    def d(f: Any, k: int = 1) -> Any:
        return sp.diff(f, TIME, k)

    if model.key == "C2.1":
        (phi,), (l, J0, m1, ge), (Mg, Mc) = q, c, u
        return [(J0 + m1 * l**2) * d(phi, 2) + m1 * ge * l * sp.cos(phi) - (Mg - Mc)]
    if model.key == "C2.2":
        (x,), (m, ge), (Fg, Fc) = q, c, u
        return [2 * m * d(x, 2) - sp.sqrt(2) * (Fg - Fc) + m * ge]
    if model.key == "C2.3a":
        (phi, S), (J, m2, ge), (Q1, Q2) = q, c, u
        return [
            (J + m2 * S**2) * d(phi, 2)
            + 2 * m2 * S * d(S) * d(phi)
            + m2 * ge * S * sp.cos(phi)
            - Q1,
            m2 * d(S, 2) - m2 * S * d(phi) ** 2 + m2 * ge * sp.sin(phi) - Q2,
        ]
    if model.key == "C2.3b":
        (S1, S2), (m1, m2, ge), (Q1, Q2) = q, c, u
        return [(m1 + m2) * d(S1, 2) - Q1, m2 * d(S2, 2) + m2 * ge - Q2]
    if model.key == "C2.3c":
        (S, phi), (m1, m2, J, l, ge), (Q1, Q2) = q, c, u
        s, co = sp.sin(phi), sp.cos(phi)
        return [
            (m1 + m2) * d(S, 2) - m2 * l * (s * d(phi, 2) + co * d(phi) ** 2) - Q1,
            (J + m2 * l**2) * d(phi, 2) - m2 * l * s * d(S, 2) + m2 * ge * l * co - Q2,
        ]
    if model.key == "C2.5":
        (x, y, phi), (m1, J, l), (Q1, Q2, Q3) = q, c, u
        s, co = sp.sin(phi), sp.cos(phi)
        return [
            m1 * d(x, 2) - m1 * l * (s * d(phi, 2) + co * d(phi) ** 2) - Q1,
            m1 * d(y, 2) + m1 * l * (co * d(phi, 2) - s * d(phi) ** 2) - Q2,
            (J + m1 * l**2) * d(phi, 2) + m1 * l * (-s * d(x, 2) + co * d(y, 2)) - Q3,
        ]
    # C2.4: each stage carries the ones after it; gravity acts along Z on the Z stage
    (m1, m2, m3, ge), Q = c, u
    carried = {"x": m1 + m2 + m3, "y": m2 + m3, "z": m3}
    return [
        carried[a] * d(qa, 2) + (m3 * ge if a == "z" else 0) - Q["xyz".index(a)]
        for a, qa in zip(model.coords, q)
    ]
