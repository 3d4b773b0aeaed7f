"""The swing of a periodic trace: the mean cycle's highest and lowest points and its mean level,
from a Fourier series fitted to each cycle between marks.

A trace read off paper (a speed trace over working cycles, TDC marks between them) is noisy at
the scale of a pixel, and its highest and lowest samples are biased outwards by that noise.
Fitting each cycle with the orders that stand out of the cycle-to-cycle scatter, and taking
the extremes of the mean of those fits, reads what a student reads with a ruler — the swing
of the mean cycle — without the noise's bias; the scatter of the cycles gives its
uncertainty by the jackknife.

Examples
--------
>>> t = np.linspace(0.0, 1.0, 4001)
>>> h = 90.0 + 0.5 * np.cos(2 * np.pi * 8 * t) + 0.2 * np.sin(2 * np.pi * 16 * t)
>>> r = cycle_range(t, h, np.arange(0.0, 1.01, 0.25))
>>> r.orders, round(r.level, 6), round(r.swing / r.level, 6)
(4, 90.0, 0.013496)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..diagnostics import Reason

SIGNIFICANCE = 3.0
"""An order is kept when its mean amplitude exceeds this many standard errors of the mean over
the cycles."""

MOST_ORDERS = 40
"""Highest order tried (and at most a quarter of a cycle's samples)."""


@dataclass(frozen=True)
class CycleRange:
    """Fourier fits of a trace's cycles and the swing of their mean.

    Attributes
    ----------
    coefficients : numpy.ndarray
        One row per cycle: a₀, a₁, b₁, …, a_M, b_M of
        h(θ) = a₀ + Σ a_m cos mθ + b_m sin mθ, θ = 2π (t − t_k)/(t_{k+1} − t_k).
    orders : int
        M, the highest order kept.
    phase : numpy.ndarray
        The grid θ the curves are evaluated on. [rad]
    durations : numpy.ndarray
        Each cycle's length t_{k+1} − t_k (the trace's time unit).
    """

    coefficients: np.ndarray
    orders: int
    phase: np.ndarray
    durations: np.ndarray

    def deblurred(self, sigma: float) -> CycleRange:
        """The cycles as they were before a Gaussian smoothing of σ along the time axis (a
        photograph's blur low-passes a trace read off it).

        A Gaussian of σ multiplies the component of frequency m/τ_k by
        exp(−(2π m σ/τ_k)²/2); order m of cycle k is divided by that.

        Parameters
        ----------
        sigma : float
            σ of the smoothing, in the trace's time unit (0: unchanged).

        Returns
        -------
        CycleRange
        """
        m = np.repeat(np.arange(1, self.orders + 1), 2)
        gain = np.ones_like(self.coefficients)
        gain[:, 1:] = np.exp(0.5 * (2 * np.pi * m[None, :] * sigma
                                    / self.durations[:, None]) ** 2)
        return CycleRange(self.coefficients * gain, self.orders, self.phase, self.durations)

    @property
    def cycles(self) -> int:
        return self.coefficients.shape[0]

    def curve(self, coefficients) -> np.ndarray:
        """h(θ) on :attr:`phase` for one row of coefficients (or their mean)."""
        c = np.asarray(coefficients, dtype=float)
        m = np.arange(1, self.orders + 1)[:, None] * self.phase
        return c[0] + c[1::2] @ np.cos(m) + c[2::2] @ np.sin(m)

    @property
    def mean_cycle(self) -> np.ndarray:
        """The mean of the cycles' fits on :attr:`phase`."""
        return self.curve(self.coefficients.mean(axis=0))

    @property
    def high(self) -> float:
        """The mean cycle's highest point."""
        return float(self.mean_cycle.max())

    @property
    def low(self) -> float:
        """The mean cycle's lowest point."""
        return float(self.mean_cycle.min())

    @property
    def level(self) -> float:
        """The mean cycle's mean level, a₀."""
        return float(self.coefficients[:, 0].mean())

    @property
    def swing(self) -> float:
        """high − low."""
        return self.high - self.low

    def relative_swing(self) -> tuple[float, float]:
        """(high − low)/level and its standard uncertainty by the jackknife over the cycles
        (NaN with fewer than three cycles).

        .. math:: u^2 = \\frac{n-1}{n} \\sum_k (r_{(-k)} - \\bar r_{(\\cdot)})^2
        """
        return self._jackknife(lambda curve, level: (curve.max() - curve.min()) / level)

    def absolute_swing(self) -> tuple[float, float]:
        """high − low and its standard uncertainty by the jackknife over the cycles (NaN with
        fewer than three cycles): the swing alone, for a trace whose zero is not on the
        record (its scale comes from elsewhere)."""
        return self._jackknife(lambda curve, level: curve.max() - curve.min())

    def _jackknife(self, stat) -> tuple[float, float]:
        """``stat(mean cycle, level)`` and its jackknife standard uncertainty over the
        cycles."""
        value = stat(self.mean_cycle, self.level)
        n = self.cycles
        if n < 3:
            return value, float("nan")
        total = self.coefficients.sum(axis=0)
        loo = np.asarray([stat(self.curve((total - row) / (n - 1)), (total[0] - row[0]) / (n - 1))
                          for row in self.coefficients])
        return value, float(np.sqrt((n - 1) / n * np.sum((loo - loo.mean()) ** 2)))


def cycle_range(time, value, starts, *, orders: int | None = None,
                grid: int = 1440) -> CycleRange:
    """Fit each cycle of a trace between successive ``starts`` with a Fourier series.

    Parameters
    ----------
    time, value : array_like
        The trace (NaN samples are left out). [s], [any unit]
    starts : array_like
        Times the cycles begin (TDC marks, every working cycle's); n + 1 of them bound n
        cycles. [s]
    orders : int, optional
        Highest order M; by default the highest whose mean amplitude over the cycles stands
        :data:`SIGNIFICANCE` standard errors out of their scatter (with at least three cycles;
        with fewer, :data:`MOST_ORDERS` or a quarter of the samples).
    grid : int
        Points of :attr:`CycleRange.phase`.

    Returns
    -------
    CycleRange

    Raises
    ------
    Reason
        No whole cycle within the trace, or a cycle with too few samples for one order (a
        ValueError, its text in English and in Russian).
    """
    t, h = np.asarray(time, dtype=float), np.asarray(value, dtype=float)
    edges = np.asarray(starts, dtype=float)
    edges = edges[(edges >= t[0]) & (edges <= t[-1])]
    if edges.size < 2:
        raise Reason("no whole cycle between the marks within the trace",
                     "между отметками в пределах записи нет ни одного целого цикла")
    pieces = []
    for a, b in zip(edges[:-1], edges[1:]):
        inside = (t >= a) & (t < b) & np.isfinite(h)
        pieces.append((2 * np.pi * (t[inside] - a) / (b - a), h[inside]))
    fewest = min(p[0].size for p in pieces)
    most = min(MOST_ORDERS, fewest // 4) if orders is None else int(orders)
    if most < 1 or 2 * most + 1 > fewest:
        raise Reason(f"a cycle holds {fewest} samples read: too few for a Fourier fit",
                     f"в цикле прочитано отсчётов: {fewest}, для ряда Фурье этого мало")
    coefficients = np.array([_fit(theta, y, most) for theta, y in pieces])
    keep = most if orders is not None else _significant(coefficients, most)
    if keep < most:
        coefficients = np.array([_fit(theta, y, keep) for theta, y in pieces])
    return CycleRange(coefficients, keep, np.linspace(0.0, 2 * np.pi, grid, endpoint=False),
                      np.diff(edges))


def _fit(theta: np.ndarray, y: np.ndarray, orders: int) -> np.ndarray:
    m = np.arange(1, orders + 1)[:, None] * theta
    design = np.empty((theta.size, 2 * orders + 1))
    design[:, 0] = 1.0
    design[:, 1::2] = np.cos(m).T
    design[:, 2::2] = np.sin(m).T
    return np.linalg.lstsq(design, y, rcond=None)[0]


def _significant(coefficients: np.ndarray, most: int) -> int:
    """The highest order whose mean amplitude stands out of the cycles' scatter."""
    n = coefficients.shape[0]
    if n < 3:
        return most
    mean = coefficients.mean(axis=0)
    se = coefficients.std(axis=0, ddof=1) / np.sqrt(n)
    amplitude = np.hypot(mean[1::2], mean[2::2])
    scatter = np.hypot(se[1::2], se[2::2])
    floor = 1e-9 * max(abs(mean[0]), amplitude.max(initial=0.0))   # rounding, not a signal
    standing = np.flatnonzero((amplitude > SIGNIFICANCE * scatter) & (amplitude > floor))
    return int(standing[-1] + 1) if standing.size else 1
