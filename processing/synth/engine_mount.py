"""An engine block on elastic mounts, shaken by its crank train, seen through accelerometers
(lab 4).

The scene behind the vibration lab, modelled just enough: the block is a rigid body on mounts
with four degrees of freedom, each a damped spring of its own natural frequency (heave z,
lateral y, roll θ_x about the crankshaft's axis, pitch θ_y), excited by

- the reciprocating inertia forces of the cylinders, P_j = −m_j j(α) (exact kinematics,
  :func:`processing.crank.dynamics.reciprocating_inertia_force`), along the vertical cylinder axes;
- the rotating masses' centrifugal forces m_r R ω² along each crank and a residual unbalance
  U ω² (kg·m times ω²) at 1×;
- the torque reaction: minus the cylinders' gas and inertia torque
  (:func:`processing.crank.dynamics.crank_train_forces` of the indicator diagram of
  :func:`processing.crank.dynamics.indicator_pressure`), with a small cylinder-to-cylinder spread of
  combustion and, optionally, one cylinder without combustion (ignition cut: the motored
  cycle, compression and expansion on the n₁ polytrope);
- the pitch moments of the cylinders' vertical forces and of the unbalance about the centre
  of mass, and a share of the torque reaction (mounts whose elastic axis is inclined).

Over a working cycle everything is periodic in the crank angle, so each excitation is a sum of
orders (half orders for a four-stroke engine) and the block's response to each is exact in the
frequency domain. A point's acceleration follows from the rigid body's motion; an accelerometer (its
own resonance, a sensitivity in V per m/s², white electrical noise, a converter's full scale that
clips) records it beside cylinder 1's ignition pickup (a falling edge at each firing TDC of cylinder
1). The true band readings come from the true orders in closed form
(:func:`processing.vibration.band_rms.meter_gain`): neither noise nor the sensor's resonance is in
them; the noise is set by its signal-to-noise ratio in the worst band.

Crank angle α is measured from cylinder 1's firing TDC (where :mod:`processing.crank.dynamics`
counts from its intake TDC, 360° earlier). SI throughout.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 4 (the excitation: P_j, P_r, the torque reaction, unbalance, misfire).
.. [2] S. S. Rao, Mechanical Vibrations, 5th ed., Pearson, 2011, §3.6 (a damped single
       degree of freedom under a harmonic force) and §10.2 (piezoelectric accelerometers:
       usable up to a fraction of their resonance).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from processing.vibration.band_rms import QUANTITIES, meter_gain, white_noise_rms
from processing.crank.dynamics import (crank_train_forces, firing_phases, gas_force,
                                       indicator_pressure, reciprocating_inertia_force)
from .engine import Engine

GRID = 2048
"""Samples of the excitation over one working cycle (orders up to GRID/4 are exact)."""

MAX_ORDER = 40.0
"""Highest order the scene carries."""

DIRECTIONS = ("vertical", "transverse", "longitudinal")


@dataclass(frozen=True)
class Block:
    """The engine block on its mounts: its inertia and the mounts' natural frequencies.

    The defaults: a 1.5 l four-cylinder car engine with its gearbox on a test bench's soft
    mounts (natural frequencies 4–8 Hz, below the lowest half order of a run).
    """

    mass: float = 140.0
    """m of the block with everything bolted to it. [kg]"""
    roll_inertia: float = 5.0
    """J_x about the crankshaft's axis through the centre of mass. [kg·m²]"""
    pitch_inertia: float = 9.0
    """J_y about the transverse axis through the centre of mass. [kg·m²]"""
    frequencies: tuple = (6.0, 5.0, 4.5, 7.5)
    """Natural frequencies of heave, lateral, roll and pitch on the mounts. [Hz]"""
    damping_ratio: float = 0.08
    """ζ of every mode. [1]"""
    cylinder_spacing: float = 0.09
    """Distance between neighbouring cylinder axes; the row is centred on the centre of
    mass. [m]"""
    rotating_mass: float = 0.0
    """m_r per crank left after the counterweights, reduced to the crank radius. [kg]"""
    unbalance: float = 4e-4
    """Residual unbalance of the crank train (mass times radius). [kg·m]"""
    unbalance_angle: float = 0.7
    """Its angle ahead of crank 1. [rad]"""
    unbalance_position: float = -0.25
    """Its place along the crankshaft from the centre of mass (the flywheel's end). [m]"""
    roll_to_pitch: float = 0.1
    """Share of the torque reaction that turns the block about its transverse axis: the
    mounts' elastic axis is inclined to the crankshaft's. [1]"""
    spread: float = 0.03
    """Relative standard deviation of the cylinders' combustion (fixed per engine). [1]"""


@dataclass(frozen=True)
class Point:
    """A measuring point and direction on the block."""

    position: tuple
    """(x along the crankshaft, y transverse, z up) from the centre of mass. [m]"""
    direction: str
    """One of :data:`DIRECTIONS`."""
    name: str = ""


POINTS = (Point((0.10, 0.0, 0.30), "vertical", "cylinder head"),
          Point((0.10, 0.0, 0.30), "transverse", "cylinder head"),
          Point((0.25, 0.10, 0.15), "longitudinal", "front cover"))
"""The default points: the manual's three directions (vertical largest, then transverse,
then longitudinal)."""


@dataclass(frozen=True)
class Accelerometer:
    """A piezoelectric accelerometer and the recorder's channel behind it."""

    sensitivity: float = 0.0102
    """[V per m/s²] (10.2 mV/(m/s²) ≈ 100 mV/g)."""
    resonance: float = 28e3
    """Mounted resonance. [Hz]"""
    damping_ratio: float = 0.02
    snr_db: float = 30.0
    """The vibration's band reading over the white noise's, in the worst of the three bands
    (:func:`processing.vibration.band_rms.white_noise_rms`): the displacement's, as a rule, since
    the noise integrated twice piles up near the 1.4 Hz edge. [dB]"""
    full_scale: float = 5.0
    """The converter's range ±; beyond it the record clips. [V]"""
    sample_rate: float = 25600.0
    """[Hz]"""

    def response(self, frequency):
        """The sensor's gain over its sensitivity, 1/(1 − r² + 2iζr), r = f/f_r. [1]"""
        r = np.asarray(frequency, dtype=float) / self.resonance
        return 1.0 / (1.0 - r * r + 2j * self.damping_ratio * r)


@dataclass(frozen=True)
class Response:
    """The orders of a point's acceleration at one speed (:func:`point_orders`)."""

    order: np.ndarray
    """k = 0.5, 1, … [1]"""
    coefficient: np.ndarray
    """Complex amplitude c_k: a(α) = Σ Re(c_k e^{ikα}). [m/s²]"""
    angular_speed: float
    """ω. [rad/s]"""

    @property
    def frequency(self) -> np.ndarray:
        """k ω/2π. [Hz]"""
        return self.order * self.angular_speed / (2 * np.pi)

    def band_rms(self, quantity: str) -> float:
        """True band reading: ``√(Σ |c_k|²/2 g(f_k))``. [m/s², m/s or m]"""
        g = meter_gain(self.frequency, quantity) ** 2
        return float(np.sqrt(np.sum(np.abs(self.coefficient) ** 2 / 2 * g)))

    def peak_to_peak(self, quantity: str) -> float:
        """True peak-to-peak of the band signal over a working cycle: each order through the
        meter's zero-phase band and (i kω)⁻ⁿ. [m/s², m/s or m]"""
        n = "avx".index(quantity)
        c = self.coefficient * meter_gain(self.frequency, quantity) * (-1j) ** n
        alpha = np.linspace(0, 4 * np.pi, 8 * GRID, endpoint=False)
        return float(np.ptp((c[None, :] * np.exp(1j * np.outer(alpha, self.order))).real.sum(1)))

    def truth(self) -> dict:
        """The band readings a, v, x, their peak-to-peak values (``a_pp`` …) and the first and
        second orders' amplitudes."""
        out = {q: self.band_rms(q) for q in QUANTITIES}
        out.update({f"{q}_pp": self.peak_to_peak(q) for q in QUANTITIES})
        for k in (1, 2):
            out[f"order{k}"] = float(np.abs(self.coefficient[self.order == k][0]))
        return out


def cylinder_factors(engine: Engine, block: Block, rng: np.random.Generator) -> np.ndarray:
    """Each cylinder's combustion relative to the mean: 1 + spread·N(0, 1), drawn once. [1]"""
    return 1.0 + block.spread * rng.standard_normal(engine.cylinders)


def excitation(engine: Engine, block: Block, angular_speed: float, *, factors=None,
               cut: int | None = None, firing_order=None) -> tuple[np.ndarray, np.ndarray]:
    """The generalised forces on the block over one working cycle, as orders.

    Parameters
    ----------
    engine : Engine
        Crank train and indicator diagram (:class:`processing.synth.engine.Engine`; its
        speed is replaced by ``angular_speed``).
    block : Block
    angular_speed : float
        ω. [rad/s]
    factors : array_like, optional
        Each cylinder's combustion relative to the mean (:func:`cylinder_factors`).
    cut : int, optional
        The cylinder (1-based) whose ignition is cut.
    firing_order : sequence of int, optional

    Returns
    -------
    order : ndarray
        k = 0.5, 1, … ≤ :data:`MAX_ORDER`.
    force : ndarray
        (4, m) complex amplitudes of the heave force, lateral force [N], roll and pitch
        moments [N·m]: Q(α) = Σ Re(c_k e^{ikα}).
    """
    i = engine.cylinders
    factors = np.ones(i) if factors is None else np.asarray(factors, dtype=float)
    phases = firing_phases(i, strokes=4, firing_order=firing_order)
    alpha = np.arange(GRID) * (4 * np.pi / GRID)
    area = np.pi * engine.bore ** 2 / 4
    diagram = dict(p_a=engine.p_a, compression_ratio=engine.compression_ratio, n1=engine.n1,
                   lambda_=engine.lambda_, p_r=engine.p_r)
    p_c = engine.p_a * engine.compression_ratio ** engine.n1
    positions = (np.arange(i) - (i - 1) / 2) * block.cylinder_spacing
    w2 = angular_speed ** 2
    lateral = block.unbalance * w2 * np.sin(alpha + block.unbalance_angle)
    heave = block.unbalance * w2 * np.cos(alpha + block.unbalance_angle)
    roll = np.zeros(GRID)
    pitch = -block.unbalance_position * heave
    for c in range(i):
        theta = alpha - phases[c]                       # from cylinder c's firing TDC
        at_intake = theta + 2 * np.pi                   # processing.crank.dynamics counts from here
        motored = indicator_pressure(at_intake, p_z=p_c, n2=engine.n1, **diagram)
        fired = indicator_pressure(at_intake, p_z=engine.p_z, n2=engine.n2, **diagram)
        share = 0.0 if cut == c + 1 else factors[c]
        pressure = motored + share * (fired - motored)
        p_j = reciprocating_inertia_force(theta, engine.reciprocating_mass,
                                          engine.crank_radius, angular_speed, engine.lambda_)
        torque = crank_train_forces(theta, gas_force(pressure, area) + p_j,
                                    engine.crank_radius, engine.lambda_).torque
        up = -p_j + block.rotating_mass * engine.crank_radius * w2 * np.cos(theta)
        heave += up
        lateral += block.rotating_mass * engine.crank_radius * w2 * np.sin(theta)
        roll -= torque
        pitch -= positions[c] * up + block.roll_to_pitch * torque
    spectrum = np.fft.rfft(np.stack([heave, lateral, roll, pitch]), axis=1) * (2.0 / GRID)
    m = int(2 * MAX_ORDER)
    return 0.5 * np.arange(1, m + 1), spectrum[:, 1:m + 1]


def point_orders(engine: Engine, block: Block, point: Point, angular_speed: float,
                 **options) -> Response:
    """The orders of a point's acceleration along its direction at speed ω.

    Each degree of freedom q (mass or inertia μ, natural frequency ω_n, ζ) answers an order of
    frequency Ω = kω with q̈ = −Ω² Q/(μ(ω_n² − Ω² + 2iζω_nΩ)); a point at (x, y, z) moves
    vertically by z + y θ_x − x θ_y, transversely by y − z θ_x, longitudinally by z θ_y.

    Parameters
    ----------
    engine, block, point, angular_speed
    **options
        ``factors``, ``cut``, ``firing_order`` of :func:`excitation`.

    Returns
    -------
    Response
    """
    order, force = excitation(engine, block, angular_speed, **options)
    omega = order * angular_speed
    inertia = np.array([block.mass, block.mass, block.roll_inertia, block.pitch_inertia])
    wn = 2 * np.pi * np.asarray(block.frequencies, dtype=float)
    acc = -omega ** 2 * force / (inertia[:, None] * (
        wn[:, None] ** 2 - omega ** 2 + 2j * block.damping_ratio * wn[:, None] * omega))
    x, y, z = point.position
    combine = {"vertical": (1.0, 0.0, y, -x), "transverse": (0.0, 1.0, -z, 0.0),
               "longitudinal": (0.0, 0.0, 0.0, z)}[point.direction]
    return Response(order, np.asarray(combine) @ acc, float(angular_speed))


@dataclass(frozen=True)
class Recording:
    """A record of several accelerometers and the ignition pickup (:func:`record`)."""

    volts: dict
    """Each channel's samples, by name. [V]"""
    tdc: np.ndarray
    """The ignition pickup: a 5 V pulse of 1 ms whose falling edge is cylinder 1's firing TDC.
    [V]"""
    sample_rate: float
    """[Hz]"""
    truth: dict = field(default_factory=dict)
    """Per channel, :meth:`Response.truth`. [SI]"""
    clipped: dict = field(default_factory=dict)
    """Per channel, the share of samples clipped. [1]"""


def record(engine: Engine, block: Block, points, sensor: Accelerometer, angular_speed: float,
           duration: float, *, seed: int = 0, names=None, **options) -> Recording:
    """Record the points at a steady speed.

    Parameters
    ----------
    engine, block : Engine, Block
    points : sequence of Point
    sensor : Accelerometer
    angular_speed : float
        ω. [rad/s]
    duration : float
        [s]
    seed : int
        Seeds the start angle and the noise.
    names : sequence of str, optional
        Channel names (default ``acc1``, ``acc2``, …).
    **options
        ``factors``, ``cut``, ``firing_order`` of :func:`excitation`.

    Returns
    -------
    Recording
    """
    rng = np.random.default_rng([seed, 4])
    rate = sensor.sample_rate
    t = np.arange(int(round(duration * rate))) / rate
    start = rng.uniform(0, 4 * np.pi)
    alpha = angular_speed * t + start
    names = names or [f"acc{j + 1}" for j in range(len(points))]
    volts, truth, clipped = {}, {}, {}
    for name, point in zip(names, points):
        resp = point_orders(engine, block, point, angular_speed, **options)
        keep = resp.frequency < 0.45 * rate
        gain = sensor.sensitivity * sensor.response(resp.frequency[keep]) * resp.coefficient[keep]
        phase = np.outer(alpha, resp.order[keep])
        clean = np.cos(phase) @ gain.real - np.sin(phase) @ gain.imag
        sigma = sensor.sensitivity * 10 ** (-sensor.snr_db / 20) * min(
            resp.band_rms(q) / white_noise_rms(rate, q) for q in QUANTITIES)
        signal = clean + sigma * rng.standard_normal(t.size)
        over = np.abs(signal) >= sensor.full_scale
        clipped[name] = float(over.mean())
        volts[name] = np.clip(signal, -sensor.full_scale, sensor.full_scale)
        truth[name] = resp.truth()
    cycle_angle = np.mod(alpha, 4 * np.pi)
    pulse = angular_speed * 1e-3
    tdc = np.where(cycle_angle > 4 * np.pi - pulse, 5.0, 0.0)
    return Recording(volts, tdc, rate, truth, clipped)
