"""The instructor's side of the classroom: presenter mode and the instructor panel.

Both live in the instructor page's own ``client.gui`` (private to that page) and know
the classroom as a :class:`~analyzer_lab.classroom.ports.RoomForPanels`.
"""

from __future__ import annotations

import html
import logging
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from analyzer_lab.classroom.link import ClassLink
from analyzer_lab.classroom.ports import RoomForPanels
from analyzer_lab.i18n import N_
from analyzer_lab.lessons.kit.message import Message
from analyzer_lab.session.session import LabError

if TYPE_CHECKING:
    from analyzer_lab.view.page import SessionView

log = logging.getLogger(__name__)


#: Presenter mode: the panel's width (px; the scene keeps >= 60 % of a 1280 px
#: projector) and the size of the scene's labels.
PANEL_WIDTH = 440
LABEL_SCALE = 1.8
#: What docking or floating the page's panel can raise (the page left, or its panel
#: cannot be placed so): presenter mode goes on with the panel where it is.
PANEL_ERRORS = (RuntimeError, ValueError)


#: The presenter's entries in the command palette: label, hotkey, step.
COMMANDS = (
    (N_("Next bookmark"), "pagedown", 1),
    (N_("Previous bookmark"), "pageup", -1),
    (N_("Next bookmark (N)"), "N", 1),
    (N_("Previous bookmark (P)"), "P", -1),
)
COMMAND_HINT = N_("presenter mode: step through the lesson's presets")
NO_PRESETS = N_("(this lesson has no presets)")


def _keys_html(keys: str) -> str:
    """The presenter's keys, as the folder shows them."""
    return f'<div style="font-size:max(11px,0.8em);color:#555">{html.escape(keys)}</div>'


class Presenter:
    """Presenter mode of one page: large fonts, docked (collapsible) panel, the
    lesson's presets as bookmarks stepped with "◀ Previous" / "Next ▶" and with the
    PageUp/PageDown keys (a presentation clicker) or P/N (viser commands with
    hotkeys; viser ignores them while a text field has focus)."""

    CSS = (
        "<style>html{font-size:135%!important}:root{--mantine-scale:1.3}"
        ".al-readout{font-size:1.0em!important}</style>"
    )

    def __init__(self, room: RoomForPanels, view: SessionView) -> None:
        self.room = room
        self.view = view
        gui = view.client.gui
        tr = view.language.gettext
        self.folder = gui.add_folder(tr("Presenter"), expand_by_default=False)
        with self.folder:
            self.toggle = gui.add_checkbox(
                tr("Presenter mode"),
                initial_value=False,
                hint=tr("large fonts for a projector; presets become bookmarks"),
            )
            self.class_table = gui.add_checkbox(
                tr("Show the class table"),
                initial_value=False,
                hint=tr("while presenting: the students' names and results on the projected panel"),
            )
            self.bookmarks = gui.add_html("")
            keys = tr(
                "Keys: PageDown / N = next, PageUp / P = previous (also in the command palette)."
            )
            self.keys = gui.add_html(_keys_html(keys))
        self.style = gui.add_html("")
        # projected: Previous/Next above everything (the readout moves up beside them)
        self.top_prev = gui.add_button("◀ " + tr("Previous"), order=-3000.0, visible=False)
        self.top_next = gui.add_button(tr("Next") + " ▶", order=-2999.0, visible=False)
        self.top_prev.on_click(view.guard(lambda e: self.step(-1)))
        self.top_next.on_click(view.guard(lambda e: self.step(+1)))
        self._readout_order = view.readout.order
        self.commands: list[Any] = []
        self.toggle.on_update(view.guard(self._on_toggle))
        self.class_table.on_update(view.guard(self._on_class_table))
        self.on = False
        self.update_bookmarks()

    def relabel(self) -> None:
        """The folder in the page's language now (after a switch of it)."""
        tr = self.view.language.gettext
        self.folder.label = tr("Presenter")
        self.toggle.label = tr("Presenter mode")
        self.toggle.hint = tr("large fonts for a projector; presets become bookmarks")
        self.class_table.label = tr("Show the class table")
        self.class_table.hint = tr(
            "while presenting: the students' names and results on the projected panel"
        )
        self.keys.content = _keys_html(
            tr("Keys: PageDown / N = next, PageUp / P = previous (also in the command palette).")
        )
        self.top_prev.label = "◀ " + tr("Previous")
        self.top_next.label = tr("Next") + " ▶"
        if self.on:  # the palette's entries are made again under their new labels
            self._set_commands(True)
        self.update_bookmarks()

    def _on_toggle(self, event: Any) -> None:
        if getattr(event, "client", None) is None:
            return
        self.set_mode(bool(self.toggle.value))

    @property
    def show_class(self) -> bool:
        """The instructor asked for the class's table on the projected panel."""
        return bool(self.class_table.value)

    def _on_class_table(self, event: Any) -> None:
        if getattr(event, "client", None) is None:
            return
        if self.on:
            self.room.project(self.view, True, self.show_class)

    def _set_commands(self, on: bool) -> None:
        """The presenter's entries of the command palette, in the page's language (none
        when ``on`` is False)."""
        gui = self.view.client.gui
        tr = self.view.language.gettext
        for c in self.commands:
            try:
                c.remove()
            except RuntimeError:  # the page left meanwhile
                pass
        self.commands = []
        if not on:
            return
        for label, key, step in COMMANDS:
            cmd = gui.add_command(tr(label), hotkey=key, description=tr(COMMAND_HINT))
            cmd.on_trigger(self.view.guard(lambda e, s=step: self.step(s)))
            self.commands.append(cmd)

    def set_mode(self, on: bool) -> None:
        gui = self.view.client.gui
        self.on = on
        self.style.content = self.CSS if on else ""
        self._set_commands(on)
        if on:
            try:
                gui.main_panel.dock_right()
                gui.main_panel.set_width(PANEL_WIDTH)
            except PANEL_ERRORS:
                pass
            self.folder.expand_by_default = True
        else:
            self.view.dock_panel()
        self.top_prev.visible = on
        self.top_next.visible = on
        self.view.readout.order = -2998.0 if on else self._readout_order
        self.room.project(self.view, on, self.show_class)
        self.view.renderer.label_scale = LABEL_SCALE if on else 1.0
        self.view.redraw(scene=True)
        self.update_bookmarks()

    def step(self, direction: int) -> None:
        """Next/previous preset of the page's lesson (caller holds the session lock)."""
        s = self.view.session
        names = [p.name for p in s.lesson.presets]
        if not names:
            raise LabError(Message(N_("this lesson has no presets to step through")))
        k = names.index(s.preset) if s.preset in names else (-1 if direction > 0 else len(names))
        k = min(max(k + direction, 0), len(names) - 1)
        if names[k] != s.preset:
            s.apply_preset(names[k])
            s.notify(
                Message(
                    N_("bookmark {number}/{count}: {name}"),
                    number=k + 1,
                    count=len(names),
                    name=names[k],
                )
            )
            self.view.after_state_change()
        self.update_bookmarks()

    def update_bookmarks(self) -> None:
        s = self.view.session
        language = self.view.language
        items = []
        for k, p in enumerate(s.lesson.presets):
            cur = p.name == s.preset
            style = "font-weight:bold;color:#1c4f8a" if cur else "color:#444"
            items.append(
                f'<li class="al-bookmark{" al-current" if cur else ""}" style="{style}">'
                f"{html.escape(p.name)}: {html.escape(language.lesson_text(p.title))}</li>"
            )
        content = (
            f'<ol class="al-bookmarks" style="font-size:max(11px,0.85em);padding-left:1.4em">{"".join(items)}</ol>'
            if items
            else '<div class="al-bookmarks" style="font-size:max(11px,0.85em)">'
            f"{html.escape(language.gettext(NO_PRESETS))}</div>"
        )
        if self.bookmarks.content != content:
            self.bookmarks.content = content


class InstructorPanel:
    """The instructor's controls, in that page's ``client.gui`` only."""

    def __init__(self, room: RoomForPanels, view: SessionView, link: ClassLink) -> None:
        self.room = room
        self.view = view
        self.link = link
        gui = view.client.gui
        tr = view.language.gettext
        self.folder = gui.add_folder(tr("Instructor panel"), order=-1000.0)
        with self.folder:
            self.counts = gui.add_html("")
            self.follow_btn = gui.add_button(
                tr("Follow me"),
                hint=tr("every student sees this page's lesson, values, play state and camera"),
            )
            self.release_btn = gui.add_button(
                tr("Release"),
                hint=tr("students get their own session back, from where the demo is"),
            )
            self.push_dd = gui.add_dropdown(tr("Preset for all"), ("(choose)",))
            self.push_btn = gui.add_button(tr("Push preset to all"))
            self.message = gui.add_text(tr("Message"), initial_value="")
            self.notify_btn = gui.add_button(tr("Notify all"))
        self.follow_btn.on_click(self._cb(lambda: room.start_follow(view)))
        self.release_btn.on_click(self._cb(lambda: room.release(everywhere=True)))
        self.push_btn.on_click(self._cb(self._push))
        self.notify_btn.on_click(self._cb(self._notify))
        self.camera: tuple[Any, ...] | None = None
        self.camera_t = 0.0  # when the instructor's browser last reported its camera
        self.lesson_t = (
            time.monotonic()
        )  # when the instructor's lesson last changed (the view framed it)
        self._lesson = view.session.lesson.id
        view.client.camera.on_update(self._on_camera)
        self.update()

    def relabel(self) -> None:
        """The panel in the page's language now (after a switch of it)."""
        tr = self.view.language.gettext
        self.folder.label = tr("Instructor panel")
        self.follow_btn.label = tr("Follow me")
        self.follow_btn.hint = tr(
            "every student sees this page's lesson, values, play state and camera"
        )
        self.release_btn.label = tr("Release")
        self.release_btn.hint = tr("students get their own session back, from where the demo is")
        self.push_dd.label = tr("Preset for all")
        self.push_btn.label = tr("Push preset to all")
        self.message.label = tr("Message")
        self.notify_btn.label = tr("Notify all")
        self.update()

    def _cb(self, fn: Callable[[], None]) -> Callable[[Any], None]:
        def wrapped(event: Any) -> None:
            if (
                getattr(event, "client", None) is None
                or event.client.client_id != self.view.client.client_id
            ):
                return
            try:
                fn()
            except LabError as exc:
                tr = self.view.language.gettext
                self.view.client.add_notification(
                    tr("Instructor"),
                    tr("refused: {reason}").format(reason=self.view.language.message(exc)),
                    auto_close_seconds=5.0,
                    color="red",
                )
            except Exception as exc:  # a page callback: the page says so, the log how
                log.exception("page %s: an instructor control failed", self.view.client.client_id)
                tr = self.view.language.gettext
                self.view.client.add_notification(
                    tr("Instructor"),
                    tr("internal error: {error}").format(error=exc),
                    auto_close_seconds=5.0,
                    color="red",
                )
            self.update()

        return wrapped

    def _on_camera(self, cam: Any) -> None:
        try:
            self.camera = (
                tuple(map(float, cam.position)),
                tuple(map(float, cam.look_at)),
                tuple(map(float, cam.up_direction)),
            )
        except (AssertionError, TypeError, ValueError):  # no camera reported, or not numbers
            return
        self.camera_t = time.monotonic()
        self.room.camera_moved()

    def fresh_camera(self) -> tuple[Any, ...] | None:
        """The instructor's camera if it was reported after the last lesson change
        (before that, each follower frames the same lesson the same way itself)."""
        if self.view.session.lesson.id != self._lesson:
            self._lesson = self.view.session.lesson.id
            self.lesson_t = time.monotonic()
        return self.camera if self.camera is not None and self.camera_t > self.lesson_t else None

    def _push(self) -> None:
        name = self.push_dd.value
        s = self.view.session
        if name not in {p.name for p in s.lesson.presets}:
            raise LabError(self.view.language.gettext("choose one of this lesson's presets"))
        self.room.push_preset(s.lesson.id, name)

    def _notify(self) -> None:
        text = self.message.value
        if not isinstance(text, str) or not text.strip():
            raise LabError(self.view.language.gettext("type a message first"))
        self.room.notify_all(text.strip())  # cut to the longest notice there
        self.message.value = ""

    def update(self) -> None:
        """Counts and the preset list (cheap; called a few times a second)."""
        students, following = self.room.counts()
        tr = self.view.language.gettext
        mode = (
            tr("following you")
            if self.room.broadcaster == self.view.client.client_id
            else tr("exploring on their own")
        )
        servers = self.link.remote_totals()[2]
        where = tr(" on {n} servers").format(n=servers + 1) if servers else ""
        # the template is the catalog's; only numbers and escaped texts go into it
        counts = tr("{students} student(s) connected{where}, {following} following; mode: {mode}")
        content = (
            '<div class="al-class-counts" style="font-size:0.9em">'
            + counts.format(
                students=f"<b>{students}</b>",
                where=html.escape(where),
                following=f'<b class="al-following">{following}</b>',
                mode=html.escape(mode),
            )
            + "</div>"
            + self.link.panel_note()
        )
        if self.counts.content != content:
            self.counts.content = content
        opts = ("(choose)", *(p.name for p in self.view.session.lesson.presets))
        if tuple(self.push_dd.options) != opts:
            self.push_dd.options = opts

    def remove(self) -> None:
        try:
            self.folder.remove()
        except RuntimeError:  # the page left meanwhile
            pass
