"""Measurement files: declared inputs, TOML parsing to SI, validation, blank templates.

A lab declares its inputs as :class:`Section` s of :class:`Field` s (name = the manual's
symbol, the unit a plain number is read in, labels, the instrument's default limit of error).
:func:`load` reads a student's TOML file against that declaration and returns
:class:`Inputs`: every quantity converted to SI as a
:class:`~processing.uncertainty.Measured`. Anything wrong raises
:class:`~processing.diagnostics.InputError` naming the file, the field and the fix.

File format (ARCHITECTURE.md, "Measurement file")::

    lab = "lab1"
    [meta]
    student = "A. Ivanov"
    [trifilar]
    l = "850 mm ± 0.5 mm"          # a string with a unit, optionally a ± limit
    R1 = 120.0                     # a number in the unit the field declares (mm)
    t = [24.31, 24.28, 24.40]      # repeated readings: mean and type A uncertainty
    m = { value = "5432 g", limit = "1 g" }   # or a table: value/readings, unit, limit, u
"""
from __future__ import annotations

import contextlib
import difflib
import math
import os
import re
import tomllib
import warnings
from collections import defaultdict
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, NamedTuple

from .decimal_comma import decode_error, split_reading
from .diagnostics import (ImplausibleValueWarning, InputError, SingleReadingWarning,
                          TextTruncatedWarning)
from .files import MEASUREMENT, read_bytes, resolved, unicode_text
from .uncertainty import Measured
from .units import (QuantityError, likely_slip, magnitude_verdict, number_to_si,
                    parse_quantity, read_quantity, si_factor, si_unit, unit_text)

def bi(en: str, ru: str) -> dict[str, str]:
    """A text in English and Russian."""
    return {"en": en, "ru": ru}


# Field presets for the manual's usual instruments (lab 1: "mass to ±1 g, lengths to ±0.5 mm";
# a stopwatch reads to 0.01 s; an amplitude is judged by eye against a scale to about 1°),
# with what they measure on the manual's benches: parts of an engine weighed on the lab's
# scales, lengths of its parts and rigs, times of 1–50 swings of 0.5–10 s, swings of a few
# degrees (the methods want 5–10°), the local gravity.
MASS = dict(unit="kg", limit="1 g", plausible=("10 g", "50 kg"))
LENGTH = dict(unit="mm", limit="0.5 mm", plausible=("1 mm", "2000 mm"))
STOPWATCH = dict(unit="s", limit="0.01 s", repeated=True, plausible=("0.5 s", "600 s"))
AMPLITUDE = dict(unit="deg", limit="1 deg", required=False, symbol="θ₀", maximum="90 deg",
                 plausible=("0.5 deg", "45 deg"))
COUNT = dict(kind="count", symbol="n")
GRAVITY = dict(unit="m/s^2", default="9.81 ± 0.02 m/s^2", plausible=("9.7 m/s^2", "9.9 m/s^2"))
# An engine running on a test bed, by its tachometer (idle to the fastest petrol engine); a
# recorder's or an ADC's sample rate (a sound card's 8 kHz to a fast card's few MHz).
ENGINE_SPEED = dict(unit="rpm", plausible=("200 rpm", "10000 rpm"))
SAMPLE_RATE = dict(unit="kHz", plausible=("1 kHz", "10000 kHz"))
# The period of an oscillograph's time marks (a timer's 0.1 ms to a second).
MARK_PERIOD = dict(unit="ms", plausible=("0.1 ms", "1000 ms"))
# An engine's strokes per cycle: a four-stroke or a two-stroke.
STROKES = dict(kind="count", default=4, symbol="τ", choices=(4, 2))

MAX_READINGS = 1000
"""Most repeated readings one field takes; longer series belong in a recording (CSV)."""

MAX_TEXT = 2000
"""Longest text (notes, names) carried into a report [characters]; longer text is cut."""

META_KEYS = ("student", "id", "group", "date", "rig", "teacher", "university", "department",
             "notes")
"""The keys of [meta]: who and where (``id``: the student's id of the class roster)."""
_TABLE_KEYS = ("value", "readings", "unit", "limit", "u")


@dataclass(frozen=True)
class Field:
    """One input of a lab, as the manual names it.

    Parameters
    ----------
    name : str
        Key in the measurement file: the manual's symbol in ASCII (``R1``, ``l_CD``, ``t``).
    label : dict
        ``{"en": ..., "ru": ...}``, what the quantity is.
    unit : str, optional
        Unit of a plain number in the file (the manual's unit: ``mm``, ``g``, ``s``); None for
        counts, choices and text.
    symbol : str
        How the report prints it (``R₁``); defaults to ``name``.
    limit : str, optional
        The usual instrument's limit of error ("0.5 mm"), used when the file gives none.
    kind : {"quantity", "count", "choice", "text", "flag", "file", "region"}
        A ``file`` is a path relative to the measurement file (a recording, an image); it
        is read as a :class:`~pathlib.Path` resolved against the file's folder. A
        ``region`` is a rectangle of a picture, [x, y, w, h] in its pixels (a tuple).
    required : bool
        Must be present (within its section).
    default : optional
        Value used when absent (a number in ``unit`` or a string with a unit).
    repeated : bool
        Whether repeated readings (an array) are expected, e.g. stopwatch times.
    allow_zero : bool
        Quantities must be > 0 unless this is set (then ≥ 0).
    choices : tuple of str, or dict
        Allowed values of a ``choice``; a dict gives each its words for a report
        (``{"in": {"en": "inlet", "ru": "впускной"}}``). A ``count`` may name its allowed
        whole numbers the same way (``(4, 2)`` strokes per cycle).
    example : optional
        A typical value, shown in the template's comment.
    maximum : str, optional
        The largest value that makes physical sense ("90 deg" for a swing amplitude);
        larger values are refused.
    plausible : (str, str), optional
        The least and the greatest value the manual's bench measures (``("10 g", "50 kg")``
        for a part on the lab's scales). A reading outside warns (``implausible_value``),
        naming the unit slip that would put it inside (:func:`processing.units.likely_slip`);
        far outside what any bench measures (:data:`processing.units.PLAUSIBLE`) it is
        refused. Zero (where allowed) is not checked; a series, by its largest reading.
    series : bool
        An array is a series of distinct values, one per step (a calibration's loads, a
        chain's masses), not repeated readings of one quantity.
    """

    name: str
    label: Mapping[str, str]
    unit: str | None = None
    symbol: str = ""
    limit: str | None = None
    kind: str = "quantity"
    required: bool = True
    default: Any = None
    repeated: bool = False
    allow_zero: bool = False
    choices: tuple[str | int, ...] | Mapping[str, Mapping[str, str]] = ()
    example: Any = None
    maximum: str | None = None
    plausible: tuple[str, str] | None = None
    series: bool = False

    @property
    def display_symbol(self) -> str:
        return self.symbol or self.name


@dataclass(frozen=True)
class Section:
    """A table of the measurement file: one method or one measured object.

    ``many=True`` makes it an array of tables (``[[analytic]]``), one entry per part.
    """

    name: str
    label: Mapping[str, str]
    fields: tuple[Field, ...]
    required: bool = False
    many: bool = False
    help: Mapping[str, str] = field(default_factory=dict)

    def field(self, name: str) -> Field:
        return next(f for f in self.fields if f.name == name)


@dataclass(frozen=True)
class Column:
    """A column of a :class:`ReadingsTable`: a field of the table's section (its readings
    one per row, or its single value on every row, as written), or a quantity ``of`` the
    row's other cells (a period T = t/n), printed with ``digits`` significant figures.

    ``heading`` is ``{"en", "ru"}`` and names the unit the cells are in: the field's declared
    unit (the manual's)."""

    heading: Mapping[str, str]
    field: str = ""
    of: Callable[[Mapping[str, float]], float] | None = None
    digits: int = 4


@dataclass(frozen=True)
class ReadingsTable:
    """One of the manual's tables of readings, with the columns the manual prints: a row per
    run (the i-th reading of each repeated field of ``section``), or, for an array of tables
    (``[[reading]]``), a row per entry. A lab declares them in its :class:`LabSpec`; the
    report's measurements section draws them."""

    title: Mapping[str, str]
    section: str
    columns: tuple[Column, ...]
    run: Mapping[str, str] = field(default_factory=lambda: bi("Run", "Опыт"))

    def rows(self, entries: list[Mapping[str, Any]], spec: Section) -> list[dict]:
        """The table's rows: each column's text keyed by its heading's English, the run's
        number first (key ``"run"``). A column with nothing to show (its field given
        nowhere) is left out; there are no rows when no field of the table repeats."""
        values = [{c.field: _in_field_unit(spec.field(c.field), entry[c.field])
                   for c in self.columns if c.field and c.field in entry}
                  for entry in entries]
        if spec.many:
            cells = [{k: v[0] for k, v in row.items()} for row in values]
        else:
            count = max((len(v) for v in values[0].values()), default=0)
            cells = [{k: v[i] if len(v) == count else v[0] for k, v in values[0].items()
                      if len(v) in (1, count)} for i in range(count)]
        if len(cells) < 2:
            return []
        rows = [{"run": str(i), **{c.heading["en"]: self._text(c, row) for c in self.columns}}
                for i, row in enumerate(cells, 1)]
        shown = [c.heading["en"] for c in self.columns
                 if any(row[c.heading["en"]] != "—" for row in rows)]
        return [{k: row[k] for k in ("run", *shown)} for row in rows]

    @staticmethod
    def _text(c: Column, cells: Mapping[str, Any]) -> str:
        """One cell: a field's reading as written (``g``), a text or a choice's words as they
        are, a derived quantity to ``c.digits`` figures; "—" where there is none."""
        if c.of is None:
            x = cells.get(c.field, math.nan)
            return x if isinstance(x, (str, Mapping)) else f"{x:g}" if math.isfinite(x) else "—"
        x = c.of(defaultdict(lambda: math.nan, cells))
        return f"{x:#.{c.digits}g}".rstrip(".") if math.isfinite(x) else "—"


def period_columns(count: str, times: Mapping[str, str]) -> tuple[Column, ...]:
    """The manual's columns for timed oscillations: the count n, then for each stopwatch field
    of ``times`` (field → its symbol) the time t of n oscillations and the period T = t/n, in
    seconds (lab 1's and lab 2's tables: run, n, t, T)."""
    def period(time):
        return lambda cells: cells[time] / cells[count]

    cols = [Column(bi("n", "n"), count)]
    for time, symbol in times.items():
        sub = symbol[1:]
        cols += [Column(bi(f"{symbol}, s", f"{symbol}, с"), time),
                 Column(bi(f"T{sub} = {symbol}/n, s", f"T{sub} = {symbol}/n, с"),
                        of=period(time))]
    return tuple(cols)


def _in_field_unit(f: Field, v) -> list:
    """A field's readings (or its one value) in the field's declared unit; a count as a
    number, a choice in its words ({"en", "ru"}) where it has them, a text as it is."""
    if isinstance(v, Measured):
        k = si_factor(f.unit)
        return [r / k for r in v.readings] if len(v.readings) > 1 else [v.value / k]
    if isinstance(f.choices, Mapping) and v in f.choices:
        return [dict(f.choices[v])]
    return [v if isinstance(v, str) else float(v)]


@dataclass(frozen=True)
class LabSpec:
    """What a lab is and what it reads: id, number, titles, its sections and the manual's
    tables of readings the report shows (:class:`ReadingsTable`)."""

    id: str
    number: str
    title: Mapping[str, str]
    goal: Mapping[str, str]
    sections: tuple[Section, ...]
    readings: tuple[ReadingsTable, ...] = ()

    def section(self, name: str) -> Section:
        return next(s for s in self.sections if s.name == name)


def image_section(name: str = "image", *, zero_default: str | None = "mean",
                  zero_help: dict | None = None) -> Section:
    """The ``[image]`` table of a lab whose records may be photographs or scans of paper:
    how to read them (:func:`processing.vision.read_paper_records`), for every image the file
    names. The time base needs ``mark_period`` (or ``paper_speed`` with a length scale); a
    length scale (``paper_width``, ``grid`` or ``dpi``) gives the deflection in mm of paper.
    A lab that chooses the zero itself when the file does not say (``zero_default`` None:
    ``zero`` is then absent from the table) describes its choice in ``zero_help``.
    """
    return Section(name, bi("Reading photographed or scanned paper records",
                            "Считывание сфотографированных или отсканированных записей"), fields=(
        Field("mark_period", bi("period of the time marks", "период отметок времени"),
              **MARK_PERIOD, required=False, symbol="T_mark", example=1),
        Field("paper_speed", bi("speed of the paper (without time marks, or as a check)",
                                "скорость ленты (без отметок времени или для проверки)"),
              unit="mm/s", required=False, symbol="v_л", plausible=("1 mm/s", "10000 mm/s")),
        Field("paper_width", bi("width of the paper between its edges (both in the picture)",
                                "ширина ленты между краями (оба видны на снимке)"),
              unit="mm", limit="0.5 mm", required=False, symbol="b", example=120,
              plausible=("10 mm", "1000 mm")),
        Field("grid", bi("pitch of a printed grid", "шаг отпечатанной сетки"), unit="mm",
              required=False, plausible=("0.5 mm", "50 mm")),
        Field("dpi", bi("a flatbed scan's resolution, dots per inch",
                        "разрешение сканера, точек на дюйм"), unit="", required=False,
              plausible=("50", "10000")),
        Field("traces", bi("how many traces the sheet carries (default: as found)",
                           "сколько линий записи на ленте (по умолчанию — по снимку)"),
              kind="count", required=False),
        Field("zero", zero_help or bi("deflection from the trace's mean level or from its "
                                      "zero line", "отклонение от среднего уровня линии или "
                                      "от её нулевой линии"),
              kind="choice", default=zero_default,
              choices={"mean": bi("from the mean level", "от среднего уровня"),
                       "line": bi("from the zero line", "от нулевой линии")},
              required=False),
        Field("bridge", bi("longest gap in a trace to interpolate across",
                           "наибольший разрыв линии, заполняемый интерполяцией"),
              unit="ms", allow_zero=True, required=False, plausible=("0.01 ms", "1000 ms")),
    ))


def firing_order(inputs, field: str = "engine.firing_order") -> list[int] | None:
    """The cylinder numbers of a firing order written as text ("1-3-4-2", "1, 3, 4, 2"), or
    None where the file gives none; the order itself is checked where it is used
    (:func:`processing.crank.dynamics.firing_phases`)."""
    section, key = field.split(".")
    text = inputs.sections.get(section, {}).get(key)
    if text is None:
        return None
    parts = text.replace(",", "-").replace(" ", "").split("-")
    if not all(p.isdigit() for p in parts):
        raise inputs.error(f"firing order '{text}' is not a list of cylinder numbers",
                           "write it as 1-3-4-2", field,
                           ru=(f"порядок работы '{text}' — не список номеров цилиндров",
                               "запишите его как 1-3-4-2"))
    return [int(p) for p in parts]


@dataclass
class Inputs:
    """A validated measurement file: SI values ready for a lab's ``reduce``.

    ``inputs["trifilar"]["l"]`` is a :class:`Measured` (or an int, str); a ``many`` section
    is a list of such dicts. Absent optional sections are absent keys.
    """

    lab: str
    file: str
    meta: dict[str, str]
    sections: dict[str, Any]
    spec: LabSpec | None = None

    def __contains__(self, section: str) -> bool:
        return section in self.sections

    def __getitem__(self, section: str):
        return self.sections[section]

    def changed(self, section: str, **values) -> Inputs:
        """A copy with fields of ``section`` replaced (a value of None removes the field): the
        same measurements as a student who slipped would have used them."""
        entry = {k: v for k, v in {**self.sections[section], **values}.items()
                 if v is not None}
        return replace(self, sections={**self.sections, section: entry})

    def flat(self) -> dict[str, Any]:
        """Every value keyed ``section.field`` (``section[i].field`` in a ``many`` section),
        the keyword arguments of a lab's measurement model."""
        flat = {}
        for name, entry in self.sections.items():
            many = isinstance(entry, list)
            for i, e in enumerate(entry if many else [entry]):
                key = f"{name}[{i}]" if many else name
                flat.update({f"{key}.{k}": v for k, v in e.items()})
        return flat

    def readings(self) -> list[tuple[ReadingsTable, list[dict]]]:
        """The manual's tables of readings the lab declares (:attr:`LabSpec.readings`), each
        with its rows for every entry of its section the file has."""
        out = []
        for table in self.spec.readings if self.spec else ():
            entries = self.sections.get(table.section)
            if entries is not None:
                rows = table.rows(entries if isinstance(entries, list) else [entries],
                                  self.spec.section(table.section))
                out += [(table, rows)] if rows else []
        return out

    def rows(self) -> list[dict]:
        """The measured inputs as report rows, each in its field's declared unit."""
        rows = []
        for sec in self.spec.sections:
            entries = self.sections.get(sec.name)
            if entries is None:
                continue
            for i, entry in enumerate(entries if sec.many else [entries]):
                where = f"{sec.name}[{i}]" if sec.many else sec.name
                for f in sec.fields:
                    if f.name in entry:
                        v = entry[f.name]
                        if isinstance(v, Path):  # as written, relative to the file's folder
                            v = os.path.relpath(v, Path(self.file).parent)
                        rows.append(_row(where, sec, f, v))
        return rows

    def error(self, problem: str, fix: str, field: str,
              ru: tuple[str, str] | None = None) -> InputError:
        """An :class:`InputError` located in this file (``ru``: the problem and fix in
        Russian)."""
        return InputError(problem, fix, file=self.file, field=field, ru=ru)


def _row(where: str, sec: Section, f: Field, v) -> dict:
    row = {"section": where, "section_label": dict(sec.label), "name": f.name,
           "symbol": f.display_symbol, "label": dict(f.label)}
    if isinstance(v, Measured) and f.series and len(v.readings) > 1:
        k = si_factor(f.unit)   # a programme of steps: its steps, not their mean ± u
        row.update(unit=f.unit, series=True, readings=[r / k for r in v.readings],
                   si={"unit": si_unit(f.unit), "readings": list(v.readings)})
    elif isinstance(v, Measured):
        k = si_factor(f.unit)
        row.update(value=v.value / k, u=v.u / k, unit=f.unit,
                   readings=[r / k for r in v.readings] if len(v.readings) > 1 else [],
                   si={"value": v.value, "u": v.u, "unit": si_unit(f.unit),
                       "readings": list(v.readings) if len(v.readings) > 1 else []})
    else:
        row.update(value=v, unit="")
        if isinstance(f.choices, Mapping) and v in f.choices:
            row["value_label"] = dict(f.choices[v])
    return row


class TomlDocument(dict):
    """A parsed measurement file, and the ``text`` it was parsed from (for the messages that
    show a line of it)."""

    def __init__(self, data: dict, text: str):
        super().__init__(data)
        self.text = text


def measurement_text(raw: bytes) -> str | None:
    """A measurement file's text as a student's editor saved it: UTF-8 (a byte-order mark
    dropped), UTF-16 with its byte-order mark (Notepad's "Unicode"), or Windows-1251 (an
    older Russian Notepad's "ANSI") where that reads as TOML; None for anything else."""
    with contextlib.suppress(UnicodeDecodeError):
        return unicode_text(raw)
    try:
        text = raw.decode("cp1251")
        tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError):
        return None
    return text


def read_toml(path: str | Path) -> TomlDocument:
    """Read a TOML measurement file (a regular file of at most 1 MiB,
    :data:`processing.files.MEASUREMENT`, in an encoding :func:`measurement_text` reads),
    turning every failure into an :class:`InputError` (a
    decimal comma outside quotes named as such, with its line: :mod:`processing.decimal_comma`)."""
    path = Path(path)
    text = measurement_text(read_bytes(path, MEASUREMENT))
    if text is None:
        raise InputError("not a text file in UTF-8, UTF-16 or Windows-1251",
                         "give a TOML measurement file saved as UTF-8 text (Notepad: Save as, "
                         "Encoding UTF-8); 'dynlab template LAB' writes one",
                         file=str(path), ru=("не текстовый файл в UTF-8, UTF-16 или "
                                             "Windows-1251",
                                             "укажите файл измерений TOML, сохранённый как "
                                             "текст UTF-8 (Блокнот: Сохранить как, Кодировка "
                                             "UTF-8); его заготовку пишет 'dynlab template "
                                             "LAB'"))
    try:
        return TomlDocument(tomllib.loads(text), text)
    except tomllib.TOMLDecodeError as exc:
        found = decode_error(text, str(exc))
        if found is not None:
            split, field = found
            raise InputError(split.problem("a decimal comma outside quotes: TOML takes a "
                                           "comma for the separator between values, so the "
                                           "file does not parse"), split.fix(),
                             file=str(path), field=field,
                             ru=(split.problem("десятичная запятая вне кавычек: в TOML запятая "
                                               "разделяет значения, и файл не читается", "ru"),
                                 split.fix("ru"))) from None
        raise InputError(f"not a valid TOML file ({exc})",
                         "correct the syntax: key = value, strings in quotes, "
                         "arrays in [ ]; compare with 'dynlab template LAB'",
                         file=str(path),
                         ru=(f"файл не по правилам TOML{toml_place(str(exc))}",
                             "исправьте запись: ключ = значение, строки в кавычках, массивы в "
                             "[ ]; сравните с 'dynlab template LAB'")) from None


def toml_place(message: str) -> str:
    """Where a TOML parser's (English) message places the fault, in Russian: " (строка 2,
    столбец 6)", or nothing.

    >>> toml_place("Expected ']' (at line 2, column 6)"), toml_place("Invalid value")
    (' (строка 2, столбец 6)', '')
    """
    found = re.search(r"line (\d+), column (\d+)", message)
    return f" (строка {found[1]}, столбец {found[2]})" if found else ""


def _did_you_mean(word: str, options, lang: str = "en") -> str:
    close = difflib.get_close_matches(word, list(options), n=1, cutoff=0.5)
    if lang == "ru":
        return f"вы имели в виду '{close[0]}'?" if close else \
            f"известные ключи: {', '.join(options)}"
    return f"did you mean '{close[0]}'?" if close else f"known keys: {', '.join(options)}"


def _unknown_key(key: str, where: str, where_ru: str,
                 options) -> tuple[str, str, tuple[str, str]]:
    """The problem, the fix and their Russian of an unknown ``key`` in ``where``."""
    return (f"unknown key '{key}' in {where}", _did_you_mean(key, options),
            (f"неизвестный ключ '{key}' в {where_ru}", _did_you_mean(key, options, "ru")))


def load(path: str | Path, spec: LabSpec, data: dict | None = None, *,
         confine: bool = False) -> Inputs:
    """Read and validate a measurement file for the lab ``spec``.

    Parameters
    ----------
    path : str or Path
        The TOML file (used in messages even when ``data`` is given).
    spec : LabSpec
        The lab's declaration.
    data : dict, optional
        The already-parsed TOML document.
    confine : bool
        Keep every file the measurement names inside the measurement file's folder (a
        teacher checking a class folder: one submission may not read another's data).

    Raises
    ------
    InputError
        Unknown or missing key, wrong unit, non-positive length, empty array, ...
    """
    file = str(path)
    data = read_toml(path) if data is None else data
    unknown = set(data) - {"lab", "meta"} - {s.name for s in spec.sections}
    for key in sorted(unknown):
        options = ["lab", "meta"] + [s.name for s in spec.sections]
        raise InputError(f"unknown section or key '{key}'", _did_you_mean(key, options),
                         file=file, field=key,
                         ru=(f"неизвестный раздел или ключ '{key}'",
                             _did_you_mean(key, options, "ru")))
    meta = _load_meta(data.get("meta", {}), file)
    folder = Path(path).parent
    where = _Where(file, folder, folder.resolve() if confine else None,
                   getattr(data, "text", None))
    sections: dict[str, Any] = {}
    for sec in spec.sections:
        raw = data.get(sec.name)
        if raw is None:
            if sec.required:
                raise InputError(f"section [{sec.name}] is missing",
                                 f"add the section [{sec.name}] ({sec.label['en']}); "
                                 f"'dynlab template {spec.id}' shows its fields", file=file,
                                 field=sec.name,
                                 ru=(f"нет раздела [{sec.name}]",
                                     f"добавьте раздел [{sec.name}] ({sec.label['ru']}); его "
                                     f"поля показывает 'dynlab template {spec.id}'"))
            continue
        if sec.many:
            if isinstance(raw, dict):
                raw = [raw]
            if not isinstance(raw, list) or not raw or not all(isinstance(r, dict) for r in raw):
                raise InputError(f"[[{sec.name}]] must be one or more tables",
                                 f"write each entry as a [[{sec.name}]] table", file=file,
                                 field=sec.name,
                                 ru=(f"[[{sec.name}]] — это одна или несколько таблиц",
                                     f"запишите каждую запись таблицей [[{sec.name}]]"))
            sections[sec.name] = [_load_section(sec, r, where, f"{sec.name}[{i}]")
                                  for i, r in enumerate(raw)]
        else:
            if not isinstance(raw, dict):
                raise InputError(f"'{sec.name}' must be a table [{sec.name}]",
                                 f"write the values under a line [{sec.name}]", file=file,
                                 field=sec.name,
                                 ru=(f"'{sec.name}' должен быть таблицей [{sec.name}]",
                                     f"запишите значения под строкой [{sec.name}]"))
            sections[sec.name] = _load_section(sec, raw, where, sec.name)
    return Inputs(spec.id, file, meta, sections, spec)


def _load_meta(raw, file: str) -> dict[str, str]:
    if not isinstance(raw, dict):
        raise InputError("[meta] must be a table", "write student, group, date under [meta]",
                         file=file, field="meta",
                         ru=("[meta] должен быть таблицей",
                             "запишите student, group, date под строкой [meta]"))
    for key in raw:
        if key not in META_KEYS:
            problem, fix, ru = _unknown_key(key, "[meta]", "[meta]", META_KEYS)
            raise InputError(problem, fix, file=file, field=f"meta.{key}", ru=ru)
    return {k: _short_text(str(v), f"meta.{k}") for k, v in raw.items()}


def _short_text(text: str, where: str) -> str:
    """``text``, cut to :data:`MAX_TEXT` characters with a warning if longer."""
    if len(text) <= MAX_TEXT:
        return text
    warnings.warn(TextTruncatedWarning(
        f"'{where}' holds {len(text)} characters; the report shows the first {MAX_TEXT}",
        f"'{where}' содержит {len(text)} символов; в отчёт вошли первые {MAX_TEXT}"))
    return text[:MAX_TEXT] + " …"


@dataclass(frozen=True)
class _Where:
    """The measurement file, its folder, the folder files must stay in (or None), and its
    text (None for a document given already parsed)."""

    file: str
    folder: Path
    root: Path | None
    text: str | None = None


def _load_section(sec: Section, raw: dict, src: _Where, where: str) -> dict:
    file = src.file
    names = [f.name for f in sec.fields]
    for key in raw:
        if key not in names:
            problem, fix, ru = _unknown_key(key, f"[{sec.name}]", f"[{sec.name}]", names)
            raise InputError(problem, fix, file=file, field=f"{where}.{key}", ru=ru)
    out = {}
    for f in sec.fields:
        path = f"{where}.{f.name}"
        if f.name not in raw:
            if f.default is not None:
                out[f.name] = _convert(f, f.default, src, path)
            elif f.required:
                raise InputError(f"'{f.name}' ({f.label['en']}) is missing",
                                 f"add a line {f.name} = ... in [{sec.name}]"
                                 + (f", in {f.unit}" if f.unit else ""), file=file, field=path,
                                 ru=(f"нет '{f.name}' ({f.label['ru']})",
                                     f"добавьте строку {f.name} = ... в [{sec.name}]"
                                     + (f", в {unit_text(f.unit, 'ru')}" if f.unit else "")))
            continue
        out[f.name] = _convert(f, raw[f.name], src, path)
    return out


def _convert(f: Field, raw, src: _Where, path: str):
    def fail(problem, fix, ru=None):
        return InputError(problem, fix, file=src.file, field=path, ru=ru)

    if raw == "" or raw == []:
        raise fail(f"'{f.name}' ({f.label['en']}) is empty",
                   "fill in the value you measured" + (f" (in {f.unit}, or a string like "
                                                       f"'12.5 {f.unit}')" if f.unit else ""),
                   ru=(f"'{f.name}' ({f.label['ru']}) не заполнено",
                       "впишите измеренное значение" + (
                           f" (в {unit_text(f.unit, 'ru')} или строкой вида "
                           f"'12,5 {unit_text(f.unit, 'ru')}')" if f.unit else "")))
    if f.kind == "text":
        return _short_text(str(raw), path)
    if f.kind == "file":
        return _file(f, raw, src, fail)
    if f.kind == "region":
        return _region(f, raw, fail)
    if f.kind == "flag":
        if not isinstance(raw, bool):
            raise fail(f"'{f.name}' must be true or false, got {raw!r}", "write true or false",
                       ru=(f"'{f.name}' — это true или false, а не {raw!r}",
                           "напишите true или false"))
        return raw
    if f.kind == "choice":
        if raw not in f.choices:
            raise fail(f"'{raw}' is not one of {', '.join(f.choices)}",
                       _did_you_mean(str(raw), f.choices),
                       ru=(f"'{raw}' — не из списка {', '.join(f.choices)}",
                           _did_you_mean(str(raw), f.choices, "ru")))
        return raw
    if f.kind == "count":
        least = 0 if f.allow_zero else 1
        if isinstance(raw, bool) or not isinstance(raw, int) or raw < least:
            raise fail(f"'{f.name}' must be a whole number ≥ {least}, got {raw!r}",
                       "write the count as a whole number, e.g. 20",
                       ru=(f"'{f.name}' должно быть целым числом ≥ {least}, а не {raw!r}",
                           "запишите число целым, например 20"))
        if f.choices and raw not in f.choices:
            allowed, allowed_ru = (word.join(map(str, f.choices)) for word in (" or ", " или "))
            raise fail(f"{f.name} = {raw}: {f.label['en']} can only be {allowed}",
                       f"write {allowed}",
                       ru=(f"{f.name} = {raw}: {f.label['ru']} может быть только {allowed_ru}",
                           f"напишите {allowed_ru}"))
        return raw
    return _measured(f, raw, fail, src, path)


def _region(f: Field, raw, fail) -> tuple[float, float, float, float]:
    """A rectangle of a picture, [x, y, w, h] in its pixels: the left and top edges from the
    picture's top left corner, the width and the height."""
    numbers = isinstance(raw, list) and len(raw) == 4 and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
        for v in raw)
    if not numbers or raw[0] < 0 or raw[1] < 0 or raw[2] <= 0 or raw[3] <= 0:
        raise fail(f"'{f.name}' must be four numbers [x, y, w, h] in pixels (x, y ≥ 0 from "
                   f"the picture's top left corner, w, h > 0), got {raw!r}",
                   f"write e.g. {f.name} = [420, 610, 80, 80]: where the marker is in the "
                   "first frame, as an image viewer shows its pixels",
                   ru=(f"'{f.name}' — это четыре числа [x, y, w, h] в пикселях (x, y ≥ 0 от "
                       f"левого верхнего угла кадра, w, h > 0), а не {raw!r}",
                       f"напишите, например, {f.name} = [420, 610, 80, 80]: где метка на "
                       "первом кадре, в пикселях, как их показывает просмотрщик изображений"))
    return tuple(float(v) for v in raw)


def _file(f: Field, raw, src: _Where, fail) -> Path:
    """A file named by the measurement, resolved against its folder (and kept in it)."""
    if not isinstance(raw, str):
        raise fail(f"'{f.name}' must be a file name in quotes, got {raw!r}",
                   f"write e.g. {f.name} = \"record.csv\" (relative to this file's folder)",
                   ru=(f"'{f.name}' — это имя файла в кавычках, а не {raw!r}",
                       f"напишите, например, {f.name} = \"record.csv\" (относительно папки "
                       f"этого файла)"))
    target = src.folder / os.path.expanduser(raw)
    if src.root is not None and not resolved(target).is_relative_to(src.root):
        raise fail(f"'{raw}' lies outside the submission's folder {src.root}",
                   "copy the file into the folder of the measurement file and name it "
                   "relative to it (files outside are not read in confined mode)",
                   ru=(f"'{raw}' лежит вне папки работы {src.root}",
                       "скопируйте файл в папку файла измерений и укажите его относительно "
                       "неё (при проверке группы файлы вне её не читаются)"))
    return target


_WHAT_RU = {"value": "значение", "limit": "предел погрешности", "u": "неопределённость u"}
"""The part of a value a message names (``what`` of :func:`_scalar`), in Russian."""


class _Reading(NamedTuple):
    """One reading of a field: SI value and ± limit, and the number and unit as written."""

    value: float
    limit: float | None
    number: float
    unit: str


def _measured(f: Field, raw, fail, src: _Where, path: str) -> Measured:
    limit = u_b = None
    if isinstance(raw, dict):
        for key in raw:
            if key not in _TABLE_KEYS:
                problem, fix, ru = _unknown_key(key, f"the table of '{f.name}'",
                                                f"таблице '{f.name}'", _TABLE_KEYS)
                raise fail(problem, fix, ru=ru)
        if ("value" in raw) == ("readings" in raw):
            raise fail(f"the table of '{f.name}' needs exactly one of 'value' or 'readings'",
                       "write { value = ... } for one reading or { readings = [...] } for repeats",
                       ru=(f"в таблице '{f.name}' нужен ровно один из ключей 'value' или "
                           f"'readings'", "напишите { value = ... } для одного отсчёта или "
                           "{ readings = [...] } для повторных"))
        unit = _table_unit(f, raw["unit"], fail) if "unit" in raw else f.unit
        body = raw.get("value", raw.get("readings"))
        if "limit" in raw:
            limit = _scalar(f, raw["limit"], unit, fail, what="limit", allow_zero=True).value
        if "u" in raw:
            u_b = _scalar(f, raw["u"], unit, fail, what="u", allow_zero=True).value
    else:
        unit, body = f.unit, raw
    if isinstance(body, list):
        if not body:
            raise fail(f"'{f.name}' has an empty list of readings", "write at least one reading",
                       ru=(f"у '{f.name}' пустой список отсчётов",
                           "запишите хотя бы один отсчёт"))
        if len(body) > MAX_READINGS:
            raise fail(f"'{f.name}' has {len(body)} readings; at most {MAX_READINGS} are taken",
                       "repeat a reading a few times (the manual asks for three); a long "
                       "series belongs in a recording file",
                       ru=(f"у '{f.name}' {len(body)} отсчётов; принимается не более "
                           f"{MAX_READINGS}", "повторите отсчёт несколько раз (методика "
                           "требует трёх); длинный ряд — это файл записи"))
        _refuse_split(f, body, src, fail)
        readings = [_scalar(f, b, unit, fail) for b in body]
        limits = [r.limit for r in readings if r.limit is not None]
        limit = limit if limit is not None else (max(limits) if limits else None)
    else:
        readings = [_scalar(f, body, unit, fail)]
        limit = limit if limit is not None else readings[0].limit
    _check_range(f, readings, path)
    if limit is None and u_b is None and f.limit is not None:
        limit = parse_quantity(f.limit, f.unit)[0]
    if len(readings) == 1 and f.repeated:
        warnings.warn(SingleReadingWarning(
            f"'{f.name}' ({f.label['en']}) was read once: its scatter is unknown and only the "
            f"instrument's limit enters its uncertainty; repeat the reading (the manual asks "
            f"for three repeats)",
            f"'{f.name}' ({f.label['ru']}) измерено один раз: разброс неизвестен, в "
            f"погрешность вошла только погрешность прибора; повторите опыт (методика требует "
            f"трёх повторений)"))
    return Measured.from_readings([r.value for r in readings], limit=limit or 0.0,
                                  u_b=u_b or 0.0)


def _refuse_split(f: Field, body: list, src: _Where, fail) -> None:
    """Refuse readings that TOML split at decimal commas (:mod:`processing.decimal_comma`),
    showing the line of the file."""
    split = None if src.text is None else split_reading(src.text, f.name, body,
                                                        series=f.series)
    if split is None:
        return
    shown = ", ".join(str(v) for v in body[:8]) + (", …" if len(body) > 8 else "")
    meant = ", ".join(f"{r:g}" for r in split.readings)
    raise fail(split.problem(f"a decimal comma outside quotes: TOML takes a comma for a "
                             f"separator, so '{f.name}' holds {len(body)} numbers "
                             f"({shown}), not the readings {meant}"), split.fix(),
               ru=(split.problem(f"десятичная запятая вне кавычек: в TOML запятая разделяет "
                                 f"значения, и в '{f.name}' {len(body)} чисел ({shown}), а не "
                                 f"отсчёты {meant}", "ru"), split.fix("ru")))


def _table_unit(f: Field, unit, fail) -> str:
    """The ``unit`` of a value table, checked: a known unit of the field's dimension."""
    from .units import _dimension_name, ureg

    fix = f"write the unit of {f.label['en']}, e.g. unit = \"{f.unit}\""
    fix_ru = f"укажите единицу величины «{f.label['ru']}», например unit = \"{f.unit}\""
    try:
        dim = ureg.Quantity(1.0, unit).dimensionality if isinstance(unit, str) else None
    except Exception:
        dim = None
    if dim is None:
        raise fail(f"unit {unit!r} of '{f.name}' is not known", fix,
                   ru=(f"единица {unit!r} у '{f.name}' неизвестна", fix_ru))
    want = ureg.Quantity(1.0, f.unit).dimensionality
    if dim != want:
        raise fail(f"unit {unit!r} of '{f.name}' is {_dimension_name(dim)}, but "
                   f"{_dimension_name(want)} is expected (unit like '{f.unit}')", fix,
                   ru=(f"единица {unit!r} у '{f.name}' — {_dimension_name(dim, 'ru')}, а ожидается "
                       f"{_dimension_name(want, 'ru')} (единица вроде '{f.unit}')", fix_ru))
    return unit


def _scalar(f: Field, raw, unit, fail, *, what: str = "value",
            allow_zero: bool | None = None) -> _Reading:
    allow_zero = f.allow_zero if allow_zero is None else allow_zero
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        raise fail(f"the {what} of '{f.name}' must be a number or a string with a unit, "
                   f"got {raw!r}", f"write e.g. {f.name} = \"12.5 {f.unit}\"",
                   ru=(f"{_WHAT_RU[what]} '{f.name}' — это число или строка с единицей, а не "
                       f"{raw!r}", f"напишите, например, {f.name} = \"12,5 {f.unit}\""))
    if isinstance(raw, str):
        try:
            value, limit, written = read_quantity(raw, unit)
        except QuantityError as exc:
            fix_ru = exc.fix_ru or (f"напишите число и единицу величины «{f.label['ru']}», "
                                    f"например \"12,5 {f.unit}\"")
            raise fail(str(exc), exc.fix or f"write a number and a unit of {f.label['en']}, "
                                            f"e.g. \"12.5 {f.unit}\"",
                       ru=(exc.problem_ru, fix_ru) if exc.problem_ru else None) from None
        number = value / number_to_si(1.0, written, f.unit)
    else:
        number, limit, written = float(raw), None, unit
        value = number_to_si(number, unit, f.unit)
    if not math.isfinite(value):
        raise fail(f"the {what} of '{f.name}' is not a finite number ({raw!r})",
                   "write the number you read",
                   ru=(f"{_WHAT_RU[what]} '{f.name}' — не конечное число ({raw!r})",
                       "запишите число, которое вы прочли"))
    _check_magnitude(f, value, raw, unit, fail, what)
    if value < 0 or (value == 0 and not allow_zero):
        bound = "≥ 0" if allow_zero else "> 0"
        raise fail(f"'{f.name}' ({f.label['en']}) must be {bound}, got {raw!r}",
                   "check the sign and the reading" if value < 0 else
                   "a zero reading cannot be right here: check the value",
                   ru=(f"'{f.name}' ({f.label['ru']}) должно быть {bound}, а не {raw!r}",
                       "проверьте знак и отсчёт" if value < 0 else
                       "нулевой отсчёт здесь невозможен: проверьте значение"))
    return _Reading(value, limit, number, written)


def _check_magnitude(f: Field, value: float, raw, unit: str, fail, what: str) -> None:
    """Refuse a value no bench can measure; warn about one outside the plausible range of its
    dimension where the field declares none of its own (that is checked per field:
    :func:`_check_range`)."""
    if f.maximum is not None and what == "value":
        top = parse_quantity(f.maximum, f.unit)[0]
        if value > top:
            raise fail(f"'{f.name}' ({f.label['en']}) is {raw!r}, above {f.maximum}, "
                       f"where the method makes no sense",
                       f"check the reading and its unit (the value must stay below {f.maximum})",
                       ru=(f"'{f.name}' ({f.label['ru']}) = {raw!r}, больше {f.maximum}, где "
                           f"метод теряет смысл", f"проверьте отсчёт и его единицу (значение "
                           f"должно быть меньше {f.maximum})"))
    verdict, plausible = magnitude_verdict(value, unit)
    if verdict == "ok" or (verdict == "suspect" and f.plausible and what == "value"):
        return
    k = si_factor(unit)
    shown = (f"{plausible[0] / k:.3g} to {plausible[1] / k:.3g} {unit}" if plausible
             else "any measurable size")
    if verdict == "refused":
        shown_ru = (f"от {plausible[0] / k:.3g} до {plausible[1] / k:.3g} {unit_text(unit, 'ru')}"
                    if plausible else "любая измеримая величина")
        raise fail(f"the {what} of '{f.name}' ({f.label['en']}) is {raw!r}, far outside what a "
                   f"lab bench measures ({shown})", f"check the number, its exponent and its "
                   f"unit (the unit of a plain number here is {unit})",
                   ru=(f"{_WHAT_RU[what]} '{f.name}' ({f.label['ru']}) = {raw!r}, далеко за "
                       f"пределами того, что измеряют на стенде ({shown_ru})",
                       f"проверьте число, его порядок и единицу (единица числа без единицы "
                       f"здесь — {unit_text(unit, 'ru')})"))
    warnings.warn(ImplausibleValueWarning(
        f"'{f.name}' ({f.label['en']}) = {raw!r} lies outside the usual {shown}: check the "
        f"number and its unit",
        f"'{f.name}' ({f.label['ru']}) = {raw!r} вне обычного диапазона {shown}: проверьте "
        f"число и единицы"))


def plausible_range(f: Field) -> tuple[float, float]:
    """The field's :attr:`~Field.plausible` range in SI."""
    return tuple(parse_quantity(x, f.unit)[0] for x in f.plausible)


def _check_range(f: Field, readings: list[_Reading], path: str) -> None:
    """Warn once about the field's readings outside the range its bench measures, naming
    the unit slip that would bring the farthest of them inside. A series (a calibration
    from zero, a loop back to it) is judged by its largest reading: its small ones near
    zero are no slip."""
    if f.plausible is None:
        return
    least, greatest = plausible_range(f)
    if f.series:
        readings = [max(readings, key=lambda r: r.value)]
    outside = [r for r in readings if r.value and not least <= r.value <= greatest]
    if not outside:
        return
    worst = max(outside, key=lambda r: abs(math.log(r.value / math.sqrt(least * greatest))))
    k = si_factor(f.unit)
    text = {}
    for lang in ("en", "ru"):
        got = f"{_number(worst.number)} {unit_text(worst.unit, lang)}".rstrip()
        more = len(outside) - 1
        if more:
            got += f" (and {more} more of its readings)" if lang == "en" else \
                f" (и ещё {more} отсчётов)"
        span = f"{_number(least / k)}–{_number(greatest / k)} {unit_text(f.unit, lang)}".rstrip()
        text[lang] = (f"'{path}' ({f.label[lang]}) = {got} lies outside {span}, what the "
                      f"manual's bench measures: " if lang == "en" else
                      f"'{path}' ({f.label[lang]}) = {got} вне диапазона {span}, измеряемого "
                      f"на стенде методички: ") + _slip_text(f, worst, least, greatest, lang)
    warnings.warn(ImplausibleValueWarning(text["en"], text["ru"]))


def _number(x: float) -> str:
    """A range's bound as a person writes it: 10000, not 1e+04 (an exponent only for the
    very large or small)."""
    return f"{x:.6g}" if 1e-3 <= abs(x) < 1e6 else f"{x:.3g}"


def _slip_text(f: Field, reading: _Reading, least: float, greatest: float, lang: str) -> str:
    """The unit slip that puts ``reading`` within [least, greatest] (SI), as a question with
    the value it would be, or the advice to check the number."""
    slip = likely_slip(reading.number, reading.unit, f.unit, least, greatest)
    if slip is None:
        return "check the number and its unit" if lang == "en" else "проверьте число и единицы"
    meant, value = slip
    into = f"{reading.number:.6g} {unit_text(meant, lang)}".rstrip()
    if meant != f.unit:
        into += f" = {value / si_factor(f.unit):.4g} {unit_text(f.unit, lang)}".rstrip()
    if lang == "en":
        return (f"a value in {unit_text(meant) or 'plain numbers'} typed as "
                f"{unit_text(reading.unit) or 'a plain number'}? {into}")
    return (f"значение в {unit_text(meant, 'ru') or 'долях'} записано как "
            f"{unit_text(reading.unit, 'ru') or 'безразмерное число'}? {into}")


def template(spec: LabSpec, lang: str = "en") -> str:
    """A commented blank measurement file for ``spec``; run as-is it says what to fill in."""
    t = _TEMPLATE_TEXT[lang]
    lines = [f"# dynlab — {t['lab']} {spec.number}: {spec.title[lang]}",
             *[f"# {line}" for line in t["intro"]], f'lab = "{spec.id}"', "", "[meta]"]
    lines += [f'{k} = ""' for k in ("student", "group", "date", "rig")]
    for sec in spec.sections:
        lines += ["", f"# ---- {sec.label[lang]} "
                  f"({t['required'] if sec.required else t['optional']}) ----"]
        lines += [f"# {h}" for h in sec.help.get(lang, "").splitlines()]
        lines.append(f"[[{sec.name}]]" if sec.many else f"[{sec.name}]")
        for f in sec.fields:
            lines.append(f"# {f.display_symbol} — {f.label[lang]}" + _hint(f, t))
            line = f'{f.name} = ""'
            if not f.required or f.default is not None:
                line = "# " + line
            lines.append(line)
    return "\n".join(lines) + "\n"


def _hint(f: Field, t) -> str:
    bits = []
    if f.unit:
        bits.append(f"[{f.unit}]")
    if f.choices:
        bits.append(" | ".join(f'"{c}"' if isinstance(c, str) else str(c) for c in f.choices))
    if f.repeated:
        bits.append(t["repeats"])
    if f.limit:
        bits.append(f"{t['limit']} ± {f.limit}")
    if f.default is not None:
        default = str(f.default).lower() if isinstance(f.default, bool) else f.default
        bits.append(f"{t['default']} {default}")
    elif not f.required:
        bits.append(t["optional"])
    if f.example is not None:
        bits.append(f"{t['example']} {f.example}")
    return " " + "; ".join(bits) if bits else ""


_TEMPLATE_TEXT = {
    "en": {
        "lab": "Lab",
        "intro": ["Fill in what you measured. A value is a number in the unit shown in brackets,",
                  "or a string with its own unit: \"850 mm\", \"5.432 kg\". Add your instrument's",
                  "limit of error as \"850 ± 0.5 mm\". Repeated readings go in an array:",
                  "t = [24.31, 24.28, 24.40]. A decimal comma goes in quotes: \"24,31\".",
                  "Delete the optional sections you did not measure;",
                  "a commented line (#) is optional. Then: dynlab run THIS_FILE"],
        "required": "required", "optional": "optional", "repeats": "repeated readings",
        "limit": "instrument", "default": "default", "example": "e.g.",
    },
    "ru": {
        "lab": "Лабораторная работа",
        "intro": ["Впишите измеренные значения: число в единицах, указанных в скобках, или",
                  "строку с единицами: \"850 мм\", \"5,432 кг\". Погрешность прибора: \"850 ± 0,5 мм\".",
                  "Повторные отсчёты — массивом: t = [24.31, 24.28, 24.40]. Десятичная запятая —",
                  "только в кавычках: \"24,31\", \"850,5 мм\". Удалите необязательные",
                  "разделы, которые не измерялись; строка с # — необязательная.",
                  "Затем: dynlab run ЭТОТ_ФАЙЛ"],
        "required": "обязательно", "optional": "необязательно", "repeats": "повторные отсчёты",
        "limit": "прибор", "default": "по умолчанию", "example": "напр.",
    },
}
