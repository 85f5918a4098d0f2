"""``/stands``: the stand kinds, their configuration, channels and limits."""

from __future__ import annotations

from fastapi import APIRouter

from rigserver.api.deps import ReadAccess, ServicesDep
from rigserver.api.problems import ApiProblem
from schemas.stands import Stand, StandKind

router = APIRouter(prefix="/stands", tags=["stands"], dependencies=[ReadAccess])


@router.get("", summary="List the stand kinds")
def list_stands(services: ServicesDep) -> list[Stand]:
    return list(services.stands.values())


@router.get("/{kind}", summary="One stand: configuration, channel groups, units, limits")
def get_stand(kind: str, services: ServicesDep) -> Stand:
    try:
        return services.stands[StandKind(kind)]
    except ValueError:
        known = ", ".join(k.value for k in StandKind)
        raise ApiProblem(
            404, "Unknown stand", f"no stand kind {kind[:40]!r}; known: {known}"
        ) from None
