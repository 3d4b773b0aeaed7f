"""A phone film of a swinging part: the marker on it tracked frame by frame, and the period of
its oscillation fitted over the whole film.

:func:`track_marker` reads the film with OpenCV, frame by frame with each frame's own
timestamp (a phone films at a variable rate: the spread of the intervals is reported). The
marker — the patch that moves most against the still background (the median of the first
frames), or the one inside a given region or of a given colour — becomes a template; each frame it is found again
by normalised cross-correlation in a window about its last place (:func:`cv2.matchTemplate`,
so an even change of lighting does not matter), then aligned to a small fraction of a pixel
by ECC (:func:`_refine`). The peak's height is the frame's confidence; frames below
:data:`MIN_CONFIDENCE` (blurred, occluded) are left out, not guessed.

Memory stays bounded whatever the film: the frame size is read off the stream's header
before a frame is decoded (over :data:`MAX_FRAME_PIXELS` is refused), a film larger than
:data:`WORK_SIDE` is tracked on its frames reduced to it (a phone's 4K film as a 1080p one),
and the background's frames are kept as bytes, their median taken a band of rows at a time:
a 4K film is tracked in about 0.4 GB (5.2 GB before, its first 64 frames stacked whole as
float32).

:func:`swing_of` turns the track into the marker's way along its arc (:meth:`Track.
displacement`) and fits a damped sinusoid on a line over every frame kept
(:func:`processing.oscillations.decay.fit_damped_sine`): the period with its u (:func:`period_of`),
the amplitude and its decay.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import cv2
import numpy as np
from scipy import stats
from scipy.ndimage import minimum_filter1d

from processing.oscillations.anharmonic import AnharmonicFit, fit_anharmonic_decay
from processing.oscillations.decay import fit_damped_sine
from ..diagnostics import (DroppedFramesWarning, FilmAmplitudeWarning, HiddenDropsWarning,
                           InconsistentInputWarning, InputError)
from processing.oscillations.savgol import savgol
from processing.inputs.reuse import by_content, scope
from ..measurement import Field, bi
from ..uncertainty import Measured, coverage_factor
from .frames import (DROPPED, IRREGULAR, frame_clock, frames, interval_spread, open_film,
                     typical_interval)
from .marker import (COLOURS, SURVEY_FRAMES, SURVEY_SECONDS, TURNS, colour_mask, survey,
                     turned)

MIN_CONFIDENCE = 0.75
"""Normalised correlation below which a frame's marker position is left out (the marker
itself matches at 0.9–0.97 through blur, noise and flicker; a hand half over it, at 0.6)."""

SEARCH = 4.0
"""Half-width of the search window where the marker is not found near its predicted place
(last place plus last step), in template sizes."""

NYQUIST_SHARE = 0.8
"""A fitted swing above this share of half the frame rate is refused: near the Nyquist
frequency a swing cannot be told from an alias (below it, an alias looks like a slower swing
that no film alone can unmask; the stopwatch's period, given too, is checked against it)."""

SWING_SNR = 5.0
"""The swing's amplitude over the track's residual σ below which there is no swing."""

AMPLITUDE_LIMIT = 0.2
"""The limit of error a film's amplitude is meant to keep (issue 18's target); a film whose
own limit (:attr:`Filmed.amplitude_limit`) is wider is warned of
(:class:`FilmAmplitudeWarning`). [deg]"""

ARC_LOCKING = 0.03
"""Bound of the bend the tracker's sub-pixel error puts into the marker's arc across its
sagitta. [px] (The error is a function of the marker's place within a pixel relative to the
template's: ECC's bilinear interpolation of the frame, the codec's blocks; the arc's sagitta
R(1 − cos θ₀) spans less than a pixel at small swings, so the error does not average out
there. Measured: a marker stepped across a pixel is tracked within 0.014 px; on the
synthetic films of 2–10° at 100–600 px arms, from above and the side, at any sub-pixel place
of the arc, the sagitta came out short by up to 0.030 px, most where it is about 0.8 px.)"""

NOTCH = 2.5
"""Frequency spacings (1/duration) each side of the swing's that the fit empties of
residual and that are left out of the residual's density."""

LOCKING = 0.003
"""The tracker's error that is a function of the marker's place in the frame (codec blocks,
the template's background), repeated every swing. [px] (Measured on the synthetic films of
the bench: 0.003 px brings the 95 % interval to hold the truth in 97 % of 114 films over
the grid, 96 % at 3° and 60 frames per second, where it weighs most.)"""

STRAIGHT = 0.01
"""Half the angle a track must sweep for its arc's angle to be its displacement. [rad]"""

OFF_PATH = (10.0, 0.5, 7)
"""A kept frame is off the marker's path (:attr:`Track.on_path`) where it lies further than
the larger of this many robust σ (1.4826 × the median) and this many px from a quadratic
through its this-many neighbouring frames (a moment's false match: one frame of the
bench's 3° film from above sat 15 px off a path its others follow within 0.07 px, and bent
that short arc's circle to a 355 000 px radius)."""

SWING_REACH = 4.0
"""A kept frame further from the track's median place than this many times the kept frames'
median distance from it is off the marker's path (:attr:`Track.on_path`), whatever its
neighbours: a swing stays within about 1.5 times that distance (its decay to a quarter over
the film included); a false match held over several frames need not (three frames of a
240 fps film 68–209 px from a swing 14 px from its median place, each beside others as far,
passed the local test and bent a 85 px arc to a 990 000 px radius, whose u then failed)."""

SURVEY_AGREES = 0.15
"""Relative difference between the fitted swing's frequency and the one the survey saw
(on its coarse grid, from a few seconds) beyond which the track is not of the swing: a
point moving at twice the swing's frequency (the trifilar's axis as the platform rises)
would halve the period."""

MIN_OSCILLATIONS = 2
"""Fewest oscillations a film must span: its period's u rests on the residual's density about
the swing's frequency, read at frequencies 1/duration apart, and under two oscillations the
fit's decay, drift and baseline take up the period's own information."""

FEW_OSCILLATIONS = 10
"""Oscillations a student is asked to film where a film is refused for its length or its
fit."""

MAX_DROPS = 20
"""Dropped frames sought in a film whose times claim a constant rate."""

DROP_SIGMAS = 4.5
"""Standard errors a step of the swing's timing must stand out by to be taken for a dropped
frame (:func:`_find_drops`), on a scan of :data:`SCAN_FRAMES` frames (more on a longer one:
:func:`scanned`), and never less than the scan's most negative step (the film's own noise:
no dropped frame steps the timing back). (Measured on 60 clean phone films of 3–19° at 30
and 60 frames per second, 8 oscillations, with a phone's shake: the step tried — the one
best explained as whole intervals, a quarter swing or more from the film's ends — stood at
most 4.3 standard errors out (a step of half an interval), and none was taken; a fresh
clean film showed one at 5.2, its scan at −5.7 the other way.)"""

SCAN_FRAMES = 300
"""Frames of the film :data:`DROP_SIGMAS` and :data:`DOUBT_SIGMAS` hold for (8 oscillations
at 30 frames per second); a longer scan tries more steps, and its threshold rises so that
noise alone passes it as seldom (:func:`scanned`)."""

DROP_DETECTABLE = 3.0
"""Standard errors a single dropped frame's step must stand out by at the film's median frame
for dropped frames to be sought at all (:func:`_drop_power`): where it would stand less, the
scan sees no frame's edge, only a level raised over seconds, which a slow-motion film's slow
noise raises as well (clean films at 240 frames per second: at 1.0, 32 frames "found" and the
period put 3.8 u off; at 2.0 and 2.4, 4–12 frames in bursts of 3–5). Of 200 films of 8
oscillations at 30 and 60 frames per second, only a 3° swing at 60 (1.5 and 1.9, with and
without its two dropped frames) stands under it: its period held either way."""

DROP_TRANSIENT = (4, 3.0, 1 / 3)
"""A step is no dropped frame where, within this many frames of it, the scan steps back by
more than the larger of this many standard errors and this share of the step
(:func:`_steps`): no dropped frame steps the timing back, and a frame or two matched off and
back (a codec's key frame, a hand's shadow) makes the scan swing both ways, +15.7 and −7.7
one frame apart on a clean film at 240 frames per second, +6.0 and −4.8 on one at 60 (a
false drop); beside the dropped frames found in films of 8 oscillations at 30 and 60 frames
per second it stepped back by 2.3 at most, or 3.1 beside one of 11.4."""

DROP_PERSISTS = 2.0
"""Standard errors short of the m intervals a dropped frame makes them late by that the frames
after a step may lie, judged away from its edge (:func:`_late_beyond`), while nearer on time
than that late, before the step is given up as a few frames matched off and back
(:func:`_lasting`). A dropped frame makes every later frame late; a transient only makes an
edge, which at 240 frames per second, where the shake is nearly all the track's noise and
the scan weighs the edge most, stands out as a drop's would: a clean film's marker drifted
off along the arc over 4 frames and snapped back, an edge of 5.1 standard errors (1.33
intervals, over the scan's 4.90) with no step back under 3, and was warned of; its later
frames are 0.10 ± 0.33 of an interval late. The 38 dropped frames found in films of 8
oscillations at 30, 60 and 240 frames per second (seeds 820–839 and 2702–2759 step 3) are
0.52–1.17 late (± 0.12–0.28). On films not read while it was made, 20 clean at 240 frames per
second were warned of no drop (one was before: later frames 0.35 ± 0.18 late), and 40 films
at 30 and 60 with two frames dropped were warned or held as before (38)."""

DOUBT_SIGMAS = 3.0
"""Standard errors a step of the swing's timing of half an interval or more must stand out
by (on :data:`SCAN_FRAMES` frames: :func:`scanned`), under :data:`DROP_SIGMAS`, for the
period's u to carry it as a dropped frame that may be there (:func:`_further_drops`; not
warned of). On 100 films of 8 oscillations at 30 and 60 frames per second with two frames
dropped, 9 were left unwarned and 7 of them hold their period within U (5 carrying such a
step, 2–6 U off without it); of their 100 clean twins, 2 carry one (u 1.3 and 1.7 times
wider); of 40 clean films at 240 frames per second, 5."""

HIDDEN_SHARE = 0.05
"""Share of a film's frames above which a film whose times claim a constant rate is warned
that a dropped frame could hide in it (:func:`_warn_hidden_drops`): frames where a single
one's step would stand under what the search needs (:func:`_drop_reach`) and move the period
by more than its u, so that two would move it beyond U. Against u, not U: a phone that drops
frames drops more than one, and held against U the warning left 3 of 30 films at 240 frames
per second with two frames dropped neither warned nor within their U (2.4–5.1 u off); held
against u, none. (Set before the films were read, not tuned: on fresh films of 8
oscillations, 320 × 180, restamped — 240 fps, seeds 4001–4088 step 3, and 30/60 fps, seeds
4200–4219 — the shares of those not warned reached 0.049 and of those warned began at 0.06;
the clean 30/60 fps films whose drops the search sees reach 0.03.) The period's u does not
carry such a drop: on the 19 clean 240 fps films warned, a single one's shift carried as a
limit would widen the u 1.2–4.1 times (median 2.0) for a drop nothing shows, where all 30
held their period within U as stated."""

DOUBT_STEPS = 3
"""Most steps too faint to be sure of that the period's u carries (:func:`_further_drops`)."""

DROP_WHOLE = 0.35
"""Farthest a step may lie from a whole number of frame intervals, in intervals (or three of
its standard errors, if more)."""

DROP_OSCILLATIONS = 2 * NOTCH + 2
"""Fewest oscillations a film must span for its dropped frames to be sought: the residual's
spectrum that weighs a step must be seen below the swing's frequency too, between the bins
the fit empties about zero and about the swing (:data:`NOTCH` spacings each), where a
phone's shake puts most of its power (on 3.5 oscillations it is not, and a hub's noisy
track showed a step of 9 standard errors that was none)."""

DROP_SMOOTH = 4
"""Frequency spacings (1/duration) each side over which the residual's periodogram is averaged
into the noise's spectrum that weighs the steps (:func:`_timing_steps`)."""

OUTLIER = (6.0, 0.5)
"""A frame is left out of the swing's fit where its residual lies further than the larger of
this many robust σ and this many px from the fit's (:func:`_consistent`); the fit is then
repeated, at most :data:`REFITS` times. (Gaussian residuals pass 6 σ but once in 5·10⁸
frames; a frame matched to a hand's knuckle lies tens of σ off.)"""

REFITS = 3
"""Fits repeated with the frames found off the fit left out."""

NOTCH_BEYOND = 3
"""Frequency spacings past the notch the residual's density is taken over at least."""

LEAK_BAND = 2.0
"""Multiple of the swing's frequency up to which each frequency of the residual weighs the
period's u by its own periodogram (:func:`_spread`): a phone's slow shake wanders most over
the film's whole length, at 1/duration, where its power can be a hundred times the density
about the swing's frequency, and the fit's frequency leaks from there. (Measured on a
slow-motion film that missed its interval by 2.6 u: half the period's error came from the
bins under a quarter of the swing's frequency, 0.9 % of the fit's weight but 117 times the
noise about it.)"""


@dataclass(frozen=True)
class Track:
    """The marker's path through a film.

    Attributes
    ----------
    path : str
    time : numpy.ndarray
        Each frame's timestamp. [s]
    x, y : numpy.ndarray
        The marker's centre (NaN where left out). [px]
    confidence : numpy.ndarray
        Peak normalised correlation of each frame, 0–1.
    size : int
        The template's side. [px]
    interval_spread : float
        Standard deviation of the frame intervals over their usual one (dropped frames and
        the container's rounding aside: :func:`~processing.vision.frames.interval_spread`).
    frames : list
        A few (index, grey frame) pairs kept for the report.
    scale : float
        The film's pixels per pixel of the frames tracked (1 unless the film is larger than
        :data:`~processing.vision.frames.WORK_SIDE`): every position and size here is in the
        frames tracked.
    dropped : int
        Frames the camera dropped (gaps in the timestamps).
    timed : bool
        Whether the container held the frames' times (False: taken at the nominal rate).
    frequency : float
        The swing's frequency the survey saw in the film's first seconds
        (:attr:`~processing.vision.marker.Marker.frequency`). [Hz]
    """

    path: str
    time: np.ndarray
    x: np.ndarray
    y: np.ndarray
    confidence: np.ndarray
    size: int
    interval_spread: float
    frames: list = field(default_factory=list, repr=False)
    scale: float = 1.0
    dropped: int = 0
    timed: bool = True
    frequency: float = math.nan

    @property
    def kept(self) -> np.ndarray:
        return np.isfinite(self.x)

    @cached_property
    def on_path(self) -> np.ndarray:
        """The kept frames on the marker's smooth path (:data:`OFF_PATH`) and within the
        swing's reach (:data:`SWING_REACH`): those the arc is fitted through. A frame beside
        one left out (a hand over the marker) is held against the quadratic in time through
        the kept frames of its window, not through frames that the gap puts out of step."""
        sigmas, floor, window = OFF_PATH
        k = self.kept
        on = k.copy()
        if k.sum() <= window:
            return on
        smooth = np.column_stack([savgol(self.x[k], window, 2), savgol(self.y[k], window, 2)])
        half = window // 2
        gappy = np.convolve(~k, np.ones(window), "same")[k] > 0
        index = np.flatnonzero(k)
        for j in np.flatnonzero(gappy):
            near = index[np.abs(index - index[j]) <= half]
            if near.size < 4:
                smooth[j] = self.x[index[j]], self.y[index[j]]
                continue
            dt = self.time[near] - self.time[index[j]]
            smooth[j] = [np.polyval(np.polyfit(dt, v[near], 2), 0.0) for v in (self.x, self.y)]
        off = np.hypot(self.x[k] - smooth[:, 0], self.y[k] - smooth[:, 1])
        far = np.hypot(self.x[k] - np.median(self.x[k]), self.y[k] - np.median(self.y[k]))
        on[k] = (off <= max(sigmas * 1.4826 * float(np.median(off)), floor)) \
            & (far <= SWING_REACH * float(np.median(far)))
        return on

    @property
    def frame_rate(self) -> float:
        """Median frames per second. [1/s]"""
        return float(1.0 / np.median(np.diff(self.time)))

    @cached_property
    def circle(self) -> tuple[float, float, float]:
        """The arc the marker runs on (see :func:`arc`). [px]"""
        return arc(self)

    def displacement(self) -> tuple[np.ndarray, np.ndarray]:
        """(times, s) of the frames kept on the marker's path (:attr:`on_path`: a moment's
        false match left out): the marker's way along its arc, s = R·θ with θ
        the angle about the arc's centre from the track's mean direction. [s], [px]

        The angle, not the position along a line: the chord R sin θ of a swing θ₀ cos ωt
        holds a third harmonic R θ₀³/24 (0.13 px at 10° and 600 px) that no damped sinusoid
        fits and that would pass for noise. A track too straight for its arc to be found
        (θ₀ below :data:`STRAIGHT` rad, where that harmonic is under 10⁻⁴ px) is projected on
        its principal direction instead.

        The camera's shake moves the picture by d(t) under the marker: along the arc by
        d·t̂(θ) = d_x cos θ − d_y sin θ (axes along and across the arc's mean direction) and
        across it by d·r̂(θ) = d_x sin θ + d_y cos θ, which is the track's distance from the
        arc less R (:meth:`radial`). The part d_y sin θ is the slow shake times the swing
        itself: sidebands at the swing's frequency ± the shake's, inside the band the fit
        empties, which neither the fit nor its residual's density would carry. The radial
        residual measures them: s = Rθ + ρ tan θ leaves the shake as d_x/cos θ, a slow
        wander whose density at the swing's frequency the u carries (:func:`period_of`)."""
        t, theta, rho, _ = self._polar
        if theta is None:
            return t, rho
        return t, self.circle[2] * theta + rho * np.tan(theta)

    def radial(self) -> np.ndarray:
        """The track's distance from its arc at the frames of :meth:`displacement`, less the
        path's own shape (a polynomial in θ to the third degree: the perspective of a
        tilted phone draws the circle as an ellipse) and a slow drift: what the camera's
        shake and the tracker's noise move the marker across its arc. Zeros where the
        track is too straight for an arc. [px]"""
        t, theta, rho, _ = self._polar
        if theta is None:
            return np.zeros_like(t)
        return rho

    def radial_shape(self) -> np.ndarray | None:
        """The columns taken out of :meth:`radial` (the path's shape in θ and the slow
        drift), at its frames; None where the track is too straight for an arc. The θ³ and
        θ columns swing at the swing's own frequency, so they empty part of the radial
        residual's density there (:func:`_density_at` allows for it)."""
        return self._polar[3]

    @cached_property
    def _polar(self):
        """(times, θ, ρ, shape) of the frames on the path: the angle about the arc's
        centre, the radial residual (:meth:`radial`) and the columns taken out of it
        (:meth:`radial_shape`); θ and shape None and ρ the projection on the principal
        direction where the track is too straight for an arc."""
        k = self.on_path
        xy = np.column_stack([self.x[k], self.y[k]])
        mean = xy.mean(axis=0)
        xc, yc, R = self.circle
        r = xy - (xc, yc)
        to_mean = mean - (xc, yc)
        theta = np.arctan2(to_mean[0] * r[:, 1] - to_mean[1] * r[:, 0], r @ to_mean)
        t = self.time[k]
        if np.isfinite(R) and np.ptp(theta) > 2 * STRAIGHT:
            rho = np.hypot(r[:, 0], r[:, 1]) - R
            tau = (t - t[0]) / max(float(t[-1] - t[0]), 1e-9)
            shape = np.column_stack([theta ** j for j in range(4)] + [tau, tau ** 2])
            rho = rho - shape @ np.linalg.lstsq(shape, rho, rcond=None)[0]
            return t, theta, rho, shape
        _, _, vt = np.linalg.svd(xy - mean, full_matrices=False)
        return t, None, (xy - mean) @ vt[0], None


@dataclass(frozen=True)
class Swing:
    """The oscillation fitted to a track.

    Attributes
    ----------
    fit : AnharmonicFit
        The decaying oscillation on the track's displacement (px), its frequency a function
        of its amplitude (:func:`processing.oscillations.anharmonic.fit_anharmonic_decay`).
    period : Measured
        T = 2π/ω̄, the mean period over the frames kept, with its u (:func:`period_of`). [s]
    oscillations : float
        Periods the kept frames span.
    amplitude : float
        The displacement's amplitude at the film's first frame kept. [px]
    kept_share : float
        Share of the film's frames the swing is fitted through (found, on the marker's path
        and consistent with the fit).
    reference_amplitude : float
        The RMS of the amplitude over the frames kept: the amplitude the period belongs to
        (a wide swing's period changes as it decays). [px]
    """

    fit: AnharmonicFit
    period: Measured
    oscillations: float
    amplitude: float
    kept_share: float
    reference_amplitude: float


def _refuse(path, field_name, problem: str, fix: str, ru=None) -> InputError:
    return InputError(problem, fix, file=str(path), field=field_name, ru=ru)


def _subpixel(c: np.ndarray, i: int, j: int) -> tuple[float, float]:
    """Parabola through the peak and its neighbours, each axis."""
    def vertex(a, b, d):
        den = a - 2 * b + d
        return 0.0 if den >= 0 else 0.5 * (a - d) / den

    dx = vertex(c[i, j - 1], c[i, j], c[i, j + 1]) if 0 < j < c.shape[1] - 1 else 0.0
    dy = vertex(c[i - 1, j], c[i, j], c[i + 1, j]) if 0 < i < c.shape[0] - 1 else 0.0
    return dx, dy


def _match(grey: np.ndarray, templates, box, tried):
    """The best of the turned templates (:data:`~processing.vision.marker.TURNS`) numbered
    ``tried`` within ``box`` = (x0, y0, x1, y1): centre, correlation and the template's
    index, or None where the window is smaller than the template. The upright template is
    kept unless a turned one matches better by :data:`TURN_MARGIN`."""
    side = templates[UPRIGHT].shape[0]
    half = side // 2
    h, w = grey.shape
    ax, ay = int(max(box[0], 0)), int(max(box[1], 0))
    bx, by = int(min(box[2], w)), int(min(box[3], h))
    window = grey[ay:by, ax:bx]
    if window.shape[0] <= side or window.shape[1] <= side:
        return None
    found = {}
    for k in tried:
        template = templates[k]
        if template is None:
            continue
        corr = cv2.matchTemplate(window, template, cv2.TM_CCOEFF_NORMED)
        i, j = np.unravel_index(int(np.argmax(corr)), corr.shape)
        found[k] = (corr, i, j)
    k = max(found, key=lambda n: found[n][0][found[n][1], found[n][2]])
    if UPRIGHT in found and found[k][0][found[k][1], found[k][2]] < \
            found[UPRIGHT][0][found[UPRIGHT][1], found[UPRIGHT][2]] + TURN_MARGIN:
        k = UPRIGHT
    corr, i, j = found[k]
    dx, dy = _subpixel(corr, i, j)
    return ax + j + dx + half, ay + i + dy + half, float(corr[i, j]), k


def _around(x: float, y: float, reach: float, side: int) -> tuple[int, int, int, int]:
    half = side // 2
    return (int(x - half - reach), int(y - half - reach), int(x + half + reach + 1),
            int(y + half + reach + 1))


ECC_STEPS = 30
"""Iterations of the ECC alignment that refines each frame's match."""

ECC_BLUR = 5
"""Side of the Gaussian kernel (σ 1.1 px) ECC smooths the template and the frame with before
aligning them: the bilinear interpolation's error, a function of the marker's place within a
pixel, falls with the image's curvature (measured on a sharp marker stepped across a pixel:
up to 0.026 px unsmoothed, 0.014 px smoothed)."""

TURN_MARGIN = 0.03
"""Correlation a turned template must gain over the upright one to be taken."""

UPRIGHT = TURNS.index(0.0)

LOST_FRAMES = 2
"""Frames the marker may go unfound (a hand, a flash of blur) before it is sought over the
whole region it swings in."""

REACQUIRE = 0.85
"""Correlation the marker must reach to be taken up again over the whole region it swings
in (far from where it was last seen, a corner of a hand or of a shadow must not pass for
it; the marker itself matches at 0.9 and more where it moves slowest)."""


def _refine(grey: np.ndarray, template: np.ndarray, x: float, y: float):
    """The template's place near (x, y) to a small fraction of a pixel, or None.

    The correlation peak's parabola is pulled towards whole pixels (pixel locking: up to
    0.07 px here, a function of the marker's place that repeats every swing and shifts the
    fitted period by several of its u); the template is aligned instead by translation
    maximising the enhanced correlation coefficient (Evangelidis G.D., Psarakis E.Z.,
    "Parametric image alignment using enhanced correlation coefficient maximization", IEEE
    PAMI 30 (10), 2008: :func:`cv2.findTransformECC`), which interpolates the frame and is
    as blind to an even change of lighting as the correlation; both smoothed first
    (:data:`ECC_BLUR`). None where the alignment does not converge or leaves the frame (the
    frame is then left out).
    """
    side = template.shape[0]
    half, margin = side // 2, 3
    x0, y0 = int(round(x)) - half - margin, int(round(y)) - half - margin
    if x0 < 0 or y0 < 0 or x0 + side + 2 * margin > grey.shape[1] \
            or y0 + side + 2 * margin > grey.shape[0]:
        return None
    window = grey[y0:y0 + side + 2 * margin, x0:x0 + side + 2 * margin]
    warp = np.array([[1, 0, x - half - x0], [0, 1, y - half - y0]], np.float32)
    try:
        _, warp = cv2.findTransformECC(template, window, warp, cv2.MOTION_TRANSLATION,
                                       (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT,
                                        ECC_STEPS, 1e-5), None, ECC_BLUR)
    except cv2.error:
        return None
    dx, dy = float(warp[0, 2]), float(warp[1, 2])
    if not (0 <= dx <= 2 * margin and 0 <= dy <= 2 * margin):
        return None
    return x0 + dx + half, y0 + dy + half


def _survey_frames(film, field, colour: str | None = None):
    """The survey's frames (:data:`~processing.vision.marker.SURVEY_FRAMES` of them, every
    so many over :data:`~processing.vision.marker.SURVEY_SECONDS` at a high frame rate),
    their times (by the nominal rate where the film holds none) and, with ``colour``, each
    one's :func:`~processing.vision.marker.colour_mask` (else None)."""
    rate = film.rate if math.isfinite(film.rate) and film.rate > 0 else 30.0
    stride = max(1, math.ceil(rate * SURVEY_SECONDS / SURVEY_FRAMES))
    kept, times, masks = None, [], []
    for index, decoded in enumerate(frames(film, field, colour=colour is not None)):
        if index % stride:
            continue
        grey, t = decoded[0], decoded[1]
        if kept is None:
            kept = np.empty((SURVEY_FRAMES, *grey.shape), np.uint8)
        kept[len(times)] = grey
        times.append(t if math.isfinite(t) else index / rate)
        if colour is not None:
            masks.append(colour_mask(decoded[2], colour))
        if len(times) == SURVEY_FRAMES:
            break
    if kept is None:
        return np.empty((0, 1, 1), np.uint8), np.empty(0), None
    return kept[:len(times)], np.asarray(times), masks if colour is not None else None


def track_marker(path, *, roi=None, colour: str | None = None, field: str | None = None,
                 roi_field: str | None = None, colour_field: str | None = None,
                 min_confidence: float = MIN_CONFIDENCE, keep_frames: int = 4) -> Track:
    """Track the marker on a swinging part through a film.

    The marker is what moves periodically in the film's first seconds
    (:func:`processing.vision.marker.survey`); each frame it is sought near its predicted
    place (last place plus last step), then within :data:`SEARCH` template sizes of its last
    place, and after :data:`LOST_FRAMES` frames unfound over the whole region it swings in,
    with its template turned as the part turns; then aligned to a small fraction of a pixel
    (:func:`_refine`). Frames where it matches below ``min_confidence`` are left out.

    Parameters
    ----------
    path : str or Path
        The film (MP4, MOV, AVI, MKV).
    roi : (x, y, w, h), optional
        Where the marker is in the first frames, in the film's pixels: the marker is the
        patch inside it that swings. [px]
    colour : str, optional
        The marker's colour (one of :data:`~processing.vision.marker.COLOURS`): the marker
        is the patch of that colour that swings.
    field : str, optional
        The measurement-file field that named the film, for errors.
    roi_field : str, optional
        The measurement-file field that gave ``roi`` (``pendulum.roi``), for errors and for
        the advice to give one.
    colour_field : str, optional
        The measurement-file field that gave ``colour``, for errors.
    min_confidence : float
        Frames whose correlation peak is lower are left out.
    keep_frames : int
        Frames kept (evenly spaced) for the report's pictures.

    Returns
    -------
    Track

    Raises
    ------
    InputError
        Not a film; frames larger than :data:`~processing.vision.frames.MAX_FRAME_PIXELS`;
        too short; nothing moves periodically (inside ``roi``, of ``colour``); the marker
        lost in most frames.
    """
    film = open_film(path, field)
    scale = film.scale
    kept, stamps, colours = _survey_frames(film, field, colour)
    if len(kept) < 16:
        raise _refuse(path, field, f"the film holds {len(kept)} frames",
                      "film the whole swing: 20 oscillations or more",
                      (f"в видео всего кадров: {len(kept)}", "снимите качания целиком: 20 "
                       "колебаний или больше"))
    if roi is not None:
        _check_roi(path, roi, film.size, roi_field)
    where = None if roi is None else tuple(scale * float(v) for v in roi)
    marker = survey(kept, stamps, where, colours)
    if marker is None and colour is not None:
        name, name_ru = COLOURS[colour]["en"], COLOURS[colour]["ru"]
        raise _refuse(path, colour_field or field, f"no {name} patch swings in the film's first "
                      f"{stamps[-1] - stamps[0]:.1f} s" + ("" if roi is None else
                                                          " inside the region given"),
                      "name the marker's colour as the film shows it ("
                      + ", ".join(COLOURS) + "), or say where it is: roi = [x, y, w, h] in "
                      "pixels of the first frame",
                      (f"за первые {stamps[-1] - stamps[0]:.1f} с видео не качается ни одна "
                       f"{name_ru} метка" + ("" if roi is None else
                                            " внутри заданной области"),
                       "укажите цвет метки, как он виден на видео (" + ", ".join(COLOURS)
                       + "), или где она: roi = [x, y, w, h] в пикселях первого кадра"))
    if marker is None and roi is not None:
        x, y, w, h = (round(v) for v in roi)
        raise _refuse(path, roi_field or field, "nothing swings inside the region "
                      f"[{x}, {y}, {w}, {h}] in the film's first {stamps[-1] - stamps[0]:.1f} s",
                      "give the rectangle the marker swings through in the first frame, in "
                      "the film's pixels (x, y from the top left corner)",
                      (f"в области [{x}, {y}, {w}, {h}] за первые {stamps[-1] - stamps[0]:.1f} с "
                       "видео ничего не качается", "задайте прямоугольник, по которому метка "
                       "качается на первом кадре, в пикселях видео (x, y от левого верхнего "
                       "угла)"))
    if marker is None:
        raise _refuse(path, field, "nothing moves periodically in the film's first "
                      f"{stamps[-1] - stamps[0]:.1f} s (no patch swings there, a hand or a "
                      "flicker aside)", "start filming while the part swings, with a "
                      "high-contrast marker on it in view",
                      (f"за первые {stamps[-1] - stamps[0]:.1f} с видео ничего не качается "
                       "(рука или мерцание не в счёт)", "начните съёмку, когда деталь уже "
                       "качается, с контрастной меткой на ней в кадре"))
    templates = [t.astype(np.uint8) if t is not None else None for t in
                 turned(kept[marker.reference], marker.x, marker.y, marker.side, TURNS)]
    del kept
    if templates[UPRIGHT] is None:
        raise _refuse(path, field, "the marker is at the frame's edge",
                      "frame the swing so that the marker stays inside the picture",
                      ("метка у края кадра", "снимайте качания так, чтобы метка не выходила "
                       "из кадра"))
    side = marker.side
    near, far = side // 2 + 2, int(SEARCH * side)
    xs, ys, conf, times = [], [], [], []
    if marker.start is not None:
        px, py = marker.start
    else:
        px, py = marker.x, marker.y
    vx = vy = 0.0
    lost = 0 if marker.start is not None else LOST_FRAMES
    turn = UPRIGHT
    every = range(len(TURNS))
    snapshots = []
    shown = set(np.linspace(0, film.frame_count - 1, keep_frames).astype(int).tolist()) \
        if film.frame_count and keep_frames else set()
    for index, (grey, stamp) in enumerate(frames(film, field)):
        boxes = [_around(px + vx, py + vy, near, side), _around(px, py, far, side)]
        if lost >= LOST_FRAMES:
            boxes.append(marker.region)
        x = y = math.nan
        c = 0.0
        for box in boxes:
            tried = sorted({UPRIGHT, turn, max(turn - 1, 0), min(turn + 1, len(TURNS) - 1)}) \
                if box is boxes[0] else every
            found = _match(grey, templates, box, tried)
            c = max(c, found[2] if found is not None else 0.0)
            least = min_confidence if box is not marker.region else \
                max(min_confidence, REACQUIRE)
            if found is not None and found[2] >= least:
                refined = _refine(grey, templates[found[3]], found[0], found[1])
                if refined is not None:
                    x, y = refined
                    turn = found[3]
                    vx, vy = (x - px, y - py) if lost == 0 else (0.0, 0.0)
                    px, py = x, y
                break
        lost = 0 if math.isfinite(x) else lost + 1
        if lost:
            vx = vy = 0.0
        xs.append(x)
        ys.append(y)
        conf.append(c)
        times.append(stamp)
        if index in shown:
            snapshots.append((index, grey.copy()))
    time, dropped = frame_clock(film, times, field)
    steps = np.diff(time)
    typical = typical_interval(time)
    spread = interval_spread(steps[steps < DROPPED * typical], typical, film.tick)
    track = Track(str(path), time, np.asarray(xs), np.asarray(ys), np.asarray(conf), side,
                  spread, snapshots, 1.0 / scale, dropped, film.timed, marker.frequency)
    if track.kept.mean() < 0.5:
        at = roi_field or "roi"
        raise _refuse(path, field, f"the marker was found in {100 * track.kept.mean():.0f} % "
                      "of the frames", "stick a high-contrast marker on the part, light it "
                      "evenly and keep it in view, or say where it is in the first frame: "
                      f"{at} = [x, y, w, h] in pixels",
                      (f"метка найдена на {100 * track.kept.mean():.0f} % кадров",
                       "наклейте на деталь контрастную метку, осветите её ровно и держите в "
                       f"кадре или укажите, где она на первом кадре: {at} = [x, y, w, h] в "
                       "пикселях"))
    return track


def _check_roi(path, roi, size: tuple[int, int], roi_field: str | None) -> None:
    """Refuse a region that does not lie inside the film's frame."""
    x, y, w, h = roi
    W, H = size
    if x + w > W or y + h > H:
        shown = ", ".join(f"{v:g}" for v in roi)
        raise _refuse(path, roi_field, f"the region [{shown}] reaches beyond the film's "
                      f"{W} × {H} px frame", f"give x + w ≤ {W} and y + h ≤ {H}: the marker's "
                      "place in the first frame at the film's own size (not a screenshot's)",
                      (f"область [{shown}] выходит за кадр видео {W} × {H} пикс",
                       f"задайте x + w ≤ {W} и y + h ≤ {H}: место метки на первом кадре в "
                       "размере самого видео (не снимка экрана)"))


def swing_of(track: Track, *, field: str | None = None) -> Swing:
    """Fit the track's oscillation (see the module's notes).

    The fit is robust to false matches the path test let through: frames whose residual
    from the fit lies beyond :data:`OUTLIER` are left out and the fit repeated
    (:func:`_consistent`); the period's u is the fit's over the frames kept.

    Raises
    ------
    InputError
        No swing above the track's noise; fewer than :data:`MIN_OSCILLATIONS` oscillations;
        a frame rate below twice the oscillation's frequency (the swing cannot be told from
        its alias); a track at another frequency than the swing the survey saw (a point
        moving at a harmonic of it); a period whose u the film cannot give.
    """
    t, s = track.displacement()
    rho = track.radial()
    shape = track.radial_shape()
    try:
        fit, drifting = _fitted(t, s)
        drops, doubt, reach = [], None, None
        if _evenly_stamped(track) and (t[-1] - t[0]) / fit.period >= DROP_OSCILLATIONS:
            interval = typical_interval(track.time)
            keep = _consistent(s - drifting.predict(t))
            with scope():           # the scan with no drop retimed is met twice or more
                if _drop_power(t[keep], s[keep], interval) >= DROP_DETECTABLE:
                    drops = _find_drops(t[keep], s[keep], interval)
                    doubt = _doubt(t, s, keep, interval, drops)
                reach = _drop_reach(t[keep], s[keep], interval, drops)
            if drops:
                t = _shifted(t, drops, interval)
                fit, drifting = _fitted(t, s)
        for _ in range(REFITS):
            keep = _consistent(s - drifting.predict(t))
            if keep.all():
                break
            t, s, rho = t[keep], s[keep], rho[keep]
            shape = None if shape is None else shape[keep]
            fit, drifting = _fitted(t, s)
    except RuntimeError as exc:
        raise _refuse(track.path, field, f"no oscillation fits the track ({exc})",
                      "film the part swinging freely, the marker in view",
                      (f"траектория метки не описывается колебаниями (подбор: '{exc}')",
                       "снимите свободно качающуюся деталь, метка в кадре")) from None
    if drops:
        _warn_unstamped_drops(track, sum(m for _, m in drops), doubt)
    if not abs(fit.amplitude) > SWING_SNR * fit.residual_sd:
        raise _refuse(track.path, field, f"no swing stands out of the track's noise (amplitude "
                      f"{abs(fit.amplitude):.2g} px, noise {fit.residual_sd:.2g} px)",
                      "film the part while it swings, the marker large and sharp in the frame",
                      (f"качания не выделяются из шума траектории (амплитуда "
                       f"{abs(fit.amplitude):.2g} пикс, шум {fit.residual_sd:.2g} пикс)",
                       "снимайте деталь, пока она качается, метка в кадре крупная и резкая"))
    rate = track.frame_rate
    if fit.omega_d / (2 * math.pi) > NYQUIST_SHARE * rate / 2:
        raise _refuse(track.path, field, f"the film's {rate:.3g} frames per second barely "
                      f"follow a swing of {fit.omega_d / (2 * math.pi):.3g} Hz (the swing may "
                      "be an alias of a faster one)", "film at 30 frames per second or more",
                      (f"частота съёмки {rate:.3g} кадр/с едва успевает за качаниями "
                       f"{fit.omega_d / (2 * math.pi):.3g} Гц (это может быть отражение "
                       "более быстрых качаний)", "снимайте с частотой 30 кадров в секунду "
                       "или больше"))
    seen = track.frequency * fit.period
    if math.isfinite(seen) and abs(seen - 1) > SURVEY_AGREES:
        raise _refuse(track.path, field, f"the track swings at {1 / fit.period:.3g} Hz where the "
                      f"film's first seconds swing at {track.frequency:.3g} Hz (the point "
                      "followed moves at a harmonic of the swing, or not with it)",
                      "say where the marker is in the first frame: roi = [x, y, w, h] in "
                      "pixels",
                      (f"траектория колеблется с частотой {1 / fit.period:.3g} Гц, а первые "
                       f"секунды видео — с {track.frequency:.3g} Гц (прослежена точка, "
                       "движущаяся с гармоникой качаний или не с ними)",
                       "укажите, где метка на первом кадре: roi = [x, y, w, h] в пикселях"))
    span = (t[-1] - t[0]) / fit.period
    if span < MIN_OSCILLATIONS:
        raise _refuse(track.path, field, f"the film spans {span:.1f} oscillations",
                      f"film at least {MIN_OSCILLATIONS} oscillations (the manual times 20; "
                      f"{MIN_OSCILLATIONS * fit.period:.1f} s of this swing)",
                      (f"видео охватывает {span:.1f} колебания",
                       f"снимите не меньше {MIN_OSCILLATIONS} колебаний (по методичке — 20; "
                       f"{MIN_OSCILLATIONS * fit.period:.1f} с этих качаний)"))
    period = period_of(drifting, t, s, rho, shape)
    if doubt is not None:
        period = replace(period, limit=doubt[1] * period.value)
    if not (math.isfinite(period.u) and period.u > 0 and math.isfinite(period.dof)):
        raise _refuse(track.path, field, f"the period's uncertainty cannot be told from the "
                      f"{span:.1f} oscillations the film holds", f"film {FEW_OSCILLATIONS} "
                      "oscillations or more (the manual times 20)",
                      (f"погрешность периода не определить по {span:.1f} колебаниям на видео",
                       f"снимите {FEW_OSCILLATIONS} колебаний или больше (по методичке — 20)"))
    if reach is not None:
        _warn_hidden_drops(track, t, s, drifting, period, interval, reach)
    return Swing(drifting, period, float(span), float(drifting.amplitude),
                 t.size / track.time.size, float(drifting.reference_amplitude))


def _evenly_stamped(track: Track) -> bool:
    """Whether the film's times are those of a constant rate without a gap (a container
    that claims a constant rate, or an AVI's nominal one): where a frame dropped by the
    camera leaves no trace in them."""
    return track.dropped == 0 and track.interval_spread <= IRREGULAR and track.time.size > 8


def _fitted(t: np.ndarray, s: np.ndarray) -> tuple:
    """The damped sinusoid on a line and, from it, the fit whose frequency follows the
    amplitude (:func:`processing.oscillations.anharmonic.fit_anharmonic_decay`)."""
    fit = fit_damped_sine(t, s, baseline_order=1)
    return fit, fit_anharmonic_decay(t, s, fit)


def _shifted(t: np.ndarray, drops, interval: float) -> np.ndarray:
    """The times with ``m`` frame intervals added from each dropped frame's time on."""
    out = np.array(t, float)
    for at, m in drops:
        out[np.asarray(t) >= at] += m * interval
    return out


def _find_drops(t: np.ndarray, s: np.ndarray, interval: float) -> list[tuple[float, int]]:
    """Frames dropped where the film's times claim a constant rate, from the swing's timing.

    After a dropped frame every later frame was taken an interval later than its time says,
    so the track runs ahead of the fitted swing by its velocity times that interval: a step
    in the swing's timing (:func:`_timing_steps`). The step that explains the track best as
    a whole number m ≥ 1 of intervals is taken while it stands :data:`DROP_SIGMAS` standard
    errors out; the frames after it are retimed and the search repeated (at most
    :data:`MAX_DROPS` times). Each step taken is then judged again with the others in place
    and with the noise of the track so retimed (the steps not yet found inflate it, and
    bias a step's size while a neighbour is missing): it must still stand out and lie within
    :data:`DROP_WHOLE` (or three standard errors) of a whole number of intervals, which it
    then takes. The first that does not is given up and the rest judged again. A step is
    never taken while it stands out less than the scan's most negative one (the film's own
    noise: no dropped frame steps the timing back; a clean film's jolt stood 5.2 standard
    errors out one way and 5.7 the other), and it is judged again only if the frames away
    from its edge are late as a dropped frame makes them (:func:`_lasting`).

    Returns
    -------
    list of (float, int)
        The time of each dropped frame's successor (by the film's times) and the intervals
        its frames are late. [s]
    """
    drops: list[tuple[float, int]] = []
    for _ in range(MAX_DROPS):
        found = _largest_step(t, s, interval, drops)
        if found is None:
            break
        drops.append(found)
    while drops:
        judged = [_largest_step(t, s, interval, drops[:j] + drops[j + 1:], at=at)
                  for j, (at, _) in enumerate(drops)]
        failed = [j for j, step in enumerate(judged) if step is None]
        if not failed:
            return judged
        del drops[failed[0]]
    return drops


def _largest_step(t, s, interval: float, drops, at: float | None = None):
    """The step of the swing's timing, with ``drops`` already retimed, that explains the
    track best as whole intervals (or the one at the frame of time ``at``), as (time, m),
    or None where it does not pass (:func:`_find_drops`)."""
    step, root, valid, floor = _steps(t, s, interval, drops)
    if not valid.any():
        return None
    k = int(np.argmax(_gain(step, root, valid, interval))) if at is None \
        else int(np.argmin(np.abs(t - at)))
    m = max(int(round(step[k] / interval)), 1)
    whole = abs(step[k] - m * interval) <= max(DROP_WHOLE * interval, 3.0 / root[k])
    if not valid[k] or step[k] * root[k] < max(scanned(DROP_SIGMAS, t.size), floor) \
            or (at is not None and not (whole and _lasting(t, s, interval, drops, k, m))):
        return None
    return float(t[k]), m


def _lasting(t, s, interval: float, drops, k: int, m: int) -> bool:
    """Whether the frames from ``k`` on, judged away from the step's edge
    (:func:`_late_beyond`), are late as ``m`` dropped intervals make them: not both nearer
    on time than ``m`` intervals late and :data:`DROP_PERSISTS` standard errors short of
    them."""
    late, se = _late_beyond(t, s, interval, drops, k)
    return late >= 0.5 * m * interval or late >= m * interval - DROP_PERSISTS * se


def _further_drops(t, s, interval: float, drops) -> list[tuple[float, int]]:
    """Steps beyond ``drops`` that may be dropped frames too faint to be sure of, as (time,
    m): the one that explains the track best as whole intervals among those nearer one
    interval than none (in a film known to drop frames, ``drops`` found, however faint),
    then, each with those before it retimed, such steps standing :data:`DOUBT_SIGMAS`
    standard errors out, at most :data:`DOUBT_STEPS` in all. The period's u carries them
    (:func:`_doubt`)."""
    further: list[tuple[float, int]] = []
    for _ in range(DOUBT_STEPS):
        step, root, valid, _ = _steps(t, s, interval, drops + further)
        valid &= step >= 0.5 * interval
        if further or not drops:
            valid &= step * root >= scanned(DOUBT_SIGMAS, t.size)
        if not valid.any():
            break
        k = int(np.argmax(_gain(step, root, valid, interval)))
        further.append((float(t[k]), max(int(round(step[k] / interval)), 1)))
    return further


def _doubt(t, s, keep, interval: float, drops):
    """The time of the first further step too faint to be sure of (:func:`_further_drops`,
    sought over the frames ``keep``) and the period's relative shift were they all dropped
    frames too (one bound of a rectangular distribution about the period without them),
    or None."""
    further = _further_drops(t[keep], s[keep], interval, drops)
    if not further:
        return None
    try:
        periods = [_fitted(_shifted(t, more, interval), s)[1].period
                   for more in (drops, drops + further)]
    except RuntimeError:
        return None
    return further[0][0], abs(periods[1] / periods[0] - 1)


def scanned(sigmas: float, frames: int) -> float:
    """The standard errors a step found by a scan of ``frames`` frames must stand out by to
    be as sure as one standing ``sigmas`` out on :data:`SCAN_FRAMES`: the same chance that
    the noise alone puts one of them there, z with n·Q(z) = n₀·Q(``sigmas``), Q the normal
    tail (4.5 on 300 frames is 4.9 on 2400)."""
    return float(stats.norm.isf(SCAN_FRAMES * stats.norm.sf(sigmas) / max(frames, 1)))


def _drop_power(t, s, interval: float) -> float:
    """Standard errors a single dropped frame's step would stand out by at the film's median
    frame (:func:`_timing_steps`; 0 where no step can be told): dropped frames are sought
    where it reaches :data:`DROP_DETECTABLE`, and found surely where it reaches
    :func:`scanned` of :data:`DROP_SIGMAS` (a step's own power follows the swing's speed at
    its frame, so some stand above the median and some below)."""
    _, z, _ = _drop_reach(t, s, interval, [])
    return float(np.median(z)) if z.size else 0.0


def _drop_reach(t, s, interval: float, drops) -> tuple[np.ndarray, np.ndarray, float]:
    """Where a single dropped frame's step can be told (:func:`_steps`, the ``drops`` found
    retimed: untimed, their steps raise the noise a further one is weighed against, and 8
    of the 15 films at 30/60 fps whose drops were found, seeds 4200–4219, were warned by
    :func:`_warn_hidden_drops` that one could hide; so retimed, none): those
    frames' times, the standard errors a step of one interval would stand out by at each,
    and the standard errors the search needs to take one on this many frames
    (:func:`scanned` of :data:`DROP_SIGMAS`). [s], [-], [-]"""
    _, root, valid, _ = _steps(t, s, interval, drops)
    return t[valid], root[valid] * interval, scanned(DROP_SIGMAS, t.size)


@by_content()
def _steps(t, s, interval: float, drops):
    """:func:`_timing_steps` of the track with ``drops`` retimed, and where a step can be
    told: a quarter swing or more from either end of the film (a step within a few frames
    of an end rests on those few, and the fit's phase and the camera's shake bend them
    alike: on a clean film a step four frames from its end stood 4.7 standard errors
    out). Inside a :func:`~processing.inputs.reuse.scope`, made once for the same track and
    drops (:func:`_drop_power`, :func:`_find_drops` and :func:`_further_drops` each scan the
    track with none retimed first)."""
    timing = _timing_of(t, s, interval, drops)
    if timing is None:                     # so retimed, no swing fits: no step to tell
        return np.zeros_like(t), np.zeros_like(t), np.zeros(t.size, bool), 0.0
    retimed, period, model = timing
    step, root = _timing_steps(*model)
    valid = np.isfinite(step * root)
    valid &= (retimed - retimed[0] >= 0.25 * period) & (retimed[-1] - retimed >= 0.25 * period)
    z = np.where(valid, step * root, 0.0)
    floor = -float(z.min())
    frames, back, share = DROP_TRANSIENT
    valid &= minimum_filter1d(z, 2 * frames + 1, mode="nearest") >= -np.maximum(back,
                                                                                 share * z)
    return step, root, valid, floor


def _gain(step, root, valid, interval: float) -> np.ndarray:
    """How much a step of the nearest whole number m ≥ 1 of intervals lowers the track's
    weighted squared residual at each frame, root²·mI·(2δ − mI) (−∞ where no step can be
    told)."""
    whole = np.clip(np.round(np.where(valid, step, 0.0) / interval), 1, None) * interval
    return np.where(valid, root ** 2 * whole * (2 * np.where(valid, step, 0.0) - whole),
                    -np.inf)


def _timing_steps(v, B, r, inverse, length: int) -> tuple[np.ndarray, np.ndarray]:
    r"""A step of the swing's timing at each frame: its size and its inverse standard error,
    from the track's :func:`_timing_model`.

    A step δ at frame d makes the residual from the fit r ≈ δ·g_d, g_d = v·H(k − d) with v
    the fitted swing's velocity and H the unit step. Its generalised least-squares estimate,
    the fit's own freedoms (amplitude, its decay, phase, frequency, its drift, the baseline:
    the columns B = swing·τʲ, v·τʲ, j ≤ 2, and 1, τ) taken out,

    .. math:: \hat δ_d = \frac{g_d^T C^{-1} r - g_d^T C^{-1} B M^{-1} B^T C^{-1} r}
              {g_d^T C^{-1} g_d - g_d^T C^{-1} B M^{-1} B^T C^{-1} g_d},\qquad
              M = B^T C^{-1} B,

    has the variance 1/denominator; every sum over g_d is a suffix sum over the frames, so
    all frames are scanned at once. C is the noise's covariance, stationary: its spectrum
    the residual's periodogram averaged over :data:`DROP_SMOOTH` spacings each side, the
    bins the fit empties (within :data:`NOTCH` of the swing's frequency and of zero) filled
    from beside them. A phone's shake puts most of the track's noise below and about the
    swing's frequency, where a step's long reach lies; weighed by that spectrum, the step's
    sharp edge at d (the swing's way over one interval) counts for what the white noise
    above leaves it.

    References
    ----------
    .. [1] P. Whittle, "Estimation and information in stationary time series", Arkiv för
           Matematik 2, 1953, 423–434 (a stationary series' likelihood by its spectrum: the
           circulant approximation of its covariance).
    """
    n = r.size
    filtered = _weighed(np.column_stack([r, B]), inverse, length)
    Cr, CB = filtered[:, 0], filtered[:, 1:]
    M_inv = np.linalg.pinv(B.T @ CB)
    c = np.fft.irfft(inverse, length)
    reach = np.fft.irfft(np.fft.rfft(v, length) * np.conj(np.fft.rfft(c[:n], length)),
                         length)[:n] - v * c[0]
    gCg = _suffix(v * v * c[0] + 2 * v * reach)
    gCB = _suffix(CB * v[:, None])
    numerator = _suffix(v * Cr) - gCB @ (M_inv @ (B.T @ Cr))
    denominator = gCg - np.einsum("ij,jk,ik->i", gCB, M_inv, gCB)
    denominator[~(denominator > 1e-12 * np.max(denominator))] = np.nan
    return numerator / denominator, np.sqrt(denominator)


@by_content(shared=True)
def _timing_of(t, s, interval: float, drops):
    """The track with ``drops`` retimed, its fitted swing's period and what a step of its
    timing is judged with (:func:`_timing_model`), or None where no swing fits it so
    retimed. Inside a :func:`~processing.inputs.reuse.scope`, made once for the same track
    and drops: :func:`_steps` and :func:`_late_beyond` judge the same retimed track (a step
    taken is then judged for lasting). Shared: no caller changes it."""
    retimed = _shifted(t, drops, interval)
    try:
        fit, drifting = _fitted(retimed, s)
    except RuntimeError:
        return None
    return retimed, drifting.period, _timing_model(retimed, s, fit, drifting, interval)


def _timing_model(t, s, fit, drifting, interval: float):
    """What a step of the swing's timing is judged with (:func:`_timing_steps`): the fitted
    swing's velocity v, the fit's own freedoms B, the residual r with them taken out, the
    noise's 1/S (:func:`_inverse_spectrum`) and its padded length."""
    h = 0.25 * interval
    model = drifting.predict(t)
    v = (drifting.predict(t + h) - drifting.predict(t - h)) / (2 * h)
    swing = model - fit.baseline_at(t)
    tau = 2 * (t - t[0]) / (t[-1] - t[0]) - 1
    B = np.column_stack([f * tau ** j for f in (swing, v) for j in range(3)] + [np.ones_like(t),
                                                                                 tau])
    q, _ = np.linalg.qr(B)
    r = s - model
    r = r - q @ (q.T @ r)
    inverse, length = _inverse_spectrum(r, interval / drifting.period)
    return v, B, r, inverse, length


def _weighed(a: np.ndarray, inverse: np.ndarray, length: int) -> np.ndarray:
    """C⁻¹a, each column of ``a`` weighed by the noise's 1/S (the circulant approximation of
    :func:`_timing_steps`)."""
    return np.fft.irfft(np.fft.rfft(a, length, axis=0) * inverse[:, None], length,
                        axis=0)[:a.shape[0]]


def _late_beyond(t, s, interval: float, drops, k: int) -> tuple[float, float]:
    r"""How late the frames are from frame ``k`` on, with ``drops`` retimed, judged away from
    the step's edge: the step δ of :func:`_timing_steps` at ``k``, with each frame within
    :data:`DROP_TRANSIENT`'s frames of the edge (k − w … k + w − 1) given its own freedom
    (an indicator column E beside the fit's B), so that only the frames beyond them tell it:

    .. math:: \hat δ = [(X^T C^{-1} X)^{-1} X^T C^{-1} r]_0,\qquad X = [g_k, B, E].

    A dropped frame makes every later frame late by its intervals; a few frames matched off
    and back make an edge but no lasting lateness (:data:`DROP_PERSISTS`). [s]"""
    timing = _timing_of(t, s, interval, drops)
    if timing is None:
        return 0.0, math.inf
    v, B, r, inverse, length = timing[2]
    n = t.size
    frames = DROP_TRANSIENT[0]
    edge = np.arange(max(k - frames, 0), min(k + frames, n))
    E = np.zeros((n, edge.size))
    E[edge, np.arange(edge.size)] = 1.0
    X = np.column_stack([v * (np.arange(n) >= k), B, E])
    CX = _weighed(X, inverse, length)
    M_inv = np.linalg.pinv(X.T @ CX)
    return float((M_inv @ (CX.T @ r))[0]), float(math.sqrt(max(M_inv[0, 0], 0.0)))


def _suffix(a: np.ndarray) -> np.ndarray:
    """Sums from each row to the last."""
    return np.cumsum(a[::-1], axis=0)[::-1]


def _inverse_spectrum(r: np.ndarray, f0: float) -> tuple[np.ndarray, int]:
    """1/S of the residual's noise on a grid padded to twice its frames (a variance per frame,
    σ² for white noise; see :func:`_timing_steps`) and the padded length. ``f0`` is the
    swing's frequency in cycles per frame."""
    n = r.size
    length = 2 * n
    power = np.abs(np.fft.rfft(r, length)) ** 2 / n
    bins = np.arange(power.size)
    width = NOTCH * length / n
    emptied = (np.abs(bins - f0 * length) <= width) | (bins <= width)
    kept = np.flatnonzero(~emptied)
    for b in np.flatnonzero(emptied):
        side = np.searchsorted(kept, b)
        power[b] = max(power[kept[max(side - 1, 0)]], power[kept[min(side, kept.size - 1)]])
    half = int(DROP_SMOOTH * length / n)
    kernel = np.ones(2 * half + 1) / (2 * half + 1)
    spectrum = np.convolve(np.pad(power, half, mode="reflect"), kernel, "valid")
    return 1.0 / spectrum, length


def _warn_unstamped_drops(track: Track, drops: int, doubt=None) -> None:
    """Warn of frames dropped under constant-rate times, found from the swing's timing;
    ``doubt``, the time of a further step too faint to be sure of and the period's relative
    shift were it a dropped frame too (:func:`_further_drops`)."""
    name = Path(track.path).name
    more_en = more_ru = ""
    if doubt is not None:
        at, share = doubt[0], 100 * doubt[1]
        more_en = (f"; the swing's timing steps less surely at {at:.2f} s, where one more may "
                   f"have been dropped: the period's u carries it (±{share:.2g} %)")
        more_ru = (f"; менее уверенный скачок фазы качаний на {at:.2f} с, где мог пропасть ещё "
                   f"один кадр, учтён в погрешности периода (±{share:.2g} %)")
    warnings.warn(DroppedFramesWarning(
        f"{name}: {drops} frame(s) dropped by the camera where the film's times claim a "
        "constant rate (the swing's phase jumps by a whole frame interval there): the frames "
        f"after each are timed that much later, as they were taken{more_en}; film as the "
        "phone records (each frame's own time) and close other apps",
        f"{name}: камера пропустила кадров: {drops}, а время кадров в файле — с постоянной "
        "частотой (фаза качаний скачет там на целый интервал между кадрами): кадры после "
        "каждого пропуска отнесены на столько же позже, как они и сняты"
        f"{more_ru}; снимайте в "
        "исходном формате телефона (со временем каждого кадра) и закройте другие "
        "приложения"))


def _drop_cost(t: np.ndarray, s: np.ndarray, drifting, interval: float) -> float:
    """The period's relative shift were a single frame dropped mid-film and not found: the
    fit through the frames from the film's middle on timed an interval later. (White noise
    aside, a step of δ at a of a film of length D moves the fitted frequency by
    6a(D − a)δ/D³ of it, most at a = D/2: 1.5 δ/D.) NaN where that fit fails."""
    middle = 0.5 * float(t[0] + t[-1])
    try:
        moved = _fitted(_shifted(t, [(middle, 1)], interval), s)[1]
    except RuntimeError:
        return math.nan
    return abs(moved.period / drifting.period - 1)


def _hidden_share(t, s, drifting, period: Measured, interval: float, reach) -> tuple:
    """The share of the frames where a single dropped frame would both go unseen and move
    the period by more than its u (:data:`HIDDEN_SHARE`), and the shift one would make
    mid-film (:func:`_drop_cost`; elsewhere that times 4a(D − a)/D², the white-noise
    sketch's shape; 0 where a drop would be seen at every frame, and then not refitted).
    ``reach`` is :func:`_drop_reach` of the film's scan."""
    at, z, needed = reach
    unseen = z < needed
    if not unseen.any():
        return 0.0, 0.0
    cost = _drop_cost(t, s, drifting, interval)
    if not math.isfinite(cost):
        return 0.0, cost
    span = float(at[-1] - at[0]) if at.size > 1 else 1.0
    shape = 4 * (at - at[0]) * (at[-1] - at) / span ** 2
    return float(np.mean(unseen & (cost * shape * period.value > period.u))), cost


def _warn_hidden_drops(track: Track, t, s, drifting, period: Measured, interval: float,
                       reach) -> None:
    """Warn where a film whose times claim a constant rate cannot show the dropped frames
    that would move its period: at more than :data:`HIDDEN_SHARE` of its frames a single
    one's step would stand under what the search needs and move the period by more than
    its u (:func:`_hidden_share`). The warning says what a drop would cost, not that one
    happened."""
    share, cost = _hidden_share(t, s, drifting, period, interval, reach)
    if not share > HIDDEN_SHARE:
        return
    name = Path(track.path).name
    _, z, needed = reach
    stands = float(np.median(z))
    U = coverage_factor(period.dof) * period.u
    moved, times = 100 * cost, cost * period.value / U
    warnings.warn(HiddenDropsWarning(
        f"{name}: the film's times claim a constant rate, so a frame dropped by the camera "
        "would leave no gap in them, and the swing could not show one either: at "
        f"{100 * share:.0f} % of its frames a dropped frame's step in the swing's phase would "
        f"stand under the {needed:.1f} standard errors the search needs ({stands:.1f} at the "
        f"median frame) and move the period by more than its u; one dropped mid-film would "
        f"move it {moved:.2g} % ({times:.1f} U). This does not say that a frame was dropped. "
        "To be sure none was, give the phone's original file (it keeps each frame's time), "
        "not a re-encoded copy; or swing wider, film more oscillations, or film a slow swing "
        "at a lower frame rate",
        f"{name}: время кадров в файле — с постоянной частотой, так что пропущенный камерой "
        "кадр не оставил бы в нём промежутка, и качания его тоже не показали бы: на "
        f"{100 * share:.0f} % кадров скачок фазы качаний от пропуска был бы меньше "
        f"{needed:.1f} стандартных ошибки, нужных поиску ({stands:.1f} на медианном кадре), и "
        f"сдвинул бы период больше его u; один пропуск в середине видео сдвинул бы его на "
        f"{moved:.2g} % ({times:.1f} U). Это не значит, что кадр пропал. Чтобы быть уверенным, "
        "что пропусков нет, дайте исходный файл телефона (в нём хранится время каждого "
        "кадра), а не перекодированную копию; или раскачайте шире, снимите больше колебаний, "
        "снимайте медленные качания с меньшей частотой кадров"))


def _consistent(r: np.ndarray) -> np.ndarray:
    """The frames whose residual from the fit lies within :data:`OUTLIER` robust σ
    (1.4826 × the median absolute deviation) of the median, or within its floor in px: a
    false match (a hand's knuckle, a shadow taken for the marker) that the path test let
    through, left out rather than let pull the least squares."""
    sigmas, floor = OUTLIER
    centre = float(np.median(r))
    spread = 1.4826 * float(np.median(np.abs(r - centre)))
    return np.abs(r - centre) <= max(sigmas * spread, floor)


def _density_near(t: np.ndarray, r: np.ndarray, f0: float) -> tuple[float, int]:
    """The residual's spectral density about the swing's frequency, as a variance per frame
    (σ² for white noise), and the number of frequencies it is the mean of.

    Periodogram |Σ r e^{−2πift}|²/n at each frequency 1/duration apart in f₀/2 … 3f₀/2 (the
    frames' own times, so a variable frame rate is no matter), less those within
    :data:`NOTCH` spacings of f₀ that the fit itself empties; where that leaves none (a film
    of under five oscillations), the band reaches :data:`NOTCH_BEYOND` spacings past the
    notch instead."""
    duration = float(t[-1] - t[0])
    for half in (0.5 * f0 * duration, NOTCH + NOTCH_BEYOND):
        f = f0 + np.arange(-half, half + 1) / duration
        f = f[(np.abs(f - f0) * duration > NOTCH) & (f > 0)]
        if f.size:
            break
    power = np.abs(_waves(f, t) @ r) ** 2 / r.size
    return float(power.mean()), int(f.size)


def _waves(f: np.ndarray, t: np.ndarray) -> np.ndarray:
    """e^{−2πif(t − t₀)} of each frequency ``f`` (rows) at the frames' own times ``t``
    (columns): a row times a series is its discrete Fourier transform at that frequency,
    whatever the frame rate's steps. [1]"""
    return np.exp(-2j * np.pi * np.outer(f, t - t[0]))


def _density_at(t: np.ndarray, r: np.ndarray, f0: float,
                basis: np.ndarray | None = None) -> tuple[float, float]:
    r"""A series' spectral density at f₀ (as :func:`_density_near`: a variance per frame),
    from the periodogram at the frequencies 1/duration apart within :data:`NOTCH` spacings
    of it, and the number of frequencies' worth it rests on.

    Where ``basis``' columns were taken out of the series by least squares, each
    frequency's periodogram holds only the share of the noise they leave it: with Q an
    orthonormal basis of the columns and e_f the frequency's exponential,
    E P_f = S·w_f, w_f = 1 − |Qᴴe_f|²/n; the density is ΣP_f/Σw_f, the mean of Σw_f
    frequencies (a column that swings at f₀ — the path's θ and θ³ on the radial residual —
    takes out about one frequency's worth of its 2 degrees of freedom there: the mean alone
    would be 20 % low on five frequencies)."""
    duration = float(t[-1] - t[0])
    f = f0 + np.arange(-math.floor(NOTCH), math.floor(NOTCH) + 1) / duration
    f = f[f > 0]
    waves = _waves(f, t)
    power = np.abs(waves @ r) ** 2 / r.size
    left = np.ones(f.size)
    if basis is not None:
        q, _ = np.linalg.qr(basis)
        left = np.clip(1 - np.sum(np.abs(waves @ q) ** 2, axis=1) / r.size, 0.0, 1.0)
    return float(power.sum() / left.sum()), float(left.sum())


def period_of(fit: AnharmonicFit, t: np.ndarray, s: np.ndarray,
              radial: np.ndarray | None = None,
              radial_shape: np.ndarray | None = None) -> Measured:
    """T = 2π/ω̄ of a track's fit, with its u.

    Type A: the least-squares covariance (JᵀJ)⁻¹ scaled by the residual's spectral density
    about the swing's frequency rather than by its variance (the frequency of a sinusoid in
    coloured noise is as uncertain as the noise's density at that frequency: Whittle P.,
    "The simultaneous estimation of a time series' harmonic components and covariance
    structure", Trabajos de Estadística 3, 1952) — the codec's noise, carried from frame
    to frame, and the tracker's errors at the swing's harmonics weigh each as much as they
    move ω_d; ν = 2 per frequency averaged. The fit's frequency also leaks noise from the
    frequencies well below the swing's (a slow wander over the film's length): where that
    noise weighed by its own power (:func:`_spread`) gives the larger variance, it is the
    u (the density about the swing stays its floor: off the swing a white track's
    periodogram scatters below it as often as above). Type B: the tracker's error that is a function
    of the marker's place (:data:`LOCKING` px) repeats every swing, so it does not average
    out; slowly shifted by the decay, it moves the phase by up to LOCKING/A over the film
    of N oscillations: u_B(T) = T·LOCKING/(2π A N).

    The density is the larger of the residual's outside the band the fit empties and the
    radial residual's (``radial``, :meth:`Track.radial`) within it (:func:`_density_at`):
    the camera's shake moves the marker across its arc as much as along it, and across
    the arc no fit of the swing empties its own frequency (the path's shape taken out there,
    ``radial_shape`` (:meth:`Track.radial_shape`), is allowed for). A phone's slow shake has most of its
    power below the swing's frequency; on a short film the residual's density is taken
    above it, where the shake has died out, and alone would miss it.
    """
    r = s - fit.predict(t)
    density, bins = _density_near(t, r, 1 / fit.period)
    if radial is not None and np.any(radial):
        across, crossing = _density_at(t, radial, 1 / fit.period, radial_shape)
        if across > density:
            density, bins = across, crossing
    i = fit.params.index("omega_d")
    variance, dof = density * fit.normal[i, i], 2 * bins
    leaked = _spread(fit.sensitivity("omega_d"), t, r, 1 / fit.period, density, dof)
    if leaked[0] > variance:
        variance, dof = leaked
    u_a = fit.period / fit.omega_d * math.sqrt(variance)
    oscillations = (t[-1] - t[0]) / fit.period
    u_b = fit.period * LOCKING / (2 * math.pi * abs(fit.amplitude) * oscillations)
    return Measured(fit.period, float(u_a), dof, u_b=float(u_b))


def _spread(gain: np.ndarray, t: np.ndarray, r: np.ndarray, f0: float, density: float,
            dof: float) -> tuple[float, float]:
    r"""The variance of a fitted parameter whose error is ``gain``·(the track's noise), and
    its effective degrees of freedom.

    In stationary noise of spectrum S the variance is Σ_f w_f S_f, w_f = 2|G_f|²/n the
    share of the gain's ‖G‖² at each frequency 1/duration apart (G_f = Σ g e^{−2πift},
    over the frames' own times; Whittle's approximation, as in :func:`_timing_steps`). Up
    to :data:`LEAK_BAND` times the swing's frequency, outside the :data:`NOTCH` the fit
    empties about it, S_f is the residual's own periodogram there; in the notch and beyond
    the band, the ``density`` about the swing's frequency (:func:`_density_near`, with its
    ``dof``): σ²‖G‖² for white noise, as the least squares state it. A slow wander (a
    phone's shake over the film's length) is weighed by its own power rather than the
    smaller one about the swing. ν is Welch–Satterthwaite's over the density's share and
    the periodogram's ordinates (2 each).
    """
    duration = float(t[-1] - t[0])
    k = np.arange(1, math.ceil(LEAK_BAND * f0 * duration) + 1)
    k = k[np.abs(k - f0 * duration) > NOTCH]
    waves = _waves(k / duration, t)
    weight = 2 * np.abs(waves @ gain) ** 2 / t.size
    own = weight * np.abs(waves @ r) ** 2 / t.size
    shared = max(float(gain @ gain - weight.sum()), 0.0) * density
    variance = shared + float(own.sum())
    spread = shared ** 2 / dof + float(np.sum(own ** 2)) / 2
    return variance, variance ** 2 / spread if spread > 0 else math.nan


def arc(track: Track) -> tuple[float, float, float]:
    """The circle the marker runs on: its centre and radius, by a geometric least-squares
    fit through the frames on the marker's path (:attr:`Track.on_path`; robust: soft-L1),
    started from the algebraic one on coordinates about their mean. [px]"""
    from scipy.optimize import least_squares

    k = track.on_path
    x0, y0 = float(np.mean(track.x[k])), float(np.mean(track.y[k]))
    x, y = track.x[k] - x0, track.y[k] - y0
    design = np.column_stack([x, y, np.ones_like(x)])
    c, *_ = np.linalg.lstsq(design, x**2 + y**2, rcond=None)
    start = [c[0] / 2, c[1] / 2, math.sqrt(c[2] + c[0] ** 2 / 4 + c[1] ** 2 / 4)]
    fit = least_squares(lambda p: np.hypot(x - p[0], y - p[1]) - p[2], start, loss="soft_l1",
                        f_scale=0.5)
    return float(fit.x[0] + x0), float(fit.x[1] + y0), float(abs(fit.x[2]))


def correlation_time(r: np.ndarray) -> float:
    """The integrated autocorrelation time of a series, 1 + 2Σρ_k summed over the lags
    until ρ first falls below zero (at most a tenth of the series): how many samples one
    independent sample's worth of error spans (1 for white noise; (1 + ρ)/(1 − ρ) for a
    first-order one; far more for a phone's slow shake, which moves the whole picture).

    References
    ----------
    .. [1] A. Sokal, "Monte Carlo methods in statistical mechanics", in Functional
           Integration, Springer, 1997, §3 (the integrated autocorrelation time).
    """
    r = np.asarray(r, float) - np.mean(r)
    n = r.size
    if n < 8 or not r @ r > 0:
        return 1.0
    spectrum = np.fft.rfft(r, 2 * n)
    acf = np.fft.irfft(spectrum * np.conj(spectrum))[:n] / (r @ r)
    lags = acf[1:max(n // 10, 2)]
    below = np.flatnonzero(lags < 0)
    used = lags[:below[0]] if below.size else lags
    return float(1 + 2 * used.sum())


ILL_POSED = 1e-10
"""Smallest ratio of the arc fit's Jacobian's singular values at which its radius is told
(:func:`arc_radius_u`); below it the radius's u is infinite."""


def arc_radius_u(track: Track) -> float:
    """Standard uncertainty of the arc's radius (:func:`arc`) from the track's scatter about
    it: s²(JᵀJ)⁻¹ of the geometric fit, s² widened by the residuals' integrated
    autocorrelation time (:func:`correlation_time`: a frame's error carried into the next,
    the phone's shake carried over many); (JᵀJ)⁻¹ from J's singular values, never negative,
    and infinite where the arc is too short and straight for its radius to be told
    (:data:`ILL_POSED`; JᵀJ inverted as it stood gave a negative variance on one such film,
    a 60 fps swing of 12 px). [px]"""
    k = track.on_path
    xc, yc, R = track.circle
    dx, dy = track.x[k] - xc, track.y[k] - yc
    d = np.hypot(dx, dy)
    r = d - R
    s2 = float(r @ r) / max(r.size - 3, 1) * correlation_time(r)
    J = np.column_stack([dx / d, dy / d, np.ones_like(d)])
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    if not sv[-1] > ILL_POSED * sv[0]:    # a short, nearly straight arc: no radius to tell
        return math.inf
    return float(math.sqrt(s2 * np.sum((vt[:, 2] / sv) ** 2)))


@dataclass(frozen=True)
class Filmed:
    """One film of a lab: where it was named, the track and the fitted swing."""

    field: str
    track: Track
    swing: Swing
    stopwatch: Measured | None = None
    """The stopwatch's time of the same oscillations, if the file gives it too."""

    @property
    def amplitude(self) -> float:
        """The swing's angle amplitude at the film's start, θ₀ = A/R: the way along the arc
        over the arc's radius. [rad]"""
        return abs(self.swing.amplitude) / self.track.circle[2]

    @property
    def period_amplitude(self) -> float:
        """The amplitude the film's period belongs to: the RMS of the swing's decaying
        amplitude over the film (:attr:`Swing.reference_amplitude`) over the arc's radius.
        A wide swing's period shortens as it decays; the film's mean period is the period
        of a swing of this amplitude (to first order in the period's dependence on the
        amplitude squared), which is what a finite-amplitude correction takes. [rad]"""
        return abs(self.swing.reference_amplitude) / self.track.circle[2]

    @property
    def period_amplitude_limit(self) -> float:
        """Limit of error of :attr:`period_amplitude`: :attr:`amplitude_limit` in the same
        proportion (both rest on the arc's radius). [rad]"""
        return self.amplitude_limit * abs(self.swing.reference_amplitude / self.swing.amplitude)

    @property
    def corrected_with(self) -> Measured:
        """The amplitude a finite-amplitude correction of the film's period takes:
        :attr:`period_amplitude` within :attr:`period_amplitude_limit`, a rectangle, where
        that stays above zero. An amplitude is not negative: where its limit reaches below
        zero (a swing of a few px whose arc hardly sags: 1.7° ± 7.8° against a true 6.4° on
        a 320 × 180 film from the side), all the film says is that it lies in [0, θ + a],
        and that range is the rectangle, [0, θ + a] about its middle. (Taken at θ, T/F(θ)
        stays near T/F(0) whatever the swing was, with a u from the folded rectangle that
        covers too little of the correction: lab 1's T₀ was 2.6 u off.) [rad]"""
        value, limit = self.period_amplitude, self.period_amplitude_limit
        if value - limit >= 0:
            return Measured(value, limit=limit)
        middle = 0.5 * (value + limit)
        return Measured(middle, limit=middle)

    @cached_property
    def amplitude_limit(self) -> float:
        r"""Limit of error of :attr:`amplitude`. [rad]

        The arc's radius rests on its sagitta h = R(1 − cos θ₀); an error δh bends R by
        δR/R = −δh/h and θ₀ = A/R by as much. The tracker's sub-pixel error bends the sagitta
        by up to :data:`ARC_LOCKING` = L, and the track's noise moves R by its u from the
        circle's fit (:func:`arc_radius_u`, k = 2):

        .. math:: a_{θ_0} = θ_0 \left(\frac{L}{R(1 - \cos θ_0)} + \frac{2u(R)}{R}\right)
                  ≈ \frac{2L}{A} + \frac{2θ_0 u(R)}{R}

        with A = Rθ₀ the swing's way along the arc in px: the limit is set by how far the
        marker swings in the picture, not by the angle (at 5° on a 200 px arm, A = 17 px:
        0.20°, and 0.23° with the noise's part over 20 oscillations; at 6°, 0.20°). The
        amplitude's own error (≈ L/R) is negligible beside it.
        """
        A = abs(self.swing.amplitude)
        theta = self.amplitude
        R = self.track.circle[2]
        locking = 2 * ARC_LOCKING / (A * np.sinc(theta / (2 * math.pi)) ** 2)
        noise = 2 * theta * arc_radius_u(self.track) / R if math.isfinite(R) else 0.0
        return float(locking + noise)


MARKER_FIELDS = (
    Field("roi", bi("where the marker is in the films' first frame, [x, y, w, h] in pixels "
                    "(without it: the patch that swings at the swing's frequency)",
                    "где метка на первом кадре видео, [x, y, w, h] в пикселях (без него — "
                    "пятно, качающееся с частотой качаний)"),
          kind="region", required=False),
    Field("colour", bi("the marker's colour, as the film shows it (without it: the patch that "
                       "swings at the swing's frequency)",
                       "цвет метки, как он виден на видео (без него — пятно, качающееся с "
                       "частотой качаний)"),
          kind="choice", choices=COLOURS, required=False))
"""A filmed section's fields saying where its films' marker is (``roi``) and what colour
(``colour``), as :func:`filmed_times` reads them."""


def filmed_times(inputs, films: dict[str, dict[str, str]], needed=("t",)):
    """Replace the stopwatch times of a lab's sections by the films that give them.

    Parameters
    ----------
    inputs : processing.measurement.Inputs
    films : dict
        Per section, each film field and the time field it stands for (``{"trifilar":
        {"video": "t", "video_p": "t_p"}}``); the time of ``n_osc`` oscillations becomes
        n_osc·T ± n_osc·u(T) from the film, and the section's ``amplitude``, if not given,
        the first film's; given (read at the film's start), it is carried to the RMS of the
        first film's decaying amplitude, the one the film's period belongs to
        (:func:`_over_film`). A section timed by films alone needs no ``n_osc``: it becomes
        the whole oscillations its shortest film holds.
    needed : sequence of str
        Time fields a section must have, from the stopwatch or from a film.

    Returns
    -------
    inputs, list of Filmed
        The inputs as the lab reduces them, and every film read.

    Raises
    ------
    InputError
        A needed time with neither the stopwatch's readings nor a film; a stopwatch's time
        without ``n_osc``; any film's (see :func:`track_marker`, :func:`swing_of`).
    """
    read = []
    for section, pairs in films.items():
        if section not in inputs:
            continue
        entry = inputs[section]
        _check_timed(inputs, section, pairs, needed)
        swings = {}
        for video, time_field in pairs.items():
            if video in entry:
                where = f"{section}.{video}"
                track = _track_in(inputs, entry[video], where, entry.get("roi"),
                                  entry.get("colour"), section)
                swings[video] = Filmed(where, track, swing_of(track, field=where),
                                       entry.get(time_field))
        if not swings:
            continue
        n = entry.get("n_osc") or max(1, min(math.floor(f.swing.oscillations)
                                              for f in swings.values()))
        changes = {} if "n_osc" in entry else {"n_osc": n}
        if "amplitude" in entry:
            changes["amplitude"] = _over_film(entry["amplitude"], next(iter(swings.values())))
        for video, film in swings.items():
            changes[pairs[video]] = film.swing.period.scaled(n)
            read.append(film)
            _compare_stopwatch(film, n)
            if ("amplitude" not in entry and "amplitude" not in changes
                    and _declares(inputs, section, "amplitude")):
                changes["amplitude"] = film.corrected_with
                _check_amplitude(film, f"{section}.amplitude")
        inputs = inputs.changed(section, **changes)
    return inputs, read


def _track_in(inputs, film, where: str, roi, colour, section: str) -> Track:
    """:func:`track_marker` of a film named by a measurement file, a region that does not
    fit the film, or a colour that does not swing in it, refused as the file's own field
    (``roi``, ``colour`` of the section)."""
    fields = (f"{section}.roi", f"{section}.colour")
    try:
        return track_marker(film, field=where, roi=roi, colour=colour, roi_field=fields[0],
                            colour_field=fields[1])
    except InputError as exc:
        if exc.field in fields:
            raise inputs.error(exc.problem, exc.fix, exc.field, exc.ru) from None
        raise


def _over_film(amplitude: Measured, film: Filmed) -> Measured:
    """The amplitude a film's period belongs to, from the amplitude the student read at the
    film's start: times the film's own ratio of the RMS of its decaying envelope to its
    start (:attr:`Swing.reference_amplitude` over :attr:`Swing.amplitude`).

    A wide swing's period shortens as it decays; the film's mean period is the period of a
    swing of its envelope's RMS amplitude θ_r (to the order θ⁴: for a pendulum the rest is
    Var(θ²)/3072 of T, under 10⁻⁶ at 19° decaying to a quarter), not of the amplitude at
    its start: corrected with the start's, T₀ = T/F(θ) comes out low by (θ₀² − θ_r²)/16
    (2–5·10⁻⁴ at 5–9° decaying by a third)."""
    return amplitude.scaled(abs(film.swing.reference_amplitude / film.swing.amplitude))


def _check_timed(inputs, section: str, pairs: dict[str, str], needed) -> None:
    """Refuse a section whose needed time has neither the stopwatch's readings nor a film,
    or whose stopwatch times do not say how many oscillations they took."""
    entry = inputs[section]
    for video, time_field in pairs.items():
        if video not in entry and time_field in needed and time_field not in entry:
            raise inputs.error(
                f"[{section}] has neither the stopwatch's time {time_field} nor a film",
                f"write {time_field} = [...] (the time of n_osc oscillations) or {video} = "
                "\"swing.mp4\"", f"{section}.{time_field}",
                ru=(f"в [{section}] нет ни времени по секундомеру {time_field}, ни видео",
                    f"запишите {time_field} = [...] (время n_osc колебаний) или {video} = "
                    "\"swing.mp4\""))
    timed = [t for t in pairs.values() if t in entry]
    if timed and "n_osc" not in entry:
        raise inputs.error(
            f"'n_osc' (full oscillations timed) is missing: {timed[0]} is the stopwatch's "
            "time of n_osc oscillations", f"add a line n_osc = ... in [{section}] (a film "
            "needs none)", f"{section}.n_osc",
            ru=(f"нет 'n_osc' (число полных колебаний): {timed[0]} — время n_osc колебаний "
                "по секундомеру", f"добавьте строку n_osc = ... в [{section}] (для видео "
                "не нужна)"))


def _declares(inputs, section: str, name: str) -> bool:
    """Whether the lab's section has the field ``name``."""
    spec = inputs.spec
    return spec is not None and any(f.name == name for f in spec.section(section).fields)


def _check_amplitude(film: Filmed, field_name: str) -> None:
    """Warn where the film's amplitude is less certain than :data:`AMPLITUDE_LIMIT`."""
    limit = math.degrees(film.amplitude_limit)
    if limit <= AMPLITUDE_LIMIT:
        return
    swing = abs(film.swing.amplitude)
    sag = film.track.circle[2] * (1 - math.cos(film.amplitude))
    warnings.warn(FilmAmplitudeWarning(
        f"{film.field}: the amplitude read off the film, {math.degrees(film.amplitude):.2f}°, "
        f"is certain to ±{limit:.2f}° only (the marker swings {swing:.0f} px along an arc "
        f"that sags {sag:.2f} px): the "
        f"finite-amplitude correction carries it; give {field_name} from the scale, or film "
        "closer so that the marker swings wider in the picture",
        f"{film.field}: амплитуда по видео {math.degrees(film.amplitude):.2f}° известна лишь с "
        f"точностью ±{limit:.2f}° (метка проходит {swing:.0f} пикс по дуге с прогибом "
        f"{sag:.2f} пикс): поправка на "
        f"конечную амплитуду учитывает это; задайте {field_name} по шкале или снимайте ближе, "
        "чтобы размах метки на кадре был больше"))


def _compare_stopwatch(film: Filmed, n: int) -> None:
    """Warn where the stopwatch's period and the film's disagree beyond both their u."""
    if film.stopwatch is None:
        return
    T_sw, u_sw = film.stopwatch.value / n, film.stopwatch.u / n
    T, u = film.swing.period.value, film.swing.period.u
    if abs(T_sw - T) > 2 * math.hypot(u_sw, u):
        warnings.warn(InconsistentInputWarning(
            f"{film.field}: the stopwatch's period {T_sw:.4f} s and the film's {T:.5f} s "
            f"differ by {100 * (T_sw / T - 1):+.2f} %, beyond both uncertainties: the film's "
            "is used; check n_osc and the stopwatch readings",
            f"{film.field}: период по секундомеру {T_sw:.4f} с и по видео {T:.5f} с "
            f"различаются на {100 * (T_sw / T - 1):+.2f} %, больше обеих погрешностей: "
            "принят период по видео; проверьте n_osc и показания секундомера"))


def film_figures(films: list[Filmed]) -> list:
    """A report figure per film: a frame with the marker's track drawn, the track's
    displacement against time with the fitted damped sinusoid, and the residual."""
    from ..result import Figure

    def draw(film: Filmed):
        def paint(fig, lang: str) -> None:
            top, middle, bottom = fig.subplots(3, 1, height_ratios=(3, 2, 1))
            if film.track.frames:
                top.imshow(film.track.frames[0][1], cmap="gray")
            top.plot(film.track.x, film.track.y, color="C1", lw=0.8)
            top.set_axis_off()
            t, s = film.track.displacement()
            fit = film.swing.fit
            middle.plot(t, s, ".", ms=2, color="C0",
                        label="track" if lang == "en" else "траектория")
            middle.plot(t, fit.predict(t), color="C1", lw=0.8,
                        label=(f"fit: T = {fit.period:.5f} s" if lang == "en"
                               else f"аппроксимация: T = {fit.period:.5f} с"))
            middle.legend(fontsize=7, loc="upper right")
            middle.set_ylabel("px")
            bottom.plot(t, s - fit.predict(t), ".", ms=2, color="C3")
            bottom.set_xlabel("t, s" if lang == "en" else "t, с")
            bottom.set_ylabel("px")
            fig.tight_layout()
        return paint

    return [Figure(f"film_{f.field.replace('.', '_')}",
                   {"en": f"The film of {f.field}: the marker's track over a frame; its "
                          "displacement with the fitted damped oscillation; the residual",
                    "ru": f"Видео {f.field}: траектория метки на кадре; её смещение и "
                          "подобранные затухающие колебания; остаток"},
                   draw(f), (6.4, 6.4)) for f in films]
