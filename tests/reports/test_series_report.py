"""The series report's overlay plots for every stand, and its tables in both languages."""

from __future__ import annotations

from datetime import UTC, datetime

import pytest

from rigserver.analysis.series import Member, series_statistics
from rigserver.reports import plots
from rigserver.reports.formatting import fmt
from rigserver.reports.i18n import Lang
from rigserver.reports.series_report import render_series_report, series_context
from schemas.series import Series, SeriesPurpose
from schemas.stands import StandKind
from tests.reports.rendered import series_report
from tests.reports.simulated import simulated, tables

MADE = datetime(2026, 11, 25, 12, 0, tzinfo=UTC)
#: The overlays each stand's series draws (docs/series.md).
PLOTS = {
    StandKind.SMTS2: 1,
    StandKind.MTOS: 2,
    StandKind.SLIDE_BEARING: 1,
    StandKind.PROFILOMETER: 2,
    StandKind.PIN_ON_DISC: 1,
    StandKind.RECIPROCATING: 1,
}


@pytest.mark.parametrize("kind", list(StandKind))
@pytest.mark.parametrize("lang", ["en", "ru"])
def test_series_report_of_every_stand(kind: StandKind, lang: str) -> None:
    runs = [simulated(kind)] * 3  # one simulated run three times: the plots and tables only
    members = [
        Member(
            run=r.run.model_copy(update={"id": f"20261125T120000Z-0000000{i}"}),
            level=level,
            values=r.result.payload["values"],
        )
        for i, (r, level) in enumerate(zip(runs, ("A", "A", "B"), strict=True))
    ]
    series = Series(
        id="s-00000000000a", name="n", purpose=SeriesPurpose.COMPARISON, factor="oil", created=MADE
    )
    detail = series_statistics(series, members, [])
    readings = {m.run.id: r.readings for m, r in zip(members, runs, strict=True)}
    context = series_context(
        detail, values={m.run.id: m.values for m in members}, readings=readings, lang=lang
    )
    assert len(context["plots"]) == PLOTS[kind]
    html = render_series_report(context, made=MADE)
    assert html.count("<svg") == PLOTS[kind]
    found = tables(html)
    runs_table = found[1]  # after the particulars
    assert [row[0] for row in runs_table.rows] == [m.run.id for m in members]
    header = found[2].header
    assert header[0] == ("Result" if lang == "en" else "Результат")
    assert found[3].header[0] == header[0]  # the spread against the instruments
    comparison = found[4]
    assert {row[1] for row in comparison.rows if row[1] in ("A", "B")} == {"A", "B"}


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_series_of_the_adhesive_and_oxidative_modes_prints_delta_f(lang: str) -> None:
    """Levels named by the two modes of lab work 2: the report prints f_a, f_ok and Δf
    (2.16), Δf recomputed here from the f printed for the two runs."""
    run = simulated(StandKind.SMTS2)
    f = run.result.payload["values"]["friction_steady"]
    members = [
        Member(
            run=run.run.model_copy(update={"id": f"20261125T120000Z-0000001{i}"}),
            level=level,
            values={**run.result.payload["values"], "friction_steady": value},
        )
        for i, (level, value) in enumerate((("Adhesive", f), ("oxidative", f / 2)))
    ]
    series = Series(
        id="s-00000000000b", name="n", purpose=SeriesPurpose.COMPARISON, factor="mode", created=MADE
    )
    detail = series_statistics(series, members, [])
    assert detail.adhesive_oxidative is not None
    assert detail.adhesive_oxidative.difference == pytest.approx(50.0, rel=1e-12)  # f_ok = f_a/2
    context = series_context(
        detail,
        values={m.run.id: m.values for m in members},
        readings={m.run.id: run.readings for m in members},
        lang=lang,
    )
    html = render_series_report(context, made=MADE)
    assert "= 50 %" in html  # fmt(50.0)
    assert ("Adhesive and oxidative friction (2.16)" in html) == (lang == "en")


@pytest.mark.parametrize(("lang", "step"), [("en", "step"), ("ru", "шаг")])
def test_a_per_step_result_names_its_step_and_load(lang: Lang, step: str) -> None:
    """f_e,3 of an MTOS series reads "…, step 3, N = 1500 N", as the run report's
    uncertainty table names the step: the load each numbered step was run at."""
    steps = simulated(StandKind.MTOS).result.payload["values"]["steps"]
    statistics = tables(series_report(StandKind.MTOS, lang).html)[2]
    named = [row[0] for row in statistics.rows if f", {step} " in row[0]]
    assert len(named) >= 2 * len(steps)  # f_e and χ of every step at least
    for i, one in enumerate(steps, start=1):
        load = fmt(one["load"]).replace(".", ",") if lang == "ru" else fmt(one["load"])
        unit = "N" if lang == "en" else "Н"
        assert any(name.endswith(f", {step} {i}, N = {load} {unit}") for name in named), i


@pytest.mark.parametrize(
    ("lang", "counts"),
    [
        ("en", {1: "1 of the runs is still open: its", 2: "2 of the runs are still open: their"}),
        (
            "ru",
            {
                1: "1 испытание серии ещё не завершено: его",
                3: "3 испытания серии ещё не завершены: их",
                5: "5 испытаний серии ещё не завершено: их",
                21: "21 испытание серии ещё не завершено: его",
            },
        ),
    ],
)
def test_the_open_runs_are_counted_in_the_plural_forms(lang: Lang, counts: dict[int, str]) -> None:
    # "1 of the runs are still open" read wrongly (gettext's plural forms, schemas.messages.NP_)
    detail = series_statistics(
        Series(id="s-00000000000c", name="n", purpose=SeriesPurpose.REPEATABILITY, created=MADE),
        [],
        [],
    )
    for n, words in counts.items():
        context = series_context(
            detail.model_copy(update={"open_runs": n}), values={}, readings={}, lang=lang
        )
        assert words in render_series_report(context, made=MADE)


def _legends(kind: StandKind, levels: tuple[str | None, ...], lang: Lang) -> list[list[str]]:
    """The legend texts of each overlay of a series of three runs of ``kind`` at ``levels``,
    by groups 1-3 on 25-27 November (the first two runs by one group on one day)."""
    run = simulated(kind)
    starts = [
        datetime(2026, 11, day, hour, tzinfo=UTC) for day, hour in ((25, 9), (25, 11), (27, 9))
    ]
    members = [
        Member(
            run=run.run.model_copy(
                update={"id": f"20261125T120000Z-0000002{i}", "operator": group, "created": start}
            ),
            level=level,
            values=run.result.payload["values"],
        )
        for i, (level, group, start) in enumerate(
            zip(levels, ("Group 1", "Group 1", "Group $3$"), starts, strict=True)
        )
    ]
    factor = "oil" if any(levels) else None
    purpose = SeriesPurpose.COMPARISON if factor else SeriesPurpose.REPEATABILITY
    series = Series(id="s-00000000000d", name="n", purpose=purpose, factor=factor, created=MADE)
    detail = series_statistics(series, members, [])
    with plots.recording() as drawn:
        series_context(
            detail,
            values={m.run.id: m.values for m in members},
            readings={m.run.id: run.readings for m in members},
            lang=lang,
        )
    return [[t.get_text() for t in ax.get_legend().get_texts()] for f in drawn for ax in f.axes]


@pytest.mark.parametrize("kind", [StandKind.SMTS2, StandKind.MTOS])
@pytest.mark.parametrize("lang", ["en", "ru"])
def test_a_series_legend_names_the_runs_by_group_and_date(kind: StandKind, lang: Lang) -> None:
    # the legends named the runs by the ends of their ids ("…0000abcd")
    mean = {"en": "mean ± s", "ru": "среднее ± s"}[lang]
    runs = ["Group 1, 2026-11-25 09:00", "Group 1, 2026-11-25 11:00", r"Group \$3\$, 2026-11-27"]
    for legend in _legends(kind, (None, None, None), lang):
        assert legend == [*runs, mean]


@pytest.mark.parametrize("kind", [StandKind.SMTS2, StandKind.MTOS])
def test_a_series_legend_names_the_runs_by_their_level(kind: StandKind) -> None:
    for legend in _legends(kind, ("A", "A", "B"), "en"):
        assert sorted(legend) == ["A", "A: mean ± s", "B"]  # B's one run draws no mean
