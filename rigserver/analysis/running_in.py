"""Where the running-in ends: change points of the friction's lap means (PELT), then the
segments that the steady state cannot be told from joined to it.

1. The record is reduced to one mean per lap (pin-on-disc) or per cycle (reciprocating),
   grouped into at most :data:`MAX_POINTS` consecutive blocks of whole laps: a once-per-lap
   part (a disc's run-out) averages out and the readings' short-term correlation with it.
2. PELT (R. Killick, P. Fearnhead, I. A. Eckley, "Optimal detection of changepoints with a
   linear computational cost", J. Amer. Statist. Assoc. 107 (2012) 1590-1598), by the
   ``ruptures`` package (C. Truong, L. Oudre, N. Vayatis, Signal Processing 167 (2020)
   107299), finds the changes in the mean with the squared-error cost and the penalty
   β = 2σ̂²·ln n, Schwarz's information criterion for a change in a Gaussian mean of known
   variance (two parameters per change: its place and the new mean), the default "SIC" of
   Killick's changepoint package. σ̂ is the noise of one block, from the median absolute
   deviation of the second differences of neighbouring blocks, σ̂ = MAD(Δ²y)/(0.6745·√6)
   (Var Δ²y = 6σ² for independent blocks; differences remove a smooth trend, the
   difference-based estimators of T. Gasser, L. Sroka, C. Jennen-Steinmetz, Biometrika 73
   (1986) 625-633, and the median ignores the few a step or a kink disturbs); a floor of
   10⁻⁹ of the mean keeps β above the arithmetic's noise.
3. From the last segment backwards, a segment joins the steady part while its mean is
   within z·σ̂·√(1/n_i + 1/n_s) of the steady part's mean (n in blocks): a two-sided z-test
   at 1 % with Bonferroni's correction for the n places a change could have been found,
   z = Φ⁻¹(1 - 0.01/(2n)) (4.05 for 200 blocks); PELT's penalty alone lets a chance change
   through now and then, which would cut the steady part short. The running-in is what is
   left before: it ends where the steady part begins, at 0 when the whole record is steady.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import ruptures
from numpy.typing import ArrayLike
from scipy.stats import norm

#: Blocks PELT works on at most (its cost grows with their number).
MAX_POINTS = 250
#: The significance of the test that joins a segment to the steady part (before Bonferroni).
JOIN_ALPHA = 0.01
#: σ̂ of a noiseless record, relative to the mean: β stays above round-off.
NOISE_FLOOR = 1e-9
_MAD_TO_SIGMA = 1.0 / (0.6744897501960817 * math.sqrt(6.0))


@dataclass(frozen=True, slots=True)
class RunningIn:
    """The steady part's first block, the change points (block indices), σ̂ and β."""

    steady_from: int
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
    starts = [0, *ends[:-1]]
    steady_from = starts[-1]
    z = float(norm.isf(JOIN_ALPHA / (2.0 * n)))
    for start, end in zip(reversed(starts[:-1]), reversed(ends[:-1]), strict=True):
        steady = y[steady_from:]
        part = y[start:end]
        gap = abs(float(part.mean()) - float(steady.mean()))
        if gap > z * noise * math.sqrt(1.0 / part.size + 1.0 / steady.size):
            break
        steady_from = start
    return RunningIn(steady_from, tuple(ends[:-1]), noise, penalty)
