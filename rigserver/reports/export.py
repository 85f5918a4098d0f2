"""A run's readings and results as CSV, and all of them in one zip archive.

The readings keep every row and full precision (``repr`` of the stored float64); an
aligned channel group is one CSV (one column per channel, headed ``name [unit]``); the
single measurements are named single values (``channel, quantity, value, unit``, the latest
value of each). The results CSV holds the single results, one row per quantity with its
label and its value in the display unit (:mod:`schemas.labels`); each per-row table (the
MTOS steps, tables 3.1-3.3, the bearing curve) is a CSV of its own; plot series stay in
``results.json``. The ``excel-ru`` dialect writes what a Russian Excel opens as it is:
``;`` between fields, a decimal comma, a UTF-8 byte-order mark.
"""

from __future__ import annotations

import csv
import io
import json
import time
import zipfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import IO, Any, Literal

from rigserver.analysis import Readings
from rigserver.reports import results_view
from rigserver.reports.i18n import Messages
from schemas import labelled
from schemas.channels import ChannelGroup
from schemas.labels import Label, plain_symbol
from schemas.runs import Run
from schemas.stands import Stand

Dialect = Literal["csv", "excel-ru"]


@dataclass(frozen=True, slots=True)
class CsvDialect:
    """How a CSV is written: the field separator, the decimal sign, a byte-order mark."""

    delimiter: str
    decimal: str
    bom: bool

    def number(self, value: float | int) -> str:
        return repr(value).replace(".", self.decimal)

    def text(self, rows: Iterator[Sequence[Any]] | list[Sequence[Any]]) -> str:
        out = io.StringIO()
        writer = csv.writer(out, delimiter=self.delimiter)
        for row in rows:
            writer.writerow(
                [
                    self.number(c) if isinstance(c, float | int) and not isinstance(c, bool) else c
                    for c in row
                ]
            )
        return ("\ufeff" if self.bom else "") + out.getvalue()


DIALECTS: dict[str, CsvDialect] = {
    "csv": CsvDialect(",", ".", bom=False),
    "excel-ru": CsvDialect(";", ",", bom=True),
}

CHUNK_ROWS = 65_536


def group_csv(readings: Readings, group: ChannelGroup) -> Iterator[str]:
    """The CSV of one channel group, in pieces of at most ``CHUNK_ROWS`` rows."""
    out = io.StringIO()
    writer = csv.writer(out)
    if not group.aligned:  # named single values: the latest of each channel posted
        writer.writerow(["channel", "quantity", "value", "unit"])
        latest = readings.measurements()
        writer.writerows(
            (c.name, c.long_name, repr(latest[c.name]), c.unit)
            for c in group.channels
            if c.name in latest
        )
        yield out.getvalue()
        return
    names = [c.name for c in group.channels]
    writer.writerow([f"{c.name} [{c.unit}]" for c in group.channels])
    if readings.rows(group.name):
        for chunk in readings.iter_chunks(group.name, names, rows=CHUNK_ROWS):
            writer.writerows(zip(*(chunk[n].tolist() for n in names), strict=True))
            yield out.getvalue()
            out.seek(0)
            out.truncate()
    yield out.getvalue()


def _shown(label: Label, value: Any, stored: str, t: Messages) -> Any:
    if value is None:
        return ""
    if isinstance(value, bool):
        return t("yes") if value else t("no")
    if isinstance(value, str):
        return t.gettext(value)
    return label.shown(value, stored)


def _unit(t: Messages, label: Label) -> str:
    return "" if label.unit == "1" else t.unit(label.unit)


def results_csv(
    payload: Mapping[str, Any], *, stand: Stand, t: Messages, dialect: CsvDialect
) -> str:
    """The single results: ``quantity, symbol, value, unit, path``, in the display units
    and the declared digits, in the declared order; no plot series, no per-row tables."""
    head = [t("col.quantity"), t("col.symbol"), t("col.value"), t("col.unit"), "path"]
    rows: list[Sequence[Any]] = [head]
    for e in labelled.scalars(stand.kind, payload):
        rows.append(
            [
                plain_symbol(results_view.name(t, e.label)),
                plain_symbol(t.symbol(e.label.symbol)),
                _shown(e.label, e.value, e.stored, t),
                _unit(t, e.label),
                e.path,
            ]
        )
    return dialect.text(rows)


def table_csvs(
    payload: Mapping[str, Any], *, stand: Stand, t: Messages, dialect: CsvDialect
) -> dict[str, str]:
    """Each per-row table of the results as a CSV of its own, by the table's name; a column
    is headed by its label, symbol and display unit."""
    found = {}
    for rows_of in labelled.row_tables(stand.kind, payload):
        head = []
        for c in rows_of.columns:
            unit = _unit(t, c.label)
            words = plain_symbol(results_view.name(t, c.label))
            name = f"{words}, {plain_symbol(t.symbol(c.symbol))}" if c.symbol else words
            head.append(f"{name} [{unit}]" if unit else name)
        body = [
            [
                _shown(c.label, cell, c.stored, t)
                for c, cell in zip(rows_of.columns, row, strict=True)
            ]
            for row in rows_of.rows
        ]
        found[rows_of.table.name] = dialect.text([head, *body])
    return found


def export_members(
    *,
    run: Run,
    stand: Stand,
    readings: Readings,
    payload: Mapping[str, Any],
    t: Messages,
    dialect: CsvDialect,
) -> Iterator[tuple[str, Iterable[bytes]]]:
    """The members of the run's export, each as its name and its content in pieces:
    ``run.json``, ``results.json`` (everything, SI), ``results.csv`` (the single results),
    a CSV per per-row table of the results (``results_<table>.csv``) and a CSV per channel
    group (streamed, a few thousand rows at a time)."""
    yield "run.json", [run.model_dump_json(indent=1).encode()]
    yield "results.json", [json.dumps(payload, indent=1).encode()]
    yield "results.csv", [results_csv(payload, stand=stand, t=t, dialect=dialect).encode()]
    for name, text in table_csvs(payload, stand=stand, t=t, dialect=dialect).items():
        yield f"results_{name}.csv", [text.encode()]
    for group in stand.groups:
        yield f"{group.name}.csv", (piece.encode() for piece in group_csv(readings, group))


def export_zip(
    target: IO[bytes], folder: str, members: Iterable[tuple[str, Iterable[bytes]]]
) -> None:
    """Write the run's archive into ``target``, under ``<folder>/`` (the run's id): the
    members of :func:`export_members`, entries dated now."""
    now = time.localtime()[:6]

    def entry(name: str) -> zipfile.ZipInfo:
        info = zipfile.ZipInfo(f"{folder}/{name}", date_time=now)
        info.compress_type = zipfile.ZIP_DEFLATED
        return info

    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, pieces in members:
            with archive.open(entry(name), "w") as member:
                for piece in pieces:
                    member.write(piece)
