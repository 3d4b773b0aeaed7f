"""processing.speed.edges: tooth-edge times from a sampled inductive-sensor signal.

Synthetic records (processing.synth.engine) carry the true edge times — the falling zeros
of u = Φ'(α)ω — so each placement method is measured against them, clean and noisy, with a
DC offset, clipping and spikes; a hand-built chirp checks an amplitude that grows with the
speed. The streaming detector must equal the in-memory one exactly.
Tolerances: edge positions in samples (1 sample = 1/f_s).
"""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from processing.bench.speed import timing_bound
from processing.diagnostics import InputError
from processing.speed.edges import (
    METHODS,
    EdgeDetector,
    detect_edges,
    fit_window,
    stream_edges,
)
from processing.synth.engine import (
    Engine,
    Sensor,
    ToothWheel,
    coast_run,
    record,
    run_engine,
    samples_per_tooth,
)
from processing.speed.toothwheel import track_teeth

WHEEL = ToothWheel(missing=2, reference_angle=np.radians(3.0))


def _nearest(found, truth):
    """Index of the true edge nearest to each found edge."""
    j = np.clip(np.searchsorted(truth, found), 1, truth.size - 1)
    return j - ((found - truth[j - 1]) < (truth[j] - found))


def _compare(found, truth):
    """Errors of the found edges against the truth [samples], checking that they pair one to
    one and that only the first or last true edge (at the record's ends) may be missing."""
    j = _nearest(found, truth)
    assert np.all(np.diff(j) > 0), "two found edges at one true edge"
    lost = np.setdiff1d(np.arange(truth.size), j)
    assert set(lost) <= {0, truth.size - 1}, f"true edges {lost} not found"
    return found - truth[j]


def _rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


@pytest.fixture(scope="module")
def run():
    """8 working cycles (16 revolutions, 0.53 s) of the default engine at 1800 min⁻¹."""
    return run_engine(Engine(), 8)


@pytest.fixture(scope="module")
def clean(run):
    """Noise-free, 16-bit, 100 kHz: 56 samples per tooth."""
    return record(run, WHEEL, Sensor(sample_rate=100e3, snr_db=np.inf, bits=16))


@pytest.fixture(scope="module")
def noisy(run):
    """SNR 20 dB at 44 kHz: 24.4 samples per tooth."""
    return record(run, WHEEL, Sensor(sample_rate=44e3, snr_db=20), seed=4)


@pytest.mark.parametrize("sample_rate", [50e3, 100e3])
@pytest.mark.parametrize("method, tolerance", [("linear", 0.01), ("cubic", 0.01), ("fit", 0.05),
                                               ("matched", 0.01)])
def test_noise_free_edges_at_the_true_times(run, clean, method, tolerance, sample_rate):
    rec = clean if sample_rate == clean.sample_rate else record(
        run, WHEEL, Sensor(sample_rate=sample_rate, snr_db=np.inf, bits=16))
    truth = rec.edge_times * rec.sample_rate
    found = detect_edges(rec.signal, method)
    assert truth.size - 2 <= found.size <= truth.size
    error = _compare(found, truth)
    assert _rms(error) < tolerance, f"{method}: RMS {_rms(error):.2g} samples"
    assert np.abs(error).max() < 3 * tolerance


def test_fit_beats_linear_in_noise(run, noisy):
    assert 20 <= samples_per_tooth(run, WHEEL, noisy.sensor) <= 25
    truth = noisy.edge_times * noisy.sample_rate
    rms = {}
    for method in ("linear", "fit"):
        error = _compare(detect_edges(noisy.signal, method), truth)
        rms[method] = _rms(error)
        assert rms[method] < 0.3, f"{method}: RMS {rms[method]:.3f} samples"
        assert abs(np.mean(error)) < 0.03, f"{method}: unbiased"
    assert rms["fit"] < 0.85 * rms["linear"], f"fitting averages the noise: {rms}"


def test_fit_window_follows_the_pulse_and_nears_the_bound(run):
    """At 200 kHz (111 samples per tooth) and 20 dB the window widens with the pulse; the
    timing noise falls toward the Cramér–Rao bound of the whole pulse, √(σ_n²/Σu'²) per edge
    (the window's middle part of the pulse holds about a third of that information)."""
    rec = record(run, WHEEL, Sensor(sample_rate=200e3, snr_db=20), seed=2)
    window = fit_window(rec.signal[:2 ** 16])
    assert 12 <= window <= 20, "0.3 of the 56-sample peak-to-trough distance"
    truth = rec.edge_times * rec.sample_rate
    bound = timing_bound(rec) * rec.sample_rate
    auto = _rms(_compare(detect_edges(rec.signal), truth))
    fixed = _rms(_compare(detect_edges(rec.signal, window=4), truth))
    assert auto < 0.5 * fixed, f"auto {auto:.3f}, 8-sample window {fixed:.3f} samples"
    assert bound < auto < 2 * bound, f"auto {auto:.3f}, bound {bound:.3f} samples"


def test_matched_edges_near_the_bound(run, noisy):
    """At 24 samples per tooth and 20 dB the matched filter uses the whole pulse: its timing
    noise comes within 30 % of the Cramér–Rao bound, where the local fit is 1.6× it."""
    truth = noisy.edge_times * noisy.sample_rate
    bound = timing_bound(noisy) * noisy.sample_rate
    error = {m: _compare(detect_edges(noisy.signal, m), truth) for m in ("fit", "matched")}
    rms = {m: _rms(e) for m, e in error.items()}
    assert bound < rms["matched"] < 1.3 * bound, f"{rms}, bound {bound:.3f} samples"
    assert rms["fit"] > 1.4 * bound
    assert abs(np.mean(error["matched"])) < 0.1 * bound, "unbiased"


def test_matched_edges_follow_a_coast_down():
    """A coast-down from 160 to 140 rad/s: the pulses widen 14 % against the shape learned on
    the first block; the stretch term keeps every edge on its true time (without it they
    drift by 0.03 samples as the speed falls)."""
    rec = record(coast_run(150.0, 1.0, deceleration=20.0), WHEEL,
                 Sensor(sample_rate=100e3, snr_db=np.inf))
    truth = rec.edge_times * rec.sample_rate
    error = _compare(detect_edges(rec.signal, "matched"), truth)
    quarters = [np.mean(part) for part in np.array_split(error, 4)]
    assert np.std(error) < 0.002 and np.ptp(quarters) < 0.002, f"quarter means {quarters}"
    assert abs(np.mean(error)) < 0.005


@pytest.mark.parametrize("method", METHODS)
def test_offset_and_clipping_do_not_move_edges(run, clean, method):
    reference = detect_edges(clean.signal, method)
    peak = np.abs(clean.signal).max() * clean.volts_per_code
    for sensor in (Sensor(sample_rate=100e3, snr_db=np.inf, offset=0.3),
                   Sensor(sample_rate=100e3, snr_db=np.inf, clip=0.4 * peak)):
        rec = record(run, WHEEL, sensor)
        found = detect_edges(rec.signal, method)
        assert found.size == reference.size
        assert _rms(found - reference) < 0.02, f"{sensor}: {_rms(found - reference):.2g}"
    assert np.mean(np.abs(rec.signal * rec.volts_per_code) >= 0.4 * peak - 1e-3) > 0.1, \
        "the clip is reached on a good part of the record"


def test_spikes_give_few_extra_edges_and_tracking_removes_them(run):
    rate = 50.0
    rec = record(run, WHEEL, Sensor(sample_rate=100e3, snr_db=40, spikes_per_second=rate),
                 seed=0)
    # the same seed without spikes: the very same noise (spikes have their own stream)
    calm = record(run, WHEEL, Sensor(sample_rate=100e3, snr_db=40), seed=0)
    spikes = rate * rec.signal.size / rec.sample_rate            # 27 expected
    found, base = detect_edges(rec.signal), detect_edges(calm.signal)
    _compare(base, calm.edge_times * calm.sample_rate)
    extra = found.size - base.size
    assert 0 <= extra <= 0.5 * spikes, f"{extra} extra edges from ~{spikes:.0f} spikes"
    track = track_teeth(found / rec.sample_rate, 60, 2)
    assert track.doubled == extra, "each extra edge is removed as a doubled one"
    assert track.times.size == base.size and track.missed == 0
    assert track.gap_found and track.bad_revolutions.size == 0
    assert_array_equal(np.bincount(track.revolution[track.valid]), 58,
                       err_msg="58 teeth in every revolution")
    kept = track.times * rec.sample_rate
    # the spikes shift the block mean a little (0.004 sample here), and move the few edges
    # they hit; every other edge stays where it was without them
    same = np.abs(kept - base) < 0.01
    assert np.mean(same) > 1 - spikes / base.size, "the edges left are the teeth, unmoved"
    assert np.abs(kept - base).max() < 0.2 * 100e3 / 1800, "a spike-hit edge stays near its tooth"


@pytest.mark.parametrize("method", METHODS)
def test_streaming_equals_in_memory(noisy, method):
    # noise and spikes, so that crossings and arming fall across block and chunk borders
    x = record(noisy.run, WHEEL, Sensor(sample_rate=44e3, snr_db=20, spikes_per_second=50),
               seed=2).signal
    reference = detect_edges(x, method, block=4096)
    assert reference.size > 900
    rng = np.random.default_rng(11)
    splits = [np.array_split(x, k) for k in (1, 2, 7, 13, 200, 1500)]      # down to 16 samples
    splits.append(np.split(x, 4096 * np.arange(1, x.size // 4096 + 1)))    # block by block
    for _ in range(4):                                                     # uneven, some empty
        splits.append(np.split(x, np.sort(rng.integers(0, x.size, 60))))
    for chunks in splits:
        streamed = stream_edges(chunks, method, block=4096)
        assert np.array_equal(streamed, reference), \
            f"{method}, {len(chunks)} chunks of {min(map(len, chunks))}..{max(map(len, chunks))}"
    det = EdgeDetector(method, block=4096)
    parts = [det.feed(c) for c in np.array_split(x, 37)]
    assert np.array_equal(np.concatenate(parts + [det.finish()]), reference)
    whole_blocks = x.size // 4096 * 4096
    held = 1 if method == "matched" else 0       # the last edge waits to see its next one
    assert sum(p.size for p in parts) >= np.sum(reference < whole_blocks - 40) - held, \
        "edges come out as soon as their block is complete (and their window's samples seen)"


@pytest.mark.parametrize("method", METHODS)
def test_integer_and_float_samples_agree(noisy, method):
    codes = noisy.signal
    reference = detect_edges(codes, method)
    for x in (codes.astype(np.float64), codes.astype(np.float32),
              codes * noisy.volts_per_code):
        found = detect_edges(x, method)
        assert found.size == reference.size, x.dtype
        assert_allclose(found, reference, rtol=0, atol=1e-9, err_msg=str(x.dtype))


def test_speed_drift_keeps_every_edge():
    run = run_engine(Engine(speed_drift=0.3), 12)
    rec = record(run, WHEEL, Sensor(sample_rate=50e3, snr_db=np.inf))
    truth = rec.edge_times * rec.sample_rate
    for method in METHODS:
        error = _compare(detect_edges(rec.signal, method), truth)
        assert _rms(error) < 0.01, method


def test_amplitude_growing_threefold_within_a_block():
    # u = A(t) sin φ(t), frequency and amplitude both growing 1 → 3 over 60 000 samples (one
    # block): falling zeros where φ = (2m + 1)π, from f0·n + c·n²/2 = m + 1/2
    n = np.arange(60_000)
    f0, c = 1 / 60, 2 / 60 / n.size
    x = (1 + c * n / f0) * np.sin(2 * np.pi * (f0 * n + c * n ** 2 / 2))
    m = np.arange(int(f0 * n[-1] + c * n[-1] ** 2 / 2 - 0.5) + 1)
    truth = (np.sqrt(f0 ** 2 + 2 * c * (m + 0.5)) - f0) / c
    assert truth.size == 2000
    for method in METHODS:
        error = _compare(detect_edges(x, method), truth)
        assert _rms(error) < 0.01, method


def test_bad_arguments(clean):
    with pytest.raises(InputError, match="method"):
        detect_edges(clean.signal, "zero")
    with pytest.raises(InputError, match="one-dimensional"):
        detect_edges(clean.signal[:1000].reshape(2, -1))
    with pytest.raises(InputError, match="one-dimensional"):
        stream_edges([clean.signal[:500], clean.signal[500:1000].reshape(2, -1)])
    with pytest.raises(InputError, match="numbers"):
        detect_edges(np.array(["1", "2", "3"]))
    with pytest.raises(InputError, match="hysteresis"):
        EdgeDetector("linear", hysteresis=0)
