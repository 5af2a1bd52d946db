"""Tests of lessons.table_6dof: Problem 2.5 (reconstructed geometry)."""

from __future__ import annotations

import numpy as np
import pytest

from lessons.core.contract import ParamError
from lessons.core.table6dof import inverse_dynamics, program_state
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
