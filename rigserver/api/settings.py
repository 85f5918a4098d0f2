"""Settings of the service, from the environment (prefix ``RIG_``) or the command line."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

from platformdirs import user_data_dir
from pydantic import Field
from pydantic_settings import BaseSettings, SettingsConfigDict


def default_data_dir() -> Path:
    """``./data`` if it exists (a checkout), else the user's data directory."""
    local = Path("data")
    return local if local.is_dir() else Path(user_data_dir("rig", appauthor=False))


@dataclass(frozen=True)
class Flag:
    """How a setting is given on ``rigserver serve``'s command line, where it differs from
    the rule (every setting a flag named after it, ``data_dir`` as ``--data-dir``)."""

    #: The flag's name without the dashes, where the setting's own does not read well
    name: str | None = None
    #: Not on the command line at all: a secret, which a command line shows to every user
    #: of the machine (``ps``)
    env_only: bool = False


class Settings(BaseSettings):
    """The service's settings: each one a field here, read from the environment (``RIG_``
    and the name in capitals) and from the flag of ``rigserver serve`` derived from it
    (:class:`Flag`), the flag winning."""

    model_config = SettingsConfigDict(env_prefix="RIG_", frozen=True)

    data_dir: Path = Field(default_factory=default_data_dir, description="where runs are stored")
    keys_file: Path | None = Field(default=None, description="JSON list of API keys and scopes")
    stands_file: Path | None = Field(
        default=None, description="JSON of the lab's stand configuration overrides"
    )
    public_reads: bool = Field(default=False, description="reads need no key")
    max_body_bytes: int = Field(default=64 << 20, gt=0, description="largest request body")
    import_max_bytes: int = Field(
        default=1 << 30,
        gt=0,
        description="largest .eln archive that POST /runs/import takes",
    )
    import_unpacked_bytes: int = Field(
        default=8 << 30,
        gt=0,
        description="most bytes the members of an imported archive may declare unpacked "
        "(more is refused as a zip bomb); each is read no further than it declares",
    )
    import_queue: int = Field(
        default=2,
        gt=0,
        description="archives imported at once (POST /runs/import); more are answered 503",
    )
    import_key_share: float = Field(
        default=0.5,
        gt=0.0,
        le=1.0,
        description="share of the imports one API key (or one address without a key) may "
        "hold; more of its imports are answered 503",
    )
    import_disk_reserve: int = Field(
        default=256 << 20,
        ge=0,
        description="bytes an import leaves free on the disk it unpacks to; an archive "
        "whose members would leave less is answered 507",
    )
    license: str | None = Field(
        default=None,
        max_length=500,
        description="the licence stated in the .eln archives exported: an SPDX identifier "
        "(CC-BY-4.0) or the licence's address; none: no licence stated",
    )
    ingest_queue: int = Field(
        default=64, gt=0, description="batch posts admitted at once; more are answered 503"
    )
    ingest_queue_bytes: int = Field(
        default=64 << 20, gt=0, description="bytes of batch bodies admitted at once"
    )
    ingest_key_share: float = Field(
        default=0.25,
        gt=0.0,
        le=1.0,
        description="share of the ingest queue (posts and bytes) one API key may hold; "
        "more of its posts are answered 503",
    )
    body_timeout: float = Field(
        default=60.0, gt=0.0, description="seconds a request body may take to arrive; 408 after"
    )
    retry_after: int = Field(
        default=1, ge=0, description="seconds in the Retry-After of a 503 or 429"
    )
    rate_limit: float = Field(
        default=0.0,
        ge=0.0,
        description="requests per second allowed to one key (or one address without a key); "
        "0 means no limit",
    )
    rate_burst: int = Field(default=200, gt=0, description="requests allowed in a burst")
    cors_origins: Annotated[tuple[str, ...], Flag(name="cors-origin")] = Field(
        default=(), description="an origin allowed by CORS, repeatable; none by default"
    )
    results_workers: int = Field(
        default=2,
        gt=0,
        description="runs whose results are computed at once; a request that would start "
        "one more is answered 503",
    )
    report_workers: int = Field(
        default=1,
        gt=0,
        description="processes rendering reports (beside the service's own, which ingest "
        "and answer reads)",
    )
    report_queue: int = Field(
        default=4,
        gt=0,
        description="report renders admitted at once (running or waiting); more are answered 503",
    )
    report_key_share: float = Field(
        default=0.5,
        gt=0.0,
        le=1.0,
        description="share of the report renders one API key (or one address without a "
        "key) may hold; more of its renders are answered 503",
    )
    reports_on_finish: bool = Field(
        default=True,
        description="render a finished run's reports at once, in the background (off: at "
        "their first download)",
    )
    report_processes: bool = Field(
        default=True,
        description="render the reports of ended runs in processes of their own (off: in "
        "threads of the service)",
    )
    synchronous: Literal["normal", "full"] = Field(
        default="normal",
        description="journal durability: 'normal' survives a crash, 'full' a power loss",
    )
    database_url: str | None = Field(
        default=None,
        description="PostgreSQL URL of a cluster's catalogue and journal (several rigservers "
        "share it); none: the embedded store in data_dir. Run files are then materialised "
        "into data_dir, which the workers may share",
    )
    hsds_endpoint: str | None = Field(
        default=None,
        description="HSDS service holding a cluster's run arrays (needs database_url and "
        "the cluster extra; http+unix://... for a unix socket); none: the journal only",
    )
    hsds_username: str = Field(default="rig", description="HSDS user")
    hsds_password: Annotated[str, Flag(env_only=True)] = Field(
        default="", description="HSDS password (set it in the env)"
    )
    hsds_bucket: str = Field(default="rig", description="HSDS bucket of the run domains")
    hsds_reads: bool = Field(
        default=False,
        description="read the rows materialised in HSDS from there; off: every read from "
        "the PostgreSQL journal (faster on one machine, docs/scale-out.md)",
    )
