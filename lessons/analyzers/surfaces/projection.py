"""The nearest point of a second-order surface (or curve) to a given point: the
closest-point problem rᵀQr + 2bᵀr + c = 0 solved through its Lagrange multiplier in any
dimension (:func:`nearest_point`), and the singular types (point, line, double plane)
by their affine frame (:func:`project_affine`).  Used by
:meth:`analyzer_lab.lessons.analyzers.surfaces.quadric.Quadric.project` (a start point put
on the surface).
"""

from __future__ import annotations

import math

import numpy as np
from analyzer_lab.lessons.analyzers.surfaces.types import Classification


def nearest_point(
    Q: np.ndarray,
    b: np.ndarray,
    c: float,
    p: np.ndarray,
    scale: float,
    max_iter: int = 30,
) -> np.ndarray:
    """Nearest point to ``p`` on rᵀQr + 2bᵀr + c = 0 (any dimension n).

    Lagrange condition (r - p) + μ(Q r + b) = 0.  In the eigenbasis of Q with p at the
    origin, y_i(μ) = -μβ_i/(1 + μλ_i) (β = half gradient at p) and F(y(μ)) = 0 is a
    polynomial of degree <= 2n in μ.  Candidates: its real roots; for each eigenvalue
    the exceptional multiplier μ = -1/λ (the point lies on a symmetry plane, the
    coordinates along λ's eigenspace are free); the two intersections of the gradient
    line through p.  Every candidate is polished (Newton on the Lagrange system, then
    Newton along the gradient onto F = 0) and the nearest one on the surface wins.
    Degenerate types with a singular surface (point, line, double plane) are handled
    by the caller."""
    n = p.size
    S = max(float(np.max(np.abs(Q))), float(np.max(np.abs(b))), abs(c), 1e-300)
    Qn, bn, cn = Q / S, b / S, c / S
    h0 = Qn @ p + bn  # half gradient at p
    F0 = float(p @ Qn @ p + 2 * bn @ p + cn)
    lam, V = np.linalg.eigh(Qn)
    lmax = float(np.max(np.abs(lam)))
    lam = np.where(np.abs(lam) <= 1e-12 * lmax, 0.0, lam)
    beta = V.T @ h0
    P = np.polynomial.polynomial
    D = [np.array([1.0, lam[j]]) for j in range(n)]
    D2 = [P.polymul(d, d) for d in D]

    def prod(skip: int | None) -> np.ndarray:
        out = np.array([1.0])
        for j in range(n):
            if j != skip:
                out = P.polymul(out, D2[j])
        return out

    poly = F0 * prod(None)
    for i in range(n):
        poly = P.polysub(poly, beta[i] ** 2 * P.polymul(np.array([0.0, 2.0, lam[i]]), prod(i)))
    ys: list[np.ndarray] = []
    poly = np.trim_zeros(np.asarray(poly, dtype=float), "b")
    if poly.size > 1:
        for mu in P.polyroots(poly):
            if abs(mu.imag) <= 1e-6 * (1 + abs(mu.real)):
                mu = mu.real
                den = 1 + mu * lam
                if np.all(np.abs(den) > 1e-14):
                    ys.append(-mu * beta / den)
    for lv in np.unique(lam[lam != 0]):
        mu = -1.0 / lv
        grp = np.abs(lam - lv) <= 1e-9 * abs(lv)
        y = np.zeros(n)
        y[~grp] = -mu * beta[~grp] / (1 + mu * lam[~grp])
        rest = float(np.sum(lam[~grp] * y[~grp] ** 2 + 2 * beta[~grp] * y[~grp]) + F0)
        bg = beta[grp]
        e = bg / np.linalg.norm(bg) if np.linalg.norm(bg) > 0 else np.eye(int(grp.sum()))[0]
        # lv ρ² + 2 (bg·e) ρ + rest = 0 along e
        for rho in np.roots([lv, 2 * float(bg @ e), rest]):
            if abs(rho.imag) <= 1e-9 * (1 + abs(rho.real)):
                yy = y.copy()
                yy[grp] = rho.real * e
                ys.append(yy)
    # gradient line r = p + t h0
    hq = float(h0 @ Qn @ h0)
    for t in np.roots([hq, 2 * float(h0 @ h0), F0]) if (hq != 0 or h0 @ h0 != 0) else []:
        if abs(t.imag) <= 1e-9 * (1 + abs(t.real)):
            ys.append(V.T @ (t.real * h0))

    def polish(r: np.ndarray) -> np.ndarray:
        # Newton on (r - p) + μ(Qr + b) = 0, F(r) = 0
        g = Qn @ r + bn
        gg = float(g @ g)
        mu = float(-(r - p) @ g / gg) if gg > 0 else 0.0
        for _ in range(max_iter):
            g = Qn @ r + bn
            Fr = float(r @ Qn @ r + 2 * bn @ r + cn)
            G = np.concatenate([(r - p) + mu * g, [Fr]])
            J = np.zeros((n + 1, n + 1))
            J[:n, :n] = np.eye(n) + mu * Qn
            J[:n, n] = g
            J[n, :n] = 2 * g
            try:
                d = np.linalg.solve(J, -G)
            except np.linalg.LinAlgError:
                break
            if not np.all(np.isfinite(d)):
                break
            r, mu = r + d[:n], mu + d[n]
            if np.linalg.norm(d[:n]) <= 1e-15 * (1 + np.linalg.norm(r)):
                break
        return r

    def onto(r: np.ndarray) -> np.ndarray:
        for _ in range(max_iter):
            g = Qn @ r + bn
            Fr = float(r @ Qn @ r + 2 * bn @ r + cn)
            gg = float(g @ g)
            if abs(Fr) * S <= 1e-14 * scale or gg == 0:
                break
            r = r - Fr * g / (2 * gg)
        return r

    best, best_d = None, math.inf
    for y in ys:
        if not np.all(np.isfinite(y)):
            continue
        r0 = p + V @ y
        for r in (onto(polish(r0)), onto(r0)):
            if not np.all(np.isfinite(r)):
                continue
            Fr = abs(float(r @ Qn @ r + 2 * bn @ r + cn)) * S
            d = float(np.linalg.norm(r - p))
            if Fr <= 1e-12 * scale and d < best_d - 1e-15 * (1 + d):
                best, best_d = r, d
    if best is None:
        raise ValueError("no point of the surface could be reached from this point")
    return best


def project_affine(cl: Classification, p: np.ndarray) -> np.ndarray:
    """Orthogonal projection onto a point, a line (3-D: along the last principal axis)
    or a doubled plane / doubled line (the last principal axis is its normal)."""
    if cl.kind == "point":
        return np.array(cl.center, dtype=float)
    A = cl.axes[:, -1:] if cl.kind == "line" else cl.axes[:, :-1]
    return cl.center + A @ (A.T @ (p - cl.center))
