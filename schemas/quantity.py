"""A pydantic field that carries its unit into the JSON Schema (``"unit": "Pa"``)."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, Field

from schemas.units import UnitSymbol


def quantity(default: Any, unit: UnitSymbol, description: str, **constraints: Any) -> Any:
    """Declare a field with its unit; the unit lands in the schema and in :func:`units_of`."""
    return Field(default, description=description, json_schema_extra={"unit": unit}, **constraints)


def units_of(model: type[BaseModel]) -> dict[str, str]:
    """The unit of every field of ``model`` declared with :func:`quantity`."""
    found: dict[str, str] = {}
    for name, info in model.model_fields.items():
        extra = info.json_schema_extra
        if isinstance(extra, dict) and isinstance(extra.get("unit"), str):
            found[name] = str(extra["unit"])
    return found
