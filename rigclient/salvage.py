"""``rigclient salvage``: a spool SQLite cannot read, saved as far as it can be read.

The rows SQLite still reads (the runs' openings, the batches not yet delivered, the file
cursors, the refused lines, the header lines) are copied into a new spool, table by table
and row by row in the order of their rowids, stepping past the parts that cannot be read;
the damaged file is then moved aside as ``spool.sqlite.damaged-<UTC time>`` (with its
``-wal`` and ``-shm``), the rest of what it held kept there, and the new spool takes its
place. The sender checks every saved batch against its checksum before it sends it.
"""

from __future__ import annotations

import shutil
import sqlite3
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from rigclient.errors import SpoolError
from rigclient.lock import SpoolLock
from rigclient.spool import FILENAME, Spool

#: The tables saved, in order (a batch needs its run).
TABLES = ("runs", "batches", "sources", "rejects", "headers")
_PROBES = 64  # rowids tried past a part that cannot be read, doubling the step


@dataclass
class Salvaged:
    """What was saved (rows per table) and what was not (parts per table), and where the
    damaged file is kept."""

    saved: dict[str, int] = field(default_factory=dict)
    lost: dict[str, int] = field(default_factory=dict)
    kept: Path | None = None

    def describe(self) -> str:
        saved = ", ".join(f"{n} {t}" for t, n in self.saved.items() if n) or "nothing"
        lost = ", ".join(f"{t} ({n} part{'s' if n > 1 else ''})" for t, n in self.lost.items())
        text = f"saved {saved}"
        if lost:
            text += f"; unreadable, kept in {self.kept}: {lost}"
        else:
            text += f"; the damaged file is kept as {self.kept}"
        return text


def _rows(
    db: sqlite3.Connection, table: str, columns: list[str], lost: dict[str, int]
) -> Iterator[tuple[Any, ...]]:
    """The rows of ``table`` that SQLite still reads, by rowid; each part it cannot read
    counted in ``lost``."""
    names = ", ".join(columns)
    last = -(2**63)
    while True:
        try:
            for row in db.execute(
                f"SELECT rowid, {names} FROM {table} WHERE rowid > ? ORDER BY rowid", (last,)
            ):
                last = row[0]
                yield row[1:]
            return
        except (sqlite3.Error, UnicodeDecodeError, OverflowError):
            lost[table] = lost.get(table, 0) + 1
        step, found = 1, None
        for _ in range(_PROBES):  # the next rowid that reads
            try:
                first = db.execute(
                    f"SELECT rowid FROM {table} WHERE rowid > ? ORDER BY rowid LIMIT 1",
                    (min(last + step, 2**63 - 1),),
                ).fetchone()
            except (sqlite3.Error, UnicodeDecodeError, OverflowError):
                step *= 2
                continue
            found = first
            break
        if found is None:
            return
        try:  # the row found reads whole, or it is skipped
            row = db.execute(
                f"SELECT rowid, {names} FROM {table} WHERE rowid = ?", (found[0],)
            ).fetchone()
        except (sqlite3.Error, UnicodeDecodeError, OverflowError):
            lost[table] = lost.get(table, 0) + 1
            last = found[0]
            continue
        last = found[0] - 1 if row is not None else found[0]


def salvage(directory: Path) -> Salvaged:
    """Save what the spool in ``directory`` still holds (see the module's docstring)."""
    path = directory / FILENAME
    if not path.exists():
        raise SpoolError(f"no spool in {directory} (no {FILENAME})")
    out = Salvaged()
    with SpoolLock(directory), tempfile.TemporaryDirectory(dir=directory) as tmp:
        with Spool(tmp):
            pass  # the new spool's tables
        new = sqlite3.connect(Path(tmp) / FILENAME, isolation_level=None)
        try:
            old = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
            old.text_factory = lambda b: b.decode("utf-8")  # not UTF-8: unreadable
        except sqlite3.Error:
            old = None
        try:
            new.execute("BEGIN")
            for table in TABLES:
                columns = [r[1] for r in new.execute(f"PRAGMA table_info({table})")]
                marks = ", ".join("?" * len(columns))
                count = 0
                if old is None:
                    out.lost[table] = 1
                    continue
                for row in _rows(old, table, columns, out.lost):
                    try:
                        new.execute(f"INSERT OR IGNORE INTO {table} VALUES ({marks})", row)
                    except sqlite3.Error:
                        out.lost[table] = out.lost.get(table, 0) + 1
                        continue
                    count += 1
                out.saved[table] = count
            orphans = new.execute(
                "DELETE FROM batches WHERE local_id NOT IN (SELECT local_id FROM runs)"
            ).rowcount  # a batch without its run's opening cannot be sent: kept aside
            if orphans:
                out.saved["batches"] -= orphans
                out.lost["batches of runs not saved"] = orphans
            new.execute("COMMIT")
            new.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        finally:
            new.close()
            if old is not None:
                old.close()
        stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
        out.kept = path.with_name(f"{FILENAME}.damaged-{stamp}")
        for suffix in ("", "-wal", "-shm"):
            part = Path(f"{path}{suffix}")
            if part.exists():
                part.rename(Path(f"{out.kept}{suffix}"))
        shutil.move(str(Path(tmp) / FILENAME), str(path))
    return out
