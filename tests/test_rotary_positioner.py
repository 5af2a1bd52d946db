"""Tests of analyzer_lab.lessons.mechanics.rotary_positioner: Problem 2.2, eqs (2.3)-(2.4)."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.kit.contract import ParamError
from analyzer_lab.lessons.mechanics.rotary_positioner import LESSON


def test_rotary_inertia_and_validation() -> None:
    lesson = LESSON
    inv = lesson.run("inverse-quarter-turn")
    J = 1.0 * 0.2**2 + 0.5 * 0.3**2 + 2.0 * 0.1**2
    t = inv.t
    phidd = 0.25 * np.sin(t)  # phi = (t - sin t)/4
    assert np.max(np.abs(inv.series["M_dv"] - J * phidd)) < 1e-9
    with pytest.raises(ParamError):
        lesson.resolve({"h1": 0, "h2": 0, "h3": 0})


def test_reduced_inertia_series() -> None:
    r = LESSON.run("forward-constant-moment", t_end=1.0)
    assert np.allclose(r.series["J_z"], 0.105, rtol=1e-12) and r.units["J_z"] == "kg m^2"
