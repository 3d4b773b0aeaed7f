"""Forces in a running valve drive, read off a strain-gauge trace of its rocker.

A rocker's strain gauge reads zero while the lash is open (the valve on its seat, the drive
unloaded), then the force rises as the cam takes the lash up; the valve leaves its seat once
the force overcomes the springs' preload P₀ and lands when it falls back through it. While
the valve is open the force carries the drive's free oscillations (the mass reduced to the
valve on the drive's and the springs' stiffness), excited where the lash closes; where the
cam's deceleration and those oscillations unload the drive completely the force stays at
zero: the drive has separated (the kinematic chain is broken).

From one trace, in its own unit (mm of an oscillogram, V of a recorder), with no knowledge
of the cam:

* :func:`trace_zero`: the trace's zero (the level of the unloaded stretches) and its noise;
* :func:`valve_events`: each whole event on the record: where the valve leaves and reaches
  its seat (the force passing the preload, interpolated between samples), the largest force
  and the least while the valve is open (a five-sample Savitzky–Golay smoothing, whose noise
  gain gives their u, and the vertex between samples), and the time without force while
  open;
* :func:`free_oscillation`: the frequency of the drive's oscillation, by a damped sinusoid on
  a polynomial baseline the data choose (:func:`processing.oscillations.decay.fit_baselines`) fitted
  from the largest swing after the opening over at most :data:`FIT_PERIODS` periods, before any loss
  of contact.

Times in s, forces in the trace's unit above its zero (the calibration scales them). A trace
clipped by its recorder (:func:`processing.inputs.record_quality.clipped_mask`) is read around the
clipped samples: an extreme that sits on them is flagged (it is cut off, not measured), and
the free oscillation's fit leaves them out.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 6 ("Исследование колебаний клапанного механизма двигателя").
.. [2] A. Savitzky, M. J. E. Golay, Smoothing and differentiation of data by simplified least
       squares procedures, Anal. Chem. 36 (1964) 1627–1639.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from processing.oscillations.decay import BaselineChoice, DampedSineFit, fit_baselines_each
from processing.oscillations.savgol import coefficients, savgol
from processing.result import Record
from processing.inputs.reuse import by_content, by_content_each

ZERO_BAND = 5.0
"""Half-width of the zero's band, in noise standard deviations: samples within it of the
trace's lower quartile are taken as unloaded."""

CONTACT_LEVEL = 5.0
"""The drive counts as loaded where the smoothed force exceeds this many of the smoothed
noise's standard deviations (a false contact from the noise alone: below 10⁻⁶ a sample)."""

LOSS_LEVEL = 3.0
"""Inside an opening, the drive counts as unloaded (contact lost) where the smoothed force
stays below this many of the smoothed noise's standard deviations."""

SMOOTH_WINDOW = 5
"""Samples of the quadratic Savitzky–Golay smoothing of the force: at ten or more samples a
period of the drive's oscillation (the manual asks for a recorder 5–10 times faster than the
drive) it lowers a crest by at most 1.3 % of the swing (0.06 % at 20 samples a period) and
the noise's σ to 0.70 of it."""

FIT_PERIODS = 5.0
"""Most oscillation periods a free-oscillation fit spans (with ζ ≈ 0.05–0.1 the swing has
fallen to a tenth by then)."""

MIN_PERIODS = 2.0
"""Fewest periods a free-oscillation stretch needs for a frequency."""

EVENT_DEGREE = 8
"""Degree of the polynomial taken for the cam's slow hump when the period is sought."""

EVENT_CYCLES = 5.0
"""Fewest oscillations per event sought: a drive's lowest mode (300–1000 Hz) rings 6–60 times
over an opening of 20–100 ms."""

NU_POOR = 0.01
"""Relative standard uncertainty of a free oscillation's frequency above which its fit is
poor: too few periods, or too weak a swing over the noise."""

FREQUENCY_SLACK = 0.2
"""A fitted frequency more than this share off the spectrum's peak is a failed fit."""

GAP_SHARE = 0.2
"""Loaded stretches closer than this share of the longest one belong to one event (the
unloaded gap between them is a loss of contact, not a closed valve)."""


@dataclass(frozen=True)
class TraceZero(Record):
    """The trace's unloaded level and its noise. [trace unit]"""

    level: float
    noise: float


@by_content(shared=True)
def trace_zero(x) -> TraceZero:
    """The zero of a strain-gauge trace: the mean of the samples within :data:`ZERO_BAND`
    noise σ of its lower quartile (the drive is unloaded over most of a cam revolution), and σ: the
    larger of the white noise from their second differences
    (:func:`processing.oscillations.decay.noise_sd`) and their robust spread about the zero (1.4826
    times the median absolute deviation), which also holds a slow wander of the zero — a trace read
    off a photograph keeps to its line within a tenth of a pixel, but not sample by sample. Found
    once for the same samples inside a :func:`processing.inputs.reuse.scope` (a trace analysed
    again with the other valve's preload).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = 3.0 + 0.1 * rng.standard_normal(4000)
    >>> x[1000:2000] += 20 * np.sin(np.linspace(0, np.pi, 1000))
    >>> z = trace_zero(x)
    >>> round(z.level, 2), round(z.noise, 2)
    (3.0, 0.1)
    """
    from processing.oscillations.decay import noise_sd

    x = np.asarray(x, dtype=float)
    base = float(np.percentile(x, 25))
    sigma = noise_sd(x)
    quiet = np.abs(x - base) < ZERO_BAND * sigma
    white = noise_sd(x[quiet]) if quiet.sum() > 10 else sigma
    sigma = white
    for _ in range(3):                  # the band widens to the wander it finds
        quiet = np.abs(x - base) < ZERO_BAND * sigma
        level = float(x[quiet].mean())
        sigma = max(white, 1.4826 * float(np.median(np.abs(x[quiet] - level))))
    return TraceZero(level, float(sigma))


@dataclass(frozen=True)
class FreeOscillation(Record):
    """The drive's free oscillation on one stretch of an opening.

    Attributes
    ----------
    frequency, u_frequency : float
        Damped frequency ω_d/2π and its standard uncertainty. [Hz]
    start, stop : float
        The stretch fitted. [s]
    periods : float
        Its length in periods.
    fit : DampedSineFit
    """

    frequency: float
    u_frequency: float
    start: float
    stop: float
    periods: float
    fit: DampedSineFit

    @property
    def dof(self) -> int:
        return self.fit.dof


@dataclass(frozen=True)
class ValveEvent(Record):
    """One valve event on a trace.

    Attributes
    ----------
    opening, closing : float
        Where the force passes the preload rising first and falling last: the valve leaves
        and reaches its seat. [s]
    u_opening, u_closing : float
        Their standard uncertainties from the noise at the crossing (σ over the force's
        slope there). [s]
    contact : (float, float)
        Where the drive is first and last loaded. [s]
    P_max, P_min : float
        The largest force, and the least while the valve is open (smoothed, the vertex
        between samples; where contact is lost, the mean force without contact, ≈ 0).
        [trace unit]
    u_P, u_P_min : float
        Their standard uncertainties from the noise. [trace unit]
    t_max, t_min : float
        Where they are. [s]
    loss : float
        Time the drive is unloaded while the valve is open. [s]
    loss_start : float
        Where the first loss of contact starts (NaN: none). [s]
    oscillation : FreeOscillation or None
        The free oscillation (after the last loss of contact, if any), or None where the
        opening holds too few periods of it.
    clipped_max, clipped_min : bool
        Whether the smoothing window of P_max (of P_min) holds a clipped sample: the
        extreme is cut off by the recorder, not measured.
    """

    opening: float
    closing: float
    u_opening: float
    u_closing: float
    contact: tuple
    P_max: float
    P_min: float
    u_P: float
    u_P_min: float
    t_max: float
    t_min: float
    loss: float
    loss_start: float
    oscillation: FreeOscillation | None
    clipped_max: bool = False
    clipped_min: bool = False


def _crossing(t, y, level: float, k: int) -> float:
    """Time where ``y`` passes ``level`` between samples k and k + 1 (linear)."""
    return float(t[k] + (level - y[k]) * (t[k + 1] - t[k]) / (y[k + 1] - y[k]))


def _stretches(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample of every run of True."""
    edges = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _merge(runs, gap: float) -> list[tuple[int, int]]:
    """Runs whose gaps are shorter than ``gap`` samples joined."""
    out = []
    for a, b in runs:
        if out and a - out[-1][1] < gap:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def valve_events(time, force, preload: float, *, noise: float,
                 period: float | None = None, resolution: float = 0.0,
                 clipped=None) -> list[ValveEvent]:
    """The whole valve events of a trace (those cut by the record's ends are left out).

    Parameters
    ----------
    time : array_like
        Sample times, uniform. [s]
    force : array_like
        The trace above its zero (:func:`trace_zero`). [trace unit]
    preload : float
        The springs' preload in the trace's unit (P₀/k). [trace unit]
    noise : float
        The trace's noise σ. [trace unit]
    period : float, optional
        The drive's oscillation period, if known; else each opening's own
        (:func:`oscillation_period`). [s]
    resolution : float
        The smallest force the trace resolves besides its noise (half the stroke of a trace
        read off a photograph; 0 for a recording): the drive counts as loaded only above
        it and as unloaded below it. [trace unit]
    clipped : array_like of bool, optional
        Samples at the recorder's limits: extremes on them are flagged
        (:attr:`ValveEvent.clipped_max`), and the free oscillation is fitted without them.

    Returns
    -------
    list of ValveEvent

    Notes
    -----
    P_max and P_min are the extremes of the trace smoothed by a quadratic Savitzky–Golay
    filter; each carries the smoothed noise's σ·√Σc² as its standard uncertainty. The
    opening and closing are the first rising and last falling passage of the raw trace
    through the preload, with u = σ/|dP/dt| there.
    """
    return valve_events_each([(time, force, preload, noise, resolution, clipped)], period)[0]


def valve_events_each(traces, period: float | None = None) -> list[list[ValveEvent]]:
    """:func:`valve_events` of each of ``traces`` (time, force, preload, noise, resolution,
    clipped: as its arguments), the free oscillations of all their openings fitted together
    (:func:`free_oscillations`)."""
    found = [_openings(*trace) for trace in traces]
    oscillations = iter(free_oscillations(
        [(t, y, start, e.closing, cut) for t, y, cut, events in found for e, start in events],
        period))
    return [[replace(e, oscillation=next(oscillations)) for e, _ in events]
            for *_, events in found]


def _openings(time, force, preload: float, noise: float, resolution: float, clipped):
    """The samples, the clipped ones and the events of a trace (:func:`valve_events`), each
    with where its free oscillation starts, the oscillations not yet sought."""
    t, y = np.asarray(time, dtype=float), np.asarray(force, dtype=float)
    cut = np.zeros(y.size, bool) if clipped is None else np.asarray(clipped, bool)
    if y.size <= SMOOTH_WINDOW:
        return t, y, cut, []
    smooth = savgol(y, SMOOTH_WINDOW, 2)
    gain = float(np.sqrt(np.sum(coefficients(SMOOTH_WINDOW, 2) ** 2)))
    s_noise = noise * gain
    loaded = smooth > max(CONTACT_LEVEL * s_noise, resolution)
    runs = _stretches(loaded)
    if not runs:
        return t, y, cut, []
    longest = max(b - a for a, b in runs)
    runs = [r for r in _merge(runs, GAP_SHARE * longest) if r[1] - r[0] > 0.5 * longest]
    found = [_event(t, y, smooth, a, b, preload, noise, s_noise, resolution, cut)
             for a, b in runs if a != 0 and b != y.size - 1]
    return t, y, cut, [f for f in found if f is not None]


def _event(t, y, smooth, a, b, preload, noise, s_noise, resolution: float,
           cut: np.ndarray) -> tuple[ValveEvent, float] | None:
    """One event over the loaded samples a…b (``cut``: the clipped samples), its free
    oscillation not yet sought, and where that starts: the opening, or the end of the last
    loss of contact. [s]"""
    seg = slice(a, b + 1)
    above = np.flatnonzero(y[seg] > preload) + a
    if above.size == 0:
        return None
    up, down = above[0] - 1, above[-1]
    opening, closing = _crossing(t, y, preload, up), _crossing(t, y, preload, down)
    dt = t[1] - t[0]
    slope_up = abs(y[up + 1] - y[up]) / dt
    slope_down = abs(y[down + 1] - y[down]) / dt
    inside = slice(up + 1, down + 1)
    k_max = int(np.argmax(smooth[seg])) + a
    t_max, P_max = _vertex(t, smooth, k_max)
    k_min = None
    unloaded = smooth[inside] < max(LOSS_LEVEL * s_noise, resolution)
    loss = float(np.count_nonzero(unloaded) * dt)
    if unloaded.any():
        gone = np.flatnonzero(unloaded) + up + 1
        loss_start, start = float(t[gone[0]]), float(t[gone[-1]])
        t_min, P_min = float(t[gone].mean()), float(y[gone].mean())
        u_min = noise / math.sqrt(gone.size)
    else:
        loss_start, start = math.nan, opening
        k_min = int(np.argmin(smooth[inside])) + up + 1
        t_min, P_min = _vertex(t, smooth, k_min)
        u_min = s_noise

    def clipped_at(k):
        reach = SMOOTH_WINDOW // 2 + 1
        return k is not None and bool(cut[max(k - reach, 0):k + reach + 1].any())

    return ValveEvent(opening, closing, noise / slope_up, noise / slope_down,
                      (float(t[a]), float(t[b])), P_max, P_min, s_noise, u_min, t_max, t_min,
                      loss, loss_start, None, clipped_at(k_max), clipped_at(k_min)), start


def _vertex(t, y, k: int) -> tuple[float, float]:
    """Time and value of the parabola's vertex through samples k − 1, k, k + 1 (an extremum
    between samples)."""
    if k == 0 or k == y.size - 1:
        return float(t[k]), float(y[k])
    a, b, c = y[k - 1], y[k], y[k + 1]
    curve = a - 2 * b + c
    shift = 0.5 * (a - c) / curve if curve != 0 else 0.0
    shift = min(max(shift, -0.5), 0.5)
    return float(t[k] + shift * (t[1] - t[0])), float(b - 0.25 * (a - c) * shift)


@by_content(shared=True)
def oscillation_period(time, force) -> float:
    """Period of the strongest oscillation over one event: the peak of the spectrum of the
    force less a polynomial of degree :data:`EVENT_DEGREE` in time (the cam's slow hump),
    above :data:`EVENT_CYCLES` cycles per event; found once for the same samples inside a
    :func:`processing.inputs.reuse.scope` (an opening read again with the other valve's
    preload spans the same samples unless its crossings move past one). [s]

    Examples
    --------
    >>> t = np.arange(0, 0.1, 1e-4)
    >>> x = 300 * np.sin(np.pi * t / 0.1) + 5 * np.sin(2 * np.pi * 450 * t)
    >>> round(1 / oscillation_period(t, x))
    450
    """
    t, y = np.asarray(time, dtype=float), np.asarray(force, dtype=float)
    if t.size < 4 * EVENT_DEGREE:
        raise RuntimeError("oscillation_period: too few samples")
    u = (t - t[0]) / (t[-1] - t[0]) * 2 - 1
    r = y - np.polynomial.legendre.legval(u, np.polynomial.legendre.legfit(u, y, EVENT_DEGREE))
    n = 8 * int(2 ** math.ceil(math.log2(r.size)))
    spectrum = np.abs(np.fft.rfft(r * np.hanning(r.size), n))
    f = np.fft.rfftfreq(n, float(np.median(np.diff(t))))
    spectrum[f < EVENT_CYCLES / (t[-1] - t[0])] = 0.0
    return 1.0 / float(f[np.argmax(spectrum)])


@by_content_each
def _fitted(stretches: list[_Stretch]) -> list[BaselineChoice | None]:
    """:func:`processing.oscillations.decay.fit_baselines_each` of stretches (:func:`_stretch`),
    fitted together, each once inside a :func:`processing.inputs.reuse.scope`: a fit is a
    function of its stretch's samples alone, so the fit made before of the same stretch (a
    trace's met again by the other valve's calibration, or by a check's slip that leaves the
    trace as it was) is the one a new fit would give."""
    with np.errstate(over="ignore", invalid="ignore"):
        return fit_baselines_each([s[:5] for s in stretches])


def free_oscillation(time, force, start: float, stop: float,
                     period: float | None = None, *, exclude=None) -> FreeOscillation:
    """The drive's free oscillation between ``start`` (the valve's opening) and ``stop``.

    The stretch fitted starts at the largest swing of the force about its running mean over the
    first half of the opening (the last excitation: the lash closing, the valve leaving its seat)
    and spans at most :data:`FIT_PERIODS` periods; a damped sinusoid on a polynomial baseline (the
    cam's slowly changing inertia and spring forces) is fitted to it, the degree chosen by the data
    and the spread over the degrees they admit added to u
    (:func:`processing.oscillations.decay.fit_baselines`: a cubic alone held ν's 95 % interval in 70
    % of the photographed records that lose contact, 0.07–0.1 % low).

    Parameters
    ----------
    time, force : array_like
        [s], [trace unit]
    start, stop : float
        The opening, and where it ends or first loses contact. [s]
    period : float, optional
        A first guess of the period. [s]
    exclude : array_like of bool, optional
        Samples left out of the fit (clipped ones), over the whole trace.

    Returns
    -------
    FreeOscillation

    Raises
    ------
    RuntimeError
        Fewer than :data:`MIN_PERIODS` periods to fit, the fit failed or wandered more
        than :data:`FREQUENCY_SLACK` from the spectrum's peak, or its frequency is not below
        the Nyquist frequency.

    Examples
    --------
    >>> t = np.arange(0, 0.04, 1e-4)
    >>> x = 50 + 300 * t + 20 * np.exp(-150 * t) * np.cos(2 * np.pi * 450 * t)
    >>> round(free_oscillation(t, x, 0.0, 0.04).frequency, 3)
    450.0
    """
    stretch = _stretch(time, force, start, stop, period, exclude)
    models = _fitted([stretch])[0]
    if models is None:
        raise RuntimeError("free_oscillation: no baseline's fit converged")
    return _oscillation(stretch, models)


def free_oscillations(openings, period: float | None = None) -> list[FreeOscillation | None]:
    """:func:`free_oscillation` of each of ``openings`` (time, force, start, stop, exclude:
    as its arguments; of one trace or of several records' traces), the stretches fitted
    together (:func:`_fitted`: a stretch met before, a record's valves' traces swapped, is the
    fit made before); None where it raises."""
    stretches = []
    for time, force, start, stop, exclude in openings:
        try:
            stretches.append(_stretch(time, force, start, stop, period, exclude))
        except RuntimeError:
            stretches.append(None)
    found = [s for s in stretches if s is not None]
    fitted = dict(zip(map(id, found), _fitted(found)))
    out = []
    for stretch in stretches:
        models = fitted.get(id(stretch))
        try:
            out.append(_oscillation(stretch, models) if models is not None else None)
        except RuntimeError:
            out.append(None)
    return out


class _Stretch(NamedTuple):
    """The stretch :func:`free_oscillation` fits."""

    time: np.ndarray
    samples: np.ndarray
    start: float
    """t₀, the largest swing. [s]"""
    period: float
    """T, the spectrum's. [s]"""
    cut: np.ndarray
    """The samples left out."""
    stop: float
    """t₁: :data:`FIT_PERIODS` periods on, or the opening's end. [s]"""
    rate: float
    """Sample rate. [Hz]"""


def _stretch(time, force, start: float, stop: float, period: float | None,
             exclude) -> _Stretch:
    """The stretch :func:`free_oscillation` fits.

    Raises
    ------
    RuntimeError
        Fewer than :data:`MIN_PERIODS` periods to fit.
    """
    t, y = np.asarray(time, dtype=float), np.asarray(force, dtype=float)
    keep = (t >= start) & (t <= stop)
    cut = np.zeros(t.size, bool) if exclude is None else np.asarray(exclude, bool)
    t, y, cut = t[keep], y[keep], cut[keep]
    if t.size < 16:
        raise RuntimeError("free_oscillation: too few samples in the stretch")
    rate = 1.0 / float(np.median(np.diff(t)))
    T = oscillation_period(t, y) if period is None else float(period)
    window = max(5, int(round(T * rate)) | 1)
    if t.size <= window + 2:
        raise RuntimeError("free_oscillation: the stretch is shorter than a period")
    swing = np.abs(y - savgol(y, window, 2))
    half = t <= start + 0.5 * (stop - start)
    k = int(np.argmax(np.where(half, swing, -np.inf)))
    t0 = float(t[k])
    t1 = min(float(t[-1]), t0 + FIT_PERIODS * T)
    if (t1 - t0) / T < MIN_PERIODS:
        raise RuntimeError(f"free_oscillation: {(t1 - t0) / T:.1f} periods to fit, at least "
                           f"{MIN_PERIODS:g} needed")
    part = (t >= t0) & (t <= t1)
    return _Stretch(t[part], y[part], t0, T, cut[part], t1, rate)


def _oscillation(stretch: _Stretch, models: BaselineChoice) -> FreeOscillation:
    """The free oscillation of a stretch (:func:`_stretch`) from its fits.

    Raises
    ------
    RuntimeError
        The fit wandered more than :data:`FREQUENCY_SLACK` from the spectrum's peak, or its
        frequency is not below the Nyquist frequency.
    """
    _, _, t0, T, _, t1, rate = stretch
    fit = models.fit
    f = fit.omega_d / (2 * math.pi)
    if not (abs(f * T - 1) < FREQUENCY_SLACK and 0 <= fit.delta < 2 * math.pi
            and f < rate / 2 and math.isfinite(fit.u("omega_d"))):
        raise RuntimeError(f"free_oscillation: the fit wandered off (ν = {f:.4g} Hz against "
                           f"{1 / T:.4g} Hz from the spectrum, δ = {fit.delta:.3g})")
    u_model = f * models.u_period / fit.period        # the baseline's model error
    return FreeOscillation(float(f), math.hypot(fit.u("omega_d") / (2 * math.pi), u_model), t0,
                           t1, (t1 - t0) * f, fit)
