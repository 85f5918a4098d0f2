"""Rendered reports kept as files, named by everything they are made of.

A report is a function of the run (its metadata, state and readings version: the catalogue
entry, whose batch count grows with every batch stored, a late measurement included), the
student's own words on it (their version, :mod:`rigserver.storage.notes`), the language,
the format, and the code and templates that render it. The file of a report is named by
the digest of all of these, so a changed run, new words, a new member of a series or a new
deployment names a new file, and the old one is never served again: nothing here knows
what a report contains. The digest is also the answer's ``ETag``.

Where: ``<data_dir>/reports/<run|series>/<id>/<lang>-<digest>.<html|pdf>``, beside the
``runs/`` of the embedded store. A cluster's workers materialise run files into their
``data_dir``; when they share it (a network file system), they share the reports too, and
otherwise each worker renders its own copy (the same bytes but for the time it was made).
Writing a new version removes the older files of the same report.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import rigserver
import schemas
from rigserver.reports.i18n import Lang
from schemas.runs import Run
from schemas.series import Series
from schemas.sketches import Sketch
from schemas.student_notes import StudentNotes

#: Formats and their media types.
MEDIA_TYPES = {"html": "text/html; charset=utf-8", "pdf": "application/pdf"}
#: Files of the code whose change may change a report (templates, catalogs, fonts too).
_CODE_SUFFIXES = frozenset({".py", ".html", ".css", ".po", ".mo", ".json", ".svg", ".ttf"})


@lru_cache(maxsize=1)
def code_version() -> str:
    """The digest of the service's code, templates and message catalogs as deployed: a new
    deployment renders its reports anew (read once per process)."""
    digest = hashlib.sha256()
    for package in (rigserver, schemas):
        root = Path(next(iter(package.__path__)))
        for path in sorted(root.rglob("*")):
            if path.suffix in _CODE_SUFFIXES and "__pycache__" not in path.parts:
                digest.update(str(path.relative_to(root)).encode())
                digest.update(path.read_bytes())
    return digest.hexdigest()


def run_version(run: Run) -> str:
    """What a run's report shows of the run: its catalogue entry (metadata, state, results'
    headline, batches and rows per group)."""
    return run.model_dump_json()


def notes_version(notes: StudentNotes) -> str:
    """What a run's report shows of the student's words: the words, their version and who
    wrote them when (a new version is a new report, even with the same words)."""
    return notes.model_dump_json()


def series_version(series: Series, runs: Iterable[Run]) -> str:
    """What a series report shows: the series (members, levels) and each member's version."""
    return series.model_dump_json() + "".join(run_version(run) for run in runs)


@dataclass(frozen=True, slots=True)
class ReportFile:
    """Where one report is (or will be) kept, and its ETag."""

    path: Path
    etag: str
    fmt: str
    lang: Lang

    @property
    def media_type(self) -> str:
        return MEDIA_TYPES[self.fmt]

    @property
    def render(self) -> str:
        """The name of the render that makes this version in every format (one job writes
        the page and the PDF): a download of either joins it while it runs."""
        return str(self.path.with_suffix(""))

    def sibling(self, fmt: str) -> ReportFile:
        """The same report in another format."""
        return ReportFile(self.path.with_suffix(f".{fmt}"), self.etag, fmt, self.lang)

    def matches(self, if_none_match: str | None) -> bool:
        """Whether ``If-None-Match`` names this version."""
        if not if_none_match:
            return False
        tags = {t.strip().removeprefix("W/") for t in if_none_match.split(",")}
        return self.etag in tags or "*" in tags

    def prune(self) -> None:
        """Remove the older versions of this report (same kind, id, language, format)."""
        for old in self.path.parent.glob(f"{self.lang}-*.{self.fmt}"):
            if old != self.path:
                old.unlink(missing_ok=True)


class ReportFiles:
    """The reports of one service, under ``root``; ``salt`` names what else renders them
    (the lab's stand configuration)."""

    def __init__(self, root: Path, salt: str = "") -> None:
        self.root = root
        self._salt = salt

    def run_report(
        self,
        run: Run,
        lang: Lang,
        fmt: str,
        notes: StudentNotes | None = None,
        sketches: Iterable[Sketch] = (),
    ) -> ReportFile:
        """The run's report; with the student's ``notes`` on it (None: never written) and
        their ``sketches`` (the version of each item's it prints)."""
        version = run_version(run) + notes_version(notes or StudentNotes())
        version += "".join(sketch.model_dump_json() for sketch in sketches)
        return self._file("run", run.id, version, lang, fmt)

    def series_report(
        self,
        series: Series,
        runs: Iterable[Run],
        lang: Lang,
        fmt: str,
        notes: Iterable[StudentNotes] = (),
        sketches: Iterable[Sketch] = (),
    ) -> ReportFile:
        """A series report; a lab work's prints its runs' ``notes`` and ``sketches`` too
        (their versions name it)."""
        version = series_version(series, runs) + "".join(map(notes_version, notes))
        version += "".join(sketch.model_dump_json() for sketch in sketches)
        return self._file("series", series.id, version, lang, fmt)

    def _file(self, kind: str, ident: str, version: str, lang: Lang, fmt: str) -> ReportFile:
        key = "\n".join((code_version(), self._salt, kind, ident, version, lang))
        digest = hashlib.sha256(key.encode()).hexdigest()[:32]
        path = self.root / kind / ident / f"{lang}-{digest}.{fmt}"
        return ReportFile(path, f'"{digest}"', fmt, lang)
