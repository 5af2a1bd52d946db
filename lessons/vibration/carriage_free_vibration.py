"""Free vibration of the air-bearing carriage of the EM-5034 plate coordinate table.

Textbook §2.3, Problem 2.6: the carriage as one rigid box with 6 degrees of freedom on
the elastic air bearing, eqs (2.35)-(2.77).  The model, its closed-form frequencies and
the box inertia are in :mod:`analyzer_lab.lessons.vibration.carriage.model`; the derivation steps in
:mod:`analyzer_lab.lessons.vibration.carriage.derivation`, the claim checks in
:mod:`analyzer_lab.lessons.vibration.carriage.claims`, the drawing in
:mod:`analyzer_lab.lessons.vibration.carriage.geometry`.
The source gives no numbers for m, I, C, K, h: the defaults here are example values,
said so in every preset note.  The modes have 40-300 Hz: the run is shown in slow
motion (``time_scale``).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np
import trimesh
from analyzer_lab.lessons.kit.bodies import mesh_item
from analyzer_lab.lessons.kit.contract import (
    MODE,
    Claim,
    ClaimResult,
    CurveItem,
    DerivationStep,
    Frame,
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
from analyzer_lab.lessons.kit.dense_solution import ClosedFormRun, RunStepper
from analyzer_lab.lessons.vibration.carriage.claims import (
    check_box_inertia,
    check_closed_vs_eig,
    check_determinant,
    check_free_response,
    check_gradients,
    check_h_zero,
    check_huygens,
    check_jeffcott,
    check_lagrange_6dof,
    check_mode_ratio,
    check_sign_268,
    check_torsional,
)
from analyzer_lab.lessons.vibration.carriage.derivation import free_vibration_steps
from analyzer_lab.lessons.vibration.carriage.geometry import CarriageGeometry
from analyzer_lab.lessons.vibration.carriage.model import (
    COORDS,
    MODE_KEYS,
    Carriage,
    ModalResponse,
    box_inertia,
    closed_form_frequencies,
    frequency_table,
    mode_character,
    mode_shape,
)

TWO_PI = 2.0 * math.pi
EXAMPLE_NOTE = (
    "The source gives no numbers for the carriage; these are example values of a plausible table."
)
MODE_LABELS = {
    "z": "z: vertical translation (single-coupled)",
    "phi_z": "phi_z: rotation about Z (single-coupled)",
    "x-phi_y upper": "x & phi_y: upper coupled mode",
    "x-phi_y lower": "x & phi_y: lower coupled mode",
    "y-phi_x upper": "y & phi_x: upper coupled mode",
    "y-phi_x lower": "y & phi_x: lower coupled mode",
}


def carriage_from_params(p: Params) -> Carriage:
    """Carriage model of the parameters: box inertia by (2.74)-(2.77) (corrected)."""
    Ix, Iy, Iz = box_inertia(p["m"], p["a"], p["b"], p["H"], p["Xc"], p["Yc"], p["Zc"])
    return Carriage(
        p["m"], Ix, Iy, Iz, p["Cx"], p["Cy"], p["Cz"], p["Kx"], p["Ky"], p["Kz"], p["h"]
    )


def geometry_from_params(p: Params) -> CarriageGeometry:
    """The drawn box b x a x H, h above the centre of stiffness."""
    return _geometry(float(p["a"]), float(p["b"]), float(p["H"]), float(p["h"]))


@lru_cache(maxsize=8)
def _geometry(a: float, b: float, H: float, h: float) -> CarriageGeometry:
    return CarriageGeometry(a, b, H, h)


def _size(name: str, default: float, label: str, lo: float, step: float) -> Param:
    return Param(name, "float", default, label, "m", lo, 5.0, step, group="carriage")


def _stiffness(name: str, default: float, label: str, unit: str, lo: float) -> Param:
    return Param(name, "float", default, label, unit, lo, 1e10, group="bearing")


def _start(name: str, default: float, label: str, unit: str, step: float) -> Param:
    return Param(name, "float", default, label, unit, -1.0, 1.0, step, group="initial")


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
    sampling = 1e-4
    # 40-300 Hz modes: 1/100 of real time shows 0.4-3 periods per second, 0.1 s in 10 s
    time_scale = 0.01
    # the mode and the start state restart the run; so does a changed carriage or bearing,
    # whose modes differ: the animated mode starts again from its new shape
    groups = (
        MODE,
        Group("carriage", "Carriage", change="restart"),
        Group("bearing", "Air bearing", change="restart"),
        Group("initial", "Start state", change="restart"),
    )
    modes = ("mode",)
    series = (
        *(Series(c, "m", f"translation {c} of the centre of gravity") for c in ("x", "y", "z")),
        *(Series(c, "rad", f"small rotation {c}") for c in ("phi_x", "phi_y", "phi_z")),
        *(Series(f"v{c}", "m/s", f"velocity {c}'") for c in ("x", "y", "z")),
        *(Series(f"omega_{c}", "rad/s", f"angular velocity phi_{c}'") for c in ("x", "y", "z")),
        *(Series(f"F{c}", "N", f"elastic force of the bearing along {c} (-K q)") for c in "xyz"),
        *(Series(f"M{c}", "N m", f"elastic moment of the bearing about {c} (-K q)") for c in "xyz"),
        Series("E", "J", "kinetic energy (2.39)"),
        Series("W", "J", "potential energy of the bearing (2.40)"),
        Series("E_total", "J", "E + W (constant: no damping)"),
    )
    readout = ("x", "z", "phi_y", "phi_z", "E_total")
    params = (
        Param(
            "mode",
            "choice",
            "x-phi_y upper",
            "animated mode",
            choices=(*MODE_KEYS, "free response"),
            group="mode",
            help="one normal mode, or the free response from the initial displacements",
        ),
        Param("m", "float", 20.0, "carriage mass m", "kg", 0.01, 1e4, 0.1, group="carriage"),
        _size("b", 0.5, "box length b (along X)", 0.01, 0.01),
        _size("a", 0.4, "box width a (along Y)", 0.01, 0.01),
        _size("H", 0.06, "box height H (along Z)", 0.001, 0.005),
        *(_size(f"{c}c", 0.0, f"centre of gravity {c}_c (2.73)", -5.0, 0.01) for c in "XYZ"),
        Param(
            "h",
            "float",
            0.02,
            "h: centre of gravity above the centre of stiffness",
            "m",
            0.0,
            1.0,
            0.005,
            group="bearing",
        ),
        _stiffness("Cx", 2e6, "C_x translational stiffness", "N/m", 1.0),
        _stiffness("Cy", 2e6, "C_y translational stiffness", "N/m", 1.0),
        _stiffness("Cz", 5e7, "C_z translational stiffness", "N/m", 1.0),
        _stiffness("Kx", 8e5, "K_x rotational stiffness", "N m/rad", 1e-3),
        _stiffness("Ky", 8e5, "K_y rotational stiffness", "N m/rad", 1e-3),
        _stiffness("Kz", 6e4, "K_z rotational stiffness", "N m/rad", 1e-3),
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
        _start("x0", 0.01, "x(0) for the free response", "m", 0.001),
        _start("y0", 0.0, "y(0)", "m", 0.001),
        _start("z0", 0.005, "z(0)", "m", 0.001),
        _start("phi_x0", 0.0, "phi_x(0)", "rad", 0.005),
        _start("phi_y0", 0.05, "phi_y(0)", "rad", 0.005),
        _start("phi_z0", 0.02, "phi_z(0)", "rad", 0.005),
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
        shape = mode_shape(carriage_from_params(params), params["mode"])
        d = geometry_from_params(params).max_corner_displacement(shape)
        return shape * (params["amplitude"] / d if d > 0 else 0.0), np.zeros(6)

    def validate(self, params: Params) -> None:
        h = params["h"]
        for K, C in (("Ky", "Cx"), ("Kx", "Cy")):
            if params[K] <= params[C] * h**2:
                raise ParamError(
                    K,
                    f"must exceed {C} h^2 = {params[C] * h**2:.4g}: K is the total rotational "
                    "stiffness about O (2.40); below that the bearing is unstable and the lower "
                    "frequency is imaginary",
                )

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, np.ndarray]:
        """Coordinates, velocities, the elastic forces -K q and the energies (2.39)/(2.40)."""
        M, K = carriage_from_params(params).matrices()
        state = np.asarray(state, dtype=float)
        q, v = state[:, :6], state[:, 6:]
        forces = -(q @ K)  # generalized elastic forces
        E = 0.5 * np.einsum("ij,jk,ik->i", v, M, v)
        W = 0.5 * np.einsum("ij,jk,ik->i", q, K, q)
        out = {c: q[:, i] for i, c in enumerate(COORDS)}
        for i, c in enumerate("xyz"):
            out[f"v{c}"], out[f"omega_{c}"] = v[:, i], v[:, 3 + i]
            out[f"F{c}"], out[f"M{c}"] = forces[:, i], forces[:, 3 + i]
        out.update({"E": E, "W": W, "E_total": E + W})
        return out

    def run_from(self, params: Params, t0: float, state: np.ndarray | None) -> ClosedFormRun:
        """The free response from ``state = (q, q')`` at ``t0`` (the start when None),
        exact by modal superposition of (2.42)-(2.44)."""
        p = carriage_from_params(params)
        q0, v0 = self.initial_state(params) if state is None else (state[:6], state[6:])
        modes = ModalResponse(p, q0, v0)  # once per parameter set
        return ClosedFormRun(lambda t: np.hstack(modes.at(np.asarray(t, dtype=float) - t0)))

    def notes(self, params: Params) -> list[Note]:
        out = [Note("info", EXAMPLE_NOTE)]
        if params["mode"] != "free response":
            p, k = carriage_from_params(params), params["mode"]
            w = closed_form_frequencies(p)[k]
            out.append(
                Note(
                    "info",
                    f"Mode {MODE_LABELS[k]}: omega = {w:.6g} rad/s ({w / TWO_PI:.6g} Hz), mostly "
                    f"{mode_character(p, k)}; drawn amplitude is illustrative.",
                )
            )
        out += [
            Note(
                "corrected",
                "(2.68) is used with '+' under the inner radical",
                "(2.68)",
                "the printed '-' contradicts (2.66) and misses the eigenvalue of the full model",
            ),
            Note(
                "corrected",
                "(2.76)-(2.77): each moment uses the two dimensions across its axis; 'h' is H",
                "(2.76)-(2.77)",
                "integration over the box b x a x H; the printed forms swap a and b",
            ),
        ]
        return out

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        table = frequency_table(carriage_from_params(params))
        p = table.carriage
        n = int(min(200_000, max(1001, 40 * t_end * float(np.max(table.eig)) / TWO_PI)))
        t = np.linspace(0.0, t_end, n)
        metrics: dict[str, Any] = {
            "I_x": p.Ix,
            "I_y": p.Iy,
            "I_z": p.Iz,
            "max_rel_err_closed_vs_eig": table.max_rel_err,
        }
        for k, w in table.closed_form.items():
            tag = k.replace(" ", "_").replace("-", "_")
            metrics[f"omega_{tag}"] = w
            metrics[f"f_{tag}_Hz"] = w / TWO_PI
            metrics[f"character_{tag}"] = mode_character(p, k)
        for i, w in enumerate(table.eig):
            metrics[f"omega_eig_{i + 1}"] = float(w)
        state = self.run_from(params, 0.0, None).state(t)
        notes = [n.text for n in self.notes(params) if n.kind == "info"]
        return self.result(params, t, state, metrics, notes)

    def stepper(self, params: Params) -> Stepper:
        """The exact free response played live; it starts from ``initial_state`` (the
        chosen mode's shape), a changed mode restarts it (group ``mode``)."""
        return RunStepper.for_lesson(self, params, self.run_from, self._frame)

    def _frame(
        self,
        params: Params,
        t: float,
        state: np.ndarray,
        scalars: dict[str, float] | None = None,
    ) -> Frame:
        pos, quat, corner, springs = geometry_from_params(params).drawn(state[0, :6])
        return Frame(
            t=t,
            points={"O (centre of gravity)": pos[None, :], "corner": corner[None, :]},
            vectors={"springs": springs},
            poses={"carriage": (pos, quat)},
            scalars=self.frame_scalars(params, t, state) if scalars is None else scalars,
        )

    def scene(self, params: Params) -> SceneSpec:
        g = geometry_from_params(params)
        box = trimesh.creation.box(extents=(g.b, g.a, g.H))
        span = 0.5 * max(g.a, g.b) + g.gap + 0.05
        stator = trimesh.creation.box(extents=(2 * span, 2 * span, 0.1 * g.gap))
        stator.apply_translation((0, 0, g.floor - 0.05 * g.gap))
        ax = 0.5 * span
        curves = [
            CurveItem("X axis (stiffness plane)", np.array([[0, 0, 0], [ax, 0, 0]]), (200, 40, 40)),
            CurveItem("Y axis (stiffness plane)", np.array([[0, 0, 0], [0, ax, 0]]), (40, 160, 40)),
            CurveItem("Z axis", np.array([[0, 0, 0], [0, 0, ax]]), (40, 40, 200)),
        ]
        markers = [
            MarkerItem(
                "centre of stiffness", np.zeros((1, 3)), (200, 120, 0), 0.01, "stiffness centre"
            ),
            MarkerItem("spring anchors", g.anchors, (90, 90, 90), 0.008),
        ]
        top = g.h + g.H / 2 + 0.5 * g.gap
        return SceneSpec(
            bounds=((-span, -span, g.floor - 0.1 * g.gap), (span, span, top)),
            meshes=[mesh_item("stator", stator, (150, 150, 150), 0.5)],
            curves=curves,
            markers=markers,
            moving_points={"O (centre of gravity)": (220, 60, 60), "corner": (60, 60, 220)},
            moving_vectors={"springs": (80, 80, 80)},
            bodies=[mesh_item("carriage", box, (120, 160, 220), 0.55)],
        )

    # -- page ---------------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        return free_vibration_steps(frequency_table(carriage_from_params(params)))

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "lagrange-6dof",
                "LagrangesMethod applied to E - W of (2.39)/(2.40) gives exactly the six "
                "equations (2.42)-(2.44) (n = 6).",
                "(2.38)-(2.44)",
                check_lagrange_6dof,
            ),
            Claim(
                "gradient-W",
                "The derivatives of W are those of (2.41).",
                "(2.41)",
                check_gradients,
            ),
            Claim(
                "determinant-forms",
                "The three expanded forms of the determinant (2.65) agree, and the radical "
                "transformation of (2.66) holds.",
                "(2.65)-(2.66)",
                check_determinant,
            ),
            Claim(
                "closed-form-vs-eig",
                "The six closed-form frequencies equal the eigenvalues of the 6-DOF model "
                "M q'' + K q = 0 to 1e-9 relative (the presets and 20 random parameter sets).",
                "(2.42)-(2.44), (2.50), (2.54), (2.66)-(2.72)",
                lambda: check_closed_vs_eig(self.preset_carriages()),
            ),
            Claim(
                "sign-2-68",
                "(2.68) with '-' under the inner radical, as extracted, misses the eigenvalue; "
                "with '+' it matches.",
                "(2.68)",
                lambda: check_sign_268(self.preset_carriages()[1]),  # strong-coupling
            ),
            Claim(
                "h-zero-decouples",
                "With h = 0 the coupled roots are sqrt(C_x/m) and sqrt(K_y/I_y); for "
                "C_x/m = 10, K_y/I_y = 4000 the '+' root 63.2455532 is the rotational mode and "
                "the '-' root 3.16227766 the translational one.",
                "(2.67)-(2.68)",
                check_h_zero,
            ),
            Claim(
                "mode-shape-ratio",
                "The amplitude ratio A_phiy/A_x = -(C_x - m varpi^2)/(C_x h) of (2.64) is the "
                "eigenvector of the full model.",
                "(2.64)",
                lambda: check_mode_ratio(self.preset_carriages()[:2]),
            ),
            Claim(
                "jeffcott",
                "z = m e varpi^2/(c - m varpi^2) solves c z = m varpi^2 (e + z) and is singular "
                "at varpi = sqrt(c/m).",
                "(2.47)-(2.50)",
                check_jeffcott,
            ),
            Claim(
                "torsional",
                "(2.53) equals (2.54) with I = m q^2; f = varpi/(2 pi) in (2.55)/(2.56).",
                "(2.53)-(2.56)",
                check_torsional,
            ),
            Claim(
                "box-inertia",
                "Integration over a uniform box b x a x H confirms (2.75) and the corrected "
                "(2.76)/(2.77); the printed (2.76)/(2.77) differ when a != b.",
                "(2.75)-(2.77)",
                check_box_inertia,
            ),
            Claim(
                "huygens-steiner",
                "For a box whose centre of gravity is at (X_c, Y_c, Z_c), I_z about the Z axis "
                "is m((a^2+b^2)/12 + X_c^2 + Y_c^2).",
                "(2.73)-(2.75)",
                check_huygens,
            ),
            Claim(
                "free-response",
                "Modal superposition of the free response equals solve_ivp (DOP853, "
                "rtol 1e-12) to 1e-8 relative.",
                "(2.42)-(2.44)",
                self._check_free_response,
            ),
        ]

    def preset_carriages(self) -> list[Carriage]:
        """The carriages of the presets, in their order."""
        return [carriage_from_params(self.resolve(preset=p.name)) for p in self.presets]

    def _check_free_response(self) -> ClaimResult:
        params = self.resolve(preset="free-response")
        return check_free_response(carriage_from_params(params), *self.initial_state(params))


LESSON = CarriageFreeVibration()
