"""Tests for lessons/laser5/interpolation.py: moves and controllers along one segment."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.laser5.interpolation import (
    Move,
    angle_between,
    bisect_segment,
    bisect_uniform,
    fixed_normal_move,
    mean_normal,
    move_deviation,
    nonlinear_submoves,
    off_normal_max,
    point_rate,
    point_speed_ratio,
    segment_distance,
)
from analyzer_lab.lessons.laser5.prototype import study


def test_segment_distance_broadcasts() -> None:
    a = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    b = np.array([[10.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # the second segment is a point
    d, lam = segment_distance(np.array([[5.0, 3.0, 0.0], [0.0, 4.0, 1.0]]), a, b)
    assert d == pytest.approx([3.0, 4.0]) and lam == pytest.approx([0.5, 0.0])


def test_tolerance_changes_pieces() -> None:
    s = study("S1")
    assert len(bisect_segment(s.machine, s.ends, s.qa, 0.1).moves) == 4
    assert len(bisect_segment(s.machine, s.ends, s.qa, 0.001).moves) == 64


def test_nonlinear_keeps_point_on_segment_at_constant_speed() -> None:
    for limits in ("original", "improved"):
        for name in ("S1", "S2", "S3", "S4"):
            s = study(name, limits)
            nl = s.nonlinear()
            assert nl.lead == ("B" if name == "S2" else "C")
            assert move_deviation(s.machine, nl) <= 1e-9
            assert point_speed_ratio(s.machine, nl) == pytest.approx(1.0, abs=1e-6)


def test_point_rate_linear_and_nonlinear() -> None:
    s = study("S3")
    m = s.machine
    tau = np.linspace(0.0, 1.0, 11)
    for mv in (s.linear(), s.nonlinear()):
        q = mv.axes(m, tau)
        rate = point_rate(m, q, mv.q0, mv.q1, mv.p0, mv.p1, mv.kind == "nonlinear")
        h = 1e-6
        t2 = np.clip(tau + h, 0, 1)
        t1 = np.clip(tau - h, 0, 1)
        numeric = (m.forward(mv.axes(m, t2))[0] - m.forward(mv.axes(m, t1))[0]) / (t2 - t1)[:, None]
        assert np.allclose(rate, numeric, atol=1e-4)


def test_nonlinear_as_linear_submoves_falls_as_inverse_square() -> None:
    s = study("S1")
    pa, _, pb, _ = s.ends
    devs = [
        max(
            move_deviation(s.machine, mv, pa, pb)
            for mv in nonlinear_submoves(s.machine, s.nonlinear(), N)
        )
        for N in (4, 16, 64)
    ]
    assert devs == pytest.approx([0.0874, 0.00547, 0.000342], rel=0.01)
    assert devs[0] / devs[1] == pytest.approx(16.0, rel=0.03)


def test_fixed_normal_half_angle() -> None:
    for name, half in (("S1", 1.645), ("S2", 1.690), ("S3", 2.578), ("S4", 1.718)):
        s = study(name)
        _, na, _, nb = s.ends
        mv = fixed_normal_move(s.machine, s.ends, float(s.qa[3]))
        assert mv.q0[3:] == pytest.approx(mv.q1[3:])
        assert move_deviation(s.machine, mv) <= 1e-9
        assert math.degrees(off_normal_max(s.machine, s.task, [mv], samples=1025)) == pytest.approx(
            half, abs=1e-3
        )
        assert math.degrees(float(angle_between(mean_normal(na, nb), na))) == pytest.approx(
            half, abs=1e-3
        )


def test_a_wrong_split_normal_would_fail() -> None:
    """The bisection claim would fail if the split normal were not the mean of the ends."""
    s = study("S1")
    pa, na, pb, _ = s.ends
    m = s.machine
    bad = [move_deviation(m, mv) for mv in bisect_uniform(m, s.ends, s.qa, 1)]
    assert max(bad) == pytest.approx(0.355, abs=1e-3)
    qm = m.inverse(0.5 * (pa + pb), na, float(s.qa[3]))  # the start normal kept at the split
    wrong = move_deviation(m, Move("linear", qm, s.qb, 0.5 * (pa + pb), pb))
    assert wrong > 0.355
