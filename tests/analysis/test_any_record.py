"""Whatever a run holds that the service took in, its stand's analysis gives results that
can be stored: a finish never fails on readings within their channels' declared limits.

Records shaped as real ones go wrong in ways the pipelines must say, not raise: a pin that
gained mass (brass transferred in the adhesive run), a zero typed for a load or a weighing,
a disc of Ra 0, a scar diameter typed in the wrong unit (wider than the ball), a journal
centred (x = x_zero, y = y_zero), a run finished before its first row. Each becomes a
pending item or a note of the results (the run finishes; a correction of the reading
computes them again)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rigserver.analysis import analyse
from rigserver.storage._results import check_results
from schemas.channels import Channel, Order
from schemas.stands import DECLARATIONS, MEASUREMENTS, StandKind
from tests.analysis.conftest import FakeReadings, friction_record, make_run

#: A magnitude below this (in the channel's unit) is read as 0: no instrument resolves
#: 10⁻⁹ of its unit, and subnormal numbers are no reading.
NOTHING = 1e-9


def _value(channel: Channel) -> st.SearchStrategy[float]:
    """A reading within the channel's declared limit (one of its nominal values, if any)."""
    limit = channel.limit
    if limit.nominal:
        return st.sampled_from(limit.nominal)
    low = -1e6 if limit.low is None else max(limit.low, -1e6)
    high = 1e6 if limit.high is None else min(limit.high, 1e6)
    found = st.floats(low, high, allow_nan=False, allow_subnormal=False)
    found = found.map(lambda v: 0.0 if abs(v) < NOTHING and low <= 0.0 <= high else v)
    return found.map(float).map(round) if limit.integer else found


@st.composite
def records(
    draw: st.DrawFn, kind: StandKind
) -> tuple[dict[str, dict[str, list[float]]], dict[str, float]]:
    """A record of the stand: its aligned groups' rows (0 to 30, ordered channels in order)
    and any of its single measurements."""
    groups: dict[str, dict[str, list[float]]] = {}
    measured: dict[str, float] = {}
    for group in DECLARATIONS[kind].groups:
        if group.name == MEASUREMENTS or not group.aligned:
            for channel in group.channels:
                if draw(st.booleans()):
                    measured[channel.name] = draw(_value(channel))
            continue
        n = draw(st.integers(0, 30))
        columns: dict[str, list[float]] = {}
        for channel in group.channels:
            values = draw(st.lists(_value(channel), min_size=n, max_size=n))
            if channel.order is Order.INCREASING:
                values = list(np.linspace(0.0, 1.0, n) * (1 + abs(max(values, default=0))))
            elif channel.order is Order.NON_DECREASING:
                values = sorted(values)
            columns[channel.name] = values
        groups[group.name] = columns
    return groups, measured


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_record_within_the_limits_gives_results_that_can_be_stored(
    kind: StandKind,
) -> None:
    @settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
    @given(records(kind))
    def finishes(record: tuple[dict[str, dict[str, list[float]]], dict[str, float]]) -> None:
        groups, measured = record
        computed = analyse(make_run(kind), FakeReadings(groups, measured))
        check_results(computed.payload, computed.key_results)  # what a finish stores

    finishes()


def test_a_pin_that_gained_mass_leaves_the_experimental_wear_pending() -> None:
    # the adhesive run: metal carried from the disc onto the pin; (2.9) needs a loss
    readings = FakeReadings(
        {"friction": friction_record()}, {"pin_mass_before": 10.0, "pin_mass_after": 10.2}
    )
    computed = analyse(make_run(StandKind.SMTS2), readings)
    values = computed.payload["values"]
    assert values["experimental"] is None
    assert any("pin gained mass" in item for item in values["pending"])
