"""Labs 3 and 4: processing of the slide-bearing stand and MTOS stand readings.

Slide-bearing stand (lab 3): eccentricity (3.16)-(3.17), measured dimensionless pressure
(3.18)-(3.19), limb angle to model angle (3.20), oil viscosity (3.21)-(3.22), mean
eccentricity ratio (3.23), relative errors (3.25)-(3.27).
MTOS stand (lab 4): eccentricity and angles (4.11)-(4.12), friction chain (4.13)-(4.16),
film viscosity (4.17)-(4.18), temperature rise (4.19, correction E4), bearing
characteristic (4.21, correction E9), error Δf of table 4.4.

Inputs are SI (m, Pa, N, s, rad; °C). Unit conversion of raw readings (divisions, "атм",
mm of loader scale) is the caller's. Equation numbers are the lab manual's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, non_negative, positive
from rigserver.core.errors import ModelInputError, ModelUndefinedError

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


def viscosity(*, t: ArrayLike, A: ArrayLike, alpha: ArrayLike) -> FloatArray:
    """Dynamic viscosity of the oil against temperature (3.21), (4.17).

    .. math:: μ = A\\exp(αt)

    Parameters
    ----------
    t : array_like
        Oil temperature, °C.
    A : array_like
        Coefficient A, Pa·s (> 0); the slide-bearing stand's oil has 0.0773 Pa·s.
    alpha : array_like
        Exponent α, 1/°C; -0.0485 1/°C for the slide-bearing stand's oil.

    Returns
    -------
    ndarray
        μ, Pa·s.

    References
    ----------
    .. [1] Lab manual, (3.21) and (4.17).
    """
    return np.asarray(
        positive("A", A) * np.exp(finite("alpha", alpha) * finite("t", t)), dtype=np.float64
    )


@dataclass(frozen=True, slots=True)
class Eccentricity:
    """Journal eccentricity from the two displacement sensors.

    Attributes
    ----------
    e_x : ndarray
        Component e_x, m (may be negative when the journal has crossed the centre).
    e_y : ndarray
        Component e_y, m.
    e : ndarray
        e = √(e_x² + e_y²), m.
    chi : ndarray
        χ = e/h0, dimensionless.
    """

    e_x: FloatArray
    e_y: FloatArray
    e: FloatArray
    chi: FloatArray


def _eccentricity(
    offset: FloatArray,
    x: ArrayLike,
    y: ArrayLike,
    x_set: ArrayLike,
    y_set: ArrayLike,
    clearance: FloatArray,
    signed: bool = False,
) -> Eccentricity:
    fold = (lambda d: -d) if signed else np.abs
    e_x = offset - fold(finite("x_set", x_set) - finite("x", x))
    e_y = offset - fold(finite("y_set", y_set) - finite("y", y))
    e = np.hypot(e_x, e_y)
    return Eccentricity(e_x=e_x, e_y=e_y, e=e, chi=e / clearance)


def slide_bearing_eccentricity(
    *,
    x: ArrayLike,
    y: ArrayLike,
    x_set: ArrayLike,
    y_set: ArrayLike,
    clearance: ArrayLike,
) -> Eccentricity:
    """Eccentricity of the journal on the slide-bearing stand (3.16)-(3.17).

    .. math:: e_x = h_0 - |X_{уст} - X|,\\ e_y = h_0 - |Y_{уст} - Y|,\\
              e = \\sqrt{e_x^2 + e_y^2},\\ χ = e/h_0

    Parameters
    ----------
    x, y : array_like
        Sensor readings X, Y of each row, m.
    x_set, y_set : array_like
        Setting readings X_уст, Y_уст, m.
    clearance : array_like
        Radial clearance h0, m (> 0); 175 μm on the stand.

    Returns
    -------
    Eccentricity
        e_x, e_y, e (m) and χ, broadcast over the rows.

    Notes
    -----
    As printed, (3.16) gives χ = √2 at X = X_уст, Y = Y_уст; χ ≥ 1 means the setting or the
    sensor calibration is off, and the theory in :mod:`rigserver.core.bearing` refuses it.

    References
    ----------
    .. [1] Lab manual, lab work 3, (3.16)-(3.17).
    """
    h0 = positive("clearance", clearance)
    return _eccentricity(h0, x, y, x_set, y_set, h0)


def measured_dimensionless_pressure(
    *,
    gauge_pressure: ArrayLike,
    clearance: ArrayLike,
    bearing_radius: ArrayLike,
    mu0: ArrayLike,
    omega0: ArrayLike,
) -> FloatArray:
    """Measured pressure in the dimensionless form of the theory (3.18)-(3.19).

    .. math:: Π_э = \\frac{(p - p_a)Ψ^2}{μ_0ω_0},\\quad Ψ = h_0/R_2

    Parameters
    ----------
    gauge_pressure : array_like
        p - p_a, Pa (the manometer reading converted from its unit by the caller).
    clearance : array_like
        h0, m (> 0).
    bearing_radius : array_like
        R2, m (> 0); 25.175 mm on the stand.
    mu0 : array_like
        Characteristic viscosity μ0, Pa·s; the stand takes μ20 = 0.0282 Pa·s.
    omega0 : array_like
        Characteristic angular speed ω0, rad/s; the stand takes 329 rad/s.

    Returns
    -------
    ndarray
        Π_э, dimensionless.

    References
    ----------
    .. [1] Lab manual, lab work 3, (3.18)-(3.19).
    """
    psi = positive("clearance", clearance) / positive("bearing_radius", bearing_radius)
    scale = positive("mu0", mu0) * positive("omega0", omega0)
    return np.asarray(finite("gauge_pressure", gauge_pressure) * psi**2 / scale, dtype=np.float64)


def slide_bearing_attitude_angle(
    *, e_x: ArrayLike, e_y: ArrayLike, limb_deg: ArrayLike
) -> FloatArray:
    """Attitude angle ψ of the slide bearing from the displacements of one row.

    .. math:: ψ = \\operatorname{atan2}(e_y, e_x) - (135° - φ_{лимб})

    The zero readings X_уст, Y_уст are taken with the limb at 135° and 45°, where the load
    presses the bearing along the X and the Y sensor: the load acts along 135° - φ_лимб from
    the X axis, and the line of centres leads it by ψ in the direction of rotation.

    Parameters
    ----------
    e_x, e_y : array_like
        Eccentricity components of :func:`slide_bearing_eccentricity`, m.
    limb_deg : array_like
        Limb reading of the row, degrees.

    Returns
    -------
    ndarray
        ψ, rad, wrapped to (-π, π].

    References
    ----------
    .. [1] Lab manual, lab work 3, (3.16)-(3.17) and the zero-reading procedure.
    """
    raw = np.arctan2(finite("e_y", e_y), finite("e_x", e_x)) - np.radians(
        135.0 - finite("limb_deg", limb_deg)
    )
    return np.asarray(np.pi - np.mod(np.pi - raw, 2.0 * np.pi), dtype=np.float64)


def model_angle_deg(*, limb_deg: ArrayLike, load_zone_end_deg: ArrayLike) -> FloatArray:
    """Angle of the model frame from the limb reading (3.20).

    .. math:: φ_{мод} = 360° - (φ_k - φ_{лимб})

    Parameters
    ----------
    limb_deg : array_like
        Limb reading φ_лимб of each row, degrees.
    load_zone_end_deg : array_like
        Limb reading φ_k at the end of the load zone (p = 0), degrees.

    Returns
    -------
    ndarray
        φ_мод, degrees, wrapped to (0, 360].

    Notes
    -----
    Wrapped to (0°, 360°], not [0°, 360°): the end of the load zone φ_лимб = φ_k is 360°
    (φ_k = 2π of (3.11), the last row of table 3.3), and the 180° turned back from it
    fill 180°..360° as in table 3.3. The wrap also covers a limb that passes through 0°.

    References
    ----------
    .. [1] Lab manual, lab work 3, (3.20), tables 3.1 and 3.3.
    """
    raw = 360.0 - (finite("load_zone_end_deg", load_zone_end_deg) - finite("limb_deg", limb_deg))
    wrapped = np.mod(raw, 360.0)
    return np.asarray(np.where(wrapped == 0.0, 360.0, wrapped), dtype=np.float64)


@dataclass(frozen=True, slots=True)
class MeanViscosity:
    """Oil viscosity at the mean temperature of the slide-bearing run (3.21)-(3.22).

    Attributes
    ----------
    temperature : float
        t = (t1ср + t2ср)/2, °C.
    viscosity : float
        μ_t = A·exp(α·t), Pa·s.
    mu_bar : float
        μ̄ = μ_t/μ0, dimensionless.
    """

    temperature: float
    viscosity: float
    mu_bar: float


def _mean(name: str, values: ArrayLike) -> float:
    arr = finite(name, values)
    if arr.size == 0:
        raise ModelInputError(f"{name} must hold at least one row, got none")
    return float(np.mean(arr))


def mean_oil_viscosity(
    *,
    t_in: ArrayLike,
    t_out: ArrayLike,
    A: float,
    alpha: float,
    mu0: float,
) -> MeanViscosity:
    """Mean oil temperature, its viscosity and μ̄ for the slide-bearing run (3.21)-(3.22).

    Parameters
    ----------
    t_in, t_out : array_like
        Inlet and outlet temperatures t1, t2 of the rows, °C.
    A, alpha : float
        Viscosity law of :func:`viscosity`, Pa·s and 1/°C.
    mu0 : float
        Characteristic viscosity μ0, Pa·s (> 0).

    Returns
    -------
    MeanViscosity
        t (°C), μ_t (Pa·s), μ̄.

    References
    ----------
    .. [1] Lab manual, lab work 3, processing items 4-5.
    """
    t = 0.5 * (_mean("t_in", t_in) + _mean("t_out", t_out))
    mu_t = float(viscosity(t=t, A=A, alpha=alpha))
    return MeanViscosity(temperature=t, viscosity=mu_t, mu_bar=mu_t / float(positive("mu0", mu0)))


def mean_eccentricity_ratio(*, chi: ArrayLike) -> float:
    """Mean eccentricity ratio over the rows of table 3.1 (3.23).

    .. math:: χ_{ср} = \\frac1n\\sum_{i=1}^n χ_i

    Parameters
    ----------
    chi : array_like
        χ of each row (dimensionless).

    Returns
    -------
    float
        χ_ср.
    """
    return _mean("chi", chi)


@dataclass(frozen=True, slots=True)
class RelativeError:
    """Relative difference in per cent against a reference value.

    Attributes
    ----------
    percent : ndarray
        (reference - other)/reference·100 %; NaN where ``defined`` is False.
    defined : ndarray
        False where |reference| is below the floor (e.g. Π = 0 at φ = π, 2π or z = ±a).
    """

    percent: FloatArray
    defined: BoolArray


def relative_error_percent(
    *, reference: ArrayLike, other: ArrayLike, floor: float = 1e-9
) -> RelativeError:
    """Relative error against a reference (3.25)-(3.27) and Δf of table 4.4.

    .. math:: Δ = \\frac{\\text{reference} - \\text{other}}{\\text{reference}}\\,100\\ \\%

    Parameters
    ----------
    reference : array_like
        The denominator: the theory Π_m, Π0, Π∞ in (3.25)-(3.27); the experiment f_э in
        Δf = (f_э - f_T)/f_э.
    other : array_like
        The compared value: Π_z, Π_э; f_T.
    floor : float, optional
        The error is left undefined where |reference| <= floor·max|reference| (default
        1e-9): a relative error at a zero of the theory has no meaning.

    Returns
    -------
    RelativeError
        Percentages and the mask of the defined ones.

    Notes
    -----
    Table 3.2 lists Π_z (measured along z) and Π_m (short-bearing model); (3.25) divides by
    Π_m, like (3.26)-(3.27) divide by the theory.
    """
    ref = finite("reference", reference)
    oth = finite("other", other)
    ref, oth = np.broadcast_arrays(ref, oth)
    limit = float(positive("floor", floor)) * float(np.max(np.abs(ref), initial=0.0))
    defined = np.abs(ref) > limit
    safe = np.where(defined, ref, 1.0)
    percent = np.where(defined, (ref - oth) / safe * 100.0, np.nan)
    return RelativeError(percent=np.asarray(percent, dtype=np.float64), defined=defined)


def mtos_eccentricity(
    *,
    x: ArrayLike,
    y: ArrayLike,
    x_set: ArrayLike,
    y_set: ArrayLike,
    clearance: ArrayLike,
    signed: bool = False,
) -> Eccentricity:
    """Eccentricity of the journal on the MTOS stand (4.11).

    .. math:: e_x = h_0\\cos45° - |X_{уст} - X|,\\ e_y = h_0\\cos45° - |Y_{уст} - Y|,\\
              e = \\sqrt{e_x^2 + e_y^2},\\ χ = e/h_0

    With ``signed`` the sensors' direction is known (they read more as the journal lifts off
    the zero contact): e_x = h_0 cos45° - (X - X_уст), likewise e_y. The |·| of (4.11) folds
    a component beyond h_0 cos45° back, which happens whenever the journal rolls up the bush
    by the friction angle γ near contact (experiments 2 and 3); the signed form does not.

    Parameters
    ----------
    x, y : array_like
        Sensor readings X, Y of each row, m.
    x_set, y_set : array_like
        Setting readings X_уст, Y_уст (taken at 2 kN), m.
    clearance : array_like
        Radial clearance h0, m (> 0).
    signed : bool
        Use the sensors' sign instead of the |·| of (4.11).

    Returns
    -------
    Eccentricity
        e_x, e_y, e (m) and χ; χ = 1 at the setting readings.

    References
    ----------
    .. [1] Lab manual, lab work 4, (4.11).
    """
    h0 = positive("clearance", clearance)
    return _eccentricity(h0 * np.cos(np.pi / 4.0), x, y, x_set, y_set, h0, signed)


@dataclass(frozen=True, slots=True)
class AttitudeAngles:
    """Angles of the line of centres on the MTOS stand (4.12).

    Attributes
    ----------
    delta : ndarray
        δ = 45° - arctg(e_x/e_y), rad: fluid film (experiment 1).
    gamma : ndarray
        γ = 45° - arctg(e_y/e_x), rad: mixed and boundary (experiments 2, 3);
        f = tg γ in those regimes.
    """

    delta: FloatArray
    gamma: FloatArray


def mtos_attitude_angles(*, e_x: ArrayLike, e_y: ArrayLike) -> AttitudeAngles:
    """Angles δ and γ of the journal centre on the MTOS stand (4.12).

    Parameters
    ----------
    e_x, e_y : array_like
        Eccentricity components of :func:`mtos_eccentricity`, m.

    Returns
    -------
    AttitudeAngles
        δ and γ, rad.

    Raises
    ------
    ModelUndefinedError
        Where e_x = e_y = 0: a centred journal has no line of centres.

    Notes
    -----
    arctg(u/v) is evaluated as atan2(u, v): equal for v > 0 and defined at v = 0. For
    positive components γ = -δ: the two angles measure the same line from the 45° line,
    to either side.

    References
    ----------
    .. [1] Lab manual, lab work 4, (4.12) and fig. 4.2.
    """
    ex = finite("e_x", e_x)
    ey = finite("e_y", e_y)
    centred = (ex == 0.0) & (ey == 0.0)
    if np.any(centred):
        raise ModelUndefinedError(
            "e_x and e_y are both 0 (journal centred): the angles δ, γ of (4.12) are undefined"
        )
    quarter = np.pi / 4.0
    return AttitudeAngles(
        delta=np.asarray(quarter - np.arctan2(ex, ey), dtype=np.float64),
        gamma=np.asarray(quarter - np.arctan2(ey, ex), dtype=np.float64),
    )


@dataclass(frozen=True, slots=True)
class MeasuredFriction:
    """Friction measured by the MTOS flat spring and indicator (4.13)-(4.16).

    Attributes
    ----------
    spring_force : ndarray
        F = k·Δl, N.
    moment : ndarray
        M_tr = F·l1, N·m.
    friction_force : ndarray
        F_tr = M_tr/l2, N.
    coefficient : ndarray
        f_э = F_tr/N, dimensionless.
    """

    spring_force: FloatArray
    moment: FloatArray
    friction_force: FloatArray
    coefficient: FloatArray


def mtos_friction(
    *,
    indicator_travel: ArrayLike,
    spring_rate: ArrayLike,
    spring_arm: ArrayLike,
    friction_arm: ArrayLike,
    load: ArrayLike,
) -> MeasuredFriction:
    """Experimental friction coefficient on the MTOS stand (4.13)-(4.16).

    .. math:: F = kΔl,\\ M_{тр} = F l_1,\\ F_{тр} = M_{тр}/l_2,\\ f_э = F_{тр}/N

    Parameters
    ----------
    indicator_travel : array_like
        Δl, indicator travel from its zero at F = 0, m.
    spring_rate : array_like
        Calibration coefficient k, N/m (> 0).
    spring_arm : array_like
        Arm l1 of the spring force, m (> 0).
    friction_arm : array_like
        Arm l2 of the friction force, m (> 0).
    load : array_like
        Load N on the bearing, N (> 0).

    Returns
    -------
    MeasuredFriction
        F (N), M_tr (N·m), F_tr (N), f_э.

    References
    ----------
    .. [1] Lab manual, lab work 4, (4.13)-(4.16) and fig. 4.5.
    """
    force = positive("spring_rate", spring_rate) * finite("indicator_travel", indicator_travel)
    moment = force * positive("spring_arm", spring_arm)
    friction_force = moment / positive("friction_arm", friction_arm)
    return MeasuredFriction(
        spring_force=force,
        moment=moment,
        friction_force=friction_force,
        coefficient=friction_force / positive("load", load),
    )


@dataclass(frozen=True, slots=True)
class FilmViscosity:
    """Viscosity near the loaded film of the MTOS bearing (4.17)-(4.18).

    Attributes
    ----------
    mu3, mu4, mu5 : ndarray
        μ at t3, t4, t5, Pa·s.
    mean : ndarray
        μ_t = (μ3 + μ4 + μ5)/3, Pa·s.
    """

    mu3: FloatArray
    mu4: FloatArray
    mu5: FloatArray
    mean: FloatArray


def mtos_film_viscosity(
    *, t3: ArrayLike, t4: ArrayLike, t5: ArrayLike, A: ArrayLike, alpha: ArrayLike
) -> FilmViscosity:
    """Mean viscosity of the loaded film from the three thermocouples (4.17)-(4.18).

    Parameters
    ----------
    t3, t4, t5 : array_like
        Temperatures near the film in the loaded zone, °C.
    A, alpha : array_like
        Viscosity law of :func:`viscosity` (stand table), Pa·s and 1/°C.

    Returns
    -------
    FilmViscosity
        μ3, μ4, μ5 and their mean μ_t (the mean of viscosities, not the viscosity of the
        mean temperature), Pa·s.
    """
    mu3 = viscosity(t=t3, A=A, alpha=alpha)
    mu4 = viscosity(t=t4, A=A, alpha=alpha)
    mu5 = viscosity(t=t5, A=A, alpha=alpha)
    return FilmViscosity(mu3=mu3, mu4=mu4, mu5=mu5, mean=(mu3 + mu4 + mu5) / 3.0)


def temperature_rise(*, t: ArrayLike, t_in: ArrayLike) -> FloatArray:
    """Temperature rise of the oil over the inlet (4.19, corrected E4).

    .. math:: Δt_i = t_i - t_1

    Parameters
    ----------
    t : array_like
        Temperature t_i (i = 2..5), °C.
    t_in : array_like
        Inlet temperature t1, °C.

    Returns
    -------
    ndarray
        Δt_i, °C (positive when the oil heats).

    Notes
    -----
    Correction E4: the print has t1 - t_i, a negative "rise".
    """
    return np.asarray(finite("t", t) - finite("t_in", t_in), dtype=np.float64)


def bearing_characteristic(
    *,
    viscosity: ArrayLike,
    omega: ArrayLike,
    load: ArrayLike,
    width: ArrayLike,
    diameter: ArrayLike,
) -> FloatArray:
    """Bearing characteristic S1 of the Hersey-Stribeck diagram (4.21, correction E9).

    .. math:: S_1 = \\frac{B D μ_t ω}{N} = \\frac{μ_t ω}{\\bar p},\\quad \\bar p = \\frac{N}{BD}

    Parameters
    ----------
    viscosity : array_like
        μ_t, Pa·s (> 0).
    omega : array_like
        Journal angular speed ω, rad/s (>= 0).
    load : array_like
        Load N, N (> 0).
    width : array_like
        Bearing width B, m (> 0).
    diameter : array_like
        Bearing diameter D, m (> 0).

    Returns
    -------
    ndarray
        S1, dimensionless.

    Notes
    -----
    Correction E9: the introduction of lab 4 calls p̄/(μω) "S1" too; this is (4.21),
    S1 = μω/p̄. Plot f against S1 (or S1⁻¹) and label the axis with the definition.
    """
    mean_pressure = positive("load", load) / (
        positive("width", width) * positive("diameter", diameter)
    )
    omega_ = non_negative("omega", omega)
    return np.asarray(positive("viscosity", viscosity) * omega_ / mean_pressure, dtype=np.float64)
