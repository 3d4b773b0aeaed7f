"""Lab 7's report: result labels, warnings' words, tables, figures and the conclusion.

Everything here lays out what :func:`labs.lab7_torsiograph.reduce` found, in the manual's
terms; nothing here reduces data.
"""
from __future__ import annotations

import numpy as np

from processing.diagnostics import (BaselineDriftWarning, InconsistentInputWarning,
                                    MixedOrdersWarning, NoiseFloorWarning,
                                    ResonanceBeyondSweepWarning,
                                    ShortRecordWarning, TorsiographResponseWarning,
                                    UnresolvedResonanceWarning)
from processing.measurement import bi
from processing.reporting.content import fmt_pm, result_pm
from processing.torsional.resonance import campbell_lines
from processing.result import KEY, STRICTLY_POSITIVE, Figure, Table, computed

RPM = 30 / np.pi
"""min⁻¹ per rad/s."""

LOAD_WORDS = {"idle": bi("idle", "холостой ход"), "part": bi("part load", "частичная нагрузка"),
              "full": bi("full load", "полная нагрузка")}

# ------------------------------------------------------------------------ the file's help

CALIBRATION_HELP = bi(
    "The case is turned against the locked inertia mass by a micrometer screw on a lever of\n"
    "radius R: φ = h/R. Write each rise h and the trace's deflection read at it, in the\n"
    "record's own unit (V for a recorder, mm for an oscillogram's paper). Needed with records.",
    "Корпус поворачивают относительно застопоренной инерционной массы микрометрическим\n"
    "винтом на рычаге длиной R: φ = h/R. Запишите каждый подъём h и отклонение записи при нём\n"
    "в единицах записи (В для регистратора, мм для бумаги осциллографа). Нужна при записях.")

TORSIOGRAPH_HELP = bi(
    "The torsiograph's own natural frequency and damping, and the recorder's marks. Needed\n"
    "with records.",
    "Собственная частота и демпфирование торсиографа, отметки регистратора. Нужны при\n"
    "записях.")

CHAIN_HELP = bi(
    "The crankshaft's equivalent torsional system, from the nose (damper hub) to the\n"
    "flywheel: n moments of inertia J and n − 1 shaft stiffnesses c between them (n if the\n"
    "flywheel is tied to a brake); one disc per crank, in cylinder order, after the hub.\n"
    "Its natural frequencies are compared with the resonances; alone, without records (before\n"
    "the test), it gives its modes, the orders' relative phase sums and the critical speeds.",
    "Эквивалентная крутильная система коленчатого вала от носка (ступицы демпфера) до\n"
    "маховика: n моментов инерции J и n − 1 жёсткостей c участков между ними (n, если маховик\n"
    "соединён с тормозом); по одной массе на кривошип в порядке цилиндров после ступицы.\n"
    "Её собственные частоты сравниваются с резонансами; одна, без записей (до опыта), она даёт\n"
    "формы колебаний, относительные фазовые суммы гармоник и критические частоты вращения.")

RECORD_HELP = bi(
    "One steady regime: the torsiograph's channel and the TDC marks (and the time marks, if\n"
    "recorded) in one file; every 200 min⁻¹ from the lowest to the highest speed, finer near\n"
    "a resonance, at each load. Optional: a [chain] alone gives the natural frequencies and\n"
    "critical speeds before the test.",
    "Один установившийся режим: канал торсиографа и отметки ВМТ (и отметки времени, если\n"
    "записаны) в одном файле; через 200 мин⁻¹ от наименьшей до наибольшей частоты вращения,\n"
    "чаще вблизи резонанса, на каждой нагрузке. Необязательно: одна [chain] даёт собственные\n"
    "частоты и критические частоты вращения до опыта.")

# ------------------------------------------------------------------------ results

FORMULAS = [
    bi("Static calibration: φ = h/R; trace scale l = (1/R) dh/dA_k by a straight line through "
       "the calibration", "Статическая тарировка: φ = h/R; масштаб записи l = (1/R) dh/dA_k по "
       "прямой через точки тарировки"),
    bi("Speed n = 60 N/(z T_mark): here the TDC marks' times; oscillation frequency "
       "ν = 60 N_k/(m T_mark): here a line through the times of the extrema (each half a "
       "period after the last)", "Частота вращения n = 60 N/(z T_отм): здесь по моментам "
       "отметок ВМТ; частота колебаний ν = 60 N_k/(m T_отм): здесь по прямой через моменты "
       "экстремумов (через полпериода)"),
    bi("Resonating order K = ν/n; amplitude A = l A_k", "Порядок резонирующей гармоники "
       "K = ν/n; амплитуда A = l A_k"),
    bi("Harmonic analysis: x(t) = Σ_k Re(c_k e^{ikθ(t)}) + drift(t), k = 0.5, 1, 1.5, … "
       "(least squares on the crank angle θ of every sample, a Legendre polynomial for the "
       "drift); the torsiograph's correction c_k/H(k n/60), H(f) = r²/(r² − 1 − 2iζr), "
       "r = f/f_c", "Гармонический анализ: x(t) = Σ_k Re(c_k e^{ikθ(t)}) + дрейф(t), "
       "k = 0,5; 1; 1,5; … (МНК по углу поворота θ каждого отсчёта, дрейф — полином "
       "Лежандра); поправка на торсиограф c_k/H(k n/60), H(f) = r²/(r² − 1 − 2iζr), r = f/f_c"),
    bi("Peak amplitude A_ij = |S_i − (h_i + (h_{i+1} − h_i)(s_i − s'_i)/(s'_{i+1} − s'_i))|/2: "
       "half the distance from an extremum to the line through its neighbouring opposite "
       "extrema (the drift taken out); φ_max = l · max A_ij over the record's single "
       "oscillations (its white noise taken out by spectral subtraction)",
       "Пиковая амплитуда A_ij = |S_i − (h_i + (h_{i+1} − h_i)(s_i − s'_i)/(s'_{i+1} − s'_i))|/2: "
       "половина расстояния от экстремума до прямой через соседние противоположные "
       "экстремумы (дрейф исключён); φ_max = l · max A_ij по отдельным колебаниям записи "
       "(белый шум вычтен по спектру)"),
    bi("Resonance: 1/A_k² = c₀ + c₁n + c₂n² through the records around the peak, "
       "n_res = −c₁/(2c₂); natural frequency f = K n_res/60", "Резонанс: 1/A_k² = c₀ + c₁n + "
       "c₂n² по режимам около пика, n_res = −c₁/(2c₂); собственная частота f = K n_res/60"),
    bi("Equivalent system: K v = ω² M v (natural frequencies and mode shapes); major orders: "
       "|Σ_c e^{ikφ_c}| = i (all cylinders in phase)", "Эквивалентная система: K v = ω² M v "
       "(собственные частоты и формы); главные порядки: |Σ_c e^{ikφ_c}| = i (все цилиндры в "
       "фазе)"),
]

REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, "
       "lab 7.", "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. "
       "Владимир: ВлГУ, 2003. Лаб. работа «Экспериментальное исследование крутильных "
       "колебаний коленчатого вала»."),
    bi("W. Ker Wilson, Practical Solution of Torsional Vibration Problems, 3rd ed., Chapman & "
       "Hall, 1956–1965 (equivalent systems, phase diagrams, torsiographs).",
       "W. Ker Wilson, Practical Solution of Torsional Vibration Problems, 3rd ed., Chapman & "
       "Hall, 1956–1965 (эквивалентные системы, фазовые диаграммы, торсиографы)."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]


def critical_names(mode: int, order: float) -> tuple[str, str]:
    """The result names of a mode's relative phase sum and critical speed for an order: a
    half order's point written as an underscore (a result name is a TOML key in [reported])."""
    k = f"{order:g}".replace(".", "_")
    return f"phase_sum_{mode}_{k}", f"n_crit_{mode}_{k}"


def result_names(recorded, found, modes, criticals=()) -> dict:
    """Labels, symbols and display units of the results of this file's records, resonances
    and chain (every one of them above zero by its nature but the phase sums); the design
    amplitude φ_max and the resonances found are the key results."""
    out = {}
    if recorded:
        out = {"l": (bi("trace scale l (angle per unit of the trace)",
                        "масштаб записи l (угол на единицу записи)"), "l", "",
                     STRICTLY_POSITIVE),
               "phi_max": (bi("largest peak amplitude over the records (the design value)",
                              "наибольшая пиковая амплитуда по всем режимам (расчётная)"),
                           "φ_max", "mrad", STRICTLY_POSITIVE, KEY)}
    for r in recorded:
        i = r.number
        out.update({
            f"n_{i}": (bi(f"speed, record {i}", f"частота вращения, режим {i}"), "n", "rpm",
                       STRICTLY_POSITIVE),
            f"nu_{i}": (bi(f"oscillation frequency by counting, record {i}",
                           f"частота колебаний по подсчёту, режим {i}"), "ν", "Hz",
                        STRICTLY_POSITIVE),
            f"K_{i}": (bi(f"oscillations per revolution K = ν/n, record {i}",
                          f"число колебаний за оборот K = ν/n, режим {i}"), "K", "",
                       STRICTLY_POSITIVE),
            f"phi_max_{i}": (bi(f"largest peak amplitude, record {i}",
                                f"наибольшая пиковая амплитуда, режим {i}"), "φ_max", "mrad",
                             STRICTLY_POSITIVE),
        })
    for f in found:
        j = f.number
        out.update({
            f"n_res_{j}": (bi(f"resonance {j}: speed", f"резонанс {j}: частота вращения"),
                           "n_res", "rpm", STRICTLY_POSITIVE, KEY),
            f"K_res_{j}": (bi(f"resonance {j}: order", f"резонанс {j}: порядок гармоники"),
                           "K", "", STRICTLY_POSITIVE),
            f"f_res_{j}": (bi(f"resonance {j}: natural frequency K n_res/60",
                              f"резонанс {j}: собственная частота K n_res/60"), "f", "Hz",
                           STRICTLY_POSITIVE, KEY),
        })
    if modes is not None:
        for m in range(1, modes.angular_frequency.shape[-1] + 1):
            out[f"f_model_{m}"] = (bi(f"natural frequency of mode {m} (equivalent system)",
                                      f"собственная частота {m}-й формы (эквивалентная "
                                      "система)"), f"f_{m}", "Hz", STRICTLY_POSITIVE)
    for m, k in criticals:
        phase_sum, n_crit = critical_names(m, k)
        out[phase_sum] = (bi(f"relative phase sum of order {k:g}, mode {m}",
                             f"относительная фазовая сумма гармоники порядка {k:g}, форма {m}"),
                          f"Σ_{k:g}", "")
        out[n_crit] = (bi(f"critical speed of order {k:g}, mode {m} (60 f_{m}/k)",
                          f"критическая частота вращения гармоники порядка {k:g}, форма {m} "
                          f"(60 f_{m}/k)"), f"n_{k:g}", "rpm", STRICTLY_POSITIVE)
    return out


def model_pairs(found, modes) -> list[tuple[str, str]]:
    """Each resonance's natural frequency against the chain's nearest mode."""
    if modes is None:
        return []
    f = modes.frequency
    return [(f"f_res_{r.number}",
             f"f_model_{int(np.argmin(np.abs(f - r.resonance.frequency))) + 1}")
            for r in found]


# ------------------------------------------------------------------------ warnings

def _list(items) -> str:
    return ", ".join(str(i) for i in items)


def speed_disagrees(where: str, omega: float, n: float) -> InconsistentInputWarning:
    gap = 100 * (omega / n - 1)
    return InconsistentInputWarning(
        f"{where}: the TDC marks give {omega * RPM:.0f} min⁻¹, the tachometer {n * RPM:.0f} "
        f"min⁻¹ ({gap:+.1f} %): check the tachometer reading and that the regime was steady",
        f"{where}: по отметкам ВМТ {omega * RPM:.0f} мин⁻¹, по тахометру {n * RPM:.0f} мин⁻¹ "
        f"({gap:+.1f} %): проверьте показание тахометра и установившийся ли режим")


def response_warning(low, ratio: float) -> TorsiographResponseWarning:
    worst = min(r for _, r in low)
    records = _list(i for i, _ in low)
    return TorsiographResponseWarning(
        f"records {records}: orders carrying the record lie only {worst:.1f} times above the "
        f"torsiograph's own frequency f_c (the manual asks for {ratio:g}–10): their amplitudes "
        "rest on the transfer function's correction, and f_c and ζ enter φ_max's uncertainty; "
        "use a softer torsiograph or measure f_c and ζ from its free oscillations",
        f"режимы {records}: несущие гармоники лишь в {worst:.1f} раза выше собственной частоты "
        f"торсиографа f_c (по методичке — в {ratio:g}–10 раз): их амплитуды держатся на "
        "поправке по передаточной функции, а f_c и ζ входят в погрешность φ_max; возьмите "
        "более мягкий торсиограф или определите f_c и ζ по его свободным колебаниям")


def short_warning(short, cycles: int) -> ShortRecordWarning:
    records = _list(f"{i} ({c:.1f})" for i, c in short)
    return ShortRecordWarning(
        f"records {records} span fewer than {cycles} working cycles: a drift reaching the "
        "half orders is no longer told from them, and their order amplitudes (the "
        "amplitude–speed curve, the resonances) may be off by more than their uncertainty "
        f"(φ_max is read from the single oscillations); record at least {cycles} working "
        "cycles",
        f"режимы {records} короче {cycles} рабочих циклов: дрейф, доходящий до полупорядковых "
        "гармоник, от них уже не отличить, и амплитуды гармоник (амплитудно-частотная "
        "характеристика, резонансы) могут отличаться больше своей погрешности (φ_max "
        f"найдена по отдельным колебаниям); записывайте не менее {cycles} рабочих циклов")


def orders_left_out(bare, cycles: int) -> ShortRecordWarning:
    records = _list(f"{i} ({c:.1f})" for i, c in bare)
    return ShortRecordWarning(
        f"records {records} span fewer than {cycles} working cycles, too few to tell their "
        "half orders from the drift: the harmonic analysis is left out, and φ_max, ν and K "
        "come from their single oscillations alone (they join neither the order curves nor "
        f"the resonances); record at least {cycles} working cycles for the orders",
        f"режимы {records} короче {cycles} рабочих циклов — слишком мало, чтобы отличить "
        "полупорядковые гармоники от дрейфа: гармонический анализ не выполнен, φ_max, ν и K "
        "найдены только по отдельным колебаниям (в кривые гармоник и резонансы эти режимы не "
        f"входят); для гармоник записывайте не менее {cycles} рабочих циклов")


def amplitude_in_noise(vague) -> NoiseFloorWarning:
    records = _list(f"{i} (U/φ = {ratio:.1f})" for i, ratio in vague)
    return NoiseFloorWarning(
        f"records {records}: the largest single oscillation is not known better than its "
        "own size (U ≥ φ_max): the trace barely rises out of its noise or its ripples, and "
        "φ_max there is no design value; raise the amplifier's gain, or record a steadier "
        "regime",
        f"режимы {records}: наибольшее отдельное колебание известно не точнее собственной "
        "величины (U ≥ φ_max): запись едва выходит из шума или ряби, и φ_max там не годится "
        "как расчётная; увеличьте усиление или запишите более устойчивый режим")


def drift_warning(drifting) -> BaselineDriftWarning:
    records = _list(f"{i} (×{d:.1f}, u {100 * u:.1f} %)" for i, d, u in drifting)
    return BaselineDriftWarning(
        f"records {records}: the baseline drifts by more than the oscillation's range and "
        "reaches the orders' frequencies, so φ_max is uncertain by the share given: balance "
        "the bridge, let the amplifier warm up and record again",
        f"режимы {records}: нулевая линия смещается больше размаха колебаний и доходит до "
        "частот гармоник, поэтому φ_max неточна на указанную долю: сбалансируйте мост, "
        "прогрейте усилитель и повторите запись")


def unread_warning(records) -> BaselineDriftWarning:
    text = _list(records)
    return BaselineDriftWarning(
        f"records {text}: the drift is steeper than the oscillation, so the trace has no single "
        "oscillations to count: ν and K = ν/n are not given (φ_max comes from the harmonic "
        "analysis, with the uncertainty the drift leaves); record again with a settled "
        "baseline",
        f"режимы {text}: дрейф круче колебаний, и на записи нет отдельных колебаний для "
        "подсчёта: ν и K = ν/n не определены (φ_max найдена гармоническим анализом с "
        "погрешностью, которую оставляет дрейф); повторите запись при установившемся нуле")


def mixed_warning(mixed) -> MixedOrdersWarning:
    records = _list(f"{i} (K = {k:.2f}, order {o:g})" for i, k, o in mixed)
    records_ru = _list(f"{i} (K = {k:.2f}, порядок {o:g})" for i, k, o in mixed)
    return MixedOrdersWarning(
        f"records {records} at resonance peaks: the curve is not one sine, and counting its "
        "oscillations gives a K = ν/n that is not the resonating order; the harmonic analysis "
        "gives the order named, and the resonances are located by it",
        f"режимы {records_ru} на пиках резонансов: кривая не синусоида, и подсчёт колебаний "
        "даёт K = ν/n, не равное порядку резонирующей гармоники; гармонический анализ даёт "
        "указанный порядок, по нему и найдены резонансы")


def unresolved_warning(found) -> UnresolvedResonanceWarning:
    r = found.resonance
    where = (f"{r.width * RPM:.0f} min⁻¹ wide against a step of {r.step * RPM:.0f} min⁻¹"
             if np.isfinite(r.width) else "not closed by the records around it")
    where_ru = (f"шириной {r.width * RPM:.0f} мин⁻¹ при шаге {r.step * RPM:.0f} мин⁻¹"
                if np.isfinite(r.width) else "не замкнут соседними режимами")
    return UnresolvedResonanceWarning(
        f"resonance {found.number} (order {r.order:g}, ≈ {r.speed * RPM:.0f} min⁻¹) is "
        f"{where}{'' if r.dominates else ', and fell between the records'}: its speed and "
        "natural frequency are uncertain; record every 50 min⁻¹ around it",
        f"резонанс {found.number} (порядок {r.order:g}, ≈ {r.speed * RPM:.0f} мин⁻¹) "
        f"{where_ru}{'' if r.dominates else ' и пришёлся между режимами'}: его частота "
        "вращения и собственная частота неточны; запишите режимы через 50 мин⁻¹ около него")


def edge_warning(load: str, edge) -> ResonanceBeyondSweepWarning:
    side = {"low": ("below the lowest", "ниже наименьшей"),
            "high": ("above the highest", "выше наибольшей")}[edge.side]
    return ResonanceBeyondSweepWarning(
        f"{LOAD_WORDS[load]['en']}: order {edge.order:g} dominates record {edge.index} and "
        f"still rises there as n^{edge.slope:+.1f}: a resonance lies {side[0]} speed recorded; "
        "extend the sweep",
        f"{LOAD_WORDS[load]['ru']}: гармоника порядка {edge.order:g} преобладает в режиме "
        f"{edge.index} и ещё растёт как n^{edge.slope:+.1f}: резонанс лежит {side[1]} "
        "записанной частоты вращения; расширьте диапазон")


# ------------------------------------------------------------------------ tables

def record_results(recorded, found, results, f_c) -> dict:
    """What the records' and resonances' tables state besides the propagated results: each
    record's largest amplitude in its mean cycle (``phi_cycle_<i>``), its baseline drift over
    its range (``drift_ratio_<i>``), its lowest carrying frequency over f_c
    (``carrying_ratio_<i>``); each resonance's width at 0.7 of its peak (``width_res_<j>``).
    Undefined ones are left out."""
    values, declared = {}, {}
    for r in recorded:
        t, i = r.trace, r.number
        if t.cycle is not None:
            values[f"phi_cycle_{i}"] = results["l"].value * t.cycle.largest
            declared[f"phi_cycle_{i}"] = (bi(f"largest amplitude of the mean cycle, record {i}",
                                             f"наибольшая амплитуда среднего цикла, режим {i}"),
                                          "φ_ц", "mrad")
        values[f"drift_ratio_{i}"] = t.drift_ratio
        declared[f"drift_ratio_{i}"] = (bi(f"baseline drift over the range, record {i}",
                                           f"дрейф нулевой линии к размаху, режим {i}"),
                                        "drift/range", "")
        values[f"carrying_ratio_{i}"] = t.lowest_frequency() / f_c
        declared[f"carrying_ratio_{i}"] = (bi(f"lowest carrying frequency over f_c, record {i}",
                                              f"низшая несущая частота к f_c, режим {i}"),
                                           "f_min/f_c", "")
    for f in found:
        values[f"width_res_{f.number}"] = f.resonance.width
        declared[f"width_res_{f.number}"] = (bi(f"width of resonance {f.number} at 0.7 of its "
                                                "peak", f"ширина резонанса {f.number} на уровне "
                                                "0,7 пика"), "Δn", "rpm")
    return computed({k: v for k, v in values.items() if np.isfinite(v)}, declared)


def _shown(results, name: str, digits: int) -> str:
    """A result found without an uncertainty, in its display unit to ``digits`` decimals;
    "—" if there is none."""
    if name not in results:
        return "—"
    r = results[name]
    return f"{r.shown(r.value):.{digits}f}"


def _records_table(recorded, results) -> Table:
    rows = []
    for r in recorded:
        t, i = r.trace, r.number
        rows.append({"i": str(i), "load": LOAD_WORDS[r.load], "cycles": f"{r.cycles:.1f}",
                     "n": result_pm(results, f"n_{i}"), "nu": result_pm(results, f"nu_{i}"),
                     "K": f"{t.K:.2f}" if np.isfinite(t.K) else "—",
                     "order": f"{t.dominant_order:g}" if t.fit is not None else "—",
                     "phi": result_pm(results, f"phi_max_{i}"),
                     "cycle": _shown(results, f"phi_cycle_{i}", 3),
                     "drift": _shown(results, f"drift_ratio_{i}", 2),
                     "fc": _shown(results, f"carrying_ratio_{i}", 1)})
    cols = (("i", bi("Record", "Режим")), ("load", bi("Load", "Нагрузка")),
            ("cycles", bi("Working cycles", "Рабочих циклов")),
            ("n", bi("n, min⁻¹", "n, мин⁻¹")), ("nu", bi("ν, Hz", "ν, Гц")),
            ("K", bi("K = ν/n", "K = ν/n")),
            ("order", bi("Dominant order", "Преобладающий порядок")),
            ("phi", bi("φ_max (largest single oscillation), mrad",
                       "φ_max (наибольшее отдельное колебание), мрад")),
            ("cycle", bi("mean cycle's largest, mrad", "наибольшая в среднем цикле, мрад")),
            ("drift", bi("drift / range", "дрейф / размах")),
            ("fc", bi("lowest carrying frequency / f_c", "низшая несущая частота / f_c")))
    return Table(bi("Records (± U)", "Торсиограммы (± U)"), cols, rows)


def _resonance_table(found, results, majors) -> Table:
    rows = []
    for f in found:
        r, j = f.resonance, f.number
        rows.append({"j": str(j), "load": LOAD_WORDS[f.load], "order": f"{r.order:g}",
                     "major": bi("yes", "да") if np.any(np.isclose(majors, r.order))
                     else bi("no", "нет"),
                     "n": result_pm(results, f"n_res_{j}"), "f": result_pm(results, f"f_res_{j}"),
                     "width": _shown(results, f"width_res_{j}", 0),
                     "records": ", ".join(map(str, f.records)),
                     "resolved": bi("yes", "да") if r.resolved else bi("NO", "НЕТ")})
    cols = (("j", bi("Resonance", "Резонанс")), ("load", bi("Load", "Нагрузка")),
            ("order", bi("Order K", "Порядок K")), ("major", bi("Major order", "Главный порядок")),
            ("n", bi("n_res, min⁻¹", "n_res, мин⁻¹")), ("f", bi("f = K n_res/60, Hz",
                                                                 "f = K n_res/60, Гц")),
            ("width", bi("width at 0.7, min⁻¹", "ширина на уровне 0,7, мин⁻¹")),
            ("records", bi("records fitted", "режимы в аппроксимации")),
            ("resolved", bi("resolved by the step", "разрешён шагом")))
    return Table(bi("Resonances (± U)", "Резонансы (± U)"), cols, rows)


def _modes_table(modes, results) -> Table:
    rel = modes.relative()
    n = rel.shape[-2]
    rows = []
    for m in range(rel.shape[-1]):
        row = {"m": str(m + 1), "f": result_pm(results, f"f_model_{m + 1}")}
        row.update({f"a{d}": f"{rel[d, m]:+.3f}" for d in range(n)})
        rows.append(row)
    cols = (("m", bi("Mode", "Форма")), ("f", bi("f, Hz", "f, Гц")),
            *((f"a{d}", bi(f"a{d + 1}", f"a{d + 1}")) for d in range(n)))
    return Table(bi("Equivalent system: natural frequencies and relative amplitudes of the "
                    "discs (1 at the nose, where the torsiograph sits)",
                    "Эквивалентная система: собственные частоты и относительные амплитуды "
                    "масс (1 на носке, где стоит торсиограф)"), cols, rows, "worked")


def _critical_table(criticals, results, majors) -> Table:
    rows = []
    for m, k in criticals:
        rows.append({"m": str(m), "k": f"{k:g}",
                     "major": bi("yes", "да") if np.any(np.isclose(majors, k))
                     else bi("no", "нет"),
                     "sum": result_pm(results, critical_names(m, k)[0]),
                     "n": result_pm(results, critical_names(m, k)[1])})
    cols = (("m", bi("Mode", "Форма")), ("k", bi("Order k", "Порядок k")),
            ("major", bi("Major order", "Главный порядок")),
            ("sum", bi("relative phase sum", "относительная фазовая сумма")),
            ("n", bi("critical speed 60 f/k, min⁻¹", "критическая частота 60 f/k, мин⁻¹")))
    return Table(bi("Critical speeds of the equivalent system's modes: the orders whose "
                    "relative phase sum |Σ a_c e^{ikφ_c}|/Σ|a_c| (a_c the mode's amplitude at "
                    "crank c) reaches 0.1 (± U)",
                    "Критические частоты вращения по формам эквивалентной системы: гармоники, "
                    "относительная фазовая сумма которых |Σ a_c e^{ikφ_c}|/Σ|a_c| (a_c — "
                    "амплитуда формы на кривошипе c) не меньше 0,1 (± U)"), cols, rows, keys=2)


def tables(*, recorded, found, results, modes, majors, criticals=(), **_) -> list[Table]:
    """The records, the resonances and (with a chain) its modes and critical speeds."""
    out = [_records_table(recorded, results)] if recorded else []
    if found:
        out.append(_resonance_table(found, results, majors))
    if modes is not None:
        out.append(_modes_table(modes, results))
    if criticals:
        out.append(_critical_table(criticals, results, majors))
    return out


# ------------------------------------------------------------------------ figures

def _t(lang, en, ru):
    return en if lang == "en" else ru


def _draw_calibration(fig, calibration, lang):
    cal, fit = calibration
    ax = fig.subplots()
    a = np.asarray(cal["deflection"].readings)
    phi = np.asarray(cal["h"].readings) / cal["R"].value
    ax.plot(a, 1e3 * phi, "o", label=_t(lang, "calibration", "тарировка"))
    grid = np.linspace(min(a.min(), 0), a.max(), 50)
    ax.plot(grid, 1e3 * fit.predict(grid) / cal["R"].value, "-", lw=1,
            label=f"l = {fit.slope / cal['R'].value:.4g}")
    ax.set_xlabel(_t(lang, "trace deflection A_k (record's unit)",
                     "отклонение записи A_k (единицы записи)"))
    ax.set_ylabel(_t(lang, "φ = h/R, mrad", "φ = h/R, мрад"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def _draw_amplitude(fig, recorded, found, results, majors, lang):
    ax = fig.subplots()
    l = results["l"].value
    for load in ("idle", "part", "full"):
        recs = sorted((r for r in recorded if r.load == load), key=lambda r: r.trace.angular_speed)
        if not recs:
            continue
        n = np.array([r.trace.angular_speed * RPM for r in recs])
        phi = np.array([results[f"phi_max_{r.number}"].value for r in recs])
        U = np.array([results[f"phi_max_{r.number}"].estimate.U for r in recs])
        ax.errorbar(n, 1e3 * phi, 1e3 * U, fmt="o-", ms=4, lw=1.5, capsize=2,
                    label=f"φ_max, {LOAD_WORDS[load][lang]}")
        for k in majors[:4]:
            a = [r.trace.order_amplitude[np.argmin(np.abs(r.trace.orders - k))]
                 if r.trace.orders.size and r.trace.orders.max() >= k else np.nan
                 for r in recs]
            ax.plot(n, 1e3 * l * np.asarray(a), "--", lw=0.8,
                    label=_t(lang, f"order {k:g}", f"порядок {k:g}"))
    for f in found:
        ax.axvline(f.resonance.speed * RPM, color="0.4", lw=0.8, ls=":")
        ax.annotate(f"K = {f.resonance.order:g}", (f.resonance.speed * RPM, 0),
                    xycoords=("data", "axes fraction"), xytext=(2, 4),
                    textcoords="offset points", fontsize=7)
    ax.set_xlabel(_t(lang, "n, min⁻¹", "n, мин⁻¹"))
    ax.set_ylabel(_t(lang, "amplitude, mrad", "амплитуда, мрад"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def _campbell_reach(recorded, modes, majors, criticals, results):
    """The Campbell diagram's speed and frequency reach, and the orders it draws: the
    records' (their speeds and orders), or without records the chain's (up to the first
    mode's critical speed at the lowest major order reported, and its reported modes)."""
    fitted = [r for r in recorded if r.trace.fit is not None]
    if recorded:
        speeds = np.array([r.trace.angular_speed for r in recorded])
        top = max((r.trace.orders.max() for r in fitted), default=float(majors.max()))
        step = fitted[0].trace.orders[0] if fitted else majors[0]
        return speeds.max() * 1.05, 0.0, np.arange(step, top + step / 2, step)
    speeds = {(m, k): results[critical_names(m, k)[1]].value for m, k in criticals}
    first = [w for (m, k), w in speeds.items()
             if m == 1 and np.any(np.isclose(majors, k))] or list(speeds.values())
    reach = 1.1 * max(first) if first else \
        1.1 * modes.angular_frequency[0] / majors[0]
    highest = max(k for _, k in criticals) if criticals else majors[min(5, majors.size - 1)]
    orders = np.union1d([k for _, k in criticals], majors[majors <= highest])
    shown = modes.frequency[:min(2, modes.frequency.size)]
    return reach, float(shown.max()), orders


def _draw_campbell(fig, recorded, found, modes, majors, lang, results=None, criticals=()):
    ax = fig.subplots()
    w_top, f_top, orders = _campbell_reach(recorded, modes, majors, criticals, results)
    for r in recorded:
        t = r.trace
        a = t.order_amplitude
        if not a.size:
            continue
        keep = a >= 0.1 * a.max()
        f = t.fit.order[keep] * t.revolution_frequency
        ax.scatter(np.full(f.size, t.angular_speed * RPM), f, s=60 * a[keep] / a.max(),
                   color="tab:blue", alpha=0.6, lw=0, zorder=3)
        f_top = max(f_top, f.max())
    for f in found:
        ax.plot(f.resonance.speed * RPM, f.resonance.frequency, "*", ms=12, color="k", zorder=4)
        ax.axhline(f.resonance.frequency, color="k", lw=0.6, ls=":")
    if modes is not None:
        for f in modes.frequency[modes.frequency < 1.5 * f_top]:
            ax.axhline(f, color="tab:green", lw=0.8, ls="--")
            f_top = max(f_top, f)
    for m, k in criticals:
        w = results[critical_names(m, k)[1]].value
        if w <= w_top:
            ax.plot(w * RPM, k * w / (2 * np.pi), "o", ms=5, mfc="none", color="tab:green",
                    zorder=4)
    f_top *= 1.15
    w = np.array([0.0, w_top])
    for k, f in zip(orders, campbell_lines(orders, w)):
        major = bool(np.any(np.isclose(majors, k)))
        ax.plot(w * RPM, f, color="tab:red" if major else "0.8", lw=1.1 if major else 0.5,
                zorder=1)
        if major:
            end = min(w_top, f_top / f[-1] * w_top)
            ax.annotate(f"{k:g}", (end * RPM, k * end / (2 * np.pi)), fontsize=7,
                        color="tab:red", xytext=(2, -8 if end < w_top else 0),
                        textcoords="offset points")
    ax.set_ylim(0, f_top)
    ax.set_xlim(0, w_top * RPM)
    ax.set_xlabel(_t(lang, "n, min⁻¹", "n, мин⁻¹"))
    ax.set_ylabel(_t(lang, "frequency, Hz", "частота, Гц"))
    ax.grid(alpha=0.2)


def _showcase(recorded, results, found=()):
    """The peak record of the resonance with the largest φ_max, or (without resonances) the
    record with the largest φ_max."""
    peaks = {f.peak for f in found}
    pool = [r for r in recorded if r.number in peaks] or recorded
    return max(pool, key=lambda r: results[f"phi_max_{r.number}"].value)


def _draw_record(fig, recorded, found, results, lang):
    r = _showcase(recorded, results, found)
    t = r.trace
    l = results["l"].value
    ax = fig.subplots()
    ax.plot(t.time, 1e3 * l * t.corrected, color="tab:blue", lw=0.7,
            label=_t(lang, "record, corrected", "запись с поправкой"))
    ax.plot(t.time, 1e3 * l * t.drift, color="0.4", lw=1, ls="--",
            label=_t(lang, "drift (fitted)", "дрейф (аппроксимация)"))
    p = t.peaks
    ok = np.isfinite(p.amplitude)
    on_trace = p.value + np.interp(p.position, t.time, t.drift)
    ax.plot(p.position[ok], 1e3 * l * on_trace[ok], "o", ms=3, color="tab:red",
            label=_t(lang, "extrema", "экстремумы"))
    j = int(np.nanargmax(p.amplitude)) if ok.any() else None
    if j is not None:
        ax.annotate(f"A = {1e3 * l * p.amplitude[j]:.2f}", (p.position[j], 1e3 * l * on_trace[j]),
                    xytext=(4, 4), textcoords="offset points", fontsize=7)
    ax.set_xlabel(_t(lang, f"t, s (record {r.number}, {t.angular_speed * RPM:.0f} min⁻¹)",
                     f"t, с (режим {r.number}, {t.angular_speed * RPM:.0f} мин⁻¹)"))
    ax.set_ylabel(_t(lang, "φ, mrad", "φ, мрад"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")


def _draw_orders(fig, recorded, found, results, majors, lang):
    r = _showcase(recorded, results, found)
    t = r.trace
    l = results["l"].value
    ax = fig.subplots()
    major = np.array([np.any(np.isclose(majors, k)) for k in t.orders])
    ax.bar(t.orders, 1e3 * l * t.order_amplitude, width=0.35,
           color=np.where(major, "tab:red", "tab:blue"))
    ax.errorbar(t.orders, 1e3 * l * t.order_amplitude, 2e3 * l * t.order_u, fmt="none",
                ecolor="k", lw=0.6)
    ax.set_xlabel(_t(lang, f"order (record {r.number}; red: major orders)",
                     f"порядок (режим {r.number}; красные — главные порядки)"))
    ax.set_ylabel(_t(lang, "amplitude, mrad", "амплитуда, мрад"))
    ax.grid(axis="y", alpha=0.3)


def figures(*, recorded, found, results, modes, majors, calibration, criticals=(),
            **_) -> list[Figure]:
    """The calibration, the amplitude–speed curve, the Campbell diagram, the record with the
    largest peak amplitude and its order spectrum; without records, the chain's Campbell
    diagram alone."""
    campbell = Figure(
        "campbell", bi("Campbell diagram: the orders' frequencies k n/60 (red: the major "
                       "orders), each record's orders carrying ≥ 10 % of its largest (dots, "
                       "size ∝ amplitude), the resonances (stars) and the natural frequencies "
                       "they imply (dotted) and, with a chain, the model's (green dashed) and "
                       "its critical speeds (circles)",
                       "Диаграмма Кэмпбелла: частоты гармоник k n/60 (красные — главные "
                       "порядки), гармоники каждого режима не менее 10 % наибольшей (точки, "
                       "размер ∝ амплитуде), резонансы (звёзды) и их собственные частоты "
                       "(пунктир), при заданной системе — расчётные (зелёный штрих) и её "
                       "критические частоты вращения (кружки)"),
        lambda fig, lang: _draw_campbell(fig, recorded, found, modes, majors, lang, results,
                                         criticals), size=(6.4, 4.2))
    if not recorded:
        return [campbell]
    return [
        Figure("calibration", bi("Static calibration: the case's angle φ = h/R against the "
                                 "trace's deflection, and the line whose slope is the scale l",
                                 "Статическая тарировка: угол поворота корпуса φ = h/R по "
                                 "отклонению записи и прямая, наклон которой — масштаб l"),
               lambda fig, lang: _draw_calibration(fig, calibration, lang), size=(5.6, 3.4)),
        Figure("amplitude_speed", bi("Amplitude–speed curve: the largest peak amplitude of each "
                                     "record (± U) and the amplitudes of the major orders "
                                     "(dashed); dotted: the resonances found",
                                     "Амплитудно-частотная характеристика: наибольшая пиковая "
                                     "амплитуда каждого режима (± U) и амплитуды главных "
                                     "порядков (штрих); пунктир — найденные резонансы"),
               lambda fig, lang: _draw_amplitude(fig, recorded, found, results, majors, lang)),
        campbell,
        Figure("record", bi("The record at the strongest resonance (without one: the record "
                            "with the largest peak amplitude), corrected for the torsiograph: "
                            "its single oscillations' extrema and the fitted drift",
                            "Торсиограмма на пике сильнейшего резонанса (если резонансов нет — "
                            "с наибольшей пиковой амплитудой) с поправкой на торсиограф: "
                            "экстремумы отдельных колебаний и дрейф"),
               lambda fig, lang: _draw_record(fig, recorded, found, results, lang)),
        Figure("orders", bi("Its order spectrum (harmonic analysis, corrected; ± U)",
                            "Её гармонический состав (с поправкой; ± U)"),
               lambda fig, lang: _draw_orders(fig, recorded, found, results, majors, lang)),
    ]


# ------------------------------------------------------------------------ conclusion

def conclusion(*, recorded, found, edges, results, modes, majors, criticals=(),
               **_) -> list[dict]:
    """The largest amplitude, the resonances with their orders and natural frequencies, the
    model's frequency against the measured one, its critical speeds."""
    lines = []
    if recorded:
        top = _showcase(recorded, results)
        phi = results["phi_max"]
        v, U = fmt_pm(1e3 * phi.value, 1e3 * phi.estimate.U)
        n = top.trace.angular_speed * RPM
        lines.append(bi(f"The largest peak amplitude is φ_max = {v} ± {U} mrad "
                        f"({np.degrees(phi.value):.3f}°), record {top.number} at {n:.0f} "
                        "min⁻¹",
                        f"Наибольшая пиковая амплитуда φ_max = {v} ± {U} мрад "
                        f"({np.degrees(phi.value):.3f}°), режим {top.number} при {n:.0f} "
                        "мин⁻¹"))
    else:
        lines.append(bi("No records: the equivalent system's modes and critical speeds alone "
                        "(the resonances are found from the torsiograms)",
                        "Записей нет: только формы и критические частоты вращения "
                        "эквивалентной системы (резонансы находятся по торсиограммам)"))
    majors_text = ", ".join(f"{k:g}" for k in majors[:6])
    lines.append(bi(f"Major orders of this engine (all cylinders in phase): {majors_text}, …",
                    f"Главные порядки этого двигателя (все цилиндры в фазе): {majors_text}, …"))
    if recorded and not found:
        lines.append(bi("No resonance was found within the speeds recorded",
                        "В записанном диапазоне частот вращения резонансов не найдено"))
    for f in found:
        r, j = f.resonance, f.number
        nres, fres = results[f"n_res_{j}"], results[f"f_res_{j}"]
        a, Ua = fmt_pm(nres.shown(nres.value), nres.shown(nres.value + nres.estimate.U)
                       - nres.shown(nres.value))
        b, Ub = fmt_pm(fres.value, fres.estimate.U)
        kind = ("major" if np.any(np.isclose(majors, r.order)) else "minor",
                "главного" if np.any(np.isclose(majors, r.order)) else "неглавного")
        lines.append(bi(f"Resonance {j} ({LOAD_WORDS[f.load]['en']}): order {r.order:g} "
                        f"({kind[0]}) at n = {a} ± {Ua} min⁻¹: natural frequency "
                        f"{b} ± {Ub} Hz",
                        f"Резонанс {j} ({LOAD_WORDS[f.load]['ru']}): гармоника {kind[1]} "
                        f"порядка {r.order:g} при n = {a} ± {Ua} мин⁻¹: собственная частота "
                        f"{b} ± {Ub} Гц"))
    if modes is not None:
        f1 = results["f_model_1"]
        c, Uc = fmt_pm(f1.value, f1.estimate.U)
        lines.append(bi(f"The equivalent system's first natural frequency is {c} ± {Uc} Hz",
                        f"Первая собственная частота эквивалентной системы {c} ± {Uc} Гц"))
        first = [k for m, k in criticals if m == 1 and np.any(np.isclose(majors, k))]
        if first:
            text = ", ".join(f"{k:g}: {results[critical_names(1, k)[1]].value * RPM:.0f}"
                             for k in first)
            lines.append(bi(f"Its critical speeds for the major orders (k: n, min⁻¹): {text}",
                            f"Её критические частоты вращения для главных порядков (k: n, "
                            f"мин⁻¹): {text}"))
    for load, e in edges:
        if e.side == "high":
            lines.append(bi(f"Order {e.order:g} still rises at the highest speed "
                            f"({LOAD_WORDS[load]['en']}): a resonance lies above it",
                            f"Гармоника порядка {e.order:g} ещё растёт при наибольшей частоте "
                            f"вращения ({LOAD_WORDS[load]['ru']}): выше лежит резонанс"))
        else:
            lines.append(bi(f"Order {e.order:g} rises steeply towards the lowest speed "
                            f"({LOAD_WORDS[load]['en']}): the crankshaft's speed irregularity "
                            "(its rigid swing), or a resonance below the sweep",
                            f"Гармоника порядка {e.order:g} круто растёт к наименьшей частоте "
                            f"вращения ({LOAD_WORDS[load]['ru']}): неравномерность вращения "
                            "вала (его колебания как целого) или резонанс ниже диапазона"))
    return lines
