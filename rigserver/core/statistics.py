"""Statistics of a series of runs: repeats of one test, or a comparison across levels of a
factor (oil, material, load, operator).

Every figure is of one headline result taken once per run (the steady friction coefficient
of each SMTs-2 run, the mean χ of each slide-bearing run, ...), so the runs are the
replicates. The distributions are SciPy's (:mod:`scipy.stats`); nothing here is a
hand-written quantile.

References
----------
.. [1] ISO 5725-2:2019, Accuracy (trueness and precision) of measurement methods and
       results, part 2: repeatability standard deviation s_r as the pooled within-cell
       standard deviation.
.. [2] ASTM E178-21, Standard Practice for Dealing With Outlying Observations: Grubbs'
       test, the two-sided criterion G = max|x_i - x̄|/s against the critical value
       G_crit = (n-1)/√n · √(t²/(n-2+t²)), t the upper α/(2n) quantile of Student's t with
       n-2 degrees of freedom.
.. [3] B. L. Welch (1947), The generalization of 'Student's' problem when several different
       population variances are involved, Biometrika 34: the unequal-variance t-test and
       its Welch-Satterthwaite degrees of freedom.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

from rigserver.core.errors import ModelInputError

__all__ = [
    "Comparison",
    "Grubbs",
    "Summary",
    "compare",
    "grubbs",
    "pooled_standard_deviation",
    "summarise",
]

#: Confidence level of every interval, and 1 - significance level of every test.
CONFIDENCE = 0.95


@dataclass(frozen=True, slots=True)
class Grubbs:
    """Grubbs' test for one outlier (ASTM E178) [2]_.

    Attributes
    ----------
    statistic : float
        G = max|x_i - x̄|/s.
    critical : float
        G_crit at the significance level ``alpha``.
    alpha : float
        Significance level (two-sided).
    index : int
        Position of the value farthest from the mean (the suspect).
    outlier : bool
        ``statistic > critical``: the suspect is flagged (it is never removed).
    """

    statistic: float
    critical: float
    alpha: float
    index: int
    outlier: bool


@dataclass(frozen=True, slots=True)
class Summary:
    """The spread of one result over n runs.

    Attributes
    ----------
    n : int
        Runs that have the result.
    mean : float
        x̄.
    std : float or None
        Sample standard deviation s (n - 1 in the denominator); None for n < 2.
    sem : float or None
        Standard error of the mean, s/√n.
    ci_low, ci_high : float or None
        The ``confidence`` interval of the mean, x̄ ∓ t_{(1+c)/2, n-1}·s/√n (Student's t).
    confidence : float
    grubbs : Grubbs or None
        Grubbs' test, for three distinct values or more (with ties down to two values,
        as a balance's resolution makes them, the farthest value of three is always at
        the test's largest possible G, (n-1)/√n, and would be flagged by rounding alone).
    """

    n: int
    mean: float
    std: float | None
    sem: float | None
    ci_low: float | None
    ci_high: float | None
    confidence: float
    grubbs: Grubbs | None


@dataclass(frozen=True, slots=True)
class Comparison:
    """The levels of a factor compared on one result.

    Attributes
    ----------
    test : {"welch", "anova"}
        Welch's t-test for two levels [3]_, one-way ANOVA for more.
    statistic : float
        t (Welch) or F (ANOVA).
    df : tuple of float
        Degrees of freedom: (ν,) of Welch-Satterthwaite, or (k - 1, N - k) of ANOVA.
    p_value : float
    significant : bool
        ``p_value < 1 - confidence``.
    difference : float or None
        Two levels: mean of the second minus mean of the first.
    difference_low, difference_high : float or None
        Its ``confidence`` interval (Welch's standard error and degrees of freedom).
    repeatability_std : float or None
        s_r, the standard deviation within levels pooled over them [1]_.
    """

    test: str
    statistic: float
    df: tuple[float, ...]
    p_value: float
    significant: bool
    difference: float | None
    difference_low: float | None
    difference_high: float | None
    repeatability_std: float | None


def _values(name: str, values: Sequence[float] | np.ndarray) -> np.ndarray:
    x = np.asarray(values, dtype=float)
    if x.ndim != 1:
        raise ModelInputError(f"{name} must be a list of numbers, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ModelInputError(f"{name} holds a value that is not a finite number")
    return x


def grubbs(values: Sequence[float] | np.ndarray, *, alpha: float = 0.05) -> Grubbs:
    """Grubbs' two-sided test for one outlier (ASTM E178) [2]_.

    .. math:: G = \\frac{\\max_i |x_i - \\bar x|}{s}, \\quad
              G_{crit} = \\frac{n-1}{\\sqrt n}\\sqrt{\\frac{t^2}{n-2+t^2}},
              \\quad t = t_{1-\\alpha/(2n),\\,n-2}

    Parameters
    ----------
    values : sequence of float, shape (n,), n >= 3
        One value per run.
    alpha : float
        Significance level, 0 < alpha < 1 (E178's usual choice: 0.05).

    Returns
    -------
    Grubbs
        The statistic, the critical value and whether the farthest value is an outlier.

    Raises
    ------
    ModelInputError
        n < 3, alpha outside (0, 1), or all values equal (s = 0: no spread to test).
    """
    x = _values("values", values)
    n = x.size
    if n < 3:
        raise ModelInputError(f"Grubbs' test needs at least 3 values, got {n}")
    if not 0.0 < alpha < 1.0:
        raise ModelInputError(f"alpha must be between 0 and 1, got {alpha}")
    s = float(np.std(x - x[0], ddof=1))
    if s == 0.0:
        raise ModelInputError("Grubbs' test needs values that differ (s = 0)")
    deviation = np.abs(x - x.mean())
    index = int(np.argmax(deviation))
    statistic = float(deviation[index]) / s
    t = float(stats.t.ppf(1.0 - alpha / (2.0 * n), n - 2))
    critical = (n - 1) / math.sqrt(n) * math.sqrt(t * t / (n - 2 + t * t))
    return Grubbs(statistic, critical, alpha, index, statistic > critical)


def summarise(values: Sequence[float] | np.ndarray, *, confidence: float = CONFIDENCE) -> Summary:
    """n, mean, standard deviation, standard error and the confidence interval of the mean.

    .. math:: \\bar x \\pm t_{(1+c)/2,\\,n-1} \\frac{s}{\\sqrt n}

    Parameters
    ----------
    values : sequence of float, shape (n,), n >= 1
        One value per run, in the result's unit.
    confidence : float
        Confidence level c of the interval, 0 < c < 1.

    Returns
    -------
    Summary
        With ``std``, ``sem`` and the interval None for a single run, and Grubbs' test for
        three runs or more that differ.
    """
    x = _values("values", values)
    if x.size == 0:
        raise ModelInputError("a summary needs at least one value")
    if not 0.0 < confidence < 1.0:
        raise ModelInputError(f"confidence must be between 0 and 1, got {confidence}")
    n = int(x.size)
    # about the first value (the shifted-data form): runs that read alike give s = 0 and
    # their value as the mean exactly, not the round-off of summing them (s = 1.7e-17)
    shifted = x - x[0]
    mean = float(x[0] + shifted.mean())
    if n < 2:
        return Summary(n, mean, None, None, None, None, confidence, None)
    std = float(np.std(shifted, ddof=1))
    sem = std / math.sqrt(n)
    half = float(stats.t.ppf((1.0 + confidence) / 2.0, n - 1)) * sem
    # values that differ only below a double's square (5e-324 apart) have s = 0: no test
    test = grubbs(x, alpha=1.0 - confidence) if np.unique(x).size >= 3 and std > 0 else None
    return Summary(n, mean, std, sem, mean - half, mean + half, confidence, test)


def pooled_standard_deviation(groups: Sequence[Sequence[float] | np.ndarray]) -> float | None:
    """The repeatability standard deviation s_r: the within-group spread pooled over groups.

    .. math:: s_r = \\sqrt{\\frac{\\sum_i (n_i - 1) s_i^2}{\\sum_i (n_i - 1)}}

    (ISO 5725-2 [1]_, one lab: the groups are the levels, or the single set of repeats.)
    Groups of one value carry no within-group spread and add nothing; None when no group
    has two values.
    """
    arrays = [_values("group", g) for g in groups]
    dof = sum(a.size - 1 for a in arrays if a.size >= 2)
    if dof == 0:
        return None
    sum_squares = sum(float(np.sum((a - a.mean()) ** 2)) for a in arrays if a.size >= 2)
    return math.sqrt(sum_squares / dof)


def compare(
    levels: Mapping[str, Sequence[float] | np.ndarray], *, confidence: float = CONFIDENCE
) -> Comparison:
    """Compare a result across the levels of a factor.

    Two levels: Welch's unequal-variance t-test [3]_ and the difference of the means
    (second level minus first, in the mapping's order) with its confidence interval,
    (x̄2 - x̄1) ± t_{(1+c)/2, ν}·√(s1²/n1 + s2²/n2), ν by Welch-Satterthwaite.
    More levels: one-way ANOVA (F-test, equal variances assumed).

    Parameters
    ----------
    levels : mapping of str to sequence of float
        Level name -> one value per run; at least two levels, each with at least two values.
    confidence : float
        Confidence level c; a difference is significant when p < 1 - c.

    Returns
    -------
    Comparison
    """
    if len(levels) < 2:
        raise ModelInputError(f"a comparison needs at least two levels, got {len(levels)}")
    groups = {name: _values(f"level {name!r}", v) for name, v in levels.items()}
    for name, g in groups.items():
        if g.size < 2:
            raise ModelInputError(f"level {name!r} needs at least two runs, has {g.size}")
    s_r = pooled_standard_deviation(list(groups.values()))
    if s_r == 0.0:
        raise ModelInputError("the levels have no spread within them: nothing to test against")
    alpha = 1.0 - confidence
    if len(groups) == 2:
        a, b = groups.values()
        with warnings.catch_warnings():
            if np.ptp(a) == 0 or np.ptp(b) == 0:
                # a level of equal values (the same reading entered for every run): SciPy
                # takes its exact zero spread for a loss of precision; its moments are exact
                warnings.filterwarnings("ignore", "Precision loss occurred", RuntimeWarning)
            welch = stats.ttest_ind(b, a, equal_var=False)
        interval = welch.confidence_interval(confidence_level=confidence)
        difference = float(b.mean() - a.mean())
        p = float(welch.pvalue)
        return Comparison(
            test="welch",
            statistic=float(welch.statistic),
            df=(float(welch.df),),
            p_value=p,
            significant=p < alpha,
            difference=difference,
            difference_low=float(interval.low),
            difference_high=float(interval.high),
            repeatability_std=s_r,
        )
    anova = stats.f_oneway(*groups.values())
    k = len(groups)
    total = sum(g.size for g in groups.values())
    p = float(anova.pvalue)
    return Comparison(
        test="anova",
        statistic=float(anova.statistic),
        df=(float(k - 1), float(total - k)),
        p_value=p,
        significant=p < alpha,
        difference=None,
        difference_low=None,
        difference_high=None,
        repeatability_std=s_r,
    )
