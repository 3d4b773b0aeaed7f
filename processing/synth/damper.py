"""A rubber torsional damper on its test rig: static loops and a free decay, with the truth.

The scene behind lab 9. The damper's inertia ring sits on a rubber layer.

* Statically, a torque M applied in steps and taken off again twists the layer along two
  branches that enclose a lens-shaped loop (:class:`RubberLayer`): loading
  φ = M/C − h·M(M_max − M)/M_max², unloading φ = M/C + h·M(M_max − M)/M_max². The secant
  stiffness at M_max is C, the energy at full twist M_max²/(2C), and the loop's area
  h·M_max/3 (through n equal load steps, the polygon's (1 − 1/n²) of it), all in closed
  form. :func:`static_runs` reads the branches through a dial gauge (reading noise, rounded
  to its division), each run's twists scaled by a few per cent (the rubber's creep between
  runs).
* Dynamically, the ring twisted to φ₀ and released rings down (:class:`Ring`): I φ̈ + c φ̇ +
  C_d φ = 0 with a damping coefficient that may depend on the amplitude,
  δ(A) = δ₀ (A/φ₀)^p, integrated by :func:`scipy.integrate.solve_ivp`
  (:func:`free_decay`). With p = 0 the motion is exactly viscous: its decrement is δ₀, and
  the manual's C_d = I ω_d² [1 + (δ/2π)²] equals C_d identically. A strain-gauge channel
  (:class:`StrainGauge`) records it with an offset, a linear drift, the rubber's slow creep
  back towards rest, and white noise; :func:`peak_readings` gives the maxima a student reads
  off a paper record instead, and :func:`calibration` the record's readings at static
  twists.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 9, formulas 7–14 and tables 1–2.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..result import Record


@dataclass(frozen=True)
class RubberLayer:
    """The rubber layer's static M–φ loop.

    Parameters
    ----------
    stiffness : float
        C, the secant stiffness at the largest moment. [N·m/rad]
    loop_width : float
        h: the branches lie h·M(M_max − M)/M_max² either side of the chord M/C (widest,
        h/4 each side, at M_max/2). [rad]

    Defaults resemble the manual's damper 1 (Table 1: C ≈ 2.6·10⁴ N·m/rad, ξ′ ≈ 0.21).
    """

    stiffness: float = 2.6e4
    loop_width: float = 3.8e-3

    def branches(self, moment, moment_max):
        """Twist on the loading and on the unloading branch at ``moment``. [rad]"""
        m = np.asarray(moment, dtype=float)
        bulge = self.loop_width * m * (moment_max - m) / moment_max**2
        chord = m / self.stiffness
        return chord - bulge, chord + bulge

    def energies(self, moment_max, steps: int | None = None) -> dict:
        """The loop's exact energies: ``E_max`` = M_max²/(2C), ``E_loss`` and ``xi_static`` =
        their ratio. [J], [J], [1]

        ``E_loss`` is the continuous loop's area h M_max/3, or with ``steps`` that of the
        polygon through its points at ``steps`` equal load steps, (1 − 1/steps²) of it (the
        trapezoidal rule on the parabolic gap between the branches): what a table read at
        those loads encloses.
        """
        e_max = moment_max**2 / (2 * self.stiffness)
        e_loss = self.loop_width * moment_max / 3.0
        if steps is not None:
            e_loss *= 1.0 - 1.0 / steps**2
        return {"E_max": e_max, "E_loss": e_loss, "xi_static": e_loss / e_max}


def static_runs(layer: RubberLayer, moment_max: float = 315.0, steps: int = 7, runs: int = 2,
                *, directions=("forward",), gauge_division: float = 1e-5, scatter: float = 0.02,
                seed: int = 0) -> list[dict]:
    """Readings of repeated loading–unloading runs, as a student writes them.

    Parameters
    ----------
    layer : RubberLayer
    moment_max : float
        Largest moment. [N·m]
    steps : int
        Equal load steps up to it.
    runs : int
        Runs; directions cycle through ``directions``.
    directions : sequence of {"forward", "reverse"}
    gauge_division : float
        The dial gauge's division, as a twist: readings carry a normal error of half a
        division and are rounded to a division. [rad]
    scatter : float
        Relative standard deviation of a run's twists about the layer's (the rubber's creep
        and temperature between runs: the manual's two runs differ by 5 %); the layer's C is
        their mean.
    seed : int

    Returns
    -------
    list of dict
        Per run: ``direction``, ``M`` [N·m] and ``phi`` [rad] as magnitudes in reading
        order (loading from the first step to M_max, unloading down to 0, the top read once).
    """
    rng = np.random.default_rng([seed, 9])
    up = moment_max * np.arange(1, steps + 1) / steps
    down = up[-2::-1].tolist() + [0.0]
    load, _ = layer.branches(up, moment_max)
    _, unload = layer.branches(np.array(down), moment_max)
    true = np.concatenate([load, unload])
    out = []
    for k in range(runs):
        read = true * (1.0 + scatter * rng.standard_normal())
        read = read + rng.normal(0.0, 0.5 * gauge_division, true.size)
        read = np.maximum(np.round(read / gauge_division) * gauge_division, 0.0)
        out.append({"direction": directions[k % len(directions)],
                    "M": np.concatenate([up, down]), "phi": read})
    return out


@dataclass(frozen=True)
class Ring:
    """The damper's inertia ring on its rubber layer, for the free decay.

    Parameters
    ----------
    inertia : float
        I. [kg·m²]
    stiffness : float
        C_d, the layer's dynamic stiffness. [N·m/rad]
    decrement : float
        δ₀, the logarithmic decrement at the release amplitude. [1]
    amplitude_exponent : float
        p in δ(A) = δ₀ (A/φ₀)^p; 0 for damping independent of the amplitude (viscous).

    Defaults resemble the manual's damper 1 (Table 2: c_d = 4.85·10⁴ N·m/rad, δ = 0.89),
    with I chosen for about 200 Hz.
    """

    inertia: float = 0.03
    stiffness: float = 4.85e4
    decrement: float = 0.89
    amplitude_exponent: float = 0.0

    @property
    def omega_n(self) -> float:
        """Undamped angular frequency √(C_d/I). [rad/s]"""
        return math.sqrt(self.stiffness / self.inertia)

    def damping_ratio(self, decrement):
        """ζ = δ/√(4π² + δ²), the damping ratio of a viscous oscillator of decrement δ."""
        return decrement / np.sqrt(4 * np.pi**2 + decrement**2)

    def truth(self) -> dict:
        """The decay's true values at the release amplitude: ``log_decrement``, ``omega_d``,
        ``T_d``, ``xi_dynamic`` (I ω_d δ/π), ``C_dynamic``. [1, rad/s, s, N·m·s, N·m/rad]"""
        zeta = float(self.damping_ratio(self.decrement))
        omega_d = self.omega_n * math.sqrt(1 - zeta**2)
        return {"log_decrement": self.decrement, "omega_d": omega_d,
                "T_d": 2 * math.pi / omega_d,
                "xi_dynamic": self.inertia * omega_d * self.decrement / math.pi,
                "C_dynamic": self.stiffness}


@dataclass(frozen=True)
class StrainGauge:
    """The strain-gauge channel that records the ring's twist.

    Parameters
    ----------
    sample_rate : float
        [Hz]
    snr_db : float
        20 log₁₀(φ₀/(√2 σ)): the release amplitude's RMS over the noise σ. [dB]
    volts_per_rad : float
        Sensitivity. [V/rad]
    offset : float
        Bridge offset, as a fraction of the release amplitude.
    drift : float
        Linear drift per period, as a fraction of the release amplitude.
    creep : float
        The rubber's slow return: the twist still held at the release, as a fraction of φ₀,
        decaying as e^{−t/τ}.
    creep_periods : float
        τ in periods.
    """

    sample_rate: float = 20e3
    snr_db: float = 40.0
    volts_per_rad: float = 100.0
    offset: float = 0.05
    drift: float = 0.002
    creep: float = 0.03
    creep_periods: float = 10.0


DRIFT_KINDS = ("linear", "quadratic", "settling", "wander")
"""The shapes of :class:`BridgeDrift`."""


@dataclass(frozen=True)
class BridgeDrift:
    """A slow wander of the record's baseline beyond the gauge's own offset, drift and creep.

    What a strain-gauge bridge and its amplifier add over a decay when they are not settled:
    a bridge warming up drifts (``linear``; ``quadratic`` where the drift bends), the
    rubber's creep or the amplifier's coupling settles (``settling``: an exponential of time
    constant τ, which may be as short as the decay itself), the supply and the mounts wander
    (``wander``: three slow sines, 0.2–1.5 cycles over the record). A paper record draws
    it with the trace.

    Parameters
    ----------
    kind : {"linear", "quadratic", "settling", "wander"}
    size : float
        Its size, as a fraction of the release twist φ₀: the ramp's rise over the record, the
        parabola's largest excursion from its vertex, the settling step at the release, each
        wander sine's amplitude.
    time_constant : float
        τ of ``settling``, in periods of the decay.
    seed : int
        Seed of the shape's draws (the parabola's vertex, the sines' frequencies and phases).

    Examples
    --------
    >>> t = np.linspace(0.0, 0.04, 5)
    >>> BridgeDrift("linear", 0.1).shape(t, 0.005, 0.04).round(3).tolist()
    [0.0, 0.025, 0.05, 0.075, 0.1]
    """

    kind: str = "linear"
    size: float = 0.1
    time_constant: float = 2.0
    seed: int = 0

    def __post_init__(self):
        if self.kind not in DRIFT_KINDS:
            raise ValueError(f"BridgeDrift: kind must be one of {DRIFT_KINDS}, got {self.kind!r}")

    def shape(self, time, period: float, duration: float) -> np.ndarray:
        """The drift at ``time`` after the release, as a fraction of φ₀.

        Parameters
        ----------
        time : ndarray
            [s]
        period, duration : float
            The decay's period and the record's length after the release. [s]
        """
        t = np.asarray(time, dtype=float)
        rng = np.random.default_rng([self.seed, 95])
        if self.kind == "linear":
            return self.size * t / duration
        if self.kind == "quadratic":
            vertex = rng.uniform(0.0, 1.0)
            return self.size * ((t / duration - vertex) / max(vertex, 1 - vertex)) ** 2
        if self.kind == "settling":
            return self.size * np.exp(-t / (self.time_constant * period))
        cycles, phase = rng.uniform(0.2, 1.5, 3), rng.uniform(0, 2 * np.pi, 3)
        return self.size * np.sin(2 * np.pi * np.outer(t / duration, cycles) + phase).sum(axis=1)


@dataclass(frozen=True)
class DecayRecord(Record):
    """A recorded free decay and its truth.

    Attributes
    ----------
    time : ndarray
        Sample times; the release is at ``release``. [s]
    signal : ndarray
        The channel. [V]
    twist : ndarray
        The ring's true twist (no creep, no sensor). [rad]
    release : float
        [s]
    truth : dict
        :meth:`Ring.truth`.
    """

    time: np.ndarray
    signal: np.ndarray
    twist: np.ndarray
    release: float
    truth: dict


@functools.lru_cache(maxsize=64)
def _motion(ring: Ring, release_twist: float, duration: float, step: float):
    """Twist of the ring released at rest from ``release_twist``, on a grid of ``step``."""
    wn = ring.omega_n
    zeta0 = float(ring.damping_ratio(ring.decrement))
    p = ring.amplitude_exponent

    def rhs(_, y):
        phi, rate = y
        if p:
            amp = math.hypot(phi, rate / wn) / release_twist
            zeta = float(ring.damping_ratio(ring.decrement * max(amp, 1e-9) ** p))
        else:
            zeta = zeta0
        return [rate, -2 * zeta * wn * rate - wn * wn * phi]

    grid = np.arange(0.0, duration, step)
    sol = solve_ivp(rhs, (0.0, duration), [release_twist, 0.0], t_eval=grid, method="DOP853",
                    rtol=1e-10, atol=1e-14 * release_twist * wn)
    return grid, sol.y[0]


def free_decay(ring: Ring, gauge: StrainGauge, *, release_twist: float = 0.01,
               periods: float = 8.0, held: float = 0.5, seed: int = 0,
               drift: BridgeDrift | None = None) -> DecayRecord:
    """Record the ring's free decay after a sudden release.

    Parameters
    ----------
    ring : Ring
    gauge : StrainGauge
    release_twist : float
        φ₀, the twist held before the release. [rad]
    periods : float
        Record length after the release, in damped periods.
    held : float
        Record length before the release (the held twist), in periods.
    seed : int
        Seed of the noise.
    drift : BridgeDrift, optional
        A baseline wander on top of the gauge's (none by default).

    Returns
    -------
    DecayRecord
    """
    rng = np.random.default_rng([seed, 91])
    truth = ring.truth()
    T = truth["T_d"]
    dt = 1.0 / gauge.sample_rate
    _, phi = _motion(ring, float(release_twist), periods * T, dt)
    n_held = int(round(held * T / dt))
    twist = np.concatenate([np.full(n_held, release_twist), phi])
    time = np.arange(twist.size) * dt
    release = n_held * dt
    after = np.clip(time - release, 0.0, None)
    creep = gauge.creep * release_twist * np.exp(-after / (gauge.creep_periods * T))
    creep[:n_held] = gauge.creep * release_twist
    ramp = gauge.drift * release_twist * time / T
    if drift is not None:             # held at its release value before the release
        ramp = ramp + release_twist * drift.shape(after, T, periods * T)
    sigma = release_twist / math.sqrt(2) * 10 ** (-gauge.snr_db / 20)
    signal = gauge.volts_per_rad * (twist + creep + ramp + gauge.offset * release_twist
                                    + sigma * rng.standard_normal(twist.size))
    return DecayRecord(time, signal, twist, release, truth)


def peak_readings(record: DecayRecord, count: int, *, scale: float = 2e3,
                  resolution: float = 0.5, seed: int = 0) -> np.ndarray:
    """Successive maxima of the true twist as read off a paper record with a ruler.

    Parameters
    ----------
    record : DecayRecord
    count : int
        Maxima read, from the release on (the release's twist is the first).
    scale : float
        Trace deflection per radian. [mm/rad]
    resolution : float
        The ruler's division: readings carry a uniform error of half of it and are rounded
        to it. [mm]
    seed : int

    Returns
    -------
    ndarray
        ``count`` deflections. [mm]
    """
    rng = np.random.default_rng([seed, 92])
    after = record.time >= record.release
    phi = record.twist[after]
    inner = np.flatnonzero((phi[1:-1] > phi[:-2]) & (phi[1:-1] >= phi[2:])) + 1
    maxima = np.concatenate([[phi[0]], phi[inner]])[:count]
    read = scale * maxima + rng.uniform(-0.5 * resolution, 0.5 * resolution, maxima.size)
    return np.round(read / resolution) * resolution


def calibration(scale: float, twists=(0.0, 3e-3, 6e-3, 9e-3), *, noise: float = 0.002,
                seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A static calibration of the record: twists set on the rig and the record's readings.

    Parameters
    ----------
    scale : float
        The record's deflection per radian (V/rad of the strain gauges, mm/rad of a paper
        record). [unit/rad]
    twists : sequence of float
        Twists set, read on the dial gauge. [rad]
    noise : float
        Normal reading error, as a fraction of the largest reading.
    seed : int

    Returns
    -------
    twists, readings : ndarray
        [rad], [unit], readings as magnitudes from the no-load level (≥ 0).
    """
    rng = np.random.default_rng([seed, 94])
    phi = np.asarray(twists, dtype=float)
    readings = scale * phi + noise * scale * phi.max() * rng.standard_normal(phi.size)
    return phi, np.abs(readings)
