"""The two pages of the service: the runs list and a run's live view, rendered on the server.

The API layer hands them their data (runs, stands); they import neither the API nor the
storage. The live chart and the results on a run's page are drawn by ``static/live.js``,
a plain script (no build step) fed by the server-sent events of ``/runs/{id}/live``.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import Any
from urllib.parse import urlencode

from jinja2 import Environment, PackageLoader, select_autoescape
from markupsafe import Markup

from rigserver.reports.formatting import fmt, html_symbol, pairs
from rigserver.reports.i18n import LANGS, UNIT_LABELS, Lang, Messages
from rigserver.reports.run_report import RESULT_MODELS
from schemas.quantity import unit_paths
from schemas.runs import Run, RunPage, RunState
from schemas.stands import Stand, StandKind

API = "/api/v1"

LIVE_AXES: dict[StandKind, tuple[str, str]] = {
    StandKind.SMTS2: ("time", "friction_moment"),
    StandKind.SLIDE_BEARING: ("limb_angle", "p3"),
    StandKind.MTOS: ("load", "indicator"),
    StandKind.PROFILOMETER: ("x", "y"),
}
"""The channels drawn first on a run's live chart: x and y (any channel can be chosen)."""

KEY_SYMBOLS: dict[str, str] = {
    "friction_steady": "f",
    "experimental.intensity": "I_{h,exp}",
    "experimental.specific_wear_rate": "k",
    "theoretical.intensity": "I_{h,theor}",
    "chi_mean": "χ_ср",
    "pressure_max": "p_max",
    "phi_max": "φ_pmax",
    "friction_fluid": "f_э",
    "h_min_smallest": "h_min",
    "h_crit": "h_min^crit",
    "ra": "R_a",
    "rz": "R_z",
    "complex_parameter": "Δ",
}
"""How the runs list names the headline results of each stand (``Run.key_results``)."""


@lru_cache
def environment() -> Environment:
    env = Environment(
        loader=PackageLoader("rigserver.web", "templates"),
        autoescape=select_autoescape(["html"]),
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters["fmt"] = fmt
    env.filters["sym"] = html_symbol
    env.filters["pairs"] = pairs
    return env


def key_results(t: Messages, run: Run) -> Markup:
    """``f = 0.3985; I_h,exp = 3.833·10⁻⁸`` with the units of the stand's results."""
    units = unit_paths(RESULT_MODELS[run.stand])
    parts = []
    for path, value in run.key_results.items():
        unit = units.get(path, "1")
        shown = f"{fmt(value)} {t.unit(unit)}" if unit != "1" else fmt(value)
        name = html_symbol(KEY_SYMBOLS[path]) if path in KEY_SYMBOLS else path
        parts.append(Markup("{} = {}").format(name, shown))
    return Markup("; ").join(parts)


def runs_page(
    *,
    page: RunPage,
    filters: Mapping[str, str],
    offset: int,
    limit: int,
    lang: Lang,
    signed_in: bool = False,
) -> str:
    """The runs, newest first, with the filter form and links to the neighbouring pages.

    ``filters`` are the form's values as given (``stand``, ``operator``, ``state``,
    ``since``, ``until``: ISO dates), kept in the links.
    """
    t = Messages(lang)
    kept = {k: v for k, v in filters.items() if v}

    def link(at: int) -> str:
        return "/?" + urlencode({**kept, "offset": at, "lang": lang})

    return (
        environment()
        .get_template("runs.html")
        .render(
            t=t,
            lang=lang,
            other=_other(lang),
            signed_in=signed_in,
            page=page,
            rows=[(run, key_results(t, run)) for run in page.runs],
            filters=filters,
            stands=list(StandKind),
            states=list(RunState),
            first=offset + 1 if page.runs else 0,
            last=offset + len(page.runs),
            newer=link(max(0, offset - limit)) if offset > 0 else None,
            older=link(offset + limit) if offset + limit < page.total else None,
        )
    )


def login_page(*, next_page: str, refused: bool, lang: Lang) -> str:
    """The form that turns a key with the ``read`` scope into a session of the pages."""
    return (
        environment()
        .get_template("login.html")
        .render(t=Messages(lang), lang=lang, other=_other(lang), next=next_page, refused=refused)
    )


def run_page(*, run: Run, stand: Stand, lang: Lang, signed_in: bool = False) -> str:
    """A run: its particulars, the live chart of its record, its results, the downloads."""
    t = Messages(lang)
    record = next(g for g in stand.groups if g.aligned)
    x, y = LIVE_AXES.get(stand.kind, (record.channels[0].name, record.channels[-1].name))
    base = f"{API}/runs/{run.id}"
    config: dict[str, Any] = {
        "run": run.id,
        "state": run.state.value,
        "group": record.name,
        "x": x,
        "y": y,
        "channels": [
            {"name": c.name, "unit": t.unit(c.unit), "long_name": c.long_name}
            for c in record.channels
        ],
        "live_url": f"{base}/live?group={record.name}",
        "results_url": f"{base}/results",
        "units": {symbol: t.unit(symbol) for symbol in UNIT_LABELS},
        "text": {
            key: t(f"page.{key}") for key in ("connecting", "streaming", "reconnecting", "ended")
        }
        | {f"state_{s.value}": t(f"state.{s.value}") for s in RunState},
    }
    return (
        environment()
        .get_template("run.html")
        .render(
            t=t,
            lang=lang,
            other=_other(lang),
            signed_in=signed_in,
            run=run,
            stand=stand,
            groups=[g.name for g in stand.groups],
            base=base,
            config=config,
            record=record,
            y=y,
        )
    )


def _other(lang: Lang) -> Lang:
    return next(code for code in LANGS if code != lang)
