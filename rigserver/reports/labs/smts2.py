"""Lab work 2 (SMTs-2): the friction record, the wear intensity (2.1)-(2.13), adequacy (2.15)."""

from __future__ import annotations

import dataclasses

import numpy as np

from rigserver.analysis.streaming import BlockSeries
from rigserver.core import wear
from rigserver.reports import blocks
from rigserver.reports.context import Context, LabReport, sections
from rigserver.reports.document import Block, Figure, Table, Text
from rigserver.reports.formatting import (
    fmt,
    html_symbol,
    percent,
    tex,
    to_uncertainty,
    with_uncertainty,
)
from rigserver.reports.i18n import Messages
from rigserver.reports.labs import iso_profile
from rigserver.reports.labs.friction_record import friction_record_svg
from rigserver.reports.plots import axes, decorate, to_svg
from schemas.labels import SMTS2
from schemas.results import Smts2Results
from schemas.stands import MEASUREMENTS, Smts2Config
from schemas.units import UNITS

GROUP = "friction"
#: Blocks the friction record is reduced to for drawing (mean, min and max of each).
DRAWN_BLOCKS = 600


def _measured(ctx: Context, v: Smts2Results, config: Smts2Config) -> list[Block]:
    """The weighings and the friction record: its figures, M_fr beside f, its plot."""
    t = ctx.t
    balance = {  # the masses with the digits the balance gives (its resolution, declared)
        name: config.accuracy.balance_resolution / UNITS[unit].factor
        for name, unit in ctx.units(MEASUREMENTS).items()
        if UNITS[unit].si == "kg"
    }
    measured: list[Block] = [ctx.measurements(balance)]
    if v.rows:
        record = blocks.quantities(
            t,
            t("w.record"),
            v,
            [
                ("rows", "", "w.rows"),
                ("duration", "τ", "w.duration"),
                ("revolutions", "M_rev", "w.revolutions"),
                ("sliding_distance", "L", "w.sliding"),
                ("mean_load", "N", "w.load"),
                ("friction_steady", "f", "w.f"),
                ("friction_steady_std", "σ_f", "w.f_std"),
                ("steady_from_time", "t_s", "w.steady_from"),
            ],
            labels=SMTS2,
        )
        # the friction moment beside f: M_fr = f·N·r2, the inverse of (2.8)
        moment = None
        if v.friction_steady is not None and v.mean_load is not None:
            moment = v.friction_steady * v.mean_load * config.disc_radius
        row: list[Text] = [
            html_symbol(t("w.moment")),
            html_symbol(t.symbol("M_fr")),
            fmt(moment),
            t.unit("N*m"),
        ]
        at = next(i for i, r in enumerate(record.rows) if str(r[1]) == "f") + 1
        rows = [*record.rows[:at], row, *record.rows[at:]]
        measured.append(dataclasses.replace(record, rows=rows))
        measured.append(Figure(t("w.fig_friction"), _friction_svg(ctx, v, config)))
    return measured


def _wear_tables(t: Messages, v: Smts2Results) -> list[Block]:
    """The pin's wear from the weighings (2.9)-(2.13), the disc's from its track, and
    (2.1)'s figures: the contact, the pressures and areas (2.3)-(2.6), I_h,th."""
    processed: list[Block] = []
    if v.experimental is not None:
        processed.append(
            blocks.quantities(
                t,
                t("w.experimental"),
                v.experimental,
                [
                    ("mass_loss", "Δm", "w.mass_loss"),
                    ("volume", "V", "w.volume"),
                    ("wear_depth", "h", "w.depth"),
                    ("intensity", "I_{h,exp}", "w.intensity_exp"),
                    ("specific_wear_rate", "k", "w.k"),
                ],
                labels=SMTS2,
                prefix="experimental.",
            )
        )
    if v.disc_wear is not None:
        processed.append(
            blocks.quantities(
                t,
                t("w.disc_wear"),
                v.disc_wear,
                [
                    ("track_area", "A", "w.track_area"),
                    ("volume", "V_2", "w.disc_volume"),
                    ("specific_wear_rate", "k_2", "w.k_disc"),
                ],
                labels=SMTS2,
                prefix="disc_wear.",
            )
        )
        track_iso = iso_profile.track_table(t, v.disc_wear.iso, SMTS2, "disc_wear.iso.")
        if track_iso is not None:
            processed.append(track_iso)
    if v.theoretical is not None:
        theory = blocks.quantities(
            t,
            t("w.theoretical"),
            v.theoretical,
            [
                ("fatigue_t", "t", "w.fatigue_t"),
                ("contour_pressure", "p_c", "w.pc"),
                ("nominal_area", "A_a", "w.aa"),
                ("contour_area", "A_c", "w.ac"),
                ("eta_c", "η_c", "w.eta_c"),
                ("complex_parameter", "Δ", "w.delta"),
                ("rmax_over_r", "R_max/R", "w.rmax_r"),
                ("C", "C", "w.C"),
                ("beta", "β", "w.beta"),
                ("k_nu", "k_ν", "w.k_nu"),
                ("k_f", "k_f", "w.k_f"),
                ("intensity", "I_{h,th}", "w.intensity_theor"),
            ],
            labels=SMTS2,
            prefix="theoretical.",
        )
        contact: list[Text] = [t("w.contact"), "", t("contact." + v.theoretical.contact), ""]
        outside = v.validity is not None and not v.validity.within_range
        note = t("w.theory_note") if outside else ""
        processed.append(dataclasses.replace(theory, rows=[contact, *theory.rows], note=note))
    return processed


def build(ctx: Context, v: Smts2Results) -> LabReport:
    t = ctx.t
    config = Smts2Config.model_validate(ctx.run.configuration)
    measured = _measured(ctx, v, config)
    processed = _wear_tables(t, v)
    if v.validity is not None:
        processed.append(_validity(t, v))
    if v.sensitivity:
        processed.append(_sensitivity(t, v))
    if v.experimental and v.theoretical and v.experimental.intensity > 0:
        processed.append(_adequacy(t, v))
    if v.experimental is not None or v.theoretical is not None:
        svg, band = _wear_svg(t, v)
        caption = t("w.fig_wear_band" if band else "w.fig_wear")
        processed.append(Figure(html_symbol(caption), svg))
    spread = blocks.uncertainties(t, v, [("friction_steady", "f", "w.f")], labels=SMTS2)
    if v.experimental is not None:
        spread += blocks.uncertainties(
            t,
            v.experimental,
            [("intensity", "I_{h,exp}", "w.intensity_exp"), ("specific_wear_rate", "k", "w.k")],
            labels=SMTS2,
            prefix="experimental.",
        )
    if v.rows:
        processed.append(blocks.uncertainty_table(t, spread))
    return LabReport(
        sections=sections(t, measured, processed),
        conclusions=_conclusions(t, v),
    )


def _validity(t: Messages, v: Smts2Results) -> Table:
    assert v.validity is not None
    table = blocks.quantities(
        t,
        t("w.validity"),
        v.validity,
        [
            ("approach", "ε", "w.approach"),
            ("real_area_ratio", "η_r", "w.eta_r"),
            ("real_contact_pressure", "p_r", "w.pr"),
            ("hardness", "HB", "w.hb"),
            ("asperity_stress", "σ", "w.sigma"),
            ("fatigue_strength", "σ_0", "w.sigma0"),
            ("cycles_to_failure", "n", "w.cycles"),
            ("plastic_k_f", "k_f^n", "w.kf_plastic"),
        ],
        labels=SMTS2,
        prefix="validity.",
    )
    verdict: list[Text] = [
        t("w.within_range"),
        "",
        t("yes" if v.validity.within_range else "no"),
        "",
    ]
    return dataclasses.replace(table, rows=[*table.rows, verdict])


def _sensitivity(t: Messages, v: Smts2Results) -> Table:
    # the theory's intensity, as the theory table names it; dimensionless columns name
    # their symbol only, as every table's header does (blocks.header)
    head: list[Text] = [
        html_symbol("t"),
        html_symbol("σ_0/σ_B"),
        html_symbol(t.symbol("I_{h,th}")),
        html_symbol("n"),
    ]
    rows: list[list[Text]] = [
        [fmt(p.fatigue_t), fmt(p.strength_ratio), fmt(p.intensity), fmt(p.cycles_to_failure)]
        for p in v.sensitivity
    ]
    return Table(caption=t("w.sensitivity"), header=head, rows=rows, labels=2)


def _adequacy(t: Messages, v: Smts2Results) -> Table:
    assert v.experimental and v.theoretical
    # the comparison the manual asks for (item 18), judged only where the theory holds
    a = v.adequacy or wear.wear_adequacy(
        i_exp=v.experimental.intensity, i_theor=v.theoretical.intensity
    )
    verdict = t("yes" if a.adequate else "no") if v.adequacy else t("w.not_judged")
    one = t.unit("1")
    rows: list[list[Text]] = [
        [
            t("w.intensity_exp"),
            html_symbol(t.symbol("I_{h,exp}")),
            to_uncertainty(v.experimental.intensity, v.experimental.intensity_expanded),
            one,
        ],
        [
            t("w.intensity_theor"),
            html_symbol(t.symbol("I_{h,th}")),
            fmt(v.theoretical.intensity),
            one,
        ],
        [t("w.error"), html_symbol("ΔI_h"), percent(a.relative_error_percent), t.unit("%")],
        [t("w.lower"), "", fmt(a.lower), one],
        [t("w.upper"), "", fmt(a.upper), one],
        [t("w.adequate"), "", verdict, ""],
    ]
    head: list[Text] = [t("col.quantity"), t("col.symbol"), t("col.value"), t("col.unit")]
    return Table(
        caption=t("w.adequacy"),
        header=head,
        rows=[[html_symbol(str(r[0])), *r[1:]] for r in rows],
        labels=2,
    )


def _friction_svg(ctx: Context, v: Smts2Results, config: Smts2Config) -> str:
    """f (2.8) over the sliding distance L = 2π r2·M_rev (2.12), every row, drawn as block
    means with their min-max band; the part before the steady window is shaded."""
    t = ctx.t
    total = ctx.readings.rows(GROUP)
    units = ctx.units(GROUP)
    per_count = UNITS[units["revolutions"]].factor
    start = wear.steady_window_start(samples=total, fraction=config.steady_fraction)
    series = BlockSeries(total, blocks=DRAWN_BLOCKS)
    first: float | None = None
    steady_distance = 0.0
    seen = 0
    for chunk in ctx.readings.iter_chunks(GROUP, ["friction_moment", "load", "revolutions"]):
        f = wear.friction_coefficient(
            friction_moment=chunk["friction_moment"], load=chunk["load"], radius=config.disc_radius
        )
        counts = chunk["revolutions"]
        if first is None:
            first = float(counts[0])
        distance = wear.sliding_distance(
            disc_radius=config.disc_radius, revolutions=(counts - first) * per_count
        )
        series.add(distance, np.asarray(f, dtype=np.float64))
        if seen <= start < seen + counts.size:
            steady_distance = float(distance[start - seen])
        seen += counts.size
    share = percent(100.0 * (1.0 - config.steady_fraction))
    return friction_record_svg(
        t,
        series.series("sliding distance", "friction coefficient"),
        "f",
        running_in=steady_distance,
        running_in_label=t("w.running_in", share=share),
        steady_from=steady_distance,
        steady=v.friction_steady,
        steady_shown=to_uncertainty(v.friction_steady, v.friction_steady_expanded),
    )


def _wear_svg(t: Messages, v: Smts2Results) -> tuple[str, bool]:
    """I_h,exp (2.13) and I_h,th (2.1) on a log axis, each named under its point, with the
    band 0.4·I_h,th … 2.6·I_h,th (2.15) about the theory; and whether the theory is judged
    (the caption says so: a theory outside its range is drawn, its band paler, not judged)."""
    fig, (ax,) = axes(height=2.8)
    ax.set_yscale("log")
    judged = v.adequacy is not None and (v.validity is None or v.validity.within_range)
    if v.theoretical is not None:  # the band of (2.15) about the theory, judged or not
        lower = wear.ADEQUACY_LOWER * v.theoretical.intensity
        upper = wear.ADEQUACY_UPPER * v.theoretical.intensity
        ax.axhspan(lower, upper, color="C2", alpha=0.25 if judged else 0.12, label=t("w.band"))
    names: list[str] = []
    if v.experimental is not None:
        ax.plot([len(names)], [v.experimental.intensity], "o", color="C0", markersize=8)
        names.append(f"{t('w.exp')}\n{tex(t.symbol('I_{h,exp}'))} (2.13)")
    if v.theoretical is not None:
        ax.plot([len(names)], [v.theoretical.intensity], "s", color="C3", markersize=8)
        theory = f"{t('w.theor')}\n{tex(t.symbol('I_{h,th}'))}"
        if v.validity is not None and not v.validity.within_range:
            theory += f"\n{t('w.out_of_range')}"
        names.append(theory)
    ax.set_xticks(range(len(names)), names)
    ax.set_xlim(-0.6, len(names) - 0.4)
    decorate(ax, xlabel=t("w.source"), ylabel=blocks.axis(t, "I_h"))
    return to_svg(fig), judged


def _conclusions(t: Messages, v: Smts2Results) -> list[Text]:
    found: list[Text] = []
    if v.rows:
        found.append(
            html_symbol(
                t(
                    "w.c_friction_u",
                    f=with_uncertainty(v.friction_steady, v.friction_steady_expanded),
                    t=fmt(v.steady_from_time),
                    load=fmt(v.mean_load),
                )
            )
        )
    if v.validity is not None and not v.validity.within_range:
        reasons = "; ".join(t.gettext(r) for r in v.validity.reasons)
        found.append(html_symbol(t("w.c_outside", reasons=reasons)))
    if v.adequacy is not None and v.experimental and v.theoretical:
        key = "w.c_adequate" if v.adequacy.adequate else "w.c_inadequate"
        text = t(
            key,
            exp=to_uncertainty(v.experimental.intensity, v.experimental.intensity_expanded),
            theor=fmt(v.theoretical.intensity),
            lower=fmt(v.adequacy.lower),
            upper=fmt(v.adequacy.upper),
            error=percent(v.adequacy.relative_error_percent),
            contact=t("contact." + v.theoretical.contact),
        )
        found.append(html_symbol(text))
    return found
