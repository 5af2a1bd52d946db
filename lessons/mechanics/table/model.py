"""Problem 2.5: a work table with six degrees of freedom driven by three planar inductors.

The source gives the mechanism only in figures lost in the extraction (Figs 2.6-2.9), so
the geometry here is **reconstructed** from the text, consistently:

* three planar inductors A, B, C move in the horizontal plane z = 0; their coordinates
  ``x_A, y_A, x_B, y_B, x_C, y_C`` are the six generalized coordinates of the source;
* the table (mass ``M_c``, centre D, inertia ``J_D`` about its tilt axes and ``J_Dz``
  about its normal; the source's isotropic ``Z_D`` is ``J_D = J_Dz``) carries three joints
  A', B', C' at the vertices of an equilateral triangle of circumradius ``r_t``;
* a rigid leg of length ``l`` (mass ``m_l``, slender rod) joins each inductor to its
  table joint: a ball joint on the inductor and a hinge on the table whose axis is
  parallel to the opposite side of the triangle.  So each leg stays in the plane through
  the vertex perpendicular to that side: the inductor moves along the axis "n (eta),
  tau, rho" of the text, perpendicular to the triangle's sides, and its displacement along
  it is ``S = sqrt(l^2 - Z'^2)`` at zero tilt: the joint height Z' sets the displacement,
  as the text says;
* table orientation: yaw ``phi`` about Z through D, then tilts ``beta`` (about Y) and
  ``alpha`` (about X): ``R = Rz(phi) Ry(beta) Rx(alpha)``.

Loops opened (§2.2): 12 coordinates ``(x_D, y_D, z_D, alpha, beta, phi, x_A, ..., y_C)``
with the six holonomic constraints per leg ``(A - A') . (R e_k) = 0`` and
``|A - A'|^2 - l^2 = 0``; 12 - 6 = 6 degrees of freedom.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from analyzer_lab.lessons.kit.bodies import (
    bounds_of,
    box,
    combine,
    cylinder,
    quat_z,
    quat_zyx,
    segment_pose,
)
from analyzer_lab.lessons.kit.contract import Frame, MeshItem, SceneSpec
from analyzer_lab.lessons.mechanics.lagrange.constrained import ConstrainedSystem
from analyzer_lab.lessons.mechanics.lagrange.model import plain_symbols
from sympy.physics.mechanics import (
    KanesMethod,
    Particle,
    Point,
    ReferenceFrame,
    RigidBody,
    dynamicsymbols,
    inertia,
)

T_ = dynamicsymbols._t
Array = np.ndarray

POSE = ("x_D", "y_D", "z_D", "alpha", "beta", "phi")
INDUCTORS = ("x_A", "y_A", "x_B", "y_B", "x_C", "y_C")
COORDS = POSE + INDUCTORS
FORCES = ("F_Ax", "F_Ay", "F_Bx", "F_By", "F_Cx", "F_Cy")
PHYSICAL = ("M_c", "J_D", "J_Dz", "m_A", "m_B", "m_C", "m_l", "l", "r_t", "g")
COLORS = ((70, 130, 200), (200, 130, 70), (160, 90, 200))  # inductors A, B, C
VERTEX_ANGLES = (np.pi / 2, np.pi / 2 + 2 * np.pi / 3, np.pi / 2 + 4 * np.pi / 3)  # A, B, C


def rotation(alpha: Any, beta: Any, phi: Any) -> Array:
    """``R = Rz(phi) Ry(beta) Rx(alpha)`` at one orientation (:func:`rotations`)."""
    return rotations(np.atleast_1d(alpha), np.atleast_1d(beta), np.atleast_1d(phi))[0]


def joints_body(r_t: float) -> Array:
    """Table joints A', B', C' in the table frame (rows)."""
    return np.array([[r_t * np.cos(a), r_t * np.sin(a), 0.0] for a in VERTEX_ANGLES])


def radial_axes() -> Array:
    """Virtual axes n_k (perpendicular to the side opposite vertex k) in the table frame."""
    return np.array([[np.cos(a), np.sin(a), 0.0] for a in VERTEX_ANGLES])


def table_joints(pose: Array, r_t: float) -> Array:
    """A', B', C' in the fixed frame for a pose (x_D, y_D, z_D, alpha, beta, phi)."""
    R = rotation(pose[3], pose[4], pose[5])
    return pose[:3] + joints_body(r_t) @ R.T


def inverse_kinematics(pose: Array, l: float, r_t: float) -> tuple[Array, bool]:
    """Inductor coordinates ``(x_A, y_A, ..., y_C)`` for a table pose; ``ok`` is False when
    a leg cannot reach the floor (joint higher than l) or the leg plane is horizontal."""
    R = rotation(pose[3], pose[4], pose[5])
    Ap = table_joints(pose, r_t)
    out = np.zeros(6)
    ok = True
    for k in range(3):
        u1 = R @ radial_axes()[k]
        u2 = R @ np.array([0.0, 0.0, 1.0])
        c = float(np.hypot(u1[2], u2[2]))
        kappa = -Ap[k, 2] / (l * c) if c > 1e-12 else np.inf
        if not abs(kappa) <= 1.0:
            ok = False
            kappa = float(np.clip(kappa, -1.0, 1.0)) if np.isfinite(kappa) else 0.0
        delta = float(np.arctan2(u2[2], u1[2]))
        cands = [delta + np.arccos(kappa), delta - np.arccos(kappa)]
        psi = max(cands, key=lambda v: np.cos(v))  # the leg splays outwards
        d = l * (np.cos(psi) * u1 + np.sin(psi) * u2)
        out[2 * k : 2 * k + 2] = (Ap[k] + d)[:2]
    return out, ok


@dataclass
class TableModel:
    system: ConstrainedSystem
    T_table: sp.Expr
    T_leg: sp.Expr
    U: sp.Expr
    q: list[sp.Function]
    S: Array  # dB/dF: how the inductor forces enter (virtual work), constant


def build_table_model() -> TableModel:
    """D'Alembert-Lagrange equations of the opened system (``KanesMethod`` with the
    generalized speeds ``u = q'``: the same equations as Lagrange's, and the principle
    (2.22) of §2.2 itself), then the six holonomic constraints of the legs.

    Each leg (slender rod, mass ``m_l``) is represented exactly, for its kinetic energy
    ``m_l/6 (|v_A|^2 + v_A.v_A' + |v_A'|^2)``, by ``m_l/6`` at both ends and ``2 m_l/3``
    at the middle."""
    q = dynamicsymbols(" ".join(COORDS))
    u = dynamicsymbols(" ".join(c + "_u" for c in COORDS))
    xD, yD, zD, al, be, ph = q[:6]
    ind = q[6:]
    pos = {n: sp.Symbol(n, real=True, positive=True) for n in PHYSICAL if n != "g"}
    g = sp.Symbol("g", real=True, nonnegative=True)
    Mc, JD, JDz, mA, mB, mC, ml, l, rt = (pos[n] for n in PHYSICAL[:-1])
    F = [sp.Symbol(n, real=True) for n in FORCES]
    N = ReferenceFrame("N")
    Tb = N.orientnew("Tb", "Body", [ph, be, al], "ZYX")  # R = Rz(phi) Ry(beta) Rx(alpha)
    w_q = Tb.ang_vel_in(N)
    qd_to_u = {qi.diff(T_): ui for qi, ui in zip(q, u)}
    Tb.set_ang_vel(N, w_q.subs(qd_to_u))
    O = Point("O")
    O.set_vel(N, 0)
    D = O.locatenew("D", xD * N.x + yD * N.y + zD * N.z)
    D.set_vel(N, u[0] * N.x + u[1] * N.y + u[2] * N.z)
    table = RigidBody("table", D, Tb, Mc, (inertia(Tb, JD, JD, JDz), D))
    bodies: list[Any] = [table]
    loads: list[Any] = [(D, -Mc * g * N.z)]
    f_hol = []
    U = Mc * g * zD
    for k, a in enumerate(VERTEX_ANGLES):
        ang = sp.Rational(int(round(np.degrees(a))), 180) * sp.pi
        ca, sa = sp.cos(ang), sp.sin(ang)
        Ap = D.locatenew(f"J{k}", rt * (ca * Tb.x + sa * Tb.y))
        Ap.v2pt_theory(D, N, Tb)
        Ak = O.locatenew(f"I{k}", ind[2 * k] * N.x + ind[2 * k + 1] * N.y)
        Ak.set_vel(N, u[6 + 2 * k] * N.x + u[7 + 2 * k] * N.y)
        Mid = Ak.locatenew(f"M{k}", Ap.pos_from(Ak) / 2)
        Mid.set_vel(N, (Ak.vel(N) + Ap.vel(N)) / 2)
        for name, P, m in (
            (f"inductor{k}", Ak, (mA, mB, mC)[k] + ml / 6),
            (f"leg_top{k}", Ap, ml / 6),
            (f"leg_mid{k}", Mid, 2 * ml / 3),
        ):
            bodies.append(Particle(name, P, m))
            loads.append((P, -m * g * N.z))
        U += ml * g * Ap.pos_from(O).dot(N.z) / 2
        loads.append((Ak, F[2 * k] * N.x + F[2 * k + 1] * N.y))
        d = Ak.pos_from(Ap)
        f_hol += [d.dot(-sa * Tb.x + ca * Tb.y), d.dot(d) - l**2]
    km = KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff(T_) - ui for qi, ui in zip(q, u)])
    km.kanes_equations(bodies, loads)
    qs, qds = plain_symbols(q)
    to_plain_u = {ui: s for ui, s in zip(u, qds)}
    to_plain_q = {qi: s for qi, s in zip(q, qs)}
    plain = {**to_plain_u, **to_plain_q}  # Kane's A and B hold q(t), u(t) and no derivatives
    A = km.mass_matrix.xreplace(plain)
    B = km.forcing.xreplace(plain)
    cs = ConstrainedSystem.build(
        qs,
        qds,
        T_,
        A,
        B,
        [*pos.values(), g],
        F,
        f_hol=[sp.sympify(f, strict=True).xreplace(to_plain_q) for f in f_hol],
    )
    T_table = table.kinetic_energy(N).subs({ui: qi.diff(T_) for qi, ui in zip(q, u)})
    vA, vJ, vAJ = sp.symbols("v_A v_J vAvJ", real=True)  # end speeds and their dot product
    T_leg = ml / 6 * (vA**2 + vAJ + vJ**2)
    S = cs.B.jacobian(F)
    if S.free_symbols:
        raise RuntimeError("inductor forces must enter B with constant coefficients")
    return TableModel(cs, T_table, T_leg, U, list(q), np.array(S.tolist(), dtype=float))


_MODEL: list[TableModel] = []


def table_model() -> TableModel:
    """The symbolic model, built once (a few seconds) and lambdified once."""
    if not _MODEL:
        tm = build_table_model()
        z = np.zeros((1, 12))  # the vectorized functions, built once with the model
        tm.system.parts_many(0.0, z, z, np.ones(len(PHYSICAL)), np.zeros(6))
        _MODEL.append(tm)
    return _MODEL[0]


def program_state(
    pose: Array, pose_d: Array, pose_dd: Array, p: Array
) -> tuple[Array, Array, Array, bool]:
    """Full 12-coordinate ``(q, q', q'')`` for a table pose program: inductors from the
    inverse kinematics, their velocities from (2.29) and accelerations from (2.30)."""
    cs = table_model().system
    l, rt = float(p[PHYSICAL.index("l")]), float(p[PHYSICAL.index("r_t")])
    ind, ok = inverse_kinematics(pose, l, rt)
    q = np.concatenate([pose, ind])
    u0 = np.zeros(6)
    qd = np.concatenate([pose_d, np.zeros(6)])
    P = cs.parts(0.0, q, qd, p, u0, ("H", "psi"))
    H = P["H"]
    Hs, Hi = H[:, :6], H[:, 6:]
    qd[6:] = np.linalg.solve(Hi, -(Hs @ pose_d + P["psi"]))
    P = cs.parts(0.0, q, qd, p, u0, ("Phi",))
    qdd = np.concatenate([pose_dd, np.linalg.solve(Hi, -(P["Phi"] + Hs @ pose_dd))])
    return q, qd, qdd, ok


def rotations(alpha: Array, beta: Array, phi: Array) -> Array:
    """``R = Rz(phi) Ry(beta) Rx(alpha)`` at ``N`` orientations at once: ``(N, 3, 3)``."""
    ca, sa, cb, sb, cp, sp_ = (
        np.cos(alpha),
        np.sin(alpha),
        np.cos(beta),
        np.sin(beta),
        np.cos(phi),
        np.sin(phi),
    )
    R = np.empty((len(ca), 3, 3))
    R[:, 0, 0], R[:, 0, 1], R[:, 0, 2] = cp * cb, cp * sb * sa - sp_ * ca, cp * sb * ca + sp_ * sa
    R[:, 1, 0], R[:, 1, 1], R[:, 1, 2] = sp_ * cb, sp_ * sb * sa + cp * ca, sp_ * sb * ca - cp * sa
    R[:, 2, 0], R[:, 2, 1], R[:, 2, 2] = -sb, cb * sa, cb * ca
    return R


def inverse_kinematics_many(pose: Array, l: float, r_t: float) -> tuple[Array, Array]:
    """:func:`inverse_kinematics` at ``N`` poses (``pose``: ``(6, N)``): ``(N, 6)`` inductor
    coordinates and ``(N,)`` ``ok``."""
    R = rotations(pose[3], pose[4], pose[5])
    Ap = pose[:3].T[:, None, :] + joints_body(r_t) @ R.transpose(0, 2, 1)  # (N, 3, 3)
    u1 = np.einsum("nij,kj->nki", R, radial_axes())  # (N, k, 3)
    u2 = R[:, :, 2]  # R e_z
    c = np.hypot(u1[:, :, 2], u2[:, None, 2])
    with np.errstate(all="ignore"):
        kappa = np.where(c > 1e-12, -Ap[:, :, 2] / (l * c), np.inf)
    reach = np.abs(kappa) <= 1.0
    ok = np.all(reach, axis=1)
    kappa = np.where(reach, kappa, np.where(np.isfinite(kappa), np.clip(kappa, -1.0, 1.0), 0.0))
    delta = np.arctan2(np.broadcast_to(u2[:, None, 2], c.shape), u1[:, :, 2])
    ac = np.arccos(kappa)
    plus, minus = delta + ac, delta - ac
    psi = np.where(np.cos(minus) > np.cos(plus), minus, plus)  # the leg splays outwards
    d = l * (np.cos(psi)[..., None] * u1 + np.sin(psi)[..., None] * u2[:, None, :])
    return (Ap + d)[:, :, :2].reshape(len(ok), 6), ok


def program_states(
    pose: Array, pose_d: Array, pose_dd: Array, p: Array
) -> tuple[Array, Array, Array, Array]:
    """:func:`program_state` at ``N`` times (``(6, N)`` poses): ``(N, 12)`` ``q, q', q''``
    and ``(N,)`` ``ok``, in one vectorized evaluation."""
    cs = table_model().system
    l, rt = float(p[PHYSICAL.index("l")]), float(p[PHYSICAL.index("r_t")])
    ind, ok = inverse_kinematics_many(pose, l, rt)
    N = len(ok)
    q = np.concatenate([pose.T, ind], axis=1)
    u0 = np.zeros(6)
    qd = np.concatenate([pose_d.T, np.zeros((N, 6))], axis=1)
    P = cs.parts_many(0.0, q, qd, p, u0, ("H", "psi"))
    H = P["H"]
    Hs, Hi = H[:, :, :6], H[:, :, 6:]
    rhs = -(Hs @ pose_d.T[:, :, None])[:, :, 0] - P["psi"]
    qd[:, 6:] = np.linalg.solve(Hi, rhs[:, :, None])[:, :, 0]
    Phi = cs.parts_many(0.0, q, qd, p, u0, ("Phi",))["Phi"]
    rhs = -(Phi + (Hs @ pose_dd.T[:, :, None])[:, :, 0])
    qdd = np.concatenate([pose_dd.T, np.linalg.solve(Hi, rhs[:, :, None])[:, :, 0]], axis=1)
    return q, qd, qdd, ok


def inverse_dynamics_many(q: Array, qd: Array, qdd: Array, p: Array) -> tuple[Array, Array]:
    """:func:`inverse_dynamics` at ``N`` states (``(N, 12)`` each): ``(N, 6)`` forces and
    multipliers."""
    tm = table_model()
    P0 = tm.system.parts_many(0.0, q, qd, p, np.zeros(6), ("A", "B", "H"))
    rhs = (P0["A"] @ qdd[:, :, None])[:, :, 0] - P0["B"]
    S = np.broadcast_to(tm.S, (len(q), *tm.S.shape))
    sol = np.linalg.solve(np.concatenate([P0["H"].transpose(0, 2, 1), S], axis=2), rhs[:, :, None])
    return sol[:, 6:, 0], sol[:, :6, 0]


def constraint_residuals(q: Array, p: Array) -> Array:
    """:func:`constraint_residual` at ``N`` configurations (``(N, 12)``)."""
    z = np.zeros_like(q)
    f = table_model().system.parts_many(0.0, q, z, p, np.zeros(6), ("f",))["f"]
    f[:, 1::2] /= 2.0 * float(p[PHYSICAL.index("l")])
    return np.max(np.abs(f), axis=1)


def inverse_states(ev: Callable[[Array], tuple[Array, Array, Array]], p: Array, t: Array) -> Array:
    """The inverse problem's states ``(q, q', q'')`` at the times ``t`` of the pose program
    ``ev``: ``(len(t), 36)``, NaN where a leg cannot reach (one vectorized evaluation)."""
    if not len(t):
        return np.full((0, 36), np.nan)
    if len(t) == 1:  # one time (a frame off the table's grain): the one-time functions
        q1, qd1, qdd1, ok1 = program_state(*(a[:, 0] for a in ev(t)), p)
        row = np.concatenate([q1, qd1, qdd1])[None, :]
        return row if ok1 else np.full((1, 36), np.nan)
    q, qd, qdd, ok = program_states(*ev(t), p)
    out = np.full((len(ok), 36), np.nan)
    out[ok] = np.concatenate([q, qd, qdd], axis=1)[ok]
    return out


def inverse_observed(states: Array, p: Array) -> tuple[Array, Array]:
    """Inductor forces ``(N, 6)`` and constraint residuals ``(N,)`` of inverse-problem
    states (NaN where a state is not finite)."""
    ok = np.all(np.isfinite(states), axis=1)
    F = np.full((len(states), 6), np.nan)
    resid = np.full(len(states), np.nan)
    if len(states) == 1 and ok[0]:  # one state: the one-time functions
        s = states[0]
        F[0] = inverse_dynamics(s[:12], s[12:24], s[24:], p)[0]
        resid[0] = constraint_residual(s[:12], p)
    elif ok.any():
        s = states[ok]
        F[ok] = inverse_dynamics_many(s[:, :12], s[:, 12:24], s[:, 24:], p)[0]
        resid[ok] = constraint_residuals(s[:, :12], p)
    return F, resid


def inverse_dynamics(q: Array, qd: Array, qdd: Array, p: Array) -> tuple[Array, Array]:
    """Inductor forces ``F`` and multipliers ``lambda`` for a motion:
    ``A q'' - B(F = 0) = H^T lambda + S F`` with ``S = dB/dF`` (virtual work of the forces)."""
    tm = table_model()
    P0 = tm.system.parts(0.0, q, qd, p, np.zeros(6), ("A", "B", "H"))
    S = tm.S
    rhs = P0["A"] @ qdd - P0["B"]
    sol = np.linalg.solve(np.column_stack([P0["H"].T, S]), rhs)
    return sol[6:], sol[:6]


def constraint_residual(q: Array, p: Array) -> float:
    """The largest leg-constraint violation, in metres: the hinge rows (2.17) and the
    length rows ``|A - A'|^2 - l^2`` divided by ``2 l`` (the leg's length error)."""
    f = table_model().system.parts(0.0, q, np.zeros(12), p, np.zeros(6), ("f",))["f"]
    f = f.copy()
    f[1::2] /= 2.0 * float(p[PHYSICAL.index("l")])
    return float(np.max(np.abs(f)))


def axis_displacements(pose: Array, l: float, r_t: float) -> Array:
    """Horizontal distance of each inductor from its table joint (along its virtual axis)."""
    ind, _ = inverse_kinematics(pose, l, r_t)
    J = table_joints(pose, r_t)
    return np.array([np.hypot(ind[2 * k] - J[k, 0], ind[2 * k + 1] - J[k, 1]) for k in range(3)])


def zero_tilt_energy_is_the_sources() -> bool:
    """At zero tilt with ``J_Dz = J_D`` the table's kinetic energy is the source's
    ``1/2 M (x'^2 + y'^2 + z'^2) + 1/2 Z_D (alpha'^2 + beta'^2 + gamma'^2)``."""
    tm = table_model()
    xD, yD, zD, al, be, ph = tm.q[:6]
    Mc, JD, JDz = (sp.Symbol(n, real=True, positive=True) for n in ("M_c", "J_D", "J_Dz"))
    rates = {qi.diff(T_): sp.Symbol(f"{qi.func}_rate", real=True) for qi in tm.q[:6]}
    d = lambda e: e.diff(T_).xreplace(rates)  # noqa: E731
    want = (
        Mc * (d(xD) ** 2 + d(yD) ** 2 + d(zD) ** 2) / 2
        + JD * (d(al) ** 2 + d(be) ** 2 + d(ph) ** 2) / 2
    )
    got = tm.T_table.subs(JDz, JD).xreplace(rates).subs({al: 0, be: 0})
    return bool(sp.simplify(got - want) == 0)


def table_scene(l: float, rt: float) -> SceneSpec:
    """The floor, the triangular table, the inductors and the legs (posed by
    :func:`pose_table`)."""
    R0 = rt + l
    floor = box(
        "floor (inductor plane z = 0)",
        (3 * R0, 3 * R0, 0.01 * R0),
        (170, 170, 170),
        center=(0, 0, -0.03),
        opacity=0.35,
    )
    plate = trimesh.creation.cylinder(radius=1.15 * rt, height=0.08 * rt, sections=3)
    plate.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1]))
    bodies: list[MeshItem] = [combine("table", [plate], (120, 190, 120))]
    for k, name in enumerate("ABC"):
        bodies.append(box(f"inductor {name}", (0.25 * rt, 0.25 * rt, 0.12 * rt), COLORS[k]))
        bodies.append(cylinder(f"leg {name}{name}'", 0.04 * rt, l, (90, 90, 90), sections=12))
    ext = 1.6 * R0
    return SceneSpec(
        bounds=bounds_of(np.array([[-ext, -ext, -0.05], [ext, ext, l + 0.3 * rt]]), 0.02),
        meshes=[floor],
        bodies=bodies,
        moving_points={"D": (120, 190, 120)},
        moving_vectors={"F_A": COLORS[0], "F_B": COLORS[1], "F_C": COLORS[2]},
    )


def pose_table(fr: Frame, q: Array, arrows: Array, r_t: float) -> None:
    """Poses of :func:`table_scene` for the 12 coordinates ``q``; ``arrows``: the six
    inductor force arrows (already scaled)."""
    fr.poses["table"] = (q[:3].copy(), quat_zyx(q[5], q[4], q[3]))
    joints = table_joints(q[:6], r_t)
    for k, name in enumerate("ABC"):
        A = np.array([q[6 + 2 * k], q[7 + 2 * k], 0.0])
        fr.poses[f"inductor {name}"] = (A.copy(), quat_z(float(q[5])))
        fr.poses[f"leg {name}{name}'"] = segment_pose(A, joints[k])
        fr.vectors[f"F_{name}"] = (
            A[None, :] + [0, 0, 0.03],
            np.array([[arrows[2 * k], arrows[2 * k + 1], 0.0]]),
        )
    fr.points["D"] = q[None, :3].copy()


def plane_through_joints(pose: Array, r_t: float) -> tuple[float, float]:
    """The table plane through A', B', C': the mixed-product determinant with D as the
    running point, and the normal form ``x cos a + y cos b + z cos g - h`` at D."""
    J = table_joints(pose, r_t)
    D = pose[:3]
    det = float(np.linalg.det(np.array([J[0] - D, J[1] - D, J[2] - D])))
    n = np.cross(J[1] - J[0], J[2] - J[0])
    n = n / np.linalg.norm(n)
    if n @ J[0] < 0:
        n = -n
    h = float(n @ J[0])
    return det, float(n @ D - h)


__all__ = [
    "COORDS",
    "FORCES",
    "INDUCTORS",
    "PHYSICAL",
    "POSE",
    "TableModel",
    "axis_displacements",
    "constraint_residual",
    "constraint_residuals",
    "inverse_dynamics",
    "inverse_dynamics_many",
    "inverse_kinematics",
    "inverse_kinematics_many",
    "inverse_observed",
    "inverse_states",
    "joints_body",
    "plane_through_joints",
    "pose_table",
    "table_scene",
    "zero_tilt_energy_is_the_sources",
    "program_state",
    "program_states",
    "radial_axes",
    "rotation",
    "rotations",
    "table_joints",
    "table_model",
]
