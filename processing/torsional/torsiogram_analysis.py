"""One torsiograph record reduced: orders, the instrument's correction, peaks, frequency.

:func:`analyse_trace` runs the chain of :mod:`processing.torsional.torsiogram` (marks, crank angle,
oscillations, the mean working cycle), :mod:`processing.torsional.orders` (orders and drift by least
squares) and :mod:`processing.torsional.seismic` (the torsiograph's transfer function) on one record
of a steady regime and returns a :class:`Torsiogram`. Amplitudes stay in the record's own unit (V or
mm of the recorder) until the static calibration scales them.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 7 (n = 60 N/(z T_отм), ν = 60 N_k/(m T_отм), A = l A_k, K = ν/n, peak amplitudes,
       a harmonic analysis of non-sinusoidal records).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.diagnostics import InputError
from .orders import OrderFit, order_fit
from processing.regression import LineFit
from processing.result import Record
from .seismic import blur_gain, correct_trace, slow_part, torsiograph_response
from .torsiogram import (EXTREMUM_THRESHOLD, CyclePeaks, Peaks, Revolutions, cycle_peaks, denoise,
                         half_range_u, oscillation_frequency, peak_amplitudes, revolutions,
                         steady_crank_angle)

MAX_ORDER = 24.0
"""Highest order :func:`analyse_trace` fits (lowered to what the sampling resolves): a
crankshaft's orders above it carry no measurable share of its motion."""

HYSTERESIS_SPAN = 1.25
"""Factor by which the hysteresis of the single oscillations is varied either way: a
ripple whose swing lies within it of the hysteresis counts as an oscillation or not, and
the largest peak amplitude's u carries that choice."""

EDGE_SPREAD = 4.0
"""How far apart, in σ of the noise left, the record read as it is and read extended by its
mirror image may be where it is still seen (:func:`seen_span`)."""

EDGE_SHARE = 0.005
"""… or, if larger, as a share of the reading's range: a difference below it moves a peak
amplitude (half a range) by under 1 %, so that a record free of noise is not cut where its
ends' transients have decayed below what any reading resolves (:func:`seen_span`)."""

ORDER_SHARE = 0.4
"""Highest frequency fitted, as a share of the sample rate (below the Nyquist frequency and a
recorder's anti-alias roll-off)."""


# ------------------------------------------------------------------------ one record

def _below(x, rate: float, frequency: float) -> np.ndarray:
    """The components of a uniformly sampled ``x`` below ``frequency`` (its mean included)."""
    spectrum = np.fft.rfft(x)
    spectrum[np.fft.rfftfreq(x.size, 1 / rate) >= frequency] = 0
    return np.fft.irfft(spectrum, x.size)


@dataclass(frozen=True)
class Torsiogram(Record):
    """What one torsiograph record reduces to (:func:`analyse_trace`); amplitudes in the
    record's own unit (scale them by the static calibration), corrected for the instrument."""

    revolutions: Revolutions
    fit: OrderFit | None
    """Orders and drift as recorded (not corrected); None where the record is too short
    for them (:func:`read_oscillations`)."""
    correction: np.ndarray
    """1/H at each order's frequency: the factor from recorded to true order amplitudes."""
    cycle: CyclePeaks | None
    """The mean working cycle of the corrected orders and its peak amplitudes (None without
    the orders)."""
    time: np.ndarray
    """Times of ``corrected``, ``upsample`` times finer than the record's. [s]"""
    corrected: np.ndarray
    """The record corrected for the instrument, its white noise taken out
    (:func:`processing.torsional.torsiogram.denoise`): the drift plus the oscillations. [record
    unit]"""
    drift: np.ndarray
    """The drift at ``time``. [record unit]"""
    peaks: Peaks
    """Peak amplitudes of the single oscillations of ``corrected`` less ``drift`` (values
    without the drift) within ``seen``, the manual's reading and the design value's source."""
    seen: tuple
    """First and last instant of the record where its reading does not lean on what lies
    beyond its ends (:func:`seen_span`): the extrema are read between them. [s]"""
    u_largest: float
    """Standard uncertainty of the largest of them from the noise left at its extrema and
    the choice among equal ones (:func:`processing.torsional.torsiogram.half_range_u`).
    [record unit]"""
    frequency: float
    """ν, the oscillations' frequency by counting them (NaN with fewer than three extrema:
    nothing oscillates above the noise, or a drift steeper than the oscillation). [Hz]"""
    frequency_fit: LineFit | None
    """The fit behind it (slope: half period, with its type A u), None without ν. [s]"""
    noise: float
    """σ of the record's white noise (from its spectrum's floor). [record unit]"""
    noise_left: float
    """σ of the noise left in ``corrected``. [record unit]"""
    cutoff: float
    """Highest frequency kept. [Hz]"""

    @property
    def angular_speed(self) -> float:
        return self.revolutions.angular_speed

    @property
    def revolution_frequency(self) -> float:
        """n/60. [Hz]"""
        return self.revolutions.angular_speed / (2 * np.pi)

    @property
    def orders(self) -> np.ndarray:
        """The orders fitted (none without the fit). [1]"""
        return self.fit.order if self.fit is not None else np.empty(0)

    @property
    def order_amplitude(self) -> np.ndarray:
        """True (instrument-corrected) amplitude of each order. [record unit]"""
        return self.fit.amplitude * np.abs(self.correction) if self.fit is not None \
            else np.empty(0)

    @property
    def order_u(self) -> np.ndarray:
        return self.fit.u * np.abs(self.correction) if self.fit is not None else np.empty(0)

    @property
    def dominant_order(self) -> float:
        """The order with the largest corrected amplitude (NaN without the orders). [1]"""
        return float(self.fit.order[np.argmax(self.order_amplitude)]) \
            if self.fit is not None else np.nan

    @property
    def carrying_frequency(self) -> float:
        """The frequency the largest oscillation is corrected at: the dominant order's, or
        without the orders the counted ν. [Hz]"""
        return self.dominant_order * self.revolution_frequency if self.fit is not None \
            else self.frequency

    @property
    def K(self) -> float:
        """ν/n: the oscillations per revolution (the manual's resonating order). [1]"""
        return self.frequency / self.revolution_frequency

    @property
    def drift_ratio(self) -> float:
        """Excursion of the drift over the oscillations' peak-to-peak range (the mean
        cycle's, or without the orders the record's). [1]"""
        span = np.ptp(self.cycle.motion) if self.cycle is not None \
            else np.ptp(self.corrected - self.drift)
        drift = self.fit.drift if self.fit is not None else self.drift
        return float(np.ptp(drift) / span) if span > 0 else np.inf

    @property
    def drift_leak(self) -> float:
        """u of the mean cycle's largest peak amplitude over what white noise alone would
        give it: how much a drift (or a disturbance) reaching the orders' frequencies widened
        it (1 without the orders). [1]"""
        c = self.cycle
        return c.u_largest / c.u_white if c is not None and c.u_white > 0 else 1.0

    def lowest_frequency(self, share: float = 0.1) -> float:
        """Frequency of the lowest order carrying at least ``share`` of the largest order's
        corrected amplitude (without the orders: the counted ν). [Hz]"""
        if self.fit is None:
            return self.frequency
        a = self.order_amplitude
        return float(self.fit.order[np.argmax(a >= share * a.max())]
                     * self.revolution_frequency)


def analyse_trace(time, x, mark_times, *, natural_frequency: float, damping_ratio: float,
                  per_revolution: int = 1, strokes: int = 4, max_order: float = MAX_ORDER,
                  upsample: int = 4, blur: float = 0.0) -> Torsiogram:
    """Reduce one torsiograph record of a steady regime.

    Steps: speed and crank angle from the TDC marks (:func:`revolutions`,
    :func:`steady_crank_angle`); orders and drift by least squares
    (:func:`processing.torsional.orders.order_fit`), each order corrected by 1/H at its frequency
    (:func:`processing.torsional.seismic.torsiograph_response`); the mean working cycle's peak
    amplitudes (:func:`cycle_peaks`); the record corrected for the instrument — the fitted drift,
    the corrected orders at every sample's crank angle and the residual corrected frequency by
    frequency (:func:`processing.torsional.seismic.correct_trace`) on a grid ``upsample`` times
    finer, its white noise taken out below the highest order fitted
    (:func:`processing.torsional.torsiogram.denoise`: whatever stands out of the noise is kept, in
    or between the orders) — and its single oscillations, the manual's reading, within the span
    where that reading does not lean on what lies beyond the record's ends (:func:`seen_span`:
    the residual read again extended by its mirror image): extrema with hysteresis at
    :data:`EXTREMUM_THRESHOLD` of their range (and 4 σ of the noise left), their peak
    amplitudes with the drift removed (:func:`peak_amplitudes`), the largest one's u
    (:func:`processing.torsional.torsiogram.half_range_u`) and their frequency by counting
    (:func:`oscillation_frequency`). The orders describe the mean working cycle; the single
    oscillations do not lean on them.

    Parameters
    ----------
    time : array_like
        Sample times, uniform. [s]
    x : array_like
        The torsiograph's record. [record unit]
    mark_times : array_like
        Times of the TDC marks. [s]
    natural_frequency, damping_ratio : float, keyword-only
        f_c [Hz] and ζ of the torsiograph.
    per_revolution : int, keyword-only
        TDC marks per revolution.
    strokes : {4, 2}, keyword-only
        Half orders for a four-stroke engine, whole orders for a two-stroke one.
    max_order : float, keyword-only
        Highest order fitted (lowered to what the sampling resolves: :data:`ORDER_SHARE` of
        the sample rate).
    upsample : int, keyword-only
        Fineness of the corrected record's grid.
    blur : float, keyword-only
        σ of the Gaussian smoothing along the time axis of a trace read off a photograph
        (:attr:`processing.vision.record.PaperRecord.stroke_blur`), undone with the
        instrument's response, order by order and frequency by frequency
        (:func:`processing.torsional.seismic.blur_gain`). [s]

    Returns
    -------
    Torsiogram

    Raises
    ------
    InputError
        Marks that do not make whole revolutions or are irregular; a record too short for its
        orders.

    Notes
    -----
    What the orders and the polynomial leave below half the lowest order's frequency is
    drift too (the polynomial follows only slow wander): it joins ``drift``.
    """
    t = np.asarray(time, dtype=float)
    x = np.asarray(x, dtype=float)
    revs = revolutions(mark_times, per_revolution=per_revolution)
    rate = (t.size - 1) / (t[-1] - t[0])
    f_rev = revs.angular_speed / (2 * np.pi)
    step = 0.5 if strokes == 4 else 1.0
    top = min(max_order, ORDER_SHARE * rate / f_rev)
    try:
        fit = order_fit(t, steady_crank_angle(t, revs), x, step=step, max_order=top)
    except ValueError:
        raise InputError(f"the record holds {t.size} samples, too few for its orders up to "
                         f"{top:g} and a drift", "record longer (several working cycles)") \
            from None
    correction = blur_gain(fit.order * f_rev, blur) / torsiograph_response(
        fit.order * f_rev, natural_frequency, damping_ratio)
    cycle = cycle_peaks(fit, correction, strokes=strokes)
    fine = t[0] + np.arange(t.size * upsample) / (rate * upsample)
    low = 0.5 * step * f_rev
    orders = fit.synthesize(steady_crank_angle(fine, revs), correction)
    residual = x - fit.periodic - fit.drift
    plain, mirrored = (correct_trace(r, rate, natural_frequency, damping_ratio, low=low,
                                     upsample=upsample, blur=blur, band=top * f_rev)
                       for r in (residual, _mirrored(residual)))
    slow = _below(plain, rate * upsample, low)
    drift = np.interp(fine, t, fit.drift) + slow
    beyond = (mirrored - _below(mirrored, rate * upsample, low))[:fine.size]
    return Torsiogram(revolutions=revs, fit=fit, correction=correction, cycle=cycle,
                      **_oscillations(fine, orders + plain - slow, orders + beyond, drift,
                                      top * f_rev, rate / 2))


def _mirrored(x: np.ndarray) -> np.ndarray:
    """The record followed by its mirror image (an even extension: no step where an FFT
    wraps it round), the other guess :func:`seen_span` compares."""
    return np.concatenate([x, x[::-1]])


def seen_span(plain: np.ndarray, mirrored: np.ndarray, noise: float, *,
              spread: float = EDGE_SPREAD, share: float = EDGE_SHARE) -> slice:
    """The samples of a record where its reading does not lean on what lies beyond its ends.

    The reader's filters (the instrument's correction, the drift's removal, the denoising,
    the band-limited upsampling) work by FFT on the record wrapped round; near each end their
    output holds a transient whose reach depends on the record. Read once as it is and once
    extended by its mirror image (a different, equally possible guess at what lies beyond),
    the two readings part where that guess matters: from each end to the last sample (within
    the outer quarter) where they differ by more than ``spread`` times the noise left, or
    ``share`` of the plain reading's range if that is more.

    Parameters
    ----------
    plain, mirrored : ndarray
        The two readings, same grid. [record unit]
    noise : float
        σ of the noise left in them. [record unit]
    spread : float, keyword-only
        The difference, in units of ``noise``, beyond which a sample is not seen.
    share : float, keyword-only
        The same as a share of the range of ``plain``.

    Returns
    -------
    slice
        The seen samples.

    Examples
    --------
    >>> a = np.sin(np.arange(100.0)); b = a.copy(); b[:3] += 1.0; b[-5:] -= 1.0
    >>> seen_span(a, b, 0.1)
    slice(3, 95, None)
    """
    plain = np.asarray(plain, dtype=float)
    far = np.abs(plain - np.asarray(mirrored)) > max(spread * noise, share * np.ptp(plain))
    n = far.size
    quarter = n // 4
    head = np.flatnonzero(far[:quarter])
    tail = np.flatnonzero(far[n - quarter:])
    return slice(int(head[-1]) + 1 if head.size else 0,
                 n - quarter + int(tail[0]) if tail.size else n)


def _oscillations(fine: np.ndarray, oscillation: np.ndarray, beyond: np.ndarray,
                  drift: np.ndarray, band: float, reach: float) -> dict:
    """The single oscillations of a drift-free corrected record on its fine grid: its noise
    taken out below ``band`` (:func:`processing.torsional.torsiogram.denoise`, its floor taken up to
    ``reach``, the record's own Nyquist frequency), the extrema with
    hysteresis at :data:`EXTREMUM_THRESHOLD` of its range (and 4 σ of the noise left), their
    peak amplitudes, the largest one's u (the noise left at its extrema, and the choice of
    the ripples within :data:`HYSTERESIS_SPAN` of the hysteresis) and the oscillations'
    frequency."""
    rate = (fine.size - 1) / (fine[-1] - fine[0])
    clean = denoise(oscillation, rate, band=band, reach=reach)
    other_end = denoise(_mirrored(beyond), rate, band=band, reach=reach)
    seen = seen_span(clean.value, other_end.value[:fine.size], clean.noise_left)
    span = np.ptp(clean.value[seen])
    share = max(EXTREMUM_THRESHOLD, 4 * clean.noise_left / span) if span > 0 \
        else EXTREMUM_THRESHOLD
    peaks = peak_amplitudes(fine[seen], clean.value[seen], share * span)
    nu, fit_nu = oscillation_frequency(peaks.position) if peaks.position.size >= 3 \
        else (np.nan, None)
    # a ripple near the hysteresis may count as an oscillation or not: the largest read
    # with the hysteresis a quarter lower or higher bounds that choice (rectangular)
    other = [peak_amplitudes(fine[seen], clean.value[seen],
                             f * share * span).largest
             for f in (1 / HYSTERESIS_SPAN, HYSTERESIS_SPAN)]
    choice = max(abs(a - peaks.largest) for a in other) / np.sqrt(3) \
        if np.isfinite(other).all() else 0.0
    u = float(np.hypot(half_range_u(peaks, clean.noise_left), choice))
    return dict(time=fine, corrected=drift + clean.value, drift=drift, peaks=peaks,
                seen=(float(fine[seen][0]), float(fine[seen][-1])), u_largest=u, frequency=nu,
                frequency_fit=fit_nu, noise=clean.noise, noise_left=clean.noise_left,
                cutoff=band)


def read_oscillations(time, x, mark_times, *, natural_frequency: float,
                      damping_ratio: float, per_revolution: int = 1, strokes: int = 4,
                      max_order: float = MAX_ORDER, upsample: int = 4,
                      blur: float = 0.0) -> Torsiogram:
    """Reduce a torsiograph record too short for its orders (under two working cycles, a
    half order cannot be told from the drift) to its single oscillations, as the manual
    reads them: the speed from the TDC marks, the record corrected for the instrument
    frequency by frequency above half the lowest order
    (:func:`processing.torsional.seismic.correct_trace`), its slow part taken for the drift
    (:func:`processing.torsional.seismic.slow_part`), and the oscillations read as by
    :func:`analyse_trace` (within :func:`seen_span`: the record less its slow part read again
    extended by its mirror image). Parameters as :func:`analyse_trace`'s; the result has no fit and
    no mean cycle.
    """
    t = np.asarray(time, dtype=float)
    x = np.asarray(x, dtype=float)
    revs = revolutions(mark_times, per_revolution=per_revolution)
    rate = (t.size - 1) / (t[-1] - t[0])
    f_rev = revs.angular_speed / (2 * np.pi)
    low = 0.5 * (0.5 if strokes == 4 else 1.0) * f_rev
    top = min(max_order, ORDER_SHARE * rate / f_rev)
    fine = t[0] + np.arange(t.size * upsample) / (rate * upsample)
    # the mirror image is taken of the record less its slow part, which the correction
    # takes out before its FFT and puts back after: a drift mirrored would turn sharply
    line = slow_part(x, rate, low)
    corrected, mirrored = (correct_trace(r, rate, natural_frequency, damping_ratio, low=low,
                                         upsample=upsample, blur=blur, band=top * f_rev)
                           for r in (x, _mirrored(x - line)))
    drift = slow_part(corrected, rate * upsample, low)
    mirrored = mirrored[:fine.size] + np.interp(fine, t, line)
    beyond = mirrored - slow_part(mirrored, rate * upsample, low)
    return Torsiogram(revolutions=revs, fit=None, correction=np.empty(0), cycle=None,
                      **_oscillations(fine, corrected - drift, beyond, drift, top * f_rev,
                                      rate / 2))
