"""A run's profile as an X3P file (ISO 25178-72, the profile form of ISO 5436-2), which
MountainsMap, Gwyddion, surfalize and the instruments' own software open.

The heights in metres on an incremental x axis (the trace's sampling step); a trace not
uniformly sampled is interpolated linearly onto its median step, and the file's comment says
so. A trace whose grid at its median step would hold more than ``RESAMPLING_LIMIT`` times its
points (a large gap) is written as the points received instead, an X3P point cloud, so that
the file's size follows what was received. The record names the operator, the instrument and
the run.
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np
import x3pio

from rigserver.analysis import Readings
from rigserver.core.profile_filter import RESAMPLING_LIMIT, on_grid, resampling_size, uniform_step
from schemas.channels import ChannelGroup
from schemas.runs import Run
from schemas.units import UNITS

#: The group a profile is traced into by default (the profilometer's).
PROFILE_GROUP = "profile"


class NoProfile(LookupError):
    """The run's stand has no profile group (channels x and y), or nothing was traced yet."""


def profile_group(groups: tuple[ChannelGroup, ...] | list[ChannelGroup], name: str) -> ChannelGroup:
    """The aligned group ``name`` with channels x and y in lengths, else :class:`NoProfile`."""
    for group in groups:
        if group.name != name:
            continue
        units = {c.name: c.unit for c in group.channels}
        lengths = {"x", "y"} <= set(units) and all(UNITS[units[c]].si == "m" for c in "xy")
        if group.aligned and lengths:
            return group
        break
    raise NoProfile(f"the stand has no profile group {name!r} with channels x and y in lengths")


def _metadata(run: Run, comment: str) -> x3pio.Metadata:
    instrument: Any = run.configuration.get("instrument", "")
    return x3pio.Metadata(
        creator=run.operator,
        instrument=x3pio.Instrument(model=str(instrument), version="rig"),
        comment=f"{comment}; {run.title}" if run.title else comment,
    )


def profile_x3p(run: Run, group: ChannelGroup, readings: Readings) -> bytes:
    """The traced profile of ``group`` as the bytes of an X3P file."""
    if readings.rows(group.name) < 2:
        raise NoProfile(f"run {run.id} has fewer than two points in {group.name!r}")
    trace = readings.read(group.name, ["x", "y"])
    units = {c.name: c.unit for c in group.channels}
    x = np.asarray(trace["x"], dtype=np.float64) * UNITS[units["x"]].factor
    z = np.asarray(trace["y"], dtype=np.float64) * UNITS[units["y"]].factor
    comment = f"rig run {run.id}, group {group.name}; x from {x[0]:.9g} m"
    out = io.BytesIO()
    step = uniform_step(x)
    if step is None and resampling_size(x) > RESAMPLING_LIMIT * x.size:
        comment += (
            f"; not uniformly sampled, with a gap: its grid at the median step would hold more "
            f"than {RESAMPLING_LIMIT} times its {x.size} points, so the points as received"
        )
        points = np.column_stack([x, np.zeros_like(x), z])
        x3pio.write_points(out, points, metadata=_metadata(run, comment))
        return out.getvalue()
    if step is None:
        step = float(np.median(np.diff(x)))
        _, z = on_grid(x, z, step)
        comment += f"; not uniformly sampled, interpolated linearly onto a step of {step:.6g} m"
    x3pio.write(out, z, x_scale=step, metadata=_metadata(run, comment))
    return out.getvalue()
