"""The baselines of ``benchmarks/ingest.py``: a bare FastAPI app, served like ``rigserver``.

``POST /api/v1/runs/{run_id}/readings`` validates the same :class:`ReadingBatch` body and
answers 201 with a receipt, storing nothing; ``POST /sink`` reads a body and answers 201
(the ceiling of the batch generator). Started as ``python benchmarks/bare_app.py PORT``
with the uvicorn and malloc settings of ``rigserver serve``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import uvicorn
from fastapi import FastAPI, Request, Response

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rigserver.cli import keep_freed_memory
from schemas.readings import BatchReceipt, ReadingBatch

app = FastAPI()


@app.post("/api/v1/runs/{run_id}/readings", status_code=201)
async def post_readings(run_id: str, request: Request) -> BatchReceipt:
    batch = ReadingBatch.model_validate_json(await request.body())
    rows = max((len(v) for v in batch.columns.values()), default=0)
    return BatchReceipt(run_id=run_id, seq=batch.seq, group=batch.group, rows=rows, group_rows=0)


@app.post("/sink", status_code=201)
async def sink(request: Request) -> Response:
    body = await request.body()
    return Response(b'{"bytes": %d}' % len(body), status_code=201, media_type="application/json")


if __name__ == "__main__":
    keep_freed_memory()  # as rigserver serve does
    uvicorn.run(app, host="127.0.0.1", port=int(sys.argv[1]), log_level="warning", access_log=False)
