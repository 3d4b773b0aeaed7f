"""The paper in a photograph or scan: read the file, find the sheet, square it up, even out the
light.

A photograph shows the sheet on a darker desk, at a slant; a flatbed scan may be cropped
inside the sheet. :func:`find_sheet` finds the sheet's four edges (Otsu's threshold on a
reduced copy, the largest bright region, a straight line fitted to each side; where a shadow
bit a corner off the region, its outline's straight runs; on a light scanner lid, which no
threshold splits from the paper, the step from the lid's level to the paper's along each
side of the frame) or reports that the sheet fills the frame. :func:`square_up` maps the sheet onto an upright rectangle with one
perspective warp that also takes out the residual skew (:func:`skew_angle`: the angle that
sharpens the row profile of the ink most, which the long straight lines of the record
decide). :func:`flatten` turns grey levels into optical density above the local paper
level, D = ln(paper / grey), which removes uneven light and adds where inks overlap.

The darkness of a pixel is its darkest colour channel, so dark traces of any hue count.
:func:`load_image` reads the file's header first (:mod:`processing.vision.header`) and
refuses a picture larger than :data:`MAX_PIXELS` before decoding a byte of it; a picture
larger than :data:`WORK_PIXELS` is read reduced to that size (the reader needs no more).
:func:`square_up` also turns the sheet by quarter turns: how the record is turned upright is
decided by what is drawn on it (:func:`processing.vision.record.read_paper_records`).

References
----------
.. [1] N. Otsu, "A threshold selection method from gray-level histograms", IEEE Trans. SMC
       9 (1979) 62–66.
.. [2] W. Postl, "Detection of linear oblique structures and skew scan in digitized
       documents", Proc. 8th Int. Conf. on Pattern Recognition, 1986, 687–689 (the
       projection-profile skew estimate).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from ..diagnostics import InputError
from ..files import IMAGE, regular
from .header import HeaderError, image_header

MIN_SIDE = 64
"""Smallest image side read. [px]"""

MAX_PIXELS = 100_000_000
"""Largest picture read, by its header. [px] A phone photographs at 12–50 Mpx (108 and 200 Mpx
in a high-resolution mode), a flatbed scans the manual's 250 × 120 mm strip at 17 Mpx at
600 dpi and 67 Mpx at 1200 dpi, a whole A4 page at 35 Mpx at 600 dpi. OpenCV's PNG, TIFF and
BMP decoders peak at about six bytes a pixel (the picture and a buffer beside it); a JPEG
this large is decoded at half size. Measured, ``dynlab run`` of lab 9 with its photograph
enlarged to 96 Mpx: 0.76 GB peak as PNG, TIFF or BMP, 0.35 GB as JPEG."""

WORK_PIXELS = 16_000_000
"""Largest picture the reader works on: a larger one is reduced to this first. [px] The
reader needs a trace's stroke a few pixels wide. Measured on a 24 Mpx photograph of a decay
(6000 × 4000, blur σ 2.5 px, JPEG) read at several sizes: the trace's RMS error was 0.09 %
of the signal's at full size and at 16 Mpx, 0.11 % at 8, 0.14 % at 4 and 0.24 % at 1 Mpx,
in 7.4 s at full size and 3.7 s at 16 Mpx; the labs' synthetic photographs (2.9–8 Mpx) are
read whole. The reader takes about 8 bytes a pixel (the density, the traces' runs): 130 MB
at this size."""

_DECODE = {1: cv2.IMREAD_COLOR, 2: cv2.IMREAD_REDUCED_COLOR_2, 4: cv2.IMREAD_REDUCED_COLOR_4,
           8: cv2.IMREAD_REDUCED_COLOR_8}
"""OpenCV's decoding flag for each reduction of a JPEG (decoded at 1/2, 1/4, 1/8 size)."""

WORK_SIDE = 1024
"""Long side of the reduced copy the sheet and the skew are found on. [px]"""

MIN_SHEET = 0.15
"""A bright region smaller than this fraction of the image is not taken for the sheet."""

SHEET_CONTRAST = 25.0
"""Grey levels the sheet must stand above the desk by to be found."""

SKEW_RANGE = 8.0
"""Largest skew searched when the sheet's edges are not in the picture. [deg]"""

SKEW_RANGE_SHEET = 2.0
"""Largest skew searched on a sheet squared up by its edges (a sheet cut at a slant). [deg]"""

BACKGROUND_REDUCTION = 4
"""Reduction of the copy the paper level is found on (a closing there spans
:data:`BACKGROUND_KERNEL` × this many pixels)."""

BACKGROUND_KERNEL = 11
"""Closing kernel of the paper level on the reduced copy: ink narrower than about 40 px is
lifted off. [px]"""

_LOG = np.log(np.maximum(np.arange(256, dtype=np.float64), 0.5)).astype(np.float32)

FIX_RU = "дайте фотографию или скан записи в PNG, JPEG или TIFF"
"""How to give a picture of a record, in Russian."""


def _meeting(sides: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray | None:
    """Where each of four sides (a point and a direction, in (column, row), in order round
    the sheet) meets the one before it: the four corners, or None if two neighbours run
    parallel."""
    corners = []
    for i in range(4):
        (p, d), (q, e) = sides[i - 1], sides[i]
        m = np.array([d, -e]).T
        if abs(np.linalg.det(m)) < 1e-6:
            return None
        corners.append(p + np.linalg.solve(m, q - p)[0] * d)
    return np.array(corners)


def load_image(path, *, field: str | None = None) -> tuple[np.ndarray, float]:
    """Read a photograph or scan as its darkness channel, at most :data:`WORK_PIXELS` large.

    The header is read first (:func:`~.header.image_header`): a picture larger than
    :data:`MAX_PIXELS` is refused before a byte of it is decoded. A JPEG larger than twice
    the working size is decoded at a half, a quarter or an eighth of its size (the JPEG
    decoder's own scaling of its blocks); whatever is still larger than the working size is
    reduced to it (:func:`working_copy`).

    Parameters
    ----------
    path : str or Path
        A PNG, JPEG, TIFF or BMP file.
    field : str, optional
        The measurement-file field that named it, for errors.

    Returns
    -------
    grey : numpy.ndarray
        uint8 image, rows × columns: the darkest colour channel of each pixel.
    scale : float
        The file's pixels per pixel of ``grey`` (1 unless reduced).

    Raises
    ------
    InputError
        The file is missing, not a PNG, JPEG, TIFF or BMP image by its first bytes, a header
        that states more than :data:`MAX_PIXELS`, not an image OpenCV decodes, or too small.
    """
    p = Path(path)
    regular(p, IMAGE, field=field)
    try:
        header = image_header(p)
    except HeaderError as exc:
        raise InputError(f"not an image: {exc}", "give a photograph or scan of the "
                         "record as PNG, JPEG or TIFF", file=str(p), field=field,
                         ru=(f"это не изображение: {exc.ru}", FIX_RU)) from None
    if header.pixels > MAX_PIXELS:
        raise InputError(f"{header.says()}, more than the {MAX_PIXELS / 1e6:.0f} Mpx a "
                         "photograph or scan is read at", "photograph the record at up to "
                         "50 Mpx (a phone's usual 12 Mpx is plenty) or scan it at 600 dpi, or "
                         f"scale the image down below {MAX_PIXELS / 1e6:.0f} Mpx",
                         file=str(p), field=field,
                         ru=(f"заголовок {header.format} ({header.field}) указывает "
                             f"{header.width} × {header.height} пикс. "
                             f"({header.pixels / 1e6:.3g} Мпикс), больше "
                             f"{MAX_PIXELS / 1e6:.0f} Мпикс, при которых читается снимок или "
                             "скан", "снимайте запись не больше чем в 50 Мпикс (обычных 12 "
                             "Мпикс телефона достаточно), сканируйте при 600 dpi или уменьшите "
                             f"снимок до {MAX_PIXELS / 1e6:.0f} Мпикс"))
    reduction = 1
    while header.format == "JPEG" and reduction < 8 \
            and header.pixels / (2 * reduction) ** 2 >= WORK_PIXELS:
        reduction *= 2
    image = _decode(p, _DECODE[reduction])
    if image is None:
        raise InputError("not an image (OpenCV cannot decode it)", "give a photograph or scan "
                         "of the record as PNG, JPEG or TIFF", file=str(p), field=field,
                         ru=("это не изображение (OpenCV не может его декодировать)", FIX_RU))
    decoded = image.shape[0] * image.shape[1]
    grey = darkness(image, name=str(p), field=field)
    del image
    grey, scale = working_copy(grey)
    return grey, scale * math.sqrt(header.pixels / decoded)


def _decode(path: Path, flags: int) -> np.ndarray | None:
    """The image decoded by OpenCV straight from the file (its bytes never all in memory
    beside the picture), or from the bytes read where OpenCV cannot open the file by its
    name (a name outside the ANSI code page on Windows)."""
    if os.name != "nt" or str(path).isascii():
        return cv2.imread(str(path), flags)
    data = np.fromfile(path, np.uint8)
    return cv2.imdecode(data, flags) if data.size else None


def working_copy(grey: np.ndarray) -> tuple[np.ndarray, float]:
    """The darkness image reduced (pixel areas averaged) to at most :data:`WORK_PIXELS`, and
    the pixels of ``grey`` per pixel of the copy (1 if it was small enough)."""
    if grey.size <= WORK_PIXELS:
        return grey, 1.0
    f = math.sqrt(WORK_PIXELS / grey.size)
    size = (max(int(grey.shape[1] * f), 1), max(int(grey.shape[0] * f), 1))
    return cv2.resize(grey, size, interpolation=cv2.INTER_AREA), grey.shape[1] / size[0]


def darkness(image: np.ndarray, *, name: str = "<array>", field: str | None = None) -> np.ndarray:
    """The darkest channel of a BGR image (a grey image is returned as it is), uint8.

    Raises
    ------
    InputError
        An image smaller than :data:`MIN_SIDE` px on a side.
    """
    image = np.asarray(image)
    if image.dtype != np.uint8:
        image = np.clip(image, 0, 255).astype(np.uint8)
    if image.ndim == 3:
        darkest = image[..., 0].copy()
        for c in range(1, min(image.shape[2], 3)):
            np.minimum(darkest, image[..., c], out=darkest)
        image = darkest
    if image.ndim != 2 or min(image.shape) < MIN_SIDE:
        raise InputError(f"the image is {image.shape[1] if image.ndim > 1 else 0} × "
                         f"{image.shape[0]} px, too small to read a trace off",
                         f"photograph or scan the record at ≥ {MIN_SIDE} px on each side "
                         "(a few thousand along the record)", file=name, field=field,
                         ru=(f"снимок {image.shape[1] if image.ndim > 1 else 0} × "
                             f"{image.shape[0]} пикс слишком мал, чтобы прочитать запись",
                             f"сфотографируйте или отсканируйте запись с разрешением не меньше "
                             f"{MIN_SIDE} пикс по каждой стороне (несколько тысяч вдоль "
                             "записи)"))
    return np.ascontiguousarray(image)


@dataclass(frozen=True)
class Sheet:
    """The sheet squared up: its grey image and how it maps into the original image.

    Attributes
    ----------
    grey : numpy.ndarray
        Upright darkness image, uint8; time runs along the columns.
    homography : numpy.ndarray
        3 × 3 map from this image's pixels to the original image's (centres at whole
        numbers).
    edges_found : bool
        Whether the sheet's four edges were found (else the frame is taken for the sheet).
    skew : float
        The skew taken out after squaring up, counter-clockwise. [deg]
    source_scale : float
        Original-image pixels per sheet pixel (the mean over the sheet): a scan's dpi
        divided by this is the sheet's.
    paper_size : tuple of float or None
        The whole sheet's length and width between its edges, in sheet pixels (None when
        the edges are not in the picture). [px]
    turns : int
        Quarter turns, counter-clockwise, the sheet was given (see :func:`square_up`).
    """

    grey: np.ndarray
    homography: np.ndarray
    edges_found: bool
    skew: float
    source_scale: float
    paper_size: tuple[float, float] | None
    turns: int = 0


def find_sheet(grey: np.ndarray) -> np.ndarray | None:
    """The sheet's corners in the image, or None if the sheet fills the frame.

    Parameters
    ----------
    grey : numpy.ndarray
        Darkness image (:func:`darkness`).

    Returns
    -------
    numpy.ndarray or None
        4 × 2 corners (column, row) [px]: top-left, top-right, bottom-right, bottom-left of
        the upright sheet, its long side horizontal (a portrait sheet is turned a quarter
        clockwise).
    """
    f = WORK_SIDE / max(grey.shape)
    small = cv2.resize(grey, None, fx=min(f, 1.0), fy=min(f, 1.0), interpolation=cv2.INTER_AREA)
    f = small.shape[1] / grey.shape[1]
    blur = cv2.GaussianBlur(small, (5, 5), 0)
    otsu, low = _levels(blur)
    mask, contour = _region(blur, otsu)
    if _solidity(contour) < SOLID_SHEET:
        lower = _region(blur, low)
        # the bite filled in, a whole sheet again (the desk's grain joined to the sheet
        # leaves it ragged)
        if _solidity(lower[1]) >= SOLID_SHEET:
            mask, contour = lower
    h, w = small.shape
    if contour is None or cv2.contourArea(contour) < MIN_SHEET * h * w:
        return _on_a_lid(blur, f)
    x, y, bw, bh = cv2.boundingRect(contour)
    if _touching(contour, (h, w)) >= 2:
        # the bright region fills the frame: a scan cropped inside the sheet, or a sheet on
        # a light lid
        return _on_a_lid(blur, f)
    if _runs_off(contour[:, 0, :], (w, h), long_side=max(bw, bh)):
        # a long edge runs off the frame: the frame's edge there is not the sheet's, and
        # squaring up to it would shear the record; the frame is squared up instead, and
        # the desk beyond the other edges cut off (beyond_the_sheet)
        return None
    inside = np.zeros_like(mask)
    cv2.drawContours(inside, [contour], -1, 255, -1)
    if cv2.mean(blur, inside)[0] - cv2.mean(blur, 255 - inside)[0] < SHEET_CONTRAST:
        return _on_a_lid(blur, f)
    corners = None if _solidity(contour) >= SOLID_SHEET else _straight_sides(inside, contour)
    if corners is None:
        corners = _quadrilateral(contour)
    if corners is None:
        return None
    corners = _refine_sides(contour[:, 0, :].astype(np.float64), corners) / f
    return _long_side_first(_order(_edges_at_full_size(grey, _order(corners),
                                                       reach=max(8.0, 3.0 / f))))


def _long_side_first(corners: np.ndarray) -> np.ndarray:
    """Ordered corners (:func:`_order`) starting so that the first side is the long one (a
    portrait sheet turned a quarter clockwise)."""
    top, left = np.hypot(*(corners[1] - corners[0])), np.hypot(*(corners[3] - corners[0]))
    return np.roll(corners, 1, axis=0) if left > top else corners


LID_STEP = 5.0
"""Grey levels a light lid must differ from the sheet by, at least, for the sheet's edge
against it to be taken (:func:`_on_a_lid`); a sheet and a lid of one level are told apart
only among the lines (:func:`processing.vision.record.judge_lines`)."""

LID_SLICES = 24
"""Slices along each side of the frame in which the sheet's edge against a lid is sought."""

LID_AGREE = 0.6
"""Share of the slices whose edge must lie on one straight line for the side to be taken."""


def _on_a_lid(blur: np.ndarray, f: float) -> np.ndarray | None:
    """The sheet's corners (as :func:`find_sheet` gives them) on a lid that shows a band of
    its own level along all four sides of the frame, or None.

    A light lid differs from the paper by a few grey levels only (brighter or darker), and
    the sheet's edge on it is a faint step or the thin shadow the paper's thickness throws:
    no threshold splits the two. Along each side of the frame, in each of
    :data:`LID_SLICES` slices across it (their mean along the side), the paper's level is
    read in the inner half of a band a quarter of the frame deep; the edge is the first
    place from the border where three pixels in a row are at the paper's level (within
    :data:`LID_STEP` grey levels or 5 σ of the slices' noise: not the flank of the shadow
    on the lid, which stays outside), and the band outside it must be off the paper's level
    by as much (a step, not a line on the paper). The side is the straight line through the
    slices' edges (Theil–Sen's median slope, then a least-squares fit to the edges within
    2 px of it) if :data:`LID_AGREE` of them lie on it and step the same way, within
    :data:`SKEW_RANGE` of the frame's side. Where any side shows no such band (a scan cut
    inside the sheet there, a lid of the paper's own level), None: the frame is squared up
    as before (:func:`beyond_the_sheet`, and the lid's edge judged among the lines).

    Parameters
    ----------
    blur : numpy.ndarray
        The reduced, smoothed darkness image.
    f : float
        Its size over the full image's.
    """
    h, w = blur.shape
    image = blur.astype(np.float32)
    sides = []
    # each side seen from the frame's border inward (rows), along the side (columns): the
    # top, bottom, left and right
    for view in (image, image[::-1], image.T, image.T[::-1]):
        side = _lid_edge(view)
        if side is None:
            return None
        sides.append(side)
    (a_t, b_t), (a_b, b_b), (a_l, b_l), (a_r, b_r) = sides
    # as lines p + s·d in (column, row): top y = a + b·x, bottom y = h − 1 − a − b·x,
    # left x = a + b·y, right x = w − 1 − a − b·y
    lines = [(np.array([0.0, a_t]), np.array([1.0, b_t])),
             (np.array([w - 1.0 - a_r, 0.0]), np.array([-b_r, 1.0])),
             (np.array([0.0, h - 1.0 - a_b]), np.array([1.0, -b_b])),
             (np.array([a_l, 0.0]), np.array([b_l, 1.0]))]
    corners = _meeting(lines)
    if corners is None:
        return None
    corners = _order(corners)
    if cv2.contourArea(corners.astype(np.float32)) < MIN_SHEET * h * w:
        return None
    return _long_side_first(corners) / f


def _lid_edge(view: np.ndarray) -> tuple[float, float] | None:
    """The sheet's edge against a lid along the top of ``view`` as (a, b): the edge lies
    a + b·x rows below the border at column x; None if there is none (:func:`_on_a_lid`)."""
    h, w = view.shape
    depth = h // 4
    bounds = np.linspace(0.1 * w, 0.9 * w, LID_SLICES + 1).astype(int)
    profiles = np.array([view[:depth, s:e].mean(axis=1) for s, e in zip(bounds, bounds[1:])])
    steps = np.diff(profiles, axis=1)
    noise = 1.4826 * float(np.median(np.abs(steps - np.median(steps)))) / math.sqrt(2)
    limit = max(LID_STEP, 5 * noise)
    x, d, sign = [], [], []
    for k, p in enumerate(profiles):
        paper = float(np.median(p[depth // 2:]))
        at = np.abs(p - paper) <= limit
        edge = int(np.argmax(at[:-2] & at[1:-1] & at[2:]))    # not a flank passing through
        if edge < 4 or edge > 0.8 * depth:
            continue
        lid = float(np.median(p[:edge - 3]))       # the shadow on the lid left out
        if abs(lid - paper) <= limit:
            continue                                 # a line on the paper, not a step
        x.append(0.5 * (bounds[k] + bounds[k + 1] - 1))
        d.append(float(edge))
        sign.append(paper > lid)
    if len(x) < LID_AGREE * LID_SLICES:
        return None
    x, d, sign = np.array(x), np.array(d), np.array(sign)
    i, j = np.triu_indices(x.size, 1)
    b = float(np.median((d[j] - d[i]) / (x[j] - x[i])))          # Theil–Sen: outliers
    a = float(np.median(d - b * x))                                # (a stroke) left out
    keep = np.abs(d - (a + b * x)) <= 2.0
    same = max(sign[keep].sum(), (~sign[keep]).sum())
    if same < LID_AGREE * LID_SLICES or abs(b) > math.tan(math.radians(SKEW_RANGE)):
        return None
    b, a = np.polyfit(x[keep], d[keep], 1)
    return float(a), float(b)


SOLID_SHEET = 0.98
"""Share of its convex hull a whole sheet's region fills at least (its outline, traced on the
reduced copy, rounds its corners a little); less, a shadow has bitten into it, and the
region at the lower threshold (:func:`_levels`) is taken if it is whole."""


def _touching(contour, shape: tuple[int, int]) -> int:
    """How many of the frame's edges the region's bounding box reaches."""
    h, w = shape
    x, y, bw, bh = cv2.boundingRect(contour)
    return int((x <= 1) + (y <= 1) + (x + bw >= w - 1) + (y + bh >= h - 1))


RUN_OFF = 0.1
"""Share of the sheet's long side that must lie along the frame's edge for the sheet to run
off the frame there (a skewed sheet's corner only touches it)."""


def _runs_off(outline: np.ndarray, size: tuple[int, int], long_side: float) -> bool:
    """Whether the sheet's outline (column, row points) runs along one of the frame's edges
    for :data:`RUN_OFF` of its long side: the sheet runs off the frame there."""
    w, h = size
    x, y = outline[:, 0], outline[:, 1]
    along = [np.unique(x[y <= 1]).size, np.unique(x[y >= h - 2]).size,
             np.unique(y[x <= 1]).size, np.unique(y[x >= w - 2]).size]
    return max(along) > RUN_OFF * long_side


def _levels(blur: np.ndarray) -> tuple[float, float]:
    """Two thresholds between the sheet and the desk: Otsu's [1]_, and one lower, above the
    desk's typical level (the median of Otsu's darker class) by :data:`SHEET_CONTRAST` grey
    levels or half the way to Otsu's if that is more. A phone's shadow over part of the
    sheet darkens it below Otsu's threshold, though well above the desk; a light desk's
    grain rises above the lower one."""
    level, _ = cv2.threshold(blur, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    dark = blur[blur <= level]
    desk = float(np.median(dark)) if dark.size else 0.0
    return float(level), min(float(level), desk + max(SHEET_CONTRAST, 0.5 * (level - desk)))


def _region(blur: np.ndarray, level: float):
    """The pixels brighter than ``level`` (closed over 15 px) and the outline of their
    largest region (None if there is none)."""
    mask = np.where(blur > level, 255, 0).astype(np.uint8)
    mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, np.ones((15, 15), np.uint8))
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return mask, (max(contours, key=cv2.contourArea) if contours else None)


def _solidity(contour) -> float:
    """The region's area over its convex hull's: 1 for a whole sheet; less where a shadow
    bit into it or the desk's grain joined it."""
    if contour is None:
        return -1.0
    hull = cv2.contourArea(cv2.convexHull(contour))
    return cv2.contourArea(contour) / hull if hull > 0 else 0.0


SIDE_VOTES = 0.15
"""Share of the region's long side that a straight run of its outline must span (votes in
the Hough transform) to be taken for a side of a bitten sheet (:func:`_straight_sides`)."""


SIDES_HOLD = 0.95
"""Share of a bitten sheet's region the quadrilateral of its straight sides must hold."""


def _straight_sides(region: np.ndarray, contour) -> np.ndarray | None:
    """Corners of a sheet whose region (``region``: its ``contour`` filled, uint8) a shadow
    has bitten into, from the straight runs of its outline.

    The bite (a phone's or a hand's shadow over a corner, deeper than any threshold between
    the sheet and the desk reaches) takes the corner and parts of two sides away, but what
    remains of each side is straight and long, and the bite's outline is curved. The
    outline is drawn one pixel wide and its straight lines found by the Hough transform
    (0.5° and 1 px steps, at least :data:`SIDE_VOTES` of the region's long side): the
    strongest line and the strongest one roughly parallel to it (within 20°, a fifth of
    the region's size away) are one pair of sides, the strongest two across them the
    other; the corners are where they meet. None if either pair is not found, or the
    quadrilateral does not hold :data:`SIDES_HOLD` of the region (the desk's grain joined
    to it may run outside).
    """
    outline = np.zeros_like(region)
    cv2.drawContours(outline, [contour], -1, 255, 1)
    _, _, bw, bh = cv2.boundingRect(contour)
    found = cv2.HoughLines(outline, 1, math.pi / 360, max(10, int(SIDE_VOTES * max(bw, bh))))
    if found is None:
        return None
    lines = found[:, 0, :]                       # (ρ, θ), strongest first
    first = lines[0]

    def across(a: float, b: float) -> float:
        d = abs(a - b) % math.pi
        return min(d, math.pi - d)

    def pair(candidates, size: float):
        chosen = [candidates[0]]
        for rho, theta in candidates[1:]:
            if across(theta, chosen[0][1]) < math.radians(20) and \
                    abs(_distance(chosen[0], (rho, theta))) > 0.2 * size:
                chosen.append((rho, theta))
                return chosen
        return None

    along = [tuple(v) for v in lines if across(v[1], first[1]) < math.radians(20)]
    other = [tuple(v) for v in lines if across(v[1], first[1]) > math.radians(60)]
    if not other:
        return None
    size_a = bh if abs(math.cos(first[1])) < 0.7 else bw       # across the first side
    size_b = bw if size_a == bh else bh
    sides_a, sides_b = pair(along, size_a), pair(other, size_b)
    if sides_a is None or sides_b is None:
        return None
    corners = np.array([_meet(a, b) for a in sides_a for b in sides_b])
    corners = _order(corners)
    quad = np.zeros_like(region)
    cv2.fillPoly(quad, [np.round(corners).astype(np.int32)], 255)
    held = np.count_nonzero(region & quad) / max(np.count_nonzero(region), 1)
    return corners if held >= SIDES_HOLD else None


def _distance(a, b) -> float:
    """How far apart two nearly parallel lines (ρ, θ) lie. [px]"""
    (r1, t1), (r2, t2) = a, b
    return r2 - r1 if math.cos(t1 - t2) > 0 else -r2 - r1


def _meet(a, b) -> np.ndarray:
    """Where two lines (ρ, θ) cross: (column, row)."""
    (r1, t1), (r2, t2) = a, b
    m = np.array([[math.cos(t1), math.sin(t1)], [math.cos(t2), math.sin(t2)]])
    return np.linalg.solve(m, np.array([r1, r2]))


def _quadrilateral(contour) -> np.ndarray | None:
    hull = cv2.convexHull(contour)
    perimeter = cv2.arcLength(hull, True)
    for eps in (0.01, 0.02, 0.03, 0.05):
        approx = cv2.approxPolyDP(hull, eps * perimeter, True)
        if len(approx) == 4:
            return approx[:, 0, :].astype(np.float64)
    return None


def _refine_sides(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Corners as the intersections of straight lines fitted to the contour along each side
    (its middle 80 %, points within 3 px of the rough side)."""
    lines = []
    for i in range(4):
        a, b = corners[i], corners[(i + 1) % 4]
        d = b - a
        length = np.hypot(*d)
        u = (points - a) @ d / length ** 2
        dist = np.abs((points - a) @ np.array([-d[1], d[0]])) / length
        near = points[(u > 0.1) & (u < 0.9) & (dist < 3)]
        if len(near) < 10:
            return corners
        vx, vy, x0, y0 = cv2.fitLine(near.astype(np.float32), cv2.DIST_HUBER, 0, 0.01, 0.01)[:, 0]
        lines.append((np.array([x0, y0], np.float64), np.array([vx, vy], np.float64)))
    out = _meeting(lines)
    return corners if out is None else out


def _edges_at_full_size(grey: np.ndarray, corners: np.ndarray, reach: float) -> np.ndarray:
    """Corners from each side located to a fraction of a pixel on the full image.

    Along each side, 64 profiles across it (± ``reach`` px) are read by bilinear
    interpolation; the edge in each is where the grey level crosses half-way between the
    sheet's level inside and the desk's outside (a blurred step crosses there at the step),
    and a straight line fitted to these points (Huber weights: a stroke near the edge does
    not pull it) replaces the side. Sides with too few clear profiles keep the rough line.
    """
    image = grey.astype(np.float32)
    centre = corners.mean(axis=0)
    offsets = np.arange(-reach, reach + 0.25, 0.5)
    t = np.linspace(0.1, 0.9, 64)
    lines = []
    for i in range(4):
        a, b = corners[i], corners[(i + 1) % 4]
        d = (b - a) / np.hypot(*(b - a))
        n = np.array([-d[1], d[0]])
        if n @ (a - centre) < 0:
            n = -n                                            # pointing out of the sheet
        base = a + t[:, None] * (b - a)
        pts = base[:, None, :] + offsets[None, :, None] * n
        prof = cv2.remap(image, pts[..., 0].astype(np.float32), pts[..., 1].astype(np.float32),
                         cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        inner = prof[:, offsets < -0.6 * reach].mean(axis=1)
        outer = prof[:, offsets > 0.6 * reach].mean(axis=1)
        found = []
        for k in np.flatnonzero(inner - outer > SHEET_CONTRAST / 2):
            level = 0.5 * (inner[k] + outer[k])
            below = np.flatnonzero(prof[k] < level)
            if below.size == 0 or below[0] == 0:
                continue
            j = below[0]
            s = offsets[j - 1] + 0.5 * (prof[k, j - 1] - level) / (prof[k, j - 1] - prof[k, j])
            found.append(base[k] + s * n)
        if len(found) < 16:
            lines.append((a, d))
            continue
        vx, vy, x0, y0 = cv2.fitLine(np.array(found, np.float32), cv2.DIST_HUBER, 0, 0.01,
                                     0.01)[:, 0]
        lines.append((np.array([x0, y0], np.float64), np.array([vx, vy], np.float64)))
    out = _meeting(lines)
    return corners if out is None else out


def _order(corners: np.ndarray) -> np.ndarray:
    """Top-left, top-right, bottom-right, bottom-left."""
    c = corners[np.argsort(np.arctan2(*(corners - corners.mean(axis=0)).T[::-1]))]
    start = np.argmin(c.sum(axis=1))
    return np.roll(c, -start, axis=0)


def square_up(grey: np.ndarray, corners: np.ndarray | None, *, turns: int = 0) -> Sheet:
    """Map the sheet onto an upright rectangle and take out the residual skew.

    Parameters
    ----------
    grey : numpy.ndarray
        Darkness image.
    corners : numpy.ndarray or None
        The sheet's corners (:func:`find_sheet`), or None to take the frame for the sheet.
    turns : int
        Quarter turns, counter-clockwise, given to the sheet as the corners (or the frame)
        lay it out, before its skew is found: how the record is turned upright (2: a sheet
        photographed upside down; 1 or 3: one whose time runs along its short side).

    Returns
    -------
    Sheet
        Cut a margin of 1.2 % of the width inside found edges (their shadow, blurred, and the
        desk stay out).
    """
    h, w = grey.shape
    if corners is None:
        base = np.eye(3)
        size = (w, h)
        margin = 0
        paper = None
    else:
        width = 0.5 * (np.hypot(*(corners[1] - corners[0])) + np.hypot(*(corners[2] - corners[3])))
        height = 0.5 * (np.hypot(*(corners[3] - corners[0])) + np.hypot(*(corners[2] - corners[1])))
        size = (int(round(width)), int(round(height)))
        paper = (float(width), float(height))
        target = np.array([[0, 0], [width - 1, 0], [width - 1, height - 1], [0, height - 1]])
        base = cv2.getPerspectiveTransform(target.astype(np.float32), corners.astype(np.float32))
        margin = max(3, int(round(0.012 * min(size))))
    for _ in range(turns % 4):
        base = base @ _quarter_turn(size)
        size = size[::-1]
        paper = paper[::-1] if paper is not None else None
    # the skew, found on a reduced copy of the squared-up sheet
    f = min(1.0, WORK_SIDE / max(size))
    reduced = cv2.resize(grey, None, fx=f, fy=f, interpolation=cv2.INTER_AREA) if f < 1 else grey
    to_reduced = np.diag([reduced.shape[1] / w, reduced.shape[0] / h, 1.0])
    small_size = (max(int(size[0] * f), 1), max(int(size[1] * f), 1))
    small = cv2.warpPerspective(reduced, to_reduced @ base @ np.diag([1 / f, 1 / f, 1.0]),
                                small_size, flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                borderMode=cv2.BORDER_REPLICATE)
    density, _ = flatten(small, reduction=1)
    limit = SKEW_RANGE if corners is None else SKEW_RANGE_SHEET
    m = int(math.ceil(margin * f))
    angle = skew_angle(density[m:small.shape[0] - m, m:small.shape[1] - m], limit,
                       sharp=corners is not None)
    a = math.radians(angle)
    cx, cy = (size[0] - 1) / 2, (size[1] - 1) / 2
    # upright pixel → skewed sheet pixel: rotate by the skew about the centre
    rotate = np.array([[math.cos(a), math.sin(a), 0], [-math.sin(a), math.cos(a), 0], [0, 0, 1]])
    centre = np.array([[1, 0, cx], [0, 1, cy], [0, 0, 1.0]])
    homography = base @ centre @ rotate @ np.linalg.inv(centre)
    crop = np.array([[1, 0, margin], [0, 1, margin], [0, 0, 1.0]])
    homography = homography @ crop
    out = (size[0] - 2 * margin, size[1] - 2 * margin)
    upright = cv2.warpPerspective(grey, homography, out,
                                  flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                  borderMode=cv2.BORDER_REPLICATE)
    if corners is None:
        (top, bottom), (left, right) = beyond_the_sheet(upright)
        upright = np.ascontiguousarray(upright[top:out[1] - bottom, left:out[0] - right])
        homography = homography @ np.array([[1, 0, left], [0, 1, top], [0, 0, 1.0]])
        out = (upright.shape[1], upright.shape[0])
    return Sheet(upright, homography, corners is not None, angle, _mean_scale(homography, out),
                 paper, turns % 4)


BARE_SHARE = 0.9
"""Share of a row (or column) of the frame the sheet must fill for the row to be the sheet's,
where the sheet runs off the frame (:func:`beyond_the_sheet`)."""


def beyond_the_sheet(upright: np.ndarray) -> tuple[tuple[int, int], tuple[int, int]]:
    """Rows and columns at the frame's border that show the desk or the scanner's lid, not
    the sheet, where the sheet runs off the frame (a strip longer than the scanner's bed, a
    photograph close up): cut off, so that the sheet's edges are not read as lines or
    traces on it.

    The frame is split into the bright sheet and a darker ground by Otsu's threshold (Otsu
    1979) on a reduced copy (closed over 15 px there, so that ink stays the sheet's), if the two
    stand :data:`SHEET_CONTRAST` grey levels apart; the rows from the top and bottom (the
    columns from either side) in which the sheet fills less than :data:`BARE_SHARE` are cut,
    with a margin of 1 % of the frame's height beyond the last of them (the edge's shadow,
    blurred). A light lid against the sheet is not told apart here: its edge is judged
    among the lines (:func:`processing.vision.record.judge_lines`).

    Parameters
    ----------
    upright : numpy.ndarray
        The frame squared up (:func:`square_up` without the sheet's corners), uint8.

    Returns
    -------
    tuple
        ((rows cut at the top, at the bottom), (columns cut at the left, at the right)). [px]
    """
    h, w = upright.shape
    f = min(1.0, WORK_SIDE / max(h, w))
    small = cv2.resize(upright, None, fx=f, fy=f, interpolation=cv2.INTER_AREA) if f < 1 \
        else upright
    blur = cv2.GaussianBlur(small, (5, 5), 0)
    _, mask = cv2.threshold(blur, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, np.ones((15, 15), np.uint8)) > 0
    if mask.all() or not mask.any() \
            or blur[mask].mean() - blur[~mask].mean() < SHEET_CONTRAST:
        return (0, 0), (0, 0)
    rows, cols = slice(0, mask.shape[0]), slice(0, mask.shape[1])
    for _ in range(2):                  # the rows within the sheet's columns, and again
        rows = _filled(mask[:, cols].mean(axis=1))
        cols = _filled(mask[rows].mean(axis=0))
        if rows.stop <= rows.start or cols.stop <= cols.start:
            return (0, 0), (0, 0)
    margin = int(math.ceil(0.01 * min(h, w)))

    def cut(k: int, size: int) -> int:
        return 0 if k == 0 else min(int(math.ceil(k / f)) + margin, size // 4)

    return ((cut(rows.start, h), cut(mask.shape[0] - rows.stop, h)),
            (cut(cols.start, w), cut(mask.shape[1] - cols.stop, w)))


def _filled(share: np.ndarray) -> slice:
    """From the first to the last place the sheet fills :data:`BARE_SHARE` of."""
    filled = np.flatnonzero(share >= BARE_SHARE)
    return slice(int(filled[0]), int(filled[-1]) + 1) if filled.size else slice(0, 0)


def _quarter_turn(size) -> np.ndarray:
    """Map from the pixels of an image of ``size`` (width, height) turned a quarter
    counter-clockwise to the pixels of the image (centres at whole numbers): the turned
    image's pixel (x′, y′) is the image's (w − 1 − y′, x′)."""
    return np.array([[0, -1, size[0] - 1], [1, 0, 0], [0, 0, 1.0]])


def _mean_scale(homography: np.ndarray, size) -> float:
    """Original pixels per sheet pixel at the sheet's centre (√ of the local area ratio)."""
    c = np.array([[[size[0] / 2, size[1] / 2]], [[size[0] / 2 + 1, size[1] / 2]],
                  [[size[0] / 2, size[1] / 2 + 1]]], np.float64)
    p = cv2.perspectiveTransform(c, homography)[:, 0, :]
    (ax, ay), (bx, by) = p[1] - p[0], p[2] - p[0]
    return float(math.sqrt(abs(ax * by - ay * bx)))


PEAK_SPAN = 0.5
"""Turn either side of the best angle at which a straight line's peak of the skew score has
fallen off (:func:`skew_angle`). [deg]"""

PEAK_DROP = 0.9
"""Largest share of the best skew score that the score :data:`PEAK_SPAN` either side may
keep for the best angle to be a straight line's peak."""


def skew_angle(density: np.ndarray, limit: float, *, sharp: bool = False) -> float:
    """The rotation (counter-clockwise, degrees) that makes the ink's rows sharpest.

    The ink pixels (density above 4 σ of the paper's) are projected onto the rows of the
    image turned by each trial angle; the angle whose row histogram has the largest sum of
    squares wins (long straight lines then fall into single rows). Searched over ± ``limit``
    in 0.1° steps, then refined by a parabola through the best three. With ``sharp`` (a
    sheet squared up by its edges, which already lie along the time base), the best angle
    is taken only where it is a straight line's peak: half a degree off it the score falls
    below :data:`PEAK_DROP` of its height. A record without long straight lines (a trace
    whose mean drifts, dots and dashes for marks) scores a broad hump whose top follows
    the trace's drift, not the paper: the edges' own angle is kept.

    Parameters
    ----------
    density : numpy.ndarray
        Optical density (:func:`flatten`).
    limit : float
        Largest angle searched. [deg]
    sharp : bool
        Take only a straight line's sharp peak.

    Returns
    -------
    float
        [deg]; 0 when no angle sharpens the profile by 2 % over none (or, with ``sharp``,
        the best is no sharp peak).
    """
    noise = _noise(density)
    rows, cols = np.nonzero(density > 4 * noise)
    if rows.size < 50:
        return 0.0
    weight = density[rows, cols].astype(np.float64)
    rows = rows.astype(np.float64)
    cols = cols.astype(np.float64) - density.shape[1] / 2
    angles = np.arange(-limit, limit + 1e-9, 0.1)

    def score(angle: float) -> float:
        r = rows + cols * math.tan(math.radians(angle))
        hist = np.bincount(np.round(r - r.min()).astype(np.int64), weights=weight)
        return float(hist @ hist)

    scores = np.array([score(a) for a in angles])
    k = int(np.argmax(scores))
    if scores[k] < 1.02 * score(0.0):
        return 0.0
    best = angles[k]
    if sharp and max(score(best - PEAK_SPAN), score(best + PEAK_SPAN)) > PEAK_DROP * scores[k]:
        return 0.0
    if 0 < k < len(angles) - 1:
        s0, s1, s2 = scores[k - 1], scores[k], scores[k + 1]
        den = s0 - 2 * s1 + s2
        if den < 0:
            best += 0.1 * 0.5 * (s0 - s2) / den
    return float(best)


def flatten(grey: np.ndarray, *, reduction: int = BACKGROUND_REDUCTION) -> tuple[np.ndarray, float]:
    """Optical density of the ink above the local paper level, and its noise.

    .. math:: D = \\ln\\frac{P}{g}

    with g the darkness channel and P the paper's level around it: a grey closing (which
    lifts off every stroke thinner than the kernel) of a reduced copy, smoothed and brought
    back to full size. The median of D over the sheet is taken as its zero.

    Parameters
    ----------
    grey : numpy.ndarray
        uint8 darkness image, the sheet squared up.
    reduction : int
        Reduction of the copy the paper level is found on.

    Returns
    -------
    density : numpy.ndarray
        float32, same shape; ≈ 0 on bare paper, ≈ 1–3 in a trace's core.
    noise : float
        Robust σ of the density on bare paper (1.4826 × the median absolute deviation).
    """
    h, w = grey.shape
    small = grey if reduction == 1 else cv2.resize(
        grey, (max(w // reduction, 1), max(h // reduction, 1)), interpolation=cv2.INTER_AREA)
    k = BACKGROUND_KERNEL if reduction > 1 else BACKGROUND_KERNEL * 2 + 1
    paper = cv2.morphologyEx(small, cv2.MORPH_CLOSE,
                             cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k)))
    paper = cv2.blur(paper, (k, k))
    if paper.shape != grey.shape:
        paper = cv2.resize(paper, (w, h), interpolation=cv2.INTER_LINEAR)
    density = cv2.LUT(paper, _LOG) - cv2.LUT(grey, _LOG)
    sample = density[::5, ::3]
    zero = float(np.median(sample))
    density -= zero
    return density, _noise(density)


def _noise(density: np.ndarray) -> float:
    sample = density[::5, ::3].ravel()
    med = np.median(sample)
    return max(float(1.4826 * np.median(np.abs(sample - med))), 1e-4)
