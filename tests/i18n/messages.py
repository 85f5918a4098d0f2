"""Every message of the package, as Babel's extraction over the Python and the templates
finds it (what ``pybabel extract`` with the same keywords writes into the template), and
the texts declared as data (channels, groups, units), which must be among them."""

from __future__ import annotations

from pathlib import Path

from babel.messages.extract import DEFAULT_KEYWORDS, extract_from_dir

from rigserver.reports.i18n import UNIT_CONTEXT, UNIT_LABELS
from schemas.stands import default_stands

ROOT = Path(__file__).resolve().parents[2]

KEYWORDS = {
    **DEFAULT_KEYWORDS,
    "N_": None,
    "NP_": (1, 2),
    "C_": ((1, "c"), 2),
    "quantity": (3,),
    "_c": (3,),
}
"""``N_`` marks a text, ``C_`` a text in a context; ``quantity(default, unit, description)``
and the stands' ``_c(name, unit, long_name)`` carry a text shown to people in their third
argument; ``NP_`` marks the singular and plural words of a count (``pybabel extract -k N_
-k NP_:1,2 -k C_:1c,2 -k quantity:3 -k _c:3``)."""

METHODS = [
    ("**/templates/**.html", "jinja2.ext:babel_extract"),
    ("**.py", "python"),
]

#: The Python of the schemas whose texts are shown on pages and reports (the results'
#: field descriptions document the JSON API and stay English).
SHOWN_SCHEMAS = ("stands.py", "labels.py")

Message = tuple[str | None, str]
"""A message: its context and its id."""


def extracted() -> dict[Message, str]:
    """Every message Babel finds in ``rigserver`` and the shown schemas, with where."""
    found: dict[Message, str] = {}
    for folder, keep in ((ROOT / "rigserver", None), (ROOT / "schemas", SHOWN_SCHEMAS)):
        for filename, lineno, message, _comments, context in extract_from_dir(
            folder, METHODS, keywords=KEYWORDS, options_map={"**.html": {}}
        ):
            if keep is not None and filename not in keep:
                continue
            text = message if isinstance(message, str) else message[0]
            if text:
                found.setdefault((context, text), f"{folder.name}/{filename}:{lineno}")
    return found


def declared() -> dict[Message, str]:
    """The texts declared as data: channel and group names, unit symbols."""
    found: dict[Message, str] = {}
    for stand in default_stands().values():
        for group in stand.groups:
            found[(None, group.long_name)] = f"{stand.kind.value}.{group.name}"
            for channel in group.channels:
                found[(None, channel.long_name)] = f"{stand.kind.value}.{channel.name}"
    for symbol, text in UNIT_LABELS.items():
        found[(UNIT_CONTEXT, text)] = f"unit {symbol}"
    return found


def every_message() -> dict[Message, str]:
    return extracted()
