"""A commercial tribometer's report (pin- or ball-on-disc, reciprocating): the friction
record with its running-in, the per-lap map or the strokes and friction loops, the wear
volumes and specific wear rates, the Hertz contact."""

from __future__ import annotations

import math

import numpy as np

from rigserver.reports import blocks
from rigserver.reports.context import Context, LabReport, sections
from rigserver.reports.document import Block, Figure, Text
from rigserver.reports.formatting import fmt, html_symbol, percent, to_uncertainty
from rigserver.reports.i18n import Messages
from rigserver.reports.labs import iso_profile
from rigserver.reports.labs.friction_record import friction_record_svg
from rigserver.reports.labs.tribometer_conditions import conditions_table, deviations
from rigserver.reports.plots import axes, decorate, to_svg
from schemas.labels import WEAR_SUBSCRIPTS, RowTable, row_labels
from schemas.results import PinOnDiscResults, ReciprocatingResults, TribometerStep, WearEstimate
from schemas.stands import (
    DECLARATIONS,
    PinOnDiscConfig,
    ReciprocatingConfig,
)
from schemas.units import UNITS

Results = PinOnDiscResults | ReciprocatingResults

#: The flat's captions on a reciprocating tribometer (ASTM G133 says "flat", not "disc").
FLAT = {"disc_track": "t.flat_track", "disc_mass": "t.flat_mass"}

#: The wear estimates in the report's order: (field, message key of its caption).
WEAR = (
    ("disc_track", "t.disc_track"),
    ("disc_mass", "t.disc_mass"),
    ("pin_scar", "t.pin_scar"),
    ("pin_mass", "t.pin_mass"),
)


def _measured(
    ctx: Context, v: Results, config: PinOnDiscConfig | ReciprocatingConfig
) -> list[Block]:
    """The weighings and the friction record: the conditions, its figures and plot, the
    steps, the lap map or the strokes and their loops."""
    t = ctx.t
    labels = DECLARATIONS[ctx.run.stand].labels
    balance = config.accuracy.balance_resolution
    masses = {
        f"{specimen}_mass_{when}": balance / UNITS["g"].factor
        for specimen in ("pin", "disc")
        for when in ("before", "after")
    }
    measured: list[Block] = [ctx.measurements(masses)]
    if v.rows:
        measured.append(conditions_table(t, ctx.run, config, v))
        flat = isinstance(v, ReciprocatingResults)
        fields = [
            ("rows", "", "w.rows"),
            ("duration", "t", "w.duration"),
            ("sliding_distance", "L", "t.distance"),
            ("laps", "n_c" if flat else "n_L", "t.cycles" if flat else "t.laps"),
            ("mean_load", "F", "t.load"),
            ("friction_mean", "μ̄", "t.mean"),
            ("friction_static", "μ_s", "t.static"),
            ("running_in_distance", "L_r", "t.running_in"),
            ("friction_steady", "μ", "t.steady"),
            ("friction_steady_std", "σ_μ", "w.f_std"),
        ]
        if isinstance(v, PinOnDiscResults) and v.lap_amplitude is not None:
            fields.append(("lap_amplitude", "Δμ_1", "t.lap_amplitude"))
        if isinstance(v, ReciprocatingResults) and v.friction_forward is not None:
            fields += [
                ("friction_forward", "μ_f", "t.forward"),
                ("friction_backward", "μ_b", "t.backward"),
            ]
        measured.append(blocks.quantities(t, t("t.record"), v, fields, labels=labels))
        measured.append(Figure(t("t.fig_friction"), _friction_svg(t, v)))
        if v.steps:
            measured += _steps(ctx, v)
        if isinstance(v, PinOnDiscResults) and v.friction_map is not None:
            measured.append(Figure(t("t.fig_map"), _map_svg(t, v)))
        if isinstance(v, ReciprocatingResults):
            if v.loops:
                measured.append(Figure(t("t.fig_loops"), _loops_svg(t, v)))
            if v.strokes:
                table = _table(ctx, "strokes")
                measured.append(
                    blocks.result_table(
                        t,
                        t.gettext(table.caption),
                        v.strokes,
                        [("cycle", "n"), ("forward", "μ_f"), ("backward", "μ_b")],
                        model=type(v.strokes[0]),
                        labels={k.removeprefix("strokes[]."): x for k, x in labels.items()},
                    )
                )
    return measured


def build(ctx: Context, v: Results) -> LabReport:
    t = ctx.t
    declared = DECLARATIONS[ctx.run.stand]
    labels = declared.labels
    config = declared.configuration.model_validate(ctx.run.configuration)
    assert isinstance(config, PinOnDiscConfig | ReciprocatingConfig)
    measured = _measured(ctx, v, config)
    processed: list[Block] = []
    if v.hertz is not None:
        processed.append(
            blocks.quantities(
                t,
                t("t.hertz"),
                v.hertz,
                [
                    ("modulus", "E*", "t.modulus"),
                    ("contact_radius", "a", "t.contact_radius"),
                    ("max_pressure", "p_0", "t.p0"),
                    ("mean_pressure", "p_m", "t.pm"),
                ],
                labels=labels,
                prefix="hertz.",
            )
        )
    spread = blocks.uncertainties(t, v, [("friction_steady", "μ", "t.steady")], labels=labels)
    for name, key in _wear(v):
        estimate: WearEstimate | None = getattr(v, name)
        if estimate is None:
            continue
        fields = [(f, s, k) for f, s, k in _wear_fields(name) if getattr(estimate, f) is not None]
        processed.append(
            blocks.quantities(t, t(key), estimate, fields, labels=labels, prefix=f"{name}.")
        )
        spread += blocks.uncertainties(
            t,
            estimate,
            [("specific_wear_rate", f"k_{{{WEAR_SUBSCRIPTS[name]}}}", f"t.k.{name}")],
            labels=labels,
            prefix=f"{name}.",
        )
    if v.disc_track is not None:
        track_iso = iso_profile.track_table(t, v.disc_track.iso, labels, "disc_track.iso.")
        if track_iso is not None:
            processed.append(track_iso)
    if v.rows:
        processed.append(blocks.uncertainty_table(t, spread))
    return LabReport(
        sections=sections(t, measured, processed),
        conclusions=_conclusions(t, v)
        + ([html_symbol(line) for line in deviations(t, config, v)] if v.rows else []),
    )


def _wear(v: Results) -> list[tuple[str, str]]:
    """The wear estimates and their captions, the flat's on a reciprocating tribometer."""
    if isinstance(v, ReciprocatingResults):
        return [(name, FLAT.get(name, key)) for name, key in WEAR]
    return list(WEAR)


def _table(ctx: Context, name: str) -> RowTable:
    return next(table for table in DECLARATIONS[ctx.run.stand].tables if table.name == name)


def _steps(ctx: Context, v: Results) -> list[Block]:
    """The recipe's steps: their table and μ against the sliding speed (a Stribeck curve)."""
    t = ctx.t
    labels = row_labels(DECLARATIONS[ctx.run.stand].labels, "steps[].")
    table = blocks.result_table(
        t,
        t.gettext(_table(ctx, "steps").caption),
        v.steps,
        [
            ("step", "i"),
            ("sliding_speed", "v"),
            ("track_radius", "R"),
            ("normal_load", "F"),
            ("duration", "t"),
            ("distance", "L"),
            ("friction_mean", "μ̄"),
            ("friction_steady", "μ"),
        ],
        model=TribometerStep,
        labels=labels,
    )
    found: list[Block] = [table]
    if any(step.sliding_speed is not None for step in v.steps):
        found.append(Figure(t("t.fig_stribeck"), stribeck_svg(t, v)))
    return found


def stribeck_svg(t: Messages, v: Results) -> str:
    """μ of each step against its sliding speed (a Stribeck curve): the steady μ where the
    step settled, the step's mean beside it."""
    known = [s for s in v.steps if s.sliding_speed is not None]
    fig, (ax,) = axes(height=3.0)
    speed = [s.sliding_speed or 0.0 for s in known]
    ax.plot(speed, [s.friction_mean for s in known], "o--", color="C0", label=t("t.step_mean"))
    steady = [(s.sliding_speed, s.friction_steady) for s in known if s.friction_steady is not None]
    if steady:
        x, y = zip(*steady, strict=True)
        ax.plot(x, y, "s-", color="C3", label=t("t.step_steady"))
    decorate(ax, xlabel=blocks.axis(t, "v", "m/s"), ylabel=blocks.axis(t, "μ"))
    return to_svg(fig)


def _wear_fields(name: str) -> list[tuple[str, str, str]]:
    sub = WEAR_SUBSCRIPTS[name]
    first = {
        "disc_track": [("traces", "n_p", "t.traces"), ("track_area", "A", "w.track_area")],
        "disc_mass": [("mass_loss", "Δm", "t.mass_loss"), ("density", "ρ", "t.density")],
        "pin_scar": [("scar_diameter", "d", "t.scar"), ("height_loss", "Δh", "t.height_loss")],
        "pin_mass": [("mass_loss", "Δm", "t.mass_loss"), ("density", "ρ", "t.density")],
    }[name]
    return [
        *first,
        ("volume", f"V_{{{sub}}}", f"t.v.{name}"),
        ("specific_wear_rate", f"k_{{{sub}}}", f"t.k.{name}"),
    ]


def _friction_svg(t: Messages, v: Results) -> str:
    """μ against the sliding distance (block means and their min-max band), the running-in
    shaded, the steady mean drawn over the steady part."""
    return friction_record_svg(
        t,
        v.friction,
        "μ",
        running_in=v.running_in_distance or None,
        running_in_label=t("t.running_in_band"),
        steady_from=v.running_in_distance,
        steady=v.friction_steady,
        steady_shown=_mu(v),
    )


def _map_svg(t: Messages, v: PinOnDiscResults) -> str:
    """μ over the angular position on the disc, a line per row of laps of the map: the
    first, two between and the last (the running-in's and the steady state's tracks)."""
    assert v.friction_map is not None
    m = v.friction_map
    fig, (ax,) = axes(height=3.0)
    rows = len(m.lap)
    step = m.lap[1] - m.lap[0] if rows > 1 else 1.0
    for i in sorted({0, rows // 3, (2 * rows) // 3, rows - 1}):
        values = np.array([np.nan if c is None else c for c in m.values[i]], dtype=float)
        first = m.lap[i] - step / 2
        ax.plot(
            m.angle,
            values,
            linewidth=0.9,
            label=t("t.laps_range", first=fmt(first), last=fmt(first + step)),
        )
    decorate(
        ax,
        xlabel=blocks.axis(t, "θ", "deg"),
        ylabel=blocks.axis(t, "μ"),
        legend_outside=True,
    )
    return to_svg(fig)


def _loops_svg(t: Messages, v: ReciprocatingResults) -> str:
    """μ (signed by the sliding direction) against the position: the first, a middle and
    the last cycle."""
    fig, (ax,) = axes(height=3.0)
    for loop in v.loops:
        ax.plot(
            np.asarray(loop.position) * 1e3,
            loop.friction,
            linewidth=0.9,
            label=t("t.loop", cycle=loop.cycle + 1),
        )
    decorate(ax, xlabel=blocks.axis(t, "x_s", "mm"), ylabel=blocks.axis(t, "μ"))
    return to_svg(fig)


def _conclusions(t: Messages, v: Results) -> list[Text]:
    found: list[Text] = []
    if v.rows and v.friction_steady is None:
        found.append(
            html_symbol(
                t("t.c_unsettled", static=fmt(v.friction_static), mean=fmt(v.friction_mean))
            )
        )
    elif v.rows:
        found.append(
            html_symbol(
                t(
                    "t.c_friction",
                    mu=_mu(v),
                    std=fmt(v.friction_steady_std),
                    distance=fmt(v.running_in_distance),
                    static=fmt(v.friction_static),
                    mean=fmt(v.friction_mean),
                )
            )
        )
    for name, key in _wear(v):
        below: float | None = getattr(v, f"{name}_below", None)
        if below is not None:
            milligrams = below / UNITS["mg"].factor
            found.append(html_symbol(t("t.c_below", what=t(key), resolution=fmt(milligrams))))
        estimate: WearEstimate | None = getattr(v, name)
        if estimate is not None:
            rate = estimate.specific_wear_rate / 1e-9  # mm³/(N·m)
            # below zero the specimen gained mass (or volume): said, never a bare negative wear
            said = "t.c_gain" if rate < 0 else "t.c_wear"
            found.append(html_symbol(t(said, what=t(key), k=_k(estimate))))
    for by_mass, by_shape in (("disc_mass", "disc_track"), ("pin_mass", "pin_scar")):
        verdict = _disagreement(t, getattr(v, by_mass), getattr(v, by_shape), by_shape)
        if verdict is not None:
            found.append(html_symbol(verdict))
    return found


def _disagreement(
    t: Messages, mass: WearEstimate | None, shape: WearEstimate | None, name: str
) -> str | None:
    """Which k to trust when the one by mass and the one by the specimen's shape (the scar,
    the track's profiles) differ beyond U = 2·√(u₁² + u₂²) (GUM, k = 2): the one of the
    smaller relative uncertainty, with why the other may be off."""
    if mass is None or shape is None:
        return None
    u_mass, u_shape = mass.specific_wear_rate_uncertainty, shape.specific_wear_rate_uncertainty
    k_mass, k_shape = mass.specific_wear_rate, shape.specific_wear_rate
    if u_mass is None or u_shape is None or k_mass <= 0 or k_shape <= 0:
        return None
    if abs(k_mass - k_shape) <= 2.0 * math.hypot(u_mass, u_shape):
        return None
    trust_mass = u_mass / k_mass < u_shape / k_shape
    return t(
        "t.c_trust_mass" if trust_mass else "t.c_trust_shape",
        specimen=t("t.specimen_disc" if name == "disc_track" else "t.specimen_pin"),
        shape=t(f"t.by.{name}"),
        k_mass=_k(mass),
        k_shape=_k(shape),
        ratio=fmt(max(k_mass, k_shape) / min(k_mass, k_shape), 2),
        relative=percent(100.0 * min(u_mass / k_mass, u_shape / k_shape)),
    )


def _mu(v: Results) -> str:
    """The steady friction coefficient to the place of its uncertainty (GUM 7.2.6)."""
    return to_uncertainty(v.friction_steady, v.friction_steady_expanded)


def _k(estimate: WearEstimate) -> str:
    """A specific wear rate in mm³/(N·m) to the place of its uncertainty (GUM 7.2.6)."""
    u = estimate.specific_wear_rate_expanded or estimate.specific_wear_rate_uncertainty
    return to_uncertainty(estimate.specific_wear_rate / 1e-9, None if u is None else u / 1e-9)
