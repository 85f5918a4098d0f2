"""The manual's formulas by their equation numbers, each printed beside the first place of a
report that cites it (docs/models.md; corrected forms where the print is wrong, marked with
the correction); later citations give the number only.

Each text is written in the reports' symbol syntax (``R_a``, ``A_3^{20}``): the symbols are
put in the report's language one by one (:meth:`Messages.symbol`), ``{um}`` is the unit µm
in it; the rest is mathematics, no words.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable, Sequence

from markupsafe import Markup, escape

from rigserver.reports.document import Block, Figure, Items, Paragraph, Section, Table, Text
from rigserver.reports.formatting import html_symbol
from rigserver.reports.i18n import Messages

EQUATIONS: dict[str, str] = {
    # lab work 1
    "1.1": "R = √(π/2)/ρ_2, ρ_2 = 2π²·ρ·ξ·λ (E5)",
    "1.3": "R_a = (1/l)·∫|y| dx",
    "1.4": "R_z = (Σ_{i=1…5} |y_{p,i}| + Σ_{i=1…5} |y_{v,i}|)/5",
    "1.5": "η_p = Σ_{i=1…n} Δ_i",
    "1.6": "t_p = η_p/l",
    "1.7": "ε = p/R_max",
    "1.8": "t_p = b·ε^ν",
    "1.9": "Δ = R_max/(R·b^{1/ν})",
    "1.10": "R_a = 4.3·Δ^{1/2}, {um}",
    "1.11": "Δ_T = (k_1·θ)^{(2ν-1)/(2ν)} · p_c^{-1/ν} · (τ_0/(k_2·α_{ef}))^{(2ν+1)/(2ν)}",
    "1.12": "θ = (1 - μ²)/E, α_{ef} = 2.5·α_r",
    "1.14": "ΔR_a = 0.02·R_{a,max} + 0.04·R_a, ΔR_z = 0.03·R_{z,max} + 0.05·R_z",
    "1.16": "ν_{ij} = lg(η_{pi}/η_{pj})/lg(p_i/p_j)",
    "1.17": "ν = (ν_{13} + ν_{25} + ν_{36})/3",
    "1.18": "lg b_i = lg t_{pi} - ν·lg ε_i",
    "1.19": "b = (b_1 + b_3 + b_5)/3",
    "1.20": (
        "δ = (R_{max1} - R_{max2})/R_{max1}·100 %, δ_{Rz} = (R_{z1} - R_{z2})/R_{z1}·100 %, "
        "δ_{Ra} = (R_{a1} - R_{a2})/R_{a1}·100 % (E10)"
    ),
    # lab work 2
    "2.1": (
        "I_h^y = C · (p_c·θ/k_ν)^{1+βt} · (k_f^y/(σ_B·θ))^t · (R_max/R)^{t(1+β)/2} · "
        "(η_c·b_ν)^{-βt}, I_h^n = C·√2 · (p_c/HB)^{(1+βt)/(1-β)} · (k_f^n/e_B)^t · "
        "(R_max/R)^{(1+t)/2} · (η_c·b_ν)^{β(1+t)/(1-β)}"
    ),
    "2.2": "C = 0.118/(1 + t/2) (E1)",
    "2.3": "p_c = N/A_c",
    "2.4": "A_c = π·r_1^2",
    "2.5": "A_a = 4π·r_2·r_1",
    "2.6": "Δ = 5.4·10⁻²·R_a^2 (E2)",
    "2.7": "p_c ≤ HB_1",
    "2.8": "f = M_fr/(N·r_2)",
    "2.9": "Δm = m_1 - m_2",
    "2.10": "V = Δm/ρ",
    "2.11": "h = V/(π·r_1^2)",
    "2.12": "L = 2π·r_2·M_rev",
    "2.13": "I_{h,exp} = h/L",
    "2.14": "ΔI_h = (I_{h,exp} - I_{h,th})/I_{h,exp}·100 %",
    "2.15": "0.4·I_{h,th} ≤ I_{h,exp} ≤ 2.6·I_{h,th}",
    "2.16": "Δf = (f_a - f_ok)/f_a·100 %",
    # lab work 3
    "3.1": "∂/∂φ(H³·∂Π/∂φ) + ∂/∂z(H³·∂Π/∂z) = 6μ̄·(Gχ sin(φ - δ) - E cos(φ - δ))",
    "3.2": "H = 1 - χ cos(φ - δ)",
    "3.5": "Π(φ, ±a) = 0, Π ≥ 0, a = B/(2R) (E3)",
    "3.10": "Π_0 = 3μ̄a²·(Gχ sin φ - E cos φ)/(1 - χ cos φ)³·((z/a)² - 1)",
    "3.11": "φ_n = π, φ_k = 2π",
    "3.12": "Π_0 = 3μ̄a²·Gχ sin φ/(1 - χ cos φ)³·((z/a)² - 1)",
    "3.14": "∂/∂φ(H³·∂Π_∞/∂φ) = 6μ̄·(Gχ sin(φ - δ) - E cos(φ - δ))",
    "3.15": "Π_∞ = 6χμ̄(2 - χ cos φ)/((2 + χ²)(1 - χ cos φ)²)·(-G sin φ)",
    "3.16": "e_x = h_0 - |X_set - X|, e_y = h_0 - |Y_set - Y|, e = √(e_x^2 + e_y^2)",
    "3.17": "χ = e/h_0",
    "3.18": "Π_e = (p - p_a)·Ψ²/(μ_0·ω_0)",
    "3.19": "Ψ = h_0/R_2",
    "3.20": "φ_mod = 360° - (φ_k - φ_limb)",
    "3.21": "μ = A·exp(α·t)",
    "3.22": "μ̄ = μ_t/μ_0",
    "3.23": "χ_mean = (1/n)·Σ_{i=1…n} χ_i",
    "3.24": "a = B/(2R_2) = B/D_2 (E3)",
    "3.25": "ΔΠ = (Π_m - Π_z)/Π_m·100 %",
    "3.26": "ΔΠ_0 = (Π_0 - Π_e)/Π_0·100 %",
    "3.27": "ΔΠ_∞ = (Π_∞ - Π_e)/Π_∞·100 %",
    "3.28": "Π_e(φ), Π_0(φ), Π_∞(φ), z = 0",
    "3.29": "Π_z(z), Π_m(z), φ = φ_max",
    # lab work 4
    "4.1": "M_fr = -½·P_τ·e + ω·μ*·R_1^3·2πB/√(h_0^2 - e²)",
    "4.2": "P_τ = P*·V",
    "4.3": "P* = 2B·R·μ_0·ω_0/ψ²",
    "4.4": "V = -χ·a²·μ̄·A_3^{20}·G",
    "4.5": "A_1^{00} = π/√(1 - χ²), A_2^{00} = A_1^{00}/(1 - χ²), A_3^{20} = π/(2(1 - χ²)^{3/2})",
    "4.6": "ψ = h_0/R",
    "4.7": "χ = e/h_0",
    "4.8": "a = B/(2R) (E3)",
    "4.9": "G = ω/ω_0",
    "4.10": "f_T = M_fr/(N·R_1)",
    "4.11": (
        "e_x = h_0·cos 45° - |X_set - X|, e_y = h_0·cos 45° - |Y_set - Y|, "
        "e = √(e_x^2 + e_y^2), χ = e/h_0"
    ),
    "4.12": "δ = 45° - arctg(e_x/e_y), γ = 45° - arctg(e_y/e_x)",
    "4.13": "F = k·Δl",
    "4.14": "M_fr = F·l_1",
    "4.15": "F_fr = M_fr/l_2",
    "4.16": "f_e = F_fr/N",
    "4.17": "μ_i = A·exp(α·t_i)",
    "4.18": "μ_t = (μ_3 + μ_4 + μ_5)/3",
    "4.19": "Δt_i = t_i - t_1 (E4)",
    "4.20": "a = B/(2R) = B/D (E3)",
    "4.21": "S_1 = μ_t·ω/p̄, p̄ = N/(BD) (E9)",
}

#: An equation number as the reports cite it: "(1.3)", "(4.21, E9)", "(4.1)-(4.10)"; a pair
#: of parentheses holds a citation only when all it holds is numbers and corrections, never
#: a value ("(2.1 ± 0.1)"), a table ("(table 3.2)") or a range of values ("(0.4–3.2)").
_NUMBER = r"[1-4]\.\d{1,2}"
_PART = rf"(?:{_NUMBER}(?:\s*[-–]\s*{_NUMBER})?|E(?:10|[1-9]))"
_CITATION = re.compile(rf"\s*{_PART}(?:\s*,\s*{_PART})*\s*")
_PARENS = re.compile(r"\(([^()]*)\)")
#: A symbol with a subscript or superscript, translated as a whole (f_e -> f_э).
_SYMBOL = re.compile(r"[^\W\d_]+_(?:\{[^}]*\}|\w+)(?:\^\{[^}]*\})?")
_TAGS = re.compile(r"<[^>]+>")


def citations(text: str) -> list[str]:
    """The equation numbers ``text`` cites, once each, in the order they are cited (both ends
    of a range)."""
    found: list[str] = []
    for group in _PARENS.findall(text):
        if _CITATION.fullmatch(group):
            found += re.findall(_NUMBER, group)
    return list(dict.fromkeys(found))


def cited(text: str) -> list[str]:
    """The equation numbers of :data:`EQUATIONS` that ``text`` cites, once each, in the
    manual's order."""
    known = [n for n in citations(text) if n in EQUATIONS]
    return sorted(known, key=lambda n: tuple(int(part) for part in n.split(".")))


def symbols_of(formula: str) -> list[str]:
    """The symbols with scripts in ``formula`` (to be put in the report's language)."""
    return _SYMBOL.findall(formula)


def formula(t: Messages, number: str) -> Markup:
    """Equation ``number``'s formula in ``t``'s language: its symbols translated, µm in the
    language's unit, a decimal comma in Russian (``f_э = F_тр/N``); a line may break only
    between its top-level parts (:func:`unbreakable`), never inside a bracket or a script."""
    text = EQUATIONS[number]
    for symbol in dict.fromkeys(symbols_of(text)):
        text = text.replace(symbol, t.symbol(symbol))
    text = text.replace("{um}", t.unit("um"))
    if t.lang == "ru":  # a decimal comma, as the page's numbers
        text = re.sub(r"(\d)\.(\d)", r"\1,\2", text)
    return unbreakable(text)


#: Where a formula's line may break: after a comma or around a product's dot, outside any
#: bracket or script.
_BREAKS = (", ", " · ")


def unbreakable(text: str) -> Markup:
    """``text`` (the reports' symbol syntax) as markup whose parts between the top-level
    breaks of :data:`_BREAKS` are each kept on one line (``<span class="nobreak">``)."""
    parts: list[str] = []
    depth, start, i = 0, 0, 0
    while i < len(text):
        if text[i] in "([{":
            depth += 1
        elif text[i] in ")]}":
            depth -= 1
        elif depth == 0 and text.startswith(_BREAKS, i):
            separator = next(b for b in _BREAKS if text.startswith(b, i))
            parts += [text[start:i], separator]
            i += len(separator)
            start = i
            continue
        i += 1
    parts.append(text[start:])
    return Markup("").join(
        Markup('<span class="nobreak">{}</span>').format(html_symbol(part))
        if k % 2 == 0
        else Markup(escape(part))
        for k, part in enumerate(parts)
    )


def _plain(text: Text) -> str:
    """What a text says, without its markup (a citation is in the words, not the tags)."""
    return Markup(_TAGS.sub("", str(text))).unescape() if isinstance(text, Markup) else text


class _Shown:
    """The equations printed so far in a report: each formula goes to the first place that
    cites it."""

    def __init__(self, t: Messages) -> None:
        self.t = t
        self.numbers: set[str] = set()

    def take(self, texts: Iterable[Text]) -> list[str]:
        """The numbers ``texts`` cite that have a formula not printed yet (now counted as
        printed)."""
        found = [n for text in texts for n in cited(_plain(text)) if n not in self.numbers]
        found = list(dict.fromkeys(found))
        self.numbers.update(found)
        return found

    def lines(self, numbers: Sequence[str], *, numbered: bool) -> list[Markup]:
        """The formulas of ``numbers``, each after its number when ``numbered`` (a place
        citing several, or a note away from the citation)."""
        numbered = numbered or len(numbers) > 1
        return [
            Markup('<span class="formula">{}</span>').format(
                Markup("({}) {}").format(n, formula(self.t, n)) if numbered else formula(self.t, n)
            )
            for n in numbers
        ]

    def after(self, text: Text, *, cell: bool = False) -> Text:
        """``text`` with the formulas it cites first below it; a table's cell is printed as it
        is (escaped), other texts with their symbols' scripts."""
        numbers = self.take([text])
        if not numbers:
            return text
        shown = escape(text) if cell else _markup(text)
        return _BREAK.join([shown, *self.lines(numbers, numbered=False)])

    def table(self, table: Table) -> Table:
        """A table with the formulas under the names of its rows that cite them first; those
        first cited by its caption, header or values under its caption, by its note in it."""
        rows = [
            [self.after(c, cell=True) if i < table.labels else c for i, c in enumerate(row)]
            for row in table.rows
        ]
        rest = self.take(
            [table.caption, *table.header, *(c for r in table.rows for c in r[table.labels :])]
        )
        note = self.after(table.note) if table.note else table.note
        formulas = _BREAK.join(self.lines(rest, numbered=True)) if rest else ""
        return dataclasses.replace(table, rows=rows, note=note, formulas=formulas)

    def block(self, block: Block) -> Block:
        if isinstance(block, Table):
            return self.table(block)
        if isinstance(block, Figure):
            return dataclasses.replace(block, caption=self.after(block.caption))
        if isinstance(block, Paragraph):
            return dataclasses.replace(block, text=self.after(block.text))
        if isinstance(block, Items):
            return dataclasses.replace(block, items=[self.after(item) for item in block.items])
        return block  # the students' own words cite what they like


_BREAK = Markup("<br>")


def _markup(text: Text) -> Markup:
    """A text as markup: plain text gets its symbols' scripts (as the template's ``sym``)."""
    return text if isinstance(text, Markup) else html_symbol(text)


def beside(t: Messages, sections: Sequence[Section]) -> list[Section]:
    """The sections with each cited equation's formula (:data:`EQUATIONS`) beside its first
    citation, in reading order: under the name of a table's row, a figure's caption, a
    paragraph, an item of a list or a table's note; cited first by a table's caption, header
    or values, under its caption."""
    shown = _Shown(t)
    return [
        dataclasses.replace(section, blocks=[shown.block(b) for b in section.blocks])
        for section in sections
    ]
