"""A run's readings and results as CSV, and all of them in one zip archive.

The readings keep every row and full precision (``repr`` of the stored float64); a
channel group is one CSV (aligned groups: one column per channel, headed ``name [unit]``;
the single measurements: ``channel, unit, value`` rows). The results are one row per
quantity: its path in the results (``table[3].chi``), its value and its unit.
"""

from __future__ import annotations

import csv
import io
import json
import zipfile
from collections.abc import Iterator, Mapping
from typing import IO, Any

from rigserver.analysis import Readings
from schemas.channels import ChannelGroup
from schemas.runs import Run
from schemas.stands import Stand

CHUNK_ROWS = 65_536


def group_csv(readings: Readings, group: ChannelGroup) -> Iterator[str]:
    """The CSV of one channel group, in pieces of at most ``CHUNK_ROWS`` rows."""
    out = io.StringIO()
    writer = csv.writer(out)
    if not group.aligned:
        writer.writerow(["channel", "unit", "value"])
        units = {c.name: c.unit for c in group.channels}
        for name, values in readings.read(group.name).items():
            writer.writerows((name, units[name], v) for v in values.tolist())
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


def result_rows(payload: Mapping[str, Any]) -> Iterator[tuple[str, Any, str]]:
    """``(path, value, unit)`` of every number, flag and word in a results payload.

    Lists are expanded with their index (``steps[2].chi``); the unit is looked up under the
    path without indices (``steps[].chi``), as the payload's ``units`` names it.
    """
    units: Mapping[str, str] = payload.get("units", {})

    def walk(node: Any, path: str, unit_path: str) -> Iterator[tuple[str, Any, str]]:
        if isinstance(node, dict):
            for key, value in node.items():
                sep = "." if path else ""
                yield from walk(value, f"{path}{sep}{key}", f"{unit_path}{sep}{key}")
        elif isinstance(node, list):
            for index, value in enumerate(node):
                yield from walk(value, f"{path}[{index}]", f"{unit_path}[]")
        else:
            unit = units.get(unit_path) or units.get(unit_path.removesuffix("[]")) or ""
            if not unit and "." in unit_path:  # a dict of quantities: temperature_rise.t2
                unit = units.get(unit_path.rsplit(".", 1)[0], "")
            yield path, node, unit

    yield from walk(payload.get("values", {}), "", "")


def results_csv(payload: Mapping[str, Any]) -> str:
    out = io.StringIO()
    writer = csv.writer(out)
    writer.writerow(["quantity", "value", "unit"])
    writer.writerows(
        (path, "" if value is None else value, unit) for path, value, unit in result_rows(payload)
    )
    return out.getvalue()


def export_zip(
    target: IO[bytes],
    *,
    run: Run,
    stand: Stand,
    readings: Readings,
    payload: Mapping[str, Any],
) -> None:
    """Write the run's archive into ``target``: ``run.json``, ``results.json``,
    ``results.csv`` and ``<group>.csv`` for every channel group, under ``<run id>/``."""
    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        folder = run.id
        archive.writestr(f"{folder}/run.json", run.model_dump_json(indent=1))
        archive.writestr(f"{folder}/results.json", json.dumps(payload, indent=1))
        archive.writestr(f"{folder}/results.csv", results_csv(payload))
        for group in stand.groups:
            with archive.open(f"{folder}/{group.name}.csv", "w") as member:
                for piece in group_csv(readings, group):
                    member.write(piece.encode())
