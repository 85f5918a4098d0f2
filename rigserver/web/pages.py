"""The pages of the service: the runs list and a run's live view, rendered on the server.

The API layer hands them their data (runs, stands); they import neither the API nor the
storage. The live chart and the results on a run's page are drawn by ``static/live.js``,
a plain script (no build step) fed by the server-sent events of ``/runs/{id}/live``; the
forms that take the readings at the stand by ``static/entry.js`` (:mod:`rigserver.web.entry`;
the page that opens a run: :mod:`rigserver.web.new_run`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import lru_cache
from typing import Any
from urllib.parse import urlencode

from babel import Locale
from jinja2 import Environment, PackageLoader, select_autoescape
from markupsafe import Markup

from rigserver.reports import results_view
from rigserver.reports.formatting import (
    decimal_sign,
    fmt,
    html_symbol,
    number_locale,
    plain_text,
    shown,
    shown_column,
    with_unit,
)
from rigserver.reports.i18n import LANGS, Lang, Messages
from rigserver.reports.kits import KITS
from rigserver.reports.labs.tribometer import stribeck_svg
from rigserver.reports.run_report import configuration_rows, particulars_text
from rigserver.reports.x3p import PROFILE_GROUP, NoProfile, profile_group
from rigserver.web.entry import ReceivedRow, entry_config, entry_groups, typed
from rigserver.web.sketches import SKETCH_MAX_MIB, sketch_items
from schemas import labelled
from schemas.channels import ChannelGroup
from schemas.digits import stated_uncertainty
from schemas.labels import Part
from schemas.messages import NP_
from schemas.quantity import unit_paths
from schemas.results import PinOnDiscResults, ReciprocatingResults
from schemas.runs import Run, RunPage, RunState
from schemas.sketches import Sketch
from schemas.stands import DECLARATIONS, Stand, StandKind, theory_outside
from schemas.student_notes import CONCLUSIONS_LIMIT, StudentNotes

API = "/api/v1"


@lru_cache
def environment(lang: Lang) -> Environment:
    """The pages' templates in ``lang``: ``_()`` of Jinja2's i18n extension is the
    language's catalog."""
    env = Environment(
        loader=PackageLoader("rigserver.web", "templates"),
        autoescape=select_autoescape(["html"]),
        trim_blocks=True,
        lstrip_blocks=True,
        extensions=["jinja2.ext.i18n"],
    )
    env.install_gettext_translations(Messages(lang).translations, newstyle=True)  # type: ignore[attr-defined]
    env.filters["fmt"] = fmt
    env.filters["sym"] = html_symbol
    env.filters["plain"] = plain_text
    env.filters["typed"] = typed
    return env


def live_axes(record: ChannelGroup) -> tuple[str, str]:
    """The channels drawn first on a run's live chart, x and y: the record's declared axis
    and main signal (its NeXus default plot), else its first and last channels (any channel
    can be chosen)."""
    if record.axis is not None and record.signals:
        return record.axis, record.signals[0]
    return record.channels[0].name, record.channels[-1].name


def render_page(template: str, lang: Lang, **context: Any) -> str:
    """A page of the site in ``lang``: the template with ``t``, ``_()`` and the link to the
    other language."""
    t = Messages(lang)
    other = _other(lang)
    with number_locale(lang):
        return (
            environment(lang)
            .get_template(template)
            .render(
                t=t,
                lang=lang,
                other=other,
                other_name=(Locale.parse(other).get_display_name(other) or other).capitalize(),
                **context,
            )
        )


def key_results(t: Messages, run: Run) -> Markup:
    """``f = 0.3985; I_h,exp = 3.833·10⁻⁸`` in the display units of the stand's results; a
    theoretical value outside its theory's range says so beside it (never a bare headline)."""
    units = unit_paths(DECLARATIONS[run.stand].results)
    labels = DECLARATIONS[run.stand].labels
    outside = theory_outside(run.stand, run.key_results)
    verdict = DECLARATIONS[run.stand].theory_verdict
    parts = []
    for path, value in run.key_results.items():
        if path == verdict:
            continue
        label = labels[path]
        u = stated_uncertainty(path, run.key_results)
        text = shown(label, value, units.get(path, label.unit), u)
        unit = results_view.unit(t, label)
        name = html_symbol(t.symbol(label.symbol) or t.gettext(label.text))
        part = Markup("{} = {}").format(name, with_unit(text, unit))
        if outside and label.part is Part.THEORY:
            part += Markup(' <em class="outside">({})</em>').format(t("theory_outside"))
        parts.append(part)
    return Markup("; ").join(parts)


def results_html(*, run: Run, payload: Mapping[str, Any], lang: Lang) -> str:
    """The results of a run grouped as in the report (measured, theory, comparison), in
    the declared order, then its per-row tables: a part of the run page."""
    t = Messages(lang)

    scalars = labelled.scalars(run.stand, payload)
    values = {e.path: e.value for e in scalars}

    def entry(e: labelled.Entry) -> dict[str, Any]:
        u = stated_uncertainty(e.path, values)
        return {
            "path": e.path,
            "name": html_symbol(results_view.name(t, e.label)),
            "symbol": html_symbol(t.symbol(e.label.symbol)),
            "value": results_view.value(t, e.label, e.value, e.stored, u),
            "unit": results_view.unit(t, e.label),
        }

    with number_locale(lang):
        parts = [
            (title, [entry(e) for e in entries]) for title, entries in labelled.by_part(scalars)
        ]
        tables = [
            {
                "name": found.table.name,
                "caption": t.gettext(found.table.caption),
                "header": [
                    {
                        "name": results_view.name(t, c.label),
                        "symbol": html_symbol(t.symbol(c.symbol) or t.gettext(c.label.text)),
                        "unit": results_view.unit(t, c.label),
                    }
                    for c in found.columns
                ],
                "rows": _printed_rows(t, found),
            }
            for found in labelled.row_tables(run.stand, payload)
        ]
        figures = _figures(t, run, payload)
    pending = [t.gettext(item) for item in payload.get("values", {}).get("pending", [])]
    return render_page(
        "results.html", lang, parts=parts, tables=tables, figures=figures, pending=pending
    )


def _printed_rows(t: Messages, found: labelled.RowsOf) -> list[list[str]]:
    """A per-row table's cells as printed: a column of numbers with one number of decimals
    (:func:`shown_column`), words in the page's language, nothing for a value not given."""
    columns = []
    for index, c in enumerate(found.columns):
        cells = [row[index] for row in found.rows]
        numbers = [
            v if isinstance(v, int | float) and not isinstance(v, bool) else None for v in cells
        ]
        printed = shown_column(c.label, numbers, c.stored)

        def cell(value: Any, number: float | None, text: str, c: labelled.Column = c) -> str:
            if number is not None:
                return text
            return "" if value is None else results_view.value(t, c.label, value, c.stored)

        columns.append([cell(*v) for v in zip(cells, numbers, printed, strict=True)])
    return [list(row) for row in zip(*columns, strict=True)]


def _figures(t: Messages, run: Run, payload: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The plots of the results part beside the live chart: a tribometer's μ against the
    sliding speed over its recipe's steps (a Stribeck curve), as the report draws it."""
    values = payload.get("values", {})
    if run.stand not in (StandKind.PIN_ON_DISC, StandKind.RECIPROCATING):
        return []
    if not any(step.get("sliding_speed") is not None for step in values.get("steps", [])):
        return []
    found = DECLARATIONS[run.stand].results.model_validate(values)
    assert isinstance(found, PinOnDiscResults | ReciprocatingResults)
    return [{"caption": t("t.fig_stribeck"), "svg": Markup(stribeck_svg(t, found))}]


def runs_page(
    *,
    page: RunPage,
    filters: Mapping[str, str],
    offset: int,
    limit: int,
    lang: Lang,
    signed_in: bool = False,
    writable: Sequence[StandKind] = (),
) -> str:
    """The runs, newest first, with the filter form and links to the neighbouring pages,
    and to open a new run on the stands ``writable`` by the caller.

    ``filters`` are the form's values as given (``stand``, ``operator``, ``state``,
    ``since``, ``until``: ISO dates), kept in the links.
    """
    t = Messages(lang)
    kept = {k: v for k, v in filters.items() if v}

    def link(at: int) -> str:
        return "/?" + urlencode({**kept, "offset": at, "lang": lang})

    with number_locale(lang):
        rows = [(run, key_results(t, run)) for run in page.runs]
    return render_page(
        "runs.html",
        lang,
        signed_in=signed_in,
        writable=writable,
        page=page,
        rows=rows,
        filters=filters,
        stands=list(StandKind),
        states=list(RunState),
        first=offset + 1 if page.runs else 0,
        last=offset + len(page.runs),
        newer=link(max(0, offset - limit)) if offset > 0 else None,
        older=link(offset + limit) if offset + limit < page.total else None,
    )


def login_page(*, next_page: str, refused: bool, lang: Lang) -> str:
    """The form that turns a key with the ``read`` scope into a session of the pages."""
    return render_page("login.html", lang, next=next_page, refused=refused, on_login=True)


#: The words after the count of a run's rows, singular and plural (message ids).
ROWS_RECEIVED = NP_("row received", "rows received")


def run_page(
    *,
    run: Run,
    stand: Stand,
    payload: Mapping[str, Any],
    lang: Lang,
    signed_in: bool = False,
    notes: StudentNotes | None = None,
    sketches: Sequence[Sketch] = (),
    may_write: bool = False,
    form_token: str = "",
    received: Mapping[str, Sequence[ReceivedRow]] | None = None,
) -> str:
    """A run: its particulars, the live chart of its record, its results (``payload``, as
    ``/results`` answers), the downloads, the student's ``notes`` and ``sketches`` on it
    (every version), and the forms that write them for the caller who ``may_write`` them
    (its stand's write scope). A session (its ``form_token``) that may write an open run
    also gets the forms that take its readings (:mod:`rigserver.web.entry`), with the rows
    ``received`` so far; of a finished run, the rows received, to be corrected."""
    t = Messages(lang)
    record = next(g for g in stand.groups if g.aligned)
    x, y = live_axes(record)
    base = f"{API}/runs/{run.id}"
    config: dict[str, Any] = {
        "run": run.id,
        "state": run.state.value,
        "group": record.name,
        "x": x,
        "y": y,
        "channels": [
            {"name": c.name, "unit": t.unit(c.unit), "label": plain_text(t.gettext(c.long_name))}
            for c in record.channels
        ],
        "live_url": f"{base}/live?group={record.name}",
        "results_url": f"/runs/{run.id}/results?lang={lang}",
        "decimal": decimal_sign_of(lang),
        "text": {
            key: t(f"page.{key}") for key in ("connecting", "streaming", "reconnecting", "ended")
        }
        | {f"state_{s.value}": t(f"state.{s.value}") for s in RunState},
        "lang": lang,
        "rows_received": t.plural_forms(*ROWS_RECEIVED),
    }
    with number_locale(lang):
        specimen = particulars_text(t, run.specimen)
        test_plan = particulars_text(t, run.test_plan)
        configuration = configuration_rows(t, run)
    # an open run takes rows; a finished one takes corrections of them
    entry = may_write and bool(form_token) and run.state in (RunState.OPEN, RunState.FINISHED)
    return render_page(
        "run.html",
        lang,
        signed_in=signed_in,
        run=run,
        stand=stand,
        base=base,
        config=config,
        record=record,
        y=y,
        specimen=specimen,
        test_plan=test_plan,
        configuration=configuration,
        results=Markup(results_html(run=run, payload=payload, lang=lang)),
        profile_x3p=_has_profile(stand),
        notes=notes or StudentNotes(),
        sketches=sketch_items(t, run.stand, sketches),
        sketch_limit=SKETCH_MAX_MIB,
        may_write=may_write,
        form_token=form_token,
        conclusions_limit=CONCLUSIONS_LIMIT,
        groups=entry_groups(t, stand, received or {}) if entry else [],
        taking=run.state is RunState.OPEN,
        entry_config=(
            entry_config(t, lang, run.id, form_token, config["decimal"]) if entry else None
        ),
        rows_received=t.plural(*ROWS_RECEIVED, 0),
        words=[
            (field.value, t.gettext(heading)) for field, heading in KITS[run.stand].contents.words()
        ],
    )


def _has_profile(stand: Stand) -> bool:
    """Whether the stand traces a profile that ``profile.x3p`` can give."""
    try:
        profile_group(stand.groups, PROFILE_GROUP)
    except NoProfile:
        return False
    return True


def decimal_sign_of(lang: Lang) -> str:
    """The decimal sign of ``lang``'s numbers (for the live chart's ticks)."""
    with number_locale(lang):
        return decimal_sign()


def _other(lang: Lang) -> Lang:
    return next(code for code in LANGS if code != lang)
