"""The OpenAPI document: it validates (openapi-spec-validator), every ``$ref`` in it
resolves, and every request body carries an example the service takes (posted as the
document gives it, each answered 2xx)."""

from __future__ import annotations

import io
import json
import re
from collections.abc import Collection, Iterator
from typing import Any

import numpy as np
from fastapi.testclient import TestClient
from openapi_spec_validator import validate

from schemas.readings import NPZ_MEDIA_TYPE
from tests.api.conftest import WRITER, auth

JSON = "application/json"


def strings_at(node: Any, keys: Collection[str]) -> Iterator[str]:
    """Every string of the document (or of a part of it) that is the value of one of
    ``keys``, in document order."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key in keys and isinstance(value, str):
                yield value
            else:
                yield from strings_at(value, keys)
    elif isinstance(node, list):
        for value in node:
            yield from strings_at(value, keys)


def resolve(document: dict[str, Any], ref: str) -> Any:
    """A local JSON Pointer (RFC 6901) into the document; KeyError when it dangles."""
    assert ref.startswith("#/"), ref
    node: Any = document
    for token in ref[2:].split("/"):
        node = node[token.replace("~1", "/").replace("~0", "~")]
    return node


def examples(document: dict[str, Any], media: dict[str, Any]) -> list[dict[str, Any]]:
    """A media type's examples as Example Objects: its own ``example``/``examples``, else
    its schema's JSON Schema ``examples``."""
    if "example" in media:
        return [{"value": media["example"]}]
    if "examples" in media:
        return [
            resolve(document, e["$ref"]) if "$ref" in e else e for e in media["examples"].values()
        ]
    schema = media.get("schema", {})
    if "$ref" in schema:
        schema = resolve(document, schema["$ref"])
    return [{"value": value} for value in schema.get("examples", [])]


def test_the_document_validates(client: TestClient) -> None:
    validate(client.get("/openapi.json").json())


def test_the_api_docs_speak_english_and_name_their_sources(client: TestClient) -> None:
    """The English API docs: no Cyrillic subscript (f_e, χ_mean, not f_э, χ_ср) and a source
    named by its title, never by a seed number."""
    # what the API docs page prints
    document = client.get("/openapi.json").json()
    found = list(strings_at(document, ("description", "summary", "title")))
    assert len(found) > 100
    wrong = [t for t in found if re.search(r"[А-Яа-яЁё]|\bseed\b", t, re.IGNORECASE)]
    assert not wrong, wrong[:10]


def test_every_ref_resolves(client: TestClient) -> None:
    document = client.get("/openapi.json").json()
    found = set(strings_at(document, ("$ref",)))
    assert "#/components/schemas/ReadingBatch" in found  # the ingest route's body
    dangling = [ref for ref in found if not _resolves(document, ref)]
    assert dangling == []


def _resolves(document: dict[str, Any], ref: str) -> bool:
    try:
        resolve(document, ref)
    except (KeyError, TypeError):
        return False
    return True


def test_the_batch_component_is_the_batch_the_route_parses(client: TestClient) -> None:
    document = client.get("/openapi.json").json()
    batch = resolve(document, "#/components/schemas/ReadingBatch")
    assert set(batch["required"]) == {"seq", "group", "columns"}
    assert batch["additionalProperties"] is False
    # what the document refuses, the route refuses: a key beside seq, group and columns
    run = client.post(
        "/api/v1/runs", json={"stand": "smts2", "operator": "x"}, headers=auth(WRITER)
    )
    (example,) = batch["examples"]
    r = client.post(
        f"/api/v1/runs/{run.json()['id']}/readings",
        json={**example, "extra": 1},
        headers=auth(WRITER),
    )
    assert r.status_code == 422
    assert r.json()["errors"][0]["field"] == "extra"


def body_examples(document: dict[str, Any], path: str) -> list[Any]:
    """The JSON example values of ``POST path``'s body."""
    media = document["paths"][path]["post"]["requestBody"]["content"][JSON]
    return [e["value"] for e in examples(document, media)]


def made_for(
    client: TestClient, document: dict[str, Any], path: str, value: Any
) -> tuple[str, str]:
    """``path`` with a new run and series of its own in place of ``{run_id}`` and
    ``{series_id}`` (the readings of one run increase; a run at a level needs a
    comparison; a row to correct is the first of the readings' example), made from the
    document's own examples; and the run's id."""
    opening = body_examples(document, "/api/v1/runs")[0]
    run = client.post("/api/v1/runs", json=opening, headers=auth(WRITER)).json()["id"]
    purpose = "comparison" if isinstance(value, dict) and value.get("level") else "repeatability"
    series_body = next(
        e for e in body_examples(document, "/api/v1/series") if e["purpose"] == purpose
    )
    series = client.post("/api/v1/series", json=series_body, headers=auth(WRITER))
    if "{index}" in path:  # a correction: of the first row of the readings' own example
        batch = body_examples(document, "/api/v1/runs/{run_id}/readings")[0]
        client.post(f"/api/v1/runs/{run}/readings", json=batch, headers=auth(WRITER))
        path = path.replace("{group}", batch["group"]).replace("{index}", "0")
    return path.replace("{run_id}", run).replace("{series_id}", series.json()["id"]), run


def test_every_request_body_has_an_example_the_service_takes(client: TestClient) -> None:
    document = client.get("/openapi.json").json()
    posted = 0
    for path, operations in document["paths"].items():
        for method, operation in operations.items():
            for media_type, media in operation.get("requestBody", {}).get("content", {}).items():
                found = examples(document, media)
                assert found, f"{method.upper()} {path} {media_type}: no example"
                for example in found:
                    if "externalValue" in example:  # a binary body; its query from the examples
                        url, _ = made_for(client, document, path, None)
                        for p in operation.get("parameters", []):  # a sketch's item
                            if p["in"] == "path" and "examples" in p["schema"]:
                                url = url.replace(
                                    f"{{{p['name']}}}", str(p["schema"]["examples"][0])
                                )
                        content = client.get(example["externalValue"]).content
                        params = {
                            p["name"]: p["example"]
                            for p in operation.get("parameters", [])
                            if p["in"] == "query" and "example" in p
                        }
                    else:
                        assert media_type == JSON
                        value, params = example["value"], {}
                        url, run = made_for(client, document, path, value)
                        if isinstance(value, dict) and "run_id" in value:  # a run that exists
                            value = {**value, "run_id": run}
                        content = json.dumps(value).encode()
                    r = client.request(
                        method,
                        url,
                        content=content,
                        params=params,
                        headers={**auth(WRITER), "Content-Type": media_type},
                    )
                    assert r.is_success, f"{method.upper()} {path} {media_type}: {r.text}"
                    posted += 1
    assert posted >= 11  # readings (JSON, npz), a run, 5 calculators, 2 series, a member


def test_the_binary_example_is_the_json_example_as_npz(client: TestClient) -> None:
    document = client.get("/openapi.json").json()
    content = document["paths"]["/api/v1/runs/{run_id}/readings"]["post"]["requestBody"]["content"]
    (json_example,) = examples(document, content["application/json"])
    (npz_example,) = examples(document, content[NPZ_MEDIA_TYPE])
    archive = np.load(io.BytesIO(client.get(npz_example["externalValue"]).content))
    columns = json_example["value"]["columns"]
    assert sorted(archive.files) == sorted(columns)
    for name, values in columns.items():
        np.testing.assert_array_equal(archive[name], values)
