"""The toy stand's simulator (copied as ``rigsim/simulators/toy.py``): a linear spring
F = F_0 + k·x stretched at a constant rate."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rigsim.batches import SimulatedRun, split
from rigsim.instruments import Fault, Instrument, apply_faults
from schemas.runs import RunCreate
from schemas.stands import StandKind
from schemas.toy import GROUPS, ToyConfig

_LOAD_CELL = Instrument(resolution=0.01, noise=0.02)


@dataclass(frozen=True, slots=True)
class ToyInstruments:
    load_cell: Instrument = _LOAD_CELL


@dataclass(frozen=True, slots=True)
class ToySettings:
    stiffness: float = 2500.0  # N/m
    preload: float = 1.5  # N
    stretch: float = 20.0  # mm
    rows: int = 201
    batch_rows: int = 50
    operator: str = "toy"
    instruments: ToyInstruments = field(default_factory=ToyInstruments)
    faults: tuple[Fault, ...] = ()


@dataclass(frozen=True, slots=True)
class ToyTruth:
    stiffness: float
    preload: float


def simulate(settings: ToySettings | None = None, seed: int = 0) -> SimulatedRun[ToyTruth]:
    s = settings or ToySettings()
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, s.stretch, s.rows)
    columns = {
        "time": np.arange(s.rows, dtype=float),
        "extension": x,
        "force": s.instruments.load_cell.read(s.preload + s.stiffness * x * 1e-3, rng),
    }
    columns, at = apply_faults(GROUPS[0], columns, columns["time"], s.faults)
    body = RunCreate(
        stand=StandKind("toy"),
        operator=s.operator,
        title="Simulated spring",
        specimen={"surface": "steel spring"},
        test_plan={"simulated": True},
        configuration=ToyConfig().model_dump(mode="json"),
    )
    return SimulatedRun(
        run_create=body,
        batches=tuple(split("stretch", columns, at, rows=s.batch_rows)),
        truth=ToyTruth(stiffness=s.stiffness, preload=s.preload),
    )
