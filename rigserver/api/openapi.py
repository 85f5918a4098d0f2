"""Components of the OpenAPI document that no route's signature brings in: the models of
bodies a route parses itself (the readings batch, see :mod:`rigserver.api.routes.readings`)
and of the errors (:mod:`rigserver.api.problems`), added by :func:`amend` as the document is
built."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

from fastapi import FastAPI
from pydantic import BaseModel

REF_TEMPLATE = "#/components/schemas/{model}"


def component_schemas(model: type[BaseModel]) -> dict[str, Any]:
    """``model``'s JSON Schema and those of the models it refers to, as components named
    after the models (FastAPI's names for the models of its routes)."""
    schema = model.model_json_schema(ref_template=REF_TEMPLATE)
    defs: dict[str, Any] = schema.pop("$defs", {})
    return {**defs, model.__name__: schema}


def amend(app: FastAPI, change: Callable[[dict[str, Any]], None]) -> None:
    """Have ``change`` complete the app's OpenAPI document (built once, on its first
    request)."""
    build = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is not None:
            return app.openapi_schema
        document = build()
        change(document)
        app.openapi_schema = document
        return document

    app.openapi = openapi  # type: ignore[method-assign]


def add_components(app: FastAPI, models: Iterable[type[BaseModel]]) -> None:
    """Put ``models`` among the document's schemas."""
    extra: dict[str, Any] = {}
    for model in models:
        extra.update(component_schemas(model))
    amend(app, lambda document: schemas_of(document).update(extra))


def schemas_of(document: dict[str, Any]) -> dict[str, Any]:
    """The document's component schemas (an empty one added if it has none)."""
    schemas: dict[str, Any] = document.setdefault("components", {}).setdefault("schemas", {})
    return schemas
