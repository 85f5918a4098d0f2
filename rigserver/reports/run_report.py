"""The report of a run: the heading, the input data, the stand's tables and plots, the
conclusions; rendered to HTML by ``templates/report.html`` and to PDF from the same HTML."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import replace
from datetime import datetime
from typing import Any, NamedTuple

from markupsafe import escape
from pydantic import BaseModel

from rigserver.analysis import Readings
from rigserver.analysis.kits import run_materials
from rigserver.reports import equations, layout
from rigserver.reports.contents.common import TASKS
from rigserver.reports.context import Context
from rigserver.reports.corrections import corrections_section
from rigserver.reports.document import Items, Paragraph, Report, Section, Table, Text
from rigserver.reports.formatting import fmt, html_symbol, number_locale, value_text, with_unit
from rigserver.reports.i18n import MESSAGES, Lang, Messages, translations
from rigserver.reports.kits import KITS
from rigserver.reports.render import render
from rigserver.reports.students import students_part
from schemas.corrections import Correction
from schemas.labels import CONFIGURATION, PARTICULARS, VALUE_WORDS
from schemas.messages import N_
from schemas.runs import Run, RunState
from schemas.stands import DECLARATIONS, Stand
from schemas.student_notes import StudentNotes


def build_report(
    *,
    run: Run,
    stand: Stand,
    values: Mapping[str, Any],
    readings: Readings,
    lang: Lang,
    made: datetime,
    notes: StudentNotes | None = None,
    corrections: Sequence[Correction] = (),
    work: tuple[str, Sequence[Section]] | None = None,
    sketches: Mapping[int, str] = {},
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
    notes
        The student's own words on the run: the group and the students are printed at the
        top, their sections of the lab's report list (:mod:`rigserver.reports.students`)
        after the computed results, as written.
    sketches
        The students' sketches uploaded on the run, printed in their items' sections in
        place of the frame to draw in: item number -> the image as a ``data:`` URI.
    work
        In a lab work of several runs (:mod:`rigserver.reports.lab_work`), the heading of
        its part 1 (this run) and the sections of its part 2, printed before the students'
        part.
    corrections
        The corrections of the run's readings (``readings`` are as corrected): printed in
        the section "Corrections", with the value as typed and the reason.
    """
    with number_locale(lang):
        t = Messages(lang)
        theirs = (notes or StudentNotes(), sketches)
        report = _build(run, stand, values, readings, t, made, theirs, work)
        corrected = corrections_section(t, stand, corrections, run.corrected_after_finish)
    if corrected is None:
        return report
    # after the measured tables and the plots, before the computed results and the students'
    closing = {t(k) for k in ("sec.computed", "sec.pending", "sec.notes", "sec.abbreviations")}
    at = next(
        (i for i, s in enumerate(report.sections) if s.title in closing), len(report.sections)
    )
    sections = [*report.sections[:at], corrected, *report.sections[at:]]
    return replace(report, sections=sections)


def _build(
    run: Run,
    stand: Stand,
    values: Mapping[str, Any],
    readings: Readings,
    t: Messages,
    made: datetime,
    theirs: tuple[StudentNotes, Mapping[int, str]],
    work: tuple[str, Sequence[Section]] | None = None,
) -> Report:
    kind = run.stand.value
    notes, sketches = theirs
    model = DECLARATIONS[run.stand].results.model_validate(values)
    lab = KITS[run.stand].build(Context(run=run, stand=stand, readings=readings, t=t), model)
    first: list[Paragraph | Table] = []
    if run.state is RunState.OPEN:
        first.append(Paragraph(t("open_warning")))
    first.append(_configuration(t, run))
    part_one = [Section(work[0])] if work else []
    sections = [Section(t("sec.input"), first), *part_one, *lab.sections]
    if lab.conclusions:  # the numbers' verdicts; the students' conclusions are theirs below
        sections.append(Section(t("sec.computed"), [Items(lab.conclusions)]))
    if work:
        sections += work[1]
    contents = KITS[run.stand].contents
    sections += students_part(t, contents.students(), notes, sketches)
    for key, items in (("sec.pending", model.pending), ("sec.notes", model.notes)):  # type: ignore[attr-defined]
        if items:  # the analysis' words, printed as they are (x_zero is not x subscript zero)
            sections.append(Section(t(key), [Items([escape(t.gettext(item)) for item in items])]))
    explained = abbreviations(t, sections)
    if explained:
        sections.append(Section(t("sec.abbreviations"), [Items(explained)]))
    sections = equations.beside(t, sections)
    return Report(
        lang=t.lang,
        title=t("title." + kind)
        if stand.lab_work is None
        else f"{t('lab_work', n=stand.lab_work)}. {t('title.' + kind)}",
        subtitle=t("stand." + kind),
        aim_label=t("aim"),
        aim=t("aim." + kind),
        tasks_label=t.gettext(TASKS),
        tasks=[t.gettext(task) for task in contents.tasks],
        particulars=_particulars(t, run, stand, notes),
        sections=sections,
        footer=t("footer", run=run.id, time=f"{made:%Y-%m-%d %H:%M}"),
    )


ABBREVIATIONS: dict[str, str] = {
    "GUM": "abbr.gum",
    "ASTM G99": "abbr.g99",
    **{f"E{n}": f"abbr.e{n}" for n in range(1, 11)},
}
"""The abbreviations and the corrections to the manual's printed formulas (docs/models.md)
a report may cite, each explained once in its appendix."""
_CITED = re.compile(r"GUM|ASTM G99|(?<=\()E(?:10|[1-9])\b|(?<=, )E(?:10|[1-9])\b")


def _texts(sections: Sequence[Section]) -> str:
    """All the words of the sections' tables, lists and captions, as one text."""
    texts: list[str] = []
    for section in sections:
        for block in section.blocks:
            if isinstance(block, Table):
                texts += [str(block.caption), str(block.note), *map(str, block.header)]
                texts += [str(cell) for row in block.rows for cell in row]
            elif isinstance(block, Items):
                texts += [str(item) for item in block.items]
            else:
                texts.append(str(getattr(block, "caption", "") or getattr(block, "text", "")))
    return " ".join(texts)


def abbreviations(t: Messages, sections: Sequence[Section]) -> list[Text]:
    """The explanations of the abbreviations and corrections (E1-E9) the sections cite, in
    the order of :data:`ABBREVIATIONS`."""
    cited = set(_CITED.findall(_texts(sections)))
    return [html_symbol(t(key)) for code, key in ABBREVIATIONS.items() if code in cited]


def render_report(report: Report) -> str:
    """The report as a standalone HTML page (A4 print styles, inline SVG plots); tables wider
    than the page's column are printed in parts (:func:`rigserver.reports.layout.fit`)."""
    fitted = layout.fit(report, translations(report.lang).gettext(MESSAGES["table.part"]))
    return render("report.html", report=fitted)


def particulars_text(t: Messages, mapping: Mapping[str, Any]) -> str:
    """A test plan or a specimen with the declared labels (:data:`schemas.labels.PARTICULARS`):
    ``load N = 300 Н; simulated: да``; a key not declared is shown as it is (user data)."""
    parts = []
    for key, value in mapping.items():
        label = PARTICULARS.get(key)
        if label is None:
            parts.append(f"{key}: {value_text(value)}")
            continue
        words = t.gettext(label.text)
        if isinstance(value, bool):
            shown = t("yes") if value else t("no")
        elif isinstance(value, str):
            shown = t.gettext(value)
        else:
            shown = value_text(value)
        unit = "" if label.unit == "1" else t.unit(label.unit)
        parts.append(f"{words}: {with_unit(shown, unit)}")
    return "; ".join(parts)


def _particulars(t: Messages, run: Run, stand: Stand, notes: StudentNotes) -> list[tuple[str, str]]:
    rows = [
        (t("run"), run.id),
        (t("stand"), t("stand." + run.stand.value)),
        (t("state"), _state(t, run)),
        (t("operator"), run.operator),
    ]
    if notes.group:
        rows.append((t("group"), notes.group))
    if notes.students:
        rows.append((t("students"), ", ".join(notes.students)))
    if run.title:
        rows.append((t("run_title"), run.title))
    if run.specimen:
        rows.append((t("specimen"), particulars_text(t, run.specimen)))
    if run.test_plan:
        rows.append((t("test_plan"), particulars_text(t, run.test_plan)))
    rows.append((t("created"), f"{run.created:%Y-%m-%d %H:%M:%S} UTC"))
    if run.ended is not None:
        rows.append((t("ended"), f"{run.ended:%Y-%m-%d %H:%M:%S} UTC"))
    rows.append((t("rows"), _rows_text(t, run, stand)))
    if run.notes:
        rows.append((t("notes"), run.notes))
    return rows


def _state(t: Messages, run: Run) -> str:
    state = t("state." + run.state.value)
    return f"{state}, {t('corrected_after_finish')}" if run.corrected_after_finish else state


def _rows_text(t: Messages, run: Run, stand: Stand) -> str:
    """The rows stored per channel group, each group by its name in ``t``'s language: a
    count, printed whole (64001, not 6.4·10⁴)."""
    names = {g.name: t.gettext(g.long_name) for g in stand.groups}
    return "; ".join(f"{names.get(g, g)}: {n}" for g, n in run.rows.items())


def _configuration(t: Messages, run: Run) -> Table:
    """The configuration snapshot of the run, each field with its description and unit."""
    head = [t("col.description"), t("col.value"), t("col.unit")]
    rows: list[list[Text]] = [list(row[:3]) for row in configuration_rows(t, run)]
    return Table(caption=t("caption.configuration"), header=head, rows=rows, labels=1)


class ConfigRow(NamedTuple):
    """A configuration value as the report and the run page print it, and who gave it:
    ``file`` (the file and its map), ``operator``, ``table`` (the materials table, for the
    material the specimen names), ``default`` (nobody), ``unrecorded`` (a run opened before
    rig kept it)."""

    words: Text
    value: str
    unit: str
    given_by: str


def configuration_rows(t: Messages, run: Run) -> list[ConfigRow]:
    """The configuration of the run as its analysis reads it: each field's description (with
    the manual's symbol) in ``t``'s language, its value and its unit, in the display unit of
    :data:`schemas.labels.CONFIGURATION` (mm, µm, MPa, GPa, mg) as the results print them,
    and who gave it; a value nobody gave for this run as "not given: the stand's default
    (value)", the properties of a material the specimen names as the materials table's."""
    rows: list[ConfigRow] = []
    materials = run_materials(run)

    def given_by(path: str) -> str:
        if path.split(".")[0] in materials.found:
            return "table"
        if run.configuration_given is None:
            return "unrecorded"
        return run.configuration_given.get(path, "default")

    def walk(model: type[BaseModel], data: Mapping[str, Any], owner: str, path: str) -> None:
        for name, info in model.model_fields.items():
            value = data.get(name)
            inner = info.annotation
            if isinstance(inner, type) and issubclass(inner, BaseModel):
                label = PARTICULARS.get(_role(name, data))
                words = t.gettext(label.text) + ": " if label else ""
                walk(inner, value or {}, words, f"{name}.")
                continue
            extra = info.json_schema_extra
            unit = extra.get("unit") if isinstance(extra, dict) else None
            words = owner + t.gettext(info.description or FIELD_WORDS.get(name, name))
            display = CONFIGURATION.get(path + name) or CONFIGURATION.get(name)
            if name == "gauge_unit" and isinstance(value, str):
                shown = t.unit(value)
            elif isinstance(value, str | bool):
                shown = (
                    t.gettext(VALUE_WORDS.get(value, value))
                    if isinstance(value, str)
                    else t("yes" if value else "no")
                )
            elif display is not None and unit is not None and isinstance(value, int | float):
                shown = fmt(display.shown(float(value), str(unit)), display.digits)
                unit = display.unit
            else:
                shown = value_text(value)
            number = isinstance(value, int | float) and not isinstance(value, bool)
            # a number without a unit is dimensionless ("—", as the results print it)
            unit_text = t.unit(str(unit or "1")) if number or unit not in (None, "1") else ""
            source = given_by(path + name)
            if source == "default":  # never printed as the test's fact
                shown = t("config.default", value=shown)
            elif source == "table":
                shown = t("config.table", value=shown)
            rows.append(ConfigRow(html_symbol(words), shown, unit_text, source))

    walk(DECLARATIONS[run.stand].configuration, materials.config.model_dump(mode="json"), "", "")
    return rows


def _role(name: str, data: Mapping[str, Any]) -> str:
    """The specimen a configuration's section describes: a tribometer's counter-body
    (``pin``) is the ball when its tip is one (ISO 20808), not the pin of ASTM G99."""
    return "ball" if name == "pin" and data.get("tip") == "ball" else name


FIELD_WORDS = {
    "name": N_("material"),
    "gauge_unit": N_("unit of the manometers"),
    "instrument": N_("instrument"),
}
"""Words for the configuration fields declared without a description."""


__all__ = ["build_report", "render_report"]
