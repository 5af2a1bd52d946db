"""Second-order surfaces (quadrics) in the textbook's notation, eq. (1.42).

    F(x, y, z) = a11 x² + a22 y² + a33 z² + 2 a12 xy + 2 a23 yz + 2 a31 zx
               + 2 a14 x + 2 a24 y + 2 a34 z + a44 = 0                      (1.42)

The textbook writes the xz cross coefficient as ``a31`` (not ``a13``), the linear
coefficients as ``a14, a24, a34`` and the constant as ``a44``; this module keeps that
indexing (DESIGN.md §3 item 1).  In matrix form F = rᵀQr + 2bᵀr + c with

    Q = [[a11, a12, a31], [a12, a22, a23], [a31, a23, a33]],  b = (a14, a24, a34),  c = a44,

so the half gradient ½∇F = Q r + b is exactly the bracket of (1.45):
F_x = 2(a11 x + a12 y + a31 z + a14), F_y = 2(a22 y + a12 x + a23 z + a24),
F_z = 2(a33 z + a23 y + a31 x + a34).  The analyzer (1.50) integrates with ½∇F.

Besides evaluation the module classifies a quadric (every real affine type,
degenerate ones included), finds the nearest point on it and meshes it inside a box.
The dimension-free algebra (principal-axis reduction, nearest point) lives in the
private helpers at the end and is shared with :mod:`lessons.core.conic`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cached_property, lru_cache
from typing import Any

import numpy as np
import sympy as sp

COEFF_NAMES: tuple[str, ...] = (
    "a11",
    "a22",
    "a33",
    "a12",
    "a23",
    "a31",
    "a14",
    "a24",
    "a34",
    "a44",
)

Vec3 = Sequence[float]
Bounds = tuple[tuple[float, float, float], tuple[float, float, float]]

#: Relative tolerance of the classification (zero eigenvalues, zero constants).
CLASSIFY_RTOL = 1e-9


def _fmt(v: float) -> str:
    return f"{v:g}"


def _at(center: Vec3) -> str:
    c = tuple(float(v) for v in center)
    return "" if not any(c) else " at (" + ", ".join(_fmt(v) for v in c) + ")"


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def _center3(center: Vec3) -> np.ndarray:
    c = np.asarray(center, dtype=float).reshape(-1)
    if c.shape != (3,) or not np.all(np.isfinite(c)):
        raise ValueError(f"center must be three finite numbers, got {center!r}")
    return c


def sym_number(v: float) -> sp.Expr:
    """A float as sympy number: an exact Rational when ``v`` is (to 1e-12 relative) a
    fraction with denominator <= 10⁶ (0.01 -> 1/100, 0.5 -> 1/2), else a Float."""
    if v == 0.0:
        return sp.Integer(0)
    fr = Fraction(v).limit_denominator(10**6)
    if abs(float(fr) - v) <= 1e-12 * abs(v):
        return sp.Rational(fr.numerator, fr.denominator)
    return sp.Float(v)


@dataclass(frozen=True)
class Classification:
    """The affine type of a quadric (or conic) and its principal frame.

    ``kind`` is a type id: the constructor ids (``"sphere"``, ``"ellipsoid"``,
    ``"elliptic-cylinder"``, ``"elliptic-cone"``, ``"elliptic-paraboloid"``,
    ``"hyperbolic-paraboloid"``, ``"hyperboloid-1"``, ``"hyperboloid-2"``) or a
    degenerate one (``"hyperbolic-cylinder"``, ``"parabolic-cylinder"``,
    ``"intersecting-planes"``, ``"parallel-planes"``, ``"coincident-planes"``,
    ``"plane"``, ``"line"``, ``"point"``, ``"empty"``, ``"all-space"``).

    ``axes`` is a rotation (det +1) whose columns are the principal directions; in
    p = axesᵀ(r - center) the surface has the canonical form of its kind, with the
    distinguished axis (axis of a cylinder, cone, paraboloid or hyperboloid; the
    normal of planes) as the LAST coordinate:

    ======================  ===========================================  ===========
    kind                    canonical form in p = (x, y, z)               semi_axes
    ======================  ===========================================  ===========
    sphere, ellipsoid       x²/a² + y²/b² + z²/c² = 1                    (a, b, c)
    hyperboloid-1 / -2      x²/a² + y²/b² - z²/c² = 1 / -1               (a, b, c)
    elliptic-cone           x²/a² + y²/b² - z²/c² = 0 (scale-free: c=1)  (a, b, 1)
    elliptic-cylinder       x²/a² + y²/b² = 1                            (a, b)
    hyperbolic-cylinder     x²/a² - y²/b² = 1                            (a, b)
    intersecting-planes     x²/a² - y²/b² = 0 (b=1)                      (a, 1)
    line                    x²/a² + y²/b² = 0 (the z axis, b=1)          (a, 1)
    elliptic-paraboloid     z = x²/a² + y²/b²                            (a, b)
    hyperbolic-paraboloid   z = x²/a² - y²/b²                            (a, b)
    parabolic-cylinder      z = x²/a²                                    (a,)
    parallel-planes         z² = d²                                      (d,)
    coincident-planes,      z = 0                                        ()
    plane
    point                   x²/a² + y²/b² + z²/c² = 0 (imaginary cone)   (a, b, 1)
    ======================  ===========================================  ===========

    ``center`` is the centre (central kinds), the vertex (paraboloids, parabolic
    cylinder), the point of the origin's nearest axis point (cylinders, lines), a
    point of the plane (planes), or None (``empty``, ``all-space``).
    For conics the same holds in 2-D (see :mod:`lessons.core.conic`).
    """

    kind: str
    name: str
    degenerate: bool
    center: np.ndarray | None
    axes: np.ndarray
    semi_axes: tuple[float, ...] = ()
    rank: int = 0  # rank of Q

    @property
    def vertex(self) -> np.ndarray | None:
        """Alias of ``center`` (reads better for paraboloids)."""
        return self.center

    @property
    def empty(self) -> bool:
        return self.kind == "empty"


@dataclass(frozen=True)
class SurfaceType:
    """One entry of :data:`CONSTRUCTORS`: calling it builds the quadric."""

    id: str
    title: str
    params: tuple[str, ...]
    defaults: dict[str, float]
    build: Callable[..., Quadric]
    equation: str = ""

    def __call__(self, *args: Any, **kwargs: Any) -> Quadric:
        return self.build(*args, **kwargs)


@dataclass(frozen=True)
class Quadric:
    """The quadric (1.42) with the textbook's coefficient names."""

    a11: float = 0.0
    a22: float = 0.0
    a33: float = 0.0
    a12: float = 0.0
    a23: float = 0.0
    a31: float = 0.0
    a14: float = 0.0
    a24: float = 0.0
    a34: float = 0.0
    a44: float = 0.0
    label: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        bad = []
        for n in COEFF_NAMES:
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
            raise ValueError("quadric coefficients must be finite: " + ", ".join(bad))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_coeffs(cls, label: str = "", **coeffs: float) -> Quadric:
        """Build from named coefficients (missing ones are 0).

        Unknown names raise ValueError naming them (e.g. ``a13``: the textbook's xz
        coefficient is ``a31``); non-finite values raise ValueError."""
        unknown = sorted(set(coeffs) - set(COEFF_NAMES))
        if unknown:
            hint = " (the xz coefficient is a31)" if "a13" in unknown else ""
            raise ValueError(
                f"unknown quadric coefficient(s) {', '.join(unknown)}{hint}; expected names from "
                + ", ".join(COEFF_NAMES)
            )
        return cls(**{k: float(v) for k, v in coeffs.items()}, label=label)

    @classmethod
    def from_matrices(
        cls, Q: np.ndarray, b: Vec3 = (0, 0, 0), c: float = 0.0, label: str = ""
    ) -> Quadric:
        """Build from F = rᵀQr + 2bᵀr + c (Q is symmetrised)."""
        Q = np.asarray(Q, dtype=float)
        if Q.shape != (3, 3):
            raise ValueError(f"Q must be 3x3, got shape {Q.shape}")
        Q = 0.5 * (Q + Q.T)
        b = np.asarray(b, dtype=float).reshape(3)
        return cls(
            a11=Q[0, 0],
            a22=Q[1, 1],
            a33=Q[2, 2],
            a12=Q[0, 1],
            a23=Q[1, 2],
            a31=Q[0, 2],
            a14=b[0],
            a24=b[1],
            a34=b[2],
            a44=float(c),
            label=label,
        )

    @classmethod
    def _canonical(cls, diag: Vec3, lin: Vec3, const: float, center: Vec3, label: str) -> Quadric:
        q = cls.from_matrices(np.diag(diag), lin, const, label=label)
        return q.translated(_center3(center)) if np.any(_center3(center)) else q

    @classmethod
    def sphere(cls, R: float = 1.0, center: Vec3 = (0, 0, 0)) -> Quadric:
        """x² + y² + z² - R² = 0 (shifted to ``center``)."""
        R = _positive("R", R)
        return cls._canonical(
            (1, 1, 1), (0, 0, 0), -R * R, center, f"sphere R={_fmt(R)}{_at(center)}"
        )

    @classmethod
    def ellipsoid(
        cls, a: float = 3.0, b: float = 2.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² + z²/c² - 1 = 0 (the form of (1.63))."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, 1 / c**2),
            (0, 0, 0),
            -1.0,
            center,
            f"ellipsoid a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    @classmethod
    def elliptic_cylinder(cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)) -> Quadric:
        """x²/a² + y²/b² - 1 = 0, axis z."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, 1 / b**2, 0),
            (0, 0, 0),
            -1.0,
            center,
            f"elliptic cylinder a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def elliptic_cone(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² - z²/c² = 0, apex at ``center``, axis z."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, -1 / c**2),
            (0, 0, 0),
            0.0,
            center,
            f"elliptic cone a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    @classmethod
    def elliptic_paraboloid(
        cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """z = x²/a² + y²/b², i.e. x²/a² + y²/b² - z = 0 (a34 = -1/2); vertex at ``center``."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, 1 / b**2, 0),
            (0, 0, -0.5),
            0.0,
            center,
            f"elliptic paraboloid a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def hyperbolic_paraboloid(
        cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """z = x²/a² - y²/b² (saddle), i.e. x²/a² - y²/b² - z = 0; saddle point at ``center``."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, -1 / b**2, 0),
            (0, 0, -0.5),
            0.0,
            center,
            f"hyperbolic paraboloid a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def hyperboloid_one_sheet(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² - z²/c² - 1 = 0, axis z."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, -1 / c**2),
            (0, 0, 0),
            -1.0,
            center,
            f"hyperboloid of one sheet a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    @classmethod
    def hyperboloid_two_sheets(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² - z²/c² + 1 = 0, axis z (sheets z >= c and z <= -c)."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, -1 / c**2),
            (0, 0, 0),
            1.0,
            center,
            f"hyperboloid of two sheets a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    # degenerate types (not in CONSTRUCTORS; handy for tests and demonstrations)
    @classmethod
    def hyperbolic_cylinder(
        cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² - y²/b² - 1 = 0, axis z."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, -1 / b**2, 0),
            (0, 0, 0),
            -1.0,
            center,
            f"hyperbolic cylinder a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def parabolic_cylinder(cls, a: float = 1.0, center: Vec3 = (0, 0, 0)) -> Quadric:
        """z = x²/a², rulings along y."""
        a = _positive("a", a)
        return cls._canonical(
            (1 / a**2, 0, 0),
            (0, 0, -0.5),
            0.0,
            center,
            f"parabolic cylinder a={_fmt(a)}{_at(center)}",
        )

    @classmethod
    def plane(cls, normal: Vec3 = (0, 0, 1), point: Vec3 = (0, 0, 0)) -> Quadric:
        """n·(r - r0) = 0 written as 2·(n/2)·r - n·r0 = 0."""
        n = np.asarray(normal, dtype=float).reshape(3)
        if not np.all(np.isfinite(n)) or np.linalg.norm(n) == 0:
            raise ValueError(f"plane normal must be a finite non-zero vector, got {normal!r}")
        p = _center3(point)
        return cls.from_matrices(np.zeros((3, 3)), n / 2, -float(n @ p), label="plane")

    # ------------------------------------------------------------------ matrices
    def coeffs(self) -> dict[str, float]:
        """The ten coefficients by their textbook names."""
        return {n: float(getattr(self, n)) for n in COEFF_NAMES}

    @property
    def Q(self) -> np.ndarray:
        """Symmetric 3x3 matrix of the quadratic part."""
        return np.array(
            [
                [self.a11, self.a12, self.a31],
                [self.a12, self.a22, self.a23],
                [self.a31, self.a23, self.a33],
            ],
            dtype=float,
        )

    @property
    def b(self) -> np.ndarray:
        """Linear part (a14, a24, a34) (half of the linear coefficients of F)."""
        return np.array([self.a14, self.a24, self.a34], dtype=float)

    @property
    def c(self) -> float:
        """Constant a44."""
        return float(self.a44)

    @property
    def matrix4(self) -> np.ndarray:
        """The 4x4 extended matrix [[Q, b], [bᵀ, c]]: F = [r,1]ᵀ E [r,1]."""
        E = np.zeros((4, 4))
        E[:3, :3] = self.Q
        E[:3, 3] = E[3, :3] = self.b
        E[3, 3] = self.c
        return E

    # ------------------------------------------------------------------ evaluation
    def F(self, points: np.ndarray | Vec3) -> np.ndarray | float:
        """F at points of shape (..., 3) (= rᵀQr + 2bᵀr + c); a float for one point."""
        r = np.asarray(points, dtype=float)
        x, y, z = r[..., 0], r[..., 1], r[..., 2]
        v = (
            x * (self.a11 * x + 2.0 * (self.a12 * y + self.a31 * z + self.a14))
            + y * (self.a22 * y + 2.0 * (self.a23 * z + self.a24))
            + z * (self.a33 * z + 2.0 * self.a34)
            + self.a44
        )
        return float(v) if np.ndim(v) == 0 else v

    def half_gradient(self, points: np.ndarray | Vec3) -> np.ndarray:
        """½∇F = Q r + b at points (..., 3) -> (..., 3): the brackets of (1.45)."""
        r = np.asarray(points, dtype=float)
        x, y, z = r[..., 0], r[..., 1], r[..., 2]
        return np.stack(
            [
                self.a11 * x + self.a12 * y + self.a31 * z + self.a14,
                self.a22 * y + self.a12 * x + self.a23 * z + self.a24,
                self.a33 * z + self.a23 * y + self.a31 * x + self.a34,
            ],
            axis=-1,
        )

    def gradient(self, points: np.ndarray | Vec3) -> np.ndarray:
        """∇F = 2(Q r + b), (1.45)."""
        return 2.0 * self.half_gradient(points)

    def sym(
        self, x: sp.Symbol | None = None, y: sp.Symbol | None = None, z: sp.Symbol | None = None
    ) -> sp.Expr:
        """F as a sympy expression in x, y, z (default real symbols x, y, z).

        Coefficients become exact Rationals when they are (to 1e-12 relative) fractions
        with denominator <= 10⁶ (1/a² with a = 10 -> 1/100); otherwise sympy Floats."""
        x = x if x is not None else sp.Symbol("x", real=True)
        y = y if y is not None else sp.Symbol("y", real=True)
        z = z if z is not None else sp.Symbol("z", real=True)
        k = {n: sym_number(getattr(self, n)) for n in COEFF_NAMES}
        return (
            k["a11"] * x**2
            + k["a22"] * y**2
            + k["a33"] * z**2
            + 2 * k["a12"] * x * y
            + 2 * k["a23"] * y * z
            + 2 * k["a31"] * z * x
            + 2 * k["a14"] * x
            + 2 * k["a24"] * y
            + 2 * k["a34"] * z
            + k["a44"]
        )

    # ------------------------------------------------------------------ transforms
    def level_through(self, point: Vec3) -> Quadric:
        """Same quadratic and linear part, a44 chosen so that F(point) = 0.

        The analyzer (1.50) keeps F constant, so this is the surface it actually
        traces from ``point`` (e.g. the ellipsoid with semi-axes 100, 50, 10 through
        (0, 50, 0) for a = 10, b = 5, c = 1)."""
        p = _center3(point)
        a44 = -float(self.F(p) - self.a44)
        lab = f"{self.label} through ({', '.join(_fmt(v) for v in p)})" if self.label else ""
        return Quadric(**{**self.coeffs(), "a44": a44}, label=lab)

    def with_coeffs(self, **changes: float) -> Quadric:
        """A copy with some coefficients replaced (same name checks as from_coeffs)."""
        return Quadric.from_coeffs(label=self.label, **{**self.coeffs(), **changes})

    def translated(self, t: Vec3) -> Quadric:
        """The surface moved by ``t``: G(r) = F(r - t)."""
        t = _center3(t)
        Q, b = self.Q, self.b
        return Quadric.from_matrices(
            Q, b - Q @ t, float(t @ Q @ t - 2 * b @ t + self.c), label=self.label
        )

    def rotated(self, R: np.ndarray) -> Quadric:
        """The surface rotated by R about the origin: G(r) = F(Rᵀ r)."""
        R = np.asarray(R, dtype=float)
        return Quadric.from_matrices(R @ self.Q @ R.T, R @ self.b, self.c, label=self.label)

    def transformed(self, R: np.ndarray, t: Vec3 = (0, 0, 0)) -> Quadric:
        """The surface mapped by r -> R r + t (rotation then translation)."""
        return self.rotated(R).translated(t)

    def scaled(self, k: float) -> Quadric:
        """Same surface, F multiplied by k != 0."""
        if not math.isfinite(k) or k == 0:
            raise ValueError("the factor must be finite and non-zero")
        return Quadric(**{n: k * v for n, v in self.coeffs().items()}, label=self.label)

    # ------------------------------------------------------------------ classification
    @cached_property
    def _classification(self) -> Classification:
        return _classify3(self.Q, self.b, self.c)

    def classify(self) -> Classification:
        """The affine type, centre/vertex, principal frame and semi-axes (see
        :class:`Classification`); relative tolerance :data:`CLASSIFY_RTOL`."""
        return self._classification

    def project(self, point: Vec3, max_iter: int = 30) -> np.ndarray:
        """The nearest point of F = 0 to ``point`` (closest-point problem solved through
        its Lagrange multiplier, see :func:`_nearest_point`); |F| <= 1e-12·scale.

        ValueError if the surface has no real points, or if ``point`` is a singular
        point of F (½∇F = 0: a centre or axis point) that is not on the surface, where
        the nearest point is not unique."""
        p = _center3(point)
        cl = self._classification
        if cl.kind == "empty":
            raise ValueError(f"the surface has no real points ({cl.name}); nothing to project on")
        if cl.kind == "all-space":
            return p.copy()
        Fp = self.F(p)
        if abs(Fp) <= 1e-14 * self.scale:
            return p.copy()
        g = self.half_gradient(p)
        gscale = float(np.linalg.norm(self.Q, 2)) * (
            float(np.linalg.norm(p)) + self.length
        ) + float(np.linalg.norm(self.b))
        if np.linalg.norm(g) <= 1e-12 * gscale and cl.kind not in (
            "point",
            "line",
            "coincident-planes",
        ):
            raise ValueError(
                f"the point {tuple(float(v) for v in p)} is a singular point of F (zero gradient: "
                f"a centre or axis of the {cl.name}) and not on the surface; its nearest point is not unique"
            )
        return (
            _project_affine(cl, p)
            if cl.kind in ("point", "line", "coincident-planes")
            else _nearest_point(self.Q, self.b, self.c, p, self.scale, max_iter)
        )

    def mesh(self, bounds: Bounds | None = None, resolution: int = 48):
        """A trimesh.Trimesh of F = 0 clipped to ``bounds`` (default :meth:`default_bounds`).

        Built parametrically in the principal frame of :meth:`classify` (an icosphere
        scaled by the semi-axes for ellipsoids; (cosh, sinh) / polar / planar grids
        with ``resolution`` samples per parameter otherwise), mapped to world
        coordinates, clipped by the six box planes; vertices cut by the box are pulled
        back onto F = 0 inside their box face; faces are oriented along ∇F.  Empty
        (zero faces) for types with no area: empty, point, line, all-space."""
        return _mesh_quadric(
            self, bounds if bounds is not None else self.default_bounds(), resolution
        )

    @cached_property
    def length(self) -> float:
        """Characteristic length L = |centre| + the largest semi-axis (1 when the type
        has no semi-axes; |centre| = 0 when there is no centre)."""
        cl = self._classification
        size = max((s for s in cl.semi_axes if s > 0), default=1.0)
        off = float(np.linalg.norm(cl.center)) if cl.center is not None else 0.0
        return off + size

    @cached_property
    def scale(self) -> float:
        """Typical magnitude of the terms of F near the surface, for relative tolerances:
        max(|a44|, ‖Q‖₂ L², ‖b‖ L) with L = :attr:`length` (1 if all vanish).
        Round-off of F at a surface point is ~1e-16 * scale."""
        L = self.length
        v = max(
            abs(self.c), float(np.linalg.norm(self.Q, 2)) * L * L, float(np.linalg.norm(self.b)) * L
        )
        return v if v > 0 else 1.0

    def default_bounds(self) -> Bounds:
        """A box ((x0, y0, z0), (x1, y1, z1)) showing the surface: the bounding box of
        an ellipsoid + 15 %; for unbounded types a cube of half-size 2·(largest
        semi-axis) about the centre (shifted along the axis for paraboloids)."""
        cl = self._classification
        if cl.kind in ("ellipsoid", "sphere"):
            half = np.sqrt(((cl.axes * np.asarray(cl.semi_axes)) ** 2).sum(axis=1)) * 1.15
            lo, hi = cl.center - half, cl.center + half
        else:
            c0 = cl.center if cl.center is not None else np.zeros(3)
            size = max((s for s in cl.semi_axes if s > 0), default=1.0)
            H = 2.0 * size
            if cl.kind in ("elliptic-paraboloid", "parabolic-cylinder"):
                c0 = c0 + cl.axes[:, 2] * 0.8 * H
            lo, hi = c0 - H, c0 + H
        return (tuple(float(v) for v in lo), tuple(float(v) for v in hi))  # type: ignore[return-value]


def _spec(
    id: str, title: str, build: Callable[..., Quadric], equation: str, **defaults: float
) -> SurfaceType:
    return SurfaceType(id, title, tuple(defaults), dict(defaults), build, equation)


#: The surface types a user picks by id; each takes its parameters plus ``center``.
CONSTRUCTORS: dict[str, SurfaceType] = {
    s.id: s
    for s in (
        _spec("sphere", "sphere", Quadric.sphere, "x² + y² + z² = R²", R=1.0),
        _spec(
            "ellipsoid",
            "ellipsoid",
            Quadric.ellipsoid,
            "x²/a² + y²/b² + z²/c² = 1",
            a=3.0,
            b=2.0,
            c=1.0,
        ),
        _spec(
            "elliptic-cylinder",
            "elliptic cylinder",
            Quadric.elliptic_cylinder,
            "x²/a² + y²/b² = 1",
            a=1.0,
            b=1.0,
        ),
        _spec(
            "elliptic-cone",
            "elliptic cone",
            Quadric.elliptic_cone,
            "x²/a² + y²/b² - z²/c² = 0",
            a=1.0,
            b=1.0,
            c=1.0,
        ),
        _spec(
            "elliptic-paraboloid",
            "elliptic paraboloid",
            Quadric.elliptic_paraboloid,
            "z = x²/a² + y²/b²",
            a=1.0,
            b=1.0,
        ),
        _spec(
            "hyperbolic-paraboloid",
            "hyperbolic paraboloid",
            Quadric.hyperbolic_paraboloid,
            "z = x²/a² - y²/b²",
            a=1.0,
            b=1.0,
        ),
        _spec(
            "hyperboloid-1",
            "hyperboloid of one sheet",
            Quadric.hyperboloid_one_sheet,
            "x²/a² + y²/b² - z²/c² = 1",
            a=1.0,
            b=1.0,
            c=1.0,
        ),
        _spec(
            "hyperboloid-2",
            "hyperboloid of two sheets",
            Quadric.hyperboloid_two_sheets,
            "x²/a² + y²/b² - z²/c² = -1",
            a=1.0,
            b=1.0,
            c=1.0,
        ),
    )
}


# ====================================================================== n-D algebra
@dataclass(frozen=True)
class _Reduced:
    """Principal-axis reduction of F = rᵀQr + 2bᵀr + c in n dimensions.

    In r = point + V_nz y + n s (+ free null directions):
        F = Σ lam_i y_i² + 2 g s + k          (g = 0: central, k = constant)
    """

    lam: np.ndarray  # non-zero eigenvalues
    V: np.ndarray  # (n, m) their eigenvectors
    null: np.ndarray  # (n, n-m) orthonormal basis of the null space of Q
    g: float  # > 0 for the parabolic case, else 0
    n_dir: np.ndarray | None  # unit direction of the linear term in the null space
    k: float  # constant after completing squares (central case), 0 when parabolic
    point: np.ndarray  # centre / vertex / min-norm point


def _reduce(Q: np.ndarray, b: np.ndarray, c: float, rtol: float = CLASSIFY_RTOL) -> _Reduced:
    n = Q.shape[0]
    lam, V = np.linalg.eigh(Q)
    lmax = float(np.max(np.abs(lam))) if lam.size else 0.0
    nz = np.abs(lam) > rtol * lmax if lmax > 0 else np.zeros(n, bool)
    beta = V.T @ b
    lam_nz, V_nz, V0 = lam[nz], V[:, nz], V[:, ~nz]
    y0 = -beta[nz] / lam_nz
    point = V_nz @ y0
    cancel = abs(c) + float(np.sum(beta[nz] ** 2 / np.abs(lam_nz)))
    k = c - float(np.sum(beta[nz] ** 2 / lam_nz))
    beta0 = V0.T @ b
    g = float(np.linalg.norm(beta0))
    bn = float(np.linalg.norm(b))
    if V0.shape[1] and bn > 0 and g > rtol * bn and g > 1e-14 * max(lmax, bn, abs(c)):
        n_dir = V0 @ beta0 / g
        s0 = -k / (2 * g)
        return _Reduced(lam_nz, V_nz, V0, g, n_dir, 0.0, point + n_dir * s0)
    if abs(k) <= rtol * cancel:
        k = 0.0
    return _Reduced(lam_nz, V_nz, V0, 0.0, None, k, point)


def _right_handed(cols: list[np.ndarray]) -> np.ndarray:
    A = np.column_stack(cols)
    if np.linalg.det(A) < 0:
        A[:, 0] = -A[:, 0]
    return A


def _orth_complement(basis: np.ndarray, dim: int) -> np.ndarray:
    """Orthonormal basis of the complement of span(basis columns) in R^dim."""
    if basis.size == 0:
        return np.eye(dim)
    u, s, _ = np.linalg.svd(basis, full_matrices=True)
    r = int(np.sum(s > 1e-12))
    return u[:, r:]


_NAMES3 = {
    "sphere": "sphere",
    "ellipsoid": "ellipsoid",
    "hyperboloid-1": "hyperboloid of one sheet",
    "hyperboloid-2": "hyperboloid of two sheets",
    "elliptic-cone": "elliptic cone",
    "elliptic-cylinder": "elliptic cylinder",
    "hyperbolic-cylinder": "hyperbolic cylinder",
    "parabolic-cylinder": "parabolic cylinder",
    "elliptic-paraboloid": "elliptic paraboloid",
    "hyperbolic-paraboloid": "hyperbolic paraboloid",
    "intersecting-planes": "pair of intersecting planes",
    "parallel-planes": "pair of parallel planes",
    "coincident-planes": "plane counted twice (coincident planes)",
    "plane": "plane",
    "line": "line (imaginary intersecting planes)",
    "point": "point (imaginary cone)",
    "empty": "no real points",
    "all-space": "F is identically zero",
}
_NONDEGENERATE3 = {
    "sphere",
    "ellipsoid",
    "hyperboloid-1",
    "hyperboloid-2",
    "elliptic-cone",
    "elliptic-cylinder",
    "elliptic-paraboloid",
    "hyperbolic-paraboloid",
}


def _close_rel(u: float, v: float, rtol: float = 1e-9) -> bool:
    return abs(u - v) <= rtol * max(abs(u), abs(v))


def _classify3(Q: np.ndarray, b: np.ndarray, c: float) -> Classification:
    red = _reduce(Q, b, c)
    lam, V = red.lam, red.V
    m = lam.size
    semi: tuple[float, ...] = ()
    name_extra = ""

    def result(
        kind: str, cols: list[np.ndarray] | None, center: np.ndarray | None
    ) -> Classification:
        axes = _right_handed(cols) if cols is not None else np.eye(3)
        nm = _NAMES3[kind] + name_extra
        return Classification(kind, nm, kind not in _NONDEGENERATE3, center, axes, semi, m)

    if red.g > 0:  # parabolic types: Σ lam_i y_i² + 2 g s = 0  ->  s = Σ kappa_i y_i²
        n = red.n_dir
        kappa = -lam / (2 * red.g)
        if m == 2:
            if np.all(kappa < 0) or (
                kappa[0] * kappa[1] < 0 and abs(kappa.max()) > abs(kappa.min())
            ):
                n, kappa = -n, -kappa  # open towards +n; saddle: a >= b
            if kappa[0] * kappa[1] > 0:
                order = np.argsort(kappa)  # a >= b
                semi = tuple(float(1 / math.sqrt(kappa[i])) for i in order)
                return result("elliptic-paraboloid", [V[:, order[0]], V[:, order[1]], n], red.point)
            ip, ineg = (0, 1) if kappa[0] > 0 else (1, 0)
            semi = (float(1 / math.sqrt(kappa[ip])), float(1 / math.sqrt(-kappa[ineg])))
            return result("hyperbolic-paraboloid", [V[:, ip], V[:, ineg], n], red.point)
        if m == 1:
            if kappa[0] < 0:
                n, kappa = -n, -kappa
            v = V[:, 0]
            semi = (float(1 / math.sqrt(kappa[0])),)
            return result("parabolic-cylinder", [v, np.cross(n, v), n], red.point)
        comp = _orth_complement(n[:, None], 3)
        return result("plane", [comp[:, 0], comp[:, 1], n], red.point)

    k = red.k
    if m == 3:
        if k != 0:
            mu = -lam / k
            npos = int(np.sum(mu > 0))
            if npos == 3:
                order = np.argsort(mu)  # a >= b >= c
                semi = tuple(float(1 / math.sqrt(mu[i])) for i in order)
                kind = "sphere" if _close_rel(semi[0], semi[2]) else "ellipsoid"
                return result(kind, [V[:, i] for i in order], red.point)
            if npos in (1, 2):
                odd = int(np.argmin(mu)) if npos == 2 else int(np.argmax(mu))
                rest = [i for i in np.argsort(np.abs(mu)) if i != odd]  # a >= b
                semi = tuple(float(1 / math.sqrt(abs(mu[i]))) for i in rest + [odd])
                return result(
                    "hyperboloid-1" if npos == 2 else "hyperboloid-2",
                    [V[:, i] for i in rest + [odd]],
                    red.point,
                )
            name_extra = " (imaginary ellipsoid)"
            return result("empty", None, None)
        npos = int(np.sum(lam > 0))
        if npos in (0, 3):
            order = np.argsort(np.abs(lam))
            semi = tuple(float(math.sqrt(abs(lam[order[2]]) / abs(lam[i]))) for i in order)
            return result("point", [V[:, i] for i in order], red.point)
        odd = int(np.argmin(lam)) if npos == 2 else int(np.argmax(lam))
        rest = [i for i in np.argsort(np.abs(lam)) if i != odd]
        semi = tuple(float(math.sqrt(abs(lam[odd]) / abs(lam[i]))) for i in rest) + (1.0,)
        return result("elliptic-cone", [V[:, i] for i in rest + [odd]], red.point)
    if m == 2:
        axis = red.null[:, 0]
        if k != 0:
            mu = -lam / k
            if np.all(mu > 0):
                order = np.argsort(mu)
                semi = tuple(float(1 / math.sqrt(mu[i])) for i in order)
                return result(
                    "elliptic-cylinder", [V[:, order[0]], V[:, order[1]], axis], red.point
                )
            if np.all(mu < 0):
                name_extra = " (imaginary elliptic cylinder)"
                return result("empty", None, None)
            ip, ineg = (0, 1) if mu[0] > 0 else (1, 0)
            semi = (float(1 / math.sqrt(mu[ip])), float(1 / math.sqrt(-mu[ineg])))
            return result("hyperbolic-cylinder", [V[:, ip], V[:, ineg], axis], red.point)
        if lam[0] * lam[1] > 0:
            order = np.argsort(np.abs(lam))
            semi = (float(math.sqrt(abs(lam[order[1]] / lam[order[0]]))), 1.0)
            return result("line", [V[:, order[0]], V[:, order[1]], axis], red.point)
        ip, ineg = (0, 1) if lam[0] > 0 else (1, 0)
        semi = (float(math.sqrt(abs(lam[ineg] / lam[ip]))), 1.0)
        return result("intersecting-planes", [V[:, ip], V[:, ineg], axis], red.point)
    if m == 1:
        v = V[:, 0]
        cols = [red.null[:, 0], red.null[:, 1], v]
        if k == 0:
            return result("coincident-planes", cols, red.point)
        if k / lam[0] < 0:
            semi = (float(math.sqrt(-k / lam[0])),)
            return result("parallel-planes", cols, red.point)
        name_extra = " (imaginary parallel planes)"
        return result("empty", None, None)
    if k == 0:
        return result("all-space", None, None)
    name_extra = " (F is a non-zero constant)"
    return result("empty", None, None)


def _nearest_point(
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


def _project_affine(cl: Classification, p: np.ndarray) -> np.ndarray:
    """Orthogonal projection onto a point, a line (3-D: along the last principal axis)
    or a doubled plane / doubled line (the last principal axis is its normal)."""
    if cl.kind == "point":
        return np.array(cl.center, dtype=float)
    A = cl.axes[:, -1:] if cl.kind == "line" else cl.axes[:, :-1]
    return cl.center + A @ (A.T @ (p - cl.center))


# ====================================================================== meshing
@lru_cache(maxsize=8)
def _icosphere(sub: int) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    ico = trimesh.creation.icosphere(subdivisions=sub)
    return np.array(ico.vertices), np.array(ico.faces)


def _grid_faces(nu: int, nv: int) -> np.ndarray:
    i, j = np.meshgrid(np.arange(nu - 1), np.arange(nv - 1), indexing="ij")
    a = (i * nv + j).ravel()
    b, c, d = a + nv, a + nv + 1, a + 1
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def _patch(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A parametric grid (nu, nv, 3) -> (vertices, faces)."""
    nu, nv = P.shape[:2]
    return P.reshape(-1, 3), _grid_faces(nu, nv)


def _canonical_patches(
    kind: str, semi: tuple[float, ...], ext: np.ndarray, zhi: float, n: int
) -> list:
    """Parametric patches of the canonical surface of ``kind`` covering the box
    |x| <= X, |y| <= Y, |z| <= Z (ext = (X, Y, Z); zhi = largest z of the box)."""

    X, Y, Z = (float(v) for v in ext)
    v = np.linspace(0.0, 2 * np.pi, n + 1)
    out = []
    if kind in ("sphere", "ellipsoid"):
        sub = int(np.clip(round(math.log2(max(n, 2) / 3)), 1, 6))
        iv, ifc = _icosphere(sub)
        out.append((iv * np.asarray(semi), ifc))
        return out
    if kind in (
        "hyperboloid-1",
        "hyperboloid-2",
        "elliptic-cone",
        "elliptic-cylinder",
        "elliptic-paraboloid",
    ):
        a, b = semi[0], semi[1]
        M = math.hypot(X / a, Y / b)  # x²/a² + y²/b² <= M² inside the box
        if kind == "hyperboloid-1":
            c = semi[2]
            if M <= 1:
                return out
            U = math.asinh(min(Z, c * math.sqrt(M * M - 1)) / c)
            u = np.linspace(-U, U, n)
            s, z = np.cosh(u), c * np.sinh(u)
        elif kind == "elliptic-cylinder":
            s, z = np.ones(n), np.linspace(-Z, Z, n)
        elif kind == "elliptic-cone":
            s = np.linspace(-min(Z, M), min(Z, M), n)
            z = s
        elif kind == "elliptic-paraboloid":
            rmax = min(math.sqrt(max(zhi, 0.0)), M)
            s = np.linspace(0.0, rmax, n)
            z = s * s
        else:  # hyperboloid-2
            c = semi[2]
            if Z <= c:
                return out
            U = math.asinh(min(M, math.sqrt((Z / c) ** 2 - 1)))
            u = np.linspace(0.0, U, n // 2 + 1)
            for sign in (1.0, -1.0):
                S, Vv = np.meshgrid(np.sinh(u), v, indexing="ij")
                Zz = sign * c * np.cosh(u)[:, None] * np.ones_like(Vv)
                P = np.stack([a * S * np.cos(Vv), b * S * np.sin(Vv), Zz], -1)
                out.append(_patch(P))
            return out
        S, Vv = np.meshgrid(s, v, indexing="ij")
        Zz = np.broadcast_to(z[:, None], S.shape)
        out.append(_patch(np.stack([a * S * np.cos(Vv), b * S * np.sin(Vv), Zz], -1)))
        return out
    if kind == "hyperbolic-cylinder":
        a, b = semi
        if X <= a:
            return out
        U = math.asinh(min(Y / b, math.sqrt((X / a) ** 2 - 1)))
        u, z = np.linspace(-U, U, n), np.linspace(-Z, Z, n)
        Uu, Zz = np.meshgrid(u, z, indexing="ij")
        for sign in (1.0, -1.0):
            out.append(_patch(np.stack([sign * a * np.cosh(Uu), b * np.sinh(Uu), Zz], -1)))
        return out
    if kind == "hyperbolic-paraboloid":
        a, b = semi
        Uu, Ww = np.meshgrid(
            np.linspace(-X / a, X / a, n), np.linspace(-Y / b, Y / b, n), indexing="ij"
        )
        out.append(_patch(np.stack([a * Uu, b * Ww, Uu**2 - Ww**2], -1)))
        return out
    if kind == "parabolic-cylinder":
        (a,) = semi
        umax = min(X / a, math.sqrt(max(zhi, 0.0)))
        Uu, Yy = np.meshgrid(np.linspace(-umax, umax, n), np.linspace(-Y, Y, n), indexing="ij")
        out.append(_patch(np.stack([a * Uu, Yy, Uu**2], -1)))
        return out
    if kind == "intersecting-planes":
        a = semi[0]
        umax = min(X, a * Y)
        Uu, Zz = np.meshgrid(np.linspace(-umax, umax, n), np.linspace(-Z, Z, n), indexing="ij")
        for sign in (1.0, -1.0):
            out.append(_patch(np.stack([Uu, sign * Uu / a, Zz], -1)))
        return out
    if kind in ("parallel-planes", "coincident-planes", "plane"):
        Xx, Yy = np.meshgrid(np.linspace(-X, X, n), np.linspace(-Y, Y, n), indexing="ij")
        heights = (semi[0], -semi[0]) if kind == "parallel-planes" else (0.0,)
        for h in heights:
            out.append(_patch(np.stack([Xx, Yy, np.full_like(Xx, h)], -1)))
        return out
    return out  # line, point, empty, all-space: nothing to draw


def _clip_triangles(tris: np.ndarray, normal: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """Keep the part of a triangle soup (M, 3, 3) on the side (r - origin)·normal >= 0;
    cut triangles are re-triangulated with their winding kept."""
    d = (tris - origin) @ normal
    inside = d >= 0
    cnt = inside.sum(axis=1)
    keep = [tris[cnt == 3]]

    def cut(a: np.ndarray, b: np.ndarray, da: np.ndarray, db: np.ndarray) -> np.ndarray:
        t = (da / (da - db))[:, None]
        return a + t * (b - a)

    for want, k_in in ((1, True), (2, False)):
        sel = cnt == want
        if not np.any(sel):
            continue
        T, D, I = tris[sel], d[sel], inside[sel]
        # rotate each triangle so that the lone vertex (inside for 1, outside for 2) comes first
        lone = np.argmax(I == k_in, axis=1)
        idx = (lone[:, None] + np.arange(3)) % 3
        T = np.take_along_axis(T, idx[:, :, None], axis=1)
        D = np.take_along_axis(D, idx, axis=1)
        v0, v1, v2 = T[:, 0], T[:, 1], T[:, 2]
        p01 = cut(v0, v1, D[:, 0], D[:, 1])
        p02 = cut(v0, v2, D[:, 0], D[:, 2])
        if want == 1:
            keep.append(np.stack([v0, p01, p02], axis=1))
        else:
            keep.append(np.stack([p01, v1, v2], axis=1))
            keep.append(np.stack([p01, v2, p02], axis=1))
    return np.concatenate(keep) if keep else np.zeros((0, 3, 3))


def _mesh_quadric(q: Quadric, bounds: Bounds, resolution: int):
    import trimesh

    lo = np.asarray(bounds[0], dtype=float)
    hi = np.asarray(bounds[1], dtype=float)
    if (
        lo.shape != (3,)
        or hi.shape != (3,)
        or not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)))
    ):
        raise ValueError(f"bounds must be two finite 3-vectors, got {bounds!r}")
    if np.any(hi <= lo):
        raise ValueError(f"bounds must satisfy lo < hi in every coordinate, got {bounds!r}")
    n = max(int(resolution), 4)
    cl = q.classify()
    empty = trimesh.Trimesh(
        vertices=np.zeros((0, 3)), faces=np.zeros((0, 3), dtype=np.int64), process=False
    )
    if cl.center is None:
        return empty
    corners = np.array(np.meshgrid(*zip(lo, hi), indexing="ij")).reshape(3, -1).T
    pc = (corners - cl.center) @ cl.axes  # canonical coordinates of the corners
    ext = np.abs(pc).max(axis=0) * 1.0001
    patches = _canonical_patches(cl.kind, cl.semi_axes, ext, float(pc[:, 2].max()), n)
    if not patches:
        return empty
    verts, faces, off = [], [], 0
    for V, Fc in patches:
        verts.append(V)
        faces.append(Fc + off)
        off += len(V)
    P = np.concatenate(verts)
    W = cl.center + P @ cl.axes.T
    m = trimesh.Trimesh(vertices=W, faces=np.concatenate(faces), process=True)
    m.update_faces(m.nondegenerate_faces())
    # clip to the box (keeps the side of each plane its normal points to)
    normals = np.concatenate([np.eye(3), -np.eye(3)])
    origins = np.concatenate([np.tile(lo, (3, 1)), np.tile(hi, (3, 1))])
    if len(m.faces) and not np.all((m.vertices >= lo) & (m.vertices <= hi)):
        tris = np.asarray(m.vertices)[np.asarray(m.faces)]
        for nrm_, org in zip(normals, origins):
            tris = _clip_triangles(tris, nrm_, org)
        if len(tris) == 0:
            return empty
        m = trimesh.Trimesh(
            vertices=tris.reshape(-1, 3),
            faces=np.arange(3 * len(tris)).reshape(-1, 3),
            process=True,
        )
    if len(m.faces) == 0:
        return empty
    V = np.array(m.vertices, dtype=float)
    Fc = np.array(m.faces, dtype=np.int64)
    # vertices made by clipping lie on box faces: pull them onto F = 0 within the face
    on_lo = np.abs(V - lo) <= 1e-9 * (hi - lo)
    on_hi = np.abs(V - hi) <= 1e-9 * (hi - lo)
    fixed = on_lo | on_hi
    sel = np.any(fixed, axis=1)
    if np.any(sel):
        R = V[sel]
        fx = fixed[sel]
        for _ in range(4):
            g = q.half_gradient(R)
            g[fx] = 0.0
            gg = np.einsum("ij,ij->i", g, g)
            Fv = q.F(R)
            ok = (gg > 1e-16 * q.scale**2 / max(q.length, 1e-300) ** 2) & (
                np.abs(Fv) > 1e-15 * q.scale
            )
            step = np.zeros_like(R)
            step[ok] = -(Fv[ok] / (2 * gg[ok]))[:, None] * g[ok]
            small = np.linalg.norm(step, axis=1) <= 0.05 * np.max(hi - lo)
            R = R + step * small[:, None]
        V0 = V.copy()
        V[sel] = R

        # undo the pull where it folded a thin triangle over (normal reversed)
        def fnormals(A: np.ndarray) -> np.ndarray:
            t = A[Fc]
            return np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])

        n0 = fnormals(V0)
        for _ in range(3):
            bad = np.einsum("ij,ij->i", fnormals(V), n0) <= 0
            if not np.any(bad):
                break
            vb = np.unique(Fc[bad])
            V[vb] = V0[vb]
    # orient every face along the gradient of F (a consistent normal field)
    tri = V[Fc]
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    grad = q.half_gradient(tri.mean(axis=1))
    dots = np.einsum("ij,ij->i", nrm, grad)
    gl = np.linalg.norm(grad, axis=1)
    gmin = 1e-7 * q.scale / max(q.length, 1e-300)  # ∇F vanishes on double planes
    flip = (dots < -1e-9 * gl * np.linalg.norm(nrm, axis=1)) & (gl > gmin)
    Fc[flip] = Fc[flip][:, ::-1]
    out = trimesh.Trimesh(vertices=V, faces=Fc, process=False)
    out.update_faces(out.nondegenerate_faces())
    out.remove_unreferenced_vertices()
    return out
