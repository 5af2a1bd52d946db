"""Tests for lessons/laser5/scene.py: the machine drawn and the program played."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.laser5 import LESSON, machine_of
from analyzer_lab.lessons.laser5.kinematics import Machine5
from analyzer_lab.lessons.laser5.scene import FRAME_GRAIN, body_poses, to_view
from scipy.spatial.transform import Rotation


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


def test_body_quaternions_equal_the_composed_rotations() -> None:
    m = Machine5(k_C1=1.3, k_C2=0.2)
    for q in (np.array([1.0, 2.0, 3.0, 0.7, -0.4]), np.array([0.0, 0.0, 0.0, 4.0, 1.2])):
        th = float(m.theta(q[3]))
        rz = Rotation.from_rotvec([0.0, 0.0, -th])
        rb = rz * Rotation.from_rotvec([float(q[4]), 0.0, 0.0])
        poses = body_poses(m, q)
        assert np.allclose(poses["lever_C"][1], rz.as_quat(scalar_first=True), atol=1e-15)
        assert np.allclose(poses["lever_B"][1], rb.as_quat(scalar_first=True), atol=1e-15)


def test_played_frames_read_one_table_per_block_of_grain_times() -> None:
    params = LESSON.resolve(preset=LESSON.presets[0].name)
    st = LESSON.stepper(params)
    prog = st.prog
    frames = []
    for k in range(40):  # frames of 16 or 17 quanta of 1/600 s, as a session plays
        frames.append(st.advance((17 if k % 3 else 16) * FRAME_GRAIN))
    table = st._table
    assert table is not None and table[0][0] is prog
    t = st.t
    direct = LESSON.observation(params, [t], prog.playhead(t))
    for name, v in frames[-1].scalars.items():
        assert v == pytest.approx(float(direct[name][0]), rel=1e-9, abs=1e-9)
    st.advance(17 * FRAME_GRAIN)
    assert st._table is table  # the same block: read, not sampled again
    # off the grain: evaluated at that time
    off = st.advance(0.123456789)
    assert off.scalars["x"] == pytest.approx(
        float(LESSON.observation(params, [st.t], prog.playhead(st.t))["x"][0]), rel=1e-12
    )
    # new values: a new program, a new table
    st.set_params(LESSON.resolve(preset=LESSON.presets[0].name, values={"V": 2.0}))
    st.advance(17 * FRAME_GRAIN - 0.123456789 % FRAME_GRAIN)
    assert st.prog is not prog and (st._table is None or st._table[0][0] is st.prog)


def test_frame_grain_is_the_sessions_time_quantum() -> None:
    from analyzer_lab.session.session import TIME_QUANTUM

    assert FRAME_GRAIN == TIME_QUANTUM
