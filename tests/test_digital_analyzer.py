"""The digital analyzer (1.24)-(1.25): successive additions, step pulses, error against the continuous path."""

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.plane.conic import (
    DigitalAnalyzer,
    PlanarModel,
    radius_growth_per_turn,
)

CIRCLE = PlanarModel.of({"a11": 1.0, "a22": 1.0}, 1.0)


def turn(mode, delta=0.01, pulse=0.0, R=5.0, turns=1):
    dda = DigitalAnalyzer(CIRCLE, np.array([[R, 0.0]]), delta, pulse, mode)
    pos, pul = dda.run(int(round(turns * 2 * np.pi / delta)))
    return dda, pos[:, 0], pul[:, 0]


@pytest.mark.parametrize("delta", [0.02, 0.01, 0.005])
def test_simple_spirals_out_by_pi_delta_R(delta):
    _, pos, _ = turn("simple", delta)
    growth = np.hypot(*pos[-1]) - 5.0
    assert growth == pytest.approx(np.pi * delta * 5.0, rel=0.04)
    assert growth == pytest.approx(5.0 * radius_growth_per_turn(delta, "simple"), rel=1e-3)


@pytest.mark.parametrize("delta", [0.02, 0.01, 0.005])
def test_improved_stays_within_delta_R_over_4(delta):
    _, pos, _ = turn("improved", delta, turns=3)
    dev = np.abs(np.hypot(pos[:, 0], pos[:, 1]) - 5.0)
    assert dev.max() == pytest.approx(delta * 5.0 / 4.0, rel=0.03)
    # the modified invariant x² + y² + Δxy is kept to round-off
    x, y = pos[:, 0], pos[:, 1]
    inv = x**2 + y**2 + delta * x * y
    assert np.ptp(inv) < 1e-9


def test_pulses_are_integers_and_positions_on_the_grid():
    dda, pos, pul = turn("improved", 0.01, pulse=0.05)
    assert pul.dtype.kind == "i"
    steps = (pos - np.array([5.0, 0.0])) / 0.05
    assert np.allclose(steps, np.round(steps), atol=1e-9)
    assert np.array_equal(np.cumsum(pul, axis=0)[-1], dda.n[0].astype(int))
    # about 4R/pulse pulses per axis per turn
    assert np.abs(pul[:, 0]).sum() == pytest.approx(4 * 5.0 / 0.05, rel=0.05)


def test_error_shrinks_with_delta():
    errs = []
    for d in (0.02, 0.01):
        _, pos, _ = turn("simple", d)
        errs.append(abs(np.hypot(*pos[-1]) - 5.0))
    assert errs[1] == pytest.approx(errs[0] / 2, rel=0.05)


def test_lessons_expose_dda_series():
    from analyzer_lab.lessons.analyzers.circle import LESSON

    res = LESSON.run("digital-staircase")
    for k in ("x_dda", "y_dda", "z_dda", "nx", "ny", "dda_error"):
        assert res.series[k].shape == res.t.shape
    assert res.metrics["pulses_x"] > 0 and res.metrics["dda_error_max"] < 0.5
    st = LESSON.stepper(LESSON.resolve(preset="digital-staircase"))
    f = st.advance(1.0)
    assert "digital" in f.points and f.scalars["dda_error"] < 0.5


def test_bad_mode_refused():
    with pytest.raises(ValueError):
        DigitalAnalyzer(CIRCLE, np.array([[1.0, 0.0]]), 0.01, 0.0, "fast")
