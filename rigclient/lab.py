"""The read side of rigclient: the lab's runs, readings and results as pandas frames.

::

    from rigclient import Lab

    lab = Lab("http://rig:8000", key)          # key: one with ``read`` (or None if public)
    run = lab.runs(stand="mtos")[0]            # newest first, paged transparently
    df = run.readings("steps")                 # one column per channel, df.attrs["units"]
    run.results(lang="ru")                     # quantity, symbol, value, uncertainty, unit

Readings travel as an Apache Arrow IPC stream (``format=arrow``), never as JSON: the
columnar form pandas takes without parsing a number (:mod:`rigserver.reports.arrow` on the
server says why). The stream is read on a connection of its own with the standard
library's ``http.client``, straight into one buffer of the answer's stated length that the
frame's columns then use as they are: httpx takes a body 64 KiB at a time, and a run of ten
million readings would spend most of its time there (docs/speed.md, "The reader").

Needs the ``frames`` extra (pandas and pyarrow); the rest of rigclient does not. Every
failure is a :class:`~rigclient.errors.RigclientError` that says what failed and where: the
API's problem document (:class:`~rigclient.errors.ServerRefused`: a key without ``read`` is
a 401/403 saying so) or the transport's error with the method and URL
(:class:`~rigclient.errors.ServerUnavailable`).
"""

from __future__ import annotations

import contextlib
import http.client
import json
import ssl
import time
from collections.abc import Iterator, Mapping
from datetime import datetime
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any
from urllib.parse import urlencode, urlsplit

import certifi
import httpx
import numpy as np

from rigclient.errors import RigclientError, ServerRefused, ServerUnavailable
from rigclient.http import API, USER_AGENT, problem_of
from schemas.readings import ARROW_MEDIA_TYPE
from schemas.runs import Run, RunState

if TYPE_CHECKING:
    import pandas as pd

PAGE = 500
"""Runs asked for in one page of the list (the API's largest)."""
RESUME_ATTEMPTS = 20
"""Reconnections in a row without a new event before :meth:`LabRun.follow` gives up."""
RESUME_DELAY = 1.0
"""Seconds between a dropped live stream and its reconnection (doubling, at most 10 s)."""
DOWNLOAD_WAIT = 600.0
"""Seconds :meth:`LabRun.download` waits for a file rendered in the background."""

DOWNLOADS: dict[str, tuple[str, dict[str, str]]] = {
    "report.pdf": ("report.pdf", {}),
    "report.html": ("report.html", {}),
    "export.eln": ("export.eln", {}),
    "export.zip": ("export.zip", {}),
    "results.csv": ("results.csv", {}),
    "hdf5": ("readings", {"format": "hdf5"}),
}
"""What :meth:`LabRun.download` fetches: the run's path below ``/runs/{id}/`` and query."""


def _frames() -> tuple[Any, Any]:
    """pandas and pyarrow, or a line that says how to install them."""
    try:
        import pandas
        import pyarrow
    except ImportError as e:
        raise RigclientError(
            f"rigclient.Lab needs pandas and pyarrow ({e.name} is missing): "
            "pip install 'rigclient[frames]' (or 'rig[frames]' from a clone of rig)"
        ) from e
    return pandas, pyarrow


class Lab:
    """A rig service, read: its runs and series.

    Parameters
    ----------
    url : str
        The service, e.g. ``http://rig:8000``.
    key : str, optional
        An API key with the ``read`` scope; None where the service has public reads.
    timeout : float
        Seconds for a connection and between two pieces of an answer.
    transport : httpx.BaseTransport, optional
        For tests: a transport to use instead of the network.
    """

    def __init__(
        self,
        url: str,
        key: str | None = None,
        *,
        timeout: float = 60.0,
        transport: httpx.BaseTransport | None = None,
    ) -> None:
        headers = {"User-Agent": USER_AGENT}
        if key is not None:
            headers["Authorization"] = f"Bearer {key}"
        self.url = url.rstrip("/")
        self._headers = headers
        self._timeout = timeout
        self._http = httpx.Client(
            base_url=self.url + API,
            headers=headers,
            timeout=httpx.Timeout(timeout),
            transport=transport,
        )

    def close(self) -> None:
        self._http.close()

    def __enter__(self) -> Lab:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Lab({self.url!r})"

    # -- the lab's runs and series ------------------------------------------------------

    def runs(
        self,
        *,
        stand: str | None = None,
        operator: str | None = None,
        state: str | RunState | None = None,
        since: datetime | str | None = None,
        until: datetime | str | None = None,
    ) -> list[LabRun]:
        """Every run that matches the filters, newest first (the pages of the list read
        one after another)."""
        query: dict[str, str] = {}
        for name, value in (("stand", stand), ("operator", operator), ("state", state)):
            if value is not None:
                query[name] = str(getattr(value, "value", value))
        for name, when in (("since", since), ("until", until)):
            if when is not None:
                query[name] = when.isoformat() if isinstance(when, datetime) else when
        found: list[LabRun] = []
        while True:
            page = self.get_json("/runs", {**query, "limit": str(PAGE), "offset": str(len(found))})
            found.extend(LabRun(self, Run.model_validate(r)) for r in page["runs"])
            if not page["runs"] or len(found) >= page["total"]:
                return found

    def run(self, run_id: str) -> LabRun:
        """One run, by its id."""
        return LabRun(self, Run.model_validate(self.get_json(f"/runs/{run_id}")))

    def series(self, series_id: str) -> LabSeries:
        """One series of runs, with its statistics."""
        return LabSeries(self.get_json(f"/series/{series_id}"))

    def every_series(self, *, stand: str | None = None) -> list[LabSeries]:
        """Every series of the lab, newest first; with ``stand``, those of its runs."""
        found = [self.series(s["id"]) for s in self.get_json("/series")]
        return [s for s in found if stand is None or s.detail.get("stand") == stand]

    # -- one request --------------------------------------------------------------------

    def get(self, path: str, params: Mapping[str, str] | None = None) -> httpx.Response:
        """``GET`` below ``/api/v1``; a refusal or a failure raised as rigclient says it."""
        url = f"{self.url}{API}{path}"
        try:
            response = self._http.get(path, params=params)
        except httpx.HTTPError as e:
            raise ServerUnavailable(f"GET {url}: {e}") from e
        _raise_for(response, url)
        return response

    def get_json(self, path: str, params: Mapping[str, str] | None = None) -> Any:
        return self.get(path, params).json()

    @contextlib.contextmanager
    def stream(
        self, path: str, params: Mapping[str, str] | None = None, **headers: str
    ) -> Iterator[httpx.Response]:
        """A streamed ``GET``, closed when the block ends."""
        url = f"{self.url}{API}{path}"
        try:
            request = self._http.build_request("GET", path, params=params, headers=headers)
            response = self._http.send(request, stream=True)
        except httpx.HTTPError as e:
            raise ServerUnavailable(f"GET {url}: {e}") from e
        try:
            if response.is_error:
                response.read()
                _raise_for(response, url)
            yield response
        finally:
            response.close()

    def body(self, path: str, params: Mapping[str, str]) -> tuple[np.ndarray, str]:
        """A ``GET``'s whole body, read into one buffer of its stated length (bytes as
        ``uint8``), and its media type; a refusal or a failure raised as :meth:`get`."""
        url = f"{self.url}{API}{path}?{urlencode(params)}"
        where = urlsplit(url)
        connection: http.client.HTTPConnection
        if where.scheme == "https":
            tls = ssl.create_default_context(cafile=certifi.where())
            connection = http.client.HTTPSConnection(
                where.netloc, timeout=self._timeout, context=tls
            )
        else:
            connection = http.client.HTTPConnection(where.netloc, timeout=self._timeout)
        try:
            connection.request("GET", f"{where.path}?{where.query}", headers=self._headers)
            answer = connection.getresponse()
            if answer.status >= 300 or answer.getheader("Content-Length") is None:
                _raise_for(_as_httpx(answer, url), url)
                raise ServerUnavailable(f"GET {url}: the answer did not state its length")
            buffer = np.empty(int(answer.getheader("Content-Length", "0")), dtype=np.uint8)
            view, got = buffer.data, 0
            while got < len(buffer):
                n = answer.readinto(view[got:])
                if not n:
                    raise ServerUnavailable(
                        f"GET {url}: the answer broke off after {got} of {len(buffer)} bytes"
                    )
                got += n
            return buffer, answer.getheader("Content-Type", "")
        except (OSError, http.client.HTTPException) as e:
            raise ServerUnavailable(f"GET {url}: {e}") from e
        finally:
            connection.close()


def _as_httpx(answer: http.client.HTTPResponse, url: str) -> httpx.Response:
    """An ``http.client`` answer as httpx's, to be read as every other answer is."""
    return httpx.Response(
        answer.status,
        headers=answer.getheaders(),
        content=answer.read(),
        request=httpx.Request("GET", url),
    )


def _raise_for(response: httpx.Response, url: str) -> None:
    if response.is_success:
        return
    if response.status_code < 500:
        raise ServerRefused(problem_of(response), method="GET", url=url)
    raise ServerUnavailable(f"GET {url}: {response.status_code} {response.reason_phrase}")


class LabRun:
    """One run of the lab, read: its readings, results, steps, live rows and files.

    ``info`` is the run as the API describes it (stand, state, operator, title, rows, ...).
    """

    def __init__(self, lab: Lab, info: Run) -> None:
        self._lab = lab
        self.info = info

    @property
    def id(self) -> str:
        return self.info.id

    @property
    def stand(self) -> str:
        return self.info.stand.value

    @property
    def state(self) -> str:
        return self.info.state.value

    def __repr__(self) -> str:
        title = f" {self.info.title!r}" if self.info.title else ""
        return f"<LabRun {self.id} {self.stand} {self.state}{title}>"

    def _group(self, group: str | None) -> str:
        if group is not None:
            return group
        stand = self._lab.get_json(f"/stands/{self.stand}")
        return str(next(g["name"] for g in stand["groups"] if g.get("aligned", True)))

    def readings(self, group: str | None = None, *, original: bool = False) -> pd.DataFrame:
        """A channel group as a frame: one float64 column per channel, one row per reading
        (a group of single measurements: one row of the latest values).
        ``df.attrs["units"]`` holds each channel's unit; the values are as corrected, or
        as typed with ``original=True``. Without ``group``, the stand's record."""
        _, pyarrow = _frames()
        chosen = self._group(group)
        params = {"group": chosen, "format": "arrow"}
        if original:
            params["original"] = "true"
        path = f"/runs/{self.id}/readings"
        body, media_type = self._lab.body(path, params)
        if ARROW_MEDIA_TYPE not in media_type:
            raise RigclientError(
                f"GET {self._lab.url}{API}{path}: the server did not answer with an Arrow "
                f"stream ({media_type!r}): is it an older rig?"
            )
        table = pyarrow.ipc.open_stream(pyarrow.py_buffer(body)).read_all()
        frame = table.to_pandas(split_blocks=True)  # a block a column: no copy into one
        frame.attrs["units"] = {
            f.name: (f.metadata or {}).get(b"unit", b"").decode() for f in table.schema
        }
        frame.attrs["group"] = chosen
        frame.attrs["run"] = self.id
        return frame

    def results(self, lang: str = "en") -> pd.DataFrame:
        """The single results as the pages list them, one row each, indexed by the result's
        path: ``quantity`` (the manual's words and equation), ``symbol``, ``value`` and
        ``uncertainty`` (standard, GUM) in the display ``unit``, ``part``."""
        pandas, _ = _frames()
        rows = self._lab.get_json(f"/runs/{self.id}/results/table", {"lang": lang})
        columns = ["quantity", "symbol", "value", "uncertainty", "unit", "part"]
        frame = pandas.DataFrame(rows, columns=["path", *columns])
        return frame.set_index("path")

    def payload(self) -> dict[str, Any]:
        """The results as the API gives them (``values``, ``units``, ...)."""
        payload: dict[str, Any] = self._lab.get_json(f"/runs/{self.id}/results")
        return payload

    def steps(self) -> pd.DataFrame:
        """The test's steps, one row each in order (the MTOS load steps, a tribometer's
        recipe steps), one column per result of a step; ``df.attrs["units"]`` their units.
        Empty for a run without steps."""
        pandas, _ = _frames()
        payload = self.payload()
        steps = payload.get("values", {}).get("steps") or []
        frame = pandas.DataFrame([_flat(step) for step in steps])
        units: Mapping[str, str] = payload.get("units", {})
        frame.attrs["units"] = {
            column: units[f"steps[].{column}"]
            for column in frame.columns
            if f"steps[].{column}" in units
        }
        return frame

    def follow(self, group: str | None = None, *, start: int = 0) -> Iterator[pd.DataFrame]:
        """The rows of a group as they arrive: a frame for each piece, indexed by row number,
        from row ``start`` on; ends when the run has ended and every row was given. A dropped
        connection is resumed where it broke (no row lost or repeated)."""
        pandas, _ = _frames()
        chosen = self._group(group)
        seen, failures = start, 0
        while True:
            try:
                with self._lab.stream(
                    f"/runs/{self.id}/live",
                    {"group": chosen, "from": str(start)},
                    **{"Last-Event-ID": str(seen)},
                ) as response:
                    for name, data in _events(response):
                        failures = 0
                        if name == "end":
                            return
                        if name == "rows" and data["stop"] > seen:
                            columns = {
                                k: [float("nan") if v is None else v for v in values]
                                for k, values in data["columns"].items()
                            }
                            rows = pandas.RangeIndex(data["start"], data["stop"])
                            frame = pandas.DataFrame(columns, index=rows)
                            fresh = frame.loc[seen:] if data["start"] < seen else frame
                            seen = data["stop"]
                            yield fresh
            except (ServerUnavailable, httpx.HTTPError) as e:
                failures += 1
                if failures > RESUME_ATTEMPTS:
                    raise ServerUnavailable(
                        f"the live rows of run {self.id} stopped after row {seen}: {e}"
                    ) from e
            else:  # the server closed the stream (its lifetime): resume at once
                continue
            time.sleep(min(10.0, RESUME_DELAY * 2 ** (failures - 1)))

    def download(self, kind: str, path: str | Path, *, lang: str | None = None) -> Path:
        """A file of the run written to ``path``: ``report.pdf``, ``report.html``,
        ``export.eln``, ``export.zip``, ``results.csv`` or ``hdf5`` (the run's file). A
        report still being rendered is waited for."""
        if kind not in DOWNLOADS:
            raise RigclientError(f"download {kind!r}: choose one of {', '.join(DOWNLOADS)}")
        where, params = DOWNLOADS[kind]
        query = dict(params)
        if lang is not None:
            query["lang"] = lang
        target = Path(path)
        deadline = time.monotonic() + DOWNLOAD_WAIT
        while True:
            with self._lab.stream(f"/runs/{self.id}/{where}", query) as response:
                if response.status_code != 202:  # not a report rendered in the background
                    partial = target.with_name(target.name + ".part")
                    with partial.open("wb") as out:
                        for piece in response.iter_bytes():
                            out.write(piece)
                    partial.replace(target)
                    return target
                wait = float(response.headers.get("retry-after", "1"))
            if time.monotonic() + wait > deadline:
                raise ServerUnavailable(
                    f"the {kind} of run {self.id} was not ready in {DOWNLOAD_WAIT:.0f} s"
                )
            time.sleep(min(wait, 5.0))


def _flat(row: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """A step's results as columns: a mapping (the MTOS rises ``t2``..``t5``) one column
    per entry (``delta_t.t2``)."""
    out: dict[str, Any] = {}
    for key, value in row.items():
        if isinstance(value, Mapping):
            out.update(_flat(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def _events(response: httpx.Response) -> Iterator[tuple[str, Any]]:
    """Server-sent events as ``(name, data)``; comments and ``retry:`` lines skipped."""
    name, data = "message", list[str]()
    for line in response.iter_lines():
        if not line:
            if data:
                yield name, json.loads("\n".join(data))
            name, data = "message", []
        elif line.startswith("event:"):
            name = line[6:].strip()
        elif line.startswith("data:"):
            data.append(line[5:].strip())


class LabSeries:
    """A series of runs, read: its members and the statistics of its results."""

    def __init__(self, detail: Mapping[str, Any]) -> None:
        self.detail = detail

    @property
    def id(self) -> str:
        return str(self.detail["id"])

    @property
    def name(self) -> str:
        return str(self.detail["name"])

    def __repr__(self) -> str:
        return f"<LabSeries {self.id} {self.name!r} {len(self.detail.get('runs', []))} runs>"

    def members(self) -> pd.DataFrame:
        """One row per member run: its level, stand, state, operator, title, creation time
        and headline results (one column each), indexed by run id."""
        pandas, _ = _frames()
        rows = [
            {
                "run_id": r["run_id"],
                "level": r.get("level"),
                "stand": r["stand"],
                "state": r["state"],
                "operator": r["operator"],
                "title": r.get("title", ""),
                "created": pandas.Timestamp(r["created"]),
                **r.get("values", {}),
            }
            for r in self.detail.get("runs", [])
        ]
        return pandas.DataFrame(rows).set_index("run_id") if rows else pandas.DataFrame()

    def statistics(self) -> pd.DataFrame:
        """One row per headline result (and per level, where the series has levels): its
        symbol, unit, n, mean, s, standard error, confidence interval; indexed by the
        result's key and level (None: every run)."""
        pandas, _ = _frames()
        rows = []
        for stat in self.detail.get("statistics", []):
            head = {"key": stat["key"], "symbol": stat["symbol"], "unit": stat["unit"]}
            if stat.get("overall"):
                rows.append({**head, "level": None, **_summary(stat["overall"])})
            for level in stat.get("levels", []):
                rows.append({**head, "level": level["level"], **_summary(level["summary"])})
        frame = pandas.DataFrame(rows)
        return frame.set_index(["key", "level"]) if rows else frame


def _summary(summary: Mapping[str, Any]) -> dict[str, Any]:
    keys = ("n", "mean", "std", "sem", "ci_low", "ci_high", "confidence")
    return {k: summary.get(k) for k in keys}
