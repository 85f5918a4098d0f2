"""The exceptions of rigsim.

::

    Exception
     └── RigsimError                 anything rigsim reports
          ├── SettingsError (also ValueError)
          │                          a stand setting the simulated stand cannot run
          │                          (names the setting, its value and the limit)
          └── PortInUse              the demo's port is taken (another demo or server)

The server's answers are rigclient's (rigsim posts through it), re-exported here:
:class:`ServerError`, :class:`ServerRefused` (an answer a retry would not change) and
:class:`ServerUnavailable` (unreachable or overloaded past the retry budget), all
:class:`rigclient.errors.RigclientError`.
"""

from __future__ import annotations

from rigclient.errors import ServerError, ServerRefused, ServerUnavailable


class RigsimError(Exception):
    """Base of every error rigsim raises."""


class SettingsError(RigsimError, ValueError):
    """A setting outside what the simulated stand can do."""


class PortInUse(RigsimError):
    """Something already listens on the port the demo would serve on."""


__all__ = [
    "PortInUse",
    "RigsimError",
    "ServerError",
    "ServerRefused",
    "ServerUnavailable",
    "SettingsError",
]
