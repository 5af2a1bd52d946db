"""The claim checks of §2.3: lessons/vibration/carriage/claims.py."""

from __future__ import annotations

import analyzer_lab.lessons.vibration.carriage.claims as cc
import numpy as np
from analyzer_lab.lessons.vibration.carriage.model import Carriage, box_inertia

# the strong-coupling carriage of Problem 2.6: C_x/m close to K_y/I_y
_I = box_inertia(20.0, 0.4, 0.5, 0.06)
STRONG = Carriage(20.0, *_I, 2e6, 2e6, 5e7, 2.7e4, 4.2e4, 6e4, 0.03)


def test_random_carriages_are_stable_and_repeatable() -> None:
    ps = cc.random_carriages(10)
    assert all(p.Ky > p.Cx * p.h**2 and p.Kx > p.Cy * p.h**2 for p in ps)
    assert [p.m for p in ps] == [p.m for p in cc.random_carriages(10)]


def test_carriage_dependent_checks_pass_for_a_strongly_coupled_carriage() -> None:
    assert cc.check_sign_268(STRONG).passed
    assert cc.check_closed_vs_eig([STRONG]).passed
    assert cc.check_mode_ratio([STRONG]).passed
    q0 = np.array([0.01, 0.0, 0.005, 0.0, 0.05, 0.02])
    assert cc.check_free_response(STRONG, q0, np.zeros(6)).passed


def test_symbolic_and_numeric_checks_pass() -> None:
    for check in (
        cc.check_lagrange_6dof,
        cc.check_gradients,
        cc.check_determinant,
        cc.check_h_zero,
        cc.check_jeffcott,
        cc.check_torsional,
        cc.check_box_inertia,
        cc.check_huygens,
        cc.check_lagrange_forced,
        cc.check_MN,
        cc.check_amp_phase,
        cc.check_homogeneous,
        cc.check_numbers,
        cc.check_quadrant,
        cc.check_closed_vs_ivp,
        cc.check_form_292,
        cc.check_regimes,
        cc.check_peak,
    ):
        r = check()
        assert r.passed, (check.__name__, r.expected, r.got)


def test_example_axis_numbers() -> None:
    assert cc.EXAMPLE.omega == 5.0 and cc.EXAMPLE.f == 0.2
    assert abs(cc.EXAMPLE.A0 - 0.164094) < 5e-7
