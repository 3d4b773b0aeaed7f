"""Lab 6's report: result labels, warnings' words, tables, figures and the conclusion.

Everything here lays out what :func:`labs.lab6_valve_dynamics.reduce` found, in the manual's
terms; nothing here reduces data.
"""
from __future__ import annotations

import math

import numpy as np

from processing.diagnostics import InconsistentInputWarning, TableCurvatureWarning
from processing.measurement import bi
from processing.reporting.content import fmt_pm, result_pm
from processing.result import KEY, STRICTLY_POSITIVE, Figure, Table, Within
from processing.diagnostics import ContactLossWarning, FreeOscillationWarning

RPM_SI = math.pi / 30
"""rad/s per min⁻¹."""

VALVE_WORDS = {"in": bi("inlet", "впускной"), "ex": bi("exhaust", "выпускной")}
VALVE_GENITIVE = {"in": "впускного", "ex": "выпускного"}
VALVE_SHORT_RU = {"in": "вп.", "ex": "вып."}
"""The valves as a Russian figure's legend names them."""

# ------------------------------------------------------------------------ the file's help

VALVE_HELP = bi(
    "One rocker with its strain gauge: its channel in the records, the springs' preload P0\n"
    "on the closed valve (lab 5's P_preload: the valve opens and closes where the force\n"
    "passes it), and the static calibration: known loads on the rocker and the trace's\n"
    "deflection read at each, in the record's unit (mm of oscillogram or V).",
    "Одно коромысло с тензодатчиком: его канал в записях, сила затяжки пружин P0 при\n"
    "закрытом клапане (P_preload из лаб. 5: клапан открывается и закрывается, когда сила\n"
    "проходит через неё) и статическая тарировка: известные нагрузки на коромысло и\n"
    "отклонение записи при каждой, в единицах записи (мм осциллограммы или В).")

RECORD_HELP = bi(
    "One regime: the force channel of each valve and the TDC marks (and the time marks, if\n"
    "recorded) in one file, at least two camshaft revolutions; n = 500, 1000, 1500, 1800\n"
    "and 2000 min⁻¹ at each clearance 0.3, 0.5 and 0.8 mm, full load.",
    "Один режим: канал силы каждого клапана и отметки ВМТ (и отметки времени, если\n"
    "записаны) в одном файле, не менее двух оборотов распределительного вала; n = 500, 1000,\n"
    "1500, 1800 и 2000 мин⁻¹ при каждом зазоре 0,3; 0,5 и 0,8 мм, полная нагрузка.")

# ------------------------------------------------------------------------ results

FORMULAS = [
    bi("Static calibration: k = dP/dA by a straight line through the loads P against the "
       "trace's deflections A; P = k A", "Статическая тарировка: k = dP/dA по прямой через "
       "нагрузки P и отклонения записи A; P = k A"),
    bi("Speed n = 60 N/(z T_mark): here from the TDC marks' times", "Частота вращения "
       "n = 60 N/(z T_отм): здесь по моментам отметок ВМТ"),
    bi("Drive's oscillation frequency ν = 60 N₁/(m T_mark): here a damped sinusoid "
       "x(t) = A e^{−δν t} cos(2πν t + ψ) + cubic fitted to the free oscillation after each "
       "opening", "Частота колебаний привода ν = 60 N₁/(m T_отм): здесь затухающая синусоида "
       "x(t) = A e^{−δν t} cos(2πν t + ψ) + кубический полином по свободным колебаниям после "
       "открытия"),
    bi("P_max = k A_max, P_min = k A_min (the least force while the valve is open); loss of "
       "contact where P ≤ 0", "P_max = k A_max, P_min = k A_min (наименьшая сила при открытом "
       "клапане); разрыв кинематической цепи там, где P ≤ 0"),
    bi("Opening φ = 360 T_open/T_cam (cam degrees; crank degrees twice that): the valve opens "
       "and closes where the force passes the springs' preload P₀", "Продолжительность "
       "открытия φ = 360 T_откр/T_рв (градусы поворота распределительного вала; коленчатого — "
       "вдвое больше): клапан открывается и закрывается при силе, равной затяжке пружин P₀"),
    bi("Separation speed: the line through the two fastest records that kept contact, "
       "n_sep = n₂ + P_min,2 (n₂ − n₁)/(P_min,1 − P_min,2)", "Частота вращения разрыва: прямая "
       "через два самых быстрых режима без разрыва, n_разр = n₂ + P_min,2 (n₂ − n₁)/"
       "(P_min,1 − P_min,2)"),
]

REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, "
       "lab 6.", "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. "
       "Владимир: ВлГУ, 2003. Лаб. работа «Исследование колебаний клапанного механизма "
       "двигателя»."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]


def _mm(clearance: float) -> str:
    return f"{1e3 * clearance:g}"


TIMING = Within(-math.pi / 2, math.pi / 2, "a valve opens and closes within 90° of crank of "
                "its dead centres (the manual's engines: 10–80°); check that the TDC marks are "
                "the cylinder's own, one a revolution at its TDC, and that each valve's channel "
                "is its own; a photograph taken as a mirror image (a front camera's mirror "
                "mode) reads backwards in time: flip it left to right")
"""Where a valve's opening advance and closing lag lie."""

POSITIVE_PER_VALVE = {**{name: (STRICTLY_POSITIVE,) for name in ("P_max", "nu", "phi",
                                                                 "phi_crank")},
                      "advance": (TIMING,), "lag": (TIMING,)}
"""A valve's results above zero by nature: its largest force (above the springs' preload),
the drive's frequency and the opening's duration; and its timing, which may lead or lag its
dead centre, but by less than :data:`TIMING`. P_min falls to zero where contact is lost, and
the angle without contact is zero with contact kept."""


def result_names(recorded, valves, seps) -> dict:
    """Labels, symbols and display units of this file's results. The speeds at which the
    drive separates are the key results; without them, the drive's oscillation frequency in
    the last record (the fastest, as the manual orders them)."""
    last = recorded[-1].number if recorded and not seps else None
    out = {f"k_{v}": (bi(f"trace scale k, {VALVE_WORDS[v]['en']} valve (N per unit of "
                         "the trace)", f"масштаб записи k, {VALVE_WORDS[v]['ru']} клапан "
                         "(Н на единицу записи)"), "k", "", STRICTLY_POSITIVE) for v in valves}
    for r in recorded:
        i = r.number
        out[f"n_{i}"] = (bi(f"speed, record {i}", f"частота вращения, режим {i}"), "n", "rpm",
                         STRICTLY_POSITIVE)
        for v in r.traces:
            w = VALVE_WORDS[v]
            where = bi(f"{w['en']}, record {i}", f"{w['ru']}, режим {i}")
            for name, en, ru, sym, unit in (
                    ("P_max", "largest force", "наибольшая сила", "P_max", "N"),
                    ("P_min", "least force while open", "наименьшая сила при открытом клапане",
                     "P_min", "N"),
                    ("nu", "drive's oscillation frequency", "частота колебаний привода", "ν",
                     "Hz"),
                    ("phi", "opening duration (cam)", "продолжительность открытия (р. вал)",
                     "φ", "deg"),
                    ("phi_crank", "opening duration (crank)",
                     "продолжительность открытия (к. вал)", "φ_кв", "deg"),
                    ("advance", "opening advance before the dead centre (crank)",
                     "опережение открытия до мёртвой точки (к. вал)", "φ_оп", "deg"),
                    ("lag", "closing lag after the dead centre (crank)",
                     "запаздывание закрытия после мёртвой точки (к. вал)", "φ_з", "deg"),
                    ("loss", "cam angle without contact", "угол р. вала без силового "
                     "замыкания", "φ_разр", "deg")):
                out[f"{name}_{v}_{i}"] = (bi(f"{en}, {where['en']}", f"{ru}, {where['ru']}"),
                                          sym, unit, *POSITIVE_PER_VALVE.get(name, ()),
                                          *((KEY,) if name == "nu" and i == last else ()))
    for s in seps:
        w = VALVE_WORDS[s.valve]
        out[s.name] = (bi(f"speed at which the drive separates, {w['en']} valve, δ = "
                          f"{_mm(s.clearance)} mm", f"частота вращения разрыва цепи, "
                          f"{w['ru']} клапан, δ = {_mm(s.clearance)} мм"), "n_разр", "rpm",
                   STRICTLY_POSITIVE, KEY)
    return out


# ------------------------------------------------------------------------ warnings

def speed_disagrees(where: str, omega: float, n: float) -> InconsistentInputWarning:
    gap = 100 * (omega / n - 1)
    return InconsistentInputWarning(
        f"{where}: the TDC marks give {omega / RPM_SI:.0f} min⁻¹, the tachometer "
        f"{n / RPM_SI:.0f} min⁻¹ ({gap:+.1f} %): check the tachometer reading and that the "
        "regime was steady",
        f"{where}: по отметкам ВМТ {omega / RPM_SI:.0f} мин⁻¹, по тахометру {n / RPM_SI:.0f} "
        f"мин⁻¹ ({gap:+.1f} %): проверьте показание тахометра и установившийся ли режим")


def bent_calibration(valve: str, bend) -> TableCurvatureWarning:
    w = VALVE_WORDS[valve]
    return TableCurvatureWarning(
        f"the {w['en']} valve's calibration bends (p = {bend.p_value:.2g}, "
        f"{100 * bend.relative_bend:.1f} % of its rise): the gauge or the amplifier is not "
        "linear over the loads, and one k misstates the forces at one end; lower the gain or "
        "check the gauge's bonding, and calibrate again",
        f"тарировка {VALVE_GENITIVE[valve]} клапана нелинейна (p = {bend.p_value:.2g}, "
        f"{100 * bend.relative_bend:.1f} % подъёма): датчик или усилитель нелинейны в "
        "диапазоне нагрузок, и один масштаб k искажает силы на краю; уменьшите усиление или "
        "проверьте наклейку датчика и повторите тарировку")


def contact_lost(lost, seps, results) -> ContactLossWarning:
    items = ", ".join(f"{i} ({v}, δ = {_mm(c)} mm, {w / RPM_SI:.0f} min⁻¹: "
                      f"{math.degrees(a):.1f}°)" for i, v, a, c, w in lost)
    items_ru = ", ".join(f"{i} ({VALVE_SHORT_RU[v]}, δ = {_mm(c)} мм, {w / RPM_SI:.0f} мин⁻¹: "
                         f"{math.degrees(a):.1f}°)" for i, v, a, c, w in lost)
    where = "; ".join(f"{s.valve}, δ = {_mm(s.clearance)} mm from about "
                      f"{results[s.name].value / RPM_SI:.0f} min⁻¹" for s in seps
                      if s.name in results)
    where_ru = "; ".join(f"{VALVE_SHORT_RU[s.valve]}, δ = {_mm(s.clearance)} мм — примерно с "
                         f"{results[s.name].value / RPM_SI:.0f} мин⁻¹" for s in seps
                         if s.name in results)
    return ContactLossWarning(
        f"the valve drive loses contact (P ≤ 0 while the valve is open) on records {items}"
        + (f"; it separates at {where}" if where else "")
        + ": the chain closes again with an impact that loads the parts beyond P_max's "
        "static share and wears the valve and its seat; reduce the clearance to the "
        "prescribed one, or do not run the engine above that speed",
        f"разрыв кинематической цепи привода (P ≤ 0 при открытом клапане) на режимах "
        f"{items_ru}" + (f"; разрыв начинается: {where_ru}" if where_ru else "")
        + ": цепь замыкается снова с ударом, который нагружает детали и изнашивает клапан и "
        "седло; установите предписанный зазор или не превышайте эту частоту вращения")


def poor_oscillation(poor, limit: float) -> FreeOscillationWarning:
    items = ", ".join(f"{i} ({v}: " + ("none fitted" if u is None else f"u {100 * u:.1f} %")
                      + ")" for i, v, u in poor)
    items_ru = ", ".join(f"{i} ({VALVE_SHORT_RU[v]}: " + ("не найдена" if u is None else f"u {100 * u:.1f} %")
                         + ")" for i, v, u in poor)
    return FreeOscillationWarning(
        f"records {items}: the drive's free oscillations are too few or too weak after the "
        f"opening (or the contact is lost first) for ν to better than {100 * limit:g} %; "
        "take ν from the other records, or record with a higher gain",
        f"режимы {items_ru}: свободных колебаний привода после открытия слишком мало или они "
        f"слишком слабы (или раньше наступает разрыв), чтобы найти ν точнее {100 * limit:g} %; "
        "возьмите ν по другим режимам или запишите с большим усилением")


# ------------------------------------------------------------------------ tables

def tables(*, recorded, results, **_) -> list[Table]:
    """The records: speed, clearance and, per valve, the forces, ν, φ, the timing and the
    losses of contact."""
    rows = []
    for r in recorded:
        i = r.number
        for v in r.traces:
            def cell(name, scale=1.0):
                return result_pm(results, f"{name}_{v}_{i}", scale)

            loss = results[f"loss_{v}_{i}"].value
            rows.append({"i": str(i), "valve": VALVE_WORDS[v], "delta": _mm(r.clearance),
                         "n": result_pm(results, f"n_{i}"), "events": str(len(r.traces[v].events)),
                         "Pmax": cell("P_max"), "Pmin": cell("P_min"), "nu": cell("nu"),
                         "phi": cell("phi"), "phic": cell("phi_crank"),
                         "adv": cell("advance"), "lag": cell("lag"),
                         "loss": f"{math.degrees(loss):.1f}" if loss > 0
                         else bi("none", "нет")})
    cols = (("i", bi("Record", "Режим")), ("valve", bi("Valve", "Клапан")),
            ("delta", bi("δ, mm", "δ, мм")), ("n", bi("n, min⁻¹", "n, мин⁻¹")),
            ("events", bi("openings read", "открытий")),
            ("Pmax", bi("P_max, N", "P_max, Н")), ("Pmin", bi("P_min, N", "P_min, Н")),
            ("nu", bi("ν, Hz", "ν, Гц")), ("phi", bi("φ (cam), °", "φ (р. вал), °")),
            ("phic", bi("φ (crank), °", "φ (к. вал), °")),
            ("adv", bi("opening advance, °", "опережение открытия, °")),
            ("lag", bi("closing lag, °", "запаздывание закрытия, °")),
            ("loss", bi("without contact (cam), °", "разрыв (р. вал), °")))
    return [Table(bi("Records (± U)", "Осциллограммы (± U)"), cols, rows)]


# ------------------------------------------------------------------------ figures

def _t(lang, en, ru):
    return en if lang == "en" else ru


def _draw_calibration(fig, valves, lang):
    ax = fig.subplots()
    for v, spec in valves.items():
        A = np.asarray(spec["deflection"].readings)
        P = np.asarray(spec["load"].readings)
        ax.plot(A, P, "o", label=f"{VALVE_WORDS[v][lang]}")
        grid = np.linspace(A.min(), A.max(), 20)
        ax.plot(grid, spec["fit"].predict(grid), "-", lw=1, label=f"k = {spec['k']:.4g}")
    ax.set_xlabel(_t(lang, "trace deflection A (record's unit)",
                     "отклонение записи A (единицы записи)"))
    ax.set_ylabel(_t(lang, "load P, N", "нагрузка P, Н"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def _showcase(recorded):
    """Per clearance, the fastest record (the one most likely to have lost contact)."""
    out = {}
    for r in recorded:
        if r.clearance not in out or r.speed.value > out[r.clearance].speed.value:
            out[r.clearance] = r
    return [out[c] for c in sorted(out)]


def _draw_traces(fig, recorded, results, lang):
    shown = _showcase(recorded)
    axes = fig.subplots(len(shown), 1, sharex=False, squeeze=False)[:, 0]
    for ax, r in zip(axes, shown):
        v = next(iter(r.traces))
        tr = r.traces[v]
        k = results[f"k_{v}"].value
        e = tr.events[0]
        pad = 0.15 * (e.closing - e.opening)
        keep = (tr.time >= e.opening - pad) & (tr.time <= e.closing + pad)
        cam = r.speed.value / 2
        angle = np.degrees((tr.time[keep] - e.opening) * cam)
        P = k * tr.value[keep]
        ax.plot(angle, P, lw=0.7, color="tab:blue")
        ax.axhline(0, color="0.3", lw=0.6)
        lost = P <= 0
        inside = (tr.time[keep] > e.opening) & (tr.time[keep] < e.closing)
        if (lost & inside).any():
            ax.plot(angle[lost & inside], P[lost & inside], "o", ms=4, color="tab:red",
                    label=_t(lang, "P ≤ 0: contact lost", "P ≤ 0: разрыв цепи"))
            ax.legend(fontsize=7, loc="upper right")
        ax.plot(np.degrees((e.t_max - e.opening) * cam), k * e.P_max, "v", color="k", ms=4)
        ax.plot(np.degrees((e.t_min - e.opening) * cam), k * e.P_min, "^", color="k", ms=4)
        ax.set_ylabel(_t(lang, "P, N", "P, Н"), fontsize=8)
        ax.set_title(_t(lang, f"record {r.number}: {VALVE_WORDS[v]['en']}, δ = "
                              f"{_mm(r.clearance)} mm, {r.speed.value / RPM_SI:.0f} min⁻¹",
                        f"режим {r.number}: {VALVE_WORDS[v]['ru']}, δ = {_mm(r.clearance)} мм, "
                        f"{r.speed.value / RPM_SI:.0f} мин⁻¹"), fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(_t(lang, "cam angle from the opening, °",
                           "угол р. вала от открытия, °"))


def _by_clearance(recorded, valve):
    groups = {}
    for r in recorded:
        if valve in r.traces:
            groups.setdefault(r.clearance, []).append(r)
    return {c: sorted(g, key=lambda r: r.speed.value) for c, g in sorted(groups.items())}


def _valves_of(recorded) -> list[str]:
    return [v for v in VALVE_WORDS if any(v in r.traces for r in recorded)]


def _draw_forces(fig, recorded, results, seps, lang):
    valves = _valves_of(recorded)
    axes = fig.subplots(len(valves), 1, sharex=True, squeeze=False)[:, 0]
    for ax, v in zip(axes, valves):
        for j, (c, recs) in enumerate(_by_clearance(recorded, v).items()):
            n = np.array([r.speed.value / RPM_SI for r in recs])
            for name, style in (("P_max", "o-"), ("P_min", "s--")):
                got = [f"{name}_{v}_{r.number}" in results for r in recs]
                keys = [f"{name}_{v}_{r.number}" for r, ok in zip(recs, got) if ok]
                val = np.array([results[k].value for k in keys])
                U = np.array([results[k].estimate.U for k in keys])
                ax.errorbar(n[got], val, U, fmt=style, ms=4, lw=1, capsize=2, color=f"C{j}",
                            label=f"{name}, δ = {_mm(c)}")
        for s in seps:
            if s.name in results and s.valve == v:
                n_sep = results[s.name].value / RPM_SI
                ax.axvline(n_sep, color="tab:red", lw=0.9, ls=":",
                           label=_t(lang, f"separation, δ = {_mm(s.clearance)}: {n_sep:.0f}",
                                    f"разрыв, δ = {_mm(s.clearance)}: {n_sep:.0f}"))
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(_t(lang, f"force, N ({v})", f"сила, Н ({VALVE_WORDS[v]['ru']})"))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
    axes[-1].set_xlabel(_t(lang, "n, min⁻¹", "n, мин⁻¹"))


def _draw_phases(fig, recorded, results, lang):
    ax = fig.subplots()
    for v in ("in", "ex"):
        for c, recs in _by_clearance(recorded, v).items():
            n = np.array([r.speed.value / RPM_SI for r in recs])
            val = np.degrees([results[f"phi_crank_{v}_{r.number}"].value for r in recs])
            U = np.degrees([results[f"phi_crank_{v}_{r.number}"].estimate.U for r in recs])
            ax.errorbar(n, val, U, fmt="o-", ms=4, lw=1, capsize=2,
                        label=f"φ {v if lang == 'en' else VALVE_SHORT_RU[v]}, δ = {_mm(c)}")
    ax.set_xlabel(_t(lang, "n, min⁻¹", "n, мин⁻¹"))
    ax.set_ylabel(_t(lang, "opening duration, crank °", "продолжительность открытия, ° п.к.в."))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def figures(*, recorded, valves, results, seps, **_) -> list[Figure]:
    """The calibration, the force traces with the contact losses marked, P_max and P_min
    against n per clearance with the separation speeds, and φ against n."""
    height = 1.0 + 1.6 * len({r.clearance for r in recorded})
    return [
        Figure("calibration", bi("Static calibration: the load against the trace's deflection "
                                 "and the line whose slope is the scale k",
                                 "Статическая тарировка: нагрузка по отклонению записи и "
                                 "прямая, наклон которой — масштаб k"),
               lambda fig, lang: _draw_calibration(fig, valves, lang), size=(5.6, 3.4)),
        Figure("traces", bi("The force in the drive over one opening, the fastest record of "
                            "each clearance (▼ P_max, ▲ P_min; red: no contact, P ≤ 0)",
                            "Сила в приводе за одно открытие, самый быстрый режим каждого "
                            "зазора (▼ P_max, ▲ P_min; красным — разрыв цепи, P ≤ 0)"),
               lambda fig, lang: _draw_traces(fig, recorded, results, lang),
               size=(6.4, height)),
        Figure("forces", bi("P_max (solid) and P_min (dashed) against n for each clearance "
                            "(± U); dotted: the speeds where the drive separates",
                            "P_max (сплошные) и P_min (штриховые) в зависимости от n при "
                            "каждом зазоре (± U); пунктир — частоты вращения разрыва цепи"),
               lambda fig, lang: _draw_forces(fig, recorded, results, seps, lang),
               size=(6.4, 1.0 + 2.6 * len(_valves_of(recorded)))),
        Figure("phases", bi("Opening durations (crank degrees) against n for each clearance",
                            "Продолжительность открытия (° п.к.в.) в зависимости от n при "
                            "каждом зазоре"),
               lambda fig, lang: _draw_phases(fig, recorded, results, lang)),
    ]


# ------------------------------------------------------------------------ conclusion

def conclusion(*, recorded, results, seps, **_) -> list[dict]:
    """The drive's frequency, the forces' extremes, the separation speeds and the clearance's
    effect on the opening."""
    lines = []
    nus = [results[k] for k in results if k.startswith("nu_")]
    if nus:
        w = np.array([1 / r.u**2 for r in nus if r.u > 0])
        if w.size:
            mean = float(np.sum(w * [r.value for r in nus if r.u > 0]) / w.sum())
            v, U = fmt_pm(mean, 2 / math.sqrt(w.sum()))
            lines.append(bi(f"The drive's free oscillations: ν = {v} ± {U} Hz (the records' "
                            "weighted mean)", f"Свободные колебания привода: ν = {v} ± {U} Гц "
                            "(взвешенное среднее по режимам)"))
    top = max((k for k in results if k.startswith("P_max_")), default=None,
              key=lambda k: results[k].value)
    low = min((k for k in results if k.startswith("P_min_")), default=None,
              key=lambda k: results[k].value)
    forces = ([(f"Largest force {results[top].value:.0f} N ({top})",
                f"Наибольшая сила {results[top].value:.0f} Н ({top})")] if top else []) + \
        ([(f"least force while open {results[low].value:.0f} N ({low})",
           f"наименьшая при открытом клапане {results[low].value:.0f} Н ({low})")] if low else [])
    if forces:
        en, ru = ("; ".join(part) for part in zip(*forces))
        lines.append(bi(en[0].upper() + en[1:], ru[0].upper() + ru[1:]))
    for s in seps:
        if s.name in results:
            r = results[s.name]
            v, U = fmt_pm(r.value / RPM_SI, r.estimate.U / RPM_SI)
            w = VALVE_WORDS[s.valve]
            lines.append(bi(f"The {w['en']} drive separates at δ = {_mm(s.clearance)} mm from "
                            f"n = {v} ± {U} min⁻¹", f"Разрыв цепи привода ({w['ru']} клапан) "
                            f"при δ = {_mm(s.clearance)} мм начинается с n = {v} ± {U} мин⁻¹"))
    if not seps:
        lines.append(bi("The drive kept contact on every record", "Разрывов кинематической "
                        "цепи ни на одном режиме нет"))
    for v in ("in", "ex"):
        groups = _by_clearance(recorded, v)
        if len(groups) > 1:
            phi = {c: np.mean([results[f"phi_crank_{v}_{r.number}"].value for r in g])
                   for c, g in groups.items()}
            text = ", ".join(f"{math.degrees(p):.1f}° at {_mm(c)} mm" for c, p in phi.items())
            text_ru = ", ".join(f"{math.degrees(p):.1f}° при {_mm(c)} мм"
                                for c, p in phi.items())
            w = VALVE_WORDS[v]
            lines.append(bi(f"The {w['en']} valve opens for {text} (crank): a larger clearance "
                            "shortens the opening and lets the lash close at a higher "
                            "velocity", f"{w['ru'].capitalize()} клапан открыт {text_ru} "
                            "(п.к.в.): больший зазор укорачивает открытие, и зазор выбирается "
                            "с большей скоростью"))
    return lines
