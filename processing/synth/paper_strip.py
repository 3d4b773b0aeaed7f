"""A light-beam oscillograph's strip, exposed from known signals, then scanned or photographed.

The second family of synthetic paper records (the first is :mod:`.paper_record`; the two share
no drawing or optics code, so a reader tuned on one is checked on the other). It models what
makes a real strip look as it does:

* **exposure** (:class:`Strip`, :class:`Trace`): each galvanometer's light spot, a Gaussian of
  the trace's width, moves across the photographic paper while the paper runs at its speed;
  the energy left per unit length is the lamp's power over the spot's speed on the paper, so
  a steep stroke is fainter than a slow one, and the paper's density follows its
  characteristic curve, D = D_max·(1 − exp(−E/E₀)). A beam at rest (a zero line) exposes a
  straight line; a trace need not have one.
* **marks** (:class:`Marks`): a marker galvanometer's ticks (a short fast excursion up or down
  from its resting line), rectangular pips, a lamp's short dashes or dots with no line, or
  lines flashed across the whole strip; time marks and TDC marks are two such rows with
  their own shape and direction.
* **print** (:class:`Grid`): a printed millimetre grid, finer and bolder lines, absorbing the
  light reflected by the paper (it is ink, not exposure), offset from the paper's edges;
  the paper's fog, grain and tint.

Then the capture, which adds the geometry and the light the reader must see through:

* :class:`Scan`: a flatbed scanner at a given resolution; the strip lies slightly skewed on
  the glass; beyond its edges the lid shows as a light or dark band, and the paper's
  thickness throws a thin shadow along the edges the lamp faces away from (a long straight
  dark line against a light lid); a line sensor's column gain, little blur, noise,
  PNG or JPEG.
* :class:`Photo`: a phone over a table: a pinhole camera tilted and turned over the sheet
  (perspective), a residual barrel distortion (a phone corrects most of its lens's), a wooden table around the sheet, uneven light (a lamp's
  falloff, the phone's shadow, vignetting, a colour cast), defocus and a little motion blur,
  signal-dependent noise, the phone's sharpening and JPEG.

:func:`expose` returns a :class:`StripScene`: the image, its encoded file and the truth (the
map from the sheet to the image, the traces, the marks' times, the straight lines drawn).
:meth:`Scan.draw` and :meth:`Photo.draw` give random captures of the kinds seen in practice.

Sheet coordinates: x [m] along the strip from its left edge (time runs to the right),
y [m] up from its lower edge.

Examples
--------
>>> strip = Strip(length=0.08, width=0.05, speed=0.4,
...               traces=(Trace(lambda t: np.sin(2 * np.pi * 20 * t), 0.025, 0.01),),
...               marks=(Marks(np.arange(0, 0.2, 0.01), 0.004, role="time"),))
>>> scene = expose(strip, Scan(dpi=150, jpeg=None), seed=1)
>>> scene.image.shape[2], scene.times("time").size
(3, 20)
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

SHAPES = ("tick", "pip", "dash", "dot", "across")
"""Mark shapes: a marker beam's short excursion from its resting line (``tick``), a longer
rectangular one (``pip``), a lamp's flash on a spot with no line (``dash``: as long as the
flash, ``dot``: a round spot), a flash across the whole strip (``across``)."""

D_MAX = 1.3
"""Highest optical density the developed paper reaches."""

MAX_CANVAS = 25_000.0
"""Finest resolution the sheet is exposed at. [px/m]"""


@dataclass(frozen=True)
class Trace:
    """One galvanometer's beam.

    Parameters
    ----------
    signal : callable
        ``signal(t)``, vectorised over times t [s]. [any unit]
    base : float
        Height of the signal's zero above the strip's lower edge. [m]
    gain : float
        Deflection per unit of the signal, upwards positive. [m per unit]
    zero_line : bool
        Also expose the beam at rest: a straight line at ``base`` along the whole strip.
    width : float
        FWHM of the light spot across the trace. [m]
    exposure : float
        Exposure of a stroke moving at the paper's speed alone, in units of the paper's E₀
        (the density at its core is D_max·(1 − exp(−exposure))).
    """

    signal: Callable[[np.ndarray], np.ndarray]
    base: float
    gain: float
    zero_line: bool = False
    width: float = 0.0003
    exposure: float = 6.0

    def height(self, t) -> np.ndarray:
        """The trace's height above the lower edge at times ``t``. [m]"""
        t = np.asarray(t, dtype=float)
        return self.base + self.gain * np.asarray(self.signal(t), dtype=float)


@dataclass(frozen=True)
class Marks:
    """A row of marks: time marks, TDC marks, any event a marker records.

    Parameters
    ----------
    times : sequence of float
        When each mark begins. [s]
    at : float
        Height of the row (the marker beam's resting line) above the lower edge. [m]
    shape : str
        One of :data:`SHAPES`.
    direction : {1, -1}
        A tick or pip points up (1) or down (−1).
    size : float
        A tick's or pip's height, a dot's diameter (give a dot its own: 0.5–1 mm). [m]
    duration : float
        How long a mark lasts: a tick's or pip's excursion, a dash's flash. [s]
    rise : float
        Share of ``duration`` a tick or pip takes to rise (and to fall): the marker's
        galvanometer is fast but not instant, so its strokes are fainter than the line.
    width : float
        FWHM of the marker's spot. [m]
    exposure : float
        As :attr:`Trace.exposure`.
    role : str
        What the marks are (``"time"``, ``"tdc"``, …): :meth:`StripScene.times` looks them up
        by it.
    """

    times: Sequence[float]
    at: float
    shape: str = "tick"
    direction: int = 1
    size: float = 0.002
    duration: float = 0.001
    rise: float = 0.15
    width: float = 0.00025
    exposure: float = 10.0
    role: str = "time"

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ValueError(f"Marks: shape {self.shape!r} is not one of {SHAPES}")
        if self.direction not in (1, -1):
            raise ValueError(f"Marks: direction must be 1 or -1, got {self.direction!r}")

    @property
    def line(self) -> bool:
        """Whether the marker's resting beam exposes a line (ticks and pips)."""
        return self.shape in ("tick", "pip")

    def offset(self, t: np.ndarray, times: np.ndarray) -> np.ndarray:
        """The marker beam's excursion from its line at times ``t`` (a trapezoid per mark). [m]"""
        out = np.zeros_like(t)
        ramp = max(self.rise * self.duration, 1e-12)
        for t0 in times:
            u = t - t0
            near = (u > -ramp) & (u < self.duration + ramp)
            up = np.clip(u[near] / ramp, 0, 1) * np.clip((self.duration - u[near]) / ramp, 0, 1)
            out[near] = np.maximum(out[near], up)
        return self.direction * self.size * out


@dataclass(frozen=True)
class Grid:
    """A millimetre grid printed on the paper.

    Parameters
    ----------
    pitch : float
        Spacing of the fine lines. [m]
    major : int
        Every ``major``-th line is bold (0: none).
    width : float
        Width of a fine line; a bold one is twice as wide. [m]
    density : float
        Share of the light a fine line absorbs (a bold one absorbs more).
    colour : (int, int, int)
        The ink's colour, BGR.
    origin : (float, float)
        Where a bold line crosses another, from the lower left corner. [m]
    """

    pitch: float = 0.001
    major: int = 10
    width: float = 0.0001
    density: float = 0.25
    colour: tuple[int, int, int] = (90, 140, 220)
    origin: tuple[float, float] = (0.0017, 0.0023)


@dataclass(frozen=True)
class Strip:
    """The exposed strip: its size and speed, what the beams drew, what was printed on it.

    Parameters
    ----------
    length, width : float
        Along the time axis and across it. [m]
    speed : float
        Paper speed. [m/s]
    start : float
        Time at the left edge. [s]
    traces : sequence of Trace
    marks : sequence of Marks
    grid : Grid or None
    tint : (int, int, int)
        The developed paper's colour, BGR.
    ink : (float, float, float)
        Relative density of the traces in the B, G, R channels (violet-brown: more in green).
    fog : float
        Density of the unexposed paper.
    grain : float
        Relative σ of the paper's grain.
    """

    length: float = 0.25
    width: float = 0.12
    speed: float = 0.5
    start: float = 0.0
    traces: Sequence[Trace] = ()
    marks: Sequence[Marks] = ()
    grid: Grid | None = None
    tint: tuple[int, int, int] = (228, 236, 240)
    ink: tuple[float, float, float] = (0.8, 1.0, 0.85)
    fog: float = 0.03
    grain: float = 0.015

    @property
    def duration(self) -> float:
        """The time the strip spans. [s]"""
        return self.length / self.speed

    def x_of(self, t) -> np.ndarray:
        """Where time ``t`` lies along the strip. [m]"""
        return (np.asarray(t, dtype=float) - self.start) * self.speed


# ------------------------------------------------------------------------ the captures

@dataclass(frozen=True)
class Scan:
    """A flatbed scan of the strip.

    Parameters
    ----------
    dpi : float
        Scan resolution. [dots per inch]
    skew : float
        The strip's angle on the glass, counter-clockwise. [deg]
    margins : (float, float, float, float)
        Lid shown beyond the strip's left, right, lower and upper edges (negative: the scan
        cuts the strip there). [m]
    lid : (int, int, int)
        The lid's colour, BGR (white foam or a black cover).
    shadow : (float, float, float, float)
        Depth of the shadow the paper's edge throws on the lid along its left, right, lower
        and upper edges (share of the light lost at the edge).
    shadow_width : float
        The shadow's width. [m]
    blur : float
        σ of the scanner's blur. [px]
    noise : float
        σ of its noise. [grey levels]
    column_gain : float
        Relative σ of the line sensor's gain from column to column.
    jpeg : int or None
        JPEG quality (None: PNG).
    """

    dpi: float = 300.0
    skew: float = 0.6
    margins: tuple[float, float, float, float] = (0.01, 0.01, 0.012, 0.015)
    lid: tuple[int, int, int] = (246, 246, 244)
    shadow: tuple[float, float, float, float] = (0.1, 0.5, 0.1, 0.6)
    shadow_width: float = 0.0004
    blur: float = 0.6
    noise: float = 1.5
    column_gain: float = 0.004
    jpeg: int | None = 92

    @classmethod
    def draw(cls, rng: np.random.Generator, *, dpi: float | None = None) -> Scan:
        """A random scan as students make them: 200–600 dpi (or ``dpi``), skew up to 2°,
        a light lid (two in three) or a dark one, lid bands up to 15 mm (an edge sometimes cut),
        the edge shadow on the sides away from the lamp, PNG or JPEG 80–95."""
        light = rng.random() < 2 / 3
        lid = tuple(int(v) for v in (rng.uniform(236, 252, 3) if light else rng.uniform(15, 45, 3)))
        margins = tuple(float(v) for v in np.where(rng.random(4) < 0.15,
                                                   -rng.uniform(0.0005, 0.003, 4),
                                                   rng.uniform(0.002, 0.015, 4)))
        away = rng.random() < 0.5
        shadow = tuple(float(v) for v in rng.uniform(0.3, 0.7, 4)
                       * (np.array([away, not away, away, not away]) + 0.15))
        return cls(dpi=float(dpi if dpi is not None else rng.choice([200, 300, 400, 600])),
                   skew=float(rng.uniform(-2, 2)), margins=margins, lid=lid, shadow=shadow,
                   shadow_width=float(rng.uniform(0.0002, 0.0008)),
                   blur=float(rng.uniform(0.4, 1.0)), noise=float(rng.uniform(0.5, 3.0)),
                   column_gain=float(rng.uniform(0.0, 0.008)),
                   jpeg=None if rng.random() < 0.3 else int(rng.integers(80, 96)))


@dataclass(frozen=True)
class Photo:
    """A phone photograph of the strip lying on a table.

    Parameters
    ----------
    size : (int, int)
        Image width and height. [px]
    fov : float
        Horizontal field of view. [deg]
    fill : float
        The strip's length as a share of the image width, seen square on.
    yaw : float
        The strip's turn in the image, counter-clockwise. [deg]
    tilt : (float, float)
        The camera's tilt away from looking straight down, about the image's horizontal and
        vertical axes. [deg]
    shift : (float, float)
        The strip's centre off the image centre, as shares of the width and height.
    distortion : float
        Radial distortion k₁ (negative: barrel).
    table : (int, int, int)
        The table's colour, BGR.
    light : float
        Depth of the lamp's falloff across the frame (share of the light lost far from it).
    shade : float
        Depth of the phone's soft shadow (0: none).
    vignetting : float
        Light lost in the image corners.
    cast : (float, float, float)
        White balance gains, BGR.
    blur : float
        σ of the defocus. [px]
    motion : float
        Length of the hand's motion blur. [px]
    noise : float
        σ of the noise at mid-grey. [grey levels]
    sharpen : float
        Strength of the phone's unsharp mask.
    jpeg : int
        JPEG quality.
    """

    size: tuple[int, int] = (3000, 2000)
    fov: float = 66.0
    fill: float = 0.85
    yaw: float = 1.0
    tilt: tuple[float, float] = (4.0, -3.0)
    shift: tuple[float, float] = (0.0, 0.0)
    distortion: float = -0.008
    table: tuple[int, int, int] = (60, 95, 140)
    light: float = 0.25
    shade: float = 0.2
    vignetting: float = 0.25
    cast: tuple[float, float, float] = (0.95, 1.0, 1.05)
    blur: float = 1.0
    motion: float = 1.5
    noise: float = 3.0
    sharpen: float = 0.4
    jpeg: int = 88

    @classmethod
    def draw(cls, rng: np.random.Generator, *, size: tuple[int, int] | None = None) -> Photo:
        """A random phone photograph: 12 MP (or ``size``), the strip filling 68–85 % of the
        width (the whole strip in the frame), turned up to 3°, tilted up to 6°, a wooden or
        grey table, a lamp's falloff,
        sometimes the phone's shadow, blur σ 0.6–2 px, motion up to 3 px, JPEG 70–92."""
        wood = rng.random() < 0.6
        table = (rng.uniform([40, 70, 110], [80, 120, 170]) if wood
                 else np.full(3, rng.uniform(70, 170)) + rng.uniform(-8, 8, 3))
        return cls(size=size or (4000, 3000), fov=float(rng.uniform(60, 75)),
                   fill=float(rng.uniform(0.68, 0.85)), yaw=float(rng.uniform(-3, 3)),
                   tilt=tuple(float(v) for v in rng.uniform(-6, 6, 2)),
                   shift=tuple(float(v) for v in rng.uniform(-0.02, 0.02, 2)),
                   distortion=float(rng.uniform(-0.012, 0.004)),
                   table=tuple(int(v) for v in table), light=float(rng.uniform(0.05, 0.4)),
                   shade=float(rng.uniform(0.15, 0.45) if rng.random() < 0.4 else 0.0),
                   vignetting=float(rng.uniform(0.1, 0.35)),
                   cast=tuple(float(v) for v in rng.uniform(0.96, 1.04, 3)),
                   blur=float(rng.uniform(0.6, 2.0)), motion=float(rng.uniform(0, 3)),
                   noise=float(rng.uniform(1.5, 5)), sharpen=float(rng.uniform(0, 0.8)),
                   jpeg=int(rng.integers(70, 93)))


# ------------------------------------------------------------------------ the scene

@dataclass(frozen=True)
class StripScene:
    """An exposed and captured strip, and its truth.

    Attributes
    ----------
    image : numpy.ndarray
        The capture, BGR uint8, as decoded from :attr:`encoded`.
    encoded : bytes
        The file: PNG or JPEG.
    strip : Strip
    capture : Scan or Photo
    """

    image: np.ndarray
    encoded: bytes
    strip: Strip
    capture: Scan | Photo
    _forward: Callable[[np.ndarray], np.ndarray] = field(repr=False)

    @property
    def suffix(self) -> str:
        """The file's suffix: ``.jpg`` or ``.png``."""
        return ".jpg" if self.encoded[:2] == b"\xff\xd8" else ".png"

    def to_image(self, points) -> np.ndarray:
        """Sheet points (x, y) [m] → image pixels (column, row; pixel centres at whole
        numbers)."""
        return self._forward(np.asarray(points, dtype=float).reshape(-1, 2))

    @property
    def pixels_per_metre(self) -> float:
        """Image pixels per metre of sheet at the strip's centre. [px/m]"""
        c = np.array([self.strip.length / 2, self.strip.width / 2])
        p = self.to_image([c, c + [1e-3, 0], c + [0, 1e-3]])
        return float(np.mean(np.hypot(*(p[1:] - p[0]).T)) / 1e-3)

    def times(self, role: str) -> np.ndarray:
        """Start times of the marks of ``role`` drawn whole on the strip. [s]"""
        out = [_whole(self.strip, m) for m in self.strip.marks if m.role == role]
        return np.sort(np.concatenate(out)) if out else np.empty(0)

    def lines(self) -> dict[str, list[np.ndarray]]:
        """The long straight lines in the image, each as its two end points (column, row):
        ``"zero"`` (the traces' zero lines), ``"marks"`` (the marker's resting lines),
        ``"edges"`` (the sheet's lower and upper edges), ``"grid"`` (the printed lines along
        the time axis)."""
        s = self.strip
        along = {"zero": [t.base for t in s.traces if t.zero_line],
                 "marks": [m.at for m in s.marks if m.line],
                 "edges": [0.0, s.width],
                 "grid": list(_grid_rows(s)) if s.grid else []}
        return {k: [self.to_image([[0, y], [s.length, y]]) for y in ys] for k, ys in along.items()}

    def write(self, path) -> Path:
        """Write the encoded file (a ``.jpg``/``.png`` name matching it), or re-encode for
        another suffix."""
        path = Path(path)
        if path.suffix.lower() in ((".jpg", ".jpeg") if self.suffix == ".jpg" else (".png",)):
            path.write_bytes(self.encoded)
        elif not cv2.imwrite(str(path), self.image):
            raise ValueError(f"StripScene.write: OpenCV cannot write {path.suffix!r} files")
        return path


def expose(strip: Strip, capture: Scan | Photo, *, seed: int = 0) -> StripScene:
    """Expose the strip and capture it.

    Parameters
    ----------
    strip : Strip
    capture : Scan or Photo
    seed : int
        Seed of the grain, the table, the shadows and the noise.

    Returns
    -------
    StripScene
    """
    rng = np.random.default_rng([seed, 2807])
    geometry = (_scan_geometry(strip, capture) if isinstance(capture, Scan)
                else _photo_geometry(strip, capture))
    res = min(MAX_CANVAS, 1.3 * geometry.finest)
    sheet = _develop(strip, res, rng)
    u, v = np.meshgrid(np.arange(geometry.size[0], dtype=np.float64),
                       np.arange(geometry.size[1], dtype=np.float64))
    x, y = (c.astype(np.float32) for c in geometry.backward(u, v))
    if isinstance(capture, Scan):
        image = _scan(sheet, res, strip, capture, x, y, rng)
    else:
        image = _photograph(sheet, res, strip, capture, x, y, rng)
    encoded = _encode(image, capture.jpeg)
    decoded = cv2.imdecode(np.frombuffer(encoded, np.uint8), cv2.IMREAD_COLOR)
    return StripScene(decoded, encoded, strip, capture, geometry.forward)


# ------------------------------------------------------------------------ exposure

def _whole(strip: Strip, marks: Marks) -> np.ndarray:
    t = np.asarray(marks.times, dtype=float)
    end = strip.start + strip.duration
    span = 0.0 if marks.shape in ("dot", "across") else marks.duration
    return t[(t >= strip.start) & (t + span <= end)]


def _develop(strip: Strip, res: float, rng: np.random.Generator) -> np.ndarray:
    """The developed strip's reflectance, float32 BGR in [0, 1], ``res`` px per metre; row 0
    is the upper edge."""
    w, h = int(math.ceil(strip.length * res)), int(math.ceil(strip.width * res))
    film = _Film(h, w)
    for trace in strip.traces:
        _beam(film, strip, res, trace.height, trace.width, trace.exposure)
        if trace.zero_line:
            _beam(film, strip, res, lambda t, b=trace.base: np.full_like(t, b),
                  trace.width, trace.exposure)
    for marks in strip.marks:
        _marks(film, strip, res, marks)
    density = strip.fog + D_MAX * (1 - np.exp(-film.exposure()))
    grain = cv2.resize(rng.standard_normal((max(h // 4, 2), max(w // 4, 2))), (w, h),
                       interpolation=cv2.INTER_CUBIC)
    paper = np.asarray(strip.tint, np.float32) / 255
    reflect = paper * 10.0 ** (-density[..., None] * np.asarray(strip.ink, np.float32))
    reflect *= (1 + strip.grain * grain.astype(np.float32))[..., None]
    if strip.grid is not None:
        reflect *= _grid_print(strip, strip.grid, res, w, h)
    return np.clip(reflect, 0, 1).astype(np.float32)


def _beam(film, strip: Strip, res: float, height, width: float, energy: float,
          window: tuple[float, float] | None = None) -> None:
    """Lay a moving spot's exposure: sampled finely in time, each sample leaving the energy of
    its time step (so a fast stroke leaves less per length), blurred by the spot."""
    t0, t1 = window or (strip.start, strip.start + strip.duration)
    coarse = np.linspace(t0, t1, max(int((t1 - t0) * strip.speed * res) * 2, 16))
    step = np.hypot(np.diff(strip.x_of(coarse)), np.diff(height(coarse))).max() * res
    t = np.linspace(t0, t1, max(int(coarse.size * step / 0.3), coarse.size))
    x, y = strip.x_of(t) * res, (strip.width - height(t)) * res
    sigma = width * res / 2.3548
    # a line drawn at the paper's speed alone peaks at ``energy`` after the spot's blur
    mass = energy * math.sqrt(2 * math.pi) * sigma * (t[1] - t[0]) * strip.speed * res
    film.splat(x, y, np.full(t.size, mass), sigma)


def _marks(film, strip: Strip, res: float, marks: Marks) -> None:
    times = np.asarray(marks.times, dtype=float)
    sigma = marks.width * res / 2.3548
    if marks.line:
        _beam(film, strip, res, lambda t: marks.at + marks.offset(t, times), marks.width,
              marks.exposure)
    elif marks.shape == "dash":
        for t0 in times:
            _beam(film, strip, res, lambda t: np.full_like(t, marks.at), marks.width,
                  marks.exposure, (max(t0, strip.start), min(t0 + marks.duration,
                                                             strip.start + strip.duration)))
    elif marks.shape == "dot":
        r = marks.size / 2 * res
        gy, gx = np.mgrid[-r:r + 0.25:0.25, -r:r + 0.25:0.25]
        disk = gx ** 2 + gy ** 2 <= r * r
        for x in strip.x_of(times) * res:
            film.splat(x + gx[disk], (strip.width - marks.at) * res + gy[disk],
                   np.full(disk.sum(), marks.exposure * 0.0625), sigma)
    else:   # across: a flash over the whole width
        ys = np.arange(0, strip.width * res, 0.25)
        for x in strip.x_of(times) * res:
            film.splat(np.full(ys.size, x), ys,
                   np.full(ys.size, marks.exposure * math.sqrt(2 * math.pi) * sigma * 0.25),
                   sigma)


class _Film:
    """The paper's exposure: point masses laid at sub-pixel positions (pixel centres at whole
    numbers, bilinear), one layer per spot width, each blurred by its Gaussian spot at the
    end."""

    def __init__(self, h: int, w: int):
        self.shape = (h, w)
        self.layers: dict[float, np.ndarray] = {}

    def splat(self, x, y, mass, sigma: float) -> None:
        h, w = self.shape
        layer = self.layers.setdefault(round(max(sigma, 0.3), 3), np.zeros(h * w, np.float64))
        ix, iy = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
        fx, fy = x - ix, y - iy
        cx = np.concatenate([ix, ix + 1, ix, ix + 1])
        cy = np.concatenate([iy, iy, iy + 1, iy + 1])
        wt = np.concatenate([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy])
        ok = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
        layer += np.bincount(cy[ok] * w + cx[ok], weights=(np.tile(mass, 4) * wt)[ok],
                             minlength=h * w)

    def exposure(self) -> np.ndarray:
        out = np.zeros(self.shape, np.float32)
        for sigma, layer in self.layers.items():
            out += cv2.GaussianBlur(layer.reshape(self.shape).astype(np.float32), (0, 0), sigma)
        return out


def _grid_rows(strip: Strip) -> np.ndarray:
    g = strip.grid
    return np.arange((g.origin[1] % g.pitch), strip.width, g.pitch)


def _grid_print(strip: Strip, grid: Grid, res: float, w: int, h: int) -> np.ndarray:
    """The grid's transmission of the reflected light, BGR: each line a box of its width,
    averaged over the pixel."""
    def cover(coord, origin):
        k = np.round((coord - origin) / grid.pitch)
        d = np.abs(coord - origin - k * grid.pitch)
        bold = (grid.major > 0) & (np.mod(k, max(grid.major, 1)) == 0)
        half = np.where(bold, grid.width, grid.width / 2)
        c = np.clip((half - d) * res + 0.5, 0, 1)
        return c * np.where(bold, min(1.0, 1.8 * grid.density), grid.density)

    x = (np.arange(w) + 0.5) / res
    y = strip.width - (np.arange(h) + 0.5) / res
    a = np.maximum(cover(x, grid.origin[0])[None, :], cover(y, grid.origin[1])[:, None])
    ink = np.asarray(grid.colour, np.float32) / 255
    return 1 - a.astype(np.float32)[..., None] * (1 - ink)


# ------------------------------------------------------------------------ geometry

@dataclass(frozen=True)
class _Geometry:
    size: tuple[int, int]
    finest: float
    """Largest image pixels per metre of sheet."""
    forward: Callable[[np.ndarray], np.ndarray]
    backward: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def _scan_geometry(strip: Strip, scan: Scan) -> _Geometry:
    """A rigid placement on the glass: image pixel (u, v) ↔ sheet (x, y)."""
    s = scan.dpi / 0.0254
    left, right, low, up = scan.margins
    a = math.radians(scan.skew)
    c, sn = math.cos(a), math.sin(a)
    half = np.array([strip.length, strip.width]) / 2
    # the strip's bounding box on the glass, turned, plus the lid bands
    ext = np.abs(np.array([[c, -sn], [sn, c]])) @ half
    size = (int(round((2 * ext[0] + left + right) * s)), int(round((2 * ext[1] + low + up) * s)))
    centre = np.array([(left + ext[0]) * s - 0.5, (up + ext[1]) * s - 0.5])

    def forward(p):
        d = p - half
        return centre + s * np.stack([c * d[:, 0] - sn * d[:, 1],
                                      -(sn * d[:, 0] + c * d[:, 1])], axis=1)

    def backward(u, v):
        du, dv = (u - centre[0]) / s, -(v - centre[1]) / s
        return half[0] + c * du + sn * dv, half[1] - sn * du + c * dv

    return _Geometry(size, s, forward, backward)


def _photo_geometry(strip: Strip, photo: Photo) -> _Geometry:
    """A pinhole camera over the sheet's plane, with radial distortion."""
    w, h = photo.size
    f = w / 2 / math.tan(math.radians(photo.fov) / 2)
    distance = f * strip.length / (photo.fill * w)
    ax, ay = (math.radians(v) for v in photo.tilt)
    yaw = math.radians(photo.yaw)
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(yaw), math.sin(yaw), 0], [-math.sin(yaw), math.cos(yaw), 0],
                   [0, 0, 1]])
    rot = rx @ ry @ rz
    # plane point (X, Y, 0), Y up on the sheet → camera coordinates (y down in the image)
    flip = np.diag([1.0, -1.0, 1.0])
    centre_off = np.array([photo.shift[0] * w / f, photo.shift[1] * h / f, 1.0]) * distance
    hom = np.column_stack([(rot @ flip)[:, 0], (rot @ flip)[:, 1], centre_off])
    inv = np.linalg.inv(hom)
    half = np.array([strip.length, strip.width]) / 2
    k1 = photo.distortion
    cx, cy = (w - 1) / 2, (h - 1) / 2
    norm = math.hypot(w, h) / 2 / f     # r normalised to the frame's half-diagonal

    def forward(p):
        q = hom @ np.vstack([(p - half).T, np.ones(len(p))])
        xn, yn = q[0] / q[2], q[1] / q[2]
        g = 1 + k1 * (xn ** 2 + yn ** 2) / norm ** 2
        return np.stack([f * xn * g + cx, f * yn * g + cy], axis=1)

    def backward(u, v):
        xd, yd = (u - cx) / f, (v - cy) / f
        xn, yn = xd, yd
        for _ in range(6):
            g = 1 + k1 * (xn ** 2 + yn ** 2) / norm ** 2
            xn, yn = xd / g, yd / g
        q0 = inv[0, 0] * xn + inv[0, 1] * yn + inv[0, 2]
        q1 = inv[1, 0] * xn + inv[1, 1] * yn + inv[1, 2]
        q2 = inv[2, 0] * xn + inv[2, 1] * yn + inv[2, 2]
        return half[0] + q0 / q2, half[1] + q1 / q2

    corners = forward(np.array([[0, 0], [strip.length, 0], [strip.length, strip.width],
                                [0, strip.width]]))
    finest = max(np.hypot(*(corners[1] - corners[0])) / strip.length,
                 np.hypot(*(corners[2] - corners[3])) / strip.length,
                 np.hypot(*(corners[3] - corners[0])) / strip.width,
                 np.hypot(*(corners[2] - corners[1])) / strip.width)
    return _Geometry((w, h), float(finest), forward, backward)


def _sample(sheet: np.ndarray, res: float, strip: Strip, x, y) -> tuple[np.ndarray, np.ndarray]:
    """The sheet's reflectance at sheet points, and how much of each pixel the sheet covers."""
    mx = (x * res - 0.5).astype(np.float32)
    my = ((strip.width - y) * res - 0.5).astype(np.float32)
    seen = cv2.remap(sheet, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    # coverage: the sheet's extent at the image's resolution (a pixel's share inside)
    px = np.hypot(np.gradient(x, axis=1), np.gradient(y, axis=1)) + 1e-12
    inside = np.minimum.reduce([x / px + 0.5, (strip.length - x) / px + 0.5, y / px + 0.5,
                                (strip.width - y) / px + 0.5])
    return seen, np.clip(inside, 0, 1).astype(np.float32)


def _outside(strip: Strip, x, y) -> np.ndarray:
    """Distance beyond each of the four edges (left, right, lower, upper), ≥ 0. [m]"""
    return np.stack([np.maximum(-x, 0), np.maximum(x - strip.length, 0), np.maximum(-y, 0),
                     np.maximum(y - strip.width, 0)])


# ------------------------------------------------------------------------ the captures

def _scan(sheet, res, strip: Strip, scan: Scan, x, y, rng) -> np.ndarray:
    seen, cover = _sample(sheet, res, strip, x, y)
    h, w = cover.shape
    lid = np.asarray(scan.lid, np.float32) / 255
    texture = 1 + 0.01 * cv2.resize(rng.standard_normal((max(h // 8, 2), max(w // 8, 2))),
                                    (w, h)).astype(np.float32)
    out = _outside(strip, x, y)
    shade = np.zeros((h, w), np.float32)
    beyond = (out > 0).sum(axis=0)
    for k, depth in enumerate(scan.shadow):
        # the shadow lies along the edge, on the lid, beyond that edge alone
        near = (out[k] > 0) & (out[k] < 8 * scan.shadow_width) & (beyond == 1)
        shade[near] = np.maximum(shade[near], depth * np.exp(-out[k][near] / scan.shadow_width))
    back = lid * (texture * (1 - shade))[..., None]
    image = seen * cover[..., None] + back * (1 - cover[..., None])
    image *= (1 + scan.column_gain * rng.standard_normal(w)).astype(np.float32)[None, :, None]
    image = image * 255
    if scan.blur > 0:
        image = cv2.GaussianBlur(image, (0, 0), scan.blur)
    image += rng.normal(0, scan.noise, image.shape).astype(np.float32)
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def _photograph(sheet, res, strip: Strip, photo: Photo, x, y, rng) -> np.ndarray:
    seen, cover = _sample(sheet, res, strip, x, y)
    h, w = cover.shape
    image = seen * cover[..., None] + _table(photo, x, y, rng) * (1 - cover[..., None])
    image *= _light(photo, w, h, rng)[..., None]
    image = image * np.asarray(photo.cast, np.float32) * 255
    if photo.blur > 0:
        image = cv2.GaussianBlur(image, (0, 0), photo.blur)
    if photo.motion >= 1:
        image = cv2.filter2D(image, -1, _motion_kernel(photo.motion, rng.uniform(0, np.pi)))
    image += (rng.standard_normal(image.shape) * photo.noise
              * np.sqrt(np.clip(image, 1, 255) / 128)).astype(np.float32)
    if photo.sharpen > 0:
        image += photo.sharpen * (image - cv2.GaussianBlur(image, (0, 0), 2.0))
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def _table(photo: Photo, x, y, rng) -> np.ndarray:
    """A wooden (or plain) table top in the sheet's plane: streaks along a direction, knots of
    darker grain."""
    a = rng.uniform(0, np.pi)
    along = x * math.cos(a) + y * math.sin(a)
    across = -x * math.sin(a) + y * math.cos(a)
    h, w = x.shape
    wander = cv2.resize(rng.standard_normal((6, 6)), (w, h), interpolation=cv2.INTER_CUBIC)
    streaks = (0.06 * np.sin(2 * np.pi * across / rng.uniform(0.004, 0.012)
                             + 3 * np.sin(2 * np.pi * along / rng.uniform(0.1, 0.3)) + 2 * wander)
               + 0.03 * np.sin(2 * np.pi * across / rng.uniform(0.0015, 0.003)) + 0.04 * wander)
    colour = np.asarray(photo.table, np.float32) / 255
    return (colour * (1 + streaks.astype(np.float32))[..., None]).astype(np.float32)


def _light(photo: Photo, w: int, h: int, rng) -> np.ndarray:
    """Illumination over the frame: a lamp's falloff, the phone's soft shadow, vignetting."""
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    lamp = rng.uniform([-0.5 * w, -0.5 * h], [1.5 * w, 1.5 * h])
    d2 = ((xx - lamp[0]) ** 2 + (yy - lamp[1]) ** 2) / (w * w + h * h)
    light = 1 - photo.light * np.clip(d2, 0, 1)
    if photo.shade > 0:
        c = rng.uniform([0.2 * w, 0.2 * h], [0.8 * w, 0.8 * h])
        r = rng.uniform(0.15, 0.35) * w
        blob = np.exp(-(((xx - c[0]) / r) ** 2 + ((yy - c[1]) / (0.6 * r)) ** 2) ** 2)
        light *= 1 - photo.shade * blob
    r2 = ((xx - w / 2) ** 2 + (yy - h / 2) ** 2) / ((w / 2) ** 2 + (h / 2) ** 2)
    return light * (1 - photo.vignetting * r2 ** 1.5)


def _motion_kernel(length: float, angle: float) -> np.ndarray:
    n = int(math.ceil(length)) | 1
    k = np.zeros((n, n), np.float32)
    c = n // 2
    for s in np.linspace(-length / 2, length / 2, 4 * n):
        k[int(round(c + s * math.sin(angle))), int(round(c + s * math.cos(angle)))] += 1
    return k / k.sum()


def _encode(image: np.ndarray, jpeg: int | None) -> bytes:
    ok, buf = (cv2.imencode(".png", image) if jpeg is None
               else cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, int(jpeg)]))
    if not ok:
        raise RuntimeError("expose: OpenCV could not encode the image")
    return buf.tobytes()
