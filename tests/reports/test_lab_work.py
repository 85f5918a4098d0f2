"""A lab work of several runs (issue 38, item 2): lab 2's wear run and its adhesive and
oxidative runs of one session, reported as the manual's two parts; part 2 with f_a, f_ok and
Δf (2.16) with its uncertainty, and the students' observations of each mode. Over the API: a
series of purpose ``lab`` names each run's part, its report is the lab work's."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from rigserver.reports.formatting import number_locale, with_uncertainty
from rigserver.reports.i18n import Lang
from rigserver.reports.lab_work import WorkRun, build_lab_work
from rigserver.reports.run_report import render_report
from rigsim.simulators import simulate
from rigsim.simulators.smts2 import Smts2Settings
from schemas.stands import StandKind
from schemas.student_notes import StudentNotes
from tests.api.conftest import READER, WRITER, auth, in_process
from tests.reports.rendered import laid_out, pdf_text, squeezed
from tests.reports.simulated import MADE, Simulated, analysed, post

MODES = ("wear", "adhesive", "oxidative")
SAID = {
    "adhesive": "Brass smeared on the disc; the moment jumped.",
    "oxidative": "A dark oxide film; quiet running.",
}


def _run(mode: str, seed: int) -> Simulated:
    return analysed(StandKind.SMTS2, simulate(StandKind.SMTS2, Smts2Settings.for_mode(mode), seed))


@pytest.fixture(scope="module")
def work() -> list[tuple[str, Simulated]]:
    return [(mode, _run(mode, 11 + i)) for i, mode in enumerate(MODES)]


def _expected(work: list[tuple[str, Simulated]]) -> tuple[float, float]:
    """Δf (2.16) and its expanded uncertainty, computed here: the arithmetic of (2.16) and a
    numerical propagation (central differences) of the runs' own u(f)."""
    v = {mode: s.result.payload["values"] for mode, s in work}
    f_a, f_ok = v["adhesive"]["friction_steady"], v["oxidative"]["friction_steady"]
    u_a = v["adhesive"]["friction_steady_uncertainty"]
    u_ok = v["oxidative"]["friction_steady_uncertainty"]

    def df(a: float, ok: float) -> float:
        return (a - ok) / a * 100.0

    h = 1e-7
    d_a = (df(f_a + h, f_ok) - df(f_a - h, f_ok)) / (2 * h)
    d_ok = (df(f_a, f_ok + h) - df(f_a, f_ok - h)) / (2 * h)
    return df(f_a, f_ok), 2.0 * math.sqrt((d_a * u_a) ** 2 + (d_ok * u_ok) ** 2)


@pytest.mark.parametrize(
    ("lang", "part1", "part2"),
    [
        ("en", "Part 1. Wear in dry friction", "Part 2. Adhesive against oxidative wear"),
        ("ru", "Часть 1. Изнашивание при сухом трении", "Часть 2. Адгезионное и окислительное"),
    ],
)
def test_a_lab_work_of_three_runs_reports_both_parts_with_delta_f(
    work: list[tuple[str, Simulated]], lang: Lang, part1: str, part2: str
) -> None:
    runs = [
        WorkRun(
            s.run.model_copy(update={"id": f"20261122T114026Z-0000000{i}"}),
            mode,
            s.result.payload["values"],
            StudentNotes(observations=SAID.get(mode, "")),
        )
        for i, (mode, s) in enumerate(work)
    ]
    wear = work[0][1]
    report = build_lab_work(
        runs=runs, stand=wear.stand, readings=wear.readings, lang=lang, made=MADE
    )
    text = squeezed(pdf_text(laid_out("lab work", render_report(report), []).pdf))
    assert squeezed(part1) in text and squeezed(part2) in text
    assert text.index(squeezed(part1)) < text.index(squeezed(part2))
    delta, expanded = _expected(work)
    assert 0 < delta < 100  # oxide films lower friction: the manual's expectation
    with number_locale(lang):
        shown = with_uncertainty(delta, expanded)
    assert squeezed(f"Δf{shown}") in text or squeezed(shown) in text
    assert "Δf=(fa-fок)/fa·100%" in text or "Δf=(fa-fok)/fa·100%" in text  # (2.16) written
    for words in SAID.values():
        assert squeezed(words) in text


def test_a_lab_series_takes_the_manuals_parts_and_reports_the_lab_work(tmp_path: Path) -> None:
    with in_process(tmp_path, report_processes=False) as client:
        ids = {
            mode: post(client, simulate(StandKind.SMTS2, Smts2Settings.for_mode(mode), 5), WRITER)
            for mode in MODES
        }
        made = client.post(
            "/api/v1/series", json={"name": "Lab 2, MT-31", "purpose": "lab"}, headers=auth(WRITER)
        )
        assert made.status_code == 201, made.text
        series = made.json()["id"]
        url = f"/api/v1/series/{series}/runs"
        refused = client.post(url, json={"run_id": ids["wear"]}, headers=auth(WRITER))
        assert refused.status_code == 422 and "wear, adhesive, oxidative" in refused.text
        for mode, run_id in ids.items():
            added = client.post(url, json={"run_id": run_id, "level": mode}, headers=auth(WRITER))
            assert added.status_code == 201, added.text
        notes = {"observations": SAID["oxidative"]}
        put = client.put(f"/api/v1/runs/{ids['oxidative']}/notes", json=notes, headers=auth(WRITER))
        assert put.status_code == 200
        detail = client.get(f"/api/v1/series/{series}", headers=auth(READER)).json()
        ao = detail["adhesive_oxidative"]
        assert ao is not None and ao["difference_uncertainty"] > 0
        # three levels of their own: no statistic pools them into one interval
        assert all(s["overall"] is None for s in detail["statistics"])
        pdf = client.get(f"/api/v1/series/{series}/report.pdf?lang=en", headers=auth(READER))
        assert pdf.status_code == 200
        text = squeezed(pdf_text(pdf.content))
        assert squeezed("Part 2. Adhesive against oxidative wear") in text
        assert squeezed(SAID["oxidative"]) in text
