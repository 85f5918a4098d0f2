"""Lab work 3 on a stored run: tables 3.1-3.3 from the limb rows and the zero readings."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from rigserver.analysis import uncertainty
from rigserver.analysis.readings import Readings
from rigserver.analysis.uncertainty import estimate
from rigserver.core import bearing, reynolds, stands
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import AxialPoint, SlideBearingResults, SlideBearingRow
from schemas.runs import Run
from schemas.stands import SlideBearingConfig
from schemas.units import UNITS

GROUP = "rows"
MANOMETERS = ("p1", "p2", "p3", "p4", "p5")


def _opt(value: float) -> float | None:
    return None if not np.isfinite(value) else float(value)


def analyse(run: Run, readings: Readings) -> SlideBearingResults:
    c = SlideBearingConfig.model_validate(run.configuration)
    a = c.width / (2.0 * c.bearing_radius)
    result = SlideBearingResults(rows=readings.rows(GROUP), half_width=a)
    m = readings.measurements()
    if "loader_scale" in m:
        result.load = m["loader_scale"] * c.loader_rate
    rows = readings.read(GROUP)
    missing = [k for k in ("x_zero", "y_zero", "load_zone_end") if k not in m]
    if not rows:
        result.pending.append(N_("no limb rows yet"))
    if missing:
        result.pending.append("needs the measurements " + ", ".join(missing))
    if not rows or missing:
        return result
    scale = c.displacement_per_division
    gauge = UNITS[c.gauge_unit].factor
    ecc = stands.slide_bearing_eccentricity(
        x=rows["x"] * scale,
        y=rows["y"] * scale,
        x_set=m["x_zero"] * scale,
        y_set=m["y_zero"] * scale,
        clearance=c.clearance,
    )
    centre = int(np.argmin(np.abs(np.asarray(c.manometer_z))))
    pressure = rows[MANOMETERS[centre]] * gauge

    def measured(p: NDArray[np.float64]) -> NDArray[np.float64]:
        return stands.measured_dimensionless_pressure(
            gauge_pressure=p,
            clearance=c.clearance,
            bearing_radius=c.bearing_radius,
            mu0=c.mu0,
            omega0=c.omega0,
        )

    pi_measured = measured(pressure)
    phi_deg = stands.model_angle_deg(
        limb_deg=rows["limb_angle"], load_zone_end_deg=m["load_zone_end"]
    )
    oil = stands.mean_oil_viscosity(
        t_in=rows["t1"], t_out=rows["t2"], A=c.viscosity.A, alpha=c.viscosity.alpha, mu0=c.mu0
    )
    chi_mean = stands.mean_eccentricity_ratio(chi=ecc.chi)
    psi = stands.slide_bearing_attitude_angle(e_x=ecc.e_x, e_y=ecc.e_y, limb_deg=rows["limb_angle"])
    result.attitude_angle = float(np.degrees(np.angle(np.mean(np.exp(1j * psi)))))
    result.temperature, result.viscosity, result.mu_bar = (
        oil.temperature,
        oil.viscosity,
        oil.mu_bar,
    )
    result.chi_mean = chi_mean
    u_chi = estimate(
        uncertainty.slide_bearing_chi_mean(
            x=rows["x"].tolist(),
            y=rows["y"].tolist(),
            x_zero=m["x_zero"],
            y_zero=m["y_zero"],
            per_division=scale,
            limit_divisions=c.accuracy.displacement,
            clearance=c.clearance,
            clearance_limit=c.accuracy.clearance,
        )
    )
    result.chi_mean_uncertainty, result.chi_mean_expanded = u_chi.standard, u_chi.expanded
    top = int(np.argmax(pressure))
    result.phi_max, result.pressure_max = float(phi_deg[top]), float(pressure[top])
    phi = np.radians(phi_deg)
    try:
        # G = ω1/ω0 = 1: the journal turns at ω0, the bearing stands still (3.12)
        pi_short = bearing.short_bearing_pressure(
            phi=phi, z=0.0, chi=chi_mean, a=a, mu_bar=oil.mu_bar, G=1.0
        )
        pi_long = bearing.long_bearing_pressure(phi=phi, chi=chi_mean, mu_bar=oil.mu_bar, G=1.0)
        err_short = stands.relative_error_percent(reference=pi_short, other=pi_measured).percent
        err_long = stands.relative_error_percent(reference=pi_long, other=pi_measured).percent
        finite = reynolds.solve_reynolds(chi=chi_mean, half_width=a, mu_bar=oil.mu_bar)

        def mid_plane(angle: NDArray[np.float64]) -> NDArray[np.float64]:
            return finite.pressure_at(phi=angle, z=np.zeros_like(angle))

        # (3.20) puts φ_k, where the holes lose pressure, at the thinnest film (φ = 360°),
        # true of (3.10) and (3.15); the finite film ruptures φ_r later, so the hole at
        # φ_мод sees the finite film's φ_мод + φ_r (docs/validity.md, slide bearing).
        rupture = bearing.rupture_angle_deg(pressure=mid_plane)
        result.rupture_angle = rupture
        pi_finite = mid_plane(phi + np.radians(rupture))
    except ModelInputError as exc:
        result.notes.append(f"theory not computed: {exc}")
        finite = None
        rupture = 0.0
        pi_short = pi_long = err_short = err_long = pi_finite = np.full(phi.shape, np.nan)
    for i in range(phi.size):
        result.table.append(
            SlideBearingRow(
                limb_angle=float(rows["limb_angle"][i]),
                phi_model=float(phi_deg[i]),
                pressure=float(pressure[i]),
                e_x=float(ecc.e_x[i]),
                e_y=float(ecc.e_y[i]),
                e=float(ecc.e[i]),
                chi=float(ecc.chi[i]),
                attitude=float(np.degrees(psi[i])),
                pi_measured=float(pi_measured[i]),
                pi_short=_opt(pi_short[i]),
                pi_long=_opt(pi_long[i]),
                pi_finite=_opt(pi_finite[i]),
                error_short=_opt(err_short[i]),
                error_long=_opt(err_long[i]),
            )
        )
    z = np.asarray(c.manometer_z)
    p_axial = np.array([rows[name][top] for name in MANOMETERS]) * gauge
    pi_z = measured(p_axial)
    try:
        pi_m = bearing.short_bearing_pressure(
            phi=phi[top], z=z, chi=chi_mean, a=a, mu_bar=oil.mu_bar, G=1.0
        )
        err_z = stands.relative_error_percent(reference=pi_m, other=pi_z).percent
    except ModelInputError:
        pi_m = err_z = np.full(z.shape, np.nan)
    pi_fz = (
        finite.pressure_at(phi=np.full(z.shape, phi[top] + np.radians(rupture)), z=z)
        if finite is not None
        else np.full(z.shape, np.nan)
    )
    result.axial = [
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
    return result
