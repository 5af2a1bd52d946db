"""Contour geometry for the servo-error lesson (Leppik 1960): signed normal distances.

The contour error delta of the article is the distance between the programmed and the
reproduced curve.  These functions give the signed normal distance of points from a line,
a parabola of degree n (axis along y or, with the coordinates swapped, along x) and an
ellipse, with the foot points; and the axes of a centred ellipse fitted to samples (the
reproduced circle or ellipse).  Signs follow the article: positive inside a convex curve
(and above a cubic), so (13) and (28) come out negative when the output lies outside.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

Distance = tuple[np.ndarray, np.ndarray, np.ndarray]
Scale = float | np.ndarray


def line_distance(
    xq: np.ndarray, yq: np.ndarray, px: np.ndarray, py: np.ndarray, angle_deg: float
) -> Distance:
    """Signed distance of (xq, yq) from the line through (px, py) at ``angle``; sign as in (5)."""
    th = math.radians(angle_deg)
    c, s = math.cos(th), math.sin(th)
    dx, dy = np.asarray(xq) - px, np.asarray(yq) - py
    d = dx * s - dy * c
    along = dx * c + dy * s
    return d, px + along * c, py + along * s


def _newton_foot(
    xq: np.ndarray, yq: np.ndarray, n: int, xc: float, yc: np.ndarray, p: float, u0: np.ndarray
) -> np.ndarray:
    """Abscissa u of the nearest point of y = yc + (u - xc)^n / p, Newton from u0."""
    if xq.size == 1:  # a live frame: one point, the same iteration on Python floats
        return np.full(
            xq.shape,
            _newton_foot_1(
                float(xq.flat[0]),
                float(yq.flat[0]),
                n,
                xc,
                float(yc.flat[0]),
                p,
                float(np.broadcast_to(u0, xq.shape).flat[0]),
            ),
        )
    u = np.broadcast_to(u0, xq.shape).copy()
    active = np.arange(u.size)
    for _ in range(60):
        ua, xa, ya = u[active], xq[active], yq[active]
        w = ua - xc
        wn2 = w ** (n - 2)
        fu = yc[active] + wn2 * w * w / p
        f1 = n * wn2 * w / p
        f2 = n * (n - 1) * wn2 / p
        g = (ua - xa) + (fu - ya) * f1
        base = 1.0 + f1 * f1
        h = base + (fu - ya) * f2
        h = np.where(h > 0.1 * base, h, base)
        du = g / h
        u[active] = ua - du
        active = active[~(np.abs(du) <= 1e-13 * (1.0 + np.abs(ua)))]
        if active.size == 0:
            break
    return u


def _newton_foot_1(xq: float, yq: float, n: int, xc: float, yc: float, p: float, u: float) -> float:
    """:func:`_newton_foot` for one point."""
    for _ in range(60):
        w = u - xc
        wn2 = w ** (n - 2)
        fu = yc + wn2 * w * w / p
        f1 = n * wn2 * w / p
        f2 = n * (n - 1) * wn2 / p
        g = (u - xq) + (fu - yq) * f1
        base = 1.0 + f1 * f1
        h = base + (fu - yq) * f2
        h = h if h > 0.1 * base else base
        du = g / h
        old = u
        u = old - du
        if abs(du) <= 1e-13 * (1.0 + abs(old)):
            break
    return u


def power_distance(
    xq: np.ndarray,
    yq: np.ndarray,
    n: int,
    xc: float,
    yc: float | np.ndarray,
    p: float,
    guess: np.ndarray | None = None,
) -> Distance:
    """Signed normal distance from y = yc + (x - xc)^n / p (+ above); foot points."""
    if np.size(xq) == 1 and np.size(yq) == 1 and np.size(yc) == 1 and np.size(guess) <= 1:
        return _power_distance_1(xq, yq, n, xc, yc, p, guess)
    xq, yq = np.broadcast_arrays(
        np.atleast_1d(np.asarray(xq, dtype=float)), np.atleast_1d(np.asarray(yq, dtype=float))
    )
    ycb = np.broadcast_to(np.asarray(yc, dtype=float), xq.shape)

    def f(u: np.ndarray) -> np.ndarray:
        return ycb + (u - xc) ** n / p

    starts = [xq] if guess is None else [xq, np.atleast_1d(np.asarray(guess, dtype=float))]
    cands = [_newton_foot(xq, yq, n, xc, ycb, p, u0) for u0 in starts]
    dist = [np.hypot(u - xq, f(u) - yq) for u in cands]
    pick = np.argmin(np.vstack(dist), axis=0)
    u = np.choose(pick, cands)
    d = np.choose(pick, dist)
    sign = np.where(yq >= f(xq), 1.0, -1.0)
    return sign * d, u, f(u)


def _power_distance_1(
    xq: Any, yq: Any, n: int, xc: float, yc: Any, p: float, guess: Any
) -> Distance:
    """:func:`power_distance` of one point (a live frame), on Python floats."""
    x, y, c = (float(np.ravel(v)[0]) for v in (xq, yq, yc))
    starts = [x] if guess is None else [x, float(np.ravel(guess)[0])]
    us = [_newton_foot_1(x, y, n, xc, c, p, u0) for u0 in starts]
    ds = [float(np.hypot(u - x, c + (u - xc) ** n / p - y)) for u in us]
    nan = [k for k, d in enumerate(ds) if math.isnan(d)]
    k = nan[0] if nan else ds.index(min(ds))  # as numpy's argmin
    sign = 1.0 if y >= c + (x - xc) ** n / p else -1.0
    return np.array([sign * ds[k]]), np.array([us[k]]), np.array([c + (us[k] - xc) ** n / p])


def ellipse_distance(
    xq: np.ndarray, yq: np.ndarray, xc: float, yc: float, a: Scale, b: Scale
) -> Distance:
    """Signed normal distance from (x-xc)^2/a^2 + (y-yc)^2/b^2 = 1 (+ inside); foot points.
    ``a``, ``b`` may be arrays (one ellipse per point)."""
    X = np.atleast_1d(np.asarray(xq, dtype=float)) - xc
    Y = np.atleast_1d(np.asarray(yq, dtype=float)) - yc
    if np.array_equal(a, b):
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
        base = (a * s) ** 2 + (b * c) ** 2
        h = base - ex * a * c - ey * b * s
        dth = g / np.where(h > 0.1 * base, h, base)
        th = th - dth
        if np.all(np.abs(dth) < 1e-14):
            break
    fx, fy = a * np.cos(th), b * np.sin(th)
    d = np.hypot(fx - X, fy - Y)
    inside = (X / a) ** 2 + (Y / b) ** 2 < 1.0
    return np.where(inside, d, -d), xc + fx, yc + fy


def fit_centred_ellipse(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """Least-squares centred conic A x^2 + 2B xy + C y^2 = 1 -> (major, minor, angle of the
    major axis [deg] in [0, 180)); NaN when the samples do not lie on an ellipse."""
    G = np.column_stack([x * x, 2 * x * y, y * y])
    coef, *_ = np.linalg.lstsq(G, np.ones_like(x), rcond=None)
    Q = np.array([[coef[0], coef[1]], [coef[1], coef[2]]])
    lam, vec = np.linalg.eigh(Q)
    if not lam[0] > 0:
        return math.nan, math.nan, math.nan
    ang = math.degrees(math.atan2(vec[1, 0], vec[0, 0])) % 180.0
    return 1.0 / math.sqrt(lam[0]), 1.0 / math.sqrt(lam[1]), ang
