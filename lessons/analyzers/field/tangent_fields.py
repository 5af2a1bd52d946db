"""The linear structure (1.43) and its conditions (1.44)-(1.47), solved symbolically.

An affine field

    dx/dφ = b0 + b1 x + b2 y + b3 z,  dy/dφ = c0 + c1 x + ...,  dz/dφ = d0 + d1 x + ...   (1.43)

stays on the quadric F = 0 for every start point when ½(F_x dx + F_y dy + F_z dz) ≡ 0
(1.44): ten homogeneous linear equations (1.47) in the twelve coefficients (one per
monomial x², y², z², xy, zx, yz, x, y, z, 1 of (1.46)).  Their rank is 9 for the
non-degenerate quadrics (three free coefficients, and the solution set is exactly the
analyzer (1.50) with u1, u2, u3) and 7 for the cylinder (five: (1.50) gives three).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import A_SYM, quadric_expr, x, y, z
from analyzer_lab.lessons.analyzers.surfaces.quadric import COEFF_NAMES, Quadric, sym_number

B = sp.symbols("b0 b1 b2 b3", real=True)
C = sp.symbols("c0 c1 c2 c3", real=True)
D = sp.symbols("d0 d1 d2 d3", real=True)
UNKNOWNS: tuple[sp.Symbol, ...] = (*B, *C, *D)
#: Row order of (1.47) in the source, top to bottom.
MONOMIALS: tuple[sp.Expr, ...] = (x**2, y**2, z**2, x * y, z * x, y * z, x, y, z, sp.Integer(1))


def structure_143() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    return (
        B[0] + B[1] * x + B[2] * y + B[3] * z,
        C[0] + C[1] * x + C[2] * y + C[3] * z,
        D[0] + D[1] * x + D[2] * y + D[3] * z,
    )


def system_147(a: Mapping[str, sp.Expr] = A_SYM) -> sp.Matrix:
    """The 10 x 12 coefficient matrix of (1.47) (rows in the source's monomial order)."""
    F = quadric_expr(a)
    f = structure_143()
    ident = sp.expand(
        sum(sp.diff(F, v) * fi for v, fi in zip((x, y, z), f)) / 2
    )  # (1.44)/2 -> (1.46)
    poly = sp.Poly(ident, x, y, z)
    rows = []
    for m in MONOMIALS:
        coeff = poly.coeff_monomial(m)
        rows.append([sp.expand(coeff).coeff(u) for u in UNKNOWNS])
    return sp.Matrix(rows)


def field_150_vectors(a: Mapping[str, sp.Expr]) -> sp.Matrix:
    """12 x 3: the coefficient vectors of (1.50) for u1, u2, u3 (columns)."""
    gx = (a["a14"], a["a11"], a["a12"], a["a31"])  # F_x/2 = a14 + a11 x + a12 y + a31 z
    gy = (a["a24"], a["a12"], a["a22"], a["a23"])
    gz = (a["a34"], a["a31"], a["a23"], a["a33"])
    zero = (0, 0, 0, 0)
    neg = lambda v: tuple(-e for e in v)  # noqa: E731
    u1 = (*gy, *neg(gx), *zero)  # dx = u1 gy, dy = -u1 gx
    u2 = (*neg(gz), *zero, *gx)  # dx = -u2 gz, dz = u2 gx
    u3 = (*zero, *gz, *neg(gy))  # dy = u3 gz, dz = -u3 gy
    return sp.Matrix([u1, u2, u3]).T


@dataclass
class StructureReport:
    """(1.47) for one surface: matrix, rank, nullspace and how (1.50) sits in it."""

    matrix: sp.Matrix
    rank: int
    nullspace: list[sp.Matrix]
    rank_150: int
    rank_combined: int

    @property
    def nullity(self) -> int:
        return len(self.nullspace)

    @property
    def family_is_150(self) -> bool:
        """True when (1.50) is the whole solution set of (1.47)."""
        return self.rank_150 == self.nullity == self.rank_combined


def exact_coeffs(q: Quadric) -> dict[str, sp.Expr]:
    return {n: sym_number(float(getattr(q, n))) for n in COEFF_NAMES}


def analyze(q: Quadric) -> StructureReport:
    a = exact_coeffs(q)
    M = system_147(a)
    ns = M.nullspace()
    W = field_150_vectors(a)
    assert all(e == 0 for e in (M * W)), "(1.50) must satisfy (1.47)"
    combined = sp.Matrix.hstack(*ns, W) if ns else W
    return StructureReport(M, M.rank(), ns, W.rank(), combined.rank())


def psi_derivation() -> dict[str, sp.Expr]:
    """(1.48)-(1.49): λ1, λ2 that make (1.44) an identity, and the resulting u1, u2, u3.

    Returns the residual of (1.44) (zero) and the differences between the ψ-form and
    (1.49) in convention B (all zero)."""
    Fx, Fy, Fz = sp.symbols("F_x F_y F_z")
    p = sp.symbols("psi1:7")
    lam1 = -(Fx * p[1] + Fy * p[3] + Fz * p[5])
    lam2 = Fx * p[0] + Fy * p[2] + Fz * p[4]
    dx, dy, dz = lam1 * p[0] + lam2 * p[1], lam1 * p[2] + lam2 * p[3], lam1 * p[4] + lam2 * p[5]
    u1 = p[1] * p[2] - p[0] * p[3]
    u2 = p[0] * p[5] - p[1] * p[4]
    u3 = p[3] * p[4] - p[2] * p[5]
    return {
        "tangency": sp.expand(Fx * dx + Fy * dy + Fz * dz),
        "dx": sp.expand(dx - (u1 * Fy - u2 * Fz)),
        "dy": sp.expand(dy - (-u1 * Fx + u3 * Fz)),
        "dz": sp.expand(dz - (u2 * Fx - u3 * Fy)),
        "u3_literal_dy": sp.expand(dy - (-u1 * Fx + (p[3] * p[5] - p[2] * p[5]) * Fz)),
    }
