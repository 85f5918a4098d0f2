"""An ``.eln`` archive read back, trusting nothing: what an import of a run takes.

The archive is refused (:class:`ArchiveRefused`, naming the member and what is wrong) when
it is no zip; when a member's name climbs out of the archive (``..``, an absolute path, a
backslash, a drive) or is given twice; when it has not one root folder holding
``ro-crate-metadata.json``; when the metadata is no JSON-LD crate, or no crate that rig
made (no ``#rig`` software, no ``run.json``), or holds other than one run; when a file the
metadata describes is missing, or a member is not described; when the sizes it declares
add up to more than the unpacked limit (a zip bomb) or a member's size differs from the
``contentSize`` the metadata gives; when a member inflates to other than its declared size
or its CRC, or its SHA-256 differs from the metadata's. Every member is read (never more
than its declared size), and the members an import needs are written into a directory.

The order bounds what a hostile archive costs (:class:`RunArchive`): the zip's directory
first (names, the sizes declared); then ``run.json`` alone, read into memory, so that the
run is checked and the caller's scope with it before anything else is unpacked; then the
metadata and every member. Nothing is written before the members to be written are known to
fit the disk (less the reserve of
:class:`ImportLimits`); each is written no further than it declares,
looking at the free space again as it goes, and a run file must begin as an HDF5 file does.
"""

from __future__ import annotations

import hashlib
import re
import shutil
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import IO, Any

from pydantic import TypeAdapter, ValidationError

from rigserver.reports.eln import (
    METADATA,
    NOTES,
    REFERENCES,
    SKETCH_NAME,
    SKETCH_SUFFIXES,
    SKETCHES,
    SOFTWARE,
    term,
)
from schemas.strict_json import JsonRefused, strict_loads
from schemas.student_notes import StudentNotes

#: The metadata of an archive is at most this large (bytes, unpacked).
METADATA_BYTES = 32 << 20
#: rig's own JSON members (run.json, results.json) are at most this large.
JSON_BYTES = 64 << 20
#: The free space is looked at again after every this many bytes written.
ROOM_STEP = 64 << 20
#: The first bytes of an HDF5 file (a run file).
HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
_DRIVE = re.compile(r"^[A-Za-z]:")


class ArchiveRefused(Exception):
    """The archive cannot be imported; ``member`` names the part that is wrong."""

    def __init__(self, member: str, detail: str) -> None:
        super().__init__(f"{member}: {detail}")
        self.member = member
        self.detail = detail


class NoRoom(ArchiveRefused):
    """The archive is not refused, but this server's disk has no room for it now."""


@dataclass(frozen=True)
class ArchivedRun:
    """A run's archive, checked, its needed members written under ``directory``.

    ``run_json`` is the text of ``run.json``; ``run_file`` the run's HDF5 file;
    ``references`` the files of the profilometer runs it names, by run id; ``sketches`` the
    students' sketches, by their member's name (item, version and media type); ``notes``
    every version of the students' words, the first first; ``server`` the address of the
    server that exported it.
    """

    directory: Path
    run_id: str
    run_json: bytes
    run_file: Path
    server: str
    exported: str
    references: dict[str, Path] = field(default_factory=dict)
    sketches: dict[str, ArchivedSketch] = field(default_factory=dict)
    notes: list[StudentNotes] = field(default_factory=list)


@dataclass(frozen=True)
class ArchivedSketch:
    """A sketch's file of the archive: its item, version, media type, where it is written."""

    item: int
    version: int
    media_type: str
    path: Path


def _checked_name(name: str) -> PurePosixPath:
    """A member's path, if it stays inside the archive."""
    if not name or "\\" in name or "\0" in name or name.startswith("/") or _DRIVE.match(name):
        raise ArchiveRefused(name[:200], "a member's name must be a relative path (path traversal)")
    path = PurePosixPath(name)
    if any(part in ("..", ".", "") for part in name.rstrip("/").split("/")):
        raise ArchiveRefused(name[:200], "a member's name must not climb (path traversal)")
    return path


def json_member(name: str, data: bytes) -> Any:
    """A JSON member's value, read strictly (:mod:`schemas.strict_json`: no key twice, no
    nesting beyond its limit)."""
    try:
        return strict_loads(data)
    except JsonRefused as exc:
        raise ArchiveRefused(name, str(exc)) from None
    except ValueError as exc:
        raise ArchiveRefused(name, f"the member is no JSON: {exc}") from None


def _as_list(value: Any) -> list[Any]:
    if value is None:
        return []
    return value if isinstance(value, list) else [value]


def _ids(value: Any) -> list[str]:
    return [str(v["@id"]) for v in _as_list(value) if isinstance(v, dict) and "@id" in v]


def _types(node: Mapping[str, Any]) -> list[str]:
    return [str(t) for t in _as_list(node.get("@type"))]


@dataclass(frozen=True)
class ImportLimits:
    """What an import may unpack: ``unpacked`` bytes declared by all the members together,
    and what it writes to disk leaving at least ``reserve`` bytes free there."""

    unpacked: int
    reserve: int


class RunArchive:
    """The archive of one run being read (module docstring), in three steps: opened (its
    directory checked, nothing unpacked), :meth:`run_json` (read into memory, so that the
    caller checks the run and the caller's scope before anything else is unpacked), then
    :meth:`extract` (every member checked, those an import needs written)."""

    def __init__(self, source: IO[bytes], limits: ImportLimits) -> None:
        try:
            self._zip = zipfile.ZipFile(source)
        except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
            raise ArchiveRefused("archive", f"not a zip archive ({exc})") from None
        self.limits = limits
        try:
            self._members = _members(self._zip, limits.unpacked)
            self._root = _root(self._members)
        except BaseException:
            self._zip.close()
            raise
        self._run_json: bytes | None = None
        self._run_json_name = ""

    def __enter__(self) -> RunArchive:
        return self

    def __exit__(self, *exc: object) -> None:
        self._zip.close()

    def run_json(self) -> bytes:
        """The text of the run's ``run.json`` (at most :data:`JSON_BYTES`), found by its
        place (``<root>/<run id>/run.json``); the metadata's word on it is checked by
        :meth:`extract`."""
        found = [
            name for name in self._members if name.endswith("/run.json") and name.count("/") == 2
        ]
        if len(found) != 1:
            raise ArchiveRefused(
                METADATA,
                f"the archive holds {len(found)} runs; an import takes the archive of one "
                "run (GET /api/v1/runs/{id}/export.eln)",
            )
        info = self._members[found[0]]
        self._run_json_name = info.filename
        if info.file_size > JSON_BYTES:
            raise ArchiveRefused(info.filename, f"oversized member: more than {JSON_BYTES} bytes")
        self._run_json = _read(self._zip, info, limit=JSON_BYTES)
        return self._run_json

    def extract(self, directory: Path) -> ArchivedRun:
        """Check every member and write the run file and the files it references into
        ``directory``: their declared sizes within the disk's free space (less the
        reserve) before any is written, each written no further than it declares."""
        archive, members, root = self._zip, self._members, self._root
        graph = _graph(archive, members, root)
        run_dataset, server, exported = _rig_run(graph)
        files = _described_files(graph, members, root)
        parts = {str(p) for p in _ids(run_dataset.get("hasPart"))}
        run_id = str(run_dataset.get("identifier", ""))
        folder = str(run_dataset["@id"])
        if self._run_json is None or self._run_json_name != f"{root}/{folder}run.json":
            raise ArchiveRefused(f"{folder}run.json", "the run's folder has no run.json")
        wanted: dict[str, Path | None] = {
            f"{folder}run.json": None,
            f"{folder}{run_id}.h5": directory / "run.h5",
        }
        references: dict[str, Path] = {}
        for part in parts:
            if part.startswith(f"{folder}{REFERENCES}/") and part.endswith(".h5"):
                other = part.removeprefix(f"{folder}{REFERENCES}/").removesuffix(".h5")
                references[other] = directory / f"reference-{len(references)}.h5"
                wanted[part] = references[other]
        sketches = _sketches(folder, parts, directory)
        wanted.update({name: s.path for name, s in sketches.items()})
        notes = f"{folder}{NOTES}"
        if notes in parts:
            wanted[notes] = directory / NOTES
        for needed in wanted:
            if needed not in parts:
                raise ArchiveRefused(needed, "the run's Dataset does not name this file")
        checked = {
            entity_id: _declared(members[f"{root}/{entity_id}"], node)
            for entity_id, node in files.items()
        }
        written = sum(members[f"{root}/{e}"].file_size for e, out in wanted.items() if out)
        room(directory, written, self.limits.reserve, f"{folder}{run_id}.h5")
        # the members that are only checked first: a lie among them costs no writing
        for entity_id in sorted(files, key=lambda e: wanted.get(e) is not None):
            out = wanted.get(entity_id)
            info = members[f"{root}/{entity_id}"]
            hdf5 = entity_id not in sketches and entity_id != notes
            _verify(archive, info, checked[entity_id], out, self.limits, hdf5=hdf5)
        return ArchivedRun(
            directory=directory,
            run_id=run_id,
            run_json=self._run_json,
            run_file=directory / "run.h5",
            server=server,
            exported=exported,
            references=references,
            sketches=sketches,
            notes=_notes(notes, directory / NOTES) if notes in wanted else [],
        )


def _notes(name: str, path: Path) -> list[StudentNotes]:
    """Every version of the students' words, checked as the API checks a write."""
    try:
        return _NOTES.validate_python(json_member(name, path.read_bytes()))
    except ValidationError as exc:
        first = exc.errors(include_url=False)[0]
        where = ".".join(str(p) for p in first["loc"])
        raise ArchiveRefused(name, f"{where}: {first['msg']}") from None


_NOTES = TypeAdapter(list[StudentNotes])


def _sketches(folder: str, parts: set[str], directory: Path) -> dict[str, ArchivedSketch]:
    """The students' sketches among the run's ``parts`` (each written to ``directory``)."""
    found = {}
    for part in sorted(parts):
        if not part.startswith(f"{folder}{SKETCHES}/"):
            continue
        named = SKETCH_NAME.fullmatch(part.removeprefix(f"{folder}{SKETCHES}/"))
        if named is None:
            raise ArchiveRefused(part, "not a sketch's name (sketches/item-<n>-v<k>.png or .jpg)")
        item, version, suffix = int(named[1]), int(named[2]), named[3]
        out = directory / f"sketch-{item}-{version}.{suffix}"
        found[part] = ArchivedSketch(item, version, SKETCH_SUFFIXES[suffix], out)
    return found


def _members(archive: zipfile.ZipFile, unpacked_limit: int) -> dict[str, zipfile.ZipInfo]:
    """The archive's files by name: names checked, none twice, the sizes they declare
    within the limit."""
    found: dict[str, zipfile.ZipInfo] = {}
    total = 0
    for info in archive.infolist():
        _checked_name(info.filename)
        if info.filename in found or (info.is_dir() and info.filename in found):
            raise ArchiveRefused(info.filename, "the member is in the archive twice")
        if info.flag_bits & 0x1:
            raise ArchiveRefused(info.filename, "the member is encrypted")
        total += info.file_size
        if total > unpacked_limit:
            raise ArchiveRefused(
                info.filename,
                f"the members declare more than {unpacked_limit} bytes unpacked, the most "
                "this server unpacks (a zip bomb?)",
            )
        found[info.filename] = info
    return {name: info for name, info in found.items() if not info.is_dir()}


def _root(members: Mapping[str, zipfile.ZipInfo]) -> str:
    roots = {name.split("/", 1)[0] for name in members}
    outside = [name for name in members if "/" not in name]
    if outside:
        raise ArchiveRefused(outside[0], "every file of an .eln archive is in its root folder")
    if len(roots) != 1:
        shown = ", ".join(sorted(roots)[:5])
        raise ArchiveRefused("archive", f"an .eln archive has one root folder, not {shown}")
    root = roots.pop()
    if f"{root}/{METADATA}" not in members:
        raise ArchiveRefused(
            f"{root}/{METADATA}", "no metadata: the root folder has no " + METADATA
        )
    return root


def _graph(
    archive: zipfile.ZipFile, members: Mapping[str, zipfile.ZipInfo], root: str
) -> dict[str, dict[str, Any]]:
    name = f"{root}/{METADATA}"
    info = members[name]
    if info.file_size > METADATA_BYTES:
        raise ArchiveRefused(name, f"the metadata is larger than {METADATA_BYTES} bytes")
    document = json_member(name, _read(archive, info, limit=METADATA_BYTES))
    if not isinstance(document, dict) or not isinstance(document.get("@graph"), list):
        raise ArchiveRefused(name, "the metadata is no JSON-LD with a @graph")
    graph: dict[str, dict[str, Any]] = {}
    for node in document["@graph"]:
        if not isinstance(node, dict) or not isinstance(node.get("@id"), str):
            raise ArchiveRefused(name, "every entity of the @graph has an @id")
        if node["@id"] in graph:
            raise ArchiveRefused(name, f"the entity {node['@id'][:100]!r} is described twice")
        graph[node["@id"]] = node
    descriptor = graph.get(METADATA)
    if descriptor is None or "./" not in _ids(descriptor.get("about")) or "./" not in graph:
        raise ArchiveRefused(name, "not an RO-Crate: no metadata descriptor about ./")
    return graph


def _rig_run(graph: Mapping[str, dict[str, Any]]) -> tuple[dict[str, Any], str, str]:
    """The one run's Dataset of a crate rig made, the server's address, the export's date."""
    software = graph.get(SOFTWARE)
    if software is None or software.get("name") != "rig":
        raise ArchiveRefused(METADATA, "not an archive made by rig (no #rig software)")
    root = graph["./"]
    runs = [
        graph[p]
        for p in _ids(root.get("hasPart"))
        if p in graph and term("TribologicalTesting") in _ids(graph[p].get("additionalType"))
    ]
    if len(runs) != 1:
        raise ArchiveRefused(
            METADATA,
            f"the archive holds {len(runs)} runs; an import takes the archive of one run "
            "(GET /api/v1/runs/{id}/export.eln)",
        )
    descriptor = graph[METADATA]
    publishers = _ids(descriptor.get("sdPublisher"))
    server = publishers[0] if publishers else ""
    return runs[0], server, str(descriptor.get("dateCreated", ""))


def _described_files(
    graph: Mapping[str, dict[str, Any]], members: Mapping[str, zipfile.ZipInfo], root: str
) -> dict[str, dict[str, Any]]:
    """The File entities, each with its member; every member but the metadata described."""
    files = {
        entity_id: node
        for entity_id, node in graph.items()
        if "File" in _types(node) and not entity_id.startswith(("#", "http://", "https://"))
    }
    for entity_id in files:
        if f"{root}/{entity_id}" not in members:
            raise ArchiveRefused(f"{root}/{entity_id}", "missing member: the metadata describes it")
    described = {f"{root}/{entity_id}" for entity_id in files} | {f"{root}/{METADATA}"}
    for name in members:
        if name not in described:
            raise ArchiveRefused(name, "the member is not described in the metadata")
    return files


def _declared(info: zipfile.ZipInfo, node: Mapping[str, Any]) -> str:
    """The member's SHA-256 as the metadata gives it, once its size is the metadata's."""
    name = info.filename
    declared, sha256 = node.get("contentSize"), node.get("sha256")
    if not isinstance(declared, str) or not declared.isascii() or not declared.isdigit():
        raise ArchiveRefused(name, f"the metadata gives no contentSize in bytes ({declared!r:.40})")
    if not isinstance(sha256, str):
        raise ArchiveRefused(name, "the metadata gives no sha256")
    if info.file_size != int(declared):
        raise ArchiveRefused(
            name,
            f"oversized member: {info.file_size} bytes in the zip, {declared} in the metadata"
            if info.file_size > int(declared)
            else f"{info.file_size} bytes in the zip, {declared} in the metadata",
        )
    if name.endswith(".json") and info.file_size > JSON_BYTES:
        raise ArchiveRefused(name, f"oversized member: more than {JSON_BYTES} bytes")
    return sha256.lower()


def room(directory: Path, needed: int, reserve: int, name: str) -> None:
    """Refuse (:class:`NoRoom`) when writing ``needed`` more bytes into ``directory``
    would leave less than ``reserve`` free on its disk."""
    free = shutil.disk_usage(directory).free
    if needed > free - reserve:
        raise NoRoom(
            name,
            f"the import would write {needed} bytes where {free} are free and "
            f"{reserve} are kept free",
        )


def _verify(
    archive: zipfile.ZipFile,
    info: zipfile.ZipInfo,
    sha256: str,
    out: Path | None,
    limits: ImportLimits,
    *,
    hdf5: bool = True,
) -> None:
    """Read the member whole (writing it to ``out`` if given, an HDF5 file unless not
    ``hdf5``), counting: never more than its declared size, the disk's free space looked at
    every :data:`ROOM_STEP` bytes written; its SHA-256 the metadata's."""
    name = info.filename
    digest = hashlib.sha256()
    seen = 0
    target: IO[bytes] | None = None
    try:
        with archive.open(info) as member:
            while piece := member.read(1 << 20):
                seen += len(piece)
                if seen > info.file_size:
                    raise ArchiveRefused(name, f"unpacks to more than {info.file_size} bytes")
                digest.update(piece)
                if out is None:
                    continue
                if target is None:
                    if hdf5 and not piece.startswith(HDF5_SIGNATURE):
                        raise ArchiveRefused(name, "the member is no HDF5 file")
                    target = out.open("wb")
                if seen // ROOM_STEP != (seen - len(piece)) // ROOM_STEP:
                    room(out.parent, len(piece), limits.reserve, name)
                target.write(piece)
    except (zipfile.BadZipFile, OSError, EOFError, ValueError, NotImplementedError) as exc:
        raise ArchiveRefused(
            name, f"the member does not unpack to what it declares ({exc})"
        ) from None
    finally:
        if target is not None:
            target.close()
    if seen != info.file_size:
        raise ArchiveRefused(name, f"unpacks to {seen} bytes, declares {info.file_size}")
    if digest.hexdigest() != sha256:
        raise ArchiveRefused(name, "checksum mismatch: its SHA-256 is not the metadata's")


def _read(archive: zipfile.ZipFile, info: zipfile.ZipInfo, *, limit: int) -> bytes:
    try:
        with archive.open(info) as member:
            data = member.read(limit + 1)
    except (zipfile.BadZipFile, OSError, EOFError, ValueError, NotImplementedError) as exc:
        raise ArchiveRefused(info.filename, f"the member does not unpack ({exc})") from None
    if len(data) > limit:
        raise ArchiveRefused(info.filename, f"oversized member: more than {limit} bytes")
    return data
