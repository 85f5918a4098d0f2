"""What an analysis reads: one run's readings, group by group, in slices."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

Columns = dict[str, NDArray[np.float64]]


class Readings(Protocol):
    def rows(self, group: str) -> int:
        """Rows stored in an aligned group."""
        ...

    def read(self, group: str, channels: list[str] | None = None) -> Columns:
        """A whole (small) group: the rows of table 3.1, the MTOS steps, a profile."""
        ...

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[Columns]:
        """A long group in consecutive slices, so a whole run is never held in memory."""
        ...

    def measurements(self) -> dict[str, float]:
        """The latest value of each single measurement posted (masses, zero readings)."""
        ...
