"""Back-pressure per page: a page whose connection does not take what is sent to it
gets no new frames while it is behind, and its playback pauses (with a notice) when it
stays behind; the server's memory for it stays bounded whatever the page does."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

#: A page whose sender is this many messages behind gets no new frame (a reading page is
#: a few frames, tens of messages, behind; a slow browser on a busy machine some hundreds).
LAG_SKIP = 2000
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
    behind_since: dict[int, float] = field(default_factory=dict)
    skipped: int = 0
    paused: int = 0

    def turn(self, page: int, lag: int, now: float, playing: bool) -> Turn:
        """The page's turn given its sender's ``lag`` (messages) at time ``now``."""
        if lag < self.skip_lag:
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


__all__ = ["LAG_SKIP", "PAUSED_NOTICE", "STALL_PAUSE", "BackPressure", "Turn"]
