"""Lab 4. Engine vibration on the test bench.

The manual's chapter: an engine on elastic mounts vibrates under the variable overturning
(reaction) torque, the unbalanced inertia forces and moments of the crank train
(P_j = −m_j R ω²(cos ωt + λ cos 2ωt) along each cylinder, P_r = −m_r R ω² along each crank), a
residual unbalance at 1×, the valve train and, in a petrol engine, a misfiring cylinder: a
polyharmonic excitation at orders of the crankshaft's speed. An accelerometer on a chosen
point and direction feeds the vibration meter ВМ-1 (acceleration and displacement 1.4–8000 Hz,
velocity 1.4–2800 Hz, RMS and peak-to-peak detectors, ±15 % basic error, a dB scale); the
student reads it over a speed range at several points, then cuts one cylinder's ignition and
reads again, and charts the readings against the speed.

Here the meter's readings are tabulated and charted as they are ([[reading]]: RMS a, v, x,
peak-to-peak, with the meter's ±15 %), or the accelerometer's records (CSV, WAV, HDF5: a channel per
point and the ignition pickup's TDC marks) are reduced the meter's way: the band readings by a
frequency-domain integration that does not drift (:mod:`processing.vibration.band_rms`), the
peak-to-peak values on the mean working cycle; beyond the meter, each record's order spectrum
against the crank angle (:mod:`processing.torsional.orders`), the order map over the sweep, the
first and second orders against the excitation formulas, and the cut cylinder found from the orders'
change against the healthy record at the same speed (:mod:`processing.vibration.misfire`). Where a
record and a meter reading share a point, speed and ignition, they are compared within the meter's
±15 %.

Results are numbered by measurement j (a record's channel, in file order, then the meter's
readings not paired with a record): ``a_rms_j``, ``v_rms_j``, ``x_rms_j``.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 4 ("Изучение вибраций двигателя в стендовых условиях").
"""
from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from labs import catalogue, lab4_vibration_report as lab_report
from processing.vibration.band_rms import (BANDS, QUANTITIES, BandRMS, band_rms, band_signals,
                                           level_db, peaks)
from processing.crank.balance import phasor_sum
from processing.diagnostics import InputError, collect_notices
from processing.crank.dynamics import firing_phases
from processing.speed.edges import detect_edges
from processing.measurement import (ENGINE_SPEED, SAMPLE_RATE, STROKES, Column, Field, Inputs,
                                    LabSpec, ReadingsTable, Section, bi, firing_order)
from processing.vibration.misfire import CutCylinder, find_cut_cylinder
from processing.torsional.orders import OrderFit, order_fits
from processing.inputs.record_checks import check_tachometer, whole_ratio
from processing.result import LabResult, compare, flag_estimates, result_values
from processing.inputs.signals import kept_open, open_channels
from processing.inputs.record_quality import check_record, irregular_marks
from processing.inputs.reuse import by_content
from processing.vibration.steady_record import decimate, mean_cycles
from processing.torsional.torsiogram import Revolutions, revolutions, steady_crank_angle
from processing.uncertainty import Measured, propagate
from processing.units import parse_quantity

DIRECTIONS = {"vertical": bi("vertical", "вертикальное"),
              "transverse": bi("transverse", "поперечное"),
              "longitudinal": bi("longitudinal", "продольное")}
IGNITION = {"all": bi("all cylinders", "все цилиндры"),
            "cut": bi("one cylinder cut", "один цилиндр отключён")}
RPM = 30 / np.pi
"""min⁻¹ per rad/s."""

METER_LIMIT = 0.15
"""The meter's basic error (relative limit), the manual's ±15 %."""

METHOD_LIMIT = 0.01
"""Relative limit of error of a band reading from a record, the reduction's own: the
benchmark's worst band at 20 dB in the worst band is 0.9 %, the noise's share (``python -m
processing.bench --topic vibration``)."""

MAX_ORDER = 12.0
"""Highest order fitted in a record's order spectrum."""

ORDER_NYQUIST = 0.4
"""Highest frequency an order fit reaches, as a share of the sample rate (below the Nyquist
frequency and a recorder's anti-alias roll-off): a record sampled too slowly for
:data:`MAX_ORDER` is fitted up to the order there."""

SAME_SPEED = 0.03
"""Records or readings within this share of each other's speed are "at the same speed"."""

LEAST_DURATION = 1 / BANDS["a"].low
"""Shortest record the band readings take: a period of the meter's lower band edge, 0.71 s.
Shorter, the displacement errs beyond :data:`METHOD_LIMIT` as the window's spread nears the
lowest orders (synthetic records at 800 min⁻¹: 0.7 % at 0.71 s, 0.9 % at 0.5 s, 4 % at
0.3 s). [s]"""

RECORD_PP_LIMIT = {"a": 0.02, "v": 0.05}
"""Relative limit of error of a peak-to-peak value read over a whole record without TDC marks
(not over its mean working cycle), beyond the noise's lift (:data:`PEAK_NOISE`): a tapered
record's own low frequencies reach the peaks (:func:`processing.vibration.band_rms.band_signals`).
Synthetic records of 0.8–2.4 s at 800–3400 min⁻¹ and 20–50 dB: a within 1.2 %, v within 3 %;
the displacement's peaks err by up to 95 %, so without marks it has none."""

PEAK_NOISE = 3.5
"""How many of the floor's RMS the noise lifts each extreme of a record without TDC marks by,
at most (a Gaussian noise's 3.5 σ is passed by 2·10⁻⁴ of its samples)."""

NOISE_ONLY = 0.9
"""The broadband floor's reading over the band reading above which, in all three bands, a
channel holds no vibration above its noise (the lines carry less than a fifth of its
power in each)."""

FLOOR_SHARE = 0.3
"""The broadband floor's reading over the band reading above which the reading is said to
rest on the floor (noise or broadband vibration, not the orders): at 0.3, the floor holds
9 % of its power."""

RANGE = (0.1, 1600.0)
"""Band accelerations (RMS) a mounted engine can show [m/s²]: the manual's 4–160 m/s² with a
decade of margin each way; beyond it a sensitivity in the wrong unit is the likely cause."""

G_RATIO = 9.80665
"""mV per g over mV per m/s²: the factor a sensitivity given in the wrong one of them makes."""

PART_MASS = dict(unit="kg", limit="0.01 kg", plausible=("10 g", "50 kg"))
"""A crank train's masses, from the engine's data or weighed."""

ACCELERATION = dict(unit="m/s^2", plausible=("0.02 m/s^2", "2000 m/s^2"))
VELOCITY = dict(unit="mm/s", plausible=("0.02 mm/s", "1000 mm/s"))
DISPLACEMENT = dict(unit="um", plausible=("0.05 um", "10000 um"))
"""What the vibration meter reads off an engine, RMS or peak to peak: the manual's
4–160 m/s² with a decade and more of margin for a quiet point and direction (the synthetic
bench's quietest reads 0.13 m/s², 0.33 mm/s, 1.1 µm), velocities and displacements to
match."""

SPEC = LabSpec(
    id="lab4", number="4",
    title=catalogue.title("lab4"),
    goal=bi("To study why a piston engine vibrates, to get to know the vibration-measuring "
            "equipment and to measure the vibration at several points of an engine running "
            "on a test bench, over its speed range and with one cylinder's ignition cut.",
            "Изучить условия возникновения вибраций поршневого двигателя, ознакомиться с "
            "аппаратурой для измерения вибрации и экспериментально определить уровень "
            "вибрации в различных точках двигателя при его работе в стендовых условиях."),
    sections=(
        Section("engine", bi("Engine", "Двигатель"), required=True, fields=(
            Field("cylinders", bi("number of cylinders", "число цилиндров"), kind="count",
                  symbol="i", example=4),
            Field("strokes", bi("strokes per cycle", "тактность"), **STROKES),
            Field("firing_order", bi("firing order, e.g. 1-3-4-2 (default 1, 2, …, i)",
                                     "порядок работы цилиндров, напр. 1-3-4-2"),
                  kind="text", required=False),
            Field("R", bi("crank radius", "радиус кривошипа"), unit="mm", limit="0.1 mm",
                  required=False, symbol="R", example=35, plausible=("10 mm", "300 mm")),
            Field("lambda", bi("crank radius over rod length", "отношение R/L"), unit="",
                  limit="0.005", required=False, symbol="λ", example=0.28,
                  plausible=("0.1", "0.5")),
            Field("m_j", bi("reciprocating mass of one cylinder", "масса поступательно "
                            "движущихся частей одного цилиндра"), **PART_MASS,
                  required=False, symbol="m_j", example=0.55),
            Field("m_r", bi("rotating mass of one crank left after the counterweights",
                            "неуравновешенная вращающаяся масса одного кривошипа"),
                  **PART_MASS, required=False, allow_zero=True, symbol="m_r", example=0),
            Field("mass", bi("mass of the engine on its mounts", "масса двигателя на опорах"),
                  unit="kg", limit="1 kg", required=False, symbol="m_дв", example=140,
                  plausible=("10 kg", "5000 kg")),
        )),
        Section("sensor", bi("Accelerometer", "Вибродатчик"), help=lab_report.SENSOR_HELP,
                fields=(
            Field("sensitivity", bi("sensitivity with its limit, e.g. \"10.2 mV/(m/s^2) "
                                    "± 2 %\" or \"100 mV/g ± 2 %\"",
                                    "коэффициент преобразования с погрешностью, напр. "
                                    "\"10.2 mV/(m/s^2) ± 2 %\" или \"100 mV/g ± 2 %\""),
                  kind="text", symbol="S"),
        )),
        Section("meter", bi("Vibration meter", "Виброметр"), fields=(
            Field("limit", bi("basic error of the meter", "основная погрешность виброметра"),
                  unit="%", default="15 %", symbol="δ_м", plausible=("1 %", "50 %")),
            Field("db_reference", bi("reference values of the dB scale: ISO 1683 "
                                     "(10⁻⁶ m/s², 10⁻⁹ m/s, 10⁻¹² m) or GOST 25275 "
                                     "(3·10⁻⁴ m/s², 5·10⁻⁸ m/s, 8·10⁻¹² m)",
                                     "опорные значения шкалы дБ: ISO 1683 или ГОСТ 25275"),
                  kind="choice", default="iso1683",
                  choices={"iso1683": bi("ISO 1683", "ISO 1683"),
                           "gost25275": bi("GOST 25275", "ГОСТ 25275")}),
        )),
        Section("point", bi("Measuring point", "Точка измерения"), many=True, required=True,
                fields=(
            Field("name", bi("where the sensor sits", "место установки датчика"), kind="text",
                  example="cylinder head"),
            Field("direction", bi("direction of measurement", "направление измерения"),
                  kind="choice", choices=DIRECTIONS),
        )),
        Section("record", bi("Record", "Запись"), many=True, help=lab_report.RECORD_HELP,
                fields=(
            Field("signal", bi("the record: CSV, WAV or HDF5 file", "файл записи: CSV, WAV "
                               "или HDF5"), kind="file", example="n2000.csv"),
            Field("channels", bi("the accelerometers' channels, one per point in the order of "
                                 "[[point]], e.g. \"acc1, acc2, acc3\"",
                                 "каналы вибродатчиков, по одному на точку в порядке "
                                 "[[point]]"), kind="text"),
            Field("tdc_channel", bi("channel of the TDC marks", "канал отметок ВМТ"),
                  kind="text", default="tdc"),
            Field("tdc", bi("what the marks are: cylinder 1's firing TDC once per working cycle "
                            "(an ignition pickup), or TDC once per revolution",
                            "отметки: ВМТ сгорания 1-го цилиндра раз за цикл (датчик "
                            "зажигания) или ВМТ раз за оборот"),
                  kind="choice", default="cycle",
                  choices={"cycle": bi("once a cycle", "раз за цикл"),
                           "revolution": bi("once a revolution", "раз за оборот")}),
            Field("sample_rate", bi("sample rate, if the file does not say",
                                    "частота дискретизации, если её нет в файле"),
                  **SAMPLE_RATE, required=False, symbol="f_s"),
            Field("n", bi("speed by the tachometer", "частота вращения по тахометру"),
                  **ENGINE_SPEED, limit="10 rpm", required=False, symbol="n"),
            Field("ignition", bi("ignition: all cylinders, or one cylinder cut",
                                 "зажигание: все цилиндры или один отключён"),
                  kind="choice", choices=IGNITION, default="all"),
            Field("cut_cylinder", bi("the cylinder whose ignition was cut, if known (to check "
                                     "the finding)", "цилиндр с отключённым зажиганием, если "
                                     "известен (для проверки)"), kind="count",
                  required=False),
        )),
        Section("reading", bi("Meter reading", "Показания виброметра"), many=True,
                help=lab_report.READING_HELP, fields=(
            Field("point", bi("number of the point (1, 2, … in the order of [[point]])",
                              "номер точки"), kind="count"),
            Field("n", bi("speed", "частота вращения"), **ENGINE_SPEED, limit="10 rpm",
                  symbol="n"),
            Field("ignition", bi("ignition", "зажигание"), kind="choice", choices=IGNITION,
                  default="all"),
            Field("a", bi("RMS acceleration", "СКЗ виброускорения"), **ACCELERATION,
                  required=False, symbol="a"),
            Field("v", bi("RMS velocity", "СКЗ виброскорости"), **VELOCITY, required=False,
                  symbol="v"),
            Field("x", bi("RMS displacement", "СКЗ виброперемещения"), **DISPLACEMENT,
                  required=False, symbol="x"),
            Field("a_pp", bi("peak-to-peak acceleration", "размах виброускорения"),
                  **ACCELERATION, required=False, symbol="2a"),
            Field("v_pp", bi("peak-to-peak velocity", "размах виброскорости"), **VELOCITY,
                  required=False, symbol="2v"),
            Field("x_pp", bi("peak-to-peak displacement", "размах виброперемещения"),
                  **DISPLACEMENT, required=False, symbol="2x"),
        )),
    ),
    readings=(ReadingsTable(
        bi("The vibration meter's readings", "Показания виброметра"), "reading",
        (Column(bi("point", "точка"), "point"), Column(bi("n, min⁻¹", "n, мин⁻¹"), "n"),
         Column(bi("ignition", "зажигание"), "ignition"),
         Column(bi("a, m/s²", "a, м/с²"), "a"), Column(bi("v, mm/s", "v, мм/с"), "v"),
         Column(bi("x, µm", "x, мкм"), "x"), Column(bi("2a, m/s²", "2a, м/с²"), "a_pp"),
         Column(bi("2v, mm/s", "2v, мм/с"), "v_pp"), Column(bi("2x, µm", "2x, мкм"), "x_pp")),
        run=bi("Reading", "Отсчёт")),),
)


# ------------------------------------------------------------------------ the sensor

_PER_G = re.compile(r"/\s*g\b")


def sensitivity(text: str, *, file: str | None = None) -> Measured:
    """An accelerometer's sensitivity from the file's text, in V per m/s².

    Accepts any voltage over an acceleration ("10.2 mV/(m/s^2)", "100 mV/g" with g =
    9.80665 m/s²), and a ± limit absolute or in % of the value.

    Examples
    --------
    >>> s = sensitivity("100 mV/g ± 2 %")
    >>> round(s.value, 6), round(s.limit / s.value, 6)
    (0.010197, 0.02)
    """
    def refuse(problem: str) -> InputError:
        return InputError(problem, "write the sensor's sensitivity from its calibration "
                          "chart as a voltage over an acceleration, e.g. \"10.2 mV/(m/s^2) "
                          "± 2 %\" or \"100 mV/g ± 2 %\"", file=file, field="sensor.sensitivity")

    try:
        value, limit = parse_quantity(_PER_G.sub("/g_n", text), "mV/(m/s^2)")
    except ValueError as exc:
        raise refuse(f"sensitivity {text!r}: {exc}") from None
    if not value > 0:
        raise refuse(f"sensitivity {text!r} is not positive")
    return Measured(value, limit=limit or 0.0)


# ------------------------------------------------------------------------ one record

@dataclass
class Channel:
    """One accelerometer channel of a record, reduced (in volts: the sensitivity enters the
    measurement model)."""

    number: int
    """The measurement j."""
    point: int
    """The point (1-based)."""
    name: str
    rms: BandRMS
    """Band readings of the record in V (V·s, V·s²)."""
    pp: dict
    """Peak-to-peak of each band signal over the mean working cycle; without TDC marks, of
    the acceleration and velocity over the whole record. [V, V·s, V·s²]"""
    fit: OrderFit | None
    """The order spectrum in V (None without TDC marks)."""
    measured: dict = field(default_factory=dict)
    """The channel's inputs of the model, by :func:`_flat`'s suffix (``a``, ``a_pp``,
    ``order1`` …): the band readings and peak-to-peak values with their limits, the first and
    second orders with their u (:func:`_measured`). [V, V·s, V·s²]"""


@dataclass
class Recorded:
    """One record of the sweep and what it reduced to."""

    number: int
    source: Path
    ignition: str
    speed: Measured | None
    """From the TDC marks; without them the tachometer's n, if given. [rad/s]"""
    channels: list[Channel]
    cycle_marks: bool
    cut_stated: int | None = None
    cut: dict = field(default_factory=dict)
    """Per channel name, the :class:`CutCylinder` against the healthy record."""
    healthy: int | None = None
    """Number of the healthy record it was compared with."""
    unmarked: dict | None = None
    """Why the record has no usable TDC marks, in English and Russian (None: it has them)."""
    rate: float = 0.0
    """Sample rate. [Hz]"""

    @property
    def marked(self) -> bool:
        return self.unmarked is None

    @property
    def verdict(self) -> CutCylinder | None:
        """The channel whose finding is the most certain: found with the largest half-order
        rise, else the largest rise (None: no channel was compared)."""
        if not self.cut:
            return None
        return max(self.cut.values(), key=lambda c: (c.found, c.rise))


@dataclass(frozen=True)
class Timing:
    """What a record's TDC marks give: the crank angle of every sample, the speed and the
    stretch of whole working cycles."""

    revolutions: Revolutions
    speed: float
    """[rad/s]"""
    u_speed: float
    """Type A u of the speed. [rad/s]"""
    angle: np.ndarray
    """Crank angle of every sample. [rad]"""
    span: slice
    """Samples of the whole working cycles between the marks."""
    per_mark: float
    """Crank angle between marks. [rad]"""


def _tdc_times(x: np.ndarray, rate: float) -> np.ndarray:
    """Times of the TDC pulses' falling edges (:func:`processing.speed.edges.detect_edges`). [s]"""
    return detect_edges(np.asarray(x, dtype=float), "fit") / rate


def _open(entry: dict, names: list[str], where: str):
    """The accelerometers' channels and the TDC channel (None when the recording holds no
    channel of the default name ``tdc``: a record without TDC marks)."""
    path, tdc = entry["signal"], entry["tdc_channel"]
    rate = entry["sample_rate"].value if "sample_rate" in entry else None
    options = dict(sample_rate=rate, field=f"{where}.signal")
    try:
        opened = open_channels(path, [*names, tdc], **options)
    except InputError as exc:
        if tdc != SPEC.section("record").field("tdc_channel").default:
            raise
        accelerometers = open_channels(path, names, **options)
        try:
            open_channels(path, [tdc], **options)
        except InputError:
            return accelerometers, None
        raise exc from None
    return opened[:-1], opened[-1]


def _timing(entry: dict, tdc, rate: float, samples: int, strokes: int, refuse, where: str):
    """The record's :class:`Timing` from its TDC channel's samples and their marks' times
    (``tdc``, as :func:`_read` gives them), or why it has none (``bi`` text).

    Marks that are there but irregular, or contradict the tachometer, are refused: they are
    marks, misread or mislabelled. A channel that is missing, flat, or holds too few marks for
    one working cycle leaves the record without marks."""
    name = entry["tdc_channel"]
    if tdc is None:
        return bi(f"the recording has no channel '{name}'", f"в файле нет канала '{name}'")
    x, times = tdc
    if times.size < 2:
        return bi(f"its TDC channel '{name}' " + (f"is constant ({x[0]:.4g})" if np.ptp(x) == 0
                                                   else f"holds {times.size} mark(s)"),
                  f"канал ВМТ '{name}' " + (f"постоянен ({x[0]:.4g})" if np.ptp(x) == 0
                                            else f"содержит отметок: {times.size}"))
    cycle = 4 * np.pi if strokes == 4 else 2 * np.pi
    per_mark = 4 * np.pi if entry["tdc"] == "cycle" and strokes == 4 else 2 * np.pi
    try:
        revs = revolutions(times)
    except InputError as exc:
        raise irregular_marks(x, refuse(exc.problem, exc.fix, "tdc_channel"),
                              file=str(entry["signal"]), field=f"{where}.tdc_channel",
                              channel=name) from None
    speed = revs.angular_speed * per_mark / (2 * np.pi)
    _check_speed(entry, speed, refuse, where)
    per_cycle = int(round(cycle / per_mark))
    last = (times.size - 1) // per_cycle * per_cycle
    if last == 0:
        spanned = (times.size - 1) * per_mark / cycle
        return bi(f"its TDC marks span {spanned:.1f} working cycle(s), less than a whole one",
                  f"отметки ВМТ охватывают {spanned:.1f} рабочего цикла, меньше целого")
    time = np.arange(samples) / rate
    return Timing(revs, speed, revs.u_speed * per_mark / (2 * np.pi),
                  steady_crank_angle(time, revs) * per_mark / (2 * np.pi),
                  slice(int(np.ceil(times[0] * rate)), int(np.ceil(times[last] * rate))),
                  per_mark)


def _channels(names: list[str], data: list[np.ndarray], rate: float, timing, strokes: int,
              refuse, lowest_line: float) -> list[Channel]:
    """A record's accelerometer channels: each one's band readings, peak-to-peak values and
    orders. The channels share the record's samples, so what depends on the time and the
    crank angle alone (the band signals' angles, the mean cycle's grid, the decimated time
    and angle, the order fit's design) is made once for all of them."""
    readings = [_band_readings(name, x, rate, refuse, lowest_line)
                for name, x in zip(names, data)]
    if not isinstance(timing, Timing):
        out = []
        for p, (name, x, rms) in enumerate(zip(names, data, readings)):
            band = band_signals(x, rate, tuple(RECORD_PP_LIMIT))
            pp = {q: float(np.ptp(band[q])) for q in RECORD_PP_LIMIT}
            out.append(Channel(0, p + 1, name, rms, pp, None, _measured(rms, pp, None, False)))
        return out
    cycle = 4 * np.pi if strokes == 4 else 2 * np.pi
    span = timing.span
    band = band_signals(np.stack([x[span] for x in data]), rate, periodic=True)
    time = np.arange(data[0].size) / rate
    band_angle = steady_crank_angle(time[span.start] + band.time, timing.revolutions) \
        * timing.per_mark / (2 * np.pi)
    cycles = mean_cycles([band[q][k] for k in range(len(data)) for q in QUANTITIES],
                         band_angle, cycle)
    pp = [{q: peaks(cycles[k * len(QUANTITIES) + i]).peak_to_peak
           for i, q in enumerate(QUANTITIES)} for k in range(len(data))]
    step = 0.5 if strokes == 4 else 1.0     # with marks per revolution: their phase is lost
    top = min(MAX_ORDER, ORDER_NYQUIST * rate * 2 * np.pi / timing.speed)
    highest = top * timing.speed / (2 * np.pi)
    decimated = [decimate(time, timing.angle, x, rate, highest) for x in data]
    try:
        fits = order_fits(*decimated[0][:2], [d[2] for d in decimated], step=step,
                          max_order=top)
    except ValueError:
        fits = [None] * len(data)
    return [Channel(0, p + 1, name, rms, pp[p], fit, _measured(rms, pp[p], fit, True))
            for p, (name, rms, fit) in enumerate(zip(names, readings, fits))]


def _measured(rms: BandRMS, pp: dict, fit: OrderFit | None, marked: bool) -> dict:
    """A channel's inputs of the model (:attr:`Channel.measured`): each band reading with
    the method's limit, each peak-to-peak value with its own (:func:`_pp_limit`), the first
    and second orders' amplitudes with their u and degrees of freedom."""
    out = {}
    for q in QUANTITIES:
        out[q] = Measured(rms[q], limit=METHOD_LIMIT * rms[q])
        if q in pp:
            out[f"{q}_pp"] = Measured(pp[q], limit=_pp_limit(rms, pp, q, marked))
    if fit is not None:
        for k in (1, 2):
            hit = np.flatnonzero(np.isclose(fit.order, k))
            if hit.size:
                out[f"order{k}"] = Measured(float(fit.amplitude[hit[0]]), float(fit.u[hit[0]]),
                                            fit.dof)
    return out


def _band_readings(name: str, x: np.ndarray, rate: float, refuse,
                   lowest_line: float) -> BandRMS:
    """A channel's band readings; a channel of noise alone is refused."""
    rms = band_rms(x, rate, lowest_line=lowest_line)
    if all(rms.floor[q] > NOISE_ONLY * rms[q] for q in QUANTITIES):
        raise refuse(f"channel '{name}' holds no vibration above its noise: its broadband "
                     "floor makes " + ", ".join(f"{100 * rms.floor[q] / rms[q]:.0f} %"
                                                for q in QUANTITIES)
                     + " of its a, v and x readings, and no engine order stands out",
                     "check that the accelerometer is mounted, connected and powered, that "
                     "the channel named is its channel, and that the amplifier's gain is set; "
                     "then record again", "channels")
    return rms


@by_content(lambda i, entry, names: (i, names, *(entry.get(k) for k in
                                                  ("signal", "tdc_channel", "sample_rate"))),
            shared=True)
def _read(i: int, entry: dict, names: list[str]):
    """Record ``i``'s accelerometer channels ``names`` read (in volts) and checked, their
    sample rate, and its TDC channel's samples (in volts) with the times of its marks (None
    without the channel): a function of the recording, the channels named and the sample
    rate alone (a slip of the tachometer's n finds it done)."""
    where = f"record[{i}]"
    with kept_open():       # the recording opened once for its channels and their samples
        accelerometers, tdc = _open(entry, names, where)
        rate = accelerometers[0].sample_rate
        data = [c.read().astype(float) * c.volts_per_code for c in accelerometers]
        for name, x in zip(names, data):
            check_record(x, rate, file=str(entry["signal"]), field=f"{where}.channels",
                         channel=name, least_duration=LEAST_DURATION,
                         purpose={"en": "the meter's band reading",
                                  "ru": "показания прибора в полосе"}, broadband=True)
        if tdc is None:
            return rate, data, None
        marks = tdc.read().astype(float) * tdc.volts_per_code
    return rate, data, (marks, _tdc_times(marks, rate))


@by_content(lambda inputs, i, entry, points, phases: (i, entry, points, phases,
                                                      inputs["engine"]["strokes"]),
            shared=True)
def _record(inputs: Inputs, i: int, entry: dict, points: int, phases) -> Recorded:
    """Record ``i``'s channels read and analysed: a function of its entry, the engine's
    strokes, the points and the cylinders' phases alone (a slip of the engine's R or m_j finds
    it done). Shared by the reductions that reuse it: each takes its own :func:`_sweep_copy`
    to number and compare."""
    where = f"record[{i}]"
    path = entry["signal"]

    def refuse(problem: str, fix: str, name: str = "signal") -> InputError:
        return InputError(problem, fix, file=str(path), field=f"{where}.{name}")

    names = [c.strip() for c in entry["channels"].split(",") if c.strip()]
    if len(names) != points:
        raise inputs.error(f"{len(names)} channel(s) named for {points} point(s)",
                           "name one accelerometer channel per [[point]], in their order, "
                           "e.g. channels = \"acc1, acc2, acc3\"", f"{where}.channels")
    stated = entry.get("cut_cylinder")
    if stated is not None and not 1 <= stated <= len(phases):
        raise inputs.error(f"cut_cylinder = {stated}: the engine has {len(phases)} cylinders",
                           f"give a cylinder 1…{len(phases)}", f"{where}.cut_cylinder")
    rate, data, tdc = _read(i, entry, names)
    strokes = inputs["engine"]["strokes"]
    timing = _timing(entry, tdc, rate, data[0].size, strokes, refuse, where)
    if isinstance(timing, Timing):
        speed = Measured(timing.speed, timing.u_speed, max(timing.revolutions.speeds.size - 1, 1),
                         limit=timing.speed / (rate * np.ptp(timing.revolutions.mark_times)))
    else:
        speed = entry.get("n")
    step = 0.5 if strokes == 4 else 1.0
    lowest = 0.0 if speed is None else step * (speed.value - 3 * speed.u) / (2 * np.pi)
    chans = _channels(names, data, rate, timing, strokes, refuse, max(lowest, 0.0))
    return Recorded(i + 1, Path(path), entry["ignition"], speed, chans, entry["tdc"] == "cycle",
                    stated, unmarked=None if isinstance(timing, Timing) else timing, rate=rate)


def _sweep_copy(r: Recorded) -> Recorded:
    """The record as :func:`_record` analysed it, with its own channels and ignition-cut
    findings for a reduction to number and fill (the analyses themselves shared, unchanged)."""
    return replace(r, channels=[replace(c) for c in r.channels], cut={}, healthy=None)


def _check_speed(entry: dict, w: float, refuse, where: str) -> None:
    """The TDC marks' speed against the tachometer's n."""
    if "n" not in entry:
        return
    n = entry["n"]

    def refused(gap: float) -> InputError:
        ratio = whole_ratio(1 + gap)
        cause = ("marks once per cycle taken for once per revolution (or back), or marks "
                 "missed" if ratio in ((1, 2), (2, 1)) else
                 "a wrong sample rate (the marks' speed scales with it)" if ratio is None else
                 "marks missed or doubled")
        return refuse(f"the TDC marks give {w * RPM:.0f} min⁻¹ but n = {n.value * RPM:.0f} "
                      f"min⁻¹ ({100 * gap:+.0f} %): {cause}, or the wrong record",
                      "check n, the TDC channel, tdc = \"cycle\" or \"revolution\" and the "
                      "recorder's sample rate", "n")

    check_tachometer(w, n, refused, lambda: lab_report.speed_disagrees(where, w, n.value))


# ------------------------------------------------------------------------ the sweep

def _cut_cylinders(recorded: list[Recorded], phases) -> None:
    """Each record with the ignition cut against the healthy record nearest in speed."""
    healthy = [r for r in recorded if r.ignition == "all" and r.marked]
    for r in recorded:
        if r.ignition != "cut" or not r.marked:
            continue
        near = [h for h in healthy if abs(h.speed.value / r.speed.value - 1) <= SAME_SPEED
                and h.cycle_marks == r.cycle_marks]
        if not near:
            warnings.warn(lab_report.no_healthy(r.number, r.speed.value))
            continue
        h = min(near, key=lambda h: abs(h.speed.value - r.speed.value))
        r.healthy = h.number
        for c, ch in zip(h.channels, r.channels):
            if c.fit is not None and ch.fit is not None and c.fit.order.size == ch.fit.order.size:
                r.cut[ch.name] = find_cut_cylinder(c.fit, ch.fit, phases,
                                                   cycle_marks=r.cycle_marks, seed=r.number)


# ------------------------------------------------------------------------ meter readings

@dataclass
class Reading:
    """A meter reading with the measurement it belongs to."""

    index: int
    """Its place in [[reading]]."""
    entry: dict
    number: int = 0
    """The measurement j (a record's channel, or its own)."""
    paired: bool = False


def _pair_readings(inputs: Inputs, recorded: list[Recorded], points: int) -> list[Reading]:
    """Each meter reading paired with a record's channel at its point, speed and ignition,
    or numbered after the records' channels."""
    readings = [Reading(k, e) for k, e in enumerate(inputs.sections.get("reading", []))]
    next_number = sum(len(r.channels) for r in recorded)
    for rd in readings:
        e = rd.entry
        if not 1 <= e["point"] <= points:
            raise inputs.error(f"point = {e['point']}: there are {points} [[point]] tables",
                               f"give the point's number 1…{points}", f"reading[{rd.index}].point")
        if not any(k in e for k in ("a", "v", "x", "a_pp", "v_pp", "x_pp")):
            raise inputs.error("the reading holds no value", "write at least one of a, v, x "
                               "(RMS) or a_pp, v_pp, x_pp", f"reading[{rd.index}].a")
        match = [r for r in recorded if r.ignition == e["ignition"] and r.speed is not None
                 and abs(r.speed.value / e["n"].value - 1) <= SAME_SPEED]
        if match:
            r = min(match, key=lambda r: abs(r.speed.value - e["n"].value))
            rd.number, rd.paired = r.channels[e["point"] - 1].number, True
        else:
            next_number += 1
            rd.number = next_number
    return readings


# ------------------------------------------------------------------------ the model

def _flat(inputs: Inputs, recorded: list[Recorded], readings: list[Reading]) -> dict:
    """The measured inputs of the model: the sensitivity, each channel's readings in volts
    (the method's limit), the orders, the speeds, the meter's readings, the engine's data."""
    flat = {}
    if recorded:
        flat["S"] = sensitivity(inputs["sensor"]["sensitivity"], file=inputs.file)
    for r in recorded:
        if r.speed is not None:
            flat[f"r{r.number}.omega"] = r.speed
        for c in r.channels:
            flat.update((f"c{c.number}.{key}", m) for key, m in c.measured.items())
    limit = inputs["meter"]["limit"].value if "meter" in inputs else METER_LIMIT
    for rd in readings:
        for key, m in rd.entry.items():
            if key in ("a", "v", "x", "a_pp", "v_pp", "x_pp"):
                flat[f"m{rd.number}.{key}"] = Measured(m.value, limit=limit * m.value)
    engine = inputs["engine"]
    for k in ("R", "lambda", "m_j", "m_r", "mass"):
        if k in engine:
            flat[f"engine.{k}"] = engine[k]
    return flat


def _pp_limit(rms: BandRMS, pp: dict, q: str, marked: bool) -> float:
    """Limit of error of a channel's peak-to-peak value: the method's on the mean working
    cycle; on a whole record without marks, the band signal's noise lifts both extremes (by
    up to :data:`PEAK_NOISE` times the floor's RMS each) and the taper's own low frequencies
    reach the peaks (:data:`RECORD_PP_LIMIT`)."""
    if marked:
        return METHOD_LIMIT * pp[q]
    return RECORD_PP_LIMIT[q] * pp[q] + 2 * PEAK_NOISE * rms.floor[q]


def free_force_factors(crank_angles) -> tuple[float, float]:
    """|Σ_c e^{iθ_c}| and |Σ_c e^{2iθ_c}| over the cranks: the free first-order force is
    (m_j + m_r) R ω² times the first, the second-order one λ m_j R ω² times the second.

    .. math:: P_{j1} = m_j R\\omega^2 \\Big|\\sum_c e^{i\\theta_c}\\Big|,\\quad
              P_{j2} = \\lambda m_j R\\omega^2 \\Big|\\sum_c e^{2i\\theta_c}\\Big|

    Examples
    --------
    A four-cylinder in-line engine (cranks at 0°, 180°, 180°, 0°): first orders cancel,
    second orders add:

    >>> free_force_factors(np.radians([0, 180, 180, 0]))
    (0.0, 4.0)
    """
    theta = np.asarray(crank_angles, dtype=float)
    return (float(abs(phasor_sum(theta, 1.0))), float(abs(phasor_sum(theta, 1.0, order=2))))


def _model(recorded: list[Recorded], readings: list[Reading], crank_angles, forces: bool,
           reference: str):
    """Every result from the inputs of :func:`_flat`. The free forces of the cylinders' row
    are the manual's P_j and P_r summed over the cranks (:func:`free_force_factors`); each
    RMS value's level ``L_<q>_<j>`` in dB against the meter's ``reference``
    (:func:`~processing.vibration.band_rms.level_db`)."""
    first, second = free_force_factors(crank_angles)

    def model(**x):
        out = {}
        for r in recorded:
            if r.marked:
                out[f"n_{r.number}"] = x[f"r{r.number}.omega"]
            for c in r.channels:
                j = c.number
                for q in QUANTITIES:
                    out[f"{q}_rms_{j}"] = x[f"c{j}.{q}"] / x["S"]
                    if f"c{j}.{q}_pp" in x:
                        out[f"{q}_pp_{j}"] = x[f"c{j}.{q}_pp"] / x["S"]
                for k in (1, 2):
                    if f"c{j}.order{k}" in x:
                        out[f"a{k}_{j}"] = x[f"c{j}.order{k}"] / x["S"]
            if forces and f"r{r.number}.omega" in x:
                w2 = x["engine.R"] * x[f"r{r.number}.omega"] ** 2
                out[f"F1_{r.number}"] = w2 * (x["engine.m_j"] * first + x.get("engine.m_r", 0.0)
                                              * first)
                out[f"F2_{r.number}"] = w2 * x["engine.lambda"] * x["engine.m_j"] * second
                if "engine.mass" in x:
                    for k in (1, 2):
                        out[f"a{k}_model_{r.number}"] = out[f"F{k}_{r.number}"] / x["engine.mass"]
        for rd in readings:
            for key in ("a", "v", "x"):
                if f"m{rd.number}.{key}" in x:
                    name = f"{key}_meter_{rd.number}" if rd.paired else f"{key}_rms_{rd.number}"
                    out[name] = x[f"m{rd.number}.{key}"]
            for key in ("a_pp", "v_pp", "x_pp"):
                if f"m{rd.number}.{key}" in x:
                    base = key.replace("_pp", "")
                    name = (f"{base}_pp_meter_{rd.number}" if rd.paired
                            else f"{base}_pp_{rd.number}")
                    out[name] = x[f"m{rd.number}.{key}"]
        for name in [k for k in out if "_rms_" in k]:
            q, _, j = name.split("_")
            out[f"L_{q}_{j}"] = level_db(out[name], q, reference)
        return out

    return model


# ------------------------------------------------------------------------ reduction

def _check_inputs(inputs: Inputs) -> np.ndarray:
    """What the file says, checked before any record is read; the firing phases."""
    engine = inputs["engine"]
    try:
        phases = firing_phases(engine["cylinders"], strokes=engine["strokes"],
                               firing_order=firing_order(inputs))
    except InputError as exc:
        raise inputs.error(exc.problem, exc.fix, "engine.firing_order") from None
    if "record" in inputs and "sensor" not in inputs:
        raise inputs.error("records are given but not the accelerometer's sensitivity",
                           "add [sensor] sensitivity = \"10.2 mV/(m/s^2) ± 2 %\" (from the "
                           "sensor's calibration chart)", "sensor.sensitivity")
    if "record" not in inputs and "reading" not in inputs:
        raise inputs.error("neither records nor meter readings are given",
                           "add [[reading]] tables (the meter's readings) or [[record]] "
                           "tables (the accelerometer's records)", "reading")
    lam = engine.get("lambda")
    if lam is not None and not 0 < lam.value < 0.5:
        raise inputs.error(f"λ = {lam.value:g}", "λ = R/L lies between 0.2 and 0.35 in "
                           "engines", "engine.lambda")
    return phases


def _check_records(inputs: Inputs, recorded: list[Recorded], readings: list[Reading]) -> None:
    """Sensitivities in the wrong unit (a g taken for a m/s²), readings resting on the
    broadband floor."""
    if not recorded:
        return
    S = sensitivity(inputs["sensor"]["sensitivity"], file=inputs.file).value
    for r in recorded:
        for c in r.channels:
            a = c.rms.a / S
            if not RANGE[0] <= a <= RANGE[1]:
                raise inputs.error(
                    f"record {r.number}, channel '{c.name}': the sensitivity makes the band "
                    f"acceleration {a:.3g} m/s² RMS, outside the {RANGE[0]:g}–{RANGE[1]:g} "
                    "m/s² an engine on its mounts shows: the sensitivity is likely in the "
                    "wrong unit (mV per g taken for mV per m/s², V for mV) or the channel's "
                    "gain is not in the record's unit",
                    "copy the sensitivity with its unit from the sensor's chart, e.g. \"100 "
                    "mV/g\" or \"10.2 mV/(m/s^2)\"", "sensor.sensitivity")
    chans = {c.number: (r, c) for r in recorded for c in r.channels}
    for rd in readings:
        if rd.paired and "a" in rd.entry:
            _, c = chans[rd.number]
            ratio = c.rms.a / S / rd.entry["a"].value
            for wrong in (G_RATIO, 1 / G_RATIO):
                if abs(ratio / wrong - 1) < 0.3:
                    raise inputs.error(
                        f"measurement {rd.number}: the record reads {ratio:.2f} times the "
                        "meter's acceleration: the sensitivity is given per m/s² where the "
                        "chart gives it per g, or back", "write the sensitivity with the "
                        "chart's unit (mV/g or mV/(m/s^2))", "sensor.sensitivity")
    floor = [(c.number, q, c.rms.floor[q] / c.rms[q]) for r in recorded for c in r.channels
             for q in QUANTITIES if c.rms[q] > 0 and c.rms.floor[q] > FLOOR_SHARE * c.rms[q]]
    if floor:
        warnings.warn(lab_report.on_floor(floor, FLOOR_SHARE))


def _check_cut(recorded: list[Recorded]) -> None:
    """A record marked cut where no cylinder was found; a finding against the stated one."""
    for r in recorded:
        v = r.verdict
        if r.ignition != "cut" or v is None:
            continue
        if not v.found:
            warnings.warn(lab_report.cut_not_found(r.number, v.rise))
        elif r.cut_stated is not None and v.cylinder != r.cut_stated:
            warnings.warn(lab_report.cut_disagrees(r.number, v.cylinder, r.cut_stated,
                                                   v.confidence))


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20034,
           report: bool = True) -> LabResult:
    """Reduce lab 4's records and meter readings.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed.
    report : bool
        Also the report's tables, figures and conclusion (False: the results, comparisons
        and warnings alone, what a check and its slips read).

    Returns
    -------
    LabResult
        Per measurement j (a record's channel, then meter readings of their own):
        ``a_rms_j`` [m/s²], ``v_rms_j`` [m/s], ``x_rms_j`` [m] and ``a_pp_j``, ``v_pp_j``,
        ``x_pp_j``; from records ``a1_j``, ``a2_j`` (the first and second orders' amplitudes)
        and per record r ``n_r``; where a meter reading shares the measurement,
        ``a_meter_j`` … compared with the record's; with the engine's R, λ, m_j ``F1_r``,
        ``F2_r`` (the free inertia forces) and with its mass ``a1_model_r``, ``a2_model_r``;
        per record with the ignition cut ``cut_cylinder_r``, ``cut_confidence_r``,
        ``half_rise_r``.

    Raises
    ------
    InputError
        A record shorter than a revolution, a speed the record contradicts, a sensitivity
        in the wrong unit, channels not matching the points, readings of points that do not
        exist.
    """
    phases = _check_inputs(inputs)
    points = len(inputs["point"])
    with collect_notices() as notices:
        recorded = [_sweep_copy(_record(inputs, i, e, points, phases))
                    for i, e in enumerate(inputs.sections.get("record", []))]
        unmarked = [(r.number, r.unmarked) for r in recorded if not r.marked]
        if unmarked:
            warnings.warn(lab_report.no_marks(unmarked))
        slow = [(r.number, r.rate) for r in recorded
                if r.rate / 2 < max(b.high for b in BANDS.values())]
        if slow:
            warnings.warn(lab_report.band_beyond_nyquist(slow))
        j = 0
        for r in recorded:
            for c in r.channels:
                j += 1
                c.number = j
        if inputs["engine"]["strokes"] == 4:
            _cut_cylinders(recorded, phases)
        elif any(r.ignition == "cut" for r in recorded):
            warnings.warn(lab_report.two_stroke_cut())
        readings = _pair_readings(inputs, recorded, points)
        _check_records(inputs, recorded, readings)
        _check_cut(recorded)
        engine = inputs["engine"]
        forces = all(k in engine for k in ("R", "lambda", "m_j"))
        crank_angles = np.mod(phases, 2 * np.pi)
        reference = inputs["meter"]["db_reference"] if "meter" in inputs else "iso1683"
        prop = propagate(_model(recorded, readings, crank_angles, forces, reference),
                         _flat(inputs, recorded, readings), n_samples=n_samples, seed=seed)
        declared = lab_report.result_names(recorded, readings, forces, "mass" in engine,
                                           inputs["point"])
        results = result_values(prop, declared)
        results.update(lab_report.cut_results(recorded))
        pairs = [(f"{q}_rms_{rd.number}", f"{q}_meter_{rd.number}") for rd in readings
                 if rd.paired for q in QUANTITIES]
        comparisons = compare(prop, pairs)
        _check_meter(comparisons, results, inputs)
        flag_estimates({k: v for k, v in results.items() if not k.startswith("cut_")}, [])
    if not report:
        return LabResult.of(inputs, results, comparisons=comparisons, warnings=notices)
    parts = dict(recorded=recorded, readings=readings, results=results, points=inputs["point"],
                 phases=phases, reference=reference, comparisons=comparisons)
    return LabResult.of(inputs, results, comparisons=comparisons,
                        tables=lab_report.tables(**parts), figures=lab_report.figures(**parts),
                        formulas=lab_report.FORMULAS, references=lab_report.REFERENCES,
                        warnings=notices, conclusion=lab_report.conclusion(**parts))


def _check_meter(comparisons, results, inputs: Inputs) -> None:
    """A record and the meter disagreeing beyond the meter's basic error: say which is
    suspect."""
    limit = inputs["meter"]["limit"].value if "meter" in inputs else METER_LIMIT
    off = [(c.a, c.b, results[c.a].value / results[c.b].value - 1) for c in comparisons
           if abs(results[c.a].value / results[c.b].value - 1) > limit]
    if off:
        warnings.warn(lab_report.meter_disagrees(off, limit))


# ------------------------------------------------------------------------ slips

SENSED = (r"[avx]_(rms|pp)_\d+", r"a[12]_\d+")
"""The results read through the accelerometer's sensitivity."""

SLIPS = [
    ("sensitivity_per_g",
     bi("the sensitivity in mV/(m/s²) taken as in mV/g: every acceleration, velocity and "
        "displacement read off the records 9.81 times too large",
        "коэффициент преобразования в мВ/(м/с²) принят за мВ/g: все ускорения, скорости и "
        "перемещения по записям в 9,81 раза больше"), SENSED, G_RATIO),
    ("sensitivity_per_m_s2",
     bi("the sensitivity in mV/g taken as in mV/(m/s²): every acceleration, velocity and "
        "displacement read off the records 9.81 times too small",
        "коэффициент преобразования в мВ/g принят за мВ/(м/с²): все ускорения, скорости и "
        "перемещения по записям в 9,81 раза меньше"), SENSED, 1 / G_RATIO),
    ("amplitude_for_range",
     bi("the amplitude (half the swing) reported for the peak-to-peak value",
        "амплитуда (половина размаха) указана вместо размаха"), (r"[avx]_pp_\d+",), 0.5),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the factor a slip of the arithmetic puts on them."""


# ------------------------------------------------------------------------ synthetic files

SYNTH_FORMATS = ("csv", "h5")

BENCH_ENGINES = {"R": (0.032, 0.039), "lambda": (0.26, 0.31), "m_j": (0.45, 0.65),
                 "mass": (120.0, 165.0), "mounts": (0.9, 1.06), "chart": (0.9, 1.1)}
"""Ranges a variant's engine, mounts and accelerometer are drawn from. The crank radius R [m]:
the scene's 82 mm bore with a 64–78 mm stroke, a 1.35–1.65 l four-cylinder car engine about
the scene's 1.5 l; λ = R/L: β_max = arcsin λ of 15–18° (FORMULAS.md A, modern engines); m_j per
cylinder [kg]: 85–123 kg/m² of the piston's area, the coursework's car example at 120 kg/m²
(12 g/cm², ``sample_data/dyncalc/car_petrol.toml``) at the top; the mass on the mounts [kg]
(about the scene's 140 kg of engine and gearbox; its roll and pitch inertia in proportion);
one factor on the mounts' four natural frequencies (a stiffer or softer set, k = m(2πf)²),
which keeps them within the 4–8 Hz of soft bench mounts, below the lowest half order of a run
(:class:`processing.synth.engine_mount.Block`); and the accelerometer's chart value over its
family's nominal 100 or 50 mV/g, the ± 10 % a general-purpose IEPE accelerometer's datasheet
allows (e.g. PCB 352C33, 100 mV/g ± 10 %), written in mV/g or in mV/(m/s²) as charts give
it."""


def bench_variant(seed: int):
    """A variant's engine on its mounts and its accelerometer's chart (:data:`BENCH_ENGINES`).
    Seed 0 is the scene's: :class:`processing.synth.engine.Engine`,
    :class:`processing.synth.engine_mount.Block` and a 10.2 mV/(m/s²) chart.

    The drawn values are rounded as a data sheet gives them (R to 0.1 mm, λ to 0.001, m_j to
    10 g, the mass to 1 kg, the chart to three figures), so the file states the part exactly.

    Returns
    -------
    engine : processing.synth.engine.Engine
    block : processing.synth.engine_mount.Block
    chart : str
        The chart's sensitivity as the file gives it, without its limit.
    """
    from processing.synth.engine import Engine
    from processing.synth.engine_mount import Block

    engine, block = Engine(), Block()
    if seed == 0:
        return engine, block, "10.2 mV/(m/s^2)"
    rng = np.random.default_rng([seed, 42])
    engine = replace(engine,
                     crank_radius=round(rng.uniform(*BENCH_ENGINES["R"]), 4),
                     lambda_=round(rng.uniform(*BENCH_ENGINES["lambda"]), 3),
                     reciprocating_mass=round(rng.uniform(*BENCH_ENGINES["m_j"]), 2))
    mass = float(np.round(rng.uniform(*BENCH_ENGINES["mass"])))
    stiffer = rng.uniform(*BENCH_ENGINES["mounts"])
    block = replace(block, mass=mass, roll_inertia=block.roll_inertia * mass / block.mass,
                    pitch_inertia=block.pitch_inertia * mass / block.mass,
                    frequencies=tuple(stiffer * f for f in block.frequencies))
    per_g = rng.choice([100.0, 50.0]) * rng.uniform(*BENCH_ENGINES["chart"])
    value, unit = (per_g, "mV/g") if rng.random() < 0.5 else (per_g / G_RATIO, "mV/(m/s^2)")
    decimals = max(0, 2 - int(np.floor(np.log10(value))))
    return engine, block, f"{value:.{decimals}f} {unit}"


def write_synthetic(out_dir, seed: int = 0, *, fmt: str = "h5", snr_db: float = 30.0,
                    speeds=(1000.0, 3000.0), step: float = 500.0, cut_speed: float = 2000.0,
                    duration: float = 2.4, meter: bool = True,
                    adc_range: float | None = None, part: int | None = None) -> dict[str, Path]:
    """Write a synthetic lab 4 measurement: records of a speed sweep, one with a cylinder's
    ignition cut, meter readings, a measurement file and the answer key.

    The scene of :mod:`processing.synth.engine_mount`: a four-cylinder petrol engine
    (firing order 1-3-4-2) on soft bench mounts, three points (cylinder head vertical and
    transverse, front cover longitudinal), an accelerometer (its true sensitivity within its
    ±2 % chart value) with its resonance at 28 kHz; seed 0 the scene's 1.5 l engine, 140 kg,
    and a 10.2 mV/(m/s²) chart, any other seed its own engine, mounts and sensor
    (:func:`bench_variant`); recorded at
    25.6 kHz beside cylinder 1's ignition pickup; every ``step`` min⁻¹ over ``speeds`` and,
    at ``cut_speed``, with the ignition of a cylinder drawn from the seed cut. The meter's
    readings of the cut record and its healthy companion (true values within the meter's
    ±15 %) come with them.

    Parameters
    ----------
    out_dir : str or Path
        Folder to write into (created).
    seed : int
        Seed of everything random (the engine, its mounts and the sensor's chart too).
    part : int, optional
        Seed of the engine, its mounts and the sensor's chart (default ``seed``; 0: the
        scene's, whatever ``seed`` draws the rest).
    fmt : {"csv", "h5"}
        Record format.
    snr_db : float
        Each channel's signal-to-noise ratio in its worst band. [dB]
    speeds : (float, float)
        Lowest and highest speed. [min⁻¹]
    step : float
        The sweep's speed step. [min⁻¹]
    cut_speed : float
        Speed of the record with a cylinder cut (one of the sweep's). [min⁻¹]
    duration : float
        Length of each record. [s]
    meter : bool
        Also write meter readings for the records at ``cut_speed``.
    adc_range : float, optional
        Write HDF5 records as a 16-bit recorder's codes over ± this range (the TDC pulse
        clipped at it), with their volts per code; default: volts as floats. [V]

    Returns
    -------
    dict
        Paths written: ``toml``, ``answer``, and one per record (``r1``, ``r2``, …).
    """
    import json

    from processing.inputs.signals import write_csv, write_hdf5
    from processing.synth.engine_mount import POINTS, Accelerometer, cylinder_factors, record

    if fmt not in SYNTH_FORMATS:
        raise InputError(f"unknown record format {fmt!r}", f"use one of {', '.join(SYNTH_FORMATS)}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng([seed, 41])
    engine, block, chart = bench_variant(seed if part is None else part)
    firing = (1, 3, 4, 2)
    factors = cylinder_factors(engine, block, rng)
    cut = int(rng.integers(1, engine.cylinders + 1))
    sensor = Accelerometer(sensitivity=sensitivity(chart).value * (1 + rng.uniform(-0.02, 0.02)),
                           snr_db=snr_db)
    plan = [(n, "all") for n in np.arange(speeds[0], speeds[1] + 1e-9, step)]
    plan.append((cut_speed, "cut"))
    written, bodies, truth = {}, [], {}
    j = 0
    meter_bodies = []
    for number, (n, ignition) in enumerate(plan, 1):
        w = n / RPM * (1 + rng.uniform(-0.004, 0.004))
        rec = record(engine, block, POINTS, sensor, w, duration, seed=seed * 1000 + number,
                     factors=factors, firing_order=firing,
                     cut=cut if ignition == "cut" else None)
        name = f"r{number:02d}.{fmt}"
        columns = {**{k: np.round(v, 6) for k, v in rec.volts.items()},
                   "tdc": np.round(rec.tdc, 2)}
        rate = ""
        if fmt == "csv":
            write_csv(out / name, columns)
            rate = f'sample_rate = "{sensor.sample_rate / 1e3:g} kHz"\n'
        elif adc_range:
            step = adc_range / 32768
            write_hdf5(out / name, {k: np.clip(np.round(v / step), -32768, 32767).astype(np.int16)
                                    for k, v in columns.items()}, sensor.sample_rate,
                       volts_per_code=step)
        else:
            write_hdf5(out / name, columns, sensor.sample_rate)
        written[f"r{number}"] = out / name
        n_tach = round(w * RPM + rng.normal(0, 4))
        cut_line = f"cut_cylinder = {cut}\n" if ignition == "cut" and seed % 2 else ""
        bodies.append(f'[[record]]\nsignal = "{name}"\n{rate}channels = "acc1, acc2, acc3"\n'
                      f'n = "{n_tach} ± 10 rpm"\nignition = "{ignition}"\n{cut_line}')
        truth[f"n_{number}"] = w
        for p, ch in enumerate(rec.volts, 1):
            j += 1
            t = rec.truth[ch]
            for q in QUANTITIES:
                truth[f"{q}_rms_{j}"], truth[f"{q}_pp_{j}"] = t[q], t[f"{q}_pp"]
            truth[f"a1_{j}"], truth[f"a2_{j}"] = t["order1"], t["order2"]
            if meter and abs(n - cut_speed) < 1e-9:
                err = 1 + rng.uniform(-0.1, 0.1, 3)
                meter_bodies.append(
                    f'[[reading]]\npoint = {p}\nn = "{n_tach} rpm"\nignition = "{ignition}"\n'
                    f'a = "{t["a"] * err[0]:.3g} m/s^2"\nv = "{1e3 * t["v"] * err[1]:.3g} mm/s"\n'
                    f'x = "{1e6 * t["x"] * err[2]:.3g} um"\n')
        if ignition == "cut":
            truth[f"cut_cylinder_{number}"] = cut
    mj, R, lam = engine.reciprocating_mass, engine.crank_radius, engine.lambda_
    toml = (f'lab = "lab4"\n[meta]\nstudent = "synthetic (dynlab synth lab4 --seed {seed})"\n'
            'notes = "generated; the true answers are in answer_key.json"\n\n'
            f'[engine]\ncylinders = {engine.cylinders}\nstrokes = 4\n'
            f'firing_order = "{"-".join(map(str, firing))}"\nR = "{1e3 * R:g} mm"\n'
            f'lambda = {lam:g}\nm_j = "{mj:g} kg"\nm_r = "0 kg"\n'
            f'mass = "{block.mass:g} kg"\n\n'
            f'[sensor]\nsensitivity = "{chart} ± 2 %"\n\n'
            + "".join(f'[[point]]\nname = "{p.name}"\ndirection = "{p.direction}"\n\n'
                      for p in POINTS)
            + "\n".join(bodies) + "\n" + "\n".join(meter_bodies))
    written["toml"] = out / f"lab4_seed{seed}.toml"
    written["toml"].write_text(toml, encoding="utf-8")
    written["answer"] = out / "answer_key.json"
    written["answer"].write_text(json.dumps({"seed": seed, "results": truth}, indent=1),
                                 encoding="utf-8")
    return written
