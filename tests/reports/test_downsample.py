"""Min-max decimation: fewer points, every bucket's extremes kept, in order."""

from __future__ import annotations

import numpy as np
import pytest

from rigserver.reports.downsample import min_max


def test_each_bucket_keeps_its_lowest_and_highest_point() -> None:
    rng = np.random.default_rng(3)
    x = np.arange(10_000, dtype=float)
    y = np.cumsum(rng.normal(size=x.size))
    shown_x, shown_y = min_max(x, y, buckets=100)
    assert shown_x.size <= 200
    assert np.all(np.diff(shown_x) > 0)  # original order
    # 100 equal buckets of 100 points: the extremes computed directly
    blocks = y.reshape(100, 100)
    assert set(blocks.max(axis=1)) <= set(shown_y)
    assert set(blocks.min(axis=1)) <= set(shown_y)
    assert shown_y.max() == y.max() and shown_y.min() == y.min()


def test_a_short_trace_is_kept_whole() -> None:
    x, y = np.arange(5.0), np.array([1.0, 3.0, 2.0, 5.0, 4.0])
    shown_x, shown_y = min_max(x, y, buckets=3)
    assert shown_x.tolist() == x.tolist() and shown_y.tolist() == y.tolist()


def test_mismatched_input_is_refused() -> None:
    with pytest.raises(ValueError, match="x and y must be 1-D of one length"):
        min_max(np.arange(3.0), np.arange(4.0), buckets=2)
