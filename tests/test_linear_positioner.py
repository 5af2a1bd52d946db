"""Tests of analyzer_lab.lessons.mechanics.linear_positioner: Problem 2.1, eq. (2.2)."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.mechanics.linear_positioner import LESSON


def test_linear_numbers() -> None:
    r = LESSON.run("forward-constant-force")
    assert r.series["x"][-1] == pytest.approx(15.0, rel=1e-8)
    assert r.series["x_ddot"][0] == pytest.approx(0.3, rel=1e-12)
    inv = LESSON.run("inverse-cosine-move")
    t = inv.t
    want = 5.0 * 0.1 * (np.pi / 2) ** 2 * np.cos(np.pi * t / 2) + 0.5
    assert np.max(np.abs(inv.series["F_dv"] - want)) < 1e-9


def test_bad_formula_does_not_crash() -> None:
    lesson = LESSON
    r = lesson.simulate(lesson.resolve({"F_dv": "1/t"}), 1.0)
    assert r.messages and "F_dv" in r.messages[0]
    r = lesson.simulate(lesson.resolve({"problem": "inverse", "x_t": "log(t)"}), 1.0)
    assert r.messages
