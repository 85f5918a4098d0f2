"""Lab work 2 on a stored run: the SMTs-2 friction record and weighings -> (2.1)-(2.15)."""

from __future__ import annotations

import numpy as np

from rigserver.analysis.readings import Readings
from rigserver.analysis.streaming import BlockSeries, TailMoments
from rigserver.core import wear
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import (
    AdequacyResult,
    ExperimentalWearResult,
    Smts2Results,
    TheoreticalWearResult,
)
from schemas.runs import Run
from schemas.stands import Smts2Config
from schemas.units import UNITS

GROUP = "friction"
_REV_PER_COUNT = UNITS["100 rev"].factor
_KG_PER_G = UNITS["g"].factor
_M_PER_UM = UNITS["um"].factor


def analyse(run: Run, readings: Readings) -> Smts2Results:
    config = Smts2Config.model_validate(run.configuration)
    total = readings.rows(GROUP)
    series = BlockSeries(total)
    start = wear.steady_window_start(samples=total, fraction=config.steady_fraction) if total else 0
    f_tail, load_tail = TailMoments(start), TailMoments(start)
    first_time = last_time = first_count = last_count = steady_time = 0.0
    seen = 0
    for chunk in readings.iter_chunks(GROUP):
        time = chunk["time"]
        f = wear.friction_coefficient(
            friction_moment=chunk["friction_moment"],
            load=chunk["load"],
            radius=config.disc_radius,
        )
        series.add(time, np.asarray(f, dtype=np.float64))
        f_tail.add(np.asarray(f, dtype=np.float64))
        load_tail.add(chunk["load"])
        if seen == 0:
            first_time, first_count = float(time[0]), float(chunk["revolutions"][0])
        if seen <= start < seen + time.size:
            steady_time = float(time[start - seen])
        seen += time.size
        last_time, last_count = float(time[-1]), float(chunk["revolutions"][-1])
    revolutions = (last_count - first_count) * _REV_PER_COUNT
    sliding = wear.sliding_distance(disc_radius=config.disc_radius, revolutions=revolutions)
    result = Smts2Results(
        rows=total,
        duration=last_time - first_time,
        revolutions=revolutions,
        sliding_distance=float(sliding),
        mean_load=load_tail.mean if total else 0.0,
        friction_steady=f_tail.mean if total else 0.0,
        friction_steady_std=f_tail.std if total else 0.0,
        steady_from_time=steady_time,
        friction=series.series("time", "friction coefficient"),
    )
    if total == 0:
        result.pending.append(N_("no friction record yet"))
        return result
    m = readings.measurements()
    pin_radius = config.pin_diameter / 2.0
    if "pin_mass_before" in m and "pin_mass_after" in m and revolutions > 0:
        exp = wear.wear_intensity_experimental(
            mass_before=m["pin_mass_before"] * _KG_PER_G,
            mass_after=m["pin_mass_after"] * _KG_PER_G,
            density=config.pin.density,
            pin_radius=pin_radius,
            disc_radius=config.disc_radius,
            revolutions=revolutions,
        )
        result.experimental = ExperimentalWearResult(
            mass_loss=exp.mass_loss,
            volume=exp.volume,
            wear_depth=exp.wear_depth,
            sliding_distance=exp.sliding_distance,
            intensity=exp.intensity,
        )
    else:
        result.pending.append(
            N_("experimental wear needs pin_mass_before, pin_mass_after and revolutions")
        )
    if "disc_ra" in m:
        result.theoretical = _theoretical(config, result, m["disc_ra"] * _M_PER_UM)
    else:
        result.pending.append(
            N_("theoretical wear needs disc_ra (the disc's Ra from the profilometer)")
        )
    if result.experimental and result.theoretical and result.experimental.intensity > 0:
        adequacy = wear.wear_adequacy(
            i_exp=result.experimental.intensity, i_theor=result.theoretical.intensity
        )
        result.adequacy = AdequacyResult(
            relative_error_percent=adequacy.relative_error_percent,
            adequate=adequacy.adequate,
            lower=adequacy.lower,
            upper=adequacy.upper,
        )
    return result


def _theoretical(
    config: Smts2Config, result: Smts2Results, ra_disc: float
) -> TheoreticalWearResult | None:
    pin = config.pin

    def at(t: float) -> wear.TheoreticalWear:
        return wear.wear_intensity_theoretical(
            load=result.mean_load,
            pin_radius=config.pin_diameter / 2.0,
            disc_radius=config.disc_radius,
            friction_coefficient=result.friction_steady,
            ra_disc=ra_disc,
            youngs_modulus=pin.youngs_modulus,
            poisson=pin.poisson,
            hardness=pin.hardness,
            yield_strength=pin.yield_strength,
            tensile_strength=pin.tensile_strength,
            elongation=pin.elongation,
            fatigue_t=t,
            nu=config.nu,
            b=config.b,
        )

    try:
        theory = at(config.fatigue_t_elastic)
        t = config.fatigue_t_elastic
        if theory.contact == "plastic":
            theory, t = at(config.fatigue_t_plastic), config.fatigue_t_plastic
    except ModelInputError as exc:
        result.notes.append(f"theoretical wear not computed: {exc}")
        return None
    return TheoreticalWearResult(
        intensity=theory.intensity,
        contact=theory.contact,
        fatigue_t=t,
        contour_pressure=theory.contour_pressure,
        nominal_area=theory.nominal_area,
        contour_area=theory.contour_area,
        eta_c=theory.eta_c,
        complex_parameter=theory.complex_parameter,
        rmax_over_r=theory.rmax_over_r,
        C=theory.C,
        beta=theory.beta,
        k_nu=theory.k_nu,
        k_f=theory.k_f,
    )
