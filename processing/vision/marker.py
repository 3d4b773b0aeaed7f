"""The marker on a swinging part: the patch of a film that moves periodically, not whatever
moves.

:func:`survey` looks at the film's first :data:`SURVEY_SECONDS` (at least
:data:`SURVEY_FRAMES` frames, every so many at a high frame rate). Each frame's light is
evened out first — divided by its own smooth lighting over the frames' median one
(:func:`even_light`: a lamp's flicker beating with the frame rate, the phone's exposure
changing) — and the still background is their median. The frame with the least difference
from the background (no hand in front of the camera) is the reference; the compact patches
that differ most from the background in it are the candidates (:func:`candidates`). Each is
followed through the survey's frames by normalised cross-correlation, with its template
turned by up to ±:data:`TURNS` (a sticker on a pendulum or a platform turns with it), and
of those whose way a single sinusoid describes as well as the best one's (R² within
:data:`AS_PERIODIC`), the one that promises the most precise track — the widest swing of
the largest patch — is the marker (:func:`periodicity`): a hand passing, a shadow, a flicker's band or a noisy corner
is not periodic.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

SURVEY_SECONDS = 4.0
"""Film surveyed for the marker: long enough for a swing of up to 4 s to show its period.
[s]"""

SURVEY_FRAMES = 64
"""Frames kept for the survey (every so many at a high frame rate): the still background is
their median, and memory stays bounded (64 frames of 1080p: 130 MB)."""

SURVEY_SIDE = 960
"""Longest side of the frames the candidates are followed on. [px]"""

CANDIDATES = 5
"""Compact moving patches followed in the survey."""

TURNS = (-24.0, -16.0, -8.0, 0.0, 8.0, 16.0, 24.0)
"""Angles the marker's template is turned by (its rotation with the part). [deg]"""

SURVEY_TURNS = (-16.0, 0.0, 16.0)
"""The same in the survey, where a coarser step serves."""

MIN_PERIODIC = 0.5
"""Share of a candidate's way (less a line) a single sinusoid must describe."""

SURVEY_CONFIDENCE = 0.6
"""Correlation above which a candidate counts as found in a survey frame."""

AS_PERIODIC = 0.01
"""R² below the most periodic candidate's by which a candidate still counts as periodic (a
thread's eye and a sticker on the same platform: 0.9970 and 0.9961, at 240 frames per
second 0.9964 and 0.9910, the sticker's cross turning with the platform; a lobe of a
marker's difference image beside the marker: 0.9934 and 0.9977, told apart by its size)."""

HARMONIC_R2 = 0.9
"""R² a candidate must reach for its frequency to be taken as the swing's beneath a
candidate moving at a harmonic of it (:func:`_fundamental`)."""

HARMONIC_SHARE = 0.08
"""Relative mismatch within which one frequency is a half or a third of another."""

SAME_FREQUENCY = 2
"""Steps of the survey's frequency grid (0.05 over its span) within which a candidate swings
at the swing's frequency."""

FOUND_SHARE = 0.6
"""Share of the survey's frames a candidate must be found in."""

STEP = 0.2
"""Farthest a candidate is sought from its last place in the next survey frame, as a share
of the frame's longest side (a swing across a third of the frame at 1 Hz moves a tenth of
it between frames 1/15 s apart)."""

MOVES = 1.0
"""Smallest amplitude of a candidate's swing, on the survey's frames. [px]"""


COLOURS = {
    "red": {"en": "red", "ru": "красная"}, "orange": {"en": "orange", "ru": "оранжевая"},
    "yellow": {"en": "yellow", "ru": "жёлтая"}, "green": {"en": "green", "ru": "зелёная"},
    "blue": {"en": "blue", "ru": "синяя"}, "magenta": {"en": "magenta", "ru": "пурпурная"},
    "white": {"en": "white", "ru": "белая"}, "black": {"en": "black", "ru": "чёрная"}}
"""The marker's colours a student may name (a measurement file's ``colour``)."""

HUES = {"red": ((0, 10), (170, 180)), "orange": ((10, 22),), "yellow": ((22, 35),),
        "green": ((35, 85),), "blue": ((85, 130),), "magenta": ((130, 170),)}
"""Hue ranges of the coloured markers, OpenCV's H (0–180, half degrees)."""

SATURATED = (90, 60)
"""Least saturation and value (0–255) of a coloured marker's pixels: a pale or dark patch
is no colour."""

WHITE, BLACK = (50, 170), 70
"""A white marker's greatest saturation and least value; a black one's greatest value."""

COLOUR_REACH = 0.5
"""How far about the pixels of the colour named the marker may lie, in shares of the
largest patch's side (its difference from the background spreads past its own
edge)."""


def colour_mask(bgr: np.ndarray, colour: str) -> np.ndarray:
    """Where a frame (BGR) shows ``colour`` (one of :data:`COLOURS`), as 0/1 (uint8),
    widened by :data:`COLOUR_REACH` of its largest patch's side."""
    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
    h, sat, val = hsv[..., 0], hsv[..., 1], hsv[..., 2]
    if colour == "white":
        mask = (sat <= WHITE[0]) & (val >= WHITE[1])
    elif colour == "black":
        mask = val <= BLACK
    else:
        mask = np.zeros(h.shape, bool)
        for lo, hi in HUES[colour]:
            mask |= (h >= lo) & (h < hi)
        mask &= (sat >= SATURATED[0]) & (val >= SATURATED[1])
    mask = mask.astype(np.uint8)
    count, _, stats, _ = cv2.connectedComponentsWithStats(mask)
    if count < 2:
        return mask
    side = int(stats[1:, cv2.CC_STAT_AREA].max() ** 0.5)
    reach = max(int(COLOUR_REACH * side), 1)
    return cv2.dilate(mask, np.ones((2 * reach + 1, 2 * reach + 1), np.uint8))


@dataclass(frozen=True)
class Marker:
    """The marker found by :func:`survey`, on the frames tracked.

    Attributes
    ----------
    x, y : float
        Its place in the reference frame. [px]
    side : int
        Its template's side (odd). [px]
    reference : int
        The survey frame the template comes from.
    start : (float, float) or None
        Its place in the film's first frame, if found there. [px]
    region : (int, int, int, int)
        x0, y0, x1, y1 of where it went in the survey, widened by two sides. [px]
    frequency : float
        The swing's frequency the survey saw. [Hz]
    contrast : float
        Its difference from the background. [grey levels]
    """

    x: float
    y: float
    side: int
    reference: int
    start: tuple[float, float] | None
    region: tuple[int, int, int, int]
    frequency: float
    contrast: float


def median_stack(frames: np.ndarray, rows: int = 16) -> np.ndarray:
    """The median of a stack of frames (frames × rows × columns) in their own type (of
    uint8, rounded), taken a band of ``rows`` at a time: the stack itself is all the
    memory it takes. Each band is turned so that a pixel's frames lie side by side before
    they are partitioned (a third faster than partitioning across the stack)."""
    n = frames.shape[0]
    middle = (n // 2,) if n % 2 else (n // 2 - 1, n // 2)
    out = np.empty(frames.shape[1:], frames.dtype)
    for r in range(0, frames.shape[1], rows):
        band = np.moveaxis(frames[:, r:r + rows], 0, -1).copy()
        band.partition(middle, axis=-1)
        mean = band[..., middle].mean(axis=-1)
        out[r:r + rows] = np.rint(mean) if out.dtype == np.uint8 else mean
    return out


def even_light(frames: np.ndarray) -> np.ndarray:
    """The frames (uint8, rounded) with their light evened out: each multiplied by the
    median lighting of all over its own lighting (the frame blurred over a sixteenth of its
    longest side; both worked out on the frames reduced eight times). A flicker, an
    exposure change or a shadow's slow sweep go; a compact moving patch stays. (Whole grey
    levels: a quarter of float32's memory, whose first touch was half the survey's time.)"""
    n, h, w = frames.shape
    small = (max(w // 8, 1), max(h // 8, 1))
    sigma = max(small) / 16
    light = np.empty((n, small[1], small[0]), np.float32)
    for k, f in enumerate(frames):
        light[k] = cv2.GaussianBlur(cv2.resize(f, small, interpolation=cv2.INTER_AREA)
                                    .astype(np.float32), (0, 0), sigma) + 1.0
    typical = np.median(light, axis=0)
    out = np.empty((n, h, w), np.uint8)
    gain = np.empty((h, w), np.float32)
    lit = np.empty((h, w), np.float32)
    for k, f in enumerate(frames):
        cv2.resize(typical / light[k], (w, h), dst=gain, interpolation=cv2.INTER_LINEAR)
        np.multiply(f, gain, out=lit)
        np.rint(lit, out=lit)
        np.clip(lit, 0, 255, out=lit)
        out[k] = lit
    return out


def _blob(diff: np.ndarray, cx: int, cy: int) -> tuple[float, float, float]:
    """Centroid and area of the patch of ``diff`` above half its value at (cx, cy)."""
    blob = (diff > 0.5 * diff[cy, cx]).astype(np.uint8)
    _, labels = cv2.connectedComponents(blob)
    ys, xs = np.nonzero(labels == labels[cy, cx])
    return float(xs.mean()), float(ys.mean()), float(xs.size)


def candidates(diff: np.ndarray, floor: float, count: int = CANDIDATES):
    """Up to ``count`` compact patches of ``diff`` above ``floor``, strongest first: (x, y,
    side, contrast), each patch blanked out before the next is sought."""
    diff = diff.copy()
    found = []
    for _ in range(count):
        peak = float(diff.max())
        if not peak > floor:
            break
        cy, cx = np.unravel_index(int(np.argmax(diff)), diff.shape)
        x, y, area = _blob(diff, int(cx), int(cy))
        side = int(np.clip(2 * math.sqrt(area / math.pi) * 2.2, 9, 81)) | 1
        found.append((x, y, side, peak))
        cv2.circle(diff, (int(round(x)), int(round(y))), side, 0.0, -1)
    return found


def turned(image: np.ndarray, x: float, y: float, side: int, angles) -> list[np.ndarray]:
    """Templates of ``side`` about (x, y) of ``image``, turned by each of ``angles`` (deg)
    about their centre; None for an angle whose template leaves the image."""
    half = side // 2
    reach = int(math.ceil(half * math.sqrt(2))) + 1
    x0, y0 = int(round(x)), int(round(y))
    if x0 - reach < 0 or y0 - reach < 0 or x0 + reach + 1 > image.shape[1] \
            or y0 + reach + 1 > image.shape[0]:
        if half <= x0 < image.shape[1] - half and half <= y0 < image.shape[0] - half:
            return [image[y0 - half:y0 + half + 1, x0 - half:x0 + half + 1].copy()
                    if a == 0 else None for a in angles]
        return [None for _ in angles]
    patch = image[y0 - reach:y0 + reach + 1, x0 - reach:x0 + reach + 1]
    out = []
    for a in angles:
        turn = cv2.getRotationMatrix2D((reach, reach), a, 1.0)
        rotated = cv2.warpAffine(patch, turn, patch.shape[::-1], flags=cv2.INTER_LINEAR)
        out.append(np.ascontiguousarray(rotated[reach - half:reach + half + 1,
                                                reach - half:reach + half + 1]))
    return out


def best_match(grey: np.ndarray, templates, box) -> tuple[float, float, float, int]:
    """The best of ``templates`` within ``box`` = (x0, y0, x1, y1) of ``grey``: centre,
    correlation and the template's index (correlation 0 where none fits)."""
    x0, y0, x1, y1 = (int(v) for v in box)
    x0, y0 = max(x0, 0), max(y0, 0)
    x1, y1 = min(x1, grey.shape[1]), min(y1, grey.shape[0])
    best = (math.nan, math.nan, 0.0, -1)
    window = grey[y0:y1, x0:x1]
    for k, template in enumerate(templates):
        if template is None or window.shape[0] <= template.shape[0] \
                or window.shape[1] <= template.shape[1]:
            continue
        corr = cv2.matchTemplate(window, template, cv2.TM_CCOEFF_NORMED)
        i, j = np.unravel_index(int(np.argmax(corr)), corr.shape)
        if corr[i, j] > best[2]:
            half = template.shape[0] // 2
            best = (x0 + j + half, y0 + i + half, float(corr[i, j]), k)
    return best


def follow(frames: np.ndarray, templates, reference: int, x: float, y: float) -> np.ndarray:
    """A candidate's way through the survey's frames, forwards and backwards from the
    reference frame: (x, y, correlation) each, sought within :data:`STEP` of the frame's
    longest side about its last place where it was found there, else over the whole
    frame."""
    h, w = frames.shape[1:]
    reach = STEP * max(h, w)
    way = np.full((len(frames), 3), np.nan)
    for order in (range(reference, len(frames)), range(reference, -1, -1)):
        px, py = x, y
        for k in order:
            box = (px - reach, py - reach, px + reach, py + reach) if math.isfinite(px) \
                else (0, 0, w, h)
            way[k] = best_match(frames[k], templates, box)[:3]
            if way[k, 2] < SURVEY_CONFIDENCE:
                px = py = math.nan
                way[k, 2] = 0.0 if math.isnan(way[k, 2]) else way[k, 2]
            else:
                px, py = way[k, 0], way[k, 1]
    return way


def periodicity(t: np.ndarray, x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """How periodic a way is: (R², amplitude [px], frequency [Hz]) of the single sinusoid
    on a line that best describes its projection on its principal direction, the frequency
    sought from half a cycle over the way's span to half its frame rate."""
    k = np.isfinite(x)
    t, xy = t[k], np.column_stack([x[k], y[k]])
    if t.size < 8:
        return 0.0, 0.0, math.nan
    xy = xy - xy.mean(axis=0)
    _, _, vt = np.linalg.svd(xy, full_matrices=False)
    s = xy @ vt[0]
    span = float(t[-1] - t[0])
    line = np.column_stack([np.ones_like(t), t - t.mean()])
    s = s - line @ np.linalg.lstsq(line, s, rcond=None)[0]
    total = float(s @ s)
    if total <= 0 or span <= 0:
        return 0.0, 0.0, math.nan
    top = 0.5 / float(np.median(np.diff(t)))
    f = np.arange(0.5 / span, top, 0.05 / span)
    if f.size == 0:
        return 0.0, 0.0, math.nan
    # every trial frequency's least squares at once: its basis (cos, sin, the line) and
    # normal equations stacked over the frequencies
    phase = 2 * np.pi * f[:, None] * t[None, :]
    basis = np.stack([np.cos(phase), np.sin(phase), np.broadcast_to(line[:, 0], phase.shape),
                      np.broadcast_to(line[:, 1], phase.shape)], axis=1)
    normal = basis @ basis.transpose(0, 2, 1)
    coef = _solve(normal, basis @ s)
    residual = s[None, :] - np.einsum("fk,fkn->fn", coef, basis)
    r2 = 1 - np.sum(residual ** 2, axis=1) / total
    k = int(np.argmax(r2))
    if not r2[k] > 0:
        return 0.0, 0.0, math.nan
    return float(r2[k]), float(math.hypot(coef[k, 0], coef[k, 1])), float(f[k])


def _solve(normal: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Stacked normal equations solved (least squares where one is singular)."""
    try:
        return np.linalg.solve(normal, right[..., None])[..., 0]
    except np.linalg.LinAlgError:
        return np.stack([np.linalg.lstsq(a, b, rcond=None)[0] for a, b in zip(normal, right)])


def _chosen(followed: list, times: np.ndarray, shape: tuple[int, int]):
    """The marker among the candidates followed (each (R², promise, x, y, side, contrast,
    way, found, frequency)): of those that swing at the swing's frequency (the most periodic
    candidate's, within :data:`SAME_FREQUENCY` steps of the survey's frequency grid) as
    periodically as it (R² within :data:`AS_PERIODIC`), the one that promises the most
    precise track — the widest swing of the largest patch (not the most contrast in the
    difference from the background: the lobes that a moving marker's difference leaves
    beside it have more) — preferring those whose way stays a side inside the frame (a dot
    at the frame's edge is lost half the time)."""
    top = _fundamental(followed, max(followed, key=lambda f: f[0]))
    step = 0.05 / float(times[-1] - times[0])
    alike = [f for f in followed if f[0] >= top[0] - AS_PERIODIC
             and abs(f[8] - top[8]) <= SAME_FREQUENCY * step]
    h, w = shape

    def inside(f) -> bool:
        way, found, side = f[6], f[7], f[4]
        xs, ys = way[found, 0], way[found, 1]
        return bool(xs.min() >= side and ys.min() >= side and xs.max() <= w - side
                    and ys.max() <= h - side)

    return max(alike, key=lambda f: (inside(f), f[1]))[2:]


def _fundamental(followed: list, top):
    """The candidate whose frequency is the swing's: ``top`` (the most periodic), unless
    another periodic one (R² ≥ :data:`HARMONIC_R2`) swings at a half or a third of its
    frequency (within :data:`HARMONIC_SHARE`): then ``top`` moves at a harmonic of the swing
    — a trifilar's ring about its axis, seen from above, moves only as the platform rises
    and sinks, twice a swing — and the slower one is the swing's."""
    for divisor in (2, 3):
        below = [f for f in followed if f[0] >= HARMONIC_R2
                 and abs(f[8] * divisor / top[8] - 1) <= HARMONIC_SHARE]
        if below:
            return max(below, key=lambda f: f[0])
    return top


def survey(kept: np.ndarray, times: np.ndarray, roi=None, colours=None):
    """The marker in a film's first frames (see the module's notes).

    Parameters
    ----------
    kept : numpy.ndarray
        The survey's frames (frames × rows × columns, uint8), at the size tracked.
    times : numpy.ndarray
        Their times. [s]
    roi : (x, y, w, h), optional
        Where the marker is sought, on the frames tracked. [px]
    colours : sequence of numpy.ndarray, optional
        Each survey frame's :func:`colour_mask` of the marker's colour, on the frames
        tracked: the marker is sought where the reference frame shows it.

    Returns
    -------
    Marker or None
        None where nothing in the frames moves periodically.
    """
    shrink = min(1.0, SURVEY_SIDE / max(kept.shape[1:]))
    small = kept if shrink >= 1 else np.stack([cv2.resize(f, None, fx=shrink, fy=shrink,
                                                          interpolation=cv2.INTER_AREA)
                                               for f in kept])
    even = even_light(small)
    background = median_stack(even)
    reference = int(np.argmin([cv2.absdiff(f, background).mean() for f in even]))
    diff = cv2.GaussianBlur(cv2.absdiff(even[reference], background).astype(np.float32),
                            (0, 0), 1.0)
    if roi is not None:
        x0, y0, w, h = (int(round(v * shrink)) for v in roi)
        mask = np.zeros(diff.shape, np.float32)
        mask[max(y0, 0):y0 + h, max(x0, 0):x0 + w] = 1.0
        diff *= mask
    if colours is not None:
        diff *= cv2.resize(colours[reference], diff.shape[::-1],
                           interpolation=cv2.INTER_NEAREST).astype(np.float32)
    noise = float(np.std(even[reference].astype(np.float32)
                         - even[reference - 1 if reference else 1])) / math.sqrt(2)
    followed = []
    for x, y, side, contrast in candidates(diff, max(3.0 * noise, 8.0)):
        templates = turned(even[reference], x, y, side, SURVEY_TURNS)
        way = follow(even, templates, reference, x, y)
        found = way[:, 2] >= SURVEY_CONFIDENCE
        if found.mean() < FOUND_SHARE:
            continue
        r2, amplitude, frequency = periodicity(times, np.where(found, way[:, 0], np.nan),
                                               way[:, 1])
        if r2 >= MIN_PERIODIC and amplitude >= MOVES:
            followed.append((r2, amplitude * side, x, y, side, contrast, way, found,
                             frequency))
    if not followed:
        return None
    x, y, side, contrast, way, found, frequency = _chosen(followed, times, small.shape[1:])
    grow = 1.0 / shrink
    wx, wy = way[found, 0] * grow, way[found, 1] * grow
    big = int(side * grow) | 1
    margin = 2 * big
    region = (int(wx.min()) - margin, int(wy.min()) - margin, int(wx.max()) + margin + 1,
              int(wy.max()) + margin + 1)
    start = (float(way[0, 0] * grow), float(way[0, 1] * grow)) if found[0] else None
    return Marker(float(x * grow), float(y * grow), int(np.clip(big, 11, 81)) | 1, reference,
                  start, region, frequency, contrast)
