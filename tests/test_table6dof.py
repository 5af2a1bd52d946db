"""Tests of analyzer_lab.lessons.mechanics.table.model: the reconstructed mechanism of Problem 2.5."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.mechanics.table.model import inverse_kinematics, table_joints


def test_table_inverse_kinematics_geometry() -> None:
    pose = np.array([0.0, 0.0, 0.2, 0.0, 0.0, 0.0])
    ind, ok = inverse_kinematics(pose, 0.3, 0.15)
    assert ok
    J = table_joints(pose, 0.15)
    for k in range(3):
        radial = J[k, :2] / np.linalg.norm(J[k, :2])
        d = ind[2 * k : 2 * k + 2] - J[k, :2]
        assert np.dot(d, radial) == pytest.approx(
            np.sqrt(0.05), abs=1e-12
        )  # outward along its axis
    _, ok = inverse_kinematics(np.array([0, 0, 0.35, 0, 0, 0.0]), 0.3, 0.15)
    assert not ok


def test_leg_energy_equals_three_particles() -> None:
    """Slender rod: m/6 (|vA|^2 + vA.vJ + |vJ|^2) = m/6 at each end + 2m/3 at the middle."""
    rng = np.random.default_rng(3)
    vA, vJ = rng.normal(size=3), rng.normal(size=3)
    m = 0.7
    rod = m / 6 * (vA @ vA + vA @ vJ + vJ @ vJ)
    # the rod integral: v(s) = vA + s (vJ - vA), T = m/2 * int_0^1 |v(s)|^2 ds
    s = np.linspace(0, 1, 20001)
    v = vA[None, :] + s[:, None] * (vJ - vA)[None, :]
    integral = m / 2 * np.trapezoid(np.sum(v * v, axis=1), s)
    particles = 0.5 * (m / 6) * (vA @ vA + vJ @ vJ) + 0.5 * (2 * m / 3) * np.sum(
        ((vA + vJ) / 2) ** 2
    )
    assert rod == pytest.approx(integral, rel=1e-8) and rod == pytest.approx(particles, rel=1e-12)
