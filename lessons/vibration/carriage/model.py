"""Vibrations of the air-bearing carriage: textbook chapter 2, Problems 2.6 and 2.7.

Numerics and symbolic models shared by :mod:`analyzer_lab.lessons.vibration.carriage_free_vibration`,
:mod:`analyzer_lab.lessons.vibration.carriage_forced_vibration` and their derivations and claim checks
(:mod:`analyzer_lab.lessons.vibration.carriage.derivation`, :mod:`analyzer_lab.lessons.vibration.carriage.claims`):

* the 6-DOF carriage (2.38)-(2.44) as ``M q'' + K q = 0`` with
  ``q = (x, y, z, phi_x, phi_y, phi_z)``, its closed-form frequencies (2.50), (2.54),
  (2.66)-(2.72) next to the generalized eigenproblem (``scipy.linalg.eigh``);
* the parallelepiped moments of inertia with Huygens-Steiner (2.73)-(2.77);
* the damped, harmonically forced oscillator (2.78)-(2.92) in closed form, for every
  damping regime, and its amplitude/phase frequency response;
* the Lagrange derivations with ``sympy.physics.mechanics``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg
import sympy as sp
from sympy.physics import mechanics as me

COORDS = ("x", "y", "z", "phi_x", "phi_y", "phi_z")
"""Order of the carriage's generalized coordinates in every vector and matrix here."""


# ---------------------------------------------------------------- carriage: parameters


@dataclass(frozen=True)
class Carriage:
    """Inertia and stiffness of the carriage on its air bearing, (2.39)-(2.40)."""

    m: float
    Ix: float
    Iy: float
    Iz: float
    Cx: float
    Cy: float
    Cz: float
    Kx: float
    Ky: float
    Kz: float
    h: float

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Mass and stiffness matrices of (2.42)-(2.44): ``M q'' + K q = 0``."""
        M = np.diag([self.m, self.m, self.m, self.Ix, self.Iy, self.Iz]).astype(float)
        K = np.diag([self.Cx, self.Cy, self.Cz, self.Kx, self.Ky, self.Kz]).astype(float)
        K[0, 4] = K[4, 0] = self.Cx * self.h  # x <-> phi_y, (2.43)
        K[1, 3] = K[3, 1] = self.Cy * self.h  # y <-> phi_x, (2.44)
        return M, K


def box_inertia(
    m: float, a: float, b: float, H: float, Xc: float = 0.0, Yc: float = 0.0, Zc: float = 0.0
) -> tuple[float, float, float]:
    """(I_x, I_y, I_z) of a solid box, b along X, a along Y, H along Z, by (2.74)-(2.77).

    (2.75) as printed; (2.76)/(2.77) in their corrected form (each moment uses the two
    dimensions perpendicular to its axis; the printed "h" is the height H).
    (Xc, Yc, Zc) is the centre of gravity (2.73) relative to the axes' origin.
    """
    Iz = m * ((a**2 + b**2) / 12.0 + Xc**2 + Yc**2)
    Ix = m * ((a**2 + H**2) / 12.0 + Yc**2 + Zc**2)
    Iy = m * ((b**2 + H**2) / 12.0 + Zc**2 + Xc**2)
    return Ix, Iy, Iz


def box_inertia_printed(
    m: float, a: float, b: float, H: float, Xc: float = 0.0, Yc: float = 0.0, Zc: float = 0.0
) -> tuple[float, float, float]:
    """(2.75)-(2.77) exactly as printed (with "h" read as H): a and b swapped in I_x, I_y."""
    Iz = m * ((a**2 + b**2) / 12.0 + Xc**2 + Yc**2)
    Ix = m * ((H**2 + b**2) / 12.0 + Yc**2 + Zc**2)
    Iy = m * ((H**2 + a**2) / 12.0 + Zc**2 + Xc**2)
    return Ix, Iy, Iz


def centre_of_gravity(weights: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(2.73): X_c = sum P_i X_i / P (and Y_c, Z_c), ``points`` of shape (n, 3)."""
    w = np.asarray(weights, dtype=float)
    return (w[:, None] * np.asarray(points, dtype=float)).sum(axis=0) / w.sum()


# ---------------------------------------------------------------- carriage: frequencies


def coupled_frequency(C: float, K: float, m: float, I: float, h: float, sign: int) -> float:
    """(2.67) (``sign=+1``) and (2.68) (``sign=-1``, with "+" under the inner radical)."""
    a, b = C / m, K / I
    inner = 0.25 * (a - b) ** 2 + C**2 * h**2 / (m * I)
    return math.sqrt(max(0.5 * (a + b) + sign * math.sqrt(inner), 0.0))


def coupled_frequency_as_printed(C: float, K: float, m: float, I: float, h: float) -> float:
    """(2.68) as extracted: "-" in front of C^2 h^2/(m I); NaN where the radicand is negative."""
    a, b = C / m, K / I
    inner = 0.25 * (a - b) ** 2 - C**2 * h**2 / (m * I)
    if inner < 0:
        return float("nan")
    outer = 0.5 * (a + b) - math.sqrt(inner)
    return math.sqrt(outer) if outer >= 0 else float("nan")


MODE_KEYS = ("z", "phi_z", "x-phi_y upper", "x-phi_y lower", "y-phi_x upper", "y-phi_x lower")
"""The six modes in the order of the closed forms: single-coupled (2.42), two-coupled (2.43), (2.44)."""


def closed_form_frequencies(p: Carriage) -> dict[str, float]:
    """The six angular frequencies (rad/s) in closed form, keyed by :data:`MODE_KEYS`.

    z: (2.50) with C_z; phi_z: (2.54) with K_z, I_z; the x-phi_y pair by (2.67)/(2.68);
    the y-phi_x pair by the same formulas with C_y, K_x, I_x (2.71)/(2.72).
    """
    return {
        "z": math.sqrt(p.Cz / p.m),
        "phi_z": math.sqrt(p.Kz / p.Iz),
        "x-phi_y upper": coupled_frequency(p.Cx, p.Ky, p.m, p.Iy, p.h, +1),
        "x-phi_y lower": coupled_frequency(p.Cx, p.Ky, p.m, p.Iy, p.h, -1),
        "y-phi_x upper": coupled_frequency(p.Cy, p.Kx, p.m, p.Ix, p.h, +1),
        "y-phi_x lower": coupled_frequency(p.Cy, p.Kx, p.m, p.Ix, p.h, -1),
    }


def eigen_frequencies(p: Carriage) -> tuple[np.ndarray, np.ndarray]:
    """Angular frequencies (ascending) and M-orthonormal mode shapes (columns) of the
    full model, from the generalized problem ``K phi = omega^2 M phi`` (scipy.linalg.eigh)."""
    M, K = p.matrices()
    lam, vecs = scipy.linalg.eigh(K, M)
    return np.sqrt(np.clip(lam, 0.0, None)), vecs


@dataclass(frozen=True)
class FrequencyTable:
    """The six frequencies of one carriage: closed forms next to the full model."""

    carriage: Carriage
    closed_form: dict[str, float]  # rad/s, keyed by MODE_KEYS
    eig: np.ndarray  # rad/s, ascending, from scipy.linalg.eigh
    max_rel_err: float  # largest relative difference of the sorted closed forms to eig


def frequency_table(p: Carriage) -> FrequencyTable:
    """Closed-form (2.50), (2.54), (2.66)-(2.72) and eigenvalue frequencies of ``p``."""
    cf = closed_form_frequencies(p)
    w_eig, _ = eigen_frequencies(p)
    rel = float(np.max(np.abs(np.sort(np.array(list(cf.values()))) - w_eig) / w_eig))
    return FrequencyTable(p, cf, w_eig, rel)


def mode_shape(p: Carriage, key: str) -> np.ndarray:
    """The normal-mode shape belonging to closed-form frequency ``key`` (6-vector, unit max).

    For a coupled pair the amplitude ratio follows from (2.64):
    A_phi/A_trans = -(C - m w^2)/(C h); with h = 0 the pair decouples.
    """
    w2 = closed_form_frequencies(p)[key] ** 2
    shape = np.zeros(6)
    if key == "z":
        shape[2] = 1.0
        return shape
    if key == "phi_z":
        shape[5] = 1.0
        return shape
    if key.startswith("x"):
        C, K, I, it, ir = p.Cx, p.Ky, p.Iy, 0, 4
    else:
        C, K, I, it, ir = p.Cy, p.Kx, p.Ix, 1, 3
    A = np.array([[C - p.m * w2, C * p.h], [C * p.h, K - I * w2]])
    row = A[0] if np.linalg.norm(A[0]) >= np.linalg.norm(A[1]) else A[1]
    scale = max(abs(C - p.m * w2), abs(K - I * w2), abs(C * p.h), 1e-300)
    if np.linalg.norm(row) <= 1e-12 * scale:  # repeated root with h = 0: any combination
        vec = np.array([1.0, 0.0]) if key.endswith("upper") else np.array([0.0, 1.0])
    else:
        vec = np.array([-row[1], row[0]])
    shape[it], shape[ir] = vec
    return shape / np.max(np.abs(shape))


def mode_character(p: Carriage, key: str) -> str:
    """ "translation" or "rotation": which part carries more kinetic energy in the mode."""
    s = mode_shape(p, key)
    M, _ = p.matrices()
    e = M.diagonal() * s**2
    return "translation" if e[:3].sum() >= e[3:].sum() else "rotation"


class ModalResponse:
    """The free response of (2.42)-(2.44) from the state (q, v), by modal superposition:
    the modes and the modal coordinates are computed once, ``at(dt)`` only propagates."""

    def __init__(self, p: Carriage, q: np.ndarray, v: np.ndarray) -> None:
        M, _ = p.matrices()
        self.w, self.Phi = eigen_frequencies(p)
        self.eta0 = self.Phi.T @ M @ np.asarray(q, dtype=float)
        self.deta0 = self.Phi.T @ M @ np.asarray(v, dtype=float)
        self._safe_w = np.where(self.w > 0, self.w, 1.0)

    def at(self, dt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) after the times ``dt`` (1-D): shapes ``(len(dt), 6)``."""
        w = self.w
        s = np.asarray(dt, dtype=float)[:, None]
        wt = w[None, :] * s
        sin, cos = np.sin(wt), np.cos(wt)
        sinc = np.where(w[None, :] > 0, sin / self._safe_w[None, :], s)
        eta = self.eta0 * cos + self.deta0 * sinc
        deta = -self.eta0 * w * sin + self.deta0 * cos
        return eta @ self.Phi.T, deta @ self.Phi.T


def modal_propagate(
    p: Carriage, q: np.ndarray, v: np.ndarray, dt: float | np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Exact free response of (2.42)-(2.44) after ``dt`` from state (q, v), by modal
    superposition.  ``dt`` may be an array (then the results have shape (len(dt), 6))."""
    qs, vs = ModalResponse(p, q, v).at(np.atleast_1d(np.asarray(dt, dtype=float)))
    if np.ndim(dt) == 0:
        return qs[0], vs[0]
    return qs, vs


def jeffcott_deflection(m: float, e: float, c: float, w: float) -> float:
    """(2.48), reconstructed: z = m e w^2 / (c - m w^2), from c z = m w^2 (e + z)."""
    return m * e * w**2 / (c - m * w**2)


def rotvec_to_quaternion(r: np.ndarray) -> np.ndarray:
    """wxyz quaternion of the rotation vector ``r`` (the small angles phi_x, phi_y, phi_z)."""
    r = np.asarray(r, dtype=float)
    angle = float(np.linalg.norm(r))
    if angle < 1e-12:
        return np.array([1.0, 0.5 * r[0], 0.5 * r[1], 0.5 * r[2]]) / math.sqrt(
            1.0 + 0.25 * angle**2
        )
    axis = r / angle
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])


def small_rotation_matrix(r: np.ndarray) -> np.ndarray:
    """Rotation matrix of the rotation vector ``r`` (Rodrigues)."""
    r = np.asarray(r, dtype=float)
    angle = float(np.linalg.norm(r))
    if angle < 1e-15:
        return np.eye(3)
    k = r / angle
    Kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * Kx + (1 - math.cos(angle)) * Kx @ Kx


# ---------------------------------------------------------------- carriage: symbolic


@dataclass(frozen=True)
class CarriageSymbols:
    t: sp.Symbol
    q: tuple[sp.Function, ...]
    m: sp.Symbol
    I: tuple[sp.Symbol, sp.Symbol, sp.Symbol]
    C: tuple[sp.Symbol, sp.Symbol, sp.Symbol]
    K: tuple[sp.Symbol, sp.Symbol, sp.Symbol]
    h: sp.Symbol
    E: sp.Expr
    W: sp.Expr
    equations: tuple[sp.Expr, ...]  # LagrangesMethod, in COORDS order, "= 0"


@lru_cache(maxsize=1)
def carriage_lagrange() -> CarriageSymbols:
    """(2.39)-(2.44): E, W and the six Lagrange equations via sympy.physics.mechanics."""
    t = me.dynamicsymbols._t
    q = me.dynamicsymbols("x y z phi_x phi_y phi_z")
    m, h = sp.symbols("m h", positive=True)
    Ix, Iy, Iz = sp.symbols("I_x I_y I_z", positive=True)
    Cx, Cy, Cz = sp.symbols("C_x C_y C_z", positive=True)
    Kx, Ky, Kz = sp.symbols("K_x K_y K_z", positive=True)
    x, y, z, px, py, pz = q
    qd = [sp.diff(c, t) for c in q]
    E = sp.Rational(1, 2) * (
        m * qd[0] ** 2
        + m * qd[1] ** 2
        + m * qd[2] ** 2
        + Ix * qd[3] ** 2
        + Iy * qd[4] ** 2
        + Iz * qd[5] ** 2
    )
    W = sp.Rational(1, 2) * (
        Cx * x**2
        + Cy * y**2
        + Cz * z**2
        + Kx * px**2
        + Ky * py**2
        + Kz * pz**2
        + 2 * Cx * h * x * py
        + 2 * Cy * h * y * px
    )
    lm = me.LagrangesMethod(E - W, list(q))
    eqs = tuple(sp.expand(e) for e in lm.form_lagranges_equations())
    return CarriageSymbols(t, tuple(q), m, (Ix, Iy, Iz), (Cx, Cy, Cz), (Kx, Ky, Kz), h, E, W, eqs)


def carriage_source_equations() -> tuple[sp.Expr, ...]:
    """(2.42)-(2.44) as printed, in COORDS order, left-hand sides of "= 0"."""
    s = carriage_lagrange()
    t = s.t
    x, y, z, px, py, pz = s.q
    Ix, Iy, Iz = s.I
    Cx, Cy, Cz = s.C
    Kx, Ky, Kz = s.K
    m, h = s.m, s.h
    d2 = lambda f: sp.diff(f, t, 2)  # noqa: E731
    return (
        m * d2(x) + Cx * x + Cx * h * py,
        m * d2(y) + Cy * y + Cy * h * px,
        m * d2(z) + Cz * z,
        Ix * d2(px) + Kx * px + Cy * h * y,
        Iy * d2(py) + Ky * py + Cx * h * x,
        Iz * d2(pz) + Kz * pz,
    )


# ---------------------------------------------------------------- forced oscillator (2.7)


@dataclass(frozen=True)
class ForcedOscillator:
    """m q'' + b q' + c q = F0 sin(w0 t), (2.78); normalized form (2.79)."""

    m: float
    b: float
    c: float
    F0: float
    w0: float

    @property
    def f(self) -> float:
        """Damping factor f = b/(2m) of (2.79) (not a frequency)."""
        return self.b / (2.0 * self.m)

    @property
    def omega(self) -> float:
        """Natural angular frequency, omega^2 = c/m."""
        return math.sqrt(self.c / self.m)

    @property
    def tau(self) -> float:
        return self.F0 / self.m

    @property
    def omega1(self) -> float:
        """Damped frequency of (2.80), sqrt(omega^2 - f^2); NaN unless f < omega."""
        d = self.omega**2 - self.f**2
        return math.sqrt(d) if d > 0 else float("nan")

    @property
    def regime(self) -> str:
        d = self.omega**2 - self.f**2
        scale = max(self.omega**2, self.f**2, 1e-300)
        if abs(d) <= 1e-12 * scale:
            return "critical"
        return "underdamped" if d > 0 else "overdamped"

    @property
    def secular(self) -> bool:
        """Undamped resonance (f = 0, w0 = omega): no bounded particular solution (2.81)."""
        return (
            self.f == 0.0
            and self.w0 > 0
            and self.F0 != 0
            and math.isclose(self.w0, self.omega, rel_tol=1e-12)
        )

    def _den(self) -> float:
        return (self.omega**2 - self.w0**2) ** 2 + 4 * self.f**2 * self.w0**2

    @property
    def MN(self) -> tuple[float, float]:
        """(M, N) of (2.86)/(2.87); (0, 0) without forcing or at undamped resonance."""
        if self.F0 == 0 or self.w0 == 0 or self.secular:
            return 0.0, 0.0
        den = self._den()
        return -2 * self.f * self.w0 * self.tau / den, self.tau * (self.omega**2 - self.w0**2) / den

    @property
    def A0(self) -> float:
        """Steady amplitude (2.88) (infinite at undamped resonance)."""
        if self.secular:
            return float("inf")
        M, N = self.MN
        return math.hypot(M, N)

    @property
    def phi1(self) -> float:
        """Phase of (2.91): atan2(M, N), in (-pi, 0] (tan phi1 = M/N of (2.90))."""
        M, N = self.MN
        return math.atan2(M, N)

    def particular(self, t: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """q*(t), q*'(t): (2.81)/(2.91); -tau t cos(w0 t)/(2 w0) at undamped resonance."""
        t = np.asarray(t, dtype=float)
        w0 = self.w0
        if self.secular:
            q = -self.tau * t * np.cos(w0 * t) / (2 * w0)
            v = -self.tau * np.cos(w0 * t) / (2 * w0) + self.tau * t * np.sin(w0 * t) / 2
            return q, v
        M, N = self.MN
        return M * np.cos(w0 * t) + N * np.sin(w0 * t), -M * w0 * np.sin(w0 * t) + N * w0 * np.cos(
            w0 * t
        )

    def homogeneous(
        self, s: np.ndarray | float, dq: float, dv: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Free solution q0 of (2.79) after time s with q0(0) = dq, q0'(0) = dv.

        f < omega: (2.80) A e^{-f s} sin(omega1 s + phi0); f = omega and f > omega: the
        critically damped and aperiodic forms.  Written through e^{-fs}(dq ch + (dv + f dq) sh)
        with ch, sh the cos/cosh-like and sin/sinh-like kernels, which stays exact across regimes.
        """
        s = np.asarray(s, dtype=float)
        f = self.f
        d = self.omega**2 - f**2
        reg = self.regime
        if reg == "underdamped":
            g = math.sqrt(d)
            decay = np.exp(-f * s)
            ch, sh = decay * np.cos(g * s), decay * np.sin(g * s) / g
        elif reg == "critical":
            decay = np.exp(-f * s)
            ch, sh = decay, decay * s
            d = 0.0
        else:
            g = math.sqrt(-d)
            e1, e2 = np.exp((g - f) * s), np.exp(-(g + f) * s)
            ch, sh = 0.5 * (e1 + e2), 0.5 * (e1 - e2) / g
        k = dv + f * dq
        q = dq * ch + k * sh
        v = dq * (-d * sh) + k * ch - f * q
        return q, v

    def amplitude_phase_constants(self, q0: float, v0: float) -> tuple[float, float]:
        """A and phi0 of (2.80)/(2.92) from q(0), q'(0) (f < omega): A sin phi0 = q0 - M,
        A cos phi0 = (v0 - N w0 + f (q0 - M))/omega1."""
        M, N = self.MN
        s_, c_ = q0 - M, (v0 - N * self.w0 + self.f * (q0 - M)) / self.omega1
        return math.hypot(s_, c_), math.atan2(s_, c_)

    def response(
        self, t: np.ndarray | float, q0: float, v0: float, t0: float = 0.0
    ) -> tuple[np.ndarray, np.ndarray]:
        """q(t), q'(t) = homogeneous + particular (2.92), with q(t0) = q0, q'(t0) = v0."""
        qp0, vp0 = self.particular(t0)
        qh, vh = self.homogeneous(np.asarray(t, dtype=float) - t0, q0 - float(qp0), v0 - float(vp0))
        qp, vp = self.particular(t)
        return qh + qp, vh + vp

    def response_292(self, t: np.ndarray, q0: float, v0: float) -> np.ndarray:
        """(2.92) literally: A e^(-f t) sin(omega1 t + phi0) + A0 sin(w0 t + phi1) (f < omega)."""
        A, ph0 = self.amplitude_phase_constants(q0, v0)
        return A * np.exp(-self.f * t) * np.sin(self.omega1 * t + ph0) + self.A0 * np.sin(
            self.w0 * t + self.phi1
        )

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        return np.array(
            [y[1], (self.F0 * math.sin(self.w0 * t) - self.b * y[1] - self.c * y[0]) / self.m]
        )

    @property
    def peak_frequency(self) -> float:
        """w0 of the amplitude maximum, sqrt(omega^2 - 2 f^2) (NaN if omega^2 <= 2 f^2)."""
        d = self.omega**2 - 2 * self.f**2
        return math.sqrt(d) if d > 0 else float("nan")

    @property
    def peak_amplitude(self) -> float:
        """A0 at the peak: tau / (2 f sqrt(omega^2 - f^2)); tau/omega^2 if there is no peak."""
        if not (self.omega**2 > 2 * self.f**2):
            return self.tau / self.omega**2 if self.omega > 0 else float("inf")
        if self.f == 0:
            return float("inf")
        return self.tau / (2 * self.f * math.sqrt(self.omega**2 - self.f**2))


def frequency_response(
    m: float, b: float, c: float, F0: float, w0: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude-frequency and phase-frequency characteristics: A0(w0) (2.88) and
    phi1(w0) = atan2(M, N) (2.90), as plain arrays over the array ``w0``."""
    w0 = np.asarray(w0, dtype=float)
    f, om2, tau = b / (2 * m), c / m, F0 / m
    den = (om2 - w0**2) ** 2 + 4 * f**2 * w0**2
    with np.errstate(divide="ignore", invalid="ignore"):
        A0 = tau / np.sqrt(den)
        phase = np.arctan2(-2 * f * w0 * tau, tau * (om2 - w0**2))
    return A0, phase


# ---------------------------------------------------------------- forced oscillator: symbolic


@dataclass(frozen=True)
class ForcedSymbols:
    t: sp.Symbol
    q: sp.Function
    m: sp.Symbol
    b: sp.Symbol
    c: sp.Symbol
    F0: sp.Symbol
    w0: sp.Symbol
    f: sp.Symbol
    omega: sp.Symbol
    tau: sp.Symbol
    lagrange: sp.Eq  # (2.78) from LagrangesMethod
    M: sp.Expr  # (2.86)
    N: sp.Expr  # (2.87)


@lru_cache(maxsize=1)
def forced_lagrange() -> ForcedSymbols:
    """(2.78) via LagrangesMethod (L = E - W, generalized force -b q' + F0 sin w0 t) and
    the particular-solution constants (2.84)-(2.87) by sympy.solve."""
    t = me.dynamicsymbols._t
    q = me.dynamicsymbols("q")
    m, b, c, F0, w0 = sp.symbols("m b c F_0 omega_0", positive=True)
    f, omega, tau = sp.symbols("f omega tau", positive=True)
    N_frame = me.ReferenceFrame("N")
    P = me.Point("P")
    P.set_vel(N_frame, sp.diff(q, t) * N_frame.x)
    body = me.Particle("carriage", P, m)
    body.potential_energy = sp.Rational(1, 2) * c * q**2
    L = me.Lagrangian(N_frame, body)
    lm = me.LagrangesMethod(
        L,
        [q],
        forcelist=[(P, (-b * sp.diff(q, t) + F0 * sp.sin(w0 * t)) * N_frame.x)],
        frame=N_frame,
    )
    eq = lm.form_lagranges_equations()[0]
    Ms, Ns = sp.symbols("M N")
    sol = sp.solve(
        [
            -Ms * w0**2 + 2 * f * Ns * w0 + omega**2 * Ms,
            -Ns * w0**2 - 2 * f * Ms * w0 + omega**2 * Ns - tau,
        ],
        [Ms, Ns],
        dict=True,
    )[0]
    return ForcedSymbols(
        t, q, m, b, c, F0, w0, f, omega, tau, sp.Eq(eq, 0), sp.factor(sol[Ms]), sp.factor(sol[Ns])
    )
