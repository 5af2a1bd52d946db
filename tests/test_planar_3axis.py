"""Tests of analyzer_lab.lessons.mechanics.planar_3axis: Problem 2.4, eqs (2.12)-(2.16)."""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.kit.bodies import quat_z
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.lessons.mechanics.planar_3axis import LESSON
from analyzer_lab.lessons.mechanics.positioners.planar3 import (
    module_positions,
    planar3_kinematics,
    reduced_model,
)


def test_the_page_reads_the_reduced_model() -> None:
    assert LESSON.model(LESSON.resolve()) is reduced_model()
    assert LESSON.physical == ("m_A", "m_B", "m_AB", "J_A", "AB")


def test_module_b_series() -> None:
    r = LESSON.run("inverse-program", t_end=1.0)
    xB, yB = planar3_kinematics(r.series["x_A"], r.series["y_A"], r.series["phi"], 0.5, np)
    assert np.allclose(r.series["x_B"], xB) and np.allclose(r.series["y_B"], yB)


def test_pose_on_floats_draws_the_absolute_positions() -> None:
    """The frame's pose (worked out on floats) puts the modules where (2.12) and
    :func:`module_positions` put them, the table in the middle of AB."""
    params = LESSON.resolve({"AB": 0.37})
    h = 0.25 * 0.37 * 0.3
    rng = np.random.default_rng(11)
    for _ in range(10):
        q, u, scale = rng.normal(size=3), rng.normal(size=5), 0.2
        fr = Frame(t=0.0)
        LESSON.pose(params, fr, q, u, scale)
        A, B = module_positions(0.37, q[0], q[1], *planar3_kinematics(*q, 0.37, np))
        mid = (A + B) / 2
        want = {
            "module A": A,
            "module B": B,
            "table": mid + [0, 0, h],
        }
        for name, pos in want.items():
            assert np.allclose(fr.poses[name][0], pos, rtol=1e-14, atol=1e-15), name
        assert np.allclose(fr.poses["table"][1], quat_z(np.pi - q[2]), rtol=1e-14, atol=1e-15)
        assert np.allclose(fr.points["C (middle of AB)"], [mid + [0, 0, h]], atol=1e-15)
        for name, at, vec in (
            ("F_A", A + [0, 0, 2 * h], [scale * u[0], scale * u[1], 0]),
            ("F_B", B + [0, 0, 2 * h], [scale * u[2], scale * u[3], 0]),
            ("M_phi", mid + [0, 0, 2 * h], [0, 0, -scale * u[4]]),
        ):
            assert np.allclose(fr.vectors[name][0], [at], atol=1e-15), name
            assert np.allclose(fr.vectors[name][1], [vec], atol=1e-15), name
