"""Channel declarations check batches and say which field, index, value and limit."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from schemas.channels import (
    Channel,
    ChannelGroup,
    Limit,
    Order,
    _in_order,
    _violations,
    check_columns,
    follows,
)
from schemas.stands import Stand, StandKind, configure_stands, default_stands

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
    assert check_columns(FRICTION, good()) == []


def test_moment_above_15_is_refused_naming_index_value_and_limit() -> None:
    cols = good()
    cols["friction_moment"][1] = 15.7  # the machine stops above 15 N·m (models.md §2)
    problems = check_columns(FRICTION, cols)
    assert len(problems) == 1
    p = problems[0]
    assert p.field == "columns.friction_moment[1]"
    assert p.value == pytest.approx(15.7)
    assert p.limit is not None and "15" in p.limit


@pytest.mark.parametrize("speed", [250.0, 700.0, 1101.0])
def test_speed_must_be_near_300_500_or_1000(speed: float) -> None:
    cols = good()
    cols["speed"][0] = speed
    problems = check_columns(FRICTION, cols)
    assert [p.field for p in problems] == ["columns.speed[0]"]


@pytest.mark.parametrize("speed", [270.0, 550.0, 900.0, 1100.0])
def test_speed_within_ten_percent_passes(speed: float) -> None:
    cols = good()
    cols["speed"][0] = speed
    assert check_columns(FRICTION, cols) == []


def test_load_outside_200_5000_with_tolerance_refused() -> None:
    cols = good()
    cols["load"][2] = 100.0
    problems = check_columns(FRICTION, cols)
    assert problems[0].field == "columns.load[2]"


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_refused(bad: float) -> None:
    cols = good()
    cols["load"][0] = bad
    problems = check_columns(FRICTION, cols)
    assert problems[0].field == "columns.load[0]"
    assert "finite" in problems[0].message


def test_time_must_increase_within_and_across_batches() -> None:
    cols = good()
    cols["time"] = [0.0, 2.0, 1.0]
    problems = check_columns(FRICTION, cols)
    assert [p.field for p in problems] == ["columns.time[2]"]
    problems = check_columns(FRICTION, good(), last_values={"time": 5.0, "revolutions": 0.0})
    assert problems[0].field == "columns.time[0]"
    assert "5" in problems[0].message


def test_unknown_missing_and_ragged_channels() -> None:
    cols = good()
    cols["torque"] = [1.0, 2.0, 3.0]
    del cols["load"]
    cols["speed"] = [1000.0]
    fields = {p.field for p in check_columns(FRICTION, cols)}
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


# --- the quick accept of small batches agrees with the full check -------------------------

GROUPS = [g for stand in default_stands().values() for g in stand.groups] + [
    ChannelGroup(
        name="synthetic",
        long_name="every kind of limit and order",
        aligned=True,
        channels=(
            Channel(name="code", unit="code", long_name="", limit=Limit(low=1, integer=True)),
            Channel(
                name="gear",
                unit="1",
                long_name="",
                limit=Limit(nominal=(-2.0, 0.0, 3.0), tolerance=0.25, high=2.9),
            ),
            Channel(name="t", unit="s", long_name="", order=Order.INCREASING),
            Channel(name="n", unit="1", long_name="", order=Order.NON_DECREASING),
        ),
    )
]


def _edges(ch: Channel) -> list[float]:
    """Values at and around every edge of a channel's limit: where the two checks could
    disagree."""
    lim = ch.limit
    points = [0.0, 1.0, -1.0]
    points += [x for x in (lim.low, lim.high) if x is not None]
    for v in lim.nominal or ():
        points += [v, v + lim.tolerance * abs(v), v - lim.tolerance * abs(v)]
    return [p + d for p in points for d in (0.0, 0.5, -0.5, 1e-9, -1e-9)]


def _inside(ch: Channel, rows: int, last: float | None) -> list[float]:
    """``rows`` values that keep the channel's limit and order (after ``last``)."""
    lim = ch.limit
    if lim.nominal:
        value = lim.nominal[0]
    elif lim.low is not None:
        value = lim.low + 1.0 if lim.high is None else (lim.low + lim.high) / 2
    else:
        value = 0.0 if lim.high is None else lim.high - 1.0
    if ch.order is Order.ANY:
        return [value] * rows
    start = max(value, (last or 0.0) + 1.0)
    return [start + i for i in range(rows)]


@st.composite
def small_batches(
    draw: st.DrawFn,
) -> tuple[ChannelGroup, dict[str, list[float]], dict[str, float]]:
    """A batch of a few rows inside the limits but for one value (or none), at an edge of
    its limit, anywhere, or not finite."""
    group = draw(st.sampled_from(GROUPS))
    channels = group.channels
    if not group.aligned:
        channels = tuple(draw(st.lists(st.sampled_from(channels), min_size=1, unique=True)))
    rows = draw(st.integers(1, 3))

    def value(ch: Channel) -> st.SearchStrategy[float]:
        return st.one_of(
            st.sampled_from(_edges(ch)),
            st.floats(-1e4, 1e4),
            st.sampled_from([math.nan, math.inf, -math.inf]),
        )

    last = {
        ch.name: draw(value(ch).filter(math.isfinite))
        for ch in channels
        if ch.order is not Order.ANY and draw(st.booleans())
    }
    columns = {ch.name: _inside(ch, rows, last.get(ch.name)) for ch in channels}
    free = draw(st.one_of(st.sampled_from(channels), st.none()))
    if free is not None:
        i = draw(st.integers(0, rows - 1))
        before = columns[free.name][i - 1] if i else last.get(free.name, 0.0)
        columns[free.name][i] = draw(st.one_of(value(free), st.just(before)))
    return group, columns, last


@settings(max_examples=500)
@given(small_batches())
def test_quick_accept_agrees_with_the_full_check(
    batch: tuple[ChannelGroup, dict[str, list[float]], dict[str, float]],
) -> None:
    group, columns, last = batch
    assert group.quick_check.accepts(columns, last) is (_violations(group, columns, last) == [])


@settings(max_examples=500)
@given(small_batches())
def test_a_batch_good_on_its_own_is_good_after_the_last_values_if_it_follows_them(
    batch: tuple[ChannelGroup, dict[str, list[float]], dict[str, float]],
) -> None:
    """What the store's lock checks of a large batch (the order across batches) is all that
    the full check with the last stored values adds to the batch checked on its own."""
    group, columns, last = batch
    arrays = {name: np.array(values) for name, values in columns.items()}
    assume(check_columns(group, arrays) == [])
    assert follows(group, arrays, last) is (check_columns(group, arrays, last) == [])


CHANNELS = [ch for group in GROUPS for ch in group.channels]


@st.composite
def columns_at_edges(draw: st.DrawFn) -> tuple[Channel, np.ndarray]:
    """A channel and a column of values at the edges of its limit, anywhere, or not finite."""
    synthetic = GROUPS[-1].channels  # every kind of limit: drawn as often as all the rest
    ch = draw(st.one_of(st.sampled_from(synthetic), st.sampled_from(CHANNELS)))
    edge = st.sampled_from(_edges(ch) + _inside(ch, 1, None))
    value = st.one_of(
        edge,
        edge,  # twice as likely: most columns should be good or broken at one edge
        st.floats(-1e4, 1e4),
        st.sampled_from([math.nan, math.inf, -math.inf, -0.0]),
    )
    return ch, np.array(draw(st.lists(value, min_size=1, max_size=6)), dtype=np.float64)


def _channel(name: str) -> Channel:
    return next(ch for ch in CHANNELS if ch.name == name)


@settings(max_examples=500)
@given(columns_at_edges())
# each edge once for sure: on a limit (15 N·m, 190 N), on a band's ends (1000 rpm ± 10 %),
# half a code, not finite where nothing else is limited
@example((_channel("friction_moment"), np.array([3.0, 15.0])))
@example((_channel("load"), np.array([190.0, 300.0])))
@example((_channel("speed"), np.array([900.0, 1100.0])))
@example((_channel("code"), np.array([1.0, 1.5])))
@example((_channel("t"), np.array([0.0, math.inf])))
def test_extremes_judge_a_column_as_the_mask_of_every_rule_does(
    drawn: tuple[Channel, np.ndarray],
) -> None:
    # Limit.holds_for looks at the least and greatest value only; Limit.violations tests
    # every value against every rule: the same verdict, but that a column spread over two
    # nominal settings is left to the mask (its extremes cannot tell)
    ch, values = drawn
    lim = ch.limit
    by_mask = bool(np.isfinite(values).all()) and not lim.violations(values).any()
    one_setting = lim.nominal is None or any(
        all(abs(x - v) <= lim.tolerance * abs(v) for x in values) for v in lim.nominal
    )
    assert lim.holds_for(values) is (by_mask and one_setting)


@settings(max_examples=300)
@given(
    st.sampled_from(list(Order)),
    st.lists(st.sampled_from([-1.0, 0.0, 0.5, 1.0, 1.0 + 1e-12, 2.0]), min_size=1, max_size=8),
    st.one_of(st.none(), st.sampled_from([-1.0, 0.0, 1.0, 2.0])),
)
def test_in_order_is_pairwise_order(order: Order, values: list[float], last: float | None) -> None:
    # each value against the one before it, the first against the last stored value
    seq = values if last is None else [last, *values]
    pairs = list(itertools.pairwise(seq))
    expected = {
        Order.ANY: True,
        Order.INCREASING: all(b > a for a, b in pairs),
        Order.NON_DECREASING: all(b >= a for a, b in pairs),
    }[order]
    assert _in_order(order, np.array(values), last) is expected


def test_a_stands_configuration_sets_its_gauges_unit() -> None:
    # the lab's stands file says its manometers read in physical atmospheres
    stand = configure_stands({"slide_bearing": {"gauge_unit": "atm"}})[StandKind.SLIDE_BEARING]

    def units(s: Stand) -> dict[str, str]:
        rows = s.group("rows")
        assert rows is not None
        return {c.name: c.unit for c in rows.channels}

    default = units(default_stands()[StandKind.SLIDE_BEARING])
    manometers = {f"p{k}" for k in range(1, 6)}
    assert units(stand) == {n: "atm" if n in manometers else u for n, u in default.items()}
    assert units(stand.for_run({"gauge_unit": "at"})) == default  # a run's own snapshot


# --- the default plot of a group ------------------------------------------------------------


def test_every_aligned_group_declares_its_plot() -> None:
    for stand in default_stands().values():
        for group in stand.groups:
            assert bool(group.signals) == group.aligned, group.name
            assert (group.axis is not None) == group.aligned, group.name


@pytest.mark.parametrize(
    ("signals", "axis", "match"),
    [(("t",), "clock", "'clock', not one of its channels"), (("t",), "t", "against itself")],
)
def test_a_plot_names_channels_of_its_group(
    signals: tuple[str, ...], axis: str, match: str
) -> None:
    with pytest.raises(ValidationError, match=match):
        ChannelGroup(
            name="g",
            long_name="",
            aligned=True,
            channels=(Channel(name="t", unit="s", long_name=""),),
            signals=signals,
            axis=axis,
        )
