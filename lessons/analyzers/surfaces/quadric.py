"""Second-order surfaces (quadrics) in the textbook's notation, eq. (1.42).

    F(x, y, z) = a11 x² + a22 y² + a33 z² + 2 a12 xy + 2 a23 yz + 2 a31 zx
               + 2 a14 x + 2 a24 y + 2 a34 z + a44 = 0                      (1.42)

The textbook writes the xz cross coefficient as ``a31`` (not ``a13``), the linear
coefficients as ``a14, a24, a34`` and the constant as ``a44``; this module keeps that
indexing.  In matrix form F = rᵀQr + 2bᵀr + c with

    Q = [[a11, a12, a31], [a12, a22, a23], [a31, a23, a33]],  b = (a14, a24, a34),  c = a44,

so the half gradient ½∇F = Q r + b is exactly the bracket of (1.45):
F_x = 2(a11 x + a12 y + a31 z + a14), F_y = 2(a22 y + a12 x + a23 z + a24),
F_z = 2(a33 z + a23 y + a31 x + a34).  The analyzer (1.50) integrates with ½∇F.

Besides evaluation a quadric classifies itself (:mod:`analyzer_lab.lessons.analyzers.surfaces.types`),
finds the nearest point on it (:mod:`analyzer_lab.lessons.analyzers.surfaces.projection`) and meshes itself
inside a box (:mod:`analyzer_lab.lessons.analyzers.surfaces.mesh`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
import sympy as sp
from analyzer_lab.lessons.analyzers.surfaces.mesh import Bounds, mesh_quadric
from analyzer_lab.lessons.analyzers.surfaces.projection import nearest_point, project_affine
from analyzer_lab.lessons.analyzers.surfaces.types import Classification, classify3
from analyzer_lab.lessons.kit.formula import plain_number
from analyzer_lab.lessons.kit.once import once

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


def _fmt(v: float) -> str:
    return f"{v:g}"


def _at(center: Vec3) -> str:
    c = tuple(float(v) for v in center)
    return "" if not any(c) else " at (" + ", ".join(_fmt(v) for v in c) + ")"


def _numbers(values: Any) -> str:
    """A sequence of numbers as typed (no numpy reprs)."""
    try:
        return "(" + ", ".join(plain_number(v) for v in np.asarray(values).ravel()[:6]) + ")"
    except (TypeError, ValueError):
        return str(values)[:60]


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {plain_number(value)}")
    return v


def _center3(center: Vec3) -> np.ndarray:
    c = np.asarray(center, dtype=float).reshape(-1)
    if c.shape != (3,) or not np.all(np.isfinite(c)):
        raise ValueError(f"center must be three finite numbers, got {_numbers(center)}")
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


def quadric_polynomial(k: Mapping[str, Any], x: Any, y: Any, z: Any) -> Any:
    """F of (1.42) written out term by term with coefficients ``k`` (by name) at x, y, z."""
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
                    f"coefficient {n} must be a number, got {plain_number(getattr(self, n))}"
                ) from None
            if not math.isfinite(v):
                bad.append(f"{n}={plain_number(v)}")
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
    def _principal(
        cls, title: str, signs: Vec3, a34: float, a44: float, center: Vec3, **semi: float
    ) -> Quadric:
        """``Σ sign_i x_i²/s_i² + 2 a34 z + a44 = 0`` with the semi-axes ``semi`` (a, b, c
        in axis order; a zero sign has none), shifted to ``center``."""
        s = [_positive(n, v) for n, v in semi.items()]
        diag = [sg / s.pop(0) ** 2 if sg else 0.0 for sg in signs]
        named = ", ".join(f"{n}={_fmt(float(v))}" for n, v in semi.items())
        return cls._canonical(diag, (0, 0, a34), a44, center, f"{title} {named}{_at(center)}")

    @classmethod
    def ellipsoid(
        cls, a: float = 3.0, b: float = 2.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² + z²/c² - 1 = 0 (the form of (1.63))."""
        return cls._principal("ellipsoid", (1, 1, 1), 0.0, -1.0, center, a=a, b=b, c=c)

    @classmethod
    def elliptic_cylinder(cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)) -> Quadric:
        """x²/a² + y²/b² - 1 = 0, axis z through ``center``."""
        return cls._principal("elliptic cylinder", (1, 1, 0), 0.0, -1.0, center, a=a, b=b)

    @classmethod
    def elliptic_cone(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² - z²/c² = 0, apex at ``center``, axis z."""
        return cls._principal("elliptic cone", (1, 1, -1), 0.0, 0.0, center, a=a, b=b, c=c)

    @classmethod
    def elliptic_paraboloid(
        cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """z = x²/a² + y²/b², i.e. x²/a² + y²/b² - z = 0 (a34 = -1/2); vertex at ``center``."""
        return cls._principal("elliptic paraboloid", (1, 1, 0), -0.5, 0.0, center, a=a, b=b)

    @classmethod
    def hyperbolic_paraboloid(
        cls, a: float = 1.0, b: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """z = x²/a² - y²/b² (saddle), i.e. x²/a² - y²/b² - z = 0; saddle point at ``center``."""
        return cls._principal("hyperbolic paraboloid", (1, -1, 0), -0.5, 0.0, center, a=a, b=b)

    @classmethod
    def hyperboloid_one_sheet(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² - z²/c² - 1 = 0, axis z."""
        return cls._principal(
            "hyperboloid of one sheet", (1, 1, -1), 0.0, -1.0, center, a=a, b=b, c=c
        )

    @classmethod
    def hyperboloid_two_sheets(
        cls, a: float = 1.0, b: float = 1.0, c: float = 1.0, center: Vec3 = (0, 0, 0)
    ) -> Quadric:
        """x²/a² + y²/b² - z²/c² + 1 = 0, axis z (sheets z >= c and z <= -c)."""
        return cls._principal(
            "hyperboloid of two sheets", (1, 1, -1), 0.0, 1.0, center, a=a, b=b, c=c
        )

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
        return quadric_polynomial(k, x, y, z)

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

    def translated(self, t: Vec3) -> Quadric:
        """The surface moved by ``t``: G(r) = F(r - t)."""
        t = _center3(t)
        Q, b = self.Q, self.b
        return Quadric.from_matrices(
            Q, b - Q @ t, float(t @ Q @ t - 2 * b @ t + self.c), label=self.label
        )

    # ------------------------------------------------------------------ classification
    @once
    def _classification(self) -> Classification:
        return classify3(self.Q, self.b, self.c)

    def classify(self) -> Classification:
        """The affine type, centre/vertex, principal frame and semi-axes (see
        :class:`Classification`); relative tolerance
        :data:`~analyzer_lab.lessons.analyzers.surfaces.types.CLASSIFY_RTOL`."""
        return self._classification

    def project(self, point: Vec3, max_iter: int = 30) -> np.ndarray:
        """The nearest point of F = 0 to ``point`` (closest-point problem solved through
        its Lagrange multiplier, see
        :func:`~analyzer_lab.lessons.analyzers.surfaces.projection.nearest_point`);
        |F| <= 1e-12·scale.

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
            project_affine(cl, p)
            if cl.kind in ("point", "line", "coincident-planes")
            else nearest_point(self.Q, self.b, self.c, p, self.scale, max_iter)
        )

    def mesh(self, bounds: Bounds | None = None, resolution: int = 48):
        """A trimesh.Trimesh of F = 0 clipped to ``bounds`` (default :meth:`default_bounds`).

        Built parametrically in the principal frame of :meth:`classify` (an icosphere
        scaled by the semi-axes for ellipsoids; (cosh, sinh) / polar / planar grids
        with ``resolution`` samples per parameter otherwise), mapped to world
        coordinates, clipped by the six box planes; vertices cut by the box are pulled
        back onto F = 0 inside their box face; faces are oriented along ∇F.  Empty
        (zero faces) for types with no area: empty, point, line, all-space."""
        return mesh_quadric(
            self, bounds if bounds is not None else self.default_bounds(), resolution
        )

    @once
    def length(self) -> float:
        """Characteristic length L = |centre| + the largest semi-axis (1 when the type
        has no semi-axes; |centre| = 0 when there is no centre)."""
        cl = self._classification
        size = max((s for s in cl.semi_axes if s > 0), default=1.0)
        off = float(np.linalg.norm(cl.center)) if cl.center is not None else 0.0
        return off + size

    @once
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


__all__ = [
    "CONSTRUCTORS",
    "COEFF_NAMES",
    "Classification",
    "Quadric",
    "SurfaceType",
    "sym_number",
]
