"""The fluid-film criterion of a journal bearing: h_min >= h_min^crit (seed 001, (2.104)).

The critical minimum film thickness (2.105) is the boundary between the mixed and the pure
fluid-film regime; the MTOS processing flags each row's regime with it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import non_negative, positive, within

FloatArray = NDArray[np.float64]
Regime = Literal["fluid", "mixed"]
LambdaRegime = Literal["full film", "mixed", "boundary"]

#: Bands of the film parameter Λ (Hamrock, Schmid and Jacobson): boundary below the first,
#: full film above the second, mixed between (both edges belong to the mixed band).
LAMBDA_BOUNDARY = 1.0
LAMBDA_FULL_FILM = 3.0


@dataclass(frozen=True, slots=True)
class CriticalFilmThickness:
    """Terms and total of the critical minimum film thickness (2.105), all in m.

    Attributes
    ----------
    journal_roughness : float
        h_ш, mean asperity height of the journal.
    bush_roughness : float
        h_с, mean asperity height of the bearing bush.
    misalignment : float
        h_n, allowance for the misalignment of the journal in the bush.
    deflection : float
        h_∂, allowance for the shaft's elastic deflection over the bearing width.
    shape_error : float
        h_u, allowance for the shape errors of journal and bush (barrel, hourglass, taper).
    total : float
        h_min^crit, the sum of the five.
    """

    journal_roughness: float
    bush_roughness: float
    misalignment: float
    deflection: float
    shape_error: float
    total: float


def critical_film_thickness(
    *,
    journal_roughness: float,
    bush_roughness: float,
    misalignment: float = 0.0,
    deflection: float = 0.0,
    shape_error: float = 0.0,
) -> CriticalFilmThickness:
    """Critical minimum film thickness of a journal bearing (2.105).

    .. math:: h_{min}^{крит} = h_ш + h_с + h_n + h_∂ + h_u

    Parameters
    ----------
    journal_roughness : float
        h_ш, m (>= 0): the mean height of the journal's asperities, e.g. Rz of (1.4) from a
        profilometer run, not Rmax.
    bush_roughness : float
        h_с, m (>= 0): the same for the bush.
    misalignment : float, optional
        h_n, m (>= 0).
    deflection : float, optional
        h_∂, m (>= 0).
    shape_error : float, optional
        h_u, m (>= 0).

    Returns
    -------
    CriticalFilmThickness
        The five terms and their sum, m.

    Notes
    -----
    The source takes the mean asperity heights ("средние высоты неровностей", GOST 2789-59,
    i.e. Rz) rather than the maximal ones: the highest asperities are few and are smoothed
    quickly on contact, so the regime is set by the contact of asperities of mean height.

    References
    ----------
    .. [1] Seed 001, critical minimum film thickness, (2.104)-(2.105).
    """
    terms = {
        "journal_roughness": journal_roughness,
        "bush_roughness": bush_roughness,
        "misalignment": misalignment,
        "deflection": deflection,
        "shape_error": shape_error,
    }
    checked = {name: float(non_negative(name, value)) for name, value in terms.items()}
    return CriticalFilmThickness(**checked, total=sum(checked.values()))


def minimum_film_thickness(*, clearance: ArrayLike, chi: ArrayLike) -> FloatArray:
    """Minimum film thickness of an eccentric journal.

    .. math:: h_{min} = h_0(1 - χ) = h_0 - e

    Parameters
    ----------
    clearance : array_like
        Radial clearance h0, m (> 0).
    chi : array_like
        Eccentricity ratio χ, in [0, 1].

    Returns
    -------
    ndarray
        h_min, m.

    References
    ----------
    .. [1] Lab manual, lab work 4, fig. 4.2 and the Hersey-Stribeck plot (h_min = h0 - e_max).
    """
    h0 = positive("clearance", clearance)
    return np.asarray(h0 * (1.0 - within("chi", chi, 0.0, 1.0)), dtype=np.float64)


def film_regime(*, h_min: float, h_crit: float) -> Regime:
    """Lubrication regime by the fluid-film criterion (2.104).

    Parameters
    ----------
    h_min : float
        Minimum film thickness, m (>= 0).
    h_crit : float
        Critical minimum film thickness h_min^crit, m (>= 0).

    Returns
    -------
    {"fluid", "mixed"}
        "fluid" when h_min >= h_crit, else "mixed".

    Notes
    -----
    Two states only: (2.105) bounds the mixed and the pure fluid regimes. The boundary
    regime of lab 4 is set by starving the oil feed, not by a film thickness, and no
    source gives a thickness threshold for it.

    References
    ----------
    .. [1] Seed 001, (2.104).
    """
    thickness = float(non_negative("h_min", h_min))
    critical = float(non_negative("h_crit", h_crit))
    return "fluid" if thickness >= critical else "mixed"


def film_parameter(*, h_min: ArrayLike, journal_rq: float, bush_rq: float) -> FloatArray:
    """Film parameter: the minimum film thickness over the composite rms roughness.

    .. math:: Λ = \\frac{h_{min}}{\\sqrt{R_{q,ш}^2 + R_{q,с}^2}}

    Parameters
    ----------
    h_min : array_like
        Minimum film thickness, m (>= 0).
    journal_rq, bush_rq : float
        Rq (= ρ of lab work 1) of the journal and of the bush, m (>= 0, not both zero).

    Returns
    -------
    ndarray
        Λ, dimensionless, shaped as ``h_min``.

    References
    ----------
    .. [1] B. J. Hamrock, S. R. Schmid, B. O. Jacobson, Fundamentals of Fluid Film
       Lubrication, 2nd ed., Marcel Dekker, 2004, ch. 3 (film parameter and the
       lubrication regimes).
    """
    h = non_negative("h_min", h_min)
    composite = float(
        np.hypot(non_negative("journal_rq", journal_rq), non_negative("bush_rq", bush_rq))
    )
    positive("composite roughness √(Rq_journal² + Rq_bush²)", composite)
    return np.asarray(h / composite, dtype=np.float64)


def lambda_regime(*, film_parameter: float) -> LambdaRegime:
    """Lubrication regime by the film parameter Λ (Hamrock, Schmid and Jacobson).

    Parameters
    ----------
    film_parameter : float
        Λ = h_min/√(Rq_journal² + Rq_bush²), dimensionless (>= 0).

    Returns
    -------
    {"full film", "mixed", "boundary"}
        "boundary" when Λ < 1, "full film" when Λ > 3, "mixed" for 1 <= Λ <= 3.

    References
    ----------
    .. [1] Hamrock, Schmid and Jacobson, Fundamentals of Fluid Film Lubrication, ch. 3.
    """
    value = float(non_negative("film_parameter", film_parameter))
    if value < LAMBDA_BOUNDARY:
        return "boundary"
    return "full film" if value > LAMBDA_FULL_FILM else "mixed"
