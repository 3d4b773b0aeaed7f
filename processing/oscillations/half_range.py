"""The half range of an oscillation's extrema with the baseline drift taken out.

Lab 7's peak amplitudes and lab 9's decay both measure an oscillation riding on a slow drift
by the manual's construction: the two opposite extrema beside an extremum are joined by a
straight line, and the extremum's distance from that line, halved, is its half range.
"""
from __future__ import annotations

import numpy as np


def neighbour_baseline(position, value) -> np.ndarray:
    r"""The line through each extremum's two neighbours, taken to its own position.

    .. math:: b_k = x_{k-1} + (x_{k+1} - x_{k-1})\,\frac{s_k - s_{k-1}}{s_{k+1} - s_{k-1}}

    and the half range is :math:`|x_k - b_k|/2`. A linear drift's offset cancels exactly.

    Parameters
    ----------
    position : array_like
        Time or crank angle of each extremum, increasing. [s] or [rad]
    value : array_like
        The record at each extremum, alternating maxima and minima. [any unit]

    Returns
    -------
    ndarray
        b_k; NaN at the first and last extremum (one neighbour missing).

    Examples
    --------
    Extrema of ±1 about a drift of 0.1 a step:

    >>> s = np.arange(5.0)
    >>> x = np.array([1, -1, 1, -1, 1]) + 0.1 * s
    >>> b = neighbour_baseline(s, x)
    >>> np.round(0.5 * np.abs(x - b), 12).tolist()
    [nan, 1.0, 1.0, 1.0, nan]
    """
    s = np.asarray(position, dtype=float)
    x = np.asarray(value, dtype=float)
    base = np.full(x.size, np.nan)
    if x.size >= 3:
        w = (s[1:-1] - s[:-2]) / (s[2:] - s[:-2])
        base[1:-1] = x[:-2] + (x[2:] - x[:-2]) * w
    return base
