"""Every plot of every stand's report and series report says what it shows: each axis names
the quantity beside its symbol (and unit), a log axis ticks in powers of ten (10ⁿ), no axis
carries offset text, the categories of a categorical axis are named, and the SMTs-2 wear
plot's caption promises the (2.15) band only where it is drawn."""

from __future__ import annotations

import re

import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import FixedFormatter, LogFormatterMathtext

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
    assert bool(bands) == judged
    no_band = {"en": "no adequacy band", "ru": "без полосы адекватности"}[lang]
    assert (no_band in html) != judged
