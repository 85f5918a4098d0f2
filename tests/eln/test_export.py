"""Every stand's run and a series as .eln archives, judged by the tools others use:
roc-validator (the RO-Crate 1.1 profile), the rocrate package, pyld's JSON-LD expansion;
and by what the ELN consortium's format asks (one root folder, the metadata in it, every
file described with its type, size and checksum)."""

from __future__ import annotations

import hashlib
import json
import subprocess
from pathlib import Path
from typing import Any
from urllib.parse import urljoin

import pytest
import rocrate
from pyld import jsonld
from rocrate.rocrate import ROCrate

from rigserver.reports.eln import (
    CONTEXT,
    METADATA,
    NO_LICENCE,
    SOFTWARE,
    UNIT_CODES,
    rig_version,
    term,
)
from schemas.stands import StandKind, default_stands
from tests.api.conftest import WRITER, auth
from tests.eln.conftest import (
    LICENCE,
    Lab,
    export,
    graph_of,
    import_archive,
    members,
    unzipped,
)
from tests.i18n.messages import ROOT

KINDS = list(StandKind)
#: The RO-Crate JSON-LD context as the rocrate package ships it (no network here)
LOCAL_CONTEXT = Path(rocrate.__file__).parent / "data" / "ro-crate.jsonld"
#: The base of a crate's relative ids when it is read as RDF (RO-Crate 1.1, appendix:
#: "arcp" URIs for a crate that has no address of its own)
BASE = "arcp://uuid,0b9e4c1e-6a52-4f6e-9c5e-8d1f0e3b7a21/"
VALIDATOR = ROOT / ".venv-crate" / "bin" / "python"


def _links(value: Any) -> list[str]:
    items = value if isinstance(value, list) else [value]
    return [item["@id"] for item in items if isinstance(item, dict)]


def _run_dataset(graph: dict[str, dict[str, Any]], run_id: str) -> dict[str, Any]:
    return graph[f"{run_id}/"]


@pytest.mark.parametrize("kind", KINDS)
def test_one_root_folder_holds_the_metadata_and_every_file(lab: Lab, kind: StandKind) -> None:
    run_id = lab.runs[kind]
    files = members(lab.archives[kind])
    assert {name.split("/", 1)[0] for name in files} == {run_id}  # named as the archive
    assert f"{run_id}/{METADATA}" in files
    inside = {name.removeprefix(f"{run_id}/{run_id}/") for name in files if name.count("/") == 2}
    groups = {f"{g.name}.csv" for g in default_stands()[kind].groups}
    reports = {f"report-{lang}.{kind}" for lang in ("en", "ru") for kind in ("pdf", "html")}
    assert {f"{run_id}.h5", "run.json", "results.json", "results.csv"} | groups | reports <= inside
    graph = graph_of(lab.archives[kind])
    for name, data in files.items():
        if name.endswith(METADATA):
            continue
        node = graph[name.removeprefix(f"{run_id}/")]
        assert node["@type"] == "File"
        assert node["contentSize"] == str(len(data)), name
        assert node["sha256"] == hashlib.sha256(data).hexdigest(), name
        assert node["encodingFormat"] in {
            "application/x-hdf5",
            "application/json",
            "text/csv",
            "application/pdf",
            "text/html",
        }
    assert files[f"{run_id}/{run_id}/report-ru.pdf"].startswith(b"%PDF")


@pytest.mark.parametrize("kind", KINDS)
def test_the_metadata_describes_the_run_once_and_links_it(lab: Lab, kind: StandKind) -> None:
    run_id = lab.runs[kind]
    graph = graph_of(lab.archives[kind])
    dataset = _run_dataset(graph, run_id)
    assert _links(dataset["additionalType"]) == [term("TribologicalTesting")]
    assert dataset["identifier"] == run_id
    assert dataset["creativeWorkStatus"] == "finished"
    assert dataset["dateCreated"].startswith(run_id[:4])
    assert "dateModified" in dataset and "/" in dataset["temporalCoverage"]
    person = graph[_links(dataset["author"])[0]]
    assert person == {"@id": "#person-rigsim", "@type": "Person", "name": "rigsim"}
    # the run, its operator, stand, software and specimens, linked by the CreateAction
    action = graph[f"#run-{run_id}"]
    assert action["@type"] == "CreateAction"
    assert _links(action["result"]) == [f"{run_id}/"]
    assert _links(action["agent"]) == [person["@id"]]
    stand_id, software = _links(action["instrument"])
    assert software == SOFTWARE and graph[SOFTWARE]["version"] == rig_version()
    assert graph[SOFTWARE]["@type"] == "SoftwareApplication"
    stand = graph[stand_id]
    assert _links(stand["additionalType"]) == [term("Device")]
    assert stand["name"] == default_stands()[kind].title
    specimens = [graph[s] for s in _links(action["object"])]
    assert specimens and all(term("Sample") in _links(s["additionalType"]) for s in specimens)
    for specimen in specimens:
        material = graph[_links(specimen["material"])[0]]
        assert _links(material["additionalType"]) == [term("Material")]
        assert specimen["name"].endswith(material["name"])
    # each entity once (the validator and rocrate would find a duplicate @id too)
    ids = [node["@id"] for node in json.loads(_metadata_text(lab, kind))["@graph"]]
    assert len(ids) == len(set(ids))


def _metadata_text(lab: Lab, kind: StandKind) -> bytes:
    run_id = lab.runs[kind]
    return members(lab.archives[kind])[f"{run_id}/{METADATA}"]


def test_the_stand_declares_its_limits_of_error(lab: Lab) -> None:
    # the SMTs-2's accuracy section (schemas/stands.py): moment 1 %, load 5 %, balance 0.1 mg
    graph = graph_of(lab.archives[StandKind.SMTS2])
    stand = graph["#stand-smts2"]
    limits = {graph[i]["propertyID"]: graph[i] for i in _links(stand["additionalProperty"])}
    balance = limits["configuration.accuracy.balance_resolution"]
    assert balance["value"] == pytest.approx(1e-7)
    assert balance["unitText"] == "kg" and balance["unitCode"] == "KGM"
    assert balance["identifier"] == term("MeasurementError")
    assert limits["configuration.accuracy.load"]["value"] == pytest.approx(0.05)
    assert limits["configuration.accuracy.load"]["unitCode"] == "C62"  # relative: one


def test_results_carry_units_and_uncertainties(lab: Lab) -> None:
    run_id = lab.runs[StandKind.SMTS2]
    graph = graph_of(lab.archives[StandKind.SMTS2])
    payload = lab.source.get(f"/api/v1/runs/{run_id}/results", headers=auth(WRITER)).json()
    values = payload["values"]
    measured = {
        graph[i]["propertyID"]: graph[i]
        for i in _links(_run_dataset(graph, run_id)["variableMeasured"])
    }
    friction = measured["results.friction_steady"]
    assert friction["@type"] == "PropertyValue"
    assert friction["value"] == values["friction_steady"]  # SI, full precision
    assert friction["identifier"] == term("CoefficientOfFriction")
    assert friction["unitCode"] == UNIT_CODES["1"]
    u, expanded = (graph[i] for i in _links(friction["valueReference"]))
    assert u["value"] == values["friction_steady_uncertainty"]
    assert expanded["value"] == values["friction_steady_expanded"]
    assert u["identifier"] == term("MeasurementError")
    distance = measured["results.sliding_distance"]
    assert distance["unitText"] == "m" and distance["unitCode"] == "MTR"
    assert distance["identifier"] == term("SlidingDistance")
    assert "results.friction_steady_uncertainty" not in measured  # beside its result only
    load = measured["test_plan.load_N"]
    assert load["identifier"] == term("NormalForce")
    assert (load["value"], load["unitText"], load["unitCode"]) == (300.0, "N", "NEW")


def test_the_licence_is_the_servers_setting(lab: Lab) -> None:
    graph = graph_of(lab.archives[StandKind.MTOS])
    licence = "https://spdx.org/licenses/" + LICENCE
    assert _links(graph["./"]["license"]) == [licence]
    assert graph[licence]["name"] == LICENCE
    # a server without the setting says that no licence was granted, and whom to ask
    graph = graph_of(_default_archive(lab))
    assert _links(graph["./"]["license"]) == [NO_LICENCE]
    assert graph[NO_LICENCE]["name"] == "No licence granted"
    assert "rig server at http://lab-b/" in graph[NO_LICENCE]["description"]


def _default_archive(lab: Lab) -> bytes:
    """An archive of the server without ``--license`` (the run imported there first)."""
    answer = import_archive(lab.target, lab.archives[StandKind.PROFILOMETER])
    assert answer.status_code == 201, answer.text
    return export(lab.target, f"/api/v1/runs/{answer.json()['id']}/export.eln")


@pytest.mark.parametrize("kind", KINDS)
def test_rocrate_reads_it(lab: Lab, kind: StandKind, tmp_path: Path) -> None:
    crate = ROCrate(unzipped(lab.archives[kind], tmp_path))
    run_id = lab.runs[kind]
    assert crate.root_dataset["name"] == f"rig run {run_id}"
    dataset = crate.dereference(f"{run_id}/")
    assert dataset is not None and dataset["identifier"] == run_id
    files = {e.id for e in crate.data_entities}
    assert f"{run_id}/{run_id}.h5" in files and f"{run_id}/results.csv" in files
    assert crate.dereference(SOFTWARE)["version"] == rig_version()


def _expand(document: dict[str, Any]) -> list[dict[str, Any]]:
    context = json.loads(LOCAL_CONTEXT.read_text())["@context"]

    def loader(url: str, options: Any = None) -> dict[str, Any]:
        assert url == CONTEXT, url  # the one remote document an archive names
        return {"contextUrl": None, "documentUrl": url, "document": {"@context": context}}

    options = {"documentLoader": loader, "base": BASE}
    found: list[dict[str, Any]] = jsonld.expand(document, options)
    return found


@pytest.mark.parametrize("kind", KINDS)
def test_the_json_ld_expands(lab: Lab, kind: StandKind) -> None:
    compact = json.loads(_metadata_text(lab, kind))
    expanded = _expand(compact)
    by_id = {node["@id"]: node for node in expanded if "@id" in node}
    run = by_id[f"{BASE}{lab.runs[kind]}/"]
    assert run["http://schema.org/additionalType"] == [{"@id": term("TribologicalTesting")}]
    # every entity comes through, and every term of it: expansion drops a term the
    # context does not define
    assert len(by_id) == len(compact["@graph"])
    for node in compact["@graph"]:
        terms = {k for k in node if not k.startswith("@")}
        got = by_id[urljoin(BASE, node["@id"])]
        assert len(terms) == len([k for k in got if not k.startswith("@")]), node["@id"]


def _validate(crate: Path) -> subprocess.CompletedProcess[str]:
    if not VALIDATOR.exists() or not (ROOT / ".venv-crate" / "bin" / ".installed").exists():
        pytest.skip("roc-validator is not installed in .venv-crate (make test installs it)")
    command = [str(VALIDATOR), str(Path(__file__).with_name("crate_validator.py"))]
    command += [str(LOCAL_CONTEXT), "-y", "--disable-color", "validate", "-p", "ro-crate-1.1"]
    command += ["--no-paging", "-f", "json", str(crate)]
    return subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)


@pytest.mark.parametrize("kind", KINDS)
def test_roc_validator_passes_every_stands_archive(
    lab: Lab, kind: StandKind, tmp_path: Path
) -> None:
    done = _validate(unzipped(lab.archives[kind], tmp_path))
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    report = json.loads(done.stdout[done.stdout.index("{") :])
    assert report["passed"] is True, done.stdout[-3000:]


def test_roc_validator_passes_the_default_configurations_archive(lab: Lab, tmp_path: Path) -> None:
    """No ``--license``: RO-Crate 1.1 requires the root's licence all the same."""
    done = _validate(unzipped(_default_archive(lab), tmp_path))
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert json.loads(done.stdout[done.stdout.index("{") :])["passed"] is True


def test_roc_validator_fails_a_broken_crate(lab: Lab, tmp_path: Path) -> None:
    # the validator can fail: a root Dataset without its name and date is no RO-Crate 1.1
    crate = unzipped(lab.archives[StandKind.PROFILOMETER], tmp_path)
    document = json.loads((crate / METADATA).read_text())
    for node in document["@graph"]:
        if node["@id"] == "./":
            del node["datePublished"], node["name"]
    (crate / METADATA).write_text(json.dumps(document))
    assert _validate(crate).returncode != 0


def test_the_series_archive_holds_each_run_and_the_statistics(lab: Lab, tmp_path: Path) -> None:
    graph = graph_of(lab.series_archive)
    series = graph[f"{lab.series_id}/"]
    assert _links(series["additionalType"]) == [term("TestSeries")]
    runs = _links(series["mentions"])
    assert len(runs) == 2 and _links(graph["./"]["hasPart"]) == [f"{lab.series_id}/", *runs]
    for run in runs:
        assert _links(graph[run]["isPartOf"]) == [f"{lab.series_id}/"]
        assert f"{run}{run.rstrip('/')}.h5" in {_links(graph[run]["hasPart"])[0]}
    names = {n.split("/", 1)[1] for n in members(lab.series_archive)}
    assert {f"{lab.series_id}/series.json", f"{lab.series_id}/runs.csv"} <= names
    stats = {graph[i]["propertyID"]: graph[i] for i in _links(series["variableMeasured"])}
    detail = json.loads(members(lab.series_archive)[f"{lab.series_id}/{lab.series_id}/series.json"])
    ra = next(s for s in detail["statistics"] if s["key"] == "ra")
    assert stats["statistics.ra.mean"]["value"] == ra["overall"]["mean"]
    assert stats["statistics.ra.mean"]["identifier"] == term("Ra")
    # the operator of both runs is one entity
    assert sum(1 for node in graph.values() if node["@type"] == "Person") == 1
    done = _validate(unzipped(lab.series_archive, tmp_path))
    assert done.returncode == 0, done.stdout[-3000:]
    ROCrate(tmp_path / lab.series_id)


@pytest.mark.parametrize(
    ("lang", "words"),
    [("en", "Everything for an electronic lab notebook"), ("ru", "электронного лабораторного")],
)
def test_the_run_and_series_pages_link_the_archive(lab: Lab, lang: str, words: str) -> None:
    run_id = lab.runs[StandKind.MTOS]
    for page, link in (
        (f"/runs/{run_id}", f"/api/v1/runs/{run_id}/export.eln"),
        (f"/series/{lab.series_id}", f"/api/v1/series/{lab.series_id}/export.eln"),
    ):
        html = lab.source.get(f"{page}?lang={lang}", headers=auth(WRITER)).text
        anchor = html[html.index('id="export-eln"') :]
        assert f'href="{link}"' in anchor[: anchor.index(">")]
        assert words in anchor[: anchor.index("</a>")]
