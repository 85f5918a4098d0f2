"""The report of a lab work of several runs (a series of purpose ``lab``): lab 2's wear run
is part 1, printed as its run report is; part 2 sets its adhesive against its oxidative run,
f_a, f_ok and Δf (2.16) with their uncertainties, and the students' observations of each
mode under the manual's items 12 and 13."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any

from markupsafe import Markup

from rigserver.analysis import Readings
from rigserver.analysis.series import Member, adhesive_oxidative
from rigserver.reports.contents import Students
from rigserver.reports.document import Paragraph, Report, Section, Table, Text
from rigserver.reports.formatting import fmt, html_symbol, number_locale, with_uncertainty
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.kits import KITS
from rigserver.reports.run_report import build_report
from rigserver.reports.students import section
from schemas.messages import N_
from schemas.runs import Run
from schemas.series import LAB_PARTS, AdhesiveOxidative
from schemas.stands import Stand, StandKind
from schemas.student_notes import StudentNotes

#: The modes of part 2 by their level, as the reports name them.
MODES = {"adhesive": N_("adhesive"), "oxidative": N_("oxidative")}
PART_1 = N_("Part 1. Wear in dry friction: the wear run {run}")
PART_2 = N_("Part 2. Adhesive against oxidative wear")
CAPTION = N_("Friction coefficients of the adhesive and the oxidative runs, and Δf (2.16)")
MISSING = N_("Part 2 needs an adhesive and an oxidative run with their friction; runs: {runs}.")
MODE = N_("Mode")


@dataclass(frozen=True, slots=True)
class WorkRun:
    """A run of the lab work at its part (its level in the series), with its results'
    ``values`` and the students' notes and ``sketches`` on it (item -> a ``data:`` URI)."""

    run: Run
    part: str
    values: Mapping[str, Any] | None
    notes: StudentNotes
    sketches: Mapping[int, str] = field(default_factory=dict)


def build_lab_work(
    *, runs: Sequence[WorkRun], stand: Stand, readings: Readings, lang: Lang, made: datetime
) -> Report:
    """The lab work's report: the first run of part 1 (``readings`` are its readings) with
    part 2 of the others. ValueError when no run is at part 1."""
    main = part_one(stand.kind, runs)
    if main is None:
        raise ValueError(f"a lab work's report needs a finished {stand.kind.value} run of part 1")
    parts = LAB_PARTS[stand.kind]
    t = Messages(lang)
    with number_locale(lang):
        second = part_two(t, stand.kind, [r for r in runs if parts.get(r.part) == 2])
    return build_report(
        run=main.run,
        stand=stand,
        values=main.values or {},
        readings=readings,
        lang=lang,
        made=made,
        notes=main.notes,
        sketches=main.sketches,
        work=(t.gettext(PART_1).format(run=main.run.id), second),
    )


def part_one(kind: StandKind, runs: Sequence[WorkRun]) -> WorkRun | None:
    """The run the report's part 1 is: the first at a level of part 1 with results."""
    parts = LAB_PARTS.get(kind, {})
    return next((r for r in runs if parts.get(r.part) == 1 and r.values is not None), None)


def part_two(t: Messages, kind: StandKind, runs: Sequence[WorkRun]) -> list[Section]:
    """Part 2: the friction of each run of the two modes, f_a, f_ok and Δf (2.16) with their
    expanded uncertainties (k = 2), then the students' observations of each mode."""
    found = adhesive_oxidative([Member(run=r.run, level=r.part, values=r.values) for r in runs])
    if found is None:
        listed = ", ".join(f"{r.run.id} ({t.gettext(MODES[r.part])})" for r in runs) or "—"
        first = Paragraph(html_symbol(t.gettext(MISSING).format(runs=listed)))
        sections = [Section(t.gettext(PART_2), [first])]
    else:
        sections = [Section(t.gettext(PART_2), [_friction_table(t, runs, found)])]
    observed = [i for i in KITS[kind].contents.items if i.students is Students.OBSERVATIONS]
    for item, mode in zip(observed, MODES, strict=True):
        said = [r.notes.observations for r in runs if r.part == mode]
        sections.append(section(t, item, "\n\n".join(w for w in said if w.strip())))
    return sections


def _friction_table(t: Messages, runs: Sequence[WorkRun], found: AdhesiveOxidative) -> Table:
    rows: list[list[Text]] = []
    for r in runs:
        v = r.values or {}
        rows.append(
            [
                t.gettext(MODES[r.part]),
                r.run.id,
                html_symbol(t.symbol("f")),
                with_uncertainty(v.get("friction_steady"), v.get("friction_steady_expanded")),
                fmt(v.get("mean_load")),
            ]
        )
    for mode, symbol, value, u in (
        ("adhesive", "f_a", found.f_adhesive, found.f_adhesive_uncertainty),
        ("oxidative", "f_ok", found.f_oxidative, found.f_oxidative_uncertainty),
        ("", "Δf", found.difference, found.difference_uncertainty),
    ):
        shown = with_uncertainty(value, None if u is None else 2.0 * u)
        if symbol == "Δf":
            shown = f"{shown}, {t.unit('%')}"
        words = t.gettext(MODES[mode]) if mode else ""
        rows.append([words, "", html_symbol(t.symbol(symbol)), shown, ""])
    head: list[Text] = [
        t.gettext(MODE),
        t("run"),
        t("col.symbol"),
        t("col.value"),
        Markup("{}, {}").format(html_symbol(t.symbol("N")), t.unit("N")),
    ]
    return Table(caption=t.gettext(CAPTION), header=head, rows=rows, labels=3)
