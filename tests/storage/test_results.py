"""The stored form of analysis results: which quantities become datasets, with which unit."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rigserver.storage._results import check_results


def test_every_quantity_with_a_unit_becomes_an_array() -> None:
    results = {
        "stand": "slide_bearing",
        "values": {
            "chi_mean": 0.61,
            "rows": [{"chi": 0.6, "p": [1.0, 2.0]}, {"chi": None, "p": [3.0, 4.0]}],
            "axial": {"z": [-0.59, 0.0, 0.59]},
        },
        "units": {"chi_mean": "1", "rows[].chi": "1", "rows[].p": "Pa", "axial.z": "1"},
    }
    checked = check_results(results, {"chi_mean": 0.61})
    assert json.loads(checked.text) == results
    assert checked.key_results == {"chi_mean": 0.61}
    assert set(checked.arrays) == {
        "values/chi_mean",
        "values/rows/chi",
        "values/rows/p",
        "values/axial/z",
    }
    assert checked.arrays["values/chi_mean"].values.shape == ()
    np.testing.assert_array_equal(checked.arrays["values/rows/chi"].values, [0.6, np.nan])
    np.testing.assert_array_equal(checked.arrays["values/rows/p"].values, [[1, 2], [3, 4]])
    assert checked.arrays["values/rows/p"].unit == "Pa"
    assert checked.arrays["values/rows/p"].path == "rows[].p"


@pytest.mark.parametrize(
    "value",
    [True, "elastic", [[1.0, 2.0], [3.0]], [1.0, "a"], {"nested": 1.0}, None],
    ids=["flag", "text", "ragged", "mixed", "object", "absent"],
)
def test_what_is_not_a_numeric_array_stays_in_the_json_only(value: object) -> None:
    checked = check_results({"values": {"q": value}, "units": {"q": "m"}}, {})
    assert checked.arrays == {}
    assert json.loads(checked.text)["values"]["q"] == value


def test_paths_that_resolve_to_nothing_are_skipped() -> None:
    results = {"values": {"a": 1.0}, "units": {"b": "m", "a.c": "m", "a[].d": "m", "x/y": "m"}}
    assert check_results(results, {}).arrays == {}
    assert check_results({"anything": [1, 2]}, {}).arrays == {}


def test_key_results_must_be_finite() -> None:
    with pytest.raises(ValueError, match="key result 'h' = inf"):
        check_results({}, {"h": float("inf")})
