"""The report's table of corrections: every reading corrected or row struck out, with the
value as typed, the value as corrected and the reason (the readings of the report's tables
and results are the corrected ones)."""

from __future__ import annotations

from collections.abc import Sequence

from markupsafe import escape

from rigserver.reports.document import Paragraph, Section, Table, Text
from rigserver.reports.formatting import DASH, decimal_sign, html_symbol
from rigserver.reports.i18n import Messages
from schemas.corrections import Correction
from schemas.stands import Stand


def corrections_section(
    t: Messages, stand: Stand, corrections: Sequence[Correction], after_finish: bool
) -> Section | None:
    """The section "Corrections", or None for a run whose readings stand as typed."""
    if not corrections:
        return None
    head = [
        t("corr.row"),
        t("col.quantity"),
        t("corr.was"),
        t("corr.now"),
        t("col.unit"),
        t("corr.reason"),
        t("corr.by"),
    ]
    blocks: list[Table | Paragraph] = []
    for name in dict.fromkeys(c.group for c in corrections):  # the groups, in order
        group = stand.group(name)
        rows: list[list[Text]] = []
        for c in corrections:
            if c.group != name:
                continue
            channel = None if group is None or c.channel is None else group.channel(c.channel)
            if c.channel is None:
                what: Text = t("corr.struck")
            elif channel is None:
                what = c.channel
            else:
                what = html_symbol(t.gettext(channel.long_name))
            rows.append(
                [
                    str(c.row + 1),
                    what,
                    _typed(c.was),
                    _typed(c.now),
                    t.unit(c.unit) if c.unit else DASH,
                    escape(c.reason),
                    escape(f"{c.by}, {c.at:%Y-%m-%d %H:%M} UTC"),
                ]
            )
        caption = t("corr.caption", group=t.gettext(group.long_name) if group else name)
        # every column may wrap (a reason is up to 500 characters); row and quantity repeat
        blocks.append(Table(caption=caption, header=head, rows=rows, labels=len(head), keys=2))
    if after_finish:
        blocks.insert(0, Paragraph(t("corr.after_finish")))
    return Section(t("sec.corrections"), blocks)


def _typed(value: float | None) -> str:
    """A value as typed, every digit it has (a correction of 12.3456 g to 12.3465 g is
    seen), with the report's decimal sign."""
    if value is None:
        return DASH
    return f"{value:.12g}".replace(".", decimal_sign())
