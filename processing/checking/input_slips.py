"""Slips a student makes inside a formula, whatever the lab: an input taken in the wrong unit
or for the wrong quantity — min⁻¹ used as rad/s, ω put where the formula takes n, g = 10, a
diameter for a radius (the stroke for the crank radius) or the reverse, T for T² — each made
as a change of the inputs (:meth:`processing.measurement.Inputs.changed`) that the lab
reduces again, so that the slip reaches every result its input reaches, through the formula
(R² and R⁴ of a moment of inertia, ω² of an inertia force).

Which inputs a slip fits is told by their declaration (:class:`processing.measurement.Field`):
the unit (a rotational speed, a length, a time, an acceleration) and, for lengths, the
manual's symbol (a radius ``r``, ``R1``; a diameter ``d``, ``D_rim``; the stroke ``S``)."""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from functools import cache

from processing.measurement import Field, Inputs
from processing.uncertainty import Measured
from processing.units import cycles_factor, dimension

ROTATIONAL_SPEED = dimension("rpm")
LENGTH = dimension("m")
TIME = dimension("s")
ACCELERATION = dimension("m/s^2")

STANDARD_G = 9.80665
"""Standard gravity [m/s²]: what a ``g = 10`` slip rounds."""


@dataclass(frozen=True)
class InputSlip:
    """A slip of a formula's input.

    Parameters
    ----------
    name : str
    text : dict
        English and Russian, with ``{symbol}``: the input slipped (the manual's symbol).
    fits : callable
        Whether the slip can be made on a field (its declaration).
    change : callable
        ``change(value, entry)``: the field's value as the slip leaves it (``entry``: the
        section's other values, for the count of a stopwatch's periods), or None.
    together : bool
        Made on every fitting field of a section at once (T for T² in every period of the
        formula; every radius of a body measured as a diameter), not on one field at a time;
        where only one field fits, only if ``alone`` (else the one-field slip says it).
    alone : bool
        A ``together`` slip is made on a section with a single fitting field too.
    """

    name: str
    text: dict[str, str]
    fits: Callable[[Field], bool]
    change: Callable[[Measured, dict], Measured | None]
    together: bool = False
    alone: bool = True


@cache
def _dimension(unit: str) -> str:
    return dimension(unit)


def _unit_is(dim: str) -> Callable[[Field], bool]:
    return lambda f: bool(f.unit) and f.kind == "quantity" and _dimension(f.unit) == dim


def _rotational_speed(f: Field) -> bool:
    """An angle per time (``rpm``, ``rad/s``): a crank's speed, not a frequency or a sample
    rate in ``Hz`` (whose dimension pint gives the same)."""
    return _unit_is(ROTATIONAL_SPEED)(f) and cycles_factor(f.unit, "Hz") != 1.0


_RADIUS_OR_DIAMETER = re.compile(r"[rRdDS](?:\d|_|$)")
"""The manual's symbols of a radius, a diameter or the stroke (``r``, ``R1``, ``d_ref``,
``D_rim``, ``S``), not a word that starts so (``division``)."""


def _radius_or_diameter(f: Field) -> bool:
    return _unit_is(LENGTH)(f) and bool(_RADIUS_OR_DIAMETER.match(f.name))


def _scaled(factor: float) -> Callable[[Measured, dict], Measured]:
    def change(m: Measured, entry: dict) -> Measured:
        return replace(m, value=m.value * factor, u_a=m.u_a * abs(factor),
                       limit=m.limit * abs(factor), u_b=m.u_b * abs(factor),
                       readings=tuple(r * factor for r in m.readings))
    return change


def _set(value: float) -> Callable[[Measured, dict], Measured]:
    return lambda m, entry: replace(m, value=value, readings=())


def _period_not_squared(m: Measured, entry: dict) -> Measured | None:
    """The time of n periods t' such that (t'/n)² = t/n: a formula's T² made T, the count of
    periods the section's (``n_osc``, ``n``; one without)."""
    n = next((v for k, v in entry.items() if k in ("n_osc", "n", "N") and isinstance(v, int)),
             1)
    if m.value <= 0:
        return None
    return replace(m, value=math.sqrt(m.value * n), u_a=0.0, limit=0.0, u_b=0.0, readings=())


INPUT_SLIPS = (
    InputSlip("rpm_as_rad_s_in_formula",
              {"en": "{symbol} in min⁻¹ used as rad/s inside the formula (×30/π)",
               "ru": "{symbol} в мин⁻¹ подставлена в формулу как рад/с (×30/π)"},
              _rotational_speed, _scaled(30 / math.pi)),
    InputSlip("omega_for_n",
              {"en": "ω in rad/s put for {symbol} in min⁻¹ inside the formula (×π/30)",
               "ru": "в формулу вместо {symbol} в мин⁻¹ подставлена ω в рад/с (×π/30)"},
              _rotational_speed, _scaled(math.pi / 30)),
    InputSlip("g_as_10",
              {"en": "g = 10 m/s² taken for {symbol}",
               "ru": "принято {symbol} = 10 м/с²"},
              lambda f: _unit_is(ACCELERATION)(f) and f.name == "g", _set(10.0)),
    InputSlip("diameter_for_radius_in_formula",
              {"en": "{symbol} doubled inside the formula: a diameter for a radius (the stroke "
                     "for the crank radius)",
               "ru": "{symbol} удвоен в формуле: диаметр вместо радиуса (ход поршня вместо "
                     "радиуса кривошипа)"},
              _radius_or_diameter, _scaled(2.0)),
    InputSlip("radius_for_diameter_in_formula",
              {"en": "{symbol} halved inside the formula: a radius for a diameter (the crank "
                     "radius for the stroke)",
               "ru": "{symbol} уменьшен вдвое в формуле: радиус вместо диаметра (радиус "
                     "кривошипа вместо хода)"},
              _radius_or_diameter, _scaled(0.5)),
    InputSlip("diameters_for_radii_in_formula",
              {"en": "{symbol} all doubled inside the formula: diameters for radii (J ×16 "
                     "and m ×4 of a body of revolution)",
               "ru": "{symbol} все удвоены в формуле: диаметры вместо радиусов (J ×16 и m ×4 "
                     "тела вращения)"},
              _radius_or_diameter, _scaled(2.0), together=True, alone=False),
    InputSlip("radii_for_diameters_in_formula",
              {"en": "{symbol} all halved inside the formula: radii for diameters",
               "ru": "{symbol} все уменьшены вдвое в формуле: радиусы вместо диаметров"},
              _radius_or_diameter, _scaled(0.5), together=True, alone=False),
    InputSlip("period_not_squared",
              {"en": "T used for T² (the period of {symbol} not squared)",
               "ru": "T вместо T² (период по {symbol} не возведён в квадрат)"},
              lambda f: _unit_is(TIME)(f) and f.repeated, _period_not_squared, together=True),
)
"""The slips of a formula's inputs, in the order they are tried."""


def slipped_inputs(inputs: Inputs) -> Iterator[tuple[InputSlip, str, Inputs]]:
    """Every input slip the inputs allow: the slip, the symbol(s) of the inputs it changes
    (``section.field`` where the symbol repeats), and the inputs as it leaves them. A lab
    whose inputs name a recording is reduced again as any (its analysis of a recording the
    slip leaves as it was is reused inside a check: :mod:`processing.inputs.reuse`)."""
    spec = inputs.spec
    if spec is None:
        return
    for section in spec.sections:
        if section.name not in inputs:
            continue
        for slip in INPUT_SLIPS:
            fields = [f for f in section.fields if slip.fits(f)]
            if slip.together:
                groups = [fields] if len(fields) > 1 or (fields and slip.alone) else []
            else:
                groups = [[f] for f in fields]
            for group in groups:
                changed = _changed(inputs, section.name, group, slip)
                if changed is not None:
                    yield slip, ", ".join(f.display_symbol for f in group), changed


def _entries(inputs: Inputs, section: str) -> list[dict]:
    entry = inputs[section]
    return entry if isinstance(entry, list) else [entry]


def _changed(inputs: Inputs, section: str, fields: list[Field],
             slip: InputSlip) -> Inputs | None:
    """The inputs with ``fields`` of ``section`` slipped (in every entry of a ``many``
    section), or None where no entry holds one."""
    entries, touched = [], False
    for entry in _entries(inputs, section):
        new = dict(entry)
        for f in fields:
            if isinstance(entry.get(f.name), Measured):
                slipped = slip.change(entry[f.name], entry)
                if slipped is not None:
                    new[f.name] = slipped
                    touched = True
        entries.append(new)
    if not touched:
        return None
    many = isinstance(inputs[section], list)
    return replace(inputs, sections={**inputs.sections,
                                     section: entries if many else entries[0]})
