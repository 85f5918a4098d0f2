"""The service's log stays readable: the PDF renderer's and the font library's messages stay
out of it, and a request adds a line at most (issue 25 item 2)."""

from __future__ import annotations

import json
from pathlib import Path

import httpx
import pytest

from schemas.stands import StandKind
from tests.api.conftest import KEYS, READER, WRITER, Server, auth
from tests.reports.simulated import post, simulated

pytestmark = pytest.mark.slow

#: What WeasyPrint and fontTools wrote into the log before (16 downloads: 9 983 lines)
RENDERER_WORDS = ("Ignored", "Anchor defined twice", "Step ", "weasyprint", "fontTools")


def test_report_downloads_add_no_renderer_lines_to_the_log(tmp_path: Path) -> None:
    keys_file = tmp_path / "keys.json"
    keys_file.write_text(json.dumps(KEYS))
    server = Server(tmp_path / "data", keys_file, args=["--log-level", "info"])
    server.start()
    try:
        with httpx.Client(base_url=server.url, timeout=300) as http:
            runs = [
                post(http, simulated(kind).sim, WRITER)  # type: ignore[arg-type]
                for kind in (StandKind.PROFILOMETER, StandKind.SLIDE_BEARING)
            ]
            before = server.log.read_text(errors="replace").splitlines()
            downloads = 0
            for run_id in runs:
                for lang in ("en", "ru"):
                    for fmt in ("pdf", "html", "pdf"):
                        answer = http.get(
                            f"/api/v1/runs/{run_id}/report.{fmt}",
                            params={"lang": lang},
                            headers=auth(READER),
                        )
                        assert answer.status_code == 200, answer.text
                        downloads += 1
            during = server.log.read_text(errors="replace").splitlines()[len(before) :]
    finally:
        server.stop()
    everything = server.log.read_text(errors="replace").splitlines()
    assert downloads == 12
    assert not [line for line in everything if any(w in line for w in RENDERER_WORDS)]
    assert len(during) <= downloads, during  # a line per request at most (here: none)
