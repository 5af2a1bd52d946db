"""Problem 1.3: the linear structure (1.43)-(1.47), the ψ-derivation (1.48)-(1.49), the analyzer on any quadric."""

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.analyzers.field.tangent_fields import (
    MONOMIALS,
    UNKNOWNS,
    analyze,
    field_150_vectors,
    system_147,
)
from analyzer_lab.lessons.analyzers.quadric import GENERAL, LESSON
from analyzer_lab.lessons.analyzers.surfaces.quadric import CONSTRUCTORS
from analyzer_lab.lessons.kit.contract import ParamError


def test_147_rows_match_the_source():
    a = {
        n: sp.Symbol(n, real=True)
        for n in ("a11", "a22", "a33", "a12", "a23", "a31", "a14", "a24", "a34", "a44")
    }
    b0, b1, b2, b3, c0, c1, c2, c3, d0, d1, d2, d3 = UNKNOWNS
    M = system_147()
    rows = [sp.expand((M[i, :] * sp.Matrix(UNKNOWNS))[0]) for i in range(10)]
    A = lambda n: a[n]  # noqa: E731
    source = [
        A("a11") * b1 + A("a12") * c1 + A("a31") * d1,
        A("a12") * b2 + A("a22") * c2 + A("a23") * d2,
        A("a31") * b3 + A("a23") * c3 + A("a33") * d3,
        A("a11") * b2
        + A("a12") * b1
        + A("a22") * c1
        + A("a12") * c2
        + A("a23") * d1
        + A("a31") * d2,
        A("a11") * b3
        + A("a31") * b1
        + A("a12") * c3
        + A("a23") * c1
        + A("a31") * d3
        + A("a33") * d1,
        A("a12") * b3
        + A("a31") * b2
        + A("a22") * c3
        + A("a23") * c2
        + A("a23") * d3
        + A("a33") * d2,
        A("a11") * b0
        + A("a14") * b1
        + A("a12") * c0
        + A("a24") * c1
        + A("a31") * d0
        + A("a34") * d1,
        A("a12") * b0
        + A("a14") * b2
        + A("a22") * c0
        + A("a24") * c2
        + A("a23") * d0
        + A("a34") * d2,
        A("a31") * b0
        + A("a14") * b3
        + A("a23") * c0
        + A("a24") * c3
        + A("a33") * d0
        + A("a34") * d3,
        A("a14") * b0 + A("a24") * c0 + A("a34") * d0,
    ]
    for got, want in zip(rows, source):
        assert sp.expand(got - want) == 0
    assert len(MONOMIALS) == 10 and M.shape == (10, 12)


@pytest.mark.parametrize("sid", list(CONSTRUCTORS))
def test_rank_per_surface(sid):
    rep = analyze(CONSTRUCTORS[sid]())
    if sid == "elliptic-cylinder":
        assert (rep.rank, rep.nullity, rep.rank_150, rep.rank_combined) == (7, 5, 3, 5)
    else:
        assert (rep.rank, rep.nullity) == (9, 3) and rep.family_is_150


def test_150_satisfies_147_symbolically():
    M = system_147()
    a = {
        n: sp.Symbol(n, real=True)
        for n in ("a11", "a22", "a33", "a12", "a23", "a31", "a14", "a24", "a34", "a44")
    }
    assert sp.simplify(M * field_150_vectors(a)) == sp.zeros(10, 3)


@pytest.mark.parametrize("preset", [p.name for p in LESSON.presets])
def test_every_preset_runs(preset):
    res = LESSON.run(preset, t_end=2.0)
    for k in ("x", "y", "z", "vx", "vy", "vz"):
        assert res.series[k].shape == res.t.shape and np.all(np.isfinite(res.series[k]))
    assert res.metrics["invariant_drift_rel"] < 1e-12


def test_coefficients_surface_and_bad_input():
    params = LESSON.resolve(preset="coefficients")
    q = LESSON.surface(params)
    assert q.coeffs() == pytest.approx(GENERAL)
    steps = LESSON.derivation(params)
    titles = [s.title for s in steps]
    assert "(1.47) on this surface" in titles and "ψ-substitution" in titles
    with pytest.raises(ParamError):
        LESSON.resolve({"surface": "coefficients", **{n: 0 for n in GENERAL}})
    with pytest.raises(ParamError):  # x² + y² + z² + 1 = 0 has no real points
        LESSON.resolve({"surface": "coefficients", "a11": 1, "a22": 1, "a33": 1, "a44": 1})


def test_constant_controls_plane_curve():
    res = LESSON.run("hyperboloid-2", t_end=3.0)
    assert res.metrics["plane_invariant_spread"] < 1e-12


def test_stepper_and_scene():
    params = LESSON.resolve(preset="elliptic-cone")
    st = LESSON.stepper(params)
    st.advance(0.5)
    st.set_params(LESSON.resolve({"u2": "1"}, preset="elliptic-cone"))
    f = st.advance(0.5)
    assert f.t == pytest.approx(1.0) and f.scalars["drift"] < 1e-12
    assert st.reset().t == 0.0
    assert np.all(np.isfinite(np.array(LESSON.scene(params).bounds)))


def test_claims_pass():
    for c in LESSON.claims():
        r = c.check()
        assert r.passed, (c.id, r)


def test_groups_separate_type_shape_and_coefficients():
    from analyzer_lab.lessons.analyzers.quadric import LESSON

    assert [g.name for g in LESSON.groups] == [
        *("mode", "shape", "coefficients", "controls", "initial", "method")
    ]
    assert LESSON.modes == ("surface",) and LESSON.param("surface").group == "mode"
    assert {LESSON.param(n).group for n in ("R", "a", "b", "c")} == {"shape"}
    assert LESSON.param("a31").group == "coefficients"
    # the coefficients are shown only for a surface given by them, and then open
    coefficients = LESSON.group("coefficients")
    assert coefficients.when == ("surface", ("coefficients",)) and coefficients.expanded
    assert not LESSON.group("method").expanded
