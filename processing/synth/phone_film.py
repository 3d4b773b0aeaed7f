"""A phone's film of a swinging pendulum or a twisting trifilar platform: a second family of
synthetic films, drawn independently of :mod:`processing.synth.swing_film`.

The physics: the part is integrated from its nonlinear equation with viscous and quadratic
(air) damping (:func:`processing.synth.pendulum.free_swing`), so a wide swing's period
lengthens and shortens as its amplitude decays — a physical pendulum J θ̈ = −m g c sin θ seen
from the side (a flywheel hung on a knife edge inside its rim), or a trifilar platform with
its exact thread geometry seen from above (it rises as it twists).

The optics: the moving part is a layer (colour and coverage, drawn at four times the
resolution and averaged down) turned about its axis for each instant of the exposure and laid
over a still room (motion blur: the shutter open for ``exposure`` of the frame interval,
sampled finely enough that the part moves under 1.5 px between samples, up to 24); a lamp on
the mains lights it with a flicker at twice the mains frequency, integrated over the
exposure (so at 30 or 60 frames per second it beats with the frame rate), beside daylight
that does not flicker; hands pass in front of the camera; the phone is rolled and tilted
(a homography of a camera turned about its axes) and shakes slightly (a smooth random walk
of its aim); the sensor adds shot and read noise and vignetting; the film is compressed with
H.264 (libx264 via PyAV: B-frames, a constant rate factor) in MP4 with each frame's
presentation timestamp — a variable frame rate and dropped frames are in the container — or
into AVI, which holds only a nominal rate. A 4K film is drawn at a quarter of its pixels and
enlarged by the camera's homography. The same scene and seed give the same file
(:func:`_x264_options`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import cv2
import numpy as np
from scipy.ndimage import gaussian_filter1d

from .pendulum import free_swing, period_of, trifilar_equation

G = 9.81
"""Gravity of the scenes. [m/s²]"""

SUPERSAMPLE = 4
"""The part's layer and the hands are drawn at this many times the frame's resolution."""

MAX_SUBFRAMES = 24
"""Most instants an exposure is sampled at (motion blur)."""

TIMESCALE = 90_000
"""Ticks per second of the MP4's timestamps (90 kHz, as phones and FFmpeg write them: a whole
number of ticks a frame at 24–240 frames per second)."""


@dataclass(frozen=True)
class Swinger:
    """What swings: a physical pendulum (``"pendulum"``) or a trifilar platform
    (``"trifilar"``), with a small-amplitude period, a release angle and damping.

    Parameters
    ----------
    kind : str
    period0 : float
        Period at vanishing amplitude. [s]
    amplitude : float
        Release angle. [rad]
    decrement : float
        Logarithmic decrement of the viscous damping alone, per period.
    drag : float
        Quadratic (air) damping: a swing at amplitude a loses π·drag·a² of it.
    trifilar : (float, float, float)
        R₁, R₂, l of the suspension. [m]
    """

    kind: str = "pendulum"
    period0: float = 1.1
    amplitude: float = math.radians(15.0)
    decrement: float = 0.01
    drag: float = 0.02
    trifilar: tuple[float, float, float] = (0.10, 0.14, 0.80)

    @classmethod
    def decaying(cls, kind: str, period0: float, amplitude: float, fall: float,
                 viscous_share: float = 0.5, swings: float = 20.0, **more) -> Swinger:
        """A swing whose amplitude falls to about ``fall`` of its release over ``swings``
        periods (a real one keeps 25–80 % after 20): the share s = ``viscous_share`` of
        the logarithmic loss by viscous damping, δ = s·ln(1/fall)/N, and the rest by air
        drag, which alone (the torque c·θ̇|θ̇| of :meth:`motion` takes (4/3)·c·a²/M of the
        amplitude a each half swing: da/dn = −π·drag·a² per swing) leaves
        1/(1 + π·drag·a₀N) = fall^(1 − s) of the amplitude a₀."""
        drag_part = fall ** (1.0 - viscous_share)
        return cls(kind=kind, period0=period0, amplitude=amplitude,
                   decrement=viscous_share * math.log(1.0 / fall) / swings,
                   drag=(1.0 / drag_part - 1.0) / (math.pi * max(amplitude, 1e-3) * swings),
                   **more)

    def equation(self):
        """(M, M', V') per unit mass of the scene's equation of motion."""
        w0 = 2 * math.pi / self.period0
        if self.kind == "pendulum":
            return (lambda q: 1.0, lambda q: 0.0, lambda q: w0 * w0 * np.sin(q))
        R1, R2, l = self.trifilar
        H = math.sqrt(l * l - (R1 - R2) ** 2)
        J = (self.period0 / (2 * math.pi)) ** 2 * G * R1 * R2 / H   # J/m for T₀
        return trifilar_equation(J, 1.0, R1, R2, l, G)

    def motion(self, duration: float):
        """θ(t) over ``duration`` and its zero crossings (see
        :func:`~processing.synth.pendulum.free_swing`)."""
        M, dM, dV = self.equation()
        m0 = M(0.0)
        w0 = 2 * math.pi / self.period0
        viscous = m0 * self.decrement * w0 / math.pi
        # a swing of amplitude a loses 8/(3π)·c_q/M·a² per half period to quadratic drag
        drag = self.drag * m0 * 3 * math.pi / 8
        return free_swing(M, dM, dV, self.amplitude, duration, viscous=viscous, drag=drag)

    def period_at(self, amplitude: float) -> float:
        """The undamped period at ``amplitude``. [s]"""
        M, dM, dV = self.equation()
        return period_of(M, dM, dV, amplitude)


@dataclass(frozen=True)
class Phone:
    """How the phone films.

    Parameters
    ----------
    size : (int, int)
        The film's width and height. [px]
    fps : float
        Nominal frames per second.
    exposure : float
        Share of the frame interval the shutter is open.
    mains : float
        Mains frequency (the lamp flickers at twice it). [Hz]
    flicker : float
        Depth of the lamp's flicker (0–1).
    daylight : float
        Share of the light that does not flicker.
    roll, tilt : float
        The phone turned about its optical axis and about its horizontal axis. [deg]
    shake : float
        RMS of the handshake's drift of the aim. [px of the film]
    hands : int
        Hands passing in front of the camera.
    noise : float
        Read noise σ. [grey levels]
    crf : int
        H.264's constant rate factor (higher: stronger compression).
    jitter : float
        Each frame interval drawn within (1 ± jitter)/fps: a variable frame rate.
    dropped : int
        Frames the phone drops (a gap of two intervals each).
    container : str
        ``"mp4"`` (each frame's timestamp) or ``"avi"`` (a nominal rate only).
    restamped : bool
        The MP4's timestamps rewritten at the nominal rate (a constant-rate export or
        conversion): a dropped frame leaves no gap in them.
    """

    size: tuple[int, int] = (640, 360)
    fps: float = 30.0
    exposure: float = 0.5
    mains: float = 50.0
    flicker: float = 0.2
    daylight: float = 0.4
    roll: float = 2.0
    tilt: float = 4.0
    shake: float = 0.3
    hands: int = 1
    noise: float = 2.0
    crf: int = 23
    jitter: float = 0.0
    dropped: int = 0
    container: str = "mp4"
    restamped: bool = False


@dataclass(frozen=True)
class Shot:
    """A film's truth.

    Attributes
    ----------
    path : Path
    times : numpy.ndarray
        The frames' capture times (the exposure's start). [s]
    nominal : bool
        Whether the container holds only a nominal rate (the capture times are lost).
    period0 : float
        The period at vanishing amplitude. [s]
    mean_period : float
        The mean period over the film: its span over the oscillations it holds (the zero
        crossings counted, :func:`_half_swings`). [s]
    amplitude : float
        θ at the release, the film's first frame. [rad]
    rms_amplitude : float
        √(2·mean θ²) over the film: the RMS of the amplitude's envelope. [rad]
    dropped : int
    """

    path: Path
    times: np.ndarray
    nominal: bool
    period0: float
    mean_period: float
    amplitude: float
    rms_amplitude: float
    dropped: int


def _frame_times(phone: Phone, duration: float, rng) -> tuple[np.ndarray, int]:
    n = int(round(duration * phone.fps))
    steps = (1 + phone.jitter * rng.uniform(-1, 1, n - 1)) / phone.fps
    times = np.concatenate([[0.0], np.cumsum(steps)])
    dropped = 0
    if phone.dropped:
        gone = rng.choice(np.arange(5, n - 5), size=phone.dropped, replace=False)
        gone = gone[np.diff(np.sort(gone), prepend=-9) > 2]
        dropped = gone.size
        times = np.delete(times, gone)
    return times, dropped


def _smooth_texture(h, w, rng, scale, amplitude) -> np.ndarray:
    small = rng.standard_normal((max(h // scale, 2), max(w // scale, 2))).astype(np.float32)
    return amplitude * cv2.resize(small, (w, h), interpolation=cv2.INTER_CUBIC)


class _Room:
    """The still scene (albedo, BGR 0–1) and the light on it."""

    def __init__(self, kind: str, w: int, h: int, rng):
        albedo = np.empty((h, w, 3), np.float32)
        if kind == "pendulum":
            wall = 0.62 + _smooth_texture(h, w, rng, 40, 0.04)
            albedo[:] = wall[..., None] * np.array([0.92, 1.0, 1.02], np.float32)
            table = int(0.86 * h)
            albedo[table:] = np.array([0.25, 0.35, 0.45], np.float32)
            for _ in range(3):                                       # posters, a door frame
                x0, y0 = int(rng.uniform(0, 0.8) * w), int(rng.uniform(0, 0.6) * h)
                x1, y1 = x0 + int(rng.uniform(0.08, 0.2) * w), y0 + int(rng.uniform(0.1, 0.3) * h)
                cv2.rectangle(albedo, (x0, y0), (x1, y1), rng.uniform(0.2, 0.9, 3).tolist(), -1)
            post = int(0.12 * w)
            cv2.rectangle(albedo, (post, 0), (post + max(w // 60, 2), table), (0.2, 0.2, 0.22), -1)
            cv2.rectangle(albedo, (post, int(0.05 * h)), (int(0.6 * w), int(0.05 * h) + max(h // 60, 2)),
                          (0.2, 0.2, 0.22), -1)
        else:
            floor = 0.45 + _smooth_texture(h, w, rng, 8, 0.06) + _smooth_texture(h, w, rng, 60, 0.05)
            albedo[:] = floor[..., None] * np.array([0.8, 0.9, 1.0], np.float32)
        self.albedo = np.clip(albedo, 0.02, 1.0)
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        lx, ly = rng.uniform(0.2, 0.8) * w, -0.3 * h
        self.lamp = (1.0 / (1.0 + ((xx - lx) ** 2 + (yy - ly) ** 2) / (1.2 * max(w, h)) ** 2))[..., None]


class _Part:
    """The moving part's layer (colour and coverage) at rest, turned about ``axis``."""

    def __init__(self, kind: str, w: int, h: int, rng):
        s = SUPERSAMPLE
        W, H = w * s, h * s
        colour = np.zeros((H, W, 3), np.float32)
        cover = np.zeros((H, W), np.float32)
        if kind == "pendulum":
            R = 0.3 * h                                   # the flywheel's rim
            cx, cy = 0.5 * w, 0.12 * h + 0.8 * R          # hung inside its rim at the top
            self.axis = (0.5 * w, 0.12 * h)
            self.marker = (cx, cy + 0.62 * R)
            disc = [((cx, cy), R, (0.28, 0.28, 0.3)), ((cx, cy), 0.78 * R, (0.4, 0.4, 0.42)),
                    ((cx, cy), 0.12 * R, (0.15, 0.15, 0.15))]
            for (x, y), r, c in disc:
                cv2.circle(colour, (int(x * s), int(y * s)), int(r * s), c, -1, cv2.LINE_AA)
                cv2.circle(cover, (int(x * s), int(y * s)), int(r * s), 1.0, -1, cv2.LINE_AA)
            cv2.circle(colour, (int(cx * s), int(cy * s)), int(0.12 * R * s), (0, 0, 0), -1)
            cv2.circle(cover, (int(cx * s), int(cy * s)), int(0.12 * R * s), 0.0, -1)
            size = 0.09 * R
            reach = 1.85 * R
        else:
            R = 0.42 * h                                  # the platform, seen from above
            cx, cy = 0.5 * w, 0.5 * h
            self.axis = (cx, cy)
            self.marker = (cx + 0.82 * R * math.cos(0.4), cy + 0.82 * R * math.sin(0.4))
            cv2.circle(colour, (int(cx * s), int(cy * s)), int(R * s), (0.7, 0.72, 0.74), -1, cv2.LINE_AA)
            cv2.circle(cover, (int(cx * s), int(cy * s)), int(R * s), 1.0, -1, cv2.LINE_AA)
            cv2.circle(colour, (int(cx * s), int(cy * s)), int(0.55 * R * s), (0.3, 0.3, 0.32), int(0.12 * R * s), cv2.LINE_AA)
            for k in range(3):                            # the threads' eyes on the rim
                a = 2 * math.pi * k / 3 + 1.0
                cv2.circle(colour, (int((cx + 0.93 * R * math.cos(a)) * s), int((cy + 0.93 * R * math.sin(a)) * s)),
                           int(0.03 * R * s), (0.2, 0.2, 0.2), -1, cv2.LINE_AA)
            size = 0.07 * R
            reach = 1.05 * R
        mx, my = self.marker                              # a sticker: a cross on white
        half = int(size * s)
        p, q = int(mx * s), int(my * s)
        cv2.rectangle(colour, (p - half, q - half), (p + half, q + half), (0.95, 0.95, 0.9), -1)
        cv2.rectangle(colour, (p - half, q - half // 4), (p + half, q + half // 4), (0.05, 0.05, 0.05), -1)
        cv2.rectangle(colour, (p - half // 4, q - half), (p + half // 4, q + half), (0.05, 0.05, 0.05), -1)
        self.colour = cv2.resize(colour, (w, h), interpolation=cv2.INTER_AREA)
        self.cover = cv2.resize(cover, (w, h), interpolation=cv2.INTER_AREA)
        self.reach = reach
        ax, ay = self.axis
        self.box = (max(int(ax - reach), 0), max(int(ay - reach), 0),
                    min(int(ax + reach) + 1, w), min(int(ay + reach) + 1, h))

    def at(self, angle: float):
        """Colour and coverage within :attr:`box` turned by ``angle`` about the axis
        (positive: clockwise in the picture)."""
        turn = cv2.getRotationMatrix2D(self.axis, -math.degrees(angle), 1.0)
        x0, y0, x1, y1 = self.box
        turn[:, 2] -= (x0, y0)
        colour = cv2.warpAffine(self.colour, turn, (x1 - x0, y1 - y0), flags=cv2.INTER_LINEAR)
        cover = cv2.warpAffine(self.cover, turn, (x1 - x0, y1 - y0), flags=cv2.INTER_LINEAR)
        return colour, cover


class _Hand:
    """A hand passing in front of the lens: a palm and four fingers, skin-coloured, crossing
    the frame in ``duration`` seconds from ``start``."""

    def __init__(self, w: int, h: int, start: float, duration: float, rng):
        self.start, self.duration = start, duration
        self.w, self.h = w, h
        side = rng.choice([-1, 1])
        y0, y1 = rng.uniform(0.2, 0.8, 2) * h
        self.path = ((0.5 * w - side * 0.9 * w, y0), (0.5 * w + side * 0.9 * w, y1))
        self.scale = rng.uniform(0.35, 0.6) * h
        self.tone = np.array([0.55, 0.65, 0.85], np.float32) * rng.uniform(0.7, 1.1)

    def at(self, t: float):
        share = (t - self.start) / self.duration
        if not 0.0 <= share <= 1.0:
            return None
        (x0, y0), (x1, y1) = self.path
        x, y = x0 + share * (x1 - x0), y0 + share * (y1 - y0)
        cover = np.zeros((self.h, self.w), np.float32)
        r = self.scale
        cv2.ellipse(cover, (int(x), int(y)), (int(0.5 * r), int(0.6 * r)), 10, 0, 360, 1.0, -1, cv2.LINE_AA)
        for k in range(4):
            fx = x + (k - 1.5) * 0.25 * r
            cv2.ellipse(cover, (int(fx), int(y - 0.9 * r)), (int(0.1 * r), int(0.45 * r)), 0, 0, 360, 1.0, -1, cv2.LINE_AA)
        return cv2.GaussianBlur(cover, (0, 0), 0.02 * r + 1.0)   # out of focus, so near


def _camera(phone: Phone, w: int, h: int, offset: tuple[float, float], scale: float) -> np.ndarray:
    """Homography from the drawn room to the film: the phone turned by ``roll`` about its
    optical axis and by ``tilt`` about its horizontal one (a pinhole of a 65° horizontal
    field of view), aimed ``offset`` film pixels off by the hand's drift, enlarged by
    ``scale``."""
    f = 0.5 * w / math.tan(math.radians(32.5))
    K = np.array([[f, 0, 0.5 * w], [0, f, 0.5 * h], [0, 0, 1.0]])
    a, b = math.radians(phone.tilt), math.radians(phone.roll)
    tilt = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    roll = np.array([[math.cos(b), -math.sin(b), 0], [math.sin(b), math.cos(b), 0], [0, 0, 1]])
    H = K @ roll @ tilt @ np.linalg.inv(K)
    S = np.array([[scale, 0, offset[0]], [0, scale, offset[1]], [0, 0, 1.0]])
    return S @ H


def _x264_options(crf: int) -> dict[str, str]:
    """libx264's options: a constant rate factor, B-frames, and its instruction sets capped
    at AVX2 where the processor has AVX-512.

    x264's AVX-512 code makes a different file of the same frames from one encode to the
    next (measured with PyAV 18 and FFmpeg 8's libx264 on an AVX-512 processor: one film
    of 197 frames encoded four times in a process gave two to three files, the first
    different in every fresh process; single-threaded as well; at ``asm=AVX2``, or with no
    assembly at all, the same file every time, as fast as before). Capped, a scene's film
    is the same file on every run, so the benchmark's figures are too.
    """
    options = {"crf": str(crf), "preset": "veryfast", "bf": "2"}
    try:
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:                     # another NumPy: x264 left to choose
        features = {}
    if features.get("AVX512F") and features.get("AVX2"):
        options["x264-params"] = "asm=AVX2"
    return options


class _Encoder:
    """H.264 in MP4 with each frame's timestamp, or MPEG-4 in AVI at a nominal rate (PyAV)."""

    def __init__(self, path, phone: Phone, size):
        import av

        self._av = av
        self._box = av.open(str(path), "w")
        if phone.container == "avi":
            self._stream = self._box.add_stream("mpeg4", rate=Fraction(round(phone.fps)))
            self._stream.codec_context.bit_rate = 8_000_000
        else:
            self._stream = self._box.add_stream("libx264", rate=Fraction(round(phone.fps)),
                                                options=_x264_options(phone.crf))
            self._stream.time_base = Fraction(1, TIMESCALE)
            self._stream.codec_context.time_base = Fraction(1, TIMESCALE)
        self._stream.width, self._stream.height = size
        self._stream.pix_fmt = "yuv420p"
        self._avi = phone.container == "avi"
        self._restamped = phone.restamped
        self._fps = phone.fps
        self._count = 0

    def write(self, bgr: np.ndarray, time: float) -> None:
        frame = self._av.VideoFrame.from_ndarray(bgr, format="bgr24")
        if self._avi:
            frame.pts = self._count
            frame.time_base = Fraction(1, self._stream.average_rate or 30)
        else:
            stamp = self._count / self._fps if self._restamped else time
            frame.pts = int(round(stamp * TIMESCALE))
            frame.time_base = Fraction(1, TIMESCALE)
        self._count += 1
        self._box.mux(self._stream.encode(frame))

    def close(self) -> None:
        self._box.mux(self._stream.encode())
        self._box.close()


def _subframes(speed_px: float, exposure_time: float) -> int:
    return int(np.clip(math.ceil(speed_px * exposure_time / 1.5), 2, MAX_SUBFRAMES))


def render(swinger: Swinger, phone: Phone, path, *, oscillations: float = 20.0,
           seed: int = 0) -> Shot:
    """Film ``oscillations`` periods of the swing into ``path`` (see the module's notes).

    Returns
    -------
    Shot
        The film's truth.
    """
    rng = np.random.default_rng([seed, 28])
    W, H = phone.size
    scale = 2.0 if W * H > 2_500_000 else 1.0            # 4K: drawn at a quarter of its pixels
    w, h = int(round(W / scale)), int(round(H / scale))
    duration = oscillations * swinger.period0 * swinger.period_at(swinger.amplitude) / swinger.period0
    times, dropped = _frame_times(phone, duration, rng)
    theta, crossings = swinger.motion(times[-1] + 1.0 / phone.fps)
    room = _Room(swinger.kind, w, h, rng)
    part = _Part(swinger.kind, w, h, rng)
    hands = [_Hand(w, h, rng.uniform(0.15, 0.85) * times[-1], rng.uniform(0.25, 0.7), rng)
             for _ in range(phone.hands)]
    exposure_time = phone.exposure / phone.fps
    phase = rng.uniform(0, 2 * math.pi)
    drift = gaussian_filter1d(np.cumsum(rng.standard_normal((times.size, 2)), axis=0),
                              max(0.25 * phone.fps, 1.0), axis=0)
    drift -= drift.mean(axis=0)
    drift *= phone.shake / max(float(np.sqrt(np.mean(drift ** 2))), 1e-9)
    bank = [rng.standard_normal((H, W, 3)).astype(np.float32) for _ in range(4)]
    vignette = 1 - 0.25 * ((np.mgrid[0:H, 0:W][1] / W - 0.5) ** 2
                           + (np.mgrid[0:H, 0:W][0] / H - 0.5) ** 2)[..., None].astype(np.float32)
    encoder = _Encoder(path, phone, (W, H))
    omega = 2 * math.pi / swinger.period0
    for k, t0 in enumerate(times):
        speed = omega * swinger.amplitude * part.reach
        n = _subframes(speed, exposure_time)
        instants = t0 + exposure_time * (np.arange(n) + 0.5) / n
        angles = theta(instants)
        image = room.albedo.copy()
        x0, y0, x1, y1 = part.box
        image[y0:y1, x0:x1] = 0.0
        for angle in angles:
            colour, cover = part.at(float(angle))
            image[y0:y1, x0:x1] += room.albedo[y0:y1, x0:x1] * (1 - cover[..., None]) \
                + colour * cover[..., None]
        image[y0:y1, x0:x1] /= n
        for hand in hands:
            for t in instants:
                palm = hand.at(float(t))
                if palm is not None:
                    image += (hand.tone - image) * palm[..., None] / n
        # the lamp's light 1 + f cos(2π·2f_mains·t + φ), averaged over the exposure
        w2 = 2 * math.pi * 2 * phone.mains
        mean_cos = (math.sin(w2 * (t0 + exposure_time) + phase) - math.sin(w2 * t0 + phase)) \
            / (w2 * exposure_time)
        light = phone.daylight + (1 - phone.daylight) * room.lamp * (1 + phone.flicker * mean_cos)
        image = image * light
        camera = _camera(phone, w, h, tuple(drift[k]), scale)
        film = cv2.warpPerspective(image, camera, (W, H), flags=cv2.INTER_CUBIC,
                                   borderMode=cv2.BORDER_REPLICATE)
        film = 255 * np.clip(film, 0, 1.2) * vignette
        grain = np.roll(bank[k % 4], (int(rng.integers(H)), int(rng.integers(W))), axis=(0, 1))
        film += (0.2 * np.sqrt(film) + phone.noise) * grain        # shot and read noise
        encoder.write(np.clip(film, 0, 255).astype(np.uint8), float(t0))
    encoder.close()
    swings = _half_swings(np.array([times[0], times[-1]]), crossings)
    mean_period = float(times[-1] - times[0]) / (0.5 * float(swings[1] - swings[0]))
    dense = theta(np.linspace(times[0], times[-1], 20 * times.size))
    return Shot(Path(path), times, phone.container == "avi", swinger.period0, mean_period,
                swinger.amplitude, float(math.sqrt(2 * np.mean(dense ** 2))), dropped)


def _half_swings(t: np.ndarray, crossings: np.ndarray) -> np.ndarray:
    """Half swings done by ``t``: the zero crossings counted, linearly between them (the
    phase of an oscillator is linear in time over a half swing) and beyond the first and
    the last by the nearest half swing's length."""
    n = np.arange(crossings.size, dtype=float)
    out = np.interp(t, crossings, n)
    out = np.where(t < crossings[0], (t - crossings[0]) / (crossings[1] - crossings[0]), out)
    return np.where(t > crossings[-1], n[-1] + (t - crossings[-1])
                    / (crossings[-1] - crossings[-2]), out)
