"""The frame cost benchmark plays a lesson the way the server does and times it."""

from benchmarks.frame_cost import frame_cost, main


def test_frame_cost_times_a_played_session() -> None:
    preset, ms, stepper_ms = frame_cost("sphere", frames=20)
    assert preset == "example-1.1"
    assert 0.0 < stepper_ms <= ms < 50.0  # the stepper's share is part of the frame


def test_table_has_a_row_per_lesson_asked(capsys) -> None:
    assert main(["--frames", "5", "--lesson", "sphere", "servo-errors"]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith("| ")]
    assert len(rows) == 3 and rows[1].startswith("| sphere |") and "servo-errors" in rows[2]
