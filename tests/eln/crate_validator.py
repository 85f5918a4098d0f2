"""rocrate-validator's CLI, run by the python of ``.venv-crate`` (see the Makefile).

This machine has no network: the validator's one remote resource, the RO-Crate 1.1 JSON-LD
context, is served from the copy that the ``rocrate`` package ships (its path is the
first argument); every check runs as the CLI runs it. Usage::

    .venv-crate/bin/python tests/eln/crate_validator.py CONTEXT.jsonld validate ...
"""

import json
import sys

import requests
from rocrate_validator.utils.http import HttpRequester

CONTEXTS = ("https://w3id.org/ro/crate/1.1/context", "http://w3id.org/ro/crate/1.1/context")

with open(sys.argv.pop(1), encoding="utf-8") as source:
    CONTEXT = json.dumps({"@context": json.load(source)["@context"]}).encode()


def _get(self, url, **kwargs):  # type: ignore[no-untyped-def]
    if url.rstrip("/") not in CONTEXTS:
        return self.__getattr__("get")(url, **kwargs)
    answer = requests.Response()
    answer.status_code = 200
    answer._content = CONTEXT
    answer.headers["Content-Type"] = "application/ld+json"
    answer.url = url
    return answer


HttpRequester.get = _get

from rocrate_validator.cli import cli  # noqa: E402

sys.exit(cli())
