"""Whether a record is what it claims to be, before a lab reduces it: clipped by the recorder,
flat, noise with nothing the sample rate resolves, or too short for the method.

One check for every lab that reads a record (a sensor channel, or a trace read off paper):
:func:`check_record` refuses a flat or noise-only channel and one too short for the method
with the cause and the fix, refuses a channel clipped beyond a limit, and warns
(:class:`~processing.diagnostics.ClippedRecordWarning`) about a smaller clipped share. The
measures themselves are :func:`assess`:

- :func:`clipped_mask`: the samples stuck at an ADC's full scale or a saturated amplifier's
  rail (a side whose extreme value piles up samples far more densely than the values just
  below it);
- flatness: the record never moves by more than its own resolution;
- :func:`roughness`: the share of the record's variance carried by its sample-to-sample
  changes, ρ = var(Δx) / (2 var(x)). White noise has ρ = 1; an oscillation the sample rate
  resolves has ρ = 2 sin²(π f / f_s), a few per cent at ten samples a period; a record
  whose broadband noise carries more power than its signal (SNR below 0 dB) has ρ > ½.

A pulse channel (a toothed wheel's sensor, TDC or time marks) is timed by its edges, which a
clipped pulse keeps, and its pulses may be a sample or two wide, which makes even a clean
train rough: :func:`check_pulses` refuses it flat or noise only by :func:`periodicity`, the
largest correlation of the channel with itself shifted (white noise: none; pulses repeating
above their noise: more than ½). :func:`check_frequency` refuses a frequency read off a record
that the record cannot hold (above its Nyquist frequency, or slower than one cycle over it).

References
----------
.. [1] J. S. Bendat, A. G. Piersol, Random Data: Analysis and Measurement Procedures, 4th ed.,
       Wiley, 2010, §5.2 (the variance of a difference of a stationary record; white noise).
.. [2] ISO 18431-1:2005, Mechanical vibration and shock — Signal processing — Part 1, §6
       (overload of the recording chain).
"""
from __future__ import annotations

import warnings
from dataclasses import InitVar, dataclass
from functools import cached_property

import numpy as np

from processing.diagnostics import ClippedRecordWarning, InputError
from processing.result import Record

CLIP_PILE = 5.0
"""How many times the samples of each of the next values below an extreme value must pile up
at it for that side to count as clipped (:func:`clipped_mask`)."""

CLIP_WARNED = 1e-3
"""Share of a record's samples clipped above which it is warned about."""

CLIP_REFUSED = 0.05
"""Share of a record's samples clipped above which it is refused (unless the lab reduces
around its clipped stretches and says so with a limit of its own)."""

LOGIC_SHARE = 0.8
"""Clipped share above which a channel is more like a logic channel's two levels (marks
named for a sensor) than an overloaded sensor's record, and is refused as either."""

NOISE_ROUGHNESS = 0.5
"""Roughness (:func:`roughness`) above which a record holds no oscillation above its noise:
the noise's power exceeds the signal's (white noise: 1)."""

FAST_ROUGHNESS = 1.5
"""Roughness above which a record's oscillation is faster than a third of its sample rate
(ρ = 2 sin²(π f/f_s) > 1.5): it changes sign from sample to sample, as white noise (ρ ≈ 1)
cannot."""

FLAT_STEPS = 2
"""A record whose whole spread is at most this many of its resolution steps is flat."""

PULSE_HEAD = 1 << 20
"""Samples of a long pulse channel that :func:`check_pulse_channel` reads (8 MB as floats):
its first seconds show whether it holds pulses as well as all of it does."""

PULSE_NOISE = 0.5
"""Periodicity (:func:`periodicity`) below which a pulse channel holds no pulses above its
noise: no shift makes it resemble itself more than the noise's share of its power allows."""

SENSOR_FIX = {"en": "check that the sensor is connected and powered, that its amplifier's gain "
                    "is set, and that the channel named is the one that recorded it; then "
                    "record again",
              "ru": "проверьте, что датчик подключён и запитан, коэффициент усиления "
                    "установлен и названный канал — тот, что его записал; затем запишите "
                    "заново"}
"""What to do about a flat or noise-only channel of a recorder."""


def _words(x) -> tuple[str, str | None]:
    """A message's part given as ``{"en": ..., "ru": ...}`` or as English alone (then None
    for its Russian)."""
    return (x["en"], x["ru"]) if isinstance(x, dict) else (x, None)


def _error(problem, fix, *, file: str, field: str | None) -> InputError:
    """An :class:`InputError` of parts each in English or both languages (:func:`_words`):
    Russian when every part has it."""
    (p, p_ru), (f, f_ru) = _words(problem), _words(fix)
    return InputError(p, f, file=file, field=field,
                      ru=(p_ru, f_ru) if p_ru is not None and f_ru is not None else None)

CLIPPED_EFFECT = ("peaks there are cut off and what is read from them is low",
                  "пики срезаны, и определённое по ним занижено")
"""What a clipped record does to a reduction that reads its peaks (English, Russian)."""


@dataclass(frozen=True)
class RecordQuality(Record):
    """What :func:`assess` measured of a record.

    Attributes
    ----------
    samples : int
        Number of samples.
    duration : float
        ``samples / rate``. [s]
    clipped : float
        Share of the samples at a clipped extreme (:func:`clipped_mask`). [1]
    spread : float
        Peak-to-peak of the record. [record's unit]
    roughness : float
        :func:`roughness`: 1 for white noise, ≪ 1 for an oscillation the sample rate
        resolves; nan for a constant record. [1]
    step : float
        The record's resolution: its smallest step between distinct values (an ADC code)
        among its first 2¹⁶ samples (``head``), 0 for a constant record; found when first
        asked for (it sorts them). [record's unit]
    """

    samples: int
    duration: float
    clipped: float
    spread: float
    roughness: float
    head: InitVar[np.ndarray]

    def __post_init__(self, head: np.ndarray) -> None:
        object.__setattr__(self, "_head", head)

    @cached_property
    def step(self) -> float:
        gaps = np.diff(np.sort(self._head))
        gaps = gaps[gaps > 0]           # between distinct values
        return float(gaps.min()) if gaps.size else 0.0

    @cached_property
    def flat(self) -> bool:
        """Whether the record never moves by more than :data:`FLAT_STEPS` of its steps.

        A head of more than FLAT_STEPS + 1 distinct values has a step of at most
        spread/(FLAT_STEPS + 1), and the record is not flat whatever its step: the sort that
        finds the step is left to the records of a few values."""
        if self.spread == 0.0:
            return True
        if _distinct_at_least(self._head, FLAT_STEPS + 2):
            return False
        return self.spread <= FLAT_STEPS * self.step

    @property
    def noise_only(self) -> bool:
        """Whether its noise carries more power than anything the sample rate resolves."""
        return not self.flat and self.roughness > NOISE_ROUGHNESS

    def to_dict(self) -> dict:
        """The measures by name, ``step`` among them (between ``spread`` and ``roughness``)."""
        out = super().to_dict()
        roughness = out.pop("roughness")
        return {**out, "step": self.step, "roughness": roughness}


def _distinct_at_least(x: np.ndarray, count: int) -> bool:
    """Whether ``x`` holds at least ``count`` distinct values: its first 64 do (a varied
    record's), or its least value taken off ``count`` − 1 times leaves some (no sort of the
    whole)."""
    if np.unique(x[:64]).size >= count:
        return True
    for _ in range(count - 1):
        if x.size == 0:
            return False
        x = x[x > x.min()]
    return x.size > 0


def clipped_mask(x) -> np.ndarray:
    """The samples stuck at the record's extremes (an ADC's full scale, a saturated amplifier).

    A side counts as clipped when its extreme value holds more than :data:`CLIP_PILE` times
    as many samples as each of the next three values below it (for unquantized floats: in
    three of their smallest steps), counting the samples that stay there for two samples or
    more. A sine's crest piles samples at its top code about twice as densely as below it; a
    rail, far more; a crest sampled exactly at its top touches it for one sample.

    Parameters
    ----------
    x : array_like
        The record. [any unit]

    Returns
    -------
    ndarray of bool
        True where a sample sits at a clipped extreme.

    Examples
    --------
    >>> t = np.arange(10000) / 10000
    >>> sine = np.round(np.sin(2 * np.pi * 7 * t) * 50)        # 50 codes: not clipped
    >>> int(clipped_mask(sine).sum()), round(float(clipped_mask(np.clip(1.2 * sine, -50, 50)).mean()), 3)
    (0, 0.377)
    """
    x = np.asarray(x, dtype=float)
    mask = np.zeros(x.shape, dtype=bool)
    if x.size == 0:
        return mask
    width = np.ptp(x)
    for side in (x, -x):
        top = side.max()
        if np.count_nonzero(side >= np.nextafter(top, -np.inf)) <= 2:
            continue    # at most two samples at the top, or a float below it (no other value
                        # lies within half a step of it): count ≤ 2 below
        near = np.unique(side[side >= top - 0.05 * width])
        step = np.diff(near).min() if near.size > 1 else 0.0
        at_top = side >= top - 0.5 * step
        at_top[1:-1] &= at_top[:-2] | at_top[2:]  # a rail holds; a crest's sample may touch
        count = np.count_nonzero(at_top)
        below = np.count_nonzero((side < top - 0.5 * step) & (side >= top - 3.5 * step))
        if width > 0 and count > 2 and count > CLIP_PILE * max(below / 3, 1):
            mask |= at_top
    return mask


def clipped_share(x) -> float:
    """Share of the samples at a clipped extreme (:func:`clipped_mask`). [1]

    >>> clipped_share(np.clip(np.sin(np.linspace(0, 20, 2001)), -0.5, 0.5)) > 0.5
    True
    """
    return float(clipped_mask(x).mean()) if np.size(x) else 0.0


def roughness(x) -> float:
    """ρ = var(Δx) / (2 var(x)): the share of a record's variance in its sample-to-sample
    changes.

    For white noise the differences of independent samples have twice the variance, ρ = 1;
    for a sinusoid of frequency f sampled at f_s, ρ = 2 sin²(π f / f_s) (0.19 at ten samples
    a period); for a resolved signal in white noise ρ ≈ σ_n² / (σ_s² + σ_n²), above ½ when
    the noise carries more power than the signal [1]_.

    Parameters
    ----------
    x : array_like
        The record, at least two samples. [any unit]

    Returns
    -------
    float
        ρ, nan for a constant record. [1]

    References
    ----------
    .. [1] J. von Neumann, "Distribution of the ratio of the mean square successive
       difference to the variance", Ann. Math. Statist. 12 (1941) 367–395.

    Examples
    --------
    >>> t = np.arange(1000)
    >>> round(roughness(np.sin(2 * np.pi * t / 10)), 3), round(float(2 * np.sin(np.pi / 10) ** 2), 3)
    (0.191, 0.191)
    >>> 0.9 < roughness(np.random.default_rng(1).standard_normal(100000)) < 1.1
    True
    """
    x = np.asarray(x, dtype=float)
    variance = x.var()
    if x.size < 2 or variance == 0:
        return float("nan")
    return float(np.diff(x).var() / (2 * variance))


def assess(x, rate: float) -> RecordQuality:
    """Measure a record's quality: its length, clipped share, spread, resolution, roughness.

    Parameters
    ----------
    x : array_like
        The record (finite samples). [any unit]
    rate : float
        Its sample rate. [Hz]

    Returns
    -------
    RecordQuality

    Examples
    --------
    >>> q = assess(np.full(500, 3.0), 1000.0)
    >>> q.flat, q.duration, q.noise_only
    (True, 0.5, False)
    """
    x = np.asarray(x, dtype=float)
    return RecordQuality(int(x.size), x.size / rate, clipped_share(x),
                         float(np.ptp(x)) if x.size else 0.0, roughness(x),
                         x[: min(x.size, 1 << 16)].copy())


def check_record(x, rate: float, *, file: str, field: str | None, channel: str,
                 least_duration: float = 0.0,
                 purpose: str | dict = {"en": "the reduction", "ru": "обработки"},
                 clip_refused: float = CLIP_REFUSED, fix: str | dict = SENSOR_FIX,
                 clipped_effect: tuple[str, str] = CLIPPED_EFFECT,
                 broadband: bool = False) -> RecordQuality:
    """Refuse a record that is flat, noise only, too short or clipped beyond a limit; warn
    about a smaller clipped share.

    Parameters
    ----------
    x : array_like
        The record. [any unit]
    rate : float
        Its sample rate. [Hz]
    file, field : str
        The recording and the measurement-file field that named it, for the messages.
    channel : str
        The channel's name in the recording, for the messages.
    least_duration : float
        The shortest record the method can use. [s]
    purpose : str
        What the record is for, in the message ("the decrement", "an order fit").
    clip_refused : float
        Clipped share above which the record is refused (:data:`CLIP_REFUSED`); a lab that
        leaves the clipped samples out of its fit may allow more.
    fix : str
        What to do about a flat or noise-only record (default :data:`SENSOR_FIX`; a trace
        read off a photograph asks for another photograph).
    clipped_effect : (str, str)
        What the clipped samples do to the reduction, in English and Russian, for the
        warning (default :data:`CLIPPED_EFFECT`; a fit around them says so).
    broadband : bool
        The signal itself may be broadband (an accelerometer's vibration, whose power may
        lie near the Nyquist frequency, where a resolved signal's roughness reaches white
        noise's): the roughness tests are left out, and the lab tells its signal from the
        noise its own way (a spectrum's lines above its floor).

    Returns
    -------
    RecordQuality

    Raises
    ------
    InputError
        Flat, noise only (or an oscillation faster than a third of the sample rate; neither when
        ``broadband``), shorter than ``least_duration``, clipped beyond ``clip_refused``, or sitting
        at two levels (:data:`LOGIC_SHARE`) whatever the lab allows.

    Examples
    --------
    >>> t = np.arange(4000) / 1000.0
    >>> check_record(np.sin(2 * np.pi * 5 * t), 1000.0, file="r.csv", field="decay.signal",
    ...              channel="u").clipped
    0.0
    >>> noise = np.random.default_rng(0).standard_normal(4000)
    >>> check_record(noise, 1000.0, file="r.csv", field="decay.signal", channel="u")
    Traceback (most recent call last):
    ...
    processing.diagnostics.InputError: r.csv, field 'decay.signal': channel 'u' holds no oscillation above its noise: ...
    """
    purpose, purpose_ru = _words(purpose)

    def refuse(en: str, ru: str | None, fix) -> InputError:
        return _error({"en": f"channel '{channel}' {en}",
                       "ru": ru and f"канал '{channel}' {ru}"}, fix, file=file, field=field)

    q = assess(x, rate)
    if q.flat:
        level = float(np.asarray(x, dtype=float)[0]) if q.samples else 0.0
        raise refuse(f"is flat: its {q.samples} samples stay at {level:.6g}"
                     + (f" within {q.spread:.3g}" if q.spread else "")
                     + f", nothing for {purpose} to read",
                     purpose_ru and f"постоянен: его {q.samples} отсчётов остаются на "
                     f"{level:.6g}" + (f" в пределах {q.spread:.3g}" if q.spread else "")
                     + f", для {purpose_ru} читать нечего", fix)
    if q.noise_only and not broadband and q.roughness > FAST_ROUGHNESS:
        raise refuse(f"swings from sample to sample (its changes carry {100 * q.roughness:.0f} % "
                     f"of its variance): what it holds is faster than a third of its sample "
                     f"rate ({rate:.6g} Hz), too fast for {purpose}",
                     purpose_ru and f"скачет от отсчёта к отсчёту (на приращения приходится "
                     f"{100 * q.roughness:.0f} % его дисперсии): записанное быстрее трети "
                     f"частоты отсчётов ({rate:.6g} Гц), слишком быстро для {purpose_ru}",
                     {"en": "record at a higher sample rate (ten or more samples a period), or "
                            "give the recorder's true sample rate",
                      "ru": "запишите с большей частотой отсчётов (десять и более на период) "
                            "или укажите истинную частоту отсчётов регистратора"})
    if q.noise_only and not broadband:
        raise refuse(f"holds no oscillation above its noise: its sample-to-sample changes "
                     f"carry {100 * q.roughness:.0f} % of its variance, as white noise does (a "
                     f"record its sample rate resolves carries a few per cent)",
                     f"не содержит колебаний выше шума: на приращения от отсчёта к отсчёту "
                     f"приходится {100 * q.roughness:.0f} % его дисперсии, как у белого шума "
                     f"(у записи, разрешённой её частотой отсчётов, — несколько процентов)", fix)
    if q.duration < least_duration:
        raise refuse(f"lasts {q.duration:.4g} s ({q.samples} samples); {purpose} needs at "
                     f"least {least_duration:.4g} s",
                     purpose_ru and f"длится {q.duration:.4g} с ({q.samples} отсчётов); для "
                     f"{purpose_ru} нужно не меньше {least_duration:.4g} с",
                     {"en": "record longer, or name the whole recording",
                      "ru": "запишите дольше или укажите всю запись"})
    if q.clipped > LOGIC_SHARE:
        raise refuse(f"sits at its two extremes in {100 * q.clipped:.0f} % of its samples: a "
                     f"logic channel (TDC or time marks), or a sensor clipped past recognition, "
                     f"nothing for {purpose} to read",
                     purpose_ru and f"в {100 * q.clipped:.0f} % отсчётов стоит на одном из "
                     f"двух крайних уровней: это логический канал (ВМТ или отметки времени) "
                     f"или датчик, зашкаленный до неузнаваемости, — для {purpose_ru} читать "
                     f"нечего",
                     {"en": "name the sensor's own channel; if it is the one, lower the "
                            "amplifier's gain or raise the recorder's range and record again",
                      "ru": "укажите собственный канал датчика; если это он, уменьшите "
                            "усиление или увеличьте диапазон регистратора и запишите заново"})
    if q.clipped > clip_refused:
        raise refuse(f"is clipped: {100 * q.clipped:.1f} % of its samples sit at the "
                     f"recorder's limits (more than {100 * clip_refused:g} %); its peaks are "
                     f"cut off",
                     f"зашкален: {100 * q.clipped:.1f} % отсчётов на пределе регистратора "
                     f"(больше {100 * clip_refused:g} %); его пики срезаны",
                     {"en": "lower the amplifier's gain or raise the recorder's range, and "
                            "record again",
                      "ru": "уменьшите усиление или увеличьте диапазон регистратора и "
                            "запишите заново"})
    if q.clipped > CLIP_WARNED:
        warnings.warn(ClippedRecordWarning(
            f"{file}, channel '{channel}': {100 * q.clipped:.2f} % of the samples sit at the "
            f"recorder's limits; {clipped_effect[0]}: lower the amplifier's gain or raise the "
            f"recorder's range",
            f"{file}, канал '{channel}': {100 * q.clipped:.2f} % отсчётов на пределе "
            f"регистратора; {clipped_effect[1]}: уменьшите усиление или увеличьте диапазон "
            f"регистратора"))
    return q


def periodicity(x) -> float:
    """The largest correlation of a record with itself shifted by 1 to n/2 samples,
    r(k) = Σ x̃ᵢ x̃ᵢ₊ₖ / ((n − k) var x), x̃ = x − x̄.

    A pulse train, or any oscillation, repeats: r at its period is the share of the record's
    power that repeats, near 1 above a weak noise, ½ where noise and pulses carry as much,
    whatever the pulses' width (a one-sample pulse makes even a clean train rough,
    :func:`roughness` ≈ 1). White noise resembles no shift of itself: r ~ 1/√(n − k).

    Parameters
    ----------
    x : array_like
        The record, at least four samples. [any unit]

    Returns
    -------
    float
        max r(k), nan for a constant or too short a record. [1]

    Examples
    --------
    >>> pulses = np.zeros(5000)
    >>> pulses[::250] = 1.0                        # one-sample pulses: rough, but periodic
    >>> round(roughness(pulses), 2), round(periodicity(pulses), 2)
    (0.98, 1.0)
    >>> periodicity(np.random.default_rng(2).standard_normal(5000)) < 0.1
    True
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    y = x - x.mean() if n else x
    variance = float(y @ y) / n if n else 0.0
    if n < 4 or variance == 0:
        return float("nan")
    size = 1 << int(np.ceil(np.log2(2 * n)))
    spectrum = np.fft.rfft(y, size)
    lags = np.arange(1, n // 2 + 1)
    r = np.fft.irfft(np.abs(spectrum) ** 2, size)[lags] / ((n - lags) * variance)
    return float(r.max())


def check_pulses(x, rate: float, *, file: str, field: str | None, channel: str,
                 pulses: str | dict = {"en": "pulses", "ru": "импульсов"},
                 fix: str | dict = SENSOR_FIX) -> float:
    """Refuse a pulse channel (a toothed wheel's sensor, TDC or time marks) that is flat or
    holds only noise; its clipping is left alone (an edge is timed where a clipped pulse
    crosses its mean level, as where a whole one does).

    Flat here is constant: a logic channel's two levels are a code apart, and whether they
    toggle with pulses or with noise in the converter's last bit, :func:`periodicity` tells.

    Parameters
    ----------
    x : array_like
        The channel, or a bounded stretch of a long one (its first million samples tell as
        much as the whole). [any unit]
    rate : float
        Its sample rate. [Hz]
    file, field, channel : str
        For the messages, as :func:`check_record`.
    pulses : str
        What its pulses are, in the message ("tooth pulses", "TDC marks").
    fix : str
        What to do about it (default :data:`SENSOR_FIX`).

    Returns
    -------
    float
        Its :func:`periodicity`.

    Raises
    ------
    InputError
        Constant, or no shift of it repeats more than :data:`PULSE_NOISE` of its power.

    Examples
    --------
    >>> marks = (np.arange(20000) % 200 < 2).astype(float)     # two-sample marks
    >>> round(check_pulses(marks, 1e4, file="r.csv", field="record.marks", channel="m"), 2)
    1.0
    >>> check_pulses(np.full(300, 5.0), 1e4, file="r.csv", field="record.marks", channel="m",
    ...              pulses="time marks")
    Traceback (most recent call last):
    ...
    processing.diagnostics.InputError: r.csv, field 'record.marks': channel 'm' is flat: its 300 samples stay at 5, no time marks to time. Fix: ...
    """
    x = np.asarray(x, dtype=float)
    pulses, pulses_ru = _words(pulses)
    if x.size == 0 or np.ptp(x) == 0:
        level = float(x[0]) if x.size else 0.0
        raise _error({"en": f"channel '{channel}' is flat: its {x.size} samples stay at "
                            f"{level:.6g}, no {pulses} to time",
                      "ru": pulses_ru and f"канал '{channel}' постоянен: его {x.size} отсчётов "
                            f"остаются на {level:.6g}, {pulses_ru} для отсчёта времени нет"},
                     fix, file=file, field=field)
    repeat = periodicity(x)
    if repeat < PULSE_NOISE:
        raise _error({"en": f"channel '{channel}' holds no {pulses} above its noise: no "
                            f"stretch of it repeats later (its best correlation with itself "
                            f"shifted is {repeat:.2f}; a train of pulses gives more than "
                            f"{PULSE_NOISE:g}), as white noise does",
                      "ru": pulses_ru and f"в канале '{channel}' нет {pulses_ru} выше шума: "
                            f"ни один его участок не повторяется дальше (наибольшая корреляция "
                            f"с самим собой со сдвигом {repeat:.2f}; у серии импульсов больше "
                            f"{PULSE_NOISE:g}), как у белого шума"}, fix, file=file, field=field)
    return repeat


def irregular_marks(x, error: InputError, *, file: str, field: str | None,
                    channel: str) -> InputError:
    """The error for a mark channel (TDC or time marks) whose marks came out irregular.

    A channel of noise, whose best correlation with itself shifted (:func:`periodicity`)
    stays below :data:`PULSE_NOISE`, holds no pulses at all and is named so (its "marks" are
    noise crossing the detector's threshold). Otherwise the marks are pulses, missed or
    doubled (or the recorder's clock is wrong), and ``error`` stands.

    Parameters
    ----------
    x : array_like
        The mark channel. [any unit]
    error : InputError
        What the marks' own check found (returned when the channel is not noise).
    file, field, channel : str
        Where the channel is, for the noise's message.

    Returns
    -------
    InputError

    Examples
    --------
    >>> noise = np.random.default_rng(0).standard_normal(4000)
    >>> e = InputError("the marks are irregular", "check the channel")
    >>> str(irregular_marks(noise, e, file="r.csv", field="tdc_channel", channel="tdc"))[:74]
    "r.csv, field 'tdc_channel': channel 'tdc' holds noise, not pulses: no stre"
    """
    repeat = periodicity(x)
    if repeat < PULSE_NOISE:
        return InputError(f"channel '{channel}' holds noise, not pulses: no stretch of it "
                          f"repeats later (its best correlation with itself shifted is "
                          f"{repeat:.2f}), and its threshold crossings are irregular",
                          "check that the mark sensor is connected and its level set, and "
                          "that the channel named is the marks' channel", file=file,
                          field=field,
                          ru=(f"в канале '{channel}' шум, а не импульсы: ни один его участок не "
                              f"повторяется дальше (наибольшая корреляция с самим собой со "
                              f"сдвигом {repeat:.2f}), и пересечения порога нерегулярны",
                              "проверьте, что датчик отметок подключён и его уровень "
                              "установлен и что названный канал — канал отметок"))
    return error


def check_frequency(frequency: float, rate: float, duration: float, *, file: str,
                    field: str | None, what: str) -> None:
    """Refuse a frequency read off a record that the record cannot hold: at or above its
    Nyquist frequency rate/2 (an alias, or a fit that ran off), or below one cycle over its
    length.

    Parameters
    ----------
    frequency : float
        The frequency found. [Hz]
    rate, duration : float
        The record's sample rate [Hz] and length [s].
    file, field : str
        For the message.
    what : str
        The frequency's name in the message ("the decay's ω_d/2π").

    Raises
    ------
    InputError

    Examples
    --------
    >>> check_frequency(450.0, 10e3, 0.5, file="r.csv", field="record.signal", what="ν")
    >>> check_frequency(6e3, 10e3, 0.5, file="r.csv", field="record.signal", what="ν")
    Traceback (most recent call last):
    ...
    processing.diagnostics.InputError: r.csv, field 'record.signal': ν = 6000 Hz is above the record's Nyquist frequency (5000 Hz at 10000 Hz sampling): the record cannot hold it. Fix: ...
    """
    if not frequency < rate / 2:
        raise InputError(f"{what} = {frequency:.4g} Hz is above the record's Nyquist frequency "
                         f"({rate / 2:.6g} Hz at {rate:.6g} Hz sampling): the record cannot "
                         "hold it", "record at a higher sample rate (ten or more samples a "
                         "period), or give the recorder's true sample rate", file=file,
                         field=field,
                         ru=(f"{what} = {frequency:.4g} Гц — выше частоты Найквиста записи "
                             f"({rate / 2:.6g} Гц при частоте отсчётов {rate:.6g} Гц): запись "
                             "не может её содержать", "запишите с большей частотой отсчётов "
                             "(десять и более на период) или укажите истинную частоту "
                             "отсчётов регистратора"))
    if not frequency * duration >= 1:
        raise InputError(f"{what} = {frequency:.4g} Hz is slower than one cycle over the "
                         f"record ({duration:.4g} s): the record cannot hold it",
                         "record longer: several periods of the oscillation", file=file,
                         field=field,
                         ru=(f"{what} = {frequency:.4g} Гц — меньше одного периода за запись "
                             f"({duration:.4g} с): запись не может её содержать",
                             "запишите дольше: несколько периодов колебаний"))


def check_pulse_channel(channel, *, field: str | None,
                        pulses: str | dict = {"en": "pulses", "ru": "импульсов"},
                        fix: str | dict = SENSOR_FIX, head: int = PULSE_HEAD) -> float:
    """:func:`check_pulses` on the first ``head`` samples of a recorded channel, read in one
    bounded block however long the recording (a
    :class:`~processing.inputs.signals.Channel`: its ``chunks``, ``sample_rate``,
    ``volts_per_code``, ``path`` and ``name``).

    Returns
    -------
    float
        The stretch's :func:`periodicity`.
    """
    stretch = next(channel.chunks(min(channel.length, head)))
    return check_pulses(stretch.astype(float) * channel.volts_per_code, channel.sample_rate,
                        file=str(channel.path), field=field, channel=str(channel.name),
                        pulses=pulses, fix=fix)
