"""Whatever a run holds that the service took in, its stand's analysis gives results that
can be stored: a finish never fails on readings within their channels' declared limits.

Records shaped as real ones go wrong in ways the pipelines must say, not raise: a pin that
gained mass (brass transferred in the adhesive run), a zero typed for a load or a weighing,
a disc of Ra 0, a scar diameter typed in the wrong unit (wider than the ball), a journal
centred (x = x_zero, y = y_zero), a run finished before its first row. Each becomes a
pending item or a note of the results (the run finishes; a correction of the reading
computes them again)."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rigserver.analysis import analyse
from rigserver.storage._results import check_results
from rigsim.simulators import SIMULATORS
from schemas.channels import Channel, Order
from schemas.stands import DECLARATIONS, MEASUREMENTS, StandKind
from tests.analysis.conftest import FakeReadings, friction_record, make_run


def _value(channel: Channel) -> st.SearchStrategy[float]:
    """A reading within the channel's declared limit (one of its nominal values, if any)."""
    limit = channel.limit
    if limit.nominal:
        return st.sampled_from(limit.nominal)
    low = -1e6 if limit.low is None else max(limit.low, -1e6)
    high = 1e6 if limit.high is None else min(limit.high, 1e6)
    found = st.floats(low, high, allow_nan=False)  # down to 5e-324: what the door takes
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


#: Records per stand (CI derandomises hypothesis: the same ones each run).
EXAMPLES = 60


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_record_within_the_limits_gives_results_that_can_be_stored(
    kind: StandKind,
) -> None:
    @settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
    @given(records(kind))
    def finishes(record: tuple[dict[str, dict[str, list[float]]], dict[str, float]]) -> None:
        groups, measured = record
        computed = analyse(make_run(kind), FakeReadings(groups, measured))
        check_results(computed.payload, computed.key_results)  # what a finish stores
        json.dumps(computed.payload, allow_nan=False)  # and the API answers as JSON

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


def _readings(kind: StandKind, seed: int = 0) -> tuple[dict[str, dict[str, list[float]]], dict]:
    """A simulated run's record as the analysis reads it: its groups' columns and its single
    measurements (the last value of each)."""
    sim = SIMULATORS[kind].simulate(SIMULATORS[kind].settings(), seed)
    groups: dict[str, dict[str, list[float]]] = {}
    measured: dict[str, float] = {}
    for group in DECLARATIONS[kind].groups:
        columns = sim.columns(group.name) if sim.rows(group.name) else {}
        if group.aligned:
            groups[group.name] = {k: list(map(float, v)) for k, v in columns.items()}
        else:
            measured |= {k: float(v[-1]) for k, v in columns.items()}
    return groups, measured


def _results(kind: StandKind, groups: dict, measured: dict) -> dict[str, Any]:
    computed = analyse(make_run(kind), FakeReadings(groups, measured))
    check_results(computed.payload, computed.key_results)
    json.dumps(computed.payload, allow_nan=False)
    return dict(computed.payload["values"])


def test_a_scar_typed_in_millimetres_as_micrometres_is_a_note() -> None:
    # a 6 mm ball (the stand's default) has no scar wider than 6000 μm; 12 000 is the
    # 1.2 mm scar typed with a digit too many
    groups, measured = _readings(StandKind.PIN_ON_DISC)
    values = _results(StandKind.PIN_ON_DISC, groups, measured | {"scar_diameter": 12_000.0})
    assert values["pin_scar"] is None
    assert any("scar" in note for note in values["notes"])
    assert values["friction_steady"] is not None  # the rest is computed


def test_an_mtos_step_without_load_and_a_centred_journal() -> None:
    groups, measured = _readings(StandKind.MTOS)
    steps = groups["steps"]
    steps["load"][0] = 0.0  # a step typed before the load was set
    values = _results(StandKind.MTOS, groups, measured)
    assert values["steps"] == [] and any("steps 0:" in p for p in values["pending"])
    steps["load"][0] = 500.0
    # the journal centred at step 1: X_set - X = h0·cos 45° on both gauges (4.9), read in μm
    # and found to the last bit, so that e_x = e_y = 0 exactly
    offset = make_run(StandKind.MTOS).configuration["clearance"] * math.cos(math.pi / 4.0)
    x = offset / 1e-6
    while x * 1e-6 != offset:
        x = math.nextafter(x, math.inf if x * 1e-6 < offset else -math.inf)
    measured = measured | {"x_zero": 0.0, "y_zero": 0.0}
    steps["x"][1] = steps["y"][1] = x
    values = _results(StandKind.MTOS, groups, measured)
    assert values["steps"][1]["chi"] == 0.0
    assert values["steps"][1]["chi_uncertainty"] is None  # hypot has no derivative at 0
    assert any("step 1: journal centred, u(χ)" in note for note in values["notes"])


def test_a_disc_of_ra_zero_or_next_to_nothing_is_a_note() -> None:
    groups, measured = _readings(StandKind.SMTS2)
    values = _results(StandKind.SMTS2, groups, measured | {"disc_ra": 0.0})  # Ra not typed
    assert values["theoretical"] is None
    assert "theoretical wear not computed: ra_disc must be > 0, got 0.0" in values["notes"]
    # 10⁻¹⁷⁰ μm: Δ = 5.4·10⁻²·Ra² (2.6) underflows to 0, so (2.1) still gives I_h but the
    # approach of its range check divides by √(Rmax/R) = 0
    values = _results(StandKind.SMTS2, groups, measured | {"disc_ra": 1e-170})
    assert values["validity"] is None
    assert any("range of (2.1) not checked" in note for note in values["notes"])


def test_a_load_of_nothing_on_the_tribometer_is_a_note() -> None:
    # 5·10⁻³²⁴ N, the least float: the door takes it (within 0..limit); the Hertz radius
    # and k's derivatives underflow, and the run still finishes
    groups, measured = _readings(StandKind.PIN_ON_DISC)
    groups["friction"]["normal_load"] = [5e-324] * len(groups["friction"]["normal_load"])
    values = _results(StandKind.PIN_ON_DISC, groups, measured)
    assert values["hertz"] is None
    assert any("Hertz contact not computed" in note for note in values["notes"])


def test_a_slide_bearing_run_finished_before_its_first_row_waits() -> None:
    groups, measured = _readings(StandKind.SLIDE_BEARING)
    groups["rows"] = {name: [] for name in groups["rows"]}
    values = _results(StandKind.SLIDE_BEARING, groups, measured)
    assert "no limb rows yet" in values["pending"]
