"""An engine on a test bed, seen through a toothed wheel and an inductive sensor (lab 3).

The scene behind the speed-irregularity lab, modelled just enough: the gas and
reciprocating-inertia torque of the cylinders (:mod:`processing.crank.dynamics`) drives the
flywheel against a dynamometer; a toothed wheel on the crankshaft (pitch errors, an optional
missing-tooth gap) passes a variable-reluctance sensor whose voltage is sampled by an ADC.
The true speed ω(α), time table t(α), tooth-edge times and δ come with the signal, so a
reduction that recovers δ from the samples has proven itself.

Crank angle α is cumulative from 0 at the start of the run; α = 0 (mod the cycle) is the TDC
of cylinder 1 at the start of its intake stroke (four-stroke; the firing TDC of cylinder 1 is
at 360°) or its firing TDC (two-stroke), as in :mod:`processing.crank.dynamics`. Cycle k spans
α ∈ [kΦ, (k + 1)Φ), Φ = 4π or 2π. SI throughout.

References
----------
- dynlab FORMULAS.md, section B (forces, torque, flywheel) and "Lab 3" (a toothed wheel, an
  inductive sensor, δ over one working cycle).
- Panov V.V. et al., "Dinamika dvigatelei vnutrennego sgoraniya: metodicheskie ukazaniya k
  laboratornym rabotam", Vladimir State University, 2003, lab 3.
- Robert Bosch GmbH, "Automotive Handbook", section "Sensors": inductive engine-speed
  sensor on a 60-2 trigger wheel (u = -N dΦ/dt, amplitude proportional to speed).
"""
from __future__ import annotations

import numbers
from collections.abc import Iterator
from dataclasses import asdict, dataclass

import numpy as np

from ..diagnostics import InputError, check_positive
from processing.crank.dynamics import (compression_pressure, crank_speed_cycle, crank_train_forces,
                                       cycle_period, firing_phases, gas_force, indicator_pressure,
                                       mean_torque, reciprocating_inertia_force, sum_cylinders)
from ..result import Record

STEP = np.radians(0.1)
"""Default crank-angle step of a run's grid, 0.1°. [rad]"""

BLOCK = 2 ** 16
"""Samples per block of random draws: block b of a record draws its clock jitter from
``np.random.default_rng([seed, b, 1])``, the tooth channel's noise from ``[seed, b, 2]`` and
spikes from ``[seed, b, 2, 1]`` (TDC channel: 3), so the samples do not depend on the chunk
size. (No entropy list ends in 0: SeedSequence ignores trailing zeros.)"""


# --- the engine and its run -------------------------------------------------------------------

@dataclass(frozen=True)
class Engine:
    """An engine on a test bed: crank train, indicator diagram, inertia, regime.

    The defaults are a 1.5 l four-cylinder four-stroke petrol car engine at full load and 1800
    min⁻¹: M_mean ≈ 86 N·m and δ ≈ 0.0185 (by :func:`~processing.crank.dynamics.crank_speed_cycle`).
    """

    cylinders: int = 4
    """Number of cylinders i, firing at even intervals Φ/i. [1]"""
    strokes: int = 4
    """4 (cycle Φ = 4π) or 2 (Φ = 2π)."""
    bore: float = 0.082
    """Cylinder bore D. [m]"""
    crank_radius: float = 0.035
    """R (stroke 2R). [m]"""
    lambda_: float = 0.28
    """λ = R/L. [1]"""
    compression_ratio: float = 9.5
    """ε. [1]"""
    p_a: float = 0.09e6
    """Intake pressure and start of compression (naturally aspirated: 0.08-0.09 MPa). [Pa]"""
    p_z: float = 5.5e6
    """Maximum cycle pressure (petrol engine at full load: 4-7 MPa). [Pa]"""
    n1: float = 1.36
    """Polytropic exponent of compression. [1]"""
    n2: float = 1.26
    """Polytropic exponent of expansion. [1]"""
    p_r: float = 0.11e6
    """Exhaust-stroke pressure (four-stroke only; ignored for two-stroke). [Pa]"""
    reciprocating_mass: float = 0.55
    """m_j per cylinder: piston group plus the rod's small-end share. [kg]"""
    inertia: float = 0.2
    """J of everything turning with the crankshaft (crank train, flywheel, clutch). [kg·m²]"""
    mean_angular_speed: float = 1800 * np.pi / 30
    """Time-mean crank speed of the steady regime, ω_mean = πn/30. [rad/s]"""
    cycle_variation: float = 0.0
    """Relative standard deviation of each firing's combustion torque (cycle-to-cycle
    scatter of combustion): the torque above the motored one is scaled by max(1 + v·N(0, 1), 0)
    per firing. [1]"""
    speed_drift: float = 0.0
    """Relative change of the dynamometer's speed set point over the run: it ramps linearly
    from ω_0 to ω_0(1 + speed_drift) (0: steady, every cycle alike; 0.05: the engine speeds up
    about 5 % and the cycles shorten). [1]"""
    firing: bool = True
    """False: fuel cut, the engine is motored (compression and expansion on the n1 polytrope
    through p_z = p_c = p_a ε^n1; the dynamometer drives it)."""


@dataclass(frozen=True)
class EngineRun(Record):
    """True crank motion of a run (:func:`run_engine`, :func:`coast_run`) on a fine angle grid."""

    crank_angle: np.ndarray
    """Cumulative crank angle, a uniform grid from 0 over the whole run. [rad]"""
    time: np.ndarray
    """t(α), t[0] = 0, strictly increasing: ∫dα/ω by the trapezoid rule. [s]"""
    angular_speed: np.ndarray
    """ω(α). [rad/s]"""
    cycle_angle: float
    """Φ: 4π (four-stroke), 2π (two-stroke, and the coast run: one revolution). [rad]"""
    delta_cycles: np.ndarray
    """True δ = (ω_max - ω_min)/ω_mean of each complete cycle, ω_mean = Φ/(cycle duration)
    (zeros for the coast run: it has no cyclic fluctuation). [1]"""
    delta: float
    """True δ of the ensemble-average cycle ω(α), ω_mean its time mean; equals each cycle's δ
    when the cycles are alike (0 for the coast run). [1]"""
    mean_angular_speed: float
    """Time-mean ω over the run, α_end/t_end. [rad/s]"""
    settings: dict
    """How the run was made (JSON-able): kind ("engine" or "coast") and its parameters."""

    def cycles_within(self, duration: float) -> tuple[float, float]:
        """True δ and mean speed of the whole cycles within the first ``duration`` of the run
        (what a record of that length holds, from t = 0).

        δ of their average cycle ω(α), ω_mean its time mean, as :attr:`delta`; the mean
        speed Φ·k/(t_k − t_0) over the k cycles.

        Returns
        -------
        tuple of float
            δ [1] and mean angular speed [rad/s].
        """
        h = self.crank_angle[1] - self.crank_angle[0]
        points = int(round(self.cycle_angle / h))
        k = int(self.angle_at(duration) // self.cycle_angle)
        if k < 1:
            raise ValueError(f"cycles_within: no whole cycle within {duration:g} s")
        return (_average_delta(self.angular_speed[:k * points + 1], k, points, h,
                               self.cycle_angle),
                float(k * self.cycle_angle / self.time[k * points]))

    def angle_at(self, t) -> np.ndarray:
        """Crank angle α(t) at times t in [0, t_end] [s], by linear interpolation. [rad]"""
        t = np.asarray(t, dtype=float)
        _check_within("t", t, self.time[-1], "s")
        return np.interp(t, self.time, self.crank_angle)

    def speed_at_angle(self, alpha) -> np.ndarray:
        """Crank speed ω(α) at angles α in [0, α_end] [rad], by linear interpolation. [rad/s]"""
        alpha = np.asarray(alpha, dtype=float)
        _check_within("alpha", alpha, self.crank_angle[-1], "rad")
        return np.interp(alpha, self.crank_angle, self.angular_speed)


def _check_within(name, value, end, unit):
    bad = ~((value >= 0) & (value <= end))
    if np.any(bad):
        raise InputError(f"{name} must lie in [0, {end:.6g}] {unit}, the span of the run, got "
                         f"{np.ravel(value[bad])[0]:.6g}", "ask only about the run's own span")


@dataclass(frozen=True)
class _CycleTorque:
    """One cycle's torque parts on the grid α_j = jΦ/N, j = 0..N (end point included)."""

    steady: np.ndarray        # M(α) of every cylinder at the mean speed, no scatter, j < N [N·m]
    motored: np.ndarray       # Σ_c gas torque of the motored cycle [N·m]
    inertia: np.ndarray       # Σ_c reciprocating-inertia torque at ω_mean [N·m]
    combustion: np.ndarray    # (N + 1, i): each cylinder's gas torque above the motored one
    firing_offset: np.ndarray  # (N + 1, i): firing number at α_j, minus the cycle number


def _cycle_torque(engine: Engine, points: int) -> _CycleTorque:
    period = cycle_period(engine.strokes)
    alpha = np.arange(points) * (period / points)
    area = np.pi * engine.bore ** 2 / 4
    p_c = compression_pressure(1.0, engine.p_a, engine.compression_ratio, engine.n1)
    diagram = {"p_a": engine.p_a, "compression_ratio": engine.compression_ratio, "n1": engine.n1,
               "lambda_": engine.lambda_, "strokes": engine.strokes,
               "p_r": engine.p_r if engine.strokes == 4 else None}

    def torque(force):
        return crank_train_forces(alpha, force, engine.crank_radius, engine.lambda_).torque

    motored = torque(gas_force(indicator_pressure(alpha, p_z=p_c, n2=engine.n1, **diagram), area))
    combustion = (torque(gas_force(indicator_pressure(alpha, p_z=engine.p_z, n2=engine.n2,
                                                      **diagram), area)) - motored
                  if engine.firing else np.zeros(points))
    inertia = torque(reciprocating_inertia_force(alpha, engine.reciprocating_mass,
                                                 engine.crank_radius, engine.mean_angular_speed,
                                                 engine.lambda_))
    phases = firing_phases(engine.cylinders, strokes=engine.strokes)
    total = {name: sum_cylinders(alpha, curve, phases, strokes=engine.strokes)
             for name, curve in (("motored", motored), ("inertia", inertia))}
    each = np.stack([sum_cylinders(alpha, combustion, [phase], strokes=engine.strokes)
                     for phase in phases], axis=1)
    # cylinder c fires (starts expanding) at Φ - 2π + φ_c, i.e. grid index `start`
    start = points - np.rint(2 * np.pi / period * points).astype(int) + np.rint(
        phases / period * points).astype(int)
    offset = (np.arange(points + 1)[:, None] - start) // points
    return _CycleTorque(steady=total["motored"] + total["inertia"] + each.sum(axis=1),
                        motored=np.append(total["motored"], total["motored"][0]),
                        inertia=np.append(total["inertia"], total["inertia"][0]),
                        combustion=np.vstack([each, each[:1]]), firing_offset=offset)


def _cycle_rows(omega: np.ndarray, cycles: int, points: int) -> np.ndarray:
    """ω over each of the first ``cycles`` cycles, a row each, its last point the next
    cycle's first (``points`` grid steps a cycle)."""
    return np.column_stack([omega[:cycles * points].reshape(cycles, points),
                            omega[points:(cycles + 1) * points:points]])


def _average_delta(omega: np.ndarray, cycles: int, points: int, h: float,
                   period: float) -> float:
    """True δ = (ω_max − ω_min)/ω_mean of the average of the first ``cycles`` cycles ω(α),
    ω_mean its time mean Φ/∫dα/ω (grid step ``h``, cycle angle Φ = ``period``)."""
    average = _cycle_rows(omega, cycles, points).mean(axis=0)
    return float((average.max() - average.min()) * _cumulative_trapezoid(1 / average, h)[-1]
                 / period)


def run_engine(engine: Engine, n_cycles: int, *, seed=0, step=STEP) -> EngineRun:
    """Integrate the crank's equation of motion over ``n_cycles`` working cycles.

    Parameters
    ----------
    engine : Engine
        The engine and its regime.
    n_cycles : int
        Number of working cycles, ≥ 1.
    seed : int, keyword-only
        Seed of the cycle-to-cycle combustion scatter (``np.random.default_rng(seed)``).
    step : float, keyword-only
        Crank-angle step of the grid, rounded so that a cycle holds a multiple of i steps.
        Memory: 24 bytes per step (0.1° at 1800 min⁻¹: 2.6 MB per second of run). [rad]

    Returns
    -------
    EngineRun
        α grid, t(α), ω(α), δ of each cycle and of the average cycle, the mean speed.

    Raises
    ------
    InputError
        For a bad parameter.
    RuntimeError
        If the engine stalls (ω² ≤ 0: the cycle's work cannot carry the crank over the
        compression; raise the inertia or the speed).

    Notes
    -----
    Energy form of the equation of motion J dω/dt = M(α) - M_load, integrated exactly
    (trapezoid on the grid), cycle after cycle:

    .. math:: \\omega^2(\\alpha) = \\omega^2(k\\Phi)
              + \\frac{2}{J}\\int_{k\\Phi}^{\\alpha}\\left(M_{motored} + r_k M_j
              + \\sum_c s_{f} M_{comb,c} - L_k\\right)d\\alpha,
              \\qquad t(\\alpha) = \\int_0^{\\alpha}\\frac{d\\alpha}{\\omega}

    M_motored, M_comb,c (gas torque above the motored one, on the expansion stroke) and M_j
    (reciprocating inertia at ω_mean) come from :mod:`processing.crank.dynamics` (indicator
    diagram → gas force → T → M = TR), shifted by the firing phases. Each firing f is scaled
    by s_f = max(1 + v z_f, 0), z_f ~ N(0, 1); M_j by r_k = (ω(kΦ)/ω_0)². The dynamometer is
    speed-holding: its controller samples the speed at each cycle start and holds

    .. math:: L_k = M_{mean} + \\frac{J\\omega_0}{2\\Phi}
              \\left(\\omega(k\\Phi) - \\omega_0\\left(1 + d\\,\\frac{t_k}{T}\\right)\\right)

    for the cycle (a speed error halves every cycle), M_mean the engine's mean torque, d the
    speed drift, T = n_cycles Φ/ω_mean. The run starts on the steady periodic solution of
    :func:`~processing.crank.dynamics.crank_speed_cycle` (ω_0 = ω(0)): with no scatter and no drift
    every cycle repeats it and δ equals its δ.

    References
    ----------
    FORMULAS.md B and Lab 3; lab manual, lab 3 (M_i = M_resist + J_o dω/dt).
    """
    if not (isinstance(n_cycles, (int, np.integer)) and n_cycles >= 1):
        raise InputError(f"n_cycles must be a positive integer, got {n_cycles!r}",
                         "give the number of working cycles to run")
    check_positive("step", step, "rad")
    for name, unit in (("bore", "m"), ("crank_radius", "m"), ("inertia", "kg*m^2"),
                       ("mean_angular_speed", "rad/s")):
        check_positive(name, getattr(engine, name), unit)
    for name in ("reciprocating_mass", "cycle_variation"):
        if not getattr(engine, name) >= 0:
            raise InputError(f"{name} must be ≥ 0, got {getattr(engine, name)!r}",
                             f"give Engine.{name} ≥ 0 (0 to leave the effect out)")
    period = cycle_period(engine.strokes)
    if not (isinstance(engine.cylinders, (int, np.integer)) and engine.cylinders >= 1):
        raise InputError(f"cylinders must be a positive integer, got {engine.cylinders!r}",
                         "give the number of cylinders i")
    points = engine.cylinders * max(1, round(period / (engine.cylinders * step)))
    h = period / points
    parts = _cycle_torque(engine, points)
    grid = np.arange(points) * h
    m_mean = mean_torque(grid, parts.steady, period=period)
    inertia = engine.inertia
    omega0 = crank_speed_cycle(grid, parts.steady, inertia, engine.mean_angular_speed,
                               period=period).initial_angular_speed
    scale = np.maximum(1 + engine.cycle_variation * np.random.default_rng(seed).standard_normal(
        (n_cycles + 3, engine.cylinders)), 0)
    gain = inertia * omega0 / (2 * period)
    nominal = n_cycles * period / engine.mean_angular_speed
    cylinder = np.arange(engine.cylinders)

    omega = np.empty(n_cycles * points + 1)
    time = np.empty_like(omega)
    omega[0], time[0] = omega0, 0.0
    for k in range(n_cycles):
        j0 = k * points
        w_start, t_start = omega[j0], time[j0]
        load = m_mean + gain * (w_start - omega0 * (1 + engine.speed_drift * t_start / nominal))
        torque = (parts.motored + (w_start / omega0) ** 2 * parts.inertia - load
                  + np.sum(parts.combustion * scale[k + 2 + parts.firing_offset, cylinder], axis=1))
        square = w_start ** 2 + 2 / inertia * _cumulative_trapezoid(torque, h)
        if not square.min() > 0:
            raise RuntimeError(f"run_engine: the engine stalls in cycle {k} (ω² ≤ 0): raise "
                               "Engine.inertia or mean_angular_speed, or lower cycle_variation")
        w = np.sqrt(square)
        omega[j0:j0 + points + 1] = w
        time[j0:j0 + points + 1] = t_start + _cumulative_trapezoid(1 / w, h)

    crank_angle = np.arange(n_cycles * points + 1) * h
    rows = _cycle_rows(omega, n_cycles, points)
    durations = np.diff(time[::points])
    delta_cycles = (rows.max(axis=1) - rows.min(axis=1)) * durations / period
    return EngineRun(
        crank_angle=crank_angle, time=time, angular_speed=omega, cycle_angle=period,
        delta_cycles=delta_cycles,
        delta=_average_delta(omega, n_cycles, points, h, period),
        mean_angular_speed=float(crank_angle[-1] / time[-1]),
        settings={"kind": "engine", "engine": _json(asdict(engine)), "n_cycles": int(n_cycles),
                  "seed": int(seed), "step": h})


def _cumulative_trapezoid(values, h):
    """∫ values dα from the first point, trapezoid rule on a uniform step h, first value 0."""
    return np.concatenate([[0.0], np.cumsum((values[1:] + values[:-1]) * (h / 2))])


def coast_run(mean_angular_speed, duration, *, deceleration=1.0,
              step=STEP) -> EngineRun:
    """A wheel spinning down smoothly: engine off, constant friction torque.

    Used to calibrate a toothed wheel's pitch errors: the speed has no cyclic fluctuation, so
    the differences between tooth periods come from the wheel alone.

    Parameters
    ----------
    mean_angular_speed : float
        Time-mean speed over the run. [rad/s]
    duration : float
        Length of the run. [s]
    deceleration : float, keyword-only, default 1
        Constant deceleration a = M_friction/J, ≥ 0. [rad/s²]
    step : float, keyword-only
        Crank-angle step of the grid (rounded to divide the run's angle). [rad]

    Returns
    -------
    EngineRun
        Cycle = one revolution (2π); ``delta_cycles`` are zeros (one per complete revolution)
        and ``delta`` is 0: the spin-down is a trend, not a cyclic irregularity.

    Raises
    ------
    InputError
        If the wheel would stop within the run (ω_mean ≤ a·duration/2) or a value is not > 0.

    Notes
    -----
    .. math:: \\omega(t) = \\omega_s - a t,\\quad \\omega_s = \\omega_{mean} + \\frac{aT}{2},
              \\quad \\omega(\\alpha) = \\sqrt{\\omega_s^2 - 2a\\alpha},
              \\quad t(\\alpha) = \\frac{2\\alpha}{\\omega_s + \\omega(\\alpha)}
    """
    check_positive("mean_angular_speed", mean_angular_speed, "rad/s")
    check_positive("duration", duration, "s")
    check_positive("step", step, "rad")
    if not 0 <= deceleration < 2 * mean_angular_speed / duration:
        raise InputError(f"deceleration must be in [0, 2ω_mean/duration) = "
                         f"[0, {2 * mean_angular_speed / duration:.4g}) rad/s², got {deceleration!r}",
                         "lower the deceleration or shorten the run: the wheel must not stop")
    start = mean_angular_speed + deceleration * duration / 2
    end_angle = mean_angular_speed * duration
    points = max(1, int(np.ceil(end_angle / step)))
    crank_angle = np.arange(points + 1) * (end_angle / points)
    omega = np.sqrt(start ** 2 - 2 * deceleration * crank_angle)
    revolutions = int(end_angle // (2 * np.pi))
    return EngineRun(
        crank_angle=crank_angle, time=2 * crank_angle / (start + omega), angular_speed=omega,
        cycle_angle=2 * np.pi, delta_cycles=np.zeros(revolutions), delta=0.0,
        mean_angular_speed=float(mean_angular_speed),
        settings={"kind": "coast", "mean_angular_speed": float(mean_angular_speed),
                  "duration": float(duration), "deceleration": float(deceleration),
                  "initial_angular_speed": float(start), "step": float(crank_angle[1])})


# --- the toothed wheel and the sensor ---------------------------------------------------------

@dataclass(frozen=True)
class ToothWheel:
    """A toothed (trigger) wheel on the crankshaft.

    Tooth k (k = 0..teeth - missing - 1) is centred at reference_angle + k·2π/teeth plus its
    pitch error; the teeth teeth - missing..teeth - 1 are absent, so the gap lies just before
    tooth 0 (a 60-2 wheel: teeth=60, missing=2).
    """

    teeth: int = 60
    """z: tooth spaces around the wheel, the missing ones included."""
    missing: int = 0
    """Teeth removed at the reference gap (0, 1, 2, ...)."""
    pitch_error: float = 0.0
    """Standard deviation of each tooth centre's angular position error, < pitch/20
    (e.g. np.radians(0.05)). [rad]"""
    seed: int = 0
    """Seed of the pitch errors (drawn once for all z positions: the errors of the present
    teeth do not depend on ``missing``)."""
    reference_angle: float = 0.0
    """Crank angle of tooth 0 (the first after the gap) from the engine's α = 0. [rad]"""

    @property
    def pitch(self) -> float:
        """Nominal tooth pitch 2π/z. [rad]"""
        return 2 * np.pi / self.teeth

    def _check(self):
        if not (isinstance(self.teeth, (int, np.integer)) and self.teeth >= 3):
            raise InputError(f"teeth must be an integer ≥ 3, got {self.teeth!r}",
                             "give the number of tooth spaces z, missing teeth included")
        if not (isinstance(self.missing, (int, np.integer)) and 0 <= self.missing <= self.teeth - 2):
            raise InputError(f"missing must be an integer in [0, teeth - 2], got {self.missing!r}",
                             "give the teeth removed at the gap (0, 1 or 2)")
        if not 0 <= self.pitch_error < self.pitch / 20:
            raise InputError(f"pitch_error must be in [0, pitch/20) = [0, "
                             f"{np.degrees(self.pitch / 20):.4g}°), got "
                             f"{np.degrees(float(self.pitch_error)):.4g}°",
                             "give the standard deviation of the tooth position error (≥ 0)")

    def _present(self) -> tuple[np.ndarray, np.ndarray]:
        """Centres of the present teeth in [0, 2π), increasing, and their tooth numbers."""
        self._check()
        error = np.random.default_rng(self.seed).normal(0.0, self.pitch_error, self.teeth)
        number = np.arange(self.teeth - self.missing)
        centre = np.mod(self.reference_angle + number * self.pitch + error[number], 2 * np.pi)
        order = np.argsort(centre)
        return centre[order], number[order]

    def tooth_angles(self) -> np.ndarray:
        """Centres α_k of the present teeth over one revolution, increasing in [0, 2π). [rad]"""
        return self._present()[0]

    def edge_angles(self) -> tuple[np.ndarray, np.ndarray]:
        """True tooth edges over one revolution: the falling zeros of dΦ/dα.

        Returns
        -------
        angle : ndarray
            Each edge's crank angle, increasing in [0, 2π). [rad]
        tooth : ndarray of int
            Its tooth number (0 after the gap).

        Notes
        -----
        Roots of the analytic Φ'(α) (see :class:`Sensor`) by bisection in α_k ± σ/2 to the
        last bit: at the gap and next to a misplaced neighbour they differ slightly from α_k.
        """
        centre, number = self._present()
        width = self.pitch / 4
        low, high = centre - width / 2, centre + width / 2
        if not (np.all(_flux_slope(low, centre, width) > 0)
                and np.all(_flux_slope(high, centre, width) < 0)):
            raise RuntimeError("ToothWheel.edge_angles: a tooth pulse has no falling zero near "
                               "its centre (pitch errors too large)")
        for _ in range(60):
            middle = (low + high) / 2
            falling = _flux_slope(middle, centre, width) < 0
            high = np.where(falling, middle, high)
            low = np.where(falling, low, middle)
        edge = np.mod((low + high) / 2, 2 * np.pi)
        order = np.argsort(edge)
        return edge[order], number[order]


def _flux_slope(alpha, centres, width):
    """dΦ/dα at each α of the sum of Gaussian bumps exp(-d²/(2 width²)) at ``centres``,
    d = α - centre wrapped into [-π, π)."""
    alpha = np.asarray(alpha, dtype=float)
    total = np.zeros_like(alpha)
    for centre in centres:
        d = np.mod(alpha - centre + np.pi, 2 * np.pi) - np.pi
        total -= d / width ** 2 * np.exp(-0.5 * (d / width) ** 2)
    return total


@dataclass(frozen=True)
class Sensor:
    """Inductive (variable-reluctance) sensor, its front end and the ADC.

    The flux through the coil is a sum of Gaussian bumps, one per present tooth, of std
    σ = pitch/4; the voltage u = dΦ/dt = Φ'(α)ω, scaled so that its peak is ``amplitude`` at the
    run's mean speed. Each tooth gives a bipolar pulse, positive before the tooth centre and
    negative after: the tooth's edge is the falling zero crossing of u.
    """

    sample_rate: float = 100e3
    """f_s. [Hz]"""
    amplitude: float = 1.0
    """Peak of u at the run's mean speed (it grows with speed). [V]"""
    snr_db: float = 40.0
    """RMS of u at the mean speed over the RMS of the white noise; np.inf for none. [dB]"""
    jitter: float = 0.0
    """Standard deviation of the sampling instants (clock jitter). [s]"""
    offset: float = 0.0
    """DC offset added before clipping. [V]"""
    spikes_per_second: float = 0.0
    """Rate of ignition-like interference spikes at random (Poisson) instants, each 1-3
    samples long, of random sign and 2-5 times ``amplitude``. [1/s]"""
    clip: float = np.inf
    """The input clips at ±clip. [V]"""
    bits: int = 16
    """ADC resolution over ±full_scale (≤ 16: codes are int16)."""
    full_scale: float = 2.0
    """ADC range ±full_scale; codes saturate beyond it. [V]"""
    tdc: bool = False
    """Also record a TDC channel: one narrow bump (σ = pitch/8) per revolution at α = 0 mod 2π,
    by the same u = dΦ/dt law, its falling zero crossing at the TDC of cylinder 1."""

    def _check(self):
        for name, unit in (("sample_rate", "Hz"), ("amplitude", "V"), ("full_scale", "V"),
                           ("clip", "V")):
            check_positive(name, getattr(self, name), unit)
        if np.isnan(self.snr_db):
            raise InputError("snr_db is NaN", "give the signal-to-noise ratio in dB, np.inf for none")
        for name in ("jitter", "spikes_per_second"):
            if not getattr(self, name) >= 0:
                raise InputError(f"{name} must be ≥ 0, got {getattr(self, name)!r}",
                                 f"give Sensor.{name} ≥ 0 (0 for none)")
        if not (isinstance(self.bits, (int, np.integer)) and 2 <= self.bits <= 16):
            raise InputError(f"bits must be an integer in [2, 16], got {self.bits!r}",
                             "give the ADC resolution (codes are stored as int16)")


@dataclass(frozen=True)
class Recording(Record):
    """An ADC record of the tooth (and TDC) channel with its true answers (:func:`record`)."""

    signal: np.ndarray
    """ADC codes of the tooth channel, int16; volts = code·volts_per_code."""
    volts_per_code: float
    """ADC step, 2·full_scale/2^bits. [V]"""
    sample_rate: float
    """f_s; sample n is nominally at t = n/f_s. [Hz]"""
    tdc_signal: np.ndarray | None
    """ADC codes of the TDC channel, or None."""
    edge_times: np.ndarray
    """True times of the tooth edges within the record (falling zeros of u), increasing. [s]"""
    edge_teeth: np.ndarray
    """Tooth number (0..teeth - missing - 1, 0 after the gap) of each edge."""
    tdc_times: np.ndarray | None
    """True times of TDC (α = 0 mod 2π) within the record, or None without a TDC channel. [s]"""
    run: EngineRun
    wheel: ToothWheel
    sensor: Sensor
    seed: int
    """Seed of the record's noise, jitter and spikes."""

    def answer_key(self) -> dict:
        """The true answers and every setting, JSON-able (infinite settings as None).

        Returns
        -------
        dict
            ``delta`` (the run's average cycle), ``delta_cycles`` and ``cycle_start_times`` of
            the cycles wholly inside the record, ``n_cycles`` (their number), the run's
            ``mean_angular_speed`` [rad/s] and ``mean_speed_rpm``, ``samples_per_tooth``,
            ``n_samples``, ``n_edges``, ``sample_rate``, ``volts_per_code``, and the
            ``wheel``, ``sensor``, ``run`` settings and the record's ``seed``.
        """
        run, period = self.run, self.run.cycle_angle
        end = (self.signal.size - 1) / self.sample_rate
        starts = np.interp(np.arange(run.delta_cycles.size + 1) * period, run.crank_angle, run.time)
        inside = int(np.sum(starts[1:] <= end))
        return {
            "delta": float(run.delta), "delta_cycles": run.delta_cycles[:inside].tolist(),
            "cycle_start_times": starts[:inside].tolist(), "n_cycles": inside,
            "mean_angular_speed": float(run.mean_angular_speed),
            "mean_speed_rpm": float(run.mean_angular_speed * 30 / np.pi),
            "samples_per_tooth": samples_per_tooth(run, self.wheel, self.sensor),
            "n_samples": int(self.signal.size), "n_edges": int(self.edge_times.size),
            "sample_rate": float(self.sample_rate), "volts_per_code": float(self.volts_per_code),
            "wheel": _json(asdict(self.wheel)), "sensor": _json(asdict(self.sensor)),
            "run": run.settings, "seed": int(self.seed)}


def _json(settings: dict) -> dict:
    """Plain ints, floats and bools; non-finite floats as None."""
    def plain(value):
        if isinstance(value, dict):
            return _json(value)
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        if isinstance(value, numbers.Integral):
            return int(value)
        if isinstance(value, numbers.Real):
            return float(value) if np.isfinite(value) else None
        return value
    return {key: plain(value) for key, value in settings.items()}


def samples_per_tooth(run: EngineRun, wheel: ToothWheel, sensor: Sensor) -> float:
    """Samples per tooth period at the run's mean speed.

    Returns
    -------
    float
        f_s / (z n/60) = 2π f_s / (z ω_mean). [1]
    """
    return float(sensor.sample_rate * 2 * np.pi / (wheel.teeth * run.mean_angular_speed))


@dataclass(frozen=True)
class _Channel:
    """Φ' over one revolution as a uniform lookup table, and the volts per unit of Φ'ω."""

    table: np.ndarray   # Φ'(2πm/M), m = 0..M-1
    rise: np.ndarray    # table[m + 1] - table[m], wrapped
    gain: float         # u = gain·Φ'·ω [V per (rad/s)]
    stream: int         # the channel's random streams: [seed, block, stream(, 1)]; 1 is the clock


def _channel(centres, width, amplitude, mean_speed, stream) -> _Channel:
    size = 2 ** max(16, int(np.ceil(np.log2(2 * np.pi * 128 / width))))
    table = _flux_slope(np.arange(size) * (2 * np.pi / size), centres, width)
    return _Channel(table=table, rise=np.roll(table, -1) - table,
                    gain=amplitude / (np.abs(table).max() * mean_speed), stream=stream)


def _lookup(channel: _Channel, alpha):
    size = channel.table.size
    x = alpha * (size / (2 * np.pi))
    index = x.astype(np.int64)
    x -= index
    index &= size - 1
    return channel.table[index] + x * channel.rise[index]


def _samples(run, sensor, duration):
    end = run.time[-1] if duration is None else duration
    if not 0 < end <= run.time[-1]:
        raise InputError(f"duration must be in (0, {run.time[-1]:.6g}] s (the run), got {duration!r}",
                         "record no longer than the run, or run more cycles")
    count = int(np.floor(end * sensor.sample_rate))
    if count < 2:
        raise InputError(f"the record would hold {count} samples", "raise duration or sample_rate")
    return count


def _blocks(run, sensor, seed, count, channels, noise) -> Iterator[list[np.ndarray]]:
    """int16 codes of each of ``channels``, block by block of BLOCK samples."""
    lsb = 2 * sensor.full_scale / 2 ** sensor.bits
    low, high = -2 ** (sensor.bits - 1), 2 ** (sensor.bits - 1) - 1
    for block in range(-(-count // BLOCK)):
        first = block * BLOCK
        size = min(BLOCK, count - first)
        t = np.arange(first, first + size) / sensor.sample_rate
        if sensor.jitter > 0:
            t += np.random.default_rng([seed, block, 1]).normal(0.0, sensor.jitter, size)
            np.clip(t, 0.0, run.time[-1], out=t)
        alpha = np.interp(t, run.time, run.crank_angle)
        omega = np.interp(t, run.time, run.angular_speed)
        codes = []
        for channel in channels:
            u = _lookup(channel, alpha)
            u *= omega
            u *= channel.gain
            if noise > 0:
                u += np.random.default_rng([seed, block, channel.stream]).normal(0.0, noise, size)
            u += sensor.offset
            if sensor.spikes_per_second > 0:
                _add_spikes(u, np.random.default_rng([seed, block, channel.stream, 1]),
                            sensor.spikes_per_second * size / sensor.sample_rate, sensor.amplitude)
            if np.isfinite(sensor.clip):
                np.clip(u, -sensor.clip, sensor.clip, out=u)
            u *= 1 / lsb
            np.rint(u, out=u)
            np.clip(u, low, high, out=u)
            codes.append(u.astype(np.int16))
        yield codes


def _add_spikes(u, rng, expected, amplitude):
    """Add Poisson(expected) spikes of 1-3 samples, random sign, 2-5 × amplitude, in place
    (a spike starting at the end of a block is cut there)."""
    count = rng.poisson(expected)
    start = rng.integers(0, u.size, count)
    length = rng.integers(1, 4, count)
    height = rng.choice([-1.0, 1.0], count) * rng.uniform(2, 5, count) * amplitude
    index = start[:, None] + np.arange(3)
    keep = (np.arange(3) < length[:, None]) & (index < u.size)
    np.add.at(u, index[keep], np.broadcast_to(height[:, None], index.shape)[keep])


def _channels(run, wheel, sensor, which) -> tuple[list[_Channel], float]:
    """The channels named in ``which`` and the noise std, from the tooth channel's RMS. [V]"""
    sensor._check()
    tooth = _channel(wheel.tooth_angles(), wheel.pitch / 4, sensor.amplitude,
                     run.mean_angular_speed, 2)
    made = [tooth] if "tooth" in which else []
    if "tdc" in which:
        made.append(_channel([0.0], wheel.pitch / 8, sensor.amplitude, run.mean_angular_speed, 3))
    rms = np.sqrt(np.mean(tooth.table ** 2)) * tooth.gain * run.mean_angular_speed
    return made, rms * 10 ** (-sensor.snr_db / 20)


def iter_signal(run: EngineRun, wheel: ToothWheel, sensor: Sensor, *, chunk=2 ** 20, seed=0,
                duration=None, channel="tooth") -> Iterator[np.ndarray]:
    """The samples of :func:`record`, chunk by chunk, in bounded memory (for large files).

    Parameters
    ----------
    run, wheel, sensor
        As for :func:`record`.
    chunk : int, keyword-only
        Samples per yielded array (the last may be shorter).
    seed : int, keyword-only
        Seed of the noise, jitter and spikes.
    duration : float, optional
        Length of the record (default: the run). [s]
    channel : {'tooth', 'tdc'}, keyword-only
        Which channel (``'tdc'`` needs ``sensor.tdc``).

    Returns
    -------
    iterator of ndarray of int16
        Consecutive chunks of the ADC codes: the same samples whatever ``chunk``, since the
        random draws are made per fixed block of :data:`BLOCK` samples.

    Raises
    ------
    InputError
        At the call, before any sample is made.
    """
    if channel not in ("tooth", "tdc") or (channel == "tdc" and not sensor.tdc):
        raise InputError(f"channel must be 'tooth' or, with Sensor(tdc=True), 'tdc'; got {channel!r}",
                         "ask for a channel the sensor records")
    if not (isinstance(chunk, (int, np.integer)) and chunk >= 1):
        raise InputError(f"chunk must be a positive integer, got {chunk!r}", "e.g. chunk=2**20")
    count = _samples(run, sensor, duration)
    channels, noise = _channels(run, wheel, sensor, [channel])
    return _rechunk((codes[0] for codes in _blocks(run, sensor, seed, count, channels, noise)),
                    chunk)


def _rechunk(blocks, chunk) -> Iterator[np.ndarray]:
    """The concatenated ``blocks`` cut into arrays of ``chunk`` (the last may be shorter)."""
    held, size = [], 0
    for block in blocks:
        held.append(block)
        size += block.size
        if size >= chunk:
            joined = np.concatenate(held)
            whole = size - size % chunk
            yield from np.split(joined[:whole], whole // chunk)
            held, size = [joined[whole:]], size - whole
    if size:
        yield np.concatenate(held)


def record(run: EngineRun, wheel: ToothWheel, sensor: Sensor, *, seed=0,
           duration=None) -> Recording:
    """Sample the sensor over the run: the ADC codes and the true edge and TDC times.

    Parameters
    ----------
    run : EngineRun
        The crank's motion (:func:`run_engine`, :func:`coast_run`).
    wheel : ToothWheel
        The toothed wheel.
    sensor : Sensor
        Sensor, front end and ADC.
    seed : int, keyword-only
        Seed of the noise, jitter and spikes (block b draws from ``default_rng([seed, b, …])``).
    duration : float, optional
        Length of the record, ≤ the run (default: the run). [s]

    Returns
    -------
    Recording
        ⌊duration·f_s⌋ samples at t_n = n/f_s (+ jitter), the true edge times, the run.

    Notes
    -----
    With Φ'(α) = -Σ_k (α - α_k)/σ² exp(-(α - α_k)²/(2σ²)) over the present teeth (wrapped,
    σ = pitch/4) as a table over one revolution (≥ 2^16 points, ≥ 128 per σ):

    .. math:: u_n = g\\,\\Phi'(\\alpha(t_n))\\,\\omega(t_n) + e_n + u_0 + \\text{spikes},
              \\qquad g = \\frac{\\text{amplitude}}{\\max|\\Phi'|\\,\\omega_{mean}}

    then clipped to ±clip and quantised: code = clip(round(u/q), -2^(b-1), 2^(b-1) - 1),
    q = 2·full_scale/2^b; e_n is white noise of std RMS(u at ω_mean)·10^(-SNR/20). α(t_n) and
    ω(t_n) are interpolated linearly in the run's table; jittered instants are clipped to the
    run. The true edge times are t(2πr + α_edge) for the roots α_edge of Φ'
    (:meth:`ToothWheel.edge_angles`), by the same interpolation, so a noise-free record crosses
    zero at them. Edges and TDCs are listed for t in [0, (n_samples - 1)/f_s].
    """
    count = _samples(run, sensor, duration)
    channels, noise = _channels(run, wheel, sensor, ["tooth", "tdc"] if sensor.tdc else ["tooth"])
    blocks = list(_blocks(run, sensor, seed, count, channels, noise))
    signals = [np.concatenate([codes[c] for codes in blocks]) for c in range(len(channels))]
    end_angle = run.angle_at((count - 1) / sensor.sample_rate)
    revolution = np.arange(int(end_angle // (2 * np.pi)) + 2)[:, None] * (2 * np.pi)
    angle, tooth = wheel.edge_angles()
    edges = (revolution + angle).ravel()
    inside = (edges >= 0) & (edges <= end_angle)
    tdc = revolution[:, 0]
    tdc = tdc[tdc <= end_angle]
    return Recording(
        signal=signals[0], volts_per_code=2 * sensor.full_scale / 2 ** sensor.bits,
        sample_rate=float(sensor.sample_rate), tdc_signal=signals[1] if sensor.tdc else None,
        edge_times=np.interp(edges[inside], run.crank_angle, run.time),
        edge_teeth=np.broadcast_to(tooth, (revolution.size, tooth.size)).ravel()[inside],
        tdc_times=np.interp(tdc, run.crank_angle, run.time) if sensor.tdc else None,
        run=run, wheel=wheel, sensor=sensor, seed=int(seed))
