"""Channel declarations check batches and say which field, index, value and limit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from schemas.channels import Limit, check_columns
from schemas.stands import StandKind, default_stands

SMTS2 = default_stands()[StandKind.SMTS2]
FRICTION = SMTS2.group("friction")
assert FRICTION is not None


def good(n: int = 3) -> dict[str, list[float]]:
    return {
        "time": [float(i) for i in range(n)],
        "load": [300.0] * n,
        "speed": [1000.0] * n,
        "friction_moment": [3.0] * n,
        "revolutions": [float(i) for i in range(n)],
    }


def test_good_batch_passes() -> None:
    arrays, problems = check_columns(FRICTION, good())
    assert problems == []
    assert set(arrays) == set(good())


def test_moment_above_15_is_refused_naming_index_value_and_limit() -> None:
    cols = good()
    cols["friction_moment"][1] = 15.7  # the machine stops above 15 N·m (models.md §2)
    _, problems = check_columns(FRICTION, cols)
    assert len(problems) == 1
    p = problems[0]
    assert p.field == "columns.friction_moment[1]"
    assert p.value == pytest.approx(15.7)
    assert p.limit is not None and "15" in p.limit


@pytest.mark.parametrize("speed", [250.0, 700.0, 1101.0])
def test_speed_must_be_near_300_500_or_1000(speed: float) -> None:
    cols = good()
    cols["speed"][0] = speed
    _, problems = check_columns(FRICTION, cols)
    assert [p.field for p in problems] == ["columns.speed[0]"]


@pytest.mark.parametrize("speed", [270.0, 550.0, 900.0, 1100.0])
def test_speed_within_ten_percent_passes(speed: float) -> None:
    cols = good()
    cols["speed"][0] = speed
    assert check_columns(FRICTION, cols)[1] == []


def test_load_outside_200_5000_with_tolerance_refused() -> None:
    cols = good()
    cols["load"][2] = 100.0
    _, problems = check_columns(FRICTION, cols)
    assert problems[0].field == "columns.load[2]"


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_refused(bad: float) -> None:
    cols = good()
    cols["load"][0] = bad
    _, problems = check_columns(FRICTION, cols)
    assert problems[0].field == "columns.load[0]"
    assert "finite" in problems[0].message


def test_time_must_increase_within_and_across_batches() -> None:
    cols = good()
    cols["time"] = [0.0, 2.0, 1.0]
    _, problems = check_columns(FRICTION, cols)
    assert [p.field for p in problems] == ["columns.time[2]"]
    _, problems = check_columns(FRICTION, good(), last_values={"time": 5.0, "revolutions": 0.0})
    assert problems[0].field == "columns.time[0]"
    assert "5" in problems[0].message


def test_unknown_missing_and_ragged_channels() -> None:
    cols = good()
    cols["torque"] = [1.0, 2.0, 3.0]
    del cols["load"]
    cols["speed"] = [1000.0]
    fields = {p.field for p in check_columns(FRICTION, cols)[1]}
    assert {"columns.torque", "columns.load", "columns"} <= fields


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e6, max_value=1e6))
def test_limit_agrees_with_its_description(value: float) -> None:
    limit = Limit(low=0.0, high=15.0)
    inside = 0.0 <= value <= 15.0
    assert bool(limit.violations(np.array([value]))[0]) is not inside


def test_every_stand_declares_units_known_and_names_unique() -> None:
    for stand in default_stands().values():
        for group in stand.groups:
            names = [c.name for c in group.channels]
            assert len(names) == len(set(names)), group.name
