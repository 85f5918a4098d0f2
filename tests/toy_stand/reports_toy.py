"""The toy stand's part of a run's report (copied as ``rigserver/reports/labs/toy.py``):
its report list and its results table."""

from __future__ import annotations

from rigserver.reports import blocks
from rigserver.reports.contents import Contents, Item, Students
from rigserver.reports.contents.common import opening
from rigserver.reports.context import Context, LabReport
from rigserver.reports.document import Section
from schemas.toy import LABELS, ToyResults

CONTENTS = Contents(
    items=(
        *opening("toy"),
        Item(4, "stiffness", "The spring"),
        Item(5, "conclusions", "Conclusions", students=Students.CONCLUSIONS),
    ),
)


def build(ctx: Context, v: ToyResults) -> LabReport:
    fields = [("stiffness", "k"), ("preload", "F_0")]
    table = blocks.result_table(ctx.t, "The spring", [v], fields, model=ToyResults, labels=LABELS)
    return LabReport(sections=[Section(ctx.t("sec.processed"), [table])], conclusions=[])
