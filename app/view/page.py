"""The generic view: one browser tab's GUI and scene, drawn from a lesson's declarations.

:class:`SessionView` renders a :class:`~analyzer_lab.session.session.Session` into one viser client
(``client.gui`` / ``client.scene``, private to that tab) from a few parts with one job
each: the lesson and preset pickers, transport and readout (here), the controls built
from the lesson's declared groups and modes (:mod:`analyzer_lab.view.controls`), the scene
(:mod:`analyzer_lab.view.scene`), the plots (:mod:`analyzer_lab.view.plots`), the derivation, export and
the state saved in the browser.  The live frames come from the server's loop through
:meth:`SessionView.tick`.

The classroom attaches through the public interface: :attr:`SessionView.gate` (refuse
an input), :attr:`SessionView.language_hooks` (relabel its folders after a switch of the
page's language), :meth:`show_session` (show another session, e.g. the instructor's demo),
:meth:`redraw`, :meth:`sync_widgets`, :meth:`after_state_change` and :meth:`guard`.

Cost per frame is kept small (DESIGN §5): one assignment for the moving points,
one for all vectors, the newest trail chunk every other frame, the readout and
one plot at a few Hz, all inside one ``client.atomic()`` (one wake-up of the
event loop).
"""

from __future__ import annotations

import contextlib
import html
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from analyzer_lab.i18n import ENGLISH, N_, Language, language_of, picker_languages
from analyzer_lab.lesson_texts import lesson_label
from analyzer_lab.lessons.kit.contract import Lesson, Param, ParamError
from analyzer_lab.lessons.kit.formula import Formula, plain_number
from analyzer_lab.session.session import LabError, Session
from analyzer_lab.view.controls import ParamControls
from analyzer_lab.view.export import ExportPanel
from analyzer_lab.view.extents import preset_extent
from analyzer_lab.view.math import derivation_to_html, prose_html
from analyzer_lab.view.persistence import save_state
from analyzer_lab.view.plots import PlotPanel
from analyzer_lab.view.readout import preset_note_html, readout_html, speed_label, status_html
from analyzer_lab.view.scene import SceneRenderer
from analyzer_lab.view.transport import MAX_DRAWN_FRAMES, Transport
from analyzer_lab.viser_boundary import fast_set, relabel_tabs, sent_value

if TYPE_CHECKING:
    import viser

log = logging.getLogger(__name__)

NO_PRESET = N_("(defaults)")
#: Labels of the page's lesson and preset pickers and of the pause-at-t_end checkbox.
LESSON_PICKER, PRESET_PICKER, PAUSE_AT_END = N_("Lesson"), N_("Preset"), N_("pause at t_end")
#: The label of the page's language picker (its options are each language's own name).
LANGUAGE_PICKER = N_("Language")
#: The tabs of the panel (English; each page shows them in its language).
TABS = (N_("Lesson"), N_("Controls"), N_("Plots"), N_("Export"))
#: Seconds a replaced GUI folder stays (hidden) before it is removed.  The page applies
#: the property updates of all the messages it read in one go after their removals, so a
#: hide and the removal read together (a page whose browser fell that far behind) would
#: update a component already gone: long enough for a busy browser.
RETIRE_DELAY = 5.0


#: The panel docked at the right edge (px): the canvas is what it leaves free, so the
#: scene is framed there (a tablet keeps 420 of its 820 px).  viser's widgets take 384 px
#: (``control_width="large"``); the rest is the panel's scroll bar.  Phones get viser's bottom
#: sheet instead (see :data:`analyzer_lab.viser_boundary.PHONE_LAYOUT`).
PANEL_WIDTH = 400


@dataclass
class ViewConfig:
    """Rates of the view (per session)."""

    fps: float = 36.0  # analyzer_lab.serve.server.DEFAULT_FPS
    trail_every: int = 2  # frames between trail uploads
    trail_chunk: int = 24  # points per trail chunk
    trail_max_points: int = 3000  # per moving point family member
    plot_send_every: int = 6  # frames between plot uploads (round-robin over plots)
    readout_every: int = 6  # frames between time readouts


def lesson_head_html(lesson: Lesson, language: Language) -> str:
    """The lesson's head: problem, title, source and summary in ``language``, escaped,
    with names written as the textbook writes them (φ, x with subscript A)."""
    text = language.lesson_text
    words = language.quantity
    problem, title = html.escape(text(lesson.problem)), prose_html(text(lesson.title), words)
    return (
        f'<div class="al-lesson-head" style="font-size:0.95em"><b>{problem} · {title}</b><br>'
        f'<span style="color:#555">{html.escape(text(lesson.source))}</span><br>'
        f"{prose_html(text(lesson.summary), words)}</div>"
    )


class SessionView:
    """One browser tab: its GUI, its scene, and the frames of its session."""

    def __init__(
        self,
        client: viser.ClientHandle,
        session: Session,
        config: ViewConfig | None = None,
        language: Language | None = None,
        language_chosen: bool = False,
    ) -> None:
        self.client = client
        self.session = session
        self.config = config or ViewConfig()
        #: the page's language (its chrome, notices and prose numbers)
        self.language = language or ENGLISH
        #: whether the language was chosen on the page (then kept with its saved state)
        self.language_chosen = language_chosen
        self.no_preset = self.language.gettext(NO_PRESET)
        self.closed = False
        self.frame_count = 0
        self.derivation_due: float | None = None
        self._drawn_lesson: str | None = None
        self._drawn_scene_rev = -1
        self._drawn_reset_rev = -1
        self._drawn_camera_rev = -1
        self._shown_notice: tuple[str, str] | None = None
        self._shown_frame_message = ""
        self._last_readout = ""
        self._retired: list[tuple[float, Any]] = []  # (when to remove, hidden GUI folder)
        self._current_target: Any = None  # the widget whose callback runs now
        self._lesson_folders: list[Any] = []
        self._frame_dirty = True
        self.following = False
        self.step_seconds = 0.0  # time spent in the lesson's stepper (frame loop)
        self.draw_seconds = 0.0  # time spent queueing the frame's updates
        self.renderer = SceneRenderer(client, self.config)
        self.renderer.text = self.language.lesson_text
        self.renderer.on_surface_click = self._on_surface_click
        self.plots = PlotPanel(client.gui)
        self._plots_folder: Any = None
        self.controls = ParamControls(
            client.gui,
            self.guard,
            self._on_slider,
            self._on_text,
            self._on_value,
            self._on_snap,
            self.language,
        )
        #: classroom hook: ``gate(view, event, retry)`` returning False refuses an input
        self.gate: Callable[[SessionView, Any, Callable[[Any], None] | None], bool] | None = None
        #: classroom hooks: called with the view after its language is switched
        self.language_hooks: list[Callable[[SessionView], None]] = []
        with session.lock:  # a callback of an early click waits until the page is built
            self._build_gui()

    # ------------------------------------------------------------------ public interface

    def guard(self, fn: Callable[..., None]) -> Callable[..., None]:
        """Wrap a GUI callback: ignore programmatic updates, serialize on the session
        lock, turn refusals into visible messages, never let an error escape."""

        def wrapped(event: Any) -> None:
            if self.closed or getattr(event, "client", None) is None:
                return
            if self.gate is not None and not self.gate(self, event, wrapped):
                return
            with self.session.lock:
                self._current_target = getattr(event, "target", None)
                try:
                    fn(event)
                except ParamError as exc:
                    field = self._field_of(exc)
                    if field is None or not self.controls.show_error(
                        field, self.language.message(exc)
                    ):
                        self.session.notify(self._refused(exc), "error")
                    self.sync_widgets()
                except LabError as exc:
                    self.session.notify(self._refused(exc), "error")
                    self.sync_widgets()
                except Exception as exc:  # a bug must not take the session down
                    log.exception(
                        "page %s: %s failed", self.client.client_id, getattr(fn, "__name__", fn)
                    )
                    self.session.notify(
                        self.language.gettext("internal error: {error}").format(
                            error=f"{type(exc).__name__}: {exc}"
                        ),
                        "error",
                    )
                    self.sync_widgets()
                finally:
                    self._current_target = None
                self.refresh(heavy=True)

        return wrapped

    def _refused(self, exc: Exception) -> str:
        """The notice of a refused input, in the page's language."""
        return self.language.gettext("refused: {reason}").format(reason=self.language.message(exc))

    def _field_of(self, exc: ParamError) -> str | None:
        """The field a refusal belongs to: the one being edited (a cross-field check
        names the other field in its message), else the one the error names."""
        for name, widgets in self.controls.widgets.items():
            if any(w is self._current_target for w in widgets):
                return name
        return exc.name if exc.name in self.controls.widgets else None

    def show_session(self, session: Session) -> None:
        """Show another session (e.g. the instructor's demo); caller holds both locks.
        The lesson's GUI is rebuilt only when the lesson differs: the widgets are
        re-synced instead (rebuilding plots while frames stream to them leaves updates
        for removed components in flight)."""
        self.session = session
        if self._drawn_lesson != session.lesson.id:
            self._drawn_lesson = None
        self._drawn_scene_rev = -1
        self._drawn_reset_rev = -1
        self._drawn_camera_rev = -1
        self._shown_notice = session.notice
        self.redraw()

    def redraw(self, scene: bool = False) -> None:
        """Bring everything in line with the session now (caller holds its lock);
        ``scene``: draw the static scene again too (e.g. larger labels)."""
        if scene:
            self._drawn_scene_rev = -1
        self.renderer.vectors_changed()
        self._frame_dirty = True
        self.refresh(heavy=True)
        self.sync_widgets(force=True)
        self.derivation_due = time.monotonic()

    def set_following(self, on: bool) -> None:
        """Show the persistent "following the instructor" banner and make every control
        read-only (or end both)."""
        self.following = on
        text = self.language.gettext(
            "Following the instructor: the controls are read-only until the demo ends."
        )
        self.banner.content = (
            '<div class="al-following-banner" style="background:#1c4f8a;color:#fff;padding:4px 8px;'
            f'border-radius:4px;font-weight:600">{html.escape(text)}</div>'
            if on
            else ""
        )
        self.banner.visible = on
        self.transport.visible = not on  # (viser's button groups cannot be disabled)
        for w in (self.lesson_dd, self.preset_dd, self.speed_dd):
            if w.disabled != on:
                w.disabled = on
        self.controls.set_read_only(on, self.session.params)

    def dock_panel(self, width: float = PANEL_WIDTH) -> None:
        """Dock the page's panel at the right edge, ``width`` px wide (a page that left
        meanwhile is passed over)."""
        gui = self.client.gui
        try:
            gui.main_panel.dock_right()
            gui.main_panel.set_width(width)
        except (RuntimeError, ValueError):
            log.debug("page %s: the panel was not docked", self.client.client_id, exc_info=True)

    def mark_dirty(self) -> None:
        """Draw the session's current frame at the next tick."""
        self._frame_dirty = True

    # ------------------------------------------------------------------ GUI

    def _build_gui(self) -> None:
        gui = self.client.gui
        tr = self.language.gettext
        gui.configure_theme(
            control_width="large",
            show_share_button=False,
            show_logo=False,
            brand_color=(40, 90, 160),
        )
        gui.set_panel_label("Analyzer Lab")
        self.dock_panel()
        s = self.session
        self.banner = gui.add_html("", visible=False)
        offered = picker_languages(self.language.code)
        self.language_dd = gui.add_dropdown(
            tr(LANGUAGE_PICKER),
            tuple(offered.values()),
            initial_value=offered[self.language.code],
        )
        self.language_dd.on_update(self.guard(self._on_language))
        self._label_lessons()
        self.lesson_dd = gui.add_dropdown(
            tr(LESSON_PICKER), tuple(self._labels), initial_value=self._ids[s.lesson.id]
        )
        self.lesson_dd.on_update(self.guard(self._on_lesson))
        self.preset_dd = gui.add_dropdown(
            tr(PRESET_PICKER), self._preset_options(), initial_value=s.preset or self.no_preset
        )
        self.preset_dd.on_update(self.guard(self._on_preset))
        self.preset_note = gui.add_html("")
        self.clock = Transport(gui, self.guard, lambda: self.session, self._played, self.language)
        self.transport, self.speed_dd = self.clock.buttons, self.clock.speed
        self.readout = gui.add_html(readout_html(self.session, self.language))
        self.status = gui.add_html(status_html(self.session, self.language))
        self.tabs = gui.add_tab_group()
        self.tab_lesson, self.tab_controls, self.tab_plots, self.tab_export = (
            self.tabs.add_tab(tr(name)) for name in TABS
        )
        with self.tab_lesson:
            self.lesson_head = gui.add_html("")
            self.derivation_html = gui.add_html("")
        with self.tab_export:
            self.exports = ExportPanel(
                gui, self.guard, lambda: self.session, self.client, self.language
            )
        with self.session.lock:
            self.refresh(heavy=True)

    def _label_lessons(self) -> None:
        """The lesson picker's labels in the page's language, mapped to lesson ids."""
        lessons = self.session.lessons.values()
        self._labels = {lesson_label(lesson, self.language): lesson.id for lesson in lessons}
        self._ids = {v: k for k, v in self._labels.items()}

    def _preset_options(self) -> tuple[str, ...]:
        return (self.no_preset, *(p.name for p in self.session.lesson.presets))

    def _build_lesson_gui(self) -> None:
        """(Re)build everything that depends on the lesson: controls, plots, header."""
        gui = self.client.gui
        tr = self.language.gettext
        # The old folders are hidden now and removed a little later: the page applies the
        # property updates of a batch of messages after the batch's removals, so a chart
        # update that is already on its way must still find its chart.
        self._retire(self._lesson_folders)
        lesson = self.session.lesson
        with self.tab_controls:
            self._lesson_folders = self.controls.build(lesson, self.session.params)
            vec_names = tuple(self.session.scene.moving_vectors)
            if vec_names:
                folder = gui.add_folder(tr("Vectors"))
                self._lesson_folders.append(folder)
                self.renderer.chosen_vectors = self.session.visible_vectors
                self.renderer.spec = self.session.scene
                visible = self.renderer.visible_vectors()
                with folder:
                    for name in vec_names:
                        cb = gui.add_checkbox(
                            tr("show {name}").format(name=name), initial_value=name in visible
                        )
                        cb.on_update(
                            self.guard(lambda e, n=name: self._on_vector_toggle(n, sent_value(e)))
                        )
            folder = gui.add_folder(tr("Playback"))
            self._lesson_folders.append(folder)
            with folder:
                self.pause_cb = gui.add_checkbox(
                    tr(PAUSE_AT_END), initial_value=self.session.pause_at_end
                )
                self.pause_cb.on_update(self.guard(self._on_pause_at_end))
        self._build_plots()
        self.exports.show_default_step(lesson, self.session.t_end)
        self.lesson_head.content = lesson_head_html(lesson, self.language)
        self._drawn_lesson = lesson.id

    def _retire(self, folders: list[Any]) -> None:
        """Hide ``folders`` now and remove them a little later (see
        :meth:`_build_lesson_gui`)."""
        due = time.monotonic() + RETIRE_DELAY
        for f in folders:
            try:
                f.visible = False
            except RuntimeError:  # already removed (the page is closing)
                log.debug("page %s: a folder was already removed", self.client.client_id)
            self._retired.append((due, f))

    def _build_plots(self) -> None:
        """(Re)build the charts for the session's lesson and values (the series a
        preset defines can differ from another's)."""
        s = self.session
        self.plots.charts = []
        if self._plots_folder is not None:
            self._retire([self._plots_folder])
        with self.tab_plots:
            self._plots_folder = self.plots.build(
                s.lesson, s.params, s.log, s.frame, s.preset, self.language
            )

    def sync_widgets(self, force: bool = False) -> None:
        """Show the session's values in the widgets (programmatic: callbacks ignore it).

        ``force``: every widget, also those whose session value did not change."""
        s = self.session
        put, current = self.controls.put, self._current_target
        try:
            put(self.lesson_dd, self._ids[s.lesson.id], force, current)
            opts = self._preset_options()
            if tuple(self.preset_dd.options) != opts:
                self.preset_dd.options = opts
                # new options: the page is sent the value again (viser moved its own copy to
                # the first option, and the page may still show the old lesson's choice)
                self.preset_dd.value = s.preset or self.no_preset
            put(self.preset_dd, s.preset or self.no_preset, force, current)
            put(self.speed_dd, speed_label(s.speed), force, current)
            if hasattr(self, "pause_cb"):
                put(self.pause_cb, bool(s.pause_at_end), force, current)
        except (RuntimeError, ValueError, KeyError):  # a removed widget, a refused value
            log.warning(
                "page %s: the pickers were not synced", self.client.client_id, exc_info=True
            )
        self.controls.sync(s.lesson, s.params, force, current)

    # ------------------------------------------------------------------ callbacks

    def _on_lesson(self, event: Any) -> None:
        tr = self.language.gettext
        lesson_id = self._labels.get(sent_value(event))
        if lesson_id is None:
            raise LabError(
                tr("unknown lesson {name}").format(name=repr(str(sent_value(event))[:60]))
            )
        if lesson_id == self.session.lesson.id:
            return
        self.session.select_lesson(lesson_id)
        label = lesson_label(self.session.lesson, self.language)
        self.session.notify(tr("lesson: {lesson}").format(lesson=label))
        self.after_state_change()

    def _on_language(self, event: Any) -> None:
        offered = picker_languages(self.language.code)
        code = next((c for c, name in offered.items() if name == sent_value(event)), None)
        if code is None:
            raise LabError(
                self.language.gettext("unknown language {name}").format(
                    name=repr(str(sent_value(event))[:30])
                )
            )
        if code != self.language.code:
            self.set_language(language_of(code))
        self.language_chosen = True
        self._save_state()

    def set_language(self, language: Language) -> None:
        """Show the page in ``language``: its chrome now, the lesson's controls rebuilt
        (caller holds the session lock)."""
        self.language = language
        tr = language.gettext
        self.no_preset = tr(NO_PRESET)
        pickers = (
            (self.language_dd, LANGUAGE_PICKER),
            (self.lesson_dd, LESSON_PICKER),
            (self.preset_dd, PRESET_PICKER),
        )
        for widget, label in pickers:
            if widget.label != tr(label):
                widget.label = tr(label)
        self._label_lessons()
        self.lesson_dd.options = tuple(self._labels)
        self.controls.language = language
        self.renderer.text = language.lesson_text
        self._drawn_scene_rev = -1  # the scene's labels drawn again in the new language
        self.clock.set_language(language)
        self.exports.set_language(language)
        relabel_tabs(self.tabs, [tr(name) for name in TABS])
        if self.following:
            self.set_following(True)
        self._drawn_lesson = None  # the controls, vectors and playback: rebuilt in it
        self._last_readout = ""
        self._shown_notice = None
        self.derivation_due = time.monotonic()  # its prose in the new language
        self.status.content = status_html(self.session, language)  # and the page's lang
        self.redraw()
        for hook in self.language_hooks:  # the classroom's folders
            hook(self)

    def _on_preset(self, event: Any) -> None:
        tr = self.language.gettext
        name = sent_value(event)
        if name == self.no_preset:
            self.session.apply_preset(None)
        else:
            chosen = next((p for p in self.session.lesson.presets if p.name == name), None)
            if chosen is None:
                raise LabError(tr("unknown preset {name}").format(name=repr(str(name)[:60])))
            self.session.apply_preset(name)
            title = self.language.lesson_text(chosen.title)
            self.session.notify(tr("preset {name}: {title}").format(name=name, title=title))
        self.after_state_change()

    def _played(self, frames: list[Any]) -> None:
        """Frames the transport made outside the loop (a step, a jump; none after a reset)."""
        s = self.session
        if frames:
            self.renderer.push_frames(frames[-MAX_DRAWN_FRAMES:], s.playing, self.frame_count)
        self._frame_dirty = True
        self._save_state()

    def _on_pause_at_end(self, event: Any) -> None:
        self.session.pause_at_end = bool(sent_value(event))
        self._save_state()

    def _on_vector_toggle(self, name: str, value: Any) -> None:
        visible = self.renderer.visible_vectors()
        if value:
            visible.add(name)
        else:
            visible.discard(name)
        self.session.visible_vectors = visible
        self.renderer.chosen_vectors = visible
        self.renderer.vectors_changed()
        self._frame_dirty = True
        self._save_state()

    def _on_slider(self, p: Param, value: Any) -> None:
        tr = self.language.gettext
        current = self.session.params.get(p.name)
        if isinstance(current, Formula) and not current.is_constant:
            raise ParamError(
                p.name,
                tr("is the formula {formula}; type a number to use the slider").format(
                    formula=current.text
                ),
            )
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParamError(
                p.name, tr("expected a number, got {kind}").format(kind=type(value).__name__)
            )
        v = float(value)
        if not math.isfinite(v):
            raise ParamError(
                p.name, tr("must be a finite number, got {value}").format(value=repr(v))
            )
        if v < float(p.min) or v > float(p.max):
            raise ParamError(
                p.name,
                tr("{value} is outside the slider range [{low}, {high}]").format(
                    value=plain_number(v), low=plain_number(p.min), high=plain_number(p.max)
                ),
            )
        v = float(f"{v:.12g}")  # slider round-off, kept in significant digits (1e-14 stays)
        self.session.set_value(p.name, repr(v) if not v.is_integer() else str(int(v)))
        self.controls.clear_error(p.name)
        self._param_changed()

    def _on_text(self, p: Param, value: Any) -> None:
        if not isinstance(value, str):
            raise ParamError(p.name, self.language.gettext("expected text"))
        self.session.set_value(p.name, self.language.read_decimal(value))
        self.controls.clear_error(p.name)
        self._param_changed()

    def _on_value(self, p: Param, value: Any) -> None:
        self.session.set_value(p.name, value)
        self.controls.clear_error(p.name)
        self._param_changed()

    def _on_snap(self, event: Any) -> None:
        pt = self.session.snap_start()
        if pt is not None:
            self.session.notify(
                self.language.gettext("start point snapped to the surface: ({point})").format(
                    point=self._point(pt, ".6g")
                )
            )
        self._param_changed()

    def _on_surface_click(self, event: Any) -> None:
        if self.closed:
            return
        if self.gate is not None and not self.gate(self, event, None):  # classroom hook
            return
        with self.session.lock:
            try:
                hit = self.renderer.hit(event.ray_origin, event.ray_direction)
                tr = self.language.gettext
                if hit is None:
                    raise LabError(tr("the click did not hit the surface"))
                self.session.set_start(hit)
                self.session.notify(
                    tr("start point set by click: ({point})").format(point=self._point(hit, ".4g"))
                )
                self._param_changed()
            except (ParamError, LabError) as exc:
                self.session.notify(self._refused(exc), "error")
            except Exception as exc:  # a bug must not take the session down
                log.exception("page %s: a click on the scene failed", self.client.client_id)
                self.session.notify(
                    self.language.gettext("internal error: {error}").format(error=exc), "error"
                )
            self.refresh(heavy=True)

    def _point(self, point: Any, spec: str) -> str:
        """A point's coordinates as the language writes them (``;`` between them where the
        comma is the decimal sign)."""
        sep = "; " if self.language.decimal == "," else ", "
        return sep.join(self.language.number(float(v), spec) for v in point)

    def _param_changed(self) -> None:
        self.sync_widgets()
        self._frame_dirty = True
        self.derivation_due = time.monotonic() + 0.4
        self._save_state()

    def after_state_change(self) -> None:
        self.sync_widgets()
        self._frame_dirty = True
        self.derivation_due = time.monotonic()
        self._save_state()

    def _save_state(self) -> None:
        save_state(self.client, self.session, self.language.code if self.language_chosen else None)

    # ------------------------------------------------------------------ per frame

    def refresh(self, heavy: bool = False) -> None:
        """Bring GUI and scene in line with the session (caller holds the session lock).

        ``heavy``: also rebuild lesson-dependent GUI (from GUI callbacks, not the loop).
        """
        s = self.session
        if self.closed:
            return
        if heavy and self._drawn_lesson != s.lesson.id:
            self._build_lesson_gui()
            self.sync_widgets()
            self.derivation_due = time.monotonic()
            new_lesson = True
        else:
            new_lesson = False
        camera_due = self._drawn_camera_rev != s.camera_revision
        if new_lesson or camera_due:
            known = not s.edits()  # a preset's (or the defaults') run: its box is known
            self.renderer.run_box = preset_extent(s.lesson.id, s.preset) if known else None
        if self._drawn_scene_rev != s.scene_revision:
            self.renderer.chosen_vectors = s.visible_vectors
            frame = new_lesson or camera_due
            self.renderer.draw_static(s.scene, frame_camera=frame)
            self._drawn_camera_rev = s.camera_revision
            self._drawn_scene_rev = s.scene_revision
            self._frame_dirty = True
        if self._drawn_camera_rev != s.camera_revision:
            self.renderer.frame_scene()
            self._drawn_camera_rev = s.camera_revision
        if self._drawn_reset_rev != s.reset_revision:
            self.renderer.reset_live()
            self._drawn_reset_rev = s.reset_revision
            self._frame_dirty = True
        if (
            heavy
            and not new_lesson
            and self.plots.layout != self.plots.layout_for(s.lesson, s.params, s.frame)
        ):
            self._build_plots()
        if heavy:
            self.plots.show_preset(s.preset)
            content = preset_note_html(s, self.language)
            if self.preset_note.content != content:
                self.preset_note.content = content
        if self._frame_dirty:
            self._frame_dirty = False
            self.renderer.push_frames([s.frame], s.playing, self.frame_count)
            self.plots.send(s.log, all_plots=True)
        self._update_texts()

    def render_derivation(self) -> None:
        """The derivation with the current parameters, as MathML (caller holds the lock;
        the server renders it off the lock and calls :meth:`set_derivation`)."""
        s = self.session
        self.derivation_due = None
        try:
            steps = s.lesson.derivation(s.params)
            content = derivation_to_html(
                steps, text=self.language.lesson_text, tr=self.language.gettext
            )
        except Exception as exc:  # any formula: the page says why
            log.warning(
                "page %s: the derivation of %s failed",
                self.client.client_id,
                s.lesson.id,
                exc_info=True,
            )
            message = self.language.gettext("The derivation could not be built: {error}")
            content = f'<div class="al-error">{html.escape(message.format(error=exc))}</div>'

        self.set_derivation(content)

    def set_derivation(self, content: str) -> None:
        if self.derivation_html.content != content:
            self.derivation_html.content = content

    def _update_texts(self) -> None:
        ro = readout_html(self.session, self.language)
        if ro != self._last_readout:
            fast_set(self.readout, "content", ro)
            self._last_readout = ro
        notice = self.session.notice
        fmsg = self.session.frame.message
        if notice != self._shown_notice or fmsg != self._shown_frame_message:
            if (
                notice is not None
                and notice != self._shown_notice
                and notice[0] in ("warning", "error")
            ):
                try:
                    self.client.add_notification(
                        "Analyzer Lab",
                        self.language.notice(notice[1]),
                        auto_close_seconds=6.0,
                        color="red" if notice[0] == "error" else "yellow",
                    )
                except RuntimeError:  # the page is closing
                    log.debug("page %s: notification not shown", self.client.client_id)
            self._shown_notice = notice
            self._shown_frame_message = fmsg
            self.status.content = status_html(self.session, self.language)

    def tick(self, wall_dt: float, atomic: bool = True) -> None:
        """One frame of the server loop (caller holds the session lock).

        ``atomic=False``: the caller groups the messages (and wakes the event loop once
        for all sessions, see :class:`analyzer_lab.serve.server.LabServer`)."""
        if self.closed:
            return
        if self._retired and time.monotonic() >= self._retired[0][0]:
            self._remove_retired()
        s = self.session
        if self.frame_count % self.config.readout_every == 0:
            if not self.renderer.follow_canvas():  # the canvas changed shape: frame it again
                self.renderer.confirm_framing()  # the page's camera took the last framing
        was_playing = s.playing
        t0 = time.perf_counter()
        frames = s.tick(wall_dt) if s.playing else []
        self.step_seconds += time.perf_counter() - t0
        self.frame_count += 1
        cfg = self.config
        if (
            not frames
            and not self._frame_dirty
            and s.scene_revision == self._drawn_scene_rev
            and s.reset_revision == self._drawn_reset_rev
            and s.camera_revision == self._drawn_camera_rev
            and not (self.frame_count % cfg.plot_send_every == 0 and self.plots.behind(s.log))
        ):
            if was_playing != s.playing or self.frame_count % cfg.readout_every == 0:
                self._update_texts()
            return
        t1 = time.perf_counter()
        with self.client.atomic() if atomic else contextlib.nullcontext():
            if (
                s.scene_revision != self._drawn_scene_rev
                or s.reset_revision != self._drawn_reset_rev
                or s.camera_revision != self._drawn_camera_rev
                or self._frame_dirty
            ):
                self.refresh()
            if frames:
                self.renderer.push_frames(frames, s.playing, self.frame_count)
                if self.frame_count % cfg.plot_send_every == 0 or not s.playing:
                    self.plots.send(s.log, all_plots=not s.playing)
            elif self.frame_count % cfg.plot_send_every == 0:
                # what came in while the charts were fresh (a step just after a preset)
                self.plots.send(s.log, all_plots=True)
            if self.frame_count % cfg.readout_every == 0 or not s.playing:
                self._update_texts()
        self.draw_seconds += time.perf_counter() - t1

    def _remove_retired(self) -> None:
        """Remove the hidden folders whose delay has passed."""
        now = time.monotonic()
        while self._retired and now >= self._retired[0][0]:
            _, folder = self._retired.pop(0)
            try:
                folder.remove()
            except RuntimeError:  # the page is closing
                log.debug("page %s: a folder was not removed", self.client.client_id)

    def close(self) -> None:
        self.closed = True
        self._retired = []

    # ------------------------------------------------------------------ export


__all__ = ["SessionView", "ViewConfig"]
