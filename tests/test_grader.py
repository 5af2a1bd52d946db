"""The grader: answers checked in a worker process, in line, within a CPU-time limit."""

from __future__ import annotations

import os
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from analyzer_lab.classroom.grader import GradeOutcome, Grader, GraderBusy
from analyzer_lab.lessons.assignments import grade, ready_assignments

from tests.support.waiting import wait_until

READY = {a.id: a for a in ready_assignments()}
CHEAP = READY["sphere-equator"]
COSTLY = READY["table-6dof-feedforward"]


class Told:
    """What one page was told: its places in line and its outcome."""

    def __init__(self) -> None:
        self.places: list[int] = []
        self.outcome: GradeOutcome | None = None
        self.done = threading.Event()

    def place(self, k: int) -> None:
        self.places.append(k)

    def finish(self, outcome: GradeOutcome) -> None:
        self.outcome = outcome
        self.done.set()


@pytest.fixture(scope="module")
def grader() -> Iterator[Grader]:
    g = Grader(student_burst=2.0)
    yield g
    g.close()


def _submit(g: Grader, key: str, a: Any, values: dict[str, Any]) -> tuple[Told, int]:
    told = Told()
    return told, g.submit(key, a, values, told.finish, told.place, owner=key)


def test_an_answer_is_graded_in_a_worker_process_as_in_this_one(grader: Grader) -> None:
    told, place = _submit(grader, "ann", CHEAP, dict(CHEAP.answers["correct"]))
    assert place == 1
    assert told.done.wait(120), "the verdict"
    assert told.outcome is not None and told.outcome.grade is not None
    here = grade(CHEAP, dict(CHEAP.answers["correct"]), "your answer")
    there = told.outcome.grade
    assert there.passed and here.passed
    assert [c.measured for c in there.checks] == [c.measured for c in here.checks]
    assert grader.worker_pid() not in (None, os.getpid())
    assert told.places[-1] == 0  # told it was being checked


def test_answers_wait_in_line_and_each_page_is_told_its_place(grader: Grader) -> None:
    first, _ = _submit(grader, "s0", COSTLY, dict(COSTLY.answers["correct"]))
    others = [_submit(grader, f"s{k}", CHEAP, dict(CHEAP.answers["wrong"])) for k in (1, 2, 3)]
    assert [place for _, place in others] in ([1, 2, 3], [2, 3, 4])
    for told, _ in [(first, 0), *others]:
        assert told.done.wait(300), "every verdict"
    last = others[-1][0]
    assert last.places == sorted(last.places, reverse=True) and last.places[-1] == 0
    assert len(last.places) >= 3  # moved up the line as the answers before it were checked
    assert first.outcome is not None and first.outcome.grade is not None
    assert first.outcome.grade.passed
    for told, _ in others:
        assert told.outcome is not None and told.outcome.grade is not None
        assert not told.outcome.grade.passed


def test_one_answer_in_line_per_student_and_a_rate_per_student(grader: Grader) -> None:
    first, _ = _submit(grader, "bob", COSTLY, dict(COSTLY.answers["correct"]))
    with pytest.raises(GraderBusy, match="previous answer"):
        _submit(grader, "bob", CHEAP, dict(CHEAP.answers["correct"]))
    assert first.done.wait(300)
    second, _ = _submit(grader, "bob", CHEAP, dict(CHEAP.answers["correct"]))
    assert second.done.wait(120)
    # a burst of 2, then 6 a minute: the third at once is refused and says when to retry
    with pytest.raises(GraderBusy, match="checks a minute"):
        _submit(grader, "bob", CHEAP, dict(CHEAP.answers["correct"]))


def test_a_refused_value_names_its_field(grader: Grader) -> None:
    told, _ = _submit(grader, "cy", CHEAP, {"u1": "sin(t"})
    assert told.done.wait(120)
    assert told.outcome is not None and told.outcome.grade is None
    assert told.outcome.field == "u1" and told.outcome.error


def test_a_page_that_leaves_takes_its_waiting_answer_with_it(grader: Grader) -> None:
    busy, _ = _submit(grader, "dee", COSTLY, dict(COSTLY.answers["correct"]))
    gone, _ = _submit(grader, "eve", CHEAP, dict(CHEAP.answers["correct"]))
    grader.cancel("eve")
    assert grader.place("eve") is None
    assert busy.done.wait(300)
    assert wait_until(lambda: grader.place("dee") is None, 30, "the line empty")
    assert not gone.done.is_set()


def test_a_check_over_its_cpu_time_is_stopped_and_the_worker_goes_on() -> None:
    g = Grader(cpu_seconds=0.3)
    try:
        costly, _ = _submit(g, "fay", COSTLY, dict(COSTLY.answers["correct"]))
        assert costly.done.wait(300)
        assert costly.outcome is not None and costly.outcome.grade is None
        assert "more than 0.3 s of computing" in costly.outcome.error
        pid = g.worker_pid()
        assert g.stats["overtime"] == 1 and g.stats["restarts"] == 0 and pid is not None
        cheap, _ = _submit(g, "gus", READY["linear-positioner-one-metre"], {})
        assert cheap.done.wait(120)
        assert g.worker_pid() == pid  # the same worker, not a new one
    finally:
        g.close()


def test_a_worker_that_dies_is_replaced_and_its_student_told() -> None:
    g = Grader()
    try:
        g.warm()
        assert wait_until(lambda: g.worker_pid() is not None, 60, "the worker started")
        first = g.worker_pid()
        told, _ = _submit(g, "hal", COSTLY, dict(COSTLY.answers["correct"]))
        assert wait_until(lambda: g.place("hal") == 0, 60, "the answer being checked")
        os.kill(first, 9)
        assert told.done.wait(120)
        assert told.outcome is not None and "stopped while checking" in told.outcome.error
        again, _ = _submit(g, "ida", CHEAP, dict(CHEAP.answers["correct"]))
        assert again.done.wait(120)
        assert again.outcome is not None and again.outcome.grade is not None
        assert g.worker_pid() not in (None, first) and g.stats["failed"] == 1
    finally:
        g.close()


def test_a_stopped_grader_takes_nothing() -> None:
    g = Grader()
    g.close()
    with pytest.raises(GraderBusy, match="stopping"):
        _submit(g, "jo", CHEAP, {})
