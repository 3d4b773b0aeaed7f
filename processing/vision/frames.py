"""A film's frames in grey with each frame's presentation time, read with PyAV (FFmpeg).

A phone films at a variable frame rate and writes each frame's presentation timestamp into
the container (MP4, MOV, Matroska); a frame it could not take in time is simply missing,
its neighbours two intervals apart. :func:`open_film` checks the file and its stream's
header (the frame size, before a frame is decoded), :func:`frames` yields each frame's
luma, reduced to the size it is tracked at, with its time, and :func:`frame_clock` says what
the times are worth: dropped frames (:class:`~processing.diagnostics.DroppedFramesWarning`)
and a container that holds only a nominal rate (AVI: the frames are taken 1/rate apart,
:class:`~processing.diagnostics.NominalFrameRateWarning`).

PyAV is what reads them: OpenCV's reader hides whether a frame's time came from the
container or was made up from the nominal rate, and does not say which frames a decoder
left out.
"""
from __future__ import annotations

import math
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from ..diagnostics import (DroppedFramesWarning, InputError, IrregularFrameRateWarning,
                           NominalFrameRateWarning)
from ..files import FILM, regular

MAX_FRAME_PIXELS = 4096 * 2304
"""Largest frame read, by the film's stream header (before a frame is decoded). [px] Phones
film 1080p (2.1 Mpx) or 4K (3840 × 2160, 8.3 Mpx; DCI 4096 × 2160) by default; the limit
holds both with room for a 16:9 4096 px frame, and keeps a decoded frame, its decoder's
buffers and the background's frames within bounded memory."""

WORK_SIDE = 1920
"""Longest side of the frames tracked: a larger film is tracked on each frame reduced to it
(pixel areas averaged). [px] A 4K film so tracked is a 1080p one: the marker swings over ~1000
px of it where the film bench's 640 × 480 films (the targets: the period to 0.02 %, the
amplitude to 0.2°) swing it over a few hundred, and the marker's template stays within the
11–81 px the tracker sizes it to."""

IRREGULAR = 0.02
"""Relative spread of the frame intervals (dropped frames aside) above which the timestamps
are called irregular."""

DROPPED = 1.5
"""A frame interval this many times the median one or longer holds dropped frames (one
dropped frame leaves a gap of two intervals; a phone's variable rate varies its intervals by
up to a fifth or so)."""

LUMA_FIRST = frozenset({"yuv420p", "yuvj420p", "yuv422p", "yuvj422p", "yuv444p", "yuvj444p",
                        "nv12", "nv21", "gray"})
"""Pixel formats of 8 bits whose first plane is the luma: read as it is decoded."""


@dataclass(frozen=True)
class Film:
    """An opened film: the file, its frame size, the nominal rate and the scale tracked at.

    Attributes
    ----------
    path : Path
    size : (int, int)
        Width and height of the film's frames. [px]
    rate : float
        The stream's nominal (average) frames per second. [1/s]
    scale : float
        Frames tracked per film pixel (1, or less for a film larger than :data:`WORK_SIDE`).
    timed : bool
        Whether the container holds each frame's time (False: AVI, a nominal rate only).
    frame_count : int
        Frames the stream's header announces (0 where it does not say).
    tick : float
        The container's unit of time: each timestamp is rounded to it. [s]
    """

    path: Path
    size: tuple[int, int]
    rate: float
    scale: float
    timed: bool
    frame_count: int
    tick: float = 0.0


def _refuse(path, field_name, problem: str, fix: str, ru: tuple[str, str]) -> InputError:
    return InputError(problem, fix, file=str(path), field=field_name, ru=ru)


RECORDED_RU = "дайте файл MP4, MOV или AVI в том виде, как его записал телефон"
"""The fix of a file that is not a film, in Russian."""


def _is_film(head: bytes) -> bool:
    """Whether a file's first bytes are those of a film container: an ISO base media file
    (MP4, MOV, 3GP: a box such as ``ftyp`` or ``moov`` first), AVI (RIFF) or Matroska/WebM
    (EBML). Anything else — a playlist or a text that names other files or addresses for the
    decoder to open — is not read.

    >>> _is_film(bytes.fromhex("0000001c") + b"ftypisom"), _is_film(b"#EXTM3U http://")
    (True, False)
    """
    return (head[4:8] in (b"ftyp", b"moov", b"mdat", b"wide", b"free", b"skip")
            or (head[:4] == b"RIFF" and head[8:12] == b"AVI ")
            or head[:4] == b"\x1a\x45\xdf\xa3")


def _container(path, field_name):
    import av

    try:
        box = av.open(str(Path(path).resolve()), "r")
    except (av.FFmpegError, UnicodeDecodeError, ValueError):
        raise _refuse(path, field_name, "not a film FFmpeg can read", "give an MP4, MOV or "
                      "AVI file as the phone recorded it",
                      ("это не видео, которое может прочитать FFmpeg", RECORDED_RU)) from None
    if not box.streams.video:
        box.close()
        raise _refuse(path, field_name, "not a film: the file holds no video stream",
                      "give the film as the phone recorded it (MP4 or MOV)",
                      ("это не видео: в файле нет видеопотока", "дайте видео в том виде, как "
                       "его записал телефон (MP4 или MOV)"))
    return box, box.streams.video[0]


def open_film(path, field_name: str | None = None) -> Film:
    """Check a film and read its stream's header.

    Raises
    ------
    InputError
        Not a film container; no video stream; frames larger than :data:`MAX_FRAME_PIXELS`.
    """
    regular(path, FILM, field=field_name)
    with open(path, "rb") as f:
        head = f.read(12)
    if not _is_film(head):
        raise _refuse(path, field_name, "not a film: its first bytes are not those of an MP4, "
                      "MOV, AVI or MKV file", "give the film as the phone recorded it (MP4 or "
                      "MOV)", ("это не видео: первые байты файла не такие, как у MP4, MOV, AVI "
                               "или MKV", "дайте видео в том виде, как его записал телефон "
                               "(MP4 или MOV)"))
    box, stream = _container(path, field_name)
    try:
        w, h = int(stream.codec_context.width), int(stream.codec_context.height)
        rate = stream.average_rate or stream.guessed_rate or stream.base_rate
        timed = "avi" not in box.format.name.split(",")
        count = int(stream.frames or 0)
        tick = float(stream.time_base) if stream.time_base else 0.0
    finally:
        box.close()
    if w * h > MAX_FRAME_PIXELS:
        raise _refuse(path, field_name, f"its video stream's header says {w} × {h} px a frame "
                      f"({w * h / 1e6:.3g} Mpx), more than the {MAX_FRAME_PIXELS / 1e6:.3g} "
                      "Mpx of a 4K frame a film is read at", "film at 1080p or 4K (the "
                      "phone's camera settings), or export the film at that size",
                      (f"по заголовку видеопотока кадр {w} × {h} пикс ({w * h / 1e6:.3g} Мпикс), "
                       f"больше {MAX_FRAME_PIXELS / 1e6:.3g} Мпикс кадра 4K, в котором "
                       "читается видео", "снимайте в 1080p или 4K (настройки камеры телефона) "
                       "или сохраните видео в этом размере"))
    if w * h == 0:
        raise _refuse(path, field_name, "not a film FFmpeg can read: its video stream has no "
                      "frame size", "give an MP4, MOV or AVI file as the phone recorded it",
                      ("это не видео, которое может прочитать FFmpeg: у видеопотока нет "
                       "размера кадра", RECORDED_RU))
    return Film(Path(path), (w, h), float(rate) if rate else math.nan,
                min(1.0, WORK_SIDE / max(w, h)), timed, count, tick)


def _luma(frame) -> np.ndarray:
    """A decoded frame's grey image (its luma plane where it has one of 8 bits)."""
    if frame.format.name in LUMA_FIRST:
        plane = frame.planes[0]
        return np.frombuffer(plane, np.uint8).reshape(plane.height, plane.line_size)[
            :, :plane.width]
    return frame.to_ndarray(format="gray")


def reduce(grey: np.ndarray, scale: float) -> np.ndarray:
    """``grey`` reduced to ``scale`` of its size (pixel areas averaged), or as it is."""
    if scale >= 1:
        return grey
    size = (max(int(round(grey.shape[1] * scale)), 1), max(int(round(grey.shape[0] * scale)), 1))
    return cv2.resize(grey, size, interpolation=cv2.INTER_AREA)


def frames(film: Film, field_name: str | None = None, *,
           colour: bool = False) -> Iterator[tuple]:
    """Each frame in presentation order: its grey image at :attr:`Film.scale` and its time
    (NaN where the frame carries none) [s]; with ``colour``, its BGR image at that scale
    too (a third item).

    Raises
    ------
    InputError
        The stream cannot be decoded from its start.
    """
    import av

    box, stream = _container(film.path, field_name)
    stream.thread_type = "AUTO"
    decoded = 0
    try:
        for frame in box.decode(stream):
            decoded += 1
            t = float(frame.time) if frame.pts is not None and film.timed else math.nan
            grey = np.ascontiguousarray(reduce(_luma(frame), film.scale))
            if colour:
                yield grey, t, reduce(frame.to_ndarray(format="bgr24"), film.scale)
            else:
                yield grey, t
    except av.FFmpegError as exc:
        if not decoded:
            raise _refuse(film.path, field_name, f"not a film FFmpeg can decode ({exc})",
                          "give an MP4, MOV or AVI file as the phone recorded it",
                          ("это не видео, которое может декодировать FFmpeg (его сообщение: "
                           f"'{exc}')", RECORDED_RU)) from None
        # a film cut short (a truncated file): the frames decoded are kept
    finally:
        box.close()


def typical_interval(times: np.ndarray) -> float:
    """The frames' usual interval: the median of the intervals averaged over four frames (a
    container's rounding of each time to its tick, 2 and 3 ticks in turn at 240 frames per
    second on a 1/600 s clock, averages out). [s]"""
    times = np.asarray(times, float)
    if times.size > 8:
        return float(np.median((times[4:] - times[:-4]) / 4))
    return float(np.median(np.diff(times)))


def interval_spread(steps: np.ndarray, typical: float, tick: float = 0.0) -> float:
    """Relative spread of the frame intervals beyond the container's rounding: their
    variance less the most that rounding each time to ``tick`` gives them (intervals one
    tick apart in turn: tick²/4), its root over the usual interval."""
    if steps.size < 2:
        return 0.0
    excess = float(np.var(steps)) - tick * tick / 4
    return math.sqrt(max(excess, 0.0)) / typical


def frame_clock(film: Film, times, field_name: str | None = None) -> tuple[np.ndarray, int]:
    """The frames' times as they are used, and the frames dropped; warns of what they are
    worth.

    Where the container holds the frames' times, they are used as they are; a gap of
    :data:`DROPPED` usual intervals (:func:`typical_interval`) or longer is a frame dropped (warned:
    :class:`DroppedFramesWarning`); intervals that vary beyond :data:`IRREGULAR` besides are
    a variable frame rate (:class:`IrregularFrameRateWarning`; the container's rounding
    aside, :func:`interval_spread`). Where it does not (AVI, or
    frames without a timestamp), the frames are taken 1/rate apart
    (:class:`NominalFrameRateWarning`).

    Returns
    -------
    times : numpy.ndarray
        [s]
    dropped : int
        Frames missing from the gaps.

    Raises
    ------
    InputError
        Times that do not rise.
    """
    times = np.asarray(times, dtype=float)
    name = film.path.name
    if not np.all(np.isfinite(times)):
        rate = film.rate if math.isfinite(film.rate) and film.rate > 0 else 30.0
        warnings.warn(NominalFrameRateWarning(
            f"{name}: the film holds no time for its frames ({'an AVI file' if not film.timed else 'frames without a timestamp'}): they are taken 1/{rate:.4g} s apart "
            "at its nominal rate, so a variable frame rate or a dropped frame would shift "
            "the period unseen; give the film as the phone recorded it (MP4 or MOV)",
            f"{name}: в файле нет времени кадров ({'файл AVI' if not film.timed else 'кадры без меток времени'}): кадры считаются через "
            f"1/{rate:.4g} с по номинальной частоте, поэтому переменная частота кадров или "
            "пропущенный кадр незаметно сдвинули бы период; дайте видео в том виде, как его "
            "записал телефон (MP4 или MOV)"))
        return np.arange(times.size) / rate, 0
    steps = np.diff(times)
    if not np.all(steps > 0):
        raise _refuse(film.path, field_name, "the frames' timestamps do not rise",
                      "export the film again from the phone without editing it",
                      ("метки времени кадров не возрастают", "заново сохраните видео с "
                       "телефона, не редактируя его"))
    if steps.size == 0:
        return times, 0
    typical = typical_interval(times)
    gaps = steps >= DROPPED * typical
    dropped = int(np.sum(np.maximum(np.round(steps[gaps] / typical) - 1, 1)))
    if dropped:
        worst = float(steps[gaps].max())
        warnings.warn(DroppedFramesWarning(
            f"{name}: {dropped} frame(s) dropped by the camera (gaps of up to "
            f"{1e3 * worst:.0f} ms against {1e3 * typical:.1f} ms between frames): each frame's "
            "own time is used, so the period holds, but the swing is followed less closely "
            "there; close other apps and film at a rate the phone keeps up with",
            f"{name}: камера пропустила кадров: {dropped} (промежутки до {1e3 * worst:.0f} мс "
            f"при {1e3 * typical:.1f} мс между кадрами): используется время каждого кадра, "
            "поэтому период верен, но там колебание прослежено хуже; закройте другие "
            "приложения и снимайте с частотой, которую телефон выдерживает"))
    spread = interval_spread(steps[~gaps], typical, film.tick)
    if spread > IRREGULAR:
        warnings.warn(IrregularFrameRateWarning(
            f"{name}: the frames' intervals vary by {100 * spread:.1f} % (a variable frame "
            "rate): each frame's own timestamp is used; film at a fixed frame rate if the "
            "phone allows",
            f"{name}: интервалы между кадрами меняются на {100 * spread:.1f} % (переменная "
            "частота кадров): используется метка времени каждого кадра; снимайте с "
            "постоянной частотой кадров, если телефон позволяет"))
    return times, dropped
