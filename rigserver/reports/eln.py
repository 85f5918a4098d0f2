"""Runs and series as ``.eln`` archives: the ELN consortium's zipped RO-Crate 1.1.

The layout (``docs/eln.md`` maps rig's entities to the crate)::

    <run id>.eln
      <run id>/                      the one root folder (the archive's name)
        ro-crate-metadata.json       JSON-LD, flattened: every entity once, linked by @id
        <run id>/                    the run: a Dataset (tribAIn TribologicalTesting)
          <run id>.h5                the run file (NeXus/HDF5)
          run.json, results.json     rig's own metadata and results (what an import reads)
          results.csv, results_<table>.csv, <group>.csv   the tidy CSVs (reports.export)
          report-en.pdf|html, report-ru.pdf|html          the report in both languages
          references/<run id>.h5     the profilometer runs the run's specimen names
          sketches/item-<n>-v<k>.png|jpg   the students' sketches, every version
          notes.json                 the students' words (conclusions, ...), every version

A series' archive holds one such folder per run and the series' own folder (``series.json``
with the statistics, ``runs.csv``, its report); each run's Dataset is ``isPartOf`` the
series' (the ELN format keeps Datasets out of a Dataset's ``hasPart``).

Entities use schema.org types, with the classes of the tribAIn ontology (Kügler et al.,
CC-BY 4.0, ``http://ktmfk.de/ontology/tribAIn/``) as ``additionalType`` where one fits, and
as the ``identifier`` of a PropertyValue (the ELN format's way of naming its meaning).
Every member's ``contentSize`` and ``sha256`` are counted as it is written; the metadata is
the archive's last member. Reading an archive back is :mod:`rigserver.reports.eln_read`.
"""

from __future__ import annotations

import hashlib
import json
import re
import zipfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import IO, Any
from urllib.parse import quote

from pydantic import BaseModel

from rigserver.analysis import Readings
from rigserver.reports import results_view
from rigserver.reports.export import DIALECTS, export_members
from rigserver.reports.i18n import Messages
from schemas import labelled
from schemas.labels import plain_symbol
from schemas.quantity import units_of
from schemas.runs import Run, RunState
from schemas.series import SeriesDetail
from schemas.stands import Stand
from schemas.student_notes import StudentNotes
from schemas.units import UNITS

ELN_MEDIA_TYPE = "application/vnd.eln+zip"
RO_CRATE = "https://w3id.org/ro/crate/1.1"
CONTEXT = f"{RO_CRATE}/context"
METADATA = "ro-crate-metadata.json"
TRIBAIN = "http://ktmfk.de/ontology/tribAIn/"
#: The software entity; an archive without it was not made by rig.
SOFTWARE = "#rig"
#: A result's standard and expanded uncertainty live beside it under these suffixes.
UNCERTAINTY, EXPANDED = "_uncertainty", "_expanded"
REFERENCES = "references"
#: The students' sketches, every version: ``sketches/item-<n>-v<k>.png`` (or ``.jpg``).
SKETCHES = "sketches"
SKETCH_NAME = re.compile(r"item-([1-9][0-9]?)-v([1-9][0-9]{0,5})\.(png|jpg)")
#: The media type of a sketch, by suffix.
SKETCH_SUFFIXES = {"png": "image/png", "jpg": "image/jpeg"}
#: The students' words on the run, every version (a JSON list of StudentNotes, first first).
NOTES = "notes.json"


def sketch_member(item: int, version: int, media_type: str) -> str:
    """The name of a sketch's file in a run's folder."""
    suffix = next(s for s, t in SKETCH_SUFFIXES.items() if t == media_type)
    return f"{SKETCHES}/item-{item}-v{version}.{suffix}"


JSON = "application/json"
CSV = "text/csv"
HDF5 = "application/x-hdf5"
#: The media types of the reports, by suffix.
REPORT_TYPES = {"pdf": "application/pdf", "html": "text/html"}

#: UN/CEFACT Recommendation 20 codes (schema.org's unitCode) of rig's units; the others
#: have a unitText only.
UNIT_CODES: dict[str, str] = {
    "1": "C62",
    "s": "SEC",
    "min": "MIN",
    "N": "NEW",
    "N*m": "NU",
    "kg": "KGM",
    "g": "GRM",
    "mg": "MGM",
    "m": "MTR",
    "mm": "MMT",
    "um": "4H",
    "rad": "C81",
    "deg": "DD",
    "rpm": "RPM",
    "rad/s": "2A",
    "Pa": "PAL",
    "MPa": "MPA",
    "at": "ATT",
    "atm": "ATM",
    "Pa*s": "C65",
    "degC": "CEL",
    "kg/m^3": "KMQ",
    "N/m": "4P",
    "m^2": "MTK",
    "mm^2": "MMK",
    "m^3": "MTQ",
    "mm^3": "MMQ",
    "%": "P1",
}

#: tribAIn classes of results and test-plan entries, by the last part of their path.
TERMS: dict[str, str] = {
    "friction_steady": "CoefficientOfFriction",
    "friction_fluid": "CoefficientOfFriction",
    "friction_measured": "CoefficientOfFriction",
    "mean_load": "NormalForce",
    "load": "NormalForce",
    "load_N": "NormalForce",
    "friction_force": "FrictionForce",
    "sliding_distance": "SlidingDistance",
    "revolutions": "SlidingCycle",
    "duration": "Runtime",
    "volume": "WearVolume",
    "temperature": "Temperature",
    "speed_rpm": "RotationSpeed",
    "contour_pressure": "ContactPressure",
    "real_contact_pressure": "ContactPressure",
    "pressure_max": "Pressure",
    "base_length": "Length",
    "ra": "Ra",
    "rz": "Rz",
    "rq": "Rq",
    "journal_rq": "Rq",
    "bush_rq": "Rq",
}

#: tribAIn's role of a specimen by its role in rig (the body the stand studies and the
#: counter-body it runs against).
ROLES: dict[str, str] = {
    "pin": "Body",
    "ball": "Body",
    "disc": "CounterBody",
    "journal": "CounterBody",
    "bush": "Body",
    "bearing": "Body",
}

_STATUS = {
    RunState.OPEN: "ActiveActionStatus",
    RunState.FINISHED: "CompletedActionStatus",
    RunState.ABORTED: "FailedActionStatus",
}

Node = dict[str, Any]


def term(name: str) -> str:
    """The IRI of a tribAIn class."""
    return TRIBAIN + name


def kind(*names: str) -> Any:
    """``additionalType``: the tribAIn classes as links (one, or a list)."""
    links = [ref(term(n)) for n in names]
    return links[0] if len(links) == 1 else links


def ref(entity_id: str) -> dict[str, str]:
    return {"@id": entity_id}


def rig_version() -> str:
    try:
        return metadata.version("rig")
    except metadata.PackageNotFoundError:  # a checkout that was never installed
        return "unknown"


@dataclass(frozen=True, slots=True)
class Licence:
    """The licence a server states for what it exports: its address, its name and what
    it says in words (for a licence without an address of its own)."""

    id: str
    name: str
    description: str = ""


#: The ``@id`` of the licence an archive names when the server states none.
NO_LICENCE = "#no-licence"


def no_licence(publisher: Publisher) -> Licence:
    """What an archive of a server without ``--license`` names as its licence (RO-Crate 1.1
    requires one): that no licence was granted, and whom to ask."""
    return Licence(
        NO_LICENCE,
        "No licence granted",
        "No licence to reuse this data has been granted; ask the lab that runs "
        f"{publisher.name} for permission",
    )


def licence_of(text: str | None) -> Licence | None:
    """The licence a server's setting names: an address as it is, anything else as an
    SPDX identifier (``CC-BY-4.0``); None for no setting."""
    if text is None or not text.strip():
        return None
    text = text.strip()
    if text.startswith(("http://", "https://")):
        return Licence(text, text)
    return Licence(f"https://spdx.org/licenses/{quote(text)}", text)


@dataclass(frozen=True, slots=True)
class Publisher:
    """The server the archive comes from: its base address (``http://host:port/``)."""

    url: str

    @property
    def name(self) -> str:
        return f"rig server at {self.url}"

    def run_url(self, run_id: str) -> str:
        return f"{self.url.rstrip('/')}/api/v1/runs/{run_id}"


@dataclass(frozen=True)
class RunPart:
    """What a run's folder of an archive holds.

    ``reports`` maps a file name (``report-en.pdf``) to its content; ``references`` maps a
    profilometer run's id that the run's specimen names to that run and its file.
    """

    run: Run
    stand: Stand
    readings: Readings
    payload: Mapping[str, Any]
    run_file: Path
    reports: Mapping[str, bytes] = field(default_factory=dict)
    references: Mapping[str, tuple[Run, Path]] = field(default_factory=dict)
    #: the students' sketches, every version: :func:`sketch_member` -> the image
    sketches: Mapping[str, bytes] = field(default_factory=dict)
    #: the students' words, every version, the first first
    notes: Sequence[StudentNotes] = ()


@dataclass(frozen=True)
class SeriesPart:
    """What a series' folder holds: its statistics, the per-run table, its reports."""

    detail: SeriesDetail
    runs_csv: str
    reports: Mapping[str, bytes] = field(default_factory=dict)


class Crate:
    """An ``.eln`` archive being written: members streamed into ``target`` under the root
    folder, the graph gathered as they go; :meth:`close` writes the metadata."""

    def __init__(
        self,
        target: IO[bytes],
        root: str,
        *,
        made: datetime,
        publisher: Publisher,
        licence: Licence | None,
    ) -> None:
        self.root = root
        self.made = made.astimezone(UTC)
        self.publisher = publisher
        self.licence = licence if licence is not None else no_licence(publisher)
        self.graph: dict[str, Node] = {}
        self._zip = zipfile.ZipFile(target, "w", compression=zipfile.ZIP_DEFLATED)
        self._date = self.made.timetuple()[:6]
        self.add(
            {
                "@id": SOFTWARE,
                "@type": "SoftwareApplication",
                "name": "rig",
                "version": rig_version(),
                "description": "Data acquisition and analysis for tribology test stands "
                "(SMTs-2, slide bearing, MTOS, ABRIS-PM7)",
            }
        )
        described: Node = {"@id": self.licence.id, "@type": "CreativeWork"}
        described["name"] = self.licence.name
        if self.licence.description:
            described["description"] = self.licence.description
        self.add(described)

    def add(self, node: Node) -> str:
        """Put an entity in the graph, once: a second node with the same ``@id`` adds its
        links to the first's (a stand's limits of error over several runs); other values
        must agree."""
        entity_id = str(node["@id"])
        found = self.graph.get(entity_id)
        if found is None:
            self.graph[entity_id] = dict(node)
            return entity_id
        for key, value in node.items():
            if key not in found:
                found[key] = value
            elif found[key] != value:
                if not (_is_links(found[key]) and _is_links(value)):
                    raise ValueError(f"entity {entity_id}: {key} is {found[key]!r} and {value!r}")
                found[key] = _union(found[key], value)
        return entity_id

    def file(
        self,
        path: str,
        pieces: Iterable[bytes],
        *,
        encoding: str,
        description: str,
        **more: Any,
    ) -> str:
        """Write a member (``path`` under the root folder) from its pieces, and its File
        entity with the size and SHA-256 counted on the way."""
        info = zipfile.ZipInfo(f"{self.root}/{path}", date_time=self._date)
        info.compress_type = zipfile.ZIP_DEFLATED
        digest = hashlib.sha256()
        size = 0
        with self._zip.open(info, "w", force_zip64=True) as member:
            for piece in pieces:
                member.write(piece)
                digest.update(piece)
                size += len(piece)
        return self.add(
            {
                "@id": path,
                "@type": "File",
                "name": path.rsplit("/", 1)[-1],
                "description": description,
                "encodingFormat": encoding,
                "contentSize": str(size),
                "sha256": digest.hexdigest(),
                "dateCreated": _iso(self.made),
                **more,
            }
        )

    def close(self, *, name: str, description: str, parts: Sequence[str]) -> None:
        """Write the metadata (the root Dataset naming ``parts``) and close the archive."""
        publisher = self.publisher.url
        self.add(
            {
                "@id": publisher,
                "@type": "Organization",
                "name": self.publisher.name,
                "url": publisher,
            }
        )
        root: Node = {
            "@id": "./",
            "@type": "Dataset",
            "name": name,
            "description": description,
            "datePublished": _iso(self.made),
            "hasPart": [ref(p) for p in parts],
            "publisher": ref(publisher),
        }
        authors = [ref(i) for i, node in self.graph.items() if node.get("@type") == "Person"]
        if authors:
            root["author"] = authors
        root["license"] = ref(self.licence.id)
        descriptor: Node = {
            "@id": METADATA,
            "@type": "CreativeWork",
            "about": ref("./"),
            "conformsTo": ref(RO_CRATE),
            "dateCreated": _iso(self.made),
            "sdPublisher": ref(publisher),
        }
        graph = [descriptor, root, *self.graph.values()]
        text = json.dumps({"@context": CONTEXT, "@graph": graph}, indent=1, ensure_ascii=False)
        info = zipfile.ZipInfo(f"{self.root}/{METADATA}", date_time=self._date)
        info.compress_type = zipfile.ZIP_DEFLATED
        self._zip.writestr(info, text.encode())
        self._zip.close()

    def abandon(self) -> None:
        self._zip.close()


def _is_links(value: Any) -> bool:
    items = value if isinstance(value, list) else [value]
    return all(isinstance(v, dict) and set(v) == {"@id"} for v in items)


def _union(a: Any, b: Any) -> list[Any]:
    found: list[Any] = []
    for item in [*(a if isinstance(a, list) else [a]), *(b if isinstance(b, list) else [b])]:
        if item not in found:
            found.append(item)
    return found


def _iso(moment: datetime) -> str:
    return moment.astimezone(UTC).isoformat().replace("+00:00", "Z")


def _slug(text: str) -> str:
    return quote(text.strip() or "-", safe="")


def _chunks(path: Path, size: int = 1 << 20) -> Iterator[bytes]:
    with path.open("rb") as source:
        while piece := source.read(size):
            yield piece


# --- a run ---------------------------------------------------------------------------


def add_run(crate: Crate, part: RunPart, *, series: str | None = None) -> str:
    """Write the run's folder and describe it; the id of its Dataset."""
    run, stand = part.run, part.stand
    folder = f"{run.id}/"
    files = [
        crate.file(
            f"{folder}{run.id}.h5",
            _chunks(part.run_file),
            encoding=HDF5,
            description="The run file: every reading of every channel group, the run's "
            "metadata and results (NeXus/HDF5)",
            additionalType=kind("MeasurementSeries"),
        )
    ]
    members = export_members(
        run=run,
        stand=stand,
        readings=part.readings,
        payload=part.payload,
        t=Messages("en"),
        dialect=DIALECTS["csv"],
    )
    for name, pieces in members:
        encoding = JSON if name.endswith(".json") else CSV
        files.append(
            crate.file(folder + name, pieces, encoding=encoding, description=_describe(name, stand))
        )
    files += _add_reports(crate, folder, part.reports, "The run's report")
    for name, image in part.sketches.items():
        found = SKETCH_NAME.fullmatch(name.removeprefix(f"{SKETCHES}/"))
        assert found is not None, name
        files.append(
            crate.file(
                folder + name,
                [image],
                encoding=SKETCH_SUFFIXES[found[3]],
                description=f"The students' sketch of item {found[1]} of the lab's report "
                f"list, version {found[2]}",
            )
        )
    if part.notes:
        words = [n.model_dump(mode="json") for n in part.notes]
        files.append(
            crate.file(
                folder + NOTES,
                [json.dumps(words, ensure_ascii=False, indent=1).encode()],
                encoding=JSON,
                description="The students' words on the run (group, names, conclusions, "
                "analysis, mismatch, observations), every version written, the first first",
            )
        )
    based_on = []
    for other_id, (other, path) in part.references.items():
        based_on.append(
            crate.file(
                f"{folder}{REFERENCES}/{other_id}.h5",
                _chunks(path),
                encoding=HDF5,
                description=f"The file of profilometer run {other_id} that the specimen "
                "names (its roughness enters the results)",
                identifier=other.id,
            )
        )
    return _describe_run(crate, part, folder, files, based_on, series)


def _add_reports(crate: Crate, folder: str, reports: Mapping[str, bytes], what: str) -> list[str]:
    """The reports (``report-<lang>.<pdf|html>``) as files of ``folder``."""
    found = []
    for name, content in reports.items():
        stem, suffix = name.rsplit(".", 1)
        lang = stem.rsplit("-", 1)[-1]
        found.append(
            crate.file(
                folder + name,
                [content],
                encoding=REPORT_TYPES[suffix],
                description=f"{what} ({lang})",
                inLanguage=lang,
            )
        )
    return found


def _describe(name: str, stand: Stand) -> str:
    if name == "run.json":
        return "The run's metadata as rig keeps it (an import reads it)"
    if name == "results.json":
        return "Every result in SI units, with its units, as rig computes it"
    if name == "results.csv":
        return "The single results: quantity, symbol, value, unit (display units)"
    if name.startswith("results_"):
        table = name.removeprefix("results_").removesuffix(".csv")
        return f"Results table {table}: a column per quantity, headed by name, symbol and unit"
    group = stand.group(name.removesuffix(".csv"))
    what = group.long_name if group is not None else name
    return f"Readings, {what}: one column per channel, headed name [unit]"


def _describe_run(
    crate: Crate,
    part: RunPart,
    folder: str,
    files: list[str],
    based_on: list[str],
    series: str | None,
) -> str:
    run, stand = part.run, part.stand
    operator = crate.add(
        {
            "@id": f"#person-{_slug(run.operator)}",
            "@type": "Person",
            "name": run.operator,
        }
    )
    stand_id = _add_stand(crate, run, stand)
    specimens = _add_specimens(crate, run)
    plan = _add_plan(crate, run)
    results = _add_results(crate, run, stand, part.payload)
    dataset: Node = {
        "@id": folder,
        "@type": "Dataset",
        "additionalType": kind("TribologicalTesting"),
        "name": run.title or f"{stand.title}: run {run.id}",
        "identifier": run.id,
        "url": crate.publisher.run_url(run.id),
        "author": ref(operator),
        "dateCreated": _iso(run.created),
        "creativeWorkStatus": run.state.value,
        "keywords": f"tribology, {stand.title}"
        + ("" if stand.lab_work is None else f", lab work {stand.lab_work}"),
        "hasPart": [ref(f) for f in files],
        "variableMeasured": [ref(v) for v in plan + results],
        "about": [ref(s) for s in specimens],
        "mentions": ref(stand_id),
    }
    if run.ended is not None:
        dataset["dateModified"] = _iso(run.ended)
        dataset["temporalCoverage"] = f"{_iso(run.created)}/{_iso(run.ended)}"
    if run.notes:
        dataset["description"] = run.notes
    if based_on:
        dataset["isBasedOn"] = [ref(b) for b in based_on]
    if series is not None:
        dataset["isPartOf"] = ref(series)
    dataset["license"] = ref(crate.licence.id)
    crate.add(dataset)
    action: Node = {
        "@id": f"#run-{run.id}",
        "@type": "CreateAction",
        "name": f"Run {run.id} on the {stand.title}",
        "agent": ref(operator),
        "instrument": [ref(stand_id), ref(SOFTWARE)],
        "object": [ref(s) for s in specimens],
        "result": ref(folder),
        "startTime": _iso(run.created),
        "actionStatus": {"@id": f"http://schema.org/{_STATUS[run.state]}"},
    }
    if run.ended is not None:
        action["endTime"] = _iso(run.ended)
    crate.add(action)
    return folder


def _add_stand(crate: Crate, run: Run, stand: Stand) -> str:
    """The stand (a tribAIn Device) with the limits of error its configuration declares
    for its instruments (a PropertyValue each, identified by its value)."""
    limits = []
    accuracy = run.configuration.get("accuracy")
    declared = getattr(stand.configuration, "accuracy", None)
    if isinstance(accuracy, Mapping) and isinstance(declared, BaseModel):
        fields = type(declared).model_fields
        units = units_of(type(declared))
        for key, value in accuracy.items():
            if key not in units or isinstance(value, bool) or not isinstance(value, int | float):
                continue
            node = _value_node(
                f"#stand-{stand.kind.value}/limit/{key}/{value!r}",
                name=f"limit of error: {key}",
                value=value,
                unit=units[key],
                property_id=f"configuration.accuracy.{key}",
                identifier=term("MeasurementError"),
                description=fields[key].description or "",
            )
            limits.append(crate.add(node))
    return crate.add(
        {
            "@id": f"#stand-{stand.kind.value}",
            "@type": "IndividualProduct",
            "additionalType": kind("Device"),
            "name": stand.title,
            "identifier": stand.kind.value,
            "description": "A commercial tribometer"
            if stand.lab_work is None
            else f"Test stand of lab work {stand.lab_work}",
            "additionalProperty": [ref(limit) for limit in limits],
        }
    )


def _add_specimens(crate: Crate, run: Run) -> list[str]:
    """The run's specimens (tribAIn Samples, in their role's Body or CounterBody) and
    their materials (once per name)."""
    found = []
    for role, value in run.specimen.items():
        if role.endswith("_profile_run"):  # a reference to a run, not a specimen
            continue
        text = str(value)
        material = crate.add(
            {
                "@id": f"#material-{_slug(text)}",
                "@type": "Product",
                "additionalType": kind("Material"),
                "name": text,
            }
        )
        roles = ("Sample", ROLES[role]) if role in ROLES else ("Sample",)
        found.append(
            crate.add(
                {
                    "@id": f"#run-{run.id}/specimen/{_slug(role)}",
                    "@type": "IndividualProduct",
                    "additionalType": kind(*roles),
                    "name": f"{role}: {text}",
                    "category": role,
                    "material": ref(material),
                }
            )
        )
    return found


def _add_plan(crate: Crate, run: Run) -> list[str]:
    """The test plan's entries; a key ending in a unit (``load_N``, ``speed_rpm``,
    ``base_length_mm``) gives its value that unit."""
    found = []
    for key, value in run.test_plan.items():
        text: Any = value if isinstance(value, str | int | float | bool) else json.dumps(value)
        unit = key.rsplit("_", 1)[-1] if "_" in key else None
        numeric = isinstance(value, int | float) and not isinstance(value, bool)
        found.append(
            crate.add(
                _value_node(
                    f"#run-{run.id}/plan/{_slug(key)}",
                    name=key,
                    value=text,
                    unit=unit if numeric and unit in UNITS else None,
                    property_id=f"test_plan.{key}",
                    identifier=term(TERMS[key]) if key in TERMS else None,
                    description="test plan",
                )
            )
        )
    return found


def _add_results(crate: Crate, run: Run, stand: Stand, payload: Mapping[str, Any]) -> list[str]:
    """The single results in SI (the stored unit, at full precision), each with its
    standard and expanded uncertainty where the analysis gives them."""
    entries = labelled.scalars(stand.kind, payload)
    by_path = {e.path: e for e in entries}
    t = Messages("en")
    found = []
    for e in entries:
        if e.path.endswith((UNCERTAINTY, EXPANDED)) and e.path.rsplit("_", 1)[0] in by_path:
            continue
        base = f"#run-{run.id}/result/{e.path}"
        value = e.value
        unit = e.stored if isinstance(value, int | float) and not isinstance(value, bool) else None
        leaf = e.path.rsplit(".", 1)[-1]
        references = []
        for suffix, words, k in (
            (UNCERTAINTY, "standard uncertainty u (GUM)", "1"),
            (EXPANDED, "expanded uncertainty U = k·u, k = 2 (GUM)", "2"),
        ):
            other = by_path.get(e.path + suffix)
            if other is None or not isinstance(other.value, int | float):
                continue
            references.append(
                crate.add(
                    _value_node(
                        base + suffix,
                        name=words,
                        value=other.value,
                        unit=other.stored,
                        property_id=f"results.{e.path}{suffix}",
                        identifier=term("MeasurementError"),
                        description=f"coverage factor k = {k}",
                    )
                )
            )
        node = _value_node(
            base,
            name=results_view.name(t, e.label),
            value=value,
            unit=unit,
            property_id=f"results.{e.path}",
            identifier=term(TERMS[leaf]) if leaf in TERMS else None,
            description=plain_symbol(e.label.symbol),
        )
        if references:
            node["valueReference"] = [ref(r) for r in references]
        found.append(crate.add(node))
    return found


def _value_node(
    entity_id: str,
    *,
    name: str,
    value: Any,
    unit: str | None,
    property_id: str,
    identifier: str | None,
    description: str,
) -> Node:
    node: Node = {
        "@id": entity_id,
        "@type": "PropertyValue",
        "name": name,
        "propertyID": property_id,
        "value": value,
    }
    if identifier is not None:
        node["identifier"] = identifier
    if unit is not None:
        node["unitText"] = unit
        if unit in UNIT_CODES:
            node["unitCode"] = UNIT_CODES[unit]
    if description:
        node["description"] = description
    return node


# --- archives --------------------------------------------------------------------------


def write_run_archive(
    target: IO[bytes],
    part: RunPart,
    *,
    made: datetime,
    publisher: Publisher,
    licence: Licence | None,
) -> None:
    """The ``.eln`` archive of one run into ``target``."""
    crate = Crate(target, part.run.id, made=made, publisher=publisher, licence=licence)
    try:
        dataset = add_run(crate, part)
    except BaseException:
        crate.abandon()
        raise
    crate.close(
        name=f"rig run {part.run.id}",
        description=f"Run {part.run.id} on the {part.stand.title}, exported by rig "
        f"{rig_version()} from {publisher.url}",
        parts=[dataset],
    )


def write_series_archive(
    target: IO[bytes],
    series: SeriesPart,
    runs: Iterable[RunPart],
    *,
    made: datetime,
    publisher: Publisher,
    licence: Licence | None,
) -> None:
    """The ``.eln`` archive of a series: its statistics and each run's folder."""
    detail = series.detail
    crate = Crate(target, detail.id, made=made, publisher=publisher, licence=licence)
    try:
        folder = f"{detail.id}/"
        parts = [folder]
        for part in runs:
            parts.append(add_run(crate, part, series=folder))
        _add_series(crate, series, folder, parts[1:])
    except BaseException:
        crate.abandon()
        raise
    crate.close(
        name=f"rig series {detail.name}",
        description=f"Series {detail.id} ({detail.purpose.value}) of {len(parts) - 1} runs, "
        f"exported by rig {rig_version()} from {publisher.url}",
        parts=parts,
    )


def _add_series(crate: Crate, series: SeriesPart, folder: str, runs: list[str]) -> None:
    detail = series.detail
    files = [
        crate.file(
            f"{folder}series.json",
            [detail.model_dump_json(indent=1).encode()],
            encoding=JSON,
            description="The series, its runs and the statistics of every headline result",
        ),
        crate.file(
            f"{folder}runs.csv",
            [series.runs_csv.encode()],
            encoding=CSV,
            description="The per-run table: one row per run, one column per headline result",
        ),
    ]
    files += _add_reports(crate, folder, series.reports, "The series report")
    statistics = []
    for stats in detail.statistics:
        if stats.overall is None:
            continue
        summary = stats.overall
        base = f"#series-{detail.id}/statistics/{_slug(stats.key)}"
        spread = []
        for key, words, value in (
            ("std", "sample standard deviation s", summary.std),
            ("sem", "standard error of the mean s/√n", summary.sem),
            ("repeatability", "repeatability standard deviation s_r", stats.repeatability_std),
        ):
            if value is None:
                continue
            spread.append(
                crate.add(
                    _value_node(
                        f"{base}/{key}",
                        name=words,
                        value=value,
                        unit=stats.unit,
                        property_id=f"statistics.{stats.key}.{key}",
                        identifier=term("RandomError"),
                        description="",
                    )
                )
            )
        node = _value_node(
            base,
            name=f"mean: {stats.description}",
            value=summary.mean,
            unit=stats.unit,
            property_id=f"statistics.{stats.key}.mean",
            identifier=term(TERMS[stats.key]) if stats.key in TERMS else None,
            description=f"mean of {summary.n} runs ({plain_symbol(stats.symbol)})",
        )
        if summary.ci_low is not None and summary.ci_high is not None:
            node["minValue"] = summary.ci_low
            node["maxValue"] = summary.ci_high
            node["description"] += (
                f"; {summary.confidence * 100:g} % confidence interval in minValue..maxValue"
            )
        if spread:
            node["valueReference"] = [ref(s) for s in spread]
        statistics.append(crate.add(node))
    dataset: Node = {
        "@id": folder,
        "@type": "Dataset",
        "additionalType": kind("TestSeries"),
        "name": detail.name,
        "identifier": detail.id,
        "dateCreated": _iso(detail.created),
        "keywords": f"tribology, series, {detail.purpose.value}",
        "hasPart": [ref(f) for f in files],
        "variableMeasured": [ref(s) for s in statistics],
        "mentions": [ref(r) for r in runs],
    }
    operators = sorted({r.operator for r in detail.runs})
    if operators:
        dataset["author"] = [ref(f"#person-{_slug(o)}") for o in operators]
    if detail.notes:
        dataset["description"] = detail.notes
    if detail.factor:
        dataset["measurementTechnique"] = f"comparison by {detail.factor}"
    dataset["license"] = ref(crate.licence.id)
    crate.add(dataset)
