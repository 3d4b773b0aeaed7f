"""Lab 5's report: result labels, formulas, the manual's tables, the P–Δl charts, the chain of
stiffnesses, the warnings' words and the conclusion.

Everything here lays out what :func:`labs.lab5_valve_stiffness.reduce` found, in the manual's
terms; nothing here reduces data.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from processing.diagnostics import (GaugeBackwardsWarning, InconsistentInputWarning,
                                    LargeHysteresisWarning, TableCurvatureWarning)
from processing.oscillations.load_cycle import BRANCHES, LoadCycle
from processing.measurement import bi
from processing.numerals import plural
from processing.reporting.content import fmt_pm, result_pm
from processing.result import KEY, STRICTLY_POSITIVE, Figure, Table, computed
from processing.uncertainty import Estimate

PARTS = ("rocker", "shaft", "rod", "cam")
"""The chain's links, from the valve to the cam."""

_SUB = "₁₂₃₄"
_PART = {"rocker": (bi("rocker", "коромысло"), "c_кор"),
         "shaft": (bi("rocker shaft with its stand", "ось коромысла со стойкой"), "c_o"),
         "rod": (bi("push rod", "штанга"), "c_ш"),
         "cam": (bi("camshaft span", "пролёт распределительного вала"), "c_в"),
         "total": (bi("whole drive at the valve", "привод клапана в целом"), "c")}
_BRANCH = {"mean": bi("mean of loading and unloading", "среднее нагрузки и разгрузки"),
           "load": bi("loading", "нагрузка"), "unload": bi("unloading", "разгрузка")}
_GAUGE = (bi("total", "общая"), bi("rocker shaft", "ось коромысла"),
          bi("push rod + camshaft", "штанга + вал"), bi("camshaft", "вал"))


def result_name(quantity: str, branch: str = "mean") -> str:
    """``c_rocker`` on the mean branch, ``c_rocker_load`` / ``c_rocker_unload`` on the others.

    >>> result_name("c_rod"), result_name("c_rod", "unload")
    ('c_rod', 'c_rod_unload')
    """
    return quantity if branch == "mean" else f"{quantity}_{branch}"


def _branch_label(label: dict, branch: str) -> dict:
    return {k: f"{v} ({_BRANCH[branch][k]})" for k, v in label.items()}


def _shown(results, name: str, digits: int = 2) -> str:
    """A result found without an uncertainty (a loop's area or share), in its display unit to
    ``digits`` decimals; "—" if there is none."""
    if name not in results:
        return "—"
    r = results[name]
    return f"{r.shown(r.value):.{digits}f}"


def valve_results(at_valve: dict) -> dict:
    """Each link's stiffness as the valve sees it (``c_<link>_at_valve``) and its share of
    the drive's compliance (``share_<link>``), named results (none without all four)."""
    if len(at_valve) < 4:
        return {}
    compliance = sum(1 / v for v in at_valve.values())
    values = {f"c_{p}_at_valve": v for p, v in at_valve.items()}
    values.update({f"share_{p}": 1 / v / compliance for p, v in at_valve.items()})
    declared = {}
    for p in at_valve:
        label = _PART[p][0]
        declared[f"c_{p}_at_valve"] = (bi(f"{label['en']}: stiffness at the valve",
                                          f"{label['ru']}: жесткость, приведённая к клапану"),
                                       f"{_PART[p][1]},кл", "kN/mm")
        declared[f"share_{p}"] = (bi(f"{label['en']}: share of the drive's compliance",
                                     f"{label['ru']}: доля податливости привода"),
                                  f"{_PART[p][1]}⁻¹/Σc⁻¹", "%")
    return computed(values, declared)


def loop_results(lines, loops, spring_loop) -> dict:
    """The gauges' lines and loops as named results: each gauge's deflection per unit load on
    each branch (``dl<j>_per_P[_load|_unload]``, ± its fit's type A U), its largest loop over
    the runs (``loop_area_<j>``) and that loop's share of the loading work (``loop_share_<j>``),
    the widest share of all (``loop_share_max``), and the springs' loop (``loop_*_spring``).
    A share where no work was done is left out."""
    values, declared = {}, {}
    for j in range(4):
        g = f"Δl{_SUB[j]}"
        for b in BRANCHES:
            f = lines[j, b].fit
            name = result_name(f"dl{j + 1}_per_P", b)
            values[name] = Estimate(f.slope, f.u_slope, f.dof)
            declared[name] = (_branch_label(bi(f"gauge {g} per unit load",
                                               f"показание {g} на единицу нагрузки"), b),
                              f"d{g}/dP", "um/kN")
        values[f"loop_area_{j + 1}"] = max(run[j].area for run in loops)
        values[f"loop_share_{j + 1}"] = max(run[j].share for run in loops)
        declared[f"loop_area_{j + 1}"] = (bi(f"hysteresis loop of gauge {g}, largest over the "
                                             "runs", f"петля гистерезиса индикатора {g}, "
                                             "наибольшая по циклам"), f"A_{j + 1}", "N*mm")
        declared[f"loop_share_{j + 1}"] = (bi(f"that loop's share of the loading work, gauge {g}",
                                              f"доля этой петли в работе нагрузки, индикатор "
                                              f"{g}"), f"A_{j + 1}/W", "%")
    values["loop_share_max"] = max(h.share for run in loops for h in run)
    declared["loop_share_max"] = (bi("the widest loop's share of the loading work",
                                     "доля наибольшей петли в работе нагрузки"), "A/W", "%")
    if spring_loop is not None:
        values.update(loop_area_spring=spring_loop.area, loop_share_spring=spring_loop.share)
        declared.update(
            loop_area_spring=(bi("hysteresis loop of the valve springs",
                                 "петля гистерезиса клапанных пружин"), "A_n", "N*mm"),
            loop_share_spring=(bi("its share of the springs' loading work",
                                  "её доля в работе нагрузки пружин"), "A_n/W", "%"))
    return computed({k: v for k, v in values.items()
                     if math.isfinite(v.value if isinstance(v, Estimate) else v)}, declared)


RESULTS = {
    **{result_name(f"c_{p}", b): (_branch_label(bi(f"stiffness: {lab['en']}",
                                                     f"жесткость: {lab['ru']}"), b), sym,
                                  "kN/mm", STRICTLY_POSITIVE, *((KEY,) if b == "mean" else ()))
       for b in BRANCHES for p, (lab, sym) in _PART.items()},
    **{f"dl{j}_0": (bi(f"gauge {j}: elastic zero, the level at no load (settling, lash)",
                       f"индикатор {j}: упругий нуль, уровень без нагрузки (усадка, зазоры)"),
                    f"Δl{_SUB[j - 1]}(0)", "mm") for j in range(1, 5)},
    **{result_name("c_spring", b): (_branch_label(bi("valve springs' stiffness",
                                                     "жесткость клапанных пружин"), b), "c_n",
                                    "N/mm", STRICTLY_POSITIVE, *((KEY,) if b == "mean" else ()))
       for b in BRANCHES},
    "P_preload": (bi("spring force with the valve closed (the elastic zero of the "
                     "characteristic)", "усилие пружин при закрытом клапане (упругий нуль "
                     "характеристики)"), "P_0", "N", STRICTLY_POSITIVE),
    "m_g": (bi("oscillating mass of the camshaft span", "колеблющаяся масса пролёта вала"),
            "m_г", "kg"),
    "M_reduced": (bi("oscillating mass reduced to the valve", "приведённая масса деталей"),
                  "M", "kg", STRICTLY_POSITIVE),
    "nu_natural": (bi("lowest natural angular frequency of the drive",
                      "низшая собственная круговая частота привода"), "ν", "rad/s",
                   STRICTLY_POSITIVE),
    "f_natural": (bi("lowest natural frequency of the drive",
                     "низшая собственная частота привода"), "f", "Hz", STRICTLY_POSITIVE, KEY),
    "cam_order": (bi("natural frequency in camshaft orders at n",
                     "собственная частота в порядках вращения распредвала при n"), "k", "",
                  STRICTLY_POSITIVE, KEY),
}
"""Labels, symbols and display units of the lab's results."""

FORMULAS = [
    bi("Load at the valve P = Q i₁; deformations reduced to the valve: rocker Δl₁ − Δl₂(i + 1) "
       "− Δl₃ i, rocker shaft Δl₂(i + 1), push rod (Δl₃ − Δl₄) i, camshaft Δl₄ i",
       "Сила на клапане P = Q i₁; приведённые к оси клапана деформации: коромысла Δl₁ − Δl₂(i + 1) "
       "− Δl₃ i, оси Δl₂(i + 1), штанги (Δl₃ − Δl₄) i, вала Δl₄ i"),
    bi("Slopes dΔl/dP by least squares over the whole table: a line through the loading and one "
       "through the unloading branch (each without its turning point, where the friction has not "
       "reversed yet), and their mean Δl = (Δl_load + Δl_unload)/2, the line midway between "
       "them; stiffnesses with P = 1 N and the slopes for Δl",
       "Наклоны dΔl/dP — по методу наименьших квадратов по всей таблице: прямая по ветви "
       "нагрузки и прямая по ветви разгрузки (каждая без своей точки поворота, где трение ещё "
       "не сменило направление) и их среднее Δl = (Δl_наг + Δl_раз)/2 — прямая посередине "
       "между ними; жесткости — при P = 1 Н с наклонами вместо Δl"),
    bi("c_rocker = P/Δl_rocker, c_shaft = P(i + 1)/Δl₂, c_rod = P i/(Δl₃ − Δl₄), c_cam = P i/Δl₄, "
       "c = P/Δl₁ = [1/c_rocker + (i + 1)²/c_shaft + i²(1/c_rod + 1/c_cam)]⁻¹",
       "c_кор = P/Δl_кор, c_o = P(i + 1)/Δl₂, c_ш = P i/(Δl₃ − Δl₄), c_в = P i/Δl₄, "
       "c = P/Δl₁ = [1/c_кор + (i + 1)²/c_o + i²(1/c_ш + 1/c_в)]⁻¹"),
    bi("Springs: c_n = dP/dh from the characteristic, P = k_d d (dynamometer 1 mm = 145 N)",
       "Пружины: c_n = dP/dh по характеристике, P = k_d d (динамометр 1 мм = 145 Н)"),
    bi("M = m_valve + m_spring/3 + J_rocker/a² + (1 + 2i²c/c_g)[(1/3) m_rod (i c/c_rod)² + "
       "((2/3) m_rod + m_tappet + m_g)(i c/c_g)²], m_g = m′_g/(2 sin²(π l/L)) ≈ (2/3) m′_g, "
       "c_g = c_cam",
       "M = m_кл + m_n/3 + J_кор/a² + (1 + 2i²c/c_г)[(1/3) m_ш (i c/c_ш)² + "
       "((2/3) m_ш + m_m + m_г)(i c/c_г)²], m_г = m′_г/(2 sin²(π l/L)) ≈ (2/3) m′_г, c_г = c_в"),
    bi("ν = √((c + c_n)/M) rad/s, f = ν/2π; in camshaft orders k = f/f_cam, f_cam = n/120 "
       "(4-stroke)",
       "ν = √((c + c_n)/M) рад/с, f = ν/2π; в порядках распредвала k = f/f_в, f_в = n/120 "
       "(4 такта)"),
    bi("Hysteresis: the loop's area between loading and unloading (shoelace rule) and its share "
       "of the loading branch's work ∫P dΔl",
       "Гистерезис: площадь петли между нагрузкой и разгрузкой (формула площади многоугольника) "
       "и её доля от работы ветви нагрузки ∫P dΔl"),
]
REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, "
       "lab 5.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: ВлГУ, "
       "2003. Лаб. работа №5."),
    bi("JCGM 100:2008 (GUM), annex H.3: a straight-line calibration; JCGM 101:2008 (Monte Carlo).",
       "JCGM 100:2008 (GUM), прил. H.3: градуировка по прямой; JCGM 101:2008 (Монте-Карло)."),
]

TABLE_HELP = bi(
    "One loading–unloading run, typed as you wrote it: a header naming the columns, then a line "
    "per load in the order applied (rising to the largest, then falling back). The load column "
    "is P (at the valve) or Q (the weights on the lever, P = Q i₁), in N unless a unit follows "
    "in brackets (Q[kg]: the weights' masses); the gauges dl1…dl4 are in the [gauges] unit "
    "unless one follows (dl1[mm], dl1[div]). Negative readings are allowed; deformations count "
    "from each gauge's first reading. Repeat [[run]] for more runs. Example:\n"
    "table = \"\"\"\n  Q[N]  dl1  dl2  dl3  dl4\n  0     0    0    0    0\n"
    "  10    4    1    1    1\n  ...\n  \"\"\"",
    "Один цикл нагрузки–разгрузки, как он записан: строка заголовка с именами столбцов, затем "
    "по строке на каждую нагрузку в порядке приложения (растут до наибольшей, затем убывают). "
    "Столбец нагрузки — P (на клапане) или Q (грузы на рычаге, P = Q i₁), в Н, если в скобках "
    "не указаны единицы (Q[kg] — масса грузов); индикаторы dl1…dl4 — в единицах [gauges], если "
    "не указаны свои (dl1[mm], dl1[div]). Отрицательные показания допустимы; деформации "
    "отсчитываются от первого показания. Для нескольких циклов повторите [[run]]. Пример:\n"
    "table = \"\"\"\n  Q[N]  dl1  dl2  dl3  dl4\n  0     0    0    0    0\n"
    "  10    4    1    1    1\n  ...\n  \"\"\"")

SPRING_HELP = bi(
    "The characteristic as you wrote it: columns h (valve lift, mm) and d (the dynamometer's "
    "indicator, mm) or P (the force, N), a line per lift, up and back down.",
    "Характеристика, как она записана: столбцы h (перемещение клапана, мм) и d (индикатор "
    "динамометра, мм) или P (усилие, Н), по строке на каждое перемещение, вверх и обратно.")


# ------------------------------------------------------------------------ what the report needs

@dataclass(frozen=True)
class Data:
    """What the report needs from a reduction.

    Attributes
    ----------
    inputs : Inputs
    tables : list of LoadCycle
        The runs: x = P [N], y = Δl₁…Δl₄ [m].
    parts : list of (ndarray, ndarray)
        Per run, the mean table's loads [N] and the links' deformations at the valve,
        shape (4, m) [m].
    lines : dict
        (gauge row 0…3, branch) → BranchLine.
    loops : list of list of Hysteresis
        Per run, per gauge.
    spring : LoadCycle or None
        x = h [m], y = [P] [N].
    spring_lines : dict or None
        (0, branch) → BranchLine of P against h.
    spring_loop : Hysteresis or None
    results : dict
        Result name → ResultValue (those reported).
    at_valve : dict
        Each link's stiffness as the valve sees it [N/m] (empty unless all four are reported).
    mass_terms : dict
        The reduced mass's terms [kg] (empty without [masses]).
    """

    inputs: object
    tables: list
    parts: list
    lines: dict
    loops: list
    spring: LoadCycle | None
    spring_lines: dict | None
    spring_loop: object
    results: dict
    at_valve: dict
    mass_terms: dict


def weakest(at_valve: dict) -> tuple[str, float] | None:
    """The link with the largest share of the drive's compliance, and that share.

    >>> part, share = weakest({"rocker": 7e6, "shaft": 6.4e6, "rod": 8.9e6, "cam": 13.3e6})
    >>> part, round(share, 3)
    ('shaft', 0.321)
    """
    if len(at_valve) < 4:
        return None
    compliance = {p: 1 / v for p, v in at_valve.items()}
    part = max(compliance, key=compliance.get)
    return part, compliance[part] / sum(compliance.values())


# ------------------------------------------------------------------------ tables

def _mm(x) -> str:
    return f"{1e3 * x:.3f}"


def _run_table(data: Data, r: int) -> Table:
    t = data.tables[r]
    P_mean, parts = data.parts[r]
    rows = []
    for k, p in enumerate(t.x[:t.peak + 1]):
        row = {"P": f"{p:.0f}"}
        down = np.flatnonzero(np.isclose(t.x[t.peak:], p, rtol=1e-9, atol=0.0))
        for j in range(4):
            up = _mm(t.y[j, k])
            row[f"g{j}"] = f"{up} / {_mm(t.y[j, t.peak + down[-1]])}" \
                if down.size and down[-1] > 0 else up
        m = np.flatnonzero(np.isclose(P_mean, p, rtol=1e-9, atol=0.0))
        for q, part in enumerate(PARTS):
            row[part] = _mm(parts[q, m[0]]) if m.size else "—"
        rows.append(row)
    cols = (("P", bi("P, N", "P, Н")),
            *((f"g{j}", bi(f"Δl{_SUB[j]} load / unload, mm", f"Δl{_SUB[j]} нагр. / разгр., мм"))
              for j in range(4)),
            *((p, bi(f"{_PART[p][0]['en']} (mean, at the valve), mm",
                     f"{_PART[p][0]['ru']} (среднее, у клапана), мм")) for p in PARTS))
    title = bi("The manual's table: gauge readings and the links' deformations reduced to the "
               "valve",
               "Таблица методички: показания индикаторов и приведённые к клапану деформации")
    if len(data.tables) > 1:
        title = bi(f"{title['en']} (run {r + 1})", f"{title['ru']} (цикл {r + 1})")
    return Table(title, cols, tuple(rows), "readings")


def _stiffness_table(data: Data) -> Table:
    res = data.results
    rows = []
    for p in PARTS:
        rows.append({"part": _PART[p][0], "load": result_pm(res, f"c_{p}_load"),
                     "unload": result_pm(res, f"c_{p}_unload"), "mean": result_pm(res, f"c_{p}"),
                     "reduced": _shown(res, f"c_{p}_at_valve"),
                     "share": _shown(res, f"share_{p}", 0)})
    rows.append({"part": _PART["total"][0], "load": result_pm(res, "c_total_load"),
                 "unload": result_pm(res, "c_total_unload"), "mean": result_pm(res, "c_total"),
                 "reduced": result_pm(res, "c_total"), "share": "100"})
    cols = (("part", bi("Link", "Звено")), ("load", bi("c loading, kN/mm", "c нагрузка, кН/мм")),
            ("unload", bi("c unloading, kN/mm", "c разгрузка, кН/мм")),
            ("mean", bi("c mean, kN/mm", "c среднее, кН/мм")),
            ("reduced", bi("at the valve, kN/mm", "приведённая к клапану, кН/мм")),
            ("share", bi("share of the compliance, %", "доля податливости, %")))
    return Table(bi("Stiffness of the links (± U): their own, and as the valve sees them",
                    "Жесткость звеньев (± U): собственная и приведённая к клапану"),
                 cols, tuple(rows))


def _line_table(data: Data) -> Table:
    rows = []
    res = data.results
    for j in range(4):
        loop = f"{_shown(res, f'loop_area_{j + 1}', 1)} / {_shown(res, f'loop_share_{j + 1}', 0)}"
        for b in BRANCHES:
            line = data.lines[j, b]
            f, c = line.fit, line.curvature
            rows.append({
                "gauge": f"Δl{_SUB[j]}", "branch": _BRANCH[b],
                "slope": result_pm(res, result_name(f"dl{j + 1}_per_P", b)),
                "icpt": " ± ".join(fmt_pm(1e3 * f.intercept, 2e3 * f.u_intercept)),
                "sd": f"{1e6 * f.residual_sd:.1f}",
                "curv": f"{c.p_value:.2g} / {100 * c.relative_bend:.1f}" if c is not None else "",
                "loop": loop if b == "mean" else ""})
    cols = (("gauge", bi("Gauge", "Индикатор")), ("branch", bi("Branch", "Ветвь")),
            ("slope", bi("dΔl/dP ± U_A, µm/kN", "dΔl/dP ± U_A, мкм/кН")),
            ("icpt", bi("intercept ± U_A, mm", "начальная ордината ± U_A, мм")),
            ("sd", bi("residual s, µm", "ост. с. к. о., мкм")),
            ("curv", bi("curvature p / bend, %", "кривизна p / изгиб, %")),
            ("loop", bi("loop area, N·mm / share of work, %",
                        "площадь петли, Н·мм / доля работы, %")))
    return Table(bi("Least-squares lines of the gauges (type A only; the gauges' scale error "
                    "enters the stiffnesses) and their hysteresis loops (largest over the runs); "
                    "each branch's line leaves out its turning point, the mean is the line "
                    "midway between them",
                    "Прямые МНК по индикаторам (только тип A; погрешность масштаба индикаторов "
                    "входит в жесткости) и петли гистерезиса (наибольшие по циклам); прямая "
                    "каждой ветви — без её точки поворота, среднее — прямая посередине между "
                    "ними"),
                 cols, tuple(rows), "worked")


def _spring_table(data: Data) -> Table:
    sp = data.spring
    rows = []
    for k in range(sp.peak + 1):
        down = np.flatnonzero(np.isclose(sp.x[sp.peak:], sp.x[k], rtol=1e-9, atol=0.0))
        rows.append({"h": f"{1e3 * sp.x[k]:g}", "load": f"{sp.y[0, k]:.1f}",
                     "unload": f"{sp.y[0, sp.peak + down[-1]]:.1f}"
                     if down.size and down[-1] > 0 else "—"})
    cols = (("h", bi("h, mm", "h, мм")), ("load", bi("P loading, N", "P нагрузка, Н")),
            ("unload", bi("P unloading, N", "P разгрузка, Н")))
    share = _shown(data.results, "loop_share_spring", 0)
    return Table(bi(f"Valve springs' characteristic (loop: {share} % of the loading work)",
                    f"Характеристика клапанных пружин (петля: {share} % работы нагрузки)"),
                 cols, tuple(rows), "readings")


_MASS_TERMS = {"valve": (bi("valve", "клапан"), "m_кл"),
               "springs": (bi("springs / 3", "пружины / 3"), "m_n/3"),
               "rocker": (bi("rocker J/a²", "коромысло J/a²"), "J_кор/a²"),
               "rod": (bi("push rod", "штанга"), "(1 + 2i²c/c_г)(1/3) m_ш (i c/c_ш)²"),
               "cam": (bi("rod, tappet and camshaft at the cam", "штанга, толкатель и вал у "
                          "кулачка"), "(1 + 2i²c/c_г)(2/3 m_ш + m_m + m_г)(i c/c_г)²")}


def _mass_table(data: Data) -> Table:
    M = sum(data.mass_terms.values())
    rows = tuple({"part": _MASS_TERMS[k][0], "term": _MASS_TERMS[k][1], "g": f"{1e3 * x:.1f}",
                  "share": f"{100 * x / M:.1f}"} for k, x in data.mass_terms.items())
    cols = (("part", bi("Part", "Деталь")), ("term", bi("Term", "Слагаемое")),
            ("g", bi("reduced mass, g", "приведённая масса, г")),
            ("share", bi("share of M, %", "доля M, %")))
    return Table(bi("Oscillating mass reduced to the valve, term by term",
                    "Приведённая к клапану масса по слагаемым"), cols, rows, "worked")


def measurements(data: Data) -> list[Table]:
    """Each run as the manual tabulates it (the load steps, the gauges' readings loading and
    unloading, the links' deformations reduced to the valve) and the springs' characteristic."""
    out = [_run_table(data, r) for r in range(len(data.tables))]
    return out + ([_spring_table(data)] if data.spring is not None else [])


def tables(data: Data) -> list[Table]:
    """The links' stiffnesses, the gauges' lines and loops, the reduced mass's terms."""
    out = [_stiffness_table(data), _line_table(data)]
    if data.mass_terms:
        out.append(_mass_table(data))
    return out


# ------------------------------------------------------------------------ figures

def _words(lang: str) -> dict:
    return {"load": "loading" if lang == "en" else "нагрузка",
            "unload": "unloading" if lang == "en" else "разгрузка",
            "fit": "least squares (mean)" if lang == "en" else "МНК (среднее)",
            "N": "N" if lang == "en" else "Н", "mm": "mm" if lang == "en" else "мм"}


def _branches(ax, cycle: LoadCycle, row: int, scale: float, w: dict, legend: bool) -> None:
    """Both branches of one run, the loop shaded (x: the cycle's x, y: ``scale``·y[row])."""
    x_up, y_up = cycle.branch("load")
    x_dn, y_dn = cycle.branch("unload")
    ax.fill(cycle.x, scale * cycle.y[row], color="C1", alpha=0.12, lw=0)
    ax.plot(x_up, scale * y_up[row], "^-", color="C0", ms=4, lw=0.8,
            label=w["load"] if legend else None)
    ax.plot(x_dn, scale * y_dn[row], "v-", color="C3", ms=4, lw=0.8,
            label=w["unload"] if legend else None)


def _draw_gauges(fig, data: Data, lang: str) -> None:
    w = _words(lang)
    axes = fig.subplots(2, 2, sharex=True).ravel()
    top = np.array([0.0, max(t.x.max() for t in data.tables)])
    for j, ax in enumerate(axes):
        for r, t in enumerate(data.tables):
            _branches(ax, t, j, 1e3, w, r == 0)
        ax.plot(top, 1e3 * data.lines[j, "mean"].fit.predict(top), "k--", lw=1, label=w["fit"])
        ax.set_ylabel(f"Δl{_SUB[j]}, {w['mm']}")
        ax.grid(alpha=0.3)
        if j == 0:
            ax.legend(fontsize=7)
    for ax in axes[2:]:
        ax.set_xlabel(f"P, {w['N']}")
    fig.tight_layout()


def _draw_parts(fig, data: Data, lang: str) -> None:
    w = _words(lang)
    ax = fig.add_subplot(1, 1, 1)
    top = np.array([0.0, max(t.x.max() for t in data.tables)])
    for q, part in enumerate(PARTS):
        for P, parts in data.parts:
            ax.plot(P, 1e3 * parts[q], "o", color=f"C{q}", ms=3.5)
        if part in data.at_valve:
            c = data.at_valve[part]
            ax.plot(top, 1e3 * top / c, "-", color=f"C{q}", lw=1,
                    label=f"{_PART[part][0][lang]}: {c / 1e6:.2f} {'k' if lang == 'en' else 'к'}"
                          f"{w['N']}/{w['mm']}")
    ax.set_xlabel(f"P, {w['N']}")
    ax.set_ylabel("Δl at the valve, mm" if lang == "en" else "Δl у клапана, мм")
    ax.grid(alpha=0.3)
    if data.at_valve:
        ax.legend(fontsize=7)
    fig.tight_layout()


def _draw_chain(fig, data: Data, lang: str) -> None:
    ax = fig.add_subplot(1, 1, 1)
    res, red = data.results, data.at_valve
    names = [*PARTS, "total"]
    values = [red[p] / 1e6 for p in PARTS] + [res["c_total"].value / 1e6]
    err = [v * res[f"c_{p}"].estimate.relative_U for v, p in zip(values, names)]
    part, _ = weakest(red)
    colors = ["C3" if p == part else ("0.35" if p == "total" else "C0") for p in names]
    y = np.arange(len(names))[::-1]
    ax.barh(y, values, xerr=err, color=colors, capsize=3, alpha=0.85)
    total = sum(1 / v for v in red.values())
    for yi, p, v, e in zip(y, names, values, err):
        if p in red:
            ax.annotate(f"{100 / red[p] / total:.0f} %", (v + e, yi), xytext=(4, 0),
                        textcoords="offset points", va="center", fontsize=8)
    ax.set_yticks(y, [_PART[p][0][lang] for p in names])
    ax.set_xlabel("stiffness at the valve, kN/mm (label: share of the compliance)" if lang == "en"
                  else "жесткость, приведённая к клапану, кН/мм (подпись: доля податливости)")
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()


def _draw_spring(fig, data: Data, lang: str) -> None:
    w = _words(lang)
    ax = fig.add_subplot(1, 1, 1)
    sp = data.spring
    _branches(ax, LoadCycle(1e3 * sp.x, sp.y, sp.peak), 0, 1.0, w, True)
    h = np.array([sp.x.min(), sp.x.max()])
    ax.plot(1e3 * h, data.spring_lines[0, "mean"].fit.predict(h), "k--", lw=1, label=w["fit"])
    ax.set_xlabel(f"h, {w['mm']}")
    ax.set_ylabel(f"P, {w['N']}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()


def figures(data: Data) -> list[Figure]:
    """P–Δl of each gauge with both branches and the fit, the links' deformations at the
    valve, the chain of stiffnesses, and the springs' characteristic."""
    out = [
        Figure("gauges", bi("Δl = f(P) of the four gauges: loading (▲), unloading (▼), the loop "
                            "shaded, the least-squares line of their mean (dashed)",
                            "Δl = f(P) по четырём индикаторам: нагрузка (▲), разгрузка (▼), петля "
                            "затенена, прямая МНК по среднему (штрих)"),
               lambda fig, lang: _draw_gauges(fig, data, lang), size=(7.0, 5.2)),
        Figure("parts", bi("Deformations of the links reduced to the valve (the manual's Fig. 3): "
                           "mean of the branches (points) and the fitted stiffness (lines)",
                           "Приведённые к клапану деформации звеньев (рис. 3 методички): среднее "
                           "ветвей (точки) и найденная жесткость (линии)"),
               lambda fig, lang: _draw_parts(fig, data, lang)),
    ]
    if data.at_valve and "c_total" in data.results:
        out.append(Figure("chain", bi("The chain of stiffnesses at the valve (bars: ± U); "
                                      "red: the weakest link, the largest share of 1/c",
                                      "Цепь жесткостей, приведённых к клапану (отрезки: ± U); "
                                      "красным — самое слабое звено, наибольшая доля 1/c"),
                          lambda fig, lang: _draw_chain(fig, data, lang), size=(6.4, 3.2)))
    if data.spring is not None:
        out.append(Figure("spring", bi("Valve springs' characteristic P = f(h) (the manual's "
                                       "Fig. 5) with both branches and the fit",
                                       "Характеристика клапанных пружин P = f(h) (рис. 5 "
                                       "методички) с обеими ветвями и прямой МНК"),
                          lambda fig, lang: _draw_spring(fig, data, lang)))
    return out


# ------------------------------------------------------------------------ warnings

def gauge_backwards(j: int, slope: float) -> GaugeBackwardsWarning:
    """Gauge ``j`` (0…3) falls as the load rises (``slope`` [m/N])."""
    g, s = _GAUGE[j], 1e9 * slope
    return GaugeBackwardsWarning(
        f"gauge {j + 1} ({g['en']}) runs backwards: its reading falls as the load rises "
        f"(slope {s:.3g} µm/kN); the stiffnesses that use it are not reported. Check that its "
        "stem rests on the part on the side it moves towards and that the readings were not "
        "written as the dial's complement",
        f"индикатор {j + 1} ({g['ru']}) идёт в обратную сторону: показание падает с ростом "
        f"нагрузки (наклон {s:.3g} мкм/кН); жесткости с его участием не приводятся. Проверьте, "
        "что ножка упирается в деталь со стороны её перемещения и что не записаны дополнения "
        "показаний до полного оборота")


def spring_backwards(slope: float) -> GaugeBackwardsWarning:
    """The dynamometer's force falls as the valve is lifted (``slope`` [N/m])."""
    return GaugeBackwardsWarning(
        f"the springs' force falls as the valve is lifted (slope {slope / 1e3:.3g} N/mm): the "
        "dynamometer's indicator or the lift gauge is read the wrong way; c_n and ν are not "
        "reported. Check the direction of both indicators",
        f"усилие пружин падает с подъёмом клапана (наклон {slope / 1e3:.3g} Н/мм): индикатор "
        "динамометра или перемещения читается в обратную сторону; c_n и ν не приводятся. "
        "Проверьте направление обоих индикаторов")


def inconsistent_part(part: str) -> InconsistentInputWarning:
    """The reduced deformation of ``part`` ("rocker" or "rod") is not positive."""
    en, ru = {"rocker": ("gauge 1 reads less than gauges 2 and 3 carry to the valve",
                         "индикатор 1 показывает меньше, чем индикаторы 2 и 3 переносят на "
                         "клапан"),
              "rod": ("gauge 3 moves less than gauge 4",
                      "индикатор 3 перемещается меньше индикатора 4")}[part]
    return InconsistentInputWarning(
        f"the {_PART[part][0]['en']}'s deformation reduced to the valve is not positive: {en}; "
        "its stiffness is not reported. Check the rocker ratio i and the gauges' positions "
        "(gauge 3 at the push rod's upper end, under the rocker, gauge 4 at the cam)",
        f"приведённая деформация ({_PART[part][0]['ru']}) не положительна: {ru}; её жесткость "
        "не приводится. Проверьте передаточное отношение i и установку индикаторов (3 — у "
        "верхнего конца штанги, под коромыслом, 4 — у кулачка)")


def withheld(names) -> InconsistentInputWarning:
    """Results left out because they came out ≤ 0 or undefined."""
    shown = ", ".join(names)
    return InconsistentInputWarning(
        f"not reported: {shown} — they come out zero, negative or undefined from these tables "
        "(or rest on such a result), which no real part can have; see the other warnings for "
        "the gauge or field behind them",
        f"не приводятся: {shown} — по этим таблицам они выходят нулевыми, отрицательными или "
        "неопределёнными (или опираются на такой результат), чего у реальной детали не бывает; "
        "причину (индикатор или поле) называют другие предупреждения")


def _table_name(j: int | None) -> tuple[str, str]:
    """Gauge ``j`` (0…3) or, for None, the springs' characteristic, in English and Russian."""
    return (f"gauge {j + 1}", f"индикатор {j + 1}") if j is not None else ("springs", "пружины")


def bent_table(j: int | None, p_value: float, bend: float) -> TableCurvatureWarning:
    """The mean table of gauge ``j`` (0…3; None: the springs) bends."""
    en, ru = _table_name(j)
    return TableCurvatureWarning(
        f"{en}: the mean table bends (quadratic term p = {p_value:.2g}, {100 * bend:.1f} % of "
        "the rise): the stiffness depends on the load (contact stiffening of the ball ends and "
        "seats at low load, or a clearance closing); the straight line gives a secant "
        "stiffness over 0…P_max. Read the chart and quote the slope over the working range, or "
        "preload the chain before the first reading",
        f"{ru}: средняя характеристика искривлена (квадратичный член, p = {p_value:.2g}, "
        f"{100 * bend:.1f} % подъёма): жесткость зависит от нагрузки (контактная жесткость "
        "сферических опор при малой нагрузке или выбираемый зазор); прямая даёт секущую "
        "жесткость на 0…P_max. Смотрите график и указывайте наклон на рабочем участке или "
        "предварительно нагружайте привод")


def wide_loop(j: int | None, share: float, limit: float) -> LargeHysteresisWarning:
    """The widest loop of gauge ``j`` (0…3; None: the springs) takes ``share`` of the work."""
    en, ru = _table_name(j)
    return LargeHysteresisWarning(
        f"{en}: the loop between loading and unloading takes {100 * share:.0f} % of the loading "
        f"work (a sound chain of oiled joints: under {100 * limit:.0f} %): friction that large "
        "shifts each branch by its force; the line midway between them stays the elastic one "
        "only while the friction is the same along the stroke, and a binding joint's is not. "
        "Look for a binding rocker, a dry ball end or a sticking gauge stem; tap the rig "
        "lightly before each reading and repeat the run",
        f"{ru}: петля между нагрузкой и разгрузкой занимает {100 * share:.0f} % работы нагрузки "
        f"(у исправного привода со смазанными сочленениями — менее {100 * limit:.0f} %): такое "
        "трение сдвигает каждую ветвь на свою силу; прямая посередине между ветвями остаётся "
        "упругой, лишь пока трение одинаково по всему ходу, а у заедающего сочленения это не "
        "так. Ищите заедание коромысла, сухую сферическую опору или заедание ножки "
        "индикатора; слегка постукивайте по установке перед каждым отсчётом и повторите цикл")


# ------------------------------------------------------------------------ text

def conclusion(data: Data) -> list[dict]:
    """The conclusion's lines: c, the weakest link, c_n, M and ν, the hysteresis."""
    res = data.results
    lines = []
    if "c_total" in res:
        lines.append(bi(f"The drive's stiffness at the valve c = {result_pm(res, 'c_total')} kN/mm "
                        f"(loading {result_pm(res, 'c_total_load')}, unloading "
                        f"{result_pm(res, 'c_total_unload')})",
                        f"Жесткость привода, приведённая к клапану, c = {result_pm(res, 'c_total')} "
                        f"кН/мм (нагрузка {result_pm(res, 'c_total_load')}, разгрузка "
                        f"{result_pm(res, 'c_total_unload')})"))
    weak = weakest(data.at_valve)
    if weak is not None:
        part, share = weak
        lines.append(bi(f"The weakest link is the {_PART[part][0]['en']}: {100 * share:.0f} % of "
                        "the drive's compliance; stiffening it raises c the most",
                        f"Самое слабое звено — {_PART[part][0]['ru']}: {100 * share:.0f} % "
                        "податливости привода; его усиление сильнее всего повышает c"))
    if "c_spring" in res:
        lines.append(bi(f"Valve springs: c_n = {result_pm(res, 'c_spring')} N/mm, preload "
                        f"{result_pm(res, 'P_preload')} N",
                        f"Клапанные пружины: c_n = {result_pm(res, 'c_spring')} Н/мм, предварительное "
                        f"усилие {result_pm(res, 'P_preload')} Н"))
    if "f_natural" in res:
        order = bi("", "")
        if "cam_order" in res:
            n = data.inputs["engine"]["n"].value * 30 / np.pi
            k = res["cam_order"].value
            order = bi(f", {k:.1f} camshaft orders at {n:.0f} min⁻¹",
                       f", {k:.1f} порядка вращения распредвала при {n:.0f} мин⁻¹")
        lines.append(bi(f"M = {result_pm(res, 'M_reduced')} kg; the lowest natural frequency "
                        f"ν = {result_pm(res, 'nu_natural')} rad/s = {result_pm(res, 'f_natural')} Hz"
                        f"{order['en']}",
                        f"M = {result_pm(res, 'M_reduced')} кг; низшая собственная частота "
                        f"ν = {result_pm(res, 'nu_natural')} рад/с = {result_pm(res, 'f_natural')} Гц"
                        f"{order['ru']}"))
    share = _shown(res, "loop_share_max", 0)
    lines.append(bi(f"Loading and unloading do not coincide: the widest loop takes {share} % "
                    "of the loading work. Friction in the rocker bearing, the ball ends and the "
                    "tappet guide opposes the motion, so the chain carries less than P while "
                    "loaded and more while unloaded, and microslip in the contacts adds its own "
                    "loop; their mean is the elastic line",
                    f"Кривые нагрузки и разгрузки не совпадают: наибольшая петля — {share} % "
                    "работы нагрузки. Трение в опоре коромысла, сферических опорах штанги и "
                    "направляющей толкателя противодействует движению: при нагрузке звенья несут "
                    "меньше P, при разгрузке — больше; микропроскальзывание в контактах добавляет "
                    "свою петлю; упругой является средняя линия"))
    return lines


def input_rows(rows: list[dict], data: Data) -> list[dict]:
    """The input table with each typed table summarised by its header and length (the
    manual's table shows it whole); in the JSON, its columns in SI."""
    out = []
    for row in rows:
        if row["name"] != "table":
            out.append(row)
            continue
        if row["section"] == "spring":
            cycle, names = data.spring, ("h", "P")
        else:
            cycle, names = data.tables[int(row["section"][4:-1])], ("P", "dl1", "dl2", "dl3",
                                                                     "dl4")
        si = {names[0]: cycle.x.tolist(), **{n: y.tolist() for n, y in zip(names[1:], cycle.y)}}
        header = row["value"].strip().splitlines()[0].strip()
        new = {k: v for k, v in row.items() if k != "u"}
        new["value"] = f"{header} — {plural(cycle.x.size, ('row', 'rows'), 'en')}"
        new["value_label"] = bi(new["value"], f"{header} — "
                                f"{plural(cycle.x.size, ('строка', 'строки', 'строк'), 'ru')}")
        new["label"] = bi(f"{row['label']['en']} (SI in JSON: N, m)",
                          f"{row['label']['ru']} (в JSON — СИ: Н, м)")
        new["si"] = {"value": si, "u": None, "unit": "N, m", "readings": []}
        out.append(new)
    return out
