"""Write the JSON Schema files of the wire models into ``schemas/json/``.

``python -m schemas.generate`` writes them; ``--check`` fails (exit 1) when a file is
missing or stale, naming it, so CI catches a model changed without regenerating.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from pydantic import BaseModel

from schemas.calculators import (
    BearingFrictionInput,
    BearingFrictionResult,
    EquilibriumRoughnessInput,
    EquilibriumRoughnessResult,
    WearTheoryInput,
)
from schemas.mechanism import DynamicErrorsRequest, DynamicErrorsResponse
from schemas.problems import Problem
from schemas.readings import BatchReceipt, ReadingBatch
from schemas.runs import Run, RunCreate, RunPage
from schemas.stands import DECLARATIONS, Stand

OUT = Path(__file__).parent / "json"

MODELS: dict[str, type[BaseModel]] = {
    "run_create": RunCreate,
    "run": Run,
    "run_page": RunPage,
    "reading_batch": ReadingBatch,
    "batch_receipt": BatchReceipt,
    "problem": Problem,
    "stand": Stand,
    **{f"results_{kind.value}": declared.results for kind, declared in DECLARATIONS.items()},
    "model_wear_theory_input": WearTheoryInput,
    "model_bearing_friction_input": BearingFrictionInput,
    "model_bearing_friction_result": BearingFrictionResult,
    "model_roughness_equilibrium_input": EquilibriumRoughnessInput,
    "model_roughness_equilibrium_result": EquilibriumRoughnessResult,
    "model_mechanism_request": DynamicErrorsRequest,
    "model_mechanism_response": DynamicErrorsResponse,
    **{f"config_{kind.value}": declared.configuration for kind, declared in DECLARATIONS.items()},
}


def rendered() -> dict[str, str]:
    return {
        f"{name}.schema.json": json.dumps(model.model_json_schema(), indent=2, ensure_ascii=False)
        + "\n"
        for name, model in MODELS.items()
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--check", action="store_true", help="fail if a file is stale")
    args = parser.parse_args(argv)
    files = rendered()
    if args.check:
        stale = [
            name
            for name, text in files.items()
            if not (OUT / name).is_file() or (OUT / name).read_text(encoding="utf-8") != text
        ]
        extra = sorted({p.name for p in OUT.glob("*.json")} - set(files))
        for name in stale:
            print(f"schemas/json/{name} is stale: run python -m schemas.generate", file=sys.stderr)
        for name in extra:
            print(f"schemas/json/{name} has no model: delete it", file=sys.stderr)
        return 1 if stale or extra else 0
    OUT.mkdir(exist_ok=True)
    for name, text in files.items():
        (OUT / name).write_text(text, encoding="utf-8")
    for path in OUT.glob("*.json"):
        if path.name not in files:
            path.unlink()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
