"""A commercial tribometer's run: pin- or ball-on-disc (ASTM G99, ISO 20808) or
reciprocating (ASTM G133). The friction record -> μ, its running-in and steady state; the
track's profiles, the scar and the weighings -> the worn volumes and k = V/(F·L).

The record needs ``time`` and μ, or the friction force with the normal load; what the
file lacks comes from the configuration: the load from the test plan, the distance from the
laps (2πR a lap on the disc, 2S a cycle of strokes) or from the time and the planned speed,
the laps from the distance. Each such choice is named in the results' notes.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from uncertainties import UFloat, wrap

from rigserver.analysis.iso import iso_result
from rigserver.analysis.readings import Readings
from rigserver.analysis.references import Profiles
from rigserver.analysis.running_in import blocks_of, running_in
from rigserver.analysis.specimens import specimen_materials
from rigserver.analysis.streaming import BlockSeries
from rigserver.analysis.uncertainty import batch_mean, estimate, from_limit, from_resolution
from rigserver.core import tribometer, wear
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import (
    FrictionLoop,
    HertzResult,
    IsoRoughnessResult,
    LapMapResult,
    MassWear,
    PinOnDiscResults,
    ReciprocatingResults,
    ScarWear,
    StrokeBlock,
    TrackWear,
    TribometerStep,
)
from schemas.runs import Run
from schemas.stands import PinOnDiscConfig, ReciprocatingConfig, StandKind, TribometerConfig
from schemas.units import UNITS

GROUP = "friction"
TRACK = "wear_track"
_KG_PER_G = UNITS["g"].factor
_M_PER_UM = UNITS["um"].factor
_M_PER_MM = UNITS["mm"].factor
_RAD_S_PER_RPM = UNITS["rpm"].factor
#: Rows of the stroke table and points of a drawn friction loop, at most.
STROKE_BLOCKS = 40
LOOP_POINTS = 200

NOTE_LOAD = N_("the record has no normal load: the test plan's load is taken")
NOTE_DISTANCE_LAPS = N_("the record has no distance: it is the laps times the track's length")
NOTE_DISTANCE_SPEED = N_(
    "the record has neither distance nor laps: they are its sliding speed integrated over time"
)
NOTE_DISTANCE_TIME = N_("the record has neither distance nor laps: the planned speed times time")
NOTE_SPEED_DEFAULT = N_(
    "the sliding distance rests on the planned speed, which was not given for this run: it "
    "is the stand's default; give plan.speed in the run's configuration"
)
NOTE_LOAD_DEFAULT = N_(
    "the normal load rests on the test plan's load, which was not given for this run: it is "
    "the stand's default; give plan.load in the run's configuration"
)
NOTE_LAPS = N_("the record has no laps: they are the distance over the track's length")
NOTE_UNSETTLED = N_(
    "the friction did not settle: no part of at least the record's last fifth stays within "
    "±5 % of its mean, so neither a running-in distance nor a steady friction is given"
)
PENDING_RECORD = N_("no friction record yet")
PENDING_TRACK = N_("the disc's wear needs profiles across the track (group wear_track)")
PENDING_SCAR = N_("the pin's wear needs scar_diameter (a ball) or pin_height_loss (a flat pin)")
PENDING_LOOPS = N_("friction loops need the position along the stroke")

Results = PinOnDiscResults | ReciprocatingResults


class _Record:
    """The friction record's columns the analysis uses, whole, in SI."""

    def __init__(
        self, readings: Readings, config: PinOnDiscConfig | ReciprocatingConfig, lap_length: float
    ) -> None:
        parts: dict[str, list[NDArray[np.float64]]] = {}
        for chunk in readings.iter_chunks(GROUP):
            for name, values in chunk.items():
                parts.setdefault(name, []).append(np.asarray(values, dtype=np.float64))
        cols = {name: np.concatenate(p) for name, p in parts.items()}
        n = cols["time"].size
        nan = np.full(n, np.nan)
        self.notes: list[str] = []
        self.time = cols["time"]
        load = cols.get("normal_load", nan)
        if not np.isfinite(load).all():
            self.notes.append(NOTE_LOAD)
            load = np.where(np.isfinite(load), load, config.plan.load)
        self.load = load
        mu = cols.get("friction_coefficient", nan)
        force = cols.get("friction_force", nan)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            self.signed = np.where(np.isfinite(mu), mu, force / load)
        self.mu = np.abs(self.signed)
        self.step = cols.get("step", nan)
        radius = cols.get("track_radius", nan)
        if isinstance(config, PinOnDiscConfig):
            radius = np.where(np.isfinite(radius), radius, config.track_radius)
        self.radius = radius
        rpm = cols.get("rotational_speed", nan) * _RAD_S_PER_RPM
        speed = cols.get("sliding_speed", nan)
        self.speed = np.where(np.isfinite(speed), speed, rpm * radius)  # v = 2πRn/60
        # a lap's length row by row: 2πR of the row's radius on the disc (a radial stage)
        varies = np.isfinite(radius).all() and bool(np.ptp(radius) > 0)
        lap_lengths = 2.0 * np.pi * radius if varies else lap_length
        distance, laps = cols.get("distance", nan), cols.get("laps", nan)
        have_distance, have_laps = np.isfinite(distance).all(), np.isfinite(laps).all()
        if not have_distance:
            if have_laps:
                self.notes.append(NOTE_DISTANCE_LAPS)
                distance = _integral(laps, lap_lengths)
            elif np.isfinite(self.speed).all():
                self.notes.append(NOTE_DISTANCE_SPEED)
                distance = _integral(self.time, self.speed)
            else:
                self.notes.append(NOTE_DISTANCE_TIME)
                distance = self.time * config.plan.speed
        if not have_laps:
            if have_distance:
                self.notes.append(NOTE_LAPS)
            laps = _integral(distance, 1.0 / lap_lengths)
        self.distance, self.laps = distance, laps
        self.position = cols.get("position", nan) * _M_PER_MM
        temperature = cols.get("temperature", nan)
        self.temperature = temperature[np.isfinite(temperature)]
        depth = cols.get("wear_depth", nan)
        self.wear_depth = depth[np.isfinite(depth)] * _M_PER_UM


def _integral(x: NDArray[np.float64], rate: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """∫ rate dx from the first row, rate taken at each step's end (exact for a rate constant
    over each step, as the radius and speed of a recipe's step are); x itself times a
    constant rate."""
    if isinstance(rate, float):
        return x * rate
    steps = np.diff(x, prepend=x[0]) * rate
    found: NDArray[np.float64] = x[0] * float(rate[0]) + np.cumsum(steps)
    return found


def analyse(run: Run, readings: Readings, profiles: Profiles | None = None) -> Results:
    """The tribometer's results on the run's readings (``profiles`` unused: the track's
    profiles are the run's own group ``wear_track``)."""
    config, lap_length = _config(run)
    specimens = specimen_materials(run, config)
    config = specimens.config
    model = PinOnDiscResults if run.stand is StandKind.PIN_ON_DISC else ReciprocatingResults
    total = readings.rows(GROUP)
    if total == 0:
        return _no_record(model)
    r = _Record(readings, config, lap_length)
    for note, path in ((NOTE_DISTANCE_TIME, "plan.speed"), (NOTE_LOAD, "plan.load")):
        if note in r.notes and run.from_default(path):
            r.notes.append(NOTE_SPEED_DEFAULT if path == "plan.speed" else NOTE_LOAD_DEFAULT)
    steady, changes = _steady_start(r.laps, r.mu)
    result = _friction(model, r, total, steady, changes)
    result.notes.extend(r.notes + specimens.notes)
    result.pending.extend(specimens.pending)
    result.steps = _steps(r)
    if steady is None:
        result.notes.append(NOTE_UNSETTLED)
    else:
        _friction_uncertainty(config, result, r.mu[steady:])
    if not specimens.unknown:
        _contact(config, result)
    load = result.mean_load * from_limit(1.0, config.accuracy.load, "F_N")
    distance = result.sliding_distance
    try:
        _wear(run, readings, config, result, load, distance, specimens.unknown)
    except ArithmeticError:  # F·L of a load or path near nothing: k's derivatives overflow
        result.notes.append(f"k = V/(F·L) not computed: F·L = {result.mean_load * distance:g} N·m")
    if isinstance(result, PinOnDiscResults):
        _lap_views(r, steady, result)
    else:
        _strokes(r, steady, result)
    return result


def _config(run: Run) -> tuple[PinOnDiscConfig | ReciprocatingConfig, float]:
    """The run's configuration and the length of a lap: 2πR on the disc (ASTM G99), 2S a
    cycle of strokes (ASTM G133)."""
    if run.stand is StandKind.PIN_ON_DISC:
        disc = PinOnDiscConfig.model_validate(run.configuration)
        return disc, 2.0 * math.pi * disc.track_radius
    strokes = ReciprocatingConfig.model_validate(run.configuration)
    return strokes, 2.0 * strokes.stroke_length


def _no_record(model: type[Results]) -> Results:
    """The results of a run without a friction record: zeros, and the record pending."""
    empty = model(
        rows=0,
        duration=0.0,
        sliding_distance=0.0,
        laps=0.0,
        mean_load=0.0,
        friction_mean=0.0,
        friction_static=0.0,
        running_in_distance=0.0,
        running_in_laps=0.0,
        change_points=0,
        friction_steady=0.0,
        friction_steady_std=0.0,
        friction=BlockSeries(0).series("sliding distance", "friction coefficient"),
    )
    empty.pending.append(PENDING_RECORD)
    return empty


def _friction(
    model: type[Results], r: _Record, total: int, steady: int | None, changes: int
) -> Results:
    """The record's ``total`` rows' figures: the path and laps, μ's mean, its static peak
    (the first lap's, or the running-in's), the running-in's distance and the steady
    friction from row ``steady`` on (None: it did not settle)."""
    series = BlockSeries(total)
    series.add(r.distance - r.distance[0], r.mu)
    static_until = _first_lap_end(r) if steady == 0 else (steady or total)
    tail = r.mu[steady:] if steady is not None else None
    return model(
        rows=total,
        duration=float(r.time[-1] - r.time[0]),
        sliding_distance=float(r.distance[-1] - r.distance[0]),
        laps=float(r.laps[-1] - r.laps[0]),
        mean_load=float(r.load.mean()),
        friction_mean=float(r.mu.mean()),
        friction_static=float(r.mu[:static_until].max()),
        running_in_distance=None if steady is None else float(r.distance[steady] - r.distance[0]),
        running_in_laps=None if steady is None else float(r.laps[steady] - r.laps[0]),
        change_points=changes,
        friction_steady=None if tail is None else float(tail.mean()),
        friction_steady_std=None if tail is None else float(tail.std()),
        friction=series.series("sliding distance", "friction coefficient"),
        temperature_mean=float(r.temperature.mean()) if r.temperature.size else None,
        wear_depth_change=float(r.wear_depth[-1] - r.wear_depth[0]) if r.wear_depth.size else None,
    )


def _friction_uncertainty(
    config: TribometerConfig, result: Results, tail: NDArray[np.float64]
) -> None:
    """u(μ) of the steady mean: the spread of its batch means and the limits of the friction
    force and the load (GUM), into result; none with fewer than two steady rows."""
    if tail.size < 2:
        return
    acc = config.accuracy
    u = estimate(
        batch_mean(tail.tolist())
        * from_limit(1.0, acc.friction_force, "F_t")
        / from_limit(1.0, acc.load, "F_N")
    )
    result.friction_steady_uncertainty, result.friction_steady_expanded = (
        u.standard,
        u.expanded,
    )


def _steady_start(turns: NDArray[np.float64], mu: NDArray[np.float64]) -> tuple[int | None, int]:
    """The first row of the steady part of the record μ over ``turns`` (laps or cycles;
    None: the friction did not settle) and the change points found (module running_in)."""
    lap = np.floor(turns - np.floor(turns[0])).astype(np.int64)
    laps, means, counts = tribometer.segment_means(lap, mu)
    per_block = blocks_of(laps.size)
    block = (np.arange(laps.size) // per_block).astype(np.int64)
    if block.size > 2 * per_block and counts[block == block[-1]].sum() < 0.5 * (
        per_block * float(np.median(counts))
    ):
        # a last block of a few rows (the record's last reading, a lap begun) is as noisy
        # as its rows: it joins the block before it
        block[block == block[-1]] -= 1
    sums = np.bincount(block, weights=means * counts)
    rows = np.bincount(block, weights=counts.astype(np.float64))
    found = running_in(sums / rows)  # each block's mean over its rows
    if found.steady_from is None:
        return None, len(found.change_points)
    first_lap = laps[found.steady_from * per_block] if found.steady_from else laps[0]
    return int(np.searchsorted(lap, first_lap)), len(found.change_points)


def _steps(r: _Record) -> list[TribometerStep]:
    """One entry per step of the recipe, in the record's order (none without ``step``): its
    speed (recorded, or v = 2πRn/60), radius, load, duration, distance and μ, the steady μ
    by the running-in's criterion within the step."""
    if not np.isfinite(r.step).all():
        return []
    starts = np.flatnonzero(np.r_[True, r.step[1:] != r.step[:-1]])
    found = []
    for first, end in zip(starts, [*starts[1:], r.step.size], strict=True):
        rows = slice(int(first), int(end))
        mu, speed, radius = r.mu[rows], r.speed[rows], r.radius[rows]
        steady = _steady_start(r.laps[rows], mu)[0] if mu.size > 1 else 0
        found.append(
            TribometerStep(
                step=int(r.step[first]),
                sliding_speed=float(speed.mean()) if np.isfinite(speed).all() else None,
                track_radius=float(radius.mean()) if np.isfinite(radius).all() else None,
                normal_load=float(r.load[rows].mean()),
                duration=float(r.time[end - 1] - r.time[first]),
                distance=float(r.distance[end - 1] - r.distance[first]),
                friction_mean=float(mu.mean()),
                friction_steady=None if steady is None else float(mu[steady:].mean()),
            )
        )
    return found


def _first_lap_end(r: _Record) -> int:
    """The rows of the record's first lap (or cycle): where the static μ is sought when
    the record is steady from its start."""
    return max(1, int(np.searchsorted(r.laps, r.laps[0] + 1.0)))


def _contact(config: TribometerConfig, result: PinOnDiscResults | ReciprocatingResults) -> None:
    """The initial Hertz contact of a ball, or the nominal pressure of a flat pin."""
    if config.tip == "flat_pin":
        result.nominal_pressure = result.mean_load / (math.pi * config.tip_diameter**2 / 4.0)
        return
    modulus = tribometer.effective_modulus(
        youngs_1=config.pin.youngs_modulus,
        poisson_1=config.pin.poisson,
        youngs_2=config.disc.youngs_modulus,
        poisson_2=config.disc.poisson,
    )
    try:
        hertz = tribometer.hertz_ball_on_flat(
            load=result.mean_load, ball_radius=config.tip_diameter / 2.0, modulus=modulus
        )
    except ModelInputError as exc:
        result.notes.append(f"Hertz contact not computed: {exc}")
        return
    result.hertz = HertzResult(
        modulus=modulus,
        contact_radius=hertz.radius,
        max_pressure=hertz.max_pressure,
        mean_pressure=hertz.mean_pressure,
    )


def _rate(volume: UFloat | float, load: UFloat | float, distance: float) -> dict[str, float]:
    """V, k = V/(F·L) and their uncertainties, as the fields of a wear estimate."""
    v, k = estimate(volume), estimate(volume / (load * distance))
    return {
        "volume": v.value,
        "volume_uncertainty": v.standard,
        "specific_wear_rate": k.value,
        "specific_wear_rate_uncertainty": k.standard,
        "specific_wear_rate_expanded": k.expanded,
    }


def _wear(
    run: Run,
    readings: Readings,
    config: PinOnDiscConfig | ReciprocatingConfig,
    result: PinOnDiscResults | ReciprocatingResults,
    load: UFloat | float,
    distance: float,
    unknown: frozenset[str] = frozenset(),
) -> None:
    """Every worn volume the readings allow: track profiles, scar or height loss, masses
    (the density the posted one, else the material's: none of a material ``unknown``)."""
    if distance <= 0:
        return
    acc = config.accuracy
    m = readings.measurements()
    if readings.rows(TRACK):
        result.disc_track = _track(readings, config, result, load, distance)
    else:
        result.pending.append(PENDING_TRACK)
    radius = config.tip_diameter / 2.0
    if config.tip == "ball" and "scar_diameter" in m:
        cap = wrap(lambda d: tribometer.spherical_cap_volume(scar_diameter=d, ball_radius=radius))
        d = m["scar_diameter"] * _M_PER_UM
        try:
            volume = cap(from_limit(d, acc.scar, "d"))
        except ModelInputError as exc:  # a reading to correct: the run still finishes
            result.notes.append(f"the ball's wear from its scar not computed: {exc}")
        else:
            result.pin_scar = ScarWear(scar_diameter=d, **_rate(volume, load, distance))
    elif config.tip == "flat_pin" and "pin_height_loss" in m:
        h = m["pin_height_loss"] * _M_PER_UM
        area = math.pi * from_limit(config.tip_diameter, acc.length, "D") ** 2 / 4.0
        volume = area * from_limit(h, acc.height, "Δh")
        result.pin_scar = ScarWear(height_loss=h, **_rate(volume, load, distance))
    else:
        result.pending.append(PENDING_SCAR)
    for specimen, material in (("pin", config.pin), ("disc", config.disc)):
        before, after = m.get(f"{specimen}_mass_before"), m.get(f"{specimen}_mass_after")
        if before is None or after is None:
            continue
        if abs(before - after) * _KG_PER_G <= acc.balance_resolution * (1.0 + 1e-9):
            # within the balance's resolution: no mass change measured, no k from it
            setattr(result, f"{specimen}_mass_below", acc.balance_resolution)
            continue
        if specimen in unknown and f"{specimen}_density" not in m:
            continue
        density = m.get(f"{specimen}_density", material.density)
        loss = from_resolution(before * _KG_PER_G, acc.balance_resolution) - from_resolution(
            after * _KG_PER_G, acc.balance_resolution
        )
        volume = loss / from_limit(density, acc.density, f"ρ_{specimen}")
        found = MassWear(
            mass_loss=(before - after) * _KG_PER_G,
            density=density,
            **_rate(volume, load, distance),
        )
        if specimen == "pin":
            result.pin_mass = found
        else:
            result.disc_mass = found


def _track(
    readings: Readings,
    config: PinOnDiscConfig | ReciprocatingConfig,
    result: PinOnDiscResults | ReciprocatingResults,
    load: UFloat | float,
    distance: float,
) -> TrackWear | None:
    """The mean cross-section of the traces across the track, times the track's length."""
    acc = config.accuracy
    cols = readings.read(TRACK)
    areas = []
    iso: IsoRoughnessResult | None = None
    for trace in np.unique(cols["trace"]):
        chosen = cols["trace"] == trace
        order = np.argsort(cols["x"][chosen], kind="stable")
        try:
            areas.append(
                wear.wear_track_area(
                    x=cols["x"][chosen][order] * _M_PER_MM,
                    y=cols["z"][chosen][order] * _M_PER_UM,
                )
            )
        except ModelInputError as exc:
            result.notes.append(f"trace {trace:g} across the track left out: {exc}")
            continue
        if iso is None:  # the roughness across the track, of its first trace
            iso = iso_result(
                cols["x"][chosen][order] * _M_PER_MM,
                cols["z"][chosen][order] * _M_PER_UM,
                lambda_c=None,
                lambda_s=None,
                notes=result.notes,
            )
    if not areas:
        return None
    mean = float(np.mean(areas))
    spread = float(np.std(areas, ddof=1)) if len(areas) > 1 else None
    scatter = (spread or 0.0) / math.sqrt(len(areas))
    area: UFloat | float = from_limit(mean, acc.profile_height * mean * math.sqrt(3.0), "A")
    if scatter > 0:
        area = area + from_limit(0.0, scatter * math.sqrt(3.0), "s(A)")
    if isinstance(config, PinOnDiscConfig):
        radius = from_limit(config.track_radius, acc.length, "R")
        volume = 2.0 * math.pi * radius * area
    else:
        volume = from_limit(config.stroke_length, acc.length, "S") * area
    return TrackWear(
        traces=len(areas),
        track_area=mean,
        track_area_std=spread,
        iso=iso,
        **_rate(volume, load, distance),
    )


def _lap_views(r: _Record, steady: int | None, result: PinOnDiscResults) -> None:
    """μ against lap and angle; the once-per-lap amplitude in the steady part."""
    laps = r.laps - np.floor(r.laps[0])
    found = tribometer.lap_map(laps=laps, values=r.mu)
    result.friction_map = LapMapResult(
        lap=found.lap.tolist(),
        angle=found.angle.tolist(),
        values=[[None if math.isnan(v) else float(v) for v in row] for row in found.values],
    )
    if steady is not None and r.mu.size - steady >= 3:
        _, result.lap_amplitude = tribometer.lap_harmonic(laps=laps[steady:], values=r.mu[steady:])


def _strokes(r: _Record, steady: int | None, result: ReciprocatingResults) -> None:
    """Forward and backward strokes (the direction by the friction's sign: it opposes the
    sliding), per block of cycles; three friction loops: the first, middle and last cycle."""
    forward = r.signed >= 0
    rest = r.mu.size if steady is None else steady  # no steady strokes: none averaged
    tail_f, tail_b = r.mu[rest:][forward[rest:]], r.mu[rest:][~forward[rest:]]
    result.friction_forward = float(tail_f.mean()) if tail_f.size else None
    result.friction_backward = float(tail_b.mean()) if tail_b.size else None
    cycle = np.floor(r.laps - np.floor(r.laps[0])).astype(np.int64)
    per_block = max(1, math.ceil((int(cycle[-1]) + 1) / STROKE_BLOCKS))
    block = cycle // per_block
    for b in np.unique(block):
        rows = block == b
        f, back = r.mu[rows & forward], r.mu[rows & ~forward]
        result.strokes.append(
            StrokeBlock(
                cycle=float((b + 0.5) * per_block),
                forward=float(f.mean()) if f.size else None,
                backward=float(back.mean()) if back.size else None,
            )
        )
    if not np.isfinite(r.position).all():
        result.pending.append(PENDING_LOOPS)
        return
    complete = int(cycle[-1]) - 1 if cycle[-1] > 0 else 0
    for c in sorted({0, complete // 2, complete}):
        rows = np.flatnonzero(cycle == c)
        step = max(1, math.ceil(rows.size / LOOP_POINTS))
        chosen = rows[::step]
        result.loops.append(
            FrictionLoop(
                cycle=c,
                position=r.position[chosen].tolist(),
                friction=r.signed[chosen].tolist(),
            )
        )
