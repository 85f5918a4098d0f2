"""The rigclient processes' fixture, for the import of rigsim's exports."""

from tests.rigclient.conftest import agents  # noqa: F401 (a fixture, registered by import)
