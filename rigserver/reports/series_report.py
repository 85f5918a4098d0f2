"""The series report (HTML, and PDF from the same page) and the per-run table as CSV.

The report holds what a lab needs to judge a series: the runs with their levels, the
statistics of every headline result (n, mean, s, the standard error, the 95 % interval of
the mean, s_r, Grubbs' test; per level and the comparison's test where the series compares
a factor), each run's own uncertainty beside the spread where it has one, and the overlay
plots of the stand's curves.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from datetime import datetime
from typing import Any

import numpy as np
from markupsafe import Markup

from rigserver.analysis import Readings
from rigserver.analysis.series import label_of
from rigserver.reports import results_view
from rigserver.reports.blocks import axis
from rigserver.reports.formatting import (
    fmt,
    number_locale,
    shown,
    shown_column,
    spreadsheet_text,
)
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.kits import KITS
from rigserver.reports.render import render
from rigserver.reports.series_plots import Curve, overlay
from schemas.labels import Label
from schemas.messages import N_, NP_
from schemas.series import ResultStatistics, SeriesDetail, SeriesPurpose, SeriesRun
from schemas.stands import StandKind
from schemas.units import UNITS

#: The report's own texts by key: English, the message ids of the catalogs
#: (``rigserver/locale``).
TEXT: dict[str, str] = {
    "title": N_("Series report"),
    "repeatability": N_("repeatability (repeats of one test)"),
    "comparison": N_("comparison by {factor}"),
    "lab": N_("one lab work of several runs, each at its part of the manual's work"),
    "by_level": N_("by level only: the levels differ by design (see the comparison below)"),
    "stand": N_("Stand"),
    "purpose": N_("Purpose"),
    "made": N_("Report made"),
    "sec.runs": N_("Runs"),
    "sec.statistics": N_("Statistics of the results"),
    "sec.spread": N_("Spread of the runs against their instruments"),
    "sec.comparison": N_("Comparison of the levels"),
    "sec.plots": N_("Overlay plots"),
    "run": N_("Run"),
    "level": N_("Factor level"),
    "state": N_("State"),
    "operator": N_("Operator"),
    "result": N_("Result"),
    "unit": N_("Unit"),
    "n": N_("n"),
    "mean": N_("mean x̄"),
    "std": N_("s"),
    "sem": N_("s/√n"),
    "ci": N_("95 % interval of the mean"),
    "s_r": N_("s_r"),
    "u_runs": N_("runs' own u (mean)"),
    "grubbs": N_("Grubbs (E178)"),
    "outlier": N_("outlier: {run}"),
    "no_outlier": N_("none"),
    "beyond": N_("|Δ| = {d} > U = {u} of the runs"),
    "explained": N_(
        "G flags {run}, but its |Δ| = {d} ≤ U = {u} the runs' own uncertainties explain: no outlier"
    ),
    "identical": N_("Identical data"),
    "identical_runs": N_("the runs {runs} have identical results, to the last digit: copied data?"),
    "adhesive_oxidative": N_("Adhesive and oxidative friction (2.16)"),
    "adhesive_oxidative_values": N_(
        "f_a = {f_a} (adhesive runs), f_ok = {f_ok} (oxidative runs), "
        "Δf = (f_a − f_ok)/f_a·100 % = {df} %"
    ),
    "test": N_("Test"),
    "welch": N_("Welch's t"),
    "anova": N_("one-way ANOVA, F"),
    "statistic": N_("statistic"),
    "p": N_("p"),
    "difference": N_("difference of means (95 % interval)"),
    "significant": N_("significant at 5 %"),
    "yes": N_("yes"),
    "no": N_("no"),
    "missing": N_("Runs that could not be read"),
    "empty": N_("The series has no runs yet."),
    "none": N_("No series yet."),
    "why.no_values": N_("no run has this result yet"),
    "why.one_level": N_("a comparison needs runs at two levels or more"),
    "why.few_runs": N_("a comparison needs at least two runs at every level"),
    "why.no_spread": N_("the runs within each level agree exactly: no spread to test against"),
    "runs_csv": N_("Runs and their results, CSV"),
    "mean_curve": N_("mean"),
    "plot.friction": N_("f against the sliding distance L (time scaled by the run's L)"),
    "plot.tribometer": N_("μ against the sliding distance L"),
    "plot.mtos_f": N_("f_e against the load N"),
    "plot.stribeck": N_("f_e against S_1 (Hersey-Stribeck)"),
    "plot.pressure": N_("Π_e against φ (z = 0)"),
    "plot.bearing": N_("Bearing curves t_p(ε)"),
    "plot.profile": N_("Profiles y(x)"),
    "state.open": N_("open"),
    "state.finished": N_("finished"),
    "state.aborted": N_("aborted"),
}

#: The runs of a series still open, by their number (one run "is", two "are").
OPEN_RUNS = NP_(
    "{n} of the runs is still open: its figures may change.",
    "{n} of the runs are still open: their figures may change.",
)

#: Per-step results (``steps[3].chi``) are in the statistics table only, not in the runs'.
_PER_STEP = "["


def text(lang: Lang) -> Callable[..., str]:
    """The report's texts in ``lang``: ``s("title")``, ``s("comparison", factor=...)``."""
    translations = Messages(lang)

    def t(key: str, **values: object) -> str:
        return translations.gettext(TEXT[key]).format(**values)

    return t


def series_csv(detail: SeriesDetail) -> str:
    """One row per run: id, level, state, operator, start, then every headline result
    (``key [unit]``, in its display unit: mm³, mg, µm) at full precision; empty where a run
    lacks it. A text cell that a spreadsheet would take for a formula (``=HYPERLINK(...)``
    for a level) starts with ``'`` (:func:`~rigserver.reports.formatting.spreadsheet_text`)."""
    out = io.StringIO()
    writer = csv.writer(out)
    shown_in: dict[str, tuple[str, float]] = {}
    for stats in detail.statistics:
        label = label_of(detail.stand, stats.key) if detail.stand else None
        unit = label.unit if label is not None else stats.unit
        shown_in[stats.key] = (unit, UNITS[stats.unit].factor / UNITS[unit].factor)
    writer.writerow(
        [
            "run_id",
            "level",
            "state",
            "operator",
            "created",
            *(f"{key} [{unit}]" for key, (unit, _) in shown_in.items()),
        ]
    )
    for row in detail.runs:
        values = [
            "" if (value := row.values.get(key)) is None else repr(value * factor)
            for key, (_, factor) in shown_in.items()
        ]
        when = row.created.isoformat()
        texts = [row.run_id, row.level or "", row.state.value, row.operator, when]
        writer.writerow([*(spreadsheet_text(cell) for cell in texts), *values])
    return out.getvalue()


def series_context(
    detail: SeriesDetail,
    *,
    values: Mapping[str, Mapping[str, Any] | None],
    readings: Mapping[str, Readings],
    lang: Lang,
) -> dict[str, Any]:
    """What the report and the series page show: the tables and the overlay plots.

    ``values`` are each run's results (by run id), ``readings`` each run's readings (for
    the profiles of the profilometer)."""
    t = text(lang)
    m = Messages(lang)
    with number_locale(lang):
        rows = [
            _statistics_row(detail.stand, s, m, _step(m, s.key, values)) for s in detail.statistics
        ]
        for row in rows:  # the runs' table: each result's column with one number of decimals
            cells = [r.values.get(row["stats"].key) for r in detail.runs]
            printed = shown_column(row["label"], cells, row["stats"].unit)
            row["cells"] = dict(zip((r.run_id for r in detail.runs), printed, strict=True))
        plots = _plots(detail, values, readings, t, m)
    purpose = {
        SeriesPurpose.COMPARISON: t("comparison", factor=detail.factor or ""),
        SeriesPurpose.REPEATABILITY: t("repeatability"),
        SeriesPurpose.LAB: t("lab"),
    }[detail.purpose]
    return {
        "lang": lang,
        "t": t,
        "fmt": fmt,
        "detail": detail,
        "purpose": purpose,
        "stand_name": m(f"stand.{detail.stand.value}") if detail.stand else None,
        "rows": rows,
        "run_columns": [r for r in rows if _PER_STEP not in r["stats"].key],
        "own_uncertainty": any(r["own_uncertainty"] is not None for r in rows),
        "plots": plots,
        "open_runs": m.plural(*OPEN_RUNS, detail.open_runs).format(n=detail.open_runs),
    }


def render_series_report(context: Mapping[str, Any], *, made: datetime) -> str:
    """The series report as a standalone HTML page (and the PDF's source)."""
    with number_locale(context["lang"]):
        return render("series.html", made=made, **context)


def render_series_body(context: Mapping[str, Any]) -> Markup:
    """The report's tables and plots, for the series page: the plots as images (``data:``
    URLs), since a page's Content-Security-Policy refuses the inline styles of an SVG."""
    with number_locale(context["lang"]):
        return Markup(render("series_body.html", as_images=True, **context))


def _step(m: Messages, key: str, values: Mapping[str, Mapping[str, Any] | None]) -> str:
    """``, step 3, N = 1500 N`` of a per-step result (``steps[2].chi``), as the run report's
    uncertainty table names the step: its load from the first run that has the step."""
    if _PER_STEP not in key:
        return ""
    index = int(key.partition("[")[2].partition("]")[0])
    for found in values.values():
        steps = (found or {}).get("steps") or []
        if index < len(steps) and steps[index].get("load") is not None:
            return m("u.step", i=index + 1, load=fmt(steps[index]["load"]))
    return ""


def _statistics_row(
    stand: StandKind | None, stats: ResultStatistics, m: Messages, step: str
) -> dict[str, Any]:
    """A headline result as the tables print it: its label's words (and ``step``, the load
    step a per-step result belongs to), symbol and display unit (schemas.labels), and a
    formatter of its values (and spreads) in that unit."""
    label = label_of(stand, stats.key) if stand else None
    if label is None:
        label = Label(stats.description, stats.symbol, unit=stats.unit)  # type: ignore[arg-type]
    own = [v.uncertainty for v in stats.values if v.uncertainty is not None]

    def show(value: float | None, uncertainty: float | None = None) -> str:
        """A value in the label's unit; to the place of ``uncertainty`` when given (GUM
        7.2.6: a mean to its standard error, a spread to its own two digits)."""
        return "—" if value is None else shown(label, value, stats.unit, uncertainty)

    return {
        "stats": stats,
        "label": label,
        "symbol": m.symbol(stats.symbol),
        "name": results_view.name(m, label) + step,
        "unit": results_view.unit(m, label),
        "show": show,
        "own_uncertainty": float(np.mean(own)) if own else None,
    }


def _plots(
    detail: SeriesDetail,
    values: Mapping[str, Mapping[str, Any] | None],
    readings: Mapping[str, Readings],
    t: Callable[..., str],
    m: Messages,
) -> list[tuple[str, str]]:
    by_level: dict[str, list[str]] = {}
    for row in detail.runs:
        if values.get(row.run_id) is not None:
            by_level.setdefault(row.level or "", []).append(row.run_id)
    if not by_level:
        return []

    names = run_names(detail.runs)

    def curves(extract: Callable[[str], Curve | None]) -> dict[str, list[Curve]]:
        found = {
            level: [replace(c, label=names[run]) for run in runs if (c := extract(run)) is not None]
            for level, runs in by_level.items()
        }
        return {level: cs for level, cs in found.items() if cs}

    def draw(key: str, xlabel: str, ylabel: str, found: dict[str, list[Curve]], **kw: Any) -> None:
        if found:
            plots.append(
                (
                    t(key),
                    overlay(found, xlabel=xlabel, ylabel=ylabel, mean_label=t("mean_curve"), **kw),
                )
            )

    plots: list[tuple[str, str]] = []
    for plot in KITS[detail.stand].series_plots if detail.stand else ():
        found = curves(plot.of(values, readings))
        draw(
            plot.caption,
            axis(m, *plot.x),
            axis(m, *plot.y),
            found,
            markers=plot.markers,
            paired=plot.paired,
        )
    return plots


def run_names(runs: Sequence[SeriesRun]) -> dict[str, str]:
    """Each run as a legend names it: its operator (the students' group) and the date it
    started, ``Group 3, 2026-11-25``; runs of one operator on one day add the time they
    started, and runs that share that too their place in the table of runs (``(2)``)."""
    day = [f"{r.operator}, {r.created:%Y-%m-%d}" for r in runs]
    clock = [f"{r.operator}, {r.created:%Y-%m-%d %H:%M}" for r in runs]
    found: dict[str, str] = {}
    for place, run in enumerate(runs):
        if day.count(day[place]) == 1:
            found[run.run_id] = day[place]
        elif clock.count(clock[place]) == 1:
            found[run.run_id] = clock[place]
        else:
            found[run.run_id] = f"{day[place]} ({place + 1})"
    return found
