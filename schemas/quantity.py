"""A pydantic field that carries its unit into the JSON Schema (``"unit": "Pa"``)."""

from __future__ import annotations

from typing import Any, get_args, get_origin

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


def unit_paths(model: type[BaseModel], prefix: str = "") -> dict[str, str]:
    """Units of every quantity field of ``model`` and of the models nested in it.

    Paths use dots for nested models and ``[]`` for lists of models, e.g.
    ``"rows[].chi"`` or ``"experimental.intensity"``.
    """
    found = {f"{prefix}{name}": unit for name, unit in units_of(model).items()}
    for name, info in model.model_fields.items():
        for inner, suffix in _nested_models(info.annotation):
            found.update(unit_paths(inner, f"{prefix}{name}{suffix}."))
    return found


def description_paths(model: type[BaseModel], prefix: str = "") -> dict[str, str]:
    """The description of every quantity field, by the paths of :func:`unit_paths`."""
    found = {
        f"{prefix}{name}": info.description or name
        for name, info in model.model_fields.items()
        if name in units_of(model)
    }
    for name, info in model.model_fields.items():
        for inner, suffix in _nested_models(info.annotation):
            found.update(description_paths(inner, f"{prefix}{name}{suffix}."))
    return found


def _nested_models(annotation: Any) -> list[tuple[type[BaseModel], str]]:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [(annotation, "")]
    origin = get_origin(annotation)
    args = get_args(annotation)
    if origin is list and args:
        return [(m, "[]" + s) for m, s in _nested_models(args[0])]
    if args:  # Optional[...] and other unions
        return [found for arg in args for found in _nested_models(arg)]
    return []
