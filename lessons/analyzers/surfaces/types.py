"""Classification of second-order surfaces (and curves): the affine type of
F = rᵀQr + 2bᵀr + c = 0 (every real type of (1.42), degenerate ones included), its centre
or vertex, principal frame and semi-axes.  The principal-axis reduction :func:`_reduce`
works in any dimension; :func:`classify3` names the types of three dimensions
(:meth:`analyzer_lab.lessons.analyzers.surfaces.quadric.Quadric.classify` calls it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Relative tolerance of the classification (zero eigenvalues, zero constants).
CLASSIFY_RTOL = 1e-9


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


def classify3(Q: np.ndarray, b: np.ndarray, c: float) -> Classification:
    """The type of F = rᵀQr + 2bᵀr + c = 0 in three dimensions (see :class:`Classification`)."""
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
