"""The model library: the formulas of the lab manual, numpy and scipy only.

Every function takes keyword arguments in SI units (metres, pascals, newtons, seconds,
radians unless a name says ``_deg``) and returns a named result. No I/O, no pydantic, no
web: the service, the reports and the simulated stands all call this package.

Modules, one per lab work or idea:

- :mod:`rigserver.core.roughness`: lab work 1, the ABRIS-PM7 profilometer.
- :mod:`rigserver.core.profile_filter`: the ISO 16610-21 Gaussian profile filter (λs, λc).
- :mod:`rigserver.core.iso_roughness`: the ISO 21920-2 parameters and the ISO 13565-2 Rk
  family of a trace, beside the manual's method.
- :mod:`rigserver.core.wear`: lab work 2, the SMTs-2 friction and wear machine.
- :mod:`rigserver.core.bearing`: labs 3 and 4, asymptotic journal-bearing theory.
- :mod:`rigserver.core.bearing_readings`: processing of the slide-bearing and MTOS readings.
- :mod:`rigserver.core.film`: the fluid-film criterion h_min >= h_min^crit (seed 001).
- :mod:`rigserver.core.reynolds`: the finite bearing, Reynolds equation (3.1) with cavitation.
- :mod:`rigserver.core.mechanism`: dynamic errors of programmed motion (seeds 000/002).
- :mod:`rigserver.core.arm`: the article's three-link arm with ball-screw drives.
"""
