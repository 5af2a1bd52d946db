"""The motion program of §1.1 and the solution of (1.5) with the controls (1.15)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.curves.motion_law import (
    controls_residuals,
    motion_program,
    solve_15,
    step_grid,
)
from scipy.integrate import solve_ivp

HELIX = ("sin(phi)", "cos(phi)", "phi", 0.0, math.pi)


@pytest.mark.parametrize("v0,d0,d1", [(1.0, 1.0, 1.0), (4.0, 2.0, 2.0)])
def test_rk4_reproduction_and_independent_dop853(v0, d0, d1):
    prog = motion_program(*HELIX, v0, d0, d1)
    X = prog.law(prog.steps)["X"]
    assert np.max(np.linalg.norm(prog.Y - X, axis=1)) <= 1e-6
    assert np.linalg.norm(prog.Y[-1] - [0.0, -1.0, math.pi]) <= 1e-6

    # the same system (1.5) with u_ij of (1.15), integrated by DOP853 (rtol 1e-11, atol 1e-12)
    def rhs(t, y):
        return prog.controls(prog.law(np.array([t])))[0] @ y

    t_eval = np.linspace(0.0, prog.T, 41)
    sol = solve_ivp(rhs, (0.0, prog.T), X[0], "DOP853", t_eval=t_eval, rtol=1e-11, atol=1e-12)
    assert np.max(np.linalg.norm(sol.y.T - prog.solution(t_eval), axis=1)) <= 1e-6


def test_dense_output_between_the_steps():
    prog = motion_program(*HELIX)
    mid = 0.5 * (prog.steps[1:] + prog.steps[:-1])
    assert np.max(np.linalg.norm(prog.solution(mid) - prog.law(mid)["X"], axis=1)) < 1e-9
    assert np.array_equal(prog.solution(prog.steps), prog.Y)
    # at rest after T
    assert np.array_equal(prog.solution(np.array([prog.T + 5.0]))[0], prog.Y[-1])


def test_error_measure_detects_a_coarse_integration():
    prog = motion_program(*HELIX)
    steps = step_grid(prog, samples=6, angle=10.0)
    Y, _ = solve_15(prog, steps)
    assert len(steps) < 20
    assert np.max(np.linalg.norm(Y - prog.law(steps)["X"], axis=1)) > 1e-4


def test_controls_are_rank_one_and_reproduce_xdot():
    prog = motion_program(*HELIX)
    law = prog.law(np.linspace(0, prog.T, 301))
    U = prog.controls(law)
    assert np.max(np.abs(np.einsum("nij,nj->ni", U, law["X"]) - law["V"])) < 1e-14
    assert np.max(np.linalg.svd(U, compute_uv=False)[:, 1:]) < 1e-14
    assert np.min(law["D"]) == pytest.approx(1.0, abs=1e-12)  # (1.14): D = 1 + Z^2
    assert np.max(np.abs(np.linalg.norm(law["V"], axis=1) - law["v"])) < 1e-14


def test_symbolic_readings_of_1_15():
    ok, other, rank = controls_residuals()
    assert list(ok) == [0, 0, 0] and any(e != 0 for e in other) and rank == 1


def test_window_around_the_origin():
    prog = motion_program("phi", "phi", "phi", -1.0, 1.0, 1.0, 0.5, 0.5)
    (t_star,) = prog.singular_t
    assert t_star == pytest.approx(0.5 + math.sqrt(3) - 0.25, abs=1e-9)
    a, b = prog.gaps[0]
    Y = prog.solution(np.array([a, t_star, b]))
    assert np.all(np.isfinite(Y[0])) and np.all(np.isnan(Y[1])) and np.all(np.isfinite(Y[2]))
    assert np.allclose(Y[2], prog.law(np.array([b]))["X"][0], atol=1e-12)  # restarted
