"""A series' ``.eln`` export whose reports are not all rendered yet (issue 39, item 10).

An archive packs each member run's report and the series report in both languages. Rendered
inline, the first export of a series of 100 runs took one request 498 s. Now the request
that finds reports missing starts their renders in the background (on the report pool,
one after another, under the export's share) and is answered at once: 202, with
``Retry-After`` and the progress. The same request asked again answers 202 with the
progress until every report is kept, then 200 with the archive (packing kept files takes
seconds). The series page shows the progress (``/series/{id}/export.eln/status``).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from rigserver.api.problems import ApiProblem

log = logging.getLogger("rigserver")

Render = Callable[[], object]
"""One missing report, rendered (and kept) when called; blocks until it is."""


@dataclass
class Progress:
    """The background renders of one series' export."""

    total: int
    done: int = 0
    failed: str | None = None
    running: bool = True


class SeriesExports:
    """The exports being prepared, by series id (one at a time per series)."""

    def __init__(self, stopping: threading.Event, retry_after: float) -> None:
        self._stopping = stopping
        self._retry_after = retry_after
        self._lock = threading.Lock()
        self._progress: dict[str, Progress] = {}

    def progress(self, series_id: str) -> Progress | None:
        """The export's progress, if one is or was being prepared."""
        with self._lock:
            return self._progress.get(series_id)

    def start(self, series_id: str, missing: Sequence[Render]) -> Progress:
        """Render ``missing`` in the background, unless this series' are being rendered; a
        failed attempt is given back once (to be said), and the next call starts anew."""
        with self._lock:
            found = self._progress.get(series_id)
            if found is not None and (found.running or found.failed):
                if found.failed:
                    del self._progress[series_id]
                return found
            progress = Progress(total=len(missing))
            self._progress[series_id] = progress
        threading.Thread(
            target=self._render,
            args=(progress, list(missing)),
            name=f"export {series_id}",
            daemon=True,
        ).start()
        return progress

    def _render(self, progress: Progress, missing: list[Render]) -> None:
        try:
            for render in missing:
                while not self._stopping.is_set():
                    try:
                        render()
                        break
                    except ApiProblem as busy:  # the pool, or the export's share, is full
                        if busy.problem.status != 503:
                            raise
                        time.sleep(self._retry_after)
                if self._stopping.is_set():
                    return
                progress.done += 1
        except Exception as exc:  # the archive cannot be made: said on the next request
            progress.failed = str(exc) or type(exc).__name__
            log.warning("a series export's reports could not be rendered: %s", progress.failed)
        finally:
            progress.running = False
