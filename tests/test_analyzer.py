"""The analyzer field (1.49)/(1.50): tangency for every surface type; the hold of (1.59)."""

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.analyzers.field.analyzer import (
    AnalyzerModel,
    Controls,
    field_expr,
    quadric_expr,
    x,
    y,
    z,
)
from analyzer_lab.lessons.analyzers.surfaces.quadric import Quadric
from analyzer_lab.lessons.kit.formula import parse_formula

from tests.support.surfaces import SURFACES


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


def test_constant_speed_field_vanishes_at_example_1_3_start():
    """Ex. 1.3 controls at t = 0 from (1, 0, 0): the field is zero, the velocity is 0;
    an instant later it is non-zero and the speed is V."""
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(f("sin(10*t)"), f("t"), f("5"), V=1.0)
    )
    r0 = np.array([[1.0, 0.0, 0.0]])
    assert np.all(model.velocity(0.0, r0) == 0.0)
    assert np.linalg.norm(model.velocity(1e-6, r0)) == pytest.approx(1.0, abs=1e-12)


def test_velocities_batch_equals_single():
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.ellipsoid(3.0, 2.0, 1.0).coeffs(), Controls(f("1 + t"), f("0.2"), f("t/3"), V=2.0)
    )
    t = np.array([0.0, 0.5, 1.0])
    R = np.array([[[0.0, 2.0, 0.0]], [[3.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]]])
    batch = model.velocities(t, R)
    for k in range(3):
        assert np.array_equal(batch[k], model.velocity(t[k], R[k]))
    assert np.linalg.norm(batch, axis=-1) == pytest.approx(2.0)


CONTROL_SETS = [
    ("5", "0", "0", None),
    ("sin(10*t)", "t", "5", 1.0),
    ("1 + t", "0.2", "t/3", "2 + sin(t)"),
    ("sqrt(1 - t)", "cos(t)", "0", None),  # not finite from t = 1
]
TIMES = (0.0, 1e-6, 0.37, 0.999, 1.5, 7.25)


@pytest.mark.parametrize("controls", CONTROL_SETS)
def test_controls_at_one_time_equal_the_arrays(controls):
    """:meth:`Controls.one` to round-off; :meth:`Controls.at` exactly as each formula."""
    f = parse_formula
    u1, u2, u3, V = controls
    c = Controls(f(u1), f(u2), f(u3), V=None if V is None else f(V) if isinstance(V, str) else V)
    with np.errstate(all="ignore"):
        for t in TIMES:
            one = c.one(t)
            arr = [*c.at(np.array([t]))[:, 0], c.speed(np.array([t]))[0]]
            assert all(type(v) is float for v in one)
            np.testing.assert_allclose(one, arr, rtol=1e-15, atol=0)
            assert np.array_equal(np.isnan(one), np.isnan(arr))
        grid = np.linspace(0.0, 3.0, 31)
        each = [np.broadcast_to(u(grid), grid.shape) for u in (c.u1, c.u2, c.u3)]
        assert np.array_equal(c.at(grid), np.array(each), equal_nan=True)


@pytest.mark.parametrize("name", SURFACES)
@pytest.mark.parametrize("controls", CONTROL_SETS[:3])
def test_a_frame_in_plain_floats_equals_the_arrays(name, controls):
    """:meth:`AnalyzerModel.at_one` and :meth:`F_one`: the field (1.50)/(1.59) to round-off,
    the half gradient and F exactly as the array forms, for a family of points."""
    f = parse_formula
    q, p = SURFACES[name]
    u1, u2, u3, V = controls
    c = Controls(f(u1), f(u2), f(u3), V=None if V is None else f(V) if isinstance(V, str) else V)
    model = AnalyzerModel.of(q.coeffs(), c)
    rng = np.random.default_rng(7)
    R = np.array([p, q.project(np.array(p) + 0.3), q.project(rng.normal(size=3))])
    for t in TIMES:
        u, v, g = model.at_one(t, R)
        ref = model.velocities(np.array([t]), R[None])[0]
        scale = max(1.0, float(np.abs(ref).max()))
        np.testing.assert_allclose(v, ref, rtol=0, atol=1e-15 * scale)
        assert np.array_equal(g, model.half_gradient(R))
        np.testing.assert_allclose(model.F_one(R), model.F(R), rtol=0, atol=1e-15)
        assert u[:3] == tuple(c.at(np.array([t]))[:, 0])


def test_a_held_point_is_held_in_plain_floats_too():
    """The constant-speed analyzer where its field vanishes: velocity 0 either way."""
    f = parse_formula
    model = AnalyzerModel.of(
        Quadric.sphere(1.0).coeffs(), Controls(f("sin(10*t)"), f("t"), f("5"), V=1.0)
    )
    R = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    _, v, _ = model.at_one(0.0, R)
    assert np.all(v[0] == 0.0) and np.all(model.velocity(0.0, R)[0] == 0.0)
    _, v, _ = model.at_one(1e-6, R)
    assert np.linalg.norm(v, axis=-1) == pytest.approx(1.0, abs=1e-12)
