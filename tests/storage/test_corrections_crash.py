"""Kill -9 a process correcting readings at random moments: no acknowledged correction is
lost, and every run file holds the corrections its journal holds."""

from __future__ import annotations

import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rigserver.storage import HDF5Store
from rigserver.storage.runfile import RunFile
from schemas.runs import RunState
from tests.processes import spawn, stop
from tests.storage.conftest import friction, make_run
from tests.storage.correction_writer import ROWS, correction

WRITER = Path(__file__).with_name("correction_writer.py")
ROUNDS = 6


def _kill_while_correcting(data: Path, run_ids: list[str], rng: random.Random) -> list[str]:
    """The lines the writer printed whole before SIGKILL reached it."""
    proc = spawn([sys.executable, str(WRITER), str(data), *run_ids], stdout=subprocess.PIPE)
    assert proc.stdout is not None
    head = proc.stdout.readline()
    assert head == b"ready\n", head
    time.sleep(rng.uniform(0.05, 0.8))
    stop(proc, sig=signal.SIGKILL)
    with proc.stdout:
        return [line.decode() for line in proc.stdout.read().splitlines(keepends=True)]


@pytest.mark.slow
def test_kill_9_loses_no_acknowledged_correction(tmp_path: Path) -> None:
    rng = random.Random(36)
    data = tmp_path / "data"
    with HDF5Store(data) as store:
        run_ids = []
        for _ in range(2):
            run_id = store.create_run(make_run()).id
            store.append(run_id, 0, "friction", friction(0, ROWS))
            run_ids.append(run_id)
        store.end_run(run_ids[1], RunState.FINISHED)
    acked = dict.fromkeys(run_ids, 0)
    for _ in range(ROUNDS):
        for line in _kill_while_correcting(data, run_ids, rng):
            word, run_id, n = line.split()
            if line.endswith("\n") and word == "ack":
                # one stored but not acknowledged before a kill is taken up by the next round
                assert int(n) in (acked[run_id] + 1, acked[run_id] + 2), line
                acked[run_id] = int(n)
    assert min(acked.values()) > 5, "the writer hardly wrote: the test proves little"

    with HDF5Store(data) as store:
        for run_id in run_ids:
            found = store.corrections(run_id)
            # the correction after the last acknowledged one may be stored, unacknowledged
            assert len(found) in (acked[run_id], acked[run_id] + 1)
            for c in found:
                assert (c.row, c.now) == correction(c.n)
            assert store.get_run(run_id).corrections == len(found)
            with RunFile.open(store.run_file(run_id), writable=False) as rf:
                assert rf.corrections() == found
                typed = rf.read("friction", ["friction_moment"], 0, None)["friction_moment"]
                assert list(typed) == list(friction(0, ROWS)["friction_moment"])
