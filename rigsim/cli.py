"""``rigsim``: post a simulated stand's run to a rigserver, or run the whole demo.

::

    rigsim run --stand mtos --url http://127.0.0.1:8000 --key KEY --seed 7 --speed 100x
    rigsim run --stand slide_bearing --noise off --truth --json
    rigsim demo --port 8000 --data-dir data
    rigsim export --stand pin_on_disc --dialect tab-comma --out test.txt --truth-json truth.json
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
from collections.abc import Sequence
from dataclasses import fields, is_dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from rigsim.bearing_model import MODELS
from rigsim.client import LabClient
from rigsim.errors import RigsimError, ServerError
from rigsim.instruments import FAULT_KINDS, Fault, Instrument
from rigsim.report import print_results
from rigsim.simulators import SIMULATORS
from rigsim.simulators.smts2 import MODES
from schemas.stands import StandKind


def parse_speed(text: str) -> float | None:
    """``"100x"`` -> 100.0, ``"1x"`` -> 1.0, ``"max"`` -> None (as fast as the server takes)."""
    value = text.strip().lower()
    if value == "max":
        return None
    try:
        speed = float(value.removesuffix("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"speed must look like 1x, 100x or max, got {text!r}"
        ) from None
    if not speed > 0:
        raise argparse.ArgumentTypeError(f"speed must be > 0, got {text!r}")
    return speed


_FAULT = re.compile(
    r"^(?P<kind>\w+):(?P<group>\w+)\.(?P<channel>\w+)"
    r"(?:@(?P<at>[0-9.]+))?(?:\*(?P<rows>\d+))?(?:\+(?P<size>[-0-9.e]+))?$"
)


def parse_fault(text: str) -> Fault:
    """``KIND:GROUP.CHANNEL[@AT][*ROWS][+SIZE]``, e.g. ``stuck:friction.load@0.5*20``."""
    found = _FAULT.match(text.strip())
    if found is None or found["kind"] not in FAULT_KINDS:
        raise argparse.ArgumentTypeError(
            f"a fault looks like KIND:GROUP.CHANNEL[@AT][*ROWS][+SIZE] with KIND one of "
            f"{', '.join(FAULT_KINDS)}, got {text!r}"
        )
    try:
        return Fault(
            kind=found["kind"],
            group=found["group"],
            channel=found["channel"],
            at=float(found["at"] or 0.5),
            rows=int(found["rows"] or 1),
            size=float(found["size"] or 0.0),
        )
    except (RigsimError, ValueError) as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def settings_for(
    kind: StandKind,
    *,
    model: str | None = None,
    mode: str | None = None,
    faults: Sequence[Fault] = (),
    noise: bool = True,
) -> Any:
    """The stand's default settings with the bearing model (MTOS, slide bearing), the
    SMTs-2 mode, the faults and the noise chosen on the command line.

    Without noise every instrument is ideal (no noise, drift, offset or quantisation) and
    the friction of the SMTs-2 and the tribometers does not fluctuate: the readings are the
    truth, so the analysis must return it to round-off or to its own discretisation
    error."""
    simulator = SIMULATORS[kind]
    if mode is not None and simulator.for_mode is not None:
        settings: Any = simulator.for_mode(mode)
    else:
        settings = simulator.settings()
    if model is not None and hasattr(settings, "model"):
        settings = replace(settings, model=model)
    if not noise:
        ideal = {f.name: Instrument() for f in fields(settings.instruments)}
        settings = replace(settings, instruments=replace(settings.instruments, **ideal))
        if hasattr(settings, "friction_fluctuation"):
            settings = replace(settings, friction_fluctuation=0.0)
    return replace(settings, faults=tuple(faults)) if faults else settings


def as_json(value: Any) -> Any:
    """The simulator's truth as JSON: dataclasses as objects, arrays as lists (SI units)."""
    if is_dataclass(value) and not isinstance(value, type):
        return {f.name: as_json(getattr(value, f.name)) for f in fields(value)}
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, tuple | list):
        return [as_json(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def progress_bar(console: Console) -> Progress:
    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("batches"),
        TimeElapsedColumn(),
        console=console,
    )


def _run(args: argparse.Namespace, console: Console) -> int:
    kind = StandKind(args.stand)
    settings = settings_for(
        kind, model=args.model, mode=args.mode, faults=args.fault, noise=args.noise == "on"
    )
    sim = SIMULATORS[kind].simulate(settings, args.seed)
    key = args.key or os.environ.get("RIG_KEY")
    if args.json:  # stdout carries the one JSON object; the progress goes to stderr
        console = Console(stderr=True)
    with LabClient(args.url, key, seed=args.seed) as client, progress_bar(console) as bar:
        client.first_contact()
        # what fails while the client tries again, above the bar (never a silent, frozen bar)
        client.report = lambda text: bar.console.print(text, markup=False, soft_wrap=True)
        task = bar.add_task(f"{kind.value} (seed {args.seed})", total=len(sim.batches))
        outcome = client.run(
            sim,
            speed=args.speed,
            binary=args.binary,
            on_batch=lambda seq, total, receipt: bar.update(task, completed=seq + 1),
        )
    if args.json:
        document = {"run_id": outcome.run.id, "results": outcome.results}
        if args.truth:
            document = {"run_id": outcome.run.id, "truth": as_json(sim.truth), **document}
        sys.stdout.write(json.dumps(document) + "\n")
        return 0
    console.print(
        f"run [bold]{outcome.run.id}[/] {outcome.run.state.value}: {len(outcome.receipts)} "
        f"batches, {outcome.duplicates} stored before a retry, {outcome.retries} retries"
    )
    console.print(f"{args.url.rstrip('/')}/api/v1/runs/{outcome.run.id}/results")
    print_results(console, outcome.results, sim.truth if args.truth else None)
    return 0


def _export(args: argparse.Namespace, console: Console) -> int:
    """A simulated tribometer's record written as a vendor's program writes it, and the
    simulator's truth beside it (``--truth-json``)."""
    from rigsim.export import export_text

    kind = StandKind(args.stand)
    settings = settings_for(kind, noise=args.noise == "on")
    if args.laps is not None:
        settings = replace(
            settings,
            laps=args.laps,
            running_in_laps=max(1, min(settings.running_in_laps, args.laps // 4)),
        )
    sim = SIMULATORS[kind].simulate(settings, args.seed)
    args.out.write_bytes(export_text(kind, sim, args.dialect))
    if args.truth_json is not None:
        document = {
            "stand": kind.value,
            "dialect": args.dialect,
            "seed": args.seed,
            "noise": args.noise,
            "configuration": sim.run_create.configuration,
            "truth": as_json(sim.truth),
        }
        args.truth_json.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    console.print(
        f"{args.out}: {sim.rows('friction')} rows of a simulated {kind.value} test, "
        f"dialect {args.dialect}"
    )
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="rigsim", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="simulate one stand's run and post it to a server")
    run.add_argument("--stand", required=True, choices=[k.value for k in StandKind])
    run.add_argument("--url", default="http://127.0.0.1:8000")
    run.add_argument("--key", help="API key with write:<stand> (or set RIG_KEY)")
    run.add_argument("--seed", type=int, default=0)
    run.add_argument("--speed", type=parse_speed, default=None, help="1x, 100x, ... or max")
    run.add_argument("--model", choices=MODELS, help="bearing model (mtos, slide_bearing)")
    run.add_argument("--mode", choices=MODES, help="SMTs-2 run: wear, adhesive, oxidative")
    run.add_argument(
        "--fault",
        type=parse_fault,
        action="append",
        default=[],
        help="KIND:GROUP.CHANNEL[@AT][*ROWS][+SIZE], e.g. out_of_limit:friction.load@0.5 "
        "(kinds: dropout, spike, stuck, out_of_limit); repeatable",
    )
    run.add_argument("--binary", action="store_true", help="post batches as npz archives")
    run.add_argument("--truth", action="store_true", help="print the simulator's truth too")
    run.add_argument(
        "--noise",
        choices=("on", "off"),
        default="on",
        help="off: ideal instruments and no friction fluctuation (the readings are the truth)",
    )
    run.add_argument(
        "--json",
        action="store_true",
        help='print one JSON object {"run_id", "truth" (with --truth), "results"}',
    )
    every = ", ".join(k.value for k in StandKind)
    said = f"start rigserver and post every stand to it ({every})"
    demo = sub.add_parser("demo", help=said, description=said)
    demo.add_argument("--host", default="127.0.0.1")
    demo.add_argument("--port", type=int, default=8000)
    demo.add_argument("--data-dir", type=Path, default=Path("data"))
    demo.add_argument("--speed", type=parse_speed, default=60.0, help="default 60x")
    demo.add_argument("--seed", type=int, default=0)
    export = sub.add_parser(
        "export", help="write a simulated tribometer's test as a vendor's program exports it"
    )
    export.add_argument(
        "--stand",
        required=True,
        choices=[kind.value for kind, s in SIMULATORS.items() if s.vendor_export],
    )
    export.add_argument("--dialect", required=True, choices=["tab-comma", "csv-units", "utf16-tab"])
    export.add_argument("--out", required=True, type=Path, help="the file to write")
    export.add_argument("--seed", type=int, default=0)
    export.add_argument("--noise", choices=("on", "off"), default="on")
    export.add_argument("--laps", type=int, help="laps (cycles) of the test (default 1000)")
    export.add_argument(
        "--truth-json", type=Path, help="write the simulator's truth (SI) to this JSON file"
    )
    args = parser.parse_args(argv)
    console = Console()
    try:
        if args.command == "run":
            return _run(args, console)
        if args.command == "export":
            return _export(args, console)
        from rigsim.demo import run_demo

        return run_demo(
            host=args.host,
            port=args.port,
            data_dir=args.data_dir,
            speed=args.speed,
            seed=args.seed,
            console=console,
        )
    except (RigsimError, ServerError) as exc:
        console.print(f"[bold red]rigsim:[/] {exc}", soft_wrap=True)
        return 1
    except KeyboardInterrupt:
        console.print("interrupted")
        return 130


if __name__ == "__main__":
    sys.exit(main())
