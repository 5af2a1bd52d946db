"""``once`` (lessons/kit/once.py): computed at the first read, kept, computed once under
concurrent readers, and a slow value of one object never holds up another object's."""

from __future__ import annotations

import threading
from dataclasses import dataclass

from analyzer_lab.lessons.kit.once import once


@dataclass(frozen=True, eq=False)
class Slow:
    name: str
    gate: threading.Event
    calls: list[str]

    @once
    def value(self) -> str:
        """The value, after the gate opens."""
        self.calls.append(self.name)
        assert self.gate.wait(10)
        return self.name.upper()


def test_computed_once_and_kept() -> None:
    gate = threading.Event()
    gate.set()
    calls: list[str] = []
    a = Slow("a", gate, calls)
    assert a.value == "A" and a.value == "A" and calls == ["a"]
    assert Slow.value.__doc__ == "The value, after the gate opens."


def test_an_object_with_a_value_is_copied_and_pickled() -> None:
    import copy
    import pickle

    kept = Kept(3)
    assert kept.square == 9
    twin = copy.deepcopy(kept)
    assert twin.square == 9 and twin.__dict__["square"] == 9
    again = pickle.loads(pickle.dumps(kept))
    assert again.square == 9 and again.n == 3
    fresh = copy.deepcopy(Kept(4))  # copied before its value was read
    assert fresh.square == 16


@dataclass(frozen=True, eq=False)
class Kept:
    n: int

    @once
    def square(self) -> int:
        return self.n * self.n


def test_a_slow_object_does_not_hold_up_another() -> None:
    calls: list[str] = []
    slow = Slow("slow", threading.Event(), calls)
    quick_gate = threading.Event()
    quick_gate.set()
    quick = Slow("quick", quick_gate, calls)
    readers = [threading.Thread(target=lambda: slow.value) for _ in range(4)]
    for r in readers:
        r.start()
    while "slow" not in calls:  # the first reader is building the slow value
        threading.Event().wait(0.01)
    got: list[str] = []
    other = threading.Thread(target=lambda: got.append(quick.value))
    other.start()
    other.join(10)
    # the quick object's value came while the slow one's build still waits at its gate
    assert got == ["QUICK"] and not slow.gate.is_set()
    slow.gate.set()
    for r in readers:
        r.join(10)
    assert calls.count("slow") == 1 and slow.value == "SLOW"
