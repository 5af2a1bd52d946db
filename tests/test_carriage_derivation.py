"""The derivation steps of §2.3: lessons/vibration/carriage/derivation.py."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from analyzer_lab.lessons.vibration.carriage.derivation import (
    carriage_lagrange_matrices,
    forced_vibration_steps,
    free_vibration_steps,
)
from analyzer_lab.lessons.vibration.carriage.model import (
    Carriage,
    ForcedOscillator,
    carriage_lagrange,
    frequency_table,
)

CARRIAGE = Carriage(20.0, 0.27, 0.42, 0.68, 2e6, 2e6, 5e7, 8e5, 8e5, 6e4, 0.02)


def test_symbolic_matrices_are_the_numeric_ones() -> None:
    s = carriage_lagrange()
    M, K = carriage_lagrange_matrices()
    p = CARRIAGE
    numbers = [p.m, p.Ix, p.Iy, p.Iz, p.Cx, p.Cy, p.Cz, p.Kx, p.Ky, p.Kz, p.h]
    values = dict(zip([s.m, *s.I, *s.C, *s.K, s.h], numbers))
    Mn, Kn = CARRIAGE.matrices()
    assert np.array(M.subs(values), dtype=float) == pytest.approx(Mn)
    assert np.array(K.subs(values), dtype=float) == pytest.approx(Kn)


def test_free_steps_cover_2_35_to_2_77_and_end_with_this_carriage() -> None:
    steps = free_vibration_steps(frequency_table(CARRIAGE))
    assert steps[0].source == "(2.35)-(2.36)" and steps[-2].source == "(2.76)-(2.77)"
    assert steps[-1].title == "This carriage" and steps[-1].math.count(r"\text{") == 2 + 2 * 6
    rebuilt = {s.source for s in steps if s.reconstructed}
    assert {"(2.66)", "(2.68)", "(2.69)-(2.72)", "(2.74)", "(2.76)-(2.77)"} <= rebuilt
    assert all(isinstance(s.math, (str, sp.Basic, list)) for s in steps)


def test_forced_steps_cover_2_78_to_2_92_with_the_response_table() -> None:
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 4.0)
    steps = forced_vibration_steps(o, np.linspace(0.0, 15.0, 9))
    assert steps[0].source == "(2.78)" and "(2.92)" in [s.source for s in steps]
    table = steps[-1].math
    # every other grid frequency, omega0 = 4, omega = 5 and the peak 4.99199
    assert table.count(r"\\") == 1 + (5 + 3) - 1
    assert "0.16409" in table and "4.992" in table
