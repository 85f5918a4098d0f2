"""Lab work 1 (ABRIS-PM7): the profile, tables 1.6-1.8, the complex parameter (1.9)-(1.11)."""

from __future__ import annotations

import dataclasses

import numpy as np
from markupsafe import Markup
from numpy.typing import NDArray

from rigserver.core import bearing_readings, roughness
from rigserver.reports import blocks
from rigserver.reports.context import Context, LabReport, sections
from rigserver.reports.document import Block, Figure, Table, Text
from rigserver.reports.downsample import min_max
from rigserver.reports.formatting import (
    DASH,
    decimal_sign,
    fmt,
    html_symbol,
    percent,
    shown,
    with_uncertainty,
)
from rigserver.reports.i18n import Messages
from rigserver.reports.labs import iso_profile
from rigserver.reports.plots import axes, decorate, to_svg
from schemas.labels import PROFILOMETER
from schemas.quantity import units_of
from schemas.results import BearingFitResult, ProfilometerResults
from schemas.units import UNITS

GROUP = "profile"
#: The symbols of the parameters :func:`roughness.outside_subrange` names.
_SYMBOLS = {"Ra": "R_a", "Rz": "R_z", "Rmax": "R_max", "Sm": "S_m"}
#: Columns the profile is decimated to for drawing (min-max keeps every peak and valley).
DRAWN_COLUMNS = 700


def build(ctx: Context, v: ProfilometerResults) -> LabReport:
    t = ctx.t
    measured: list[Block] = [ctx.measurements()]
    if ctx.readings.rows(GROUP):
        measured.append(Figure(t("p.fig_profile"), _profile_svg(ctx, v)))
    if v.ra is not None:
        params = blocks.quantities(
            t,
            t("p.params"),
            v,
            [
                ("base_length", "l", "p.base_length"),
                ("ra", "R_a", "p.ra"),
                ("rq", "R_q", "p.rq"),
                ("rz", "R_z", "p.rz"),
                ("rmax", "R_max", "p.rmax"),
                ("sm", "S_m", "p.sm"),
                ("asperity_radius", "R", "p.r"),
            ],
            errors={"ra": v.ra_error, "rz": v.rz_error, "rmax": v.rmax_error, "sm": v.sm_error},
            labels=PROFILOMETER,
        )
        if v.outside_subrange and v.base_length is not None:
            params = dataclasses.replace(params, note=_outside(t, v))
        measured.append(params)
    if v.rz_peaks:
        measured.append(_peaks(t, v))
    if v.rmax_difference is not None:
        measured.append(_against_profilogram(ctx, v))
    processed: list[Block] = []
    if v.tp:
        processed.append(_table_1_6(t, v))
    fits = [f for f in (v.fit_manual, v.fit_lsq) if f is not None]
    if fits:
        processed.append(_table_1_7(t, fits))
    if v.fit_manual is not None:
        processed.append(_table_1_8(t, v, v.fit_manual))
    if v.tp:
        processed.append(Figure(t("p.fig_bearing"), _bearing_svg(t, v, fits)))
    if v.complex_parameter is not None:
        processed.append(
            blocks.quantities(
                t,
                t("p.complex"),
                v,
                [
                    ("complex_parameter", "Δ", "p.delta"),
                    ("ra_from_complex", "R_{a,Δ}", "p.ra_delta"),
                    ("complex_parameter_equilibrium", "Δ_T", "p.delta_t"),
                ],
                labels=PROFILOMETER,
            )
        )
    spread = blocks.uncertainties(
        t, v, [("ra", "R_a", "p.ra"), ("rz", "R_z", "p.rz")], labels=PROFILOMETER
    )
    if spread and v.ra_expanded is not None:
        processed.append(blocks.uncertainty_table(t, spread))
    found = sections(t, measured, processed)
    iso = iso_profile.profilometer_section(
        t, v, _trace_m(ctx) if ctx.readings.rows(GROUP) else None
    )
    if iso is not None:
        found.append(iso)
    return LabReport(sections=found, conclusions=_conclusions(t, v))


def _trace_m(ctx: Context) -> dict[str, NDArray[np.float64]]:
    """The trace in metres."""
    trace = ctx.readings.read(GROUP, ["x", "y"])
    units = ctx.units(GROUP)
    return {name: trace[name] * UNITS[units[name]].factor for name in ("x", "y")}


def _profile_svg(ctx: Context, v: ProfilometerResults) -> str:
    """The trace as measured (mm, μm) with the mean, peak and valley lines of (1.3)-(1.4)."""
    t = ctx.t
    trace = ctx.readings.read(GROUP, ["x", "y"])
    units = ctx.units(GROUP)
    fx, fy = UNITS[units["x"]].factor, UNITS[units["y"]].factor
    x, y = trace["x"], trace["y"]
    fig, (ax,) = axes(height=3.0)
    shown_x, shown_y = min_max(x, y, buckets=DRAWN_COLUMNS)
    ax.plot(shown_x, shown_y, linewidth=0.6, color="0.25", label=t("p.profile"))
    if v.rmax is not None:
        line = roughness.mean_line(x=x * fx, y=y * fy)
        deviation = y * fy - (line.slope * x * fx + line.intercept)
        ends = np.array([x[0], x[-1]])
        base = (line.slope * ends * fx + line.intercept) / fy
        for offset, key, style in (
            (0.0, "p.mean_line", "-"),
            (float(deviation.max()) / fy, "p.peak_line", "--"),
            (float(deviation.min()) / fy, "p.valley_line", "--"),
        ):
            ax.plot(ends, base + offset, style, linewidth=1.0, label=t(key))
        peak = float(deviation.max()) / fy
        for number, depth in enumerate(v.levels):  # the sections of table 1.6, p_i below it
            ax.plot(
                ends,
                base + peak - depth / fy,
                ":",
                linewidth=0.6,
                color="C3",
                label=t("p.levels") if number == 0 else None,
            )
    decorate(
        ax,
        xlabel=blocks.axis(t, "x", units["x"]),
        ylabel=blocks.axis(t, "y", units["y"]),
        legend_outside=True,
    )
    return to_svg(fig)


def _outside(t: Messages, v: ProfilometerResults) -> Text:
    """The parameters outside the ranges of the subrange of the base length, flagged."""
    assert v.base_length is not None
    sub = roughness.subrange_of_base_length(v.base_length)
    assert sub is not None
    um = 1.0 / UNITS["um"].factor

    def span(low: float, high: float) -> str:
        return f"{fmt(low * um)}–{fmt(high * um)}"

    return html_symbol(
        t(
            "p.outside",
            names=", ".join(t.symbol(_SYMBOLS[n]) for n in v.outside_subrange),
            cutoff=fmt(sub.cutoff / UNITS["mm"].factor),
            ra=span(sub.ra_min, sub.ra_max),
            rz=span(sub.rz_min, sub.rz_max),
            sm=span(sub.sm_min, sub.sm_max),
        )
    )


#: Decimals of the item 10 table: the readings as the instrument gives them (0.001 µm), the
#: profilogram's values one place finer, δ to 0.01 %: δ recomputed from the printed values
#: agrees with the printed δ to its last place.
READING_PLACES, PROFILOGRAM_PLACES, DIFFERENCE_PLACES = 3, 4, 2


def _fixed(value: float, places: int) -> str:
    return f"{value:.{places}f}".replace(".", decimal_sign())


def _against_profilogram(ctx: Context, v: ProfilometerResults) -> Table:
    """Item 10: the profilometer's Ra, Rz, Rmax against the profilogram's, δ (1.20) relative
    to the reading (E10), each input printed to the digits δ needs."""
    t = ctx.t
    m = ctx.readings.measurements()
    um = 1.0 / UNITS["um"].factor
    rows: list[list[Text]] = []
    for name, field, symbol in (
        ("ra", "ra_difference", "δ_{Ra}"),
        ("rz", "rz_difference", "δ_{Rz}"),
        ("rmax", "rmax_difference", "δ"),
    ):
        reading, value, difference = (
            m.get(f"{name}_instrument"),
            getattr(v, name),
            getattr(v, field),
        )
        if reading is None or value is None or difference is None:
            continue
        rows.append(
            [
                html_symbol(t.symbol(PROFILOMETER[name].symbol)),
                _fixed(reading, READING_PLACES),
                _fixed(value * um, PROFILOGRAM_PLACES),
                html_symbol(t.symbol(symbol)),
                _fixed(difference, DIFFERENCE_PLACES),
            ]
        )
    head: list[Text] = [
        t("col.quantity"),
        blocks.header(t, t("p.instrument"), "um"),
        blocks.header(t, t("p.profilogram"), "um"),
        t("col.symbol"),
        blocks.header(t, t("p.difference"), "%"),
    ]
    return Table(
        caption=html_symbol(t("p.vs")),
        header=head,
        rows=rows,
        labels=1,
        note=html_symbol(t("p.vs_source")),
    )


def _peaks(t: Messages, v: ProfilometerResults) -> Table:
    """The five highest peaks and the five deepest valleys behind Rz (1.4), µm, and Rz from
    them as printed."""
    um = 1.0 / UNITS["um"].factor
    rows: list[list[Text]] = [
        [str(i), _fixed(p * um, PROFILOGRAM_PLACES), _fixed(w * um, PROFILOGRAM_PLACES)]
        for i, (p, w) in enumerate(zip(v.rz_peaks, v.rz_valleys, strict=False), start=1)
    ]
    printed = [round(p * um, PROFILOGRAM_PLACES) for p in v.rz_peaks]
    printed += [abs(round(w * um, PROFILOGRAM_PLACES)) for w in v.rz_valleys]
    rz = sum(printed) / len(v.rz_peaks) if v.rz_peaks else None
    total = (
        Markup("{} = {}").format(html_symbol(t.symbol("R_z")), _fixed(rz, PROFILOGRAM_PLACES))
        if rz is not None
        else ""
    )
    rows.append([total, "", ""])
    head: list[Text] = [
        "i",
        blocks.header(t, "y_{p,i}", "um"),
        blocks.header(t, "y_{v,i}", "um"),
    ]
    return Table(caption=html_symbol(t("p.peaks")), header=head, rows=rows, labels=1)


def _levels_table(t: Messages, caption: Text, rows: list[list[Text]], count: int) -> Table:
    head: list[Text] = [t("col.level"), *(str(i) for i in range(1, count + 1))]
    return Table(caption=caption, header=head, rows=rows, labels=1)


def _table_1_6(t: Messages, v: ProfilometerResults) -> Table:
    units = units_of(ProfilometerResults)
    fields = (
        ("levels", "p_i"),
        ("bearing_lengths", "η_p"),
        ("tp", "t_p = η_p/l"),
        ("eps", "ε = p_i/R_max"),
    )
    rows: list[list[Text]] = []
    for name, symbol in fields:  # µm for the depths, as the manual's table 1.6
        head, cells = blocks.field(t, PROFILOMETER[name], symbol, units[name], getattr(v, name))
        rows.append([head, *cells])
    return _levels_table(t, html_symbol(t("p.table_1_6")), rows, len(v.tp))


def _table_1_7(t: Messages, fits: list[BearingFitResult]) -> Table:
    head: list[Text] = [
        t("col.method"),
        *(html_symbol(s) for s in ("ν_{1,3}", "ν_{2,5}", "ν_{3,6}", "ν", "b_1", "b_3", "b_5", "b")),
    ]
    rows: list[list[Text]] = []
    for fit in fits:
        nu = [fmt(n) for n in fit.nu_partial] or [DASH] * 3
        b = [fmt(n) for n in fit.b_partial] or [DASH] * 3
        rows.append([t("p.manual" if fit.method == "manual" else "p.lsq"), *nu, fmt(fit.nu)])
        rows[-1] += [*b, fmt(fit.b)]
    return Table(caption=html_symbol(t("p.table_1_7")), header=head, rows=rows, labels=1)


def _table_1_8(t: Messages, v: ProfilometerResults, fit: BearingFitResult) -> Table:
    residuals = np.asarray(fit.residuals)
    theory = np.asarray(v.tp) - residuals  # Δt_p = t_pэ - t_pт (table 1.8)
    rows: list[list[Text]] = [
        [html_symbol(t.symbol("t_{p,e}")), *(fmt(p) for p in v.tp)],
        [html_symbol(t.symbol("t_{p,t}") + " = b·ε^ν"), *(fmt(float(p)) for p in theory)],
        [
            html_symbol(f"Δt_p = {t.symbol('t_{p,e}')} - {t.symbol('t_{p,t}')}"),
            *(fmt(float(p)) for p in residuals),
        ],
    ]
    return _levels_table(t, html_symbol(t("p.table_1_8")), rows, len(v.tp))


def _bearing_svg(t: Messages, v: ProfilometerResults, fits: list[BearingFitResult]) -> str:
    fig, (ax,) = axes(height=3.0)
    eps = np.asarray(v.eps)
    ax.plot(eps, v.tp, "o", markersize=4, label=t("p.measured"))
    grid: NDArray[np.float64] = np.linspace(0.0, float(eps.max()) * 1.05, 200)
    for fit in fits:
        name = t("p.manual" if fit.method == "manual" else "p.lsq")
        ax.plot(
            grid,
            fit.b * grid**fit.nu,  # (1.8)
            "-" if fit.method == "manual" else "--",
            linewidth=1.0,
            label=f"t_p = {fmt(fit.b)}·ε^{{{fmt(fit.nu)}}}, {name}",
        )
    decorate(ax, xlabel=blocks.axis(t, "ε"), ylabel=blocks.axis(t, "t_p"))
    return to_svg(fig)


def _percent(reference: float, other: float) -> str:
    error = bearing_readings.relative_error_percent(reference=reference, other=other)
    return percent(float(error.percent))


def _conclusions(t: Messages, v: ProfilometerResults) -> list[Text]:
    found: list[Text] = []
    if v.fit_manual is not None and v.fit_lsq is not None:
        found.append(
            html_symbol(
                t(
                    "p.c_fit",
                    nu=fmt(v.fit_manual.nu),
                    b=fmt(v.fit_manual.b),
                    nu_lsq=fmt(v.fit_lsq.nu),
                    b_lsq=fmt(v.fit_lsq.b),
                    residual=fmt(max(abs(r) for r in v.fit_manual.residuals)),
                )
            )
        )
    if v.ra is not None and v.ra_from_complex is not None:
        found.append(
            html_symbol(
                t(
                    "p.c_ra",
                    ra=with_uncertainty(v.ra * 1e6, v.ra_expanded * 1e6)
                    if v.ra_expanded
                    else shown(PROFILOMETER["ra"], v.ra, "m"),
                    ra_delta=shown(PROFILOMETER["ra_from_complex"], v.ra_from_complex, "m"),
                    diff=_percent(v.ra, v.ra_from_complex),
                )
            )
        )
    if v.complex_parameter is not None and v.complex_parameter_equilibrium is not None:
        found.append(
            html_symbol(
                t(
                    "p.c_delta",
                    delta=fmt(v.complex_parameter),
                    delta_t=fmt(v.complex_parameter_equilibrium),
                    diff=_percent(v.complex_parameter_equilibrium, v.complex_parameter),
                )
            )
        )
    return found
