"""A profilometer's trace from a file: CSV/TXT (x, y), X3P (ISO 5436-2, ISO 25178-72) or SDF
(ISO 25178-71), as the profilometer's ``profile`` group (x in mm, y in µm).

X3P and SDF are read by ``x3pio`` and ``sdfio`` (maintained readers of the two ISO formats,
MIT, numpy only); both give metres. Of an areal file (a surface) one row is taken
(``row``). Points not measured (NaN) are left out. A CSV/TXT file has a header naming the
columns (with units, or through the map) or none: then its first two columns are x in mm
and y in µm.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import sdfio
import x3pio
from numpy.typing import ArrayLike, NDArray

from rigclient.errors import InputError
from rigclient.mapping import StandMap
from rigclient.table import Table, sniff
from schemas.labels import PROFILOMETER
from schemas.stands import StandKind, default_stands
from schemas.units import UNITS

GROUP = "profile"
_MM = UNITS["mm"].factor
_UM = UNITS["um"].factor


@dataclass(frozen=True, slots=True)
class Trace:
    """A profile: x along the trace in mm, y heights in µm, and where it came from."""

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    source: str
    skipped: int = 0  # points not measured, left out

    def columns(self) -> dict[str, NDArray[np.float64]]:
        return {"x": self.x, "y": self.y}


def read_profile(path: Path, *, mapping: StandMap | None = None, row: int = 0) -> Trace:
    """The trace in ``path``, by its suffix: ``.x3p``, ``.sdf``, else CSV/TXT."""
    suffix = path.suffix.lower()
    if suffix == ".x3p":
        x, y = _x3p(path, row)
    elif suffix == ".sdf":
        x, y = _sdf(path, row)
    else:
        return _text(path, mapping)
    return _measured(x / _MM, y / _UM, str(path))


def _measured(x: NDArray[np.float64], y: NDArray[np.float64], source: str) -> Trace:
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() < 2:
        raise InputError("fewer than two measured points", file=source)
    return Trace(x[keep], y[keep], source, int((~keep).sum()))


def _pick(values: ArrayLike, row: int, source: str) -> NDArray[np.float64]:
    """Row ``row`` of a profile (one row) or an areal grid."""
    z = np.asarray(values, dtype=np.float64)
    z = z.reshape(-1, z.shape[-1])
    if not 0 <= row < z.shape[0]:
        raise InputError(f"row {row} asked, the file has rows 0 to {z.shape[0] - 1}", file=source)
    picked: NDArray[np.float64] = z[row]
    return picked


def _x3p(path: Path, row: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    try:
        found = x3pio.read(path)
    except (x3pio.X3pError, OSError) as exc:
        raise InputError(f"not a readable X3P file: {exc}", file=str(path)) from None
    if isinstance(found, x3pio.PointCloud):
        raise InputError("an X3P point cloud is not a profile", file=str(path))
    layer = found.layers[0]
    z = _pick(layer.z, row, str(path))
    if layer.header.x.is_incremental:
        x = np.arange(z.size, dtype=np.float64) * layer.header.x.increment
    else:
        assert layer.x is not None  # an absolute x axis has its coordinates
        x = _pick(layer.x, row, str(path))
    return x, z


def _sdf(path: Path, row: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    try:
        found = sdfio.read(path)
    except (sdfio.SdfError, OSError) as exc:
        raise InputError(f"not a readable SDF file: {exc}", file=str(path)) from None
    z = _pick(found.data, row, str(path))
    return np.asarray(found.x_axis, dtype=np.float64), z


def _text(path: Path, mapping: StandMap | None) -> Trace:
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the profile: {exc}", file=str(path)) from None
    numbered = [
        (n, s)
        for n, s in enumerate(text.splitlines(), start=1)
        if s.strip() and not s.lstrip().startswith("#")
    ]
    if not numbered:
        raise InputError("no lines", file=str(path))
    first = numbered[0][1]
    if "," not in first and ";" not in first and "\t" not in first:  # separated by blanks
        numbered = [(n, "\t".join(s.split())) for n, s in numbered]
        first = numbered[0][1]
    delimiter = sniff(first)
    if any(ch.isalpha() for ch in first):
        header, data = first, numbered[1:]
    else:  # no header: x in mm, y in µm
        header, data = delimiter.join(("x", "y")), numbered
    group = default_stands()[StandKind.PROFILOMETER].group(GROUP)
    assert group is not None
    table = Table.from_header(header, file=str(path), group=group, mapping=mapping)
    columns = table.columns([table.parse(s, n) for n, s in data])
    return _measured(columns["x"], columns["y"], str(path))


_FLAT = str.maketrans("", "", "_{}")

#: The roughness printed after a profile is posted: the manual's, then the ISO 21920-2 one.
MANUAL_SHOWN = ("ra", "rq", "rz", "rmax", "sm")
ISO_SHOWN = ("ra", "rq", "rz", "rt", "rsm", "rsk", "rku", "rk", "rpk", "rvk")


def roughness_lines(payload: Mapping[str, Any]) -> list[str]:
    """The manual's roughness and the ISO 21920-2 one (with its filter's settings) of a
    profilometer run's results, a line each, in the display units of their labels."""
    values: Mapping[str, Any] = payload.get("values", {})
    units: Mapping[str, str] = payload.get("units", {})

    def item(path: str) -> str | None:
        node: Any = values
        for part in path.split("."):
            node = node.get(part) if isinstance(node, Mapping) else None
        if not isinstance(node, int | float) or isinstance(node, bool):
            return None
        label = PROFILOMETER[path]
        unit = "" if label.unit == "1" else " " + UNITS[label.unit].symbol.replace("um", "µm")
        number = label.shown(float(node), units.get(path, label.unit))
        symbol = label.symbol.replace("^{ISO}", "").translate(
            _FLAT
        )  # as profilometers print them: Ra, RSm, λc
        return f"{symbol} = {number:.{label.digits}g}{unit}"

    lines = []
    manual = [found for path in MANUAL_SHOWN if (found := item(path))]
    if manual:
        lines.append("manual (lab work 1): " + ", ".join(manual))
    iso = values.get("iso")
    if isinstance(iso, Mapping):
        settings = [found for path in ("iso.lambda_c", "iso.lambda_s") if (found := item(path))]
        settings += [str(iso.get("lambda_c_source", "")), str(iso.get("ends", ""))]
        shown = [found for name in ISO_SHOWN if (found := item("iso." + name))]
        lines.append(f"ISO 21920-2 ({'; '.join(settings)}): " + ", ".join(shown))
    return lines
