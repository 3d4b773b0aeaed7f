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

References
----------
.. [1] J. S. Bendat, A. G. Piersol, Random Data: Analysis and Measurement Procedures, 4th ed.,
       Wiley, 2010, §5.2 (the variance of a difference of a stationary record; white noise).
.. [2] ISO 18431-1:2005, Mechanical vibration and shock — Signal processing — Part 1, §6
       (overload of the recording chain).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .diagnostics import ClippedRecordWarning, InputError
from .result import Record

CLIP_PILE = 5.0
"""How many times the samples of each of the next values below an extreme value must pile up
at it for that side to count as clipped (:func:`clipped_mask`)."""

CLIP_WARNED = 1e-3
"""Share of a record's samples clipped above which it is warned about."""

CLIP_REFUSED = 0.05
"""Share of a record's samples clipped above which it is refused (unless the lab reduces
around its clipped stretches and says so with a limit of its own)."""

NOISE_ROUGHNESS = 0.5
"""Roughness (:func:`roughness`) above which a record holds no oscillation above its noise:
the noise's power exceeds the signal's (white noise: 1)."""

FLAT_STEPS = 2
"""A record whose whole spread is at most this many of its resolution steps is flat."""


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
    step : float
        The record's resolution: its smallest step between distinct values (an ADC code),
        0 for a constant record. [record's unit]
    roughness : float
        :func:`roughness`: 1 for white noise, ≪ 1 for an oscillation the sample rate
        resolves; nan for a constant record. [1]
    """

    samples: int
    duration: float
    clipped: float
    spread: float
    step: float
    roughness: float

    @property
    def flat(self) -> bool:
        """Whether the record never moves by more than :data:`FLAT_STEPS` of its steps."""
        return self.spread == 0.0 or self.spread <= FLAT_STEPS * self.step

    @property
    def noise_only(self) -> bool:
        """Whether its noise carries more power than anything the sample rate resolves."""
        return not self.flat and self.roughness > NOISE_ROUGHNESS


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
    distinct = np.unique(x[: min(x.size, 1 << 16)])
    step = float(np.diff(distinct).min()) if distinct.size > 1 else 0.0
    return RecordQuality(int(x.size), x.size / rate, clipped_share(x),
                         float(np.ptp(x)) if x.size else 0.0, step, roughness(x))


def check_record(x, rate: float, *, file: str, field: str | None, channel: str,
                 least_duration: float = 0.0, purpose: str = "the reduction",
                 clip_refused: float = CLIP_REFUSED, broadband: bool = False) -> RecordQuality:
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
    broadband : bool
        The signal itself may be broadband (an accelerometer's vibration, whose power may
        lie near the Nyquist frequency, where a resolved signal's roughness reaches white
        noise's): the roughness test is left out, and the lab tells its signal from the
        noise its own way (a spectrum's lines above its floor).

    Returns
    -------
    RecordQuality

    Raises
    ------
    InputError
        Flat, noise only (unless ``broadband``), shorter than ``least_duration`` or clipped
        beyond ``clip_refused``.

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
    def refuse(problem: str, fix: str) -> InputError:
        return InputError(f"channel '{channel}' {problem}", fix, file=file, field=field)

    q = assess(x, rate)
    sensor = ("check that the sensor is connected and powered, that its amplifier's gain is "
              "set, and that the channel named is the one that recorded it; then record again")
    if q.flat:
        level = float(np.asarray(x, dtype=float)[0]) if q.samples else 0.0
        raise refuse(f"is flat: its {q.samples} samples stay at {level:.6g}"
                     + (f" within {q.spread:.3g}" if q.spread else "")
                     + f", nothing for {purpose} to read", sensor)
    if q.noise_only and not broadband:
        raise refuse(f"holds no oscillation above its noise: its sample-to-sample changes "
                     f"carry {100 * q.roughness:.0f} % of its variance, as white noise does (a "
                     f"record its sample rate resolves carries a few per cent)", sensor)
    if q.duration < least_duration:
        raise refuse(f"lasts {q.duration:.4g} s ({q.samples} samples); {purpose} needs at "
                     f"least {least_duration:.4g} s", "record longer, or name the whole "
                     "recording")
    if q.clipped > clip_refused:
        raise refuse(f"is clipped: {100 * q.clipped:.1f} % of its samples sit at the "
                     f"recorder's limits (more than {100 * clip_refused:g} %); its peaks are "
                     f"cut off", "lower the amplifier's gain or raise the recorder's range, "
                     "and record again")
    if q.clipped > CLIP_WARNED:
        warnings.warn(ClippedRecordWarning(
            f"{file}, channel '{channel}': {100 * q.clipped:.2f} % of the samples sit at the "
            f"recorder's limits; peaks there are cut off and what is read from them is low: "
            f"lower the amplifier's gain or raise the recorder's range",
            f"{file}, канал '{channel}': {100 * q.clipped:.2f} % отсчётов на пределе "
            f"регистратора; пики срезаны, и определённое по ним занижено: уменьшите усиление "
            f"или увеличьте диапазон регистратора"))
    return q


def irregular_marks(x, error: InputError, *, file: str, field: str | None,
                    channel: str) -> InputError:
    """The error for a mark channel (TDC or time marks) whose marks came out irregular.

    Pulses of a few samples' width have a roughness of about one over their width; a channel
    of noise, above :data:`NOISE_ROUGHNESS`, holds no pulses at all and is named so (its
    "marks" are noise crossing the detector's threshold). Otherwise the marks are pulses,
    missed or doubled (or the recorder's clock is wrong), and ``error`` stands.

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
    "r.csv, field 'tdc_channel': channel 'tdc' holds noise, not pulses: its sam"
    """
    rho = roughness(x)
    if rho > NOISE_ROUGHNESS:
        return InputError(f"channel '{channel}' holds noise, not pulses: its sample-to-sample "
                          f"changes carry {100 * rho:.0f} % of its variance, as white noise's "
                          "do, and its threshold crossings are irregular",
                          "check that the mark sensor is connected and its level set, and "
                          "that the channel named is the marks' channel", file=file,
                          field=field)
    return error
