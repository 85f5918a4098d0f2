"""The exceptions of rigsim.

::

    Exception
     └── RigsimError                 anything rigsim reports
          ├── SettingsError (also ValueError)
          │                          a stand setting the simulated stand cannot run
          │                          (names the setting, its value and the limit)
          ├── PortInUse              the demo's port is taken (another demo or server)
          └── ServerError            the server could not take what the lab PC sent
               ├── ServerRefused     an answer that a retry would not change (4xx, 500):
               │                     the problem's title, detail and fields
               └── ServerUnavailable the server stayed unreachable or overloaded past the
                                     retry budget (the last cause is chained)

Transport errors of httpx are translated at the client's boundary and chained with
``raise ... from``; they never leave rigsim bare.
"""

from __future__ import annotations

from schemas.problems import Problem


class RigsimError(Exception):
    """Base of every error rigsim raises."""


class SettingsError(RigsimError, ValueError):
    """A setting outside what the simulated stand can do."""


class PortInUse(RigsimError):
    """Something already listens on the port the demo would serve on."""


class ServerError(RigsimError):
    """The server did not take a request."""


class ServerRefused(ServerError):
    """The server answered with a problem that retrying the same request will not change."""

    def __init__(self, problem: Problem) -> None:
        fields = "; ".join(e.message for e in problem.errors[:3] if e.message)
        text = f"{problem.status} {problem.title}: {problem.detail}"
        super().__init__(f"{text} ({fields})" if fields and fields not in text else text)
        self.problem = problem


class ServerUnavailable(ServerError):
    """The server stayed unreachable or overloaded after every retry."""
