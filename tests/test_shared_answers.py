"""Answers kept per parameter set are shared by every page of a server; its pages are built
and played on several threads at once (the connect handlers and the frame loop)."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.lessons.kit.steppers import DenseSolution

pytestmark = pytest.mark.quick


def _on_threads(work, n: int = 12) -> list[BaseException]:
    errors: list[BaseException] = []
    start = threading.Barrier(n)

    def run() -> None:
        start.wait()
        try:
            work()
        except BaseException as exc:  # noqa: BLE001 - reported by the test
            errors.append(exc)

    threads = [threading.Thread(target=run) for _ in range(n)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    return errors


def test_one_solution_read_from_many_threads_is_the_solution_read_from_one() -> None:
    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return np.array([y[1], -np.sin(y[0])])

    shared = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]), chunk=0.5)
    alone = DenseSolution(rhs, 0.0, np.array([1.0, 0.0]), chunk=0.5)
    times = np.linspace(0.0, 20.0, 401)
    got: list[np.ndarray] = []

    def read() -> None:
        got.append(np.array([shared(np.array([t]))[0] for t in times]))

    assert _on_threads(read) == []
    want = alone(times)
    for g in got:
        assert np.array_equal(g, want)


@pytest.mark.parametrize(
    "lesson_id", ["linear-positioner", "rotary-positioner", "planar-3axis", "table-6dof"]
)
def test_pages_built_and_played_at_once_share_one_run(lesson_id: str) -> None:
    lesson = get_lesson(lesson_id)
    preset = lesson.presets[0].name
    lesson.__class__._cache.clear()  # noqa: SLF001 - a fresh server
    lesson.__class__._by_object.clear()  # noqa: SLF001
    states: list[np.ndarray] = []

    def page() -> None:
        params = lesson.resolve({}, preset)
        stepper = lesson.stepper(params)
        for _ in range(40):
            stepper.advance(1 / 36)
        states.append(np.asarray(stepper.state(), dtype=float))

    assert _on_threads(page) == []
    alone = lesson.stepper(lesson.resolve({}, preset))
    for _ in range(40):
        alone.advance(1 / 36)
    for s in states:
        assert np.array_equal(s, np.asarray(alone.state(), dtype=float))
