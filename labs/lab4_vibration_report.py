"""Lab 4's report: result labels, formulas, the manual's table of readings, the charts against
the speed, the order map, the cut cylinder, the warnings' words and the conclusion.

Everything here lays out what :func:`labs.lab4_vibration.reduce` found, in the manual's
terms; nothing here reduces data.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from processing.vibration.band_rms import BANDS, QUANTITIES, REFERENCES as DB_REFERENCES
from processing.diagnostics import (CutCylinderWarning, MethodsDisagreeWarning,
                                    NoiseFloorWarning, NoMarksWarning, RecordBandwidthWarning,
                                    SpeedDisagreesWarning)
from processing.measurement import bi
from processing.reporting.content import result_pm
from processing.result import KEY, STRICTLY_POSITIVE, Figure, ResultValue, Table
from processing.uncertainty import Estimate

RPM = 30 / np.pi


NAMES = {
    "a": (bi("RMS vibration acceleration", "СКЗ виброускорения"), "a", "m/s^2"),
    "v": (bi("RMS vibration velocity", "СКЗ виброскорости"), "v", "mm/s"),
    "x": (bi("RMS vibration displacement", "СКЗ виброперемещения"), "x", "µm"),
}
PP = {"a": "m/s^2", "v": "mm/s", "x": "µm"}
DIRECTION = {"vertical": bi("vertical", "вертикальное"),
             "transverse": bi("transverse", "поперечное"),
             "longitudinal": bi("longitudinal", "продольное")}


def _where(j: int, place: dict) -> dict:
    """The words "measurement j: point, direction, n" in both languages."""
    p = place.get(j)
    if p is None:
        return bi(f"measurement {j}", f"измерение {j}")
    return bi(f"measurement {j}: point {p[0]}, {DIRECTION[p[1]]['en']}, {p[2]:.0f} min⁻¹"
              + (", ignition cut" if p[3] == "cut" else ""),
              f"измерение {j}: точка {p[0]}, {DIRECTION[p[1]]['ru']}, {p[2]:.0f} мин⁻¹"
              + (", зажигание отключено" if p[3] == "cut" else ""))


def _label(base: dict, where: dict) -> dict:
    return {k: f"{base[k]} ({where[k]})" for k in base}


def placements(recorded, readings, points) -> dict:
    """Measurement j → (point, direction, n in min⁻¹, ignition)."""
    place = {}
    for r in recorded:
        for c in r.channels:
            place[c.number] = (c.point, points[c.point - 1]["direction"],
                               r.speed.value * RPM if r.speed is not None else np.nan,
                               r.ignition)
    for rd in readings:
        e = rd.entry
        place.setdefault(rd.number, (e["point"], points[e["point"] - 1]["direction"],
                                     e["n"].value * RPM, e["ignition"]))
    return place


def result_names(recorded, readings, forces: bool, mass: bool, points) -> dict:
    """Labels, symbols and display units of every result the reduction may give: the
    readings, amplitudes and speeds above zero by their nature; the free forces and their
    accelerations zero where the cranks cancel them (a four's first order). The RMS
    vibration velocity of each measurement, the quantity the vibration norms judge, is the
    key result."""
    place = placements(recorded, readings, points)
    numbers = sorted({c.number for r in recorded for c in r.channels}
                     | {rd.number for rd in readings})
    return dict(_names(tuple(place.items()), tuple(numbers), tuple(r.number for r in recorded),
                       forces, mass))


@lru_cache(maxsize=32)
def _names(place: tuple, numbers: tuple, records: tuple, forces: bool, mass: bool) -> dict:
    """:func:`result_names` of the measurements' places, numbers and records (kept: a check
    reduces a submission again for each slip, mostly to the same places)."""
    place = dict(place)
    out = {}
    for j in numbers:
        w = _where(j, place)
        for q in QUANTITIES:
            label, sym, unit = NAMES[q]
            out[f"{q}_rms_{j}"] = (_label(label, w), f"{sym}_{j}", unit, STRICTLY_POSITIVE,
                                   *((KEY,) if q == "v" else ()))
            out[f"{q}_meter_{j}"] = (_label(bi(f"{label['en']} by the meter",
                                               f"{label['ru']} по виброметру"), w),
                                     f"{sym}_м{j}", unit, STRICTLY_POSITIVE)
            out[f"L_{q}_{j}"] = (_label(bi(f"level of the {label['en'][4:]} (RMS)",
                                           f"уровень {label['ru'][4:]} (СКЗ)"), w),
                                 f"L_{sym},{j}", "dB")
            out[f"{q}_pp_{j}"] = (_label(bi(f"peak-to-peak {label['en'][4:]}",
                                            f"размах {label['ru'][4:]}"), w), f"2{sym}_{j}",
                                  PP[q], STRICTLY_POSITIVE)
            out[f"{q}_pp_meter_{j}"] = (_label(bi(f"peak-to-peak {label['en'][4:]} by the "
                                                  "meter", f"размах {label['ru'][4:]} по "
                                                  "виброметру"), w), f"2{sym}_м{j}", PP[q],
                                        STRICTLY_POSITIVE)
        for k in (1, 2):
            out[f"a{k}_{j}"] = (_label(bi(f"amplitude of order {k} of the acceleration",
                                          f"амплитуда гармоники {k}-го порядка "
                                          "виброускорения"), w), f"a_{k},{j}", "m/s^2",
                                STRICTLY_POSITIVE)
    for n in records:
        out[f"n_{n}"] = (bi(f"speed from the TDC marks, record {n}",
                            f"частота вращения по отметкам ВМТ, запись {n}"), f"n_{n}", "rpm",
                         STRICTLY_POSITIVE)
        if forces:
            for k in (1, 2):
                out[f"F{k}_{n}"] = (bi(f"free inertia force of order {k}, record {n}",
                                       f"свободная сила инерции {k}-го порядка, запись {n}"),
                                    f"P_j{k},{n}", "N")
                if mass:
                    out[f"a{k}_model_{n}"] = (bi(f"heave acceleration of order {k} by the "
                                                 f"formulas (P_j{k}/m), record {n}",
                                                 f"виброускорение {k}-го порядка по формулам "
                                                 f"(P_j{k}/m), запись {n}"), f"a_{k}м,{n}",
                                              "m/s^2")
    return out


def cut_results(recorded) -> dict:
    """The cut cylinder, its confidence and the half orders' rise of each record with the
    ignition cut: discrete findings, without uncertainty."""
    out = {}
    for r in recorded:
        v = r.verdict
        if r.ignition != "cut" or v is None:
            continue
        n = r.number
        for name, value, label, sym in (
                ("cut_cylinder", v.cylinder, bi(f"cylinder found cut, record {n} (0: none)",
                                                f"отключённый цилиндр, запись {n} (0 — не "
                                                "найден)"), "c"),
                ("cut_confidence", v.confidence, bi(f"confidence of the cut cylinder, record "
                                                    f"{n}", f"достоверность определения "
                                                    f"цилиндра, запись {n}"), "P"),
                ("half_rise", v.rise, bi(f"rise of the half orders against the healthy "
                                         f"record, record {n}", f"рост полуцелых гармоник "
                                         f"относительно исправного режима, запись {n}"),
                 "ρ")):
            out[f"{name}_{n}"] = ResultValue(f"{name}_{n}",
                                             Estimate(float(value), 0.0, math.inf), "",
                                             label, f"{sym}_{n}", "")
    return out


FORMULAS = [
    bi("Excitation: P_j = −m_j R ω² (cos ωt + λ cos 2ωt) along each cylinder; P_r = −m_r R ω² "
       "along each crank; one cylinder's torque M ≈ −(P_g + P_j) R (sin ωt + (λ/2) sin 2ωt), "
       "its reaction on the mounts; unbalance at 1×; free forces of the row "
       "P_j1 = (m_j + m_r) R ω² |Σ e^{iθ_c}|, P_j2 = λ m_j R ω² |Σ e^{2iθ_c}|",
       "Возбуждение: P_j = −m_j R ω² (cos ωt + λ cos 2ωt) вдоль оси цилиндра; P_r = −m_r R ω² "
       "вдоль кривошипа; момент цилиндра M ≈ −(P_g + P_j) R (sin ωt + (λ/2) sin 2ωt) и его "
       "реакция на опорах; дисбаланс с частотой вращения; свободные силы ряда "
       "P_j1 = (m_j + m_r) R ω² |Σ e^{iθ_c}|, P_j2 = λ m_j R ω² |Σ e^{2iθ_c}|"),
    bi("Meter bands: a and x 1.4–8000 Hz, v 1.4–2800 Hz; edges are Butterworth filters "
       "(−3 dB at the edge; order 2 for a, 3 for v, 4 for x); reading "
       "X_n² = ∫ S_a(f) |H(f)|²/(2πf)^{2n} df, n = 0, 1, 2, on a Hann-windowed spectrum of "
       "the whole record (no integration in time: no drift)",
       "Полосы виброметра: a и x 1,4–8000 Гц, v 1,4–2800 Гц; края — фильтры Баттерворта "
       "(−3 дБ на краю; порядок 2 для a, 3 для v, 4 для x); показание "
       "X_n² = ∫ S_a(f) |H(f)|²/(2πf)^{2n} df, n = 0, 1, 2, по спектру всей записи с окном "
       "Ханна (без интегрирования во времени — без дрейфа)"),
    bi("a = U/S (S the sensor's sensitivity); peak-to-peak of the band signal's mean working "
       "cycle (averaged over the record's cycles against the crank angle; without TDC marks, "
       "of a and v over the whole record); L = 20 lg(X/X₀) dB; the broadband floor: the "
       "spectrum between its lines (orders, tones) through the band's weight",
       "a = U/S (S — коэффициент преобразования датчика); размах среднего рабочего цикла "
       "сигнала в полосе (осреднение циклов записи по углу поворота; без отметок ВМТ — a и v "
       "по всей записи); L = 20 lg(X/X₀) дБ; широкополосный фон — спектр между его линиями "
       "(гармониками, тонами) через вес полосы"),
    bi("Orders: x(t) = Σ Re(c_k e^{ikθ}) + drift, by least squares on the crank angle θ from "
       "the TDC marks (half orders for a four-stroke engine)",
       "Гармоники: x(t) = Σ Re(c_k e^{ikθ}) + дрейф, МНК по углу поворота θ от отметок ВМТ "
       "(полуцелые порядки для четырёхтактного двигателя)"),
    bi("Cut cylinder: deficit d_k = c_k(cut) − c_k(healthy) at the same speed; found when the "
       "half orders' RMS rises ≥ 2 times and the change is significant (χ², p < 10⁻⁴); the "
       "cylinder whose firing sector holds the largest envelope |Σ d_k e^{ikθ}|",
       "Отключённый цилиндр: дефицит d_k = c_k(откл.) − c_k(испр.) при той же частоте; "
       "найден, если СКЗ полуцелых гармоник выросло ≥ 2 раз и изменение значимо (χ², "
       "p < 10⁻⁴); цилиндр, в секторе сгорания которого огибающая |Σ d_k e^{ikθ}| наибольшая"),
]
REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, "
       "lab 4.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: "
       "ВлГУ, 2003. Лаб. работа №4."),
    bi("ISO 2954:2012 (vibration meters' band filters); ISO 1683:2015 and GOST 25275-82 "
       "(reference values of the dB levels).",
       "ISO 2954:2012 (фильтры виброметров); ISO 1683:2015 и ГОСТ 25275-82 (опорные значения "
       "уровней в дБ)."),
    bi("R. B. Randall, Vibration-based Condition Monitoring, Wiley, 2011 (order analysis, "
       "misfire from the half orders).",
       "R. B. Randall, Vibration-based Condition Monitoring, Wiley, 2011 (порядковый анализ, "
       "пропуски воспламенения по полуцелым гармоникам)."),
]

SENSOR_HELP = bi(
    "The accelerometer's sensitivity from its calibration chart, with its unit: a voltage "
    "over an acceleration (mV/(m/s^2) or mV/g), and its limit (± 2 % or in the same unit).",
    "Коэффициент преобразования вибродатчика из его паспорта с единицами: напряжение на "
    "ускорение (mV/(m/s^2) или mV/g) и погрешность (± 2 % или в тех же единицах).")
RECORD_HELP = bi(
    "A record of a steady regime: the accelerometers' channels (one per [[point]], in their "
    "order) and the TDC marks, at best cylinder 1's ignition pickup (tdc = \"cycle\": a "
    "falling edge at each firing TDC of cylinder 1; it fixes the half orders' phase and "
    "tells which cylinder is cut). Two working cycles at least; a few seconds. Without TDC "
    "marks (no channel 'tdc') the band readings, levels and peak-to-peak a and v are still "
    "reduced; the orders, x's peak-to-peak and the cut cylinder need the marks.",
    "Запись установившегося режима: каналы вибродатчиков (по одному на [[point]], в их "
    "порядке) и отметки ВМТ, лучше всего от датчика зажигания 1-го цилиндра (tdc = "
    "\"cycle\": спад импульса в каждой ВМТ сгорания 1-го цилиндра). Не менее двух рабочих "
    "циклов; несколько секунд. Без отметок ВМТ (нет канала 'tdc') определяются СКЗ, уровни и "
    "размахи a и v; гармоники, размах x и отключённый цилиндр требуют отметок.")
READING_HELP = bi(
    "One reading of the vibration meter: the point's number, the speed, the ignition and "
    "what the meter showed (RMS a in m/s², v in mm/s, x in µm; peak-to-peak a_pp, v_pp, "
    "x_pp). A reading at the point, speed and ignition of a record is compared with it.",
    "Одно показание виброметра: номер точки, частота вращения, зажигание и показания "
    "(СКЗ a в м/с², v в мм/с, x в мкм; размах a_pp, v_pp, x_pp). Показание в той же точке, "
    "при той же частоте и зажигании, что и запись, сравнивается с ней.")


# ------------------------------------------------------------------------ warnings

def speed_disagrees(where: str, w: float, n: float) -> SpeedDisagreesWarning:
    return SpeedDisagreesWarning(
        f"{where}: the TDC marks give {w * RPM:.0f} min⁻¹, the tachometer {n * RPM:.0f} "
        "min⁻¹: the marks' speed is used; check the tachometer",
        f"{where}: по отметкам ВМТ {w * RPM:.0f} мин⁻¹, по тахометру {n * RPM:.0f} мин⁻¹: "
        "принята частота по отметкам; проверьте тахометр")


def no_healthy(number: int, w: float) -> CutCylinderWarning:
    return CutCylinderWarning(
        f"record {number} (ignition cut, {w * RPM:.0f} min⁻¹) has no healthy record within "
        "3 % of its speed: the cut cylinder cannot be found; record the healthy engine at the "
        "same speed",
        f"запись {number} (зажигание отключено, {w * RPM:.0f} мин⁻¹): нет записи исправного "
        "двигателя при той же частоте (±3 %), цилиндр не определить; запишите исправный "
        "двигатель на том же режиме")


def two_stroke_cut() -> CutCylinderWarning:
    return CutCylinderWarning(
        "a record has a cylinder cut, but the engine is a two-stroke: the cut cylinder is "
        "found from the half orders a four-stroke engine's misfire raises, so it is not "
        "looked for; compare the records' order spectra in the order map",
        "в записи отключён цилиндр, но двигатель двухтактный: отключённый цилиндр ищется по "
        "полуцелым гармоникам четырёхтактного двигателя и здесь не определяется; сравните "
        "спектры гармоник на карте порядков")


def cut_not_found(number: int, rise: float) -> CutCylinderWarning:
    return CutCylinderWarning(
        f"record {number} is marked with a cylinder cut, but its half orders rose only "
        f"{rise:.2f} times against the healthy record: no cylinder was found cut (was the "
        "ignition really cut? is a channel on the transverse direction, where the torque "
        "reaction shows?)",
        f"запись {number} помечена как с отключённым цилиндром, но полуцелые гармоники "
        f"выросли лишь в {rise:.2f} раза: отключённый цилиндр не найден (было ли зажигание "
        "отключено? есть ли датчик в поперечном направлении, где видна реакция момента?)")


def cut_disagrees(number: int, found: int, stated: int, confidence: float) -> CutCylinderWarning:
    return CutCylinderWarning(
        f"record {number}: cylinder {found} was found cut (confidence {confidence:.2f}), but "
        f"the file says cylinder {stated}: check the firing order and that the TDC marks are "
        "cylinder 1's firing TDC",
        f"запись {number}: найден отключённым цилиндр {found} (достоверность "
        f"{confidence:.2f}), а в файле указан {stated}: проверьте порядок работы и что "
        "отметки ВМТ — это ВМТ сгорания 1-го цилиндра")


def band_beyond_nyquist(items) -> RecordBandwidthWarning:
    text = ", ".join(f"{n} ({rate / 1e3:.3g} kHz)" for n, rate in items)
    nyquist = min(rate for _, rate in items) / 2
    edges = ", ".join(f"{q} {b.high:g} Hz" for q, b in BANDS.items() if b.high > nyquist)
    return RecordBandwidthWarning(
        f"records {text} hold frequencies up to half their sample rate ({nyquist:.0f} Hz at the "
        f"least), below the meter's upper band edges ({edges}): those readings leave out "
        "whatever vibration lies above it and are low by that much; record at twice the "
        "highest band edge or more (e.g. 25.6 kHz)",
        f"записи {text} содержат частоты лишь до половины частоты дискретизации "
        f"({nyquist:.0f} Гц у наименьшей), ниже верхних краёв полос виброметра ({edges}): эти "
        "показания не учитывают вибрацию выше и занижены на неё; записывайте с частотой не "
        "менее удвоенного верхнего края полосы (напр. 25,6 кГц)")


def no_marks(items) -> NoMarksWarning:
    text = "; ".join(f"record {n}: {why['en']}" for n, why in items)
    text_ru = "; ".join(f"запись {n}: {why['ru']}" for n, why in items)
    return NoMarksWarning(
        f"records without TDC marks ({text}): their band readings a, v, x, dB levels, "
        "peak-to-peak acceleration and velocity (over the whole record, not its mean working "
        "cycle, with a wider uncertainty) and the comparison with the meter are reduced; the "
        "speed n_r from the marks, the peak-to-peak displacement x_pp_j, the orders a1_j and "
        "a2_j and the cut cylinder need the marks and are left out (the free forces and the "
        "meter's pairing take the tachometer's n where it is given): record the ignition "
        "pickup's TDC marks beside the accelerometers and name their channel (tdc_channel = "
        "...)",
        f"записи без отметок ВМТ ({text_ru}): по ним определены СКЗ "
        "a, v, x, уровни в дБ, размахи ускорения и скорости (по всей записи, а не по среднему "
        "рабочему циклу, с большей погрешностью) и сравнение с виброметром; частота вращения "
        "n_r по отметкам, размах перемещения x_pp_j, гармоники a1_j и a2_j и отключённый "
        "цилиндр требуют отметок и не определены "
        "(свободные силы и сопоставление с виброметром — по тахометру, если n указана): "
        "записывайте отметки ВМТ датчика зажигания вместе с вибродатчиками и укажите их канал "
        "(tdc_channel = ...)")


def on_floor(items, share: float) -> NoiseFloorWarning:
    text = ", ".join(f"{q}_rms_{j} ({100 * s:.0f} %)" for j, q, s in items)
    return NoiseFloorWarning(
        f"these readings rest on the record's broadband floor (its own reading over the "
        f"band's, above {100 * share:.0f} %): {text}; sensor noise integrated towards the "
        "1.4 Hz edge, or broadband vibration: a displacement or velocity so read is an upper "
        "bound of the engine's",
        f"эти показания определяются широкополосным фоном записи (его доля выше "
        f"{100 * share:.0f} %): {text}; шум датчика, проинтегрированный к краю 1,4 Гц, или "
        "широкополосная вибрация: такое перемещение или скорость — оценка сверху")


def meter_disagrees(items, limit: float) -> MethodsDisagreeWarning:
    text = ", ".join(f"{a}/{b} − 1 = {100 * d:+.0f} %" for a, b, d in items)
    return MethodsDisagreeWarning(
        f"record and meter differ beyond the meter's ±{100 * limit:.0f} %: {text}; the meter "
        "is suspect where the record's orders and speed hold together (check its range "
        "switch and filter buttons), the record where a channel is clipped or the "
        "sensitivity unsure",
        f"запись и виброметр расходятся больше ±{100 * limit:.0f} %: {text}; подозрителен "
        "виброметр, если гармоники и частота записи согласованы (проверьте переключатели "
        "диапазона и фильтров), запись — если канал ограничен или коэффициент датчика "
        "сомнителен")


# ------------------------------------------------------------------------ tables

def _t(lang: str, en: str, ru: str) -> str:
    return ru if lang == "ru" else en


def _readings_table(results, place, reference) -> Table:
    ref = DB_REFERENCES[reference]
    cols = (("j", bi("j", "j")), ("point", bi("point", "точка")),
            ("direction", bi("direction", "направление")), ("n", bi("n, min⁻¹", "n, мин⁻¹")),
            ("ignition", bi("ignition", "зажигание")),
            ("a", bi("a, m/s²", "a, м/с²")), ("v", bi("v, mm/s", "v, мм/с")),
            ("x", bi("x, µm", "x, мкм")),
            ("La", bi(f"L_a, dB re {ref['a']:g} m/s²", f"L_a, дБ отн. {ref['a']:g} м/с²")),
            ("Lv", bi(f"L_v, dB re {ref['v']:g} m/s", f"L_v, дБ отн. {ref['v']:g} м/с")),
            ("Lx", bi(f"L_x, dB re {ref['x']:g} m", f"L_x, дБ отн. {ref['x']:g} м")),
            ("pp", bi("2a, 2v, 2x", "2a, 2v, 2x")))
    rows = []
    for j, (p, d, n, ign) in sorted(place.items()):
        row = {"j": str(j), "point": str(p), "direction": DIRECTION[d],
               "n": f"{n:.0f}" if np.isfinite(n) else "—",
               "ignition": bi("cut", "откл.") if ign == "cut" else bi("all", "все")}
        for q in QUANTITIES:
            name = f"{q}_rms_{j}"
            row[q] = result_pm(results, name)
            row[f"L{q}"] = result_pm(results, f"L_{q}_{j}")
        row["pp"] = ", ".join(result_pm(results, f"{q}_pp_{j}") for q in QUANTITIES)
        rows.append(row)
    return Table(bi("Vibration by point, direction and speed (± U); dB levels",
                    "Вибрация по точкам, направлениям и режимам (± U); уровни в дБ"),
                 cols, tuple(rows))


def _meter_table(results, comparisons) -> Table | None:
    if not comparisons:
        return None
    cols = (("pair", bi("record / meter", "запись / виброметр")),
            ("record", bi("record", "запись")), ("meter", bi("meter", "виброметр")),
            ("diff", bi("difference, %", "разность, %")), ("agree", bi("within U", "в пределах U")))
    rows = []
    for c in comparisons:
        rel = results[c.a].value / results[c.b].value - 1
        rows.append({"pair": f"{c.a} / {c.b}", "record": result_pm(results, c.a),
                     "meter": result_pm(results, c.b), "diff": f"{100 * rel:+.1f}",
                     "agree": bi("yes", "да") if c.agree else bi("no", "нет")})
    return Table(bi("The record against the meter (its ±15 % in U)",
                    "Запись и виброметр (±15 % виброметра в U)"), cols, tuple(rows))


def _orders_table(recorded, results) -> Table | None:
    rows = []
    for r in recorded:
        for c in r.channels:
            j = c.number
            if f"a1_{j}" not in results:
                continue
            row = {"j": str(j), "n": f"{r.speed.value * RPM:.0f}",
                   "a1": result_pm(results, f"a1_{j}"), "a2": result_pm(results, f"a2_{j}"),
                   "m1": result_pm(results, f"a1_model_{r.number}"),
                   "m2": result_pm(results, f"a2_model_{r.number}")}
            rows.append(row)
    if not rows:
        return None
    cols = (("j", bi("j", "j")), ("n", bi("n, min⁻¹", "n, мин⁻¹")),
            ("a1", bi("order 1, m/s²", "1-й порядок, м/с²")),
            ("a2", bi("order 2, m/s²", "2-й порядок, м/с²")),
            ("m1", bi("P_j1/m, m/s²", "P_j1/m, м/с²")), ("m2", bi("P_j2/m, m/s²", "P_j2/m, м/с²")))
    return Table(bi("First and second orders of the acceleration against the free inertia "
                    "forces over the engine's mass (the block's heave above its mounts' "
                    "resonance; a point's rotation adds to it)",
                    "Гармоники 1-го и 2-го порядков виброускорения и свободные силы инерции, "
                    "отнесённые к массе двигателя (вертикальные колебания выше резонанса "
                    "опор; поворот блока добавляется)"), cols, tuple(rows))


def _cut_table(recorded) -> Table | None:
    rows = []
    for r in recorded:
        v = r.verdict
        if r.ignition != "cut" or v is None:
            continue
        shares = ", ".join(f"{c + 1}: {s:.2f}" for c, s in enumerate(v.shares))
        rows.append({"r": str(r.number), "healthy": str(r.healthy),
                     "n": f"{r.speed.value * RPM:.0f}", "rise": f"{v.rise:.2f}",
                     "p": f"{v.p_value:.1e}",
                     "found": str(v.cylinder) if v.found else bi("none", "нет"),
                     "shares": shares,
                     "stated": str(r.cut_stated) if r.cut_stated else "—"})
    if not rows:
        return None
    cols = (("r", bi("record", "запись")), ("healthy", bi("healthy", "исправный")),
            ("n", bi("n, min⁻¹", "n, мин⁻¹")), ("rise", bi("half orders' rise", "рост полуцелых")),
            ("p", bi("p", "p")), ("found", bi("cylinder cut", "отключён цилиндр")),
            ("shares", bi("confidence by cylinder", "достоверность по цилиндрам")),
            ("stated", bi("stated", "указан")))
    return Table(bi("Ignition cut: the cylinder found", "Отключение зажигания: найденный "
                    "цилиндр"), cols, tuple(rows))


def tables(*, recorded, readings, results, points, reference, comparisons,
           **_) -> list[Table]:
    place = placements(recorded, readings, points)
    out = [_readings_table(results, place, reference),
           _meter_table(results, comparisons), _orders_table(recorded, results),
           _cut_table(recorded)]
    return [t for t in out if t is not None]


# ------------------------------------------------------------------------ figures

def _draw_speed(fig, results, place, lang):
    axes = fig.subplots(1, 3)
    scale = {"a": 1.0, "v": 1e3, "x": 1e6}
    units = {"a": _t(lang, "a, m/s²", "a, м/с²"), "v": _t(lang, "v, mm/s", "v, мм/с"),
             "x": _t(lang, "x, µm", "x, мкм")}
    groups = sorted({(p, d, ign) for p, d, _, ign in place.values()})
    for ax, q in zip(axes, QUANTITIES):
        for p, d, ign in groups:
            js = sorted((j for j, v in place.items() if (v[0], v[1], v[3]) == (p, d, ign)),
                        key=lambda j: place[j][2])
            js = [j for j in js if f"{q}_rms_{j}" in results and np.isfinite(place[j][2])]
            if not js:
                continue
            n = [place[j][2] for j in js]
            y = [scale[q] * results[f"{q}_rms_{j}"].value for j in js]
            U = [scale[q] * results[f"{q}_rms_{j}"].estimate.U for j in js]
            style = "s--" if ign == "cut" else "o-"
            ax.errorbar(n, y, U, fmt=style, ms=3, lw=1, capsize=2,
                        label=f"{p}, {DIRECTION[d][lang]}" + (_t(lang, ", cut", ", откл.")
                                                              if ign == "cut" else ""))
            meter = [(place[j][2], scale[q] * results[f"{q}_meter_{j}"].value) for j in js
                     if f"{q}_meter_{j}" in results]
            if meter:
                ax.plot(*zip(*meter), "kx", ms=5)
        ax.set_xlabel(_t(lang, "n, min⁻¹", "n, мин⁻¹"))
        ax.set_ylabel(units[q])
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.tight_layout()


def _draw_order_map(fig, recorded, lang):
    healthy = [r for r in recorded if r.ignition == "all" and r.marked]
    cols = len(healthy[0].channels) if healthy else 0
    if not cols:
        return
    axes = np.atleast_1d(fig.subplots(1, cols))
    speeds = np.array([r.speed.value * RPM for r in healthy])
    order = np.argsort(speeds)
    for p, ax in enumerate(axes):
        fits = [healthy[i].channels[p].fit for i in order]
        if any(f is None for f in fits):
            continue
        k = fits[0].order
        amp = np.array([f.amplitude[:k.size] for f in fits]).T
        mesh = ax.pcolormesh(speeds[order], k,
                             20 * np.log10(np.maximum(amp, 1e-12 * amp.max())),
                             shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label=_t(lang, "dB re 1 V", "дБ отн. 1 В"))
        ax.set_xlabel(_t(lang, "n, min⁻¹", "n, мин⁻¹"))
        ax.set_title(_t(lang, f"point {p + 1}", f"точка {p + 1}"), fontsize=8)
    axes[0].set_ylabel(_t(lang, "order", "порядок"))
    fig.tight_layout()


def _draw_cut(fig, recorded, phases, lang):
    cut = [r for r in recorded if r.ignition == "cut" and r.verdict is not None]
    if not cut:
        return
    r = cut[0]
    v = r.verdict
    ax = fig.subplots()
    span = 720 if r.cycle_marks else 360
    ax.plot(np.degrees(v.angle), v.envelope, lw=1.2)
    for c, phi in enumerate(np.degrees(phases)):
        ax.axvline(phi % span, color="0.5", lw=0.7, ls=":")
        ax.annotate(str(c + 1), (phi % span, 1), xycoords=("data", "axes fraction"),
                    xytext=(2, -10), textcoords="offset points", fontsize=8)
    ax.set_xlabel(_t(lang, "crank angle from cylinder 1's firing TDC, °",
                     "угол поворота от ВМТ сгорания 1-го цилиндра, °"))
    ax.set_ylabel(_t(lang, "|deficit|, V", "|дефицит|, В"))
    ax.grid(alpha=0.3)


def figures(*, recorded, readings, results, points, phases, **_) -> list[Figure]:
    place = placements(recorded, readings, points)
    out = [Figure("speed", bi("RMS acceleration, velocity and displacement against the speed "
                              "by point and direction (± U); dashed: a cylinder cut; ×: the "
                              "meter", "СКЗ виброускорения, виброскорости и виброперемещения "
                              "в зависимости от частоты вращения по точкам и направлениям "
                              "(± U); штрих — цилиндр отключён; × — виброметр"),
                  lambda fig, lang: _draw_speed(fig, results, place, lang), size=(9.0, 3.4))]
    if any(r.ignition == "all" and r.marked for r in recorded):
        out.append(Figure("order_map", bi("Order map: each order's acceleration amplitude "
                                          "(dB) over the speed, by point",
                                          "Карта гармоник: амплитуда виброускорения каждого "
                                          "порядка (дБ) по частоте вращения, по точкам"),
                          lambda fig, lang: _draw_order_map(fig, recorded, lang),
                          size=(9.0, 3.2)))
    if any(r.cut for r in recorded):
        out.append(Figure("cut", bi("Ignition cut: the envelope of the orders' deficit over "
                                    "the working cycle; dotted: the cylinders' firing TDCs",
                                    "Отключение зажигания: огибающая дефицита гармоник за "
                                    "цикл; пунктир — ВМТ сгорания цилиндров"),
                          lambda fig, lang: _draw_cut(fig, recorded, phases, lang)))
    return out


# ------------------------------------------------------------------------ conclusion

def conclusion(*, recorded, readings, results, points, **_) -> list[dict]:
    """The largest acceleration and where, the directions' order, the cut cylinder."""
    lines = []
    place = placements(recorded, readings, points)
    a = {j: results[f"a_rms_{j}"].value for j in place if f"a_rms_{j}" in results}
    if a:
        j = max(a, key=a.get)
        p, d, n, _ = place[j]
        lines.append(bi(f"The largest RMS acceleration is {result_pm(results, f'a_rms_{j}')} "
                        f"m/s² ({a[j] / 9.80665:.2f} g) at point {p}, {DIRECTION[d]['en']}, "
                        f"{n:.0f} min⁻¹ (the manual: 4–100 m/s², up to 160)",
                        f"Наибольшее СКЗ виброускорения {result_pm(results, f'a_rms_{j}')} "
                        f"м/с² ({a[j] / 9.80665:.2f} g) в точке {p}, {DIRECTION[d]['ru']}, "
                        f"{n:.0f} мин⁻¹ (по методичке 4–100 м/с², до 160)"))
        by_dir = {}
        for jj, v in a.items():
            by_dir.setdefault(place[jj][1], []).append(v)
        ranked = sorted(by_dir, key=lambda d: -np.mean(by_dir[d]))
        lines.append(bi("Mean acceleration by direction, largest first: "
                        + ", ".join(DIRECTION[d]["en"] for d in ranked)
                        + " (the manual: vertical, transverse, longitudinal)",
                        "Среднее виброускорение по направлениям, по убыванию: "
                        + ", ".join(DIRECTION[d]["ru"] for d in ranked)
                        + " (по методичке: вертикальное, поперечное, продольное)"))
    for r in recorded:
        v = r.verdict
        if r.ignition != "cut" or v is None:
            continue
        if v.found:
            lines.append(bi(f"Record {r.number}: the half orders rose {v.rise:.1f} times; "
                            f"cylinder {v.cylinder} is cut (confidence {v.confidence:.2f})",
                            f"Запись {r.number}: полуцелые гармоники выросли в {v.rise:.1f} "
                            f"раза; отключён цилиндр {v.cylinder} (достоверность "
                            f"{v.confidence:.2f})"))
        else:
            lines.append(bi(f"Record {r.number}: no cylinder was found cut",
                            f"Запись {r.number}: отключённый цилиндр не найден"))
    return lines
