"""A full disk: ``post`` raises before it acknowledges, and every batch it acknowledged is
in the spool, whole.

The disk is made full for the agent alone with RLIMIT_FSIZE (a file may not grow past the
limit; SIGXFSZ ignored, so the write fails with EFBIG as on a full disk) in a subprocess.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from rigclient.spool import Spool, columns_of

LIMIT = 1 << 20  # bytes a file of the spool may reach
ROWS = 1000

CHILD = """
import json, resource, signal, sys
import numpy as np
from rigclient import Client, SpoolError

signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
client = Client("http://127.0.0.1:9", None, spool=sys.argv[1], start=False)
run = client.open_run(stand="profilometer", operator="disk")
limit = int(sys.argv[2])
resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
acked, error = [], None
try:
    for k in range(100000):
        x = k + np.arange({rows}) / {rows}
        acked.append(run.post("profile", {{"x": x, "y": np.sin(x)}}))
except SpoolError as exc:
    error = [type(exc).__name__, str(exc)]
print(json.dumps({{"local_id": run.local_id, "acked": acked, "error": error}}))
"""


def test_a_full_disk_is_reported_before_anything_is_acknowledged(tmp_path: Path) -> None:
    spool = tmp_path / "spool"
    done = subprocess.run(
        [sys.executable, "-c", CHILD.format(rows=ROWS), str(spool), str(LIMIT)],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    report = json.loads(done.stdout)
    kind, message = report["error"]
    assert kind == "SpoolFull", message
    assert "nothing was spooled" in message, message
    acked = report["acked"]
    assert len(acked) > 10 and acked == list(range(len(acked)))
    with Spool(spool) as opened:  # no limit now: what was acknowledged is there, whole
        (record,) = opened.runs()
        assert record.pending == len(acked) and record.batches == len(acked)
        for seq in acked[:: max(1, len(acked) // 10)]:
            batch = opened.next_batch(report["local_id"], seq)
            assert batch is not None and batch.seq == seq
            x = seq + np.arange(ROWS) / ROWS
            np.testing.assert_array_equal(columns_of(batch.payload)["x"], x)
        # and the spool takes batches again once there is room
        opened.append(report["local_id"], "profile", {"x": [1.0], "y": [0.0]})
        assert opened.runs()[0].batches == len(acked) + 1
