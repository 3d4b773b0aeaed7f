"""Reading a torsiograph record: speed from the marks, the oscillations, the mean cycle.

A seismic torsiograph on the crankshaft nose records the nose's angular vibration relative to
an inertia mass on a soft spring; revolution (TDC) marks and time marks run beside it. From
one record of a steady regime:

- the speed from the marks: counted (:func:`speed_from_counts`, the manual's
  n = 60 N/(z T_mark)) or from the marks' times (:func:`revolutions`);
- the crank angle of every sample, by interpolating the revolution marks (:func:`crank_angle`)
  or, for a steady regime, by a smooth fit through them (:func:`steady_crank_angle`);
- the oscillations: alternating extrema with hysteresis (:func:`extrema`), each
  oscillation's half range with the baseline drift removed by interpolating the neighbouring
  extrema to the same instant (:func:`peak_amplitudes`), and their frequency by counting
  them (:func:`oscillation_frequency`, the manual's ν = 60 N_k/(m T_mark));
- the orders of the crank angle fitted with the drift
  (:func:`processing.torsional.orders.order_fit`),
  each corrected for the instrument (:func:`processing.torsional.seismic.torsiograph_response`), and
  the peak amplitudes of the mean working cycle they make, with the uncertainty of the largest
  (:func:`cycle_peaks`).

:func:`processing.torsional.torsiogram_analysis.analyse_trace` runs the whole chain on one record.
SI throughout: times in s, angles in rad, frequencies in Hz; a trace in its own unit
(V or mm of the recorder) until the static calibration scales it.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 7 ("Экспериментальное исследование крутильных колебаний коленчатого вала"):
       n = 60 N/(z T_отм), ν = 60 N_k/(m T_отм), A = l A_k, K = ν/n, peak amplitudes A_ij.
.. [2] W. Ker Wilson, Practical Solution of Torsional Vibration Problems, vol. 4, 3rd ed.,
       Chapman & Hall, 1965, ch. 27–28 (torsiographs, their calibration and records).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.diagnostics import InputError
from processing.oscillations.half_range import neighbour_baseline
from .orders import OrderFit
from processing.regression import LineFit, fit_line
from processing.result import Record

MARK_TOLERANCE = 0.25
"""Largest relative departure of a mark interval from the record's median interval: beyond
it a mark was missed or doubled (a steady regime's revolutions differ by a few %)."""

EXTREMUM_THRESHOLD = 0.2
"""Hysteresis of :func:`extrema` as a share of the periodic part's peak-to-peak range: a
swing smaller than this is a ripple on an oscillation, not an oscillation of its own."""

CYCLE_POINTS = 1024
"""Points per working cycle on which the mean cycle's extrema are searched (a third of a
degree for a four-stroke cycle; each extremum is refined between them)."""


# ------------------------------------------------------------------------ speed from marks

def speed_from_counts(revolutions, marks, mark_period):
    """Crank speed from a record's counts, the manual's n = 60 N/(z T_mark).

    .. math:: \\omega = \\frac{2\\pi N}{z\\,T_{mark}} \\quad
              \\left(n = \\frac{60 N}{z T_{mark}}\\ \\text{min}^{-1}\\right)

    Parameters
    ----------
    revolutions : float or ndarray
        N, revolutions counted between TDC marks. [1]
    marks : float or ndarray
        z, time marks over those N revolutions. [1]
    mark_period : float or ndarray
        T_mark, period of the time marks. [s]

    Returns
    -------
    float or ndarray
        ω. [rad/s]

    Examples
    --------
    20 revolutions over 60 marks of 0.01 s: n = 2000 min⁻¹.

    >>> round(speed_from_counts(20, 60, 0.01) * 30 / np.pi, 9)
    2000.0
    """
    return 2 * np.pi * revolutions / (marks * mark_period)


def frequency_from_counts(oscillations, marks, mark_period):
    """Oscillation frequency from a record's counts, the manual's ν = 60 N_k/(m T_mark).

    .. math:: \\nu = \\frac{N_k}{m\\,T_{mark}}

    Parameters
    ----------
    oscillations : float or ndarray
        N_k, oscillations counted. [1]
    marks : float or ndarray
        m, time marks over those oscillations. [1]
    mark_period : float or ndarray
        T_mark. [s]

    Returns
    -------
    float or ndarray
        ν (× 60 for the manual's oscillations per minute). [Hz]

    Examples
    --------
    >>> round(frequency_from_counts(40, 20, 0.01), 9)
    200.0
    """
    return oscillations / (marks * mark_period)


@dataclass(frozen=True)
class Revolutions(Record):
    """Revolutions of a record from its TDC marks (:func:`revolutions`)."""

    mark_times: np.ndarray
    """Times of the marks used. [s]"""
    per_revolution: int
    """Marks per revolution."""
    count: float
    """Whole revolutions between the first and the last mark. [1]"""
    angular_speed: float
    """Mean speed over them: 2π·count/(t_last − t_first). [rad/s]"""
    speeds: np.ndarray
    """Speed of each revolution. [rad/s]"""

    @property
    def u_speed(self) -> float:
        """Type A u of the mean speed: the revolutions' scatter over √count (0 for one). [rad/s]"""
        return float(self.speeds.std(ddof=1) / np.sqrt(self.speeds.size)) \
            if self.speeds.size > 1 else 0.0


def revolutions(mark_times, *, per_revolution: int = 1) -> Revolutions:
    """Speed from the times of revolution (TDC) marks of a steady regime.

    Parameters
    ----------
    mark_times : array_like
        Times of the marks, increasing. [s]
    per_revolution : int, keyword-only
        Marks per crankshaft revolution (1 for a flywheel mark; a mark at every cylinder's
        TDC gives i/2 on a four-stroke engine).

    Returns
    -------
    Revolutions

    Raises
    ------
    InputError
        Fewer than one revolution of marks, or an interval more than :data:`MARK_TOLERANCE`
        off the median (a missed or doubled mark).

    Examples
    --------
    >>> r = revolutions(np.arange(11) * 0.03)            # 2000 min⁻¹
    >>> round(r.angular_speed * 30 / np.pi, 6), r.count
    (2000.0, 10.0)
    """
    t = np.asarray(mark_times, dtype=float)
    if t.size < per_revolution + 1:
        raise InputError(f"{t.size} revolution mark(s): at least one whole revolution "
                         f"({per_revolution + 1} marks) is needed",
                         "check the TDC channel and that the record spans several revolutions")
    gaps = np.diff(t)
    usual = np.median(gaps)
    off = np.abs(gaps / usual - 1)
    if off.max() > MARK_TOLERANCE:
        k = int(np.argmax(off))
        raise InputError(f"the revolution marks are irregular: the interval after the mark at "
                         f"t = {t[k]:.4g} s is {gaps[k] / usual:.2f} times the usual one (a mark "
                         f"missed or doubled, or the speed not steady)",
                         "check the TDC channel's level and marks per revolution, or cut the "
                         "record to a steady stretch")
    whole = (t.size - 1) // per_revolution * per_revolution
    t = t[:whole + 1]
    per_rev = t[::per_revolution]
    speeds = 2 * np.pi / np.diff(per_rev)
    count = whole / per_revolution
    return Revolutions(mark_times=t, per_revolution=per_revolution, count=float(count),
                       angular_speed=float(2 * np.pi * count / (t[-1] - t[0])), speeds=speeds)


def crank_angle(time, revs: Revolutions) -> np.ndarray:
    """Crank angle at the given times: 2π per revolution between the marks, linear in time
    between them, extended beyond the first and last mark at the mean speed. 0 at the first
    mark. [rad]

    Examples
    --------
    >>> r = revolutions([0.0, 0.1, 0.2])
    >>> np.round(crank_angle([-0.05, 0.05, 0.25], r) / np.pi, 9).tolist()
    [-1.0, 1.0, 5.0]
    """
    t = np.asarray(time, dtype=float)
    m = revs.mark_times
    angle = 2 * np.pi * np.arange(m.size) / revs.per_revolution
    inside = np.interp(t, m, angle)
    w = revs.angular_speed
    return np.where(t < m[0], (t - m[0]) * w, np.where(t > m[-1], angle[-1] + (t - m[-1]) * w,
                                                       inside))


STEADY_DEGREE = 2
"""Degree of the polynomial in time through the marks' angles of a steady regime: a mean
speed and a slow change of it."""


def steady_crank_angle(time, revs: Revolutions, *, degree: int = STEADY_DEGREE) -> np.ndarray:
    """Crank angle of a steady regime: a polynomial in time fitted through the marks' angles.

    Unlike :func:`crank_angle`, which runs linearly from mark to mark, the fit averages the
    marks' timing errors over the record (an edge timed to a fraction of a sample smears a
    high order's phase by 2π k n/60 times that error) and keeps the marked disc's own
    vibration out of the angle, so that the orders are taken against the mean rotation. 0 at
    the first mark. [rad]

    Parameters
    ----------
    time : array_like
        [s]
    revs : Revolutions
    degree : int, keyword-only
        Of the polynomial (lowered to what the marks allow: one less than their count).

    Examples
    --------
    Marks of 2000 min⁻¹ jittered by ±0.1 ms (±1.2° of crank angle): between them the
    stepwise angle is 1.6° off the mean rotation, the fitted one less than half that.

    >>> marks = np.arange(9) * 0.03 + np.array([1, -1, 1, -1, 1, -1, 1, -1, 1]) * 1e-4
    >>> t = np.linspace(0.0, 0.24, 7)
    >>> true = 2 * np.pi * (t - marks[0]) / 0.03
    >>> [round(float(np.degrees(np.abs(f(t, revolutions(marks)) - true)).max()), 1)
    ...  for f in (crank_angle, steady_crank_angle)]
    [1.6, 0.8]
    """
    t = np.asarray(time, dtype=float)
    m = revs.mark_times
    angle = 2 * np.pi * np.arange(m.size) / revs.per_revolution
    fit = np.polynomial.Polynomial.fit(m, angle, min(degree, m.size - 1))
    return fit(t) - fit(m[0])


# ------------------------------------------------------------------------ oscillations

def extrema(x, threshold: float) -> tuple[np.ndarray, np.ndarray]:
    """Alternating maxima and minima of a smooth record, ignoring ripples.

    A maximum is kept once the record has fallen ``threshold`` below it, a minimum once it
    has risen ``threshold`` above it (a zig-zag with hysteresis): swings smaller than the
    threshold are ripples on an oscillation, not oscillations. The walk starts from the
    record's first sample as both the highest and the lowest value seen: the first extremum
    is the lowest (or highest) turn before the record's first swing of ``threshold``,
    whichever way a ripple before it first turned; the first sample itself is not an
    extremum (the record may have been falling or rising before it). The last candidate is
    kept if the record has left it by ``threshold`` at its last sample, and left out
    otherwise.

    Parameters
    ----------
    x : array_like
        The record (smooth: low-passed). [any unit]
    threshold : float
        The hysteresis, > 0. [unit of x]

    Returns
    -------
    index : ndarray of int
        Sample index of each extremum, increasing.
    kind : ndarray of int
        +1 for a maximum, −1 for a minimum, alternating.

    Examples
    --------
    >>> t = np.linspace(0, 2, 801)
    >>> i, k = extrema(np.sin(2 * np.pi * t) + 0.05 * np.sin(2 * np.pi * 25 * t), 0.5)
    >>> k.tolist(), np.round(t[i], 2).tolist()
    ([1, -1, 1, -1], [0.25, 0.75, 1.25, 1.75])

    A record that starts on a ripple falling into its first minimum: the minimum is kept,
    whether the ripple first turns up or down.

    >>> i, k = extrema(np.array([0.1, 0.12, 0.05, 0.0, 0.5, 1.0, 0.4, 0.0, 0.6]), 0.5)
    >>> i.tolist(), k.tolist()
    ([3, 5, 7], [-1, 1, -1])
    """
    x = np.asarray(x, dtype=float)
    d = np.diff(x)
    turn = np.flatnonzero(np.sign(d[1:]) * np.sign(d[:-1]) < 0) + 1
    if turn.size == 0:
        return np.empty(0, int), np.empty(0, int)
    # the zig-zag walks the turning points as Python numbers (numpy scalars cost a
    # microsecond an operation, and a long record turns thousands of times)
    turns = zip(turn.tolist(), np.where(d[turn - 1] > 0, 1, -1).tolist(), x[turn].tolist())
    kept_i, kept_k = [], []
    start = float(x[0])
    low, high = (-1, start), (-1, start)       # (index, value); -1: the first sample
    best_i = -1
    for i, k, v in turns:
        if k > 0 and v > high[1]:
            high = (i, v)
        elif k < 0 and v < low[1]:
            low = (i, v)
        if high[1] - low[1] >= threshold:
            (first, first_k), (best_i, best_v) = (low, -1), high
            best_k = 1
            if high[0] < low[0]:
                (first, first_k), (best_i, best_v), best_k = (high, 1), low, -1
            if first[0] >= 0:
                kept_i.append(first[0])
                kept_k.append(first_k)
            break
    for i, k, v in turns:
        if k == best_k:
            if (v - best_v) * k > 0:
                best_i, best_v = i, v
        elif (best_v - v) * best_k >= threshold:
            kept_i.append(best_i)
            kept_k.append(best_k)
            best_i, best_k, best_v = i, k, v
    if best_i >= 0 and (best_v - x[-1]) * best_k >= threshold:
        kept_i.append(best_i)
        kept_k.append(best_k)
    return np.asarray(kept_i, dtype=int), np.asarray(kept_k, dtype=int)


@dataclass(frozen=True)
class Peaks(Record):
    """Peak amplitudes of one record (:func:`peak_amplitudes`)."""

    position: np.ndarray
    """Time (or crank angle) of each extremum. [s] or [rad]"""
    value: np.ndarray
    """The record at each extremum (refined between samples). [unit of the record]"""
    kind: np.ndarray
    """+1 maximum, −1 minimum."""
    baseline: np.ndarray
    """The opposite extrema on either side interpolated to this extremum's position (NaN at
    the ends). [unit of the record]"""
    amplitude: np.ndarray
    """A_i = |value − baseline|/2, the half range of each oscillation with the drift removed
    (NaN at the ends). [unit of the record]"""

    @property
    def largest(self) -> float:
        """The largest peak amplitude: the design value. [unit of the record]"""
        return float(np.nanmax(self.amplitude)) if np.isfinite(self.amplitude).any() else np.nan

    @property
    def index_of_largest(self) -> int:
        return int(np.nanargmax(self.amplitude))


def _refine(x, i):
    """Value and fractional position of a sampled extremum: the parabola through the sample
    and its two neighbours."""
    i = np.clip(i, 1, len(x) - 2)
    y0, y1, y2 = x[i - 1], x[i], x[i + 1]
    den = y0 - 2 * y1 + y2
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den != 0, 0.5 * (y0 - y2) / den, 0.0)
    s = np.clip(s, -0.5, 0.5)
    return y1 - 0.25 * (y0 - y2) * s, i + s


def peak_amplitudes(position, x, threshold: float) -> Peaks:
    r"""Each oscillation's half range, with the baseline drift removed.

    For every extremum S_i (at position s_i) of the record, the two opposite extrema beside
    it, h_i at s'_i and h_{i+1} at s'_{i+1}, are joined by a straight line taken to s_i: the
    drifting baseline at the same crank angle. The peak amplitude is half the distance from
    the extremum to that line:

    .. math:: A_i = \frac{1}{2}\left|S_i - \Big(h_i + (h_{i+1} - h_i)
              \frac{s_i - s'_i}{s'_{i+1} - s'_i}\Big)\right|

    the intent of the manual's formula for A_ij (lab 7, rendered garbled in the source; see
    FORMULAS.md). A linear drift's offset cancels exactly; its slope d′ moves the extrema off
    the oscillation's peaks, which shortens a sine's half range by the factor
    :math:`\sqrt{1 - \rho^2}`, ρ = d′/(2πνA) (ρ = 0.14: 1 %); a curved drift leaves
    :math:`d''\,(s'_{i+1} - s_i)(s_i - s'_i)/4`.

    Parameters
    ----------
    position : array_like
        Time (or crank angle) of each sample, uniformly spaced. [s] or [rad]
    x : array_like
        The record, smooth (low-passed, corrected). [any unit]
    threshold : float
        Hysteresis of :func:`extrema`. [unit of x]

    Returns
    -------
    Peaks

    Examples
    --------
    A sine of amplitude 2 on a drift twice its size (ρ = 0.03), and on one whose slope is a
    quarter of the sine's (ρ = 0.24: √(1 − ρ²) = 0.971):

    >>> t = np.linspace(0, 1, 2001)
    >>> p = peak_amplitudes(t, 2 * np.sin(2 * np.pi * 10 * t) + 4 * t, 1.0)
    >>> round(p.largest, 4), round(float(np.nanmin(p.amplitude)), 4)
    (1.999, 1.999)
    >>> round(peak_amplitudes(t, 2 * np.sin(2 * np.pi * 10 * t) + 30 * t, 1.0).largest, 4)
    1.9422
    """
    pos = np.asarray(position, dtype=float)
    x = np.asarray(x, dtype=float)
    idx, kind = extrema(x, threshold)
    if idx.size == 0:
        empty = np.empty(0)
        return Peaks(empty, empty, np.empty(0, int), empty, empty)
    value, fractional = _refine(x, idx)
    step = (pos[-1] - pos[0]) / (pos.size - 1)
    s = pos[0] + fractional * step
    base = neighbour_baseline(s, value)
    return Peaks(position=s, value=value, kind=kind, baseline=base,
                 amplitude=0.5 * np.abs(value - base))


def oscillation_frequency(times) -> tuple[float, LineFit]:
    """Frequency of the oscillations from the times of their alternating extrema.

    The digital form of the manual's count ν = N_k/(m T_mark): the extrema's times against
    their count of half periods are fitted by a straight line (every extremum counts, not
    only the first and the last); its slope is the half period.

    .. math:: t_j = t_0 + j\\,\\frac{1}{2\\nu}

    Parameters
    ----------
    times : array_like
        Times of the alternating extrema (:attr:`Peaks.position`). [s]

    Returns
    -------
    nu : float
        [Hz]
    fit : LineFit
        The fit (its slope, the half period, with its type A u). [s]

    Examples
    --------
    >>> nu, fit = oscillation_frequency(np.arange(9) / 400.0)
    >>> round(nu, 9), fit.dof
    (200.0, 7)
    """
    t = np.asarray(times, dtype=float)
    if t.size < 3:
        raise InputError(f"{t.size} extrema: an oscillation frequency needs at least three",
                         "record longer, or check that the trace oscillates")
    fit = fit_line(np.arange(t.size, dtype=float), t)
    return 1 / (2 * fit.slope), fit



@dataclass(frozen=True)
class Denoised(Record):
    """A record with its white noise's spectral floor taken out (:func:`denoise`)."""

    value: np.ndarray
    """The record, denoised. [record unit]"""
    noise: float
    """σ of the white noise in the record within the band, from the spectrum's floor.
    [record unit]"""
    noise_left: float
    """σ of that noise left in ``value`` (the gain's share of it). [record unit]"""


def denoise(x, sample_rate: float, *, band: float, reach: float | None = None) -> Denoised:
    r"""Take a record's white noise out by spectral subtraction (a Wiener-type gain per bin).

    The periodogram's floor N is the median of :math:`|X_k|^2` over the bins up to ``reach``
    over ln 2 (the median of an exponential law: a crankshaft's orders and a slow drift hold
    few of a record's bins, white noise every one). Each bin keeps the share of its power
    that stands above the floor, and every bin above ``band`` is cut:

    .. math:: G_k = \max\left(0,\ 1 - \frac{N}{|X_k|^2}\right), \qquad
              \hat x = \mathcal F^{-1}(G_k X_k).

    A component well above the floor passes whole (its peaks keep their height: no fixed
    low-pass edge cuts an oscillation the record holds, in or between the orders), a bin
    of noise alone goes or shrinks. The noise left has the variance
    :math:`(2/n^2)\sum_k G_k^2 N_k`, with :math:`N_k = N` in the bins above the universal
    threshold N ln m (m bins below ``band``: noise alone passes it once in a record), which
    hold content, and :math:`N_k = |X_k|^2` below it, where what passed is taken for noise.

    Parameters
    ----------
    x : array_like
        The record, uniformly sampled (its drift best taken out). [any unit]
    sample_rate : float
        [Hz]
    band : float, keyword-only
        Highest frequency the record's content may reach: the bins above it are cut. [Hz]
    reach : float, keyword-only, optional
        Highest frequency the noise reaches, the floor taken over the bins below it (default:
        the Nyquist frequency; an upsampled record's: its own sample rate's). Taken over the
        whole band, not the content's, the floor stays the noise's on a short record, whose
        few bins the content may fill. [Hz]

    Returns
    -------
    Denoised

    References
    ----------
    .. [1] S. F. Boll, "Suppression of acoustic noise in speech using spectral
           subtraction", IEEE Trans. ASSP 27 (1979) 113–120, doi:10.1109/TASSP.1979.1163209.

    Examples
    --------
    A 50 Hz sine of amplitude 1 in white noise of σ 0.1, its content below 500 Hz: the noise
    left is a quarter of what came in, as stated.

    >>> rng = np.random.default_rng(1); t = np.arange(4000) / 4000.0
    >>> sine = np.sin(2 * np.pi * 50 * t)
    >>> d = denoise(sine + 0.1 * rng.standard_normal(t.size), 4000.0, band=500.0)
    >>> round(d.noise, 3), round(d.noise_left, 3), round(float(np.std(d.value - sine)), 3)
    (0.098, 0.024, 0.025)
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    spectrum = np.fft.rfft(x)
    f = np.fft.rfftfreq(n, 1 / sample_rate)
    inside = (f > 0) & (f <= band)
    noisy = (f > 0) & (f <= (sample_rate / 2 if reach is None else reach))
    power = np.abs(spectrum) ** 2
    floor = float(np.median(power[noisy]) / np.log(2)) if noisy.any() else 0.0
    gain = np.zeros(f.size)
    gain[f == 0] = 1.0
    with np.errstate(divide="ignore"):
        gain[inside] = np.clip(1 - floor / power[inside], 0, None)
    noise = float(np.sqrt(2 * floor * noisy.sum())) / n
    kept = gain[inside] ** 2 * power[inside]
    content = power[inside] > floor * np.log(max(inside.sum(), 2))
    left = float(np.sqrt(2 * np.sum(np.where(content, gain[inside] ** 2 * floor, kept)))) / n
    return Denoised(np.fft.irfft(spectrum * gain, n), noise, left)


def half_range_u(peaks: Peaks, noise: float) -> float:
    r"""Standard uncertainty of the largest peak amplitude from noise of σ ``noise`` at the
    extrema, independent from one to the next (half a period apart):

    .. math:: u(A) = \frac{\sigma}{2}\sqrt{1 + (1 - w)^2 + w^2}, \qquad
              w = \frac{s_i - s'_i}{s'_{i+1} - s'_i},

    widened for the choice of the largest among m oscillations as large as it within that
    u (each could have been it): by the expected largest of m standard normal deviates,
    :math:`\sqrt{2 \ln m}`, as a bias added in quadrature. [unit of the record]

    Examples
    --------
    >>> p = peak_amplitudes(np.arange(9.0), np.array([1, -1] * 4 + [1.0]), 0.5)
    >>> round(half_range_u(p, 0.1), 4)
    0.1258
    """
    a = peaks.amplitude
    if not np.isfinite(a).any():
        return np.nan
    j = peaks.index_of_largest
    s0, s1, s2 = peaks.position[j - 1:j + 2]
    w = (s1 - s0) / (s2 - s0)
    u = 0.5 * noise * np.sqrt(1 + (1 - w) ** 2 + w ** 2)
    rivals = int(np.sum(a[np.isfinite(a)] >= a[j] - 2 * u))
    return float(u * np.sqrt(1 + 2 * np.log(max(rivals, 1))))


# ------------------------------------------------------------------------ the mean cycle

@dataclass(frozen=True)
class CyclePeaks(Record):
    """Peak amplitudes of the mean working cycle made by the fitted orders (:func:`cycle_peaks`)."""

    angle: np.ndarray
    """Crank angle over one working cycle. [rad]"""
    motion: np.ndarray
    """The orders, each multiplied by its gain, at those angles. [record unit]"""
    peaks: Peaks
    """Peak amplitudes of the cycle (positions in crank angle). [record unit]"""
    largest: float
    """The largest peak amplitude: the design value. [record unit]"""
    u_largest: float
    """Its standard uncertainty from the fit's noise (to first order: the extrema do not
    move with small changes of the coefficients). [record unit]"""
    u_white: float
    """The same as if the fit's residual were white noise: ``u_largest`` over it says how
    much a drift or a disturbance near the orders widened it. [record unit]"""
    dof: int
    """Degrees of freedom of ``u_largest`` (the fit's)."""


def cycle_peaks(fit: OrderFit, gain=None, *, strokes: int = 4,
                threshold: float = EXTREMUM_THRESHOLD,
                points: int = CYCLE_POINTS) -> CyclePeaks:
    r"""Peak amplitudes of the mean working cycle of a record, with the largest one's u.

    The fitted orders (each multiplied by ``gain``: the instrument's correction) are summed
    over three working cycles; the extrema of the middle one (hysteresis ``threshold`` of its
    range) give the peak amplitudes by :func:`peak_amplitudes`. The largest,

    .. math:: A = \tfrac12\left|x(s_1) - x(s_0) - (x(s_2) - x(s_0))
              \frac{s_1 - s_0}{s_2 - s_0}\right|,

    is linear in the coefficients (a, b) of the orders at the extrema's positions s_j (which do not
    move to first order), so its variance is gᵀ Σ g with g its gradient and Σ the fit's covariance
    (:attr:`processing.torsional.orders.OrderFit.covariance`). Averaged over every cycle of the
    record, the mean cycle's peaks are free of the upward bias the noise gives the largest of many
    single oscillations.

    Parameters
    ----------
    fit : OrderFit
    gain : array_like, optional
        Complex factor of each order (default 1).
    strokes : {4, 2}, keyword-only
        A working cycle of two revolutions or one.
    threshold : float, keyword-only
        Hysteresis as a share of the cycle's peak-to-peak range.
    points : int, keyword-only
        Samples per working cycle.

    Returns
    -------
    CyclePeaks

    Examples
    --------
    3 cos 2θ + cos 6θ = 4 cos³ 2θ swings from 4 to −4 twice a revolution:

    >>> from processing.torsional.orders import order_fit
    >>> t = np.linspace(0, 1, 2001); th = 2 * np.pi * 16 * t
    >>> f = order_fit(t, th, 3 * np.cos(2 * th) + np.cos(6 * th), max_order=8)
    >>> c = cycle_peaks(f)
    >>> round(c.largest, 4), c.u_largest < 1e-6, c.peaks.position.size
    (4.0, True, 8)
    """
    cycle = 4 * np.pi if strokes == 4 else 2 * np.pi
    angle = np.arange(3 * points) * cycle / points
    x = fit.synthesize(angle, gain)
    span = np.ptp(x)
    peaks = peak_amplitudes(angle, x, threshold * span if span > 0 else 1.0)
    middle = (peaks.position >= cycle) & (peaks.position < 2 * cycle)
    middle_peaks = Peaks(*(getattr(peaks, f)[middle] for f in
                           ("position", "value", "kind", "baseline", "amplitude")))
    inner = np.flatnonzero(np.isfinite(peaks.amplitude) & middle)
    if inner.size == 0:
        return CyclePeaks(angle[points:2 * points] - cycle, x[points:2 * points],
                          middle_peaks, 0.0, 0.0, 0.0, fit.dof)
    j = inner[np.argmax(peaks.amplitude[inner])]
    s0, s1, s2 = peaks.position[j - 1:j + 2]
    w = (s1 - s0) / (s2 - s0)
    rows = fit.design([s0, s1, s2], gain)
    g = 0.5 * np.sign(peaks.value[j] - peaks.baseline[j]) * (rows[1] - (1 - w) * rows[0]
                                                              - w * rows[2])
    shifted = Peaks(middle_peaks.position - cycle, *(getattr(middle_peaks, f) for f in
                                                     ("value", "kind", "baseline", "amplitude")))
    return CyclePeaks(angle[points:2 * points] - cycle, x[points:2 * points], shifted,
                      float(peaks.amplitude[j]), float(np.sqrt(fit.variance(g)[0])),
                      float(np.sqrt(fit.variance(g, white=True)[0])), fit.dof)
