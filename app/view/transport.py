"""The transport: one time control shared by every lesson (play, pause, step by the
source's sampling, reset, speed, go to a time)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.formula import parse_number
from analyzer_lab.session.session import SPEEDS, LabError, Session
from analyzer_lab.view.readout import speed_label
from analyzer_lab.viser_boundary import sent_value

#: Frames of a jump ("go to t") drawn into the trail at most.
MAX_DRAWN_FRAMES = 2000

#: The label of the Run buttons and the button that plays.
RUN, PLAY = N_("Run"), N_("Play")
#: The Run buttons (English; each page shows them in its language).
BUTTONS = (PLAY, N_("Pause"), N_("Step"), N_("Reset"))

Played = Callable[[list[Any]], None]


class Transport:
    """The Run buttons, the speed and "go to t" of one page.  ``played(frames)`` gets
    the frames a step or jump made (none after play, pause, a reset or a new speed)."""

    def __init__(
        self,
        gui: Any,
        guard: Callable[[Callable[[Any], None]], Callable[[Any], None]],
        session: Callable[[], Session],
        played: Played,
        language: Language = ENGLISH,
    ) -> None:
        self.session = session
        self.played = played
        self.language = language
        #: the shown button -> the command (English)
        self.commands = {language.gettext(b): b for b in BUTTONS}
        run, speed, goto, hint = self._labels(language)
        self.buttons = gui.add_button_group(run, tuple(self.commands))
        self.buttons.on_click(guard(self._on_button))
        s = session()
        self.speed = gui.add_dropdown(
            speed, tuple(speed_label(x) for x in SPEEDS), initial_value=speed_label(s.speed)
        )
        self.speed.on_update(guard(self._on_speed))
        self.goto = gui.add_text(goto, initial_value="", hint=hint)
        self.goto.on_update(guard(self._on_goto))

    @staticmethod
    def _labels(language: Language) -> tuple[str, str, str, str]:
        """The labels of the Run buttons, the speed and "go to t", and the latter's hint."""
        tr = language.gettext
        return (
            tr(RUN),
            tr("Speed"),
            tr("go to t [{unit}]").format(unit=language.unit("s")),
            tr("show the run at this time (paused)"),
        )

    def set_language(self, language: Language) -> None:
        """Label the buttons and fields in ``language`` (the commands stay)."""
        self.language = language
        self.commands = {language.gettext(b): b for b in BUTTONS}
        run, speed, goto, hint = self._labels(language)
        for widget, label in ((self.buttons, run), (self.speed, speed), (self.goto, goto)):
            if widget.label != label:
                widget.label = label
        if tuple(self.buttons.options) != tuple(self.commands):
            self.buttons.options = tuple(self.commands)
        if self.goto.hint != hint:
            self.goto.hint = hint

    def _on_button(self, event: Any) -> None:
        tr = self.language.gettext
        what = self.commands.get(sent_value(event), sent_value(event))
        s = self.session()
        if what == PLAY:
            s.play()
            self.played([])
        elif what == "Pause":
            s.pause()
            self.played([])
        elif what == "Step":  # by the source's sampling (t = 0, 1, 2, ...)
            self.played(s.step())
        elif what == "Reset":  # paused at the start, the scene framed again
            s.reset(playing=False, reframe=True)
            self.played([])
        else:
            raise LabError(tr("unknown transport command {name}").format(name=repr(str(what)[:40])))

    def _on_speed(self, event: Any) -> None:
        text = str(sent_value(event))
        if not text.endswith("x"):
            raise LabError(
                self.language.gettext("unknown speed {name}").format(name=repr(text[:20]))
            )
        self.session().set_speed(text[:-1])
        self.played([])

    def _on_goto(self, event: Any) -> None:
        text = str(sent_value(event)).strip()
        if not text:
            return
        try:
            t = parse_number(self.language.read_decimal(text))
        except ValueError as exc:
            raise LabError(self.language.gettext("go to t: {error}").format(error=exc)) from None
        self.played(self.session().go_to(t))
