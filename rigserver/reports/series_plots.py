"""Overlay plots of a series: every run's curve, coloured by its level, and each level's
mean with a band of one standard deviation either side.

A level's runs rarely share their abscissae (sliding distances, loads, angles), so the mean
is taken on a common grid over the range all of them cover, each run interpolated linearly
onto it; a level of one run draws no band. The legend names the runs by their level, or,
in a series without levels, each run by what its curve is labelled with (its operator and
date, :func:`rigserver.reports.series_report.run_names`). A level and a run's name are a
user's text: drawn as written, never read as mathtext
(:func:`~rigserver.reports.formatting.plot_text`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rigserver.reports.formatting import plot_text, tex
from rigserver.reports.plots import axes, decorate, to_svg

#: Points of the common grid a level's mean and band are drawn on.
GRID = 200
#: One colour per level, in order (matplotlib's default cycle).
COLOURS = ("C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9")


@dataclass(frozen=True, slots=True)
class Curve:
    """One run's curve: its name in the legend and points (any order; drawn sorted by x)."""

    label: str
    x: NDArray[np.float64]
    y: NDArray[np.float64]


def level_band(
    curves: Sequence[Curve], *, points: int = GRID
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    """The mean of the curves and their sample standard deviation on a common grid.

    The grid spans the x range every curve covers; None for fewer than two curves or
    curves that share no range.
    """
    usable = [c for c in curves if c.x.size >= 2]
    if len(usable) < 2:
        return None
    low = max(float(np.min(c.x)) for c in usable)
    high = min(float(np.max(c.x)) for c in usable)
    if not high > low:
        return None
    grid = np.linspace(low, high, points)
    stack = np.vstack([np.interp(grid, *_sorted(c)) for c in usable])
    return grid, stack.mean(axis=0), stack.std(axis=0, ddof=1)


def paired_band(
    curves: Sequence[Curve],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    """Point by point over runs whose points pair up (the same load steps in the same
    order): the mean x, the mean y and y's sample standard deviation at each point.

    Runs of different lengths pair over the points all of them have; None for fewer than
    two runs."""
    if len(curves) < 2:
        return None
    points = min(c.x.size for c in curves)
    if points == 0:
        return None
    xs = np.vstack([c.x[:points] for c in curves])
    ys = np.vstack([c.y[:points] for c in curves])
    return xs.mean(axis=0), ys.mean(axis=0), ys.std(axis=0, ddof=1)


STYLES = ("-", "--", ":", "-.")
MARKS = ("o", "^", "v", "D", "x")


def overlay(
    levels: Mapping[str, Sequence[Curve]],
    *,
    xlabel: str,
    ylabel: str,
    mean_label: str,
    markers: bool = False,
    paired: bool = False,
) -> str:
    """One axes: the runs of each level in the level's colour, named once by the level, its
    mean and ±s band (SVG); a series of one level draws each run in its own colour, named by
    its curve's label, and the mean in black (runs of one colour and their mean would not
    tell apart on a noisy record).

    ``paired``: the runs' points pair up by position (load steps): each run is drawn as
    points, the level's mean as points with ±s bars (no interpolation across steps)."""
    fig, (ax,) = axes(height=3.4)
    alone = len(levels) == 1
    for i, (level, curves) in enumerate(levels.items()):
        colour = "black" if alone else COLOURS[i % len(COLOURS)]
        runs = [COLOURS[n % len(COLOURS)] if alone else colour for n in range(len(curves))]
        shown = plot_text(level)
        name = f"{shown}: {tex(mean_label)}" if level else tex(mean_label)
        names = [_legend(level, curve, number) for number, curve in enumerate(curves)]
        if paired:
            for number, curve in enumerate(curves):
                ax.plot(
                    curve.x,
                    curve.y,
                    MARKS[number % len(MARKS)],
                    color=runs[number],
                    markersize=3,
                    alpha=0.7,
                    label=names[number],
                )
            pairs = paired_band(curves)
            if pairs is not None:
                x, mean, std = pairs
                ax.errorbar(
                    x,
                    mean,
                    yerr=std,
                    fmt="s",
                    color=colour,
                    markersize=4,
                    capsize=2,
                    label=f"{name} ± s",
                )
            continue
        for number, curve in enumerate(curves):
            x, y = _sorted(curve)
            ax.plot(
                x,
                y,
                color=runs[number],
                linewidth=0.8,
                alpha=0.8,
                linestyle=STYLES[number % len(STYLES)],
                marker="o" if markers else None,
                markersize=3,
                label=names[number],
            )
        band = level_band(curves)
        if band is not None:
            grid, mean, std = band
            ax.plot(grid, mean, color=colour, linewidth=2.0, label=f"{name} ± s")
            ax.fill_between(grid, mean - std, mean + std, color=colour, alpha=0.2, linewidth=0)
    decorate(
        ax,
        xlabel=xlabel,
        ylabel=ylabel,
        legend_outside=True,
        labels_drawn_as_given=True,
    )
    return to_svg(fig)


def _legend(level: str, curve: Curve, number: int) -> str:
    """A run's entry in the legend: its level, once per level (matplotlib leaves out the
    labels that start with ``_``), or its curve's label in a series without levels."""
    if level:
        return plot_text(level) if number == 0 else "_nolegend_"
    return plot_text(curve.label)


def _sorted(curve: Curve) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    order = np.argsort(curve.x, kind="stable")
    return curve.x[order], curve.y[order]
