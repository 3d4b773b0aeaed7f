"""Lab 2. Reducing the connecting-rod mass to the piston-pin and crank-pin axes.

The manual's chapter: the two-mass model (formulas 1–7), the weighing method (8, 9), the
swinging method (10) and the statistical shares (11, 12). :func:`reduce` fills the manual's
table, method × (l_shp, l_shk, m_shp, m_shk), with uncertainties, and from the swinging
periods also finds the rod's moment of inertia about its centre of mass and the residual of
the third equivalence condition.

Notation: index ``shp`` — the piston-pin (small) end, ``shk`` — the crank-pin (big) end;
l_shp, l_shk the distances of the centre of mass from those axes; l_sh = l_shp + l_shk.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 2 ("Приведение масс шатуна").
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from processing.diagnostics import IllConditionedWarning, InconsistentInputWarning, collect_notices
from processing.measurement import (AMPLITUDE, COUNT, GRAVITY, LENGTH, MASS, STOPWATCH, Field,
                                    Inputs, LabSpec, ReadingsTable, Section, bi,
                                    period_columns)
from processing.oscillations.oscillation import (check_amplitude, pendulum_period_factor,
                                                 period_from_total)
from processing.reporting.content import fmt_pm
from processing.reporting.figures import histogram, method_chart
from processing.result import (KEY, SIGNED, STRICTLY_POSITIVE, Figure, LabResult, Table, compare,
                               flag_estimates, result_values)
from processing.uncertainty import Measured, propagate
from processing.vision.video import MARKER_FIELDS, film_figures, filmed_times

KATER_CONDITION_LIMIT = 10.0
"""Condition number of formula (10) above which the swinging method is called ill-conditioned.
κ = 2/(1 − q) − 4 l_C l_D/l_CD², q = k²/(l_C l_D): ordinary rods (q ≈ 0.5) have κ ≈ 3; κ = 10
near q ≈ 0.83, where a hand-timed period (± 0.4 %) moves the centre of mass by 4 % of l_CD."""

STATISTICAL_SHARE = {"petrol": 0.25, "diesel": 0.30}
"""m_shp/m_sh by the manual's statistics, formula (12); the spread 0.2–0.3 of formula (11)
is taken as a rectangular ± 0.05."""


# ------------------------------------------------------------------------ formulas

def two_mass(m_sh, l_shp, l_shk):
    """Masses at the piston-pin and crank-pin axes, formulas (6) and (7).

    .. math:: m_{shp} = m_{sh}\\frac{l_{shk}}{l_{sh}}, \\qquad
              m_{shk} = m_{sh}\\frac{l_{shp}}{l_{sh}}, \\qquad l_{sh} = l_{shp} + l_{shk}

    Parameters
    ----------
    m_sh : float or ndarray
        Mass of the rod. [kg]
    l_shp, l_shk : float or ndarray
        Distances of the centre of mass from the piston-pin and crank-pin axes. [m]

    Returns
    -------
    m_shp, m_shk : float or ndarray
        [kg]

    Examples
    --------
    >>> two_mass(1.0, 0.12, 0.04)
    (0.25, 0.75)
    """
    l_sh = l_shp + l_shk
    return m_sh * l_shk / l_sh, m_sh * l_shp / l_sh


def weighing(R_A, m_sh, l_sh):
    """Centre of mass from the balance reading at the small end, formulas (8) and (9).

    .. math:: l_{shk} = \\frac{R_A}{G_{sh}} l_{sh}, \\qquad l_{shp} = \\Big(1 -
              \\frac{R_A}{G_{sh}}\\Big) l_{sh}

    Parameters
    ----------
    R_A : float or ndarray
        Balance reading under the small end, ΔG, as a mass. [kg]
    m_sh : float or ndarray
        Mass of the rod. [kg]
    l_sh : float or ndarray
        Distance between the piston-pin and crank-pin axes. [m]

    Returns
    -------
    l_shp, l_shk : float or ndarray
        [m]
    """
    share = R_A / m_sh
    return (1.0 - share) * l_sh, share * l_sh


def swinging(T_C, T_D, l_CD, g):
    """Distance of the centre of mass from the small-end prism edge, formula (10).

    .. math:: l_C = l_{CD}\\,\\frac{4\\pi^2 l_{CD} - T_D^2 g}{8\\pi^2 l_{CD} - (T_C^2 + T_D^2) g},
              \\qquad l_D = l_{CD} - l_C

    Parameters
    ----------
    T_C, T_D : float or ndarray
        Small-swing periods hung at the small end (C) and at the big end (D). [s]
    l_CD : float or ndarray
        Distance between the two prism edges. [m]
    g : float or ndarray
        Local acceleration of gravity. [m/s²]

    Returns
    -------
    l_C, l_D : float or ndarray
        [m]

    Notes
    -----
    From T² g/4π² = (k² + l²)/l for both pivots (k the radius of gyration about the centre
    of mass). Numerator and denominator are both proportional to l_C l_D − k²: at
    k² = l_C l_D the pivots are conjugate (Kater's reversible pendulum), T_C = T_D and the
    formula is 0/0. See :func:`condition_number`.
    """
    l_C = l_CD * (4 * np.pi**2 * l_CD - T_D**2 * g) / (8 * np.pi**2 * l_CD - (T_C**2 + T_D**2) * g)
    return l_C, l_CD - l_C


def condition_number(T_C, T_D, l_CD, g):
    r"""How strongly formula (10) amplifies period errors: a relative error ε in the periods
    moves the centre of mass by up to κ ε l_CD.

    .. math:: \kappa = \frac{1}{l_{CD}}\left(\left|\frac{\partial l_C}{\partial \ln T_C}
              \right| + \left|\frac{\partial l_C}{\partial \ln T_D}\right|\right)
              = \frac{2}{1 - q} - \frac{4 l_C l_D}{l_{CD}^2}, \qquad q = \frac{k^2}{l_C l_D}

    (the closed form for an ideal pendulum). About 3 for an ordinary rod (q ≈ 0.5),
    unbounded at the Kater point q → 1, symmetric in the two pivots.

    Examples
    --------
    A symmetric body with q = 0.5 gives κ = (1 + q)/(1 − q) = 3:

    >>> g, l = 9.81, 0.08
    >>> T = 2 * np.pi * np.sqrt((0.5 * l * l + l * l) / (g * l))
    >>> round(float(condition_number(T, T, 2 * l, g)), 9)
    3.0
    """
    den = 8 * np.pi**2 * l_CD - (T_C**2 + T_D**2) * g
    num = 4 * np.pi**2 * l_CD - T_D**2 * g
    l_C = l_CD * num / den
    d_c = 2 * T_C**2 * g * l_C / den
    d_d = 2 * T_D**2 * g * l_C * (1.0 / den - 1.0 / num)
    return (np.abs(d_c) + np.abs(d_d)) / l_CD


def inertia_about_cm(T, l, m_sh, g):
    """Moment of inertia about the centre of mass from a pendulum period about a pivot l away.

    .. math:: J_c = m\\left(\\frac{g T^2 l}{4\\pi^2} - l^2\\right)

    (lab 1, formulas 15 and 16, applied to the rod).
    """
    return m_sh * (g * T**2 * l / (4 * np.pi**2) - l**2)


# -------------------------------------------------------------------- the measurement file

ROD_LENGTH = {**LENGTH, "plausible": ("50 mm", "1000 mm")}
"""Lengths along a connecting rod."""

BORE = dict(unit="mm", limit="0.05 mm", plausible=("5 mm", "200 mm"))
"""A rod's bore on the caliper."""

SPEC = LabSpec(
    id="lab2", number="2",
    title=bi("Reducing the connecting-rod mass", "Приведение масс шатуна"),
    goal=bi("To study the methods of reducing the connecting-rod mass and to find by experiment "
            "the position of the rod's centre of mass and the masses reduced to the piston-pin "
            "axis and to the crank-pin axis.",
            "Изучить методы приведения масс шатуна и экспериментально определить положение "
            "центра масс шатуна и массы, отнесённые к оси поршневого пальца и к оси "
            "кривошипной головки."),
    sections=(
        Section("rod", bi("The connecting rod", "Шатун"), required=True, fields=(
            Field("m_sh", bi("mass of the rod", "масса шатуна"), **MASS, symbol="m_ш",
                  example="1.012 kg"),
            Field("l_sh", bi("distance between the pin and crank-pin axes",
                             "расстояние между осями головок"), unit="mm", limit="0.1 mm",
                  symbol="l_ш", plausible=("50 mm", "1000 mm")),
            Field("engine", bi("engine type (for the statistics)", "тип двигателя"),
                  kind="choice", default="petrol",
                  choices={"petrol": bi("petrol", "бензиновый"),
                           "diesel": bi("diesel", "дизель")}),
            Field("g", bi("local acceleration of gravity", "ускорение свободного падения"),
                  **GRAVITY),
        )),
        Section("weighing", bi("Weighing method", "Метод взвешивания"), fields=(
            Field("R_A", bi("balance reading under the small end (ΔG)",
                            "показание весов под поршневой головкой (ΔG)"), unit="g",
                  limit="1 g", symbol="R_A", plausible=("10 g", "20 kg")),
        )),
        Section("swinging", bi("Swinging method", "Метод качания"), fields=(
            Field("l_CD", bi("distance between the prism edges C and D",
                             "расстояние между рёбрами призм C и D"), **ROD_LENGTH,
                  symbol="l_CD"),
            Field("d_C", bi("small-end bore diameter (prism C rests on it)",
                            "диаметр отверстия поршневой головки (опора призмы C)"), **BORE,
                  symbol="d_C"),
            Field("d_D", bi("big-end bore diameter (prism D rests on it)",
                            "диаметр отверстия кривошипной головки (опора призмы D)"),
                  **BORE, symbol="d_D"),
            Field("n_osc", bi("full oscillations timed (a film needs none)",
                               "число полных колебаний (для видео не нужно)"),
                  **COUNT, required=False),
            Field("t_C", bi("time of n_osc oscillations hung at the small end",
                            "время n колебаний на поршневой головке"),
                  **{**STOPWATCH, "required": False}, symbol="t_C"),
            Field("video_C", bi("or: a film of the swing hung at the small end (MP4, MOV, AVI; "
                                "a marker on the rod)", "или: видео качаний на поршневой "
                                "головке (MP4, MOV, AVI; метка на шатуне)"), kind="file",
                  required=False),
            *MARKER_FIELDS,
            Field("t_D", bi("time of n_osc oscillations hung at the big end",
                            "время n колебаний на кривошипной головке"),
                  **{**STOPWATCH, "required": False}, symbol="t_D"),
            Field("video_D", bi("or: a film of the swing hung at the big end",
                                "или: видео качаний на кривошипной головке"), kind="file",
                  required=False),
            Field("amplitude", bi("swing amplitude", "амплитуда качаний"), **AMPLITUDE),
        )),
    ),
    readings=(ReadingsTable(bi("Swinging: hung at the small end (t_C) and at the big end (t_D)",
                               "Качание: подвес на поршневой (t_C) и на кривошипной (t_D) "
                               "головке"), "swinging",
                            period_columns("n_osc", {"t_C": "t_C", "t_D": "t_D"})),),
)

FILMS = {"swinging": {"video_C": "t_C", "video_D": "t_D"}}
"""The films that may stand for the stopwatch (:func:`processing.vision.video.filmed_times`)."""

_QUANTITIES = {
    "l_shp": (bi("centre of mass from the piston-pin axis", "центр масс от оси поршневого пальца"),
              "l_шп", "mm"),
    "l_shk": (bi("centre of mass from the crank-pin axis", "центр масс от оси шатунной шейки"),
              "l_шк", "mm"),
    "m_shp": (bi("mass at the piston-pin axis", "масса на оси поршневого пальца"), "m_шп", "kg"),
    "m_shk": (bi("mass at the crank-pin axis", "масса на оси шатунной шейки"), "m_шк", "kg"),
}
METHODS = {"weighing": bi("weighing", "взвешивание"), "swinging": bi("swinging", "качание"),
           "statistics": bi("statistics", "статистика")}
RESULTS = {
    f"{q}_{m}": ({k: f"{lab[k]} ({mlab[k]})" for k in ("en", "ru")}, sym, unit,
                 STRICTLY_POSITIVE, *((KEY,) if q.startswith("m_") else ()))
    for m, mlab in METHODS.items() for q, (lab, sym, unit) in _QUANTITIES.items()
}
RESULTS.update({
    "J_cm_swinging": (bi("moment of inertia about the centre of mass (swinging)",
                         "момент инерции относительно центра масс (качание)"), "J_c", "kg*m^2",
                      STRICTLY_POSITIVE, KEY),
    "dJ_third_condition": (bi("third condition residual J_c − m_sh l_shp l_shk",
                              "невязка третьего условия J_c − m_ш l_шп l_шк"), "ΔJ", "kg*m^2",
                           SIGNED),
    "l_C_swinging": (bi("centre of mass from prism C", "центр масс от призмы C"), "l_C", "mm",
                     STRICTLY_POSITIVE),
    "l_D_swinging": (bi("centre of mass from prism D", "центр масс от призмы D"), "l_D", "mm",
                     STRICTLY_POSITIVE),
    "kappa_swinging": (bi("condition number of formula (10)", "число обусловленности формулы (10)"),
                       "κ", ""),
})

FORMULAS = [
    bi("Two-mass model: m_shp = m_sh l_shk/l_sh, m_shk = m_sh l_shp/l_sh  (6), (7)",
       "Двухмассовая модель: m_шп = m_ш l_шк/l_ш, m_шк = m_ш l_шп/l_ш  (6), (7)"),
    bi("Weighing: l_shk = (R_A/G_sh) l_sh, l_shp = (1 − R_A/G_sh) l_sh  (8), (9)",
       "Взвешивание: l_шк = (R_A/G_ш) l_ш, l_шп = (1 − R_A/G_ш) l_ш  (8), (9)"),
    bi("Swinging: l_C = l_CD (4π² l_CD − T_D² g)/(8π² l_CD − (T_C² + T_D²) g), l_D = l_CD − l_C  (10); "
       "the prisms rest on the bores: l_shp = l_C − d_C/2, l_shk = l_D − d_D/2",
       "Качание: l_C = l_CD (4π² l_CD − T_D² g)/(8π² l_CD − (T_C² + T_D²) g), l_D = l_CD − l_C  (10); "
       "призмы опираются на отверстия головок: l_шп = l_C − d_C/2, l_шк = l_D − d_D/2"),
    bi("J_c = m_sh (g T_C² l_C/(4π²) − l_C²); third condition residual ΔJ = J_c − m_sh l_shp l_shk  (4), (5)",
       "J_c = m_ш (g T_C² l_C/(4π²) − l_C²); невязка третьего условия ΔJ = J_c − m_ш l_шп l_шк  (4), (5)"),
    bi("Statistics: m_shp = (0.2…0.3) m_sh; petrol ≈ 0.25 m_sh, diesel ≈ 0.3 m_sh  (11), (12)",
       "Статистика: m_шп = (0,2…0,3) m_ш; бензиновые ≈ 0,25 m_ш, дизели ≈ 0,3 m_ш  (11), (12)"),
]
def _pin_distance_for_prisms(inputs: Inputs) -> Inputs | None:
    """The wrong pivot distance: the pin-axis distance l_ш taken for the prism edges' l_CD."""
    if "swinging" not in inputs:
        return None
    return inputs.changed("swinging", l_CD=inputs["rod"]["l_sh"])


SLIPS = [
    ("wrong_pivot_distance",
     bi("the wrong pivot distance: the axes' distance l_ш used for the prism edges' l_CD",
        "неверное расстояние между осями качания: l_ш взято вместо l_CD"),
     ("l_shp_swinging", "l_shk_swinging", "m_shp_swinging", "m_shk_swinging", "J_cm_swinging",
      "l_C_swinging", "l_D_swinging"), _pin_distance_for_prisms),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the inputs as the slip leaves them."""


REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, lab 2.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: ВлГУ, 2003. Лаб. работа №2."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]


# ------------------------------------------------------------------------ reduction

def _model(inputs: Inputs):
    secs = inputs.sections

    def model(**x):
        m, l_sh, g = x["rod.m_sh"], x["rod.l_sh"], x["rod.g"]
        out = {}

        def put(method, l_shp, l_shk):
            out[f"l_shp_{method}"], out[f"l_shk_{method}"] = l_shp, l_shk
            out[f"m_shp_{method}"], out[f"m_shk_{method}"] = two_mass(m, l_shp, l_shk)

        share = x["statistics.share"]
        put("statistics", (1 - share) * l_sh, share * l_sh)
        if "weighing" in secs:
            put("weighing", *weighing(x["weighing.R_A"], m, l_sh))
        if "swinging" in secs:
            sw = secs["swinging"]
            factor = pendulum_period_factor(x.get("swinging.amplitude", 0.0))
            T_C = period_from_total(x["swinging.t_C"], sw["n_osc"]) / factor
            T_D = period_from_total(x["swinging.t_D"], sw["n_osc"]) / factor
            l_C, l_D = swinging(T_C, T_D, x["swinging.l_CD"], g)
            l_shp, l_shk = l_C - 0.5 * x["swinging.d_C"], l_D - 0.5 * x["swinging.d_D"]
            put("swinging", l_shp, l_shk)
            out["l_C_swinging"], out["l_D_swinging"] = l_C, l_D
            out["J_cm_swinging"] = inertia_about_cm(T_C, l_C, m, g)
            out["dJ_third_condition"] = out["J_cm_swinging"] - m * l_shp * l_shk
            out["kappa_swinging"] = condition_number(T_C, T_D, x["swinging.l_CD"], g)
            out["l_sh_swinging"] = l_shp + l_shk
        return out

    return model


def _checks(inputs: Inputs, prop) -> None:
    rod = inputs["rod"]
    if "weighing" in inputs and inputs["weighing"]["R_A"].value >= rod["m_sh"].value:
        raise inputs.error("the balance reading R_A is not smaller than the rod's mass",
                           "R_A carries only part of the rod: check the reading and its unit",
                           "weighing.R_A",
                           ru=("показание весов R_A не меньше массы шатуна",
                               "на весы R_A опирается лишь часть шатуна: проверьте показание "
                               "и его единицу"))
    if "swinging" not in inputs:
        return
    sw = inputs["swinging"]
    if sw["l_CD"].value <= 0.5 * (sw["d_C"].value + sw["d_D"].value):
        raise inputs.error("l_CD is shorter than the two bore radii together",
                           "l_CD is the distance between the prism edges (mm); d_C, d_D are "
                           "diameters", "swinging.l_CD")
    if "amplitude" in sw:
        check_amplitude(sw["amplitude"], SPEC.section("swinging").label)
    kappa = prop["kappa_swinging"].value
    l_C = prop["l_C_swinging"]
    if kappa > KATER_CONDITION_LIMIT or not 0 < l_C.value < sw["l_CD"].value:
        lo, hi = (1e3 * v for v in l_C.interval95)
        warnings.warn(IllConditionedWarning(
            f"swinging method fails here: the prisms are close to conjugate points (Kater's "
            f"reversible pendulum, k² ≈ l_C·l_D), where formula (10) is 0/0; its condition number "
            f"is {kappa:.0f} (an ordinary rod gives about 3), so a 0.1 % period error moves the "
            f"centre of mass by {0.1 * kappa:.1f} % of l_CD, and the errors are large and lopsided: Monte Carlo 95 % "
            f"interval of l_C [{lo:.1f}, {hi:.1f}] mm. Trust the weighing method; to use swinging, "
            f"hang the rod from points farther from its centre of mass",
            f"метод качания здесь не работает: точки подвеса близки к сопряжённым (оборотный "
            f"маятник Катера, k² ≈ l_C·l_D), где формула (10) даёт 0/0; число обусловленности "
            f"{kappa:.0f} (у обычного шатуна около 3): ошибка периода 0,1 % смещает центр масс "
            f"на {0.1 * kappa:.1f} % от l_CD, ошибки велики и несимметричны: интервал Монте-Карло 95 % для "
            f"l_C [{lo:.1f}, {hi:.1f}] мм. Доверяйте методу взвешивания; для качания подвешивайте "
            f"шатун в точках, более удалённых от центра масс"))
    l_sw = prop["l_sh_swinging"]
    gap = l_sw.value - rod["l_sh"].value
    u = np.hypot(l_sw.u, rod["l_sh"].u)
    if abs(gap) > 3 * u:
        warnings.warn(InconsistentInputWarning(
            f"l_CD − (d_C + d_D)/2 = {1e3 * l_sw.value:.1f} mm, but the measured centre distance "
            f"l_sh is {1e3 * rod['l_sh'].value:.1f} mm: check l_CD and the bore diameters",
            f"l_CD − (d_C + d_D)/2 = {1e3 * l_sw.value:.1f} мм, а измеренное межосевое "
            f"расстояние l_ш = {1e3 * rod['l_sh'].value:.1f} мм: проверьте l_CD и диаметры "
            f"отверстий"))


def _method_table(results) -> Table:
    rows = []
    for m, mlab in METHODS.items():
        row = {"method": mlab}
        for q in _QUANTITIES:
            r = results.get(f"{q}_{m}")
            row[q] = "—" if r is None else " ± ".join(
                fmt_pm(r.shown(r.value), r.shown(r.value + r.estimate.U) - r.shown(r.value)))
        rows.append(row)
    return Table(bi("The manual's table: centre of mass and reduced masses by method (± U)",
                    "Таблица методички: координаты центра масс и приведённые массы (± U)"),
                 (("method", bi("Method", "Метод")), ("l_shp", bi("l_shp, mm", "l_шп, мм")),
                  ("l_shk", bi("l_shk, mm", "l_шк, мм")), ("m_shp", bi("m_shp, kg", "m_шп, кг")),
                  ("m_shk", bi("m_shk, kg", "m_шк, кг"))),
                 tuple(rows))


def _conclusion(results, inputs: Inputs) -> list[dict]:
    lines = []
    m = inputs["rod"]["m_sh"].value
    for method, mlab in METHODS.items():
        key = f"m_shp_{method}"
        if key in results:
            r = results[key]
            v, U = fmt_pm(r.value, r.estimate.U)
            lines.append(bi(f"{mlab['en']}: m_shp = {v} ± {U} kg "
                            f"({100 * r.value / m:.1f} % of the rod)",
                            f"{mlab['ru']}: m_шп = {v} ± {U} кг "
                            f"({100 * r.value / m:.1f} % массы шатуна)"))
    if "dJ_third_condition" in results:
        dJ, J = results["dJ_third_condition"], results["J_cm_swinging"]
        lines.append(bi(f"Third equivalence condition: the two-mass model's J differs from the "
                        f"rod's J_c by {100 * dJ.value / J.value:+.1f} % of J_c",
                        f"Третье условие эквивалентности: J двухмассовой модели отличается от "
                        f"J_c шатуна на {100 * dJ.value / J.value:+.1f} % от J_c"))
    return lines


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20031) -> LabResult:
    """Reduce lab 2's measurements into the manual's table, with uncertainties.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed.

    Returns
    -------
    LabResult
        ``l_shp_*``, ``l_shk_*``, ``m_shp_*``, ``m_shk_*`` for ``weighing``, ``swinging``,
        ``statistics`` (those measured), ``J_cm_swinging``, ``dJ_third_condition``,
        ``l_C_swinging``, ``l_D_swinging``, ``kappa_swinging``.
    """
    with collect_notices() as notices:
        inputs, films = filmed_times(inputs, FILMS, needed=("t_C", "t_D"))
        flat = inputs.flat()
        flat["statistics.share"] = Measured(STATISTICAL_SHARE[inputs["rod"]["engine"]],
                                            limit=0.05)
        prop = propagate(_model(inputs), flat, n_samples=n_samples, seed=seed)
        _checks(inputs, prop)
        results = result_values(prop, RESULTS)
        experimental = [(f"{q}_weighing", f"{q}_swinging") for q in ("l_shp", "m_shp")]
        statistical = [(f"m_shp_{m}", "m_shp_statistics") for m in ("weighing", "swinging")]
        checked = compare(prop, experimental)
        flag_estimates(results, checked)
        comparisons = checked + compare(prop, statistical)
    figures = [Figure("m_shp", bi("Mass at the piston-pin axis by method (bars: ± U; ticks: Monte "
                                  "Carlo 95 %)", "Масса на оси поршневого пальца по методам "
                                  "(отрезки: ± U; штрихи: Монте-Карло 95 %)"),
                      lambda fig, lang: method_chart(
                          fig, [results[f"m_shp_{m}"] for m in METHODS if f"m_shp_{m}" in results],
                          lang))]
    if any(n.code == "ill_conditioned" for n in notices):
        samples = 1e3 * prop.samples("l_C_swinging")
        l_C = results["l_C_swinging"]
        figures.append(Figure("l_C_mc", bi("Swinging method near the Kater point: Monte Carlo "
                                           "distribution of l_C", "Метод качания вблизи точки "
                                           "Катера: распределение l_C по Монте-Карло"),
                              lambda fig, lang: histogram(
                                  fig, samples, 1e3 * l_C.value,
                                  [1e3 * v for v in l_C.estimate.interval95], "l_C, mm", lang)))
    return LabResult.of(inputs, results, comparisons=comparisons, tables=[_method_table(results)],
                        figures=figures + film_figures(films), formulas=FORMULAS,
                        references=REFERENCES,
                        warnings=notices, conclusion=_conclusion(results, inputs))


# ------------------------------------------------------------------------ synthetic files

SYNTH_RESULTS = ("l_shp", "l_shk", "m_shp", "m_shk")


def write_synthetic(out_dir, seed: int = 0, *, film: bool = False) -> dict[str, Path]:
    """Write a synthetic lab 2 measurement: a connecting rod of its own per seed, weighed and
    swung on its prisms, and its answer key.

    The rod: 0.8–1.4 kg, 140–200 mm between its axes, the centre of mass 22–30 % of that
    from the big end, its moment of inertia about the centre of mass 80–95 % of m l_шп l_шк
    (the third condition's usual deficit), bores of 20–30 and 50–65 mm. Weighed on the
    balance under the small end (R_A = m l_шк/l_ш, to ± 1 g); swung at 5–8° from prisms in
    the bores' tops (pivots d/2 above the axes), the periods integrated from the nonlinear
    pendulum (:mod:`processing.synth.pendulum`) and timed by hand over 20 oscillations, three
    times; lengths read to ± 0.5 mm (bores to ± 0.05 mm), masses to ± 1 g. With ``film``,
    both swings are filmed from the side instead (:mod:`processing.synth.swing_film`, 10
    oscillations at 30 frames per second, each at the period of the RMS of its decaying
    amplitude) and the amplitude is left to the films.

    Returns
    -------
    dict
        Paths written: ``toml`` and ``answer`` (``"results"``: the weighing's and the
        swinging's l_shp, l_shk, m_shp, m_shk, and J_cm_swinging, l_C_swinging,
        l_D_swinging, true, SI).
    """
    import json

    from processing.synth.pendulum import measured, physical_pendulum_period, stopwatch
    from processing.inputs.toml_writer import dumps

    rng = np.random.default_rng([seed, 2])
    g = 9.8156
    m, l_sh = rng.uniform(0.8, 1.4), rng.uniform(0.14, 0.20)
    l_shk = rng.uniform(0.22, 0.30) * l_sh
    l_shp = l_sh - l_shk
    J_cm = rng.uniform(0.80, 0.95) * m * l_shp * l_shk
    d_C, d_D = rng.uniform(0.020, 0.030), rng.uniform(0.050, 0.065)
    l_C, l_D = l_shp + d_C / 2, l_shk + d_D / 2
    amp = np.radians(rng.uniform(5.0, 8.0))
    T_C = physical_pendulum_period(J_cm + m * l_C**2, m, l_C, amp, g)
    T_D = physical_pendulum_period(J_cm + m * l_D**2, m, l_D, amp, g)

    def times(period):
        return [round(float(x), 2) for x in stopwatch(period, 20, 3, rng)]

    doc = {"lab": "lab2",
           "meta": {"student": f"synthetic (dynlab synth lab2 --seed {seed})",
                    "notes": "generated; the true answers are in answer_key.json"},
           "rod": {"m_sh": f"{measured(1e3 * m, 1.0, rng):.1f} g",
                   "l_sh": f"{measured(1e3 * l_sh, 0.1, rng):.2f} mm", "engine": "petrol",
                   "g": f"{g} ± 0.0005 m/s^2"},
           "weighing": {"R_A": f"{measured(1e3 * m * l_shk / l_sh, 1.0, rng):.1f} g"},
           "swinging": {"l_CD": round(measured(1e3 * (l_C + l_D), 0.5, rng), 1),
                        "d_C": round(measured(1e3 * d_C, 0.05, rng), 3),
                        "d_D": round(measured(1e3 * d_D, 0.05, rng), 3), "n_osc": 20,
                        "t_C": times(T_C), "t_D": times(T_D),
                        "amplitude": f"{round(float(np.degrees(amp)))} deg"}}
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = {}
    if film:
        from processing.synth.swing_film import Film, render

        swung = Film(amplitude=amp, oscillations=10.0).rms_amplitude
        for end, l_end in (("C", l_C), ("D", l_D)):
            name = f"swing_{end}.mp4"
            period = physical_pendulum_period(J_cm + m * l_end**2, m, l_end, swung, g)
            written[name] = render(Film(period=period, amplitude=amp, oscillations=10.0),
                                   out / name, seed=seed * 10 + len(written))
            doc["swinging"].pop(f"t_{end}")
            doc["swinging"][f"video_{end}"] = name
        doc["swinging"].pop("amplitude")
    written.update(toml=out / f"lab2_seed{seed}.toml", answer=out / "answer_key.json")
    written["toml"].write_text(dumps(doc), encoding="utf-8")
    true = dict(zip(SYNTH_RESULTS, (l_shp, l_shk, m * l_shk / l_sh, m * l_shp / l_sh)))
    truth = {f"{k}_{method}": v for method in ("weighing", "swinging") for k, v in true.items()}
    truth.update(J_cm_swinging=J_cm, l_C_swinging=l_C, l_D_swinging=l_D)
    written["answer"].write_text(json.dumps({"seed": seed, "results": truth}, indent=1),
                                 encoding="utf-8")
    return written
