"""The finiteness check of a played frame: one sum, then quantity by quantity only when
something is not finite (the same answer and message as checking each quantity)."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.session.pace import first_non_finite, non_finite
from analyzer_lab.session.session import Session

LESSONS = all_lessons()
NAN, INF = float("nan"), float("inf")


def frame(scalars=None, points=None, vectors=None) -> Frame:
    return Frame(
        t=1.25,
        points=points if points is not None else {"point": np.array([[1.0, 2.0, 3.0]])},
        vectors=vectors
        if vectors is not None
        else {"velocity": (np.zeros((1, 3)), np.ones((1, 3)))},
        scalars=scalars if scalars is not None else {"x": 1.0, "speed": 2.0},
    )


CASES = [
    frame(),
    frame(scalars={"x": 1.0, "u11": NAN, "speed": 2.0}),
    frame(scalars={"x": 1.0, "u11": NAN, "speed": INF}),
    frame(scalars={"x": np.float64(-INF), "y": NAN}),
    frame(scalars={"x": 1.0, "n": 3, "label": "text"}),  # not a number: not checked
    frame(scalars={"x": 1e308, "y": 1e308}),  # the sum overflows, every value is finite
    frame(points={"point": np.array([[1.0, NAN, 0.0]])}),
    frame(points={"point": [[1.0, 2.0, 3.0]], "digital": np.array([[INF, 0.0, 0.0]])}),
    frame(points={"point": np.full((200, 3), 1e307)}),  # large: summed by numpy
    frame(points={"point": np.r_[np.zeros((199, 3)), [[0.0, -INF, 0.0]]]}),
    frame(points={"p": np.array([[1, 2, 3]], dtype=np.int64)}),
    frame(vectors={"velocity": (np.zeros((1, 3)), np.array([[INF, -INF, 0.0]]))}),
    frame(vectors={"gradient": (np.array([[NAN, 0.0, 0.0]]), np.zeros((1, 3)))}),
    frame(vectors={"velocity": (np.zeros(3), [1.0, 2.0, 3.0])}),
]


@pytest.mark.parametrize("case", range(len(CASES)))
@pytest.mark.parametrize("allowed", [frozenset(), frozenset({"u11", "y"})])
def test_one_sum_answers_as_each_quantity_does(case: int, allowed: frozenset[str]) -> None:
    fr = CASES[case]
    assert non_finite(fr, allowed) == first_non_finite(fr, allowed)


def test_the_answers_name_the_first_bad_quantity() -> None:
    assert non_finite(CASES[0]) is None and non_finite(CASES[5]) is None
    assert non_finite(CASES[1]) == "u11" and non_finite(CASES[1], frozenset({"u11"})) is None
    assert non_finite(CASES[2], frozenset({"u11"})) == "speed"
    assert non_finite(CASES[6]) == "the point" and non_finite(CASES[7]) == "the digital"
    assert non_finite(CASES[9]) == "the point" and non_finite(CASES[8]) is None
    assert non_finite(CASES[11]) == "the velocity vector"
    assert non_finite(CASES[12]) == "the gradient vector"


@pytest.mark.parametrize(
    ("lesson_id", "values"),
    [("sphere", {"u1": "sqrt(101-t)"}), ("circle", {"u": "sqrt(101-t)"})],
)
def test_a_non_finite_played_frame_pauses_with_the_same_message(lesson_id, values) -> None:
    """The frames of a run that becomes non-finite: each is judged as quantity by quantity,
    and the session pauses naming the quantity and the time."""
    s = Session(LESSONS, lesson_id)
    s.set_values(values)
    s.pause_at_end = False
    s.set_speed(8)
    s.go_to(100.0)
    seen = []
    step = s.pace.step

    def judged(stepper, d: float, allowed: frozenset[str]):
        fr, why = step(stepper, d, allowed)
        seen.append((stepper.frame(), why))
        return fr, why

    s.pace.step = judged  # type: ignore[method-assign]
    s.play()
    with np.errstate(all="ignore"):
        for _ in range(100):
            s.tick(0.25)
            if not s.playing:
                break
    assert not s.playing
    allowed = s._allowed()
    for fr, why in seen:
        assert non_finite(fr, allowed) == first_non_finite(fr, allowed)
    bad = [(fr, why) for fr, why in seen if why]
    assert len(bad) == 1
    fr, why = bad[0]
    name = first_non_finite(fr, allowed)
    assert name is not None and why.startswith(f"{name} is not finite (NaN or infinite) at t = ")
    assert s.notices[-1] == ("error", why)


@pytest.mark.parametrize("ticks", [[21], [19, 25, 17, 40, 21], [60, 150]])
def test_pieces_of_a_long_tick_are_whole_grains(ticks: list[int]) -> None:
    """A tick longer than one piece (1/30 s) is cut into pieces of whole grains, so every
    frame lands on a grain time (the times lessons keep tables for)."""
    from analyzer_lab.session.pace import TIME_QUANTUM

    s = Session(LESSONS, "table-6dof", "inverse-program")
    s.play()
    times = []
    for k in ticks:
        times += [f.t for f in s.advance_wall(k * TIME_QUANTUM)]
    grains = np.array(times) / TIME_QUANTUM
    assert len(times) > len(ticks)  # some ticks were cut into pieces
    assert np.abs(grains - np.round(grains)).max() < 1e-6
