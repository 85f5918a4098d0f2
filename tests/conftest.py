"""Test-wide settings: hypothesis runs derandomized in CI, so a failure reproduces."""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
