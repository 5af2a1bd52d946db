"""Tests of analyzer_lab.lessons.mechanics.positioners.planar3: the mechanism of Problem 2.4."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.kit.bodies import quat_z
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.lessons.mechanics.planar_3axis import LESSON
from analyzer_lab.lessons.mechanics.positioners.planar3 import (
    BODY,
    body_value,
    body_values,
    default_trace,
    module_positions,
    planar3_kinematics,
    planar3_phi,
    planar3_scene,
    pose_planar3,
    reduced_model,
)


def test_kinematics_and_its_inverse() -> None:
    xB, yB = planar3_kinematics(0.1, -0.2, 0.3, 0.5, np)
    a, b, c = planar3_phi(0.1, -0.2, float(xB), float(yB), 0.5)
    assert a == pytest.approx(0.3) and b == pytest.approx(0.3) and c == pytest.approx(0.3)
    # full range: atan2 recovers phi = 2.5 where arcsin cannot
    xB, yB = planar3_kinematics(0.0, 0.0, 2.5, 0.5, np)
    assert planar3_phi(0.0, 0.0, float(xB), float(yB), 0.5)[2] == pytest.approx(2.5)


def test_reduced_model_mass_matrix() -> None:
    m = reduced_model()
    M = m.mass_matrix
    mA, mB, mAB, J, AB = m.params
    phi = m.q[2]
    assert sp.simplify(M[0, 0] - (mA + mB + mAB)) == 0
    assert sp.simplify(M[0, 2] - AB * mB * sp.sin(phi)) == 0
    assert sp.simplify(M[2, 2] - (J + AB**2 * mB)) == 0


def test_body_values_in_the_models_order() -> None:
    assert [p.name for p in BODY] == [str(s) for s in reduced_model().params]
    assert body_values().tolist() == [2.0, 1.5, 3.0, 0.4, 0.5]
    assert body_value("AB") == 0.5


def test_default_trace_is_the_pages_default_run() -> None:
    """The trace is the forward run of the page at its defaults, every tenth sample."""
    r = LESSON.coarse_run(LESSON.resolve())
    q = np.array([r.series["x_A"], r.series["y_A"], r.series["phi"]])[:, ::10]
    assert default_trace() == pytest.approx(q, abs=1e-9)


def test_scene_floor_covers_the_trace() -> None:
    trace = default_trace()
    spec = planar3_scene(0.5, trace, {"F_A": (1, 2, 3)})
    lo, hi = (np.array(b) for b in spec.bounds)
    xB, yB = planar3_kinematics(trace[0], trace[1], trace[2], 0.5, np)
    for x, y in ((trace[0], trace[1]), (xB - 0.5, yB)):
        assert np.all((lo[0] <= x) & (x <= hi[0]) & (lo[1] <= y) & (y <= hi[1]))
    assert [b.name for b in spec.bodies] == ["module A", "module B", "table"]
    assert spec.moving_vectors == {"F_A": (1, 2, 3)}


def test_pose_puts_the_table_in_the_middle_of_ab() -> None:
    rng = np.random.default_rng(11)
    AB, h = 0.37, 0.25 * 0.37 * 0.3
    for _ in range(10):
        xA, yA, phi = rng.normal(size=3)
        xB, yB = planar3_kinematics(xA, yA, phi, AB, np)
        fr = Frame(t=0.0)
        A, B, mid, height = pose_planar3(fr, AB, xA, yA, xB, yB, phi)
        want_A, want_B = module_positions(AB, xA, yA, xB, yB)
        assert height == pytest.approx(h, rel=1e-15)
        assert np.allclose(fr.poses["module A"][0], want_A, atol=1e-15)
        assert np.allclose(fr.poses["module B"][0], want_B, atol=1e-15)
        assert np.allclose(mid, (A + B) / 2 + [0, 0, h], atol=1e-15)
        assert np.allclose(fr.poses["table"][1], quat_z(np.pi - phi), rtol=1e-14, atol=1e-15)
        assert np.allclose(fr.points["C (middle of AB)"], [mid], atol=1e-15)
