"""A series archive whose reports are not rendered yet is answered at once with 202 and
its progress, rendered in the background, then given (issue 39, item 10: the first export
of 100 runs was one request of 498 s)."""

from __future__ import annotations

import time
import zipfile
from io import BytesIO
from pathlib import Path

from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.reports.i18n import LANGS
from rigserver.storage import MemoryStore
from rigsim.simulators import simulate
from schemas.stands import StandKind, configure_stands
from tests.api.conftest import KEYS, READER, WRITER, auth
from tests.reports.simulated import post, series_of


def test_the_first_export_answers_202_with_its_progress_then_the_archive(
    tmp_path: Path,
) -> None:
    app = create_app(
        Settings(data_dir=tmp_path, retry_after=1),
        MemoryStore(),
        [ApiKey.model_validate(k) for k in KEYS],
        configure_stands(),
    )
    with TestClient(app) as client:
        runs = [post(client, simulate(StandKind.PROFILOMETER, seed=s), WRITER) for s in (1, 2)]
        series = series_of(client, WRITER, runs, name="two traces", purpose="repeatability")
        here = f"/api/v1/series/{series}/export.eln"
        first = client.get(here, headers=auth(READER))
        assert first.status_code == 202
        assert first.headers["location"] == here and first.headers["retry-after"] == "1"
        progress = first.json()
        # every report the archive packs: each run's and the series', in each language
        total = (len(runs) + 1) * len(LANGS)
        assert progress["reports_total"] == total
        assert progress["reports_done"] < total  # answered before the renders were done
        seen = []
        answer = first
        deadline = time.monotonic() + 300
        while answer.status_code == 202 and time.monotonic() < deadline:
            status = client.get(f"{here}/status", headers=auth(READER)).json()
            seen.append(status["reports_done"])
            time.sleep(0.2)
            answer = client.get(here, headers=auth(READER))
        assert answer.status_code == 200, answer.text
        assert seen == sorted(seen) and max(seen) <= total
        with zipfile.ZipFile(BytesIO(answer.content)) as archive:
            names = archive.namelist()
        assert sum(n.endswith(".pdf") for n in names) >= total
        again = client.get(here, headers=auth(READER))  # kept now: the archive at once
        assert again.status_code == 200
        assert client.get(f"{here}/status", headers=auth(READER)).json()["state"] == "ready"
