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
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cached_property
from typing import Any, Callable, Sequence

import numpy as np
import sympy as sp

COEFF_NAMES: tuple[str, ...] = ("a11", "a22", "a33", "a12", "a23", "a31", "a14", "a24", "a34", "a44")

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
    build: Callable[..., "Quadric"]
    equation: str = ""

    def __call__(self, *args: Any, **kwargs: Any) -> "Quadric":
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
                raise ValueError(f"coefficient {n} must be a number, got {getattr(self, n)!r}") from None
            if not math.isfinite(v):
                bad.append(f"{n}={v}")
            object.__setattr__(self, n, v)
        if bad:
            raise ValueError("quadric coefficients must be finite: " + ", ".join(bad))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_coeffs(cls, label: str = "", **coeffs: float) -> "Quadric":
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
    def from_matrices(cls, Q: np.ndarray, b: Vec3 = (0, 0, 0), c: float = 0.0, label: str = "") -> "Quadric":
        """Build from F = rᵀQr + 2bᵀr + c (Q is symmetrised)."""
        Q = np.asarray(Q, dtype=float)
        if Q.shape != (3, 3):
            raise ValueError(f"Q must be 3x3, got shape {Q.shape}")
        Q = 0.5 * (Q + Q.T)
        b = np.asarray(b, dtype=float).reshape(3)
        return cls(
            a11=Q[0, 0], a22=Q[1, 1], a33=Q[2, 2], a12=Q[0, 1], a23=Q[1, 2], a31=Q[0, 2],
            a14=b[0], a24=b[1], a34=b[2], a44=float(c), label=label,
        )

    @classmethod
    def _canonical(cls, diag: Vec3, lin: Vec3, const: float, center: Vec3, label: str) -> "Quadric":
        q = cls.from_matrices(np.diag(diag), lin, const, label=label)
        return q.translated(_center3(center)) if np.any(_center3(center)) else q

    @classmethod
    def sphere(cls, R: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """x² + y² + z² - R² = 0 (shifted to ``center``)."""
        R = _positive("R", R)
        return cls._canonical((1, 1, 1), (0, 0, 0), -R * R, center, f"sphere R={_fmt(R)}{_at(center)}")

    @classmethod
    def ellipsoid(cls, a: float = 3.0, b: float = 2.0, c: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """x²/a² + y²/b² + z²/c² - 1 = 0 (the form of (1.63))."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, 1 / c**2), (0, 0, 0), -1.0, center,
            f"ellipsoid a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    @classmethod
    def elliptic_cylinder(cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """x²/a² + y²/b² - 1 = 0, axis z."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, 1 / b**2, 0), (0, 0, 0), -1.0, center,
            f"elliptic cylinder a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def elliptic_cone(cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """x²/a² + y²/b² - z²/c² = 0, apex at ``center``, axis z."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, -1 / c**2), (0, 0, 0), 0.0, center,
            f"elliptic cone a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    @classmethod
    def elliptic_paraboloid(cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """z = x²/a² + y²/b², i.e. x²/a² + y²/b² - z = 0 (a34 = -1/2); vertex at ``center``."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, 1 / b**2, 0), (0, 0, -0.5), 0.0, center,
            f"elliptic paraboloid a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def hyperbolic_paraboloid(cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """z = x²/a² - y²/b² (saddle), i.e. x²/a² - y²/b² - z = 0; saddle point at ``center``."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, -1 / b**2, 0), (0, 0, -0.5), 0.0, center,
            f"hyperbolic paraboloid a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def hyperboloid_one_sheet(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> "Quadric":
        """x²/a² + y²/b² - z²/c² - 1 = 0, axis z."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, -1 / c**2), (0, 0, 0), -1.0, center,
            f"hyperboloid of one sheet a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    @classmethod
    def hyperboloid_two_sheets(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> "Quadric":
        """x²/a² + y²/b² - z²/c² + 1 = 0, axis z (sheets z >= c and z <= -c)."""
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        return cls._canonical(
            (1 / a**2, 1 / b**2, -1 / c**2), (0, 0, 0), 1.0, center,
            f"hyperboloid of two sheets a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}{_at(center)}",
        )

    # degenerate types (not in CONSTRUCTORS; handy for tests and demonstrations)
    @classmethod
    def hyperbolic_cylinder(cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """x²/a² - y²/b² - 1 = 0, axis z."""
        a, b = _positive("a", a), _positive("b", b)
        return cls._canonical(
            (1 / a**2, -1 / b**2, 0), (0, 0, 0), -1.0, center,
            f"hyperbolic cylinder a={_fmt(a)}, b={_fmt(b)}{_at(center)}",
        )

    @classmethod
    def parabolic_cylinder(cls, a: float = 1.0, center: Vec3 = (0, 0, 0)) -> "Quadric":
        """z = x²/a², rulings along y."""
        a = _positive("a", a)
        return cls._canonical((1 / a**2, 0, 0), (0, 0, -0.5), 0.0, center, f"parabolic cylinder a={_fmt(a)}{_at(center)}")

    @classmethod
    def plane(cls, normal: Vec3 = (0, 0, 1), point: Vec3 = (0, 0, 0)) -> "Quadric":
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
            [[self.a11, self.a12, self.a31], [self.a12, self.a22, self.a23], [self.a31, self.a23, self.a33]],
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

    def sym(self, x: sp.Symbol | None = None, y: sp.Symbol | None = None, z: sp.Symbol | None = None) -> sp.Expr:
        """F as a sympy expression in x, y, z (default real symbols x, y, z).

        Coefficients become exact Rationals when they are (to 1e-12 relative) fractions
        with denominator <= 10⁶ (1/a² with a = 10 -> 1/100); otherwise sympy Floats."""
        x = x if x is not None else sp.Symbol("x", real=True)
        y = y if y is not None else sp.Symbol("y", real=True)
        z = z if z is not None else sp.Symbol("z", real=True)
        k = {n: sym_number(getattr(self, n)) for n in COEFF_NAMES}
        return (
            k["a11"] * x**2 + k["a22"] * y**2 + k["a33"] * z**2
            + 2 * k["a12"] * x * y + 2 * k["a23"] * y * z + 2 * k["a31"] * z * x
            + 2 * k["a14"] * x + 2 * k["a24"] * y + 2 * k["a34"] * z + k["a44"]
        )

    # ------------------------------------------------------------------ transforms
    def level_through(self, point: Vec3) -> "Quadric":
        """Same quadratic and linear part, a44 chosen so that F(point) = 0.

        The analyzer (1.50) keeps F constant, so this is the surface it actually
        traces from ``point`` (e.g. the ellipsoid with semi-axes 100, 50, 10 through
        (0, 50, 0) for a = 10, b = 5, c = 1)."""
        p = _center3(point)
        a44 = -float(self.F(p) - self.a44)
        lab = f"{self.label} through ({', '.join(_fmt(v) for v in p)})" if self.label else ""
        return Quadric(**{**self.coeffs(), "a44": a44}, label=lab)

    def with_coeffs(self, **changes: float) -> "Quadric":
        """A copy with some coefficients replaced (same name checks as from_coeffs)."""
        return Quadric.from_coeffs(label=self.label, **{**self.coeffs(), **changes})

    def translated(self, t: Vec3) -> "Quadric":
        """The surface moved by ``t``: G(r) = F(r - t)."""
        t = _center3(t)
        Q, b = self.Q, self.b
        return Quadric.from_matrices(Q, b - Q @ t, float(t @ Q @ t - 2 * b @ t + self.c), label=self.label)

    def rotated(self, R: np.ndarray) -> "Quadric":
        """The surface rotated by R about the origin: G(r) = F(Rᵀ r)."""
        R = np.asarray(R, dtype=float)
        return Quadric.from_matrices(R @ self.Q @ R.T, R @ self.b, self.c, label=self.label)

    def transformed(self, R: np.ndarray, t: Vec3 = (0, 0, 0)) -> "Quadric":
        """The surface mapped by r -> R r + t (rotation then translation)."""
        return self.rotated(R).translated(t)

    def scaled(self, k: float) -> "Quadric":
        """Same surface, F multiplied by k != 0."""
        if not math.isfinite(k) or k == 0:
            raise ValueError("the factor must be finite and non-zero")
        return Quadric(**{n: k * v for n, v in self.coeffs().items()}, label=self.label)


def _spec(id: str, title: str, build: Callable[..., Quadric], equation: str, **defaults: float) -> SurfaceType:
    return SurfaceType(id, title, tuple(defaults), dict(defaults), build, equation)


#: The surface types a user picks by id; each takes its parameters plus ``center``.
CONSTRUCTORS: dict[str, SurfaceType] = {
    s.id: s
    for s in (
        _spec("sphere", "sphere", Quadric.sphere, "x² + y² + z² = R²", R=1.0),
        _spec("ellipsoid", "ellipsoid", Quadric.ellipsoid, "x²/a² + y²/b² + z²/c² = 1", a=3.0, b=2.0, c=1.0),
        _spec("elliptic-cylinder", "elliptic cylinder", Quadric.elliptic_cylinder, "x²/a² + y²/b² = 1", a=1.0, b=1.0),
        _spec("elliptic-cone", "elliptic cone", Quadric.elliptic_cone, "x²/a² + y²/b² - z²/c² = 0", a=1.0, b=1.0, c=1.0),
        _spec("elliptic-paraboloid", "elliptic paraboloid", Quadric.elliptic_paraboloid, "z = x²/a² + y²/b²", a=1.0, b=1.0),
        _spec("hyperbolic-paraboloid", "hyperbolic paraboloid", Quadric.hyperbolic_paraboloid, "z = x²/a² - y²/b²", a=1.0, b=1.0),
        _spec("hyperboloid-1", "hyperboloid of one sheet", Quadric.hyperboloid_one_sheet, "x²/a² + y²/b² - z²/c² = 1", a=1.0, b=1.0, c=1.0),
        _spec("hyperboloid-2", "hyperboloid of two sheets", Quadric.hyperboloid_two_sheets, "x²/a² + y²/b² - z²/c² = -1", a=1.0, b=1.0, c=1.0),
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
