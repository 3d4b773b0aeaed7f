"""Traces on a paper record: followed column by column to a sub-pixel row, with a confidence
per column and gaps where a trace is lost or two traces cross.

:func:`find_runs` cuts every column of the density (straight lines and marks already lifted
off) into *runs*: stretches of rows above a threshold (4.5 σ of the paper's noise, and a
quarter of a trace's typical peak). Each run gets its exposure-weighted centroid (over the
run and two rows either side; the exposure E undoes the paper's saturation,
:func:`exposure`), its mass, peak and spread, and the centroid's standard uncertainty from
the noise:

.. math:: \\bar y = \\frac{\\sum_i E_i y_i}{\\sum_i E_i}, \\qquad
          u(\\bar y) = \\frac{\\sigma_D \\sqrt{\\sum_i (E'_i (y_i - \\bar y))^2}}{\\sum_i E_i}

The exposure centroid is the light spot's path averaged over the spot's profile (and the
capture's blur) along the time axis: the trace low-passed by a Gaussian of about the σ the
stroke shows across (:attr:`Traces.spread`), even at a crest sharper than the stroke is wide.

:func:`follow` links runs into traces. It starts from a column where every trace shows as a
separate run and walks to either end, predicting each trace's row from its last row and slope;
a trace takes the run nearest its prediction among those whose rows reach within a gate of
it. When two traces want the same run (they cross, or touch) both get a gap: the reader
never guesses which is which inside a merge. They are picked up again together where each
has a run of its own, and afterwards every such pick-up is checked (:func:`_rejoin`): the
pairing whose strokes join more smoothly across the gap (a quartic through 20 rows each side)
wins; where the two pairings fit about equally well, which trace is which beyond the gap is
unknown, and both keep a confidence of at most 0.3 there. A run's vertical extent covers a
steep stroke, so fast swings are followed too. Where a straight line (a zero line) crosses a
trace, the line's rows are interpolated across before the runs are cut, so the stroke stays
whole.

:func:`confidence` scores each column from 0 to 1 as the product of three factors: the run's
peak over the noise (full at 12 σ, nothing at 4.5 σ), its extent against what a single stroke
of the trace's width at the local slope covers (a run much taller is two strokes merged or a
blot), and its clearance from the nearest other run in the column (tails that touch pull the
centroid).
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..diagnostics import Reason
from ..result import Record

THRESHOLD_SIGMA = 4.5
"""Rows above this many σ of the paper's density noise belong to a run."""

PEAK_SHARE = 0.25
"""... and above this share of a trace's typical peak density."""

PAD = 2
"""Rows either side of a run included in its centroid (the anti-aliased, blurred tails). [px]"""

FULL_CONTRAST = 12.0
"""Peak over σ at which the contrast factor of the confidence reaches 1."""

LOW_CONFIDENCE = 0.5
"""A column read with a confidence below this is counted as unreliable."""

MIN_COVERAGE = 0.2
"""A trace followed in fewer than this share of the columns between its ends is dropped as
noise."""


@dataclass(frozen=True)
class Runs(Record):
    """The runs of every column, ordered by column then row.

    Attributes
    ----------
    column : numpy.ndarray
        Column of each run.
    lo, hi : numpy.ndarray
        First row above the threshold and one past the last.
    top, bottom : numpy.ndarray
        Where the density crosses the threshold above and below the run, interpolated
        linearly between rows (sub-pixel edges). [px]
    centre : numpy.ndarray
        Density-weighted centroid. [px]
    u : numpy.ndarray
        Its standard uncertainty from the noise. [px]
    peak : numpy.ndarray
        Highest density in the run.
    sigma : numpy.ndarray
        The stroke's spread about the centroid in the column (:func:`_spread_of`). [px]
    starts : numpy.ndarray
        Index of the first run of each column (length columns + 1).
    noise : float
        σ of the density.
    typical_peak : float
        Median over the columns of the highest run peak.
    """

    column: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    top: np.ndarray
    bottom: np.ndarray
    centre: np.ndarray
    u: np.ndarray
    peak: np.ndarray
    sigma: np.ndarray
    starts: np.ndarray
    noise: float
    typical_peak: float

    def of(self, column: int) -> slice:
        """The runs of ``column``."""
        return slice(int(self.starts[column]), int(self.starts[column + 1]))

    @property
    def counts(self) -> np.ndarray:
        """Runs in each column."""
        return np.diff(self.starts)


def ink_threshold(density: np.ndarray, noise: float) -> tuple[float, float]:
    """The density above which a pixel is a trace's ink: :data:`THRESHOLD_SIGMA` σ of the
    paper's noise, or :data:`PEAK_SHARE` of the typical column's darkest density if higher;
    and that typical density (the median of the columns' darkest, over those standing
    2 × :data:`THRESHOLD_SIGMA` σ out of the noise)."""
    col_max = density.max(axis=0)
    strong = col_max[col_max > 2 * THRESHOLD_SIGMA * noise]
    typical = float(np.median(strong)) if strong.size else 0.0
    return max(THRESHOLD_SIGMA * noise, PEAK_SHARE * typical), typical


def find_runs(density: np.ndarray, noise: float, lines=()) -> Runs:
    """Cut every column into runs of rows above the threshold and measure each.

    Parameters
    ----------
    density : numpy.ndarray
        Density with lines and marks lifted off, rows × columns; changed in place where a
        trace crosses a line (see ``lines``).
    noise : float
        σ of the density on bare paper.
    lines : sequence of Line
        Straight lines lifted off. Where beams saturate the paper, the stroke of a trace
        crossing a line loses the line's density too; in the columns where the trace is dark
        just above and just below a line, the line's rows are filled by linear interpolation
        between the two, so that the stroke is whole again.

    Returns
    -------
    Runs
        Empty when nothing stands above the threshold.
    """
    h, w = density.shape
    col_max = density.max(axis=0)
    threshold, typical = ink_threshold(density, noise)
    for line in lines:
        _mend_crossings(density, line, threshold)
    mask = np.zeros((w, h + 2), np.int8)
    mask[:, 1:-1] = (density > threshold).T
    change = np.diff(mask, axis=1)
    col, lo = np.nonzero(change == 1)
    _, hi = np.nonzero(change == -1)
    # close gaps of one row inside a stroke (a noisy dip below the threshold)
    if col.size:
        joined = np.concatenate([[False], (col[1:] == col[:-1]) & (lo[1:] - hi[:-1] <= 1)])
        first = np.flatnonzero(~joined)
        last = np.append(first[1:] - 1, col.size - 1)
        col, lo, hi = col[first], lo[first], hi[last]
    starts = np.searchsorted(col, np.arange(w + 1))
    if col.size == 0:
        empty = np.empty(0)
        return Runs(col, lo, hi, empty, empty, empty, empty, empty, empty, starts, noise,
                    typical)
    # padded windows, not reaching into the neighbouring runs of the column
    same_prev = np.concatenate([[False], col[1:] == col[:-1]])
    same_next = np.concatenate([col[1:] == col[:-1], [False]])
    prev_hi = np.where(same_prev, np.roll(hi, 1), 0)
    next_lo = np.where(same_next, np.roll(lo, -1), h)
    a = np.maximum(lo - PAD, prev_hi)
    b = np.minimum(hi + PAD, next_lo)
    size = b - a
    run = np.repeat(np.arange(col.size), size)
    offset = np.arange(run.size) - np.repeat(np.cumsum(size) - size, size)
    rows = np.repeat(a, size) + offset
    values = density[rows, col[run]].astype(np.float64)
    weights, gain = exposure(values, saturation(col_max, noise))
    mass = np.bincount(run, weights, col.size)
    moment = np.bincount(run, weights * rows, col.size)
    centre = moment / np.where(mass > 0, mass, 1.0)
    spread = np.bincount(run, ((rows - centre[run]) * gain) ** 2, col.size)
    u = noise * np.sqrt(spread) / np.where(mass > 0, mass, np.inf)
    sigma = _spread_of(run, rows - centre[run], weights, values, col.size)
    inner = (rows >= np.repeat(lo, size)) & (rows < np.repeat(hi, size))
    peak = np.zeros(col.size)
    np.maximum.at(peak, run[inner], values[inner])
    top, bottom = _edges(density, col, lo, hi, threshold)
    return Runs(col, lo, hi, top, bottom, centre, u, peak, sigma, starts, noise, typical)


SATURATION_PERCENTILE = 99
"""The paper's saturated density is taken as this percentile of the columns' highest
densities (the beams' slow strokes reach it) ..."""

SATURATION_MARGIN = 1.05
"""... times this (a blurred core falls a little short of it)."""

EXPOSURE_CLIP = 0.99
"""Densities are turned into exposures up to this share of the saturated density (beyond,
the noise would decide)."""


def saturation(col_max: np.ndarray, noise: float) -> float:
    """The density at which the paper saturates, from the columns' highest densities
    (:data:`SATURATION_PERCENTILE`, :data:`SATURATION_MARGIN`); inf on a bare sheet."""
    strong = col_max[col_max > 2 * THRESHOLD_SIGMA * noise]
    if strong.size == 0:
        return float("inf")
    return SATURATION_MARGIN * float(np.percentile(strong, SATURATION_PERCENTILE))


def exposure(density: np.ndarray, saturated: float) -> tuple[np.ndarray, np.ndarray]:
    r"""The light each pixel received, from its density on a saturating paper.

    A light-beam oscillograph's paper darkens as :math:`D = D_s (1 - e^{-E/E_0})` with the
    exposure E (a development's characteristic curve, first-order), so that

    .. math:: E = -D_s \ln(1 - D/D_s)

    in units of density (E ≈ D on faint strokes). The centroid of E across a stroke is the
    spot's path averaged over the time it lights the column (the beam's dwell at a crest
    counts fully); that of D is pulled towards where the ink is merely wide (a saturated
    stroke's flat top, the flanks' ink under a sharp crest).

    Parameters
    ----------
    density : numpy.ndarray
        Optical density above the paper's.
    saturated : float
        The paper's saturated density :math:`D_s` (:func:`saturation`).

    Returns
    -------
    exposure : numpy.ndarray
        E, the density's share of :math:`D_s` clipped to [0, :data:`EXPOSURE_CLIP`].
    gain : numpy.ndarray
        dE/dD there: how the density's noise is amplified.
    """
    share = np.clip(density / saturated, 0.0, EXPOSURE_CLIP)
    return -saturated * np.log1p(-share), 1.0 / (1.0 - share)


def _spread_of(run: np.ndarray, offset: np.ndarray, weights: np.ndarray, values: np.ndarray,
               count: int) -> np.ndarray:
    """σ of each run across the stroke: the root of the mean of two second moments about
    the centroid, the exposure's (``weights``: the spot's profile, right where the paper
    saturates and the capture adds little) and the absorbed light's, 1 − 10^(−D) (linear in
    the capture's blur, right where that blur dominates). [px]"""
    light = -np.expm1(-np.log(10.0) * np.clip(values, 0.0, None))
    square = offset ** 2
    exposed = np.bincount(run, weights * square, count) / np.maximum(
        np.bincount(run, weights, count), 1e-12)
    absorbed = np.bincount(run, light * square, count) / np.maximum(
        np.bincount(run, light, count), 1e-12)
    return np.sqrt(0.5 * (exposed + absorbed))


def _edges(density, col, lo, hi, threshold: float) -> tuple[np.ndarray, np.ndarray]:
    """Sub-pixel rows where each run's density crosses ``threshold``, above and below it."""
    h = density.shape[0]

    def crossing(inside, outside):
        a = density[inside, col].astype(np.float64)
        b = density[np.clip(outside, 0, h - 1), col].astype(np.float64)
        share = np.where(a > b, (a - threshold) / np.where(a > b, a - b, 1.0), 0.5)
        return inside + np.clip(share, 0.0, 1.0) * np.sign(outside - inside)

    return crossing(lo, lo - 1), crossing(hi - 1, hi)


def _mend_crossings(density: np.ndarray, line, threshold: float) -> None:
    """Interpolate across ``line``'s rows in the columns a stroke crosses it (dark on both
    sides) and lost its density there (light on the line's row; a stroke left whole, as a
    trace resting on the line and given back, stays as it is)."""
    h, w = density.shape
    cols = np.arange(w)
    half = line.width / 2 + 1
    top = np.floor(line.at(cols) - half).astype(int) - 1
    span = int(np.ceil(2 * half)) + 2
    bottom = top + span
    inside = (top >= 0) & (bottom < h)
    crossing = np.zeros(w, bool)
    centre = np.clip(np.round(line.at(cols)).astype(int), 0, h - 1)
    crossing[inside] = (density[top[inside], cols[inside]] > threshold) \
        & (density[bottom[inside], cols[inside]] > threshold) \
        & (density[centre[inside], cols[inside]] <= threshold)
    c = cols[crossing]
    if c.size == 0:
        return
    a, b = density[top[c], c], density[bottom[c], c]
    for k in range(1, span):
        density[top[c] + k, c] = a + (b - a) * (k / span)


@dataclass(frozen=True)
class Traces(Record):
    """Runs linked into traces.

    Attributes
    ----------
    run : numpy.ndarray
        traces × columns: the run each trace takes in each column, −1 in a gap.
    row : numpy.ndarray
        traces × columns: its centroid row, NaN in a gap. [px]
    u : numpy.ndarray
        Standard uncertainty of ``row`` from the noise, NaN in a gap. [px]
    confidence : numpy.ndarray
        traces × columns, 0 to 1; 0 in a gap.
    width : numpy.ndarray
        Each trace's stroke width across it (:func:`_across`). [px]
    spread : numpy.ndarray
        Each trace's σ across it (:func:`_across` of the runs' ``sigma``): the light spot's
        and the capture's blur, which low-pass the rows read. [px]
    """

    run: np.ndarray
    row: np.ndarray
    u: np.ndarray
    confidence: np.ndarray
    width: np.ndarray
    spread: np.ndarray

    @property
    def count(self) -> int:
        return int(self.run.shape[0])


class NoTraceError(Reason):
    """No trace stands out of the paper: why, in English and Russian."""


def follow(runs: Runs, columns: int, count: int | None = None) -> Traces:
    """Link the runs of consecutive columns into traces.

    Parameters
    ----------
    runs : Runs
    columns : int
        Width of the sheet. [px]
    count : int, optional
        How many traces there are; default: the commonest number of strong runs (peak at
        least half the typical) in a column.

    Returns
    -------
    Traces
        Sorted from the top of the sheet down; traces followed in fewer than
        :data:`MIN_COVERAGE` of their columns are dropped.

    Raises
    ------
    NoTraceError
        No column holds a strong run, or none holds ``count`` separate ones.
    """
    strong = runs.peak >= 0.5 * runs.typical_peak
    per_column = np.bincount(runs.column[strong], minlength=columns)
    if runs.column.size == 0 or per_column.max() == 0:
        raise NoTraceError("no trace stands out of the paper",
                           "ни одна линия записи не выделяется на бумаге")
    if count is None:
        count = int(np.argmax(np.bincount(per_column[per_column > 0])))
    seed = _seed_column(runs, strong, per_column, count)
    if seed is None:
        raise NoTraceError(f"no column shows {count} separate traces",
                           "ни в одном столбце снимка не видны раздельно все линии записи "
                           f"(их должно быть {count})")
    sl = runs.of(seed)
    picked = np.flatnonzero(strong[sl]) + sl.start
    chosen = np.full((count, columns), -1, np.int64)
    chosen[:, seed] = picked
    extent = float(np.median((runs.hi - runs.lo)[strong]))
    doubtful = [(j, c, 1) for j, c in _walk(runs, chosen, seed, range(seed + 1, columns),
                                             extent)]
    doubtful += [(j, c, -1) for j, c in _walk(runs, chosen, seed, range(seed - 1, -1, -1),
                                              extent)]
    ok = chosen >= 0
    row = np.where(ok, runs.centre[np.maximum(chosen, 0)], np.nan)
    cap = _rejoin(chosen, row, seed)
    for j, c, direction in doubtful:
        stretch = _to_next_gap(chosen[j], c, direction)
        cap[j, stretch] = np.minimum(cap[j, stretch], AMBIGUOUS_CONFIDENCE)
    ok = chosen >= 0
    u = np.where(ok, runs.u[np.maximum(chosen, 0)], np.nan)
    row, apex = _apexes(runs, chosen, row)
    keep = []
    for j in range(count):
        valid = np.flatnonzero(ok[j])
        if valid.size and valid.size >= MIN_COVERAGE * (valid[-1] - valid[0] + 1) \
                and valid.size >= 0.05 * columns:
            keep.append(j)
    if not keep:
        raise NoTraceError("no trace could be followed along the sheet",
                           "ни одну линию записи не удалось проследить вдоль ленты")
    order = sorted(keep, key=lambda j: np.nanmean(row[j]))
    chosen, row, u, cap, apex = chosen[order], row[order], u[order], cap[order], apex[order]
    conf, width = confidence(runs, chosen, row, apex)
    return Traces(chosen, row, u, np.minimum(conf, cap), width, _spread(runs, chosen, row))


SHARP = 1.0
"""A crest is read off the stroke's outer edge where the run under it is taller than a single
stroke by more than this many stroke widths: the flanks' ink merged under a crest sharper
than the stroke is wide."""


def _apexes(runs: Runs, chosen: np.ndarray, row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows at the trace's extremes sharper than the stroke, read off its outer edge.

    Where a column's run is taller than a single stroke at its edges' slopes explains (by a
    quarter of the stroke's width across, :func:`_across`, and 1 px) and an extreme of the
    centroids is near (within a stroke width of columns; the nearer kind decides), the
    column lies under a crest or trough: the ink of both flanks fills it. The exposure
    centroid (:func:`exposure`) is still the spot's path there, low-passed by the spot and
    the blur; where the run is taller than the stroke by more than :data:`SHARP` widths,
    the swing is too sharp for that low-pass to be undone, and the row is the outer edge ∓
    (W/2)·√(1 + s²) instead, s the edge's slope — the upper edge at a crest, the lower at a
    trough — W the stroke's edge-to-edge width across (on the convex side the union of
    the spot's discs is bounded by the offset curve).

    Returns
    -------
    row : numpy.ndarray
        The rows, read off the outer edge at the sharp extremes.
    apex : numpy.ndarray
        True under every extreme (the tall run explained).
    """
    ok = chosen >= 0
    idx = np.maximum(chosen, 0)
    top = np.where(ok, runs.top[idx], np.nan)
    bottom = np.where(ok, runs.bottom[idx], np.nan)
    out, apex = row.copy(), np.zeros(row.shape, bool)
    with np.errstate(invalid="ignore"):
        slope = _slope(row)
        s_top, s_bottom = _slope(top), _slope(bottom)
    for j in range(row.shape[0]):
        if not ok[j].any():
            continue
        width = _across(bottom[j] - top[j], slope[j])
        if not np.isfinite(width):      # no two neighbouring columns read: no extreme
            continue
        half, reach = width / 2, max(1, int(np.ceil(width)))
        crest = top[j] + half * np.sqrt(1 + s_top[j] ** 2)
        trough = bottom[j] - half * np.sqrt(1 + s_bottom[j] ** 2)
        r = row[j]                      # extremes of the centroids (NaN compares False)
        up = np.zeros(r.size, bool)
        down = np.zeros(r.size, bool)
        up[1:-1] = (r[1:-1] <= r[:-2]) & (r[1:-1] <= r[2:])
        down[1:-1] = (r[1:-1] >= r[:-2]) & (r[1:-1] >= r[2:])
        to_up, to_down = _distance_to(up), _distance_to(down)
        with np.errstate(invalid="ignore"):
            tall = (trough - crest) > max(1.0, 0.25 * width)
            sharp = (trough - crest) > SHARP * width
        at_crest = tall & (to_up < to_down) & (to_up <= reach)
        at_trough = tall & (to_down < to_up) & (to_down <= reach)
        out[j, at_crest & sharp] = crest[at_crest & sharp]
        out[j, at_trough & sharp] = trough[at_trough & sharp]
        apex[j] = at_crest | at_trough
    return out, apex


def _seed_column(runs: Runs, strong: np.ndarray, per_column: np.ndarray,
                 count: int) -> int | None:
    """The middle one of the columns with exactly ``count`` strong runs, all well apart
    (those without weak runs preferred)."""
    candidates = np.flatnonzero(per_column == count)
    good = []
    for c in candidates:
        sl = runs.of(c)
        mine = np.flatnonzero(strong[sl]) + sl.start
        if count == 1 or np.all(runs.lo[mine][1:] - runs.hi[mine][:-1] >= 3):
            good.append(c)
    clean = [c for c in good if runs.counts[c] == count]
    good = clean if len(clean) >= 0.1 * len(good) else good
    if not good:
        return None
    return int(good[len(good) // 2])


MAX_WAIT = 60
"""Columns traces that merged wait to part together before each may be picked up alone
(then with a confidence of at most :data:`AMBIGUOUS_CONFIDENCE` until its next gap)."""


def _walk(runs: Runs, chosen: np.ndarray, seed: int, steps: range, extent: float) -> list:
    """Follow every trace from ``seed`` over ``steps`` (one direction), filling ``chosen``.

    Traces that lose a run to each other (a crossing, a merge) form a group: they are picked
    up again together, in a column where the runs near them are at least as many as they
    (each a single stroke), by the pairing of traces and runs nearest their predictions. A
    group still merged after :data:`MAX_WAIT` columns breaks up, and each trace is picked up
    alone (doubtful). A trace lost for more than three columns is predicted by a quadratic
    through its last :data:`REJOIN_FIT` rows.

    Returns
    -------
    list of (trace, column)
        Pick-ups after a group broke up: doubtful.
    """
    count = chosen.shape[0]
    pos = runs.centre[chosen[:, seed]].astype(float)
    vel = np.zeros(count)
    last = np.full(count, seed)
    group = np.arange(count)
    history: list[list[tuple[int, float]]] = [[(seed, p)] for p in pos]
    doubtful = []
    base_gate = 1.5 * extent + 2.0
    centre, lo, hi = runs.centre, runs.lo, runs.hi
    starts = runs.starts
    for c in steps:
        s, e = starts[c], starts[c + 1]
        if s == e:
            continue
        dt = c - last
        pred = pos + vel * dt
        for j in np.flatnonzero(np.abs(dt) > 3):
            pred[j] = _extrapolate(history[j], c, pred[j])
        gate = base_gate + 0.5 * np.abs(vel * dt) + 0.5 * (np.abs(dt) - 1)
        rlo, rhi, rc = lo[s:e], hi[s:e] - 1, centre[s:e]
        outside = np.maximum(np.maximum(rlo[None, :] - pred[:, None],
                                        pred[:, None] - rhi[None, :]), 0.0)
        near = outside <= gate[:, None]
        cost = np.where(near, np.abs(rc[None, :] - pred[:, None]), np.inf)
        best = np.argmin(cost, axis=1)
        found = np.isfinite(cost[np.arange(count), best])
        single = extent * np.sqrt(1 + vel ** 2) + np.abs(vel)
        waiting = np.array([(group == group[j]).sum() > 1 for j in range(count)])
        if count > 1:
            # a run two traces want, or one taller than a single stroke with two traces
            # near it, holds both: neither takes it, and they wait to part together
            solo = found & ~waiting
            taken = np.bincount(best[solo], minlength=e - s)
            tall = (rhi - rlo + 1)[best] > 1.8 * single + 2
            crowded = near.sum(axis=0)[best] > 1
            clash = solo & ((taken[best] > 1) | (tall & crowded))
            for r in np.unique(best[clash]):
                members = np.flatnonzero(clash & (best == r))
                partners = np.flatnonzero(near[:, r] & ~waiting)
                group[np.isin(group, group[np.union1d(members, partners)])] = \
                    group[members].min()
            found &= ~clash & ~waiting
            free = np.ones(e - s, bool)
            free[best[found]] = False
            for g in np.unique(group):
                members = np.flatnonzero(group == g)
                if members.size < 2 or (group[members] != g).any():
                    continue
                picked = _pick_group(pred[members], gate[members], single[members],
                                     rlo, rhi, rc, free)
                if picked is None and np.abs(dt[members]).min() > MAX_WAIT:
                    group[members] = members        # broken up: alone, and doubtful
                    ok = found[members] = np.isfinite(cost[members, best[members]])
                    doubtful += [(int(j), c) for j in members[ok]]
                    continue
                if picked is not None:
                    best[members] = picked
                    found[members] = True
                    free[picked] = False
                    group[members] = members
        for j in np.flatnonzero(found):
            y = rc[best[j]]
            step = (y - pos[j]) / dt[j]
            vel[j] = step if abs(dt[j]) > 1 else 0.6 * step + 0.4 * vel[j]
            pos[j], last[j] = y, c
            chosen[j, c] = s + best[j]
            history[j].append((c, y))
            if len(history[j]) > REJOIN_FIT:
                history[j].pop(0)
    return doubtful


def _pick_group(pred, gate, single, rlo, rhi, rc, free) -> np.ndarray | None:
    """Distinct runs for a group's traces: among the free single-stroke runs within twice
    their gates, the pairing with the least total distance from the predictions; None when
    the runs near them are fewer than they."""
    outside = np.maximum(np.maximum(rlo[None, :] - pred[:, None],
                                    pred[:, None] - rhi[None, :]), 0.0)
    near = (outside <= 2 * gate[:, None]) & free[None, :] \
        & ((rhi - rlo + 1)[None, :] <= 1.8 * single[:, None] + 2)
    candidates = np.flatnonzero(near.any(axis=0))
    if candidates.size < pred.size:
        return None
    best, choice = np.inf, None
    for combo in itertools.permutations(candidates, pred.size):
        combo = np.array(combo)
        if not near[np.arange(pred.size), combo].all():
            continue
        total = np.abs(rc[combo] - pred).sum()
        if total < best:
            best, choice = total, combo
    return choice


def _extrapolate(history: list[tuple[int, float]], c: int, linear: float) -> float:
    """Row at column ``c`` from a quadratic through a trace's recent rows (the linear
    prediction with fewer than four)."""
    if len(history) < 4:
        return linear
    x = np.array([h[0] for h in history], dtype=float)
    y = np.array([h[1] for h in history])
    coef = np.polyfit(x - x[-1], y, 2)
    return float(np.polyval(coef, c - x[-1]))


REJOIN_FIT = 20
"""Samples each side of a gap the continuation of a trace is fitted to (a quadratic)."""

AMBIGUOUS = 0.6
"""A rejoining whose better pairing costs more than this share of the other is ambiguous:
which trace is which beyond it is not known, and both keep at most
:data:`AMBIGUOUS_CONFIDENCE` there."""

AMBIGUOUS_CONFIDENCE = 0.3


def _rejoin(chosen: np.ndarray, row: np.ndarray, seed: int) -> np.ndarray:
    """Check which trace is which after every gap two traces share (a crossing or a merge),
    outward from the seed: the pairing that joins into the smoother strokes
    (:func:`_pairing_cost`) is kept, swapping the traces beyond the gap if need be. Returns a
    traces × columns cap on the confidence (below 1 beyond an ambiguous rejoining)."""
    count, columns = chosen.shape
    cap = np.ones(chosen.shape)
    if count < 2:
        return cap
    for direction in (1, -1):
        done: set = set()
        while True:
            event = _next_shared_gap(chosen, seed, direction, done)
            if event is None:
                break
            done.add(event)
            i, k, a, b = event
            keep, swap = (_pairing_cost(row, i, k, a, b, direction, crossed)
                          for crossed in (False, True))
            if not (np.isfinite(keep) or np.isfinite(swap)):
                continue
            far = slice(b, columns) if direction > 0 else slice(0, a + 1)
            if swap < keep:
                chosen[[i, k], far] = chosen[[k, i], far]
                row[[i, k], far] = row[[k, i], far]
                cap[[i, k], far] = cap[[k, i], far]
            if min(keep, swap) > AMBIGUOUS * max(keep, swap):
                cap[[i, k], far] = np.minimum(cap[[i, k], far], AMBIGUOUS_CONFIDENCE)
    return cap


def _next_shared_gap(chosen, seed, direction, done):
    """The nearest gap beyond the seed (in ``direction``) that two traces share:
    (i, k, first column of the gap, first column after it) in walking order, widened to
    both traces' gaps; None when there is none left."""
    count, columns = chosen.shape
    lost = chosen < 0
    cols = np.arange(seed, columns) if direction > 0 else np.arange(seed, -1, -1)
    for c in cols:
        both = np.flatnonzero(lost[:, c])
        if both.size < 2:
            continue
        for x, i in enumerate(both):
            for k in both[x + 1:]:
                a, b = _gap_span(lost[i], c), _gap_span(lost[k], c)
                lo, hi = min(a[0], b[0]), max(a[1], b[1])
                if lo == 0 or hi == columns:
                    continue                       # a trace's end, not a crossing
                ends = (lo - 1, hi) if direction > 0 else (hi, lo - 1)
                key = (int(i), int(k), *ends)
                if key not in done:
                    return key
    return None


def _gap_span(lost: np.ndarray, c: int) -> tuple[int, int]:
    """First and one-past-last column of the gap holding column ``c``."""
    a = c
    while a > 0 and lost[a - 1]:
        a -= 1
    b = c
    while b < lost.size and lost[b]:
        b += 1
    return a, b


def _pairing_cost(row, i, k, a, b, direction, crossed) -> float:
    """How badly the traces join across the gap between columns ``a`` (the last read before
    it, in walking order) and ``b`` (the first after): the RMS residual of a quartic through
    the :data:`REJOIN_FIT` rows each side of each joined pair (one smooth stroke leaves
    noise; a wrong pairing, a kink)."""
    if direction < 0:
        a, b = b, a
    cost = 0.0
    for near, far in ((i, k if crossed else i), (k, i if crossed else k)):
        before = _samples(row[near], a, -1)
        after = _samples(row[far], b, 1)
        if before is None or after is None:
            return np.inf
        x = np.concatenate([before, after]).astype(float)
        y = np.concatenate([row[near][before], row[far][after]])
        t = (x - 0.5 * (a + b)) / max(x.max() - x.min(), 1.0)
        fit = np.polyfit(t, y, 4)
        cost += float(np.sqrt(np.mean((np.polyval(fit, t) - y) ** 2)))
    return cost


def _samples(row: np.ndarray, start: int, direction: int) -> np.ndarray | None:
    """Columns of the :data:`REJOIN_FIT` rows read nearest ``start`` going ``direction``
    (None with fewer than four)."""
    cols = np.arange(start, row.size) if direction > 0 else np.arange(start, -1, -1)
    cols = cols[:3 * REJOIN_FIT]
    cols = cols[np.isfinite(row[cols])][:REJOIN_FIT]
    return cols if cols.size >= 4 else None


def _to_next_gap(chosen_row: np.ndarray, start: int, direction: int) -> slice:
    cols = np.arange(start, chosen_row.size) if direction > 0 else np.arange(start, -1, -1)
    lost = np.flatnonzero(chosen_row[cols] < 0)
    end = cols[lost[0]] if lost.size else (chosen_row.size if direction > 0 else -1)
    return slice(start, end) if direction > 0 else slice(end + 1, start + 1)


FLAT_SHARE = 0.1
"""Share of a trace's columns running flat (|slope| < 0.3) from which its stroke width is
taken there."""

STROKE_PERCENTILE = 30
"""Otherwise the stroke's width across is this percentile of the columns' extents taken
across the trace: a column under a sharp crest is taller than the stroke (both flanks'
ink), hardly any is thinner (a ringing may never run flat)."""


def _across(extent: np.ndarray, slope: np.ndarray) -> float:
    """The stroke's width across the trace from its columns' vertical ``extent`` and the
    trace's ``slope`` there: the median extent where it runs flat, or, on a trace that
    seldom does, a straight stroke of width w covering w·√(1 + s²) rows of a column, w =
    extent/√(1 + s²) at :data:`STROKE_PERCENTILE`."""
    s = np.abs(slope)
    seen = np.isfinite(extent) & np.isfinite(s)
    flat = seen & (s < 0.3)
    if flat.sum() >= max(FLAT_SHARE * seen.sum(), 1):
        return float(np.median(extent[flat]))
    w = extent[seen] / np.sqrt(1 + s[seen] ** 2)
    return float(np.percentile(w, STROKE_PERCENTILE)) if w.size else float("nan")


def _spread(runs: Runs, chosen: np.ndarray, row: np.ndarray) -> np.ndarray:
    """Each trace's σ across the stroke (:func:`_across` of its runs' σ). [px]"""
    ok = chosen >= 0
    sigma = np.where(ok, runs.sigma[np.maximum(chosen, 0)], np.nan)
    with np.errstate(invalid="ignore"):
        slope = _slope(row)
    return np.array([_across(sigma[j], slope[j]) for j in range(len(chosen))])


def _distance_to(mask: np.ndarray) -> np.ndarray:
    """Columns from each column to the nearest True of ``mask`` (inf if none)."""
    where = np.flatnonzero(mask)
    if where.size == 0:
        return np.full(mask.size, np.inf)
    cols = np.arange(mask.size)
    k = np.clip(np.searchsorted(where, cols), 1, where.size) - 1
    right = where[np.minimum(k + 1, where.size - 1)]
    return np.minimum(np.abs(cols - where[k]), np.abs(right - cols)).astype(float)


def confidence(runs: Runs, chosen: np.ndarray, row: np.ndarray,
               apex: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per-column confidence of each trace (see the module notes) and each trace's width.

    A column read at a sharp extreme (``apex``, :func:`_apexes`) has its tall run explained
    by the crest: its shape factor is 1.

    Returns
    -------
    confidence : numpy.ndarray
        traces × columns, 0 in gaps.
    width : numpy.ndarray
        Typical extent of each trace where it runs flat. [px]
    """
    ok = chosen >= 0
    idx = np.maximum(chosen, 0)
    extent = np.where(ok, runs.hi[idx] - runs.lo[idx], np.nan)
    with np.errstate(invalid="ignore"):
        slope = np.abs(_slope(row))
    width = np.array([_across(extent[j], slope[j]) for j in range(len(chosen))])
    expected = width[:, None] * np.sqrt(1 + np.nan_to_num(slope) ** 2) + np.nan_to_num(slope)
    ratio = (np.nan_to_num(extent) - 1) / expected
    shape = np.clip(2.5 - ratio, 0, 1)
    if apex is not None:
        shape = np.where(apex, 1.0, shape)
    snr = runs.peak[idx] / runs.noise
    contrast = np.clip((snr - THRESHOLD_SIGMA) / (FULL_CONTRAST - THRESHOLD_SIGMA), 0, 1)
    clear = np.ones(chosen.shape)
    counts = runs.counts
    crowded = np.flatnonzero(counts > 1)
    for j in range(len(chosen)):
        cols = crowded[ok[j, crowded]]
        mine = chosen[j, cols]
        gaps = np.full(cols.size, np.inf)
        for side in (-1, 1):
            other = mine + side
            inside = (other >= runs.starts[cols]) & (other < runs.starts[cols + 1])
            o = other[inside]
            gap = np.where(side < 0, runs.lo[mine[inside]] - runs.hi[o],
                           runs.lo[o] - runs.hi[mine[inside]])
            gaps[inside] = np.minimum(gaps[inside], gap)
        clear[j, cols] = np.clip(gaps / np.maximum(width[j], 1.0), 0, 1)
    return np.where(ok, contrast * shape * clear, 0.0), width


def _slope(row: np.ndarray) -> np.ndarray:
    """Rows per column by central differences, one-sided at a gap's edges, NaN in gaps."""
    left = np.full_like(row, np.nan)
    right = np.full_like(row, np.nan)
    left[:, 1:] = row[:, 1:] - row[:, :-1]
    right[:, :-1] = row[:, 1:] - row[:, :-1]
    both = np.where(np.isnan(left), right, np.where(np.isnan(right), left, (left + right) / 2))
    return np.where(np.isnan(row), np.nan, both)
