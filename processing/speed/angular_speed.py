"""Instantaneous angular speed over working cycles, and the speed irregularity δ.

Two ways from numbered tooth edges (:mod:`processing.speed.toothwheel`) to ω(α):

``tooth`` — :func:`tooth_cycles`
    ω_k = Δθ_k / Δt_k for every tooth interval, the mean speed over the pitch (what a
    frequency-to-voltage converter shows). Simple and model-free, but each value carries
    the timing noise of two edges, and max − min of noisy values is biased upward.
``fourier`` — :func:`fit_cycles`
    The edge times of each cycle are fitted, by linear least squares, with the time integral
    of a Fourier series of 1/ω(α) in the cycle's orders (half orders for a four-stroke
    engine) plus a slow drift: t(θ) = t₀ + ∫₀^θ u(φ)dφ, u = 1/ω. Every edge counts once (no
    differencing), the pitch averaging of the tooth method is undone exactly, and the noise
    above the highest order is left out.

For both, δ = (ω_max − ω_min)/ω_mean with ω_mean the time mean over the cycle (cycle angle
over cycle duration), and the manual's form δ' = (ω_max − ω_min)/ω_cp with
ω_cp = (ω_max + ω_min)/2, which equals (ω_max² − ω_min²)/(2ω_cp²) (FORMULAS.md B, lab 3).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from processing.diagnostics import InputError
from processing.result import Record
from .toothwheel import ToothTrack


@dataclass(frozen=True)
class Irregularity(Record):
    """Extremes, mean and δ of speed curves (last axis = angle)."""

    omega_min: np.ndarray
    """[rad/s]"""
    omega_max: np.ndarray
    """[rad/s]"""
    omega_mean: np.ndarray
    """Time-mean speed: cycle angle / cycle duration. [rad/s]"""
    delta: np.ndarray
    """δ = (ω_max − ω_min)/ω_mean. [1]"""
    delta_mid: np.ndarray
    """δ' = (ω_max − ω_min)/ω_cp, ω_cp = (ω_max + ω_min)/2 (the manual's form). [1]"""


def irregularity(speed, omega_mean) -> Irregularity:
    """δ of speed curves sampled over whole cycles.

    Parameters
    ----------
    speed : array_like
        ω(α) over a cycle, angle on the last axis. [rad/s]
    omega_mean : array_like
        The time-mean speed of each curve. [rad/s]

    Returns
    -------
    Irregularity

    Examples
    --------
    >>> r = irregularity([99.0, 101.0, 100.0], 100.0)
    >>> float(r.delta), float(r.delta_mid)
    (0.02, 0.02)
    """
    speed = np.asarray(speed, dtype=float)
    lo, hi = speed.min(axis=-1), speed.max(axis=-1)
    mean = np.asarray(omega_mean, dtype=float)
    return Irregularity(omega_min=lo, omega_max=hi, omega_mean=mean, delta=(hi - lo) / mean,
                        delta_mid=2 * (hi - lo) / (hi + lo))


@dataclass(frozen=True)
class CycleSpeeds(Record):
    """ω(α) of each complete working cycle of a record."""

    method: str
    """``fourier`` or ``tooth``."""
    cycle_angle: float
    """Φ: 4π for a four-stroke engine, 2π for a two-stroke. [rad]"""
    angle: np.ndarray
    """Angle within the cycle from the reference tooth, where ω is given. [rad]"""
    speed: np.ndarray
    """ω(α) of each cycle, shape (cycles, angles). [rad/s]"""
    start_time: np.ndarray
    """Time of each cycle's reference edge. [s]"""
    duration: np.ndarray
    """Duration of each cycle. [s]"""
    per_cycle: Irregularity
    """Extremes and δ of each cycle."""
    mean_cycle: Irregularity
    """Extremes and δ of the mean cycle (ω averaged over the cycles at each angle)."""
    skipped: int
    """Cycles left out: a tooth missing or miscounted in them. [1]"""
    residual: float
    """RMS of the edge-time residuals of the fit, as an angle (timing noise plus any
    unmodelled pitch error; 0 for the tooth method). [rad]"""
    orders: np.ndarray | None = None
    """Orders (per revolution) of the harmonics in the fitted curves. [1]"""
    selection: float = 0.0
    """How much the mean cycle's δ would change if every harmonic above the noise (χ² >
    ``lenient``) were kept, the stray high ones too: the choice of harmonics' share of the
    uncertainty (a limit, rectangular). [1]"""
    pitch_error: float = 0.0
    """σ of the tooth-angle errors counted when choosing the harmonics (estimated, or 0 for
    a calibrated wheel). [rad]"""
    pitch_deviation: np.ndarray | None = None
    """The edge-time residual that repeats every revolution, as an angle per tooth position
    (NaN where a tooth is missing), zero mean: the wheel's pitch errors above the fitted
    orders (those below are inseparable from the engine's own speed fluctuation). [rad]"""
    pitch_response: np.ndarray | None = None
    """How the kept harmonics of u = 1/ω (cos and sin parts, shape (2, kept orders, z)) move
    per radian of angle error of each tooth position: the fit's own linear map, gap and
    fitted orders included. [s/rad²]"""

    @property
    def mean_speed(self) -> np.ndarray:
        """ω(α) of the mean cycle. [rad/s]"""
        return self.speed.mean(axis=0)

    @property
    def cycles(self) -> int:
        return self.speed.shape[0]


def _cycle_table(track: ToothTrack, revolutions: int, tooth_angles=None):
    """Edge times of the complete cycles, one row per cycle, one column per present tooth
    position plus the next cycle's reference edge; and those columns' angles."""
    per = track.teeth * revolutions
    seen = np.bincount(track.tooth[track.valid], minlength=track.teeth)
    present = seen > seen.max() / 2          # the gap's positions, wherever counting began
    columns = np.flatnonzero(np.tile(present, revolutions))
    columns = np.append(columns, per)
    if tooth_angles is None:
        angles = columns * track.pitch
    else:
        within = np.mod(columns, track.teeth)
        angles = np.asarray(tooth_angles, dtype=float)[within] + 2 * np.pi * (columns // track.teeth)
    pos = track.position
    ok = track.valid
    first_rev = int(np.ceil(max(pos[ok].min(), 0) / track.teeth)) if ok.any() else 0
    n_cycles = int((track.revolutions - first_rev) // revolutions)
    if n_cycles < 1:
        return None, angles, 0
    times = np.full(pos.max() + per + 1, np.nan)
    sel = pos >= 0
    times[pos[sel]] = np.where(ok[sel], track.times[sel], np.nan)
    # each cycle's closing edge is the next cycle's reference edge, valid or not
    start = first_rev * track.teeth
    ends = start + per * np.arange(1, n_cycles + 1)
    closing = np.isin(pos, ends)
    times[pos[closing]] = track.times[closing]
    index = start + per * np.arange(n_cycles)[:, None] + columns
    table = times[np.minimum(index, times.size - 1)]
    table[index >= times.size] = np.nan
    complete = ~np.isnan(table).any(axis=1)
    return table[complete], angles, int(n_cycles - complete.sum())


def _check_cycles(table, skipped):
    if table is None or table.shape[0] == 0:
        raise InputError("no complete working cycle in the record"
                         + (f" ({skipped} cycles had teeth missing or miscounted)" if skipped
                            else ""),
                         "record at least two working cycles (720° of a four-stroke engine "
                         "each) and check the wheel's z, its gap and the stroke number",
                         ru=("в записи нет ни одного полного рабочего цикла"
                             + (f" (в циклах с пропущенными или лишними зубьями: {skipped})"
                                if skipped else ""),
                             "запишите хотя бы два рабочих цикла (по 720° у четырёхтактного "
                             "двигателя) и проверьте z колеса, его пропуск и тактность"))


def fit_cycles(track: ToothTrack, *, revolutions: int = 2, orders: float | None = None,
               tooth_angles=None, pitch_error: float | None = None, points: int = 1440,
               significance: float | None = None, lenient: float = 4.0) -> CycleSpeeds:
    """ω(α) of every complete cycle by a least-squares Fourier fit of the edge times.

    Parameters
    ----------
    track : ToothTrack
        Numbered edges of the record.
    revolutions : int
        Revolutions per working cycle: 2 for a four-stroke engine, 1 for a two-stroke.
    orders : float, optional
        Highest order (per revolution) fitted; at most teeth/3. Default: teeth/3, capped at
        24, keeping only the harmonics that stand out of the noise (see Notes).
    tooth_angles : array_like, optional
        Calibrated angle of each tooth position from tooth 0
        (:attr:`processing.speed.toothwheel.PitchCalibration.angles`); default equal pitches.
    pitch_error : float, optional
        σ of the wheel's tooth-angle errors [rad] (with ``tooth_angles``: of their
        calibration). Default: 0 with ``tooth_angles``, else estimated from the residual that
        repeats every revolution.
    points : int
        Angles per cycle at which ω is returned.
    significance : float, optional
        χ²₂ threshold a harmonic of the mean cycle must exceed to be kept when ``orders``
        is not given. Default 2 ln(H/0.05) for H harmonics tested (Bonferroni): a record of
        pure noise lets a harmonic through one time in twenty, whatever H; a single stray
        high order would spoil max − min.
    lenient : float
        χ²₂ a harmonic below the highest significant one must exceed to be kept (4: twice
        the mean χ² of pure noise; one noise harmonic in seven passes).

    Returns
    -------
    CycleSpeeds

    Notes
    -----
    With u = 1/ω = c₀ + Σ_m a_m cos k_mθ + b_m sin k_mθ, k_m = 2πm/Φ, the time of the edge
    at angle θ is

    .. math:: t(\\theta) = t_0 + c_0\\theta
              + \\sum_m \\frac{a_m\\sin k_m\\theta + b_m(1 - \\cos k_m\\theta)}{k_m}

    linear in the coefficients. Every complete cycle has the same edge angles, so one least-
    squares solve fits all cycles at once; ω_mean = 1/c₀ is exactly the cycle angle over the
    cycle duration. The residuals give the edge-timing noise σ, hence the covariance
    σ²(AᵀA)⁻¹/n of the mean cycle's coefficients; a harmonic is kept when
    χ² = a²/var(a) + b²/var(b) exceeds ``lenient`` and its order is at most the highest
    order whose χ² exceeds ``significance``. Dropping what is noise keeps max − min of the
    fitted curve from being inflated by noise, and the strict test on the band's top keeps
    out a stray high order; dropping real small harmonics flattens the curve a little (the
    benchmark's stability map shows the balance). Kept harmonics are not shrunk toward zero:
    on the benchmark's engines that biased δ low by a further 0.1-0.8 %.

    Pitch errors of an uncalibrated wheel repeat every revolution, so no averaging removes
    them from the whole orders. Independent tooth errors of σ put into order k of the speed
    a relative pattern of variance about 2k²σ²/z per part (exactly: through the fit's own
    linear map, :class:`_WheelMaps`), growing with k while the engine's own harmonics fall
    off; counting it in var(a), var(b) keeps the orders where the wheel, not the engine,
    dominates out of the curve. An estimated σ has few degrees of freedom ν, so the
    thresholds are then those of 2·F(2, ν) at the same tail probability. (Half orders of a
    four-stroke cycle are immune in the speed, but not quite in the integrated edge times,
    so they are tested alike.)
    """
    limit = track.teeth / 3
    if orders is not None and not 0 < orders <= limit:
        raise InputError(f"{orders} orders cannot be resolved by a {track.teeth}-tooth wheel",
                         f"use at most {track.teeth // 3} orders (a third of the teeth)")
    table, theta, skipped = _cycle_table(track, revolutions, tooth_angles)
    _check_cycles(table, skipped)
    phi = 2 * np.pi * revolutions
    top = orders if orders is not None else min(limit, 24)
    k = 2 * np.pi * np.arange(1, int(np.floor(top * revolutions)) + 1) / phi
    kt = np.outer(theta, k)
    design = np.column_stack([np.ones_like(theta), theta, np.sin(kt) / k, (1 - np.cos(kt)) / k])
    rel = table - table[:, :1]
    solve = np.linalg.pinv(design)
    coef = solve @ rel.T
    resid = rel.T - design @ coef
    n_cycles = table.shape[0]
    duration = table[:, -1] - table[:, 0]
    omega = phi / duration.mean()
    noise = resid - resid.mean(axis=1, keepdims=True)
    sigma2 = float(np.sum(noise ** 2) / max(noise.size - coef.size - theta.size, 1))
    wheel = _WheelMaps.of(design, solve, theta, track)
    deviation = wheel.deviation(resid.mean(axis=1) * omega)
    pitch_dof = np.inf                  # a calibration's σ is stated, not estimated here
    if pitch_error is None and tooth_angles is not None:
        pitch_error = 0.0
    elif pitch_error is None:
        pitch_error, pitch_dof = wheel.pitch_error(deviation, sigma2 * omega ** 2 / n_cycles)
    c0, a, b = coef[1], coef[2: 2 + k.size], coef[2 + k.size:]
    response = np.mean(c0) * wheel.response[2:].reshape(2, k.size, track.teeth)
    angle = np.arange(points) * phi / points
    keep = np.ones(k.size, bool)
    selection = 0.0
    if orders is None:
        var = sigma2 * np.sum(solve ** 2, axis=1) / n_cycles
        var_pitch = pitch_error ** 2 * np.sum(response ** 2, axis=2)
        total = var[2:].reshape(2, k.size) + var_pitch
        chi2 = a.mean(axis=1) ** 2 / total[0] + b.mean(axis=1) ** 2 / total[1]
        share = var_pitch.sum(axis=0) / total.sum(axis=0)
        dof = np.where(share > 0, pitch_dof / np.maximum(share, 1e-300) ** 2, np.inf)
        strict = chi2 > _threshold(
            2 * np.log(k.size / 0.05) if significance is None else significance, dof)
        above = chi2 > _threshold(lenient, dof)
        band = k <= k[strict].max() if strict.any() else np.zeros(k.size, bool)
        keep = band & above
        selection = abs(_mean_delta(c0, a, b, k, above, angle, omega)
                        - _mean_delta(c0, a, b, k, keep, angle, omega))
    speed = 1 / (c0[:, None] + _harmonics(a[keep].T, b[keep].T, k[keep], angle))
    return CycleSpeeds(method="fourier", cycle_angle=phi, angle=angle, speed=speed,
                       start_time=table[:, 0], duration=duration,
                       per_cycle=irregularity(speed, 1 / c0),
                       mean_cycle=irregularity(speed.mean(axis=0), omega),
                       skipped=skipped, residual=float(np.sqrt(sigma2) * omega),
                       orders=k[keep].copy(), selection=selection, pitch_deviation=deviation,
                       pitch_error=float(pitch_error), pitch_response=response[:, keep])


def _threshold(chi2, dof) -> np.ndarray:
    """The χ²₂ threshold ``chi2`` for a harmonic whose variance is known to ``dof`` degrees
    of freedom only: 2·F(2, ν) at the same tail probability e^(−χ²/2) (χ²₂ where ν = ∞)."""
    dof = np.asarray(dof, dtype=float)
    out = np.full(dof.shape, float(chi2))
    finite = np.isfinite(dof)
    out[finite] = 2 * stats.f.isf(np.exp(-chi2 / 2), 2, dof[finite])
    return out


def _mean_delta(c0, a, b, k, keep, angle, omega) -> float:
    """δ of the curve 1/u from the cycles' mean coefficients, the harmonics where ``keep``."""
    u = np.mean(c0) + _harmonics(keep * a.mean(axis=1), keep * b.mean(axis=1), k, angle)
    return float(irregularity(1 / u, omega).delta)


def _harmonics(a, b, k, angle) -> np.ndarray:
    """Σ a_m cos k_mα + b_m sin k_mα at ``angle``; rows of ``a``, ``b`` are separate curves."""
    ka = np.outer(k, angle)
    return a @ np.cos(ka) + b @ np.sin(ka)


PITCH_SIGNIFICANCE = 0.01
"""How often a wheel without pitch errors is taken for a rough one: the repeating residual
must exceed the timing noise's share of it at this level before σ is estimated from it (an
estimate made of noise would only take real harmonics out of the fit)."""


@dataclass(frozen=True)
class _WheelMaps:
    """The fit's linear maps of the wheel's tooth-angle errors e (one per tooth position).

    An edge whose tooth sits e off its nominal angle comes e/ω late, so the edge times of a
    cycle, taken from its reference edge, move by S e / ω, with S the tooth position of each
    edge less that of the reference. The fitted coefficients move by P S e / ω (P the
    least-squares solve) and the residual by (I − D P) S e / ω. These maps replace the
    full-wheel formula (independent errors put 2k²σ²/z into each part of order k): beside a
    gap, and with the orders above the fitted ones leaking in, a 60−2 wheel's errors move the
    fitted orders by 1.2–1.7 times that variance.
    """

    response: np.ndarray
    """Coefficients per unit ω·e: P S, shape (coefficients, z)."""
    average: np.ndarray
    """Per tooth position: the mean over the revolutions of a quantity given per edge (the
    cycle's closing edge left out), less its mean over the present positions; shape (z,
    edges), zero rows where no tooth is."""
    wheel: np.ndarray
    """The repeating residual per unit e: A (I − D P) S, shape (z, z)."""
    noise: np.ndarray
    """The repeating residual per unit residual: A (I − D P), shape (z, edges)."""

    @classmethod
    def of(cls, design, solve, theta, track: ToothTrack) -> _WheelMaps:
        tooth = np.mod(np.rint(theta / track.pitch).astype(int), track.teeth)
        edges = np.arange(theta.size)
        shift = np.zeros((theta.size, track.teeth))
        shift[edges, tooth] += 1.0
        shift[:, tooth[0]] -= 1.0
        count = np.bincount(tooth[:-1], minlength=track.teeth)
        average = np.zeros((track.teeth, theta.size))
        average[tooth[:-1], edges[:-1]] = 1.0 / count[tooth[:-1]]
        present = count > 0
        average[present] -= average[present].mean(axis=0)
        noise = average - (average @ design) @ solve
        return cls(solve @ shift, average, noise @ shift, noise)

    @property
    def present(self) -> np.ndarray:
        return np.any(self.average != 0, axis=1)

    def deviation(self, residual) -> np.ndarray:
        """The repeating residual per tooth position of the mean cycle's residual (an angle;
        NaN where no tooth is). [rad]"""
        return np.where(self.present, self.average @ residual, np.nan)

    def pitch_error(self, deviation, noise_var) -> tuple[float, float]:
        """σ of independent tooth-angle errors from the repeating residual, and the degrees
        of freedom of σ² (0 and ∞ when the residual does not stand out of the timing noise
        at :data:`PITCH_SIGNIFICANCE`).

        The residual's expected sum of squares is σ²‖W‖² + σ_n²‖N‖² (W = A(I − DP)S,
        N = A(I − DP), σ_n² = ``noise_var`` the variance of the cycles' mean residual per
        edge, as an angle), so σ̂² = (Σdev² − σ_n²‖N‖²)/‖W‖²; as a quadratic form in normal
        variables of covariance C = σ²WWᵀ + σ_n²NNᵀ it has the variance 2 tr C²/‖W‖⁴, hence
        ν = σ⁴‖W‖⁴/tr C² (with σ̂ for σ; about 20 on a 60−2 wheel: the orders above the
        fitted ones are all that tell the wheel from the engine). [rad], [1]"""
        present = self.present
        wheel, noise = self.wheel[present], self.noise[present]
        norm = np.sum(wheel ** 2)
        total = np.sum(deviation[present] ** 2)
        expected = noise_var * np.sum(noise ** 2)
        null_dof = np.sum(noise ** 2) ** 2 / np.sum((noise @ noise.T) ** 2)
        if total <= expected * stats.chi2.isf(PITCH_SIGNIFICANCE, null_dof) / null_dof:
            return 0.0, np.inf
        sigma2 = (total - expected) / norm
        cov = sigma2 * wheel @ wheel.T + noise_var * noise @ noise.T
        return float(np.sqrt(sigma2)), float(sigma2 ** 2 * norm ** 2 / np.sum(cov ** 2))


def pitch_uncertainty(cycles: CycleSpeeds, *, draws: int = 400, seed: int = 20031) -> float:
    """Standard uncertainty of the mean cycle's δ from tooth-pitch errors of σ =
    ``cycles.pitch_error`` in the harmonics that were kept (an uncalibrated wheel's errors in
    them cannot be separated from the engine's own fluctuation).

    Parameters
    ----------
    cycles : CycleSpeeds
        A :func:`fit_cycles` result.
    draws : int
        Random pitch-error patterns tried.
    seed : int

    Returns
    -------
    float
        u(δ). [1]

    Notes
    -----
    Independent tooth errors e_j ~ N(0, σ²) move the kept harmonics of 1/ω by
    :attr:`CycleSpeeds.pitch_response` @ e (mostly the whole orders: the half orders of a
    four-stroke cycle see the same tooth in both revolutions). Each pattern is added to the
    mean cycle; the spread of δ is u.
    """
    response = cycles.pitch_response
    if cycles.pitch_error == 0 or response is None or response.shape[1] == 0:
        return 0.0
    rng = np.random.default_rng(seed)
    error = rng.normal(0.0, cycles.pitch_error, (draws, response.shape[2]))
    du = _harmonics(error @ response[0].T, error @ response[1].T, cycles.orders, cycles.angle)
    speed = 1 / (1 / cycles.mean_speed + du)
    delta = irregularity(speed, cycles.mean_cycle.omega_mean).delta
    return float(np.std(delta, ddof=1))


def jackknife(cycles: CycleSpeeds) -> Irregularity:
    """Standard uncertainties of the mean cycle's extremes, mean speed and δ, by leaving out
    one cycle at a time.

    Parameters
    ----------
    cycles : CycleSpeeds

    Returns
    -------
    Irregularity
        u of each field: sqrt((n − 1)/n · Σ(x₍₋ᵢ₎ − x̄₍₋₎)²); NaN for fewer than 3 cycles.

    Notes
    -----
    The cycles are the repeated observations, so the scatter includes the engine's own
    cycle-to-cycle variation as well as the measurement noise: the uncertainty is that of
    the regime's mean cycle, not of one cycle.
    """
    n = cycles.cycles
    if n < 3:
        nan = np.float64(np.nan)
        return Irregularity(nan, nan, nan, nan, nan)
    leave_out = (cycles.speed.sum(axis=0) - cycles.speed) / (n - 1)
    durations = (cycles.duration.sum() - cycles.duration) / (n - 1)
    r = irregularity(leave_out, cycles.cycle_angle / durations)

    def u(x):
        return np.sqrt((n - 1) / n * np.sum((x - x.mean()) ** 2))

    return Irregularity(u(r.omega_min), u(r.omega_max), u(r.omega_mean), u(r.delta),
                        u(r.delta_mid))


def tooth_cycles(track: ToothTrack, *, revolutions: int = 2, tooth_angles=None) -> CycleSpeeds:
    """ω over every tooth interval of every complete cycle: Δθ/Δt at the interval's middle.

    Parameters
    ----------
    track, revolutions, tooth_angles
        As for :func:`fit_cycles`.

    Returns
    -------
    CycleSpeeds
        ``angle`` are the interval midpoints; across the gap one interval spans it.

    Notes
    -----
    ω_k = (θ_{k+1} − θ_k)/(t_{k+1} − t_k) is the mean of ω over the pitch in the sense
    Δθ/∫dt; a speed harmonic of order k (per revolution) is seen attenuated by
    sinc(k p/2) with p the pitch (0.2 % for order 2 on a 60-tooth wheel, 4.5 % on 12 teeth).
    """
    table, theta, skipped = _cycle_table(track, revolutions, tooth_angles)
    _check_cycles(table, skipped)
    phi = 2 * np.pi * revolutions
    speed = np.diff(theta) / np.diff(table, axis=1)
    duration = table[:, -1] - table[:, 0]
    omega_mean = phi / duration
    return CycleSpeeds(method="tooth", cycle_angle=phi, angle=(theta[1:] + theta[:-1]) / 2,
                       speed=speed, start_time=table[:, 0], duration=duration,
                       per_cycle=irregularity(speed, omega_mean),
                       mean_cycle=irregularity(speed.mean(axis=0), phi / duration.mean()),
                       skipped=skipped, residual=0.0)


@dataclass(frozen=True)
class OrderSpectrum(Record):
    """Harmonic content of ω(α) over a cycle (:func:`order_spectrum`)."""

    order: np.ndarray
    """Order: harmonics per revolution (0.5, 1, 1.5, ... for a four-stroke cycle). [1]"""
    amplitude: np.ndarray
    """Amplitude of each harmonic of ω. [rad/s]"""
    relative: np.ndarray
    """Amplitude over the mean speed. [1]"""


def order_spectrum(angle, speed, cycle_angle: float, max_order: float | None = None) -> OrderSpectrum:
    """Orders of a speed curve over one cycle, by FFT after resampling to equal angles.

    Parameters
    ----------
    angle : array_like
        Increasing angles within one cycle. [rad]
    speed : array_like
        ω at those angles. [rad/s]
    cycle_angle : float
        Φ, the cycle's period. [rad]
    max_order : float, optional
        Highest order returned (default: what the sampling resolves).

    Returns
    -------
    OrderSpectrum

    Examples
    --------
    >>> a = np.arange(720) * np.pi / 180
    >>> s = order_spectrum(a, 100 + 2 * np.cos(2 * a), 4 * np.pi, max_order=3)
    >>> s.order.tolist(), np.round(s.amplitude, 6).tolist()
    ([0.5, 1.0, 1.5, 2.0, 2.5, 3.0], [0.0, 0.0, 0.0, 2.0, 0.0, 0.0])
    """
    angle = np.asarray(angle, dtype=float)
    speed = np.asarray(speed, dtype=float)
    n = angle.size
    grid = np.arange(n) * cycle_angle / n
    closed_a = np.append(angle, angle[0] + cycle_angle)
    closed_s = np.append(speed, speed[0])
    uniform = np.interp(grid, closed_a, closed_s, period=cycle_angle)
    spectrum = np.fft.rfft(uniform) / n
    revolutions = cycle_angle / (2 * np.pi)
    order = np.arange(spectrum.size) / revolutions
    amplitude = 2 * np.abs(spectrum)
    keep = order > 0
    if max_order is not None:
        keep &= order <= max_order + 1e-9
    mean = spectrum[0].real
    return OrderSpectrum(order=order[keep], amplitude=amplitude[keep],
                         relative=amplitude[keep] / mean)
