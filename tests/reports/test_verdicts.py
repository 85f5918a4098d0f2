"""The theory's verdict beside every theoretical value wherever it is shown: the runs list
and the run page (key results), the console summary of `make run` and of rigsim, and the
report's theory table; the conclusions quote the tables' value ± U (k = 2)."""

from __future__ import annotations

import io

from rich.console import Console

from rigserver.reports.formatting import with_uncertainty
from rigserver.reports.i18n import Messages
from rigserver.web.pages import key_results
from rigsim.demo import _headline
from rigsim.report import print_results
from schemas.results import Smts2Results
from schemas.stands import DECLARATIONS, StandKind, theory_outside
from tests.reports.rendered import run_report
from tests.reports.simulated import simulated

KIND = StandKind.SMTS2
VERDICT = DECLARATIONS[KIND].theory_verdict or ""


def _outside_run() -> tuple[Smts2Results, dict[str, float]]:
    s = simulated(KIND)
    v = s.result.values
    assert isinstance(v, Smts2Results) and v.validity is not None
    return v, s.result.key_results


def test_the_key_results_carry_the_verdict() -> None:
    v, keys = _outside_run()
    assert keys[VERDICT] == float(v.validity.within_range)  # type: ignore[union-attr]
    assert theory_outside(KIND, keys) == (not v.validity.within_range)  # type: ignore[union-attr]


def test_the_runs_list_and_the_console_mark_a_theory_out_of_range() -> None:
    s = simulated(KIND)
    for within, marked in ((0.0, True), (1.0, False)):
        keys = {**s.result.key_results, VERDICT: within}
        run = s.run.model_copy(update={"key_results": keys})
        for lang, words in (("en", "theory outside its range"), ("ru", "теория вне области")):
            page = str(key_results(Messages(lang), run))  # type: ignore[arg-type]
            assert (words in page) == marked, page
            assert "within" not in page  # the verdict marks the values, it is not one
        line = _headline(keys, s.result.payload["units"], KIND)
        assert "experimental" not in line and "theoretical" not in line  # symbols, not keys
        theory = [p for p in line.split(", ") if p.startswith("Iₕ,ₜₕ = ")]  # I_h,th
        assert theory and ("outside its range" in theory[0]) == marked, line


def test_rigsim_prints_the_verdict_beside_the_theory() -> None:
    s = simulated(KIND)
    out = io.StringIO()
    print_results(Console(file=out, width=200), s.result.payload)
    lines = [line for line in out.getvalue().splitlines() if "theoretical wear intensity" in line]
    outside = theory_outside(KIND, s.result.payload["values"])
    assert lines and all(("outside its range" in line) == outside for line in lines)


def test_the_conclusions_quote_the_uncertainty_table() -> None:
    v, _ = _outside_run()
    html = run_report(KIND, "en").html
    quoted = with_uncertainty(v.friction_steady, v.friction_steady_expanded)
    conclusions = html.split("Computed results")[-1]
    assert f"f = {quoted}" in conclusions
    assert html.count(quoted) >= 2  # the uncertainty table and the conclusions
    if not v.validity.within_range:  # type: ignore[union-attr]
        assert "outside its range for this test (see the validity table)" in html


def test_abbreviations_and_corrections_are_explained_once() -> None:
    for lang in ("en", "ru"):
        html = run_report(KIND, lang).html  # type: ignore[arg-type]
        appendix = html.split("<h2>")[-1]
        assert "GUM" in appendix and "ASTM G99" in appendix and "E2 (2.6)" in appendix
        assert appendix.count("E2 (2.6)") == 1


def test_a_specimen_that_gained_mass_is_said_so_not_worn() -> None:
    """The simulated reciprocating run's ball weighs 0.02 mg more after the test: its wear
    rate from the mass is below zero, and the conclusion says why; the disc's is not."""
    v = simulated(StandKind.RECIPROCATING).result.values
    gained = v.pin_mass  # type: ignore[union-attr]
    assert gained is not None and gained.specific_wear_rate < 0
    for lang, title, words in (
        ("en", "Computed results", "the specimen gained"),
        ("ru", "Вычисленные результаты", "образец прибавил"),
    ):
        html = run_report(StandKind.RECIPROCATING, lang).html  # type: ignore[arg-type]
        (conclusions,) = [s for s in html.split("<h2>") if s.startswith(title)]
        said = [line for line in conclusions.split("<li>") if words in line]
        assert len(said) == 1, conclusions
        assert "-5" in said[0]  # the ball's k from its mass, not the disc's
