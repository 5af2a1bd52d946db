"""Forced vibration of the air-bearing carriage along one axis.

Textbook §2.3, Problem 2.7, eqs (2.78)-(2.92): m q'' + b q' + c q = F0 sin(w0 t), the
transient plus steady response in closed form
(:class:`analyzer_lab.lessons.vibration.carriage.model.ForcedOscillator`), amplitude and phase against the
forcing frequency, resonance.  The derivation steps are in
:mod:`analyzer_lab.lessons.vibration.carriage.derivation`, the claim checks in
:mod:`analyzer_lab.lessons.vibration.carriage.claims`.  The source gives no numbers for m, b, c, F0, w0:
the defaults are illustrative, said so in the preset notes.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import trimesh
from analyzer_lab.lessons.kit.bodies import mesh_item
from analyzer_lab.lessons.kit.contract import (
    Claim,
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
    check_amp_phase,
    check_closed_vs_ivp,
    check_form_292,
    check_homogeneous,
    check_lagrange_forced,
    check_MN,
    check_numbers,
    check_peak,
    check_quadrant,
    check_regimes,
)
from analyzer_lab.lessons.vibration.carriage.derivation import forced_vibration_steps
from analyzer_lab.lessons.vibration.carriage.model import ForcedOscillator, frequency_response

TWO_PI = 2.0 * math.pi


def oscillator_from_params(p: Params) -> ForcedOscillator:
    return ForcedOscillator(p["m"], p["b"], p["c"], p["F0"], p["w0"])


class CarriageForcedVibration(Lesson):
    id = "carriage-forced-vibration"
    title = "Forced vibration of the carriage"
    chapter = "2"
    problem = "Problem 2.7"
    source = "Textbook §2.3, Problem 2.7, eqs (2.78)-(2.92)"
    summary = (
        "One axis of the carriage: m q̈ + b q̇ + c q = F₀ sin(ω₀t).  Transient plus steady "
        "response in closed form, amplitude and phase against the forcing frequency, resonance."
    )
    order = 2.7
    t_end = 20.0
    sampling = 0.01
    # omega = 5 rad/s (0.8 Hz): twice real time shows 1.6 periods per second, 20 s in 10 s
    time_scale = 2.0
    # the closed form restarts from the current state after any change of m, b, c, F0,
    # omega0: they act at once (the characteristic in the scene follows); q(0), q'(0) restart
    groups = (
        Group("carriage", "Carriage"),
        Group("bearing", "Air bearing"),
        Group("forcing", "Forcing", change="live"),
        Group("initial", "Start state", change="restart"),
    )
    series = (
        Series("q", "m", "coordinate of the carriage (2.92)"),
        Series("v", "m/s", "velocity q̇"),
        Series("q_steady", "m", "steady (particular) response q* (2.91)"),
        Series("q_transient", "m", "free part q - q* (2.80)"),
        Series("F_drive", "N", "driving force F0 sin(omega0 t)"),
        Series("F_spring", "N", "elastic force -c q"),
        Series("F_damper", "N", "resistance -b q'"),
    )
    readout = ("q", "v", "q_steady", "F_drive")
    params = (
        Param("m", "float", 2.0, "mass m", "kg", 1e-6, 1e6, 0.1, group="carriage"),
        Param(
            "b",
            "float",
            0.8,
            "damping coefficient b of the air bearing",
            "N s/m",
            0.0,
            1e7,
            0.1,
            group="bearing",
        ),
        Param("c", "float", 50.0, "stiffness c", "N/m", 0.0, 1e10, 1.0, group="bearing"),
        Param("F0", "float", 3.0, "force amplitude F0", "N", -1e7, 1e7, 0.1, group="forcing"),
        Param(
            "w0", "float", 4.0, "forcing frequency omega0", "rad/s", 0, 1e5, 0.1, group="forcing"
        ),
        Param("q0", "float", 0.05, "q(0)", "m", -1e3, 1e3, 0.01, group="initial"),
        Param("v0", "float", 0.0, "q'(0)", "m/s", -1e4, 1e4, 0.01, group="initial"),
    )
    presets = (
        Preset(
            "example",
            "Illustrative carriage axis, omega0 = 4 < omega = 5",
            {},
            20.0,
            "The source gives no numbers; these are the illustrative values of the verification "
            "(m=2, b=0.8, c=50, F0=3, omega0=4).",
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
            "(2.80) does not apply; q0 = (C1 + C2 t) e^(-f t).",
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
                f"b = 0: undamped oscillation at omega = {o.omega:.4g} rad/s; "
                "the free part never decays."
            )
        elif o.regime == "underdamped":
            out.append(
                f"f = {o.f:.4g} < omega = {o.omega:.4g}: decaying oscillation (2.80) "
                f"with omega1 = {o.omega1:.4g} rad/s."
            )
        elif o.regime == "critical":
            out.append("f = omega: critically damped; (2.80) is replaced by (C1 + C2 t) e^(-f t).")
        else:
            out.append(
                f"f = {o.f:.4g} > omega = {o.omega:.4g}: aperiodic transient; (2.80) does not "
                "apply (the source's 'f > omega' is read as f < omega)."
            )
        if o.secular:
            out.append(
                "Undamped resonance: the amplitude grows without bound, "
                "q* = -tau t cos(omega0 t)/(2 omega0)."
            )
        return out

    def notes(self, params: Params) -> list[Note]:
        out = [Note("info", text) for text in self.messages(oscillator_from_params(params))]
        out.append(
            Note(
                "corrected",
                "(2.80) oscillates for f < omega",
                "(2.80)",
                "the source writes 'small resistance (f > omega)'; omega1 = sqrt(omega^2 - f^2) "
                "is real only for f < omega",
            )
        )
        return out

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, np.ndarray]:
        o = oscillator_from_params(params)
        q, v = np.asarray(state, dtype=float).T
        qs, _ = o.particular(t)
        return {
            "q": q,
            "v": v,
            "q_steady": qs,
            "q_transient": q - qs,
            "F_drive": o.F0 * np.sin(o.w0 * t),
            "F_spring": -o.c * q,
            "F_damper": -o.b * v,
        }

    def run_from(self, params: Params, t0: float, state: np.ndarray | None) -> ClosedFormRun:
        """The closed-form response (2.92) from ``state = (q, q')`` at ``t0``."""
        o = oscillator_from_params(params)
        q0, v0 = (float(params["q0"]), float(params["v0"])) if state is None else state
        return ClosedFormRun(lambda t: np.column_stack(o.response(t, q0, v0, t0)))

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        o = oscillator_from_params(params)
        fast = max(o.w0, o.omega, 1e-9)
        n = int(min(200_000, max(2001, 40 * t_end * fast / TWO_PI)))
        t = np.linspace(0.0, t_end, n)
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
        state = self.run_from(params, 0.0, None).state(t)
        return self.result(params, t, state, metrics, self.messages(o))

    def stepper(self, params: Params) -> Stepper:
        return RunStepper.for_lesson(self, params, self.run_from, self._frame)

    def _frame(
        self,
        params: Params,
        t: float,
        state: np.ndarray,
        scalars: dict[str, float] | None = None,
    ) -> Frame:
        o, L = oscillator_from_params(params), self._length(params)
        s = 0.6 * L
        q = float(state[0, 0])
        F = o.F0 * math.sin(o.w0 * t)
        centre = np.array([q, 0.0, s / 2])
        left = centre - np.array([s / 2, 0, 0])
        wall = np.array([-2.5 * L, 0.0, 0.0])
        spring_o = wall + np.array([0, -0.2 * s, 0.7 * s])
        damper_o = wall + np.array([0, 0.2 * s, 0.3 * s])
        F_len = (F / abs(o.F0) if o.F0 else 0.0) * L
        return Frame(
            t=t,
            points={"q(t) trace": np.array([[q, -1.5 * s - 0.25 * L * t, 0.0]])},
            vectors={
                "spring": (spring_o[None, :], (left + [0, -0.2 * s, 0.2 * s] - spring_o)[None, :]),
                "damper": (damper_o[None, :], (left + [0, 0.2 * s, -0.2 * s] - damper_o)[None, :]),
                "force F0 sin(omega0 t)": (
                    (centre + np.array([s / 2, 0, 0]))[None, :],
                    np.array([[F_len, 0.0, 0.0]]),
                ),
            },
            poses={"carriage": (centre, np.array([1.0, 0.0, 0.0, 0.0]))},
            scalars=self.frame_scalars(params, t, state) if scalars is None else scalars,
            message="" if np.isfinite(state).all() else "the state is not finite",
        )

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
            meshes=[mesh_item("wall", wall, (150, 150, 150), 0.7)],
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
                MarkerItem(
                    "omega0 on the characteristic",
                    here,
                    (220, 40, 40),
                    0.05 * L,
                    "ω0 (forcing): amplitude A0",
                ),
                MarkerItem(
                    "omega (natural)",
                    np.array([[-2.5 * L + 5 * L * o.omega / w[-1], 3 * L, 0]]),
                    (40, 40, 220),
                    0.04 * L,
                    "ω (natural)",
                ),
                MarkerItem(
                    "characteristic title",
                    np.array([[-2.5 * L, 3 * L, 1.05 * float(np.max(Ashow))]]),
                    (200, 80, 0),
                    0.001 * L,
                    "steady amplitude A0 over the forcing frequency ω0",
                ),
            ],
            moving_points={"q(t) trace": (40, 120, 40)},
            moving_vectors={
                "spring": (80, 80, 80),
                "damper": (140, 90, 40),
                "force F0 sin(omega0 t)": (220, 40, 40),
            },
            bodies=[mesh_item("carriage", box, (120, 160, 220), 0.6)],
        )

    def derivation(self, params: Params) -> list[DerivationStep]:
        o = oscillator_from_params(params)
        return forced_vibration_steps(o, self.afc_curve(params, 9)[0])

    def claims(self) -> list[Claim]:
        return [
            Claim(
                "lagrange-2-78",
                "Lagrange's equation of the 2nd kind gives m q̈ + c q = -b q̇ + F₀ sin(ω₀t).",
                "(2.78)",
                check_lagrange_forced,
            ),
            Claim(
                "particular-M-N",
                "M, N solving (2.84) are (2.86)/(2.87); they satisfy (2.85); the particular "
                "solution (2.81) leaves residual 0.",
                "(2.81)-(2.87)",
                check_MN,
            ),
            Claim(
                "amplitude-phase",
                "A0 = sqrt(M^2 + N^2) is (2.88); M/N is (2.90); "
                "A0 sin(omega0 t + phi1) = M cos + N sin (2.91).",
                "(2.88)-(2.91)",
                check_amp_phase,
            ),
            Claim(
                "homogeneous-2-80",
                "A e^(-f t) sin(omega1 t + phi0) solves the free equation, with "
                "omega1 = sqrt(omega^2 - f^2) real only for f < omega.",
                "(2.80)",
                check_homogeneous,
            ),
            Claim(
                "illustrative-numbers",
                "m=2, b=0.8, c=50, F0=3, omega0=4: A0 = 0.164094 m, phi1 = -0.175940 rad.",
                "(2.88), (2.90)",
                check_numbers,
            ),
            Claim(
                "phase-quadrant",
                "For omega0 = 7 > omega = 5, atan2(M, N) reproduces q*, plain atan(M/N) does not.",
                "(2.90)-(2.91)",
                check_quadrant,
            ),
            Claim(
                "closed-vs-ivp",
                "The closed form (2.92) (and its critical/aperiodic/undamped-resonance forms) "
                "equals solve_ivp (DOP853, rtol 1e-12) to 1e-8.",
                "(2.92)",
                check_closed_vs_ivp,
            ),
            Claim(
                "form-2-92",
                "(2.92) written with A, phi0 equals the response from q(0), q'(0) to 1e-12.",
                "(2.92)",
                check_form_292,
            ),
            Claim(
                "regimes",
                "f < omega: decaying oscillation (many zero crossings); f > omega: aperiodic "
                "(at most one zero crossing).",
                "(2.80)",
                check_regimes,
            ),
            Claim(
                "resonance-peak",
                "A0(omega0) is largest at sqrt(omega^2 - 2 f^2) = 4.99199 rad/s with "
                "A0 = tau/(2 f omega1) = 0.750601 m (illustrative values).",
                "(2.88)",
                check_peak,
            ),
        ]


LESSON = CarriageForcedVibration()
