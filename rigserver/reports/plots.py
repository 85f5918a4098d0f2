"""Vector plots (SVG) for the reports, with symbols and units on the axes.

Figures are built with matplotlib's object API (no pyplot, no global state), so pages can
be drawn from several threads at once.
"""

from __future__ import annotations

import io
import math
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar

from matplotlib.axes import Axes
from matplotlib.axis import Axis
from matplotlib.figure import Figure
from matplotlib.ticker import LogFormatterMathtext, NullFormatter, ScalarFormatter

from rigserver.reports.formatting import decimal_sign, tex

WIDTH = 7.0
"""Width of a report figure, inches: the text width of an A4 page with 15 mm margins."""


_DRAWN: ContextVar[list[Figure] | None] = ContextVar("drawn_figures", default=None)


@contextmanager
def recording() -> Iterator[list[Figure]]:
    """The figures drawn to SVG inside the block, for tests that inspect their axes."""
    found: list[Figure] = []
    token = _DRAWN.set(found)
    try:
        yield found
    finally:
        _DRAWN.reset(token)


def to_svg(fig: Figure) -> str:
    """The figure as an inline ``<svg>`` element."""
    drawn = _DRAWN.get()
    if drawn is not None:
        drawn.append(fig)
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    text = buf.getvalue()
    return text[text.index("<svg") :]


def axes(
    *, height: float = 3.2, columns: int = 1, sharey: bool = False
) -> tuple[Figure, list[Axes]]:
    """A new figure of the report's width with ``columns`` axes side by side."""
    fig = Figure(figsize=(WIDTH, height), layout="constrained" if columns > 1 else None)
    found = fig.subplots(1, columns, squeeze=False, sharey=sharey)
    return fig, list(found[0])


class LocaleTicks(ScalarFormatter):
    """Matplotlib's tick labels with the decimal sign of the report's language (a comma in
    Russian), chosen when the axes are decorated (:func:`formatting.number_locale`); no
    offset and no multiplier at the axis' end: a power of ten the ticks share is divided out
    here and named in the axis label (:func:`decorate`)."""

    def __init__(self, power: int = 0) -> None:
        super().__init__(useOffset=False)
        self.set_scientific(False)
        self.decimal = decimal_sign()
        self.power = power

    def __call__(self, x: float, pos: int | None = None) -> str:
        return self._local(super().__call__(x / 10.0**self.power, pos))

    def set_locs(self, locs: Sequence[float]) -> None:
        super().set_locs([x / 10.0**self.power for x in locs])

    def get_offset(self) -> str:
        return ""

    def _local(self, text: str) -> str:
        if self.decimal == ".":
            return text
        return text.replace(".", "{,}" if "$" in text else self.decimal)


def decorate(
    ax: Axes,
    *,
    xlabel: str,
    ylabel: str,
    title: str = "",
    legend_outside: bool = False,
    labels_drawn_as_given: bool = False,
) -> None:
    """Axis labels (symbol, unit), a light grid, and a legend when lines are labelled.

    Legend labels may hold symbols in the syntax of :func:`formatting.tex` (``"Π_э"``);
    ``labels_drawn_as_given``: they are matplotlib's text already (made with
    :func:`formatting.tex` and :func:`formatting.plot_text`, for labels holding a user's
    text); ``legend_outside`` puts the legend right of the axes, for plots that fill them.
    """
    ax.set_xlabel(_ticks(ax.xaxis, xlabel))
    ax.set_ylabel(_ticks(ax.yaxis, ylabel))
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, linewidth=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        texts = labels if labels_drawn_as_given else [tex(label) for label in labels]
        if legend_outside:
            ax.legend(handles, texts, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        else:
            ax.legend(handles, texts, fontsize=8)


POWER = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def _ticks(axis: Axis, label: str) -> str:
    """Tick labels for ``axis``: powers of ten (10ⁿ, mathtext) on a log axis; on a linear
    axis the language's decimal sign, and a power of ten all the ticks share divided out and
    named in the label (``I_h, 10⁻⁸``), so no offset text stands at the axis' end; named
    categories (fixed tick labels) are kept. Returns the label."""
    if axis.get_scale() == "log":
        axis.set_major_formatter(LogFormatterMathtext())
        axis.set_minor_formatter(NullFormatter())
        return label
    if not isinstance(axis.get_major_formatter(), ScalarFormatter):
        return label  # categories named by their ticks
    low, high = axis.get_view_interval()
    biggest = max(abs(low), abs(high))
    power = 0
    if biggest > 0 and not 1e-2 <= biggest < 1e4:
        power = math.floor(math.log10(biggest))
    axis.set_major_formatter(LocaleTicks(power))
    if power == 0:
        return label
    scale = "10" + str(power).translate(POWER)
    head, comma, unit = label.rpartition(", ")
    if comma and "$" not in unit:  # in units of 10ⁿ of the unit: "L, 10³ m"
        return f"{head}, {scale} {unit}"
    return f"{label}, {scale}" if label else scale


def lines(
    x: Sequence[float],
    series: Sequence[tuple[str, Sequence[float]]],
    *,
    xlabel: str,
    ylabel: str,
    title: str = "",
) -> str:
    """One axes with several labelled lines (labels in matplotlib's text already), as SVG;
    ticks in the language's decimal sign (:func:`decorate`)."""
    fig = Figure(figsize=(WIDTH, 3.2))
    ax = fig.subplots()
    for label, y in series:
        ax.plot(x, y, label=label if len(series) > 1 else None, linewidth=1.2)
    decorate(ax, xlabel=xlabel, ylabel=ylabel, title=title, labels_drawn_as_given=True)
    return to_svg(fig)
