"""Tests for lessons/laser5/prototype.py: the four segments S1-S4 measured, the claims' checks."""

from __future__ import annotations

import math

import pytest
from analyzer_lab.lessons.laser5.interpolation import (
    axis_path_length,
    bisect_uniform,
    move_deviation,
    moves_backwards,
    off_normal_max,
    point_speed_ratio,
    sagitta_estimate,
)
from analyzer_lab.lessons.laser5.prototype import (
    CLAIMS,
    adaptive,
    near_vertical,
    study,
    uniform_levels,
)


def test_linear_interpolation_deviates() -> None:
    s = study("S1")
    dev = move_deviation(s.machine, s.linear())
    assert dev == pytest.approx(1.398, abs=0.001)
    assert sagitta_estimate(s.machine, s.qa, s.qb) == pytest.approx(dev, rel=0.005)
    s2, s3 = study("S2"), study("S3")
    assert move_deviation(s2.machine, s2.linear()) == pytest.approx(0.1305, abs=1e-4)
    assert move_deviation(s3.machine, s3.linear()) == pytest.approx(3.058, abs=1e-3)


def test_linear_speed_nonuniform() -> None:
    for name, ratio in (("S1", 1.008), ("S3", 1.061), ("S4", 2.295)):
        s = study(name)
        assert point_speed_ratio(s.machine, s.linear()) == pytest.approx(ratio, abs=2e-3)


def test_bisection_levels_quarter_per_split() -> None:
    lv = uniform_levels("S1", "original")
    assert lv[1:] == pytest.approx([0.355, 0.0891, 0.0223, 0.00558, 0.00139, 0.000349], rel=0.01)
    assert all(3.9 < lv[d] / lv[d + 1] < 4.05 for d in range(6))
    lv3 = uniform_levels("S3", "original")
    assert lv3[1] == pytest.approx(0.874, abs=1e-3)
    assert lv3[5] / lv3[6] == pytest.approx(4.0, abs=0.02)


def test_bisection_reaches_tolerance() -> None:
    for name, pieces, depth in (("S1", 16, 4), ("S2", 4, 2), ("S3", 16, 4)):
        b = adaptive(name, "original")
        assert b.converged and b.worst_mm <= 0.020
        assert (len(b.moves), b.max_depth) == (pieces, depth)


def test_nonlinear_orientation_and_axis_travel() -> None:
    for name, beam, xy in (("S1", 0.079, 5.9), ("S2", 0.006, 42.5), ("S3", 0.248, 35.9)):
        s = study(name)
        nl = s.nonlinear()
        assert math.degrees(off_normal_max(s.machine, s.task, [nl])) == pytest.approx(
            beam, abs=1e-3
        )
        assert axis_path_length(s.machine, [nl], slice(0, 2)) == pytest.approx(xy, abs=0.05)


def test_near_vertical_original_limits() -> None:
    r = near_vertical("original")
    assert r["dC"] == pytest.approx(-198.925, abs=0.01)
    assert r["linear"] == pytest.approx(243.5, abs=0.1)
    assert uniform_levels("S4", "original")[1:3] == pytest.approx([352.0, 364.0], abs=1.0)
    assert not r["converged"] and r["depth"] == 30 and r["worst"] == pytest.approx(403.0, abs=1.0)
    assert r["pieces"] == 143
    assert r["xy"] == pytest.approx(693.3, abs=0.2) and r["beam"] == pytest.approx(2.029, abs=2e-3)


def test_near_vertical_improved_limits() -> None:
    r = near_vertical("improved")
    assert r["dC"] == pytest.approx(-18.925, abs=0.01) and r["dB"] == pytest.approx(
        -3.484, abs=0.01
    )
    assert r["linear"] == pytest.approx(1.509, abs=1e-3)
    assert uniform_levels("S4", "improved")[1:] == pytest.approx(
        [41.4, 34.7, 22.4, 9.92, 3.18, 0.861], rel=0.01
    )
    assert r["converged"] and (r["pieces"], r["depth"]) == (122, 9)
    s = study("S4", "improved")
    pa, _, pb, _ = s.ends
    assert moves_backwards(s.machine, bisect_uniform(s.machine, s.ends, s.qa, 1), pa, pb)
    assert r["xy"] == pytest.approx(78.1, abs=0.1)


def test_every_check_passes() -> None:
    assert len(CLAIMS) == 14
    for claim_id, _, source, check in CLAIMS:
        result = check()
        assert result.passed, (claim_id, result.expected, result.got)
        assert source.startswith("LSP-2000 article")
