"""Back-pressure per page: a page whose connection does not take what is sent to it (its
sender far behind, or taking nothing for a second) gets no new frames while it is behind,
and its playback pauses (with a notice) when it stays behind; the server's memory for it
stays bounded whatever the page does."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

#: A page whose sender is this many messages behind gets no new frame (a reading page is
#: a few frames, tens of messages, behind; a slow browser on a busy machine some hundreds).
LAG_SKIP = 2000
#: A page whose sender has taken nothing for :data:`STALL_SKIP` s while this many messages
#: wait for it is behind too (a page that stopped reading, found long before it is
#: :data:`LAG_SKIP` messages behind: with a hundred such pages each gets a frame only
#: every few ticks, and would be stepped and drawn for tens of seconds).
STALL_LAG = 100
STALL_SKIP = 1.0
#: A page behind for this long has its playback paused and is told why.
STALL_PAUSE = 5.0

PAUSED_NOTICE = (
    "Playback paused: this page has not been taking its updates for "
    f"{STALL_PAUSE:g} s (a slow or stalled connection). Press Play to go on."
)


class Turn(Enum):
    """What the frame loop does with a page this tick."""

    DRAW = "draw"
    SKIP = "skip"
    PAUSE = "pause"


@dataclass
class BackPressure:
    """Which pages are behind, since when, and what was held back from them."""

    skip_lag: int = LAG_SKIP
    pause_after: float = STALL_PAUSE
    stall_lag: int = STALL_LAG
    stall_after: float = STALL_SKIP
    behind_since: dict[int, float] = field(default_factory=dict)
    #: page -> (the last message its sender took, since when)
    taken: dict[int, tuple[int, float]] = field(default_factory=dict)
    skipped: int = 0
    paused: int = 0

    def turn(self, page: int, lag: int, now: float, playing: bool, taken: int = -1) -> Turn:
        """The page's turn given its sender's ``lag`` (messages) and the number of the
        last message it ``taken`` at time ``now``."""
        last = self.taken.get(page)
        if last is None or last[0] != taken or lag < self.stall_lag:
            self.taken[page] = last = (taken, now)  # the stall clock runs while messages wait
        stalled = lag >= self.stall_lag and now - last[1] >= self.stall_after
        if lag < self.skip_lag and not stalled:
            self.behind_since.pop(page, None)
            return Turn.DRAW
        since = self.behind_since.setdefault(page, now)
        self.skipped += 1
        if playing and now - since >= self.pause_after:
            self.paused += 1
            return Turn.PAUSE
        return Turn.SKIP

    def forget(self, page: int) -> None:
        """The page left."""
        self.behind_since.pop(page, None)
        self.taken.pop(page, None)


__all__ = [
    "LAG_SKIP",
    "PAUSED_NOTICE",
    "STALL_LAG",
    "STALL_PAUSE",
    "STALL_SKIP",
    "BackPressure",
    "Turn",
]
