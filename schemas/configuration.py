"""The base of every stand's configuration: frozen, strict, no unknown field."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict


class Configuration(BaseModel):
    """A stand's configuration or a part of it (its instruments' accuracy, its specimens)."""

    # strict: a flag or a text is no number (``true`` for a spring rate is refused, not 1.0)
    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False, strict=True)
