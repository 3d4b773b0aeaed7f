"""Straight lines across a paper record: the time-mark and TDC lines, the beams' zero lines, a
printed grid. Found, measured and lifted off the density so that the traces stand alone.

A straight line running along the sheet holds the same row in most columns of a stretch, so
the median of each row over a block of columns keeps it, while a trace (which crosses a row
in a few columns) and the short vertical strokes of pips drop out. :func:`remove_lines`
takes these block medians, finds the rows where they peak in most blocks, fits each line's
row across the blocks (a straight line, or it is not one), and subtracts the block medians,
interpolated between blocks, from the rows around each line. Densities add where inks
overlap, so a trace crossing a line is left whole. The same function on the transposed
density finds the vertical lines of a grid.

:func:`grid_spacing` finds the regularly spaced subset of the lines (a printed grid) and its
pitch with the type A uncertainty of a line fitted through the lines' positions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.signal import find_peaks

from ..regression import fit_line
from ..result import Record

MIN_BLOCK_SHARE = 0.6
"""A line must be seen in at least this share of the blocks (it runs along most of the sheet)."""

MAX_WAVINESS = 0.75
"""Largest RMS departure of a line's block positions from a straight line. [px]"""

PULLED_SHARE = 0.25
"""Largest share of a line's blocks that a trace dwelling beside it may pull off its row
(their centroids drawn towards the trace) and that are left out of its fit."""

MAX_WANDER = 0.75
"""How far a line's column centroids may stray to both sides of it. [px]"""

MAX_ABSENCE = 0.1
"""Longest stretch, as a share of the sheet's length, along which a line may hold no ink: a
line is broken only where a pip lifts it. A trace at rest for a while (a valve's force while
the valve is shut, a decay settled) runs straight too, but leaves its row for whole events."""

DIPPING = 0.5
"""Largest share of the columns where a line's row holds no ink (when at least 5 % of the
columns are such) that may lie in stretches along which the ink beside the row moves — its
nearest row changing by 2 px or more. A pip lifts a line to a flat top; a trace that dwells
at one level and dips off it (a speed trace of small δ) leaves for rows it sweeps through."""

REST_MIN = 0.03
"""Shortest stretch, as a share of the sheet's length, along which a trace is taken to rest on
a line (:func:`restore_rests`); a trace lost where it crosses a line leaves a few columns."""

BLOCK_COLUMNS = 160
"""Typical block length along the line; 6 to 32 blocks per sheet. [px]"""


@dataclass(frozen=True)
class Line(Record):
    """A straight line across the sheet (as a lens draws it: bent by a sag of a few pixels).

    Attributes
    ----------
    position : float
        Its row at the sheet's middle column (for a vertical line: its column at the middle
        row). [px]
    slope : float
        Rows per column along it.
    strength : float
        Its density at its centre (median over the blocks).
    width : float
        Its full width at half its strength (σ of a Gaussian stroke × 2.355). [px]
    share : float
        Share of the blocks it is seen in.
    middle : float
        The column ``position`` refers to. [px]
    bend : float
        Rows per column² the line bends by about ``middle`` (a lens's radial distortion bends
        the straight lines away from the picture's centre; 0 on a flat scan). [1/px]
    """

    position: float
    slope: float
    strength: float
    width: float
    share: float
    middle: float
    bend: float = 0.0

    def at(self, x):
        """The line's row at columns ``x``. [px]"""
        d = np.asarray(x, dtype=float) - self.middle
        return self.position + self.slope * d + self.bend * d * d


@dataclass(frozen=True)
class _Course:
    """A candidate line's row along the sheet: straight, or bent by a lens."""

    middle: float
    coefficients: tuple[float, float, float]
    """Bend, slope and row at ``middle``."""
    residual_sd: float

    def predict(self, x):
        return np.polyval(self.coefficients, np.asarray(x, dtype=float) - self.middle)


MAX_SAG = 0.004
"""Largest sag of a line bent by the camera's lens, over its length (a phone's residual
barrel distortion bends a line near the picture's edge by a few pixels in a thousand)."""


def _course(x: np.ndarray, rows: np.ndarray, middle: float, length: float) -> _Course:
    """The straight line through the block centres, or the parabola if the straight one
    leaves them by more than :data:`MAX_WAVINESS` and the parabola sags by no more than
    :data:`MAX_SAG` of the length (the parabola is then the line's course)."""
    fit = fit_line(x, rows)
    straight = _Course(middle, (0.0, fit.slope, float(fit.predict(middle))), fit.residual_sd)
    if fit.residual_sd <= MAX_WAVINESS or x.size < 5:
        return straight
    c = np.polyfit(x - middle, rows, 2)
    sd = float(np.sqrt(np.sum((np.polyval(c, x - middle) - rows) ** 2) / (x.size - 3)))
    if abs(c[0]) * (length / 2) ** 2 > MAX_SAG * length:
        return straight
    return _Course(middle, (float(c[0]), float(c[1]), float(c[2])), sd)


def _block_medians(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Median of each row over each block of columns (about 64 columns sampled per block):
    rows × blocks, and the blocks' middle columns."""
    h, w = a.shape
    blocks = int(np.clip(w // BLOCK_COLUMNS, 6, 32))
    edges = np.linspace(0, w, blocks + 1).round().astype(int)
    step = max(1, (w // blocks) // 64)
    med = np.stack([np.median(a[:, lo:hi:step], axis=1)
                    for lo, hi in zip(edges[:-1], edges[1:])], axis=1)
    return med, (edges[:-1] + edges[1:] - 1) / 2


def _line_course(middles: np.ndarray, centres: np.ndarray, present: np.ndarray,
                 length: float) -> _Course | None:
    """The course (:func:`_course`) of a line through the blocks' centroids where it is seen,
    or None if they scatter about it by more than :data:`MAX_WAVINESS`. Where a trace runs
    beside a line (a decay settling on its zero line, a torsiogram crossing it at a shallow
    angle) the merged strokes pull a block's centroid off: the block farthest off is left
    out, one at a time, up to :data:`PULLED_SHARE` of the blocks; a trace keeping near one
    level scatters along its whole length and stays wavy."""
    keep = present.copy()
    spare = int(PULLED_SHARE * present.sum())
    while True:
        fit = _course(middles[keep], centres[keep], length / 2, length)
        if fit.residual_sd <= MAX_WAVINESS:
            return fit
        if spare == 0:
            return None
        off = np.where(keep, np.abs(centres - fit.predict(middles)), -1.0)
        keep[int(np.argmax(off))] = False
        spare -= 1


def remove_lines(density: np.ndarray, noise: float) -> list[Line]:
    """Find the straight lines running along the rows and subtract them from ``density``.

    Parameters
    ----------
    density : numpy.ndarray
        Optical density, float32, rows × columns; changed in place (pass its transpose for
        lines running down the columns).
    noise : float
        σ of the density on bare paper.

    Returns
    -------
    list of Line
        Top to bottom.
    """
    h, w = density.shape
    med, middles = _block_medians(density)
    blocks = med.shape[1]
    sigma = noise * 1.25 / np.sqrt(64)                   # σ of a median of 64 samples
    profile = med.mean(axis=1)
    peaks, _ = find_peaks(profile, height=6 * sigma, distance=3)
    reach = 6
    lines: list[Line] = []
    for row in peaks[np.argsort(profile[peaks])[::-1]]:
        lo, hi = max(row - reach, 0), min(row + reach + 1, h)
        window = med[lo:hi]
        tops = window.max(axis=0)
        present = (tops > 4 * sigma) & (tops > 0.5 * np.median(tops))
        if present.sum() < max(3, MIN_BLOCK_SHARE * blocks):
            continue
        rows = np.arange(lo, hi, dtype=float)[:, None]
        weight = np.where(window > 0.5 * tops, window, 0.0)
        centres = (weight * rows).sum(axis=0) / np.maximum(weight.sum(axis=0), 1e-12)
        fit = _line_course(middles, centres, present, w)
        if fit is None:
            continue
        position = float(fit.predict(w / 2))
        wide = med[max(row - 3 * reach, 0):min(row + 3 * reach + 1, h)]
        width = _fwhm(wide[:, present].mean(axis=1), row - max(row - 3 * reach, 0))
        if _wavy(density, fit, max(2, int(round(width))), noise):
            continue                    # a trace that keeps near one level, not a line
        absent, dipping = _absences(density, fit, width, float(np.median(tops[present])),
                                    noise)
        if absent > MAX_ABSENCE * w:
            continue                    # a trace at rest between events, not a line
        if dipping > DIPPING:
            continue                    # a trace dwelling at one level and dipping off it
        if any(abs(position - other.position) < max(3.0, width + other.width)
               for other in lines):
            continue                    # a shoulder of a stronger line (its pips, blurred)
        lines.append(Line(position, fit.coefficients[1], float(np.median(tops[present])),
                          width, float(present.mean()), w / 2, fit.coefficients[0]))
    lines = _without_shoulders(sorted(lines, key=lambda line: line.position))
    lines = _without_combs(density, lines, noise)
    _subtract(density, med, middles, lines)
    return lines


def restore_rests(density: np.ndarray, drawn: np.ndarray, lines: list[Line],
                  threshold: float) -> list[tuple[Line, int, int]]:
    """Give a line back its density where a trace rests on it.

    A beam at rest draws along its zero line (a valve's force while the valve is shut, a
    decay settled): lifted off with the line, the trace would be lost there, and its events
    would stand apart as if no trace joined them. What tells a trace at rest from the line
    is where the trace goes on: an event is a stroke that leaves the line's row and comes
    back to it, so the trace rests on the line between the end of one such stroke and the
    start of the next (or the sheet's end), wherever both ends of that stretch lie on the
    line's row. A trace crossing the line leaves no such stretch (it runs on as one stroke,
    or is lost for a few columns: stretches shorter than :data:`REST_MIN` of the sheet are
    left alone), a mark line's pips are no events (strokes shorter than that along the
    sheet), and a line no stroke leaves from stays lifted off whole.

    Parameters
    ----------
    density : numpy.ndarray
        Density with the lines lifted off, rows × columns; changed in place.
    drawn : numpy.ndarray
        The density before the lines were lifted off.
    lines : list of Line
        The lines a trace may rest on (the zero lines).
    threshold : float
        Density above which a pixel is ink.

    Returns
    -------
    list of (Line, int, int)
        Each stretch given back: the line, its first column and one past its last.
    """
    h, w = density.shape
    labels, _ = ndimage.label(density > threshold, structure=np.ones((3, 3), bool))
    boxes = ndimage.find_objects(labels)
    cols = np.arange(w)
    out = []
    for line in lines:
        reach = line.width / 2 + max(3.0, line.width)
        offsets = np.arange(-int(np.ceil(reach)), int(np.ceil(reach)) + 1)
        rows = np.round(line.at(cols))[None, :].astype(int) + offsets[:, None]
        inside = (rows >= 0) & (rows < h)
        band = np.where(inside, labels[np.clip(rows, 0, h - 1), cols[None, :]], 0)
        occupied = np.zeros(w, bool)
        starts, ends = set(), set()
        for k in np.unique(band[band > 0]):
            rs, cs = boxes[k - 1]
            if not _leaves(line, rs, cs, reach):
                continue                # a remnant of the line itself, or of the rest on it
            occupied[cs] = True
            if cs.stop - cs.start < REST_MIN * w:
                continue                # a mark's pip, or a stroke's fragment: no event
            on = (band == k).any(axis=0)
            if on[cs.start:cs.start + 3].any():
                starts.add(cs.start)
            if on[cs.stop - 3:cs.stop].any():
                ends.add(cs.stop)
        edges = np.flatnonzero(np.diff(np.concatenate([[1], occupied.astype(np.int8), [1]])))
        for a, b in zip(edges[::2], edges[1::2]):
            bounded = (a == 0 or a in ends) and (b == w or b in starts)
            if bounded and (a in ends or b in starts) and b - a >= REST_MIN * w:
                _give_back(density, drawn, line, a, b)
                out.append((line, int(a), int(b)))
    return out


def _leaves(line: Line, rows: slice, cols: slice, reach: float) -> bool:
    """Whether a stroke's bounding box reaches beyond ``reach`` of the line's row."""
    at = line.at(np.array([cols.start, cols.stop - 1], dtype=float))
    return bool(rows.start < at.min() - reach or rows.stop - 1 > at.max() + reach)


def _give_back(density: np.ndarray, drawn: np.ndarray, line: Line, a: int, b: int) -> None:
    """Copy the drawn density back over the rows :func:`_subtract` lifted along ``line``
    between columns ``a`` and ``b``."""
    h = density.shape[0]
    span = line.width / 2 + 3
    cols = np.arange(a, b)
    centre = line.at(cols)
    offsets = np.arange(-int(np.ceil(span)), int(np.ceil(span)) + 1)
    rows = np.clip(np.round(centre)[None, :].astype(int) + offsets[:, None], 0, h - 1)
    density[rows, cols[None, :]] = drawn[rows, cols[None, :]]


JOINED = 0.5
"""Share of the columns in which the row midway between two close parallel lines holds ink,
above which the two are a mark line and the tops of its pips, joined by the pips' sides."""


def _inked(density: np.ndarray, rows: np.ndarray, level: float) -> np.ndarray:
    """Whether each column holds ink (above ``level``) in any of ``rows`` (rows × columns)."""
    h, w = density.shape
    rows = np.clip(np.round(rows).astype(int), 0, h - 1)
    return (density[rows, np.arange(w)[None, :]] > level).any(axis=0)


def _without_combs(density: np.ndarray, lines: list[Line], noise: float) -> list[Line]:
    """Drop the 'lines' that are the tops of a mark line's pips: time marks so dense (a few
    pixels apart, or blurred into bars) that their top strokes fill most of a row, as a line
    does. Two unrelated lines are joined only here and there (by a trace crossing, a grid
    line), and a line three times darker or fainter than another was not drawn by its
    marker (a printed grid's line beside a mark line); a mark line and its pips' tops are
    joined by the pips' sides, so that the row midway between them holds ink in more than :data:`JOINED` of the columns. Of the two,
    the mark line holds ink in more columns (it runs between the pips, a top only over its
    pip) and is kept. Taken for a line, the tops would hide the pips from their line."""
    h, w = density.shape
    cols = np.arange(w)
    ink = [_inked(density, line.at(cols)[None, :] + np.arange(-1, 2)[:, None],
                  max(line.strength / 3, 4 * noise)) for line in lines]
    tops = set()
    for i, a in enumerate(lines):
        for j in range(i + 1, len(lines)):
            b = lines[j]
            if abs(a.position - b.position) >= 0.1 * h \
                    or not 1 / 3 < a.strength / b.strength < 3:
                continue                # apart, or not drawn by one marker
            level = max(min(a.strength, b.strength) / 3, 4 * noise)
            middle = 0.5 * (a.at(cols) + b.at(cols))
            if np.mean(_inked(density, middle[None, :] + np.arange(-1, 2)[:, None],
                              level)) > JOINED:
                tops.add(j if (ink[i].mean(), a.strength) >= (ink[j].mean(), b.strength)
                         else i)
    return [line for k, line in enumerate(lines) if k not in tops]


def _without_shoulders(lines: list[Line]) -> list[Line]:
    """Drop the faint 'lines' beside a dark one: a third as dark or less, within 6 of its
    widths + 10 px, and not one of a printed grid. Blurred pips, 30 % of a mark line's
    length, leave such a row in the block medians along their tops; taking it for a line
    would lift the pips' tops off."""
    printed = grid_spacing(lines)
    grid = set() if printed is None else {id(line) for line in printed.lines}
    return [line for line in lines if id(line) in grid or not any(
        other.strength > 3 * line.strength
        and abs(other.position - line.position) < 6 * other.width + 10 for other in lines)]


def _wavy(density: np.ndarray, fit, reach: int, noise: float) -> bool:
    """Whether the stroke along a candidate line wanders to both sides of it: a fifth of its
    column centroids (256 columns, ± ``reach`` rows: its width) lie more than
    :data:`MAX_WANDER` px above the fitted line and a fifth as far below. A line holds its
    row in every column (pips beside it pull the centroids to one side only); a trace that
    oscillates about one level keeps to it only in the block medians. The window spans the
    candidate's width as the block medians show it, which for a small ripple blurred into
    its own stroke (or a trace dwelling at one level and dipping off it) is the width of the
    rows it dwells on: narrower windows saw too little of its swing to tell it from a line."""
    h, w = density.shape
    cols = np.linspace(0, w - 1, 256).round().astype(int)
    centre = fit.predict(cols)
    offsets = np.arange(-reach, reach + 1)
    rows = np.clip(np.round(centre)[None, :].astype(int) + offsets[:, None], 0, h - 1)
    v = np.clip(density[rows, cols[None, :]], 0, None)
    mass = v.sum(axis=0)
    seen = mass > 6 * noise * np.sqrt(offsets.size)
    if seen.sum() < 16:
        return False
    y = (v * rows).sum(axis=0)[seen] / mass[seen] - centre[seen]
    low, high = np.percentile(y, [20, 80])
    return bool(low < -MAX_WANDER and high > MAX_WANDER)


def _absences(density: np.ndarray, fit, width: float, strength: float,
              noise: float) -> tuple[int, float]:
    """Where the ink left the candidate line's row (± half its width + 1 px: less than a
    third of its strength there): the longest stretch of such columns [px], and the share of
    them in stretches along which the nearest ink beside the row (within two widths + 1 px
    more) moves by 2 px or more — 0 when they are fewer than 5 % of the columns."""
    h, w = density.shape
    cols = np.arange(w)
    reach = int(np.ceil(width / 2)) + 1
    offsets = np.arange(-reach - int(np.ceil(2 * width)) - 1, reach + int(np.ceil(2 * width)) + 2)
    rows = np.clip(np.round(fit.predict(cols))[None, :].astype(int) + offsets[:, None], 0, h - 1)
    ink = density[rows, cols[None, :]] > max(strength / 3, 4 * noise)
    inked = ink[np.abs(offsets) <= reach].any(axis=0)
    edges = np.flatnonzero(np.diff(np.concatenate([[1], inked.astype(np.int8), [1]])))
    starts, stops = edges[::2], edges[1::2]
    longest = int((stops - starts).max()) if edges.size else 0
    if (~inked).mean() < 0.05 or _mark_train(starts, stops - starts, w):
        return longest, 0.0
    nearest = np.where(ink, np.abs(offsets)[:, None], np.inf).min(axis=0)
    dipping = 0
    for a, b in zip(starts, stops):
        seen = nearest[a:b][np.isfinite(nearest[a:b])]
        if seen.size >= 3 and np.ptp(seen) >= 2:
            dipping += b - a
    return longest, dipping / int((~inked).sum())


MARK_DUTY = 0.5
"""Largest share of a mark line's length its marks lift it off its row: a marker's tick or
pip lasts a fraction of the mark period (the manual's records: 15–35 %)."""

TRAIN_SHARE = 0.8
"""Share of a line's empty stretches that must lie on one even grid, of about one length,
for them to be a train of marks."""


def _mark_train(starts: np.ndarray, lengths: np.ndarray, w: int) -> bool:
    """Whether the stretches where a candidate line's row is empty are a train of marks: at
    least three, of one length (within 1 px or 10 % of their median: a marker's marks last
    alike; a trace's dips vary with the signal), their starts on an even
    grid (within a fifth of its spacing of their places) and together less than
    :data:`MARK_DUTY` of the line, for :data:`TRAIN_SHARE` of them. A marker lifts its line
    periodically, at a nearly constant spacing along the time base, whatever its marks'
    shape (a slow marker's sloping sides sweep the rows beside the line as a trace does);
    a trace that dwells at one level leaves it as its signal goes, for most of its length or
    unevenly."""
    inner = (starts > 0) & (starts + lengths < w) & (lengths > 1)
    starts, lengths = starts[inner], lengths[inner]
    if starts.size < 3 or lengths.sum() > MARK_DUTY * w:
        return False
    spacing = float(np.median(np.diff(starts)))
    if spacing <= 2 * np.median(lengths):
        return False
    # numbered by the gaps between neighbours, so that a spacing known to a pixel does not
    # misnumber the far end of a long train; then afresh as the spacing is refined
    k = np.concatenate([[0.0], np.cumsum(np.maximum(np.round(np.diff(starts) / spacing), 1))])
    origin, on_grid = float(starts[0]), np.ones(starts.size, bool)
    for _ in range(3):
        on_grid = np.abs(starts - origin - spacing * k) < 0.2 * spacing
        if on_grid.sum() < 3:
            return False
        spacing, origin = np.polyfit(k[on_grid], starts[on_grid], 1)
        k = np.round((starts - origin) / spacing)
    typical = float(np.median(lengths))
    alike = np.abs(lengths - typical) <= max(1.0, 0.1 * typical)
    return bool(np.mean(on_grid & alike) >= TRAIN_SHARE)


def _fwhm(profile: np.ndarray, near: int) -> float:
    """Full width at half maximum of the peak of ``profile`` nearest index ``near``: twice
    the narrower half width (the pips beside a line may lift one flank), the half-level
    crossings interpolated linearly. [px]"""
    lo, hi = max(near - 3, 0), min(near + 4, profile.size)
    k = lo + int(np.argmax(profile[lo:hi]))
    half = 0.5 * profile[k]
    below = np.flatnonzero(profile[:k] < half)
    above = np.flatnonzero(profile[k:] < half) + k
    sides = []
    if below.size:
        a = below[-1]
        sides.append(k - (a + (half - profile[a]) / (profile[a + 1] - profile[a])))
    if above.size:
        b = above[0]
        sides.append(b - 1 + (profile[b - 1] - half) / (profile[b - 1] - profile[b]) - k)
    return 2.0 * float(min(sides)) if sides else float((profile > half).sum())


def _subtract(density: np.ndarray, med: np.ndarray, middles: np.ndarray,
              lines: list[Line]) -> None:
    """Subtract the block medians, interpolated linearly between blocks, from the rows each
    line covers (its width and 3 px either side, along its slope)."""
    h, w = density.shape
    if not lines:
        return
    rows = set()
    for line in lines:
        ends = line.at(np.linspace(0.0, w - 1.0, 9))
        span = line.width / 2 + 3
        rows.update(range(max(int(np.floor(ends.min() - span)), 0),
                          min(int(np.ceil(ends.max() + span)) + 1, h)))
    rows = np.array(sorted(rows))
    x = np.arange(w, dtype=float)
    weights = np.stack([np.interp(x, middles, np.eye(len(middles))[b])
                        for b in range(len(middles))])
    density[rows] -= (med[rows] @ weights).astype(density.dtype)


@dataclass(frozen=True)
class Grid(Record):
    """The regularly spaced lines of a printed grid.

    Attributes
    ----------
    pitch : float
        Pixels between neighbouring grid lines. [px]
    u_pitch : float
        Its standard uncertainty (type A, from the line through the positions). [px]
    dof : int
        Degrees of freedom of ``u_pitch``.
    lines : tuple of Line
        The grid's lines.
    """

    pitch: float
    u_pitch: float
    dof: int
    lines: tuple[Line, ...]


def grid_spacing(lines: list[Line], *, min_lines: int = 4) -> Grid | None:
    """The printed grid among ``lines``: the largest set at a common pitch.

    Lines are numbered by their distance from the first in units of the median spacing of
    neighbours; those within 0.15 of a whole number belong to the grid, and a straight line
    through (number, position) gives the pitch.

    Parameters
    ----------
    lines : list of Line
        Lines of one direction, sorted by position.
    min_lines : int
        Fewest lines that make a grid.

    Returns
    -------
    Grid or None
    """
    if len(lines) < min_lines:
        return None
    pos = np.array([line.position for line in lines])
    gaps = np.diff(pos)
    best = None
    for start in range(len(lines) - min_lines + 1):
        d = np.median(gaps[start:])
        k = (pos - pos[start]) / d
        member = (np.abs(k - np.round(k)) < 0.15) & (k > -0.5)
        if member.sum() >= min_lines and (best is None or member.sum() > best[0].sum()):
            best = (member, np.round(k))
    if best is None:
        return None
    member, k = best
    _, first = np.unique(k[member], return_index=True)
    idx = np.flatnonzero(member)[first]
    if idx.size < min_lines:
        return None
    fit = fit_line(k[idx], pos[idx])
    return Grid(float(fit.slope), float(fit.u_slope), int(fit.dof),
                tuple(lines[i] for i in idx))
