"""Lab 1. Moments of inertia of engine parts.

The manual's chapter, method by method: the analytic sum over regular bodies (formulas 1–6),
the unifilar torsion pendulum (7–12), the physical pendulum (13–16) and the trifilar
suspension (17). Each function is the formula; :func:`reduce` takes a measurement file's
inputs through them with uncertainties and compares the methods.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 1 ("Определение моментов инерции деталей двигателя").
"""
from __future__ import annotations

import itertools
import warnings
from pathlib import Path

import numpy as np

from processing.diagnostics import IllConditionedWarning, collect_notices
from processing.measurement import (AMPLITUDE, COUNT, GRAVITY, LENGTH, MASS, STOPWATCH, Field,
                                    Inputs, LabSpec, ReadingsTable, Section, bi,
                                    period_columns)
from processing.oscillations.oscillation import (check_amplitude, pendulum_period_factor,
                                                 period_factor, period_from_total)
from processing.numerals import plural
from processing.reporting.content import fmt_pm
from processing.reporting.figures import method_chart
from processing.result import (KEY, SIGNED, STRICTLY_POSITIVE, Figure, LabResult, Table,
                               compare, flag_estimates, result_values)
from processing.uncertainty import Measured, propagate
from processing.vision.video import MARKER_FIELDS, film_figures, filmed_times


# ------------------------------------------------------------------------ formulas

def cylinder(m, R, r=0.0, h=0.0, *, axis="axial"):
    """Moment of inertia of a solid (r = 0) or hollow cylinder about its own axis or a
    transverse axis through its centre of mass.

    Parameters
    ----------
    m : float or ndarray
        Mass. [kg]
    R, r : float or ndarray
        Outer and inner radius. [m]
    h : float or ndarray
        Height (length along the axis); used only for ``axis="transverse"``. [m]
    axis : {"axial", "transverse"}

    Returns
    -------
    float or ndarray
        J. [kg·m²]

    Notes
    -----
    Lab manual, lab 1, formulas (1) and (2):

    .. math:: J_z = \\frac{m}{2}(R^2 + r^2), \\qquad
              J_x = J_y = \\frac{m}{12}(3R^2 + 3r^2 + h^2)

    Examples
    --------
    >>> round(cylinder(2.0, 0.1), 12)
    0.01
    """
    if axis == "axial":
        return 0.5 * m * (R**2 + r**2)
    return m * (3 * R**2 + 3 * r**2 + h**2) / 12.0


def thin_rod(m, l, *, axis="end"):
    """Moment of inertia of a thin rod about a transverse axis at its end or centre.

    Notes
    -----
    Lab manual, lab 1, formula (3): :math:`J = m l^2/3` about the end; :math:`m l^2/12` about
    the centre.

    Examples
    --------
    >>> thin_rod(3.0, 1.0)
    1.0
    """
    return m * l**2 / (3.0 if axis == "end" else 12.0)


def torus(m, R, r, *, axis="axial"):
    """Moment of inertia of a ring of circular cross-section (torus).

    Parameters
    ----------
    m : float or ndarray
        Mass. [kg]
    R : float or ndarray
        Radius of the ring's centre line. [m]
    r : float or ndarray
        Radius of the cross-section. [m]
    axis : {"axial", "transverse"}
        The symmetry axis, or a diameter.

    Notes
    -----
    Lab manual, lab 1, formulas (4) and (5):

    .. math:: J_z = m\\left(R^2 + \\tfrac34 r^2\\right), \\qquad
              J_x = m\\left(\\tfrac{R^2}{2} + \\tfrac58 r^2\\right)
    """
    if axis == "axial":
        return m * (R**2 + 0.75 * r**2)
    return m * (0.5 * R**2 + 0.625 * r**2)


def parallel_axis(J_c, m, c):
    """Steiner's theorem, lab manual, lab 1, formula (6): :math:`J = J_c + m c^2`."""
    return J_c + m * c**2


def trifilar_height(l, R1, R2):
    """Vertical height of a trifilar suspension at rest: :math:`H = \\sqrt{l^2 - (R_1 - R_2)^2}`.

    The manual's formula (17) writes the thread length l; for R₁ ≠ R₂ the threads slant and
    the height H is what enters the restoring torque.
    """
    return np.sqrt(l**2 - (R1 - R2) ** 2)


def trifilar(period, m, R1, R2, l, g):
    """Moment of inertia on a trifilar suspension from the small-twist period.

    Parameters
    ----------
    period : float or ndarray
        Small-twist period of one full oscillation. [s]
    m : float or ndarray
        Mass hanging on the threads. [kg]
    R1, R2 : float or ndarray
        Radii of the thread points on the upper and the lower disc. [m]
    l : float or ndarray
        Thread length. [m]
    g : float or ndarray
        Local acceleration of gravity. [m/s²]

    Returns
    -------
    float or ndarray
        J about the vertical axis. [kg·m²]

    Notes
    -----
    Lab manual, lab 1, formula (17), with the vertical height H instead of l (equal when
    R₁ = R₂):

    .. math:: J = \\frac{T^2 m g R_1 R_2}{4\\pi^2 H}, \\qquad H = \\sqrt{l^2 - (R_1 - R_2)^2}
    """
    return period**2 * m * g * R1 * R2 / (4 * np.pi**2 * trifilar_height(l, R1, R2))


def trifilar_period_factor(amplitude, m, J, R1, R2, l):
    """T(φ₀)/T₀ of a trifilar suspension twisted by φ₀, from its exact geometry.

    The platform rises by H − h(φ) with h(φ)² = l² − R₁² − R₂² + 2R₁R₂ cos φ; the kinetic
    energy includes that vertical motion, ½(J + m h'²)φ̇². The period integral is evaluated by
    :func:`processing.oscillations.oscillation.period_factor`.

    Parameters
    ----------
    amplitude : float or ndarray
        Twist amplitude φ₀. [rad]
    m, J : float or ndarray
        Mass [kg] and (approximate) moment of inertia [kg·m²] of what hangs.
    R1, R2, l : float or ndarray
        Geometry as in :func:`trifilar`. [m]
    """
    H = trifilar_height(l, R1, R2)

    def h(phi):
        return np.sqrt(H**2 - 4 * R1 * R2 * np.sin(0.5 * phi) ** 2)

    def potential(phi):
        return m * 4 * R1 * R2 * np.sin(0.5 * phi) ** 2 / (H + h(phi))

    def inertia(phi):
        return J + m * (R1 * R2 * np.sin(phi) / h(phi)) ** 2

    return period_factor(amplitude, potential, inertia, m * R1 * R2 / H)


def wire_stiffness(G, d, l):
    """Torsional stiffness of a round wire, lab manual, lab 1, formula (11).

    .. math:: c = \\frac{G J_p}{l}, \\qquad J_p = \\frac{\\pi d^4}{32}

    (the OCR of the manual prints d²: the polar moment of a circle is πd⁴/32).

    Parameters
    ----------
    G : float or ndarray
        Shear modulus of the wire. [Pa]
    d, l : float or ndarray
        Wire diameter and free length. [m]

    Returns
    -------
    float or ndarray
        c. [N·m/rad]
    """
    return G * np.pi * d**4 / (32.0 * l)


def unifilar_reference(period, period_ref, J_ref, period_empty=0.0):
    """Unifilar torsion pendulum compared with a reference body ("English method").

    Parameters
    ----------
    period, period_ref : float or ndarray
        Periods with the part and with the reference body in the clamp. [s]
    J_ref : float or ndarray
        Moment of inertia of the reference body, usually a cylinder m r²/2. [kg·m²]
    period_empty : float or ndarray
        Period of the empty clamp, 0 to neglect the clamp's inertia. [s]

    Notes
    -----
    Lab manual, lab 1, formula (12), with the clamp's inertia removed when it was timed:

    .. math:: J = J_{ref}\\frac{T^2 - T_0^2}{T_{ref}^2 - T_0^2}
    """
    return J_ref * (period**2 - period_empty**2) / (period_ref**2 - period_empty**2)


def unifilar_wire(period, stiffness, period_empty=0.0):
    """Unifilar torsion pendulum from the wire's stiffness, formula (10):
    :math:`J = c (T^2 - T_0^2) / 4\\pi^2`."""
    return stiffness * (period**2 - period_empty**2) / (4 * np.pi**2)


def physical_pendulum(period, m, c, g):
    """Moment of inertia about the pivot of a physical pendulum, formula (15).

    .. math:: J = \\frac{T^2}{4\\pi^2} m g c

    Parameters
    ----------
    period : float or ndarray
        Small-swing period. [s]
    m : float or ndarray
        Mass. [kg]
    c : float or ndarray
        Distance from the pivot to the centre of mass. [m]
    g : float or ndarray
        Local acceleration of gravity. [m/s²]

    Examples
    --------
    A point mass on a string of 1 m: T = 2π√(l/g), J = m l².

    >>> g = 9.81
    >>> round(float(physical_pendulum(2 * np.pi * np.sqrt(1 / g), 2.0, 1.0, g)), 12)
    2.0
    """
    return period**2 * m * g * c / (4 * np.pi**2)


# -------------------------------------------------------------------- the measurement file

PART_LENGTH = {**LENGTH, "plausible": ("1 mm", "1000 mm")}
"""A part's dimensions on the caliper or the ruler, a bolt hole's to a flywheel's rim."""

RIG_RADIUS = {**LENGTH, "plausible": ("10 mm", "500 mm")}
"""Radii of the trifilar suspension's thread points on its discs."""

SUSPENSION = {**LENGTH, "plausible": ("100 mm", "3000 mm")}
"""Lengths of a suspension's threads or wire."""

SHAPES = {"cylinder": bi("cylinder", "цилиндр"), "thin_rod": bi("thin rod", "тонкий стержень"),
          "torus": bi("torus", "тор"), "point_mass": bi("point mass", "точечная масса")}
"""The simple bodies of the analytic model, as a report names them."""

AXES = {"axial": bi("axial", "продольная"), "transverse": bi("transverse", "поперечная"),
        "end": bi("transverse, through the end", "поперечная, через торец"),
        "centre": bi("transverse, through the centre", "поперечная, через центр")}
"""The axes of a simple body the model's inertia is taken about, as a report names them."""

SPEC = LabSpec(
    id="lab1", number="1",
    title=bi("Moments of inertia of engine parts", "Определение моментов инерции деталей двигателя"),
    goal=bi("To study the experimental methods of finding the axial moment of inertia of engine "
            "parts and to compare them with the analytic value.",
            "Изучить экспериментальные методы определения осевого момента инерции деталей "
            "двигателя и сравнить их с расчётным значением."),
    sections=(
        Section("body", bi("The part", "Деталь"), required=True, fields=(
            Field("m", bi("mass of the part", "масса детали"), **MASS, example="12.345 kg"),
            Field("g", bi("local acceleration of gravity", "ускорение свободного падения"),
                  **GRAVITY),
        )),
        Section("analytic", bi("Analytic method: the part as regular bodies",
                               "Расчётный метод: деталь как сумма тел правильной формы"),
                many=True,
                help=bi("One [[analytic]] table per part; holes with hole = true. Give the mass m\n"
                        "or the density rho. offset = distance of the part's axis from the axis of\n"
                        "rotation; count = number of identical parts at that offset.",
                        "Одна таблица [[analytic]] на каждую часть; отверстия: hole = true. Масса m\n"
                        "или плотность rho. offset — смещение оси части от оси вращения;\n"
                        "count — число одинаковых частей."),
                fields=(
            Field("shape", bi("shape", "форма"), kind="choice",
                  choices=SHAPES),
            Field("axis", bi("axis", "ось"), kind="choice", default="axial",
                  choices=AXES),
            Field("m", bi("mass of the part", "масса части"), **MASS, required=False),
            Field("rho", bi("density (instead of m)", "плотность (вместо m)"), unit="kg/m^3",
                  limit="100 kg/m^3", required=False, symbol="ρ", example="7200",
                  plausible=("500 kg/m^3", "20000 kg/m^3")),
            Field("R", bi("outer radius (torus: centre-line radius)",
                          "наружный радиус (тор: радиус средней линии)"), **PART_LENGTH,
                  required=False),
            Field("r", bi("inner radius (torus: section radius)",
                          "внутренний радиус (тор: радиус сечения)"), **PART_LENGTH,
                  required=False, allow_zero=True),
            Field("h", bi("height along the axis", "высота вдоль оси"), **PART_LENGTH,
                  required=False),
            Field("l", bi("rod length", "длина стержня"), **PART_LENGTH, required=False),
            Field("offset", bi("distance from the axis of rotation", "расстояние до оси вращения"),
                  **PART_LENGTH, required=False, allow_zero=True, symbol="c"),
            Field("count", bi("number of identical parts", "число одинаковых частей"),
                  kind="count", default=1),
            Field("hole", bi("a hole (subtracted)", "отверстие (вычитается)"), kind="flag",
                  default=False),
        )),
        Section("trifilar", bi("Trifilar suspension", "Трёхнитяный подвес"), fields=(
            Field("R1", bi("radius of the thread points, upper disc",
                           "радиус точек крепления нитей на верхнем диске"), **RIG_RADIUS,
                  symbol="R₁"),
            Field("R2", bi("radius of the thread points, lower platform",
                           "радиус точек крепления нитей на нижнем диске"), **RIG_RADIUS,
                  symbol="R₂"),
            Field("l", bi("thread length", "длина нити"), **SUSPENSION),
            Field("n_osc", bi("full oscillations timed (a film needs none)",
                               "число полных колебаний (для видео не нужно)"),
                  **COUNT, required=False),
            Field("t", bi("time of n_osc oscillations, part on the platform",
                          "время n колебаний, деталь на платформе"),
                  **{**STOPWATCH, "required": False}),
            Field("video", bi("or: a film of the swing, part on the platform (MP4, MOV, AVI; "
                              "a marker on the platform's edge)",
                              "или: видео качаний платформы с деталью (MP4, MOV, AVI; метка на "
                              "краю платформы)"), kind="file", required=False),
            *MARKER_FIELDS,
            Field("m_p", bi("mass of the empty platform", "масса пустой платформы"), **MASS,
                  required=False, symbol="m_p"),
            Field("t_p", bi("time of n_osc oscillations, empty platform",
                            "время n колебаний пустой платформы"), **STOPWATCH, required=False,
                  symbol="t_p"),
            Field("video_p", bi("or: a film of the empty platform's swing",
                                "или: видео качаний пустой платформы"), kind="file",
                  required=False),
            Field("amplitude", bi("twist amplitude", "амплитуда закрутки"), **AMPLITUDE),
        )),
        Section("unifilar", bi("Unifilar torsion pendulum", "Унифилярный подвес"), fields=(
            Field("n_osc", bi("full oscillations timed (a film needs none)",
                               "число полных колебаний (для видео не нужно)"),
                  **COUNT, required=False),
            Field("t", bi("time of n_osc oscillations with the part",
                          "время n колебаний с деталью"), **{**STOPWATCH, "required": False}),
            Field("video", bi("or: a film of the twist with the part (a marker on it)",
                              "или: видео крутильных колебаний с деталью (метка на ней)"),
                  kind="file", required=False),
            *MARKER_FIELDS,
            Field("t_0", bi("time of n_osc oscillations of the empty clamp",
                            "время n колебаний пустого подвеса"), **STOPWATCH, required=False,
                  symbol="t₀"),
            Field("video_0", bi("or: a film of the empty clamp's twist",
                                "или: видео колебаний пустого подвеса"), kind="file",
                  required=False),
            Field("t_ref", bi("time of n_osc oscillations with the reference body",
                              "время n колебаний с эталоном"), **STOPWATCH, required=False,
                  symbol="t_э"),
            Field("video_ref", bi("or: a film of the twist with the reference body",
                                  "или: видео колебаний с эталоном"), kind="file",
                  required=False),
            Field("J_ref", bi("reference body's moment of inertia", "момент инерции эталона"),
                  unit="kg*m^2", required=False, symbol="J_э",
                  plausible=("1e-4 kg*m^2", "10 kg*m^2")),
            Field("m_ref", bi("reference cylinder's mass (instead of J_ref)",
                              "масса эталонного цилиндра (вместо J_э)"), **MASS, required=False),
            Field("d_ref", bi("reference cylinder's diameter", "диаметр эталонного цилиндра"),
                  unit="mm", limit="0.05 mm", required=False, plausible=("10 mm", "1000 mm")),
            Field("G", bi("shear modulus of the wire", "модуль сдвига проволоки"), unit="GPa",
                  limit="2 GPa", required=False, example="79 GPa for steel",
                  plausible=("20 GPa", "100 GPa")),
            Field("d", bi("wire diameter", "диаметр проволоки"), unit="mm", limit="0.005 mm",
                  required=False, plausible=("0.3 mm", "10 mm")),
            Field("l", bi("wire length", "длина проволоки"), **SUSPENSION, required=False),
        )),
        Section("pendulum", bi("Physical pendulum", "Физический маятник"), fields=(
            Field("c", bi("distance from the pivot to the centre of mass",
                          "расстояние от оси подвеса до центра масс"), **PART_LENGTH),
            Field("n_osc", bi("full oscillations timed (a film needs none)",
                               "число полных колебаний (для видео не нужно)"),
                  **COUNT, required=False),
            Field("t", bi("time of n_osc oscillations", "время n колебаний"),
                  **{**STOPWATCH, "required": False}),
            Field("video", bi("or: a film of the swing (MP4, MOV, AVI; a marker on the part)",
                              "или: видео качаний (MP4, MOV, AVI; метка на детали)"),
                  kind="file", required=False),
            *MARKER_FIELDS,
            Field("amplitude", bi("swing amplitude", "амплитуда качаний"), **AMPLITUDE),
        )),
    ),
    readings=(
        ReadingsTable(bi("Trifilar suspension: the part on the platform (t) and the empty "
                         "platform (t_p)", "Трёхнитяный подвес: деталь на платформе (t) и "
                         "пустая платформа (t_p)"), "trifilar",
                      period_columns("n_osc", {"t": "t", "t_p": "t_p"})),
        ReadingsTable(bi("Unifilar pendulum: with the part (t), the empty clamp (t_0), the "
                         "reference body (t_ref)", "Унифилярный подвес: с деталью (t), пустой "
                         "зажим (t_0), эталон (t_ref)"), "unifilar",
                      period_columns("n_osc", {"t": "t", "t_0": "t_0", "t_ref": "t_ref"})),
        ReadingsTable(bi("Physical pendulum", "Физический маятник"), "pendulum",
                      period_columns("n_osc", {"t": "t"})),
    ),
)

FILMS = {"trifilar": {"video": "t", "video_p": "t_p"}, "pendulum": {"video": "t"},
         "unifilar": {"video": "t", "video_0": "t_0", "video_ref": "t_ref"}}
"""The films that may stand for the stopwatch (:func:`processing.vision.video.filmed_times`)."""

RESULTS = {name: (label, symbol, unit, STRICTLY_POSITIVE, *((KEY,) if unit == "kg*m^2" else ()))
           for name, (label, symbol, unit) in {
    "J_analytic": (bi("analytic (sum of regular bodies)", "расчётный (сумма простых тел)"),
                   "J_an", "kg*m^2"),
    "J_trifilar": (bi("trifilar suspension", "трёхнитяный подвес"), "J_tr", "kg*m^2"),
    "J_unifilar": (bi("unifilar, reference body", "унифиляр, по эталону"), "J_un", "kg*m^2"),
    "J_unifilar_wire": (bi("unifilar, from the wire's stiffness", "унифиляр, по жёсткости"),
                        "J_un,c", "kg*m^2"),
    "J_pendulum_pivot": (bi("physical pendulum, about the pivot", "физический маятник, ось подвеса"),
                         "J_O", "kg*m^2"),
    "J_pendulum_cm": (bi("physical pendulum, about the centre of mass",
                         "физический маятник, ось через центр масс"), "J_c", "kg*m^2"),
    "m_analytic": (bi("mass of the analytic model", "масса расчётной модели"), "m_an", "kg"),
    "m_measured": (bi("mass, weighed", "масса, взвешиванием"), "m", "kg"),
}.items()}
"""Every result of the lab, each above zero by its nature; the moments of inertia are its
key results."""
CENTRAL = ("J_analytic", "J_trifilar", "J_unifilar", "J_unifilar_wire", "J_pendulum_cm")

FORMULAS = [
    bi("Analytic: J = Σ ± (J_c + m c²); cylinder J_z = m(R² + r²)/2, "
       "J_x = m(3R² + 3r² + h²)/12; rod m l²/3; torus J_z = m(R² + 3r²/4)  (1)–(6)",
       "Расчёт: J = Σ ± (J_c + m c²); цилиндр J_z = m(R² + r²)/2, "
       "J_x = m(3R² + 3r² + h²)/12; стержень m l²/3; тор J_z = m(R² + 3r²/4)  (1)–(6)"),
    bi("Period from the stopwatch: T = t/n; finite amplitude: T₀ = T·π/(2K(sin²(θ₀/2)))",
       "Период по секундомеру: T = t/n; конечная амплитуда: T₀ = T·π/(2K(sin²(θ₀/2)))"),
    bi("Trifilar: J = T² m g R₁R₂/(4π² H), H = √(l² − (R₁ − R₂)²); platform subtracted: "
       "J = g R₁R₂[(m + m_p)T² − m_p T_p²]/(4π² H)  (17)",
       "Трифиляр: J = T² m g R₁R₂/(4π² H), H = √(l² − (R₁ − R₂)²); с вычетом платформы: "
       "J = g R₁R₂[(m + m_p)T² − m_p T_p²]/(4π² H)  (17)"),
    bi("Unifilar: J = J_ref (T² − T₀²)/(T_ref² − T₀²)  (12); from the wire: "
       "J = c(T² − T₀²)/(4π²), c = G π d⁴/(32 l)  (10), (11)",
       "Унифиляр: J = J_э (T² − T₀²)/(T_э² − T₀²)  (12); по жёсткости: "
       "J = c(T² − T₀²)/(4π²), c = G π d⁴/(32 l)  (10), (11)"),
    bi("Physical pendulum: J_O = T² m g c/(4π²)  (15); J_c = J_O − m c²  (16)",
       "Физический маятник: J_O = T² m g c/(4π²)  (15); J_c = J_O − m c²  (16)"),
]
def _platform_kept(inputs: Inputs) -> Inputs | None:
    """The trifilar's empty platform not subtracted: the part and the platform timed together
    taken for the part, J = g R₁R₂ (m + m_p) T²/(4π² H) without − m_p T_p²."""
    tri = inputs.sections.get("trifilar")
    if not tri or "m_p" not in tri or "t_p" not in tri:
        return None
    both = Measured(inputs["body"]["m"].value + tri["m_p"].value)
    return inputs.changed("body", m=both).changed("trifilar", m_p=None, t_p=None)


SLIPS = [
    ("platform_not_subtracted",
     bi("the empty platform not subtracted: J of the part and the platform together",
        "не вычтен момент инерции пустой платформы: J детали вместе с платформой"),
     ("J_trifilar",), _platform_kept),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the inputs as the slip leaves them."""


REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, lab 1.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: ВлГУ, 2003. Лаб. работа №1."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]


# ------------------------------------------------------------------------ reduction

def _part(x, key, part):
    """J and m of one analytic part (signed: holes are negative)."""
    def get(name, default=0.0):
        return x.get(f"{key}.{name}", default)

    shape, axis = part["shape"], part["axis"]
    R, r, h, l = get("R"), get("r"), get("h"), get("l")
    if "m" in part:
        m = get("m")
    elif shape == "cylinder":
        m = get("rho") * np.pi * (R**2 - r**2) * h
    else:
        m = get("rho") * 2 * np.pi**2 * R * r**2
    if shape == "cylinder":
        J = cylinder(m, R, r, h, axis=axis)
    elif shape == "torus":
        J = torus(m, R, r, axis=axis)
    elif shape == "thin_rod":
        J = thin_rod(m, l, axis=axis)
    else:
        J = 0.0 * m
    sign = -1.0 if part["hole"] else 1.0
    n = part["count"]
    return sign * n * parallel_axis(J, m, get("offset")), sign * n * m


_NEEDS = {"cylinder": ("R",), "torus": ("R", "r"), "thin_rod": ("l",), "point_mass": ("offset",)}
_AXES = {"cylinder": ("axial", "transverse"), "torus": ("axial", "transverse"),
         "thin_rod": ("end", "centre"), "point_mass": ("axial",)}


def _check_part(inputs: Inputs, i: int, part: dict) -> None:
    where = f"analytic[{i}]"
    shape = part["shape"]
    for name in _NEEDS[shape]:
        if name not in part:
            raise inputs.error(f"a {shape} needs '{name}'", f"add {name} = ... to this part",
                               f"{where}.{name}")
    if part["axis"] not in _AXES[shape]:
        raise inputs.error(f"axis '{part['axis']}' does not apply to a {shape}",
                           f"use one of {', '.join(_AXES[shape])}", f"{where}.axis")
    if ("m" in part) == ("rho" in part):
        raise inputs.error("give exactly one of the mass m or the density rho",
                           "weigh the part (m) or give its material's density (rho)",
                           f"{where}.m")
    if "rho" in part and shape not in ("cylinder", "torus"):
        raise inputs.error(f"the mass of a {shape} cannot follow from a density",
                           "give its mass m", f"{where}.rho")
    if shape == "cylinder" and "rho" in part and "h" not in part:
        raise inputs.error("a cylinder given by its density needs its height h",
                           "add h = ... (the part's length along its axis)", f"{where}.h")
    if "r" in part and "R" in part and part["r"].value >= part["R"].value and shape == "cylinder":
        raise inputs.error("the inner radius r is not smaller than the outer radius R",
                           "check R and r (radii, not diameters)", f"{where}.r")


def _check_sections(inputs: Inputs) -> None:
    methods = [s for s in ("analytic", "trifilar", "unifilar", "pendulum") if s in inputs]
    if not methods:
        raise inputs.error("no method measured", "add at least one of the sections [[analytic]], "
                           "[trifilar], [unifilar], [pendulum]", "trifilar")
    if "trifilar" in inputs:
        tr = inputs["trifilar"]
        if ("m_p" in tr) != ("t_p" in tr):
            missing = "t_p" if "m_p" in tr else "m_p"
            raise inputs.error("the empty platform needs both its mass m_p and its time t_p",
                               f"add {missing}, or remove both", f"trifilar.{missing}")
        if abs(tr["R1"].value - tr["R2"].value) >= tr["l"].value:
            raise inputs.error("the threads are shorter than the difference of the radii",
                               "check l, R1, R2 (radii, not diameters; l in mm)", "trifilar.l")
    if "unifilar" in inputs:
        un = inputs["unifilar"]
        by_ref = "t_ref" in un
        by_wire = all(k in un for k in ("G", "d", "l"))
        if not by_ref and not by_wire:
            raise inputs.error("the unifilar needs a reference body (t_ref with J_ref or "
                               "m_ref and d_ref) or the wire (G, d, l)",
                               "add t_ref and J_ref, or G, d and l", "unifilar.t_ref")
        if by_ref and "J_ref" not in un and not ("m_ref" in un and "d_ref" in un):
            raise inputs.error("the reference body needs J_ref, or m_ref and d_ref",
                               "add J_ref = ..., or the cylinder's m_ref and d_ref",
                               "unifilar.J_ref")
        if "t_0" in un:
            for key in ("t", "t_ref"):
                if key in un and un[key].value <= un["t_0"].value:
                    raise inputs.error(f"{key} is not longer than the empty clamp's t_0",
                                       "a body in the clamp must slow it down: check the times",
                                       f"unifilar.{key}")
    for i, part in enumerate(inputs.sections.get("analytic", [])):
        _check_part(inputs, i, part)


def _model(inputs: Inputs):
    """The lab's measurement model: named SI inputs → every result (vectorised)."""
    secs = inputs.sections

    def model(**x):
        out = {"m_measured": x["body.m"] + 0.0}
        m, g = x["body.m"], x["body.g"]
        if "analytic" in secs:
            parts = [_part(x, f"analytic[{i}]", p) for i, p in enumerate(secs["analytic"])]
            for i, (J, mp) in enumerate(parts):
                out[f"J_part_{i}"] = J
                out[f"m_part_{i}"] = mp
            out["J_analytic"] = sum(p[0] for p in parts)
            out["m_analytic"] = sum(p[1] for p in parts)
        if "trifilar" in secs:
            tr = secs["trifilar"]
            R1, R2, l = x["trifilar.R1"], x["trifilar.R2"], x["trifilar.l"]
            amp = x.get("trifilar.amplitude", 0.0)

            def j_small(period, mass):
                J0 = trifilar(period, mass, R1, R2, l, g)
                return trifilar(period / trifilar_period_factor(amp, mass, J0, R1, R2, l),
                                mass, R1, R2, l, g)

            m_p = x.get("trifilar.m_p", 0.0)
            J = j_small(period_from_total(x["trifilar.t"], tr["n_osc"]), m + m_p)
            if "t_p" in tr:
                J = J - j_small(period_from_total(x["trifilar.t_p"], tr["n_osc"]), m_p)
            out["J_trifilar"] = J
        if "unifilar" in secs:
            un, n = secs["unifilar"], secs["unifilar"]["n_osc"]
            T = period_from_total(x["unifilar.t"], n)
            T0 = period_from_total(x["unifilar.t_0"], n) if "t_0" in un else 0.0
            if "t_ref" in un:
                J_ref = x["unifilar.J_ref"] if "J_ref" in un else \
                    cylinder(x["unifilar.m_ref"], 0.5 * x["unifilar.d_ref"])
                out["J_unifilar"] = unifilar_reference(
                    T, period_from_total(x["unifilar.t_ref"], n), J_ref, T0)
            if all(k in un for k in ("G", "d", "l")):
                c = wire_stiffness(x["unifilar.G"], x["unifilar.d"], x["unifilar.l"])
                out["J_unifilar_wire"] = unifilar_wire(T, c, T0)
        if "pendulum" in secs:
            pe = secs["pendulum"]
            c = x["pendulum.c"]
            T = period_from_total(x["pendulum.t"], pe["n_osc"])
            T = T / pendulum_period_factor(x.get("pendulum.amplitude", 0.0))
            out["J_pendulum_pivot"] = physical_pendulum(T, m, c, g)
            out["J_pendulum_cm"] = out["J_pendulum_pivot"] - m * c**2
        return out

    return model


def _check_physics(inputs: Inputs, prop) -> None:
    for sec in ("trifilar", "pendulum"):
        if sec in inputs and "amplitude" in inputs[sec]:
            check_amplitude(inputs[sec]["amplitude"], SPEC.section(sec).label)
    if "analytic" in inputs and min(prop["J_analytic"].value, prop["m_analytic"].value) <= 0:
        holes = [i for i, p in enumerate(inputs["analytic"]) if p["hole"]]
        largest = max(holes, key=lambda i: abs(prop[f"J_part_{i}"].value), default=0)
        raise inputs.error(
            f"the parts add up to m = {prop['m_analytic'].value:.4g} kg and J = "
            f"{prop['J_analytic'].value:.4g} kg·m²: the holes remove more than the solid parts "
            f"hold", "a hole must fit inside a solid part: check its radii, height and count, "
            "and that hole = true is set only on holes", f"analytic[{largest}]",
            ru=(f"детали в сумме дают m = {prop['m_analytic'].value:.4g} кг и J = "
                f"{prop['J_analytic'].value:.4g} кг·м²: отверстия убирают больше, чем содержат "
                f"сплошные детали", "отверстие должно помещаться в сплошной детали: проверьте "
                "его радиусы, высоту и число, и что hole = true стоит только у отверстий"))
    if "trifilar" in inputs and prop["J_trifilar"].value <= 0:
        raise inputs.error(f"the part's J comes out {prop['J_trifilar'].value:.4g} kg·m² ≤ 0 after "
                           f"the empty platform is subtracted", "the platform with the part must "
                           "swing slower than alone: check t, t_p, m and m_p", "trifilar.t_p",
                           ru=(f"J детали получается {prop['J_trifilar'].value:.4g} кг·м² ≤ 0 "
                               f"после вычитания пустой платформы", "платформа с деталью должна "
                               "качаться медленнее пустой: проверьте t, t_p, m и m_p"))
    if "pendulum" in inputs:
        if prop["J_pendulum_cm"].value <= 0:
            raise inputs.error(
                f"J about the centre of mass comes out {prop['J_pendulum_cm'].value:.4g} kg·m² ≤ 0",
                "c is the distance from the pivot to the centre of mass (mm): check it and the "
                "times", "pendulum.c",
                ru=(f"J относительно центра масс получается "
                    f"{prop['J_pendulum_cm'].value:.4g} кг·м² ≤ 0", "c — расстояние от оси "
                    "качания до центра масс (мм): проверьте его и времена"))
        ratio = prop["J_pendulum_pivot"].value / prop["J_pendulum_cm"].value
        if ratio > 5:
            warnings.warn(IllConditionedWarning(
                f"physical pendulum: J about the centre of mass is a small difference of two large "
                f"numbers (J_O/J_c = {ratio:.1f}), so its relative error is {ratio:.0f} times that "
                f"of J_O; hang the part closer to its centre of mass",
                f"физический маятник: J_c — малая разность двух больших чисел "
                f"(J_O/J_c = {ratio:.1f}), относительная погрешность J_c в {ratio:.0f} раз больше, "
                f"чем J_O; подвесьте деталь ближе к центру масс"))


def _part_names(inputs: Inputs) -> dict:
    """The analytic model's parts as named results, ``m_part_<i>`` and ``J_part_<i>`` (i from
    0 in the file's order; a hole's are negative)."""
    out = {}
    for i, _ in enumerate(inputs.sections.get("analytic", [])):
        out[f"m_part_{i}"] = (bi(f"analytic model: mass of part {i + 1}",
                                 f"расчётная модель: масса части {i + 1}"), f"m_{i + 1}", "kg",
                              SIGNED)
        out[f"J_part_{i}"] = (bi(f"analytic model: J of part {i + 1} about the axis",
                                 f"расчётная модель: J части {i + 1} относительно оси"),
                              f"J_{i + 1}", "kg*m^2", SIGNED)
    return out


def _parts_table(inputs: Inputs, prop) -> Table:
    rows = []
    for i, p in enumerate(inputs["analytic"]):
        count = f" ×{p['count']}" if p["count"] > 1 else ""
        hole = bi(" — hole", " — отверстие") if p["hole"] else bi("", "")
        rows.append({"part": {lang: f"{SHAPES[p['shape']][lang]} ({AXES[p['axis']][lang]})"
                              f"{count}{hole[lang]}" for lang in ("en", "ru")},
                     "m": f"{prop[f'm_part_{i}'].value:.4g}",
                     "J": f"{prop[f'J_part_{i}'].value:.5g}"})
    return Table(bi("Analytic model: the parts", "Расчётная модель: части детали"),
                 (("part", bi("part", "часть")), ("m", bi("m, kg", "m, кг")),
                  ("J", bi("J about the axis, kg·m²", "J относительно оси, кг·м²"))), tuple(rows))


def _conclusion(results, comparisons) -> list[dict]:
    lines = []
    for name in CENTRAL:
        if name in results:
            r = results[name]
            v, U = fmt_pm(r.value, r.estimate.U)
            lines.append(bi(f"{r.label['en']}: J = {v} ± {U} kg·m² "
                            f"(k = {r.estimate.k:.2g}, {100 * r.estimate.relative_U:.2f} %)",
                            f"{r.label['ru']}: J = {v} ± {U} кг·м² "
                            f"(k = {r.estimate.k:.2g}, {100 * r.estimate.relative_U:.2f} %)"))
    measured = [n for n in CENTRAL if n in results]
    if len(measured) > 1:
        best = min(measured, key=lambda n: results[n].estimate.relative_U)
        lines.append(bi(f"The most precise method here: {results[best].label['en']}.",
                        f"Наиболее точный метод в этом опыте: {results[best].label['ru']}."))
        bad = [c for c in comparisons if not c.agree and c.a.startswith("J")]
        lines.append(bi("All methods agree within their uncertainties." if not bad else
                        f"{plural(len(bad), ('pair', 'pairs'), 'en')} of methods disagree: "
                        "see the warnings.",
                        "Все методы согласуются в пределах погрешностей." if not bad else
                        "Не согласуются "
                        f"{plural(len(bad), ('пара', 'пары', 'пар'), 'ru')} методов: "
                        "см. предупреждения."))
    return lines


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20031) -> LabResult:
    """Reduce lab 1's measurements: J of the part by every method measured, compared.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed (see :func:`processing.uncertainty.propagate`).

    Returns
    -------
    LabResult
        Results ``J_analytic``, ``J_trifilar``, ``J_unifilar``, ``J_unifilar_wire``,
        ``J_pendulum_pivot``, ``J_pendulum_cm``, ``m_analytic``, ``m_measured`` (those the file
        measures), pairwise comparisons of the central-axis values, warnings.
    """
    with collect_notices() as notices:
        inputs, films = filmed_times(inputs, FILMS)
        _check_sections(inputs)
        prop = propagate(_model(inputs), inputs.flat(), n_samples=n_samples, seed=seed)
        results = result_values(prop, {**RESULTS, **_part_names(inputs)})
        pairs = list(itertools.combinations([n for n in CENTRAL if n in results], 2))
        comparisons = compare(prop, pairs + [("m_analytic", "m_measured")])
        _check_physics(inputs, prop)
        flag_estimates(results, comparisons)
    tables = [_parts_table(inputs, prop)] if "analytic" in inputs else []
    shown = [n for n in CENTRAL if n in results]
    figures = [Figure("methods", bi("Moment of inertia by method (bars: ± U; ticks: Monte Carlo "
                                    "95 % interval)",
                                    "Момент инерции по методам (отрезки: ± U; штрихи: интервал "
                                    "Монте-Карло 95 %)"),
                      lambda fig, lang: method_chart(fig, [results[n] for n in shown], lang))]
    return LabResult.of(inputs, results, comparisons=comparisons, tables=tables,
                        figures=figures + film_figures(films), formulas=FORMULAS,
                        references=REFERENCES, warnings=notices,
                        conclusion=_conclusion(results, comparisons))


# ------------------------------------------------------------------------ synthetic files

def write_synthetic(out_dir, seed: int = 0, *, film: bool = False) -> dict[str, Path]:
    """Write a synthetic lab 1 measurement: a flywheel of its own size per seed, measured by
    the analytic method, the trifilar suspension and as a physical pendulum, and its key.

    The flywheel is a rim (R 130–170 mm, 25–40 mm thick radially, 30–50 mm wide) on a web
    (12–20 mm thick, down to a 30–45 mm hub bore), cast iron of 7200 kg/m³; its true
    J = ρπ/2 [h (R⁴ − r⁴) + h_w (r⁴ − r_h⁴)]. The trifilar (R₁ = 100 mm, R₂ = 140 mm,
    l = 800 mm, a 2.105 kg platform) and the knife edge on the rim's inside (c = r) swing at
    5–8°, their periods integrated from the nonlinear equations
    (:mod:`processing.synth.pendulum`) and timed by hand over 20 oscillations, three times;
    lengths read to ± 0.5 mm, masses to ± 1 g. With ``film``, each swing is filmed instead
    of timed (:mod:`processing.synth.swing_film`, 10 oscillations at 30 frames per second:
    the platform's edge from above, the pendulum from the side; each film's period is the
    swing's at the RMS of its decaying amplitude, the one a real swing's mean period belongs
    to) and the amplitude is left to the films.

    Returns
    -------
    dict
        Paths written: ``toml`` and ``answer`` (``"results"``: J_trifilar, J_pendulum_cm,
        J_analytic, m_measured, m_analytic, true, SI), and the films.
    """
    import json

    from processing.synth.pendulum import (measured, physical_pendulum_period, stopwatch,
                                           trifilar_period)
    from processing.inputs.toml_writer import dumps

    rng = np.random.default_rng([seed, 1])
    g, rho = 9.8156, 7200.0
    R = rng.uniform(0.13, 0.17)
    r = R - rng.uniform(0.025, 0.04)
    h, h_w, r_h = rng.uniform(0.03, 0.05), rng.uniform(0.012, 0.02), rng.uniform(0.03, 0.045)
    J = rho * np.pi / 2 * (h * (R**4 - r**4) + h_w * (r**4 - r_h**4))
    m = rho * np.pi * (h * (R**2 - r**2) + h_w * (r**2 - r_h**2))
    R1, R2, l, m_p = 0.100, 0.140, 0.800, 2.105
    J_p = 0.5 * m_p * 0.16**2
    amp = np.radians(rng.uniform(5.0, 8.0))
    T = trifilar_period(J + J_p, m + m_p, R1, R2, l, amp, g)
    T_p = trifilar_period(J_p, m_p, R1, R2, l, amp, g)
    T_pe = physical_pendulum_period(J + m * r**2, m, r, amp, g)

    def mm(v):
        return round(measured(1e3 * v, 0.5, rng), 1)

    def times(period):
        return [round(float(x), 2) for x in stopwatch(period, 20, 3, rng)]

    deg = round(float(np.degrees(amp)))
    doc = {"lab": "lab1",
           "meta": {"student": f"synthetic (dynlab synth lab1 --seed {seed})",
                    "notes": "generated; the true answers are in answer_key.json"},
           "body": {"m": f"{measured(m, 0.001, rng):.4f} kg", "g": f"{g} ± 0.0005 m/s^2"},
           "analytic": [{"shape": "cylinder", "R": mm(R), "r": mm(r), "h": mm(h),
                         "rho": "7200 ± 100 kg/m^3"},
                        {"shape": "cylinder", "R": mm(r), "r": mm(r_h), "h": mm(h_w),
                         "rho": "7200 ± 100 kg/m^3"}],
           "trifilar": {"R1": mm(R1), "R2": mm(R2), "l": mm(l), "n_osc": 20, "t": times(T),
                        "m_p": f"{measured(m_p, 0.001, rng):.4f} kg", "t_p": times(T_p),
                        "amplitude": f"{deg} deg"},
           "pendulum": {"c": mm(r), "n_osc": 20, "t": times(T_pe), "amplitude": f"{deg} deg"}}
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = {}
    if film:
        from processing.synth.swing_film import Film, render

        above = dict(arm=200.0, pivot=(320.0, 240.0), oscillations=10.0, amplitude=amp)
        side = dict(arm=600.0, pivot=(320.0, -360.0), oscillations=10.0, amplitude=amp)
        swung = Film(**above).rms_amplitude          # the amplitude a film's period is at
        for section, key, period, view in (
                ("trifilar", "t", trifilar_period(J + J_p, m + m_p, R1, R2, l, swung, g), above),
                ("trifilar", "t_p", trifilar_period(J_p, m_p, R1, R2, l, swung, g), above),
                ("pendulum", "t", physical_pendulum_period(J + m * r**2, m, r, swung, g),
                 side)):
            name = f"{section}{'_p' if key == 't_p' else ''}.mp4"
            written[name] = render(Film(period=period, **view), out / name,
                                   seed=seed * 10 + len(written))
            doc[section].pop(key)
            doc[section].pop("amplitude", None)
            doc[section]["video" + key[1:]] = name
    written.update(toml=out / f"lab1_seed{seed}.toml", answer=out / "answer_key.json")
    written["toml"].write_text(dumps(doc), encoding="utf-8")
    truth = {"J_trifilar": J, "J_pendulum_cm": J, "J_analytic": J, "m_measured": m,
             "m_analytic": m}
    written["answer"].write_text(json.dumps({"seed": seed, "results": truth}, indent=1),
                                 encoding="utf-8")
    return written
