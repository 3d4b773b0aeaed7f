"""Judging a student's reported values against a reduction: right, rounded, over-precise,
wrong (with the classic slip that explains it) or missing.

A reported value r (± its own u_r, if the student gave one) is set against our value x ± u
by two tests, either of which passes it, as a teacher's quiz does (Moodle's and STACK's
relative tolerance, a z-score where both sides state an uncertainty):

* the relative tolerance of the teacher's :class:`Policy`, |r − x| ≤ tol·|x|, widened by
  half a unit of the last digit the student wrote (a value rounded to its digits is not
  wrong for that);
* the z-score z = (r − x)/u, |z| ≤ k, the coverage factor of our U = k·u (2, or Student's t
  for the effective degrees of freedom where few readings dominate:
  :func:`processing.uncertainty.coverage_factor`), so that a value inside the interval the
  report states agrees.

The teacher's tolerance comes first: a student's own u widens the z-score,
z = (r − x)/√(u² + u_r²), only where the policy allows it (:attr:`Policy.student_u`) and only
where that u is plausible — no larger than :data:`STUDENT_U_MAX` times ours, what the same
measurement can justify. A u claimed wider earns nothing (a slip of +16 % "covered" by a u of
12 % stays wrong).

A right value written to fewer significant figures than the policy asks is *rounded*; one
written far beyond its uncertainty (its last digit below a thousandth of U = k·u) is
*over-precise*. A wrong value is tried against each candidate :class:`Slip` — the value the
student would have got through it, a known factor of ours (×1000, rpm taken as rad/s,
degrees as radians, 2π dropped, diameter for radius) or a lab's own slip re-reduced from
slipped inputs (the platform not subtracted, the wrong pivot distance) — by the same tests;
of those that fit, the one nearest the student's value (and nearer than ours) names the likely
cause.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import cache

from processing.diagnostics import InputError

VERDICTS = ("right", "rounded", "over-precise", "wrong", "missing", "unreadable")
"""Every verdict, best first."""

OVER_PRECISE = 1e-3
"""A value whose last written digit is worth less than this share of its U = k·u is
over-precise: GUM rounds U to two figures and the value to the same place (about U/10 to
U/100); one digit more is tolerated, two are not."""

STUDENT_U_MAX = 2.0
"""Largest plausible student's u, in units of ours: the same readings evaluated more coarsely
(a Type B bound for a repeated reading, a rounded constant) may double u; a wider u is more
than the measurement can justify and widens nothing."""

Z_LIMIT = 2.0
"""|z| up to which a reported value agrees with ours where our u has infinite degrees of
freedom (about 95 %); the caller gives the coverage factor of its own U otherwise."""


@dataclass(frozen=True)
class Policy:
    """A teacher's tolerance for one lab.

    Parameters
    ----------
    rel_tol : float
        Relative tolerance (0.01: within 1 %).
    sig_figs : int
        Significant figures a value must be written with; fewer is *rounded*.
    expected : tuple of str
        Result names every submission must report; absent ones are *missing*.
    student_u : bool
        Whether a student's own u may widen what agrees (where it is plausible:
        :func:`counted_u`); by default only the tolerance and our own U count.
    """

    rel_tol: float = 0.01
    sig_figs: int = 3
    expected: tuple[str, ...] = ()
    student_u: bool = False


@dataclass(frozen=True)
class Reported:
    """What a student reported for one result, in SI.

    ``digits`` is how many significant figures were written and ``last_place`` the SI value
    of a unit in the last digit written (half of it is the rounding the student did)."""

    name: str
    value: float
    u: float = 0.0
    digits: int = 15
    last_place: float = 0.0


@dataclass(frozen=True)
class Slip:
    """A classic mistake: what a value would be through it.

    ``value(x)`` maps our value to the slipped one (a factor, an offset), or ``reduced``
    gives it from a re-reduction of slipped inputs; ``applies(unit)`` says whether the slip
    is possible for a result in that SI unit."""

    name: str
    text: dict[str, str]
    value: Callable[[float], float] | None = None
    applies: Callable[[str], bool] = lambda unit: True
    reduced: dict[str, float] = field(default_factory=dict)

    def candidate(self, name: str, x: float, unit: str) -> float | None:
        if self.value is not None:
            return self.value(x) if self.applies(unit) else None
        return self.reduced.get(name)


def _is(*units: str) -> Callable[[str], bool]:
    return lambda unit: unit in units


def _pressure(unit: str) -> bool:
    """Whether a result's unit is a pressure (Pa, or kg/m/s² as the coursework writes it)."""
    return _dimension(unit) == _dimension("Pa")


@cache
def _dimension(unit: str) -> str | None:
    from processing.units import dimension

    try:
        return dimension(unit)
    except Exception:                   # a unit pint cannot read has no slip of a unit
        return None


def _not_angle(unit: str) -> bool:
    """Whether a result is no angle: an angle read off a record (a phase, a lag) has no
    constant of a formula to slip."""
    return unit != "rad"


def _holds_force(unit: str) -> bool:
    """Whether a unit holds a force (mass·length/time², as N, N·m, Pa, N/m do): where a
    weight m·g is inside."""
    dims = _dimension(unit) or ""
    return "[mass]" in dims and "[time] ** -2" in dims


FACTOR_SLIPS = (
    Slip("prefix_x1000", {"en": "a unit prefix slipped (×1000: g for kg, mm for m, kN for N)",
                          "ru": "ошибка в приставке единицы (×1000: г вместо кг, мм вместо м)"},
         lambda x: 1e3 * x, lambda unit: unit != ""),
    Slip("prefix_div1000", {"en": "a unit prefix slipped (÷1000)",
                            "ru": "ошибка в приставке единицы (÷1000)"},
         lambda x: 1e-3 * x, lambda unit: unit != ""),
    Slip("rpm_as_rad_s", {"en": "min⁻¹ taken as rad/s (or the reverse): a factor π/30",
                          "ru": "мин⁻¹ принята за рад/с (или наоборот): множитель π/30"},
         lambda x: 30 / math.pi * x, _is("rad/s")),
    Slip("rad_s_as_rpm", {"en": "rad/s taken as min⁻¹: a factor 30/π",
                          "ru": "рад/с приняты за мин⁻¹: множитель 30/π"},
         lambda x: math.pi / 30 * x, _is("rad/s")),
    Slip("degrees_as_radians", {"en": "degrees taken as radians (×180/π)",
                                "ru": "градусы приняты за радианы (×180/π)"},
         lambda x: 180 / math.pi * x, _is("rad")),
    Slip("radians_as_degrees", {"en": "radians taken as degrees (×π/180)",
                                "ru": "радианы приняты за градусы (×π/180)"},
         lambda x: math.pi / 180 * x, _is("rad")),
    Slip("two_pi_dropped", {"en": "2π dropped (frequency in Hz for ω in rad/s, or the reverse)",
                            "ru": "потерян множитель 2π (частота в Гц вместо ω в рад/с)"},
         lambda x: x / (2 * math.pi), _is("rad/s", "Hz", "1/s", "s")),
    Slip("two_pi_extra", {"en": "2π too many (ω in rad/s for a frequency in Hz, or the reverse)",
                          "ru": "лишний множитель 2π"},
         lambda x: 2 * math.pi * x, _is("rad/s", "Hz", "1/s", "s")),
    Slip("diameter_for_radius", {"en": "a diameter used for a radius (×2; ×4 in a moment of "
                                       "inertia)",
                                 "ru": "диаметр взят вместо радиуса (×2; ×4 в моменте инерции)"},
         lambda x: 2 * x, _is("m")),
    Slip("diameter_for_radius_squared", {"en": "a diameter used for a radius in R² (×4)",
                                         "ru": "диаметр вместо радиуса в R² (×4)"},
         lambda x: 4 * x, _is("kg*m^2", "kg*m**2", "kg m^2")),
    Slip("radius_for_diameter", {"en": "a radius used for a diameter (÷2; ÷4 in R²)",
                                 "ru": "радиус взят вместо диаметра (÷2; ÷4 в R²)"},
         lambda x: x / 2, _is("m")),
    Slip("radius_for_diameter_squared", {"en": "a radius used for a diameter in R² (÷4)",
                                         "ru": "радиус вместо диаметра в R² (÷4)"},
         lambda x: x / 4, _is("kg*m^2", "kg*m**2", "kg m^2")),
    Slip("gauge_pressure", {"en": "gauge and absolute pressure confused (p₀ = 0.1 MPa not "
                                  "subtracted, or subtracted twice)",
                            "ru": "перепутаны избыточное и абсолютное давление (p₀ = 0,1 МПа "
                                  "не вычтено или вычтено дважды)"},
         lambda x: x + 1e5, _pressure),
    Slip("gauge_pressure_minus", {"en": "gauge and absolute pressure confused (p₀ subtracted "
                                        "where it should not be)",
                                  "ru": "перепутаны избыточное и абсолютное давление (p₀ "
                                        "вычтено лишний раз)"},
         lambda x: x - 1e5, _pressure),
)
"""Slips that act on a result through a factor or an offset, whatever the lab."""

TRANSCENDENTAL_SLIPS = (
    Slip("four_pi_squared_dropped", {"en": "4π² dropped (ω² = 4π²/T² taken as 1/T², or the "
                                           "reverse)",
                                     "ru": "потерян множитель 4π² (ω² = 4π²/T² взято как 1/T²)"},
         lambda x: x / (4 * math.pi ** 2), _not_angle),
    Slip("four_pi_squared_extra", {"en": "4π² too many", "ru": "лишний множитель 4π²"},
         lambda x: 4 * math.pi ** 2 * x, _not_angle),
    Slip("pi_for_pi_squared", {"en": "π written for π² (a factor π dropped)",
                               "ru": "π вместо π² (потерян множитель π)"},
         lambda x: x / math.pi, _not_angle),
    Slip("pi_squared_for_pi", {"en": "π² written for π (a factor π too many)",
                               "ru": "π² вместо π (лишний множитель π)"},
         lambda x: x * math.pi, _not_angle),
)
"""A formula's transcendental constants slipped (4π², π²) on a result whatever its unit: no
slip of an input makes these factors, so they are tried before any input is (cheaply)."""

CONSTANT_SLIPS = TRANSCENDENTAL_SLIPS + (
    Slip("half_dropped", {"en": "a factor ½ dropped (×2)", "ru": "потерян множитель ½ (×2)"},
         lambda x: 2 * x, _not_angle),
    Slip("two_dropped", {"en": "a factor 2 dropped (or ½ too many: ÷2)",
                         "ru": "потерян множитель 2 (или лишний ½: ÷2)"},
         lambda x: x / 2, _not_angle),
    Slip("g_as_10", {"en": "g = 10 m/s² taken for 9.81 m/s²", "ru": "принято g = 10 м/с²"},
         lambda x: x * 10 / 9.80665, lambda unit: _holds_force(unit)),
)
"""A formula's constants slipped (4π², π², ½, 2, g = 10), on a result whatever its unit: ½, 2
and g = 10 are tried last, after the slips of the inputs (:mod:`processing.checking.input_slips`),
which name the input a factor 2 came from."""

SQUARED_SPEED_SLIPS = (
    Slip("omega_for_n_squared", {"en": "ω in rad/s put for n in min⁻¹ in a square (×(30/π)²: "
                                       "e.g. the flywheel's I = 900·A/(π²·n²·δ) with ω)",
                                 "ru": "в квадрат подставлена ω в рад/с вместо n в мин⁻¹ "
                                       "(×(30/π)²: например, I маховика = 900·A/(π²·n²·δ) "
                                       "с ω)"},
         lambda x: x * (30 / math.pi) ** 2, _not_angle),
    Slip("n_for_omega_squared", {"en": "n in min⁻¹ put for ω in rad/s in a square (×(π/30)²)",
                                 "ru": "в квадрат подставлена n в мин⁻¹ вместо ω в рад/с "
                                       "(×(π/30)²)"},
         lambda x: x * (math.pi / 30) ** 2, _not_angle),
)
"""A speed squared in the wrong unit inside one formula only (the flywheel's n², while the
forces take n right): tried after every other slip, since n taken as rad/s in every formula it
enters (an input's slip, :mod:`processing.checking.input_slips`) gives the same factor on a
result that only ω² reaches, and names the input."""


@dataclass(frozen=True)
class Verdict:
    """One result judged.

    Attributes
    ----------
    name : str
    verdict : str
        One of :data:`VERDICTS`.
    reported : Reported or None
    value, u : float
        Ours, SI. (NaN for a name we do not compute.)
    z : float
        (r − x)/√(u² + u_r²), u_r the student's u as it counts (:func:`counted_u`); NaN
        where neither side states an uncertainty.
    relative : float
        (r − x)/|x|.
    slip : Slip or None
        The slip that explains a wrong value.
    problem : InputError or None
        Why an *unreadable* value could not be read, and the fix.
    """

    name: str
    verdict: str
    reported: Reported | None
    value: float
    u: float
    z: float = math.nan
    relative: float = math.nan
    slip: Slip | None = None
    problem: InputError | None = None


def counted_u(r: Reported, u: float, policy: Policy) -> float:
    """The part of a student's u that counts: all of it where the policy allows a student's
    u and it is at most :data:`STUDENT_U_MAX` times ours (``u``), else none.

    >>> r = Reported("J", 0.1749, u=0.002)
    >>> counted_u(r, 0.0012, Policy()), counted_u(r, 0.0012, Policy(student_u=True))
    (0.0, 0.002)
    >>> counted_u(Reported("J", 0.199, u=0.02), 0.0012, Policy(student_u=True))
    0.0
    """
    return r.u if policy.student_u and r.u <= STUDENT_U_MAX * u else 0.0


def agrees(r: Reported, x: float, u: float, policy: Policy, *,
           k: float = Z_LIMIT) -> tuple[bool, float, float]:
    """Whether ``r`` agrees with x ± u by the policy's tolerance or by |z| ≤ k (the coverage
    factor of our U = k·u; the student's u in it only as :func:`counted_u` allows); z and the
    relative difference."""
    rel = (r.value - x) / abs(x) if x else (math.inf if r.value else 0.0)
    combined = math.hypot(u, counted_u(r, u, policy))
    z = (r.value - x) / combined if combined > 0 else math.nan
    tolerance = policy.rel_tol * abs(x) + 0.5 * r.last_place
    ok = abs(r.value - x) <= tolerance or (combined > 0 and abs(z) <= k)
    return ok, z, rel


def judge(name: str, reported: Reported | None, value: float, u: float, unit: str,
          policy: Policy = Policy(), slips: Iterable[Slip] = FACTOR_SLIPS, *,
          k: float = Z_LIMIT) -> Verdict:
    """Judge one reported value against ours.

    Parameters
    ----------
    name : str
        The result's name.
    reported : Reported or None
        The student's value; None: *missing*.
    value, u : float
        Our value and its standard uncertainty, SI.
    unit : str
        The result's SI unit (which slips are possible).
    policy : Policy
    slips : iterable of Slip
        Candidates for a wrong value, tried in order.
    k : float
        The coverage factor of our expanded uncertainty U = k·u (the report's and the JSON's
        ``k``): a reported value within U of ours agrees.

    Returns
    -------
    Verdict

    Examples
    --------
    >>> judge("omega", Reported("omega", 188.5, digits=4, last_place=0.1), 188.496, 0.2,
    ...       "rad/s").verdict
    'right'
    >>> v = judge("omega", Reported("omega", 1800.0, digits=4, last_place=1.0), 188.496, 0.2,
    ...           "rad/s")
    >>> v.verdict, v.slip.name
    ('wrong', 'rpm_as_rad_s')
    """
    if reported is None:
        return Verdict(name, "missing", None, value, u)
    ok, z, rel = agrees(reported, value, u, policy, k=k)
    if ok:
        scale = k * max(u, counted_u(reported, u, policy))
        if reported.digits < policy.sig_figs and abs(rel) > 1e-12:
            verdict = "rounded"
        elif scale > 0 and reported.last_place < OVER_PRECISE * scale and reported.digits > 3:
            verdict = "over-precise"
        else:
            verdict = "right"
        return Verdict(name, verdict, reported, value, u, z, rel)
    best, closest = None, math.inf
    for slip in slips:
        s = slip.candidate(name, value, unit)
        if s is None or not math.isfinite(s):
            continue
        ok, _, rel_s = agrees(reported, s, u * abs(s / value) if value else u, policy, k=k)
        if ok and abs(rel_s) < min(closest, abs(rel)):
            best, closest = slip, abs(rel_s)
    return Verdict(name, "wrong", reported, value, u, z, rel, best)


_NUMBER = re.compile(r"^\s*([-+]?)(\d*)(?:\.(\d*))?(?:[eE]([-+]?\d+))?")


def written_digits(text: str) -> tuple[int, int]:
    """Significant figures of the number a text starts with, and the decimal exponent of its
    last digit (``"0.01230 kg"`` → (4, −5); ``"1500 rpm"`` → (2, 2): an integer's trailing
    zeros are not counted as significant).

    Examples
    --------
    >>> written_digits("0.01230 kg*m^2"), written_digits("1500"), written_digits("2.5e3 N")
    ((4, -5), (2, 2), (2, 2))
    """
    m = _NUMBER.match(text)
    whole, frac, exp = m.group(2) or "", m.group(3), int(m.group(4) or 0)
    if frac is None:
        stripped = whole.lstrip("0")
        zeros = len(stripped) - len(stripped.rstrip("0"))
        digits = max(len(stripped) - zeros, 1)
        return digits, zeros + exp
    mantissa = (whole + frac).lstrip("0")
    return max(len(mantissa), 1), exp - len(frac)
