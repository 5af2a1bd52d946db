"""Arc-length reparametrization of a space curve, robust to end-point singularities.

Textbook §1.1, algorithm step 1: s(phi) = integral of |r'(phi)| over [phi0, phi]
(1.12); its inverse phi = omega(s) gives the arc-length form (1.13)/(1.6).

Numerics (not in the source).  The substitution

    phi = phi0 + (phi1 - phi0) sin^2(theta / 2),   theta in [0, pi]

turns an inverse-square-root singularity of |r'| at either end (such as
|r'|^2 = 2 / (1 - phi^2) of the helix form (1.4)) into a smooth integrand
g(theta) = |r'(phi(theta))| dphi/dtheta.  g is approximated on panels by Chebyshev
series at first-kind nodes (never at the panel ends), integrated exactly, and the
panel count is doubled until the total length settles to ~1e-13.  The inverse
s -> theta uses a safeguarded Newton iteration on the panel's polynomial.  For many
evaluations (a time law played frame by frame) the inverse phi = omega(s) is also
tabulated once per curve (``omega``): phi and dphi/ds = 1/|r'| at dense nodes uniform in
theta (so they crowd where the curve is slow), cubic Hermite in between (:class:`CubicHermite`;
error ~ h^4, a few 1e-13 of the range for a smooth curve).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import chebyshev as C

VecFn = Callable[[np.ndarray], np.ndarray]  # phi (N,) -> (N, 3)


def _clenshaw_rows(coef: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Evaluate Chebyshev series, one coefficient row per point: coef (N, m), x (N,)."""
    b1 = np.zeros_like(x)
    b2 = np.zeros_like(x)
    for j in range(coef.shape[1] - 1, 0, -1):
        b1, b2 = 2 * x * b1 - b2 + coef[:, j], b1
    return x * b1 - b2 + coef[:, 0]


@dataclass
class ArcLengthTable:
    """Piecewise Chebyshev model of s(theta) for one curve."""

    edges: np.ndarray  # (M+1,) theta panel edges
    cum: np.ndarray  # (M+1,) s at the edges
    g_coef: np.ndarray  # (M, n) Chebyshev coefficients of g on each panel (x in [-1, 1])
    s_coef: np.ndarray  # (M, n+1) antiderivative in theta, zero at the panel start
    accuracy: float  # last change of the total length on refinement


class CubicHermite:
    """Piecewise cubic Hermite interpolation of ``values`` (n,) or (n, k) with ``slopes`` at
    the non-decreasing ``nodes`` (n,); evaluated at points clamped to the nodes' range.

    The cubics are stored in power form once, so that an evaluation (also at one point,
    as a live frame needs) costs a search and one Horner scheme."""

    def __init__(self, nodes: np.ndarray, values: np.ndarray, slopes: np.ndarray) -> None:
        self.nodes = np.asarray(nodes, dtype=float)
        y, m = np.asarray(values, dtype=float), np.asarray(slopes, dtype=float)
        h = np.diff(self.nodes).reshape((-1,) + (1,) * (y.ndim - 1))
        with np.errstate(all="ignore"):
            d = np.where(h > 0, (y[1:] - y[:-1]) / h, 0.0)
            c2 = np.where(h > 0, (3 * d - 2 * m[:-1] - m[1:]) / h, 0.0)
            c3 = np.where(h > 0, (m[:-1] + m[1:] - 2 * d) / (h * h), 0.0)
        self.coef = np.stack([y[:-1], m[:-1], c2, c3])  # (4, n-1[, k])

    def __call__(self, x: np.ndarray) -> np.ndarray:
        if type(x) is np.ndarray and x.shape == (1,):  # one point (a played frame)
            one = self._one(float(x[0]))
            if one is not None:
                return one
        x = np.clip(np.asarray(x, dtype=float), self.nodes[0], self.nodes[-1])
        k = np.clip(np.searchsorted(self.nodes, x, side="right") - 1, 0, len(self.nodes) - 2)
        c0, c1, c2, c3 = self.coef[:, k]
        u = (x - self.nodes[k]).reshape(x.shape + (1,) * (c0.ndim - x.ndim))
        # at a node its value exactly (also when the next node is undefined)
        return np.where(u == 0, c0, c0 + u * (c1 + u * (c2 + u * c3)))

    def _one(self, x: float) -> np.ndarray | None:
        """:meth:`__call__` at ``[x]`` in plain floats (the same search and Horner scheme),
        None for a non-finite ``x``."""
        if not math.isfinite(x):
            return None
        nodes = self.nodes
        lo, hi = float(nodes[0]), float(nodes[-1])
        x = lo if x < lo else hi if x > hi else x
        k = min(max(int(nodes.searchsorted(x, side="right")) - 1, 0), len(nodes) - 2)
        u = x - float(nodes[k])
        c0, c1, c2, c3 = self.coef[:, k].tolist()
        if u == 0:
            return np.array([c0])
        if type(c0) is float:
            return np.array([c0 + u * (c1 + u * (c2 + u * c3))])
        return np.array([[a + u * (b + u * (c + u * d)) for a, b, c, d in zip(c0, c1, c2, c3)]])


class ArcLengthCurve:
    """A curve r(phi), phi in [phi0, phi1], with its arc length and inverse.

    ``r(phi)`` and ``dr(phi)`` take a 1-D array and return an (N, 3) array.
    """

    ORDER = 16
    MAX_PANELS = 4096

    def __init__(self, r: VecFn, dr: VecFn, phi0: float, phi1: float, tol: float = 1e-13) -> None:
        if not (math.isfinite(phi0) and math.isfinite(phi1)) or not phi1 > phi0:
            raise ValueError(f"need phi0 < phi1, got [{phi0:g}, {phi1:g}]")
        self.r = r
        self.dr = dr
        self.phi0 = float(phi0)
        self.phi1 = float(phi1)
        self.table = self._build(tol)
        self.S_l = float(self.table.cum[-1])
        self.omega = self._omega_table()

    # -- the substitution -----------------------------------------------------------

    def phi_of_theta(self, theta: np.ndarray) -> np.ndarray:
        """phi = phi0 + (phi1 - phi0) sin^2(theta/2), computed from the nearer end."""
        theta = np.asarray(theta, dtype=float)
        d = self.phi1 - self.phi0
        return np.where(
            theta <= np.pi / 2,
            self.phi0 + d * np.sin(theta / 2) ** 2,
            self.phi1 - d * np.cos(theta / 2) ** 2,
        )

    def dphi_dtheta(self, theta: np.ndarray) -> np.ndarray:
        return (self.phi1 - self.phi0) * np.sin(np.asarray(theta, dtype=float)) / 2

    def theta_of_phi(self, phi: np.ndarray) -> np.ndarray:
        u = np.clip((np.asarray(phi, dtype=float) - self.phi0) / (self.phi1 - self.phi0), 0.0, 1.0)
        return 2 * np.arcsin(np.sqrt(u))

    def speed_phi(self, phi: np.ndarray) -> np.ndarray:
        """|r'(phi)| (may be inf at an end point)."""
        with np.errstate(all="ignore"):
            return np.linalg.norm(self.dr(np.asarray(phi, dtype=float)), axis=1)

    def g(self, theta: np.ndarray) -> np.ndarray:
        """ds/dtheta = |r'(phi(theta))| dphi/dtheta."""
        theta = np.asarray(theta, dtype=float)
        with np.errstate(all="ignore"):
            return self.speed_phi(self.phi_of_theta(theta)) * self.dphi_dtheta(theta)

    # -- the table -------------------------------------------------------------------

    def _panels(self, M: int) -> ArcLengthTable:
        n = self.ORDER
        edges = np.linspace(0.0, np.pi, M + 1)
        k = np.arange(n)
        x = np.cos(np.pi * (k + 0.5) / n)  # first-kind nodes, interior
        a, b = edges[:-1, None], edges[1:, None]
        theta = (a + b) / 2 + (b - a) / 2 * x[None, :]
        g = self.g(theta.ravel()).reshape(M, n)
        if not np.all(np.isfinite(g)):
            bad = theta.ravel()[np.argmax(~np.isfinite(g.ravel()))]
            raise ValueError(
                f"|r'(phi)| is not finite at phi = {float(self.phi_of_theta(np.array([bad]))[0]):.6g}"
            )
        V = np.cos(np.outer(np.arange(n), np.pi * (k + 0.5) / n))  # (n, n): T_j(x_k)
        coef = g @ V.T * (2.0 / n)
        coef[:, 0] /= 2
        half = (edges[1:] - edges[:-1]) / 2
        s_coef = C.chebint(coef, m=1, lbnd=-1, axis=1) * half[:, None]
        panel_len = s_coef.sum(axis=1)  # T_j(1) = 1
        cum = np.concatenate([[0.0], np.cumsum(panel_len)])
        return ArcLengthTable(edges, cum, coef, s_coef, math.inf)

    def _build(self, tol: float) -> ArcLengthTable:
        M = 8
        prev = self._panels(M)
        while True:
            M *= 2
            cur = self._panels(M)
            change = abs(cur.cum[-1] - prev.cum[-1])
            cur.accuracy = float(change)
            if change <= tol * max(1.0, abs(cur.cum[-1])) or M >= self.MAX_PANELS:
                return cur
            prev = cur

    def _omega_table(self) -> CubicHermite:
        """phi = omega(s) (1.13) at 8 nodes per panel (at least 4097), uniform in theta, with
        the slopes dphi/ds = 1/|r'(phi)|, at most 3 x the neighbouring secants (finite at a
        cusp, where |r'| = 0, and the cubic stays monotone)."""
        theta = np.linspace(0.0, np.pi, max(4096, 8 * (len(self.table.edges) - 1)) + 1)
        s = np.maximum.accumulate(self.s_of_theta(theta))
        s[0], s[-1] = 0.0, self.S_l
        phi = self.phi_of_theta(theta)
        phi[0], phi[-1] = self.phi0, self.phi1
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = 1.0 / self.speed_phi(phi)
            secant = np.diff(phi) / np.diff(s)
        secant = np.where(np.isfinite(secant), secant, 0.0)
        # Fritsch-Carlson bound: slopes <= 3 x the neighbouring secants keep the cubic
        # monotone (and finite at a cusp, where |r'| = 0)
        cap = 3 * np.minimum(np.append(secant, secant[-1]), np.insert(secant, 0, secant[0]))
        return CubicHermite(s, phi, np.where(np.isfinite(slope), np.minimum(slope, cap), cap))

    # -- s(theta), theta(s) --------------------------------------------------------------

    def _locate(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        e = self.table.edges
        idx = np.clip(np.searchsorted(e, theta, side="right") - 1, 0, len(e) - 2)
        a, b = e[idx], e[idx + 1]
        return idx, (2 * theta - a - b) / (b - a)

    def s_of_theta(self, theta: np.ndarray) -> np.ndarray:
        theta = np.clip(np.atleast_1d(np.asarray(theta, dtype=float)), 0.0, np.pi)
        idx, x = self._locate(theta)
        return self.table.cum[idx] + _clenshaw_rows(self.table.s_coef[idx], x)

    def s_of_phi(self, phi: np.ndarray) -> np.ndarray:
        """(1.12): s(phi)."""
        return self.s_of_theta(self.theta_of_phi(phi))

    def theta_of_s(self, s: np.ndarray) -> np.ndarray:
        """Inverse of s(theta) on [0, S_l] (safeguarded Newton on each panel's polynomial)."""
        s = np.clip(np.atleast_1d(np.asarray(s, dtype=float)), 0.0, self.S_l)
        tab = self.table
        idx = np.clip(np.searchsorted(tab.cum, s, side="right") - 1, 0, len(tab.edges) - 2)
        target = s - tab.cum[idx]
        sc, gc = tab.s_coef[idx], tab.g_coef[idx]
        a, b = tab.edges[idx], tab.edges[idx + 1]
        half = (b - a) / 2
        plen = tab.cum[idx + 1] - tab.cum[idx]
        with np.errstate(all="ignore"):
            x = np.where(plen > 0, -1 + 2 * target / plen, 0.0)
        x = np.clip(np.nan_to_num(x), -1.0, 1.0)
        lo = np.full_like(x, -1.0)
        hi = np.full_like(x, 1.0)
        for _ in range(80):
            f = _clenshaw_rows(sc, x) - target
            lo = np.where(f <= 0, x, lo)
            hi = np.where(f >= 0, x, hi)
            d = _clenshaw_rows(gc, x) * half
            with np.errstate(all="ignore"):
                xn = np.where(f == 0, x, x - f / d)
            bad = ~np.isfinite(xn) | (xn < lo) | (xn > hi)
            xn = np.where(bad, (lo + hi) / 2, xn)
            step = np.abs(xn - x)
            x = xn
            if np.all((step <= 1e-14) | (hi - lo <= 1e-14)):
                break
        return (a + b) / 2 + half * x

    def phi_of_s(self, s: np.ndarray) -> np.ndarray:
        """(1.13): phi = omega(s)."""
        return self.phi_of_theta(self.theta_of_s(s))

    def point_of_s(self, s: np.ndarray) -> np.ndarray:
        """(1.6): r(s) as an (N, 3) array."""
        return self.r(self.phi_of_s(s))

    def unit_tangent(self, phi: np.ndarray) -> np.ndarray:
        """r'/|r'| at ``phi``; where it is undefined (an infinite or a zero derivative, e.g.
        at the ends of (1.4)) the limit from a nearby interior point (see below)."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        if phi.shape == (1,):  # one point (a played frame): plain floats where defined
            d = self.dr(phi)
            if d.shape == (1, 3):
                dx, dy, dz = d[0].tolist()
                n = math.sqrt(dx * dx + dy * dy + dz * dz)
                if n > 0 and math.isfinite(n):
                    return np.array([[dx / n, dy / n, dz / n]])
        out = self._unit(phi)
        bad = ~np.all(np.isfinite(out), axis=1)
        if bad.any():
            out[bad] = self.unit_tangent_theta(self.theta_of_phi(phi[bad]))
        return out

    def unit_tangent_theta(self, theta: np.ndarray) -> np.ndarray:
        """r'/|r'| at phi(theta); where it is undefined (an infinite or a zero derivative,
        e.g. at the ends of (1.4)) the limit is taken from a nearby interior point."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        out = self._unit(self.phi_of_theta(theta))
        bad = ~np.all(np.isfinite(out), axis=1)
        for eps in (1e-9, 1e-7, 1e-5, 1e-3):
            if not bad.any():
                break
            th = theta[bad]
            nudged = np.where(th < np.pi / 2, th + eps, th - eps)
            out[bad] = self._unit(self.phi_of_theta(np.clip(nudged, eps, np.pi - eps)))
            bad = ~np.all(np.isfinite(out), axis=1)
        return out

    def _unit(self, phi: np.ndarray) -> np.ndarray:
        d = self.dr(phi)
        with np.errstate(all="ignore"):
            n = np.sqrt(np.einsum("ij,ij->i", d, d))
            out = d / n[:, None]
        out[~np.isfinite(n) | (n == 0)] = np.nan
        return out


__all__ = ["ArcLengthCurve", "ArcLengthTable", "CubicHermite"]
