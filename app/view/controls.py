"""The controls: a lesson's parameters as widgets, built from its declarations.

The lesson's mode selectors come first, then its parameter groups in the declared
order with their titles; a lesson with a start point gets "Snap to surface" in the
group that holds it.  :meth:`ParamControls.sync` shows the session's values without
overwriting a value the user has just typed elsewhere, and only the groups and fields
that apply to the current mode (a group's or a parameter's ``when``).
"""

from __future__ import annotations

import html
import logging
import math
from collections.abc import Callable
from typing import Any

from analyzer_lab.i18n import ENGLISH, Language
from analyzer_lab.lessons.kit.contract import Lesson, Param, Params
from analyzer_lab.lessons.kit.formula import Formula
from analyzer_lab.view.notation import unit_text
from analyzer_lab.viser_boundary import sent_value

_UNSHOWN = object()
Handler = Callable[[Any], None]

log = logging.getLogger(__name__)


def is_constant(value: Any) -> bool:
    """A number, or a formula without t."""
    return not isinstance(value, Formula) or value.is_constant


def slider_value(value: Any, p: Param) -> float:
    """Slider position for a formula value: its constant, else the range's midpoint."""
    lo, hi = float(p.min), float(p.max)
    v = math.nan
    if isinstance(value, Formula):
        if value.is_constant:
            try:
                v = float(value.value(0.0))
            except (ArithmeticError, ValueError, TypeError):
                v = math.nan
    else:
        v = float(value)
    if not math.isfinite(v):
        v = min(max(0.0, lo), hi)
    return min(max(v, lo), hi)


def number_text(value: Any) -> str:
    """A number as a text field shows it (shortest exact form)."""
    v = float(value)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def shown_value(p: Param, value: Any) -> Any:
    """The value as a widget of ``p`` shows it (text for formulas and decimals)."""
    if p.kind == "formula":
        return value.text if isinstance(value, Formula) else str(value)
    if p.kind == "float":
        return number_text(value)
    if p.kind == "bool":
        return bool(value)
    if p.kind == "choice":
        return str(value)
    return int(value) if p.kind == "int" else float(value)


class ParamControls:
    """The widgets of one lesson's parameters in one page.

    ``guard`` wraps every callback (the view's lock and refusal handling);
    ``on_slider``, ``on_text`` and ``on_value`` get ``(param, value)``; ``on_snap`` the
    click event of "Snap to surface".
    """

    def __init__(
        self,
        gui: Any,
        guard: Callable[[Handler], Handler],
        on_slider: Callable[[Param, Any], None],
        on_text: Callable[[Param, Any], None],
        on_value: Callable[[Param, Any], None],
        on_snap: Handler,
        language: Language = ENGLISH,
    ) -> None:
        self.gui = gui
        self.language = language
        self.guard = guard
        self.on_slider = on_slider
        self.on_text = on_text
        self.on_value = on_value
        self.on_snap = on_snap
        self.widgets: dict[str, list[Any]] = {}
        self.errors: dict[str, Any] = {}  # param name -> its (hidden) error line
        self.read_only = False  # while following the instructor
        self.locked: frozenset[str] = frozenset()  # fields an open assignment locks
        self.folders: dict[str, tuple[Any, Any]] = {}  # group name -> (group, folder)
        self._shown: dict[int, Any] = {}  # widget id -> the session value it last showed

    def build(self, lesson: Lesson, params: Params) -> list[Any]:
        """Create the folders and widgets (inside the caller's tab); returns the folders."""
        self.widgets = {}
        self.errors = {}
        self.folders = {}
        self._shown = {}
        folders: list[Any] = []
        gui = self.gui
        tr = self.language.gettext
        if lesson.modes:
            folder = gui.add_folder(tr("Mode"))
            folders.append(folder)
            with folder:
                for name in lesson.modes:
                    self._add(lesson.param(name), params)
        grouped: dict[str, list[Param]] = {}
        for p in lesson.params:
            if p.name not in lesson.modes:
                grouped.setdefault(p.group, []).append(p)
        for group in lesson.groups:
            members = grouped.get(group.name, [])
            if not members:
                continue
            folder = gui.add_folder(
                self.language.lesson_text(group.title),
                expand_by_default=group.expanded,
                visible=group.applies(params),
            )
            folders.append(folder)
            self.folders[group.name] = (group, folder)
            with folder:
                for p in members:
                    self._add(p, params)
                if lesson.start_point is not None and lesson.start_point[0] in {
                    p.name for p in members
                }:
                    gui.add_button(tr("Snap to surface")).on_click(self.guard(self.on_snap))
                    hint = html.escape(tr("Click the surface to set the start point."))
                    gui.add_html(f'<div style="font-size:max(11px,0.8em);color:#555">{hint}</div>')
        return folders

    def _add(self, p: Param, params: Params) -> None:
        gui = self.gui
        label = self.language.lesson_text(p.label) or p.name
        unit = unit_text(p.unit)
        if unit:
            label = f"{label} [{self.language.unit(unit)}]"
        value = params[p.name]
        hint = self.language.lesson_text(p.help) or None
        widgets: list[Any] = []
        if p.kind == "formula":
            if p.min is not None and p.max is not None:
                step = p.step or (p.max - p.min) / 200.0
                slider = gui.add_slider(
                    p.name,
                    min=float(p.min),
                    max=float(p.max),
                    step=float(step),
                    initial_value=slider_value(value, p),
                    hint=hint,
                    disabled=self.read_only or not is_constant(value),
                )
                slider.on_update(self.guard(lambda e, p=p: self.on_slider(p, sent_value(e))))
                widgets.append(slider)
            text = gui.add_text(f"{label} =", initial_value=shown_value(p, value), hint=hint)
            text.on_update(self.guard(lambda e, p=p: self.on_text(p, sent_value(e))))
            widgets.append(text)
        elif p.kind == "choice":
            w = gui.add_dropdown(label, tuple(p.choices), initial_value=str(value), hint=hint)
            widgets.append(w)
        elif p.kind == "bool":
            widgets.append(gui.add_checkbox(label, initial_value=bool(value), hint=hint))
        elif p.kind == "int" and p.min is not None and p.max is not None and p.max - p.min <= 100:
            widgets.append(
                gui.add_slider(
                    label,
                    min=int(p.min),
                    max=int(p.max),
                    step=1,
                    initial_value=int(value),
                    hint=hint,
                )
            )
        else:
            # typed text (a number or a constant expression such as pi/2): a bad entry
            # stays visible next to its message instead of being blanked by the browser
            text = gui.add_text(label, initial_value=number_text(value), hint=hint)
            text.on_update(self.guard(lambda e, p=p: self.on_text(p, sent_value(e))))
            widgets.append(text)
        for w in widgets:
            if (self.read_only or p.name in self.locked) and not w.disabled:
                w.disabled = True
            if not p.applies(params):  # e.g. the paraboloid's p while the cone is chosen
                w.visible = False
        if p.kind in ("choice", "bool", "int"):
            widgets[0].on_update(self.guard(lambda e, p=p: self.on_value(p, sent_value(e))))
        if any(isinstance(w.value, str) for w in widgets):
            self.errors[p.name] = gui.add_html("", visible=False)
        self.widgets[p.name] = widgets

    def set_read_only(self, on: bool, params: Params | None = None) -> None:
        """Disable every field (following the instructor) or enable them again (a
        formula's slider stays off while its value is a formula of t)."""
        self.read_only = on
        for name, widgets in self.widgets.items():
            for w in widgets:
                off = on or name in self.locked
                is_slider = hasattr(w, "min") and not hasattr(w, "multiline")
                if not off and params is not None and is_slider and name in params:
                    off = not is_constant(params[name])
                if w.disabled != off:
                    w.disabled = off

    def set_locked(self, names: frozenset[str], params: Params | None = None) -> None:
        """Make the fields ``names`` read-only (an open assignment's locked values)."""
        self.locked = frozenset(names)
        self.set_read_only(self.read_only, params)

    def show_error(self, name: str, message: str) -> bool:
        """Show ``message`` under the field ``name``; False if it has no error line."""
        line = self.errors.get(name)
        if line is None:
            return False
        line.content = (
            '<div class="al-field-error" style="color:#a61b1b;font-size:max(11px,0.85em)">'
            f"{html.escape(message)}</div>"
        )
        line.visible = True
        return True

    def clear_error(self, name: str) -> None:
        line = self.errors.get(name)
        if line is not None and line.visible:
            line.visible = False
            line.content = ""

    def failing(self) -> set[str]:
        """The fields that show an error now (their typed text is kept)."""
        return {n for n, line in self.errors.items() if line.visible}

    def put(self, widget: Any, value: Any, force: bool, current: Any = None) -> None:
        """Show ``value`` in ``widget`` when the session's value changed since this page
        last showed it (or when forced, or when it is the widget being handled): a value
        the user has just set in another widget, whose callback has not run yet, is not
        overwritten with the session's old value."""
        key = id(widget)
        if force or widget is current or self._shown.get(key, _UNSHOWN) != value:
            if widget.value != value:
                widget.value = value
        self._shown[key] = value

    def sync(self, lesson: Lesson, params: Params, force: bool, current: Any = None) -> None:
        """Show the session's values in the widgets (programmatic: callbacks ignore it).
        A field that shows an error keeps the text the student typed."""
        failing = self.failing()
        for group, folder in self.folders.values():
            shown = group.applies(params)  # e.g. only the selected task's parameters
            if folder.visible != shown:
                folder.visible = shown
        for name, widgets in self.widgets.items():
            if name not in params:
                continue
            p = lesson.param(name)
            applies = p.applies(params)
            for w in widgets:
                if w.visible != applies:
                    w.visible = applies
            if name in failing:
                continue
            value = params[name]
            for w in widgets:
                try:
                    is_slider = hasattr(w, "min") and not hasattr(w, "multiline")
                    if p.kind == "formula" and is_slider:
                        # a slider never stands for a formula of t: off until a number
                        off = self.read_only or name in self.locked or not is_constant(value)
                        if w.disabled != off:
                            w.disabled = off
                        constant = is_constant(value)
                        if constant:
                            self.put(w, slider_value(value, p), force, current)
                    else:
                        self.put(w, shown_value(p, value), force, current)
                except Exception:
                    log.exception("the widget of %s could not show %r", p.name, value)


__all__ = ["ParamControls", "shown_value", "slider_value"]
