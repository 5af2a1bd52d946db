"""Played frames of the 6-DOF table's inverse problem, read from blocks evaluated at once.

A played frame falls on the session's time quanta (:data:`FRAME_GRAIN`); the states,
scalars and drawing of a block of :data:`TABLE_BLOCK` such times are evaluated in one
vectorized call (:func:`lessons.core.table6dof.program_states` and the lesson's
observation), so a frame reads a row.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from lessons.core.contract import Frame
from lessons.core.table6dof import inverse_states, joints_body, rotations

Array = np.ndarray


#: lesson seconds between the times a played frame can fall on (the session's time quanta)
FRAME_GRAIN = 1.0 / 600.0
#: grain times evaluated at once for played frames (see :class:`InverseTable`)
TABLE_BLOCK = 512


class InverseTable:
    """The inverse problem for played frames.  A time on the grain of played frames
    (multiples of :data:`FRAME_GRAIN`) is read from a block of :data:`TABLE_BLOCK` grain
    times, states and the lesson's observation (``observe(t, states)``, the scalars
    ``names``) evaluated in one vectorized call when a frame first reaches it; any other
    time is evaluated directly.  One table per parameter set."""

    def __init__(
        self,
        ev: Callable[[Array], tuple[Array, Array, Array]],
        p: Array,
        observe: Callable[[Array, Array], dict[str, Array]],
        names: tuple[str, ...],
        draw: Callable[[Array, dict[str, Array]], dict[str, Array]] | None = None,
    ) -> None:
        self.ev, self.p, self.observe, self.names, self.draw = ev, p, observe, names, draw
        #: (block, states (TABLE_BLOCK, 36), scalars (TABLE_BLOCK, len(names)), the rows
        #: ``draw(states, observation)`` gives (:func:`pose_rows`))
        self.block: tuple[int, Array, Array, dict[str, Array]] | None = None
        self.builds = 0  # blocks evaluated so far

    def _row(self, t: float) -> int | None:
        """Index of ``t`` in the (current or new) block, None off the grain."""
        j = round(t / FRAME_GRAIN)
        if j < 0 or abs(t / FRAME_GRAIN - j) > 1e-9:
            return None
        b, i = divmod(j, TABLE_BLOCK)
        if self.block is None or self.block[0] != b:
            tt = (b * TABLE_BLOCK + np.arange(TABLE_BLOCK)) * FRAME_GRAIN
            S = inverse_states(self.ev, self.p, tt)
            obs = self.observe(tt, S)
            rows = self.draw(S, obs) if self.draw is not None else {}
            self.block = (b, S, np.column_stack([obs[n] for n in self.names]), rows)
            self.builds += 1
        return i

    def states(self, t: Array) -> Array:
        """States at the times ``t`` (``(len(t), 36)``)."""
        if len(t) == 1:
            i = self._row(float(t[0]))
            if i is not None and self.block is not None:
                return self.block[1][i : i + 1].copy()
        return inverse_states(self.ev, self.p, t)

    def scalars(self, t: float, state: Array) -> dict[str, float] | None:
        """The observation of ``state`` at ``t`` from the table, or None when ``t`` is off
        the grain or ``state`` is not the table's state at ``t``."""
        i = self._row(t)
        if i is None or self.block is None or not np.array_equal(self.block[1][i], state):
            return None
        return dict(zip(self.names, self.block[2][i].tolist()))

    def drawn(self, t: float, state: Array) -> tuple[dict[str, Array], int] | None:
        """The drawing rows of the block and the row of ``state`` at ``t``, or None as
        :meth:`scalars` (or when the table draws nothing)."""
        i = self._row(t)
        if (
            i is None
            or self.block is None
            or not self.block[3]
            or not np.array_equal(self.block[1][i], state)
        ):
            return None
        return self.block[3], i


def pose_rows(q: Array, arrows: Array, r_t: float) -> dict[str, Array]:
    """What :func:`pose_table` draws, for ``N`` states at once (``q (N, 12)``, ``arrows
    (N, 6)``): per name, the rows of its position and quaternion (or arrow)."""
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
    """Row ``i`` of :func:`pose_rows` into the frame, as :func:`pose_table` poses it."""
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


__all__ = ["FRAME_GRAIN", "TABLE_BLOCK", "InverseTable", "pose_row", "pose_rows"]
