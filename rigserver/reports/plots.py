"""Vector plots (SVG) for the reports, with symbols and units on the axes.

Figures are built with matplotlib's object API (no pyplot, no global state), so pages can
be drawn from several threads at once.
"""

from __future__ import annotations

import io
from collections.abc import Sequence

from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import ScalarFormatter

from rigserver.reports.formatting import decimal_sign, tex

WIDTH = 7.0
"""Width of a report figure, inches: the text width of an A4 page with 15 mm margins."""


def to_svg(fig: Figure) -> str:
    """The figure as an inline ``<svg>`` element."""
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
    Russian), chosen when the axes are decorated (:func:`formatting.number_locale`)."""

    def __init__(self) -> None:
        super().__init__()
        self.decimal = decimal_sign()

    def __call__(self, x: float, pos: int | None = None) -> str:
        return self._local(super().__call__(x, pos))

    def get_offset(self) -> str:
        return self._local(super().get_offset())

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
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.xaxis.set_major_formatter(LocaleTicks())
    ax.yaxis.set_major_formatter(LocaleTicks())
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


def lines(
    x: Sequence[float],
    series: Sequence[tuple[str, Sequence[float]]],
    *,
    xlabel: str,
    ylabel: str,
    title: str = "",
) -> str:
    """One axes with several labelled lines, as SVG."""
    fig = Figure(figsize=(WIDTH, 3.2))
    ax = fig.subplots()
    for label, y in series:
        ax.plot(x, y, label=label, linewidth=1.2)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.grid(True, linewidth=0.3)
    if len(series) > 1:
        ax.legend(fontsize=8)
    return to_svg(fig)
