"""What the wire takes: values that can be stored and shown, strictly typed.

Every text, number and time a client sends goes through one of these types, so a value
that HDF5, SQLite, JSON or a page cannot hold is refused at the door (422 naming the
field) and never stored:

- text without NUL characters (HDF5 attributes cannot hold them) or lone surrogates (UTF-8
  cannot);
- finite numbers: no NaN or ±Infinity, and no literal that overflows a double (``1e400``
  parses as Infinity);
- whole numbers within SQLite's 64-bit integers;
- times that exist in UTC (``0001-01-01T00:00:00+01:00`` does not).

Conversions belong to clients: a number sent as text, or ``true`` for a number, is refused.
"""

from __future__ import annotations

import math
import re
from datetime import UTC, datetime
from typing import Annotated, Any

from pydantic import AfterValidator, BeforeValidator, Strict
from pydantic_core import PydanticCustomError

#: The whole numbers the wire takes: SQLite's INTEGER.
WHOLE_MIN, WHOLE_MAX = -(2**63), 2**63 - 1


_COUNT = re.compile(r"[0-9]{1,19}")


def ascii_count(text: str) -> int | None:
    """A count or sequence number written in a header or query (``Last-Event-ID``,
    ``?seq=``): ASCII digits only, at most 19 (below 2^63); else ``None``. Python's
    ``str.isdigit`` and ``int`` would take Arabic-Indic or fullwidth digits, and ``int``
    fails on numbers longer than its conversion limit."""
    return int(text) if _COUNT.fullmatch(text) else None


_UNSTORABLE = re.compile("[\x00\ud800-\udfff]")


def clean_text(value: str) -> str:
    """``value`` if it holds no NUL character and no lone surrogate (pydantic refuses lone
    surrogates only in a constrained ``str``)."""
    found = _UNSTORABLE.search(value)
    if found is not None:
        what = "a NUL character" if found.group() == "\x00" else "a lone surrogate"
        raise PydanticCustomError(
            "text_unstorable",
            "text must not hold {what} (character {at})",
            {"what": what, "at": found.start()},
        )
    return value


def is_finite_number(value: object) -> bool:
    """True for an int or float (not a bool) that a double holds as a finite number."""
    if isinstance(value, bool):
        return False
    if isinstance(value, int):
        return WHOLE_MIN <= value <= WHOLE_MAX
    return isinstance(value, float) and math.isfinite(value)


def _scalar(value: Any) -> Any:
    if isinstance(value, str):
        return clean_text(value)
    if isinstance(value, bool) or is_finite_number(value):
        return value
    raise PydanticCustomError(
        "scalar",
        "must be text, true/false, a finite number or a whole number within ±2^63, not {shown}",
        {"shown": shown(value)},
    )


def _plan_value(value: Any) -> Any:
    if not isinstance(value, list):
        return _scalar(value)
    for i, item in enumerate(value):
        if not is_finite_number(item):
            raise PydanticCustomError(
                "finite_list",
                "item {index} must be a finite number, not {shown}",
                {"index": i, "shown": shown(item)},
            )
    return value


def _utc(value: datetime) -> datetime:
    try:
        return value.replace(tzinfo=UTC) if value.tzinfo is None else value.astimezone(UTC)
    except OverflowError:
        raise PydanticCustomError(
            "datetime_range", "the time is outside 0001-01-01 .. 9999-12-31 in UTC"
        ) from None


def unstorable(value: object, path: str) -> str | None:
    """Where a JSON-like ``value`` (e.g. a stored configuration) holds what the wire
    refuses, and what: ``"configuration.pin.hardness: null"``; ``None`` if nowhere. A null
    is what an older build stored for a NaN or an infinity."""
    if isinstance(value, dict):
        for key, item in value.items():
            found = unstorable(key, f"{path}[key]") or unstorable(item, f"{path}.{key}")
            if found:
                return found
        return None
    if isinstance(value, list):
        return next(
            (f for i, item in enumerate(value) if (f := unstorable(item, f"{path}.{i}"))), None
        )
    if isinstance(value, str):
        return None if _UNSTORABLE.search(value) is None else f"{path}: {shown(value)}"
    if value is None or not (isinstance(value, bool) or is_finite_number(value)):
        return f"{path}: {shown(value)}"
    return None


def shown(value: object) -> str:
    """A short, printable text of a refused value (for messages)."""
    if isinstance(value, float):
        return repr(value)  # 'nan', 'inf'
    if isinstance(value, int) and not isinstance(value, bool):
        digits = value.bit_length() * 0.30103
        return f"a whole number of about {digits:.0f} digits" if digits > 30 else str(value)
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


#: Text without NUL characters.
Text = Annotated[str, AfterValidator(clean_text)]
#: A specimen value: text, a flag, a finite number or a whole number within ±2^63.
Scalar = Annotated[str | float | int | bool, BeforeValidator(_scalar)]
#: A test-plan value: a :data:`Scalar` or a list of finite numbers (e.g. the load steps).
PlanValue = Annotated[str | float | int | bool | list[float], BeforeValidator(_plan_value)]
#: A number of a configuration or a calculator's input: a JSON number (whole or not), never
#: ``true`` or ``"1.5"`` (pydantic's lax mode takes both as 1.0 and 1.5). The models that
#: take them are strict as a whole (``ConfigDict(strict=True)``); a tuple of them is a
#: field with ``strict=False`` (a JSON array is a list) of these.
Number = Annotated[float, Strict()]
#: A time, converted to UTC; refused if it does not exist there.
UtcTime = Annotated[datetime, AfterValidator(_utc)]
