"""The steady heat balance of a lubricated bearing, closed through the viscosity law.

The friction power heats the film; the oil flow and the housing carry the heat away:

    P(t) = M_tr(t)·ω = (ρ·c_p·Q + G)·(t - t_in),

where the friction moment depends on the film temperature t through μ = A·exp(α·t) (3.21,
4.17). A hotter film is thinner-oiled, the journal sinks, the friction falls, and the film
cools: the self-regulation of a hydrodynamic bearing that lab work 4 describes. The film
temperature is the fixed point of that loop, found here as the root of
t - t_in - P(t)/(ρ·c_p·Q + G) on [t_in, t_in + span] (Brent's method).

The balance is steady: the stands are read at the end of each step, after the 2-3 minutes
the manual allows for the thermal regime to settle; with the default conductances the time
constant of a bush of a few hundred J/K is well under a minute.

Where friction grows with temperature (a starved film, the manual's unstable branch E of
fig. 4.1) the balance may have several roots. The bearing warms up from the inlet
temperature, so the root taken is the lowest: the warm-up iteration t_{k+1} = t_in + P(t_k)/G
climbs from t_in until it overshoots a root, which Brent's method then refines.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from scipy.optimize import brentq

from rigsim.errors import SettingsError

#: Density of a mineral oil, kg/m³.
OIL_DENSITY = 870.0
#: Specific heat of a mineral oil, J/(kg·K).
OIL_HEAT_CAPACITY = 1900.0
#: Volume of one drop of oil from a drip feeder, m³ (about 0.03 ml).
DROP_VOLUME = 3e-8


@dataclass(frozen=True, slots=True)
class HeatBalance:
    """Where the friction heat goes.

    Attributes
    ----------
    oil_flow : float
        Oil flow through the bearing Q, m³/s.
    conductance : float
        Heat conducted into the journal and shaft and convected from the housing per kelvin
        of film temperature over the inlet, W/K.
    """

    oil_flow: float
    conductance: float

    def __post_init__(self) -> None:
        if self.oil_flow < 0:
            raise SettingsError(f"oil_flow must be >= 0 m^3/s, got {self.oil_flow}")
        if self.total <= 0:
            raise SettingsError(
                f"the heat balance needs some way out: oil_flow = {self.oil_flow} m^3/s and "
                f"conductance = {self.conductance} W/K"
            )

    @property
    def total(self) -> float:
        """ρ·c_p·Q + G, W/K."""
        return OIL_DENSITY * OIL_HEAT_CAPACITY * self.oil_flow + self.conductance


@dataclass(frozen=True, slots=True)
class FilmTemperature:
    """The steady film temperature and the friction power there.

    Attributes
    ----------
    temperature : float
        t, °C.
    power : float
        Friction power P(t), W.
    """

    temperature: float
    power: float


def steady_film_temperature(
    *,
    power: Callable[[float], float],
    inlet: float,
    balance: HeatBalance,
    span: float = 150.0,
    max_steps: int = 200,
) -> FilmTemperature:
    """Film temperature at which the friction power ``power(t)`` (W) is carried away.

    Parameters
    ----------
    power : callable
        Friction power at film temperature t (°C), W (>= 0).
    inlet : float
        Oil inlet temperature t_in, °C.
    balance : HeatBalance
        Oil flow and conductance.
    span : float
        Largest rise over the inlet considered, K.
    max_steps : int
        Steps of the warm-up iteration before the stand is declared in thermal runaway.

    Returns
    -------
    FilmTemperature

    Raises
    ------
    SettingsError
        When the warm-up passes ``inlet + span`` (the stand would overheat) or does not
        settle in ``max_steps`` (thermal runaway).
    """
    G = balance.total

    def imbalance(t: float) -> float:
        return t - inlet - power(t) / G

    top = inlet + span
    low, t = inlet, inlet
    if imbalance(inlet) >= 0.0:
        return FilmTemperature(temperature=inlet, power=power(inlet))
    for _ in range(max_steps):
        nxt = inlet + power(t) / G
        if nxt > top:
            raise SettingsError(
                f"the bearing would overheat: {power(t):.4g} W of friction at {t:.4g} °C "
                f"would raise the film over {top:.4g} °C ({G:.4g} W/K carry the heat off)"
            )
        if imbalance(nxt) >= 0.0:
            found = float(brentq(imbalance, low, nxt, xtol=1e-4))
            return FilmTemperature(temperature=found, power=power(found))
        low, t = nxt, nxt
    raise SettingsError(
        f"thermal runaway: the film temperature still rises after {max_steps} steps "
        f"(at {t:.4g} °C); friction grows with temperature faster than {G:.4g} W/K carry it off"
    )
