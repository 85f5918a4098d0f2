"""The tribometer report as ASTM G99 and G133 ask (issue 37, item 7): planned against
measured conditions (rotational speed, environment, distance), the deviations from the plan
and from G133's procedure, "flat" and "cycles" on the reciprocating tribometer."""

from __future__ import annotations

import math
from html import unescape

from rigserver.reports.i18n import Messages
from rigserver.reports.labs.tribometer_conditions import deviations
from schemas.results import PinOnDiscResults, ReciprocatingResults
from schemas.stands import PinOnDiscConfig, PlannedTest, ReciprocatingConfig, StandKind
from tests.reports.rendered import report_html
from tests.reports.simulated import simulated


def test_the_disc_report_has_the_g99_conditions() -> None:
    done = simulated(StandKind.PIN_ON_DISC)
    v = done.result.values
    assert isinstance(v, PinOnDiscResults)
    html = unescape(report_html(done, "en"))
    assert "Test conditions, planned and measured (ASTM G99-17, clause 10)" in html
    # n = 60·v/(2πR): 0.1 m/s on the 10 mm track, 95.49 rpm planned
    assert "rotational speed of the disc" in html and "95.49" in html
    assert "relative humidity" in html and "not recorded" in html


def test_the_flat_report_cites_g133_and_says_flat_and_cycles() -> None:
    done = simulated(StandKind.RECIPROCATING)
    v = done.result.values
    assert isinstance(v, ReciprocatingResults)
    for lang, words in (
        ("en", ("ASTM G133-05", "Wear of the flat", "cycles run", "procedure A: load 5 N")),
        ("ru", ("ASTM G133-05", "Износ пластины", "пройдено циклов", "процедуры A ASTM G133")),
    ):
        html = unescape(report_html(done, lang))  # type: ignore[arg-type]
        for said in words:
            assert said in html, (lang, said)
        assert "Wear of the disc" not in html


def test_a_flat_test_as_procedure_a_is_said_to_follow_it() -> None:
    v = simulated(StandKind.RECIPROCATING).result.values
    assert isinstance(v, ReciprocatingResults)
    # G133 procedure A (as the code takes it, see G133's comment): 25 N, 10 mm stroke, 5 Hz,
    # 100 m, dry, a 9.525 mm ball; the record as planned
    config = ReciprocatingConfig(plan=PlannedTest(load=25.0, distance=100.0), tip_diameter=9.525e-3)
    as_run = v.model_copy(update={"mean_load": 25.0, "sliding_distance": 100.0})
    said = deviations(Messages("en"), config, as_run)
    assert said == ["The test on the flat follows the parameters of ASTM G133 procedure A."]
    # lubricated: procedure B's 200 N, 10 Hz, 400 m, 150 °C
    oiled = config.model_copy(update={"plan": PlannedTest(load=25.0, lubricant="PAO 4")})
    (apart,) = deviations(Messages("en"), oiled, as_run)
    assert apart.startswith("The test on the flat departs from ASTM G133 procedure B")
    assert "load 25 N instead of 200 N" in apart and "frequency 5 Hz instead of 10 Hz" in apart
    assert "temperature 23 °C instead of 150 °C" in apart  # the plan's room temperature
    assert "ball" not in apart  # B's ball is A's, 9.525 mm
    assert math.isclose(config.stroke_length, 0.01)


def test_a_run_that_differs_from_procedure_a_is_told_each_difference() -> None:
    v = simulated(StandKind.RECIPROCATING).result.values
    assert isinstance(v, ReciprocatingResults)
    # the stand's defaults: a 6 mm ball, 5 N, 5 Hz, a 10 mm stroke, 100 m, dry
    (apart,) = deviations(Messages("en"), ReciprocatingConfig(), v)[-1:]
    assert apart == (
        "The test on the flat departs from ASTM G133 procedure A: load 5 N instead of 25 N; "
        "ball 6 mm instead of 9.525 mm."
    )
    pin = ReciprocatingConfig(tip="flat_pin", plan=PlannedTest(load=25.0))
    (apart,) = deviations(Messages("ru"), pin, v)[-1:]
    assert apart == (
        "Испытание пластины отличается от процедуры A ASTM G133: "
        "палец с плоским торцом вместо шарика."
    )


def test_the_disc_report_says_its_parameters_are_its_own() -> None:
    # ASTM G99-17, 1.3 and 4.2: a test with parameters other than the interlaboratory
    # study's says so, and its results are not compared with the study's
    done = simulated(StandKind.PIN_ON_DISC)
    v = done.result.values
    assert isinstance(v, PinOnDiscResults)
    config = PinOnDiscConfig(plan=PlannedTest(distance=v.sliding_distance, load=v.mean_load))
    assert deviations(Messages("en"), config, v) == [
        "The test parameters (load, speed, distance, materials, environment) are this test's "
        "own, not those of the interlaboratory study of ASTM G99 (G99-17, 1.3 and 4.2): its "
        "results are not to be compared with that study's."
    ]
    html = unescape(report_html(done, "ru"))
    assert "не взяты из межлабораторного исследования ASTM G99" in html


def test_the_reciprocating_report_cites_g133_not_g99() -> None:
    # issue 38: the flat's report cited G99 (the pin-on-disc method) through the counter-
    # body's description, and so listed G99 among its abbreviations
    for lang in ("en", "ru"):
        text = unescape(report_html(simulated(StandKind.RECIPROCATING), lang))
        assert "G133" in text and "G99" not in text, lang
