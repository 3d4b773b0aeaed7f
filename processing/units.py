"""Units at the boundary: parse '120.5 mm', '2345 g ± 1 g', convert to SI.

SI inside the toolkit; the manual's customary units (mm, g, min⁻¹, degrees, kgf) only where
data enter. Parsing uses `pint <https://pint.readthedocs.io>`_, which knows every unit a lab
sheet may carry and checks dimensions for us.

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
``u``, ``U``                  standard, expanded (k = 2) uncertainty      as value
============================  ==========================================  ========
"""
from __future__ import annotations

import re
from functools import cache

import pint

ureg = pint.UnitRegistry()
ureg.define("kgf = 9.80665 * newton")

_PLUS_MINUS = re.compile(r"\s*(?:±|\+/-|\+-)\s*")
_PER_MINUTE = re.compile(r"(?:1\s*/\s*min\b|min\s*(?:\^|\*\*)\s*-1|min⁻¹|мин⁻¹|об/мин)")


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


_NAMES = {"m": "a length", "kg": "a mass", "s": "a time", "": "a plain number or angle",
          "m/s^2": "an acceleration", "Pa": "a pressure or modulus",
          "kg*m^2": "a moment of inertia", "1/s": "a frequency or speed"}


def _dimension_name(unit: str) -> str:
    names = {dimension(u): name for u, name in _NAMES.items()}
    key = dimension(unit)
    return names.get(key, f"a quantity of dimension {key}")


PLAUSIBLE = {dimension(si): (lo, hi, si) for lo, hi, si in (
    (1e-9, 1e6, "kg"), (1e-9, 1e3, "m"), (1e-9, 1e5, "s"), (1e-4, 1e8, "1/s"),
    (1e-6, 1e6, "m/s^2"), (1e-3, 1e13, "Pa"), (1e-3, 1e5, "kg/m^3"), (1e-15, 1e7, "kg*m^2"),
    (1e-6, 1e9, "N"), (1e-9, 1e9, "N*m"), (1e-3, 1e13, "N/m"), (1e-15, 1e3, "m^3"),
    (1e-15, 1e4, "m^2"), (1e-9, 1e6, "V"))}
"""What a lab bench can measure, by dimension: (least, greatest, SI unit) of a magnitude.
Outside it a value is suspect (a warning); :data:`REJECT_FACTOR` beyond it, it is refused."""

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


@cache
def _to_base(unit: str) -> tuple[float, float]:
    """(factor, offset) with x·factor + offset the SI base value of x in ``unit`` (the
    offset is 0 but for temperatures): pint asked once per unit."""
    zero = float(ureg.Quantity(0.0, unit).to_base_units().magnitude)
    return float(ureg.Quantity(1.0, unit).to_base_units().magnitude) - zero, zero


@cache
def _dimensionality(unit: str):
    return ureg.Quantity(1.0, unit).dimensionality


def si_factor(unit: str) -> float:
    """Factor converting a value in ``unit`` to SI base units (degrees → radians).

    >>> si_factor("mm")
    0.001
    """
    return _to_base(unit)[0]


@cache
def si_unit(unit: str) -> str:
    """The SI unit, written compactly, of a quantity declared in ``unit``.

    >>> si_unit("mm"), si_unit("g*cm^2")
    ('m', 'kg*m^2')
    """
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


def parse_quantity(text: str, expected_unit: str) -> tuple[float, float | None]:
    """Parse ``'850 mm'``, ``'850 ± 0.5 mm'`` or ``'850 mm ± 0.5 mm'`` into SI.

    Parameters
    ----------
    text : str
        A number with a unit, optionally followed by a ± limit with its own unit (or sharing
        the value's unit when only one is written). A bare number takes ``expected_unit``.
    expected_unit : str
        The unit the field is declared in; only its dimension is checked here.

    Returns
    -------
    value, limit : float, float or None
        In SI base units; ``limit`` is None when the text has no ± part.

    Raises
    ------
    ValueError
        When the text is not a number with a unit, or the unit's dimension is wrong.

    Examples
    --------
    >>> parse_quantity("850 ± 0.5 mm", "mm")
    (0.85, 0.0005)
    >>> parse_quantity("2345 g", "kg")
    (2.345, None)
    >>> round(parse_quantity("1500 min^-1", "rpm")[0], 4)   # speeds: revolutions per minute
    157.0796
    """
    if expected_unit == "rpm":
        # the manual's min⁻¹ is revolutions per minute; pint would read 1/min as 1/60 rad/s
        text = _PER_MINUTE.sub("rpm", text)
    parts = _PLUS_MINUS.split(text.strip())
    if len(parts) > 2 or not parts[0]:
        raise ValueError(f"cannot read {text!r} as a value with a unit")
    main, tol = parts[0], parts[1] if len(parts) == 2 else None
    if tol is not None and _is_number(main):
        unit_part = _unit_of(tol)
        main = f"{main} {unit_part}" if unit_part else main
    value = _to_si(main, expected_unit, text)
    limit = None
    if tol is not None:
        if _is_number(tol):
            tol = f"{tol} {_unit_of(main) or expected_unit}"
        limit = _to_si(tol, expected_unit, text)
        if limit < 0:
            raise ValueError(f"the ± limit in {text!r} is negative: a limit of error is a "
                             f"half-width, ≥ 0")
    return value, limit


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
    return m.group(2).strip() if m else ""


def _to_si(s: str, expected_unit: str, whole: str) -> float:
    s = s.strip()
    if _is_number(s):
        return to_si(float(s), expected_unit)
    if not re.match(r"^\s*[-+]?(?:\d|\.\d)", s):
        raise ValueError(f"cannot read {whole!r}: it should start with a number, e.g. '12.5 {expected_unit}'")
    number, unit = _NUMBER_AND_UNIT.match(s).groups()
    try:
        dimension = _dimensionality(unit)
        factor, offset = _to_base(unit)
    except Exception as exc:
        raise ValueError(f"cannot read {whole!r} as a value with a unit ({exc})") from None
    if dimension != _dimensionality(expected_unit):
        raise ValueError(
            f"{whole!r} is {_dimension_name(str(ureg.Unit(unit)))}, but "
            f"{_dimension_name(expected_unit)} "
            f"is expected (unit like '{expected_unit}')"
        )
    return float(number) * factor + offset


RU_UNITS = {"kg": "кг", "mm": "мм", "m": "м", "s": "с", "g": "г", "deg": "°", "GPa": "ГПа",
             "rad": "рад", "N": "Н", "Pa": "Па", "J": "Дж", "MPa": "МПа", "kN": "кН", "L": "л",
             "cm": "см", "kW": "кВт", "MW": "МВт", "Hz": "Гц", "min": "мин", "rpm": "мин⁻¹",
             "W": "Вт"}


def unit_text(unit: str, lang: str = "en") -> str:
    """A unit as printed: ``kg*m^2`` → ``kg·m²`` (``кг·м²`` in Russian).

    >>> unit_text("kg*m^2", "ru")
    'кг·м²'
    """
    if lang == "ru":
        unit = re.sub(r"[A-Za-z]+", lambda m: RU_UNITS.get(m.group(0), m.group(0)), unit)
    return unit.replace("*", "·").replace("^2", "²").replace("^3", "³").replace("^-1", "⁻¹")
