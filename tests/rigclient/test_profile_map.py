"""The map's ``[profile]`` table (issue 37, item 4): the profile an instrument exported, as
the profilometer run's configuration (profile_kind, lambda_c, lambda_s, sections)."""

from __future__ import annotations

from pathlib import Path

import pytest

from rigclient.agent import run_metadata
from rigclient.errors import InputError
from rigclient.mapping import load_map

PM7 = """\
[columns]
"X, mm" = "x"
"Z, um" = "y"
[profile]
kind = "roughness"
lambda_c = { value = 0.8, unit = "mm" }
lambda_s = { value = 2.5, unit = "um" }
sections = 5
"""


def test_the_profile_table_becomes_the_run_configuration(tmp_path: Path) -> None:
    path = tmp_path / "pm7.toml"
    path.write_text(PM7, encoding="utf-8")
    meta = run_metadata(tmp_path / "trace.csv", "profilometer", load_map(path))
    assert meta["configuration"] == {
        "profile_kind": "roughness",
        "lambda_c": pytest.approx(0.8e-3, rel=1e-12),  # mm -> m, the field's unit
        "lambda_s": pytest.approx(2.5e-6, rel=1e-12),
        "sections": 5,
    }


@pytest.mark.parametrize(
    ("table", "said"),
    [
        ('kind = "filtered"', "profile.kind: Input should be 'primary' or 'roughness'"),
        ("cutoff = 0.8", "profile.cutoff: not a key of the map's [profile]; it takes kind"),
        (
            "sections = 5\n[run.configuration]\nsections = 4",
            "[profile] sections and [run.configuration] sections both set it",
        ),
    ],
)
def test_a_wrong_profile_table_is_named(tmp_path: Path, table: str, said: str) -> None:
    path = tmp_path / "pm7.toml"
    path.write_text(f"[profile]\n{table}\n", encoding="utf-8")
    with pytest.raises(InputError, match=said.replace("[", r"\[").replace("]", r"\]")):
        load_map(path)
