"""Tests for lessons/laser5/kinematics.py: the LSP-2000 kinematics (1a), (1b), (2), (3)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.laser5.kinematics import LimitError, Machine5, translate_poses
from analyzer_lab.lessons.laser5.task import Paraboloid, make_task


@pytest.mark.parametrize("limits", ["original", "improved"])
def test_round_trip_random_poses(limits: str) -> None:
    m = Machine5(R_C=230.0, R_B=310.0, k_C2=0.3, k_X=5.0, k_Y=-7.0, k_Z=11.0, limits=limits)  # type: ignore[arg-type]
    q = m.random_poses(np.random.default_rng(7), 500)
    p, n = m.forward(q)
    for i in range(len(q)):
        q2 = m.inverse(p[i], n[i], C_ref=float(q[i, 3]))
        p2, n2 = m.forward(q2)
        assert np.abs(p2 - p[i]).max() <= 1e-9
        assert np.abs(n2 - n[i]).max() <= 1e-12
        assert np.abs(q2 - q[i]).max() <= 1e-9


def test_inverse_sense_minus_one() -> None:
    m = Machine5(k_C1=-1.0)
    q = np.array([500.0, 600.0, 100.0, 2.0, 0.4])
    p, n = m.forward(q)
    assert np.allclose(m.inverse(p, n), q, atol=1e-9)


def test_vertical_beam_is_ambiguous_and_rule_picks_c() -> None:
    m = Machine5()
    q1 = np.array([1000.0, 1000.0, 100.0, 1.0, 0.0])
    p, n = m.forward(q1)
    assert np.allclose(p, [1168.294197, 1108.060461, 400.0], atol=1e-6)
    q0 = m.inverse(p, n)
    assert q0[3] == 0.0 and np.allclose(q0[:3], [1168.294197, 908.060461, 100.0], atol=1e-6)
    assert np.allclose(m.inverse(p, n, C_ref=1.0), q1, atol=1e-9)
    assert np.allclose(m.forward(q0)[0], p, atol=1e-9)


def test_limits_enforced() -> None:
    tilt = np.array([math.sin(0.9), 0.0, math.cos(0.9)])  # 51.6 deg
    assert Machine5().inverse(np.zeros(3), tilt)[4] == pytest.approx(0.9)
    with pytest.raises(LimitError):
        Machine5(limits="improved").inverse(np.zeros(3), tilt)
    with pytest.raises(LimitError):
        Machine5().inverse(np.zeros(3), np.array([1.0, 0.0, -0.1]))


def test_improved_takes_nearest_branch() -> None:
    m = Machine5(limits="improved")
    n = m.beam(-0.2, 0.1)
    C, B = m.rotary(n, C_ref=2.5)  # the branch (theta + pi, -B) is nearer
    assert C == pytest.approx(math.pi - 0.2) and B == pytest.approx(-0.1)
    C, B = m.rotary(n, C_ref=-0.1 + 4 * math.pi)
    assert C == pytest.approx(-0.2 + 4 * math.pi) and B == pytest.approx(0.1)


def test_point_velocity_is_the_derivative_of_1b() -> None:
    m = Machine5(R_C=230.0, R_B=310.0, k_C1=-1.0, k_C2=0.3)
    rng = np.random.default_rng(5)
    q = m.random_poses(rng, 20)
    dq = rng.normal(size=(20, 5))
    h = 1e-6
    numeric = (m.forward(q + h * dq)[0] - m.forward(q - h * dq)[0]) / (2 * h)
    assert np.allclose(m.point_velocity(q, dq), numeric, atol=1e-5)


def test_task_translation_sequential() -> None:
    m = Machine5(limits="improved")
    task = make_task(Paraboloid(), "circle", 32, radius=300.0)
    qs = translate_poses(m, task.points, task.normals)
    steps = np.degrees(np.diff([q[3] for q in qs]))
    assert np.allclose(np.abs(steps), 11.25, atol=1e-9)
