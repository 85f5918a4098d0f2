"""Markers of the texts shown to people, for Babel's extraction into the gettext catalogs
(``rigserver/locale``); they return the text as it is (English, the message id)."""

from __future__ import annotations


def N_(text: str) -> str:
    """Mark ``text`` for the catalogs without translating it (gettext's ``N_``)."""
    return text


def C_(context: str, text: str) -> str:
    """Mark ``text`` for the catalogs in a message ``context`` (``C_("unit", "s")``: the
    unit, not the word); extracted with the keyword ``C_:1c,2``."""
    return text


def NP_(singular: str, plural: str) -> tuple[str, str]:
    """Mark the words of a count, singular and plural, for extraction (``-k NP_:1,2``);
    translated by their number at run time (:meth:`rigserver.reports.i18n.Messages.plural`)."""
    return singular, plural
