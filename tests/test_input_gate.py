"""The input gate: coalesced inputs are replayed, and a replay never lands after a newer
value of the same widget."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from analyzer_lab.classroom.input_gate import INPUT_BURST, REBUILD_COST, InputGate


@dataclass
class Widget:
    id: str


@dataclass
class Event:
    target: Widget
    value: str


@dataclass
class Page:
    """What the page's callback applied, in order."""

    applied: list[str] = field(default_factory=list)


def _gate() -> tuple[InputGate, dict[str, int]]:
    stats = {"admitted": 0, "coalesced": 0, "replayed": 0, "superseded": 0}
    gate = InputGate(stats, server=lambda: None)  # no callback queue: replayed in place
    gate.open(1)
    return gate, stats


def _send(gate: InputGate, page: Page, event: Event) -> None:
    def callback(e: Any) -> None:
        if gate.admit(1, e, callback):
            page.applied.append(e.value)

    callback(event)


def test_inputs_over_the_burst_wait_and_only_the_newest_is_replayed() -> None:
    gate, stats = _gate()
    page = Page()
    w = Widget("u1")
    for k in range(int(INPUT_BURST) + 5):
        _send(gate, page, Event(w, f"v{k}"))
    assert len(page.applied) == int(INPUT_BURST)
    assert stats["coalesced"] == 5
    gate.buckets[1].tokens = INPUT_BURST  # the bucket refilled
    gate.replay()
    assert page.applied[-1] == f"v{int(INPUT_BURST) + 4}"
    assert stats["replayed"] == 1 and not gate.pending


def test_a_replay_overtaken_by_a_newer_input_is_dropped() -> None:
    gate, stats = _gate()
    page = Page()
    w = Widget("u1")
    gate.buckets[1].tokens = 0.0
    _send(gate, page, Event(w, "old"))  # over the limit: waits
    assert page.applied == [] and stats["coalesced"] == 1
    # the replay is taken from the waiting inputs, but the page's own queue runs a newer
    # input before it
    key, (again, stale, _) = next(iter(gate.pending.items()))
    gate.pending.clear()
    gate.buckets[1].tokens = INPUT_BURST
    _send(gate, page, Event(w, "new"))
    gate.run_replayed(key, again, stale)
    assert page.applied == ["new"]
    assert stats["superseded"] == 1


def test_an_input_let_through_drops_an_older_waiting_value_of_its_widget() -> None:
    gate, stats = _gate()
    page = Page()
    w, other = Widget("u1"), Widget("V")
    gate.buckets[1].tokens = 0.0
    _send(gate, page, Event(w, "old"))
    _send(gate, page, Event(other, "2.0"))
    gate.buckets[1].tokens = INPUT_BURST
    _send(gate, page, Event(w, "new"))
    gate.replay()
    assert page.applied == ["new", "2.0"]  # the other widget's value still lands
    gate.forget(1)
    assert not gate.pending and not gate.newest


def test_a_choice_that_rebuilds_the_page_costs_more_than_a_slider_step() -> None:
    gate, stats = _gate()
    lesson, slider = Widget("lesson"), Widget("V")
    rebuilds = sum(gate.admit(1, Event(lesson, f"l{k}"), None, rebuilds=True) for k in range(50))
    assert rebuilds == int(INPUT_BURST / REBUILD_COST)  # 4 lessons at once, then 4 a second
    gate.buckets[1].tokens = INPUT_BURST
    steps = sum(gate.admit(1, Event(slider, str(k)), None) for k in range(50))
    assert steps == int(INPUT_BURST)
