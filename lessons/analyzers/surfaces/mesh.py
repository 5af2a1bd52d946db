"""Triangle meshes of quadrics inside a box, for the scene: built parametrically in the
principal frame of the classification (an icosphere scaled by the semi-axes for
ellipsoids; (cosh, sinh), polar or planar grids otherwise), mapped to world coordinates
and clipped by the six box planes.  :func:`mesh_quadric` meshes any :class:`Surface`
(what :class:`analyzer_lab.lessons.analyzers.surfaces.quadric.Quadric` is, read by
:meth:`~analyzer_lab.lessons.analyzers.surfaces.quadric.Quadric.mesh`).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any, Protocol

import numpy as np
from analyzer_lab.lessons.analyzers.surfaces.types import Classification

#: A box ((x0, y0, z0), (x1, y1, z1)).
Bounds = tuple[tuple[float, float, float], tuple[float, float, float]]


class Surface(Protocol):
    """What a mesh is built from: F = rᵀQr + 2bᵀr + c = 0, its half gradient Q r + b,
    its classification and the sizes its tolerances are relative to."""

    @property
    def length(self) -> float: ...

    @property
    def scale(self) -> float: ...

    def classify(self) -> Classification: ...

    def F(self, points: np.ndarray) -> Any: ...

    def half_gradient(self, points: np.ndarray) -> np.ndarray: ...


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


def mesh_quadric(q: Surface, bounds: Bounds, resolution: int):
    """A trimesh.Trimesh of F = 0 clipped to ``bounds`` with ``resolution`` samples per
    parameter (see :meth:`~analyzer_lab.lessons.analyzers.surfaces.quadric.Quadric.mesh`)."""
    import trimesh

    lo = np.asarray(bounds[0], dtype=float)
    hi = np.asarray(bounds[1], dtype=float)
    if (
        lo.shape != (3,)
        or hi.shape != (3,)
        or not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)))
    ):
        raise ValueError(
            f"bounds must be two finite 3-vectors, got {lo.tolist()} and {hi.tolist()}"
        )
    if np.any(hi <= lo):
        raise ValueError(
            f"bounds must satisfy lo < hi in every coordinate, got {lo.tolist()} and {hi.tolist()}"
        )
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
