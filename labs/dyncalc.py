"""Coursework: the dynamic calculation of the crank mechanism.

The chapter "Динамический расчёт" of the engine-design coursework, from the thermal
calculation's state points to the flywheel: the polytropes and the calculated indicator
diagram, its unrolling over crank angle (exactly, with the Brix offset reported only), the
gas and reciprocating inertia forces (with the Tolle segments AC, BD, EF), the driving force
and its decomposition S, N, K, T every 15°, the engine's summed tangential force in firing
order, the mean tangential pressure checked against p_i, the excess work, the flywheel, the
torque non-uniformity μ and the speed irregularity δ, by the shortcut A/(Iω²) and by
integrating the crank's equation of motion.

The physics is :mod:`processing.crank.dynamics` and :mod:`processing.crank.kinematics`; this module
strings it together (:func:`dynamic_calculation`), lays it out as the coursework's tables and
figures and reads the student's file (:data:`SPEC`, :func:`reduce`).

Crank angle α is counted from the TDC that starts the intake stroke of cylinder 1
(four-stroke: firing TDC at 360°, cycle 720°), or from the firing TDC (two-stroke, 360°).
Forces per unit piston area (specific, as the coursework draws them) are pressures [Pa];
forces [N] are those times F_p.

References
----------
.. [1] Kolchin A.I., Demidov V.P. Raschet avtomobil'nykh i traktornykh dvigatelei (Design
       calculation of automotive and tractor engines). Moscow: Vysshaya Shkola, chapters on the
       dynamic calculation and the flywheel.
.. [2] Lukanin V.N. (ed.) Dvigateli vnutrennego sgoraniya, vol. 2: Dinamika i
       konstruirovanie. Moscow: Vysshaya Shkola, 1995 / 2009.
.. [3] Panov V.V. et al. Dinamika dvigatelei vnutrennego sgoraniya: lab manual. Vladimir
       State University, 2003 (lab 3: μ, δ and the crank's equation of motion).
"""
from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, replace

import numpy as np

from processing.crank import dynamics as dyn
from processing.diagnostics import (DynlabWarning, FlywheelNotNeededWarning,
                                    InconsistentInputWarning, InputError,
                                    MeanPressureDiscrepancyWarning, collect_notices)
from processing.crank.kinematics import (mean_piston_speed, relative_displacement,
                                         relative_velocity, rod_angle)
from processing.measurement import STROKES, Field, Inputs, LabSpec, Section, bi
from processing.result import (Figure, LabResult, Record, Table, flag_estimates, result_values,
                               with_key)
from processing.uncertainty import Measured, propagate

from . import catalogue

T_MEAN_TOLERANCE = 0.03
"""Accepted relative discrepancy between the analytic and the diagram's mean tangential
pressure (coursework practice: < 3 %)."""

STEP_DEG = 0.5
"""Crank-angle step of the computed curves [deg]: divides 15° (the tables) and the firing
interval of every usual even-firing engine (720°/i for i = 1…6, 8, 9, 10, 12, 16, 18, 20)."""

TABLE_STEP_DEG = 15.0
"""Crank-angle step of the printed force tables [deg]."""

MAX_MC_DRAWS = 2000
"""Monte Carlo draws used when some input carries an uncertainty: each draw reruns the whole
calculation over the crank-angle grid (about 1 ms), so 2000 draws keep a run near 2 s."""

MEAN_PISTON_SPEED = (3.0, 30.0)
"""Plausible mean piston speeds [m/s]: slow two-stroke marine engines run about 6–9 m/s, racing
engines up to about 25 m/s. Outside, S or n is wrong."""

CONSISTENCY_TOLERANCE = 0.02
"""Allowed relative gap between a given p_c (p_b) and the polytrope's p_a ε^n₁ (p_z/δ^n₂),
and between a given V_s and F_p S: thermal-calculation rounding."""


# ------------------------------------------------------------------------ the calculation

@dataclass(frozen=True)
class Polytropes(Record):
    """The coursework's polytrope tables (:func:`polytrope_points`).

    ``compression_ratio[k]`` = V_a/V_x and ``compression_pressure[k]`` = p_a (V_a/V_x)^n₁;
    ``expansion_ratio[k]`` = V_x/V_z and ``expansion_pressure[k]`` = p_z (V_z/V_x)^n₂.
    Ratios [1], pressures [Pa].
    """

    compression_ratio: np.ndarray
    compression_pressure: np.ndarray
    expansion_ratio: np.ndarray
    expansion_pressure: np.ndarray


def _ratios(top: float) -> np.ndarray:
    """1, 2, …, ⌊top⌋ and top itself when it is not a whole number."""
    whole = np.arange(1.0, math.floor(top + 1e-9) + 1.0)
    return whole if abs(whole[-1] - top) < 1e-9 else np.append(whole, top)


def polytrope_points(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio=1.0) -> Polytropes:
    """Points of the compression and expansion polytropes, as the coursework tabulates them.

    Parameters
    ----------
    p_a : float
        Pressure at the start of compression. [Pa]
    p_z : float
        Maximum cycle pressure, start of expansion. [Pa]
    compression_ratio : float
        ε. [1]
    n1, n2 : float
        Polytropic exponents of compression and expansion. [1]
    pre_expansion_ratio : float, default 1
        ρ = V_z/V_c. [1]

    Returns
    -------
    Polytropes
        Compression at V_a/V_x = 1, 2, …, ε and expansion at V_x/V_z = 1, 2, …, δ = ε/ρ
        (the last point the exact end ratio when it is not whole).

    Notes
    -----
    .. math:: p_x = p_a\\left(\\frac{V_a}{V_x}\\right)^{n_1}, \\qquad
              p_x = p_z\\left(\\frac{V_z}{V_x}\\right)^{n_2}

    (:func:`processing.crank.dynamics.compression_pressure`,
    :func:`~processing.crank.dynamics.expansion_pressure`.)

    Examples
    --------
    Exponents of 1.5 and ε = 9 make the numbers exact: 9^1.5 = 27.

    >>> pts = polytrope_points(0.1e6, 5.4e6, 9.0, 1.5, 1.5)
    >>> [round(float(p) / 1e6, 4) for p in pts.compression_pressure[[0, 3, 8]]]
    [0.1, 0.8, 2.7]
    >>> [round(float(p) / 1e6, 4) for p in pts.expansion_pressure[[0, 3, 8]]]
    [5.4, 0.675, 0.2]
    """
    ends = dyn.cycle_pressures(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio)
    comp = _ratios(compression_ratio)
    expa = _ratios(ends.expansion_ratio)
    return Polytropes(compression_ratio=comp,
                      compression_pressure=dyn.compression_pressure(1.0 / comp, p_a, 1.0, n1),
                      expansion_ratio=expa,
                      expansion_pressure=dyn.expansion_pressure(expa, p_z, 1.0, n2))


@dataclass(frozen=True)
class DynamicCalculation(Record):
    """Everything the dynamic calculation finds (:func:`dynamic_calculation`). SI units.

    Curves are sampled at ``crank_angle`` (one cycle of cylinder 1, end point left out);
    "specific" curves are per unit piston area [Pa]; multiply by ``piston_area`` for [N].
    """

    # the engine
    strokes: int
    cylinders: int
    phases: np.ndarray
    """Lag of each cylinder behind cylinder 1 (index c − 1). [rad]"""
    crank_radius: float
    lambda_: float
    piston_area: float
    angular_speed: float
    p_0: float
    reciprocating_mass_per_area: float
    """m_j/F_p. [kg/m²]"""
    volumes: dyn.CycleVolumes
    pressures: dyn.CyclePressures
    polytropes: Polytropes
    # one cylinder's curves
    crank_angle: np.ndarray
    gas_pressure: np.ndarray
    """p_g(α), absolute. [Pa]"""
    inertia_pressure: np.ndarray
    """p_j(α) = −(m_j/F_p) j. [Pa]"""
    driving_pressure: np.ndarray
    """p = p_g − p_0 + p_j. [Pa]"""
    forces: dyn.CrankTrainForces
    """S, N, K, T of one cylinder, specific [Pa] (torque per unit area [N·m/m²])."""
    tolle: dyn.TolleValues
    """AC, BD, EF, specific. [Pa]"""
    brix_offset: float
    """OO' = Rλ/2. [m]"""
    # the engine's torque
    tangential_sum: np.ndarray
    """Σ t_c(α), specific. [Pa]"""
    torque_sum: np.ndarray
    """M(α) = Σ T_c R. [N·m]"""
    p_i: float
    """Mean indicated pressure used for the analytic t_mean (given, or the cycle's). [Pa]"""
    p_i_given: bool
    diagram_fullness: float
    """φ_i, the rounded diagram's area over the calculated one's. [1]"""
    p_i_diagram: float
    """∮p dV / V_s of the sampled diagram. [Pa]"""
    t_mean_analytic: float
    t_mean_diagram: float
    excess: dyn.ExcessWork
    mu_torque: float
    # flywheel
    target_irregularity: float
    inertia_total: float
    """Total inertia needed for the target δ. [kg·m²]"""
    inertia_crank: float
    inertia_flywheel: float
    """I_total − I_crank (≥ 0). [kg·m²]"""
    inertia_flywheel_chosen: float | None
    rim: dyn.FlywheelRim | None
    """Rim of the flywheel used (chosen, else the one sized); None if no flywheel is needed."""
    rim_diameter: float
    delta_shortcut: float
    speed: dyn.SpeedCycle

    @property
    def cycle(self) -> float:
        """Crank angle of one cycle. [rad]"""
        return dyn.cycle_period(self.strokes)

    @property
    def firing_interval(self) -> float:
        """θ = cycle/i. [rad]"""
        return self.cycle / self.cylinders

    @property
    def t_mean_discrepancy(self) -> float:
        """(φ_i t_mean_diagram − t_mean_analytic)/t_mean_analytic. [1]"""
        return self.diagram_fullness * self.t_mean_diagram / self.t_mean_analytic - 1.0

    @property
    def inertia_used(self) -> float:
        """Total inertia of the crank train with the flywheel used. [kg·m²]"""
        fly = self.inertia_flywheel if self.inertia_flywheel_chosen is None else \
            self.inertia_flywheel_chosen
        return self.inertia_crank + fly

    def values(self) -> dict[str, float]:
        """The scalar results, keyed by the stable result names (SI)."""
        F, R = self.piston_area, self.crank_radius
        rim = self.rim
        out = {
            "V_s": self.volumes.total_volume - self.volumes.clearance_volume,
            "V_c": self.volumes.clearance_volume, "F_p": F,
            "c_m": mean_piston_speed(2 * R, self.angular_speed),
            "p_c": self.pressures.p_c, "p_b": self.pressures.p_b,
            "lambda_p": self.pressures.pressure_ratio, "p_i": self.p_i,
            "p_i_diagram": self.p_i_diagram,
            "brix_OO": self.brix_offset, "AC": self.tolle.ac, "BD": self.tolle.bd,
            "EF": self.tolle.ef,
            "p_max": float(self.gas_pressure.max()),
            "P_max": float(np.max(np.abs(self.driving_pressure))) * F,
            "T_max": float(np.max(np.abs(self.forces.tangential))) * F,
            "S_max": float(np.max(np.abs(self.forces.rod))) * F,
            "N_max": float(np.max(np.abs(self.forces.side))) * F,
            "t_mean_analytic": self.t_mean_analytic, "t_mean_diagram": self.t_mean_diagram,
            "t_mean_discrepancy": self.t_mean_discrepancy,
            "M_mean": self.excess.mean_torque,
            "M_max": float(self.torque_sum.max()), "M_min": float(self.torque_sum.min()),
            "N_i": self.excess.mean_torque * self.angular_speed,
            "mu_torque": self.mu_torque, "A_excess": self.excess.work,
            "A_lobe": self.excess.lobe_work, "alpha_lobe_start": self.excess.lobe_start,
            "alpha_lobe_end": self.excess.lobe_end,
            "I_total": self.inertia_total, "I_crank": self.inertia_crank,
            "I_flywheel": self.inertia_flywheel,
            "m_flywheel": rim.mass if rim else 0.0,
            "mD2_flywheel": rim.mass * self.rim_diameter ** 2 if rim else 0.0,
            "v_rim": self.angular_speed * self.rim_diameter / 2,
            "delta_shortcut": self.delta_shortcut,
            "delta_integrated": self.speed.speed_irregularity,
        }
        if self.inertia_flywheel_chosen is not None:
            out["I_flywheel_chosen"] = self.inertia_flywheel_chosen
        return out

    def force_table(self, step_deg: float = TABLE_STEP_DEG):
        """One cylinder's forces every ``step_deg`` over the cycle, as the coursework lists them.

        Returns
        -------
        pandas.DataFrame
            ``alpha_deg`` [deg], ``beta_deg`` [deg], ``p_g``, ``dp_g`` (p_g − p_0), ``p_j``,
            ``p`` [Pa]; ``P`` [N]; the factors ``tan_beta``, ``inv_cos_beta``,
            ``cos_ab`` = cos(α+β)/cos β, ``sin_ab`` = sin(α+β)/cos β [1]; the forces ``N``,
            ``S``, ``K``, ``T`` [N] and the cylinder's torque ``M`` [N·m].
        """
        import pandas as pd

        idx = self._rows(step_deg, self.cycle)
        a = self.crank_angle[idx]
        beta = rod_angle(a, self.lambda_)
        F, f = self.piston_area, self.forces
        return pd.DataFrame({
            "alpha_deg": np.degrees(a), "beta_deg": np.degrees(beta),
            "p_g": self.gas_pressure[idx], "dp_g": self.gas_pressure[idx] - self.p_0,
            "p_j": self.inertia_pressure[idx], "p": self.driving_pressure[idx],
            "P": self.driving_pressure[idx] * F,
            "tan_beta": np.tan(beta), "N": f.side[idx] * F,
            "inv_cos_beta": 1 / np.cos(beta), "S": f.rod[idx] * F,
            "cos_ab": np.cos(a + beta) / np.cos(beta), "K": f.radial[idx] * F,
            "sin_ab": relative_velocity(a, self.lambda_), "T": f.tangential[idx] * F,
            "M": f.torque[idx] * F})

    def summed_table(self, step_deg: float = TABLE_STEP_DEG):
        """The engine's tangential force over one firing interval, cylinder by cylinder.

        Returns
        -------
        pandas.DataFrame
            ``alpha_deg`` (cylinder 1) [deg], ``T1`` … ``Ti`` (each cylinder's T at that
            moment) [N], ``T_sum`` [N], ``M`` [N·m].
        """
        import pandas as pd

        idx = self._rows(step_deg, self.firing_interval, closed=True)
        a = self.crank_angle[idx % self.crank_angle.size] + self.cycle * (idx // self.crank_angle.size)
        t1 = self.forces.tangential * self.piston_area
        cols = {"alpha_deg": np.degrees(a)}
        for c, phase in enumerate(self.phases, 1):
            cols[f"T{c}"] = np.interp(a - phase, self.crank_angle, t1, period=self.cycle)
        cols["T_sum"] = self.tangential_sum[idx % self.crank_angle.size] * self.piston_area
        cols["M"] = self.torque_sum[idx % self.crank_angle.size]
        return pd.DataFrame(cols)

    def _rows(self, step_deg, span, closed=False):
        step = np.degrees(self.crank_angle[1] - self.crank_angle[0])
        every = step_deg / step
        if abs(every - round(every)) > 1e-6:
            raise InputError(f"the table step {step_deg:g}° is not a multiple of the grid step "
                             f"{step:g}°", f"use a multiple of {step:g}°")
        every = int(round(every))
        last = int(math.floor(np.degrees(span) / step + 1e-6))
        return np.arange(0, last + (1 if closed else 0), every)


def dynamic_calculation(*, p_a, p_z, compression_ratio, n1, n2, crank_radius, lambda_,
                        piston_area, angular_speed, cylinders, reciprocating_mass_per_area,
                        target_irregularity, rim_diameter, p_r=None, p_0=0.1e6,
                        pre_expansion_ratio=1.0, strokes=4, firing_order=None,
                        mean_indicated_pressure=None, diagram_fullness=1.0, crank_inertia=None,
                        crank_inertia_share=None, flywheel_inertia=None, rim_speed_limit=70.0,
                        firing_interval=None, step_deg=STEP_DEG) -> DynamicCalculation:
    """The dynamic calculation of a multi-cylinder in-line engine, from the thermal
    calculation to the flywheel.

    Parameters
    ----------
    p_a, p_z : float
        Start-of-compression and maximum cycle pressures (absolute). [Pa]
    compression_ratio : float
        ε. [1]
    n1, n2 : float
        Polytropic exponents of compression and expansion. [1]
    crank_radius : float
        R = S/2. [m]
    lambda_ : float
        λ = R/L. [1]
    piston_area : float
        F_p = πD²/4. [m²]
    angular_speed : float
        ω = πn/30 (the mean crank speed). [rad/s]
    cylinders : int
        i, firing evenly every cycle/i.
    reciprocating_mass_per_area : float
        m_j/F_p. [kg/m²]
    target_irregularity : float
        Target speed irregularity δ for sizing the flywheel. [1]
    rim_diameter : float
        Mean rim diameter of the flywheel. [m]
    p_r : float, optional
        Exhaust pressure (four-stroke only). [Pa]
    p_0 : float, default 0.1 MPa
        Pressure under the piston (crankcase). [Pa]
    pre_expansion_ratio : float, default 1
        ρ. [1]
    strokes : {4, 2}
    firing_order : sequence of int, optional
        Cylinders in firing order, from 1 (the default 1, 2, … gives the same sum).
    mean_indicated_pressure : float, optional
        p_i of the thermal calculation for the analytic t_mean; default: the calculated
        diagram's own (:func:`processing.crank.dynamics.mean_indicated_pressure`) times
        ``diagram_fullness``. [Pa]
    diagram_fullness : float
        φ_i, the fullness factor of the rounded indicator diagram (0.92–0.97 in coursework;
        1: not rounded): the student's rounded diagram encloses φ_i of the calculated one's
        area, so its mean tangential pressure is φ_i t_mean' and p_i = φ_i p_i'. The check
        of t_mean compares like with like: φ_i t_mean' against p_i·i·k/π.
    crank_inertia : float, optional
        The crank train's own inertia I_crank. [kg·m²]
    crank_inertia_share : float, optional
        Or I_crank as a share of the required total (0.1–0.2 in automotive practice, the
        flywheel taking 80–90 %). Exactly one of the two.
    flywheel_inertia : float, optional
        Inertia of the flywheel actually chosen; default: the one sized for the target δ.
        [kg·m²]
    rim_speed_limit : float, default 70
        Allowed rim speed (cast iron). [m/s]
    firing_interval : float, optional
        θ between cylinders firing one after another; default cycle/i (even firing). A
        student's sum at the wrong interval (360°/i in a four-stroke) is this set wrong
        (:data:`SLIPS`). [rad]
    step_deg : float
        Crank-angle step of the curves. [deg]

    Returns
    -------
    DynamicCalculation

    Raises
    ------
    InputError
        On inconsistent inputs (p_z < p_c, both or neither of ``crank_inertia`` and
        ``crank_inertia_share``, a bad firing order, ...).

    Warns
    -----
    MeanPressureDiscrepancyWarning
        When the diagram's t_mean misses p_i·i·k/π by ≥ :data:`T_MEAN_TOLERANCE`.
    RimSpeedWarning
        When the rim of the flywheel used runs faster than ``rim_speed_limit``.
    FlywheelNotNeededWarning
        When the crank train alone meets the target δ.

    Notes
    -----
    α-grid of ``step_deg`` over one cycle; p_g(α) by
    :func:`processing.crank.dynamics.indicator_pressure` (exact V(α)); p_j by
    :func:`~processing.crank.dynamics.reciprocating_inertia_force` (exact kinematics); S, N, K, T by
    :func:`~processing.crank.dynamics.crank_train_forces`; the engine's sum by
    :func:`~processing.crank.dynamics.sum_cylinders` with
    :func:`~processing.crank.dynamics.firing_phases`; t_mean, A, μ over the whole cycle (right for
    uneven patterns too); I = A/(δω²); δ of the inertia used both by A/(Iω²) and by
    :func:`~processing.crank.dynamics.crank_speed_cycle`.

    Examples
    --------
    A single-cylinder four-stroke with exact numbers (ε = 9, n₁ = n₂ = 1.5: p_c = 2.7 MPa,
    p_i = 0.45 MPa, t_mean = p_i/(2π)):

    >>> calc = dynamic_calculation(p_a=0.1e6, p_z=5.4e6, compression_ratio=9.0, n1=1.5, n2=1.5,
    ...     p_r=0.1e6, crank_radius=0.04, lambda_=0.25, piston_area=5e-3, angular_speed=300.0,
    ...     cylinders=1, reciprocating_mass_per_area=100.0, target_irregularity=0.01,
    ...     crank_inertia_share=0.1, rim_diameter=0.25)
    >>> round(calc.p_i / 1e6, 6), round(calc.t_mean_analytic / 1e6, 5)
    (0.45, 0.07162)
    >>> abs(calc.t_mean_discrepancy) < 1e-3
    True
    """
    cycle = dyn.cycle_period(strokes)
    if (crank_inertia is None) == (crank_inertia_share is None):
        raise InputError("give exactly one of the crank train's inertia I_crank and its share "
                         "k_crank of the total",
                         "I_crank in kg·m² if known, else k_crank (0.1–0.2: the flywheel takes "
                         "80–90 % of the total inertia)")
    if crank_inertia_share is not None and not 0 <= crank_inertia_share < 1:
        raise InputError(f"k_crank must be in [0, 1), got {crank_inertia_share!r}",
                         "k_crank = I_crank/I_total, typically 0.1–0.2")
    n_grid = cycle / np.radians(step_deg)
    if abs(n_grid - round(n_grid)) > 1e-9:
        raise InputError(f"step_deg must divide the cycle, got {step_deg!r}", "use e.g. 0.5 or 1")
    alpha = np.radians(np.arange(int(round(n_grid))) * step_deg)
    swept = piston_area * 2 * crank_radius
    volumes = dyn.cycle_volumes(swept, compression_ratio, pre_expansion_ratio)
    pressures = dyn.cycle_pressures(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio)
    gas = dyn.indicator_pressure(alpha, p_a=p_a, p_z=p_z, compression_ratio=compression_ratio,
                                 n1=n1, n2=n2, lambda_=lambda_, p_r=p_r,
                                 pre_expansion_ratio=pre_expansion_ratio, strokes=strokes)
    inertia = dyn.reciprocating_inertia_force(alpha, reciprocating_mass_per_area, crank_radius,
                                              angular_speed, lambda_)
    driving = dyn.gas_force(gas, 1.0, p_0) + inertia
    forces = dyn.crank_train_forces(alpha, driving, crank_radius, lambda_)
    phases = dyn.firing_phases(cylinders, strokes=strokes, firing_order=firing_order)
    if firing_interval is not None:
        phases = phases * firing_interval / (cycle / cylinders)
    t_sum = dyn.sum_cylinders(alpha, forces.tangential, phases, strokes=strokes)
    torque = t_sum * piston_area * crank_radius
    given = mean_indicated_pressure is not None
    p_i = mean_indicated_pressure if given else diagram_fullness * dyn.mean_indicated_pressure(
        p_a=p_a, p_z=p_z, compression_ratio=compression_ratio, n1=n1, n2=n2, p_r=p_r,
        pre_expansion_ratio=pre_expansion_ratio, strokes=strokes)
    p_i_diagram = dyn.diagram_mean_pressure(alpha, gas, lambda_, strokes=strokes)
    t_analytic = dyn.mean_tangential_pressure(p_i, cylinders, strokes=strokes)
    t_diagram = dyn.mean_torque(alpha, t_sum, period=cycle)
    gap = diagram_fullness * t_diagram / t_analytic - 1.0
    if abs(gap) >= T_MEAN_TOLERANCE:
        _warn_discrepancy(gap, p_i, p_i_diagram, given, diagram_fullness)
    excess = dyn.excess_work(alpha, torque, period=cycle)
    mu = dyn.torque_nonuniformity(alpha, torque, period=cycle)
    total = dyn.required_inertia(excess.work, angular_speed, target_irregularity)
    crank = crank_inertia if crank_inertia is not None else crank_inertia_share * total
    flywheel = max(total - crank, 0.0)
    used = flywheel if flywheel_inertia is None else flywheel_inertia
    if flywheel_inertia is None and flywheel == 0.0:
        warnings.warn(FlywheelNotNeededWarning(
            f"the crank train's own inertia {crank:.4g} kg·m² already exceeds the "
            f"{total:.4g} kg·m² needed for δ = {target_irregularity:g}: no flywheel is needed "
            f"(δ below is that of the crank train alone); check I_crank",
            f"собственный момент инерции КШМ {crank:.4g} кг·м² больше потребного "
            f"{total:.4g} кг·м² для δ = {target_irregularity:g}: маховик не нужен (δ ниже — для "
            f"одного КШМ); проверьте I_crank"))
    rim = dyn.flywheel_rim(used, rim_diameter, angular_speed, speed_limit=rim_speed_limit) \
        if used > 0 else None
    if rim is None:
        dyn.flywheel_rim(1.0, rim_diameter, angular_speed, speed_limit=rim_speed_limit)  # checks
    inertia_used = crank + used
    return DynamicCalculation(
        strokes=strokes, cylinders=cylinders, phases=phases, crank_radius=crank_radius,
        lambda_=lambda_, piston_area=piston_area, angular_speed=angular_speed, p_0=p_0,
        reciprocating_mass_per_area=reciprocating_mass_per_area, volumes=volumes,
        pressures=pressures,
        polytropes=polytrope_points(p_a, p_z, compression_ratio, n1, n2, pre_expansion_ratio),
        crank_angle=alpha, gas_pressure=gas, inertia_pressure=inertia, driving_pressure=driving,
        forces=forces,
        tolle=dyn.tolle_construction(reciprocating_mass_per_area, crank_radius, angular_speed,
                                     lambda_),
        brix_offset=dyn.brix_offset(crank_radius, lambda_),
        tangential_sum=t_sum, torque_sum=torque, p_i=p_i, p_i_given=given,
        diagram_fullness=diagram_fullness,
        p_i_diagram=p_i_diagram, t_mean_analytic=t_analytic, t_mean_diagram=t_diagram,
        excess=excess, mu_torque=mu, target_irregularity=target_irregularity,
        inertia_total=total, inertia_crank=crank, inertia_flywheel=flywheel,
        inertia_flywheel_chosen=flywheel_inertia, rim=rim, rim_diameter=rim_diameter,
        delta_shortcut=dyn.speed_irregularity(excess.work, inertia_used, angular_speed),
        speed=dyn.crank_speed_cycle(alpha, torque, inertia_used, angular_speed, period=cycle))


def _warn_discrepancy(gap, p_i, p_i_diagram, given, fullness):
    src_en = "the p_i given" if given else "the cycle's p_i"
    src_ru = "заданное p_i" if given else "p_i цикла"
    if fullness == 1.0:
        hint_en = ("the calculated diagram here is not rounded, so a p_i reduced by the "
                   "fullness factor φ_i shows up as a gap (give cycle.phi_i)")
        hint_ru = ("расчётная диаграмма здесь не скруглена, поэтому p_i, уменьшенное на "
                   "коэффициент полноты φ_i, даёт расхождение (укажите cycle.phi_i)")
    else:
        hint_en = f"the fullness factor φ_i = {fullness:g} is taken into account"
        hint_ru = f"коэффициент полноты φ_i = {fullness:g} учтён"
    warnings.warn(MeanPressureDiscrepancyWarning(
        f"the mean of the summed tangential force differs from p_i·i·k/π by {100 * gap:+.1f} % "
        f"(coursework accepts < {100 * T_MEAN_TOLERANCE:g} %): {src_en} is "
        f"{p_i / 1e6:.4g} MPa, the diagram's own ∮p dV/V_s is {p_i_diagram / 1e6:.4g} MPa. "
        f"Check that p_i is the indicated (not effective) pressure of this cycle; {hint_en}; "
        f"check ε, n₁, n₂, ρ, p_z, i and the stroke type",
        f"среднее суммарной тангенциальной силы отличается от p_i·i·k/π на {100 * gap:+.1f} % "
        f"(в курсовой допускается < {100 * T_MEAN_TOLERANCE:g} %): {src_ru} равно "
        f"{p_i / 1e6:.4g} МПа, а ∮p dV/V_s самой диаграммы — {p_i_diagram / 1e6:.4g} МПа. "
        f"Проверьте, что p_i — индикаторное (не эффективное) давление этого цикла; {hint_ru}; "
        f"проверьте ε, n₁, n₂, ρ, p_z, i и тактность"))


# -------------------------------------------------------------------- the measurement file

PRESSURE = dict(unit="MPa")
RATIO = dict(unit="")
CYLINDER = dict(unit="mm", plausible=("20 mm", "1000 mm"))
"""A bore or a stroke, a moped's to a marine diesel's."""
INERTIA = dict(unit="kg*m^2", plausible=("1e-3 kg*m^2", "1e5 kg*m^2"))
"""A crank train's or a flywheel's moment of inertia, a small engine's to a ship's."""

SPEC = LabSpec(
    id="dyncalc", number="",
    title=catalogue.title("dyncalc"),
    goal=bi("To build the calculated indicator diagram from the thermal calculation, find the "
            "gas and inertia forces and the forces in the crank train of one cylinder, sum the "
            "tangential forces of all cylinders in firing order, check the mean tangential "
            "pressure against the mean indicated pressure, and size the flywheel for the "
            "required speed irregularity.",
            "По данным теплового расчёта построить расчётную индикаторную диаграмму, найти "
            "силы давления газов и инерции и силы, действующие в КШМ одного цилиндра, "
            "просуммировать тангенциальные силы всех цилиндров в порядке работы, проверить "
            "среднее тангенциальное давление по среднему индикаторному давлению и рассчитать "
            "маховик на заданную степень неравномерности хода."),
    sections=(
        Section("engine", bi("The engine", "Двигатель"), required=True, fields=(
            Field("i", bi("number of cylinders (in line, firing evenly)",
                          "число цилиндров (рядный, равномерное чередование)"), kind="count",
                  symbol="i", example=4),
            Field("strokes", bi("strokes per cycle", "тактность"), **STROKES),
            Field("n", bi("crank speed (min⁻¹)", "частота вращения (мин⁻¹)"), unit="rpm",
                  symbol="n", example=5600, plausible=("50 rpm", "12000 rpm")),
            Field("firing_order", bi("firing order", "порядок работы цилиндров"), kind="text",
                  required=False, example="1-3-4-2"),
        )),
        Section("cycle", bi("Thermal calculation", "Данные теплового расчёта"), required=True,
                fields=(
            Field("p_a", bi("pressure at the end of intake (start of compression)",
                            "давление в конце впуска (начало сжатия)"), **PRESSURE, symbol="p_a",
                  example=0.085, plausible=("0.05 MPa", "0.5 MPa")),
            Field("p_c", bi("pressure at the end of compression (check; default p_a ε^n₁)",
                            "давление в конце сжатия (проверка; по умолчанию p_a ε^n₁)"),
                  **PRESSURE, symbol="p_c", required=False, plausible=("0.5 MPa", "20 MPa")),
            Field("p_z", bi("maximum cycle pressure", "максимальное давление цикла"), **PRESSURE,
                  symbol="p_z", example=6.5, plausible=("2 MPa", "30 MPa")),
            Field("p_b", bi("pressure at the end of expansion (check; default p_z/δ^n₂)",
                            "давление в конце расширения (проверка; по умолчанию p_z/δ^n₂)"),
                  **PRESSURE, symbol="p_b", required=False, plausible=("0.1 MPa", "2 MPa")),
            Field("p_r", bi("exhaust pressure (four-stroke)", "давление остаточных газов (выпуск)"),
                  **PRESSURE, symbol="p_r", required=False, example=0.115,
                  plausible=("0.05 MPa", "0.5 MPa")),
            Field("p_0", bi("pressure under the piston (ambient)",
                            "давление под поршнем (окружающей среды)"), **PRESSURE,
                  symbol="p_0", default="0.1 MPa", plausible=("0.05 MPa", "0.5 MPa")),
            Field("eps", bi("compression ratio", "степень сжатия"), **RATIO, symbol="ε",
                  example=10, plausible=("4", "25")),
            Field("rho", bi("pre-expansion ratio (1 for petrol)",
                            "степень предварительного расширения (1 для бензиновых)"), **RATIO,
                  symbol="ρ", default=1.0, plausible=("1", "3")),
            Field("n1", bi("mean polytropic exponent of compression",
                           "средний показатель политропы сжатия"), **RATIO, symbol="n₁",
                  example=1.37, plausible=("1.1", "1.6")),
            Field("n2", bi("mean polytropic exponent of expansion",
                           "средний показатель политропы расширения"), **RATIO, symbol="n₂",
                  example=1.25, plausible=("1.05", "1.6")),
            Field("p_i", bi("mean indicated pressure (default: that of the diagram)",
                            "среднее индикаторное давление (по умолчанию — по диаграмме)"),
                  **PRESSURE, symbol="p_i", required=False, plausible=("0.2 MPa", "5 MPa")),
            Field("phi_i", bi("fullness factor of the rounded diagram, p_i = φ_i p_i' (1: not "
                              "rounded)", "коэффициент полноты скруглённой диаграммы, "
                              "p_i = φ_i p_i' (1 — без скругления)"), **RATIO, symbol="φ_i",
                  default=1.0, maximum="1", plausible=("0.5", "1")),
        )),
        Section("geometry", bi("Crank mechanism", "Кривошипно-шатунный механизм"), required=True,
                help=bi("Give the stroke S and the bore D, or S and the swept volume V_s.",
                        "Укажите ход S и диаметр D или ход S и рабочий объём V_s."), fields=(
            Field("D", bi("cylinder bore", "диаметр цилиндра"), **CYLINDER, symbol="D",
                  required=False, example=82),
            Field("S", bi("piston stroke", "ход поршня"), **CYLINDER, symbol="S", example=84),
            Field("V_s", bi("swept volume of one cylinder", "рабочий объём цилиндра"), unit="L",
                  symbol="V_s", required=False, plausible=("0.01 L", "1000 L")),
            Field("lambda", bi("crank radius over rod length", "отношение радиуса кривошипа к "
                               "длине шатуна"), **RATIO, symbol="λ", example=0.28,
                  plausible=("0.1", "0.5")),
        )),
        Section("masses", bi("Reciprocating masses", "Возвратно-поступательно движущиеся массы"),
                required=True,
                help=bi("Give m_j (piston group + rod small-end share) or m_j/F_p.",
                        "Укажите m_j (поршневая группа + часть шатуна) или m_j/F_p."), fields=(
            Field("m_j", bi("reciprocating mass of one cylinder", "масса поступательно "
                            "движущихся частей одного цилиндра"), unit="kg", symbol="m_j",
                  required=False, plausible=("10 g", "5000 kg")),
            Field("m_j_spec", bi("reciprocating mass per unit piston area",
                                 "удельная масса поступательно движущихся частей"),
                  unit="kg/m^2", symbol="m_j/F_p", required=False, example="12 g/cm^2",
                  plausible=("20 kg/m^2", "1000 kg/m^2")),
        )),
        Section("flywheel", bi("Flywheel", "Маховик"), required=True,
                help=bi("Give I_crank or k_crank = I_crank/I_total (0.1–0.2).",
                        "Укажите I_crank или k_crank = I_кшм/I_0 (0,1–0,2)."), fields=(
            Field("delta", bi("required speed irregularity", "требуемая степень неравномерности"),
                  **RATIO, symbol="δ", example=0.01, plausible=("0.001", "0.1")),
            Field("I_crank", bi("the crank train's own moment of inertia",
                                "собственный момент инерции КШМ"), **INERTIA,
                  symbol="I_кшм", required=False),
            Field("k_crank", bi("crank train's share of the total inertia",
                                "доля КШМ в суммарном моменте инерции"), **RATIO,
                  symbol="k_кшм", required=False, allow_zero=True, example=0.15,
                  plausible=("0.01", "1")),
            Field("I_flywheel", bi("moment of inertia of the flywheel chosen (default: as sized)",
                                   "момент инерции принятого маховика (по умолчанию — расчётный)"),
                  **INERTIA, symbol="I_м", required=False),
            Field("D_rim", bi("mean rim diameter", "средний диаметр обода"), unit="mm",
                  symbol="D_ср", example=230, plausible=("50 mm", "5000 mm")),
            Field("v_rim_max", bi("allowed rim speed", "допустимая окружная скорость обода"),
                  unit="m/s", symbol="[v]", default="70 m/s", plausible=("10 m/s", "200 m/s")),
        )),
        Section("drawing", bi("Scales of the drawing", "Масштабы чертежа"),
                help=bi("Optional: with them the report adds the forces' ordinates in mm, as "
                        "drawn.", "Необязательно: с ними в отчёт добавляются ординаты сил в мм, "
                        "как на чертеже."), fields=(
            Field("mu_p", bi("pressure (force per piston area) scale",
                             "масштаб давлений (удельных сил)"), unit="MPa/mm", symbol="μ_p",
                  example=0.05, plausible=("0.001 MPa/mm", "1 MPa/mm")),
            Field("mu_alpha", bi("crank-angle scale", "масштаб угла поворота кривошипа"),
                  unit="deg/mm", symbol="μ_α", required=False, example=3,
                  plausible=("0.1 deg/mm", "10 deg/mm")),
        )),
    ),
)

# name: (label, symbol, display unit)
_DECLARED = {
    "V_s": (bi("swept volume of one cylinder", "рабочий объём цилиндра"), "V_s", "L"),
    "V_c": (bi("clearance volume", "объём камеры сгорания"), "V_c", "L"),
    "F_p": (bi("piston area", "площадь поршня"), "F_p", "cm^2"),
    "c_m": (bi("mean piston speed", "средняя скорость поршня"), "c_m", "m/s"),
    "p_c": (bi("pressure at the end of compression", "давление в конце сжатия"), "p_c", "MPa"),
    "p_b": (bi("pressure at the end of expansion", "давление в конце расширения"), "p_b", "MPa"),
    "lambda_p": (bi("pressure rise ratio p_z/p_c", "степень повышения давления p_z/p_c"),
                 "λ_p", ""),
    "p_i": (bi("mean indicated pressure used", "среднее индикаторное давление (принятое)"),
            "p_i", "MPa"),
    "p_i_diagram": (bi("mean indicated pressure of the diagram ∮p dV/V_s",
                       "среднее индикаторное давление по диаграмме ∮p dV/V_s"), "p_i'", "MPa"),
    "p_max": (bi("maximum gas pressure", "максимальное давление газов"), "p_max", "MPa"),
    "brix_OO": (bi("Brix correction OO' = Rλ/2", "поправка Брикса OO' = Rλ/2"), "OO'", "mm"),
    "AC": (bi("Tolle segment AC, specific inertia force at TDC",
              "отрезок AC построения Толле (удельная сила инерции в ВМТ)"), "AC", "MPa"),
    "BD": (bi("Tolle segment BD, specific inertia force at BDC",
              "отрезок BD построения Толле (удельная сила инерции в НМТ)"), "BD", "MPa"),
    "EF": (bi("Tolle segment EF = 3λ m_j Rω²/F_p", "отрезок EF = 3λ m_j Rω²/F_p"), "EF", "MPa"),
    "P_max": (bi("largest driving force |P| of one cylinder", "наибольшая суммарная сила |P| "
                 "одного цилиндра"), "P_max", "kN"),
    "S_max": (bi("largest rod force |S|", "наибольшая сила вдоль шатуна |S|"), "S_max", "kN"),
    "N_max": (bi("largest side force |N|", "наибольшая нормальная сила |N|"), "N_max", "kN"),
    "T_max": (bi("largest tangential force |T| of one cylinder",
                 "наибольшая тангенциальная сила |T| одного цилиндра"), "T_max", "kN"),
    "t_mean_analytic": (bi("mean tangential pressure p_i·i·k/π",
                           "среднее тангенциальное давление p_i·i·k/π"), "t_ср", "MPa"),
    "t_mean_diagram": (bi("mean tangential pressure from the summed curve",
                          "среднее тангенциальное давление по суммарной кривой"), "t_ср'", "MPa"),
    "t_mean_discrepancy": (bi("discrepancy of the two t_mean (diagram − analytic)",
                              "расхождение двух t_ср (диаграмма − расчёт)"), "Δt", "%"),
    "M_mean": (bi("mean indicated torque", "средний индикаторный крутящий момент"), "M_ср",
               "N*m"),
    "M_max": (bi("largest engine torque", "наибольший крутящий момент"), "M_max", "N*m"),
    "M_min": (bi("smallest engine torque", "наименьший крутящий момент"), "M_min", "N*m"),
    "N_i": (bi("indicated power", "индикаторная мощность"), "N_i", "kW"),
    "mu_torque": (bi("torque non-uniformity μ = (M_max − M_min)/M_mean (= the manual's K)",
                     "неравномерность крутящего момента μ = (M_max − M_min)/M_ср (= K методички)"),
                  "μ", ""),
    "A_excess": (bi("excess work: the swing of ∫(M − M_mean)dα over the cycle",
                    "избыточная работа: размах ∫(M − M_ср)dα за цикл"), "A_изб", "J"),
    "A_lobe": (bi("largest single area of M above M_mean (the drawing's; ≤ A_excess)",
                  "наибольшая площадь M над M_ср (по чертежу; ≤ A_изб)"), "F_изб", "J"),
    "alpha_lobe_start": (bi("that area begins at", "начало этой площади"), "α₁", "deg"),
    "alpha_lobe_end": (bi("that area ends at", "конец этой площади"), "α₂", "deg"),
    "I_total": (bi("total moment of inertia needed for δ", "потребный суммарный момент инерции"),
                "I_0", "kg*m^2"),
    "I_crank": (bi("the crank train's own moment of inertia", "момент инерции КШМ"), "I_кшм",
                "kg*m^2"),
    "I_flywheel": (bi("flywheel moment of inertia needed", "потребный момент инерции маховика"),
                   "I_м", "kg*m^2"),
    "I_flywheel_chosen": (bi("flywheel moment of inertia chosen",
                             "момент инерции принятого маховика"), "I_м'", "kg*m^2"),
    "m_flywheel": (bi("flywheel mass M = 4I_м/D² (all of it on the mean rim diameter, as "
                      "coursework sizes it)", "масса маховика m_м = 4I_м/D² (вся на среднем "
                      "диаметре обода, как в курсовой)"), "m_м", "kg"),
    "mD2_flywheel": (bi("flywheel moment m_м D² = 4I_м", "маховой момент m_м D² = 4I_м"),
                     "m_м D²", "kg*m^2"),
    "v_rim": (bi("rim peripheral speed πD n/60", "окружная скорость обода πD n/60"), "v_ок",
              "m/s"),
    "delta_shortcut": (bi("speed irregularity δ = A/(Iω²)", "неравномерность хода δ = A/(Iω²)"),
                       "δ", ""),
    "delta_integrated": (bi("speed irregularity δ from the equation of motion",
                            "неравномерность хода δ по уравнению движения"), "δ'", ""),
}
KEY_RESULTS = ("p_i", "P_max", "M_mean", "N_i", "I_flywheel", "m_flywheel", "delta_integrated")
"""What the coursework comes to: the cycle's pressure, the largest force, the torque and
power, the flywheel and the δ it gives."""
RESULTS = with_key(_DECLARED, KEY_RESULTS)

FORMULAS = [
    bi("Volumes: V_c = V_s/(ε − 1), V_a = V_s + V_c, V_z = ρV_c; V(α) = V_c + F_p S(α) with the "
       "exact piston displacement (the Brix correction OO' = Rλ/2 is reported only)",
       "Объёмы: V_c = V_s/(ε − 1), V_a = V_s + V_c, V_z = ρV_c; V(α) = V_c + F_p S(α) по точной "
       "кинематике (поправка Брикса OO' = Rλ/2 приводится для сравнения)"),
    bi("Polytropes: compression p_x = p_a (V_a/V_x)^n₁, expansion p_x = p_z (V_z/V_x)^n₂; "
       "p_c = p_a ε^n₁, p_b = p_z/δ^n₂, δ = ε/ρ",
       "Политропы: сжатие p_x = p_a (V_a/V_x)^n₁, расширение p_x = p_z (V_z/V_x)^n₂; "
       "p_c = p_a ε^n₁, p_b = p_z/δ^n₂, δ = ε/ρ"),
    bi("Mean indicated pressure of the calculated (unrounded) diagram: p_i = p_c/(ε − 1)·"
       "[λ_p(ρ − 1) + λ_pρ/(n₂ − 1)(1 − δ^(1−n₂)) − 1/(n₁ − 1)(1 − ε^(1−n₁))] − (p_r − p_a)",
       "Среднее индикаторное давление расчётной (нескруглённой) диаграммы: p_i = p_c/(ε − 1)·"
       "[λ_p(ρ − 1) + λ_pρ/(n₂ − 1)(1 − δ^(1−n₂)) − 1/(n₁ − 1)(1 − ε^(1−n₁))] − (p_r − p_a)"),
    bi("Forces per unit piston area: gas Δp_g = p_g − p_0; inertia p_j = −(m_j/F_p) j(α), "
       "j ≈ Rω²(cos α + λ cos 2α) (computed exactly); driving p = Δp_g + p_j; P = p F_p",
       "Удельные силы: газов Δp_г = p_г − p_0; инерции p_j = −(m_j/F_п) j(α), "
       "j ≈ Rω²(cos α + λ cos 2α) (расчёт по точной формуле); суммарная p = Δp_г + p_j; "
       "P = p F_п"),
    bi("Tolle construction: AC = (m_j/F_p)Rω²(1 + λ), BD = (m_j/F_p)Rω²(1 − λ), "
       "EF = 3λ(m_j/F_p)Rω²",
       "Построение Толле: AC = (m_j/F_п)Rω²(1 + λ), BD = (m_j/F_п)Rω²(1 − λ), "
       "EF = 3λ(m_j/F_п)Rω²"),
    bi("Crank train: sin β = λ sin α; S = P/cos β, N = P tg β, K = P cos(α + β)/cos β, "
       "T = P sin(α + β)/cos β, M = TR",
       "КШМ: sin β = λ sin α; S = P/cos β, N = P tg β, K = P cos(α + β)/cos β, "
       "T = P sin(α + β)/cos β, M = TR"),
    bi("Engine: ΣT(α) = Σ_c T₁(α − φ_c), φ_c = θ × (place of cylinder c in the firing order), "
       "θ = 720°/i (four-stroke) or 360°/i",
       "Двигатель: ΣT(α) = Σ_c T₁(α − φ_c), φ_c = θ × (место цилиндра c в порядке работы), "
       "θ = 720°/i (четырёхтактный) или 360°/i"),
    bi("Mean tangential pressure: t_mean = p_i·i·k/π (k = 0.5 four-stroke, 1 two-stroke) against "
       "the mean of ΣT/F_p; coursework accepts < 3 %",
       "Среднее тангенциальное давление: t_ср = p_i·i·k/π (k = 0,5 для четырёхтактного, 1 для "
       "двухтактного) против среднего ΣT/F_п; в курсовой допускается < 3 %"),
    bi("Excess work A = max − min over the cycle of ∫(M − M_mean)dα; torque non-uniformity "
       "μ = (M_max − M_min)/M_mean (the manual's second coefficient K is the same formula: one "
       "number)",
       "Избыточная работа A = max − min по циклу от ∫(M − M_ср)dα; неравномерность крутящего "
       "момента μ = (M_max − M_min)/M_ср (второй коэффициент K методички — та же формула, "
       "это одно число)"),
    bi("Flywheel: I_0 = A/(δω²) = 900A/(π²n²δ), I_fw = I_0 − I_crank; thin rim m = 4I_fw/D², "
       "v = πDn/60 ≤ [v]",
       "Маховик: I_0 = A/(δω²) = 900A/(π²n²δ), I_м = I_0 − I_кшм; тонкий обод m = 4I_м/D², "
       "v = πDn/60 ≤ [v]"),
    bi("Speed irregularity of the inertia used: shortcut δ = A/(Iω²); and from the equation of "
       "motion M(α) = M_mean + I dω/dt, i.e. ω² = ω₀² + (2/I)∫(M − M_mean)dα with the time-mean "
       "ω equal to πn/30, δ = (ω_max − ω_min)/ω_mean",
       "Неравномерность хода при принятом моменте инерции: δ = A/(Iω²); и по уравнению "
       "движения M(α) = M_ср + I dω/dt, т. е. ω² = ω₀² + (2/I)∫(M − M_ср)dα при среднем по "
       "времени ω = πn/30, δ = (ω_max − ω_min)/ω_ср"),
]

REFERENCES = [
    bi("Kolchin A.I., Demidov V.P. Design calculation of automotive and tractor engines. Moscow: "
       "Vysshaya Shkola (chapters on the dynamic calculation and the flywheel).",
       "Колчин А.И., Демидов В.П. Расчёт автомобильных и тракторных двигателей. М.: Высшая "
       "школа (главы «Динамический расчёт», «Маховик»)."),
    bi("Lukanin V.N. (ed.) Internal combustion engines, vol. 2: Dynamics and design. Moscow: "
       "Vysshaya Shkola, 1995 / 2009.",
       "Двигатели внутреннего сгорания. Кн. 2: Динамика и конструирование / под ред. "
       "В.Н. Луканина. М.: Высшая школа, 1995 / 2009."),
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003 "
       "(lab 3: μ, δ and the crank's equation of motion).",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: "
       "ВлГУ, 2003 (лаб. работа №3: μ, δ, уравнение движения)."),
]


# ------------------------------------------------------------------------ slips

TORQUE_RESULTS = ("M_max", "M_min", "mu_torque", "A_excess", "A_lobe", "alpha_lobe_start",
                  "alpha_lobe_end", "I_total", "I_crank", "I_flywheel", "m_flywheel",
                  "mD2_flywheel")
"""Results that follow the engine's summed torque curve."""

FORCE_RESULTS = ("P_max", "S_max", "N_max", "T_max", *TORQUE_RESULTS)
"""Results that follow one cylinder's driving force."""


def _firing_interval_slipped(inputs: Inputs) -> Inputs | None:
    """The cylinders summed 360°/i apart in a four-stroke (720°/i in a two-stroke)."""
    eng = inputs["engine"]
    if eng["i"] < 2:
        return None
    wrong = (360.0 if eng["strokes"] == 4 else 720.0) / eng["i"]
    return inputs.changed("engine", theta=math.radians(wrong))


def _p0_kept(inputs: Inputs) -> Inputs:
    """The absolute gas pressure taken for the gas force: p = p_g + p_j."""
    return inputs.changed("cycle", p_0=Measured(0.0))


def _mass_not_per_area(inputs: Inputs) -> Inputs | None:
    """m_j [kg] taken for m_j/F_p [kg/m²] (not divided by the piston area)."""
    masses = inputs["masses"]
    if "m_j" not in masses:
        return None
    return inputs.changed("masses", m_j=None, m_j_spec=masses["m_j"])


def _bore_as_radius(inputs: Inputs) -> Inputs | None:
    """F_p = πD² (the bore taken for a radius in πr²): as a bore twice as large."""
    geometry = inputs["geometry"]
    if "D" not in geometry:
        return None
    return inputs.changed("geometry", D=Measured(2 * geometry["D"].value))


SLIPS = [
    ("firing_interval",
     bi("the cylinders summed at the wrong firing interval (360°/i for a four-stroke's 720°/i, "
        "or the reverse)",
        "цилиндры просуммированы с неверным интервалом (360°/i вместо 720°/i для "
        "четырёхтактного или наоборот)"), TORQUE_RESULTS, _firing_interval_slipped),
    ("p0_not_subtracted",
     bi("p₀ not subtracted: the absolute gas pressure p_g used for the gas force",
        "не вычтено p₀: в силу давления газов взято абсолютное давление p_г"),
     FORCE_RESULTS, _p0_kept),
    ("mass_not_per_area",
     bi("the reciprocating mass m_j not divided by the piston area F_p",
        "масса m_j не отнесена к площади поршня F_п"),
     ("AC", "BD", "EF", *FORCE_RESULTS), _mass_not_per_area),
    ("bore_as_radius",
     bi("the piston area from the bore taken as a radius (F_p = πD², four times too large)",
        "площадь поршня по диаметру как по радиусу (F_п = πD², вчетверо больше)"),
     ("F_p", "V_s", "V_c", "M_mean", "N_i", "AC", "BD", "EF", *FORCE_RESULTS),
     _bore_as_radius),
]
"""The coursework's classic slips (:mod:`labs.teachers.check`): name, text, the results they change,
and the inputs as the slip leaves them (None where the file gives no room for it). The firing
interval is set through ``engine.theta``, a key no file holds: only a slip sets it."""


# ------------------------------------------------------------------------ reduction

def _firing_order(text: str | None, cylinders: int, inputs: Inputs | None = None):
    if text is None:
        return None
    order = [int(x) for x in re.findall(r"\d+", text)]
    if sorted(order) != list(range(1, cylinders + 1)) or order[0] != 1:
        problem = (f"firing order {text!r} must list cylinders 1..{cylinders} once each, "
                   f"starting with 1")
        fix = "write it as \"1-3-4-2\""
        if inputs is not None:
            raise inputs.error(problem, fix, "engine.firing_order")
        raise InputError(problem, fix)
    return order


def _arguments(x: dict, inputs: Inputs) -> dict:
    """Keyword arguments of :func:`dynamic_calculation` from the flat (SI) inputs."""
    S = x["geometry.S"]
    if "geometry.D" in x:
        area = np.pi * x["geometry.D"] ** 2 / 4
    else:
        area = x["geometry.V_s"] / S
    m_spec = x["masses.m_j_spec"] if "masses.m_j_spec" in x else x["masses.m_j"] / area
    i = inputs["engine"]["i"]
    return dict(
        p_a=x["cycle.p_a"], p_z=x["cycle.p_z"], compression_ratio=x["cycle.eps"],
        n1=x["cycle.n1"], n2=x["cycle.n2"], p_r=x.get("cycle.p_r"), p_0=x["cycle.p_0"],
        pre_expansion_ratio=x["cycle.rho"], mean_indicated_pressure=x.get("cycle.p_i"),
        diagram_fullness=x["cycle.phi_i"],
        crank_radius=S / 2, lambda_=x["geometry.lambda"], piston_area=area,
        angular_speed=x["engine.n"], cylinders=i, strokes=inputs["engine"]["strokes"],
        firing_order=_firing_order(inputs["engine"].get("firing_order"), i),
        reciprocating_mass_per_area=m_spec, target_irregularity=x["flywheel.delta"],
        crank_inertia=x.get("flywheel.I_crank"), crank_inertia_share=x.get("flywheel.k_crank"),
        flywheel_inertia=x.get("flywheel.I_flywheel"), rim_diameter=x["flywheel.D_rim"],
        rim_speed_limit=x["flywheel.v_rim_max"], firing_interval=x.get("engine.theta"))


def _model(inputs: Inputs):
    """The measurement model for :func:`processing.uncertainty.propagate`: the whole
    calculation per draw (its curve steps are one-cycle, 1-D primitives)."""
    def model(**x):
        size = max((np.size(v) for v in x.values() if isinstance(v, np.ndarray)), default=0)
        if size == 0:
            return dynamic_calculation(**_arguments(x, inputs)).values()
        rows = []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DynlabWarning)
            for k in range(size):
                xk = {n: (v[k] if isinstance(v, np.ndarray) else v) for n, v in x.items()}
                try:
                    rows.append(dynamic_calculation(**_arguments(xk, inputs)).values())
                except (InputError, RuntimeError):
                    rows.append(None)
        names = next(r for r in rows if r is not None)
        return {n: np.array([r[n] if r is not None else np.nan for r in rows]) for n in names}
    return model


def _checks(inputs: Inputs) -> None:
    """Inputs the calculation cannot take, and inputs that contradict each other."""
    eng, cyc, geo, mas, fly = (inputs[s] for s in ("engine", "cycle", "geometry", "masses",
                                                   "flywheel"))
    if eng["strokes"] == 4 and "p_r" not in cyc:
        raise inputs.error("a four-stroke cycle needs the exhaust pressure p_r",
                           "add p_r (MPa) from the thermal calculation, about 1.05–1.25 p_0",
                           "cycle.p_r")
    if eng["strokes"] == 2 and "p_r" in cyc:
        raise inputs.error("the two-stroke cycle here has no exhaust stroke, so no p_r",
                           "delete p_r for strokes = 2", "cycle.p_r")
    if "D" not in geo and "V_s" not in geo:
        raise inputs.error("neither the bore D nor the swept volume V_s is given",
                           "add D (mm) or V_s (L)", "geometry.D")
    if ("m_j" in mas) == ("m_j_spec" in mas):
        raise inputs.error("give exactly one of m_j and m_j_spec",
                           "m_j in kg for one cylinder, or m_j_spec = m_j/F_p (kg/m², g/cm²)",
                           "masses.m_j")
    if ("I_crank" in fly) == ("k_crank" in fly):
        raise inputs.error("give exactly one of I_crank and k_crank",
                           "I_crank in kg·m² if known, else k_crank = I_crank/I_total (0.1–0.2)",
                           "flywheel.I_crank")
    if "k_crank" in fly and not fly["k_crank"].value < 1:
        raise inputs.error(f"k_crank must be below 1, got {fly['k_crank'].value:g}",
                           "k_crank = I_crank/I_total, typically 0.1–0.2", "flywheel.k_crank")
    _firing_order(eng.get("firing_order"), eng["i"], inputs)
    eps, rho = cyc["eps"].value, cyc["rho"].value
    if not eps > 1:
        raise inputs.error(f"ε must be > 1, got {eps:g}", "ε = V_a/V_c, 8–11 petrol, 12–22 "
                           "diesel", "cycle.eps")
    if not 1 <= rho < eps:
        raise inputs.error(f"ρ must lie in [1, ε), got {rho:g}",
                           "ρ = V_z/V_c: 1 for petrol, 1.2–1.7 for a diesel", "cycle.rho")
    for name in ("n1", "n2"):
        if not cyc[name].value > 1:
            raise inputs.error(f"{name} must be > 1, got {cyc[name].value:g}",
                               "mean polytropic exponents are about 1.2–1.4", f"cycle.{name}")
    if not 0 < geo["lambda"].value < 1:
        raise inputs.error(f"λ must be in (0, 1), got {geo['lambda'].value:g}",
                           "λ = R/L, typically 0.24–0.32", "geometry.lambda")
    p_c = cyc["p_a"].value * eps ** cyc["n1"].value
    if not cyc["p_z"].value >= p_c:
        raise inputs.error(f"p_z = {cyc['p_z'].value / 1e6:.4g} MPa is below p_c = p_a ε^n₁ = "
                           f"{p_c / 1e6:.4g} MPa", "check p_z, p_a, ε and n₁", "cycle.p_z")
    p_b = cyc["p_z"].value / (eps / rho) ** cyc["n2"].value
    for name, derived, formula in (("p_c", p_c, "p_a ε^n₁"), ("p_b", p_b, "p_z (ρ/ε)^n₂")):
        if name in cyc:
            given = cyc[name].value
            if abs(given / derived - 1) > CONSISTENCY_TOLERANCE:
                warnings.warn(InconsistentInputWarning(
                    f"{name} = {given / 1e6:.4g} MPa given, but the polytrope gives {formula} = "
                    f"{derived / 1e6:.4g} MPa ({100 * (given / derived - 1):+.1f} %); the diagram "
                    f"uses the polytrope: check {name}, ε, ρ and the exponents",
                    f"задано {name} = {given / 1e6:.4g} МПа, а по политропе {formula} = "
                    f"{derived / 1e6:.4g} МПа ({100 * (given / derived - 1):+.1f} %); диаграмма "
                    f"строится по политропе: проверьте {name}, ε, ρ и показатели политроп"))
    c_m = geo["S"].value * eng["n"].value / np.pi
    if not MEAN_PISTON_SPEED[0] <= c_m <= MEAN_PISTON_SPEED[1]:
        warnings.warn(InconsistentInputWarning(
            f"mean piston speed c_m = Sn/30 = {c_m:.3g} m/s is outside the "
            f"{MEAN_PISTON_SPEED[0]:g}–{MEAN_PISTON_SPEED[1]:g} m/s of real engines: check S and "
            f"n (S in mm, n in min⁻¹)",
            f"средняя скорость поршня c_m = Sn/30 = {c_m:.3g} м/с вне "
            f"{MEAN_PISTON_SPEED[0]:g}–{MEAN_PISTON_SPEED[1]:g} м/с реальных двигателей: "
            f"проверьте S и n (S в мм, n в мин⁻¹)"))
    if "D" in geo and "V_s" in geo:
        v = np.pi * geo["D"].value ** 2 / 4 * geo["S"].value
        if abs(geo["V_s"].value / v - 1) > CONSISTENCY_TOLERANCE:
            warnings.warn(InconsistentInputWarning(
                f"V_s = {geo['V_s'].value * 1e3:.4g} L given, but πD²S/4 = {v * 1e3:.4g} L; "
                f"the calculation uses D and S: check V_s (one cylinder, not the engine)",
                f"задано V_s = {geo['V_s'].value * 1e3:.4g} л, а πD²S/4 = {v * 1e3:.4g} л; "
                f"расчёт ведётся по D и S: проверьте V_s (одного цилиндра, а не двигателя)"))


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20031,
           report: bool = True) -> LabResult:
    """The dynamic calculation of a coursework file: tables, figures, flywheel, checks.

    Parameters
    ----------
    inputs : Inputs
        A validated file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed. Design inputs usually carry no uncertainty (then
        every U is 0 and no draws are made); when some do, each draw reruns the whole
        calculation, so at most :data:`MAX_MC_DRAWS` draws are used.
    report : bool
        Also the report's tables, figures and conclusion (False: the results and warnings
        alone, what a check reads; the tables are a third of a check's time).

    Returns
    -------
    LabResult
        Results (stable names) ``V_s``, ``V_c``, ``F_p``, ``c_m``, ``p_c``, ``p_b``,
        ``lambda_p``, ``p_i``, ``p_i_diagram``, ``p_max``, ``brix_OO``, ``AC``, ``BD``,
        ``EF``, ``P_max``, ``S_max``, ``N_max``, ``T_max``, ``t_mean_analytic``,
        ``t_mean_diagram``, ``t_mean_discrepancy``, ``M_mean``, ``M_max``, ``M_min``,
        ``N_i``, ``mu_torque``, ``A_excess``, ``I_total``, ``I_crank``, ``I_flywheel``
        (``I_flywheel_chosen`` if the file chose one), ``m_flywheel``, ``v_rim``,
        ``delta_shortcut``, ``delta_integrated``; the polytrope, force and summed-force
        tables (with a ``[drawing]`` scale μ_p also the forces' and ΣT's ordinates in mm);
        the figures; warnings ``t_mean_discrepancy``, ``rim_speed``,
        ``inconsistent_input``, ``flywheel_not_needed``.
    """
    flat = inputs.flat()
    uncertain = any(isinstance(v, Measured) and v.u > 0 for v in flat.values())
    with collect_notices() as notices:
        _checks(inputs)
        nominal = {k: (v.value if isinstance(v, Measured) else v) for k, v in flat.items()}
        try:
            calc = dynamic_calculation(**_arguments(nominal, inputs))
        except InputError as exc:
            raise exc.located(inputs.file) from None
        prop = propagate(_model(inputs), flat, n_samples=min(n_samples, MAX_MC_DRAWS), seed=seed)
        results = result_values(prop, RESULTS)
        if uncertain:
            flag_estimates(results, [])
    if not report:
        return LabResult.of(inputs, results, warnings=notices)
    tables = [_polytrope_table(calc), *_force_tables(calc), _summed_table(calc),
              *_drawing_tables(calc, inputs.sections.get("drawing"))]
    figures = _figures(calc)
    conclusion = _conclusion(calc)
    if uncertain:
        conclusion.append(bi(
            f"Uncertainties: the calculation was rerun for {min(n_samples, MAX_MC_DRAWS)} Monte "
            f"Carlo draws of the inputs given with a ± (GUM linear estimate checked by them).",
            f"Неопределённости: расчёт повторён для {min(n_samples, MAX_MC_DRAWS)} выборок "
            f"Монте-Карло входных данных, заданных с ± (линейная оценка GUM, проверенная ими)."))
    # every table of the coursework is its calculation worked step by step (the JSON's
    # "tables" carries them as printed); its results are the named ones
    worked = [replace(t, kind="worked") for t in tables]
    return LabResult.of(inputs, results, tables=worked, figures=figures, formulas=FORMULAS,
                        references=REFERENCES, warnings=notices, conclusion=conclusion)


# ------------------------------------------------------------------------ tables

def _column(values, digits: int = 4, decimals: int | None = None) -> list[str]:
    """Table cells of one column: fixed decimals (given, or ``digits`` significant digits of
    the column's largest value), so that rounding noise (1e-15 at a dead centre) prints as 0."""
    v = np.asarray(values, dtype=float)
    top = np.max(np.abs(v)) if v.size else 0.0
    if decimals is None:
        decimals = max(0, digits - 1 - int(math.floor(math.log10(top)))) if top > 0 else 0
    cells = []
    for x in v:
        text = f"{x:.{decimals}f}"
        if text.lstrip("-").strip("0.") == "":
            text = text.lstrip("-")
        cells.append(text.replace("-", "−"))
    return cells


def _ratio(r: float) -> str:
    return f"{r:.0f}" if abs(r - round(r)) < 1e-9 else f"{r:.3f}"


def _rows(columns: dict[str, list[str]]) -> tuple[dict, ...]:
    n = max(len(c) for c in columns.values())
    return tuple({k: c[i] for k, c in columns.items() if i < len(c)} for i in range(n))


def _polytrope_table(calc: DynamicCalculation) -> Table:
    pts, v, c = calc.polytropes, calc.volumes, calc.pressures
    n1 = math.log(c.p_c / pts.compression_pressure[0]) / math.log(pts.compression_ratio[-1])
    n2 = math.log(pts.expansion_pressure[0] / c.p_b) / math.log(pts.expansion_ratio[-1])
    rc, re_ = pts.compression_ratio, pts.expansion_ratio
    columns = {
        "rc": [_ratio(r) for r in rc], "fc": _column(rc ** n1),
        "vc": _column(1e3 * v.total_volume / rc), "pc": _column(pts.compression_pressure / 1e6),
        "re": [_ratio(r) for r in re_], "fe": _column(re_ ** n2),
        "ve": _column(1e3 * v.combustion_volume * re_),
        "pe": _column(pts.expansion_pressure / 1e6)}
    return Table(
        bi("Polytropes: compression at V_a/V_x = 1…ε, expansion at V_x/V_z = 1…δ",
           "Политропы: сжатие при V_a/V_x = 1…ε, расширение при V_x/V_z = 1…δ"),
        (("rc", bi("V_a/V_x", "V_a/V_x")), ("fc", bi("(V_a/V_x)^n₁", "(V_a/V_x)^n₁")),
         ("vc", bi("V_x, L", "V_x, л")), ("pc", bi("p_x, MPa", "p_x, МПа")),
         ("re", bi("V_x/V_z", "V_x/V_z")), ("fe", bi("(V_x/V_z)^n₂", "(V_x/V_z)^n₂")),
         ("ve", bi("V_x, L", "V_x, л")), ("pe", bi("p_x, MPa", "p_x, МПа"))),
        _rows(columns))


SIGNS = bi("P, S and K are positive towards the crankshaft's axis (S compressing the rod), "
           "T in the direction of rotation; N = P tg β follows P and β (β > 0 while the crank "
           "goes from TDC to BDC)",
           "P, S и K положительны, если направлены к оси коленчатого вала (S сжимает шатун), "
           "T — по направлению вращения; N = P tg β по знаку следует P и β (β > 0, пока "
           "кривошип идёт от ВМТ к НМТ)")
"""The sign convention of the force tables (Kolchin's)."""


def _force_tables(calc: DynamicCalculation) -> list[Table]:
    df = calc.force_table()
    alpha = [f"{a:.0f}" for a in df.alpha_deg]
    axis = {"a": alpha, "b": _column(df.beta_deg, decimals=2),
            "pg": _column(df.p_g / 1e6, decimals=3), "dpg": _column(df.dp_g / 1e6, decimals=3),
            "pj": _column(df.p_j / 1e6, decimals=3), "p": _column(df.p / 1e6, decimals=3),
            "P": _column(df.P / 1e3)}
    crank = {"a": alpha, "tb": _column(df.tan_beta), "N": _column(df.N / 1e3),
             "icb": _column(df.inv_cos_beta), "S": _column(df.S / 1e3),
             "cab": _column(df.cos_ab), "K": _column(df.K / 1e3),
             "sab": _column(df.sin_ab), "T": _column(df["T"] / 1e3), "M": _column(df.M)}
    return [
        Table(bi(f"One cylinder every {TABLE_STEP_DEG:g}°: pressures and the driving force "
                 f"(α from TDC of intake)",
                 f"Один цилиндр через {TABLE_STEP_DEG:g}°: давления и суммарная сила "
                 f"(α от ВМТ впуска)"),
              (("a", bi("α, °", "α, °")), ("b", bi("β, °", "β, °")),
               ("pg", bi("p_g, MPa", "p_г, МПа")), ("dpg", bi("Δp_g = p_g − p_0, MPa",
                                                             "Δp_г = p_г − p_0, МПа")),
               ("pj", bi("p_j, MPa", "p_j, МПа")), ("p", bi("p = Δp_g + p_j, MPa",
                                                            "p = Δp_г + p_j, МПа")),
               ("P", bi("P = pF_p, kN", "P = pF_п, кН"))), _rows(axis)),
        Table(bi(f"One cylinder every {TABLE_STEP_DEG:g}°: forces in the crank train",
                 f"Один цилиндр через {TABLE_STEP_DEG:g}°: силы в КШМ"),
              (("a", bi("α, °", "α, °")), ("tb", bi("tg β", "tg β")), ("N", bi("N, kN", "N, кН")),
               ("icb", bi("1/cos β", "1/cos β")), ("S", bi("S, kN", "S, кН")),
               ("cab", bi("cos(α+β)/ cos β", "cos(α+β)/ cos β")), ("K", bi("K, kN", "K, кН")),
               ("sab", bi("sin(α+β)/ cos β", "sin(α+β)/ cos β")), ("T", bi("T, kN", "T, кН")),
               ("M", bi("M = TR, N·m", "M = TR, Н·м"))), _rows(crank)),
        Table(bi(f"One cylinder every {TABLE_STEP_DEG:g}°: the same forces per unit piston "
                 f"area, MPa (signs: {SIGNS['en']})",
                 f"Один цилиндр через {TABLE_STEP_DEG:g}°: те же силы на единицу площади "
                 f"поршня, МПа (знаки: {SIGNS['ru']})"),
              (("a", bi("α, °", "α, °")), ("p", bi("p", "p")), ("N", bi("p_N", "p_N")),
               ("S", bi("p_S", "p_S")), ("K", bi("p_K", "p_K")), ("T", bi("p_T", "p_T"))),
              _rows({"a": alpha, "p": axis["p"],
                     **{k: _column(df[k] / calc.piston_area / 1e6, decimals=3)
                        for k in ("N", "S", "K", "T")}})),
    ]


def _summed_table(calc: DynamicCalculation) -> Table:
    df = calc.summed_table()
    cyl = [f"T{c}" for c in range(1, calc.cylinders + 1)]
    cols = [("a", bi("α₁, °", "α₁, °"))]
    for c, phase in zip(cyl, calc.phases):
        lag = f"{np.degrees(phase):.0f}°"
        cols.append((c, bi(f"T{_sub(c[1:])}, kN (φ {lag})", f"T{_sub(c[1:])}, кН (φ {lag})")))
    cols += [("sum", bi("ΣT, kN", "ΣT, кН")), ("M", bi("M, N·m", "M, Н·м"))]
    scale = np.max(np.abs(df[cyl].to_numpy()))
    cells = {"a": [f"{a:.0f}" for a in df.alpha_deg], "sum": _column(df.T_sum / 1e3),
             "M": _column(df.M)}
    for c in cyl:   # one precision for all cylinder columns
        cells[c] = _column(np.append(df[c].to_numpy(), scale) / 1e3)[:-1]
    theta = np.degrees(calc.firing_interval)
    return Table(bi(f"Tangential forces of all cylinders over one firing interval θ = {theta:g}° "
                    f"(α₁ — crank angle of cylinder 1; cylinder c lags φ behind it; the pattern "
                    f"repeats every θ)",
                    f"Тангенциальные силы всех цилиндров за один интервал θ = {theta:g}° "
                    f"(α₁ — угол поворота кривошипа цилиндра 1; цилиндр c отстаёт от него на φ; "
                    f"картина повторяется через θ)"),
                 tuple(cols), _rows(cells))


def _drawing_tables(calc: DynamicCalculation, scales: dict | None) -> list[Table]:
    """The specific forces and ΣT/F_p as ordinates of the drawing [mm] at its scale μ_p (and
    α as an abscissa at μ_α); none without a ``[drawing]`` section."""
    if not scales:
        return []
    mu_p, mu_alpha = scales["mu_p"].value, scales.get("mu_alpha")
    df, summed = calc.force_table(), calc.summed_table()

    def axis(alpha_deg):
        cols = {"a": [f"{a:.0f}" for a in alpha_deg]}
        if mu_alpha is not None:
            cols["x"] = _column(1e3 * np.radians(alpha_deg) / mu_alpha.value, decimals=1)
        return cols

    def mm(specific):
        return _column(1e3 * np.asarray(specific) / mu_p, decimals=1)

    head = [("a", bi("α, °", "α, °"))] + ([("x", bi("x_α, mm", "x_α, мм"))]
                                         if mu_alpha is not None else [])
    scale = f"μ_p = {mu_p / 1e9:g} MPa/mm" + (f", μ_α = {math.degrees(mu_alpha.value) / 1e3:g}"
                                             f" °/mm" if mu_alpha is not None else "")
    scale_ru = scale.replace("MPa/mm", "МПа/мм").replace("°/mm", "°/мм")
    F = calc.piston_area
    forces = Table(
        bi(f"One cylinder's forces per piston area as drawn, mm ({scale})",
           f"Удельные силы одного цилиндра на чертеже, мм ({scale_ru})"),
        tuple(head) + tuple((k, bi(f"{k}, mm", f"{k}, мм")) for k in ("p", "N", "S", "K", "T")),
        _rows({**axis(df.alpha_deg), "p": mm(df.p),
               **{k: mm(df[k] / F) for k in ("N", "S", "K", "T")}}))
    total = Table(
        bi(f"Summed tangential force per piston area as drawn, mm ({scale})",
           f"Суммарная удельная тангенциальная сила на чертеже, мм ({scale_ru})"),
        tuple(head) + (("sum", bi("ΣT/F_p, mm", "ΣT/F_п, мм")),),
        _rows({**axis(summed.alpha_deg), "sum": mm(summed.T_sum / F)}))
    return [forces, total]


def _number(x: float) -> str:
    return f"{x:.0f}" if abs(x) >= 1e3 else f"{x:.4g}"


def _sub(digits: str) -> str:
    return digits.translate(str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉"))


# ------------------------------------------------------------------------ figures

def _t(lang, en, ru):
    return ru if lang == "ru" else en


def _angle_axis(ax, calc, lang):
    ax.set_xlim(0, np.degrees(calc.cycle))
    ax.set_xticks(np.arange(0, np.degrees(calc.cycle) + 1, 90))
    ax.set_xlabel(_t(lang, "crank angle α, °", "угол поворота кривошипа α, °"))
    ax.grid(alpha=0.3)


def _closed(calc, y):
    """Angle [deg] and values with the first point repeated one cycle on."""
    return (np.degrees(np.append(calc.crank_angle, calc.cycle)), np.append(y, y[0]))


def draw_pv(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """The calculated indicator diagram p–V with the polytrope points of the table."""
    ax = fig.add_subplot(1, 1, 1)
    s = relative_displacement(calc.crank_angle, calc.lambda_) / 2
    V = 1e3 * (calc.volumes.clearance_volume + (calc.volumes.total_volume
                                                - calc.volumes.clearance_volume) * s)
    ax.plot(np.append(V, V[0]), np.append(calc.gas_pressure, calc.gas_pressure[0]) / 1e6,
            color="C0", lw=1.4, label=_t(lang, "calculated diagram", "расчётная диаграмма"))
    pts, v = calc.polytropes, calc.volumes
    ax.plot(1e3 * v.total_volume / pts.compression_ratio, pts.compression_pressure / 1e6, "o",
            color="C1", ms=4, label=_t(lang, "compression points (table)", "точки сжатия (таблица)"))
    ax.plot(1e3 * v.combustion_volume * pts.expansion_ratio, pts.expansion_pressure / 1e6, "s",
            color="C3", ms=4, label=_t(lang, "expansion points (table)",
                                       "точки расширения (таблица)"))
    ax.axhline(calc.p_0 / 1e6, color="grey", ls=":", lw=1)
    marks = [("a", v.total_volume, pts.compression_pressure[0]),
             ("c", v.clearance_volume, calc.pressures.p_c),
             ("z", v.combustion_volume, pts.expansion_pressure[0]),
             ("b", v.total_volume, pts.expansion_pressure[-1])]
    for name, x, y in marks:
        ax.annotate(name, (1e3 * x, y / 1e6), textcoords="offset points", xytext=(5, 3))
    ax.set_xlabel(_t(lang, "cylinder volume V, L", "объём цилиндра V, л"))
    ax.set_ylabel(_t(lang, "pressure p, MPa", "давление p, МПа"))
    ax.set_xlim(0, 1.05e3 * v.total_volume)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()


def draw_p_alpha(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """The indicator diagram unrolled over crank angle, p_g(α)."""
    ax = fig.add_subplot(1, 1, 1)
    a, p = _closed(calc, calc.gas_pressure)
    ax.plot(a, p / 1e6, color="C0")
    ax.axhline(calc.p_0 / 1e6, color="grey", ls=":", lw=1)
    names = ([_t(lang, "intake", "впуск"), _t(lang, "compression", "сжатие"),
              _t(lang, "expansion", "расширение"), _t(lang, "exhaust", "выпуск")]
             if calc.strokes == 4 else [_t(lang, "expansion", "расширение"),
                                        _t(lang, "compression", "сжатие")])
    top = p.max() / 1e6
    for k, name in enumerate(names):
        ax.text(180 * k + 90, 0.92 * top, name, ha="center", fontsize=8, color="0.3")
    _angle_axis(ax, calc, lang)
    ax.set_ylabel(_t(lang, "gas pressure p_g, MPa", "давление газов p_г, МПа"))
    fig.tight_layout()


def draw_tolle(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """The inertia force over the stroke, exact, with the Tolle construction (C, F, D)."""
    ax = fig.add_subplot(1, 1, 1)
    down = calc.crank_angle <= np.pi + 1e-12
    stroke = 2e3 * calc.crank_radius
    x = 1e3 * calc.crank_radius * relative_displacement(calc.crank_angle[down], calc.lambda_)
    ax.plot(x, calc.inertia_pressure[down] / 1e6, color="C0", lw=1.6,
            label=_t(lang, "p_j exact", "p_j точно"))
    tv = calc.tolle
    C, D = np.array([0.0, -tv.ac]), np.array([stroke, tv.bd])
    xE = stroke * tv.ac / (tv.ac + tv.bd)
    F = np.array([xE, tv.ef])
    u = np.linspace(0, 1, 101)[:, None]
    bez = (1 - u) ** 2 * C + 2 * u * (1 - u) * F + u ** 2 * D   # = Tolle's envelope parabola
    ax.plot(bez[:, 0], bez[:, 1] / 1e6, "--", color="C3",
            label=_t(lang, "Tolle parabola", "парабола Толле"))
    ax.plot([C[0], D[0]], [C[1] / 1e6, D[1] / 1e6], color="0.5", lw=0.8)
    ax.plot([C[0], F[0], D[0]], [C[1] / 1e6, F[1] / 1e6, D[1] / 1e6], color="0.5", lw=0.8, ls=":")
    ax.plot([xE, xE], [0, tv.ef / 1e6], color="C2", lw=1.2)
    ax.axhline(0, color="k", lw=0.8)
    for name, (px, py) in {"A": (0, 0), "B": (stroke, 0), "C": C, "D": D, "E": (xE, 0),
                           "F": F}.items():
        ax.plot(px, py / 1e6, "k.", ms=5)
        ax.annotate(name, (px, py / 1e6), textcoords="offset points", xytext=(4, 4))
    ax.set_xlabel(_t(lang, "piston displacement from TDC, mm", "перемещение поршня от ВМТ, мм"))
    ax.set_ylabel(_t(lang, "p_j, MPa", "p_j, МПа"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()


def draw_driving(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """Specific gas, inertia and driving forces of one cylinder over the cycle."""
    ax = fig.add_subplot(1, 1, 1)
    for y, label, style in ((calc.gas_pressure - calc.p_0, "Δp_g = p_g − p_0", "C0"),
                            (calc.inertia_pressure, "p_j", "C1"),
                            (calc.driving_pressure, "p = Δp_g + p_j", "k")):
        a, v = _closed(calc, y)
        ax.plot(a, v / 1e6, color=style, lw=1.6 if style == "k" else 1.0,
                label=label if lang == "en" else label.replace("_g", "_г"))
    ax.axhline(0, color="k", lw=0.6)
    _angle_axis(ax, calc, lang)
    ax.set_ylabel(_t(lang, "force per piston area, MPa", "удельная сила, МПа"))
    ax.legend(fontsize=8)
    fig.tight_layout()


def draw_crank_forces(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """One cylinder's T, K and N over the cycle."""
    ax = fig.add_subplot(1, 1, 1)
    F = calc.piston_area / 1e3
    for y, label, color in ((calc.forces.tangential, "T", "C3"), (calc.forces.radial, "K", "C0"),
                            (calc.forces.side, "N", "C2")):
        a, v = _closed(calc, y)
        ax.plot(a, v * F, color=color, label=label)
    ax.axhline(0, color="k", lw=0.6)
    _angle_axis(ax, calc, lang)
    ax.set_ylabel(_t(lang, "force, kN", "сила, кН"))
    ax.legend(fontsize=8)
    fig.tight_layout()


def draw_summed(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """The engine's summed tangential force with its means and the excess-work lobe shaded."""
    ax = fig.add_subplot(1, 1, 1)
    F = calc.piston_area / 1e3
    a, T = _closed(calc, calc.tangential_sum * F)
    ax.plot(a, T, color="C0", label="ΣT")
    ax.axhline(calc.t_mean_diagram * F, color="C3", lw=1.2,
               label=_t(lang, "mean of ΣT", "среднее ΣT"))
    ax.axhline(calc.t_mean_analytic * F, color="k", ls="--", lw=1,
               label=_t(lang, "p_i·i·k/π · F_p", "p_i·i·k/π · F_п"))
    ex = calc.excess
    # E(α) = ∫(M − M_mean)dα repeats every firing interval θ, so its extremes recur each θ:
    # shade the one lobe from the minimum forward to the next maximum
    theta = np.degrees(calc.firing_interval)
    lo = np.degrees(ex.crank_angle_min) % np.degrees(calc.cycle)
    hi = lo + (np.degrees(ex.crank_angle_max - ex.crank_angle_min) % theta or theta)
    span = ((a >= lo) & (a <= hi)) | (a <= hi - np.degrees(calc.cycle))
    ax.fill_between(a, T, calc.t_mean_diagram * F, where=span, color="C1", alpha=0.3,
                    label=_t(lang, f"excess work A = {_number(ex.work)} J",
                             f"избыточная работа A = {_number(ex.work)} Дж"))
    _angle_axis(ax, calc, lang)
    bottom, top = T.min(), T.max()
    ax.set_ylim(bottom - 0.05 * (top - bottom), top + 0.45 * (top - bottom))  # room for the key
    ax.set_ylabel(_t(lang, "summed tangential force ΣT, kN", "суммарная тангенциальная сила "
                                                                "ΣT, кН"))
    ax.legend(fontsize=7, loc="upper center", ncol=2)
    fig.tight_layout()


def draw_speed(fig, calc: DynamicCalculation, lang: str = "en") -> None:
    """Crank speed over the cycle from the equation of motion with the inertia used."""
    ax = fig.add_subplot(1, 1, 1)
    a, w = _closed(calc, calc.speed.angular_speed)
    ax.plot(a, w, color="C0", label="ω(α)")
    ax.axhline(calc.angular_speed, color="k", ls="--", lw=1,
               label=_t(lang, "ω_mean = πn/30", "ω_ср = πn/30"))
    ax.set_title(_t(lang, f"δ = {calc.speed.speed_irregularity:.5g} (integrated), "
                          f"{calc.delta_shortcut:.4g} (A/(Iω²))",
                    f"δ = {calc.speed.speed_irregularity:.5g} (интегрирование), "
                    f"{calc.delta_shortcut:.4g} (A/(Iω²))"), fontsize=9)
    _angle_axis(ax, calc, lang)
    ax.set_ylabel(_t(lang, "crank speed ω, rad/s", "угловая скорость ω, рад/с"))
    ax.legend(fontsize=8)
    fig.tight_layout()


def _figures(calc: DynamicCalculation) -> list[Figure]:
    def fig(name, en, ru, draw, size=(6.4, 3.6)):
        return Figure(name, bi(en, ru), lambda f, lang: draw(f, calc, lang), size)

    return [
        fig("pv", "Calculated indicator diagram p–V with the polytrope points",
            "Расчётная индикаторная диаграмма p–V с точками политроп", draw_pv, (6.4, 4.2)),
        fig("p_alpha", "Indicator diagram unrolled over crank angle (exact V(α), no Brix "
            "construction)", "Развёрнутая по углу поворота кривошипа индикаторная диаграмма "
            "(точная V(α), без построения Брикса)", draw_p_alpha),
        fig("tolle", "Inertia force of the reciprocating masses over the stroke: exact curve "
            "and Tolle's construction (AC at TDC, BD at BDC, EF at E)",
            "Сила инерции поступательно движущихся масс по ходу поршня: точная кривая и "
            "построение Толле (AC в ВМТ, BD в НМТ, EF в точке E)", draw_tolle),
        fig("driving", "Gas, inertia and driving force per unit piston area, one cylinder",
            "Удельные силы давления газов, инерции и суммарная сила, один цилиндр", draw_driving),
        fig("crank_forces", "Tangential T, radial K and side N forces of one cylinder",
            "Тангенциальная T, радиальная K и нормальная N силы одного цилиндра",
            draw_crank_forces),
        fig("summed", "Summed tangential force of the engine, its mean and the excess-work lobe",
            "Суммарная тангенциальная сила двигателя, её среднее и площадка избыточной работы",
            draw_summed),
        fig("speed", "Crank speed over the cycle from the equation of motion (inertia used)",
            "Угловая скорость коленчатого вала за цикл по уравнению движения (принятый момент "
            "инерции)", draw_speed),
    ]


# ------------------------------------------------------------------------ conclusion

def _conclusion(calc: DynamicCalculation) -> list[dict]:
    v = calc.values()
    gap = v["t_mean_discrepancy"]
    ok = abs(gap) < T_MEAN_TOLERANCE
    lines = [
        bi(f"Calculated diagram: p_c = {v['p_c'] / 1e6:.3f} MPa, p_z = {v['p_max'] / 1e6:.3f} MPa, "
           f"p_b = {v['p_b'] / 1e6:.3f} MPa; its mean indicated pressure "
           f"{v['p_i_diagram'] / 1e6:.4f} MPa.",
           f"Расчётная диаграмма: p_c = {v['p_c'] / 1e6:.3f} МПа, p_z = {v['p_max'] / 1e6:.3f} МПа, "
           f"p_b = {v['p_b'] / 1e6:.3f} МПа; её среднее индикаторное давление "
           f"{v['p_i_diagram'] / 1e6:.4f} МПа."),
        bi(f"Inertia per unit area: AC = {v['AC'] / 1e6:.3f}, BD = {v['BD'] / 1e6:.3f}, "
           f"EF = {v['EF'] / 1e6:.3f} MPa; one cylinder's largest forces: |P| = "
           f"{v['P_max'] / 1e3:.4g} kN, |S| = {v['S_max'] / 1e3:.4g} kN, |N| = "
           f"{v['N_max'] / 1e3:.4g} kN, |T| = {v['T_max'] / 1e3:.4g} kN.",
           f"Удельные силы инерции: AC = {v['AC'] / 1e6:.3f}, BD = {v['BD'] / 1e6:.3f}, "
           f"EF = {v['EF'] / 1e6:.3f} МПа; наибольшие силы одного цилиндра: |P| = "
           f"{v['P_max'] / 1e3:.4g} кН, |S| = {v['S_max'] / 1e3:.4g} кН, |N| = "
           f"{v['N_max'] / 1e3:.4g} кН, |T| = {v['T_max'] / 1e3:.4g} кН."),
        bi(f"Mean tangential pressure: {v['t_mean_analytic'] / 1e6:.4f} MPa from p_i, "
           f"{v['t_mean_diagram'] / 1e6:.4f} MPa from the summed curve, discrepancy "
           f"{100 * gap:+.2f} % — " + ("within the 3 % accepted." if ok else
                                       "ABOVE the 3 % accepted: see the warning."),
           f"Среднее тангенциальное давление: {v['t_mean_analytic'] / 1e6:.4f} МПа по p_i, "
           f"{v['t_mean_diagram'] / 1e6:.4f} МПа по суммарной кривой, расхождение "
           f"{100 * gap:+.2f} % — " + ("в пределах допустимых 3 %." if ok else
                                       "БОЛЬШЕ допустимых 3 %: см. предупреждение.")),
        bi(f"Mean indicated torque {v['M_mean']:.5g} N·m ({v['N_i'] / 1e3:.4g} kW); torque "
           f"non-uniformity μ = {v['mu_torque']:.3f} (the manual's K is the same number).",
           f"Средний индикаторный момент {v['M_mean']:.5g} Н·м ({v['N_i'] / 1e3:.4g} кВт); "
           f"неравномерность крутящего момента μ = {v['mu_torque']:.3f} (K методички — то же "
           f"число)."),
        bi(f"Excess work A = {v['A_excess']:.5g} J; for δ = {calc.target_irregularity:g} the "
           f"rotating parts need I_0 = {v['I_total']:.4g} kg·m², of which the crank train gives "
           f"{v['I_crank']:.4g} and the flywheel {v['I_flywheel']:.4g} kg·m².",
           f"Избыточная работа A = {v['A_excess']:.5g} Дж; для δ = {calc.target_irregularity:g} "
           f"нужен суммарный момент инерции I_0 = {v['I_total']:.4g} кг·м², из них КШМ "
           f"{v['I_crank']:.4g}, маховик {v['I_flywheel']:.4g} кг·м²."),
    ]
    if calc.rim is not None:
        fast = not calc.rim.within_limit
        lines.append(bi(
            f"Flywheel rim on D = {1e3 * calc.rim_diameter:.0f} mm: mass {calc.rim.mass:.4g} kg, "
            f"peripheral speed {calc.rim.peripheral_speed:.1f} m/s "
            + (f"— ABOVE the allowed {calc.rim.speed_limit:g} m/s." if fast else
               f"(allowed {calc.rim.speed_limit:g} m/s)."),
            f"Обод маховика на D = {1e3 * calc.rim_diameter:.0f} мм: масса {calc.rim.mass:.4g} кг, "
            f"окружная скорость {calc.rim.peripheral_speed:.1f} м/с "
            + (f"— БОЛЬШЕ допустимой {calc.rim.speed_limit:g} м/с." if fast else
               f"(допустимо {calc.rim.speed_limit:g} м/с).")))
    d1, d2 = v["delta_shortcut"], v["delta_integrated"]
    lines.append(bi(
        f"Speed irregularity with I = {calc.inertia_used:.4g} kg·m²: δ = {d1:.4g} by A/(Iω²), "
        f"{d2:.4g} by integrating the equation of motion ({100 * (d2 / d1 - 1):+.2f} %); "
        f"typical δ: automotive 0.01–0.02, tractor 0.003–0.01.",
        f"Неравномерность хода при I = {calc.inertia_used:.4g} кг·м²: δ = {d1:.4g} по A/(Iω²), "
        f"{d2:.4g} по уравнению движения ({100 * (d2 / d1 - 1):+.2f} %); типичные δ: "
        f"автомобильные 0,01–0,02, тракторные 0,003–0,01."))
    return lines


# ------------------------------------------------------------------------ variants

VARIED = {"engine": ("n",), "cycle": ("p_a", "p_z", "eps", "n1", "n2"),
          "geometry": ("D", "S", "lambda"), "masses": ("m_j_spec",),
          "flywheel": ("delta", "D_rim")}
"""The example's data a variant changes (each by up to ± 10 %)."""


def write_synthetic(out_dir, seed: int = 0) -> dict:
    """Write a variant of the bundled 1.8 L petrol four (:data:`VARIED` changed by up to
    ± 10 %) with its answer key (:func:`labs.sample_variant.design_variant`)."""
    from .sample_variant import design_variant

    return design_variant("dyncalc", "car_petrol.toml", out_dir, seed, VARIED)
