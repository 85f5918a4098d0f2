"""Roughness as the standards define it, on any stored profile: the ISO 21920-2 parameters of
:func:`rigserver.core.iso_roughness.iso_profile` as a result with units.

The profilometer's runs, the SMTs-2 disc's wear-track profile and any stand that traces a
profile call :func:`iso_result` with the trace in metres and the filter settings of its
configuration (None: the ISO 21920-3 tables choose them).
"""

from __future__ import annotations

from numpy.typing import ArrayLike

from rigserver.core.errors import ModelInputError
from rigserver.core.iso_roughness import IsoProfile, iso_profile
from schemas.labels import ISO_ENDS, ISO_LAMBDA_C_SOURCE, ISO_REMARKS
from schemas.results import IsoRoughnessResult


def iso_result(
    x: ArrayLike,
    z: ArrayLike,
    *,
    lambda_c: float | None,
    lambda_s: float | None,
    notes: list[str],
) -> tuple[IsoRoughnessResult, IsoProfile] | None:
    """The ISO analysis of a trace (m) as a result, or None with the reason in ``notes``;
    the analysis' own remarks (a short trace, a resampled one) are added to ``notes``."""
    try:
        found = iso_profile(x, z, lambda_c=lambda_c, lambda_s=lambda_s)
    except ModelInputError as exc:
        notes.append(f"ISO roughness not computed: {exc}")
        return None
    q = found.parameters
    notes.extend(ISO_REMARKS[code] for code in found.remarks)
    result = IsoRoughnessResult(
        lambda_c=found.lambda_c,
        lambda_s=found.lambda_s,
        lambda_c_source=ISO_LAMBDA_C_SOURCE[found.lambda_c_basis],
        ends=ISO_ENDS[found.ends],
        sections=found.sections,
        evaluation_length=found.evaluation_length,
        ra=q.ra,
        rq=q.rq,
        rsk=q.rsk,
        rku=q.rku,
        rp=q.rp,
        rv=q.rv,
        rz=q.rz,
        rt=q.rt,
        rsm=q.rsm,
        rdq=q.rdq,
        rk=q.rk,
        rpk=q.rpk,
        rvk=q.rvk,
        mr1=q.mr1,
        mr2=q.mr2,
    )
    return result, found
