"""Statistics gathered slice by slice over a long record."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from schemas.results import Series


class BlockSeries:
    """Reduce a record of known length to ``blocks`` block means (with min and max).

    Slices are fed in order with :meth:`add`; memory is O(blocks) whatever the length.
    """

    def __init__(self, total_rows: int, blocks: int = 1000) -> None:
        self.total = total_rows
        self.n = max(1, min(blocks, total_rows))
        self._x = np.zeros(self.n)
        self._y = np.zeros(self.n)
        self._count = np.zeros(self.n)
        self._lo = np.full(self.n, np.inf)
        self._hi = np.full(self.n, -np.inf)
        self._seen = 0

    def add(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> None:
        index = (np.arange(self._seen, self._seen + y.size) * self.n) // max(self.total, 1)
        index = np.minimum(index, self.n - 1)
        self._seen += y.size
        np.add.at(self._x, index, x)
        np.add.at(self._y, index, y)
        np.add.at(self._count, index, 1.0)
        np.minimum.at(self._lo, index, y)
        np.maximum.at(self._hi, index, y)

    def series(self, x_name: str, y_name: str) -> Series:
        filled = self._count > 0
        c = self._count[filled]
        return Series(
            x_name=x_name,
            y_name=y_name,
            x=(self._x[filled] / c).tolist(),
            y=(self._y[filled] / c).tolist(),
            y_min=self._lo[filled].tolist(),
            y_max=self._hi[filled].tolist(),
        )


class TailMoments:
    """Mean and standard deviation of the rows from ``start`` on, fed slice by slice."""

    def __init__(self, start: int) -> None:
        self.start = start
        self._seen = 0
        self._n = 0
        self._sum = 0.0
        self._sq = 0.0
        self._shift: float | None = None

    def add(self, values: NDArray[np.float64]) -> None:
        skip = max(0, self.start - self._seen)
        self._seen += values.size
        tail = values[skip:]
        if tail.size == 0:
            return
        if self._shift is None:
            self._shift = float(tail[0])
        d = tail - self._shift
        self._n += tail.size
        self._sum += float(d.sum())
        self._sq += float((d * d).sum())

    @property
    def count(self) -> int:
        return self._n

    @property
    def mean(self) -> float:
        return (self._shift or 0.0) + self._sum / self._n if self._n else float("nan")

    @property
    def std(self) -> float:
        if not self._n:
            return float("nan")
        m = self._sum / self._n
        return float(np.sqrt(max(self._sq / self._n - m * m, 0.0)))
