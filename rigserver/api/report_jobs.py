"""One report render: what it needs (picklable, for the render pool's process) and the render.

A run that has ended is read from its final HDF5 file (:class:`FileReadings`), so a report
can be rendered in another process with nothing but the job: the run, its stand, its
results and the file's path. An open run's readings are only in its store: its job carries
them as a :class:`~rigserver.analysis.Readings` of this process and is rendered in a thread.
Each target file is written under a temporary name and renamed, so a reader never sees half
a report.
"""

from __future__ import annotations

import logging
import os
import signal
import threading
import time
from collections.abc import Iterator, Mapping
from contextlib import ExitStack
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rigserver.analysis import Readings
from rigserver.reports.i18n import Lang
from rigserver.reports.lab_work import WorkRun, build_lab_work, part_one
from rigserver.reports.pdf import html_to_pdf
from rigserver.reports.run_report import build_report, render_report
from rigserver.reports.series_report import render_series_report, series_context
from rigserver.storage.corrections import CorrectedReadings
from rigserver.storage.errors import RunDamaged
from rigserver.storage.runfile import RunFile
from schemas.corrections import Correction
from schemas.runs import Run
from schemas.series import SeriesDetail
from schemas.stands import MEASUREMENTS, Stand
from schemas.student_notes import StudentNotes

#: The loggers of the PDF renderer and its font library: their warnings about the report's
#: CSS and fonts ("Ignored `stroke: ...`", "Anchor defined twice", "Step 5 - Creating
#: layout") say nothing to the lab and thousands of lines of them buried the service's own.
QUIET_LOGGERS = ("weasyprint", "fontTools")


def quiet_renderer_logs() -> None:
    """Keep the renderer's and the font library's messages out of the service's log; a
    failed render is logged once by the service (:mod:`rigserver.api.report_pool`)."""
    for name in QUIET_LOGGERS:
        logger = logging.getLogger(name)
        logger.setLevel(logging.CRITICAL + 1)
        logger.propagate = False
        if not logger.handlers:
            logger.addHandler(logging.NullHandler())


#: Seconds between two looks of a render process at its parent (:func:`exit_with_parent`).
PARENT_POLL_SECONDS = 0.5


def exit_with_parent(parent: int) -> None:
    """End this process once ``parent`` is no longer its parent: the service has died (a
    ``kill -9``, the kernel's out-of-memory killer) and this process was handed to init.

    A render process waits on the pool's pipes, whose write ends it holds itself, and
    multiprocessing's resource tracker waits for the render process: neither would see
    the service go (issue 39, item 5). Looking at ``getppid`` is what every Unix offers
    (Linux's parent-death signal fires when the *thread* that started the process ends,
    which in a thread pool is any time).
    """
    while os.getppid() == parent:
        time.sleep(PARENT_POLL_SECONDS)
    os._exit(0)


def render_process_started() -> None:
    """A render process's start: the renderer's messages kept out of the log, Ctrl-C
    left to the service (a terminal sends SIGINT to the whole process group; the service
    stops its render processes as it stops, once the renders under way are done, instead
    of each printing a traceback), and an end with the service's (:func:`exit_with_parent`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    quiet_renderer_logs()
    threading.Thread(
        target=exit_with_parent, args=(os.getppid(),), name="exit-with-parent", daemon=True
    ).start()


class FileReadings(CorrectedReadings):
    """A run's readings from its HDF5 file (read-only, opened once per render), as
    corrected by the corrections the file holds, or as typed if ``original``."""

    def __init__(self, path: Path, stack: ExitStack, *, original: bool = False) -> None:
        rows = _FileRows(path, stack)
        super().__init__(rows, [] if original else rows.corrections())


class _FileRows:
    """A run's readings as its HDF5 file keeps them (as typed)."""

    def __init__(self, path: Path, stack: ExitStack) -> None:
        try:
            self._file = stack.enter_context(RunFile.open(path, writable=False))
        except OSError as exc:  # missing or not HDF5: the run's routes answer 409 for it
            raise RunDamaged(
                f"run {path.stem} is damaged: its file {path.name} cannot be read ({exc})"
            ) from None

    def rows(self, group: str) -> int:
        return self._file.rows(group)

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, NDArray[np.float64]]:
        if self.rows(group) == 0:
            return {}
        return self._file.read(group, channels, 0, None)

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        for start in range(0, self.rows(group), rows):
            yield self._file.read(group, channels, start, start + rows)

    def measurements(self) -> dict[str, float]:
        if self.rows(MEASUREMENTS) == 0:
            return {}
        return self._file.last_values(MEASUREMENTS)

    def corrections(self) -> list[Correction]:
        return self._file.corrections()


@dataclass(frozen=True)
class RunReportJob:
    """The report of one run in one language, written to ``targets`` (format -> file)."""

    run: Run
    stand: Stand
    values: Mapping[str, Any]
    lang: Lang
    targets: Mapping[str, Path]
    #: the final file of an ended run; None: ``readings`` (an open run, this process only)
    run_file: Path | None = None
    readings: Readings | None = field(default=None, compare=False)
    #: the student's own words on the run (rigserver.storage.notes)
    notes: StudentNotes | None = None
    #: the students' sketches on the run: item -> the image as a data: URI
    sketches: Mapping[int, str] = field(default_factory=dict)

    def render(self) -> None:
        with ExitStack() as stack:
            readings = self.readings
            if self.run_file is not None:
                readings = FileReadings(self.run_file, stack)
            assert readings is not None, "a job reads a run file or readings"
            report = build_report(
                run=self.run,
                stand=self.stand,
                values=self.values,
                readings=readings,
                lang=self.lang,
                made=datetime.now(UTC),
                notes=self.notes,
                sketches=self.sketches,
                corrections=readings.corrections if isinstance(readings, CorrectedReadings) else (),
            )
            html = render_report(report)
        write_targets(html, self.targets)


@dataclass(frozen=True)
class SeriesReportJob:
    """The report of a series in one language, written to ``targets``."""

    detail: SeriesDetail
    values: Mapping[str, Mapping[str, Any] | None]
    lang: Lang
    targets: Mapping[str, Path]
    #: member run id -> its final file; members missing here are in ``readings``
    run_files: Mapping[str, Path] = field(default_factory=dict)
    readings: Mapping[str, Readings] = field(default_factory=dict, compare=False)
    #: a lab work (purpose ``lab``): its runs at their parts, and their stand
    work: tuple[WorkRun, ...] = ()
    stand: Stand | None = None

    def render(self) -> None:
        with ExitStack() as stack:
            readings: dict[str, Readings] = dict(self.readings)
            for run_id, path in self.run_files.items():
                readings[run_id] = FileReadings(path, stack)
            main = part_one(self.stand.kind, self.work) if self.stand else None
            if self.stand is not None and main is not None:
                report = build_lab_work(
                    runs=self.work,
                    stand=self.stand,
                    readings=readings[main.run.id],
                    lang=self.lang,
                    made=datetime.now(UTC),
                )
                html = render_report(report)
            else:
                context = series_context(
                    self.detail, values=self.values, readings=readings, lang=self.lang
                )
                html = render_series_report(context, made=datetime.now(UTC))
        write_targets(html, self.targets)


Job = RunReportJob | SeriesReportJob


def render_job(job: Job) -> None:
    """The render pool's task (in its process or thread)."""
    job.render()


#: What :func:`warm_up` lays out: a heading and a line in Latin and Cyrillic, no report.
_BLANK = "<html><body><h1>rig</h1><p>0,1 Н·м</p></body></html>"


def warm_up() -> None:
    """Load WeasyPrint and the fonts by laying out a blank page (Matplotlib came with this
    module's import): the render process's first report then does not wait for them."""
    html_to_pdf(_BLANK)


def write_targets(html: str, targets: Mapping[str, Path]) -> None:
    """The page as ``html`` and ``pdf`` files where asked, each written whole or not at all."""
    for fmt, path in targets.items():
        data = html.encode() if fmt == "html" else html_to_pdf(html)
        write_atomically(path, data)


def write_atomically(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_bytes(data)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
