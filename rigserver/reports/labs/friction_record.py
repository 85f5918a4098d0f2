"""The friction record as the friction machines' reports draw it (lab 2's SMTs-2, the
tribometers): the block means over the sliding distance with their min-max band, the
running-in shaded, the steady mean drawn over the steady part."""

from __future__ import annotations

from rigserver.reports import blocks
from rigserver.reports.i18n import Messages
from rigserver.reports.plots import axes, decorate, to_svg
from schemas.results import Series


def friction_record_svg(
    t: Messages,
    drawn: Series,
    symbol: str,
    *,
    running_in: float | None,
    running_in_label: str,
    steady_from: float | None,
    steady: float | None,
    steady_shown: str,
) -> str:
    """The coefficient ``symbol`` (f, μ) against the sliding distance L: ``drawn``'s block
    means and min-max band; the distance up to ``running_in`` shaded (none: not shaded);
    the ``steady`` mean (printed ``steady_shown``) from ``steady_from`` to the record's end
    (either none: not drawn)."""
    fig, (ax,) = axes(height=3.0)
    if running_in is not None:
        ax.axvspan(0.0, running_in, color="0.88", label=running_in_label)
    ax.fill_between(drawn.x, drawn.y_min, drawn.y_max, color="C0", alpha=0.25, linewidth=0)
    ax.plot(drawn.x, drawn.y, color="C0", linewidth=0.8, label=t("w.block_mean"))
    if drawn.x and steady is not None and steady_from is not None:
        ax.hlines(
            steady,
            steady_from,
            drawn.x[-1],
            colors="C3",
            linewidth=1.2,
            label=f"{t('w.steady_mean')} {symbol} = {steady_shown}",
        )
    decorate(ax, xlabel=blocks.axis(t, "L", "m"), ylabel=blocks.axis(t, symbol))
    return to_svg(fig)
