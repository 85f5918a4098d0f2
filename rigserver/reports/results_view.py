"""A run's results as people read them in a language: the label's words with the manual's
equation number, the value in the display unit and digits, the unit (the walking of the
payload is :mod:`schemas.labelled`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from rigserver.reports.formatting import shown
from rigserver.reports.i18n import Messages
from schemas import labelled
from schemas.labels import VALUE_WORDS, Label, plain_symbol
from schemas.quantities import Quantity
from schemas.stands import StandKind

UNCERTAINTY = "_uncertainty"


def name(t: Messages, label: Label) -> str:
    """The label's words in ``t``'s language with the manual's equation number."""
    words = t.gettext(label.text)
    return f"{words} ({label.equation})" if label.equation else words


def value(
    t: Messages, label: Label, stored_value: Any, stored: str, uncertainty: float | None = None
) -> str:
    """A result's value as printed: a number in the display unit to its digits (to its
    ``uncertainty``'s place when it has one, GUM 7.2.6), a word or a verdict in ``t``'s
    language."""
    if isinstance(stored_value, bool):
        return t("yes") if stored_value else t("no")
    if isinstance(stored_value, str):
        return t.gettext(VALUE_WORDS.get(stored_value, stored_value))
    return shown(label, stored_value, stored, uncertainty)


def unit(t: Messages, label: Label) -> str:
    """The display unit as printed (empty for a dimensionless result)."""
    return "" if label.unit == "1" else t.unit(label.unit)


def _number(label: Label, stored_value: Any, stored: str) -> Any:
    """A value in the display unit to full precision (a frame's cell); words as they are."""
    if isinstance(stored_value, bool | str) or stored_value is None:
        return stored_value
    return label.displayed(float(stored_value), stored)


def quantities(t: Messages, kind: StandKind, payload: Mapping[str, Any]) -> list[Quantity]:
    """The single results as the pages list them, one row each with the standard
    uncertainty beside its value (both in the display unit, unrounded: the data of a
    notebook's frame, not the printed digits); the ``*_uncertainty`` results themselves are
    folded into their value's row."""
    entries = labelled.scalars(kind, payload)
    by_path = {e.path: e for e in entries}
    rows = []
    for e in entries:
        if e.path.endswith(UNCERTAINTY) and e.path.removesuffix(UNCERTAINTY) in by_path:
            continue
        u = by_path.get(e.path + UNCERTAINTY)
        rows.append(
            Quantity(
                path=e.path,
                quantity=plain_symbol(name(t, e.label)),
                symbol=plain_symbol(t.symbol(e.label.symbol)),
                value=_number(e.label, e.value, e.stored),
                uncertainty=None if u is None else _number(e.label, u.value, u.stored),
                unit=unit(t, e.label),
                part=e.label.part.value,
            )
        )
    return rows
