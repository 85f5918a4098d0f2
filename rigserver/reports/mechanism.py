"""The report page of a dynamic-errors computation: ξ_k(t) beside the programmed motion."""

from __future__ import annotations

import numpy as np

from rigserver.reports.formatting import html_symbol
from rigserver.reports.i18n import Messages
from rigserver.reports.plots import lines
from rigserver.reports.render import render
from schemas.mechanism import DynamicErrorsRequest, DynamicErrorsResponse

JOINTS = ("shoulder q1", "forearm q2", "gripper q3")


def mechanism_report(request: DynamicErrorsRequest, result: DynamicErrorsResponse) -> str:
    """An HTML page with the programme, the errors in arc-minutes, and the maxima."""
    arcmin = 180.0 * 60.0 / np.pi
    programme = lines(
        result.t,
        [(name, result.q[k]) for k, name in enumerate(JOINTS)],
        xlabel="t, s",
        ylabel="q_k, rad",
        title="Programmed motion",
    )
    errors = lines(
        result.t,
        [
            (f"ξ{k + 1} ({name})", list(np.asarray(result.xi[k]) * arcmin))
            for k, name in enumerate(JOINTS)
        ],
        xlabel="t, s",
        ylabel="ξ_k, arcmin",
        title="Dynamic errors",
    )
    maxima = [
        {"joint": name, "rad": result.max_abs[k], "arcmin": result.max_abs[k] * arcmin}
        for k, name in enumerate(JOINTS)
    ]
    t = Messages("en")
    corrections = [html_symbol(t(f"abbr.e{n}")) for n in (6, 7, 8)]
    return render(
        "mechanism.html",
        corrections=corrections,
        request=request,
        result=result,
        programme=programme,
        errors=errors,
        maxima=maxima,
    )
