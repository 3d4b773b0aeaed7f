"""Forces, torque and flywheel: the "dynamic calculation" of a piston engine.

SI throughout: Pa, m, m³, kg, rad, rad/s, N, N·m, J. Names as in :mod:`processing.crank.kinematics`
(``crank_angle``, ``lambda_``, ``offset_ratio``, ``crank_radius``, ``angular_speed``); the
thermodynamic state points keep the manual's letters (``p_a``, ``p_c``, ``p_z``, ``p_b``,
``p_r``, ``n1``, ``n2``).

Crank angle origin: α = 0 at the TDC that starts the intake stroke (four-stroke, cycle 720°;
firing TDC at 360°), or at the firing TDC (two-stroke, cycle 360°).

References
----------
- dynlab FORMULAS.md, section B "Forces, torque, flywheel".
- Panov V.V., Dragomirov S.G., Gots A.N., Sharapov A.M., "Dinamika dvigatelei
  vnutrennego sgoraniya: metodicheskie ukazaniya k laboratornym rabotam", Vladimir State
  University, 2003 (lab 3: μ, δ, the crank's equation of motion).
- Lukanin V.N. (ed.), "Dvigateli vnutrennego sgoraniya", vol. 2 "Dinamika i
  konstruirovanie", Vysshaya Shkola, 1995 / 2009.
- Kolchin A.I., Demidov V.P., "Raschet avtomobil'nykh i traktornykh dvigatelei"
  (Design calculation of automotive and tractor engines), Vysshaya Shkola.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from processing.diagnostics import InputError, RimSpeedWarning, check_positive, first
from .kinematics import (check_mechanism, crank_angle_from_displacement, dead_centres,
                         piston_acceleration, relative_displacement, rod_angle)
from processing.result import Record

STANDARD_GRAVITY = 9.80665
"""g for GD² [m/s²]."""


def cycle_period(strokes=4):
    """Crank angle of one working cycle.

    Parameters
    ----------
    strokes : {4, 2}
        Four-stroke or two-stroke engine.

    Returns
    -------
    float
        4π (720°) or 2π (360°). [rad]
    """
    if strokes not in (2, 4):
        raise InputError(f"strokes must be 4 or 2, got {strokes!r}",
                         "pass strokes=4 (four-stroke, 720° cycle) or strokes=2 (360° cycle)")
    return strokes * np.pi


# --- cycle volumes and pressures -------------------------------------------------------------

@dataclass(frozen=True)
class CycleVolumes(Record):
    """Characteristic volumes of the cycle (:func:`cycle_volumes`). [m³]"""

    clearance_volume: float
    """V_c = V_s/(ε - 1). [m³]"""
    total_volume: float
    """V_a = V_s + V_c. [m³]"""
    combustion_volume: float
    """V_z = ρ V_c, end of the isobaric combustion. [m³]"""


def cycle_volumes(swept_volume, compression_ratio, pre_expansion_ratio=1.0) -> CycleVolumes:
    """Clearance, total and end-of-combustion volumes.

    Parameters
    ----------
    swept_volume : float
        Swept (displacement) volume of one cylinder, V_s. [m³]
    compression_ratio : float
        ε = V_a/V_c, > 1. [1]
    pre_expansion_ratio : float, default 1
        ρ = V_z/V_c (1 for a spark-ignition engine), in [1, ε). [1]

    Returns
    -------
    CycleVolumes
        V_c, V_a, V_z. [m³]

    Notes
    -----
    .. math:: V_c = \\frac{V_s}{\\varepsilon - 1},\\quad V_a = V_s + V_c,\\quad V_z = \\rho V_c

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov.
    """
    check_positive("swept_volume", swept_volume, "m^3")
    _check_ratios(compression_ratio, pre_expansion_ratio)
    clearance = swept_volume / (compression_ratio - 1)
    return CycleVolumes(clearance_volume=clearance, total_volume=swept_volume + clearance,
                        combustion_volume=pre_expansion_ratio * clearance)


def _check_ratios(compression_ratio, pre_expansion_ratio):
    if not compression_ratio > 1:
        raise InputError(f"compression_ratio must be > 1, got {compression_ratio!r}",
                         "give ε = V_a/V_c (about 8-11 petrol, 15-22 diesel)")
    if not 1 <= pre_expansion_ratio < compression_ratio:
        raise InputError("pre_expansion_ratio must be in [1, compression_ratio), "
                         f"got {pre_expansion_ratio!r}",
                         "give ρ = V_z/V_c: 1 for a petrol engine, about 1.2-1.7 for a diesel")


def _check_exponent(name, value):
    if not value > 1:
        raise InputError(f"{name} must be > 1, got {value!r}",
                         f"give the polytropic exponent {name} (typically 1.2-1.4)")


def cylinder_volume(crank_angle, swept_volume, compression_ratio, lambda_, offset_ratio=0.0):
    """Cylinder volume above the piston, from the exact piston displacement.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    swept_volume : float
        V_s. [m³]
    compression_ratio : float
        ε. [1]
    lambda_, offset_ratio : float
        λ = R/L, z = k/R. [1]

    Returns
    -------
    float or ndarray
        V(α). [m³]

    Notes
    -----
    .. math:: V(\\alpha) = V_c + F_p S(\\alpha) = V_c + V_s\\,\\frac{s(\\alpha)}{S_{max}/R}

    (F_p S_max = V_s). Exact kinematics replaces the graphical Brix correction.

    References
    ----------
    FORMULAS.md B.
    """
    clearance = cycle_volumes(swept_volume, compression_ratio).clearance_volume
    stroke = dead_centres(lambda_, offset_ratio).stroke_ratio
    return clearance + swept_volume * relative_displacement(crank_angle, lambda_, offset_ratio) / stroke


def compression_pressure(volume, p_a, total_volume, n1):
    """Pressure on the compression polytrope.

    Parameters
    ----------
    volume : float or array_like
        Cylinder volume V_x. [m³]
    p_a : float
        Pressure at the start of compression (BDC). [Pa]
    total_volume : float
        V_a, the volume at the start of compression. [m³]
    n1 : float
        Mean polytropic exponent of compression. [1]

    Returns
    -------
    float or ndarray
        p_x. [Pa]

    Notes
    -----
    .. math:: p_x = p_a\\left(\\frac{V_a}{V_x}\\right)^{n_1}

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov.
    """
    check_positive("p_a", p_a, "Pa")
    _check_exponent("n1", n1)
    return p_a * (total_volume / volume) ** n1


def expansion_pressure(volume, p_z, combustion_volume, n2):
    """Pressure on the expansion polytrope.

    Parameters
    ----------
    volume : float or array_like
        Cylinder volume V_x (≥ V_z on the real line). [m³]
    p_z : float
        Maximum cycle pressure, at the start of expansion. [Pa]
    combustion_volume : float
        V_z = ρV_c, the volume at the start of expansion. [m³]
    n2 : float
        Mean polytropic exponent of expansion. [1]

    Returns
    -------
    float or ndarray
        p_x. [Pa]

    Notes
    -----
    .. math:: p_x = p_z\\left(\\frac{V_z}{V_x}\\right)^{n_2}

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov.
    """
    check_positive("p_z", p_z, "Pa")
    _check_exponent("n2", n2)
    return p_z * (combustion_volume / volume) ** n2


@dataclass(frozen=True)
class CyclePressures(Record):
    """End points of the polytropes (:func:`cycle_pressures`)."""

    p_c: float
    """End of compression, p_a ε^n1. [Pa]"""
    p_b: float
    """End of expansion, p_z / δ^n2. [Pa]"""
    pressure_ratio: float
    """Pressure rise in combustion, λ_p = p_z/p_c. [1]"""
    expansion_ratio: float
    """δ = ε/ρ = V_a/V_z. [1]"""


def cycle_pressures(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio=1.0) -> CyclePressures:
    """End-of-compression and end-of-expansion pressures of the simplified cycle.

    Parameters
    ----------
    p_a : float
        Start of compression. [Pa]
    p_z : float
        Maximum pressure. [Pa]
    compression_ratio : float
        ε. [1]
    n1, n2 : float
        Polytropic exponents of compression and expansion. [1]
    pre_expansion_ratio : float, default 1
        ρ. [1]

    Returns
    -------
    CyclePressures
        p_c, p_b [Pa], λ_p = p_z/p_c, δ = ε/ρ.

    Raises
    ------
    InputError
        If p_z < p_c (combustion would lower the pressure).

    Notes
    -----
    .. math:: p_c = p_a\\varepsilon^{n_1},\\quad p_b = \\frac{p_z}{\\delta^{n_2}},
              \\quad \\delta = \\frac{\\varepsilon}{\\rho}

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov.
    """
    _check_ratios(compression_ratio, pre_expansion_ratio)
    p_c = compression_pressure(1.0, p_a, compression_ratio, n1)
    if not p_z >= p_c:
        raise InputError(f"p_z must be ≥ p_c = p_a·ε^n1 = {p_c:.4g} Pa, got {p_z:.4g} Pa",
                         "check p_z (maximum cycle pressure), p_a, ε and n1 of the thermal calculation")
    expansion_ratio = compression_ratio / pre_expansion_ratio
    return CyclePressures(p_c=p_c, p_b=expansion_pressure(expansion_ratio, p_z, 1.0, n2),
                          pressure_ratio=p_z / p_c, expansion_ratio=expansion_ratio)


def _check_exhaust(p_r, strokes):
    if strokes == 4 and p_r is None:
        raise InputError("a four-stroke cycle needs p_r, the exhaust-stroke pressure",
                         "pass p_r in Pa (about 1.05-1.25 × ambient)")
    if strokes == 2 and p_r is not None:
        raise InputError(f"the simplified two-stroke cycle has no exhaust stroke, got p_r = {p_r!r}",
                         "drop p_r for strokes=2")
    if p_r is not None:
        check_positive("p_r", p_r, "Pa")


def indicator_pressure(crank_angle, *, p_a, p_z, compression_ratio, n1, n2, lambda_, p_r=None,
                       pre_expansion_ratio=1.0, offset_ratio=0.0, strokes=4):
    """Cylinder pressure p(α) of the simplified (calculated) indicator diagram.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α (any range; the cycle repeats). [rad]
    p_a : float
        Intake-line pressure and start of compression. [Pa]
    p_z : float
        Maximum cycle pressure. [Pa]
    compression_ratio : float
        ε. [1]
    n1, n2 : float
        Polytropic exponents of compression and expansion. [1]
    lambda_ : float
        λ = R/L (maps volume to crank angle exactly). [1]
    p_r : float, optional
        Exhaust-line pressure; required for four-stroke, refused for two-stroke. [Pa]
    pre_expansion_ratio : float, default 1
        ρ: 1 gives isochoric combustion (petrol); ρ > 1 adds the isobaric line p_z from V_c to
        V_z (diesel, mixed cycle). [1]
    offset_ratio : float, default 0
        z = k/R. [1]
    strokes : {4, 2}
        Four-stroke (720°) or two-stroke (360°) cycle.

    Returns
    -------
    ndarray
        Absolute cylinder pressure. [Pa]

    Notes
    -----
    The cycle, with V(α) from :func:`cylinder_volume` and the phases switching at multiples
    of 180° (no valve timing, no rounding of the corners):

    four-stroke: 0-180° intake at p_a; 180-360° compression p_a(V_a/V)^n1; at 360° an
    isochoric jump to p_z, then p_z while V < V_z, then expansion p_z(V_z/V)^n2 to 540°;
    540-720° exhaust at p_r. Two-stroke: 0-180° combustion and expansion as above, 180-360°
    compression (scavenging at BDC is instantaneous).

    .. math:: p(\\alpha) = \\begin{cases} p_a(V_a/V)^{n_1} & \\text{compression} \\\\
              p_z\\,(V_z/\\max(V, V_z))^{n_2} & \\text{combustion and expansion}\\end{cases}

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov (construction of the indicator diagram).
    """
    period = cycle_period(strokes)
    _check_exhaust(p_r, strokes)
    cycle_pressures(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio)  # checks p_z ≥ p_c
    ratio = 1 + (compression_ratio - 1) * (relative_displacement(crank_angle, lambda_, offset_ratio)
                                           / dead_centres(lambda_, offset_ratio).stroke_ratio)
    compression = compression_pressure(ratio, p_a, compression_ratio, n1)
    expansion = expansion_pressure(np.maximum(ratio, pre_expansion_ratio), p_z, pre_expansion_ratio, n2)
    phases = [p_a, compression, expansion, p_r] if strokes == 4 else [expansion, compression]
    phase = np.minimum(np.mod(crank_angle, period) // np.pi, len(phases) - 1)
    return np.select([phase == k for k in range(len(phases))],
                     [np.broadcast_to(p, np.shape(ratio)) for p in phases])[()]


def mean_indicated_pressure(*, p_a, p_z, compression_ratio, n1, n2, p_r=None,
                            pre_expansion_ratio=1.0, strokes=4):
    """Mean indicated pressure of the simplified cycle of :func:`indicator_pressure`, analytic.

    Parameters
    ----------
    p_a, p_z : float
        Start-of-compression and maximum pressures. [Pa]
    compression_ratio : float
        ε. [1]
    n1, n2 : float
        Polytropic exponents. [1]
    p_r : float, optional
        Exhaust-line pressure (four-stroke only). [Pa]
    pre_expansion_ratio : float, default 1
        ρ. [1]
    strokes : {4, 2}
        Cycle type.

    Returns
    -------
    float
        p_i = (cycle work)/V_s, pumping loop included for four-stroke. [Pa]

    Notes
    -----
    .. math::
        p_i' = \\frac{p_c}{\\varepsilon - 1}\\left[\\lambda_p(\\rho - 1)
        + \\frac{\\lambda_p\\rho}{n_2 - 1}\\left(1 - \\delta^{1 - n_2}\\right)
        - \\frac{1}{n_1 - 1}\\left(1 - \\varepsilon^{1 - n_1}\\right)\\right],
        \\qquad p_i = p_i' - (p_r - p_a)\\ \\text{(four-stroke)}

    The diagram is not rounded, so no fullness factor is applied.

    References
    ----------
    Kolchin & Demidov (theoretical mean indicated pressure); FORMULAS.md B.
    """
    cycle_period(strokes)
    _check_exhaust(p_r, strokes)
    ends = cycle_pressures(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio)
    lam_p, rho = ends.pressure_ratio, pre_expansion_ratio
    closed = ends.p_c / (compression_ratio - 1) * (
        lam_p * (rho - 1)
        + lam_p * rho / (n2 - 1) * (1 - ends.expansion_ratio ** (1 - n2))
        - (1 - compression_ratio ** (1 - n1)) / (n1 - 1))
    return closed - (p_r - p_a) if strokes == 4 else closed


def diagram_mean_pressure(crank_angle, pressure, lambda_, offset_ratio=0.0, *, strokes=4):
    """Mean indicated pressure of a sampled indicator diagram p(α), numerically.

    Parameters
    ----------
    crank_angle : array_like
        Increasing crank angles covering one cycle (end point optional). [rad]
    pressure : array_like
        Cylinder pressure at those angles. [Pa]
    lambda_, offset_ratio : float
        λ and z. [1]
    strokes : {4, 2}
        Cycle type (sets the period).

    Returns
    -------
    float
        p_i = ∮p dV / V_s. [Pa]

    Notes
    -----
    .. math:: p_i = \\frac{1}{V_s}\\oint p\\,dV = \\frac{\\oint p\\,ds}{S_{max}/R}

    Trapezoid rule over the closed cycle.

    References
    ----------
    FORMULAS.md B.
    """
    angle, p = _closed_cycle(crank_angle, pressure, cycle_period(strokes))
    s = relative_displacement(angle, lambda_, offset_ratio)
    work = np.sum((p[1:] + p[:-1]) / 2 * np.diff(s))
    return float(work / dead_centres(lambda_, offset_ratio).stroke_ratio)


def interpolate_pressure(crank_angle, table_crank_angle, table_pressure, *, strokes=4):
    """Pressure at any crank angle from a measured table p(α), periodic over the cycle.

    Parameters
    ----------
    crank_angle : float or array_like
        Where to evaluate. [rad]
    table_crank_angle : array_like
        Crank angles of the table (any order, any number of cycles' offset). [rad]
    table_pressure : array_like
        Measured pressure at those angles. [Pa]
    strokes : {4, 2}
        Cycle type (period 4π or 2π).

    Returns
    -------
    float or ndarray
        Linearly interpolated pressure. [Pa]

    References
    ----------
    FORMULAS.md B (indicator diagram p(α)).
    """
    angles = np.asarray(table_crank_angle, dtype=float)
    values = np.asarray(table_pressure, dtype=float)
    if angles.ndim != 1 or angles.shape != values.shape or angles.size < 2:
        raise InputError(f"the pressure table needs two 1-D columns of equal length ≥ 2, got "
                         f"{angles.shape} angles and {values.shape} pressures",
                         "pass one crank angle per pressure reading")
    return np.interp(crank_angle, angles, values, period=cycle_period(strokes))


def crank_angle_from_volume(volume, swept_volume, compression_ratio, lambda_, offset_ratio=0.0):
    """Crank angles of a cycle-ordered p(V) table, by exact inverse kinematics.

    Parameters
    ----------
    volume : array_like
        Cylinder volumes in the order they were recorded around the cycle, noise-free enough
        that V changes direction only at the dead centres. [m³]
    swept_volume : float
        V_s. [m³]
    compression_ratio : float
        ε. [1]
    lambda_, offset_ratio : float
        λ and z. [1]

    Returns
    -------
    ndarray
        Unwrapped, increasing crank angles: a table starting at TDC with V rising starts at
        α_TDC (the intake stroke of a four-stroke engine). [rad]

    Notes
    -----
    Each stroke (a run of rising or falling V) is inverted on its branch with
    :func:`~processing.crank.kinematics.crank_angle_from_displacement`; stroke m adds 2π·(m // 2).
    The sample nearest a dead centre may lie before or after it (V alone cannot tell): it is
    placed where the angular spacing to its neighbours is most even, which is right for
    tables sampled at a uniform crank-angle step. Feed the result to
    :func:`interpolate_pressure`.

    References
    ----------
    FORMULAS.md B (p(V) → p(α) without the Brix construction).
    """
    v = np.asarray(volume, dtype=float)
    volumes = cycle_volumes(swept_volume, compression_ratio)
    if v.ndim != 1 or v.size < 2:
        raise InputError(f"volume must be a 1-D table of ≥ 2 readings, got shape {v.shape}",
                         "pass the volumes in cycle order")
    tolerance = 1e-9 * volumes.total_volume
    outside = (v < volumes.clearance_volume - tolerance) | (v > volumes.total_volume + tolerance)
    if np.any(outside):
        raise InputError(f"volume must lie in [V_c, V_a] = [{volumes.clearance_volume:.6g}, "
                         f"{volumes.total_volume:.6g}] m^3, got {first(v[outside]):.6g}",
                         "check swept_volume, compression_ratio and the volume column's unit")
    stroke_ratio = dead_centres(lambda_, offset_ratio).stroke_ratio
    s = np.clip((v - volumes.clearance_volume) / swept_volume, 0, 1) * stroke_ratio
    down = crank_angle_from_displacement(s, lambda_, offset_ratio, stroke="down")
    up = crank_angle_from_displacement(s, lambda_, offset_ratio, stroke="up")
    direction = _held_sign(np.diff(s))
    before = _unwrap_strokes(np.concatenate([direction[:1], direction]), down, up)
    after = _unwrap_strokes(np.concatenate([direction, direction[-1:]]), down, up)
    # a sample next to a dead centre may lie on either side of it: keep the spacing even
    inner = slice(1, -1)
    middle = (before[:-2] + before[2:]) / 2
    pick_after = np.abs(after[inner] - middle) < np.abs(before[inner] - middle)
    before[inner] = np.where(pick_after, after[inner], before[inner])
    return before


def _unwrap_strokes(direction, down, up):
    """Crank angles given each sample's direction of travel (+1 towards BDC)."""
    stroke = (direction[0] < 0) + np.concatenate([[0], np.cumsum(direction[1:] != direction[:-1])])
    return 2 * np.pi * (stroke // 2) + np.where(stroke % 2 == 0, down, up)


def _held_sign(steps):
    """Sign of each step, zero steps taking the previous (or first) non-zero sign."""
    sign = np.sign(steps)
    moving = np.flatnonzero(sign)
    if moving.size == 0:
        raise InputError("volume never changes", "pass a table covering at least part of a stroke")
    index = np.maximum.accumulate(np.where(sign != 0, np.arange(sign.size), moving[0]))
    return sign[index]


def brix_offset(crank_radius, lambda_):
    """Brix correction OO' of the graphical p(V) → p(α) construction.

    Parameters
    ----------
    crank_radius : float
        R. [m]
    lambda_ : float
        λ. [1]

    Returns
    -------
    float
        OO', the shift of the Brix pole towards BDC. [m]

    Notes
    -----
    .. math:: OO' = \\frac{R\\lambda}{2}

    Reported for comparison; this toolkit maps volume to angle exactly.

    References
    ----------
    FORMULAS.md B.
    """
    check_positive("crank_radius", crank_radius, "m")
    check_mechanism(lambda_)
    return crank_radius * lambda_ / 2


# --- forces -----------------------------------------------------------------------------------

def gas_force(pressure, piston_area, ambient_pressure=101325.0):
    """Gas force on the piston along the cylinder axis.

    Parameters
    ----------
    pressure : float or array_like
        Absolute cylinder pressure p_g. [Pa]
    piston_area : float
        F_p = πD²/4 (pass 1 for the force per unit area, in Pa). [m²]
    ambient_pressure : float, default 101325
        p_0 under the piston (crankcase). [Pa]

    Returns
    -------
    float or ndarray
        P_g = (p_g - p_0)F_p, positive towards the crank. [N]

    References
    ----------
    FORMULAS.md B; Li Bin et al. 2006, section 1.3.1.
    """
    check_positive("piston_area", piston_area, "m^2")
    return (pressure - ambient_pressure) * piston_area


def reciprocating_inertia_force(crank_angle, reciprocating_mass, crank_radius, angular_speed, lambda_,
                                offset_ratio=0.0, *, method="exact"):
    """Inertia force of the reciprocating masses, P_j = -m_j j.

    Parameters
    ----------
    crank_angle : float or array_like
        α. [rad]
    reciprocating_mass : float
        m_j (piston group plus the rod's small-end share); pass m_j/F_p [kg/m²] for the
        specific force p_j [Pa]. [kg]
    crank_radius : float
        R. [m]
    angular_speed : float
        ω. [rad/s]
    lambda_, offset_ratio : float
        λ and z. [1]
    method : {'exact', 'approx'}, keyword-only
        Exact kinematics, or the two-harmonic series.

    Returns
    -------
    float or ndarray
        P_j, positive towards the crank. [N]

    Notes
    -----
    .. math:: P_j = -m_j R\\omega^2(\\cos\\alpha + \\lambda\\cos 2\\alpha)\\ \\text{(approx)},
              \\qquad P_j = -m_j\\,j(\\alpha)\\ \\text{(exact)}

    References
    ----------
    FORMULAS.md B.
    """
    return -reciprocating_mass * piston_acceleration(crank_angle, crank_radius, angular_speed,
                                                     lambda_, offset_ratio, method=method)


def rotating_inertia_force(rotating_mass, crank_radius, angular_speed):
    """Centrifugal force of the rotating masses, K_r.

    Parameters
    ----------
    rotating_mass : float
        m_r (crank pin, webs reduced to R, the rod's big-end share). [kg]
    crank_radius : float
        R. [m]
    angular_speed : float
        ω. [rad/s]

    Returns
    -------
    float
        K_r = -m_r R ω², negative: directed along the crank away from the axis. [N]

    References
    ----------
    FORMULAS.md B.
    """
    check_positive("crank_radius", crank_radius, "m")
    return -rotating_mass * crank_radius * angular_speed ** 2


@dataclass(frozen=True)
class TolleValues(Record):
    """Segments of the Tolle construction of P_j (:func:`tolle_construction`)."""

    ac: float
    """AC = m R ω²(1 + λ), |P_j| at TDC. [N] (or Pa per unit area)"""
    bd: float
    """BD = m R ω²(1 - λ), P_j at BDC. [N]"""
    ef: float
    """EF = 3λ m R ω². [N]"""


def tolle_construction(reciprocating_mass, crank_radius, angular_speed, lambda_) -> TolleValues:
    """The three segments of the graphical Tolle construction of the inertia force.

    Parameters
    ----------
    reciprocating_mass : float
        m_j, or m_j/F_p for values per unit piston area. [kg]
    crank_radius : float
        R. [m]
    angular_speed : float
        ω. [rad/s]
    lambda_ : float
        λ. [1]

    Returns
    -------
    TolleValues
        AC, BD, EF. [N]

    Notes
    -----
    .. math:: AC = mR\\omega^2(1 + \\lambda),\\quad BD = mR\\omega^2(1 - \\lambda),\\quad
              EF = 3\\lambda mR\\omega^2

    References
    ----------
    FORMULAS.md B.
    """
    check_positive("crank_radius", crank_radius, "m")
    check_mechanism(lambda_)
    scale = reciprocating_mass * crank_radius * angular_speed ** 2
    return TolleValues(ac=scale * (1 + lambda_), bd=scale * (1 - lambda_), ef=3 * lambda_ * scale)


@dataclass(frozen=True)
class CrankTrainForces(Record):
    """Forces of the crank train from the driving force (:func:`crank_train_forces`).

    All in N (or Pa when the driving force is per unit piston area), torque in N·m.
    """

    rod: np.ndarray
    """S = P/cos β, along the rod (positive compresses it)."""
    side: np.ndarray
    """N = P tan β, normal to the cylinder wall."""
    radial: np.ndarray
    """K = P cos(α + β)/cos β, along the crank (positive towards the crank axis)."""
    tangential: np.ndarray
    """T = P sin(α + β)/cos β, normal to the crank (positive in the sense of rotation)."""
    torque: np.ndarray
    """M = T R. [N·m]"""


def crank_train_forces(crank_angle, driving_force, crank_radius, lambda_,
                       offset_ratio=0.0) -> CrankTrainForces:
    """Decompose the driving force P along the rod, wall, crank and its normal.

    Parameters
    ----------
    crank_angle : float or array_like
        α. [rad]
    driving_force : float or array_like
        P = P_g + P_j along the cylinder axis, positive towards the crank. [N]
    crank_radius : float
        R. [m]
    lambda_, offset_ratio : float
        λ and z (exact rod angle). [1]

    Returns
    -------
    CrankTrainForces
        S, N, K, T [N] and torque M [N·m].

    Notes
    -----
    .. math:: S = \\frac{P}{\\cos\\beta},\\ N = P\\tan\\beta,\\
              K = P\\frac{\\cos(\\alpha+\\beta)}{\\cos\\beta},\\
              T = P\\frac{\\sin(\\alpha+\\beta)}{\\cos\\beta},\\ M = TR

    T R = P dS/dα (virtual work), for desaxial mechanisms too.

    References
    ----------
    FORMULAS.md B; Li Bin et al. 2006, section 1.3.
    """
    check_positive("crank_radius", crank_radius, "m")
    beta = rod_angle(crank_angle, lambda_, offset_ratio)
    rod = driving_force / np.cos(beta)
    tangential = rod * np.sin(crank_angle + beta)
    return CrankTrainForces(rod=rod, side=driving_force * np.tan(beta),
                            radial=rod * np.cos(crank_angle + beta), tangential=tangential,
                            torque=tangential * crank_radius)


# --- several cylinders, torque ----------------------------------------------------------------

def firing_phases(cylinders, *, strokes=4, firing_order=None):
    """Phase lag of each cylinder's cycle behind cylinder 1, for even firing intervals.

    Parameters
    ----------
    cylinders : int
        Number of cylinders i.
    strokes : {4, 2}, keyword-only
        Cycle type: firing interval θ = 720°/i or 360°/i.
    firing_order : sequence of int, optional
        Cylinder numbers (1-based) in firing order, starting with cylinder 1; default 1, 2, ….

    Returns
    -------
    ndarray
        φ_c for cylinders 1..i (index c - 1): θ times the cylinder's place in the order. [rad]

    Notes
    -----
    .. math:: \\theta = \\frac{\\text{cycle}}{i},\\qquad M_c(\\alpha) = M_1(\\alpha - \\varphi_c)

    For uneven firing pass the phases to :func:`sum_cylinders` directly.

    References
    ----------
    FORMULAS.md B ("Total tangential force").
    """
    if not (isinstance(cylinders, (int, np.integer)) and cylinders >= 1):
        raise InputError(f"cylinders must be a positive integer, got {cylinders!r}",
                         "give the number of cylinders i")
    order = np.arange(1, cylinders + 1) if firing_order is None else np.asarray(firing_order)
    if sorted(order.tolist()) != list(range(1, cylinders + 1)) or order[0] != 1:
        raise InputError(f"firing_order must list cylinders 1..{cylinders} once each, starting "
                         f"with 1, got {np.ravel(order).tolist()}", "e.g. firing_order=[1, 3, 4, 2]")
    order = order.astype(int)
    interval = cycle_period(strokes) / cylinders
    phases = np.empty(cylinders)
    phases[order - 1] = interval * np.arange(cylinders)
    return phases


def sum_cylinders(crank_angle, cylinder_curve, phases, *, strokes=4):
    """Sum one cylinder's curve (T or M) over all cylinders, each shifted by its phase.

    Parameters
    ----------
    crank_angle : array_like
        Crank angles sampling one cycle of cylinder 1 (any order). [rad]
    cylinder_curve : array_like
        Tangential force [N] or torque [N·m] of one cylinder at those angles.
    phases : array_like
        Phase lag φ_c of each cylinder, e.g. from :func:`firing_phases`. [rad]
    strokes : {4, 2}, keyword-only
        Cycle type (the period of the curve).

    Returns
    -------
    ndarray
        Σ_c curve(α - φ_c) at ``crank_angle`` (periodic linear interpolation; exact on the
        samples when the step divides every phase).

    References
    ----------
    FORMULAS.md B.
    """
    period = cycle_period(strokes)
    angle = np.asarray(crank_angle, dtype=float)
    return sum(np.interp(angle - phase, angle, cylinder_curve, period=period)
               for phase in np.atleast_1d(phases))


def mean_tangential_pressure(mean_indicated_pressure, cylinders, *, strokes=4):
    """Mean of the engine's summed tangential force per unit piston area, analytic.

    Parameters
    ----------
    mean_indicated_pressure : float
        p_i of one cylinder. [Pa]
    cylinders : int
        i. [1]
    strokes : {4, 2}, keyword-only
        k = 0.5 (four-stroke) or 1 (two-stroke).

    Returns
    -------
    float
        t_mean. [Pa]

    Notes
    -----
    Cycle work p_i V_s = p_i F_p 2R per cylinder, spread over 4π (or 2π) rad of crank angle:

    .. math:: t_{mean} = \\frac{p_i\\,i\\,k}{\\pi}

    Coursework accepts < 3 % against the mean of the summed diagram.

    References
    ----------
    FORMULAS.md B.
    """
    cycle_period(strokes)
    return mean_indicated_pressure * cylinders * (2 / strokes) / np.pi


def _closed_cycle(crank_angle, values, period):
    """Samples of one period, with the first point repeated one period on if not present."""
    angle = np.asarray(crank_angle, dtype=float)
    value = np.asarray(values, dtype=float)
    if angle.ndim != 1 or angle.shape != value.shape or angle.size < 3:
        raise InputError(f"need two 1-D arrays of equal length ≥ 3, got {angle.shape} and {value.shape}",
                         "sample the curve over one period")
    steps = np.diff(angle)
    span = angle[-1] - angle[0]
    if np.any(steps <= 0) or span > period * (1 + 1e-9):
        raise InputError("crank_angle must increase strictly within one period "
                         f"({np.degrees(period):g}°), "
                         f"got a span of {np.degrees(span):g}°", "sample exactly one cycle, in order")
    gap = period - span
    if gap <= 1e-9 * period:
        return angle, value
    if gap > 1.5 * steps.max():
        raise InputError(f"the samples cover {np.degrees(span):g}° of a {np.degrees(period):g}° period",
                         "sample the whole period (the end point may be left out)")
    return np.append(angle, angle[0] + period), np.append(value, value[0])


def _running_integral(angle, value):
    return np.concatenate([[0.0], np.cumsum((value[1:] + value[:-1]) / 2 * np.diff(angle))])


def mean_torque(crank_angle, torque, *, period):
    """Mean over one period of a periodic curve (torque, tangential force).

    Parameters
    ----------
    crank_angle : array_like
        Increasing angles covering one period (end point optional). [rad]
    torque : array_like
        The curve at those angles. [N·m]
    period : float, keyword-only
        Its period (cycle, or firing interval). [rad]

    Returns
    -------
    float
        (1/Φ)∮M dα (trapezoid). [N·m]

    References
    ----------
    FORMULAS.md B.
    """
    angle, value = _closed_cycle(crank_angle, torque, period)
    return float(_running_integral(angle, value)[-1] / period)


def torque_nonuniformity(crank_angle, torque, *, period):
    """Torque non-uniformity coefficient μ.

    Parameters
    ----------
    crank_angle : array_like
        Angles covering one period. [rad]
    torque : array_like
        Engine torque. [N·m]
    period : float, keyword-only
        Period. [rad]

    Returns
    -------
    float
        μ. [1]

    Notes
    -----
    .. math:: \\mu = \\frac{M_{max} - M_{min}}{M_{mean}}

    The manual prints the same formula for a second coefficient K: they are one number.

    References
    ----------
    Lab manual, lab 3; FORMULAS.md B.
    """
    mean = mean_torque(crank_angle, torque, period=period)
    if not mean > 0:
        raise InputError(f"the mean torque must be > 0 for μ, got {mean:.4g} N·m",
                         "pass the engine's indicated or effective torque over a whole cycle")
    return float((np.max(torque) - np.min(torque)) / mean)


@dataclass(frozen=True)
class ExcessWork(Record):
    """Largest energy swing of the crank over a period (:func:`excess_work`)."""

    work: float
    """A = max - min of ∫(M - M_mean)dα. [J]"""
    mean_torque: float
    """M_mean. [N·m]"""
    crank_angle_min: float
    """Where the running integral is lowest (ω lowest). [rad]"""
    crank_angle_max: float
    """Where it is highest (ω highest). [rad]"""
    lobe_work: float
    """The largest single area of M above M_mean, the coursework's graphical A. [J]"""
    lobe_start: float
    """Where that lobe begins (M rises through M_mean). [rad]"""
    lobe_end: float
    """Where it ends (M falls through M_mean); past ``lobe_start`` by less than a period. [rad]"""


def excess_work(crank_angle, torque, *, period) -> ExcessWork:
    """Excess (fluctuating) work of the torque about its mean, A.

    Parameters
    ----------
    crank_angle : array_like
        Increasing angles covering one period (end point optional). [rad]
    torque : array_like
        Engine torque (or T R). [N·m]
    period : float, keyword-only
        Period: the cycle, or the firing interval of an evenly firing engine. [rad]

    Returns
    -------
    ExcessWork
        A [J], M_mean [N·m], the angles of the energy minimum and maximum [rad], and the
        largest single lobe of M above M_mean with its angles, as coursework draws it.

    Notes
    -----
    .. math:: E(\\alpha) = \\int_{\\alpha_0}^{\\alpha}(M - M_{mean})\\,d\\alpha,\\qquad
              A = \\max E - \\min E

    This is the "largest area between the curve and its mean" done right: with several
    lobes the largest single lobe can understate A; the swing of E cannot. The largest lobe
    (between a rise and the next fall of M through M_mean, E's minimum and maximum there) is
    given too, for the coursework's drawing; with one lobe per period the two agree.
    For M = M_0 + a sin kα, A = 2a/k.

    Examples
    --------
    >>> alpha = np.radians(np.arange(0.0, 360.0, 0.5))
    >>> round(excess_work(alpha, 100 + 40 * np.sin(2 * alpha), period=2 * np.pi).work, 2)
    40.0

    Two lobes a period, one larger: the swing of E spans both, the largest lobe is one.

    >>> swing = excess_work(alpha, 100 + 40 * np.sin(2 * alpha) + 10 * np.sin(alpha),
    ...                     period=2 * np.pi)
    >>> ends = np.degrees([swing.lobe_start, swing.lobe_end])
    >>> round(swing.lobe_work, 1), np.round(ends, 1).tolist()
    (50.6, [0.0, 97.2])

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov (flywheel calculation).
    """
    angle, value = _closed_cycle(crank_angle, torque, period)
    integral = _running_integral(angle, value)
    mean = integral[-1] / period
    energy = integral - mean * (angle - angle[0])
    low, high = np.argmin(energy), np.argmax(energy)
    lobe_work, lobe_start, lobe_end = _largest_lobe(angle, value - mean, energy, period)
    return ExcessWork(work=float(energy[high] - energy[low]), mean_torque=float(mean),
                      crank_angle_min=float(angle[low]), crank_angle_max=float(angle[high]),
                      lobe_work=lobe_work, lobe_start=lobe_start, lobe_end=lobe_end)


def _largest_lobe(angle, deviation, energy, period) -> tuple[float, float, float]:
    """The largest area of ``deviation`` > 0 between a rise through zero and the next fall,
    on a closed period (last sample = first + period), with its crossing angles."""
    d, e, a = deviation[:-1], energy[:-1], angle[:-1]
    after = np.roll(d, -1)
    rises = np.flatnonzero((d <= 0) & (after > 0))
    falls = np.flatnonzero((d > 0) & (after <= 0))
    if rises.size == 0:
        return 0.0, float(angle[0]), float(angle[0])
    step = np.diff(angle)

    def crossing(k):
        return a[k] + step[k] * d[k] / (d[k] - after[k])

    nxt = falls[np.searchsorted(falls, rises) % falls.size]
    # E is periodic (its mean is removed), so a lobe across the period's end needs no offset;
    # at a crossing E is flat, so the larger (smaller) of its two samples is the extremum.
    areas = (np.maximum(e[nxt], e[(nxt + 1) % d.size])
             - np.minimum(e[rises], e[(rises + 1) % d.size]))
    best = int(np.argmax(areas))
    start, end = crossing(rises[best]), crossing(nxt[best])
    start -= period * (start >= angle[0] + period)
    return float(areas[best]), float(start), float(end + period * (end < start))


# --- flywheel ---------------------------------------------------------------------------------

def required_inertia(excess_work, mean_angular_speed, speed_irregularity):
    """Total moment of inertia of the rotating parts for a target speed irregularity.

    Parameters
    ----------
    excess_work : float
        A. [J]
    mean_angular_speed : float
        ω_mean = πn/30. [rad/s]
    speed_irregularity : float
        Target δ (automotive 0.01-0.02, tractor 0.003-0.01). [1]

    Returns
    -------
    float
        I_total; subtract the crank train's own inertia for the flywheel. [kg·m²]

    Notes
    -----
    .. math:: I = \\frac{A}{\\delta\\,\\omega_{mean}^2} = \\frac{900 A}{\\pi^2 n^2 \\delta}

    Examples
    --------
    >>> required_inertia(1000.0, 200.0, 0.01)
    2.5

    References
    ----------
    FORMULAS.md B; lab manual, lab 3.
    """
    check_positive("mean_angular_speed", mean_angular_speed, "rad/s")
    check_positive("speed_irregularity", speed_irregularity, "(dimensionless)")
    return excess_work / (speed_irregularity * mean_angular_speed ** 2)


def speed_irregularity(excess_work, inertia, mean_angular_speed):
    """Speed irregularity δ of a given inertia, by the shortcut formula.

    Parameters
    ----------
    excess_work : float
        A. [J]
    inertia : float
        Total inertia on the crankshaft. [kg·m²]
    mean_angular_speed : float
        ω_mean. [rad/s]

    Returns
    -------
    float
        δ ≈ A/(I ω²). [1]

    Notes
    -----
    From ω_max² - ω_min² = 2A/I and ω_mean ≈ (ω_max + ω_min)/2; good for small δ.
    :func:`crank_speed_cycle` integrates the motion instead.

    References
    ----------
    Lab manual, lab 3; FORMULAS.md B.
    """
    check_positive("inertia", inertia, "kg*m^2")
    check_positive("mean_angular_speed", mean_angular_speed, "rad/s")
    return excess_work / (inertia * mean_angular_speed ** 2)


@dataclass(frozen=True)
class SpeedCycle(Record):
    """Steady periodic crank speed over one period (:func:`crank_speed_cycle`)."""

    crank_angle: np.ndarray
    """The input angles. [rad]"""
    angular_speed: np.ndarray
    """ω(α). [rad/s]"""
    omega_min: float
    """[rad/s]"""
    omega_max: float
    """[rad/s]"""
    speed_irregularity: float
    """δ = (ω_max - ω_min)/ω_mean. [1]"""
    initial_angular_speed: float
    """ω at the first angle, chosen so that the time-mean speed is ω_mean. [rad/s]"""


def crank_speed_cycle(crank_angle, torque, inertia, mean_angular_speed, *, period) -> SpeedCycle:
    """Integrate the crank's equation of motion over one period against the mean load.

    Parameters
    ----------
    crank_angle : array_like
        Increasing angles covering one period (end point optional). [rad]
    torque : array_like
        Engine torque M(α). [N·m]
    inertia : float
        Total inertia J on the crankshaft. [kg·m²]
    mean_angular_speed : float
        ω_mean = πn/30, the time-mean speed (what a tachometer shows). [rad/s]
    period : float, keyword-only
        Period of the torque. [rad]

    Returns
    -------
    SpeedCycle
        ω(α), ω_min, ω_max, δ and the initial speed.

    Raises
    ------
    RuntimeError
        If no periodic solution exists (the root search fails).

    Notes
    -----
    J dω/dt = M(α) - M_load with M_load = M_mean (steady state), integrated exactly in its
    energy form:

    .. math:: \\omega(\\alpha)^2 = \\omega_0^2
              + \\frac{2}{J}\\int_{\\alpha_0}^{\\alpha}(M - M_{mean})d\\alpha,\\qquad
              \\frac{\\Phi}{\\oint d\\alpha/\\omega} = \\omega_{mean}

    ω_0 is found by Brent's method. Since ω_max² - ω_min² = 2A/J exactly, δ = (ω_max -
    ω_min)/ω_mean equals the shortcut A/(Jω²) times ω_mean/((ω_max + ω_min)/2): the relative
    gap is first order in δ (about 0.1 % at δ = 0.01 for a four-stroke engine) and grows to
    several per cent for δ of a few tenths.

    References
    ----------
    Lab manual, lab 3 (M_i = M_resist + J_o dω/dt); FORMULAS.md B.
    """
    check_positive("inertia", inertia, "kg*m^2")
    check_positive("mean_angular_speed", mean_angular_speed, "rad/s")
    angle, value = _closed_cycle(crank_angle, torque, period)
    integral = _running_integral(angle, value)
    energy = integral - integral[-1] / period * (angle - angle[0])
    lift = 2 * energy / inertia

    def excess_speed(omega0):
        omega = np.sqrt(omega0 ** 2 + lift)
        time = np.sum((1 / omega[1:] + 1 / omega[:-1]) / 2 * np.diff(angle))
        return period / time - mean_angular_speed

    floor = -lift.min()
    low = np.sqrt(floor + (1e-6 * mean_angular_speed) ** 2)
    high = np.sqrt(floor + mean_angular_speed ** 2)
    try:
        omega0 = brentq(excess_speed, low, high, xtol=1e-12 * mean_angular_speed)
    except ValueError as exc:
        raise RuntimeError(f"crank_speed_cycle: no periodic speed found ({exc})") from None
    omega = np.sqrt(omega0 ** 2 + lift)[: np.size(crank_angle)]
    return SpeedCycle(crank_angle=np.asarray(crank_angle, dtype=float), angular_speed=omega,
                      omega_min=float(omega.min()), omega_max=float(omega.max()),
                      speed_irregularity=float((omega.max() - omega.min()) / mean_angular_speed),
                      initial_angular_speed=float(omega0))


@dataclass(frozen=True)
class FlywheelRim(Record):
    """Thin-rim flywheel sizing (:func:`flywheel_rim`)."""

    mass: float
    """Rim mass m = 4I/D². [kg]"""
    gd2: float
    """Flywheel moment GD² = 4gI [N·m²]; divide by g for the old kgf·m² value (= 4I)."""
    peripheral_speed: float
    """Rim speed ωD/2 = πDn/60. [m/s]"""
    speed_limit: float
    """Allowed rim speed. [m/s]"""
    within_limit: bool
    """peripheral_speed ≤ speed_limit."""


def flywheel_rim(inertia, rim_diameter, angular_speed, *, speed_limit=70.0) -> FlywheelRim:
    """Rim mass, GD² and peripheral speed of a flywheel of given inertia.

    Parameters
    ----------
    inertia : float
        Flywheel inertia I_flywheel = I_total - I_crank. [kg·m²]
    rim_diameter : float
        Mean rim diameter D. [m]
    angular_speed : float
        Highest crank speed to check the rim against. [rad/s]
    speed_limit : float, keyword-only
        Allowed rim speed: about 70 m/s for cast iron (default), higher for steel. [m/s]

    Returns
    -------
    FlywheelRim
        Mass, GD², peripheral speed and the check.

    Warns
    -----
    RimSpeedWarning
        When the rim is faster than ``speed_limit``.

    Notes
    -----
    All the mass on the mean rim diameter (thin rim):

    .. math:: m = \\frac{4I}{D^2},\\quad GD^2 = 4gI,\\quad
              u = \\frac{\\omega D}{2} = \\frac{\\pi D n}{60}

    References
    ----------
    FORMULAS.md B; Kolchin & Demidov (flywheel).
    """
    check_positive("inertia", inertia, "kg*m^2")
    check_positive("rim_diameter", rim_diameter, "m")
    check_positive("speed_limit", speed_limit, "m/s")
    speed = abs(angular_speed) * rim_diameter / 2
    if speed > speed_limit:
        warnings.warn(RimSpeedWarning(
            f"flywheel rim speed {speed:.1f} m/s exceeds the limit {speed_limit:g} m/s: the rim may "
            f"burst; choose a smaller diameter (a heavier rim) or a stronger material",
            f"окружная скорость обода маховика {speed:.1f} м/с больше допустимой {speed_limit:g} м/с: "
            f"уменьшите диаметр (утяжелив обод) или выберите более прочный материал"), stacklevel=2)
    return FlywheelRim(mass=4 * inertia / rim_diameter ** 2, gd2=4 * STANDARD_GRAVITY * inertia,
                       peripheral_speed=speed, speed_limit=speed_limit,
                       within_limit=speed <= speed_limit)
