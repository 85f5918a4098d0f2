"""``rigserver serve``: run the service on uvicorn with the embedded HDF5 storage."""

from __future__ import annotations

import argparse
import json
import logging
import sys
from collections.abc import Sequence
from pathlib import Path

import uvicorn
from fastapi import FastAPI

from rigserver.api.app import create_app
from rigserver.api.auth import load_keys
from rigserver.api.settings import Settings
from rigserver.storage import HDF5Store
from schemas.stands import configure_stands


def build_app(settings: Settings) -> FastAPI:
    """The service with the data directory, keys and stands of ``settings``."""
    keys = load_keys(settings.keys_file) if settings.keys_file else []
    overrides = (
        json.loads(settings.stands_file.read_text(encoding="utf-8"))
        if settings.stands_file
        else None
    )
    settings.data_dir.mkdir(parents=True, exist_ok=True)
    store = HDF5Store(settings.data_dir, synchronous=settings.synchronous)  # type: ignore[arg-type]
    return create_app(settings, store, keys, configure_stands(overrides))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="rigserver", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    serve = sub.add_parser("serve", help="run the service")
    serve.add_argument("--host", default="127.0.0.1")
    serve.add_argument("--port", type=int, default=8000)
    serve.add_argument("--data-dir", type=Path, help="where runs are stored (RIG_DATA_DIR)")
    serve.add_argument("--keys-file", type=Path, help="JSON list of API keys (RIG_KEYS_FILE)")
    serve.add_argument("--stands-file", type=Path, help="the lab's stand configuration")
    serve.add_argument("--public-reads", action="store_true", help="reads need no key")
    serve.add_argument("--log-level", default="info")
    args = parser.parse_args(argv)
    given = {
        "data_dir": args.data_dir,
        "keys_file": args.keys_file,
        "stands_file": args.stands_file,
        "public_reads": True if args.public_reads else None,
    }
    settings = Settings(**{k: v for k, v in given.items() if v is not None})
    logging.basicConfig(
        level=args.log_level.upper(), format="%(asctime)s %(levelname)s %(message)s"
    )
    app = build_app(settings)
    print(f"rigserver: data in {settings.data_dir.resolve()}", file=sys.stderr)
    uvicorn.run(app, host=args.host, port=args.port, log_level=args.log_level, access_log=False)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
