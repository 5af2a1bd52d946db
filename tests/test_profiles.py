"""Speed laws of §1.1: trapezoid (1.8), triangle (1.9), their join at L = 0."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.analyzers.curves.profiles import (
    check_covers,
    check_join,
    check_numbers,
    check_triangle_formulas,
    speed_profile,
    trapezoid_L,
    triangle_1_9,
    triangle_symbolic,
)
from analyzer_lab.lessons.analyzers.curves.profiles import integral_of_v as area

S_HELIX = math.pi * math.sqrt(2.0)


def test_trapezoid_helix_numbers():
    p = speed_profile(S_HELIX, 1.0, 1.0, 1.0)
    assert p.kind == "trapezoid"
    assert p.L == pytest.approx(3.442882938158366, abs=1e-12)
    assert p.Delta == pytest.approx(3.442882938158366, abs=1e-12)
    assert p.T == pytest.approx(5.442882938158366, abs=1e-12)
    assert p.v1 == 1.0
    assert area(p) == pytest.approx(S_HELIX, abs=1e-10)
    assert float(p.s(p.T)) == pytest.approx(S_HELIX, abs=1e-13)


def test_triangle_helix_numbers_match_1_9():
    p = speed_profile(S_HELIX, 4.0, 2.0, 2.0)
    assert p.kind == "triangle"
    assert p.L == pytest.approx(-3.557117061841634, abs=1e-12)
    assert p.t1 == pytest.approx(1.4904500894290902, abs=1e-12)
    assert p.tau == pytest.approx(2.9809001788581804, abs=1e-12)
    assert p.v1 == pytest.approx(2.9809001788581804, abs=1e-12)
    t1, tau, v1 = triangle_1_9(S_HELIX, p.k1, p.k2)
    assert (t1, tau, v1) == pytest.approx((p.t1, p.tau, p.v1), abs=1e-13)
    assert area(p) == pytest.approx(S_HELIX, abs=1e-10)


def test_asymmetric_triangle_respects_slopes_and_v0():
    p = speed_profile(S_HELIX, 4.0, 1.0, 3.0)
    assert p.kind == "triangle"
    assert p.k1 == 4.0 and p.k2 == pytest.approx(4 / 3)
    assert p.v1 / p.t1 == pytest.approx(p.k1, rel=1e-12)
    assert p.v1 / (p.tau - p.t1) == pytest.approx(p.k2, rel=1e-12)
    assert p.v1 <= p.v0
    t = np.linspace(0, p.T, 10001)
    assert np.max(p.v(t)) <= p.v1 + 1e-12
    assert area(p) == pytest.approx(S_HELIX, abs=1e-10)


@pytest.mark.parametrize(
    "v0,d0,d1",
    [(1.0, 1.0, 1.0), (4.0, 2.0, 2.0), (2.0, 0.0, 1.0), (3.0, 0.5, 0.0), (0.5, 0.0, 0.0)],
)
def test_s_is_the_integral_of_v_and_time_at_inverts_it(v0, d0, d1):
    p = speed_profile(S_HELIX, v0, d0, d1)
    t = np.linspace(0, p.T, 4001)
    s = p.s(t)
    assert np.all(np.diff(s) >= -1e-15)
    assert s[-1] == pytest.approx(S_HELIX, abs=1e-12)
    # s' = v (central differences away from the kinks)
    mid = 0.5 * (t[1:] + t[:-1])
    smooth = np.ones(len(mid), dtype=bool)
    for b in p.breakpoints:
        smooth &= ~((t[:-1] < b) & (t[1:] > b))
    assert np.max(np.abs(np.diff(s) / np.diff(t) - p.v(mid))[smooth]) < 1e-8
    assert np.max(np.abs(p.time_at(s) - t)[s < S_HELIX - 1e-9]) < 1e-6
    assert np.max(p.v(t)) <= v0 * (1 + 1e-12)


def test_cases_join_at_L_zero():
    v0, d0, d1 = 1.5, 0.7, 1.3
    S0 = v0 * (d0 + d1) / 2
    assert trapezoid_L(S0, v0, d0, d1) == pytest.approx(0.0, abs=1e-15)
    tri = speed_profile(S0, v0, d0, d1)
    assert (
        tri.kind == "triangle"
        and tri.v1 == pytest.approx(v0, abs=1e-14)
        and tri.T == pytest.approx(d0 + d1, abs=1e-14)
    )
    above = speed_profile(S0 * (1 + 1e-10), v0, d0, d1)
    below = speed_profile(S0 * (1 - 1e-10), v0, d0, d1)
    assert above.kind == "trapezoid" and below.kind == "triangle"
    t = np.linspace(0, tri.T, 1001)
    assert np.max(np.abs(above.v(t) - below.v(t))) < 1e-9


def test_L_nonpositive_iff_v1_at_most_v0():
    rng = np.random.default_rng(1)
    for _ in range(200):
        S, v0, d0, d1 = rng.uniform(0.1, 10, 4)
        p = speed_profile(S, v0, d0, d1)
        v1 = math.sqrt(2 * S * v0 / (d0 + d1))
        assert (p.L <= 0) == (v1 <= v0)
        assert p.v1 <= v0 * (1 + 1e-12)


def test_triangle_symbolic_matches_printed_1_9():
    sol = triangle_symbolic()
    S, k1, k2 = sp.symbols("S_l k_1 k_2", positive=True)
    t1 = sp.sqrt(2 * S * k2 / (k1 * (k1 + k2)))
    assert sp.simplify(sol["t_1"] - t1) == 0
    assert sp.simplify(sol["tau"] - (k1 + k2) / k2 * t1) == 0
    assert sp.simplify(sol["v_1"] - sp.sqrt(2 * S * k1 * k2 / (k1 + k2))) == 0


@pytest.mark.parametrize(
    "args", [(0.0, 1, 1, 1), (1, 0.0, 1, 1), (1, 1, -1, 1), (math.nan, 1, 1, 1)]
)
def test_bad_inputs_raise(args):
    with pytest.raises(ValueError):
        speed_profile(*args)


def test_forced_laws():
    tri = speed_profile(S_HELIX, 1.0, 1.0, 1.0, "triangle")  # L = 3.44 > 0
    assert tri.kind == "triangle" and tri.v1 == pytest.approx(math.sqrt(S_HELIX), abs=1e-14)
    assert tri.v1 > tri.v0 and area(tri) == pytest.approx(S_HELIX, abs=1e-10)
    assert speed_profile(S_HELIX, 1.0, 1.0, 1.0, "trapezoid") == speed_profile(S_HELIX, 1, 1, 1)
    with pytest.raises(ValueError, match="L > 0"):
        speed_profile(S_HELIX, 4.0, 2.0, 2.0, "trapezoid")
    with pytest.raises(ValueError, match="Delta0 \\+ Delta1 > 0"):
        speed_profile(S_HELIX, 1.0, 0.0, 0.0, "triangle")
    with pytest.raises(ValueError, match="one of"):
        speed_profile(S_HELIX, 1.0, 1.0, 1.0, "square")


def test_piecewise_law_at_the_edges():
    p = speed_profile(S_HELIX, 1.0, 1.0, 1.0)
    t = np.array([-1.0, 0.0, 1.0, p.T - 1.0, p.T, p.T + 1.0])
    assert p.v(t).tolist() == pytest.approx([0.0, 0.0, 1.0, 1.0, 0.0, 0.0], abs=1e-15)
    assert p.s(t).tolist() == pytest.approx([0, 0, 0.5, S_HELIX - 0.5, S_HELIX, S_HELIX])
    assert p.acceleration(t).tolist() == [0.0, 1.0, 0.0, -1.0, 0.0, 0.0]


def test_checks_pass_and_can_fail():
    assert check_covers(S_HELIX, 1.0, 1.0, 1.0).passed and check_join().passed
    assert check_triangle_formulas().passed
    p = speed_profile(S_HELIX, 1.0, 1.0, 1.0)
    assert check_numbers(p, "trapezoid", L=3.442882938158366, T=5.442882938158366).passed
    assert not check_numbers(p, "trapezoid", L=3.4429).passed
    assert not check_numbers(p, "triangle", L=3.442882938158366).passed
