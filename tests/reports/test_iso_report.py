"""The ISO roughness in the reports (issue 23): the sentence on why it differs from the
manual's, the two side by side, every ISO parameter with the filter's settings, and the
figure of the profile with both mean lines; in English and Russian."""

from __future__ import annotations

import pytest

from rigserver.reports.formatting import fmt, number_locale
from rigserver.reports.i18n import Lang
from schemas.results import ProfilometerResults
from schemas.stands import StandKind
from tests.reports.simulated import simulated, table
from tests.reports.test_report import report, row_of, svgs

CAPTION = {"en": "ISO 21920-2 parameters", "ru": "Параметры профиля шероховатости по ISO"}
SIDE = {"en": "The manual's parameters beside", "ru": "Параметры по методике рядом"}


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_the_iso_section_prints_the_results(lang: Lang) -> None:
    v = simulated(StandKind.PROFILOMETER).result.values
    assert isinstance(v, ProfilometerResults) and v.iso is not None and v.ra is not None
    html = report(StandKind.PROFILOMETER, lang)
    with number_locale(lang):
        ra, ra_iso = fmt(float(f"{v.ra * 1e6:.3g}")), fmt(float(f"{v.iso.ra * 1e6:.3g}"))
        lc = fmt(v.iso.lambda_c * 1e3)
    assert f"Ra = {ra} " in html and f"Ra = {ra_iso} " in html and f"λc = {lc} " in html
    side = table(html, SIDE[lang])
    assert side.rows[0] == [f"Ra = {ra}", f"RaISO = {ra_iso}", side.rows[0][2]]
    params = table(html, CAPTION[lang])
    assert len(params.rows) == len(type(v.iso).model_fields) - 2  # the two in words below
    assert [row[2] for row in params.rows[:2]] == [lc, fmt(2.5)] or lang == "ru"
    figure = svgs(html)[-1]  # the profile, both mean lines, the roughness profile
    assert figure.count('<g id="line2d_') > 4


def test_the_report_says_how_the_filter_was_set() -> None:
    html = report(StandKind.PROFILOMETER)
    assert (
        "how λc was chosen: by Ra, table of ISO 21920-3; end effects of the filter: kept, "
        "corrected by renormalised weights (ISO 16610-28)."
    ) in html
    assert "ISO roughness: the trace is shorter than 2λc" in html


def test_the_smts2_report_prints_the_roughness_across_the_track() -> None:
    from rigserver.analysis import analyse
    from rigserver.reports.run_report import build_report, render_report
    from tests.reports.simulated import MADE

    wear, track = simulated(StandKind.SMTS2), simulated(StandKind.PROFILOMETER)
    run = wear.run.model_copy(update={"specimen": {**wear.run.specimen, "disc_profile_run": "P"}})
    values = analyse(run, wear.readings, {"P": (track.run, track.readings)}.get).values
    html = render_report(
        build_report(
            run=run,
            stand=wear.stand,
            values=values.model_dump(mode="json"),
            readings=wear.readings,
            lang="ru",
            made=MADE,
        )
    )
    found = table(html, "Шероховатость поперёк дорожки")
    track_values = track.result.values
    assert isinstance(track_values, ProfilometerResults) and track_values.iso is not None
    with number_locale("ru"):
        assert row_of(
            html,
            "Шероховатость поперёк дорожки",
            "граничная длина волны λc фильтра шероховатости (ISO 16610-21)",
        )[1] == fmt(track_values.iso.lambda_c * 1e3)
    assert len(found.rows) == len(type(track_values.iso).model_fields) - 2
