"""Lab work 1 on a stored run: tables 1.6-1.8 and the complex parameter from one trace."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from rigserver.analysis.iso import iso_result
from rigserver.analysis.readings import Readings
from rigserver.analysis.uncertainty import estimate, from_limit
from rigserver.core import roughness
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import BearingFitResult, ProfilometerResults
from schemas.runs import Run
from schemas.stands import ProfilometerConfig
from schemas.units import UNITS

GROUP = "profile"
_M_PER_MM = UNITS["mm"].factor
_M_PER_UM = UNITS["um"].factor


def analyse(run: Run, readings: Readings) -> ProfilometerResults:
    """Lab work 1 on a trace: the ISO parameters, Ra, Rq, Rz, Rmax, Sm and R (1.1)-(1.5)
    with the instrument's error, the profilogram against the instrument's reading (1.20),
    the bearing curve of table 1.6 and its fits (1.8), and the complex parameter Δ."""
    config = ProfilometerConfig.model_validate(run.configuration)
    result = ProfilometerResults(rows=readings.rows(GROUP))
    trace = readings.read(GROUP)
    if not trace:
        result.pending.append(N_("no profile yet"))
        return result
    x = trace["x"] * _M_PER_MM
    y = trace["y"] * _M_PER_UM
    result.iso = iso_result(
        x,
        y,
        lambda_c=config.lambda_c or None,
        lambda_s=config.lambda_s or None,
        notes=result.notes,
        roughness=config.profile_kind == "roughness",
        sections=config.sections,
    )
    try:
        params = roughness.profile_parameters(x=x, y=y)
    except ModelInputError as exc:
        result.pending.append(f"the profile cannot be analysed yet: {exc}")
        return result
    _heights(result, params)
    _instrument_error(result, params)
    _against_instrument(result, params, readings.measurements())
    _bearing_curve(result, params, x, y, config.levels)
    if result.fit_manual is not None:
        _complex_parameters(result, result.fit_manual, params, config)
    return result


def _heights(result: ProfilometerResults, params: roughness.ProfileParameters) -> None:
    """Ra, Rq, Rz with its five peaks and valleys, Rmax, Sm and R (1.1)-(1.5)."""
    result.base_length = params.base_length
    result.ra, result.rq, result.rz = params.ra, params.rq, params.rz
    result.rmax, result.sm, result.asperity_radius = params.rmax, params.sm, params.asperity_radius
    result.rz_peaks, result.rz_valleys = list(params.rz_peaks), list(params.rz_valleys)
    if params.asperity_radius is None:
        result.notes.append(
            f"R (1.1) not computed: ρ2 = {params.rms_curvature:.3g} 1/m, R = √(π/2)/ρ2 "
            "exceeds the largest number a double holds"
        )
    sub = roughness.subrange_of_base_length(params.base_length)
    if sub is not None:
        result.outside_subrange = list(roughness.outside_subrange(parameters=params, subrange=sub))


def _instrument_error(result: ProfilometerResults, params: roughness.ProfileParameters) -> None:
    """The profilometer's limits of error and the uncertainties of Ra and Rz they make."""
    try:
        err = roughness.instrument_error(parameters=params)
    except ModelInputError as exc:
        result.notes.append(f"instrument error not given: {exc}")
        return
    result.ra_error, result.rz_error = err.ra, err.rz
    result.rmax_error, result.sm_error = err.rmax, err.sm
    ra = estimate(from_limit(params.ra, err.ra))
    rz = estimate(from_limit(params.rz, err.rz))
    result.ra_uncertainty, result.ra_expanded = ra.standard, ra.expanded
    result.rz_uncertainty, result.rz_expanded = rz.standard, rz.expanded


def _against_instrument(
    result: ProfilometerResults, params: roughness.ProfileParameters, read: dict[str, float]
) -> None:
    """(1.20): the profilogram's Rmax, Rz and Ra against the instrument's readings."""
    if "rz_instrument" not in read or "rmax_instrument" not in read:
        return
    try:
        found = roughness.profilogram_discrepancy(
            rmax_instrument=read["rmax_instrument"] * _M_PER_UM,
            rmax_profilogram=params.rmax,
            rz_instrument=read["rz_instrument"] * _M_PER_UM,
            rz_profilogram=params.rz,
            ra_instrument=read["ra_instrument"] * _M_PER_UM if "ra_instrument" in read else None,
            ra_profilogram=params.ra,
        )
    except ModelInputError as exc:
        result.notes.append(f"(1.20) not computed: {exc}")
        return
    result.rmax_difference, result.rz_difference = found.rmax, found.rz
    result.ra_difference = found.ra


def _bearing_curve(
    result: ProfilometerResults,
    params: roughness.ProfileParameters,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    levels: int,
) -> None:
    """Table 1.6: strips of equal depth from the peak line down to the mean line, the
    bearing lengths η_p = t_p·l (1.6), and the curve (1.8) fitted by both methods."""
    line = roughness.mean_line(x=x, y=y)
    peak = float(np.max(y - (line.slope * x + line.intercept)))
    curve = roughness.bearing_curve(x=x, y=y, levels=peak * np.arange(1, levels + 1) / levels)
    result.levels, result.eps, result.tp = (
        curve.levels.tolist(),
        curve.eps.tolist(),
        curve.tp.tolist(),
    )
    result.bearing_lengths = (curve.tp * params.base_length).tolist()
    for method in ("manual", "lsq"):
        try:
            fit = roughness.fit_bearing_curve(eps=curve.eps, tp=curve.tp, method=method)
        except ModelInputError as exc:
            result.notes.append(f"bearing curve (1.8) not fitted by the {method} method: {exc}")
            continue
        model = BearingFitResult(
            method=method,
            b=fit.b,
            nu=fit.nu,
            residuals=fit.residuals.tolist(),
            nu_partial=list(fit.nu_partial),
            b_partial=list(fit.b_partial),
        )
        if method == "manual":
            result.fit_manual = model
        else:
            result.fit_lsq = model


def _complex_parameters(
    result: ProfilometerResults,
    fit: BearingFitResult,
    params: roughness.ProfileParameters,
    c: ProfilometerConfig,
) -> None:
    """Δ (1.9), Ra from Δ (1.10) and Δ_T (1.11), or what stops each, in ``result.notes``."""
    try:
        if params.asperity_radius is None:
            raise ModelInputError("it needs R (1.1)")
        delta = float(
            roughness.complex_parameter(
                rmax=params.rmax, radius=params.asperity_radius, b=fit.b, nu=fit.nu
            )
        )
        ra_from_complex = float(roughness.ra_from_complex_parameter(delta=delta))
        result.complex_parameter, result.ra_from_complex = delta, ra_from_complex
    except ModelInputError as exc:
        result.notes.append(f"Δ (1.9) not computed: {exc}")
    try:
        result.complex_parameter_equilibrium = float(
            roughness.equilibrium_complex_parameter(
                nu=fit.nu,
                poisson=c.poisson,
                youngs_modulus=c.youngs_modulus,
                contour_pressure=c.contour_pressure,
                tau0=c.tau0,
                alpha_r=c.alpha_r,
            )
        )
    except ModelInputError as exc:
        result.notes.append(f"Δ_T not computed: {exc}")
