"""Lab work 4's report list (the manual, "Оформление отчета", its bullets counted from 1;
the analysis of the graphs is item 6 of "Иллюстрация полученных результатов")."""

from __future__ import annotations

from rigserver.reports.contents import Contents, Item, Students
from rigserver.reports.contents.common import opening
from schemas.messages import N_

CONTENTS = Contents(
    tasks=(
        N_("Learn the purpose, design and principle of the MTOS stand (slide-bearing friction)."),
        N_("Learn the order of work in the tests."),
        N_("Study and understand how a journal bearing regulates itself in fluid lubrication."),
        N_("Build the Hersey-Stribeck diagram by experiment."),
        N_("Build the trajectory of the journal's centre in the bearing by experiment."),
        N_("Compare the theoretical and the measured friction coefficients."),
        N_("Write the report."),
    ),
    items=(
        *opening("mtos", joint=True),
        Item(
            3,
            "формулы для расчета теоретического значения коэффициента трения",
            formulas=tuple(f"4.{n}" for n in range(1, 11)),
        ),
        Item(4, "схема стенда МТОС", N_("Scheme of the MTOS stand"), students=Students.SKETCH),
        Item(
            5,
            "формулы для обработки результатов испытаний",
            formulas=tuple(f"4.{n}" for n in range(11, 22)),
        ),
        Item(6, "результаты измерений: табл. 4.1, 4.2, 4.3", tables=("4.1", "4.2", "4.3")),
        Item(
            7,
            "результаты обработки и теоретических расчетов: табл. 4.4-4.6",
            tables=("4.4", "4.5", "4.6"),
        ),
        Item(
            8,
            "графики по п.п. 1-4 раздела «Иллюстрация полученных результатов»",
            figures=("m.fig_stribeck", "m.fig_trajectory", "m.fig_friction", "m.fig_temperature"),
        ),
        Item(
            9,
            "анализ графиков п. 3 и п. 4, объяснение их поведения (п. 6 «Иллюстрации»)",
            N_("Analysis of the graphs and of their behaviour"),
            students=Students.ANALYSIS,
        ),
        Item(
            9,
            "причины несовпадения теоретического и экспериментального коэффициентов трения",
            N_("Reasons for the mismatch of theory and experiment"),
            students=Students.MISMATCH,
        ),
        Item(
            9,
            "выводы по работе: итог анализа, физическая суть изучаемых процессов",
            N_("Conclusions: the results summed up, the physics of the processes studied"),
            students=Students.CONCLUSIONS,
        ),
    ),
)
