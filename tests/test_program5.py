"""Tests for lessons/laser5/program.py: the executed CNC program and its playhead."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.laser5.kinematics import Machine5
from analyzer_lab.lessons.laser5.program import build_program, program_metrics
from analyzer_lab.lessons.laser5.prototype import SEGMENTS
from analyzer_lab.lessons.laser5.task import Paraboloid, make_task


def _program(method: str, segment: str = "S1", **more):
    a, b = SEGMENTS[segment]
    task = make_task(Paraboloid(), "line", 1, a, b)
    return build_program(Machine5(), task, method, 0.020, 10.0, **more)


def test_moves_and_durations() -> None:
    prog = _program("bisection")
    assert len(prog.moves) == 16 and prog.converged and not prog.notes
    assert prog.duration == pytest.approx(6.0027, abs=1e-4)
    assert np.allclose(prog.starts[1:], np.cumsum(prog.durations)[:-1])


def test_playhead_boundaries_belong_to_the_earlier_move() -> None:
    prog = _program("bisection")
    end0 = prog.starts[1]
    head = prog.playhead([0.0, end0, end0 * (1 + 1e-14), end0 * 1.5, prog.duration + 1.0])
    assert list(head.move) == [0, 0, 0, 1, 15]
    assert head.tau == pytest.approx([0.0, 1.0, 1.0, 0.5, 1.0])
    assert list(head.running) == [True, True, True, True, False]


def test_sample_speed_travel_and_hold() -> None:
    nl = _program("nonlinear")
    s = nl.sample(nl.playhead(np.linspace(0.0, nl.duration, 7)))
    assert s["speed"] == pytest.approx(10.0, rel=1e-12)  # (4): constant contour speed
    assert s["deviation"].max() <= 1e-9
    assert s["travel_tool"][-1] == pytest.approx(60.027, abs=1e-3)
    lin = _program("linear")
    head = lin.playhead([lin.duration / 2, lin.duration + 1.0])
    s = lin.sample(head)
    assert s["deviation"][0] == pytest.approx(1.398, abs=2e-3)
    assert s["speed"][1] == 0.0  # the tool holds after the task
    assert np.all(np.diff(lin.sample(lin.playhead(np.linspace(0, 6, 50)))["travel_linear"]) >= 0)


def test_sample_times_end_at_t_end() -> None:
    prog = _program("bisection")
    t = prog.sample_times(2.0)
    assert t[0] == 0.0 and t[-1] == 2.0 and np.all(np.diff(t) > 0)
    assert prog.sample_times(10.0)[-2] == pytest.approx(prog.duration)


def test_metrics_by_method() -> None:
    lin, bis, nl, fn = (
        program_metrics(_program(m)) for m in ("linear", "bisection", "nonlinear", "fixed-normal")
    )
    assert lin["deviation_max_um"] == pytest.approx(1398.0, abs=1.0)
    assert bis["moves"] == 16 and bis["deviation_max_um"] <= 20.0 and bis["within_tolerance"]
    assert nl["deviation_max_um"] <= 1e-6
    assert fn["off_normal_max_deg"] == pytest.approx(1.645, abs=1e-3) and fn["laser_switches"] == 1


def test_bisection_that_cannot_converge_says_why() -> None:
    prog = _program("bisection", "S4")
    assert not prog.converged and prog.notes[0].kind == "warning"
    assert "vertical" in prog.notes[0].text and "segment 1" in prog.notes[0].text
    assert program_metrics(prog)["deviation_max_um"] > 4e5
