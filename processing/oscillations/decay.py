"""Free decay of an oscillator: its peaks, its logarithmic decrement and its damped frequency.

A body twisted and released rings down: x(t) = B(t) + A e^{−σt} cos(ω_d t + ψ), where B is
the record's baseline (the sensor's offset and drift, a slow creep of the part). Two
reductions are offered, with no knowledge of what rang:

* :func:`find_peaks` finds the extrema of the record (half a period apart) and the
  *half range* of each, its distance from the straight line through its two neighbours
  halved, which removes any linear drift; :func:`log_decrement` fits ln amplitude against the
  peak number over all peaks (:func:`~processing.regression.fit_line`, type A u from the
  residuals; over a record's half ranges by generalised least squares, for they share
  extrema) and tests a quadratic term (the decrement changing along the record).
* :func:`fit_damped_sine` fits the whole trace by least squares (the decrement δ, ω_d, the
  amplitude and phase, a polynomial baseline) and gives their covariance from the residuals;
  :func:`decrement_trend` refits with a quadratic log-envelope and tests whether δ changes
  along the record (damping that depends on the amplitude).
* :func:`analyse_decay` does both to a record and returns them together.

A record clipped by its recorder (its first swings cut at the converter's or the amplifier's
limit) is reduced around the clipped samples: each function takes their mask
(:func:`processing.inputs.record_quality.clipped_mask`); the extrema they touch are not used, and
the fits leave them out, so the decrement comes from what the record holds unharmed.

The half range of an exponentially decaying record is the amplitude times
(1 + cosh(δ/2))/2, the same factor for every peak, so ratios of half ranges are ratios of
amplitudes.

References
----------
.. [1] S. S. Rao, Mechanical Vibrations, 6th ed., Pearson, 2017, §2.6.4 (logarithmic
       decrement).
.. [2] P. C. Hansen, V. Pereyra, G. Scherer, Least Squares Data Fitting with Applications,
       Johns Hopkins, 2013, ch. 9 (variable projection for exponential models).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats
from scipy.ndimage import uniform_filter1d

from processing.diagnostics import Reason

from .half_range import neighbour_baseline
from processing.regression import CurvatureTest, LineFit, curvature_test, fit_line
from .savgol import coefficients, savgol
from processing.result import Record
from processing.uncertainty import Measured

PEAK_SNR = 5.0
"""Smallest half range used, in standard deviations of the record's noise σ. A peak refined
by a parabola through the samples of a quarter period (25 at 100 samples a period) carries
about 0.3 σ, a half range about 0.2 σ: its logarithm is then known to about 4 %."""

BAND = 5.0
"""Hysteresis of the lobe detector, in noise standard deviations: a lobe starts when the
record leaves the baseline by more than this on the other side."""

FEW_PERIODS = 2.0
"""Periods a decay must stand :data:`PEAK_SNR` σ out of the noise, or last before the record
ends, for :attr:`RecordedDecay.short` to be False: below, δ rests on the first swing or two,
the line through the peaks has too few of them to check it, and a decrement changing with
the amplitude goes unseen. (A decrement of 0.89 at 30 dB stands out for 2.4 periods, and δ's
95 % interval still holds it in 96 % of records: ``python -m processing.bench --topic
damper``.)"""


def noise_sd(x, window: int | None = None, *, exclude=None) -> float:
    """Standard deviation of the noise on a smooth, well-sampled record.

    Without ``window``: from the median absolute deviation of second differences (white
    noise of σ gives Δ²x of σ√6; a smooth signal sampled ten or more times a period adds
    little). With ``window`` (odd, ≥ 7 samples, a small part of a period): from the median
    absolute deviation of the residuals of a cubic Savitzky–Golay smoothing over that many
    samples, divided by √(1 − h₀) (h₀ the smoother's own weight at the centre). The second
    form also holds for noise correlated over a few samples — a trace read off an image, one
    sample per pixel column, whose errors alternate from column to column, fools the first
    by a factor of six.

    ``exclude`` (a mask) leaves samples out of the median: a clipped stretch, whose held
    value has no noise.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(20000) / 2e4
    >>> x = np.sin(2 * np.pi * 50 * t) + 0.01 * rng.standard_normal(t.size)
    >>> round(noise_sd(x), 3), round(noise_sd(x, window=51), 3)
    (0.01, 0.01)
    """
    x = np.asarray(x, dtype=float)
    keep = np.ones(x.size, bool) if exclude is None else ~np.asarray(exclude, bool)
    if window is None or x.size <= max(int(window) | 1, 7):
        d2 = np.diff(x, 2)[keep[1:-1] & keep[:-2] & keep[2:]]
        return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6.0)) \
            if d2.size else 0.0
    window = max(int(window) | 1, 7)
    r = (x - savgol(x, window, 3))[keep]
    h0 = float(coefficients(window, 3)[window // 2])
    return float(1.4826 * np.median(np.abs(r - np.median(r))) / math.sqrt(1.0 - h0)) \
        if r.size else 0.0


RINGING_BLOCKS = 256
"""Blocks a record is cut into to find where its ringing ends (:func:`ringing_end`)."""

RINGING_SNR = 2.0
"""A block rings while its standard deviation stands this many noise σ out (a block of noise
alone, 16 samples or more, stays under 1.6 σ in 256)."""


def ringing_end(x) -> int:
    """One past the last sample of a record that still rings, with a margin.

    A recorder left running after the decay has died holds a long tail of noise: it tells
    nothing of the decay, swamps the spectrum that finds the period and costs the fits their
    time. The record is cut into :data:`RINGING_BLOCKS` blocks (at least 16 samples each);
    the last block whose standard deviation about its own mean stands :data:`RINGING_SNR`
    noise σ (:func:`noise_sd`) out ends the ringing, and as many samples again (at least four
    blocks) are kept after it: nothing the peaks or the fits could still use is cut.

    Parameters
    ----------
    x : array_like
        The record. [any unit]

    Returns
    -------
    int
        The length to keep (the whole record where it rings to its end).

    Examples
    --------
    >>> t = np.arange(300000) / 1e4
    >>> x = np.exp(-t) * np.sin(2 * np.pi * 20 * t)
    >>> x += 1e-3 * np.random.default_rng(0).standard_normal(t.size)
    >>> ringing_end(x)    # its std e^-t/√2 falls to 2σ at t = 5.9 s; as much again kept
    124126
    """
    x = np.asarray(x, dtype=float)
    block = max(16, x.size // RINGING_BLOCKS)
    count = x.size // block
    if count < 8:
        return x.size
    spread = x[:count * block].reshape(count, block).std(axis=1)
    loud = np.flatnonzero(spread > RINGING_SNR * noise_sd(x))
    if loud.size == 0:
        return x.size
    end = (loud[-1] + 1) * block
    return int(min(x.size, 2 * end + 4 * block))


def dominant_period(time, x) -> float:
    """Period of the strongest oscillation in a record (the peak of its zero-padded spectrum,
    below two cycles per record excluded as drift). [s]"""
    t, x = np.asarray(time, dtype=float), np.asarray(x, dtype=float)
    dt = float(np.median(np.diff(t)))
    y = x - np.polyval(np.polyfit(t - t[0], x, 1), t - t[0])
    n = 8 * int(2 ** math.ceil(math.log2(y.size)))
    spectrum = np.abs(np.fft.rfft(y * np.hanning(y.size), n))
    f = np.fft.rfftfreq(n, dt)
    spectrum[f < 2.0 / (t[-1] - t[0])] = 0.0
    return 1.0 / float(f[np.argmax(spectrum)])


@dataclass(frozen=True)
class Peaks(Record):
    """Extrema of a decay record, refined between samples, and their half ranges.

    Attributes
    ----------
    time, value : ndarray
        Extremum times [s] and values [record's unit], in order, alternating in sign.
    sign : ndarray
        +1 at a maximum, −1 at a minimum.
    half_range : ndarray
        |value − the line through the two neighbouring extrema at this time| / 2 [record's
        unit]; NaN at the first and last extremum (one neighbour missing).
    used : ndarray of bool
        Extrema whose half range stands :data:`PEAK_SNR` noise σ out of the noise, from the
        first interior one on, up to the first that does not.
    noise : float
        Noise standard deviation of the record (:func:`noise_sd`). [record's unit]
    period : float
        Period from the spacing of the extrema (twice their median spacing). [s]
    clipped : ndarray of bool or None
        Extrema whose lobe holds a clipped sample (None: no mask was given).
    """

    time: np.ndarray
    value: np.ndarray
    sign: np.ndarray
    half_range: np.ndarray
    used: np.ndarray
    noise: float
    period: float
    clipped: np.ndarray | None = None

    @property
    def clear(self) -> int:
        """Extrema whose lobe holds no clipped sample."""
        return int(self.time.size - (0 if self.clipped is None else self.clipped.sum()))

    @property
    def amplitudes(self) -> np.ndarray:
        """Half ranges of the used extrema, half a period apart."""
        return self.half_range[self.used]

    @property
    def times(self) -> np.ndarray:
        """Times of the used extrema. [s]"""
        return self.time[self.used]


def _lobes(y: np.ndarray, band: float) -> list[tuple[int, int, int]]:
    """(first, last, sign) of each lobe of ``y`` beyond ±band, with hysteresis."""
    s = np.where(y > band, 1, np.where(y < -band, -1, 0))
    idx = np.flatnonzero(s)
    if idx.size == 0:
        return []
    signs = s[idx]
    starts = np.concatenate([[0], np.flatnonzero(np.diff(signs)) + 1])
    bounds = list(idx[starts]) + [y.size]
    return [(int(bounds[k]), int(bounds[k + 1]), int(signs[starts[k]]))
            for k in range(len(starts))]


def _refine(t: np.ndarray, x: np.ndarray, i: int, half: int) -> tuple[float, float]:
    """Vertex of a parabola fitted to the samples around index ``i`` (the sample itself if
    the vertex falls outside the window)."""
    a, b = max(i - half, 0), min(i + half + 1, x.size)
    if b - a < 3:
        return float(t[i]), float(x[i])
    tau = t[a:b] - t[i]
    c2, c1, c0 = np.polyfit(tau, x[a:b], 2)
    if c2 == 0.0:
        return float(t[i]), float(x[i])
    v = -c1 / (2.0 * c2)
    if not tau[0] <= v <= tau[-1]:
        return float(t[i]), float(x[i])
    return float(t[i] + v), float(c0 - c1 * c1 / (4.0 * c2))


def find_peaks(time, x, *, period: float | None = None, min_snr: float = PEAK_SNR,
               clipped=None) -> Peaks:
    """Extrema of a free-decay record and their drift-free half ranges.

    Parameters
    ----------
    time, x : array_like
        Sample times (uniform) [s] and the record [any unit].
    period : float, optional
        The oscillation's period if known; otherwise :func:`dominant_period`. [s]
    min_snr : float
        Smallest half range used, in noise standard deviations.
    clipped : array_like of bool, optional
        Samples at the recorder's limits (:func:`processing.inputs.record_quality.clipped_mask`):
        an extremum in a lobe that holds one is cut off, and so is the half range of its
        neighbours, which is taken from it; the extrema used start after the last of those.

    Returns
    -------
    Peaks

    Notes
    -----
    The noise σ is :func:`noise_sd` over an eighth of a period (from 56 samples a period;
    below, of the second differences). The baseline is taken out by a moving average over one
    period; the lobes of what is left
    beyond ±:data:`BAND` σ (with hysteresis, so noise does not split a lobe) each hold one
    extremum, refined by a parabola through the samples within an eighth of a period. The
    first lobe (cut by the record's start, or holding the release, whose kink a parabola does
    not follow) is dropped, and so is the last if the record ends while it still rings; a
    lobe shorter than an eighth of a period at the record's start (the moving average's edge
    over a held twist that drifts, which the smooth trace of a paper record shows beyond
    :data:`BAND` σ) goes before it. The
    half range of extremum k,

    .. math:: a_k = \\tfrac12\\left|x_k - \\Big(x_{k-1} + (x_{k+1} - x_{k-1})
              \\frac{t_k - t_{k-1}}{t_{k+1} - t_{k-1}}\\Big)\\right|,

    is free of a linear drift and, for an exponential decay, proportional to the amplitude.

    Examples
    --------
    >>> t = np.arange(4000) / 4e3
    >>> x = np.exp(-2.0 * t) * np.cos(2 * np.pi * 10 * t) + 0.3 * t
    >>> p = find_peaks(t, x)
    >>> round(p.period, 3), int(p.used.sum())
    (0.1, 17)
    >>> d = np.log(p.amplitudes[:-2] / p.amplitudes[2:])    # one period apart
    >>> bool(np.allclose(d, 2.0 * 0.1, rtol=2e-3))
    True
    """
    t, x = np.asarray(time, dtype=float), np.asarray(x, dtype=float)
    if t.shape != x.shape or t.ndim != 1:
        raise ValueError("find_peaks: time and x must be 1-D arrays of one length")
    dt = float(np.median(np.diff(t)))
    T0 = dominant_period(t, x) if period is None else float(period)
    n_T = max(int(round(T0 / dt)), 3)
    cut = np.zeros(x.size, bool) if clipped is None else np.asarray(clipped, bool)
    sigma = noise_sd(x, window=n_T // 8 if n_T >= 56 else None, exclude=cut)
    y = x - uniform_filter1d(x, n_T, mode="nearest")
    lobes = _lobes(y, BAND * sigma)
    while lobes and lobes[0][0] == 0 and lobes[0][1] < n_T // 8:
        lobes = lobes[1:]                   # the running mean's edge on a tilted held twist
    lobes = lobes[1:]
    if lobes and np.any(np.abs(y[-max(n_T // 4, 1):]) > BAND * sigma):
        lobes = lobes[:-1]                  # the record ends while it still rings
    half = max(n_T // 8, 1)
    found = []
    for a, b, sign in lobes:
        i = a + int(np.argmax(sign * y[a:b]))
        found.append((*_refine(t, x, i, half), sign, bool(cut[a:b].any())))
    mask = None if clipped is None else np.array([f[3] for f in found], bool)
    if not found:
        empty = np.array([])
        return Peaks(empty, empty, empty, empty, np.array([], bool), sigma, T0, mask)
    tk, xk, sk = (np.array(c) for c in list(zip(*found))[:3])
    half_range = 0.5 * np.abs(xk - neighbour_baseline(tk, xk))
    used = np.zeros(tk.size, bool)
    spacing = np.diff(tk)
    typical = float(np.median(spacing)) if spacing.size else T0 / 2
    touched = np.zeros(tk.size, bool) if mask is None else \
        np.convolve(mask, np.ones(3), mode="same") > 0
    first = int(np.flatnonzero(touched)[-1]) + 1 if touched.any() else 1
    for k in range(max(first, 1), tk.size - 1):
        regular = max(abs(spacing[k - 1] / typical - 1.0), abs(spacing[k] / typical - 1.0)) < 0.35
        if not (half_range[k] >= min_snr * sigma and regular):
            break
        used[k] = True
    return Peaks(tk, xk, sk, half_range, used, sigma, 2.0 * typical, mask)


@dataclass(frozen=True)
class DecrementFit(Record):
    """Logarithmic decrement from successive amplitudes by a straight line through ln A.

    Attributes
    ----------
    delta : float
        δ = −(slope of ln A against the period number), per full period. [1]
    u_delta : float
        Its standard uncertainty (type A, from the residuals). [1]
    dof : int
        n − 2.
    cycle : ndarray
        Period number of each amplitude (steps of 1/2 for alternate extrema).
    amplitude : ndarray
        The amplitudes fitted. [any unit]
    per_cycle : ndarray
        Decrement between neighbouring amplitudes, per period: ln(A_k/A_{k+1})/step. [1]
    line : LineFit
        The fit of ln A against the period number.
    curvature : CurvatureTest or None
        A quadratic term in ln A against the period number (≥ 4 amplitudes): a significant
        one says the decrement changes along the record.
    """

    delta: float
    u_delta: float
    dof: int
    cycle: np.ndarray
    amplitude: np.ndarray
    per_cycle: np.ndarray
    line: LineFit
    curvature: CurvatureTest | None

    def measured(self, *, u_b: float = 0.0) -> Measured:
        """δ as a measured input (type A with n − 2 degrees of freedom, optional type B)."""
        return self.line.measured_slope(u_b=u_b).scaled(-1.0)

    def u_from_readings(self, u_reading) -> float:
        r"""Standard uncertainty of δ from an uncertainty of each amplitude's reading (a
        ruler's division: type B), through the line's slope. [1]

        .. math:: u_B(\delta) = \sqrt{\sum_k \Big(\frac{n_k - \bar n}
                  {\sum_j (n_j - \bar n)^2}\,\frac{u_k}{A_k}\Big)^2}

        Examples
        --------
        >>> f = log_decrement([10.0, 5.0, 2.5])
        >>> round(f.u_from_readings(0.1), 6)        # √(0.01² + 0.04²)/2
        0.020616
        """
        n = self.cycle - self.cycle.mean()
        w = n / (n @ n) * np.broadcast_to(u_reading, self.amplitude.shape) / self.amplitude
        return float(math.sqrt(w @ w))

    def decrement_at(self, cycle):
        """Local decrement at period number ``cycle`` from the quadratic term,
        δ − 2 c₂ (n − n̄) (δ itself without one). [1]"""
        n = np.asarray(cycle, dtype=float)
        if self.curvature is None:
            return np.full_like(n, self.delta)
        return self.delta - 2.0 * self.curvature.c2 * (n - self.cycle.mean())

    def decrement_change(self) -> float:
        """Relative change of the decrement from the first amplitude to the last,
        −2 c₂ (n_last − n_first)/δ from the quadratic term (NaN without one)."""
        if self.curvature is None:
            return math.nan
        span = float(self.cycle[-1] - self.cycle[0])
        return -2.0 * self.curvature.c2 * span / self.delta


HALF_RANGE_CORRELATION = (1.0, 2.0 / 3.0, 1.0 / 6.0)
"""Correlation of the errors of successive half ranges at lags 0, 1, 2. Each is
(x_k − (x_{k−1} + x_{k+1})/2)/2 up to its sign, so neighbours share extrema: with
independent extremum errors of σ, the variance is 3σ²/8, the lag-one covariance σ²/4 and the
lag-two one σ²/16."""


def log_decrement(amplitudes, *, step: float = 1.0, half_ranges: bool = False) -> DecrementFit:
    """Logarithmic decrement by a least-squares line through ln A over all amplitudes.

    Parameters
    ----------
    amplitudes : array_like
        Successive amplitudes, ``step`` periods apart (1 for successive maxima, 1/2 for
        alternate extrema). [any unit, > 0]
    step : float
        Periods between neighbouring amplitudes.
    half_ranges : bool
        The amplitudes are the half ranges of successive extrema of a record
        (:attr:`Peaks.amplitudes`): their errors are correlated
        (:data:`HALF_RANGE_CORRELATION`) and of one size in the record's unit, so those of
        ln A grow as 1/A. The line and the quadratic term are then fitted by generalised
        least squares with that covariance (up to a scale taken from the residuals), which
        keeps u honest: ordinary least squares over half ranges states half of it.

    Returns
    -------
    DecrementFit

    Raises
    ------
    ValueError
        Fewer than three amplitudes, or one that is not > 0.

    Notes
    -----
    .. math:: \\ln A_k = \\ln A_0 - \\delta\\, n_k, \\qquad
              \\delta = \\ln\\frac{A_n}{A_{n+1}}

    (lab manual, lab 9, formula 10). Over all amplitudes the line averages the reading
    errors of each; its u is type A from the residuals (ν = n − 2).

    Examples
    --------
    >>> f = log_decrement(10.0 * np.exp(-0.5 * np.arange(5)))
    >>> round(f.delta, 12), f.dof
    (0.5, 3)
    >>> round(log_decrement(10.0 * np.exp(-0.25 * np.arange(6)), step=0.5,
    ...                     half_ranges=True).delta, 12)
    0.5
    """
    a = np.asarray(amplitudes, dtype=float).ravel()
    if a.size < 3:
        raise ValueError(f"log_decrement: {a.size} amplitude(s); at least 3 are needed")
    if not np.all(np.isfinite(a) & (a > 0)):
        raise ValueError("log_decrement: every amplitude must be a finite number > 0")
    n = step * np.arange(a.size)
    ln_a = np.log(a)
    if half_ranges:
        corr = np.zeros((a.size, a.size))
        for lag, c in enumerate(HALF_RANGE_CORRELATION):
            corr += c * (np.eye(a.size, k=lag) + (np.eye(a.size, k=-lag) if lag else 0))
        cov = corr / np.outer(a, a)
        line = _gls_line(n, ln_a, cov)
        curvature = _gls_curvature(n, ln_a, cov) if a.size >= 4 else None
    else:
        line = fit_line(n, ln_a)
        curvature = curvature_test(n, ln_a) if a.size >= 4 else None
    return DecrementFit(-line.slope, line.u_slope, line.dof, n, a, -np.diff(ln_a) / step, line,
                        curvature)


def _gls(columns: np.ndarray, y: np.ndarray, cov: np.ndarray):
    """Generalised least squares with the errors' covariance known up to a scale:
    coefficients, their covariance (scale from the whitened residuals), that scale s and
    the degrees of freedom."""
    L = np.linalg.cholesky(cov)
    Xw, yw = np.linalg.solve(L, columns), np.linalg.solve(L, y)
    coef, *_ = np.linalg.lstsq(Xw, yw, rcond=None)
    dof = y.size - columns.shape[1]
    r = yw - Xw @ coef
    s2 = float(r @ r) / dof if dof > 0 else 0.0
    return coef, s2 * np.linalg.inv(Xw.T @ Xw), math.sqrt(s2), dof


def _gls_line(x, y, cov) -> LineFit:
    """:class:`~processing.regression.LineFit` of y = a + b x by :func:`_gls`."""
    coef, c, s, dof = _gls(np.column_stack([np.ones_like(x), x]), y, cov)
    return LineFit(float(coef[1]), float(coef[0]), math.sqrt(c[1, 1]), math.sqrt(c[0, 0]),
                   float(c[0, 1]), s, dof, x.size)


def _gls_curvature(x, y, cov) -> CurvatureTest:
    """:class:`~processing.regression.CurvatureTest` of a quadratic term by :func:`_gls`."""
    span = float(x.max() - x.min())
    t = (x - x.mean()) / span
    coef, c, _, dof = _gls(np.column_stack([np.ones_like(t), t, t * t]), y, cov)
    u = math.sqrt(c[2, 2])
    p = float(2 * stats.t.sf(abs(coef[2]) / u, dof)) if u > 0 and dof > 0 else 1.0
    bend = abs(coef[2]) / 4 / abs(coef[1]) if coef[1] else math.inf
    return CurvatureTest(float(coef[2] / span**2), u / span**2, p, float(bend))


# ----------------------------------------------------------------------------- the whole trace

@dataclass(frozen=True)
class DampedSineFit(Record):
    """Least-squares fit of a damped sinusoid on a polynomial baseline to a record.

    .. math:: x(t) = e^{-\\frac{\\delta\\omega_d}{2\\pi}\\tau - \\gamma\\tau^2}
              (a\\cos\\omega_d\\tau + b\\sin\\omega_d\\tau) + \\sum_j c_j (\\tau/\\tau_{max})^j,
              \\qquad \\tau = t - t_0

    Attributes
    ----------
    delta : float
        Logarithmic decrement at t₀ (per period). [1]
    omega_d : float
        Damped angular frequency. [rad/s]
    gamma : float
        Curvature of the log-envelope (0 unless fitted): the decay rate grows by 2γ per
        second. [1/s²]
    amplitude : float
        √(a² + b²) at t₀. [record's unit]
    phase : float
        ψ with a cos ωτ + b sin ωτ = A cos(ωτ + ψ). [rad]
    baseline : ndarray
        c_j. [record's unit]
    start, span : float
        t₀ and τ_max. [s]
    params : tuple of str
        Names of the fitted parameters, in the order of ``cov``.
    cov : ndarray
        Their covariance: s²(JᵀJ)⁻¹, widened by (1 + ρ)/(1 − ρ) where the residuals' lag-one
        correlation ρ is significant (the noise is not white, or the model misses part of
        the record).
    residual_sd : float
        s. [record's unit]
    residual_correlation : float
        ρ, the residuals' lag-one autocorrelation.
    dof : int
        Samples less parameters.
    normal : ndarray
        (JᵀJ)⁻¹: the covariance per unit of residual variance, for a caller with a noise
        model of its own (:func:`processing.vision.video.period_of`).
    """

    delta: float
    omega_d: float
    gamma: float
    amplitude: float
    phase: float
    baseline: np.ndarray
    start: float
    span: float
    params: tuple
    cov: np.ndarray
    residual_sd: float
    residual_correlation: float
    dof: int
    normal: np.ndarray

    @property
    def baseline_order(self) -> int:
        """Degree of the baseline polynomial."""
        return self.baseline.size - 1

    def baseline_at(self, time):
        """The fitted baseline at ``time``. [record's unit]"""
        tau = np.asarray(time, dtype=float) - self.start
        return np.polyval(self.baseline[::-1], tau / self.span)

    def u(self, name: str) -> float:
        """Standard uncertainty of the parameter ``name`` ("delta", "omega_d", "gamma")."""
        i = self.params.index(name)
        return float(math.sqrt(self.cov[i, i]))

    def measured(self, name: str) -> Measured:
        """A fitted parameter as a measured input (type A, ν = samples − parameters)."""
        return Measured(float(getattr(self, name)), self.u(name), self.dof)

    @property
    def period(self) -> float:
        """T = 2π/ω_d. [s]"""
        return 2.0 * math.pi / self.omega_d

    def envelope(self, time):
        """A e^{−στ − γτ²}: the decaying amplitude at ``time``. [record's unit]"""
        tau = np.asarray(time, dtype=float) - self.start
        return self.amplitude * np.exp(-self.delta * self.omega_d / (2 * np.pi) * tau
                                       - self.gamma * tau**2)

    def decrement_at(self, time):
        """Local decrement 2π(σ + 2γτ)/ω_d at ``time``. [1]"""
        tau = np.asarray(time, dtype=float) - self.start
        return self.delta + 4.0 * np.pi * self.gamma * tau / self.omega_d

    def predict(self, time):
        """The fitted record at ``time``. [record's unit]"""
        tau = np.asarray(time, dtype=float) - self.start
        osc = self.envelope(time) * np.cos(self.omega_d * tau + self.phase)
        return osc + self.baseline_at(time)


def _baseline_columns(tau, span: float, order: int) -> np.ndarray:
    """The baseline's columns: (τ/τ_max)^j for j ≤ ``order``."""
    u = tau / span
    return np.column_stack([u**j for j in range(order + 1)])


def _columns(tau, delta, omega, gamma, base):
    env = np.exp(-delta * omega / (2 * np.pi) * tau - gamma * tau**2)
    return np.column_stack([env * np.cos(omega * tau), env * np.sin(omega * tau), base])


def _column_derivatives(tau, A, d, w, curved: bool) -> list[np.ndarray]:
    """∂/∂δ, ∂/∂ω_d (and ∂/∂γ) of the damped sine's two columns A₀ = e cos ω_dτ,
    A₁ = e sin ω_dτ (e = exp(−δω_dτ/2π − γτ²)): one (n, 2) array per parameter."""
    A0, A1 = A[:, 0], A[:, 1]
    rate = tau / (2 * np.pi)
    out = [np.column_stack([-w * rate * A0, -w * rate * A1]),
           np.column_stack([-d * rate * A0 - tau * A1, -d * rate * A1 + tau * A0])]
    if curved:
        out.append(np.column_stack([-tau**2 * A0, -tau**2 * A1]))
    return out


OUT_OF_REACH = 1e150
"""Residual of every sample at a trial point whose envelope overflows (:class:`_Projection`):
finite, so that the solver's norms stay finite, and larger than any record's."""


TOLERANCES = {"ftol": 1e-14, "xtol": 1e-12, "gtol": 1e-12}
"""Stopping tolerances of the projection's Levenberg–Marquardt solve (:func:`fit_damped_sine`),
tighter than :func:`scipy.optimize.least_squares`' 1e-8 as no joint refinement follows it:
a step that would lower ‖r‖² by less than ``ftol``·‖r‖² (the parameters within
(10⁻¹⁴ν)^½ of their standard uncertainties of the minimum, ‖r‖²/ν being the cost of one u:
10⁻⁶ u for a valve's hundred samples), or a kept step shorter than ``xtol`` relative to the
scaled parameters."""
MAX_STEPS = 200
"""Steps of :meth:`_Projection.minimise` before it gives up (to scipy's solver)."""


class _Projection:
    """Variable projection of K damped-sine fits at once, each of its own record on its own
    polynomial baseline: for the nonlinear parameters p = (δ, ω_d[, γ/``gamma_unit``]) of
    each, the residual r = P⊥x left by the linear least squares of the amplitude terms and
    its baseline, and its exact Jacobian, Golub and Pereyra's −P⊥(∂A/∂p)c − (A⁺)ᵀ(∂A/∂p)ᵀr
    (Hansen, Pereyra & Scherer [2]_, ch. 9). The last point's solution is kept: a solver
    asks for the residual and the Jacobian at the same point. Made by :func:`_projection`.

    The records are padded to the longest with samples that weigh nothing (τ = x = 0, no
    baseline, the oscillation masked). Each baseline's orthonormal basis Q_k (one QR) and its
    record without it, x̃ = x − Q_kQ_kᵀx, are made once. Only the two oscillating columns
    A₀ = e cos ω_dτ, A₁ = e sin ω_dτ (e = exp(−δω_dτ/2π − γτ²)) depend on p: each step
    orthogonalises them against Q_k and each other (Ã = Q̂R̂, Gram–Schmidt), and by
    Frisch–Waugh–Lovell r = x̃ − Q̂Q̂ᵀx̃, the amplitudes are R̂⁻¹Q̂ᵀx̃ and the oscillating rows
    of A⁺ are R̂⁻¹Q̂ᵀ, so that J = Q̂(Q̂ᵀD − R̂⁻ᵀV) − (D − Q_kQ_kᵀD) with D = (∂A/∂p)c and
    V = (∂A/∂p)ᵀr. Their derivatives are A₀, A₁ times τ/2π, τ and τ²
    (:func:`_column_derivatives`): D and V are formed from the oscillation y = c₀A₀ + c₁A₁,
    its quadrature c₁A₀ − c₀A₁ and the moments Σ τᵏ A_i r, without a column per parameter.
    A valve's ringing is a hundred samples, so the cost is in the number of array operations,
    not in their size: the K fits share each one."""

    def __init__(self, problems, tau, x, mask, base, curved: bool):
        self.problems, self.tau, self.x, self.mask = problems, tau, x, mask
        self.gamma_unit = 1.0 / np.array([_span(t) ** 2 for t, _, _ in problems]) \
            if curved else None
        self.powers = np.stack([tau / (2 * np.pi), tau, tau * tau])
        self.moments = self.powers.transpose(1, 2, 0).copy()          # (K, samples, 3)
        self.widths = np.array([order + 1 for _, _, order in problems])
        basis, R = np.linalg.qr(base)
        self.kept = np.arange(base.shape[2]) < self.widths[:, None]
        self.base = base * self.kept[:, None]                         # (K, samples, columns)
        self.basis = basis.transpose(0, 2, 1) * self.kept[..., None]  # Q_kᵀ
        self.base_inverse = _inverses(R, self.widths)
        self.free = x - self._projected(x[:, None])[:, 0]             # x̃ = P_k⊥x
        self._key, self._parts = None, (None, None)

    def _projected(self, rows):
        """``rows`` (K, m, samples) on each baseline: Q_kQ_kᵀ."""
        return (rows @ self.basis.transpose(0, 2, 1)) @ self.basis

    def solve(self, p):
        """The amplitudes c (K, 2), the residuals (K, samples) and their Jacobians
        (K, samples, parameters) at p (K, parameters)."""
        key = np.asarray(p, dtype=float).tobytes()
        if key == self._key:
            return self._solved
        p = np.asarray(p, dtype=float).reshape(self.widths.size, -1)
        curved = self.gamma_unit is not None
        d, w = p[:, :1], p[:, 1:2]
        g = p[:, 2:3] * self.gamma_unit[:, None] if curved else 0.0
        tau = self.tau
        with np.errstate(over="ignore", invalid="ignore"):
            env = np.exp(-d * w / (2 * np.pi) * tau - g * tau * tau)
            A = np.stack([env * np.cos(w * tau), env * np.sin(w * tau)], axis=1)
        A *= self.mask[:, None]
        # a trial step to an envelope that overflows over the record: its residual beyond
        # any other's makes the solver refuse the step and shorten it
        reached = np.isfinite(A).all(axis=(1, 2))
        if not reached.all():
            A[~reached] = 0.0
        q, r01, inv0, inv1 = _orthonormal(A - self._projected(A))
        qx = (q @ self.free[..., None])[..., 0]
        c1 = qx[:, 1] * inv1
        c = np.stack([(qx[:, 0] - r01 * c1) * inv0, c1], axis=1)              # R̂⁻¹Q̂ᵀx̃
        r = self.free - (qx[:, None] @ q)[:, 0]
        rate, tau, tau2 = self.powers
        y = (c[:, None] @ A)[:, 0]
        D = np.empty((len(p), p.shape[1], y.shape[1]))
        D[:, 0] = -w * rate * y
        D[:, 1] = -d * rate * y + tau * (c[:, 1:] * A[:, 0] - c[:, :1] * A[:, 1])
        m = (A * r[:, None]) @ self.moments                 # Σ τʲ A_i r: j = rate, τ, τ²
        V = np.empty((len(p), 2, p.shape[1]))
        V[:, :, 0] = -w * m[..., 0]
        V[:, 0, 1], V[:, 1, 1] = -d[:, 0] * m[:, 0, 0] - m[:, 1, 1], -d[:, 0] * m[:, 1, 0] + m[:, 0, 1]
        if curved:
            D[:, 2] = -self.gamma_unit[:, None] * tau2 * y
            V[:, :, 2] = -self.gamma_unit[:, None] * m[..., 2]
        Z = np.empty_like(V)                                                     # R̂⁻ᵀV
        Z[:, 0] = V[:, 0] * inv0[:, None]
        Z[:, 1] = (V[:, 1] - r01[:, None] * Z[:, 0]) * inv1[:, None]
        J = (q.transpose(0, 2, 1) @ (q @ D.transpose(0, 2, 1) - Z)
             - (D - self._projected(D)).transpose(0, 2, 1))
        if not reached.all():
            c[~reached], r[~reached], J[~reached], y[~reached] = \
                np.nan, OUT_OF_REACH, 0.0, np.nan
        self._key, self._solved, self._oscillation = key, (c, r, J), y
        self._columns = (A, D)
        return self._solved

    def coefficients(self, p) -> list[np.ndarray]:
        """Each fit's linear coefficients at p: its amplitudes, then its baseline's,
        B_k⁺(x − c₀A₀ − c₁A₁)."""
        c = self.solve(p)[0]
        rest = self.x - self._oscillation
        return [np.concatenate([c[k], self.base_inverse[k] @ (self.basis[k, :b] @ rest[k])])
                for k, b in enumerate(self.widths)]

    def residual(self, p):
        """The residual of a single fit (K = 1), for scipy's solver."""
        return self.solve(p)[1][0]

    def jacobian(self, p):
        return self.solve(p)[2][0]

    def _part(self, index: np.ndarray) -> _Projection:
        """The projection of the fits ``index`` alone, the one made last for the same ones
        (its arrays taken, no QR made again): a step solves only the fits still stepping,
        each as it would among all of them."""
        if len(index) == self.widths.size:
            return self
        if self._parts[0] is not None and np.array_equal(self._parts[0], index):
            return self._parts[1]
        part = object.__new__(_Projection)
        part.problems = [self.problems[k] for k in index]
        for name in ("tau", "x", "mask", "moments", "widths", "kept", "base", "basis",
                     "free"):
            setattr(part, name, getattr(self, name)[index])
        part.gamma_unit = None if self.gamma_unit is None else self.gamma_unit[index]
        part.powers = self.powers[:, index]
        part.base_inverse = [self.base_inverse[k] for k in index]
        part._key, part._parts = None, (None, None)
        self._parts = (index, part)
        return part

    def minimise(self, p0, scale) -> tuple[np.ndarray, np.ndarray]:
        """The p of least |r(p)|² of each fit, by Levenberg–Marquardt steps from ``p0``
        (K, parameters), and whether each converged.

        Each step solves (JₛᵀJₛ + μ diag JₛᵀJₛ) h = −Jₛᵀr in the variables scaled by
        ``scale`` (Jₛ = J diag ``scale``; μ starts at 10⁻⁶ of the largest diagonal term, a
        near Gauss–Newton step: the starting values are close), is kept where it lowers
        |r|², and μ follows the gain ratio ϱ of the actual to the predicted decrease
        L = hᵀ(μ diag·h − Jₛᵀr): μ·max(1/3, 1 − (2ϱ − 1)³) after a kept step, μ·ν (ν
        doubling) after a refused one (Madsen, Nielsen & Tingleff, Methods for non-linear
        least squares problems, DTU, 2004, alg. 3.16). A fit stops where L or a kept step
        falls below :data:`TOLERANCES` (converged), or after :data:`MAX_STEPS`, or where its
        step's matrix is singular (not: the caller falls back to scipy's MINPACK solver);
        the others step on. Two or three parameters: a hand-written step costs less than a
        general solver's set-up, and the K fits step together.
        """
        xtol, ftol = TOLERANCES["xtol"], TOLERANCES["ftol"]
        scale = np.asarray(scale, dtype=float)
        p = np.asarray(p0, dtype=float).copy()
        _, r, J = self.solve(p)
        cost = np.einsum("kn,kn->k", r, r)
        mu, nu = None, np.full(cost.size, 2.0)
        running, converged = np.ones(cost.size, bool), np.zeros(cost.size, bool)
        for _ in range(MAX_STEPS):
            Js = J * scale[:, None]
            H, g = Js.transpose(0, 2, 1) @ Js, np.einsum("knj,kn->kj", Js, r)
            diag = np.maximum(np.diagonal(H, axis1=1, axis2=2), np.finfo(float).tiny)
            mu = 1e-6 * diag.max(axis=1) if mu is None else mu
            h, solved = _solve_each(H + mu[:, None, None] * _diagonal(diag), -g)
            running &= solved
            predicted = np.einsum("kj,kj->k", h, mu[:, None] * diag * h - g)
            done = running & (predicted <= ftol * cost)
            converged |= done
            running &= ~done
            if not running.any():
                break
            run = np.flatnonzero(running)
            trial = p[run] + scale[run] * h[run]
            _, r_new, J_new = self._part(run).solve(trial)
            cost_new = np.einsum("kn,kn->k", r_new, r_new)
            better = cost_new < cost[run]
            kept = np.zeros(cost.size, bool)
            kept[run[better]] = True
            gain = np.zeros(cost.size)
            with np.errstate(divide="ignore", invalid="ignore"):
                gain[run] = (cost[run] - cost_new) / predicted[run]
            small = np.linalg.norm(h, axis=1) <= xtol * (np.linalg.norm(p / scale, axis=1)
                                                          + xtol)
            p[kept], r[kept], J[kept], cost[kept] = trial[better], r_new[better], \
                J_new[better], cost_new[better]
            converged |= kept & small
            running &= ~(kept & small)
            refused = running & ~kept
            mu = np.where(kept, mu * np.maximum(1.0 / 3.0, 1.0 - (2.0 * gain - 1.0) ** 3),
                          np.where(refused, mu * nu, mu))
            nu = np.where(kept, 2.0, np.where(refused, 2.0 * nu, nu))
        return p, converged


def _projection(problems, curved: bool = False) -> _Projection:
    """The :class:`_Projection` of ``problems``, each (τ, x, baseline degree), padded to the
    longest; with ``curved``, γ fitted too (in units of 1/τ_max², ``gamma_unit``)."""
    n = max(tau.size for tau, _, _ in problems)
    top = max(order for _, _, order in problems)
    tau, x = np.zeros((len(problems), n)), np.zeros((len(problems), n))
    mask, base = np.zeros((len(problems), n)), np.zeros((len(problems), n, top + 1))
    for k, (t, y, _) in enumerate(problems):
        tau[k, :t.size], x[k, :t.size], mask[k, :t.size] = t, y, 1.0
    u = tau / np.array([_span(t) for t, _, _ in problems])[:, None]
    for j in range(top + 1):            # _baseline_columns of every record at once
        base[..., j] = u**j * mask
    return _Projection(problems, tau, x, mask, base, curved)


def _span(tau) -> float:
    """τ_max, the baseline's unit of time (1 for a single sample)."""
    return float(tau[-1]) or 1.0


def _diagonal(values: np.ndarray) -> np.ndarray:
    """Diagonal matrices (K, m, m) of ``values`` (K, m)."""
    return values[:, :, None] * np.eye(values.shape[1])


def _solve_each(H: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """h of H h = b for each of K small systems, and which were solved (a singular H is
    not: its h is 0)."""
    try:
        return np.linalg.solve(H, b[..., None])[..., 0], np.ones(len(H), bool)
    except np.linalg.LinAlgError:
        h, solved = np.zeros_like(b), np.ones(len(H), bool)
        for k in range(len(H)):
            try:
                h[k] = np.linalg.solve(H[k], b[k])
            except np.linalg.LinAlgError:
                solved[k] = False
        return h, solved


def _inverses(R: np.ndarray, widths: np.ndarray) -> list[np.ndarray]:
    """R_k⁻¹ of the leading ``widths[k]`` columns of each R (K, m, m) of a QR
    (:func:`_inverse`), those of one width inverted together."""
    out = [None] * len(widths)
    for b in np.unique(widths):
        which = np.flatnonzero(widths == b)
        try:
            inverses = np.linalg.inv(R[which, :b, :b])
        except np.linalg.LinAlgError:
            inverses = np.stack([_inverse(R[k, :b, :b]) for k in which])
        finite = np.isfinite(inverses).all(axis=(1, 2))
        for k, inverse, ok in zip(which, inverses, finite):
            out[k] = inverse if ok else np.linalg.pinv(R[k, :b, :b])
    return out


def _inverse(R) -> np.ndarray:
    """R⁻¹ of the small upper triangular R of a QR; the pseudo-inverse where R is singular
    (a column the others repeat)."""
    try:
        out = np.linalg.inv(R)
    except np.linalg.LinAlgError:
        return np.linalg.pinv(R)
    return out if np.all(np.isfinite(out)) else np.linalg.pinv(R)


def _orthonormal(rows) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Gram–Schmidt of K pairs of rows a₀, a₁ (K, 2, samples): orthonormal pairs q with
    a₀ = R₀₀q₀, a₁ = R₀₁q₀ + R₁₁q₁, and R₀₁, 1/R₀₀, 1/R₁₁ (each (K,)). A row that is nil,
    or that the other repeats (to 10⁻¹² of its length), spans nothing: its q is 0 and its
    1/R is 0 (the pseudo-inverse's least-norm solution)."""
    a0, a1 = rows[:, 0], rows[:, 1]
    r00 = np.sqrt(np.einsum("kn,kn->k", a0, a0))
    inv0 = np.divide(1.0, r00, out=np.zeros_like(r00), where=r00 > 0)
    q0 = a0 * inv0[:, None]
    r01 = np.einsum("kn,kn->k", q0, a1)
    rest = a1 - r01[:, None] * q0
    r11 = np.sqrt(np.einsum("kn,kn->k", rest, rest))
    spans = r11 > 1e-12 * np.sqrt(np.einsum("kn,kn->k", a1, a1))
    inv1 = np.divide(1.0, r11, out=np.zeros_like(r11), where=spans)
    return np.stack([q0, rest * inv1[:, None]], axis=1), r01, inv0, inv1


def _projected(problem: _Projection, guess, scale) -> tuple[np.ndarray, np.ndarray]:
    """Each fit's minimum from ``guess`` (K, parameters) (:meth:`_Projection.minimise`, or
    scipy's MINPACK Levenberg–Marquardt where that does not converge), and whether it
    converged."""
    found, converged = problem.minimise(guess, scale)
    for k in np.flatnonzero(~converged):
        single = _projection([problem.problems[k]], problem.gamma_unit is not None)
        best = optimize.least_squares(single.residual, guess[k], jac=single.jacobian,
                                      x_scale=np.abs(scale[k]), method="lm", **TOLERANCES)
        found[k], converged[k] = best.x, best.success
    return found, converged


def fit_damped_sine(time, x, *, start: float | None = None, period: float | None = None,
                    delta: float | None = None, baseline_order: int = 2,
                    curved_envelope: bool = False, exclude=None) -> DampedSineFit:
    """Fit a damped sinusoid on a polynomial baseline to a free-decay record.

    Parameters
    ----------
    time, x : array_like
        Sample times [s] and the record [any unit].
    start : float, optional
        t₀: samples before it are left out (the held twist before the release). [s]
    period, delta : float, optional
        Starting values of T [s] and δ (default: :func:`dominant_period`, 0.3).
    baseline_order : int
        Degree of the baseline polynomial (2: offset, drift and the curvature of a slow
        creep).
    curved_envelope : bool
        Also fit γ, a quadratic term of the log-envelope (see :func:`decrement_trend`).
    exclude : array_like of bool, optional
        Samples left out of the fit (clipped ones); the model holds between them.

    Returns
    -------
    DampedSineFit

    Raises
    ------
    RuntimeError
        The fit did not converge, or its normal matrix is singular.

    Notes
    -----
    δ and ω_d are found by variable projection (the amplitude terms and the baseline are
    linear and solved for at each step): its minimum is the joint least squares' minimum
    over every parameter (Golub and Pereyra; Hansen, Pereyra & Scherer 2013, ch. 9), so the
    joint problem is solved again by :func:`scipy.optimize.least_squares` only where the
    projection did not converge. The covariance is s²(JᵀJ)⁻¹, J the analytic Jacobian of
    the joint model over every parameter at the minimum, s² = Σr²/(n − p).

    Examples
    --------
    >>> t = np.arange(3000) / 3e3
    >>> x = np.exp(-0.4 * 10 * t) * np.cos(2 * np.pi * 10 * t) + 0.2 + 0.05 * t
    >>> f = fit_damped_sine(t, x)
    >>> round(f.delta, 6), round(f.omega_d / (2 * np.pi), 6)
    (0.4, 10.0)
    """
    t0, T0, tau, x = _fitted_samples(time, x, start, period, exclude)
    order = int(baseline_order)
    size = 5 + order + curved_envelope
    if tau.size <= size:
        raise RuntimeError(f"fit_damped_sine: {tau.size} samples to fit, fewer than its "
                           f"{size} parameters and one")
    guess = [0.3 if delta is None else float(delta), 2 * np.pi / T0]
    fit = _fits(*_minima([(tau, x, order, guess)], curved_envelope), [t0])[0]
    if isinstance(fit, RuntimeError):
        raise fit
    return fit


def _fitted_samples(time, x, start: float | None, period: float | None, exclude):
    """t₀, the period to start from (:func:`dominant_period` without one), and τ = t − t₀
    and x of the samples fitted: from t₀ on, the excluded left out."""
    t, x = np.asarray(time, dtype=float), np.asarray(x, dtype=float)
    t0 = float(t[0]) if start is None else float(start)
    T0 = dominant_period(t[t >= t0], x[t >= t0]) if period is None else float(period)
    keep = t >= t0
    if exclude is not None:
        keep &= ~np.asarray(exclude, bool)
    return t0, T0, t[keep] - t0, x[keep]


def _minima(problems, curved_envelope: bool) -> tuple[_Projection, np.ndarray, np.ndarray]:
    """The projection's minimum of each of ``problems`` (τ, x, baseline degree, a guess of
    δ and ω_d), the fits stepping together; with ``curved_envelope``, γ fitted too from each
    plain minimum. Returns the projection, the nonlinear parameters (K, 2 or 3; γ in the
    projection's unit) and whether each converged."""
    plain = _projection([(tau, x, order) for tau, x, order, _ in problems])
    start = np.array([guess for *_, guess in problems], dtype=float)
    ones = np.ones(len(problems))
    found, converged = _projected(plain, start, np.column_stack([ones, start[:, 1]]))
    if not curved_envelope:
        return plain, found, converged
    curved = _projection(plain.problems, True)
    found, converged = _projected(curved, np.column_stack([found, 0 * ones]),
                                  np.column_stack([ones, found[:, 1], ones]))
    return curved, found, converged


def _fits(problem: _Projection, found, converged, starts) -> list[DampedSineFit | RuntimeError]:
    """Each fit of ``problem`` from its minimum ``found`` (its start t₀ of ``starts``): the
    joint least squares over every parameter first where the projection did not converge
    (:func:`_joint_minimum`); then, for all at once, the covariance s²(JᵀJ)⁻¹, J the
    analytic Jacobian of the joint model over every parameter (δ, ω_d[, γ], a, b and the
    baseline's) at the minimum, s² = Σr²/(n − p) (widened by (1 + ρ)/(1 − ρ) where the
    residuals' lag-one correlation ρ exceeds 3/√n). Each fit, or the RuntimeError that says
    why it failed."""
    curved = problem.gamma_unit is not None
    failed = {}
    coef = problem.coefficients(found)
    for k in np.flatnonzero(~converged):
        try:
            found[k] = _joint_minimum(problem.problems[k], found[k], coef[k],
                                      problem.gamma_unit[k] if curved else None)
        except RuntimeError as exc:
            failed[k] = exc
    coef = problem.coefficients(found)
    _, r, _ = problem.solve(found)
    A, D = problem._columns
    if curved:
        D = np.concatenate([D[:, :2], D[:, 2:] / problem.gamma_unit[:, None, None]], axis=1)
        found = np.column_stack([found[:, :2], found[:, 2] * problem.gamma_unit])
    J = np.concatenate([D, A, problem.base.transpose(0, 2, 1)], axis=1)   # (K, p, samples)
    nonlinear = D.shape[1]
    unused = np.concatenate([np.zeros((len(J), nonlinear + 2), bool), ~problem.kept], axis=1)
    normal, solved = _inverse_each(J @ J.transpose(0, 2, 1) + _diagonal(unused * 1.0))
    names = ["delta", "omega_d"] + (["gamma"] if curved else []) + ["a", "b"]
    out = []
    for k, (tau, _, order) in enumerate(problem.problems):
        size = nonlinear + 3 + order
        if k in failed:
            out.append(failed[k])
        elif not solved[k]:
            out.append(RuntimeError("fit_damped_sine: the normal matrix is singular (no "
                                    "oscillation in the record?)"))
        else:
            out.append(_fit(found[k], coef[k], r[k, :tau.size], normal[k, :size, :size],
                            starts[k], _span(tau),
                            tuple(names + [f"c{j}" for j in range(order + 1)])))
    return out


def _fit(nonlinear, lin, r, normal, t0: float, span: float, names: tuple) -> DampedSineFit:
    """The :class:`DampedSineFit` of parameters (``nonlinear``: δ, ω_d[, γ]; ``lin``: a, b
    and the baseline's), residuals ``r`` and (JᵀJ)⁻¹ ``normal`` (:func:`_fits`)."""
    dof = r.size - len(names)
    s2 = float(r @ r) / dof
    cov = s2 * normal
    rho = float(r[:-1] @ r[1:] / (r @ r)) if r @ r > 0 else 0.0
    if rho > 3.0 / math.sqrt(r.size):
        cov = cov * (1.0 + rho) / (1.0 - rho)
    d, w = nonlinear[0], nonlinear[1]
    g = nonlinear[2] if len(nonlinear) > 2 else 0.0
    a, b = lin[0], lin[1]
    return DampedSineFit(float(d), float(w), float(g), float(math.hypot(a, b)),
                         float(math.atan2(-b, a)), np.asarray(lin[2:], float), t0, span,
                         names, cov, math.sqrt(s2), rho, int(dof), normal)


def _inverse_each(N: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """N⁻¹ of each of K small matrices, and which were inverted (a singular N is not)."""
    try:
        return np.linalg.inv(N), np.ones(len(N), bool)
    except np.linalg.LinAlgError:
        out, solved = np.zeros_like(N), np.ones(len(N), bool)
        for k in range(len(N)):
            try:
                out[k] = np.linalg.inv(N[k])
            except np.linalg.LinAlgError:
                solved[k] = False
        return out, solved


def _joint_minimum(problem: tuple, nonlinear, coef, gamma_unit: float | None) -> np.ndarray:
    """The nonlinear parameters of the joint least squares over every parameter of a fit
    (``problem``: τ, x, baseline degree) from the projection's point (``nonlinear``, its
    linear ``coef``), by :func:`scipy.optimize.least_squares`: where the projection did not
    converge.

    Raises
    ------
    RuntimeError
        That did not converge either.
    """
    tau, x, order = problem
    curved = gamma_unit is not None
    base = _baseline_columns(tau, _span(tau), order)

    def unpack(p):
        d, w = p[0], p[1]
        g = p[2] if curved else 0.0
        lin = p[3 if curved else 2:]
        return d, w, g, lin

    last = {}

    def columns(d, w, g):
        """A at (δ, ω_d, γ), kept for the Jacobian the solver asks for at the same point."""
        if last.get("at") != (d, w, g):
            last.update(at=(d, w, g), A=_columns(tau, d, w, g, base))
        return last["A"]

    def residual(p):
        d, w, g, lin = unpack(p)
        return columns(d, w, g) @ lin - x

    def jacobian(p):
        d, w, g, lin = unpack(p)
        A = columns(d, w, g)
        swing = [a @ lin[:2] for a in _column_derivatives(tau, A, d, w, curved)]
        return np.column_stack(swing + [A])

    natural = np.array(nonlinear, dtype=float)
    if curved:
        natural[2] *= gamma_unit
    p0 = np.concatenate([natural, coef])
    sol = optimize.least_squares(residual, p0, jac=jacobian, method="lm",
                                 x_scale=np.abs(p0) + 1e-12 * np.max(np.abs(p0)))
    if not sol.success:
        raise RuntimeError(f"fit_damped_sine: the fit did not converge ({sol.message})")
    found = sol.x[:natural.size].copy()
    if curved:
        found[2] /= gamma_unit
    return found


@dataclass(frozen=True)
class DecrementTrend(Record):
    """Whether the decrement changes along a record (a quadratic log-envelope tested).

    Attributes
    ----------
    delta_start, delta_end : float
        Local decrement at the start of the fit and at ``end``. [1]
    end : float
        Where the plain fit's envelope sinks to :data:`PEAK_SNR` noise σ, or the record's
        end if it does not. [s]
    relative_change : float
        (δ_end − δ_start)/δ_start.
    p_value : float
        Two-sided p-value of γ = 0 (normal: the fit has hundreds of degrees of freedom).
    fit : DampedSineFit
        The fit with the curved envelope.
    """

    delta_start: float
    delta_end: float
    end: float
    relative_change: float
    p_value: float
    fit: DampedSineFit

    def significant(self, level: float = 0.01, *, least_change: float = 0.1) -> bool:
        """γ significant at ``level`` and δ changing by at least ``least_change``."""
        return self.p_value < level and abs(self.relative_change) >= least_change

    def measured_at(self, time) -> Measured:
        """The local decrement at ``time`` as a measured input: its u from the curved fit's
        covariance of (δ, ω_d, γ) (type A, ν = samples − parameters)."""
        f = self.fit
        tau = float(time) - f.start
        grad = np.zeros(len(f.params))
        grad[[f.params.index(k) for k in ("delta", "omega_d", "gamma")]] = (
            1.0, -4.0 * np.pi * f.gamma * tau / f.omega_d**2, 4.0 * np.pi * tau / f.omega_d)
        return Measured(float(f.decrement_at(time)), float(math.sqrt(grad @ f.cov @ grad)),
                        f.dof)


def _visible_end(t: np.ndarray, fit: DampedSineFit, sigma: float) -> float:
    """Last time at which ``fit``'s envelope stands :data:`PEAK_SNR` σ above the noise (the
    record's end if it still does there; one period after the start if it never does)."""
    inside = t[(t >= fit.start) & (fit.envelope(t) >= PEAK_SNR * sigma)]
    return float(inside[-1]) if inside.size else fit.start + fit.period


def decrement_trend(time, x, fit: DampedSineFit, *, noise: float | None = None,
                    exclude=None) -> DecrementTrend:
    """Refit ``fit``'s record with a quadratic log-envelope and test its curvature γ.

    Parameters
    ----------
    time, x : array_like
        The record fitted by :func:`fit_damped_sine`. [s], [any unit]
    fit : DampedSineFit
        The plain fit (its start, baseline degree and values are reused).
    noise : float, optional
        The record's noise σ (default :func:`noise_sd`), for where the oscillation ends.
    exclude : array_like of bool, optional
        Samples the plain fit left out (clipped ones), left out here too.

    Returns
    -------
    DecrementTrend

    Notes
    -----
    With e^{−στ − γτ²} the decay rate is σ + 2γτ, so the decrement per period changes
    linearly in time: δ(τ) = δ₀ + 4πγτ/ω_d. Damping that falls with the amplitude (filled
    rubber) gives γ < 0.
    """
    t, x = np.asarray(time, dtype=float), np.asarray(x, dtype=float)
    sigma = noise_sd(x, exclude=exclude) if noise is None else noise
    curved = fit_damped_sine(t, x, start=fit.start, period=fit.period, delta=fit.delta,
                             baseline_order=fit.baseline_order, curved_envelope=True,
                             exclude=exclude)
    end = _visible_end(t, fit, sigma)
    d0, d1 = float(curved.decrement_at(fit.start)), float(curved.decrement_at(end))
    z = curved.gamma / curved.u("gamma") if curved.u("gamma") > 0 else 0.0
    return DecrementTrend(d0, d1, end, (d1 - d0) / d0 if d0 else math.nan,
                          float(2 * stats.norm.sf(abs(z))), curved)


# ----------------------------------------------------------------------------- the baseline's model

BASELINE_ORDERS = (1, 2, 3, 4, 5)
"""Degrees of the baseline polynomial a record's trace is fitted with (:func:`fit_baselines`):
a straight drift up to the slow wander of a bridge that is not settled."""

ADMISSIBLE_BIC = 300.0
"""Baselines whose Bayesian information criterion lies within this of the best one's are
admissible (:func:`fit_baselines`): their spread of δ and T is the baseline model's error.
Chosen on records with drifting baselines (``python -m processing.bench --topic damper``,
family ``baseline drift``): at 10–100 a slow wander's bias stays out of U (δ's interval held
the truth in 72–78 % of those records); at 300 δ's and T's held it in 95 % and 94 % of 160
records (90–97.5 % for each kind of drift), with a median U/|error| of 3.1 and 5.2."""


@dataclass(frozen=True)
class BaselineChoice(Record):
    """A record's trace fitted on each baseline of :data:`BASELINE_ORDERS`, the one the data
    choose and the model error the others leave.

    Attributes
    ----------
    fit : DampedSineFit
        The fit on the baseline with the least BIC.
    orders : ndarray
        The polynomial degrees fitted.
    delta, period : ndarray
        δ [1] and T [s] of each fit.
    bic : ndarray
        n_e ln(RSS/n) + p ln n_e of each, n_e = n(1 − ρ)/(1 + ρ) the samples worth of
        independent ones (ρ the least lag-one correlation of the fits' residuals: a paper
        record's errors run over neighbouring columns).
    admissible : ndarray of bool
        BIC within :data:`ADMISSIBLE_BIC` of the least.
    """

    fit: DampedSineFit
    orders: np.ndarray
    delta: np.ndarray
    period: np.ndarray
    bic: np.ndarray
    admissible: np.ndarray

    @property
    def u_delta(self) -> float:
        """The baseline model's standard uncertainty of δ: the largest departure of an
        admissible fit's δ from the chosen one's. [1]"""
        return float(np.max(np.abs(self.delta[self.admissible] - self.fit.delta)))

    @property
    def u_period(self) -> float:
        """The same for T. [s]"""
        return float(np.max(np.abs(self.period[self.admissible] - self.fit.period)))


def fit_baselines(time, x, *, start: float, period: float, exclude=None) -> BaselineChoice:
    """Fit a decay on each baseline of :data:`BASELINE_ORDERS` and let the data choose.

    Parameters
    ----------
    time, x : array_like
        The record. [s], [any unit]
    start, period : float
        As :func:`fit_damped_sine`. [s]
    exclude : array_like of bool, optional
        As :func:`fit_damped_sine`.

    Returns
    -------
    BaselineChoice

    Raises
    ------
    RuntimeError
        No baseline's fit converged.

    Notes
    -----
    A baseline the record does not follow (a bridge's drift bending, an amplifier settling,
    a slow wander) leaves a bias in δ and T that the fit's own u, taken from its residuals,
    does not carry. The degree is chosen by the Bayesian information criterion (Schwarz
    [3]_) over samples worth n_e = n(1 − ρ)/(1 + ρ) independent ones, and the spread of δ
    and T over the admissible baselines (:data:`ADMISSIBLE_BIC`) is stated as the model's
    standard uncertainty (GUM, JCGM 100:2008, F.2.4.4: a correction's uncertainty from the
    alternatives the data do not exclude).

    References
    ----------
    .. [3] G. Schwarz, Estimating the dimension of a model, Ann. Statist. 6 (1978) 461–464,
           doi:10.1214/aos/1176344136.
    """
    choice = fit_baselines_each([(time, x, start, period, exclude)])[0]
    if choice is None:
        raise RuntimeError("fit_damped_sine: no baseline's fit converged")
    return choice


def fit_baselines_each(records) -> list[BaselineChoice | None]:
    """:func:`fit_baselines` of each of ``records`` (time, x, start, period, exclude), the
    fits of all of them on all their baselines stepping together (:class:`_Projection`: a
    few array operations for all, instead of a few for each); None for a record where no
    baseline's fit converged.

    Every baseline's fit starts from the period given and δ = 0.3 (a baseline's degree moves
    δ and T little, so they all start close), as :func:`fit_damped_sine`'s."""
    prepared = [_fitted_samples(time, x, start, period, exclude)
                for time, x, start, period, exclude in records]
    problems = [(i, (tau, x, order, [0.3, 2 * np.pi / period]))
                for i, (_, period, tau, x) in enumerate(prepared)
                for order in BASELINE_ORDERS if tau.size > 5 + order]  # a sample more than
    fits = [[] for _ in records]                                          # the parameters
    if problems:
        fitted = _fits(*_minima([q for _, q in problems], False),
                       [prepared[i][0] for i, _ in problems])
        for (i, _), fit in zip(problems, fitted):
            if isinstance(fit, DampedSineFit):
                fits[i].append(fit)
    return [_chosen(f) if f else None for f in fits]


def _chosen(fits: list[DampedSineFit]) -> BaselineChoice:
    """The baseline the data choose among a record's ``fits`` (:func:`fit_baselines`)."""
    rss = np.array([f.residual_sd**2 * f.dof for f in fits])
    size = np.array([f.dof + len(f.params) for f in fits], dtype=float)
    rho = max(min(f.residual_correlation for f in fits), 0.0)
    n_e = size * (1.0 - rho) / (1.0 + rho)
    bic = n_e * np.log(rss / size) + np.array([len(f.params) for f in fits]) * np.log(n_e)
    best = int(np.argmin(bic))
    return BaselineChoice(fits[best], np.array([f.baseline_order for f in fits]),
                          np.array([f.delta for f in fits]), np.array([f.period for f in fits]),
                          bic, bic - bic[best] <= ADMISSIBLE_BIC)


# ----------------------------------------------------------------------------- a whole record

@dataclass(frozen=True)
class RecordedDecay(Record):
    """A free-decay record reduced both ways (:func:`analyse_decay`).

    Attributes
    ----------
    found : Peaks
        Its extrema and half ranges.
    trace : DampedSineFit
        The damped sinusoid fitted to the whole record after the release: δ and ω_d.
    peaks : DecrementFit or None
        The line through ln(half range) of the used extrema, half a period apart (None
        with fewer than three).
    trend : DecrementTrend
        The test of a decrement changing along the record.
    models : BaselineChoice
        The trace fitted on each baseline; ``trace`` is the one the data chose.
    """

    found: Peaks
    trace: DampedSineFit
    peaks: DecrementFit | None
    trend: DecrementTrend
    models: BaselineChoice

    @property
    def visible_periods(self) -> float:
        """Periods from the fit's start to where the oscillation sinks into the noise or
        the record ends."""
        return (self.trend.end - self.trace.start) / self.trace.period

    @property
    def short(self) -> bool:
        """Fewer than :data:`FEW_PERIODS` visible periods."""
        return self.visible_periods < FEW_PERIODS

    def measured_delta(self) -> Measured:
        """δ as a measured input: type A from the trace fit, type B the baseline model's
        (:attr:`BaselineChoice.u_delta`). [1]"""
        t = self.trace
        return Measured(t.delta, t.u("delta"), t.dof, u_b=self.models.u_delta)

    def measured_period(self, time_scale: float = 0.0) -> Measured:
        """T = 2π/ω_d as a measured input: type A from the trace fit, type B the baseline
        model's (:attr:`BaselineChoice.u_period`) and the time base's. [s]

        Parameters
        ----------
        time_scale : float
            Relative standard uncertainty of the record's time base (a paper record's
            seconds per pixel from its time marks; 0 for a recorder's clock).
        """
        t = self.trace
        return Measured(t.period, t.period * t.u("omega_d") / t.omega_d, t.dof,
                        u_b=math.hypot(self.models.u_period, t.period * time_scale))


RAIL_BAND = 3.0
"""Samples within this many noise σ of a clipped record's rail are left out of its fit with
the clipped ones: the recorder kept them only because their noise fell below the rail, so
their noise is biased away from it."""


def _near_rails(x: np.ndarray, clipped, sigma: float):
    """The clipped samples and those within :data:`RAIL_BAND` σ of the rails they sit at
    (None without a mask)."""
    if clipped is None or not np.any(clipped):
        return clipped
    cut = np.asarray(clipped, bool)
    out = cut.copy()
    middle = float(np.median(x))
    for side in (1.0, -1.0):
        rail = side * x[cut] > side * middle
        if rail.any():
            edge = side * float(np.min(side * x[cut][rail]))
            out |= side * x >= side * edge - RAIL_BAND * sigma
    return out


class NoDecayError(RuntimeError):
    """The fitted oscillation does not decay measurably: why, in English and Russian
    (``ru``); a RuntimeError, as the fit's own failures are, not a :class:`Reason` (a
    ValueError: too few extrema)."""

    def __init__(self, reason: str, ru: str):
        super().__init__(reason)
        self.ru = ru


def analyse_decay(time, x, *, clipped=None) -> RecordedDecay:
    """Reduce a free-decay record: its extrema, a damped sinusoid over the whole trace, a
    line through the peaks and the test of a changing decrement.

    Parameters
    ----------
    time, x : array_like
        Sample times (uniform) [s] and the record [any unit]; it may begin with the held
        twist before the release.
    clipped : array_like of bool, optional
        Samples at the recorder's limits (:func:`processing.inputs.record_quality.clipped_mask`):
        left out of the fits with the samples within :data:`RAIL_BAND` noise σ of their
        rails, and the extrema they touch out of the peaks.

    Returns
    -------
    RecordedDecay

    Raises
    ------
    Reason
        Fewer than three extrema stand out of the noise (no oscillation to fit), or fewer
        than three are clear of the clipped samples (a ValueError, in English and Russian).
    RuntimeError
        The fit failed, or the fitted oscillation does not decay measurably (δ ≤ 2u(δ):
        :class:`NoDecayError`).

    Notes
    -----
    The record is first cut where its ringing ends (:func:`ringing_end`): a noise tail left
    by a recorder running on tells nothing of the decay. The trace is fitted on each baseline
    of :data:`BASELINE_ORDERS` and the data choose (:func:`fit_baselines`). The trace fit
    starts 0.45 of a
    period before the first extremum after the release
    (:func:`find_peaks` drops the lobe that holds the release, which the held twist joins),
    so that the kink of the release is left out and the first swing is kept.

    Examples
    --------
    >>> t = np.arange(4000) / 4e3
    >>> x = np.where(t < 0.05, 1.0, np.exp(-3.0 * (t - 0.05)) * np.cos(2 * np.pi * 10 * (t - 0.05)))
    >>> d = analyse_decay(t, x)
    >>> round(d.trace.delta, 6), round(d.trace.period, 6), d.trend.significant()
    (0.3, 0.1, False)
    """
    t, x = np.asarray(time, dtype=float), np.asarray(x, dtype=float)
    keep = ringing_end(x)
    t, x = t[:keep], x[:keep]
    clipped = None if clipped is None else np.asarray(clipped, bool)[:keep]
    found = find_peaks(t, x, clipped=clipped)
    if found.time.size < 3:
        raise Reason(f"{found.time.size} extrema of an oscillation stand out of the noise; "
                     "a decay needs at least three", "из шума выделяются экстремумов колебаний: "
                     f"{found.time.size}, а для затухания нужно хотя бы три")
    if found.clear < 3:
        raise Reason(f"{found.clear} of the {found.time.size} extrema after the release are "
                     "clear of the clipped samples; a decay needs at least three",
                     f"из {found.time.size} экстремумов после отпускания не задеты "
                     f"срезанными отсчётами лишь {found.clear}, а для затухания нужно хотя бы "
                     "три")
    start = float(found.time[0] - 0.45 * found.period)
    clipped = _near_rails(x, clipped, found.noise)
    models = fit_baselines(t, x, start=start, period=found.period, exclude=clipped)
    trace = models.fit
    if not trace.delta > 2.0 * trace.u("delta"):
        raise NoDecayError(f"the oscillation does not decay measurably (δ = {trace.delta:.2g} "
                           f"± {2 * trace.u('delta'):.2g}, k = 2): it is not a free decay",
                           f"колебания заметно не затухают (δ = {trace.delta:.2g} ± "
                           f"{2 * trace.u('delta'):.2g}, k = 2): это не свободное затухание")
    peaks = (log_decrement(found.amplitudes, step=0.5, half_ranges=True)
             if found.used.sum() >= 3 else None)
    return RecordedDecay(found, trace, peaks, decrement_trend(t, x, trace, noise=found.noise,
                                                              exclude=clipped), models)
