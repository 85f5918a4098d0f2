"""Fewer points to draw, the same picture: min-max decimation of a long trace.

For drawing only; every number of a report is computed on all the readings.
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import ArrayLike, NDArray


def min_max(
    x: ArrayLike, y: ArrayLike, *, buckets: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Keep, in each of ``buckets`` runs of consecutive points, its lowest and highest point.

    At most ``2·buckets`` points remain, in their original order, so a polyline through
    them touches every peak and valley that the full trace reaches at the resolution of
    ``buckets`` columns. Traces of at most ``2·buckets`` points come back whole.

    Parameters
    ----------
    x, y : array_like
        The trace, as many ``x`` as ``y``.
    buckets : int
        Number of runs (about the drawing's width in pixels or points), >= 1.
    """
    xs = np.asarray(x, dtype=np.float64)
    ys = np.asarray(y, dtype=np.float64)
    if xs.shape != ys.shape or xs.ndim != 1:
        raise ValueError(f"x and y must be 1-D of one length, got {xs.shape} and {ys.shape}")
    if buckets < 1:
        raise ValueError(f"buckets must be >= 1, got {buckets}")
    n = ys.size
    if n <= 2 * buckets:
        return xs, ys
    edges = np.linspace(0, n, buckets + 1).astype(np.intp)
    keep: list[int] = []
    for start, stop in itertools.pairwise(edges):
        part = ys[start:stop]
        lo = start + int(np.argmin(part))
        hi = start + int(np.argmax(part))
        keep.extend(sorted({lo, hi}))
    index = np.asarray(keep, dtype=np.intp)
    return xs[index], ys[index]
