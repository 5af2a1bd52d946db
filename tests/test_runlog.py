"""The run log's table of scalars: a frame's row written at once, the same columns as
one array per name (names in any order, missing ones NaN, new ones added)."""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.session.runlog import RunLog

NAN = float("nan")


def reference(frames: list[Frame]) -> dict[str, list[float]]:
    """One column per name, NaN where a frame lacks it (what the log keeps)."""
    names: list[str] = []
    for fr in frames:
        names += [n for n in fr.scalars if n not in names]
    return {n: [float(fr.scalars.get(n, NAN)) for fr in frames] for n in names}


def test_scalars_in_any_order_missing_or_new_keep_their_columns() -> None:
    frames = [
        Frame(t=0.0, scalars={"a": 1.0, "b": 2.0}),
        Frame(t=1.0, scalars={"a": 3.0, "b": 4.0}),
        Frame(t=2.0, scalars={"b": 5.0, "a": np.float64(6.0)}),  # another order
        Frame(t=3.0, scalars={"a": 7, "c": 8.0}),  # b missing, c new
        Frame(t=4.0, scalars={}),
        Frame(t=5.0, scalars={"c": True, "b": 9.0, "a": 10.0}),
        Frame(t=6.0, scalars={"a": np.array(11.0), "b": 12.0, "c": 13.0}),  # not plain
    ]
    log = RunLog(limit=1000)
    for fr in frames:
        log.add(fr)
    ref = reference(frames)
    assert log.scalar_names == list(ref) == ["a", "b", "c"]
    for name, col in ref.items():
        np.testing.assert_array_equal(log.scalar(name), col)
    assert log.sample(3).scalars == {"a": 7.0, "c": 8.0}
    assert log.sample(4).scalars == {}
    assert log.nbytes == log._t.nbytes + log._sc.nbytes


def test_thinning_and_growth_keep_rows_together() -> None:
    log = RunLog(limit=100)
    frames = [
        Frame(
            t=float(k),
            points={"p": np.full((2, 3), float(k))},
            scalars={"k": float(k), "sq": float(k * k)} if k % 3 else {"sq": float(k * k)},
        )
        for k in range(1000)
    ]
    for fr in frames:
        log.add(fr)
    t = log.t
    assert log.stride == 16 and np.all(np.diff(t) == 16)
    kept = [frames[int(v)] for v in t]
    ref = reference(kept)
    np.testing.assert_array_equal(log.scalar("sq"), ref["sq"])
    np.testing.assert_array_equal(log.scalar("k"), ref["k"])
    np.testing.assert_array_equal(log.points("p")[:, 0, 0], t)


def test_points_of_another_size_than_the_column() -> None:
    log = RunLog(limit=100)
    log.add(Frame(t=0.0, points={"p": np.ones((2, 3))}))
    log.add(Frame(t=1.0, points={"p": np.full((2, 3), 2.0)}))  # the same members: one copy
    log.add(Frame(t=2.0, points={"p": [3.0, 3.0, 3.0]}))  # one point, as a list
    log.add(Frame(t=3.0, points={"p": np.full((3, 3), 4.0)}))  # more than the column
    log.add(Frame(t=4.0, points={}))
    p = log.points("p")
    np.testing.assert_array_equal(p[1], 2.0)
    np.testing.assert_array_equal(p[2, 0], 3.0)
    np.testing.assert_array_equal(p[3], 4.0)
    assert np.isnan(p[2, 1]).all() and np.isnan(p[4]).all()
