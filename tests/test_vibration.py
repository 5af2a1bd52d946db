"""Shared vibration maths: lessons/vibration/carriage/model.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.vibration.carriage.model import (
    MODE_KEYS,
    Carriage,
    ForcedOscillator,
    box_inertia,
    box_inertia_printed,
    carriage_lagrange,
    carriage_source_equations,
    centre_of_gravity,
    closed_form_frequencies,
    coupled_frequency,
    coupled_frequency_as_printed,
    eigen_frequencies,
    forced_lagrange,
    frequency_response,
    jeffcott_deflection,
    modal_propagate,
    mode_character,
    mode_shape,
    rotvec_to_quaternion,
    small_rotation_matrix,
)
from scipy.integrate import solve_ivp


def random_carriage(rng: np.random.Generator) -> Carriage:
    m = rng.uniform(1, 50)
    Ix, Iy, Iz = box_inertia(m, *rng.uniform(0.05, 1.0, 3))
    C = 10 ** rng.uniform(4, 8, 3)
    h = rng.uniform(0, 0.2)
    K = 10 ** rng.uniform(2, 7, 3) + np.array([C[1], C[0], 0.0]) * h**2
    return Carriage(m, Ix, Iy, Iz, *C, *K, h=h)


@pytest.mark.parametrize("seed", range(10))
def test_closed_form_equals_generalized_eigenvalues(seed: int) -> None:
    p = random_carriage(np.random.default_rng(seed))
    cf = np.sort(list(closed_form_frequencies(p).values()))
    w, _ = eigen_frequencies(p)
    assert np.max(np.abs(cf - w) / w) <= 1e-9


def test_mode_shapes_are_eigenvectors() -> None:
    p = random_carriage(np.random.default_rng(42))
    M, K = p.matrices()
    for key in MODE_KEYS:
        s = mode_shape(p, key)
        w2 = closed_form_frequencies(p)[key] ** 2
        assert np.linalg.norm(K @ s - w2 * M @ s) <= 1e-9 * np.linalg.norm(K @ s)
        assert np.max(np.abs(s)) == pytest.approx(1.0)


def test_h_zero_labels_follow_the_mode_shape() -> None:
    p = Carriage(1, 1, 1, 1, 10, 10, 10, 4000, 4000, 4000, 0.0)
    assert coupled_frequency(10, 4000, 1, 1, 0, +1) == pytest.approx(63.245553203367585, rel=1e-14)
    assert coupled_frequency(10, 4000, 1, 1, 0, -1) == pytest.approx(3.1622776601683795, rel=1e-14)
    assert mode_character(p, "x-phi_y upper") == "rotation"
    assert mode_character(p, "x-phi_y lower") == "translation"


def test_printed_268_is_wrong() -> None:
    # strongly coupled: the printed radicand goes negative
    assert math.isnan(coupled_frequency_as_printed(2e6, 4.2e4, 20, 0.4227, 0.03))
    # weakly coupled: finite but not the eigenvalue
    p = Carriage(2, 1, 1, 1, 100, 100, 100, 150, 150, 150, 0.5)
    lo = coupled_frequency(100, 150, 2, 1, 0.5, -1)
    assert abs(coupled_frequency_as_printed(100, 150, 2, 1, 0.5) - lo) > 1e-3 * lo
    assert lo == pytest.approx(eigen_frequencies(p)[0][0], rel=1e-12)


def test_lagrange_matches_source_equations() -> None:
    s = carriage_lagrange()
    assert len(s.equations) == 6
    for a, b in zip(s.equations, carriage_source_equations()):
        assert sp.simplify(a - b) == 0


def test_box_inertia_and_printed_swap() -> None:
    Ix, Iy, Iz = box_inertia(12.0, 0.4, 0.5, 0.06)
    assert (Ix, Iy, Iz) == pytest.approx((0.1636, 0.2536, 0.41))
    Px, Py, Pz = box_inertia_printed(12.0, 0.4, 0.5, 0.06)
    assert (Px, Py) == pytest.approx((Iy, Ix)) and Pz == Iz
    assert box_inertia(2.0, 0.4, 0.5, 0.06, 0.1, -0.2, 0.05)[2] == pytest.approx(
        2 * (0.41 / 12 + 0.05)
    )


def test_centre_of_gravity() -> None:
    cg = centre_of_gravity(np.array([10.0, 30.0]), np.array([[0, 0, 0], [1, 2, 4]]))
    assert cg == pytest.approx([0.75, 1.5, 3.0])


def test_modal_propagation_against_solve_ivp() -> None:
    p = random_carriage(np.random.default_rng(5))
    M, K = p.matrices()
    q0, v0 = np.array([1e-3, -2e-3, 5e-4, 1e-2, -1e-2, 3e-3]), np.array([0.1, 0, 0, 0, 1.0, 0])
    t = np.linspace(0, 0.05, 101)
    qs, vs = modal_propagate(p, q0, v0, t)
    A = np.block([[np.zeros((6, 6)), np.eye(6)], [-np.linalg.solve(M, K), np.zeros((6, 6))]])
    sol = solve_ivp(
        lambda _t, y: A @ y,
        (0, 0.05),
        np.r_[q0, v0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
        t_eval=t,
    )
    assert np.max(np.abs(sol.y[:6].T - qs)) <= 1e-8 * np.max(np.abs(qs))
    q1, v1 = modal_propagate(p, q0, v0, 0.02)
    q2, _ = modal_propagate(p, q1, v1, 0.03)
    assert q2 == pytest.approx(qs[-1], abs=1e-14)


def test_quaternion_and_rotation_agree() -> None:
    r = np.array([0.1, -0.2, 0.05])
    w, x, y, z = rotvec_to_quaternion(r)
    R = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    assert R == pytest.approx(small_rotation_matrix(r), abs=1e-14)
    assert rotvec_to_quaternion(np.zeros(3)) == pytest.approx([1, 0, 0, 0])


def test_jeffcott_singular_at_critical_speed() -> None:
    assert jeffcott_deflection(2.0, 0.01, 50.0, 1.0) == pytest.approx(2 * 0.01 / 48)
    assert abs(jeffcott_deflection(2.0, 0.01, 50.0, 5.0 * (1 - 1e-9))) > 1e6


@pytest.mark.parametrize(
    "m,b,c,F0,w0,q0,v0",
    [
        (2, 0.8, 50, 3, 4, 0.05, 0),
        (2, 0.8, 50, 3, 7, 0, 0.4),
        (2, 20, 50, 3, 4, 0.05, 0),
        (2, 40, 50, -3, 9, 0.05, 1),
        (2, 0, 50, 3, 5, 0, 0),
        (1, 0, 0, 1, 3, 0, 0),
        (3, 1, 2, 0, 0, 1, 0),
    ],
)
def test_forced_closed_form_against_solve_ivp(m, b, c, F0, w0, q0, v0) -> None:
    o = ForcedOscillator(m, b, c, F0, w0)
    t = np.linspace(0, 15, 751)
    q, v = o.response(t, q0, v0)
    sol = solve_ivp(o.rhs, (0, 15), [q0, v0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=t)
    assert np.max(np.abs(sol.y[0] - q)) <= 1e-8
    assert np.max(np.abs(sol.y[1] - v)) <= 1e-7


def test_forced_numbers_and_quadrant() -> None:
    o = ForcedOscillator(2, 0.8, 50, 3, 4)
    assert o.A0 == pytest.approx(0.164094, abs=5e-7)
    assert o.phi1 == pytest.approx(-0.175940, abs=5e-7)
    assert o.regime == "underdamped" and ForcedOscillator(2, 20, 50, 3, 4).regime == "critical"
    assert ForcedOscillator(2, 40, 50, 3, 4).regime == "overdamped"
    above = ForcedOscillator(2, 0.8, 50, 3, 7)
    assert -math.pi < above.phi1 < -math.pi / 2
    t = np.linspace(0, 20, 401)
    assert np.max(np.abs(o.response_292(t, 0.05, 0) - o.response(t, 0.05, 0)[0])) < 1e-12


def test_frequency_response_plain_arrays() -> None:
    w = np.linspace(0, 15, 301)
    A, ph = frequency_response(2, 0.8, 50, 3, w)
    assert isinstance(A, np.ndarray) and A.shape == w.shape and ph.shape == w.shape
    assert A[0] == pytest.approx(3 / 50)
    assert np.all(np.diff(ph) <= 1e-15) and ph[-1] > -math.pi
    o = ForcedOscillator(2, 0.8, 50, 3, 4)
    fine = np.linspace(4.9, 5.1, 20001)
    Af, _ = frequency_response(2, 0.8, 50, 3, fine)
    assert fine[np.argmax(Af)] == pytest.approx(o.peak_frequency, abs=2e-5)
    assert np.max(Af) == pytest.approx(o.peak_amplitude, rel=1e-9)
    assert o.peak_frequency == pytest.approx(math.sqrt(25 - 0.08))


def test_forced_symbolic_constants() -> None:
    S = forced_lagrange()
    qs = S.M * sp.cos(S.w0 * S.t) + S.N * sp.sin(S.w0 * S.t)
    res = (
        sp.diff(qs, S.t, 2)
        + 2 * S.f * sp.diff(qs, S.t)
        + S.omega**2 * qs
        - S.tau * sp.sin(S.w0 * S.t)
    )
    assert sp.simplify(res) == 0
