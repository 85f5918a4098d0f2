"""The statistics of a series against hand-computed values, published tables and SciPy's
reference functions."""

from __future__ import annotations

import math
import statistics

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy import stats

from rigserver.core.errors import ModelInputError
from rigserver.core.statistics import compare, grubbs, pooled_standard_deviation, summarise

# Four repeats of a steady friction coefficient, worked by hand:
# x̄ = 1.61/4 = 0.4025; deviations -0.0025, 0.0175, -0.0225, 0.0075; Σd² = 8.75e-4;
# s = √(8.75e-4/3) = 0.0170783; s/√n = 0.00853913; t_{0.975,3} = 3.182 (Student's t table).
REPEATS = [0.40, 0.42, 0.38, 0.41]


def test_summary_of_four_repeats_by_hand() -> None:
    s = summarise(REPEATS)
    assert s.n == 4
    assert s.mean == pytest.approx(0.4025, rel=1e-12)
    assert s.std == pytest.approx(math.sqrt(8.75e-4 / 3), rel=1e-12)
    assert s.sem == pytest.approx(math.sqrt(8.75e-4 / 3) / 2, rel=1e-12)
    half = 3.182446305284263 * math.sqrt(8.75e-4 / 3) / 2  # t table: 3.182 (3 dof, 97.5 %)
    assert s.ci_low == pytest.approx(0.4025 - half, rel=1e-9)
    assert s.ci_high == pytest.approx(0.4025 + half, rel=1e-9)
    assert s.grubbs is not None and not s.grubbs.outlier  # G = 0.0225/0.01708 = 1.317 < 1.481


def test_one_run_has_a_mean_and_nothing_else() -> None:
    s = summarise([0.4])
    assert (s.n, s.mean, s.std, s.ci_low, s.grubbs) == (1, 0.4, None, None, None)


# Two-sided critical values of Grubbs' test at α = 0.05 (ASTM E178, table of G for the
# two-sided test; also Grubbs & Beck, Technometrics 14 (1972)).
GRUBBS_TABLE = {3: 1.1543, 4: 1.4812, 5: 1.7150, 6: 1.8871, 7: 2.0200, 10: 2.2900, 20: 2.7082}


@pytest.mark.parametrize(("n", "critical"), GRUBBS_TABLE.items())
def test_grubbs_critical_values_match_the_table(n: int, critical: float) -> None:
    values = np.arange(n, dtype=float)  # any values that differ; G_crit depends on n only
    assert grubbs(values).critical == pytest.approx(critical, abs=6e-4)


def test_grubbs_flags_a_planted_outlier_and_names_it() -> None:
    # 0.40, 0.41, 0.39, 0.40, 0.55: x̄ = 0.43, s = 0.06892; G = 0.12/0.06892 = 1.741 > 1.715.
    values = [0.40, 0.41, 0.39, 0.40, 0.55]
    test = grubbs(values)
    assert test.index == 4
    assert test.statistic == pytest.approx(0.12 / float(np.std(values, ddof=1)), rel=1e-12)
    assert test.outlier


def test_grubbs_needs_three_values_that_differ() -> None:
    with pytest.raises(ModelInputError, match="at least 3"):
        grubbs([1.0, 2.0])
    with pytest.raises(ModelInputError, match="s = 0"):
        grubbs([1.0, 1.0, 1.0])


def test_welch_by_hand() -> None:
    a = [0.40, 0.42, 0.38, 0.41]
    b = [0.35, 0.36, 0.33, 0.37, 0.34]
    va, vb = np.var(a, ddof=1) / 4, np.var(b, ddof=1) / 5
    t = (np.mean(b) - np.mean(a)) / math.sqrt(va + vb)
    nu = (va + vb) ** 2 / (va**2 / 3 + vb**2 / 4)  # Welch-Satterthwaite
    found = compare({"oil A": a, "oil B": b})
    assert found.test == "welch"
    assert found.statistic == pytest.approx(t, rel=1e-10)
    assert found.df[0] == pytest.approx(nu, rel=1e-10)
    assert found.p_value == pytest.approx(2 * stats.t.sf(abs(t), nu), rel=1e-8)
    half = stats.t.ppf(0.975, nu) * math.sqrt(va + vb)
    assert found.difference == pytest.approx(np.mean(b) - np.mean(a), rel=1e-12)
    assert found.difference_low == pytest.approx(found.difference - half, rel=1e-8)
    assert found.difference_high == pytest.approx(found.difference + half, rel=1e-8)
    assert found.significant


@settings(max_examples=60, deadline=None)
@given(
    st.floats(0.01, 2.0),
    st.integers(2, 8),
    st.lists(st.floats(0.01, 2.0), min_size=2, max_size=12).filter(lambda v: np.ptp(v) > 1e-3),
)
def test_welch_against_a_level_of_equal_values_is_a_one_sample_t_test(
    value: float, runs: int, b: list[float]
) -> None:
    # One level's runs all read the same value: its variance is 0, so Welch's statistic is
    # (x̄b - value)/(sb/√nb) and the Welch-Satterthwaite ν reduces to nb - 1: Student's
    # one-sample test of b against the value. No warning: the suite turns them into errors.
    found = compare({"same": [value] * runs, "other": b})
    alone = stats.ttest_1samp(b, value)
    assert found.statistic == pytest.approx(float(alone.statistic), rel=1e-9)
    assert found.df[0] == pytest.approx(len(b) - 1, rel=1e-9)
    assert found.p_value == pytest.approx(float(alone.pvalue), rel=1e-7, abs=1e-300)


def test_anova_on_the_textbook_example() -> None:
    # Means 5, 9, 10, grand mean 8: SSB = 6·(9 + 1 + 4) = 84, SSW = 16 + 24 + 28 = 68,
    # F = (84/2)/(68/15) = 9.2647 on (2, 15) degrees of freedom.
    groups = {
        "A": [6, 8, 4, 5, 3, 4],
        "B": [8, 12, 9, 11, 6, 8],
        "C": [13, 9, 11, 8, 7, 12],
    }
    found = compare(groups)
    assert found.test == "anova"
    assert found.statistic == pytest.approx(42 / (68 / 15), rel=1e-12)
    assert found.df == (2.0, 15.0)
    assert found.p_value == pytest.approx(stats.f.sf(42 / (68 / 15), 2, 15), rel=1e-10)
    assert found.repeatability_std == pytest.approx(math.sqrt(68 / 15), rel=1e-12)
    assert found.difference is None


def test_pooled_standard_deviation_skips_single_runs() -> None:
    # (2 - 1)·0.5 + (1 - 1)·... : only the first group counts: s² of [1, 2] is 0.5.
    assert pooled_standard_deviation([[1.0, 2.0], [7.0]]) == pytest.approx(math.sqrt(0.5))
    assert pooled_standard_deviation([[1.0], [2.0]]) is None


def test_bad_input_is_refused_by_name() -> None:
    with pytest.raises(ModelInputError, match="not a finite number"):
        summarise([0.4, math.nan])
    with pytest.raises(ModelInputError, match="two levels"):
        compare({"A": [1.0, 2.0]})
    with pytest.raises(ModelInputError, match="level 'B' needs at least two runs"):
        compare({"A": [1.0, 2.0], "B": [3.0]})
    with pytest.raises(ModelInputError, match="no spread"):
        compare({"A": [1.0, 1.0], "B": [2.0, 2.0]})


finite = st.floats(-1e6, 1e6, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(finite, min_size=2, max_size=30).filter(lambda v: np.ptp(v) > 1e-3))
def test_interval_is_scipys_t_interval(values: list[float]) -> None:
    s = summarise(values)
    low, high = stats.t.interval(
        0.95, len(values) - 1, loc=np.mean(values), scale=stats.sem(values)
    )
    assert s.ci_low == pytest.approx(low, rel=1e-9, abs=1e-9)
    assert s.ci_high == pytest.approx(high, rel=1e-9, abs=1e-9)
    assert s.ci_low <= s.mean <= s.ci_high


@settings(max_examples=40, deadline=None)
@given(
    st.lists(finite, min_size=2, max_size=12).filter(lambda v: np.ptp(v) > 1e-3),
    st.lists(finite, min_size=2, max_size=12).filter(lambda v: np.ptp(v) > 1e-3),
    st.lists(finite, min_size=2, max_size=12).filter(lambda v: np.ptp(v) > 1e-3),
)
def test_anova_is_scipys_and_pooled_sd_is_the_within_mean_square(
    a: list[float], b: list[float], c: list[float]
) -> None:
    found = compare({"a": a, "b": b, "c": c})
    reference = stats.f_oneway(a, b, c)
    assert found.statistic == pytest.approx(reference.statistic, rel=1e-7)
    within = sum(np.sum((np.asarray(g) - np.mean(g)) ** 2) for g in (a, b, c))
    assert found.repeatability_std == pytest.approx(
        math.sqrt(within / (len(a) + len(b) + len(c) - 3)), rel=1e-9
    )


def test_no_grubbs_on_ties_of_a_balances_resolution() -> None:
    # Masses 6.8, 6.5, 6.8 mg: G = (n-1)/√n = 1.1547, the largest any three values reach,
    # just above G_crit = 1.1543: the test would flag the rounding, so it is not applied.
    assert summarise([6.8e-6, 6.5e-6, 6.8e-6]).grubbs is None
    assert summarise([6.8e-6, 6.5e-6, 6.7e-6]).grubbs is not None


@given(
    value=st.floats(-1e6, 1e6, allow_nan=False).filter(lambda v: v == 0 or abs(v) > 1e-300),
    n=st.integers(2, 12),
)
def test_runs_that_read_alike_have_no_spread(value: float, n: int) -> None:
    # a series of copies printed s = 1.7·10⁻¹⁷: the round-off of summing n equal values
    summary = summarise([value] * n)
    assert summary.mean == value and summary.std == 0.0 and summary.sem == 0.0


@given(st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=2, max_size=30))
@example(values=[0.0, 5e-324, 1e-323])  # three values, yet s underflows to 0: no Grubbs
def test_the_summary_is_the_textbook_mean_and_s(values: list[float]) -> None:
    # against Python's statistics module (exact rational arithmetic for the mean)
    summary = summarise(values)
    assert summary.mean == pytest.approx(statistics.fmean(values), abs=1e-12)
    assert summary.std == pytest.approx(statistics.stdev(values), rel=1e-9, abs=1e-12)
