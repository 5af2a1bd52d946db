"""Tests of lessons/servo/paths.py: the programming devices and the contour error."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo
from analyzer_lab.lessons.servo.paths import CURVES, horizontal_parabola_program, make_path

NUMBERS = {"x0": 0.0, "y0": -30.0, "xc": 1.0, "yc": 2.0, "p": 20.0, "omega": 5.0, "v": 50.0}
NUMBERS.update({"angle": 30.0, "a": 15.0, "b": 6.0})


def test_horizontal_parabola_program_is_9_with_x_and_y_exchanged() -> None:
    program = horizontal_parabola_program(-30.0, 1.0, 2.0, 20.0, 5.0)
    ch = Channel(0.01, 0.001)
    system = TwoAxisServo(program, ch, ch)
    t = np.linspace(0.0, 2.0, 41)
    out = system.outputs(system.states(t, system.initial_state()))
    x, y = out["x"], out["y"]
    assert np.allclose(x - 1.0, (y - 2.0) ** 2 / 20.0, atol=1e-9)  # p (x - xc) = (y - yc)^2
    assert np.allclose(np.diff(y), 50.0 * np.diff(t))  # dy/dt = omega p / 2
    assert x[0] == pytest.approx(1.0 + 32.0**2 / 20.0)  # the start is taken on the curve


@pytest.mark.parametrize("curve", CURVES)
def test_programmed_point_has_no_contour_error(curve: str) -> None:
    g = dict(NUMBERS, y0=8.0) if curve in ("circle", "ellipse") else NUMBERS
    path = make_path(curve, g)
    ch = Channel(0.01, 0.001)
    system = TwoAxisServo(path.program, ch, ch)
    out = system.outputs(system.states(np.linspace(0.0, 0.5, 11), system.initial_state()))
    d, fx, fy = path.contour(out["x"], out["y"], out["x"], out["y"])
    assert np.max(np.abs(d)) < 1e-9
    assert np.allclose(fx, out["x"]) and np.allclose(fy, out["y"])


def test_horizontal_parabola_contour_sign_and_vertex() -> None:
    path = make_path("parabola-horizontal", dict(NUMBERS, xc=0.0, yc=0.0))
    assert path.vertex() == ("vertex", pytest.approx((0.0, 0.0)))
    x, y = np.array([path.start[0]]), np.array([path.start[1]])
    inside = path.contour(x + 0.1, y, x, y)[0]
    outside = path.contour(np.array([-0.2]), np.array([0.0]), x, y)[0]
    assert inside[0] > 0 and outside[0] == pytest.approx(-0.2)
