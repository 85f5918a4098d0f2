"""``rigserver check``: which runs of a data directory are damaged, and how; read-only.

A run is damaged when its catalogue row holds what the service refuses today (a NaN that
an older build stored as null, a NUL character),
when its final file is missing, unreadable, or disagrees with the catalogue on its rows, or
when the journal lacks readings it lists for an open run. A run file that no catalogue row
names is reported too. Nothing is changed, and a running server may keep the directory.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from rigserver.storage._failures import UNREADABLE
from rigserver.storage.embedded.journal import CATALOGUE_COLUMNS, CatalogueEntry, catalogue_entry
from rigserver.storage.errors import RunDamaged
from rigserver.storage.runfile import read_summary


@dataclass(frozen=True, slots=True)
class Damage:
    """One damaged run: its id and what is wrong with it."""

    run_id: str
    what: str


@dataclass(frozen=True, slots=True)
class Report:
    """What :func:`check_data_dir` found: the runs looked at and the damaged ones."""

    runs: int
    damaged: list[Damage]


def check_data_dir(data_dir: Path) -> Report:
    """Look at every run of ``data_dir`` (see the module docstring); ``FileNotFoundError``
    if it is no data directory."""
    journal = data_dir / "journal.sqlite"
    if not journal.is_file():
        raise FileNotFoundError(f"{data_dir} holds no journal.sqlite: it is no data directory")
    db = sqlite3.connect(f"{journal.resolve().as_uri()}?mode=ro", uri=True)
    try:
        rows = db.execute(f"SELECT {CATALOGUE_COLUMNS} FROM runs ORDER BY created").fetchall()
        damaged = [d for row in rows for d in _row_damage(db, data_dir, row)]
    finally:
        db.close()
    known = {row[0] for row in rows}
    damaged += [
        Damage(path.stem, f"the run file {path.name} has no catalogue entry")
        for path in sorted((data_dir / "runs").glob("*.h5"))
        if path.stem not in known
    ]
    return Report(runs=len(rows), damaged=damaged)


def _row_damage(
    db: sqlite3.Connection, data_dir: Path, row: tuple[object, ...]
) -> Iterator[Damage]:
    run_id = str(row[0])
    try:
        entry = catalogue_entry(row)  # type: ignore[arg-type]
    except RunDamaged as exc:
        yield Damage(run_id, str(exc).removeprefix(f"run {run_id} is damaged: "))
        return
    if entry.file_final:
        yield from _file_damage(data_dir, entry)
    else:
        yield from _payload_damage(db, data_dir, run_id)


def _file_damage(data_dir: Path, entry: CatalogueEntry) -> Iterator[Damage]:
    run = entry.run
    path = data_dir / "runs" / f"{run.id}.h5"
    if not path.exists():
        yield Damage(run.id, f"its file {path.name} is missing")
        return
    try:
        summary = read_summary(path)
    except UNREADABLE as exc:
        yield Damage(run.id, f"its file {path.name} cannot be read ({exc})")
        return
    if summary.run.id != run.id:
        yield Damage(run.id, f"its file {path.name} holds run {summary.run.id}")
    elif not summary.finalized:
        yield Damage(run.id, f"its file {path.name} is not finalized")
    for group, rows in run.rows.items():
        held = summary.run.rows.get(group, 0)
        if held != rows:
            yield Damage(run.id, f"its file holds {held} rows of {group}, the catalogue {rows}")


def _payload_damage(db: sqlite3.Connection, data_dir: Path, run_id: str) -> Iterator[Damage]:
    """The readings of an unfinished run are in its payload file until the run ends."""
    (end,) = db.execute(
        "SELECT COALESCE(MAX(at + size), 0) FROM batches WHERE run_id = ? AND size > 0",
        (run_id,),
    ).fetchone()
    if not end:
        return
    payload = data_dir / "payloads" / f"{run_id}.bin"
    size = payload.stat().st_size if payload.exists() else None
    if size is None or size < end:
        held = "is missing" if size is None else f"holds {size} bytes"
        yield Damage(run_id, f"its readings file {payload.name} {held}; the journal lists {end}")
