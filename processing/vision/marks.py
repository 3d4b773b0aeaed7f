"""Marks on a paper record: the pips on the time-mark and TDC lines, and the time base.

An oscillograph's time marker lifts its line into a rectangular pip once every mark period
T_mark; a TDC marker does so once per revolution. Once the lines themselves are lifted off
the density (:func:`processing.vision.lines.remove_lines`), a pip leaves its top stroke,
parallel to the line and a pip's height away. :func:`find_pips` looks on either side of a
line for the row where such strokes gather, sums the density of that row band in each column
and times every pip by the sub-pixel column where the sum first rises through half its
level.

:func:`time_base` numbers the time marks (a missing or spurious pip is found by its place
on the grid of the median spacing) and fits the mark positions x_k = a + b·k (b: pixels per
mark period, with its type A uncertainty from the residuals); when a quadratic term is
significant (the paper's speed changed, or the photograph's perspective is not fully taken
out) it is kept, and the time of a column follows from the fitted curve:

.. math:: t(x) = T_{mark}\\, k(x), \\qquad x(k) = a + b k \\;(+ c k^2)

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       labs 6 and 7: n = 60 N/(z T_отм), the time marks as the oscillogram's time base.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize
from scipy.signal import find_peaks

from ..diagnostics import Reason
from ..regression import curvature_test, fit_line
from ..result import Record
from .lines import Line

MIN_PIPS = 2
"""Fewest pips that make a mark line."""

PIP_INK = 0.33
"""Least density of a pip's stroke over its line's (the same marker draws both, within a
factor of three)."""

ROOT_SHARE = 0.12
"""Least density of a pip's sides next to its line, as a share of the line's: a marker's
galvanometer swings out fast, so the sides of a short tick are far fainter than its line and
its tip (a spot's exposure goes as one over its speed); a trace passing by leaves nothing
there."""

MIN_RISE = 1.5
"""Least distance of a pip's tops from its line's centre, in the line's widths (+1 px): a
marker lifts its spot clear of the line it draws at rest; a trace that keeps near one level
and dips off it by less than its own stroke (a small speed ripple) is no mark line."""

MIN_TIME_MARKS = 3
"""Fewest time marks a time base is fitted to."""

OFF_GRID = 0.2
"""A pip farther than this fraction of the spacing from its place on the grid is dropped."""

MAX_RESIDUAL = 0.05
"""Largest RMS scatter of the marks about the fitted time base, as a fraction of their
spacing: more means the pips were not timed (blurred into each other, or edges counted as
pips)."""


@dataclass(frozen=True)
class Pips(Record):
    """The pips beside one straight line.

    Attributes
    ----------
    line : Line
        The line they rise from.
    side : int
        −1: above the line (towards smaller rows), +1: below.
    offset : float
        Distance of the pips' tops from the line. [px]
    rising : numpy.ndarray
        Column of each pip's rising edge (sub-pixel), increasing. [px]
    falling : numpy.ndarray
        Column of each pip's falling edge. [px]
    band : tuple of int
        First and one-past-last row the line and its pips occupy.
    edge_u : float
        Standard uncertainty of where each pip rises against its centre (common to all
        pips): small where the pip's sides are resolved, half the pip where blur merges
        them. [px]
    """

    line: Line
    side: int
    offset: float
    rising: np.ndarray
    falling: np.ndarray
    band: tuple[int, int]
    edge_u: float

    @property
    def count(self) -> int:
        return int(self.rising.size)


def find_pips(density: np.ndarray, line: Line, noise: float,
              reach: tuple[float, float]) -> Pips | None:
    """The pips on either side of ``line``, or None.

    Parameters
    ----------
    density : numpy.ndarray
        Density with the straight lines removed.
    line : Line
        A straight line along the rows.
    noise : float
        σ of the density on bare paper.
    reach : (float, float)
        Farthest distance from the line searched for the pips' tops, above and below it.
        [px]

    Returns
    -------
    Pips or None
        The side with more pips of a consistent length (at least :data:`MIN_PIPS`) whose
        strokes are about as dark as the line (0.33–3 times: drawn by the same marker).
    """
    h, w = density.shape
    cols = np.arange(w)
    centre = line.at(cols)
    near = line.width / 2 + 2
    best = None
    for side in (-1, 1):
        room = (line.position - 3) if side < 0 else (h - 4 - line.position)
        far = min(reach[0] if side < 0 else reach[1], room)          # the sheet's edge stays out
        offsets = np.arange(near, max(far, near + 2))
        rows = np.clip(np.round(centre[None, :] + side * offsets[:, None]).astype(int), 0, h - 1)
        strip = density[rows, cols[None, :]]
        # each row's paper level (its median: pips are a small share of its columns) set
        # aside, so that a few sparse pips stand out of an unevenly flattened paper
        profile = strip.mean(axis=1) - np.median(strip, axis=1)
        # the pips' tops gather in one row band, well above the rows their sides cross (a
        # spike's tip, where the beam turns, only about twice its slanted sides): the three
        # highest maxima of the row profile are tried, and proved pips or not below
        peaks, _ = find_peaks(np.concatenate([[-np.inf], profile, [-np.inf]]))
        peaks = peaks - 1
        peaks = peaks[(profile[peaks] >= 8 * noise / math.sqrt(w))
                      & (offsets[peaks] >= MIN_RISE * line.width + 1)]
        standing = profile[peaks] >= TOPS_OVER_SIDES * np.median(profile)
        if standing.any() or offsets[-1] > 2 * offsets[peaks].max(initial=0.0):
            peaks = peaks[standing]
        # else: the rows searched end near the pips' tops (a mark line by the sheet's
        # edge), so their slanted sides fill most of them: the highest maxima are tried
        for j in peaks[np.argsort(profile[peaks])[::-1]][:3]:
            found = _pips_at(density, strip, offsets, int(j), side, line, noise, centre)
            if found is not None and (best is None or found.count > best.count):
                best = found
    if best is None:
        combs = [_comb(density, line, noise, centre, side, reach) for side in (-1, 1)]
        found = [c for c in combs if c is not None]
        best = found[0] if len(found) == 1 else None      # a comb on both sides: no base
    return best


TOPS_OVER_SIDES = 1.5
"""Least density of the row the pips' tops gather in, over the median row beside the line (a
flat-topped pip's top stroke stands far above its sides; a narrow spike's tip, 1.9 times its
slanted sides on the lab 3 strips of :mod:`processing.synth.paper_strip`)."""


COMB_SHARE = 0.5
"""Share of the column profile's varying power that its strongest frequency (with its
neighbouring bins) holds, above which a band beside a line is a comb of pips."""


def _comb(density, line, noise, centre, side, reach) -> Pips | None:
    """Pips too dense to be told apart one by one (a few pixels apart, their sides blurred
    into bars): timed by their own period. The rows beside the line that its pips fill
    (from next to the line out to where the row mean falls below half its level) give a column
    profile; if one frequency holds :data:`COMB_SHARE` of its varying power, the pips stand
    on the even grid x_k = a + b k, b the period of the spectrum's peak (refined between
    bins), each bar's centre where the fundamental peaks, its rising edge half the bars' duty
    (the profile's share above half its range) of b before that; the edges' u is that half
    bar over √3 (rectangular), and the run of the comb the columns where the profile stands
    out of the noise. A line with such a band on both sides is the middle of a comb taken
    for a line, not its base: no side is taken (the pips' direction is unknown)."""
    h, w = density.shape
    cols = np.arange(w)
    room = (line.position - 3) if side < 0 else (h - 4 - line.position)
    far = min(reach[0] if side < 0 else reach[1], room)
    offsets = np.arange(line.width / 2 + 2, max(far, line.width / 2 + 4))
    rows = np.clip(np.round(centre[None, :] + side * offsets[:, None]).astype(int), 0, h - 1)
    strip = density[rows, cols[None, :]]
    rows = strip.mean(axis=1)
    level = max(8 * noise / math.sqrt(w), 2 * float(np.median(rows)))
    filled = np.flatnonzero(rows >= level)
    if filled.size == 0 or offsets[filled[0]] > 2 * line.width + 4:
        return None                                   # nothing rising from the line
    start = int(filled[0])
    top = start + int(np.argmax(np.concatenate([rows[start:] < 0.5 * rows[start], [True]])))
    if top - start < 2:
        return None
    profile = strip[start:top].mean(axis=0)
    cols = np.flatnonzero(profile > 4 * noise / math.sqrt(top - start))
    if cols.size < 16:
        return None
    lo, hi = int(cols[0]), int(cols[-1]) + 1
    x = profile[lo:hi] - profile[lo:hi].mean()
    power = np.abs(np.fft.rfft(x * np.hanning(x.size))) ** 2
    power[:3] = 0.0
    k = int(np.argmax(power))
    if k + 1 >= power.size or power[k - 1:k + 2].sum() < COMB_SHARE * power.sum():
        return None
    a, b, c = np.log(power[k - 1:k + 2] + 1e-300)
    peak = k + 0.5 * (a - c) / (a - 2 * b + c)
    period = x.size / peak
    if period < 3 or (hi - lo) / period < MIN_TIME_MARKS:
        return None
    phase = np.angle(np.sum(x * np.exp(-2j * np.pi * np.arange(x.size) / period)))
    first = lo + (phase / (2 * np.pi)) % 1 * period
    span = np.ptp(x)
    duty = float(np.mean(x > x.min() + 0.5 * span)) if span > 0 else 0.5
    centres = first + period * np.arange(-1, (hi - first) / period + 1)
    centres = centres[(centres - duty * period / 2 >= lo) & (centres + duty * period / 2 <= hi)]
    rising, falling = centres - duty * period / 2, centres + duty * period / 2
    if rising.size < MIN_TIME_MARKS:
        return None
    offset = float(offsets[top - 1])
    near = line.width / 2 + 2
    band = np.concatenate([centre + side * (offset + line.width + 2), centre - side * near])
    return Pips(line, side, offset, rising, falling,
                (max(int(np.floor(band.min())), 0), min(int(np.ceil(band.max())) + 1, h)),
                float(duty * period / 2 / math.sqrt(3)))


def _pips_at(density, strip, offsets, j, side, line, noise, centre) -> Pips | None:
    """The pips whose tops lie at ``offsets[j]`` on ``side`` of ``line``, if they pass as
    pips (see :func:`find_pips`)."""
    h, w = density.shape
    cols = np.arange(w)
    half = int(math.ceil(line.width)) + 1
    band = strip[max(j - half, 0):j + half + 1]
    # a pip is drawn by the line's marker, about as dark as the line: what stays below a
    # third of it across the band is a printed grid's cross lines, not pips
    tops = band.max(axis=0)
    found = _pulses(np.where(tops > PIP_INK * line.strength, tops, 0.0), noise,
                    line.width)                               # one box per pip
    if found is None or found[0].size < MIN_PIPS:
        return None
    rising, falling = found
    # the whole pip, the line's and the tops' flanks included: there the top stroke and the
    # line missing under it cancel, and the two sides are left
    whole = np.arange(-line.width, offsets[j] + line.width + 0.5)
    rows = np.clip(np.round(centre[None, :] + side * whole[:, None]).astype(int), 0, h - 1)
    sides = density[rows, cols[None, :]].sum(axis=0)
    rising, falling, edge_u = _side_centres(sides, rising, falling, line.width)
    inside = np.concatenate([np.arange(max(int(np.ceil(a)), 0), min(int(b) + 1, w))
                             for a, b in zip(rising, falling)])
    if inside.size == 0:
        return None
    stroke = float(np.median(band[:, inside].max(axis=0)))
    if not PIP_INK < stroke / line.strength < 1 / PIP_INK:
        return None                                   # not drawn by this line's marker
    first = offsets[j] + 1.5 * line.width + 2                 # clear of the tops' blur
    beyond = np.arange(first, first + max(4.0, offsets[j]))
    rows = np.clip(np.round(centre[None, :] + side * beyond[:, None]).astype(int), 0, h - 1)
    below_tops = slice(0, j + 2 * half + 3)       # a trace farther out stays out of it
    if _tops_wander(strip[below_tops], offsets[below_tops], rising, falling) \
            > 1.0 + 0.1 * line.width \
            or not _rooted(strip[:3], rising, line) \
            or not _capped(density[rows, cols[None, :]], rising, falling, line, noise):
        return None                                   # a trace passing by, not pips
    near = line.width / 2 + 2
    span = np.concatenate([centre + side * (offsets[j] + half + 2), centre - side * near])
    return Pips(line, side, float(offsets[j]), rising, falling,
                (max(int(np.floor(span.min())), 0), min(int(np.ceil(span.max())) + 1, h)),
                edge_u)


def _tops_wander(strip: np.ndarray, offsets: np.ndarray, rising: np.ndarray,
                 falling: np.ndarray) -> float:
    """Median distance of each pulse's top row (the offset of the densest row over its middle
    half) from their median: pips' tops lie in one row, a trace's crests do not. [px]"""
    tops = []
    for a, b in zip(rising, falling):
        lo, hi = int(np.ceil(a + 0.25 * (b - a))), int(np.floor(b - 0.25 * (b - a))) + 1
        if hi > lo:
            tops.append(offsets[int(np.argmax(strip[:, lo:hi].mean(axis=1)))])
    tops = np.array(tops)
    return float(np.median(np.abs(tops - np.median(tops)))) if tops.size else np.inf


def _rooted(rows: np.ndarray, rising: np.ndarray, line: Line) -> bool:
    """Whether the pulses' sides rise from the line: in the rows next to it, the density near
    the rising edges (± the line's width) reaches :data:`ROOT_SHARE` of the line's, for most
    pulses."""
    profile = rows.mean(axis=0)
    reach = int(np.ceil(line.width)) + 1
    peaks = [profile[max(int(x) - reach, 0):int(x) + reach + 2].max() for x in rising]
    return float(np.median(peaks)) > ROOT_SHARE * line.strength


def _capped(rows: np.ndarray, rising: np.ndarray, falling: np.ndarray, line: Line,
            noise: float) -> bool:
    """Whether the pulses end at their tops: in the rows beyond them, around each pulse (half
    its length and the line's width either side), the density stays below a quarter of the
    line's (and 5 σ of the noise) for most pulses. A trace crossing a line runs on past any
    'top'."""
    profile = rows.max(axis=0)
    peaks = []
    for a, b in zip(rising, falling):
        reach = 0.5 * (b - a) + line.width
        peaks.append(profile[max(int(a - reach), 0):int(b + reach) + 1].max())
    return float(np.median(peaks)) < max(0.25 * line.strength, 5 * noise)


def _side_centres(sums: np.ndarray, rising: np.ndarray, falling: np.ndarray,
                  width: float) -> tuple[np.ndarray, np.ndarray, float]:
    """The centres of the pips' vertical sides, from the column profile summed over the
    whole height of the pips (the line lifted off leaves a gap under each pip that the pip's
    top fills, so only the two sides remain).

    Each pip's centre is the midpoint of the centroids of its two sides (taken in windows
    re-centred twice on them; blur pulls the two towards each other alike, so their midpoint
    stays true, even where they merge into one). The sides' half distance h then comes from
    one fit to all pips' profiles, laid over each other at their centres, of two equal
    Gaussian strokes A [g(x + h) + g(x − h)] + B (σ fitted too). The third value returned
    is the standard uncertainty of the edges against the centre [px]: u(h) from the fit,
    and at least h/2 where the sides are blurred into one (σ ≥ h: no dip between them).
    """
    reach = np.minimum(1.5 * width + 2, 0.45 * (falling - rising))
    rise, fall = rising.copy(), falling.copy()
    for _ in range(3):
        rise = _centroids(sums, rise, reach)
        fall = _centroids(sums, fall, reach)
    centre = 0.5 * (rise + fall)
    half = 0.5 * float(np.median(falling - rising))
    gap = float(np.median(np.diff(centre))) if centre.size > 1 else np.inf
    span = min(half + 3 * width + 3, 0.5 * gap)          # the neighbours stay out
    x, y = [], []
    for c in centre:
        cols = np.arange(max(int(np.ceil(c - span)), 0),
                         min(int(np.floor(c + span)), sums.size - 1) + 1)
        x.append(cols - c)
        y.append(sums[cols])
    x, y = np.concatenate(x), np.concatenate(y)

    def model(x, h, sigma, a, b):
        return a * (np.exp(-0.5 * ((x + h) / sigma) ** 2)
                    + np.exp(-0.5 * ((x - h) / sigma) ** 2)) + b

    try:
        (h, sigma, *_), cov = optimize.curve_fit(
            model, x, y, p0=(half, max(width / 2.355, 0.7), max(float(y.max()), 1e-6), 0.0),
            bounds=([0.1 * half, 0.3, 0, -np.inf], [2 * half + 1, span, np.inf, np.inf]))
    except (RuntimeError, ValueError):
        return centre - half, centre + half, half
    u = math.sqrt(max(float(cov[0, 0]), 0.0))
    return centre - h, centre + h, u if sigma < h else max(u, 0.5 * h)


def _centroids(sums: np.ndarray, near: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Centroid of the (non-negative) profile in a window of ± ``reach`` about each point."""
    out = near.copy()
    for i, (x, r) in enumerate(zip(near, reach)):
        a = max(int(np.floor(x - r)), 0)
        b = min(int(np.ceil(x + r)) + 1, sums.size)
        cols = np.arange(a, b)
        v = np.clip(sums[a:b], 0, None) * np.clip(r + 0.5 - np.abs(cols - x), 0, 1)
        if v.sum() > 0:
            out[i] = float((v * cols).sum() / v.sum())
    return out


def _pulses(sums: np.ndarray, sigma: float, bridge: float) -> tuple[np.ndarray, np.ndarray] | None:
    """Rising and falling edges of the pulses in a column profile (half-level crossings),
    pulses closer than ``bridge`` px joined (a blurred pip's sides outshine its top), and
    keeping pulses whose length is within 0.6–1.6 of the median."""
    high = sums > 6 * sigma
    if high.sum() < 3:
        return None
    level = float(np.median(sums[high]))
    threshold = max(0.5 * level, 4 * sigma)
    above = np.concatenate([[False], sums > threshold, [False]])
    change = np.diff(above.astype(np.int8))
    starts, ends = np.flatnonzero(change == 1), np.flatnonzero(change == -1)
    if starts.size > 1:
        join = starts[1:] - ends[:-1] < bridge
        starts = starts[np.concatenate([[True], ~join])]
        ends = ends[np.concatenate([~join, [True]])]
    inner = (starts > 0) & (ends < sums.size)
    starts, ends = starts[inner], ends[inner]
    length = ends - starts
    if starts.size < MIN_PIPS:
        return None
    typical = np.median(length)
    keep = (length >= max(2, 0.6 * typical)) & (length <= 1.6 * typical)
    starts, ends = starts[keep], ends[keep]
    if starts.size < MIN_PIPS:
        return None
    rise = starts - 1 + (threshold - sums[starts - 1]) / (sums[starts] - sums[starts - 1])
    fall = ends - 1 + (sums[ends - 1] - threshold) / (sums[ends - 1] - sums[ends])
    return rise.astype(float), fall.astype(float)


@dataclass(frozen=True)
class TimeBase(Record):
    """Column → time, from the time marks.

    Attributes
    ----------
    period : float
        The mark period T_mark. [s]
    origin : float
        Column of mark number 0. [px]
    spacing : float
        Pixels per mark period at mark 0 (b). [px]
    u_spacing : float
        Standard uncertainty of ``spacing`` (type A, residuals of the straight-line fit). [px]
    curvature : float
        c of the quadratic term, 0 when none is significant. [px]
    dof : int
        Degrees of freedom of ``u_spacing``.
    residual : float
        RMS of the marks about the fitted curve. [px]
    marks : numpy.ndarray
        Columns of the marks used. [px]
    numbers : numpy.ndarray
        Their numbers k.
    """

    period: float
    origin: float
    spacing: float
    u_spacing: float
    curvature: float
    dof: int
    residual: float
    marks: np.ndarray
    numbers: np.ndarray

    def time(self, x) -> np.ndarray:
        """Time at columns ``x`` from mark 0. [s]"""
        x = np.asarray(x, dtype=float)
        if self.curvature == 0.0:
            return self.period * (x - self.origin) / self.spacing
        k = np.linspace(self.numbers.min() - 2, self.numbers.max() + 2, 4001)
        xk = self.origin + self.spacing * k + self.curvature * k ** 2
        slope_lo = self.spacing + 2 * self.curvature * k[0]
        slope_hi = self.spacing + 2 * self.curvature * k[-1]
        kx = np.interp(x, xk, k)
        kx = np.where(x < xk[0], k[0] + (x - xk[0]) / slope_lo, kx)
        kx = np.where(x > xk[-1], k[-1] + (x - xk[-1]) / slope_hi, kx)
        return self.period * kx

    @property
    def speed_change(self) -> float:
        """Relative change of the pixels per period from the first mark to the last."""
        return float(2 * self.curvature * (self.numbers.max() - self.numbers.min())
                     / self.spacing)


class TimeMarkError(Reason):
    """The time marks do not make a time base (too few, or not on a regular grid): why, in
    English and Russian."""


def time_base(rising, period: float) -> TimeBase:
    """Number the time marks and fit their positions.

    Parameters
    ----------
    rising : array_like
        Columns of the pips' rising edges, increasing. [px]
    period : float
        The mark period. [s]

    Returns
    -------
    TimeBase

    Raises
    ------
    TimeMarkError
        Fewer than :data:`MIN_TIME_MARKS` marks on a common grid, or marks scattered by more
        than :data:`MAX_RESIDUAL` of their spacing.

    Examples
    --------
    >>> tb = time_base([10.0, 60.1, 109.9, 160.0, 260.1, 310.0], 0.01)
    >>> tb.numbers.tolist(), round(tb.spacing, 2), round(float(tb.time(210.0)), 4)
    ([0, 1, 2, 3, 5, 6], 50.0, 0.04)
    """
    x = np.asarray(rising, dtype=float)
    if x.size < MIN_TIME_MARKS:
        raise TimeMarkError(f"{x.size} time mark(s) found, at least {MIN_TIME_MARKS} needed",
                            f"найдено отметок времени: {x.size}, а нужно не меньше "
                            f"{MIN_TIME_MARKS}")
    gaps = np.diff(x)
    spacing = float(np.median(gaps))
    regular = np.flatnonzero(np.abs(gaps - spacing) < 0.1 * spacing)
    if regular.size == 0:
        raise TimeMarkError("the time marks are not evenly spaced",
                            "отметки времени стоят неравномерно")
    origin = x[regular[0]]
    keep = np.ones(x.size, bool)
    for _ in range(3):
        k = np.round((x - origin) / spacing)
        off = np.abs(x - origin - spacing * k) > OFF_GRID * spacing
        keep = ~off & _first_of_each(k, np.abs(x - origin - spacing * k))
        if keep.sum() < MIN_TIME_MARKS:
            raise TimeMarkError(f"only {keep.sum()} time mark(s) lie on a regular grid, at "
                                f"least {MIN_TIME_MARKS} needed",
                                f"отметок времени на равномерной сетке лишь {keep.sum()}, а "
                                f"нужно не меньше {MIN_TIME_MARKS}")
        fit = fit_line(k[keep], x[keep])
        origin, spacing = fit.intercept, fit.slope
    if fit.residual_sd > MAX_RESIDUAL * spacing:
        raise TimeMarkError(f"the time marks scatter by {fit.residual_sd:.2g} px about an even "
                            f"spacing of {spacing:.4g} px: they cannot be timed",
                            f"отметки времени отклоняются на {fit.residual_sd:.2g} пикс от "
                            f"равномерного шага {spacing:.4g} пикс: по ним не отсчитать "
                            "время")
    k = np.round((x - origin) / spacing)
    k0 = k[keep].min()
    numbers, marks = (k[keep] - k0).astype(int), x[keep]
    fit = fit_line(numbers, marks)
    curvature, residual = 0.0, fit.residual_sd
    if numbers.size >= 5 and curvature_test(numbers, marks).significant():
        c, b, a = np.polyfit(numbers, marks, 2)
        quad = marks - (a + b * numbers + c * numbers ** 2)
        curvature, residual = float(c), float(np.sqrt(np.sum(quad ** 2) / (numbers.size - 3)))
        return TimeBase(period, float(a), float(b), fit.u_slope, curvature, fit.dof - 1,
                        residual, marks, numbers)
    return TimeBase(period, fit.intercept, fit.slope, fit.u_slope, curvature, fit.dof,
                    residual, marks, numbers)


def _first_of_each(k: np.ndarray, distance: np.ndarray) -> np.ndarray:
    """True at the mark nearest its grid place among those given the same number."""
    keep = np.zeros(k.size, bool)
    order = np.lexsort((distance, k))
    _, first = np.unique(k[order], return_index=True)
    keep[order[first]] = True
    return keep


ROW_SHARE = (0.04, 0.6)
"""Share of a row's columns a row of marks without a line inks: at least a few marks' worth,
at most a marker's longest flashes (a trace at rest along a row inks more)."""

ROW_HEIGHT = 0.06
"""Tallest band of rows a row of marks without a line fills, as a share of the sheet's
height (a lamp's dashes or dots are a millimetre or two across)."""


def find_mark_rows(density: np.ndarray, noise: float) -> list[Pips]:
    """Rows of marks drawn without a line: a lamp's dashes or dots flashed on the paper (a
    time marker or a TDC contact lighting a spot), found where the straight lines have been
    lifted off.

    A band of rows is a row of marks when, across it, the ink forms a periodic train: the
    columns summed over the band hold pulses of one length (:func:`_pulses`) whose starts lie
    on an even grid (:func:`time_base`, at least :data:`MIN_TIME_MARKS` of them), and each
    pulse ends within the band: the rows just beyond it, above and below, are bare there (a
    trace crossing the band runs on; its crossings of its own middle row are as even as marks).
    Each row found is returned as :class:`Pips` on a level 'line' through the band's middle
    (no line is drawn: its ``share`` is 0), the marks' rising edges (sub-pixel half-level
    crossings) as their times, their u the scatter of their lengths over √2.

    Parameters
    ----------
    density : numpy.ndarray
        Density with the straight lines removed.
    noise : float
        σ of the density on bare paper.

    Returns
    -------
    list of Pips
        Top to bottom.
    """
    h, w = density.shape
    level = 6 * noise
    share = (density > level).mean(axis=1)
    rows = np.flatnonzero((share >= ROW_SHARE[0]) & (share <= ROW_SHARE[1]))
    if rows.size == 0:
        return []
    bands = np.split(rows, np.flatnonzero(np.diff(rows) > 2) + 1)
    out = []
    for band in bands:
        lo, hi = int(band[0]), int(band[-1]) + 1
        if hi - lo > ROW_HEIGHT * h or hi - lo < 2:
            continue
        found = _pulses(np.clip(density[lo:hi], 0, None).max(axis=0), noise, 2.0)
        if found is None or found[0].size < MIN_TIME_MARKS:
            continue
        rising, falling = found
        try:
            base = time_base(rising, 1.0)
        except TimeMarkError:
            continue
        strength = float(np.median([density[lo:hi, int(a):int(b) + 1].max()
                                    for a, b in zip(rising, falling)]))
        if not _bounded(density, lo, hi, rising, falling, strength, noise):
            continue
        keep = np.isin(rising, base.marks)
        rising, falling = rising[keep], falling[keep]
        line = Line(0.5 * (lo + hi - 1), 0.0, strength, float(hi - lo), 0.0, w / 2)
        spread = float(np.std(falling - rising)) / math.sqrt(2) if rising.size > 1 else 0.5
        out.append(Pips(line, -1, 0.0, rising, falling,
                        (max(lo - 2, 0), min(hi + 2, h)), max(spread, 0.1)))
    return out


def _bounded(density: np.ndarray, lo: int, hi: int, rising: np.ndarray, falling: np.ndarray,
             strength: float, noise: float) -> bool:
    """Whether the pulses of a band end within it: beyond the band by 2–5 px above and
    below, over each pulse's columns, the density stays below a quarter of theirs (and 5 σ
    of the noise) for most pulses."""
    h = density.shape[0]
    beyond = [r for r in (*range(lo - 5, lo - 1), *range(hi + 2, hi + 6)) if 0 <= r < h]
    if not beyond:
        return False
    peaks = [density[beyond, max(int(a), 0):int(b) + 1].max() for a, b in zip(rising, falling)]
    return float(np.median(peaks)) < max(0.25 * strength, 5 * noise)
