"""Reports rendered once per version and kept as files, on a bounded pool with a per-key share
(issue 25 item 1, issue 22 item 9)."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from rigserver.api import report_files, report_jobs
from rigserver.reports.run_report import build_report
from schemas.runs import Run
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, auth, in_process
from tests.reports.simulated import post, simulated

API = "/api/v1"
_T0 = datetime(2026, 11, 22, tzinfo=UTC)


@pytest.fixture
def renders(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The languages of the run reports built in this process, in order."""
    built: list[str] = []
    real = build_report

    def counting(**kwargs: Any) -> Any:
        built.append(kwargs["lang"])
        return real(**kwargs)

    monkeypatch.setattr(report_jobs, "build_report", counting)
    return built


@pytest.fixture
def threaded(tmp_path: Path) -> Iterator[TestClient]:
    """The service rendering in its threads (so that the renders can be counted here)."""
    with in_process(tmp_path, report_processes=False) as client:
        yield client


def test_a_report_is_rendered_once_and_served_with_its_etag(
    threaded: TestClient, renders: list[str], tmp_path: Path
) -> None:
    run_id = post(threaded, simulated(StandKind.PROFILOMETER).sim, WRITER, finish=False)
    url = f"{API}/runs/{run_id}/report.html"
    first = threaded.get(url, headers=auth(READER))
    again = threaded.get(url, headers=auth(READER))
    assert first.status_code == again.status_code == 200
    assert first.text == again.text
    assert first.headers["etag"] == again.headers["etag"]
    assert renders == ["en"]
    unchanged = threaded.get(url, headers={**auth(READER), "If-None-Match": first.headers["etag"]})
    assert unchanged.status_code == 304
    assert unchanged.content == b""
    assert renders == ["en"]
    kept = list((tmp_path / "reports" / "run" / run_id).glob("en-*.html"))
    assert [p.read_text() for p in kept] == [first.text]


def test_a_run_changed_after_its_report_renders_again(
    threaded: TestClient, renders: list[str], tmp_path: Path
) -> None:
    """A batch stored after the report (a late measurement) makes a new version: a new ETag,
    a new render, and the old file gone."""
    sim = simulated(StandKind.SLIDE_BEARING).sim
    run_id = post(threaded, sim, WRITER, finish=False)
    url = f"{API}/runs/{run_id}/report.html"
    before = threaded.get(url, headers=auth(READER))
    late = {"seq": len(sim.batches), "group": "measurements", "columns": sim.batches[0].as_json()}
    stored = threaded.post(f"{API}/runs/{run_id}/readings", json=late, headers=auth(WRITER))
    assert stored.status_code == 201, stored.text
    after = threaded.get(url, headers={**auth(READER), "If-None-Match": before.headers["etag"]})
    assert after.status_code == 200
    assert after.headers["etag"] != before.headers["etag"]
    assert renders == ["en", "en"]
    assert len(list((tmp_path / "reports" / "run" / run_id).glob("en-*.html"))) == 1


def test_a_new_deployment_names_new_files(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    files = report_files.ReportFiles(tmp_path)
    run = Run(
        id="20261122T114026Z-0000abcd",
        stand=StandKind.MTOS,
        operator="t",
        configuration={},
        created=_T0,
    )
    before = files.run_report(run, "en", "pdf")
    monkeypatch.setattr(report_files, "code_version", lambda: "another deployment")
    after = files.run_report(run, "en", "pdf")
    assert before.path != after.path
    assert before.etag != after.etag
    assert report_files.ReportFiles(tmp_path, "other stands").run_report(run, "en", "pdf") != before


def test_one_key_beyond_its_share_is_answered_503_and_another_key_gets_its_report(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two places, one per key: the writer's key holding one render is refused a second at
    once (503, Retry-After), while the reader's key gets its report."""
    held = threading.Event()
    release = threading.Event()
    real = build_report

    def slow_russian(**kwargs: Any) -> Any:
        if kwargs["lang"] == "ru":
            held.set()
            assert release.wait(60)
        return real(**kwargs)

    monkeypatch.setattr(report_jobs, "build_report", slow_russian)
    with in_process(
        tmp_path, report_processes=False, report_workers=2, report_queue=2, report_key_share=0.5
    ) as client:
        run_id = post(client, simulated(StandKind.PROFILOMETER).sim, WRITER, finish=False)
        url = f"{API}/runs/{run_id}/report.html"
        with ThreadPoolExecutor(1) as pool:
            first = pool.submit(client.get, url, params={"lang": "ru"}, headers=auth(WRITER))
            assert held.wait(60)
            refused = client.get(f"{API}/runs/{run_id}/report.pdf", headers=auth(WRITER))
            served = client.get(url, headers=auth(READER))
            release.set()
            assert first.result(timeout=60).status_code == 200
    assert refused.status_code == 503
    assert refused.headers["retry-after"] == "1"
    assert "one key may have at most 1" in refused.json()["detail"]
    assert served.status_code == 200


def test_finishing_a_run_renders_its_reports_in_the_background(tmp_path: Path) -> None:
    """In the render processes, from the run's final file: both languages, page and PDF,
    before anyone asks; the download is then the file."""
    with in_process(tmp_path, reports_on_finish=True) as client:
        run_id = post(client, simulated(StandKind.PROFILOMETER).sim, WRITER)
        kept = tmp_path / "reports" / "run" / run_id
        deadline = time.monotonic() + 180
        while len(list(kept.glob("*-*.*"))) < 4 and time.monotonic() < deadline:
            time.sleep(0.2)
        assert sorted(p.name.split("-")[0] + p.suffix for p in kept.glob("*")) == [
            "en.html",
            "en.pdf",
            "ru.html",
            "ru.pdf",
        ]
        pdf = next(kept.glob("ru-*.pdf"))
        answer = client.get(f"{API}/runs/{run_id}/report.pdf?lang=ru", headers=auth(READER))
        assert answer.status_code == 200
        assert answer.content == pdf.read_bytes()
        assert answer.content.startswith(b"%PDF")
        assert answer.headers["etag"].strip('"') in pdf.name
        assert client.app.state.services.reports.admitted.renders == 0  # type: ignore[attr-defined]


def test_a_download_joins_the_background_render_of_its_report(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """One render makes a version's page and PDF: asking for the page while the finished
    run's background render of that language runs waits for it, and renders nothing again
    (a 50-million-reading run's page took 12.8 s behind both languages' renders, 7.5-7.8 s
    alone: docs/speed.md)."""
    started = threading.Event()
    release = threading.Event()
    built: list[str] = []
    real = build_report

    def slow(**kwargs: Any) -> Any:
        built.append(kwargs["lang"])
        if kwargs["lang"] == "en":
            started.set()
            assert release.wait(60)
        return real(**kwargs)

    monkeypatch.setattr(report_jobs, "build_report", slow)
    with in_process(tmp_path, report_processes=False, reports_on_finish=True) as client:
        run_id = post(client, simulated(StandKind.PROFILOMETER).sim, WRITER)
        assert started.wait(60)  # the background render of the English report runs
        with ThreadPoolExecutor(1) as pool:
            page = pool.submit(client.get, f"{API}/runs/{run_id}/report.html", headers=auth(READER))
            time.sleep(0.5)  # the download is waiting
            assert not page.done()
            release.set()
            assert page.result(timeout=60).status_code == 200
        deadline = time.monotonic() + 60
        while client.app.state.services.reports.admitted.renders and time.monotonic() < deadline:  # type: ignore[attr-defined]
            time.sleep(0.1)
    assert sorted(built) == ["en", "ru"]
