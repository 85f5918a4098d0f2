"""Every stand's report list, by the stand's kind."""

from __future__ import annotations

from rigserver.reports.contents import Contents, mtos, profilometer, slide_bearing, smts2
from rigserver.reports.contents.tribometer import contents
from schemas.stands import StandKind

CONTENTS: dict[StandKind, Contents] = {
    StandKind.PROFILOMETER: profilometer.CONTENTS,
    StandKind.SMTS2: smts2.CONTENTS,
    StandKind.SLIDE_BEARING: slide_bearing.CONTENTS,
    StandKind.MTOS: mtos.CONTENTS,
    StandKind.PIN_ON_DISC: contents("pin_on_disc"),
    StandKind.RECIPROCATING: contents("reciprocating"),
}
