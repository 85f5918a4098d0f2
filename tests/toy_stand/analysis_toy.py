"""The toy stand's pipeline (copied as ``rigserver/analysis/toy.py``): the spring's
stiffness as the least-squares slope of F against x."""

from __future__ import annotations

import numpy as np

from rigserver.analysis.readings import Readings
from schemas.runs import Run
from schemas.toy import ToyResults

_M_PER_MM = 1e-3


def analyse(run: Run, readings: Readings) -> ToyResults:
    rows = readings.rows("stretch")
    if rows < 2:
        return ToyResults(rows=rows, pending=["two rows of the stretch are needed"])
    found = readings.read("stretch", ["extension", "force"])
    slope, intercept = np.polyfit(found["extension"] * _M_PER_MM, found["force"], 1)
    return ToyResults(rows=rows, stiffness=float(slope), preload=float(intercept))
