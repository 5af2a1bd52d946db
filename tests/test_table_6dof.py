"""Tests of lessons.table_6dof: Problem 2.5 (reconstructed geometry)."""

from __future__ import annotations

import numpy as np
import pytest

from lessons.core.contract import Frame, ParamError
from lessons.core.table6dof import (
    FORCES,
    constraint_residual,
    constraint_residuals,
    inverse_dynamics,
    inverse_dynamics_many,
    inverse_kinematics,
    inverse_kinematics_many,
    inverse_states,
    pose_table,
    program_state,
    program_states,
    table_joints,
)
from lessons.core.table6dof_frames import FRAME_GRAIN, TABLE_BLOCK, pose_row, pose_rows
from lessons.table_6dof import Table6DOF


def test_table_static_and_validation() -> None:
    lesson = Table6DOF()
    p = lesson.pvec(lesson.resolve({"m_l": 0.0, "M_c": 12.0}))
    q, qd, qdd, _ = program_state(np.array([0, 0, 0.25, 0, 0, 0.0]), np.zeros(6), np.zeros(6), p)
    F, lam = inverse_dynamics(q, qd, qdd, p)
    want = 12.0 * 9.81 * np.sqrt(0.3**2 - 0.25**2) / (3 * 0.25)
    assert np.allclose([np.hypot(F[2 * k], F[2 * k + 1]) for k in range(3)], want, rtol=1e-10)
    with pytest.raises(ParamError):
        lesson.resolve({"z_D_t": "0.5"})


def test_table_runs_short() -> None:
    lesson = Table6DOF()
    inv = lesson.run("inverse-program", t_end=1.0)
    assert not inv.messages and inv.metrics["max_constraint_residual"] < 1e-12
    fw = lesson.run("forward-disturbance", t_end=0.3)
    assert not fw.messages and fw.metrics["max_constraint_residual"] < 1e-9
    assert 0 < fw.metrics["max_position_error"] < 1e-3
    for problem in ("forward", "inverse"):
        params = lesson.resolve({"problem": problem})
        st = lesson.stepper(params)
        f = st.advance(0.02)
        assert set(f.poses) == {b.name for b in lesson.scene(params).bodies}
        st.set_params(params)
        assert st.advance(0.02).t == pytest.approx(0.04)
        assert st.reset().t == 0.0
    assert np.all(np.isfinite(np.array(lesson.scene(lesson.resolve()).bounds)))
    steps = lesson.derivation(lesson.resolve())
    assert any(s.reconstructed for s in steps)


def test_table_plots_have_frame_scalars() -> None:
    lesson = Table6DOF()
    for problem in ("forward", "inverse"):
        f = lesson.stepper(lesson.resolve({"problem": problem})).advance(0.01)
        assert {s for p in lesson.plots for s in p.series} <= set(f.scalars)


def test_vectorized_program_matches_one_time_at_a_time() -> None:
    lesson = Table6DOF()
    params = lesson.resolve(preset="inverse-program")
    p, ev = lesson.pvec(params), lesson.program(params)
    t = np.array([0.0, 0.37, 1.1, 2.5])
    q, qd, qdd, ok = program_states(*ev(t), p)
    F, _ = inverse_dynamics_many(q, qd, qdd, p)
    resid = constraint_residuals(q, p)
    assert ok.all()
    for k, tk in enumerate(t):
        q1, qd1, qdd1, ok1 = program_state(*ev(float(tk)), p)
        assert ok1
        for a, b in ((q1, q[k]), (qd1, qd[k]), (qdd1, qdd[k])):
            assert np.allclose(a, b, rtol=1e-12, atol=1e-12)
        F1 = inverse_dynamics(q1, qd1, qdd1, p)[0]
        assert np.allclose(F1, F[k], rtol=1e-10, atol=1e-10 * np.abs(F1).max())
        assert abs(constraint_residual(q1, p) - resid[k]) < 1e-14
    ind, ok = inverse_kinematics_many(np.array([[0, 0, 0.5, 0, 0, 0.0]]).T, 0.3, 0.1)
    assert not ok[0]  # the legs cannot reach the floor: flagged as the one-time version does
    assert not inverse_kinematics(np.array([0, 0, 0.5, 0, 0, 0.0]), 0.3, 0.1)[1]


def test_inverse_table_serves_frames_and_rebuilds_per_block_and_parameters() -> None:
    lesson = Table6DOF()
    params = lesson.resolve(preset="inverse-program")
    table = lesson.inverse_table(params)
    st = lesson.stepper(params)
    times, frames = [], []
    for _ in range(TABLE_BLOCK // 17 - 1):
        frames.append(st.advance(17 * FRAME_GRAIN))
        times.append(st.t)
    assert table.builds == 1  # frames inside one block: evaluated once
    off = np.array(times[:3]) + 0.3 * FRAME_GRAIN  # off the grain: evaluated directly
    want_off = inverse_states(lesson.program(params), lesson.pvec(params), off)
    got_off = np.vstack([table.states(off[k : k + 1]) for k in range(3)])
    assert np.allclose(got_off, want_off, rtol=1e-12, atol=1e-12)
    assert table.builds == 1
    names = lesson.series_names(params)
    grid_obs = lesson.observation(
        params,
        np.array(times),
        inverse_states(lesson.program(params), lesson.pvec(params), np.array(times)),
    )
    for k, fr in enumerate(frames):
        for n in names:
            want = grid_obs[n][k]
            assert abs(fr.scalars[n] - want) <= 1e-9 * (abs(want) + 1e-3), (n, k)
    # a time past the block builds the next one; a state that is not the table's is not served
    st.advance(TABLE_BLOCK * FRAME_GRAIN)
    assert table.builds == 2
    t = st.t
    assert table.scalars(t, table.states(np.array([t]))[0] + 1e-6) is None
    assert table.scalars(t + 0.3 * FRAME_GRAIN, table.states(np.array([t]))[0]) is None
    # new parameters: a new table, built for them
    other = lesson.resolve({**params.raw(), "M_c": float(params["M_c"]) * 2})
    table2 = lesson.inverse_table(other)
    assert table2 is not table and table2.builds == 0
    f2 = lesson.stepper(other).advance(17 * FRAME_GRAIN)
    assert table2.builds == 1
    assert abs(f2.scalars["F_Ax"] - frames[0].scalars["F_Ax"]) > 1e-6 * abs(
        frames[0].scalars["F_Ax"]
    )


def test_table_frames_draw_as_the_direct_pose() -> None:
    lesson = Table6DOF()
    params = lesson.resolve(preset="inverse-program")
    st = lesson.stepper(params)
    for _ in range(5):
        fr = st.advance(17 * FRAME_GRAIN)
        state = lesson.inverse_table(params).states(np.array([fr.t]))[0]
        direct = Frame(t=fr.t, scalars=fr.scalars)
        F = np.array([fr.scalars[f] for f in FORCES])
        pose_table(direct, state[:12], lesson.arrow_scale(params) * F, float(params["r_t"]))
        assert list(direct.poses) == list(fr.poses) and list(direct.vectors) == list(fr.vectors)
        for name, (pos, quat) in direct.poses.items():
            assert np.allclose(pos, fr.poses[name][0], rtol=1e-12, atol=1e-15)
            assert np.allclose(quat, fr.poses[name][1], rtol=1e-12, atol=1e-15)
        for name, (at, vec) in direct.vectors.items():
            assert at.shape == fr.vectors[name][0].shape and np.allclose(at, fr.vectors[name][0])
            assert vec.shape == fr.vectors[name][1].shape and np.allclose(vec, fr.vectors[name][1])
        assert np.array_equal(direct.points["D"], fr.points["D"])
    # a leg pointing straight down and a zero-length leg get the direct pose's quaternions
    q = np.zeros((2, 12))
    q[0, 2] = -0.2  # the table below the inductor plane: every leg points straight down
    q[:, 6:] = table_joints(q[0, :6], 0.1)[:, :2].ravel()  # inductors under the joints
    rows = pose_rows(q, np.zeros((2, 6)), 0.1)
    for i in range(2):
        a = Frame(t=0.0)
        pose_table(a, q[i], np.zeros(6), 0.1)
        b = Frame(t=0.0)
        pose_row(b, rows, i)
        for name in a.poses:
            assert np.allclose(a.poses[name][1], b.poses[name][1], atol=1e-12), name
