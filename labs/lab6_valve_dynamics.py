"""Lab 6. Oscillations of the valve mechanism on a running engine.

The manual's chapter: strain gauges on the rockers, through an amplifier, record the force in
the valve drive on a light-beam oscillograph (or an ADC) beside time marks and TDC marks.
A static calibration first gives the trace's scale k (the manual: 80…100 mm of trace for
1500 N). Records are taken at n = 500, 1000, 1500, 1800 and 2000 min⁻¹, full load, with the
valve clearance δ set to 0.3, 0.5 and 0.8 mm. From each record: the speed n = 60 N/(z T_mark),
the drive's oscillation frequency ν = 60 N₁/(m T_mark), the forces P_max = k A_max and
P_min = k A_min, the losses of contact (P ≤ 0: the kinematic chain broken), the opening
durations φ = 360 T_open/T_cam and the valve timing against the TDC and BDC marks; then
P_max, P_min and φ against n for each clearance.

Here each record is a signal file (CSV, WAV or HDF5: one force channel per valve, the TDC marks,
optionally the time marks) or a photograph of the paper oscillogram ([image]); a record is a channel
of samples with its marks, whatever made it. The speed comes from the TDC marks' times, k from a
straight line through the calibration (:func:`processing.regression.fit_line`), the events, forces,
contact losses and free oscillations from :mod:`processing.valvetrain.valve_force` (the valve opens
and closes where the force passes the springs' preload P₀, which the file gives from lab 5); ν is a
damped sinusoid fitted to each opening's free oscillation. Across the records of one clearance, the
speed at which the drive separates is where the line through the two fastest records that kept
contact reaches P_min = 0.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 6 ("Исследование колебаний клапанного механизма двигателя").
"""
from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from processing.diagnostics import InputError, collect_notices
from processing.measurement import (ENGINE_SPEED, MARK_PERIOD, SAMPLE_RATE, STROKES, Field, Inputs,
                                    LabSpec, Section, bi, image_section)
from processing.inputs.record_checks import check_tachometer, check_time_marks
from processing.inputs.record_quality import (SENSOR_FIX, check_pulses, check_record,
                                       clipped_mask)
from processing.inputs.reuse import by_content, scope
from processing.regression import calibration_fault, curvature_test, fit_line
from processing.result import LabResult, flag_estimates, result_values
from processing.inputs.signals import (image_options, is_image, open_channels,
                                read_figures)
from processing.torsional.torsiogram import Revolutions, crank_angle, revolutions
from processing.uncertainty import Measured, propagate
from processing.valvetrain.valve_force import (NU_POOR, ValveEvent, trace_zero,
                                              valve_events_each)

from . import catalogue, lab6_valve_dynamics_report as lab_report

VALVES = ("in", "ex")
"""The valves: inlet and exhaust."""

CURVATURE_LEVEL = 0.01
"""Significance level of the calibration's quadratic term."""

CURVATURE_BEND = 0.005
"""Relative bend of the calibration (the quadratic term's largest share of its rise) above
which a significant bend is called out: the straight line's k then errs by more than the
forces' own uncertainty (about 0.5 % at the manual's 80…100 mm for 1500 N read to 0.2 mm)
somewhere over the loads."""

CONTACT_MARGIN = 2.0
"""A record keeps contact for the separation line when P_min exceeds this many of its
standard uncertainties and no loss of contact is seen."""

CLIPPED_FORCE = (
    "an opening whose largest (least) force sits on them is cut off there, and its P_max "
    "(P_min) is left out of the results",
    "у открытий, чья наибольшая (наименьшая) сила приходится на них, она срезана, и P_max "
    "(P_min) этого режима в результаты не включена")
"""What a clipped force channel's warning says the reduction did (English, Russian)."""

PHOTO_FIX = {"en": "photograph the oscillogram again, sharp and whole, with each valve's "
                   "trace, its zero and the marks in the frame",
             "ru": "сфотографируйте осциллограмму заново, резко и целиком, с линией каждого "
                   "клапана, её нулём и отметками в кадре"}
"""What to do about a flat or noise-only trace read off a photograph."""

MARKS_FIX = {"en": "check the time-mark generator's lead to the recorder and record again, or "
                   "leave marks_channel out",
             "ru": "проверьте провод от генератора отметок времени к регистратору и запишите "
                   "заново, или уберите marks_channel"}
"""What to do about a flat or noise-only time-mark channel."""

SEPARATION_MODEL = 0.02
"""Half-width, as a share of the speed, of the rectangular type B uncertainty of the
separation speed for the straight line's own error (P_min falls slightly faster than linearly
towards the separation; the benchmark's line errs by under 1 %)."""

SPEC = LabSpec(
    id="lab6", number="6",
    title=catalogue.title("lab6"),
    goal=bi("To study the experimental methods for the oscillations of a valve mechanism and "
            "to find the real loads on the valve-drive parts: the forces, the drive's "
            "oscillation frequency, the losses of contact and the valve timing against the "
            "speed and the valve clearance.",
            "Изучить методы экспериментального исследования колебаний клапанного механизма "
            "и определить действительные нагрузки на детали привода клапана: силы, частоту "
            "колебаний привода, разрывы кинематической цепи и фазы газораспределения в "
            "зависимости от частоты вращения и зазора."),
    sections=(
        Section("engine", bi("Engine and marks", "Двигатель и отметки"), required=True, fields=(
            Field("strokes", bi("strokes per cycle", "тактность"), **STROKES),
            Field("tdc_per_revolution", bi("TDC marks per crankshaft revolution",
                                           "отметок ВМТ за оборот коленчатого вала"),
                  kind="count", default=1),
            Field("mark_period", bi("period of the time marks", "период отметчика времени"),
                  **MARK_PERIOD, required=False, symbol="T_отм"),
        )),
        Section("valve", bi("Valve drive with a strain gauge", "Привод клапана с тензодатчиком"),
                required=True, many=True, help=lab_report.VALVE_HELP, fields=(
            Field("name", bi("which valve: in (inlet) or ex (exhaust)",
                             "клапан: in (впускной) или ex (выпускной)"), kind="choice",
                  choices={"in": bi("inlet", "впускной"), "ex": bi("exhaust", "выпускной")}),
            Field("channel", bi("its channel in the records (default: its name)",
                                "его канал в записях (по умолчанию — имя клапана)"),
                  kind="text", required=False),
            Field("P0", bi("springs' preload on the closed valve (lab 5)",
                           "сила предварительной затяжки пружин при закрытом клапане "
                           "(лаб. 5)"), unit="N", limit="10 N", symbol="P₀", example=260,
                  plausible=("10 N", "5000 N")),
            Field("load", bi("calibration loads", "тарировочные нагрузки"), unit="N",
                  limit="5 N", allow_zero=True, symbol="P", series=True,
                  example="[0, 300, 600, 900, 1200, 1500]", plausible=("1 N", "20000 N")),
            Field("deflection", bi("the trace's deflection at each load (the record's unit: mm "
                                   "of oscillogram or V)", "отклонение записи при каждой "
                                   "нагрузке (в единицах записи: мм осциллограммы или В)"),
                  unit="", limit="0.2", allow_zero=True, symbol="A", series=True,
                  example="[0, 18.1, 36.0, 54.2, 71.9, 90.1]", plausible=("1e-4", "1e4")),
        )),
        Section("record", bi("Record", "Осциллограмма"), many=True, required=True,
                help=lab_report.RECORD_HELP, fields=(
            Field("signal", bi("the record: CSV, WAV or HDF5 file, or a photograph or scan of "
                               "the paper oscillogram ([image])", "запись: файл CSV, WAV или "
                               "HDF5 или снимок бумажной осциллограммы ([image])"),
                  kind="file", example="r500_03.csv"),
            Field("clearance", bi("valve clearance", "зазор между клапаном и коромыслом"),
                  unit="mm", limit="0.02 mm", symbol="δ", example=0.3,
                  plausible=("0.1 mm", "1.5 mm")),
            Field("n", bi("speed by the tachometer", "частота вращения по тахометру"),
                  **ENGINE_SPEED, limit="10 rpm", required=False, symbol="n_t"),
            Field("tdc_channel", bi("channel of the TDC marks", "канал отметок ВМТ"),
                  kind="text", default="tdc"),
            Field("marks_channel", bi("channel of the time marks, if recorded",
                                      "канал отметок времени, если записан"),
                  kind="text", required=False),
            Field("sample_rate", bi("sample rate, if the file does not say",
                                    "частота дискретизации, если её нет в файле"),
                  **SAMPLE_RATE, required=False, symbol="f_s"),
        )),
        image_section(),
    ),
)


# ------------------------------------------------------------------------ formulas

def force(k, A):
    """Force from the trace, the manual's P = k A.

    Parameters
    ----------
    k : float or ndarray
        The trace's scale from the calibration. [N per trace unit]
    A : float or ndarray
        Deflection of the trace from its zero. [trace unit]

    Examples
    --------
    >>> round(force(1500 / 90, 45.0), 6)
    750.0
    """
    return k * A


def opening_duration(T_open, T_cam):
    """Opening duration in camshaft angle, the manual's φ = 360 T_open/T_cam (in rad: 2π).

    .. math:: φ = 2π \\frac{T_{open}}{T_{cam}}

    Crank degrees are twice the cam's on a four-stroke engine.

    Parameters
    ----------
    T_open, T_cam : float or ndarray
        The opening's length and one camshaft revolution, in the same unit (s or mm of
        paper).

    Examples
    --------
    >>> round(math.degrees(opening_duration(30.0, 120.0)), 9)
    90.0
    """
    return 2 * np.pi * T_open / T_cam


def separation_speed(n1, P1, n2, P2):
    """Speed where the line through (n₁, P_min,1) and (n₂, P_min,2) reaches P_min = 0.

    .. math:: n_{sep} = n_2 + P_2 \\frac{n_2 - n_1}{P_1 - P_2}

    Examples
    --------
    >>> round(separation_speed(1000.0, 92.0, 1500.0, 19.0), 3)
    1630.137
    """
    return n2 + P2 * (n2 - n1) / (P1 - P2)


# ------------------------------------------------------------------------ records

@dataclass
class Trace:
    """One valve's force channel of a record, whatever made it: samples, the zero and noise,
    and the events read."""

    valve: str
    time: np.ndarray
    value: np.ndarray
    """Deflection above the trace's zero. [trace unit]"""
    noise: float
    events: list[ValveEvent]
    stroke_time: float = 0.0
    """A photographed trace's stroke width along the time axis (0 for a recording): a
    steep stroke's time is read within half of it. [s]"""
    stroke: float = 0.0
    """Its stroke width across: a sharp extreme is read within :data:`PHOTO_EXTREME` of
    it (0 for a recording). [trace unit]"""


@dataclass
class Recorded:
    """One record and what it reduced to."""

    number: int
    source: Path
    clearance: float
    speed: Measured
    """From the TDC marks. [rad/s]"""
    revs: Revolutions
    """Its revolutions from the TDC marks."""
    traces: dict
    channels: dict
    """Each valve's channel read off a photograph (for the overlay figure and what its stroke
    hides); none for recordings."""


def _marks(x, rate: float) -> np.ndarray:
    """Times of the marks of a pulse channel: where each pulse falls through half the
    channel's range (linear between the samples around it). [s]"""
    x = np.asarray(x, dtype=float)
    if x.size < 2:
        return np.array([])
    half = 0.5 * (x.min() + x.max())
    k = np.flatnonzero((x[:-1] >= half) & (x[1:] < half))
    return (k + (x[k] - half) / (x[k] - x[k + 1])) / rate


def _read(inputs: Inputs, where: str, entry: dict, names: dict):
    """Time, the valves' traces, the TDC marks' times and the channels (for their figures) of
    a record file or a photographed oscillogram; each channel checked to be what it claims
    (:mod:`processing.inputs.record_quality`): a trace neither flat nor noise nor clipped beyond
    the limit, the marks neither flat nor noise."""
    path, field = entry["signal"], f"{where}.signal"
    if is_image(path):
        options = image_options(inputs.sections.get("image"))
        photos = dict(zip(names, open_channels(path, list(names.values()), field=field,
                                               image=options)))
        traces, tdc = _on_one_time_axis(photos, path, field)
        rate = next(iter(photos.values())).sample_rate
        labels = {v: str(photos[v].name) for v in names}
    else:
        uses = [({"en": f"the {lab_report.VALVE_WORDS[v]['en']} valve's force",
                  "ru": f"силы {lab_report.VALVE_GENITIVE[v]} клапана"}, c,
                 f"valve[{list(names).index(v)}].channel") for v, c in names.items()]
        uses.append(({"en": "the TDC marks", "ru": "отметок ВМТ"}, entry["tdc_channel"],
                     f"{where}.tdc_channel"))
        if "marks_channel" in entry:
            uses.append(({"en": "the time marks", "ru": "отметок времени"},
                         entry["marks_channel"], f"{where}.marks_channel"))
        _distinct(inputs, uses)
        time, channels, tdc = _recorded(inputs, where, entry, tuple(sorted(names.values())))
        return time, {v: channels[c] for v, c in names.items()}, tdc, {}
    return _checked(traces, labels, rate, path, PHOTO_FIX, field), traces, tdc, photos


def _checked(traces: dict, labels: dict, rate: float, path, fix: dict, field: str):
    """The samples' times of force ``traces`` (their channels' ``labels`` by the same keys),
    each checked to be what it claims (:func:`processing.inputs.record_quality.check_record`:
    ``fix`` says how to mend a trace that is not). [s]"""
    for key, x in traces.items():
        check_record(x, rate, file=str(path), field=field, channel=labels[key],
                     purpose={"en": "the valve's forces", "ru": "сил в клапане"},
                     fix=fix, clipped_effect=CLIPPED_FORCE)
    return np.arange(next(iter(traces.values())).size) / rate


@by_content(lambda inputs, where, entry, channels: (
    where, *(entry.get(k) for k in ("signal", "sample_rate", "tdc_channel", "marks_channel")),
    channels, inputs["engine"]), shared=True)
def _recorded(inputs: Inputs, where: str, entry: dict, channels: tuple) -> tuple:
    """Time, the force ``channels`` by name and the TDC marks' times of a record file, each
    channel checked to be what it claims (:mod:`processing.inputs.record_quality`), the time
    marks against the engine's mark period; read once inside a scope for the same channels,
    whichever valve each is named for (the valves' traces swapped read the same)."""
    path, field = entry["signal"], f"{where}.signal"
    rate = entry["sample_rate"].value if "sample_rate" in entry else None
    wanted = [*channels, entry["tdc_channel"]] + (
        [entry["marks_channel"]] if "marks_channel" in entry else [])
    read = open_channels(path, wanted, sample_rate=rate, field=field)
    rate = read[0].sample_rate
    traces = {c: ch.read().astype(float) * ch.volts_per_code for c, ch in zip(channels, read)}
    tdc = _pulse_marks(read[len(channels)], rate, f"{where}.tdc_channel",
                       {"en": "TDC marks", "ru": "отметок ВМТ"}, SENSOR_FIX)
    if len(read) > len(channels) + 1:
        marks = read[-1]
        check_time_marks(inputs, "engine", marks.name,
                         _pulse_marks(marks, rate, f"{where}.marks_channel",
                                      {"en": "time marks", "ru": "отметок времени"},
                                      MARKS_FIX), rate,
                         lambda problem, fix, key: InputError(
                             problem, fix, file=marks.path, field=f"{where}.{key}"),
                         "2 ms")
    labels = {c: str(ch.name) for c, ch in zip(channels, read)}
    return _checked(traces, labels, rate, path, SENSOR_FIX, field), traces, tdc


SHARED_SPAN = 0.5
"""Least share of the longest trace's span that the valves' traces of one sheet must be read
over together."""


def _on_one_time_axis(photos: dict, path, field: str) -> tuple[dict, np.ndarray]:
    """The valves' traces read off one sheet, on the first's time grid over the time all of
    them are read [mm of paper], and the TDC marks' times on it [s].

    Each trace read off a sheet starts its time where it is first read, so two traces of
    one sheet are shifted by the difference of the times each puts the same mark at (a
    time mark, else a TDC mark; none: no shift). A trace read over less than
    :data:`SHARED_SPAN` of the longest one's span is refused: the reader lost it."""
    first = next(iter(photos.values()))
    kind = next((k for k in ("time", "tdc") if first.marks.get(k, np.empty(0)).size), None)
    shift = {v: float(first.marks[kind][0] - ch.marks[kind][0]) if kind else 0.0
             for v, ch in photos.items()}
    lo = max(shift.values())
    hi = min(shift[v] + ch.time[-1] for v, ch in photos.items())
    longest = max(ch.time[-1] for ch in photos.values())
    if hi - lo < SHARED_SPAN * longest:
        short = min(photos, key=lambda v: photos[v].time[-1])
        raise InputError(
            f"{photos[short].name} is read over {photos[short].time[-1]:.3g} s, the valves' "
            f"traces together over {max(hi - lo, 0.0):.3g} s of the sheet's {longest:.3g} s: "
            "the reader lost a trace", "look at the overlay: photograph or scan the sheet "
            "flat, sharp and evenly lit, the traces whole", file=str(path), field=field,
            ru=(f"{photos[short].name} прочитана на {photos[short].time[-1]:.3g} с, кривые "
                f"клапанов вместе — на {max(hi - lo, 0.0):.3g} с из {longest:.3g} с листа: "
                "кривая потеряна при чтении", "посмотрите на наложение: снимите или "
                "отсканируйте лист ровно, резко и равномерно освещённым, кривые целиком"))
    grid = first.time[(first.time >= lo) & (first.time <= hi)]
    traces = {v: np.interp(grid, ch.time + shift[v], np.nan_to_num(ch.read() * _paper_mm(ch)))
              for v, ch in photos.items()}
    return traces, first.marks.get("tdc", np.array([])) - (grid[0] if grid.size else 0.0)


def _distinct(inputs: Inputs, uses: list[tuple[dict, object, str]]) -> None:
    """Refuse one channel named for two things (a valve's force and the TDC marks): each use
    is (what it is for, in English and Russian, the channel, the field that names it)."""
    seen = {}
    for use, channel, field in uses:
        if str(channel) in seen:
            first = seen[str(channel)]
            raise inputs.error(f"channel '{channel}' is named both for {first['en']} "
                               f"and for {use['en']}", "name each its own channel of the record: "
                               "[[valve]] channel, tdc_channel and marks_channel", field,
                               (f"канал '{channel}' назван и для {first['ru']}, и для "
                                f"{use['ru']}", "назовите для каждого свой канал записи: "
                                "channel = … в [[valve]], tdc_channel = … и marks_channel = …"))
        seen[str(channel)] = use


def _pulse_marks(channel, rate: float, field: str, pulses: dict, fix: dict) -> np.ndarray:
    """The marks' times of a recorded pulse channel, refused flat or noise only. [s]"""
    x = channel.read().astype(float) * channel.volts_per_code
    check_pulses(x, rate, file=str(channel.path), field=field, channel=str(channel.name),
                 pulses=pulses, fix=fix)
    return _marks(x, rate)


def _paper_mm(channel) -> float:
    """Factor from a photographed trace's unit to the record's: mm of paper."""
    return 1e3 if channel.unit == "m" else 1.0


@dataclass
class _Read:
    """One record read, its traces not yet analysed (:func:`_read_record`)."""

    number: int
    entry: dict
    where: str
    names: dict
    """Each valve's channel name."""
    time: np.ndarray
    raw: dict
    """Each valve's trace as read. [trace unit]"""
    photos: dict
    speed: Measured
    revs: Revolutions
    duration: float
    """[s]"""
    cam_turn: float
    """One camshaft revolution at its speed. [s]"""


def _records(inputs: Inputs, valves: dict) -> list[Recorded]:
    """Every record read (:func:`_read_record`, in order), then the valves' traces of all of
    them analysed at once (:func:`_traces`: their free oscillations fitted together)."""
    read = [_read_record(inputs, i, e, valves) for i, e in enumerate(inputs["record"])]
    analysed = _traces([(r.time, r.raw, {v: valves[v]["P0"].value / valves[v]["k"]
                                          for v in r.raw}, r.photos) for r in read])
    return [_recorded_with(r, traces) for r, traces in zip(read, analysed)]


def _read_record(inputs: Inputs, i: int, entry: dict, valves: dict) -> _Read:
    """Record ``i`` read, its speed from the TDC marks checked against the tachometer's.
    Inside a scope (a check's slips reduced again) its channels are read once
    (:func:`_recorded`); the valves' traces swapped read the same channels."""
    where = f"record[{i}]"
    names = {v: spec.get("channel", v) for v, spec in valves.items()}
    time, raw, tdc, photos = _read(inputs, where, entry, names)
    rate = 1.0 / (time[1] - time[0])
    duration = time.size / rate
    per_rev = inputs["engine"]["tdc_per_revolution"]
    if tdc.size < per_rev + 1:
        raise _few_marks(inputs, entry, tdc.size, duration, where, photos)
    try:
        revs = revolutions(tdc, per_revolution=per_rev)
    except InputError as exc:
        raise InputError(exc.problem, exc.fix, file=str(entry["signal"]),
                         field=f"{where}.tdc_channel") from None
    span = revs.mark_times[-1] - revs.mark_times[0]
    speed = Measured(revs.angular_speed, revs.u_speed, max(revs.speeds.size - 1, 1),
                     limit=revs.angular_speed / (rate * span))
    _check_speed(entry, speed.value, where, photos)
    cam_turn = 4 * np.pi / inputs["engine"]["strokes"] / speed.value
    return _Read(i + 1, entry, where, names, time, raw, photos, speed, revs, duration,
                 cam_turn)


def _recorded_with(read: _Read, traces: dict) -> Recorded:
    """A record read and its traces analysed; refused where a trace holds no whole valve
    event."""
    duration = read.duration
    for valve, trace in traces.items():
        if not trace.events:
            raise InputError(f"channel '{read.names[valve]}' holds no whole valve event above "
                             f"its noise (σ = {trace.noise:.3g}) over its {duration:.3g} s, "
                             f"{duration / read.cam_turn:.1f} camshaft revolutions",
                             "record at least two camshaft revolutions and check the channel "
                             "names, the preload P0 and the amplifier's gain",
                             file=str(read.entry["signal"]), field=f"{read.where}.signal")
    return Recorded(read.number, Path(read.entry["signal"]), read.entry["clearance"].value,
                    read.speed, read.revs, traces, read.photos)


def _traces(records: list[tuple]) -> list[dict]:
    """Each valve's force channel of each record (time, the valves' traces, their preloads in
    the trace's unit, the photographed channels) analysed
    (:func:`processing.valvetrain.valve_force.valve_events_each`: the free oscillations of all
    of them fitted together, each once inside a scope: the valves' traces swapped meet the
    fits made before)."""
    prepared = []
    for time, raw, preloads, photos in records:
        zeros = {v: trace_zero(x) for v, x in raw.items()}
        strokes = {v: photos[v].stroke_value * _paper_mm(photos[v]) if v in photos else 0.0
                   for v in raw}
        prepared.append((time, raw, photos, zeros, strokes))
    events = iter(valve_events_each([
        (time, x - zeros[v].level, preloads[v], zeros[v].noise, strokes[v] / 2, _clipped(x))
        for (time, raw, _, zeros, strokes), (_, _, preloads, _) in zip(prepared, records)
        for v, x in raw.items()]))
    return [{v: Trace(v, time, x - zeros[v].level, zeros[v].noise, next(events),
                      photos[v].stroke_time if v in photos else 0.0, strokes[v])
             for v, x in raw.items()} for time, raw, photos, zeros, strokes in prepared]


@by_content(shared=True)
def _clipped(x) -> np.ndarray:
    """The clipped samples of a valve's trace
    (:func:`processing.inputs.record_quality.clipped_mask`), found once for the same samples
    inside a scope (the valves' traces swapped meet them again)."""
    return clipped_mask(x)


def _few_marks(inputs: Inputs, entry: dict, found: int, duration: float,
               where: str, photos: dict) -> InputError:
    """Too few TDC marks for a revolution: a record too short for the tachometer's speed,
    or marks the channel does not hold (on a photograph: the TDC marks not found, named
    with the lines the reader found)."""
    n = entry.get("n")
    strokes = inputs["engine"]["strokes"]
    need = 2 * np.pi * strokes / n.value if n is not None else 0.0
    if duration < need and not photos:
        return InputError(f"{found} TDC mark(s) on the record: it lasts {duration:.3g} s, "
                          f"shorter than the two camshaft revolutions its speed and a whole "
                          f"valve event need ({need:.3g} s at n = {n.value / lab_report.RPM_SI:.0f} "
                          "min⁻¹)", "record at least two camshaft revolutions",
                          file=str(entry["signal"]), field=f"{where}.signal",
                          ru=(f"отметок ВМТ в записи: {found}; она длится {duration:.3g} с, "
                              "меньше двух оборотов распределительного вала, нужных для "
                              "частоты вращения и целого события клапана "
                              f"({need:.3g} с при n = {n.value / lab_report.RPM_SI:.0f} мин⁻¹)",
                              "запишите хотя бы два оборота распределительного вала"))
    if photos:
        channel = next(iter(photos.values()))
        lines, lines_ru = channel.lines, channel.lines_ru
        return InputError(
            f"{found} TDC mark(s) found along the {duration:.3g} s of trace read off the "
            f"photograph, a revolution's speed needs two: the reader did not find the TDC "
            f"marks' line, or lost the traces ({lines})",
            "look at the overlay: photograph or scan the TDC-mark line whole and sharp, with "
            "the sheet's edges in the picture, or give the record as a recording",
            file=str(entry["signal"]), field=f"{where}.signal",
            ru=(f"на {duration:.3g} с кривых, прочитанных со снимка, найдено отметок ВМТ: "
                f"{found}, а для скорости за оборот нужны две: линия отметок ВМТ не найдена "
                f"или кривые потеряны при чтении ({lines_ru})",
                "посмотрите на наложение: снимите или отсканируйте линию отметок ВМТ целиком и "
                "резко, с краями листа в кадре, или дайте запись файлом сигналов"))
    return InputError(f"{found} TDC mark(s) on the record's {duration:.3g} s: its speed needs "
                      "a whole revolution", "name the TDC channel (tdc_channel = ...) and "
                      "record at least two camshaft revolutions", file=str(entry["signal"]),
                      field=f"{where}.tdc_channel",
                      ru=(f"отметок ВМТ за {duration:.3g} с записи: {found}, а для частоты "
                          "вращения нужен целый оборот", "укажите канал ВМТ (tdc_channel = ...) "
                          "и запишите хотя бы два оборота распределительного вала"))


def _check_speed(entry: dict, omega: float, where: str, photos: dict) -> None:
    """The TDC marks' speed against the tachometer's n (on a photograph, marks of another
    line taken for the TDC marks, named with the lines the reader found)."""
    if "n" not in entry:
        return
    n = entry["n"]

    def refuse(gap):
        said = (f"the TDC marks give {omega / lab_report.RPM_SI:.0f} min⁻¹ but n = "
                f"{n.value / lab_report.RPM_SI:.0f} min⁻¹ ({100 * gap:+.0f} %)")
        if photos:
            channel = next(iter(photos.values()))
            return InputError(
                f"{said}: the reader took other pips for the TDC marks, or missed some of "
                f"them ({channel.lines})", "look at the overlay: photograph or scan the TDC-mark "
                "line whole and sharp, or give the record as a recording; check n",
                file=str(entry["signal"]), field=f"{where}.signal",
                ru=(f"отметки ВМТ дают {omega / lab_report.RPM_SI:.0f} мин⁻¹, а n = "
                    f"{n.value / lab_report.RPM_SI:.0f} мин⁻¹ ({100 * gap:+.0f} %): за отметки ВМТ "
                    f"приняты другие метки или часть их пропущена ({channel.lines_ru})", "посмотрите на наложение: снимите или отсканируйте линию "
                    "отметок ВМТ целиком и резко или дайте запись файлом сигналов; проверьте n"))
        return InputError(f"{said}: a mark per revolution too many or too few, or the wrong "
                          "record", "check n, the TDC channel and tdc_per_revolution in "
                          "[engine]", file=str(entry["signal"]), field=f"{where}.n")

    check_tachometer(omega, n, refuse, lambda: lab_report.speed_disagrees(where, omega, n.value))


# ------------------------------------------------------------------------ calibration

def _calibration(inputs: Inputs, entry: dict, where: str):
    """k = dP/dA by a line through the calibration (type A from its residuals, the loads'
    limit as type B through the slope), the fit, and its curvature test."""
    P = np.asarray(entry["load"].readings, dtype=float)
    A = np.asarray(entry["deflection"].readings, dtype=float)
    if P.size != A.size:
        raise inputs.error(f"{P.size} loads but {A.size} deflections", "write one deflection "
                           "for every load, in the same order", f"{where}.deflection",
                           ru=(f"нагрузок {P.size}, а прогибов {A.size}", "запишите по прогибу "
                               "на каждую нагрузку, в том же порядке"))
    if np.unique(P).size < 3:
        raise inputs.error(f"the calibration has {np.unique(P).size} distinct load(s)",
                           "load the rocker in several steps up to about 1500 N (the manual: "
                           "80…100 mm of trace) and read the trace at each", f"{where}.load",
                           ru=(f"различных нагрузок при тарировке: {np.unique(P).size}",
                               "нагрузите коромысло несколькими ступенями примерно до 1500 Н "
                               "(по методичке: 80…100 мм записи) и снимите запись на каждой"))
    fault = calibration_fault(P, A, names=("load", "deflection"),
                              resolution=entry["deflection"].limit)
    if fault is not None:
        raise inputs.error(str(fault), "read the trace's deflection again at each calibration "
                           "load, each beside its own load (the channel must be the gauge's, "
                           "its amplifier on)", f"{where}.deflection",
                           ru=(fault.ru, "снимите прогиб записи заново при каждой тарировочной "
                               "нагрузке и запишите рядом со своей нагрузкой (канал — "
                               "тензодатчика, усилитель включён)"))
    fit = fit_line(A, P)
    if not fit.slope > 0:
        raise inputs.error("the trace's deflection does not grow with the load",
                           "check the pairing of load and deflection, and their signs",
                           f"{where}.deflection",
                           ru=("прогиб записи не растёт с нагрузкой", "проверьте, что прогибы "
                               "записаны против своих нагрузок, и их знаки"))
    u_b = math.hypot(entry["load"].u_type_b,
                     fit.slope * entry["deflection"].u_type_b) / math.sqrt(np.sum((A - A.mean())
                                                                                  ** 2))
    bend = curvature_test(A, P) if P.size >= 4 else None
    return fit.measured_slope(u_b=u_b), fit, bend


def _valves(inputs: Inputs) -> dict:
    """The valves by name, each with its k (Measured), line and bend."""
    out = {}
    for j, entry in enumerate(inputs["valve"]):
        where = f"valve[{j}]"
        if entry["name"] in out:
            raise inputs.error(f"valve '{entry['name']}' is described twice", "give each valve "
                               "(in, ex) one [[valve]] table", f"{where}.name")
        k, fit, bend = _calibration(inputs, entry, where)
        if bend is not None and bend.significant(CURVATURE_LEVEL) \
                and bend.relative_bend > CURVATURE_BEND:
            warnings.warn(lab_report.bent_calibration(entry["name"], bend))
        out[entry["name"]] = {**entry, "k": k.value, "k_measured": k, "fit": fit}
    return out


# ------------------------------------------------------------------------ reduction

def _timing(rec: Recorded, trace: Trace, valve: str) -> tuple[float, float]:
    """The valve's timing in crank angle, the mean over its events: the opening's advance
    before its dead centre and the closing's lag after its one. The inlet opens before the
    overlap TDC (the TDC mark nearest its opening) and closes after the next BDC; the exhaust
    opens before the BDC half a revolution ahead of the overlap TDC (the mark nearest its
    closing) and closes after that TDC. [rad]"""
    revs = rec.revs
    advance, lag = [], []
    for e in trace.events:
        a_open, a_close = crank_angle([e.opening, e.closing], revs)
        if valve == "in":
            tdc = 2 * np.pi * np.round(a_open / (2 * np.pi))
            advance.append(tdc - a_open)
            lag.append(a_close - tdc - np.pi)
        else:
            tdc = 2 * np.pi * np.round(a_close / (2 * np.pi))
            advance.append(tdc - np.pi - a_open)
            lag.append(a_close - tdc)
    return float(np.mean(advance)), float(np.mean(lag))


def _mean(values, u: float, m: int, **extra) -> Measured:
    """The mean of an event's reading over the record's m events, u/√m."""
    return Measured(float(np.mean(values)), u / math.sqrt(m), **extra)


def _flat(recorded, valves) -> dict:
    """The model's measured inputs: the scales, and each record's speed and readings."""
    flat = {f"k_{v}": spec["k_measured"] for v, spec in valves.items()}
    for r in recorded:
        i, omega = r.number, r.speed.value
        flat[f"r{i}.omega"] = r.speed
        if r.channels:                  # the photograph's time base, common to its traces
            flat[f"r{i}.clock"] = next(iter(r.channels.values())).clock
        for v, tr in r.traces.items():
            ev, key = tr.events, f"r{i}.{v}"
            m = len(ev)
            u_open = math.sqrt(np.mean([e.u_opening**2 for e in ev]))
            u_close = math.sqrt(np.mean([e.u_closing**2 for e in ev]))
            # a crossing at a kink: within half a sample, or half a photographed stroke
            dt = max(tr.time[1] - tr.time[0], tr.stroke_time)
            extreme = PHOTO_EXTREME * tr.stroke
            flat[f"{key}.T_open"] = _mean([e.closing - e.opening for e in ev],
                                          math.hypot(u_open, u_close), m, limit=dt)
            if not any(e.clipped_max for e in ev):
                flat[f"{key}.A_max"] = _mean([e.P_max for e in ev], ev[0].u_P, m,
                                             limit=extreme)
            if not any(e.clipped_min for e in ev):
                flat[f"{key}.A_min"] = _mean([e.P_min for e in ev], ev[0].u_P_min, m,
                                             limit=extreme)
            advance, lag = _timing(r, tr, v)
            flat[f"{key}.advance"] = Measured(advance, omega * u_open / math.sqrt(m),
                                              limit=omega * dt / 2)
            flat[f"{key}.lag"] = Measured(lag, omega * u_close / math.sqrt(m),
                                          limit=omega * dt / 2)
            flat[f"{key}.loss"] = Measured(float(np.mean([e.loss for e in ev])), limit=dt)
            fits = [e.oscillation for e in ev if e.oscillation is not None]
            if fits:
                w = np.array([1 / f.u_frequency**2 for f in fits])
                nu = float(np.sum(w * [f.frequency for f in fits]) / w.sum())
                flat[f"{key}.nu"] = Measured(nu, 1 / math.sqrt(w.sum()),
                                             min(f.dof for f in fits))
    return flat


@dataclass(frozen=True)
class Separation:
    """The records of one valve and clearance between which its drive separates."""

    valve: str
    clearance: float
    below: tuple[int, int]
    """The two fastest records that kept contact (slower first)."""
    lost: int
    """The slowest record that lost it."""

    @property
    def name(self) -> str:
        """``n_sep_in_800``: valve and clearance in µm."""
        return f"n_sep_{self.valve}_{round(self.clearance * 1e6)}"


def separations(recorded, flat) -> list[Separation]:
    """Each valve and clearance whose records include a loss of contact with two records
    that kept it below."""
    out = []
    for v in VALVES:
        for c in sorted({r.clearance for r in recorded if v in r.traces}):
            recs = sorted((r for r in recorded if r.clearance == c and v in r.traces),
                          key=lambda r: r.speed.value)
            lost = [r for r in recs if _lost(flat, r.number, v)]
            if not lost:
                continue
            kept = [r for r in recs if r.speed.value < lost[0].speed.value
                    and not _lost(flat, r.number, v)
                    and f"r{r.number}.{v}.A_min" in flat
                    and flat[f"r{r.number}.{v}.A_min"].value
                    > CONTACT_MARGIN * flat[f"r{r.number}.{v}.A_min"].u]
            if len(kept) >= 2:
                out.append(Separation(v, c, (kept[-2].number, kept[-1].number),
                                      lost[0].number))
    return out


def _lost(flat, i: int, v: str) -> bool:
    """Whether record i's valve v lost contact (a stretch without force while open)."""
    return flat[f"r{i}.{v}.loss"].value > 0


def _model(recorded, seps, strokes: int):
    """The measurement model: every result from the inputs of :func:`_flat`."""
    cam = 2 / strokes           # camshaft turns per crankshaft turn

    def model(**x):
        out = {k: v for k, v in x.items() if k.startswith("k_")}
        for r in recorded:
            i = r.number
            clock = x.get(f"r{i}.clock", 1.0)     # frequencies ×, durations ÷ the time base
            w = x[f"r{i}.omega"] * clock
            out[f"n_{i}"] = w
            for v in r.traces:
                key, k = f"r{i}.{v}", x[f"k_{v}"]
                for extreme in ("max", "min"):
                    if f"{key}.A_{extreme}" in x:
                        out[f"P_{extreme}_{v}_{i}"] = force(k, x[f"{key}.A_{extreme}"])
                T_cam = 2 * np.pi / (cam * w)
                out[f"phi_{v}_{i}"] = opening_duration(x[f"{key}.T_open"] / clock, T_cam)
                out[f"phi_crank_{v}_{i}"] = out[f"phi_{v}_{i}"] / cam
                out[f"advance_{v}_{i}"] = x[f"{key}.advance"]
                out[f"lag_{v}_{i}"] = x[f"{key}.lag"]
                out[f"loss_{v}_{i}"] = x[f"{key}.loss"] / clock * cam * w
                if f"{key}.nu" in x:
                    out[f"nu_{v}_{i}"] = x[f"{key}.nu"] * clock
        for s in seps:
            (a, b), v = s.below, s.valve
            n_sep = separation_speed(out[f"n_{a}"], out[f"P_min_{v}_{a}"], out[f"n_{b}"],
                                     out[f"P_min_{v}_{b}"])
            out[s.name] = n_sep * (1 + x[f"{s.name}.model"])
        return out

    return model


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20036,
           report: bool = True) -> LabResult:
    """Reduce lab 6's calibrations and records to the forces, the drive's frequency, the
    contact losses, the opening durations, the valve timing and the separation speeds.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`);
        record paths are relative to the file.
    n_samples, seed : int
        Monte Carlo draws and their seed.
    report : bool
        Also the report's tables, figures and conclusion (False: the results and warnings
        alone, what a check and its slips read).

    Returns
    -------
    LabResult
        ``k_in`` / ``k_ex`` (the traces' scales); per record i: ``n_i`` (from the TDC
        marks), and per valve v: ``P_max_v_i``, ``P_min_v_i``, ``nu_v_i`` (the drive's free
        oscillation; left out where no opening holds enough of it), ``phi_v_i`` (cam angle)
        and ``phi_crank_v_i``, ``advance_v_i`` and ``lag_v_i`` (the timing, crank angle),
        ``loss_v_i`` (cam angle without contact); per valve and clearance whose drive
        separates, ``n_sep_v_<clearance in µm>``.

    Raises
    ------
    InputError
        A calibration that cannot give a scale, a record whose channels or marks cannot be
        read, a speed far from the tachometer's.
    """
    strokes = inputs["engine"]["strokes"]
    with scope(), collect_notices() as notices:      # a stretch met twice is fitted once
        valves = _valves(inputs)
        recorded = _records(inputs, valves)
        flat = _flat(recorded, valves)
        seps = separations(recorded, flat)
        for s in seps:
            flat[f"{s.name}.model"] = Measured(0.0, limit=SEPARATION_MODEL)
        prop = propagate(_model(recorded, seps, strokes), flat, n_samples=n_samples,
                         seed=seed)
        results = result_values(prop, lab_report.result_names(recorded, valves, seps))
        _warn(recorded, flat, results, seps)
        flag_estimates(results, [])
    if not report:
        return LabResult.of(inputs, results, warnings=notices)
    parts = dict(recorded=recorded, valves=valves, results=results, seps=seps)
    photos = read_figures([c for r in recorded for c in r.channels.values()])
    return LabResult.of(inputs, results, tables=lab_report.tables(**parts),
                        figures=lab_report.figures(**parts) + photos, formulas=lab_report.FORMULAS,
                        references=lab_report.REFERENCES, warnings=notices,
                        conclusion=lab_report.conclusion(**parts))


def _warn(recorded, flat, results, seps) -> None:
    """The named warnings of the records and the sweep."""
    lost = [(r.number, v, results[f"loss_{v}_{r.number}"].value, r.clearance, r.speed.value)
            for r in recorded for v in r.traces if _lost(flat, r.number, v)]
    if lost:
        warnings.warn(lab_report.contact_lost(lost, seps, results))
    poor = []
    for r in recorded:
        for v in r.traces:
            name = f"nu_{v}_{r.number}"
            if name not in results:
                poor.append((r.number, v, None))
            elif results[name].u > NU_POOR * results[name].value:
                poor.append((r.number, v, results[name].u / results[name].value))
    if poor:
        warnings.warn(lab_report.poor_oscillation(poor, NU_POOR))


# ------------------------------------------------------------------------ slips

def _valves_swapped(inputs: Inputs) -> Inputs | None:
    """The inlet's trace read for the exhaust's and the reverse (each valve's channel
    swapped), with each valve's own calibration and preload."""
    entries = inputs["valve"]
    if len(entries) != 2:
        return None
    channels = [e.get("channel", e["name"]) for e in entries]
    swapped = [{**e, "channel": c} for e, c in zip(entries, channels[::-1])]
    return replace(inputs, sections={**inputs.sections, "valve": swapped})


PER_VALVE = r"(P_max|P_min|nu|phi|phi_crank|advance|lag|loss)_(in|ex)_\d+"
"""Every result read off a valve's trace."""

SLIPS = [
    ("valves_swapped",
     bi("the inlet's and the exhaust's traces confused: each valve's forces, timing and "
        "durations read off the other's trace",
        "перепутаны записи впускного и выпускного клапанов: силы, фазы и продолжительности "
        "каждого клапана прочитаны по записи другого"),
     (PER_VALVE, r"n_sep_(in|ex)_\d+"), _valves_swapped),
    ("camshaft_turn_as_crank_turn",
     bi("the camshaft's revolution T_cam taken as one crankshaft revolution (the TDC marks' "
        "spacing): φ = 360 T_open/T_cam doubled",
        "за оборот распределительного вала T_р.в взят оборот коленчатого (промежуток между "
        "отметками ВМТ): φ = 360 T_откр/T_р.в вдвое больше"), (r"phi_(in|ex)_\d+",), 2.0),
    ("cam_angle_for_crank_angle",
     bi("the opening's camshaft angle reported for its crank angle (half of it)",
        "угол открытия по распределительному валу указан вместо угла по коленчатому "
        "(вдвое меньше)"), (r"phi_crank_(in|ex)_\d+",), 0.5),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the inputs as the slip leaves them, or the factor a slip of the arithmetic puts on them."""


# ------------------------------------------------------------------------ synthetic files

SYNTH_FORMATS = ("csv", "h5")

PHOTO_EXTREME = 1.25
"""Limit of error of P_max and P_min read off a photographed oscillogram, in stroke widths
(:attr:`processing.vision.record.PaperRecord.stroke`, in the trace's unit): the drive's
oscillation turns sharper than the stroke is wide, and even read at the stroke's outer
edge its crests come out up to 1.2 widths inside (``dynlab synth lab6 --image``, seeds
1–3: 180 extremes, strokes 0.44 mm at 25 N/mm)."""

PHOTO_MARKS = 5e-3
"""Period of the time marks on the photographed oscillograms. [s]"""

PHOTO_SCALE = 25.0
"""The gauges' gain on the photographed oscillograms: 1500 N per 60 mm of paper, so that the
largest force of the scene (900 N) stays within 36 mm. [N/mm]"""

PHOTO_SIZE = (4000, 2000)
"""The photographs' size: a 12-megapixel phone's width, so that the drive's oscillation
(450 Hz) spans 20 px or more at 500 min⁻¹. [px]"""

PHOTO_ZEROS = {"in": 0.062, "ex": 0.016}
"""Each valve's zero above the paper's lower edge on the photographs (the intake's trace on
top). [m]"""

SPEEDS = (500.0, 1000.0, 1500.0, 1800.0, 2000.0)
"""The manual's speeds. [min⁻¹]"""

CLEARANCES = (0.3e-3, 0.5e-3, 0.8e-3)
"""The manual's valve clearances. [m]"""


def write_synthetic(out_dir, seed: int = 0, *, fmt: str = "csv", speeds=SPEEDS,
                    clearances=CLEARANCES, valves=VALVES, snr_db: float | None = None,
                    sample_rate: float = 10e3, revolutions: float = 4.4,
                    bend: float = 0.0, image: bool = False, shot=None,
                    part: int | None = None, draw=None) -> dict[str, Path]:
    """Write a synthetic lab 6 measurement: the calibrations, a record per speed and
    clearance, the measurement file and the answer key.

    The scene of :mod:`processing.synth.valve_drive`: seed 0 has the default cam (9 mm
    harmonic main event over 110° of the cam with 0.25 mm ramps) and drive (M = 0.25 kg,
    c = 2 kN/mm, c_n = 30 N/mm, P₀ = 260 N, ζ = 0.06: ν ≈ 453 Hz; at 0.8 mm the drive
    separates near 1630 min⁻¹), any other seed a cam and drive of its own (:func:`_part`);
    each valve's gauge at 1500 N per 90 mm of trace with 0.2 mm of noise and a 4 mm zero,
    TDC marks every revolution, time marks every 2 ms; a calibration of six loads read to
    ± 0.2 mm.

    Parameters
    ----------
    out_dir : str or Path
        Folder to write into (created).
    seed : int
        Seed of the start angles, noise and calibration readings (and of the part, unless
        ``part`` is given).
    fmt : {"csv", "h5"}
        Record format.
    speeds : sequence of float
        [min⁻¹]
    clearances : sequence of float
        [m]
    valves : sequence of {"in", "ex"}
    snr_db : float, optional
        The trace's noise as the ratio of 1500 N of trace to its σ (default: 0.2 mm). [dB]
    sample_rate : float
        [Hz]
    revolutions : float
        Length of each record in crankshaft revolutions (two camshaft revolutions hold at
        least one whole event).
    bend : float
        The calibration's parabolic bend at its top load, a share of its deflection.
    image : bool
        Write each record as a phone photograph of its paper oscillogram (``rNN.jpg``,
        :func:`processing.synth.paper_record.photograph`: the whole record over 250 mm, the
        intake's trace above the exhaust's, time marks every :data:`PHOTO_MARKS`, a TDC mark
        every revolution) at :data:`PHOTO_SCALE`, with an ``[image]`` table; the calibration's
        deflections in mm of paper.
    shot : processing.synth.paper_record.Shot, optional
        The camera of the photographs (default: the phone's, :data:`PHOTO_SIZE`).
    part : int, optional
        Seed of the part: the cam's lift and the drive (default ``seed``; 0: the scene's
        defaults, whatever ``seed`` draws the readings).
    draw : callable, optional
        With ``image``: who draws each record's paper instead of the phone's photograph
        (:func:`labs.bench.foreign_records.paper` protocol: ``draw(stem, signals, *, duration,
        gain, zeros, mark_period, tdc_times, seed) -> Path``).

    Returns
    -------
    dict
        Paths written: ``toml``, ``answer``, and one per record (``r1``, ``r2``, …).
    """
    from processing.inputs.signals import write_csv, write_hdf5
    from processing.synth.valve_drive import (RPM, Gauge, calibration, record,
                                              separation_speed as true_separation,
                                              simulate_event)

    if fmt not in SYNTH_FORMATS:
        raise InputError(f"unknown record format {fmt!r}",
                         f"use one of {', '.join(SYNTH_FORMATS)}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cam, drive = _part(seed if part is None else part)
    noise = 0.2 if snr_db is None else 90.0 / 10 ** (snr_db / 20)
    gauge = Gauge(noise=noise, sample_rate=sample_rate)
    if image:       # the beam draws the force itself; the photograph adds its own noise
        gauge = Gauge(scale=PHOTO_SCALE, offset=0.0, noise=0.0, sample_rate=sample_rate,
                      mark_period=PHOTO_MARKS)
    rng = np.random.default_rng([seed, 6])
    loads = np.arange(0.0, 1501.0, 300.0)
    truth, bodies, written = {}, [], {}
    valve_text = []
    for j, v in enumerate(valves):
        a = calibration(gauge, loads, bend=bend, seed=seed * 10 + j)
        truth[f"k_{v}"] = gauge.scale
        channel = f"channel = {valves.index(v)}\n" if image else ""
        valve_text.append(
            f'[[valve]]\nname = "{v}"\n{channel}P0 = "{drive.P0:g} ± 10 N"\n'
            f'load = [{", ".join(f"{x:g}" for x in loads)}]\n'
            f'deflection = [{", ".join(f"{x:g}" for x in a)}]\n')
    number = 0
    for c in clearances:
        lost_speeds = []
        for n in speeds:
            number += 1
            events = {v: simulate_event(cam, drive, c, n * RPM / 2) for v in valves}
            rec = record(cam, drive, gauge, c, n * RPM, valves=valves, revolutions=revolutions,
                         seed=seed * 1000 + number, events=events)
            if image and draw is not None:
                name, rate, marks = _drawn(draw, out / f"r{number:02d}", rec, valves,
                                           seed * 1000 + number), "", ""
            elif image:
                name, rate, marks = f"r{number:02d}.jpg", "", ""
                _photograph(rec, valves, seed * 1000 + number, shot).write(out / name)
            else:
                name, marks = f"r{number:02d}.{fmt}", 'marks_channel = "marks"\n'
                columns = {v: np.round(rec.channels[v], 2) for v in valves}
                columns.update(tdc=np.round(rec.channels["tdc"], 2),
                               marks=np.round(rec.channels["marks"], 2))
                if fmt == "csv":
                    write_csv(out / name, columns)
                    rate = f'sample_rate = "{sample_rate / 1e3:g} kHz"\n'
                else:
                    write_hdf5(out / name, columns, sample_rate)
                    rate = ""
            written[f"r{number}"] = out / name
            n_tach = round(n + rng.normal(0, 4))
            bodies.append(f'[[record]]\nsignal = "{name}"\n{rate}clearance = "{1e3 * c:g} '
                          f'mm"\nn = "{n_tach} ± 10 rpm"\n{marks}')
            truth[f"n_{number}"] = n * RPM
            for v in valves:
                ev, timing = rec.events[v], rec.timing[v]
                truth.update({f"P_max_{v}_{number}": ev.P_max, f"P_min_{v}_{number}": ev.P_min,
                              f"phi_{v}_{number}": ev.closing - ev.opening,
                              f"phi_crank_{v}_{number}": 2 * (ev.closing - ev.opening),
                              f"advance_{v}_{number}": timing["advance"],
                              f"lag_{v}_{number}": timing["lag"],
                              f"loss_{v}_{number}": ev.loss,
                              f"nu_{v}_{number}": drive.damped_frequency})
            if events[valves[0]].loss > 0:
                lost_speeds.append(n)
        if lost_speeds:
            low = max([s for s in speeds if s < lost_speeds[0]], default=speeds[0])
            n_sep = true_separation(cam, drive, c, low * RPM, lost_speeds[0] * RPM)
            for v in valves:
                truth[f"n_sep_{v}_{round(c * 1e6)}"] = n_sep
    toml = (f'lab = "lab6"\n[meta]\nstudent = "synthetic (dynlab synth lab6 --seed {seed})"\n'
            'notes = "generated; the true answers are in answer_key.json"\n\n'
            f'[engine]\nstrokes = 4\nmark_period = "{1e3 * gauge.mark_period:g} ms"\n\n'
            + "\n".join(valve_text) + "\n" + "\n".join(bodies)
            + (f'\n[image]\nmark_period = "{1e3 * PHOTO_MARKS:g} ms"\npaper_width = "120 mm"\n'
               if image else ""))
    written["toml"] = out / f"lab6_seed{seed}.toml"
    written["toml"].write_text(toml, encoding="utf-8")
    written["answer"] = out / "answer_key.json"
    written["answer"].write_text(json.dumps({"seed": seed, "results": truth}, indent=1),
                                 encoding="utf-8")
    return written


def _drawn(draw, stem: Path, rec, valves, seed: int) -> str:
    """A record's paper drawn by ``draw`` (as :func:`_photograph` lays it out): the file's
    name."""
    t = rec.time
    return draw(stem, [lambda x, v=v: np.interp(x, t, rec.channels[v]) for v in valves],
                duration=float(t[-1]), gain=1e-3, zeros=[PHOTO_ZEROS[v] for v in valves],
                mark_period=PHOTO_MARKS, tdc_times=_marks(rec.channels["tdc"], 1.0 / (t[1] - t[0])),
                seed=seed).name


def _photograph(rec, valves, seed: int, shot=None):
    """A photograph of a record's paper oscillogram (``shot``, default the phone's): the
    valves' traces in mm of paper (the record's trace unit), its TDC marks and time marks."""
    from processing.synth.paper_record import PHONE, photograph

    t = rec.time
    tdc_times = _marks(rec.channels["tdc"], 1.0 / (t[1] - t[0]))
    return photograph([lambda x, v=v: np.interp(x, t, rec.channels[v]) for v in valves],
                      float(t[-1]), 1e-3, mark_period=PHOTO_MARKS, tdc_times=tdc_times,
                      zero=[PHOTO_ZEROS[v] for v in valves], seed=seed,
                      shot=replace(PHONE, size=PHOTO_SIZE) if shot is None else shot)


DRIVES = {"M": (0.21, 0.28), "c": (1.7e6, 2.4e6), "c_n": (30e3, 45e3), "P0": (240.0, 290.0),
          "lift": (8.5e-3, 9.5e-3)}
"""Ranges a variant's valve drive is drawn from: the reduced mass, the drive's stiffness at
the valve and the springs' stiffness and preload over lab 5's scene and its variants (M =
0.237 kg, c = 2.055 kN/mm, c_n = 45 N/mm, P₀ = 250 N there; :data:`labs.lab5_valve_stiffness
.VALVE_TRAINS`) and this scene's (0.25 kg, 2 kN/mm, 30 N/mm, 260 N); the cam's lift at the
valve within ± 0.5 mm of the scene's 9 mm (:func:`_part` keeps those whose separation
falls where the manual's records find it: seeds 1–30 draw ν of 414–512 Hz, separating at
0.8 mm between 1600 and 1955 min⁻¹). [kg], [N/m], [N/m], [N], [m]"""

KEPT_MARGIN = 15.0
"""The least P_min a variant's record keeps where it keeps contact: 4.5 σ of the trace's
noise (0.2 mm at 1500 N per 90 mm), so that a kept record is not read as lost (the scene's
closest, 1500 min⁻¹ at 0.8 mm, keeps 18.9 N). [N]"""

LOSS_MARGIN = math.radians(1.0)
"""The least loss of contact a variant's record shows where it loses contact: two samples
of 10 kHz at 1800 min⁻¹, so that a lost record is not read as kept (the scene's least,
1800 min⁻¹ at 0.8 mm, 1.6°). [rad of the cam]"""

KEPT_UP_TO = 1500.0
"""A variant's drive keeps contact at every clearance up to this speed, as the scene's: its
separation then falls between 1500 and 2000 min⁻¹, where the manual's records are 200–300
min⁻¹ apart and the line through the last two kept ones finds it within its interval (a
drive separating between 1000 and 1500 min⁻¹ is found 6 % low). [min⁻¹]"""


def _part(seed: int):
    """A variant's cam and drive (:data:`DRIVES`); seed 0 the scene's (ν = 453 Hz, the
    drive separating near 1630 min⁻¹ at 0.8 mm).

    A drive is drawn until it separates within the manual's speeds at its largest clearance
    (at 2000 min⁻¹ and 0.8 mm), keeps contact up to :data:`KEPT_UP_TO`, and no record of the
    manual's speeds and clearances sits at the edge of a separation (each either keeps
    :data:`KEPT_MARGIN` or loses :data:`LOSS_MARGIN`): every variant has a separation to
    find, between records the lab tells apart. The events are
    :func:`processing.synth.valve_drive.simulate_event`'s, which the records then reuse.

    Returns
    -------
    tuple
        (:class:`~processing.synth.valve_drive.Cam`, :class:`~processing.synth.valve_drive.Drive`)
    """
    from processing.synth.valve_drive import RPM, Cam, Drive, simulate_event

    if seed == 0:
        return Cam(), Drive()

    def lost(n, event):
        return n > KEPT_UP_TO and event.loss >= LOSS_MARGIN

    rng = np.random.default_rng([seed, 62])
    records = [(lash, n) for lash in sorted(CLEARANCES, reverse=True)
               for n in sorted(SPEEDS, reverse=True)]
    while True:
        M, c, c_n, P0, lift = (float(rng.uniform(*DRIVES[k]))
                               for k in ("M", "c", "c_n", "P0", "lift"))
        cam, drive = Cam(lift=lift), Drive(M=M, c=c, c_n=c_n, P0=P0)
        events = ((n, simulate_event(cam, drive, lash, n * RPM / 2)) for lash, n in records)
        if lost(*next(events)) and all(e.P_min >= KEPT_MARGIN or lost(n, e)
                                       for n, e in events):
            return cam, drive
