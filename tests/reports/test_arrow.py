"""The Arrow stream of a channel group (``format=arrow``): its stated size is its length,
its rows those the run held when asked, its values the store's (rigserver.reports.arrow)."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pyarrow as pa
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.reports import arrow
from rigserver.reports.arrow import group_arrow
from rigserver.storage._checks import channel_group
from schemas.stands import StandKind

FRICTION = channel_group(StandKind.SMTS2, "friction")
NAMES = [c.name for c in FRICTION.channels]


class Slices:
    """Readings of ``held`` rows that the store gives in slices of ``rows`` (at most the
    asked size, as a store of struck rows does), with ``stored`` rows there by the time the
    slices are read (rows posted while the answer goes out)."""

    def __init__(self, held: int, stored: int, cut: int | None = None) -> None:
        self.held, self.stored, self.cut = held, stored, cut

    def rows(self, group: str) -> int:
        return self.held

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, np.ndarray]:
        return {n: _column(n, 0, self.stored) for n in channels or NAMES}

    def measurements(self) -> dict[str, float]:
        return {}

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, np.ndarray]]:
        step = min(rows, self.cut or rows)
        for lo in range(0, self.stored, step):
            hi = min(lo + step, self.stored)
            yield {n: _column(n, lo, hi) for n in channels or NAMES}


def _column(name: str, lo: int, hi: int) -> np.ndarray:
    """Values that tell channel and row apart: row + channel's place / 10."""
    return np.arange(lo, hi, dtype=np.float64) + NAMES.index(name) / 10


def _read(stream: arrow.ArrowStream) -> tuple[bytes, pa.Table]:
    body = b"".join(bytes(p) for p in stream.pieces)
    return body, pa.ipc.open_stream(body).read_all()


@settings(max_examples=40, deadline=None)
@given(
    held=st.integers(0, 3000),
    later=st.integers(0, 500),
    cut=st.integers(1, 700),
    chunk=st.sampled_from([1, 7, 256, 1 << 20]),
)
def test_the_stated_size_is_the_length_and_the_rows_those_held(
    held: int, later: int, cut: int, chunk: int
) -> None:
    """Whatever the store's slicing and the rows arriving meanwhile, the stream is as long
    as it says and holds exactly the ``held`` rows, each channel's own values."""
    original = arrow.CHUNK_ROWS
    arrow.CHUNK_ROWS = chunk
    try:
        stream = group_arrow(Slices(held, held + later, cut), FRICTION)
        body, table = _read(stream)
    finally:
        arrow.CHUNK_ROWS = original
    assert stream.size == len(body)
    assert table.num_rows == held and table.column_names == NAMES
    for name in NAMES:
        np.testing.assert_array_equal(table[name].to_numpy(), _column(name, 0, held))


def test_a_column_is_one_piece_of_memory() -> None:
    """One record batch: each column reaches pandas without a copy into one block."""
    _, table = _read(group_arrow(Slices(5000, 5000, 300), FRICTION))
    assert {table[n].num_chunks for n in NAMES} == {1}


def test_rows_gone_before_they_are_sent_break_the_answer_off() -> None:
    """Fewer rows than stated: the answer breaks off, it is not padded or cut short."""
    with pytest.raises(RuntimeError, match="were not there"):
        _read(group_arrow(Slices(100, 60), FRICTION))


def test_the_fields_carry_units() -> None:
    _, table = _read(group_arrow(Slices(3, 3), FRICTION))
    units = {f.name: (f.metadata or {})[b"unit"].decode() for f in table.schema}
    assert units == {c.name: c.unit for c in FRICTION.channels}
