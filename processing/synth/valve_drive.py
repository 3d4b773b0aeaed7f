"""A running valve drive: a cam lifting a one-mass valve train through a lash, the force in
its rocker recorded by a strain gauge with time marks and TDC marks.

The scene, modelled just enough for the valve-drive oscillation lab:

* the cam's lift *at the valve* (the tappet's lift times the rocker ratio) against the cam
  angle: a constant-velocity opening ramp of height r over θ_r, a main event over θ_e with
  velocity continuous at its ends, and the mirrored closing ramp (:class:`Cam`);
* the valve train reduced to the valve (:class:`Drive`): a mass M on the drive's stiffness c
  (rocker, push rod, camshaft, as lab 5 measures them) and the springs' c_n with their
  preload P₀, the drive's damping b set by a damping ratio ζ of the drive's lowest mode,
  and a lash δ between the rocker and the valve;
* the compression of the drive s = h − x − δ (h the cam's lift, x the valve's) carries the
  force P = (c s + b ṡ)⁺ while s > 0 and none while the lash is open; the valve obeys
  M ẍ = P − P₀ − c_n x off its seat and sits (x = 0, inelastic) while P ≤ P₀;
* every cam revolution repeats the same event (the valve starts each from rest on its
  seat), at a constant speed; the trace is P/k plus the zero's offset and white noise.

The event is integrated with :func:`scipy.integrate.solve_ivp` (the force is a kink where
the lash opens, which its step control passes; the seat is an event). The lowest natural
frequency is :func:`processing.valvetrain.valve_train.natural_frequency`; its damped value is what a
record's free oscillations show.

Nothing here knows a measurement-file format: the lab's ``write_synthetic`` writes files.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import integrate, optimize

from ..result import Record
from processing.valvetrain.valve_train import natural_frequency

RPM = math.pi / 30
"""rad/s per min⁻¹."""


@dataclass(frozen=True)
class Cam(Record):
    """The cam's lift at the valve against the cam angle θ from the start of its ramp.

    Attributes
    ----------
    lift : float
        Lift of the main event's harmonic part, H. [m]
    ramp : float
        Height of each ramp, r. [m]
    ramp_angle : float
        Cam angle of each ramp, θ_r. [rad]
    event_angle : float
        Cam angle of the main event, θ_e. [rad]

    Notes
    -----
    With u = (θ − θ_r)/θ_e and the ramp's slope v_r = r/θ_r:

    .. math:: h = v_r θ \\;(θ < θ_r), \\qquad
              h = r + \\frac{H}{2}(1 - \\cos 2πu) + \\frac{v_r θ_e}{π} \\sin πu
              \\;(0 ≤ u ≤ 1)

    and the mirror image on the closing side: the velocity is continuous where the ramps
    meet the main event, the acceleration steps there, and the velocity jumps to v_r where
    the ramps start. A lash below r is taken up on the ramp; the default r lies below the
    manual's clearances, so each is taken up on the flank, harder the larger it is.
    """

    lift: float = 9e-3
    ramp: float = 0.25e-3
    ramp_angle: float = math.radians(20.0)
    event_angle: float = math.radians(110.0)

    @property
    def total_angle(self) -> float:
        """Cam angle from the start of the opening ramp to the end of the closing one. [rad]"""
        return 2 * self.ramp_angle + self.event_angle

    def profile(self, theta):
        """Lift, dh/dθ and d²h/dθ² at cam angles ``theta`` (0 outside the event).

        Returns
        -------
        tuple of ndarray
            [m], [m/rad], [m/rad²]

        Examples
        --------
        >>> cam = Cam()
        >>> h, v, a = cam.profile(np.array([0.0, cam.total_angle]))
        >>> np.allclose(h, 0.0), np.allclose(v, [cam.ramp / cam.ramp_angle, -v[0]])
        (True, True)
        """
        th = np.asarray(theta, dtype=float)
        tr, te, r, H = self.ramp_angle, self.event_angle, self.ramp, self.lift
        vr = r / tr
        u = (th - tr) / te
        w = np.pi * u
        main = (r + H / 2 * (1 - np.cos(2 * w)) + vr * te / np.pi * np.sin(w),
                H * np.pi / te * np.sin(2 * w) + vr * np.cos(w),
                2 * H * np.pi**2 / te**2 * np.cos(2 * w) - vr * np.pi / te * np.sin(w))
        back = self.total_angle - th
        opening, closing = (th >= 0) & (th < tr), (back >= 0) & (back < tr)
        inside = (u >= 0) & (u <= 1)
        h = np.where(inside, main[0], np.where(opening, vr * th, np.where(closing, vr * back,
                                                                           0.0)))
        v = np.where(inside, main[1], np.where(opening, vr, np.where(closing, -vr, 0.0)))
        a = np.where(inside, main[2], 0.0)
        return h, v, a


@dataclass(frozen=True)
class Drive(Record):
    """A valve train reduced to the valve (lab 5's c, c_n, M).

    Attributes
    ----------
    M : float
        Reduced oscillating mass. [kg]
    c : float
        Drive stiffness at the valve. [N/m]
    c_n : float
        Valve springs' stiffness. [N/m]
    P0 : float
        Springs' preload on the closed valve. [N]
    zeta : float
        Damping ratio of the drive's lowest mode (b = 2ζ√((c + c_n)M)). [1]
    """

    M: float = 0.25
    c: float = 2.0e6
    c_n: float = 30e3
    P0: float = 260.0
    zeta: float = 0.06

    @property
    def b(self) -> float:
        """Damping coefficient of the drive. [N·s/m]"""
        return 2 * self.zeta * math.sqrt((self.c + self.c_n) * self.M)

    @property
    def nu(self) -> float:
        """Undamped natural angular frequency √((c + c_n)/M). [rad/s]"""
        return float(natural_frequency(self.c, self.c_n, self.M))

    @property
    def damped_frequency(self) -> float:
        """The free oscillations' frequency ν√(1 − ζ²)/(2π). [Hz]"""
        return self.nu * math.sqrt(1 - self.zeta**2) / (2 * math.pi)


@dataclass(frozen=True)
class Event(Record):
    """One valve event at one speed: the force and the valve's lift on a fine grid, and what
    a perfect reading of them gives.

    Attributes
    ----------
    theta : ndarray
        Cam angle from the start of the opening ramp. [rad]
    force, lift : ndarray
        Force in the drive P and the valve's lift x there. [N], [m]
    opening, closing : float
        Cam angles where the force passes the preload rising first and falling last: where
        the valve leaves its seat, and lands on it (to within a re-lift of micrometres where
        the seat stops the valve while the drive still presses). [rad]
    contact : (float, float)
        Cam angles where the lash closes first and opens last (the force's stretch). [rad]
    P_max, P_min : float
        Largest force, and the least between the opening and the closing. [N]
    loss : float
        Cam angle over which the force is 0 between the opening and the closing. [rad]
    """

    theta: np.ndarray
    force: np.ndarray
    lift: np.ndarray
    opening: float
    closing: float
    contact: tuple
    P_max: float
    P_min: float
    loss: float

    def force_at(self, theta):
        """P at cam angles ``theta`` (0 outside the event). [N]"""
        return np.interp(theta, self.theta, self.force, left=0.0, right=0.0)


@functools.lru_cache(maxsize=128)
def simulate_event(cam: Cam, drive: Drive, lash: float, omega_cam: float, *,
                   per_period: int = 60) -> Event:
    """Integrate one valve event at the cam speed ``omega_cam`` through the lash ``lash``
    (the last events are kept: a sweep's records at the same speeds share them).

    Parameters
    ----------
    cam : Cam
    drive : Drive
    lash : float
        Clearance between the rocker and the valve. [m]
    omega_cam : float
        Camshaft speed. [rad/s]
    per_period : int
        Points of the output grid per period of the drive's oscillation.

    Returns
    -------
    Event
    """
    w, M, c, cn, P0, b = omega_cam, drive.M, drive.c, drive.c_n, drive.P0, drive.b
    end = cam.total_angle / w
    step = 2 * math.pi / drive.nu / per_period
    grid = np.arange(0.0, end + step, step)
    grid[-1] = min(grid[-1], end)

    def cam_at(t):
        h, v, a = cam.profile(w * np.asarray(t))
        return h, v * w

    def closed_force(t):
        h, hd = cam_at(t)
        s = h - lash
        return np.where(s > 0, np.maximum(c * s + b * hd, 0.0), 0.0)

    def rhs(t, y):
        h, hd = cam_at(t)
        s = h - lash - y[0]
        P = max(c * s + b * (hd - y[1]), 0.0) if s > 0 else 0.0
        return [y[1], (P - P0 - cn * y[0]) / M]

    def seat(t, y):
        return y[0] if t > t_lift + step else 1.0

    seat.terminal, seat.direction = True, -1
    x = np.zeros_like(grid)
    v = np.zeros_like(grid)
    lifts, lands = [], []
    t0 = 0.0
    while t0 < end:
        over = closed_force(grid) > P0
        over &= grid > t0
        if not over.any():
            break
        k = int(np.argmax(over))
        low = max(grid[k - 1], t0)
        t_lift = low if closed_force(low) > P0 else optimize.brentq(
            lambda t: float(closed_force(t)) - P0, low, grid[k], xtol=1e-12)
        sol = integrate.solve_ivp(rhs, (t_lift, end), [0.0, 0.0], events=seat, dense_output=True,
                                  rtol=1e-9, atol=1e-13, max_step=step)
        t_land = float(sol.t_events[0][0]) if sol.t_events[0].size else end
        part = (grid >= t_lift) & (grid <= t_land)
        x[part], v[part] = sol.sol(grid[part])
        lifts.append(t_lift)
        lands.append(t_land)
        t0 = t_land + step
    x = np.maximum(x, 0.0)
    h, hd = cam_at(grid)
    s = h - lash - x
    force = np.where(s > 0, np.maximum(c * s + b * (hd - v), 0.0), 0.0)
    theta = w * grid
    above = np.flatnonzero(force > P0)
    k = above[-1]
    closing = theta[k] + (force[k] - P0) / (force[k] - force[k + 1]) * (theta[k + 1] - theta[k])
    open_ = (grid >= lifts[0]) & (theta <= closing)
    loaded = np.flatnonzero(s > 0)
    d = theta[1] - theta[0]
    return Event(theta, force, x, w * lifts[0], float(closing),
                 (float(theta[loaded[0]]), float(theta[loaded[-1]])), float(force.max()),
                 float(force[open_].min()), float(np.count_nonzero(open_ & (force <= 0)) * d))


def separation_speed(cam: Cam, drive: Drive, lash: float, low: float, high: float, *,
                     xtol: float = 0.5 * RPM) -> float:
    """The engine speed at which P_min first reaches 0 (the drive separates), by bisection on
    the event's P_min between ``low`` and ``high`` (crankshaft speeds, rad/s); NaN if the
    drive keeps contact at ``high`` or has lost it at ``low``. [rad/s]"""
    def margin(n):
        return simulate_event(cam, drive, lash, n / 2).P_min - 1e-6

    if margin(high) > 0 or margin(low) <= 0:
        return math.nan
    return float(optimize.brentq(margin, low, high, xtol=xtol))


@dataclass(frozen=True)
class Gauge(Record):
    """The strain-gauge channel and the recorder.

    Attributes
    ----------
    scale : float
        Force per unit of the trace, k. [N per trace unit]
    offset : float
        The trace's zero (no force). [trace unit]
    noise : float
        Standard deviation of the trace's white noise. [trace unit]
    sample_rate : float
        [Hz]
    mark_period : float
        Period of the time marks. [s]
    """

    scale: float = 1500 / 90
    offset: float = 4.0
    noise: float = 0.2
    sample_rate: float = 10e3
    mark_period: float = 2e-3


@dataclass(frozen=True)
class Timing(Record):
    """Where each valve's cam event starts, in crank angle from the overlap TDC. [rad]"""

    inlet: float = math.radians(-62.0)
    exhaust: float = math.radians(-238.0)


@dataclass
class Recording:
    """A synthetic record: channels and the true values of what it holds.

    ``channels`` maps a channel's name (``"in"``, ``"ex"``, ``"tdc"``, ``"marks"``) to its
    samples; ``truth`` maps a valve to its :class:`Event` and its timing in crank angle
    (``advance``: the opening before its dead centre, ``lag``: the closing after it).
    """

    time: np.ndarray
    channels: dict
    speed: float
    events: dict = field(default_factory=dict)
    timing: dict = field(default_factory=dict)


def _pulses(phase, width: float, rise: float) -> np.ndarray:
    """Pulses 0 → 1 → 0 whose falling edge is centred on each integer of ``phase``, high for
    ``width`` before it, both edges ``rise`` long (in units of ``phase``)."""
    before = np.mod(-np.asarray(phase) + 0.5, 1.0) - 0.5       # to the nearest integer
    return np.minimum(np.clip(before / rise + 0.5, 0, 1),
                      np.clip((width - before) / rise + 0.5, 0, 1))


def record(cam: Cam, drive: Drive, gauge: Gauge, lash: float, n: float, *,
           valves=("in", "ex"), revolutions: float = 4.4, timing: Timing = Timing(),
           seed: int = 0, events: dict | None = None) -> Recording:
    """A record at crankshaft speed ``n`` [rad/s]: the valves' traces, TDC marks (every
    revolution; a pulse whose falling edge is the mark) and time marks (likewise), starting at a random crank angle, ``revolutions`` long.

    ``events`` may hold the valves' :class:`Event` at this speed and lash (computed if not).
    """
    rng = np.random.default_rng(seed)
    samples = int(round(revolutions * 2 * math.pi / n * gauge.sample_rate))
    t = np.arange(samples) / gauge.sample_rate
    crank = rng.uniform(0, 4 * math.pi) + n * t                 # from an overlap TDC
    start = {"in": timing.inlet, "ex": timing.exhaust}
    channels, out_events, out_timing = {}, {}, {}
    period = 4 * math.pi
    for valve in valves:
        ev = (events or {}).get(valve) or simulate_event(cam, drive, lash, n / 2)
        cam_angle = np.mod(crank - start[valve], period) / 2
        P = ev.force_at(cam_angle)
        channels[valve] = (P / gauge.scale + gauge.offset
                           + gauge.noise * rng.standard_normal(samples))
        out_events[valve] = ev
        opens, closes = start[valve] + 2 * ev.opening, start[valve] + 2 * ev.closing
        if valve == "in":       # opens before the overlap TDC, closes after the next BDC
            out_timing[valve] = {"advance": -opens, "lag": closes - math.pi}
        else:                   # opens before the BDC ahead of the overlap TDC
            out_timing[valve] = {"advance": -math.pi - opens, "lag": closes}
    per_sample = n / (2 * math.pi * gauge.sample_rate)         # revolutions a sample
    channels["tdc"] = _pulses(crank / (2 * math.pi), 0.01, 2 * per_sample)
    channels["marks"] = _pulses(t / gauge.mark_period, 0.25,
                                2 / (gauge.mark_period * gauge.sample_rate))
    return Recording(t, channels, n, out_events, out_timing)


def calibration(gauge: Gauge, loads, *, reading: float = 0.2, bend: float = 0.0,
                seed: int = 0) -> np.ndarray:
    """The trace's deflections [trace unit] read at the static ``loads`` [N]: P/k, a bend
    (``bend`` times the top deflection at the top, parabolic) and reading errors within
    ± ``reading`` (none at no load: the trace's zero is set there)."""
    rng = np.random.default_rng([seed, 61])
    loads = np.asarray(loads, dtype=float)
    a = loads / gauge.scale
    top = a.max() or 1.0
    a = a + bend * top * (a / top) ** 2
    a = a + np.where(loads > 0, rng.uniform(-reading, reading, a.size), 0.0)
    return np.round(a, 1)

