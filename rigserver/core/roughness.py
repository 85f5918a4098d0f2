"""Lab work 1: roughness of a run-in surface from an ABRIS-PM7 profile.

Equation numbers are those of the lab manual (see ``docs/models.md`` of the project).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import non_negative

#: Coefficient of the run-in relation Ra ≈ 4.3·Δ^(1/2), Ra in μm (1.10).
RA_PER_SQRT_DELTA_UM = 4.3


def ra_from_complex_parameter(*, delta: ArrayLike) -> NDArray[np.float64]:
    """Arithmetic mean deviation of a run-in surface from its complex parameter (1.10).

    .. math:: R_a = 4.3\\,\\Delta^{1/2} \\quad (R_a \\text{ in μm})

    Parameters
    ----------
    delta : array_like
        Complex roughness parameter Δ (dimensionless, >= 0).

    Returns
    -------
    ndarray
        Ra in metres.
    """
    d = non_negative("delta", delta)
    return RA_PER_SQRT_DELTA_UM * np.sqrt(d) * 1e-6


def complex_parameter_from_ra(*, ra: ArrayLike) -> NDArray[np.float64]:
    """Complex roughness parameter of a run-in surface from its Ra (2.6, corrected E2).

    .. math:: \\Delta = (R_a / 4.3)^2 \\approx 5.4\\cdot10^{-2} R_a^2 \\quad (R_a \\text{ in μm})

    The inverse of (1.10); the manual's print of (2.6) drops the square (correction E2).

    Parameters
    ----------
    ra : array_like
        Arithmetic mean deviation Ra in metres (>= 0).

    Returns
    -------
    ndarray
        Δ, dimensionless.
    """
    ra_um = non_negative("ra", ra) * 1e6
    return (ra_um / RA_PER_SQRT_DELTA_UM) ** 2
