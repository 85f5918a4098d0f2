"""``rigserver serve``'s flags are derived from :class:`Settings`: every setting one flag
(a secret none), given on the command line it reaches the service, not given it comes from
the environment or its default."""

from __future__ import annotations

import typing
from pathlib import Path
from typing import Any, Literal

import pytest
from pydantic.fields import FieldInfo

from rigserver.api.settings import Flag, Settings
from rigserver.cli import given_settings, parser

ON_THE_COMMAND_LINE = [
    name
    for name, field in Settings.model_fields.items()
    if not any(isinstance(m, Flag) and m.env_only for m in field.metadata)
]


def _serve(*flags: str) -> Settings:
    return given_settings(parser().parse_args(["serve", *flags]))


def _flag(name: str, field: FieldInfo) -> str:
    named = next((m.name for m in field.metadata if isinstance(m, Flag) and m.name), None)
    return f"--{named or name.replace('_', '-')}"


def _not_the_default(name: str, field: FieldInfo) -> tuple[list[str], Any]:
    """Flags setting ``name`` to a value other than its default, and that value."""
    flag, default = _flag(name, field), field.get_default(call_default_factory=True)
    kind = field.annotation
    if typing.get_origin(kind) is Literal:
        other = next(c for c in typing.get_args(kind) if c != default)
        return [flag, other], other
    if kind is bool:
        return ([f"--no-{flag[2:]}"] if default else [flag]), not default
    if typing.get_origin(kind) is tuple:
        return [flag, "http://a.lab", flag, "http://b.lab"], ("http://a.lab", "http://b.lab")
    if kind is int:
        return [flag, str(default + 1)], default + 1
    if kind is float:  # halved, a share stays within (0, 1]; 0 (no limit) becomes 1
        value = default / 2 if default else 1.0
        return [flag, str(value)], value
    if kind in (Path, Path | None):
        return [flag, "/srv/elsewhere"], Path("/srv/elsewhere")
    assert kind in (str, str | None), f"{name}: a flag of {kind} has no test value here"
    return [flag, "given"], "given"


@pytest.mark.parametrize("name", ON_THE_COMMAND_LINE)
def test_every_setting_is_a_flag_that_reaches_the_settings(name: str) -> None:
    flags, value = _not_the_default(name, Settings.model_fields[name])
    assert getattr(_serve(*flags), name) == value
    assert _serve() == Settings()  # and without it, the default


def test_the_flag_wins_over_the_environment_which_wins_over_the_default(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv("RIG_RATE_BURST", "7")
    assert _serve().rate_burst == 7
    assert _serve("--rate-burst", "9").rate_burst == 9


def test_a_secret_is_no_flag(capsys: pytest.CaptureFixture[str]) -> None:
    """A command line is seen by every user of the machine (ps): the HSDS password is read
    from the environment only."""
    assert "hsds_password" in Settings.model_fields
    assert "hsds_password" not in ON_THE_COMMAND_LINE
    with pytest.raises(SystemExit) as stop:
        _serve("--hsds-password", "secret")
    assert stop.value.code == 2
    assert "--hsds-password" in capsys.readouterr().err


def test_the_help_names_each_flag_its_variable_and_its_meaning(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(SystemExit):
        _serve("--help")
    text = " ".join(capsys.readouterr().out.split())
    for name in ON_THE_COMMAND_LINE:
        field = Settings.model_fields[name]
        assert field.description, f"{name}: a setting says what it is (its flag's help)"
        assert _flag(name, field) in text
        assert f"RIG_{name.upper()}" in text
        assert " ".join(str(field.description).split()) in text


def test_the_flags_of_the_readme_are_kept() -> None:
    """The flags the README and the lab's scripts use (rigserver/cluster.py, rigsim's
    demo) are still there, with their types and choices."""
    settings = _serve(
        *("--data-dir", "/srv/rig", "--keys-file", "keys.json", "--public-reads"),
        *("--cors-origin", "http://a.lab", "--synchronous", "full", "--max-body-bytes", "5"),
    )
    assert settings.data_dir == Path("/srv/rig")
    assert settings.keys_file == Path("keys.json")
    assert settings.public_reads is True
    assert settings.cors_origins == ("http://a.lab",)
    assert settings.synchronous == "full"
    assert settings.max_body_bytes == 5
    with pytest.raises(SystemExit):
        _serve("--synchronous", "sometimes")


def test_a_bad_setting_is_named_with_why_not_a_traceback(monkeypatch: pytest.MonkeyPatch) -> None:
    # a flag is named as typed, a variable of the environment as set; both at once
    monkeypatch.setenv("RIG_SYNCHRONOUS", "sometimes")
    with pytest.raises(SystemExit) as stopped:
        _serve("--report-workers", "0")
    said = str(stopped.value.code)
    assert said.startswith("rigserver: ")
    assert "--report-workers: Input should be greater than 0 (given 0)" in said
    assert "RIG_SYNCHRONOUS: Input should be 'normal' or 'full' (given 'sometimes')" in said
