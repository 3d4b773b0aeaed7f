"""One torsiograph record reduced: orders, the instrument's correction, peaks, frequency.

:func:`analyse_trace` runs the chain of :mod:`processing.torsiogram` (marks, crank angle,
oscillations, the mean working cycle), :mod:`processing.orders` (orders and drift by least
squares) and :mod:`processing.seismic` (the torsiograph's transfer function) on one record of
a steady regime and returns a :class:`Torsiogram`. Amplitudes stay in the record's own unit
(V or mm of the recorder) until the static calibration scales them.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 7 (n = 60 N/(z T_отм), ν = 60 N_k/(m T_отм), A = l A_k, K = ν/n, peak amplitudes,
       a harmonic analysis of non-sinusoidal records).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .diagnostics import InputError
from .orders import OrderFit, order_fit
from .regression import LineFit
from .result import Record
from .seismic import correct_trace, torsiograph_response
from .torsiogram import (EXTREMUM_THRESHOLD, CyclePeaks, Peaks, Revolutions, cycle_peaks,
                         oscillation_frequency, peak_amplitudes, revolutions,
                         steady_crank_angle)

MAX_ORDER = 24.0
"""Highest order :func:`analyse_trace` fits (lowered to what the sampling resolves): a
crankshaft's orders above it carry no measurable share of its motion."""

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
    fit: OrderFit
    """Orders and drift as recorded (not corrected)."""
    correction: np.ndarray
    """1/H at each order's frequency: the factor from recorded to true order amplitudes."""
    cycle: CyclePeaks
    """The mean working cycle of the corrected orders and its peak amplitudes."""
    time: np.ndarray
    """Times of ``corrected``, ``upsample`` times finer than the record's. [s]"""
    corrected: np.ndarray
    """The record corrected for the instrument and low-passed: the fitted drift, the
    corrected orders and the corrected residual. [record unit]"""
    drift: np.ndarray
    """The fitted drift at ``time``. [record unit]"""
    peaks: Peaks
    """Peak amplitudes of the single oscillations of ``corrected`` less ``drift`` (values
    without the drift), the manual's reading: a drift steeper than the oscillation would
    leave the record without extrema to read."""
    frequency: float
    """ν, the oscillations' frequency by counting them (NaN with fewer than three extrema:
    nothing oscillates above the noise, or a drift steeper than the oscillation). [Hz]"""
    frequency_fit: LineFit | None
    """The fit behind it (slope: half period, with its type A u), None without ν. [s]"""
    noise: float
    """Standard deviation of the noise left in ``corrected``. [record unit]"""
    cutoff: float
    """Low-pass edge used. [Hz]"""

    @property
    def angular_speed(self) -> float:
        return self.revolutions.angular_speed

    @property
    def revolution_frequency(self) -> float:
        """n/60. [Hz]"""
        return self.revolutions.angular_speed / (2 * np.pi)

    @property
    def order_amplitude(self) -> np.ndarray:
        """True (instrument-corrected) amplitude of each order. [record unit]"""
        return self.fit.amplitude * np.abs(self.correction)

    @property
    def order_u(self) -> np.ndarray:
        return self.fit.u * np.abs(self.correction)

    @property
    def dominant_order(self) -> float:
        """The order with the largest corrected amplitude. [1]"""
        return float(self.fit.order[np.argmax(self.order_amplitude)])

    @property
    def K(self) -> float:
        """ν/n: the oscillations per revolution (the manual's resonating order). [1]"""
        return self.frequency / self.revolution_frequency

    @property
    def drift_ratio(self) -> float:
        """Excursion of the fitted drift over the mean cycle's peak-to-peak range. [1]"""
        span = np.ptp(self.cycle.motion)
        return float(np.ptp(self.fit.drift) / span) if span > 0 else np.inf

    @property
    def drift_leak(self) -> float:
        """u of the largest peak amplitude over what white noise alone would give it: how much
        a drift (or a disturbance) reaching the orders' frequencies widened it. [1]"""
        c = self.cycle
        return c.u_largest / c.u_white if c.u_white > 0 else 1.0

    def lowest_frequency(self, share: float = 0.1) -> float:
        """Frequency of the lowest order carrying at least ``share`` of the largest order's
        corrected amplitude. [Hz]"""
        a = self.order_amplitude
        return float(self.fit.order[np.argmax(a >= share * a.max())]
                     * self.revolution_frequency)


def analyse_trace(time, x, mark_times, *, natural_frequency: float, damping_ratio: float,
                  per_revolution: int = 1, strokes: int = 4, max_order: float = MAX_ORDER,
                  upsample: int = 4) -> Torsiogram:
    """Reduce one torsiograph record of a steady regime.

    Steps: speed and crank angle from the TDC marks (:func:`revolutions`,
    :func:`steady_crank_angle`); orders and drift by least squares
    (:func:`processing.orders.order_fit`), each order corrected by 1/H at its frequency
    (:func:`processing.seismic.torsiograph_response`); the mean working cycle's peak
    amplitudes (:func:`cycle_peaks`); the record corrected for the instrument — the fitted
    drift, the corrected orders at every sample's crank angle and the residual corrected
    frequency by frequency (:func:`processing.seismic.correct_trace`), cut above the highest
    significant order, on a grid ``upsample`` times finer — and its single oscillations: extrema
    with hysteresis at :data:`EXTREMUM_THRESHOLD` of the cycle's range (and 4 noise σ), their
    peak amplitudes with the drift removed (:func:`peak_amplitudes`) and their frequency by
    counting (:func:`oscillation_frequency`).

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
    drift too (the polynomial follows only slow wander): it joins ``drift``, and the noise
    σ is taken on the rest.
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
    correction = 1 / torsiograph_response(fit.order * f_rev, natural_frequency, damping_ratio)
    cycle = cycle_peaks(fit, correction, strokes=strokes)
    significant = fit.significant()
    highest = fit.order[significant].max() if significant.any() else top
    cutoff = min((highest + 0.25) * f_rev, 0.3 * rate)
    fine = t[0] + np.arange(t.size * upsample) / (rate * upsample)
    low = 0.5 * step * f_rev
    residual = correct_trace(x - fit.periodic - fit.drift, rate, natural_frequency,
                             damping_ratio, low=low, high=cutoff, upsample=upsample)
    slow = _below(residual, rate * upsample, low)
    drift = np.interp(fine, t, fit.drift) + slow
    corrected = drift + fit.synthesize(steady_crank_angle(fine, revs), correction) \
        + residual - slow
    noise = float(np.std(residual - slow))
    threshold = max(EXTREMUM_THRESHOLD * np.ptp(cycle.motion), 4 * noise)
    peaks = peak_amplitudes(fine, corrected - drift, threshold)
    nu, fit_nu = oscillation_frequency(peaks.position) if peaks.position.size >= 3 \
        else (np.nan, None)
    return Torsiogram(revolutions=revs, fit=fit, correction=correction, cycle=cycle,
                      time=fine, corrected=corrected, drift=drift, peaks=peaks, frequency=nu,
                      frequency_fit=fit_nu, noise=noise, cutoff=cutoff)
