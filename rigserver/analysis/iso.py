"""Roughness as the standards define it, on any stored profile: the ISO 21920-2 parameters of
:func:`rigserver.core.iso_roughness.iso_profile` as a result with units.

The profilometer's runs, the SMTs-2 disc's wear-track profile and any stand that traces a
profile call :func:`iso_result` with the trace in metres and the filter settings of its
configuration (None: the ISO 21920-3 tables choose them).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike

from rigserver.core.errors import ModelInputError
from rigserver.core.iso_roughness import DEFAULT_SECTIONS, instrument_roughness, iso_profile
from schemas.labels import ISO_ENDS, ISO_LAMBDA_C_SOURCE, ISO_REMARKS
from schemas.results import IsoRoughnessResult


def iso_result(
    x: ArrayLike,
    z: ArrayLike,
    *,
    lambda_c: float | None,
    lambda_s: float | None,
    notes: list[str],
    roughness: bool = False,
    sections: int = 0,
) -> IsoRoughnessResult | None:
    """The ISO analysis of a trace (m) as a result, or None with the reason in ``notes``;
    the analysis' own remarks (a short trace, a resampled one) are added to ``notes``.

    ``roughness``: the trace is an instrument's roughness profile, evaluated whole in
    ``sections`` sampling lengths (0: its length over λc, rounded, or five without λc) and
    not filtered again; λc and λs are the instrument's."""
    try:
        if roughness:
            if not sections:
                length = float(np.ptp(np.asarray(x, dtype=np.float64)))
                sections = max(1, round(length / lambda_c)) if lambda_c else DEFAULT_SECTIONS
            found = instrument_roughness(
                x, z, sections=sections, lambda_c=lambda_c or 0.0, lambda_s=lambda_s or 0.0
            )
        else:
            found = iso_profile(x, z, lambda_c=lambda_c, lambda_s=lambda_s)
    except ModelInputError as exc:
        notes.append(f"ISO roughness not computed: {exc}")
        return None
    notes.extend(ISO_REMARKS[code] for code in found.remarks)
    return IsoRoughnessResult(
        lambda_c=found.lambda_c,
        lambda_s=found.lambda_s,
        lambda_c_source=ISO_LAMBDA_C_SOURCE[found.lambda_c_basis],
        ends=ISO_ENDS[found.ends],
        sections=found.sections,
        evaluation_length=found.evaluation_length,
        parts=found.parts,
        **dataclasses.asdict(found.parameters),
    )
