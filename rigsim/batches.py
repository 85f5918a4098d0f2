"""What a simulated stand produces: the run to open, its batches in stand order, its truth."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigsim.errors import SettingsError
from schemas.runs import RunCreate

FloatArray = NDArray[np.float64]
Truth = TypeVar("Truth")


@dataclass(frozen=True, slots=True)
class Batch:
    """One batch of readings of one channel group, as the lab PC would post it.

    Attributes
    ----------
    group : str
        Channel group, e.g. ``"friction"``.
    columns : Mapping[str, ndarray]
        Channel name -> values, in the channel's declared unit.
    at : float
        Stand time at which the batch is complete and would be sent, s from the start.
    """

    group: str
    columns: Mapping[str, FloatArray]
    at: float

    @property
    def rows(self) -> int:
        return max((len(v) for v in self.columns.values()), default=0)

    def as_json(self) -> dict[str, list[float]]:
        """The columns as JSON lists."""
        return {name: values.tolist() for name, values in self.columns.items()}


@dataclass(frozen=True, slots=True)
class SimulatedRun(Generic[Truth]):
    """A simulated run: the body that opens it, its batches in order, and the truth.

    Attributes
    ----------
    run_create : RunCreate
        The body of ``POST /runs``.
    batches : tuple of Batch
        In the order and at the times the stand produces them; the client numbers them
        0, 1, 2, ... as sequence numbers.
    truth : Truth
        The simulated stand's true values (a frozen dataclass per stand).
    """

    run_create: RunCreate
    batches: tuple[Batch, ...]
    truth: Truth

    @property
    def duration(self) -> float:
        """Stand time of the last batch, s."""
        return max((b.at for b in self.batches), default=0.0)

    def rows(self, group: str) -> int:
        """Rows of ``group`` over all batches."""
        return sum(b.rows for b in self.batches if b.group == group)

    def columns(self, group: str) -> dict[str, FloatArray]:
        """All batches of ``group`` joined, channel by channel."""
        parts = [b.columns for b in self.batches if b.group == group]
        names = list(dict.fromkeys(name for p in parts for name in p))
        return {n: np.concatenate([np.asarray(p[n]) for p in parts if n in p]) for n in names}


def split(group: str, columns: Mapping[str, ArrayLike], at: ArrayLike, rows: int) -> list[Batch]:
    """Cut aligned columns into batches of at most ``rows`` rows.

    ``at`` is the stand time of every row, s; a batch is sent when its last row is taken.
    """
    arrays = {k: np.asarray(v, dtype=np.float64) for k, v in columns.items()}
    times = np.asarray(at, dtype=np.float64)
    if rows < 1:
        raise SettingsError(f"rows must be >= 1, got {rows}")
    out = []
    for start in range(0, times.size, rows):
        stop = min(start + rows, times.size)
        out.append(
            Batch(
                group=group,
                columns={k: v[start:stop].copy() for k, v in arrays.items()},
                at=float(times[stop - 1]),
            )
        )
    return out
