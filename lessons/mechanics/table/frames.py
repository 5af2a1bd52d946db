"""Played frames of the 6-DOF table's inverse problem, read from chunks evaluated at once.

A played frame falls on the session's time quanta (:data:`FRAME_GRAIN`), about every
sixteenth or seventeenth of them at speed 1.  The states, scalars and drawing of the grain
times the next :data:`CHUNK_FRAMES` frames will read are evaluated in one vectorized call
(:func:`analyzer_lab.lessons.mechanics.table.model.program_states` and the lesson's observation), so a frame
reads a row.  The times are foreseen from the mean step between frames, each within the
spread the frames showed about such foresight.  Frames that do not play evenly (the first
ones, or several sessions reading one table in turn) read aligned chunks of every grain
time instead, the latest :data:`DENSE_CHUNKS` of them kept.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict, deque
from collections.abc import Callable

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame
from analyzer_lab.lessons.mechanics.table.model import inverse_states, joints_body, rotations

Array = np.ndarray


#: lesson seconds between the times a played frame can fall on (the session's time quanta)
FRAME_GRAIN = 1.0 / 600.0
#: played frames one evaluated chunk is planned for (see :class:`InverseTable`)
CHUNK_FRAMES = 64
#: most grain times evaluated at once (a chunk of every grain time in its span)
MAX_ROWS = 512
#: frames whose offsets from their foreseen times set the windows of a chunk
RECENT = 4 * CHUNK_FRAMES
#: frames over which a mean step a quarter off the long one means a new speed
SPEED_FRAMES = 8
#: grain times of an aligned chunk of every grain time (read while the playing is not even)
DENSE_ROWS = 128
#: aligned chunks kept (the latest read), e.g. one per session playing the parameter set
DENSE_CHUNKS = 96

#: a chunk: (grain time -> row, states (rows, 36), scalars (rows, len(names)), the rows
#: ``draw(states, observation)`` gives (:func:`pose_rows`))
Block = tuple[dict[int, int], Array, Array, dict[str, Array]]


class InverseTable:
    """The inverse problem for played frames.  A time on the grain of played frames
    (multiples of :data:`FRAME_GRAIN`) is read from a chunk of grain times, states and
    the lesson's observation (``observe(t, states)``, the scalars ``names``) evaluated in
    one vectorized call when a frame reaches a time the chunk lacks; any other time is
    evaluated directly.  One table per parameter set.

    A chunk is planned when a frame needs it: the frames since the playing went on evenly
    (no jump back, no new speed) give the mean step ``r`` and the line ``phase + r i``
    about which frame ``i`` fell; the next :data:`CHUNK_FRAMES` frames are foreseen on it,
    each within the ``spread`` of the recent frames about it.  When such windows would
    cover most of their span, the chunk is every grain time of :data:`MAX_ROWS`.  Until
    :data:`SPEED_FRAMES` frames played evenly (after a jump, or while the frames of several
    sessions sharing the table interleave), a frame reads the aligned chunk of every grain
    time :data:`DENSE_ROWS` that holds it (``j // DENSE_ROWS``), kept among the latest
    :data:`DENSE_CHUNKS` of them.
    """

    def __init__(
        self,
        ev: Callable[[Array], tuple[Array, Array, Array]],
        p: Array,
        observe: Callable[[Array, Array], dict[str, Array]],
        names: tuple[str, ...],
        draw: Callable[[Array, dict[str, Array]], dict[str, Array]] | None = None,
    ) -> None:
        self.ev, self.p, self.observe, self.names, self.draw = ev, p, observe, names, draw
        self.block: Block | None = None  # the chunk planned for the frames foreseen
        self.dense: OrderedDict[int, Block] = OrderedDict()  # aligned chunks, latest last
        self.builds = 0  # chunks evaluated so far
        self.rows_built = 0  # grain times evaluated so far
        #: lowest and highest offset (grain times) of the recent frames from the line
        #: they foresee, as the last chunk was planned with
        self.spread = (0.0, 0.0)
        self._last = -1  # the grain time of the last frame read
        self._even = (-1, 0)  # (grain time, frames read since) where the playing went even
        self._recent: deque[tuple[int, int]] = deque(maxlen=RECENT)  # (frame, grain time)
        #: the pages with these values read the table on several threads; a chunk, once
        #: built, is never changed
        self._lock = threading.Lock()

    def _count(self, j: int) -> None:
        """Count the frame at grain time ``j`` (not the last one read)."""
        last, (a, n) = self._last, self._even
        self._last = j
        pts = self._recent
        if last >= 0 and j > last:
            self._even = (a, n + 1)
            pts.append((n + 1, j))
            if len(pts) <= SPEED_FRAMES:
                return
            mean = (j - a) / (n + 1)
            lately = (j - pts[-SPEED_FRAMES - 1][1]) / SPEED_FRAMES
            if 0.75 * mean <= lately <= 1.33 * mean:
                return
        # the first frame, a jump back or a new speed: the even playing starts again
        self._even = (j, 0)
        pts.clear()
        pts.append((0, j))

    def _grains(self, j: int) -> Array:
        """The grain times of a new chunk from ``j``."""
        n = self._even[1]  # at least SPEED_FRAMES frames played evenly
        pts = self._recent
        i_mean = sum(i for i, _ in pts) / len(pts)
        g_mean = sum(g for _, g in pts) / len(pts)
        var = sum((i - i_mean) ** 2 for i, _ in pts)
        r = sum((i - i_mean) * (g - g_mean) for i, g in pts) / var  # least squares
        offsets = [g - g_mean - r * (i - i_mean) for i, g in pts]
        lo, hi = min(*offsets, 0.0), max(*offsets, 0.0)
        if hi - lo > 1.0:  # frames that jitter: the rarer offsets a little beyond the recent
            lo, hi = lo - 0.25 * (hi - lo), hi + 0.25 * (hi - lo)
        self.spread = (lo, hi)
        # the line is known within about a grain time over the recent frames: a window
        # widens by that much per such span foreseen ahead
        drift = (hi - lo + 1.0) / (pts[-1][0] - pts[0][0])
        grains = {j}
        for k in range(n + 1, n + CHUNK_FRAMES):
            c, d = g_mean + r * (k - i_mean), drift * (k - n)
            grains.update(range(math.ceil(c + lo - d - 1e-9), math.floor(c + hi + d + 1e-9) + 1))
            if len(grains) >= MAX_ROWS:
                break
        rows = sorted(g for g in grains if g >= j)
        if 4 * len(rows) > 3 * (rows[-1] - j + 1):  # windows that nearly meet: every time
            return j + np.arange(MAX_ROWS)
        return np.array(rows[:MAX_ROWS])

    def _build(self, grains: Array) -> Block:
        """The chunk of the grain times ``grains``, evaluated in one vectorized call."""
        tt = grains * FRAME_GRAIN
        S = inverse_states(self.ev, self.p, tt)
        obs = self.observe(tt, S)
        rows = self.draw(S, obs) if self.draw is not None else {}
        self.builds += 1
        self.rows_built += len(grains)
        index = {int(g): i for i, g in enumerate(grains)}
        return index, S, np.column_stack([obs[n] for n in self.names]), rows

    def _row(self, t: float) -> tuple[Block, int] | None:
        """The chunk holding ``t`` (the current, a kept or a new one) and its row, None
        off the grain."""
        with self._lock:
            return self._row_unlocked(t)

    def _row_unlocked(self, t: float) -> tuple[Block, int] | None:
        j = round(t / FRAME_GRAIN)
        if j < 0 or abs(t / FRAME_GRAIN - j) > 1e-9:
            return None
        if j != self._last:
            self._count(j)
        if self.block is not None:
            i = self.block[0].get(j)
            if i is not None:
                return self.block, i
        c = j // DENSE_ROWS
        block = self.dense.get(c)
        if block is not None:
            self.dense.move_to_end(c)
            return block, j - c * DENSE_ROWS
        if self._even[1] < SPEED_FRAMES:  # no even playing to foresee frames on
            block = self.dense[c] = self._build(c * DENSE_ROWS + np.arange(DENSE_ROWS))
            if len(self.dense) > DENSE_CHUNKS:
                self.dense.popitem(last=False)
            return block, j - c * DENSE_ROWS
        grains = self._grains(j)
        self.block = self._build(grains)
        return self.block, 0

    def states(self, t: Array) -> Array:
        """States at the times ``t`` (``(len(t), 36)``)."""
        if len(t) == 1:
            hit = self._row(float(t[0]))
            if hit is not None:
                return hit[0][1][hit[1] : hit[1] + 1].copy()
        return inverse_states(self.ev, self.p, t)

    def scalars(self, t: float, state: Array) -> dict[str, float] | None:
        """The observation of ``state`` at ``t`` from the table, or None when ``t`` is off
        the grain or ``state`` is not the table's state at ``t``."""
        hit = self._row(t)
        if hit is None or not np.array_equal(hit[0][1][hit[1]], state):
            return None
        return dict(zip(self.names, hit[0][2][hit[1]].tolist()))

    def drawn(self, t: float, state: Array) -> tuple[dict[str, Array], int] | None:
        """The drawing rows of the chunk and the row of ``state`` at ``t``, or None as
        :meth:`scalars` (or when the table draws nothing)."""
        hit = self._row(t)
        if hit is None or not hit[0][3] or not np.array_equal(hit[0][1][hit[1]], state):
            return None
        return hit[0][3], hit[1]


def pose_rows(q: Array, arrows: Array, r_t: float) -> dict[str, Array]:
    """What :func:`~analyzer_lab.lessons.mechanics.table.model.pose_table` draws, for ``N``
    states at once (``q (N, 12)``, ``arrows (N, 6)``): per name, the rows of its position
    and quaternion (or arrow)."""
    N = len(q)
    R = rotations(q[:, 3], q[:, 4], q[:, 5])
    joints = q[:, None, :3] + joints_body(r_t) @ R.transpose(0, 2, 1)  # (N, 3, 3)
    cz, sz = np.cos(q[:, 5] / 2), np.sin(q[:, 5] / 2)
    cy, sy = np.cos(q[:, 4] / 2), np.sin(q[:, 4] / 2)
    cx, sx = np.cos(q[:, 3] / 2), np.sin(q[:, 3] / 2)
    out: dict[str, Array] = {
        "table": np.column_stack(
            [
                q[:, :3],
                cz * cy * cx + sz * sy * sx,
                cz * cy * sx - sz * sy * cx,
                cz * sy * cx + sz * cy * sx,
                sz * cy * cx - cz * sy * sx,
            ]
        )
    }
    qz = np.column_stack([np.cos(q[:, 5] / 2), np.zeros(N), np.zeros(N), np.sin(q[:, 5] / 2)])
    for k, name in enumerate("ABC"):
        A = np.column_stack([q[:, 6 + 2 * k], q[:, 7 + 2 * k], np.zeros(N)])
        out[f"inductor {name}"] = np.column_stack([A, qz])
        d = joints[:, k] - A
        n = np.sqrt(np.einsum("ij,ij->i", d, d))
        b = d / np.where(n < 1e-15, 1.0, n)[:, None]
        quat = np.column_stack([1.0 + b[:, 2], -b[:, 1], b[:, 0], np.zeros(N)])
        with np.errstate(invalid="ignore", divide="ignore"):  # rows replaced just below
            quat /= np.sqrt(np.einsum("ij,ij->i", quat, quat))[:, None]
        quat[n < 1e-15] = [1.0, 0.0, 0.0, 0.0]
        quat[(n >= 1e-15) & (b[:, 2] < -1.0 + 1e-12)] = [0.0, 1.0, 0.0, 0.0]
        out[f"leg {name}{name}'"] = np.column_stack([(A + joints[:, k]) / 2, quat])
        out[f"F_{name}"] = np.column_stack(
            [A + [0, 0, 0.03], arrows[:, 2 * k], arrows[:, 2 * k + 1], np.zeros(N)]
        )
    out["D"] = q[:, :3]
    return out


def pose_row(fr: Frame, rows: dict[str, Array], i: int) -> None:
    """Row ``i`` of :func:`pose_rows` into the frame, as
    :func:`~analyzer_lab.lessons.mechanics.table.model.pose_table` poses it."""
    for name in (
        "table",
        "inductor A",
        "leg AA'",
        "inductor B",
        "leg BB'",
        "inductor C",
        "leg CC'",
    ):
        r = rows[name][i]
        fr.poses[name] = (r[:3].copy(), r[3:].copy())
    for name in ("F_A", "F_B", "F_C"):
        r = rows[name][i]
        fr.vectors[name] = (r[None, :3].copy(), r[None, 3:].copy())
    fr.points["D"] = rows["D"][i : i + 1].copy()


__all__ = [
    "CHUNK_FRAMES",
    "DENSE_ROWS",
    "FRAME_GRAIN",
    "MAX_ROWS",
    "InverseTable",
    "pose_row",
    "pose_rows",
]
