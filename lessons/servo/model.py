"""Two-coordinate servo systems with program control (Leppik 1960): the linear model.

The programming device (PU) of the article is a linear ODE system that produces the
programmed coordinates x = f1(t), y = f2(t); each coordinate drives a linear servo
channel (2), (T2^2 s^2 + T1 s + 1) x1 = x.  PU + both channels form one autonomous
linear system dz/dt = M z whose state at any time is the exact closed form
z(t) = exp(M (t - t0)) z(t0) (:meth:`TwoAxisServo.states`, one matrix exponential per
time, vectorized): a headless run and a live frame at the same time compute the same
numbers.  Program correction (7), (21)-(22), (31)-(34) is one rule for every PU: feed
each channel with (T2^2 s^2 + T1 s + 1) applied to the programmed coordinate, i.e. the
output map Cx (I + T1 A + T2^2 A^2) of the same PU (the article's "modified initial
conditions" and, for non-identical channels, its extra constant input).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy import linalg, signal

Correction = Literal["off", "on", "derivative"]
#: a uniform grid is solved exactly at every ANCHOR-th time (see TwoAxisServo.states)
ANCHOR = 16
#: step maps exp(M dt) kept per servo (see TwoAxisServo.step_map)
STEP_MAPS = 64


@dataclass(frozen=True)
class Channel:
    """One servo channel (2): (T2^2 s^2 + T1 s + 1) x1 = x."""

    T1: float
    T2sq: float

    @classmethod
    def from_open_loop(cls, k: float, T: float) -> Channel:
        """Closed loop of W(s) = k/((Ts+1)s): T2^2 = T/k, T1 = 1/k (Fig. 1b)."""
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


@dataclass
class Program:
    """A programming device: dz/dt = A z, x = Cx z, y = Cy z (z contains a constant 1)."""

    A: np.ndarray
    z0: np.ndarray
    Cx: np.ndarray
    Cy: np.ndarray


def planar_program(A: np.ndarray, x0: float, y0: float) -> Program:
    """A PU with state (x, y, 1) started at (x0, y0)."""
    return Program(A, np.array([x0, y0, 1.0]), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]))


class TwoAxisServo:
    """PU + x channel + y channel as one autonomous linear system, solved exactly.

    State: z = (PU state, x1, dx1/dt, y1, dy1/dt).  ``correction``: ``off`` feeds the
    programmed coordinates; ``on`` feeds (T2^2 s^2 + T1 s + 1) x (the program correction);
    ``derivative`` feeds x + T1 dx/dt (the article's concluding counter-example).
    """

    def __init__(
        self, program: Program, cx: Channel, cy: Channel, correction: Correction = "off"
    ) -> None:
        self.program = program
        self.cx = cx
        self.cy = cy
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

    def _input_map(self, C: np.ndarray, ch: Channel, correction: Correction) -> np.ndarray:
        A = self.program.A
        if correction == "on":
            return ch.inverse_poly(A).T @ C
        if correction == "derivative":
            return (np.eye(A.shape[0]) + ch.T1 * A).T @ C
        return C.copy()

    def initial_state(self, xdot0: float = 0.0, ydot0: float = 0.0) -> np.ndarray:
        """Servo outputs start at the programmed start point with velocities xdot0, ydot0."""
        z0 = self.program.z0
        return np.concatenate([z0, [self.program.Cx @ z0, xdot0, self.program.Cy @ z0, ydot0]])

    def states(self, t: np.ndarray, z0: np.ndarray, t0: float = 0.0) -> np.ndarray:
        """exp(M (t - t0)) z0 at every time t: the exact states, shape (len(t), dim).

        On a uniform grid every ``ANCHOR``-th state is exp(M (t - t0)) z0 itself and the
        ones between are exp(M j h) applied to it (j < ANCHOR: round-off stays at a few
        ulps, at a fraction of the cost of one matrix exponential per time).
        """
        tt = np.atleast_1d(np.asarray(t, dtype=float)) - float(t0)
        z0 = np.asarray(z0, dtype=float)
        h = np.diff(tt)
        if len(tt) <= ANCHOR or not np.allclose(h, h[0], rtol=1e-9, atol=0.0):
            return linalg.expm(tt[:, None, None] * self.M) @ z0
        anchors = linalg.expm(tt[::ANCHOR, None, None] * self.M) @ z0
        step = linalg.expm(h[0] * self.M)
        powers = [np.eye(len(z0))]
        for _ in range(ANCHOR - 1):
            powers.append(step @ powers[-1])
        Z = np.einsum("kab,mb->mka", np.stack(powers), anchors).reshape(-1, len(z0))
        return Z[: len(tt)]

    def step_map(self, dt: float) -> np.ndarray:
        """exp(M dt), kept per step length (a played run repeats a few frame lengths)."""
        cache: dict[float, np.ndarray] = self.__dict__.setdefault("_step_maps", {})
        E = cache.get(dt)
        if E is None:
            if len(cache) >= STEP_MAPS:
                cache.clear()
            E = cache[dt] = linalg.expm(dt * self.M)
        return E

    def outputs(self, Z: np.ndarray) -> dict[str, np.ndarray]:
        """Programmed x, y; channel inputs ux, uy; outputs x1, y1; steady outputs x1ss, y1ss."""
        Z = np.atleast_2d(Z)
        zp = Z[:, : self.n]
        return {
            "x": zp @ self.program.Cx,
            "y": zp @ self.program.Cy,
            "ux": zp @ self.Kx,
            "uy": zp @ self.Ky,
            "x1": Z[:, self.n],
            "y1": Z[:, self.n + 2],
            "x1ss": zp @ self.Sx,
            "y1ss": zp @ self.Sy,
        }

    def decay_rate(self) -> float:
        return min(self.cx.decay_rate(), self.cy.decay_rate())

    def settled_outputs(
        self,
        window: float = 1.0,
        n: int = 2001,
        settle: float = 25.0,
        xdot0: float = 0.0,
        ydot0: float = 0.0,
    ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Times and outputs on [t_s, t_s + window] after ``settle`` slowest time constants."""
        t_s = settle / self.decay_rate()
        t = t_s + np.linspace(0.0, window, n)
        return t, self.outputs(self.states(t, self.initial_state(xdot0, ydot0)))


def settled(
    program: Program, cx: Channel, cy: Channel, correction: Correction = "off", **kw: float
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Times and outputs of a run after its transient (:meth:`TwoAxisServo.settled_outputs`)."""
    return TwoAxisServo(program, cx, cy, correction).settled_outputs(**kw)
