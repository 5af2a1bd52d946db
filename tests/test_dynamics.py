"""Tests of analyzer_lab.lessons.mechanics.positioners.dynamics: a page solved once per
parameter set."""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.kit.formula import parse_formula
from analyzer_lab.lessons.mechanics.positioners.dynamics import (
    PROBLEM,
    DynamicsLesson,
    check_formulas,
)
from analyzer_lab.lessons.mechanics.table_6dof import LESSON as TABLE


def test_formulas_not_finite_on_the_grid_are_named() -> None:
    t = np.linspace(0.0, 2.0, 5)
    msgs = check_formulas([("F", parse_formula("sin(t)")), ("G", parse_formula("1/(t - 1)"))], t)
    assert len(msgs) == 1 and msgs[0].startswith("G: ")


def test_every_dynamics_page_has_the_problem_mode() -> None:
    assert PROBLEM.choices == ("forward", "inverse")
    assert isinstance(TABLE, DynamicsLesson) and TABLE.modes[0] == "problem"
    assert DynamicsLesson.modes == ("problem",)


def test_one_solution_per_parameter_set() -> None:
    params = TABLE.resolve()
    assert TABLE.solution(params) is TABLE.solution(TABLE.resolve())
