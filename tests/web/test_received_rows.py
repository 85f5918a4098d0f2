"""The rows received as the run page shows them (:func:`rigserver.web.entry.received`): as
corrected, the value as typed and the reasons kept, struck rows marked; a one-row group's
latest values taken from rows not struck out, each cell with the row that holds it."""

from __future__ import annotations

from datetime import UTC, datetime

import numpy as np

from rigserver.web.entry import Cell, ReceivedRow, received
from schemas.corrections import Correction
from schemas.stands import SLIDE_BEARING_GROUPS

ROWS, MEASUREMENTS = SLIDE_BEARING_GROUPS
AT = datetime(2026, 11, 28, 10, 0, tzinfo=UTC)
NAN = float("nan")


def fix(
    n: int, group: str, row: int, channel: str | None, now: float | None, reason: str
) -> Correction:
    return Correction(
        n=n, group=group, row=row, channel=channel, now=now, reason=reason, by="PC", at=AT
    )


def test_a_window_of_rows_reads_as_corrected_with_the_typed_values_kept() -> None:
    # rows 10..12 of the group as stored: every channel 1.0, 2.0, 3.0 down the rows
    typed = {c.name: np.array([1.0, 2.0, 3.0]) for c in ROWS.channels}
    fixes = [
        fix(1, "rows", 11, "p3", 2.5, "misread"),
        fix(2, "measurements", 11, "x_zero", 9.0, "another group"),
        fix(3, "rows", 11, "p3", 2.25, "read again"),
        fix(4, "rows", 12, None, None, "typed twice"),
        fix(5, "rows", 2, "p3", 7.0, "a row before the window"),
    ]
    shown = received(ROWS, typed, 10, fixes)
    assert [r.index for r in shown] == [10, 11, 12]
    assert [r.struck for r in shown] == ["", "", "typed twice"]
    assert shown[0].cells[3] == Cell(1.0, 1.0, 10)
    assert shown[1].cells[3] == Cell(2.25, 2.0, 11, ("misread", "read again"))
    assert shown[1].cells[4] == Cell(2.0, 2.0, 11)  # p4: untouched
    assert shown[2].cells[3] == Cell(3.0, 3.0, 12)  # struck, its values as they read


def test_a_one_row_group_shows_the_latest_of_each_from_rows_not_struck() -> None:
    # row 0: load_zone_end and x_zero; row 1: x_zero again and y_zero; loader_scale never
    typed = {
        "load_zone_end": np.array([142.0, NAN]),
        "x_zero": np.array([400.0, 401.0]),
        "y_zero": np.array([NAN, 380.0]),
        "loader_scale": np.array([NAN, NAN]),
    }
    assert received(MEASUREMENTS, typed, 0, []) == [
        ReceivedRow(
            (
                Cell(142.0, 142.0, 0),
                Cell(401.0, 401.0, 1),
                Cell(380.0, 380.0, 1),
                Cell(None, None, -1),
            ),
            None,
        )
    ]
    fixes = [
        fix(1, "measurements", 1, None, None, "wrong dial"),
        fix(2, "measurements", 0, "x_zero", 399.5, "misread"),
    ]
    (row,) = received(MEASUREMENTS, typed, 0, fixes)
    assert row.cells[1] == Cell(399.5, 400.0, 0, ("misread",))  # row 1 struck: row 0's
    assert row.cells[2] == Cell(None, None, -1)  # y_zero held by the struck row only
    everything = [
        fix(1, "measurements", 0, None, None, "a"),
        fix(2, "measurements", 1, None, None, "b"),
    ]
    assert received(MEASUREMENTS, typed, 0, everything) == []
