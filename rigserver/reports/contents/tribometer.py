"""The tribometers' report list: they have no lab work in the manual, so the students' part
the lab's other lists share (sketch, analysis, conclusions) around the friction plot."""

from __future__ import annotations

from rigserver.reports.contents import Contents, Item, Students
from rigserver.reports.i18n import MESSAGES
from schemas.messages import N_


def contents(kind: str) -> Contents:
    return Contents(
        items=(
            Item(1, "title", heading=MESSAGES["title." + kind]),
            Item(2, "aim", heading=MESSAGES["aim"]),
            Item(3, "sketch", N_("Sketch of the specimens"), students=Students.SKETCH),
            Item(4, "friction", tables=("caption.configuration",), figures=("t.fig_friction",)),
            Item(5, "analysis", N_("Analysis of the graphs"), students=Students.ANALYSIS),
            Item(6, "conclusions", N_("Conclusions"), students=Students.CONCLUSIONS),
        )
    )
