"""A photographed or scanned paper record read into the channel every lab reads: time, value,
marks, with a confidence per sample and the overlay of what was read.

:func:`read_paper_records` runs the chain once: the file (:func:`~.paper.load_image`), the
sheet found and squared up (:func:`~.paper.find_sheet`, :func:`~.paper.square_up`), its
density (:func:`~.paper.flatten`), the straight lines lifted off
(:func:`~.lines.remove_lines`), the pips beside them timed (:func:`~.marks.find_pips`), the
traces followed (:func:`~.traces.find_runs`, :func:`~.traces.follow`), then the scales:

* time: from the time marks and their period, ``t = T_mark·k(x)``
  (:func:`~.marks.time_base`), or from the paper speed and the length scale when the record
  has no time marks; given both, they must agree;
* length on the paper, in m per pixel, from one of: a printed grid's pitch (``grid``), the
  sheet's width between its edges (``paper_width``, 120 mm on the manual's torsiograph), a
  scan's resolution (``dpi``); given several, they must agree;
* value: the deflection from the beam's zero (the trace's mean level, or its zero line) in m,
  times ``scale`` (a calibration: value units per m of deflection) if given; in pixels
  when no length scale is known.

The sheet is turned upright by what the oscillograph draws on it: the time runs along the
mark lines, and the time-mark line runs below the TDC line (a lone one in the lower half). A
photograph taken upside down, in portrait either way or at any angle on the desk
is read turned upright (``turns`` of each record says how): with both mark lines on it, the
time-mark line runs below the TDC line, whichever way their pips point (a marker's ticks point
up or down as it is wired); a lone time-mark line lies in the sheet's lower half, a lone TDC
line in its upper half. A sheet with no
mark line at all is read as its edges lay it out (nothing on it tells up from
down). A mirror image cannot be told from a turned one: the time marks are evenly spaced
rectangles, the same read forwards or backwards, so a sheet flipped top to bottom looks
exactly like one turned half round and read backwards in time, and one flipped left to right
like the sheet read backwards; the traces' shapes are the experiment's, not the reader's to
judge. So a photograph is taken as unmirrored — as a camera or a scanner sees the face of an
opaque sheet — and a mirrored one (a phone's front camera set to mirror) reads backwards in
time.

Every sample of a :class:`PaperRecord` lies on a uniform time grid from t = 0, so a lab reads
it like a recorded channel (``sample_rate``, ``read()``, ``chunks()``); in a gap (the trace
lost or crossing another) the value is NaN and ``read()`` refuses, unless the record was read
with ``bridge`` (the longest gap to interpolate across, reported by a warning).

Examples
--------
>>> from processing.synth.paper_record import Beam, Layout, Shot, render
>>> scene = render(Layout(length=0.25, tdc_times=(0.05, 0.15, 0.25)),
...                [Beam(lambda t: np.sin(2 * np.pi * 10 * t), 0.06, 0.02)],
...                Shot(size=(900, 500), rotation=1.5))
>>> rec = read_paper_record(scene.image, mark_period=0.01, paper_width=0.12)
>>> rec.unit, round(rec.sample_rate, -2), rec.marks["tdc"].size
('m', 1600.0, 3)
>>> bool(np.nanmax(rec.value) > 0.019 and np.nanmin(rec.value) < -0.019)
True
"""
from __future__ import annotations

import math
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

from ..diagnostics import (BlurredMarksWarning, InputError, LowConfidenceTraceWarning,
                           UnevenTimeBaseWarning)
from ..numerals import plural
from ..result import Figure
from ..uncertainty import Measured
from .lines import Line, grid_spacing, remove_lines, restore_rests
from .marks import (MIN_TIME_MARKS, Pips, TimeBase, TimeMarkError, find_mark_rows, find_pips,
                    time_base)
from .overlay import Overlay, plot_values
from .paper import Sheet, darkness, find_sheet, flatten, load_image, square_up, working_copy
from .traces import LOW_CONFIDENCE, NoTraceError, Traces, find_runs, follow, ink_threshold

LOW_SHARE = 0.05
"""Share of low-confidence samples above which a record warns."""

SCALE_AGREEMENT = 0.03
"""Relative disagreement allowed between two length scales, or between the paper speed and
the time marks (on top of twice their combined u)."""

UNEVEN_SPEED = 0.005
"""Relative change of the mark spacing along the record above which a record warns."""

BLURRED_MARKS = 0.5
"""Standard uncertainty of where the marks rise above which a record warns. [px]"""

ZERO_CHOICES = ("mean", "line")

ZERO_LINE_SHARE = 0.9
"""Share of the longest line's length a zero line runs along: a beam at rest exposes it end to
end, as the markers their lines (the frame may hold more than the sheet)."""

EDGE_STEP = 0.025
"""Relative difference of the bare background's brightness on the two sides of a straight line
above which it is the sheet's edge against a scanner's lid or a table (a zero line has paper
on both sides)."""

BARE_PERCENTILE = 75
"""Percentile of a column's brightness across a band beside a line taken for its bare
background (:func:`_edge_step`)."""

INK_SHARE = 0.5
"""Least density of a zero line as a share of the darkest line's: a beam at rest exposes it
fully, as the traces are; a printed grid line or the shadow of the paper's edge is fainter."""

MARK_INK = 0.2
"""Least density of a line bearing marks as a share of the darkest line's (a marker's line is
broken where its pips lift it, so it reads fainter than a zero line, but far darker than a
printed grid line or an edge's shadow)."""

GRID_INK = 4.0
"""A line on a printed grid's pitch this many times darker than the grid's lines (their median)
was exposed there, not printed."""

PARALLEL = 2.0
"""Largest drift of a zero line from the time base's direction over the sheet's length. [px]"""


@dataclass(frozen=True)
class PaperRecord:
    """One trace of a paper record: a channel like a recorded one, with its confidence.

    Attributes
    ----------
    path : str
        The image (``"<image>"`` for an array).
    name : str
        ``"trace k"``, k counted from the top of the sheet, 0-based.
    field : str or None
        The measurement-file field that named the image.
    time : numpy.ndarray
        Sample times, uniform, from 0. [s]
    value : numpy.ndarray
        Deflection from the zero (see ``unit``); NaN where the trace was not read.
    confidence : numpy.ndarray
        0–1 per sample; 0 in gaps and across bridged gaps.
    u_value : numpy.ndarray
        Standard uncertainty of each sample from the image noise (the scales' u not
        included), in ``unit``.
    unit : str
        ``"m"`` (deflection on the paper), ``"px"`` (no length scale), or the unit of
        ``scale`` as given.
    marks : dict
        ``"time"``: the time marks (where the time base puts them, T_mark apart), ``"tdc"``:
        the TDC marks (as read), on the record's time axis. [s]
    marks_u : dict
        Standard uncertainty of where each kind of mark rises against the trace (common to
        all marks of a kind; blur widens it). [s]
    time_scale : Measured
        Seconds per pixel along the sheet (at the middle of the marks). [s/px]
    value_scale : Measured
        Value units per pixel across the sheet (1 for ``"px"``).
    time_base : TimeBase or None
        The fit of the time marks (None when the time came from the paper speed).
    bridged : numpy.ndarray
        True where a gap was interpolated across (``bridge``).
    stroke : float
        The trace's stroke width across where it runs flat. [px] Times and extremes read off
        a steep or sharply turning stroke are known only within about this much
        (:attr:`stroke_time`, :attr:`stroke_value`).
    spread : float
        σ of the light across the stroke where it runs flat (the spot's and the capture's
        blur, :attr:`~.traces.Traces.spread`). [px]
    overlay : Overlay
        What was read, to draw over the sheet.
    turns : int
        Quarter turns, counter-clockwise, that brought the sheet upright (the photograph
        turned: 2 upside down, 1 or 3 in portrait).
    lines : str
        The straight lines found along the sheet and what each was taken for (the zero line
        measured from marked ``taken``), for messages.
    lines_ru : str
        The same in Russian.
    """

    path: str
    name: str
    field: str | None
    time: np.ndarray
    value: np.ndarray
    confidence: np.ndarray
    u_value: np.ndarray
    unit: str
    marks: dict
    marks_u: dict
    time_scale: Measured
    value_scale: Measured
    time_base: TimeBase | None
    bridged: np.ndarray
    stroke: float
    spread: float
    overlay: Overlay = field(repr=False)
    turns: int = 0
    lines: str = ""
    lines_ru: str = ""

    @property
    def clock(self) -> Measured:
        """The time base as a factor on every time read off the record: 1 with the relative
        standard uncertainty of :attr:`time_scale` (type B), so that a lab's model carries
        it once, in common to all it times: a frequency read off the record is the factor
        times its reading, a duration its reading over the factor (a ratio of two times,
        a phase, does not depend on it)."""
        return Measured(1.0, u_b=self.time_scale.u / abs(self.time_scale.value))

    @property
    def stroke_time(self) -> float:
        """The stroke's width along the time axis. [s]"""
        return self.stroke * self.time_scale.value

    @property
    def stroke_value(self) -> float:
        """The stroke's width across, in ``unit``."""
        return self.stroke * abs(self.value_scale.value)

    @property
    def stroke_blur(self) -> float:
        """σ of the low-pass along the time axis that the rows read have been through [s]:
        an exposure centroid is the spot's path averaged over the light spot's profile and
        the capture's blur along the time axis (a ripple of period P flattened by
        exp(−(2πσ/P)²/2)), which a round spot and an even blur spread alike across the
        stroke (:attr:`spread`)."""
        return self.spread * self.time_scale.value

    # --- the channel's interface (processing.inputs.signals.Channel) ---

    @property
    def sample_rate(self) -> float:
        """Samples per second. [Hz]"""
        return 1.0 / float(self.time[1] - self.time[0])

    @property
    def length(self) -> int:
        return int(self.value.size)

    @property
    def duration(self) -> float:
        """``length / sample_rate``. [s]"""
        return self.length / self.sample_rate

    @property
    def dtype(self) -> np.dtype:
        return np.dtype(np.float64)

    @property
    def volts_per_code(self) -> float:
        """1: the values are already in ``unit``."""
        return 1.0

    def read(self) -> np.ndarray:
        """The whole record (a copy).

        Raises
        ------
        InputError
            The trace has gaps (not read there); names the first and the fix.
        """
        (values,) = self.chunks(self.length)
        return values

    def chunks(self, size: int = 2 ** 22, start: int = 0,
               stop: int | None = None) -> Iterator[np.ndarray]:
        """Consecutive blocks of the record, as :meth:`processing.inputs.signals.Channel.chunks`.

        Raises
        ------
        InputError
            At the first gap in ``start``–``stop``.
        ValueError
            ``size`` < 1 or not ``0 ≤ start ≤ stop ≤ length``.
        """
        stop = self.length if stop is None else int(stop)
        if size < 1:
            raise ValueError(f"chunks: size must be ≥ 1 sample, got {size}")
        if not 0 <= start <= stop <= self.length:
            raise ValueError(f"chunks: need 0 ≤ start ≤ stop ≤ {self.length}, "
                             f"got start={start}, stop={stop}")
        lost = np.flatnonzero(~np.isfinite(self.value[start:stop]))
        if lost.size:
            gaps = self.gaps()
            t0 = self.time[start + lost[0]]
            raise InputError(
                f"{self.name} is not read over {len(gaps)} stretch(es) of the image "
                f"({_share(lost.size / max(stop - start, 1))} of the samples), the first at "
                f"t = {t0 * 1e3:.4g} ms", "look at the overlay: retake the photograph flat, "
                "sharp and evenly lit, or allow the gaps to be interpolated across with "
                "bridge (the longest gap, e.g. \"2 ms\") where the trace is smooth",
                file=self.path, field=self.field,
                ru=(f"линия записи не прочитана на участках снимка: {len(gaps)} "
                    f"({_share(lost.size / max(stop - start, 1))} отсчётов), первый при "
                    f"t = {t0 * 1e3:.4g} мс", "посмотрите на наложение: переснимите запись "
                    "ровно, резко и при ровном освещении или разрешите интерполировать "
                    "разрывы параметром bridge (наибольший разрыв, например \"2 ms\") там, "
                    "где линия плавная"))
        return (self.value[a:min(a + size, stop)].copy() for a in range(start, stop, size))

    # --- the reading's quality ---

    @property
    def low_confidence_share(self) -> float:
        """Share of the samples read with a confidence below 0.5 (gaps included)."""
        return float(np.mean(self.confidence < LOW_CONFIDENCE))

    def gaps(self) -> list[tuple[float, float]]:
        """(first, last) time of each stretch not read. [s]"""
        lost = ~np.isfinite(self.value)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], lost.astype(np.int8), [0]])))
        return [(float(self.time[a]), float(self.time[b - 1]))
                for a, b in zip(edges[::2], edges[1::2])]

    # --- drawing ---

    def plot(self, ax=None, *, lang: str = "en") -> None:
        """Draw the sheet with what was read on a matplotlib axis (a new figure if None)."""
        if ax is None:
            from matplotlib.figure import Figure as MplFigure
            ax = MplFigure(figsize=(8, 4)).add_subplot(1, 1, 1)
        self.overlay.plot(ax, lang=lang)

    def figure(self, name: str = "paper_record", caption: dict | None = None) -> Figure:
        """A report figure: the sheet with the overlay above, the record against time below."""
        caption = caption or {
            "en": f"The record read off {Path(self.path).name}: {self.name} (orange, "
                  "unreliable columns red), the marks and zero lines found; below, the "
                  "values against time",
            "ru": f"Запись, считанная с {Path(self.path).name}: "
                  f"{self.name.replace('trace', 'линия')} (оранжевая, недостоверные участки — красные), найденные отметки и нулевые "
                  "линии; ниже — значения по времени"}

        def draw(fig, lang: str) -> None:
            top, bottom = fig.subplots(2, 1, height_ratios=(3, 2))
            self.overlay.plot(top, lang=lang)
            plot_values(bottom, self.time, self.value, self.confidence, lang=lang,
                        unit=self.unit)
            fig.tight_layout()

        return Figure(name, caption, draw, (6.4, 6.0))


@dataclass(frozen=True)
class _Where:
    """The image and the fields errors point to."""

    path: str
    field: str | None
    options: str

    def error(self, problem: str, fix: str, option: str | None = None,
              ru: tuple[str, str] | None = None) -> InputError:
        where = f"{self.options}.{option}" if option else self.field
        return InputError(problem, fix, file=self.path, field=where, ru=ru)


def read_paper_record(source, *, trace: int = 0, **options) -> PaperRecord:
    """Read one trace of a photographed or scanned paper record.

    Parameters
    ----------
    source : str, Path or numpy.ndarray
        The image file (PNG, JPEG, TIFF, ...) or an image array (BGR or grey, uint8).
    trace : int
        Which trace: 0 is the topmost on the sheet, −1 the lowest.
    **options
        As :func:`read_paper_records`.

    Returns
    -------
    PaperRecord

    Raises
    ------
    InputError
        As :func:`read_paper_records`; also a ``trace`` beyond those found.
    """
    records = read_paper_records(source, **options)
    if not -len(records) <= trace < len(records):
        where = _where(source, options.get("field"), options.get("options", "image"))
        raise where.error(f"trace {trace} asked for, {len(records)} trace(s) found on the sheet",
                          f"choose trace = 0 … {len(records) - 1} (0 is the topmost), or look "
                          "at the overlay for the trace missed", "trace",
                          ru=(f"запрошена линия {trace}, а на ленте найдено линий: "
                              f"{len(records)}", f"выберите trace = 0 … {len(records) - 1} "
                              "(0 — верхняя) или найдите пропущенную линию на наложении"))
    return records[trace]


def read_paper_records(source, *, traces: int | None = None, mark_period=None,
                       paper_speed=None, dpi=None, paper_width=None, grid=None, scale=None,
                       unit: str = "", zero: str = "mean", bridge: float = 0.0,
                       field: str | None = None, options: str = "image") -> list[PaperRecord]:
    """Read every trace of a photographed or scanned paper record.

    The time runs along the mark lines, left to right with the marks lifting their lines
    (the sheet is turned so, see the module's notes); the time-mark line and the TDC line are
    straight lines with rectangular pips (the denser regular set of pips is the time
    marks). A picture larger than :data:`~.paper.WORK_PIXELS` is read reduced to it.

    Parameters
    ----------
    source : str, Path or numpy.ndarray
        The image file or an image array (BGR or grey, uint8).
    traces : int, optional
        How many traces the sheet carries (default: the commonest count per column).
    mark_period : float or Measured, optional
        Period of the time marks, T_mark. [s]
    paper_speed : float or Measured, optional
        Speed of the paper. [m/s] Without time marks it sets the time base (with a length
        scale); with them, it is checked against them.
    dpi : float or Measured, optional
        A flatbed scan's resolution. [1/inch]
    paper_width : float or Measured, optional
        The sheet's width between its long edges (both in the picture). [m]
    grid : float or Measured, optional
        Pitch of a printed grid on the sheet. [m]
    scale : float or Measured, optional
        Calibration: value units per metre of deflection (e.g. rad/m from the torsiograph's
        static calibration). Needs a length scale.
    unit : str
        The unit of ``scale``'s values, for labels.
    zero : {"mean", "line"}
        Deflection measured from the trace's mean level, or from the nearest straight line
        without marks (the beam's zero line).
    bridge : float
        Longest gap interpolated across (monotone cubic), reported by a warning. [s]
    field : str, optional
        The measurement-file field that named the image.
    options : str
        Dotted path of the table holding these options in the measurement file, for errors.

    Returns
    -------
    list of PaperRecord
        Top to bottom.

    Raises
    ------
    InputError
        A missing file, not an image, or one whose header states more than
        :data:`~.paper.MAX_PIXELS`; signs of the sheet's orientation that disagree; no
        trace found; no time base (no mark period, or
        fewer than three time marks without a paper speed); a paper speed or a length scale
        that contradicts the marks or another scale; an option out of range.

    Warns
    -----
    LowConfidenceTraceWarning
        More than 5 % of a trace's samples read with low confidence, or any gap bridged.
    UnevenTimeBaseWarning
        The mark spacing changes by more than 0.5 % along the record.
    BlurredMarksWarning
        Where the marks rise is uncertain by more than half a pixel (pips blurred into
        blobs).
    """
    where = _where(source, field, options)
    given = _options(where, mark_period=mark_period, paper_speed=paper_speed, dpi=dpi,
                     paper_width=paper_width, grid=grid, scale=scale)
    if zero not in ZERO_CHOICES:
        raise where.error(f"zero = {zero!r}", f"use one of {', '.join(ZERO_CHOICES)}", "zero",
                          ru=(f"zero = {zero!r}", f"укажите одно из {', '.join(ZERO_CHOICES)}"))
    if not (bridge >= 0 and math.isfinite(bridge)):
        raise where.error(f"bridge = {bridge!r}", "give the longest gap to interpolate, ≥ 0 s",
                          "bridge", ru=(f"bridge = {bridge!r}", "укажите наибольший "
                                        "интерполируемый разрыв, ≥ 0 с"))
    grey, reduction = (load_image(source, field=field) if isinstance(source, (str, Path))
                       else working_copy(darkness(source, name=where.path, field=field)))
    laid = _upright(where, grey)
    sheet, density, noise = laid.sheet, laid.density, laid.noise
    lines, time_pips, tdc_pips, plain = laid.lines, laid.time_pips, laid.tdc_pips, laid.plain
    for pips in (time_pips, tdc_pips):
        if pips is not None:
            density[pips.band[0]:pips.band[1]] = 0.0
    metres = _length_scale(where, given, sheet, plain, reduction)
    seconds = _time_scale(where, given, metres, time_pips)
    found_pips = {k: p for k, p in (("time", time_pips), ("tdc", tdc_pips)) if p is not None}
    judged = judge_lines(sheet.grey, lines, plain, found_pips) if lines else []
    zero_lines = [line for line, kind in judged if kind == "zero line"]
    restore_rests(density, laid.drawn, zero_lines, ink_threshold(density, noise)[0])
    try:
        found = _on_sheet(follow(find_runs(density, noise, plain), density.shape[1], traces),
                          density.shape[0])
    except NoTraceError as exc:
        raise where.error(f"{exc} (after the straight lines and marks were set aside)",
                          "photograph the record so that the traces fill the frame, sharp and "
                          "evenly lit; check that the file is the oscillogram",
                          ru=(f"{exc.ru} (прямые линии и отметки отложены в сторону)",
                              "сфотографируйте запись так, чтобы линии заполняли кадр, резко "
                              "и при ровном освещении; проверьте, что это файл "
                              "осциллограммы")) from None
    value_scale, unit = _value_scale(where, given, metres, unit)
    overlay_marks = {k: (p.rising, float(p.line.at(density.shape[1] / 2) + p.side * p.offset))
                     for k, p in (("time", time_pips), ("tdc", tdc_pips)) if p is not None}
    records = []
    for j in range(found.count):
        records.append(_record(where, found, j, seconds, value_scale, unit, zero, zero_lines,
                               lines, found_pips, bridge, sheet, overlay_marks, judged,
                               metres))
    return records


MIN_SPAN = 0.05
"""A 'trace' whose record (:func:`_ends`: its confident stretch, bits cut off at its ends
left out) spans less than this share of the sheet's columns is a follower's few steps
through the noise, not a beam's record."""


def _on_sheet(found: Traces, h: int) -> Traces:
    """The traces on the paper: a 'trace' whose stroke reaches the squared-up sheet's top or
    bottom border (``h`` rows) in most of its columns is the background beyond the sheet's
    edge (a dark lid or table left inside the sheet's outline), not a beam's record; nor is
    one whose record spans less than :data:`MIN_SPAN` of the sheet.

    Raises
    ------
    NoTraceError
        Nothing is left."""
    keep = []
    for j in range(found.count):
        rows = found.row[j][np.isfinite(found.row[j])]
        reach = float(found.width[j])
        border = (rows < reach) | (rows > h - 1 - reach)
        first, last = _ends(found.row[j], found.confidence[j], reach)
        if not np.mean(border) > 0.5 and last - first + 1 >= MIN_SPAN * found.row.shape[1]:
            keep.append(j)
    if not keep:
        raise NoTraceError("no trace stands out of the paper inside the sheet's edges",
                           "ни одна линия записи не выделяется на бумаге внутри краёв ленты")
    if len(keep) == found.count:
        return found
    return replace(found, run=found.run[keep], row=found.row[keep], u=found.u[keep],
                   confidence=found.confidence[keep], width=found.width[keep],
                   spread=found.spread[keep])


def judge_lines(grey: np.ndarray, lines: list[Line], plain: list[Line],
                marked: dict[str, Pips]) -> list[tuple[Line, str]]:
    """What each straight line along the sheet is: ``"time marks"`` / ``"TDC marks"`` (the
    lines the pips rise from), ``"grid"`` (a printed grid's), ``"edge"`` (the sheet's edge
    against a lid or table: bare background of different brightness on its two sides, or
    the frame's edge beside it), ``"beside marks"`` (along the pips' tops), ``"faint"`` (fainter than ink: an edge's shadow, a printed
    line), ``"short"``, ``"skewed"`` (not parallel to the time base), or ``"zero line"``:
    long, straight, parallel to the time base, inside the sheet, exposed like the marks.

    Parameters
    ----------
    grey : numpy.ndarray
        The squared-up sheet's brightness image (:attr:`~.paper.Sheet.grey`).
    lines : list of Line
        Every straight line found along the rows.
    plain : list of Line
        Those without pips.
    marked : dict
        The pips found, with their lines: ``"time"`` and ``"tdc"`` → Pips.

    Returns
    -------
    list of (Line, str)
        Top to bottom.
    """
    printed = grid_spacing(plain)
    grid = set()
    if printed is not None:
        # a line exposed on a grid line's place is far darker than the print
        typical = float(np.median([line.strength for line in printed.lines]))
        grid = {id(line) for line in printed.lines if line.strength < GRID_INK * typical}
    reference = max(line.strength for line in lines)
    slope = float(np.median([p.line.slope for p in marked.values()])) if marked else 0.0
    w = grey.shape[1]
    longest = max(line.share for line in lines)
    owner = {id(p.line): ("time marks" if k == "time" else "TDC marks") for k, p in marked.items()}
    out = []
    for line in lines:
        if id(line) in owner:
            kind = owner[id(line)]
        elif line not in plain:
            kind = "beside marks"
        elif id(line) in grid:
            kind = "grid"
        elif _edge_step(grey, line) > EDGE_STEP:
            kind = "edge"
        elif line.strength < INK_SHARE * reference:
            kind = "faint"
        elif line.share < ZERO_LINE_SHARE * longest:
            kind = "short"
        elif abs(line.slope - slope) * w > max(PARALLEL, line.width):
            kind = "skewed"
        else:
            kind = "zero line"
        out.append((line, kind))
    return out


def _edge_step(grey: np.ndarray, line: Line) -> float:
    """Relative difference of the bare background's brightness in two bands beside a line,
    clear of its stroke (1 where a band leaves the frame: the line runs along the frame's
    edge). The background of a column's band is its brightest rows (:data:`BARE_PERCENTILE`):
    ink only darkens, and a trace dwelling beside a zero line (a decay settled on it, a
    torsiogram about it) covers a few of the band's rows, where a lid or a table covers all;
    the median over the columns follows."""
    h, w = grey.shape
    cols = np.arange(0, w, max(1, w // 600))
    centre = line.at(cols)
    near = line.width + 3
    offsets = np.arange(near, near + max(6.0, 0.01 * h))
    sides = []
    for side in (-1, 1):
        rows = np.round(centre[None, :] + side * offsets[:, None]).astype(int)
        if np.mean((rows >= 0) & (rows < h)) < 0.9:
            return 1.0
        band = grey[np.clip(rows, 0, h - 1), cols[None, :]].astype(float)
        sides.append(float(np.median(np.percentile(band, BARE_PERCENTILE, axis=0))))
    return abs(sides[0] - sides[1]) / max(max(sides), 1.0)


@dataclass(frozen=True)
class _Laid:
    """The sheet squared up one way, with what lies on it."""

    sheet: Sheet
    density: np.ndarray
    noise: float
    lines: list[Line]
    drawn: np.ndarray
    """The density before the straight lines were lifted off."""
    time_pips: Pips | None
    tdc_pips: Pips | None
    plain: list[Line]

    @property
    def marks(self) -> Pips | None:
        """The pips the orientation is told by: the time marks', else the TDC marks'."""
        return self.time_pips if self.time_pips is not None else self.tdc_pips

    def upright(self) -> bool:
        """Whether the sheet lies upright: the time-mark line runs below the TDC line where
        both are on it, else a lone time-mark line in the sheet's lower half (a lone TDC line
        in its upper half). A marker's pips point up or down as it is wired, so they do not
        tell."""
        middle = self.density.shape[0] / 2
        if self.time_pips is not None and self.tdc_pips is not None:
            return self.time_pips.line.position > self.tdc_pips.line.position
        if self.time_pips is not None:
            return self.time_pips.line.position > middle
        return self.tdc_pips.line.position < middle


def _laid_out(grey: np.ndarray, corners, turns: int) -> _Laid:
    """The sheet squared up and turned ``turns`` quarters counter-clockwise: its density,
    its straight lines lifted off, the pips beside them."""
    sheet = square_up(grey, corners, turns=turns)
    density, noise = flatten(sheet.grey)
    drawn = density.copy()
    lines = remove_lines(density, noise)
    remove_lines(density.T, noise)
    return _Laid(sheet, density, noise, lines, drawn, *_mark_lines(density, lines, noise))


def _upright(where: _Where, grey: np.ndarray) -> _Laid:
    """The sheet turned upright by what is drawn on it (:meth:`_Laid.upright`): time along
    the mark lines, the marks lifting their lines (the pips point up), the time-mark line
    below the TDC line.

    The sheet is read as its edges (or the frame) lay it out, its long side along the rows;
    if it has no mark line along the rows, it is read turned a quarter. Lying upside down
    (the time-mark line above the TDC line, or a lone one in the upper half), it is turned
    half round. A sheet without any mark line is read as laid out (nothing on
    it tells which way is up).

    Raises
    ------
    InputError
        Turned half round, the sheet does not read upright either (its mark lines are not
        found again the same way).
    """
    corners = find_sheet(grey)
    laid = _laid_out(grey, corners, 0)
    if laid.marks is None:
        across = _laid_out(grey, corners, 1)
        if across.marks is None:
            return laid
        laid = across
    if laid.upright():
        return laid
    turned = _laid_out(grey, corners, laid.sheet.turns + 2)
    if turned.marks is None or not turned.upright():
        raise _orientation_unknown(where, laid)
    return turned


def _orientation_unknown(where: _Where, laid: _Laid) -> InputError:
    """The refusal of a sheet whose signs of which way is up disagree, naming them."""
    time, tdc = laid.time_pips, laid.tdc_pips
    told, told_ru = [], []
    for kind, kind_ru, p in (("time", "времени", time), ("TDC", "ВМТ", tdc)):
        if p is not None:
            told.append(f"the {kind} marks point {'up' if p.side < 0 else 'down'}")
            told_ru.append(f"отметки {kind_ru} направлены {'вверх' if p.side < 0 else 'вниз'}")
    if time is not None and tdc is not None:
        below = time.line.position > tdc.line.position
        told.append(f"the time-mark line runs {'below' if below else 'above'} the TDC line")
        told_ru.append(f"линия отметок времени идёт {'ниже' if below else 'выше'} линии ВМТ")
    return where.error(
        f"which way is up cannot be told from the sheet: {', '.join(told)}",
        "rotate the photograph so that the time runs left to right along the sheet, with the "
        "time-mark line at the bottom below the TDC line and the marks pointing up (a marker "
        "lifts its line)",
        ru=(f"по ленте не понять, где верх: {', '.join(told_ru)}",
            "поверните снимок так, чтобы время шло вдоль ленты слева направо, линия отметок "
            "времени была внизу, под линией ВМТ, а отметки смотрели вверх (отметчик "
            "приподнимает свою линию)"))


def _where(source, field, options) -> _Where:
    return _Where(str(source) if isinstance(source, (str, Path)) else "<image>", field, options)


def _options(where: _Where, **values) -> dict[str, Measured]:
    """The given options as Measured, each checked to be a positive number."""
    out = {}
    for name, v in values.items():
        if v is None:
            continue
        m = v if isinstance(v, Measured) else None
        if m is None:
            try:
                m = Measured(float(v))
            except (TypeError, ValueError):
                raise where.error(f"{name} = {v!r} is not a number",
                                  f"give {name} as a positive number in SI units",
                                  name, ru=(f"{name} = {v!r} — не число", f"укажите {name} "
                                            "положительным числом в единицах СИ")) from None
        if not (math.isfinite(m.value) and m.value > 0) and name != "scale":
            raise where.error(f"{name} = {m.value!r}", f"{name} must be a positive number",
                              name, ru=(f"{name} = {m.value!r}",
                                        f"{name} должно быть положительным числом"))
        if name == "scale" and not (math.isfinite(m.value) and m.value != 0):
            raise where.error(f"scale = {m.value!r}", "scale must be a non-zero number of "
                              "value units per metre of deflection", name,
                              ru=(f"scale = {m.value!r}", "scale — ненулевое число единиц "
                                  "величины на метр отклонения"))
        out[name] = m
    return out


def _mark_lines(density, lines: list[Line], noise: float):
    """The time-mark pips (the line with the most pips on an even grid), the TDC pips (the
    line with the most of the rest) and the lines without pips. A line fainter than the
    exposed ones bears no marks (a printed grid's: the grid's cross lines hang from it like
    pips; the shadow of the sheet's edge on a scanner's lid)."""
    h = density.shape[0]
    found: list[Pips] = []
    darkest = max((line.strength for line in lines), default=0.0)
    for line in lines:
        if line.strength < MARK_INK * darkest:
            continue
        # the pips stay clear of the next line as dark as this one, on either side
        reach = []
        for side in (-1, 1):
            gaps = [side * (o.position - line.position) - o.width / 2 for o in lines
                    if o is not line and o.strength > 0.5 * line.strength
                    and side * (o.position - line.position) > 0]
            reach.append(min([0.1 * h] + [0.75 * d for d in gaps]))
        pips = find_pips(density, line, noise, tuple(reach))
        if pips is not None:
            found.append(pips)
    # pips seen from two lines belong to the one that drew them: the one as dark as they
    # (a faint 'line' along their tops is not), else the nearer (their sides rise from it)
    found = [p for p in found if not any(
        q is not p and abs(_top_row(p) - _top_row(q)) < 3 and _owns(q, p) for q in found)]
    # a row of marks without a line (dots): where a line as dark as the marks runs through
    # it, its pips were sought from the line (its own bumps and the stroke beside it are none)
    inked = [line.position for line in lines if line.strength >= MARK_INK * darkest]
    found += [p for p in find_mark_rows(density, noise) if all(
        p.band[1] <= q.band[0] or p.band[0] >= q.band[1] for q in found)
        and not any(p.band[0] <= y < p.band[1] for y in inked)]
    chosen: list[Pips] = []
    for pips in sorted(found, key=lambda p: (_regular_marks(p), p.line.strength), reverse=True):
        if all(pips.band[1] <= c.band[0] or pips.band[0] >= c.band[1] for c in chosen):
            chosen.append(pips)
    time_pips = chosen[0] if chosen and _regular_marks(chosen[0]) >= 3 else None
    rest = chosen[1:] if time_pips is not None else chosen
    # a TDC marker marks each revolution of a steady regime: its pips lie on an even grid
    # (some may be missed); a trace's strokes off a line it swings about do not
    rest = [p for p in rest if p.count < MIN_TIME_MARKS or _regular_marks(p) >= MIN_TIME_MARKS]
    tdc_pips = max(rest, key=lambda p: p.count) if rest else None
    marked = [p for p in (time_pips, tdc_pips) if p is not None]
    # a faint 'line' along the pips' tops belongs to them too
    plain = [line for line in lines if not any(
        p.line is line or p.band[0] <= line.position < p.band[1] for p in marked)]
    return time_pips, tdc_pips, plain


def _owns(q: Pips, p: Pips) -> bool:
    """Whether the pips seen from both q's line and p's belong to q's."""
    ratio = q.line.strength / p.line.strength
    return ratio > 3 or (ratio > 1 / 3 and q.offset < p.offset)


def _top_row(pips: Pips) -> float:
    return pips.line.position + pips.side * pips.offset


def _regular_marks(pips: Pips) -> int:
    """How many of the pips make an even time base (0 if they make none)."""
    try:
        return int(time_base(pips.rising, 1.0).numbers.size)
    except TimeMarkError:
        return 0


def _length_scale(where: _Where, given: dict, sheet, plain: list[Line],
                  reduction: float) -> Measured | None:
    """Metres of paper per sheet pixel from the grid, the paper width or the dpi (of the
    file's pixels, ``reduction`` to each pixel the sheet was read off); several must
    agree."""
    scales = {}
    if "grid" in given:
        g = grid_spacing(plain)
        if g is None:
            raise where.error("no printed grid found on the sheet (at least 4 evenly spaced "
                              "straight lines)", "leave grid out, or give paper_width or dpi",
                              "grid", ru=("на ленте не найдена отпечатанная сетка (хотя бы 4 "
                                          "равноотстоящие прямые)", "уберите grid или укажите "
                                          "paper_width или dpi"))
        m = given["grid"]
        scales["grid"] = Measured(m.value / g.pitch, u_b=math.hypot(
            m.u / g.pitch, m.value * g.u_pitch / g.pitch ** 2))
    if "paper_width" in given:
        if sheet.paper_size is None:
            raise where.error("the sheet's edges are not in the picture, so its width in "
                              "pixels is unknown", "photograph the whole sheet on a darker "
                              "background, or give dpi (a scan) or grid", "paper_width",
                              ru=("края ленты не видны на снимке, и её ширина в пикселях "
                                  "неизвестна", "снимите ленту целиком на более тёмном фоне "
                                  "или укажите dpi (скан) или grid"))
        m, px = given["paper_width"], sheet.paper_size[1]
        scales["paper_width"] = Measured(m.value / px, u_b=math.hypot(m.u / px,
                                                                       m.value / px ** 2))
    if "dpi" in given:
        m = given["dpi"]
        per_px = 0.0254 / m.value * sheet.source_scale * reduction
        scales["dpi"] = Measured(per_px, u_b=per_px * m.u / m.value)
    if not scales:
        return None
    names = list(scales)
    first = scales[names[0]]
    for other in names[1:]:
        s = scales[other]
        gap = s.value / first.value - 1
        if abs(gap) > SCALE_AGREEMENT + 2 * math.hypot(s.u / s.value, first.u / first.value):
            raise where.error(f"{other} gives {s.value * 1e3:.5g} mm per pixel and {names[0]} "
                              f"{first.value * 1e3:.5g} ({100 * gap:+.1f} %)",
                              f"correct {other} or {names[0]}, or give only one of them",
                              other, ru=(f"{other} даёт {s.value * 1e3:.5g} мм на пиксель, а "
                                         f"{names[0]} — {first.value * 1e3:.5g} "
                                         f"({100 * gap:+.1f} %)", f"исправьте {other} или "
                                         f"{names[0]} либо укажите только одно из них"))
    return first


def _time_scale(where: _Where, given: dict, metres: Measured | None,
                pips: Pips | None) -> tuple[TimeBase | None, Measured]:
    """The time base: from the marks (checked against the paper speed if given), else from
    the paper speed and the length scale."""
    speed = given.get("paper_speed")
    if "mark_period" in given:
        period = given["mark_period"]
        try:
            if pips is None:
                raise TimeMarkError("no line with evenly spaced pips found",
                                    "не найдено линии с равномерно расставленными отметками")
            tb = time_base(pips.rising, period.value)
        except TimeMarkError as exc:
            if speed is None or metres is None:
                raise where.error(f"{exc}: too few time marks for a time base",
                                  "photograph the whole time-mark line sharply; or give "
                                  "paper_speed with paper_width, grid or dpi instead",
                                  "mark_period",
                                  ru=(f"{exc.ru}: по таким отметкам времени не построить "
                                      "шкалу времени", "сфотографируйте всю линию отметок "
                                      "времени резко или вместо этого укажите paper_speed "
                                      "вместе с paper_width, grid или dpi")) from None
        else:
            rel = math.hypot(tb.u_spacing / tb.spacing, period.u / period.value)
            per_px = Measured(period.value / tb.spacing, u_b=rel * period.value / tb.spacing)
            if speed is not None and metres is not None:
                implied = metres.value * tb.spacing / period.value
                gap = implied / speed.value - 1
                u = math.hypot(rel, metres.u / metres.value, speed.u / speed.value)
                if abs(gap) > SCALE_AGREEMENT + 2 * u:
                    raise where.error(
                        f"the time marks, {tb.spacing * metres.value * 1e3:.4g} mm apart, "
                        f"mean a paper speed of {implied:.4g} m/s with mark_period = "
                        f"{period.value:.4g} s, not the {speed.value:.4g} m/s given "
                        f"({100 * gap:+.1f} %)", "correct paper_speed or mark_period (the "
                        "marker's period), or leave paper_speed out", "paper_speed",
                        ru=(f"отметки времени в {tb.spacing * metres.value * 1e3:.4g} мм друг от "
                            f"друга при mark_period = {period.value:.4g} с означают скорость "
                            f"ленты {implied:.4g} м/с, а не заданные {speed.value:.4g} м/с "
                            f"({100 * gap:+.1f} %)", "исправьте paper_speed или mark_period "
                            "(период отметчика) либо уберите paper_speed"))
            return tb, per_px
    if speed is None:
        raise where.error("no time base: neither the time marks' period nor the paper speed "
                          "is given", "give mark_period (the time marker's period, e.g. "
                          "\"10 ms\"), or paper_speed with paper_width, grid or dpi",
                          "mark_period", ru=("нет масштаба времени: не заданы ни период "
                                             "отметок времени, ни скорость ленты", "укажите "
                                             "mark_period (период отметчика времени, например "
                                             "\"10 ms\") или paper_speed вместе с "
                                             "paper_width, grid или dpi"))
    if metres is None:
        raise where.error("paper_speed needs a length scale to turn pixels into time",
                          "also give paper_width, grid or dpi, or give mark_period",
                          "paper_speed", ru=("paper_speed нужен масштаб длины, чтобы перевести "
                                             "пиксели во время", "укажите также paper_width, "
                                             "grid или dpi либо задайте mark_period"))
    value = metres.value / speed.value
    return None, Measured(value, u_b=value * math.hypot(metres.u / metres.value,
                                                        speed.u / speed.value))


def _value_scale(where: _Where, given: dict, metres: Measured | None,
                 unit: str) -> tuple[Measured, str]:
    if "scale" in given:
        if metres is None:
            raise where.error("scale (value per metre of deflection) needs a length scale",
                              "also give paper_width, grid or dpi", "scale",
                              ru=("scale (величина на метр отклонения) нужен масштаб длины",
                                  "укажите также paper_width, grid или dpi"))
        s = given["scale"]
        v = s.value * metres.value
        return Measured(v, u_b=abs(v) * math.hypot(s.u / s.value, metres.u / metres.value)), unit
    if metres is not None:
        return metres, "m"
    return Measured(1.0), "px"


LINE_KINDS_RU = {"time marks": "отметки времени", "TDC marks": "отметки ВМТ",
                 "beside marks": "вдоль отметок", "grid": "сетка", "edge": "край ленты",
                 "faint": "бледная", "short": "короткая", "skewed": "косая",
                 "zero line": "нулевая линия"}
"""The kinds of :func:`judge_lines` in Russian."""


def describe_lines(judged: list[tuple[Line, str]], rows: float,
                   metres: Measured | None, taken: Line | None = None,
                   lang: str = "en") -> str:
    """The straight lines found, for messages in ``lang``: where each lies (mm below the
    sheet's top, or px) and what it was taken for."""
    ru = lang == "ru"

    def at(line):
        if metres is not None:
            return f"{line.position * metres.value * 1e3:.1f} {'мм' if ru else 'mm'}"
        return (f"строка {line.position:.0f} из {rows:.0f}" if ru
                else f"row {line.position:.0f} of {rows:.0f}")

    def told(kind, line):
        name = LINE_KINDS_RU[kind] if ru else kind
        return name + ((", взята" if ru else ", taken") if line is taken else "")

    grid = [line for line, kind in judged if kind == "grid"]
    parts = [f"{at(line)} ({told(kind, line)})" for line, kind in judged if kind != "grid"]
    if grid:
        parts.append(plural(len(grid), ("линия сетки", "линии сетки", "линий сетки"), "ru")
                     if ru else f"{len(grid)} grid lines")
    if not parts:
        return "прямых линий не найдено" if ru else "no straight line found"
    return (("найдены прямые линии (от верхнего края ленты): " if ru
             else "straight lines found (from the sheet's top): ") + "; ".join(parts))


def _record(where: _Where, found: Traces, j: int, seconds, value_scale: Measured, unit: str,
            zero: str, zero_lines: list[Line], lines: list[Line], pips: dict,
            bridge: float, sheet: Sheet, overlay_marks: dict, judged: list,
            metres: Measured | None) -> PaperRecord:
    tb, per_px = seconds
    row = found.row[j]
    first, last = _ends(row, found.confidence[j], float(found.width[j]))
    cols = np.arange(first, last + 1, dtype=float)
    row, u_row, conf = row[first:last + 1], found.u[j, first:last + 1], \
        found.confidence[j, first:last + 1]
    row, u_row, conf = _along_lines(cols, row, u_row, conf, zero_lines, float(found.width[j]))
    name = f"trace {j}"
    ref = None
    if zero == "line":
        if not zero_lines:
            rows = sheet.grey.shape[0]
            raise where.error("zero = \"line\" but no zero line (a long straight line without "
                              "marks, parallel to the time base, inside the sheet, as dark as "
                              "a trace) is on the sheet; "
                              + describe_lines(judged, rows, metres),
                              "use zero = \"mean\", or photograph the record with its zero "
                              "line", "zero",
                              ru=("zero = \"line\", но нулевой линии (длинной прямой без "
                                  "отметок, параллельной оси времени, внутри ленты, тёмной как "
                                  "запись) на ленте нет; "
                                  + describe_lines(judged, rows, metres, lang="ru"),
                                  "укажите zero = \"mean\" или сфотографируйте запись вместе "
                                  "с её нулевой линией"))
        middle = np.nanmedian(row)
        ref = min(zero_lines, key=lambda line: abs(line.at(cols.mean()) - middle))
        pixels = ref.at(cols) - row
    else:
        tilt = float(np.median([line.slope for line in lines])) if lines else 0.0
        pixels = -(row - tilt * (cols - cols.mean()))
        pixels -= np.nanmean(pixels)
    clock = (lambda x: tb.time(x)) if tb is not None else (lambda x: np.asarray(x) * per_px.value)
    t_cols = clock(cols) - clock(first)
    time = np.arange(cols.size) * (t_cols[-1] / (cols.size - 1))
    pixels, u_row, conf = _resample(t_cols, time, pixels, u_row, conf)
    value = pixels * value_scale.value
    u_value = u_row * abs(value_scale.value)
    # a gap no longer than the stroke's own smear (where the trace crosses a line or a
    # mark, its run merged with theirs) is crossed as a gap asked for is
    short = SHORT_GAP * float(found.width[j]) * (time[1] - time[0])
    value, bridged = _bridge(time, value, max(bridge, short))
    marks = {k: clock(p.rising) - clock(first) for k, p in pips.items()}
    if tb is not None:               # the time marks where the fit puts them: t = T_mark·k
        marks["time"] = tb.period * tb.numbers - clock(first)
    marks_u = {k: p.edge_u * per_px.value for k, p in pips.items()}
    overlay = Overlay.of(sheet.grey, found.row, found.confidence, j, overlay_marks,
                         [line.position for line in zero_lines],
                         taken=None if ref is None else ref.position)
    record = PaperRecord(where.path, name, where.field, time, value, conf, u_value, unit,
                         marks, marks_u, per_px, value_scale, tb, bridged,
                         float(found.width[j]), float(found.spread[j]), overlay, sheet.turns,
                         *(describe_lines(judged, sheet.grey.shape[0], metres, ref, lang)
                           for lang in ("en", "ru")))
    _warn(record, tb, {k: p.edge_u for k, p in pips.items()})
    return record


SHORT_GAP = 2.0
"""Gaps up to this many stroke widths long are interpolated across whatever ``bridge`` asks
(and counted in the low-confidence warning): within them the trace can hardly turn."""


END_FRAGMENT = 3.0
"""A piece of a trace at either end of it, cut off from the rest by a gap and shorter than
this many stroke widths, is no part of the record (:func:`_ends`)."""


def _ends(row: np.ndarray, confidence: np.ndarray, stroke: float) -> tuple[int, int]:
    """The first and last columns of a trace's record: those read with confidence, less a
    piece at either end shorter than :data:`END_FRAGMENT` stroke widths and cut off from
    the rest by a gap (the follower's step into what bounds the trace: the sheet's edge, a
    lid's shadow across it)."""
    valid = np.flatnonzero(np.isfinite(row) & (confidence >= LOW_CONFIDENCE))
    if valid.size < 2:
        valid = np.flatnonzero(np.isfinite(row))
    breaks = np.flatnonzero(np.diff(valid) > 1)
    pieces = np.split(valid, breaks + 1)
    if len(pieces) > 1 and pieces[0].size < END_FRAGMENT * stroke:
        pieces = pieces[1:]
    if len(pieces) > 1 and pieces[-1].size < END_FRAGMENT * stroke:
        pieces = pieces[:-1]
    return int(pieces[0][0]), int(pieces[-1][-1])


def _along_lines(cols: np.ndarray, row: np.ndarray, u_row: np.ndarray, conf: np.ndarray,
                 lines: list[Line], stroke: float):
    """The trace across its gaps along a zero line: where a beam runs on its zero line (a
    decay settling, a torsiogram's slow part), the two strokes merge and the trace is lost
    with the line lifted off; it lies within the line's stroke there. A gap both of whose
    ends lie within half the line's width and the trace's whole width of a zero line (the
    trace touching the line, its centroid pulled by the merge) is filled by a straight line
    between its ends, known within that reach (rectangular), and read with
    confidence :data:`~.traces.LOW_CONFIDENCE` (not counted as unreliable: the stroke
    bounds it)."""
    lost = ~np.isfinite(row)
    if not lost.any() or not lines:
        return row, u_row, conf
    row, u_row, conf = row.copy(), u_row.copy(), conf.copy()
    edges = np.flatnonzero(np.diff(np.concatenate([[0], lost.astype(np.int8), [0]])))
    for a, b in zip(edges[::2], edges[1::2]):
        if a == 0 or b == row.size:
            continue
        for line in lines:
            reach = line.width / 2 + stroke
            ends = np.array([a - 1, b])
            if np.all(np.abs(row[ends] - line.at(cols[ends])) <= reach):
                row[a:b] = np.interp(cols[a:b], cols[ends], row[ends])
                u_row[a:b] = reach / np.sqrt(3)
                conf[a:b] = LOW_CONFIDENCE
                break
    return row, u_row, conf


def _resample(t_cols, time, *arrays):
    """Arrays given at the columns' times onto the uniform grid ``time`` (linear between
    columns; NaN beside a gap, the lower confidence of the two)."""
    if np.allclose(t_cols, time, rtol=0, atol=1e-9 * max(time[-1], 1e-12)):
        return arrays
    pos = np.interp(time, t_cols, np.arange(t_cols.size, dtype=float))
    i = np.clip(np.floor(pos).astype(int), 0, t_cols.size - 2)
    f = pos - i
    out = [a[i] * (1 - f) + a[i + 1] * f for a in arrays[:-1]]
    out.append(np.minimum(arrays[-1][i], arrays[-1][i + 1]))
    return out


def _bridge(time: np.ndarray, value: np.ndarray, longest: float):
    """Gaps up to ``longest`` [s] filled by a monotone cubic through the samples read."""
    lost = ~np.isfinite(value)
    if not lost.any():
        return value, np.zeros(value.size, bool)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], lost.astype(np.int8), [0]])))
    fill = np.zeros(value.size, bool)
    step = time[1] - time[0]
    for a, b in zip(edges[::2], edges[1::2]):
        if (b - a) * step <= longest:
            fill[a:b] = True
    if fill.any():
        ok = ~lost
        value = value.copy()
        value[fill] = PchipInterpolator(time[ok], value[ok])(time[fill])
    return value, fill


def _warn(record: PaperRecord, tb: TimeBase | None, edge_u: dict) -> None:
    share = record.low_confidence_share
    bridged = int(record.bridged.sum())
    if share > LOW_SHARE or bridged:
        gaps = record.gaps()
        detail = (f"; {len(gaps)} stretch(es) not read" if gaps else "") + \
                 (f", {bridged} samples interpolated" if bridged else "")
        detail_ru = (f"; не считано участков: {len(gaps)}" if gaps else "") + \
                    (f", интерполировано отсчётов: {bridged}" if bridged else "")
        warnings.warn(LowConfidenceTraceWarning(
            f"{Path(record.path).name}, {record.name}: {_share(share)} of the samples were "
            f"read with low confidence{detail}; values there may be wrong (red on the "
            "overlay): retake the photograph flat, sharp and evenly lit, or check the result "
            "against a ruler reading",
            f"{Path(record.path).name}, {record.name.replace('trace', 'линия')}: "
            f"{_share(share)} отсчётов считано с низкой достоверностью{detail_ru}; значения "
            "там могут быть неверны (красные на наложении): переснимите запись ровно, резко "
            "и при равномерном освещении или проверьте результат по линейке"))
    blurred = [k for k, u in edge_u.items() if u > BLURRED_MARKS]
    if blurred:
        kinds = {"time": ("time", "времени"), "tdc": ("TDC", "ВМТ")}
        en = " and ".join(kinds[k][0] for k in blurred)
        ru = " и ".join(kinds[k][1] for k in blurred)
        ms = max(record.marks_u[k] for k in blurred) * 1e3
        warnings.warn(BlurredMarksWarning(
            f"{Path(record.path).name}: the {en} marks are blurred into blobs, so where each "
            f"rises is uncertain by ± {ms:.2g} ms: phases measured from them against the "
            "trace carry that error (the time scale itself does not): retake the photograph "
            "sharper",
            f"{Path(record.path).name}: отметки {ru} размыты, начало каждой известно лишь с "
            f"точностью ± {ms:.2g} мс: фазы, отсчитанные от них по линии записи, имеют ту же "
            "погрешность (масштаб времени — нет): переснимите запись резче"))
    if tb is not None and abs(tb.speed_change) > UNEVEN_SPEED:
        warnings.warn(UnevenTimeBaseWarning(
            f"{Path(record.path).name}: the time marks' spacing changes by "
            f"{100 * tb.speed_change:+.1f} % along the record (the paper's speed changed, or "
            "the photograph's perspective is not fully corrected); the time base follows "
            "the marks, but check that the photograph was taken square to the sheet",
            f"{Path(record.path).name}: шаг отметок времени меняется на "
            f"{100 * tb.speed_change:+.1f} % вдоль записи (менялась скорость ленты или не "
            "полностью устранена перспектива снимка); шкала времени следует отметкам, но "
            "проверьте, что снимок сделан перпендикулярно ленте"))


def _share(x: float) -> str:
    return f"{100 * x:.1f} %"
