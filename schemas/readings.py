"""Batches of readings on the wire and the receipt the service answers with."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, StringConstraints

GroupName = Annotated[str, StringConstraints(pattern=r"^[a-z][a-z0-9_]{0,39}$")]

#: Content type of the binary batch form: a NumPy ``.npz`` archive, one 1-D array per channel.
NPZ_MEDIA_TYPE = "application/x-npz"
#: Content type of a channel group read back as an Apache Arrow IPC stream (``format=arrow``).
ARROW_MEDIA_TYPE = "application/vnd.apache.arrow.stream"


class ReadingBatch(BaseModel):
    """One batch of readings of one channel group, as columns.

    ``seq`` is the client's sequence number for this batch, unique within the run: a batch
    posted again with the same ``seq`` (a retry) is stored once and answered with the same
    receipt.
    """

    model_config = ConfigDict(
        extra="forbid",
        strict=True,  # no "1.5" or true for a reading, no "3" for a seq
        json_schema_extra={
            "examples": [
                {
                    "seq": 0,
                    "group": "friction",
                    "columns": {
                        "time": [0.0, 0.5, 1.0],
                        "load": [300.0, 300.0, 301.0],
                        "speed": [1000.0, 1000.0, 999.0],
                        "friction_moment": [2.9, 3.1, 3.0],
                        "revolutions": [0.0, 0.0, 0.0],
                    },
                }
            ]
        },
    )

    seq: int = Field(ge=0, le=2**62, description="client sequence number, unique in the run")
    group: GroupName = Field(description="the channel group, e.g. 'friction'")
    columns: dict[str, list[float]] = Field(description="channel name -> values")


class BatchReceipt(BaseModel):
    """The answer to a stored batch; the same for a retried one (``duplicate`` true)."""

    run_id: str
    seq: int
    group: str
    rows: int = Field(description="rows in this batch")
    group_rows: int = Field(description="rows of the group stored after this batch")
    duplicate: bool = Field(default=False, description="true when this seq was stored before")
