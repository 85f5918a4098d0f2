"""The ISO roughness of a profile in a report: a sentence on why it differs from the manual's,
the manual's parameters beside the ISO ones, every ISO parameter with the filter's settings,
and a figure of the profile with both mean lines and the filtered roughness profile.

A block of its own (issue 23), called by the profilometer's and the SMTs-2's reports.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from markupsafe import Markup
from matplotlib.figure import Figure as PlotFigure

from rigserver.core import roughness
from rigserver.core.iso_roughness import iso_profile
from rigserver.reports import blocks, results_view
from rigserver.reports.document import Block, Figure, Paragraph, Section, Table, Text
from rigserver.reports.downsample import min_max
from rigserver.reports.formatting import html_symbol, shown
from rigserver.reports.i18n import Messages
from rigserver.reports.plots import WIDTH, decorate, to_svg
from schemas.labels import PROFILOMETER, Label
from schemas.quantity import units_of
from schemas.results import IsoRoughnessResult, ProfilometerResults

#: Columns a trace is decimated to for drawing (min-max keeps every peak and valley).
DRAWN_COLUMNS = 700

#: The manual's parameters and the ISO ones that answer the same question.
PAIRS = (("ra", "ra"), ("rq", "rq"), ("rz", "rz"), ("rmax", "rt"), ("sm", "rsm"))

_M_PER_MM, _M_PER_UM = 1e-3, 1e-6


def parameters_table(
    t: Messages, caption: Text, iso: IsoRoughnessResult, labels: Mapping[str, Label], prefix: str
) -> Table:
    """Every quantity of the ISO result, the filter's settings first: name (with the
    standard), symbol, value, unit; how λc was chosen and the ends were handled, in words,
    below the table."""
    units = units_of(IsoRoughnessResult)
    rows: list[list[Text]] = []
    words: list[str] = []
    for name in IsoRoughnessResult.model_fields:
        label = labels[prefix + name]
        value: Any = getattr(iso, name)
        if isinstance(value, str):
            words.append(f"{t.gettext(label.text)}: {t.gettext(value)}")
            continue
        rows.append(
            [
                html_symbol(results_view.name(t, label)),
                html_symbol(label.symbol),
                results_view.value(t, label, value, units.get(name, label.unit)),
                t.unit(label.unit),
            ]
        )
    head: list[Text] = [t("col.quantity"), t("col.symbol"), t("col.value"), t("col.unit")]
    return Table(caption=caption, header=head, rows=rows, labels=2, note="; ".join(words) + ".")


def _comparison(t: Messages, v: ProfilometerResults, iso: IsoRoughnessResult) -> Table:
    manual_units, iso_units = units_of(ProfilometerResults), units_of(IsoRoughnessResult)
    rows: list[list[Text]] = []
    for manual, standard in PAIRS:
        m_label, i_label = PROFILOMETER[manual], PROFILOMETER["iso." + standard]
        m_value = shown(m_label, getattr(v, manual), manual_units[manual])
        i_value = shown(m_label, getattr(iso, standard), iso_units[standard])
        rows.append(
            [
                Markup("{} = {}").format(html_symbol(m_label.symbol), m_value),
                Markup("{} = {}").format(html_symbol(i_label.symbol), i_value),
                t.unit(m_label.unit),
            ]
        )
    head: list[Text] = [t("iso.col_manual"), t("iso.col_iso"), t("col.unit")]
    return Table(caption=t("iso.compare"), header=head, rows=rows, labels=0)


def _explanation(t: Messages, v: ProfilometerResults, iso: IsoRoughnessResult) -> Text:
    return html_symbol(
        t(
            "iso.explain",
            ra=shown(PROFILOMETER["ra"], v.ra, "m"),
            ra_iso=shown(PROFILOMETER["iso.ra"], iso.ra, "m"),
            lambda_c=shown(PROFILOMETER["iso.lambda_c"], iso.lambda_c, "m"),
            lambda_s=shown(PROFILOMETER["iso.lambda_s"], iso.lambda_s, "m"),
        )
    )


def _two_lines(t: Messages, symbol: str) -> str:
    """The axis label of a stacked plot, the quantity's name above its symbol and unit: on
    one line it is longer than the plot is high and runs into its neighbour's."""
    name = t.gettext(blocks.AXES[symbol])
    return blocks.axis(t, symbol, "um").replace(f"{name} ", f"{name}\n", 1)


def _figure_svg(t: Messages, x: Any, y: Any, iso: IsoRoughnessResult) -> str:
    """Above: the trace with the manual's least-squares mean line and the ISO mean line
    (form + λc waviness); below: the roughness profile with the evaluation length's sections."""
    found = iso_profile(x, y, lambda_c=iso.lambda_c, lambda_s=iso.lambda_s)
    xs = found.x / _M_PER_MM
    line = roughness.mean_line(x=x, y=y)
    fig = PlotFigure(figsize=(WIDTH, 4.6), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    drawn_x, drawn_y = min_max(
        np.asarray(x) / _M_PER_MM, np.asarray(y) / _M_PER_UM, buckets=DRAWN_COLUMNS
    )
    top.plot(drawn_x, drawn_y, linewidth=0.6, color="0.25", label=t("p.profile"))
    ends = np.array([x[0], x[-1]])
    top.plot(
        ends / _M_PER_MM,
        (line.slope * ends + line.intercept) / _M_PER_UM,
        "--",
        linewidth=1.0,
        label=t("iso.ls_line"),
    )
    top.plot(
        xs, (found.form + found.waviness) / _M_PER_UM, linewidth=1.2, label=t("iso.gauss_line")
    )
    r_x, r_y = min_max(xs, found.roughness / _M_PER_UM, buckets=DRAWN_COLUMNS)
    bottom.plot(r_x, r_y, linewidth=0.6, color="0.25", label=t("iso.roughness"))
    bottom.axhline(0.0, linewidth=0.8, color="C1")
    first, last = xs[found.start], xs[found.stop - 1]
    top.axvspan(first, last, color="C2", alpha=0.08)
    bottom.axvspan(first, last, color="C2", alpha=0.08, label=t("iso.evaluation"))
    if found.parts == 1:  # a trace analysed in parts has its sections apart, in each part
        for k in range(1, found.sections):
            bottom.axvline(first + k * found.section_length / _M_PER_MM, linewidth=0.5, color="C2")
    decorate(top, xlabel=blocks.axis(t, "x", "mm"), ylabel=_two_lines(t, "y"), legend_outside=True)
    top.set_xlabel("")  # the x axis is shared: named once, under the lower plot
    decorate(
        bottom, xlabel=blocks.axis(t, "x", "mm"), ylabel=_two_lines(t, "Z"), legend_outside=True
    )
    fig.align_ylabels([top, bottom])
    return to_svg(fig)


def profilometer_section(
    t: Messages, v: ProfilometerResults, trace: Mapping[str, Any] | None
) -> Section | None:
    """The ISO section of a profilometer report; ``trace`` holds x and y in metres."""
    if v.iso is None:
        return None
    found: list[Block] = []
    if v.ra is not None:
        found.append(Paragraph(_explanation(t, v, v.iso)))
        found.append(_comparison(t, v, v.iso))
    found.append(parameters_table(t, t("iso.params"), v.iso, PROFILOMETER, "iso."))
    if trace is not None:
        found.append(Figure(t("iso.fig"), _figure_svg(t, trace["x"], trace["y"], v.iso)))
    return Section(t("iso.section"), found)


def track_table(
    t: Messages, iso: IsoRoughnessResult | None, labels: Mapping[str, Label], prefix: str
) -> Table | None:
    """The ISO roughness across a wear track, labelled ``<prefix>*`` (``disc_wear.iso.``)."""
    if iso is None:
        return None
    return parameters_table(t, t("iso.track"), iso, labels, prefix)
