"""The decimation of a run for a chart: min and max of every pixel column kept."""

from __future__ import annotations

import numpy as np
import pytest
from analyzer_lab.view.decimation import minmax_indices


def _columns(t: np.ndarray, buckets: int) -> np.ndarray:
    return np.minimum(((t - t[0]) * (buckets / (t[-1] - t[0]))).astype(int), buckets - 1)


def test_every_column_keeps_each_series_min_and_max_and_its_ends() -> None:
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0.0, 60.0, 20000))
    fast = np.sin(2 * np.pi * 9.7 * t)  # ~580 periods over 360 columns: aliases if sampled
    noisy = np.cos(t) + rng.normal(0.0, 0.3, t.size)
    noisy[3000:3400] = np.nan  # undefined for a while
    keep = minmax_indices(t, [fast, noisy], 360)
    assert np.all(np.diff(keep) > 0)  # ascending, no repeats
    assert keep[0] == 0 and keep[-1] == t.size - 1
    assert len(keep) < t.size / 4
    col = _columns(t, 360)
    kept_col = col[keep]
    for j in np.unique(col):
        kept = keep[kept_col == j]
        every = np.flatnonzero(col == j)
        assert kept[0] == every[0] and kept[-1] == every[-1]  # the column's ends
        for v in (fast, noisy):
            if np.isnan(v[every]).all():
                continue
            assert np.nanmin(v[kept]) == np.nanmin(v[every])
            assert np.nanmax(v[kept]) == np.nanmax(v[every])


def test_a_fast_oscillation_keeps_its_full_amplitude_everywhere() -> None:
    """The picture of an 8x run: a sine much faster than the pixel columns is drawn as
    its envelope (every column spans -1..1), never as a slow zig-zag."""
    t = np.linspace(0.0, 100.0, 20001)
    v = np.sin(2 * np.pi * 4.3 * t)
    keep = minmax_indices(t, [v], 300)
    col = _columns(t, 300)[keep]
    for j in range(300):
        values = v[keep][col == j]
        assert values.max() > 0.99 and values.min() < -0.99


def test_few_samples_are_all_kept_and_a_single_instant_is_its_ends() -> None:
    t = np.linspace(0.0, 1.0, 50)
    assert np.array_equal(minmax_indices(t, [t**2], 100), np.arange(50))
    flat = np.zeros(1000)
    assert list(minmax_indices(flat, [flat], 100)) == [0, 999]


@pytest.mark.parametrize("buckets", [1, 7, 360])
def test_columns_without_samples_are_skipped(buckets: int) -> None:
    t = np.concatenate([np.linspace(0, 1, 3000), np.linspace(9, 10, 3000)])  # a gap
    v = np.sin(40 * t)
    keep = minmax_indices(t, [v], buckets)
    assert keep[0] == 0 and keep[-1] == t.size - 1
    assert np.isclose(v[keep].max(), v.max()) and np.isclose(v[keep].min(), v.min())
