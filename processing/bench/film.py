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

The error is T/T_true − 1. Coverage: seeded films at the default scene, the share whose 95 %
interval (the fit's t interval) holds the truth. Targets: the period within 0.02 % in every
case of the grid (20 oscillations at 30 fps and more), coverage 90–98 %, and ≥ 300 frames
per second tracked on one core (decoding included).
"""
from __future__ import annotations

import itertools
import math
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from ..diagnostics import InputError
from ..synth.swing_film import Film, render
from ..vision.video import Track, swing_of, track_marker
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
    seeds: int
    """Films at the default scene for the coverage."""


FULL = Plan(noise=(1.0, 4.0, 8.0), exposure=(0.1, 0.5), fps=(30.0, 60.0),
            amplitude_deg=(3.0, 10.0), seeds=40)
QUICK = Plan(noise=(2.0, 8.0), exposure=(0.5,), fps=(30.0,), amplitude_deg=(3.0, 10.0),
             seeds=8)

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
    path = render(film, folder / f"film{seed}.mp4", seed=seed)
    start = time.perf_counter()
    track = track_marker(path)
    return Filmed(track, time.perf_counter() - start)


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


def _coverage(plan: Plan, folder: Path, log) -> tuple[list[bool], list[float]]:
    covered, rates = [], []
    for seed in range(plan.seeds):
        film = Film(period=1.0 + 0.02 * seed, amplitude=math.radians(4.0 + seed % 5))
        filmed = _film(film, folder, 1000 + seed)
        swing = swing_of(filmed.track)
        k = stats.t.ppf(0.975, swing.period.dof_a)
        covered.append(abs(swing.period.value - film.period) <= k * swing.period.u)
        rates.append(filmed.track.time.size / filmed.seconds)
    log(f"coverage: {sum(covered)}/{len(covered)} films")
    return covered, rates


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
        covered, rates = _coverage(plan, Path(tmp), log)
    rates += [case.data.track.time.size / case.data.seconds for case in grid]
    frame = write_rows(rows, out / "bench.csv")
    ours = frame[frame["method"] == "dynlab"]
    plot_error_time(frame, out / "error_time.png", {"period from film": "relative period error"})
    plot_map(ours, out / "stability_map.png", MAP_AXES, threshold=ERROR_TARGET)
    targets = [Target("period from film, worst case of the grid", float(abs_error(ours).max()),
                      ERROR_TARGET, unit="relative"),
               *coverage_targets("period from film", covered, "films"),
               Target("frames tracked per second (640 × 480, one core)",
                      float(np.median(rates)), FPS_TARGET, "min")]
    write_targets(targets, out / "targets.json", environment())
    return frame, targets


def summary_lines(frame: pd.DataFrame) -> list[str]:
    """The summary printed after the run."""
    return ["Summary (|err| relative):",
            summary(frame).to_string(index=False, float_format=lambda v: f"{v:.3g}")]
