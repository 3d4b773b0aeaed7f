"""Benchmark of periods from films (:mod:`processing.vision.video`) against the reference
families a student would otherwise use, on synthetic films of known swings.

Every case is a film made by :func:`processing.synth.swing_film.render` (640 × 480, a marker
swinging on a 600 px arm, 20 oscillations of 1.2345 s, flicker, a lighting change, five hidden
frames, MPEG-4) over a grid of sensor noise × exposure (motion blur) × frame rate ×
amplitude. The marker is tracked once per case; the families differ in how they turn the
track into a period:

``dynlab``
    :func:`~processing.vision.video.swing_of`: a damped sinusoid on a line fitted over every
    frame kept, u from the fit.
``zero crossings``
    What a Tracker user does with the track (Tracker's autotracking is template matching
    with a sub-pixel peak, as here, and states no uncertainty): the mean interval between
    the displacement's upward zero crossings, each found by linear interpolation.
``autocorrelation``
    phyphox's way: the lag of the displacement's autocorrelation peak nearest one period, on
    the frame grid (quantised to a frame).

The error is T/T_true − 1. Coverage: seeded films spread over the grid's region (each
noise × exposure × frame rate × amplitude, ``repeats`` times, the period drawn in 1–1.55 s),
the share whose 95 % interval (t of the stated u's effective degrees of freedom) holds the
truth; these are filmed at 320 × 240 — the same marker on the same 600 px arm, the frame
cropped about its swing, which halves the time and changes nothing the tracker sees.
Variable frame rate: films of a phone's clock (each interval ±20 % at 30 fps, and a drop from
30 to 24 fps halfway, written with each frame's timestamp), whose period must meet the same
target and which must each be warned irregular. Targets: the period within 0.02 % in every
case of the grid (20 oscillations at 30 fps and more) and of the variable-rate films,
coverage 90–98 % (widened for the number of films), and ≥ 300 frames per second tracked on
one core (decoding included; processor time, so that other work on the machine does not
count).

Phone films (:mod:`processing.bench.film_phone`): the second family, drawn by
:mod:`processing.synth.phone_film`, written to ``phone.csv`` with its own targets.

Amplitude: the angle read off the marker's arc (:attr:`~processing.vision.video.Filmed.
amplitude`) on every film of the grid (from the side, 600 px arm) and on films of issue 18's
scene (20 oscillations at 30 fps, 640 × 480) with the marker on a disc's edge 100 or 200 px
from its axis seen from above, or on a 300 px arm from the side, at 2–10°, written to
``amplitude.csv``. Targets: every film's stated limit
(:attr:`~processing.vision.video.Filmed.amplitude_limit`) holds its truth, and the error is
within 0.2° wherever that limit is (where it is wider, the film is warned of).
"""
from __future__ import annotations

import itertools
import math
import tempfile
import time
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from ..diagnostics import InputError, IrregularFrameRateWarning
from ..synth.swing_film import Film, render
from ..vision.video import AMPLITUDE_LIMIT, Track, swing_of, track_marker
from ..vision.video import Filmed as Read
from . import film_phone
from .harness import (Case, Family, MapAxes, Method, Target, abs_error, coverage_targets,
                      environment, plot_error_time, plot_map, run_family, summary, write_rows,
                      write_targets)

ERROR_TARGET = 2e-4
"""The period's relative error allowed in every case of the grid."""

PERIOD = 1.2345
"""The grid's period: not a whole number of frames at any frame rate of the grid (a period
of whole frames would flatter the frame-quantised autocorrelation)."""

FPS_TARGET = 300.0
"""Frames per second tracked on one core (640 × 480)."""


@dataclass(frozen=True)
class Plan:
    noise: tuple
    exposure: tuple
    fps: tuple
    amplitude_deg: tuple
    repeats: int
    """Coverage films per point of the grid."""
    variable_seeds: int
    """Films of each variable frame rate."""
    amplitude_scenes: tuple
    """(view, arm [px], amplitudes [deg], seeds) of the amplitude's films."""


FULL = Plan(noise=(1.0, 4.0, 8.0), exposure=(0.1, 0.5), fps=(30.0, 60.0),
            amplitude_deg=(3.0, 10.0), repeats=9, variable_seeds=3,
            amplitude_scenes=(("above", 200.0, (2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0), 2),
                              ("above", 100.0, (5.0, 8.0), 1),
                              ("side", 300.0, (3.0, 5.0, 8.0), 1)))
QUICK = Plan(noise=(2.0, 8.0), exposure=(0.5,), fps=(30.0,), amplitude_deg=(3.0, 10.0),
             repeats=6, variable_seeds=1,
             amplitude_scenes=(("above", 200.0, (3.0, 5.0, 8.0), 1),))

VIEWS = {"above": lambda arm, phase: {"arm": arm, "pivot": (320.0 + phase, 240.0 + phase)},
         "side": lambda arm, phase: {"arm": arm, "pivot": (320.0 + phase, 120.0 - arm + phase)}}
"""Where the pivot is for an arm: a disc's axis in the frame's middle (from above), or above
the frame with the marker swinging through its upper part (from the side), shifted by a
fraction of a pixel (the tracker's error is a function of the marker's place in a pixel)."""

PHASE = 0.37
"""Step of that shift from one amplitude film to the next. [px]"""

CROPPED = {"size": (320, 240), "pivot": (160.0, -420.0)}
"""The coverage films' frame: the default scene's swing cropped to 320 × 240."""

MAP_AXES = MapAxes(x="noise", y="amplitude_deg", column="exposure", row="fps",
                   labels={"noise": "sensor noise σ, grey levels", "amplitude_deg": "amplitude, °",
                           "exposure": "exposure, share of a frame", "fps": "frames per second"})


@dataclass(frozen=True)
class Filmed:
    """A case's film, tracked once, and the time tracking took."""

    track: Track
    seconds: float


def zero_crossings(track: Track) -> float:
    """Mean interval between upward zero crossings of the displacement (linear
    interpolation between frames). [s]"""
    t, s = track.displacement()
    s = s - np.polyval(np.polyfit(t, s, 1), t)
    up = np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0))
    crossings = t[up] - s[up] * (t[up + 1] - t[up]) / (s[up + 1] - s[up])
    return float(np.mean(np.diff(crossings)))


def autocorrelation(track: Track) -> float:
    """The lag of the autocorrelation's first peak past its first zero, on the frame grid.
    [s]"""
    t, s = track.displacement()
    s = s - s.mean()
    ac = np.correlate(s, s, "full")[s.size - 1:]
    first_zero = int(np.argmax(ac < 0))
    lag = first_zero + int(np.argmax(ac[first_zero:first_zero + s.size // 4]))
    return float(lag * np.median(np.diff(t)))


def _film(film: Film, folder: Path, seed: int) -> Filmed:
    """A case's film rendered and tracked, with the processor time tracking took (every
    thread's: decoding's too; on a machine shared with other work, the wall clock would
    time the others)."""
    path = render(film, folder / f"film{seed}.mp4", seed=seed)
    start = time.process_time()
    track = track_marker(path)
    return Filmed(track, time.process_time() - start)


def cases(plan: Plan, folder: Path) -> Iterator[Case]:
    for k, (noise, exposure, fps, amp) in enumerate(itertools.product(
            plan.noise, plan.exposure, plan.fps, plan.amplitude_deg)):
        film = Film(period=PERIOD, noise=noise, exposure=exposure, fps=fps,
                    amplitude=math.radians(amp))
        filmed = _film(film, folder, k)
        yield Case({"noise": noise, "exposure": exposure, "fps": fps, "amplitude_deg": amp},
                   filmed, film.period, filmed.track.time.size)


def family() -> Family:
    def error(estimate, truth):
        return {"error": estimate / truth - 1}

    methods = [Method("dynlab", lambda f: swing_of(f.track).period.value, "damped sine fit"),
               Method("zero crossings", lambda f: zero_crossings(f.track), "Tracker-like"),
               Method("autocorrelation", lambda f: autocorrelation(f.track), "phyphox-like")]
    return Family("period from film", methods, error, "relative period error",
                  failures=(InputError, RuntimeError))


def _coverage(plan: Plan, folder: Path, log) -> list[bool]:
    covered = []
    points = list(itertools.product(plan.noise, plan.exposure, plan.fps, plan.amplitude_deg))
    for k in range(plan.repeats * len(points)):
        noise, exposure, fps, amp = points[k % len(points)]
        film = Film(period=1.0 + 0.0137 * (7 * k % 41), noise=noise, exposure=exposure,
                    fps=fps, amplitude=math.radians(amp), **CROPPED)
        T = swing_of(_film(film, folder, 1000 + k).track).period
        covered.append(abs(T.value - film.period) <= stats.t.ppf(0.975, T.dof) * T.u)
    log(f"coverage: {sum(covered)}/{len(covered)} films")
    return covered


def variable_films(seeds: int) -> Iterator[tuple[str, Film, int]]:
    """Films of a phone's variable frame rate: ±20 % intervals, and 30 then 24 fps."""
    n = int(round(20 * PERIOD * 30 / 2))
    halves = np.concatenate([np.arange(n) / 30, (n - 1) / 30 + np.arange(1, n * 4 // 5) / 24])
    for seed in range(seeds):
        yield f"jitter ±20 % (seed {seed})", Film(period=PERIOD, jitter=0.2), seed
        yield f"30 → 24 fps (seed {seed})", Film(period=PERIOD, frame_times=tuple(halves)), seed


def _variable(plan: Plan, folder: Path, log) -> tuple[list[float], list[bool]]:
    errors, warned = [], []
    for name, film, seed in variable_films(plan.variable_seeds):
        path = render(film, folder / f"vfr{len(errors)}.mp4", seed=2000 + seed)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", IrregularFrameRateWarning)
            T = swing_of(track_marker(path)).period
        errors.append(T.value / film.period - 1)
        warned.append(any(issubclass(w.category, IrregularFrameRateWarning) for w in caught))
        log(f"variable frame rate, {name}: period error {errors[-1]:+.2e}, "
            f"{'warned' if warned[-1] else 'NOT warned'}")
    return errors, warned


def _amplitude_row(view: str, arm: float, film: Film, path, track=None, **more) -> dict:
    """The amplitude read off a film against its truth, with the film's stated limit; a film
    refused (:class:`InputError`: a swing narrower than the marker is not always told from
    the background) has no error and its reason."""
    row = {"view": view, "arm_px": arm, "amplitude_deg": math.degrees(film.amplitude), **more}
    try:
        track = track_marker(path) if track is None else track
        read = Read("film", track, swing_of(track))
    except InputError as exc:
        return {**row, "error_deg": math.nan, "limit_deg": math.nan, "held": False,
                "refused": exc.problem}
    error = math.degrees(read.amplitude - film.amplitude)
    limit = math.degrees(read.amplitude_limit)
    return {**row, "error_deg": error, "limit_deg": limit, "held": abs(error) <= limit,
            "refused": ""}


def _amplitudes(plan: Plan, grid: list[Case], folder: Path, log) -> list[dict]:
    rows = [_amplitude_row("side", Film().arm, Film(amplitude=math.radians(
        case.params["amplitude_deg"])), case.data.track.path, case.data.track, case=k,
        noise=case.params["noise"], exposure=case.params["exposure"], fps=case.params["fps"])
        for k, case in enumerate(grid)]
    for view, arm, degrees, seeds in plan.amplitude_scenes:
        for amp, seed in itertools.product(degrees, range(seeds)):
            film = Film(period=1.3, amplitude=math.radians(amp),
                        **VIEWS[view](arm, PHASE * len(rows) % 1.0))
            path = render(film, folder / f"amplitude{len(rows)}.mp4", seed=3000 + len(rows))
            row = _amplitude_row(view, arm, film, path, seed=seed)
            rows.append(row)
            log(f"amplitude {amp:g}° from {view}, {arm:g} px arm (seed {seed}): "
                + (f"refused ({row['refused']})" if row["refused"] else
                   f"error {row['error_deg']:+.3f}°, stated limit {row['limit_deg']:.3f}°"))
    return rows


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Run the grid and the coverage; write ``bench.csv``, the charts and ``targets.json``."""
    import cv2

    cv2.setNumThreads(1)                       # one core: decoding and matching alike
    plan = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        log(f"films: noise {plan.noise} x exposure {plan.exposure} x fps {plan.fps} x "
            f"amplitude {plan.amplitude_deg}°")
        grid = list(cases(plan, Path(tmp)))
        rows = run_family(family(), grid, repeat=1)
        methods = len(family().methods)
        for k, case in enumerate(grid):
            for row in rows[k * methods:(k + 1) * methods]:
                row["tracking_fps"] = case.data.track.time.size / case.data.seconds
        covered = _coverage(plan, Path(tmp), log)
        variable, warned = _variable(plan, Path(tmp), log)
        amplitudes = write_rows(_amplitudes(plan, grid, Path(tmp), log), out / "amplitude.csv")
        phone = film_phone.run_films(film_phone.QUICK if quick else film_phone.FULL,
                                     Path(tmp), log)
    write_rows(phone, out / "phone.csv")
    rates = [case.data.track.time.size / case.data.seconds for case in grid]
    read = amplitudes[amplitudes["refused"] == ""]
    frame = write_rows(rows, out / "bench.csv")
    ours = frame[frame["method"] == "dynlab"]
    plot_error_time(frame, out / "error_time.png", {"period from film": "relative period error"})
    plot_map(ours, out / "stability_map.png", MAP_AXES, threshold=ERROR_TARGET)
    targets = [Target("period from film, worst case of the grid", float(abs_error(ours).max()),
                      ERROR_TARGET, unit="relative"),
               Target("period from variable-rate films, worst",
                      float(np.max(np.abs(variable))), ERROR_TARGET, unit="relative"),
               Target("variable-rate films warned irregular", float(np.mean(warned)), 1.0,
                      "min"),
               *coverage_targets("period from film", covered, "films"),
               Target("film amplitude's stated limit holds the truth",
                      float(read["held"].mean()), 1.0, "min",
                      detail=f"{len(read)} films read, {len(amplitudes) - len(read)} refused"),
               Target("film amplitude, worst |error| where its limit is ≤ 0.2°",
                      float(read.loc[read["limit_deg"] <= AMPLITUDE_LIMIT,
                                     "error_deg"].abs().max()), AMPLITUDE_LIMIT, unit="deg",
                      detail=f"{int((read['limit_deg'] <= AMPLITUDE_LIMIT).sum())} films; "
                      f"worst of all {read['error_deg'].abs().max():.3f}°"),
               Target("frames tracked per second (640 × 480, one core)",
                      float(np.median(rates)), FPS_TARGET, "min"),
               *film_phone.targets(phone)]
    write_targets(targets, out / "targets.json", environment())
    return frame, targets


def summary_lines(frame: pd.DataFrame) -> list[str]:
    """The summary printed after the run."""
    return ["Summary (|err| relative):",
            summary(frame).to_string(index=False, float_format=lambda v: f"{v:.3g}")]
