"""A live stepper that reads a lesson's solution instead of integrating on its own.

A lesson whose state at any time comes from one object per parameter set (a *track*:
a closed form, or fixed steps on a fixed grid kept in memory) gets its live view from
:class:`TrackStepper`: advancing only moves the time and every frame reads the track, so
the live frames and the headless run
(:meth:`~analyzer_lab.lessons.kit.contract.Lesson.simulate` reading the same track on its
sample grid) are the same numbers.  A live parameter change continues from the
current state with a new track (the lesson's ``continue_track``) or, when the lesson
cannot continue (another start point or family size), starts over.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, Params, Stepper


class Track(Protocol):
    def at(self, t: np.ndarray) -> Any:
        """The lesson's state at the times ``t`` (leading axis = time)."""


class TrackedLesson(Protocol):
    def track(self, params: Params) -> Track: ...

    def continue_track(self, old: Params, params: Params, t: float, state: Any) -> Track | None: ...

    def make_frame(self, params: Params, t: float, state: Any) -> Frame: ...


class TrackStepper(Stepper):
    """Live run of a tracked lesson: the time advances, the frame is read from the track."""

    def __init__(self, lesson: TrackedLesson, params: Params) -> None:
        self.lesson, self.params = lesson, params
        self._t = 0.0
        self.track = lesson.track(params)

    @property
    def t(self) -> float:
        return self._t

    def _state(self) -> Any:
        return self.track.at(np.array([self._t]))

    def frame(self) -> Frame:
        return self.lesson.make_frame(self.params, self._t, self._state())

    def advance(self, dt: float) -> Frame:
        if np.isfinite(dt) and dt > 0:
            self._t += float(dt)
        return self.frame()

    def set_params(self, params: Params) -> None:
        """New values act from the current state, or from the start if the lesson says so."""
        track = self.lesson.continue_track(self.params, params, self._t, self._state())
        if track is None:
            track, self._t = self.lesson.track(params), 0.0
        self.params, self.track = params, track

    def reset(self) -> Frame:
        self._t = 0.0
        self.track = self.lesson.track(self.params)
        return self.frame()
