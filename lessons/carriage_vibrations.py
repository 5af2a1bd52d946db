"""Vibrations of the air-bearing carriage of the EM-5034 plate coordinate table.

Textbook §2.3: Problem 2.6, free vibration of the 6-DOF carriage, eqs (2.35)-(2.77), and
Problem 2.7, forced vibration along one axis, eqs (2.78)-(2.92).  The source gives no
numbers for m, I, C, K, h, b, F0, w0: the defaults here are example values, said so in
every preset note.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from scipy.integrate import solve_ivp

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
    at_most,
    close,
)
from lessons.core.vibration import (
    COORDS,
    MODE_KEYS,
    Carriage,
    ForcedOscillator,
    box_inertia,
    box_inertia_printed,
    carriage_lagrange,
    carriage_source_equations,
    closed_form_frequencies,
    coupled_frequency,
    coupled_frequency_as_printed,
    eigen_frequencies,
    forced_lagrange,
    frequency_response,
    jeffcott_deflection,
    modal_propagate,
    mode_character,
    mode_shape,
    rotvec_to_quaternion,
    small_rotation_matrix,
)

TWO_PI = 2.0 * math.pi
EXAMPLE_NOTE = (
    "The source gives no numbers for the carriage; these are example values of a plausible table."
)


def _mesh(
    name: str, mesh: trimesh.Trimesh, color: tuple[int, int, int], opacity: float = 0.6
) -> MeshItem:
    return MeshItem(
        name,
        np.asarray(mesh.vertices, dtype=float),
        np.asarray(mesh.faces, dtype=np.int64),
        color,
        opacity,
    )


def _mode_label(key: str) -> str:
    return {
        "z": "z: vertical translation (single-coupled)",
        "phi_z": "phi_z: rotation about Z (single-coupled)",
        "x-phi_y upper": "x & phi_y: upper coupled mode",
        "x-phi_y lower": "x & phi_y: lower coupled mode",
        "y-phi_x upper": "y & phi_x: upper coupled mode",
        "y-phi_x lower": "y & phi_x: lower coupled mode",
    }[key]


# ====================================================================== Problem 2.6


def carriage_from_params(p: Params) -> Carriage:
    """Carriage model of the parameters: box inertia by (2.74)-(2.77) (corrected)."""
    Ix, Iy, Iz = box_inertia(p["m"], p["a"], p["b"], p["H"], p["Xc"], p["Yc"], p["Zc"])
    return Carriage(
        p["m"], Ix, Iy, Iz, p["Cx"], p["Cy"], p["Cz"], p["Kx"], p["Ky"], p["Kz"], p["h"]
    )


def _body_rotvec(q: np.ndarray) -> np.ndarray:
    """Drawn rotation of the carriage.  (2.40)'s "+C_x h x phi_y" means the stiffness
    centre (h below O) moves by x + h phi_y: phi_y is counted clockwise about +Y."""
    return np.array([q[3], -q[4], q[5]])


class _CarriageGeometry:
    """Where the springs attach, for the scene and the frames."""

    def __init__(self, p: Params) -> None:
        self.a, self.b, self.H, self.h = float(p["a"]), float(p["b"]), float(p["H"]), float(p["h"])
        self.cg0 = np.array([0.0, 0.0, self.h])  # stiffness centre at the origin, O h above it
        self.gap = max(0.25 * max(self.a, self.b), 0.02)  # drawn air gap (exaggerated)
        self.floor = self.h - self.H / 2 - self.gap
        sx, sy = 0.4 * self.b, 0.4 * self.a
        self.body_pts = np.array(
            [
                [sx, sy, -self.H / 2],
                [-sx, sy, -self.H / 2],
                [-sx, -sy, -self.H / 2],
                [sx, -sy, -self.H / 2],
                [0, 0, -self.h],
                [0, 0, -self.h],
            ]
        )
        reach = 0.5 * max(self.a, self.b) + self.gap
        self.anchors = np.array(
            [
                [sx, sy, self.floor],
                [-sx, sy, self.floor],
                [-sx, -sy, self.floor],
                [sx, -sy, self.floor],
                [-reach, 0, 0],
                [0, -reach, 0],
            ]
        )
        self.corners = np.array(
            [
                [sx2, sy2, sz2]
                for sx2 in (-self.b / 2, self.b / 2)
                for sy2 in (-self.a / 2, self.a / 2)
                for sz2 in (-self.H / 2, self.H / 2)
            ]
        )

    def pose(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.cg0 + q[:3], rotvec_to_quaternion(_body_rotvec(q))

    def spring_vectors(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        R = small_rotation_matrix(_body_rotvec(q))
        ends = self.cg0 + q[:3] + self.body_pts @ R.T
        return self.anchors.copy(), ends - self.anchors

    def max_corner_displacement(self, q: np.ndarray) -> float:
        """Largest displacement of a box corner for the linearized motion q."""
        r = _body_rotvec(q)
        return float(np.max(np.linalg.norm(q[:3] + np.cross(r, self.corners), axis=1)))


class CarriageFreeVibration(Lesson):
    id = "carriage-free-vibration"
    title = "Free vibration of the carriage on its air bearing"
    chapter = "2"
    problem = "Problem 2.6"
    source = "Textbook §2.3, Problem 2.6, eqs (2.35)-(2.77)"
    summary = (
        "The carriage as one rigid box with 6 degrees of freedom on the elastic air bearing: "
        "z and phi_z oscillate alone, x couples with phi_y and y with phi_x because the centre of "
        "stiffness lies h below the centre of gravity.  Closed-form frequencies next to the "
        "eigenvalues of the full model; each mode animated."
    )
    order = 2.6
    t_end = 0.1
    params = (
        Param(
            "mode",
            "choice",
            "x-phi_y upper",
            "animated mode",
            choices=(*MODE_KEYS, "free response"),
            help="one normal mode, or the free response from the initial displacements",
        ),
        Param("m", "float", 20.0, "carriage mass m", "kg", 0.01, 1e4, 0.1, group="surface"),
        Param("b", "float", 0.5, "box length b (along X)", "m", 0.01, 5.0, 0.01, group="surface"),
        Param("a", "float", 0.4, "box width a (along Y)", "m", 0.01, 5.0, 0.01, group="surface"),
        Param(
            "H", "float", 0.06, "box height H (along Z)", "m", 0.001, 5.0, 0.005, group="surface"
        ),
        Param(
            "Xc",
            "float",
            0.0,
            "centre of gravity X_c (2.73)",
            "m",
            -5.0,
            5.0,
            0.01,
            group="surface",
        ),
        Param(
            "Yc",
            "float",
            0.0,
            "centre of gravity Y_c (2.73)",
            "m",
            -5.0,
            5.0,
            0.01,
            group="surface",
        ),
        Param(
            "Zc",
            "float",
            0.0,
            "centre of gravity Z_c (2.73)",
            "m",
            -5.0,
            5.0,
            0.01,
            group="surface",
        ),
        Param(
            "h",
            "float",
            0.02,
            "h: centre of gravity above the centre of stiffness",
            "m",
            0.0,
            1.0,
            0.005,
        ),
        Param("Cx", "float", 2e6, "C_x translational stiffness", "N/m", 1.0, 1e10),
        Param("Cy", "float", 2e6, "C_y translational stiffness", "N/m", 1.0, 1e10),
        Param("Cz", "float", 5e7, "C_z translational stiffness", "N/m", 1.0, 1e10),
        Param("Kx", "float", 8e5, "K_x rotational stiffness", "N m/rad", 1e-3, 1e10),
        Param("Ky", "float", 8e5, "K_y rotational stiffness", "N m/rad", 1e-3, 1e10),
        Param("Kz", "float", 6e4, "K_z rotational stiffness", "N m/rad", 1e-3, 1e10),
        Param(
            "amplitude",
            "float",
            0.02,
            "drawn mode amplitude (largest corner displacement)",
            "m",
            0.0,
            1.0,
            0.005,
            group="initial",
            help="the mode is linear: any amplitude is a valid picture of it",
        ),
        Param(
            "x0",
            "float",
            0.01,
            "x(0) for the free response",
            "m",
            -1.0,
            1.0,
            0.001,
            group="initial",
        ),
        Param("y0", "float", 0.0, "y(0)", "m", -1.0, 1.0, 0.001, group="initial"),
        Param("z0", "float", 0.005, "z(0)", "m", -1.0, 1.0, 0.001, group="initial"),
        Param("phi_x0", "float", 0.0, "phi_x(0)", "rad", -1.0, 1.0, 0.005, group="initial"),
        Param("phi_y0", "float", 0.05, "phi_y(0)", "rad", -1.0, 1.0, 0.005, group="initial"),
        Param("phi_z0", "float", 0.02, "phi_z(0)", "rad", -1.0, 1.0, 0.005, group="initial"),
        Param(
            "slowdown",
            "float",
            200.0,
            "live slow motion (physical time = view time / slowdown)",
            "",
            1.0,
            1e5,
            group="method",
        ),
    )
    presets = (
        Preset("example", "Example carriage (illustrative numbers)", {}, 0.1, EXAMPLE_NOTE),
        Preset(
            "strong-coupling",
            "C_x/m close to K_y/I_y: strongly coupled x-phi_y",
            {"Ky": 4.2e4, "Kx": 2.7e4, "h": 0.03, "mode": "x-phi_y lower"},
            0.2,
            EXAMPLE_NOTE + " K chosen so that C/m ~ K/I: the two coupled modes share x and phi.",
        ),
        Preset(
            "h-zero",
            "h = 0: centre of gravity at the centre of stiffness, modes decouple",
            {"h": 0.0, "mode": "x-phi_y lower"},
            0.1,
            "The second term under the inner radical of (2.67)-(2.72) vanishes.",
        ),
        Preset(
            "free-response",
            "Free response from initial displacements",
            {"mode": "free response"},
            0.1,
            EXAMPLE_NOTE,
        ),
    )
    plots = (
        PlotSpec("Translations", ("x", "y", "z"), "m"),
        PlotSpec("Rotations", ("phi_x", "phi_y", "phi_z"), "rad"),
        PlotSpec("Velocities", ("vx", "vy", "vz"), "m/s"),
        PlotSpec("Bearing forces", ("Fx", "Fy", "Fz"), "N"),
        PlotSpec("Energy", ("E", "W", "E_total"), "J"),
    )

    # -- model ----------------------------------------------------------------------

    def initial_state(self, params: Params) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) at t = 0: the scaled mode shape, or the given initial displacements."""
        if params["mode"] == "free response":
            q = np.array([params[f"{c}0"] for c in COORDS], dtype=float)
            return q, np.zeros(6)
        p = carriage_from_params(params)
        shape = mode_shape(p, params["mode"])
        d = _CarriageGeometry(params).max_corner_displacement(shape)
        return shape * (params["amplitude"] / d if d > 0 else 0.0), np.zeros(6)

    def validate(self, params: Params) -> None:
        h = params["h"]
        for K, C in (("Ky", "Cx"), ("Kx", "Cy")):
            if params[K] <= params[C] * h**2:
                raise ParamError(
                    K,
                    f"must exceed {C} h^2 = {params[C] * h**2:.4g}: K is the total rotational stiffness about O "
                    "(2.40); below that the bearing is unstable and the lower frequency is imaginary",
                )

    def _observables(self, p: Carriage, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        M, K = p.matrices()
        q2, v2 = np.atleast_2d(q), np.atleast_2d(v)
        forces = -(q2 @ K)  # generalized elastic forces: -K q
        E = 0.5 * np.einsum("ij,jk,ik->i", v2, M, v2)
        W = 0.5 * np.einsum("ij,jk,ik->i", q2, K, q2)
        out = {c: q2[:, i] for i, c in enumerate(COORDS)}
        out.update(
            {
                "vx": v2[:, 0],
                "vy": v2[:, 1],
                "vz": v2[:, 2],
                "omega_x": v2[:, 3],
                "omega_y": v2[:, 4],
                "omega_z": v2[:, 5],
            }
        )
        out.update(
            {
                "Fx": forces[:, 0],
                "Fy": forces[:, 1],
                "Fz": forces[:, 2],
                "Mx": forces[:, 3],
                "My": forces[:, 4],
                "Mz": forces[:, 5],
            }
        )
        out.update({"E": E, "W": W, "E_total": E + W})
        return out

    def frequency_table(self, params: Params) -> dict[str, Any]:
        """Closed-form and eigenvalue frequencies for these parameters (plain numbers)."""
        p = carriage_from_params(params)
        cf = closed_form_frequencies(p)
        w_eig, _ = eigen_frequencies(p)
        cf_sorted = np.sort(np.array(list(cf.values())))
        rel = float(np.max(np.abs(cf_sorted - w_eig) / w_eig))
        return {"closed_form": cf, "eig": w_eig, "max_rel_err": rel, "carriage": p}

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        p = carriage_from_params(params)
        info = self.frequency_table(params)
        w_max = float(np.max(info["eig"]))
        n = int(min(200_000, max(1001, 40 * t_end * w_max / TWO_PI)))
        t = np.linspace(0.0, t_end, n)
        q0, v0 = self.initial_state(params)
        qs, vs = modal_propagate(p, q0, v0, t)
        series = self._observables(p, qs, vs)
        metrics: dict[str, Any] = {
            "I_x": p.Ix,
            "I_y": p.Iy,
            "I_z": p.Iz,
            "max_rel_err_closed_vs_eig": info["max_rel_err"],
        }
        for k, w in info["closed_form"].items():
            tag = k.replace(" ", "_").replace("-", "_")
            metrics[f"omega_{tag}"] = w
            metrics[f"f_{tag}_Hz"] = w / TWO_PI
            metrics[f"character_{tag}"] = mode_character(p, k)
        for i, w in enumerate(info["eig"]):
            metrics[f"omega_eig_{i + 1}"] = float(w)
        messages = [EXAMPLE_NOTE]
        if params["mode"] != "free response":
            k = params["mode"]
            messages.append(
                f"Mode {_mode_label(k)}: omega = {info['closed_form'][k]:.6g} rad/s "
                f"({info['closed_form'][k] / TWO_PI:.6g} Hz), mostly {mode_character(p, k)}; drawn amplitude is illustrative."
            )
        return RunResult(self.id, None, params.raw(), t, series, metrics, messages)

    def stepper(self, params: Params) -> Stepper:
        return _CarriageStepper(self, params)

    def scene(self, params: Params) -> SceneSpec:
        g = _CarriageGeometry(params)
        box = trimesh.creation.box(extents=(g.b, g.a, g.H))
        span = 0.5 * max(g.a, g.b) + g.gap + 0.05
        stator = trimesh.creation.box(extents=(2 * span, 2 * span, 0.1 * g.gap))
        stator.apply_translation((0, 0, g.floor - 0.05 * g.gap))
        axis_len = 0.5 * span
        curves = [
            CurveItem(
                "X axis (stiffness plane)", np.array([[0, 0, 0], [axis_len, 0, 0]]), (200, 40, 40)
            ),
            CurveItem(
                "Y axis (stiffness plane)", np.array([[0, 0, 0], [0, axis_len, 0]]), (40, 160, 40)
            ),
            CurveItem("Z axis", np.array([[0, 0, 0], [0, 0, axis_len]]), (40, 40, 200)),
        ]
        markers = [
            MarkerItem("centre of stiffness (Ц.Ж.)", np.zeros((1, 3)), (200, 120, 0), 0.01, "Ц.Ж."),
            MarkerItem("spring anchors", g.anchors, (90, 90, 90), 0.008),
        ]
        top = g.h + g.H / 2 + 0.5 * g.gap
        return SceneSpec(
            bounds=((-span, -span, g.floor - 0.1 * g.gap), (span, span, top)),
            meshes=[_mesh("stator", stator, (150, 150, 150), 0.5)],
            curves=curves,
            markers=markers,
            moving_points={"O (centre of gravity)": (220, 60, 60), "corner": (60, 60, 220)},
            moving_vectors={"springs": (80, 80, 80)},
            bodies=[_mesh("carriage", box, (120, 160, 220), 0.55)],
        )

    # -- page ---------------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        s = carriage_lagrange()
        t = s.t
        x, y, z, px, py, pz = s.q
        Ix, Iy, Iz = s.I
        Cx, Cy, Cz = s.C
        Kx, Ky, Kz = s.K
        m, h = s.m, s.h
        E, W = sp.symbols("E W")
        w = sp.Symbol("varpi", positive=True)
        e, c, zz, k, qq, I = sp.symbols("e c z k q I", positive=True)
        M, K = carriage_lagrange_matrices()
        grads = [sp.Eq(sp.Derivative(W, v), sp.diff(s.W, v)) for v in s.q]
        a_, b_ = Cx / m, Ky / Iy
        info = self.frequency_table(params)
        rows = " \\\\ ".join(
            f"\\text{{{k_}}} & {info['closed_form'][k_]:.6g} & {info['closed_form'][k_] / TWO_PI:.6g} & \\text{{{mode_character(info['carriage'], k_)}}}"
            for k_ in MODE_KEYS
        )
        eig = ", ".join(f"{v:.6g}" for v in info["eig"])
        return [
            DerivationStep(
                "Lagrange equations of the carriage",
                "E is the kinetic and W the potential energy; Q the external generalized forces; n = 6 for a body in space. "
                "The term -dE/dq is absent because E does not depend on q.",
                r"\frac{d}{dt}\frac{\partial E}{\partial \dot q_i}+\frac{\partial W}{\partial q_i}=Q_i,\quad i=1,\dots,n",
                "(2.35)-(2.36)",
            ),
            DerivationStep(
                "Coordinates",
                "The Cartesian coordinates of every point follow from the generalized ones.",
                r"x_k=x_k(q_1,\dots,q_n,t),\; y_k=y_k(q_1,\dots,q_n,t),\; z_k=z_k(q_1,\dots,q_n,t)",
                "(2.37)",
            ),
            DerivationStep(
                "No external action",
                "Problem 2.6: Q(t) = 0 for q = x, y, z, phi_x, phi_y, phi_z.",
                r"\frac{d}{dt}\frac{\partial E}{\partial \dot q}+\frac{\partial W}{\partial q}=0",
                "(2.38)",
            ),
            DerivationStep(
                "Kinetic energy",
                "Translations of the centre of gravity and small rotations about the axes.",
                sp.Eq(E, s.E),
                "(2.39)",
            ),
            DerivationStep(
                "Potential energy of the air bearing",
                "C: translational, K: rotational stiffnesses; h: distance from the centre of gravity down to the centre of stiffness. "
                "The x-phi_y and y-phi_x products couple the motions.",
                sp.Eq(W, s.W),
                "(2.40)",
            ),
            DerivationStep("Derivatives of W", "", grads, "(2.41)"),
            DerivationStep(
                "Single-coupled equations (sympy LagrangesMethod of E - W)",
                "",
                [sp.Eq(s.equations[2], 0), sp.Eq(s.equations[5], 0)],
                "(2.42)",
            ),
            DerivationStep(
                "Two-coupled equations: x with phi_y",
                "",
                [sp.Eq(s.equations[0], 0), sp.Eq(s.equations[4], 0)],
                "(2.43)",
            ),
            DerivationStep(
                "Two-coupled equations: y with phi_x",
                "",
                [sp.Eq(s.equations[1], 0), sp.Eq(s.equations[3], 0)],
                "(2.44)",
            ),
            DerivationStep(
                "Matrix form",
                "M q'' + K q = 0 with q = (x, y, z, phi_x, phi_y, phi_z); the full model whose eigenvalues are compared below.",
                [sp.Eq(sp.Symbol("M"), M), sp.Eq(sp.Symbol("K"), K)],
                "(2.42)-(2.44)",
            ),
            DerivationStep(
                "Linear oscillation of an eccentric disc",
                "Elastic force equals the inertia force of the rotating mass (2.45): c z = m varpi^2 (e + z), radius of rotation e + z.",
                sp.Eq(zz, jeffcott_deflection(m, e, c, w)),
                "(2.45)-(2.48)",
                reconstructed="the printed (2.46)-(2.48) are garbled and mutually inconsistent; rebuilt as the Jeffcott rotor balance",
            ),
            DerivationStep(
                "Critical speed",
                "The deflection grows without bound when the denominator vanishes.",
                [sp.Eq(c - m * w**2, 0), sp.Eq(w, sp.sqrt(c / m))],
                "(2.49)-(2.50)",
            ),
            DerivationStep(
                "Torsional oscillation",
                "k phi = m varpi^2 (e + z)^2 with e + z = q, phi = 1; then I = m q^2.",
                [sp.Eq(w, sp.sqrt(k / (m * qq**2))), sp.Eq(w, sp.sqrt(k / I))],
                "(2.51)-(2.54)",
            ),
            DerivationStep(
                "In hertz",
                "",
                [
                    sp.Eq(sp.Symbol("f_c"), sp.sqrt(c / m) / (2 * sp.pi)),
                    sp.Eq(sp.Symbol("f_k"), sp.sqrt(k / I) / (2 * sp.pi)),
                ],
                "(2.55)-(2.56)",
            ),
            DerivationStep(
                "Single-coupled frequencies",
                "From (2.42) with (2.50) and (2.54).",
                [
                    sp.Eq(sp.Symbol("omega_z"), sp.sqrt(Cz / m)),
                    sp.Eq(sp.Symbol("omega_phi_z"), sp.sqrt(Kz / Iz)),
                ],
                "(2.42), (2.50), (2.54)",
            ),
            DerivationStep(
                "Harmonic trial solution",
                "x = A_x sin(varpi t), phi_y = A_phiy sin(varpi t); x'' = -A_x varpi^2 sin(varpi t), phi_y'' = -A_phiy varpi^2 sin(varpi t).",
                r"x=A_x\sin\varpi t,\quad \varphi_y=A_{\varphi y}\sin\varpi t",
                "(2.57)-(2.62)",
                reconstructed="the source writes two frequencies varpi_c, varpi_K; cancelling sin(varpi t) in (2.63) needs one common varpi (a normal mode)",
            ),
            DerivationStep(
                "Amplitude equations",
                "Substituted into (2.43) (the source cites (2.39), (2.42), (2.44)); sin(varpi t) cancelled.",
                r"\begin{cases}A_x(C_x-m\varpi^2)+C_xhA_{\varphi y}=0\\ A_{\varphi y}(K_y-I_y\varpi^2)+C_xhA_x=0\end{cases}",
                "(2.63)-(2.64)",
            ),
            DerivationStep(
                "Frequency determinant",
                "",
                [
                    sp.Eq(sp.Matrix([[Cx - m * w**2, Cx * h], [Cx * h, Ky - Iy * w**2]]).det(), 0),
                    sp.Eq(w**4 - (a_ + b_) * w**2 + (Cx * Ky - Cx**2 * h**2) / (m * Iy), 0),
                ],
                "(2.65)",
            ),
            DerivationStep(
                "Roots",
                "The second radical transformed: (a+b)^2/4 - ab + C_x^2h^2/(mI_y) = (a-b)^2/4 + C_x^2h^2/(mI_y).",
                r"\varpi_{x,\varphi y}=\sqrt{\tfrac12\left(\tfrac{C_x}{m}+\tfrac{K_y}{I_y}\right)\pm\sqrt{\tfrac14\left(\tfrac{C_x}{m}-\tfrac{K_y}{I_y}\right)^2+\tfrac{C_x^2h^2}{mI_y}}}",
                "(2.66)",
                reconstructed="partly lost in extraction; re-derived by solving (2.65) with sympy",
            ),
            DerivationStep(
                "Upper coupled frequency",
                "The source calls it the translational frequency along X.",
                sp.Eq(
                    sp.Symbol("varpi_x"),
                    sp.sqrt((a_ + b_) / 2 + sp.sqrt((a_ - b_) ** 2 / 4 + Cx**2 * h**2 / (m * Iy))),
                ),
                "(2.67)",
                reconstructed="partly lost in extraction; the '+' root of (2.66)",
            ),
            DerivationStep(
                "Lower coupled frequency",
                "The source calls it the rotational frequency about Y.",
                sp.Eq(
                    sp.Symbol("varpi_phi_y"),
                    sp.sqrt((a_ + b_) / 2 - sp.sqrt((a_ - b_) ** 2 / 4 + Cx**2 * h**2 / (m * Iy))),
                ),
                "(2.68)",
                reconstructed="printed with '-' before C_x^2h^2/(mI_y), which contradicts (2.66) and gives wrong values or NaN; '+' used",
            ),
            DerivationStep(
                "Which root is which mode",
                "The '+' root is translational only if C_x/m > K_y/I_y: with h = 0 the roots are max and min of sqrt(C_x/m), sqrt(K_y/I_y). "
                "Here modes are labelled upper/lower and their character is read from the mode shape A_phiy/A_x = -(C_x - m varpi^2)/(C_x h). "
                "With h = 0 the second term under the inner radical vanishes and the modes decouple.",
                sp.Eq(sp.Symbol("A_phi_y") / sp.Symbol("A_x"), -(Cx - m * w**2) / (Cx * h)),
                "(2.64), (2.67)-(2.68)",
            ),
            DerivationStep(
                "In hertz, and the y-phi_x pair",
                "f = varpi/(2 pi); the pair (2.44) has the same roots with C_y, K_x, I_x.",
                r"f_{y,\varphi x}=\frac1{2\pi}\sqrt{\tfrac12\left(\tfrac{C_y}{m}+\tfrac{K_x}{I_x}\right)\pm\sqrt{\tfrac14\left(\tfrac{C_y}{m}-\tfrac{K_x}{I_x}\right)^2+\tfrac{C_y^2h^2}{mI_x}}}",
                "(2.69)-(2.72)",
                reconstructed="lost in extraction except 1/(2 pi); rebuilt from (2.67)/(2.68) with C_y, K_x, I_x",
            ),
            DerivationStep(
                "Centre of gravity of the assembled carriage",
                "P_i: weight of part i; X_i, Y_i, Z_i: its centre of gravity; P = sum P_i.",
                r"X_c=\frac{\sum P_iX_i}{P},\quad Y_c=\frac{\sum P_iY_i}{P},\quad Z_c=\frac{\sum P_iZ_i}{P}",
                "(2.73)",
            ),
            DerivationStep(
                "Huygens-Steiner",
                "rho: distance from the centre of gravity to the respective axis (the source says 'to the origin').",
                r"I_{z,x,y}=I_{c\,z,x,y}+m\rho^2_{z,x,y},\quad \rho_z^2=X_c^2+Y_c^2,\ \rho_x^2=Y_c^2+Z_c^2,\ \rho_y^2=Z_c^2+X_c^2",
                "(2.74)",
                reconstructed="rho must be measured to the axis, as (2.75)-(2.77) themselves use it",
            ),
            DerivationStep(
                "Box of b (X) x a (Y) x H (Z)",
                "",
                r"I_z=m\left(\frac{a^2+b^2}{12}+X_c^2+Y_c^2\right)",
                "(2.75)",
            ),
            DerivationStep(
                "I_x and I_y of the box",
                "Printed: I_x = m((h^2+b^2)/12 + ...), I_y = m((h^2+a^2)/12 + ...).  Integration over the box gives the forms below.",
                r"I_x=m\left(\frac{a^2+H^2}{12}+Y_c^2+Z_c^2\right),\quad I_y=m\left(\frac{b^2+H^2}{12}+Z_c^2+X_c^2\right)",
                "(2.76)-(2.77)",
                reconstructed="printed 'h' is the height H, and a, b are swapped against the source's own definitions",
            ),
            DerivationStep(
                "This carriage",
                f"I_x = {info['carriage'].Ix:.6g}, I_y = {info['carriage'].Iy:.6g}, I_z = {info['carriage'].Iz:.6g} kg m^2.  "
                f"Eigenvalues of the full model (scipy.linalg.eigh(K, M)), sqrt, rad/s: {eig}.  "
                f"Largest relative difference to the closed forms: {info['max_rel_err']:.2e}.",
                r"\begin{array}{lccc}\text{mode}&\varpi\ (\mathrm{rad/s})&f\ (\mathrm{Hz})&\text{character}\\ \hline "
                + rows
                + r"\end{array}",
                "(2.42), (2.50), (2.54), (2.66)-(2.72)",
            ),
        ]

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "lagrange-6dof",
                "LagrangesMethod applied to E - W of (2.39)/(2.40) gives exactly the six equations (2.42)-(2.44) (n = 6).",
                "(2.38)-(2.44)",
                _check_lagrange_6dof,
            ),
            Claim(
                "gradient-W",
                "The derivatives of W are those of (2.41).",
                "(2.41)",
                _check_gradients,
            ),
            Claim(
                "determinant-forms",
                "The three expanded forms of the determinant (2.65) agree, and the radical transformation of (2.66) holds.",
                "(2.65)-(2.66)",
                _check_determinant,
            ),
            Claim(
                "closed-form-vs-eig",
                "The six closed-form frequencies equal the eigenvalues of the 6-DOF model M q'' + K q = 0 to 1e-9 relative "
                "(the three presets and 20 random parameter sets).",
                "(2.42)-(2.44), (2.50), (2.54), (2.66)-(2.72)",
                _check_closed_vs_eig,
            ),
            Claim(
                "sign-2-68",
                "(2.68) with '-' under the inner radical, as extracted, misses the eigenvalue; with '+' it matches.",
                "(2.68)",
                _check_sign_268,
            ),
            Claim(
                "h-zero-decouples",
                "With h = 0 the coupled roots are sqrt(C_x/m) and sqrt(K_y/I_y); for C_x/m = 10, K_y/I_y = 4000 the '+' root "
                "63.2455532 is the rotational mode and the '-' root 3.16227766 the translational one.",
                "(2.67)-(2.68)",
                _check_h_zero,
            ),
            Claim(
                "mode-shape-ratio",
                "The amplitude ratio A_phiy/A_x = -(C_x - m varpi^2)/(C_x h) of (2.64) is the eigenvector of the full model.",
                "(2.64)",
                _check_mode_ratio,
            ),
            Claim(
                "jeffcott",
                "z = m e varpi^2/(c - m varpi^2) solves c z = m varpi^2 (e + z) and is singular at varpi = sqrt(c/m).",
                "(2.47)-(2.50)",
                _check_jeffcott,
            ),
            Claim(
                "torsional",
                "(2.53) equals (2.54) with I = m q^2; f = varpi/(2 pi) in (2.55)/(2.56).",
                "(2.53)-(2.56)",
                _check_torsional,
            ),
            Claim(
                "box-inertia",
                "Integration over a uniform box b x a x H confirms (2.75) and the corrected (2.76)/(2.77); the printed (2.76)/(2.77) "
                "differ when a != b.",
                "(2.75)-(2.77)",
                _check_box_inertia,
            ),
            Claim(
                "huygens-steiner",
                "For a box whose centre of gravity is at (X_c, Y_c, Z_c), I_z about the Z axis is m((a^2+b^2)/12 + X_c^2 + Y_c^2).",
                "(2.73)-(2.75)",
                _check_huygens,
            ),
            Claim(
                "free-response",
                "Modal superposition of the free response equals solve_ivp (DOP853, rtol 1e-12) to 1e-8 relative.",
                "(2.42)-(2.44)",
                _check_free_response,
            ),
        ]


def carriage_lagrange_matrices() -> tuple[sp.Matrix, sp.Matrix]:
    """Symbolic M and K of (2.42)-(2.44) read off the Lagrange equations."""
    s = carriage_lagrange()
    qdd = [sp.diff(c, s.t, 2) for c in s.q]
    M = sp.Matrix(6, 6, lambda i, j: sp.diff(s.equations[i], qdd[j]))
    K = sp.Matrix(6, 6, lambda i, j: sp.diff(s.equations[i], s.q[j]))
    return M, K


class _CarriageStepper(Stepper):
    def __init__(self, lesson: CarriageFreeVibration, params: Params) -> None:
        self.lesson = lesson
        self._t = 0.0
        self._take(params)
        self.q, self.v = lesson.initial_state(params)

    def _take(self, params: Params) -> None:
        self.params = params
        self.p = carriage_from_params(params)
        self.geom = _CarriageGeometry(params)

    @property
    def t(self) -> float:
        return self._t

    def frame(self, message: str = "") -> Frame:
        obs = self.lesson._observables(self.p, self.q, self.v)
        pos, quat = self.geom.pose(self.q)
        origins, dirs = self.geom.spring_vectors(self.q)
        R = small_rotation_matrix(_body_rotvec(self.q))
        corner = pos + R @ self.geom.corners[-1]
        return Frame(
            t=self._t,
            points={"O (centre of gravity)": pos[None, :], "corner": corner[None, :]},
            vectors={"springs": (origins, dirs)},
            poses={"carriage": (pos, quat)},
            scalars={k: float(v[0]) for k, v in obs.items()},
            message=message,
        )

    def advance(self, dt: float) -> Frame:
        dt_phys = max(float(dt), 0.0) / float(self.params["slowdown"])
        self.q, self.v = modal_propagate(self.p, self.q, self.v, dt_phys)
        self._t += dt_phys
        return self.frame()

    def set_params(self, params: Params) -> None:
        keys = ("mode", "amplitude", *(f"{c}0" for c in COORDS))
        restart = any(params[k] != self.params[k] for k in keys)
        self._take(params)
        if restart:
            self.q, self.v = self.lesson.initial_state(params)

    def reset(self) -> Frame:
        self._t = 0.0
        self.q, self.v = self.lesson.initial_state(self.params)
        return self.frame()


# -- claim checks, Problem 2.6 ---------------------------------------------------------


def _check_lagrange_6dof() -> ClaimResult:
    s = carriage_lagrange()
    diffs = [sp.simplify(a - b) for a, b in zip(s.equations, carriage_source_equations())]
    ok = len(s.equations) == 6 and all(d == 0 for d in diffs)
    return ClaimResult(
        "6 equations, each equal to (2.42)-(2.44)",
        f"{len(s.equations)} equations, differences {diffs}",
        ok,
    )


def _check_gradients() -> ClaimResult:
    s = carriage_lagrange()
    x, y, z, px, py, pz = s.q
    Cx, Cy, Cz = s.C
    Kx, Ky, Kz = s.K
    h = s.h
    printed = [
        Cx * x + Cx * h * py,
        Cy * y + Cy * h * px,
        Cz * z,
        Kx * px + Cy * h * y,
        Ky * py + Cx * h * x,
        Kz * pz,
    ]
    diffs = [sp.simplify(sp.diff(s.W, c) - e) for c, e in zip(s.q, printed)]
    return ClaimResult("all differences 0", str(diffs), all(d == 0 for d in diffs))


def _check_determinant() -> ClaimResult:
    m, Iy, Cx, Ky, h, w2 = sp.symbols("m I_y C_x K_y h varpi2", positive=True)
    det = sp.Matrix([[Cx - m * w2, Cx * h], [Cx * h, Ky - Iy * w2]]).det()
    f1 = (Cx - m * w2) * (Ky - Iy * w2) - Cx**2 * h**2
    f2 = m * Iy * w2**2 - (Cx * Iy + m * Ky) * w2 + Cx * Ky - Cx**2 * h**2
    f3 = w2**2 - (Cx / m + Ky / Iy) * w2 + (Cx * Ky - Cx**2 * h**2) / (m * Iy)
    a, b = Cx / m, Ky / Iy
    rad = sp.simplify(
        (a + b) ** 2 / 4
        - (Cx * Ky - Cx**2 * h**2) / (m * Iy)
        - ((a - b) ** 2 / 4 + Cx**2 * h**2 / (m * Iy))
    )
    d = [sp.expand(det - f1), sp.expand(det - f2), sp.simplify(det / (m * Iy) - f3), rad]
    return ClaimResult("all differences 0", str(d), all(x == 0 for x in d))


def _random_carriages(n: int, seed: int = 7) -> list[Carriage]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        m = rng.uniform(1, 50)
        Ix, Iy, Iz = box_inertia(m, *rng.uniform(0.05, 1.0, 3))
        C = 10 ** rng.uniform(4, 8, 3)
        h = rng.uniform(0, 0.2)
        K = (
            10 ** rng.uniform(2, 7, 3) + np.array([C[1], C[0], 0.0]) * h**2
        )  # total about O: K_x > C_y h^2, K_y > C_x h^2
        out.append(Carriage(m, Ix, Iy, Iz, *C, *K, h=h))
    return out


def _preset_carriages() -> list[Carriage]:
    lesson = CarriageFreeVibration()
    return [carriage_from_params(lesson.resolve(preset=p.name)) for p in lesson.presets]


def _check_closed_vs_eig() -> ClaimResult:
    worst = 0.0
    for p in _preset_carriages() + _random_carriages(20):
        cf = np.sort(np.array(list(closed_form_frequencies(p).values())))
        w, _ = eigen_frequencies(p)
        worst = max(worst, float(np.max(np.abs(cf - w) / w)))
    return at_most(1e-9, worst, "max relative difference ")


def _check_sign_268() -> ClaimResult:
    lesson = CarriageFreeVibration()
    p = carriage_from_params(lesson.resolve(preset="strong-coupling"))
    w, _ = eigen_frequencies(p)
    pair = sorted([coupled_frequency(p.Cx, p.Ky, p.m, p.Iy, p.h, s) for s in (+1, -1)])
    target = [v for v in w if any(abs(v - c) <= 1e-9 * v for c in pair)]
    printed = coupled_frequency_as_printed(p.Cx, p.Ky, p.m, p.Iy, p.h)
    plus_ok = len(target) >= 2 and abs(pair[0] - min(target)) <= 1e-9 * pair[0]
    printed_wrong = (not math.isfinite(printed)) or abs(printed - pair[0]) > 1e-3 * pair[0]
    return ClaimResult(
        f"'+': {pair[0]:.8g} rad/s = eigenvalue; '-' differs",
        f"'+': {pair[0]:.8g}, eigenvalues {', '.join(f'{v:.8g}' for v in target)}; as printed: {printed:.8g}",
        plus_ok and printed_wrong,
    )


def _check_h_zero() -> ClaimResult:
    # Digest §13 S4: C_x/m = 10 < K_y/I_y = 4000, h = 0.
    p = Carriage(1.0, 1.0, 1.0, 1.0, 10.0, 10.0, 10.0, 4000.0, 4000.0, 4000.0, 0.0)
    up, lo = (
        coupled_frequency(10.0, 4000.0, 1.0, 1.0, 0.0, +1),
        coupled_frequency(10.0, 4000.0, 1.0, 1.0, 0.0, -1),
    )
    ok = (
        close(63.245553203367585, up, rtol=1e-12).passed
        and close(3.1622776601683795, lo, rtol=1e-12).passed
        and mode_character(p, "x-phi_y upper") == "rotation"
        and mode_character(p, "x-phi_y lower") == "translation"
    )
    return ClaimResult(
        "+ root 63.2455532 (rotation), - root 3.16227766 (translation)",
        f"+ {up:.10g} ({mode_character(p, 'x-phi_y upper')}), - {lo:.10g} ({mode_character(p, 'x-phi_y lower')})",
        ok,
    )


def _check_mode_ratio() -> ClaimResult:
    worst = 0.0
    for p in _preset_carriages()[:2] + _random_carriages(5, seed=3):
        M, K = p.matrices()
        for key in ("x-phi_y upper", "x-phi_y lower", "y-phi_x upper", "y-phi_x lower"):
            s = mode_shape(p, key)
            w2 = closed_form_frequencies(p)[key] ** 2
            worst = max(worst, float(np.linalg.norm(K @ s - w2 * (M @ s)) / np.linalg.norm(K @ s)))
    return at_most(1e-9, worst, "relative residual |K s - w^2 M s| ")


def _check_jeffcott() -> ClaimResult:
    m, e, c, w = sp.symbols("m e c varpi", positive=True)
    zz = jeffcott_deflection(m, e, c, w)
    residual = sp.simplify(c * zz - m * w**2 * (e + zz))
    singular = sp.solve(sp.denom(sp.together(zz)), w)
    ok = (
        residual == 0
        and singular == [sp.sqrt(c / m)]
        or (residual == 0 and sp.sqrt(c) / sp.sqrt(m) in singular)
    )
    return ClaimResult(
        "residual 0; singular at sqrt(c/m)",
        f"residual {residual}; singular at {singular}",
        bool(ok),
    )


def _check_torsional() -> ClaimResult:
    k, m, q, w = sp.symbols("k m q varpi", positive=True)
    d1 = sp.simplify(
        sp.sqrt(k / (m * q**2))
        - sp.sqrt(k / (m * q**2)).subs(m * q**2, sp.Symbol("I")).subs(sp.Symbol("I"), m * q**2)
    )
    fc = 1 / (2 * math.pi) * math.sqrt(50.0 / 2.0)
    return ClaimResult(
        "difference 0; f_c = 0.7957747 Hz for c/m = 25",
        f"{d1}; {fc:.7f}",
        d1 == 0 and abs(fc - 0.7957747) < 1e-7,
    )


def _box_integrals() -> dict[str, sp.Expr]:
    a, b, H, m = sp.symbols("a b H m", positive=True)
    X, Y, Z = sp.symbols("X Y Z", real=True)
    rho = m / (a * b * H)
    lim = [(X, -b / 2, b / 2), (Y, -a / 2, a / 2), (Z, -H / 2, H / 2)]
    return {
        "Ix": sp.simplify(sp.integrate(rho * (Y**2 + Z**2), *lim)),
        "Iy": sp.simplify(sp.integrate(rho * (X**2 + Z**2), *lim)),
        "Iz": sp.simplify(sp.integrate(rho * (X**2 + Y**2), *lim)),
        "syms": (a, b, H, m),
    }


def _check_box_inertia() -> ClaimResult:
    r = _box_integrals()
    a, b, H, m = r["syms"]
    d_z = sp.simplify(r["Iz"] - m * (a**2 + b**2) / 12)
    d_x = sp.simplify(r["Ix"] - m * (a**2 + H**2) / 12)
    d_y = sp.simplify(r["Iy"] - m * (b**2 + H**2) / 12)
    printed = box_inertia_printed(1.0, 0.4, 0.5, 0.06)
    exact = box_inertia(1.0, 0.4, 0.5, 0.06)
    numeric_ok = abs(exact[2] - float(r["Iz"].subs({a: 0.4, b: 0.5, H: 0.06, m: 1}))) < 1e-15
    printed_differs = abs(printed[0] - exact[0]) > 1e-6 and abs(printed[1] - exact[1]) > 1e-6
    return ClaimResult(
        "(2.75) and corrected (2.76)/(2.77): differences 0; printed differ",
        f"{d_z}, {d_x}, {d_y}; printed I_x, I_y = {printed[0]:.6g}, {printed[1]:.6g} vs {exact[0]:.6g}, {exact[1]:.6g}",
        d_z == 0 and d_x == 0 and d_y == 0 and numeric_ok and printed_differs,
    )


def _check_huygens() -> ClaimResult:
    a, b, H, m = sp.symbols("a b H m", positive=True)
    X, Y, Z, Xc, Yc, Zc = sp.symbols("X Y Z X_c Y_c Z_c", real=True)
    rho = m / (a * b * H)
    lim = [(X, Xc - b / 2, Xc + b / 2), (Y, Yc - a / 2, Yc + a / 2), (Z, Zc - H / 2, Zc + H / 2)]
    Iz = sp.integrate(rho * (X**2 + Y**2), *lim)
    d = sp.simplify(Iz - m * ((a**2 + b**2) / 12 + Xc**2 + Yc**2))
    num = box_inertia(2.0, 0.4, 0.5, 0.06, 0.1, -0.2, 0.05)[2]
    return ClaimResult(
        "difference 0; I_z(m=2, a=.4, b=.5, Xc=.1, Yc=-.2) = 0.168333",
        f"{d}; {num:.6f}",
        d == 0 and abs(num - 0.1683333333) < 1e-9,
    )


def _check_free_response() -> ClaimResult:
    lesson = CarriageFreeVibration()
    params = lesson.resolve(preset="free-response")
    p = carriage_from_params(params)
    M, K = p.matrices()
    q0, v0 = lesson.initial_state(params)
    t = np.linspace(0.0, 0.05, 401)
    qs, _ = modal_propagate(p, q0, v0, t)
    A = np.block([[np.zeros((6, 6)), np.eye(6)], [-np.linalg.solve(M, K), np.zeros((6, 6))]])
    sol = solve_ivp(
        lambda _t, y: A @ y,
        (0.0, 0.05),
        np.concatenate([q0, v0]),
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
        t_eval=t,
    )
    err = float(np.max(np.abs(sol.y[:6].T - qs)) / np.max(np.abs(qs)))
    return at_most(1e-8, err, "max relative difference ")


# ====================================================================== Problem 2.7


def oscillator_from_params(p: Params) -> ForcedOscillator:
    return ForcedOscillator(p["m"], p["b"], p["c"], p["F0"], p["w0"])


class CarriageForcedVibration(Lesson):
    id = "carriage-forced-vibration"
    title = "Forced vibration of the carriage"
    chapter = "2"
    problem = "Problem 2.7"
    source = "Textbook §2.3, Problem 2.7, eqs (2.78)-(2.92)"
    summary = (
        "One axis of the carriage: m q'' + b q' + c q = F0 sin(w0 t).  Transient plus steady "
        "response in closed form, amplitude and phase against the forcing frequency, resonance."
    )
    order = 2.7
    t_end = 20.0
    params = (
        Param("m", "float", 2.0, "mass m", "kg", 1e-6, 1e6, 0.1),
        Param(
            "b", "float", 0.8, "damping coefficient b of the air bearing", "N s/m", 0.0, 1e7, 0.1
        ),
        Param("c", "float", 50.0, "stiffness c", "N/m", 0.0, 1e10, 1.0),
        Param("F0", "float", 3.0, "force amplitude F0", "N", -1e7, 1e7, 0.1),
        Param("w0", "float", 4.0, "forcing frequency omega0", "rad/s", 0.0, 1e5, 0.1),
        Param("q0", "float", 0.05, "q(0)", "m", -1e3, 1e3, 0.01, group="initial"),
        Param("v0", "float", 0.0, "q'(0)", "m/s", -1e4, 1e4, 0.01, group="initial"),
    )
    presets = (
        Preset(
            "example",
            "Illustrative carriage axis, omega0 = 4 < omega = 5",
            {},
            20.0,
            "The source gives no numbers; these are the illustrative values of the verification (m=2, b=0.8, c=50, F0=3, omega0=4).",
        ),
        Preset(
            "above-resonance",
            "omega0 = 7 > omega: the phase passes -90 degrees",
            {"w0": 7.0},
            20.0,
            "tan phi1 = M/N loses the quadrant here; phi1 = atan2(M, N).",
        ),
        Preset(
            "resonance",
            "omega0 at the amplitude peak sqrt(omega^2 - 2 f^2)",
            {"w0": math.sqrt(25.0 - 2 * 0.2**2)},
            30.0,
            "",
        ),
        Preset(
            "critical",
            "Critical damping f = omega (b = 2 sqrt(m c))",
            {"b": 20.0},
            10.0,
            "(2.80) does not apply; q0 = (C1 + C2 t) e^{-ft}.",
        ),
        Preset(
            "overdamped",
            "Large resistance f > omega: aperiodic transient",
            {"b": 40.0},
            10.0,
            "The source writes f > omega for (2.80); the oscillating form needs f < omega.",
        ),
        Preset(
            "undamped-resonance",
            "b = 0, omega0 = omega: amplitude grows linearly",
            {"b": 0.0, "w0": 5.0, "q0": 0.0},
            20.0,
            "No bounded particular solution (2.81): q* = -tau t cos(omega0 t)/(2 omega0).",
        ),
    )
    plots = (
        PlotSpec("Coordinate", ("q", "q_steady", "q_transient"), "m"),
        PlotSpec("Velocity", ("v",), "m/s"),
        PlotSpec("Forces", ("F_drive", "F_spring", "F_damper"), "N"),
    )

    def validate(self, params: Params) -> None:
        if params["m"] <= 0:
            raise ParamError("m", "the mass must be positive")

    def messages(self, o: ForcedOscillator) -> list[str]:
        out = []
        if o.f == 0:
            out.append(
                f"b = 0: undamped oscillation at omega = {o.omega:.4g} rad/s; the free part never decays."
            )
        elif o.regime == "underdamped":
            out.append(
                f"f = {o.f:.4g} < omega = {o.omega:.4g}: decaying oscillation (2.80) with omega1 = {o.omega1:.4g} rad/s."
            )
        elif o.regime == "critical":
            out.append("f = omega: critically damped; (2.80) is replaced by (C1 + C2 t) e^{-ft}.")
        else:
            out.append(
                f"f = {o.f:.4g} > omega = {o.omega:.4g}: aperiodic transient; (2.80) does not apply (the source's 'f > omega' is read as f < omega)."
            )
        if o.secular:
            out.append(
                "Undamped resonance: the amplitude grows without bound, q* = -tau t cos(omega0 t)/(2 omega0)."
            )
        return out

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        o = oscillator_from_params(params)
        fast = max(o.w0, o.omega, 1e-9)
        n = int(min(200_000, max(2001, 40 * t_end * fast / TWO_PI)))
        t = np.linspace(0.0, t_end, n)
        q, v = o.response(t, params["q0"], params["v0"])
        qs, _ = o.particular(t)
        series = {
            "q": q,
            "v": v,
            "q_steady": qs,
            "q_transient": q - qs,
            "F_drive": o.F0 * np.sin(o.w0 * t),
            "F_spring": -o.c * q,
            "F_damper": -o.b * v,
        }
        M, N = o.MN
        metrics: dict[str, Any] = {
            "f": o.f,
            "omega": o.omega,
            "omega1": o.omega1,
            "tau": o.tau,
            "M": M,
            "N": N,
            "A0": o.A0,
            "phi1": o.phi1,
            "phase_lag_deg": -math.degrees(o.phi1),
            "regime": o.regime,
            "peak_w0": o.peak_frequency,
            "peak_A0": o.peak_amplitude,
        }
        if o.regime == "underdamped" and not o.secular:
            A, ph0 = o.amplitude_phase_constants(params["q0"], params["v0"])
            metrics.update({"A": A, "phi0": ph0})
        return RunResult(self.id, None, params.raw(), t, series, metrics, self.messages(o))

    def stepper(self, params: Params) -> Stepper:
        return _ForcedStepper(self, params)

    def _length(self, params: Params) -> float:
        o = oscillator_from_params(params)
        A0 = o.A0 if math.isfinite(o.A0) else abs(o.tau) * 10 / max(o.w0, 1e-9) ** 2
        return max(abs(params["q0"]), A0, abs(params["v0"]) / max(o.omega, o.w0, 1.0), 1e-3)

    def afc_curve(self, params: Params, n: int = 400) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Amplitude and phase of the steady response over omega0 in [0, 3 max(omega, omega0)]."""
        o = oscillator_from_params(params)
        top = 3.0 * max(o.omega, o.w0, 1e-3)
        w = np.linspace(0.0, top, n)
        A, ph = frequency_response(o.m, o.b, o.c, o.F0, w)
        return w, A, ph

    def scene(self, params: Params) -> SceneSpec:
        L = self._length(params)
        s = 0.6 * L
        box = trimesh.creation.box(extents=(s, s, s))
        wall = trimesh.creation.box(extents=(0.05 * L, 2 * s, 2 * s))
        wall.apply_translation((-2.5 * L, 0, s))
        floor_y = -1.5 * s
        w, A, _ = self.afc_curve(params)
        finite = np.isfinite(A)
        Amax = float(np.max(A[finite])) if finite.any() and np.max(A[finite]) > 0 else 1.0
        Ashow = np.clip(np.where(finite, A, 4 * Amax) / Amax, 0, 4) * 1.5 * L
        xs = -2.5 * L + 5 * L * w / w[-1]
        afc = np.column_stack([xs, np.full_like(xs, 3 * L), Ashow])
        o = oscillator_from_params(params)
        A_now = o.A0 if math.isfinite(o.A0) else 4 * Amax
        here = np.array([[-2.5 * L + 5 * L * o.w0 / w[-1], 3 * L, min(A_now / Amax, 4) * 1.5 * L]])
        t_end = self.t_end
        return SceneSpec(
            bounds=((-2.6 * L, floor_y - 0.25 * L * t_end, 0.0), (2.6 * L, 3.2 * L, 6.5 * L)),
            meshes=[_mesh("wall", wall, (150, 150, 150), 0.7)],
            curves=[
                CurveItem("rest position", np.array([[0, -s, 0], [0, s, 0]]), (120, 120, 120)),
                CurveItem("amplitude-frequency characteristic A0(omega0)", afc, (200, 80, 0)),
                CurveItem(
                    "omega0 axis",
                    np.array([[-2.5 * L, 3 * L, 0], [2.5 * L, 3 * L, 0]]),
                    (60, 60, 60),
                    1.0,
                ),
            ],
            markers=[
                MarkerItem("omega0 on the characteristic", here, (220, 40, 40), 0.05 * L, "omega0"),
                MarkerItem(
                    "omega (natural)",
                    np.array([[-2.5 * L + 5 * L * o.omega / w[-1], 3 * L, 0]]),
                    (40, 40, 220),
                    0.04 * L,
                    "omega",
                ),
            ],
            moving_points={"q(t) trace": (40, 120, 40)},
            moving_vectors={
                "spring": (80, 80, 80),
                "damper": (140, 90, 40),
                "force F0 sin(omega0 t)": (220, 40, 40),
            },
            bodies=[_mesh("carriage", box, (120, 160, 220), 0.6)],
        )

    def derivation(self, params: Params) -> list[DerivationStep]:
        S = forced_lagrange()
        t, q = S.t, S.q
        f, om, tau, w0 = S.f, S.omega, S.tau, S.w0
        M, N, A, ph0, om1, A0, ph1 = sp.symbols("M N A varphi_0 omega_1 A_0 varphi_1")
        qd, qdd = sp.diff(q, t), sp.diff(q, t, 2)
        o = oscillator_from_params(params)
        w, Aw, phw = self.afc_curve(params, 9)
        picks = sorted(
            set(
                [*w[::2].tolist(), o.w0, o.omega]
                + ([o.peak_frequency] if math.isfinite(o.peak_frequency) else [])
            )
        )
        Ap, php = frequency_response(o.m, o.b, o.c, o.F0, np.array(picks))
        rows = " \\\\ ".join(
            f"{wi:.4g} & {ai:.5g} & {math.degrees(pi):.4g}" for wi, ai, pi in zip(picks, Ap, php)
        )
        return [
            DerivationStep(
                "Lagrange equation with resistance and a periodic force",
                "L = E - W, E = m q'^2/2, W = c q^2/2; generalized force -b q' + F0 sin(omega0 t) (sympy LagrangesMethod).",
                S.lagrange,
                "(2.78)",
                reconstructed="the second printed form has '-P q''; the resistance coefficient is b",
            ),
            DerivationStep(
                "Normalized form",
                "f = b/(2m) (a damping factor, not a frequency), omega^2 = c/m, tau = F0/m.",
                sp.Eq(qdd + 2 * f * qd + om**2 * q, tau * sp.sin(w0 * t)),
                "(2.79)",
            ),
            DerivationStep(
                "Free part",
                "Decaying oscillation; valid for f < omega (underdamped).",
                [
                    sp.Eq(sp.Symbol("q_0"), A * sp.exp(-f * t) * sp.sin(om1 * t + ph0)),
                    sp.Eq(om1, sp.sqrt(om**2 - f**2)),
                ],
                "(2.80)",
                reconstructed="the source says 'small resistance (f > omega) ... aperiodic'; the formula needs f < omega and oscillates",
            ),
            DerivationStep(
                "Other damping regimes",
                "Not in the source: f = omega gives (C1 + C2 t) e^{-ft}; f > omega two real exponents.",
                r"q_0=C_1e^{(-f+\sqrt{f^2-\omega^2})t}+C_2e^{(-f-\sqrt{f^2-\omega^2})t}",
                "note to (2.80)",
            ),
            DerivationStep(
                "Particular solution",
                "",
                sp.Eq(sp.Symbol("q^*"), M * sp.cos(w0 * t) + N * sp.sin(w0 * t)),
                "(2.81)-(2.82)",
            ),
            DerivationStep(
                "Coefficients of cos and sin vanish",
                "Substituted into (2.79) (the source says (2.81)).",
                [
                    sp.Eq(-M * w0**2 + 2 * f * N * w0 + om**2 * M, 0),
                    sp.Eq(-N * w0**2 - 2 * f * M * w0 + om**2 * N - tau, 0),
                ],
                "(2.83)-(2.84)",
                reconstructed="(2.84) partly lost in extraction; rebuilt from (2.83)",
            ),
            DerivationStep("Ratio", "", sp.Eq(N, (w0**2 - om**2) / (2 * f * w0) * M), "(2.85)"),
            DerivationStep(
                "M and N",
                "",
                [sp.Eq(M, S.M), sp.Eq(N, S.N)],
                "(2.86)-(2.87)",
                reconstructed="lost in extraction; solved from (2.84) with sympy",
            ),
            DerivationStep(
                "Amplitude",
                "M = A0 sin phi1, N = A0 cos phi1.",
                sp.Eq(A0, tau / sp.sqrt((om**2 - w0**2) ** 2 + 4 * f**2 * w0**2)),
                "(2.88)",
            ),
            DerivationStep(
                "Phase",
                "tan phi1 = M/N; the quadrant is taken from the signs of M and N: phi1 = atan2(M, N), in (-pi, 0].",
                sp.Eq(sp.tan(ph1), -2 * f * w0 / (om**2 - w0**2)),
                "(2.89)-(2.90)",
                reconstructed="(2.89) is a garbled intermediate that reduces to (2.90)",
            ),
            DerivationStep(
                "Steady response", "", sp.Eq(sp.Symbol("q^*"), A0 * sp.sin(w0 * t + ph1)), "(2.91)"
            ),
            DerivationStep(
                "Complete response",
                "A and phi0 from q(0), q'(0): A sin phi0 = q(0) - M, A cos phi0 = (q'(0) - N omega0 + f (q(0) - M))/omega1.",
                sp.Eq(
                    q,
                    A * sp.exp(-f * t) * sp.sin(om1 * t + ph0)
                    + tau / sp.sqrt((om**2 - w0**2) ** 2 + 4 * f**2 * w0**2) * sp.sin(w0 * t + ph1),
                ),
                "(2.92)",
                reconstructed="the subscripts of A and phi0 are garbled (A_1, phi_2); the same integration constants",
            ),
            DerivationStep(
                "Resonance",
                "Not in the source: A0(omega0) peaks at omega0 = sqrt(omega^2 - 2 f^2) when omega^2 > 2 f^2, with A0 = tau/(2 f omega1).",
                sp.Eq(sp.Symbol("omega_peak"), sp.sqrt(om**2 - 2 * f**2)),
                "from (2.88)",
            ),
            DerivationStep(
                "Frequency response of these parameters",
                f"f = {o.f:.5g} 1/s, omega = {o.omega:.5g} rad/s, tau = {o.tau:.5g} m/s^2, regime: {o.regime}; "
                f"at omega0 = {o.w0:.5g}: A0 = {o.A0:.6g} m, phi1 = {o.phi1:.6g} rad.",
                r"\begin{array}{ccc}\omega_0\ (\mathrm{rad/s})&A_0\ (\mathrm{m})&\varphi_1\ (^\circ)\\ \hline "
                + rows
                + r"\end{array}",
                "(2.88), (2.90)",
            ),
        ]

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "lagrange-2-78",
                "LagrangesMethod gives m q'' + c q = -b q' + F0 sin(omega0 t).",
                "(2.78)",
                _check_lagrange_forced,
            ),
            Claim(
                "particular-M-N",
                "M, N solving (2.84) are (2.86)/(2.87); they satisfy (2.85); the particular solution (2.81) leaves residual 0.",
                "(2.81)-(2.87)",
                _check_MN,
            ),
            Claim(
                "amplitude-phase",
                "A0 = sqrt(M^2 + N^2) is (2.88); M/N is (2.90); A0 sin(omega0 t + phi1) = M cos + N sin (2.91).",
                "(2.88)-(2.91)",
                _check_amp_phase,
            ),
            Claim(
                "homogeneous-2-80",
                "A e^{-ft} sin(omega1 t + phi0) solves the free equation, with omega1 = sqrt(omega^2 - f^2) real only for f < omega.",
                "(2.80)",
                _check_homogeneous,
            ),
            Claim(
                "illustrative-numbers",
                "m=2, b=0.8, c=50, F0=3, omega0=4: A0 = 0.164094 m, phi1 = -0.175940 rad.",
                "(2.88), (2.90)",
                _check_numbers,
            ),
            Claim(
                "phase-quadrant",
                "For omega0 = 7 > omega = 5, atan2(M, N) reproduces q*, plain atan(M/N) does not.",
                "(2.90)-(2.91)",
                _check_quadrant,
            ),
            Claim(
                "closed-vs-ivp",
                "The closed form (2.92) (and its critical/aperiodic/undamped-resonance forms) equals solve_ivp (DOP853, rtol 1e-12) to 1e-8.",
                "(2.92)",
                _check_closed_vs_ivp,
            ),
            Claim(
                "form-2-92",
                "(2.92) written with A, phi0 equals the response from q(0), q'(0) to 1e-12.",
                "(2.92)",
                _check_form_292,
            ),
            Claim(
                "regimes",
                "f < omega: decaying oscillation (many zero crossings); f > omega: aperiodic (at most one zero crossing).",
                "(2.80)",
                _check_regimes,
            ),
            Claim(
                "resonance-peak",
                "A0(omega0) is largest at sqrt(omega^2 - 2 f^2) = 4.99199 rad/s with A0 = tau/(2 f omega1) = 0.750601 m "
                "(illustrative values).",
                "(2.88)",
                _check_peak,
            ),
        ]


class _ForcedStepper(Stepper):
    def __init__(self, lesson: CarriageForcedVibration, params: Params) -> None:
        self.lesson = lesson
        self._t = 0.0
        self.params = params
        self.o = oscillator_from_params(params)
        self.q, self.v = float(params["q0"]), float(params["v0"])
        self.L = lesson._length(params)

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        o, L, s = self.o, self.L, 0.6 * self.L
        qs, _ = o.particular(self._t)
        F = o.F0 * math.sin(o.w0 * self._t)
        centre = np.array([self.q, 0.0, s / 2])
        left = centre - np.array([s / 2, 0, 0])
        wall = np.array([-2.5 * L, 0.0, 0.0])
        spring_o = wall + np.array([0, -0.2 * s, 0.7 * s])
        damper_o = wall + np.array([0, 0.2 * s, 0.3 * s])
        F_len = (F / abs(o.F0) if o.F0 else 0.0) * L
        bad = not (math.isfinite(self.q) and math.isfinite(self.v))
        return Frame(
            t=self._t,
            points={"q(t) trace": np.array([[self.q, -1.5 * s - 0.25 * L * self._t, 0.0]])},
            vectors={
                "spring": (
                    spring_o[None, :],
                    (left + np.array([0, -0.2 * s, 0.2 * s]) - spring_o)[None, :],
                ),
                "damper": (
                    damper_o[None, :],
                    (left + np.array([0, 0.2 * s, -0.2 * s]) - damper_o)[None, :],
                ),
                "force F0 sin(omega0 t)": (
                    (centre + np.array([s / 2, 0, 0]))[None, :],
                    np.array([[F_len, 0.0, 0.0]]),
                ),
            },
            poses={"carriage": (centre, np.array([1.0, 0.0, 0.0, 0.0]))},
            scalars={
                "q": self.q,
                "v": self.v,
                "q_steady": float(qs),
                "q_transient": self.q - float(qs),
                "F_drive": F,
                "F_spring": -o.c * self.q,
                "F_damper": -o.b * self.v,
            },
            message="the state is not finite" if bad else "",
        )

    def advance(self, dt: float) -> Frame:
        t1 = self._t + max(float(dt), 0.0)
        q, v = self.o.response(t1, self.q, self.v, t0=self._t)
        self.q, self.v, self._t = float(q), float(v), t1
        return self.frame()

    def set_params(self, params: Params) -> None:
        self.params = params
        self.o = oscillator_from_params(params)
        self.L = self.lesson._length(params)

    def reset(self) -> Frame:
        self._t = 0.0
        self.q, self.v = float(self.params["q0"]), float(self.params["v0"])
        return self.frame()


# -- claim checks, Problem 2.7 ---------------------------------------------------------


def _check_lagrange_forced() -> ClaimResult:
    S = forced_lagrange()
    t, q = S.t, S.q
    expected = S.m * sp.diff(q, t, 2) + S.c * q - (-S.b * sp.diff(q, t) + S.F0 * sp.sin(S.w0 * t))
    d = sp.simplify(S.lagrange.lhs - expected)
    return ClaimResult("difference 0", str(d), d == 0)


def _check_MN() -> ClaimResult:
    S = forced_lagrange()
    f, om, tau, w0, t = S.f, S.omega, S.tau, S.w0, S.t
    M, N = S.M, S.N
    M_src = -2 * f * w0 * tau / ((om**2 - w0**2) ** 2 + 4 * f**2 * w0**2)
    N_src = tau * (om**2 - w0**2) / ((om**2 - w0**2) ** 2 + 4 * f**2 * w0**2)
    qs = M * sp.cos(w0 * t) + N * sp.sin(w0 * t)
    residual = sp.simplify(
        sp.diff(qs, t, 2) + 2 * f * sp.diff(qs, t) + om**2 * qs - tau * sp.sin(w0 * t)
    )
    d = [
        sp.simplify(M - M_src),
        sp.simplify(N - N_src),
        sp.simplify(N - (w0**2 - om**2) / (2 * f * w0) * M),
        residual,
    ]
    return ClaimResult("all 0", str(d), all(x == 0 for x in d))


def _check_amp_phase() -> ClaimResult:
    S = forced_lagrange()
    f, om, tau, w0, t = S.f, S.omega, S.tau, S.w0, S.t
    d1 = sp.simplify(
        S.M**2 + S.N**2 - tau**2 / ((om**2 - w0**2) ** 2 + 4 * f**2 * w0**2)
    )  # A0^2, both sides positive
    d2 = sp.simplify(S.M / S.N - (-2 * f * w0 / (om**2 - w0**2)))
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 4.0)
    tt = np.linspace(0, 10, 101)
    M, N = o.MN
    d3 = float(
        np.max(
            np.abs(
                o.A0 * np.sin(o.w0 * tt + o.phi1) - (M * np.cos(o.w0 * tt) + N * np.sin(o.w0 * tt))
            )
        )
    )
    return ClaimResult("0, 0, < 1e-14", f"{d1}, {d2}, {d3:.2e}", d1 == 0 and d2 == 0 and d3 < 1e-14)


def _check_homogeneous() -> ClaimResult:
    t = sp.Symbol("t", real=True)
    A, ph0 = sp.symbols("A varphi_0", real=True)
    f, om = sp.symbols("f omega", positive=True)
    om1 = sp.sqrt(om**2 - f**2)
    q0 = A * sp.exp(-f * t) * sp.sin(om1 * t + ph0)
    residual = sp.simplify(sp.diff(q0, t, 2) + 2 * f * sp.diff(q0, t) + om**2 * q0)
    real_when = (
        ForcedOscillator(1, 2 * 1.0, 4.0, 0, 0).regime,
        ForcedOscillator(1, 2 * 3.0, 4.0, 0, 0).regime,
    )
    ok = residual == 0 and real_when == ("underdamped", "overdamped")
    return ClaimResult(
        "residual 0; f=1<omega=2 oscillates, f=3>omega=2 does not", f"{residual}; {real_when}", ok
    )


def _check_numbers() -> ClaimResult:
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 4.0)
    a, p = close(0.164094, o.A0, atol=5e-7), close(-0.175940, o.phi1, atol=5e-7)
    return ClaimResult(
        f"A0 {a.expected}; phi1 {p.expected}", f"A0 {a.got}; phi1 {p.got}", a.passed and p.passed
    )


def _check_quadrant() -> ClaimResult:
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 7.0)
    M, N = o.MN
    t = np.linspace(0, 5, 501)
    qs = M * np.cos(7 * t) + N * np.sin(7 * t)
    e2 = float(np.max(np.abs(o.A0 * np.sin(7 * t + math.atan2(M, N)) - qs)))
    e1 = float(np.max(np.abs(o.A0 * np.sin(7 * t + math.atan(M / N)) - qs)))
    return ClaimResult(
        "atan2 error < 1e-14, atan error > 1e-2",
        f"atan2 {e2:.2e}, atan {e1:.2e}",
        e2 < 1e-14 and e1 > 1e-2,
    )


def _ivp_error(o: ForcedOscillator, q0: float, v0: float, t_end: float) -> float:
    t = np.linspace(0.0, t_end, 1001)
    q, _ = o.response(t, q0, v0)
    sol = solve_ivp(
        o.rhs, (0.0, t_end), [q0, v0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=t
    )
    return float(np.max(np.abs(sol.y[0] - q)))


def _check_closed_vs_ivp() -> ClaimResult:
    cases = [
        (2, 0.8, 50, 3, 4, 0.05, 0),
        (2, 0.8, 50, 3, 7, 0.05, 0.3),
        (2, 20, 50, 3, 4, 0.05, 0),
        (2, 40, 50, 3, 4, 0.05, -0.2),
        (2, 0, 50, 3, 5, 0.0, 0.0),
        (2, 0, 0, 3, 2, 0.1, 0.1),
    ]
    worst = max(_ivp_error(ForcedOscillator(*c[:5]), c[5], c[6], 20.0) for c in cases)
    return at_most(1e-8, worst, "max |q_closed - q_ivp| (m) ")


def _check_form_292() -> ClaimResult:
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 4.0)
    t = np.linspace(0, 20, 2001)
    err = float(np.max(np.abs(o.response_292(t, 0.05, 0.0) - o.response(t, 0.05, 0.0)[0])))
    return at_most(1e-12, err, "max difference (m) ")


def _check_regimes() -> ClaimResult:
    t = np.linspace(0, 20, 20001)
    under, _ = ForcedOscillator(2, 0.8, 50, 0, 0).homogeneous(t, 0.05, 0.0)
    over, _ = ForcedOscillator(2, 40, 50, 0, 0).homogeneous(t, 0.05, -1.0)
    zc = lambda y: int(np.count_nonzero(np.diff(np.sign(y[np.abs(y) > 1e-14])) != 0))  # noqa: E731
    return ClaimResult(
        "f<omega: > 10 crossings; f>omega: <= 1",
        f"{zc(under)}; {zc(over)}",
        zc(under) > 10 and zc(over) <= 1,
    )


def _check_peak() -> ClaimResult:
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 4.0)
    w = np.linspace(4.9, 5.1, 200001)
    A, _ = frequency_response(2.0, 0.8, 50.0, 3.0, w)
    w_num, A_num = float(w[np.argmax(A)]), float(np.max(A))
    ok = (
        abs(w_num - o.peak_frequency) < 2e-6
        and abs(o.peak_frequency - 4.99199) < 5e-6
        and abs(A_num - o.peak_amplitude) < 1e-9
        and abs(o.peak_amplitude - 0.750601) < 5e-7
    )
    return ClaimResult(
        "peak at 4.99199 rad/s, A0 0.750601 m",
        f"numeric peak at {w_num:.6f}, A0 {A_num:.7f}; formula {o.peak_frequency:.6f}, {o.peak_amplitude:.7f}",
        ok,
    )


LESSONS = [CarriageFreeVibration(), CarriageForcedVibration()]
