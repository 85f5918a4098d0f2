"""The report page of a dynamic-errors computation: ξ_k(t) beside the programmed motion, in
the page's language."""

from __future__ import annotations

import numpy as np

from rigserver.reports.formatting import fmt, html_symbol, number_locale, tex
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.plots import lines
from rigserver.reports.render import render
from schemas.mechanism import DynamicErrorsRequest, DynamicErrorsResponse

JOINTS = ("mech.shoulder", "mech.forearm", "mech.gripper")
"""The message keys of the arm's joints, q1 … q3."""


def mechanism_report(
    request: DynamicErrorsRequest, result: DynamicErrorsResponse, lang: Lang = "en"
) -> str:
    """An HTML page with the programme, the errors in arc-minutes, and the maxima."""
    t = Messages(lang)
    with number_locale(lang):
        return _page(t, request, result)


def _page(t: Messages, request: DynamicErrorsRequest, result: DynamicErrorsResponse) -> str:
    arcmin = 180.0 * 60.0 / np.pi
    joints = [t(key) for key in JOINTS]
    time_axis = f"{tex('t')}, {t.unit('s')}"
    programme = lines(
        result.t,
        [(name, result.q[k]) for k, name in enumerate(joints)],
        xlabel=time_axis,
        ylabel=f"{tex('q_k')}, {t.unit('rad')}",
        title=t("mech.programme"),
    )
    errors = lines(
        result.t,
        [
            (f"{tex(f'ξ_{k + 1}')} ({name})", list(np.asarray(result.xi[k]) * arcmin))
            for k, name in enumerate(joints)
        ],
        xlabel=time_axis,
        ylabel=f"{tex('ξ_k')}, {t('mech.arcmin')}",
        title=t("mech.errors"),
    )
    move = request.move
    described = t(
        "mech.move",
        article=t("mech.article"),
        start="; ".join(fmt(q) for q in move.q_start),
        end="; ".join(fmt(q) for q in move.q_end),
        rad=t.unit("rad"),
        duration=fmt(move.duration),
        s=t.unit("s"),
        profile=t(f"mech.{move.profile}"),
        method=request.method,
        evaluations=result.evaluations,
    )
    maxima = [
        (name, fmt(result.max_abs[k]), fmt(result.max_abs[k] * arcmin))
        for k, name in enumerate(joints)
    ]
    header = [
        t("mech.joint"),
        f"max |ξ|, {t.unit('rad')}",
        f"max |ξ|, {t('mech.arcmin')}",
    ]
    return render(
        "mechanism.html",
        lang=t.lang,
        title=t("mech.title"),
        described=described,
        failed=None if result.success else t("mech.failed", message=result.message),
        programme=programme,
        errors=errors,
        header=header,
        maxima=maxima,
        corrections_title=t("mech.corrections"),
        corrections=[html_symbol(t(f"abbr.e{n}")) for n in (6, 7, 8)],
    )
