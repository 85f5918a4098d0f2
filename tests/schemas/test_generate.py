"""The JSON Schema files in schemas/json/ match the models."""

from schemas import generate


def test_json_schema_files_are_current() -> None:
    assert generate.main(["--check"]) == 0, "run: python -m schemas.generate"


def test_config_schemas_carry_units() -> None:
    files = generate.rendered()
    assert '"unit": "Pa*s"' in files["config_slide_bearing.schema.json"]
