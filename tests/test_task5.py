"""Tests for lessons/laser5/task.py: workpieces and task paths."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.laser5.task import Paraboloid, SphereCap, make_task


def test_workpieces_points_and_normals() -> None:
    par = Paraboloid()
    p, n = par.point_normal(np.array([300.0]), np.array([0.0]))
    assert p[0] == pytest.approx([1800.0, 1500.0, 900.0 - 300.0**2 / 2000.0])
    assert n[0] == pytest.approx(np.array([0.3, 0.0, 1.0]) / math.hypot(0.3, 1.0))
    sph = SphereCap(R=1000.0)
    p, n = sph.point_normal(np.array([0.0, 600.0]), np.array([0.0, 0.0]))
    assert p[0] == pytest.approx([1500.0, 1500.0, 400.0])
    assert np.linalg.norm(p[1] - np.array([1500.0, 1500.0, 1400.0])) == pytest.approx(1000.0)
    assert n[1] == pytest.approx([-0.6, 0.0, 0.8])
    for wp in (par, sph):
        mesh = wp.mesh()
        assert len(mesh.faces) > 100 and np.isfinite(mesh.vertices).all()


def test_paths_line_and_closed_circle() -> None:
    line = make_task(Paraboloid(), "line", 4, (0.0, 0.0), (100.0, 0.0))
    assert line.segments == 4 and np.allclose(line.uv[:, 0], [0, 25, 50, 75, 100])
    circle = make_task(Paraboloid(), "circle", 32, radius=300.0)
    assert circle.segments == 32 and np.array_equal(circle.points[0], circle.points[-1])
    assert np.allclose(np.hypot(*circle.uv.T), 300.0)


def test_normal_below_a_chord_point() -> None:
    task = make_task(Paraboloid(), "line", 1, (100.0, 0.0), (160.0, 0.0))
    mid = task.normal_at(np.array([0]), np.array([0.5]))
    assert mid[0] == pytest.approx(Paraboloid().point_normal(np.array(130.0), np.array(0.0))[1])
    assert task.normal_at(0, np.array([-1.0, 2.0])) == pytest.approx(task.normals)
