"""Lab work 4 (MTOS): tables 4.1-4.6 and the four plots of "Illustration of the results"."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from markupsafe import Markup
from matplotlib.axes import Axes
from numpy.typing import NDArray
from scipy.interpolate import make_interp_spline

from rigserver.reports import blocks
from rigserver.reports.context import Context, LabReport, sections
from rigserver.reports.document import Block, Figure, Paragraph, Table, Text
from rigserver.reports.formatting import fmt, html_symbol, percent, shown, tex
from rigserver.reports.i18n import Messages
from rigserver.reports.plots import axes, decorate, to_svg
from schemas.labels import MTOS, Label, row_labels
from schemas.quantity import units_of
from schemas.results import MtosResults, MtosStep
from schemas.stands import MtosConfig
from schemas.units import UNITS

GROUP = "steps"
REGIMES = ("fluid", "mixed", "boundary")
"""The three experiments in the manual's order: 1 fluid film, 2 mixed, 3 boundary."""
MARKERS = {"fluid": "o", "mixed": "s", "boundary": "^"}
RISES = ("t2", "t3", "t4", "t5")
VISCOSITIES = ("t1", *RISES)
"""μ1…μ5 of table 4.4 (4.17), by the thermocouple each is read at."""


def build(ctx: Context, v: MtosResults) -> LabReport:
    t = ctx.t
    config = MtosConfig.model_validate(ctx.run.configuration)
    measured: list[Block] = [ctx.measurements()]
    if ctx.readings.rows(GROUP):
        measured.extend(_raw_tables(ctx))
    measured.append(
        blocks.quantities(
            t,
            t("m.film"),
            v,
            [
                ("h_crit", "h_{min,cr}", "m.h_crit"),
                ("h_min_smallest", "h_min", "m.h_min_smallest"),
                ("friction_fluid", "f̄_e", "m.friction_fluid"),
                ("half_width", "a", "m.half_width"),
            ],
            labels=MTOS,
        )
    )
    processed: list[Block] = [Paragraph(t("m.processing_formulas"))]
    if any(s.friction_theory is not None for s in v.steps):
        processed.append(Paragraph(t("m.theory_formulas")))
    for number, regime in enumerate(REGIMES, start=1):
        steps = _of(v.steps, regime)
        if steps:
            processed.extend(_processed_tables(t, number, regime, steps, v.steps))
    spread = [
        row
        for i, s in enumerate(v.steps)
        for row in blocks.uncertainties(
            t,
            s,
            [
                ("chi", f"χ_{{{i + 1}}}", "m.chi"),
                ("friction_measured", f"f_{{e,{i + 1}}}", "m.f_measured"),
            ],
            label=t("u.step", i=i + 1, load=fmt(s.load)),
            labels=MTOS,
            prefix="steps[].",
        )
    ]
    if spread:
        processed.append(blocks.uncertainty_table(t, spread))
    if v.steps:
        processed += [
            Figure(html_symbol(t("m.fig_stribeck")), _stribeck_svg(t, v, config)),
            Figure(t("m.fig_trajectory"), _trajectory_svg(t, v, config)),
            Figure(t("m.fig_friction"), _friction_svg(t, v)),
            Figure(t("m.fig_temperature"), _temperature_svg(t, v)),
        ]
    return LabReport(
        sections=sections(t, measured, processed),
        conclusions=_conclusions(t, v),
    )


def _of(steps: Sequence[MtosStep], regime: str) -> list[MtosStep]:
    return [s for s in steps if s.regime == regime]


def _raw_tables(ctx: Context) -> list[Table]:
    """Tables 4.1-4.3: the readings of each experiment as posted."""
    t = ctx.t
    raw = ctx.readings.read(GROUP)
    units = ctx.units(GROUP)
    names = ("load", "indicator", "x", "y", "t1", "t2", "t3", "t4", "t5")
    symbols = ("N", "Δl", "X", "Y", "t_1", "t_2", "t_3", "t_4", "t_5")
    head = [blocks.header(t, s, units[n]) for s, n in zip(symbols, names, strict=True)]
    tables = []
    for number, regime in enumerate(REGIMES, start=1):
        rows = raw["regime"] == number
        if rows.any():
            tables.append(
                blocks.columns(
                    t("m.raw", n=number, regime=t("regime." + regime)),
                    head,
                    [raw[n][rows].tolist() for n in names],
                )
            )
    return tables


def _eccentricity_part(
    t: Messages, caption: str, steps: list[MtosStep], angle: str, labels: dict[str, Label]
) -> Table:
    """Table 4.4's first part: each step's eccentricity (4.6)-(4.9) and the friction
    measured (4.10)-(4.11)."""
    first = blocks.result_table(
        t,
        caption,
        steps,
        [
            ("load", "N"),
            ("e_x", "e_x"),
            ("e_y", "e_y"),
            ("e", "e"),
            ("chi", "χ"),
            ("angle", angle),
            ("spring_force", "F"),
            ("friction_moment", "M_fr"),
            ("friction_force", "F_fr"),
            ("friction_measured", "f_e"),
        ],
        model=MtosStep,
        labels=labels,
    )
    return first


def _processed_tables(
    t: Messages, experiment: int, regime: str, steps: list[MtosStep], every: list[MtosStep]
) -> list[Table]:
    """Table 4.4 (fluid film, in three parts as the manual prints it), 4.5 and 4.6."""
    u = units_of(MtosStep)
    regime_name = t("regime." + regime)
    caption = t("m.processed", table=experiment + 3, n=experiment, regime=regime_name)
    angle = "δ" if regime == "fluid" else "γ"

    labels = row_labels(MTOS, "steps[].")

    def field(name: str, symbol: str) -> tuple[Markup, list[Text]]:
        return blocks.field(t, labels[name], symbol, u[name], [getattr(s, name) for s in steps])

    first = _eccentricity_part(t, caption, steps, angle, labels)
    rises = RISES if regime == "fluid" else RISES[1:]
    rise = MTOS["steps[].temperature_rise"]
    at = MTOS["steps[].viscosity_at"]
    thermocouples = [k for k in VISCOSITIES if any(k in s.viscosity_at for s in steps)]
    fields = [
        field("load", "N"),
        *(
            blocks.field(
                t, at, f"μ_{k[1]}", u["viscosity_at"], [s.viscosity_at.get(k) for s in steps]
            )
            for k in thermocouples
        ),
        field("viscosity", "μ_t"),
        field("bearing_characteristic", "S_1"),
        field("bearing_characteristic_inverse", "S_1^{-1}"),
        *(
            blocks.field(
                t,
                rise,
                f"Δt_{k[1]}",
                u["temperature_rise"],
                [s.temperature_rise.get(k) for s in steps],
            )
            for k in rises
        ),
        field("h_min", "h_min"),
        field("film_parameter", "Λ"),
    ]
    head: list[Text] = [
        *(h for h, _ in fields),
        html_symbol(t("col.film")),
        html_symbol(t("col.film_lambda")),
    ]
    data: list[Sequence[float | Text | None]] = [c for _, c in fields]
    data.append([t("regime." + s.film) for s in steps])
    data.append([t("regime." + s.film_lambda) for s in steps])
    note: Text = ""
    if regime != "fluid":
        fluid = {s.load: s.friction_measured for s in _of(every, "fluid")}
        head.append(html_symbol(t.symbol("f_e/f_e1")))
        data.append(
            [s.friction_measured / fluid[s.load] if s.load in fluid else None for s in steps]
        )
        note = html_symbol(t("m.ratio_note"))
    second = blocks.columns(caption, head, data, note=note)
    if regime != "fluid":
        return _parts_of(caption, first, second)
    return _parts_of(caption, first, second, _theory_part(t, steps, labels))


def _theory_part(t: Messages, steps: list[MtosStep], labels: dict[str, Label]) -> Table:
    """Table 4.4's third part: the fluid film's theory, f_T against f_e and the finite
    bearing's f and N."""
    finite = t("m.f_finite")
    third = blocks.result_table(
        t,
        html_symbol(t("m.theory")),
        steps,
        [
            ("load", "N"),
            ("viscosity_ratio", "μ_t/μ_0"),
            ("a1_00", "A_1^{00}"),
            ("a2_00", "A_2^{00}"),
            ("a3_00", "A_3^{00}"),
            ("a3_02", "A_3^{02}"),
            ("a3_20", "A_3^{20}"),
            ("a3_11", "A_3^{11}"),
            ("v_factor", "V"),
            ("tangential_force", "P_τ"),
            ("friction_measured", "f_e"),
            ("friction_theory", "f_T"),
            ("friction_error", "Δf"),
            ("friction_finite", f"f, {finite}"),
            ("load_finite", f"N, {finite}"),
        ],
        model=MtosStep,
        labels=labels,
    )
    return third


def _parts_of(caption: str, *tables: Table) -> list[Table]:
    """The pieces of one printed table (the manual's 4.4-4.6): their captions numbered as
    its parts when the report is laid out (:func:`rigserver.reports.layout.numbered`)."""
    return [dataclasses.replace(table, part_of=caption) for table in tables]


def _plot_measured(ax: Axes, t: Messages, v: MtosResults, x: str, line: str = "") -> None:
    """f_э of every step against its field ``x``, one series per experiment (regime)."""
    for regime in REGIMES:
        steps = _of(v.steps, regime)
        if steps:
            ax.plot(
                [getattr(s, x) for s in steps],
                [s.friction_measured for s in steps],
                MARKERS[regime] + line,
                label=t("m.f_exp", regime=t("regime." + regime)),
            )


def _stribeck_svg(t: Messages, v: MtosResults, config: MtosConfig) -> str:
    """f_э of every step and f_T of the fluid steps against S1⁻¹ = p̄/(μ_t·ω) (4.21, E9), as
    the manual's Hersey-Stribeck diagram (fig. 4.1) plots it: the boundary regime on the
    left, the fluid film on the right; the step of the largest eccentricity in experiment 1
    marked (h_min = h0 - e_max). Both axes span whole decades, each labelled, every point
    inside the frame."""
    fig, (ax,) = axes(height=3.4)
    _plot_measured(ax, t, v, "bearing_characteristic_inverse")
    fluid = sorted(
        (s for s in _of(v.steps, "fluid") if s.bearing_characteristic_inverse is not None),
        key=lambda s: s.bearing_characteristic_inverse or 0.0,
    )
    theory = [
        (s.bearing_characteristic_inverse, s.friction_theory) for s in fluid if s.friction_theory
    ]
    if theory:
        ax.plot(*zip(*theory, strict=True), "-", color="C3", label=t("m.f_theory"))
    if fluid:
        worst = max(fluid, key=lambda s: s.e)
        ax.annotate(
            tex(t("m.h_min_mark", h=shown(MTOS["steps[].h_min"], config.clearance - worst.e, "m"))),
            xy=(worst.bearing_characteristic_inverse, worst.friction_measured),
            xytext=(0.55, 0.9),  # above the fluid film's points, below the boundary's level
            textcoords="axes fraction",
            fontsize=8,
            arrowprops={"arrowstyle": "->", "linewidth": 0.8},
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    xs = [x for s in v.steps if (x := s.bearing_characteristic_inverse) is not None]
    fs = [f for s in v.steps for f in (s.friction_measured, s.friction_theory) if f]
    ax.set_xlim(*decades(xs))
    ax.set_ylim(*decades(fs))
    decorate(
        ax,
        xlabel=blocks.axis(t, "S_1^{-1} = p̄/(μ_t·ω)"),
        ylabel=blocks.axis(t, "f"),
        legend_outside=True,
    )
    return to_svg(fig)


def decades(values: Sequence[float]) -> tuple[float, float]:
    """Limits of a log axis: the whole decades around ``values`` with a margin of a fifth of
    a decade, so that every point lies inside the frame and at least two decades are
    labelled."""
    logs = np.log10([x for x in values if x > 0])
    low = math.floor(float(logs.min()) - 0.2)
    high = max(math.ceil(float(logs.max()) + 0.2), low + 1)
    return 10.0**low, 10.0**high


def _trajectory_svg(t: Messages, v: MtosResults, config: MtosConfig) -> str:
    """The journal centre (e_x, e_y) of every step (4.11) inside the clearance circle, with
    the Gümbel semicircle: the diameter from the bearing centre to the point h0 along the
    load line (e_x = e_y, δ = 0 in (4.12)), on the side the fluid-film steps lie."""
    shown_in = MTOS["steps[].e_x"].unit  # µm, the manual's
    scale = 1.0 / UNITS[shown_in].factor
    h0 = config.clearance * scale
    fig, (ax,) = axes(height=4.2)
    along = np.array([1.0, 1.0]) / np.sqrt(2.0)
    across = np.array([-1.0, 1.0]) / np.sqrt(2.0)
    fluid = _of(v.steps, "fluid")
    side = 1.0 if not fluid or np.mean([s.e_y - s.e_x for s in fluid]) >= 0 else -1.0
    theta = np.linspace(0.0, np.pi, 181)
    arc = (h0 / 2.0) * (
        np.outer(1.0 - np.cos(theta), along) + side * np.outer(np.sin(theta), across)
    )
    ax.plot(arc[:, 0], arc[:, 1], "-", color="C3", linewidth=1.0, label=t("m.gumbel"))
    circle = np.linspace(0.0, 2.0 * np.pi, 361)
    ax.plot(h0 * np.cos(circle), h0 * np.sin(circle), ":", color="0.4", label=t("m.clearance"))
    ax.plot([0.0, h0 * along[0]], [0.0, h0 * along[1]], "--", color="0.6", linewidth=0.8)
    for number, regime in enumerate(REGIMES):
        steps = sorted(_of(v.steps, regime), key=lambda s: s.load)
        if steps:
            x = np.array([s.e_x * scale for s in steps])
            y = np.array([s.e_y * scale for s in steps])
            ax.plot(x, y, MARKERS[regime], color=f"C{number}", markersize=5)
            ax.plot(
                *_smooth(x, y), "-", color=f"C{number}", linewidth=0.8, label=t("regime." + regime)
            )
            for s in _labelled(steps, 0.12 * config.clearance) if regime == "fluid" else ():
                ax.annotate(
                    fmt(s.load),
                    (s.e_x * scale, s.e_y * scale),
                    fontsize=6,
                    xytext=(4, -2),
                    textcoords="offset points",
                )
    ax.set_aspect("equal")
    decorate(
        ax,
        xlabel=blocks.axis(t, "e_x", shown_in),
        ylabel=blocks.axis(t, "e_y", shown_in),
        legend_outside=True,
    )
    return to_svg(fig)


def _labelled(steps: Sequence[MtosStep], gap: float) -> list[MtosStep]:
    """The steps (in load order) whose load is written beside the point: the lightest, the
    heaviest, and between them each at least ``gap`` (m) from the last one written, so that
    no two labels overlap where the journal centre hardly moves."""
    chosen: list[MtosStep] = []
    for step in steps:
        if not chosen or math.hypot(step.e_x - chosen[-1].e_x, step.e_y - chosen[-1].e_y) >= gap:
            chosen.append(step)
    last = steps[-1] if steps else None
    if last is not None and chosen[-1] is not last:
        if len(chosen) > 1:
            chosen.pop()  # the heaviest load is written, the one too close before it is not
        chosen.append(last)
    return chosen


def _smooth(x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """The measured points in load order joined by a smooth curve, as the manual asks of the
    trajectory: a parametric spline (cubic, or of the points' count less one) through every
    point, parametrised by the chord length; the points themselves where fewer than three."""
    if x.size < 3:
        return x, y
    chord = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])
    if not np.all(np.diff(chord) > 0):
        return x, y
    spline = make_interp_spline(chord, np.column_stack([x, y]), k=min(3, x.size - 1))
    drawn = spline(np.linspace(0.0, chord[-1], 200))
    return drawn[:, 0], drawn[:, 1]


def _friction_svg(t: Messages, v: MtosResults) -> str:
    fig, (ax,) = axes(height=3.2)
    _plot_measured(ax, t, v, "load", "-")
    theory = [(s.load, s.friction_theory) for s in _of(v.steps, "fluid") if s.friction_theory]
    if theory:
        ax.plot(*zip(*theory, strict=True), "--", color="C3", label=t("m.f_theory"))
    ax.set_yscale("log")
    u = units_of(MtosStep)
    decorate(
        ax, xlabel=blocks.axis(t, "N", u["load"]), ylabel=blocks.axis(t, "f"), legend_outside=True
    )
    return to_svg(fig)


def _temperature_svg(t: Messages, v: MtosResults) -> str:
    """Δt2…Δt5 (4.19, E4) against the load, a panel per regime."""
    present = [r for r in REGIMES if _of(v.steps, r)]
    fig, found = axes(height=2.8, columns=len(present))
    # the fluid film warms the oil a few degrees, the others tens: a scale of its own, the
    # mixed and the boundary regimes on one
    thin = [ax for ax, regime in zip(found, present, strict=True) if regime != "fluid"]
    for ax in thin[1:]:
        ax.sharey(thin[0])
    u = units_of(MtosStep)
    for ax, regime in zip(found, present, strict=True):
        steps = _of(v.steps, regime)
        for k in RISES:
            ax.plot(
                [s.load for s in steps],
                [s.temperature_rise.get(k, np.nan) for s in steps],
                "o-",
                markersize=3,
                label=f"Δt_{k[1]}",
            )
        decorate(
            ax,
            xlabel=blocks.axis(t, "N", u["load"]),
            ylabel=blocks.axis(t, "Δt", u["temperature_rise"])
            if ax is found[0] or thin[:1] == [ax]
            else "",
            title=t("regime." + regime),
        )
    return to_svg(fig)


def _conclusions(t: Messages, v: MtosResults) -> list[Text]:
    found: list[Text] = []
    fluid = _of(v.steps, "fluid")
    errors = [abs(s.friction_error) for s in fluid if s.friction_error is not None]
    if fluid and errors:
        f = [s.friction_measured for s in fluid]
        found.append(
            html_symbol(
                t(
                    "m.c_friction",
                    f_min=fmt(min(f)),
                    f_max=fmt(max(f)),
                    error=percent(float(np.mean(errors))),
                )
            )
        )
    for regime in REGIMES[1:]:
        steps = _of(v.steps, regime)
        if steps:
            f = [s.friction_measured for s in steps]
            found.append(
                html_symbol(
                    t(
                        "m.c_regime",
                        regime=t("regime." + regime).capitalize(),
                        f_min=fmt(min(f)),
                        f_max=fmt(max(f)),
                    )
                )
            )
    if v.steps:
        thin = sum(s.film != "fluid" for s in v.steps)
        found.append(
            html_symbol(
                t(
                    "m.c_film",
                    h_crit=shown(MTOS["h_crit"], v.h_crit, "m"),
                    count=thin,
                    total=len(v.steps),
                )
            )
        )
    if v.regime_disagreements:
        found.append(html_symbol(t("m.disagree", items="; ".join(v.regime_disagreements))))
    return found
