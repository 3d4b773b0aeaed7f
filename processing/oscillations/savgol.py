"""Savitzky–Golay smoothing as :func:`scipy.signal.savgol_filter` does it with
``mode="interp"`` (each end fitted by one polynomial over the first or last window), with
the end rows' coefficients (and the centre's, :func:`coefficients`) worked out once per
window and kept: scipy fits them by a least-squares solve on every call, which on the short
stretches of a valve's events costs more than the smoothing itself.

References
----------
.. [1] A. Savitzky, M. J. E. Golay, Smoothing and differentiation of data by simplified least
       squares procedures, Anal. Chem. 36 (1964) 1627–1639, doi:10.1021/ac60214a047.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.signal import savgol_coeffs, savgol_filter


@lru_cache(maxsize=32)
def _rows(window: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """The centre's coefficients and the first half window's rows: row i evaluates at sample
    i the polynomial fitted over the first ``window`` samples."""
    centre = savgol_coeffs(window, order, use="dot")
    ends = np.array([savgol_coeffs(window, order, pos=i, use="dot")
                     for i in range(window // 2)]).reshape(window // 2, window)
    centre.flags.writeable = ends.flags.writeable = False
    return centre, ends


def coefficients(window: int, order: int) -> np.ndarray:
    """The smoothing's coefficients, as :func:`scipy.signal.savgol_coeffs` gives them (the
    centre's, symmetric: a convolution's order and a dot's are one), kept read-only with the
    ends' (:func:`_rows`): their sum of squares is the smoothed white noise's share, the
    centre's the smoother's own weight."""
    return _rows(window, order)[0]


def savgol(x, window: int, order: int) -> np.ndarray:
    """The record smoothed by a Savitzky–Golay filter, its ends fitted as a whole window.

    Parameters
    ----------
    x : array_like
        Uniformly sampled. [any unit]
    window : int
        Odd number of samples fitted at once.
    order : int
        Degree of the fitted polynomial (< ``window``).

    Returns
    -------
    ndarray
        [x's unit]

    Examples
    --------
    A parabola passes a quadratic filter unchanged, ends included:

    >>> x = np.arange(9.0) ** 2
    >>> bool(np.allclose(savgol(x, 5, 2), x))
    True
    """
    x = np.asarray(x, dtype=float)
    if x.size < window:
        return savgol_filter(x, window, order)
    centre, ends = _rows(window, order)
    half = window // 2
    out = np.empty_like(x)
    out[half:x.size - half] = np.convolve(x, centre[::-1], mode="valid")
    out[:half] = ends @ x[:window]
    out[x.size - half:] = (ends @ x[::-1][:window])[::-1]
    return out
