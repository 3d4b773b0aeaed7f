"""Lab 3's synthetic scene: engine → flywheel → toothed wheel → inductive sensor → ADC.

The run is checked against :func:`processing.crank.dynamics.crank_speed_cycle` (the steady periodic
solution it must reproduce), the recording against its own true edge times (a noise-free
record crosses zero at them), and the generator against itself (seeds, chunking).
Tolerances: δ and speeds relative; edge times in tooth periods (STYLE.md 9).
"""

import json

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from processing.crank import dynamics as dyn
from processing.diagnostics import InputError
from processing.synth.engine import (
    Engine,
    Sensor,
    ToothWheel,
    coast_run,
    iter_signal,
    record,
    run_engine,
    samples_per_tooth,
)

CLEAN = Sensor(sample_rate=1e6, snr_db=np.inf)
WHEEL = ToothWheel(missing=2, pitch_error=np.radians(0.05), seed=3,
                   reference_angle=np.radians(3.0))  # no edge at t = 0, before the first sample


def _steady_torque(engine, alpha):
    """M(α) of the whole engine built straight from processing.crank.dynamics (FORMULAS.md B)."""
    pressure = dyn.indicator_pressure(
        alpha, p_a=engine.p_a, p_z=engine.p_z, compression_ratio=engine.compression_ratio,
        n1=engine.n1, n2=engine.n2, lambda_=engine.lambda_, p_r=engine.p_r)
    force = (dyn.gas_force(pressure, np.pi * engine.bore**2 / 4)
             + dyn.reciprocating_inertia_force(alpha, engine.reciprocating_mass,
                                               engine.crank_radius, engine.mean_angular_speed,
                                               engine.lambda_))
    one = dyn.crank_train_forces(alpha, force, engine.crank_radius, engine.lambda_).torque
    return dyn.sum_cylinders(alpha, one, dyn.firing_phases(engine.cylinders))


def _falling_crossings(codes, sample_rate):
    """Falling zero crossings of a sampled signal, by linear interpolation. [s]"""
    x = codes.astype(float)
    i = np.flatnonzero((x[:-1] > 0) & (x[1:] <= 0))
    return (i + x[i] / (x[i] - x[i + 1])) / sample_rate


def _tooth_period(run, wheel):
    return 2 * np.pi / (wheel.teeth * run.mean_angular_speed)


@pytest.fixture(scope="module")
def steady():
    return run_engine(Engine(), 4)


@pytest.fixture(scope="module")
def steady_record(steady):
    return record(steady, WHEEL, Sensor(sample_rate=1e6, snr_db=np.inf, tdc=True),
                  duration=0.15)


# ------------------------------------------------------------------------------ the run

def test_steady_run_matches_crank_speed_cycle(steady):
    engine = Engine()
    alpha = np.arange(7200) * (4 * np.pi / 7200)  # the run's grid at the default 0.1° step
    cycle = dyn.crank_speed_cycle(alpha, _steady_torque(engine, alpha), engine.inertia,
                                  engine.mean_angular_speed, period=4 * np.pi)
    assert_allclose(steady.delta, cycle.speed_irregularity, rtol=1e-4,
                    err_msg="steady δ = crank_speed_cycle's δ")
    assert_allclose(steady.delta_cycles, cycle.speed_irregularity, rtol=1e-4,
                    err_msg="each cycle's δ = crank_speed_cycle's δ")
    assert_allclose(steady.angular_speed[:7200], cycle.angular_speed, rtol=1e-9,
                    err_msg="the first cycle is the steady periodic ω(α)")
    assert 0.01 <= steady.delta <= 0.02, "the default car engine: δ in the manual's 0.01-0.02"


def test_steady_cycles_are_identical(steady):
    cycles = steady.angular_speed[:-1].reshape(4, -1)
    assert_allclose(cycles, np.broadcast_to(cycles[0], cycles.shape), rtol=1e-9,
                    err_msg="every cycle repeats the first")
    durations = np.diff(steady.time[::7200])
    assert_allclose(durations, 4 * np.pi / Engine().mean_angular_speed, rtol=1e-9,
                    err_msg="each cycle lasts Φ/ω_mean")
    assert_allclose(steady.delta_cycles, steady.delta, rtol=1e-9, err_msg="δ of each cycle")


def test_time_table_and_mean_speed(steady):
    assert steady.time[0] == 0 and np.all(np.diff(steady.time) > 0), "t(α) starts at 0, rises"
    assert_allclose(np.diff(steady.crank_angle), np.radians(0.1), rtol=1e-9,
                    err_msg="uniform 0.1° grid")
    assert steady.cycle_angle == 4 * np.pi
    assert_allclose(steady.mean_angular_speed, Engine().mean_angular_speed, rtol=1e-9,
                    err_msg="time-mean speed = ω_mean")
    # t(α) = ∫dα/ω: Simpson's rule on the same grid agrees to the trapezoid's error
    w = steady.angular_speed[: 7200 + 1]
    simpson = np.radians(0.1) / 3 * np.sum(1 / w[:-1:2] + 4 / w[1::2] + 1 / w[2::2])
    assert_allclose(steady.time[7200], simpson, rtol=1e-7, err_msg="cycle time")
    assert_allclose(steady.angle_at(steady.time[::997]), steady.crank_angle[::997], rtol=1e-12,
                    err_msg="α(t) inverts t(α)")
    assert_allclose(steady.speed_at_angle(steady.crank_angle[::997]), steady.angular_speed[::997],
                    rtol=1e-12, err_msg="ω(α) on the grid")
    with pytest.raises(InputError, match="span of the run"):
        steady.angle_at(steady.time[-1] + 1.0)


def test_cycle_variation_scatters_delta_with_a_stable_speed():
    engine = Engine(cycle_variation=0.05)
    run = run_engine(engine, 40, seed=7)
    assert np.std(run.delta_cycles) > 0.03 * np.mean(run.delta_cycles), "δ scatters"
    cycle_speed = 4 * np.pi / np.diff(run.time[::7200])
    assert_allclose(cycle_speed, engine.mean_angular_speed, rtol=0.02,
                    err_msg="the dynamometer holds the speed")
    assert_allclose(run.mean_angular_speed, engine.mean_angular_speed, rtol=0.005,
                    err_msg="mean speed")
    assert_array_equal(run_engine(engine, 40, seed=7).angular_speed, run.angular_speed,
                       err_msg="same seed, same run")
    assert not np.array_equal(run_engine(engine, 40, seed=8).angular_speed, run.angular_speed)


def test_speed_drift_makes_cycles_unequal():
    engine = Engine(speed_drift=0.1)
    run = run_engine(engine, 20)
    durations = np.diff(run.time[::7200])
    assert np.all(np.diff(durations) < 0), "the engine speeds up: each cycle is shorter"
    last = 4 * np.pi / durations[-1]
    assert 1.05 < last / engine.mean_angular_speed < 1.1, "speed follows the set point, lagging"


def test_two_stroke_and_motored_runs():
    two = run_engine(Engine(strokes=2, cylinders=2), 3)
    assert two.cycle_angle == 2 * np.pi
    assert_allclose(two.mean_angular_speed, Engine().mean_angular_speed, rtol=1e-9,
                    err_msg="two-stroke mean speed")
    motored = run_engine(Engine(firing=False), 3)
    assert 0 < motored.delta < run_engine(Engine(), 1).delta, "compression alone: smaller δ"
    with pytest.raises(InputError, match="n_cycles"):
        run_engine(Engine(), 0)


def test_coast_run_is_smooth():
    run = coast_run(100.0, 2.0, deceleration=5.0)
    assert np.all(np.diff(run.angular_speed) < 0), "spins down"
    assert run.delta == 0 and np.all(run.delta_cycles == 0) and run.delta_cycles.size == 31
    t = run.time
    assert_allclose(run.crank_angle, 105.0 * t - 2.5 * t**2, rtol=1e-12, atol=1e-12,
                    err_msg="α(t) = ω_s t - a t²/2")
    assert_allclose(run.angular_speed, 105.0 - 5.0 * t, rtol=1e-12, err_msg="ω(t) = ω_s - a t")
    assert_allclose(run.mean_angular_speed, 100.0, rtol=1e-12, err_msg="mean speed")
    with pytest.raises(InputError, match="deceleration"):
        coast_run(100.0, 2.0, deceleration=100.0)


# ------------------------------------------------------------------------- wheel, sensor

def test_wheel_teeth_and_true_edges():
    angles = WHEEL.tooth_angles()
    assert angles.size == 58 and np.all(np.diff(angles) > 0)
    assert 0 <= angles[0] and angles[-1] < 2 * np.pi
    gaps = np.diff(np.append(angles, angles[0] + 2 * np.pi))
    # two teeth's position errors: the gap's std is √2·pitch_error; allow 5 of them
    assert_allclose(np.sort(gaps)[-1], 3 * WHEEL.pitch, atol=5 * np.sqrt(2) * WHEEL.pitch_error,
                    err_msg="the 60-2 gap spans three pitches")
    edge, tooth = WHEEL.edge_angles()
    assert_allclose(edge, angles, atol=1e-3 * WHEEL.pitch, rtol=0, err_msg="edges at the teeth")
    assert_array_equal(np.sort(tooth), np.arange(58))
    assert_allclose(edge[tooth == 0], np.radians(3.0), atol=5 * WHEEL.pitch_error,
                    err_msg="tooth 0 at the reference angle")
    assert_allclose(ToothWheel(pitch_error=np.radians(0.05), seed=3).tooth_angles()[[1, 5]],
                    WHEEL.tooth_angles()[[1, 5]] - np.radians(3.0), rtol=0, atol=1e-12,
                    err_msg="a tooth's error does not depend on the gap or reference")
    with pytest.raises(InputError, match="pitch_error"):
        ToothWheel(pitch_error=0.1).tooth_angles()


def test_noise_free_record_crosses_zero_at_the_true_edges(steady, steady_record):
    rec = steady_record
    crossings = _falling_crossings(rec.signal, rec.sample_rate)
    assert crossings.size == rec.edge_times.size
    assert_allclose(crossings, rec.edge_times, rtol=0, atol=1e-3 * _tooth_period(steady, WHEEL),
                    err_msg="falling zero crossings = true edge times")
    per_revolution = np.diff(np.searchsorted(rec.edge_times, steady.time[::3600]))
    assert_array_equal(per_revolution[per_revolution > 0][:2], 58,
                       err_msg="teeth - missing edges per revolution")
    assert_array_equal(rec.edge_teeth[:58], np.roll(np.arange(58), -np.argmin(rec.edge_teeth[:58])))
    tdc = _falling_crossings(rec.tdc_signal, rec.sample_rate)
    assert_allclose(tdc, rec.tdc_times[1:], rtol=0, atol=1e-3 * _tooth_period(steady, WHEEL),
                    err_msg="TDC crossings (the one at t = 0 has no sample before it)")
    assert_allclose(steady.angle_at(rec.tdc_times) / (2 * np.pi), np.arange(rec.tdc_times.size),
                    atol=1e-12, err_msg="TDC at α = 0 mod 2π")


def test_coast_record_shows_the_wheel_alone():
    run = coast_run(150.0, 0.2)
    rec = record(run, WHEEL, CLEAN)
    angle = np.mod(run.angle_at(rec.edge_times), 2 * np.pi)
    edge = WHEEL.edge_angles()[0]
    assert_allclose(angle, edge[np.searchsorted(edge, angle - 1e-9)], atol=1e-9,
                    err_msg="edge angles through the smooth run's α(t) = the wheel's edges")
    crossings = _falling_crossings(rec.signal, rec.sample_rate)
    assert_allclose(crossings, rec.edge_times, rtol=0, atol=1e-3 * _tooth_period(run, WHEEL),
                    err_msg="coast record crossings")


def test_amplitude_grows_with_speed():
    run = run_engine(Engine(speed_drift=0.3), 12)
    rec = record(run, ToothWheel(), Sensor(sample_rate=200e3, snr_db=np.inf))
    ends = np.interp([0, 4 * np.pi, 44 * np.pi, 48 * np.pi], run.crank_angle, run.time)
    n = (ends * rec.sample_rate).astype(int)
    first, last = np.abs(rec.signal[n[0]:n[1]]).max(), np.abs(rec.signal[n[2]:n[3]]).max()
    cycle = run.angular_speed[:-1].reshape(12, -1)
    assert_allclose(last / first, cycle[-1].max() / cycle[0].max(), rtol=1e-2,
                    err_msg="u = Φ'ω: the peak grows with the speed")
    assert_allclose(first * rec.volts_per_code, cycle[0].max() / run.mean_angular_speed,
                    rtol=1e-2, err_msg="peak = amplitude (1 V) at the mean speed")


def test_chunks_seeds_and_determinism(steady):
    sensor = Sensor(sample_rate=1e6, snr_db=30, jitter=2e-8, spikes_per_second=100, tdc=True)
    rec = record(steady, WHEEL, sensor, seed=5, duration=0.2)
    assert rec.signal.dtype == np.int16 and rec.signal.size == 200_000
    for chunk in (1000, 65_536, 77_777, 2**20):
        parts = list(iter_signal(steady, WHEEL, sensor, chunk=chunk, seed=5, duration=0.2))
        assert all(p.size == chunk for p in parts[:-1])
        assert_array_equal(np.concatenate(parts), rec.signal, err_msg=f"chunk={chunk}")
    tdc = np.concatenate(list(iter_signal(steady, WHEEL, sensor, chunk=12_345, seed=5,
                                          duration=0.2, channel="tdc")))
    assert_array_equal(tdc, rec.tdc_signal, err_msg="TDC channel by chunks")
    assert_array_equal(record(steady, WHEEL, sensor, seed=5, duration=0.2).signal, rec.signal,
                       err_msg="same seed, same record")
    assert np.mean(record(steady, WHEEL, sensor, seed=6, duration=0.2).signal != rec.signal) > 0.5
    with pytest.raises(InputError, match="channel"):
        iter_signal(steady, WHEEL, CLEAN, channel="tdc")


def test_noise_level_quantisation_and_clipping(steady):
    noisy = record(steady, WHEEL, Sensor(snr_db=20, offset=0.0), duration=0.1)
    clean = record(steady, WHEEL, Sensor(snr_db=np.inf), duration=0.1)
    signal_rms = np.std(clean.signal.astype(float))
    noise_rms = np.std(noisy.signal.astype(float) - clean.signal)
    assert_allclose(noise_rms / signal_rms, 0.1, rtol=0.05, err_msg="SNR 20 dB")

    sensor = Sensor(bits=12, clip=0.5, offset=0.1, spikes_per_second=500, snr_db=20)
    rec = record(steady, WHEEL, sensor, duration=0.1)
    assert rec.signal.dtype == np.int16
    assert rec.volts_per_code == 4.0 / 4096
    assert -2048 <= rec.signal.min() and rec.signal.max() <= 2047
    volts = rec.signal * rec.volts_per_code
    assert np.abs(volts).max() <= 0.5 + rec.volts_per_code / 2, "clipped at ±0.5 V"
    assert np.mean(np.abs(volts) >= 0.5 - rec.volts_per_code) > 0.01, "and the clip is reached"

    saturated = record(steady, WHEEL, Sensor(full_scale=0.5, snr_db=np.inf), duration=0.05)
    assert saturated.signal.max() == 32767 and saturated.signal.min() == -32768
    with pytest.raises(InputError, match="bits"):
        record(steady, WHEEL, Sensor(bits=20))
    with pytest.raises(InputError, match="duration"):
        record(steady, WHEEL, CLEAN, duration=10.0)


def test_answer_key(steady, steady_record):
    key = steady_record.answer_key()
    json.dumps(key, allow_nan=False)
    assert_allclose(key["delta"], steady.delta, rtol=1e-12)
    assert key["n_cycles"] == 2 and len(key["delta_cycles"]) == 2
    assert_allclose(key["mean_speed_rpm"], 1800, rtol=1e-9)
    assert_allclose(key["samples_per_tooth"], 1e6 / (60 * 30), rtol=1e-9)
    assert_allclose(samples_per_tooth(steady, WHEEL, CLEAN), key["samples_per_tooth"], rtol=0)
    assert key["sensor"]["snr_db"] is None and key["wheel"]["missing"] == 2
    assert key["run"]["engine"]["inertia"] == Engine().inertia and key["seed"] == 0
    assert steady_record.to_dict()["run"]["delta"] == steady.delta
