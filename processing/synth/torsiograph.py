"""A crankshaft in torsional vibration, seen by a seismic torsiograph on its nose (lab 7).

The scene behind the torsiograph lab, modelled just enough: a four-cylinder four-stroke
diesel's crankshaft as an equivalent chain of discs (:mod:`processing.torsional.chain`: the damper
hub on the nose, four cranks, the flywheel) with viscous damping, driven at each crank by its
cylinder's torque — gas and reciprocating inertia (:mod:`processing.crank.dynamics`), expanded in
half orders and shifted by the firing phases — at a steady speed. The nose's steady forced
motion is the sum of the orders' responses (rigid-body speed fluctuation and elastic twist
together). The torsiograph sees it through its own transfer function
(:func:`~processing.torsional.seismic.torsiograph_response`); the recorder adds a slow baseline
drift and white noise; a TDC mark once per revolution and time marks run beside it.

The truths come with the scene: per speed, the nose's orders and its largest peak amplitude (by the
same definition the lab uses, :func:`~processing.torsional.torsiogram.peak_amplitudes`); over the
speed range, every resonance (the peak of an order's amplitude at the nose where that order
dominates) with its speed and order; the chain's natural frequencies.

References
----------
- dynlab FORMULAS.md, "Lab 7"; lab manual (Vladimir State University, 2003), lab 7.
- W. Ker Wilson, Practical Solution of Torsional Vibration Problems, vol. 1 and 2 (the
  equivalent system, harmonic torques, damping).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import find_peaks, peak_prominences

from processing.crank.dynamics import (crank_train_forces, firing_phases, gas_force,
                                       indicator_pressure, reciprocating_inertia_force)
from processing.torsional.resonance import PROMINENCE, locate_resonances
from ..result import Record
from processing.torsional.seismic import torsiograph_response
from processing.torsional.chain import forced_response, natural_modes
from processing.torsional.torsiogram import (EXTREMUM_THRESHOLD, oscillation_frequency,
                                             peak_amplitudes)

RPM = np.pi / 30
"""One min⁻¹ in rad/s."""

CLEAR = 1.5
"""A resonance is clear when its order's amplitude is at least this many times every other
order's at the peak: a lab must find it. Between 1/CLEAR and CLEAR it may or may not."""


@dataclass(frozen=True)
class Crankshaft:
    """A tractor diesel's crankshaft (D-240 class: four cylinders, 110 × 125 mm) as a chain.

    The defaults give a first mode at 200 Hz (damping ratio 0.036) and clear resonances of
    orders 8 (1500 min⁻¹) and 6 (2000 min⁻¹) in the speed range 800–2100 min⁻¹.
    """

    cylinders: int = 4
    strokes: int = 4
    firing_order: tuple = (1, 3, 4, 2)
    bore: float = 0.110
    """D. [m]"""
    crank_radius: float = 0.0625
    """R. [m]"""
    lambda_: float = 0.27
    compression_ratio: float = 16.0
    pre_expansion_ratio: float = 1.4
    p_a: float = 0.09e6
    """[Pa]"""
    p_z: float = 8.0e6
    """Maximum cycle pressure at full load. [Pa]"""
    n1: float = 1.36
    n2: float = 1.25
    p_r: float = 0.11e6
    """[Pa]"""
    reciprocating_mass: float = 2.0
    """m_j per cylinder. [kg]"""
    combustion_spread: float = np.radians(6.0)
    """Combustion is not the diagram's instantaneous jump: the gas torque's harmonics are
    rounded off by a Gaussian of this width in crank angle (order k × exp(−(kσ)²/2)). [rad]"""
    inertia: tuple = (0.05, 0.035, 0.035, 0.035, 0.035, 1.3)
    """J of the discs from the nose: damper hub, cranks 1–4, flywheel. [kg·m²]"""
    stiffness: tuple = (0.52e6, 0.78e6, 0.78e6, 0.78e6, 0.61e6)
    """c of the shafts between them. [N·m/rad]"""
    damping: tuple = (8.0, 1.5, 1.5, 1.5, 1.5, 0.0)
    """Viscous damping of each disc (the damper, piston friction). [N·m·s/rad]"""
    first_crank: int = 1
    """Disc (0-based) of crank 1; cranks follow in cylinder order."""
    max_order: float = 24.0
    """Highest order modelled."""

    @property
    def orders(self) -> np.ndarray:
        step = 0.5 if self.strokes == 4 else 1.0
        return step * np.arange(1, int(self.max_order / step) + 1)

    def natural_frequencies(self) -> np.ndarray:
        """The chain's undamped natural frequencies. [Hz]"""
        return natural_modes(self.inertia, self.stiffness).frequency


LOADS = {"idle": 0.1, "part": 0.5, "full": 1.0}
"""Share of the full-load combustion torque (above the motored one) at each named load."""


@functools.cache
def _cylinder_harmonics(shaft: Crankshaft, points: int = 2880):
    """One cylinder's torque harmonics: (orders, motored gas, combustion part, inertia at
    ω = 1 rad/s), complex, M(α) = Re Σ C_k e^{ikα}. [N·m]"""
    period = 4 * np.pi if shaft.strokes == 4 else 2 * np.pi
    alpha = np.arange(points) * period / points
    area = np.pi * shaft.bore ** 2 / 4
    diagram = dict(p_a=shaft.p_a, compression_ratio=shaft.compression_ratio, n1=shaft.n1,
                   lambda_=shaft.lambda_, strokes=shaft.strokes,
                   p_r=shaft.p_r if shaft.strokes == 4 else None)
    p_c = shaft.p_a * shaft.compression_ratio ** shaft.n1

    def torque(force):
        return crank_train_forces(alpha, force, shaft.crank_radius, shaft.lambda_).torque

    motored = torque(gas_force(indicator_pressure(alpha, p_z=p_c, n2=shaft.n1, **diagram),
                               area))
    fired = torque(gas_force(indicator_pressure(alpha, p_z=shaft.p_z, n2=shaft.n2,
                                                pre_expansion_ratio=shaft.pre_expansion_ratio,
                                                **diagram), area))
    inertia = torque(reciprocating_inertia_force(alpha, shaft.reciprocating_mass,
                                                 shaft.crank_radius, 1.0, shaft.lambda_))
    revs = period / (2 * np.pi)
    index = np.rint(shaft.orders * revs).astype(int)

    def harmonics(x):
        return (2 * np.fft.rfft(x) / points)[index]

    rounding = np.exp(-0.5 * (shaft.orders * shaft.combustion_spread) ** 2)
    return (shaft.orders, harmonics(motored) * rounding,
            harmonics(fired - motored) * rounding, harmonics(inertia))


@dataclass(frozen=True)
class NoseMotion(Record):
    """The nose's steady motion at one speed and load (:func:`nose_motion`)."""

    angular_speed: float
    """ω. [rad/s]"""
    load: float
    """Share of full load."""
    order: np.ndarray
    """Orders k. [1]"""
    coefficient: np.ndarray
    """Complex amplitude of each order: θ(t) = Re Σ c_k e^{ikωt}, t = 0 at the TDC of
    cylinder 1 (start of its intake stroke). [rad]"""

    @property
    def amplitude(self) -> np.ndarray:
        return np.abs(self.coefficient)

    def angle(self, t) -> np.ndarray:
        """θ(t). [rad]"""
        t = np.asarray(t, dtype=float)
        return (self.coefficient * np.exp(1j * self.order * self.angular_speed
                                          * t[..., None])).real.sum(axis=-1)

    def peak_amplitude(self, points_per_revolution: int = 2048) -> float:
        """The largest peak amplitude of the motion (:func:`peak_amplitudes` over three
        working cycles, hysteresis :data:`EXTREMUM_THRESHOLD` of its range): the truth the lab's
        A_max is judged against. [rad]"""
        revs = 3 * (2 if self.order[0] == 0.5 else 1)
        t = np.arange(revs * points_per_revolution) * 2 * np.pi / (
            self.angular_speed * points_per_revolution)
        theta = self.angle(t)
        return peak_amplitudes(t, theta, EXTREMUM_THRESHOLD * np.ptp(theta)).largest


def nose_motion(shaft: Crankshaft, angular_speed: float, load: float = 1.0) -> NoseMotion:
    """Steady forced motion of the nose (disc 0) at a speed and load.

    Parameters
    ----------
    shaft : Crankshaft
    angular_speed : float
        ω. [rad/s]
    load : float
        Share of the full-load combustion torque (:data:`LOADS`).

    Returns
    -------
    NoseMotion

    Notes
    -----
    Cylinder c's torque M_c(α) = M_1(α − φ_c) acts on its crank; each order k is solved
    separately, :math:`(K - (k\\omega)^2 M + ik\\omega C)\\Theta_k = T_k`,
    :math:`T_{k,c} = C_k e^{-ik\\varphi_c}`, C_k = motored + load · combustion + ω² ·
    inertia harmonic of one cylinder.
    """
    orders, theta = nose_coefficients(shaft, angular_speed, load)
    return NoseMotion(float(angular_speed), float(load), orders, theta)


def nose_coefficients(shaft: Crankshaft, angular_speed, load: float = 1.0):
    """The nose's complex order amplitudes at one speed or many (:func:`nose_motion`'s
    ``coefficient``, batched). Returns ``(orders, coefficients)``, the latter shaped
    ``np.shape(angular_speed) + orders.shape``. [1], [rad]"""
    orders, motored, combustion, inertia = _cylinder_harmonics(shaft)
    phases = firing_phases(shaft.cylinders, strokes=shaft.strokes,
                           firing_order=list(shaft.firing_order))
    w = np.asarray(angular_speed, dtype=float)[..., None]
    per_cylinder = motored + load * combustion + w ** 2 * inertia
    n = len(shaft.inertia)
    torque = np.zeros(per_cylinder.shape + (n,), dtype=complex)
    cranks = shaft.first_crank + np.arange(shaft.cylinders)
    torque[..., cranks] = per_cylinder[..., None] * np.exp(-1j * orders[:, None] * phases)
    theta = forced_response(shaft.inertia, shaft.stiffness, torque, orders * w,
                            damping=shaft.damping)
    return orders, theta[..., 0]


@dataclass(frozen=True)
class TrueResonance(Record):
    """A resonance of the scene: an order's amplitude at the nose peaks where it dominates."""

    order: float
    speed: float
    """n_res, the peak of the order's nose amplitude. [rad/s]"""
    amplitude: float
    """That order's amplitude there. [rad]"""
    dominance: float
    """Its amplitude over the largest other order's there."""

    @property
    def clear(self) -> bool:
        return self.dominance >= CLEAR


def resonances(shaft: Crankshaft, low: float, high: float, *, load: float = 1.0,
               step: float = 2 * RPM) -> list[TrueResonance]:
    """Every resonance of the scene between two speeds (dominance ≥ 1/:data:`CLEAR`).

    The orders' nose amplitudes on a grid of ``step``; peaks standing
    :data:`~processing.torsional.resonance.PROMINENCE` of their height above their lower flank,
    refined by a parabola through 1/A² of the three grid points around them.

    Parameters
    ----------
    shaft : Crankshaft
    low, high : float
        Speed range. [rad/s]
    load : float, keyword-only
    step : float, keyword-only
        Grid step. [rad/s]

    Returns
    -------
    list of TrueResonance
        By speed.
    """
    speeds = np.arange(low, high + step / 2, step)
    orders, coefficients = nose_coefficients(shaft, speeds, load)
    amp = np.abs(coefficients)
    out = []
    for j, k in enumerate(orders):
        y = amp[:, j]
        peaks, _ = find_peaks(y)
        if peaks.size == 0:
            continue
        prom = peak_prominences(y, peaks)[0]
        for p, pr in zip(peaks, prom):
            if pr < PROMINENCE * y[p]:
                continue
            z = 1 / y[p - 1:p + 2] ** 2
            shift = 0.5 * (z[0] - z[2]) / (z[0] - 2 * z[1] + z[2])
            w = speeds[p] + shift * step
            motion = nose_motion(shaft, w, load)
            a = motion.amplitude
            others = np.delete(a, j).max()
            if a[j] >= others / CLEAR:
                out.append(TrueResonance(float(k), float(w), float(a[j]), float(a[j] / others)))
    return sorted(out, key=lambda r: r.speed)


def sweep(shaft: Crankshaft, low: float, high: float, *, step: float = 200 * RPM,
          fine: float = 50 * RPM, load: float = 1.0, found=None) -> np.ndarray:
    """Record speeds as the manual has them taken: every ``step`` from ``low`` to ``high``,
    and every ``fine`` within ± 2·``fine`` of each clear resonance (``found``: the scene's
    :func:`resonances`, if already known). [rad/s]"""
    base = np.arange(low, high + step / 2, step)
    found = resonances(shaft, low, high, load=load) if found is None else found
    extra = [np.round(r.speed / fine) * fine + fine * np.arange(-2, 3)
             for r in found if r.clear]
    speeds = np.concatenate([base, *extra]) if extra else base
    speeds = speeds[(speeds >= low - 1e-9) & (speeds <= high + 1e-9)]
    return np.unique(np.round(speeds / RPM, 6)) * RPM


def sweep_resonances(shaft: Crankshaft, speeds, *, load: float = 1.0,
                     prominence: float = PROMINENCE):
    """What the lab's search (:func:`processing.torsional.resonance.locate_resonances`) finds in a
    sweep of noise-free records: the nose's true order amplitudes at ``speeds`` [rad/s], each
    record's dominant order their largest. Returns ``(resonances, edges)`` as that function
    does: whether a sweep resolves the scene's resonances, and whether an order still rises
    at its ends."""
    orders, coefficients = nose_coefficients(shaft, speeds, load)
    amp = np.abs(coefficients)
    return locate_resonances(speeds, amp, orders, orders[np.argmax(amp, axis=1)],
                             prominence=prominence)


@dataclass(frozen=True)
class Torsiograph:
    """The instrument and its recorder."""

    natural_frequency: float = 3.0
    """f_c of the seismic mass on its spring. [Hz]"""
    damping_ratio: float = 0.2
    """ζ. [1]"""
    scale: float = 0.004
    """l, the trace scale: rad per volt of the recorder. [rad/V]"""
    sample_rate: float = 4000.0
    """[Hz]"""
    snr_db: float = 35.0
    """RMS of the recorded oscillation over the noise's σ (the gain is set for each record,
    as the manual asks: the largest trace the recorder takes). [dB]"""
    drift: float = 1.0
    """Excursion of the baseline drift over the record, in units of the record's true largest
    peak amplitude. [1]"""
    drift_frequency: float = 0.5
    """Upper bound of the frequency of the drift's slow wave (a ramp plus one wave of
    0.1…drift_frequency Hz: the thermal wander of a strain-gauge bridge, the slip rings'
    contact). [Hz]"""
    revolutions: int = 16
    """Length of each record. [revolutions]"""
    mark_period: float = 0.01
    """Period of the time marks. [s]"""
    mark_width: float = 1.5e-3
    """Width of a mark pulse (TDC or time). [s]"""


@dataclass(frozen=True)
class TorsiographRecord(Record):
    """One synthetic record and its truth (:func:`record`)."""

    time: np.ndarray
    """[s]"""
    trace: np.ndarray
    """The recorder's trace. [V]"""
    tdc: np.ndarray
    """TDC mark channel (pulses 0 → 1 at each TDC of cylinder 1). [1]"""
    timer: np.ndarray
    """Time-mark channel, pulses every mark period. [1]"""
    motion: NoseMotion
    """The true nose motion."""
    peak_amplitude: float
    """True largest peak amplitude of the nose. [rad]"""
    tdc_times: np.ndarray
    """True times of the TDC marks' starts. [s]"""
    start: float = 0.0
    """Time of the record's first sample on the motion's clock (0 at a TDC of cylinder 1,
    the start of its intake stroke). [s]"""
    settings: dict = field(default_factory=dict)

    def frequency(self, threshold: float = EXTREMUM_THRESHOLD) -> float:
        """The true motion's oscillation frequency over the record's span, by counting its
        extrema as the lab does (hysteresis ``threshold`` of its range). [Hz]"""
        t = self.time[0] + np.arange(8 * self.time.size) * (self.time[1] - self.time[0]) / 8
        theta = self.motion.angle(t + self.start)
        peaks = peak_amplitudes(t, theta, threshold * np.ptp(theta))
        return oscillation_frequency(peaks.position)[0]

    def truth(self) -> dict:
        """The record's results as lab 7 names them (without the record's number): ``n``
        [rad/s], ``phi_max`` [rad] and, where counting the oscillations is well defined (the
        same ν with a quarter less or more hysteresis, within 0.5 %), ``nu`` [Hz] and ``K``."""
        w = self.motion.angular_speed
        out = {"n": w, "phi_max": self.peak_amplitude}
        nu = [self.frequency(EXTREMUM_THRESHOLD * f) for f in (0.75, 1.0, 1.25)]
        if max(nu) / min(nu) - 1 < 0.005:
            out.update(nu=nu[1], K=2 * np.pi * nu[1] / w)
        return out


def _pulses(t, starts, width, rise):
    """Trapezoid pulses 0 → 1 from each start for ``width``, edges ``rise`` long."""
    d = t[:, None] - np.asarray(starts)[None, :]
    up = np.clip(d / rise, 0, 1)
    down = np.clip((width - d) / rise, 0, 1)
    return np.minimum(up, down).max(axis=1) if len(starts) else np.zeros(t.size)


def record(shaft: Crankshaft, instrument: Torsiograph, angular_speed: float, *,
           load: float = 1.0, seed: int = 0) -> TorsiographRecord:
    """A torsiograph record of a steady regime.

    Parameters
    ----------
    shaft : Crankshaft
    instrument : Torsiograph
    angular_speed : float
        ω. [rad/s]
    load : float, keyword-only
    seed : int, keyword-only
        Seed of the start phase, the drift and the noise.

    Returns
    -------
    TorsiographRecord

    Notes
    -----
    trace(t) = Re Σ_k H(kω/2π) c_k e^{ikω(t + t₀)}/l + d(t) + e(t): H the torsiograph's
    response, l its scale, d a drift (a ramp and a slow wave, excursion ``drift`` × the true
    largest peak amplitude), e white noise at ``snr_db`` below the oscillation's RMS.
    """
    rng = np.random.default_rng([seed, 7])
    motion = nose_motion(shaft, angular_speed, load)
    f_rev = angular_speed / (2 * np.pi)
    duration = instrument.revolutions / f_rev
    fs = instrument.sample_rate
    t = np.arange(int(duration * fs)) / fs
    t0 = rng.uniform(0, 2 / f_rev)
    h = torsiograph_response(motion.order * f_rev, instrument.natural_frequency,
                             instrument.damping_ratio)
    seen = (motion.coefficient * h * np.exp(1j * motion.order * angular_speed * t0))
    oscillation = (seen * np.exp(1j * motion.order * angular_speed * t[:, None])).real.sum(1)
    oscillation /= instrument.scale
    true_peak = motion.peak_amplitude()
    ramp = rng.uniform(-1, 1)
    wave_frequency = rng.uniform(0.1, max(instrument.drift_frequency, 0.1))
    wave = np.sin(2 * np.pi * wave_frequency * t + rng.uniform(0, 2 * np.pi))
    shape = ramp * (t / duration - 0.5) + (1 - abs(ramp)) * wave
    drift = instrument.drift * true_peak / instrument.scale * shape / max(np.ptp(shape), 1e-12)
    sigma = np.sqrt(np.mean(oscillation ** 2)) / 10 ** (instrument.snr_db / 20)
    trace = oscillation + drift + sigma * rng.standard_normal(t.size)
    cycle_rev = 2 * np.pi / angular_speed
    first = (-t0) % cycle_rev
    tdc_times = np.arange(first, t[-1], cycle_rev)
    rise = 2 / fs
    tdc = _pulses(t, tdc_times, instrument.mark_width, rise)
    marks = np.arange(rng.uniform(0, instrument.mark_period), t[-1], instrument.mark_period)
    timer = _pulses(t, marks, instrument.mark_width, rise)
    settings = {"speed_rpm": float(angular_speed / RPM), "load": float(load), "seed": seed,
                "snr_db": instrument.snr_db, "drift": instrument.drift,
                "drift_frequency": instrument.drift_frequency,
                "sample_rate": fs, "revolutions": instrument.revolutions}
    return TorsiographRecord(time=t, trace=trace, tdc=tdc, timer=timer, motion=motion,
                             peak_amplitude=float(true_peak), tdc_times=tdc_times,
                             start=float(t0), settings=settings)


def calibration(instrument: Torsiograph, lever: float, heights, *, reading: float = 0.005,
                offset: float = 0.02, seed: int = 0) -> np.ndarray:
    """Trace deflections of a static calibration: the case turned by φ = h/R against the
    locked mass. Deflection = offset + φ/l, read to ± ``reading``.

    Parameters
    ----------
    instrument : Torsiograph
    lever : float
        R, the lever's radius. [m]
    heights : array_like
        h, the micrometer's rises. [m]
    reading, offset : float, keyword-only
        Reading error (σ, normal) and zero offset of the deflection. [V]
    seed : int, keyword-only

    Returns
    -------
    ndarray
        Deflections. [V]
    """
    rng = np.random.default_rng([seed, 11])
    phi = np.asarray(heights, dtype=float) / lever
    return offset + phi / instrument.scale + reading * rng.standard_normal(phi.size)


def ringing_record(seed: int, rpm: float, revolutions: int, *, cylinders: int = 6,
                   natural: float = 73.0, sample_rate: float = 4000.0, snr_db: float = 30.0,
                   natural_frequency: float = 1.5, damping_ratio: float = 0.2):
    """A record no order fit describes: a few orders of the crank (the major ones, multiples
    of i/2, five times the others) and a free vibration of the shaft at ``natural`` Hz
    (damping ratio 0.05) rung anew, with a random strength, at every firing — locked to no
    order, as a crankshaft rings between the firings near a resonance — seen through a
    torsiograph of ``natural_frequency`` and ``damping_ratio``, on a ramp and a slow wave
    as large as the motion's range, with white noise at ``snr_db``.

    Returns
    -------
    tuple
        (time [s], trace [rad], TDC mark times [s], the motion's largest peak amplitude with
        the lab's hysteresis [rad])
    """
    rng = np.random.default_rng([seed, 28])
    f_rev = rpm / 60
    t = np.arange(int(revolutions / f_rev * sample_rate)) / sample_rate
    orders = np.arange(0.5, 12.01, 0.5)
    amp = 0.2 * rng.uniform(0, 1, orders.size) / orders
    amp[np.isclose(orders % (cylinders / 2), 0)] *= 5
    motion = (amp[:, None] * np.cos(2 * np.pi * orders[:, None] * f_rev * t
                                     + rng.uniform(0, 2 * np.pi, orders.size)[:, None])).sum(0)
    interval = 2 / (f_rev * cylinders)
    for start in np.arange(rng.uniform(0, interval), t[-1], interval):
        d = t - start
        ring = np.exp(-2 * np.pi * natural * 0.05 * d) * np.sin(2 * np.pi * natural * d)
        motion += np.where(d >= 0, rng.uniform(0.5, 1.0) * ring, 0.0)
    truth = peak_amplitudes(t, motion, EXTREMUM_THRESHOLD * np.ptp(motion)).largest
    spectrum = np.fft.rfft(motion)
    f = np.fft.rfftfreq(t.size, 1 / sample_rate)
    response = np.concatenate([[1], torsiograph_response(f[1:], natural_frequency,
                                                         damping_ratio)])
    seen = np.fft.irfft(spectrum * response, t.size)
    drift = np.ptp(motion) * (rng.uniform(-1, 1) * t / t[-1]
                              + 0.5 * np.sin(2 * np.pi * 0.3 * t + rng.uniform(0, 6)))
    noise = np.std(seen) / 10 ** (snr_db / 20) * rng.standard_normal(t.size)
    marks = np.arange(rng.uniform(0, 1 / f_rev), t[-1], 1 / f_rev)
    return t, seen + drift + noise, marks, float(truth)

