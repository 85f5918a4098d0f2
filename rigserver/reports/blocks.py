"""Tables built from the result models: values printed with ``fmt``, units from the schema."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from markupsafe import Markup
from pydantic import BaseModel

from rigserver.reports.document import Table, Text
from rigserver.reports.formatting import (
    column,
    decimal_sign,
    fmt,
    html_symbol,
    shown,
    shown_column,
    tex,
    with_uncertainty,
)
from rigserver.reports.i18n import Messages
from schemas.channels import ChannelGroup
from schemas.digits import stated_uncertainty
from schemas.labels import Label
from schemas.messages import N_
from schemas.quantity import units_of
from schemas.units import UNITS


def header(t: Messages, symbol: str, unit: str | None = None) -> Markup:
    """A column header: the symbol and, unless dimensionless, its unit (``e<sub>x</sub>, m``)."""
    label = html_symbol(t.symbol(symbol))
    if unit is None or unit == "1":
        return label
    return Markup("{}, {}").format(label, t.unit(unit))


AXES: dict[str, str] = {
    "L": N_("sliding distance"),
    "f": N_("friction coefficient"),
    "f_e": N_("measured friction coefficient"),
    "μ": N_("friction coefficient"),
    "x_s": N_("position along the stroke"),
    "θ": N_("angle on the disc"),
    "I_h": N_("wear intensity"),
    "N": N_("load"),
    "S_1": N_("bearing characteristic"),
    "S_1 = μ_t·ω/p̄": N_("bearing characteristic"),
    "S_1^{-1} = p̄/(μ_t·ω)": N_("inverse bearing characteristic"),
    "e_x": N_("journal centre along x"),
    "e_y": N_("journal centre along y"),
    "Δt": N_("temperature rise of the oil"),
    "x": N_("position along the trace"),
    "y": N_("height of the profile"),
    "ε": N_("relative depth"),
    "t_p": N_("relative bearing length"),
    "φ": N_("angle"),
    "Π": N_("dimensionless pressure"),
    "Π_e": N_("measured dimensionless pressure"),
    "z = Z/R": N_("axial coordinate"),
    "Z": N_("roughness profile"),
}
"""The quantity each plotted symbol stands for, named on the axis beside the symbol."""


def axis(t: Messages, symbol: str, unit: str | None = None) -> str:
    """An axis label for the plots: the quantity, its symbol in mathtext and the unit
    (``friction coefficient $f$``, ``journal centre along x $e_{x}$, µm``)."""
    label = tex(t.symbol(symbol))
    if symbol in AXES:
        label = f"{t.gettext(AXES[symbol])} {label}"
    if unit is None or unit == "1":
        return label
    return f"{label}, {t.unit(unit)}"


def quantities(
    t: Messages,
    caption: Text,
    model: BaseModel,
    fields: Sequence[tuple[str, str, str]],
    errors: Mapping[str, float | None] | None = None,
    *,
    labels: Mapping[str, Label],
    prefix: str = "",
) -> Table:
    """One row per quantity: its name, symbol, value and unit.

    ``fields`` holds ``(field name, symbol, message key of the quantity's name)``; the value
    is printed in the display unit and digits of its label (``labels[prefix + name]``);
    a value with an uncertainty among the model's fields is printed to it (GUM 7.2.6);
    ``errors`` adds a column of the instrument error of some fields (labels ``<name>_error``).
    """
    units = units_of(type(model))
    results = {n: getattr(model, n) for n in type(model).model_fields}
    rows: list[list[Text]] = []
    for name, symbol, key in fields:
        label = labels[prefix + name]
        stored = units.get(name, label.unit)
        row: list[Text] = [
            html_symbol(t(key)),
            html_symbol(t.symbol(symbol or label.symbol)),
            shown(label, getattr(model, name), stored, stated_uncertainty(name, results)),
            t.unit(label.unit),
        ]
        if errors is not None:
            error = labels.get(f"{prefix}{name}_error", label)
            row.append(shown(error, errors.get(name), stored))
        rows.append(row)
    head: list[Text] = [t("col.quantity"), t("col.symbol"), t("col.value"), t("col.unit")]
    if errors is not None:
        head.append(t("col.instrument_error"))
    return Table(caption=caption, header=head, rows=rows, labels=2)


def field(
    t: Messages,
    label: Label,
    symbol: str,
    stored: str,
    values: Sequence[float | None],
) -> tuple[Markup, list[Text]]:
    """A table column of a result: its header (``symbol``, display unit) and its values in
    the display unit (stored in ``stored``): a count whole, other numbers with one number of
    decimals, that of the largest to the label's digits (:mod:`schemas.digits`)."""
    return header(t, symbol, label.unit), shown_column(label, values, stored)


def result_table(
    t: Messages,
    caption: Text,
    rows: Sequence[BaseModel],
    fields: Sequence[tuple[str, str]],
    *,
    model: type[BaseModel],
    labels: Mapping[str, Label],
    note: Text = "",
) -> Table:
    """A table of result rows (``model`` each, labelled ``labels["<field>"]``), one column
    per ``(field name, symbol)``, in the display units and digits of the labels."""
    units = units_of(model)
    columns = [
        field(t, labels[name], symbol, units[name], [getattr(r, name) for r in rows])
        for name, symbol in fields
    ]
    return Table(
        caption=caption,
        header=[h for h, _ in columns],
        rows=[list(row) for row in zip(*(c for _, c in columns), strict=True)],
        note=note,
    )


def measurements(
    t: Messages,
    group: ChannelGroup,
    values: Mapping[str, float],
    resolutions: Mapping[str, float] | None = None,
) -> Table:
    """The single measurements posted (masses, zero readings) with their declared units;
    a channel with a ``resolutions`` entry (its instrument's step, in the channel's unit: the
    balance's 0.1 mg) is printed with the digits that instrument gives (12.2004 g)."""
    steps = resolutions or {}

    def printed(name: str) -> str:
        value = values.get(name)
        step = steps.get(name)
        if value is None or not step or step <= 0 or not math.isfinite(value):
            return fmt(value)
        places = max(0, -math.floor(math.log10(step) + 1e-9))
        return f"{value:.{places}f}".replace(".", decimal_sign())

    rows: list[list[Text]] = [
        [html_symbol(t.gettext(c.long_name)), printed(c.name), t.unit(c.unit)]
        for c in group.channels
    ]
    return Table(
        caption=t("caption.measurements"),
        header=[t("col.quantity"), t("col.value"), t("col.unit")],
        rows=rows,
        labels=1,
    )


def columns(
    caption: Text,
    head: Sequence[Text],
    data: Sequence[Sequence[float | Text | None]],
    note: Text = "",
) -> Table:
    """A table from columns of numbers (or printed cells), one list per column; the numbers
    of a column with one number of decimals (:func:`formatting.column`)."""
    printed = [_column(list(c)) for c in data]
    rows = [list(row) for row in zip(*printed, strict=True)]
    return Table(caption=caption, header=head, rows=rows, note=note)


def _column(cells: list[float | Text | None]) -> list[Text]:
    numbers = [None if isinstance(c, str) else c for c in cells]
    as_numbers = column(numbers)
    return [c if isinstance(c, str) else n for c, n in zip(cells, as_numbers, strict=True)]


def uncertainties(
    t: Messages,
    model: BaseModel,
    fields: Sequence[tuple[str, str, str]],
    label: str = "",
    *,
    labels: Mapping[str, Label],
    prefix: str = "",
) -> list[list[Text]]:
    """Rows of the uncertainty table: ``(field, symbol, message key)`` with the field's
    ``<field>_expanded`` beside it, printed ``value ± U (k = 2)`` in the display unit of
    its label (``labels[prefix + field]``); fields without a value are left out. ``label``
    goes after the quantity's name (an MTOS step)."""
    units = units_of(type(model))
    rows: list[list[Text]] = []
    for name, symbol, key in fields:
        value = getattr(model, name)
        if value is None:
            continue
        shown_as = labels[prefix + name]
        stored = units.get(name, shown_as.unit)
        factor = UNITS[stored].factor / UNITS[shown_as.unit].factor
        expanded = getattr(model, f"{name}_expanded", None)
        rows.append(
            [
                html_symbol(f"{t(key)}{label}"),
                html_symbol(t.symbol(symbol)),
                with_uncertainty(value * factor, None if expanded is None else expanded * factor),
                t.unit(shown_as.unit),
            ]
        )
    return rows


def uncertainty_table(t: Messages, rows: list[list[Text]]) -> Table:
    """The results with their expanded uncertainties (GUM, k = 2)."""
    head: list[Text] = [t("col.quantity"), t("col.symbol"), t("col.value"), t("col.unit")]
    return Table(caption=t("u.caption"), header=head, rows=rows, labels=2)
