"""The analyzer field (1.49)/(1.50): tangency for every surface type, invariant to round-off."""

import numpy as np
import pytest
import sympy as sp

from lessons.core.analyzer import (
    COEFF_NAMES,
    AnalyzerModel,
    Controls,
    field_expr,
    integrate,
    quadric_expr,
    x,
    y,
    z,
)
from lessons.core.formula import parse_formula
from lessons.core.quadric import Quadric

SURFACES = {
    "sphere": (Quadric.sphere(1.0), (1.0, 0.0, 0.0)),
    "ellipsoid": (Quadric.ellipsoid(3.0, 2.0, 1.0), (0.0, 2.0, 0.0)),
    "elliptic-cylinder": (Quadric.elliptic_cylinder(2.0, 1.0), (2.0, 0.0, 0.5)),
    "elliptic-cone": (Quadric.elliptic_cone(1.0, 2.0, 1.0), (1.0, 0.0, 1.0)),
    "elliptic-paraboloid": (Quadric.elliptic_paraboloid(1.0, 2.0), (1.0, 0.0, 1.0)),
    "hyperbolic-paraboloid": (Quadric.hyperbolic_paraboloid(1.0, 1.0), (1.0, 0.0, 1.0)),
    "hyperboloid-1": (Quadric.hyperboloid_one_sheet(1.0, 1.0, 2.0), (1.0, 0.0, 0.0)),
    "hyperboloid-2": (Quadric.hyperboloid_two_sheets(1.0, 1.0, 1.0), (0.0, 0.0, 1.0)),
}


def test_tangency_identity_symbolic_general():
    """grad F . field == 0 identically, for symbolic coefficients and controls."""
    F = quadric_expr()
    f = field_expr(F)
    dot = sum(sp.diff(F, v) * fi for v, fi in zip((x, y, z), f))
    assert sp.expand(dot) == 0


@pytest.mark.parametrize("name", SURFACES)
def test_tangency_identity_every_type(name):
    q, _ = SURFACES[name]
    F = q.sym(x, y, z)
    f = field_expr(F)
    assert sp.simplify(sum(sp.diff(F, v) * fi for v, fi in zip((x, y, z), f))) == 0


def test_sphere_field_is_154():
    u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
    f = field_expr(x**2 + y**2 + z**2 - 1)
    assert [sp.expand(e) for e in f] == [u1 * y - u2 * z, -u1 * x + u3 * z, u2 * x - u3 * y]


def test_ellipsoid_field_is_163():
    a, b, c = 10, 5, 1
    u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
    f = field_expr(x**2 / sp.Integer(a**2) + y**2 / sp.Integer(b**2) + z**2 / sp.Integer(c**2) - 1)
    expected = [
        u1 * y / b**2 - u2 * z / c**2,
        -u1 * x / a**2 + u3 * z / c**2,
        u2 * x / a**2 - u3 * y / b**2,
    ]
    assert all(sp.simplify(e - g) == 0 for e, g in zip(f, expected))


def family_model(V):
    qs = [SURFACES[n][0] for n in SURFACES]
    coeffs = {n: np.array([getattr(q, n) for q in qs]) for n in COEFF_NAMES}
    f = parse_formula
    controls = Controls(f("0.6 + 0.3*sin(t)"), f("0.2*cos(2*t)"), f("0.4"), V=V)
    r0 = np.array([SURFACES[n][1] for n in SURFACES])
    scales = np.array([q.scale for q in qs])
    return AnalyzerModel(coeffs, controls), r0, scales


@pytest.mark.parametrize(
    "V", [None, parse_formula("1 + 0.5*sin(t)")], ids=["analyzer", "constant-speed"]
)
def test_invariant_round_off_over_1e5_steps_every_type(V):
    model, r0, scales = family_model(V)
    assert np.all(np.abs(model.F(r0)) < 1e-12)
    h = 1e-4 if V is None else 2e-4
    run = integrate(model, r0, 1e5 * h, h=h, samples=501)
    assert run.r.shape[1] == len(SURFACES)
    # relative to the size of F's terms where the point went (a hyperbolic paraboloid's
    # trajectories run far out): round-off of F itself is ~1e-16 of that
    rel = run.drift.max(axis=0) / np.maximum(scales, model.F_scale(run.r))
    assert np.all(rel <= 1e-12), dict(zip(SURFACES, rel))
    moved = np.linalg.norm(run.r[-1] - run.r[0], axis=-1)
    assert np.all(moved > 1e-3)


def test_constant_speed_holds_where_field_vanishes():
    """Ex. 1.3 controls at t = 0 from (1, 0, 0): the field is zero; the point holds, then moves."""
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(f("sin(10*t)"), f("t"), f("5"), V=1.0)
    )
    v0 = model.velocity(0.0, np.array([[1.0, 0.0, 0.0]]))
    assert np.all(v0 == 0.0)
    run = integrate(model, [1.0, 0.0, 0.0], 1.0, h=1e-3, samples=101)
    speed = np.linalg.norm(run.v[:, 0], axis=-1)
    assert run.held[0, 0] and not run.held[-1, 0]
    assert np.abs(speed[1:] - 1.0).max() < 1e-9


def test_speed_parallel_controls_hold():
    """u parallel to the gradient in constant-speed mode: grad F x w = 0, hold."""
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(0.0, 0.0, 2.0, V=1.0)
    )  # w ~ (u3,u2,u1) = (2,0,0)
    run = integrate(model, [1.0, 0.0, 0.0], 0.5, h=1e-2)
    assert run.held.all() and np.allclose(run.r, [1.0, 0.0, 0.0])


def test_reference_solver_drifts_where_gl_does_not():
    model, r0, scales = family_model(None)
    gl = integrate(model, r0, 50.0, h=1e-2, samples=501)
    rk = integrate(model, r0, 50.0, method="RK45", samples=501)
    gl_rel = gl.drift.max(axis=0) / np.maximum(scales, model.F_scale(gl.r))
    rk_rel = rk.drift.max(axis=0) / np.maximum(scales, model.F_scale(rk.r))
    assert gl_rel.max() < 1e-13
    assert rk_rel.max() > 1e-7
