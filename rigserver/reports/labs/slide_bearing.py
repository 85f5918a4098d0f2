"""Lab work 3 (slide-bearing stand): tables 3.1-3.3 and Π against φ and z (3.28)-(3.29)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from markupsafe import Markup

from rigserver.reports import blocks
from rigserver.reports.context import Context, LabReport, sections
from rigserver.reports.document import Block, Figure, Paragraph, Table, Text
from rigserver.reports.formatting import fmt, html_symbol, percent, shown, with_uncertainty
from rigserver.reports.i18n import Messages
from rigserver.reports.plots import axes, decorate, to_svg
from schemas.labels import SLIDE_BEARING, row_labels
from schemas.quantity import units_of
from schemas.results import AxialPoint, SlideBearingResults, SlideBearingRow

GROUP = "rows"


def build(ctx: Context, v: SlideBearingResults) -> LabReport:
    t = ctx.t
    measured: list[Block] = [ctx.measurements()]
    if ctx.readings.rows(GROUP):
        measured.append(_table_3_1(ctx, v))
    measured.append(
        blocks.quantities(
            t,
            t("b.oil"),
            v,
            [
                ("load", "N", "b.load"),
                ("temperature", "t", "b.temperature"),
                ("viscosity", "μ_t", "b.viscosity"),
                ("mu_bar", "μ̄", "b.mu_bar"),
                ("chi_mean", "χ_mean", "b.chi_mean"),
                ("attitude_angle", "ψ", "b.attitude"),
                ("rupture_angle", "φ_r", "b.rupture"),
                ("half_width", "a", "b.half_width"),
                ("phi_max", "φ_pmax", "b.phi_max"),
                ("pressure_max", "p_max", "b.p_max"),
            ],
            labels=SLIDE_BEARING,
        )
    )
    processed: list[Block] = [Paragraph(t("b.models"))]
    if v.axial:
        processed.append(_table_3_2(t, v))
    if v.table:
        processed.append(_table_3_3(t, v.table))
        processed.append(Figure(html_symbol(t("b.fig_phi")), _angle_svg(t, v.table)))
    if v.axial:
        processed.append(Figure(html_symbol(t("b.fig_z")), _axial_svg(t, v)))
    spread = blocks.uncertainties(
        t, v, [("chi_mean", "χ_mean", "b.chi_mean")], labels=SLIDE_BEARING
    )
    if spread:
        processed.append(blocks.uncertainty_table(t, spread))
    return LabReport(
        sections=sections(t, measured, processed),
        conclusions=_conclusions(t, v),
    )


def _table_3_1(ctx: Context, v: SlideBearingResults) -> Table:
    """The limb rows as read (X, Y, t1, t2) beside their processing (3.16)-(3.20)."""
    t = ctx.t
    raw = ctx.readings.read(GROUP, ["limb_angle", "x", "y", "t1", "t2"])
    units = ctx.units(GROUP)
    n = raw["limb_angle"].size
    rows = v.table if len(v.table) == n else [None] * n

    def col(name: str) -> list[float | None]:
        return [getattr(r, name) if r is not None else None for r in rows]

    row_units = units_of(SlideBearingRow)

    def field(name: str, symbol: str) -> tuple[Markup, list[Text]]:
        return blocks.field(t, SLIDE_BEARING[f"table[].{name}"], symbol, row_units[name], col(name))

    processed = [
        field("e_x", "e_x"),
        field("e_y", "e_y"),
        field("e", "e"),
        field("chi", "χ"),
        field("phi_model", "φ_mod"),
    ]
    pressure = field("pressure", "p")
    data: list[Sequence[float | Text | None]] = [
        raw["limb_angle"].tolist(),
        pressure[1],
        raw["x"].tolist(),
        raw["y"].tolist(),
        raw["t1"].tolist(),
        raw["t2"].tolist(),
        *(cells for _, cells in processed),
    ]
    head = [
        blocks.header(t, "φ_limb", units["limb_angle"]),
        pressure[0],
        blocks.header(t, "X", units["x"]),
        blocks.header(t, "Y", units["y"]),
        blocks.header(t, "t_1", units["t1"]),
        blocks.header(t, "t_2", units["t2"]),
        *(h for h, _ in processed),
    ]
    table = blocks.columns(html_symbol(t("b.table_3_1")), head, data)
    mean: list[Text] = [t("mean"), "", "", "", fmt(float(np.mean(raw["t1"])))]
    chi_mean = shown(SLIDE_BEARING["chi_mean"], v.chi_mean, "1")
    mean += [fmt(float(np.mean(raw["t2"]))), "", "", "", chi_mean, ""]
    return Table(caption=table.caption, header=table.header, rows=[*table.rows, mean])


def _table_3_2(t: Messages, v: SlideBearingResults) -> Table:
    return blocks.result_table(
        t,
        html_symbol(t("b.table_3_2", phi=fmt(v.phi_max))),
        v.axial,
        [
            ("z", "z"),
            ("pressure", "p"),
            ("pi_measured", "Π_z"),
            ("pi_short", "Π_m"),
            ("pi_finite", f"Π, {t('b.finite')}"),
            ("error", "ΔΠ"),
        ],
        model=AxialPoint,
        labels=row_labels(SLIDE_BEARING, "axial[]."),
        note=html_symbol(t("b.edges", a=fmt(v.half_width))),
    )


def _by_angle(table: Sequence[SlideBearingRow]) -> list[SlideBearingRow]:
    return sorted(table, key=lambda r: r.phi_model)


def _table_3_3(t: Messages, table: Sequence[SlideBearingRow]) -> Table:
    return blocks.result_table(
        t,
        html_symbol(t("b.table_3_3")),
        _by_angle(table),
        [
            ("phi_model", "φ"),
            ("pi_short", "Π_0"),
            ("pi_long", "Π_∞"),
            ("pi_finite", f"Π, {t('b.finite')}"),
            ("pi_measured", "Π_e"),
            ("error_short", "ΔΠ_0"),
            ("error_long", "ΔΠ_∞"),
        ],
        model=SlideBearingRow,
        labels=row_labels(SLIDE_BEARING, "table[]."),
    )


def _curve(values: Sequence[float | None]) -> list[float]:
    return [np.nan if x is None else x for x in values]


def _angle_svg(t: Messages, table: Sequence[SlideBearingRow]) -> str:
    rows = _by_angle(table)
    phi = [r.phi_model for r in rows]
    fig, (ax,) = axes(height=3.2)
    ax.plot(phi, _curve([r.pi_short for r in rows]), "-", linewidth=1.2, label=t("b.short"))
    ax.plot(phi, _curve([r.pi_long for r in rows]), "--", linewidth=1.2, label=t("b.long"))
    if any(r.pi_finite is not None for r in rows):
        ax.plot(phi, _curve([r.pi_finite for r in rows]), "-.", linewidth=1.2, label=t("b.finite"))
    ax.plot(phi, [r.pi_measured for r in rows], "o", color="k", markersize=4, label=t("b.measured"))
    decorate(ax, xlabel=blocks.axis(t, "φ", "deg"), ylabel=blocks.axis(t, "Π"))
    return to_svg(fig)


def _axial_svg(t: Messages, v: SlideBearingResults) -> str:
    """Π along z at φ_max, with Π = 0 at the edges z = ±a (the boundary condition of (3.1))."""
    a = v.half_width
    points = v.axial
    z = [-a, *(p.z for p in points), a]

    def closed(values: Sequence[float | None]) -> list[float]:
        return [0.0, *_curve(values), 0.0]

    fig, (ax,) = axes(height=3.0)  # table 3.2's symbols: Π_z measured, Π_m the short bearing
    ax.plot(z, closed([p.pi_short for p in points]), "-", linewidth=1.2, label=t("b.short_z"))
    if any(p.pi_finite is not None for p in points):
        ax.plot(z, closed([p.pi_finite for p in points]), "-.", linewidth=1.2, label=t("b.finite"))
    measured = closed([p.pi_measured for p in points])
    ax.plot(z, measured, "o", color="k", markersize=4, label=t("b.measured_z"))
    decorate(ax, xlabel=blocks.axis(t, "z = Z/R"), ylabel=blocks.axis(t, "Π"))
    return to_svg(fig)


def _mean_abs(values: Sequence[float | None]) -> float | None:
    found = [abs(x) for x in values if x is not None]
    return float(np.mean(found)) if found else None


def _conclusions(t: Messages, v: SlideBearingResults) -> list[Text]:
    found: list[Text] = []
    if v.chi_mean is not None and v.pressure_max is not None:
        found.append(
            html_symbol(
                t(
                    "b.c_chi",
                    chi=with_uncertainty(v.chi_mean, v.chi_mean_expanded)
                    if v.chi_mean_expanded
                    else shown(SLIDE_BEARING["chi_mean"], v.chi_mean, "1"),
                    p=shown(SLIDE_BEARING["pressure_max"], v.pressure_max, "Pa"),
                    unit=t.unit(SLIDE_BEARING["pressure_max"].unit),
                    phi=fmt(v.phi_max),
                )
            )
        )
    short = _mean_abs([r.error_short for r in v.table])
    long = _mean_abs([r.error_long for r in v.table])
    if short is not None and long is not None:
        found.append(html_symbol(t("b.c_errors", short=percent(short), long=percent(long))))
    axial = _mean_abs([p.error for p in v.axial])
    if axial is not None:
        found.append(html_symbol(t("b.c_axial", phi=fmt(v.phi_max), error=percent(axial))))
    return found
