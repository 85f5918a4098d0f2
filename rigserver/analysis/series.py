"""A series' statistics: each headline result of its runs gathered and summarised.

Every stand's kit declares the results a series compares (``Kit.series`` in
:mod:`rigserver.analysis.kits`): a path into the run's results (``experimental.intensity``;
``steps[].friction_measured`` stands for one result per load step) and, where the run
reports one, the path of its own standard uncertainty. Aborted runs are listed but left out
of the statistics; open runs count with what they hold so far.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from rigserver.analysis.kits import KITS, Headline
from rigserver.core import statistics, wear
from schemas.labels import Label, round_to
from schemas.quantity import description_paths, unit_paths
from schemas.runs import Run, RunState
from schemas.series import (
    AdhesiveOxidative,
    ComparisonResult,
    GrubbsResult,
    LevelSummary,
    ResultStatistics,
    RunValue,
    Series,
    SeriesDetail,
    SeriesPurpose,
    SeriesRun,
    Summary,
    Untested,
)
from schemas.stands import DECLARATIONS, StandKind

#: Why a result's levels were not compared, as the API says it (the pages translate the code).
UNTESTED: dict[Untested, str] = {
    "no_values": "no run has this result yet",
    "one_level": "a comparison needs runs at two levels or more",
    "few_runs": "a comparison needs at least two runs at every level",
    "no_spread": "the runs within each level agree exactly: no spread to test against",
}

#: Paths of a list of per-step results: one headline per step, keyed by the step's index.
_EACH = "[]"


@dataclass(frozen=True, slots=True)
class Member:
    """A run of the series as the statistics see it: its metadata, level and results."""

    run: Run
    level: str | None
    values: Mapping[str, Any] | None


def series_statistics(
    series: Series, members: Sequence[Member], missing: list[str]
) -> SeriesDetail:
    """The series with its per-run table and the statistics of every headline result.

    ``members`` are the runs that could be read, in the order they joined; ``missing``
    says which could not, and why.
    """
    stand = members[0].run.stand if members else None
    keys = _keys(stand, members) if stand else []
    rows = [
        SeriesRun(
            run_id=m.run.id,
            level=m.level,
            stand=m.run.stand,
            state=m.run.state,
            operator=m.run.operator,
            title=m.run.title,
            created=m.run.created,
            values={key: _number(m.values, key) for key, _ in keys},
        )
        for m in members
    ]
    counted = [m for m in members if m.run.state is not RunState.ABORTED and m.values is not None]
    comparison = series.purpose is not SeriesPurpose.REPEATABILITY  # levels of their own
    units = unit_paths(DECLARATIONS[stand].results) if stand else {}
    described = description_paths(DECLARATIONS[stand].results) if stand else {}
    statistics_ = [
        _result_statistics(key, headline, counted, comparison, units, described)
        for key, headline in keys
    ]
    return SeriesDetail(
        **series.model_dump(),
        stand=stand,
        runs=rows,
        statistics=statistics_,
        open_runs=sum(m.run.state is RunState.OPEN for m in members),
        missing=missing,
        identical=identical_runs(rows),
        adhesive_oxidative=adhesive_oxidative(counted) if stand is StandKind.SMTS2 else None,
    )


#: The two modes of lab work 2's second part, (2.16).
_MODES = ("adhesive", "oxidative")


def _mode(member: Member) -> str | None:
    """A run's mode: its level's name if it is one of the modes, else its test plan's."""
    level = (member.level or "").strip().lower()
    if level in _MODES:
        return level
    planned = member.run.test_plan.get("mode") if member.run.test_plan else None
    return planned if planned in _MODES else None


def adhesive_oxidative(members: Sequence[Member]) -> AdhesiveOxidative | None:
    """f_a, f_ok (the levels' mean steady friction) and Δf (2.16) with its uncertainty, when
    the series' runs of the two modes fall into two levels, one of each (a lab work's wear
    run, at a level of its own, is left aside); None otherwise."""
    by_level: dict[str, set[str | None]] = {}
    friction: dict[str, list[tuple[float, float | None]]] = {}
    for m in members:
        mode = _mode(m)
        by_level.setdefault(m.level or "", set()).add(mode)
        f = _number(m.values, "friction_steady")
        if mode is not None and f is not None:
            u = _number(m.values, "friction_steady_uncertainty")
            friction.setdefault(mode, []).append((f, u))
    moded = [found for found in by_level.values() if found & set(_MODES)]
    modes = sorted(next(iter(found)) or "" for found in moded if len(found) == 1)
    if len(moded) != 2 or modes != list(_MODES) or any(not friction.get(k) for k in _MODES):
        return None
    f_a, f_ok = (float(np.mean([f for f, _ in friction[k]])) for k in _MODES)
    u_a, u_ok = (_mean_uncertainty([u for _, u in friction[k]]) for k in _MODES)
    u = (
        None
        if u_a is None or u_ok is None
        else wear.adhesive_oxidative_uncertainty(
            f_adhesive=f_a, f_oxidative=f_ok, u_adhesive=u_a, u_oxidative=u_ok
        )
    )
    return AdhesiveOxidative(
        f_adhesive=f_a,
        f_oxidative=f_ok,
        f_adhesive_uncertainty=u_a,
        f_oxidative_uncertainty=u_ok,
        difference=wear.adhesive_oxidative_difference(f_adhesive=f_a, f_oxidative=f_ok),
        difference_uncertainty=u,
        runs={k: len(friction[k]) for k in _MODES},
    )


def _mean_uncertainty(own: Sequence[float | None]) -> float | None:
    """The standard uncertainty of the mean of independent runs, √(Σu_i²)/n (GUM 5.1.2);
    None unless every run states its own."""
    if not own or any(u is None for u in own):
        return None
    return math.sqrt(sum(u * u for u in own if u is not None)) / len(own)


def identical_runs(rows: Sequence[SeriesRun]) -> list[list[str]]:
    """Groups of two runs or more whose headline results are all present and identical to
    the last digit: two specimens never give that, copied data does."""
    groups: dict[tuple[tuple[str, float], ...], list[str]] = {}
    for row in rows:
        found = tuple(sorted((k, v) for k, v in row.values.items() if v is not None))
        if found:
            groups.setdefault(found, []).append(row.run_id)
    return [ids for ids in groups.values() if len(ids) > 1]


def _keys(stand: StandKind, members: Sequence[Member]) -> list[tuple[str, Headline]]:
    """Each headline's keys: its path, or one path per step for a per-step result."""
    keys: list[tuple[str, Headline]] = []
    for headline in KITS[stand].series:
        if _EACH not in headline.path:
            keys.append((headline.path, headline))
            continue
        head, _, _ = headline.path.partition(_EACH)
        steps = max((len(_resolve(m.values, head) or []) for m in members), default=0)
        keys.extend((headline.path.replace(_EACH, f"[{i}]", 1), headline) for i in range(steps))
    return keys


def _result_statistics(
    key: str,
    headline: Headline,
    members: Sequence[Member],
    comparison: bool,
    units: Mapping[str, str],
    described: Mapping[str, str],
) -> ResultStatistics:
    generic = _generic(key)
    values = [
        RunValue(
            run_id=m.run.id,
            level=m.level,
            value=value,
            uncertainty=_uncertainty(m.values, key, headline),
        )
        for m in members
        if (value := _number(m.values, key)) is not None
    ]
    result = ResultStatistics(
        key=key,
        symbol=_symbol(key, headline),
        unit=units.get(generic, "1"),
        description=described.get(generic, key),
        values=values,
    )
    if not values:
        result.untested = "no_values"
        result.notes.append(UNTESTED["no_values"])
        return result
    numbers = [v.value for v in values]
    label = label_of(members[0].run.stand, key)
    digits = label.digits if label is not None else 4
    own = [v.uncertainty for v in values]
    if not comparison:  # a comparison's levels differ by design: never one pooled interval
        result.overall = _summary(numbers, [v.run_id for v in values], digits, own)
    levels: dict[str, list[RunValue]] = {}
    for v in values:
        levels.setdefault(v.level or "", []).append(v)
    groups = [[v.value for v in group] for group in levels.values()]
    result.repeatability_std = statistics.pooled_standard_deviation(groups)
    if comparison:
        result.levels = [
            LevelSummary(
                level=name,
                summary=_summary([v.value for v in group], [v.run_id for v in group], digits),
            )
            for name, group in levels.items()
        ]
        result.untested = _untested(levels, result.repeatability_std)
        if result.untested is None:
            result.comparison = _comparison(levels)
        else:
            result.notes.append(UNTESTED[result.untested])
    return result


def _summary(
    values: list[float],
    run_ids: list[str],
    digits: int,
    own: Sequence[float | None] = (),
) -> Summary:
    """The summary of the values; Grubbs' test only on three values or more that differ as
    printed (to the result's declared digits): values that differ below that are ties of
    the instruments' resolution, which the test would flag by rounding alone. A run Grubbs
    flags is an outlier only where its deviation from the other runs' mean exceeds the
    expanded uncertainty the runs' own standard uncertainties give it (:func:`_explained`)."""
    found = statistics.summarise(values)
    distinct = len({round_to(v, digits) for v in values})
    test = found.grubbs if distinct >= 3 else None
    deviation = explained = None
    if test is not None:
        rest = [v for i, v in enumerate(values) if i != test.index]
        deviation = values[test.index] - sum(rest) / len(rest)
        explained = _explained(test.index, list(own))
    return Summary(
        n=found.n,
        mean=found.mean,
        std=found.std,
        sem=found.sem,
        ci_low=found.ci_low,
        ci_high=found.ci_high,
        confidence=found.confidence,
        grubbs=None
        if test is None
        else GrubbsResult(
            statistic=test.statistic,
            critical=test.critical,
            alpha=test.alpha,
            run_id=run_ids[test.index],
            flagged=test.outlier,
            deviation=deviation,
            explained=explained,
            outlier=test.outlier
            and (explained is None or deviation is None or abs(deviation) > explained),
        ),
    )


def _explained(index: int, own: list[float | None]) -> float | None:
    """U = 2·√(u_i² + u_rest²), u_rest = √(Σ_{j≠i} u_j²)/(n - 1): the expanded (k = 2)
    uncertainty of the deviation of run ``index`` from the mean of the others, from each
    run's own standard uncertainty; None unless every run has one (GUM, uncorrelated)."""
    if len(own) < 2 or any(u is None for u in own):
        return None
    u = [float(x) for x in own if x is not None]
    rest = [x for j, x in enumerate(u) if j != index]
    u_rest = math.sqrt(sum(x * x for x in rest)) / len(rest)
    return 2.0 * math.sqrt(u[index] ** 2 + u_rest**2)


def _untested(
    levels: Mapping[str, list[RunValue]], repeatability_std: float | None
) -> Untested | None:
    """Why the levels cannot be compared (None when they can)."""
    if len(levels) < 2:
        return "one_level"
    if min(len(group) for group in levels.values()) < 2:
        return "few_runs"
    if not repeatability_std:
        return "no_spread"
    return None


def _comparison(levels: Mapping[str, list[RunValue]]) -> ComparisonResult:
    found = statistics.compare({k: [v.value for v in g] for k, g in levels.items()})
    return ComparisonResult(
        test="welch" if found.test == "welch" else "anova",
        statistic=found.statistic,
        df=list(found.df),
        p_value=found.p_value,
        significant=found.significant,
        difference=found.difference,
        difference_low=found.difference_low,
        difference_high=found.difference_high,
    )


def label_of(stand: StandKind, key: str) -> Label | None:
    """The label (schemas.labels) of a headline result: ``steps[3].chi`` -> ``steps[].chi``."""
    return DECLARATIONS[stand].labels.get(_generic(key))


def _symbol(key: str, headline: Headline) -> str:
    """``f_e`` of the load step ``steps[2]`` -> ``f_{e,3}`` (steps counted from 1)."""
    if _EACH not in headline.path:
        return headline.symbol
    step = int(key.partition("[")[2].partition("]")[0]) + 1
    base, _, sub = headline.symbol.partition("_")
    return f"{base}_{{{sub.strip('{}')},{step}}}" if sub else f"{base}_{step}"


def _generic(key: str) -> str:
    """``steps[3].chi`` -> ``steps[].chi``: the path the units and descriptions use."""
    head, bracket, rest = key.partition("[")
    if not bracket:
        return key
    _, _, tail = rest.partition("]")
    return f"{head}[]{tail}"


def _resolve(values: Mapping[str, Any] | None, path: str) -> Any:
    node: Any = values
    for part in path.split("."):
        name, bracket, index = part.partition("[")
        if not isinstance(node, Mapping):
            return None
        node = node.get(name)
        if bracket:
            if not isinstance(node, list):
                return None
            i = int(index.rstrip("]"))
            node = node[i] if i < len(node) else None
    return node


def _number(values: Mapping[str, Any] | None, path: str) -> float | None:
    node = _resolve(values, path)
    if isinstance(node, bool) or not isinstance(node, int | float):
        return None
    return float(node) if math.isfinite(node) else None


def _uncertainty(values: Mapping[str, Any] | None, key: str, headline: Headline) -> float | None:
    """The run's own standard uncertainty of the result ``key`` (per step: of that step)."""
    if headline.uncertainty is None:
        return None
    step = key[key.find("[") : key.find("]") + 1] if _EACH in headline.path else _EACH
    return _number(values, headline.uncertainty.replace(_EACH, step, 1))
