"""Sampled sensor recordings: one channel of a CSV table, a WAV file or an HDF5 file.

:func:`open_channel` reads a recording's metadata (name, sample rate, length, stored dtype)
and returns a :class:`Channel`, which reads its samples on demand, whole (:meth:`Channel.read`)
or block by block (:meth:`Channel.chunks`) with bounded memory: an HDF5 dataset is sliced
(h5py reads only the slice) and a WAV file is read from disk block by block, so a channel
of 10⁹ samples streams through one block of memory. A CSV table is small by nature and is
parsed whole. Inside :func:`kept_open` an HDF5 file is opened once for all its channels.
:func:`read_edge_times` reads ready edge timestamps from a counter. The writers
(:func:`write_wav`, :func:`write_hdf5`, :func:`write_csv`) produce files these readers accept;
:func:`write_hdf5` also streams, from an iterable of blocks.

Formats
-------
CSV / TXT (``.csv``, ``.txt``, ``.tsv``, ``.dat``)
    Comma, semicolon, tab or whitespace separated; a header row is optional; ``#`` starts a
    comment; with semicolons or tabs a decimal comma is accepted. A first column named
    ``t``, ``time`` or ``время``, optionally with a unit (``time_s``, ``t, ms``, ``t [us]``),
    is the time base: it must rise uniformly, and the sample rate follows from it. A channel
    is in volts, or in the unit its name ends with (``U, mV``, ``u_мВ``, ``ch1 [µV]``). A
    header naming more columns than the rows hold (``t, ms,U, mV``: a comma inside a name
    unquoted) is refused. Rows are counted as a spreadsheet shows them (the header is row 1).
CSV exported by an oscilloscope or acquisition program; LabVIEW Measurement (``.lvm``)
    Rigol DS1000Z and DS1000E, Tektronix TDS/TBS1000 and MSO/MDO, Siglent SDS, Keysight
    InfiniiVision, PicoScope 6/7, LabVIEW's Write To Measurement File (one segment):
    recognised by their header rows, not the file's name
    (:mod:`processing.inputs.scope_exports` lists the layouts). The channels keep the
    instrument's names (``CH1``, ``Channel A``) and are also chosen by index; the header's
    time base (Start and Increment, Sample Interval) or the time column with its unit row
    gives the rate; times go to seconds and values to volts; the header's settings never
    become data. A header the rows contradict (Record Length, a time column off the stated
    interval, a skipped sample index, a cut last row, no rows at all) is refused naming the
    setting and its row. An over-range mark (PicoScope's ``∞``, ``-∞``; SCPI's ±9.9E+37) is
    read as the channel's highest (lowest) reading, where a recorder's rail holds a clipped
    sample, so that :func:`~processing.inputs.record_quality.clipped_mask` and
    ``check_record`` count it as clipped.
WAV (``.wav``)
    A sound-card recording: uint8, int16, 24-bit, int32, float32 or float64 samples; the
    channel is its 0-based index or ``"left"`` / ``"right"``. The rate is the file's.
HDF5 (``.h5``, ``.hdf5``)
    One 1-D dataset per channel, named by its path in the file. The sample rate is the
    attribute ``sample_rate`` (or ``fs``) [Hz] of the dataset, else of the file; the
    attribute ``volts_per_code`` scales stored codes to volts.
Image (``.png``, ``.jpg``, ``.jpeg``, ``.tif``, ``.tiff``, ``.bmp``)
    A photograph or scan of a paper record, read by :mod:`processing.vision` into a
    :class:`~processing.vision.record.PaperRecord` (the same interface as a channel, with the
    overlay of what was read, :func:`read_figures`); the channel is the trace's index from the
    top of the sheet, and ``image`` gives the reader's options (the ``[image]`` table of a
    measurement file, :func:`processing.measurement.image_section`).

Every problem with a file raises :class:`~processing.diagnostics.InputError` naming the file,
the measurement-file field that pointed to it (``field=``) and the fix.
"""
from __future__ import annotations

import contextlib
import csv
import dataclasses
import difflib
import functools
import hashlib
import itertools
import math
import operator
import re
import struct
import warnings
from collections.abc import Callable, Iterable, Iterator
from contextlib import AbstractContextManager
from contextvars import ContextVar
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
from scipy.io import wavfile

from processing.diagnostics import InputError
from processing.files import IMAGE, STREAMED, TABLE, read_text, regular
from processing.inputs.reuse import by_content
from processing.inputs.scope_exports import (OVER, PREAMBLE_MOST, TIME_UNITS, VOLT_UNITS,
                                             Layout, recognise, scpi_marks)

CHUNK = 2**22
"""Default block length of :meth:`Channel.chunks` [samples]: 32 MB of float64."""

HDF5_CHUNK = 2**18
"""Storage chunk of the datasets :func:`write_hdf5` streams [samples]."""

HDF5_MAX_CHUNK = 64 << 20
"""Largest storage chunk of a dataset read [bytes]: HDF5 decompresses a chunk whole, so a
chunk of gigabytes compressed to a few bytes would fill the memory for one sample."""

RATE_TOLERANCE = 1e-3
"""Relative disagreement allowed between a given sample rate and the file's, and the allowed
relative deviation of a CSV time step from the usual (median) step."""

_FORMATS = {".csv": "csv", ".txt": "csv", ".tsv": "csv", ".dat": "csv", ".lvm": "csv",
            ".wav": "wav", ".h5": "hdf5", ".hdf5": "hdf5"}
_FORMAT_HINTS = {"csv": ".csv or .txt (a table of numbers)", "wav": ".wav (a sound-card recording)",
                 "hdf5": ".h5 or .hdf5", "image": ".png, .jpg or .tif (a photograph or scan of "
                 "a paper record)"}
_FORMAT_HINTS_RU = {"csv": ".csv или .txt (таблица чисел)", "wav": ".wav (запись звуковой карты)",
                    "hdf5": ".h5 или .hdf5", "image": ".png, .jpg или .tif (снимок или скан "
                    "бумажной записи)"}
_IMAGES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")
_FORMATS.update(dict.fromkeys(_IMAGES, "image"))
_FILE_KINDS = {"csv": TABLE, "image": IMAGE}
"""The formats read whole, and their size limits; the others stream (:data:`STREAMED`)."""
_TIME_NAME = re.compile(r"(?:t|time|время)(?:\s*[,_\[(/]\s*(" + "|".join(TIME_UNITS)
                        + r")\s*[\])]?)?")
_VOLT_NAME = re.compile(r".*?\S\s*[,_\[(/]\s*(" + "|".join(VOLT_UNITS) + r")\s*[\])]?")
_WAV_SIDES = {"left": 0, "right": 1}

_Reader = Callable[[int, int], np.ndarray]
"""``read(a, b)``: samples ``a`` to ``b - 1`` of a channel, a fresh array in the stored dtype."""


@dataclasses.dataclass(frozen=True)
class Channel:
    """One sampled channel of a recording; reads its samples on demand.

    Made by :func:`open_channel` / :func:`open_channels`, which check the file first.

    Parameters
    ----------
    path : str
        The recording file.
    name : str
        Column header (CSV), ``"channel k"`` (WAV) or dataset path (HDF5).
    sample_rate : float
        Sampling frequency. [Hz]
    length : int
        Number of samples, ≥ 1.
    dtype : numpy.dtype
        The samples' type as stored (int16 codes of a WAV or an ADC, float32, float64, ...).
    volts_per_code : float
        Scale from stored codes to physical units [V], from the HDF5 attribute
        ``volts_per_code``; 1.0 when the file does not say.
    field : str, optional
        The measurement-file field that named the recording, for error messages.
    """

    path: str
    name: str
    sample_rate: float
    length: int
    dtype: np.dtype
    volts_per_code: float = 1.0
    field: str | None = None
    _opener: Callable[[], AbstractContextManager[_Reader]] = dataclasses.field(
        repr=False, compare=False, kw_only=True)

    @property
    def duration(self) -> float:
        """Recording length, ``length / sample_rate``. [s]"""
        return self.length / self.sample_rate

    def chunks(self, size: int = CHUNK, start: int = 0,
               stop: int | None = None) -> Iterator[np.ndarray]:
        """Consecutive blocks of samples, in the stored dtype (not converted, for speed).

        Parameters
        ----------
        size : int
            Block length [samples]; the last block is shorter.
        start, stop : int
            First sample and one past the last (default: the whole channel), 0-based.

        Yields
        ------
        numpy.ndarray
            A fresh 1-D array of at most ``size`` samples; blocks concatenate to the samples
            ``start`` to ``stop - 1``.

        Raises
        ------
        InputError
            A NaN or infinite sample in float data, naming its index.
        ValueError
            ``size`` < 1 or not ``0 ≤ start ≤ stop ≤ length``.
        """
        size, start = operator.index(size), operator.index(start)
        stop = self.length if stop is None else operator.index(stop)
        if size < 1:
            raise ValueError(f"chunks: size must be ≥ 1 sample, got {size}")
        if not 0 <= start <= stop <= self.length:
            raise ValueError(f"chunks: need 0 ≤ start ≤ stop ≤ {self.length}, "
                             f"got start={start}, stop={stop}")
        return self._blocks(size, start, stop)

    def read(self) -> np.ndarray:
        """The whole channel as one array in the stored dtype (checked as :meth:`chunks`)."""
        (samples,) = self.chunks(self.length)
        return samples

    def _blocks(self, size: int, start: int, stop: int) -> Iterator[np.ndarray]:
        with self._opener() as read:
            for a in range(start, stop, size):
                b = min(a + size, stop)
                try:
                    block = read(a, b)
                except (OSError, ValueError) as exc:
                    raise InputError(f"channel '{self.name}' cannot be read at samples {a}–"
                                     f"{b - 1}: the file is damaged or cut short ({exc})",
                                     "copy the recording again from the recorder, or export "
                                     "it anew", file=self.path, field=self.field,
                                     ru=(f"канал '{self.name}' не читается в отсчётах {a}–"
                                         f"{b - 1}: файл повреждён или обрезан",
                                         "скопируйте запись с регистратора заново или "
                                         "экспортируйте её снова")) from None
                if len(block) != b - a:
                    raise InputError(f"channel '{self.name}' ends at sample {a + len(block)}, "
                                     f"before the {self.length} samples its header announces: "
                                     "the file is cut short", "copy the recording again whole",
                                     file=self.path, field=self.field,
                                     ru=(f"канал '{self.name}' кончается на отсчёте "
                                         f"{a + len(block)}, раньше {self.length} отсчётов, "
                                         "объявленных в заголовке: файл обрезан",
                                         "скопируйте запись заново целиком"))
                self._check_finite(block, a)
                yield block

    def _check_finite(self, block: np.ndarray, offset: int) -> None:
        if block.dtype.kind != "f":
            return
        finite = np.isfinite(block)
        if finite.all():
            return
        k = int(np.argmin(finite))
        i = offset + k
        raise InputError(f"channel '{self.name}': sample {i} (t = {i / self.sample_rate:.6g} s) "
                         f"is {float(block[k])}",
                         "the recorder writes NaN/inf for lost or overranged samples: check the "
                         "sensor's range and record again, or reduce a stretch without them",
                         file=self.path, field=self.field,
                         ru=(f"канал '{self.name}': отсчёт {i} (t = {i / self.sample_rate:.6g} с) "
                             f"равен {float(block[k])}", "регистратор пишет NaN/inf вместо "
                             "потерянных или зашкаливших отсчётов: проверьте диапазон датчика "
                             "и запишите заново или обработайте участок без них"))


@dataclasses.dataclass(frozen=True)
class _Source:
    """The file being read and the field that named it: where errors point."""

    path: Path
    field: str | None

    def error(self, problem: str, fix: str, ru: tuple[str, str] | None = None) -> InputError:
        return InputError(problem, fix, file=str(self.path), field=self.field, ru=ru)

    def channel(self, name: str, rate: float, length: int, dtype, opener,
                volts_per_code: float = 1.0) -> Channel:
        return Channel(str(self.path), name, float(rate), int(length), np.dtype(dtype),
                       float(volts_per_code), self.field, _opener=opener)


def open_channel(path, *, channel: str | int | None = None, sample_rate: float | None = None,
                 field: str | None = None, image: dict | None = None) -> Channel:
    """Open one channel of a recording (CSV, WAV or HDF5) without reading its samples, or
    read one trace of a photographed paper record.

    Parameters
    ----------
    path : str or Path
        The recording; its extension tells the format (see the module's notes).
    channel : str or int, optional
        CSV: a column name or the 0-based index among the data columns (default: the first
        data column). WAV: 0-based index, ``"left"`` or ``"right"`` (default: 0). HDF5: the
        dataset path (default: the only 1-D dataset).
    sample_rate : float, optional
        Sampling frequency [Hz], for a file that does not state it (a CSV without a time
        column, an HDF5 dataset without the attribute). If the file states it too, the two
        must agree to 0.1 %.
    field : str, optional
        The measurement-file field that named the file (``"regime[0].signal"``), for errors.
    image : dict, optional
        For an image: the keyword options of
        :func:`processing.vision.read_paper_records` (``mark_period``, ``paper_width``, ...),
        as :func:`image_options` makes them from a measurement file's ``[image]`` table.

    Returns
    -------
    Channel
        Or, for an image, a :class:`~processing.vision.record.PaperRecord`.

    Raises
    ------
    InputError
        Missing, empty or unreadable file, unknown extension, unknown channel (with a
        did-you-mean), no or conflicting sample rate, non-numeric or missing values, a time
        column that is not uniform, a zero-length channel.

    Examples
    --------
    >>> import shutil, tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> write_hdf5(folder / "run.h5", {"tooth": np.arange(10, dtype=np.int16)}, 1e5)
    >>> ch = open_channel(folder / "run.h5")
    >>> ch.name, ch.sample_rate, ch.length, ch.duration
    ('tooth', 100000.0, 10, 0.0001)
    >>> [len(block) for block in ch.chunks(4)]
    [4, 4, 2]
    >>> shutil.rmtree(folder)
    """
    return open_channels(path, [channel], sample_rate=sample_rate, field=field, image=image)[0]


def open_channels(path, names: Iterable[str | int | None], *, sample_rate: float | None = None,
                  field: str | None = None, image: dict | None = None) -> list[Channel]:
    """Open several channels recorded together in one file (a tooth and a TDC channel).

    Parameters
    ----------
    path : str or Path
        The recording.
    names : iterable of str, int or None
        The channels, each chosen as ``channel`` of :func:`open_channel`; a text of digits
        (as a measurement file writes ``channel = "1"``) is an index.
    sample_rate : float, optional
        As in :func:`open_channel`. [Hz]
    field : str, optional
        The measurement-file field, for errors.
    image : dict, optional
        As in :func:`open_channel`.

    Returns
    -------
    list of Channel
        In the order of ``names``, all with the same sample rate and length (traces of one
        image share its time base).

    Raises
    ------
    InputError
        As :func:`open_channel`; also channels that differ in sample rate or length.
    """
    names = [int(n) if isinstance(n, str) and n.strip().isdigit() else n for n in names]
    if not names:
        raise ValueError("open_channels: names must name at least one channel")
    src = _Source(Path(path), field)
    kind = _file_format(src, ("csv", "wav", "hdf5", "image"))
    if kind == "image":
        return _image_channels(src, names, sample_rate, image or {})
    given = _given_rate(src, sample_rate)
    channels = {"csv": _csv_channels, "wav": _wav_channels, "hdf5": _hdf5_channels}[kind](
        src, names, given)
    _check_simultaneous(src, channels)
    return channels


DIGEST_SAMPLES = 4096
"""Samples of each channel :func:`sample_digest` takes (all of a shorter one): a recording's
noise tells it from any other within its first few, and a format that reads by blocks (WAV,
HDF5) reads no more."""


def sample_digest(path) -> str | None:
    """A digest of what a recording holds, not of how it is written: SHA-256 of each
    channel's length and first :data:`DIGEST_SAMPLES` samples (in volts, as read), the
    channels in any order under any name. The same recording saved again — in another format,
    with another separator, decimal comma, header, column names or order — has the same digest.

    Returns
    -------
    str or None
        None for a photograph, or a file that is not a readable CSV, WAV or HDF5 recording.

    Examples
    --------
    >>> import shutil, tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> x = np.random.default_rng(1).normal(size=1000)
    >>> write_csv(folder / "a.csv", {"acc": x, "tdc": -x}, 1e4)
    >>> write_hdf5(folder / "b.h5", {"second": -x, "first": x}, 1e4)
    >>> sample_digest(folder / "a.csv") == sample_digest(folder / "b.h5")
    True
    >>> write_csv(folder / "c.csv", {"acc": x + 1e-9, "tdc": -x}, 1e4)
    >>> sample_digest(folder / "a.csv") == sample_digest(folder / "c.csv")
    False
    >>> shutil.rmtree(folder)
    """
    src = _Source(Path(path), None)
    try:
        kind = _file_format(src, ("csv", "wav", "hdf5", "image"))
        if kind == "image":
            return None
        parts = sorted(hashlib.sha256(np.ascontiguousarray(x, dtype=float).tobytes()
                                      + str(n).encode()).hexdigest()
                       for x, n in _first_samples(src, kind))
    except (InputError, OSError, ValueError):
        return None
    return hashlib.sha256("".join(parts).encode()).hexdigest() if parts else None


def _first_samples(src: _Source, kind: str) -> Iterator[tuple[np.ndarray, int]]:
    """Each channel's first :data:`DIGEST_SAMPLES` samples in volts and its length."""
    if kind == "csv":
        table = _Table.read(src)
        time, _ = _time_base(src, table)
        for name in table.names:
            if name != time:
                values = table.numbers(name)
                yield values[:DIGEST_SAMPLES], len(values)
        return
    if kind == "wav":
        _, layout = _wav_layout(src)
        for c in _wav_channels(src, list(range(layout.count)), None):
            yield next(c.chunks(DIGEST_SAMPLES)) * c.volts_per_code, c.length
        return
    with h5py.File(src.path, "r") as f:
        for name, ds in _datasets(f).items():
            if ds.ndim == 1 and ds.dtype.kind in "biuf" and ds.shape[0]:
                volts = _attr(src, name, (ds, f), ("volts_per_code",))
                yield ds[:DIGEST_SAMPLES] * (1.0 if volts is None else volts), ds.shape[0]


def is_image(path) -> bool:
    """Whether ``path`` names a photograph or scan (by its extension)."""
    return Path(path).suffix.lower() in _IMAGES


def image_options(table: dict | None) -> dict:
    """The reader's keyword options from a measurement file's ``[image]`` table (validated by
    :func:`processing.measurement.image_section`: quantities as Measured in SI)."""
    options = {}
    for name, value in (table or {}).items():
        options[name] = value.value if name == "bridge" else value
    return options


def read_figures(channels: Iterable) -> list:
    """The overlay figure (:meth:`~processing.vision.record.PaperRecord.figure`) of every
    channel read off an image, so that the report shows what was read; none for recordings."""
    read = [c for c in channels if hasattr(c, "overlay")]
    return [c.figure(f"paper_record_{k}" if len(read) > 1 else "paper_record")
            for k, c in enumerate(read, 1)]


def _image_channels(src: _Source, names: list, sample_rate, options: dict) -> list:
    """The traces ``names`` (indices from the top; None: 0) of a photographed record."""
    from processing.vision import read_paper_records

    if sample_rate is not None:
        raise src.error("a sample rate is given for an image",
                        "leave sample_rate out: the time marks (mark_period in [image]) "
                        "or the paper speed set an image's time base")
    picked = []
    for name in names:
        if name is not None and not isinstance(name, int):
            raise src.error(f"channel {name!r} of an image", "give the trace's number, 0 for "
                            "the topmost trace on the sheet, 1 for the next")
        picked.append(0 if name is None else name)
    records = read_paper_records(src.path, field=src.field, **options)
    for k in picked:
        if not -len(records) <= k < len(records):
            raise src.error(f"trace {k} asked for, {len(records)} trace(s) found on the sheet",
                            f"choose channel = 0 … {len(records) - 1} (0 is the topmost), or "
                            "look at the photograph for the trace missed")
    return [records[k] for k in picked]


def read_edge_times(path, *, column: str | int | None = None,
                    field: str | None = None) -> np.ndarray:
    """Edge timestamps written by a counter (a CSV/TXT table), in seconds.

    Parameters
    ----------
    path : str or Path
        A ``.csv`` / ``.txt`` file: one column of times, or several with the times in a
        ``t`` / ``time`` first column or named by ``column``. Times are in seconds unless the
        header gives a unit (``t_ms``, ``t, us``).
    column : str or int, optional
        The column's name or 0-based index.
    field : str, optional
        The measurement-file field, for errors.

    Returns
    -------
    numpy.ndarray
        At least 3 finite, strictly increasing times, float64. [s]

    Raises
    ------
    InputError
        Missing, empty or unreadable file, unknown column, non-numeric or missing values,
        fewer than 3 times, times that do not rise (naming the first bad row).
    """
    src = _Source(Path(path), field)
    _file_format(src, ("csv",))
    table = _Table.read(src)
    name = _edge_column(src, table, column)
    scale = 1.0 if table.layout is not None else _time_scale(name) or 1.0  # an export's: s
    times = table.numbers(name).astype(np.float64) * scale
    if len(times) < 3:
        raise src.error(f"only {len(times)} edge time(s) in column '{name}': at least 3 are "
                        "needed", "record longer, or check that the counter wrote every edge")
    _check_rising(src, table, name, times)
    return times


def write_wav(path, channels: dict[str, np.ndarray] | np.ndarray, sample_rate: float) -> None:
    """Write int16 codes as a WAV file, one WAV channel per array.

    Parameters
    ----------
    path : str or Path
        The ``.wav`` file (overwritten).
    channels : dict of str to ndarray, or ndarray
        Integer codes within int16: a dict of equally long 1-D arrays (WAV keeps their order,
        not their names), a 1-D array (mono) or an array of shape ``(n, k)`` (k channels).
    sample_rate : float
        A whole number of samples per second. [Hz]

    Raises
    ------
    ValueError
        Non-integer codes or codes beyond int16, arrays of different lengths, a sample rate
        that is not a positive whole number.
    """
    if isinstance(channels, dict):
        if not channels:
            raise ValueError("write_wav: no channels given")
        codes = np.column_stack(list(channels.values())) if len(channels) > 1 else \
            np.asarray(next(iter(channels.values())))
    else:
        codes = np.asarray(channels)
    if codes.dtype.kind not in "iu" or codes.ndim not in (1, 2) or not codes.size:
        raise ValueError("write_wav: give integer codes, a 1-D array or one column per channel "
                         f"(got dtype {codes.dtype}, shape {codes.shape}); round a float signal "
                         "to int16 codes first")
    if codes.min() < -(2**15) or codes.max() >= 2**15:
        raise ValueError(f"write_wav: codes {codes.min()} … {codes.max()} exceed int16 "
                         "(−32768 … 32767); scale the signal down")
    if not (sample_rate > 0 and float(sample_rate).is_integer()):
        raise ValueError(f"write_wav: a WAV stores a whole number of samples per second, "
                         f"got {sample_rate!r}")
    wavfile.write(path, int(sample_rate), codes.astype(np.int16))


def write_hdf5(path, datasets: dict[str, np.ndarray | Iterable[np.ndarray]], sample_rate: float,
               *, volts_per_code: float = 1.0, length: int | None = None,
               attrs: dict | None = None) -> None:
    """Write channels as 1-D HDF5 datasets, streaming those given as blocks.

    Parameters
    ----------
    path : str or Path
        The ``.h5`` file (overwritten).
    datasets : dict of str to ndarray or iterable of ndarray
        Dataset path → the samples, as one 1-D array or as an iterable of 1-D blocks (written
        one by one to a chunked dataset, so memory holds one block at a time).
    sample_rate : float
        Stored as the attribute ``sample_rate`` of each dataset. [Hz]
    volts_per_code : float
        Stored as the attribute ``volts_per_code`` of each dataset. [V]
    length : int, optional
        The number of samples of each dataset, if known: blocks then fill a dataset of that
        size, and the total is checked.
    attrs : dict, optional
        Extra attributes of the file (the rig, the synthetic case's true values, ...).

    Raises
    ------
    ValueError
        A non-positive sample rate, a block that is not 1-D, no samples, or a total that is
        not ``length``.
    """
    if not (sample_rate > 0 and math.isfinite(sample_rate)):
        raise ValueError(f"write_hdf5: sample_rate must be > 0 Hz, got {sample_rate!r}")
    with h5py.File(path, "w") as f:
        f.attrs.update(attrs or {})
        for name, data in datasets.items():
            if isinstance(data, np.ndarray):
                ds = _write_array(f, name, data, length)
            else:
                ds = _write_blocks(f, name, data, length)
            ds.attrs["sample_rate"] = float(sample_rate)
            ds.attrs["volts_per_code"] = float(volts_per_code)


def write_csv(path, columns: dict[str, np.ndarray], sample_rate: float | None = None) -> None:
    """Write equally long columns as a comma-separated table with a header row.

    Parameters
    ----------
    path : str or Path
        The ``.csv`` file (overwritten).
    columns : dict of str to ndarray
        Header → 1-D values, written at full precision.
    sample_rate : float, optional
        If given, a first column ``t`` [s] holds the sample times ``k / sample_rate``.

    Raises
    ------
    ValueError
        No columns, columns of different lengths, or a column ``t`` as well as a sample rate.
    """
    if not columns:
        raise ValueError("write_csv: no columns given")
    frame = pd.DataFrame({name: np.asarray(values) for name, values in columns.items()})
    if sample_rate is not None:
        if "t" in frame:
            raise ValueError("write_csv: a column 't' and a sample_rate: give only one")
        frame.insert(0, "t", np.arange(len(frame)) / sample_rate)
    frame.to_csv(path, index=False)


# ---- files and sample rates ----

def _file_format(src: _Source, allowed: tuple[str, ...]) -> str:
    """The format of an existing, non-empty regular file of at most the size its reader takes
    (:mod:`processing.files`), one of ``allowed``."""
    kind = _FORMATS.get(src.path.suffix.lower())
    info = regular(src.path, _FILE_KINDS.get(kind, STREAMED), field=src.field)
    if kind not in allowed:
        raise src.error(f"unknown file type '{src.path.suffix or '(no extension)'}'",
                        "give a " + ", a ".join(_FORMAT_HINTS[k] for k in allowed)
                        + " file; export the recorder's data to one of these",
                        ru=(f"неизвестный тип файла '{src.path.suffix or '(без расширения)'}'",
                            "укажите файл " + ", или ".join(_FORMAT_HINTS_RU[k] for k in allowed)
                            + "; экспортируйте данные регистратора в один из них"))
    if info.st_size == 0:
        raise src.error("the file is empty (0 bytes)", "the recorder did not write it: "
                        "record or export again",
                        ru=("файл пуст (0 байт)", "регистратор его не записал: запишите или "
                            "экспортируйте заново"))
    return kind


def _given_rate(src: _Source, sample_rate) -> float | None:
    if sample_rate is None:
        return None
    if isinstance(sample_rate, bool) or not isinstance(sample_rate, (int, float, np.number)) \
            or not (math.isfinite(sample_rate) and sample_rate > 0):
        raise src.error(f"sample_rate must be a positive number of Hz, got {sample_rate!r}",
                        "give the recorder's sampling frequency in Hz",
                        ru=(f"sample_rate — положительное число герц, а не {sample_rate!r}",
                            "укажите частоту отсчётов регистратора в герцах"))
    return float(sample_rate)


def _rate(src: _Source, found: float | None, given: float | None,
          missing: tuple) -> float:
    """The sample rate: the file's, else the given one; they must agree if both exist.
    ``missing``: the problem, the fix and their Russian when there is neither."""
    if found is None:
        if given is None:
            raise src.error(*missing)
        return given
    if given is not None and abs(found - given) > RATE_TOLERANCE * found:
        raise src.error(f"the file's sample rate is {found:.6g} Hz but sample_rate = "
                        f"{given:.6g} Hz was given", "drop sample_rate (the file's rate is "
                        "used), or check that this is the right file",
                        ru=(f"частота отсчётов файла {found:.6g} Гц, а задано sample_rate = "
                            f"{given:.6g} Гц", "уберите sample_rate (будет взята частота "
                            "файла) или проверьте, тот ли это файл"))
    return found


def _check_simultaneous(src: _Source, channels: list[Channel]) -> None:
    first = channels[0]
    for ch in channels[1:]:
        if ch.length != first.length or not math.isclose(ch.sample_rate, first.sample_rate,
                                                         rel_tol=1e-9):
            raise src.error(f"channels '{first.name}' ({first.length} samples at "
                            f"{first.sample_rate:.6g} Hz) and '{ch.name}' ({ch.length} samples "
                            f"at {ch.sample_rate:.6g} Hz) were not recorded together",
                            "give channels sampled simultaneously: same rate, same length")


def _pick(src: _Source, options: list[str], selector, what: str) -> str:
    """The option a selector names: None → the first, an int → by 0-based index, else by name."""
    if selector is None:
        return options[0]
    if isinstance(selector, (int, np.integer)) and not isinstance(selector, bool):
        if 0 <= selector < len(options):
            return options[selector]
        raise src.error(f"there is no {what} {selector}: the file has {len(options)} "
                        f"({_listing(options)})",
                        f"give an index from 0 to {len(options) - 1}, or a name",
                        ru=(f"нет {_WHAT_RU.get(what, what)} {selector}: в файле их "
                            f"{len(options)} ({_listing(options, lang='ru')})",
                            f"укажите номер от 0 до {len(options) - 1} или имя"))
    if isinstance(selector, str) and selector.strip() in options:
        return selector.strip()
    raise src.error(f"the file has no {what} {selector!r}", _suggest(str(selector), options),
                    ru=(f"в файле нет {_WHAT_RU.get(what, what)} {selector!r}",
                        _suggest(str(selector), options, "ru")))


_WHAT_RU = {"column": "столбца", "dataset": "набора данных", "channel": "канала"}
"""What :func:`_pick` looks for, in the genitive a Russian message takes."""


def _suggest(word: str, options: list[str], lang: str = "en") -> str:
    lower = [o.lower() for o in options]
    close = difflib.get_close_matches(word.strip().lower(), lower, n=1, cutoff=0.5)
    if lang == "ru":
        guess = f"вы имели в виду '{options[lower.index(close[0])]}'? " if close else ""
        return f"{guess}в файле есть {_listing(options, lang=lang)}"
    guess = f"did you mean '{options[lower.index(close[0])]}'? " if close else ""
    return f"{guess}the file has {_listing(options)}"


def _listing(options: list[str], most: int = 12, lang: str = "en") -> str:
    shown = ", ".join(f"'{o}'" for o in options[:most])
    more = " и ещё {}" if lang == "ru" else " and {} more"
    return shown + (more.format(len(options) - most) if len(options) > most else "")


def _volt_scale(name: str) -> float:
    """Volts per unit of a channel whose header names its unit (``U, mV``, ``ch1_мВ``,
    ``u [µV]``); 1 for any other (a plain table's values are volts)."""
    match = _VOLT_NAME.fullmatch(name.strip().lower())
    return 1.0 if match is None else VOLT_UNITS[match.group(1)]


def _time_scale(name: str) -> float | None:
    """Seconds per unit of a time column's header (``t``, ``time_ms``, ``t, us``), else None."""
    match = _TIME_NAME.fullmatch(name.strip().lower())
    return None if match is None else TIME_UNITS[match.group(1) or "s"]


# ---- CSV ----

@dataclasses.dataclass(frozen=True, eq=False)
class _Table:
    """A parsed text table and what is needed to point at its rows."""

    src: _Source
    frame: pd.DataFrame
    text: str
    header: bool
    decimal: str
    layout: Layout | None = None

    @classmethod
    def read(cls, src: _Source) -> _Table:
        """The file parsed, once per content inside a :func:`processing.inputs.reuse.scope`
        (a check's reductions of its slips and its digest of the recordings read the file
        again), pointing at ``src``'s field."""
        return dataclasses.replace(cls._parsed(src), src=src)

    @classmethod
    @by_content(lambda cls, src: src.path, shared=True)
    def _parsed(cls, src: _Source) -> _Table:
        text = _read_text(src)
        layout = recognise(list(itertools.islice(_content_lines(text), PREAMBLE_MOST + 1)),
                           lambda problem, fix, ru: src.error(problem, fix, ru=ru))
        if layout is not None:
            return cls._export(src, text, layout)
        lines = _content_lines(text)
        first = next(lines, None)
        if first is None:
            raise src.error("no data: only blank or comment lines", "export the recording "
                            "again as a table of numbers",
                            ru=("нет данных: только пустые строки или комментарии",
                                "экспортируйте запись заново как таблицу чисел"))
        sep = _separator(first[1])
        titles = _cells(first[1], sep)
        header = any(f.strip(" \"'") and not _is_number(f) for f in titles)
        data_line = next(lines, None) if header else first
        if data_line is None:
            raise src.error("no data: only a header row", "export the recording with its rows "
                            "of numbers", ru=("нет данных: только строка заголовка",
                                              "экспортируйте запись со строками чисел"))
        row = _cells(data_line[1], sep)
        if not any(_is_number(c) for c in row):
            raise src.error(f"row {data_line[0]} holds no number: this is text, not a table "
                            "of readings", "give the recording exported as a table of numbers "
                            "(a header row, then one row of numbers per sample)",
                            ru=(f"в строке {data_line[0]} нет ни одного числа: это текст, а не "
                                "таблица отсчётов", "укажите запись, экспортированную "
                                "таблицей чисел (строка заголовка, затем по строке чисел на "
                                "отсчёт)"))
        decimal = "," if sep != "," and "," in data_line[1] else "."
        named = [f.strip() for f in titles if f.strip()] if header else []
        if len(row) < len(named):
            raise src.error(f"the header names {len(named)} columns ({', '.join(named)}) but "
                            f"row {data_line[0]} holds {len(row)} cells: "
                            f"a '{sep}' inside a name (\"t, ms\") splits it in two",
                            f"put such a name in quotes (\"t, ms\"), write it without the "
                            f"'{sep}' (t_ms, t [ms]) or separate the columns with ';'",
                            ru=(f"в заголовке {len(named)} имён столбцов, а в строке "
                                f"{data_line[0]} {len(row)} ячеек: "
                                f"'{sep}' внутри имени (\"t, мс\") делит его надвое",
                                f"возьмите такое имя в кавычки (\"t, мс\"), напишите его без "
                                f"'{sep}' (t_ms, t [мс]) или разделяйте столбцы ';'"))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", pd.errors.ParserWarning)  # rows beyond the header
                frame = pd.read_csv(_Slices(text), sep=sep, header=0 if header else None,
                                    decimal=decimal, comment="#", skipinitialspace=True,
                                    index_col=False, low_memory=False)
        except (pd.errors.ParserError, pd.errors.ParserWarning, ValueError) as exc:
            if sep == "," and re.search(r"\d,\d", data_line[1]) and header and \
                    len(row) > len(titles):
                raise src.error("the rows have more cells than the header: the numbers seem to "
                                "use decimal commas while commas also separate the columns",
                                "export the table with ';' (or tabs) between the columns, or "
                                "with '.' as the decimal point",
                                ru=("в строках больше ячеек, чем в заголовке: похоже, в числах "
                                    "десятичные запятые, а запятые же разделяют столбцы",
                                    "экспортируйте таблицу с ';' (или табуляцией) между "
                                    "столбцами или с '.' как десятичным знаком")) from None
            raise src.error(f"not a regular table ({exc})".replace("\n", " "),
                            "give every row the same number of cells, and every column a name "
                            "in the header",
                            ru=("таблица неправильная: в строках разное число ячеек",
                                "дайте каждой строке одинаковое число ячеек, а каждому столбцу "
                                "имя в заголовке")) from None
        return cls(src, _clean_columns(frame, header), text, header, decimal)

    @classmethod
    def _export(cls, src: _Source, text: str, layout: Layout) -> _Table:
        """An instrument's export (:mod:`processing.inputs.scope_exports`): its columns of
        numbers read under the instrument's names, the rows counted against its header."""
        cls._check_segments(src, text, layout)
        data = next(itertools.islice(_content_lines(text), layout.lead, None))[1]
        decimal = "," if layout.sep != "," and "," in data else "."
        try:
            frame = pd.read_csv(_Slices(text), sep=layout.sep, header=None, skiprows=layout.skip,
                                usecols=list(layout.usecols), decimal=decimal, comment="#",
                                skipinitialspace=True, index_col=False, low_memory=False)
        except (pd.errors.ParserError, ValueError) as exc:
            raise src.error(f"the {layout.instrument} export is not a regular table after its "
                            f"header ({exc})".replace("\n", " "),
                            "export the waveform again, unedited",
                            ru=(f"экспорт {layout.instrument} после заголовка — не правильная "
                                "таблица", "экспортируйте осциллограмму заново, без правки")
                            ) from None
        table = cls(src, frame.set_axis(list(layout.names), axis=1), text, True, decimal, layout)
        table._check_export()
        return table

    @staticmethod
    def _check_segments(src: _Source, text: str, layout: Layout) -> None:
        """One segment of an export whose headers end in a mark line (LabVIEW's): a header
        met among the rows opens a second, refused."""
        end = layout.end
        if end is None or text.count(end) <= 2:
            return
        at = text.index(end, text.index(end, text.index(end) + 1) + 1)
        row = text.count("\n", 0, at) + 1
        raise src.error(f"a second segment begins: its header ends at row {row}",
                        "save one segment a file (Write To Measurement File: one header only, "
                        "or a new file for each segment)",
                        ru=(f"начинается второй сегмент: его заголовок кончается в строке "
                            f"{row}", "сохраняйте по сегменту в файл (Write To Measurement File: "
                            "один заголовок или новый файл на сегмент)"))

    def _check_export(self) -> None:
        """An export's rows against its header: the stated number of samples, a last row
        cut short."""
        layout, rows = self.layout, len(self.frame)
        if layout.length is not None and rows != layout.length.value:
            n, where = layout.length, f"'{layout.length.name}' (row {layout.length.row})"
            raise self.src.error(
                f"the header's {where} says {n.value:.0f} samples, but {rows} rows of numbers "
                "follow: the file was cut short or edited",
                "export the waveform again and copy the whole file; if rows were cut on "
                f"purpose, correct {n.name} to {rows}",
                ru=(f"{where} заголовка говорит {n.value:.0f} отсчётов, а строк чисел {rows}: "
                    "файл обрезан или правлен", "экспортируйте осциллограмму заново и "
                    f"скопируйте файл целиком; если строки убраны намеренно, исправьте "
                    f"{n.name} на {rows}"))
        last = self.frame.iloc[-1]
        if last.isna().any():
            row = self.line(rows - 1)
            raise self.src.error(f"the last row (row {row}) is cut short: it lacks "
                                 f"'{last.index[last.isna()][0]}'",
                                 "copy the whole file again from the instrument, or delete the "
                                 "cut row", ru=(f"последняя строка (строка {row}) обрезана",
                                                "скопируйте файл с прибора заново целиком или "
                                                "удалите обрезанную строку"))

    @property
    def names(self) -> list[str]:
        return list(self.frame.columns)

    def line(self, row: int) -> int:
        """The file's row number (as a spreadsheet counts them) of data row ``row`` (0-based)."""
        lead = self.header if self.layout is None else self.layout.lead
        return next(itertools.islice(_content_lines(self.text), row + lead, None))[0]

    def numbers(self, name: str) -> np.ndarray:
        """Column ``name`` as numbers, every cell checked: numeric and finite; an export's in
        seconds or volts, its over-range marks at the column's extremes (:meth:`_over`)."""
        column = self.frame[name]
        over = None
        if column.dtype.kind not in "biuf":
            text = column.astype(str).str.strip()
            if self.decimal == ",":
                text = text.str.replace(",", ".", regex=False)
            if self.layout is not None and self.layout.marks:
                over = text.map(OVER).to_numpy(dtype=float, na_value=0.0)
                text = text.where(over == 0, "0")
            numeric = pd.to_numeric(text, errors="coerce")
            bad = (numeric.isna() & column.notna()).to_numpy()
            if bad.any():
                row = int(np.argmax(bad))
                raise self.src.error(
                    f"row {self.line(row)}, column '{name}': {column.iloc[row]!r} is not a number",
                    "write plain numbers in every cell (units go in the header, e.g. 't, ms') "
                    "with one decimal separator throughout",
                    ru=(f"строка {self.line(row)}, столбец '{name}': {column.iloc[row]!r} — не "
                        "число", "пишите в каждой ячейке только числа (единицы — в заголовке, "
                        "например 't, ms') с одним десятичным разделителем во всей таблице"))
            column = numeric
        values = column.to_numpy()
        finite = np.isfinite(values)
        if not finite.all():
            row = int(np.argmin(finite))
            what = "is empty" if np.isnan(values[row]) else f"is {values[row]}"
            what_ru = "пуст" if np.isnan(values[row]) else f"равен {values[row]}"
            raise self.src.error(f"row {self.line(row)}, column '{name}' {what}",
                                 "fill in the missing value or delete the row (a gap in a "
                                 "sampled signal means the recording must be cut there)",
                                 ru=(f"строка {self.line(row)}, столбец '{name}' {what_ru}",
                                     "впишите недостающее значение или удалите строку (пропуск "
                                     "в оцифрованном сигнале значит, что запись надо разрезать "
                                     "здесь)"))
        if self.layout is None:
            scale = _volt_scale(name) if self.header else 1.0
            return values * scale if scale != 1.0 else values.copy()   # the caller's own
        over = np.zeros(len(values)) if over is None else over
        if values.dtype.kind == "f":
            scpi, holes = scpi_marks(values)
            if holes.any():
                row = self.line(int(np.argmax(holes)))
                raise self.src.error(
                    f"row {row}, column '{name}' holds {values[holes][0]:.4g}, the "
                    "instrument's mark of a sample it does not have", "export the waveform "
                    "again, or reduce a stretch without holes",
                    ru=(f"строка {row}, столбец '{name}' содержит {values[holes][0]:.4g} — "
                        "так прибор отмечает отсутствующий отсчёт", "экспортируйте "
                        "осциллограмму заново или обработайте участок без пропусков"))
            over = over + scpi
        if over.any():
            values = self._over(name, values, over)
        return values * self._scale(name)

    def _over(self, name: str, values: np.ndarray, over: np.ndarray) -> np.ndarray:
        """Over-range samples (``over`` = +1 above the range, −1 below) put at the column's
        highest or lowest reading, where a recorder's rail holds a clipped sample: there
        :func:`~processing.inputs.record_quality.clipped_mask` counts them as clipped."""
        values = values.astype(float)
        inside = over == 0
        if not inside.any():
            raise self.src.error(f"every sample of '{name}' is marked over range (∞)",
                                 "raise the channel's input range and record again",
                                 ru=(f"все отсчёты '{name}' отмечены как вне диапазона (∞)",
                                     "увеличьте диапазон входа канала и запишите заново"))
        values[over > 0] = values[inside].max()
        values[over < 0] = values[inside].min()
        return values

    def _scale(self, name: str) -> float:
        """Seconds or volts per unit of an export's column ``name``."""
        scale = self.layout.scale(name)
        if scale is not None:
            return scale
        unit = self.layout.units.get(name, "")
        if name == self.layout.time:
            raise self.src.error(f"the time column '{name}' is in '{unit}', not a unit of time",
                                 "export the waveform with its time axis in s, ms, µs or ns",
                                 ru=(f"столбец времени '{name}' в '{unit}', а не в единицах "
                                     "времени", "экспортируйте осциллограмму со временем в "
                                     "s, ms, µs или ns"))
        raise self.src.error(f"column '{name}' is in '{unit}', not in volts",
                             "export the channel in volts (V or mV), the probe's scaling off: "
                             "the lab converts volts with the sensor's own sensitivity",
                             ru=(f"столбец '{name}' в '{unit}', а не в вольтах",
                                 "экспортируйте канал в вольтах (V или mV), без пересчёта "
                                 "пробника: лаб. работа пересчитывает вольты по "
                                 "чувствительности датчика"))


def _read_text(src: _Source) -> str:
    """The table's text: UTF-8, else Windows-1251 (Russian Excel); binary data refused."""
    return read_text(src.path, TABLE, field=src.field, legacy="cp1251",
                     fix="give a .csv/.txt table of numbers, or the recording's real extension",
                     fix_ru="укажите таблицу чисел .csv/.txt или настоящее расширение записи")


def _content_lines(text: str) -> Iterator[tuple[int, str]]:
    """(row number, line) of the lines that are neither blank nor comments."""
    return ((no, line) for no, line in enumerate(_lines(text), 1)
            if line.strip() and not line.lstrip().startswith("#"))


def _lines(text: str) -> Iterator[str]:
    """The lines of ``text``, each with its newline, sliced as they are asked for (a
    :class:`io.StringIO` would first copy the whole text, at four bytes a character)."""
    start = 0
    while start < len(text):
        end = text.find("\n", start) + 1 or len(text)
        yield text[start:end]
        start = end


class _Slices:
    """A long text handed to :func:`pandas.read_csv` in slices, without a copy of the
    whole (see :func:`_lines`)."""

    def __init__(self, text: str):
        self.text, self.at = text, 0

    def read(self, size: int = -1) -> str:
        end = len(self.text) if size is None or size < 0 else self.at + size
        piece, self.at = self.text[self.at:end], min(end, len(self.text))
        return piece

    def __iter__(self) -> Iterator[str]:
        return _lines(self.text[self.at:])


def _separator(line: str) -> str:
    return next((s for s in (";", "\t", ",") if s in line), r"\s+")


def _cells(line: str, sep: str) -> list[str]:
    """A row's cells as the table's reader takes them: a separator inside quotes is text."""
    if sep == r"\s+":
        return line.split()
    return next(csv.reader([line.rstrip("\r\n")], delimiter=sep, skipinitialspace=True), [])


def _is_number(cell: str) -> bool:
    try:
        float(cell.strip(" \"'\n").replace(",", "."))
    except ValueError:
        return False
    return True


def _clean_columns(frame: pd.DataFrame, header: bool) -> pd.DataFrame:
    """Names stripped (``column k`` without a header); empty unnamed columns (a trailing
    separator) dropped."""
    names = [str(c).strip() if header else f"column {c}" for c in frame.columns]
    frame = frame.set_axis(names, axis=1)
    empty = [n for n in names
             if (not header or n.startswith("Unnamed:")) and frame[n].isna().all()]
    return frame.drop(columns=empty) if empty else frame


def _csv_channels(src: _Source, selectors: list, given: float | None) -> list[Channel]:
    table = _Table.read(src)
    time, found = _time_base(src, table, given)
    data = [n for n in table.names if n != time]
    if not data:
        raise src.error(f"only a time column '{time}', no data column",
                        "add the sensor's column next to the time column",
                        ru=(f"только столбец времени '{time}', столбца данных нет",
                            "добавьте столбец датчика рядом со столбцом времени"))
    alone = len(table.names) == 1
    rate = _rate(src, found, given, (
        f"{'one column' if alone else 'no time column'} and no sample rate",
        "add a time column t [s] as the first column, or give sample_rate",
        (f"{'один столбец' if alone else 'нет столбца времени'} и не задана частота отсчётов",
         "добавьте первым столбцом время t [с] или задайте sample_rate")))
    channels = []
    for selector in selectors:
        name = _pick(src, data, selector, "column")
        values = table.numbers(name)
        channels.append(src.channel(name, rate, len(values), values.dtype,
                                    functools.partial(_memory_reader, values)))
    return channels


@contextlib.contextmanager
def _memory_reader(values: np.ndarray) -> Iterator[_Reader]:
    yield lambda a, b: values[a:b].copy()


def _time_base(src: _Source, table: _Table,
               given: float | None = None) -> tuple[str | None, float | None]:
    """The time column's name and the sample rate it implies, or (None, None). An export's
    header interval gives its rate, every step of its time column checked against it; an
    export's time column rounded so far that it repeats gives none, and ``given`` [Hz] is
    checked against it (:func:`_rounded_rate`)."""
    layout, interval = table.layout, None
    if layout is not None and layout.time is None:
        return None, None if layout.interval is None else 1.0 / layout.interval.value
    if layout is not None:
        first, interval = layout.time, layout.interval
        t = table.numbers(first)
    else:
        first = table.names[0]
        scale = _time_scale(first) if table.header else None
        if scale is None:
            return None, None
        t = table.numbers(first) * scale
    if len(t) < 2:
        raise src.error("one row: a sample rate needs at least two times",
                        "export the whole recording",
                        ru=("одна строка: для частоты отсчётов нужны хотя бы два момента "
                            "времени", "экспортируйте всю запись"))
    if interval is not None:
        return first, _stated_rate(src, table, t, interval)
    if layout is not None and (np.diff(t) == 0).any():
        return first, _rounded_rate(src, table, t, given)
    _check_rising(src, table, first, t)
    steps = np.diff(t)
    typical = np.median(steps)
    off = np.abs(steps - typical) > RATE_TOLERANCE * typical
    if off.any():
        k = int(np.argmax(off))
        raise src.error(f"the time column '{first}' is not uniformly sampled at row "
                        f"{table.line(k + 1)}: step {steps[k]:.6g} s, usual step "
                        f"{typical:.6g} s", "a gap means lost samples"
                        + (" or a new segment (an oscilloscope's segmented memory saved whole: "
                           "export one segment)" if layout is not None else "")
                        + ": cut the file to an unbroken stretch; if the times were rounded on "
                        "export, write them with more digits, or delete the time column and "
                        "give sample_rate")
    return first, (len(t) - 1) / (t[-1] - t[0])  # the mean step: robust to rounded times


def _rounded_rate(src: _Source, table: _Table, t: np.ndarray, given: float | None) -> float:
    """The ``given`` sample rate [Hz] of an export whose times (``t`` [s]) were printed with
    too few digits to tell the samples apart (Rigol DS1000E: three), once they agree with it:
    they never fall, and each lies within two of their largest steps (a unit of their last
    digit) of ``t[0] + k / given``."""
    name = table.layout.time
    _check_rising(src, table, name, t, strict=False)
    k = int(np.argmax(np.diff(t) == 0)) + 1
    if given is None:
        raise src.error(f"the time column '{name}' repeats its times from row {table.line(k)} "
                        f"({t[k]:.6g} s): the instrument printed them with too few digits to "
                        "give the sample rate", "give sample_rate = the oscilloscope's Sa/s "
                        "(shown on its screen); the times are then checked against it",
                        ru=(f"столбец времени '{name}' повторяет значения со строки "
                            f"{table.line(k)} ({t[k]:.6g} с): прибор записал время слишком "
                            "малым числом цифр, и частоту отсчётов по нему не найти",
                            "задайте sample_rate = частота дискретизации осциллографа (Sa/s "
                            "на его экране); время будет проверено по ней"))
    off = np.abs(t - t[0] - np.arange(len(t)) / given)
    unit = np.diff(t).max()
    if (off > 2 * unit).any():
        k = int(np.argmax(off > 2 * unit))
        raise src.error(f"sample_rate = {given:.6g} Hz puts row {table.line(k)} at "
                        f"{t[0] + k / given:.6g} s, but its time is {t[k]:.6g} s (the times "
                        f"are rounded to {unit:.3g} s)", "give the oscilloscope's true Sa/s, "
                        "or check that this is the right file",
                        ru=(f"при sample_rate = {given:.6g} Гц строка {table.line(k)} "
                            f"приходится на {t[0] + k / given:.6g} с, а её время {t[k]:.6g} с "
                            f"(время округлено до {unit:.3g} с)", "укажите истинную частоту "
                            "дискретизации осциллографа или проверьте, тот ли это файл"))
    return given


def _stated_rate(src: _Source, table: _Table, t: np.ndarray, interval) -> float:
    """1 / the interval an export's header states [Hz], once every step of its time column
    (``t`` [s]) agrees with it."""
    layout = table.layout
    steps = np.diff(t)
    off = np.abs(steps - interval.value) > RATE_TOLERANCE * interval.value
    if off.any():
        k = int(np.argmax(off))
        raise src.error(f"row {table.line(k + 1)}: the time column '{layout.time}' steps by "
                        f"{steps[k]:.6g} s, but the header's '{interval.name}' (row "
                        f"{interval.row}) is {interval.value:.6g} s",
                        "a jump means lost or deleted rows: export the waveform again whole "
                        "and leave it unedited (or cut it to an unbroken stretch)",
                        ru=(f"строка {table.line(k + 1)}: столбец времени '{layout.time}' "
                            f"шагает на {steps[k]:.6g} с, а '{interval.name}' заголовка "
                            f"(строка {interval.row}) равен {interval.value:.6g} с",
                            "скачок значит потерянные или удалённые строки: экспортируйте "
                            "осциллограмму заново целиком и не правьте её"))
    return 1.0 / interval.value


def _check_rising(src: _Source, table: _Table, name: str, t: np.ndarray, *,
                  strict: bool = True) -> None:
    """Times that rise (``strict``) or, rounded, never fall."""
    falls = np.diff(t) <= 0 if strict else np.diff(t) < 0
    if falls.any():
        k = int(np.argmax(falls))
        how, how_ru = ("strictly increasing", "строго ") if strict else ("rising", "")
        raise src.error(f"column '{name}' is not {how} at row {table.line(k + 1)}"
                        f" ({t[k + 1]:.9g} s after {t[k]:.9g} s)", "times must rise: remove "
                        "repeated rows, and split a recording whose counter restarted",
                        ru=(f"столбец '{name}' не возрастает {how_ru}в строке "
                            f"{table.line(k + 1)} ({t[k + 1]:.9g} с после {t[k]:.9g} с)",
                            "время должно расти: удалите повторные строки и разделите запись, "
                            "счётчик которой начался заново"))


def _edge_column(src: _Source, table: _Table, column) -> str:
    if column is not None or len(table.names) == 1:
        return _pick(src, table.names, column, "column")
    if table.header and _time_scale(table.names[0]) is not None:
        return table.names[0]
    raise src.error(f"{len(table.names)} columns and none named t or time",
                    f"name the column of edge times: column = one of {_listing(table.names)}")


# ---- WAV ----

def _wav_channels(src: _Source, selectors: list, given: float | None) -> list[Channel]:
    rate, layout = _wav_layout(src)
    if layout.frames == 0:
        raise src.error("the WAV file holds no samples", "record again",
                        ru=("в WAV-файле нет отсчётов", "запишите заново"))
    rate = _rate(src, float(rate) if rate > 0 else None, given,
                 ("the WAV header gives no sample rate", "give sample_rate",
                  ("в заголовке WAV нет частоты отсчётов", "задайте sample_rate")))
    names = [f"channel {k}" for k in range(layout.count)]
    channels = []
    for selector in selectors:
        side = _WAV_SIDES.get(selector) if isinstance(selector, str) else None
        name = _pick(src, names, selector if side is None else side, "channel")
        channels.append(src.channel(name, rate, layout.frames, layout.dtype,
                                    dataclasses.replace(layout, channel=names.index(name))))
    return channels


def _wav_layout(src: _Source) -> tuple[int, _WavOpener]:
    """The sample rate [Hz] and where the samples lie; scipy parses the header (its
    memory map is only looked at, not read)."""
    try:
        rate, data = wavfile.read(src.path, mmap=True)
    except ValueError as exc:
        if "container size" in str(exc):
            return _packed_layout(src)
        if "mmap length is greater than file size" in str(exc):
            raise src.error(f"the file is cut short: its header announces more samples than "
                            f"its {src.path.stat().st_size} bytes hold",
                            "copy the recording again whole from the recorder",
                            ru=(f"файл обрезан: заголовок объявляет больше отсчётов, чем "
                                f"вмещают его {src.path.stat().st_size} байт",
                                "скопируйте запись с регистратора заново целиком")) from None
        raise src.error(f"not a readable WAV file ({exc})",
                        "export the recording as a PCM (8/16/24/32-bit) or float WAV",
                        ru=("WAV-файл не читается: это не запись RIFF/RF64",
                            "экспортируйте запись как WAV PCM (8/16/24/32 бит) или с "
                            "плавающей точкой")) from None
    except (struct.error, EOFError):
        raise src.error("the WAV header is cut short or damaged",
                        "copy the recording again whole, or export it anew",
                        ru=("заголовок WAV обрезан или повреждён",
                            "скопируйте запись заново целиком или экспортируйте её снова")
                        ) from None
    except ZeroDivisionError:
        raise src.error("the WAV header says the file has no channels",
                        "export the recording again as a mono or stereo WAV",
                        ru=("по заголовку WAV в файле нет каналов",
                            "экспортируйте запись заново как моно- или стерео-WAV")) from None
    count = 1 if data.ndim == 1 else data.shape[1]
    return rate, _WavOpener(src.path, data.offset, data.shape[0], count, data.dtype.itemsize,
                            data.dtype)


def _packed_layout(src: _Source) -> tuple[int, _WavOpener]:
    """As :func:`_wav_layout` for samples numpy has no type for (24-bit), which scipy cannot
    map: the RIFF chunks are walked to the data (scipy has checked the header already)."""
    with open(src.path, "rb") as fid:
        riff = fid.read(12)[:4]
        if riff == b"RIFX":
            raise src.error("a big-endian 24-bit WAV file cannot be streamed",
                            "convert it to a standard (little-endian) WAV")
        fmt = big_size = None
        while len(head := fid.read(8)) == 8:
            cid, size = struct.unpack("<4sI", head)
            body = fid.tell()
            if cid == b"ds64":
                big_size = struct.unpack("<QQ", fid.read(16))[1]
            elif cid == b"fmt ":
                fmt = struct.unpack("<HHIIHH", fid.read(16))
            elif cid == b"data":
                _, count, rate, _, align, _ = fmt
                size = min(big_size if riff == b"RF64" else size, src.path.stat().st_size - body)
                width = align // count
                return rate, _WavOpener(src.path, body, size // align, count, width,
                                        np.dtype("<i4" if width == 3 else "<i8"))
            fid.seek(body + size + size % 2)
    raise src.error("the WAV file has no data chunk", "record or export again")


@dataclasses.dataclass(frozen=True)
class _WavOpener:
    """Reads channel ``channel`` of a WAV file block by block with plain file reads (memory
    holds one block). The data start at byte ``offset``: ``frames`` frames of ``count``
    samples of ``width`` bytes. Samples narrower than ``dtype`` (24-bit in int32) are
    left-justified, as scipy reads them."""

    path: Path
    offset: int
    frames: int
    count: int
    width: int
    dtype: np.dtype
    channel: int = 0

    @contextlib.contextmanager
    def __call__(self) -> Iterator[_Reader]:
        with open(self.path, "rb") as fid:
            yield functools.partial(self._read, fid)

    def _read(self, fid, a: int, b: int) -> np.ndarray:
        frame = self.count * self.width
        fid.seek(self.offset + a * frame)
        raw = np.fromfile(fid, np.uint8, (b - a) * frame).reshape(b - a, self.count, self.width)
        mine = raw[:, self.channel]
        if self.width == self.dtype.itemsize:
            return np.ascontiguousarray(mine).view(self.dtype)[:, 0]
        return _unpack(mine, self.width)


def _unpack(raw: np.ndarray, width: int) -> np.ndarray:
    """Little-endian signed samples of ``width`` bytes (rows of ``raw``), left-justified."""
    size = 4 if width == 3 else 8
    out = np.zeros((len(raw), size), np.uint8)
    out[:, size - width:] = raw
    return out.view(f"<i{size}")[:, 0]


# ---- HDF5 ----

def _hdf5_channels(src: _Source, selectors: list, given: float | None) -> list[Channel]:
    with contextlib.ExitStack() as stack:
        try:
            f = stack.enter_context(_hdf5_file(src.path))
        except OSError as exc:
            raise src.error(f"not a readable HDF5 file ({exc})",
                            "give an HDF5 file (.h5) as the recorder or write_hdf5 writes it",
                            ru=("файл HDF5 не читается", "укажите файл HDF5 (.h5), как его "
                                "пишет регистратор или write_hdf5")) from None
        datasets = _datasets(f)
        return [_hdf5_channel(src, f, _dataset_name(src, datasets, s), given) for s in selectors]


def _datasets(f: h5py.File) -> dict[str, h5py.Dataset]:
    found = {}

    def keep(name, obj) -> None:  # visititems stops at the first callback not returning None
        if isinstance(obj, h5py.Dataset):
            found[name] = obj

    f.visititems(keep)
    return found


def _dataset_name(src: _Source, datasets: dict[str, h5py.Dataset], selector) -> str:
    listing = ", ".join(f"'{n}' {d.shape}" for n, d in datasets.items()) or "none"
    if selector is None:
        one_d = [n for n, d in datasets.items() if d.ndim == 1]
        if len(one_d) == 1:
            return one_d[0]
        raise src.error(f"{len(one_d)} one-dimensional datasets, so which is the channel is not "
                        f"clear (datasets: {listing})",
                        "name the dataset of the channel" if one_d else
                        "store each channel as a 1-D dataset",
                        ru=(f"одномерных наборов данных: {len(one_d)}, и какой из них канал, "
                            f"неясно (наборы: {listing})",
                            "назовите набор данных канала" if one_d else
                            "храните каждый канал одномерным набором данных"))
    if not isinstance(selector, str):
        raise src.error(f"an HDF5 channel is a dataset path, got {selector!r}",
                        f"give the dataset's path (datasets: {listing})")
    return _pick(src, list(datasets), selector.strip("/ "), "dataset")


def _hdf5_channel(src: _Source, f: h5py.File, name: str, given: float | None) -> Channel:
    ds = f[name]
    if ds.ndim != 1 or ds.dtype.kind not in "biuf":
        raise src.error(f"dataset '{name}' holds {ds.dtype} of shape {ds.shape}, not a channel",
                        "store each channel as a 1-D dataset of numbers")
    if ds.shape[0] == 0:
        raise src.error(f"dataset '{name}' holds no samples", "record again",
                        ru=(f"в наборе данных '{name}' нет отсчётов", "запишите заново"))
    _check_storage(src, name, ds)
    missing = (f"no sample rate for dataset '{name}'",
               "add the attribute sample_rate [Hz] to the dataset or the file, or give sample_rate",
               (f"у набора данных '{name}' нет частоты отсчётов",
                "добавьте набору данных или файлу атрибут sample_rate [Гц] или задайте "
                "sample_rate"))
    rate = _rate(src, _attr(src, name, (ds, f), ("sample_rate", "fs")), given, missing)
    volts = _attr(src, name, (ds, f), ("volts_per_code",))
    return src.channel(name, rate, ds.shape[0], ds.dtype,
                       functools.partial(_hdf5_reader, src.path, name),
                       1.0 if volts is None else volts)


def _check_storage(src: _Source, name: str, ds: h5py.Dataset) -> None:
    """Refuse samples stored outside the file (external or virtual storage names other
    files, which the reader would open unjudged: a FIFO, a device) and chunks larger than
    :data:`HDF5_MAX_CHUNK` (each is decompressed whole, however few samples are asked)."""
    if ds.external or ds.is_virtual:
        raise src.error(f"dataset '{name}' keeps its samples in other files "
                        f"({'virtual' if ds.is_virtual else 'external'} storage)",
                        "store the samples in the file itself (h5repack copies them in)",
                        ru=(f"набор данных '{name}' хранит отсчёты в других файлах "
                            f"({'виртуальное' if ds.is_virtual else 'внешнее'} хранение)",
                            "сохраните отсчёты в самом файле (h5repack копирует их внутрь)"))
    chunk = math.prod(ds.chunks) * ds.dtype.itemsize if ds.chunks else 0
    if chunk > HDF5_MAX_CHUNK:
        raise src.error(f"dataset '{name}' is stored in chunks of {chunk / 2**20:.0f} MiB, "
                        f"each read whole (at most {HDF5_MAX_CHUNK >> 20} MiB)",
                        "write it with smaller chunks (h5repack -l CHUNK=262144), as "
                        "recorders do",
                        ru=(f"набор данных '{name}' хранится блоками по "
                            f"{chunk / 2**20:.0f} МиБ, и каждый читается целиком (допустимо "
                            f"не больше {HDF5_MAX_CHUNK >> 20} МиБ)", "запишите его меньшими "
                            "блоками (h5repack -l CHUNK=262144), как это делают регистраторы"))


def _attr(src: _Source, name: str, holders, keys: tuple[str, ...]) -> float | None:
    """The first of the attributes ``keys`` found on the dataset, then the file."""
    for holder, key in itertools.product(holders, keys):
        if key in holder.attrs:
            value = np.asarray(holder.attrs[key])
            if value.size != 1 or value.dtype.kind not in "iuf" \
                    or not (math.isfinite(value.item()) and value.item() > 0):
                raise src.error(f"attribute {key} = {value!r} (of '{holder.name}') is not a "
                                f"positive number", f"correct the attribute {key} "
                                f"(dataset '{name}')")
            return float(value.item())
    return None


@contextlib.contextmanager
def _hdf5_reader(path: Path, name: str) -> Iterator[_Reader]:
    with _hdf5_file(path) as f:
        ds = f[name]
        yield lambda a, b: ds[a:b]


_KEPT_OPEN: ContextVar[dict | None] = ContextVar("processing.inputs.signals.kept_open",
                                                 default=None)


@contextlib.contextmanager
def kept_open() -> Iterator[None]:
    """Inside the block, an HDF5 recording once opened (by :func:`open_channels`, or to read
    a channel's samples) stays open and serves every later opening of it, until the block
    ends: a recording's channels opened, then read one by one, cost one opening of the file
    instead of one each (an opening costs a third of a millisecond, as much as reading
    10 000 samples). Other formats read as they do outside it. Nested blocks share the
    outermost one's files."""
    if _KEPT_OPEN.get() is not None:
        yield
        return
    kept: dict = {}
    token = _KEPT_OPEN.set(kept)
    try:
        yield
    finally:
        _KEPT_OPEN.reset(token)
        for f in kept.values():
            f.close()


@contextlib.contextmanager
def _hdf5_file(path: Path) -> Iterator[h5py.File]:
    """The HDF5 file open for reading: kept open inside :func:`kept_open`, else closed after."""
    kept = _KEPT_OPEN.get()
    if kept is None:
        with h5py.File(path, "r") as f:
            yield f
        return
    key = Path(path)
    if key not in kept:
        kept[key] = h5py.File(path, "r")
    yield kept[key]


def _write_array(f: h5py.File, name: str, data: np.ndarray, length: int | None) -> h5py.Dataset:
    if data.ndim != 1 or not data.size or (length is not None and len(data) != length):
        raise ValueError(f"write_hdf5: dataset '{name}' must be a non-empty 1-D array"
                         + (f" of {length} samples" if length is not None else "")
                         + f", got shape {data.shape}")
    return f.create_dataset(name, data=data)


def _write_blocks(f: h5py.File, name: str, blocks: Iterable[np.ndarray],
                  length: int | None) -> h5py.Dataset:
    """Append 1-D blocks to a chunked dataset (pre-sized if ``length`` is known)."""
    ds, n = None, 0
    for block in map(np.asarray, blocks):
        if block.ndim != 1:
            raise ValueError(f"write_hdf5: blocks of '{name}' must be 1-D, got shape "
                             f"{block.shape}")
        if not block.size:
            continue
        if ds is None:
            ds = f.create_dataset(name, shape=(length or 0,), dtype=block.dtype,
                                  maxshape=(length,) if length else (None,),
                                  chunks=(min(HDF5_CHUNK, length or max(len(block), 4096)),))
        end = n + len(block)
        if end > ds.shape[0]:
            if length:
                raise ValueError(f"write_hdf5: '{name}' has more than length={length} samples")
            ds.resize((end,))
        ds[n:end] = block
        n = end
    if ds is None or n != ds.shape[0]:
        raise ValueError(f"write_hdf5: '{name}' got {n} samples"
                         + (f", not length={length}" if length else ""))
    return ds
