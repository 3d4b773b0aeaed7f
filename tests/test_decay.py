"""processing.oscillations.decay: peaks, logarithmic decrement and damped-sinusoid fits of free
decays.

Closed forms (a geometric series of amplitudes, an exponential decay on a drift), the noise
structure the half ranges are fitted with, and over seeded records of the damper's scene
(:mod:`processing.synth.damper`) the coverage of the stated uncertainties and where the
decrement's trend test must fire and must not.
"""
import numpy as np
import pytest
from scipy import stats

from processing.oscillations.decay import (HALF_RANGE_CORRELATION, analyse_decay, decrement_trend,
                              find_peaks, fit_damped_sine, log_decrement, noise_sd)
from processing.synth.damper import Ring, StrainGauge, free_decay


def decay(t, delta=0.4, f=50.0, t0=0.0):
    """A viscous decay of decrement ``delta`` released from 1 at ``t0`` (held before)."""
    tau = np.clip(t - t0, 0.0, None)
    sigma, w = delta * f, 2 * np.pi * f
    return np.exp(-sigma * tau) * (np.cos(w * tau) + sigma / w * np.sin(w * tau))


# ----------------------------------------------------------------------------- closed forms

def test_line_through_a_geometric_series_is_exact():
    a = 12.0 * np.exp(-0.7 * np.arange(6))
    fit = log_decrement(a)
    assert fit.delta == pytest.approx(0.7, abs=1e-12)
    assert fit.u_delta == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(fit.per_cycle, 0.7)
    # half ranges half a period apart: the generalised fit is exact too
    half = log_decrement(12.0 * np.exp(-0.35 * np.arange(9)), step=0.5, half_ranges=True)
    assert half.delta == pytest.approx(0.7, abs=1e-12)


def test_reading_uncertainty_through_the_slope():
    """u_B(δ) = √Σ (w_k u/A_k)², w_k = (n_k − n̄)/Σ(n − n̄)²: three readings, worked by hand."""
    fit = log_decrement([10.0, 5.0, 2.5])
    assert fit.u_from_readings(0.1) == pytest.approx(np.hypot(0.1 / 10, 0.1 / 2.5) / 2,
                                                     rel=1e-12)


def test_local_decrement_of_a_quadratic_envelope():
    """ln A = −δ₀ n + c n²: the local decrement δ₀ − 2cn, its change −2c·span/δ̄."""
    n = np.arange(8.0)
    fit = log_decrement(np.exp(-0.8 * n + 0.03 * n**2))
    assert fit.curvature.c2 == pytest.approx(0.03, rel=1e-9)
    assert np.allclose(fit.decrement_at(n), 0.8 - 0.06 * n)
    assert fit.decrement_change() == pytest.approx(-0.06 * 7 / fit.delta, rel=1e-9)


def test_half_ranges_of_a_drifting_decay_are_proportional_to_the_envelope():
    """Released from rest, the extrema fall at kT/2 with values ±e^{−σkT/2}: each half range
    is e^{−σt_k}(1 + cosh(δ/2))/2, and a linear drift's offset cancels (its slope d′ moves
    the extrema: kept to d′/(ωA) < 0.01 here)."""
    t = np.arange(20000) / 20e3
    x = decay(t, delta=0.4) + 0.2 * t + 0.2
    p = find_peaks(t, x)
    assert p.period == pytest.approx(0.02, rel=2e-3)
    big = p.amplitudes > 0.1
    assert np.allclose(p.times[big], np.round(p.times[big] / 0.01) * 0.01, atol=5e-5)
    env = np.exp(-0.4 * 50 * p.times[big]) * (1 + np.cosh(0.2)) / 2
    assert big.sum() >= 8
    assert np.allclose(p.amplitudes[big] / env, 1.0, rtol=2e-3)


def test_trace_fit_recovers_a_noiseless_decay_on_a_curved_baseline():
    t = np.arange(6000) / 20e3
    x = decay(t, delta=0.6, t0=0.005) + 0.1 + 0.5 * t - 2.0 * t**2
    fit = fit_damped_sine(t, x, start=0.006, period=0.02)
    assert fit.delta == pytest.approx(0.6, rel=1e-6)
    assert fit.period == pytest.approx(0.02, rel=1e-8)


def test_noise_of_a_smooth_record():
    rng = np.random.default_rng(5)
    t = np.arange(50000) / 50e3
    assert noise_sd(np.sin(2 * np.pi * 40 * t) + 0.02 * rng.standard_normal(t.size)) == \
        pytest.approx(0.02, rel=0.03)


def test_half_range_errors_correlate_as_stated():
    """Independent extremum errors e_k give half-range errors (e_k − (e_{k−1} + e_{k+1})/2)/2
    (signs aside): correlation 2/3 with the neighbour, 1/6 with the next, 0 beyond."""
    e = np.random.default_rng(3).standard_normal((400000, 5))
    sign = np.array([1, -1, 1, -1, 1])
    x = sign * 10.0 + e                                   # alternating extrema
    half = 0.5 * np.abs(x[:, 1:-1] - 0.5 * (x[:, :-2] + x[:, 2:]))
    c = np.corrcoef(half.T)
    assert c[0, 1] == pytest.approx(HALF_RANGE_CORRELATION[1], abs=0.01)
    assert c[0, 2] == pytest.approx(HALF_RANGE_CORRELATION[2], abs=0.01)


# ----------------------------------------------------------------------------- bad records

def test_noise_alone_is_not_a_decay():
    x = np.random.default_rng(0).standard_normal(4000)
    with pytest.raises(ValueError, match="extrema.*at least three"):
        analyse_decay(np.arange(4000) / 20e3, x)


def test_a_steady_oscillation_is_not_a_decay():
    t = np.arange(4000) / 20e3
    x = np.sin(2 * np.pi * 200 * t) + 0.01 * np.random.default_rng(1).standard_normal(t.size)
    with pytest.raises(RuntimeError, match="does not decay measurably"):
        analyse_decay(t, x)


def test_a_record_cut_after_one_period_is_refused():
    rec = free_decay(Ring(), StrainGauge(snr_db=30), periods=1.0, seed=0)
    with pytest.raises(ValueError, match="at least three"):
        analyse_decay(rec.time, rec.signal)


# ----------------------------------------------------------------------------- seeded records

def reduce_records(n, **scene):
    """(δ error, u(δ), peaks' δ error, its 95 % half-width, trend significant) over seeds."""
    ring = Ring(amplitude_exponent=scene.pop("p", 0.0))
    out = []
    for seed in range(n):
        rec = free_decay(ring, StrainGauge(snr_db=scene.get("snr_db", 30)),
                         periods=scene.get("periods", 5), seed=seed)
        d = analyse_decay(rec.time, rec.signal)
        truth = rec.truth["log_decrement"]
        p = d.peaks
        out.append((d.trace.delta - truth, d.trace.u("delta"),
                    np.nan if p is None else p.delta - truth,
                    np.nan if p is None else p.u_delta * stats.t.ppf(0.975, p.dof),
                    d.trend.significant()))
    return np.array(out, dtype=float)


@pytest.fixture(scope="module")
def target_region():
    """200 records of the manual's damper (δ = 0.89) at 30 dB, 5 periods: the benchmark's
    target corner."""
    return reduce_records(200)


def test_trace_fit_interval_covers_the_truth(target_region):
    err, u = target_region[:, 0], target_region[:, 1]
    covered = np.mean(np.abs(err) <= 1.96 * u)
    assert 0.90 <= covered <= 0.98, covered
    assert np.mean(np.abs(err) / 0.89 <= 0.02) >= 0.95


def test_line_through_half_ranges_states_an_honest_interval(target_region):
    """Ordinary least squares over the correlated half ranges covered 52–59 %; the
    generalised fit (with Student t for its 1–3 degrees of freedom) holds at least 90 %."""
    err, half = target_region[:, 2], target_region[:, 3]
    ok = np.isfinite(err)
    assert ok.sum() >= 50
    assert np.mean(np.abs(err[ok]) <= half[ok]) >= 0.90


def test_trend_stays_silent_on_viscous_damping(target_region):
    assert np.mean(target_region[:, 4]) <= 0.03


@pytest.mark.parametrize("p", [0.1, 0.3])
def test_trend_sees_amplitude_dependent_damping(p):
    flagged = reduce_records(10, p=p, snr_db=40, periods=8)[:, 4]
    assert flagged.all()


def test_trend_of_a_curved_envelope_is_measured():
    """δ(τ) = δ₀ + 4πγτ/ω_d: a record made with γ is found with it, and the local decrement
    at its end carries the fit's covariance."""
    t = np.arange(8000) / 20e3
    gamma, w = -20.0, 2 * np.pi * 50
    tau = np.clip(t - 0.005, 0, None)
    x = np.where(t < 0.005, 1.0, np.exp(-0.5 * 50 * tau - gamma * tau**2) * np.cos(w * tau))
    x = x + 1e-4 * np.random.default_rng(2).standard_normal(t.size)
    plain = fit_damped_sine(t, x, start=0.006, period=0.02)
    trend = decrement_trend(t, x, plain)
    assert trend.fit.gamma == pytest.approx(gamma, rel=0.02)
    end = trend.measured_at(trend.end)
    assert end.value == pytest.approx(0.5 + 4 * np.pi * gamma * (trend.end - 0.006) / w,
                                      abs=3 * end.u + 1e-3)
    assert end.u > trend.fit.u("delta")


def test_benchmark_families_and_targets_on_a_few_records():
    """The benchmark's families run and judge (its targets are the benchmark's, not here)."""
    from processing.bench import damper
    from processing.bench.harness import Case, run_family

    rows = run_family(damper.decrement_family(), damper.decay_cases((40,), (5,), (0.89,), 2),
                      repeat=1)
    rows += run_family(damper.table1_family(), [Case({}, None, damper.PRINTED_C, 9)],
                       repeat=1)
    frame = __import__("pandas").DataFrame(rows)
    trace = frame[frame["method"] == "trace fit"]
    assert (trace["error"].abs() < damper.DELTA_TOLERANCE).all() and trace["covered"].all()
    found = damper.targets(frame)
    # two records cannot show a coverage below 98 %: that target needs the benchmark's 1200
    judged = [t for t in found if "at most" not in t.name]
    assert all(t.passed for t in judged), [t.line() for t in judged]
    assert sum(t.name.startswith("Table 1") for t in found) == 2


def test_variable_projection_jacobian_is_the_residuals_derivative():
    # Golub–Pereyra's Jacobian of P⊥x against a central difference, on a noisy record far
    # from its fit (where Kaufman's shortcut, without the second term, would be off)
    from scipy.optimize._numdiff import approx_derivative

    from processing.oscillations.decay import _projection

    rng = np.random.default_rng(3)
    tau = np.linspace(0, 0.05, 300)
    u = tau / tau[-1]
    x = 3 * np.exp(-40 * tau) * np.cos(2 * np.pi * 120 * tau + 0.3) + 0.5 + 0.2 * u \
        + 0.3 * rng.standard_normal(tau.size)
    for curved, p in ((False, [0.25, 2 * np.pi * 118]), (True, [0.25, 2 * np.pi * 118, 0.3])):
        projection = _projection([(tau, x, 2)], curved)
        exact = projection.jacobian(np.array(p))
        numeric = approx_derivative(projection.residual, np.array(p), method="3-point")
        assert np.max(np.abs(exact - numeric)) < 1e-8 * np.max(np.abs(numeric))
