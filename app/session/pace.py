"""How a session's playback keeps pace: the work budget of its steps, the "running at"
notice when it cannot keep up, and the pause on a state that is not finite.

A :class:`analyzer_lab.session.session.Session` holds one :class:`Pace` and asks it to size
and take each piece of a tick and to follow how much of the asked speed the run keeps up
with; the constants are the budget the live server gives each session per frame tick.
"""

from __future__ import annotations

import logging
import math
from typing import Any, Literal

import numpy as np
from analyzer_lab.lessons.kit.budget import clock
from analyzer_lab.lessons.kit.contract import Frame, Lesson, Stepper
from analyzer_lab.lessons.kit.message import N_, Message

log = logging.getLogger(__name__)

#: CPU seconds one session may spend stepping in one frame tick (a seventh of a frame at
#: 36 fps; the sphere at 8x needs 1.2 ms): a run that needs more plays slower, its own
#: clock only, and says so on its page.
STEP_BUDGET = 0.004
#: Lesson seconds: the grain of a played tick (a piece of a tick is whole grains when it can
#: be, so that frames land on the times lessons keep tables for).
TIME_QUANTUM = 1.0 / 600.0
#: Wall seconds of stepping per tick in the live server (a busy machine steps less).
STEP_WALL_BUDGET = 0.006
#: The budgets (CPU, wall) of the one run playing on a server: the loop's time it does
#: not share (the 6-DOF table's forward problem needs 0.63 CPU seconds a lesson second,
#: 0.47x real time on :data:`STEP_BUDGET`, 0.68x on this).
SOLO_STEP_BUDGET, SOLO_WALL_BUDGET = 0.012, 0.016
#: The share of the asked speed below which a page says it runs slower (and above which
#: it says it is back).
SLOW_BELOW, SLOW_CLEARED = 0.9, 0.97
#: Wall seconds a run is behind before the page gets a notice (the figure has settled).
SLOW_NOTICE_AFTER = 1.0

#: What the page is to be told after a tick: the run fell behind, or it is back.
PaceNews = Literal["slow", "back"]


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


class Pace:
    """How one session's playback keeps pace: pieces sized to the budget left (by the
    recent cost per lesson second), each piece stepped and checked, and the share of the
    asked speed the run keeps up with (and when its page is told)."""

    def __init__(self) -> None:
        self.cost = 0.0  # CPU seconds per lesson second of the recent pieces
        #: the share of the asked speed the run keeps up with (moving average over ticks)
        self.keeping_up = 1.0
        self.slowed = False  # shown on the page: "running at 0.3x ..."
        #: the last cut tick spent little CPU: the machine, not the run, was slow
        self.machine_busy = False
        self._slow_wall = 0.0  # wall seconds since the run fell behind
        self._slow_told = False  # the page was told (a notice)

    def piece_size(self, piece: float, left: float, quantum: float) -> float:
        """The next piece of lesson time: ``piece``, less if the recent cost per lesson
        second says it would not fit into the budget ``left`` (CPU seconds); whole grains
        of ``quantum`` lesson seconds where it is longer than one (at least one grain, so a
        busy machine moves the run less but never off the grain)."""
        if self.cost > 0.0 and self.cost * piece > left:
            fit = max(left / self.cost, 1e-9)
            if piece >= quantum:  # at least one whole grain: a frame never lands between grains
                return max(math.floor(fit / quantum + 1e-9), 1) * quantum
            return fit
        # whole grains (rounded up: the pieces of a tick of whole grains stay whole)
        return math.ceil(piece / quantum - 1e-9) * quantum if piece > quantum else piece

    def step(self, stepper: Stepper, d: float, allowed: frozenset[str]) -> tuple[Frame | None, str]:
        """One stepper call of lesson time ``d``: the frame, or None and why it stopped
        (``allowed``: the series the lesson declares undefined somewhere)."""
        t0, c0 = stepper.t, clock()
        try:
            frame = stepper.advance(d)
        except (ValueError, ArithmeticError, FloatingPointError) as exc:
            log.info("the integration stopped at t = %.6g s: %s", t0, exc)
            return None, Message(N_("the integration stopped: {error}"), error=str(exc))
        moved = stepper.t - t0
        if moved > 0:
            cost = (clock() - c0) / moved
            # a dearer piece counts at once, a cheaper one halves the gap
            self.cost = cost if cost > self.cost else 0.5 * (self.cost + cost)
        bad = non_finite(frame, allowed)
        if bad is not None:
            return None, Message(
                N_(
                    "{quantity} is not finite (NaN or infinite) at t = {t:.6g} s: playback"
                    " paused; change the values or reset"
                ),
                quantity=bad,
                t=frame.t,
            )
        return frame, ""

    def cut(self, cpu_spent: float, budget: float) -> None:
        """A tick stopped at its budget, after ``cpu_spent`` CPU seconds of ``budget``: by
        the stepping itself, or by a busy machine (wall time, little CPU)."""
        self.machine_busy = cpu_spent < 0.5 * budget

    def restart(self) -> None:
        """Playback starts: the run keeps up until a tick says otherwise."""
        self.keeping_up, self.slowed = 1.0, False

    def follow(self, wanted: float, moved: float, wall_dt: float) -> PaceNews | None:
        """Follow the share of the asked lesson time the run keeps up with (``moved`` of
        ``wanted`` in ``wall_dt`` wall seconds): ``"slow"`` when the page is to be told the
        run fell behind (once the figure has settled), ``"back"`` when it is back."""
        share = min(max(moved / wanted, 0.0), 1.0) if wanted > 0 else 1.0
        self.keeping_up = 0.85 * self.keeping_up + 0.15 * share
        news: PaceNews | None = None
        if not self.slowed and self.keeping_up < SLOW_BELOW:
            self.slowed, self._slow_wall, self._slow_told = True, 0.0, False
        elif self.slowed and self.keeping_up > SLOW_CLEARED:
            self.slowed = False
            if self._slow_told:
                news = "back"
        if self.slowed and not self._slow_told:
            self._slow_wall += wall_dt
            if self._slow_wall >= SLOW_NOTICE_AFTER:  # the figure has settled
                self._slow_told = True
                news = "slow"
        return news

    def effective_speed(self, speed: float) -> float:
        """The speed the run keeps up with (the asked ``speed`` unless :attr:`slowed`)."""
        return speed * (self.keeping_up if self.slowed else 1.0)

    def slow_text(self, speed: float, lesson: Lesson) -> str:
        """What the page says while the run cannot keep up with the asked ``speed``."""
        names = {p.name for p in lesson.params}
        if self.machine_busy:
            why = N_("running at {speed:.2g}x: the server's machine is busy")
        elif names & {"h", "rtol"}:
            why = N_(
                "running at {speed:.2g}x: the step is too small for live play (a larger step h"
                " or a looser tolerance plays faster)"
            )
        else:
            why = N_("running at {speed:.2g}x: the computation is too slow for live play")
        return Message(why, speed=self.effective_speed(speed))
