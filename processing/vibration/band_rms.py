"""A vibration meter's bands: RMS acceleration, velocity and displacement of an acceleration
record, integrated in the frequency domain without drift, and their levels in dB.

A vibration meter (the manual's ВМ-1: accelerometer, preamplifier, single and double
integrators, band filters, RMS and peak detectors) reads acceleration and displacement over
1.4–8000 Hz and velocity over 1.4–2800 Hz. Its band edges are filters, not walls: here each
edge is a Butterworth filter whose −3 dB point is the edge, and integrating n times divides
by (2πf)ⁿ. So a band reading of a recorded acceleration a(t) is

.. math:: X_n^2 = \\int_0^\\infty S_a(f)\\, g_n(f)\\, df, \\qquad
          g_n(f) = \\frac{|H_{lo}(f)|^2 |H_{hi}(f)|^2}{(2\\pi f)^{2n}}

with S_a the one-sided power spectral density; n = 0, 1, 2 for a, v, x.

:func:`band_rms` evaluates it on one Hann-windowed periodogram of the whole record. The window
spreads each spectral line over a few bins (a spectral second moment σ_f² = 1/(3T²) for a record of
T seconds), and a weight that curves across the spread, as 1/f⁴ does at a few Hz, would bias the
sum; the weight is therefore deconvolved to second order, g̃ = g − ½ σ_f² g''
(:func:`deconvolved_weight`), which leaves an error of order (σ_f/f)⁴. The window-weighted mean is
taken out first (a sensor's offset would otherwise leak into the lowest bins, where the
displacement's weight is largest). Nothing is integrated in the time domain, so nothing drifts; the
high-pass edge at 1.4 Hz is the meter's own. :func:`band_signals` gives the band-limited a, v and x
as time signals (for the peak and peak-to-peak detectors). Beside each reading, what the record's
broadband floor alone would read: the periodogram between its lines, level by level along the
frequency axis (:func:`broadband_floor`), through the same weight, so that a floor rising with
frequency is not carried down to the 1.4 Hz edge, where the displacement's weight is largest. Its
edge filters have order 2 for the acceleration, 3 for the velocity, 4 for the displacement
(:data:`FILTER_ORDER`), so that no reading passes a constant or a slow wander.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 4 (the vibration meter ВМ-1: bands 1.4–8000 Hz for acceleration and displacement,
       1.4–2800 Hz for velocity; RMS and peak-to-peak detectors; ±15 % basic error).
.. [2] ISO 2954:2012, Mechanical vibration of rotating and reciprocating machinery:
       requirements for instruments for measuring vibration severity (band-limit filters of
       at least 12 dB per octave, i.e. second order, at the −3 dB band edges).
.. [3] ISO 1683:2015, Acoustics: preferred reference values for acoustical and vibratory
       levels (a₀ = 10⁻⁶ m/s², v₀ = 10⁻⁹ m/s, x₀ = 10⁻¹² m).
.. [4] GOST 25275-82 (ГОСТ 25275-82), Vibration measuring instruments for rotating machines
       (the Soviet meters' dB scale: a₀ = 3·10⁻⁴ m/s², v₀ = 5·10⁻⁸ m/s, x₀ = 8·10⁻¹² m).
.. [5] F. J. Harris, On the use of windows for harmonic analysis with the discrete Fourier
       transform, Proc. IEEE 66 (1978) 51–83, doi:10.1109/PROC.1978.10837.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.fft
from scipy.special import gammaincinv

from processing.result import Record

FILTER_ORDER = 2
"""Order of the Butterworth filters at the acceleration band's edges (12 dB per octave, ISO
2954's least). Each integration adds an order (a meter's integrator is a lossy one, a first
order high-pass at the band's lower edge: with a plain 1/(2πf)² and a second-order edge the
displacement would read a sensor's slow wander at a gain of 1/(2π f_lo)²)."""

QUANTITIES = ("a", "v", "x")
"""Acceleration, velocity, displacement: the record integrated 0, 1 and 2 times."""

INTEGRATIONS = {"a": 0, "v": 1, "x": 2}


@dataclass(frozen=True)
class Band:
    """A meter band: −3 dB edges of Butterworth high- and low-pass filters of one order."""

    low: float
    """Lower edge. [Hz]"""
    high: float
    """Upper edge. [Hz]"""
    order: int = FILTER_ORDER

    def gain(self, frequency):
        """|H(f)| = [1 + (f_lo/f)^{2N}]^{-1/2} [1 + (f/f_hi)^{2N}]^{-1/2} (0 at f = 0). [1]

        Examples
        --------
        >>> b = Band(1.4, 8000.0)
        >>> np.round(b.gain([1.4, 100.0, 8000.0]), 6).tolist()
        [0.707107, 1.0, 0.707107]
        """
        f = np.abs(np.asarray(frequency, dtype=float))
        with np.errstate(divide="ignore"):
            low = np.where(f > 0, 1.0 / (1.0 + _even_power(self.low / np.where(f > 0, f, 1.0),
                                                           self.order)), 0.0)
        return np.sqrt(low / (1.0 + _even_power(f / self.high, self.order)))


def _even_power(x, order: int):
    """x^{2N} by squarings and products (a whole power; a float power costs ten times as
    much over a spectrum's bins and gives the same to a few units of the last place)."""
    square = np.square(x)
    out = None
    while order:
        if order & 1:
            out = square if out is None else out * square
        order >>= 1
        if order:
            square = np.square(square)
    return np.ones_like(square) if out is None else out


BANDS = {"a": Band(1.4, 8000.0), "v": Band(1.4, 2800.0, FILTER_ORDER + 1),
         "x": Band(1.4, 8000.0, FILTER_ORDER + 2)}
"""The manual's meter: acceleration and displacement 1.4–8000 Hz, velocity 1.4–2800 Hz;
orders 2, 3 and 4 (:data:`FILTER_ORDER`)."""

REFERENCES = {
    "iso1683": {"a": 1e-6, "v": 1e-9, "x": 1e-12},
    "gost25275": {"a": 3e-4, "v": 5e-8, "x": 8e-12},
}
"""Reference values of the dB levels, SI (m/s², m/s, m): ISO 1683 and the Soviet GOST 25275."""


def meter_gain(frequency, quantity: str, band: Band | None = None):
    """The meter's gain from acceleration to a reading: |H(f)| / (2πf)ⁿ.

    Parameters
    ----------
    frequency : float or ndarray
        f. [Hz]
    quantity : {"a", "v", "x"}
        What the meter reads (n = 0, 1, 2 integrations).
    band : Band, optional
        Default: the manual's band of ``quantity``.

    Returns
    -------
    float or ndarray
        [1], [s], [s²] for a, v, x (0 at f = 0).
    """
    band = BANDS[quantity] if band is None else band
    n = INTEGRATIONS[quantity]
    f = np.abs(np.asarray(frequency, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(f > 0, band.gain(f) / (2 * np.pi * np.where(f > 0, f, 1.0)) ** n, 0.0)
    return w


def sine_band_rms(amplitude, frequency, quantity: str, band: Band | None = None):
    """Closed form: the band reading of an acceleration A cos 2πft.

    .. math:: X_n = \\frac{A}{\\sqrt 2}\\,\\frac{|H(f)|}{(2\\pi f)^n}

    Examples
    --------
    10 m/s² at 50 Hz (the edges take 0.004 % of a): a = 7.0711 m/s²,
    v = 22.508 mm/s, x = 71.64 µm (RMS):

    >>> [round(float(sine_band_rms(10.0, 50.0, q)), 8) for q in QUANTITIES]
    [7.07106563, 0.02250791, 7.164e-05]
    """
    return np.asarray(amplitude, dtype=float) / np.sqrt(2) * meter_gain(frequency, quantity, band)


def level_db(rms, quantity: str, reference: str = "iso1683"):
    """Level in dB of an RMS reading, L = 20 lg(X/X₀), X₀ of :data:`REFERENCES`.

    Examples
    --------
    >>> round(float(level_db(1.0, "a")), 6), round(float(level_db(3e-4, "a", "gost25275")), 6)
    (120.0, 0.0)
    """
    return 20 * np.log10(np.asarray(rms, dtype=float) / REFERENCES[reference][quantity])


def window_spread(size: int) -> float:
    """σ_f² T² of the periodic Hann window of ``size`` samples: the second moment of its
    power spectrum over the DFT bins, in bins² (1/3 for a long window). [1]

    Examples
    --------
    >>> round(window_spread(4096), 6)
    0.333333
    """
    return _spread(int(size))


@lru_cache(maxsize=64)
def _spread(size: int) -> float:
    power = np.abs(np.fft.fft(_hann(size))) ** 2
    k = np.fft.fftfreq(size, 1.0 / size)
    return float(np.sum(k * k * power) / np.sum(power))


@lru_cache(maxsize=64)
def _hann(size: int) -> np.ndarray:
    return 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(size) / size)


@lru_cache(maxsize=64)
def _hann_sum(size: int) -> float:
    return float(np.sum(_hann(size)))


def deconvolved_weight(frequency, weight, spread: float) -> np.ndarray:
    """g̃ = g − ½ σ² g'': a weight whose convolution with a window's power spectrum of second
    moment σ² gives back g to second order.

    Parameters
    ----------
    frequency : ndarray
        A uniform grid. [Hz]
    weight : callable
        g(f).
    spread : float
        σ². [Hz²]

    Returns
    -------
    ndarray
        g̃ on the grid.
    """
    f = np.asarray(frequency, dtype=float)
    h = 1e-3 * np.maximum(f, 1e-3)
    g0, gp, gm = weight(f), weight(f + h), weight(np.abs(f - h))
    return g0 - 0.5 * spread * (gp - 2 * g0 + gm) / (h * h)


@lru_cache(maxsize=64)
def _weights(size: int, sample_rate: float, bands: tuple) -> np.ndarray:
    """Per rfft bin, the deconvolved weights of each (quantity, band), the one-sided factor 2
    and the window's power normalisation folded in: MS = weights @ |X|²."""
    f = np.fft.rfftfreq(size, 1.0 / sample_rate)
    spread = _spread(size) * (sample_rate / size) ** 2
    side = np.full(f.size, 2.0)
    side[0] = 1.0
    if size % 2 == 0:
        side[-1] = 1.0
    norm = side / (size * np.sum(_hann(size) ** 2))
    rows = np.stack([deconvolved_weight(f, lambda x, q=q, b=b: meter_gain(x, q, b) ** 2, spread)
                     * norm for q, b in bands])
    rows[:, 0] = 0.0      # the windowed mean is taken out: the DC bin holds nothing
    return rows


def clear_weights() -> None:
    """Forget the cached per-length weights (a benchmark's cold start)."""
    _weights.cache_clear()


@dataclass(frozen=True)
class BandRMS(Record):
    """RMS band readings of one acceleration record (:func:`band_rms`)."""

    a: float
    """Acceleration, 1.4–8000 Hz. [m/s²] (the record's unit)"""
    v: float
    """Velocity, 1.4–2800 Hz. [m/s]"""
    x: float
    """Displacement, 1.4–8000 Hz. [m]"""
    floor: dict
    """What the record's broadband floor alone would read in each band: the periodogram less
    its lines (:func:`broadband_floor`) through the band's weight. Sensor noise and broadband
    vibration alike; where it nears a reading, the reading rests on it. [m/s², m/s, m]"""

    def __getitem__(self, quantity: str) -> float:
        return getattr(self, quantity)


SEGMENT = 2 ** 20
"""Longest stretch transformed at once (41 s at 25.6 kHz): a longer record is cut into equal
segments whose periodograms are averaged (Welch's method without overlap; the window's
spread is then the segment's), which keeps the transform in the processor's cache."""

FLOOR_BLOCK = (8, 1 / 6)
"""The blocks of periodogram bins in which :func:`broadband_floor` takes the floor's level: at
least 8 bins, else 1/6 octave wide (a level that rises as f² changes by 26 % across one)."""

FLOOR_QUANTILE = 0.2
"""Quantile of a block's bins that gives its floor level: lines (orders, tones) may fill up to
80 % of a block without lifting it."""

FLOOR_LINE = 10.0
"""A bin is a line's when its power exceeds this many times its block's floor level: a bin of
noise alone does so with probability e⁻¹⁰ = 5·10⁻⁵ (one per 20 000 bins)."""

FLOOR_STRIDE = 4
"""In a block of more than 256 bins every this-many-th enters the level's quantile (its
value, not its cost, needs them)."""


def band_rms(acceleration, sample_rate: float, *, bands: dict | None = None,
             lowest_line: float = 0.0) -> BandRMS:
    """RMS acceleration, velocity and displacement of an acceleration record in the meter's
    bands, integrated in the frequency domain.

    .. math:: X_n^2 = \\frac{1}{N\\sum w^2} \\sum_j c_j\\,|W_j|^2\\, \\tilde g_n(f_j)

    W = DFT of the Hann-windowed record less its windowed mean, c_j = 2 (1 at 0 and Nyquist),
    g̃ the deconvolved weight (module docstring); a record longer than :data:`SEGMENT`
    samples is cut into equal segments whose ``|W_j|²`` are averaged.

    Parameters
    ----------
    acceleration : array_like
        A uniformly sampled record. [m/s²]
    sample_rate : float
        [Hz]
    bands : dict, optional
        Band of each quantity (default :data:`BANDS`).
    lowest_line : float, optional
        The lowest frequency a line of the record can have (an engine's lowest order, where
        its speed is known): what lies below it is floor (:func:`broadband_floor`); 0 when
        unknown. [Hz]

    Returns
    -------
    BandRMS

    Raises
    ------
    ValueError
        Fewer than 16 samples.

    Examples
    --------
    A 10 m/s² sine at 21.3 Hz (not a whole number of periods in 2 s) and a 5 m/s² one at
    1000 Hz, against the closed form:

    >>> t = np.arange(51200) / 25600.0
    >>> acc = 10 * np.cos(2 * np.pi * 21.3 * t + 1) + 5 * np.sin(2 * np.pi * 1000 * t) + 0.3
    >>> r = band_rms(acc, 25600.0)
    >>> truth = [np.hypot(sine_band_rms(10, 21.3, q), sine_band_rms(5, 1000, q))
    ...          for q in QUANTITIES]
    >>> [abs(round(float(r[q] / s - 1), 5)) for q, s in zip(QUANTITIES, truth)]
    [0.0, 0.0, 0.0]
    """
    x = np.asarray(acceleration, dtype=float)
    if x.size < 16:
        raise ValueError(f"band_rms: {x.size} samples are too few for a spectrum")
    bands = BANDS if bands is None else {**BANDS, **bands}
    key = tuple((q, bands[q]) for q in QUANTITIES)
    count = -(-x.size // SEGMENT)
    size = x.size // count
    w = _weights(size, float(sample_rate), key)
    window = _hann(size)
    total = _hann_sum(size)
    power = np.zeros(size // 2 + 1)
    for k in range(count):
        part = x[k * size:(k + 1) * size]
        spectrum = scipy.fft.rfft((part - np.dot(part, window) / total) * window)
        power += spectrum.real ** 2 + spectrum.imag ** 2
    power /= count
    ms = w @ power
    first = int(np.floor(lowest_line * size / sample_rate)) - HANN_LOBE
    lines, under = _lines(power, count, first)
    floor = np.sqrt(np.maximum(ms - w[:, lines] @ (power[lines] - under), 0.0))
    return BandRMS(*np.sqrt(np.maximum(ms, 0.0)).tolist(), floor=dict(zip(QUANTITIES,
                                                                           floor.tolist())))


HANN_LOBE = 2
"""Half-width of the Hann window's main lobe, in bins: a line's power lies within it."""


@lru_cache(maxsize=64)
def _blocks(bins: int) -> tuple[np.ndarray, np.ndarray, tuple]:
    """The blocks of :data:`FLOOR_BLOCK` over bins 1 … ``bins`` − 1 (a last block shorter than
    the least joins the one before it): each one's first bin and size, and the slice and the
    rank that give its :data:`FLOOR_QUANTILE` quantile."""
    least, octave = FLOOR_BLOCK
    edges = [1]
    while edges[-1] < bins:
        edges.append(min(max(edges[-1] + least, int(edges[-1] * 2 ** octave)), bins))
    if len(edges) > 2 and edges[-1] - edges[-2] < least:
        del edges[-2]
    starts, sizes = np.array(edges[:-1]), np.diff(edges)
    starts.flags.writeable = sizes.flags.writeable = False
    ranks = []
    for a, n in zip(edges[:-1], sizes.tolist()):
        stride = FLOOR_STRIDE if n > 256 else 1
        ranks.append((slice(a, a + n, stride), int(FLOOR_QUANTILE * ((n - 1) // stride))))
    return starts, sizes, tuple(ranks)


def _lines(power: np.ndarray, segments: int, first: int) -> tuple[np.ndarray, np.ndarray]:
    """The bins of a periodogram's lines and the floor under each (:func:`broadband_floor`)."""
    starts, sizes, ranks = _blocks(power.size)
    factor = FLOOR_LINE * segments / gammaincinv(segments, FLOOR_QUANTILE)
    level = np.array([np.partition(power[part], k)[k] for part, k in ranks]) * factor
    line = power[1:] > np.repeat(level, sizes)
    line[:max(first - 1, 0)] = False
    at = np.flatnonzero(line) + 1
    block = np.searchsorted(starts, at, "right") - 1
    kept = np.add.reduceat(power, starts) - np.bincount(block, weights=power[at],
                                                         minlength=starts.size)
    count = sizes - np.bincount(block, minlength=starts.size)
    return at, (kept / np.maximum(count, 1))[block]


def broadband_floor(power, segments: int = 1, first: int = 1) -> np.ndarray:
    """The broadband floor of a Hann-windowed periodogram, bin by bin: its power less its
    lines.

    The bins (but the mean's, bin 0) are taken in blocks (:data:`FLOOR_BLOCK`, narrow enough
    that a floor rising or falling with frequency is level across one). A block's floor
    level is its :data:`FLOOR_QUANTILE` quantile over the quantile of the floor's own
    distribution (a bin of Gaussian noise, averaged over m segments, is Γ(m)/m-distributed
    about its mean: exponential for one [1]_). A bin above :data:`FLOOR_LINE` times that
    level, at or above bin ``first``, is a line's (an engine order's, a tone's); the floor is
    every other bin's own power and, under a line, the mean of its block's other bins. So
    the floor is estimated where a band reading uses it, between the lines, whatever its
    spectrum (white, rising with frequency, confined to low frequencies); below ``first``
    everything is floor, as no line lies there.

    Parameters
    ----------
    power : ndarray
        ``|W_j|²``, bins 0 … N/2 of an rfft, averaged over ``segments``. [record unit² · s]
    segments : int
        m, the periodograms averaged.
    first : int
        The lowest bin a line can reach.

    Returns
    -------
    ndarray
        The floor's power in every bin, shaped as ``power`` (0 in bin 0).

    References
    ----------
    .. [1] J. S. Bendat, A. G. Piersol, Random Data, 4th ed., Wiley, 2010, §8.5.4 (the
           periodogram's χ² distribution with 2m degrees of freedom).

    Examples
    --------
    White noise of unit variance over 2¹⁶ samples, and a 5 units sine at bin 1000.3 on it:
    the floor is the noise's own (σ² Σw² per bin: 0.375 N for a Hann window; its mean over
    32 768 bins within 0.6 %) with or without the sine.

    >>> rng = np.random.default_rng(0)
    >>> n = 2 ** 16
    >>> x = rng.standard_normal(n)
    >>> def power(y):
    ...     return np.abs(np.fft.rfft(y * _hann(n))) ** 2
    >>> t = np.arange(n)
    >>> sine = x + 5 * np.cos(2 * np.pi * 1000.3 * t / n)
    >>> [round(float(broadband_floor(power(y)).mean() / (0.375 * n)), 2) for y in (x, sine)]
    [1.01, 1.01]
    """
    power = np.asarray(power, dtype=float)
    lines, under = _lines(power, segments, first)
    floor = power.copy()
    floor[0] = 0.0
    floor[lines] = under
    return floor


@lru_cache(maxsize=64)
def white_noise_rms(sample_rate: float, quantity: str, band: Band | None = None) -> float:
    """The band reading of white noise of unit standard deviation sampled at f_s.

    .. math:: X_n = \\sqrt{\\frac{2}{f_s}\\int_0^{f_s/2} g_n(f)\\,df}

    Returns
    -------
    float
        [1], [s], [s²] per unit of the noise for a, v, x.

    Examples
    --------
    Sampled at 25.6 kHz, 1.4–8000 Hz holds 65 % of white noise's power (8000/12800 and the
    low-pass edge's skirt):

    >>> round(white_noise_rms(25600.0, "a") ** 2, 3)
    0.646
    """
    f = np.geomspace(1e-3, sample_rate / 2, 200001)
    g = meter_gain(f, quantity, band) ** 2
    return float(np.sqrt(2 / sample_rate * np.trapezoid(g, f)))


TAPER = 0.1
"""Share of a record tapered (and left out) at each end by :func:`band_signals`."""


@lru_cache(maxsize=16)
def _response(length: int, sample_rate: float, band: Band, quantity: str) -> np.ndarray:
    """|H(f)|/(2πf)ⁿ on the bins of an rfft of ``length`` samples (0 at f = 0), the modulus
    of the band's H(f)/(i2πf)ⁿ, whose phase is (−i)ⁿ whatever f (:data:`_PHASE`): a real
    array, which a spectrum is multiplied by at half a complex one's cost; cached, as a
    record's channels are cut alike."""
    h = meter_gain(np.fft.rfftfreq(length, 1.0 / sample_rate), quantity, band)
    h.flags.writeable = False
    return h


_PHASE = (1.0, -1j, -1.0)
"""1/iⁿ, the phase of n integrations in the frequency domain."""


@dataclass(frozen=True)
class BandSignals(Record):
    """Band-limited acceleration, velocity and displacement of one record as time signals
    (:func:`band_signals`)."""

    time: np.ndarray
    """Of each sample, from the record's first sample. [s]"""
    signals: dict
    """Each quantity's signal on ``time``. [m/s², m/s, m]"""

    def __getitem__(self, quantity: str) -> np.ndarray:
        return self.signals[quantity]


def band_signals(acceleration, sample_rate: float, quantities=QUANTITIES, *,
                 bands: dict | None = None, periodic: bool = False,
                 taper: float = TAPER) -> BandSignals:
    """The band-limited acceleration, velocity and displacement as time signals.

    The record less its mean is transformed once, multiplied in the frequency domain by each
    band's H(f)/(i2πf)ⁿ and transformed back. A band edge at 1.4 Hz rings for about a
    second, as long as a record, so a signal is exact only where the record's periodic
    extension is seamless: a record cut to whole periods (``periodic``: a steady regime cut at
    its working cycles' TDC marks) is transformed as it is and comes back whole, on the next
    length the FFT factors fast (:func:`scipy.fft.next_fast_len`): the spectrum is padded
    with zeros and its Nyquist bin split between ±f_s/2, which is the periodic signal's
    band-limited interpolation, exact at every point, and spares the slow inverse transforms
    of lengths with large prime factors (a record cut to whole cycles has any length; 51 197
    samples transform 15 times slower than 51 200). Otherwise it is tapered (cosine ends over
    ``taper`` of its length), padded with zeros to at least twice its length and cut back to
    its untapered middle: no wrap-around and no drift, but the taper's own low frequencies
    reach the displacement (its peaks then err by up to 10–15 % below 20 Hz). Several records
    of one length (a recording's channels) are transformed together (:func:`_spectra`).

    Parameters
    ----------
    acceleration : array_like
        One record, or several of one length as rows. [m/s²]
    sample_rate : float
        [Hz]
    quantities : sequence of {"a", "v", "x"}
    bands : dict, optional
        Band of each quantity (default :data:`BANDS`).
    periodic : bool, keyword-only
        The record spans whole periods of everything it holds.
    taper : float, keyword-only
        Share tapered at each end of a non-periodic record (0 < taper < 0.5).

    Returns
    -------
    BandSignals
        The whole period (periodic, at a rate raised by less than a few per cent) or the
        record's middle (1 − 2 taper of it, at its own samples); of several records, each
        quantity's signals as rows.

    Examples
    --------
    Ten periods of a 10 m/s² sine at 50 Hz integrated twice: 10/(2π·50)² = 101.3 µm:

    >>> t = np.arange(5120) / 25600.0
    >>> s = band_signals(10 * np.cos(2 * np.pi * 50 * t), 25600.0, periodic=True)
    >>> round(float(s["x"].max() * 1e6), 2), round(float(s["x"].min() * 1e6), 2)
    (101.32, -101.32)
    """
    bands = BANDS if bands is None else {**BANDS, **bands}
    x = np.asarray(acceleration, dtype=float)
    size = x.shape[-1]
    edge = 0 if periodic else int(round(taper * size))
    w = np.ones(size)
    if edge > 0:
        ramp = 0.5 - 0.5 * np.cos(np.pi * np.arange(edge) / edge)
        w[:edge], w[size - edge:] = ramp, ramp[::-1]
    length = size if periodic else scipy.fft.next_fast_len(2 * size, real=True)
    back = scipy.fft.next_fast_len(size, real=True) if periodic else length
    spectrum = _spectra([(r - r.mean()) * w for r in np.atleast_2d(x)], length)
    if back > length and length % 2 == 0:
        spectrum[:, -1] *= 0.5
    keep = slice(0, back) if periodic else slice(edge, size - edge)
    scale = back / length
    signals = {q: scipy.fft.irfft(spectrum * (_response(length, float(sample_rate), bands[q], q)
                                              * (_PHASE[INTEGRATIONS[q]] * scale)), back)[:, keep]
               for q in quantities}
    if x.ndim == 1:
        signals = {q: s[0] for q, s in signals.items()}
    step = size / back if periodic else 1.0
    return BandSignals(np.arange(keep.start, keep.stop) * (step / sample_rate), signals)


def _spectra(records: list[np.ndarray], length: int) -> np.ndarray:
    """The rfft of each record at ``length`` (zero-padded), as rows.

    Where ``length`` is not one the FFT factors fast (a record cut to whole cycles: its
    transform runs Bluestein's algorithm, a complex transform whatever the input), a real
    transform is packed into a complex one [1]_. Of an even length N, each record's even and
    odd samples are one complex record z_n = x_{2n} + i x_{2n+1} of N/2 samples, whose
    transform Z gives the record's: X_k = E_k + e^{−2πik/N} O_k, E_k = (Z_k + Z̄_{−k})/2,
    O_k = (Z_k − Z̄_{−k})/(2i) (the transforms of the even and the odd samples), k = 0 … N/2
    (Z periodic in N/2), which halves the cost. Of an odd length, two real records x, y share
    one complex transform Z of x + iy: X_k = (Z_k + Z̄_{−k})/2, Y_k = (Z_k − Z̄_{−k})/(2i), and
    an odd record left over is transformed as a complex one. Either way each spectrum comes
    within a few units of the last place of the largest record's, and the records are
    transformed in one call, which prepares the length's transform (its chirp and the chirp's
    spectrum) once.

    References
    ----------
    .. [1] W. H. Press et al., Numerical Recipes, 3rd ed., Cambridge, 2007, §12.3.1 (two
           real FFTs for the price of one complex one; one real FFT of 2N points by a complex
           one of N).
    """
    if scipy.fft.next_fast_len(length, real=True) == length:
        return np.array([scipy.fft.rfft(r, length) for r in records])
    bins = length // 2 + 1
    if length % 2 == 0:
        x = np.zeros((len(records), length))
        for row, r in zip(x, records):
            row[:len(r)] = r
        z = scipy.fft.fft(x.view(complex))          # x_{2n} + i x_{2n+1}, n < N/2
        ahead = np.concatenate([z, z[:, :1]], axis=1)                       # Z_k
        mirror = np.conj(np.concatenate([z[:, :1], z[:, :0:-1], z[:, :1]], axis=1))  # Z̄_{−k}
        odd = ahead - mirror
        odd *= -0.5j * np.exp(-2j * np.pi * np.arange(bins) / length)
        ahead += mirror
        ahead *= 0.5
        ahead += odd
        return ahead
    if len(records) == 1:
        return np.array([scipy.fft.rfft(records[0], length)])
    pairs = len(records) // 2
    z = scipy.fft.fft(np.array([records[k] + 1j * records[k + 1] for k in range(0, 2 * pairs, 2)]
                               + ([records[-1] + 0j] if len(records) % 2 else [])), length)
    mirror = np.conj(np.concatenate([z[:pairs, :1], z[:pairs, :length - bins:-1]], axis=1))
    out = np.empty((len(records), bins), complex)
    out[0:2 * pairs:2] = 0.5 * (z[:pairs, :bins] + mirror)
    out[1:2 * pairs:2] = -0.5j * (z[:pairs, :bins] - mirror)
    if len(records) % 2:
        out[-1] = z[-1, :bins]
    return out


@dataclass(frozen=True)
class Peaks(Record):
    """Peak and peak-to-peak of a band signal (:func:`peaks`)."""

    peak: float
    """Largest |s − mean|. [signal unit]"""
    peak_to_peak: float
    """max − min, the meter's "double amplitude". [signal unit]"""


def peaks(signal) -> Peaks:
    """Peak and peak-to-peak of a band signal (:func:`band_signals`).

    Examples
    --------
    >>> peaks(np.array([1.0, 3.0, -1.0, 1.0]))
    Peaks(peak=2.0, peak_to_peak=4.0)
    """
    s = np.asarray(signal, dtype=float)
    return Peaks(float(np.max(np.abs(s - s.mean()))), float(np.ptp(s)))
