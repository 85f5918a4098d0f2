"""Runs: what a lab PC sends to open one, and what the service says about it."""

from __future__ import annotations

import re
import secrets
from collections.abc import Mapping
from datetime import UTC, datetime
from enum import StrEnum
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, StringConstraints

from schemas.stands import StandKind
from schemas.wire import PlanValue, Scalar, Text, UtcTime

RUN_ID_PATTERN = r"^[0-9]{8}T[0-9]{6}Z-[0-9a-f]{8}$"
_RUN_ID = re.compile(RUN_ID_PATTERN)

#: Entries of a run's specimen, and of its test plan, at most.
SPECIMEN_KEYS = 100
PLAN_KEYS = 100

RunId = Annotated[str, StringConstraints(pattern=RUN_ID_PATTERN, max_length=25)]
ShortText = Annotated[Text, StringConstraints(max_length=200)]
#: Who gave a configuration value: the file and its map, or the operator.
Source = Literal["file", "operator"]


def new_run_id(now: datetime | None = None) -> str:
    """A sortable, unguessable run id: UTC start time and 32 random bits."""
    t = (now or datetime.now(UTC)).astimezone(UTC)
    return f"{t:%Y%m%dT%H%M%S}Z-{secrets.token_hex(4)}"


def is_run_id(text: str) -> bool:
    return bool(_RUN_ID.match(text))


class RunState(StrEnum):
    OPEN = "open"
    FINISHED = "finished"
    ABORTED = "aborted"


class RunCreate(BaseModel):
    """What a lab PC posts to open a run."""

    model_config = ConfigDict(
        extra="forbid",
        allow_inf_nan=False,
        json_schema_extra={
            "examples": [
                {
                    "stand": "smts2",
                    "operator": "Ivanova",
                    "title": "Wear of St3sp on R9, 300 N, 1000 rpm",
                    "specimen": {"pin": "St3sp", "disc": "R9"},
                    "test_plan": {"mode": "wear", "load_N": 300, "speed_rpm": 1000},
                    "configuration": {"disc_radius": 0.0225},
                }
            ]
        },
    )

    stand: StandKind
    operator: Annotated[Text, StringConstraints(min_length=1, max_length=100)]
    title: ShortText = ""
    specimen: dict[ShortText, Scalar] = Field(
        default_factory=dict,
        max_length=SPECIMEN_KEYS,
        description="specimens and materials, free key-value",
    )
    test_plan: dict[ShortText, PlanValue] = Field(
        default_factory=dict,
        max_length=PLAN_KEYS,
        description="e.g. the load steps or the SMTs-2 mode",
    )
    configuration: dict[Text, Any] = Field(
        default_factory=dict,
        description="overrides of the stand's configuration for this run (checked by its schema)",
    )
    notes: Annotated[Text, StringConstraints(max_length=5000)] = ""
    given_by: Source = Field(
        default="operator",
        description="who gave the configuration's overrides: the operator (a form, the API) "
        "or the file and its map (rigclient import, tail, profile)",
    )


def given_paths(given: Mapping[str, Any], prefix: str = "") -> list[str]:
    """The dotted paths of the values a configuration's overrides give
    (``{"plan": {"speed": 0.2}}`` -> ``["plan.speed"]``)."""
    paths: list[str] = []
    for key, value in given.items():
        if isinstance(value, Mapping):
            paths += given_paths(value, f"{prefix}{key}.")
        else:
            paths.append(f"{prefix}{key}")
    return paths


class ImportedFrom(BaseModel):
    """Where an imported run comes from: its id on the server that exported it."""

    run_id: RunId = Field(description="the run's id on the server it was exported from")
    server: Text = Field(description="the address of that server, as its archive names it")
    exported: Text = Field(default="", description="when the archive was made (ISO 8601)")


class Run(BaseModel):
    """A run as stored: metadata, the configuration snapshot, state and progress."""

    id: RunId
    stand: StandKind
    state: RunState = RunState.OPEN
    operator: Text
    title: Text = ""
    specimen: dict[Text, Scalar] = Field(default_factory=dict)
    test_plan: dict[Text, PlanValue] = Field(default_factory=dict)
    notes: Text = ""
    configuration: dict[Text, Any] = Field(description="the full stand configuration snapshot")
    created: datetime
    ended: datetime | None = None
    batches: int = Field(default=0, description="batches stored")
    rows: dict[str, int] = Field(default_factory=dict, description="rows stored per channel group")
    key_results: dict[str, float] = Field(
        default_factory=dict, description="a few headline results for the runs list"
    )
    imported_from: ImportedFrom | None = Field(
        default=None,
        description="for a run imported from an .eln archive (POST /runs/import): the "
        "original run and server; null for a run recorded here",
    )
    damage: str | None = Field(
        default=None,
        description="what is wrong with a damaged run: it is listed, but cannot be read "
        "(`rigserver check` reports it); null for a sound run",
    )
    corrections: int = Field(
        default=0,
        description="corrections of its readings stored (a cell corrected or a row struck "
        "out, each with its reason: GET /runs/{id}/corrections); the values as typed are kept",
    )
    corrected_after_finish: bool = Field(
        default=False,
        description="true once a reading was corrected after the run finished (its results "
        "and reports were made again)",
    )
    configuration_given: dict[Text, Source] | None = Field(
        default=None,
        description="where each configuration value given for this run came from, by its "
        "dotted path (the file and its map, or the operator); a value not named here is the "
        "stand's default; null for a run opened before this was recorded",
    )

    def from_default(self, path: str) -> bool:
        """Whether the configuration's value at ``path`` (dotted) is the stand's default,
        given by nobody for this run (False when that was not recorded)."""
        given = self.configuration_given
        return given is not None and path not in given


class RunQuery(BaseModel):
    """Filters of the runs list; all optional, newest first."""

    stand: StandKind | None = None
    operator: Text | None = None
    state: RunState | None = None
    since: UtcTime | None = None
    until: UtcTime | None = None
    limit: int = Field(default=50, ge=1, le=500)
    offset: int = Field(default=0, ge=0)


class RunPage(BaseModel):
    total: int
    runs: list[Run]
