"""The students' sketches on a run (issue 38 item 5): an image uploaded for a sketch item of
the lab's report list by a key with the run's stand's write scope, checked at the door (PNG
or JPEG by its bytes, not its header; the size in bytes and in pixels; no decompression
bomb), every version kept and readable."""

from __future__ import annotations

import base64
import io
import json
import re
import struct
import threading
import time
import zlib
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
import pytest
from fastapi.testclient import TestClient
from PIL import Image, ImageFile, PngImagePlugin

from rigserver.api.sketch_images import checked
from rigsim.simulators import simulate
from rigsim.simulators.smts2 import Smts2Settings
from schemas.sketches import SKETCH_MAX_BYTES, SKETCH_MAX_PIXELS, SKETCH_MAX_SIDE
from schemas.stands import StandKind
from tests.api.conftest import KEYS, MTOS_ONLY, READER, WRITER, Server, auth, in_process
from tests.api.test_service import open_run
from tests.reports.simulated import post, series_of
from tests.reports.test_lab_work import MODES

API = "/api/v1"
#: The SMTs-2 lab's sketch items: 4 the specimens, 5 the loading scheme (its contents).
ITEM = 4


def image(fmt: str, size: tuple[int, int] = (40, 30), colour: str = "red") -> bytes:
    """An image of ``size`` in ``fmt`` (PNG, JPEG)."""
    out = io.BytesIO()
    Image.new("RGB", size, colour).save(out, fmt)
    return out.getvalue()


def bomb(width: int, height: int) -> bytes:
    """A small PNG whose header declares ``width`` × ``height`` pixels (its IHDR rewritten,
    its CRC with it): decoding it would take what the header says."""
    png = bytearray(image("PNG", (1, 1)))
    ihdr = png[12:29]  # b"IHDR", width, height, depth, colour, compression, filter, interlace
    ihdr[4:12] = struct.pack(">II", width, height)
    png[12:29] = ihdr
    png[29:33] = struct.pack(">I", zlib.crc32(bytes(ihdr)))
    return bytes(png)


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with in_process(tmp_path, report_processes=False) as c:
        yield c


def put(
    client: TestClient,
    run_id: str,
    body: bytes,
    key: str | None,
    media: str = "image/png",
    item: int = ITEM,
) -> httpx.Response:
    headers = {"Content-Type": media, **(auth(key) if key else {})}
    return client.put(f"{API}/runs/{run_id}/sketches/{item}", content=body, headers=headers)


def test_an_upload_is_fetched_as_sent_and_a_replaced_one_stays_readable(
    client: TestClient,
) -> None:
    run_id = open_run(client)  # an SMTs-2 run
    first, second = image("PNG"), image("JPEG", (64, 48), "blue")
    one = put(client, run_id, first, WRITER)
    assert one.status_code == 201, one.text
    assert {k: one.json()[k] for k in ("item", "version", "media_type", "width", "height")} == {
        "item": ITEM,
        "version": 1,
        "media_type": "image/png",
        "width": 40,
        "height": 30,
    }
    assert (one.json()["size"], one.json()["by"]) == (len(first), "lab PC")
    two = put(client, run_id, second, WRITER, "image/jpeg")
    assert two.status_code == 201 and two.json()["version"] == 2
    url = f"{API}/runs/{run_id}/sketches/{ITEM}"
    latest = client.get(url, headers=auth(READER))
    assert latest.status_code == 200 and latest.content == second
    assert latest.headers["content-type"] == "image/jpeg"
    assert latest.headers["x-content-type-options"] == "nosniff"
    earlier = client.get(f"{url}?version=1", headers=auth(READER))
    assert earlier.content == first and earlier.headers["content-type"] == "image/png"
    listed = client.get(f"{API}/runs/{run_id}/sketches", headers=auth(READER)).json()
    assert [(s["item"], s["version"]) for s in listed["sketches"]] == [(ITEM, 1), (ITEM, 2)]
    assert client.get(f"{url}?version=3", headers=auth(READER)).status_code == 404
    # beyond SQLite's integer (2^63, what schemathesis tried): refused at the door, not a 500
    huge = client.get(f"{url}?version={2**63}", headers=auth(READER))
    assert huge.status_code == 422 and "version" in huge.text
    assert client.get(f"{API}/runs/{run_id}/sketches/5", headers=auth(READER)).status_code == 404


def test_the_order_is_key_then_body_then_scope(client: TestClient) -> None:
    run_id = open_run(client)
    not_image = b"GIF89a not taken"
    assert put(client, run_id, not_image, None).status_code == 401  # before the body is read
    assert put(client, run_id, not_image, "not-a-key-000000000000").status_code == 401
    assert put(client, run_id, not_image, READER).status_code == 415  # parsed before the scope
    refused = put(client, run_id, image("PNG"), READER)
    assert refused.status_code == 403 and "write:smts2" in refused.json()["detail"]
    other = put(client, run_id, image("PNG"), MTOS_ONLY)  # a writer of another stand
    assert other.status_code == 403 and "write:smts2" in other.json()["detail"]
    assert client.get(f"{API}/runs/{run_id}/sketches", headers=auth(READER)).json() == {
        "sketches": []
    }
    assert put(client, "20261122T114026Z-00000000", image("PNG"), WRITER).status_code == 404


@pytest.mark.parametrize(
    ("body", "media", "status", "words"),
    [
        # a header that lies about the bytes
        (image("JPEG"), "image/png", 415, "says image/png, but the bytes are image/jpeg"),
        (image("PNG"), "image/jpeg", 415, "says image/jpeg, but the bytes are image/png"),
        (b"<svg xmlns='http://www.w3.org/2000/svg'/>", "image/png", 415, "no PNG or JPEG"),
        (image("GIF"), "image/png", 415, "no PNG or JPEG"),
        (image("PNG"), "application/octet-stream", 415, "image/png or image/jpeg"),
        (image("PNG"), "", 415, "image/png or image/jpeg"),
        # PNG's signature, then nothing of an image
        (b"\x89PNG\r\n\x1a\n" + b"\x00" * 64, "image/png", 422, "cannot be decoded"),
        (image("PNG", (300, 300))[:200], "image/png", 422, "cannot be decoded"),  # truncated
        (b"", "image/png", 415, "no PNG or JPEG"),
        # the limits, each named in the answer
        (b"\x89PNG" + b"\x00" * SKETCH_MAX_BYTES, "image/png", 413, str(SKETCH_MAX_BYTES)),
        (image("PNG", (SKETCH_MAX_SIDE + 1, 1)), "image/png", 422, f"{SKETCH_MAX_SIDE} pixels"),
        # a decompression bomb: a small file declaring 20000 × 20000 pixels, never decoded
        (bomb(20000, 20000), "image/png", 422, str(SKETCH_MAX_SIDE)),
        (bomb(7000, 7000), "image/png", 422, f"{SKETCH_MAX_PIXELS} pixels in all"),
    ],
)
@pytest.mark.parametrize("truncated_allowed", [False, True])
def test_what_is_no_sketch_is_refused_naming_the_problem(
    client: TestClient,
    body: bytes,
    media: str,
    status: int,
    words: str,
    truncated_allowed: bool,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # WeasyPrint, once imported (a report rendered in the service), sets Pillow's global
    # LOAD_TRUNCATED_IMAGES: a truncated PNG was then taken as a sketch
    monkeypatch.setattr(ImageFile, "LOAD_TRUNCATED_IMAGES", truncated_allowed)
    run_id = open_run(client)
    answer = put(client, run_id, body, WRITER, media)
    assert answer.status_code == status, answer.text
    assert answer.headers["content-type"] == "application/problem+json"
    assert words in answer.json()["detail"]
    assert client.get(f"{API}/runs/{run_id}/sketches", headers=auth(READER)).json() == {
        "sketches": []
    }


def test_only_the_labs_sketch_items_take_one(client: TestClient) -> None:
    run_id = open_run(client)
    refused = put(client, run_id, image("PNG"), WRITER, item=8)  # the results: no sketch
    assert refused.status_code == 422
    assert "sketch items are 4, 5" in refused.json()["detail"]
    assert put(client, run_id, image("PNG"), WRITER, item=5).status_code == 201


def test_the_report_prints_the_latest_upload_and_renders_again_after_one(
    client: TestClient,
) -> None:
    run_id = open_run(client)
    url = f"{API}/runs/{run_id}/report.html?lang=en"
    before = client.get(url, headers=auth(READER))
    assert before.status_code == 200 and 'class="sketch"' not in before.text
    first, second = image("PNG"), image("PNG", (50, 20), "green")
    assert put(client, run_id, first, WRITER).status_code == 201
    assert put(client, run_id, second, WRITER).status_code == 201
    after = client.get(url, headers={**auth(READER), "If-None-Match": before.headers["etag"]})
    assert after.status_code == 200  # a new version of the report, not 304
    shown = re.findall(r'<img class="sketch" src="data:image/png;base64,([^"]+)"', after.text)
    assert [base64.b64decode(s) for s in shown] == [second]  # the latest version only


def test_the_sketches_outlive_a_restart_of_the_embedded_server(tmp_path: Path) -> None:
    keys_file = tmp_path / "keys.json"
    keys_file.write_text(json.dumps(KEYS))
    server = Server(tmp_path / "data", keys_file)
    server.start()
    png = image("PNG")
    try:
        with httpx.Client(base_url=server.url, headers=auth(WRITER), timeout=30) as http:
            made = http.post(f"{API}/runs", json={"stand": "smts2", "operator": "Ivanova"})
            run_id = made.json()["id"]
            url = f"{API}/runs/{run_id}/sketches/{ITEM}"
            uploaded = http.put(url, content=png, headers={"Content-Type": "image/png"})
            assert uploaded.status_code == 201, uploaded.text
        server.stop()
        server.start()
        with httpx.Client(base_url=server.url, headers=auth(READER), timeout=30) as http:
            assert http.get(url).content == png
    finally:
        server.stop()
    assert (tmp_path / "data" / "sketches.sqlite").exists()


def test_a_lab_works_report_prints_the_sketch_of_its_part_one_run(client: TestClient) -> None:
    ids = {
        mode: post(client, simulate(StandKind.SMTS2, Smts2Settings.for_mode(mode), 5), WRITER)
        for mode in MODES
    }
    series = series_of(
        client, WRITER, list(ids.values()), list(ids), name="Lab 2, MT-31", purpose="lab"
    )
    url = f"{API}/series/{series}/report.html?lang=en"
    before = client.get(url, headers=auth(READER))
    assert before.status_code == 200 and 'class="sketch"' not in before.text
    png = image("PNG")
    assert put(client, ids["wear"], png, WRITER).status_code == 201
    after = client.get(url, headers={**auth(READER), "If-None-Match": before.headers["etag"]})
    assert after.status_code == 200  # a new version of the report, not 304
    shown = re.findall(r'<img class="sketch" src="data:image/png;base64,([^"]+)"', after.text)
    assert [base64.b64decode(s) for s in shown] == [png]


def test_no_more_than_two_sketches_are_decoded_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """A decode holds the image's pixels: uploads at once wait their turn rather than take
    the service's memory (rigserver.api.sketch_images.DECODING)."""
    decoding, most, lock = 0, 0, threading.Lock()
    load = PngImagePlugin.PngImageFile.load

    def counted(self: PngImagePlugin.PngImageFile) -> object:
        nonlocal decoding, most
        with lock:
            decoding += 1
            most = max(most, decoding)
        time.sleep(0.05)
        try:
            return load(self)
        finally:
            with lock:
                decoding -= 1

    monkeypatch.setattr(PngImagePlugin.PngImageFile, "load", counted)
    png = image("PNG")
    with ThreadPoolExecutor(6) as pool:
        done = list(pool.map(lambda _: checked(png, "image/png"), range(6)))
    assert [d.size for d in done] == [(40, 30)] * 6
    assert most == 2
