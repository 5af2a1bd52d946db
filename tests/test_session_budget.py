"""A session's stepping budget per tick, the "running at" notice, and the pause on a
non-finite state."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.lessons.kit.budget import clock
from analyzer_lab.session.session import SOLO_STEP_BUDGET, STEP_BUDGET, Session
from analyzer_lab.session.state import SessionState
from analyzer_lab.view.persistence import restore_state
from analyzer_lab.view.readout import readout_html

LESSONS = all_lessons()
TICK = 1 / 36


def attacked(lesson_id: str, **values: object) -> Session:
    s = Session(LESSONS, lesson_id)
    s.set_values(values)
    s.pause_at_end = False
    s.set_speed(8)
    s.play()
    return s


@pytest.mark.parametrize("lesson_id", ["sphere", "sphere-constant-speed"])
def test_a_tiny_step_slows_only_its_own_clock_and_says_so(lesson_id: str) -> None:
    s = attacked(lesson_id, u1="5*sin(t)", h=1.1e-5)
    worst = 0.0
    for _ in range(60):  # 1.7 s of frames
        c0 = clock()
        s.tick(TICK)
        worst = max(worst, clock() - c0)
    assert worst < STEP_BUDGET + 0.1  # the budget plus at most one block of steps
    assert s.playing and s.slowed
    assert s.stepper.t < 0.9 * 60 * TICK * 8  # the session's own clock slowed down
    assert s.effective_speed() < 0.9 * 8
    level, text = s.notices[-1]
    assert level == "warning" and text.startswith("running at ")
    assert "the step is too small for live play" in text
    assert "running at" in readout_html(s)


def test_a_normal_run_is_not_slowed() -> None:
    s = Session(LESSONS, "sphere", "example-1.1")
    s.pause_at_end = False
    s.set_speed(8)
    s.play()
    for _ in range(60):
        s.tick(TICK)
    assert not s.slowed and "running at" not in readout_html(s)
    assert s.stepper.t == pytest.approx(60 * TICK * 8, abs=0.01)


def test_a_slowed_run_says_when_it_is_back_to_full_speed() -> None:
    s = attacked("sphere", u1="5*sin(t)", h=1.1e-5)
    for _ in range(60):
        s.tick(TICK)
    assert s.slowed
    s.set_values({"h": 0.01})
    for _ in range(60):
        s.tick(TICK)
    assert not s.slowed and s.notices[-1] == ("info", "playing at 8x again")


def test_a_non_finite_state_pauses_naming_the_quantity_and_time() -> None:
    s = attacked("sphere", u1="sqrt(101-t)")
    s.go_to(100.0)
    s.play()
    with np.errstate(all="ignore"):
        for _ in range(200):
            s.tick(0.25)
            if not s.playing:
                break
    assert not s.playing
    level, text = s.notices[-1]
    assert level == "error" and "is not finite" in text and "at t = 101" in text
    assert "playback paused" in text
    rows = len(s.log)
    assert all(np.all(np.isfinite(v)) for v in s.run_result().series.values())
    assert np.isfinite(s.frame.t) and np.all(np.isfinite(s.frame.points["point"]))
    # playing again pauses again at once: no non-finite row is ever added
    s.play()
    with np.errstate(all="ignore"):
        s.tick(0.25)
    assert not s.playing and len(s.log) == rows


def test_go_to_stops_after_its_budget_with_a_notice() -> None:
    s = Session(LESSONS, "sphere-constant-speed")
    s.set_values({"u1": "5*sin(t)", "h": 1.1e-5})
    c0 = clock()
    s.go_to(9.0)
    assert clock() - c0 < 1.5
    assert 0 < s.stepper.t < 9.0
    level, text = s.notices[-1]
    assert level == "warning" and text.startswith("go to t: stopped at t = ")


def test_messages_show_plain_numbers() -> None:
    s = Session(LESSONS, "sphere")
    with pytest.raises(Exception) as exc:
        s.set_speed(np.float64(3.0))
    assert "got 3" in str(exc.value) and "np.float64" not in str(exc.value)
    with pytest.raises(Exception) as exc:
        s.set_values({"h": np.float64(0.5)})
    assert str(exc.value) == "h: 0.5 is above the maximum 0.1 s"


class SavedPage:
    """A page's saved state as the browser's local storage hands it over."""

    def __init__(self, text: str) -> None:
        self.local_storage = self
        self.text = text

    def get_item(self, key: str, timeout: float = 2.0) -> str:
        return self.text


def test_a_restored_states_dropped_values_are_in_the_newest_notice() -> None:
    state = SessionState("sphere", None, {"u1": "2", "h": "oops"}, 1.0, True, None)
    s = Session(LESSONS, "sphere")
    restore_state(SavedPage(state.to_json()), s)
    level, text = s.notices[-1]
    assert level == "warning"
    assert text.startswith("restored your last lesson and parameters (sphere), but: h:")
    assert "value dropped" in text
    assert s.raw_values()["u1"] == "2"


def test_a_typed_speed_of_1e4_keeps_every_tick_within_the_budget() -> None:
    # one step of (1.59) cut into 10^4 substeps: charged substep by substep, never a whole
    # step (about 1.7 s) or a block of steps (a minute) inside one tick
    s = Session(LESSONS, "sphere-constant-speed", "varying-controls")
    s.pause_at_end = False
    s.play()
    s.set_values({"V": "1e4"})
    worst = 0.0
    for _ in range(60):
        c0 = clock()
        s.tick(TICK)
        worst = max(worst, clock() - c0)
    assert worst < STEP_BUDGET + 0.05, worst
    assert s.playing


def _preset_ids() -> list[tuple[str, str]]:
    return [(lesson.id, p.name) for lesson in LESSONS for p in lesson.presets]


@pytest.mark.parametrize(("lesson_id", "preset"), _preset_ids())
def test_every_preset_plays_at_least_half_real_time_on_the_budget_of_a_page_alone(
    lesson_id: str, preset: str
) -> None:
    """At 1x, 36 ticks of 1/36 s with the CPU budget the server gives the one run it
    plays: at least half a second of the lesson's time (the budget is CPU time: the
    figure holds on a busy machine)."""
    s = Session(LESSONS, lesson_id, preset)
    s.step_budget = SOLO_STEP_BUDGET
    s.pause_at_end = False
    s.set_speed(1)
    s.tick(TICK)  # the first step builds what the run keeps (not the played rate)
    s.play()
    t0 = s.frame.t
    for _ in range(36):
        s.tick(TICK)
    played = (s.frame.t - t0) / s.lesson.time_scale
    assert s.playing, s.notices
    assert played >= 0.5, f"{played:.3f} s of the lesson in 1 s"
