"""The series pages: ``/series`` (every series) and ``/series/{id}`` (its runs, statistics and
overlay plots, the same tables as its report; ``static/series.js`` refreshes them while a
member run is open)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from markupsafe import Markup

from rigserver.reports.i18n import Lang
from rigserver.reports.series_report import text
from rigserver.web.pages import render_page
from schemas.series import Series, SeriesDetail

#: Seconds between refreshes of a series page while a member run is open.
REFRESH_SECONDS = 5


def series_list_page(*, series: list[Series], lang: Lang, signed_in: bool = False) -> str:
    return render_page("series_list.html", lang, s=text(lang), signed_in=signed_in, series=series)


def series_page(
    *,
    detail: SeriesDetail,
    context: Mapping[str, Any],
    body: Markup,
    lang: Lang,
    signed_in: bool = False,
) -> str:
    """A series: what it is for, and the report's tables and plots (``body``)."""
    return render_page(
        "series.html",
        lang,
        s=text(lang),
        signed_in=signed_in,
        detail=detail,
        purpose=context["purpose"],
        body=body,
        refresh=REFRESH_SECONDS if detail.open_runs else 0,
    )
