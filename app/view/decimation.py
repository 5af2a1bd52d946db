"""Decimation of a recorded run for a chart: the samples kept so that the picture of the
whole run is the picture of every sample (min/max per pixel column)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def minmax_indices(t: np.ndarray, columns: Sequence[np.ndarray], buckets: int) -> np.ndarray:
    """The indices of the samples to draw, ascending: the time span is cut into
    ``buckets`` equal columns; of each column the first and the last sample and, for every
    series of ``columns``, the sample of its least and of its greatest value (NaN is
    passed over where the column has a number).  A line through the kept samples has
    the same extent in every column as a line through all of them: nothing is aliased
    however fast a series moves.  ``t`` ascending; all indices when there are few."""
    n = len(t)
    buckets = max(1, int(buckets))
    if n <= 2 * buckets:
        return np.arange(n)
    t = np.asarray(t, dtype=float)
    span = float(t[-1] - t[0])
    if not span > 0.0:
        return np.array([0, n - 1])
    column = np.minimum(((t - t[0]) * (buckets / span)).astype(np.int64), buckets - 1)
    starts = np.flatnonzero(np.diff(column)) + 1
    first = np.insert(starts, 0, 0)  # the first sample of every column that has samples
    segment = np.repeat(np.arange(len(first)), np.diff(np.append(first, n)))
    keep = [first, np.append(starts - 1, n - 1)]
    for values in columns:
        v = np.asarray(values, dtype=float)
        nan = np.isnan(v)
        for fill, extreme in ((np.inf, np.minimum), (-np.inf, np.maximum)):
            # NaN counted as +inf for the least, -inf for the greatest: a number wins
            filled = np.where(nan, fill, v)
            hit = np.flatnonzero(filled == extreme.reduceat(filled, first)[segment])
            keep.append(hit[np.insert(np.diff(segment[hit]) > 0, 0, True)])
    return np.unique(np.concatenate(keep))


__all__ = ["minmax_indices"]
