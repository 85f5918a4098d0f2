"""English and Russian (the lab's language) for the reports and pages.

:data:`MESSAGES` maps a message id to its English and Russian text (a tuple, so neither
can be missing); :data:`UNIT_LABELS` does the same for every unit symbol of
:mod:`schemas.units`. :func:`negotiate` picks the language from ``?lang=`` or the
``Accept-Language`` header.
"""

from __future__ import annotations

from typing import Literal, get_args

from markupsafe import Markup

Lang = Literal["en", "ru"]
LANGS: tuple[Lang, ...] = get_args(Lang)
DEFAULT: Lang = "en"


def negotiate(requested: str | None, accept_language: str | None) -> Lang:
    """The report's language: ``requested`` if given, else the best of ``Accept-Language``.

    ``Accept-Language: ru-RU,ru;q=0.9,en;q=0.8`` gives ``"ru"``; a header naming no
    supported language (or none) gives English. ``requested`` must be a supported code
    (the routes check it).
    """
    if requested is not None:
        if requested not in LANGS:
            raise ValueError(f"lang must be one of {', '.join(LANGS)}, got {requested!r}")
        return requested
    ranked: list[tuple[float, int, str]] = []
    for position, item in enumerate((accept_language or "").split(",")):
        tag, _, params = item.strip().partition(";")
        quality = 1.0
        for param in params.split(";"):
            name, _, value = param.strip().partition("=")
            if name == "q":
                try:
                    quality = float(value)
                except ValueError:
                    quality = 0.0
        primary = tag.strip().split("-")[0].lower()
        if quality > 0 and primary in LANGS:
            ranked.append((-quality, position, primary))
    return min(ranked)[2] if ranked else DEFAULT  # type: ignore[return-value]


class Messages:
    """The texts of one language: ``t("sec.input")``, ``t("lab_work", n=2)``, ``t.unit("Pa")``."""

    def __init__(self, lang: Lang) -> None:
        self.lang = lang
        self._index = LANGS.index(lang)

    def __call__(self, key: str, **values: object) -> str:
        return MESSAGES[key][self._index].format(**values)

    def markup(self, key: str, **values: object) -> Markup:
        """A message that holds markup (``<sub>``), with the values escaped."""
        return Markup(MESSAGES[key][self._index]).format(**values)

    def channel(self, name: str, long_name: str) -> str:
        """A single measurement's name: the schema's ``long_name``, or its Russian."""
        return long_name if self.lang == "en" else CHANNELS_RU[name]

    def unit(self, symbol: str) -> str:
        """A unit as printed: ``Pa*s`` -> ``Pa·s`` (``Па·с``); dimensionless -> ``—``."""
        return UNIT_LABELS[symbol][self._index]


UNIT_LABELS: dict[str, tuple[str, str]] = {
    "1": ("—", "—"),
    "s": ("s", "с"),
    "min": ("min", "мин"),
    "N": ("N", "Н"),
    "N*m": ("N·m", "Н·м"),
    "kg": ("kg", "кг"),
    "g": ("g", "г"),
    "mg": ("mg", "мг"),
    "m": ("m", "м"),
    "mm": ("mm", "мм"),
    "um": ("μm", "мкм"),
    "rad": ("rad", "рад"),
    "deg": ("°", "°"),
    "rev": ("rev", "об"),
    "100 rev": ("100 rev", "100 об"),
    "rpm": ("rpm", "об/мин"),
    "rad/s": ("rad/s", "рад/с"),
    "Pa": ("Pa", "Па"),
    "MPa": ("MPa", "МПа"),
    "at": ("at", "ат"),
    "atm": ("atm", "атм"),
    "Pa*s": ("Pa·s", "Па·с"),
    "degC": ("°C", "°C"),
    "1/degC": ("1/°C", "1/°C"),
    "kg/m^3": ("kg/m³", "кг/м³"),
    "N/mm": ("N/mm", "Н/мм"),
    "N/m": ("N/m", "Н/м"),
    "m^2": ("m²", "м²"),
    "m^3": ("m³", "м³"),
    "mm^3": ("mm³", "мм³"),
    "m^2/N": ("m³/(N·m)", "м³/(Н·м)"),
    "mm^3/(N*m)": ("mm³/(N·m)", "мм³/(Н·м)"),
    "1/m": ("1/m", "1/м"),
    "m/N": ("m/N", "м/Н"),
    "m/N^(2/3)": ("m/N^(2/3)", "м/Н^(2/3)"),
    "N*m/rad": ("N·m/rad", "Н·м/рад"),
    "N*m*s/rad": ("N·m·s/rad", "Н·м·с/рад"),
    "drops/min": ("drops/min", "кап./мин"),
    "div": ("div", "дел."),
    "code": ("code", "код"),
    "%": ("%", "%"),
}

CHANNELS_RU: dict[str, str] = {
    "pin_mass_before": "m1, масса образца до испытания (2.9)",
    "pin_mass_after": "m2, масса образца после испытания (2.9)",
    "disc_ra": "Ra диска по профилометру (2.6)",
    "load_zone_end": "φ_k, угол по лимбу в конце несущей зоны (3.20)",
    "x_zero": "X_уст, начальная установка датчика X",
    "y_zero": "Y_уст, начальная установка датчика Y",
    "loader_scale": "показание указателя нагружателя (16,2 Н/мм)",
    "base_length": "l, базовая длина",
    "subrange": "верхняя граница поддиапазона Ra (1.14)",
}
"""Russian names of the single measurements (the English is the schema's ``long_name``)."""

MESSAGES: dict[str, tuple[str, str]] = {
    # --- the heading and the run ----------------------------------------------------------
    "lab_work": ("Lab work {n}", "Лабораторная работа № {n}"),
    "report": ("Report", "Отчёт"),
    "aim": ("Aim", "Цель работы"),
    "title.profilometer": (
        "Experimental and theoretical determination of the parameters of equilibrium roughness",
        "Экспериментальное и теоретическое определение основных параметров равновесной "
        "шероховатости",
    ),
    "title.smts2": (
        "Experimental and theoretical study of wear in sliding under dry friction",
        "Экспериментальное и теоретическое изучение износа при скольжении в условиях режима "
        "сухого трения",
    ),
    "title.slide_bearing": (
        "Experimental and theoretical hydrodynamic pressure diagrams of a slide bearing",
        "Экспериментальное и теоретическое построение эпюр гидродинамического давления в опоре "
        "скольжения",
    ),
    "title.mtos": ("Friction in slide bearings", "Изучение трения в опорах скольжения"),
    "aim.profilometer": (
        "To study the equipment and the methods of measuring and computing the roughness "
        "parameters of a run-in surface.",
        "Изучить оборудование, методики измерения и расчёта основных параметров шероховатости "
        "приработанной поверхности.",
    ),
    "aim.smts2": (
        "To study the experimental and theoretical methods of finding the linear wear "
        "intensity in sliding of a pin on a disc.",
        "Изучить экспериментальную и теоретическую методики определения линейной интенсивности "
        "изнашивания при скольжении для образцов типа диск-стержень.",
    ),
    "aim.slide_bearing": (
        "To study the experimental and theoretical methods of finding the hydrodynamic "
        "pressure along the angle and the axis of a bearing, and to compare them.",
        "Изучить экспериментальную и теоретические методики определения эпюр гидродинамического "
        "давления по угловой и осевой координате. Сравнить результаты опытов с расчётами.",
    ),
    "aim.mtos": (
        "To study the experimental and theoretical methods of finding the friction "
        "coefficient of a slide bearing in fluid, mixed and boundary lubrication.",
        "Изучить экспериментальную и теоретическую методики определения коэффициента трения в "
        "опорах скольжения при жидкостной, полужидкостной и граничной смазке.",
    ),
    "stand.smts2": ("SMTs-2 friction and wear machine", "Машина трения СМЦ-2"),
    "stand.slide_bearing": ("Slide-bearing stand", "Стенд «Опора скольжения»"),
    "stand.mtos": ("MTOS stand", "Стенд «МТОС»"),
    "stand.profilometer": ("ABRIS-PM7 profilometer", "Профилограф-профилометр АБРИС-ПМ7"),
    "run": ("Run", "Испытание"),
    "stand": ("Stand", "Стенд"),
    "state": ("State", "Состояние"),
    "operator": ("Operator", "Оператор"),
    "run_title": ("Title", "Название"),
    "specimen": ("Specimen", "Образцы"),
    "test_plan": ("Test plan", "Программа испытания"),
    "created": ("Started", "Начато"),
    "ended": ("Ended", "Окончено"),
    "rows": ("Rows stored", "Сохранено строк"),
    "notes": ("Notes", "Примечания"),
    "state.open": ("open", "идёт"),
    "state.finished": ("finished", "завершено"),
    "state.aborted": ("aborted", "прервано"),
    "open_warning": (
        "The run is still open: the results are computed on the readings received so far.",
        "Испытание ещё идёт: результаты рассчитаны по полученным на данный момент показаниям.",
    ),
    "footer": (
        "Made by rig from run {run} at {time} UTC.",
        "Сформировано rig по испытанию {run} {time} UTC.",
    ),
    # --- sections and columns -------------------------------------------------------------
    "sec.input": ("Input data", "Исходные данные"),
    "sec.measured": ("Results of the measurements", "Результаты измерений"),
    "sec.processed": ("Processing and theory", "Обработка результатов и расчёт"),
    "sec.plots": ("Plots", "Графики"),
    "sec.conclusions": ("Conclusions", "Выводы"),
    "sec.pending": ("Not computed yet", "Ещё не рассчитано"),
    "sec.notes": ("Notes of the analysis", "Замечания расчёта"),
    "caption.configuration": (
        "Stand configuration of this run: calibration, geometry, materials",
        "Конфигурация стенда в этом испытании: градуировка, геометрия, материалы",
    ),
    "caption.measurements": ("Single measurements", "Отдельные измерения"),
    "col.parameter": ("Parameter", "Параметр"),
    "col.description": ("Description", "Описание"),
    "col.quantity": ("Quantity", "Величина"),
    "col.symbol": ("Symbol", "Обозначение"),
    "col.value": ("Value", "Значение"),
    "col.unit": ("Unit", "Ед."),
    "col.channel": ("Channel", "Канал"),
    "col.instrument_error": ("Instrument error (1.14)", "Погрешность прибора (1.14)"),
    "col.method": ("Method", "Метод"),
    "col.level": ("Level", "Сечение"),
    "col.regime": ("Regime", "Режим"),
    "col.film": ("Film (seed 001)", "Плёнка (по h_min^кр)"),
    "mean": ("Mean", "Среднее"),
    "sym.i_exp": ("I_{{h,exp}}", "I_{{h,эксп}}"),
    "sym.i_theor": ("I_{{h,theor}}", "I_{{h,теор}}"),
    "yes": ("yes", "да"),
    "no": ("no", "нет"),
    "regime.fluid": ("fluid film", "жидкостная"),
    "regime.mixed": ("mixed", "полужидкостная"),
    "regime.boundary": ("boundary", "граничная"),
    "regime.full film": ("full film", "жидкостная"),
    "col.film_lambda": ("Regime by Λ", "Режим по Λ"),
    "u.caption": (
        "Measurement uncertainty (GUM): value ± expanded uncertainty U = 2u (k = 2)",
        "Неопределённость измерений (GUM): значение ± расширенная неопределённость U = 2u (k = 2)",
    ),
    "u.step": (", step {i}, N = {load} N", ", шаг {i}, N = {load} Н"),
    "m.chi": ("eccentricity ratio (4.11)", "относительный эксцентриситет (4.11)"),
    "m.f_measured": ("friction coefficient (4.16)", "коэффициент трения (4.16)"),
    "m.disagree": (
        "Where the film criteria name another regime than the experiment's oil feed: {items}.",
        "Где критерии плёнки называют иной режим, чем подача масла в опыте: {items}.",
    ),
    "b.attitude": ("attitude angle ψ from X, Y", "угол положения линии центров ψ по X, Y"),
    "b.rupture": (
        "rupture of the finite film past the thinnest film",
        "разрыв плёнки конечного подшипника за минимальным зазором",
    ),
    "contact.elastic": ("elastic", "упругий"),
    "contact.plastic": ("plastic", "пластический"),
    # --- the web pages --------------------------------------------------------------------
    "page.runs": ("Runs", "Испытания"),
    "page.series": ("Series", "Серии"),
    "page.login": ("Log in", "Вход"),
    "page.login_why": (
        "The pages show the runs to holders of a key with the scope read.",
        "Страницы показывают испытания владельцам ключа с правом read.",
    ),
    "page.login_refused": (
        "This key is not known to the server or may not read.",
        "Сервер не знает этот ключ, или ключ не даёт права чтения.",
    ),
    "page.key": ("API key", "Ключ API"),
    "page.logout": ("Log out", "Выйти"),
    "page.all": ("all", "все"),
    "page.since": ("from", "с"),
    "page.until": ("to", "по"),
    "page.apply": ("Show", "Показать"),
    "page.reset": ("Reset", "Сбросить"),
    "page.key_result": ("Key results", "Основные результаты"),
    "page.none": ("No run matches.", "Испытаний не найдено."),
    "page.damaged": ("damaged", "повреждено"),
    "page.newer": ("← newer", "← новее"),
    "page.older": ("older →", "старше →"),
    "page.shown": ("{first}–{last} of {total}", "{first}–{last} из {total}"),
    "page.back": ("All runs", "Все испытания"),
    "page.live": ("Readings as they arrive", "Показания по мере поступления"),
    "page.channel": ("Channel", "Канал"),
    "page.rows_received": ("rows received", "строк получено"),
    "page.connecting": ("connecting…", "подключение…"),
    "page.streaming": ("live", "в реальном времени"),
    "page.reconnecting": ("connection lost, reconnecting…", "связь потеряна, переподключение…"),
    "page.ended": ("run ended", "испытание окончено"),
    "page.results": ("Results", "Результаты"),
    "page.results_note": (
        "While the run is open, computed on the readings so far and refreshed every 5 s.",
        "Пока испытание идёт, рассчитываются по полученным показаниям и обновляются каждые 5 с.",
    ),
    "page.downloads": ("Downloads", "Скачать"),
    "page.report_html": ("Report, web page", "Отчёт, веб-страница"),
    "page.report_pdf": ("Report, PDF (A4)", "Отчёт, PDF (A4)"),
    "page.readings_csv": ("Readings, CSV", "Показания, CSV"),
    "page.results_csv": ("Results, CSV", "Результаты, CSV"),
    "page.zip": ("Everything, zip of CSV and JSON", "Всё, zip с CSV и JSON"),
    "page.hdf5": ("Run file, HDF5", "Файл испытания, HDF5"),
    "page.language": ("Русский", "English"),
    # --- lab work 1: profilometer ---------------------------------------------------------
    "p.params": (
        "Roughness parameters over the base length (1.1)-(1.4)",
        "Параметры шероховатости на базовой длине (1.1)-(1.4)",
    ),
    "p.base_length": ("base length", "базовая длина"),
    "p.ra": ("arithmetic mean deviation (1.3)", "среднее арифметическое отклонение (1.3)"),
    "p.rq": ("root-mean-square deviation", "среднее квадратическое отклонение"),
    "p.rz": ("ten-point height (1.4)", "высота неровностей по десяти точкам (1.4)"),
    "p.rmax": ("peak line to valley line", "от линии выступов до линии впадин"),
    "p.sm": ("mean spacing of profile elements", "средний шаг неровностей"),
    "p.r": ("mean asperity radius (1.1, E5)", "средний радиус выступов (1.1, E5)"),
    "p.table_1_6": (
        "Table 1.6. Bearing length of the profile at the levels p_i below the peak line",
        "Таблица 1.6. Опорная длина профиля в i-х сечениях",
    ),
    "p.table_1_7": (
        "Table 1.7. Coefficients ν and b of t_p = b·ε^ν (1.16)-(1.19)",
        "Таблица 1.7. Коэффициенты ν и b аппроксимирующей формулы (1.16)-(1.19)",
    ),
    "p.table_1_8": (
        "Table 1.8. Measured t_pэ against t_pт = b·ε^ν (manual method)",
        "Таблица 1.8. Сравнение теоретических t_pт и экспериментальных t_pэ",
    ),
    "p.manual": ("three pairs of levels (1.16)-(1.19)", "по трём парам сечений (1.16)-(1.19)"),
    "p.lsq": ("least squares in log-log", "метод наименьших квадратов (лог. оси)"),
    "p.complex": (
        "Complex roughness parameter (1.9)-(1.11)",
        "Комплексный параметр шероховатости (1.9)-(1.11)",
    ),
    "p.delta": ("complex parameter (1.9)", "комплексный параметр (1.9)"),
    "p.ra_delta": ("Ra from Δ (1.10)", "Ra по Δ (1.10)"),
    "p.delta_t": (
        "equilibrium complex parameter (1.11)",
        "комплексный параметр равновесной шероховатости (1.11)",
    ),
    "p.fig_profile": (
        "Profile with the mean line, the peak line and the valley line",
        "Профилограмма со средней линией, линией выступов и линией впадин",
    ),
    "p.fig_bearing": (
        "Initial part of the bearing curve and the fits t_p = b·ε^ν (fig. 1.5)",
        "Начальный участок кривой опорной поверхности и аппроксимация t_p = b·ε^ν (рис. 1.5)",
    ),
    "p.profile": ("profile", "профиль"),
    "p.mean_line": ("mean line", "средняя линия"),
    "p.peak_line": ("peak line", "линия выступов"),
    "p.valley_line": ("valley line", "линия впадин"),
    "p.measured": ("measured", "эксперимент"),
    "p.c_ra": (
        "Ra = {ra} m measured; Ra = 4.3·Δ^(1/2) = {ra_delta} m from the complex parameter "
        "(1.10), {diff} % apart.",
        "Ra = {ra} м по профилю; по комплексному параметру Ra = 4,3·Δ^(1/2) = {ra_delta} м "
        "(1.10), расхождение {diff} %.",
    ),
    "p.c_delta": (
        "Δ = {delta} from the profile against Δ_T = {delta_t} for the equilibrium roughness "
        "(1.11): {diff} % apart.",
        "Δ = {delta} по профилю и Δ_T = {delta_t} для равновесной шероховатости (1.11): "
        "расхождение {diff} %.",
    ),
    "p.c_fit": (
        "t_p = b·ε^ν: ν = {nu}, b = {b} by three pairs of levels, ν = {nu_lsq}, b = {b_lsq} by "
        "least squares; the largest |Δt_p| is {residual}.",
        "t_p = b·ε^ν: ν = {nu}, b = {b} по трём парам сечений, ν = {nu_lsq}, b = {b_lsq} методом "
        "наименьших квадратов; наибольшее |Δt_p| = {residual}.",
    ),
    # --- lab work 2: SMTs-2 ---------------------------------------------------------------
    "w.record": ("Friction record", "Запись момента трения"),
    "w.rows": ("rows analysed", "обработано строк"),
    "w.duration": ("duration", "продолжительность"),
    "w.revolutions": ("disc revolutions", "число оборотов диска"),
    "w.sliding": ("sliding distance (2.12)", "путь трения (2.12)"),
    "w.load": ("mean load, steady part", "средняя нагрузка, установившийся участок"),
    "w.f": ("friction coefficient, steady part (2.8)", "коэффициент трения, уст. участок (2.8)"),
    "w.f_std": ("its standard deviation", "его среднее квадратическое отклонение"),
    "w.steady_from": ("steady part from", "начало установившегося участка"),
    "w.experimental": (
        "Experimental linear wear intensity (2.9)-(2.13)",
        "Экспериментальная линейная интенсивность изнашивания (2.9)-(2.13)",
    ),
    "w.mass_loss": ("mass loss of the pin (2.9)", "потеря массы образца (2.9)"),
    "w.volume": ("worn volume (2.10)", "объём изношенного материала (2.10)"),
    "w.depth": ("linear wear (2.11)", "линейный износ (2.11)"),
    "w.intensity_exp": ("wear intensity (2.13)", "интенсивность изнашивания (2.13)"),
    "w.theoretical": (
        "Theoretical linear wear intensity, fatigue wear (2.1)-(2.7)",
        "Теоретическая линейная интенсивность изнашивания, усталостный износ (2.1)-(2.7)",
    ),
    "w.contact": ("contact mode (2.7)", "вид контакта (2.7)"),
    "w.fatigue_t": ("fatigue parameter t", "параметр фрикционной усталости t"),
    "w.pc": ("contour pressure (2.3)", "контурное давление (2.3)"),
    "w.aa": ("nominal area (2.5)", "номинальная площадь (2.5)"),
    "w.ac": ("contour area (2.4)", "контурная площадь (2.4)"),
    "w.eta_c": ("A_c/A_a", "A_c/A_a"),
    "w.delta": ("complex parameter of the disc (2.6, E2)", "комплексный параметр диска (2.6, E2)"),
    "w.rmax_r": ("Rmax/R", "Rmax/R"),
    "w.C": ("C of (2.1)", "C в (2.1)"),
    "w.beta": ("β = 1/(1 + 2ν)", "β = 1/(1 + 2ν)"),
    "w.k_nu": ("k_ν of (2.1)", "k_ν в (2.1)"),
    "w.k_f": ("k_f of the contact mode", "k_f для вида контакта"),
    "w.intensity_theor": ("wear intensity (2.1)", "интенсивность изнашивания (2.1)"),
    "w.adequacy": (
        "Theory against experiment (2.14)-(2.15)",
        "Сравнение теории и опыта (2.14)-(2.15)",
    ),
    "w.error": ("relative difference (2.14)", "относительное расхождение (2.14)"),
    "w.lower": ("lower bound 0.4·I_{{h,theor}} (2.15)", "нижняя граница 0,4·I_{{h,теор}} (2.15)"),
    "w.upper": ("upper bound 2.6·I_{{h,theor}} (2.15)", "верхняя граница 2,6·I_{{h,теор}} (2.15)"),
    "w.adequate": ("model adequate (2.15)", "модель адекватна (2.15)"),
    "w.fig_friction": (
        "Friction coefficient against the sliding distance; the running-in part is shaded",
        "Коэффициент трения в зависимости от пути трения; участок приработки затенён",
    ),
    "w.fig_wear": (
        "Experimental and theoretical wear intensity with the adequacy band (2.15)",
        "Экспериментальная и теоретическая интенсивность изнашивания и интервал (2.15)",
    ),
    "w.running_in": (
        "running-in: first {share} % of the record, not averaged",
        "приработка: первые {share} % записи, не усредняются",
    ),
    "w.steady_mean": ("steady mean", "среднее на установившемся участке"),
    "w.envelope": ("min-max per block", "мин.-макс. по блокам"),
    "w.block_mean": ("block means", "средние по блокам"),
    "w.band": ("0.4·I_theor … 2.6·I_theor (2.15)", "0,4·I_теор … 2,6·I_теор (2.15)"),
    "w.exp": ("experiment", "эксперимент"),
    "w.theor": ("theory (2.1)", "теория (2.1)"),
    "w.c_friction": (
        "Steady friction coefficient f = {f} ± {std} (from t = {t} s, load {load} N).",
        "Установившийся коэффициент трения f = {f} ± {std} (с t = {t} с, нагрузка {load} Н).",
    ),
    "w.c_adequate": (
        "I_{{h,exp}} = {exp} lies within 0.4·I_{{h,theor}} … 2.6·I_{{h,theor}} = "
        "{lower} … {upper} (I_{{h,theor}} = {theor}, {contact} contact): the model (2.1) is "
        "adequate (2.15).",
        "I_{{h,эксп}} = {exp} лежит в интервале 0,4·I_{{h,теор}} … 2,6·I_{{h,теор}} = "
        "{lower} … {upper} (I_{{h,теор}} = {theor}, контакт {contact}): модель (2.1) "
        "адекватна (2.15).",
    ),
    "w.c_inadequate": (
        "I_{{h,exp}} = {exp} lies outside 0.4·I_{{h,theor}} … 2.6·I_{{h,theor}} = "
        "{lower} … {upper} (I_{{h,theor}} = {theor}, {contact} contact; ΔI_h = {error} %): "
        "the model (2.1) is not adequate to this test (2.15).",
        "I_{{h,эксп}} = {exp} вне интервала 0,4·I_{{h,теор}} … 2,6·I_{{h,теор}} = "
        "{lower} … {upper} (I_{{h,теор}} = {theor}, контакт {contact}; ΔI_h = {error} %): "
        "модель (2.1) неадекватна этому опыту (2.15).",
    ),
    "w.k": (
        "specific wear rate k = V/(F·L) (ASTM G99)",
        "удельная интенсивность изнашивания k = V/(F·L) (ASTM G99)",
    ),
    "w.disc_wear": (
        "Wear of the disc from a profile across its track (ASTM G99)",
        "Износ диска по профилограмме поперёк дорожки трения (ASTM G99)",
    ),
    "w.track_area": ("cross-section area of the track", "площадь сечения дорожки"),
    "w.disc_volume": ("worn volume of the disc", "объём износа диска"),
    "w.validity": (
        "Validity of the fatigue-wear theory (2.1) (docs/validity.md)",
        "Применимость усталостной теории изнашивания (2.1) (docs/validity.md)",
    ),
    "w.within_range": ("theory within its range", "теория в своей области применимости"),
    "w.approach": ("relative approach ε", "относительное сближение ε"),
    "w.eta_r": ("real contact area over contour area", "отношение фактической площади к контурной"),
    "w.pr": ("real-contact pressure", "фактическое давление на пятнах контакта"),
    "w.hb": ("hardness of the pin HB", "твёрдость образца HB"),
    "w.sigma": ("asperity stress k_f·p_r", "напряжение на неровности k_f·p_r"),
    "w.sigma0": ("fatigue strength σ0", "параметр усталости σ0"),
    "w.cycles": ("cycles to failure per asperity", "число циклов до разрушения неровности"),
    "w.kf_plastic": ("k_f^n of the plastic branch", "k_f^n пластического контакта"),
    "w.sensitivity": (
        "Sensitivity of I_h (2.1) to t and σ0/σ_B",
        "Чувствительность I_h (2.1) к t и σ0/σ_B",
    ),
    "w.c_outside": (
        "The fatigue-wear theory (2.1) is outside its range for this test, so (2.15) is not "
        "judged: {reasons}.",
        "Теория усталостного изнашивания (2.1) вне области применимости для этого опыта, "
        "поэтому (2.15) не оценивается: {reasons}.",
    ),
    # --- lab work 3: slide-bearing stand --------------------------------------------------
    "b.table_3_1": (
        "Table 3.1. Hydrodynamic pressure along the angle at z = 0, and its processing",
        "Таблица 3.1. Распределение ГДД по угловой координате φ при z = 0. Результаты обработки",
    ),
    "b.oil": ("Oil and bearing (3.21)-(3.24)", "Масло и подшипник (3.21)-(3.24)"),
    "b.load": ("load from the loader scale", "нагрузка по указателю нагружателя"),
    "b.temperature": ("mean oil temperature (3.21)", "средняя температура масла (3.21)"),
    "b.viscosity": ("oil viscosity (3.21)", "вязкость масла (3.21)"),
    "b.mu_bar": ("dimensionless viscosity (3.22)", "безразмерная вязкость (3.22)"),
    "b.chi_mean": ("mean eccentricity ratio (3.23)", "среднее значение χ (3.23)"),
    "b.half_width": ("relative half-width (3.24, E3)", "относительная полуширина (3.24, E3)"),
    "b.phi_max": ("angle of the largest pressure", "угол максимального давления"),
    "b.p_max": ("largest pressure", "максимальное давление"),
    "b.table_3_2": (
        "Table 3.2. Pressure along the axis at φ = {phi}°, the angle of the largest pressure",
        "Таблица 3.2. Распределение ГДД по осевой координате z при φ = {phi}°",
    ),
    "b.edges": (
        "Π = 0 at the edges z = ±a = ±{a}.",
        "Π = 0 на торцах z = ±a = ±{a}.",
    ),
    "b.table_3_3": (
        "Table 3.3. Π along the angle at z = 0: short bearing Π_0, long bearing Π_∞, finite "
        "bearing, measured Π_э",
        "Таблица 3.3. ГДД по угловой координате при z = 0: короткая опора Π_0, без торцового "
        "истечения Π_∞, конечная опора, эксперимент Π_э",
    ),
    "b.fig_phi": (
        "Dimensionless pressure Π against the angle φ at z = 0 (3.28)",
        "Безразмерное давление Π по углу φ при z = 0 (3.28)",
    ),
    "b.fig_z": (
        "Dimensionless pressure Π against z at the angle of the largest pressure (3.29)",
        "Безразмерное давление Π по оси z при угле максимального давления (3.29)",
    ),
    "b.measured": ("measured Π_э", "эксперимент Π_э"),
    "b.short": ("short bearing Π_0 (3.12)", "короткая опора Π_0 (3.12)"),
    "b.long": ("long bearing Π_∞ (3.15)", "без торцового истечения Π_∞ (3.15)"),
    "b.finite": ("finite bearing (3.1)", "конечная опора (3.1)"),
    "b.c_chi": (
        "Mean eccentricity ratio χ_ср = {chi}; the largest pressure {p} Pa at φ = {phi}°.",
        "Средний относительный эксцентриситет χ_ср = {chi}; максимальное давление {p} Па при "
        "φ = {phi}°.",
    ),
    "b.c_errors": (
        "Mean |ΔΠ_0| = {short} % (short bearing), mean |ΔΠ_∞| = {long} % (long bearing) over "
        "the rows where the theory is not zero.",
        "Среднее |ΔΠ_0| = {short} % (короткая опора), среднее |ΔΠ_∞| = {long} % (без торцового "
        "истечения) по строкам, где теория не равна нулю.",
    ),
    "b.c_axial": (
        "Along z at φ = {phi}°: mean |ΔΠ| = {error} % against the short bearing (3.25).",
        "По оси z при φ = {phi}°: среднее |ΔΠ| = {error} % относительно короткой опоры (3.25).",
    ),
    # --- lab work 4: MTOS -----------------------------------------------------------------
    "m.raw": (
        "Table 4.{n}. Readings, experiment {n} ({regime})",
        "Таблица 4.{n}. Показания, опыт № {n} ({regime})",
    ),
    "m.film": (
        "Film thickness (seed 001) and headline results",
        "Толщина смазочного слоя и основные результаты",
    ),
    "m.h_crit": ("h_min^crit, sum of the five terms", "h_min^кр, сумма пяти слагаемых"),
    "m.half_width": ("a = B/D (E3)", "a = B/D (E3)"),
    "m.h_min_smallest": ("smallest h_min of the run", "наименьшая h_min испытания"),
    "m.friction_fluid": ("mean f_э, fluid film", "среднее f_э, жидкостная смазка"),
    "m.processed": (
        "Table 4.{table}. Processing, experiment {n} ({regime})",
        "Таблица 4.{table}. Результаты обработки, опыт № {n} ({regime})",
    ),
    "m.continued": ("continued", "продолжение"),
    "m.theory": (
        "Table 4.4, end. Theory (4.1)-(4.10) and the finite bearing (3.1) beside the experiment",
        "Окончание таблицы 4.4. Теория (4.1)-(4.10) и конечная опора (3.1) рядом с опытом",
    ),
    "m.ratio_note": (
        "f_э/f_э1: against experiment 1 at the same load.",
        "f_э/f_э1: по отношению к опыту № 1 при той же нагрузке.",
    ),
    "m.fig_stribeck": (
        "Hersey-Stribeck diagram: f against S_1 = μ_t·ω/p̄ (4.21, E9)",
        "Диаграмма Герси-Штрибека: f в зависимости от S_1 = μ_t·ω/p̄ (4.21, E9)",
    ),
    "m.fig_trajectory": (
        "Journal-centre trajectory and the Gümbel semicircle",
        "Траектория центра шипа и полуокружность Гюмбеля",
    ),
    "m.fig_friction": (
        "Friction coefficient against the load, three regimes",
        "Коэффициент трения в зависимости от нагрузки для трёх режимов",
    ),
    "m.fig_temperature": (
        "Temperature rise of the oil against the load (4.19, E4)",
        "Прирост температуры масла в зависимости от нагрузки (4.19, E4)",
    ),
    "m.f_exp": ("f_э, {regime}", "f_э, {regime}"),
    "m.f_theory": ("f_T (4.10)", "f_T (4.10)"),
    "m.f_finite": ("finite bearing (3.1)", "конечная опора (3.1)"),
    "m.h_min_mark": ("h_min = h_0 - e_max = {h} m", "h_min = h_0 - e_max = {h} м"),
    "m.clearance": ("clearance circle h_0", "окружность зазора h_0"),
    "m.gumbel": ("Gümbel semicircle", "полуокружность Гюмбеля"),
    "m.c_friction": (
        "Fluid film: f_э = {f_min} … {f_max}, mean |Δf| = {error} % against f_T (4.10).",
        "Жидкостная смазка: f_э = {f_min} … {f_max}, среднее |Δf| = {error} % относительно "
        "f_T (4.10).",
    ),
    "m.c_regime": (
        "{regime}: f_э = {f_min} … {f_max}.",
        "{regime}: f_э = {f_min} … {f_max}.",
    ),
    "m.c_film": (
        "h_min is below h_min^crit = {h_crit} m at {count} of {total} steps (no fluid film).",
        "h_min меньше h_min^кр = {h_crit} м на {count} из {total} ступеней (режим не жидкостный).",
    ),
}
