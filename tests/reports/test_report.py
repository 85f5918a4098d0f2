"""Every stand's report, rendered from a simulated run: the manual's tables carry the numbers
the analysis computed (printed with four significant figures), the readings as posted, and
the plots as inline SVG; the Russian report carries the same numbers.

The expected numbers come from the analysis of the simulated readings (what the report
must print) or are computed here from the posted readings (raw tables, means, ratios).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from functools import lru_cache

import numpy as np
import pytest

from rigserver.analysis import analyse
from rigserver.reports.formatting import fmt, with_uncertainty
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.run_report import (
    build_report,
    configuration_rows,
    particulars_text,
    render_report,
)
from rigsim.simulators.smts2 import MODES
from schemas.labels import MTOS, PROFILOMETER, SLIDE_BEARING, Label
from schemas.results import MtosResults, ProfilometerResults, SlideBearingResults, Smts2Results
from schemas.runs import RunState
from schemas.stands import StandKind
from tests.reports.rendered import run_html
from tests.reports.simulated import MADE, HtmlTable, Simulated, simulated, table, tables


@lru_cache
def report(kind: StandKind, lang: Lang = "en") -> str:
    return run_html(kind, lang)


def printed(values: list[float] | list[float | None] | np.ndarray) -> list[str]:
    return [fmt(None if v is None else float(v)) for v in values]


def declared(label: Label, values: Sequence[float | None], factor: float = 1.0) -> list[str]:
    """The values as their label declares them: times ``factor`` (SI to the display unit),
    0 below its resolution, a column with one number of decimals at the label's digits."""
    shown = [None if v is None else v * factor for v in values]
    if label.unit == "%":  # a percentage to 0.1
        return [fmt(None) if x is None else f"{x:.1f}" for x in shown]
    return as_column(
        [None if x is None else 0.0 if abs(x) < label.resolution else x for x in shown],
        label.digits,
    )


def as_column(values: Sequence[float | None], digits: int = 4) -> list[str]:
    """A table's column as issue 37 (item 6) asks: the decimals of the value that shows the
    most at ``digits`` significant digits, at most two beyond the largest's own; below
    10⁻⁴ one power of ten for the column (written out here apart from schemas.digits)."""
    numbers = [abs(v) for v in values if v]
    if not numbers:
        return [fmt(v) for v in values]

    def decimals(x: float, n: int) -> int:
        text = f"{x:.{n}g}"
        if "e" in text:
            mantissa, exponent = text.split("e")
            return max(0, len(mantissa.partition(".")[2].rstrip("0")) - int(exponent))
        return len(text.partition(".")[2].rstrip("0"))

    largest = max(numbers)
    own = digits - 1 - math.floor(math.log10(float(f"{largest:.{digits}g}")))
    places = min(max(decimals(x, digits) for x in numbers), max(0, own) + 2)
    power = math.floor(math.log10(largest)) if largest < 1e-4 else 0
    out = []
    for v in values:
        if v is None:
            out.append(fmt(None))
            continue
        text = (
            f"{v / 10.0**power:.{places + power}f}".replace("-0.", "0.", 1)
            if v == 0
            else f"{v / 10.0**power:.{places + power}f}"
        )
        out.append(text + (f"·10{str(power).translate(SUPERSCRIPT)}" if power else ""))
    return out


SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def to_place_of(value: float, expanded: float) -> str:
    """``value`` rounded to the decimal place of the second significant digit of its
    expanded uncertainty (GUM 7.2.6)."""
    return f"{value:.{max(0, 1 - math.floor(math.log10(expanded)))}f}"


def row_of(html: str, caption: str, name: str) -> list[str]:
    """The cells after the first of the row whose first cell is ``name`` (its first line:
    the formula of an equation it cites first is under it)."""
    rows = [r for r in table(html, caption).rows if r[0].split("\n")[0] == name]
    assert len(rows) == 1, f"{len(rows)} rows named {name!r} under {caption!r}"
    return rows[0][1:]


def svgs(html: str) -> list[str]:
    parts = html.split("<svg")[1:]
    return [p[: p.index("</svg>")] for p in parts]


# --- lab work 1 ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("lang", "words"),
    [
        ("en", ("mode of measurement:", "profilograph", "vertical magnification", "horizontal")),
        ("ru", ("режим измерения:", "профилограф", "вертикальное увеличение", "горизонтальное")),
    ],
)
def test_profilometer_report_prints_the_mode_and_the_magnifications(
    lang: Lang, words: tuple[str, str, str, str]
) -> None:
    # lab 1's report names "the modes of measurement" and "the horizontal and vertical
    # magnification" (the manual's list of what the report contains); a run's own settings,
    # a nominal vertical magnification of the instrument's data (200 … 100 000)
    mode_row, mode, vertical, horizontal = words
    s = simulated(StandKind.PROFILOMETER)
    settings = {"mode": "profilograph", "vertical_magnification": 5000.0}
    run = s.run.model_copy(update={"configuration": {**s.run.configuration, **settings}})
    html = render_report(
        build_report(
            run=run,
            stand=s.stand,
            values=s.result.payload["values"],
            readings=s.readings,
            lang=lang,
            made=MADE,
        )
    )
    caption = "Stand configuration" if lang == "en" else "Конфигурация стенда"
    rows = table(html, caption).rows

    def value(start: str) -> list[str]:
        found = [r[1:] for r in rows if r[0].startswith(start)]
        assert len(found) == 1, f"{len(found)} rows named {start!r}"
        return found[0]

    assert value(mode_row) == [mode, ""]
    # a magnification is a number without a unit: dimensionless, "—" as in the results
    assert value(vertical) == ["5000", "—"]
    assert value(horizontal) == ["100", "—"]  # the default of the configuration


def test_profilometer_tables_1_6_to_1_8() -> None:
    s = simulated(StandKind.PROFILOMETER)
    v = s.result.values
    assert isinstance(v, ProfilometerResults) and v.fit_manual and v.fit_lsq
    html = report(StandKind.PROFILOMETER)
    t16 = table(html, "Table 1.6.")
    assert t16.rows[0][:1] == ["pi, µm"]  # depths in µm, not metres
    assert t16.rows[0][1:] == declared(PROFILOMETER["levels"], v.levels, 1e6)
    # η_p = t_p·l (table 1.6), recomputed here from t_p and the base length, in mm
    assert t16.rows[1][1:] == declared(
        PROFILOMETER["bearing_lengths"], [tp * (v.base_length or 0.0) for tp in v.tp], 1e6
    )
    assert t16.rows[2][1:] == declared(PROFILOMETER["tp"], v.tp)
    assert t16.rows[3][1:] == declared(PROFILOMETER["eps"], v.eps)
    manual = row_of(html, "Table 1.7.", "three pairs of levels (1.16)-(1.19)")
    assert manual == [
        *printed(v.fit_manual.nu_partial),
        fmt(v.fit_manual.nu),
        *printed(v.fit_manual.b_partial),
        fmt(v.fit_manual.b),
    ]
    lsq = row_of(html, "Table 1.7.", "least squares in log-log")
    assert lsq == ["—", "—", "—", fmt(v.fit_lsq.nu), "—", "—", "—", fmt(v.fit_lsq.b)]
    t18 = table(html, "Table 1.8.")
    eps = np.asarray(v.eps)
    # t_pт = b·ε^ν (1.8) recomputed here from the fitted b, ν and the levels' ε
    assert t18.rows[1][1:] == printed(v.fit_manual.b * eps**v.fit_manual.nu)
    assert t18.rows[2][1:] == printed(v.fit_manual.residuals)


def test_profilometer_parameters_with_instrument_errors() -> None:
    v = simulated(StandKind.PROFILOMETER).result.values
    assert isinstance(v, ProfilometerResults)
    html = report(StandKind.PROFILOMETER)
    caption = "Roughness parameters"
    # micrometres, to the digits declared (Ra three, its instrument error two)
    # Ra to the place of its expanded uncertainty (GUM 7.2.6)
    assert v.ra_expanded is not None
    assert row_of(html, caption, "arithmetic mean deviation (1.3)") == [
        "Ra",
        to_place_of(v.ra * 1e6, v.ra_expanded * 1e6),
        "µm",
        fmt(float(f"{v.ra_error * 1e6:.2g}")),
    ]
    assert row_of(html, caption, "ten-point height (1.4)")[1::2] == [
        fmt(float(f"{v.rz * 1e6:.3g}")),
        fmt(float(f"{v.rz_error * 1e6:.2g}")),
    ]
    assert row_of(html, "Complex roughness", "complex parameter (1.9)")[1] == fmt(
        v.complex_parameter
    )
    assert len(svgs(html)) == 3  # the profile, the bearing curve, the ISO filtering


def _number(cell: str) -> float:
    return float(cell.replace(",", ".").replace("−", "-"))


def test_profilometer_against_profilogram_and_the_subrange() -> None:
    """Item 10: the instrument's Ra, Rz, Rmax against the trace's, (1.20, E10) recomputed
    here, and again from the printed cells (the report is reproducible); the five peaks and
    valleys give the printed Rz; a parameter outside its subrange's range flagged."""
    s = simulated(StandKind.PROFILOMETER)
    v = s.result.values
    assert isinstance(v, ProfilometerResults) and v.rmax is not None and v.rz is not None
    m = s.sim.columns("measurements")
    rmax1, rz1 = float(m["rmax_instrument"][0]), float(m["rz_instrument"][0])
    rmax2, rz2 = v.rmax * 1e6, v.rz * 1e6
    assert v.rmax_difference == pytest.approx((rmax1 - rmax2) / rmax1 * 100, rel=1e-6, abs=1e-9)
    assert v.rz_difference == pytest.approx((rz1 - rz2) / rz1 * 100, rel=1e-6, abs=1e-9)
    html = report(StandKind.PROFILOMETER)
    vs = table(html, "Profilometer against profilogram")
    assert [r[0] for r in vs.rows] == ["Ra", "Rz", "Rmax"]
    assert vs.rows[2][1] == f"{rmax1:.3f}"
    for row in vs.rows:  # δ from the printed reading and profilogram, to δ's printed place
        one, two, delta = _number(row[1]), _number(row[2]), _number(row[4])
        assert abs((one - two) / one * 100 - delta) <= 0.006, row
    peaks = table(html, "The five highest peaks")
    cells = [(_number(r[1]), _number(r[2])) for r in peaks.rows[:5]]
    assert len(cells) == 5 and all(p > 0 > w for p, w in cells)
    rz = sum(p - w for p, w in cells) / 5  # (1.4) from the printed peaks and valleys
    assert peaks.rows[5][0] == f"Rz = {rz:.4f}"
    assert rz == pytest.approx(rz2, abs=1e-3)
    sm = v.sm or 0.0
    flagged = not 8e-6 <= sm <= 80e-6  # the 0.8 mm subrange's Sm range (technical data)
    assert ("Sm" in v.outside_subrange) == flagged
    assert ("outside the ranges of the subrange" in html) == bool(v.outside_subrange)


# --- lab work 2 ---------------------------------------------------------------------------


def test_smts2_wear_tables_and_validity() -> None:
    v = simulated(StandKind.SMTS2).result.values
    assert isinstance(v, Smts2Results) and v.experimental and v.theoretical and v.validity
    # the lab's steel is outside (2.1)'s range (docs/validity.md): no (2.15) verdict then
    assert not v.validity.within_range and v.adequacy is None
    html = report(StandKind.SMTS2)
    caption = "Experimental linear wear intensity"
    assert row_of(html, caption, "mass loss of the pin (2.9)") == [
        "Δm",
        fmt(float(f"{v.experimental.mass_loss * 1e6:.4g}")),  # kg -> mg
        "mg",
    ]
    assert row_of(html, caption, "experimental wear intensity (2.13)")[1] == fmt(
        v.experimental.intensity
    )
    theory = "Theoretical linear wear intensity"
    assert row_of(html, theory, "contour pressure (2.3)") == [
        "pc",
        fmt(float(f"{v.theoretical.contour_pressure / 1e6:.4g}")),  # Pa -> MPa
        "MPa",
    ]
    assert row_of(html, theory, "theoretical wear intensity (2.1)")[1] == fmt(
        v.theoretical.intensity
    )
    validity = "Validity of the fatigue-wear theory (2.1)"
    assert row_of(html, validity, "cycles to failure per asperity")[1] == fmt(
        v.validity.cycles_to_failure
    )
    assert row_of(html, validity, "theory within its range")[1] == "no"
    assert "outside its range" in html
    # the comparison the manual asks for, its verdict withheld where the theory fails
    assert row_of(html, "Theory against experiment", "model adequate (2.15)")[1] == (
        "not judged: the theory is outside its range"
    )
    k_shown = v.experimental.specific_wear_rate / 1e-9  # m³/(N·m) -> mm³/(N·m), its label's unit
    assert row_of(html, caption, "specific wear rate k = V/(F·L) (ASTM G99)")[1] == fmt(
        float(f"{k_shown:.4g}")
    )
    assert v.friction_steady is not None and v.friction_steady_expanded is not None
    assert row_of(html, "Friction record", "friction coefficient, steady part (2.8)")[1] == (
        to_place_of(v.friction_steady, v.friction_steady_expanded)
    )
    assert f"f = {with_uncertainty(v.friction_steady, v.friction_steady_expanded)}" in html


def test_smts2_measurements_as_posted() -> None:
    s = simulated(StandKind.SMTS2)
    posted = s.sim.columns("measurements")
    html = report(StandKind.SMTS2)
    row = row_of(html, "Single measurements", "m1, pin mass before the test (2.9)")
    # with the digits the balance gives: 0.1 mg = 10⁻⁴ g (Smts2Config.accuracy)
    assert row == [f"{float(posted['pin_mass_before'][-1]):.4f}", "g"]
    plots = svgs(html)
    assert len(plots) == 2 and all("<path" in p for p in plots)  # f(L), wear intensity


# --- lab work 3 ---------------------------------------------------------------------------


def test_slide_bearing_table_3_1_readings_beside_their_processing() -> None:
    s = simulated(StandKind.SLIDE_BEARING)
    v = s.result.values
    assert isinstance(v, SlideBearingResults)
    rows = s.sim.columns("rows")
    t31 = table(report(StandKind.SLIDE_BEARING), "Table 3.1.")
    assert t31.column(0)[:-1] == printed(rows["limb_angle"])
    assert t31.column(2)[:-1] == printed(rows["x"])
    assert t31.column(9)[:-1] == declared(SLIDE_BEARING["table[].chi"], [r.chi for r in v.table])
    assert t31.column(10)[:-1] == printed([r.phi_model for r in v.table])
    e_x = declared(SLIDE_BEARING["table[].e_x"], [r.e_x for r in v.table], 1e6)  # m -> µm
    assert t31.column(6)[:-1] == e_x and t31.header[6] == "ex, µm"
    mean = t31.rows[-1]
    assert mean[0] == "Mean"
    assert mean[4:6] == [fmt(float(np.mean(rows["t1"]))), fmt(float(np.mean(rows["t2"])))]
    assert mean[9] == fmt(v.chi_mean)


def test_slide_bearing_tables_3_2_and_3_3() -> None:
    v = simulated(StandKind.SLIDE_BEARING).result.values
    assert isinstance(v, SlideBearingResults)
    html = report(StandKind.SLIDE_BEARING)
    t32 = table(html, "Table 3.2.")
    axial = {k: SLIDE_BEARING[f"axial[].{k}"] for k in ("z", "pi_measured", "pi_short", "error")}
    assert t32.column(0) == declared(axial["z"], [p.z for p in v.axial])
    assert t32.column(2) == declared(axial["pi_measured"], [p.pi_measured for p in v.axial])
    assert t32.column(3) == declared(axial["pi_short"], [p.pi_short for p in v.axial])
    assert t32.column(5) == declared(axial["error"], [p.error for p in v.axial])
    t33 = table(html, "Table 3.3.")
    by_angle = sorted(v.table, key=lambda r: r.phi_model)
    names = ("phi_model", "pi_short", "pi_long", "pi_finite", "pi_measured")
    names += ("error_short", "error_long")
    columns = [
        declared(SLIDE_BEARING[f"table[].{n}"], [getattr(r, n) for r in by_angle]) for n in names
    ]
    assert t33.rows == [list(row) for row in zip(*columns, strict=True)]
    assert len(svgs(html)) == 2  # Π(φ), Π(z)


# --- lab work 4 ---------------------------------------------------------------------------


def test_mtos_readings_and_processing_tables() -> None:
    s = simulated(StandKind.MTOS)
    v = s.result.values
    assert isinstance(v, MtosResults)
    html = report(StandKind.MTOS)
    steps = s.sim.columns("steps")
    fluid = steps["regime"] == 1
    t41 = table(html, "Table 4.1.")
    assert t41.column(0) == printed(steps["load"][fluid])
    assert t41.column(1) == printed(steps["indicator"][fluid])
    assert t41.column(8) == printed(steps["t5"][fluid])
    t44 = [t for t in tables(html) if t.caption.startswith("Table 4.4. Processing")]
    # the table and its continuation in three parts by the page's width; the theory follows
    # in two: one printed table in five numbered parts
    assert [t.caption[-13:] for t in t44] == [f"(part {n} of 5)" for n in (1, 2, 3)]
    processing = joined(t44)
    first = [x for x in v.steps if x.regime == "fluid"]
    assert processing.column(4) == declared(MTOS["steps[].chi"], [x.chi for x in first])
    assert processing.column(9) == as_column([x.friction_measured for x in first])
    mu1 = MTOS["steps[].viscosity_at"]
    assert processing.column(10) == declared(mu1, [x.viscosity_at["t1"] for x in first])
    assert processing.column(16) == as_column([x.bearing_characteristic for x in first])
    parts = [t for t in tables(html) if t.caption.startswith("Table 4.4. Theory")]
    assert [t.caption[-13:] for t in parts] == ["(part 4 of 5)", "(part 5 of 5)"]
    theory = joined(parts)
    assert theory.header[1:10] == [
        "μt/μ0", "A100", "A200", "A300", "A302", "A320", "A311", "V", "Pτ, N"
    ]  # fmt: skip
    assert theory.column(8) == as_column([x.v_factor for x in first])
    assert theory.column(11) == as_column([x.friction_theory for x in first])
    error = MTOS["steps[].friction_error"]
    assert theory.column(12) == declared(error, [x.friction_error for x in first])


def joined(parts: list[HtmlTable]) -> HtmlTable:
    """The parts of a table printed in parts as one table, the key columns each part
    repeats (the leading header cells they share) once."""
    whole = HtmlTable(parts[0].caption, list(parts[0].header), [list(r) for r in parts[0].rows])
    for part in parts[1:]:
        keys = next(
            i for i, (a, b) in enumerate(zip(whole.header, part.header, strict=False)) if a != b
        )
        whole.header += part.header[keys:]
        for row, more in zip(whole.rows, part.rows, strict=True):
            row += more[keys:]
    return whole


PART = re.compile(r"\((?:part|часть) (\d+) (?:of|из) (\d+)\)$")


def whole_tables(html: str) -> list[HtmlTable]:
    """The report's tables, each printed in parts joined (:func:`joined`)."""
    found: list[HtmlTable] = []
    parts: list[HtmlTable] = []
    for one in tables(html):
        numbered = PART.search(one.caption)
        if numbered is None:
            found.append(one)
            continue
        parts.append(one)
        if numbered[1] == numbered[2]:
            found.append(joined(parts))
            parts = []
    return found


def test_mtos_mixed_friction_against_fluid_friction() -> None:
    v = simulated(StandKind.MTOS).result.values
    assert isinstance(v, MtosResults)
    html = report(StandKind.MTOS)
    fluid = {x.load: x.friction_measured for x in v.steps if x.regime == "fluid"}
    mixed = [x for x in v.steps if x.regime == "mixed"]
    continued = [t for t in tables(html) if t.caption.startswith("Table 4.5.")][-1]
    # f_э/f_э1 at the same load, divided here
    ratios = [x.friction_measured / fluid[x.load] for x in mixed]
    assert continued.column(-1) == as_column(ratios)  # one number of decimals in the column
    assert len(svgs(html)) == 4  # Hersey-Stribeck, trajectory, f(N), Δt(N)


# --- all stands -----------------------------------------------------------------------------


@pytest.mark.parametrize("kind", list(StandKind))
def test_the_russian_report_prints_the_same_numbers(kind: StandKind) -> None:
    en, ru = report(kind, "en"), report(kind, "ru")
    assert '<html lang="ru">' in ru
    lab_work = simulated(kind).stand.lab_work
    if lab_work is None:  # a commercial tribometer: no lab work, the test's title
        assert "Лабораторная работа" not in ru and "<h1>Трение и изнашивание" in ru
    else:
        assert f"Лабораторная работа № {lab_work}." in ru
    assert "Исходные данные" in ru and "Input data" not in ru
    english, russian = whole_tables(en), whole_tables(ru)
    assert len(english) == len(russian)
    for a, b in zip(english, russian, strict=True):
        # the same numbers, with a decimal comma in Russian
        numbers = [[c for c in row if c[:1].isdigit() or c[:1] == "-"] for row in a.rows]
        commas = [[c.replace(".", ",") for c in row] for row in numbers]
        assert commas == [[c for c in row if c[:1].isdigit() or c[:1] == "-"] for row in b.rows]
        assert not any("." in c for row in b.rows for c in row if c[:1].isdigit())


@pytest.mark.parametrize("kind", list(StandKind))
def test_an_open_run_without_readings_says_what_is_missing(kind: StandKind) -> None:
    s = simulated(kind)
    empty = EmptyReadings()
    run = s.run.model_copy(update={"state": RunState.OPEN, "rows": {}, "ended": None})
    values = analyse(run, empty).payload["values"]
    html = render_report(
        build_report(run=run, stand=s.stand, values=values, readings=empty, lang="en", made=MADE)
    )
    assert "The run is still open" in html
    for missing in values["pending"]:  # what the analysis says it still needs
        assert f"<li>{missing}</li>" in html
    assert ("Not computed yet" in html) == bool(values["pending"])


class EmptyReadings:
    def rows(self, group: str) -> int:
        return 0

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, np.ndarray]:
        return {}

    def iter_chunks(self, group: str, channels: list[str] | None = None, rows: int = 1 << 20):  # type: ignore[no-untyped-def]
        return iter(())

    def measurements(self) -> dict[str, float]:
        return {}


def test_input_data_print_the_configuration_with_units() -> None:
    s: Simulated = simulated(StandKind.SLIDE_BEARING)
    html = report(StandKind.SLIDE_BEARING)
    config = table(html, "Stand configuration of this run")
    rows = {r[0].split("\n")[0]: r[1:] for r in config.rows}  # the names, not the formulas
    # in the display unit of the results (µm for clearances, schemas.labels.CONFIGURATION)
    clearance_um = s.run.configuration["clearance"] * 1e6
    assert rows["h0, radial clearance (3.17)"] == [fmt(clearance_um), "µm"]
    assert [v[1] for k, v in rows.items() if k.startswith("B, bearing width")] == ["mm"]
    assert rows["α of the oil's viscosity μ = A·exp(α·t)"] == [
        fmt(s.run.configuration["viscosity"]["alpha"]),
        "1/°C",
    ]


@pytest.mark.parametrize("kind", list(StandKind))
def test_the_russian_report_has_no_tex_and_no_english(kind: StandKind) -> None:
    html = re.sub(r"<(svg|style)\b.*?</\1>", "", report(kind, "ru"), flags=re.S)
    text = re.sub(r"<[^>]+>", " ", html)
    assert not re.findall(r"\S*[_^{}]\S*", text)  # h_min^кр, Δ^(1/2) print as scripts or √
    run = simulated(kind).run
    typed = " ".join([run.operator, run.title or "", *map(str, run.specimen.values())])
    typed += " " + " ".join(str(v) for v in run.test_plan.values())
    words = set(re.findall(r"\b[A-Za-z]{3,}\b", text)) - set(re.findall(r"[A-Za-z]+", typed))
    # the names of standards and methods stay as they are: ASTM G99, ISO 20808, GUM (JCGM 100),
    # PELT
    names = {"ASTM", "GUM", "JCGM", "ISO", "PELT"}
    maths = {
        "exp",
        "sin",
        "cos",
        "arctg",
    }  # the functions of the formulas printed beside the quantities
    assert words <= {"Rmax", "max", "min", "rev", "pmax", "rig", "UTC", *maths, *names}, words


def test_headline_results_carry_their_expanded_uncertainty() -> None:
    # "0.401 ± 0.012 (k = 2)": the value and U = 2u (GUM) of each headline result
    v = simulated(StandKind.SMTS2).result.values
    assert isinstance(v, Smts2Results) and v.experimental is not None
    html = report(StandKind.SMTS2)
    caption = "Measurement uncertainty (GUM)"
    shown = row_of(html, caption, "friction coefficient, steady part (2.8)")[1]
    assert shown == with_uncertainty(v.friction_steady, v.friction_steady_expanded)
    assert shown.endswith("(k = 2)") and " ± " in shown
    k = row_of(html, caption, "specific wear rate k = V/(F·L) (ASTM G99)")[1]
    to_mm3 = 1e9  # m³/(N·m) -> mm³/(N·m), the display unit of k's label
    assert k == with_uncertainty(
        v.experimental.specific_wear_rate * to_mm3,
        v.experimental.specific_wear_rate_expanded * to_mm3,
    )
    m = simulated(StandKind.MTOS).result.values
    assert isinstance(m, MtosResults)
    first = m.steps[0]
    mtos = report(StandKind.MTOS)
    label = f"friction coefficient (4.16), step 1, N = {fmt(first.load)} N"
    assert row_of(mtos, caption, label)[1] == with_uncertainty(
        first.friction_measured, first.friction_measured_expanded
    )
    assert "Regime by Λ" in mtos


def test_with_uncertainty_rounds_to_two_figures_of_u() -> None:
    assert with_uncertainty(0.40123, 0.0118) == "0.401 ± 0.012 (k = 2)"
    assert with_uncertainty(3.833e-8, 9.5e-10) == "(3.833 ± 0.095)·10⁻⁸ (k = 2)"
    assert with_uncertainty(0.4, None) == "0.4"


@pytest.mark.parametrize("kind", [StandKind.PIN_ON_DISC, StandKind.RECIPROCATING])
def test_the_rows_stored_are_printed_whole(kind: StandKind) -> None:
    """Tens of thousands of rows: the count as stored (64001), not rounded (6.4·10⁴)."""
    s = simulated(kind)
    html = report(kind)
    assert max(s.run.rows.values()) >= 10_000  # more digits than fmt's four
    for rows in s.run.rows.values():
        assert f": {rows}" in html


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_the_moment_sensor_error_is_the_manuals_five_percent(lang: Lang) -> None:
    # the manual's SMTs-2 data: "допускаемая погрешность измерения момента трения ... ±5 %",
    # printed in % as the description says it (it was 0.05 with the unit "—")
    config = next(t for t in tables(report(StandKind.SMTS2, lang)) if len(t.header) == 3)
    moment = ("friction", "момент")
    (row,) = [r for r in config.rows if "±5 %" in r[0] and r[0].startswith(moment)]
    assert row[1:] == ["5", "%"]


@pytest.mark.parametrize("kind", [StandKind.PIN_ON_DISC, StandKind.RECIPROCATING])
@pytest.mark.parametrize("lang", ["en", "ru"])
def test_a_ball_is_named_a_ball_not_a_pin(kind: StandKind, lang: Lang) -> None:
    # the ball's properties were printed as the SMTs-2's "образец (стержень)" (its pin)
    s = simulated(kind)
    assert s.run.configuration["tip"] == "ball"
    config = next(t for t in tables(report(kind, lang)) if len(t.header) == 3)
    names = [row[0] for row in config.rows]
    ball, pin = {"en": ("ball: ", "pin: "), "ru": ("шарик: ", "образец (стержень): ")}[lang]
    assert sum(name.startswith(ball) for name in names) == len(s.run.configuration["pin"])
    assert not [name for name in names if name.startswith(pin)]
    flat_pin = s.run.model_copy(
        update={"configuration": {**s.run.configuration, "tip": "flat_pin"}}
    )
    rows = configuration_rows(Messages(lang), flat_pin)
    assert sum(str(row.words).startswith(pin) for row in rows) == len(s.run.configuration["pin"])
    # the tip printed in words, not as the code word "flat_pin"
    tip = {"en": "flat-ended pin", "ru": "палец с плоским торцом"}[lang]
    assert tip in [row.value for row in rows]


@pytest.mark.parametrize("mode", MODES)
def test_every_mode_of_the_smts2_is_translated(mode: str) -> None:
    # "режим: adhesive" was printed while "wear" read "износ"
    shown = particulars_text(Messages("ru"), {"mode": mode})
    assert shown.startswith("режим: ") and re.fullmatch(r"[а-яё ]+", shown.partition(": ")[2])
