"""The transport: one time control shared by every lesson (play, pause, step by the
source's sampling, reset, speed, go to a time)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from analyzer_lab.lessons.kit.formula import parse_number
from analyzer_lab.session.session import SPEEDS, LabError, Session
from analyzer_lab.view.readout import speed_label

#: Frames of a jump ("go to t") drawn into the trail at most.
MAX_DRAWN_FRAMES = 2000

#: The label of the Run buttons and the button that plays.
RUN, PLAY = "Run", "Play"

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
    ) -> None:
        self.session = session
        self.played = played
        self.buttons = gui.add_button_group(RUN, (PLAY, "Pause", "Step", "Reset"))
        self.buttons.on_click(guard(self._on_button))
        s = session()
        self.speed = gui.add_dropdown(
            "Speed", tuple(speed_label(x) for x in SPEEDS), initial_value=speed_label(s.speed)
        )
        self.speed.on_update(guard(self._on_speed))
        self.goto = gui.add_text(
            "go to t [s]", initial_value="", hint="show the run at this time (paused)"
        )
        self.goto.on_update(guard(self._on_goto))

    def _on_button(self, event: Any) -> None:
        what = event.target.value
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
            raise LabError(f"unknown transport command {str(what)[:40]!r}")

    def _on_speed(self, event: Any) -> None:
        text = str(event.target.value)
        if not text.endswith("x"):
            raise LabError(f"unknown speed {text[:20]!r}")
        self.session().set_speed(text[:-1])
        self.played([])

    def _on_goto(self, event: Any) -> None:
        text = str(event.target.value).strip()
        if not text:
            return
        try:
            t = parse_number(text)
        except ValueError as exc:
            raise LabError(f"go to t: {exc}") from None
        self.played(self.session().go_to(t))
