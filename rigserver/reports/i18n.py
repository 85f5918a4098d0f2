"""Languages of the reports and pages: gettext catalogs read with Babel.

The English texts are the message ids; every other language is a catalog,
``rigserver/locale/<lang>/LC_MESSAGES/messages.po``, compiled when first used (Babel's
``read_po``/``write_mo``). Python code names its texts by key (:data:`MESSAGES`, each marked
with ``N_`` so that Babel's extraction finds it); templates call ``_()`` through Jinja2's
i18n extension. :func:`negotiate` picks the language from ``?lang=`` or ``Accept-Language``
with Babel's locale negotiation.
"""

from __future__ import annotations

import gettext
import io
import re
from functools import lru_cache
from importlib import resources
from typing import Literal, get_args

from babel.core import negotiate_locale
from babel.messages.mofile import write_mo
from babel.messages.pofile import read_po

from schemas.messages import C_, N_
from schemas.stands import DECLARATIONS

Lang = Literal["en", "ru"]
LANGS: tuple[Lang, ...] = get_args(Lang)
DEFAULT: Lang = "en"
DOMAIN = "messages"
_STEP = re.compile(r"([^_{}]+)_\{([^,{}]+),(\d+)\}")
UNIT_CONTEXT = "unit"
"""The message context of unit symbols (``s`` the unit is not ``s`` the word)."""
SYMBOL_CONTEXT = "symbol"
"""The message context of the quantities' symbols: written in English (``f_e``, ``χ_mean``,
``I_{h,exp}``), each language's catalog gives its own (``f_э``, ``χ_ср``, ``I_{h,э}``)."""


def language_headers(lang: str) -> dict[str, str]:
    """The headers of an answer in ``lang`` chosen by :func:`negotiate`: its language, and
    that it varies with ``Accept-Language`` (for caches)."""
    return {"Content-Language": lang, "Vary": "Accept-Language"}


def negotiate(requested: str | None, accept_language: str | None) -> Lang:
    """The language: ``requested`` if given, else the best of ``Accept-Language``.

    ``Accept-Language: ru-RU,ru;q=0.9,en;q=0.8`` gives ``"ru"``; a header naming no
    supported language (or none) gives English. ``requested`` must be a supported code
    (the routes check it).
    """
    if requested is not None:
        if requested not in LANGS:
            raise ValueError(f"lang must be one of {', '.join(LANGS)}, got {requested!r}")
        return requested
    ranked: list[tuple[float, int, str]] = []
    for position, item in enumerate((accept_language or "").split(",")):
        tag, _, params = item.strip().partition(";")
        quality = 1.0
        for param in params.split(";"):
            name, _, value = param.strip().partition("=")
            if name == "q":
                try:
                    quality = float(value)
                except ValueError:
                    quality = 0.0
        if quality > 0 and tag.strip():
            ranked.append((-quality, position, tag.strip()))
    preferred = [tag for _, _, tag in sorted(ranked)]
    for tag in preferred:  # each tag in turn, ru-RU matching ru
        found = negotiate_locale([tag, tag.split("-")[0]], list(LANGS), sep="-")
        if found is not None:
            return found  # type: ignore[return-value]
    return DEFAULT


@lru_cache
def translations(lang: str) -> gettext.NullTranslations:
    """The compiled catalog of ``lang`` (English: the message ids themselves)."""
    po = resources.files("rigserver") / "locale" / lang / "LC_MESSAGES" / f"{DOMAIN}.po"
    if not po.is_file():
        return gettext.NullTranslations()
    with po.open("rb") as source:
        catalog = read_po(source, locale=lang, domain=DOMAIN)
    compiled = io.BytesIO()
    write_mo(compiled, catalog)
    compiled.seek(0)
    return gettext.GNUTranslations(compiled)


class Messages:
    """The texts of one language: ``t("sec.input")``, ``t("lab_work", n=2)``, ``t.unit("Pa")``,
    ``t.gettext(label.text)`` for the declared labels."""

    def __init__(self, lang: Lang) -> None:
        self.lang = lang
        self.translations = translations(lang)

    def __call__(self, key: str, **values: object) -> str:
        return self.gettext(MESSAGES[key]).format(**values)

    def gettext(self, text: str) -> str:
        """``text`` (a message id: an English text of the code or the schemas) translated."""
        return self.translations.gettext(text) if text else text

    def plural(self, singular: str, plural: str, n: int) -> str:
        """``singular`` or ``plural`` (message ids) for a count of ``n``, in this language's
        plural forms (Russian has three: 1 строка, 2 строки, 5 строк)."""
        return self.translations.ngettext(singular, plural, n)

    def plural_forms(self, singular: str, plural: str) -> dict[str, str]:
        """The forms of a count's words by CLDR plural category (``one``, ``few``, ``many``,
        ``other``), for a page whose script counts (``Intl.PluralRules``)."""
        return {category: self.plural(singular, plural, n) for category, n in _CATEGORY_N}

    def symbol(self, symbol: str) -> str:
        """A quantity's symbol in this language (``f_e`` -> ``f_э``); a symbol without a
        translation is the same in every language (``N``, ``e_x``)."""
        if not symbol:
            return symbol
        found = self.translations.pgettext(SYMBOL_CONTEXT, symbol)
        step = _STEP.fullmatch(symbol)
        if found == symbol and step:  # f_{e,3}: the symbol f_e of load step 3
            base = self.translations.pgettext(SYMBOL_CONTEXT, f"{step[1]}_{step[2]}")
            head, _, script = base.partition("_")
            return f"{head}_{{{script.strip('{}')},{step[3]}}}"
        return found

    def unit(self, symbol: str) -> str:
        """A unit as printed: ``Pa*s`` -> ``Pa·s`` (``Па·с``); dimensionless -> ``—``."""
        return self.translations.pgettext(UNIT_CONTEXT, UNIT_LABELS[symbol])


#: A whole number of each CLDR plural category of English and Russian (``other`` is what a
#: count of 5 reads in English, of 1.5 in Russian: its whole numbers are one, few or many).
_CATEGORY_N = (("one", 1), ("few", 2), ("many", 5), ("other", 5))

UNIT_LABELS: dict[str, str] = {
    "1": C_("unit", "—"),
    "s": C_("unit", "s"),
    "min": C_("unit", "min"),
    "N": C_("unit", "N"),
    "N*m": C_("unit", "N·m"),
    "kg": C_("unit", "kg"),
    "g": C_("unit", "g"),
    "mg": C_("unit", "mg"),
    "m": C_("unit", "m"),
    "mm": C_("unit", "mm"),
    "um": C_("unit", "µm"),
    "rad": C_("unit", "rad"),
    "deg": C_("unit", "°"),
    "rev": C_("unit", "rev"),
    "100 rev": C_("unit", "100 rev"),
    "rpm": C_("unit", "rpm"),
    "rad/s": C_("unit", "rad/s"),
    "Pa": C_("unit", "Pa"),
    "MPa": C_("unit", "MPa"),
    "at": C_("unit", "at"),
    "atm": C_("unit", "atm"),
    "Pa*s": C_("unit", "Pa·s"),
    "degC": C_("unit", "°C"),
    "1/degC": C_("unit", "1/°C"),
    "kg/m^3": C_("unit", "kg/m³"),
    "N/mm": C_("unit", "N/mm"),
    "N/m": C_("unit", "N/m"),
    "m^2": C_("unit", "m²"),
    "mm^2": C_("unit", "mm²"),
    "m^3": C_("unit", "m³"),
    "mm^3": C_("unit", "mm³"),
    "m^2/N": C_("unit", "m³/(N·m)"),
    "mm^3/(N*m)": C_("unit", "mm³/(N·m)"),
    "1/m": C_("unit", "1/m"),
    "m/N": C_("unit", "m/N"),
    "m/N^(2/3)": C_("unit", "m/N^(2/3)"),
    "N*m/rad": C_("unit", "N·m/rad"),
    "N*m*s/rad": C_("unit", "N·m·s/rad"),
    "drops/min": C_("unit", "drops/min"),
    "div": C_("unit", "div"),
    "code": C_("unit", "code"),
    "%": C_("unit", "%"),
    "Hz": C_("unit", "Hz"),
    "m/s": C_("unit", "m/s"),
    "GPa": C_("unit", "GPa"),
}
"""Every unit symbol of :mod:`schemas.units` as printed in English (message ids in the
context ``unit``)."""

MESSAGES: dict[str, str] = {
    **{f"stand.{kind.value}": declared.name for kind, declared in DECLARATIONS.items()},
    **{f"title.{kind.value}": declared.work for kind, declared in DECLARATIONS.items()},
    **{f"aim.{kind.value}": declared.aim for kind, declared in DECLARATIONS.items()},
    "lab_work": N_("Lab work {n}"),
    "report": N_("Report"),
    "aim": N_("Aim"),
    "run": N_("Run"),
    "stand": N_("Stand"),
    "state": N_("State"),
    "operator": N_("Operator"),
    "run_title": N_("Title"),
    "specimen": N_("Specimen"),
    "test_plan": N_("Test plan"),
    "created": N_("Started"),
    "ended": N_("Ended"),
    "rows": N_("Rows stored"),
    "notes": N_("Notes"),
    "group": N_("Group"),
    "students": N_("Students"),
    "state.open": N_("open"),
    "state.finished": N_("finished"),
    "state.aborted": N_("aborted"),
    "open_warning": N_(
        "The run is still open: the results are computed on the readings received so far."
    ),
    "footer": N_("Made by rig from run {run} at {time} UTC."),
    "sec.input": N_("Input data"),
    "sec.measured": N_("Results of the measurements"),
    "sec.processed": N_("Processing and theory"),
    "sec.plots": N_("Plots"),
    "sec.computed": N_("Computed results"),
    "table_number": N_("Table {n}"),
    "sec.pending": N_("Not computed yet"),
    "sec.notes": N_("Notes of the analysis"),
    "sec.corrections": N_("Corrections"),
    "corr.caption": N_(
        "Corrections of the readings, {group}: the tables and results above use the "
        "corrected values; the values as typed are kept in the run's file"
    ),
    "corr.after_finish": N_("The readings were corrected after the run was finished."),
    "corrected_after_finish": N_("corrected after it was finished"),
    "corr.row": N_("Row"),
    "corr.was": N_("Was"),
    "corr.now": N_("Now"),
    "corr.reason": N_("Reason"),
    "corr.by": N_("Who, when"),
    "corr.struck": N_("row struck out"),
    "caption.configuration": N_(
        "Stand configuration of this run: calibration, geometry, materials"
    ),
    "caption.measurements": N_("Single measurements"),
    "table.part": N_("{caption} (part {part} of {parts})"),
    "sec.abbreviations": N_("Abbreviations and corrections to the printed formulas"),
    "abbr.gum": N_(
        "GUM: the Guide to the expression of uncertainty in measurement (JCGM 100:2008): "
        "u is the standard uncertainty, U = 2u the expanded one (k = 2, about 95 %)."
    ),
    "abbr.g99": N_(
        "ASTM G99: the standard test method for wear testing with a pin-on-disc apparatus; its "
        "specific wear rate is k = V/(F·L)."
    ),
    "abbr.e1": N_(
        "E1 (2.2): C = 0.118/(1 + t/2), not 0.118·(1 + t/2) as printed: the general C of (2.1) "
        "at ν = 2."
    ),
    "abbr.e2": N_(
        "E2 (2.6): Δ = 5.4·10⁻²·Ra² (Ra in µm), the inverse of (1.10); the print drops the square."
    ),
    "abbr.e3": N_(
        "E3 (3.5, 3.24, 4.8, 4.20): a = B/(2R) = B/D, not B/(4R): only this half-width gives "
        "the short-bearing load of (3.12)."
    ),
    "abbr.e4": N_(
        "E4 (4.19): the temperature rise is Δt_i = t_i - t_1; the print has t_1 - t_i, "
        "negative for oil that warms."
    ),
    "abbr.e5": N_(
        "E5 (1.1): R = √(π/2)/ρ_2, ρ_2 the rms curvature of the profile; the print puts the "
        "whole product under the root, which is not a length."
    ),
    "abbr.e6": N_(
        "E6 (the article, (9)): ∂F/∂q = (1 - φ²)^{{-1/2}}·∂φ/∂q, a product (F = arcsin φ); "
        "the print has a sum."
    ),
    "abbr.e7": N_(
        "E7 (the article, (5)): the left side of the second definition is γ_{{mlk}}, not λ_{{mlk}}."
    ),
    "abbr.e8": N_(
        "E8 (the article, the final system): the velocity term multiplies ξ'_l, as in (6)."
    ),
    "mech.title": N_("Dynamic errors of the lever mechanism"),
    "mech.article": N_("Estimation of dynamic errors of a lever mechanism"),
    "mech.move": N_(
        "Three-link arm with two ball-screw drives, as in the article «{article}»; move from "
        "q = ({start}) {rad} to q = ({end}) {rad} in {duration} {s}, {profile} velocity "
        "profile; solver {method} ({evaluations} evaluations of the right-hand side)."
    ),
    "mech.failed": N_("The solver failed: {message}"),
    "mech.trapezoidal": N_("trapezoidal"),
    "mech.quintic": N_("quintic"),
    "mech.programme": N_("Programmed motion"),
    "mech.errors": N_("Dynamic errors"),
    "mech.shoulder": N_("shoulder q1"),
    "mech.forearm": N_("forearm q2"),
    "mech.gripper": N_("gripper q3"),
    "mech.joint": N_("Joint"),
    "mech.arcmin": N_("arcmin"),
    "mech.corrections": N_("Corrections to the article's printed formulas"),
    "abbr.e9": N_(
        "E9 (4.21): the manual calls both μω/p̄ and p̄/(μω) S_1; the report uses "
        "S_1 = μ_t·ω/p̄ as (4.21) does, and plots f against its inverse S_1^{{-1}} = p̄/(μ_t·ω) "
        "as fig. 4.1 does."
    ),
    "abbr.e10": N_(
        "E10 (1.20): the manual divides δ by the profilometer's R_max1 but δ_Rz by the "
        "profilogram's R_z2; the report divides each difference, δ_Ra too, by the "
        "profilometer's reading."
    ),
    "theory_outside": N_("theory outside its range"),
    "col.parameter": N_("Parameter"),
    "col.description": N_("Description"),
    "col.quantity": N_("Quantity"),
    "col.symbol": N_("Symbol"),
    "col.value": N_("Value"),
    "col.unit": N_("Unit"),
    "col.channel": N_("Channel"),
    "col.instrument_error": N_("Instrument error (1.14)"),
    "col.method": N_("Method"),
    "col.level": N_("Level"),
    "col.regime": N_("Regime"),
    "col.film": N_("Film against h_{{min,cr}}"),
    "mean": N_("Mean"),
    "sym.i_exp": N_("I_{{h,exp}}"),
    "sym.i_theor": N_("I_{{h,th}}"),
    "yes": N_("yes"),
    "no": N_("no"),
    "config.default": N_("not given: the stand's default ({value})"),
    "config.table": N_("{value}, the materials table's"),
    "col.given_by": N_("Given by"),
    "given.file": N_("the file and its map"),
    "given.operator": N_("the operator"),
    "given.table": N_("the materials table, for the material the specimen names"),
    "given.default": N_("not given: the stand's default"),
    "given.unrecorded": N_("not recorded (a run opened before rig kept it)"),
    "regime.fluid": N_("fluid film"),
    "regime.mixed": N_("mixed"),
    "regime.boundary": N_("boundary"),
    "contact.elastic": N_("elastic"),
    "contact.plastic": N_("plastic"),
    "page.shown": N_("{first}–{last} of {total}"),
    "page.connecting": N_("connecting…"),
    "page.streaming": N_("live"),
    "page.reconnecting": N_("connection lost, reconnecting…"),
    "page.ended": N_("run ended"),
    "p.params": N_("Roughness parameters over the base length (1.1)-(1.4)"),
    "p.base_length": N_("base length"),
    "p.ra": N_("arithmetic mean deviation (1.3)"),
    "p.rq": N_("root-mean-square deviation"),
    "p.rz": N_("ten-point height (1.4)"),
    "p.rmax": N_("peak line to valley line"),
    "p.sm": N_("mean spacing of profile elements"),
    "p.r": N_("mean asperity radius (1.1, E5)"),
    "p.table_1_6": N_(
        "Table 1.6. Bearing length of the profile at the levels p_i below the peak line (1.5), "
        "(1.6), (1.7)"
    ),
    "p.table_1_7": N_(
        "Table 1.7. Coefficients ν and b of t_p = b·ε^ν (1.16), (1.17), (1.18), (1.19)"
    ),
    "p.table_1_8": N_("Table 1.8. Measured t_{{p,e}} against t_{{p,t}} = b·ε^ν (manual method)"),
    "p.manual": N_("three pairs of levels (1.16)-(1.19)"),
    "p.lsq": N_("least squares in log-log"),
    "p.complex": N_("Complex roughness parameter (1.9)-(1.11)"),
    "p.delta": N_("complex parameter (1.9)"),
    "p.ra_delta": N_("Ra from Δ (1.10)"),
    "p.delta_t": N_("equilibrium complex parameter (1.11)"),
    "p.fig_profile": N_("Profile with the mean line, the peak line and the valley line"),
    "p.fig_bearing": N_(
        "Initial part of the bearing curve and the fits t_p = b·ε^ν (1.8), as in fig. 1.5"
    ),
    "p.profile": N_("profile"),
    "p.mean_line": N_("mean line"),
    "p.peak_line": N_("peak line"),
    "p.valley_line": N_("valley line"),
    "p.levels": N_("levels p_i of table 1.6"),
    "p.vs": N_("Profilometer against profilogram (item 10, (1.20, E10))"),
    "p.vs_source": N_(
        "The profilometer's R_a, R_z, R_max: its readings typed in from its display "
        "(procedure item 1), in the run's single measurements; the profilogram's: computed "
        "from the trace as (1.3), (1.4). The ISO 21920-2 values further on are rig's own, from "
        "the filtered trace, and are not the instrument's reading. δ is relative to the "
        "reading (E10)."
    ),
    "p.peaks": N_("The five highest peaks and the five deepest valleys behind R_z (1.4)"),
    "p.instrument": N_("profilometer"),
    "p.profilogram": N_("profilogram"),
    "p.difference": N_("difference"),
    "p.outside": N_(
        "{names} outside the ranges of the subrange of l = {cutoff} mm (Ra {ra}, Rz and Rmax "
        "{rz}, Sm {sm} µm): the error limits (1.14) are not stated for them."
    ),
    "p.measured": N_("measured"),
    "p.c_ra": N_(
        "Ra = {ra} µm measured; Ra = 4.3·√Δ = {ra_delta} µm from the complex parameter "
        "(1.10), {diff} % apart."
    ),
    "p.c_delta": N_(
        "Δ = {delta} from the profile against Δ_T = {delta_t} for the equilibrium roughness "
        "(1.11): {diff} % apart."
    ),
    "p.c_fit": N_(
        "t_p = b·ε^ν: ν = {nu}, b = {b} by three pairs of levels, ν = {nu_lsq}, b = {b_lsq} "
        "by least squares; the largest |Δt_p| is {residual}."
    ),
    "w.record": N_("Friction record"),
    "w.rows": N_("rows analysed"),
    "w.duration": N_("duration"),
    "w.revolutions": N_("disc revolutions"),
    "w.sliding": N_("sliding distance (2.12)"),
    "w.load": N_("mean load, steady part"),
    "w.f": N_("friction coefficient, steady part (2.8)"),
    "w.f_std": N_("its standard deviation"),
    "w.moment": N_("friction moment, steady part, M_fr = f·N·r_2 (2.8)"),
    "w.steady_from": N_("steady part from"),
    "w.experimental": N_("Experimental linear wear intensity (2.9)-(2.13)"),
    "w.mass_loss": N_("mass loss of the pin (2.9)"),
    "w.volume": N_("worn volume (2.10)"),
    "w.depth": N_("linear wear (2.11)"),
    "w.intensity_exp": N_("experimental wear intensity (2.13)"),
    "w.theoretical": N_("Theoretical linear wear intensity, fatigue wear (2.1)-(2.7)"),
    "w.contact": N_("contact mode (2.7)"),
    "w.fatigue_t": N_("fatigue parameter t"),
    "w.pc": N_("contour pressure (2.3)"),
    "w.aa": N_("nominal area (2.5)"),
    "w.ac": N_("contour area (2.4)"),
    "w.eta_c": N_("ratio of the contour to the nominal area"),
    "w.delta": N_("complex parameter of the disc (2.6, E2)"),
    "w.rmax_r": N_("ratio of the peak height to the radius"),
    "w.C": N_("C of (2.1), (2.2, E1)"),
    "w.beta": N_("β = 1/(1 + 2ν)"),
    "w.k_nu": N_("k_ν of (2.1)"),
    "w.k_f": N_("k_f of the contact mode"),
    "w.intensity_theor": N_("theoretical wear intensity (2.1)"),
    "w.adequacy": N_("Theory against experiment (2.14)-(2.15)"),
    "w.error": N_("relative difference (2.14)"),
    "w.lower": N_("lower bound 0.4·I_{{h,th}} (2.15)"),
    "w.upper": N_("upper bound 2.6·I_{{h,th}} (2.15)"),
    "w.adequate": N_("model adequate (2.15)"),
    "w.not_judged": N_("not judged: the theory is outside its range"),
    "w.fig_friction": N_(
        "Friction coefficient against the sliding distance; the running-in part is shaded"
    ),
    "w.fig_wear": N_(
        "Experimental and theoretical wear intensity with the band (2.15) about the theory, "
        "pale: the theory is outside its range for this test and is not judged"
    ),
    "w.fig_wear_band": N_(
        "Experimental and theoretical wear intensity with the adequacy band (2.15)"
    ),
    "w.source": N_("source of the value"),
    "w.out_of_range": N_("(outside its range)"),
    "w.running_in": N_("running-in (not averaged): the record's first {share} %"),
    "w.steady_mean": N_("steady mean"),
    "w.envelope": N_("min-max per block"),
    "w.block_mean": N_("block means"),
    "w.band": N_("0.4·I_{{h,th}} … 2.6·I_{{h,th}} (2.15)"),
    "w.exp": N_("experiment"),
    "w.theor": N_("theory (2.1)"),
    "w.c_friction_u": N_(
        "Steady friction coefficient f = {f} (the record from {t} s on, load {load} N), as in "
        "the uncertainty table."
    ),
    "w.theory_note": N_(
        "The fatigue-wear theory (2.1) is outside its range for this test (see the validity "
        "table): these values are not judged against the experiment."
    ),
    "w.c_adequate": N_(
        "I_{{h,exp}} = {exp} lies within 0.4·I_{{h,th}} … 2.6·I_{{h,th}} = {lower} … "
        "{upper} (I_{{h,th}} = {theor}, {contact} contact): the model (2.1) is adequate "
        "(2.15)."
    ),
    "w.c_inadequate": N_(
        "I_{{h,exp}} = {exp} lies outside 0.4·I_{{h,th}} … 2.6·I_{{h,th}} = {lower} … "
        "{upper} (I_{{h,th}} = {theor}, {contact} contact; ΔI_h = {error} %): the model "
        "(2.1) is not adequate to this test (2.15)."
    ),
    "b.models": N_(
        "The pressure by the two asymptotic models: the short bearing (3.12) over the load "
        "zone (3.11); the bearing without end leakage (3.14), whose solution is (3.15)."
    ),
    "b.table_3_1": N_(
        "Table 3.1. Hydrodynamic pressure along the angle at z = 0, and its processing"
    ),
    "b.oil": N_("Oil and bearing (3.21)-(3.24)"),
    "b.load": N_("load from the loader scale"),
    "b.temperature": N_("mean oil temperature (3.21)"),
    "b.viscosity": N_("oil viscosity (3.21)"),
    "b.mu_bar": N_("dimensionless viscosity (3.22)"),
    "b.chi_mean": N_("mean eccentricity ratio (3.23)"),
    "b.half_width": N_("relative half-width (3.24, E3)"),
    "b.phi_max": N_("angle of the largest pressure"),
    "b.p_max": N_("largest pressure"),
    "b.table_3_2": N_(
        "Table 3.2. Pressure along the axis at φ = {phi}°, the angle of the largest pressure"
    ),
    "b.edges": N_("Π = 0 at the edges z = ±a = ±{a}."),
    "b.table_3_3": N_(
        "Table 3.3. Π along the angle at z = 0: short bearing Π_0, long bearing Π_∞, finite "
        "bearing, measured Π_e; their differences (3.26), (3.27)"
    ),
    "b.fig_phi": N_("Dimensionless pressure Π against the angle φ at z = 0 (3.28)"),
    "b.fig_z": N_("Dimensionless pressure Π against z at the angle of the largest pressure (3.29)"),
    "b.measured": N_("measured Π_e"),
    "b.short": N_("short bearing Π_0 (3.12)"),
    "b.long": N_("long bearing Π_∞ (3.15)"),
    "b.finite": N_("finite bearing (3.1)"),
    "b.measured_z": N_("measured Π_z"),
    "b.short_z": N_("short bearing Π_m (3.12)"),
    "b.c_chi": N_(
        "Mean eccentricity ratio χ_mean = {chi}; the largest pressure, {p} {unit}, is at "
        "φ = {phi}°."
    ),
    "b.c_errors": N_(
        "Mean |ΔΠ_0| = {short} % (short bearing), mean |ΔΠ_∞| = {long} % (long bearing) over "
        "the rows where the theory is not zero."
    ),
    "b.c_axial": N_(
        "Along z at φ = {phi}°: mean |ΔΠ| = {error} % against the short bearing (3.25)."
    ),
    "m.theory_formulas": N_(
        "The theoretical friction coefficient of the fluid film, by the short-bearing method: "
        "(4.1), (4.2), (4.3), (4.4), (4.5), (4.6), (4.7), (4.8, E3), (4.9), (4.10). Here P* is "
        "the scale of the film force and V its dimensionless tangential component; μ_0 and "
        "ω_0, the characteristic viscosity (at 50 °C) and angular velocity that make the "
        "pressure dimensionless, cancel in P_τ = P*·V."
    ),
    "m.processing_formulas": N_(
        "Processing of the readings: (4.11), (4.12), (4.13), (4.14), (4.15), (4.16), (4.17), "
        "(4.18), (4.19, E4), (4.20, E3), (4.21, E9)."
    ),
    "m.raw": N_("Table 4.{n}. Readings, experiment {n} ({regime})"),
    "m.film": N_("Film thickness against the critical one, and headline results"),
    "m.h_crit": N_("critical film thickness, sum of the five terms"),
    "m.half_width": N_("a = B/D (E3)"),
    "m.h_min_smallest": N_("smallest film thickness of the run"),
    "m.friction_fluid": N_("mean measured friction coefficient, fluid film (4.16)"),
    "m.processed": N_("Table 4.{table}. Processing, experiment {n} ({regime})"),
    "m.theory": N_(
        "Table 4.4. Theory (4.1)-(4.10) and the finite bearing (3.1) beside the experiment"
    ),
    "m.ratio_note": N_("f_e/f_e1: against experiment 1 at the same load."),
    "m.fig_stribeck": N_(
        "Hersey-Stribeck diagram: f against S_1^{{-1}} = p̄/(μ_t·ω), as fig. 4.1 plots it (4.21, E9)"
    ),
    "m.fig_trajectory": N_("Journal-centre trajectory and the Gümbel semicircle"),
    "m.fig_friction": N_("Friction coefficient against the load, three regimes"),
    "m.fig_temperature": N_("Temperature rise of the oil against the load (4.19, E4)"),
    "m.f_exp": N_("f_e, {regime}"),
    "m.f_theory": N_("f_T (4.10)"),
    "m.f_finite": N_("finite bearing (3.1)"),
    "m.h_min_mark": N_("h_min = h_0 - e_max = {h} µm"),
    "m.clearance": N_("clearance circle h_0"),
    "m.gumbel": N_("Gümbel semicircle"),
    "m.c_friction": N_(
        "Fluid film: f_e = {f_min} … {f_max}, mean |Δf| = {error} % against f_T (4.10)."
    ),
    "m.c_regime": N_("{regime}: f_e = {f_min} … {f_max}."),
    "m.c_film": N_(
        "h_min is below h_{{min,cr}} = {h_crit} µm at {count} of {total} steps (no fluid film)."
    ),
    "regime.full film": N_("full film"),
    "col.film_lambda": N_("Regime by Λ"),
    "u.caption": N_("Measurement uncertainty (GUM): value ± expanded uncertainty U = 2u (k = 2)"),
    "u.step": N_(", step {i}, N = {load} N"),
    "m.chi": N_("eccentricity ratio (4.11)"),
    "m.f_measured": N_("friction coefficient (4.16)"),
    "m.disagree": N_(
        "Where the film criteria name another regime than the experiment's oil feed: {items}."
    ),
    "b.attitude": N_("attitude angle ψ from X, Y"),
    "b.rupture": N_("rupture of the finite film past the thinnest film"),
    "w.k": N_("specific wear rate k = V/(F·L) (ASTM G99)"),
    "w.disc_wear": N_("Wear of the disc from a profile across its track (ASTM G99)"),
    "w.track_area": N_("cross-section area of the track"),
    "w.disc_volume": N_("worn volume of the disc"),
    "w.k_disc": N_("specific wear rate of the disc k_2 = V_2/(F·L) (ASTM G99)"),
    "w.validity": N_("Validity of the fatigue-wear theory (2.1)"),
    "w.within_range": N_("theory within its range"),
    "w.approach": N_("relative approach ε"),
    "w.eta_r": N_("real contact area over contour area"),
    "w.pr": N_("real-contact pressure"),
    "w.hb": N_("hardness of the pin HB"),
    "w.sigma": N_("asperity stress k_f·p_r"),
    "w.sigma0": N_("fatigue strength of the pin"),
    "w.cycles": N_("cycles to failure per asperity"),
    "w.kf_plastic": N_("k_f^n of the plastic branch"),
    "w.sensitivity": N_("Sensitivity of I_h (2.1) to t and σ0/σ_B"),
    "t.record": N_("Friction record of the tribometer"),
    "t.distance": N_("sliding distance"),
    "t.laps": N_("laps (cycles) run"),
    "t.load": N_("mean normal load"),
    "t.mean": N_("friction coefficient, whole record"),
    "t.static": N_("static (peak) friction coefficient at the start"),
    "t.running_in": N_("running-in distance (settled within ±5 %)"),
    "t.steady": N_("friction coefficient, steady part"),
    "t.lap_amplitude": N_("once-per-lap amplitude of μ"),
    "t.forward": N_("friction coefficient, forward strokes"),
    "t.backward": N_("friction coefficient, backward strokes"),
    "t.fig_friction": N_(
        "Friction coefficient against the sliding distance: block means with their min-max "
        "band; the running-in (found by PELT) shaded"
    ),
    "t.fig_map": N_(
        "Friction coefficient over the angular position on the disc, by laps (the lap map of "
        "the results)"
    ),
    "t.fig_loops": N_("Friction loops: μ against the position along the stroke"),
    "t.running_in_band": N_("running-in"),
    "t.fig_stribeck": N_("Friction coefficient against the sliding speed over the steps"),
    "t.step_mean": N_("mean of the step"),
    "t.step_steady": N_("steady part of the step"),
    "t.laps_range": N_("laps {first} to {last}"),
    "t.loop": N_("cycle {cycle}"),
    "t.hertz": N_("Initial contact of the ball on the flat (Hertz)"),
    "t.modulus": N_("contact modulus"),
    "t.contact_radius": N_("radius of the contact circle"),
    "t.p0": N_("maximum contact pressure"),
    "t.pm": N_("mean contact pressure"),
    "t.disc_track": N_("Wear of the disc from profiles across its track"),
    "t.disc_mass": N_("Wear of the disc from its mass loss"),
    "t.pin_scar": N_("Wear of the ball or pin from its scar"),
    "t.pin_mass": N_("Wear of the ball or pin from its mass loss"),
    "t.traces": N_("profiles across the track"),
    "t.mass_loss": N_("mass loss"),
    "t.density": N_("density"),
    "t.scar": N_("wear scar diameter"),
    "t.height_loss": N_("height loss of the pin"),
    "t.v.disc_track": N_("worn volume of the disc, from the track"),
    "t.v.disc_mass": N_("worn volume of the disc, from its mass loss"),
    "t.v.pin_scar": N_("worn volume of the ball or pin, from its scar"),
    "t.v.pin_mass": N_("worn volume of the ball or pin, from its mass loss"),
    "t.k.disc_track": N_("specific wear rate of the disc, from the track"),
    "t.k.disc_mass": N_("specific wear rate of the disc, from its mass loss"),
    "t.k.pin_scar": N_("specific wear rate of the ball or pin, from its scar"),
    "t.k.pin_mass": N_("specific wear rate of the ball or pin, from its mass loss"),
    "t.c_friction": N_(
        "The friction coefficient starts at μ_s = {static}, runs in over L_r = {distance} m "
        "and is μ = {mu} (s = {std}) after it; over the whole record μ̄ = {mean}."
    ),
    "t.c_wear": N_("{what}: k = {k} mm³/(N·m)."),
    "t.c_unsettled": N_(
        "The friction coefficient starts at μ_s = {static} and does not settle: no part of at "
        "least the record's last fifth stays within ±5 % of its mean, so no running-in "
        "distance and no steady μ are given; over the whole record μ̄ = {mean}."
    ),
    "c.caption_g99": N_("Test conditions, planned and measured (ASTM G99-17, clause 10)"),
    "c.caption_g133": N_("Test conditions, planned and measured (ASTM G133-05, clause 10)"),
    "c.planned": N_("Planned"),
    "c.measured": N_("Measured"),
    "c.not_recorded": N_("not recorded"),
    "c.speed": N_("sliding speed"),
    "c.rpm": N_("rotational speed of the disc"),
    "c.frequency": N_("frequency of the cycles"),
    "c.stroke": N_("stroke length"),
    "c.distance": N_("sliding distance"),
    "c.temperature": N_("temperature"),
    "c.humidity": N_("relative humidity"),
    "c.off_distance": N_(
        "The sliding distance run, {measured} m, departs from the planned {planned} m."
    ),
    "c.off_load": N_("The mean normal load, {measured} N, departs from the planned {planned} N."),
    "c.dev_load": N_("load {given} N instead of {standard} N"),
    "c.dev_stroke": N_("stroke {given} mm instead of {standard} mm"),
    "c.dev_frequency": N_("frequency {given} Hz instead of {standard} Hz"),
    "c.dev_distance": N_("distance {given} m instead of {standard} m"),
    "c.dev_ball": N_("ball {given} mm instead of {standard} mm"),
    "c.dev_temperature": N_("temperature {given} °C instead of {standard} °C"),
    "c.dev_tip": N_("a flat-ended pin instead of a ball"),
    "c.g133_apart": N_(
        "The test on the flat departs from ASTM G133 procedure {procedure}: {what}."
    ),
    "c.g133_as": N_(
        "The test on the flat follows the parameters of ASTM G133 procedure {procedure}."
    ),
    "c.g99_own": N_(
        "The test parameters (load, speed, distance, materials, environment) are this test's "
        "own, not those of the interlaboratory study of ASTM G99 (G99-17, 1.3 and 4.2): its "
        "results are not to be compared with that study's."
    ),
    "t.flat_track": N_("Wear of the flat from profiles across its track"),
    "t.flat_mass": N_("Wear of the flat from its mass loss"),
    "t.cycles": N_("cycles run"),
    "t.c_trust_mass": N_(
        "The {specimen}'s k by its mass loss ({k_mass} mm³/(N·m)) and by its {shape} "
        "({k_shape} mm³/(N·m)) differ {ratio}-fold, beyond their uncertainties: trust the "
        "mass loss, whose relative uncertainty is the smaller ({relative} %); the {shape} "
        "gives a volume only as far as the worn shape is the one assumed."
    ),
    "t.c_trust_shape": N_(
        "The {specimen}'s k by its mass loss ({k_mass} mm³/(N·m)) and by its {shape} "
        "({k_shape} mm³/(N·m)) differ {ratio}-fold, beyond their uncertainties: trust the "
        "{shape}, whose relative uncertainty is the smaller ({relative} %); a weighing also "
        "counts material transferred, oxide and moisture, and a loss near the balance's "
        "resolution."
    ),
    "t.specimen_disc": N_("disc"),
    "t.specimen_pin": N_("ball or pin"),
    "t.by.disc_track": N_("profiles across the track"),
    "t.by.pin_scar": N_("scar"),
    "t.c_below": N_(
        "{what}: below the balance's resolution (< {resolution} mg): the mass changed by no "
        "more than one step of the balance, so no k is given from it."
    ),
    "t.c_gain": N_(
        "{what}: k = {k} mm³/(N·m), below zero: the specimen gained, material was "
        "transferred onto it; its wear is not measured this way."
    ),
    "w.c_outside": N_(
        "The fatigue-wear theory (2.1) is outside its range for this test, so (2.15) is not "
        "judged: {reasons}."
    ),
    # the ISO roughness beside the manual's (issue 23; rigserver/reports/labs/iso_profile.py)
    "iso.section": N_("Roughness as ISO 21920-2 defines it (Gaussian filter, ISO 16610-21)"),
    "iso.explain": N_(
        "The manual measures the profile from its least-squares mean line over the whole "
        "trace, unfiltered, so Ra = {ra} µm holds the waviness too. ISO 21920-2 measures the "
        "roughness profile from the Gaussian mean line of cut-off λc = {lambda_c} mm "
        "(λs = {lambda_s} µm), which takes the waviness out: Ra = {ra_iso} µm, the value a "
        "profilometer's own software reports with these settings."
    ),
    "iso.compare": N_("The manual's parameters beside the ISO 21920-2 ones"),
    "iso.col_manual": N_("lab manual"),
    "iso.col_iso": N_("ISO 21920-2"),
    "iso.params": N_("ISO 21920-2 parameters of the roughness profile and the filter's settings"),
    "iso.fig": N_(
        "The profile with the manual's least-squares mean line and the Gaussian mean line "
        "(λc); below, the roughness profile and the sections of the evaluation length"
    ),
    "iso.ls_line": N_("least-squares mean line (manual)"),
    "iso.gauss_line": N_("Gaussian mean line, λc (ISO)"),
    "iso.roughness": N_("roughness profile"),
    "iso.evaluation": N_("evaluation length"),
    "iso.track": N_("Roughness across the track, ISO 21920-2 (the track's form filtered out)"),
}
"""The texts of the code by key: English, the message ids of the catalogs."""
