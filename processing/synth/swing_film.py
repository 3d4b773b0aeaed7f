"""A phone film of a swinging part with a marker on it, drawn from a known oscillation.

The marker (a dark disc with a light rim, stuck on the part) swings on an arc about the
pivot — a pendulum seen from the side, or a trifilar platform's edge seen from above: the
same picture — by θ(t) = θ₀ e^{−δt/T} cos(2πt/T), the linear damped oscillation the lab's
period is defined by (the amplitude correction is the lab's business). The camera sees it on
a still, textured background at ``fps`` frames per second, each frame the mean of the
exposure's sub-frames (motion blur), with sensor noise, mains flicker (100 Hz, aliased by the
frame rate), a slow change of lighting, a few frames where a hand hides the marker, and the
codec's compression (OpenCV's MPEG-4 writer).

A phone films at a variable frame rate: given its frames' own times (``frame_times``, or a
random ``jitter`` of the intervals), the film is written as H.264 in MP4 with each frame's
timestamp set (PyAV, the ``test`` extra: OpenCV's writer knows only a fixed rate), and
OpenCV reads those timestamps back exactly.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np


@dataclass(frozen=True)
class Film:
    """What the camera films and how.

    Parameters
    ----------
    period : float
        T. [s]
    decrement : float
        δ per period.
    amplitude : float
        θ₀ at t = 0. [rad]
    oscillations : float
        Length of the film in periods.
    arm : float
        Distance of the marker from the pivot. [px]
    pivot : (float, float)
        The pivot in the frame. [px]
    size : (int, int)
        Frame width and height. [px]
    fps : float
        Frames per second.
    exposure : float
        Share of a frame interval the shutter is open (motion blur).
    noise : float
        Sensor noise σ. [grey levels]
    flicker : float
        Relative depth of the 100 Hz mains flicker.
    lighting : float
        Relative change of the light over the film.
    occluded : int
        Frames in which a hand hides the marker.
    marker : float
        Radius of the marker. [px]
    jitter : float
        Frame intervals drawn uniformly within (1 ± jitter)/fps: a variable frame rate.
    frame_times : tuple of float, optional
        Each frame's time instead of k/fps (``fps`` then sets only the exposure's length and
        the film's nominal rate). [s]
    """

    period: float = 1.2
    decrement: float = 0.02
    amplitude: float = math.radians(6.0)
    oscillations: float = 20.0
    arm: float = 600.0
    pivot: tuple[float, float] = (320.0, -360.0)
    size: tuple[int, int] = (640, 480)
    fps: float = 30.0
    exposure: float = 0.25
    noise: float = 2.0
    flicker: float = 0.03
    lighting: float = 0.1
    occluded: int = 5
    marker: float = 9.0
    jitter: float = 0.0
    frame_times: tuple[float, ...] | None = None

    @property
    def variable(self) -> bool:
        """Whether the frames have their own times (a variable frame rate)."""
        return self.frame_times is not None or self.jitter > 0

    def angle(self, t) -> np.ndarray:
        """θ(t). [rad]"""
        t = np.asarray(t, dtype=float)
        return self.amplitude * np.exp(-self.decrement * t / self.period) * np.cos(
            2 * np.pi * t / self.period)

    def position(self, t) -> tuple[np.ndarray, np.ndarray]:
        """The marker's centre at ``t``. [px]"""
        th = self.angle(t)
        return self.pivot[0] + self.arm * np.sin(th), self.pivot[1] + self.arm * np.cos(th)

    @property
    def rms_amplitude(self) -> float:
        """√(mean θ_a²) of the decaying amplitude θ₀e^{−δt/T} over the film: θ₀√((1 −
        e^{−2δN})/(2δN)) for N oscillations. A real swing's period shortens as it decays,
        and its mean over the film is its period at this amplitude: the period a scene of
        the lab's should give the film to be true to the swing it stands for. [rad]"""
        x = 2 * self.decrement * self.oscillations
        return self.amplitude * (math.sqrt(-math.expm1(-x) / x) if x > 0 else 1.0)

    def truth(self) -> dict:
        return {"period": self.period, "decrement": self.decrement,
                "amplitude_deg": math.degrees(self.amplitude),
                "oscillations": self.oscillations}


def _background(size, rng) -> np.ndarray:
    w, h = size
    base = 170 + 25 * cv2.GaussianBlur(rng.standard_normal((h, w)).astype(np.float32),
                                       (0, 0), 6)
    base += np.linspace(-10, 10, w, dtype=np.float32)[None, :]
    cv2.rectangle(base, (40, 30), (110, 440), 120, -1)          # a stand's leg
    return base


def _disc(canvas: np.ndarray, x: float, y: float, radius: float, grey: float) -> None:
    """Paint a disc of centre (x, y) and ``radius`` [px] in ``grey`` over ``canvas``, each
    pixel by the share of its area the disc covers (a camera's pixel integrates the light
    over its area), that share taken as clip(radius + ½ − d, 0, 1) with d the distance of the
    pixel's centre from the disc's.

    The disc's centroid is then where it is drawn to within 0.01 px at any sub-pixel place.
    OpenCV's antialiased :func:`cv2.circle` (at 1/16 px) misplaces it by up to 0.13 px, and
    the error's pattern over a pixel bends a short arc's sagitta (0.27 px at 3° on a 200 px
    arm) by half: the amplitude read off such a film was 1.7° off at 3° for a fault of the
    film, not of its reading (0.04° with the disc drawn by area)."""
    h, w = canvas.shape
    reach = int(math.ceil(radius)) + 2
    i0, j0 = max(int(math.floor(y)) - reach, 0), max(int(math.floor(x)) - reach, 0)
    i1, j1 = min(int(math.floor(y)) + reach + 2, h), min(int(math.floor(x)) + reach + 2, w)
    if i0 >= i1 or j0 >= j1:
        return
    rows, cols = np.mgrid[i0:i1, j0:j1]
    cover = np.clip(radius + 0.5 - np.hypot(cols - x, rows - y), 0.0, 1.0)
    patch = canvas[i0:i1, j0:j1]
    patch += cover * (grey - patch)


def _draw_marker(canvas, x, y, r) -> None:
    """The marker: a dark disc of radius ``r`` on a light rim of 1.6 r. [px]"""
    _disc(canvas, x, y, 1.6 * r, 235.0)
    _disc(canvas, x, y, r, 25.0)


def frame_times(film: Film, rng: np.random.Generator) -> np.ndarray:
    """The frames' times: ``film.frame_times``, or k/fps over the film's length, each
    interval jittered by ``film.jitter``. [s]"""
    if film.frame_times is not None:
        return np.asarray(film.frame_times, dtype=float)
    n = int(round(film.oscillations * film.period * film.fps))
    steps = (1 + film.jitter * rng.uniform(-1, 1, n - 1)) / film.fps if film.jitter \
        else np.ones(n - 1) / film.fps
    return np.concatenate([[0.0], np.cumsum(steps)])


TIMESCALE = 90_000
"""Ticks per second of a variable-rate film's timestamps (as a phone's MP4)."""


class _TimedWriter:
    """H.264 in MP4 with each frame's own timestamp (PyAV)."""

    def __init__(self, path, fps: float, size: tuple[int, int]):
        try:
            import av
        except ImportError:
            raise ImportError("a film of variable frame rate is written with PyAV: install "
                              "the test extra, pip install 'dynlab[test]'") from None
        from fractions import Fraction

        self._av = av
        self._box = av.open(str(path), "w")
        self._stream = self._box.add_stream("libx264", rate=round(fps))
        self._stream.width, self._stream.height = size
        self._stream.pix_fmt = "yuv420p"
        self._stream.time_base = Fraction(1, TIMESCALE)
        self._stream.codec_context.time_base = Fraction(1, TIMESCALE)

    def write(self, grey: np.ndarray, time: float) -> None:
        frame = self._av.VideoFrame.from_ndarray(grey, format="gray").reformat(
            format="yuv420p")
        frame.pts = int(round(time * TIMESCALE))
        frame.time_base = self._stream.time_base
        self._box.mux(self._stream.encode(frame))

    def release(self) -> None:
        self._box.mux(self._stream.encode())
        self._box.close()


class _FixedWriter:
    """OpenCV's MPEG-4 writer at a fixed rate."""

    def __init__(self, path, fps: float, size: tuple[int, int]):
        self._writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, size,
                                       False)

    def write(self, grey: np.ndarray, time: float) -> None:
        self._writer.write(grey)

    def release(self) -> None:
        self._writer.release()


def render(film: Film, path, *, seed: int = 0, subframes: int = 5, upscale: int = 1) -> Path:
    """Film the swing into ``path`` (MP4: MPEG-4 part 2 at a fixed frame rate, H.264 with
    each frame's timestamp at a variable one). Returns the path.

    ``upscale`` > 1 writes each frame enlarged that many times (bilinear): a film of
    ``upscale`` × ``film.size`` (a phone's 4K from a 960 × 540 scene) at the cost of drawing
    the small one; positions in the film are ``upscale`` × the scene's (pixel centres at
    (k + ½)·upscale − ½).

    Raises
    ------
    ImportError
        A variable frame rate without PyAV (the ``test`` extra).
    """
    rng = np.random.default_rng([seed, 18])
    w, h = film.size
    background = _background(film.size, rng)
    times = frame_times(film, rng)
    n = times.size
    hidden = set(rng.choice(np.arange(n // 4, n), size=min(film.occluded, n // 2),
                            replace=False).tolist()) if film.occluded else set()
    writer = (_TimedWriter if film.variable else _FixedWriter)(path, film.fps,
                                                               (w * upscale, h * upscale))
    for k, t0 in enumerate(times):
        frame = np.zeros((h, w), np.float32)
        for s in range(subframes):
            t = t0 + film.exposure / film.fps * (s + 0.5) / subframes
            canvas = background.copy()
            x, y = film.position(t)
            _draw_marker(canvas, float(x), float(y), film.marker)
            frame += canvas
        frame /= subframes
        if k in hidden:
            x, y = film.position(t0)
            cv2.rectangle(frame, (int(x) - 40, int(y) - 30), (int(x) + 40, int(y) + 60), 95, -1)
        light = (1 + film.flicker * math.sin(2 * math.pi * 100 * t0 + 0.7)) * (
            1 - film.lighting * k / max(n - 1, 1))
        frame = frame * light + film.noise * rng.standard_normal(frame.shape)
        if upscale > 1:
            frame = cv2.resize(frame.astype(np.float32), (w * upscale, h * upscale),
                               interpolation=cv2.INTER_LINEAR)
        writer.write(np.clip(frame, 0, 255).astype(np.uint8), float(t0))
    writer.release()
    return Path(path)
