"""The session object: parameters validated, refused values change nothing, state copyable."""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
from analyzer_lab.lessons.kit.contract import Frame, ParamError
from analyzer_lab.session.runlog import RunLog, scenes_equal
from analyzer_lab.session.session import LabError, Session, SessionState


@pytest.fixture()
def session() -> Session:
    s = Session([SPHERE], "sphere", "example-1.1")
    s.pause_at_end = False
    return s


def play(s: Session, frames: int = 10, dt: float = 1 / 30) -> None:
    s.play()
    for _ in range(frames):
        s.tick(dt)


def test_starts_on_preset(session: Session) -> None:
    assert session.lesson.id == "sphere" and session.preset == "example-1.1"
    assert np.allclose(session.frame.points["point"][0], (1, 0, 0))


def test_play_moves_the_point(session: Session) -> None:
    play(session, 15)
    assert session.frame.t == pytest.approx(0.5)
    assert not np.allclose(session.frame.points["point"][0], (1, 0, 0))
    assert session.frame.scalars["v2"] == pytest.approx(50.0)


def test_live_control_change_keeps_state(session: Session) -> None:
    play(session, 6)
    t, p = session.frame.t, session.frame.points["point"].copy()
    session.set_value("u1", "t")
    assert session.frame.t == t and np.allclose(session.frame.points["point"], p)
    play(session, 6)
    assert session.frame.scalars["u1"] == pytest.approx(session.frame.t)


@pytest.mark.parametrize(
    "name, raw",
    [
        ("R", -1.0),
        ("R", float("nan")),
        ("R", "abc"),
        ("R", "1e999"),
        ("u1", "__import__('os')"),
        ("u1", "open('x')"),
        ("u1", float("inf")),
        ("family", 2.5),
        ("integrator", "euler"),
        ("x0", [1, 2]),
    ],
)
def test_bad_values_are_refused_and_change_nothing(
    session: Session, name: str, raw: object
) -> None:
    play(session, 3)
    before = session.raw_values()
    t = session.frame.t
    with pytest.raises(ParamError) as err:
        session.set_value(name, raw)
    assert err.value.name in (name, "u1", "params")
    assert session.raw_values() == before
    play(session, 3)  # keeps running
    assert session.frame.t > t


def test_unknown_parameter_is_refused(session: Session) -> None:
    with pytest.raises(ParamError):
        session.set_value("no_such_param", 1)


def test_unknown_lesson_is_refused(session: Session) -> None:
    with pytest.raises(LabError, match="unknown lesson"):
        session.select_lesson("no-such-lesson")
    assert session.lesson.id == "sphere"


def test_unknown_lesson_at_start_is_corrected() -> None:
    s = Session([SPHERE], "nope")
    assert s.lesson.id == "sphere"
    assert any("unknown lesson" in text for _, text in s.notices)


def test_unknown_preset_is_refused(session: Session) -> None:
    with pytest.raises(ParamError):
        session.apply_preset("example-9.9")
    assert session.preset == "example-1.1"


def test_start_point_off_the_surface_is_projected_with_a_message(session: Session) -> None:
    session.set_values({"x0": 2.0, "y0": 0.0, "z0": 0.0})
    p = session.frame.points["point"][0]
    assert np.linalg.norm(p) == pytest.approx(1.0)
    assert any("off the surface" in text for _, text in session.notices)
    assert session.snap_start() == pytest.approx((1.0, 0.0, 0.0))
    assert session.params["x0"] == pytest.approx(1.0)


def test_click_start_point_restarts_the_run(session: Session) -> None:
    play(session, 5)
    session.set_start((0.0, 1.0, 0.0))
    assert session.frame.t == 0.0 and np.allclose(session.frame.points["point"][0], (0, 1, 0))
    with pytest.raises(LabError):
        session.set_start((math.nan, 0.0, 0.0))


def test_other_sessions_unaffected() -> None:
    a = Session([SPHERE], "sphere", "example-1.1")
    b = Session([SPHERE], "sphere", "example-1.1")
    with pytest.raises(ParamError):
        a.set_value("u1", "__import__('os')")
    a.set_value("u2", "1")
    play(b, 5)
    assert b.raw_values()["u2"] == "5" and a.raw_values()["u2"] == "1"
    assert a.frame.t == 0.0 and b.frame.t > 0


def test_speed_and_step_by_the_textbook_sampling(session: Session) -> None:
    session.set_speed(8)
    frames = session.step()  # the sphere's table is sampled at t = 0, 1, 2, ...
    assert session.frame.t == pytest.approx(1.0) and len(frames) >= 1
    session.go_to(0.4)
    session.step()  # to the next grid time, not by a whole step
    assert session.frame.t == pytest.approx(1.0)
    frames = session.go_to(3.25)
    assert session.frame.t == pytest.approx(3.25) and not session.playing
    assert session.frame.scalars["v2"] == pytest.approx(50.0, rel=1e-9)
    session.go_to(0.5)  # earlier: from the start again
    assert session.frame.t == pytest.approx(0.5)
    for bad in (-1.0, float("nan"), 1e9):
        with pytest.raises(LabError, match="go to t"):
            session.go_to(bad)
    for bad in (3, "fast", float("nan"), None):
        with pytest.raises(LabError):
            session.set_speed(bad)
    assert session.speed == 8


def test_pause_at_end(session: Session) -> None:
    session.pause_at_end = True
    session.set_speed(8)
    play(session, 60)
    assert session.frame.t == pytest.approx(10.0) and not session.playing


def test_the_end_of_a_run_is_not_told_to_the_run_started_again(session: Session) -> None:
    session.pause_at_end = True
    session.set_speed(8)
    play(session, 60)
    assert session.notice is not None and "t = 10 s reached" in session.notice[1]
    session.reset()
    assert session.notice is None and session.frame.t == 0.0
    assert any("reached" in text for _, text in session.notices)  # kept in the history
    # a notice that is not about the run stays through a reset
    session.notify("the start point was moved", "warning")
    session.reset()
    assert session.notice == ("warning", "the start point was moved")
    # a new end reached is told again
    play(session, 60)
    assert session.notice is not None and "reached" in session.notice[1]


def test_reset(session: Session) -> None:
    play(session, 5)
    session.reset()
    assert session.frame.t == 0.0 and len(session.log) == 1


@pytest.mark.parametrize(
    ("change", "reframed", "playing"),
    [
        (lambda s: s.select_lesson("sphere", "example-1.2"), True, False),
        (lambda s: s.apply_preset("example-1.2"), True, True),
        (lambda s: s.apply_state(SessionState("sphere", "example-1.2")), False, False),
        (lambda s: s.set_values({"x0": 0.0, "y0": 1.0, "z0": 0.0}), False, True),
        (lambda s: s.reset(), False, True),
        (lambda s: s.reset(playing=False, reframe=True), True, False),  # the Reset button
    ],
)
def test_every_path_starts_the_run_again_the_one_way(
    session: Session, change, reframed: bool, playing: bool
) -> None:
    """A new lesson, preset, state or start value and the Reset button: the run log keeps
    the start only and the pages clear their trails; the camera is framed again and the
    playback stopped where each path does so."""
    play(session, 6)
    resets, cameras = session.reset_revision, session.camera_revision
    change(session)
    assert session.frame.t == 0.0 and list(session.log.t) == [0.0]
    assert np.array_equal(session.frame.points["point"], session.stepper.frame().points["point"])
    assert session.reset_revision == resets + 1
    assert session.camera_revision == cameras + reframed
    assert session.playing is playing


def test_a_copied_run_goes_on_from_where_it_stands(session: Session) -> None:
    play(session, 6)
    other = Session([SPHERE], "sphere")
    other.apply_state(session.state())
    other.reset(stepper=copy.deepcopy(session.stepper), at=session.frame, playing=True)
    assert other.playing and other.frame is session.frame and len(other.log) == 1
    for s in (session, other):
        for _ in range(6):
            s.tick(1 / 30)
    assert other.frame.t == session.frame.t
    assert np.array_equal(other.frame.points["point"], session.frame.points["point"])


def test_state_round_trip_and_copy(session: Session) -> None:
    session.set_values({"u1": "sin(t)", "R": 2.0})
    session.set_speed(2)
    text = session.state().to_json()
    other = Session([SPHERE], "sphere")
    other.apply_state(SessionState.from_json(text))
    assert (
        other.raw_values() == session.raw_values()
        and other.speed == 2
        and other.preset == "example-1.1"
    )
    third = Session([SPHERE])
    third.copy_from(session)
    assert third.state() == session.state()


@pytest.mark.parametrize(
    "text", ["", "not json", "[]", '{"values": {}}', "x" * 30000, '{"lesson": 5}']
)
def test_malformed_saved_state_is_refused(text: str) -> None:
    with pytest.raises(LabError):
        SessionState.from_json(text)


def test_saved_state_with_bad_values_keeps_the_good_ones() -> None:
    text = json.dumps(
        {
            "lesson": "sphere",
            "preset": "example-9",
            "values": {"u1": "__import__('os')", "u2": "2", "R": -5, "zzz": 1},
            "speed": 1000,
        }
    )
    s = Session([SPHERE])
    problems = s.apply_state(SessionState.from_json(text))
    assert s.raw_values()["u2"] == "2" and s.raw_values()["u1"] == "5" and s.params["R"] == 1.0
    assert s.speed == 1.0 and s.preset is None and len(problems) >= 3


def test_run_result_exports_the_frames(session: Session) -> None:
    play(session, 9)
    res = session.run_result()
    assert len(res.t) == 10 and res.lesson == "sphere" and res.preset == "example-1.1"
    csv = res.to_csv().splitlines()
    assert csv[0].startswith("t,x,y,z") and "v2" in csv[0] and len(csv) == 11
    data = res.to_json_dict()
    assert data["params"]["u1"] == "5" and len(data["series"]["x"]) == 10


def test_run_log_is_bounded() -> None:
    log = RunLog(limit=100)
    for k in range(1000):
        log.add(Frame(t=float(k), points={"p": np.zeros((1, 3))}, scalars={"a": 1.0}))
    assert len(log) < 100 and log.samples[0].t == 0.0
    t = log.t
    assert np.all(np.diff(t) == log.stride) and log.stride == 16  # thinned evenly, in order


def test_run_log_keeps_missing_values_as_nan_and_grows_by_doubling() -> None:
    log = RunLog(limit=1000)
    log.add(Frame(t=0.0, points={"p": np.ones((2, 3))}, scalars={"a": 1.0}))
    log.add(Frame(t=1.0, points={"p": np.full((1, 3), 2.0)}, scalars={"b": 5.0}))
    assert log.points("p").shape == (2, 2, 3) and np.isnan(log.points("p")[1, 1]).all()
    assert (
        np.isnan(log.scalar("a")[1]) and np.isnan(log.scalar("b")[0]) and log.scalar("b")[1] == 5.0
    )
    assert log._cap == 64  # not the whole limit for a short run
    for k in range(200):
        log.add(Frame(t=2.0 + k, points={"p": np.zeros((2, 3))}, scalars={}))
    assert log._cap == 256 and len(log) == 202


def test_run_log_memory_at_its_cap_for_a_playing_sphere(session: Session) -> None:
    """A session that plays for ever keeps at most MAX_LOG rows: for the sphere's point
    and its 12 declared series that is about 2.6 MB (it was 18.6 MB as a list of dicts)."""
    from analyzer_lab.session.runlog import MAX_LOG

    log = RunLog()
    frame = session.frame
    for k in range(MAX_LOG + 5):
        log.add(frame)
    assert len(log) <= MAX_LOG
    assert log.nbytes <= (1 + 3 + len(frame.scalars)) * 8 * MAX_LOG
    assert log.nbytes < 3e6


def test_control_changes_defer_the_scene(session: Session) -> None:
    rev = session.scene_revision
    session.set_value("u1", "2")
    assert session.scene_revision == rev and session.scene_due is not None
    assert session.refresh_scene() is False  # same drawing: no redraw
    session.set_value("R", 2.0)
    assert session.scene_revision == rev + 1
    assert not scenes_equal(SPHERE.scene(SPHERE.resolve()), session.scene)


def test_trail_colours_segments_by_scalar():
    from analyzer_lab.view.scene import Trail

    class Recorder:
        def __init__(self):
            self.calls = []

        def add_line_segments(self, name, segs, colors, **kw):
            self.calls.append((name, np.asarray(segs), colors))
            return type("H", (), {"remove": lambda self: None})()

    rec = Recorder()
    tr = Trail(rec, "/t", (200, 0, 0), chunk=8, max_points=100)
    tr.color_by = (20.0, 40.0)
    for k, dev in enumerate([0.0, 10.0, 30.0, 80.0]):
        tr.add(np.array([[k, 0.0, 0.0]]), dev)
    tr.flush()
    _, segs, colors = rec.calls[-1]
    colors = np.asarray(colors)
    assert segs.shape == (3, 2, 3) and colors.shape == (3, 2, 3)
    assert colors[0, 0, 1] > colors[0, 0, 0]  # within tolerance: green
    assert colors[2, 0, 0] > colors[2, 0, 1]  # beyond twice the tolerance: red


def test_played_time_follows_the_wall_clock_in_quanta(session: Session) -> None:
    """Wall-clock ticks jitter; lesson time advances in whole TIME_QUANTUM pieces with the
    remainder carried over, so it stays within half a quantum of the wall time played."""
    from analyzer_lab.session.session import TIME_QUANTUM

    rng = np.random.default_rng(3)
    session.play()
    session.tick(1 / 36)
    wall = 1 / 36
    for _ in range(300):
        dt = float(rng.uniform(0.024, 0.032))
        wall += dt
        session.tick(dt)
    assert abs(session.stepper.t - wall) <= TIME_QUANTUM / 2 + 1e-12
    assert session.frame.scalars["v2"] == pytest.approx(50.0, rel=1e-9)
