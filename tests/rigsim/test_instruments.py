"""rigsim.instruments: each effect alone, their composition, and the faults."""

from __future__ import annotations

import numpy as np
import pytest

from rigsim.errors import SettingsError
from rigsim.instruments import (
    Fault,
    Instrument,
    add_drift,
    add_noise,
    apply_faults,
    beyond_limit,
    quantise,
)
from schemas.channels import check_columns
from schemas.stands import MTOS_GROUPS, SMTS2_GROUPS

FRICTION = SMTS2_GROUPS[0]


def _record(n: int = 10) -> dict[str, np.ndarray]:
    return {
        "time": np.arange(n, dtype=float),
        "load": np.full(n, 300.0),
        "speed": np.full(n, 980.0),
        "friction_moment": np.linspace(2.0, 14.0, n),
        "revolutions": np.floor(np.arange(n) / 3.0),
    }


def test_quantise_rounds_to_the_step_and_prints_like_the_dial() -> None:
    # 0.04 -> 0, 0.06 -> 0.1, 26.44 -> 26.4 at a 0.1 step; the value is the float 26.4 itself
    out = quantise([0.04, 0.06, 26.44], 0.1)
    assert out.tolist() == [0.0, 0.1, 26.4]
    assert quantise([1.23456], 0.0).tolist() == [1.23456]
    with pytest.raises(SettingsError, match="resolution must be >= 0, got -1"):
        quantise([1.0], -1.0)


def test_noise_has_the_asked_spread_and_zero_noise_changes_nothing() -> None:
    rng = np.random.default_rng(1)
    values = add_noise(np.zeros(20_000), 0.5, rng)
    # standard error of a sample std is σ/√(2n) = 0.0025: 3 % is twelve of them
    assert np.std(values) == pytest.approx(0.5, rel=0.03)
    assert add_noise([1.0, 2.0], 0.0, rng).tolist() == [1.0, 2.0]
    with pytest.raises(SettingsError, match="noise sigma must be >= 0"):
        add_noise([1.0], -0.1, rng)


def test_drift_is_linear_in_time() -> None:
    assert add_drift([1.0, 1.0, 1.0], [0.0, 10.0, 20.0], 0.05).tolist() == [1.0, 1.5, 2.0]


def test_instrument_adds_offset_and_drift_then_quantises() -> None:
    gauge = Instrument(resolution=0.5, offset=10.0, drift=0.1)
    rng = np.random.default_rng(0)
    # 1 + 10 + 0.1·0 = 11; 1 + 10 + 0.1·10 = 12; 1.2 + 10 + 0.1·3 = 11.5
    assert gauge.read([1.0, 1.0, 1.2], rng, [0.0, 10.0, 3.0]).tolist() == [11.0, 12.0, 11.5]


def test_instrument_is_deterministic_from_the_generator() -> None:
    noisy = Instrument(noise=1.0)
    a = noisy.read(np.zeros(5), np.random.default_rng(7))
    b = noisy.read(np.zeros(5), np.random.default_rng(7))
    c = noisy.read(np.zeros(5), np.random.default_rng(8))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_dropout_loses_rows_of_every_channel_and_their_times() -> None:
    record = _record()
    fault = Fault(kind="dropout", group="friction", channel="load", at=0.5, rows=3)
    out, times = apply_faults(FRICTION, record, record["time"], [fault])
    kept = [0, 1, 2, 3, 4, 8, 9]  # rows 5, 6, 7 lost (at 0.5 of 10 rows)
    assert times.tolist() == [float(i) for i in kept]
    assert all(v.size == 7 for v in out.values())
    assert out["friction_moment"].tolist() == record["friction_moment"][kept].tolist()


def test_stuck_channel_repeats_its_value() -> None:
    record = _record()
    fault = Fault(kind="stuck", group="friction", channel="friction_moment", at=0.2, rows=4)
    out, _ = apply_faults(FRICTION, record, record["time"], [fault])
    assert out["friction_moment"][2:6].tolist() == [record["friction_moment"][2]] * 4
    assert out["friction_moment"][6] == record["friction_moment"][6]


def test_spike_stays_within_the_limit_and_is_accepted() -> None:
    record = _record()
    fault = Fault(kind="spike", group="friction", channel="friction_moment", at=0.9, size=5.0)
    out, _ = apply_faults(FRICTION, record, record["time"], [fault])
    # row 9 holds 14 N·m; 14 + 5 is clipped to the declared 15 N·m
    assert out["friction_moment"][9] == 15.0
    assert check_columns(FRICTION, out) == []


def test_out_of_limit_reading_is_refused_naming_the_field() -> None:
    record = _record()
    fault = Fault(kind="out_of_limit", group="friction", channel="friction_moment", at=0.5)
    out, _ = apply_faults(FRICTION, record, record["time"], [fault])
    # above the declared 15 N·m by max(10 %, 1): 16.5
    assert out["friction_moment"][5] == 16.5
    problems = check_columns(FRICTION, out)
    assert [p.field for p in problems] == ["columns.friction_moment[5]"]


def test_faults_of_other_groups_are_skipped_and_unknown_channels_refused() -> None:
    record = _record()
    other = Fault(kind="stuck", group="measurements", channel="pin_mass_before")
    out, _ = apply_faults(FRICTION, record, record["time"], [other])
    assert np.array_equal(out["friction_moment"], record["friction_moment"])
    with pytest.raises(SettingsError, match=r"friction\.torque: the group posts no such"):
        apply_faults(FRICTION, record, record["time"], [Fault("spike", "friction", "torque")])


def test_a_channel_without_limits_cannot_be_put_outside_them() -> None:
    x_channel = MTOS_GROUPS[0].channel("x")
    assert x_channel is not None
    with pytest.raises(SettingsError, match="'x' declares no limit"):
        beyond_limit(x_channel)


def test_fault_settings_are_checked() -> None:
    with pytest.raises(SettingsError, match=r"fault.at must lie in \[0, 1\], got 1.5"):
        Fault(kind="spike", group="friction", channel="load", at=1.5)
    with pytest.raises(SettingsError, match="fault kind must be one of"):
        Fault(kind="melt", group="friction", channel="load")  # type: ignore[arg-type]
