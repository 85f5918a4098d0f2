"""Where the running-in ends: the end of the transient, where the friction's level has
settled into a band a tribologist calls steady; the change points in the mean beside it.

1. The record is reduced to one mean per lap (pin-on-disc) or per cycle (reciprocating),
   grouped into at most :data:`MAX_POINTS` consecutive blocks of whole laps: a once-per-lap
   part (a disc's run-out) averages out and the readings' short-term correlation with it.
2. The steady part is the longest tail of blocks that all stay within ±δ of its own mean,
   δ = :data:`~rigserver.core.tribometer.STEADY_BAND` (5 %), widened by the blocks' noise
   z·σ̂ (:func:`rigserver.core.tribometer.settled_from`); it must hold at least a fifth of
   the record, else the friction did not settle and no running-in distance is given. A slow
   drift of the steady level (up to 2δ over the steady part) stays inside the band; a join
   test against the noise alone read any drift as running-in still going on.
   σ̂ is the noise of one block, from the median absolute deviation of the second
   differences of neighbouring blocks, σ̂ = MAD(Δ²y)/(0.6745·√6) (Var Δ²y = 6σ² for
   independent blocks; differences remove a smooth trend, the difference-based estimators
   of T. Gasser, L. Sroka, C. Jennen-Steinmetz, Biometrika 73 (1986) 625-633, and the
   median ignores the few a step or a kink disturbs); z = Φ⁻¹(1 - 0.01/(2n)), a two-sided
   1 % with Bonferroni's correction over the n blocks (4.05 for 200 blocks), so that the
   noise of a steady block leaves the band at 1 % of the records; a floor of 10⁻⁹ of the
   mean keeps σ̂ above the arithmetic's noise.
3. PELT (R. Killick, P. Fearnhead, I. A. Eckley, "Optimal detection of changepoints with a
   linear computational cost", J. Amer. Statist. Assoc. 107 (2012) 1590-1598), by the
   ``ruptures`` package (C. Truong, L. Oudre, N. Vayatis, Signal Processing 167 (2020)
   107299), counts the changes in the mean with the squared-error cost and the penalty
   β = 2σ̂²·ln n, Schwarz's information criterion for a change in a Gaussian mean of known
   variance (the default "SIC" of Killick's changepoint package). They are reported beside
   the running-in; a drift shows as many of them, which is why they no longer decide it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import ruptures
from numpy.typing import ArrayLike
from scipy.stats import norm

from rigserver.core.tribometer import STEADY_BAND, settled_from

#: Blocks PELT works on at most (its cost grows with their number).
MAX_POINTS = 250
#: The share of steady records whose noise leaves the band (before Bonferroni).
NOISE_ALPHA = 0.01
#: σ̂ of a noiseless record, relative to the mean: β stays above round-off.
NOISE_FLOOR = 1e-9
_MAD_TO_SIGMA = 1.0 / (0.6744897501960817 * math.sqrt(6.0))


@dataclass(frozen=True, slots=True)
class RunningIn:
    """The steady part's first block (None: the record did not settle), the change points
    (block indices), σ̂ and β."""

    steady_from: int | None
    change_points: tuple[int, ...]
    noise: float
    penalty: float


def blocks_of(count: int) -> int:
    """Laps per block: the laps grouped so that at most :data:`MAX_POINTS` blocks remain."""
    return max(1, math.ceil(count / MAX_POINTS))


def running_in(means: ArrayLike) -> RunningIn:
    """The running-in of a record given as its block means (laps or cycles, in order)."""
    y = np.asarray(means, dtype=np.float64)
    n = y.size
    if n < 4:
        return RunningIn(0, (), 0.0, 0.0)
    second = np.diff(y, 2)
    noise = float(np.median(np.abs(second - np.median(second)))) * _MAD_TO_SIGMA
    noise = max(noise, NOISE_FLOOR * max(float(np.abs(y).mean()), 1e-12))
    penalty = 2.0 * noise**2 * math.log(n)
    found = ruptures.Pelt(model="l2", min_size=1, jump=1).fit(y.reshape(-1, 1))
    ends = [int(e) for e in found.predict(pen=penalty)]  # segment ends, the last is n
    z = float(norm.isf(NOISE_ALPHA / (2.0 * n)))
    steady_from = settled_from(y, band=STEADY_BAND, allowance=z * noise)
    return RunningIn(steady_from, tuple(ends[:-1]), noise, penalty)
