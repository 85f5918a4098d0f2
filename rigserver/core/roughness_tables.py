"""Reference data of lab work 1 (tables 1.1, 1.2, 1.4, 1.5) and the ABRIS-PM7 subranges.

Transcribed from the lab manual (``seeds/004_*.txt``), converted to SI: lengths in metres,
stresses in pascals; dimensionless quantities as printed. Names are kept as printed
(``name_ru``) with an English gloss (``name``). The service offers these as presets.

What the print does not make clear, and how it is handled:

- Table 1.1: eight rows disagree with (1.9), Δ = Rmax/(R·b^(1/ν)), computed from their own
  Rmax, R, b, ν by more than the rounding of two printed digits (5 %): the 2Kh13 bearing
  (+7 %), the cast-iron piston ring (-26 %), the MKV-50 brake disc (x10), the 30KhGSA brake
  disc (+11 %), the piston pin and the small-end bush (x10: Rmax 6.7 and 7.0 μm are likely
  0.67 and 0.70 μm, which also gives their Ra ≈ Rmax/6 of (1.2)), the diesel injector (x5)
  and the Volga big-end shell (x9). The rows are transcribed as printed.
- Table 1.5 is garbled in the text: the kerosene entries (16.5, 7.0 and 1.0 MPa) cannot be
  assigned to their materials with certainty (the likeliest reading gives them, in this
  order, to 30KhGSA, BrB2 and BrAZhMts 10-3-1.5) and are left out; "MoS2" and "ShKh15"
  appear beside steel 45 without a value of their own and are left out too.
- The instrument data print the largest cutoff as "205" mm; it is 2.5 mm (the subranges
  are quoted "на базовой длине 2,5 мм").
"""

from __future__ import annotations

from dataclasses import dataclass

_UM = 1e-6
_MPA = 1e6


@dataclass(frozen=True, slots=True)
class RunInRoughness:
    """A row of table 1.1: roughness of a run-in surface.

    Attributes
    ----------
    name, name_ru : str
        The surface (English gloss; as printed).
    rmax : float
        Greatest profile height Rmax, m.
    radius : float
        Mean asperity radius R, m.
    b, nu : float
        Bearing-curve parameters of t_p = b·ε^ν (1.8), dimensionless.
    ra : float
        Arithmetic mean deviation Ra, m.
    delta : float
        Complex roughness parameter Δ (1.9) as printed, dimensionless.
    """

    name: str
    name_ru: str
    rmax: float
    radius: float
    b: float
    nu: float
    ra: float
    delta: float


def _run_in(
    name: str,
    name_ru: str,
    rmax_um: float,
    r_um: float,
    b: float,
    nu: float,
    ra_um: float,
    delta: float,
) -> RunInRoughness:
    return RunInRoughness(name, name_ru, rmax_um * _UM, r_um * _UM, b, nu, ra_um * _UM, delta)


# fmt: off
#: Table 1.1: approximate roughness parameters of run-in surfaces [manual, ref. 3].
RUN_IN_ROUGHNESS: tuple[RunInRoughness, ...] = tuple(_run_in(*row) for row in (
    # name, name as printed, then Rmax (μm), R (μm), b, ν, Ra (μm), Δ
    ("steel at rubber lip seals",
     "Поверхности стальных деталей в местах уплотнений резиновыми манжетами",
     0.72, 184, 3.1, 3.0, 0.13, 2.7e-3),
    ("slide bearing, steel 2Kh13", "Подшипник скольжения (сталь 2Х13)",
     0.84, 53, 1.8, 2.0, 0.15, 1.1e-2),
    ("piston ring, cast iron", "Поршневое кольцо (чугун)",
     0.15, 100, 3.0, 1.8, 0.03, 1.1e-3),
    ("slide bearing, cermet bush with MoS2",
     "Подшипник скольжения (втулка из металлокерамики, содержащей MoS2)",
     5.4, 77, 3.5, 1.8, 0.09, 3.5e-2),
    ("aircraft brake disc, Retinax", "Диски самолетного тормоза: Ретинакс",
     4, 30, 4.0, 2.4, 0.70, 7.4e-2),
    ("aircraft brake disc, FMK-11", "Диски самолетного тормоза: ФМК-11",
     6.5, 120, 3.5, 2.5, 1.15, 3.3e-2),
    ("aircraft brake disc, MKV-50", "Диски самолетного тормоза: МКВ-50",
     6, 15, 1.1, 2.1, 0.91, 3.7e-2),
    ("aircraft brake disc, ChNMKh", "Диски самолетного тормоза: ЧНМХ",
     4, 76, 1.0, 2.1, 0.65, 5.3e-2),
    ("aircraft brake disc, steel 30KhGSA", "Диски самолетного тормоза: Сталь 30ХГСА",
     5, 82, 1.0, 2.2, 0.78, 5.5e-2),
    ("cylinder liner", "Гильза цилиндра",
     1.2, 1000, 1.0, 1.0, 0.04, 1.2e-3),
    ("piston ring", "Поршневое кольцо",
     0.48, 270, 1.02, 0.4, 0.02, 1.7e-3),
    ("crankshaft main and crankpin journals", "Коленчатый вал (коренные и шатунные шейки)",
     1.6, 500, 1.04, 1.2, 0.05, 3.1e-3),
    ("crankshaft bearing shells", "Вкладыши подшипника коленчатого вала",
     2.6, 300, 1.01, 1.2, 0.42, 8.6e-3),
    ("piston pin", "Поршневой палец",
     6.7, 300, 1.01, 1.2, 0.11, 2.2e-3),
    ("connecting-rod small-end bush", "Втулка верхней головки шатуна",
     7.0, 250, 1.0, 1.2, 0.112, 2.8e-3),
    ("piston, pin-boss bores", "Поршень (отверстия в бобышках)",
     1.1, 220, 1.0, 1.2, 0.18, 5.0e-3),
    ("diesel injector", "Форсунка дизеля",
     0.6, 35, 3.8, 1.9, 0.1, 1.7e-3),
    ("big-end shell, Volga car", "Шатунный вкладыш автомобиля «Волга»",
     1.3, 54, 1.2, 2.0, 0.24, 2.4e-3),
))
# fmt: on


@dataclass(frozen=True, slots=True)
class HysteresisLoss:
    """A row of table 1.2: hysteresis loss coefficient α_r under uniaxial tension-compression.

    Attributes
    ----------
    name, name_ru : str
        The material (English gloss; as printed).
    alpha_r_min, alpha_r_max : float
        The printed range of α_r, dimensionless (equal when a single value is printed).
    """

    name: str
    name_ru: str
    alpha_r_min: float
    alpha_r_max: float


#: Table 1.2: hysteresis loss coefficient α_r of friction-unit materials [manual, ref. 4].
HYSTERESIS_LOSS: tuple[HysteresisLoss, ...] = (
    HysteresisLoss("copper (hard)", "Медь (твердая)", 0.04, 0.04),
    HysteresisLoss("phosphor bronze", "Фосфористая бронза", 0.04, 0.04),
    HysteresisLoss("duralumin", "Дюралюминий", 0.03, 0.03),
    HysteresisLoss("hardened steel", "Закаленная сталь", 0.02, 0.02),
    HysteresisLoss("plastics", "Пластмасса", 0.08, 0.12),
    HysteresisLoss("rubber", "Резина", 0.09, 0.13),
    HysteresisLoss("wood", "Дерево", 0.2, 0.2),
)


@dataclass(frozen=True, slots=True)
class FrictionParameter:
    """A row of table 1.4 (dry) or 1.5 (lubricated): the friction parameter τ0.

    τ0 is the shear strength of the molecular bond on the real contact area.

    Attributes
    ----------
    name, name_ru : str
        The material (English gloss; as printed).
    lubricant : str
        The lubricant or surface film as printed; empty for dry contact (table 1.4).
    tau0_min, tau0_max : float
        The printed range of τ0, Pa (equal when a single value is printed).
    """

    name: str
    name_ru: str
    lubricant: str
    tau0_min: float
    tau0_max: float


def _tau0(
    name: str, name_ru: str, low_mpa: float, high_mpa: float | None = None, lubricant: str = ""
) -> FrictionParameter:
    high = low_mpa if high_mpa is None else high_mpa
    return FrictionParameter(name, name_ru, lubricant, low_mpa * _MPA, high * _MPA)


#: Table 1.4: friction parameter τ0 without lubricant [manual, ref. 4].
FRICTION_PARAMETER_DRY: tuple[FrictionParameter, ...] = (
    _tau0("lead", "Свинец", 2.74),
    _tau0("silver", "Серебро", 7.7),
    _tau0("copper", "Медь", 18),
    _tau0("chromium", "Хром", 15),
    _tau0("cadmium", "Кадмий", 9.43),
    _tau0("titanium", "Титан", 28.2),
    _tau0("tin", "Олово", 4.49),
    _tau0("PTFE (fluoroplastic)", "Фторопласт", 3.41),
    _tau0("polypropylene", "Полипропилен", 0.11),
    _tau0("caprolon (cast polyamide)", "Капролон", 1.95),
    _tau0("alloy ASS-6-5", "Сплав АСС-6-5", 10),
    _tau0("alloy A-20", "Сплав А-20", 16),
    _tau0("steel 30KhGSA", "Сталь 30ХГСА", 200),
    _tau0("steel 45", "Сталь 45", 204),
    _tau0("steel 08Kh18N19T (as printed)", "Сталь 08Х18Н19Т", 31.8),
    _tau0("steel 40Kh", "Сталь 40Х", 184),
    _tau0("steel 45, hardened", "Сталь 45 (закалка)", 130),
    _tau0("polyethylene (PEVP)", "Полиэтилен (ПЭВП)", 0.44),
    _tau0("polyethylene (PEVN, as printed)", "Полиэтилен (ПЭВН)", 1.14),
    _tau0("technical capron (polyamide)", "Капрон технический", 1.61),
)

#: Table 1.5: friction parameter τ0 of lubricated contacts [manual, refs. 3, 4]; the
#: entries the text makes clear (see the module docstring for what is left out).
FRICTION_PARAMETER_LUBRICATED: tuple[FrictionParameter, ...] = (
    _tau0("steel 30KhGSA", "Сталь 30ХГСА", 1.0, lubricant="ЦИАТИМ-201"),
    _tau0("steel 30KhGSA", "Сталь 30ХГСА", 1.0, lubricant="АК-6"),
    _tau0("steel 30KhGSA", "Сталь 30ХГСА", 1.0, lubricant="Вазелиновое масло"),
    _tau0("beryllium bronze BrB2", "Бр Б2", 0.5, lubricant="ЦИАТИМ-201"),
    _tau0("beryllium bronze BrB2", "Бр Б2", 1.0, lubricant="АК-6"),
    _tau0("beryllium bronze BrB2", "Бр Б2", 1.0, lubricant="Вазелиновое масло"),
    _tau0("aluminium bronze BrAZhMts 10-3-1.5", "БрАЖМц 10-3-1,5", 0.5, lubricant="ЦИАТИМ-201"),
    _tau0("aluminium bronze BrAZhMts 10-3-1.5", "БрАЖМц 10-3-1,5", 1.0, lubricant="АК-6"),
    _tau0(
        "aluminium bronze BrAZhMts 10-3-1.5", "БрАЖМц 10-3-1,5", 1.0, lubricant="Вазелиновое масло"
    ),
    _tau0("steel 45, annealed", "Сталь 45 (отжиг)", 1.0, 50.0, lubricant="АСсп-6"),
    _tau0("steel 45, annealed", "Сталь 45 (отжиг)", 1.0, 50.0, lubricant="Трансформаторное масло"),
    _tau0("glass", "Стекло", 1.0, lubricant="Стеариновая кислота (монослой)"),
    _tau0("glass", "Стекло", 0.5, lubricant="Фторопласт"),
    _tau0("glass", "Стекло", 5.0, 6.0, lubricant="Полиэтилен ВД"),
    _tau0("glass", "Стекло", 3.0, 4.0, lubricant="Себациновая кислота"),
)


@dataclass(frozen=True, slots=True)
class ProfilometerSubrange:
    """One measuring subrange of the ABRIS-PM7 profilometer (manual, technical data item 1).

    The upper limits are the ``г.н.`` values of the error limits (1.14).

    Attributes
    ----------
    cutoff : float
        Sampling (base) length, the cutoff of the filter, m.
    ra_min, ra_max : float
        Range of Ra, m.
    rz_min, rz_max : float
        Range of Rz and of Rmax, m.
    sm_min, sm_max : float
        Range of Sm, m.
    """

    cutoff: float
    ra_min: float
    ra_max: float
    rz_min: float
    rz_max: float
    sm_min: float
    sm_max: float


# fmt: off
#: The three subranges of the ABRIS-PM7 (t_p, 0.1-99.9 %, is the same in all three).
ABRIS_PM7_SUBRANGES: tuple[ProfilometerSubrange, ...] = (
    #                    cutoff, Ra min, max (μm), Rz and Rmax min, max (μm), Sm min, max (μm)
    ProfilometerSubrange(0.25e-3, 0.04 * _UM, 0.40 * _UM, 0.16 * _UM, 1.60 * _UM,
                         8.0 * _UM, 25.0 * _UM),
    ProfilometerSubrange(0.8e-3, 0.40 * _UM, 3.20 * _UM, 1.60 * _UM, 12.50 * _UM,
                         8.0 * _UM, 80.0 * _UM),
    ProfilometerSubrange(2.5e-3, 3.20 * _UM, 12.50 * _UM, 12.50 * _UM, 50.00 * _UM,
                         8.0 * _UM, 250.0 * _UM),
)
# fmt: on
