"""Lab work 1's report list (the manual, "Оформление отчета", its bullets counted from 1)."""

from __future__ import annotations

from rigserver.reports.contents import Contents, Item, Students
from rigserver.reports.contents.common import opening
from schemas.messages import N_

CONTENTS = Contents(
    tasks=(
        N_("Learn the purpose, design and principle of the ABRIS-PM7 profilograph-profilometer."),
        N_("Learn how to take a profilogram of a specimen's surface and to measure its R_a."),
        N_(
            "Learn how a profilogram is processed into the main roughness parameters and the "
            "bearing curve."
        ),
        N_("Take a profilogram of the surface of an engine part's specimen."),
        N_("Process it: the parameters of the bearing curve, and its plot."),
        N_("Find R_z and R_a from the experiment."),
        N_("Find the mean radius of the asperities' tops from the profilogram."),
        N_("Write the report on A4 sheets."),
    ),
    items=(
        *opening("profilometer"),
        Item(4, "эскиз образца", N_("Sketch of the specimen"), students=Students.SKETCH),
        Item(
            5,
            "блок-схему профилографа-профилометра и принцип его работы",
            N_("Block diagram of the profilograph-profilometer and how it works"),
            students=Students.SKETCH,
        ),
        Item(6, "копию профилограммы и результаты ее обработки", figures=("p.fig_profile",)),
        Item(7, "режимы измерения", tables=("caption.measurements",)),
        Item(
            8,
            "горизонтальное и вертикальное увеличение",
            tables=("caption.configuration",),
            words=(
                "horizontal magnification of the profilogram",
                "vertical magnification of the profilogram",
            ),
        ),
        Item(
            9,
            "основные параметры R_z, R_max, привести их расчет по профилограмме",
            formulas=("1.3", "1.4"),
            tables=("p.params", "p.peaks"),
        ),
        Item(
            10,
            "построения для определения t_p = f(ε); табл. 1.6",
            formulas=("1.5", "1.6", "1.7"),
            tables=("p.table_1_6",),
        ),
        Item(
            11, "график t_p = f(ε), подобно рис. 1.5", formulas=("1.8",), figures=("p.fig_bearing",)
        ),
        Item(
            12,
            "формулы расчета ν и b и результаты расчетов в форме табл. 1.7",
            formulas=("1.16", "1.17", "1.18", "1.19"),
            tables=("p.table_1_7",),
        ),
        Item(13, "t_pт и t_pэ и их разность Δt_p в форме табл. 1.8", tables=("p.table_1_8",)),
        Item(
            14,
            "сравнение R_a, R_z, R_max профилометра и профилограммы, погрешность в %",
            formulas=("1.20",),
            tables=("p.vs",),
        ),
        Item(15, "средний радиус кривизны выступов", formulas=("1.1",)),
        Item(16, "расчет комплексного параметра шероховатости Δ", formulas=("1.9", "1.10")),
        Item(
            17,
            "расчет Δ_T по заданным исходным данным и результат их сравнения",
            formulas=("1.11", "1.12"),
            tables=("p.complex",),
        ),
        Item(
            18,
            "выводы по анализу результатов работы",
            N_("Conclusions from the analysis of the results"),
            students=Students.CONCLUSIONS,
        ),
    ),
)
