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
from collections.abc import Callable, Mapping
from datetime import datetime
from typing import Any

import numpy as np
from markupsafe import Markup

from rigserver.analysis import Readings
from rigserver.reports.blocks import axis
from rigserver.reports.downsample import min_max
from rigserver.reports.formatting import fmt
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.render import render
from rigserver.reports.series_plots import Curve, overlay
from schemas.series import ResultStatistics, SeriesDetail, SeriesPurpose
from schemas.stands import StandKind

#: The report's own texts, English and Russian.
TEXT: dict[str, tuple[str, str]] = {
    "title": ("Series report", "Отчёт по серии испытаний"),
    "repeatability": ("repeatability (repeats of one test)", "повторяемость (повторные испытания)"),
    "comparison": ("comparison by {factor}", "сравнение по фактору «{factor}»"),
    "stand": ("Stand", "Стенд"),
    "purpose": ("Purpose", "Назначение"),
    "made": ("Report made", "Отчёт составлен"),
    "open_runs": (
        "{n} of the runs are still open: their figures may change.",
        "Испытаний ещё не завершено: {n}; их значения могут измениться.",
    ),
    "sec.runs": ("Runs", "Испытания"),
    "sec.statistics": ("Statistics of the results", "Статистика результатов"),
    "sec.comparison": ("Comparison of the levels", "Сравнение уровней"),
    "sec.plots": ("Overlay plots", "Совмещённые графики"),
    "run": ("Run", "Испытание"),
    "level": ("Level", "Уровень"),
    "state": ("State", "Состояние"),
    "operator": ("Operator", "Оператор"),
    "result": ("Result", "Результат"),
    "unit": ("Unit", "Ед."),
    "n": ("n", "n"),
    "mean": ("mean x̄", "среднее x̄"),
    "std": ("s", "s"),
    "sem": ("s/√n", "s/√n"),
    "ci": ("95 % interval of the mean", "95 % интервал среднего"),
    "s_r": ("s_r", "s_r"),
    "u_runs": ("runs' own u (mean)", "собственная u испытаний (средняя)"),
    "grubbs": ("Grubbs (E178)", "Граббс (E178)"),
    "outlier": ("outlier: {run}", "выброс: {run}"),
    "no_outlier": ("none", "нет"),
    "test": ("Test", "Критерий"),
    "welch": ("Welch's t", "t Уэлча"),
    "anova": ("one-way ANOVA, F", "дисперсионный анализ, F"),
    "statistic": ("statistic", "статистика"),
    "p": ("p", "p"),
    "difference": ("difference of means (95 % interval)", "разность средних (95 % интервал)"),
    "significant": ("significant at 5 %", "значимо при 5 %"),
    "yes": ("yes", "да"),
    "no": ("no", "нет"),
    "missing": ("Runs that could not be read", "Испытания, которые не удалось прочитать"),
    "empty": ("The series has no runs yet.", "В серии ещё нет испытаний."),
    "none": ("No series yet.", "Серий пока нет."),
    "why.no_values": (
        "no run has this result yet",
        "ни в одном испытании этого результата ещё нет",
    ),
    "why.one_level": (
        "a comparison needs runs at two levels or more",
        "для сравнения нужны испытания хотя бы на двух уровнях",
    ),
    "why.few_runs": (
        "a comparison needs at least two runs at every level",
        "для сравнения нужно не меньше двух испытаний на каждом уровне",
    ),
    "why.no_spread": (
        "the runs within each level agree exactly: no spread to test against",
        "испытания внутри уровней совпадают точно: разброса для критерия нет",
    ),
    "runs_csv": ("Runs and their results, CSV", "Испытания и их результаты, CSV"),
    "mean_curve": ("mean", "среднее"),
    "plot.friction": (
        "f against the sliding distance L (time scaled by the run's L)",
        "f в зависимости от пути трения L (время, приведённое к L испытания)",
    ),
    "plot.mtos_f": ("f_э against the load N", "f_э в зависимости от нагрузки N"),
    "plot.stribeck": (
        "f_э against S_1 (Hersey-Stribeck)",
        "f_э в зависимости от S_1 (диаграмма Герси-Штрибека)",
    ),
    "plot.pressure": ("Π_э against φ (z = 0)", "Π_э в зависимости от φ (z = 0)"),
    "plot.bearing": ("Bearing curves t_p(ε)", "Опорные кривые t_p(ε)"),
    "plot.profile": ("Profiles y(x)", "Профилограммы y(x)"),
    "state.open": ("open", "идёт"),
    "state.finished": ("finished", "завершено"),
    "state.aborted": ("aborted", "прервано"),
}

#: Per-step results (``steps[3].chi``) are in the statistics table only, not in the runs'.
_PER_STEP = "["
#: Points of a profile drawn per run (min-max decimation; the statistics use every reading).
PROFILE_POINTS = 800


def text(lang: Lang) -> Callable[..., str]:
    index = 0 if lang == "en" else 1

    def t(key: str, **values: object) -> str:
        return TEXT[key][index].format(**values)

    return t


def series_csv(detail: SeriesDetail) -> str:
    """One row per run: id, level, state, operator, start, then every headline result
    (``key [unit]``) at full precision; empty where a run lacks it."""
    out = io.StringIO()
    writer = csv.writer(out)
    units = {s.key: s.unit for s in detail.statistics}
    keys = list(units)
    writer.writerow(
        ["run_id", "level", "state", "operator", "created", *(f"{k} [{units[k]}]" for k in keys)]
    )
    for row in detail.runs:
        writer.writerow(
            [
                row.run_id,
                row.level or "",
                row.state.value,
                row.operator,
                row.created.isoformat(),
                *("" if row.values.get(k) is None else repr(row.values[k]) for k in keys),
            ]
        )
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
    rows = [_statistics_row(s) for s in detail.statistics]
    purpose = (
        t("comparison", factor=detail.factor or "")
        if detail.purpose is SeriesPurpose.COMPARISON
        else t("repeatability")
    )
    return {
        "lang": lang,
        "t": t,
        "fmt": fmt,
        "unit": Messages(lang).unit,
        "detail": detail,
        "purpose": purpose,
        "rows": rows,
        "run_columns": [r for r in rows if _PER_STEP not in r["stats"].key],
        "own_uncertainty": any(r["own_uncertainty"] is not None for r in rows),
        "plots": _plots(detail, values, readings, t, Messages(lang)),
    }


def render_series_report(context: Mapping[str, Any], *, made: datetime) -> str:
    """The series report as a standalone HTML page (and the PDF's source)."""
    return render("series.html", made=made, **context)


def render_series_body(context: Mapping[str, Any]) -> Markup:
    """The report's tables and plots, for the series page."""
    return Markup(render("series_body.html", **context))


def _statistics_row(stats: ResultStatistics) -> dict[str, Any]:
    own = [v.uncertainty for v in stats.values if v.uncertainty is not None]
    return {
        "stats": stats,
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

    def curves(extract: Callable[[str], Curve | None]) -> dict[str, list[Curve]]:
        found = {
            level: [c for run in runs if (c := extract(run)) is not None]
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
    v = values
    if detail.stand is StandKind.SMTS2:
        draw("plot.friction", axis(m, "L", "m"), axis(m, "f"), curves(lambda r: _friction(r, v[r])))
    elif detail.stand is StandKind.MTOS:
        draw(
            "plot.mtos_f",
            axis(m, "N", "N"),
            axis(m, "f_э"),
            curves(lambda r: _rows(r, v[r], "steps", "load", "friction_measured")),
            paired=True,
        )
        draw(
            "plot.stribeck",
            axis(m, "S_1"),
            axis(m, "f_э"),
            curves(
                lambda r: _rows(r, v[r], "steps", "bearing_characteristic", "friction_measured")
            ),
            paired=True,
        )
    elif detail.stand is StandKind.SLIDE_BEARING:
        draw(
            "plot.pressure",
            axis(m, "φ", "deg"),
            axis(m, "Π_э"),
            curves(lambda r: _rows(r, v[r], "table", "phi_model", "pi_measured")),
            markers=True,
        )
    elif detail.stand is StandKind.PROFILOMETER:
        draw(
            "plot.bearing",
            axis(m, "ε"),
            axis(m, "t_p"),
            curves(lambda r: _pairs(r, v[r], "eps", "tp")),
            markers=True,
        )
        draw(
            "plot.profile",
            axis(m, "x", "mm"),
            axis(m, "y", "um"),
            curves(lambda r: _profile(r, readings.get(r))),
        )
    return plots


def _friction(run_id: str, values: Mapping[str, Any] | None) -> Curve | None:
    """f against the sliding distance: the block means' times scaled so the last reaches
    the run's L (the disc turns at a constant speed within ±10 %)."""
    if values is None or not values.get("friction") or not values.get("sliding_distance"):
        return None
    x = np.asarray(values["friction"]["x"], dtype=float)
    y = np.asarray(values["friction"]["y"], dtype=float)
    if x.size < 2 or not x[-1] > x[0]:
        return None
    distance = (x - x[0]) / (x[-1] - x[0]) * float(values["sliding_distance"])
    return Curve(run_id, distance, y)


def _rows(
    run_id: str, values: Mapping[str, Any] | None, table: str, x: str, y: str
) -> Curve | None:
    if values is None:
        return None
    rows = [r for r in values.get(table) or [] if r.get(x) is not None and r.get(y) is not None]
    if not rows:
        return None
    return Curve(
        run_id, np.array([r[x] for r in rows], float), np.array([r[y] for r in rows], float)
    )


def _pairs(run_id: str, values: Mapping[str, Any] | None, x: str, y: str) -> Curve | None:
    if values is None or not values.get(x) or len(values[x]) != len(values.get(y) or []):
        return None
    return Curve(run_id, np.asarray(values[x], float), np.asarray(values[y], float))


def _profile(run_id: str, readings: Readings | None) -> Curve | None:
    if readings is None or readings.rows("profile") < 2:
        return None
    columns = readings.read("profile", ["x", "y"])
    x, y = min_max(columns["x"], columns["y"], buckets=PROFILE_POINTS // 2)
    return Curve(run_id, x, y)
