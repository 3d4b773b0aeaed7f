"""From tooth-edge times to teeth: which tooth each edge is, and where each revolution starts.

A toothed wheel of ``teeth`` equal pitches (``missing`` of them removed at a reference gap,
as on a 60−2 wheel) passes a sensor; :mod:`processing.speed.edges` gives the time of every tooth
that passed. Before speed can be computed, each edge needs its tooth: the interval to the
previous edge, divided by the local typical interval, is about 1 for a neighbour, 2 after a
tooth the sensor missed, ``missing + 1`` across the gap — and far below 1 after a spurious
(doubled) edge, which is removed. Revolutions then start at the gap, at a once-per-revolution
(TDC) channel, or, with neither, at the first edge.

Everything here works on edge lists (one number per tooth), so it costs nothing next to the
edge detection itself.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.ndimage import median_filter

from processing.diagnostics import InputError
from processing.result import Record

REFERENCES = ("gap", "tdc", "none")


@dataclass(frozen=True)
class ToothTrack(Record):
    """Edges with their teeth and revolutions (:func:`track_teeth`)."""

    times: np.ndarray
    """Edge times, doubled edges removed. [s]"""
    position: np.ndarray
    """Tooth position of each edge in pitches, counted from the first revolution's
    reference tooth (tooth 0 of revolution 0 is at 0; revolution r starts at r·teeth). [1]"""
    valid: np.ndarray
    """Whether the edge lies in a revolution whose teeth all counted right. [bool]"""
    teeth: int
    """Pitches per revolution (present and missing teeth). [1]"""
    missing: int
    """Teeth removed at the reference gap. [1]"""
    reference: str
    """What revolution 0 starts at: ``gap``, ``tdc`` or ``none`` (the first edge; also
    when a gap was asked for but not found)."""
    revolutions: int
    """Revolutions spanned by the record (complete or not). [1]"""
    bad_revolutions: np.ndarray
    """Revolution numbers whose tooth count was wrong (excluded). [1]"""
    missed: int
    """Teeth the sensor did not see (besides the gap). [1]"""
    doubled: int
    """Spurious edges removed (a spike, ringing). [1]"""
    gap_found: bool
    """Whether the reference gap was found where it was expected (always True without one)."""
    reference_offset: float
    """With a TDC channel: the mean angle from the TDC mark to tooth 0. [rad]"""

    @property
    def pitch(self) -> float:
        """Nominal angular pitch 2π/teeth. [rad]"""
        return 2 * np.pi / self.teeth

    @property
    def tooth(self) -> np.ndarray:
        """Tooth index of each edge within its revolution (0 = the reference tooth)."""
        return np.mod(self.position, self.teeth).astype(int)

    @property
    def revolution(self) -> np.ndarray:
        """Revolution number of each edge."""
        return np.floor_divide(self.position, self.teeth).astype(int)


def _typical_interval(intervals: np.ndarray) -> np.ndarray:
    """Running median of the tooth intervals (robust to the gap and to odd edges)."""
    size = min(15, intervals.size | 1)
    return median_filter(intervals, size=size, mode="nearest")


def _remove_doubled(times: np.ndarray) -> tuple[np.ndarray, int]:
    """Remove spurious edges: an interval far shorter than its neighbours is merged with the
    neighbour that makes the merged interval closest to the typical one."""
    removed = 0
    for _ in range(3):
        intervals = np.diff(times)
        typical = _typical_interval(intervals)
        short = np.flatnonzero(intervals < 0.6 * typical)
        if short.size == 0:
            break
        drop: set[int] = set()
        for k in short:
            if k in drop or k + 1 in drop:
                continue
            left = intervals[k] + intervals[k - 1] if k > 0 else np.inf
            right = intervals[k] + intervals[k + 1] if k + 1 < intervals.size else np.inf
            # merging with the left neighbour removes edge k, with the right one edge k+1
            drop.add(k if abs(left - typical[k]) <= abs(right - typical[k]) else k + 1)
        keep = np.ones(times.size, bool)
        keep[[d for d in drop if 0 < d < times.size]] = False
        removed += int((~keep).sum())
        times = times[keep]
    return times, removed


def track_teeth(edge_times, teeth: int, missing: int = 0, *, reference: str | None = None,
                reference_times=None) -> ToothTrack:
    """Number the teeth of an edge list and find the revolutions.

    Parameters
    ----------
    edge_times : array_like
        Increasing edge times (:func:`processing.speed.edges.detect_edges` / sample rate). [s]
    teeth : int
        z, pitches per revolution including the missing ones (60 for a 60−2 wheel).
    missing : int
        Teeth removed at the reference gap (0 for a plain wheel).
    reference : {"gap", "tdc", "none"}, optional
        What starts a revolution. Default: ``tdc`` when ``reference_times`` are given, else
        ``gap`` when ``missing`` > 0, else ``none``.
    reference_times : array_like, optional
        Times of a once-per-revolution mark (TDC channel edges). [s]

    Returns
    -------
    ToothTrack

    Notes
    -----
    The tooth increment across interval k is round(Δt_k / Δt̃_k) with Δt̃ the running median
    of 15 intervals; it is 1 normally, ``missing + 1`` across the gap, larger after a missed
    tooth. A revolution (gap to gap, or mark to mark) whose increments do not add up to
    ``teeth`` is marked bad and its edges invalid; the next reference restarts the count, so
    one miscount does not spoil the rest of the record. With ``missing = 1`` a gap and a
    missed tooth look alike; the gap is the one that recurs every revolution.
    """
    t = np.asarray(edge_times, dtype=float)
    if t.ndim != 1 or t.size < 3:
        raise InputError(f"{t.size} tooth edges found, at least a few revolutions' worth "
                         "are needed", "check the channel, its gain and the sample rate")
    if teeth < 3 or not 0 <= missing < teeth // 2:
        raise InputError(f"a wheel of {teeth} teeth with {missing} missing is not usable",
                         "give z ≥ 3 and fewer missing teeth than half of z")
    reference = reference or ("tdc" if reference_times is not None
                              else "gap" if missing else "none")
    if reference not in REFERENCES:
        raise InputError(f"unknown angle reference {reference!r}",
                         f"use one of {', '.join(REFERENCES)}")
    if reference == "tdc" and reference_times is None:
        raise InputError("the TDC reference needs the TDC channel's times",
                         "give the TDC channel, or use the gap or no reference")
    t, doubled = _remove_doubled(t)
    intervals = np.diff(t)
    steps = np.maximum(np.rint(intervals / _typical_interval(intervals)), 1).astype(int)
    count = np.concatenate([[0], np.cumsum(steps)])
    gaps = _gap_starts(steps, teeth, missing) if missing else np.empty(0, int)
    missed = int(np.sum(steps - 1)) - missing * gaps.size
    offset = 0.0
    gap_found = reference != "gap" or gaps.size >= max(1, count[-1] // teeth // 2)
    if not gap_found:
        reference = "none"
    if reference == "none":
        position = count
        closed = int(count[-1] // teeth)
        bad = np.empty(0, int)
        spoiled = np.zeros(count.size, bool)
    else:
        if reference == "gap":
            starts = gaps
        else:
            starts, offset = _mark_starts(t, np.asarray(reference_times, dtype=float), teeth)
        if starts.size == 0:
            starts = np.array([0])
        position, bad, spoiled, closed = _positions(count, starts, teeth)
    revolution = np.floor_divide(position, teeth)
    valid = (revolution >= 0) & (revolution < closed) & ~spoiled
    return ToothTrack(times=t, position=position, valid=valid, teeth=teeth, missing=missing,
                      reference=reference, revolutions=max(closed, 0), bad_revolutions=bad,
                      missed=max(missed, 0), doubled=doubled, gap_found=bool(gap_found),
                      reference_offset=offset)


def recurring_gap(edge_times) -> tuple[int, int] | None:
    """The wheel a record shows: (z, missing) when one gap recurs at a fixed tooth count.

    Parameters
    ----------
    edge_times : array_like
        Increasing edge times. [s]

    Returns
    -------
    tuple of int or None
        ``(z, missing)`` — pitches per revolution and teeth missing at the gap — when at least
        three gaps of one size stand the same number of edges apart, nine times in ten (a
        missed tooth here and there does not hide the wheel); None when the record shows no
        such gap (a plain wheel, or too few revolutions).

    Examples
    --------
    >>> pitch = np.arange(5 * 60)
    >>> times = pitch[pitch % 60 < 58] * 1e-3       # a 60−2 wheel turning at a steady speed
    >>> recurring_gap(times)
    (60, 2)
    """
    t = np.asarray(edge_times, dtype=float)
    if t.size < 16:
        return None
    intervals = np.diff(t)
    steps = np.maximum(np.rint(intervals / _typical_interval(intervals)), 1).astype(int)
    big = np.flatnonzero(steps > 1)
    if big.size < 3:
        return None
    size = int(np.bincount(steps[big]).argmax())
    gaps = big[steps[big] == size]
    spacings = np.diff(gaps)
    if spacings.size < 2:
        return None
    spacing = int(np.bincount(spacings).argmax())
    if np.mean(spacings == spacing) < 0.9 or gaps.size < 0.9 * big.size:
        return None
    return spacing + size - 1, size - 1


def _gap_starts(steps: np.ndarray, teeth: int, missing: int) -> np.ndarray:
    """Indices of the edges just after the gap (tooth 0 of each revolution)."""
    candidates = np.flatnonzero(steps == missing + 1) + 1
    if missing == 1 and candidates.size:
        count = np.concatenate([[0], np.cumsum(steps)])
        phase = np.mod(count[candidates], teeth)
        candidates = candidates[phase == np.bincount(phase).argmax()]
    return candidates


def _mark_starts(t: np.ndarray, marks: np.ndarray, teeth: int) -> tuple[np.ndarray, float]:
    """Indices of the first edge after each reference mark, and the mean mark-to-edge angle."""
    marks = marks[(marks >= t[0]) & (marks < t[-1])]
    first = np.searchsorted(t, marks)
    starts, keep = np.unique(first, return_index=True)
    if starts.size < 2:
        return np.empty(0, int), 0.0
    period = np.median(np.diff(t[starts]))
    delay = t[starts] - marks[keep]
    return starts, float(np.mean(delay) / period * 2 * np.pi)


def _positions(count: np.ndarray, starts: np.ndarray, teeth: int):
    """Pitch position of every edge, counted afresh from each reference.

    Each reference is numbered by the revolutions counted since the first (a reference not
    seen — a missed tooth beside the gap hides it — leaves a span of two revolutions, and
    the numbers after it stay true). Returns the positions, the numbers of the revolutions
    in spans between references that did not count ``teeth`` pitches (bad), which edges lie
    in such a span (told by their reference: a long span spills past its own number), and
    the number of the last reference."""
    number = np.rint((count[starts] - count[starts[0]]) / teeth).astype(int)
    spans = np.flatnonzero(np.diff(count[starts]) != teeth)
    anchor = np.searchsorted(starts, np.arange(count.size), side="right") - 1
    before = anchor < 0
    anchor = np.maximum(anchor, 0)
    position = number[anchor] * teeth + count - count[starts[anchor]]
    position[before] = count[before] - count[starts[0]]
    spoiled = np.isin(anchor, spans) & ~before
    bad = [np.arange(number[k], max(number[k + 1], number[k] + 1)) for k in spans]
    return (position.astype(int), np.concatenate(bad) if bad else np.empty(0, int), spoiled,
            int(number[-1]))


@dataclass(frozen=True)
class PitchCalibration(Record):
    """Tooth angles measured on a smoothly coasting wheel (:func:`calibrate_pitch`)."""

    angles: np.ndarray
    """Angle of each tooth position 0..teeth-1 from tooth 0 (NaN where a tooth is missing). [rad]"""
    deviation: np.ndarray
    """angles − k·2π/teeth, the pitch error accumulated up to each tooth. [rad]"""
    u: np.ndarray
    """Standard uncertainty of each angle (scatter over revolutions / √n). [rad]"""
    revolutions: int
    """Revolutions averaged. [1]"""


def calibrate_pitch(track: ToothTrack) -> PitchCalibration:
    """Measure the wheel's tooth angles on a record where it turns smoothly (a coast-down).

    Parameters
    ----------
    track : ToothTrack
        A record of the wheel turning without cyclic speed fluctuation (engine off, coasting
        or motored without compression), with a reference (gap or TDC) so teeth are known.

    Returns
    -------
    PitchCalibration

    Notes
    -----
    The reference edges of successive revolutions are 2π apart: a cubic spline through
    (t_r, 2πr) is the wheel's angle θ(t) for a smooth motion. Each edge's angle within its
    revolution is θ(t_k) − 2πr; its mean over the revolutions is the tooth's true angle.
    Any speed fluctuation within a revolution that the spline does not follow is taken for a
    pitch error, so the record must come from a smooth run.
    """
    tooth0 = track.valid & (track.tooth == 0)
    revs = track.revolution[tooth0]
    if revs.size < 4:
        raise InputError(f"the calibration record spans {revs.size} complete revolutions",
                         "record at least 4 (better 20 or more) revolutions of the coasting wheel")
    theta = CubicSpline(track.times[tooth0], 2 * np.pi * revs)
    inside = track.valid & (track.times >= track.times[tooth0][0]) & \
        (track.times <= track.times[tooth0][-1])
    within = theta(track.times[inside]) - 2 * np.pi * track.revolution[inside]
    teeth = track.tooth[inside]
    n = np.bincount(teeth, minlength=track.teeth).astype(float)
    s = np.bincount(teeth, within, minlength=track.teeth)
    s2 = np.bincount(teeth, within ** 2, minlength=track.teeth)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(n > 0, s / n, np.nan)
        var = np.where(n > 1, (s2 - n * mean ** 2) / (n - 1), np.nan)
        u = np.sqrt(np.maximum(var, 0) / n)
    nominal = np.arange(track.teeth) * track.pitch
    return PitchCalibration(angles=mean, deviation=mean - nominal, u=u,
                            revolutions=int(revs.size - 1))
