"""Kill -9 a process appending to a store (HDF5Store, PostgresStore) at random moments;
nothing acknowledged is lost, nothing is stored twice, every run file opens with plain h5py,
appending goes on."""

from __future__ import annotations

import random
import signal
import subprocess
import sys
import time
from contextlib import closing
from pathlib import Path

import h5py
import numpy as np
import pytest

from rigserver.storage._checks import channel_group, padded
from schemas.runs import RunQuery, RunState
from schemas.stands import StandKind
from tests.storage.conftest import make_run
from tests.storage.crash_writer import batch_of, open_store

WRITER = Path(__file__).with_name("crash_writer.py")
ROUNDS = 10


def _expected(last_seq: int) -> dict[str, dict[str, np.ndarray]]:
    """The two groups as stored after seqs 0..last_seq, in that order."""
    parts: dict[str, list[dict[str, np.ndarray]]] = {"friction": [], "measurements": []}
    for seq in range(last_seq + 1):
        group, columns = batch_of(seq)
        rows = max(len(v) for v in columns.values())
        parts[group].append(padded(channel_group(StandKind.SMTS2, group), columns, rows))
    return {
        group: {name: np.concatenate([p[name] for p in found]) for name in found[0]}
        for group, found in parts.items()
    }


def _kill_while_writing(
    target: str, files: Path, run_id: str, first_seq: int, rng: random.Random
) -> str:
    with subprocess.Popen(
        [sys.executable, str(WRITER), target, run_id, str(first_seq), str(files)],
        stdout=subprocess.PIPE,
        text=True,
    ) as proc:
        assert proc.stdout is not None
        if rng.random() < 0.3:  # sometimes while it opens the store (recovery, rebuilds)
            time.sleep(rng.uniform(0.3, 1.2))
            head = ""
        else:
            head = proc.stdout.readline()
            assert head == "ready\n", head
            time.sleep(rng.uniform(0.02, 0.6))
        proc.send_signal(signal.SIGKILL)
        return head + proc.stdout.read()


@pytest.mark.slow
@pytest.mark.parametrize("deployment", ["hdf5", "hdf5-backlog", "postgres"])
def test_kill_9_at_random_moments_loses_nothing_acknowledged(
    deployment: str, tmp_path: Path, request: pytest.FixtureRequest
) -> None:
    rng = random.Random(20240301)
    target = {"hdf5": str(tmp_path), "hdf5-backlog": f"backlog:{tmp_path}"}.get(deployment) or str(
        request.getfixturevalue("postgres_url")
    )
    files_dir = tmp_path / "files"
    store = open_store(target, files_dir)
    with closing(store):
        run_id = store.create_run(make_run()).id
    acked: list[int] = []
    ended: set[str] = set()
    for _ in range(ROUNDS):
        out = _kill_while_writing(target, files_dir, run_id, (acked[-1] + 1) if acked else 0, rng)
        for line in out.splitlines(keepends=True):
            if not line.endswith("\n"):
                continue  # cut by the kill: not acknowledged
            word, _, value = line.strip().partition(" ")
            if word == "ack":
                acked.append(int(value))
            elif word == "ended":
                ended.add(value)
    assert acked == sorted(set(acked)), "a seq was acknowledged twice"
    assert len(acked) > 20, "the writer hardly wrote: the test proves little"

    store = open_store(target, files_dir)
    with closing(store):
        # the batch after the last acknowledged one may have been stored, unacknowledged
        last = acked[-1] + (store.receipt(run_id, acked[-1] + 1) is not None)
        assert all(store.receipt(run_id, seq) is not None for seq in range(last + 1))
        run = store.get_run(run_id)
        assert run.batches == last + 1
        for group, columns in _expected(last).items():
            assert run.rows[group] == len(columns["time" if group == "friction" else "disc_ra"])
            got = store.read(run_id, group)
            for name, values in columns.items():
                np.testing.assert_array_equal(got[name], values, err_msg=f"{group}/{name}")
        runs = store.list_runs(RunQuery(limit=500)).runs
        # every run file opens with plain h5py and holds what the catalogue says (the
        # embedded store's files themselves; the cluster's as materialised from the journal)
        files = {
            r.id: (
                tmp_path / "runs" / f"{r.id}.h5"
                if deployment.startswith("hdf5")
                else store.run_file(r.id)
            )
            for r in runs
        }
    assert ended <= {r.id for r in runs}
    for run in runs:
        with h5py.File(files[run.id], "r") as f:
            for group, rows in run.rows.items():
                for ds in f["entry"][group].values():
                    assert ds.shape == (rows,)
            assert bool(f["entry"].attrs.get("finalized", False)) == (
                run.state is not RunState.OPEN
            )
            if run.id in ended:
                assert run.state is RunState.FINISHED

    store = open_store(target, files_dir)
    with closing(store):
        receipt = store.append(run_id, last + 1, *batch_of(last + 1))
        assert not receipt.duplicate
        assert store.end_run(run_id, RunState.FINISHED).batches == last + 2
        with h5py.File(store.run_file(run_id), "r") as f:
            assert bool(f["entry"].attrs["finalized"])
