"""A light-beam oscillograph's paper record, photographed or scanned, drawn from known signals.

The scene behind the paper-record reader (:mod:`processing.vision`). A strip of photographic
paper (:class:`Layout`: 120 mm wide, as the manual's torsiograph records, moving at a known
speed) carries:

* the beams' traces (:class:`Beam`): each draws ``zero + gain·signal(t)`` across the paper,
  optionally with its straight zero line;
* the time-mark line near the lower edge: a straight line with a rectangular pip every
  ``mark_period`` (its rising edge at t = k·T_mark);
* the TDC line near the upper edge, with a pip at each TDC time;
* optionally a printed grid.

The beams expose one ink layer (where traces cross, the exposure saturates), a printed grid
absorbs its share of the light on top, and the paper has grain. The camera (:class:`Shot`) sees the sheet on a darker desk: scaled to fill a part of
the frame, rotated, with a slight perspective (each corner moved at random), uneven light
(vignetting, a gradient), blur, noise and JPEG compression. With ``fill > 1`` the sheet
overflows the frame, as on a flatbed scan cropped inside the paper.

:func:`render` returns a :class:`PaperScene`: the image and the truth (the homography from
the paper to the image, the signals, the mark times), and :meth:`PaperScene.compare` judges
a trace read off the image against the true signal.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

SUPERSAMPLE = 2
"""The sheet is drawn at this multiple of its final resolution, then averaged down."""


@dataclass(frozen=True)
class Beam:
    """One galvanometer's beam.

    Parameters
    ----------
    signal : callable
        ``signal(t)``: the recorded quantity at times ``t`` [s], vectorised. [any unit]
    zero : float
        Height of the beam's zero above the paper's lower edge. [m]
    gain : float
        Deflection per unit of the signal, upwards positive. [m per unit]
    zero_line : bool
        Also draw the straight zero line (the beam at rest).
    """

    signal: Callable[[np.ndarray], np.ndarray]
    zero: float
    gain: float
    zero_line: bool = False

    def height(self, t) -> np.ndarray:
        """The trace's height above the paper's lower edge at times ``t``. [m]"""
        return self.zero + self.gain * np.asarray(self.signal(np.asarray(t, dtype=float)),
                                                  dtype=float)


@dataclass(frozen=True)
class Layout:
    """The paper strip and what the oscillograph draws on it besides the traces.

    Parameters
    ----------
    length, width : float
        The sheet along the time axis and across it. [m]
    speed : float
        Paper speed. [m/s]
    start : float
        Time at the sheet's left edge. [s]
    mark_period : float
        Period of the time marks. [s]
    marks_at : float
        Height of the time-mark line above the lower edge. [m]
    pip_height : float
        Height of a pip above its line. [m]
    pip_duty : float
        Fraction of a mark period a time-mark pip lasts.
    tdc_times : sequence of float
        TDC times; the TDC line is drawn only with some. [s]
    tdc_at : float
        Height of the TDC line above the lower edge (its pips point up). [m]
    tdc_pip : float
        Duration of a TDC pip. [s]
    line_width : float
        Width of traces and lines. [m]
    grid : float or None
        Spacing of a printed square grid. [m]
    grid_width : float
        Width of the grid's lines. [m]
    """

    length: float = 0.25
    width: float = 0.12
    speed: float = 0.5
    start: float = 0.0
    mark_period: float = 0.01
    marks_at: float = 0.006
    pip_height: float = 0.0025
    pip_duty: float = 0.3
    tdc_times: Sequence[float] = ()
    tdc_at: float = 0.110
    tdc_pip: float = 0.003
    line_width: float = 0.0003
    grid: float | None = None
    grid_width: float = 0.00012

    @property
    def duration(self) -> float:
        """Time the sheet spans. [s]"""
        return self.length / self.speed

    def mark_times(self) -> np.ndarray:
        """Rising edges of the time marks on the sheet (whole pips only). [s]"""
        k0 = np.ceil(self.start / self.mark_period - 1e-9)
        k1 = np.floor((self.start + self.duration) / self.mark_period
                      - self.pip_duty - 1e-9)
        return np.arange(k0, k1 + 1) * self.mark_period


@dataclass(frozen=True)
class Shot:
    """How the sheet is photographed or scanned.

    Parameters
    ----------
    size : (int, int)
        Image width and height. [px]
    fill : float
        The sheet's length as a fraction of the image width (> 1: it overflows the frame).
    rotation : float
        Rotation of the sheet in the image, counter-clockwise. [deg]
    perspective : float
        Random displacement of each corner, as a fraction of the image's width (a phone
        held at a slant: 0.01–0.03).
    blur : float
        σ of the Gaussian camera or print blur. [px]
    noise : float
        σ of the sensor's white noise. [grey levels]
    jpeg : int or None
        JPEG quality (None: no compression).
    vignetting : float
        Light lost at the image's corners (0.3: 30 %).
    gradient : float
        Light falling linearly across the image from left to right (0.1: 10 %).
    grain : float
        Relative σ of the paper's grain.
    tint : (int, int, int)
        Paper colour, BGR.
    ink : (int, int, int)
        Colour of the exposed traces, BGR.
    ink_density : float
        Fraction of light a trace's core absorbs.
    grid_density : float
        Fraction of light a grid line absorbs.
    desk : (int, int, int)
        Background colour, BGR.
    """

    size: tuple[int, int] = (1600, 800)
    fill: float = 0.9
    rotation: float = 0.0
    perspective: float = 0.0
    blur: float = 0.7
    noise: float = 2.0
    jpeg: int | None = 92
    vignetting: float = 0.15
    gradient: float = 0.05
    grain: float = 0.02
    tint: tuple[int, int, int] = (205, 225, 235)
    ink: tuple[int, int, int] = (70, 35, 60)
    ink_density: float = 0.85
    grid_density: float = 0.3
    desk: tuple[int, int, int] = (55, 70, 90)


PHONE = Shot(size=(2400, 1200), fill=0.85, rotation=1.5, perspective=0.005, blur=1.0,
             noise=3.0, jpeg=90, vignetting=0.2, gradient=0.05)
"""A phone photograph of a record on a desk: 2400 × 1200 px JPEG (quality 90), the sheet
filling 85 % of its width, skewed 1.5°, its corners moved by up to 0.5 %, blur σ 1 px, noise σ
3 grey levels, 20 % vignetting (the labs' synthetic photographed records)."""


@dataclass(frozen=True)
class PaperScene:
    """A rendered record and its truth.

    Attributes
    ----------
    image : numpy.ndarray
        The photograph, BGR uint8 (after JPEG compression if any).
    encoded : bytes
        The image as a file (JPEG if the shot compresses, else PNG).
    layout, beams, shot : Layout, tuple of Beam, Shot
        What was drawn and how.
    homography : numpy.ndarray
        3 × 3 map from the sheet (x along it from the left edge, y up from the lower edge,
        both in m) to image pixels (column, row; pixel centres at whole numbers).
    """

    image: np.ndarray
    encoded: bytes
    layout: Layout
    beams: tuple[Beam, ...]
    shot: Shot
    homography: np.ndarray = field(repr=False)

    @property
    def pixels_per_metre(self) -> float:
        """Mean image pixels per metre of sheet (the scale at its centre). [px/m]"""
        lay = self.layout
        c = np.array([[lay.length / 2, lay.width / 2]])
        p = self.to_image(np.vstack([c, c + [[1e-3, 0]], c + [[0, 1e-3]]]))
        return float(np.mean(np.hypot(*(p[1:] - p[0]).T)) / 1e-3)

    def to_image(self, points) -> np.ndarray:
        """Sheet points (x, y) [m] → image pixels (column, row)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 1, 2)
        return cv2.perspectiveTransform(pts, self.homography).reshape(-1, 2)

    def mark_times(self) -> np.ndarray:
        """Rising edges of the time marks drawn. [s]"""
        return self.layout.mark_times()

    def tdc_times(self) -> np.ndarray:
        """TDC marks drawn (whole pips on the sheet). [s]"""
        return _tdc_times(self.layout)

    def write(self, path) -> Path:
        """Write the image; a ``.jpg`` / ``.jpeg`` / ``.png`` name matching the encoding
        gets the encoded bytes as they are, another name is encoded by OpenCV."""
        path = Path(path)
        jpeg = self.encoded[:2] == b"\xff\xd8"
        if path.suffix.lower() in ((".jpg", ".jpeg") if jpeg else (".png",)):
            path.write_bytes(self.encoded)
        elif not cv2.imwrite(str(path), self.image):
            raise ValueError(f"PaperScene.write: OpenCV cannot write {path.suffix!r} files")
        return path

    def compare(self, time, value, marks, *, beam: int = 0, centred: bool = True,
                scale: float = 1.0) -> dict:
        """Judge a trace read off the image against the beam's true deflection.

        The reader's time starts at its first sample, so its origin is found first: of the
        offsets that put its first time mark on a true one, the one that fits the trace
        best.

        Parameters
        ----------
        time, value : array_like
            The trace as read: times from its first sample [s] and ``scale`` × the
            deflection from the beam's zero [m] (NaN where not read).
        marks : array_like
            The time marks the reader found, on its time axis. [s]
        beam : int
            Which beam it is.
        centred : bool
            Compare about the means (a reader that measures from the trace's mean level).
        scale : float
            Value units per metre of deflection the reader was told.

        Returns
        -------
        dict
            ``rms_error`` (same unit as ``value``), ``relative`` (rms error over the RMS of
            the true signal about its mean), ``snr_db`` (−20 log₁₀ relative), ``offset``
            (true time of the reader's t = 0) [s], ``coverage`` (fraction of the samples
            read).
        """
        t = np.asarray(time, dtype=float)
        v = np.asarray(value, dtype=float)
        marks = np.asarray(marks, dtype=float)
        ok = np.isfinite(v)
        if ok.sum() < 2 or marks.size == 0:
            return {"rms_error": np.nan, "relative": np.nan, "snr_db": np.nan,
                    "offset": np.nan, "coverage": 0.0}
        b = self.beams[beam]
        true_marks = self.mark_times()
        best = None
        for offset in true_marks - marks[0]:
            truth = (b.height(t[ok] + offset) - b.zero) * scale
            err = v[ok] - truth
            if centred:
                err = err - err.mean()
            rms = float(np.sqrt(np.mean(err ** 2)))
            if best is None or rms < best[0]:
                best = (rms, offset, truth)
        rms, offset, truth = best
        spread = float(np.sqrt(np.mean((truth - truth.mean()) ** 2)))
        rel = rms / spread if spread > 0 else np.nan
        return {"rms_error": rms, "relative": rel,
                "snr_db": float(-20 * np.log10(rel)) if rel > 0 else np.inf,
                "offset": float(offset), "coverage": float(ok.mean())}


def render(layout: Layout, beams: Sequence[Beam], shot: Shot = Shot(), *,
           seed: int = 0) -> PaperScene:
    """Draw a paper record as a camera or scanner sees it.

    Parameters
    ----------
    layout : Layout
        The sheet and its marks.
    beams : sequence of Beam
        The traces.
    shot : Shot
        The camera.
    seed : int
        Seed of the perspective, the grain and the noise.

    Returns
    -------
    PaperScene

    Examples
    --------
    >>> scene = render(Layout(length=0.1), [Beam(lambda t: np.sin(60 * t), 0.06, 0.02)],
    ...                Shot(size=(500, 300)))
    >>> scene.image.shape, round(scene.pixels_per_metre)
    ((300, 500, 3), 4500)
    """
    rng = np.random.default_rng([seed, 16])
    w_img, h_img = shot.size
    ppm = shot.fill * w_img / layout.length            # image pixels per metre of sheet
    sheet = _sheet(layout, tuple(beams), shot, ppm, rng)
    to_image = _camera(layout, shot, ppm, rng)
    paper_px = np.diag([ppm, -ppm, 1.0])
    paper_px[1, 2] = layout.width * ppm                 # sheet metres → sheet pixel edges
    # pixels are indexed by their centres (OpenCV): index = edge coordinate − 0.5
    by_index = _shift(-0.5) @ to_image @ _shift(0.5)
    size = (w_img, h_img)
    warped = cv2.warpPerspective(sheet, by_index, size, flags=cv2.INTER_LINEAR,
                                 borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0))
    inside = cv2.warpPerspective(np.full(sheet.shape[:2], 255, np.uint8), by_index, size,
                                 flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
    image = _compose(warped, inside, shot, rng)
    encoded = _encode(image, shot.jpeg)
    image = cv2.imdecode(np.frombuffer(encoded, np.uint8), cv2.IMREAD_COLOR)
    return PaperScene(image, encoded, layout, tuple(beams), shot,
                      _shift(-0.5) @ to_image @ paper_px)


def photograph(signal: Callable[[np.ndarray], np.ndarray] | Sequence[Callable], duration: float,
               gain: float, *, mark_period: float, tdc_times: Sequence[float] = (),
               zero: float | Sequence[float] = 0.06, zero_line: bool = False,
               shot: Shot = PHONE, seed: int = 0) -> PaperScene:
    """A record drawn whole across 250 mm of 120 mm paper and photographed: the labs'
    synthetic paper records.

    Parameters
    ----------
    signal : callable or sequence of callable
        ``signal(t)``, the recorded quantity over t in [0, ``duration``], one per beam. [any
        unit]
    duration : float
        The record's length, drawn over the 250 mm. [s]
    gain : float
        Deflection per unit of the signal. [m per unit]
    mark_period : float
        Time marks' period. [s]
    tdc_times : sequence of float
        TDC marks. [s]
    zero : float or sequence of float
        Each beam's zero above the paper's lower edge. [m]
    zero_line : bool
        Also draw the zero lines.
    shot, seed
        As :func:`render`.
    """
    layout = Layout(length=0.25, speed=0.25 / duration, mark_period=mark_period,
                    tdc_times=tuple(tdc_times))
    signals = list(signal) if isinstance(signal, Sequence) else [signal]
    zeros = list(zero) if isinstance(zero, Sequence) else [zero] * len(signals)
    return render(layout, [Beam(f, z, gain, zero_line) for f, z in zip(signals, zeros)], shot,
                  seed=seed)


def _sheet(layout: Layout, beams: tuple[Beam, ...], shot: Shot, ppm: float,
           rng: np.random.Generator) -> np.ndarray:
    """The flat sheet, BGR uint8, one pixel per 1/ppm m (drawn supersampled)."""
    s = SUPERSAMPLE
    w = int(round(layout.length * ppm))
    h = int(round(layout.width * ppm))
    ink = np.zeros((h * s, w * s), np.uint8)
    thick = max(1, int(round(layout.line_width * ppm * s)))
    t = layout.start + np.arange(0, w * s + 1, 0.5) / (ppm * s) / layout.speed
    x = (t - layout.start) * layout.speed
    for beam in beams:
        _polyline(ink, x, beam.height(t), ppm * s, layout.width, thick)
        if beam.zero_line:
            _polyline(ink, x[[0, -1]], np.full(2, beam.zero), ppm * s, layout.width, thick)
    _pips(ink, layout, layout.mark_times(), layout.mark_period * layout.pip_duty,
          layout.marks_at, ppm * s, thick)
    if len(layout.tdc_times):
        _pips(ink, layout, _tdc_times(layout), layout.tdc_pip, layout.tdc_at, ppm * s, thick)
    coverage = cv2.resize(ink, (w, h), interpolation=cv2.INTER_AREA).astype(np.float32) / 255
    absorbed = (shot.ink_density * coverage)[..., None]
    colour = (np.array(shot.tint, np.float32) * (1 - absorbed)
              + np.array(shot.ink, np.float32) * absorbed)
    if layout.grid:
        grid = np.zeros((h * s, w * s), np.uint8)
        gthick = max(1, int(round(layout.grid_width * ppm * s)))
        step = layout.grid * ppm * s
        for gx in np.arange(step, w * s, step):
            _line(grid, (gx, 0), (gx, h * s), gthick)
        for gy in np.arange(h * s - step, 0, -step):
            _line(grid, (0, gy), (w * s, gy), gthick)
        gcov = cv2.resize(grid, (w, h), interpolation=cv2.INTER_AREA).astype(np.float32) / 255
        colour *= (1.0 - shot.grid_density * gcov)[..., None]
    grain = rng.standard_normal((max(h // 3, 2), max(w // 3, 2))).astype(np.float32)
    colour *= (1.0 + shot.grain * cv2.resize(grain, (w, h), interpolation=cv2.INTER_LINEAR))[
        ..., None]
    return np.clip(colour, 0, 255).astype(np.uint8)


def _tdc_times(layout: Layout) -> np.ndarray:
    t = np.asarray(layout.tdc_times, dtype=float)
    return t[(t >= layout.start) & (t + layout.tdc_pip <= layout.start + layout.duration)]


def _shift(d: float) -> np.ndarray:
    return np.array([[1, 0, d], [0, 1, d], [0, 0, 1.0]])


def _polyline(canvas, x_m, y_m, ppm, width, thick) -> None:
    pts = np.stack([x_m * ppm, (width - np.asarray(y_m)) * ppm], axis=1)
    cv2.polylines(canvas, [np.round((pts - 0.5) * 16).astype(np.int32)], False, 255, thick,
                  cv2.LINE_AA, shift=4)


def _line(canvas, a, b, thick) -> None:
    cv2.line(canvas, tuple(int(round((v - 0.5) * 16)) for v in a),
             tuple(int(round((v - 0.5) * 16)) for v in b), 255, thick, cv2.LINE_AA, shift=4)


def _pips(canvas, layout: Layout, times, duration, height, ppm, thick) -> None:
    """A straight line at ``height`` [m] with a rectangular pip rising at each time."""
    t0, t1 = layout.start, layout.start + layout.duration
    xs, ys = [0.0], [height]
    for t in times:
        a, b = (t - t0) * layout.speed, (t + duration - t0) * layout.speed
        xs += [a, a, b, b]
        ys += [height, height + layout.pip_height, height + layout.pip_height, height]
    xs.append((t1 - t0) * layout.speed)
    ys.append(height)
    _polyline(canvas, np.array(xs), np.array(ys), ppm, layout.width, thick)


def _camera(layout: Layout, shot: Shot, ppm: float, rng: np.random.Generator) -> np.ndarray:
    """Homography from sheet pixels to image pixels: centred, rotated, corners displaced."""
    w, h = layout.length * ppm, layout.width * ppm
    corners = np.array([[0, 0], [w, 0], [w, h], [0, h]], np.float64)
    a = np.radians(shot.rotation)
    rot = np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
    placed = (corners - [w / 2, h / 2]) @ rot.T + np.array(shot.size) / 2
    placed += rng.uniform(-1, 1, (4, 2)) * shot.perspective * shot.size[0]
    return cv2.getPerspectiveTransform(corners.astype(np.float32), placed.astype(np.float32))


def _compose(warped: np.ndarray, inside: np.ndarray, shot: Shot,
             rng: np.random.Generator) -> np.ndarray:
    """Sheet on the desk, uneven light, blur and noise: float → uint8."""
    h, w = inside.shape
    alpha = inside.astype(np.float32)[..., None] / 255
    desk = np.array(shot.desk, np.float32) * (1 + 0.05 * cv2.resize(
        rng.standard_normal((max(h // 16, 2), max(w // 16, 2))).astype(np.float32), (w, h)))[
        ..., None]
    image = warped.astype(np.float32) * alpha + desk * (1 - alpha)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    r2 = ((xx - w / 2) / (w / 2)) ** 2 + ((yy - h / 2) / (h / 2)) ** 2
    light = (1 - shot.vignetting * r2 / 2) * (1 - shot.gradient * xx / w)
    image *= light[..., None]
    if shot.blur > 0:
        image = cv2.GaussianBlur(image, (0, 0), shot.blur)
    if shot.noise > 0:
        image += rng.normal(0, shot.noise, image.shape).astype(np.float32)
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def _encode(image: np.ndarray, jpeg: int | None) -> bytes:
    if jpeg is None:
        ok, buf = cv2.imencode(".png", image)
    else:
        ok, buf = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, int(jpeg)])
    if not ok:
        raise RuntimeError("render: OpenCV could not encode the image")
    return buf.tobytes()
