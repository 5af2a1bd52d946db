"""Plane second-order curves (conics) in the textbook's notation, eq. (1.21).

    F(x, y) = a11 x² + 2 a12 xy + a22 y² + 2 a13 x + 2 a23 y + a33 = 0      (1.21)

In 2-D the linear coefficients are ``a13, a23`` and the constant is ``a33`` (unlike the
3-D quadric (1.42), where ``a13`` does not exist and the xz term is ``a31``).  In matrix
form F = rᵀQr + 2bᵀr + c with Q = [[a11, a12], [a12, a22]], b = (a13, a23), c = a33,
and the half gradient ½∇F = Q r + b gives the analyzer (1.30):
dx/dφ = ω(a12 x + a22 y + a23), dy/dφ = -ω(a11 x + a12 y + a13).

The classification, nearest-point and principal-axis algebra is shared with
:mod:`lessons.core.quadric`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import sympy as sp

from lessons.core.quadric import (
    Classification,
    _nearest_point,
    _orth_complement,
    _project_affine,
    _reduce,
    sym_number,
)

CONIC_COEFF_NAMES: tuple[str, ...] = ("a11", "a22", "a12", "a13", "a23", "a33")
COEFF_NAMES = CONIC_COEFF_NAMES

Vec2 = Sequence[float]
Bounds2 = tuple[tuple[float, float], tuple[float, float]]


def _fmt(v: float) -> str:
    return f"{v:g}"


def _center2(center: Vec2, what: str = "center") -> np.ndarray:
    c = np.asarray(center, dtype=float).reshape(-1)
    if c.shape != (2,) or not np.all(np.isfinite(c)):
        raise ValueError(f"{what} must be two finite numbers, got {center!r}")
    return c


def _at(center: Vec2) -> str:
    c = tuple(float(v) for v in center)
    return "" if not any(c) else " at (" + ", ".join(_fmt(v) for v in c) + ")"


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


@dataclass(frozen=True)
class CurveType:
    """One entry of :data:`CONSTRUCTORS`: calling it builds the conic."""

    id: str
    title: str
    params: tuple[str, ...]
    defaults: dict[str, float]
    build: Callable[..., Conic]
    equation: str = ""

    def __call__(self, *args: Any, **kwargs: Any) -> Conic:
        return self.build(*args, **kwargs)


@dataclass(frozen=True)
class Conic:
    """The conic (1.21) with the textbook's coefficient names."""

    a11: float = 0.0
    a22: float = 0.0
    a12: float = 0.0
    a13: float = 0.0
    a23: float = 0.0
    a33: float = 0.0
    label: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        bad = []
        for n in CONIC_COEFF_NAMES:
            try:
                v = float(getattr(self, n))
            except (TypeError, ValueError):
                raise ValueError(
                    f"coefficient {n} must be a number, got {getattr(self, n)!r}"
                ) from None
            if not math.isfinite(v):
                bad.append(f"{n}={v}")
            object.__setattr__(self, n, v)
        if bad:
            raise ValueError("conic coefficients must be finite: " + ", ".join(bad))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_coeffs(cls, label: str = "", **coeffs: float) -> Conic:
        """Build from named coefficients (missing ones are 0); unknown names or
        non-finite values raise ValueError."""
        unknown = sorted(set(coeffs) - set(CONIC_COEFF_NAMES))
        if unknown:
            raise ValueError(
                f"unknown conic coefficient(s) {', '.join(unknown)}; expected names from "
                + ", ".join(CONIC_COEFF_NAMES)
            )
        return cls(**{k: float(v) for k, v in coeffs.items()}, label=label)

    @classmethod
    def from_matrices(
        cls, Q: np.ndarray, b: Vec2 = (0, 0), c: float = 0.0, label: str = ""
    ) -> Conic:
        """Build from F = rᵀQr + 2bᵀr + c (Q is symmetrised)."""
        Q = np.asarray(Q, dtype=float)
        if Q.shape != (2, 2):
            raise ValueError(f"Q must be 2x2, got shape {Q.shape}")
        Q = 0.5 * (Q + Q.T)
        b = np.asarray(b, dtype=float).reshape(2)
        return cls(
            a11=Q[0, 0], a22=Q[1, 1], a12=Q[0, 1], a13=b[0], a23=b[1], a33=float(c), label=label
        )

    @classmethod
    def _canonical(cls, diag: Vec2, lin: Vec2, const: float, center: Vec2, label: str) -> Conic:
        q = cls.from_matrices(np.diag(diag), lin, const, label=label)
        c = _center2(center)
        return q.translated(c) if np.any(c) else q

    @classmethod
    def circle(cls, R: float = 1.0, center: Vec2 = (0, 0)) -> Conic:
        """x² + y² - R² = 0 ((1.34) when centred)."""
        R = _positive("R", R)
        return cls._canonical((1, 1), (0, 0), -R * R, center, f"circle R={_fmt(R)}{_at(center)}")

    @classmethod
    def ellipse(cls, a: float = 2.0, b: float = 1.0, center: Vec2 = (0, 0)) -> Conic:
        """x²/a² + y²/b² - 1 = 0."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, 1 / b**2),
            (0, 0),
            -1.0,
            center,
            f"ellipse a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def parabola(cls, a: float = 1.0, center: Vec2 = (0, 0)) -> Conic:
        """y = x²/a², i.e. x²/a² - y = 0 (a23 = -1/2); vertex at ``center``."""
        a = _positive("a", a)
        return cls._canonical(
            (1 / a**2, 0), (0, -0.5), 0.0, center, f"parabola a={_fmt(a)}{_at(center)}"
        )

    @classmethod
    def hyperbola(cls, a: float = 1.0, b: float = 1.0, center: Vec2 = (0, 0)) -> Conic:
        """x²/a² - y²/b² - 1 = 0."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, -1 / b**2),
            (0, 0),
            -1.0,
            center,
            f"hyperbola a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def line(cls, normal: Vec2 = (0, 1), point: Vec2 = (0, 0)) -> Conic:
        """n·(r - r0) = 0."""
        n = _center2(normal, "normal")
        if not np.any(n):
            raise ValueError("line normal must be non-zero")
        p = _center2(point, "point")
        return cls.from_matrices(np.zeros((2, 2)), n / 2, -float(n @ p), label="line")

    # ------------------------------------------------------------------ matrices
    def coeffs(self) -> dict[str, float]:
        """The six coefficients by their textbook names."""
        return {n: float(getattr(self, n)) for n in CONIC_COEFF_NAMES}

    @property
    def Q(self) -> np.ndarray:
        return np.array([[self.a11, self.a12], [self.a12, self.a22]], dtype=float)

    @property
    def b(self) -> np.ndarray:
        """(a13, a23)."""
        return np.array([self.a13, self.a23], dtype=float)

    @property
    def c(self) -> float:
        """a33."""
        return float(self.a33)

    # ------------------------------------------------------------------ evaluation
    def F(self, points: np.ndarray | Vec2) -> np.ndarray | float:
        """F at points of shape (..., 2); a float for one point."""
        r = np.asarray(points, dtype=float)
        x, y = r[..., 0], r[..., 1]
        v = (
            x * (self.a11 * x + 2.0 * (self.a12 * y + self.a13))
            + y * (self.a22 * y + 2.0 * self.a23)
            + self.a33
        )
        return float(v) if np.ndim(v) == 0 else v

    def half_gradient(self, points: np.ndarray | Vec2) -> np.ndarray:
        """½∇F = (a11 x + a12 y + a13, a12 x + a22 y + a23), shape (..., 2)."""
        r = np.asarray(points, dtype=float)
        x, y = r[..., 0], r[..., 1]
        return np.stack(
            [self.a11 * x + self.a12 * y + self.a13, self.a12 * x + self.a22 * y + self.a23],
            axis=-1,
        )

    def gradient(self, points: np.ndarray | Vec2) -> np.ndarray:
        return 2.0 * self.half_gradient(points)

    def sym(self, x: sp.Symbol | None = None, y: sp.Symbol | None = None) -> sp.Expr:
        """F as a sympy expression (exact Rationals for simple fractions, see
        :func:`lessons.core.quadric.sym_number`)."""
        x = x if x is not None else sp.Symbol("x", real=True)
        y = y if y is not None else sp.Symbol("y", real=True)
        k = {n: sym_number(getattr(self, n)) for n in CONIC_COEFF_NAMES}
        return (
            k["a11"] * x**2
            + 2 * k["a12"] * x * y
            + k["a22"] * y**2
            + 2 * k["a13"] * x
            + 2 * k["a23"] * y
            + k["a33"]
        )

    # ------------------------------------------------------------------ transforms
    def level_through(self, point: Vec2) -> Conic:
        """Same quadratic and linear part, a33 chosen so that F(point) = 0 (the curve an
        analyzer (1.30) started at ``point`` draws)."""
        p = _center2(point, "point")
        a33 = -float(self.F(p) - self.a33)
        lab = f"{self.label} through ({', '.join(_fmt(v) for v in p)})" if self.label else ""
        return Conic(**{**self.coeffs(), "a33": a33}, label=lab)

    def with_coeffs(self, **changes: float) -> Conic:
        return Conic.from_coeffs(label=self.label, **{**self.coeffs(), **changes})

    def translated(self, t: Vec2) -> Conic:
        """G(r) = F(r - t)."""
        t = _center2(t, "t")
        Q, b = self.Q, self.b
        return Conic.from_matrices(
            Q, b - Q @ t, float(t @ Q @ t - 2 * b @ t + self.c), label=self.label
        )

    def rotated(self, angle: float) -> Conic:
        """The curve rotated by ``angle`` (rad) about the origin."""
        R = _rot2(angle)
        return Conic.from_matrices(R @ self.Q @ R.T, R @ self.b, self.c, label=self.label)

    def transformed(self, angle: float, t: Vec2 = (0, 0)) -> Conic:
        return self.rotated(angle).translated(t)

    def scaled(self, k: float) -> Conic:
        if not math.isfinite(k) or k == 0:
            raise ValueError("the factor must be finite and non-zero")
        return Conic(**{n: k * v for n, v in self.coeffs().items()}, label=self.label)

    # ------------------------------------------------------------------ classification
    @cached_property
    def _classification(self) -> Classification:
        return _classify2(self.Q, self.b, self.c)

    def classify(self) -> Classification:
        """Type id (``ellipse``, ``circle``, ``parabola``, ``hyperbola``,
        ``intersecting-lines``, ``parallel-lines``, ``coincident-lines``, ``line``,
        ``point``, ``empty``, ``all-plane``), centre/vertex, 2x2 principal frame and
        semi-axes: ellipse/hyperbola x²/a² ± y²/b² = 1 (a, b); parabola y = x²/a² (a,);
        intersecting lines x²/a² - y² = 0 (a, 1); parallel lines y² = d² (d,); the
        distinguished axis (parabola axis, line normal) is the last column."""
        return self._classification

    @cached_property
    def length(self) -> float:
        """|centre| + the largest semi-axis (1 without semi-axes)."""
        cl = self._classification
        size = max((s for s in cl.semi_axes if s > 0), default=1.0)
        off = float(np.linalg.norm(cl.center)) if cl.center is not None else 0.0
        return off + size

    @cached_property
    def scale(self) -> float:
        """max(|a33|, ‖Q‖₂ L², ‖b‖ L) with L = :attr:`length` (1 if all vanish)."""
        L = self.length
        v = max(
            abs(self.c), float(np.linalg.norm(self.Q, 2)) * L * L, float(np.linalg.norm(self.b)) * L
        )
        return v if v > 0 else 1.0

    def default_bounds(self) -> Bounds2:
        """Bounding box + 15 % for ellipses; a square of half-size 2·(largest
        semi-axis) about the centre otherwise (moved along the axis for a parabola)."""
        cl = self._classification
        if cl.kind in ("ellipse", "circle"):
            half = np.sqrt(((cl.axes * np.asarray(cl.semi_axes)) ** 2).sum(axis=1)) * 1.15
            lo, hi = cl.center - half, cl.center + half
        else:
            c0 = cl.center if cl.center is not None else np.zeros(2)
            H = 2.0 * max((s for s in cl.semi_axes if s > 0), default=1.0)
            if cl.kind == "parabola":
                c0 = c0 + cl.axes[:, 1] * 0.8 * H
            lo, hi = c0 - H, c0 + H
        return (tuple(float(v) for v in lo), tuple(float(v) for v in hi))  # type: ignore[return-value]

    def project(self, point: Vec2, max_iter: int = 30) -> np.ndarray:
        """Nearest point of F = 0 to ``point`` (|F| <= 1e-12·scale).  ValueError for an
        empty curve or a singular point of F (centre) not on the curve."""
        p = _center2(point, "point")
        cl = self._classification
        if cl.kind == "empty":
            raise ValueError(f"the curve has no real points ({cl.name}); nothing to project on")
        if cl.kind == "all-plane":
            return p.copy()
        if abs(self.F(p)) <= 1e-14 * self.scale:
            return p.copy()
        if cl.kind in ("point", "coincident-lines"):
            return _project_affine(cl, p)
        g = self.half_gradient(p)
        gscale = float(np.linalg.norm(self.Q, 2)) * (
            float(np.linalg.norm(p)) + self.length
        ) + float(np.linalg.norm(self.b))
        if np.linalg.norm(g) <= 1e-12 * gscale:
            raise ValueError(
                f"the point {tuple(float(v) for v in p)} is a singular point of F (zero gradient: the centre "
                f"of the {cl.name}) and not on the curve; its nearest point is not unique"
            )
        return _nearest_point(self.Q, self.b, self.c, p, self.scale, max_iter)

    def polyline(self, bounds: Bounds2 | None = None, resolution: int = 256) -> list[np.ndarray]:
        """The curve inside the rectangle ``bounds`` = ((x0, y0), (x1, y1)) as a list of
        (N, 2) pieces (a closed ellipse inside the box: one piece, first == last point).
        Sampled parametrically in the principal frame; ends cut by the box are pulled
        back onto F = 0 along the box edge.  [] for point / empty / all-plane."""
        return _polyline(self, bounds if bounds is not None else self.default_bounds(), resolution)


def _rot2(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


_NAMES2 = {
    "circle": "circle",
    "ellipse": "ellipse",
    "hyperbola": "hyperbola",
    "parabola": "parabola",
    "intersecting-lines": "pair of intersecting lines",
    "parallel-lines": "pair of parallel lines",
    "coincident-lines": "line counted twice (coincident lines)",
    "line": "line",
    "point": "point (imaginary intersecting lines)",
    "empty": "no real points",
    "all-plane": "F is identically zero",
}
_NONDEGENERATE2 = {"circle", "ellipse", "hyperbola", "parabola"}


def _right2(c0: np.ndarray, c1: np.ndarray) -> np.ndarray:
    A = np.column_stack([c0, c1])
    if np.linalg.det(A) < 0:
        A[:, 0] = -A[:, 0]
    return A


def _classify2(Q: np.ndarray, b: np.ndarray, c: float) -> Classification:
    red = _reduce(Q, b, c)
    lam, V = red.lam, red.V
    m = lam.size

    def result(
        kind: str,
        axes: np.ndarray | None,
        center: np.ndarray | None,
        semi: tuple = (),
        extra: str = "",
    ) -> Classification:
        return Classification(
            kind,
            _NAMES2[kind] + extra,
            kind not in _NONDEGENERATE2,
            center,
            axes if axes is not None else np.eye(2),
            semi,
            m,
        )

    if red.g > 0:
        n = red.n_dir
        if m == 1:
            kappa = -lam[0] / (2 * red.g)
            if kappa < 0:
                n, kappa = -n, -kappa
            return result(
                "parabola", _right2(V[:, 0], n), red.point, (float(1 / math.sqrt(kappa)),)
            )
        return result("line", _right2(_orth_complement(n[:, None], 2)[:, 0], n), red.point)
    k = red.k
    if m == 2:
        if k != 0:
            mu = -lam / k
            if np.all(mu > 0):
                order = np.argsort(mu)
                semi = tuple(float(1 / math.sqrt(mu[i])) for i in order)
                kind = "circle" if abs(semi[0] - semi[1]) <= 1e-9 * semi[0] else "ellipse"
                return result(kind, _right2(V[:, order[0]], V[:, order[1]]), red.point, semi)
            if np.all(mu < 0):
                return result("empty", None, None, (), " (imaginary ellipse)")
            ip, ineg = (0, 1) if mu[0] > 0 else (1, 0)
            semi = (float(1 / math.sqrt(mu[ip])), float(1 / math.sqrt(-mu[ineg])))
            return result("hyperbola", _right2(V[:, ip], V[:, ineg]), red.point, semi)
        if lam[0] * lam[1] > 0:
            return result(
                "point", V.copy() if np.linalg.det(V) > 0 else _right2(V[:, 0], V[:, 1]), red.point
            )
        ip, ineg = (0, 1) if lam[0] > 0 else (1, 0)
        semi = (float(math.sqrt(abs(lam[ineg] / lam[ip]))), 1.0)
        return result("intersecting-lines", _right2(V[:, ip], V[:, ineg]), red.point, semi)
    if m == 1:
        axes = _right2(red.null[:, 0], V[:, 0])
        if k == 0:
            return result("coincident-lines", axes, red.point)
        if k / lam[0] < 0:
            return result("parallel-lines", axes, red.point, (float(math.sqrt(-k / lam[0])),))
        return result("empty", None, None, (), " (imaginary parallel lines)")
    if k == 0:
        return result("all-plane", None, None)
    return result("empty", None, None, (), " (F is a non-zero constant)")


# ====================================================================== polylines
def _canonical_pieces(
    kind: str, semi: tuple[float, ...], ext: np.ndarray, yhi: float, n: int
) -> list[tuple[np.ndarray, bool]]:
    """(points (N, 2), closed) in canonical coordinates covering |x| <= X, |y| <= Y."""
    X, Y = float(ext[0]), float(ext[1])
    if kind in ("ellipse", "circle"):
        t = np.linspace(0.0, 2 * np.pi, n + 1)
        return [(np.stack([semi[0] * np.cos(t), semi[1] * np.sin(t)], -1), True)]
    if kind == "hyperbola":
        a, b = semi
        if X <= a:
            return []
        U = math.asinh(min(Y / b, math.sqrt((X / a) ** 2 - 1)))
        u = np.linspace(-U, U, n)
        return [(np.stack([s * a * np.cosh(u), b * np.sinh(u)], -1), False) for s in (1.0, -1.0)]
    if kind == "parabola":
        (a,) = semi
        umax = min(X / a, math.sqrt(max(yhi, 0.0)))
        u = np.linspace(-umax, umax, n)
        return [(np.stack([a * u, u * u], -1), False)]
    if kind == "intersecting-lines":
        a = semi[0]
        u = np.linspace(-min(X, a * Y), min(X, a * Y), 2)
        return [(np.stack([u, s * u / a], -1), False) for s in (1.0, -1.0)]
    if kind in ("parallel-lines", "coincident-lines", "line"):
        x = np.linspace(-X, X, 2)
        hs = (semi[0], -semi[0]) if kind == "parallel-lines" else (0.0,)
        return [(np.stack([x, np.full_like(x, h)], -1), False) for h in hs]
    return []


def _clip_segments(
    P: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Liang-Barsky for the segments P[i] -> P[i+1]: (valid, t0, t1)."""
    a, d = P[:-1], P[1:] - P[:-1]
    t0 = np.zeros(len(d))
    t1 = np.ones(len(d))
    valid = np.ones(len(d), bool)
    for k in range(2):
        for p_, q_ in ((-d[:, k], a[:, k] - lo[k]), (d[:, k], hi[k] - a[:, k])):
            par = p_ == 0
            valid &= ~(par & (q_ < 0))
            with np.errstate(divide="ignore", invalid="ignore"):
                r = np.where(par, 0.0, q_ / np.where(par, 1.0, p_))
            neg, pos = (p_ < 0) & ~par, (p_ > 0) & ~par
            t0 = np.where(neg, np.maximum(t0, r), t0)
            t1 = np.where(pos, np.minimum(t1, r), t1)
    valid &= t0 <= t1
    return valid, t0, t1


def _snap_edge(
    conic: Conic, r: np.ndarray, lo: np.ndarray, hi: np.ndarray, maxstep: float
) -> np.ndarray:
    """Pull a point lying on a box edge back onto F = 0 along that edge."""
    free = np.ones(2, bool)
    free &= ~((np.abs(r - lo) <= 1e-9 * (hi - lo)) | (np.abs(r - hi) <= 1e-9 * (hi - lo)))
    x = r.copy()
    gmin = 1e-8 * conic.scale / conic.length
    for _ in range(6):
        Fx = conic.F(x)
        g = conic.half_gradient(x) * free
        gg = float(g @ g)
        if abs(Fx) <= 1e-15 * conic.scale or gg <= gmin * gmin:
            break
        x = x - Fx * g / (2 * gg)
    return x if np.linalg.norm(x - r) <= maxstep else r


def _polyline(conic: Conic, bounds: Bounds2, resolution: int) -> list[np.ndarray]:
    lo = np.asarray(bounds[0], dtype=float)
    hi = np.asarray(bounds[1], dtype=float)
    if (
        lo.shape != (2,)
        or hi.shape != (2,)
        or not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)))
    ):
        raise ValueError(f"bounds must be two finite 2-vectors, got {bounds!r}")
    if np.any(hi <= lo):
        raise ValueError(f"bounds must satisfy lo < hi in every coordinate, got {bounds!r}")
    cl = conic.classify()
    if cl.center is None:
        return []
    corners = np.array([[lo[0], lo[1]], [lo[0], hi[1]], [hi[0], lo[1]], [hi[0], hi[1]]])
    pc = (corners - cl.center) @ cl.axes
    ext = np.abs(pc).max(axis=0) * 1.0001
    out: list[np.ndarray] = []
    for P, closed in _canonical_pieces(
        cl.kind, cl.semi_axes, ext, float(pc[:, 1].max()), max(int(resolution), 8)
    ):
        W = cl.center + P @ cl.axes.T
        valid, t0, t1 = _clip_segments(W, lo, hi)
        pieces: list[list[np.ndarray]] = []
        cur: list[np.ndarray] | None = None
        prev_end = -1
        for i in np.flatnonzero(valid):
            a, d = W[i], W[i + 1] - W[i]
            s, e = a + t0[i] * d, a + t1[i] * d
            seg_len = float(np.linalg.norm(d))
            if cur is not None and t0[i] == 0.0 and prev_end == i:
                cur.append(e)
            else:
                if t0[i] > 0:
                    s = _snap_edge(conic, s, lo, hi, seg_len)
                cur = [s, e]
                pieces.append(cur)
            if t1[i] < 1.0:
                cur[-1] = _snap_edge(conic, e, lo, hi, seg_len)
                cur = None
                prev_end = -1
            else:
                prev_end = i + 1
        if closed and len(pieces) > 1:
            first_starts = valid[0] and t0[0] == 0.0
            last_ends = valid[-1] and t1[-1] == 1.0
            if first_starts and last_ends:
                pieces[0] = pieces[-1] + pieces[0][1:]
                pieces.pop()
        out.extend(np.array(pc_) for pc_ in pieces if len(pc_) >= 2)
    return out


def _spec(
    id: str, title: str, build: Callable[..., Conic], equation: str, **defaults: float
) -> CurveType:
    return CurveType(id, title, tuple(defaults), dict(defaults), build, equation)


#: The curve types a user picks by id; each takes its parameters plus ``center``.
CONSTRUCTORS: dict[str, CurveType] = {
    s.id: s
    for s in (
        _spec("circle", "circle", Conic.circle, "x² + y² = R²", R=1.0),
        _spec("ellipse", "ellipse", Conic.ellipse, "x²/a² + y²/b² = 1", a=2.0, b=1.0),
        _spec("parabola", "parabola", Conic.parabola, "y = x²/a²", a=1.0),
        _spec("hyperbola", "hyperbola", Conic.hyperbola, "x²/a² - y²/b² = 1", a=1.0, b=1.0),
    )
}
