"""A tribometer report's test conditions as ASTM G99-17 and G133-05 ask them to be reported
(their "Report" clause): each planned value beside the one measured (load, sliding speed,
rotational speed or frequency, distance, laps or cycles, temperature, humidity), and the
deviations from the standard's parameters: G133's procedures A and B fix theirs; G99-17
(1.2, 1.3, 4.2) has the parameters of its interlaboratory study (its tables 1 and 2) and
asks a test with other parameters to say so, its results then not comparable with that
study's."""

from __future__ import annotations

import math
from dataclasses import dataclass

from rigserver.reports.document import Table
from rigserver.reports.formatting import fmt, html_symbol
from rigserver.reports.i18n import Messages
from schemas.digits import count
from schemas.results import PinOnDiscResults, ReciprocatingResults
from schemas.runs import Run
from schemas.stands import PinOnDiscConfig, ReciprocatingConfig


@dataclass(frozen=True, slots=True)
class Procedure:
    """The fixed parameters of a standard's procedure (SI; temperature in °C, ``None``:
    room temperature)."""

    name: str
    load: float
    stroke_length: float
    frequency: float
    distance: float
    temperature: float | None
    lubricated: bool
    ball_diameter: float = 9.525e-3  # a 3/8 in ball


#: ASTM G133 (-95, -05 (2016), -22), Procedures A and B. What stored public copies confirm
#: (the standard's scope 1.1 and 5.1, on astm.org's page of G133-22 and on the iTeh and BSI
#: catalogue pages of G133-95, -05 (2016) and -22): the test "encompasses both unlubricated
#: and lubricated testing procedures", "either of two sets of testing conditions (designated
#: Procedures A and B) may be used", and the parameters reported "should conform with either
#: Procedure A or B". The numbers below could NOT be confirmed from a stored copy of the
#: standard's text (only its first pages are stored): they are the values commonly quoted
#: for it, A unlubricated at room temperature, 25 N, 10 mm stroke, 5 Hz, 100 m (1000 s);
#: B lubricated at 150 °C, 200 N, 10 mm, 10 Hz, 400 m (2000 s), both with a 9.525 mm ball.
#: They are at least consistent: L = 2·S·f·t (100 m = 2 · 10 mm · 5 Hz · 1000 s; 400 m =
#: 2 · 10 mm · 10 Hz · 2000 s). Which lubricant B names is not stated here (an earlier note
#: said diesel fuel; unconfirmed): any lubricant is taken as B's.
G133 = (
    Procedure("A", 25.0, 10e-3, 5.0, 100.0, None, False),
    Procedure("B", 200.0, 10e-3, 10.0, 400.0, 150.0, True),
)
#: A measured value departs from the planned or the standard's one beyond this share.
TOLERANCE = 0.05

Config = PinOnDiscConfig | ReciprocatingConfig
Results = PinOnDiscResults | ReciprocatingResults


def conditions_table(t: Messages, run: Run, config: Config, v: Results) -> Table:
    """Planned against measured; a planned value nobody gave is printed as the stand's
    default, a measured one the record does not hold as "not recorded"."""
    plan = config.plan
    speed = v.sliding_distance / v.duration if v.duration > 0 else None
    rows: list[tuple[str, str, str | None, float | None, float | None, str]] = [
        ("t.load", "F", "plan.load", plan.load, v.mean_load, "N"),
    ]
    if isinstance(config, PinOnDiscConfig):
        per_minute = 60.0 / (2.0 * math.pi * config.track_radius)
        rows += [
            ("c.speed", "v", "plan.speed", plan.speed, speed, "m/s"),
            ("c.rpm", "n", "plan.speed", plan.speed * per_minute, _times(speed, per_minute), "rpm"),
            ("c.distance", "L", "plan.distance", plan.distance, v.sliding_distance, "m"),
            (
                "t.laps",
                "n_L",
                "plan.distance",
                plan.distance / (2 * math.pi * config.track_radius),
                v.laps,
                "",
            ),
        ]
    else:
        frequency = v.laps / v.duration if v.duration > 0 else None
        rows += [
            ("c.frequency", "f", "frequency", config.frequency, frequency, "Hz"),
            ("c.stroke", "S", "stroke_length", config.stroke_length * 1e3, None, "mm"),
            ("c.distance", "L", "plan.distance", plan.distance, v.sliding_distance, "m"),
            (
                "t.cycles",
                "n_c",
                "plan.distance",
                plan.distance / (2 * config.stroke_length),
                v.laps,
                "",
            ),
        ]
    rows += [
        ("c.temperature", "T", "plan.temperature", plan.temperature, v.temperature_mean, "degC"),
        ("c.humidity", "RH", "plan.humidity", plan.humidity, None, "%"),
    ]
    printed: list[list[str]] = []
    for key, symbol, path, planned, measured, unit in rows:
        number = _count if key in ("t.laps", "t.cycles") else fmt
        shown = number(planned)
        if path is not None and run.from_default(path):
            shown = t("config.default", value=shown)
        printed.append(
            [
                html_symbol(t(key)),
                html_symbol(t.symbol(symbol)),
                shown,
                number(measured) if measured is not None else t("c.not_recorded"),
                t.unit(unit) if unit else "",
            ]
        )
    head = [t("col.quantity"), t("col.symbol"), t("c.planned"), t("c.measured"), t("col.unit")]
    caption = t("c.caption_g99" if isinstance(config, PinOnDiscConfig) else "c.caption_g133")
    return Table(caption=caption, header=head, rows=printed, labels=2)


def _count(value: float | None) -> str:
    """Laps or cycles: a whole number (issue 37, item 6)."""
    return fmt(None) if value is None else str(count(value))


def _times(value: float | None, factor: float) -> float | None:
    return None if value is None else value * factor


def deviations(t: Messages, config: Config, v: Results) -> list[str]:
    """The sentences of the report on what departs: from the plan (distance, load); on the
    flat from G133's procedure of the same lubrication (A dry, B lubricated); on the disc,
    G99's statement that the parameters are the test's own."""
    found: list[str] = []
    plan = config.plan
    for key, planned, measured in (
        ("c.off_distance", plan.distance, v.sliding_distance),
        ("c.off_load", plan.load, v.mean_load),
    ):
        if planned > 0 and abs(measured - planned) > TOLERANCE * planned:
            found.append(t(key, planned=fmt(planned), measured=fmt(measured)))
    if isinstance(config, ReciprocatingConfig):
        lubricated = plan.lubricant.strip().casefold() not in ("", "none", "dry")
        procedure = G133[1] if lubricated else G133[0]
        apart = [
            t(key, given=fmt(given), standard=fmt(standard))
            for key, given, standard in _against(config, procedure)
            if abs(given - standard) > TOLERANCE * abs(standard)
        ]
        if config.tip != "ball":
            apart.insert(0, t("c.dev_tip"))
        if apart:
            found.append(t("c.g133_apart", procedure=procedure.name, what="; ".join(apart)))
        else:
            found.append(t("c.g133_as", procedure=procedure.name))
    else:
        # G99-17, 1.3 and 4.2 (stored copies of its scope on the AFNOR, KPT and iTeh
        # catalogue pages): a test with parameters of its own says so. The study's own
        # parameters (G99-17, table 1) could not be read from a stored copy, so rig does not
        # compare them: it says what G99 asks of every test it cannot show to be the study's.
        found.append(t("c.g99_own"))
    return found


def _against(config: ReciprocatingConfig, procedure: Procedure) -> list[tuple[str, float, float]]:
    """The run's parameters beside the procedure's: ``(message key, given, standard)``,
    lengths in mm; the ball's diameter only for a ball, the temperature only where the
    procedure fixes one (B's 150 °C)."""
    plan = config.plan
    pairs = [
        ("c.dev_load", plan.load, procedure.load),
        ("c.dev_stroke", config.stroke_length * 1e3, procedure.stroke_length * 1e3),
        ("c.dev_frequency", config.frequency, procedure.frequency),
        ("c.dev_distance", plan.distance, procedure.distance),
    ]
    if config.tip == "ball":
        pairs.append(("c.dev_ball", config.tip_diameter * 1e3, procedure.ball_diameter * 1e3))
    if procedure.temperature is not None:
        pairs.append(("c.dev_temperature", plan.temperature, procedure.temperature))
    return pairs
