"""Every plot of every stand's report and series report says what it shows: each axis names
the quantity beside its symbol (and unit), a log axis ticks in powers of ten (10ⁿ), no axis
carries offset text, the categories of a categorical axis are named, the SMTs-2 wear plot
draws the (2.15) band and its caption says whether the theory is judged, no two texts of a
plot overlap, and the Hersey-Stribeck diagram spans labelled decades."""

from __future__ import annotations

import math
import re
from typing import Any

import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import FixedFormatter, LogFormatterMathtext
from matplotlib.transforms import Bbox

from rigserver.reports.i18n import LANGS, Lang
from schemas.stands import StandKind
from tests.reports.rendered import run_report, series_report
from tests.reports.simulated import simulated

CASES = [(kind, lang) for kind in StandKind for lang in LANGS]


def figures(kind: StandKind, lang: Lang) -> tuple[list[Figure], str]:
    """The figures a stand's run report and series report draw (laid out once for all the
    report tests, tests/reports/rendered.py), and the run report."""
    run, series = run_report(kind, lang), series_report(kind, lang)
    return [*run.figures, *series.figures], run.html


def _words(label: str) -> bool:
    """The label names a quantity in words, beside any mathtext symbol."""
    return bool(re.search(r"[^\W\d_]{3,}", re.sub(r"\$[^$]*\$", "", label)))


def _plotted(fig: Figure) -> list[Axes]:
    return [ax for ax in fig.axes if ax.get_visible() and (ax.lines or ax.collections)]


@pytest.mark.parametrize(("kind", "lang"), CASES)
def test_axes_name_their_quantities(kind: StandKind, lang: Lang) -> None:
    drawn, _ = figures(kind, lang)
    assert drawn
    for number, fig in enumerate(drawn, start=1):
        found = _plotted(fig)
        assert found, f"figure {number} draws nothing"
        for ax in found:
            where = f"figure {number}"
            if ax.get_label() == "<colorbar>":  # a colorbar names its quantity on its one axis
                assert _words(ax.get_ylabel()), f"{where}: colour bar {ax.get_ylabel()!r}"
                continue
            ticks = ax.xaxis.get_major_formatter()
            # a shared x axis is named once, under the lowest of the plots that share it
            named = [a for a in ax.get_shared_x_axes().get_siblings(ax) if a.get_xlabel()]
            assert named, f"{where}: no x label"
            assert all(_words(a.get_xlabel()) for a in named), f"{where}: {ax.get_xlabel()!r}"
            if isinstance(ticks, FixedFormatter):  # categories: each named in words
                assert all(_words(str(s)) for s in ticks.seq), f"{where}: {ticks.seq}"
            shared = [a for a in ax.get_shared_y_axes().get_siblings(ax) if a.get_ylabel()]
            assert shared, f"{where}: no y label"
            assert all(_words(a.get_ylabel()) for a in shared), f"{where}: {ax.get_ylabel()!r}"
            for axis in (ax.xaxis, ax.yaxis):
                assert axis.get_offset_text().get_text() == "", f"{where}: offset text"
                if axis.get_scale() == "log":
                    assert isinstance(axis.get_major_formatter(), LogFormatterMathtext), where


@pytest.mark.parametrize("lang", LANGS)
def test_the_wear_plot_caption_says_what_is_drawn(lang: Lang) -> None:
    drawn, html = figures(StandKind.SMTS2, lang)
    v = simulated(StandKind.SMTS2).result.values
    judged = v.adequacy is not None and (v.validity is None or v.validity.within_range)  # type: ignore[union-attr]
    wear = [fig for fig in drawn if any(ax.get_yscale() == "log" for ax in fig.axes)]
    assert len(wear) == 1
    bands = [p for ax in wear[0].axes for p in ax.patches]
    assert len(bands) == 1  # the band of (2.15), judged or not
    theory = v.theoretical.intensity  # type: ignore[union-attr]
    (low, high) = sorted({y for y in bands[0].get_path().vertices[:, 1]})
    transform = bands[0].get_transform() - wear[0].axes[0].transData
    (_, low), (_, high) = transform.transform([(0, low), (0, high)])
    assert (low, high) == pytest.approx((0.4 * theory, 2.6 * theory))  # (2.15)
    not_judged = {"en": "is not judged", "ru": "не оценивается"}[lang]
    assert (not_judged in html) != judged


def _texts(fig: Figure) -> list[tuple[str, Bbox]]:
    """Every visible, non-empty text of a drawn figure with its box in display units."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    FigureCanvasAgg(fig).draw()
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    ticks = {id(label) for ax in fig.axes for a in (ax.xaxis, ax.yaxis) for label in _all(a)}
    # the labels of the ticks drawn (matplotlib keeps labels of ticks beyond the view limits)
    drawn = {
        id(label)
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
        for tick in axis._update_ticks()
        for label in (tick.label1, tick.label2)
        if label.get_visible()
    }
    found = []
    for text in fig.findobj(Text):
        if id(text) in ticks and id(text) not in drawn:
            continue
        if text.get_visible() and text.get_text().strip() and text.get_alpha() != 0:
            found.append((text.get_text(), text.get_window_extent(renderer)))
    return found


def _all(axis: Any) -> list[Any]:
    ticks = [*axis.get_major_ticks(), *axis.get_minor_ticks()]
    return [label for tick in ticks for label in (tick.label1, tick.label2)]


@pytest.mark.parametrize(("kind", "lang"), CASES)
def test_no_two_texts_of_a_plot_overlap(kind: StandKind, lang: Lang) -> None:
    # the stacked plots of the profilometer's ISO figure once printed their y labels on
    # top of each other
    drawn, _ = figures(kind, lang)
    for number, fig in enumerate(drawn, start=1):
        texts = _texts(fig)
        clashes = [
            f"{a!r} and {b!r}"
            for i, (a, box_a) in enumerate(texts)
            for b, box_b in texts[i + 1 :]
            if _overlap(box_a, box_b) > 0.15 * min(_area(box_a), _area(box_b))
        ]
        assert not clashes, f"figure {number}: " + "; ".join(clashes[:5])


def _area(box: Bbox) -> float:
    return max(box.width, 0.0) * max(box.height, 0.0) or 1.0


def _overlap(a: Bbox, b: Bbox) -> float:
    width = min(a.x1, b.x1) - max(a.x0, b.x0)
    height = min(a.y1, b.y1) - max(a.y0, b.y0)
    return width * height if width > 0 and height > 0 else 0.0


@pytest.mark.parametrize("lang", LANGS)
def test_the_stribeck_plot_is_against_the_inverse_with_decades_and_every_point_inside(
    lang: Lang,
) -> None:
    v = simulated(StandKind.MTOS).result.values
    drawn, _ = figures(StandKind.MTOS, lang)
    (ax,) = [a for a in drawn[0].axes if a.get_xscale() == "log"]
    assert "S_{1}^{-1}" in ax.get_xlabel() or "S₁⁻¹" in ax.get_xlabel()
    inverse = sorted(s.bearing_characteristic_inverse for s in v.steps)  # type: ignore[union-attr]
    plotted = sorted(
        x for line in ax.lines for x in line.get_xdata() if line.get_marker() != "None"
    )
    assert plotted == pytest.approx(inverse)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    for line in ax.lines:
        for x, y in zip(line.get_xdata(), line.get_ydata(), strict=True):
            assert x0 < x < x1 and y0 < y < y1  # inside the frame, not on it
    for low, high in ((x0, x1), (y0, y1)):  # whole decades at both ends: two labelled at least
        assert math.log10(low).is_integer() and math.log10(high).is_integer()
        assert math.log10(high) - math.log10(low) >= 1
