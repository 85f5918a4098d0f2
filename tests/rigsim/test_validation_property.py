"""Property: readings of settings inside the stands' limits pass the server's check; a
reading outside a limit is refused, naming its field."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rigsim.batches import SimulatedRun
from rigsim.instruments import Fault, beyond_limit
from rigsim.simulators import mtos, profilometer, slide_bearing, smts2, tribometer
from schemas.channels import check_columns
from schemas.stands import default_stands

STANDS = default_stands()
FAST = settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _problems(run: SimulatedRun[Any]) -> list[str]:
    """Every violation the server's check finds, batch by batch, with ordering carried over."""
    stand = STANDS[run.run_create.stand]
    last: dict[str, dict[str, float]] = {}
    found: list[str] = []
    for batch in run.batches:
        group = stand.group(batch.group)
        assert group is not None
        problems = check_columns(group, batch.columns, last.get(group.name))
        found += [p.field for p in problems]
        if group.aligned and batch.rows:
            last[group.name] = {k: float(v[-1]) for k, v in batch.columns.items()}
    return found


@st.composite
def smts2_settings(draw: st.DrawFn) -> smts2.Smts2Settings:
    mode = draw(st.sampled_from(smts2.MODES))
    base = smts2.Smts2Settings.for_mode(mode)
    # the largest load whose running-in peak stays under the machine's 15 N·m (a hair
    # below: at the bound itself the product may round to just above 15)
    peak_per_newton = base.friction_start * (1 + 4 * base.friction_fluctuation) * 0.0225
    top = min(5000.0, 15.0 / peak_per_newton * (1 - 1e-12))
    return replace(
        base,
        load=draw(st.floats(200.0, top)),
        speed=draw(st.sampled_from(smts2.SPEEDS)),
        revolutions=draw(st.floats(200.0, 3000.0)),
    )


@FAST
@given(smts2_settings(), st.integers(0, 2**32 - 1))
def test_smts2_inside_limits_passes(s: smts2.Smts2Settings, seed: int) -> None:
    assert _problems(smts2.simulate(s, seed)) == []


@FAST
@given(st.floats(5.0, 40.0), st.floats(15.0, 30.0), st.integers(0, 2**32 - 1))
def test_slide_bearing_inside_limits_passes(scale: float, inlet: float, seed: int) -> None:
    s = slide_bearing.SlideBearingSettings(
        model="short", loader_scale=scale, inlet_temperature=inlet
    )
    assert _problems(slide_bearing.simulate(s, seed)) == []


@FAST
@given(
    st.lists(st.floats(200.0, 3000.0), min_size=1, max_size=4),
    st.lists(st.floats(200.0, 2500.0), min_size=1, max_size=2),
    st.integers(0, 2**32 - 1),
)
def test_mtos_inside_limits_passes(fluid: list[float], starved: list[float], seed: int) -> None:
    s = mtos.MtosSettings(
        model="short",
        loads_fluid=tuple(fluid),
        loads_mixed=tuple(starved),
        loads_boundary=tuple(starved),
    )
    assert _problems(mtos.simulate(s, seed)) == []


@FAST
@given(st.floats(0.05e-6, 12e-6), st.integers(0, 2**32 - 1))
def test_profilometer_inside_limits_passes(ra: float, seed: int) -> None:
    s = profilometer.ProfilometerSettings(ra=ra)
    assert _problems(profilometer.simulate(s, seed)) == []


@FAST
@given(st.sampled_from(["pin_on_disc", "reciprocating"]), st.integers(0, 2**32 - 1))
def test_tribometers_inside_limits_pass(kind: str, seed: int) -> None:
    assert _problems(SIMULATE[kind]((), seed)) == []


SIMULATE: dict[str, Callable[[tuple[Fault, ...], int], SimulatedRun[Any]]] = {
    "smts2": lambda faults, seed: smts2.simulate(
        smts2.Smts2Settings.for_mode("oxidative", revolutions=300.0, faults=faults), seed
    ),
    "slide_bearing": lambda faults, seed: slide_bearing.simulate(
        slide_bearing.SlideBearingSettings(model="short", faults=faults), seed
    ),
    "mtos": lambda faults, seed: mtos.simulate(
        mtos.MtosSettings(
            model="short",
            loads_fluid=(1000.0,),
            loads_mixed=(),
            loads_boundary=(500.0,),
            faults=faults,
        ),
        seed,
    ),
    "profilometer": lambda faults, seed: profilometer.simulate(
        profilometer.ProfilometerSettings(faults=faults), seed
    ),
    "pin_on_disc": lambda faults, seed: tribometer.simulate(
        tribometer.TribometerSettings(laps=20, running_in_laps=5, faults=faults), seed
    ),
    "reciprocating": lambda faults, seed: tribometer.simulate(
        tribometer.TribometerSettings.reciprocating(laps=20, running_in_laps=5, faults=faults),
        seed,
    ),
}


def _posted(kind: str) -> set[tuple[str, str]]:
    """(group, channel) of every channel the simulator of ``kind`` posts (a declared channel it
    leaves to the configuration, as the tribometers' densities, cannot be made faulty)."""
    run = SIMULATE[kind]((), 0)
    return {(batch.group, name) for batch in run.batches for name in batch.columns}


LIMITED = [
    (kind, group.name, channel.name)
    for kind, stand in STANDS.items()
    for posted in [_posted(kind.value)]
    for group in stand.groups
    for channel in group.channels
    if (
        channel.limit.low is not None
        or channel.limit.high is not None
        or channel.limit.nominal is not None
    )
    and (group.name, channel.name) in posted
]


@settings(max_examples=20, deadline=None)
@given(st.sampled_from(LIMITED), st.floats(0.0, 1.0), st.integers(0, 2**32 - 1))
def test_a_reading_outside_its_limit_is_refused_by_name(
    where: tuple[Any, str, str], at: float, seed: int
) -> None:
    kind, group, channel = where
    fault = Fault(kind="out_of_limit", group=group, channel=channel, at=at)
    run = SIMULATE[kind.value]((fault,), seed)
    problems = _problems(run)
    assert problems, f"{kind.value}: {group}.{channel} outside its limit was accepted"
    # every refusal names the faulty channel (an ordered one may also break its order there)
    assert all(p.startswith(f"columns.{channel}[") for p in problems)
    declared = STANDS[kind].group(group)
    assert declared is not None
    spec = declared.channel(channel)
    assert spec is not None
    assert np.count_nonzero(run.columns(group)[channel] == beyond_limit(spec)) == 1
