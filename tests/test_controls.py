"""The controls part on its own: widgets built from a lesson's declarations (a real
viser server's GUI API, no browser)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from analyzer_lab.lessons.catalog import get_lesson
from analyzer_lab.view.controls import ParamControls


@pytest.fixture(scope="module")
def gui() -> Iterator[Any]:
    import viser

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    yield server.gui
    server.stop()


def _controls(gui: Any) -> ParamControls:
    def guard(fn: Any) -> Any:
        return fn

    def noop(*args: Any) -> None:
        return None

    return ParamControls(gui, guard, noop, noop, noop, noop)


def test_folders_follow_the_declared_modes_groups_and_titles(gui: Any) -> None:
    lesson = get_lesson("self-study-1")
    params = lesson.resolve(preset="C1.4-ab")
    c = _controls(gui)
    folders = c.build(lesson, params)
    labels = [f.label for f in folders]
    assert labels[0] == "Mode"  # the lesson's mode selectors first
    declared = [g.title for g in lesson.groups if g.name != "mode"]
    shown = [f.label for f in folders[1:]]
    assert shown == [t for t in declared if t in shown]  # the declared order
    assert {p.name for p in lesson.params} == set(c.widgets)
    # only the selected task's group is shown
    visible = {name for name, (_, folder) in c.folders.items() if folder.visible}
    assert "c1_4" in visible and "c1_5" not in visible and "c1_1" not in visible
    other = lesson.resolve(preset="C1.5b-cone")
    c.sync(lesson, other, force=True)
    visible = {name for name, (_, folder) in c.folders.items() if folder.visible}
    assert "c1_5" in visible and "c1_4" not in visible


def _shown(c: ParamControls) -> set[str]:
    return {name for name, widgets in c.widgets.items() if all(w.visible for w in widgets)}


def test_only_the_fields_of_the_chosen_mode_are_shown(gui: Any) -> None:
    lesson = get_lesson("self-study-1")
    c = _controls(gui)
    c.build(lesson, lesson.resolve(preset="C1.5b-cone"))
    assert {"a", "b", "c"} <= _shown(c) and "p" not in _shown(c)  # the cone has no p
    c.sync(lesson, lesson.resolve(preset="C1.5c-paraboloid"), force=True)
    assert {"a", "b", "p"} <= _shown(c) and "c" not in _shown(c)

    quadric = get_lesson("quadric")
    c = _controls(gui)
    c.build(quadric, quadric.resolve(preset="sphere"))
    assert "R" in _shown(c) and not {"a", "b", "c"} & _shown(c)
    assert not c.folders["coefficients"][1].visible
    c.sync(quadric, quadric.resolve(preset="coefficients"), force=True)
    group, folder = c.folders["coefficients"]
    assert folder.visible and group.expanded  # open when it is the surface's only description
    assert not c.folders["shape"][1].visible
    c.sync(quadric, quadric.resolve(preset="elliptic-cone"), force=True)
    assert {"a", "b", "c"} <= _shown(c) and "R" not in _shown(c)

    positioner = get_lesson("linear-positioner")
    c = _controls(gui)
    c.build(positioner, positioner.resolve(preset="forward-harmonic"))
    assert not c.folders["program"][1].visible and "F_dv" in _shown(c)
    c.sync(positioner, positioner.resolve(preset="inverse-cosine-move"), force=True)
    assert c.folders["program"][1].visible and "F_dv" not in _shown(c)  # found, not given
    assert "R_sopr" in _shown(c)  # given in both problems


def test_a_formula_of_t_turns_its_slider_off(gui: Any) -> None:
    lesson = get_lesson("circle")
    name = next(p.name for p in lesson.params if p.kind == "formula" and p.min is not None)
    c = _controls(gui)
    c.build(lesson, lesson.resolve({name: "t"}))
    slider = c.widgets[name][0]
    assert slider.disabled  # never stands for a formula of t
    c.sync(lesson, lesson.resolve({name: "2"}), force=True)
    assert not slider.disabled and slider.value == 2.0


def test_a_refused_entry_keeps_its_text_and_shows_its_message(gui: Any) -> None:
    lesson = get_lesson("circle")
    params = lesson.resolve()
    name = next(p.name for p in lesson.params if p.kind == "formula")
    c = _controls(gui)
    c.build(lesson, params)
    text = c.widgets[name][-1]
    text.value = "sin("
    assert c.show_error(name, f"{name}: the formula does not parse")
    c.sync(lesson, params, force=True)
    assert text.value == "sin(" and name in c.failing()
    c.clear_error(name)
    c.sync(lesson, params, force=True)
    assert text.value != "sin(" and not c.failing()


def test_read_only_while_following(gui: Any) -> None:
    lesson = get_lesson("circle")
    params = lesson.resolve()
    c = _controls(gui)
    c.build(lesson, params)
    c.set_read_only(True, params)
    assert all(w.disabled for ws in c.widgets.values() for w in ws)
    c.set_read_only(False, params)
    assert not all(w.disabled for ws in c.widgets.values() for w in ws)


def test_labels_write_units_as_the_textbook_does(gui: Any) -> None:
    """A length of the analyzer lessons has no unit (R = 1): the speed field reads
    ``V(t) =``, not ``V(t) [units/s] =``; a real unit stays in the label."""
    lesson = get_lesson("sphere-constant-speed")
    c = _controls(gui)
    c.build(lesson, lesson.resolve())
    assert [w.label for w in c.widgets["V"]] == ["V", "V(t) ="]
    every = [w.label for ws in c.widgets.values() for w in ws if hasattr(w, "label")]
    assert not [label for label in every if "units" in label]
    positioner = get_lesson("linear-positioner")
    c2 = _controls(gui)
    c2.build(positioner, positioner.resolve())
    with_units = [w.label for ws in c2.widgets.values() for w in ws if "[" in str(w.label)]
    assert with_units and all(label.rstrip(" =").endswith("]") for label in with_units)


def test_a_russian_page_shows_the_lessons_group_titles_labels_and_hints_in_russian(
    gui: Any,
) -> None:
    from analyzer_lab.i18n import resolve

    def guard(fn: Any) -> Any:
        return fn

    def noop(*args: Any) -> None:
        return None

    lesson = get_lesson("sphere")
    ru = ParamControls(gui, guard, noop, noop, noop, noop, resolve("ru")[0])
    folders = [f.label for f in ru.build(lesson, lesson.resolve())]
    assert folders == [
        "Сфера",
        "Управления u1(t), u2(t), u3(t)",
        "Начальная точка и семейство кривых",
        "Интегратор",
    ]
    labels = {name: [w.label for w in widgets] for name, widgets in ru.widgets.items()}
    assert labels["R"] == ["радиус сферы R"]
    assert labels["family"] == ["кривых в семействе"]
    assert labels["u1"][-1] == "u1(t) ="  # a symbol stays as written
    hints = {name: widgets[-1].hint for name, widgets in ru.widgets.items()}
    assert hints["u1"] == "управление u1: число или формула от t"
    assert hints["family"] == "несколько начальных точек сразу (рис. 1.12, 1.26)"
    # the English page shows the lesson as written
    en = _controls(gui)
    assert [f.label for f in en.build(lesson, lesson.resolve())][0] == "Sphere"
    assert [w.label for w in en.widgets["R"]] == ["sphere radius R"]
