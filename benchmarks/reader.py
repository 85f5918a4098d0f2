"""A large run into a DataFrame: ``rigclient.Lab`` over HTTP against h5py on the same file
(issue 41, item 2).

Run from the repository root::

    .venv/bin/python benchmarks/reader.py [--readings N] [--repeat K]

Prints one JSON object. One ``rigserver serve`` on loopback with a fresh data directory
receives an SMTs-2 record of ``--readings`` readings (5 channels, binary batches); the run
stays open. Then, ``--repeat`` times each, alternating:

``lab``
    ``Lab(url, key).run(id).readings("friction")``: the group streamed as Arrow by the
    service, read into a DataFrame;
``local``
    the baseline: the same run's HDF5 file (downloaded once, ``format=hdf5``) read with
    h5py from this disk into a DataFrame of the same columns.

The medians of both in seconds, and their ratio (lab / local). Target: the ratio at most
2 (:data:`TARGET_RATIO`). The frames are compared, so a fast wrong answer does not count.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import h5py
import httpx
import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.ingest import API, KEY, body, open_runs, rigserver
from rigclient import Lab

TARGET_RATIO = 2.0
CHANNELS = 5  # the SMTs-2 record: time, load, speed, friction_moment, revolutions
BATCH_ROWS = 200_000


def post_record(url: str, run_id: str, rows: int) -> None:
    """``rows`` rows of the SMTs-2 record, posted as binary batches."""
    headers = {"Authorization": f"Bearer {KEY}", "Content-Type": "application/x-npz"}
    with httpx.Client(base_url=url + API, headers=headers, timeout=120) as http:
        for seq in range(-(-rows // BATCH_ROWS)):
            r = http.post(
                f"/runs/{run_id}/readings",
                params={"seq": seq, "group": "friction"},
                content=body("npz", seq, min(BATCH_ROWS, rows - seq * BATCH_ROWS)),
            )
            r.raise_for_status()


def read_local(path: Path) -> pd.DataFrame:
    """The baseline: the run file's friction group with h5py, into a frame."""
    with h5py.File(path, "r") as f:
        group = f["entry/friction"]
        return pd.DataFrame({name: group[name][...] for name in group})


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--readings", type=int, default=10_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    rows = args.readings // CHANNELS
    out: dict[str, Any] = {"readings": rows * CHANNELS, "rows": rows, "repeat": args.repeat}
    with (
        tempfile.TemporaryDirectory(prefix="rig-bench-") as tmp,
        rigserver(Path(tmp), "reader") as (url, _pid),
    ):
        (run_id,) = open_runs(url, 1)
        post_record(url, run_id, rows)
        local = Path(tmp) / "run.h5"
        with Lab(url, KEY) as lab:
            run = lab.run(run_id)
            run.download("hdf5", local)
            lab_s, local_s = [], []
            for _ in range(args.repeat):
                t = time.perf_counter()
                frame = run.readings("friction")
                lab_s.append(time.perf_counter() - t)
                t = time.perf_counter()
                baseline = read_local(local)
                local_s.append(time.perf_counter() - t)
        assert len(frame) == rows
        for name in frame.columns:
            np.testing.assert_array_equal(frame[name].to_numpy(), baseline[name].to_numpy())
    out["lab_s"] = round(statistics.median(lab_s), 4)
    out["local_h5py_s"] = round(statistics.median(local_s), 4)
    out["ratio"] = round(out["lab_s"] / out["local_h5py_s"], 3)
    out["target_ratio"] = TARGET_RATIO
    out["meets_target"] = out["ratio"] <= TARGET_RATIO
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
