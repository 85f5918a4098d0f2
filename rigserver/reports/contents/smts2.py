"""Lab work 2's report list (the manual, "Оформление отчета", its bullets counted from 1):
part 1 the wear test, part 2 the adhesive against the oxidative test (items 12-14)."""

from __future__ import annotations

from rigserver.reports.contents import Contents, Item, Students
from rigserver.reports.contents.common import opening
from rigserver.reports.i18n import MESSAGES
from schemas.messages import N_

CONTENTS = Contents(
    tasks=(
        N_("Learn the purpose, design and principle of the SMTs-2 friction machine."),
        N_("Learn the order of work in testing the specimens."),
        N_(
            "Learn the experimental and the theoretical methods of finding the fatigue wear "
            "intensity and the wear."
        ),
        N_(
            "Test two steel specimens and find their wear and fatigue wear intensity in dry "
            "friction by experiment."
        ),
        N_(
            "Compute the theoretical wear intensity and wear for the test's conditions and "
            "compare them with the experiment."
        ),
        N_("Study the signs that tell oxidative from adhesive wear, by experiment and theory."),
        N_("Understand the fatigue mechanism of wear in friction."),
        N_("Write the report on A4 sheets."),
    ),
    items=(
        *opening("smts2"),
        Item(4, "эскиз образцов", N_("Sketch of the specimens"), students=Students.SKETCH),
        Item(
            5,
            "схему нагружения образцов (рис. 2.3)",
            N_("Loading scheme of the specimens (fig. 2.3)"),
            students=Students.SKETCH,
        ),
        Item(
            6,
            "название испытательного оборудования, инструмента и приборов",
            words=(MESSAGES["stand.smts2"],),
        ),
        Item(
            7,
            "исходные данные для расчета теоретического значения интенсивности изнашивания",
            tables=("caption.configuration",),
        ),
        Item(
            8,
            "результаты эксперимента",
            formulas=("2.8", "2.12"),
            tables=("caption.measurements", "w.record"),
            figures=("w.fig_friction",),
        ),
        Item(
            9,
            "расчет теоретического значения линейной интенсивности изнашивания",
            formulas=("2.1", "2.2", "2.3", "2.4", "2.5", "2.6", "2.7"),
            tables=("w.theoretical",),
        ),
        Item(
            10,
            "расчет экспериментального значения линейной интенсивности изнашивания",
            formulas=("2.9", "2.10", "2.11", "2.13"),
            tables=("w.experimental",),
        ),
        Item(
            11,
            "сравнение теоретического и экспериментального значений интенсивности (п. 18)",
            formulas=("2.14", "2.15"),
            tables=("w.adequacy",),
            figures=("w.fig_wear_band|w.fig_wear",),
        ),
        Item(
            12,
            "описание наблюдений при адгезионном характере износа",
            N_("Observations of adhesive wear"),
            students=Students.OBSERVATIONS,
            part=2,
        ),
        Item(
            13,
            "описание наблюдения при окислительном характере износа",
            N_("Observations of oxidative wear"),
            students=Students.OBSERVATIONS,
            part=2,
        ),
        Item(
            14,
            "сравнение коэффициентов трения при окислительном и адгезионном износах",
            formulas=("2.16",),
            part=2,
        ),
        Item(
            15,
            "выводы по полученным результатам и наблюдениям",
            N_("Conclusions from the results and the observations"),
            students=Students.CONCLUSIONS,
        ),
    ),
)
