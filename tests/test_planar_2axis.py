"""Tests of analyzer_lab.lessons.mechanics.planar_2axis: Problem 2.3, eqs (2.5)-(2.11)."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.mechanics.planar_2axis import LESSON


def test_planar2_layouts_differ() -> None:
    lesson = LESSON
    h = lesson.run(values={"layout": "horizontal", "Q_y": "0"}, t_end=1.0)
    v = lesson.run(values={"layout": "vertical", "Q_y": "0"}, t_end=1.0)
    assert h.series["y"][-1] == pytest.approx(0.0, abs=1e-12)
    assert v.series["y"][-1] == pytest.approx(-9.81 / 2, rel=1e-8)
    assert np.allclose(v.series["v"], np.hypot(v.series["x_dot"], v.series["y_dot"]))


def test_corrected_equation_note() -> None:
    notes = LESSON.notes(LESSON.resolve())
    assert [n.kind for n in notes] == ["corrected"] and notes[0].source == "(2.11)"
