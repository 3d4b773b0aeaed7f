"""A record of a steady regime prepared for the crank-angle domain: its mean working cycle and
a lower rate for an order fit.

- :func:`mean_cycle`: the time-synchronous average, each working cycle interpolated on one
  crank-angle grid and averaged (noise and whatever is not periodic in the cycle average
  out; peaks of the mean cycle are not lifted by the noise as a record's are);
- :func:`decimate`: time, angle and record resampled to the least rate an order fit up to a
  given frequency needs (an order fit's cost grows with the samples);

References
----------
.. [1] R. B. Randall, Vibration-based Condition Monitoring, Wiley, 2011, §3.6.2
       (time-synchronous averaging against a once-per-cycle tachometer).
.. [2] A. V. Oppenheim, R. W. Schafer, Discrete-Time Signal Processing, 3rd ed., Pearson,
       2010, §4.6 (downsampling after a low-pass filter; the Kaiser window design).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

DECIMATION_TAPS = 24
"""Length of the anti-alias filter of :func:`decimate`, in decimated samples."""


def mean_cycle(signal, angle, cycle: float) -> np.ndarray:
    """The mean working cycle of a signal spanning whole cycles.

    Each cycle is interpolated on a common crank-angle grid (as many points as samples per
    cycle) and the cycles are averaged.

    Parameters
    ----------
    signal : array_like
        Uniformly sampled, spanning whole cycles. [any unit]
    angle : array_like
        Crank angle of each sample, increasing. [rad]
    cycle : float
        Angle of a working cycle (4π for a four-stroke engine). [rad]

    Returns
    -------
    ndarray
        The mean cycle from the first sample's angle on. [signal unit]

    Examples
    --------
    >>> a = np.linspace(0, 6 * np.pi, 600, endpoint=False)
    >>> m = mean_cycle(np.cos(a) + np.where(a < 2 * np.pi, 0.3, 0.0), a, 2 * np.pi)
    >>> round(float(m.max()), 6), m.size
    (1.1, 200)
    """
    return mean_cycles([signal], angle, cycle)[0]


def mean_cycles(signals, angle, cycle: float) -> np.ndarray:
    """:func:`mean_cycle` of several signals sampled alike (a record's band signals, its
    channels): the grid is placed among the angles once, and each signal interpolated on it
    as :func:`numpy.interp` does (the same slope times the same offset, so the same values).

    Parameters
    ----------
    signals : sequence of array_like
        Each as long as ``angle``. [any unit]
    angle : array_like
        Crank angle of each sample, strictly increasing. [rad]
    cycle : float
        Angle of a working cycle. [rad]

    Returns
    -------
    ndarray
        One mean cycle per signal (a row each). [signal unit]
    """
    angle = np.asarray(angle, dtype=float)
    count = max(int(round((angle[-1] - angle[0]) / cycle)), 1)
    points = max(angle.size // count, 2)
    grid = (angle[0] + (np.arange(count)[:, None] * cycle
                        + np.arange(points)[None, :] * (cycle / points))).ravel()
    left = np.clip(np.searchsorted(angle, grid, "right") - 1, 0, angle.size - 2)
    right = left + 1
    offset = grid - angle[left]
    width = angle[right] - angle[left]
    beyond = grid >= angle[-1]
    out = []
    for signal in signals:
        y = np.asarray(signal, dtype=float)
        low = y[left]
        value = (y[right] - low) / width * offset + low
        value[beyond] = y[-1]
        out.append(value.reshape(count, points).mean(axis=0))
    return np.array(out)


@lru_cache(maxsize=16)
def _taps(q: int) -> np.ndarray:
    """The anti-alias filter of :func:`decimate` by ``q`` (the records of a sweep share a few
    factors)."""
    from scipy.signal import firwin

    taps = firwin(DECIMATION_TAPS * q + 1, 0.8 / q, window=("kaiser", 9.0))
    taps.flags.writeable = False
    return taps


def decimate(time, angle, x, rate: float, highest: float):
    """Time, angle and record at the least rate that keeps ``highest`` below a quarter of it.

    The record is low-passed by a Kaiser FIR (β = 9, :data:`DECIMATION_TAPS` decimated
    samples long, cut-off at 0.4 of the new rate: flat to 10⁻⁴ below a quarter of it,
    centred on its sample) at every q-th sample alone (:func:`_decimated`); the samples whose
    filter would reach past the record's ends are left out.

    Parameters
    ----------
    time, angle, x : array_like
        Time [s], crank angle [rad] and record of each sample.
    rate : float
        Sample rate. [Hz]
    highest : float
        Highest frequency to keep. [Hz]

    Returns
    -------
    time, angle, x : ndarray
        The same at the lower rate (unchanged when no lower rate will do).

    Examples
    --------
    A 50 Hz cosine at 25.6 kHz, kept to 200 Hz: 32 times fewer samples, the same amplitude
    (to 2·10⁻⁵):

    >>> t = np.arange(25600) / 25600.0
    >>> t2, _, y = decimate(t, t, np.cos(2 * np.pi * 50 * t), 25600.0, 200.0)
    >>> round(float(t2[1] - t2[0]), 9), round(float(np.abs(y).max()), 4)
    (0.00125, 1.0)
    """
    q = max(1, int(rate / (4 * highest)))
    if q == 1:
        return np.asarray(time), np.asarray(angle), np.asarray(x)
    x = np.asarray(x, dtype=float)
    first = DECIMATION_TAPS // 2 + 1
    keep = slice(first, max(-(-x.size // q) - first, first))
    y = _decimated(x, _taps(q), q, first - DECIMATION_TAPS // 2, keep.stop - keep.start)
    return np.asarray(time)[::q][keep], np.asarray(angle)[::q][keep], y


def _decimated(x: np.ndarray, taps: np.ndarray, q: int, first: int, count: int) -> np.ndarray:
    """y_k = Σ_j h_j x_{(first + k) q + j}, k = 0 … count − 1: an FIR's output at every q-th
    sample alone, in its polyphase form: the record as rows of q samples times the taps as
    columns of q (one matrix product), each output the sum along a diagonal."""
    if count < 1:
        return np.zeros(0)
    width = -(-taps.size // q)
    columns = np.zeros(width * q)
    columns[:taps.size] = taps
    rows = x[first * q:(first + count + width - 1) * q].reshape(-1, q)
    products = rows @ columns.reshape(width, q).T
    y = products[:count, 0].copy()
    for m in range(1, width):
        y += products[m:m + count, m]
    return y
