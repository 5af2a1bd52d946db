"""Tests of lessons/servo/model.py: the channel model and the exact two-axis solution."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo
from analyzer_lab.lessons.servo.paths import power_program
from scipy import linalg, signal


@pytest.mark.filterwarnings("ignore::scipy.signal.BadCoefficients")
def test_open_loop_channel_matches_closed_loop_of_W() -> None:
    k, T = 200.0, 0.5
    ch = Channel.from_open_loop(k, T)
    assert ch.T1 == pytest.approx(1 / k) and ch.T2sq == pytest.approx(T / k)
    # closed loop of W = k/((Ts+1)s) is k / (T s^2 + s + k) = 1 / ((T/k) s^2 + (1/k) s + 1)
    ss = ch.state_space()
    b, a = signal.ss2tf(ss.A, ss.B, ss.C, ss.D)
    assert np.allclose(b[0] / a[-1], [0.0, 0.0, 1.0])
    assert np.allclose(a / a[-1], [T / k, 1 / k, 1.0])
    w = 3.0
    expected = k / ((1j * w) * (T * 1j * w + 1) + k)
    assert ch.response(w) == pytest.approx(expected, rel=1e-12)
    _, h = signal.freqresp(ch.state_space(), [w])
    assert h[0] == pytest.approx(expected, rel=1e-10)


def test_exact_solution_agrees_with_lsim() -> None:
    """The matrix-exponential model and scipy.signal.lsim give the same channel output."""
    ch = Channel(0.01, 0.001)
    system = TwoAxisServo(power_program(2, -50.0, 0.0, 0.0, 20.0, 5.0), ch, ch)
    t = np.linspace(0.0, 2.0, 4001)
    out = system.outputs(system.states(t, system.initial_state()))
    _, y, _ = signal.lsim(ch.state_space(), out["y"], t, X0=[out["y"][0], 0.0])
    assert 0.0 < np.max(np.abs(y - out["y1"])) < 1e-3  # lsim interpolates linearly: O(dt^2)


def test_states_on_a_grid_equal_one_exponential_per_time() -> None:
    ch = Channel.from_open_loop(100.0, 0.1)
    system = TwoAxisServo(power_program(2, -125.0, 0.0, 0.0, 20.0, 5.0), ch, ch)
    z0 = system.initial_state()
    t = np.linspace(0.0, 5.0, 2001)
    grid = system.states(t, z0)
    for k in (0, 17, 999, 2000):
        exact = linalg.expm(t[k] * system.M) @ z0
        assert np.max(np.abs(grid[k] - exact)) <= 1e-12 * np.max(np.abs(exact))
    # from an anchor: exp(M (t - t_a)) z_a
    later = system.states([3.0], grid[800], t0=t[800])[0]
    assert np.allclose(later, system.states([3.0], z0)[0], rtol=0, atol=1e-9)


def test_program_correction_input_map() -> None:
    ch = Channel(0.01, 0.001)
    program = power_program(2, -125.0, 0.0, 0.0, 20.0, 5.0)
    system = TwoAxisServo(program, ch, ch, "on")
    t, out = system.settled_outputs(window=1.0, n=11)
    assert np.max(np.abs(out["x1"] - out["x"])) < 1e-7
    assert np.max(np.abs(out["y1"] - out["y"])) < 1e-7
    assert np.all(t > 20.0 / ch.decay_rate())
