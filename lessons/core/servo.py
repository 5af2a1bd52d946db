"""Two-coordinate servo systems with program control (Leppik 1960, eqs (1)-(35)).

The programming device (PU) of the article is a linear ODE system that produces the
programmed coordinates x = f1(t), y = f2(t); each coordinate drives a linear servo
channel (2):

    (T2^2 s^2 + T1 s + 1) x1 = x,

so PU + both channels form one autonomous linear system dz/dt = M z.  It is advanced
*exactly* by the state-space discretization of :func:`scipy.signal.cont2discrete`
(zero-order hold of a zero input = the matrix exponential).  The channels are
:class:`scipy.signal.StateSpace` models in physical coordinates (x1, dx1/dt).

Program correction (7), (21)-(22), (31)-(34) is one rule for every PU: feed each
channel with (T2^2 s^2 + T1 s + 1) applied to the programmed coordinate.  Because the
PU is linear (dz/dt = A z, x = Cx z), that input is the output map
Cx (I + T1 A + T2^2 A^2) of the same PU, which is the article's "modified initial
conditions" (and, for non-identical channels, its extra constant input).

Signed contour errors follow the article: positive inside a closed/convex curve (and
above a cubic), so (13) and (28) come out negative when the output lies outside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy import signal

Correction = Literal["off", "on", "derivative"]

# ---------------------------------------------------------------- servo channel


@dataclass(frozen=True)
class Channel:
    """One servo channel (2): (T2^2 s^2 + T1 s + 1) x1 = x."""

    T1: float
    T2sq: float

    @classmethod
    def from_open_loop(cls, k: float, T: float) -> Channel:
        """Closed loop of W(s) = k/((Ts+1)s): T2^2 = T/k, T1 = 1/k."""
        return cls(T1=1.0 / k, T2sq=T / k)

    def scaled(self, gamma: float) -> Channel:
        """The non-identical channel of the article: T1y = gamma T1, T2y^2 = gamma T2^2."""
        return Channel(T1=gamma * self.T1, T2sq=gamma * self.T2sq)

    def state_space(self) -> signal.StateSpace:
        """State (x1, dx1/dt), input x, output x1."""
        a = np.array([[0.0, 1.0], [-1.0 / self.T2sq, -self.T1 / self.T2sq]])
        b = np.array([[0.0], [1.0 / self.T2sq]])
        c = np.array([[1.0, 0.0]])
        return signal.StateSpace(a, b, c, np.zeros((1, 1)))

    def transfer_function(self) -> signal.TransferFunction:
        return signal.TransferFunction([1.0], [self.T2sq, self.T1, 1.0])

    def response(self, omega: float) -> complex:
        """Phi(j omega) = 1/(1 - T2^2 omega^2 + j T1 omega)."""
        return 1.0 / complex(1.0 - self.T2sq * omega**2, self.T1 * omega)

    def roots(self) -> tuple[complex, complex]:
        """alpha_1, alpha_2: roots of T2^2 a^2 + T1 a + 1 = 0."""
        r = np.roots([self.T2sq, self.T1, 1.0])
        return complex(r[0]), complex(r[1])

    def decay_rate(self) -> float:
        """Slowest decay rate min |Re alpha| [1/s] (0 for an undamped channel)."""
        return float(min(-a.real for a in self.roots()))

    @property
    def zeta(self) -> float:
        return self.T1 / (2.0 * math.sqrt(self.T2sq))

    def inverse_poly(self, A: np.ndarray) -> np.ndarray:
        """I + T1 A + T2^2 A^2: the channel's inverse applied to a PU with matrix A."""
        n = A.shape[0]
        return np.eye(n) + self.T1 * A + self.T2sq * (A @ A)


# ---------------------------------------------------------------- programming devices


@dataclass
class Program:
    """A programming device: dz/dt = A z, x = Cx z, y = Cy z (z contains a constant 1)."""

    kind: str
    A: np.ndarray
    z0: np.ndarray
    Cx: np.ndarray
    Cy: np.ndarray
    info: dict[str, float] = field(default_factory=dict)


def line_program(x0: float, y0: float, v: float, angle_deg: float) -> Program:
    """(1): x = x0 + omega yc t, y = y0 + omega xc t, with omega yc = v cos(angle), omega xc = v sin(angle)."""
    th = math.radians(angle_deg)
    A = np.zeros((3, 3))
    A[0, 2] = v * math.cos(th)
    A[1, 2] = v * math.sin(th)
    return Program(
        "line",
        A,
        np.array([x0, y0, 1.0]),
        np.array([1.0, 0, 0]),
        np.array([0, 1.0, 0]),
        {"vx": v * math.cos(th), "vy": v * math.sin(th)},
    )


def power_program(n: int, x0: float, xc: float, yc: float, p: float, omega: float) -> Program:
    """Parabola of degree n about the vertex/inflection (xc, yc): y - yc = (x - xc)^n / p.

    n = 2 is the article's PU (9): dx/dt = omega p/2, dy/dt = omega (x - xc).  For n = 3, 4
    (Fig. 7, not described in the article) the PU is an integrator chain producing
    x - xc = omega p tau, y - yc = omega^n p^(n-1) tau^n (tau = t + tau0), as in the article.
    """
    if n == 2:
        A = np.zeros((3, 3))
        A[0, 2] = omega * p / 2.0
        A[1, 0] = omega
        A[1, 2] = -omega * xc
        y0 = yc + (x0 - xc) ** 2 / p
        return Program(
            "parabola",
            A,
            np.array([x0, y0, 1.0]),
            np.array([1.0, 0, 0]),
            np.array([0, 1.0, 0]),
            {"vertex_x": xc, "vertex_y": yc},
        )
    if n not in (3, 4):
        raise ValueError("degree must be 2, 3 or 4")
    # z = (x, y, y', ..., y^(n-1), 1)
    dim = n + 2
    A = np.zeros((dim, dim))
    A[0, dim - 1] = omega * p
    for i in range(1, n):
        A[i, i + 1] = 1.0
    A[n, dim - 1] = math.factorial(n) * omega**n * p ** (n - 1)
    tau0 = (x0 - xc) / (omega * p)
    c = omega**n * p ** (n - 1)
    z0 = np.zeros(dim)
    z0[0] = x0
    for j in range(n):  # y^(j)(tau0)
        z0[1 + j] = (yc if j == 0 else 0.0) + c * math.factorial(n) / math.factorial(
            n - j
        ) * tau0 ** (n - j)
    z0[dim - 1] = 1.0
    Cx = np.zeros(dim)
    Cx[0] = 1.0
    Cy = np.zeros(dim)
    Cy[1] = 1.0
    return Program(
        "cubic" if n == 3 else "quartic", A, z0, Cx, Cy, {"vertex_x": xc, "vertex_y": yc}
    )


def ellipse_program(
    x0: float, y0: float, xc: float, yc: float, a: float, b: float, omega: float
) -> Program:
    """PU of the ellipse (I.6) / circle (26) (a = b): dx/dt = omega (a/b)(y - yc), dy/dt = -omega (b/a)(x - xc)."""
    A = np.zeros((3, 3))
    A[0, 1] = omega * a / b
    A[0, 2] = -omega * a / b * yc
    A[1, 0] = -omega * b / a
    A[1, 2] = omega * b / a * xc
    return Program(
        "ellipse" if a != b else "circle",
        A,
        np.array([x0, y0, 1.0]),
        np.array([1.0, 0, 0]),
        np.array([0, 1.0, 0]),
        {"xc": xc, "yc": yc},
    )


# ---------------------------------------------------------------- the two-axis system


class TwoAxisServo:
    """PU + x channel + y channel as one autonomous linear system, advanced exactly.

    State: z = (PU state, x1, dx1/dt, y1, dy1/dt).  ``correction``: ``off`` feeds the
    programmed coordinates; ``on`` feeds (T2^2 s^2 + T1 s + 1) x (the program correction);
    ``derivative`` feeds x + T1 dx/dt (the paper's concluding counter-example).
    """

    def __init__(
        self, program: Program, cx: Channel, cy: Channel, correction: Correction = "off"
    ) -> None:
        self.program = program
        self.cx = cx
        self.cy = cy
        self.correction = correction
        A = program.A
        n = A.shape[0]
        self.n = n
        self.Kx = self._input_map(program.Cx, cx, correction)
        self.Ky = self._input_map(program.Cy, cy, correction)
        ssx, ssy = cx.state_space(), cy.state_space()
        M = np.zeros((n + 4, n + 4))
        M[:n, :n] = A
        M[n : n + 2, n : n + 2] = ssx.A
        M[n : n + 2, :n] = ssx.B @ self.Kx[None, :]
        M[n + 2 :, n + 2 :] = ssy.A
        M[n + 2 :, :n] = ssy.B @ self.Ky[None, :]
        self.M = M
        # steady state: x1_ss = Kx (I + T1 A + T2^2 A^2)^-1 z_pu
        self.Sx = np.linalg.solve(cx.inverse_poly(A).T, self.Kx)
        self.Sy = np.linalg.solve(cy.inverse_poly(A).T, self.Ky)
        self._cache: dict[float, np.ndarray] = {}

    def _input_map(self, C: np.ndarray, ch: Channel, correction: Correction) -> np.ndarray:
        A = self.program.A
        if correction == "on":
            return ch.inverse_poly(A).T @ C
        if correction == "derivative":
            return (np.eye(A.shape[0]) + ch.T1 * A).T @ C
        return C.copy()

    def initial_state(self, xdot0: float = 0.0, ydot0: float = 0.0) -> np.ndarray:
        """Servo outputs start at the programmed start point (x0, y0) with velocities xdot0, ydot0."""
        z0 = self.program.z0
        return np.concatenate([z0, [self.program.Cx @ z0, xdot0, self.program.Cy @ z0, ydot0]])

    def transition(self, dt: float) -> np.ndarray:
        """Exact step matrix exp(M dt) (scipy.signal.cont2discrete, zero-order hold)."""
        key = float(dt)
        m = self._cache.get(key)
        if m is None:
            dim = self.M.shape[0]
            ad, *_ = signal.cont2discrete(
                (self.M, np.zeros((dim, 1)), np.eye(dim), np.zeros((dim, 1))), key, method="zoh"
            )
            m = np.asarray(ad)
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[key] = m
        return m

    def run(self, t: np.ndarray, z0: np.ndarray) -> np.ndarray:
        """States at the (uniform) times t, starting from z0 at t[0]; shape (len(t), dim)."""
        t = np.asarray(t, dtype=float)
        out = np.empty((len(t), len(z0)))
        out[0] = z0
        if len(t) < 2:
            return out
        dts = np.diff(t)
        uniform = np.allclose(dts, dts[0], rtol=1e-9, atol=0.0)
        z = np.array(z0, dtype=float)
        phi = self.transition(float(dts[0])) if uniform else None
        for i in range(1, len(t)):
            step = phi if phi is not None else self.transition(float(dts[i - 1]))
            z = step @ z
            out[i] = z
        return out

    def outputs(self, Z: np.ndarray) -> dict[str, np.ndarray]:
        """Programmed x, y; channel inputs ux, uy; outputs x1, y1; steady outputs x1ss, y1ss."""
        Z = np.atleast_2d(Z)
        n = self.n
        zp = Z[:, :n]
        return {
            "x": zp @ self.program.Cx,
            "y": zp @ self.program.Cy,
            "ux": zp @ self.Kx,
            "uy": zp @ self.Ky,
            "x1": Z[:, n],
            "y1": Z[:, n + 2],
            "x1dot": Z[:, n + 1],
            "y1dot": Z[:, n + 3],
            "x1ss": zp @ self.Sx,
            "y1ss": zp @ self.Sy,
        }

    def decay_rate(self) -> float:
        return min(self.cx.decay_rate(), self.cy.decay_rate())


# ---------------------------------------------------------------- contour distance


def line_distance(
    xq: np.ndarray, yq: np.ndarray, px: np.ndarray, py: np.ndarray, angle_deg: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signed distance of (xq, yq) from the line through (px, py) at ``angle``; sign as in (5)."""
    th = math.radians(angle_deg)
    c, s = math.cos(th), math.sin(th)
    dx, dy = np.asarray(xq) - px, np.asarray(yq) - py
    d = dx * s - dy * c
    along = dx * c + dy * s
    return d, px + along * c, py + along * s


def power_distance(
    xq: np.ndarray,
    yq: np.ndarray,
    n: int,
    xc: float,
    yc: float,
    p: float,
    guess: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signed normal distance from y = yc + (x - xc)^n / p (+ above); foot points."""
    xq = np.atleast_1d(np.asarray(xq, dtype=float))
    yq = np.atleast_1d(np.asarray(yq, dtype=float))
    xq, yq = np.broadcast_arrays(xq, yq)

    def f(u: np.ndarray) -> np.ndarray:
        return yc + (u - xc) ** n / p

    def best(u0: np.ndarray) -> np.ndarray:
        u = np.broadcast_to(u0, xq.shape).copy()
        active = np.arange(u.size)
        ycb = np.broadcast_to(np.asarray(yc, dtype=float), xq.shape)
        for _ in range(60):
            ua, xa, ya = u[active], xq[active], yq[active]
            w = ua - xc
            wn2 = w ** (n - 2)
            fu = ycb[active] + wn2 * w * w / p
            f1 = n * wn2 * w / p
            f2 = n * (n - 1) * wn2 / p
            g = (ua - xa) + (fu - ya) * f1
            base = 1.0 + f1 * f1
            h = base + (fu - ya) * f2
            h = np.where(h > 0.1 * base, h, base)
            du = g / h
            u[active] = ua - du
            keep = ~(np.abs(du) <= 1e-13 * (1.0 + np.abs(ua)))
            active = active[keep]
            if active.size == 0:
                break
        return u

    cands = [best(xq)]
    if guess is not None:
        cands.append(best(np.atleast_1d(np.asarray(guess, dtype=float))))
    dist = [np.hypot(u - xq, f(u) - yq) for u in cands]
    pick = np.argmin(np.vstack(dist), axis=0)
    u = np.choose(pick, cands)
    d = np.choose(pick, dist)
    sign = np.where(yq >= f(xq), 1.0, -1.0)
    return sign * d, u, f(u)


def ellipse_distance(
    xq: np.ndarray, yq: np.ndarray, xc: float, yc: float, a: float, b: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signed normal distance from the ellipse (x-xc)^2/a^2 + (y-yc)^2/b^2 = 1 (+ inside); foot points."""
    X = np.atleast_1d(np.asarray(xq, dtype=float)) - xc
    Y = np.atleast_1d(np.asarray(yq, dtype=float)) - yc
    if a == b:
        r = np.hypot(X, Y)
        safe = np.where(r > 0, r, 1.0)
        fx = np.where(r > 0, X / safe * a, a)
        fy = np.where(r > 0, Y / safe * a, 0.0)
        return a - r, xc + fx, yc + fy
    th = np.arctan2(Y * a, X * b)
    for _ in range(60):
        c, s = np.cos(th), np.sin(th)
        ex, ey = a * c - X, b * s - Y
        g = -ex * a * s + ey * b * c
        h = (a * s) ** 2 + (b * c) ** 2 - ex * a * c - ey * b * s
        h = np.where(h > 0.1 * ((a * s) ** 2 + (b * c) ** 2), h, (a * s) ** 2 + (b * c) ** 2)
        dth = g / h
        th = th - dth
        if np.all(np.abs(dth) < 1e-14):
            break
    fx, fy = a * np.cos(th), b * np.sin(th)
    d = np.hypot(fx - X, fy - Y)
    inside = (X / a) ** 2 + (Y / b) ** 2 < 1.0
    return np.where(inside, d, -d), xc + fx, yc + fy


def fit_centred_ellipse(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """Least-squares centred conic A x^2 + 2B xy + C y^2 = 1 -> (major, minor, major-axis angle [deg] in [0, 180))."""
    G = np.column_stack([x * x, 2 * x * y, y * y])
    coef, *_ = np.linalg.lstsq(G, np.ones_like(x), rcond=None)
    Q = np.array([[coef[0], coef[1]], [coef[1], coef[2]]])
    lam, vec = np.linalg.eigh(Q)
    if not lam[0] > 0:  # not an ellipse (e.g. samples still in the transient)
        return math.nan, math.nan, math.nan
    major = 1.0 / math.sqrt(lam[0])
    minor = 1.0 / math.sqrt(lam[1])
    ang = math.degrees(math.atan2(vec[1, 0], vec[0, 0])) % 180.0
    return major, minor, ang


# ---------------------------------------------------------------- closed forms of the article


def f_transient(t: np.ndarray, ch: Channel) -> np.ndarray:
    """f(t) = (e^{a1 t} - e^{a2 t})/(a1 - a2) (the transient shape in (4), (8), (24)); real-valued."""
    a1, a2 = ch.roots()
    t = np.asarray(t, dtype=float)
    if abs(a1 - a2) < 1e-12 * (abs(a1) + abs(a2)):
        return (t * np.exp(a1.real * t)).real
    return ((np.exp(a1 * t) - np.exp(a2 * t)) / (a1 - a2)).real


def delta_line_5(v: float, angle_deg: float, T1: float, gamma: float) -> float:
    """(5)/(6): delta = v xc yc T1 (gamma - 1)/(xc^2 + yc^2) with (yc, xc) ~ (cos, sin) of the angle."""
    th = math.radians(angle_deg)
    return v * math.sin(th) * math.cos(th) * T1 * (gamma - 1.0)


def delta_parabola_13(omega: float, p: float, T1: float, T2sq: float) -> float:
    """(13): delta_max = omega^2 p/4 (T1^2 - 2 T2^2)."""
    return omega**2 * p / 4.0 * (T1**2 - 2.0 * T2sq)


def parabola_vertex_17(
    omega: float, p: float, T1: float, T2sq: float, gamma: float
) -> tuple[float, float]:
    """Vertex of the output parabola (17) relative to the programmed vertex."""
    return (
        -omega * p * T1 * (1.0 - gamma) / 2.0,
        omega**2 * p / 4.0 * (gamma**2 * T1**2 - 2.0 * gamma * T2sq),
    )


def circle_axes_29_30(
    m: float, n: float, dphi: float, printed: bool = False
) -> tuple[float, float, float]:
    """(29) tilt alpha [deg] of the major axis and (30) semi-axes (major, minor).

    Corrected (30): numerator cos^2(phi2 - phi1); ``printed=True`` uses the printed cos.
    (29) fixes the axes modulo 90 deg; the major one is picked from the quadratic form.
    """
    num = math.cos(dphi) if printed else math.cos(dphi) ** 2
    s = (m * m + n * n) / (2 * m * m * n * n)
    r = math.sqrt(
        max((m * m + n * n) ** 2 / (4 * m**4 * n**4) - math.cos(dphi) ** 2 / (m * m * n * n), 0.0)
    )
    major = math.sqrt(num / (s - r)) if s - r > 0 and num >= 0 else math.nan
    minor = math.sqrt(num / (s + r)) if num >= 0 else math.nan  # the printed cos can be negative
    # (29): ctg 2 alpha = (n^2 - m^2)/(2 m n sin(dphi))
    two_alpha = math.atan2(2 * m * n * math.sin(dphi), n * n - m * m)
    alpha = math.degrees(two_alpha / 2.0)
    Q = np.array([[1 / m**2, math.sin(dphi) / (m * n)], [math.sin(dphi) / (m * n), 1 / n**2]])
    u = np.array([math.cos(math.radians(alpha)), math.sin(math.radians(alpha))])
    lam = float(u @ Q @ u)
    lam_min = float(np.linalg.eigvalsh(Q)[0])
    if abs(lam - lam_min) > 1e-9 * abs(lam_min):
        alpha += 90.0
    return alpha % 180.0, major, minor


# ---------------------------------------------------------------- the parabola table


PARABOLA_TABLE_K = (100.0, 200.0, 500.0, 1000.0)
PARABOLA_TABLE_T = (0.01, 0.1, 0.5, 1.0)
#: the printed table [mm] as printed (rows k [1/s], columns T [s]; the header is transposed in print)
PARABOLA_TABLE_PRINTED: dict[tuple[float, float], str] = {
    (100.0, 0.01): "-0.01",
    (100.0, 0.1): "-0.19",
    (100.0, 0.5): "-1.0",
    (100.0, 1.0): "-2",
    (200.0, 0.01): "-0.0075",
    (200.0, 0.1): "-0.1",
    (200.0, 0.5): "-0.5",
    (200.0, 1.0): "-1",
    (500.0, 0.01): "-0.0036",
    (500.0, 0.1): "-0.04",
    (500.0, 0.5): "-0.2",
    (500.0, 1.0): "-0.4",
    (1000.0, 0.01): "-0.002",
    (1000.0, 0.1): "-0.02",
    (1000.0, 0.5): "-0.1",
    (1000.0, 1.0): "-0.2",
}


def printed_half_unit(text: str) -> float:
    """Half a unit in the last printed digit (the rounding interval of a printed value)."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0 ** (-decimals)


@dataclass(frozen=True)
class TableRow:
    """One cell of the parabola table: formula (13), simulation and the printed value [mm]."""

    k: float
    T: float
    T1: float
    T2sq: float
    formula_13: float
    simulated: float
    printed: float
    printed_text: str
    printed_over_formula: float
    simulated_over_formula: float
    point_eight_formula: float
    within_print_rounding: bool


def simulate_parabola_vertex_error(
    ch: Channel,
    omega: float,
    p: float,
    settle: float = 20.0,
    gamma: float = 1.0,
    correction: Correction = "off",
) -> float:
    """Signed contour error of largest magnitude near the vertex after the transient.

    The PU starts far before the vertex (the vertex is reached after ``settle`` slowest
    time constants), the servo at rest on the start point; the state is carried to the
    vertex exactly and the exact normal distance to y = x^2/p is maximised around it.
    """
    rate = min(ch.decay_rate(), ch.scaled(gamma).decay_rate())
    speed = omega * p / 2.0
    t_v = max(settle / rate, 1.0)
    x0 = -speed * t_v
    system = TwoAxisServo(
        power_program(2, x0, 0.0, 0.0, p, omega), ch, ch.scaled(gamma), correction
    )
    z = system.transition(t_v - 0.5) @ system.initial_state()
    t = np.linspace(0.0, 1.0, 4001)
    out = system.outputs(system.run(t, z))
    d, _, _ = power_distance(out["x1"], out["y1"], 2, 0.0, 0.0, p, guess=out["x"])
    i = int(np.argmax(np.abs(d)))
    return float(d[i])


def parabola_table(v: float = 50.0, p: float = 20.0, omega: float = 5.0) -> list[TableRow]:
    """The article's table three ways: formula (13), simulation, the printed values.

    v = 50 mm/s is the vertex speed omega p/2 of the stated omega = 5, p = 20.  Rows k
    [1/s], columns T [s] (the printed header is transposed).  The printed values are
    0.8 x (13) in every cell (to their printed digits).
    """
    rows: list[TableRow] = []
    for k in PARABOLA_TABLE_K:
        for T in PARABOLA_TABLE_T:
            ch = Channel.from_open_loop(k, T)
            f13 = delta_parabola_13(omega, p, ch.T1, ch.T2sq)
            sim = simulate_parabola_vertex_error(ch, omega, p)
            text = PARABOLA_TABLE_PRINTED[(k, T)]
            printed = float(text)
            rows.append(
                TableRow(
                    k=k,
                    T=T,
                    T1=ch.T1,
                    T2sq=ch.T2sq,
                    formula_13=f13,
                    simulated=sim,
                    printed=printed,
                    printed_text=text,
                    printed_over_formula=printed / f13,
                    simulated_over_formula=sim / f13,
                    point_eight_formula=0.8 * f13,
                    within_print_rounding=abs(printed - 0.8 * f13)
                    <= printed_half_unit(text) + 1e-12,
                )
            )
    return rows


def table_ratio_interval() -> tuple[float, float]:
    """The interval of c/(omega^2 p/4) for which table = c (T1^2 - 2T2^2) rounds to every printed cell."""
    lo, hi = -math.inf, math.inf
    for (k, T), text in PARABOLA_TABLE_PRINTED.items():
        g = (1.0 / k) ** 2 - 2.0 * T / k  # negative in every cell
        val, h = float(text), printed_half_unit(text)
        c1, c2 = (val - h) / g, (val + h) / g
        lo, hi = max(lo, min(c1, c2)), min(hi, max(c1, c2))
    return lo / 125.0, hi / 125.0


def format_table(rows: list[TableRow]) -> str:
    """Markdown table: (13) | simulation | printed | printed/(13)."""
    lines = [
        "| k [1/s] | T [s] | (13) [mm] | simulation [mm] | printed [mm] | 0.8 x (13) | printed / (13) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r.k:g} | {r.T:g} | {r.formula_13:.6g} | {r.simulated:.6g} | {r.printed_text} | "
            f"{r.point_eight_formula:.4g} | {r.printed_over_formula:.3f} |"
        )
    return "\n".join(lines)
