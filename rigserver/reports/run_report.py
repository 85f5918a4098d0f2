"""The report of a run: the heading, the input data, the stand's tables and plots, the
conclusions; rendered to HTML by ``templates/report.html`` and to PDF from the same HTML."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from datetime import datetime
from typing import Any

from markupsafe import escape
from pydantic import BaseModel

from rigserver.analysis import Readings
from rigserver.reports.context import Context, LabReport
from rigserver.reports.document import Items, Paragraph, Report, Section, Table, Text
from rigserver.reports.formatting import html_symbol, pairs, value_text
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.labs import mtos, profilometer, slide_bearing, smts2
from rigserver.reports.render import render
from schemas.results import MtosResults, ProfilometerResults, SlideBearingResults, Smts2Results
from schemas.runs import Run, RunState
from schemas.stands import CONFIG_MODELS, Stand, StandKind

RESULT_MODELS: dict[StandKind, type[BaseModel]] = {
    StandKind.SMTS2: Smts2Results,
    StandKind.SLIDE_BEARING: SlideBearingResults,
    StandKind.MTOS: MtosResults,
    StandKind.PROFILOMETER: ProfilometerResults,
}

_LABS: dict[StandKind, Callable[[Context, Any], LabReport]] = {
    StandKind.SMTS2: smts2.build,
    StandKind.SLIDE_BEARING: slide_bearing.build,
    StandKind.MTOS: mtos.build,
    StandKind.PROFILOMETER: profilometer.build,
}


def build_report(
    *,
    run: Run,
    stand: Stand,
    values: Mapping[str, Any],
    readings: Readings,
    lang: Lang,
    made: datetime,
) -> Report:
    """The report of ``run`` in ``lang``.

    Parameters
    ----------
    run, stand
        The run and its stand's declaration (channels, units).
    values
        The ``values`` of the run's results payload (stored at finish, or computed now).
    readings
        The run's readings: the measured tables and the long traces drawn come from here.
    lang
        ``"en"`` or ``"ru"``.
    made
        When the report is made (printed in the footer), UTC.
    """
    t = Messages(lang)
    kind = run.stand.value
    model = RESULT_MODELS[run.stand].model_validate(values)
    lab = _LABS[run.stand](Context(run=run, stand=stand, readings=readings, t=t), model)
    first: list[Paragraph | Table] = []
    if run.state is RunState.OPEN:
        first.append(Paragraph(t("open_warning")))
    first.append(_configuration(t, run))
    sections = [Section(t("sec.input"), first), *lab.sections]
    if lab.conclusions:
        sections.append(Section(t("sec.conclusions"), [Items(lab.conclusions)]))
    for key, items in (("sec.pending", model.pending), ("sec.notes", model.notes)):  # type: ignore[attr-defined]
        if items:  # the analysis' words, printed as they are (x_zero is not x subscript zero)
            sections.append(Section(t(key), [Items([escape(item) for item in items])]))
    return Report(
        lang=lang,
        title=f"{t('lab_work', n=stand.lab_work)}. {t('title.' + kind)}",
        subtitle=t("stand." + kind),
        aim_label=t("aim"),
        aim=t("aim." + kind),
        particulars=_particulars(t, run),
        sections=sections,
        footer=t("footer", run=run.id, time=f"{made:%Y-%m-%d %H:%M}"),
    )


def render_report(report: Report) -> str:
    """The report as a standalone HTML page (A4 print styles, inline SVG plots)."""
    return render("report.html", report=report)


def _particulars(t: Messages, run: Run) -> list[tuple[str, str]]:
    rows = [
        (t("run"), run.id),
        (t("stand"), t("stand." + run.stand.value)),
        (t("state"), t("state." + run.state.value)),
        (t("operator"), run.operator),
    ]
    if run.title:
        rows.append((t("run_title"), run.title))
    if run.specimen:
        rows.append((t("specimen"), pairs(run.specimen)))
    if run.test_plan:
        rows.append((t("test_plan"), pairs(run.test_plan)))
    rows.append((t("created"), f"{run.created:%Y-%m-%d %H:%M:%S} UTC"))
    if run.ended is not None:
        rows.append((t("ended"), f"{run.ended:%Y-%m-%d %H:%M:%S} UTC"))
    rows.append((t("rows"), pairs(run.rows)))
    if run.notes:
        rows.append((t("notes"), run.notes))
    return rows


def _configuration(t: Messages, run: Run) -> Table:
    """The configuration snapshot of the run, each field with its description and unit."""
    rows: list[list[Text]] = []

    def walk(model: type[BaseModel], data: Mapping[str, Any], prefix: str) -> None:
        for name, info in model.model_fields.items():
            value = data.get(name)
            inner = info.annotation
            if isinstance(inner, type) and issubclass(inner, BaseModel):
                walk(inner, value or {}, f"{prefix}{name}.")
                continue
            extra = info.json_schema_extra
            unit = extra.get("unit") if isinstance(extra, dict) else None
            rows.append(
                [
                    f"{prefix}{name}",
                    html_symbol(info.description or ""),
                    value_text(value),
                    t.unit(str(unit)) if unit is not None else "",
                ]
            )

    walk(CONFIG_MODELS[run.stand], run.configuration, "")
    head = [t("col.parameter"), t("col.description"), t("col.value"), t("col.unit")]
    return Table(caption=t("caption.configuration"), header=head, rows=rows, labels=2)


__all__ = ["RESULT_MODELS", "build_report", "render_report"]
