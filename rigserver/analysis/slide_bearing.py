"""Lab work 3 on a stored run: tables 3.1-3.3 from the limb rows and the zero readings."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rigserver.analysis import uncertainty
from rigserver.analysis.readings import Columns, Readings
from rigserver.analysis.uncertainty import estimate
from rigserver.core import bearing, bearing_readings, reynolds
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import AxialPoint, SlideBearingResults, SlideBearingRow
from schemas.runs import Run
from schemas.stands import SlideBearingConfig
from schemas.units import UNITS

GROUP = "rows"
MANOMETERS = ("p1", "p2", "p3", "p4", "p5")


def analyse(run: Run, readings: Readings) -> SlideBearingResults:
    """Tables 3.1-3.3 of lab work 3: the eccentricity (3.22)-(3.24) of each limb row, the
    measured pressure (3.25) beside the short (3.10), long (3.15) and finite (3.1) bearing's,
    along the circumference at the middle plane and along the axis where the pressure is
    highest; pending until the rows and the zero readings are there."""
    config = SlideBearingConfig.model_validate(run.configuration)
    a = config.width / (2.0 * config.bearing_radius)
    result = SlideBearingResults(rows=readings.rows(GROUP), half_width=a)
    zeros = readings.measurements()
    if "loader_scale" in zeros:
        result.load = zeros["loader_scale"] * config.loader_rate
    rows = readings.read(GROUP)
    missing = [k for k in ("x_zero", "y_zero", "load_zone_end") if k not in zeros]
    if result.rows == 0:
        result.pending.append(N_("no limb rows yet"))
    if missing:
        result.pending.append("needs the measurements " + ", ".join(missing))
    if result.rows == 0 or missing:
        return result
    limbs = _Limbs.of(config, rows, zeros)
    result.attitude_angle = float(np.degrees(np.angle(np.mean(np.exp(1j * limbs.attitude)))))
    result.temperature, result.viscosity, result.mu_bar = (
        limbs.oil.temperature,
        limbs.oil.viscosity,
        limbs.oil.mu_bar,
    )
    result.chi_mean = limbs.chi_mean
    u_chi = _chi_mean_uncertainty(config, rows, zeros)
    result.chi_mean_uncertainty, result.chi_mean_expanded = u_chi.standard, u_chi.expanded
    top = int(np.argmax(limbs.pressure))
    result.phi_max, result.pressure_max = float(limbs.phi_deg[top]), float(limbs.pressure[top])
    theory = _circumference(config, limbs, result.notes)
    result.rupture_angle = theory.rupture if theory.finite is not None else None
    result.table = _table_3_1(rows, limbs, theory)
    result.axial = _axial(config, rows, limbs, theory, top)
    return result


def _opt(value: float) -> float | None:
    return None if not np.isfinite(value) else float(value)


@dataclass(frozen=True, slots=True)
class _Limbs:
    """Every limb row's measured figures at once (arrays, one value a row)."""

    eccentricity: bearing_readings.Eccentricity
    pressure: NDArray[np.float64]
    pi_measured: NDArray[np.float64]
    phi_deg: NDArray[np.float64]
    oil: bearing_readings.MeanViscosity
    chi_mean: float
    attitude: NDArray[np.float64]

    @classmethod
    def of(cls, config: SlideBearingConfig, rows: Columns, zeros: dict[str, float]) -> _Limbs:
        scale = config.displacement_per_division
        centre = int(np.argmin(np.abs(np.asarray(config.manometer_z))))
        pressure = rows[MANOMETERS[centre]] * UNITS[config.gauge_unit].factor
        eccentricity = bearing_readings.slide_bearing_eccentricity(
            x=rows["x"] * scale,
            y=rows["y"] * scale,
            x_set=zeros["x_zero"] * scale,
            y_set=zeros["y_zero"] * scale,
            clearance=config.clearance,
        )
        viscosity = config.viscosity
        return cls(
            eccentricity=eccentricity,
            pressure=pressure,
            pi_measured=_dimensionless(config, pressure),
            phi_deg=bearing_readings.model_angle_deg(
                limb_deg=rows["limb_angle"], load_zone_end_deg=zeros["load_zone_end"]
            ),
            oil=bearing_readings.mean_oil_viscosity(
                t_in=rows["t1"],
                t_out=rows["t2"],
                A=viscosity.A,
                alpha=viscosity.alpha,
                mu0=config.mu0,
            ),
            chi_mean=bearing_readings.mean_eccentricity_ratio(chi=eccentricity.chi),
            attitude=bearing_readings.slide_bearing_attitude_angle(
                e_x=eccentricity.e_x, e_y=eccentricity.e_y, limb_deg=rows["limb_angle"]
            ),
        )


def _dimensionless(
    config: SlideBearingConfig, pressure: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Π of a gauge pressure (3.25)."""
    return bearing_readings.measured_dimensionless_pressure(
        gauge_pressure=pressure,
        clearance=config.clearance,
        bearing_radius=config.bearing_radius,
        mu0=config.mu0,
        omega0=config.omega0,
    )


def _chi_mean_uncertainty(
    config: SlideBearingConfig, rows: Columns, zeros: dict[str, float]
) -> uncertainty.Estimate:
    return estimate(
        uncertainty.slide_bearing_chi_mean(
            x=rows["x"].tolist(),
            y=rows["y"].tolist(),
            x_zero=zeros["x_zero"],
            y_zero=zeros["y_zero"],
            per_division=config.displacement_per_division,
            limit_divisions=config.accuracy.displacement,
            clearance=config.clearance,
            clearance_limit=config.accuracy.clearance,
        )
    )


@dataclass(frozen=True, slots=True)
class _Circumference:
    """The theory at the limb rows' angles: Π of the short (3.10), long (3.15) and finite
    (3.1) bearing at the middle plane, the errors of the measured Π against the first two,
    the finite solution and its film's rupture angle φ_r, degrees (NaN where not computed)."""

    pi_short: NDArray[np.float64]
    pi_long: NDArray[np.float64]
    pi_finite: NDArray[np.float64]
    error_short: NDArray[np.float64]
    error_long: NDArray[np.float64]
    finite: reynolds.ReynoldsSolution | None = None
    rupture: float = 0.0


def _circumference(config: SlideBearingConfig, limbs: _Limbs, notes: list[str]) -> _Circumference:
    phi = np.radians(limbs.phi_deg)
    a = config.width / (2.0 * config.bearing_radius)
    chi, mu_bar = limbs.chi_mean, limbs.oil.mu_bar
    try:
        # G = ω1/ω0 = 1: the journal turns at ω0, the bearing stands still (3.12)
        pi_short = bearing.short_bearing_pressure(
            phi=phi, z=0.0, chi=chi, a=a, mu_bar=mu_bar, G=1.0
        )
        pi_long = bearing.long_bearing_pressure(phi=phi, chi=chi, mu_bar=mu_bar, G=1.0)
        finite = reynolds.solve_reynolds(chi=chi, half_width=a, mu_bar=mu_bar)

        def mid_plane(angle: NDArray[np.float64]) -> NDArray[np.float64]:
            return finite.pressure_at(phi=angle, z=np.zeros_like(angle))

        # (3.20) puts φ_k, where the holes lose pressure, at the thinnest film (φ = 360°),
        # true of (3.10) and (3.15); the finite film ruptures φ_r later, so the hole at
        # φ_мод sees the finite film's φ_мод + φ_r (docs/validity.md, slide bearing).
        rupture = bearing.rupture_angle_deg(pressure=mid_plane)
        return _Circumference(
            pi_short=pi_short,
            pi_long=pi_long,
            pi_finite=mid_plane(phi + np.radians(rupture)),
            error_short=_error(pi_short, limbs.pi_measured),
            error_long=_error(pi_long, limbs.pi_measured),
            finite=finite,
            rupture=rupture,
        )
    except ModelInputError as exc:
        notes.append(f"theory not computed: {exc}")
        nan = np.full(phi.shape, np.nan)
        return _Circumference(nan, nan, nan, nan, nan)


def _error(theory: NDArray[np.float64], measured: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(
        bearing_readings.relative_error_percent(reference=theory, other=measured).percent
    )


def _table_3_1(rows: Columns, limbs: _Limbs, theory: _Circumference) -> list[SlideBearingRow]:
    ecc = limbs.eccentricity
    return [
        SlideBearingRow(
            limb_angle=float(rows["limb_angle"][i]),
            phi_model=float(limbs.phi_deg[i]),
            pressure=float(limbs.pressure[i]),
            e_x=float(ecc.e_x[i]),
            e_y=float(ecc.e_y[i]),
            e=float(ecc.e[i]),
            chi=float(ecc.chi[i]),
            attitude=float(np.degrees(limbs.attitude[i])),
            pi_measured=float(limbs.pi_measured[i]),
            pi_short=_opt(theory.pi_short[i]),
            pi_long=_opt(theory.pi_long[i]),
            pi_finite=_opt(theory.pi_finite[i]),
            error_short=_opt(theory.error_short[i]),
            error_long=_opt(theory.error_long[i]),
        )
        for i in range(limbs.phi_deg.size)
    ]


def _axial(
    config: SlideBearingConfig, rows: Columns, limbs: _Limbs, theory: _Circumference, top: int
) -> list[AxialPoint]:
    """Table 3.3: the pressure along the axis at the row of the highest pressure, measured
    beside the short (3.10) and the finite (3.1) bearing's."""
    z = np.asarray(config.manometer_z)
    phi_top = float(np.radians(limbs.phi_deg[top]))
    p_axial = np.array([rows[name][top] for name in MANOMETERS]) * UNITS[config.gauge_unit].factor
    pi_z = _dimensionless(config, p_axial)
    a = config.width / (2.0 * config.bearing_radius)
    try:
        pi_m = bearing.short_bearing_pressure(
            phi=phi_top, z=z, chi=limbs.chi_mean, a=a, mu_bar=limbs.oil.mu_bar, G=1.0
        )
        err_z = _error(pi_m, pi_z)
    except ModelInputError:
        pi_m = err_z = np.full(z.shape, np.nan)
    pi_fz = (
        theory.finite.pressure_at(phi=np.full(z.shape, phi_top + np.radians(theory.rupture)), z=z)
        if theory.finite is not None
        else np.full(z.shape, np.nan)
    )
    return [
        AxialPoint(
            z=float(z[k]),
            pressure=float(p_axial[k]),
            pi_measured=float(pi_z[k]),
            pi_short=_opt(pi_m[k]),
            pi_finite=_opt(pi_fz[k]),
            error=_opt(err_z[k]),
        )
        for k in range(z.size)
    ]
