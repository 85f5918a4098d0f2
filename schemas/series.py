"""Series of runs: repeats of one test, or a comparison by a named factor, and their
statistics (what ``/series`` takes and answers)."""

from __future__ import annotations

import re
import secrets
from datetime import datetime
from enum import StrEnum
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, StringConstraints, model_validator

from schemas.quantity import quantity
from schemas.runs import RunId, RunState
from schemas.stands import StandKind
from schemas.wire import Text

SERIES_ID_PATTERN = r"^s-[0-9a-f]{12}$"
_SERIES_ID = re.compile(SERIES_ID_PATTERN)

#: Runs a series may hold: its statistics and report are computed on request.
SERIES_RUNS_LIMIT = 100

SeriesId = Annotated[str, StringConstraints(pattern=SERIES_ID_PATTERN, max_length=14)]
Level = Annotated[Text, StringConstraints(min_length=1, max_length=100)]


def new_series_id() -> str:
    return f"s-{secrets.token_hex(6)}"


def is_series_id(text: str) -> bool:
    return bool(_SERIES_ID.match(text))


class SeriesPurpose(StrEnum):
    REPEATABILITY = "repeatability"
    COMPARISON = "comparison"
    LAB = "lab"
    """One lab work of several runs, each at the manual's part it belongs to (its level):
    lab 2's wear run (part 1) and its adhesive and oxidative runs (part 2)."""


#: The manual's parts of a lab work of several runs, by the level naming each run (lab 2:
#: part 1 the wear test, part 2 the adhesive against the oxidative test).
LAB_PARTS: dict[StandKind, dict[str, int]] = {
    StandKind.SMTS2: {"wear": 1, "adhesive": 2, "oxidative": 2},
}


class SeriesCreate(BaseModel):
    """What opens a series; a comparison names its factor (oil, material, load, operator)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "examples": [
                {
                    "name": "Wear of St3sp on R9, groups 1-3",
                    "purpose": "repeatability",
                    "notes": "300 N, 1000 rpm, 15 000 rev; fresh pins",
                },
                {
                    "name": "MTOS: I-20A against I-40A",
                    "purpose": "comparison",
                    "factor": "oil",
                },
            ]
        },
    )

    name: Annotated[Text, StringConstraints(min_length=1, max_length=200)]
    purpose: SeriesPurpose
    factor: Annotated[Text, StringConstraints(min_length=1, max_length=100)] | None = Field(
        default=None, description="the factor compared (comparison only), e.g. oil or load"
    )
    notes: Annotated[Text, StringConstraints(max_length=5000)] = ""

    @model_validator(mode="after")
    def _factor_with_comparison(self) -> SeriesCreate:
        if self.purpose is SeriesPurpose.COMPARISON and self.factor is None:
            raise ValueError("a comparison names its factor (e.g. 'oil', 'load')")
        if self.purpose is not SeriesPurpose.COMPARISON and self.factor is not None:
            raise ValueError(
                f"a {self.purpose.value} series has no factor: only a comparison names one"
            )
        return self


class SeriesMemberAdd(BaseModel):
    """A run joins a series; in a comparison, at a level of the factor (e.g. 'I-20A'); in a
    lab work, at the manual's part it is (lab 2: 'wear', 'adhesive', 'oxidative')."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{"run_id": "20261122T114026Z-1a2b3c4d", "level": "I-20A"}]},
    )

    run_id: RunId
    level: Level | None = None


class SeriesMember(BaseModel):
    run_id: RunId
    level: str | None = None
    added: datetime


class Series(BaseModel):
    """A series as stored: what it is for and its runs, in the order they joined."""

    id: SeriesId
    name: str
    purpose: SeriesPurpose
    factor: str | None = None
    notes: str = ""
    created: datetime
    members: list[SeriesMember] = Field(default_factory=list)


class GrubbsResult(BaseModel):
    """Grubbs' test for one outlier (ASTM E178): flagged, never removed."""

    statistic: float = Field(description="G = max|x_i - x̄|/s")
    critical: float = Field(description="G_crit at the significance level")
    alpha: float = Field(description="significance level")
    run_id: str = Field(description="the run farthest from the mean")
    flagged: bool = Field(False, description="Grubbs' statistic exceeds its critical value")
    deviation: float | None = Field(
        None, description="the run's value less the mean of the other runs, same unit"
    )
    explained: float | None = Field(
        None,
        description="2·√(u² + u_rest²): the expanded uncertainty of that deviation from the "
        "runs' own standard uncertainties (None where the runs carry none)",
    )
    outlier: bool = Field(
        description="flagged by Grubbs and the deviation larger than the runs' own expanded "
        "uncertainty explains (docs/series.md)"
    )


class Summary(BaseModel):
    """The spread of one result over the runs (or over the runs of one level)."""

    n: int
    mean: float
    std: float | None = Field(None, description="sample standard deviation s")
    sem: float | None = Field(None, description="standard error of the mean s/√n")
    ci_low: float | None = Field(None, description="lower end of the confidence interval")
    ci_high: float | None = Field(None, description="upper end of the confidence interval")
    confidence: float = Field(description="confidence level of the interval (Student's t)")
    grubbs: GrubbsResult | None = None


class LevelSummary(BaseModel):
    level: str
    summary: Summary


class ComparisonResult(BaseModel):
    """Welch's t-test (two levels) or one-way ANOVA (more) on one result."""

    test: Literal["welch", "anova"]
    statistic: float = Field(description="t (Welch) or F (ANOVA)")
    df: list[float] = Field(description="degrees of freedom")
    p_value: float
    significant: bool = Field(description="p below 1 - confidence")
    difference: float | None = Field(None, description="second level's mean minus the first's")
    difference_low: float | None = None
    difference_high: float | None = None


class RunValue(BaseModel):
    """One run's value of a result, with its own standard uncertainty where it has one."""

    run_id: str
    level: str | None = None
    value: float
    uncertainty: float | None = Field(None, description="the run's own uncertainty, same unit")


Untested = Literal["no_values", "one_level", "few_runs", "no_spread"]


class ResultStatistics(BaseModel):
    """The statistics of one headline result across the series."""

    key: str = Field(description="path of the result in a run's results, e.g. friction_steady")
    symbol: str = Field(description="the manual's symbol; per load step with the step's number")
    unit: str
    description: str
    values: list[RunValue]
    overall: Summary | None = None
    repeatability_std: float | None = Field(
        None, description="s_r, the within-level standard deviation pooled over levels"
    )
    levels: list[LevelSummary] = Field(default_factory=list)
    comparison: ComparisonResult | None = None
    untested: Untested | None = Field(
        None, description="why no statistics, or no comparison of the levels, were possible"
    )
    notes: list[str] = Field(default_factory=list)


class SeriesRun(BaseModel):
    """A row of the per-run table."""

    run_id: str
    level: str | None = None
    stand: StandKind
    state: RunState
    operator: str
    title: str = ""
    created: datetime
    values: dict[str, float | None]


class AdhesiveOxidative(BaseModel):
    """Lab work 2's adhesive and oxidative runs compared (2.16): a series whose two levels
    are the adhesive and the oxidative mode, by level name or the runs' test plan."""

    f_adhesive: float = quantity(..., "1", "f_a, mean steady friction of the adhesive runs")
    f_oxidative: float = quantity(..., "1", "f_ok, mean steady friction of the oxidative runs")
    f_adhesive_uncertainty: float | None = quantity(
        None, "1", "u(f_a), standard, of the mean of the adhesive runs' own u"
    )
    f_oxidative_uncertainty: float | None = quantity(
        None, "1", "u(f_ok), standard, of the mean of the oxidative runs' own u"
    )
    difference: float = quantity(..., "%", "Δf = (f_a - f_ok)/f_a (2.16)")
    difference_uncertainty: float | None = quantity(
        None, "%", "u(Δf), standard, propagated from u(f_a) and u(f_ok) (GUM 5.1.2)"
    )
    runs: dict[str, int] = Field(default_factory=dict, description="runs of each mode")


class SeriesDetail(Series):
    """A series with its runs and the statistics of every headline result."""

    stand: StandKind | None = Field(None, description="the stand of its runs (one per series)")
    runs: list[SeriesRun] = Field(default_factory=list)
    statistics: list[ResultStatistics] = Field(default_factory=list)
    open_runs: int = Field(0, description="member runs still open (their figures may change)")
    identical: list[list[str]] = Field(
        default_factory=list,
        description="groups of runs whose headline results are all identical: copied data",
    )
    missing: list[str] = Field(
        default_factory=list, description="member runs that could not be read, and why"
    )
    adhesive_oxidative: AdhesiveOxidative | None = Field(
        None, description="SMTs-2: f_a, f_ok and Δf (2.16) when the levels are the two modes"
    )
