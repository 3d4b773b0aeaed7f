"""A seismic vibration pickup (a torsiograph): its transfer function and a record corrected by it.

A seismic instrument measures the motion of its case relative to an inertia mass hung on a
soft spring inside it: well above the mass's own natural frequency f_c the mass stands still
and the record is the case's absolute motion; near f_c the record is amplified and shifted in
phase; below it the instrument does not see the motion. The manual's torsiograph (lab 7) is
one: an inertia mass on a flat spring with strain gauges, its case on the crankshaft nose,
f_c 5–10 times below the lowest recorded frequency.

- :func:`torsiograph_response`: recorded over true angle, H(f), complex;
- :func:`amplitude_ratio`: |H(f)|;
- :func:`correct_trace`: a uniformly sampled record divided by H frequency by frequency.

References
----------
.. [1] S. S. Rao, Mechanical Vibrations, 5th ed., Pearson, 2011, §3.10 (vibration measuring
       instruments: the seismic instrument's relative-motion response).
.. [2] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 7 (the torsiograph, its natural frequency f_c = 7.5 Hz against crankshaft modes of
       105–115 Hz).
"""
from __future__ import annotations

import numpy as np


def torsiograph_response(frequency, natural_frequency, damping_ratio):
    r"""Transfer function of a seismic torsiograph: recorded over true angle of its case.

    The inertia mass hangs on a spring of natural frequency f_c (damping ratio ζ) inside the
    case on the crankshaft nose; the trace is the case's angle relative to the mass.

    .. math:: H(f) = \frac{r^2}{r^2 - 1 - 2i\zeta r}, \qquad r = \frac{f}{f_c}, \qquad
              |H| = \frac{r^2}{\sqrt{(1 - r^2)^2 + (2\zeta r)^2}}

    From the mass's equation of motion J θ̈_m = c(θ̇_c − θ̇_m) + k(θ_c − θ_m): the relative
    angle z = θ_c − θ_m obeys z̈ + 2ζω_c ż + ω_c² z = θ̈_c. |H| → 1 well above f_c (the
    mass stands still: the trace is the nose's absolute motion); the manual asks for f_c 5–10
    times below the recorded frequencies.

    Parameters
    ----------
    frequency : float or ndarray
        f. [Hz]
    natural_frequency : float or ndarray
        f_c of the instrument. [Hz]
    damping_ratio : float or ndarray
        ζ of the instrument. [1]

    Returns
    -------
    complex or ndarray
        H(f) (real part positive above f_c: the trace follows the nose). [1]

    Examples
    --------
    The manual's instrument, f_c = 7.5 Hz, at 5 and 10 times f_c (ζ = 0.2):

    >>> np.round(np.abs(torsiograph_response([37.5, 75.0], 7.5, 0.2)), 4).tolist()
    [1.0381, 1.0093]
    """
    r = np.asarray(frequency, dtype=float) / natural_frequency
    return r ** 2 / (r ** 2 - 1 - 2j * damping_ratio * r)


def amplitude_ratio(frequency, natural_frequency, damping_ratio):
    """|H(f)| of :func:`torsiograph_response`: recorded over true amplitude. [1]

    Examples
    --------
    >>> round(float(amplitude_ratio(7.5, 7.5, 0.2)), 6)          # at f_c: 1/(2ζ)
    2.5
    """
    r = np.asarray(frequency, dtype=float) / natural_frequency
    return r ** 2 / np.sqrt((1 - r ** 2) ** 2 + (2 * damping_ratio * r) ** 2)


def blur_gain(frequency, blur: float):
    r"""The restoration of a Gaussian smoothing along the time axis: a record low-passed by
    a Gaussian of σ = ``blur`` [s] (a photographed trace: the light spot's profile and the
    capture's blur, :attr:`processing.vision.record.PaperRecord.stroke_blur`) holds the
    component of frequency f multiplied by exp(−(2πfσ)²/2); this is its inverse,

    .. math:: G_b(f) = e^{(2\pi f \sigma)^2/2}

    Parameters
    ----------
    frequency : array_like
        [Hz]
    blur : float
        σ [s] (0: no smoothing, gain 1).

    Returns
    -------
    ndarray
        G_b ≥ 1.
    """
    return np.exp(0.5 * (2 * np.pi * np.asarray(frequency, dtype=float) * blur) ** 2)


def correct_trace(trace, sample_rate: float, natural_frequency: float, damping_ratio: float, *,
                  low: float, high: float | None = None, upsample: int = 1,
                  blur: float = 0.0, band: float = np.inf) -> np.ndarray:
    """A record corrected for the torsiograph's response, frequency by frequency.

    Every component above ``low`` is divided by :func:`torsiograph_response`; below it (the
    recorder's baseline drift, which never passed through the instrument) the record is kept
    as it is. Optionally components above ``high`` are cut off (a cosine taper from ``high``
    to 1.5·``high``: the noise above the highest order recorded) and the result is
    resampled ``upsample`` times more finely (band-limited interpolation, for the extrema).

    Parameters
    ----------
    trace : array_like
        The record, uniformly sampled. [trace unit]
    sample_rate : float
        [Hz]
    natural_frequency, damping_ratio : float
        f_c [Hz] and ζ [1] of the torsiograph.
    low : float, keyword-only
        Below this the record is not corrected. [Hz]
    high : float, keyword-only, optional
        Low-pass edge. [Hz]
    upsample : int, keyword-only
        Output samples per input sample.
    blur : float, keyword-only
        σ of a Gaussian smoothing along the time axis the record went through after the
        instrument (a photographed trace's): above ``low`` it is undone too
        (:func:`blur_gain`). [s]
    band : float, keyword-only
        Highest frequency the record holds (its highest order): above it the blur's gain is
        held at its value there, so that the noise beyond is not raised. [Hz]

    Returns
    -------
    ndarray
        ``upsample · len(trace)`` samples. [trace unit]

    Notes
    -----
    The record's slow part — a cubic fitted to its moving average over one period of ``low``
    (which averages out the components to be corrected) — and then the straight line through
    the ends of what is left (means over the first and the last such period) are taken out
    before the FFT and put back after, uncorrected, so that the record wraps around without a
    step; what still rings at the ends decays within an oscillation or two.

    Examples
    --------
    A 40 Hz sine seen by an instrument of f_c = 10 Hz on a slow drift, corrected back:

    >>> fs, t = 2000.0, np.arange(2000) / 2000.0
    >>> seen = np.abs(torsiograph_response(40.0, 10.0, 0.3)) * np.sin(2 * np.pi * 40 * t
    ...        + np.angle(torsiograph_response(40.0, 10.0, 0.3)))
    >>> drift = 0.5 * np.sin(2 * np.pi * 0.2 * t)
    >>> x = correct_trace(seen + drift, fs, 10.0, 0.3, low=5.0)
    >>> round(float(np.abs(x - drift - np.sin(2 * np.pi * 40 * t)).max()), 3)
    0.0
    """
    x = np.asarray(trace, dtype=float)
    n = x.size
    line = slow_part(x, sample_rate, low)
    spectrum = np.fft.rfft(x - line)
    f = np.fft.rfftfreq(n, 1 / sample_rate)
    gain = np.ones(f.size, dtype=complex)
    above = f >= low
    gain[above] = blur_gain(np.minimum(f[above], band), blur) / torsiograph_response(
        f[above], natural_frequency, damping_ratio)
    if high is not None:
        taper = np.clip((f - high) / (0.5 * high), 0, 1)
        gain *= 0.5 * (1 + np.cos(np.pi * taper))
    m = n * upsample
    out = np.fft.irfft(spectrum * gain, m) * upsample
    return out + np.interp(np.arange(m) / upsample, np.arange(n), line)


def slow_part(trace, sample_rate: float, low: float) -> np.ndarray:
    """A record's slow part: a cubic fitted to its moving average over one period of
    ``low`` (which averages out the faster components), plus the straight line through the
    ends of what is left (means over the first and the last such period), so that the rest
    wraps around without a step. [trace unit]

    Examples
    --------
    A 40 Hz sine on a slow ramp: the ramp comes back within 0.5 % of the sine.

    >>> t = np.arange(2000) / 2000.0
    >>> x = np.sin(2 * np.pi * 40 * t) + 3 * t
    >>> float(np.abs(slow_part(x, 2000.0, 5.0) - 3 * t).max()) < 0.005
    True
    """
    x = np.asarray(trace, dtype=float)
    n = x.size
    k = int(np.clip(round(sample_rate / low), 1, max(n // 4, 1)))
    smooth = _moving_average(x, k)
    u = np.linspace(-1, 1, n)
    inner = slice(k // 2, n - k // 2)
    slow = np.polynomial.legendre.legval(
        u, np.polynomial.legendre.legfit(u[inner], smooth[inner], min(3, n - k - 1)))
    rest = x - slow
    return slow + np.linspace(rest[:k].mean(), rest[-k:].mean(), n)


def _moving_average(x: np.ndarray, k: int) -> np.ndarray:
    """The mean of ``x`` over ``k`` samples about each sample, the samples beyond its ends
    taken as zero: ``np.convolve(x, np.ones(k) / k, mode="same")`` by running sums, O(n)
    whatever ``k`` (the record's mean taken out first, so that the sums do not cancel)."""
    mean = x.mean()
    sums = np.concatenate([[0.0], np.cumsum(x - mean)])
    i = np.arange(x.size)
    first, stop = np.maximum(i - k // 2, 0), np.minimum(i + (k - 1) // 2, x.size - 1) + 1
    return (sums[stop] - sums[first] + mean * (stop - first)) / k
