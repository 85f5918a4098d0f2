"""One report kit per stand kind: the stand's part of a run's report (its lab's ``build``),
the lab's report list (:mod:`rigserver.reports.contents`) and the overlay plots of a series
report. The one place in the reports that names the stand kinds; a new kind is a lab module,
a contents module and one entry in :data:`KITS` (``tests/test_stand_kinds.py`` checks that
every kind has one)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rigserver.reports.contents import Contents
from rigserver.reports.contents import mtos as mtos_contents
from rigserver.reports.contents import profilometer as profilometer_contents
from rigserver.reports.contents import slide_bearing as slide_bearing_contents
from rigserver.reports.contents import smts2 as smts2_contents
from rigserver.reports.contents.tribometer import contents as tribometer_contents
from rigserver.reports.context import Context, LabReport
from rigserver.reports.labs import mtos, profilometer, slide_bearing, smts2, tribometer
from rigserver.reports.series_curves import SeriesPlot, friction, pairs, profile, rows, series
from schemas.stands import StandKind


@dataclass(frozen=True, slots=True)
class ReportKit:
    """A stand kind's reports: its lab's part of the run report, its report list, and the
    plots that overlay a series' runs."""

    build: Callable[[Context, Any], LabReport]
    contents: Contents
    series_plots: tuple[SeriesPlot, ...]


_TRIBOMETER_PLOTS = (
    SeriesPlot("plot.tribometer", ("L", "m"), ("μ",), lambda run, v, _: series(run, v, "friction")),
)

KITS: dict[StandKind, ReportKit] = {
    StandKind.SMTS2: ReportKit(
        build=smts2.build,
        contents=smts2_contents.CONTENTS,
        series_plots=(
            SeriesPlot("plot.friction", ("L", "m"), ("f",), lambda run, v, _: friction(run, v)),
        ),
    ),
    StandKind.SLIDE_BEARING: ReportKit(
        build=slide_bearing.build,
        contents=slide_bearing_contents.CONTENTS,
        series_plots=(
            SeriesPlot(
                "plot.pressure",
                ("φ", "deg"),
                ("Π_e",),
                lambda run, v, _: rows(run, v, "table", "phi_model", "pi_measured"),
                markers=True,
            ),
        ),
    ),
    StandKind.MTOS: ReportKit(
        build=mtos.build,
        contents=mtos_contents.CONTENTS,
        series_plots=(
            SeriesPlot(
                "plot.mtos_f",
                ("N", "N"),
                ("f_e",),
                lambda run, v, _: rows(run, v, "steps", "load", "friction_measured"),
                paired=True,
            ),
            SeriesPlot(
                "plot.stribeck",
                ("S_1",),
                ("f_e",),
                lambda run, v, _: rows(
                    run, v, "steps", "bearing_characteristic", "friction_measured"
                ),
                paired=True,
            ),
        ),
    ),
    StandKind.PROFILOMETER: ReportKit(
        build=profilometer.build,
        contents=profilometer_contents.CONTENTS,
        series_plots=(
            SeriesPlot(
                "plot.bearing",
                ("ε",),
                ("t_p",),
                lambda run, v, _: pairs(run, v, "eps", "tp"),
                markers=True,
            ),
            SeriesPlot(
                "plot.profile",
                ("x", "mm"),
                ("y", "um"),
                lambda run, _, readings: profile(run, readings),
            ),
        ),
    ),
    StandKind.PIN_ON_DISC: ReportKit(
        build=tribometer.build,
        contents=tribometer_contents("pin_on_disc"),
        series_plots=_TRIBOMETER_PLOTS,
    ),
    StandKind.RECIPROCATING: ReportKit(
        build=tribometer.build,
        contents=tribometer_contents("reciprocating"),
        series_plots=_TRIBOMETER_PLOTS,
    ),
}
