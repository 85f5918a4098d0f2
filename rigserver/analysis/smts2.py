"""Lab work 2 on a stored run: the SMTs-2 friction record and weighings -> (2.1)-(2.15)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rigserver.analysis.readings import Readings
from rigserver.analysis.references import Profiles
from rigserver.analysis.specimens import SMTS2, specimen_materials
from rigserver.analysis.streaming import BlockSeries, TailMoments
from rigserver.analysis.uncertainty import batch_mean, estimate, from_limit, from_resolution
from rigserver.core import wear
from rigserver.core.errors import ModelInputError
from rigserver.core.wear_validity import wear_theory_validity
from schemas.messages import N_
from schemas.results import (
    AdequacyResult,
    DiscWearResult,
    ExperimentalWearResult,
    IsoRoughnessResult,
    SensitivityPoint,
    Smts2Results,
    TheoreticalWearResult,
    WearValidityResult,
)
from schemas.runs import Run
from schemas.stands import Smts2Config
from schemas.units import UNITS

GROUP = "friction"
_REV_PER_COUNT = UNITS["100 rev"].factor
_KG_PER_G = UNITS["g"].factor
_M_PER_UM = UNITS["um"].factor
_M_PER_MM = UNITS["mm"].factor
#: t over the range of table 2.1 (1.3 for plastic steels to 13-14 for steel 30).
#: Why (2.1) is outside its range, by the codes of core.wear_validity (the figures behind
#: each are in the validity result beside them).
REASONS = {
    "plastic_asperities": N_(
        "the asperities are plastic: the real-contact pressure p_r exceeds HB, though "
        "p_c <= HB by (2.7)"
    ),
    "few_cycles": N_(
        "an asperity fails in fewer passes n = (σ0/σ)^t than the fatigue theory needs (n ≫ 1)"
    ),
    "no_plastic_k_f": N_("the plastic branch has no k_f^n: σ_T <= 2f·HB"),
}
#: The verdicts on the wear theory (2.1) against the experiment.
VERDICT_OUTSIDE = N_("theory outside its range")
VERDICT_ADEQUATE = N_("model (2.1) adequate (2.15)")
VERDICT_NOT_ADEQUATE = N_("model (2.1) not adequate (2.15)")

SENSITIVITY_T = (1.3, 2.0, 3.0, 5.0, 8.0, 11.0, 14.0)
#: σ0/σ_B of the sensitivity table, at the t that (2.7) picks.
SENSITIVITY_STRENGTH = (0.5, 1.0, 2.0, 5.0, 10.0)

TheoryAt = Callable[[float, float], wear.TheoreticalWear]


def analyse(run: Run, readings: Readings, profiles: Profiles | None = None) -> Smts2Results:
    """Lab 2's results; the pin's properties are its named material's (the materials table)
    where the configuration does not give them, and wait for them when the table lacks it."""
    specimens = specimen_materials(run, Smts2Config.model_validate(run.configuration), SMTS2)
    config = specimens.config
    pin_known = "pin" not in specimens.unknown
    record = _friction_record(readings, config)
    result = record.result()
    result.notes.extend(specimens.notes)
    result.pending.extend(specimens.pending)
    if record.rows == 0:
        result.pending.append(N_("no friction record yet"))
        return result
    _friction_uncertainty(config, result)
    m = readings.measurements()
    weighed = "pin_mass_before" in m and "pin_mass_after" in m and record.revolutions > 0
    if not weighed:
        result.pending.append(
            N_("experimental wear needs pin_mass_before, pin_mass_after and revolutions")
        )
    elif pin_known:  # else the pending item asks for the pin's properties
        try:
            _experimental(config, result, m["pin_mass_before"], m["pin_mass_after"])
        except ModelInputError as exc:  # a weighing to correct: the run still finishes
            result.pending.append(f"experimental wear not computed: {exc}")
        else:
            _wear_uncertainty(
                config, result, m["pin_mass_before"], m["pin_mass_after"], record.revolutions
            )
    track = (profiles or Profiles()).traces.get("disc")
    if track is not None and record.revolutions > 0:
        traced = (profiles or Profiles()).found.get("disc")
        iso = None if traced is None else traced.iso
        result.disc_wear = _disc_wear(run, config, result, track, iso)
    if "disc_ra" not in m:
        result.pending.append(
            N_("theoretical wear needs disc_ra (the disc's Ra from the profilometer)")
        )
    elif pin_known:
        _theoretical(config, result, m["disc_ra"] * _M_PER_UM)
    _verdict(result)
    return result


@dataclass(frozen=True, slots=True)
class _FrictionRecord:
    """The friction record's figures, read once in chunks: f (2.8) over time, its steady
    tail's moments, the disc's turns and the path (2.12)."""

    rows: int
    duration: float
    revolutions: float
    sliding_distance: float
    steady_time: float
    f_tail: TailMoments
    load_tail: TailMoments
    series: BlockSeries

    def result(self) -> Smts2Results:
        """The results of the record alone, before the weighings and the theory."""
        some = self.rows > 0
        return Smts2Results(
            rows=self.rows,
            duration=self.duration,
            revolutions=self.revolutions,
            sliding_distance=self.sliding_distance,
            mean_load=self.load_tail.mean if some else 0.0,
            friction_steady=self.f_tail.mean if some else 0.0,
            friction_steady_std=self.f_tail.std if some else 0.0,
            steady_from_time=self.steady_time,
            friction=self.series.series("time", "friction coefficient"),
        )


def _friction_record(readings: Readings, config: Smts2Config) -> _FrictionRecord:
    """f = M_tr/(N·r2) (2.8) chunk by chunk, its mean and spread over the steady tail, and
    the revolutions the counter gives (its unit: 100 rev)."""
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
    return _FrictionRecord(
        rows=total,
        duration=last_time - first_time,
        revolutions=revolutions,
        sliding_distance=float(sliding),
        steady_time=steady_time,
        f_tail=f_tail,
        load_tail=load_tail,
        series=series,
    )


def _friction_uncertainty(config: Smts2Config, result: Smts2Results) -> None:
    """u(f) of the steady mean (2.8): the spread of its batch means and the limits of M, N
    and r2 (GUM), into result; none with fewer than two steady points."""
    acc = config.accuracy
    steady = [
        y
        for x, y in zip(result.friction.x, result.friction.y, strict=True)
        if x >= result.steady_from_time
    ]
    if len(steady) < 2:
        return
    f_u = estimate(
        batch_mean(steady)
        * from_limit(1.0, acc.moment, "M")
        / from_limit(1.0, acc.load, "N")
        * config.disc_radius
        / from_limit(config.disc_radius, acc.length, "r2")
    )
    result.friction_steady_uncertainty, result.friction_steady_expanded = (
        f_u.standard,
        f_u.expanded,
    )


def _experimental(
    config: Smts2Config, result: Smts2Results, before_g: float, after_g: float
) -> None:
    """The pin's wear from its weighings, (2.9)-(2.13), and the specific wear rate
    k = V/(N·L), into result."""
    exp = wear.wear_intensity_experimental(
        mass_before=before_g * _KG_PER_G,
        mass_after=after_g * _KG_PER_G,
        density=config.pin.density,
        pin_radius=config.pin_diameter / 2.0,
        disc_radius=config.disc_radius,
        revolutions=result.revolutions,
    )
    result.experimental = ExperimentalWearResult(
        mass_loss=exp.mass_loss,
        volume=exp.volume,
        wear_depth=exp.wear_depth,
        sliding_distance=exp.sliding_distance,
        intensity=exp.intensity,
        specific_wear_rate=exp.volume / (result.mean_load * exp.sliding_distance),
    )


def _verdict(result: Smts2Results) -> None:
    """The theory against the experiment: outside its range, or (2.14)-(2.15)."""
    if result.validity is not None and not result.validity.within_range:
        result.verdict = VERDICT_OUTSIDE
    elif (
        result.experimental
        and result.theoretical
        and result.experimental.intensity > 0
        and result.theoretical.intensity > 0
    ):
        adequacy = wear.wear_adequacy(
            i_exp=result.experimental.intensity, i_theor=result.theoretical.intensity
        )
        result.adequacy = AdequacyResult(
            relative_error_percent=adequacy.relative_error_percent,
            adequate=adequacy.adequate,
            lower=adequacy.lower,
            upper=adequacy.upper,
        )
        result.verdict = VERDICT_ADEQUATE if adequacy.adequate else VERDICT_NOT_ADEQUATE


def _theoretical(config: Smts2Config, result: Smts2Results, ra_disc: float) -> None:
    """(2.1) for the run, its applicability figures and the sensitivity table, into result."""
    pin = config.pin

    def at(t: float, strength_ratio: float = 1.0) -> wear.TheoreticalWear:
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
            fatigue_strength=strength_ratio * pin.tensile_strength,
        )

    try:
        theory = at(config.fatigue_t_elastic)
        t = config.fatigue_t_elastic
        if theory.contact == "plastic":
            theory, t = at(config.fatigue_t_plastic), config.fatigue_t_plastic
    except ModelInputError as exc:
        result.notes.append(f"theoretical wear not computed: {exc}")
        return
    try:
        result.validity = _validity(config, result.friction_steady, theory, t, 1.0)
    except ModelInputError as exc:
        result.notes.append(f"the range of (2.1) not checked: {exc}")
    result.sensitivity = _sensitivity(config, result.friction_steady, at, t)
    result.theoretical = TheoreticalWearResult(
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


def _validity(
    config: Smts2Config,
    f: float,
    theory: wear.TheoreticalWear,
    t: float,
    strength_ratio: float,
) -> WearValidityResult:
    pin = config.pin
    v = wear_theory_validity(
        theory=theory,
        friction_coefficient=f,
        poisson=pin.poisson,
        hardness=pin.hardness,
        yield_strength=pin.yield_strength,
        fatigue_strength=strength_ratio * pin.tensile_strength,
        fatigue_t=t,
        b=config.b,
        nu=config.nu,
    )
    found = dataclasses.asdict(v) | {"reasons": [REASONS[code] for code in v.reasons]}
    return WearValidityResult.model_validate(found)


def _sensitivity(
    config: Smts2Config, f: float, at: TheoryAt, t_used: float
) -> list[SensitivityPoint]:
    """I_h and n over t (at σ0 = σ_B) and over σ0/σ_B (at the t used)."""
    grid = [(t, 1.0) for t in SENSITIVITY_T] + [
        (t_used, r) for r in SENSITIVITY_STRENGTH if r != 1.0
    ]
    points = []
    for t, ratio in grid:
        try:
            theory = at(t, ratio)
            n = _validity(config, f, theory, t, ratio).cycles_to_failure
        except ModelInputError:
            points.append(SensitivityPoint(fatigue_t=t, strength_ratio=ratio))
            continue
        points.append(
            SensitivityPoint(
                fatigue_t=t,
                strength_ratio=ratio,
                intensity=theory.intensity,
                cycles_to_failure=n,
            )
        )
    return points


def _wear_uncertainty(
    config: Smts2Config, result: Smts2Results, before_g: float, after_g: float, turns: float
) -> None:
    """u(I_h) and u(k) from the balance's resolution, the specimens' dimensions, ρ, the
    counter's step and the load's tolerance, first order (GUM 5.1.2)."""
    assert result.experimental is not None
    acc = config.accuracy
    loss = from_resolution(before_g * _KG_PER_G, acc.balance_resolution) - from_resolution(
        after_g * _KG_PER_G, acc.balance_resolution
    )
    volume = loss / from_limit(config.pin.density, acc.density)
    r1 = from_limit(config.pin_diameter / 2.0, acc.length)
    distance = (
        2.0
        * math.pi
        * from_limit(config.disc_radius, acc.length)
        * from_resolution(turns, acc.counter)
    )
    intensity = estimate(volume / (math.pi * r1**2) / distance)
    rate = estimate(volume / (result.mean_load * from_limit(1.0, acc.load) * distance))
    e = result.experimental
    e.intensity_uncertainty, e.intensity_expanded = intensity.standard, intensity.expanded
    e.specific_wear_rate_uncertainty, e.specific_wear_rate_expanded = rate.standard, rate.expanded


def _disc_wear(
    run: Run,
    config: Smts2Config,
    result: Smts2Results,
    track: Readings,
    iso: IsoRoughnessResult | None,
) -> DiscWearResult | None:
    """The disc's worn volume: the track's cross-section (a profile across it) × 2π r2; with
    the ISO roughness across the track (the profilometer run's, its form filtered out)."""
    trace = track.read("profile")
    try:
        area = wear.wear_track_area(x=trace["x"] * _M_PER_MM, y=trace["y"] * _M_PER_UM)
    except (KeyError, ModelInputError) as exc:
        result.notes.append(f"disc wear not computed from the track's profile: {exc}")
        return None
    volume = area * 2.0 * math.pi * config.disc_radius
    return DiscWearResult(
        profile_run=str(run.specimen["disc_profile_run"]),
        track_area=area,
        volume=volume,
        specific_wear_rate=volume / (result.mean_load * result.sliding_distance),
        iso=iso,
    )
