"""The forms that take the readings on a run's page, at the stand: one per channel group,
one input per channel in the manual's column order, each labelled with the channel's symbol
and unit, and the rows the server has taken.

The channels' limits handed to the page (``static/entry.js`` checks each cell as it is
typed) are the declaration the API checks a batch against (:mod:`schemas.channels`), for
the run's configuration (the slide-bearing gauges' unit): one source, two checks. The page
keeps what it has not yet had acknowledged in the browser's IndexedDB and sends it as the
page's own posts (``/runs/{id}/rows``, never the API), each row one batch with a ``seq``
fixed when the row was kept, so a row sent again is stored once.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from markupsafe import Markup
from numpy.typing import NDArray

from rigserver.reports.formatting import decimal_sign, html_symbol, number_locale, plain_text
from rigserver.reports.i18n import Lang, Messages
from schemas.channels import ChannelGroup, Violation
from schemas.corrections import Correction
from schemas.labels import channel_symbol, plain_symbol
from schemas.messages import N_, NP_
from schemas.problems import Problem
from schemas.stands import Stand

TEXTS: dict[str, str] = {
    "not_a_number": N_("“{value}” is not a number"),
    "empty": N_("to be filled in"),
    "below": N_("{symbol} = {value} {unit} is below the limit {low} {unit}"),
    "above": N_("{symbol} = {value} {unit} is above the limit {high} {unit}"),
    "nominal": N_("{symbol} = {value} {unit}: one of {values} {unit} is expected"),
    "integer": N_("{symbol} = {value}: a whole number is expected"),
    "one_value": N_("type at least one value"),
    "all_sent": N_("Every row typed is on the server"),
    "offline": N_(
        "the server does not answer; the rows are kept in this browser and sent once it answers"
    ),
    "refused": N_("refused by the server: {reason}"),
    "stopped": N_("not sent: {reason}"),
    "confirm_finish": N_("Finish the run? Its results are computed and it takes no more rows."),
    "confirm_abort": N_("Abort the run? It keeps its rows but takes no more and gets no results."),
    "wait_first": N_("{waiting}: wait until they are sent"),
    "sent": N_("sent"),
    "waits": N_("waits"),
    "dismiss": N_("Drop"),
    "correct": N_("Correct"),
    "strike": N_("Strike out"),
    "save": N_("Save"),
    "cancel": N_("Cancel"),
    "reason": N_("Reason"),
    "reason_needed": N_("say why the reading is corrected"),
    "no_change": N_("change a value, or cancel"),
    "corrected_title": N_("Corrected: {reason}"),
    "struck_title": N_("Struck out: {reason}"),
    "struck": N_("struck out"),
}
"""What the page says as it checks, sends and corrects (``{…}`` filled in by the script)."""

#: The count of the rows still in the browser, in the plural forms of the page's language
#: (Russian has three: 1 строка, 2 строки, 5 строк), picked by the script.
WAITING = NP_("{n} row waits to be sent", "{n} rows wait to be sent")


FORM_HEADER = "x-rig-form"
"""The header that carries the session's form token on the page's own requests."""

#: The title of a correction refused for its reason.
REASON_MISSING = "Reason missing"
_REFUSALS: dict[tuple[int, str], str] = {
    (401, ""): N_("The session has ended: log in again (the rows stay in this browser)."),
    (403, "Scope missing"): N_(
        "This key lacks the scope {scope}: it may not write runs of this stand."
    ),
    (403, ""): N_("This form is not of this page's session: reload the page."),
    (404, ""): N_("There is no such run."),
    (409, "Run is not open"): N_("The run is not open any more: it takes no more rows."),
    (413, ""): N_("The row is too large for the server."),
    (422, REASON_MISSING): N_("Say why the reading is corrected: the reason is required."),
    (422, ""): N_("Refused: {detail}"),
    (503, ""): N_("The server is busy: the row is sent again shortly."),
    (0, ""): N_("The server refused ({status}): {detail}"),
}
"""The page's line for each refusal (status and, where one status means several, the
title); the detail as the API words it."""
_SCOPE = re.compile(r"'(write:[a-z0-9_*]+)'")


def refusal_line(t: Messages, problem: Problem, stand: Stand | None = None) -> str:
    """One line of the page's language saying why the server refused; a reading beyond
    its channel's limit (of ``stand``, as the run's configuration sets its units) in the
    words the page uses as it checks a cell."""
    status = problem.status if problem.status != 429 else 503
    text = _REFUSALS.get((status, problem.title)) or _REFUSALS.get((status, ""))
    if text is None:
        text = _REFUSALS[(0, "")]
    scope = _SCOPE.search(problem.detail or "")
    detail = problem.detail or ""
    if status == 422 and stand is not None and problem.errors:
        detail = limit_refusal(t, stand, problem.errors[0]) or detail
    return t.gettext(text).format(
        detail=detail, status=problem.status, scope=scope[1] if scope else ""
    )


_CELL = re.compile(r"columns\.(\w+)\[\d+\]|values\.(\w+)")


def limit_refusal(t: Messages, stand: Stand, violation: Violation) -> str | None:
    """A reading beyond its channel's limit, worded as ``entry.js`` words it as the cell is
    typed (the same rules in the same order); None for any other refusal (an order across
    rows, a missing channel)."""
    cell = _CELL.fullmatch(violation.field)
    value = violation.value
    if cell is None or not isinstance(value, float):
        return None
    name = cell[1] or cell[2]
    channel = next((c for g in stand.groups if (c := g.channel(name)) is not None), None)
    if channel is None:
        return None
    limit = channel.limit
    with number_locale(t.lang):
        sign = decimal_sign()

    def shown(number: float) -> str:
        return f"{number:.12g}".replace(".", sign)

    symbol = channel_symbol(channel.name, channel.long_name)
    say = {
        "symbol": plain_symbol(t.symbol(symbol)) if symbol else t.gettext(channel.long_name),
        "value": shown(value),
        "unit": "" if channel.unit in ("1", "code") else t.unit(channel.unit),
    }
    if limit.low is not None and value < limit.low:
        return t.gettext(TEXTS["below"]).format(**say, low=shown(limit.low))
    if limit.high is not None and value > limit.high:
        return t.gettext(TEXTS["above"]).format(**say, high=shown(limit.high))
    if limit.nominal is not None and not any(
        abs(value - v) <= limit.tolerance * abs(v) for v in limit.nominal
    ):
        values = ", ".join(shown(v) for v in limit.nominal)
        return t.gettext(TEXTS["nominal"]).format(**say, values=values)
    if limit.integer and value != round(value):
        return t.gettext(TEXTS["integer"]).format(**say)
    return None


def typed(value: float) -> str:
    """A reading as it was typed (up to 12 significant digits), in the page language's
    decimal sign (:func:`rigserver.reports.formatting.number_locale`)."""
    if not math.isfinite(value):  # a channel left out of its row (stored as NaN)
        return ""
    return f"{value:.12g}".replace(".", decimal_sign())


def _channels(t: Messages, group: ChannelGroup) -> list[dict[str, Any]]:
    channels = []
    for c in group.channels:
        symbol = channel_symbol(c.name, c.long_name)
        words = t.gettext(c.long_name)
        shown = t.symbol(symbol) if symbol else plain_text(words)
        unit = "" if c.unit in ("1", "code") else t.unit(c.unit)
        channels.append(
            {
                "name": c.name,
                "label": Markup("{}{}").format(
                    html_symbol(shown) if symbol else shown,
                    Markup(", {}").format(unit) if unit else "",
                ),
                "symbol": plain_symbol(shown) if symbol else shown,
                "words": plain_text(words),
                "unit": unit,
                "limit": c.limit.model_dump(mode="json"),
            }
        )
    return channels


@dataclass(frozen=True, slots=True)
class Cell:
    """A reading the server holds, as the page shows it: ``value`` as corrected, ``typed``
    as typed (both None: none posted), ``index`` the row as stored that holds it, the
    ``reasons`` of its corrections in the order made."""

    value: float | None
    typed: float | None
    index: int
    reasons: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class ReceivedRow:
    """A row of the table of rows received: its cells in the channels' order, its index as
    stored (None: the one-row groups' latest values, each cell from its own row), and the
    reason it was struck out ("" if it stands)."""

    cells: tuple[Cell, ...]
    index: int | None
    struck: str = ""


def received(
    group: ChannelGroup,
    typed_rows: Mapping[str, NDArray[np.float64]],
    start: int,
    corrections: Sequence[Correction],
) -> list[ReceivedRow]:
    """Rows ``start:`` of ``group`` as stored (``typed_rows``) as the page shows them:
    corrected, the value as typed kept, the struck rows marked; of a group of single
    values, one row of the latest value of each channel in a row not struck out (the value
    the results take)."""
    names = [c.name for c in group.channels]
    n = max((len(v) for v in typed_rows.values()), default=0)
    mine = [c for c in corrections if c.group == group.name]
    struck = {c.row: c.reason for c in mine if c.strikes}

    def cell(name: str, index: int) -> Cell:
        typed = float(typed_rows[name][index - start])
        if math.isnan(typed):
            return Cell(None, None, index)
        fixes = [c for c in mine if c.row == index and c.channel == name]
        value = fixes[-1].now if fixes else typed
        return Cell(value, typed, index, tuple(c.reason for c in fixes))

    if group.aligned:
        return [
            ReceivedRow(tuple(cell(name, i) for name in names), i, struck.get(i, ""))
            for i in range(start, start + n)
        ]
    latest: list[Cell] = []
    for name in names:
        held = [
            i
            for i in range(start, start + n)
            if i not in struck and not math.isnan(typed_rows[name][i - start])
        ]
        latest.append(cell(name, held[-1]) if held else Cell(None, None, -1))
    return [ReceivedRow(tuple(latest), None)] if any(c.index >= 0 for c in latest) else []


def entry_groups(
    t: Messages, stand: Stand, rows: Mapping[str, Sequence[ReceivedRow]]
) -> list[dict[str, Any]]:
    """The forms of the run's channel groups: the channels with their limits, and the
    ``rows`` the server holds of each (the last ones, :func:`received`)."""
    return [
        {
            "name": g.name,
            "title": t.gettext(g.long_name),
            "aligned": g.aligned,
            "required": [list(r) for r in g.required],
            "channels": _channels(t, g),
            "received": list(rows.get(g.name, ())),
        }
        for g in stand.groups
    ]


def entry_config(
    t: Messages, lang: Lang, run_id: str, form_token: str, decimal: str
) -> dict[str, Any]:
    """What ``entry.js`` needs beside the forms: where to send, the form token, the texts."""
    return {
        "run": run_id,
        "lang": lang,
        "rows_url": f"/runs/{run_id}/rows?lang={lang}",
        "readings_url": f"/runs/{run_id}/readings",
        "form_token": form_token,
        "decimal": decimal,
        "text": {key: t.gettext(text) for key, text in TEXTS.items()},
        "waiting": t.plural_forms(*WAITING),
    }
