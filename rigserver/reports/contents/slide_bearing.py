"""Lab work 3's report list (the manual, "Оформление отчета", items 1-9)."""

from __future__ import annotations

from rigserver.reports.contents import Contents, Item, Students
from rigserver.reports.contents.common import opening
from schemas.messages import N_

CONTENTS = Contents(
    tasks=(
        N_("Learn the purpose, design and principle of the slide-bearing stand."),
        N_("Learn the order of work in the tests."),
        N_(
            "Study the asymptotic models of a slide bearing: without end leakage (the "
            "infinitely long bearing) and the short bearing."
        ),
        N_(
            "Run the test and measure the hydrodynamic pressure along the angle φ and along "
            "the axis z."
        ),
        N_("Study and understand how the hydrodynamic pressure arises in a slide bearing."),
        N_(
            "Compute the pressure by the simplest hydrodynamic models and compare theory and "
            "experiment."
        ),
        N_("Write the report."),
    ),
    items=(
        *opening("slide_bearing", joint=True),
        Item(
            3,
            "формулы ГДД по моделям короткой опоры и без торцового истечения ((3.11), (3.14))",
            formulas=("3.11", "3.12", "3.14", "3.15"),
        ),
        Item(
            4,
            "основные геометрические размеры подшипника (рис. 3.5) и система координат (рис. 3.2)",
            N_("Main dimensions of the bearing (fig. 3.5) and the coordinate system (fig. 3.2)"),
            students=Students.SKETCH,
        ),
        Item(
            5,
            "результаты измерений: φ_k, температура масла, X_уст, Y_уст; ГДД (табл. 3.1, 3.2)",
            tables=("caption.measurements", "b.table_3_1", "b.table_3_2"),
        ),
        Item(
            6,
            "формулы (3.16-3.27), результаты и табл. 3.1, 3.2, 3.3",
            formulas=tuple(f"3.{n}" for n in range(16, 28)),
            tables=("b.table_3_3",),
        ),
        Item(
            7,
            "графики распределения ГДД по углу φ и осевой координате z",
            formulas=("3.28", "3.29"),
            figures=("b.fig_phi", "b.fig_z"),
        ),
        Item(
            8,
            "выводы: степень соответствия теории и эксперимента",
            N_("Conclusions: how well theory and experiment agree"),
            students=Students.CONCLUSIONS,
        ),
        Item(
            8,
            "причины несовпадения теории и опыта",
            N_("Reasons for the mismatch of theory and experiment"),
            students=Students.MISMATCH,
        ),
    ),
)
