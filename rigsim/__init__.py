"""rigsim: simulated tribology stands that post readings to a real rigserver over HTTP.

- :mod:`rigsim.simulators`: the lab's four stands and the two tribometers,
  ``simulate(settings, seed) -> SimulatedRun`` (the run to open, its batches in stand
  order, and the truth).
- :mod:`rigsim.instruments`: offsets, drift, noise, quantisation and faults.
- :mod:`rigsim.bearing_model`, :mod:`rigsim.thermal`: the physics behind the bearing stands.
- :mod:`rigsim.client`: the simulated lab PC (pacing, sequence numbers), posting through
  :mod:`rigclient.http` (retries, backoff, Retry-After, duplicate receipts).
- :mod:`rigsim.cli`: ``rigsim run``, ``rigsim demo`` and ``rigsim export`` (a tribometer's
  test as a vendor's program writes it, :mod:`rigsim.export`).
"""

from rigsim.batches import Batch, SimulatedRun
from rigsim.client import LabClient, RetryPolicy, RunOutcome
from rigsim.errors import (
    RigsimError,
    ServerError,
    ServerRefused,
    ServerUnavailable,
    SettingsError,
)
from rigsim.instruments import Fault, Instrument
from rigsim.simulators import SIMULATORS, simulate

__all__ = [
    "SIMULATORS",
    "Batch",
    "Fault",
    "Instrument",
    "LabClient",
    "RetryPolicy",
    "RigsimError",
    "RunOutcome",
    "ServerError",
    "ServerRefused",
    "ServerUnavailable",
    "SettingsError",
    "SimulatedRun",
    "simulate",
]
