"""Lab 9. Internal-friction (rubber) torsional dampers: static loops and the free decay.

The manual's chapter: the damper's inertia ring is loaded on a rig with a pure torque M in
steps, both directions, and its twist φ read by a dial gauge on a lever, loading then
unloading, repeated (Table 1). The loop M–φ gives the mean stiffness C = M/φ, the energy at
the largest twist E_max = M_max φ_max/2 (formula 7), the energy lost per cycle E_n (the
loop's area, formula 8) and the relative damping coefficient ξ′_d = E_n/E_max. Released
suddenly, the ring rings down; its record gives the logarithmic decrement
δ = ln(φ_n/φ_{n+1}) (10), the damped frequency ω_d = 2π/T (14), the damping coefficient
ξ_d = I ω_d δ/π (12) and the dynamic stiffness C_d = I ω_d² [1 + (δ/2π)²] (13). The manual's
six dampers (Table 2) have C_d about twice C: the equivalent torsional system must be built
with the dynamic stiffness.

Here each run's loop is a closed polygon of the readings; the stiffness is also taken as the slope
of a straight line through the loading branch; the runs' means carry their type A scatter. The decay
is reduced from a recording (a least-squares damped sinusoid over the whole trace, with a line
through the peaks as a check: :func:`processing.oscillations.decay.analyse_decay`) or from the peak
amplitudes a student read off a paper record with the period; whether δ changes along the record
(rubber's damping depends on the amplitude) is tested and said.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 9 ("Экспериментальное исследование демпферов внутреннего трения").
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from processing.oscillations.decay import DecrementFit, RecordedDecay, analyse_decay, log_decrement
from processing.diagnostics import (InputError, collect_notices)
from processing.oscillations.load_cycle import out_of_order
from processing.oscillations.loops import branch_work, loop_area
from processing.measurement import (SAMPLE_RATE, Field, Inputs, LabSpec, Section, bi,
                                    image_section)
from processing.inputs.record_quality import (SENSOR_FIX, check_frequency, check_record,
                                       clipped_mask)
from processing.regression import LineFit, calibration_fault, fit_line
from processing.result import LabResult, compare, flag_estimates, result_values
from processing.inputs.signals import image_options, is_image, open_channel, read_figures
from processing.uncertainty import Measured, propagate

from . import lab9_damper_report as report

RUBBER_RATIO = {"natural": (1.1, 1.4), "synthetic": (1.5, 2.0)}
"""C_d/C of rubber (the manual): lightly filled natural rubber, heavily filled synthetic."""

RATIO_RANGE = (1.0, 3.0)
"""C_d/C outside which the stiffnesses are suspect: rubber is never softer dynamically, and
the manual's dampers stay below 2.2."""

RESIDUAL_TWIST = 0.15
"""Twist left at zero load, as a share of the largest, above which a loop is called unclosed
(the manual's second run leaves 7 %)."""

WIDE_LOOP = 0.5
"""ξ′ of one loop above which it is called too wide: the manual's damper gives 0.21–0.25 in
one direction (0.43–0.54 for a full cycle in both, Table 2)."""

DRIFT_CORRELATION = 0.3
"""Lag-one correlation of the trace fit's residuals above which the baseline is suspect."""

DIRECTIONS = {"forward": 1.0, "reverse": -1.0}

WHOLE_DECAY_RU = ("запишите затухание целиком: от момента до отпускания, пока колебания не "
                  "утонут в шуме")
"""The fix of a decay recorded too short, in Russian."""

DECAY_CLIPPED = (
    "the fit leaves them out and reads the decrement from the rest of the record, with the "
    "uncertainty of what is left",
    "подбор их не учитывает и определяет декремент по остальной записи, с неопределённостью "
    "по оставшемуся")
"""What a clipped decay record's warning says the reduction did (English, Russian)."""

PHOTO_FIX = {"en": "photograph the paper record again, sharp and whole, with its trace and "
                   "time marks in the frame",
             "ru": "сфотографируйте бумажную запись заново, резко и целиком, с линией записи и "
                   "отметками времени в кадре"}
"""What to do about a flat or noise-only trace read off a photograph."""

SPEC = LabSpec(
    id="lab9", number="9",
    title=bi("Internal-friction (rubber) torsional dampers",
             "Экспериментальное исследование демпферов внутреннего трения"),
    goal=bi("To study the experimental methods for torsional dampers of crankshafts: the static "
            "stiffness and hysteresis loop of a damper's rubber layer, and its dynamic stiffness "
            "and damping from the free decay of the damper's ring.",
            "Изучить методы экспериментального исследования крутильных колебаний демпферов "
            "коленчатых валов ДВС: статическую жёсткость и петлю гистерезиса резинового слоя, "
            "динамическую жёсткость и демпфирование по свободным колебаниям маховика демпфера."),
    sections=(
        Section("damper", bi("The damper", "Демпфер"), fields=(
            Field("rubber", bi("rubber of the layer (for the typical C_d/C)",
                               "резина слоя (для типичного C_d/C)"), kind="choice",
                  choices={"natural": bi("natural", "натуральная"),
                           "synthetic": bi("synthetic", "синтетическая")}, required=False),
        )),
        Section("run", bi("Static loop: one run of loading and unloading (Table 1)",
                          "Статическая петля: один опыт нагружения и разгружения (табл. 1)"),
                many=True,
                help=report.RUN_HELP,
                fields=(
                    Field("direction", bi("direction of the twist", "направление закрутки"),
                          kind="choice", default="forward",
                          choices={"forward": bi("forward", "прямое"),
                                   "reverse": bi("reverse", "обратное")}),
                    Field("M", bi("moment, in the order applied", "момент в порядке нагружения"),
                          unit="N*m", limit="0.5 N*m", allow_zero=True, symbol="M",
                          example="[90, 180, 270, 315, 270, 180, 90, 0]", series=True,
                          plausible=("0.1 N*m", "10000 N*m")),
                    Field("phi", bi("twist, read with each moment",
                                    "угол закрутки при каждом моменте"),
                          unit="mrad", limit="0.01 mrad", allow_zero=True, symbol="φ",
                          example="[2.69, 6.15, 9.91, 12.12, 10.89, 7.90, 4.58, 0.09]",
                          series=True, plausible=("0.005 mrad", "1000 mrad")),
                )),
        Section("decay", bi("Free decay after a sudden release", "Свободные затухающие колебания"),
                help=report.DECAY_HELP,
                fields=(
                    Field("I", bi("moment of inertia of the damper's ring",
                                  "момент инерции маховика демпфера"), unit="kg*m^2", symbol="I",
                          example="0.030 ± 0.0003 kg*m^2",
                          plausible=("1e-3 kg*m^2", "10 kg*m^2")),
                    Field("signal", bi("record of the decay: CSV, WAV or HDF5 file, or a "
                                       "photograph or scan of the paper record ([image])",
                                       "запись колебаний: файл CSV, WAV или HDF5 или снимок "
                                       "бумажной записи ([image])"),
                          kind="file", required=False, example="decay.csv"),
                    Field("channel", bi("channel of the record", "канал записи"), kind="text",
                          required=False),
                    Field("sample_rate", bi("sample rate, if the file does not say",
                                            "частота дискретизации, если её нет в файле"),
                          **SAMPLE_RATE, required=False, symbol="f_s"),
                    Field("peaks", bi("or: successive amplitudes read off the record, one per "
                                      "period", "или: последовательные амплитуды по "
                                      "осциллограмме, по одной за период"),
                          unit="mm", limit="0.25 mm", required=False, symbol="φ_n",
                          series=True, plausible=("0.1 mm", "500 mm")),
                    Field("T", bi("period of the oscillation", "период колебаний"), unit="ms",
                          limit="0.05 ms", required=False, symbol="T",
                          plausible=("0.5 ms", "1000 ms")),
                    Field("t_N", bi("or: time of N periods", "или: время N периодов"),
                          unit="ms", limit="0.1 ms", required=False, symbol="t_N",
                          plausible=("1 ms", "60000 ms")),
                    Field("N", bi("periods timed", "число периодов"), kind="count",
                          required=False, symbol="N"),
                    Field("cal_phi", bi("calibration: twists set on the static rig",
                                        "тарировка: углы, заданные на статическом стенде"),
                          unit="mrad", limit="0.01 mrad", allow_zero=True, required=False,
                          symbol="φ_k", example="[0, 3, 6, 9]", series=True,
                          plausible=("0.01 mrad", "1000 mrad")),
                    Field("cal_reading", bi("calibration: the record's deflection at each "
                                            "twist (its unit: V, or mm on paper)",
                                            "тарировка: отклонение записи при каждом угле (в "
                                            "её единицах: В или мм на бумаге)"),
                          unit="", allow_zero=True, required=False, symbol="u_k",
                          example="[0, 0.301, 0.598, 0.902]", series=True,
                          plausible=("1e-6", "1e6")),
                )),
        image_section(),
    ),
)


# ------------------------------------------------------------------------ formulas

def secant_stiffness(M_max, phi_max):
    """Mean (secant) stiffness of the rubber layer at the largest moment (manual, lab 9).

    .. math:: C = \\frac{M_{max}}{\\varphi_{max}}

    Parameters
    ----------
    M_max : float or ndarray
        Largest moment of the run. [N·m]
    phi_max : float or ndarray
        Twist read at it. [rad]

    Returns
    -------
    float or ndarray
        [N·m/rad]

    Examples
    --------
    >>> round(secant_stiffness(315.0, 12.12e-3))      # Table 1, first run
    25990
    """
    return M_max / phi_max


def energy_at_max(M_max, phi_max):
    """Energy stored at the largest twist, the triangle OAB (formula 7).

    .. math:: E_{max} = \\frac{M_{max}\\varphi_{max}}{2}

    Returns
    -------
    float or ndarray
        [J]

    Examples
    --------
    >>> round(energy_at_max(315.0, 12.12e-3), 4)
    1.9089
    """
    return 0.5 * M_max * phi_max


def relative_damping(E_loss, E_max):
    """Relative damping coefficient of the layer, ξ′_d = E_n/E_max = S_n/S (manual, lab 9)."""
    return E_loss / E_max


def damping_coefficient(I, omega_d, delta):
    """Damping coefficient of the rubber layer from the decay (formula 12).

    .. math:: \\xi_d = \\frac{I\\,\\omega_d\\,\\delta}{\\pi}

    Parameters
    ----------
    I : float or ndarray
        Moment of inertia of the ring. [kg·m²]
    omega_d : float or ndarray
        Damped angular frequency. [rad/s]
    delta : float or ndarray
        Logarithmic decrement. [1]

    Returns
    -------
    float or ndarray
        [N·m·s]
    """
    return I * omega_d * delta / np.pi


def dynamic_stiffness(I, omega_d, delta):
    """Dynamic stiffness of the rubber layer from the free decay (formula 13).

    .. math:: C_d = I\\,\\omega_d^2\\left[1 + \\left(\\frac{\\delta}{2\\pi}\\right)^2\\right]

    Exact for a viscously damped oscillator: with ζ = δ/√(4π² + δ²),
    ω_d² (1 + ζ²/(1 − ζ²)) = ω_n² = C_d/I.

    Examples
    --------
    >>> I, wn, zeta = 0.03, 1200.0, 0.1
    >>> wd, d = wn * np.sqrt(1 - zeta**2), 2 * np.pi * zeta / np.sqrt(1 - zeta**2)
    >>> round(float(dynamic_stiffness(I, wd, d) / (I * wn**2)), 12)
    1.0
    """
    return I * omega_d**2 * (1.0 + (delta / (2 * np.pi)) ** 2)


# ------------------------------------------------------------------------ static runs

@dataclass(frozen=True)
class Run:
    """One static run: its readings as a closed path (magnitudes, from (0, 0) on) and its
    loading branch's fit."""

    number: int
    direction: str
    M: np.ndarray
    phi: np.ndarray
    origin: bool
    """Whether (0, 0) was added before the readings (the gauge's zero at no load)."""
    top: int
    fit: LineFit

    @property
    def sign(self) -> float:
        return DIRECTIONS[self.direction]

    @property
    def residual_twist(self) -> float:
        """Twist left at zero load, as a share of the largest. [1]"""
        return float(self.phi[-1] / self.phi[self.top])


def _run(inputs: Inputs, k: int, entry: dict) -> Run:
    where = f"run[{k}]"
    M = np.asarray(entry["M"].readings, dtype=float)
    phi = np.asarray(entry["phi"].readings, dtype=float)
    if M.size != phi.size:
        raise inputs.error(f"{M.size} moments but {phi.size} twists",
                           "write one twist for every moment, in the same order", f"{where}.phi")
    top, i = out_of_order(M)
    if i is not None:
        raise inputs.error(f"the loads are out of order: reading {i + 1} ({M[i]:g} N·m) after "
                           f"{M[i - 1]:g} N·m", "write the moments in the order they were "
                           "applied: rising to the largest, then falling to zero (the top "
                           "point once, or twice if re-read)", f"{where}.M")
    if np.count_nonzero(M[:top + 1] > 0) < 2:
        raise inputs.error("the loading branch has fewer than two readings above zero load",
                           "load in at least two steps (the manual uses four)", f"{where}.M")
    if top == M.size - 1 or M[-1] != 0.0:
        raise inputs.error(f"the loop is not closed: the readings end at {M[-1]:g} N·m, "
                           "not at zero load", "unload down to zero and read the twist there "
                           "(the last moment must be 0)", f"{where}.M")
    if not phi[top] > 0:
        raise inputs.error("the twist at the largest moment is zero",
                           "check the gauge readings (rad·10⁻³)", f"{where}.phi")
    origin = bool(M[0] > 0)
    if origin:
        M, phi, top = np.concatenate([[0.0], M]), np.concatenate([[0.0], phi]), top + 1
    fit = fit_line(M[:top + 1], phi[:top + 1])
    if not fit.slope > 0:
        raise inputs.error("the twist does not grow with the moment on the loading branch",
                           "check the pairing of the moments and the gauge readings",
                           f"{where}.phi")
    return Run(k + 1, entry["direction"], M, phi, origin, top, fit)


def _run_inputs(inputs: Inputs, runs: list[Run]) -> dict:
    """Every reading as its own measured input (the instrument's limit), and each run's
    loading-branch compliance from its fit (type A, ν = n − 2)."""
    flat = {}
    for run, entry in zip(runs, inputs["run"]):
        m, p = entry["M"], entry["phi"]
        first = 1 if run.origin else 0
        for j in range(first, run.M.size):
            flat[f"r{run.number}.M{j}"] = Measured(run.M[j], limit=m.limit, u_b=m.u_b)
            flat[f"r{run.number}.phi{j}"] = Measured(run.phi[j], limit=p.limit, u_b=p.u_b)
        if run.origin:
            flat[f"r{run.number}.M0"] = flat[f"r{run.number}.phi0"] = 0.0
        flat[f"r{run.number}.compliance"] = run.fit.measured_slope()
    return flat


def _run_model(runs: list[Run]):
    def model(**x):
        out = {}
        for run in runs:
            k, n = run.number, run.M.size
            M = np.stack(np.broadcast_arrays(*[x[f"r{k}.M{j}"] for j in range(n)]), axis=-1)
            phi = np.stack(np.broadcast_arrays(*[x[f"r{k}.phi{j}"] for j in range(n)]), axis=-1)
            M_max, phi_max = M[..., run.top], phi[..., run.top]
            out[f"C_static_{k}"] = secant_stiffness(M_max, phi_max)
            out[f"C_static_fit_{k}"] = 1.0 / x[f"r{k}.compliance"]
            out[f"E_max_{k}"] = energy_at_max(M_max, phi_max)
            out[f"E_loss_{k}"] = loop_area(phi, M)
            out[f"xi_static_{k}"] = relative_damping(out[f"E_loss_{k}"], out[f"E_max_{k}"])
        return out

    return model


def _check_runs(runs: list[Run], stage) -> None:
    for run in runs:
        k = run.number
        if branch_work(run.phi, run.M) < 0:
            warnings.warn(report.inverted_loop(k))
        if run.residual_twist > RESIDUAL_TWIST:
            warnings.warn(report.unclosed_loop(k, run.residual_twist))
        if (xi := stage[f"xi_static_{k}"].value) > WIDE_LOOP:
            warnings.warn(report.wide_loop(k, xi, WIDE_LOOP))
    if len(runs) == 1:
        warnings.warn(report.single_run())


def _means(runs: list[Run], prop) -> dict:
    """Each static quantity over the runs: type A from their scatter (Student t, ν = runs − 1)
    and, as type B, their own propagated u (the readings' limits), √Σu²/runs: with two runs
    the scatter alone may come out near zero."""
    out = {}
    for q in report.STATIC:
        values = [prop[f"{q}_{r.number}"] for r in runs]
        u_b = float(np.sqrt(sum(v.u**2 for v in values))) / len(values)
        if len(values) > 1:
            out[q] = Measured.from_readings([v.value for v in values], u_b=u_b)
        else:
            out[q] = Measured(values[0].value, values[0].u, values[0].dof)
    return out


# ------------------------------------------------------------------------ the free decay

@dataclass(frozen=True)
class Decay:
    """What the free decay reduces to: δ and T as measured inputs, and how they were found."""

    delta: Measured
    period: Measured
    peaks: DecrementFit | None
    """The line through ln φ_n: of the readings, or of a record's half ranges."""
    record: RecordedDecay | None = None
    time: np.ndarray | None = None
    signal: np.ndarray | None = None
    scale: Measured | None = None
    """μ_φ from the calibration: twist per unit of the record (per mm of a paper record, as
    the readings were written) [rad/unit]."""
    channel: object = None
    """The record's channel (a paper record read off an image carries its overlay)."""

    @property
    def from_record(self) -> bool:
        return self.record is not None


def _decay(inputs: Inputs) -> Decay:
    d = inputs["decay"]
    has_record, has_peaks = "signal" in d, "peaks" in d
    if has_record == has_peaks:
        raise inputs.error("give the decay either as a record or as peak amplitudes"
                           + (", not both" if has_record else ""),
                           "write signal = \"decay.csv\", or peaks = [...] with T (or t_N and N)",
                           "decay.signal" if has_record else "decay.peaks")
    if has_record and any(k in d for k in ("T", "t_N", "N")):
        raise inputs.error("a record and paper readings are both given",
                           "the record gives the period itself: delete T, t_N, N", "decay.T")
    if "T" in d and "t_N" in d:
        raise inputs.error("both T and t_N are given", "give one of them", "decay.t_N")
    if ("t_N" in d) != ("N" in d):
        raise inputs.error("t_N needs N, the periods it spans", "write both t_N and N",
                           "decay.N" if "t_N" in d else "decay.t_N")
    scale = _scale(inputs)
    return _record_decay(inputs, scale) if has_record else _paper_decay(inputs, scale)


def _scale(inputs: Inputs) -> Measured | None:
    """μ_φ, the record's twist per unit, by a line through the calibration (type A from its
    residuals, and the gauge's limit through the slope)."""
    d = inputs["decay"]
    if "cal_phi" not in d and "cal_reading" not in d:
        return None
    missing = "cal_reading" if "cal_phi" in d else "cal_phi"
    if missing not in d:
        raise inputs.error("the calibration needs both the twists and the record's readings",
                           f"add {missing} = [...], one value for each twist", f"decay.{missing}",
                           ru=("для тарировки нужны и углы закрутки, и показания записи",
                               f"добавьте {missing} = [...], по значению на каждый угол"))
    phi = np.asarray(d["cal_phi"].readings, dtype=float)
    reading = np.asarray(d["cal_reading"].readings, dtype=float)
    if phi.size != reading.size:
        raise inputs.error(f"{phi.size} calibration twists but {reading.size} readings",
                           "write one reading for every twist", "decay.cal_reading",
                           ru=(f"углов закрутки при тарировке {phi.size}, а показаний "
                               f"{reading.size}", "запишите по показанию на каждый угол"))
    if np.unique(phi).size < 2:
        one = phi.size < 2
        raise inputs.error(f"the calibration has {np.unique(phi).size} distinct "
                           f"{'point' if one else 'twist'}(s); a scale needs a straight line "
                           "through at least two", "read the record at two or more twists, "
                           "e.g. at no load and at the largest twist (better: four steps)",
                           "decay.cal_reading" if one else "decay.cal_phi",
                           ru=(f"различных {'точек' if one else 'углов закрутки'} при тарировке: "
                               f"{np.unique(phi).size}; для масштаба нужна прямая хотя бы через "
                               "две", "снимите запись хотя бы при двух углах закрутки, например "
                               "без нагрузки и при наибольшем угле (лучше: четыре ступени)"))
    fault = calibration_fault(phi, reading, names=("twist", "reading"),
                              resolution=d["cal_reading"].limit)
    if fault is not None:
        raise inputs.error(str(fault), "read the record's deflection again at each twist set, "
                           "each beside its own twist in cal_reading (the channel must be "
                           "the strain gauges', its amplifier on)", "decay.cal_reading",
                           ru=(fault.ru, "снимите отклонение записи заново при каждом угле "
                               "закрутки и запишите его в cal_reading рядом со своим углом "
                               "(канал — тензодатчиков, усилитель включён)"))
    fit = fit_line(reading, phi)
    u_b = d["cal_phi"].u_type_b / np.sqrt(np.sum((reading - reading.mean()) ** 2))
    return fit.measured_slope(u_b=u_b).scaled(float(np.sign(fit.slope)))


def _paper_decay(inputs: Inputs, scale) -> Decay:
    d = inputs["decay"]
    peaks = np.asarray(d["peaks"].readings, dtype=float)
    if peaks.size < 3:
        raise inputs.error(f"{peaks.size} amplitude(s) read; the decrement needs at least three",
                           "read the amplitude of at least three successive periods",
                           "decay.peaks")
    if "T" in d:
        period = d["T"]
    elif "t_N" in d:
        period = d["t_N"].scaled(1.0 / d["N"])
    else:
        raise inputs.error("the period is not given", "add T = \"4.9 ms\", or the time of N "
                           "periods: t_N = \"24.6 ms\" and N = 5", "decay.T")
    fit = log_decrement(peaks)
    if not fit.delta > 0:
        raise inputs.error("the amplitudes do not decrease: this is not a free decay",
                           "write the successive amplitudes from the release on", "decay.peaks")
    u_b = fit.u_from_readings(d["peaks"].u_type_b)
    return Decay(fit.measured(u_b=u_b), period, fit, scale=scale)


def _record_decay(inputs: Inputs, scale) -> Decay:
    d = inputs["decay"]
    path = d["signal"]
    key = d.get("channel")
    rate = d["sample_rate"].value if "sample_rate" in d else None
    channel = open_channel(path, channel=key, sample_rate=rate, field="decay.signal",
                           image=image_options(inputs.sections.get("image")))
    x = channel.read().astype(float) * channel.volts_per_code
    if getattr(channel, "unit", None) == "m":     # a photographed record: mm of paper, as
        x = x * 1e3                               # the calibration's readings are written
    t = np.arange(x.size) / channel.sample_rate

    def refuse(problem: str, fix: str, ru: tuple[str, str]) -> InputError:
        return InputError(f"channel '{channel.name}': {problem}", fix, file=str(path),
                          field="decay.signal", ru=(f"канал '{channel.name}': {ru[0]}", ru[1]))

    if x.size < 64:
        raise refuse(f"the record holds {x.size} samples, too short for a decay",
                     "record the whole decay, from before the release until the swing dies "
                     "into the noise", (f"в записи отсчётов: {x.size}, для затухания это "
                                        "слишком мало", WHOLE_DECAY_RU))
    quality = check_record(x, channel.sample_rate, file=str(path), field="decay.signal",
                           channel=str(channel.name), purpose={"en": "the decrement", "ru": "декремента"}, clip_refused=1.0,
                           fix=PHOTO_FIX if is_image(path) else SENSOR_FIX,
                           clipped_effect=DECAY_CLIPPED)
    clipped = clipped_mask(x) if quality.clipped else None
    try:
        record = analyse_decay(t, x, clipped=clipped)
    except ValueError as exc:
        told = getattr(exc, "ru", None) or f"'{exc}'"
        if clipped is not None:
            raise refuse(f"clipped: {100 * quality.clipped:.1f} % of its samples sit at the "
                         f"recorder's limits, and {exc}", "lower the amplifier's gain or "
                         "raise the recorder's range, and record the decay again",
                         (f"запись срезана: {100 * quality.clipped:.1f} % отсчётов на пределах "
                          f"регистратора, и {told}", "уменьшите усиление усилителя или "
                          "увеличьте диапазон регистратора и запишите затухание заново")) from None
        raise refuse(f"{exc}: the record lasts {quality.duration:.3g} s ({x.size} samples)",
                     "record the whole decay, from before the release until "
                     "the swing dies into the noise (five periods or more); a larger twist "
                     "before the release lifts it out of the noise",
                     (f"{told}: запись длится {quality.duration:.3g} с (отсчётов: {x.size})",
                      WHOLE_DECAY_RU + " (пять периодов или больше); больший закрут перед "
                      "отпусканием поднимет его над шумом")) from None
    except RuntimeError as exc:
        told = getattr(exc, "ru", None) or f"затухание не удалось подобрать (подбор: '{exc}')"
        raise refuse(str(exc), "check that the record holds a free decay after a sudden "
                     "release" + ("; a mirror image of the paper (a front camera's mirror "
                                  "mode) reads backwards in time, the decay growing: flip it "
                                  "left to right" if is_image(path) else ""),
                     (told, "проверьте, что в записи свободное затухание после резкого "
                      "отпускания" + ("; зеркальный снимок ленты (зеркальный режим фронтальной "
                                      "камеры) читается назад во времени, и затухание "
                                      "нарастает: отразите его слева направо"
                                      if is_image(path) else ""))) from None
    check_frequency(record.trace.omega_d / (2 * np.pi), channel.sample_rate, quality.duration,
                    file=str(path), field="decay.signal", what="the decay's frequency ω_d/2π")
    clock = getattr(channel, "time_scale", None)        # a paper record's time base
    return Decay(record.measured_delta(),
                 record.measured_period(clock.u / clock.value if clock is not None else 0.0),
                 record.peaks,
                 record, t, x, scale, channel)


def _check_decay(dec: Decay) -> None:
    fit = dec.peaks
    if not dec.from_record:
        if fit.curvature is not None and fit.curvature.significant() \
                and abs(fit.decrement_change()) >= 0.1:
            ends = fit.decrement_at(fit.cycle[[0, -1]])
            warnings.warn(report.amplitude_dependent(float(ends[0]), float(ends[1]), "peaks"))
        return
    rec, trace = dec.record, dec.record.trace
    if rec.short:
        warnings.warn(report.short_record(rec.visible_periods))
    if rec.trend.significant():
        warnings.warn(report.amplitude_dependent(rec.trend.delta_start, rec.trend.delta_end,
                                                 "record"))
    elif trace.residual_correlation > DRIFT_CORRELATION:
        warnings.warn(report.unfollowed_baseline(trace.residual_correlation))
    drift = np.ptp(trace.baseline_at(trace.start + np.linspace(0.0, trace.span, 50)))
    if drift > trace.amplitude:
        warnings.warn(report.large_drift(drift / trace.amplitude))


# ------------------------------------------------------------------------ reduction

def _decay_model(**x):
    out = {q: x[q] for q in report.STATIC if q in x}
    if "decay.delta" in x:
        delta, T = x["decay.delta"], x["decay.T"]
        omega = 2 * np.pi / T
        out.update(log_decrement=delta, T_d=T, omega_d=omega,
                   xi_dynamic=damping_coefficient(x["decay.I"], omega, delta),
                   C_dynamic=dynamic_stiffness(x["decay.I"], omega, delta))
        for name in ("log_decrement_peaks", "mu_phi"):
            if f"decay.{name}" in x:
                out[name] = x[f"decay.{name}"]
        if "C_static" in x:
            out["C_ratio"] = out["C_dynamic"] / x["C_static"]
    return out


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20039) -> LabResult:
    """Reduce lab 9's static runs and free decay, with uncertainties.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed.

    Returns
    -------
    LabResult
        Per run k: ``C_static_k``, ``C_static_fit_k``, ``E_max_k``, ``E_loss_k``,
        ``xi_static_k``; their means over the runs ``C_static``, ``C_static_fit``, ``E_max``,
        ``E_loss``, ``xi_static``; from the decay ``log_decrement`` (and
        ``log_decrement_peaks`` with at least three peaks), ``T_d``, ``omega_d``,
        ``xi_dynamic``, ``C_dynamic`` and, with a calibration, ``mu_phi``; with both,
        ``C_ratio``.
    """
    if "run" not in inputs and "decay" not in inputs:
        raise inputs.error("neither static runs nor a decay are given",
                           "add [[run]] tables (Table 1) and/or a [decay] table; 'dynlab "
                           "template lab9' shows them", "run")
    with collect_notices() as notices:
        runs = [_run(inputs, k, e) for k, e in enumerate(inputs.sections.get("run", []))]
        flat, results = {}, {}
        if runs:
            stage = propagate(_run_model(runs), _run_inputs(inputs, runs), n_samples=n_samples,
                              seed=seed)
            _check_runs(runs, stage)
            results.update(result_values(stage, report.run_results(r.number for r in runs)))
            flat.update(_means(runs, stage))
        dec = None
        if "decay" in inputs:
            dec = _decay(inputs)
            flat.update({"decay.I": inputs["decay"]["I"], "decay.delta": dec.delta,
                         "decay.T": dec.period})
            if dec.peaks is not None and dec.from_record:
                flat["decay.log_decrement_peaks"] = dec.peaks.measured()
            if dec.scale is not None:
                flat["decay.mu_phi"] = dec.scale
            _check_decay(dec)
        prop = propagate(_decay_model, flat, n_samples=n_samples, seed=seed + 1)
        if "C_ratio" in prop and not RATIO_RANGE[0] <= prop["C_ratio"].value <= RATIO_RANGE[1]:
            warnings.warn(report.stiffness_ratio(prop["C_ratio"].value, RATIO_RANGE))
        results.update(result_values(prop, report.RESULTS))
        comparisons = compare(prop, [("C_static_fit", "C_static"),
                                     ("log_decrement_peaks", "log_decrement")])
        # not flagged: the stiffnesses differ by definition where the loading branch bends,
        # and the line through a few peaks (ν = 1–3) needs more than k = 2
        flag_estimates(results, [])
    kind = inputs.sections.get("damper", {}).get("rubber")
    return LabResult.of(inputs, results, comparisons=comparisons,
                        tables=report.tables(runs, dec, results),
                        measurements=report.measurements(runs),
                        figures=report.figures(runs, dec) + (
                            read_figures([dec.channel]) if dec is not None else []),
                        formulas=report.FORMULAS, references=report.REFERENCES,
                        warnings=notices,
                        conclusion=report.conclusion(runs, dec, results, RUBBER_RATIO, kind))


# ------------------------------------------------------------------------ slips

SLIPS = [
    ("common_logarithm",
     bi("the decrement taken with the common logarithm, δ = lg(φ_n/φ_{n+1}): ln 10 = 2.3 "
        "times too small, and ξ_d = I ω_d δ/π with it",
        "декремент вычислен через десятичный логарифм, δ = lg(φ_n/φ_{n+1}): в ln 10 = 2,3 "
        "раза меньше, и с ним ξ_d = I ω_d δ/π"),
     ("log_decrement", "log_decrement_peaks", "xi_dynamic"), 1 / np.log(10)),
    ("energy_without_half",
     bi("the energy at the largest twist taken as M_max φ_max, the rectangle for the triangle "
        "OAB (½ dropped): E_max doubled and ξ′ = E_n/E_max halved",
        "энергия при наибольшей закрутке взята как M_max φ_max — прямоугольник вместо "
        "треугольника OAB (потерян множитель ½): E_max вдвое больше, ξ′ = E_n/E_max вдвое "
        "меньше"),
     (r"E_max(_\d+)?",), 2.0),
    ("energy_without_half",
     bi("ξ′ = E_n/E_max with E_max taken as M_max φ_max (½ dropped): ξ′ halved",
        "ξ′ = E_n/E_max при E_max = M_max φ_max (потерян множитель ½): ξ′ вдвое меньше"),
     (r"xi_static(_\d+)?",), 0.5),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the factor a slip of the arithmetic puts on them (one slip, ½ dropped from E_max, changes E_max and
ξ′ by different factors: two entries of one name)."""


# ------------------------------------------------------------------------ synthetic files

PHOTO_MARKS = 1e-3
"""Period of the time marks on the photographed decay record. [s]"""


def write_synthetic(out_dir, seed: int = 0, *, snr_db: float = 40.0, periods: float = 8.0,
                    amplitude_exponent: float = 0.0, ratio: float = 1.87, runs: int = 2,
                    sample_rate: float = 20e3, paper: bool = False,
                    image: bool = False, drift=None, draw=None) -> dict[str, Path]:
    """Write a synthetic lab 9 measurement: static runs, a decay record, the answer key.

    The scene of :mod:`processing.synth.damper`: seed 0 is the manual's damper 1, a rubber
    layer of C = 2.6·10⁴ N·m/rad with a lens loop (ξ′ ≈ 0.21) read in 7 steps up to 315 N·m,
    runs alternating forward and reverse, and a ring of I = 0.03 kg·m² on it (C_d =
    ``ratio``·C, δ = 0.89 at the release); any other seed draws a damper of its own
    (:func:`_damper`: C over the manual's six dampers' 2.6…6.9·10⁴ N·m/rad, its ξ′, δ and
    ring, loaded to about 12 mrad). The ring is twisted 10 mrad and released, recorded by
    strain gauges with offset, drift, creep and noise, calibrated at four static twists; or
    (``paper``) four
    maxima read off that record (40 mm at the release) with a ruler and the time of three
    periods; or (``image``) the light-beam oscillograph's paper record of it, photographed
    (35 mm at the release, a time mark every millisecond:
    :func:`processing.synth.paper_record.photograph`).

    Parameters
    ----------
    out_dir : str or Path
        Folder to write into (created).
    seed : int
        Seed of the readings and the noise.
    snr_db, sample_rate : float
        The record's release amplitude (RMS) over its noise [dB], its sample rate [Hz].
    periods : float
        Record length after the release, in periods.
    amplitude_exponent : float
        p in δ(A) = δ₀ (A/φ₀)^p; 0: the damping does not depend on the amplitude.
    ratio : float
        C_d/C.
    runs : int
        Static runs.
    paper : bool
        Write the paper readings instead of the record.
    image : bool
        Write the record as a photograph of the paper (``decay.jpg``) with an ``[image]``
        table instead of a CSV.
    drift : processing.synth.damper.BridgeDrift, optional
        A baseline wander the record carries besides the gauge's offset, drift and creep.
    draw : callable, optional
        With ``image``: who draws the paper record instead of the first family's phone
        (:func:`labs.bench.foreign_records.paper` protocol: ``draw(stem, signals, *, duration,
        gain, zeros, mark_period, tdc_times, seed) -> Path``, the file it wrote).

    Returns
    -------
    dict
        Paths written: ``toml``, ``answer``, and ``record`` (unless ``paper``).

    Notes
    -----
    The answer key's E_loss and ξ′ are those of the polygon through the true loop's points at
    the loads read: the continuous loop encloses 1/(1 − 1/n²) of it (2 % more for 7 steps).
    With p ≠ 0 the key's δ, ξ_d, ω_d belong to the release amplitude, and δ falls along the
    record.
    """
    import json

    from processing.inputs.signals import write_csv
    from processing.synth.damper import (Ring, StrainGauge, calibration,
                                         free_decay, peak_readings, static_runs)
    from processing.synth.paper_record import photograph

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    layer, moment_max, inertia, decrement = _damper(seed, ratio)
    steps = 7
    table = static_runs(layer, moment_max, steps=steps, runs=runs,
                        directions=("forward", "reverse"), seed=seed)
    ring = Ring(inertia=inertia, stiffness=ratio * layer.stiffness, decrement=decrement,
                amplitude_exponent=amplitude_exponent)
    gauge = StrainGauge(sample_rate=sample_rate, snr_db=snr_db)
    rec = free_decay(ring, gauge, periods=periods, seed=seed, drift=drift)
    body = [f'lab = "lab9"\n[meta]\nstudent = "synthetic (dynlab synth lab9 --seed {seed})"\n'
            'notes = "generated; the true answers are in answer_key.json"\n\n'
            '[damper]\nrubber = "synthetic"\n']
    for run in table:
        M = ", ".join(f"{m:g}" for m in run["M"])
        phi = ", ".join(f"{1e3 * p:.2f}" for p in run["phi"])
        body.append(f'[[run]]\ndirection = "{run["direction"]}"\nM = [{M}]\nphi = [{phi}]\n')
    decay = [f'[decay]\nI = "{ring.inertia:g} ± {0.005 * ring.inertia:g} kg*m^2"']
    written = {}
    if paper:
        rng = np.random.default_rng([seed, 93])
        scale = 4e3                                 # mm of trace per rad
        peaks = peak_readings(rec, 4, scale=scale, seed=seed)
        t_N = 3 * rec.truth["T_d"] * 1e3 + rng.uniform(-0.1, 0.1)
        decay += [f"peaks = [{', '.join(f'{p:.1f}' for p in peaks)}]",
                  f't_N = "{t_N:.2f} ms"', "N = 3"]
    elif image:
        scale = 3.5e3                               # mm of trace per rad
        centre = float(np.median(rec.signal))

        def signal(t):
            return np.interp(t, rec.time, rec.signal) - centre

        gain = 1e-3 * scale / gauge.volts_per_rad
        if draw is None:
            written["record"] = photograph(signal, float(rec.time[-1]), gain,
                                           mark_period=PHOTO_MARKS, seed=seed).write(
                out / "decay.jpg")
        else:
            written["record"] = draw(out / "decay", [signal], duration=float(rec.time[-1]),
                                      gain=gain, zeros=[0.06], mark_period=PHOTO_MARKS,
                                      tdc_times=(), seed=seed)
        decay.append(f'signal = "{written["record"].name}"')
    else:
        scale = gauge.volts_per_rad
        written["record"] = out / "decay.csv"
        write_csv(written["record"], {"u": np.round(rec.signal, 4)}, gauge.sample_rate)
        decay.append('signal = "decay.csv"')
    cal_phi, cal_reading = calibration(scale, seed=seed)
    decay += [f"cal_phi = [{', '.join(f'{1e3 * p:.2f}' for p in cal_phi)}]",
              f"cal_reading = [{', '.join(f'{r:.4g}' for r in cal_reading)}]"]
    body.append("\n".join(decay) + "\n")
    if image:
        body.append(f'[image]\nmark_period = "{1e3 * PHOTO_MARKS:g} ms"\n'
                    'paper_width = "120 mm"\n')
    written["toml"] = out / f"lab9_seed{seed}.toml"
    written["toml"].write_text("\n".join(body), encoding="utf-8")
    truth = {"C_static": layer.stiffness, **layer.energies(moment_max, steps), **rec.truth,
             "C_ratio": ratio, "mu_phi": 1.0 / scale}
    written["answer"] = out / "answer_key.json"
    written["answer"].write_text(json.dumps(
        {"seed": seed, "results": truth,
         "notes": f"E_loss and xi_static are the polygon's through the loop's points at the "
                  f"{steps} load steps read, (1 - 1/{steps}^2) of the continuous loop's. "
                  "log_decrement, omega_d, T_d, xi_dynamic belong to the release amplitude"
                  + (f" (delta falls as (A/A0)^{amplitude_exponent:g})."
                     if amplitude_exponent else " (the damping is viscous).")}, indent=1),
        encoding="utf-8")
    return written


DAMPERS = {"C": (2.6e4, 6.9e4), "xi_static": (0.17, 0.25), "decrement": (0.71, 0.90),
           "frequency": (150.0, 260.0)}
"""Ranges a variant's damper is drawn from: the static stiffness, the loop's relative damping
and the decrement over the manual's six dampers (Table 2; ξ′ of the static loop as Table 1's),
and the ring's damped frequency (I follows from it and C_d). [N·m/rad], [1], [1], [Hz]"""

TWIST_MAX = 12e-3
"""The static loop's largest twist a variant is loaded to, as in Table 1. [rad]"""


def _damper(seed: int, ratio: float):
    """A variant's damper: the rubber layer, the largest moment of its static runs, the ring's
    inertia and its decrement at the release. Seed 0 is the manual's damper 1 (C = 2.6·10⁴
    N·m/rad, ξ′ ≈ 0.21, 315 N·m, I = 0.03 kg·m², δ = 0.89).

    The loop's width follows from ξ′ = E_n/E_max = 2hC/(3 M_max) (:class:`RubberLayer`), the
    largest moment is seven steps of 5 N·m multiples near C·:data:`TWIST_MAX`, and
    I = C_d/ω_n² with ω_n from the drawn frequency.
    """
    from processing.synth.damper import RubberLayer, Ring

    if seed == 0:
        return RubberLayer(), 315.0, Ring().inertia, Ring().decrement
    rng = np.random.default_rng([seed, 91])
    C = rng.uniform(*DAMPERS["C"])
    moment_max = 7 * 5.0 * round(C * TWIST_MAX / 35.0)
    width = 1.5 * rng.uniform(*DAMPERS["xi_static"]) * moment_max / C
    decrement = rng.uniform(*DAMPERS["decrement"])
    inertia = ratio * C / (2 * np.pi * rng.uniform(*DAMPERS["frequency"])) ** 2
    return RubberLayer(stiffness=C, loop_width=width), moment_max, inertia, decrement
