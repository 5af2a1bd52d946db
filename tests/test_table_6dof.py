"""Tests of analyzer_lab.lessons.mechanics.table_6dof: Problem 2.5 (reconstructed geometry)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from analyzer_lab.lessons.kit.contract import Frame, ParamError
from analyzer_lab.lessons.mechanics.table.frames import (
    CHUNK_FRAMES,
    DENSE_ROWS,
    FRAME_GRAIN,
    pose_row,
    pose_rows,
)
from analyzer_lab.lessons.mechanics.table.model import (
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
from analyzer_lab.lessons.mechanics.table_6dof import Table6DOF


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


def _frames_match_the_grid(lesson: Table6DOF, params: Any, frames: list[Frame]) -> None:
    """Each frame's state and scalars are those of a grid run at its time."""
    times = np.array([fr.t for fr in frames])
    states = inverse_states(lesson.program(params), lesson.pvec(params), times)
    grid_obs = lesson.observation(params, times, states)
    table = lesson.inverse_table(params)
    for k, fr in enumerate(frames):
        assert np.allclose(table.states(times[k : k + 1])[0], states[k], rtol=1e-12, atol=1e-14)
        for n in lesson.series_names(params):
            want = grid_obs[n][k]
            assert abs(fr.scalars[n] - want) <= 1e-9 * (abs(want) + 1e-3), (n, k)


def test_inverse_table_evaluates_the_times_frames_read_in_chunks() -> None:
    lesson = Table6DOF()
    params = lesson.resolve({**lesson.resolve(preset="inverse-program").raw(), "M_c": 11.25})
    table = lesson.inverse_table(params)
    st = lesson.stepper(params)
    step = lambda k: (16 if k % 3 == 2 else 17) * FRAME_GRAIN  # noqa: E731  (36 frames/s)
    frames = [st.advance(step(k)) for k in range(100)]
    assert table.builds <= 6 and table.rows_built < 17 * 100  # fewer than the grain times
    builds, rows = table.builds, table.rows_built
    frames += [st.advance(step(k)) for k in range(100, 300)]
    # once the step is known, a chunk serves its frames with a few grain times each
    assert table.builds - builds <= 1 + 200 // CHUNK_FRAMES
    assert table.rows_built - rows < 3 * 200
    _frames_match_the_grid(lesson, params, frames[::7])
    builds = table.builds
    off = np.array([fr.t for fr in frames[:3]]) + 0.3 * FRAME_GRAIN  # off the grain: direct
    want_off = inverse_states(lesson.program(params), lesson.pvec(params), off)
    got_off = np.vstack([table.states(off[k : k + 1]) for k in range(3)])
    assert np.allclose(got_off, want_off, rtol=1e-12, atol=1e-12)
    assert table.builds == builds
    # a chunk's rows are the numbers a chunk of every grain time gives at those times
    j = round(frames[-1].t / FRAME_GRAIN)
    dense = inverse_states(
        lesson.program(params), lesson.pvec(params), (j + np.arange(-40, 1)) * FRAME_GRAIN
    )
    assert np.array_equal(table.states(np.array([frames[-1].t]))[0], dense[-1])
    # a state that is not the table's, or a time off the grain, is not served
    t = frames[-1].t
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


def test_inverse_table_follows_uneven_frames_jumps_and_speeds() -> None:
    lesson = Table6DOF()
    params = lesson.resolve({**lesson.resolve(preset="inverse-program").raw(), "M_c": 9.5})
    table = lesson.inverse_table(params)
    st = lesson.stepper(params)
    rng = np.random.default_rng(5)
    builds = table.builds
    frames = [st.advance(int(rng.integers(13, 21)) * FRAME_GRAIN) for _ in range(150)]
    assert table.builds - builds < 150 // 8  # frames that jitter still read chunks
    assert st.reset().t == 0.0  # a jump back: served from a new chunk
    frames += [st.advance(17 * FRAME_GRAIN) for _ in range(20)]
    frames += [st.advance(67 * FRAME_GRAIN) for _ in range(60)]  # four times the speed
    builds = table.builds
    frames += [st.advance(67 * FRAME_GRAIN) for _ in range(60)]
    assert table.builds - builds <= 2
    _frames_match_the_grid(lesson, params, frames[::5])


def test_inverse_table_serves_sessions_that_read_it_in_turn() -> None:
    """Several sessions with the same values share one table; their uneven frames come
    interleaved, so none plays evenly for the table: they read aligned chunks of every
    grain time, a few grain times evaluated per frame, the direct path's numbers."""
    lesson = Table6DOF()
    params = lesson.resolve({**lesson.resolve(preset="inverse-program").raw(), "M_c": 10.5})
    table = lesson.inverse_table(params)
    steppers = [lesson.stepper(params) for _ in range(12)]
    rng = np.random.default_rng(11)
    for k, st in enumerate(steppers):  # sessions started at different times
        st.advance((1 + 37 * k) * FRAME_GRAIN)
    builds, rows = table.builds, table.rows_built
    frames: list[Frame] = []
    for _ in range(60):
        for st in steppers:
            frames.append(st.advance(int(rng.integers(14, 21)) * FRAME_GRAIN))
    span = max(fr.t for fr in frames) - min(fr.t for fr in frames)
    # every grain time the sessions crossed, about once: not a chunk per frame
    assert table.builds - builds <= 2 + span / (DENSE_ROWS * FRAME_GRAIN) + len(steppers)
    assert table.rows_built - rows < 5 * len(frames)
    _frames_match_the_grid(lesson, params, frames[::9])
    for fr in frames[-len(steppers) :]:  # the drawing is the direct pose's
        state = table.states(np.array([fr.t]))[0]
        direct = Frame(t=fr.t, scalars=fr.scalars)
        F = np.array([fr.scalars[f] for f in FORCES])
        pose_table(direct, state[:12], lesson.arrow_scale(params) * F, float(params["r_t"]))
        for name, (pos, quat) in direct.poses.items():
            assert np.allclose(pos, fr.poses[name][0], rtol=1e-12, atol=1e-15)
            assert np.allclose(quat, fr.poses[name][1], rtol=1e-12, atol=1e-15)


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


def test_rotation_is_rz_ry_rx_at_one_and_many_orientations() -> None:
    from analyzer_lab.lessons.mechanics.table.model import rotation, rotations

    rng = np.random.default_rng(3)
    angles = rng.uniform(-np.pi, np.pi, (3, 20))
    many = rotations(*angles)
    for k, (a, b, p) in enumerate(angles.T):
        ca, sa, cb, sb, cp, sp_ = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(p), np.sin(p)
        Rz = np.array([[cp, -sp_, 0], [sp_, cp, 0], [0, 0, 1]])
        Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
        Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
        assert np.abs(rotation(a, b, p) - Rz @ Ry @ Rx).max() <= 1e-15
        assert np.array_equal(rotation(a, b, p), many[k])
