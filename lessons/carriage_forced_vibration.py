"""Forced vibration of the air-bearing carriage along one axis.

Textbook §2.3, Problem 2.7, eqs (2.78)-(2.92): m q'' + b q' + c q = F0 sin(w0 t), the
transient plus steady response in closed form (:class:`lessons.core.vibration.ForcedOscillator`),
amplitude and phase against the forcing frequency, resonance.  The source gives no
numbers for m, b, c, F0, w0: the defaults are illustrative, said so in the preset notes.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp
import trimesh
from scipy.integrate import solve_ivp

from lessons.core.bodies import mesh_item
from lessons.core.contract import (
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
    at_most,
    close,
)
from lessons.core.dense_solution import ClosedFormRun, RunStepper
from lessons.core.vibration import ForcedOscillator, forced_lagrange, frequency_response

TWO_PI = 2.0 * math.pi


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
    sampling = 0.01
    groups = (
        Group("carriage", "Carriage"),
        Group("bearing", "Air bearing"),
        Group("forcing", "Forcing"),
        Group("initial", "Start state"),
    )
    series = (
        Series("q", "m", "coordinate of the carriage (2.92)"),
        Series("v", "m/s", "velocity q'"),
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
        return RunStepper(self.run_from, self._frame, params)

    def _frame(self, params: Params, t: float, state: np.ndarray) -> Frame:
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
            scalars=self.frame_scalars(params, t, state),
            message="" if np.all(np.isfinite(state)) else "the state is not finite",
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
            bodies=[mesh_item("carriage", box, (120, 160, 220), 0.6)],
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
    f, om, tau, w0 = S.f, S.omega, S.tau, S.w0
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


LESSON = CarriageForcedVibration()
