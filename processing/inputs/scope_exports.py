"""The CSV exports of oscilloscopes and acquisition programs, recognised by their layout.

A plain table (an optional header row of names, then rows of numbers) is not an export: it is
read as it is. An export puts rows of its own before the numbers; :func:`recognise` reads them
(never the file's name) and returns the :class:`Layout`: where the numbers start, which
columns hold them, what the channels are called, in which units, and the time base the
header states. The layouts recognised (every one as a student's file shows it; sources in
``tests/test_scope_exports.py``):

Rigol DS1000Z / MSO1000Z
    ``X,CH1,CH2,Start,Increment,`` then ``Sequence,Volt,Volt,<start>,<increment>,``, then
    rows ``k,value,value,``: sample k lies at Start + k·Increment [s].
Tektronix TDS / TBS1000 (one channel a file)
    The settings in the first two columns of the first rows (``Record Length``, ``Sample
    Interval``, ``Source``, ``Vertical Units``, ``Horizontal Units`` …) beside the data, which
    fill the fourth and fifth columns of every row: time, value. The channel is named by
    ``Source``.
Name–value preamble (Tektronix MSO/DPO/TBS2000, Siglent SDS)
    Rows ``name,value`` (``Record Length``, ``Sample Interval``, ``Vertical Units``,
    ``Source`` …), then a header row whose first cell is the time (``TIME,CH1,CH2``; Siglent's
    ``Second,Volt,Volt`` or ``Second,Value``, whose channels are named by ``Source``), then rows
    of numbers. Siglent's ``Record Length,Analog:1400`` counts the analog samples.
Keysight / Agilent InfiniiVision; Rigol DS1000E
    ``x-axis,1,2`` then ``second,Volt,Volt`` (Rigol DS1000E: ``X,CH1,CH2`` then
    ``Second,Voltage,Voltage``, or ``Time,X(CH1),X(CH2),`` then ``Second,Volt,Volt,``), then
    rows; channel k is named ``CHk``. The DS1000E prints its times to three digits, so that
    they repeat: its rate is the ``sample_rate`` given, checked against them within their
    rounding.
PicoScope 6 / 7
    ``Time,Channel A,Channel B`` then the units ``(ms),(V),(mV)``, a blank row, then rows;
    ``∞`` and ``-∞`` mark a sample beyond the input range.
LabVIEW Measurement (``.lvm``, NI's Write To Measurement File)
    The file's header and one segment's (``Channels``, ``Samples``, ``Y_Unit_Label``,
    ``X0``, ``Delta_X``), each closed by ``***End_of_Header***``, then ``X_Value,<channels>,
    Comment`` and the rows, tab- or comma-separated with the stated decimal separator; the
    time is a first column (``X_Columns One``) or ``X0 + k·Delta_X`` (``No``). One segment is
    read: a file of several is refused.

In every layout a number of SCPI's, ±9.9E+37 (beyond the range) or 9.91E+37 (no reading), is a
mark, never a value (:func:`scpi_marks`).

Times are converted to seconds (``s``, ``ms``, ``µs``/``us``, ``ns``) and values to volts
(``V``, ``mV``, ``µV``); a channel in any other unit is refused when it is read. A header that
the rows contradict (a ``Record Length`` that is not the number of rows, a time column that
steps otherwise than the stated interval, a sample index that skips) is refused by the
reader, naming the field, its row and the fix.
"""
from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable, Sequence

import numpy as np

PREAMBLE_MOST = 40
"""Rows an export's preamble may take before its first row of numbers."""

OVER = {"∞": 1, "+∞": 1, "-∞": -1, "−∞": -1}
"""Over-range marks (PicoScope) and the side of the range they mark."""

SCPI_INFINITY = 9.9e37
"""SCPI's +∞ (−9.9E+37: −∞), which SCPI instruments write for a reading beyond their range
(SCPI-99, vol. 1, the special numeric values INFinity and NAN); no recorded voltage comes near
it."""

SCPI_NAN = 9.91e37
"""SCPI's not-a-number: a reading the instrument does not have (a hole in the record)."""

TIME_UNITS = {"s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0, "с": 1.0, "ms": 1e-3,
              "мс": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "мкс": 1e-6, "ns": 1e-9}
"""Seconds per unit of a time axis, an export's or a plain table's (units as written, lower
case, Russian too)."""

VOLT_UNITS = {"v": 1.0, "volt": 1.0, "volts": 1.0, "voltage": 1.0, "в": 1.0, "mv": 1e-3,
              "мв": 1e-3, "uv": 1e-6, "µv": 1e-6, "μv": 1e-6, "мкв": 1e-6, "kv": 1e3}
"""Volts per unit of a channel, an export's or a plain table's (units as written, lower case,
Russian too)."""

END_OF_HEADER = "***End_of_Header***"
"""The line that ends a LabVIEW Measurement file's header and each segment's."""

SETTINGS = {"record length", "sample interval", "memory length", "sampling period",
            "horizontal scale", "vertical units"}
"""Names of the settings rows that open an oscilloscope's export."""

_TIME_HEADER = re.compile(r"(?:t|time|second|seconds|x-axis)(?:\s*[(\[].*[)\]])?")
"""A header cell that names an export's time column (``TIME``, ``Time (s)``, ``x-axis``)."""


@dataclasses.dataclass(frozen=True)
class Field:
    """A setting the export's header states: its name as written, its value, its row."""

    name: str
    value: float
    row: int


@dataclasses.dataclass(frozen=True)
class Layout:
    """Where an export keeps its samples and what its header says of them.

    Attributes
    ----------
    instrument : str
        The layout's instrument, for messages ("Rigol DS1000Z").
    skip : int
        The file's lines before the first row of numbers.
    lead : int
        The rows (neither blank nor comments) before the first row of numbers.
    sep : str
        The cell separator.
    usecols : tuple of int
        The cells of a row that hold the time and the channels.
    names : tuple of str
        Their names (the time column's first).
    units : dict of str to str
        Each column's unit as written (the time column's: ``"Sequence"`` for a sample index).
    interval : Field or None
        The sampling interval the header states [s].
    length : Field or None
        The number of samples the header states.
    marks : bool
        Whether cells may hold over-range marks (:data:`OVER`).
    timed : bool
        Whether the first of ``names`` is a time column (else the header's interval alone
        gives the time base).
    end : str or None
        The line that ends a header: met again among the rows, it opens a second segment.
    """

    instrument: str
    skip: int
    lead: int
    sep: str
    usecols: tuple[int, ...]
    names: tuple[str, ...]
    units: dict[str, str]
    interval: Field | None = None
    length: Field | None = None
    marks: bool = False
    timed: bool = True
    end: str | None = None

    @property
    def time(self) -> str | None:
        """The time column's name, None for an export without one."""
        return self.names[0] if self.timed else None

    def scale(self, name: str) -> float | None:
        """SI units (seconds, volts) per unit of column ``name``, None for a unit not known."""
        unit = self.units.get(name, "").strip("()[] ").lower()
        if name == self.time:
            if unit == "sequence" and self.interval is not None:
                return self.interval.value
            return TIME_UNITS.get(unit)
        return VOLT_UNITS.get(unit)


Refuse = Callable[[str, str, tuple[str, str]], Exception]
"""``refuse(problem, fix, (problem_ru, fix_ru))``: the error naming the file and its field."""


def recognise(lines: Sequence[tuple[int, str]], refuse: Refuse) -> Layout | None:
    """The export layout of a text table, or None for a plain table.

    Parameters
    ----------
    lines : sequence of (int, str)
        The table's first rows that are neither blank nor comments, with their row numbers
        (1-based, as a spreadsheet counts them), at least :data:`PREAMBLE_MOST` + 1 of them
        unless the file is shorter.
    refuse : callable
        Makes the error of a layout recognised with no samples after its header.

    Returns
    -------
    Layout or None

    Raises
    ------
    Exception
        ``refuse``'s, for a recognised header followed by no row of numbers (an export saved
        without its data, or cut within its header).

    Examples
    --------
    >>> rows = ["X,CH1,Start,Increment,", "Sequence,Volt,-2.0e-02,2.0e-05,", "0,0.01,"]
    >>> lay = recognise(list(enumerate(rows, 1)), None)
    >>> lay.instrument, lay.names, lay.scale("X"), lay.skip
    ('Rigol DS1000Z', ('X', 'CH1'), 2e-05, 2)
    """
    if not lines:
        return None
    if _cells(lines[0][1], _separator(lines[0][1]))[0] == "LabVIEW Measurement":
        return _labview(lines, refuse)
    tek = _tektronix(lines)
    if tek is not None:
        return tek
    first = next((k for k, (_, line) in enumerate(lines) if _numbers(line)), None)
    if first is None and len(lines) > PREAMBLE_MOST:
        return None
    preamble = lines[:first] if first is not None else lines
    if len(preamble) < 2:
        return None
    data = lines[first] if first is not None else None
    sep = _separator(data[1] if data else preamble[-1][1])
    layout = (_rigol(preamble, sep, data) or _units_row(preamble, sep, data)
              or _name_values(preamble, sep, data))
    if data is None and (layout is not None or _settings_only(preamble, sep)):
        instrument = "oscilloscope" if layout is None else layout.instrument
        raise refuse(f"the {instrument} export holds its header ({len(preamble)} rows) "
                     "but no samples: it was saved without its data or cut short",
                     "export the waveform again (with its data points) and copy the whole "
                     "file", (f"экспорт {instrument} содержит заголовок "
                              f"({len(preamble)} строк), но ни одного отсчёта: он сохранён "
                              "без данных или обрезан", "экспортируйте осциллограмму заново "
                              "(с точками данных) и скопируйте файл целиком"))
    return layout


def scpi_marks(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The SCPI marks among an export's numbers.

    Parameters
    ----------
    values : ndarray
        A column as read.

    Returns
    -------
    over : ndarray of float
        +1 at SCPI +∞ (9.9E+37), −1 at −∞, 0 elsewhere.
    holes : ndarray of bool
        True at SCPI NaN (9.91E+37).

    Examples
    --------
    >>> over, holes = scpi_marks(np.array([0.5, 9.9e37, -9.9e37, 9.91e37]))
    >>> over.tolist(), holes.tolist()
    ([0.0, 1.0, -1.0, 0.0], [False, False, False, True])
    """
    size = np.abs(values)
    holes = size >= 0.5 * (SCPI_INFINITY + SCPI_NAN)
    return np.sign(values) * ((size >= 0.5 * SCPI_INFINITY) & ~holes), holes


def _rigol(preamble, sep: str, data) -> Layout | None:
    """``X,CH1,…,Start,Increment,`` / ``Sequence,Volt,…,<start>,<increment>,``."""
    if len(preamble) != 2:
        return None
    names = _cells(preamble[0][1], sep)
    lower = [n.lower() for n in names]
    if "start" not in lower or "increment" not in lower:
        return None
    values = _cells(preamble[1][1], sep)
    at_start, at_step = lower.index("start"), lower.index("increment")
    if max(at_start, at_step) >= len(values) or not (_number(values[at_start]) is not None
                                                     and _positive(values[at_step])):
        return None
    channels = min(at_start, at_step)
    row = preamble[1][0]
    return Layout("Rigol DS1000Z", _skip(preamble, data), 2, sep, tuple(range(channels)),
                  tuple(names[:channels]), dict(zip(names[:channels], values[:channels])),
                  interval=Field(names[at_step], _number(values[at_step]), row))


def _units_row(preamble, sep: str, data) -> Layout | None:
    """A header row, then a row of units (Keysight ``second,Volt``, PicoScope ``(ms),(V)``)."""
    if len(preamble) != 2:
        return None
    names, units = (_filled(_cells(line, sep)) for _, line in preamble)
    if len(units) != len(names) or not (_TIME_HEADER.fullmatch(names[0].lower())
                                        or units[0].lower() in TIME_UNITS) \
            or not all(u.strip("()[] ").lower() in TIME_UNITS | VOLT_UNITS or
                       re.fullmatch(r"\(.*\)", u) for u in units):
        return None
    keysight = names[0].lower() == "x-axis"
    rigol = names[0] == "X" or any(re.fullmatch(r"X\(.+\)", n) for n in names[1:])
    names = [names[0]] + [_channel(n) for n in names[1:]]
    pico = all(u.startswith("(") for u in units)
    return Layout("Keysight InfiniiVision" if keysight else "PicoScope" if pico else
                  "Rigol DS1000E" if rigol else "header and units rows",
                  _skip(preamble, data), 2, sep,
                  tuple(range(len(names))), tuple(names), dict(zip(names, units)), marks=pico)


def _name_values(preamble, sep: str, data) -> Layout | None:
    """Rows ``name,value,…``, then a header row whose first cell is the time column."""
    names = _filled(_cells(preamble[-1][1], sep))
    if not _TIME_HEADER.fullmatch(names[0].lower()) or len(names) < 2:
        return None
    settings = {}
    for row, line in preamble[:-1]:
        cells = _filled(_cells(line, sep))
        if len(cells) > 1 and cells[0]:
            settings[cells[0].lower()] = (cells, row)
    if not settings:
        return None
    columns = names[1:]
    vertical = settings.get("vertical units", ([], 0))[0][1:]
    if all(c.lower() in set(VOLT_UNITS) | {"value"} for c in columns):  # Siglent's Second,Volt
        vertical = [c if c.lower() in VOLT_UNITS else "V" for c in columns]
        source = settings.get("source", ([], 0))[0][1:]
        columns = source if len(source) == len(columns) else \
            [f"CH{k}" for k in range(1, len(columns) + 1)]
    horizontal = settings.get("horizontal units", (["", "s"], 0))[0][1]
    names = [names[0]] + [_channel(c) for c in columns]
    units = {names[0]: horizontal}
    units.update((n, vertical[k] if k < len(vertical) and vertical[k] else "V")
                 for k, n in enumerate(names[1:]))
    return Layout("name–value header", _skip(preamble, data), len(preamble), sep,
                  tuple(range(len(names))), tuple(names), units,
                  interval=_field(settings, "sample interval", _positive),
                  length=_field(settings, "record length", _whole))


def _labview(lines, refuse: Refuse) -> Layout:
    """A LabVIEW Measurement file (NI's LVM, Writer_Version 2): the file's header, a
    segment's header (``Channels``, ``Samples``, ``Y_Unit_Label``, ``X0``, ``Delta_X``), each
    ending in ``***End_of_Header***``, the row of names (``X_Value``, the channels,
    ``Comment``), the rows; the time is a first column (``X_Columns One``) or ``X0 + k
    Delta_X`` (``X_Columns No``, the first cell left empty)."""
    sep = {"tab": "\t", "comma": ",", "semicolon": ";"}
    ends = [k for k, (_, line) in enumerate(lines) if line.strip().startswith(END_OF_HEADER)]
    head = {}
    for _, line in lines[:ends[0] if ends else len(lines)]:
        cells = _cells(line, "\t" if "\t" in line else ",")
        head[cells[0].lower()] = cells[1] if len(cells) > 1 else ""
    separator = sep.get(head.get("separator", "tab").lower(), "\t")
    columns = head.get("x_columns", "One").lower()
    if len(ends) < 2 or len(lines) <= ends[1] + 2:
        raise refuse("the LabVIEW Measurement file holds no segment of samples (a segment "
                     "header ending in ***End_of_Header***, a row of names, rows of numbers)",
                     "save the measurement again with Write To Measurement File, segment "
                     "headers on", ("в файле LabVIEW Measurement нет сегмента отсчётов",
                                    "сохраните измерение заново (Write To Measurement File) "
                                    "с заголовками сегментов"))
    if columns == "multi":
        raise refuse("the LabVIEW Measurement file has a time column for every channel "
                     "(X_Columns Multi)", "save it with X Value Columns: One column only (or "
                     "None)",
                     ("в файле LabVIEW Measurement столбец времени у каждого канала "
                      "(X_Columns Multi)", "сохраните его с X Value Columns: One column only "
                      "(или None)"))
    settings = {}
    for row, line in lines[ends[0] + 1:ends[1]]:
        cells = _cells(line, separator)
        settings[cells[0].lower()] = (cells, row)
    names_row, names_line = lines[ends[1] + 1]
    names = _filled(_cells(names_line, separator))
    if names and names[-1] == "Comment":
        names = names[:-1]
    count = len(names) - 1
    units = settings.get("y_unit_label", ([], 0))[0][1:]
    channels = [_channel(n) for n in names[1:]]
    unit_of = {n: units[k] if k < len(units) and units[k] else "V"
               for k, n in enumerate(channels)}
    timed = columns == "one"
    if timed:
        unit_of[names[0]] = "s"
    return Layout("LabVIEW Measurement", names_row, ends[1] + 2, separator,
                  tuple(range(count + 1)) if timed else tuple(range(1, count + 1)),
                  tuple(([names[0]] if timed else []) + channels), unit_of,
                  interval=_field(settings, "delta_x", _positive),
                  length=_field(settings, "samples", _whole), timed=timed,
                  end=END_OF_HEADER)


def _tektronix(lines) -> Layout | None:
    """TDS/TBS1000: settings in columns 1–2 beside the data in columns 4–5 of every row."""
    line = lines[0][1]
    sep = _separator(line)
    cells = _cells(line, sep)
    if cells[0].lower() != "record length" or len(cells) < 5 or not _numbers(sep.join(cells[3:5])):
        return None
    settings = {}
    for row, line in lines:
        cells = _cells(line, sep)
        if cells[0] and len(cells) > 1:
            settings[cells[0].lower()] = (cells, row)
    source = settings.get("source", (["", "CH1"], 0))[0][1] or "CH1"
    units = {"TIME": settings.get("horizontal units", (["", "s"], 0))[0][1],
             source: settings.get("vertical units", (["", "V"], 0))[0][1]}
    return Layout("Tektronix TDS/TBS", lines[0][0] - 1, 0, sep, (3, 4), ("TIME", source), units,
                  interval=_field(settings, "sample interval", _positive),
                  length=_field(settings, "record length", _whole))


def _settings_only(preamble, sep: str) -> bool:
    """Whether rows without a number are an instrument's settings (a header saved alone)."""
    return any(_cells(line, sep)[0].lower() in SETTINGS for _, line in preamble)


def _field(settings: dict, key: str, valid) -> Field | None:
    """A setting's number (``Sample Interval,2e-05``; Siglent's ``Record Length,Analog:1400``)."""
    cells, row = settings.get(key, ([], 0))
    value = cells[1].rpartition(":")[2] if len(cells) > 1 else ""
    if not valid(value):
        return None
    return Field(cells[0], _number(value), row)


def _filled(cells: list[str]) -> list[str]:
    """The cells without the empty ones a trailing separator leaves."""
    while cells and not cells[-1]:
        cells = cells[:-1]
    return cells


def _channel(name: str) -> str:
    """A channel's name as the instrument calls it: Keysight's ``1`` → ``CH1``, an older
    Rigol's ``X(CH1)`` → ``CH1``."""
    inner = re.fullmatch(r"X\((.+)\)", name)
    name = inner.group(1) if inner else name
    return f"CH{name}" if name.isdigit() else name


def _skip(preamble, data) -> int:
    """The file's lines before the first row of numbers (after the preamble)."""
    return (data[0] if data else preamble[-1][0] + 1) - 1


def _separator(line: str) -> str:
    return next((s for s in (";", "\t") if s in line), ",")


def _cells(line: str, sep: str) -> list[str]:
    return [c.strip(" \"'\r\n") for c in line.split(sep)]


def _number(cell: str) -> float | None:
    try:
        value = float(cell.strip(" \"'").replace(",", "."))
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def _positive(cell: str) -> bool:
    value = _number(cell)
    return value is not None and value > 0


def _whole(cell: str) -> bool:
    value = _number(cell)
    return value is not None and value >= 1 and value.is_integer()


def _numbers(line: str) -> bool:
    """Whether every non-empty cell of a row is a number or an over-range mark (and one is)."""
    cells = [c for c in _cells(line, _separator(line)) if c]
    return bool(cells) and all(c in OVER or _number(c) is not None for c in cells)
