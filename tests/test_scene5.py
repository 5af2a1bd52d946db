"""Tests for lessons/core/scene5.py: the machine drawn and the program played."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from lessons.core.kinematics5 import Machine5
from lessons.core.scene5 import body_poses, to_view
from lessons.laser_5axis import LESSON, machine_of


def test_posed_b_lever_ends_at_the_working_point() -> None:
    m = Machine5(R_C=230.0, R_B=310.0)
    q = np.array([900.0, 1300.0, 250.0, 0.8, 0.35])
    pos, quat = body_poses(m, q)["lever_B"]
    tip = pos + Rotation.from_quat(quat, scalar_first=True).apply([0.0, 0.0, -m.R_B])
    assert np.allclose(tip, to_view(m.forward(q)[0]), atol=1e-9)


def test_scene_and_bodies_stay_in_bounds() -> None:
    params = LESSON.resolve()
    scene = LESSON.scene(params)
    lo, hi = np.array(scene.bounds[0]), np.array(scene.bounds[1])
    assert np.isfinite(lo).all() and np.isfinite(hi).all() and (hi > lo).all()
    assert "tool" in scene.moving_points and "beam" in scene.moving_vectors
    names = {b.name for b in scene.bodies}
    assert names == {"portal_X", "portal_Y", "portal_Z", "lever_C", "lever_B"}
    for item in scene.meshes + scene.bodies:
        assert np.isfinite(item.vertices).all()
    assert machine_of(params).R_B == 300.0
    frame = LESSON.stepper(params).advance(5.0)
    for body in scene.bodies:
        p, qw = frame.poses[body.name]
        v = Rotation.from_quat(qw, scalar_first=True).apply(body.vertices) + p
        assert (v >= lo - 1e-6).all() and (v <= hi + 1e-6).all()


def test_tool_trail_coloured_by_deviation() -> None:
    params = LESSON.resolve({"delta_p": 20})
    name, lo, hi = LESSON.scene(params).trail_color_by["tool"]
    assert name == "deviation" and (lo, hi) == (20.0, 40.0)
    frame = LESSON.stepper(params).advance(0.5)
    assert name in frame.scalars and "tool" in frame.points
