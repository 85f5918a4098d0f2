"""What real instruments add to a true value: offsets, drift, noise, quantisation; and faults.

Small functions, each one effect, driven by a :class:`numpy.random.Generator` where random;
:class:`Instrument` composes them in the order a reading is made (the sensor's zero offset
and drift, then noise, then the dial's or converter's quantisation). :class:`Fault` and
:func:`apply_faults` break a group's readings on request: a dropout (rows lost), a spike (one
reading off, within the channel's limits), a stuck channel (one value repeated) and a
reading outside the channel's declared limits (which the server must refuse).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigsim.errors import SettingsError
from schemas.channels import Channel, ChannelGroup, Limit

FloatArray = NDArray[np.float64]

FaultKind = Literal["dropout", "spike", "stuck", "out_of_limit"]
FAULT_KINDS: tuple[FaultKind, ...] = ("dropout", "spike", "stuck", "out_of_limit")


def add_noise(values: ArrayLike, sigma: float, rng: np.random.Generator) -> FloatArray:
    """Values plus independent Gaussian noise of standard deviation ``sigma`` (>= 0)."""
    v = np.asarray(values, dtype=np.float64)
    if sigma < 0:
        raise SettingsError(f"noise sigma must be >= 0, got {sigma}")
    return v + rng.normal(0.0, sigma, v.shape) if sigma > 0 else v.copy()


def quantise(values: ArrayLike, step: float) -> FloatArray:
    """Values rounded to the nearest multiple of ``step`` (the resolution); 0 leaves them.

    The multiples are then rounded to the step's decimals, so 0.1·264 reads 26.4, as the
    dial shows it, not 26.400000000000002.
    """
    v = np.asarray(values, dtype=np.float64)
    if step < 0:
        raise SettingsError(f"resolution must be >= 0, got {step}")
    if step == 0:
        return v.copy()
    decimals = max(0, int(np.ceil(-np.log10(step))) + 1)
    return np.asarray(np.round(np.round(v / step) * step, decimals), dtype=np.float64)


def add_drift(values: ArrayLike, time: ArrayLike, rate: float) -> FloatArray:
    """Values plus a linear drift ``rate``·t (unit per second, t in s from the start)."""
    return np.asarray(values, dtype=np.float64) + rate * np.asarray(time, dtype=np.float64)


@dataclass(frozen=True, slots=True)
class Instrument:
    """One channel's instrument, in the channel's unit.

    Attributes
    ----------
    resolution : float
        Quantisation step of the dial or converter (0: none).
    noise : float
        Standard deviation of the reading noise.
    offset : float
        Zero offset: the reading at a true value of zero.
    drift : float
        Drift of the zero, per second of stand time.
    """

    resolution: float = 0.0
    noise: float = 0.0
    offset: float = 0.0
    drift: float = 0.0

    def read(
        self, true: ArrayLike, rng: np.random.Generator, time: ArrayLike | None = None
    ) -> FloatArray:
        """Readings of the true values (taken at stand times ``time``, s, for the drift)."""
        v = np.asarray(true, dtype=np.float64) + self.offset
        if self.drift and time is not None:
            v = add_drift(v, time, self.drift)
        return quantise(add_noise(v, self.noise, rng), self.resolution)


@dataclass(frozen=True, slots=True)
class Fault:
    """A fault asked of a simulated instrument.

    Attributes
    ----------
    kind : {"dropout", "spike", "stuck", "out_of_limit"}
        dropout: ``rows`` rows lost from the group (every channel of an aligned group);
        spike: one reading off by ``size`` (clipped to the channel's limits);
        stuck: the channel repeats one value for ``rows`` rows;
        out_of_limit: one reading beyond the channel's declared limit.
    group : str
        Channel group of the faulty channel.
    channel : str
        The faulty channel (for a dropout in an aligned group, any of its channels).
    at : float
        Where the fault starts, as a fraction 0..1 of the group's rows.
    rows : int
        Rows affected (dropout, stuck).
    size : float
        Height of a spike, in the channel's unit.
    """

    kind: FaultKind
    group: str
    channel: str
    at: float = 0.5
    rows: int = 1
    size: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in FAULT_KINDS:
            raise SettingsError(f"fault kind must be one of {FAULT_KINDS}, got {self.kind!r}")
        if not 0.0 <= self.at <= 1.0:
            raise SettingsError(f"fault.at must lie in [0, 1], got {self.at}")
        if self.rows < 1:
            raise SettingsError(f"fault.rows must be >= 1, got {self.rows}")


def beyond_limit(channel: Channel) -> float:
    """A value of ``channel`` that breaks its declared limit (above it where it has a top)."""
    limit: Limit = channel.limit
    if limit.high is not None:
        return limit.high + max(abs(limit.high) * 0.1, 1.0)
    if limit.low is not None:
        return limit.low - max(abs(limit.low) * 0.1, 1.0)
    if limit.nominal is not None:
        return max(limit.nominal) * (1.0 + limit.tolerance) * 1.5 + 1.0
    raise SettingsError(
        f"channel {channel.name!r} declares no limit: a reading outside it cannot be made"
    )


def _clip(values: FloatArray, limit: Limit) -> FloatArray:
    low = -np.inf if limit.low is None else limit.low
    high = np.inf if limit.high is None else limit.high
    return np.clip(values, low, high)


def apply_faults(
    group: ChannelGroup,
    columns: Mapping[str, ArrayLike],
    time: ArrayLike,
    faults: Sequence[Fault],
) -> tuple[dict[str, FloatArray], FloatArray]:
    """The group's columns and row times with the faults of this group applied in order.

    Faults naming another group are skipped; a fault naming a channel the group does not
    have is a :class:`SettingsError`.
    """
    out = {k: np.asarray(v, dtype=np.float64).copy() for k, v in columns.items()}
    times = np.asarray(time, dtype=np.float64).copy()
    for fault in (f for f in faults if f.group == group.name):
        channel = group.channel(fault.channel)
        if channel is None or fault.channel not in out:
            raise SettingsError(
                f"fault on {fault.group}.{fault.channel}: the group posts no such channel"
            )
        values = out[fault.channel]
        n = values.size
        start = min(int(fault.at * n), n - 1)
        stop = min(start + fault.rows, n)
        if fault.kind == "dropout":
            if group.aligned:
                keep = np.ones(n, dtype=bool)
                keep[start:stop] = False
                out = {k: v[keep] for k, v in out.items()}
                times = times[keep]
            else:
                del out[fault.channel]
        elif fault.kind == "stuck":
            values[start:stop] = values[start]
        elif fault.kind == "spike":
            values[start] = _clip(np.asarray([values[start] + fault.size]), channel.limit)[0]
        else:
            values[start] = beyond_limit(channel)
    return out, times
