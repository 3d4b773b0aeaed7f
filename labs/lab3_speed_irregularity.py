"""Lab 3. Speed irregularity of the engine on a steady regime.

The manual's chapter: a spur gear of z teeth on the crankshaft tail passes an inductive
sensor, f = n z/60; the pulses are shaped, turned into a voltage proportional to the speed
and recorded; δ = (ω_max − ω_min)/ω_cp over one working cycle, ω_cp = (ω_max + ω_min)/2
= πn/30 (720° for a four-stroke engine), for two regimes 20–50 min⁻¹ apart at
(0.6…0.8) n_nom. Typical δ: automotive engines 0.01–0.02, tractor engines 0.003–0.01.

Here the sensor's own signal (or a counter's edge times) is reduced: every tooth edge is timed
(:mod:`processing.speed.edges`), numbered (:mod:`processing.speed.toothwheel`), and ω(α) of every
working cycle is found twice — tooth by tooth and by a Fourier fit of the edge times
(:mod:`processing.speed.angular_speed`). The student's reading of the frequency-to-voltage
oscillogram (h_max, h_min and the mean level, scaled by the tachometer) is reduced by the manual's
formula and compared with the signal's δ. A photograph of the oscillogram is read by the machine
(:mod:`processing.vision`): δ of its mean cycle, and the mean speed from its TDC marks on the time
marks' scale; with no recording, the photograph alone gives the regime.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 3 ("Определение неравномерности хода двигателя на установившемся режиме").
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from labs import lab3_speed_irregularity_report as report
from processing.speed.angular_speed import (CycleSpeeds, Irregularity, fit_cycles, jackknife,
                                      pitch_uncertainty, tooth_cycles)
from processing.speed.cycle_range import cycle_range
from processing.diagnostics import (GapNotFoundWarning, InconsistentInputWarning, InputError,
                                    PitchErrorWarning, ShortRecordWarning, TeethMiscountedWarning,
                                    UndersampledWarning, UnequalCyclesWarning, collect_notices)
from processing.speed.edges import METHODS as EDGE_METHODS
from processing.speed.edges import stream_edges
from processing.measurement import (ENGINE_SPEED, SAMPLE_RATE, STROKES, Field, Inputs, LabSpec,
                                    Section, bi, image_section)
from processing.inputs.record_quality import check_pulse_channel, check_record
from processing.inputs.reuse import by_content
from processing.result import (KEY, STRICTLY_POSITIVE, LabResult, Typical, compare, computed,
                               flag_estimates, result_values)
from processing.inputs.signals import image_options, open_channel, read_edge_times, read_figures
from processing.speed.toothwheel import ToothTrack, calibrate_pitch, recurring_gap, track_teeth
from processing.uncertainty import Measured, propagate

REFERENCE_RANGES = {"automotive": (0.01, 0.02), "tractor": (0.003, 0.01)}
"""The manual's typical δ (lab 3): automotive 0.01–0.02, tractor 0.003–0.01."""

TYPICAL_FOR = {"automotive": bi("automotive engines", "автомобильные двигатели"),
                "tractor": bi("tractor engines", "тракторные двигатели"),
                None: bi("automotive and tractor engines",
                         "автомобильные и тракторные двигатели")}
"""Whose typical δ a report compares with: the engine's kind, or both kinds' where the file
does not say it."""


def typical_delta(kind: str | None) -> Typical:
    """The manual's typical δ for an engine of ``kind`` (None: either kind's)."""
    lows, highs = zip(*(v for k, v in REFERENCE_RANGES.items() if kind in (None, k)))
    return Typical(min(lows), max(highs), TYPICAL_FOR[kind])

MIN_SAMPLES_PER_TOOTH = 12.0
"""Below this the edges' sub-sample timing degrades fast (the benchmark's stability map)."""

MIN_CYCLES = 3
"""Complete working cycles δ needs at all: its uncertainty comes from their scatter."""

FEW_CYCLES = 8
"""Below this many complete cycles δ of the mean cycle reads low by up to 10 % (the higher
orders do not yet stand out of the noise, 2–7 cycles of synthetic and independent records)
and the jackknife u over so few cycles does not cover it."""

UNEQUAL_CYCLES = 0.01
"""Spread (max − min)/mean of the cycle durations above which the regime is not steady."""

PITCH_BIAS = 0.02
"""Relative bias of the tooth-by-tooth δ from pitch errors above which a warning is given."""

PLAUSIBLE = {"automotive": (0.002, 0.1), "tractor": (0.0006, 0.05)}
"""δ a photographed oscillogram may report, by the engine's kind: five times beyond the manual's
typical range either way (automotive 0.01–0.02, tractor 0.003–0.01; a worn engine at a low
speed lies well above it). Outside, the zero or the scale taken is not the trace's: refused."""

ENGINE_KINDS = {"automotive": "an automotive engine", "tractor": "a tractor engine"}
"""The engine's kind in messages."""
ENGINE_KINDS_RU = {"automotive": "автомобильного двигателя", "tractor": "тракторного двигателя"}
"""The same in Russian (genitive: "для автомобильного двигателя")."""

TACH_REFUSE = 0.15
"""Relative disagreement of the oscillogram's TDC marks' mean speed with the tachometer beyond
which the marks read are not the TDC marks (a lid's edge or a trace taken for their line, a
wrong mark period): refused instead of warned."""

PHOTO_FIX = {"en": "photograph the oscillogram again, sharp and whole, with its speed trace, "
                   "zero line and marks in the frame",
             "ru": "сфотографируйте осциллограмму заново, резко и целиком, с линией скорости, "
                   "нулевой линией и отметками в кадре"}
"""What to do about a flat or noise-only trace read off a photograph."""

TOOTH_PULSES = {"en": "tooth pulses", "ru": "импульсов зубьев"}
"""The pulses of the toothed wheel's sensor, as a message names them."""

ORDINATE = dict(unit="mm", limit="0.5 mm", plausible=("1 mm", "500 mm"))
"""A height read off an oscillogram's paper with a ruler."""

SPEC = LabSpec(
    id="lab3", number="3",
    title=bi("Speed irregularity of the engine on a steady regime",
             "Определение неравномерности хода двигателя на установившемся режиме"),
    goal=bi("Determine the coefficient of speed irregularity δ of the crankshaft on two steady "
            "regimes from the speed sensor's pulses and compare it with typical values.",
            "Экспериментально определить степень неравномерности вращения коленчатого вала δ "
            "на двух установившихся режимах по импульсам датчика частоты вращения и сравнить "
            "со среднестатистическими данными."),
    sections=(
        Section("wheel", bi("Toothed wheel and sensor (for recordings)",
                            "Зубчатое колесо и датчик (для записей)"), fields=(
                    Field("z", bi("number of tooth pitches (incl. missing teeth)",
                                  "число шагов зубьев (вместе с пропущенными)"),
                          kind="count", symbol="z", example=60),
                    Field("missing", bi("teeth missing at the reference gap (0: none)",
                                        "число пропущенных зубьев в метке (0 — нет метки)"),
                          kind="count", allow_zero=True, default=0),
                    Field("calibration", bi("record of the wheel coasting smoothly (pitch "
                                            "calibration), a file", "запись выбега (калибровка "
                                            "шага зубьев), файл"), kind="file", required=False),
                    Field("calibration_channel", bi("channel of the calibration record",
                                                    "канал записи выбега"),
                          kind="text", required=False),
                )),
        Section("engine", bi("Engine", "Двигатель"), required=True, fields=(
            Field("strokes", bi("strokes per cycle", "тактность"), **STROKES),
            Field("cylinders", bi("number of cylinders", "число цилиндров"), kind="count",
                  required=False, symbol="i"),
            Field("kind", bi("kind (for the typical range)", "тип (для сравнения)"),
                  kind="choice", required=False,
                  choices={k: TYPICAL_FOR[k] for k in REFERENCE_RANGES}),
        )),
        Section("analysis", bi("Signal analysis", "Обработка сигнала"), fields=(
            Field("edge_method", bi("edge timing between samples", "интерполяция фронта"),
                  kind="choice", default="fit",
                  choices=dict(zip(EDGE_METHODS, (
                      bi("linear", "линейная"), bi("cubic", "кубическая"),
                      bi("fitted edge", "по подобранному фронту"),
                      bi("matched pulse", "по образцу импульса"))))),
            Field("orders", bi("highest order of ω(α) fitted (default: chosen from the noise)",
                               "наибольший порядок гармоник ω(α) (по умолчанию — по шуму)"),
                  kind="count", required=False),
        )),
        Section("regime", bi("Regime", "Режим"), many=True, required=True, fields=(
            Field("signal", bi("sensor recording: CSV, WAV or HDF5 file",
                               "запись датчика: файл CSV, WAV или HDF5"),
                  kind="file", required=False, example="regime1.wav"),
            Field("channel", bi("channel (column, dataset or WAV channel number)",
                                "канал (столбец, набор данных или номер канала WAV)"),
                  kind="text", required=False),
            Field("tdc_channel", bi("once-per-revolution (TDC) channel, if recorded",
                                    "канал отметки ВМТ (раз за оборот), если записан"),
                  kind="text", required=False),
            Field("sample_rate", bi("sample rate, if the file does not say",
                                    "частота дискретизации, если её нет в файле"),
                  **SAMPLE_RATE, required=False, symbol="f_s"),
            Field("edges", bi("or: tooth edge times from a counter (CSV, s)",
                              "или: моменты фронтов от счётчика (CSV, с)"),
                  kind="file", required=False),
            Field("n_tach", bi("tachometer reading", "показание тахометра"), **ENGINE_SPEED,
                  limit="5 rpm", symbol="n", example=1800),
            Field("h_max", bi("oscillogram: highest point of the speed trace",
                              "осциллограмма: наибольшая ордината"), **ORDINATE,
                  required=False, symbol="h_max"),
            Field("h_min", bi("oscillogram: lowest point of the speed trace",
                              "осциллограмма: наименьшая ордината"), **ORDINATE,
                  required=False, symbol="h_min"),
            Field("h_mean", bi("oscillogram: mean level (default (h_max + h_min)/2)",
                               "осциллограмма: средний уровень (по умолчанию (h_max + h_min)/2)"),
                  **ORDINATE, required=False, symbol="h_cp"),
            Field("oscillogram", bi("or: a photograph or scan of the oscillogram, with its zero "
                                    "line (or the converter's scale) and TDC marks ([image])",
                                    "или: снимок осциллограммы с нулевой линией (или с масштабом "
                                    "преобразователя) и отметками ВМТ ([image])"),
                  kind="file", required=False, example="regime1.jpg"),
            Field("converter_scale", bi("the frequency-to-voltage converter's scale on the "
                                        "paper (calibration), for an oscillogram without its "
                                        "zero line", "масштаб преобразователя «частота-"
                                        "напряжение» на ленте (тарировка) — для осциллограммы "
                                        "без нулевой линии"),
                  unit="mm/rpm", required=False, symbol="μ",
                  plausible=("0.0005 mm/rpm", "5 mm/rpm")),
            Field("trace", bi("the speed trace on the photograph (0: the topmost)",
                              "линия скорости на снимке (0 — верхняя)"),
                  kind="count", allow_zero=True, required=False),
        )),
        image_section(zero_default=None, zero_help=bi(
            "the speed trace's zero: \"line\" (its zero line on the paper) or \"mean\" (the "
            "converter's scale or h_mean scales it); default: the zero line if one is on the "
            "paper, else the converter's scale",
            "ноль линии скорости: \"line\" (нулевая линия на ленте) или \"mean\" (масштаб "
            "преобразователя или h_mean); по умолчанию — нулевая линия, если она есть, иначе "
            "масштаб преобразователя")),
    ),
)


# ------------------------------------------------------------------------ formulas

def delta_oscillogram(h_max, h_min, h_mean=None):
    """δ read off a frequency-to-voltage oscillogram, the manual's way.

    .. math:: \\delta = \\frac{h_{max} - h_{min}}{h_{cp}}, \\qquad
              h_{cp} = \\frac{h_{max} + h_{min}}{2}\\ \\text{(unless read)}

    The trace's height is proportional to ω, so the scale (mm per min⁻¹, from the
    tachometer) cancels.

    Parameters
    ----------
    h_max, h_min : float or ndarray
        Highest and lowest ordinates of the speed trace over a working cycle. [m]
    h_mean : float or ndarray, optional
        The mean level, if read; otherwise the mid-range. [m]

    Returns
    -------
    float or ndarray
        δ. [1]

    Examples
    --------
    >>> round(delta_oscillogram(0.0408, 0.0400), 5)
    0.0198
    """
    h_cp = (h_max + h_min) / 2 if h_mean is None else h_mean
    return (h_max - h_min) / h_cp


def oscillogram_scale(h_mean, n_tach):
    """Scale of the oscillogram: mm of trace per min⁻¹ (manual, lab 3, step 6).

    Parameters
    ----------
    h_mean : float
        Mean level of the trace. [m]
    n_tach : float
        Tachometer reading. [rad/s]

    Returns
    -------
    float
        Scale in m per rad/s (× 1000·π/30 for mm per min⁻¹).
    """
    return h_mean / n_tach


def delta_scaled(swing, scale=None, n_tach=None, h_mean=None):
    """δ of a speed trace whose zero is not on the paper, the manual's other scaling (lab 3,
    step 6: the oscillogram's scale in mm per min⁻¹).

    .. math:: \\delta = \\frac{h_{max} - h_{min}}{\\mu\\,\\omega_{cp}}
              \\quad\\text{or}\\quad \\frac{h_{max} - h_{min}}{h_{cp}}

    μ the frequency-to-voltage converter's scale (its calibration), ω_cp = πn/30 from the
    tachometer; or h_cp, the trace's mean height above the converter's zero, read.

    Parameters
    ----------
    swing : float or ndarray
        h_max − h_min of the mean cycle. [m]
    scale : float or ndarray, optional
        μ. [m per rad/s]
    n_tach : float or ndarray, optional
        The tachometer's speed. [rad/s]
    h_mean : float or ndarray, optional
        h_cp, used when no scale is given. [m]

    Returns
    -------
    float or ndarray
        δ. [1]

    Examples
    --------
    >>> mu = 0.05e-3 / (np.pi / 30)          # 0.05 mm per min⁻¹
    >>> round(delta_scaled(1.35e-3, mu, 1800 * np.pi / 30), 5)
    0.015
    """
    if scale is None:
        return swing / h_mean
    return swing / (scale * n_tach)


FORMULAS = [
    bi("Tooth frequency f = n z/60; instantaneous speed over a pitch ω_k = Δθ_k/Δt_k",
       "Частота следования зубьев f = n z/60; мгновенная скорость на шаге ω_k = Δθ_k/Δt_k"),
    bi("Fourier fit of the edge times: t(θ) = t₀ + ∫₀^θ dφ/ω(φ), 1/ω a Fourier series in the "
       "cycle's orders (half orders for a four-stroke engine)",
       "Аппроксимация моментов фронтов: t(θ) = t₀ + ∫₀^θ dφ/ω(φ), 1/ω — ряд Фурье по порядкам "
       "цикла (полупорядки для четырёхтактного двигателя)"),
    bi("δ = (ω_max − ω_min)/ω_mean, ω_mean = cycle angle / cycle time; the manual's form "
       "δ′ = (ω_max − ω_min)/ω_cp = (ω_max² − ω_min²)/(2ω_cp²), ω_cp = (ω_max + ω_min)/2",
       "δ = (ω_max − ω_min)/ω_ср, ω_ср = угол цикла / время цикла; по методичке "
       "δ′ = (ω_max − ω_min)/ω_cp = (ω_max² − ω_min²)/(2ω_cp²), ω_cp = (ω_max + ω_min)/2"),
    bi("Oscillogram: δ = (h_max − h_min)/h_cp; scale μ = h_cp/n (mm per min⁻¹); without its "
       "zero line δ = (h_max − h_min)/(μ·n) with the converter's scale μ",
       "Осциллограмма: δ = (h_max − h_min)/h_cp; масштаб μ = h_cp/n (мм/мин⁻¹); без нулевой "
       "линии δ = (h_max − h_min)/(μ·n) по масштабу преобразователя μ"),
    bi("Uncertainty of the mean cycle: jackknife over the cycles (type A, n − 1 degrees of freedom)",
       "Неопределённость среднего цикла: метод складного ножа по циклам (тип A, n − 1 степеней свободы)"),
]

REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, lab 3.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: ВлГУ, 2003. Лаб. работа №3."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]


# ------------------------------------------------------------------------ one regime

@dataclass(frozen=True)
class Oscillogram:
    """The speed trace read off a photographed oscillogram: its cycles' fits, δ and the mean
    speed."""

    channel: object
    cycles: object
    """:class:`processing.speed.cycle_range.CycleRange` of the working cycles between TDC marks."""
    delta: Measured | None
    """δ from the trace's height above its zero line (None: scaled by the converter)."""
    omega_mean: Measured
    """Cycle angle over the mean time between the cycles' TDC marks. [rad/s]"""
    swing: Measured | None = None
    """h_max − h_min of the mean cycle on the paper, where the trace has no zero line: δ is
    then the swing over the converter's scale times the speed, or over h_mean. [m]"""


def mean_speed(starts, cycle_angle: float, time_scale: Measured) -> Measured:
    """Mean angular speed from the times of successive working cycles' starts.

    .. math:: \\omega_{cp} = \\frac{\\Theta}{\\bar{\\tau}}, \\qquad
              \\bar{\\tau} = \\frac{t_n - t_0}{n}

    Θ the cycle angle (4π for a four-stroke engine). Type A from the scatter of the n cycle
    times τ_k (n − 1 degrees of freedom: the marks' reading and the engine's own cycle-to-cycle
    scatter); type B from the relative u of the time scale (a paper record's time marks).

    Parameters
    ----------
    starts : array_like
        Times of the cycles' starts, n + 1 of them, n ≥ 2. [s]
    cycle_angle : float
        Θ. [rad]
    time_scale : Measured
        The scale the times were read on (only its relative u is used).

    Returns
    -------
    Measured
        ω_cp. [rad/s]

    Examples
    --------
    >>> w = mean_speed([0.0, 0.0666, 0.1334, 0.2], 4 * np.pi, Measured(1.0))
    >>> round(w.value * 30 / np.pi, 1)
    1800.0
    """
    tau = np.diff(np.asarray(starts, dtype=float))
    n = tau.size
    value = cycle_angle / tau.mean()
    u_a = value * tau.std(ddof=1) / np.sqrt(n) / tau.mean()
    return Measured(float(value), float(u_a), n - 1,
                    u_b=float(value * time_scale.u / abs(time_scale.value)))


def _oscillogram(inputs: Inputs, i: int, entry: dict, revolutions: int) -> Oscillogram | None:
    """δ of the mean working cycle of a photographed speed trace: its swing over its level
    above the zero line (the manual's (h_max − h_min)/h_cp, read by the machine), the cycles
    bounded by every ``revolutions``-th TDC mark, u by the jackknife over the cycles. The
    light spot and the photograph's blur flatten the ripple (order m of a cycle τ by
    exp(−(2πmσ/τ)²/2), σ the stroke's spread: :attr:`~processing.vision.record.PaperRecord.
    stroke_blur`): δ restored, with the restoration's size as the width of a rectangle
    (type B)."""
    if "oscillogram" not in entry:
        return None
    field, path = f"regime[{i}].oscillogram", entry["oscillogram"]
    if "h_max" in entry or "h_min" in entry:
        raise inputs.error("both a photograph of the oscillogram and readings off it are given",
                           "give the photograph (oscillogram) or the readings (h_max, h_min), "
                           "not both", field,
                           ("даны и фотография осциллограммы, и отсчёты по ней",
                            "дайте фотографию (oscillogram) или отсчёты (h_max, h_min), но не "
                            "то и другое"))
    channel = _speed_trace(inputs, i, entry)
    check_record(channel.value[np.isfinite(channel.value)], channel.sample_rate, file=str(path),
                 field=field, channel=str(channel.name), purpose={"en": "δ", "ru": "δ"}, fix=PHOTO_FIX)
    tdc = channel.marks.get("tdc", np.array([]))
    starts = tdc[::revolutions]
    if starts.size < 3:
        raise InputError(f"{tdc.size} TDC mark(s) found on the oscillogram: δ needs at least two "
                         "whole working cycles between them", "photograph the record with its "
                         "TDC mark line and at least two working cycles", file=str(path),
                         field=field, ru=(f"на осциллограмме найдено отметок ВМТ: {tdc.size}, "
                                          "а для δ между ними нужны хотя бы два целых рабочих "
                                          "цикла", "сфотографируйте запись с линией отметок "
                                          "ВМТ и хотя бы двумя рабочими циклами"))
    try:
        cycles = cycle_range(channel.time, channel.value, starts)
    except ValueError as exc:
        raise InputError(str(exc), "photograph the trace sharply, its whole length",
                         file=str(path), field=field,
                         ru=(getattr(exc, "ru", None) or f"'{exc}'",
                             "сфотографируйте линию резко, по всей её длине")) from None
    inside = starts[(starts >= channel.time[0]) & (starts <= channel.time[-1])]
    omega = mean_speed(inside, 2 * np.pi * revolutions, channel.time_scale)
    engine = inputs["engine"]
    _check_tdc_speed(omega, entry, tdc, channel, path, field,
                     engine.get("cylinders", 1) / revolutions)
    # the spot and the camera's blur low-passed the ripple: restored by the σ the stroke
    # shows, the restoration known within its own size (a rectangle that wide, type B)
    full = cycles.deblurred(channel.stroke_blur)
    if channel.overlay.taken is None:            # no zero on the paper: the swing alone
        # each extreme is read within ± half the stroke (rectangular), and the blur's range
        swing, u = full.absolute_swing()
        swing = _jack(swing, u, cycles.cycles,
                      u_b=np.hypot(abs(full.swing - cycles.swing) / (2 * np.sqrt(3)),
                                   channel.stroke_value / np.sqrt(6)))
        osc = Oscillogram(channel, cycles, None, omega, swing)
        nominal = swing.value / _converter_level(entry)
    else:
        span = abs(full.swing / full.level - cycles.swing / cycles.level)
        delta, u = full.relative_swing()
        osc = Oscillogram(channel, cycles, _jack(delta, u, cycles.cycles,
                                                 u_b=span / (2 * np.sqrt(3))), omega)
        nominal = delta
    _check_plausible(inputs, entry, nominal, channel, path, field)
    return osc


def _speed_trace(inputs: Inputs, i: int, entry: dict):
    """The speed trace read off the photograph, its deflection from its zero line, or from its
    mean level where the file scales it otherwise (the converter's scale or h_mean): as the
    file says (``zero`` in [image]), else the zero line if one is on the paper, else the
    scale."""
    field, path = f"regime[{i}].oscillogram", entry["oscillogram"]
    options = image_options(inputs.sections.get("image"))
    scaled = "converter_scale" in entry or "h_mean" in entry
    zero = options.pop("zero", None)
    if zero == "mean" and not scaled:
        raise InputError("zero = \"mean\" measures the speed trace from its own mean level, "
                         "so nothing scales its swing to a speed", SCALE_FIX,
                         file=inputs.file, field="image.zero",
                         ru=("при zero = \"mean\" линия скорости отсчитывается от своего "
                             "среднего уровня, и её размах нечем перевести в скорость",
                             SCALE_FIX_RU))
    if zero is None and "converter_scale" in entry:
        zero = "mean"                 # the calibration scales the trace; any line is not needed
    try:
        channel = open_channel(path, channel=entry.get("trace"), field=field,
                               image={**options, "zero": zero or "line"})
    except InputError as exc:
        if zero is None and scaled and (exc.field or "").endswith("zero"):
            return open_channel(path, channel=entry.get("trace"), field=field,
                                image={**options, "zero": "mean"})
        if (exc.field or "").endswith("zero"):
            raise InputError(exc.problem, SCALE_FIX, file=exc.file, field=field,
                             ru=exc.ru and (exc.ru[0], SCALE_FIX_RU)) from None
        raise
    if channel.overlay.taken is None and channel.unit != "m":
        raise InputError("the converter's scale is in mm of paper, but the photograph has no "
                         "length scale", "give dpi (a scan), paper_width or grid in [image]",
                         file=inputs.file, field="image",
                         ru=("масштаб преобразователя задан в мм бумаги, а у снимка нет "
                             "масштаба длины", "укажите в [image] dpi (для скана), paper_width "
                             "или grid"))
    return channel


SCALE_FIX = ("give the frequency-to-voltage converter's scale from its calibration "
             "(converter_scale = \"… mm/rpm\" in the regime) or the trace's mean height above "
             "the converter's zero (h_mean), and zero = \"mean\" in [image]; or photograph the "
             "record with its zero line")
SCALE_FIX_RU = ("укажите масштаб преобразователя частота–напряжение по его тарировке "
                "(converter_scale = \"… mm/rpm\" в режиме) или высоту средней линии записи над "
                "нулём преобразователя (h_mean) и zero = \"mean\" в [image]; либо "
                "сфотографируйте запись с её нулевой линией")
"""What to do about a speed trace that nothing on the paper or in the file scales."""


def _converter_level(entry: dict) -> float:
    """The trace's mean height above the converter's zero: μ·ω from the converter's scale and
    the tachometer, or h_mean as read. [m]"""
    if "converter_scale" in entry:
        return entry["converter_scale"].value * entry["n_tach"].value
    return entry["h_mean"].value


FIRING_MATCH = 0.05
"""How close (relative) the TDC marks' speed must come to the tachometer's times the firings
a revolution for the marks read to be taken for the speed trace's ripple."""


def _check_tdc_speed(omega: Measured, entry: dict, tdc, channel, path, field: str,
                     firings: float) -> None:
    """The TDC marks' mean speed against the tachometer: far apart, the marks read are not
    the TDC marks (a lid's edge, a trace or the time marks taken for them) or the mark
    period is wrong; refused, naming the lines found. Marks that come ``firings`` times a
    revolution (the cylinders' firings: two on a four-cylinder four-stroke engine) are the
    dips of the speed trace's ripple, the trace taken for a mark line."""
    n_t = entry["n_tach"]
    gap = omega.value / n_t.value - 1
    tolerance = TACH_REFUSE + 2 * np.hypot(n_t.u / n_t.value, omega.u / omega.value)
    if firings >= 2 and abs(omega.value / (firings * n_t.value) - 1) < FIRING_MATCH:
        rpm, tach = omega.value * 30 / np.pi, n_t.value * 30 / np.pi
        raise InputError(
            f"the {tdc.size} TDC marks read off the oscillogram give {rpm:.0f} min⁻¹, "
            f"{firings:g} times the tachometer's {tach:.0f} min⁻¹: they come with the "
            "cylinders' firings, so the speed trace's ripple (its dips) was taken for a line "
            f"with TDC marks; {channel.lines}",
            "look at the overlay; photograph or scan the record with its TDC mark line (a "
            "mark each revolution) whole and sharp, or read h_max and h_min off the trace "
            "by hand", file=str(path), field=field,
            ru=(f"{tdc.size} отметок ВМТ на осциллограмме дают {rpm:.0f} мин⁻¹ — в "
                f"{firings:g} раза больше, чем тахометр ({tach:.0f} мин⁻¹): они идут с "
                "частотой вспышек, то есть за линию с отметками ВМТ приняты провалы "
                f"пульсаций кривой скорости; {channel.lines_ru}",
                "посмотрите на наложение; снимите или отсканируйте запись с линией отметок "
                "ВМТ (одна отметка за оборот) целиком и резко или прочтите h_max и h_min с "
                "кривой вручную"))
    if abs(gap) > tolerance:
        raise InputError(
            f"the {tdc.size} TDC marks read off the oscillogram give a mean speed of "
            f"{omega.value * 30 / np.pi:.0f} min⁻¹, the tachometer {n_t.value * 30 / np.pi:.0f} "
            f"min⁻¹ ({100 * gap:+.0f} %): what was read as the TDC marks is not them, or the "
            f"time marks' period is wrong; {channel.lines}",
            "check mark_period in [image] and the tachometer reading, and photograph the record "
            "with its TDC mark line (a mark each revolution) whole and sharp",
            file=str(path), field=field,
            ru=(f"по {tdc.size} отметкам ВМТ на осциллограмме средняя частота вращения "
                f"{omega.value * 30 / np.pi:.0f} мин⁻¹, по тахометру {n_t.value * 30 / np.pi:.0f} "
                f"мин⁻¹ ({100 * gap:+.0f} %): за отметки ВМТ принято не то, или неверен период "
                f"отметок времени; {channel.lines_ru}", "проверьте mark_period в [image] и "
                "показание тахометра и сфотографируйте запись с линией отметок ВМТ (отметка "
                "на каждый оборот) целиком и резко"))


def _check_plausible(inputs: Inputs, entry: dict, delta: float, channel, path,
                     field: str) -> None:
    """δ read off a photograph must be positive and plausible for the engine
    (:data:`PLAUSIBLE`): else the zero or the scale taken is not the trace's."""
    kind = inputs["engine"].get("kind")
    lo = min(PLAUSIBLE[k][0] for k in PLAUSIBLE if kind in (None, k))
    hi = max(PLAUSIBLE[k][1] for k in PLAUSIBLE if kind in (None, k))
    if lo <= delta <= hi:
        return
    zero, zero_ru = (("its zero line", "её нулевой линии") if channel.overlay.taken is not None
                     else ("the converter's scale", "масштабу преобразователя")
                     if "converter_scale" in entry else ("h_mean", "h_mean"))
    raise InputError(
        f"δ = {delta:.4g} read off the oscillogram, measured from {zero}, is not plausible for "
        f"{ENGINE_KINDS.get(kind, 'an engine')} ({lo:g}…{hi:g}): the zero or "
        f"scale taken is not the trace's; {channel.lines}",
        "look at the overlay: if the zero line taken is the paper's edge, a grid line or "
        "another beam's, " + SCALE_FIX[0].lower() + SCALE_FIX[1:], file=str(path), field=field,
        ru=(f"δ = {delta:.4g}, прочитанное по осциллограмме от {zero_ru}, неправдоподобно для "
            f"{ENGINE_KINDS_RU.get(kind, 'двигателя')} ({lo:g}…{hi:g}): взятые ноль или "
            f"масштаб — не этой линии; {channel.lines_ru}",
            "посмотрите на наложение: если за нулевую линию взят край бумаги, линия сетки или "
            "линия другого луча, " + SCALE_FIX_RU))


@dataclass
class Recording:
    """What a regime's sensor recording (or counter's edge times) reduces to."""

    track: ToothTrack
    fourier: CycleSpeeds
    tooth: CycleSpeeds
    u_fourier: Irregularity
    u_tooth: Irregularity
    samples_per_tooth: float | None
    pitch_bias: dict


@dataclass
class Regime:
    """What one regime reduces to: its recording, its photographed oscillogram, or both."""

    number: int
    recording: Recording | None
    oscillogram: Oscillogram | None

    @property
    def cycles(self) -> int:
        """Working cycles δ was found over (the recording's, else the photograph's)."""
        if self.recording is not None:
            return self.recording.fourier.cycles
        return self.oscillogram.cycles.cycles


def _edges_of(channel, method: str) -> np.ndarray:
    """Edge times of a channel, streamed chunk by chunk. [s]"""
    return stream_edges(channel.chunks(), method) / channel.sample_rate


def _signal_edges(inputs: Inputs, i: int, entry: dict, method: str):
    """Edge times of a regime, its TDC marks and the samples per tooth (None for counters)."""
    where = f"regime[{i}]"
    if "edges" in entry:
        return read_edge_times(entry["edges"], field=f"{where}.edges"), None, None
    rate = entry["sample_rate"].value if "sample_rate" in entry else None
    path = entry["signal"]
    channel = open_channel(path, channel=entry.get("channel"), sample_rate=rate,
                           field=f"{where}.signal")
    check_pulse_channel(channel, field=f"{where}.signal", pulses=TOOTH_PULSES)
    times = _edges_of(channel, method)
    if times.size < 3:
        raise InputError(f"no tooth pulses found in channel '{channel.name}' "
                         f"({times.size} edges in {channel.duration:.3g} s): too short a "
                         "record, or pulses too slow for it", "record at least eight working "
                         "cycles of the sensor's channel", file=str(path),
                         field=f"{where}.signal")
    tdc = None
    if "tdc_channel" in entry:
        mark = open_channel(path, channel=entry["tdc_channel"], sample_rate=rate,
                            field=f"{where}.tdc_channel")
        check_pulse_channel(mark, field=f"{where}.tdc_channel", pulses={"en": "TDC marks", "ru": "отметок ВМТ"})
        tdc = _edges_of(mark, method)
    return times, tdc, channel.sample_rate * float(np.median(np.diff(times)))


def _track(inputs: Inputs, times, field: str, path, tdc=None) -> ToothTrack:
    """The teeth of a record numbered, with the wheel the file describes checked against the
    gap the record shows; every failure located at the record and its field."""
    wheel = inputs["wheel"]
    seen = recurring_gap(times)
    if seen is not None and seen != (wheel["z"], wheel["missing"]):
        z, missing = seen
        wrong = "wheel.missing" if z == wheel["z"] or missing != wheel["missing"] else "wheel.z"
        raise InputError(f"the record shows a gap of {missing} missing teeth every {z - missing} "
                         f"pulses, a {z}−{missing} wheel, but the file describes z = {wheel['z']} "
                         f"with {wheel['missing']} missing", f"write z = {z} and missing = "
                         f"{missing} in [wheel] (z counts the missing teeth too)",
                         file=inputs.file, field=wrong)
    try:
        return track_teeth(times, wheel["z"], wheel["missing"], reference_times=tdc)
    except InputError as exc:
        raise InputError(exc.problem, exc.fix, file=str(path), field=field, ru=exc.ru) from None


def _calibration(inputs: Inputs, method: str):
    wheel = inputs.sections.get("wheel", {})
    if "calibration" not in wheel:
        return None
    path = wheel["calibration"]
    channel = open_channel(path, channel=wheel.get("calibration_channel"),
                           field="wheel.calibration")
    check_pulse_channel(channel, field="wheel.calibration", pulses=TOOTH_PULSES)
    track = _track(inputs, _edges_of(channel, method), "wheel.calibration", path)
    try:
        return calibrate_pitch(track)
    except InputError as exc:
        raise InputError(exc.problem, exc.fix, file=str(path), field="wheel.calibration",
                         ru=exc.ru) from None


def _regime(inputs: Inputs, i: int, entry: dict, calibration) -> Regime:
    revolutions = inputs["engine"]["strokes"] // 2
    recorded = "signal" in entry or "edges" in entry
    if not recorded and "oscillogram" not in entry:
        raise inputs.error("neither a recording, edge times nor a photographed oscillogram "
                           "is given", "add signal = \"file.wav\" (or .csv, .h5), edges = "
                           "\"edges.csv\" or oscillogram = \"photo.jpg\"", f"regime[{i}]")
    recording = _recording(inputs, i, entry, calibration, revolutions) if recorded else None
    return Regime(i + 1, recording, _oscillogram(inputs, i, entry, revolutions))


@by_content(lambda inputs, i, entry, calibration, revolutions: (
    i, {k: v for k, v in entry.items() if k != "n_tach"}, calibration, revolutions,
    inputs.sections.get("analysis"), inputs["wheel"]), shared=True)
def _recording(inputs: Inputs, i: int, entry: dict, calibration, revolutions: int) -> Recording:
    """Regime ``i``'s recording analysed: a function of its entry but the tachometer's
    reading (a slip of n reaches ω_tach, not the teeth), the wheel, the analysis's settings
    and the calibration alone."""
    analysis = inputs.sections.get("analysis", {"edge_method": "fit"})
    times, tdc, spt = _signal_edges(inputs, i, entry, analysis["edge_method"])
    label = bi(f"regime {i + 1}", f"режим {i + 1}")
    if spt is not None and spt < MIN_SAMPLES_PER_TOOTH:
        warnings.warn(UndersampledWarning(
            f"{label['en']}: {spt:.1f} samples per tooth (fewer than {MIN_SAMPLES_PER_TOOTH:.0f}): "
            "edge times lose their sub-sample accuracy; record at a higher sample rate",
            f"{label['ru']}: {spt:.1f} отсчётов на зуб (меньше {MIN_SAMPLES_PER_TOOTH:.0f}): "
            "точность моментов фронтов падает; увеличьте частоту дискретизации"))
    kind = "edges" if "edges" in entry else "signal"
    field, source = f"regime[{i}].{kind}", entry[kind]
    track = _track(inputs, times, field, source, tdc)
    _check_track(track, label)
    angles = None if calibration is None else calibration.angles
    options = {"revolutions": revolutions, "tooth_angles": angles}
    try:
        pitch_u = None if calibration is None else float(np.sqrt(np.nanmean(calibration.u ** 2)))
        fourier = fit_cycles(track, orders=analysis.get("orders"), pitch_error=pitch_u, **options)
        tooth = tooth_cycles(track, **options)
    except InputError as exc:
        raise InputError(exc.problem, exc.fix, file=str(source), field=field, ru=exc.ru) from None
    _check_cycles(fourier, label, field, source)
    bias = _pitch_bias(track, fourier, tooth, calibration, analysis.get("orders"), revolutions)
    return Recording(track, fourier, tooth, jackknife(fourier), jackknife(tooth), spt, bias)


def _check_track(track: ToothTrack, label) -> None:
    if track.missing and not track.gap_found:
        warnings.warn(GapNotFoundWarning(
            f"{label['en']}: the {track.missing}-tooth reference gap was not found once per "
            "revolution: check z and the number of missing teeth; revolutions are counted "
            "from the first edge",
            f"{label['ru']}: метка из {track.missing} пропущенных зубьев не найдена раз за оборот: "
            "проверьте z и число пропущенных зубьев; обороты отсчитаны от первого фронта"))
    if track.missed or track.doubled or track.bad_revolutions.size:
        warnings.warn(TeethMiscountedWarning(
            f"{label['en']}: {track.missed} teeth missed and {track.doubled} spurious edges "
            f"removed; {track.bad_revolutions.size} revolutions miscounted and left out: check "
            "the sensor gap and the signal's level",
            f"{label['ru']}: пропущено зубьев {track.missed}, удалено ложных фронтов "
            f"{track.doubled}; отброшено оборотов со сбитым счётом {track.bad_revolutions.size}: "
            "проверьте зазор датчика и уровень сигнала"))


def _check_cycles(cycles: CycleSpeeds, label, field: str, file) -> None:
    if cycles.cycles < MIN_CYCLES:
        raise InputError(f"{label['en']}: the record holds {cycles.cycles} complete working "
                         f"cycle(s); δ and its uncertainty need at least {MIN_CYCLES}",
                         f"record longer: {FEW_CYCLES} or more working cycles (better 20)",
                         file=str(file), field=field)
    if cycles.cycles < FEW_CYCLES:
        warnings.warn(ShortRecordWarning(
            f"{label['en']}: only {cycles.cycles} complete working cycles: the higher orders of "
            f"ω(α) do not yet stand out of the noise, so δ may read low by up to 10 %, more "
            f"than its stated uncertainty; record at least {FEW_CYCLES} (better 20) cycles",
            f"{label['ru']}: всего {cycles.cycles} полных рабочих цикла: высшие гармоники ω(α) "
            f"ещё не выделяются из шума, δ может быть занижена до 10 %, больше указанной "
            f"погрешности; запишите не менее {FEW_CYCLES} (лучше 20) циклов"))
    spread = np.ptp(cycles.duration) / cycles.duration.mean() if cycles.cycles > 1 else 0.0
    if spread > UNEQUAL_CYCLES:
        warnings.warn(UnequalCyclesWarning(
            f"{label['en']}: the working cycles differ in length by {100 * spread:.1f} %: the "
            "speed was changing, so this is not a steady regime; wait for the speed to settle",
            f"{label['ru']}: длительности рабочих циклов различаются на {100 * spread:.1f} %: "
            "скорость менялась, режим не установившийся; дождитесь стабилизации"))


def _pitch_bias(track, fourier, tooth, calibration, orders, revolutions) -> dict:
    """How much the wheel's pitch errors move δ: with a calibration, nominal versus calibrated
    pitch; without, the tooth method versus the pitch errors that repeat every revolution.
    ``u`` is the standard uncertainty of δ from the pitch errors left in the kept orders
    (the calibration's own scatter, or the estimated errors of an uncalibrated wheel)."""
    if calibration is not None:
        nominal = {"revolutions": revolutions}
        f0 = fit_cycles(track, orders=orders, **nominal).mean_cycle.delta
        t0 = tooth_cycles(track, **nominal).mean_cycle.delta
        deviation = calibration.deviation
        return {"source": "calibration", "u": pitch_uncertainty(fourier),
                "fourier": float(f0 / fourier.mean_cycle.delta - 1),
                "tooth": float(t0 / tooth.mean_cycle.delta - 1),
                "rms": float(np.sqrt(np.nanmean((deviation - np.nanmean(deviation)) ** 2)))}
    dev = fourier.pitch_deviation
    angles = np.arange(track.teeth) * track.pitch + np.nan_to_num(dev - dev[0])
    corrected = tooth_cycles(track, revolutions=revolutions, tooth_angles=angles).mean_cycle.delta
    return {"source": "repeating", "u": pitch_uncertainty(fourier),
            "tooth": float(tooth.mean_cycle.delta / corrected - 1),
            "rms": float(np.sqrt(np.nanmean(dev ** 2)))}


# ------------------------------------------------------------------------ results

def _result_names(r: int, kind: str | None) -> dict:
    """Labels, symbols and display units of regime r's results: speeds and δ, every one
    above zero by nature (:data:`~processing.result.STRICTLY_POSITIVE`); δ and the mean speed
    are the key results, δ compared with the typical δ of an engine of ``kind``."""
    names = {
        f"omega_mean_{r}": (bi(f"mean speed, regime {r} (signal)", f"средняя частота вращения, "
                              f"режим {r} (сигнал)"), "n", "rpm"),
        f"omega_min_{r}": (bi(f"lowest speed of the mean cycle, regime {r}",
                              f"наименьшая частота вращения среднего цикла, режим {r}"),
                           "n_min", "rpm"),
        f"omega_max_{r}": (bi(f"highest speed of the mean cycle, regime {r}",
                              f"наибольшая частота вращения среднего цикла, режим {r}"),
                           "n_max", "rpm"),
        f"delta_{r}": (bi(f"speed irregularity of the mean cycle, regime {r}",
                          f"степень неравномерности среднего цикла, режим {r}"), "δ", ""),
        f"delta_mid_{r}": (bi(f"the same relative to (ω_max + ω_min)/2, regime {r}",
                              f"то же относительно (ω_max + ω_min)/2, режим {r}"), "δ′", ""),
        f"delta_tooth_{r}": (bi(f"δ tooth by tooth (mean cycle), regime {r}",
                                f"δ по отдельным зубьям (средний цикл), режим {r}"), "δ_z", ""),
        f"delta_osc_{r}": (bi(f"δ read off the oscillogram, regime {r}",
                              f"δ по осциллограмме, режим {r}"), "δ_osc", ""),
        f"omega_osc_{r}": (bi(f"mean speed from the oscillogram's TDC marks, regime {r}",
                              f"средняя частота вращения по отметкам ВМТ осциллограммы, "
                              f"режим {r}"), "n_osc", "rpm"),
        f"omega_tach_{r}": (bi(f"tachometer, regime {r}", f"тахометр, режим {r}"), "n_t", "rpm"),
    }
    key = {f"delta_{r}": typical_delta(kind), f"delta_osc_{r}": typical_delta(kind),
           f"omega_mean_{r}": None, f"omega_osc_{r}": None}
    return {name: (*declared, STRICTLY_POSITIVE,
                   *(() if name not in key else (KEY,) if key[name] is None else (KEY, key[name])))
            for name, declared in names.items()}


def _jack(value, u, n, u_b: float = 0.0, limit: float = 0.0) -> Measured:
    """A mean-cycle quantity: jackknife u over the cycles (type A), plus type B parts."""
    return Measured(float(value), float(u) if np.isfinite(u) else 0.0, max(n - 1, 1),
                    limit=limit, u_b=u_b)


SIGNAL_RESULTS = ("omega_mean", "omega_min", "omega_max", "delta", "delta_mid", "delta_tooth")
"""What a regime's recording gives (``{name}_{r}``)."""


def _signal_inputs(reg: Regime) -> dict[str, Measured]:
    r, rec, osc = reg.number, reg.recording, reg.oscillogram
    out = {}
    if rec is not None:
        f, n = rec.fourier, rec.fourier.cycles
        mc, u = f.mean_cycle, rec.u_fourier
        out = {f"s{r}.omega_mean": Measured.from_readings(f.cycle_angle / f.duration),
               f"s{r}.omega_min": _jack(mc.omega_min, u.omega_min, n),
               f"s{r}.omega_max": _jack(mc.omega_max, u.omega_max, n),
               f"s{r}.delta": _jack(mc.delta, u.delta, n, rec.pitch_bias["u"], f.selection),
               f"s{r}.delta_mid": _jack(mc.delta_mid, u.delta_mid, n, rec.pitch_bias["u"],
                                        f.selection),
               f"s{r}.delta_tooth": _jack(rec.tooth.mean_cycle.delta, rec.u_tooth.delta,
                                          rec.tooth.cycles)}
    if osc is not None:
        out[f"s{r}.omega_osc"] = osc.omega_mean
        if osc.delta is not None:
            out[f"s{r}.delta_osc"] = osc.delta
        else:
            out[f"s{r}.swing_osc"] = osc.swing
    return out


def _check_inputs(inputs: Inputs) -> None:
    """What the file says, checked before any recording is read."""
    wheel = inputs.sections.get("wheel")
    for i, e in enumerate(inputs["regime"]):
        if "h_max" in e and "h_min" in e and not e["h_max"].value > e["h_min"].value:
            raise inputs.error(f"h_max = {1e3 * e['h_max'].value:g} mm is not above h_min = "
                               f"{1e3 * e['h_min'].value:g} mm: δ = (h_max − h_min)/h_cp would "
                               "not be above zero", "h_max is the highest point of the speed "
                               "trace over a working cycle and h_min the lowest: check that "
                               "they are not swapped, and read the ripple with a magnifier if "
                               "it is finer than the ruler", f"regime[{i}].h_max",
                               (f"h_max = {1e3 * e['h_max'].value:g} мм не больше h_min = "
                                f"{1e3 * e['h_min'].value:g} мм: δ = (h_max − h_min)/h_cp не "
                                "получится больше нуля", "h_max — наивысшая точка линии "
                                "скорости за рабочий цикл, h_min — низшая: проверьте, не "
                                "перепутаны ли они, и снимите пульсацию через лупу, если она "
                                "мельче деления линейки"))
    recorded = [i for i, e in enumerate(inputs["regime"]) if "signal" in e or "edges" in e]
    if wheel is None:
        if recorded:
            raise inputs.error("a recording of the toothed wheel's sensor is given but not the "
                               "wheel", "add a [wheel] table with z (tooth pitches, the missing "
                               "teeth included) and missing", f"regime[{recorded[0]}]")
        return
    if wheel["z"] < 3:
        raise inputs.error(f"a wheel of z = {wheel['z']} tooth pitches cannot time a revolution",
                           "z is the number of tooth pitches, the missing teeth included "
                           "(60 for a 60−2 wheel)", "wheel.z",
                           ru=(f"колесо с z = {wheel['z']} шагами зубьев не может отсчитать "
                               "оборот", "z — число шагов зубьев вместе с пропущенными зубьями "
                               "(60 у колеса 60−2)"))
    if wheel["missing"] >= wheel["z"] // 2:
        raise inputs.error(f"a wheel of {wheel['z']} teeth with {wheel['missing']} missing is "
                           "not usable", f"missing counts the teeth removed at the reference "
                           f"gap (2 on a 60−2 wheel); it must be below {wheel['z'] // 2}",
                           "wheel.missing",
                           ru=(f"колесо из {wheel['z']} зубьев, {wheel['missing']} из которых "
                               "пропущены, непригодно", "missing — число зубьев, снятых у "
                               f"опорной впадины (2 у колеса 60−2); оно меньше {wheel['z'] // 2}"))
    orders = inputs.sections.get("analysis", {}).get("orders")
    if orders is not None and orders > wheel["z"] / 3:
        raise inputs.error(f"{orders} orders cannot be resolved by a {wheel['z']}-tooth wheel",
                           f"use at most {wheel['z'] // 3} orders (a third of the teeth), or "
                           "leave orders out to let the noise choose", "analysis.orders",
                           ru=(f"{orders} гармоник не различить колесом из {wheel['z']} зубьев",
                               f"возьмите не больше {wheel['z'] // 3} гармоник (треть числа "
                               "зубьев) или не указывайте orders: число выберет уровень шума"))


def _model(regimes: list[Regime], entries: list[dict]):
    def model(**x):
        out = {}
        for reg, entry in zip(regimes, entries):
            r = reg.number
            for q in SIGNAL_RESULTS if reg.recording is not None else ():
                out[f"{q}_{r}"] = x[f"s{r}.{q}"]
            out[f"omega_tach_{r}"] = x[f"regime[{r - 1}].n_tach"]
            if "h_max" in entry and "h_min" in entry:
                mean = x.get(f"regime[{r - 1}].h_mean")
                out[f"delta_osc_{r}"] = delta_oscillogram(x[f"regime[{r - 1}].h_max"],
                                                          x[f"regime[{r - 1}].h_min"], mean)
            elif reg.oscillogram is not None and reg.oscillogram.delta is not None:
                out[f"delta_osc_{r}"] = x[f"s{r}.delta_osc"]
            elif reg.oscillogram is not None:
                out[f"delta_osc_{r}"] = delta_scaled(
                    x[f"s{r}.swing_osc"], x.get(f"regime[{r - 1}].converter_scale"),
                    x[f"regime[{r - 1}].n_tach"], x.get(f"regime[{r - 1}].h_mean"))
            if reg.oscillogram is not None:
                out[f"omega_osc_{r}"] = x[f"s{r}.omega_osc"]
        return out

    return model


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20031) -> LabResult:
    """Reduce lab 3's recordings (and oscillogram readings) to δ of each regime.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`);
        recording paths are relative to the file.
    n_samples, seed : int
        Monte Carlo draws and their seed.

    Returns
    -------
    LabResult
        Per regime r: from a recording ``omega_mean_r``, ``omega_min_r``, ``omega_max_r``,
        ``delta_r`` (the mean cycle, Fourier fit), ``delta_mid_r``, ``delta_tooth_r``;
        ``omega_tach_r``; with oscillogram readings or a photograph ``delta_osc_r``, and with
        a photograph ``omega_osc_r``.
    """
    _check_inputs(inputs)
    with collect_notices() as notices:
        method = inputs.sections.get("analysis", {"edge_method": "fit"})["edge_method"]
        calibration = _calibration(inputs, method)
        entries = inputs["regime"]
        regimes = [_regime(inputs, i, e, calibration) for i, e in enumerate(entries)]
        flat = {k: v for k, v in inputs.flat().items() if isinstance(v, Measured)}
        for reg in regimes:
            flat.update(_signal_inputs(reg))
            _check_tachometer(reg, entries[reg.number - 1])
            _check_pitch(reg)
        prop = propagate(_model(regimes, entries), flat, n_samples=n_samples, seed=seed)
        kind = inputs["engine"].get("kind")
        declared = {k: v for reg in regimes for k, v in _result_names(reg.number, kind).items()}
        results = result_values(prop, declared)
        results.update(_record_results(regimes, entries))
        # the student's oscillogram reading is compared with the signal; δ tooth by tooth is
        # not (the edges' timing noise biases it up by design: a table saying the two
        # disagree would flag good data), it stands beside δ in the regime table
        pairs = [pair for r in regimes for pair in (
            (f"delta_osc_{r.number}", f"delta_{r.number}"),
            (f"omega_osc_{r.number}", f"omega_mean_{r.number}"))]
        comparisons = compare(prop, pairs)
        flag_estimates(results, comparisons)
    ranges = {k: v for k, v in REFERENCE_RANGES.items() if kind in (None, k)}
    return LabResult.of(inputs, results, comparisons=comparisons,
                        tables=[report.regime_table(regimes, results, _scales(entries)),
                                *report.pitch_table(regimes)],
                        figures=report.figures(regimes, ranges) + read_figures(
                            [r.oscillogram.channel for r in regimes if r.oscillogram]),
                        formulas=FORMULAS,
                        references=REFERENCES, warnings=notices,
                        conclusion=report.conclusion(regimes, results, ranges))


def _record_results(regimes, entries) -> dict:
    """What the regime table states of each record besides δ and n: the oscillogram's scale
    ``mu_<r>`` read off one, and a recording's samples per tooth ``samples_per_tooth_<r>``
    (a counter's edge times have none)."""
    values, declared = {}, {}
    for reg in regimes:
        r = reg.number
        if reg.recording is not None and reg.recording.samples_per_tooth is not None:
            values[f"samples_per_tooth_{r}"] = reg.recording.samples_per_tooth
            declared[f"samples_per_tooth_{r}"] = (bi(f"samples per tooth, regime {r}",
                                                     f"отсчётов на зуб, режим {r}"), "N_z", "")
    for r, mu in _scales(entries).items():
        if mu is not None:
            values[f"mu_{r}"] = mu * 30 / np.pi * 1e-3
            declared[f"mu_{r}"] = (bi(f"scale of the oscillogram, regime {r}",
                                      f"масштаб осциллограммы, режим {r}"), "μ", "mm/rpm")
    return computed(values, declared)


def _scales(entries) -> dict[int, float | None]:
    """The oscillogram's scale μ of each regime read off one [mm per min⁻¹]."""
    out = {}
    for r, entry in enumerate(entries, 1):
        if "h_max" in entry and "h_min" in entry:
            h_cp = entry["h_mean"].value if "h_mean" in entry else \
                (entry["h_max"].value + entry["h_min"].value) / 2
            out[r] = oscillogram_scale(h_cp, entry["n_tach"].value) * 1e3 * np.pi / 30
        else:
            out[r] = None
    return out


def _check_tachometer(reg: Regime, entry: dict) -> None:
    """The tachometer against the mean speed of the recording and of the photograph."""
    n_t = entry["n_tach"]
    seen = []
    if reg.recording is not None:
        f = reg.recording.fourier
        seen.append((float(np.mean(f.cycle_angle / f.duration)), 0.0,
                     bi("the signal's", "по сигналу"),
                     bi("z, the sample rate", "z, частоту дискретизации")))
    if reg.oscillogram is not None:
        w = reg.oscillogram.omega_mean
        seen.append((w.value, w.u, bi("the oscillogram's TDC marks'", "по отметкам ВМТ "
                                      "осциллограммы"), bi("the time marks' period, the "
                                                           "strokes", "период отметок времени, "
                                                           "тактность")))
    for w, u, by, what in seen:
        gap = w / n_t.value - 1
        if abs(gap) > 0.03 + 2 * np.hypot(n_t.u / n_t.value, u / w):
            warnings.warn(InconsistentInputWarning(
                f"regime {reg.number}: {by['en']} mean speed ({w * 30 / np.pi:.0f} min⁻¹) and "
                f"the tachometer ({n_t.value * 30 / np.pi:.0f} min⁻¹) differ by "
                f"{100 * gap:+.1f} %: check {what['en']} and the tachometer reading",
                f"режим {reg.number}: средняя частота {by['ru']} ({w * 30 / np.pi:.0f} мин⁻¹) и "
                f"по тахометру ({n_t.value * 30 / np.pi:.0f} мин⁻¹) различаются на "
                f"{100 * gap:+.1f} %: проверьте {what['ru']} и показание тахометра"))


def _check_pitch(reg: Regime) -> None:
    if reg.recording is None:
        return
    bias, sigma = reg.recording.pitch_bias, reg.recording.fourier.pitch_error
    # only errors that stand out of the timing noise (σ̂ > 0) are the wheel's: on a perfect
    # wheel the noise alone moves the tooth-by-tooth δ too
    if bias["source"] == "repeating" and sigma > 0 and abs(bias["tooth"]) > PITCH_BIAS:
        warnings.warn(PitchErrorWarning(
            f"regime {reg.number}: the wheel's pitch errors (≈ {np.degrees(sigma):.3f}° "
            f"rms) move the tooth-by-tooth δ by {100 * bias['tooth']:+.1f} %; the Fourier δ "
            "does not see them above its highest order, but below it they cannot be told from "
            "the engine: calibrate the wheel on a coast-down record ([wheel] calibration)",
            f"режим {reg.number}: погрешности шага зубьев (≈ {np.degrees(sigma):.3f}° "
            f"ср. кв.) смещают δ по зубьям на {100 * bias['tooth']:+.1f} %; δ по ряду Фурье их "
            "не видит выше наибольшего порядка, ниже — их не отличить от двигателя: "
            "откалибруйте колесо по записи выбега ([wheel] calibration)"))


# ------------------------------------------------------------------------ slips

def _teeth_for_pitches(inputs: Inputs) -> float | None:
    """The teeth counted for the pitches (58 on a 60−2 wheel): f = n z/60 with the smaller z
    gives every speed z/(z − missing) times ours."""
    wheel = inputs.sections.get("wheel")
    if not wheel or not wheel["missing"]:
        return None
    return wheel["z"] / (wheel["z"] - wheel["missing"])


SLIPS = [
    ("teeth_for_pitches",
     bi("the wheel's teeth counted for its tooth pitches (z without the missing teeth, "
        "58 on a 60−2 wheel): every speed z/(z − missing) times too high",
        "за число шагов взято число зубьев (z без пропущенных зубьев, 58 у колеса 60−2): "
        "все частоты вращения завышены в z/(z − пропуск) раз"),
     (r"omega_(mean|min|max)_\d+",), _teeth_for_pitches),
    ("half_swing",
     bi("δ from half the swing, (ω_max − ω_min)/(2 ω_m): the amplitude of the speed's "
        "fluctuation taken for its range",
        "δ по половине размаха, (ω_max − ω_min)/(2 ω_ср): амплитуда колебаний скорости "
        "принята за её размах"), (r"delta(_mid|_tooth|_osc)?_\d+",), 0.5),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the factor a slip of the arithmetic puts on them (set by the inputs, or fixed). δ against the
mid-range (ω_max + ω_min)/2 instead of the mean speed is no slip here: the two differ by a fraction
of a per cent (``delta_mid_r`` against ``delta_r``), inside any tolerance."""


# ------------------------------------------------------------------------ synthetic files

SYNTH_FORMATS = ("wav", "csv", "h5")

PHOTO_MARKS = 0.01
"""Period of the time marks on the photographed oscillograms. [s]"""


PHOTO_CYCLES = 8
"""Working cycles on a photographed oscillogram."""


def _photo_duration(run) -> float:
    return PHOTO_CYCLES * run.cycle_angle / run.mean_angular_speed


def oscillogram_photo(run, *, seed: int = 0):
    """A phone photograph (:func:`processing.synth.paper_record.photograph`) of the
    frequency-to-voltage oscillogram of an engine run's first :data:`PHOTO_CYCLES` working
    cycles.

    On 250 mm of 120 mm paper: the speed trace ω(t) with its mean level 70 mm above its zero
    line (drawn, 20 mm from the lower edge), a TDC pip every revolution, a time mark every
    :data:`PHOTO_MARKS`. Returns the :class:`~processing.synth.paper_record.PaperScene`."""
    from processing.synth.paper_record import photograph

    duration = _photo_duration(run)
    revolutions = np.arange(0.0, run.crank_angle[-1], 2 * np.pi)
    tdc = np.interp(revolutions, run.crank_angle, run.time)
    return photograph(lambda t: run.speed_at_angle(run.angle_at(t)) / run.mean_angular_speed,
                      duration, 0.07, mark_period=PHOTO_MARKS, tdc_times=tdc[tdc < duration],
                      zero=0.02, zero_line=True, seed=seed)



ENGINES = {"inertia": (0.18, 0.23), "p_z": (5.0e6, 6.0e6), "speed": (1700.0, 1900.0),
           "gap": (20.0, 50.0)}
"""Ranges a variant's engine and regimes are drawn from: the moment of inertia of everything
turning with the crankshaft (flywheel, crank train, clutch) [kg·m²], the maximum cycle pressure,
i.e. the load [Pa] (within the 4–7 MPa of a petrol engine at full load,
:class:`processing.synth.engine.Engine`), the first regime's speed and the second's above it
[min⁻¹] (the manual: two regimes 20–50 min⁻¹ apart). The scene's engine (0.2 kg·m², 5.5 MPa,
1800 min⁻¹) lies inside. δ falls with J, rises with p_z and falls with the speed (roughly as
n⁻³ here: the inertia torque cancels part of the gas torque's swing), so the ranges hold δ to
0.013–0.024 (40 seeds), about the manual's automotive 0.01–0.02: the photographed ripple
(δ·70 mm) stays near a millimetre and a 60−2 wheel at 48 kHz gets ≥ 24 samples per tooth."""


def engine_variant(seed: int):
    """A variant's engine and its two regimes' speeds (:data:`ENGINES`). Seed 0 is the scene's
    engine (:class:`processing.synth.engine.Engine` with 2 % cycle-to-cycle scatter) at 1800
    and 1840 min⁻¹.

    Returns
    -------
    engine : processing.synth.engine.Engine
        Its mean speed is the regime's to set.
    speeds : tuple of float
        The regimes' mean speeds. [min⁻¹]
    """
    from processing.synth.engine import Engine

    if seed == 0:
        return Engine(cycle_variation=0.02), (1800.0, 1840.0)
    rng = np.random.default_rng([seed, 31])
    engine = Engine(inertia=rng.uniform(*ENGINES["inertia"]), p_z=rng.uniform(*ENGINES["p_z"]),
                    cycle_variation=0.02)
    first = float(np.round(rng.uniform(*ENGINES["speed"])))
    return engine, (first, first + float(np.round(rng.uniform(*ENGINES["gap"]))))


def write_synthetic(out_dir, seed: int = 0, *, fmt: str = "wav", speeds=None,
                    cycles: int = 40, snr_db: float = 30.0, pitch_error_deg: float = 0.03,
                    sample_rate: float = 48e3, calibrate: bool = True,
                    image: bool = False, recording: bool = True,
                    part: int | None = None) -> dict[str, Path]:
    """Write a synthetic lab 3 measurement: recordings, a measurement file and the answer key.

    Two regimes of the variant's four-cylinder engine (:func:`engine_variant`: seed 0 the
    scene's default :class:`processing.synth.engine.Engine`, any other seed its own flywheel
    and load) at ``speeds`` (min⁻¹), seen by a 60−2 wheel with pitch errors through an inductive sensor
    and a 16-bit sound card; a coast-down record for the pitch calibration; the oscillogram
    readings a student would take (mean level 90 mm, read to 0.2 mm) from the true mean cycle.

    Parameters
    ----------
    out_dir : str or Path
        Folder to write into (created).
    seed : int
        Seed of everything random (the engine and its regimes, engine scatter, wheel, noise,
        readings).
    fmt : {"wav", "csv", "h5"}
        Recording format.
    speeds : sequence of float, optional
        Regimes' mean speeds (default: the variant's, 1800 and 1840 for seed 0). [min⁻¹]
    part : int, optional
        Seed of the engine and its regimes (default ``seed``; 0: the scene's engine, whatever
        ``seed`` draws the rest).
    cycles : int
        Working cycles recorded per regime.
    snr_db, pitch_error_deg, sample_rate : float
        Sensor SNR [dB], σ of the wheel's tooth-angle errors [°], sample rate [Hz].
    calibrate : bool
        Also write the coast-down record and name it in the file.
    image : bool
        Instead of the readings, a phone photograph of each regime's frequency-to-voltage
        oscillogram (:func:`oscillogram_photo`: the first :data:`PHOTO_CYCLES` working cycles,
        the zero line, TDC and time marks), named in the file with an ``[image]`` table; its
        answers are the photographed cycles' true δ and mean speed.
    recording : bool
        Write the sensor's recordings (and the wheel) too; ``False`` with ``image`` leaves the
        photographs alone, as a student with only the paper record has them.

    Returns
    -------
    dict
        Paths written: ``toml``, ``answer`` (``"results"``: of each regime r, true, SI,
        ``delta_r`` and ``omega_mean_r`` with the recordings, ``delta_osc_r`` and
        ``omega_osc_r`` with the photographs; ``"regimes"``: every setting of each record),
        the recordings and the photographs.
    """
    import json
    from dataclasses import replace

    from processing.inputs.signals import write_csv, write_hdf5, write_wav
    from processing.synth.engine import Sensor, ToothWheel, coast_run, record, run_engine

    if fmt not in SYNTH_FORMATS:
        raise InputError(f"unknown recording format {fmt!r}", f"use one of {', '.join(SYNTH_FORMATS)}")
    if not (recording or image):
        raise InputError("neither recordings nor photographs asked for",
                         "write the recordings, the photographs (image), or both")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng([seed, 3])
    engine, drawn = engine_variant(seed if part is None else part)
    speeds = drawn if speeds is None else speeds
    wheel = ToothWheel(teeth=60, missing=2, pitch_error=np.radians(pitch_error_deg), seed=seed)
    sensor = Sensor(sample_rate=sample_rate, snr_db=snr_db, spikes_per_second=0.5)

    def save(name: str, rec) -> str:
        file = f"{name}.{fmt}"
        if fmt == "wav":
            write_wav(out / file, rec.signal, rec.sample_rate)
        elif fmt == "h5":
            write_hdf5(out / file, {"tooth": rec.signal}, rec.sample_rate,
                       volts_per_code=rec.volts_per_code)
        else:
            write_csv(out / file, {"u": rec.signal * rec.volts_per_code}, rec.sample_rate)
        return file

    written, regimes, answers, photographed = {}, [], [], []
    for i, n in enumerate(speeds, start=1):
        run = run_engine(replace(engine, mean_angular_speed=n * np.pi / 30), cycles + 1,
                         seed=seed * 100 + i)
        rec = record(run, wheel, sensor, seed=seed * 100 + i)
        regime = ""
        if recording:
            file = save(f"regime{i}", rec)
            written[f"regime{i}"] = out / file
            regime = f'signal = "{file}"\n'
        grid = np.linspace(0, run.cycle_angle, 2881)[:-1]
        mean_cycle = np.mean([run.speed_at_angle(c * run.cycle_angle + grid)
                              for c in range(cycles)], axis=0)
        h_cp = 90.0
        h = h_cp * np.array([mean_cycle.max(), mean_cycle.min()]) / run.mean_angular_speed
        h_read = np.round((h + rng.normal(0, 0.1, 2)) / 0.2) * 0.2
        n_tach = round(float(run.mean_angular_speed * 30 / np.pi) + rng.normal(0, 2))
        regime = f'[[regime]]\n{regime}n_tach = "{n_tach} ± 5 rpm"\n'
        if image:
            photo = oscillogram_photo(run, seed=seed * 100 + i).write(out / f"regime{i}.jpg")
            written[f"oscillogram{i}"] = photo
            regime += f'oscillogram = "{photo.name}"\n'
            photographed.append(run.cycles_within(_photo_duration(run)))
        else:
            regime += (f'h_max = "{h_read[0]:.1f} ± 0.2 mm"\nh_min = "{h_read[1]:.1f} ± 0.2 mm"\n'
                       f'h_mean = "{h_cp:.1f} ± 0.2 mm"\n')
        regimes.append(regime)
        answers.append(rec.answer_key())
    calibration = ""
    if calibrate and recording:
        coast = record(coast_run(speeds[0] * np.pi / 30, 2.0), wheel, sensor, seed=seed * 100)
        calibration = f'calibration = "{save("coast", coast)}"\n'
        written["coast"] = out / f"coast.{fmt}"
    toml = (f'lab = "lab3"\n[meta]\nstudent = "synthetic (dynlab synth lab3 --seed {seed})"\n'
            f'notes = "generated; the true answers are in answer_key.json"\n\n'
            + (f'[wheel]\nz = 60\nmissing = 2\n{calibration}\n' if recording else "")
            + '[engine]\nstrokes = 4\ncylinders = 4\nkind = "automotive"\n\n' + "\n".join(regimes)
            + (f'\n[image]\nmark_period = "{1e3 * PHOTO_MARKS:g} ms"\npaper_width = "120 mm"\n'
               if image else ""))
    written["toml"] = out / f"lab3_seed{seed}.toml"
    written["toml"].write_text(toml, encoding="utf-8")
    written["answer"] = out / "answer_key.json"
    results = {}
    for r, a in enumerate(answers, 1):
        if recording:
            results.update({f"delta_{r}": a["delta"], f"omega_mean_{r}": a["mean_angular_speed"]})
        if image:
            delta, speed = photographed[r - 1]
            results.update({f"delta_osc_{r}": delta, f"omega_osc_{r}": speed})
    written["answer"].write_text(json.dumps({"seed": seed, "results": results,
                                             "regimes": answers}, indent=1), encoding="utf-8")
    return written
