"""Issue 22, item 6: the spool's integrity. Bytes flipped in the SQLite file's batch payloads
pass ``PRAGMA quick_check``; the checksum written with each batch catches them before it is
sent: the damaged batch is named (run, seq, file), kept, never sent, and its run stops
there. A spool of an older rigclient (no checksums) is checked by its npz's CRC-32s."""

from __future__ import annotations

import contextlib
import io
import json
import random
import sqlite3
from pathlib import Path

import httpx
import numpy as np
import pytest

from rigclient import Client, RetryPolicy
from rigclient.cli import main
from rigclient.errors import SpoolDamaged
from rigclient.spool import FILENAME, Spool, columns_of
from tests.rigclient.fake import RUN_ID, FakeServer
from tests.rigclient.test_faults import old_spool

FAST = RetryPolicy(base_delay=0.01, max_delay=0.05)
BATCHES = 8


def _columns(k: int) -> dict[str, list[float]]:
    x = 4.0 * k + np.arange(4.0)
    return {"x": x.tolist(), "y": np.sin(x).tolist()}


def _client(server: FakeServer, spool: Path, said: list[str] | None = None) -> Client:
    client = Client(
        "http://rig.test", "k", spool=spool, transport=httpx.MockTransport(server), retry=FAST
    )
    if said is not None:
        client.say = said.append
    return client


def spool_batches(spool: Path) -> str:
    """A run of ``BATCHES`` batches spooled while the server is out of reach; the spool
    checkpointed into its main file (as after a clean stop)."""
    server = FakeServer()
    server.down = True
    with _client(server, spool) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        for k in range(BATCHES):
            run.post("profile", _columns(k))
        run.finish()
    db = sqlite3.connect(spool / FILENAME)
    db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    db.close()
    return run.local_id


def payloads(spool: Path) -> dict[int, bytes]:
    db = sqlite3.connect(spool / FILENAME)
    found = {int(s): bytes(p) for s, p in db.execute("SELECT seq, payload FROM batches")}
    db.close()
    return found


def flip(spool: Path, seq: int, offsets: list[int]) -> None:
    """Flip one bit at each offset of the payload of batch ``seq``, in the file itself."""
    path = spool / FILENAME
    data = bytearray(path.read_bytes())
    payload = payloads(spool)[seq]
    start = data.find(payload)
    assert start >= 0 and data.find(payload, start + 1) < 0, "the payload is not in one page"
    for offset in offsets:
        data[start + offset] ^= 1 << (offset % 8)
    path.write_bytes(bytes(data))


def quick_check(spool: Path) -> str:
    db = sqlite3.connect(spool / FILENAME)
    (result,) = db.execute("PRAGMA quick_check").fetchone()
    db.close()
    return str(result)


def test_a_flipped_byte_is_named_kept_and_never_sent(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    local_id = spool_batches(tmp_path)
    payload = payloads(tmp_path)[3]
    flip(tmp_path, 3, [len(payload) // 2])
    assert quick_check(tmp_path) == "ok"  # SQLite does not see it
    server, said = FakeServer(), []
    with _client(server, tmp_path, said) as client:
        assert not client.wait(10)  # stopped at the damaged batch
        (record,) = client.status().runs
    assert sorted(server.stored) == [0, 1, 2]  # never sent, nor anything after it
    for k in range(3):
        assert server.stored[k] == _columns(k)
    assert record.state == "damaged" and record.pending == BATCHES - 3
    where = f"batch 3 of run {RUN_ID} (4 rows) in {tmp_path / FILENAME}"
    assert any(where in s and "damaged" in s for s in said), said
    assert main(["status", "--spool", str(tmp_path), "--json"]) == 0
    (report,) = json.loads(capsys.readouterr().out)
    assert report["state"] == "damaged" and [b["seq"] for b in report["damaged_batches"]] == [3]
    assert "checksum" in report["damaged"]
    # kept: the damaged bytes are still in the spool; retry checks them again, in vain
    assert payloads(tmp_path)[3] != payload and len(payloads(tmp_path)) == BATCHES - 3
    assert main(["retry", RUN_ID, "--spool", str(tmp_path)]) == 1
    assert "batch 3 still damaged" in capsys.readouterr().err
    # the operator drops the damaged batch: the rest goes on without its rows
    assert main(["drop", RUN_ID, "--damaged", "--spool", str(tmp_path)]) == 0
    assert "dropped its 1 batch (4 rows) damaged" in capsys.readouterr().err
    with _client(server, tmp_path) as client:
        assert client.wait(10)
    assert sorted(server.stored) == [k for k in range(BATCHES) if k != 3]
    assert server.state == "finished"
    with Spool(tmp_path) as spool:
        assert spool.runs(local_id)[0].state == "delivered"


@pytest.mark.parametrize("seed", range(12))
def test_random_bytes_flipped_in_the_payloads_are_caught(tmp_path: Path, seed: int) -> None:
    rng = random.Random(seed)
    spool_batches(tmp_path)
    before = payloads(tmp_path)
    hit = sorted(rng.sample(range(BATCHES), rng.randint(1, 3)))
    for seq in hit:
        size = len(before[seq])
        flip(tmp_path, seq, rng.sample(range(size), rng.randint(1, 4)))
    assert quick_check(tmp_path) == "ok"
    server = FakeServer()
    with _client(server, tmp_path) as client:
        assert not client.wait(10)
        (record,) = client.status().runs
    # every batch before the first damaged one, bit for bit; nothing from it on
    assert sorted(server.stored) == list(range(hit[0]))
    for k in range(hit[0]):
        assert server.stored[k] == _columns(k)
    assert record.state == "damaged" and f"batch {hit[0]} of run" in str(record.damaged)


def test_damage_in_a_spool_of_an_older_rigclient_is_caught_by_the_npz_crc(
    tmp_path: Path,
) -> None:
    old_spool(tmp_path, {"title": "Internal Server Error", "status": 500, "detail": "<html>"})
    payload = payloads(tmp_path)[2]
    data = columns_of(payload)["x"].tobytes()
    flip(tmp_path, 2, [payload.find(data) + 3])  # inside the stored array: the CRC-32 is wrong
    server = FakeServer()
    server.stored[0] = {"x": [0.0, 1.0], "y": [0.0, 0.0]}
    with _client(server, tmp_path) as client:
        assert not client.wait(10)
        (record,) = client.status().runs
    assert sorted(server.stored) == [0, 1]  # the intact old batch went, the damaged one not
    assert record.state == "damaged" and "npz archive does not read back" in str(record.damaged)


def _run_main(*argv: str) -> tuple[int, str]:
    """``rigclient ARGV`` in this process (an exception escaping it fails the test)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(list(argv))
    return code, err.getvalue()


@pytest.mark.parametrize("seed", range(8))
def test_random_bytes_in_the_spools_file_say_it_is_damaged_and_salvage_saves_the_rest(
    tmp_path: Path, seed: int
) -> None:
    """Issue 39, item 9: random bytes in the spool's SQLite file (past its first page, the
    schema) ended `send` and `status` in "database disk image is malformed" tracebacks.
    Now each says the spool is damaged and names `rigclient salvage`, which keeps what
    still reads (the batches that do are delivered bit for bit) and moves the file aside."""
    rng = random.Random(seed)
    for _ in range(3):  # three runs of many batches: many pages
        spool_batches(tmp_path)
    before = {bytes(p) for p in payloads(tmp_path).values()}
    path = tmp_path / FILENAME
    data = bytearray(path.read_bytes())
    page = 4096
    for _ in range(8):  # a run of random bytes in a random page past the schema's
        at = rng.randrange(page, len(data) - 64)
        data[at : at + 32] = rng.randbytes(32)
    path.write_bytes(bytes(data))
    url = ["--url", "http://127.0.0.1:9", "--drain", "0"]
    for argv in (["status"], ["send", *url]):
        code, said = _run_main(*argv, "--spool", str(tmp_path))
        if "the spool is damaged" in said:
            assert code == 1 and f"rigclient salvage --spool {tmp_path}" in said, said
    code, said = _run_main("salvage", "--spool", str(tmp_path))
    assert "saved" in said and ".damaged-" in said, said
    kept = sorted(tmp_path.glob(f"{FILENAME}.damaged-*"))
    assert kept and kept[0].read_bytes()[:16] == bytes(data[:16])  # the damaged file, aside
    code, said = _run_main("status", "--spool", str(tmp_path))
    assert code == 0, said
    server = FakeServer()
    with _client(server, tmp_path) as client:
        client.wait(10)
    # what was delivered is what was spooled, bit for bit
    with Spool(tmp_path) as spool:
        assert all(r.damaged is None or "checksum" in r.damaged for r in spool.runs())
    for batch in server.stored.values():
        assert any(np.array_equal(batch["x"], columns_of(p)["x"]) for p in before)


def test_json_nested_deeper_than_the_limit_in_the_spool_is_read_as_damaged(
    tmp_path: Path,
) -> None:
    """Issue 39, items 3 and 9: the JSON the spool keeps (a refusal's problem, an opening)
    is read with the server's depth limit; 100 000 levels were a RecursionError in
    `rigclient status`."""
    local_id = spool_batches(tmp_path)
    deep = "[" * 100_000 + "]" * 100_000
    db = sqlite3.connect(tmp_path / FILENAME)
    db.execute("UPDATE runs SET refused = ?, refused_what = 'opening', body = ?", (deep, deep))
    db.commit()
    db.close()
    code, said = _run_main("status", "--spool", str(tmp_path), "--json")
    assert code == 0 and "Traceback" not in said, said
    with Spool(tmp_path) as spool:
        (record,) = spool.runs(local_id)
        assert record.title == "(the opening is damaged)"
        assert record.refused is not None and record.refused["status"] is None  # as text
        with pytest.raises(SpoolDamaged):  # the checksum, before the depth
            spool.opening(local_id)
