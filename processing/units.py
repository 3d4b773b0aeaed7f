"""Units at the boundary: parse '120.5 mm', '2345 g ± 1 g', '30,62 с', convert to SI.

SI inside the toolkit; the manual's customary units (mm, g, min⁻¹, degrees, kgf) only where
data enter. Parsing uses `pint <https://pint.readthedocs.io>`_, which knows every unit a lab
sheet may carry and checks dimensions for us. Four conventions of a Russian lab sheet are
read here, the same for every field of every lab and for the values ``dynlab check`` reads:

* **Decimal commas.** Inside a value written as text a comma between digits is a decimal
  comma: ``"30,62"``, ``"0,1706 kg*m^2"``, ``"30,62 ± 0,05 s"``. A number holding two commas
  (``"1,234,5"``) or a comma and a point (``"1.234,5"``, ``"1,234.5"``) is refused as
  ambiguous (a thousands separator or a slip), with the message saying so: write one decimal
  separator and no thousands separator. A comma followed by a space is no decimal comma:
  such a text holds two values, and the message says that readings go in an array. (A
  comma outside quotes is TOML's own separator: :mod:`processing.decimal_comma` finds where
  it split a reading.)
* **Units in Russian**, as the reports print them: ``кг``, ``мм``, ``с``, ``Н·м``, ``кгс``,
  ``об/мин``, ``мин⁻¹``, ``рад/с``, ``Гц``, ``°``, ``МПа``, ``мВ/(м/с²)`` … (:data:`RU_WORDS`, a
  pint preprocessor; pint itself reads ``·``, ``×``, ``²``, ``³``, ``⁻¹`` and ``°``), and as
  typed: in a case that cannot be confused (``КГ``; not ``МН`` for ``мН``), a power without
  its caret (``м2``, ``с-1``), a second typed as a Latin ``c`` (the key of ``с``).
* **Numbers as written by hand or copied from a report** (:func:`plain_notation`): a power of
  ten (``6,13·10⁶``, ``1,706*10^-1``, ``2×10**3``), a minus sign (``−0,5``), a stopwatch's
  minutes and seconds (``1:05,32`` is 65.32 s), a value and its limit in brackets
  (``(2,23 ± 0,06) кН/мм``, ``(6,13 ± 0,05)·10⁶ Н/м``).
* **Rotational speeds count revolutions** (:func:`cycles_factor`): in a field declared as an
  angle per time (``rpm``, ``rad/s``) a speed written per time alone (``1/s``, ``s^-1``,
  ``с⁻¹``, ``Hz``, ``Гц``, ``1/min``, ``мин⁻¹``) is revolutions per that time, as are ``rps``,
  ``об/с``, ``rpm`` and ``об/мин``; only ``rad/s`` (``рад/с``), ``deg/s`` are angles per time.
  A frequency field (``Hz``, ``kHz``: a sample rate, a natural frequency) counts cycles the
  same way: ``3000 rpm`` there is 50 Hz.

Glossary of names used across the toolkit
-----------------------------------------
============================  ==========================================  ========
name                          meaning                                     SI unit
============================  ==========================================  ========
``period``                    one full oscillation                        s
``amplitude``                 angular amplitude of a swing                rad
``mass``, ``m``               mass                                        kg
``J_*``                       moment of inertia about the named axis      kg·m²
``g``                         local acceleration of gravity               m/s²
``crank_angle``               crank angle from TDC, α                     rad
``angular_speed``             crank angular speed, ω                      rad/s
``lambda_``                   crank radius / rod length, λ = R/L          1
``crank_radius``              crank radius, R                             m
``offset_ratio``              piston-pin offset over crank radius, z=k/R  1
``readings``                  repeated readings of one quantity           as given
``u``, ``U``                  standard, expanded (k·u) uncertainty        as value
============================  ==========================================  ========
"""
from __future__ import annotations

import math
import re
from functools import cache

import pint

RU_UNITS = {"kg": "кг", "mm": "мм", "m": "м", "s": "с", "g": "г", "deg": "°", "GPa": "ГПа",
            "rad": "рад", "N": "Н", "Pa": "Па", "J": "Дж", "MPa": "МПа", "kN": "кН", "L": "л",
            "cm": "см", "kW": "кВт", "MW": "МВт", "Hz": "Гц", "min": "мин", "rpm": "мин⁻¹",
            "W": "Вт", "ms": "мс", "um": "мкм", "mrad": "мрад", "kHz": "кГц", "V": "В",
            "mV": "мВ", "kgf": "кгс", "kPa": "кПа", "kJ": "кДж", "rps": "об/с", "dB": "дБ",
            "us": "мкс", "uV": "мкВ", "MHz": "МГц", "h": "ч", "px": "пикс"}
"""How a Russian report prints a unit's symbols (:func:`unit_text`)."""

EN_UNITS = {"um": "µm", "us": "µs", "uV": "µV"}
"""The symbols an English report prints otherwise than pint spells them (:func:`unit_text`)."""

RU_WORDS = {**{ru: en for en, ru in RU_UNITS.items() if ru.isalpha()},
            "сек": "s", "мкс": "us", "ч": "h", "мг": "mg", "т": "t", "дм": "dm", "км": "km",
            "мН": "mN", "МН": "MN", "Нм": "N*m", "бар": "bar", "атм": "atm", "мкВ": "uV",
            "МГц": "MHz", "град": "deg", "об": "turn", "мл": "mL"}
"""Russian unit symbols as a student types them → pint's (the inverse of :data:`RU_UNITS`
and the usual others); a word of Cyrillic letters is looked up whole."""


_RU_ANY_CASE = {word.lower(): word for word in RU_WORDS
                if sum(w.lower() == word.lower() for w in RU_WORDS) == 1}
"""The symbols a wrong case cannot confuse (КГ, Кг for кг; not МН, mega, for мН, milli)."""

_POWER = re.compile(r"(?<=[^\W\d_])(-?[1-9])(?![\d.,])")
"""A power typed without its caret after a unit's letters: м2, с-1, мин-1."""

_LATIN_C = re.compile(r"(?<![\w])c(?![\w])")
"""A Latin c alone: с (second) typed with the keyboard in English (the same key); no lab
measures anything in speeds of light."""


@cache
def _russian_units(text: str) -> str:
    """A unit expression as a Russian student types it in pint's symbols (a pint
    preprocessor): Russian symbols (in any case that cannot be confused), powers without
    their caret, a second typed as a Latin c.

    >>> [_russian_units(t) for t in ("кг·м2", "КГ", "мин-1", "мм/c")]
    ['kg·m^2', 'kg', 'min^-1', 'mm/s']
    """
    def symbol(m: re.Match) -> str:
        word = m.group(0)
        return RU_WORDS.get(word) or RU_WORDS.get(_RU_ANY_CASE.get(word.lower(), ""), word)

    text = re.sub(r"[А-Яа-яЁё]+", symbol, text)
    return _LATIN_C.sub("s", _POWER.sub(r"^\1", text))


ureg = pint.UnitRegistry(preprocessors=[_russian_units])

_PLUS_MINUS = re.compile(r"\s*(?:±|\+/-|\+-)\s*")


class QuantityError(ValueError):
    """A value's text that cannot be read, with how to write it (``fix``), and both in
    Russian (``ru``: the problem, and the fix or None)."""

    def __init__(self, problem: str, fix: str | None = None,
                 ru: tuple[str, str | None] | None = None):
        super().__init__(problem)
        self.fix = fix
        self.problem_ru, self.fix_ru = ru or (None, None)


@cache
def dimension(unit: str) -> str:
    """The dimension of ``unit``, its base dimensions in alphabetical order (whatever order
    pint found them in): the key of :data:`PLAUSIBLE`.

    Examples
    --------
    >>> dimension("g*cm^2") == dimension("kg*m^2"), dimension("N/m"), dimension("")
    (True, '[mass] * [time] ** -2', 'dimensionless')
    """
    dims = ureg.Quantity(1.0, unit).dimensionality if unit else {}
    return " * ".join(k if v == 1 else f"{k} ** {v:g}" for k, v in sorted(dims.items())) \
        or "dimensionless"


_NAMES = {"m": ("a length", "длина"), "kg": ("a mass", "масса"), "s": ("a time", "время"),
          "": ("a plain number or angle", "безразмерное число или угол"),
          "m/s^2": ("an acceleration", "ускорение"),
          "Pa": ("a pressure or modulus", "давление или модуль упругости"),
          "kg*m^2": ("a moment of inertia", "момент инерции"),
          "1/s": ("a frequency or speed", "частота или скорость вращения")}


def _dimension_name(unit: str, lang: str = "en") -> str:
    """What a quantity of ``unit`` is, in words of ``lang``.

    >>> _dimension_name("mm"), _dimension_name("g", "ru"), _dimension_name("N", "ru")
    ('a length', 'масса', 'величина размерности [length] * [mass] * [time] ** -2')
    """
    names = {dimension(u): name for u, name in _NAMES.items()}
    key = dimension(unit)
    if key in names:
        return names[key][lang == "ru"]
    return f"величина размерности {key}" if lang == "ru" else f"a quantity of dimension {key}"


PLAUSIBLE = {dimension(si): (lo, hi, si) for lo, hi, si in (
    (1e-9, 1e6, "kg"), (1e-9, 1e3, "m"), (1e-9, 1e5, "s"), (1e-4, 1e8, "1/s"),
    (1e-6, 1e6, "m/s^2"), (1e-3, 1e13, "Pa"), (1e-3, 1e5, "kg/m^3"), (1e-15, 1e7, "kg*m^2"),
    (1e-6, 1e9, "N"), (1e-9, 1e9, "N*m"), (1e-3, 1e13, "N/m"), (1e-15, 1e3, "m^3"),
    (1e-15, 1e4, "m^2"), (1e-9, 1e6, "V"))}
"""What any lab bench can measure, by dimension: (least, greatest, SI unit) of a magnitude.
Outside it a value is suspect (a warning) where its field declares no range of its own
(:attr:`processing.measurement.Field.plausible`); :data:`REJECT_FACTOR` beyond it, it is
refused."""

REJECT_FACTOR = 1e3
"""How far beyond the plausible range a magnitude is refused rather than warned about."""

ANY_MAGNITUDE = (1e-30, 1e30)
"""Magnitudes refused whatever the dimension: beyond them products of inputs overflow."""


def magnitude_verdict(value: float, unit: str) -> tuple[str, tuple[float, float, str] | None]:
    """Whether a nonzero SI ``value`` of a quantity declared in ``unit`` is plausible.

    Returns
    -------
    verdict : {"ok", "suspect", "refused"}
    plausible : tuple or None
        ``(least, greatest, SI unit)`` of its dimension (:data:`PLAUSIBLE`), if known.

    Examples
    --------
    >>> magnitude_verdict(11.8, "kg")[0], magnitude_verdict(2e6, "kg")[0]
    ('ok', 'suspect')
    >>> magnitude_verdict(1e308, "kg")[0], magnitude_verdict(1e-320, "g")[0]
    ('refused', 'refused')
    """
    size = abs(value)
    if value == 0.0:
        return "ok", None
    plausible = PLAUSIBLE.get(dimension(unit))
    if not ANY_MAGNITUDE[0] <= size <= ANY_MAGNITUDE[1]:
        return "refused", plausible
    if plausible is None:
        return "ok", None
    lo, hi, _ = plausible
    if not lo / REJECT_FACTOR <= size <= hi * REJECT_FACTOR:
        return "refused", plausible
    return ("ok" if lo <= size <= hi else "suspect"), plausible


LEVEL_UNITS = ("dB",)
"""Units of levels, 20 lg of a ratio to a stated reference (a vibration meter's dB scale): a
level is carried in its unit as it is (there is no SI unit to convert it to, and pint's
logarithmic dB would turn 122 dB into a ratio)."""


@cache
def _to_base(unit: str) -> tuple[float, float]:
    """(factor, offset) with x·factor + offset the SI base value of x in ``unit`` (the
    offset is 0 but for temperatures; a level's is as it is): pint asked once per unit."""
    if unit in LEVEL_UNITS:
        return 1.0, 0.0
    zero = float(ureg.Quantity(0.0, unit).to_base_units().magnitude)
    return float(ureg.Quantity(1.0, unit).to_base_units().magnitude) - zero, zero


@cache
def _dimensionality(unit: str):
    return ureg.Quantity(1.0, unit).dimensionality


@cache
def _radians(unit: str) -> float:
    """The power of the radian in ``unit``: 1 for an angle per time (``rpm``, ``rad/s``),
    0 for a count per time (``Hz``, ``1/min``), which pint takes for radians."""
    return dict(ureg.Quantity(1.0, unit).to_root_units().unit_items()).get("radian", 0)


_PER_TIME = ureg.Quantity(1.0, "1/s").dimensionality


def cycles_factor(unit: str, declared: str) -> float:
    """What a value written in ``unit`` is multiplied by, beyond pint's conversion, in a field
    declared in ``declared``: a speed written as a count per time (``Hz``, ``1/s``,
    ``1/min``) where an angle per time is declared (``rpm``, ``rad/s``) counts revolutions
    (2π rad each); an angle per time written where a count per time is declared (a frequency
    in ``Hz``) counts cycles the same way (÷ 2π). pint would take ``1/s`` for ``rad/s``. The
    same holds for a speed inside a compound unit (a converter's scale in ``mm/rpm`` written
    ``мм/мин⁻¹``): whatever carries time to the power ±1 (not ``N*m/rad``).

    Examples
    --------
    >>> round(cycles_factor("Hz", "rpm"), 6), round(cycles_factor("rpm", "Hz"), 6)
    (6.283185, 0.159155)
    >>> cycles_factor("rad/s", "rpm"), cycles_factor("Hz", "kHz"), cycles_factor("mm", "m")
    (1.0, 1.0, 1.0)
    >>> round(cycles_factor("mm/min^-1", "mm/rpm"), 6), cycles_factor("N*m", "N*m/rad")
    (0.159155, 1.0)
    """
    dims = _dimensionality(unit)
    if dims != _dimensionality(declared) or abs(dims["[time]"]) != 1:
        return 1.0
    return (2 * math.pi) ** (_radians(declared) - _radians(unit))


def si_factor(unit: str) -> float:
    """Factor converting a value in ``unit`` to SI base units (degrees → radians).

    >>> si_factor("mm")
    0.001
    """
    return _to_base(unit)[0]


@cache
def si_unit(unit: str) -> str:
    """The SI unit, written compactly, of a quantity declared in ``unit``.

    >>> si_unit("mm"), si_unit("g*cm^2"), si_unit("dB")
    ('m', 'kg*m^2', 'dB')
    """
    if unit in LEVEL_UNITS:
        return unit
    base = ureg.Quantity(1.0, unit).to_base_units().units
    text = f"{base:~C}".replace("**", "^")
    return text or "1"


def convert(value: float, unit: str, to: str) -> float:
    """Convert ``value`` from ``unit`` to ``to``.

    >>> convert(1500, "mm", "m")
    1.5
    """
    if _dimensionality(unit) != _dimensionality(to):
        return float(ureg.Quantity(value, unit).to(to).magnitude)   # pint says why not
    (a, b), (c, d) = _to_base(unit), _to_base(to)
    return float((value * a + b - d) / c)


def number_to_si(value: float, unit: str, declared: str) -> float:
    """A plain number written in ``unit`` for a field declared in ``declared`` → SI, a
    rotational speed counting revolutions (:func:`cycles_factor`).

    >>> round(number_to_si(33.3, "Hz", "rpm") * 30 / math.pi, 1)   # in min⁻¹
    1998.0
    """
    factor, offset = _to_base(unit)
    return (value * factor + offset) * cycles_factor(unit, declared)


_GROUPED = re.compile(r"\d+(?:[.,]\d+)+")
"""A number's digits with the separators between them (``30,62``, ``1.234,5``)."""


def decimal_point(text: str) -> str:
    """``text`` with each decimal comma between digits written as a point.

    A number with one comma and no point has a decimal comma. Two commas, or a comma and a
    point, are ambiguous (a thousands separator, a slip): refused.

    Raises
    ------
    QuantityError
        For an ambiguous number, saying how to write it.

    Examples
    --------
    >>> decimal_point("30,62 ± 0,05 s"), decimal_point("0,1706 kg*m^2")
    ('30.62 ± 0.05 s', '0.1706 kg*m^2')
    >>> decimal_point("1.234,5 mm")
    Traceback (most recent call last):
    ...
    processing.units.QuantityError: '1.234,5 mm': the number 1.234,5 holds both a comma and a point: a thousands separator cannot be told from a decimal one
    """
    def point(match: re.Match) -> str:
        number = match.group(0)
        commas, points = number.count(","), number.count(".")
        if not commas:
            return number
        if commas == 1 and not points:
            return number.replace(",", ".")
        how = "two commas" if not points else "both a comma and a point"
        how_ru = "две запятые" if not points else "и запятая, и точка"
        raise QuantityError(f"{text!r}: the number {number} holds {how}: a thousands "
                            f"separator cannot be told from a decimal one",
                            "write the number with one decimal separator (a point or a comma) "
                            "and no thousands separator, e.g. \"1234.5\" or \"1234,5\"",
                            ru=(f"{text!r}: в числе {number} {how_ru}: разделитель тысяч не "
                                f"отличить от десятичного",
                                "запишите число с одним десятичным разделителем (точкой или "
                                "запятой) и без разделителя тысяч, например \"1234.5\" или "
                                "\"1234,5\""))
    return _GROUPED.sub(point, text)


_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")

_POWER_OF_TEN = re.compile(
    r"(?<![\w.])(?P<mantissa>\d+(?:\.\d*)?|\.\d+)\s*[·⋅*×]\s*10\s*"
    r"(?:(?:\^|\*\*)\s*\(?\s*(?P<power>[-+]?\d+)(?:\s*\))?|(?P<super>[⁻⁺]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+))")
"""A number times a power of ten as written by hand or by a word processor: ``6.13·10⁶``,
``1.706*10^-1``, ``2×10**3``, ``5·10^(-3)``."""

_BRACKETED = re.compile(r"^\s*\((?P<inner>[^()]*±[^()]*)\)\s*(?P<times>[·⋅*×]\s*10\s*"
                        r"(?:(?:\^|\*\*)\s*\(?\s*[-+]?\d+(?:\s*\))?|[⁻⁺]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+))?"
                        r"(?P<unit>.*)$")
"""A value and its limit in brackets, as a report writes them: ``(2.23 ± 0.06) kN/mm``,
``(6.13 ± 0.05)·10⁶ N/m``."""


_CLOCK = re.compile(r"^\s*(?:(?P<h>\d+):(?=\d{2}:))?(?P<m>\d+):(?P<s>[0-5]\d(?:\.\d*)?)"
                    r"(?=\s*(?:±|$))")
"""A stopwatch's reading, minutes and seconds (``1:05.32``) or hours too (``1:02:05``), alone
or before a ± limit."""


def plain_notation(text: str, expected_unit: str = "") -> str:
    """``text`` with the ways a number is written by hand or copied from a report put as
    Python writes it: its decimal commas as points (:func:`decimal_point`), a minus sign (−)
    as a hyphen, a stopwatch's minutes and seconds as seconds (where ``expected_unit`` is a
    time: ``1:10`` is no lever ratio), a power of ten as an exponent, a value and its limit
    in brackets each followed by the power and the unit.

    Examples
    --------
    >>> plain_notation("6.13·10⁶ Н/м"), plain_notation("1.706*10^-1 kg*m^2")
    ('6.13e6 Н/м', '1.706e-1 kg*m^2')
    >>> plain_notation("(2.23 ± 0.06) kN/mm"), plain_notation("(6.13 ± 0.05)·10⁶ N/m")
    ('2.23 kN/mm ± 0.06 kN/mm', '6.13e6 N/m ± 0.05e6 N/m')
    >>> plain_notation("−0.5 mm"), plain_notation("1:05.32", "s")
    ('-0.5 mm', '65.32 s')
    >>> plain_notation("1:05.3 ± 0.2 s", "s"), plain_notation("1:10", "")
    ('65.3 s ± 0.2 s', '1:10')
    """
    text = decimal_point(text).replace("\u2212", "-")
    clock = _CLOCK.match(text) if dimension(expected_unit) == dimension("s") else None
    if clock:
        h, m = int(clock["h"] or 0), int(clock["m"])
        if clock["h"] is None or m < 60:
            text = f"{(h * 60 + m) * 60 + float(clock['s']):.10g} s{text[clock.end():]}"
    bracketed = _BRACKETED.match(text)
    if bracketed:
        times, unit = bracketed["times"] or "", bracketed["unit"].strip()
        value, limit = _PLUS_MINUS.split(bracketed["inner"].strip(), maxsplit=1)
        if limit.rstrip().endswith("%"):
            text = f"{value}{times} {unit} ± {limit}"
        else:
            text = f"{value}{times} {unit} ± {limit}{times} {unit}"
    return _POWER_OF_TEN.sub(lambda m: f"{m['mantissa']}e"
                             f"{m['power'] or m['super'].translate(_SUPERSCRIPT)}", text)


def parse_quantity(text: str, expected_unit: str) -> tuple[float, float | None]:
    """Parse ``'850 mm'``, ``'850 ± 0.5 mm'``, ``'850 mm ± 0.5 mm'`` or ``'850 mm ± 0.1 %'``
    into SI.

    Parameters
    ----------
    text : str
        A number with a unit, optionally followed by a ± limit with its own unit (or sharing
        the value's unit when only one is written), or in per cent of the value (an
        instrument's accuracy class). A bare number takes ``expected_unit``.
        Decimal commas, units in Russian and rotational speeds as the module says.
    expected_unit : str
        The unit the field is declared in; only its dimension is checked here (and whether
        it counts an angle: :func:`cycles_factor`).

    Returns
    -------
    value, limit : float, float or None
        In SI base units; ``limit`` is None when the text has no ± part.

    Raises
    ------
    QuantityError
        When the text is not a number with a unit, or the unit's dimension is wrong.

    Examples
    --------
    >>> parse_quantity("850 ± 0.5 mm", "mm")
    (0.85, 0.0005)
    >>> parse_quantity("2345 г", "kg"), parse_quantity("30,62 ± 0,05 с", "s")
    ((2.345, None), (30.62, 0.05))
    >>> parse_quantity("850 mm ± 2 %", "mm"), parse_quantity("10,2 ± 2,5 %", "m")
    ((0.85, 0.017), (10.2, 0.255))
    >>> [round(parse_quantity(t, "rpm")[0], 4) for t in ("1500 min^-1", "25 1/s", "25 Гц")]
    [157.0796, 157.0796, 157.0796]
    """
    return read_quantity(text, expected_unit)[:2]


def read_quantity(text: str, expected_unit: str) -> tuple[float, float | None, str]:
    """:func:`parse_quantity`, and the unit the value was written in (``expected_unit`` for a
    bare number): ``(value, limit, unit)``.

    >>> read_quantity("0,8 m", "mm")
    (0.8, None, 'm')
    """
    written, text = text, plain_notation(text, expected_unit)
    if "," in text:
        raise QuantityError(f"cannot read {written!r}: a comma that is no decimal comma (not "
                            f"between two digits) separates two values",
                            "write one value per text, with a decimal comma between digits "
                            "(\"30,62\"); repeated readings go in an array, "
                            "t = [\"30,62\", \"30,81\"]",
                            ru=(f"не прочесть {written!r}: запятая не между двумя цифрами — не "
                                f"десятичная и разделяет два значения",
                                "пишите одно значение в строке, с десятичной запятой между "
                                "цифрами (\"30,62\"); повторные отсчёты — массивом, "
                                "t = [\"30,62\", \"30,81\"]"))
    parts = _PLUS_MINUS.split(text.strip())
    if len(parts) > 2 or not parts[0]:
        raise QuantityError(f"cannot read {written!r} as a value with a unit",
                            ru=(f"не прочесть {written!r} как значение с единицей", None))
    main, tol = parts[0], parts[1] if len(parts) == 2 else None
    percent = tol is not None and tol.rstrip().endswith("%")
    if percent:                           # an instrument's accuracy, relative to the value
        tol = tol.rstrip()[:-1].strip()
        if not _is_number(tol):
            raise QuantityError(f"cannot read the ± limit in {written!r}: a limit in per cent "
                                f"is a number before the % sign",
                                ru=(f"не прочесть предел ± в {written!r}: предел в процентах — "
                                    f"это число перед знаком %", None))
    if tol is not None and _is_number(main) and not percent:
        unit_part = _unit_of(tol)
        main = f"{main} {unit_part}" if unit_part else main
    unit = _russian_units(_unit_of(main)) or expected_unit
    value = _to_si(main, expected_unit, written)
    limit = None
    if percent:
        limit = abs(value) * float(tol) / 100
    elif tol is not None:
        if _is_number(tol):
            tol = f"{tol} {_unit_of(main) or expected_unit}"
        limit = _to_si(tol, expected_unit, written)
        if limit < 0:
            raise QuantityError(f"the ± limit in {written!r} is negative: a limit of error is "
                                f"a half-width, ≥ 0",
                                ru=(f"предел ± в {written!r} отрицателен: предел погрешности — "
                                    f"полуширина, ≥ 0", None))
    return value, limit, unit


def to_si(value: float, unit: str) -> float:
    """A plain number in ``unit`` → SI base units."""
    return value * si_factor(unit)


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


_NUMBER_AND_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*)$")
"""A number and what follows it (its unit)."""


def _unit_of(s: str) -> str:
    m = _NUMBER_AND_UNIT.match(s)
    unit = m.group(2).strip() if m else ""
    return f"1{unit}" if unit.startswith("/") else unit      # "33.3 /s": per second


def _to_si(s: str, expected_unit: str, whole: str) -> float:
    s = s.strip()
    if _is_number(s):
        return to_si(float(s), expected_unit)
    if not re.match(r"^\s*[-+]?(?:\d|\.\d)", s):
        raise QuantityError(f"cannot read {whole!r}: it should start with a number, e.g. "
                            f"'12.5 {expected_unit}'",
                            ru=(f"не прочесть {whole!r}: значение начинается с числа, например "
                                f"'12,5 {expected_unit}'", None))
    number, unit = _NUMBER_AND_UNIT.match(s).group(1), _unit_of(s)
    if ":" in s:
        raise QuantityError(*_colon(whole, expected_unit))
    try:
        dimension = _dimensionality(unit)
    except Exception as exc:
        raise QuantityError(f"cannot read {whole!r} as a value with a unit ({exc})",
                            ru=(f"не прочесть {whole!r} как значение с единицей (единица не "
                                f"разобрана)",
                                None)) from None
    if dimension != _dimensionality(expected_unit):
        given = str(ureg.Unit(unit))
        raise QuantityError(
            f"{whole!r} is {_dimension_name(given)}, but {_dimension_name(expected_unit)} "
            f"is expected (unit like '{expected_unit}')",
            ru=(f"{whole!r} — {_dimension_name(given, 'ru')}, а ожидается "
                f"{_dimension_name(expected_unit, 'ru')} (единица вроде '{expected_unit}')",
                None))
    if not same_kind(unit, expected_unit):
        raise QuantityError(*_angle_for_ratio(whole, expected_unit))
    return number_to_si(float(number), unit, expected_unit)


def _colon(whole: str, expected_unit: str) -> tuple:
    """Why a text with a colon that is no stopwatch's time is refused, and the fix."""
    if dimension(expected_unit) == dimension("s"):
        return (f"cannot read {whole!r} as a stopwatch's time: minutes:seconds, the seconds "
                f"under 60 (1:05,32), or hours:minutes:seconds",
                "write the time as the stopwatch shows it, or in seconds (65,32 s)",
                (f"не прочесть {whole!r} как время секундомера: минуты:секунды, секунд меньше "
                 f"60 (1:05,32), или часы:минуты:секунды",
                 "запишите время, как его показал секундомер, или в секундах (65,32 с)"))
    example = f"12.5 {expected_unit}".strip()
    return (f"cannot read {whole!r}: a colon is read only in a stopwatch's time (1:05,32), "
            f"and here no time is expected",
            f"write the value as a number and a unit, e.g. '{example}'; a ratio as its value "
            f"(1:10 as 0.1)",
            (f"не прочесть {whole!r}: двоеточие читается только во времени секундомера "
             f"(1:05,32), а здесь ожидается не время",
             f"запишите значение числом и единицей, например '{example.replace('.', ',')}'; "
             f"отношение — его значением (1:10 как 0,1)"))


def same_kind(unit: str, declared: str) -> bool:
    """Whether a value written in ``unit`` may stand for a field declared in ``declared``:
    the same dimension, and of dimensionless units either both angles or neither (pint takes
    an angle for a plain number).

    Examples
    --------
    >>> same_kind("kN/mm", "N/m"), same_kind("deg", "rad"), same_kind("%", "")
    (True, True, True)
    >>> same_kind("deg", ""), same_kind("%", "deg"), same_kind("mm", "kg")
    (False, False, False)
    """
    dims = _dimensionality(unit)
    return dims == _dimensionality(declared) and (bool(dims) or
                                                   _radians(unit) == _radians(declared))


def _angle_for_ratio(whole: str, expected_unit: str) -> tuple[str, tuple[str, None]]:
    """Why an angle is refused for a plain number (a ratio, a share) or a plain number for an
    angle: pint takes both for dimensionless, so 1.5 deg would be read 0.026 as a rocker
    ratio, 30 % 0.3 rad as an angle."""
    if _radians(expected_unit):
        return (f"{whole!r} is a plain number or share, but an angle is expected (in deg or "
                f"rad)",
                (f"{whole!r} — безразмерное число или доля, а ожидается угол (в градусах или "
                 f"радианах)", None))
    return (f"{whole!r} is an angle, but a plain number is expected (a ratio or share: no "
            f"unit, or %)",
            (f"{whole!r} — угол, а ожидается безразмерное число (отношение или доля: без "
             f"единицы или %)", None))


SLIP_UNITS = ("mg", "g", "kg", "t", "um", "mm", "cm", "m", "ms", "s", "min", "rpm", "rps",
              "rad/s", "Hz", "kHz", "MHz", "deg", "rad", "mrad", "", "%", "N", "kN", "kgf",
              "N*m", "N*mm", "kN*m", "kgf*m", "N/m", "N/mm", "kN/mm", "kgf/mm", "Pa", "kPa",
              "MPa", "GPa", "bar", "kg*m^2", "kg*cm^2", "kg*mm^2", "g*cm^2", "mm/s", "m/s",
              "cm/s^2", "m/s^2", "kg/m^3", "g/cm^3", "kg/m^2", "g/cm^2", "L", "cm^3",
              "N*m/rad", "kN*m/rad", "N*m/mrad", "mV", "V", "um/s")
"""The units a number is usually meant in, one of which a unit slip swaps for another."""


def likely_slip(number: float, written: str, declared: str, least: float,
                greatest: float) -> tuple[str, float] | None:
    """The unit that ``number``, written in ``written`` for a field declared in ``declared``,
    was likely meant in: the one of :data:`SLIP_UNITS` (of the same dimension, counting
    angles as the field does) that puts it within ``least``–``greatest`` [SI], nearest the
    range's middle. None if none does.

    Returns
    -------
    unit, value : str, float
        The unit meant, and the value in SI it gives.

    Examples
    --------
    >>> likely_slip(8450, "kg", "kg", 0.01, 50)      # grams typed as kg
    ('g', 8.45)
    >>> likely_slip(0.1, "mm", "mm", 0.01, 0.5)      # metres typed as mm
    ('m', 0.1)
    """
    middle = math.log(least * greatest) / 2
    found = []
    for unit in SLIP_UNITS:
        if _dimensionality(unit) != _dimensionality(written) \
                or _radians(unit) != _radians(declared):
            continue
        value = number_to_si(number, unit, declared)
        if least <= abs(value) <= greatest and \
                not math.isclose(value, number_to_si(number, written, declared)):
            found.append((abs(math.log(abs(value)) - middle), unit, value))
    return min(found)[1:] if found else None


def unit_text(unit: str, lang: str = "en") -> str:
    """A unit as printed: ``kg*m^2`` → ``kg·m²`` (``кг·м²`` in Russian).

    >>> unit_text("kg*m^2", "ru"), unit_text("um")
    ('кг·м²', 'µm')
    """
    table = RU_UNITS if lang == "ru" else EN_UNITS
    unit = re.sub(r"[A-Za-z]+", lambda m: table.get(m.group(0), m.group(0)), unit)
    return unit.replace("*", "·").replace("^2", "²").replace("^3", "³").replace("^-1", "⁻¹")
