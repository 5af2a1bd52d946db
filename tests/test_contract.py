"""The lesson contract itself: declarations checked, one observation, results that say
where a series is not defined."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.lessons.kit.contract import (
    MODE,
    Frame,
    Group,
    Lesson,
    Note,
    ObservationError,
    Param,
    ParamError,
    Params,
    Preset,
    SceneSpec,
    Series,
    Stepper,
)


class Decay(Lesson):
    """x' = -k x from x0 (a small lesson of its own, for the contract's machinery)."""

    id = "decay"
    groups = (MODE, Group("rate", "Rate", change="live", when=("shape", ("exp",))))
    modes = ("shape",)
    family = "family"
    params = (
        Param("shape", "choice", "exp", choices=("exp", "sqrt"), group="mode"),
        Param("k", "float", 1.0, min=0.0, max=10.0, group="rate"),
        Param("family", "int", 1, min=1, max=3, group="mode"),
    )
    series = (
        Series("x", "m", "the decaying quantity", member=True),
        Series("k_used", "1/s", "the rate"),
    )
    readout = ("x",)
    sampling = 0.5

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, Any]:
        out: dict[str, Any] = {"k_used": np.full(len(t), params["k"])}
        for m in range(int(params["family"])):
            name = "x" if m == 0 else f"x_{m + 1}"
            out[name] = np.sqrt(1.0 - t) if params["shape"] == "sqrt" else np.exp(-t) * (m + 1)
        return out

    def simulate(self, params: Params, t_end: float | None = None):  # type: ignore[override]
        t = self.sample_grid(t_end or 2.0)
        return self.result(params, t, None)

    def derivation(self, params: Params) -> list:  # type: ignore[override]
        return []

    def stepper(self, params: Params) -> Stepper:  # type: ignore[override]
        raise NotImplementedError

    def scene(self, params: Params):  # type: ignore[override]
        raise NotImplementedError

    def claims(self) -> list:  # type: ignore[override]
        return []


def test_declarations_are_checked() -> None:
    assert Decay().declaration_errors() == []

    class Broken(Decay):
        groups = (MODE,)
        readout = ("nothing",)

    errors = Broken().declaration_errors()
    assert any("group 'rate' is not declared" in e for e in errors)
    assert any("readout 'nothing'" in e for e in errors)


def test_family_members_get_their_own_columns_and_units() -> None:
    lesson = Decay()
    params = lesson.resolve({"family": 3})
    names = [s.name for s in lesson.series_for(params)]
    assert names == ["x", "k_used", "x_2", "x_3"]
    result = lesson.simulate(params, 2.0)
    assert list(result.series) == names
    assert result.units == {"x": "m", "k_used": "1/s", "x_2": "m", "x_3": "m"}
    assert list(result.t) == [0.0, 0.5, 1.0, 1.5, 2.0]  # the lesson's sampling
    assert result.series["x_3"][0] == pytest.approx(3.0)
    assert result.to_json_dict()["units"]["x_2"] == "m"


def test_a_series_that_is_not_defined_is_reported_not_silent() -> None:
    lesson = Decay()
    result = lesson.simulate(lesson.resolve({"shape": "sqrt"}), 2.0)
    assert np.isnan(result.series["x"][-1])
    assert any(m.startswith("x is not defined from t = 1.5") for m in result.messages)


def test_an_observation_that_differs_from_the_declarations_is_refused() -> None:
    class Sloppy(Decay):
        def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, Any]:
            return {"x": np.zeros(len(t)), "extra": np.zeros(len(t))}

    with pytest.raises(ObservationError, match="missing \\['k_used'\\], undeclared \\['extra'\\]"):
        Sloppy().simulate(Sloppy().resolve(), 1.0)


def test_groups_apply_to_their_mode_values() -> None:
    lesson = Decay()
    rate = lesson.group("rate")
    assert rate.applies(lesson.resolve()) and not rate.applies(lesson.resolve({"shape": "sqrt"}))
    assert lesson.describe()["groups"][1] == {
        "name": "rate",
        "title": "Rate",
        "change": "live",
        "when": ["shape", ["exp"]],
    }


class Broken(Decay):
    """Decay whose observation misses a series or gives two values for one time."""

    id = "broken"
    mode = "missing"

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, Any]:
        out = dict(super().observe(params, t, state))
        if self.mode == "missing":
            out.pop("k_used")
        else:
            out["k_used"] = np.array([1.0, 2.0])
        return out


def test_frame_scalars_read_the_observation_at_one_time() -> None:
    lesson = Decay()
    for family in (1, 3):
        params = lesson.resolve({"family": family, "k": 2.5})
        full = lesson.observation(params, [0.3], None)
        fast = lesson.frame_scalars(params, 0.3, None)
        assert list(fast) == list(full) == list(lesson.series_names(params))
        assert all(type(v) is float and v == full[k][0] for k, v in fast.items())
    assert set(lesson._series_names) == {1, 3}  # the names are kept per family size


@pytest.mark.parametrize("mode", ["missing", "shape"])
def test_frame_scalars_of_a_wrong_observation_say_what_differs(mode: str) -> None:
    lesson = Broken()
    lesson.mode = mode
    with pytest.raises((ObservationError, ValueError)):
        lesson.frame_scalars(lesson.resolve(), 0.3, None)


class DecayOne(Decay):
    """Decay with its observation at one time in plain numbers (in another order)."""

    id = "decay-one"
    wrong = False

    def observe_one(self, params: Params, t: float, state: Any) -> dict[str, float] | None:
        out = {f"x_{m + 1}" if m else "x": math.exp(-t) * (m + 1) for m in range(params["family"])}
        out["k_used"] = float(params["k"])
        if self.wrong:
            out["extra"] = 1.0
        return out if params["shape"] == "exp" else None


def test_frame_scalars_read_observe_one_where_the_lesson_has_it() -> None:
    lesson = DecayOne()
    for family in (1, 3):
        for shape in ("exp", "sqrt"):
            params = lesson.resolve({"family": family, "k": 2.5, "shape": shape})
            for t in (0.0, 0.3, 0.9):
                full = lesson.observation(params, [t], None)
                fast = lesson.frame_scalars(params, t, None)
                assert list(fast) == list(full) == list(lesson.series_names(params))
                for k, v in fast.items():
                    assert type(v) is float and v == pytest.approx(full[k][0], rel=1e-15)
    # an observation at one time that differs from the declared series: the full one says so
    params = lesson.resolve({"family": 2})
    with pytest.raises(ObservationError, match="undeclared \\['extra'\\]"):
        DecayOneBroken().frame_scalars(params, 0.3, None)


class DecayOneBroken(DecayOne):
    """observe_one and observe both with an undeclared series."""

    wrong = True

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, Any]:
        return {**super().observe(params, t, state), "extra": np.zeros(len(t))}


class DecayKeyed(Decay):
    """Decay whose series depend on the shape too (its series key says so)."""

    id = "decay-keyed"

    def series_for(self, params: Params) -> tuple[Series, ...]:
        out = super().series_for(params)
        return out if params["shape"] == "exp" else tuple(s for s in out if s.name != "k_used")

    def series_key(self, params: Params) -> Any:
        return super().series_key(params), params["shape"]

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, Any]:
        out = super().observe(params, t, state)
        if params["shape"] != "exp":
            out.pop("k_used")
        return out


def test_series_names_are_kept_per_series_key() -> None:
    lesson = DecayKeyed()
    for shape in ("exp", "sqrt", "exp"):
        params = lesson.resolve({"family": 2, "shape": shape})
        names = lesson.series_names(params)
        assert names == tuple(s.name for s in lesson.series_for(params))
        assert list(lesson.frame_scalars(params, 0.25, None)) == list(names)
    assert set(lesson._series_names) == {(2, "exp"), (2, "sqrt")}


class DecayCounted(Decay):
    """Decay that counts its preset look-ups and the steppers and scenes it builds."""

    id = "decay-counted"
    presets = (Preset("fast", "A fast decay", {"k": 5.0}, t_end=4.0),)

    def __init__(self) -> None:
        self.calls: dict[str, int] = {"preset": 0, "stepper": 0, "scene": 0, "notes": 0}

    def preset(self, name: str) -> Preset:
        self.calls["preset"] += 1
        return super().preset(name)

    def stepper(self, params: Params) -> Stepper:  # type: ignore[override]
        self.calls["stepper"] += 1
        return object()  # type: ignore[return-value]

    def scene(self, params: Params):  # type: ignore[override]
        self.calls["scene"] += 1
        return SceneSpec(bounds=((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)))

    def notes(self, params: Params) -> list[Note]:
        self.calls["notes"] += 1
        return [Note("info", f"k = {params['k']:g}")]


def test_open_looks_a_preset_up_once_and_builds_each_part_once_when_read() -> None:
    lesson = DecayCounted()
    setup = lesson.open({"family": 2}, "fast")
    assert lesson.calls == {"preset": 1, "stepper": 0, "scene": 0, "notes": 0}
    assert setup.lesson is lesson and setup.preset == "fast"
    assert setup.params == lesson.resolve({"family": 2}, "fast") and setup.params["k"] == 5.0
    assert setup.t_end == 4.0
    for _ in range(3):
        assert setup.stepper is setup.stepper and setup.scene is setup.scene
        assert setup.notes == (Note("info", "k = 5"),)
    assert lesson.calls == {"preset": 2, "stepper": 1, "scene": 1, "notes": 1}  # +1: resolve
    assert lesson.open().t_end == lesson.t_end and lesson.calls["preset"] == 2


def test_open_takes_its_scenes_where_it_is_told() -> None:
    lesson = DecayCounted()
    asked: list[tuple[Lesson, Params]] = []
    made = SceneSpec(bounds=((0.0, 0.0, 0.0), (2.0, 2.0, 2.0)))

    def shared(of: Lesson, params: Params) -> SceneSpec:
        asked.append((of, params))
        return made

    setup = lesson.open({"k": 2}, scene_of=shared)
    assert setup.scene is made and setup.scene is made
    assert asked == [(lesson, setup.params)] and lesson.calls["scene"] == 0


def test_open_refuses_as_resolve_does_and_builds_nothing() -> None:
    lesson = DecayCounted()
    with pytest.raises(ParamError, match="unknown preset 'slow'"):
        lesson.open(preset="slow")
    with pytest.raises(ParamError, match="k: 11 is above the maximum 10"):
        lesson.open({"k": 11}, "fast")
    with pytest.raises(ParamError, match="unknown parameter"):
        lesson.open({"q": 1})
    assert lesson.calls["stepper"] == lesson.calls["scene"] == 0
    setup = Decay().open()  # a lesson without a live run still opens ...
    with pytest.raises(NotImplementedError):
        setup.stepper  # ... and says so when its stepper is read


def _same_frame(a: Frame, b: Frame) -> bool:
    return (
        a.t == b.t
        and a.scalars.keys() == b.scalars.keys()
        and all(np.array_equal(a.scalars[k], b.scalars[k], equal_nan=True) for k in a.scalars)
        and a.points.keys() == b.points.keys()
        and all(np.array_equal(a.points[k], b.points[k], equal_nan=True) for k in a.points)
    )


@pytest.mark.parametrize("lesson_id", [lesson.id for lesson in all_lessons()])
def test_open_returns_what_the_four_calls_return(lesson_id: str) -> None:
    """For the defaults and every preset: the values of ``resolve``, the run's length of
    ``preset_t_end``, the start of ``stepper``, the drawing of ``scene`` and the ``notes``."""
    from analyzer_lab.session.runlog import scenes_equal

    lesson = get_lesson(lesson_id)
    for preset in (None, *(p.name for p in lesson.presets[:2])):
        setup = lesson.open(None, preset)
        params = lesson.resolve(None, preset)
        assert setup.params == params and setup.preset == preset
        assert setup.t_end == lesson.preset_t_end(preset)
        assert setup.notes == tuple(lesson.notes(params))
        assert type(setup.stepper) is type(lesson.stepper(params))
        assert _same_frame(setup.stepper.reset(), lesson.stepper(params).reset())
        assert scenes_equal(setup.scene, lesson.scene(params))
