"""Tests of lessons/servo/table.py: the article's parabola table three ways."""

from __future__ import annotations

import math

import pytest
from analyzer_lab.lessons.servo.table import parabola_table, table_ratio_interval, table_row


def test_parabola_table_three_ways() -> None:
    rows = parabola_table()
    assert len(rows) == 16
    cell = table_row(100.0, 0.1)
    assert cell is not None and table_row(100.0, 0.2) is None
    assert cell.formula_13 == pytest.approx(-0.2375)
    assert cell.simulated == pytest.approx(-0.2375, rel=1e-4)
    assert cell.printed == pytest.approx(-0.19)
    assert cell.printed_over_formula == pytest.approx(0.8)
    for r in rows:
        assert r.simulated == pytest.approx(r.formula_13, rel=0.01)
        assert r.within_print_rounding, r
        assert abs(r.printed - r.formula_13) > 0.1 * abs(r.formula_13)  # the print is not (13)
    lo, hi = table_ratio_interval()
    assert lo == pytest.approx(0.79467, abs=1e-4) and hi == pytest.approx(0.80533, abs=1e-4)


def test_table_with_omega_squared_20_matches_the_print() -> None:
    for r in parabola_table(omega=math.sqrt(20.0)):  # omega^2 = 20 reproduces the print
        decimals = len(r.printed_text.split(".")[1]) if "." in r.printed_text else 0
        assert abs(r.simulated - r.printed) <= 0.5 * 10**-decimals + 1e-9
