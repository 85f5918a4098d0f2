"""The page that opens a run (``/runs/new?stand=``): its fields generated from the stand's
declaration, and the posted form read back into what ``POST /api/v1/runs`` takes.

The fields are named as the API's (``operator``, ``title``, ``specimen.pin``,
``test_plan.load_N``, ``configuration.viscosity.A``); each number is typed in the unit the
results print it in (:data:`schemas.labels.CONFIGURATION`: mm, µm, MPa, ...), a decimal
comma read as a point, and the stand's passport (its configuration as the lab set it) is
shown as the default. Only a value changed from the passport is sent as an override, so the
run keeps where each value came from.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, replace
from typing import Any, Literal, get_args, get_origin

from markupsafe import Markup
from pydantic import BaseModel

from rigserver.reports.formatting import html_symbol
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.run_report import FIELD_WORDS
from rigserver.web.entry import TEXTS
from rigserver.web.pages import render_page
from schemas.labels import CONFIGURATION, PARTICULARS
from schemas.messages import N_
from schemas.stands import DECLARATIONS, Stand, StandKind
from schemas.units import UNITS

Kind = Literal["text", "number", "numbers", "choice", "lines"]

_TEXT_PLAN = frozenset({"mode"})
"""Test-plan keys that hold words, not numbers."""


@dataclass(frozen=True, slots=True)
class Field:
    """One input of the form: its name (the API's field), words, symbol and unit (in the
    page's language), the value shown, and the refusal beside it."""

    name: str
    words: str
    symbol: Markup
    unit: str
    value: str
    kind: Kind
    choices: tuple[tuple[str, str], ...] = ()
    error: str = ""


@dataclass(frozen=True, slots=True)
class _Leaf:
    """A configuration value of the stand: where it sits, what it is, its passport value."""

    path: tuple[str, ...]
    annotation: Any
    description: str
    stored: str | None
    display: str | None
    default: Any

    @property
    def name(self) -> str:
        return "configuration." + ".".join(self.path)

    @property
    def factor(self) -> float:
        """Display unit -> stored unit."""
        if self.stored is None or self.display is None or self.display == self.stored:
            return 1.0
        return UNITS[self.display].factor / UNITS[self.stored].factor


def _leaves(model: BaseModel, path: tuple[str, ...] = ()) -> Iterator[_Leaf]:
    """The stand's configuration values that a form can take (numbers, words, choices,
    flags; not the tuples such as the manometers' z, kept from the passport)."""
    for name, info in type(model).model_fields.items():
        value = getattr(model, name)
        if isinstance(value, BaseModel):
            yield from _leaves(value, (*path, name))
            continue
        if isinstance(value, tuple):
            continue
        extra = info.json_schema_extra
        stored = extra.get("unit") if isinstance(extra, dict) else None
        dotted = ".".join((*path, name))
        label = CONFIGURATION.get(dotted) or CONFIGURATION.get(name)
        unit = None if stored is None else str(stored)
        display = label.unit if label is not None and unit is not None else unit
        yield _Leaf(
            (*path, name),
            info.annotation,
            info.description or FIELD_WORDS.get(name, name),
            unit,
            display,
            value,
        )


def _number_text(value: float, lang: Lang) -> str:
    text = f"{value:.12g}"
    return text.replace(".", ",") if lang == "ru" else text


def parse_number(text: str) -> float | None:
    """A number as typed: a decimal comma is a point; None if it is not a finite number."""
    cleaned = text.strip().replace(",", ".").replace("\u2212", "-")
    try:
        value = float(cleaned)
    except ValueError:
        return None
    return value if math.isfinite(value) and cleaned.lower() not in ("inf", "nan") else None


def _split_head(text: str) -> tuple[str, str]:
    """``"r2, disc radius"`` -> (``"r2"``, ``"disc radius"``): the symbol a description
    starts with, and its words."""
    head, comma, rest = text.partition(", ")
    if comma and " " not in head and len(head) <= 12:
        return head, rest
    return "", text


def _leaf_field(t: Messages, leaf: _Leaf, lang: Lang, owner: str) -> Field:
    words = t.gettext(leaf.description)
    symbol, words = _split_head(words)
    choices: tuple[tuple[str, str], ...] = ()
    kind: Kind
    if isinstance(leaf.default, bool):
        choices = (("true", t("yes")), ("false", t("no")))
        value, kind = ("true" if leaf.default else "false"), "choice"
    elif get_origin(leaf.annotation) is Literal:
        choices = tuple(
            (str(c), t.unit(c) if c in UNITS else t.gettext(c)) for c in get_args(leaf.annotation)
        )
        value, kind = str(leaf.default), "choice"
    elif isinstance(leaf.default, str):
        value, kind = leaf.default, "text"
    else:
        kind = "number"
        value = _number_text(float(leaf.default) / leaf.factor, lang)
    unit = t.unit(leaf.display) if leaf.display is not None and leaf.display != "1" else ""
    return Field(
        leaf.name, owner + words, html_symbol(t.symbol(symbol)), unit, value, kind, choices
    )


def _particular(t: Messages, group: str, key: str) -> Field:
    label = PARTICULARS.get(key)
    words = t.gettext(label.text) if label else key
    symbol = html_symbol(t.symbol(label.symbol)) if label else Markup("")
    unit = t.unit(label.unit) if label and label.unit != "1" else ""
    kind: Kind = "text"
    if group == "test_plan" and key not in _TEXT_PLAN:
        kind = "numbers" if key.startswith("loads_") else "number"
    return Field(f"{group}.{key}", words, symbol, unit, "", kind)


def form_fields(t: Messages, stand: Stand, lang: Lang) -> dict[str, list[Field]]:
    """The form's fields in sections: the run, the specimens, the test plan, the stand's
    configuration (its passport values as the defaults)."""
    run = [
        Field("operator", t.gettext(N_("operator")), Markup(""), "", "", "text"),
        Field(
            "students", t.gettext(N_("students, one name per line")), Markup(""), "", "", "lines"
        ),
        Field("title", t.gettext(N_("title of the run")), Markup(""), "", "", "text"),
        Field("notes", t.gettext(N_("notes")), Markup(""), "", "", "lines"),
    ]
    owners = {}
    for leaf in _leaves(stand.configuration):
        owners[leaf.path] = ""
        if len(leaf.path) > 1:
            label = PARTICULARS.get(leaf.path[0])
            owners[leaf.path] = (t.gettext(label.text) if label else t.gettext(leaf.path[0])) + ": "
    return {
        "run": run,
        "specimen": [_particular(t, "specimen", k) for k in DECLARATIONS[stand.kind].specimens],
        "test_plan": [_particular(t, "test_plan", k) for k in DECLARATIONS[stand.kind].plan],
        "configuration": [
            _leaf_field(t, leaf, lang, owners[leaf.path]) for leaf in _leaves(stand.configuration)
        ],
    }


@dataclass
class Posted:
    """The form as posted: what ``POST /api/v1/runs`` takes (``body``), the students'
    names, and the refusals by field (typed numbers that are none)."""

    body: dict[str, Any]
    students: list[str]
    errors: dict[str, str]


NOT_A_NUMBER = TEXTS["not_a_number"]
REQUIRED = TEXTS["empty"]
NO_STAND = N_("This key may open no run: it has no stand's write scope.")
INVALID = N_("not taken: {detail}")


def read_posted(t: Messages, stand: Stand, form: Mapping[str, str]) -> Posted:
    """The posted ``form`` (field name -> text) as a run's opening."""
    errors: dict[str, str] = {}
    body: dict[str, Any] = {"stand": stand.kind.value, "specimen": {}, "test_plan": {}}
    for name in ("operator", "title", "notes"):
        body[name] = form.get(name, "").strip()
    for key in DECLARATIONS[stand.kind].specimens:
        text = form.get(f"specimen.{key}", "").strip()
        if text:
            body["specimen"][key] = text
    for key in DECLARATIONS[stand.kind].plan:
        name = f"test_plan.{key}"
        text = form.get(name, "").strip()
        if not text:
            continue
        if key in _TEXT_PLAN:
            body["test_plan"][key] = text
            continue
        parts = text.replace(";", " ").split() if key.startswith("loads_") else [text]
        numbers = [parse_number(p) for p in parts]
        bad = next((p for p, n in zip(parts, numbers, strict=True) if n is None), None)
        if bad is not None:
            errors[name] = t.gettext(NOT_A_NUMBER).format(value=bad[:40])
            continue
        body["test_plan"][key] = numbers if key.startswith("loads_") else numbers[0]
    overrides: dict[str, Any] = {}
    for leaf in _leaves(stand.configuration):
        given = form.get(leaf.name)
        if given is None:
            continue
        value = _leaf_value(leaf, given)
        if value is None:
            errors[leaf.name] = t.gettext(NOT_A_NUMBER).format(value=given.strip()[:40])
        elif value != leaf.default and not _same_number(value, leaf.default):
            place = overrides
            for part in leaf.path[:-1]:
                place = place.setdefault(part, {})
            place[leaf.path[-1]] = value
    body["configuration"] = overrides
    students = [n.strip() for n in form.get("students", "").splitlines() if n.strip()]
    return Posted(body, students, errors)


def _leaf_value(leaf: _Leaf, text: str) -> Any:
    """The typed value in the stored unit (None: not a number where one is asked for)."""
    if isinstance(leaf.default, bool):
        return text == "true"
    if isinstance(leaf.default, str):
        return text.strip()
    number = parse_number(text)
    if number is None:
        return None
    value = float(f"{number * leaf.factor:.12g}")  # 180 µm is 0.00018 m, not ...97998
    if isinstance(leaf.default, int):
        return int(value) if value == int(value) else value
    return value


def _same_number(a: Any, b: Any) -> bool:
    """Equal up to the display's rounding (a passport value shown and sent back)."""
    if isinstance(a, bool | str) or isinstance(b, bool | str):
        return False
    return math.isclose(float(a), float(b), rel_tol=1e-11, abs_tol=0.0)


def with_posted(
    fields: dict[str, list[Field]], form: Mapping[str, str], errors: Mapping[str, str]
) -> dict[str, list[Field]]:
    """The fields showing what was posted, each with its refusal."""
    return {
        section: [
            replace(f, value=form.get(f.name, f.value), error=errors.get(f.name, "")) for f in items
        ]
        for section, items in fields.items()
    }


def new_run_page(
    *,
    stand: Stand | None,
    stands: list[StandKind],
    fields: dict[str, list[Field]] | None,
    lang: Lang,
    form_token: str,
    idempotency_key: str,
    refusal: str = "",
) -> str:
    """The form that opens a run on ``stand`` (None: the stands the key may open runs of)."""
    return render_page(
        "new_run.html",
        lang,
        signed_in=True,
        stand=stand,
        stands=stands,
        fields=fields,
        form_token=form_token,
        idempotency_key=idempotency_key,
        refusal=refusal,
    )
