"""The registry of simulated stands, their determinism, and rigsim's public surface."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest

import rigsim
from rigsim.simulators import SIMULATORS, simulate
from schemas.stands import StandKind

FAST: dict[StandKind, dict[str, Any]] = {
    StandKind.MTOS: {"model": "short"},
    StandKind.SLIDE_BEARING: {"model": "short"},
    StandKind.SMTS2: {"revolutions": 1000.0},
    StandKind.PROFILOMETER: {},
    StandKind.PIN_ON_DISC: {"laps": 200, "running_in_laps": 40},
    StandKind.RECIPROCATING: {"laps": 200, "running_in_laps": 40},
}


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_stand_is_deterministic_from_its_seed(kind: StandKind) -> None:
    settings = SIMULATORS[kind].settings(**FAST[kind])
    a, b, c = (simulate(kind, settings, seed) for seed in (3, 3, 4))
    assert a.run_create == b.run_create and a.run_create.stand is kind
    pairs = list(zip(a.batches, b.batches, strict=True))
    assert all(x.group == y.group and x.at == y.at for x, y in pairs)
    assert all(np.array_equal(x.columns[k], y.columns[k]) for x, y in pairs for k in x.columns)
    differs = any(
        not np.array_equal(x.columns[k], y.columns[k])
        for x, y in zip(a.batches, c.batches, strict=False)
        for k in x.columns
        if k in y.columns
    )
    assert differs, "another seed should give other readings"
    assert dataclasses.is_dataclass(a.truth)
    assert [b.at for b in a.batches] == sorted(b.at for b in a.batches)  # stand order


def test_simulate_takes_the_kind_by_name() -> None:
    run = simulate("profilometer", seed=1)
    assert run.run_create.stand is StandKind.PROFILOMETER


def test_public_surface_is_sorted_and_complete() -> None:
    assert rigsim.__all__ == sorted(rigsim.__all__, key=lambda n: (not n.isupper(), n))
    for name in rigsim.__all__:
        assert getattr(rigsim, name) is not None
