"""A run's results as people read them in a language: the label's words with the manual's
equation number, the value in the display unit and digits, the unit (the walking of the
payload is :mod:`schemas.labelled`)."""

from __future__ import annotations

from typing import Any

from rigserver.reports.formatting import shown
from rigserver.reports.i18n import Messages
from schemas.labels import VALUE_WORDS, Label


def name(t: Messages, label: Label) -> str:
    """The label's words in ``t``'s language with the manual's equation number."""
    words = t.gettext(label.text)
    return f"{words} ({label.equation})" if label.equation else words


def value(t: Messages, label: Label, stored_value: Any, stored: str) -> str:
    """A result's value as printed: a number in the display unit to its digits, a word or
    a verdict in ``t``'s language."""
    if isinstance(stored_value, bool):
        return t("yes") if stored_value else t("no")
    if isinstance(stored_value, str):
        return t.gettext(VALUE_WORDS.get(stored_value, stored_value))
    return shown(label, stored_value, stored)


def unit(t: Messages, label: Label) -> str:
    """The display unit as printed (empty for a dimensionless result)."""
    return "" if label.unit == "1" else t.unit(label.unit)
