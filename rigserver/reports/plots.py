"""Vector plots (SVG) for the reports, with symbols and units on the axes.

Figures are built with matplotlib's object API (no pyplot, no global state), so pages can
be drawn from several threads at once.
"""

from __future__ import annotations

import io
from collections.abc import Sequence

from matplotlib.figure import Figure


def to_svg(fig: Figure) -> str:
    """The figure as an inline ``<svg>`` element."""
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    text = buf.getvalue()
    return text[text.index("<svg") :]


def lines(
    x: Sequence[float],
    series: Sequence[tuple[str, Sequence[float]]],
    *,
    xlabel: str,
    ylabel: str,
    title: str = "",
) -> str:
    """One axes with several labelled lines, as SVG."""
    fig = Figure(figsize=(7.0, 3.2))
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
