"""How a session's playback keeps pace: the work budget of its steps, the "running at"
notice when it cannot keep up, and the pause on a state that is not finite.

:class:`Pacing` is part of :class:`analyzer_lab.session.session.Session` (its stepping methods); the
constants are the budget the live server gives each session per frame tick.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.budget import clock
from analyzer_lab.lessons.kit.contract import Frame, Lesson, Params, Stepper
from analyzer_lab.lessons.kit.formula import plain_number as plain

#: CPU seconds one session may spend stepping in one frame tick (a seventh of a frame at
#: 36 fps; the sphere at 8x needs 1.2 ms): a run that needs more plays slower, its own
#: clock only, and says so on its page.
STEP_BUDGET = 0.004
#: Lesson seconds: the grain of a played tick (a piece of a tick is whole grains when it can
#: be, so that frames land on the times lessons keep tables for).
TIME_QUANTUM = 1.0 / 600.0
#: Wall seconds of stepping per tick in the live server (a busy machine steps less).
STEP_WALL_BUDGET = 0.006
#: The share of the asked speed below which a page says it runs slower (and above which
#: it says it is back).
SLOW_BELOW, SLOW_CLEARED = 0.9, 0.97
#: Wall seconds a run is behind before the page gets a notice (the figure has settled).
SLOW_NOTICE_AFTER = 1.0


def non_finite(frame: Frame, allowed: frozenset[str] = frozenset()) -> str | None:
    """The name of the first quantity of ``frame`` that is not finite, or None;
    ``allowed``: quantities the lesson declares undefined somewhere (``Series.undefined``).

    One sum over every number of the frame says at once that all are finite (a sum of
    finite numbers is finite unless it overflows); only otherwise are the quantities
    looked at one by one (:func:`first_non_finite`)."""
    try:
        total = sum(frame.scalars.values())
        for pts in frame.points.values():
            total += _sum(pts)
        for at, vec in frame.vectors.values():
            total += _sum(at) + _sum(vec)
        if math.isfinite(total):
            return None
    except TypeError:  # a value that is not a number: looked at one by one
        pass
    return first_non_finite(frame, allowed)


def _sum(values: Any) -> float:
    """The sum of an array's numbers (NaN if one is NaN, or +inf and -inf both occur)."""
    if type(values) is np.ndarray and values.dtype == np.float64 and values.size <= 64:
        return sum(values.ravel().tolist())
    with np.errstate(over="ignore", invalid="ignore"):
        return float(np.sum(np.asarray(values, dtype=float)))


def first_non_finite(frame: Frame, allowed: frozenset[str] = frozenset()) -> str | None:
    """:func:`non_finite`, quantity by quantity: the scalars in order (but the
    ``allowed``), then the points, then the vectors."""
    for name, v in frame.scalars.items():
        if name in allowed:
            continue
        if isinstance(v, (int, float, np.floating, np.integer)) and not math.isfinite(float(v)):
            return name
    for name, pts in frame.points.items():
        if not np.all(np.isfinite(np.asarray(pts, dtype=float))):
            return f"the {name}"
    for name, (at, vec) in frame.vectors.items():
        if not (
            np.all(np.isfinite(np.asarray(at, dtype=float)))
            and np.all(np.isfinite(np.asarray(vec, dtype=float)))
        ):
            return f"the {name} vector"
    return None


class Pacing:
    """The stepping half of a session: pieces sized to the budget, the cost per lesson
    second, the share of the asked speed kept up with."""

    lesson: Lesson
    params: Params
    stepper: Stepper
    speed: float
    pause_at_end: bool
    t_end: float
    notify: Any

    def _init_pacing(self) -> None:
        self.step_budget = STEP_BUDGET  # CPU seconds of stepping per tick
        #: wall seconds of stepping per tick (the live server sets it; None: CPU only)
        self.wall_budget: float | None = None
        self._cost = 0.0  # CPU seconds per lesson second of the recent pieces
        #: the share of the asked speed the run keeps up with (moving average over ticks)
        self.keeping_up = 1.0
        self.slowed = False  # shown on the page: "running at 0.3x ..."
        self._slow_wall = 0.0  # wall seconds since the run fell behind
        self._slow_told = False  # the page was told (a notice)
        #: the last cut tick spent little CPU: the machine, not the run, was slow
        self.machine_busy = False
        #: (lesson, params, the series that may be undefined) of the last frame checked
        self._allowed_for: tuple[Lesson, Params, frozenset[str]] | None = None

    def _piece_size(self, piece: float, left: float) -> float:
        """The next piece of lesson time: ``piece``, less if the recent cost per lesson
        second says it would not fit into the budget ``left`` (CPU seconds); whole
        :data:`TIME_QUANTUM` grains where it is longer than one."""
        q = TIME_QUANTUM * self.lesson.time_scale
        if self._cost > 0.0 and self._cost * piece > left:
            piece = max(left / self._cost, 1e-9)
            return math.floor(piece / q + 1e-9) * q if piece >= q else piece
        # whole grains (rounded up: the pieces of a tick of whole grains stay whole)
        return math.ceil(piece / q - 1e-9) * q if piece > q else piece

    def _step_piece(self, d: float) -> tuple[Frame | None, str]:
        """One stepper call of lesson time ``d``: the frame, or None and why it stopped."""
        t0, c0 = self.stepper.t, clock()
        try:
            frame = self.stepper.advance(d)
        except (ValueError, ArithmeticError, FloatingPointError) as exc:
            return None, f"the integration stopped: {exc}"
        moved = self.stepper.t - t0
        if moved > 0:
            cost = (clock() - c0) / moved
            # a dearer piece counts at once, a cheaper one halves the gap
            self._cost = cost if cost > self._cost else 0.5 * (self._cost + cost)
        bad = non_finite(frame, self._allowed())
        if bad is not None:
            return None, (
                f"{bad} is not finite (NaN or infinite) at t = {frame.t:.6g} s:"
                " playback paused; change the values or reset"
            )
        return frame, ""

    def _allowed(self) -> frozenset[str]:
        """The series of the lesson that may be undefined (``Series.undefined``), kept for
        the current lesson and parameters."""
        key = self._allowed_for
        if key is None or key[0] is not self.lesson or key[1] is not self.params:
            names = frozenset(s.name for s in self.lesson.series_for(self.params) if s.undefined)
            key = self._allowed_for = (self.lesson, self.params, names)
        return key[2]

    def _keep_up(self, wanted: float, moved: float, wall_dt: float) -> None:
        """Follow the share of the asked lesson time the run keeps up with; say so on the
        page when it falls behind (and when it is back)."""
        if self.pause_at_end and self.stepper.t >= self.t_end - 1e-9:
            return  # stopped at t_end on purpose
        share = min(max(moved / wanted, 0.0), 1.0) if wanted > 0 else 1.0
        self.keeping_up = 0.85 * self.keeping_up + 0.15 * share
        if not self.slowed and self.keeping_up < SLOW_BELOW:
            self.slowed, self._slow_wall, self._slow_told = True, 0.0, False
        elif self.slowed and self.keeping_up > SLOW_CLEARED:
            self.slowed = False
            if self._slow_told:
                self.notify(f"playing at {plain(self.speed)}x again", "info")
        if self.slowed and not self._slow_told:
            self._slow_wall += wall_dt
            if self._slow_wall >= SLOW_NOTICE_AFTER:  # the figure has settled
                self._slow_told = True
                self.notify(self.slow_text(), "warning")

    def effective_speed(self) -> float:
        """The speed the run keeps up with (the asked speed unless :attr:`slowed`)."""
        return self.speed * (self.keeping_up if self.slowed else 1.0)

    def slow_text(self) -> str:
        """What the page says while the run cannot keep up with the asked speed."""
        names = {p.name for p in self.lesson.params}
        if self.machine_busy:
            why = "the server's machine is busy"
        elif names & {"h", "rtol"}:
            why = (
                "the step is too small for live play (a larger step h or a looser tolerance"
                " plays faster)"
            )
        else:
            why = "the computation is too slow for live play"
        return f"running at {self.effective_speed():.2g}x: {why}"
